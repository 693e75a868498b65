#include "crc16.h"

/* Built at boot rather than stored: 512 bytes of RAM instead of EPROM, and
 * one loop of 2048 bit steps (about 140k cycles, 9 ms) instead of a generated table. */
uint8_t crc16_hi[256], crc16_lo[256];

uint16_t crc16_bitwise(uint16_t crc, uint8_t byte)
{
    crc = (uint16_t)(crc ^ ((uint16_t)byte << 8));
    for (int i = 0; i < 8; i++)
        crc = (crc & 0x8000u) ? (uint16_t)((unsigned)(crc << 1) ^ 0x1021u) : (uint16_t)(crc << 1);
    return crc;
}

void crc16_init_table(void)
{
    for (unsigned i = 0; i < 256; i++) {
        uint16_t t = crc16_bitwise(0, (uint8_t)i);
        crc16_hi[i] = (uint8_t)(t >> 8);
        crc16_lo[i] = (uint8_t)t;
    }
}
