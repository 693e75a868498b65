/* 68000 register access: plain volatile word/long/byte moves. */
#ifndef HAL_TARGET_H
#define HAL_TARGET_H
#include <stdint.h>

/* An interrupt handler the vector enters directly (vectors.S): it saves
 * the registers it uses and returns with RTE, where an entry stub would
 * save four and call it (docs/performance.md: the level-5 pulse and level-4
 * UART handlers, which the UART's deadline counts a dozen times). */
#define HAL_ISR __attribute__((interrupt_handler))

static inline uint8_t hal_rd8(uint32_t a) { return *(volatile uint8_t *)a; }
static inline uint16_t hal_rd16(uint32_t a) { return *(volatile uint16_t *)a; }
static inline uint32_t hal_rd32(uint32_t a) { return *(volatile uint32_t *)a; }
static inline void hal_wr8(uint32_t a, uint8_t v) { *(volatile uint8_t *)a = v; }
static inline void hal_wr16(uint32_t a, uint16_t v) { *(volatile uint16_t *)a = v; }
static inline void hal_wr32(uint32_t a, uint32_t v) { *(volatile uint32_t *)a = v; }

/* The live vector table is the DPRAM's (hal_copy_vectors): the timer's
 * vector can be pointed at the other tick body of vectors.S's
 * _tick_vectors (0: fw_isr_tick, 1: fw_isr_tick_general; servo_card.h
 * tick_select). */
#define HAL_VECTORED 1
extern const uint32_t _tick_vectors[2];
static inline void hal_set_tick_vector(unsigned general)
{
    uint32_t a = DPRAM_VECTORS + 4u * (24u + IRQ_LEVEL_TIMER);
    __asm__("" : "+a"(a));      /* an address below 4 KiB: GCC would call it a null-pointer access */
    hal_wr32(a, _tick_vectors[general]);
}

static inline unsigned hal_irq_save(void)
{
    uint16_t sr;
    __asm__ volatile("move.w %%sr, %0\n\tori.w #0x0700, %%sr" : "=d"(sr) : : "memory", "cc");
    return sr;
}

static inline void hal_irq_restore(unsigned prev)
{
    uint16_t sr = (uint16_t)prev;
    __asm__ volatile("move.w %0, %%sr" : : "d"(sr) : "memory", "cc");
}

static inline void hal_irq_enable_all(void)
{
    __asm__ volatile("andi.w #0xF8FF, %%sr" : : : "memory", "cc");
}

#endif
