/* k_encoder.c - witness kernel: encoder decoding in firmware/measure.c, its
 * static helpers.  The rest of the file is compiled but not called; both
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
        w_begin("encoder", "delta_gray", n);
        w_u32((uint32_t)eb);
        w_u32(now);
        w_u32(last);
        w_u32((uint32_t)delta_eb(now & eb_mask(eb), last & eb_mask(eb), eb));
        w_u32(g);
        w_u32(gray_to_binary(g));
        w_end();
    }
}
