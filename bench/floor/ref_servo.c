/*
 * ref_servo.c - the MAC4-INC/SSI servo tick's floor routines against the
 * firmware's C (floorrun.c, bench/floor/README.md).  Compiled once per card
 * (MAC4_CARD) with the firmware's servo.c, measure.c and params.c for the
 * host: the filter is firmware/servo.h itself, the measurement measure.h
 * and measure.c, the brake step tick.h's and the axis-state changes an
 * encoder error makes axis.h's; the tick's glue around them - fw_isr_tick,
 * take_row, tick_axis - is firmware/tick_servo.c's, restated below
 * (tick_servo.c keeps it static).
 */
#include <stdio.h>
#include <string.h>
#include "fw.h"
#include "hal.h"
#include "card.h"
#include "params.h"
#include "measure.h"
#include "motion.h"
#include "cmd.h"
#include "cmd_table.h"
#include "leds.h"
#include "servo_card.h"         /* tick_result, as the supervision uses it */
#include "axis.h"                /* axis_set_mode_at, axis_disable_at; tick.h */
#include <stddef.h>
#include "floor.h"
#include "floorrun.h"

#if MAC4_CARD == MAC4_CARD_STP
#error "ref_servo.c is the INC/SSI tick"
#endif

/* ---- the firmware state the C works on (card.c's globals) ----------------- */
axis_t axes[MAC4_NAXES];
axis_t *const axis_at[MAC4_NAXES] = {&axes[0], &axes[1], &axes[2], &axes[3]};
uint32_t card_ticks;
uint16_t card_profile_late;
volatile uint8_t card_profile_due;
uint8_t card_servo_general;
uint32_t card_ostat;
uint16_t card_err_report;
/* card.c's statics of the supervision, cmd.c's and serial.c's counters it
 * publishes, ext.c's switch */
uint32_t card_supervised;
uint16_t card_supervise_late;
static uint8_t estop_seen, ext_on;
volatile uint8_t vme_irq_waiting;          /* card.h */
uint32_t virq_lost;                         /* card.h */
static uint32_t n_commands, n_rsp_lost, n_queue_errors, serial_stats[8];

/* axis.c's mode changes, the state an encoder error changes
 * (measure_encoder_error): the firmware's own bodies, axis.h */
void axis_set_mode(unsigned n, uint8_t mode) { axis_set_mode_at(&axes[n], n, mode); }
void axis_disable(unsigned n) { axis_disable_at(&axes[n], n); }

void axis_error(unsigned n, uint32_t ubit, uint16_t code)
{
    axes[n].ustat |= ubit;
    axes[n].err_report = code;
}

static int vme_irqs;
void vme_irq(uint8_t vector) { vme_irqs += vector != 0; }   /* the DPRAM path only: never in these inputs */
/* measure_init's, never called here (the inputs set meas_cfg themselves) */
void axis_prepare(unsigned n) { (void)n; }

/* ---- tick_servo.c's tick (INC/SSI) ------------------------------------------
 * The firmware dispatches each axis on its byte servo_path (servo_card.h
 * servo_path_of: IDLE for disabled or test, BRAKE while braking, else RUN or
 * RUN_FULL by gains.full) to one body instantiated per path; the path is a
 * function of the mode, braking and the gains, so the same tick is stated
 * here with those tests made directly. */
/* the tick's brake: tick.h's brake_slower and brake_step */
static void tick_axis(unsigned n, unsigned ph4, int general)
{
    axis_t *x = &axes[n];
    uint8_t mk = x->mk_tick;
#if MAC4_CARD != MAC4_CARD_SSI
    if (mk == MK_COUNTER) {
        measure_apply(x, measure_counter(x, n));
#else
    int32_t d;
    if (mk == MK_SSI_ABS) {
        if (measure_ssi(x, n, &d, 1) == 0)
            measure_apply_k(x, d, 1);
    } else if (mk == MK_SSI) {
        if (measure_ssi(x, n, &d, 0) == 0)
            measure_apply(x, d);
#endif
    } else if (mk != MK_NONE) {
        measure_ext(x, &meas_cfg[n], n);
    }
    int16_t u = 0;
    uint8_t mode = x->mode;
    if (mode == M_DISABLE) {
    } else if (mode == M_TEST) {
        u = (int16_t)PAR(n, DA);
    } else {
        int32_t sp;
        if (!x->braking) {
            sp = *(const int32_t *)(const void *)((const uint8_t *)x->sp_now + ph4);
        } else {
            brake_step(x, brake_slower(x));
            sp = brake_setpoint(x);
        }
        int32_t e = pos_sub(sp, x->meas);
        if (general && x->gains.full)
            u = servo_filter(&x->servo, &x->gains, e);
        else
            u = servo_step_k(&x->servo, &x->gains, e);
        if (x->ustat & UB(REV_O))
            u = (int16_t)(u == SERVO_OUT_MIN ? SERVO_OUT_MAX : -u);
    }
    x->out = u;
    hal_wr16(AX_REG(n, AX_DAC), (uint16_t)u);
}

static unsigned take_row(unsigned n)
{
    axis_t *x = &axes[n];
    int32_t *row = x->sp_now;
    if (x->nx_ready) {
        x->sp_now = x->sp_next;
        x->sp_next = row;
        x->sp_vel = x->sp_vel_next;
        x->nx_ready = 0;
        return 0;
    }
    if (x->braking)
        return 0;
    row[0] = row[1] = row[2] = row[PROFILE_DIVIDER - 1u];
    x->sp_vel = 0;
    return x->mode != M_DISABLE && x->mode != M_TEST;
}

static void tick(int general)
{
    hal_wr16(TMR_STATUS, TMR_ST_EXPIRED);
    unsigned phase = card_ticks & (PROFILE_DIVIDER - 1u);
    if (phase == 0) {
        card_profile_late = (uint16_t)(card_profile_late + take_row(0) + take_row(1) + take_row(2) + take_row(3));
        card_profile_due = MAC4_NAXES;
    }
    unsigned ph4 = phase * 4u;
    tick_axis(0, ph4, general);
    tick_axis(1, ph4, general);
    tick_axis(2, ph4, general);
    tick_axis(3, ph4, general);
    card_ticks++;
}

static void fw_isr_tick_ref(void)
{
    if (card_servo_general)
        tick(1);
    else
        tick(0);
}

/* ---- firmware state <-> the routines' memory (floor.h) --------------------- */
static void w8(unsigned n, unsigned off, uint32_t v) { m_wr8(FLOOR_AX(n) + off, (uint8_t)v); }
static void w16(unsigned n, unsigned off, uint32_t v) { m_wr16(FLOOR_AX(n) + off, (uint16_t)v); }
static void w32(unsigned n, unsigned off, uint32_t v) { m_wr32(FLOOR_AX(n) + off, v); }

static uint32_t row_addr(unsigned n, const int32_t *row)
{
    const axis_t *x = &axes[n];
    unsigned k = row == x->sp_rows[1] ? 1u : 0u;
    if (row != x->sp_rows[k])
        fprintf(stderr, "floorrun: axis %u: a row pointer off the rows\n", n);
    return FLOOR_AX(n) + SV_ROWS + 16u * k;
}

static void pack(void)
{
    memset(fmem + FLOOR_CARD, 0, FLOOR_AX(MAC4_NAXES) - FLOOR_CARD);
    m_wr32(FLOOR_CARD + CD_TICKS, card_ticks);
    m_wr16(FLOOR_CARD + CD_LATE, card_profile_late);
    m_wr8(FLOOR_CARD + CD_DUE, card_profile_due);
    m_wr8(FLOOR_CARD + CD_GENERAL, card_servo_general);
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
        const servo_gains_t *g = &x->gains;
        const servo_state_t *s = &x->servo;
        const meas_cfg_t *c = &meas_cfg[n];
        w32(n, SV_USTAT, x->ustat);
        w8(n, SV_MK, x->mk_tick);
        w8(n, SV_MODE, x->mode);
        w8(n, SV_BRAKING, x->braking);
        w8(n, SV_NXREADY, x->nx_ready);
        w8(n, SV_LINEAR, x->linear);
        w8(n, SV_FULL, g->full);
        w8(n, SV_KISC, g->kisc);
        w8(n, SV_SC, c->sc);
        w16(n, SV_OUT, (uint16_t)x->out);
        w16(n, SV_DA, (uint16_t)PAR(n, DA));
        w32(n, SV_COUNTER, x->counter);
        w32(n, SV_MEAS, (uint32_t)x->meas);
        w32(n, SV_POS, (uint32_t)x->pos);
        w32(n, SV_RAW, x->raw);
        w32(n, SV_CR, (uint32_t)x->cr);
        w32(n, SV_SPNOW, row_addr(n, x->sp_now));
        w32(n, SV_SPNEXT, row_addr(n, x->sp_next));
        w32(n, SV_SPVEL, (uint32_t)x->sp_vel);
        w32(n, SV_SPVELNX, (uint32_t)x->sp_vel_next);
        w32(n, SV_BRPOSH, (uint32_t)((uint64_t)x->br_posh >> 32));
        w32(n, SV_BRPOSH + 4, (uint32_t)x->br_posh);
        w32(n, SV_BRV, (uint32_t)x->br_v);
        w32(n, SV_BRDEC, (uint32_t)x->br_dec);
        w16(n, SV_GA, (uint16_t)g->ga);
        w16(n, SV_ZE, (uint16_t)g->ze);
        w16(n, SV_PO, (uint16_t)g->po);
        w16(n, SV_KI, (uint16_t)g->ki);
        w16(n, SV_GZH, (uint16_t)g->gzh);
        w16(n, SV_GZL, (uint16_t)g->gzl);
        w16(n, SV_KIMASK, (uint16_t)g->ki_mask);
        w16(n, SV_OUTHI, (uint16_t)g->out_hi);
        w16(n, SV_OUTLO, (uint16_t)g->out_lo);
        w16(n, SV_ELIM, (uint16_t)g->e_lim);
        w32(n, SV_U2HI, (uint32_t)g->u2_hi);
        w32(n, SV_U2LO, (uint32_t)g->u2_lo);
        w32(n, SV_ELIML, (uint32_t)(int32_t)g->e_lim);          /* floor: derived with the gains */
        w32(n, SV_ELIM2, 2u * (uint32_t)(int32_t)g->e_lim);
        w32(n, SV_U1, (uint32_t)s->u1);
        w32(n, SV_U2, (uint32_t)s->u2);
        w32(n, SV_U2RES, (uint32_t)s->u2_res);
        w16(n, SV_EPREV, (uint16_t)s->e_prev);
        w16(n, SV_CTRL, x->ctrl);
        w16(n, SV_ERR, x->err_report);
        w8(n, SV_STOPTHEN, x->stop_then);
        w8(n, SV_STOPSETTLE, x->stop_settle);
        w8(n, SV_NEXTMODE, x->next_mode);
        w8(n, SV_PATH, c->path);
        w8(n, SV_ABS, c->abs);
        w8(n, SV_FAILED, c->failed);
        w32(n, SV_MASK, c->mask);
        w32(n, SV_LIM, c->lim);
        w32(n, SV_RANGE, (uint32_t)c->range);
        w32(n, SV_HALF, (uint32_t)c->half);
        w32(n, SV_SIGN, c->sign);
        w32(n, SV_EADDR, c->addr);
        w16(n, SV_PAGE, c->page);
        w8(n, SV_DKIND, c->abs ? (x->linear ? 0 : 1) : 2);               /* floor: at INIT */
        w32(n, SV_SSTAT, x->sstat);
        w32(n, SV_VEL, (uint32_t)x->vel);
        w32(n, SV_SETPOINT, (uint32_t)x->setpoint);
        w32(n, SV_FERR, (uint32_t)x->ferr);
        w32(n, SV_MEASSUP, (uint32_t)x->meas_sup);
        w32(n, SV_MF, (uint32_t)x->mf);
        w32(n, SV_LP, (uint32_t)x->lp);
        w32(n, SV_LN, (uint32_t)x->ln);
        w16(n, SV_IN, x->in);
        w16(n, SV_SWEN, x->sw_en);
        w16(n, SV_SWINV, x->sw_inv);
        w8(n, SV_MKSUP, x->mk);
        w8(n, SV_INEVAL, x->in_eval);
        w8(n, SV_IDXSEEN, x->idx_seen);
        w8(n, SV_DF, (uint32_t)PAR(n, DF));
        w32(n, SV_OUTLOL, (uint32_t)(int32_t)g->out_lo);                  /* floor: with the gains */
        w32(n, SV_OUTSPAN, (uint32_t)((int32_t)g->out_hi - g->out_lo));
        for (unsigned k = 0; k < 2; k++)
            for (unsigned i = 0; i < PROFILE_DIVIDER; i++)
                w32(n, SV_ROWS + 16 * k + 4 * i, (uint32_t)x->sp_rows[k][i]);
    }
}

/* names for the messages */
static const field_t fields[] = {
    {SV_USTAT, 4, "ustat"}, {SV_MK, 1, "mk_tick"}, {SV_MODE, 1, "mode"}, {SV_BRAKING, 1, "braking"},
    {SV_NXREADY, 1, "nx_ready"}, {SV_LINEAR, 1, "linear"}, {SV_FULL, 1, "gains.full"}, {SV_KISC, 1, "kisc"},
    {SV_SC, 1, "sc"}, {SV_OUT, 2, "out"}, {SV_DA, 2, "da"}, {SV_COUNTER, 4, "counter"}, {SV_MEAS, 4, "meas"},
    {SV_POS, 4, "pos"}, {SV_RAW, 4, "raw"}, {SV_CR, 4, "cr"}, {SV_SPNOW, 4, "sp_now"}, {SV_SPNEXT, 4, "sp_next"},
    {SV_SPVEL, 4, "sp_vel"}, {SV_SPVELNX, 4, "sp_vel_next"}, {SV_BRPOSH, 8, "br_posh"}, {SV_BRV, 4, "br_v"},
    {SV_BRDEC, 4, "br_dec"}, {SV_GA, 2, "ga"}, {SV_ZE, 2, "ze"}, {SV_PO, 2, "po"}, {SV_KI, 2, "ki"},
    {SV_GZH, 2, "gzh"}, {SV_GZL, 2, "gzl"}, {SV_KIMASK, 2, "ki_mask"}, {SV_OUTHI, 2, "out_hi"},
    {SV_OUTLO, 2, "out_lo"}, {SV_ELIM, 2, "e_lim"}, {SV_U2HI, 4, "u2_hi"}, {SV_U2LO, 4, "u2_lo"},
    {SV_ELIML, 4, "e_lim (long)"}, {SV_ELIM2, 4, "2 e_lim"}, {SV_U1, 4, "servo.u1"}, {SV_U2, 4, "servo.u2"},
    {SV_U2RES, 4, "servo.u2_res"}, {SV_EPREV, 2, "servo.e_prev"}, {SV_CTRL, 2, "ctrl"}, {SV_ERR, 2, "err_report"},
    {SV_STOPTHEN, 1, "stop_then"}, {SV_STOPSETTLE, 1, "stop_settle"}, {SV_NEXTMODE, 1, "next_mode"},
    {SV_PATH, 1, "path"}, {SV_ABS, 1, "abs"}, {SV_FAILED, 1, "failed"}, {SV_MASK, 4, "mask"}, {SV_LIM, 4, "lim"},
    {SV_RANGE, 4, "range"}, {SV_HALF, 4, "half"}, {SV_SIGN, 4, "sign"}, {SV_EADDR, 4, "addr"},
    {SV_PAGE, 2, "page"}, {SV_DKIND, 1, "delta kind"}, {SV_OUTLOL, 4, "out_lo (long)"},
    {SV_ROWS, 32, "sp_rows"}, {SV_OUTSPAN, 4, "out_hi - out_lo"}, {SV_SSTAT, 4, "sstat"}, {SV_VEL, 4, "vel"},
    {SV_SETPOINT, 4, "setpoint"}, {SV_FERR, 4, "ferr"}, {SV_MEASSUP, 4, "meas_sup"}, {SV_MF, 4, "mf"},
    {SV_LP, 4, "lp"}, {SV_LN, 4, "ln"}, {SV_IN, 2, "in"}, {SV_SWEN, 2, "sw_en"}, {SV_SWINV, 2, "sw_inv"},
    {SV_MKSUP, 1, "mk"}, {SV_INEVAL, 1, "in_eval"}, {SV_IDXSEEN, 1, "idx_seen"}, {SV_DF, 1, "df"},
};

/* ---- inputs ------------------------------------------------------------------ */
enum { R_COUNTER, R_SSI_ABS, R_SSI, R_EXT };
static int routine_kind;

static int32_t rnd_gain(void)
{
    switch (rnd_below(4)) {
    case 0: return 0;
    case 1: return rnd_range(1, 8);
    case 2: return rnd_range(9, 200);
    default: return rnd_range(0, 32767);
    }
}

/* a 32-bit value near base: within span either side, or anywhere */
static int32_t near(int32_t base, int32_t span)
{
    if (rnd_pct(10))
        return (int32_t)rnd();
    return pos_add(base, rnd_range(-span, span));
}

static uint32_t eb_mask(int eb) { return eb >= 32 ? 0xFFFFFFFFu : ((1u << eb) - 1u); }

/* meas_cfg as measure_init derives it for <eb>, <ec>, <et> */
static void cfg_range(meas_cfg_t *c, int eb, uint32_t ec, int abs)
{
    uint32_t lim = eb_mask(eb);
    if (ec > 0 && ec - 1u < lim)
        lim = ec - 1u;
    c->lim = lim;
    c->range = lim < eb_mask(eb) ? (int32_t)(lim + 1u) : 0;
    c->half = c->range >> 1;
    c->abs = (uint8_t)abs;
    c->mask = eb_mask(eb);
    c->sign = eb < 32 ? 1u << (eb - 1) : 0;
}

/* A scenario's motion per tick (10 000 increments/s: 25) and the setpoint
 * rows about the position: following errors within about +-130. */
#define SCEN_STEP_MIN 20
#define SCEN_STEP_MAX 30
#define SCEN_SPAN 100

static int32_t step(int broad)
{
    return broad ? rnd_range(-300, 300) : rnd_range(SCEN_STEP_MIN, SCEN_STEP_MAX);
}

/* scenario numbers (gen's argument) */
enum { S_MOVING, S_CIRCULAR, S_FULL, S_BRAKING, S_LOSS, S_REL_LINEAR };
/* S_LOSS, as perfscen.encoder_loss's window: the boards there until the
 * tick in which all four go (half the samples each way), so that the
 * scenario's floor is its worst tick's, min= the failing tick's */
static int boards_gone;

static void gen_axis(unsigned n, int scen)
{
    axis_t *x = &axes[n];
    meas_cfg_t *c = &meas_cfg[n];
    memset(x, 0, sizeof *x);
    memset(c, 0, sizeof *c);
    int broad = scen < 0;
    /* gains: the scenario's (perfscen.FULL_FILTER, the defaults) or any */
    servo_gains_t g;
    if (broad) {
        int full = rnd_pct(50);
        servo_set_gains(&g, rnd_gain(), full && rnd_pct(70) ? rnd_range(0, 255) : 0,
                        full && rnd_pct(70) ? rnd_range(-255, 255) : 0, full && rnd_pct(70) ? rnd_gain() : 0,
                        rnd_range(0, 15));
        servo_set_limit(&g, full && rnd_pct(50) ? rnd_range(0, 2048) : 2048);
    } else if (scen == S_FULL) {
        servo_set_gains(&g, 40, 128, 10, 41, 8);
        servo_set_limit(&g, 2000);
    } else {
        servo_set_gains(&g, 40, 0, 0, 0, 8);
        servo_set_limit(&g, 2048);
    }
    x->gains = g;
    servo_state_t *s = &x->servo;
    s->e_prev = (int16_t)rnd_range(-g.e_lim, g.e_lim);
    s->u1 = broad ? rnd_range(-SERVO_U1_MAX, SERVO_U1_MAX) : rnd_range(-300000, 300000);
    s->u2 = rnd_range(g.u2_lo, g.u2_hi);
    s->u2_res = (int32_t)(rnd() & (uint32_t)(uint16_t)g.ki_mask);
    if (!broad) {           /* a move the default plant follows: |u| about 8 V at most */
        s->e_prev = (int16_t)rnd_range(-130, 130);
        s->u1 = 64 * 40 * s->e_prev;
        s->u2 = scen == S_FULL ? rnd_range(-50000, 50000) : 0;   /* K only: the integrator at rest */
        s->u2_res = (int32_t)(rnd() & (uint32_t)(uint16_t)g.ki_mask);
    }
    /* mode, measurement kind, flags */
    static const uint8_t modes[] = {M_DISABLE, M_TEST, M_ENABLE, M_POSITIONING, M_BRAKE, M_SPEED, M_HOME};
    x->mode = broad ? modes[rnd_below(sizeof modes)] : M_POSITIONING;
    x->ustat = (broad ? rnd() : 0) & ~(US_MODE_MASK | UB(DR_EN));
    x->ustat |= UB(INIT) | x->mode | (x->mode != M_DISABLE ? UB(DR_EN) : 0);
    if (!broad)
        x->ustat |= MAC4_CARD == MAC4_CARD_SSI ? UB(GRAY) : 0;
    x->braking = (uint8_t)(broad ? rnd_pct(25) : scen == S_BRAKING);
    x->nx_ready = (uint8_t)(broad ? rnd_pct(50) : scen != S_BRAKING);
    x->next_mode = NO_MODE;
    x->ctrl = (uint16_t)((broad ? rnd() & 0xFFFF : 0) | (x->mode != M_DISABLE ? AX_CTRL_EN : 0));
    x->err_report = (uint16_t)(broad && rnd_pct(20) ? 162 : 0);
    x->stop_then = (uint8_t)(broad ? rnd_below(4) : 0);
    x->stop_settle = (uint8_t)(broad ? rnd_below(2) : 0);
    par_a[P_DA][n] = rnd_range(-2048, 2047);
    int linear = broad ? rnd_pct(50) : scen == S_MOVING || scen == S_BRAKING || scen == S_LOSS || scen == S_REL_LINEAR ||
                                       routine_kind == R_EXT;    /* perfscen.external: linear axes */
    x->linear = (uint8_t)linear;
    x->cr = broad ? (rnd_pct(20) ? rnd_range(1, 3000) : rnd_range(1000, INT32_MAX)) : 2000000;
    /* positions */
    x->meas = broad ? (int32_t)rnd() : (int32_t)(1000000 + rnd_below(100000));
    x->pos = linear ? (broad ? (int32_t)rnd() : x->meas) : (int32_t)rnd_below((uint32_t)x->cr);
    x->counter = rnd() & 0xFFFFFFu;
    x->raw = rnd();
    x->out = (int16_t)rnd_range(-2048, 2047);
    /* setpoint rows: near the position (a following error the filter uses,
     * saturating now and then) or anywhere */
    int32_t span = broad ? (rnd_pct(50) ? g.e_lim + 10 : 3 * (int32_t)g.e_lim + 1000) : SCEN_SPAN;
    for (unsigned k = 0; k < 2; k++)
        for (unsigned i = 0; i < PROFILE_DIVIDER; i++)
            x->sp_rows[k][i] = broad ? near(x->meas, span) : pos_add(x->meas, rnd_range(-span, span));
    unsigned k = rnd_below(2);
    x->sp_now = x->sp_rows[k];
    x->sp_next = x->sp_rows[k ^ 1];
    x->sp_vel = (int32_t)rnd();
    x->sp_vel_next = (int32_t)rnd();
    /* the tick's own brake: speed Q16 per tick, deceleration per tick^2 */
    x->br_v = broad ? (rnd_pct(10) ? (int32_t)rnd() : rnd_range(-(30 << 16), 30 << 16)) : 25 << 16;
    x->br_dec = broad ? (rnd_pct(20) ? rnd_range(1, INT32_MAX) : rnd_range(1, 1 << 16)) : 1000;
    /* the measurement */
    int mine = broad ? rnd_pct(85) : 1;
    switch (routine_kind) {
    case R_COUNTER: {
        x->mk_tick = mine ? MK_COUNTER : MK_NONE;
        int16_t d = broad ? (int16_t)rnd() : (int16_t)rnd_range(SCEN_STEP_MIN, SCEN_STEP_MAX);
        m_wr16(AX_REG(n, AX_CNT_LIVE), (uint16_t)(x->counter + (uint32_t)d));
        /* circular: a step that stays within a turn or two (the wrap loops) */
        if (!linear && broad && x->cr < 40000)
            m_wr16(AX_REG(n, AX_CNT_LIVE), (uint16_t)(x->counter + (uint32_t)rnd_range(-x->cr, x->cr)));
        break;
    }
    case R_SSI_ABS:
    case R_SSI: {
        x->mk_tick = mine ? (routine_kind == R_SSI_ABS ? MK_SSI_ABS : MK_SSI) : MK_NONE;
        c->path = EXT_SSI;
        int sc = broad ? (int)rnd_below(26) : 2;
        int eb = broad ? (int)rnd_range(1, 26 - sc) : 24;
        c->sc = (uint8_t)sc;
        /* S_REL_LINEAR: the absolute reading followed as relative, as a
         * compensation table has it (ext_comp.c clears abs) */
        int abs = routine_kind == R_SSI_ABS ? 1 : broad ? rnd_pct(50) : scen != S_REL_LINEAR;
        cfg_range(c, eb, broad && rnd_pct(30) ? rnd_below(eb_mask(eb) < INT32_MAX ? eb_mask(eb) : INT32_MAX) + 1u : 0, abs);
        if (routine_kind == R_SSI_ABS) {
            x->linear = 1;
            linear = 1;
        }
        /* the reading: near the last one (or, absolute and linear, the
         * position), sometimes beyond <ec> */
        uint32_t last = linear && abs ? (uint32_t)x->meas & c->mask : rnd() & c->lim;
        if (!broad) {
            x->meas = (int32_t)(1000000 + rnd_below(100000));
            last = (uint32_t)x->meas;
            x->pos = linear ? x->meas : (int32_t)(last % (uint32_t)x->cr);
            for (unsigned j = 0; j < 2; j++)
                for (unsigned i = 0; i < PROFILE_DIVIDER; i++)
                    x->sp_rows[j][i] = pos_add(x->meas, rnd_range(-SCEN_SPAN, SCEN_SPAN));
        }
        x->counter = last;
        if (!linear && abs) {
            /* circular absolute: the reading goes round with the axis */
            x->counter = last % (uint32_t)x->cr;
        }
        /* anywhere only on a linear axis: on a circular one the position
         * would wrap for as many turns (measure_apply's loops) */
        uint32_t now = broad && linear && rnd_pct(10) ? rnd() & c->mask
                                                      : (last + (uint32_t)step(broad)) & c->mask;
        if (!linear && abs)
            now = (uint32_t)(x->counter + (uint32_t)step(broad)) % (uint32_t)x->cr;
        if (broad && rnd_pct(5) && (linear || c->lim < c->mask))
            now = c->lim + 1u + rnd_below(c->mask - c->lim);   /* beyond <ec>: an encoder error */
        if (broad && rnd_pct(5) && linear)
            now = c->lim + (c->lim < c->mask ? rnd_below(2) : 0);   /* on <ec>'s bound */
        uint32_t code = now;
        if (x->ustat & UB(GRAY))
            code = now ^ (now >> 1);             /* the encoder sends Gray */
        uint32_t frame = (code << sc) | (broad ? rnd() & ((1u << sc) - 1u) : 0);
        if (broad && rnd_pct(20))
            frame |= rnd() & ~((c->mask << sc) | ((1u << sc) - 1u));   /* bits above <eb>: masked */
        m_wr16(AX_REG(n, AX_SSI_HI), (uint16_t)(frame >> 16));
        m_wr16(AX_REG(n, AX_SSI_LO), (uint16_t)frame);
        m_wr16(AX_REG(n, AX_IN), (uint16_t)(rnd() & ~AX_IN_SSI_BUSY));
        dev.ssi_busy[n] = broad && rnd_pct(10) ? rnd_below(5) : 0;
        if (broad && rnd_pct(2))
            dev.ssi_busy[n] = 199 + rnd_below(4);    /* about the poll's bound */
        c->failed = (uint8_t)(broad ? rnd_pct(30) : 0);
        break;
    }
    case R_EXT: {
        x->mk_tick = mine ? MK_OTHER : MK_NONE;
        int eb = broad ? (int)rnd_range(17, 32) : 24;
        int abs = broad ? rnd_pct(60) : 1;
        cfg_range(c, eb, broad && rnd_pct(30) ? rnd_below(eb_mask(eb) < INT32_MAX ? eb_mask(eb) : INT32_MAX) + 1u : 0, abs);
        uint32_t ea = 0x80C000u + 0x10u * n;
        if (broad && rnd_pct(30))
            ea = (rnd() & 0xFFFFFCu) | (rnd_pct(50) ? 0 : 0);
        c->path = broad && rnd_pct(5) ? EXT_NONE : EXT_VME32;
        c->page = (uint16_t)(ea >> 20);
        c->addr = VME_WIN_BASE + (ea & (VME_WIN_SIZE - 1u));
        if ((ea & (VME_WIN_SIZE - 1u)) > VME_WIN_SIZE - 4u) {  /* measure_ea_ok refuses it */
            ea &= ~0xFFu;
            c->addr = VME_WIN_BASE + (ea & (VME_WIN_SIZE - 1u));
        }
        uint32_t last = linear && abs ? (uint32_t)x->meas : rnd();
        if (!broad) {
            x->meas = (int32_t)(100000 + rnd_below(100000));
            last = (uint32_t)x->meas;
            x->pos = x->meas;
            for (unsigned j = 0; j < 2; j++)
                for (unsigned i = 0; i < PROFILE_DIVIDER; i++)
                    x->sp_rows[j][i] = pos_add(x->meas, rnd_range(-SCEN_SPAN, SCEN_SPAN));
        }
        x->counter = last & c->mask;
        if (x->counter > c->lim)                 /* the last reading was a valid one */
            x->counter %= c->lim + 1u;
        uint32_t now = (x->counter + (uint32_t)step(broad)) & c->mask;
        if (!linear && abs) {                    /* the reading goes round with the axis */
            x->counter = (last & c->mask) % (uint32_t)x->cr;
            now = (uint32_t)(x->counter + (uint32_t)step(broad)) % (uint32_t)x->cr;
        }
        if (broad && linear && rnd_pct(10))
            now = rnd();
        if (broad && linear && rnd_pct(5))
            now = c->lim + (c->lim < c->mask ? rnd_below(2) : 0);   /* on <ec>'s bound */
        int present = broad ? rnd_pct(85) : !(scen == S_LOSS && boards_gone);
        dev.vme_boards[n].a24 = present ? ea : 0;
        dev.vme_boards[n].value = now | (broad ? rnd() & ~c->mask : 0);
        c->failed = (uint8_t)(broad ? rnd_pct(30) : 0);
        break;
    }
    }
    /* the brake's setpoint near the position the measurement leaves */
    x->br_posh = ((int64_t)x->meas << 16) + BR_HALF + (broad ? (int64_t)(int32_t)rnd() : 12345 << 4);
    if (broad && rnd_pct(10))
        x->br_posh = (int64_t)((uint64_t)rnd() << 32 | rnd());
}

/* Aim an axis of the counter routines at a bound: the setpoint at the
 * following error's limit (or one beyond), and u2 so that the output, or
 * the integrator before its bound, lands on either side of a limit - the
 * filter's macros are the same in every routine. */
static void aim(unsigned n)
{
    axis_t *x = &axes[n];
    if (x->mk_tick != MK_COUNTER || x->mode == M_DISABLE || x->mode == M_TEST || x->braking)
        return;
    int32_t d = (int16_t)(uint16_t)(m_rd16(AX_REG(n, AX_CNT_LIVE)) - (uint16_t)x->counter);
    int32_t meas = pos_add(x->meas, d), lim = x->gains.e_lim;
    static const int32_t es[] = {0, 1, -1, 0, 0};
    int32_t e = rnd_pct(50) ? rnd_range(-lim - 1, lim + 1) : (rnd_pct(50) ? 1 : -1) * (lim + es[rnd_below(5)]);
    for (unsigned k = 0; k < 2; k++)
        for (unsigned i = 0; i < PROFILE_DIVIDER; i++)
            x->sp_rows[k][i] = pos_add(meas, e);
    const servo_gains_t *g = &x->gains;
    servo_state_t s2 = x->servo;
    int full = g->full != 0;
    int32_t inc = 0;
    if (full) {
        servo_filter(&s2, g, e);
        if (g->ki)
            inc = (x->servo.u2_res + (int32_t)g->ki * x->servo.e_prev) >> g->kisc;
    } else {
        servo_step_k(&s2, g, e);
    }
    int32_t t;                       /* u2 + the integrator's step, before its bound */
    switch (rnd_below(full ? 6 : 4)) {
    case 0: t = (g->out_hi + 1) * 256 - 1 - 128 - s2.u1; break;
    case 1: t = (g->out_hi + 1) * 256 - 128 - s2.u1; break;
    case 2: t = g->out_lo * 256 - 1 - 128 - s2.u1; break;
    case 3: t = g->out_lo * 256 - 128 - s2.u1; break;
    case 4: t = g->u2_hi + (int32_t)rnd_below(2); break;
    default: t = g->u2_lo - (int32_t)rnd_below(2); break;
    }
    int32_t u2 = t - inc;
    if (u2 >= g->u2_lo && u2 <= g->u2_hi)
        x->servo.u2 = u2;
}

static void gen(int scen)
{
    memset(&dev, 0, sizeof dev);
    memset(fmem + IO_BASE, 0, 0x2000);
    card_servo_general = 0;
    int all_k = scen < 0 && rnd_pct(30);
    boards_gone = scen == S_LOSS && rnd_pct(50);
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        gen_axis(n, scen);
        if (all_k && axes[n].gains.full)
            servo_set_gains(&axes[n].gains, axes[n].gains.ga, 0, 0, 0, axes[n].gains.kisc);
        if (axes[n].gains.full)
            card_servo_general |= (uint8_t)(1u << n);
        if (scen < 0 && routine_kind == R_COUNTER && rnd_pct(40))
            aim(n);
    }
    /* the worst tick: the SP boundary (phase 0) */
    card_ticks = scen < 0 ? rnd() : 4000u + 4u * rnd_below(1000);
    card_profile_late = (uint16_t)rnd();
    card_profile_due = (uint8_t)rnd_below(5);
    dev.vme_page = (uint16_t)rnd_below(16);
    dev.vme_berr = (uint16_t)(scen < 0 ? rnd_pct(20) : 0);
    m_wr16(VME_PAGE, dev.vme_page);
    m_wr16(TMR_STATUS, 0);
    pack();
}

static int compare(char *msg, size_t len)
{
    floor_restore_inputs();
    fw_isr_tick_ref();
    pack();
    return floor_compare(msg, len, fields, sizeof fields / sizeof fields[0]);
}

#define GEN_FOR(kind) static void __attribute__((unused)) gen_##kind(int scen) { routine_kind = kind; gen(scen); }
GEN_FOR(R_COUNTER)
GEN_FOR(R_SSI_ABS)
GEN_FOR(R_SSI)
GEN_FOR(R_EXT)

/* ---- the supervision after a tick (supervise.c card_supervise_tick), on the
 * path of its floor routine (sup.inc): what lies beyond it is not an
 * input of these (beyond is set if one is) ---------------------------- */
static int beyond;

/* tick_result: the firmware's own (servo_card.h, included above). */

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
    if (MAC4_CARD == MAC4_CARD_SSI) {
        if (in & AX_IN_GRAY)
            x->ustat |= UB(GRAY);
        else
            x->ustat &= ~UB(GRAY);
    }
    if (!axis_initialised(n))
        return;
    uint16_t active = (uint16_t)((in ^ x->sw_inv) & x->sw_en);
    x->in_eval = (active & AX_IN_DF) != 0;
    uint32_t sw = sw_ustat[active & 7u];
    uint32_t prev = x->ustat;
    x->ustat = (x->ustat & ~(UB(HWL_P) | UB(HWL_N) | UB(REF))) | sw;
    if ((active & AX_IN_DF) && x->mode != M_DISABLE && !(x->ustat & UB(DR_F)))
        beyond = 1;                               /* the drive fault's reaction (motion.c) */
    if (x->mode == M_TEST && (sw & ~prev & (UB(HWL_P) | UB(HWL_N))))
        beyond = 1;                               /* axis_disable */
}

static void supervise_axis(unsigned n, unsigned ph)
{
    unsigned prev = hal_irq_save();
    axis_t *x = &axes[n];
    tick_result(x, ph);
    if (x->mk_tick != MK_NONE)
        x->vel = x->meas - x->meas_sup;
    if (x->mk_tick == MK_COUNTER)
        x->raw = x->counter;
    x->meas_sup = x->meas;
    x->mk_tick = (x->ustat & UB(INIT)) ? x->mk : MK_NONE;
    axis_inputs(n);
    if (!motion_quiet(x))
        beyond = 1;                               /* motion_supervise */
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
    hal_wr32(d + DPA_OUT, (uint32_t)(int32_t)x->out);
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
    supervise_axis(0, phase);
    supervise_axis(1, phase);
    supervise_axis(2, phase);
    supervise_axis(3, phase);
    uint16_t w = hal_rd16(DP_STOP_BITS);                    /* stop_bits */
    if ((w | (w >> 8)) & 0xAAu)
        beyond = 1;
    if (ext_on)
        beyond = 1;                                         /* ext_supervise */
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
    hal_wr32(DPC_COMMANDS, n_commands);                     /* cmd_publish */
    hal_wr32(DPC_RSP_LOST, n_rsp_lost);
    hal_wr32(DPC_QUEUE_ERRORS, n_queue_errors);
    unsigned i = 2u * (phase & 3u);                         /* serial_publish */
    hal_wr32(DPC_SERIAL_RX_OK + 4u * i, serial_stats[i]);
    hal_wr32(DPC_SERIAL_RX_OK + 4u * (i + 1u), serial_stats[i + 1u]);
    if (vme_irq_waiting)
        beyond = 1;                                         /* vme_irq_service_do */
}

/* a tick's state (gen) as the supervision finds it, on its routine's path */
static void gen_sup(int scen)
{
    routine_kind = MAC4_CARD == MAC4_CARD_SSI ? R_SSI_ABS : R_COUNTER;
    gen(scen);
    int broad = scen < 0;
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        axis_t *x = &axes[n];
        x->braking = 0;
        x->ustat &= ~(UB(HWL_P) | UB(HWL_N) | UB(SWL_P) | UB(SWL_N) | UB(POS_END));
        x->ustat |= broad && rnd_pct(50) ? UB(POS_END) : 0;
        x->ustat &= broad && rnd_pct(10) ? ~UB(INIT) : ~0u;
        x->sstat = rnd();
        x->mk = MAC4_CARD == MAC4_CARD_SSI ? MK_SSI_ABS : MK_COUNTER;
        x->mk_tick = broad && rnd_pct(15) ? MK_NONE : x->mk;
        x->meas_sup = broad ? (int32_t)rnd() : x->meas - 25;
        x->vel = (int32_t)rnd();
        x->setpoint = (int32_t)rnd();
        x->ferr = (int32_t)rnd();
        x->stop_settle = 0;
        /* the following error the tick used, within <mf> (or on it) */
        unsigned ph = (card_ticks - 1u) & 3u;
        int32_t f = x->mode == M_DISABLE ? 0 : x->mode == M_TEST ? x->ferr : pos_sub(x->sp_now[ph], x->meas);
        int32_t af = f < 0 ? -f : f;
        x->mf = af == INT32_MIN ? INT32_MAX : af + (broad ? (int32_t)rnd_below(3) * (rnd_pct(50) ? 1 : 1000) : 1000);
        /* within the software limits (or on them) */
        x->lp = pos_add(x->pos, broad ? (int32_t)rnd_below(3) * (rnd_pct(50) ? 1 : 100000) : 100000);
        x->ln = pos_sub(x->pos, broad ? (int32_t)rnd_below(3) * (rnd_pct(50) ? 1 : 100000) : 100000);
        if (x->lp < x->pos || x->ln > x->pos) {
            x->lp = INT32_MAX;
            x->ln = INT32_MIN;
        }
        /* the switches: configured, the reference active at times, no limit,
         * no drive fault; the inputs changed (an index pulse, the reference
         * switch) or not */
        x->sw_en = (uint16_t)((broad ? rnd() : 0xF) & (AX_IN_IESP | AX_IN_IESN | AX_IN_RS | AX_IN_DF));
        x->sw_inv = (uint16_t)(rnd() & x->sw_en);
        uint16_t in = (uint16_t)(rnd() & 0x7FF & ~AX_IN_SSI_BUSY);   /* (busy: the device model's) */
        in = (uint16_t)((in & ~(AX_IN_IESP | AX_IN_IESN | AX_IN_DF)) | (x->sw_inv & (AX_IN_IESP | AX_IN_IESN | AX_IN_DF)));
        if (!broad)
            in = (uint16_t)(in & ~AX_IN_GRAY) | (MAC4_CARD == MAC4_CARD_SSI ? AX_IN_GRAY : 0);
        /* the scenario: the INC's encoders' index pulses change the inputs
         * (their evaluation), the SSI's absolute encoders have none */
        int same = broad ? rnd_pct(40) : MAC4_CARD == MAC4_CARD_SSI;
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
    if (!broad)
        card_ticks = 4001u + 4u * rnd_below(1000);      /* after an SP boundary's tick: the LEDs too */
    m_wr16(SYS_STATUS, (uint16_t)rnd());
    memset(fmem + DPRAM_BASE + 0x400, 0, DPRAM_SIZE - 0x400);
    m_wr16(DP_STOP_BITS, (uint16_t)(rnd() & 0x5555u));      /* the even bits are not stop bits */
    pack();
}

static int compare_sup(char *msg, size_t len)
{
    floor_restore_inputs();
    beyond = 0;
    card_supervise_tick_ref();
    if (beyond) {
        snprintf(msg, len, "an input beyond the routine's path (ref_servo.c gen_sup)");
        return 1;
    }
    pack();
    return floor_compare(msg, len, fields, sizeof fields / sizeof fields[0]);
}

static const routine_t sup_routines[] = {
    {MAC4_CARD == MAC4_CARD_INC ? "inc_supervise" : "ssi_supervise", gen_sup, compare_sup, 0, NULL},
};
static const scenario_t sup_scenarios[] = {
    {"moving", MAC4_CARD == MAC4_CARD_INC ? "inc_supervise" : "ssi_supervise", S_MOVING,
     MAC4_CARD == MAC4_CARD_INC ? "four axes positioning, an index pulse on each, after the SP boundary's tick (the LEDs)"
                                : "four axes positioning, after the SP boundary's tick (the LEDs)", 0},
};
static const module_t sup_module = {
    MAC4_CARD == MAC4_CARD_INC ? "inc" : "ssi", "supervise", sup_routines, 1, sup_scenarios, 1,
};

/* ---- the command path (cmd.c cmd_poll and what it calls), on the path
 * of its floor routine (cmd.inc): the VME host's reads ------------------- */
/* cmd.c's table, restated: code -> kind and argument */
#define DIAG_FIELD(f) CK_FIELD, offsetof(axis_t, f)
#define DIAG_RCP  DIAG_FIELD(pos)
#define DIAG_RCPI DIAG_FIELD(counter)
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

/* the record's offset of a CK_FIELD (floor: the table with the routine's offsets) */
static uint8_t field_off(uint8_t host)
{
    static const struct { size_t host; uint8_t fl; } map[] = {
        {offsetof(axis_t, pos), SV_POS}, {offsetof(axis_t, counter), SV_COUNTER}, {offsetof(axis_t, raw), SV_RAW},
        {offsetof(axis_t, ferr), SV_FERR}, {offsetof(axis_t, vel), SV_VEL}, {offsetof(axis_t, ustat), SV_USTAT},
        {offsetof(axis_t, sstat), SV_SSTAT},
    };
    for (unsigned i = 0; i < sizeof map / sizeof map[0]; i++)
        if (map[i].host == host)
            return map[i].fl;
    fprintf(stderr, "floorrun: a CK_FIELD of no known field\n");
    return 0xFF;
}

static uint8_t serial_rx_work, serial_fifo_count, wd_fired, n_held, queue_bad, last_valid_axis, irq12;
uint8_t cmd_mr;                               /* cmd.h */
uint8_t motion_vq_due;
static int32_t par_wd;

static void cmd_poll_ref(void)
{
    if (serial_rx_work)
        beyond = 1;                                 /* serial_poll_work */
    if (par_wd > 0)
        beyond = 1;                                 /* watchdog_check */
    if (cmd_mr)
        return;
    if (n_held)
        beyond = 1;                                 /* release_held */
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
                beyond = 1;                         /* interrupt 1 */
        }
    }
    if (!have)
        return;
    /* must_wait: a read never waits; the read itself (cmd_execute) */
    cmd_t c = in.code < NCODES ? cmds[in.code] : (cmd_t){CK_NONE, 0};
    if (!kind_is_read(c.kind) || in.axis >= MAC4_NAXES)
        beyond = 1;                                 /* the other commands, 160 */
    if (beyond)
        return;
    mac4_msg_t out = {0, 0, 0, 0};
    unsigned prev = hal_irq_save();
    if (card_ticks != card_supervised)
        beyond = 1;                                 /* card_supervise_tick first */
    out.axis = in.axis;
    out.source = in.source;
    out.code = in.code;
    wd_fired = 0;
    last_valid_axis = in.axis;
    const axis_t *x = axis_at[in.axis];
    if (c.kind == CK_FIELD)
        out.param = *(const uint32_t *)(const void *)((const uint8_t *)x + c.arg);
    else if (c.kind == CK_DIAG && c.arg == CI_ROUT)
        out.param = (uint32_t)(int32_t)x->out;     /* cmd_read_value */
    else
        beyond = 1;
    hal_irq_restore(prev);
    hal_wr32(DPC_COMMANDS, ++n_commands);
    if (motion_vq_due)
        beyond = 1;                                 /* motion_after_command_do */
    if (q_put_at(DP_RSP_QUEUE, out.axis, out.code, out.param, MSG_SRC_VME) != Q_OK) {
        hal_wr32(DPC_RSP_LOST, ++n_rsp_lost);
        return;
    }
    if (irq12 & 2u)
        beyond = 1;                                 /* interrupt 2 */
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

/* the host's reads in turn, as perf host-load sends them */
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

enum { S_CMD, S_CMD_IDLE };
static unsigned cmd_k;

static void gen_cmd(int scen)
{
    int broad = scen < 0;
    routine_kind = MAC4_CARD == MAC4_CARD_SSI ? R_SSI_ABS : R_COUNTER;
    gen(broad ? -1 : S_MOVING);
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        axes[n].sstat = rnd();
        axes[n].vel = (int32_t)rnd();
        axes[n].ferr = (int32_t)rnd();
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
    /* the command queue: one command waiting (or none, a corrupt header) */
    uint32_t rear = rnd_below(Q_NEL), front = rear == Q_NEL - 1 ? 0 : rear + 1;
    if (scen == S_CMD_IDLE || (broad && rnd_pct(10)))
        front = rear;
    queue_make(DP_CMD_QUEUE, front, rear);
    if (broad && rnd_pct(10))
        m_wr32(DP_CMD_QUEUE + (rnd_pct(50) ? QH_WIDTH : rnd_pct(50) ? QH_FRONT : QH_REAR), 10 + rnd_below(5));
    uint32_t e = DP_CMD_QUEUE + Q_HEADER_SIZE + 10 * rear;
    unsigned k = cmd_k++;
    uint16_t code = code_of(load_mn[k % 4]);
    if (broad && rnd_pct(50)) {               /* any read of a field, or ROUT */
        do
            code = (uint16_t)rnd_below(NCODES);
        while (!(cmds[code].kind == CK_FIELD || (cmds[code].kind == CK_DIAG && cmds[code].arg == CI_ROUT)));
    }
    m_wr16(e + MSG_AXIS, (uint16_t)((broad ? rnd_below(4) : (k / 4) % 4) << 8 | (rnd() & 0xFF)));
    m_wr16(e + MSG_CODE, code);
    m_wr32(e + MSG_PARAM, rnd());
    m_wr16(e + MSG_SOURCE, (uint16_t)rnd());
    /* the response queue: room (or full, a corrupt header) */
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
        snprintf(msg, len, "an input beyond the routine's path (ref_servo.c gen_cmd)");
        return 1;
    }
    pack_cmd();
    return floor_compare(msg, len, fields, sizeof fields / sizeof fields[0]);
}

static const routine_t cmd_routines[] = {
    {MAC4_CARD == MAC4_CARD_INC ? "inc_cmd" : "ssi_cmd", gen_cmd, compare_cmd, 0, NULL},
};
static const scenario_t cmd_scenarios[] = {
    {"moving", MAC4_CARD == MAC4_CARD_INC ? "inc_cmd" : "ssi_cmd", S_CMD,
     "the host's reads in turn (RBS, RCP, RFE, ROUT on axes 1-4): a command pass beyond an idle one", 1 + S_CMD_IDLE},
};
static const module_t cmd_module = {
    MAC4_CARD == MAC4_CARD_INC ? "inc" : "ssi", "command", cmd_routines, 1, cmd_scenarios, 1,
};

#if MAC4_CARD == MAC4_CARD_INC
static const routine_t routines[] = {
    {"inc_counter", gen_R_COUNTER, compare, 1, NULL},
    {"inc_counter_circ", gen_R_COUNTER, compare, 1, NULL},
    {"inc_counter_brake", gen_R_COUNTER, compare, 1, NULL},
    {"inc_ext", gen_R_EXT, compare, 1, NULL},
};
static const scenario_t scenarios[] = {
    {"moving", "inc_counter", S_MOVING, "counter, linear, K only", 0},
    {"circular", "inc_counter_circ", S_CIRCULAR, "counter, circular, K only", 0},
    {"full", "inc_counter_circ", S_FULL, "counter, circular, the general filter and <sw>", 0},
    {"external", "inc_ext", S_MOVING, "VMEbus encoders (<et> 4, 24 bits), linear, K only", 0},
    {"external_full", "inc_ext", S_FULL, "VMEbus encoders, the general filter and <sw>", 0},
    {"braking", "inc_counter_brake", S_BRAKING, "counter, linear, the tick's own brake, K only", 0},
    {"encoder_loss", "inc_ext", S_LOSS, "VMEbus encoders, linear, K only: the ticks before all four fail, and the one they fail in", 0},
    {"ext_table", "inc_counter", S_MOVING, "as moving: the extensions work after the tick", 0},
    {"ext_compare", "inc_counter", S_MOVING, "as moving", 0},
    {"ext_feedback", "inc_counter", S_MOVING, "as moving", 0},
};
#else
static const routine_t routines[] = {
    {"ssi_abs", gen_R_SSI_ABS, compare, 1, NULL},
    {"ssi_abs_brake", gen_R_SSI_ABS, compare, 1, NULL},
    {"ssi_rel", gen_R_SSI, compare, 1, NULL},
    {"ssi_rel_circ", gen_R_SSI, compare, 1, NULL},
    {"ssi_ext", gen_R_EXT, compare, 1, NULL},
};
static const scenario_t scenarios[] = {
    {"moving", "ssi_abs", S_MOVING, "SSI absolute, linear (MK_SSI_ABS), Gray, K only", 0},
    {"circular", "ssi_rel_circ", S_CIRCULAR, "SSI absolute, circular (MK_SSI), Gray, K only", 0},
    {"full", "ssi_rel_circ", S_FULL, "SSI absolute, circular, Gray, the general filter and <sw>", 0},
    {"external", "ssi_ext", S_MOVING, "VMEbus encoders (<et> 4, 24 bits), linear, K only", 0},
    {"external_full", "ssi_ext", S_FULL, "VMEbus encoders, the general filter and <sw>", 0},
    {"braking", "ssi_abs_brake", S_BRAKING, "SSI absolute, linear, the tick's own brake, K only", 0},
    {"encoder_loss", "ssi_ext", S_LOSS, "VMEbus encoders, linear, K only: the ticks before all four fail, and the one they fail in", 0},
    {"ext_table", "ssi_rel", S_REL_LINEAR, "SSI absolute followed as relative (MK_SSI), linear, K only", 0},
    {"ext_compare", "ssi_abs", S_MOVING, "as moving", 0},
    {"ext_feedback", "ssi_rel", S_REL_LINEAR, "as ext_table", 0},
};
#endif

static const module_t tick_module = {
    MAC4_CARD == MAC4_CARD_INC ? "inc" : "ssi", "tick", routines, sizeof routines / sizeof routines[0],
    scenarios, sizeof scenarios / sizeof scenarios[0],
};
const module_t *const floor_modules[] = {&tick_module, &sup_module, &cmd_module, NULL};
