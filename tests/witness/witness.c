/* witness.c - output formatting and input generation shared by both builds. */
#include "witness.h"
#include "kernels.h"            /* build/witness: KERNEL(name) for every kernel built */

static char buf[4096];
static unsigned used;

void w_flush(void)
{
    if (used)
        w_write(buf, used);
    used = 0;
}

static void put(char c)
{
    if (used == sizeof buf)
        w_flush();
    buf[used++] = c;
}

void w_str(const char *s)
{
    while (*s)
        put(*s++);
}

static void hex32(uint32_t v)
{
    static const char hex[] = "0123456789abcdef";
    for (int i = 28; i >= 0; i -= 4)
        put(hex[(v >> i) & 15u]);
}

void w_u32(uint32_t v)
{
    put(' ');
    hex32(v);
}

void w_u64(uint64_t v)
{
    put(' ');
    hex32((uint32_t)(v >> 32));
    hex32((uint32_t)v);
}

void w_begin(const char *kernel, const char *what, uint32_t index)
{
    w_str(kernel);
    put(' ');
    w_str(what);
    w_u32(index);
}

void w_end(void) { put('\n'); }

void w_seed(w_rng_t *r, const char *name)
{
    uint32_t h = 2166136261u;
    while (*name) {
        h ^= (uint8_t)*name++;
        h = (h << 24) + (h << 8) + (h << 7) + (h << 4) + (h << 1) + h;   /* h * 16777619 */
    }
    r->s = h ? h : 1u;
}

uint32_t w_rand(w_rng_t *r)
{
    uint32_t x = r->s;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    r->s = x;
    return x;
}

uint32_t w_edgy(w_rng_t *r)
{
    uint32_t k = w_rand(r);
    switch (k & 7u) {
    case 0: return (k >> 3) & 3u;                            /* 0..3 */
    case 1: return 0u - ((k >> 3) & 3u);                     /* 0, -1, -2, -3 */
    case 2: return (uint32_t)1 << ((k >> 3) & 31u);
    case 3: return ((uint32_t)1 << ((k >> 3) & 31u)) - 1u;
    case 4: return 0x80000000u + ((k >> 3) & 1u) - ((k >> 4) & 1u);
    default: return w_rand(r);
    }
}

#define KERNEL(name) void k_##name(void);
KERNELS
#undef KERNEL

int w_main(void);
int w_main(void)
{
#define KERNEL(name) k_##name(); w_flush();
    KERNELS
#undef KERNEL
    w_str("end\n");
    w_flush();
    return 0;
}
