/* uart.h - the state of the IPC's UART and the line towards it (uart.c,
 * the only writer; the serial host sets the transmit hook). */
#ifndef UART_H
#define UART_H
#include <stdint.h>

#define UART_WIRE_SIZE 8192
typedef struct {
    uint16_t ctrl;
    uint8_t rx_hold;               /* receive holding register */
    int rx_full, overrun, framing;
    uint8_t wire[UART_WIRE_SIZE];  /* bytes on the line towards the card */
    unsigned wire_head, wire_tail;
    uint64_t rx_done;              /* when the character on the wire is complete */
    int tx_busy;
    uint64_t tx_done;
    uint8_t tx_shift;
    void (*on_tx)(void *ctx, uint8_t byte);
    void *tx_ctx;
} uart_t;

#endif
