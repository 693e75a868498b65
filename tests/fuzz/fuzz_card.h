/*
 * fuzz_card.h - the emulated MAC4 without a CPU, for the fuzz targets
 * (docs/hardening.md).  The firmware is compiled natively (HAL_NATIVE, as
 * in tests/unit) against the emulator's bus and peripheral models; this
 * file is the rest of a card: boot, a scheduler that serves the interrupts
 * between main-loop passes, the watchdog reset, and a VME host that uses
 * the DPRAM queues as manual 7.3.2 describes.
 *
 * Each target includes this file once and defines LLVMFuzzerTestOneInput.
 * A broken property prints "PROPERTY VIOLATED: ..." and aborts, which
 * libFuzzer records as a crash and the corpus replay as a failure.
 */
#ifndef FUZZ_CARD_H
#define FUZZ_CARD_H
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "sim.h"
#include "periph.h"
#include "hal.h"
#include "fw.h"
#include "crc16.h"
#include "queue.h"
#include "card.h"
#include "cmd.h"
#include "params.h"
#include "serial.h"
#include "fuzz_input.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerInitialize(int *argc, char ***argv);

extern jmp_buf *hal_native_stop_jmp;
unsigned hal_native_irq_mask(void);
extern int fz_boot_phase;
extern void (*fz_violation_hook)(const char *what, uint32_t addr, int size);
extern void (*fz_ubsan_hook)(const char *kind, const char *msg, const char *file, unsigned line);

static sim_t S;
static uint8_t fz_eprom[EPROM_SIZE];
static char fz_log[1 << 16];       /* what the card printed during the last pass */
static FILE *fz_log_f;
static jmp_buf fz_stop_jb;
static unsigned fz_resets;          /* watchdog resets during this input */

/* ---- known bugs ------------------------------------------------------------
 * Bugs found by these targets in code this harness does not own, reported
 * and not fixed yet (docs/hardening.md, "Findings").  While the card's state
 * shows the trigger of one, a broken property is counted as that bug and the
 * input ends quietly, so the fuzzer can go on looking for new ones.
 * FUZZ_STRICT=1 turns this off (make fuzz-known replays the reproducers). */
static jmp_buf fz_known_jb;
static int fz_known_armed;
static unsigned long fz_known_hits;
static const char *fz_known_ub;    /* undefined behaviour of a known bug seen (UBSan recovered) */

/* Undefined behaviour of known bugs: UBSan reports it once per place per
 * process (and the 68000 simply wraps), then the input ends. */
static inline const char *fz_known_ub_bug(const char *msg, const char *file)
{
    /* K3 (the setpoint interpolation overflowing 32 bits) is fixed: the
     * positions wrap modulo 2^32 as on the 68000 (card.h pos_add/pos_sub);
     * its reproducer is in corpus/cmd.  No undefined behaviour is known. */
    (void)msg;
    (void)file;
    return NULL;
}

static inline const char *fz_known_bug(const char *failure)
{
    /* K1 (unchecked <ea>) and K2 (encoder error re-reported every tick) are
     * fixed (measure.c, cmd.c); their reproducers are in corpus/.  No
     * state-triggered known bug is open. */
    (void)failure;
    return NULL;
}

/* ---- failing --------------------------------------------------------------- */
static inline void fz_fail(const char *file, int line, const char *fmt, ...)
    __attribute__((noreturn, format(printf, 3, 4)));
static inline void fz_fail(const char *file, int line, const char *fmt, ...)
{
    char msg[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    const char *known = fz_known_bug(msg);
    if (known && fz_known_armed && !getenv("FUZZ_STRICT")) {
        fz_known_hits++;
        if (getenv("FUZZ_TRACE"))
            fprintf(stderr, "known bug, input ends: %s (%s)\n", known, msg);
        longjmp(fz_known_jb, 1);
    }
    fflush(fz_log_f);
    fprintf(stderr, "\nPROPERTY VIOLATED (%s:%d): %s\ncard display %X, last events:\n%s\n", file, line, msg,
            S.sys.display, fz_log);
    if (known)
        fprintf(stderr, "(the card's state shows the trigger of known bug %s)\n", known);
    abort();
}

#define FZ_FAIL(...) fz_fail(__FILE__, __LINE__, __VA_ARGS__)

static inline void fz_violation_in_hal(const char *what, uint32_t addr, int size)
{
    FZ_FAIL("%s at $%06X (size %d)", what, (unsigned)addr, size);
}

static inline void fz_ubsan_report(const char *kind, const char *msg, const char *file, unsigned line)
{
    const char *known = fz_known_ub_bug(msg, file);
    if (known && !getenv("FUZZ_STRICT")) {
        fz_known_ub = known;        /* fz_check_card() ends the input */
        return;
    }
    fprintf(stderr, "\nUNDEFINED BEHAVIOUR (%s) at %s:%u: %s\n", kind, file, line, msg);
    abort();
}
#define FZ_CHECK(cond, ...) do { if (!(cond)) FZ_FAIL(__VA_ARGS__); } while (0)

/* ---- the firmware's stop (fw_halt) is a property violation here ---------- */
static inline void fz_check_card(const char *after)
{
    if (fz_known_ub && fz_known_armed) {
        fz_known_hits++;
        if (getenv("FUZZ_TRACE"))
            fprintf(stderr, "known bug, input ends: %s\n", fz_known_ub);
        fz_known_ub = NULL;
        longjmp(fz_known_jb, 1);
    }
    if (S.faults) {
        fflush(fz_log_f);
        FZ_FAIL("emulator fault after %s", after);
    }
}

static inline void fz_log_rewind(void)
{
    fflush(fz_log_f);
    fz_log[0] = 0;
    rewind(fz_log_f);
}

/* ---- power-on and reset ---------------------------------------------------- */
static inline void fz_boot_firmware(void)
{
    fz_boot_phase = 1;
    S.sysctl = 0;                   /* crt0 releases the boot overlay */
    hal_irq_restore(7);             /* the 68000 after reset: all masked */
    fw_boot_stage1();
    fw_init();
    fz_boot_phase = 0;
    fz_check_card("boot");
    FZ_CHECK(S.sys.display == 5, "card did not reach display 5 at boot");
}

static void (*fz_on_reset)(void);  /* the target's bookkeeping after a watchdog reset */

static inline void fz_watchdog_reset(void)
{
    /* What run.c's sim_reset does, with the native firmware as the CPU. */
    S.in_reset_by_wdg = 1;
    S.resets++;
    S.nactive = 0;
    periph_reset(&S);
    fz_resets++;
    fz_boot_firmware();
    if (fz_on_reset)
        fz_on_reset();
}

/* Power-on: a full boot (RAM test, EPROM check sum: 2 ms natively) for
 * the replay.  The libFuzzer builds (FZ_FAST_BOOT) boot in full once, keep
 * the emulated card as it was then, and afterwards start each input from
 * that copy with the firmware's state set as fw_init() leaves it
 * (card_reset, card_start); fz_init_once() checks that this gives the very
 * same card as a full boot, and falls back to full boots if not. */
static sim_t fz_booted;
static int fz_fast;                 /* 1: fz_booted is valid and the fast path is exact */

static inline void fz_full_boot(void)
{
    sim_init(&S, MAC4_CARD);
    memcpy(S.eprom, fz_eprom, sizeof fz_eprom);
    S.out = fz_log_f;
    fz_boot_firmware();
}

static inline void fz_fast_boot(void)
{
    memcpy(&S, &fz_booted, sizeof S);
    g_sim = &S;
    fz_boot_phase = 1;
    hal_irq_restore(7);
    card_reset();
    card_start();
    fz_boot_phase = 0;
}

static inline void fz_power_on(void)
{
    fz_log_rewind();
    fz_resets = 0;
    hal_native_stop_jmp = &fz_stop_jb;
    fz_violation_hook = fz_violation_in_hal;
    fz_ubsan_hook = fz_ubsan_report;
    fz_known_ub = NULL;
    if (fz_fast)
        fz_fast_boot();
    else
        fz_full_boot();
    S.out = fz_log_f;
}

/* A 64 KiB EPROM pattern with a valid CRC (the firmware checks it at boot). */
static inline void fz_init_once(void)
{
    if (fz_log_f)
        return;
    for (unsigned i = 0; i < EPROM_CRC_OFFSET; i++)
        fz_eprom[i] = (uint8_t)(i * 7u + 1u);
    uint16_t crc = CRC16_INIT;
    for (unsigned i = 0; i < EPROM_CRC_OFFSET; i++)
        crc = crc16_bitwise(crc, fz_eprom[i]);
    fz_eprom[EPROM_CRC_OFFSET] = (uint8_t)(crc >> 8);
    fz_eprom[EPROM_CRC_OFFSET + 1] = (uint8_t)crc;
    fz_eprom[EPROM_CRC_OFFSET + 2] = (uint8_t)~(crc >> 8);
    fz_eprom[EPROM_CRC_OFFSET + 3] = (uint8_t)~crc;
    fz_log_f = fmemopen(fz_log, sizeof fz_log - 1, "w");
    if (!fz_log_f)
        abort();
#ifdef FZ_FAST_BOOT
    hal_native_stop_jmp = NULL;          /* a boot failure here aborts */
    fz_violation_hook = NULL;
    fz_full_boot();
    memcpy(&fz_booted, &S, sizeof S);
    fz_fast_boot();
    static sim_t fast;
    memcpy(&fast, &S, sizeof S);
    fz_full_boot();
    fz_fast = !memcmp(&fast, &S, sizeof S);
    if (!fz_fast)
        fprintf(stderr, "fuzz_card.h: the fast boot differs from fw_init(): full boots, slower\n");
#endif
}

/* Every target's libFuzzer initialisation (each target is one binary). */
int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    fz_init_once();
    return 0;
}

/* ---- the scheduler ----------------------------------------------------------
 * Interrupts are served between main-loop passes, at the peripheral event
 * that raises them, with the 68000's priority rule. */
static inline void fz_serve_irqs(void)
{
    for (int guard = 0;; guard++) {
        int lvl = sim_irq_level(&S);
        unsigned mask = hal_native_irq_mask();
        if (lvl == 0 || (lvl < 7 && (unsigned)lvl <= mask))
            return;
        FZ_CHECK(guard < 64, "interrupt level %d stays asserted after its handler ran", lvl);
        hal_irq_restore((unsigned)lvl);   /* the CPU raises the mask to the level taken */
        switch (lvl) {
        case IRQ_LEVEL_ESTOP: estop_irq_ack(&S); fw_isr_estop(); break;
        case IRQ_LEVEL_TIMER: fw_isr_tick(); break;
        case IRQ_LEVEL_AXIS: fw_isr_axis(); break;
        case IRQ_LEVEL_UART: fw_isr_uart(); break;
        default: FZ_FAIL("interrupt level %d has no handler", lvl);
        }
        hal_irq_restore(mask);
        fz_check_card("an interrupt handler");
    }
}

/* Let time pass with the main loop stalled: only interrupts run. */
static inline void fz_advance(cyc_t dt)
{
    cyc_t end = S.slice_base + dt;
    while (S.slice_base < end) {
        cyc_t next = periph_next_event(&S);
        if (next > end)
            next = end;
        if (next <= S.slice_base)
            next = S.slice_base + 1;
        S.slice_base = next;
        periph_events(&S, next);
        if (S.wdg.reset_pending) {
            fz_watchdog_reset();
            continue;
        }
        fz_serve_irqs();
    }
}

/* One main-loop pass after dt cycles. */
static inline void fz_pass(cyc_t dt)
{
    fz_log_rewind();
    fz_advance(dt);
    fw_main_step();
    fz_check_card("a main-loop pass");
}

/* ---- the VME host's side of the queues (manual 7.3.2) ------------------- */
static inline uint32_t fz_rd32(uint32_t a) { return dp_rd32(&S, a); }
static inline void fz_wr32(uint32_t a, uint32_t v) { dp_wr32(&S, a, v); }

/* The header as q_check sees it. */
static inline int fz_hdr_ok(uint32_t q)
{
    return fz_rd32(q + QH_BASE) == Q_HEADER_SIZE && fz_rd32(q + QH_WIDTH) == Q_WIDTH &&
           fz_rd32(q + QH_NEL) == Q_NEL && fz_rd32(q + QH_FRONT) < Q_NEL && fz_rd32(q + QH_REAR) < Q_NEL;
}

/* Restore a queue header the host wrecked: the fixed words, and the
 * indices so that the queue is empty (the host throws away what was in it:
 * for the command queue its own front goes to the card's rear, for the
 * response queue its own rear to the card's front; an index out of range
 * becomes 0). */
static inline void fz_hdr_repair(uint32_t q)
{
    fz_wr32(q + QH_BASE, Q_HEADER_SIZE);
    fz_wr32(q + QH_WIDTH, Q_WIDTH);
    fz_wr32(q + QH_NEL, Q_NEL);
    uint32_t card_idx = fz_rd32(q + (q == DP_CMD_QUEUE ? QH_REAR : QH_FRONT));
    if (card_idx >= Q_NEL)
        card_idx = 0;
    fz_wr32(q + QH_FRONT, card_idx);
    fz_wr32(q + QH_REAR, card_idx);
}

typedef struct {
    uint8_t axis, source, pad1, pad2;
    uint16_t code;
    uint32_t param;
} fz_elem_t;

static inline fz_elem_t fz_elem(uint32_t q, uint32_t i)
{
    uint32_t e = q + Q_HEADER_SIZE + i * Q_WIDTH;
    fz_elem_t m;
    m.axis = S.dpram[e + MSG_AXIS];
    m.pad1 = S.dpram[e + MSG_AXIS + 1];
    m.code = dp_rd16(&S, e + MSG_CODE);
    m.param = dp_rd32(&S, e + MSG_PARAM);
    m.source = S.dpram[e + MSG_SOURCE];
    m.pad2 = S.dpram[e + MSG_SOURCE + 1];
    return m;
}

/* Dequeue every response; returns how many (0 if the header is unusable). */
static inline int fz_host_drain(void)
{
    int n = 0;
    while (fz_hdr_ok(DP_RSP_QUEUE)) {
        uint32_t f = fz_rd32(DP_RSP_QUEUE + QH_FRONT), r = fz_rd32(DP_RSP_QUEUE + QH_REAR);
        if (f == r)
            break;
        fz_wr32(DP_RSP_QUEUE + QH_REAR, q_next(r, Q_NEL));
        n++;
    }
    return n;
}

static inline int fz_is_error(uint16_t code) { return code >= ERR_AXIS && code <= ERR_HSTOP; }

/* ---- codes known to the firmware (any card), to steer the fuzzer --------- */
static const uint16_t fz_codes[] = {
#define GEN(mn, code, cards, kind, desc) code,
#define MODESEL(mn, code, cards, mode, desc) code,
#define DIAG(mn, code, cards, units, desc) code,
#define PARAM(id, mn, kind, wcode, cards, flags, min, max, def, units, desc) wcode, (wcode) + 1,
#include "commands.def"
};
#define FZ_NCODES (sizeof fz_codes / sizeof fz_codes[0])

/* A code: mostly one the firmware knows, sometimes anything. */
static inline uint16_t fz_code(fz_in_t *in)
{
    uint8_t b = fz_u8(in);
    if (b < 0xF0)
        return fz_codes[((unsigned)b << 8 | fz_u8(in)) % FZ_NCODES];
    if (b < 0xF8)
        return (uint16_t)(b - 0xF0);            /* 0..7 */
    return fz_u16(in);
}

/* A parameter value: small numbers, edges and anything. */
static inline uint32_t fz_param(fz_in_t *in)
{
    uint8_t b = fz_u8(in);
    switch (b >> 5) {
    case 0: return b & 31u;
    case 1: return (uint32_t)-(int32_t)(b & 31u);
    case 2: return (uint32_t)fz_u8(in) << (b & 31u);
    case 3: {
        static const uint32_t edge[] = {0x7FFFFFFFu, 0x80000000u, 0xFFFFFFu, 0x1000000u, 0x10u,
                                        0x1010u, 0x101010u, 0x10101010u, 65535u, 65536u, 8388607u,
                                        3600000u, 1000000000u, 0xC4653600u, 2047u, 50000u};
        return edge[b & 15u];
    }
    default: return fz_u32(in);
    }
}

/* At the end: the host repairs what it broke, and VER is answered.
 * What the firmware promises (firmware/cmd.c, 5.15): commands held behind an
 * off-fly move wait there, at most CMD_HOLD_MAX of them; once the moves have
 * ended they are released one per main-loop pass, oldest first, each answered
 * once (with 163 when the stop's error waits to be reported), and a read such
 * as VER is never held.  The repair empties both queues, and only a command
 * taken is answered (a response that finds the queue full is counted in
 * DPC_RSP_LOST, not kept), so one VER asked once is answered after at most
 * CMD_HOLD_MAX other answers, within FZ_STOP_PASSES passes for the moves to
 * stop plus one pass per held command.  Only a watchdog reset, which clears
 * the queues, is a reason to ask again. */
#define FZ_STOP_PASSES 2000         /* 0.5 s at 250 us: every stop ramp is shorter */
static inline void fz_final_ver_vme(cyc_t pass_cyc)
{
    estop_set(&S, 0);
    S.wdg.j11 = 1;
    /* A command held in off-fly (5.15) waits for its axis' move, which may
     * not end by itself (speed mode, a search that finds no index): like a
     * host that wants its card back, stop every axis with the stop bits
     * (3.5.1) first. */
    dp_wr16(&S, DP_STOP_BITS, 0x00AA);
    for (int asked = 0; asked < 4; asked++) {
        fz_hdr_repair(DP_CMD_QUEUE);
        fz_hdr_repair(DP_RSP_QUEUE);
        FZ_CHECK(host_send(&S, 0, 7, 0, 0) == 1, "VER could not be queued after repair");
        unsigned resets0 = fz_resets, others = 0;
        for (int passes = 0; passes <= FZ_STOP_PASSES + CMD_HOLD_MAX + 2 && fz_resets == resets0;) {
            uint32_t f = fz_rd32(DP_RSP_QUEUE + QH_FRONT), r = fz_rd32(DP_RSP_QUEUE + QH_REAR);
            if (f != r) {
                fz_elem_t rsp = fz_elem(DP_RSP_QUEUE, r);
                fz_wr32(DP_RSP_QUEUE + QH_REAR, q_next(r, Q_NEL));   /* dequeue one */
                if (getenv("FUZZ_TRACE"))
                    fprintf(stderr, "  answer %u %u $%08X\n", rsp.axis, rsp.code, (unsigned)rsp.param);
                if (rsp.code == 7 && rsp.axis == 0) {
                    FZ_CHECK(rsp.param == FW_VER_WORD, "VER answered $%08X", (unsigned)rsp.param);
                    return;
                }
                others++;       /* a held command answered now */
                FZ_CHECK(others <= CMD_HOLD_MAX, "%u answers before VER's, more than %u held commands",
                         others, CMD_HOLD_MAX);
                continue;       /* the next answer may be in the queue already */
            }
            fz_pass(pass_cyc);
            passes++;
        }
        if (fz_resets == resets0)
            break;              /* no reset: the card did not answer */
    }
    FZ_FAIL("the card no longer answers VER (queues: command front %u rear %u, response front %u rear %u)",
            (unsigned)fz_rd32(DP_CMD_QUEUE + QH_FRONT), (unsigned)fz_rd32(DP_CMD_QUEUE + QH_REAR),
            (unsigned)fz_rd32(DP_RSP_QUEUE + QH_FRONT), (unsigned)fz_rd32(DP_RSP_QUEUE + QH_REAR));
}

/* Guard a call into the firmware: fw_halt/hal_stop longjmp here; a known
 * bug ends the input here (return 0 from LLVMFuzzerTestOneInput). */
#define FZ_FW_GUARD()                                                                 \
    do {                                                                              \
        if (setjmp(fz_stop_jb))                                                       \
            FZ_FAIL("the firmware stopped the card (boot error $%X, fault vector %u)", \
                    (unsigned)fz_rd32(DPC_BOOT_ERROR), (unsigned)fz_rd32(DPC_FAULT_VECTOR)); \
        fz_known_armed = 1;                                                           \
        if (setjmp(fz_known_jb)) {                                                    \
            fz_known_armed = 0;                                                       \
            return 0;                                                                 \
        }                                                                             \
    } while (0)

#endif
