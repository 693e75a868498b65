/*
 * hal.h - the only way the firmware touches the card.
 *
 * Addresses come from mac4_map.h.  On the 68000 (HAL_TARGET) the accessors
 * are volatile loads and stores; on the host (HAL_NATIVE) they call the
 * emulator's bus, so the same peripheral models serve both builds.
 * Word and long accesses must be at even addresses (68000 rule).
 */
#ifndef HAL_H
#define HAL_H

#include <stdint.h>
#include "mac4_map.h"

#if defined(HAL_TARGET)
#include "target/hal_target.h"
#elif defined(HAL_NATIVE)
#include "native/hal_native.h"
#else
#error "define HAL_TARGET or HAL_NATIVE"
#endif

/* Interrupt masking: hal_irq_save() masks levels 1-6 (level 7, the
 * emergency stop, cannot be masked on a 68000) and returns the previous
 * mask for hal_irq_restore().  Inline on the target: they guard short
 * critical sections in the tick's neighbourhood. */
#if !defined(HAL_TARGET)
#define HAL_ISR                 /* the emulator calls the handlers as functions */
unsigned hal_irq_save(void);
void hal_irq_restore(unsigned prev);
void hal_irq_enable_all(void);
#endif

/* Put the live vector table in place (target); nothing to do natively. */
int hal_copy_vectors(void);

/* Stop the card for good after a fatal boot error or fault: the target
 * spins retriggering the watchdog so the error display stays; the native
 * build returns control to the emulator. */
void hal_stop(void) __attribute__((noreturn));
/* The same without retriggering the watchdog: it resets the card when
 * jumper J11 is in (2.1.3); with J11 out the card stays stopped. */
void hal_stop_no_kick(void) __attribute__((noreturn));

#endif
