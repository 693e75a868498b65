/* witness_m68k.c - the 68000 side of the witness: a freestanding static
 * m68k Linux program (no C library: all of it is -m68000 code, so it runs
 * under qemu-m68k -cpu m68000), output through the write system call. */
#include "witness.h"

static long sys3(long nr, long a, long b, long c)
{
    register long d0 __asm__("d0") = nr;
    register long d1 __asm__("d1") = a;
    register long d2 __asm__("d2") = b;
    register long d3 __asm__("d3") = c;
    __asm__ volatile("trap #0" : "+d"(d0) : "d"(d1), "d"(d2), "d"(d3) : "memory", "cc");
    return d0;
}

void w_write(const char *s, unsigned n)
{
    while (n) {
        long k = sys3(4, 1, (long)s, (long)n);          /* write(1, s, n) */
        if (k <= 0)
            sys3(1, 2, 0, 0);                           /* exit(2) */
        s += k;
        n -= (unsigned)k;
    }
}

int w_main(void);
void w_start(void) __attribute__((noreturn));
void w_start(void)
{
    sys3(1, w_main(), 0, 0);                            /* exit */
    for (;;)
        ;
}
