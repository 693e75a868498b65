/*
 * serial.c - UART driver.  The receive interrupt only moves bytes into a
 * ring buffer; decoding telegrams happens in the main loop.
 */
#include "fw.h"
#include "hal.h"
#include "serial.h"

#define RX_SIZE 64u                       /* power of two */
static volatile uint8_t rx_buf[RX_SIZE];
static volatile uint8_t rx_head, rx_tail; /* head written by the ISR only */
static volatile uint16_t rx_overruns;

void serial_reset(void) { rx_head = rx_tail = 0; rx_overruns = 0; }

void fw_isr_uart(void)
{
    uint16_t st = hal_rd16(UART_STATUS);
    if (st & UART_ST_OVERRUN)
        rx_overruns++;
    while (st & UART_ST_RXRDY) {
        uint8_t b = (uint8_t)hal_rd16(UART_DATA);
        uint8_t next = (uint8_t)((rx_head + 1u) & (RX_SIZE - 1u));
        if (next != rx_tail) {
            rx_buf[rx_head] = b;
            rx_head = next;
        } else {
            rx_overruns++;
        }
        st = hal_rd16(UART_STATUS);
    }
}

void serial_poll(void)
{
    /* Telegram decoding arrives with the command-interface issue. */
    rx_tail = rx_head;
}

int serial_get(mac4_msg_t *m)
{
    (void)m;
    return 0;
}

void serial_send(const mac4_msg_t *m)
{
    (void)m;
}
