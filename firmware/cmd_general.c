/*
 * cmd_general.c - the commands that change an axis (1.2 groups 1-3): the
 * general instructions (INIT, E, DEINIT, MR, C), the mode change that E
 * activates (its checks, 6.3.7; the plan and the start, motion.c) and the
 * system set-up (USR/USN, FLYON/FLYOFF, TURBO).  cmd_execute_other is the
 * dispatcher's (cmd.c) entry for every command but the reads.
 */
#include "fw.h"
#include "hal.h"
#include "card.h"
#include "axis.h"
#include "cmd.h"
#include "cmd_table.h"
#include "params.h"
#include "motion.h"
#include "measure.h"
#include "ext.h"
#include "card_variant.h"

/* ---- targets ------------------------------------------------------------ */
static int absolute_encoder(unsigned a)
{
    int32_t et = PAR(a, ET);
    return et == 2 || et == 4;
}

/* Is a target position reachable on this axis (6.3.3)?  Uses the system
 * parameters in force.  For E and for <ap>/<at> writes (cmd_param.c); here,
 * beside E's checks, the compiler knows which registers it uses (do_execute
 * saves fewer around it: 26 bytes less). */
int cmd_target_ok(unsigned a, int32_t t)
{
    int32_t sh = PAR(a, SH);
    if (sh == 1) {
        if (t < PAR(a, LN) || t > PAR(a, LP))
            return 0;
    } else if (t < 0 || t >= PAR(a, CR)) {
        return 0;
    }
    if (absolute_encoder(a) && axis_initialised(a)) {
        int64_t raw = (int64_t)t - PAR(a, AO);
        int32_t ec = PAR(a, EC);
        if (raw < 0 || (ec > 0 && raw >= ec))
            return 0;
    }
    return 1;
}

/* ---- mode changes (E) ---------------------------------------------------- */
static int mode_change_check(unsigned a, uint8_t target)
{
    uint8_t cur = axes[a].mode;
    if (target != M_DISABLE && !axis_initialised(a))
        return ERR_LOGICAL;                       /* operation starts after INIT (4) */
    if (axes[a].stop_then >= STOP_DISABLE && target != M_DISABLE && target != M_RESET)
        return ERR_LOGICAL;                       /* being stopped to disable it (4.8, 4.9) */
    switch (target) {
    case M_DISABLE:
    case M_RESET:
        return 0;
    case M_ENABLE:
        return (cur == M_DISABLE || cur == M_ENABLE || cur == M_BRAKE || cur == M_TEST) ? 0 : ERR_LOGICAL;
    case M_UE:
        return (cur == M_DISABLE || cur == M_TEST || cur == M_RESET) ? ERR_LOGICAL : 0;
    case M_BRAKE:
        return cur == M_DISABLE ? ERR_LOGICAL : 0;
    case M_TEST:
        return (cur == M_DISABLE || cur == M_ENABLE || cur == M_TEST) ? 0 : ERR_LOGICAL;
    default:
        break;
    }
    /* motion modes: only from enable or brake (6.3.7), or a new target on-fly */
    if (!(cur == M_ENABLE || cur == M_BRAKE || cur == target))
        return ERR_LOGICAL;
    switch (target) {
    case M_SEARCH_IDX_C:
    case M_SEARCH_IDX:
    case M_HOME:
        if (PAR(a, ET) != 1)
            return ERR_LOGICAL;                   /* index needs the incremental encoder at P2 */
        if (target == M_HOME && PAR(a, RS) == 0)
            return ERR_LOGICAL;                   /* reference switch declared OFF */
        break;
    case M_FIND_EDGE: {
        int32_t dl = PAR_W(a, DL);
        int32_t cfg = dl == 0 ? PAR(a, RS) : dl == 1 ? PAR(a, NS) : PAR(a, PS);
        if (cfg == 0)
            return ERR_LOGICAL;                   /* that switch is declared OFF */
        if (dl != 0 && PAR(a, SH) != 1)
            return ERR_LOGICAL;                   /* circular axes: reference switch only */
        break;
    }
    case M_POSITIONING:
        if (!cmd_target_ok(a, PAR_W(a, AP)))
            return ERR_LIMIT;
        break;
    case M_POS_TRACK:             /* the limits may have changed since WAT (INIT) */
        if (!cmd_target_ok(a, PAR(a, AT)))
            return ERR_LIMIT;
        break;
    default:
        break;
    }
    return 0;
}

static __attribute__((noinline)) int do_execute(unsigned a)
{
    uint8_t target = axes[a].next_mode;
    if (target == NO_MODE)
        target = axes[a].mode;
    else if (target == M_BRAKE && axes[a].mode == M_TEST)
        target = M_DISABLE;                       /* 3.5.1: test mode stops by disabling */
    /* the checks read the mode, the status and the parameters, which only
     * the main loop writes: unmasked */
    cmd_unmask();
    int r = mode_change_check(a, target);
    cmd_remask();
    if (r)
        return r;
    uint8_t mode = target == M_UE ? M_ENABLE : target;
    motion_plan_t plan;
    motion_plan_target(a, mode, &plan);           /* masked: a circular axis's from the tick's position */
    /* The activation, <mf> and the gains are read by the main loop only (the
     * tick reads no mode parameter but <da> in test mode, one word): they
     * run with interrupts enabled, between the checks and the commit, which
     * are masked. */
    int init = axis_initialised(a);
    cmd_unmask();
    params_activate(a, PK_MODE);
    if (init)
        axis_prepare_mode(a);                     /* the system parameters' part is INIT's */
    if (mode != M_DISABLE)
        motion_plan(a, &plan);
    cmd_remask();
    /* The one thing an interrupt does to an axis' state: a tick that failed
     * to measure it raised encoder_f and disabled it (6.3.8,
     * measure_encoder_error).  Met while unmasked, it counts as come first:
     * the error is not acknowledged (6.3.7), the axis stays disabled. */
    if (mode != M_DISABLE && (axes[a].ustat & US_ERRORS))
        return ERR_LOGICAL;
    if (!init)
        axis_prepare(a);
    axis_select_mode(&axes[a], NO_MODE);
    /* pos_end, jus_end and LED P are cleared only by the next E (5.6) */
    axes[a].ustat &= ~(UB(POS_END) | UB(JUS_END));
    axes[a].sstat &= ~SB(IN_POS);
    uint8_t from = axes[a].mode;
    if (mode == M_DISABLE || (mode == M_RESET && (from == M_DISABLE || from == M_TEST))) {
        axis_disable(a);                          /* (reset: nothing moves to stop) */
    } else {
        axis_set_mode(a, mode);
        motion_start(a, mode, from, &plan);
    }
    return 0;
}

/* ---- general instructions ---------------------------------------------- */
static int do_init(unsigned a)
{
    if (axes[a].mode != M_DISABLE)
        return ERR_LOGICAL;
    if (PAR_W(a, SH) == 1 && PAR_W(a, LP) <= PAR_W(a, LN))
        return ERR_LIMIT;                         /* 4.3.1.1: <lp> > <ln> */
    if (!et_ok(PAR_W(a, ET)))
        return ERR_LIMIT;
    if (PAR_W(a, ET) >= 3 && !measure_ea_ok((uint32_t)PAR_W(a, EA), PAR_W(a, EB)))
        return ERR_LIMIT;                         /* external encoder: no usable <ea> for this <eb> */
    /* INIT needs the axis disabled: the servo tick drives 0 V there and,
     * with its measurement of the axis held off until the supervision after
     * INIT (mk_tick), reads nothing INIT writes - so the bulk of INIT runs
     * with interrupts enabled (the other axes' ticks are not held off by
     * it).  The STP's tick works on a disabled axis' step output and step
     * count too (stp_t, which the measurement's set-up rewrites): that part
     * stays masked.  The parameters' activation only copies the axis'
     * written values, which no interrupt reads on a disabled axis but one at
     * a time in a single move (<irq6>, <irq5>): unmasked on every card. */
    if (!CARD_INIT_MASKED)
        axis_measure_off(&axes[a]);             /* the servo tick leaves the axis alone */
    cmd_unmask();
    params_activate(a, PK_SYS);
    params_activate(a, PK_MODE);
    if (!CARD_INIT_MASKED)
        axis_init_measurement(a);
    cmd_remask();
    if (CARD_INIT_MASKED)
        axis_init_measurement(a);
    axes[a].ustat |= UB(INIT);
    axis_select_mode(&axes[a], NO_MODE);
    return 0;
}

static int do_general(int ci, unsigned a, uint32_t p)
{
    switch (ci) {
    case CI_INIT:
        return do_init(a);
    case CI_E:
        return do_execute(a);
    case CI_DEINIT: {                             /* 4.9: stop, disable, deinitialise */
        axis_t *x = axis_at[a];                   /* the table, not a multiply by sizeof(axis_t) */
        if (axis_standstill(a) || x->mode == M_TEST) {
            axis_disable(a);
            x->ustat &= ~UB(INIT);
        } else {
            motion_emergency(a, STOP_DEINIT);
        }
        axis_select_mode(x, NO_MODE);
        return 0;
    }
    case CI_MR:
        if (!(hal_rd16(SYS_STATUS) & SYS_ST_J11))
            return ERR_LOGICAL;                   /* 2.1.3: MR works only with J11 in */
        cmd_mr = 1;
        for (unsigned n = 0; n < MAC4_NAXES; n++)
            axes[n].sstat &= ~SB(M_RDY);          /* no more commands until the reset */
        return 0;
    case CI_FLYON:
        axes[a].ustat |= UB(ON_FLY);
        return 0;
    case CI_FLYOFF:
        axes[a].ustat &= ~UB(ON_FLY);
        return 0;
    case CI_USR:
    case CI_USN:
        if (!system_change_allowed(a))
            return ERR_LOGICAL;
        if (ci == CI_USR)
            axes[a].ustat |= UB(REV_O);
        else
            axes[a].ustat &= ~UB(REV_O);
        return 0;
    case CI_TURBO:
        if (p > 1)
            return ERR_LIMIT;
        if (!axis_standstill(a))
            return ERR_LOGICAL;
        if (p)
            axes[a].sstat |= SB(TURBO);
        else
            axes[a].sstat &= ~SB(TURBO);
        return 0;
    case CI_WAP_R: {
        int64_t t = (int64_t)PAR_W(a, AP) + (int32_t)p;
        if (t < INT32_MIN || t > INT32_MAX)
            return ERR_LIMIT;
        return write_param(a, P_AP, (int32_t)t);
    }
    default:
        return ext_general(ci, a, p);             /* the extensions (ext.h), else 161 */
    }
}

/* Everything but the reads (cmd_execute's common case): C, and the commands
 * that need every error acknowledged first (6.3.7).  (Out of line, as it was
 * beside the dispatcher.) */
uint16_t cmd_execute_other(cmd_t c, unsigned a, uint32_t param)
{
    axis_t *x = axis_at[a];
    if (c.kind == CK_GEN && c.arg == CI_C) {
        x->ustat &= ~US_ERRORS;
        card_ostat &= ~(OB(AXIS_F) | OB(WATCH_F));
        if (!(hal_rd16(SYS_STATUS) & SYS_ST_STOP))
            card_ostat &= ~OB(H_STOP);
        return 0;
    }
    if ((x->ustat & US_ERRORS) || (card_ostat & (OB(AXIS_F) | OB(WATCH_F) | OB(H_STOP))))
        return ERR_LOGICAL;                       /* 6.3.7: error not acknowledged */
    if (c.kind == CK_MODE) {
        axis_select_mode(x, c.arg);
        return 0;
    }
    if (c.kind == CK_WPAR)
        return (uint16_t)write_param(a, c.arg, (int32_t)param);
    return (uint16_t)do_general(c.arg, a, param);
}
