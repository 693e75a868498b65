/* CRC-16/CCITT (poly $1021, init $FFFF, no reflection): the EPROM check sum
 * of the "$3" boot step (manual 2.5.2).  tools/mkeprom.py computes the same. */
#ifndef CRC16_H
#define CRC16_H
#include <stdint.h>

#define CRC16_INIT 0xFFFFu

extern uint16_t crc16_table[256];
void crc16_init_table(void);           /* fills the 512-byte table in RAM */

static inline uint16_t crc16_update(uint16_t crc, uint8_t byte)
{
    return (uint16_t)((unsigned)(crc << 8) ^ crc16_table[(uint8_t)((crc >> 8) ^ byte)]);
}
uint16_t crc16_bitwise(uint16_t crc, uint8_t byte); /* reference, no table */

#endif
