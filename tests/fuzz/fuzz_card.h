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

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerInitialize(int *argc, char ***argv);

extern jmp_buf *hal_native_stop_jmp;
unsigned hal_native_irq_mask(void);
extern int fz_boot_phase;
void fz_violation(const char *what, uint32_t addr, int size) __attribute__((noreturn));

static sim_t S;
static uint8_t fz_eprom[EPROM_SIZE];
static char fz_log[1 << 16];       /* what the card printed during the last pass */
static FILE *fz_log_f;
static jmp_buf fz_stop_jb;
static unsigned fz_resets;          /* watchdog resets during this input */

/* ---- failing --------------------------------------------------------------- */
static void fz_fail(const char *file, int line, const char *fmt, ...)
    __attribute__((noreturn, format(printf, 3, 4)));
static void fz_fail(const char *file, int line, const char *fmt, ...)
{
    va_list ap;
    fflush(fz_log_f);
    fprintf(stderr, "\nPROPERTY VIOLATED (%s:%d): ", file, line);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, "\ncard display %X, last events:\n%s\n", S.display, fz_log);
    abort();
}
#define FZ_FAIL(...) fz_fail(__FILE__, __LINE__, __VA_ARGS__)
#define FZ_CHECK(cond, ...) do { if (!(cond)) FZ_FAIL(__VA_ARGS__); } while (0)

/* ---- the fuzz input as a stream of numbers --------------------------------- */
typedef struct {
    const uint8_t *p;
    size_t n, i;
} fz_in_t;

static int fz_more(const fz_in_t *in) { return in->i < in->n; }
static uint8_t fz_u8(fz_in_t *in) { return in->i < in->n ? in->p[in->i++] : 0; }
static uint16_t fz_u16(fz_in_t *in)
{
    uint16_t hi = fz_u8(in);
    return (uint16_t)(hi << 8 | fz_u8(in));
}
static uint32_t fz_u32(fz_in_t *in)
{
    uint32_t hi = fz_u16(in);
    return hi << 16 | fz_u16(in);
}

/* ---- the firmware's stop (fw_halt) is a property violation here ---------- */
static void fz_check_card(const char *after)
{
    if (S.faults) {
        fflush(fz_log_f);
        FZ_FAIL("emulator fault after %s", after);
    }
}

static void fz_log_rewind(void)
{
    fflush(fz_log_f);
    fz_log[0] = 0;
    rewind(fz_log_f);
}

/* ---- power-on and reset ---------------------------------------------------- */
static void fz_boot_firmware(void)
{
    fz_boot_phase = 1;
    S.sysctl = 0;                   /* crt0 releases the boot overlay */
    hal_irq_restore(7);             /* the 68000 after reset: all masked */
    fw_boot_stage1();
    fw_init();
    fz_boot_phase = 0;
    fz_check_card("boot");
    FZ_CHECK(S.display == 5, "card did not reach display 5 at boot");
}

static void (*fz_on_reset)(void);  /* the target's bookkeeping after a watchdog reset */

static void fz_watchdog_reset(void)
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

static void fz_power_on(void)
{
    sim_init(&S, MAC4_CARD);
    memcpy(S.eprom, fz_eprom, sizeof fz_eprom);
    fz_log_rewind();
    S.out = fz_log_f;
    fz_resets = 0;
    hal_native_stop_jmp = &fz_stop_jb;
    fz_boot_firmware();
}

/* A 64 KiB EPROM pattern with a valid CRC (the firmware checks it at boot). */
static void fz_init_once(void)
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
}

/* ---- the scheduler ----------------------------------------------------------
 * Interrupts are served between main-loop passes, at the peripheral event
 * that raises them, with the 68000's priority rule. */
static void fz_serve_irqs(void)
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
static void fz_advance(cyc_t dt)
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
static void fz_pass(cyc_t dt)
{
    fz_log_rewind();
    fz_advance(dt);
    fw_main_step();
    fz_check_card("a main-loop pass");
}

/* ---- the VME host's side of the queues (manual 7.3.2) ------------------- */
static uint32_t fz_rd32(uint32_t a) { return dp_rd32(&S, a); }
static void fz_wr32(uint32_t a, uint32_t v) { dp_wr32(&S, a, v); }

/* The header as q_check sees it. */
static int fz_hdr_ok(uint32_t q)
{
    return fz_rd32(q + QH_BASE) == Q_HEADER_SIZE && fz_rd32(q + QH_WIDTH) == Q_WIDTH &&
           fz_rd32(q + QH_NEL) == Q_NEL && fz_rd32(q + QH_FRONT) < Q_NEL && fz_rd32(q + QH_REAR) < Q_NEL;
}

/* Restore a queue header the host wrecked: the fixed words, and the
 * indices so that the queue is empty (the host throws away what was in it:
 * for the command queue its own front goes to the card's rear, for the
 * response queue its own rear to the card's front; an index out of range
 * becomes 0). */
static void fz_hdr_repair(uint32_t q)
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

static fz_elem_t fz_elem(uint32_t q, uint32_t i)
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
static int fz_host_drain(void)
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

static int fz_is_error(uint16_t code) { return code >= ERR_AXIS && code <= ERR_HSTOP; }

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
static uint16_t fz_code(fz_in_t *in)
{
    uint8_t b = fz_u8(in);
    if (b < 0xF0)
        return fz_codes[((unsigned)b << 8 | fz_u8(in)) % FZ_NCODES];
    if (b < 0xF8)
        return (uint16_t)(b - 0xF0);            /* 0..7 */
    return fz_u16(in);
}

/* A parameter value: small numbers, edges and anything. */
static uint32_t fz_param(fz_in_t *in)
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

/* Guard a call into the firmware: fw_halt/hal_stop longjmp here. */
#define FZ_FW_GUARD()                                                                 \
    do {                                                                              \
        if (setjmp(fz_stop_jb))                                                       \
            FZ_FAIL("the firmware stopped the card (boot error $%X, fault vector %u)", \
                    (unsigned)fz_rd32(DPC_BOOT_ERROR), (unsigned)fz_rd32(DPC_FAULT_VECTOR)); \
    } while (0)

#endif
