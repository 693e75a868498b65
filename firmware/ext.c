/*
 * ext.c - the extensions' commands and their place after each tick
 * (ext.h, docs/extensions.md).
 */
/* The extensions run after every tick: their hot paths compiled for speed
 * (the rest of the firmware for size, Makefile OPT68). */
#pragma GCC optimize("O2")
#include "fw.h"
#include "hal.h"
#include "card.h"
#include "cmd.h"
#include "params.h"
#include "ext.h"
#include "cmd_mask.h"
#include "queue.h"
#include "serial.h"

uint16_t ext_on;
static uint8_t ext_again;   /* a tick came before the round of slices ended */

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
    ext_due = 0;
    ext_again = 0;
    ext_late = 0;
}

void ext_axis_init(unsigned n)
{
    ext_comp_init(n);
    if (ext_pc[n].armed)
        ext_pc_locate(&ext_pc[n], (int64_t)pos_add(axes[n].meas, par_a[P_AO][n]));
}

/* The work after each tick comes in slices, one per main-loop pass
 * (fw_main_step), so that a command waits for one slice at most, not for
 * all of them: the conversion table in two halves, then each axis'
 * correction and compare.  Each slice masked: a tick never sees half of
 * it.  The supervision of a tick starts them (ext_supervise); a round not
 * done when the next tick is supervised ends first and the next follows
 * at once, one tick late, counted in ext_late (REXL: the extensions
 * switched on take more than the main loop has, which the budget, ext.h,
 * keeps from happening). */
volatile uint8_t ext_due;
uint16_t ext_late;

/* A round's slices: the conversion table's two only while an entry is on
 * (EXT_FB_ON), the four axes' always. */
FW_INLINE uint8_t round_slices(void)
{
    return (ext_on & EXT_FB_ON) ? EXT_SLICES : EXT_SLICES - 2u;
}

void ext_supervise_do(void)
{
    if (ext_due) {
        ext_late++;
        ext_again = 1;                            /* the round ends first, then the next one */
    } else {
        ext_due = round_slices();
    }
}

void ext_slice(void)
{
    unsigned prev = hal_irq_save();
    unsigned k = EXT_SLICES - ext_due;
    ext_due--;
    if (!ext_due && ext_again) {
        ext_again = 0;
        ext_due = round_slices();
    }
    uint16_t on = ext_on;
    if (k < 2) {                                  /* the conversion table, entries in order */
        if (on & EXT_FB_ON)
            for (unsigned i = k * (EXT_FB_N / 2); i < (k + 1) * (EXT_FB_N / 2); i++)
                if (ext_fb[i].setup)
                    ext_fb_step(&ext_fb[i]);
    } else {
        unsigned n = k - 2;
        ext_comp_t *t = ext_comp_at[n];
        int32_t fbe = (on & EXT_FB_ON) ? par_a[P_FBE][n] : 0;
        if ((on & (1u << n)) || fbe || t->cin || t->rel) {
            if (on & (1u << n))
                ext_comp_apply(n);
            ext_axis_correct(n, fbe ? ext_fb[fbe - 1].result : 0, fbe != 0);
        }
        if (on & (0x10u << n))
            ext_pc_check(n);
    }
    hal_irq_restore(prev);
}

/* Slices one after the other while no command waits at either interface:
 * a command waits for one slice at most. */
static inline int command_waiting(void)
{
    return serial_pending() || hal_rd32(DP_CMD_QUEUE + QH_FRONT) != hal_rd32(DP_CMD_QUEUE + QH_REAR);
}

void ext_work_do(void)
{
    do
        ext_slice();
    while (ext_due && !command_waiting());
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
    case CI_FBS: {
        /* the conversion table and its bit of ext_on are the main loop's
         * (ext_slice): set up with interrupts enabled, as RCSM below */
        cmd_unmask();
        int r = ext_fb_setup(ext_fb_sel, p);
        cmd_remask();
        return r;
    }
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
    case CI_RCSM: {
        /* Read in a command, masked (cmd.c): a CRC over up to 256 entries,
         * byte by byte, is some 62 000 cycles, more than a servo period; the
         * table is the main loop's and no interrupt reads it, so it is
         * summed with interrupts enabled, as cmd_mask.h's cmd_unmask()
         * lets a command's part the tick does not read run. */
        cmd_unmask();
        uint32_t v = ext_comp_sum(a);
        cmd_remask();
        return v;
    }
    case CI_RCC: return (uint32_t)t->cor;
    case CI_RPCC: return ext_pc[a].crossings;
    case CI_RPCI: return ext_pc[a].irqs;
    case CI_RFBS: return e->setup;
    case CI_RFW1: return e->w1;
    case CI_RFW2: return e->w2;
    case CI_RFBR: return (uint32_t)e->result;
    case CI_REXL: return ext_late;
    case CI_REXB: return (uint32_t)EXT_BUDGET << 16 | ext_load();
    default: return 0;
    }
}
