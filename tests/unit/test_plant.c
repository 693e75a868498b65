/* The plant models behind the axis boards (harness/plant.c, docs/plant.md),
 * driven through the bus as the 68000 would, on a card without a CPU:
 * time advances event by event through the scheduler's own entry points. */
#include "unit_support.h"
#include "periph.h"
#include "plant.h"
#include <unistd.h>
#include <stdlib.h>

static void setup_card(int type)
{
    card_setup();
    if (type != MAC4_CARD_INC) {
        FILE *f = card.out;
        sim_init(&card, type);
        card.sysctl = 0;
        card.out = f;
    }
    card.wdg.j11 = 0;     /* nobody kicks the watchdog here */
    card.host_reads = 0;
}

static cyc_t now(void) { return sim_now(&card); }

/* Advance emulated time as run.c does, minus the CPU. */
static void advance_cyc(cyc_t cyc)
{
    cyc_t end = card.slice_base + cyc;
    periph_events(&card, card.slice_base);   /* as sim_run: see what changed meanwhile */
    for (int guard = 0; guard < 100000000; guard++) {
        cyc_t nx = periph_next_event(&card);
        if (nx > end)
            break;
        if (nx > card.slice_base)
            card.slice_base = nx;
        periph_events(&card, card.slice_base);
        if (nx < card.slice_base)
            break;
    }
    card.slice_base = end;
    periph_events(&card, end);
}
static void advance_ms(double ms) { advance_cyc((cyc_t)(ms * 16000.0 + 0.5)); }

static uint16_t rd(int n, uint32_t off) { return (uint16_t)bus_read(&card, AX_REG((uint32_t)n, off), 2); }
static void wr(int n, uint32_t off, uint32_t v) { bus_write(&card, AX_REG((uint32_t)n, off), v & 0xFFFF, 2); }
static uint32_t counter(int n) { uint32_t hi = rd(n, AX_CNT_HI); return hi << 16 | rd(n, AX_CNT_LO); }
static uint32_t idx(int n) { uint32_t hi = rd(n, AX_IDX_HI); return hi << 16 | rd(n, AX_IDX_LO); }
static uint32_t ssi_reg(int n) { uint32_t hi = rd(n, AX_SSI_HI); return hi << 16 | rd(n, AX_SSI_LO); }
static uint32_t irq(void) { return bus_read(&card, AXIS_IRQ_PENDING, 2); }
static int32_t sext24(uint32_t v) { return (int32_t)(v << 8) >> 8; }

/* ---- reset states -------------------------------------------------------- */
static void reset_states(void **st)
{
    (void)st;
    static const int types[] = {MAC4_CARD_INC, MAC4_CARD_SSI, MAC4_CARD_STP};
    for (unsigned t = 0; t < 3; t++) {
        setup_card(types[t]);
        for (int n = 0; n < 4; n++) {
            assert_int_equal(rd(n, AX_CTRL), 0);
            assert_int_equal(counter(n), 0);
            assert_int_equal(idx(n), 0);
            uint16_t want = types[t] == MAC4_CARD_SSI ? AX_IN_GRAY : types[t] == MAC4_CARD_STP ? AX_IN_BR_STEPS : 0;
            assert_int_equal(rd(n, AX_IN), want);   /* no switch, no fault, nothing latched */
            assert_int_equal(ssi_reg(n), 0);
            assert_int_equal(rd(n, AX_PULSES), 0);
            assert_int_equal(card.ax[n].dac, 0);
            assert_int_equal(card.ax[n].rate, 0);
        }
        assert_int_equal(irq(), 0);
        advance_ms(50);   /* nothing moves by itself */
        for (int n = 0; n < 4; n++)
            assert_int_equal(counter(n), 0);
        assert_int_equal(periph_next_event(&card), CYC_NEVER);   /* at rest: no events at all */
    }
    /* a card reset clears the board but the motor keeps its position */
    setup_card(MAC4_CARD_INC);
    plant_set_position(&card, 1, 1234);
    assert_int_equal(counter(1), 1234);
    wr(1, AX_CTRL, AX_CTRL_EN);
    wr(1, AX_DAC, 300);
    periph_reset(&card);
    assert_int_equal(rd(1, AX_CTRL), 0);
    assert_int_equal(card.ax[1].dac, 0);
    assert_int_equal(counter(1), 0);
    assert_int_equal((int)(plant_units(&card, 1, now()) + 0.5), 1234);
}

/* ---- DC servo --------------------------------------------------------------- */
static void positive_dac_counts_up(void **st)
{
    (void)st;
    setup_card(MAC4_CARD_INC);
    wr(0, AX_DAC, 1000);
    advance_ms(20);
    assert_int_equal(counter(0), 0);            /* not enabled: the DAC does nothing */
    wr(0, AX_CTRL, AX_CTRL_EN);
    advance_ms(100);
    uint32_t c1 = counter(0);
    advance_ms(100);
    uint32_t c2 = counter(0);
    assert_true(c1 > 0 && c2 > c1);
    /* steady speed: 1000/2048 of 3000 rpm behind 16:1, 4000 inc/rev -> 6104 inc/s */
    double v = (double)(c2 - c1) / 0.1;
    assert_true(v > 5900 && v < 6110);
    wr(0, AX_DAC, (uint32_t)-1000);
    advance_ms(300);
    uint32_t c3 = counter(0);
    advance_ms(100);
    assert_true(sext24(counter(0)) < sext24(c3));   /* negative DAC counts down */
    /* the DAC is 12 bits: bit 11 is the sign */
    wr(0, AX_DAC, 0x0FFF);
    assert_int_equal(card.ax[0].dac, -1);
}

static void reads_see_the_cycle_they_happen(void **st)
{
    (void)st;
    setup_card(MAC4_CARD_INC);
    wr(0, AX_CTRL, AX_CTRL_EN);
    wr(0, AX_DAC, 2047);
    advance_ms(100);
    /* 12 500 inc/s: 5 us apart is 1/16 increment, 100 us is 1.25 */
    uint32_t a = counter(0);
    card.slice_base += US_TO_CYC(400);   /* as if the CPU ran 400 us without an event */
    uint32_t b = counter(0);
    assert_true(b - a >= 4 && b - a <= 6);
}

static void disabled_amplifier_coasts_and_estop_disables(void **st)
{
    (void)st;
    setup_card(MAC4_CARD_INC);
    wr(0, AX_CTRL, AX_CTRL_EN);
    wr(1, AX_CTRL, AX_CTRL_EN);
    wr(0, AX_DAC, 2047);
    wr(1, AX_DAC, 2047);
    advance_ms(100);
    /* axis 0: enabled at 0 V, the speed loop brakes; axis 1: /EN open, it coasts */
    wr(0, AX_DAC, 0);
    wr(1, AX_CTRL, 0);
    uint32_t a0 = counter(0), a1 = counter(1);
    advance_ms(50);
    uint32_t d0 = counter(0) - a0, d1 = counter(1) - a1;
    assert_true(d0 < 120);          /* stopped in 16 ms at the current limit */
    assert_true(d1 > 5 * d0);       /* still turning on its inertia */
    advance_ms(4000);
    uint32_t r1 = counter(1);
    advance_ms(100);
    assert_int_equal(counter(1), r1);   /* friction stopped it in the end */
    /* the emergency stop opens every /EN, whatever AX_CTRL says */
    wr(2, AX_CTRL, AX_CTRL_EN);
    wr(2, AX_DAC, 1500);
    estop_set(&card, 1);
    advance_ms(50);
    assert_int_equal(counter(2), 0);
    estop_set(&card, 0);
    advance_ms(50);
    assert_true(counter(2) > 0);
}

static void index_latches_once_per_revolution(void **st)
{
    (void)st;
    setup_card(MAC4_CARD_INC);
    wr(0, AX_CTRL, AX_CTRL_EN | AX_CTRL_IDX_IE | AX_CTRL_IDX_ARM);
    wr(0, AX_DAC, 1500);
    uint32_t expect = 4000;   /* the index increment is 0 in the revolution */
    for (int rev = 0; rev < 3; rev++) {
        /* look only at the interrupt line (no register read that would
         * bring the model up to date): the scheduler event must raise it */
        int ms = 0;
        while (!(irq() & AXIS_IRQ_IDX(0)) && ms < 20000) {
            advance_ms(0.1);
            ms++;
        }
        assert_true(rd(0, AX_IN) & AX_IN_IDX);
        assert_int_equal(idx(0), expect);
        assert_int_equal(irq(), AXIS_IRQ_IDX(0));
        /* the interrupt came at the crossing: at most 0.1 ms of travel (0.9 increments) later */
        assert_true(counter(0) - expect <= 1);
        advance_ms(300);   /* the latch holds, though the shaft goes on */
        assert_int_equal(idx(0), expect);
        wr(0, AX_CTRL, AX_CTRL_EN | AX_CTRL_IDX_IE | AX_CTRL_IDX_ARM);
        assert_int_equal(irq(), 0);
        expect += 4000;
    }
    /* backwards: entered from above at increment -4000 of the first turn */
    setup_card(MAC4_CARD_INC);
    plant_axis_t *p = &card.plant.ax[1];
    p->index = 1000;
    plant_changed(&card, 1);
    wr(1, AX_CTRL, AX_CTRL_EN | AX_CTRL_IDX_ARM);   /* no interrupt: the flag alone */
    wr(1, AX_DAC, (uint32_t)-1500);
    advance_ms(1000);
    assert_true(rd(1, AX_IN) & AX_IN_IDX);
    assert_int_equal(irq(), 0);
    assert_int_equal(sext24(idx(1)), 1000 - 4000);
    /* a cleared counter moves the latched values with it */
    double u = plant_units(&card, 1, now());
    int32_t raw = (int32_t)(u + 0.5) - ((u + 0.5) < 0 && (u + 0.5) != (int32_t)(u + 0.5) ? 1 : 0);
    wr(1, AX_CTRL, AX_CTRL_EN | AX_CTRL_IDX_ARM | AX_CTRL_CNT_CLR);
    assert_int_equal(counter(1), 0);
    advance_ms(1000);
    assert_true(rd(1, AX_IN) & AX_IN_IDX);
    int32_t next = 1000;   /* the next index increment below */
    while (next >= raw)
        next -= 4000;
    assert_int_equal(sext24(idx(1)), next - raw);
}

/* A proportional position loop at the servo period, as the firmware will
 * run it: u = K (e - A e_prev), K in DAC LSB per increment (WGA = 4 K). */
static int closed_loop(double K, double A, int32_t target, int32_t *final, int32_t *peak)
{
    setup_card(MAC4_CARD_INC);
    wr(0, AX_CTRL, AX_CTRL_EN);
    double e_prev = 0;
    int32_t pk = 0, pos = 0, moved_late = 0;
    for (int k = 0; k < 800; k++) {   /* 2 s */
        pos = sext24(counter(0));
        double e = target - pos;
        double u = K * e - K * A * e_prev;
        e_prev = e;
        int32_t dac = u > 2047 ? 2047 : u < -2048 ? -2048 : (int32_t)(u < 0 ? u - 0.5 : u + 0.5);
        advance_cyc(US_TO_CYC(100));   /* computation time before the output */
        wr(0, AX_DAC, (uint32_t)dac);
        advance_cyc(US_TO_CYC(SERVO_PERIOD_US_SERVO - 100));
        if (pos > pk)
            pk = pos;
        if (k >= 600 && (pos > target + 3 || pos < target - 3))
            moved_late = 1;
    }
    *final = pos;
    *peak = pk;
    return moved_late;
}

static void default_plant_is_stable_for_k_1_to_50(void **st)
{
    (void)st;
    static const double ks[] = {1, 2, 5, 10, 20, 30, 40, 50};
    for (unsigned i = 0; i < sizeof ks / sizeof ks[0]; i++) {
        int32_t fin, peak;
        /* a small step: linear range at every gain */
        assert_false(closed_loop(ks[i], 0.0, 20, &fin, &peak));
        assert_true(fin >= 17 && fin <= 23);
        assert_true(peak <= 20 + 10);     /* overshoot well damped */
    }
    /* and the loop does go unstable well above: the plant is not a sponge */
    int32_t f2, p2;
    assert_true(closed_loop(160, 0.0, 20, &f2, &p2));
    /* the manual's MAC4-INC example: WGA 80 (K = 20), WZE 128 (A = 0.5); a
     * large move saturates the DAC and still settles */
    int32_t fin, peak;
    assert_false(closed_loop(20, 0.5, 2000, &fin, &peak));
    assert_true(fin >= 1997 && fin <= 2003);
    assert_true(peak <= 2000 + 40);
}

/* The index interrupt is raised at the crossing, not before, even when
 * register accesses in the middle of an integration step came first. */
static void index_interrupt_timing_after_accesses(void **st)
{
    (void)st;
    setup_card(MAC4_CARD_INC);
    wr(0, AX_CTRL, AX_CTRL_EN | AX_CTRL_IDX_IE);
    wr(0, AX_DAC, 2047);   /* 12 500 inc/s: 0.8 increments per 64 us */
    while (counter(0) < 3999) {
        advance_cyc(37 * 16 + 5);
        wr(0, AX_CTRL, AX_CTRL_EN | AX_CTRL_IDX_IE);   /* same value: a write re-predicts */
    }
    int fired = 0;
    for (int us = 0; us < 2000 && !fired; us++) {
        advance_cyc(16);
        fired = (irq() & AXIS_IRQ_IDX(0)) != 0;
    }
    assert_true(fired);
    uint32_t c = counter(0);
    assert_true(c == 4000);
    assert_int_equal(idx(0), 4000);
}

static void counter_wraps_at_2_24(void **st)
{
    (void)st;
    setup_card(MAC4_CARD_INC);
    axb_counter_set(&card, 0, now(), 0xFFFFF0);
    assert_int_equal(counter(0), 0xFFFFF0);
    wr(0, AX_CTRL, AX_CTRL_EN);
    wr(0, AX_DAC, 200);   /* ~600 inc/s */
    advance_ms(200);
    uint32_t c = counter(0);
    assert_true(c > 0x10 && c < 0x200);
    assert_int_equal(rd(0, AX_CNT_HI), 0);
    /* a value poked straight into the model's register is adopted */
    card.ax[0].counter = 1000;
    assert_true(counter(0) >= 1000 && counter(0) < 1002);
    /* CNT_CLR */
    wr(0, AX_CTRL, AX_CTRL_EN | AX_CTRL_CNT_CLR);
    assert_true(counter(0) < 2);
    assert_int_equal(rd(0, AX_CTRL), AX_CTRL_EN);   /* the command bits do not stick */
}

static void encoder_faults(void **st)
{
    (void)st;
    setup_card(MAC4_CARD_INC);
    wr(0, AX_CTRL, AX_CTRL_EN);
    wr(0, AX_DAC, 500);
    advance_ms(100);
    plant_set_enc_fault(&card, 0, PLANT_ENC_FROZEN);
    uint32_t f = counter(0);
    advance_ms(100);
    assert_int_equal(counter(0), f);
    plant_set_enc_fault(&card, 0, PLANT_ENC_OK);
    advance_ms(10);
    assert_true(counter(0) > f && counter(0) < f + 100);   /* goes on from where it stopped */
    uint32_t b = counter(0);
    plant_enc_jump(&card, 0, -5000);
    assert_true(sext24(counter(0)) - sext24(b) < -4990);
}

/* ---- switches ---------------------------------------------------------------- */
static void switch_levels_and_polarity(void **st)
{
    (void)st;
    setup_card(MAC4_CARD_INC);
    plant_axis_t *p = &card.plant.ax[2];
    p->sw[PLANT_SW_LP] = (plant_switch_t){1, 0, 10000, 0};     /* low active */
    p->sw[PLANT_SW_LN] = (plant_switch_t){1, 1, -10000, 0};    /* high active */
    p->sw[PLANT_SW_REF] = (plant_switch_t){1, 0, 500, 100};
    assert_int_equal(rd(2, AX_IN) & 0xF, AX_IN_IESN);          /* high active and off: 0 V */
    plant_set_position(&card, 2, 550);
    assert_int_equal(rd(2, AX_IN) & 0xF, AX_IN_IESN | AX_IN_RS);
    plant_set_position(&card, 2, 600);                         /* the window is [500, 600) */
    assert_int_equal(rd(2, AX_IN) & 0xF, AX_IN_IESN);
    plant_set_position(&card, 2, 10000);
    assert_int_equal(rd(2, AX_IN) & 0xF, AX_IN_IESN | AX_IN_IESP);
    plant_set_position(&card, 2, -20000);                      /* beyond: stays on */
    assert_int_equal(rd(2, AX_IN) & 0xF, 0);                   /* ln on = 24 V */
    assert_true(plant_switch_active(&card, 2, PLANT_SW_LN, now()));
    p->sw[PLANT_SW_REF].high = 1;
    assert_int_equal(rd(2, AX_IN) & 0xF, AX_IN_RS);
    /* drive fault: DF line and the power stage off */
    plant_set_position(&card, 2, 0);
    p->drive_fault = 1;
    plant_changed(&card, 2);
    assert_true(rd(2, AX_IN) & AX_IN_DF);
    wr(2, AX_CTRL, AX_CTRL_EN);
    wr(2, AX_DAC, 1000);
    advance_ms(50);
    assert_int_equal(counter(2), 0);
    p->df_high = 1;
    assert_false(rd(2, AX_IN) & AX_IN_DF);
    /* a forced bit in axis_hw_t.in (test hook) shows as well */
    card.ax[3].in = AX_IN_IESP;
    assert_int_equal(rd(3, AX_IN) & 0xF, AX_IN_IESP);
}

/* ---- SSI -------------------------------------------------------------------- */
/* The timer's expiry reaches the axis board as a signal (timer.expired): the
 * SSI receivers set to AX_CTRL_SSI_SYNC start reading at the expiry, and with
 * TMR_CTRL_SSI_WAIT the timer's request waits for the last of them
 * (axis.ssi_busy); without it, or with no receiver synced, it is at once. */
static void timer_expiry_starts_the_synced_ssi_reads(void **st)
{
    (void)st;
    static const uint16_t modes[3] = {TMR_CTRL_RUN | TMR_CTRL_IE | TMR_CTRL_SSI_WAIT,
                                      TMR_CTRL_RUN | TMR_CTRL_IE, TMR_CTRL_RUN | TMR_CTRL_IE | TMR_CTRL_SSI_WAIT};
    for (int m = 0; m < 3; m++) {
        setup_card(MAC4_CARD_SSI);
        assert_string_equal(card.sig[SIG_TMR_EXPIRED].name, "timer.expired");
        card.ssi_clock = 3;                              /* 750 kHz: 555 cycles a frame */
        if (m < 2) {
            wr(0, AX_CTRL, AX_CTRL_SSI_SYNC);
            wr(2, AX_CTRL, AX_CTRL_SSI_SYNC);
        }
        bus_write(&card, TMR_PERIOD, SERVO_PERIOD_US_SERVO, 2);
        bus_write(&card, TMR_CTRL, modes[m], 2);
        cyc_t expiry = now() + US_TO_CYC(SERVO_PERIOD_US_SERVO);
        advance_cyc(US_TO_CYC(SERVO_PERIOD_US_SERVO));
        assert_int_equal(now(), expiry);
        assert_true(bus_read(&card, TMR_STATUS, 2) & TMR_ST_EXPIRED);
        if (m < 2) {                                           /* both synced receivers read from the expiry */
            assert_int_equal(card.ax[0].ssi_start, expiry);
            assert_int_equal(card.ax[2].ssi_start, expiry);
            assert_true(rd(2, AX_IN) & AX_IN_SSI_BUSY);
            assert_false(rd(1, AX_IN) & AX_IN_SSI_BUSY);
        } else
            assert_false(rd(0, AX_IN) & AX_IN_SSI_BUSY);
        if (m == 0) {                                          /* the request waits for the reads */
            assert_false(sim_irq_lines(&card) & (1u << IRQ_LEVEL_TIMER));
            assert_int_equal(periph_next_event(&card), expiry + 555);
            advance_cyc(554);
            assert_false(sim_irq_lines(&card) & (1u << IRQ_LEVEL_TIMER));
            advance_cyc(1);
        }
        assert_true(sim_irq_lines(&card) & (1u << IRQ_LEVEL_TIMER));
    }
}

static void ssi_gray_binary_placement_and_busy_time(void **st)
{
    (void)st;
    setup_card(MAC4_CARD_SSI);
    plant_set_position(&card, 0, 12345);
    assert_int_equal(plant_ssi_value(&card, 0, now()), 12345);
    static const cyc_t busy[4] = {4438, 2219, 1110, 555};   /* 26 clocks at 93.75 ... 750 kHz */
    for (int j = 0; j < 4; j++) {
        card.ssi_clock = j;
        wr(0, AX_SSI_START, 0);
        assert_true(rd(0, AX_IN) & AX_IN_SSI_BUSY);
        advance_cyc(busy[j] - 1);
        assert_true(rd(0, AX_IN) & AX_IN_SSI_BUSY);
        advance_cyc(1);
        assert_false(rd(0, AX_IN) & AX_IN_SSI_BUSY);
        /* 24 bits Gray, left-aligned in the 26-bit register: <sc> = 2 */
        assert_int_equal(ssi_reg(0), (uint32_t)(12345 ^ (12345 >> 1)) << 2);
    }
    /* binary (J1 closed), 13 bits: value mod 8192 at bits 25..13 */
    card.ax[0].gray = 0;
    card.plant.ax[0].ssi_bits = 13;
    wr(0, AX_SSI_START, 0);
    advance_ms(1);
    assert_int_equal(ssi_reg(0), (uint32_t)(12345 & 8191) << 13);
    assert_int_equal(ssi_reg(0) >> 13, 12345 - 8192);
    /* while busy the register shows the bits shifted in so far, MSB first */
    card.ssi_clock = 0;   /* 93.75 kHz: 170.67 cycles per bit */
    plant_set_position(&card, 0, 8191);   /* all ones in 13 bits */
    uint32_t before = ssi_reg(0);
    wr(0, AX_SSI_START, 0);
    advance_cyc(171 * 5);                 /* five clocks */
    assert_int_equal(ssi_reg(0), ((before << 5) | 0x1F) & SSI_FRAME_MASK);
    advance_ms(1);
    assert_int_equal(ssi_reg(0), 8191u << 13);
    /* the position is taken at the start of the read */
    card.plant.ax[0].ssi_bits = 24;
    card.ax[0].gray = 0;
    wr(0, AX_CTRL, AX_CTRL_EN);
    wr(0, AX_DAC, 2047);
    advance_ms(50);
    uint32_t at = plant_ssi_value(&card, 0, now());
    wr(0, AX_SSI_START, 0);
    advance_ms(1);
    assert_int_equal(ssi_reg(0) >> 2, at);
    assert_true(plant_ssi_value(&card, 0, now()) > at);
    /* faults: data line stuck */
    plant_set_enc_fault(&card, 0, PLANT_ENC_STUCK1);
    wr(0, AX_SSI_START, 0);
    advance_ms(1);
    assert_int_equal(ssi_reg(0), SSI_FRAME_MASK);
    plant_set_enc_fault(&card, 0, PLANT_ENC_STUCK0);
    wr(0, AX_SSI_START, 0);
    advance_ms(1);
    assert_int_equal(ssi_reg(0), 0);
    /* the counter of the SSI board never counts; `counter` sets the SSI reading */
    plant_set_enc_fault(&card, 0, PLANT_ENC_OK);
    assert_int_equal(counter(0), 0);
    axb_counter_set(&card, 0, now(), 1000);
    assert_int_equal(plant_ssi_value(&card, 0, now()), 1000);
}

/* ---- STP: step generator ----------------------------------------------------- */
static void step_generator_frequencies(void **st)
{
    (void)st;
    setup_card(MAC4_CARD_STP);
    /* BR closed: the counter counts generated steps, DIR positive */
    wr(0, AX_CTRL, AX_CTRL_DIR);
    wr(0, AX_RATE, 65535);                 /* 49 999.2 Hz */
    wr(1, AX_CTRL, AX_CTRL_DIR | AX_CTRL_TURBO);
    wr(1, AX_RATE, 1000);                  /* 7 629.39 Hz */
    wr(2, AX_CTRL, AX_CTRL_DIR);
    wr(2, AX_RATE, 1);                     /* 0.7629 Hz */
    wr(3, AX_CTRL, AX_CTRL_DIR | AX_CTRL_TURBO);
    wr(3, AX_RATE, 65535);                 /* 499 992 Hz */
    advance_ms(1000);
    assert_int_equal(counter(0), 49999);
    assert_int_equal(counter(1), 7629);
    assert_int_equal(counter(2), 0);
    assert_int_equal(counter(3), 499992);
    advance_ms(9000);
    assert_int_equal(counter(2), 7);
    assert_int_equal(counter(1), 76293);
    /* DIR open collector: negative, counts down */
    wr(1, AX_CTRL, AX_CTRL_TURBO);
    advance_ms(1000);
    assert_true(counter(1) >= 76293 - 7630 && counter(1) <= 76293 - 7628);
    /* the analytic count is the same however often it is looked at */
    setup_card(MAC4_CARD_STP);
    wr(0, AX_CTRL, AX_CTRL_DIR);
    wr(0, AX_RATE, 12345);
    wr(1, AX_CTRL, AX_CTRL_DIR);
    wr(1, AX_RATE, 12345);
    for (int i = 0; i < 1000; i++) {
        advance_cyc(997);
        (void)counter(0);
    }
    assert_int_equal(counter(0), counter(1));
}

static void pulse_down_counter_and_interrupts(void **st)
{
    (void)st;
    setup_card(MAC4_CARD_STP);
    wr(0, AX_CTRL, AX_CTRL_DIR | AX_CTRL_DONE_IE);
    wr(0, AX_PULSES, 100);
    wr(0, AX_RATE, 1000);   /* 763 Hz: the 100th pulse at clock ceil(6553600/1000) = 6554 */
    advance_cyc(6554 * 320 - 1);
    assert_int_equal(counter(0), 99);
    assert_int_equal(rd(0, AX_PULSES), 1);
    assert_int_equal(irq(), 0);
    advance_cyc(1);
    assert_int_equal(counter(0), 100);
    assert_true(rd(0, AX_IN) & AX_IN_PDONE);
    assert_int_equal(irq(), AXIS_IRQ_DONE(0));
    advance_ms(100);
    assert_int_equal(counter(0), 100);     /* stopped */
    wr(0, AX_CTRL, AX_CTRL_DIR | AX_CTRL_DONE_IE | AX_CTRL_DONE_ACK);
    assert_int_equal(irq(), 0);
    wr(0, AX_PULSES, 0);                   /* free running again */
    advance_ms(100);
    assert_true(counter(0) > 170);

    /* one interrupt per pulse; acknowledge by PULSE_ACK; a missed one is flagged */
    setup_card(MAC4_CARD_STP);
    wr(1, AX_CTRL, AX_CTRL_DIR | AX_CTRL_PULSE_IE);
    wr(1, AX_RATE, 100);                   /* 76.3 Hz, 13.1 ms apart */
    int seen = 0;
    for (int i = 0; i < 1000; i++) {
        advance_ms(0.1);
        if (irq() & AXIS_IRQ_PULSE(1)) {
            assert_true(rd(1, AX_IN) & AX_IN_PULSE);
            wr(1, AX_CTRL, AX_CTRL_DIR | AX_CTRL_PULSE_IE | AX_CTRL_PULSE_ACK);
            seen++;
        }
    }
    assert_int_equal(seen, (int)counter(1));
    assert_true(seen >= 7 && seen <= 8);
    assert_false(rd(1, AX_IN) & AX_IN_PULSE_OVR);
    advance_ms(30);
    assert_true(rd(1, AX_IN) & AX_IN_PULSE_OVR);
    wr(1, AX_CTRL, AX_CTRL_DIR | AX_CTRL_PULSE_ACK);
    assert_false(rd(1, AX_IN) & (AX_IN_PULSE | AX_IN_PULSE_OVR));
}

/* ---- STP: the stepper motor ---------------------------------------------------- */
static uint16_t rate_for(double hz) { return (uint16_t)(hz * 65536.0 / 50000.0 + 0.5); }

static int64_t lost(int n)
{
    int64_t g, l;
    plant_step_counts(&card, n, &g, &l);
    return l;
}

static void stepper_start_stop_frequency(void **st)
{
    (void)st;
    setup_card(MAC4_CARD_STP);   /* default ssf 1000 Hz */
    for (int n = 0; n < 4; n++)
        wr(n, AX_CTRL, AX_CTRL_EN | AX_CTRL_DIR);
    wr(0, AX_RATE, rate_for(800));    /* jump from stand-still below ssf: follows */
    wr(1, AX_RATE, rate_for(1500));   /* above: stalls */
    advance_ms(200);
    assert_int_equal(lost(0), 0);
    assert_true(plant_units(&card, 0, now()) > 150);
    int64_t g;
    int64_t l1;
    plant_step_counts(&card, 1, &g, &l1);
    assert_true(g > 290);
    assert_int_equal(l1, g);                           /* the rotor never moved */
    assert_int_equal((int)plant_units(&card, 1, now()), 0);
    wr(0, AX_RATE, 0);                                 /* abrupt stop from below ssf */
    wr(1, AX_RATE, rate_for(600));                     /* back within reach: it locks in */
    advance_ms(100);
    assert_int_equal(lost(0), 0);
    int64_t before = lost(1);
    advance_ms(100);
    assert_int_equal(lost(1), before);                 /* no more steps lost */

    /* ramp up in 200 Hz stairs to 3 kHz, then an abrupt stop: it overshoots */
    wr(2, AX_RATE, rate_for(800));
    wr(3, AX_RATE, rate_for(800));
    for (double f = 1000; f <= 3000; f += 200) {
        advance_ms(5);
        wr(2, AX_RATE, rate_for(f));
    }
    advance_ms(50);
    assert_int_equal(lost(2), 0);
    wr(2, AX_RATE, 0);
    wr(3, AX_RATE, 0);
    advance_ms(100);
    /* overshoot (v^2 - ssf^2) / 2 accel = (9e6 - 1e6) / 5e5 = 16 steps: negative loss */
    assert_true(lost(2) <= -14 && lost(2) >= -18);
    assert_int_equal(lost(3), 0);
    /* the rotor stands on a whole step and the counter counted what was generated */
    assert_int_equal(sext24(counter(2)) - (int32_t)plant_units(&card, 2, now()), (int32_t)lost(2));
}

static void stepper_torque_limit_and_disable(void **st)
{
    (void)st;
    setup_card(MAC4_CARD_STP);
    wr(0, AX_CTRL, AX_CTRL_EN | AX_CTRL_DIR);
    wr(1, AX_CTRL, AX_CTRL_EN | AX_CTRL_DIR);
    wr(0, AX_RATE, rate_for(900));
    wr(1, AX_RATE, rate_for(900));
    /* 900 Hz every 2 ms = 450 000 Hz/s, above the 250 000 steps/s^2 it can do;
     * 900 Hz every 8 ms = 112 500 Hz/s is fine */
    for (int i = 0; i < 40; i++) {
        advance_ms(2);
        if (i % 4 == 3)
            wr(1, AX_RATE, rate_for(900.0 * (1 + (i + 1) / 4)));
        if (i < 10)
            wr(0, AX_RATE, rate_for(900.0 * (i + 2)));
    }
    assert_true(lost(0) > 0);
    assert_false(card.plant.ax[0].sync == 1 && lost(0) == 0);
    assert_int_equal(lost(1), 0);
    /* pulses while the driver is disabled are lost too */
    setup_card(MAC4_CARD_STP);
    wr(2, AX_CTRL, AX_CTRL_DIR);
    wr(2, AX_RATE, rate_for(500));
    advance_ms(100);
    assert_true(lost(2) >= 49 && lost(2) <= 51);
    assert_int_equal((int)plant_units(&card, 2, now()), 0);
    /* BR open: the counter counts the encoder on the motor shaft, 1000 lines,
     * 500 steps/rev: 8 increments per step */
    setup_card(MAC4_CARD_STP);
    card.plant.ax[3].br_steps = 0;
    plant_changed(&card, 3);
    assert_false(rd(3, AX_IN) & AX_IN_BR_STEPS);
    wr(3, AX_CTRL, AX_CTRL_EN | AX_CTRL_DIR | AX_CTRL_IDX_IE | AX_CTRL_IDX_ARM);
    wr(3, AX_PULSES, 600);
    wr(3, AX_RATE, rate_for(800));
    advance_ms(1000);
    assert_int_equal(counter(3), 600 * 8);
    assert_int_equal(idx(3), 4000);            /* one revolution = 500 steps */
    assert_int_equal(irq(), AXIS_IRQ_IDX(3));
}

/* ---- VMEbus slave: the absolute encoder of the manual's SSI example ------------ */
static void vme_encoder_board(void **st)
{
    (void)st;
    setup_card(MAC4_CARD_SSI);
    assert_int_equal(plant_vme_add(&card, 0x80C000, 0, 14, 10000.0, 1, 0, 0), 0);
    plant_set_position(&card, 0, 1.5 * 4096);  /* 1.5 revolutions of the output shaft */
    bus_write(&card, VME_PAGE, 8, 2);
    assert_int_equal(bus_read(&card, VME_WIN_BASE + 0xC000, 2), 5000);
    assert_int_equal(bus_read(&card, VME_STATUS, 2), 0);
    assert_int_equal(bus_read(&card, VME_WIN_BASE + 0xC001, 1), 5000 & 0xFF);
    /* 14 bits: one word; nothing answers at +2 */
    assert_int_equal(bus_read(&card, VME_WIN_BASE + 0xC002, 2), 0xFFFF);
    assert_int_equal(bus_read(&card, VME_STATUS, 2), VME_ST_BERR);
    assert_int_equal(bus_read(&card, VME_STATUS, 2), 0);
    bus_write(&card, VME_PAGE, 7, 2);
    assert_int_equal(bus_read(&card, VME_WIN_BASE + 0xC000, 2), 0xFFFF);
    assert_int_equal(bus_read(&card, VME_STATUS, 2), VME_ST_BERR);
    /* it turns with the shaft */
    bus_write(&card, VME_PAGE, 8, 2);
    wr(0, AX_CTRL, AX_CTRL_EN);
    wr(0, AX_DAC, 1000);
    advance_ms(200);
    uint32_t v = bus_read(&card, VME_WIN_BASE + 0xC000, 2);
    assert_true(v > 5000 && v < 10000);
    /* more than 16 bits: MSW at base, LSW at base+2; reading the LSW latches */
    assert_int_equal(plant_vme_add(&card, 0x80D000, 0, 24, 10000.0, 1000, 0, 0), 0);
    wr(0, AX_DAC, 0);
    advance_ms(100);
    plant_set_position(&card, 0, 7.25 * 4096);
    uint32_t lo = bus_read(&card, VME_WIN_BASE + 0xD002, 2);
    wr(0, AX_DAC, 2047);
    advance_ms(100);   /* the value moves on, the latched MSW does not */
    uint32_t hi = bus_read(&card, VME_WIN_BASE + 0xD000, 2);
    assert_int_equal(hi << 16 | lo, 72500);
    assert_int_equal(bus_read(&card, VME_STATUS, 2), 0);
    assert_int_equal(plant_vme_remove(&card, 0x80C000), 0);
    assert_int_equal(bus_read(&card, VME_WIN_BASE + 0xC000, 2), 0xFFFF);
}

static void trace_writes_csv(void **st)
{
    (void)st;
    setup_card(MAC4_CARD_INC);
    char path[] = "/tmp/test_plant_traceXXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    assert_int_equal(plant_trace_start(&card, 0, path, US_TO_CYC(500)), 0);
    wr(0, AX_CTRL, AX_CTRL_EN);
    wr(0, AX_DAC, 1000);
    advance_ms(10);
    plant_trace_stop(&card, 0);
    FILE *f = fopen(path, "r");
    char line[256];
    int rows = 0;
    double last_pos = -1;
    assert_non_null(fgets(line, sizeof line, f));
    assert_string_equal(line, "t_ms,dac,volts,en,position,velocity,motor_rpm,counter\n");
    while (fgets(line, sizeof line, f)) {
        double t, volts, pos, vel, rpm;
        int dac, en;
        unsigned cnt;
        assert_int_equal(sscanf(line, "%lf,%d,%lf,%d,%lf,%lf,%lf,%u", &t, &dac, &volts, &en, &pos, &vel, &rpm, &cnt), 8);
        assert_true(pos >= last_pos);
        last_pos = pos;
        rows++;
    }
    fclose(f);
    close(fd);
    unlink(path);
    assert_int_equal(rows, 21);   /* 0, 0.5, ... 10 ms */
    assert_true(last_pos > 10);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(reset_states),
        cmocka_unit_test(positive_dac_counts_up),
        cmocka_unit_test(reads_see_the_cycle_they_happen),
        cmocka_unit_test(disabled_amplifier_coasts_and_estop_disables),
        cmocka_unit_test(index_latches_once_per_revolution),
        cmocka_unit_test(default_plant_is_stable_for_k_1_to_50),
        cmocka_unit_test(index_interrupt_timing_after_accesses),
        cmocka_unit_test(counter_wraps_at_2_24),
        cmocka_unit_test(encoder_faults),
        cmocka_unit_test(switch_levels_and_polarity),
        cmocka_unit_test(ssi_gray_binary_placement_and_busy_time),
        cmocka_unit_test(timer_expiry_starts_the_synced_ssi_reads),
        cmocka_unit_test(step_generator_frequencies),
        cmocka_unit_test(pulse_down_counter_and_interrupts),
        cmocka_unit_test(stepper_start_stop_frequency),
        cmocka_unit_test(stepper_torque_limit_and_disable),
        cmocka_unit_test(vme_encoder_board),
        cmocka_unit_test(trace_writes_csv),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
