/*
 * fuzz_emu.h - what the fuzz targets on the emulator share (fuzz_script.c,
 * fuzz_image.c, fuzz_card68k.c): the emulator as mac4sim links it (harness/,
 * Musashi), one card per input chosen by its first byte, the EPROM images of
 * the build, and a property check that names the input's card.
 */
#ifndef FUZZ_EMU_H
#define FUZZ_EMU_H
#include <setjmp.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "sim.h"
#include "cpu.h"
#include "fuzz_input.h"

#ifndef FZ_EPROM_DIR
#define FZ_EPROM_DIR "build/eprom"
#endif

static sim_t S;
static const char *const fz_cards[3] = {"inc", "ssi", "stp"};
static FILE *fz_null;               /* the card's events: not looked at */

static void fz_emu_fail(const char *file, int line, const char *fmt, ...) __attribute__((noreturn, format(printf, 3, 4)));
static void fz_emu_fail(const char *file, int line, const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "\nPROPERTY VIOLATED (%s:%d) on the %s card: ", file, line, fz_cards[S.card % 3]);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, "\n");
    abort();
}
#define FZ_FAIL(...) fz_emu_fail(__FILE__, __LINE__, __VA_ARGS__)
#define FZ_CHECK(cond, ...) do { if (!(cond)) FZ_FAIL(__VA_ARGS__); } while (0)

static inline FILE *fz_null_out(void)
{
    if (!fz_null)
        fz_null = fopen("/dev/null", "w");
    return fz_null;
}

/* The image of a card as the build made it: its bytes into buf (64 KiB). */
static inline size_t fz_card_image(int card, uint8_t *buf)
{
    char path[512];
    snprintf(path, sizeof path, "%s/mac4-%s.bin", getenv("FUZZ_EPROM_DIR") ? getenv("FUZZ_EPROM_DIR") : FZ_EPROM_DIR,
             fz_cards[card]);
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "fuzz: cannot open %s (make images first, or FUZZ_EPROM_DIR=)\n", path);
        exit(2);
    }
    size_t n = fread(buf, 1, EPROM_SIZE, f);
    fclose(f);
    return n;
}

#endif
