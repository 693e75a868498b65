/* k_crc16.c - witness kernel: firmware/crc16.c (the boot step "$3" check sum). */
#include "witness.h"
#include "crc16.c"

W_KERNEL(crc16)
{
    w_rng_t r;
    w_seed(&r, "crc16");
    crc16_init_table();
    for (unsigned i = 0; i < 256; i += 8) {
        w_begin("crc16", "table", i);
        for (unsigned k = 0; k < 8; k++)
            w_u32(crc16_entry(i + k));
        w_end();
    }
    /* the standard check value of CRC-16/CCITT-FALSE is $29B1 */
    static const char check[] = "123456789";
    uint16_t a = CRC16_INIT, b = CRC16_INIT;
    for (unsigned i = 0; check[i]; i++) {
        a = crc16_bitwise(a, (uint8_t)check[i]);
        b = crc16_update(b, (uint8_t)check[i]);
    }
    w_begin("crc16", "check", 0);
    w_u32(a);
    w_u32(b);
    w_end();
    for (uint32_t n = 0; n < 400; n++) {
        uint16_t x = (uint16_t)w_rand(&r), y = x;
        uint32_t len = n < 64 ? n : w_rand(&r) % 600u;
        for (uint32_t i = 0; i < len; i++) {
            uint8_t byte = (uint8_t)w_edgy(&r);
            x = crc16_bitwise(x, byte);
            y = crc16_update(y, byte);
        }
        w_begin("crc16", "buffer", n);
        w_u32(len);
        w_u32(x);
        w_u32(y);
        w_end();
    }
}
