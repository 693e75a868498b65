/* Host build: every access goes to the emulator's bus (harness/bus.c);
 * implemented by the harness, harness/hal_native.c. */
#ifndef HAL_NATIVE_H
#define HAL_NATIVE_H
#include <stdint.h>

uint8_t hal_rd8(uint32_t a);
uint16_t hal_rd16(uint32_t a);
uint32_t hal_rd32(uint32_t a);
void hal_wr8(uint32_t a, uint8_t v);
void hal_wr16(uint32_t a, uint16_t v);
void hal_wr32(uint32_t a, uint32_t v);

/* No vector table: the emulator calls fw_isr_tick, which chooses the tick's
 * body itself (tick_servo.c). */
#define HAL_VECTORED 0
static inline void hal_set_tick_vector(unsigned general) { (void)general; }

#endif
