/*
 * fuzz_hal.c - hal/native for the fuzz targets, with the checks a real
 * 68000 would make for us.  harness/hal_native.c is compiled unchanged
 * here, with its two calls into the emulator's bus renamed to the checking
 * versions below:
 *   - a word or long access at an odd address is an address error on the
 *     68000 (the card would stop with "F."): property violated;
 *   - while the firmware runs (not during boot), a write into the live
 *     vector table / boot area of the DPRAM ($0000-$2FFF) or into a word of
 *     the queue headers the card does not own is a property violation
 *     (manual 7.3.2: the card writes only the command queue's rear and the
 *     response queue's front and elements).
 * Everything else (unmapped accesses, EPROM writes, byte writes to word
 * registers) the bus itself counts in sim_t.faults, which the targets check
 * after every call into the firmware.
 */
#include <stdio.h>
#include <stdlib.h>
#include "sim.h"

int fz_boot_phase = 1;           /* 1 while the card boots: it creates the queues */
/* fuzz_card.h's failure path (known bugs, the card's last events) */
void (*fz_violation_hook)(const char *what, uint32_t addr, int size);

static void fz_violation(const char *what, uint32_t addr, int size) __attribute__((noreturn));
static void fz_violation(const char *what, uint32_t addr, int size)
{
    if (fz_violation_hook)
        fz_violation_hook(what, addr, size);
    fprintf(stderr, "\nPROPERTY VIOLATED: %s at $%06X (size %d)\n", what, (unsigned)addr, size);
    abort();
}

/* UBSan reports (the fuzz builds recover from them, -fsanitize-recover=
 * undefined) come here first: fuzz_card.h decides whether it is a known bug
 * (the input ends quietly) or not (abort: a crash for libFuzzer). */
void (*fz_ubsan_hook)(const char *kind, const char *msg, const char *file, unsigned line);
#ifndef FZ_NO_SAN                /* the coverage build (make fuzz-cov) has no sanitizers */
void __ubsan_get_current_report_data(const char **kind, const char **msg, const char **file, unsigned *line,
                                     unsigned *col, char **addr);
void __ubsan_on_report(void);
void __ubsan_on_report(void)
{
    const char *kind = "", *msg = "", *file = "";
    unsigned line = 0, col = 0;
    char *addr = NULL;
    __ubsan_get_current_report_data(&kind, &msg, &file, &line, &col, &addr);
    if (!fz_ubsan_hook)
        abort();
    fz_ubsan_hook(kind, msg, file ? file : "", line);
}
#endif

static int card_owns(uint32_t a)
{
    if (a < DP_HOST_AREA)
        return 0;                                          /* vectors, monitor, boot stack */
    if (a >= DP_CMD_QUEUE && a < DP_CMD_QUEUE + 0x100)     /* command queue: rear only */
        return a - (DP_CMD_QUEUE + QH_REAR) < 4;
    if (a >= DP_RSP_QUEUE && a < DP_RSP_QUEUE + Q_HEADER_SIZE)
        return a - (DP_RSP_QUEUE + QH_FRONT) < 4;          /* response queue: front ... */
    return 1;                                              /* ... and elements, host area */
}

static uint32_t fz_bus_read(sim_t *s, uint32_t a, int size)
{
    if (size > 1 && (a & 1u))
        fz_violation("address error (odd word/long read)", a, size);
    return bus_read(s, a, size);
}

static void fz_bus_write(sim_t *s, uint32_t a, uint32_t v, int size)
{
    if (size > 1 && (a & 1u))
        fz_violation("address error (odd word/long write)", a, size);
    if (!fz_boot_phase && a < DPRAM_SIZE)
        for (int i = 0; i < size; i++)
            if (!card_owns(a + (uint32_t)i))
                fz_violation("card wrote DPRAM it does not own", a + (uint32_t)i, size);
    bus_write(s, a, v, size);
}

#define bus_read fz_bus_read
#define bus_write fz_bus_write
#include "../../harness/hal_native.c"
