/* k_runtime.c - witness kernel: hal/target/runtime.c (the integer helpers
 * GCC calls on the 68000) and hal/mul16.h, directly and through C's own
 * operators (which the 68000 build turns into calls of those helpers). */
#include "witness.h"
#include "runtime.h"
#include "mul16.h"
#include <string.h>

W_KERNEL(runtime)
{
    w_rng_t r;
    w_seed(&r, "runtime");
    for (uint32_t n = 0; n < 3000; n++) {
        uint32_t a = w_edgy(&r), b = w_edgy(&r);   /* declarators are sequenced */
        int32_t sa = (int32_t)a, sb = (int32_t)b;
        uint32_t rem = 0, q = rt_udivmod32(a, b, &rem);
        w_begin("runtime", "mul_div", n);
        w_u32(a);
        w_u32(b);
        w_u32(rt_mul32(a, b));
        w_u32(q);
        w_u32(rem);
        w_u32((uint32_t)rt_div32(sa, sb));
        w_u32((uint32_t)rt_mod32(sa, sb));
        w_u32(a * b);                               /* __mulsi3 on the 68000 */
        if (b) {
            w_u32(a / b);                           /* __udivsi3 */
            w_u32(a % b);                           /* __umodsi3 */
            if (!(sa == INT32_MIN && sb == -1)) {
                w_u32((uint32_t)(sa / sb));         /* __divsi3 */
                w_u32((uint32_t)(sa % sb));         /* __modsi3 */
            }
        }
        w_u32(mulu16((uint16_t)a, (uint16_t)b));
        w_u32((uint32_t)muls16((int16_t)a, (int16_t)b));
        w_end();
    }
    for (uint32_t n = 0; n < 1000; n++) {
        uint32_t hi = w_edgy(&r), lo = w_edgy(&r);
        uint64_t v = (uint64_t)hi << 32 | lo;
        unsigned s = w_rand(&r) % 64u;
        w_begin("runtime", "shift64", n);
        w_u64(v);
        w_u32(s);
        w_u64(rt_lshr64(v, s));
        w_u64(rt_shl64(v, s));
        w_u64((uint64_t)rt_ashr64((int64_t)v, s));
        w_u64(v >> s);                              /* __lshrdi3 */
        w_u64(v << s);                              /* __ashldi3 */
        w_u64((uint64_t)((int64_t)v >> s));         /* __ashrdi3 */
        w_end();
    }
    /* memset, memcpy, memmove (runtime.c on the 68000: long moves where both
     * ends are even) at every parity of both ends, short and long */
    static uint8_t buf[160], src[160];
    for (uint32_t n = 0; n < 600; n++) {
        for (unsigned i = 0; i < sizeof buf; i++) {
            buf[i] = (uint8_t)(i * 7u + n);
            src[i] = (uint8_t)(i * 13u + 5u * n);
        }
        unsigned d = w_rand(&r) % 40u, s = w_rand(&r) % 40u, len = w_rand(&r) % (n & 1u ? 9u : 90u);
        switch (n % 3u) {
        case 0: memset(buf + d, (int)(w_rand(&r) & 0xFFu), len); break;
        case 1: memcpy(buf + d, src + s, len); break;
        default: memmove(buf + d, buf + s, len); break;
        }
        uint32_t h = 0;
        for (unsigned i = 0; i < sizeof buf; i++)
            h = (h << 5 | h >> 27) ^ buf[i];
        w_begin("runtime", "mem", n);
        w_u32(d << 16 | s << 8 | len);
        w_u32(h);
        w_end();
    }
}
