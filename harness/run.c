/*
 * run.c - the scheduler: the CPU runs in slices that end at the next
 * peripheral event, so interrupts are raised at the cycle they occur.
 */
#include "cpu.h"
#include "periph.h"
#include "vcd.h"

static const cpu_t *cpu;
int sim_halted;
char sim_halt_why[200];

#define HOST_POLL_CYC US_TO_CYC(500)   /* the VME host looks at the queue every 0.5 ms */

void sim_attach_cpu(sim_t *s, const cpu_t *c)
{
    cpu = c;
    sim_reset(s, NULL);
}

void sim_update_irq(sim_t *s)
{
    if (cpu)
        cpu->set_irq(sim_irq_level(s));
    if (s->vcd)                   /* after every I/O access and at every slice */
        vcd_sample(s);
}

void sim_reset(sim_t *s, const char *why)
{
    if (why)
        sim_printf(s, "reset %s\n", why);
    s->in_reset_by_wdg = why && why[0] == 'w';
    s->resets++;
    s->nactive = 0;
    periph_reset(s);
    sim_halted = 0;
    cpu->reset(s);
    sim_update_irq(s);
}

void sim_run(sim_t *s, cyc_t cycles)
{
    cyc_t end = s->slice_base + cycles;
    while (s->slice_base < end) {
        cyc_t now = s->slice_base;
        periph_events(s, now);
        if (s->wdg.reset_pending) {
            sim_reset(s, "watchdog");
            continue;
        }
        int polled = 0;
        if (s->host_reads && now >= s->host_next_poll) {
            host_poll_responses(s);
            s->host_next_poll = now + HOST_POLL_CYC;
            polled = 1;
        }
        if (s->on_slice)              /* measurement (perf.c) */
            s->on_slice(s, now, polled);
        sim_update_irq(s);
        cyc_t next = periph_next_event(s);
        if (s->host_reads && s->host_next_poll < next)
            next = s->host_next_poll;
        if (next > end)
            next = end;
        if (next <= now)
            next = now + 1;
        if (sim_halted) {            /* a halted 68000 does nothing until reset */
            s->slice_base = next;
            continue;
        }
        cyc_t ran = cpu->execute(s, next - now);
        s->slice_base = now + (ran ? ran : 1);
        if (cpu->halted()) {      /* reported once: nothing runs until a reset */
            sim_halted = 1;
            sim_fault(s, "CPU halted (double bus fault)%s; %s", sim_halt_why,
                      s->wdg.j11 ? "the watchdog resets the card 100 ms after its last kick"
                                 : "J11 out: halted until a reset");
            sim_halt_why[0] = 0;
        }
    }
    periph_events(s, s->slice_base);
    if (s->host_reads)
        host_poll_responses(s);
}
