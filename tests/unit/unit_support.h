/* Shared set-up for the native unit tests: an emulated card without a CPU,
 * whose bus the natively compiled firmware uses through hal/native. */
#ifndef UNIT_SUPPORT_H
#define UNIT_SUPPORT_H
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>
#include "sim.h"
#include "crc16.h"

extern jmp_buf *hal_native_stop_jmp;

/* Reproducible random inputs (xorshift64), and Q16 for the fixed-point tests. */
static uint64_t unit_seed = 0x9E3779B97F4A7C15ull;
static inline uint32_t rnd32(void)
{
    unit_seed ^= unit_seed << 13;
    unit_seed ^= unit_seed >> 7;
    unit_seed ^= unit_seed << 17;
    return (uint32_t)unit_seed;
}
#define Q(x) ((int64_t)(x) * 65536)

static sim_t card;
static char events[8192];          /* what the card printed (display ...) */
static FILE *events_f;

/* A card whose EPROM holds a pattern with a valid CRC, overlay released as
 * crt0 would, events captured in `events`. */
static inline void card_setup(void)
{
    sim_init(&card, MAC4_CARD_INC);
    for (unsigned i = 0; i < EPROM_CRC_OFFSET; i++)
        card.eprom[i] = (uint8_t)(i * 7u + 1u);
    uint16_t crc = CRC16_INIT;
    for (unsigned i = 0; i < EPROM_CRC_OFFSET; i++)
        crc = crc16_bitwise(crc, card.eprom[i]);
    card.eprom[EPROM_CRC_OFFSET] = (uint8_t)(crc >> 8);
    card.eprom[EPROM_CRC_OFFSET + 1] = (uint8_t)crc;
    card.eprom[EPROM_CRC_OFFSET + 2] = (uint8_t)~(crc >> 8);
    card.eprom[EPROM_CRC_OFFSET + 3] = (uint8_t)~crc;
    card.sysctl = 0;               /* crt0 releases the boot overlay */
    memset(events, 0, sizeof events);
    if (events_f)
        fclose(events_f);
    events_f = fmemopen(events, sizeof events - 1, "w");
    card.out = events_f;
}

#endif
