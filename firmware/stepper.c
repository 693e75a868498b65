/*
 * stepper.c - the MAC4-STP (docs/stepper.md): the axis - measurement,
 * motion (positioning, BOOST), status.  The step rate, the creep phase
 * and the output: stp_rate.c; the profile arithmetic: stp_profile.c.
 *
 * Open loop: the profile generator (motion.c, one SP of 32 ms ahead) gives
 * a position per tick; each 8 ms tick the step generator gets the rate that
 * emits exactly that tick's distance (400 generator clocks per tick, the
 * remainder carried), so the steps follow the profile's velocity.  The
 * profile obeys the start/stop frequency (5.14): from stand-still it jumps
 * to <ssf>, and it stops from at most <ssf>.  Positioning ends in the creep
 * phase (5.6, diagram 5.2): <stc> steps at <lv>, programmed into the pulse
 * down-counter AX_PULSES with the exact number of steps still missing and
 * counted by the step-pulse interrupt, so the axis stops on the target step.
 * BOOST (4.1.4) is raised <bt> ms before the first step of every move and
 * dropped at stand-still.
 *
 * Position units are steps.  The position counter counts either the
 * generated steps (<et> 0, solder bridge BR closed) or an encoder's
 * increments (BR open, or an external encoder), which ms/(4 es) converts
 * to steps (4.4.2.3).  The STP's image alone links it (Makefile, FW_STP).
 */
#include "inline.h"
#include "fw.h"
#include "hal.h"
#include "mul16.h"
#include "stepper.h"
#include "stp_profile.h"
#include "card.h"
#include "params.h"
#include "motion.h"
#include "measure.h"
#include "stp_card.h"

stp_t stp_ax[MAC4_NAXES];
uint8_t stp_conv;           /* bit n: axis n's counter counts increments */

/* ---- measurement ---------------------------------------------------------- */
void stp_init(unsigned n)
{
    axis_t *x = axis_at[n];
    stp_t *s = &stp_ax[n];
    int32_t et = PAR(n, ET);
    int exact;
    int8_t dir = s->dir;
    *s = (stp_t){0};
    s->dir = dir;
    s->clocks = STP_TICK_CLOCKS;
    s->lim = (uint32_t)STP_TICK_CLOCKS << 16;
    s->obits = stp_dir_bit(x, dir);
    if (et == 0) {                               /* the step counter (4.4.1.1) */
        stp_conv = (uint8_t)(stp_conv & ~(1u << n));
        s->ratio = 0x10000u;
    } else {                                     /* increments: ms / (4 es) (4.4.2.3) */
        stp_conv = (uint8_t)(stp_conv | (1u << n));
        s->ratio = stp_ratio_q16((uint32_t)PAR(n, MS), (uint32_t)PAR(n, ES), &exact);
        /* one increment is ratio steps: the tolerance of RFE and <tr> (4.8.1, 5.6) */
        s->tol = (int32_t)((s->ratio >> 16) + ((s->ratio & 0xFFFFu) != 0));
        s->inc = x->meas;                        /* 0, or the absolute encoder's value */
        s->conv = stp_scale_call(s->inc, s->ratio);
        measure_meas_set(x, s->conv);
    }
    /* BR (2.4.2): closed to count the steps (<et> 0), open for the encoder (<et> 1) */
    if (et <= 1) {
        int br = (hal_rd16(AX_REG(n, AX_IN)) & AX_IN_BR_STEPS) != 0;
        if (br != (et == 0))
            axis_error(n, UB(ENCODER_F) | UB(LOGO_F), ERR_LOGICAL);
    }
}

int32_t stp_counts(unsigned n) { return stp_counts_at(&axes[n], &stp_ax[n], n); }

int32_t stp_tol(unsigned n) { return stp_ax[n].tol; }

/* ---- motion (motion.c, main loop) ----------------------------------------- */
void stp_motion_plan(unsigned n, int64_t ssf, stp_plan_t *pl)
{
    /* TURBO and USR change only at stand-still, before the next E */
    pl->turbo = (axis_at[n]->sstat & SB(TURBO)) ? AX_CTRL_TURBO : 0;
    pl->ssf = (int32_t)stp_ssf_grid(ssf, pl->turbo != 0);   /* at most 0x7FFFFFFF */
    uint16_t lv = (uint16_t)(stp_rate_hz((uint32_t)PAR(n, LV)) >> PAR(n, SF));
    pl->lv_rate = lv ? lv : 1u;
}

void stp_motion_start(unsigned n, uint8_t mode, const stp_plan_t *pl)
{
    axis_t *x = axis_at[n];
    stp_t *s = &stp_ax[n];
    if (s->creep != CREEP_IDLE)
        stp_creep_abort(n);
    uint16_t turbo = pl->turbo;
    s->clocks = turbo ? STP_TICK_CLOCKS_TURBO : STP_TICK_CLOCKS;
    s->lim = (uint32_t)s->clocks << 16;
    s->obits = (uint16_t)((s->obits & AX_CTRL_BOOST) | turbo | stp_dir_bit(x, s->dir));
    s->ssf = pl->ssf;
    s->lv_rate = pl->lv_rate;
    if (mode == M_POSITIONING) {
        /* the ramps end <stc> steps before the target, on the near side */
        int64_t rem = x->target - x->prof.pos, stc = (int64_t)PAR(n, STC) << 16;
        if (rem > stc)
            s->creep_from = x->target - stc;
        else if (rem < -stc)
            s->creep_from = x->target + stc;
        else
            s->creep_from = x->prof.pos;
    }
}

int stp_positioning(unsigned n, int64_t vmax, int64_t acc, int64_t dec, int64_t ssf)
{
    axis_t *x = axis_at[n];
    stp_t *s = &stp_ax[n];
    PIN_PTR(x);
    PIN_PTR(s);
    prof_t *p = &x->prof;
    switch (x->phase) {
    case 0: {                                    /* the ramps, to creep_from */
        uint32_t r;
        int neg;
        int32_t a[5];
        if (stp_args32(p, s->creep_from, vmax, acc, dec, ssf, &r, &neg, a)) {
            if (r != 0 || a[0] > a[4] || a[0] < -a[4]) {
                stp_position32(p, r, neg, a[0], a[1], a[2], a[3], a[4]);
                return 0;
            }
        } else if (p->pos != s->creep_from || mag64(p->vel) > ssf) {
            stp_position(p, s->creep_from, vmax, acc, dec, ssf);
            return 0;
        }
        axis_phase_set(x, 1);                    /* landed, from at most <ssf> */
    }
        /* fall through */
    case 1:                                      /* the creep: <stc> steps at <lv> */
        s->creep = CREEP_REQ;
        p->pos = x->target;
        p->vel = 0;
        axis_phase_set(x, 2);
        return 0;
    default:                                     /* until the last pulse is out */
        if (s->creep != CREEP_DONE)
            return 0;
        s->creep = CREEP_IDLE;
        return 1;
    }
}

/* Once per SP for every axis: the system status bits (7.1.2,
 * docs/interpretations.md). */
FW_INLINE void status_of(axis_t *x, const stp_t *s)
{
    uint32_t ss = x->sstat & ~(SB(DR_DISABLE) | SB(SERVO_ON) | SB(BOOST) | SB(BOOST_EN) | SB(IRQ_LINE) |
                               SB(LED_FAULT) | SB(PHASE5) | SB(BOOST_LOCK));
    if (s->dir < 0)
        ss |= SB(DR_DISABLE);                    /* "direction": motion in negative direction */
    if (x->mode != M_DISABLE && x->mode != M_TEST)
        ss |= SB(SERVO_ON);                      /* profile and step output in charge */
    if (s->boost)
        ss |= SB(BOOST);                         /* the BOOST output */
    if (s->boost_en)
        ss |= SB(BOOST_EN);                      /* BOOST on for <bt>: the move may go */
    else if (s->boost)
        ss |= SB(BOOST_LOCK);                    /* a move waits for the BOOST lead time */
    if (x->ctrl & AX_CTRL_PULSE_IE)
        ss |= SB(IRQ_LINE);                      /* creep pulses counted by interrupt */
    if (s->creep == CREEP_RUN) {
        ss |= SB(PHASE5);                        /* the creep phase */
        /* ... to its end: the last pulse's interrupt has already cleared
         * PULSE_IE when it comes between a tick and this (the next tick ends
         * the creep) */
        if (s->hw_done && s->creep_irq)
            ss |= SB(IRQ_LINE);
    }
    if (x->ustat & US_ERRORS)
        ss |= SB(LED_FAULT);                     /* LED F */
    x->sstat = ss;
}

void stp_status(unsigned n)
{
    axis_t *x = axis_at[n];
    const stp_t *s = &stp_ax[n];
    PIN_PTR(x);
    PIN_PTR(s);
    status_of(x, s);
}

/* stp_profile_end() but for a move under way (below). */
static __attribute__((noinline)) void profile_end(axis_t *x, stp_t *s, unsigned n, int64_t before, int64_t before_vel)
{
    prof_t *p = &x->prof;
    int wants = s->creep != CREEP_IDLE || p->pos != before;
    if (wants && !s->active) {
        if (!s->boost) {                         /* BOOST on, <bt> before the first step */
            s->boost = 1;
            s->obits |= AX_CTRL_BOOST;
            s->boost_tick = card_ticks;          /* the next tick puts it out */
        }
        /* this segment starts at the next SP boundary, tick `start` */
        uint32_t start = (card_ticks + (PROFILE_DIVIDER - 1u)) & ~(PROFILE_DIVIDER - 1u);
        if (((start - s->boost_tick) << 3) >= (uint32_t)PAR(n, BT)) {
            s->active = 1;
            s->boost_en = 1;
        } else {                                 /* not yet: stand still this SP */
            p->pos = before;
            p->vel = 0;
            if (s->creep == CREEP_REQ) {
                s->creep = CREEP_IDLE;
                axis_phase_set(x, 1);
            }
        }
    } else if (!wants && s->boost && p->vel == 0 && before_vel == 0) {
        s->active = s->boost = s->boost_en = 0;  /* stand-still: BOOST off */
        s->obits &= (uint16_t)~AX_CTRL_BOOST;
    }
    status_of(x, s);
}

void stp_profile_end(unsigned n, int64_t before, int64_t before_vel)
{
    axis_t *x = axis_at[n];
    stp_t *s = &stp_ax[n];
    PIN_PTR(x);
    PIN_PTR(s);
    /* a move under way that goes on: BOOST stays as it is */
    if (s->active && (s->creep != CREEP_IDLE || x->prof.pos != before))
        status_of(x, s);
    else
        profile_end(x, s, n, before, before_vel);
}
