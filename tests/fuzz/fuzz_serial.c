/*
 * fuzz_serial.c - the front-panel serial line (manual 3.3, 7.3.1,
 * docs/serial.md) under arbitrary byte streams.
 *
 * Part 1, the pure codec: the input bytes go through serial_dec_step and,
 * in parallel, through an independent decoder written here from the table
 * in docs/serial.md; both must give the same events and garbage counts, and
 * every message decoded must encode (serial_encode) to a telegram that
 * decodes back to it.
 *
 * Part 2, the driver on the emulated UART: the input is a sequence of
 * operations (well-formed telegrams encoded here, raw bytes, bursts, pauses,
 * main-loop stalls, framing errors).  The reference decoder follows the
 * bytes the card receives, with the 100 ms timeout applied at long pauses.
 * Everything the card sends is parsed (it must be telegrams and NAKs only,
 * with correct checksums and DLE doubling).  Whenever the line is quiet:
 *   - every telegram the reference decoded was taken (RX_OK) or refused with
 *     a NAK (CMD_LOST); every one taken was executed (DPC_COMMANDS) and
 *     answered once: its response telegram is on the wire or counted in
 *     TX_LOST; the NAKs match the reference's broken telegrams;
 *   - without refusals or TX losses, the responses answer the decoded
 *     commands one by one, in order (axis, code or error 160-165);
 *   - a host that waits for each answer (every operation here but bursts
 *     and stalls) loses nothing: no CMD_LOST, no TX_LOST.
 * Byte loss (overruns in a stall, a watchdog reset) makes the card's decoder
 * and the reference part ways; they meet again at the next long pause, and
 * only the counting identities are checked in between.
 * At the end the card answers VER over the line.
 */
#include "fuzz_card.h"

/* ---- an independent decoder, from the table in docs/serial.md ----------- */
enum { R_HUNT, R_HDR, R_DATA, R_ESC, R_CSUM };
typedef struct {
    int st, n, free;
    uint8_t d[7], sum;
    uint32_t garbage, msgs, naks;
} ref_t;

/* Feed one byte; returns SERIAL_EV_* and fills m on a message. */
static int ref_step(ref_t *r, uint8_t b, mac4_msg_t *m)
{
    switch (r->st) {
    case R_HUNT:
        r->free = 0;
        if (b == 0x10)
            r->st = R_HDR;
        else
            r->garbage++;
        return SERIAL_EV_NONE;
    case R_HDR:
        if (b == 0x02) {
            r->st = R_DATA;
            r->n = 0;
            r->sum = 0;
            r->free = 0;
            return SERIAL_EV_NONE;
        }
        if (r->free) r->free--; else r->garbage++;        /* the held DLE */
        if (b != 0x10) {
            r->garbage++;
            r->free = 0;
            r->st = R_HUNT;
        }
        return SERIAL_EV_NONE;
    case R_DATA:
        if (b == 0x10) {
            r->st = R_ESC;
            return SERIAL_EV_NONE;
        }
        break;
    case R_ESC:
        if (b == 0x02) {
            r->st = R_DATA;
            r->n = 0;
            r->sum = 0;
            r->free = 0;
            r->naks++;
            return SERIAL_EV_TRUNCATED;
        }
        if (b != 0x10) {
            r->st = R_HUNT;
            r->naks++;
            return SERIAL_EV_BROKEN;
        }
        break;                                            /* a data byte $10 */
    case R_CSUM: {
        int ok = b == r->sum;
        if (ok) {
            m->axis = r->d[0];
            m->code = (uint16_t)(r->d[1] << 8 | r->d[2]);
            m->param = (uint32_t)r->d[3] << 24 | (uint32_t)r->d[4] << 16 | (uint32_t)r->d[5] << 8 | r->d[6];
            m->source = MSG_SRC_SERIAL;
            r->msgs++;
        } else {
            r->naks++;
        }
        if (b == 0x10) {
            r->st = R_HDR;
            r->free = 2;
        } else {
            r->st = R_HUNT;
        }
        return ok ? SERIAL_EV_MSG : SERIAL_EV_CHECKSUM;
    }
    }
    r->d[r->n++] = b;                                     /* DATA or ESC: one data byte */
    r->sum = (uint8_t)(r->sum + b);
    r->st = r->n == 7 ? R_CSUM : R_DATA;
    return SERIAL_EV_NONE;
}

static int ref_timeout(ref_t *r)
{
    int ev = SERIAL_EV_NONE;
    if (r->st == R_HDR) {
        if (r->free) r->free--; else r->garbage++;
    } else if (r->st != R_HUNT) {
        ev = SERIAL_EV_STALLED;
        r->naks++;
    }
    r->st = R_HUNT;
    r->free = 0;
    return ev;
}

/* ---- an independent encoder (manual 3.3) --------------------------------- */
static unsigned encode(uint8_t axis, uint16_t code, uint32_t param, uint8_t *out)
{
    uint8_t d[7] = {axis, (uint8_t)(code >> 8), (uint8_t)code, (uint8_t)(param >> 24),
                    (uint8_t)(param >> 16), (uint8_t)(param >> 8), (uint8_t)param};
    unsigned n = 0;
    uint8_t sum = 0;
    out[n++] = 0x10;
    out[n++] = 0x02;
    for (int i = 0; i < 7; i++) {
        out[n++] = d[i];
        if (d[i] == 0x10)
            out[n++] = 0x10;
        sum = (uint8_t)(sum + d[i]);
    }
    out[n++] = sum;
    if (sum == 0x10)
        out[n++] = 0x10;
    return n;
}

/* ---- part 1: the pure codec ----------------------------------------------- */
static void codec_differential(const uint8_t *data, size_t size)
{
    serial_dec_t d;
    ref_t r;
    serial_dec_init(&d);
    memset(&r, 0, sizeof r);
    for (size_t i = 0; i <= size; i++) {
        mac4_msg_t m1 = {0, 0, 0, 0}, m2 = {0, 0, 0, 0};
        int e1, e2;
        if (i == size) {                 /* the line goes quiet */
            e1 = serial_dec_timeout(&d);
            e2 = ref_timeout(&r);
        } else {
            e1 = serial_dec_step(&d, data[i], &m1);
            e2 = ref_step(&r, data[i], &m2);
        }
        FZ_CHECK(e1 == e2, "decoder event %d, reference %d at byte %zu", e1, e2, i);
        FZ_CHECK(d.n <= SERIAL_DATA_LEN, "decoder data count %u", d.n);
        FZ_CHECK(serial_dec_busy(&d) == (r.st != R_HUNT), "decoder busy %d in reference state %d",
                 serial_dec_busy(&d), r.st);
        if (e1 == SERIAL_EV_MSG) {
            FZ_CHECK(m1.axis == m2.axis && m1.code == m2.code && m1.param == m2.param &&
                     m1.source == MSG_SRC_SERIAL, "decoded message differs from the reference");
            /* the card's encoder: same bytes as ours, and back again */
            uint8_t buf[SERIAL_TELEGRAM_MAX + 2], mine[SERIAL_TELEGRAM_MAX + 2];
            memset(buf, 0xEE, sizeof buf);
            unsigned n = serial_encode(&m1, buf);
            FZ_CHECK(n >= 10 && n <= SERIAL_TELEGRAM_MAX && buf[n] == 0xEE, "encode length %u", n);
            FZ_CHECK(n == encode(m1.axis, m1.code, m1.param, mine) && !memcmp(buf, mine, n),
                     "serial_encode differs from manual 3.3");
            serial_dec_t d2;
            serial_dec_init(&d2);
            mac4_msg_t back = {0, 0, 0, 0};
            int last = SERIAL_EV_NONE;
            for (unsigned k = 0; k < n; k++) {
                int ev = serial_dec_step(&d2, buf[k], &back);
                FZ_CHECK(ev == SERIAL_EV_NONE || (k == n - 1 || (k == n - 2 && buf[k] == 0x10)),
                         "event %d inside an encoded telegram", ev);
                if (ev != SERIAL_EV_NONE)
                    last = ev;
            }
            FZ_CHECK(last == SERIAL_EV_MSG && back.axis == m1.axis && back.code == m1.code &&
                     back.param == m1.param, "round trip");
            FZ_CHECK(d2.garbage == 0, "encoded telegram left garbage");
        }
    }
    FZ_CHECK(d.garbage == r.garbage, "garbage %u, reference %u", (unsigned)d.garbage, (unsigned)r.garbage);
}

/* ---- part 2: the driver ---------------------------------------------------- */
#define PASS_CYC US_TO_CYC(1000)
#define MAX_MS 20000

/* what the card sent */
typedef struct { uint8_t axis; uint16_t code; uint32_t param; } rsp_t;
static uint8_t out_bytes[1 << 16];
static unsigned out_n, out_parsed;
static rsp_t wire_rsp[4096];
static unsigned wire_nrsp, wire_naks;
/* what the reference decoded */
static mac4_msg_t ref_msg[4096];
static ref_t ref;
static unsigned ref_nmsg;
/* bookkeeping */
static int lossy;                  /* bytes were lost: reference and card part ways */
static int impolite;               /* a burst or a stall: losses allowed */
static unsigned ms_used;
static unsigned vme_cmds;          /* commands through the VME queue since the last reset */
/* since the last reset (the card's counters restart, the wire does not) */
static unsigned ep_rsp, ep_nak;
/* since the reference last agreed with the card (boot, or a long pause after a loss) */
static unsigned sy_rsp, sy_msg;
static uint32_t sy_rx, sy_naks, sy_garbage, sy_cmd_lost, sy_tx_lost;

static void on_tx(void *ctx, uint8_t b)
{
    (void)ctx;
    if (out_n < sizeof out_bytes)
        out_bytes[out_n++] = b;
}

/* Parse what the card sent so far: NAKs and whole telegrams only. */
static void parse_output(void)
{
    for (;;) {
        unsigned i = out_parsed;
        if (i >= out_n)
            return;
        if (out_bytes[i] == SERIAL_NAK) {
            wire_naks++;
            out_parsed = i + 1;
            continue;
        }
        FZ_CHECK(out_bytes[i] == 0x10, "card sent $%02X outside a telegram", out_bytes[i]);
        if (i + 1 >= out_n)
            return;
        FZ_CHECK(out_bytes[i + 1] == 0x02, "card sent DLE $%02X", out_bytes[i + 1]);
        i += 2;
        uint8_t d[7], sum = 0;
        for (int k = 0; k < 7; k++) {
            if (i >= out_n)
                return;
            d[k] = out_bytes[i++];
            if (d[k] == 0x10) {
                if (i >= out_n)
                    return;
                FZ_CHECK(out_bytes[i] == 0x10, "card did not double a DLE");
                i++;
            }
            sum = (uint8_t)(sum + d[k]);
        }
        if (i >= out_n)
            return;
        FZ_CHECK(out_bytes[i] == sum, "card sent checksum $%02X, the sum is $%02X", out_bytes[i], sum);
        i++;
        if (sum == 0x10) {
            if (i >= out_n)
                return;
            FZ_CHECK(out_bytes[i] == 0x10, "checksum $10 not doubled");
            i++;
        }
        FZ_CHECK(wire_nrsp < sizeof wire_rsp / sizeof wire_rsp[0], "too many responses");
        rsp_t *r = &wire_rsp[wire_nrsp++];
        r->axis = d[0];
        r->code = (uint16_t)(d[1] << 8 | d[2]);
        r->param = (uint32_t)d[3] << 24 | (uint32_t)d[4] << 16 | (uint32_t)d[5] << 8 | d[6];
        out_parsed = i;
    }
}

static void ref_event(int ev, const mac4_msg_t *m)
{
    if (ev == SERIAL_EV_MSG && ref_nmsg < sizeof ref_msg / sizeof ref_msg[0])
        ref_msg[ref_nmsg++] = *m;
}

static uint32_t busy_ms;
static int timed;
static uint32_t now_ms(void);

static void feed(const uint8_t *b, unsigned n)
{
    uart_feed(&S, b, n);
    busy_ms = now_ms();
    timed = 0;
    for (unsigned i = 0; i < n; i++) {
        mac4_msg_t m;
        ref_event(ref_step(&ref, b[i], &m), &m);
    }
}

static uint32_t st(uint32_t a) { return fz_rd32(a); }

static int wire_idle(void) { return S.uart.wire_head == S.uart.wire_tail && S.uart.rx_done == CYC_NEVER; }

static void parse_output(void);

static void on_reset(void)
{
    /* MR or a watchdog reset: what was in the rings is gone, and a response
     * being sent may be cut short */
    parse_output();
    out_parsed = out_n;
    ep_rsp = wire_nrsp;
    ep_nak = wire_naks;
    vme_cmds = 0;
    lossy = 1;
}

/* The card's decoder times out 100 ms after serial_poll last took a byte
 * (SERIAL_TIMEOUT_US): the poll of the main-loop pass in which the last byte
 * arrived, so at the first pass more than 100 ms later.  Passes are 1 ms
 * apart here: that is 102 ms after the last pass that still saw the line
 * busy (busy_ms).  The reference takes its timeout in that same pass
 * (timed: taken for this quiet spell). */

static uint32_t now_ms(void) { return (uint32_t)(S.slice_base / US_TO_CYC(1000)); }
static uint32_t quiet_ms(void) { return now_ms() - busy_ms; }

static void passes(unsigned ms)
{
    for (; ms > 0 && ms_used < MAX_MS; ms--, ms_used++) {
        fz_pass(PASS_CYC);
        if (!wire_idle()) {
            busy_ms = now_ms();
            timed = 0;
        } else if (!timed && quiet_ms() >= 102) {
            mac4_msg_t m;
            ref_event(ref_timeout(&ref), &m);
            timed = 1;
        }
    }
}

/* Counting identities, valid whenever the line is quiet. */
static void check_quiet(void)
{
    parse_output();
    FZ_CHECK(out_parsed == out_n, "card stopped in the middle of a telegram");
    uint32_t rx_ok = st(DPC_SERIAL_RX_OK), naks = st(DPC_SERIAL_NAKS), cmd_lost = st(DPC_SERIAL_CMD_LOST);
    uint32_t tx_ok = st(DPC_SERIAL_TX_OK), tx_lost = st(DPC_SERIAL_TX_LOST);
    unsigned e_rsp = wire_nrsp - ep_rsp, e_nak = wire_naks - ep_nak;
    FZ_CHECK(st(DPC_COMMANDS) - vme_cmds == rx_ok, "%u telegrams taken, %u executed", (unsigned)rx_ok,
             (unsigned)(st(DPC_COMMANDS) - vme_cmds));
    FZ_CHECK(tx_ok == e_rsp, "%u responses queued, %u on the wire", (unsigned)tx_ok, e_rsp);
    FZ_CHECK(rx_ok + naks == e_rsp + e_nak + tx_lost,
             "taken %u + NAKs %u != responses %u + NAKs sent %u + TX lost %u", (unsigned)rx_ok,
             (unsigned)naks, e_rsp, e_nak, (unsigned)tx_lost);
    if (!impolite)
        FZ_CHECK(cmd_lost == 0 && tx_lost == 0, "a polite host lost %u commands, %u responses",
                 (unsigned)cmd_lost, (unsigned)tx_lost);
    if (lossy)
        return;
    FZ_CHECK(rx_ok + cmd_lost - sy_rx == ref.msgs, "card took %u + refused %u telegrams, reference %u",
             (unsigned)(rx_ok - sy_rx), (unsigned)cmd_lost, (unsigned)ref.msgs);
    FZ_CHECK(naks - cmd_lost - sy_naks == ref.naks, "card NAKs %u (%u refusals), reference %u",
             (unsigned)(naks - sy_naks), (unsigned)cmd_lost, (unsigned)ref.naks);
    FZ_CHECK(st(DPC_SERIAL_GARBAGE) - sy_garbage == ref.garbage, "garbage %u, reference %u",
             (unsigned)(st(DPC_SERIAL_GARBAGE) - sy_garbage), (unsigned)ref.garbage);
    if (cmd_lost == sy_cmd_lost && tx_lost == sy_tx_lost) {
        FZ_CHECK(wire_nrsp - sy_rsp == ref_nmsg - sy_msg, "%u responses for %u commands",
                 wire_nrsp - sy_rsp, ref_nmsg - sy_msg);
        for (unsigned i = 0; i < wire_nrsp - sy_rsp; i++) {
            const rsp_t *r = &wire_rsp[sy_rsp + i];
            const mac4_msg_t *m = &ref_msg[sy_msg + i];
            FZ_CHECK(r->axis == m->axis, "response %u: axis %u for axis %u", i, r->axis, m->axis);
            FZ_CHECK(r->code == m->code || fz_is_error(r->code), "response %u: code %u for %u", i,
                     r->code, m->code);
            if (m->axis >= MAC4_NAXES)
                FZ_CHECK(r->code == ERR_AXIS, "axis %u answered %u", m->axis, r->code);
            if (m->code == 7 && r->code == 7)
                FZ_CHECK(r->param == FW_VER_WORD, "VER answered $%08X", (unsigned)r->param);
        }
    }
}

/* The reference and the card agree again (both hunt after a timeout). */
static void resync(void)
{
    lossy = 0;
    memset(&ref, 0, sizeof ref);
    sy_rsp = wire_nrsp;
    sy_msg = ref_nmsg;
    sy_rx = st(DPC_SERIAL_RX_OK) + st(DPC_SERIAL_CMD_LOST);
    sy_naks = st(DPC_SERIAL_NAKS) - st(DPC_SERIAL_CMD_LOST);
    sy_garbage = st(DPC_SERIAL_GARBAGE);
    sy_cmd_lost = st(DPC_SERIAL_CMD_LOST);
    sy_tx_lost = st(DPC_SERIAL_TX_LOST);
}

/* Wait until the line is quiet: nothing on the wire either way, every
 * command taken executed.  Up to 80 ms after the last byte nothing times
 * out; past that, wait until 120 ms so that the 100 ms timeout surely came
 * (then the reference takes it too). */
static void settle(int allow_long)
{
    while (!wire_idle() && ms_used < MAX_MS)
        passes(1);
    uint32_t start = now_ms();
    for (;;) {
        int quiet = !S.uart.tx_busy && !(S.uart.ctrl & UART_CTRL_TXIE) &&
                    st(DPC_COMMANDS) - vme_cmds == st(DPC_SERIAL_RX_OK) && quiet_ms() >= 3;
        if ((quiet && (!allow_long || timed)) || ms_used >= MAX_MS)
            break;
        if (now_ms() - start == 1500)
            dp_wr16(&S, DP_STOP_BITS, 0x00AA);   /* a command held off-fly (5.15): stop the moves */
        FZ_CHECK(now_ms() - start < 2500, "the line is idle, but after 2.5 s commands %u, taken %u, TX %s",
                 (unsigned)(st(DPC_COMMANDS) - vme_cmds), (unsigned)st(DPC_SERIAL_RX_OK),
                 S.uart.tx_busy || (S.uart.ctrl & UART_CTRL_TXIE) ? "busy" : "idle");
        passes(1);
    }
    if (ms_used >= MAX_MS)
        return;
    check_quiet();
    if (timed && lossy)
        resync();
}

static void send_cmd(fz_in_t *in)
{
    uint8_t a = fz_u8(in);
    uint8_t axis = (a & 0x80) ? a : (uint8_t)(a & 3u);
    uint16_t code = fz_code(in);
    uint8_t tel[SERIAL_TELEGRAM_MAX];
    uint32_t param = fz_param(in);
    unsigned n = encode(axis, code, param, tel);
    if (getenv("FUZZ_TRACE"))
        fprintf(stderr, "  send axis %u code %u param $%08X at %llu us\n", axis, code, (unsigned)param,
                (unsigned long long)(S.slice_base / MAC4_CYCLES_PER_US));
    feed(tel, n);
}

static void final_ver(void)
{
    estop_set(&S, 0);
    /* A <wd> shorter than a few telegrams (21 ms each) locks a serial-only
     * host out: every command is answered 164 and not executed (6.3.6), and
     * then 163 until C.  A VME host can still switch it off (C, C, WWD 0 in
     * quick succession): do that first. */
    fz_hdr_repair(DP_CMD_QUEUE);
    fz_hdr_repair(DP_RSP_QUEUE);
    unsigned resets0 = fz_resets;
    host_send(&S, 0, 4, 0, 0);
    host_send(&S, 0, 4, 0, 0);
    host_send(&S, 0, 138, 0, 0);
    for (int i = 0; i < 6; i++) {
        fz_pass(US_TO_CYC(100));
        fz_host_drain();
    }
    if (fz_resets == resets0) {
        FZ_CHECK(fz_rd32(DP_CMD_QUEUE + QH_FRONT) == fz_rd32(DP_CMD_QUEUE + QH_REAR), "VME commands not taken");
        vme_cmds += 3;
    }
    for (int attempt = 0; attempt < 5; attempt++) {
        settle(1);                 /* whatever was in progress times out */
        unsigned before = wire_nrsp;
        uint8_t tel[SERIAL_TELEGRAM_MAX];
        unsigned n = encode(0, 7, 0, tel);
        feed(tel, n);
        unsigned resets0 = fz_resets;
        for (int ms = 0; ms < 300 && wire_nrsp == before && fz_resets == resets0; ms++) {
            fz_pass(PASS_CYC);
            parse_output();
        }
        if (wire_nrsp > before) {
            const rsp_t *r = &wire_rsp[wire_nrsp - 1];
            if (getenv("FUZZ_TRACE"))
                fprintf(stderr, "  VER answered %u $%08X\n", r->code, (unsigned)r->param);
            FZ_CHECK(r->axis == 0, "VER answered for axis %u", r->axis);
            if (r->code == 7) {
                FZ_CHECK(r->param == FW_VER_WORD, "VER answered $%08X", (unsigned)r->param);
                return;
            }
            FZ_CHECK(fz_is_error(r->code), "VER answered with code %u", r->code);
        }
    }
    FZ_FAIL("the card no longer answers VER over the serial line");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_init_once();
    codec_differential(data, size);

    FZ_FW_GUARD();
    fz_on_reset = on_reset;
    fz_power_on();
    S.uart.on_tx = on_tx;
    out_n = out_parsed = wire_nrsp = wire_naks = 0;
    ref_nmsg = 0;
    busy_ms = 0;
    timed = 1;
    ep_rsp = ep_nak = 0;
    vme_cmds = 0;
    impolite = 0;
    ms_used = 0;
    resync();
    fz_in_t in = {data, size, 0};
    while (fz_more(&in) && ms_used < MAX_MS) {
        uint8_t op = fz_u8(&in);
        switch (op % 8) {
        case 0:                                    /* one command, then wait for the answer */
        case 1:
            send_cmd(&in);
            settle(0);
            break;
        case 2: {                                  /* raw bytes */
            uint8_t b[64];
            unsigned n = 1 + fz_u8(&in) % 48;
            for (unsigned i = 0; i < n; i++)
                b[i] = fz_u8(&in);
            feed(b, n);
            if (op & 0x80)
                break;                             /* more bytes follow at once */
            settle(0);
            break;
        }
        case 3: {                                  /* a pause; long ones time out */
            uint8_t b = fz_u8(&in);
            settle(b >= 0x80);
            passes(b & 0x3F);
            break;
        }
        case 4: {                                  /* a burst of commands, not waiting */
            impolite = 1;
            for (int k = 2 + fz_u8(&in) % 10; k > 0; k--)
                send_cmd(&in);
            settle(0);
            break;
        }
        case 5: {                                  /* the main loop stalls while bytes come */
            impolite = 1;
            lossy = 1;
            for (int k = 1 + fz_u8(&in) % 8; k > 0; k--)
                send_cmd(&in);
            fz_advance(US_TO_CYC(1000u * (1u + fz_u8(&in))));
            busy_ms = now_ms();               /* the card polls everything only now */
            timed = 0;
            settle(1);
            break;
        }
        case 6:                                    /* a framing error on the next character */
            S.uart.framing = 1;
            break;
        case 7: {                                  /* a telegram with one byte changed */
            uint8_t tel[SERIAL_TELEGRAM_MAX];
            unsigned n = encode(fz_u8(&in) & 3u, fz_code(&in), fz_param(&in), tel);
            uint8_t at = fz_u8(&in);
            tel[at % n] ^= fz_u8(&in);
            feed(tel, n);
            settle(0);
            break;
        }
        }
    }
    settle(1);
    final_ver();
    fz_check_card("the final VER");
    if (getenv("FUZZ_TRACE"))
        fprintf(stderr, "serial: %u ms, %u responses, %u NAKs on the wire, reference %u telegrams, "
                "card RX_OK %u NAKS %u GARBAGE %u CMD_LOST %u TX_LOST %u, resets %u%s%s\n", ms_used,
                wire_nrsp, wire_naks, ref_nmsg, (unsigned)st(DPC_SERIAL_RX_OK), (unsigned)st(DPC_SERIAL_NAKS),
                (unsigned)st(DPC_SERIAL_GARBAGE), (unsigned)st(DPC_SERIAL_CMD_LOST),
                (unsigned)st(DPC_SERIAL_TX_LOST), fz_resets, lossy ? " lossy" : "", impolite ? " impolite" : "");
    return 0;
}
