/* periph.h - register interfaces of the peripheral models (periph.c). */
#ifndef PERIPH_H
#define PERIPH_H
#include "sim.h"

uint32_t sys_rd(sim_t *s, uint32_t off, int size);
void sys_wr(sim_t *s, uint32_t off, uint32_t v, int size);
uint32_t tmr_rd(sim_t *s, uint32_t off, int size);
void tmr_wr(sim_t *s, uint32_t off, uint32_t v, int size);
uint32_t uart_rd(sim_t *s, uint32_t off, int size);
void uart_wr(sim_t *s, uint32_t off, uint32_t v, int size);
uint32_t virq_rd(sim_t *s, uint32_t off, int size);
void virq_wr(sim_t *s, uint32_t off, uint32_t v, int size);
uint32_t vme_win_rd(sim_t *s, uint32_t off, int size);
void vme_win_wr(sim_t *s, uint32_t off, uint32_t v, int size);
uint32_t wdg_rd(sim_t *s, uint32_t off, int size);
void wdg_wr(sim_t *s, uint32_t off, uint32_t v, int size);
uint32_t axis_rd(sim_t *s, uint32_t off, int size);
void axis_wr(sim_t *s, uint32_t off, uint32_t v, int size);
uint32_t axis_irq_rd(sim_t *s, uint32_t off, int size);
void axis_irq_wr(sim_t *s, uint32_t off, uint32_t v, int size);

/* axisboard.c */
/* The six LEDs of an axis on the front panel (2.5.3), lit: D, P, F from the
 * LED register, LP, LN, REF from the input levels (at 0 V: AX_IN bit set). */
#define AXIS_NLEDS 6
typedef struct {
    const char *name;
    uint16_t reg, in;              /* SYS_LED_* bit of the axis, or AX_IN_* bit */
} axis_led_t;
extern const axis_led_t axis_leds[AXIS_NLEDS];
unsigned axisboard_leds(sim_t *s, int n);   /* bit i: axis_leds[i] lit */
void axisboard_reset(sim_t *s);
cyc_t axisboard_next_event(sim_t *s);
void axisboard_events(sim_t *s, cyc_t now);

void estop_set(sim_t *s, int active);
int estop_irq_pending(sim_t *s);
void estop_irq_ack(sim_t *s);

#endif
