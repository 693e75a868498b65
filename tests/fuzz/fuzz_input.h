/* The fuzz input as a stream of numbers, big-endian as the card's bus: one
 * reader for the firmware targets (fuzz_card.h) and the emulator targets
 * (fuzz_emu.h).  A missing byte reads as 0, so every input is a whole run. */
#ifndef FUZZ_INPUT_H
#define FUZZ_INPUT_H
#include <stddef.h>
#include <stdint.h>

typedef struct {
    const uint8_t *p;
    size_t n, i;
} fz_in_t;

static inline int fz_more(const fz_in_t *in) { return in->i < in->n; }
static inline uint8_t fz_u8(fz_in_t *in) { return in->i < in->n ? in->p[in->i++] : 0; }
static inline uint16_t fz_u16(fz_in_t *in)
{
    uint16_t hi = fz_u8(in);
    return (uint16_t)(hi << 8 | fz_u8(in));
}
static inline uint32_t fz_u32(fz_in_t *in)
{
    uint32_t hi = fz_u16(in);
    return hi << 16 | fz_u16(in);
}

#endif
