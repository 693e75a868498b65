/*
 * uart.c - the IPC's UART on the front-panel serial line, 4800 baud 8N1
 * (level 4): a device of periph.c's table.
 */
#include "sim.h"
#include "periph.h"

/* ---- UART, 4800 baud 8N1 ------------------------------------------------- */
void uart_feed(sim_t *s, const uint8_t *bytes, unsigned n)
{
    uart_t *u = &s->uart;
    for (unsigned i = 0; i < n; i++) {
        unsigned next = (u->wire_head + 1) % UART_WIRE_SIZE;
        if (next == u->wire_tail) {
            sim_printf(s, "error serial input buffer of the emulator full\n");
            return;
        }
        u->wire[u->wire_head] = bytes[i];
        u->wire_head = next;
    }
    if (u->rx_done == CYC_NEVER && u->wire_head != u->wire_tail)
        u->rx_done = sim_now(s) + UART_CHAR_CYC;
}

static uint32_t uart_rd(sim_t *s, uint32_t off, int size)
{
    (void)size;
    uart_t *u = &s->uart;
    switch (off) {
    case 0x0: u->rx_full = 0; return u->rx_hold;
    case 0x2: {
        uint32_t st = (u->rx_full ? UART_ST_RXRDY : 0) | (u->tx_busy ? 0 : UART_ST_TXEMPTY) |
                      (u->overrun ? UART_ST_OVERRUN : 0) | (u->framing ? UART_ST_FRAMING : 0);
        u->overrun = u->framing = 0;
        return st;
    }
    case 0x4: return u->ctrl;
    }
    sim_fault(s, "read of undefined UART register +$%X", (unsigned)off);
    return 0xFFFF;
}

static void uart_wr(sim_t *s, uint32_t off, uint32_t v, int size)
{
    (void)size;
    uart_t *u = &s->uart;
    switch (off) {
    case 0x0:
        if (u->tx_busy) {
            sim_fault(s, "UART transmit while busy: byte $%02X lost", (unsigned)(v & 0xFF));
            return;
        }
        u->tx_busy = 1;
        u->tx_shift = (uint8_t)v;
        u->tx_done = sim_now(s) + UART_CHAR_CYC;
        return;
    case 0x4: u->ctrl = (uint16_t)v; return;
    }
    sim_fault(s, "write to undefined UART register +$%X", (unsigned)off);
}

static void uart_event(sim_t *s, cyc_t now)
{
    uart_t *u = &s->uart;
    while (u->rx_done <= now) {
        uint8_t b = u->wire[u->wire_tail];
        u->wire_tail = (u->wire_tail + 1) % UART_WIRE_SIZE;
        if (u->rx_full)
            u->overrun = 1;          /* the new character is lost, as on a real UART */
        else {
            u->rx_hold = b;
            u->rx_full = 1;
        }
        u->rx_done = (u->wire_head != u->wire_tail) ? u->rx_done + UART_CHAR_CYC : CYC_NEVER;
    }
    if (u->tx_busy && u->tx_done <= now) {
        u->tx_busy = 0;
        u->tx_done = CYC_NEVER;
        if (u->on_tx)
            u->on_tx(u->tx_ctx, u->tx_shift);
    }
}

static void uart_reset(sim_t *s)
{
    uart_t *u = &s->uart;
    u->ctrl = 0;
    u->rx_full = u->overrun = u->framing = 0;
    u->tx_busy = 0;
    u->tx_done = CYC_NEVER;
    u->rx_done = (u->wire_head != u->wire_tail) ? sim_now(s) + UART_CHAR_CYC : CYC_NEVER;
}

static cyc_t uart_next_event(sim_t *s) { return s->uart.rx_done < s->uart.tx_done ? s->uart.rx_done : s->uart.tx_done; }

static unsigned uart_irq_lines(sim_t *s)
{
    if ((s->uart.ctrl & UART_CTRL_RXIE) && (s->uart.rx_full || s->uart.overrun))
        return 1u << IRQ_LEVEL_UART;
    if ((s->uart.ctrl & UART_CTRL_TXIE) && !s->uart.tx_busy)
        return 1u << IRQ_LEVEL_UART;
    return 0;
}

const device_t uart_device = {.name = "uart", .win = {{uart_rd, uart_wr}}, .reset = uart_reset,
                              .next_event = uart_next_event, .events = uart_event, .irq_lines = uart_irq_lines};
