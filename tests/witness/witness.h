/*
 * witness.h - the qemu-m68k witness (docs/hardening.md): the firmware's
 * fixed-point kernels compiled twice, for the host and for the 68000 (run
 * under qemu-m68k -cpu m68000, an emulator independent of Musashi), fed the
 * same input vectors; the two outputs must be identical byte for byte.
 *
 * Output goes through w_* only: hexadecimal numbers formatted here, so no C
 * library is needed on the 68000 side (it runs freestanding, like the EPROM,
 * with the firmware's own integer helpers).
 */
#ifndef WITNESS_H
#define WITNESS_H
#include <stdint.h>

void w_write(const char *s, unsigned n);      /* witness_native.c / witness_m68k.c */

void w_begin(const char *kernel, const char *what, uint32_t index);
void w_u32(uint32_t v);
void w_u64(uint64_t v);
void w_str(const char *s);
void w_end(void);
void w_flush(void);

/* xorshift32: shifts and exclusive-or only, the same on both CPUs */
typedef struct { uint32_t s; } w_rng_t;
void w_seed(w_rng_t *r, const char *name);
uint32_t w_rand(w_rng_t *r);
/* a 32-bit value biased towards edges: 0, +-1, powers of two, extremes */
uint32_t w_edgy(w_rng_t *r);

#define W_KERNEL(name) void k_##name(void); void k_##name(void)

#endif
