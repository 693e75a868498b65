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

uint16_t ext_on;

void ext_reset(void)
{
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        ext_comp[n] = (ext_comp_t){0};
        ext_pc[n] = (ext_pc_t){0};
    }
    for (unsigned k = 0; k < EXT_FB_N; k++)
        ext_fb[k] = (ext_fb_t){0};
    ext_fb_sel = 0;
    ext_on = 0;
}

void ext_axis_init(unsigned n)
{
    ext_comp_init(n);
    if (ext_pc[n].armed)
        ext_pc_locate(&ext_pc[n], (int64_t)pos_add(axes[n].meas, par_a[P_AO][n]));
}

/* After each tick, before the axes' supervision (card_supervise_tick), so
 * that it sees the corrected positions: the conversion table, then each
 * axis' correction (a table's source may be another axis: each reads the
 * others' own measurements, without their corrections), then the compares
 * on the corrected positions.  Masked in parts: a tick never sees half a
 * correction, and the table reads one tick's measurements. */
void ext_supervise_do(void)
{
    uint16_t on = ext_on;
    if (on & EXT_FB_ON) {
        unsigned prev = hal_irq_save();
        for (unsigned k = 0; k < EXT_FB_N; k++)
            if (ext_fb[k].setup)
                ext_fb_step(&ext_fb[k]);
        hal_irq_restore(prev);
    }
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        ext_comp_t *t = &ext_comp[n];
        int32_t fbe = (on & EXT_FB_ON) ? par_a[P_FBE][n] : 0;
        if (!(on & (1u << n)) && !fbe && !t->cin && !t->rel)
            continue;
        unsigned prev = hal_irq_save();
        if (on & (1u << n))
            ext_comp_apply(n);
        ext_axis_correct(n, fbe ? ext_fb[fbe - 1].result : 0, fbe != 0);
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
    ext_fb_t *e = &ext_fb[ext_fb_sel];
    switch (ci) {
    case CI_CDEF: return ext_comp_define(a);
    case CI_CENT: return ext_comp_entry(a, (int32_t)p);
    case CI_CPTR: return ext_comp_pointer(a, p);
    case CI_CON: return ext_comp_switch(a, p);
    case CI_PCON: return ext_pc_arm(a, p);
    case CI_FBX:
        if (p >= EXT_FB_N)
            return ERR_LIMIT;
        ext_fb_sel = (uint8_t)p;
        return 0;
    case CI_FBS: return ext_fb_setup(ext_fb_sel, p);
    case CI_FBW1:
    case CI_FBW2:
        if (e->setup)
            return ERR_LOGICAL;                   /* FBS 0 first: the words are checked at FBS */
        if (ci == CI_FBW1)
            e->w1 = p;
        else
            e->w2 = p;
        return 0;
    default: return ERR_SYNTAX;
    }
}

uint32_t ext_read(unsigned ci, unsigned a)
{
    const ext_comp_t *t = &ext_comp[a];
    const ext_fb_t *e = &ext_fb[ext_fb_sel];
    switch (ci) {
    case CI_RCEN: return (uint32_t)(int32_t)(t->ptr < t->n ? t->e[t->ptr + 1u] : 0);
    case CI_RCSM: return ext_comp_sum(a);
    case CI_RCC: return (uint32_t)t->cor;
    case CI_RPCC: return ext_pc[a].crossings;
    case CI_RPCI: return ext_pc[a].irqs;
    case CI_RFBS: return e->setup;
    case CI_RFW1: return e->w1;
    case CI_RFW2: return e->w2;
    case CI_RFBR: return (uint32_t)e->result;
    default: return 0;
    }
}
