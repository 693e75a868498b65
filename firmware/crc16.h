/* CRC-16/CCITT (poly $1021, init $FFFF, no reflection): the EPROM check sum
 * of the "$3" boot step (manual 2.5.2).  tools/mkeprom.py computes the same. */
#ifndef CRC16_H
#define CRC16_H
#include <stdint.h>

#define CRC16_INIT 0xFFFFu

/* The table of the byte-wise CRC as its two byte halves: a step is then
 * two byte moves and an EOR on the 68000, no 16-bit shifts (crc << 8 and
 * crc >> 8 are 22 cycles each there), which makes the boot's check sum of
 * the 64 KiB EPROM three times faster (docs/performance.md, "Boot"). */
extern uint8_t crc16_hi[256], crc16_lo[256];
void crc16_init_table(void);           /* fills the two 256-byte tables in RAM */

static inline uint16_t crc16_entry(unsigned i) { return (uint16_t)((unsigned)crc16_hi[i & 0xFFu] << 8 | crc16_lo[i & 0xFFu]); }

/* One byte into a CRC kept as its halves *hi, *lo. */
static inline void crc16_step(uint8_t *hi, uint8_t *lo, uint8_t byte)
{
    uint8_t i = (uint8_t)(*hi ^ byte);
    *hi = (uint8_t)(*lo ^ crc16_hi[i]);
    *lo = crc16_lo[i];
}

static inline uint16_t crc16_update(uint16_t crc, uint8_t byte)
{
    uint8_t hi = (uint8_t)(crc >> 8), lo = (uint8_t)crc;
    crc16_step(&hi, &lo, byte);
    return (uint16_t)((unsigned)hi << 8 | lo);
}
uint16_t crc16_bitwise(uint16_t crc, uint8_t byte); /* reference, no table */

#endif
