/*
 * axisboard.c - the axis interface boards of the MAC4-INC/SSI/STP (registers
 * in hal/mac4_map.h, "Axis board"): the position counter chip with its index
 * latch, the SSI receiver, the DAC or the step generator with its pulse
 * down-counter, the switch inputs.  A device of periph.c's table.
 *
 * What is wired to a board is the plant (plant.c: motor and drive, encoder,
 * switches; plant_vme.c: the VME slave boards), reached through the lines of
 * plant.h's "wires" section only: the board drives /EN, DIR, BOOST, the DAC
 * and the step pulses, and samples the encoder, the SSI data and the switch
 * levels.  Every access brings the plant up to the cycle it happens
 * (sim_axis_now); the timer's expiry reaches the SSI receivers as the signal
 * timer.expired, and each receiver tells the timer how long it reads
 * (axis.ssi_busy).
 */
#include "sim.h"
#include "periph.h"
#include "plant.h"
#include "plant_math.h"
#include "vcd.h"

#define CNT_MASK 0xFFFFFFu

static int is_stp(sim_t *s) { return s->card == MAC4_CARD_STP; }
static int is_ssi(sim_t *s) { return s->card == MAC4_CARD_SSI; }
static uint32_t mask24(int64_t v) { return (uint32_t)((uint64_t)v & CNT_MASK); }

/* ======================================================================== */
/* the lines the board drives                                                */
/* ======================================================================== */
/* /EN: closed by AX_CTRL_EN, opened by /STOP (sys.stop) */
int axb_en(sim_t *s, int n) { return (s->ax[n].ctrl & AX_CTRL_EN) && !s->ax[n].stop; }
int axb_dir(sim_t *s, int n) { return (s->ax[n].ctrl & AX_CTRL_DIR) != 0; }
int axb_boost(sim_t *s, int n) { return (s->ax[n].ctrl & AX_CTRL_BOOST) != 0; }
uint16_t axb_rate(sim_t *s, int n) { return s->ax[n].rate; }
int16_t axb_dac(sim_t *s, int n) { return s->ax[n].dac; }
double axb_dac_volts(sim_t *s, int n) { return (double)s->ax[n].dac * (10.0 / 2048.0); }
/* What a servo's drive sees, as one word: the plant's step inputs change
 * only when it does (plant.c inputs_key). */
uint32_t axb_drive_lines(sim_t *s, int n)
{
    const axis_hw_t *a = &s->ax[n];
    return (uint16_t)a->dac | (uint32_t)(a->ctrl & (AX_CTRL_EN | AX_CTRL_BOOST)) << 16 | (uint32_t)(a->stop != 0) << 31;
}

/* ======================================================================== */
/* step generator: phase accumulator, pulses counted analytically            */
/* ======================================================================== */
static double step_clock_hz(sim_t *s, int n)
{
    return (s->ax[n].ctrl & AX_CTRL_TURBO) ? (double)STP_CLK_HZ_TURBO : (double)STP_CLK_HZ;
}

/* The rate of the step output, steps/s, signed by DIR; 0 when the
 * generator is stopped by the down-counter. */
double axb_step_hz(sim_t *s, int n)
{
    axis_hw_t *a = &s->ax[n];
    if (a->pmode == AXB_PULSES_DONE)
        return 0.0;
    double f = (double)a->rate * step_clock_hz(s, n) / 65536.0;
    return (a->ctrl & AX_CTRL_DIR) ? f : 0.0 - f;   /* no -0 */
}

cyc_t axb_step_period(sim_t *s, int n)
{
    return (s->ax[n].ctrl & AX_CTRL_TURBO) ? (cyc_t)(PLANT_CPU_HZ / STP_CLK_HZ_TURBO)
                                           : (cyc_t)(PLANT_CPU_HZ / STP_CLK_HZ);
}

int axb_step_running(sim_t *s, int n)
{
    return is_stp(s) && s->ax[n].rate && s->ax[n].pmode != AXB_PULSES_DONE;
}

/* The cycle at which the j-th pulse comes (j >= 1) after the clock stood
 * at nco_t with the accumulator at acc. */
cyc_t axb_step_pulse_time(sim_t *s, int n, cyc_t nco_t, uint32_t acc, uint64_t j)
{
    uint32_t rate = s->ax[n].rate;
    if (!rate || !j)
        return CYC_NEVER;
    cyc_t P = axb_step_period(s, n);
    uint64_t need = j * 65536u - acc;
    uint64_t m = (need + rate - 1) / rate;
    return (nco_t / P + m) * P;
}

/* ... from now */
cyc_t axb_step_time(sim_t *s, int n, uint64_t j)
{
    axis_hw_t *a = &s->ax[n];
    return axb_step_pulse_time(s, n, a->nco_t, a->acc, j);
}

uint64_t axb_steps_left(sim_t *s, int n)
{
    return s->ax[n].pmode == AXB_PULSES_COUNTING ? s->ax[n].remaining : UINT64_MAX;
}

cyc_t axb_step_done_time(sim_t *s, int n)
{
    axis_hw_t *a = &s->ax[n];
    if (!is_stp(s) || a->pmode != AXB_PULSES_COUNTING)
        return CYC_NEVER;
    return axb_step_time(s, n, a->remaining);
}

/* Clock the accumulator up to `to`, the pulses going out on STEP/DIR to the
 * driver (plant_step_pulses); returns 1 if the down-counter ended. */
int axb_step_advance(sim_t *s, int n, cyc_t to)
{
    axis_hw_t *a = &s->ax[n];
    if (to <= a->nco_t)
        return 0;
    if (!is_stp(s) || !a->rate) {
        a->nco_t = to;
        return 0;
    }
    cyc_t P = axb_step_period(s, n);
    uint64_t k = to / P - a->nco_t / P;
    cyc_t nco_t0 = a->nco_t;            /* for the waveform's STEP edges (vcd.c) */
    uint32_t acc0 = a->acc;
    a->nco_t = to;
    if (!k)
        return 0;
    uint64_t sum = a->acc + k * a->rate;
    uint64_t c = sum >> 16;
    a->acc = (uint32_t)(sum & 0xFFFF);
    int ended = 0;
    if (a->pmode == AXB_PULSES_DONE)
        return 0;                       /* output gated off, accumulator keeps turning */
    if (a->pmode == AXB_PULSES_COUNTING) {
        if (c >= a->remaining) {
            c = a->remaining;
            a->remaining = 0;
            a->pmode = AXB_PULSES_DONE;
            a->pstat |= AX_IN_PDONE;
            ended = 1;
        } else {
            a->remaining -= (uint32_t)c;
        }
    }
    if (!c)
        return ended;
    int64_t d = (a->ctrl & AX_CTRL_DIR) ? (int64_t)c : -(int64_t)c;
    a->gen += d;
    plant_step_pulses(s, n, d);
    if (s->vcd)
        vcd_pulses(s, n, nco_t0, acc0, c);
    if (a->ctrl & AX_CTRL_PULSE_IE) {
        if ((a->pstat & AX_IN_PULSE) || c > 1)
            a->pstat |= AX_IN_PULSE_OVR;
        a->pstat |= AX_IN_PULSE;
    }
    return ended;
}

static void pulses_write(sim_t *s, int n, cyc_t now, uint16_t v)
{
    axis_hw_t *a = &s->ax[n];
    plant_sync(s, n, now);
    a->pstat &= (uint16_t)~AX_IN_PDONE;
    a->remaining = v;
    a->pmode = v ? AXB_PULSES_COUNTING : AXB_PULSES_FREE;
    plant_inputs(s, n, now);
}

/* ======================================================================== */
/* the position counter chip and its index latch                             */
/* ======================================================================== */
/* What it counts: the encoder's increments, or (STP, BR closed) the steps
 * generated; nothing on the SSI board. */
int64_t axb_counter_raw(sim_t *s, int n, cyc_t t)
{
    if (is_ssi(s))
        return 0;
    if (!plant_has_encoder(s, n))
        return s->ax[n].gen;
    return ifloor(plant_enc_e(s, n, t));
}

uint32_t axb_counter_at(sim_t *s, int n, cyc_t t)
{
    axis_hw_t *a = &s->ax[n];
    if (plant_enc_stuck(s, n))
        return a->cnt_frozen;
    return mask24(axb_counter_raw(s, n, t) + a->cnt_off);
}

/* A test or tool may have written axis_hw_t.counter directly. */
void axb_counter_poked(sim_t *s, int n)
{
    axis_hw_t *a = &s->ax[n];
    if (a->counter == a->cnt_seen)
        return;
    a->counter &= CNT_MASK;
    a->cnt_frozen = a->counter;
    a->cnt_off = (int64_t)a->counter - a->raw_seen;
    a->cnt_seen = a->counter;
}

void axb_counter_mirror(sim_t *s, int n, cyc_t t)
{
    axis_hw_t *a = &s->ax[n];
    a->raw_seen = axb_counter_raw(s, n, t);
    a->counter = a->cnt_seen = plant_enc_stuck(s, n) ? a->cnt_frozen : mask24(a->raw_seen + a->cnt_off);
}

uint32_t axb_counter(sim_t *s, int n, cyc_t now)
{
    plant_sync(s, n, now);
    return axb_counter_at(s, n, now);
}

void axb_counter_set(sim_t *s, int n, cyc_t now, uint32_t value)
{
    axis_hw_t *a = &s->ax[n];
    plant_sync(s, n, now);
    value &= CNT_MASK;
    if (is_ssi(s)) {   /* no counter on the SSI board: set the encoder's reading */
        plant_ssi_set(s, n, now, value);
        return;
    }
    a->cnt_frozen = value;
    a->cnt_off = (int64_t)value - axb_counter_raw(s, n, now);
    axb_counter_mirror(s, n, now);
}

/* The encoder's lines stick (plant_set_enc_fault): the counter keeps its value... */
void axb_counter_freeze(sim_t *s, int n, cyc_t now) { s->ax[n].cnt_frozen = axb_counter_at(s, n, now); }

/* ... and goes on from it when they move again. */
void axb_counter_thaw(sim_t *s, int n, cyc_t now)
{
    s->ax[n].cnt_off = (int64_t)s->ax[n].cnt_frozen - axb_counter_raw(s, n, now);
}

/* The encoder jumped by `by` increments (plant_enc_jump). */
void axb_counter_jump(sim_t *s, int n, int64_t by)
{
    axis_hw_t *a = &s->ax[n];
    a->cnt_off += by;
    a->cnt_frozen = mask24((int64_t)a->cnt_frozen + by);
}

int axb_index_armed(sim_t *s, int n) { return !s->ax[n].idx_latched; }

/* An index pulse while armed: the counter's value at the index increment. */
void axb_index_pulse(sim_t *s, int n, int64_t incr)
{
    axis_hw_t *a = &s->ax[n];
    a->idx_latched = 1;
    a->idx_latch = mask24(incr + a->cnt_off);
}

static void index_arm(sim_t *s, int n, cyc_t now)
{
    plant_sync(s, n, now);
    s->ax[n].idx_latched = 0;
    plant_index_armed(s, n, now);
}

/* ======================================================================== */
/* SSI receiver                                                              */
/* ======================================================================== */
static const double ssi_hz[4] = {93750.0, 187500.0, 375000.0, 750000.0};

uint64_t axb_ssi_cycles(int clock)
{
    return (uint64_t)ceil_(SSI_FRAME_BITS * PLANT_CPU_HZ / ssi_hz[clock & 3]);
}

static uint32_t ssi_reg(sim_t *s, int n, cyc_t now);

/* The clock starts: the encoder freezes its position at the first falling
 * edge and sends its frame, MSB first. */
static void ssi_start(sim_t *s, int n, cyc_t now)
{
    axis_hw_t *a = &s->ax[n];
    if (!is_ssi(s) || now < a->ssi_end)
        return;                          /* a read in progress runs on */
    plant_sync(s, n, now);
    a->ssi_old = ssi_reg(s, n, now);
    a->ssi_frame = plant_ssi_frame(s, n, now, a->gray);
    a->ssi_start = now;
    a->ssi_end = now + axb_ssi_cycles(s->ssi_clock);
}

static int ssi_busy(sim_t *s, int n, cyc_t now) { return now < s->ax[n].ssi_end; }

/* The shift register: bits come in MSB first at the rising clock edges. */
static uint32_t ssi_reg(sim_t *s, int n, cyc_t now)
{
    axis_hw_t *a = &s->ax[n];
    if (a->ssi_end == 0)
        return a->ssi & SSI_FRAME_MASK;
    if (now >= a->ssi_end) {
        a->ssi = a->ssi_frame;
        return a->ssi;
    }
    uint64_t k = (uint64_t)((double)(now - a->ssi_start) * ssi_hz[s->ssi_clock & 3] / PLANT_CPU_HZ);
    if (k == 0)
        return a->ssi_old;
    if (k >= SSI_FRAME_BITS)
        return a->ssi_frame;
    return (uint32_t)(((uint64_t)a->ssi_old << k | a->ssi_frame >> (SSI_FRAME_BITS - k)) & SSI_FRAME_MASK);
}

/* ======================================================================== */
/* registers                                                                 */
/* ======================================================================== */
static uint32_t axis_rd(sim_t *s, uint32_t off, int size)
{
    (void)size;
    int n = (int)(off / AXIS_STRIDE);
    axis_hw_t *a = &s->ax[n];
    cyc_t now = sim_axis_now(s);   /* sim_now(s) unless axis_sync (sim.h) */
    switch (off % AXIS_STRIDE) {
    case AX_CNT_HI: {
        uint32_t c = axb_counter(s, n, now);
        a->cnt_lo_latch = (uint16_t)c;
        return (c >> 16) & 0xFF;
    }
    case AX_CNT_LO: return a->cnt_lo_latch;
    case AX_CNT_LIVE: return axb_counter(s, n, now) & 0xFFFF;
    case AX_IDX_HI:
        plant_sync(s, n, now);
        a->idx_lo_latch = (uint16_t)a->idx_latch;
        return (a->idx_latch >> 16) & 0xFF;
    case AX_IDX_LO: return a->idx_lo_latch;
    case AX_IN:
        return (uint32_t)(plant_inputs_word(s, n, now) | a->in | (a->idx_latched ? AX_IN_IDX : 0) |
                          (a->gray ? AX_IN_GRAY : 0) | (ssi_busy(s, n, now) ? AX_IN_SSI_BUSY : 0) |
                          a->pstat);
    case AX_CTRL: return a->ctrl;
    case AX_SSI_HI: return (ssi_reg(s, n, now) >> 16) & 0x3FF;
    case AX_SSI_LO: return ssi_reg(s, n, now) & 0xFFFF;
    case AX_PULSES:
        plant_sync(s, n, now);
        return a->remaining & 0xFFFF;
    }
    sim_fault(s, "read of undefined axis register +$%X", (unsigned)(off % AXIS_STRIDE));
    return 0xFFFF;
}

#define AX_CTRL_W_ONLY (AX_CTRL_IDX_ARM | AX_CTRL_CNT_CLR | AX_CTRL_PULSE_ACK | AX_CTRL_DONE_ACK)

static void axis_wr(sim_t *s, uint32_t off, uint32_t v, int size)
{
    (void)size;
    int n = (int)(off / AXIS_STRIDE);
    axis_hw_t *a = &s->ax[n];
    cyc_t now = sim_axis_now(s);   /* sim_now(s) unless axis_sync (sim.h) */
    switch (off % AXIS_STRIDE) {
    case AX_CTRL:
        plant_sync(s, n, now);
        if (v & AX_CTRL_CNT_CLR)
            axb_counter_set(s, n, now, 0);
        if (v & AX_CTRL_PULSE_ACK)
            a->pstat &= (uint16_t)~(AX_IN_PULSE | AX_IN_PULSE_OVR);
        if (v & AX_CTRL_DONE_ACK)
            a->pstat &= (uint16_t)~AX_IN_PDONE;
        a->ctrl = (uint16_t)(v & ~(uint32_t)AX_CTRL_W_ONLY);
        if (v & AX_CTRL_IDX_ARM)
            index_arm(s, n, now);
        plant_inputs(s, n, now);
        return;
    case AX_DAC:   /* AX_RATE on the STP board */
        plant_sync(s, n, now);
        if (s->card == MAC4_CARD_STP)
            a->rate = (uint16_t)v;
        else   /* 12-bit two's complement converter: the upper bits are not wired */
            a->dac = (int16_t)((int16_t)(uint16_t)(v << 4) >> 4);
        plant_inputs(s, n, now);
        return;
    case AX_SSI_START:
        ssi_start(s, n, now);
        return;
    case AX_PULSES:
        pulses_write(s, n, now, (uint16_t)v);
        return;
    }
    sim_fault(s, "write to undefined axis register +$%X", (unsigned)(off % AXIS_STRIDE));
}

static uint32_t axis_irq_rd(sim_t *s, uint32_t off, int size)
{
    (void)off;
    (void)size;
    uint32_t p = 0;
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        const axis_hw_t *a = &s->ax[n];
        if (a->idx_latched && (a->ctrl & AX_CTRL_IDX_IE))
            p |= AXIS_IRQ_IDX(n);
        if ((a->pstat & AX_IN_PULSE) && (a->ctrl & AX_CTRL_PULSE_IE))
            p |= AXIS_IRQ_PULSE(n);
        if ((a->pstat & AX_IN_PDONE) && (a->ctrl & AX_CTRL_DONE_IE))
            p |= AXIS_IRQ_DONE(n);
    }
    return p;
}

static void axis_irq_wr(sim_t *s, uint32_t off, uint32_t v, int size)
{
    (void)off;
    (void)v;
    (void)size;
    sim_fault(s, "write to the read-only axis interrupt register");
}

const axis_led_t axis_leds[AXIS_NLEDS] = {
    {"D", SYS_LED_D, 0}, {"P", SYS_LED_P, 0}, {"F", SYS_LED_F, 0},
    {"LP", 0, AX_IN_IESP}, {"LN", 0, AX_IN_IESN}, {"REF", 0, AX_IN_RS},
};

unsigned axisboard_leds(sim_t *s, int n)
{
    uint16_t reg = (uint16_t)(s->sys.leds >> SYS_LED_SHIFT(n));
    uint16_t in = plant_inputs_word(s, n, sim_now(s));
    unsigned lit = 0;
    for (unsigned i = 0; i < AXIS_NLEDS; i++)
        if ((reg & axis_leds[i].reg) || (in & axis_leds[i].in))
            lit |= 1u << i;
    return lit;
}

/* Reset (tables 2.2, 2.6, 2.12): /EN open, DAC 0 V, rate 0, DIR and BOOST
 * open collector, counters, latches, SSI receivers and pulse logic cleared.
 * The plant itself is not reset: the motors coast.  At the first reset after
 * power-on the jumpers take their bench defaults: J1 open (Gray code, the
 * usual SSI encoder), J2 at D (750 kHz, docs/plant.md). */
static void axisboard_reset(sim_t *s)
{
    cyc_t now = sim_now(s);
    if (!s->plant.init) {
        s->ssi_clock = 3;
        for (int n = 0; n < MAC4_NAXES; n++) {
            s->ax[n].gray = is_ssi(s);
            s->ax[n].nco_t = now;
        }
        plant_power_on(s);
    }
    for (int n = 0; n < MAC4_NAXES; n++) {
        axis_hw_t *a = &s->ax[n];
        plant_sync(s, n, now);
        a->ctrl = 0;
        a->dac = 0;
        a->rate = 0;
        a->idx_latched = 0;
        a->idx_latch = 0;
        a->pstat = 0;
        a->ssi = 0;
        a->acc = 0;
        a->pmode = AXB_PULSES_FREE;
        a->remaining = 0;
        a->ssi_end = 0;
        a->ssi_old = a->ssi_frame = 0;
        a->cnt_frozen = 0;
        a->cnt_off = -axb_counter_raw(s, n, now);   /* the counter chip is cleared */
        plant_board_reset(s, n, now);
        axb_counter_mirror(s, n, now);
    }
}

static cyc_t min_cyc(cyc_t a, cyc_t b) { return a < b ? a : b; }

/* The board's own events (the index interrupt, pulse interrupts, the end
 * of a pulse count) and the plant's (plant_next_event). */
static cyc_t next_event(sim_t *s)
{
    cyc_t t = CYC_NEVER;
    for (int n = 0; n < MAC4_NAXES; n++) {
        axis_hw_t *a = &s->ax[n];
        t = min_cyc(t, plant_next_event(s, n, (a->ctrl & AX_CTRL_IDX_IE) && !a->idx_latched));
        if (is_stp(s)) {
            if ((a->ctrl & AX_CTRL_PULSE_IE) && axb_step_running(s, n))
                t = min_cyc(t, axb_step_time(s, n, 1));
            if (a->ctrl & AX_CTRL_DONE_IE)
                t = min_cyc(t, axb_step_done_time(s, n));
        }
    }
    return t;
}

/* With axis_sync the plant lives on the axis clock: it is brought up to date
 * at every access and every scheduler event, never scheduled in real time. */
static cyc_t axisboard_next_event(sim_t *s) { return s->axis_sync ? CYC_NEVER : next_event(s); }

static void axisboard_events(sim_t *s, cyc_t now) { plant_events(s, s->axis_sync ? sim_axis_peek(s) : now); }

static unsigned axisboard_irq_lines(sim_t *s) { return axis_irq_rd(s, 0, 2) ? 1u << IRQ_LEVEL_AXIS : 0; }

/* The timer expired at `at`: the SSI receivers set to AX_CTRL_SSI_SYNC
 * freeze their encoders and start reading (on the axis clock of the
 * differential test, at the axis clock's time); each tells the timer how
 * long it reads. */
static void axisboard_tmr_expired(sim_t *s, uint64_t at)
{
    for (int n = 0; n < MAC4_NAXES; n++)
        if (s->card == MAC4_CARD_SSI && (s->ax[n].ctrl & AX_CTRL_SSI_SYNC)) {
            ssi_start(s, n, s->axis_sync ? sim_axis_peek(s) : at);
            sig_raise(s, SIG_SSI_BUSY, s->ax[n].ssi_end);
        }
}

/* /STOP changed: every board's /EN follows at once (the plant sees it at
 * its next sync, as any input change). */
static void axisboard_stop(sim_t *s, uint64_t active)
{
    for (int n = 0; n < MAC4_NAXES; n++)
        s->ax[n].stop = active != 0;
}

void axisboard_connect(sim_t *s)
{
    sig_connect(s, SIG_TMR_EXPIRED, axisboard_tmr_expired);
    sig_connect(s, SIG_STOP, axisboard_stop);
}

/* window 0: the four boards' registers (AX_REG), window 1: AXIS_IRQ_PENDING */
const device_t axisboard_device = {.name = "axis", .win = {{axis_rd, axis_wr}, {axis_irq_rd, axis_irq_wr}},
                                   .reset = axisboard_reset, .next_event = axisboard_next_event,
                                   .events = axisboard_events, .irq_lines = axisboard_irq_lines};
