/* k_encoder.c - witness kernel: encoder decoding in firmware/measure.c and
 * measure.h, its helpers.  The rest of the file is compiled but not called; both
 * links drop it (--gc-sections), so what it calls need not exist here. */
#include "witness.h"
#include "measure.c"

W_KERNEL(encoder)
{
    w_rng_t r;
    w_seed(&r, "encoder");
    w_begin("encoder", "eb_mask", 0);
    for (int32_t eb = 1; eb <= 32; eb++)
        w_u32(eb_mask(eb));
    w_end();
    for (uint32_t n = 0; n < 2000; n++) {
        int32_t eb = 1 + (int32_t)(w_rand(&r) % 32u);
        uint32_t now = w_edgy(&r), last = (n & 1) ? w_edgy(&r) : now - (w_rand(&r) & 0xFFFFu) + 0x8000u;
        uint32_t g = w_edgy(&r);
        /* measure_delta() (measure.h) as INIT prepares it: relative, the
         * counter wrapping at 2^<eb>, or at an <ec> below it */
        meas_cfg_t c = {0};
        axis_t x = {0};
        c.mask = eb_mask(eb);
        c.sign = eb < 32 ? (uint32_t)1 << (eb - 1) : 0;
        uint32_t ec = (n & 2) ? (w_rand(&r) & c.mask) | 2u : 0;
        if (ec && ec - 1u < c.mask) {
            c.range = (int32_t)(ec & 0x7FFFFFFFu);
            c.half = c.range >> 1;
        }
        x.linear = 1;
        x.counter = c.range ? (last & c.mask) % (uint32_t)c.range : last & c.mask;
        uint32_t raw = c.range ? (now & c.mask) % (uint32_t)c.range : now & c.mask;
        w_begin("encoder", "delta_gray", n);
        w_u32((uint32_t)eb);
        w_u32(raw);
        w_u32(x.counter);
        w_u32((uint32_t)c.range);
        w_u32((uint32_t)measure_delta(&x, &c, raw));
        w_u32(g);
        w_u32(gray_to_binary(g));
        w_end();
    }
}
