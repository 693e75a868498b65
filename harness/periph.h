/* periph.h - the devices of the card (periph.c's table) and their register
 * interfaces. */
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

/* A device of the card (periph.c's table): its reset, the cycle of its next
 * event (NULL: none), its events up to now, its interrupt request lines
 * (bit L: a request at level L; NULL: none).  Its registers are its rows
 * of the bus table (bus_map.h, generated from board/mac4.toml). */
typedef struct {
    const char *name;
    void (*reset)(sim_t *s);
    cyc_t (*next_event)(sim_t *s);
    void (*events)(sim_t *s, cyc_t now);
    unsigned (*irq_lines)(sim_t *s);
} device_t;

/* the devices, each in a file of its own */
extern const device_t sys_device, wdg_device, estop_device;   /* sysctl.c */
extern const device_t tmr_device;                              /* timer.c */
extern const device_t uart_device;                             /* uart.c */
extern const device_t vme_device;                              /* virq.c */
void timer_connect(sim_t *s);              /* its end of the SSI receivers' busy line */

/* axisboard.c */
extern const device_t axisboard_device;
void axisboard_connect(sim_t *s);          /* its end of the timer's expiry line */
/* The six LEDs of an axis on the front panel (2.5.3), lit: D, P, F from the
 * LED register, LP, LN, REF from the input levels (at 0 V: AX_IN bit set). */
#define AXIS_NLEDS 6
typedef struct {
    const char *name;
    uint16_t reg, in;              /* SYS_LED_* bit of the axis, or AX_IN_* bit */
} axis_led_t;
extern const axis_led_t axis_leds[AXIS_NLEDS];
unsigned axisboard_leds(sim_t *s, int n);   /* bit i: axis_leds[i] lit */

void estop_set(sim_t *s, int active);
int estop_irq_pending(sim_t *s);
void estop_irq_ack(sim_t *s);

#endif
