/*
 * periph.c - the table of the card's devices, through which the scheduler
 * resets them, asks for their next event, runs their events and reads
 * their interrupt request lines, and the signals between them.  Each device
 * is a small model with the register interface of mac4_map.h and its timing
 * driven by the CPU cycle count, in a file of its own: sysctl.c (system
 * control, watchdog, /STOP), timer.c, uart.c, virq.c, axisboard.c (the axis
 * interface board, the plant wired behind it).  What a wire carries from
 * one device to another is a named signal (sim.h, SIG_*), wired in
 * periph_connect().
 */
#include "sim.h"
#include "periph.h"

/* ---- the devices ---------------------------------------------------------- */
/* The card's devices, in the order of their reset and of their events. */
static const device_t *const devices[] = {
    &sys_device, &tmr_device, &uart_device, &vme_device, &wdg_device, &estop_device, &axisboard_device,
};
#define NDEVICES (sizeof devices / sizeof devices[0])

/* ---- the signals between them ---------------------------------------------- */
void sig_connect(sim_t *s, int sig, sim_sig_hook_t hook)
{
    sim_sig_t *g = &s->sig[sig];
    if (g->n < SIM_SIG_HOOKS)
        g->hook[g->n++] = hook;
}

void sig_raise(sim_t *s, int sig, uint64_t value)
{
    const sim_sig_t *g = &s->sig[sig];
    for (unsigned i = 0; i < g->n; i++)
        g->hook[i](s, value);
}

void periph_connect(sim_t *s)
{
    static const char *const names[SIG_COUNT] = {"timer.expired", "axis.ssi_busy", "sys.stop"};
    for (int i = 0; i < SIG_COUNT; i++) {
        s->sig[i].name = names[i];
        s->sig[i].n = 0;
    }
    axisboard_connect(s);                       /* timer.expired -> the SSI receivers */
    timer_connect(s);                           /* axis.ssi_busy -> the timer's request */
    /* sys.stop -> the axis boards' /EN outputs: axisboard_connect() too */
}

/* ---- all devices ------------------------------------------------------------ */
void periph_reset(sim_t *s)
{
    for (unsigned i = 0; i < NDEVICES; i++)
        devices[i]->reset(s);
}

/* Every request line (the waveform shows them one by one, vcd.c). */
unsigned sim_irq_lines(sim_t *s)
{
    unsigned l = 0;
    for (unsigned i = 0; i < NDEVICES; i++)
        if (devices[i]->irq_lines)
            l |= devices[i]->irq_lines(s);
    return l;
}

int sim_irq_level(sim_t *s)
{
    unsigned l = sim_irq_lines(s);
    int lvl = 0;
    while (l >>= 1)
        lvl++;
    return lvl;                    /* the highest request */
}

int sim_irq_source(int level)
{
    switch (level) {
    case IRQ_LEVEL_ESTOP: return SRC_ESTOP;
    case IRQ_LEVEL_TIMER: return SRC_TIMER;
    case IRQ_LEVEL_AXIS: return SRC_AXIS;
    case IRQ_LEVEL_UART: return SRC_UART;
    }
    return SRC_OTHER;
}

cyc_t periph_next_event(sim_t *s)
{
    cyc_t t = CYC_NEVER;
    for (unsigned i = 0; i < NDEVICES; i++)
        if (devices[i]->next_event) {
            cyc_t e = devices[i]->next_event(s);
            if (e < t)
                t = e;
        }
    return t;
}

void periph_events(sim_t *s, cyc_t now)
{
    for (unsigned i = 0; i < NDEVICES; i++)
        if (devices[i]->events)
            devices[i]->events(s, now);
}
