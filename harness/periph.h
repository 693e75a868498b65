/* periph.h - the devices of the card (periph.c's table) and their register
 * interfaces. */
#ifndef PERIPH_H
#define PERIPH_H
#include "sim.h"

/* A device of the card (periph.c's table), as MAME's devices and simavr's
 * avr_io_t: its register windows (the bus table maps an address range to a
 * device and one of its windows: bus_map.h, generated from board/mac4.toml),
 * its reset, the cycle of its next event (NULL: none), its events up to
 * now and its interrupt request lines (bit L: a request at level L; NULL:
 * none).  Its state is its own type (sysctl.h, timer.h, ...), stored in
 * sim_t; what it tells another device goes through a named signal
 * (sim.h, SIG_*).  The memories are devices with a window and nothing else
 * (bus.c). */
typedef struct {
    uint32_t (*rd)(sim_t *s, uint32_t off, int size);            /* off from the window's base; size 1 or 2 */
    void (*wr)(sim_t *s, uint32_t off, uint32_t v, int size);
} dev_window_t;
#define DEV_WINDOWS 2

typedef struct device {
    const char *name;
    dev_window_t win[DEV_WINDOWS];
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
extern const device_t dpram_device, eprom_device, sram_device;   /* bus.c: the memories */
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
