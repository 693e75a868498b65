/*
 * ref_stp.c - the MAC4-STP tick's floor routines against the firmware's C
 * (floorrun.c, bench/floor/README.md).  The tick is the firmware's own:
 * tick_stp.c (fw_isr_tick, stp_take_segment, the axis body and its
 * instantiations per path), tick.h, stepper.h's rate stage, stp_rate.c's
 * creep phase, stp_meas.c's measurement, stepper.c, axis.c's state changes
 * of an encoder error and motion.c's motion_hold, compiled for the host
 * (floor.mk FLOOR_REF_stp).  Here: the card's state those files leave to
 * others (card.c's, cmd.c's globals), the functions they reach that no
 * input of the check gets to (each aborts the run), the inputs, and the
 * supervision and the command path, restated (card.c's and cmd.c's are
 * static, or in files that bring the whole main loop).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "fw.h"
#include "hal.h"
#include "card.h"
#include "params.h"
#include "measure.h"
#include "stepper.h"
#include "stp_card.h"
#include "motion.h"
#include "cmd.h"
#include "cmd_table.h"
#include "leds.h"
#include <stddef.h>
#include "floor.h"
#include "floorrun.h"

#if MAC4_CARD != MAC4_CARD_STP
#error "ref_stp.c is the STP tick"
#endif

_Static_assert(US_ERRORS == FL_US_ERRORS && STP_TICK_CLOCKS_TURBO == FL_STP_TICK_CLOCKS_TURBO &&
               STP_TICK_CLOCKS == FL_STP_TICK_CLOCKS && STP_OBITS == FL_STP_OBITS && M_POSITIONING == FL_M_POSITIONING && CREEP_IDLE == FL_CREEP_IDLE &&
               CREEP_REQ == FL_CREEP_REQ && CREEP_WAIT == FL_CREEP_WAIT && CREEP_RUN == FL_CREEP_RUN &&
               CREEP_DONE == FL_CREEP_DONE && CREEP_TRIM == FL_CREEP_TRIM,
               "floor.h's numbers are the firmware's");
_Static_assert(M_DISABLE == FL_M_DISABLE && M_TEST == FL_M_TEST && MK_COUNTER == FL_MK_COUNTER &&
               MK_OTHER == FL_MK_OTHER && MK_NONE == FL_MK_NONE && EXT_VME32 == FL_EXT_VME32 &&
               NO_MODE == FL_NO_MODE && US_DR_EN == FL_US_DR_EN && US_REV_O == FL_US_REV_O &&
               US_LOGO_F == FL_US_LOGO_F && US_ENCODER_F == FL_US_ENCODER_F && ERR_LOGICAL == FL_ERR_LOGICAL,
               "floor.h's numbers are the firmware's");

/* ---- the firmware state (card.c's globals) ---------------------------------- */
axis_t axes[MAC4_NAXES];
axis_t *const axis_at[MAC4_NAXES] = {&axes[0], &axes[1], &axes[2], &axes[3]};
uint32_t card_ticks;
uint16_t card_profile_late;
volatile uint8_t card_profile_due;
uint32_t card_ostat;
uint16_t card_err_report;
/* card.c's statics of the supervision, cmd.c's and serial.c's counters it
 * publishes, ext.c's switch; the command path's (cmd.c, serial.c, motion.c) */
uint32_t card_supervised;
uint16_t card_supervise_late;
static uint8_t estop_seen, ext_on;
volatile uint8_t vme_irq_waiting;
uint32_t virq_lost;                         /* card.h */
static uint32_t n_commands, n_rsp_lost, n_queue_errors, serial_stats[8];
static uint8_t serial_rx_work, serial_fifo_count, wd_fired, n_held, queue_bad, last_valid_axis, irq12;
uint8_t cmd_mr;
uint8_t card_servo_general;
static int32_t par_wd;
static int beyond;

/* what the compiled files reach beyond the tick's paths: never on an
 * input of the check (a routine would stop on ILLEGAL there) */
static void unreached(const char *f)
{
    fprintf(stderr, "floorrun: ref_stp.c: %s reached: an input beyond the check's paths\n", f);
    abort();
}
void ext_axis_init(unsigned n) { (void)n; unreached("ext_axis_init"); }     /* INIT's */
static int vme_irqs;
void vme_irq(uint8_t vector) { vme_irqs += vector != 0; }   /* the DPRAM path only: never in these inputs */

/* ---- firmware state <-> the routines' memory (floor.h) --------------------- */
static void w8(unsigned n, unsigned off, uint32_t v) { m_wr8(FLOOR_AX(n) + off, (uint8_t)v); }
static void w16(unsigned n, unsigned off, uint32_t v) { m_wr16(FLOOR_AX(n) + off, (uint16_t)v); }
static void w32(unsigned n, unsigned off, uint32_t v) { m_wr32(FLOOR_AX(n) + off, v); }
static void w64(unsigned n, unsigned off, int64_t v)
{
    w32(n, off, (uint32_t)((uint64_t)v >> 32));
    w32(n, off + 4, (uint32_t)v);
}

static void pack(void)
{
    memset(fmem + FLOOR_CARD, 0, FLOOR_AX(MAC4_NAXES) - FLOOR_CARD);
    m_wr32(FLOOR_CARD + CD_TICKS, card_ticks);
    m_wr16(FLOOR_CARD + CD_LATE, card_profile_late);
    m_wr8(FLOOR_CARD + CD_DUE, card_profile_due);
    m_wr8(FLOOR_CARD + CD_STPCONV, stp_conv);
    m_wr8(FLOOR_CARD + CD_ESTOP, estop_seen);
    m_wr8(FLOOR_CARD + CD_EXTON, ext_on);
    m_wr8(FLOOR_CARD + CD_VIRQWAIT, vme_irq_waiting);
    m_wr16(FLOOR_CARD + CD_SUPLATE, card_supervise_late);
    m_wr32(FLOOR_CARD + CD_SUPERVISED, card_supervised);
    m_wr32(FLOOR_CARD + CD_OSTAT, card_ostat);
    m_wr32(FLOOR_CARD + CD_VIRQLOST, virq_lost);
    m_wr32(FLOOR_CARD + CD_NCMD, n_commands);
    m_wr32(FLOOR_CARD + CD_RSPLOST, n_rsp_lost);
    m_wr32(FLOOR_CARD + CD_QERR, n_queue_errors);
    for (unsigned i = 0; i < 8; i++)
        m_wr32(FLOOR_CARD + CD_SERSTATS + 4 * i, serial_stats[i]);
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        const axis_t *x = &axes[n];
        const stp_t *s = &stp_ax[n];
        const meas_cfg_t *c = &meas_cfg[n];
        w32(n, ST_USTAT, x->ustat);
        w8(n, ST_MK, x->mk_tick);
        w8(n, ST_MODE, x->mode);
        w8(n, ST_BRAKING, x->braking);
        w8(n, ST_NXREADY, x->nx_ready);
        w8(n, ST_LINEAR, x->linear);
        w8(n, ST_DIR, (uint8_t)s->dir);
        w8(n, ST_CREEP, s->creep);
        w8(n, ST_ACTIVE, s->active);
        w16(n, ST_CTRL, x->ctrl);
        w16(n, ST_OUT, (uint16_t)x->out);
        w32(n, ST_RAW, x->raw);
        w32(n, ST_COUNTER, x->counter);
        w32(n, ST_MEAS, (uint32_t)x->meas);
        w32(n, ST_POS, (uint32_t)x->pos);
        w32(n, ST_SETPOINT, (uint32_t)x->setpoint);
        w32(n, ST_FERR, (uint32_t)x->ferr);
        w32(n, ST_SPI, (uint32_t)x->sp_i);
        w16(n, ST_SPF, x->sp_f);
        w16(n, ST_STF, x->st_f);
        w32(n, ST_STI, (uint32_t)x->st_i);
        w32(n, ST_STARTI, (uint32_t)x->start_i);
        w32(n, ST_ENDI, (uint32_t)x->end_i);
        w16(n, ST_STARTF, x->start_f);
        w16(n, ST_ENDF, x->end_f);
        w32(n, ST_NXSTARTI, (uint32_t)x->nx_start_i);
        w32(n, ST_NXSTI, (uint32_t)x->nx_st_i);
        w32(n, ST_NXENDI, (uint32_t)x->nx_end_i);
        w16(n, ST_NXSTARTF, x->nx_start_f);
        w16(n, ST_NXSTF, x->nx_st_f);
        w16(n, ST_NXENDF, x->nx_end_f);
        w8(n, ST_BOOST, s->boost);
        w8(n, ST_BOOSTEN, s->boost_en);
        w64(n, ST_BRPOSH, x->br_posh);
        w32(n, ST_BRV, (uint32_t)x->br_v);
        w32(n, ST_BRDEC, (uint32_t)x->br_dec);
        w32(n, ST_BRSSF, (uint32_t)x->br_ssf);
        w32(n, ST_CR, (uint32_t)x->cr);
        w64(n, ST_PROFVEL, x->prof.vel);
        w32(n, ST_RATIO, s->ratio);
        w32(n, ST_INC, (uint32_t)s->inc);
        w32(n, ST_CONV, (uint32_t)s->conv);
        w16(n, ST_RATE, s->rate);
        w16(n, ST_OBITS, s->obits);
        w16(n, ST_CLOCKS, s->clocks);
        w16(n, ST_LVRATE, s->lv_rate);
        w32(n, ST_LIM, s->lim);
        w32(n, ST_CARRY, s->carry);
        w32(n, ST_DA, (uint32_t)PAR(n, DA));
        w16(n, ST_ERR, x->err_report);
        w8(n, ST_STOPTHEN, x->stop_then);
        w8(n, ST_STOPSETTLE, x->stop_settle);
        w8(n, ST_NEXTMODE, x->next_mode);
        w8(n, ST_PATH, c->path);
        w8(n, ST_ABS, c->abs);
        w8(n, ST_FAILED, c->failed);
        w32(n, ST_MASK, c->mask);
        w32(n, ST_MLIM, c->lim);
        w32(n, ST_RANGE, (uint32_t)c->range);
        w32(n, ST_HALF, (uint32_t)c->half);
        w32(n, ST_SIGN, c->sign);
        w32(n, ST_EADDR, c->addr);
        w16(n, ST_PAGE, c->page);
        w8(n, ST_DKIND, c->abs ? (x->linear ? 0 : 1) : 2);             /* floor: at INIT */
        w64(n, ST_TARGET, x->target);
        w32(n, ST_CREEPBASE, (uint32_t)s->creep_base);
        w16(n, ST_CREEPN, s->creep_n);
        w16(n, ST_COUNTED, s->counted);
        w8(n, ST_HWDONE, s->hw_done);
        w8(n, ST_CREEPDIR, (uint8_t)s->creep_dir);
        w8(n, ST_CREEPIRQ, s->creep_irq);
        w8(n, ST_MKSUP, x->mk);
        w16(n, ST_IN, x->in);
        w64(n, ST_PROFPOS, x->prof.pos);
        w32(n, ST_SSTAT, x->sstat);
        w32(n, ST_VEL, (uint32_t)x->vel);
        w32(n, ST_MEASSUP, (uint32_t)x->meas_sup);
        w32(n, ST_MF, (uint32_t)x->mf);
        w32(n, ST_LP, (uint32_t)x->lp);
        w32(n, ST_LN, (uint32_t)x->ln);
        w16(n, ST_SWEN, x->sw_en);
        w16(n, ST_SWINV, x->sw_inv);
        w8(n, ST_INEVAL, x->in_eval);
        w8(n, ST_IDXSEEN, x->idx_seen);
        w8(n, ST_DF, (uint32_t)PAR(n, DF));
    }
}

static const field_t fields[] = {
    {ST_USTAT, 4, "ustat"}, {ST_MK, 1, "mk_tick"}, {ST_MODE, 1, "mode"}, {ST_BRAKING, 1, "braking"},
    {ST_NXREADY, 1, "nx_ready"}, {ST_LINEAR, 1, "linear"}, {ST_DIR, 1, "stp.dir"}, {ST_CREEP, 1, "stp.creep"},
    {ST_ACTIVE, 1, "stp.active"}, {ST_CTRL, 2, "ctrl"}, {ST_OUT, 2, "out"}, {ST_RAW, 4, "raw"},
    {ST_COUNTER, 4, "counter"}, {ST_MEAS, 4, "meas"}, {ST_POS, 4, "pos"}, {ST_SETPOINT, 4, "setpoint"},
    {ST_FERR, 4, "ferr"}, {ST_SPI, 4, "sp_i"}, {ST_SPF, 2, "sp_f"}, {ST_STF, 2, "st_f"}, {ST_STI, 4, "st_i"},
    {ST_STARTI, 4, "start_i"}, {ST_ENDI, 4, "end_i"}, {ST_STARTF, 2, "start_f"}, {ST_ENDF, 2, "end_f"},
    {ST_NXSTARTI, 4, "nx_start_i"}, {ST_NXSTI, 4, "nx_st_i"}, {ST_NXENDI, 4, "nx_end_i"},
    {ST_NXSTARTF, 2, "nx_start_f"}, {ST_NXSTF, 2, "nx_st_f"}, {ST_NXENDF, 2, "nx_end_f"},
    {ST_BOOST, 1, "stp.boost"}, {ST_BOOSTEN, 1, "stp.boost_en"}, {ST_BRPOSH, 8, "br_posh"}, {ST_BRV, 4, "br_v"},
    {ST_BRDEC, 4, "br_dec"}, {ST_BRSSF, 4, "br_ssf"}, {ST_CR, 4, "cr"}, {ST_PROFVEL, 8, "prof.vel"},
    {ST_RATIO, 4, "stp.ratio"}, {ST_INC, 4, "stp.inc"}, {ST_CONV, 4, "stp.conv"}, {ST_RATE, 2, "stp.rate"},
    {ST_OBITS, 2, "stp.obits"}, {ST_CLOCKS, 2, "stp.clocks"}, {ST_LVRATE, 2, "stp.lv_rate"}, {ST_LIM, 4, "stp.lim"},
    {ST_CARRY, 4, "stp.carry"}, {ST_DA, 4, "da"}, {ST_ERR, 2, "err_report"}, {ST_STOPTHEN, 1, "stop_then"},
    {ST_STOPSETTLE, 1, "stop_settle"}, {ST_NEXTMODE, 1, "next_mode"}, {ST_PATH, 1, "path"}, {ST_ABS, 1, "abs"},
    {ST_FAILED, 1, "failed"}, {ST_MASK, 4, "mask"}, {ST_MLIM, 4, "lim"}, {ST_RANGE, 4, "range"},
    {ST_HALF, 4, "half"}, {ST_SIGN, 4, "sign"}, {ST_EADDR, 4, "addr"}, {ST_PAGE, 2, "page"},
    {ST_DKIND, 1, "delta kind"}, {ST_TARGET, 8, "target"}, {ST_CREEPBASE, 4, "stp.creep_base"},
    {ST_CREEPN, 2, "stp.creep_n"}, {ST_COUNTED, 2, "stp.counted"}, {ST_HWDONE, 1, "stp.hw_done"},
    {ST_CREEPDIR, 1, "stp.creep_dir"}, {ST_CREEPIRQ, 1, "stp.creep_irq"}, {ST_MKSUP, 1, "mk"}, {ST_IN, 2, "in"},
    {ST_PROFPOS, 8, "prof.pos"}, {ST_SSTAT, 4, "sstat"}, {ST_VEL, 4, "vel"}, {ST_MEASSUP, 4, "meas_sup"},
    {ST_MF, 4, "mf"}, {ST_LP, 4, "lp"}, {ST_LN, 4, "ln"}, {ST_SWEN, 2, "sw_en"}, {ST_SWINV, 2, "sw_inv"},
    {ST_INEVAL, 1, "in_eval"}, {ST_IDXSEEN, 1, "idx_seen"}, {ST_DF, 1, "df"},
};

/* ---- inputs ------------------------------------------------------------------ */
enum { R_COUNTER, R_EXT };
static int routine_kind;
enum { S_MOVING, S_START, S_BRAKING, S_STANDSTILL, S_ENCODER, S_CREEP, S_CREEP_TWO, S_EXT_BRAKE };
/* S_CREEP_TWO, S_EXT_BRAKE: inputs per sample, half the samples each way,
 * so that the scenario's floor is the firmware's worst tick of it (read off
 * its instruction profile) and min= the easier tick the floor measured
 * before (as ref_servo.c's encoder_loss):
 * - creep: at an SP boundary two creep phases begin (axes 1 and 2, the
 *   shorter moves) while axes 0 and 3 move on; min= four moves starting;
 * - external: the tick's brake on four axes, its ramp's last step (from
 *   above <ssf> it ends at <ssf>, 5.14: motion.c brake_now's stop), not at
 *   an SP boundary; min= the axes standing, at the SP boundary. */
static int mixed_hard;
static int32_t near(int32_t base, int32_t span) { return pos_add(base, rnd_range(-span, span)); }
static uint32_t eb_mask(int eb) { return eb >= 32 ? 0xFFFFFFFFu : ((1u << eb) - 1u); }

/* A scenario (perfscen) at 2000 steps/s: 16 steps per 8 ms tick, the
 * direction of the axis' target (axes 1 and 3 negative). */
#define SCEN_STEPS 16

static void gen_axis(unsigned n, int scen)
{
    axis_t *x = &axes[n];
    stp_t *s = &stp_ax[n];
    meas_cfg_t *c = &meas_cfg[n];
    memset(x, 0, sizeof *x);
    memset(s, 0, sizeof *s);
    memset(c, 0, sizeof *c);
    int broad = scen < 0;
    int sign = n & 1 ? -1 : 1;
    static const uint8_t modes[] = {M_DISABLE, M_TEST, M_ENABLE, M_POSITIONING, M_BRAKE, M_SPEED, M_HOME};
    x->mode = broad ? modes[rnd_below(sizeof modes)] : M_POSITIONING;
    x->ustat = (broad ? rnd() : 0) & ~(US_MODE_MASK | UB(DR_EN));
    x->ustat |= UB(INIT) | x->mode | (x->mode != M_DISABLE ? UB(DR_EN) : 0);
    x->next_mode = NO_MODE;
    x->braking = (uint8_t)(broad ? rnd_pct(25) : scen == S_BRAKING || scen == S_EXT_BRAKE);
    x->nx_ready = (uint8_t)(broad ? rnd_pct(50) : scen == S_MOVING || scen == S_START || scen == S_ENCODER ||
                                                  scen == S_CREEP);   /* the creep's: the profile's next segment is there */
    x->ctrl = (uint16_t)((broad ? rnd() & 0xFFFF : 0) | (x->mode != M_DISABLE ? AX_CTRL_EN : 0));
    x->err_report = (uint16_t)(broad && rnd_pct(20) ? 162 : 0);
    x->stop_then = (uint8_t)(broad ? rnd_below(4) : 0);
    x->stop_settle = (uint8_t)(broad ? rnd_below(2) : 0);
    x->linear = (uint8_t)(broad ? rnd_pct(70) : 1);
    x->cr = broad ? (rnd_pct(20) ? rnd_range(1, 3000) : rnd_range(1000, INT32_MAX)) : 10000;
    x->meas = broad ? (int32_t)rnd() : rnd_range(-20000, 20000);
    x->pos = x->linear ? (broad ? (int32_t)rnd() : x->meas) : (int32_t)rnd_below((uint32_t)x->cr);
    x->counter = rnd() & 0xFFFFFFu;
    x->raw = rnd();
    x->out = (int16_t)rnd();
    x->setpoint = (int32_t)rnd();
    x->ferr = (int32_t)rnd();
    par_a[P_DA][n] = broad ? (rnd_pct(10) ? rnd_range(-60000, 60000) : rnd_range(-50000, 50000)) : 0;
    /* the setpoint: the last tick's, and the segment the profile prepared */
    int32_t span = broad ? (rnd_pct(20) ? 100000 : 3000) : 0;
    x->sp_i = broad ? near(x->meas, span) : x->meas;
    x->sp_f = (uint16_t)rnd();
    int32_t step = broad ? (rnd_pct(10) ? rnd_range(-40000, 40000) : rnd_range(-100, 100)) : sign * SCEN_STEPS;
    if (scen == S_STANDSTILL)
        step = 0;
    uint16_t stf = (uint16_t)(broad || step ? rnd() : 0);
    x->start_i = broad ? near(x->sp_i, 50) : x->sp_i;
    x->start_f = broad ? (uint16_t)rnd() : x->sp_f;
    x->st_i = broad ? rnd_range(-100, 100) : step;
    x->st_f = broad ? (uint16_t)rnd() : stf;
    x->end_i = broad ? near(x->sp_i, 400) : x->sp_i + 4 * step;
    x->end_f = (uint16_t)(broad ? rnd() : x->sp_f);
    x->nx_start_i = broad ? near(x->sp_i, 50) : x->sp_i;      /* the next segment starts where the last ended */
    x->nx_start_f = (uint16_t)(broad ? rnd() : x->sp_f);
    x->nx_st_i = step;
    x->nx_st_f = stf;
    x->nx_end_i = broad ? near(x->sp_i, 400) : x->sp_i + 4 * step;
    x->nx_end_f = (uint16_t)rnd();
    if (broad && rnd_pct(20))
        x->st_i = x->nx_st_i = rnd_range(-40000, 40000);   /* a jump the rate saturates on */
    x->prof.vel = broad ? (rnd_pct(40) ? 0 : (int64_t)(int32_t)rnd()) : (scen == S_BRAKING ? 0 : sign * (32 << 16));
    /* the tick's own brake: at rest (the stand-still then trims), or slowing down */
    x->br_ssf = broad ? rnd_range(0, 3 << 16) : 1 << 16;
    x->br_v = broad ? (rnd_pct(30) ? 0 : rnd_range(-(40 << 16), 40 << 16)) : 0;
    x->br_dec = broad ? rnd_range(1, 1 << 16) : 1 << 12;
    x->br_posh = ((int64_t)x->sp_i << 16) + x->sp_f + BR_HALF;
    if (scen == S_EXT_BRAKE) {          /* the ramp's last step: <pd> takes it below 0, <ssf> holds it there */
        x->br_v = sign * (3 << 15);
        x->br_dec = 1 << 17;
    }
    /* stp_t */
    s->clocks = broad && rnd_pct(30) ? STP_TICK_CLOCKS_TURBO : STP_TICK_CLOCKS;
    s->lim = (uint32_t)s->clocks << 16;
    s->carry = rnd_below(s->clocks);
    s->dir = (int8_t)(broad ? rnd_range(-1, 1) : scen == S_START ? 0 : sign);
    s->rate = (uint16_t)(broad ? rnd() : scen == S_BRAKING ? 0 : 2621);
    s->obits = (uint16_t)(broad ? rnd() & STP_OBITS : AX_CTRL_BOOST | (sign > 0 ? AX_CTRL_DIR : 0));
    s->lv_rate = (uint16_t)rnd_range(1, 1311);
    s->boost = (uint8_t)(broad ? rnd_pct(50) : 1);
    s->boost_en = (uint8_t)(broad ? rnd_pct(50) : 1);
    s->active = (uint8_t)(broad ? rnd_pct(50) : 1);
    s->creep = CREEP_IDLE;
    x->mk = routine_kind == R_COUNTER ? MK_COUNTER : MK_OTHER;
    x->in = (uint16_t)rnd();
    x->prof.pos = (int64_t)((uint64_t)rnd() << 32 | rnd());
    x->target = ((int64_t)x->meas << 16) + (int64_t)(uint16_t)rnd();
    s->creep_base = near(x->meas, 50);
    s->creep_dir = (int8_t)(rnd_pct(50) ? 1 : -1);
    s->creep_n = (uint16_t)rnd_below(100);
    s->counted = (uint16_t)(broad && rnd_pct(10) ? rnd() : rnd_below((uint32_t)s->creep_n + 1u));
    s->hw_done = (uint8_t)(broad && rnd_pct(20));
    s->creep_irq = (uint8_t)rnd_below(2);
    if (broad && rnd_pct(30)) {             /* the creep phase: requested, waiting, running, done; the trim */
        static const uint8_t cs[] = {CREEP_REQ, CREEP_WAIT, CREEP_RUN, CREEP_RUN, CREEP_DONE, CREEP_TRIM};
        s->creep = cs[rnd_below(sizeof cs)];
        x->target += (int64_t)rnd_range(-300, 300) << 16;
        if (rnd_pct(70))
            x->mode = M_POSITIONING, x->stop_then = 0;
        x->ustat = (x->ustat & ~US_MODE_MASK) | x->mode;
        x->ctrl = (uint16_t)((x->ctrl & ~AX_CTRL_EN) | (x->mode != M_DISABLE ? AX_CTRL_EN : 0));
    }
    if (scen == S_CREEP) {                  /* the ramp has ended: <stc> 20 steps to go at <lv> 100 Hz */
        s->creep = CREEP_REQ;
        x->target = ((int64_t)(x->meas + sign * 20) << 16) + 0x4000;
        s->lv_rate = 131;
    }
    int conv = broad ? rnd_pct(40) : scen == S_ENCODER || routine_kind == R_EXT;
    s->ratio = conv ? (uint32_t)(broad ? rnd_range(0x1000, 0x80000) : 0x2000) : 0x10000u;   /* <ms> 500 / (4 <es> 1000) */
    s->inc = broad ? rnd_range(-(1 << 24), 1 << 24) : x->meas * 8;
    s->conv = stp_scale(s->inc, s->ratio);
    if (conv) {
        stp_conv = (uint8_t)(stp_conv | (1u << n));
        if (!broad)
            x->meas = s->conv;
    }
    if (broad && rnd_pct(25)) {         /* standing: the setpoint stays, a few steps off it (the trim) */
        x->start_i = x->end_i = x->nx_start_i = x->nx_end_i = x->sp_i;
        x->start_f = x->end_f = x->nx_start_f = x->nx_end_f = x->sp_f;
        x->st_i = x->nx_st_i = 0;
        x->st_f = x->nx_st_f = 0;
        x->br_v = 0;
        x->br_posh = ((int64_t)x->sp_i << 16) + x->sp_f + BR_HALF;
        x->prof.vel = rnd_pct(70) ? 0 : x->prof.vel;
        s->rate = (uint16_t)(rnd_pct(60) ? 0 : s->rate);
        x->meas = x->sp_i + (x->sp_f >= 0x8000u) + rnd_range(-5, 5);
    }
    if (scen == S_BRAKING) {            /* the brake stood: a step or two off the setpoint, the trim */
        x->meas = x->sp_i + (x->sp_f >= 0x8000u) + (int32_t)rnd_range(1, 3) * sign;
        x->pos = x->meas;
    }
    stp_path_set(x);                    /* as axis_set_mode and the brake keep it */
    int mine = broad ? rnd_pct(85) : 1;
    if (routine_kind == R_COUNTER) {
        x->mk_tick = mine ? MK_COUNTER : MK_NONE;
        int16_t d = broad ? (int16_t)rnd() : (int16_t)(sign * (conv ? 8 * SCEN_STEPS : SCEN_STEPS));
        if (scen == S_STANDSTILL || scen == S_BRAKING)
            d = 0;
        if (!x->linear && broad && x->cr < 40000)
            d = (int16_t)rnd_range(-x->cr, x->cr);
        m_wr16(AX_REG(n, AX_CNT_LIVE), (uint16_t)(x->counter + (uint32_t)d));
        /* the whole counter as creep_begin re-reads it: where the tick left it, a step on or so */
        uint32_t c = (x->counter + (uint32_t)(int16_t)(uint16_t)(m_rd16(AX_REG(n, AX_CNT_LIVE)) - (uint16_t)x->counter) +
                      (uint32_t)(broad ? rnd_range(-2, 2) : 0)) & 0xFFFFFFu;
        m_wr16(AX_REG(n, AX_CNT_HI), (uint16_t)(c >> 16));
        m_wr16(AX_REG(n, AX_CNT_LO), (uint16_t)c);
    } else {
        x->mk_tick = mine ? MK_OTHER : MK_NONE;
        int eb = broad ? (int)rnd_range(17, 32) : 24;
        int abs = broad ? rnd_pct(60) : 1;
        uint32_t ec = broad && rnd_pct(30) ? rnd_below(eb_mask(eb) < INT32_MAX ? eb_mask(eb) : INT32_MAX) + 1u : 0;
        uint32_t lim = eb_mask(eb);
        if (ec > 0 && ec - 1u < lim)
            lim = ec - 1u;
        c->lim = lim;
        c->range = lim < eb_mask(eb) ? (int32_t)(lim + 1u) : 0;
        c->half = c->range >> 1;
        c->abs = (uint8_t)abs;
        c->mask = eb_mask(eb);
        c->sign = eb < 32 ? 1u << (eb - 1) : 0;
        uint32_t ea = 0x80C000u + 0x10u * n;
        if (broad && rnd_pct(30))
            ea = rnd() & 0xFFFF00u;
        c->path = broad && rnd_pct(5) ? EXT_NONE : EXT_VME32;
        c->page = (uint16_t)(ea >> 20);
        c->addr = VME_WIN_BASE + (ea & (VME_WIN_SIZE - 1u));
        /* the last reading: the counter in its increments (absolute: the
         * encoder's position, stp_counts) */
        uint32_t last = (uint32_t)stp_counts(n) & c->mask;
        if (abs && broad) {                 /* the encoder's position is the counter's */
            last = rnd() & c->mask & 0x7FFFFFu;
            if (stp_conv & (1u << n)) {
                s->inc = (int32_t)last;
                s->conv = stp_scale(s->inc, s->ratio);
            } else {
                x->meas = (x->ustat & UB(REV_O)) ? -(int32_t)last : (int32_t)last;
            }
        }
        if (!abs) {
            last = x->counter & c->mask;
            if (last > c->lim)
                last %= c->lim + 1u;
        }
        x->counter = last;
        int32_t dd = broad ? rnd_range(-300, 300) : sign * 8 * SCEN_STEPS;
        if (scen == S_STANDSTILL)
            dd = 0;
        uint32_t now = (last + (uint32_t)dd) & c->mask;
        if (broad && x->linear && rnd_pct(10))
            now = rnd();
        if (broad && x->linear && rnd_pct(5))
            now = c->lim + (c->lim < c->mask ? rnd_below(2) : 0);
        dev.vme_boards[n].a24 = (broad ? rnd_pct(85) : 1) ? ea : 0;
        dev.vme_boards[n].value = now | (broad ? rnd() & ~c->mask : 0);
        c->failed = (uint8_t)(broad ? rnd_pct(30) : 0);
    }
}

static void gen(int scen)
{
    memset(&dev, 0, sizeof dev);
    memset(fmem + IO_BASE, 0, 0x2000);
    stp_conv = 0;
    mixed_hard = scen == S_CREEP_TWO || scen == S_EXT_BRAKE ? rnd_pct(50) : 0;
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        int sn = scen;
        if (scen == S_CREEP_TWO)
            sn = !mixed_hard ? S_START : n == 1 || n == 2 ? S_CREEP : S_MOVING;
        else if (scen == S_EXT_BRAKE)
            sn = mixed_hard ? S_EXT_BRAKE : S_STANDSTILL;
        gen_axis(n, sn);
    }
    card_ticks = scen < 0 ? rnd() : 4000u + 4u * rnd_below(1000);   /* a scenario: the SP boundary */
    if (scen == S_EXT_BRAKE && mixed_hard)
        card_ticks++;                   /* the brake's worst tick: the firmware's was not an SP boundary's */
    card_profile_late = (uint16_t)rnd();
    card_profile_due = (uint8_t)rnd_below(5);
    dev.vme_page = (uint16_t)rnd_below(16);
    dev.vme_berr = (uint16_t)(scen < 0 ? rnd_pct(20) : 0);
    m_wr16(VME_PAGE, dev.vme_page);
    pack();
}

static int compare(char *msg, size_t len)
{
    floor_restore_inputs();
    fw_isr_tick();
    pack();
    return floor_compare(msg, len, fields, sizeof fields / sizeof fields[0]);
}

static void gen_counter(int scen)
{
    routine_kind = R_COUNTER;
    gen(scen);
}
static void gen_ext(int scen)
{
    routine_kind = R_EXT;
    gen(scen);
}

/* ---- the supervision after a tick (supervise.c card_supervise_tick, STP), on
 * the path of its floor routine (sup.inc) ---------------------------------- */
static const uint32_t sw_ustat[8] = {
    0, UB(HWL_P), UB(HWL_N), UB(HWL_P) | UB(HWL_N), UB(REF), UB(REF) | UB(HWL_P),
    UB(REF) | UB(HWL_N), UB(REF) | UB(HWL_P) | UB(HWL_N),
};

static void axis_inputs(unsigned n)
{
    axis_t *x = &axes[n];
    uint16_t in = hal_rd16(AX_REG(n, AX_IN));
    if (in == x->in && !x->in_eval)
        return;
    x->in = in;
    x->in_eval = 0;
    if (!axis_initialised(n))
        return;
    uint16_t active = (uint16_t)((in ^ x->sw_inv) & x->sw_en);
    x->in_eval = (active & AX_IN_DF) != 0;
    uint32_t sw = sw_ustat[active & 7u];
    uint32_t prev = x->ustat;
    x->ustat = (x->ustat & ~(UB(HWL_P) | UB(HWL_N) | UB(REF))) | sw;
    if ((active & AX_IN_DF) && x->mode != M_DISABLE && !(x->ustat & UB(DR_F)))
        beyond = 1;
    if (x->mode == M_TEST && (sw & ~prev & (UB(HWL_P) | UB(HWL_N))))
        beyond = 1;
}

static void supervise_axis(unsigned n)
{
    unsigned prev = hal_irq_save();
    axis_t *x = &axes[n];
    if (x->mk_tick != MK_NONE)
        x->vel = x->meas - x->meas_sup;
    if (x->mk_tick == MK_COUNTER)
        x->raw = x->counter;
    x->meas_sup = x->meas;
    x->mk_tick = (x->ustat & UB(INIT)) ? x->mk : MK_NONE;
    axis_inputs(n);
    if (!motion_quiet(x))
        beyond = 1;
    hal_irq_restore(prev);
}

static void publish(unsigned n)
{
    const axis_t *x = &axes[n];
    uint32_t d = DP_AXIS_DATA(n);
    hal_wr32(d + DPA_USTAT, x->ustat);
    hal_wr32(d + DPA_SSTAT, x->sstat);
    hal_wr32(d + DPA_POS, (uint32_t)x->pos);
    hal_wr32(d + DPA_SETPOINT, (uint32_t)pos_add(x->pos, x->ferr));
    hal_wr32(d + DPA_FERR, (uint32_t)x->ferr);
    hal_wr32(d + DPA_OUT, (uint32_t)stp_hz_now(n));
    hal_wr32(d + DPA_VEL, (uint32_t)x->vel);
    hal_wr32(d + DPA_RAW, x->raw);
}

/* supervise.c's: one axis' body from leds.h */
static void leds(void)
{
    uint16_t l = 0;
    for (unsigned n = 0; n < MAC4_NAXES; n++)
        l = axis_leds(l, n);
    hal_wr16(SYS_LEDS, l);
}

static void card_supervise_tick_ref(void)
{
    uint32_t t = card_ticks;
    if (t == card_supervised)
        return;
    if (t - card_supervised > 1u)
        card_supervise_late++;
    card_supervised = t;
    uint16_t sys = hal_rd16(SYS_STATUS);
    card_ostat = (card_ostat & ~(uint32_t)(OB(FCODE0) | OB(FCODE1) | OB(FCODE2))) |
                 ((uint32_t)((sys >> SYS_ST_FC_SHIFT) & 7u) << OS_FCODE0);
    if (estop_seen)
        beyond = 1;
    unsigned phase = (t - 1u) & (PROFILE_DIVIDER - 1u);
    for (unsigned n = 0; n < MAC4_NAXES; n++)
        supervise_axis(n);
    uint16_t w = hal_rd16(DP_STOP_BITS);
    if ((w | (w >> 8)) & 0xAAu)
        beyond = 1;
    if (ext_on)
        beyond = 1;
    unsigned prev = hal_irq_save();
    publish(phase);
    hal_irq_restore(prev);
    if (phase == 0)
        leds();
    hal_wr32(DPC_TICKS, t);
    hal_wr32(DPC_OSTAT, card_ostat);
    hal_wr32(DPC_PROFILE_LATE, card_profile_late);
    hal_wr32(DPC_SUPERVISE_LATE, card_supervise_late);
    hal_wr32(DPC_VME_IRQ_LOST, virq_lost);
    hal_wr32(DPC_COMMANDS, n_commands);
    hal_wr32(DPC_RSP_LOST, n_rsp_lost);
    hal_wr32(DPC_QUEUE_ERRORS, n_queue_errors);
    unsigned i = 2u * (phase & 3u);
    hal_wr32(DPC_SERIAL_RX_OK + 4u * i, serial_stats[i]);
    hal_wr32(DPC_SERIAL_RX_OK + 4u * (i + 1u), serial_stats[i + 1u]);
    if (vme_irq_waiting)
        beyond = 1;
}

static void gen_sup(int scen)
{
    routine_kind = R_COUNTER;
    gen(scen < 0 ? -1 : S_MOVING);
    int broad = scen < 0;
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        axis_t *x = &axes[n];
        x->braking = 0;
        x->ustat &= ~(UB(HWL_P) | UB(HWL_N) | UB(SWL_P) | UB(SWL_N) | UB(POS_END));
        x->ustat |= broad && rnd_pct(50) ? UB(POS_END) : 0;
        x->ustat &= broad && rnd_pct(10) ? ~UB(INIT) : ~0u;
        x->ustat &= broad && rnd_pct(70) ? ~US_ERRORS : ~0u;
        x->sstat = rnd();
        x->mk = MK_COUNTER;
        x->mk_tick = broad && rnd_pct(15) ? MK_NONE : MK_COUNTER;
        x->meas_sup = broad ? (int32_t)rnd() : x->meas - 16;
        x->vel = (int32_t)rnd();
        x->setpoint = pos_add(x->meas, rnd_range(-3, 3));
        x->ferr = pos_sub(x->setpoint, x->meas);
        x->stop_settle = 0;
        int32_t af = x->ferr < 0 ? -x->ferr : x->ferr;
        x->mf = af + (broad ? (int32_t)rnd_below(3) * (rnd_pct(50) ? 1 : 1000) : 1000);
        x->lp = pos_add(x->pos, broad ? (int32_t)rnd_below(3) * (rnd_pct(50) ? 1 : 100000) : 100000);
        x->ln = pos_sub(x->pos, broad ? (int32_t)rnd_below(3) * (rnd_pct(50) ? 1 : 100000) : 100000);
        if (x->lp < x->pos || x->ln > x->pos) {
            x->lp = INT32_MAX;
            x->ln = INT32_MIN;
        }
        x->sw_en = (uint16_t)((broad ? rnd() : 0xF) & (AX_IN_IESP | AX_IN_IESN | AX_IN_RS | AX_IN_DF));
        x->sw_inv = (uint16_t)(rnd() & x->sw_en);
        uint16_t in = (uint16_t)(rnd() & 0x7FF & ~AX_IN_SSI_BUSY);
        in = (uint16_t)((in & ~(AX_IN_IESP | AX_IN_IESN | AX_IN_DF)) | (x->sw_inv & (AX_IN_IESP | AX_IN_IESN | AX_IN_DF)));
        int same = broad ? rnd_pct(40) : 1;          /* the STP's steps: no index pulse */
        x->in = same ? in : (uint16_t)(in ^ AX_IN_IDX);
        x->in_eval = (uint8_t)(broad && rnd_pct(20));
        m_wr16(AX_REG(n, AX_IN), in);
        x->idx_seen = (uint8_t)(x->mode == M_SEARCH_IDX_C || x->mode == M_SEARCH_IDX || x->mode == M_HOME ||
                                rnd_pct(50));
        par_a[P_DF][n] = (int32_t)rnd_below(3);
    }
    card_supervised = card_ticks - (broad ? (rnd_pct(10) ? 0 : rnd_pct(20) ? rnd_range(2, 5) : 1) : 1);
    card_supervise_late = (uint16_t)rnd();
    card_ostat = rnd();
    estop_seen = ext_on = 0;
    vme_irq_waiting = 0;
    virq_lost = rnd();
    n_commands = rnd();
    n_rsp_lost = rnd();
    n_queue_errors = rnd();
    for (unsigned i = 0; i < 8; i++)
        serial_stats[i] = rnd();
    if (!broad) {
        card_ticks = 4001u + 4u * rnd_below(1000);
        card_supervised = card_ticks - 1u;
    }
    m_wr16(SYS_STATUS, (uint16_t)rnd());
    memset(fmem + DPRAM_BASE + 0x400, 0, DPRAM_SIZE - 0x400);
    m_wr16(DP_STOP_BITS, (uint16_t)(rnd() & 0x5555u));
    pack();
}

static int compare_sup(char *msg, size_t len)
{
    floor_restore_inputs();
    beyond = 0;
    card_supervise_tick_ref();
    if (beyond) {
        snprintf(msg, len, "an input beyond the routine's path (ref_stp.c gen_sup)");
        return 1;
    }
    pack();
    return floor_compare(msg, len, fields, sizeof fields / sizeof fields[0]);
}

/* ---- the command path (cmd.c cmd_poll), the VME host's reads (cmd.inc) --- */
#define DIAG_FIELD(f) CK_FIELD, offsetof(axis_t, f)
#define DIAG_RCP  DIAG_FIELD(pos)
#define DIAG_RCPI CK_DIAG, CI_RCPI
#define DIAG_ROUT CK_DIAG, CI_ROUT
#define DIAG_RCT  DIAG_FIELD(counter)
#define DIAG_RED  DIAG_FIELD(raw)
#define DIAG_RFE  DIAG_FIELD(ferr)
#define DIAG_RPS  CK_DIAG, CI_RPS
#define DIAG_RAV  DIAG_FIELD(vel)
#define DIAG_RAS  CK_DIAG, CI_RAS
#define DIAG_RBS  DIAG_FIELD(ustat)
#define DIAG_RSS  DIAG_FIELD(sstat)
#define CMD_ON(cards, kind, arg) {ON_THIS_CARD(cards) ? (kind) : CK_NONE, (uint8_t)(arg)}
#define CMD_ON_(...) CMD_ON(__VA_ARGS__)
static const cmd_t cmds[] = {
#define GEN(mn, code, cards, kind, desc) [code] = CMD_ON(cards, kind, CI_##mn),
#define MODESEL(mn, code, cards, mode, desc) [code] = CMD_ON(cards, CK_MODE, (mode)),
#define DIAG(mn, code, cards, units, desc) [code] = CMD_ON_(cards, DIAG_##mn),
#define PARAM(id, mn, kind, wcode, cards, flags, min, max, def, units, desc) \
    [wcode] = CMD_ON(cards, CK_WPAR, P_##id), [(wcode) + 1] = CMD_ON(cards, CK_RPAR, P_##id),
#include "commands.def"
};
#define NCODES (sizeof cmds / sizeof cmds[0])

static uint8_t field_off(uint8_t host)
{
    static const struct { size_t host; uint8_t fl; } map[] = {
        {offsetof(axis_t, pos), ST_POS}, {offsetof(axis_t, counter), ST_COUNTER}, {offsetof(axis_t, raw), ST_RAW},
        {offsetof(axis_t, ferr), ST_FERR}, {offsetof(axis_t, vel), ST_VEL}, {offsetof(axis_t, ustat), ST_USTAT},
        {offsetof(axis_t, sstat), ST_SSTAT},
    };
    for (unsigned i = 0; i < sizeof map / sizeof map[0]; i++)
        if (map[i].host == host)
            return map[i].fl;
    fprintf(stderr, "floorrun: a CK_FIELD of no known field\n");
    return 0xFF;
}

static void cmd_poll_ref(void)
{
    if (serial_rx_work || par_wd > 0)
        beyond = 1;
    if (cmd_mr)
        return;
    if (n_held)
        beyond = 1;
    int have = 0;
    mac4_msg_t in;
    if (serial_fifo_count)
        beyond = 1;                                 /* serial_command, after the VME queue */
    int r = q_get_at(DP_CMD_QUEUE, &in, 0);
    if (r == Q_CORRUPT) {
        if (!queue_bad)
            hal_wr32(DPC_QUEUE_ERRORS, ++n_queue_errors);
        queue_bad = 1;
    } else {
        queue_bad = 0;
        have = r;
        if (have) {
            in.source = MSG_SRC_VME;
            if ((irq12 & 1u) && in.axis < MAC4_NAXES)
                beyond = 1;
        }
    }
    if (!have)
        return;
    cmd_t c = in.code < NCODES ? cmds[in.code] : (cmd_t){CK_NONE, 0};
    if (!kind_is_read(c.kind) || in.axis >= MAC4_NAXES)
        beyond = 1;
    if (beyond)
        return;
    mac4_msg_t out = {0, 0, 0, 0};
    unsigned prev = hal_irq_save();
    if (card_ticks != card_supervised)
        beyond = 1;
    out.axis = in.axis;
    out.source = in.source;
    out.code = in.code;
    wd_fired = 0;
    last_valid_axis = in.axis;
    const axis_t *x = axis_at[in.axis];
    if (c.kind == CK_FIELD)
        out.param = *(const uint32_t *)(const void *)((const uint8_t *)x + c.arg);
    else if (c.kind == CK_DIAG && c.arg == CI_ROUT)
        out.param = (uint32_t)stp_out_steps_sp(in.axis);  /* cmd_read_value */
    else
        beyond = 1;
    hal_irq_restore(prev);
    hal_wr32(DPC_COMMANDS, ++n_commands);
    if (motion_vq_due)
        beyond = 1;
    if (q_put_at(DP_RSP_QUEUE, out.axis, out.code, out.param, MSG_SRC_VME) != Q_OK) {
        hal_wr32(DPC_RSP_LOST, ++n_rsp_lost);
        return;
    }
    if (irq12 & 2u)
        beyond = 1;
}

static void pack_cmd(void)
{
    pack();
    m_wr8(FLOOR_CARD + CD_SERWORK, serial_rx_work);
    m_wr8(FLOOR_CARD + CD_FIFOCNT, serial_fifo_count);
    m_wr8(FLOOR_CARD + CD_WDFIRED, wd_fired);
    m_wr8(FLOOR_CARD + CD_MR, cmd_mr);
    m_wr8(FLOOR_CARD + CD_NHELD, n_held);
    m_wr8(FLOOR_CARD + CD_QBAD, queue_bad);
    m_wr8(FLOOR_CARD + CD_LASTAX, last_valid_axis);
    m_wr8(FLOOR_CARD + CD_IRQ12, irq12);
    m_wr8(FLOOR_CARD + CD_VQDUE, motion_vq_due);
    m_wr16(FLOOR_CARD + CD_NCODES, (uint16_t)NCODES);
    m_wr32(FLOOR_CARD + CD_WD, (uint32_t)par_wd);
    m_wr8(FLOOR_CARD + CD_CIROUT, CI_ROUT);
    for (unsigned k = 0; k < NCODES; k++) {
        m_wr8(FLOOR_CMDTAB + 2 * k, cmds[k].kind);
        m_wr8(FLOOR_CMDTAB + 2 * k + 1, cmds[k].kind == CK_FIELD ? field_off(cmds[k].arg) : cmds[k].arg);
    }
}

static const char *const load_mn[] = {"RBS", "RCP", "RFE", "ROUT"};
static uint16_t code_of(const char *mn)
{
    static const struct { const char *mn; uint16_t code; } t[] = {
#define GEN(mn, code, cards, kind, desc) {#mn, code},
#define MODESEL(mn, code, cards, mode, desc) {#mn, code},
#define DIAG(mn, code, cards, units, desc) {#mn, code},
#define PARAM(id, mn, kind, wcode, cards, flags, min, max, def, units, desc)
#include "commands.def"
    };
    for (unsigned i = 0; i < sizeof t / sizeof t[0]; i++)
        if (!strcmp(t[i].mn, mn))
            return t[i].code;
    return 0xFFFF;
}

static void queue_make(uint32_t q, uint32_t front, uint32_t rear)
{
    m_wr32(q + QH_BASE, Q_HEADER_SIZE);
    m_wr32(q + QH_FRONT, front);
    m_wr32(q + QH_REAR, rear);
    m_wr32(q + QH_FREE, rnd());
    m_wr32(q + QH_WIDTH, Q_WIDTH);
    m_wr32(q + QH_NEL, Q_NEL);
}

enum { S_CMD = 10, S_CMD_IDLE };
static unsigned cmd_k;

static void gen_cmd(int scen)
{
    int broad = scen < 0;
    routine_kind = R_COUNTER;
    gen(broad ? -1 : S_MOVING);
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        axes[n].sstat = rnd();
        axes[n].vel = (int32_t)rnd();
    }
    serial_rx_work = serial_fifo_count = 0;
    par_wd = broad && rnd_pct(20) ? -(int32_t)rnd_below(5) : 0;
    cmd_mr = (uint8_t)(broad && rnd_pct(5));
    n_held = 0;
    queue_bad = (uint8_t)rnd_below(2);
    last_valid_axis = (uint8_t)rnd_below(4);
    irq12 = 0;
    motion_vq_due = 0;
    wd_fired = (uint8_t)rnd_below(2);
    card_supervised = card_ticks;
    n_commands = rnd();
    n_rsp_lost = rnd();
    n_queue_errors = rnd();
    memset(fmem + DPRAM_BASE + 0x400, 0, DPRAM_SIZE - 0x400);
    uint32_t rear = rnd_below(Q_NEL), front = rear == Q_NEL - 1 ? 0 : rear + 1;
    if (scen == S_CMD_IDLE || (broad && rnd_pct(10)))
        front = rear;
    queue_make(DP_CMD_QUEUE, front, rear);
    if (broad && rnd_pct(10))
        m_wr32(DP_CMD_QUEUE + (rnd_pct(50) ? QH_WIDTH : rnd_pct(50) ? QH_FRONT : QH_REAR), 10 + rnd_below(5));
    uint32_t e = DP_CMD_QUEUE + Q_HEADER_SIZE + 10 * rear;
    unsigned k = cmd_k++;
    uint16_t code = code_of(load_mn[k % 4]);
    if (broad && rnd_pct(50)) {
        do
            code = (uint16_t)rnd_below(NCODES);
        while (!(cmds[code].kind == CK_FIELD || (cmds[code].kind == CK_DIAG && cmds[code].arg == CI_ROUT)));
    }
    m_wr16(e + MSG_AXIS, (uint16_t)((broad ? rnd_below(4) : (k / 4) % 4) << 8 | (rnd() & 0xFF)));
    m_wr16(e + MSG_CODE, code);
    m_wr32(e + MSG_PARAM, rnd());
    m_wr16(e + MSG_SOURCE, (uint16_t)rnd());
    uint32_t rf = rnd_below(Q_NEL), rr = broad && rnd_pct(10) ? (rf + 1) % Q_NEL : (rf + 2 + rnd_below(8)) % Q_NEL;
    if (rr == rf)
        rr = (rf + 5) % Q_NEL;
    queue_make(DP_RSP_QUEUE, rf, rr);
    if (broad && rnd_pct(5))
        m_wr32(DP_RSP_QUEUE + QH_NEL, 11);
    pack_cmd();
}

static int compare_cmd(char *msg, size_t len)
{
    floor_restore_inputs();
    beyond = 0;
    cmd_poll_ref();
    if (beyond) {
        snprintf(msg, len, "an input beyond the routine's path (ref_stp.c gen_cmd)");
        return 1;
    }
    pack_cmd();
    return floor_compare(msg, len, fields, sizeof fields / sizeof fields[0]);
}

static const routine_t sup_routines[] = {{"stp_supervise", gen_sup, compare_sup, 0, NULL}};
static const scenario_t sup_scenarios[] = {
    {"moving", "stp_supervise", S_MOVING, "four axes positioning, after the SP boundary's tick (the LEDs)", 0},
};
static const module_t sup_module = {"stp", "supervise", sup_routines, 1, sup_scenarios, 1};
static const routine_t cmd_routines[] = {{"stp_cmd", gen_cmd, compare_cmd, 0, NULL}};
static const scenario_t cmd_scenarios[] = {
    {"moving", "stp_cmd", S_CMD,
     "the host's reads in turn (RBS, RCP, RFE, ROUT on axes 1-4): a command pass beyond an idle one", 1 + S_CMD_IDLE},
};
static const module_t cmd_module = {"stp", "command", cmd_routines, 1, cmd_scenarios, 1};

static const routine_t routines[] = {
    {"stp_counter", gen_counter, compare, 1, NULL},
    {"stp_counter_brake", gen_counter, compare, 1, NULL},
    {"stp_encoder", gen_counter, compare, 1, NULL},
    {"stp_ext", gen_ext, compare, 1, NULL},
    {"stp_counter_creep", gen_counter, compare, 1, NULL},
    {"stp_ext_brake", gen_ext, compare, 1, NULL},
};
static const scenario_t scenarios[] = {
    {"moving", "stp_counter", S_MOVING, "the step counter, positioning at 2000 steps/s: the rate of the segment", 0},
    {"creep", "stp_counter_creep", S_CREEP_TWO,
     "the step counter, two creep phases beginning at the SP boundary, two axes moving on (min: four moves starting)", 0},
    {"creep_starts", "stp_counter_creep", S_CREEP,
     "the step counter, four creep phases beginning at the SP boundary: the missing steps to the pulse counter", 0},
    {"braking", "stp_counter_brake", S_BRAKING, "the step counter, the tick's brake at rest: the trim", 0},
    {"external", "stp_ext_brake", S_EXT_BRAKE,
     "VMEbus encoders (<et> 4, 24 bits, increments), the tick's brake ending its ramp at <ssf> (min: the axes standing)", 0},
    {"encoder_loss", "stp_ext", S_MOVING, "VMEbus encoders, positioning (the worst tick comes before the boards go)", 0},
    {"encoder", "stp_encoder", S_ENCODER, "the encoder on the motor (<et> 1): increments to steps, positioning", 0},
    {"ext_table", "stp_counter", S_MOVING, "as moving: the extensions work after the tick", 0},
    {"ext_compare", "stp_counter", S_MOVING, "as moving", 0},
    {"ext_feedback", "stp_counter", S_MOVING, "as moving", 0},
    {"ext", "stp_counter", S_MOVING, "as moving", 0},
};

static const module_t tick_module = {
    "stp", "tick", routines, sizeof routines / sizeof routines[0], scenarios, sizeof scenarios / sizeof scenarios[0],
};
const module_t *const floor_modules[] = {&tick_module, &sup_module, &cmd_module, NULL};
