/*
 * test_serial.c - the serial line (firmware/serial.c, docs/serial.md):
 * the codec against the telegrams of manual 7.3.1 byte for byte, the
 * decoder's resynchronisation, and the driver over the emulator's UART
 * model (interrupt handler, rings, NAK, statistics words in the DPRAM).
 */
#include "unit_support.h"
#include "fw.h"
#include "hal.h"
#include "serial.h"

/* ---- helpers -------------------------------------------------------------- */

static uint8_t sent[16384];        /* what the card put on the line */
static unsigned nsent;

static void capture(void *ctx, uint8_t b)
{
    (void)ctx;
    if (nsent < sizeof sent)
        sent[nsent++] = b;
}

static void serial_setup(void)
{
    card_setup();
    card.uart.on_tx = capture;
    nsent = 0;
    hal_wr16(UART_CTRL, UART_CTRL_RXIE);   /* as card_start does */
    serial_reset();
}

/* Advance the emulated time in 100 us steps; at each step the UART
 * interrupt is served while it is asserted, and (if poll) the main loop
 * runs serial_poll(). */
static void line_run_ex(cyc_t cycles, int poll)
{
    const cyc_t step = US_TO_CYC(100);
    for (cyc_t t = 0; t < cycles; t += step) {
        card.slice_base += step;
        periph_events(&card, card.slice_base);
        for (int guard = 0; sim_irq_level(&card) == IRQ_LEVEL_UART; guard++) {
            assert_true(guard < 8);
            fw_isr_uart();
        }
        if (poll)
            serial_poll();
    }
}
static void line_run(cyc_t cycles) { line_run_ex(cycles, 1); }

/* Bytes to the card over the line, with time for them to arrive. */
static void line_feed(const uint8_t *b, unsigned n)
{
    uart_feed(&card, b, n);
    line_run((cyc_t)n * UART_CHAR_CYC + US_TO_CYC(500));
}

static unsigned hex(const char *s, uint8_t *out)
{
    unsigned n = 0;
    unsigned v;
    int k;
    while (sscanf(s, " %2x%n", &v, &k) == 1) {
        out[n++] = (uint8_t)v;
        s += k;
    }
    return n;
}

static void feed_hex(const char *s)
{
    uint8_t b[512];
    line_feed(b, hex(s, b));
}

/* Run the pure decoder over a hex string; returns the last event and
 * counts the messages in *msgs (last one in *m). */
static int dec_hex(serial_dec_t *d, const char *s, mac4_msg_t *m, int *msgs)
{
    uint8_t b[512];
    unsigned n = hex(s, b);
    int last = SERIAL_EV_NONE;
    for (unsigned i = 0; i < n; i++) {
        int ev = serial_dec_step(d, b[i], m);
        assert_true(d->n <= SERIAL_DATA_LEN);
        if (ev == SERIAL_EV_MSG && msgs)
            (*msgs)++;
        if (ev != SERIAL_EV_NONE)
            last = ev;
    }
    return last;
}

static uint32_t stat(uint32_t addr) { return dp_rd32(&card, addr); }

static uint32_t rng = 12345;
static uint32_t rnd(void)
{
    rng = rng * 1103515245u + 12345u;
    return rng >> 8;
}

/* ---- codec ------------------------------------------------------------------ */

/* Manual 7.3.1, "Response Message via the Serial Interface": the five
 * responses of the example, byte for byte (decimal in the manual). */
static void encode_manual_responses(void **st)
{
    (void)st;
    static const struct { uint16_t code; uint32_t param; uint8_t tel[10]; } ex[] = {
        {70, 0x02000101u, {16, 2, 0, 0, 70, 2, 0, 1, 1, 74}},
        {59, 0x02000101u, {16, 2, 0, 0, 59, 2, 0, 1, 1, 63}},
        {3, 0x02000108u, {16, 2, 0, 0, 3, 2, 0, 1, 8, 14}},
        {116, 0x000003E8u, {16, 2, 0, 0, 116, 0, 0, 3, 232, 95}},
        {161, 0x02002108u, {16, 2, 0, 0, 161, 2, 0, 33, 8, 204}},
    };
    for (unsigned i = 0; i < sizeof ex / sizeof ex[0]; i++) {
        mac4_msg_t m = {0, ex[i].code, ex[i].param, MSG_SRC_SERIAL};
        uint8_t buf[SERIAL_TELEGRAM_MAX + 8];
        memset(buf, 0xEE, sizeof buf);
        assert_int_equal(serial_encode(&m, buf), 10);
        assert_memory_equal(buf, ex[i].tel, 10);
        assert_int_equal(buf[10], 0xEE);                  /* nothing written beyond */
        assert_int_equal(serial_checksum(&ex[i].tel[2]), ex[i].tel[9]);
    }
}

static void encode_doubles_every_dle(void **st)
{
    (void)st;
    uint8_t buf[SERIAL_TELEGRAM_MAX];
    mac4_msg_t all = {0x10, 0x1010, 0x10101010u, 1};
    static const uint8_t want_all[] = {0x10, 0x02, 0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x10,
                                       0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x70};
    assert_int_equal(serial_encode(&all, buf), sizeof want_all);
    assert_memory_equal(buf, want_all, sizeof want_all);
    /* a checksum of $10 is sent doubled */
    mac4_msg_t c10 = {0, 1, 0x0000000Fu, 1};
    static const uint8_t want_c10[] = {0x10, 0x02, 0, 0, 1, 0, 0, 0, 0x0F, 0x10, 0x10};
    assert_int_equal(serial_encode(&c10, buf), sizeof want_c10);
    assert_memory_equal(buf, want_c10, sizeof want_c10);
    /* the longest possible telegram fits SERIAL_TELEGRAM_MAX */
    mac4_msg_t worst = {0x10, 0x1010, 0x101010B0u, 1};  /* six DLEs, sum $10 */
    assert_int_equal(serial_encode(&worst, buf), 17);
    assert_true(17 <= SERIAL_TELEGRAM_MAX);
}

/* Manual 7.3.1, "Transmit Message over the Serial Interface". */
static void decode_manual_commands(void **st)
{
    (void)st;
    static const struct { const char *tel; uint16_t code; uint32_t param; } ex[] = {
        {"10 02 00 00 46 00 00 00 10 10 56", 70, 16},      /* WAP 16: the DLE doubled */
        {"10 02 00 00 3B 00 00 00 00 3B", 59, 0},          /* MP */
        {"10 02 00 00 03 00 00 00 00 03", 3, 0},           /* E */
        {"10 02 00 00 74 00 00 00 00 74", 116, 0},         /* RCP */
        {"10 02 00 00 01 00 00 00 00 01", 1, 0},           /* not implemented */
    };
    serial_dec_t d;
    serial_dec_init(&d);
    for (unsigned i = 0; i < sizeof ex / sizeof ex[0]; i++) {
        mac4_msg_t m = {0xAA, 0xAAAA, 0xAAAAAAAAu, 0};
        int msgs = 0;
        assert_int_equal(dec_hex(&d, ex[i].tel, &m, &msgs), SERIAL_EV_MSG);
        assert_int_equal(msgs, 1);
        assert_int_equal(m.axis, 0);
        assert_int_equal(m.code, ex[i].code);
        assert_int_equal(m.param, ex[i].param);
        assert_int_equal(m.source, MSG_SRC_SERIAL);
        assert_false(serial_dec_busy(&d));
    }
    assert_int_equal(d.garbage, 0);
}

static void round_trip_random_messages(void **st)
{
    (void)st;
    serial_dec_t d;
    serial_dec_init(&d);
    for (int i = 0; i < 20000; i++) {
        /* bias towards $10 bytes so doubling is exercised a lot */
        uint32_t r = rnd();
        mac4_msg_t in = {(uint8_t)((r & 1) ? 0x10 : rnd()), (uint16_t)((r & 2) ? 0x1010 : rnd()),
                         (r & 4) ? 0x10101010u : (rnd() << 16 ^ rnd()), 0};
        uint8_t buf[SERIAL_TELEGRAM_MAX];
        unsigned n = serial_encode(&in, buf);
        assert_true(n >= 10 && n <= SERIAL_TELEGRAM_MAX);
        mac4_msg_t out;
        int msgs = 0;
        for (unsigned k = 0; k < n; k++) {
            int ev = serial_dec_step(&d, buf[k], &out);
            assert_true(ev == SERIAL_EV_NONE || ev == SERIAL_EV_MSG);
            msgs += ev == SERIAL_EV_MSG;
        }
        assert_int_equal(msgs, 1);
        assert_int_equal(out.axis, in.axis);
        assert_int_equal(out.code, in.code);
        assert_int_equal(out.param, in.param);
        assert_int_equal(out.source, MSG_SRC_SERIAL);
    }
    assert_int_equal(d.garbage, 0);   /* back-to-back telegrams, doubled $10 checksums: no garbage */
}

/* ---- decoder: broken input ---------------------------------------------------- */

static void bad_checksum_is_nak(void **st)
{
    (void)st;
    serial_dec_t d;
    mac4_msg_t m;
    serial_dec_init(&d);
    assert_int_equal(dec_hex(&d, "10 02 00 00 01 00 00 00 00 02", &m, NULL), SERIAL_EV_CHECKSUM);
    assert_false(serial_dec_busy(&d));
    int msgs = 0;
    assert_int_equal(dec_hex(&d, "10 02 00 00 01 00 00 00 00 01", &m, &msgs), SERIAL_EV_MSG);
    assert_int_equal(msgs, 1);
}

static void garbage_is_counted_and_skipped(void **st)
{
    (void)st;
    serial_dec_t d;
    mac4_msg_t m;
    int msgs = 0;
    serial_dec_init(&d);
    /* FF 00 41: 3, a DLE followed by a DLE: 1, DLE 41: 2, a lone STX: 1 */
    assert_int_equal(dec_hex(&d, "FF 00 41 10 10 41 02 10 02 00 00 03 00 00 00 00 03", &m, &msgs),
                     SERIAL_EV_MSG);
    assert_int_equal(msgs, 1);
    assert_int_equal(m.code, 3);
    assert_int_equal(d.garbage, 7);
}

static void truncated_telegram_restarts(void **st)
{
    (void)st;
    serial_dec_t d;
    mac4_msg_t m;
    serial_dec_init(&d);
    assert_int_equal(dec_hex(&d, "10 02 00 00 46 00", &m, NULL), SERIAL_EV_NONE);
    assert_int_equal(dec_hex(&d, "10 02", &m, NULL), SERIAL_EV_TRUNCATED);
    assert_true(serial_dec_busy(&d));
    int msgs = 0;
    assert_int_equal(dec_hex(&d, "00 00 3B 00 00 00 00 3B", &m, &msgs), SERIAL_EV_MSG);
    assert_int_equal(msgs, 1);
    assert_int_equal(m.code, 59);
    assert_int_equal(d.garbage, 0);
    /* cut short right before the checksum: the next header's DLE is taken
     * as the checksum (wrong, NAK) but also kept as a possible header DLE,
     * so its STX starts the next telegram */
    serial_dec_init(&d);
    assert_int_equal(dec_hex(&d, "10 02 00 00 46 00 00 00 05 10", &m, NULL), SERIAL_EV_CHECKSUM);
    msgs = 0;
    assert_int_equal(dec_hex(&d, "02 00 00 3B 00 00 00 00 3B", &m, &msgs), SERIAL_EV_MSG);
    assert_int_equal(msgs, 1);
    assert_int_equal(m.code, 59);
}

static void dle_then_other_is_broken(void **st)
{
    (void)st;
    serial_dec_t d;
    mac4_msg_t m;
    serial_dec_init(&d);
    /* an undoubled DLE in the data, followed by $00 */
    assert_int_equal(dec_hex(&d, "10 02 00 00 46 00 00 00 10 00", &m, NULL), SERIAL_EV_BROKEN);
    assert_false(serial_dec_busy(&d));
    /* a DLE as the last data byte, then the checksum: broken as well */
    serial_dec_init(&d);
    assert_int_equal(dec_hex(&d, "10 02 00 00 46 00 00 00 10 56", &m, NULL), SERIAL_EV_BROKEN);
    int msgs = 0;
    dec_hex(&d, "10 02 00 00 46 00 00 00 10 10 56", &m, &msgs);
    assert_int_equal(msgs, 1);
    assert_int_equal(m.param, 16);
}

static void dle_at_the_end_stalls(void **st)
{
    (void)st;
    serial_dec_t d;
    mac4_msg_t m;
    serial_dec_init(&d);
    assert_int_equal(dec_hex(&d, "10 02 00 00 46 00 00 00 10", &m, NULL), SERIAL_EV_NONE);
    assert_true(serial_dec_busy(&d));
    assert_int_equal(serial_dec_timeout(&d), SERIAL_EV_STALLED);
    assert_false(serial_dec_busy(&d));
    assert_int_equal(serial_dec_timeout(&d), SERIAL_EV_NONE);     /* once only */
    /* a lone DLE between telegrams is garbage, not a NAK */
    assert_int_equal(dec_hex(&d, "10", &m, NULL), SERIAL_EV_NONE);
    assert_int_equal(serial_dec_timeout(&d), SERIAL_EV_NONE);
    assert_int_equal(d.garbage, 1);
}

static void overlong_data(void **st)
{
    (void)st;
    serial_dec_t d;
    mac4_msg_t m;
    serial_dec_init(&d);
    /* eight data bytes: the eighth is taken as the checksum (wrong), the
     * real checksum is garbage, the next telegram is fine */
    assert_int_equal(dec_hex(&d, "10 02 00 00 01 00 00 00 00 00 01", &m, NULL), SERIAL_EV_CHECKSUM);
    int msgs = 0;
    assert_int_equal(dec_hex(&d, "10 02 00 00 74 00 00 00 00 74", &m, &msgs), SERIAL_EV_MSG);
    assert_int_equal(msgs, 1);
    assert_int_equal(d.garbage, 1);
}

static void checksum_dle_doubled_or_not(void **st)
{
    (void)st;
    serial_dec_t d;
    mac4_msg_t m;
    int msgs = 0;
    serial_dec_init(&d);
    /* code 1, parameter $0F: checksum $10 -- doubled, then undoubled, each
     * followed by another telegram, then undoubled at the very end */
    dec_hex(&d, "10 02 00 00 01 00 00 00 0F 10 10", &m, &msgs);
    dec_hex(&d, "10 02 00 00 03 00 00 00 00 03", &m, &msgs);
    dec_hex(&d, "10 02 00 00 01 00 00 00 0F 10", &m, &msgs);
    dec_hex(&d, "10 02 00 00 03 00 00 00 00 03", &m, &msgs);
    dec_hex(&d, "10 02 00 00 01 00 00 00 0F 10", &m, &msgs);
    assert_int_equal(msgs, 5);
    assert_int_equal(m.param, 0x0F);
    assert_int_equal(serial_dec_timeout(&d), SERIAL_EV_NONE);
    assert_int_equal(d.garbage, 0);
    /* an undoubled checksum $10 directly followed by STX: the DLE doubled
     * as the next header's DLE (the sender lost that one) */
    msgs = 0;
    dec_hex(&d, "10 02 00 00 01 00 00 00 0F 10 02 00 00 03 00 00 00 00 03", &m, &msgs);
    assert_int_equal(msgs, 2);
    assert_int_equal(d.garbage, 0);
    /* a doubled checksum DLE followed by anything else: that is garbage */
    dec_hex(&d, "10 02 00 00 01 00 00 00 0F 10 10 41", &m, &msgs);
    assert_int_equal(d.garbage, 1);
    dec_hex(&d, "10 02 00 00 01 00 00 00 0F 10 10 10 41", &m, &msgs);
    assert_int_equal(d.garbage, 3);
}

static void random_streams_resynchronise(void **st)
{
    (void)st;
    serial_dec_t d;
    mac4_msg_t m;
    serial_dec_init(&d);
    for (int round = 0; round < 2000; round++) {
        /* random bytes, DLE and STX made frequent */
        unsigned len = rnd() % 64;
        for (unsigned i = 0; i < len; i++) {
            uint32_t r = rnd();
            uint8_t b = (r & 3) == 0 ? 0x10 : (r & 3) == 1 ? 0x02 : (uint8_t)(r >> 8);
            int ev = serial_dec_step(&d, b, &m);
            assert_true(ev >= SERIAL_EV_NONE && ev <= SERIAL_EV_BROKEN);
            assert_true(d.n <= SERIAL_DATA_LEN);
        }
        /* after a pause, a valid telegram always gets through */
        serial_dec_timeout(&d);
        mac4_msg_t in = {(uint8_t)rnd(), (uint16_t)rnd(), rnd() ^ rnd() << 9, 0};
        uint8_t buf[SERIAL_TELEGRAM_MAX];
        unsigned n = serial_encode(&in, buf);
        int msgs = 0;
        for (unsigned k = 0; k < n; k++)
            msgs += serial_dec_step(&d, buf[k], &m) == SERIAL_EV_MSG;
        assert_int_equal(msgs, 1);
        assert_int_equal(m.code, in.code);
        assert_int_equal(m.param, in.param);
    }
}

/* ---- driver over the UART model ------------------------------------------------- */

static void driver_receives_and_answers(void **st)
{
    (void)st;
    serial_setup();
    assert_int_equal(card.uart.ctrl & UART_CTRL_TXIE, 0);
    feed_hex("10 02 00 00 46 00 00 00 10 10 56");
    mac4_msg_t m;
    assert_int_equal(serial_get(&m), 1);
    assert_int_equal(m.axis, 0);
    assert_int_equal(m.code, 70);
    assert_int_equal(m.param, 16);
    assert_int_equal(m.source, MSG_SRC_SERIAL);
    assert_int_equal(serial_get(&m), 0);
    assert_int_equal(stat(DPC_SERIAL_RX_OK), 1);
    /* nothing went into the DPRAM command queue */
    assert_int_equal(nsent, 0);

    mac4_msg_t r = {0, 70, 0x02000101u, MSG_SRC_SERIAL};
    serial_send(&r);
    assert_true(card.uart.ctrl & UART_CTRL_TXIE);
    line_run(MS_TO_CYC(30));
    static const uint8_t want[] = {16, 2, 0, 0, 70, 2, 0, 1, 1, 74};
    assert_int_equal(nsent, sizeof want);
    assert_memory_equal(sent, want, sizeof want);
    /* the transmit interrupt is off again once the ring is empty */
    assert_int_equal(card.uart.ctrl & UART_CTRL_TXIE, 0);
    assert_true(card.uart.ctrl & UART_CTRL_RXIE);
    assert_int_equal(stat(DPC_SERIAL_TX_OK), 1);
    assert_int_equal(stat(DPC_SERIAL_NAKS), 0);
}

static void driver_naks_bad_telegrams(void **st)
{
    (void)st;
    serial_setup();
    feed_hex("10 02 00 00 01 00 00 00 00 02");     /* bad checksum */
    line_run(MS_TO_CYC(5));
    assert_int_equal(nsent, 1);
    assert_int_equal(sent[0], SERIAL_NAK);
    feed_hex("10 02 00 00 46 00 00 00 10 00");     /* DLE + other */
    feed_hex("10 02 00 00 46 10 02 00 00 03 00 00 00 00 03");  /* truncated, then fine */
    line_run(MS_TO_CYC(5));
    assert_int_equal(nsent, 3);
    assert_int_equal(sent[1], SERIAL_NAK);
    assert_int_equal(sent[2], SERIAL_NAK);
    mac4_msg_t m;
    assert_int_equal(serial_get(&m), 1);
    assert_int_equal(m.code, 3);
    assert_int_equal(stat(DPC_SERIAL_NAKS), 3);
    assert_int_equal(stat(DPC_SERIAL_RX_OK), 1);
    assert_int_equal(stat(DPC_SERIAL_GARBAGE), 0);
    feed_hex("55 AA 10 41");
    assert_int_equal(stat(DPC_SERIAL_GARBAGE), 4);
    assert_int_equal(nsent, 3);                     /* garbage is not answered */
}

/* serial_poll() works only while there is news from the ISR or an open
 * telegram to time out: serial_rx_work says which, and serial_pending()
 * what serial_get() would give. */
static void driver_idles_without_work(void **st)
{
    (void)st;
    serial_setup();
    assert_int_equal(serial_rx_work, 0);
    assert_false(serial_pending());
    uart_feed(&card, (const uint8_t *)"\x10\x02\x00", 3);  /* a telegram begins */
    line_run_ex(3 * UART_CHAR_CYC + US_TO_CYC(500), 0);
    assert_int_equal(serial_rx_work, 1);                /* the ISR has news */
    serial_poll();
    assert_int_equal(serial_rx_work, 1);                /* open: its timeout needs watching */
    line_run(MS_TO_CYC(110));
    assert_int_equal(nsent, 1);                          /* timed out: NAK */
    assert_int_equal(serial_rx_work, 0);                /* nothing open any more */
    feed_hex("10 02 00 00 01 00 00 00 00 01");
    assert_int_equal(serial_rx_work, 0);
    assert_true(serial_pending());
    mac4_msg_t m;
    assert_int_equal(serial_get(&m), 1);
    assert_false(serial_pending());
    assert_int_equal(serial_get(&m), 0);
    /* an overrun alone (no byte taken) is news too: counted at the next poll */
    card.uart.rx_full = 1;
    card.uart.rx_hold = 0x41;
    card.uart.framing = 1;
    fw_isr_uart();
    assert_int_equal(serial_rx_work, 1);
    serial_poll();
    assert_int_equal(stat(DPC_SERIAL_FRAMING), 1);
    assert_int_equal(serial_rx_work, 0);
}

static void driver_drops_a_stalled_telegram(void **st)
{
    (void)st;
    serial_setup();
    feed_hex("10 02 00 00 46 00");
    line_run(MS_TO_CYC(90));
    assert_int_equal(nsent, 0);                     /* not yet */
    line_run(MS_TO_CYC(20));
    assert_int_equal(nsent, 1);
    assert_int_equal(sent[0], SERIAL_NAK);
    assert_int_equal(stat(DPC_SERIAL_NAKS), 1);
    /* the rest of it arriving late is garbage; the next telegram is fine */
    feed_hex("00 00 10 10 56");
    feed_hex("10 02 00 00 01 00 00 00 00 01");
    mac4_msg_t m;
    assert_int_equal(serial_get(&m), 1);
    assert_int_equal(m.code, 1);
    assert_int_equal(stat(DPC_SERIAL_GARBAGE), 5);  /* 00 00 10 10 56: no header among them */
    assert_int_equal(nsent, 1);
    /* the slow but steady sender is not timed out: a byte every 90 ms */
    static const uint8_t slow[] = {0x10, 0x02, 0, 0, 3, 0, 0, 0, 0, 3};
    for (unsigned i = 0; i < sizeof slow; i++) {
        line_feed(&slow[i], 1);
        line_run(MS_TO_CYC(90));
    }
    assert_int_equal(serial_get(&m), 1);
    assert_int_equal(m.code, 3);
    assert_int_equal(nsent, 1);
}

static void driver_full_fifo_naks_and_counts(void **st)
{
    (void)st;
    serial_setup();
    for (unsigned i = 0; i < SERIAL_FIFO_LEN + 2; i++) {
        mac4_msg_t c = {0, (uint16_t)(100 + i), i, 0};
        uint8_t buf[SERIAL_TELEGRAM_MAX];
        line_feed(buf, serial_encode(&c, buf));
    }
    line_run(MS_TO_CYC(5));
    assert_int_equal(stat(DPC_SERIAL_RX_OK), SERIAL_FIFO_LEN);
    assert_int_equal(stat(DPC_SERIAL_CMD_LOST), 2);
    assert_int_equal(stat(DPC_SERIAL_NAKS), 2);
    assert_int_equal(nsent, 2);
    assert_int_equal(sent[0], SERIAL_NAK);
    assert_int_equal(sent[1], SERIAL_NAK);
    mac4_msg_t m;
    for (unsigned i = 0; i < SERIAL_FIFO_LEN; i++) {
        assert_int_equal(serial_get(&m), 1);
        assert_int_equal(m.code, 100 + i);          /* in order */
        assert_int_equal(m.param, i);
    }
    assert_int_equal(serial_get(&m), 0);
    /* room again */
    feed_hex("10 02 00 00 01 00 00 00 00 01");
    assert_int_equal(serial_get(&m), 1);
}

static void driver_never_sends_half_a_telegram(void **st)
{
    (void)st;
    serial_setup();
    /* telegrams with doubled DLEs (17 bytes): 7 fit into 127 bytes of ring */
    mac4_msg_t r = {0x10, 0x1010, 0x10101010u, MSG_SRC_SERIAL};
    for (int i = 0; i < 20; i++)
        serial_send(&r);
    uint32_t ok = stat(DPC_SERIAL_TX_OK), lost = stat(DPC_SERIAL_TX_LOST);
    assert_int_equal(ok + lost, 20);
    assert_int_equal(ok, (SERIAL_TX_SIZE - 1) / 17);       /* whole telegrams only */
    line_run(MS_TO_CYC(400));
    assert_int_equal(nsent, ok * 17);
    uint8_t one[SERIAL_TELEGRAM_MAX];
    assert_int_equal(serial_encode(&r, one), 17);
    for (unsigned i = 0; i < ok; i++)
        assert_memory_equal(sent + 17 * i, one, 17);
    assert_int_equal(card.uart.ctrl & UART_CTRL_TXIE, 0);
    /* a NAK that does not fit is counted as lost too: hold the
     * transmitter (as if the line were blocked) and fill the ring */
    card.uart.tx_busy = 1;
    card.uart.tx_done = CYC_NEVER;
    for (int i = 0; i < 20; i++)
        serial_send(&r);
    lost = stat(DPC_SERIAL_TX_LOST);
    unsigned room = SERIAL_TX_SIZE - 1 - ok * 17;          /* 8 bytes */
    for (unsigned i = 0; i <= room; i++)
        feed_hex("10 02 00 00 01 00 00 00 00 02");
    assert_int_equal(stat(DPC_SERIAL_NAKS), room + 1);
    assert_int_equal(stat(DPC_SERIAL_TX_LOST), lost + 1);
    card.uart.tx_busy = 0;
    line_run(MS_TO_CYC(400));
    assert_int_equal(nsent, 2 * ok * 17 + room);
    for (unsigned i = 0; i < room; i++)
        assert_int_equal(sent[2 * ok * 17 + i], SERIAL_NAK);
    assert_int_equal(stat(DPC_SERIAL_TX_OK), 2 * ok);
    assert_int_equal(card.uart.ctrl & UART_CTRL_TXIE, 0);
}

static void driver_counts_overruns(void **st)
{
    (void)st;
    serial_setup();
    /* the main loop stalls: the ring fills, the ISR drops and counts */
    uint8_t b[300];
    for (unsigned i = 0; i < sizeof b; i++)
        b[i] = (uint8_t)(0x20 + i % 64);
    uart_feed(&card, b, sizeof b);
    line_run_ex((cyc_t)sizeof b * UART_CHAR_CYC + US_TO_CYC(500), 0);
    serial_poll();
    assert_int_equal(stat(DPC_SERIAL_OVERRUNS), sizeof b - (SERIAL_RX_SIZE - 1));
    assert_int_equal(stat(DPC_SERIAL_GARBAGE), SERIAL_RX_SIZE - 1);
    /* interrupts masked too long: the UART's holding register overruns */
    uart_feed(&card, b, 3);
    card.slice_base += 3 * UART_CHAR_CYC + US_TO_CYC(10);
    periph_events(&card, card.slice_base);
    fw_isr_uart();
    serial_poll();
    assert_int_equal(stat(DPC_SERIAL_OVERRUNS), sizeof b - (SERIAL_RX_SIZE - 1) + 1);
    assert_int_equal(stat(DPC_SERIAL_FRAMING), 0);
    card.uart.rx_full = 1;
    card.uart.rx_hold = 0x41;
    card.uart.framing = 1;
    fw_isr_uart();
    serial_poll();
    assert_int_equal(stat(DPC_SERIAL_FRAMING), 1);
    /* and it still works */
    feed_hex("10 02 00 00 01 00 00 00 00 01");
    mac4_msg_t m;
    assert_int_equal(serial_get(&m), 1);
}

static void driver_random_bytes(void **st)
{
    (void)st;
    serial_setup();
    mac4_msg_t m;
    uint8_t b[97];
    for (int round = 0; round < 60; round++) {
        for (unsigned i = 0; i < sizeof b; i++) {
            uint32_t r = rnd();
            b[i] = (r & 3) == 0 ? 0x10 : (r & 3) == 1 ? 0x02 : (uint8_t)(r >> 8);
        }
        line_feed(b, sizeof b);
        while (serial_get(&m))
            serial_send(&m);
        if (round % 8 == 0)
            line_run(MS_TO_CYC(150));
    }
    line_run(MS_TO_CYC(1000));
    /* every byte the card sent is a NAK or part of a whole telegram */
    serial_dec_t d;
    serial_dec_init(&d);
    unsigned naks = 0, tels = 0;
    for (unsigned i = 0; i < nsent; i++) {
        if (sent[i] == SERIAL_NAK && (d.state == SERIAL_DS_HUNT || d.state == SERIAL_DS_HUNT_DLE)) {
            naks++;
            continue;
        }
        int ev = serial_dec_step(&d, sent[i], &m);
        assert_true(ev == SERIAL_EV_NONE || ev == SERIAL_EV_MSG);
        tels += ev == SERIAL_EV_MSG;
    }
    assert_int_equal(d.garbage, 0);
    assert_true(naks > 0 && naks <= stat(DPC_SERIAL_NAKS));
    assert_true(naks + stat(DPC_SERIAL_TX_LOST) >= stat(DPC_SERIAL_NAKS));
    assert_int_equal(tels, stat(DPC_SERIAL_TX_OK));
    assert_int_equal(card.uart.ctrl & UART_CTRL_TXIE, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(encode_manual_responses),
        cmocka_unit_test(encode_doubles_every_dle),
        cmocka_unit_test(decode_manual_commands),
        cmocka_unit_test(round_trip_random_messages),
        cmocka_unit_test(bad_checksum_is_nak),
        cmocka_unit_test(garbage_is_counted_and_skipped),
        cmocka_unit_test(truncated_telegram_restarts),
        cmocka_unit_test(dle_then_other_is_broken),
        cmocka_unit_test(dle_at_the_end_stalls),
        cmocka_unit_test(overlong_data),
        cmocka_unit_test(checksum_dle_doubled_or_not),
        cmocka_unit_test(random_streams_resynchronise),
        cmocka_unit_test(driver_receives_and_answers),
        cmocka_unit_test(driver_naks_bad_telegrams),
        cmocka_unit_test(driver_idles_without_work),
        cmocka_unit_test(driver_drops_a_stalled_telegram),
        cmocka_unit_test(driver_full_fifo_naks_and_counts),
        cmocka_unit_test(driver_never_sends_half_a_telegram),
        cmocka_unit_test(driver_counts_overruns),
        cmocka_unit_test(driver_random_bytes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
