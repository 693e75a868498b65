/*
 * vcd.h - waveforms of the card as a Value Change Dump (docs/debugging.md,
 * "Waveforms"): `vcd FILE [SIGNALS]`, `vcd off`.  Time 0 is the power-on
 * reset, `$timescale 100ps`: 625 units per 68000 cycle at 16 MHz.
 *
 * The models call the hooks below only while s->vcd is set; each only
 * looks (no model is synced, no event scheduled), so a run with a dump is
 * the run without one.
 */
#ifndef VCD_H
#define VCD_H
#include "sim.h"

struct vcd;

/* Start a dump of SIGNALS (comma-separated names of the header, a name
 * without its axis for all four, or "all"); NULL or "" = all.  0, or -1
 * with a message in err. */
int vcd_open(sim_t *s, const char *path, const char *signals, char *err, size_t errlen);
void vcd_close(sim_t *s);                 /* writes what is pending */
void vcd_list(FILE *f, int card);          /* the names of the signals */

/* hooks */
void vcd_sample(sim_t *s);                 /* sim_update_irq: registers and lines may have changed */
void vcd_handler(sim_t *s, cyc_t t);       /* irq_enter/irq_leave: the handler running from t */
/* plant.c: the mechanics of axis n moved linearly from (ta, xa) to (tb, xb)
 * (plant_axis_t x: motor revolutions, STP out of step: rotor steps) */
void vcd_piece(sim_t *s, int n, cyc_t ta, double xa, cyc_t tb, double xb);
/* plant.c: the step generator of axis n emitted c pulses after its clock
 * stood at nco_t0 with accumulator acc0 (the pulses' times follow) */
void vcd_pulses(sim_t *s, int n, cyc_t nco_t0, uint32_t acc0, uint64_t c);
/* plant.c: axis n is brought up to date until its t_sync */
void vcd_synced(sim_t *s, int n);

#endif
