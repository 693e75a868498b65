/*
 * serial.c - the front-panel serial line (manual 3.3), docs/serial.md.
 *
 * Interrupt level 4 (fw_isr_uart) moves bytes only: from the UART into the
 * receive ring, and from the transmit ring into the UART.  serial_poll()
 * runs the telegram decoder from the main loop, answers broken telegrams
 * with NAK and puts valid commands into a small FIFO for serial_get().
 * serial_send() encodes a response into the transmit ring, all of it or
 * nothing.  The telegram decoder, byte by byte, is serial_dec.c.
 *
 * Everything starts from zero: .bss is cleared by crt0, which is the same
 * state serial_reset() produces, so the driver works before anyone calls it.
 */
#include "inline.h"
#include "fw.h"
#include "hal.h"
#include "serial.h"

/* ---- the encoder (the decoder: serial_dec.c) ------------------------------ */

/* One data byte (or the checksum) at out[h], doubled if it is DLE: the
 * next h.  Through a volatile pointer, so no two byte stores ever merge
 * (serial.h, the toolchain hazard). */
FW_INLINE unsigned put_data(volatile uint8_t *out, unsigned h, unsigned mask, uint8_t b)
{
    out[h] = b;
    h = (h + 1u) & mask;
    if (b == SERIAL_DLE) {
        out[h] = SERIAL_DLE;
        h = (h + 1u) & mask;
    }
    return h;
}

/* The telegram of m from out[h] on, h advancing modulo mask + 1 (a ring),
 * or without a wrap (mask ~0u): the h after it.  The one encoder, of the
 * transmit ring (serial_send) and of serial_encode. */
FW_INLINE unsigned encode_at(volatile uint8_t *out, unsigned h, unsigned mask, const mac4_msg_t *m)
{
    uint8_t a = m->axis, c1 = (uint8_t)(m->code >> 8), c0 = (uint8_t)m->code;
    uint32_t p = m->param;
    uint16_t ph = (uint16_t)(p >> 16), pl = (uint16_t)p;
    uint8_t p3 = (uint8_t)(ph >> 8), p2 = (uint8_t)ph, p1 = (uint8_t)(pl >> 8), p0 = (uint8_t)pl;
    out[h] = SERIAL_DLE;
    h = (h + 1u) & mask;
    out[h] = SERIAL_STX;
    h = (h + 1u) & mask;
    h = put_data(out, h, mask, a);
    h = put_data(out, h, mask, c1);
    h = put_data(out, h, mask, c0);
    h = put_data(out, h, mask, p3);
    h = put_data(out, h, mask, p2);
    h = put_data(out, h, mask, p1);
    h = put_data(out, h, mask, p0);
    /* the checksum, sent doubled like a data byte (docs/serial.md) */
    return put_data(out, h, mask, (uint8_t)(a + c1 + c0 + p3 + p2 + p1 + p0));
}

unsigned serial_encode(const mac4_msg_t *m, uint8_t *buf)
{
    return encode_at(buf, 0, ~0u, m);
}

/* ---- driver state -------------------------------------------------------- */

/* Receive ring: head written by the ISR only, tail by the main loop only. */
static volatile uint8_t rx_buf[SERIAL_RX_SIZE];
static volatile uint8_t rx_head, rx_tail;
/* Transmit ring: head written by the main loop only, tail by the ISR only. */
static volatile uint8_t tx_buf[SERIAL_TX_SIZE];
static volatile uint8_t tx_head, tx_tail;
static volatile uint8_t tx_on;            /* UART_CTRL_TXIE is set */
/* Counted by the ISR (16 bits: one move.w, atomic for the main loop). */
static volatile uint16_t isr_overruns, isr_framing;

static serial_dec_t dec;
static uint32_t last_rx_us;               /* when serial_poll last took a byte */

static mac4_msg_t fifo[SERIAL_FIFO_LEN];
static uint8_t fifo_head;
uint8_t serial_fifo_count;                /* decoded commands waiting (serial_pending) */
/* Set by the ISR whenever the receive side has news (a byte, an overrun, a
 * framing error) and kept set by serial_poll while a telegram is open (its
 * timeout needs the clock): serial_poll has nothing to do while it is 0. */
volatile uint8_t serial_rx_work;

/* Statistics, mirrored into the card data block (DPC_SERIAL_*). */
enum { ST_RX_OK, ST_NAKS, ST_GARBAGE, ST_OVERRUNS, ST_FRAMING, ST_CMD_LOST, ST_TX_OK, ST_TX_LOST,
       ST_COUNT };
uint32_t serial_stats[SERIAL_N_STATS];          /* serial.h: written here only */
_Static_assert(ST_COUNT == SERIAL_N_STATS, "serial.h counts the statistics");
static uint16_t seen_overruns, seen_framing;

#define RX_MASK (SERIAL_RX_SIZE - 1u)
#define TX_MASK (SERIAL_TX_SIZE - 1u)

static void stat_set(unsigned i, uint32_t v)
{
    serial_stats[i] = v;
    hal_wr32(DPC_SERIAL_RX_OK + 4u * i, v);
}

static void stat_add(unsigned i, uint32_t n) { stat_set(i, serial_stats[i] + n); }

void serial_reset(void)
{
    unsigned sr = hal_irq_save();
    hal_wr16(UART_CTRL, (uint16_t)(hal_rd16(UART_CTRL) & ~UART_CTRL_TXIE));
    tx_on = 0;
    rx_head = rx_tail = 0;
    tx_head = tx_tail = 0;
    isr_overruns = isr_framing = 0;
    serial_rx_work = 0;
    hal_irq_restore(sr);
    seen_overruns = seen_framing = 0;
    serial_dec_init(&dec);
    last_rx_us = 0;
    fifo_head = serial_fifo_count = 0;
    for (unsigned i = 0; i < ST_COUNT; i++)
        stat_set(i, 0);
}

/* ---- interrupt level 4 --------------------------------------------------- */

HAL_ISR void fw_isr_uart(void)
{
    uint16_t st = hal_rd16(UART_STATUS);      /* reading clears OVERRUN and FRAMING */
    if (st & (UART_ST_OVERRUN | UART_ST_FRAMING | UART_ST_RXRDY))
        serial_rx_work = 1;
    for (;;) {
        if (st & UART_ST_OVERRUN)
            isr_overruns++;
        if (st & UART_ST_FRAMING)
            isr_framing++;
        if (!(st & UART_ST_RXRDY))
            break;
        uint8_t b = (uint8_t)hal_rd16(UART_DATA);
        uint8_t next = (uint8_t)((rx_head + 1u) & RX_MASK);
        if (next != rx_tail) {
            rx_buf[rx_head] = b;
            rx_head = next;
        } else {
            isr_overruns++;                   /* never overwrite unread bytes */
        }
        st = hal_rd16(UART_STATUS);
    }
    if (st & UART_ST_TXEMPTY) {
        uint8_t t = tx_tail;
        if (t != tx_head) {
            hal_wr16(UART_DATA, tx_buf[t]);
            tx_tail = (uint8_t)((t + 1u) & TX_MASK);
        } else if (tx_on) {
            tx_on = 0;                        /* nothing left: stop the TX interrupt */
            hal_wr16(UART_CTRL, (uint16_t)(hal_rd16(UART_CTRL) & ~UART_CTRL_TXIE));
        }
    }
}

/* ---- main loop ------------------------------------------------------------ */

static uint32_t now_us(void)
{
    unsigned sr = hal_irq_save();             /* reading HI latches LO: keep the pair together */
    uint32_t hi = hal_rd16(TMR_FREE_HI);
    uint32_t lo = hal_rd16(TMR_FREE_LO);
    hal_irq_restore(sr);
    return hi << 16 | lo;
}

/* The bytes up to head are queued: the ISR may send them. */
static void tx_publish(uint8_t head)
{
    tx_head = head;                           /* after the bytes */
    if (!tx_on) {
        unsigned sr = hal_irq_save();
        tx_on = 1;
        hal_wr16(UART_CTRL, (uint16_t)(hal_rd16(UART_CTRL) | UART_CTRL_TXIE));
        hal_irq_restore(sr);
    }
}

static unsigned tx_room(void) { return (unsigned)(tx_tail - tx_head - 1u) & TX_MASK; }

/* Queue n bytes for sending, all or none.  Returns 1 if queued. */
static int tx_put(const uint8_t *p, unsigned n)
{
    if (n > tx_room()) {
        stat_add(ST_TX_LOST, 1);
        return 0;
    }
    uint8_t head = tx_head;
    for (unsigned i = 0; i < n; i++) {
        tx_buf[head] = p[i];
        head = (uint8_t)((head + 1u) & TX_MASK);
    }
    tx_publish(head);
    return 1;
}

static void nak(void)
{
    static const uint8_t b = SERIAL_NAK;
    stat_add(ST_NAKS, 1);
    tx_put(&b, 1);
}

static void event(int ev, const mac4_msg_t *m)
{
    if (ev == SERIAL_EV_NONE)
        return;
    if (ev != SERIAL_EV_MSG) {
        nak();
        return;
    }
    if (serial_fifo_count >= SERIAL_FIFO_LEN) {
        /* No room: refuse it loudly, the sender may repeat it. */
        stat_add(ST_CMD_LOST, 1);
        nak();
        return;
    }
    fifo[(fifo_head + serial_fifo_count) % SERIAL_FIFO_LEN] = *m;
    serial_fifo_count++;
    stat_add(ST_RX_OK, 1);
}

/* The bytes that have arrived, through the decoder (out of line: the
 * common pass, a telegram open and nothing new, needs none of its
 * registers). */
static __attribute__((noinline)) void take_bytes(void)
{
    mac4_msg_t m;               /* filled by the decoder before any use */
    while (rx_tail != rx_head) {
        uint8_t t = rx_tail;
        uint8_t b = rx_buf[t];
        rx_tail = (uint8_t)((t + 1u) & RX_MASK);
        event(serial_dec_step(&dec, b, &m), &m);
    }
    last_rx_us = now_us();
    if (dec.garbage != serial_stats[ST_GARBAGE])
        stat_set(ST_GARBAGE, dec.garbage);
}

void serial_poll_work(void)
{
    serial_rx_work = 0;         /* before looking: news from now on sets it again */
    /* The clock is read only when it matters: an idle line costs nothing. */
    if (rx_tail != rx_head) {
        take_bytes();
    } else if (dec.state != SERIAL_DS_HUNT && (uint32_t)(now_us() - last_rx_us) > SERIAL_TIMEOUT_US) {
        mac4_msg_t m;           /* (no message from a timeout) */
        event(serial_dec_timeout(&dec), &m);
        if (dec.garbage != serial_stats[ST_GARBAGE])
            stat_set(ST_GARBAGE, dec.garbage);
    }
    if (dec.state != SERIAL_DS_HUNT)
        serial_rx_work = 1;     /* a telegram is open (serial_dec_busy): watch its timeout */

    uint16_t o = isr_overruns, f = isr_framing;
    if (o != seen_overruns) {
        stat_add(ST_OVERRUNS, (uint16_t)(o - seen_overruns));
        seen_overruns = o;
    }
    if (f != seen_framing) {
        stat_add(ST_FRAMING, (uint16_t)(f - seen_framing));
        seen_framing = f;
    }
}

int serial_get(mac4_msg_t *m)
{
    if (!serial_fifo_count)
        return 0;
    *m = fifo[fifo_head];
    fifo_head = (uint8_t)((fifo_head + 1u) % SERIAL_FIFO_LEN);
    serial_fifo_count--;
    return 1;
}

void serial_send(const mac4_msg_t *m)
{
    if (tx_room() >= SERIAL_TELEGRAM_MAX) {
        /* room for the longest: encoded straight into the ring (the ISR
         * reads none of it before tx_head moves) */
        tx_publish((uint8_t)encode_at(tx_buf, tx_head, TX_MASK, m));
        stat_add(ST_TX_OK, 1);
        return;
    }
    uint8_t buf[SERIAL_TELEGRAM_MAX];     /* nearly full: all of it or nothing */
    unsigned n = serial_encode(m, buf);
    if (tx_put(buf, n))
        stat_add(ST_TX_OK, 1);
}
