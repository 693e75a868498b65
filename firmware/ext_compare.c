/*
 * ext_compare.c - position compare after the Turbo PMAC's position-compare
 * feature: an axis crossing a programmed position (once, or every <pcn>
 * counts from <pcp> up to <pce>) sets pc_hit and raises its own VMEbus
 * interrupt (<irq7>, as the vectors of 4.6).  Checked after each tick, in
 * the supervision, on the actual position in the frame of RCP: at most one
 * interrupt per axis per tick, however many points the axis crossed in it;
 * every crossing is counted (RPCC).  docs/extensions.md.
 */
/* The extensions run after every tick: their hot paths compiled for speed
 * (the rest of the firmware for size, Makefile OPT68). */
#pragma GCC optimize("O2")
#include "inline.h"
#include "fw.h"
#include "hal.h"
#include "card.h"
#include "params.h"
#include "ext.h"
#include "cmd_mask.h"

ext_pc_t ext_pc[MAC4_NAXES];

#define P_LOW INT64_MIN
#define P_HIGH INT64_MAX

void ext_pc_locate(ext_pc_t *c, int64_t p)
{
    if (p < c->p0) {
        c->idx = 0;
        c->lo = P_LOW;
        c->hi = c->p0;
        return;
    }
    uint32_t q = c->n ? (uint32_t)(p - c->p0) / (uint32_t)c->n : 0;   /* p - p0 < 2^32: positions are 32-bit */
    if (q + 1u >= (uint32_t)c->k) {
        c->idx = c->k;
        c->lo = c->last_pt;
        c->hi = P_HIGH;
        return;
    }
    c->idx = (int32_t)q + 1;
    c->lo = c->p0 + (int64_t)(q * (uint32_t)c->n);
    c->hi = c->lo + c->n;
}

/* One point up or down from where idx stands (the neighbouring range). */
FW_INLINE void step_up(ext_pc_t *c)
{
    c->idx++;
    c->lo = c->hi;
    c->hi = c->idx == c->k ? P_HIGH : c->hi + c->n;
}

FW_INLINE void step_down(ext_pc_t *c)
{
    c->idx--;
    c->hi = c->lo;
    c->lo = c->idx == 0 ? P_LOW : c->lo - c->n;
}

/* A few points per tick at speed (a small <pcn>) step without a division;
 * more, or a jump, is located afresh. */
#define PC_STEPS 8
uint32_t ext_pc_cross(ext_pc_t *c, int64_t p)
{
    int32_t was = c->idx;
    unsigned i = 0;
    while (p >= c->hi && i++ < PC_STEPS)
        step_up(c);
    while (p < c->lo && i++ < PC_STEPS)
        step_down(c);
    if (p >= c->hi || p < c->lo)
        ext_pc_locate(c, p);
    int32_t d = c->idx - was;
    return (uint32_t)(d < 0 ? -d : d);
}

FW_INLINE int64_t pc_pos(unsigned n)
{
    return (int64_t)pos_add(axis_at[n]->meas, par_a[P_AO][n]);
}

void ext_pc_check(unsigned n)
{
    ext_pc_t *c = &ext_pc[n];
    int64_t p = pc_pos(n);
    if (p >= c->lo && p < c->hi)
        return;                                   /* the common case: no point crossed */
    uint32_t k = ext_pc_cross(c, p);
    if (!k)
        return;
    c->crossings += k;
    axis_at[n]->ustat |= UB(PC_HIT);
    if (c->n == 0 && c->irq_done)
        return;                                   /* once: one interrupt */
    c->irq_done = 1;
    c->irqs++;
    vme_irq((uint8_t)PAR(n, IRQ7));
}

int ext_pc_arm(unsigned a, uint32_t on)
{
    ext_pc_t *c = &ext_pc[a];
    if (on > 1)
        return ERR_LIMIT;
    /* A command (masked by the command path): the budget and the window from
     * the parameters are main-loop state no interrupt reads, worked out with
     * interrupts enabled as cmd_mask.h's cmd_unmask() does; the commit, from
     * the position of the moment, masked again. */
    cmd_unmask();
    int fits = !on || c->armed || ext_fits(EXT_W_COMPARE);
    int64_t p0 = PAR(a, PCP), e = PAR(a, PCE), n = PAR(a, PCN);
    int32_t k = 1;
    if (n && e > p0)
        k = (int32_t)((uint32_t)(e - p0) / (uint32_t)n) + 1;
    int64_t last = p0 + (int64_t)((uint32_t)(k - 1) * (uint32_t)n);
    cmd_remask();
    axis_at[a]->ustat &= ~UB(PC_HIT);
    if (!on) {
        c->armed = 0;
        ext_on &= (uint16_t)~(0x10u << a);
        return 0;
    }
    if (!fits)
        return ERR_LOGICAL;                       /* beyond the extensions' budget (ext.h) */
    c->p0 = p0;
    c->n = n;
    c->k = k;
    c->last_pt = last;
    c->crossings = c->irqs = 0;
    c->irq_done = 0;
    ext_pc_locate(c, pc_pos(a));                  /* where the axis is now: no crossing yet */
    c->armed = 1;
    ext_on |= (uint16_t)(0x10u << a);
    return 0;
}
