/*
 * ext.c - the extensions' commands and their place after each tick
 * (ext.h, docs/extensions.md).
 */
#include "fw.h"
#include "hal.h"
#include "card.h"
#include "cmd.h"
#include "params.h"
#include "ext.h"

uint8_t ext_on;

void ext_reset(void)
{
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        ext_comp[n] = (ext_comp_t){0};
        ext_pc[n] = (ext_pc_t){0};
    }
    ext_on = 0;
}

void ext_axis_init(unsigned n)
{
    ext_comp_init(n);
    if (ext_pc[n].armed)
        ext_pc_locate(&ext_pc[n], (int64_t)pos_add(axes[n].meas, par_a[P_AO][n]));
}

/* After each tick, before the axes' supervision (card_supervise_tick), so
 * that it sees the corrected positions: the corrections first (a table's
 * source may be another axis), then the compares on the corrected
 * positions.  Each axis masked: a tick never sees half a correction. */
void ext_supervise_do(void)
{
    uint8_t on = ext_on;
    for (unsigned n = 0; n < MAC4_NAXES; n++)
        if (on & (1u << n)) {
            unsigned prev = hal_irq_save();
            ext_comp_apply(n);
            hal_irq_restore(prev);
        }
    for (unsigned n = 0; n < MAC4_NAXES; n++)
        if (on & (0x10u << n)) {
            unsigned prev = hal_irq_save();
            ext_pc_check(n);
            hal_irq_restore(prev);
        }
}

int ext_general(int ci, unsigned a, uint32_t p)
{
    switch (ci) {
    case CI_CDEF: return ext_comp_define(a);
    case CI_CENT: return ext_comp_entry(a, (int32_t)p);
    case CI_CPTR: return ext_comp_pointer(a, p);
    case CI_CON: return ext_comp_switch(a, p);
    case CI_PCON: return ext_pc_arm(a, p);
    default: return ERR_SYNTAX;
    }
}

uint32_t ext_read(unsigned ci, unsigned a)
{
    const ext_comp_t *t = &ext_comp[a];
    switch (ci) {
    case CI_RCEN: return (uint32_t)(int32_t)(t->ptr < t->n ? t->e[t->ptr + 1u] : 0);
    case CI_RCSM: return ext_comp_sum(a);
    case CI_RCC: return (uint32_t)t->cor;
    case CI_RPCC: return ext_pc[a].crossings;
    case CI_RPCI: return ext_pc[a].irqs;
    default: return 0;
    }
}
