/* witness_native.c - the host side of the witness: output to stdout, and the
 * HAL the included firmware sources name (never called by a kernel). */
#include <stdlib.h>
#include <unistd.h>
#include "witness.h"
#include "hal.h"

void w_write(const char *s, unsigned n)
{
    while (n) {
        ssize_t k = write(1, s, n);
        if (k <= 0)
            exit(2);
        s += k;
        n -= (unsigned)k;
    }
}

static void no_hw(void) { abort(); }
uint8_t hal_rd8(uint32_t a) { (void)a; no_hw(); return 0; }
uint16_t hal_rd16(uint32_t a) { (void)a; no_hw(); return 0; }
uint32_t hal_rd32(uint32_t a) { (void)a; no_hw(); return 0; }
void hal_wr8(uint32_t a, uint8_t v) { (void)a; (void)v; no_hw(); }
void hal_wr16(uint32_t a, uint16_t v) { (void)a; (void)v; no_hw(); }
void hal_wr32(uint32_t a, uint32_t v) { (void)a; (void)v; no_hw(); }
unsigned hal_irq_save(void) { no_hw(); return 0; }
void hal_irq_restore(unsigned prev) { (void)prev; no_hw(); }
void hal_irq_enable_all(void) { no_hw(); }

int w_main(void);
int main(void) { return w_main(); }
