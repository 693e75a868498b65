/*
 * hal_native.c - hal.h for the host build: every register and DPRAM access
 * goes to the emulator's bus and peripheral models (harness/bus.c), the same
 * ones the 68000 image sees.  Harness code: it is linked into the native
 * firmware object (Makefile NATIVE_RULES, its static data reset with the
 * firmware's), and implements what hal/native/hal_native.h declares.
 */
#include <setjmp.h>
#include <stdlib.h>
#include "hal.h"
#include "sim.h"

jmp_buf *hal_native_stop_jmp;   /* set by the harness around firmware calls */
static unsigned irq_mask = 7;   /* like the 68000 after reset: all masked */

uint8_t hal_rd8(uint32_t a) { return (uint8_t)bus_read(g_sim, a, 1); }
uint16_t hal_rd16(uint32_t a) { return (uint16_t)bus_read(g_sim, a, 2); }
uint32_t hal_rd32(uint32_t a) { return bus_read(g_sim, a, 4); }
void hal_wr8(uint32_t a, uint8_t v) { bus_write(g_sim, a, v, 1); }
void hal_wr16(uint32_t a, uint16_t v) { bus_write(g_sim, a, v, 2); }
void hal_wr32(uint32_t a, uint32_t v) { bus_write(g_sim, a, v, 4); }

unsigned hal_irq_save(void)
{
    unsigned prev = irq_mask;
    irq_mask = 7;
    return prev;
}
void hal_irq_restore(unsigned prev) { irq_mask = prev; }
void hal_irq_enable_all(void) { irq_mask = 0; }
unsigned hal_native_irq_mask(void) { return irq_mask; }
int hal_copy_vectors(void) { return 0; }

void hal_stop(void)
{
    if (hal_native_stop_jmp)
        longjmp(*hal_native_stop_jmp, 1);
    abort();
}

/* The native build takes no exceptions, so no fault reaches this. */
void hal_stop_no_kick(void) { hal_stop(); }
