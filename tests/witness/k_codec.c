/* k_codec.c - witness kernel: the telegram codec, the encoder of
 * firmware/serial.c and the decoder of firmware/serial_dec.c. */
#include "witness.h"
#include "serial.c"
#include "serial_dec.c"

static uint8_t pick(w_rng_t *r)
{
    uint32_t k = w_rand(r);
    switch (k & 3u) {
    case 0: return SERIAL_DLE;
    case 1: return (k & 4u) ? SERIAL_STX : SERIAL_NAK;
    default: return (uint8_t)(k >> 8);
    }
}

W_KERNEL(codec)
{
    w_rng_t r;
    w_seed(&r, "codec");
    for (uint32_t n = 0; n < 600; n++) {
        mac4_msg_t m;
        /* one call per statement: C leaves the order within an expression open */
        m.axis = pick(&r);
        m.code = pick(&r);
        m.code = (uint16_t)(m.code << 8 | pick(&r));
        m.param = 0;
        for (int k = 0; k < 4; k++)
            m.param = m.param << 8 | pick(&r);
        m.source = 1;
        uint8_t buf[SERIAL_TELEGRAM_MAX + 2];
        unsigned len = serial_encode(&m, buf);
        w_begin("codec", "encode", n);
        w_u32(len);
        for (unsigned i = 0; i < len; i += 4) {
            uint32_t w = 0;
            for (unsigned k = 0; k < 4; k++)
                w = w << 8 | (i + k < len ? buf[i + k] : 0u);
            w_u32(w);
        }
        uint8_t data[SERIAL_DATA_LEN];
        for (unsigned i = 0; i < SERIAL_DATA_LEN; i++)
            data[i] = pick(&r);
        w_u32(serial_checksum(data));
        w_end();
    }
    for (uint32_t n = 0; n < 400; n++) {
        serial_dec_t d;
        serial_dec_init(&d);
        uint32_t len = w_rand(&r) % 80u;
        w_begin("codec", "stream", n);
        w_u32(len);
        for (uint32_t i = 0; i <= len; i++) {
            mac4_msg_t m = {0, 0, 0, 0};
            int ev = i < len ? serial_dec_step(&d, pick(&r), &m) : serial_dec_timeout(&d);
            if (ev != SERIAL_EV_NONE) {
                w_u32(i);
                w_u32((uint32_t)ev);
                if (ev == SERIAL_EV_MSG) {
                    w_u32(m.axis);
                    w_u32(m.code);
                    w_u32(m.param);
                }
            }
        }
        w_u32(d.garbage);
        w_u32((uint32_t)d.state << 24 | (uint32_t)d.n << 16 | (uint32_t)d.sum << 8 | d.free_dles);
        w_u32((uint32_t)serial_dec_busy(&d));
        w_end();
    }
}
