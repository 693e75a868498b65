/*
 * card.c - reset state, the periodic tick and the main loop.
 * Data flows one way through a tick: position measurement -> the setpoint
 * the profile generator prepared for this tick -> servo filter (STP: step
 * rate) -> outputs.  After it, in the main loop (card_supervise): what the
 * tick did -> switches, stop bits and protective reactions -> status and
 * the published axis data; then the profile generator's next SP, one axis
 * per pass, and the commands.
 */
#include "fw.h"
#include "hal.h"
#include "mul16.h"
#include "card.h"
#include "cmd.h"
#include "params.h"
#include "measure.h"
#include "serial.h"
#include "motion.h"
#include "ext.h"
#if MAC4_CARD == MAC4_CARD_STP
#include "stepper.h"
#endif

axis_t axes[MAC4_NAXES];
axis_t *const axis_at[MAC4_NAXES] = {&axes[0], &axes[1], &axes[2], &axes[3]};
_Static_assert(MAC4_NAXES == 4, "axis_at[] lists four axes");
uint32_t card_ostat;
uint16_t card_err_report;
uint32_t card_ticks;
uint8_t card_servo_general;
static volatile uint8_t estop_seen;   /* set by the level 7 handler */
uint32_t card_supervised;             /* card_ticks at the last card_supervise() */
uint16_t card_supervise_late;         /* ticks the main loop did not supervise in time */

#if MAC4_CARD == MAC4_CARD_STP
#define TICK_US SERVO_PERIOD_US_STP
#else
#define TICK_US SERVO_PERIOD_US_SERVO
#endif

/* ---- VMEbus interrupts (4.6) --------------------------------------------
 * The interrupter holds one request until the host's IACK; more wait here. */
#define VIRQ_FIFO 16u
static uint8_t virq_fifo[VIRQ_FIFO];
static uint8_t virq_head;
volatile uint8_t vme_irq_waiting;      /* virq_tail != virq_head: see vme_irq_service() */
static uint8_t virq_tail;
static uint32_t virq_lost;             /* DPC_VME_IRQ_LOST, kept in RAM (published every tick) */

void vme_irq(uint8_t vector)
{
    if (vector == 0)
        return;                                   /* vector 0: interrupt off */
    unsigned prev = hal_irq_save();
    uint8_t next = (uint8_t)((virq_head + 1u) % VIRQ_FIFO);
    if (next == virq_tail) {
        hal_wr32(DPC_VME_IRQ_LOST, ++virq_lost);
    } else {
        virq_fifo[virq_head] = vector;
        virq_head = next;
        vme_irq_waiting = 1;
    }
    vme_irq_service();
    hal_irq_restore(prev);
}

void vme_irq_service_do(void)
{
    unsigned prev = hal_irq_save();
    if (virq_tail != virq_head && !(hal_rd16(VIRQ_STATUS) & VIRQ_ST_PENDING)) {
        hal_wr16(VIRQ_VECTOR, virq_fifo[virq_tail]);
        virq_tail = (uint8_t)((virq_tail + 1u) % VIRQ_FIFO);
    }
    vme_irq_waiting = virq_tail != virq_head;
    hal_irq_restore(prev);
}

/* ---- axis state ---------------------------------------------------------- */
static void axis_output(unsigned n, int32_t out);
int axis_standstill(unsigned n)
{
    uint8_t m = axes[n].mode;
    if (m == M_DISABLE || m == M_TEST)
        return 1;
    return motion_at_rest(n) && !motion_busy(n) && m != M_SPEED && m != M_VEL_TRACK &&
           m != M_POS_TRACK && !axes[n].stop_then;
}

/* The only writer of an axis' gains, so that card_servo_general always
 * says which axes need the general filter (interrupts masked: motion_start) */
#if MAC4_CARD != MAC4_CARD_STP
void axis_set_gains(unsigned n, const servo_gains_t *g)
{
    axis_at[n]->gains = *g;
    if (g->full)
        card_servo_general |= (uint8_t)(1u << n);
    else
        card_servo_general &= (uint8_t)~(1u << n);
}
#endif

void axis_set_mode(unsigned n, uint8_t mode)
{
    axis_t *x = &axes[n];
    x->mode = mode;
    x->ustat = (x->ustat & ~US_MODE_MASK) | mode;
    if (mode == M_DISABLE) {
        x->ustat &= ~UB(DR_EN);
    } else {
        x->ustat |= UB(DR_EN);
        meas_cfg[n].failed = 0;                   /* the axis runs: a failure counts again (6.3.8) */
    }
#if MAC4_CARD != MAC4_CARD_STP
    /* /EN follows the mode at once (the tick writes only the DAC) */
    x->ctrl = (uint16_t)((x->ctrl & ~AX_CTRL_EN) | (mode != M_DISABLE ? AX_CTRL_EN : 0));
    hal_wr16(AX_REG(n, AX_CTRL), x->ctrl);
#endif
}

void axis_disable(unsigned n)
{
    axis_set_mode(n, M_DISABLE);
    axis_output(n, 0);           /* /EN open, 0 V or no pulses now, not at the next tick */
    axes[n].stop_then = STOP_NONE;
    axes[n].stop_settle = 0;
    axes[n].next_mode = NO_MODE;
}

void axis_error(unsigned n, uint32_t ubit, uint16_t code)
{
    axes[n].ustat |= ubit;
    axes[n].err_report = code;
}

void axis_init_measurement(unsigned n)
{
    measure_init(n);
    axes[n].meas_sup = axes[n].meas;
    ext_axis_init(n);                            /* the extensions follow the new measurement */
}

/* The part of axis_prepare that follows mode parameters (<mf>): all that
 * changes at an E on an initialised axis, since system parameters change
 * only at INIT, which prepares the rest. */
void axis_prepare_mode(unsigned n)
{
    axis_t *x = &axes[n];
    x->mf = PAR(n, MF);
#if MAC4_CARD == MAC4_CARD_STP
    x->mf += stp_tol(n);                         /* 4.8.1: the tolerance of <ms>/(4 <es>) */
#endif
    x->in_eval = 1;                              /* the switches again at the next tick */
}

void axis_prepare(unsigned n)
{
    axis_t *x = &axes[n];
    int32_t et = PAR(n, ET);
    x->linear = PAR(n, SH) == 1;
    x->mk = et > 2 ? MK_OTHER : MAC4_CARD == MAC4_CARD_SSI ? (et == 2 && x->linear ? MK_SSI_ABS : MK_SSI)
                   : et <= 1 ? MK_COUNTER : MK_OTHER;
    x->cr = PAR(n, CR);
    x->lp = PAR(n, LP);
    x->ln = PAR(n, LN);
    axis_prepare_mode(n);
    /* switch configuration (4.5): 0 off, 1 low active, 2 high active */
    static const uint16_t bits[4] = {AX_IN_IESP, AX_IN_IESN, AX_IN_RS, AX_IN_DF};
    int32_t cfg[4] = {PAR(n, PS), PAR(n, NS), PAR(n, RS), PAR(n, DF)};
#if MAC4_CARD == MAC4_CARD_SSI
    /* the SSI receiver reads the encoder at every timer expiry (the
     * sampling instant): the tick finds the value there, or nearly */
    uint16_t sync = et <= 2 ? AX_CTRL_SSI_SYNC : 0;
    x->ctrl = (uint16_t)((x->ctrl & ~AX_CTRL_SSI_SYNC) | sync);
    hal_wr16(AX_REG(n, AX_CTRL), x->ctrl);
#endif
    x->sw_en = x->sw_inv = 0;
    for (unsigned i = 0; i < 4; i++) {
        if (cfg[i])
            x->sw_en |= bits[i];
        if (cfg[i] == 2)
            x->sw_inv |= bits[i];
    }
}

void axis_set_pos(unsigned n)
{
    axis_t *x = &axes[n];
    int32_t pos = pos_add(x->meas, PAR(n, AO));
    if (!x->linear) {
        pos %= x->cr;          /* main loop only: a division is fine here */
        if (pos < 0)
            pos += x->cr;
    }
    x->pos = pos;
}

static void axis_outputs_reset(unsigned n)
{
    /* Tables 2.2, 2.6, 2.12: enable off (/EN open), DAC 0 V or no pulses,
     * DIR and BOOST open collector. */
    axes[n].ctrl = 0;
    axes[n].out = 0;
    hal_wr16(AX_REG(n, AX_CTRL), 0);
    hal_wr16(AX_REG(n, AX_DAC), 0);
}

void card_reset(void)
{
    hal_wr16(TMR_CTRL, 0);
    hal_wr16(UART_CTRL, 0);
    params_reset();
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        axis_outputs_reset(n);
        axis_t *x = &axes[n];
        *x = (axis_t){0};
        x->next_mode = NO_MODE;
        x->mk_tick = MK_NONE;
        x->ustat = UB(ON_FLY);                    /* on-fly after switch-on (5.15) */
        axis_set_mode(n, M_DISABLE);
        motion_hold(n);
#if MAC4_CARD == MAC4_CARD_SSI
        /* J1 (Gray or binary) is readable from basic init on: known before
         * an INIT that comes ahead of the first tick reads the encoder */
        if (hal_rd16(AX_REG(n, AX_IN)) & AX_IN_GRAY)
            x->ustat |= UB(GRAY);
#endif
    }
    hal_wr16(SYS_LEDS, 0x1111);                   /* LED D on for every axis */
    card_ostat = 0;
    card_err_report = 0;
    card_ticks = 0;
    card_servo_general = 0;
    card_profile_due = 0;
    card_profile_late = 0;
    card_supervise_late = 0;
    card_supervised = 0;
    estop_seen = 0;
    virq_head = virq_tail = 0;
    virq_lost = 0;
    vme_irq_waiting = 0;
    cmd_reset();
    serial_reset();
    ext_reset();                                  /* the extensions off (docs/extensions.md) */
}

void card_start(void)
{
    hal_wr16(TMR_PERIOD, TICK_US);
#if MAC4_CARD == MAC4_CARD_SSI
    /* the tick comes when the SSI reads the expiry started are done */
    hal_wr16(TMR_CTRL, TMR_CTRL_RUN | TMR_CTRL_IE | TMR_CTRL_SSI_WAIT);
#else
    hal_wr16(TMR_CTRL, TMR_CTRL_RUN | TMR_CTRL_IE);
#endif
    hal_wr16(UART_CTRL, UART_CTRL_RXIE);
    /* 7.1.2 m_rdy "command operational": the card takes commands for every
     * axis from here (display $5) until a reset; MR clears it (cmd.c) */
    for (unsigned n = 0; n < MAC4_NAXES; n++)
        axes[n].sstat |= SB(M_RDY);
    hal_irq_enable_all();
}

volatile uint8_t card_profile_due;
uint16_t card_profile_late;

/* The profile generator runs in the main loop, one SP ahead of the servo
 * ticks that interpolate its segments: the tick stays short, and the
 * profile has a whole SP to finish (7.4).  One axis per main-loop pass
 * (card_profile_due: how many axes are still to do), so a command waits for
 * one axis' step at most, not four; each with interrupts masked, so a tick
 * never sees half a segment or half a mode change. */
void card_profile_tick(void)
{
    unsigned prev = hal_irq_save();
    uint8_t due = card_profile_due;
    if (due) {
        /* axes in turn: due counts down 4, 3, 2, 1 */
        card_profile_due = (uint8_t)(due - 1u);
        motion_profile_tick(MAC4_NAXES - due);
    }
    hal_irq_restore(prev);
}

/* ---- the tick ------------------------------------------------------------ */
static void stop_bits(void)
{
    /* 3.5.1: bits 1, 3, 5, 7 at $4600; accepted in either byte of the word */
    uint16_t w = hal_rd16(DP_STOP_BITS);
    uint16_t bits = (uint16_t)((w | (w >> 8)) & 0xAAu);
    if (!bits)
        return;
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        if (!(bits & (2u << (2 * n))))
            continue;
        axis_t *x = &axes[n];
        if (x->mode == M_TEST)
            axis_disable(n);                      /* test mode: disable */
        else if (x->mode != M_DISABLE) {
            axis_set_mode(n, M_BRAKE);
            x->next_mode = NO_MODE;
            motion_brake(n);                      /* from the next tick on */
        }
    }
    /* the card clears the bits it acted on, nothing else */
    uint16_t now = hal_rd16(DP_STOP_BITS);
    hal_wr16(DP_STOP_BITS, (uint16_t)(now & ~(bits | (uint16_t)(bits << 8))));
}

/* AX_IN switch bits (IESP, IESN, RS) -> user status bits */
static const uint32_t sw_ustat[8] = {
    0, UB(HWL_P), UB(HWL_N), UB(HWL_P) | UB(HWL_N), UB(REF), UB(REF) | UB(HWL_P),
    UB(REF) | UB(HWL_N), UB(REF) | UB(HWL_P) | UB(HWL_N),
};

static inline __attribute__((always_inline)) void axis_inputs(unsigned n)
{
    axis_t *x = &axes[n];
    PIN_PTR(x);
    uint16_t in = hal_rd16(AX_REG(n, AX_IN));
    /* nothing to do when no input changed, unless a drive fault is active
     * (it acts as soon as the axis runs) or INIT/E reconfigured the switches */
    if (in == x->in && !x->in_eval)
        return;
    x->in = in;
    x->in_eval = 0;
    if (MAC4_CARD == MAC4_CARD_SSI) {             /* J1 is readable from basic init on */
        if (in & AX_IN_GRAY)
            x->ustat |= UB(GRAY);
        else
            x->ustat &= ~UB(GRAY);
    }
    if (!axis_initialised(n))
        return;                                   /* switches count after INIT (4.9) */
    uint16_t active = (uint16_t)((in ^ x->sw_inv) & x->sw_en);
    x->in_eval = (active & AX_IN_DF) != 0;
    uint32_t sw = sw_ustat[active & 7u];
    uint32_t prev = x->ustat;
    x->ustat = (x->ustat & ~(UB(HWL_P) | UB(HWL_N) | UB(REF))) | sw;

    if ((active & AX_IN_DF) && x->mode != M_DISABLE && !(x->ustat & UB(DR_F))) {
        axis_error(n, UB(DR_F), ERR_LOGICAL);     /* 6.3.4 drive fault: ramp <ed>, disable */
        motion_drive_fault(n);
        vme_irq((uint8_t)PAR(n, IRQ3));
    }
    /* 5.13: a limit switch reached in test mode turns the axis off; it can
     * then be driven out of the switch in test mode again (edge, not level) */
    if (x->mode == M_TEST && (sw & ~prev & (UB(HWL_P) | UB(HWL_N))))
        axis_disable(n);
}

static inline __attribute__((always_inline)) void axis_output_at(unsigned n, int32_t out);
static void axis_output(unsigned n, int32_t out) { axis_output_at(n, out); }

static inline __attribute__((always_inline)) void axis_output_at(unsigned n, int32_t out)
{
    axis_t *x = &axes[n];
    PIN_PTR(x);
    uint16_t ctrl = (uint16_t)(x->ctrl & ~AX_CTRL_EN);
    if (x->mode != M_DISABLE)
        ctrl |= AX_CTRL_EN;
#if MAC4_CARD == MAC4_CARD_STP
    /* DIR, BOOST, TURBO and the step rate register, prepared by stepper.c
     * (stepper.h); `out` is not used: the rate is exact to the Q16 step */
    (void)out;
    out = stp_output(n, x->mode, &ctrl);
#endif
    x->ctrl = ctrl;
    x->out = (int16_t)out;
    hal_wr16(AX_REG(n, AX_CTRL), ctrl);
    hal_wr16(AX_REG(n, AX_DAC), (uint16_t)out);
}

static void publish(unsigned n)
{
    const axis_t *x = &axes[n];
    uint32_t d = DP_AXIS_DATA(n);
    hal_wr32(d + DPA_USTAT, x->ustat);
    hal_wr32(d + DPA_SSTAT, x->sstat);
    hal_wr32(d + DPA_POS, (uint32_t)x->pos);
    /* in the frame of the position (with <ao>, 4.3.2), so that setpoint -
     * position is the following error for the host too */
    hal_wr32(d + DPA_SETPOINT, (uint32_t)pos_add(x->pos, x->ferr));
    hal_wr32(d + DPA_FERR, (uint32_t)x->ferr);
#if MAC4_CARD == MAC4_CARD_STP
    hal_wr32(d + DPA_OUT, (uint32_t)stp_hz_now(n));   /* ROUT: Hz */
#else
    hal_wr32(d + DPA_OUT, (uint32_t)(int32_t)x->out);
#endif
    hal_wr32(d + DPA_VEL, (uint32_t)x->vel);
    hal_wr32(d + DPA_RAW, x->raw);
}

/* The LEDs the firmware drives (2.5.3; the limit and reference LEDs follow
 * the input levels in hardware): D disabled, P pos_end, F the drive fault
 * signal as the card recognises it with the polarity <df> in force (UWSO),
 * whatever its level; on the STP F also shows an unacknowledged error
 * (7.1.2 led_fault). */
static void leds(void)
{
    uint16_t l = 0;
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        const axis_t *x = &axes[n];
        if (x->mode == M_DISABLE)
            l |= (uint16_t)(SYS_LED_D << SYS_LED_SHIFT(n));
        if (x->ustat & UB(POS_END))
            l |= (uint16_t)(SYS_LED_P << SYS_LED_SHIFT(n));
        int32_t df = PAR(n, DF);
        int df_on = df != 0 && (((hal_rd16(AX_REG(n, AX_IN)) & AX_IN_DF) != 0) ^ (df == 2));
        if (df_on || (MAC4_CARD == MAC4_CARD_STP && (x->ustat & US_ERRORS)))
            l |= (uint16_t)(SYS_LED_F << SYS_LED_SHIFT(n));
    }
    hal_wr16(SYS_LEDS, l);
}

/* The tick's own braking ramp (motion.c brake_now): the speed of this
 * tick, br_dec closer to 0 ... */
static inline __attribute__((always_inline)) int32_t brake_slower(const axis_t *x)
{
    int32_t v = x->br_v, dv = x->br_dec;
    if (v > 0)
        v = v > dv ? v - dv : 0;
    else if (v < 0)
        v = v < -dv ? v + dv : 0;
    return v;
}

/* ... and the step at that speed. */
static inline __attribute__((always_inline)) void brake_step(axis_t *x, int32_t v)
{
    x->br_v = v;
    x->br_posh += v;
}

/* The tick does only what must happen at the sampling instant (7.4):
 * measure, interpolate the setpoint, filter, drive the outputs.  Everything
 * that looks at the result - switches, protective reactions, stop bits,
 * status, the DPRAM data - is card_supervise() in the main loop, which
 * runs before anything else there once per tick. */
#if MAC4_CARD != MAC4_CARD_STP
/* One axis of the INC/SSI tick.  Inlined four times with a constant n, so
 * the registers are absolute addresses and the axis one address register;
 * ph4 is the tick's phase in the SP times 4 (the row offset in bytes).
 * /EN follows the mode in axis_set_mode(); here only the DAC. */
static inline __attribute__((always_inline)) void tick_axis(unsigned n, unsigned ph4, int general)
{
    axis_t *x = &axes[n];
    PIN_PTR(x);
    uint8_t mk = x->mk_tick;                      /* MK_NONE before INIT (4.9) */
    /* the card's own encoder first: one test on the common path */
#if MAC4_CARD != MAC4_CARD_SSI
    if (mk == MK_COUNTER) {
        measure_apply(x, measure_counter(x, n));
#else
    int32_t d;
    if (mk == MK_SSI_ABS) {                       /* the encoder at the connector, absolute, linear */
        if (measure_ssi(x, n, &d, 1) == 0)
            measure_apply_k(x, d, 1);
    } else if (mk == MK_SSI) {                    /* relative, or a circular axis */
        if (measure_ssi(x, n, &d, 0) == 0)
            measure_apply(x, d);
#endif
    } else if (mk != MK_NONE) {
        measure_ext(x, &meas_cfg[n], n);          /* <et> 3/4 (measure.h) */
    }
    int16_t u = 0;
    uint8_t mode = x->mode;
    if (mode == M_DISABLE) {
        /* setpoint and following error: card_supervise (tick_result) */
    } else if (mode == M_TEST) {
        u = (int16_t)PAR(n, DA);                  /* 5.13: straight to the DAC */
    } else {
        int32_t sp;
        if (!x->braking) {
            sp = *(const int32_t *)(const void *)((const uint8_t *)x->sp_now + ph4);
        } else {                                  /* a stop that cannot wait for the next SP */
            brake_step(x, brake_slower(x));
            sp = brake_setpoint(x);
        }
        int32_t e = pos_sub(sp, x->meas);
        if (general && x->gains.full)             /* card_servo_general: K-only gains without it */
            u = servo_filter(&x->servo, &x->gains, e);
        else
            u = servo_step_k(&x->servo, &x->gains, e);
        if (x->ustat & UB(REV_O))                 /* USR (4.2) */
            u = (int16_t)(u == SERVO_OUT_MIN ? SERVO_OUT_MAX : -u);
    }
    x->out = u;
    hal_wr16(AX_REG(n, AX_DAC), (uint16_t)u);
}

/* The SP boundary for INC/SSI (the STP's is stp_take_segment), inlined
 * with a constant n: 1 if late */
static inline __attribute__((always_inline)) unsigned take_row(unsigned n)
{
    axis_t *x = &axes[n];
    PIN_PTR(x);
    int32_t *row = x->sp_now;
    if (x->nx_ready) {
        x->sp_now = x->sp_next;
        x->sp_next = row;
        x->sp_vel = x->sp_vel_next;
        x->nx_ready = 0;
        return 0;
    }
    if (x->braking)
        return 0;                                 /* the tick brakes by itself */
    row[0] = row[1] = row[2] = row[PROFILE_DIVIDER - 1u];
    x->sp_vel = 0;
    return x->mode != M_DISABLE && x->mode != M_TEST;
}

/* The tick, inlined twice: for K-only gains on every axis (the defaults)
 * and with the general filter inline (card_servo_general) */
static inline __attribute__((always_inline)) void tick(int general)
{
    hal_wr16(TMR_STATUS, TMR_ST_EXPIRED);
    unsigned phase = card_ticks & (PROFILE_DIVIDER - 1u);
    if (phase == 0) {                             /* SP boundary: take the prepared rows */
        card_profile_late = (uint16_t)(card_profile_late + take_row(0) + take_row(1) + take_row(2) +
                                       take_row(3));
        card_profile_due = MAC4_NAXES;
    }
    unsigned ph4 = phase * 4u;
    tick_axis(0, ph4, general);
    tick_axis(1, ph4, general);
    tick_axis(2, ph4, general);
    tick_axis(3, ph4, general);
    card_ticks++;
}

static void __attribute__((noinline)) tick_k_only(void) { tick(0); }
static void __attribute__((noinline)) tick_general(void) { tick(1); }

/* two tail calls: each body saves only the registers it uses */
void fw_isr_tick(void)
{
    if (card_servo_general)
        tick_general();
    else
        tick_k_only();
}
#else
/* The STP's position counter (steps, or encoder increments with BR closed)
 * as the INC's, converted to steps. */
static inline __attribute__((always_inline)) void stp_tick_measure(unsigned n)
{
    axis_t *x = &axes[n];
    PIN_PTR(x);
    uint8_t mk = x->mk_tick;
    if (mk == MK_COUNTER)
        measure_apply(x, measure_steps(x, n, measure_counter(x, n)));
    else if (mk != MK_NONE)                       /* MK_NONE: position reads 0 before INIT (4.9) */
        measure_ext(x, &meas_cfg[n], n);          /* <et> 3/4 (measure.h) */
}

/* At each SP boundary: take the segment the main loop prepared (motion.c,
 * next_segment), split into 32-bit parts, which the tick interpolates in
 * Q16 for the step rate, or hold at the end of the last one; 1 if late.
 * No 64-bit arithmetic here. */
static inline __attribute__((always_inline)) int stp_take_segment(unsigned n)
{
    axis_t *x = &axes[n];
    PIN_PTR(x);
    if (x->braking)
        return 0;                                /* the tick brakes by itself */
    if (x->nx_ready) {
        x->start_i = x->nx_start_i;
        x->start_f = x->nx_start_f;
        x->st_i = x->nx_st_i;
        x->st_f = x->nx_st_f;
        x->end_i = x->nx_end_i;
        x->end_f = x->nx_end_f;
        x->nx_ready = 0;
        return 0;
    }
    x->start_i = x->end_i;
    x->start_f = x->end_f;
    x->st_i = 0;
    x->st_f = 0;
    return x->mode != M_DISABLE && x->mode != M_TEST;
}

/* One axis of the STP tick after its measurement: the setpoint, the step
 * rate (stepper.h), the outputs. */
static inline __attribute__((always_inline)) void stp_tick_axis(unsigned n, unsigned phase)
{
    axis_t *x = &axes[n];
    PIN_PTR(x);
    if (x->mode == M_DISABLE) {
        x->setpoint = x->meas;
        x->ferr = 0;
    } else if (x->mode != M_TEST) {
        /* Setpoint: the SP segment in four steps, integer + Q16 fraction in
         * 32 bits; the segment's start and end are taken exactly from the
         * profile. */
        int32_t old_i = x->sp_i;
        uint16_t old_f = x->sp_f;
        if (x->braking) {                        /* a stop that cannot wait for the next SP */
            int32_t v = brake_slower(x), ssf = x->br_ssf;
            if (v <= ssf && v >= -ssf) {
                /* from <ssf> or less a stepper stops at once (5.14); a ramp step
                 * that would jump from above it to below it ends at <ssf> first */
                int32_t w = x->br_v;
                v = w > ssf ? ssf : w < -ssf ? -ssf : 0;
            }
            brake_step(x, v);
            int32_t i;
            uint16_t f;
            brake_split(x, &i, &f);              /* into locals: they alias nothing */
            x->sp_i = i;
            x->sp_f = f;
        } else if (phase == 3) {
            x->sp_i = x->end_i;
            x->sp_f = x->end_f;
        } else {
            if (phase == 0) {
                x->sp_i = x->start_i;
                x->sp_f = x->start_f;
            }
            uint32_t f = (uint32_t)x->sp_f + x->st_f;
            x->sp_i = pos_add(pos_add(x->sp_i, x->st_i), (int32_t)(f >> 16));
            x->sp_f = (uint16_t)f;
        }
        x->setpoint = pos_add(x->sp_i, x->sp_f >= 0x8000u);
        x->ferr = pos_sub(x->setpoint, x->meas);
        stp_servo(x, n, phase, old_i, old_f);    /* step rate, creep phase, RFE (stepper.h) */
    }
    axis_output_at(n, 0);   /* the step rate and DIR, BOOST, TURBO (stp_output); test mode: <da> in Hz */
}

void fw_isr_tick(void)
{
    hal_wr16(TMR_STATUS, TMR_ST_EXPIRED);
    unsigned phase = card_ticks & (PROFILE_DIVIDER - 1u);
    if (phase == 0) {                             /* SP boundary: take the prepared segments */
        card_profile_late = (uint16_t)(card_profile_late + stp_take_segment(0) + stp_take_segment(1) +
                                       stp_take_segment(2) + stp_take_segment(3));
        card_profile_due = MAC4_NAXES;
    }
    /* four times with a constant n: absolute register addresses, the axis
     * in an address register */
    stp_tick_measure(0);
    stp_tick_axis(0, phase);
    stp_tick_measure(1);
    stp_tick_axis(1, phase);
    stp_tick_measure(2);
    stp_tick_axis(2, phase);
    stp_tick_measure(3);
    stp_tick_axis(3, phase);
    card_ticks++;
}
#endif

/* Main loop, once after every tick (fw_main_step calls it first).  Each
 * axis with interrupts masked, so it sees one tick's results, never half of
 * the next.  A reaction taken here acts within the servo period of the
 * event: axis_disable() opens /EN at once, and a ramp is braked by the tick
 * itself from the next tick on (motion.c, brake_now). */

#if MAC4_CARD != MAC4_CARD_STP
/* The setpoint and following error of the tick in phase ph, as it used
 * them (RCP-side values, the following-error check): the tick itself keeps
 * only what the next tick needs. */
static inline __attribute__((always_inline)) void tick_result(axis_t *x, unsigned ph)
{
    if (x->mode == M_DISABLE) {
        x->setpoint = x->meas;
        x->ferr = 0;
    } else if (x->mode != M_TEST) {
        x->setpoint = x->braking ? brake_setpoint(x) : x->sp_now[ph];
        x->ferr = pos_sub(x->setpoint, x->meas);
    }
}
#endif

/* One axis of card_supervise_tick(), inlined four times with a constant n
 * (absolute register addresses), interrupts masked: what the tick did, the
 * inputs, the protective reactions. */
static inline __attribute__((always_inline)) void supervise_axis(unsigned n, unsigned ph)
{
    unsigned prev = hal_irq_save();
    axis_t *x = &axes[n];
    PIN_PTR(x);
#if MAC4_CARD != MAC4_CARD_STP
    tick_result(x, ph);
#else
    (void)ph;
#endif
    if (x->mk_tick != MK_NONE)                    /* RAV: the tick keeps only meas */
        x->vel = x->meas - x->meas_sup;
    if (x->mk_tick == MK_COUNTER)                 /* RED: the counter path keeps only the counter */
        x->raw = x->counter;
    x->meas_sup = x->meas;
    x->mk_tick = (x->ustat & UB(INIT)) ? x->mk : MK_NONE;
    axis_inputs(n);
    if (!motion_quiet(x))
        motion_supervise(n);
    hal_irq_restore(prev);
}

void card_supervise_tick(void)
{
    uint32_t t = *(volatile uint32_t *)&card_ticks;
    if (t == card_supervised)
        return;
    if (t - card_supervised > 1u)
        card_supervise_late++;
    card_supervised = t;
    uint16_t sys = hal_rd16(SYS_STATUS);
    card_ostat = (card_ostat & ~(uint32_t)(OB(FCODE0) | OB(FCODE1) | OB(FCODE2))) |
                 ((uint32_t)((sys >> SYS_ST_FC_SHIFT) & 7u) << OS_FCODE0);
    if (estop_seen) {                             /* 6.3.5: all axes, no ramp */
        estop_seen = 0;
        for (unsigned n = 0; n < MAC4_NAXES; n++)
            axis_disable(n);
    }
    unsigned phase = (t - 1u) & (PROFILE_DIVIDER - 1u);
    supervise_axis(0, phase);
    supervise_axis(1, phase);
    supervise_axis(2, phase);
    supervise_axis(3, phase);
    stop_bits();             /* after the reactions: a stop they began keeps its <ed> */
    ext_supervise();         /* the extensions' slices due (ext.h): one test while all are off */
    /* One axis' DPRAM data per tick: each is fresh every profile period
     * (10 ms / 32 ms), at a quarter of the cost. */
    unsigned prev = hal_irq_save();
    publish(phase);
    hal_irq_restore(prev);
    if (phase == 0)
        leds();
    hal_wr32(DPC_TICKS, t);
    hal_wr32(DPC_OSTAT, card_ostat);
    hal_wr32(DPC_PROFILE_LATE, card_profile_late);
    hal_wr32(DPC_SUPERVISE_LATE, card_supervise_late);
    /* the counters live in RAM: a host write to them lasts a tick at most */
    hal_wr32(DPC_VME_IRQ_LOST, virq_lost);
    cmd_publish();
    serial_publish(phase);
    vme_irq_service();
}

HAL_ISR void fw_isr_axis(void)
{
    /* The STP's creep phase counts its pulses here (stepper.c).  The index
     * latch is polled by the supervision (the searches); its interrupt is
     * never enabled, so an index request can only be a fault: it is
     * switched off, and the latch the search waits for is left alone. */
    uint16_t pending = hal_rd16(AXIS_IRQ_PENDING);
#if MAC4_CARD == MAC4_CARD_STP
    if (pending & 0x0FF0u)
        stp_isr(pending);                        /* creep phase: step pulses, count done */
#endif
    if (!(pending & 0x000Fu))
        return;
    for (unsigned n = 0; n < MAC4_NAXES; n++)
        if (pending & (1u << n)) {
            axes[n].ctrl = (uint16_t)(axes[n].ctrl & ~AX_CTRL_IDX_IE);
            hal_wr16(AX_REG(n, AX_CTRL), axes[n].ctrl);
        }
}

void fw_isr_estop(void)
{
    /* The hardware has already opened every /EN (2.2.3).  Here only what
     * cannot wait: the report and the interrupt; the tick disables the
     * axes in firmware state. */
    estop_seen = 1;
    card_ostat |= OB(H_STOP);
    card_err_report = ERR_HSTOP;
    vme_irq((uint8_t)PAR(0, IRQ5));
}

/* ---- main loop ----------------------------------------------------------- */
static uint16_t shown = 0xFFFF;

static void display_update(void)
{
    /* Table 2.16: the most serious condition wins. */
    uint16_t d = 5;
    int any_init = 0;
    uint32_t all = 0;
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        any_init |= axis_initialised(n);
        all |= axes[n].ustat;
    }
    if (any_init)
        d = 0;
    if (all & UB(SYN_F))
        d = 9;
    if (all & UB(LIMIT_F))
        d = 7;
    if (all & UB(LOGO_F))
        d = 8;
    if (all & UB(ENCODER_F))
        d = 0xC;
    if (card_ostat & OB(WATCH_F))
        d = 0xD;
    if (card_ostat & OB(H_STOP))
        d = 0xE;
    if (d != shown) {
        shown = d;
        hal_wr16(SYS_DISPLAY, d);
        hal_wr32(DPC_BOOT_STATE, d);
    }
}

void fw_main_step(void)
{
    card_supervise();
    if (!cmd_mr_pending())
        hal_wr16(WDG_KICK, 0);
    if (card_profile_due) {
        card_supervise();   /* the SP boundary's tick first, wherever the tick hit the pass */
        card_profile_tick();
    }
    ext_work();              /* one slice of the extensions' work, if due (ext.h) */
    cmd_poll();
    vme_irq_service();
    display_update();
}

void fw_fault(uint16_t vector, uint32_t pc, uint16_t sr, uint32_t addr)
{
    hal_wr32(DPC_FAULT_VECTOR, vector);
    hal_wr32(DPC_FAULT_PC, pc);
    hal_wr32(DPC_FAULT_SR, sr);
    hal_wr32(DPC_FAULT_ADDR, addr);
    hal_wr32(DPC_FAULT_COUNT, hal_rd32(DPC_FAULT_COUNT) + 1);   /* in the DPRAM: the reset tests the RAM */
    for (unsigned n = 0; n < MAC4_NAXES; n++)
        hal_wr16(AX_REG(n, AX_CTRL), 0);   /* a crashed card drives nothing */
    fw_halt_for_watchdog(0xF, DPC_ERR_EXCEPTION);   /* J11 in: restart (2.1.3) */
}
