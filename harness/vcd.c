/*
 * vcd.c - the card's signals as a Value Change Dump (docs/debugging.md).
 *
 * Register outputs (DAC word, /EN, DIR, BOOST, step rate, display, LEDs),
 * the interrupt request lines and the level presented to the CPU are looked
 * at whenever the emulator re-evaluates the interrupt lines (sim_update_irq:
 * after every I/O access and at every scheduler slice), so each change
 * carries the cycle of the access that made it.  The handler running comes
 * from the interrupt accounting (acknowledge to the end of RTE).
 *
 * The plant counts and does not produce edges; they are made here at their
 * true times.  The encoder lines A/B/Z, the counter and the limit and
 * reference inputs from the linear pieces of the mechanics (plant.c reports
 * each piece as it ends; the piece in progress is read at every flush): a
 * line changes where the position crosses the boundary of an increment,
 * found by solving the piece for that position, to 100 ps.  STEP pulses from
 * the step generator's accumulator: pulse j comes at the clock edge where
 * the accumulator carries, as plant.c counts them.  The UART's TxD and RxD
 * and the SSI clock and data are laid out bit by bit when a character or a
 * read starts, since their timing is fixed from then on.
 *
 * Events are buffered and written in time order up to the time every model
 * has been brought to (the minimum of the plant axes' sync times).
 */
#include <stdlib.h>
#include <string.h>
#include "vcd.h"
#include "periph.h"
#include "plant.h"

#define UNITS_PER_CYC 625u          /* 100 ps units in one 62.5 ns cycle */
#define NAX MAC4_NAXES

/* ---- the signals ------------------------------------------------------- */
enum {
    /* card */
    S_IRQ4, S_IRQ5, S_IRQ6, S_IRQ7, S_IPL, S_HANDLER, S_TXD, S_RXD, S_DIGIT, S_DP, S_LEDS, S_STOP,
    S_CARD_N,
    /* per axis, at S_CARD_N + n * S_AX_N */
    A_DAC = 0, A_RATE, A_EN_N, A_DIR, A_BOOST, A_COUNTER, A_A, A_B, A_Z, A_STEP, A_IESP, A_IESN, A_RS,
    A_DF, A_SSI_CLK, A_SSI_DATA, S_AX_N
};
#define NSIG (S_CARD_N + NAX * S_AX_N)
#define AXS(n, a) (S_CARD_N + (n) * S_AX_N + (a))

typedef struct {
    const char *name;
    int width;
    const char *what;
    unsigned cards;                 /* bit per MAC4_CARD_* */
} sigdef_t;

#define ALL 7u
#define INC (1u << MAC4_CARD_INC)
#define SSI (1u << MAC4_CARD_SSI)
#define STP (1u << MAC4_CARD_STP)
static const sigdef_t card_sigs[S_CARD_N] = {
    {"irq4_uart", 1, "interrupt request, level 4 (UART)", ALL},
    {"irq5_axis", 1, "interrupt request, level 5 (axis board)", ALL},
    {"irq6_timer", 1, "interrupt request, level 6 (timer)", ALL},
    {"irq7_stop", 1, "interrupt request, level 7 (/STOP edge)", ALL},
    {"ipl", 3, "interrupt level presented to the 68000", ALL},
    {"handler", 3, "level of the interrupt handler running, acknowledge to RTE (0: none)", ALL},
    {"txd", 1, "serial line, card to host (1 = idle, mark)", ALL},
    {"rxd", 1, "serial line, host to card", ALL},
    {"digit", 4, "7-segment display digit", ALL},
    {"dp", 1, "7-segment decimal point", ALL},
    {"leds", 16, "LED register (D, P, F per axis n at bits 4n..)", ALL},
    {"stop", 1, "/STOP input active (the STOP LED)", ALL},
};
static const sigdef_t ax_sigs[S_AX_N] = {
    {"dac", 12, "DAC word (12-bit two's complement)", INC | SSI},
    {"rate", 16, "step rate register", STP},
    {"en_n", 1, "/EN output (0 = axis enabled)", ALL},
    {"dir", 1, "DIR (1 = positive)", STP},
    {"boost", 1, "BOOST output", STP},
    {"counter", 24, "position counter", INC | STP},
    {"enc_a", 1, "encoder track A", INC},
    {"enc_b", 1, "encoder track B", INC},
    {"enc_z", 1, "encoder index Z", INC},
    {"step", 1, "STEP output pulses", STP},
    {"iesp", 1, "limit switch + input (1 = high, 0 = at 0 V: LED lit)", ALL},
    {"iesn", 1, "limit switch - input", ALL},
    {"rs", 1, "reference switch input", ALL},
    {"df", 1, "drive fault input", ALL},
    {"ssi_clk", 1, "SSI clock (idle high)", SSI},
    {"ssi_data", 1, "SSI data", SSI},
};

typedef struct {
    uint64_t t;                     /* 100 ps units */
    uint64_t seq;
    uint32_t sig, val;
} vev_t;

typedef struct vcd {
    FILE *f;
    int on[NSIG];
    char id[NSIG][4];
    uint32_t cur[NSIG];             /* the last value given (written or pending) */
    uint32_t written[NSIG];
    int have_written[NSIG];
    vev_t *ev;
    size_t nev, cap;
    uint64_t seq, last_t;
    int wrote_time;
    /* edge synthesis per axis */
    double until[NAX];              /* cycles up to which the mechanics' edges are made */
    int64_t k[NAX];                 /* position (rounded units) at `until` */
    cyc_t ssi_start[NAX];
    cyc_t tx_done, rx_done;
} vcd_t;

static int sig_exists(int card, int sig)
{
    if (sig < S_CARD_N)
        return (card_sigs[sig].cards >> card) & 1;
    return (ax_sigs[(sig - S_CARD_N) % S_AX_N].cards >> card) & 1;
}

static void sig_name(int sig, char *buf, size_t len)
{
    if (sig < S_CARD_N)
        snprintf(buf, len, "card.%s", card_sigs[sig].name);
    else
        snprintf(buf, len, "axis%d.%s", (sig - S_CARD_N) / S_AX_N + 1, ax_sigs[(sig - S_CARD_N) % S_AX_N].name);
}

static int sig_width(int sig) { return sig < S_CARD_N ? card_sigs[sig].width : ax_sigs[(sig - S_CARD_N) % S_AX_N].width; }

void vcd_list(FILE *f, int card)
{
    char b[64];
    for (int i = 0; i < NSIG; i++)
        if (sig_exists(card, i)) {
            sig_name(i, b, sizeof b);
            fprintf(f, "vcd-signal %s %d %s\n", b, sig_width(i),
                    i < S_CARD_N ? card_sigs[i].what : ax_sigs[(i - S_CARD_N) % S_AX_N].what);
        }
}

/* ---- buffer and writer ------------------------------------------------------ */
static void put(vcd_t *v, uint64_t t, int sig, uint32_t val)
{
    if (!v->on[sig])
        return;
    val &= sig_width(sig) >= 32 ? 0xFFFFFFFFu : (1u << sig_width(sig)) - 1u;
    if (v->nev == v->cap) {
        size_t nc = v->cap ? v->cap * 2 : 4096;
        vev_t *ne = realloc(v->ev, nc * sizeof *ne);
        if (!ne)
            return;
        v->ev = ne;
        v->cap = nc;
    }
    v->ev[v->nev++] = (vev_t){t, v->seq++, (uint32_t)sig, val};
}

/* A register-like value looked at now: only its changes. */
static void look(vcd_t *v, uint64_t t, int sig, uint32_t val)
{
    if (!v->on[sig] || v->cur[sig] == val)
        return;
    v->cur[sig] = val;
    put(v, t, sig, val);
}

static int by_time(const void *a, const void *b)
{
    const vev_t *x = a, *y = b;
    if (x->t != y->t)
        return x->t < y->t ? -1 : 1;
    return x->seq < y->seq ? -1 : x->seq > y->seq;
}

static void write_value(vcd_t *v, int sig, uint32_t val)
{
    int w = sig_width(sig);
    if (w == 1) {
        fprintf(v->f, "%u%s\n", val & 1u, v->id[sig]);
        return;
    }
    char b[40];
    int k = 0;
    int top = w - 1;
    while (top > 0 && !((val >> top) & 1u))
        top--;
    for (int i = top; i >= 0; i--)
        b[k++] = (char)('0' + ((val >> i) & 1u));
    b[k] = 0;
    fprintf(v->f, "b%s %s\n", b, v->id[sig]);
}

/* Write the events up to (and including) time `upto`. */
static void flush_to(vcd_t *v, uint64_t upto)
{
    if (!v->nev)
        return;
    qsort(v->ev, v->nev, sizeof *v->ev, by_time);
    size_t i = 0;
    for (; i < v->nev && v->ev[i].t <= upto; i++) {
        vev_t *e = &v->ev[i];
        if (v->have_written[e->sig] && v->written[e->sig] == e->val)
            continue;
        uint64_t t = e->t < v->last_t ? v->last_t : e->t;
        if (!v->wrote_time || t != v->last_t) {
            fprintf(v->f, "#%llu\n", (unsigned long long)t);
            v->last_t = t;
            v->wrote_time = 1;
        }
        write_value(v, (int)e->sig, e->val);
        v->written[e->sig] = e->val;
        v->have_written[e->sig] = 1;
    }
    memmove(v->ev, v->ev + i, (v->nev - i) * sizeof *v->ev);
    v->nev -= i;
}

/* no libm: the unit tests link the harness without it */
static uint64_t units(double cyc) { return cyc <= 0 ? 0 : (uint64_t)(cyc * UNITS_PER_CYC + 0.5); }
static int64_t ifloor(double x)
{
    int64_t i = (int64_t)x;
    return (double)i > x ? i - 1 : i;
}
#define floor(x) ((double)ifloor(x))

/* ---- the mechanics: edges where the position crosses an increment ------------- */
static int is_servo(sim_t *s) { return s->card != MAC4_CARD_STP; }

/* position in the axis' units (plant_units) from the piece's x */
static double x_units(sim_t *s, int n, double x)
{
    if (!is_servo(s))
        return x;                   /* the STP out of step: rotor steps */
    return x / s->plant.ax[n].gear * plant_units_per_rev(s, n);
}

static void switches(vcd_t *v, sim_t *s, int n, uint64_t t, int64_t k)
{
    plant_axis_t *p = &s->plant.ax[n];
    static const int sig[PLANT_NSW] = {A_IESP, A_IESN, A_RS};
    for (int w = 0; w < PLANT_NSW; w++) {
        /* AX_IN: an input is at 0 V when a low-active switch is on or a
         * high-active one off (plant_inputs_word) */
        int low = p->sw[w].used && (plant_switch_at(p, w, k) ^ p->sw[w].high);
        look(v, t, AXS(n, sig[w]), (uint32_t)!low);
    }
}

/* The state of the lines at position k (rounded units), from time t. */
static void lines_at(vcd_t *v, sim_t *s, int n, uint64_t t, int64_t k)
{
    plant_axis_t *p = &s->plant.ax[n];
    switches(v, s, n, t, k);
    if (s->card != MAC4_CARD_INC || p->enc_fault != PLANT_ENC_OK)
        return;                     /* frozen or stuck: the lines stand still */
    static const uint8_t quad[4] = {0, 2, 3, 1};   /* B A: 00 10 11 01, A leads B counting up */
    unsigned ph = (unsigned)(k & 3);
    look(v, t, AXS(n, A_A), (quad[ph] >> 1) & 1u);
    look(v, t, AXS(n, A_B), quad[ph] & 1u);
    int64_t per = 4 * (int64_t)p->lines, idx = (int64_t)(p->index % (4u * p->lines));
    look(v, t, AXS(n, A_Z), (uint32_t)((((k % per) + per) % per) == idx));
    look(v, t, AXS(n, A_COUNTER), (uint32_t)((uint64_t)(k + s->ax[n].cnt_off) & 0xFFFFFFu));
}

static void edges(sim_t *s, int n, double ta, double xa, double tb, double xb)
{
    vcd_t *v = s->vcd;
    if (tb <= v->until[n] || tb <= ta)
        return;
    double t0 = ta > v->until[n] ? ta : v->until[n];
    double ua = x_units(s, n, xa), ub = x_units(s, n, xb);
    double u0 = ua + (ub - ua) * (t0 - ta) / (tb - ta);
    int64_t k0 = (int64_t)floor(u0 + 0.5), k1 = (int64_t)floor(ub + 0.5);
    if (k0 != v->k[n])              /* moved by hand (plant pos), or the first piece */
        lines_at(v, s, n, units(t0), k0);
    v->k[n] = k0;
    if (k1 - k0 > 100000 || k0 - k1 > 100000) {
        lines_at(v, s, n, units(tb), k1);   /* not a motion: a jump */
    } else {
        while (v->k[n] != k1) {
            int up = k1 > v->k[n];
            int64_t m = up ? v->k[n] + 1 : v->k[n] - 1;
            double uc = up ? (double)m - 0.5 : (double)m + 0.5;
            double tc = ta + (uc - ua) / (ub - ua) * (tb - ta);
            if (tc < t0)
                tc = t0;
            if (tc > tb)
                tc = tb;
            lines_at(v, s, n, units(tc), m);
            v->k[n] = m;
        }
    }
    v->until[n] = tb;
}

void vcd_piece(sim_t *s, int n, cyc_t ta, double xa, cyc_t tb, double xb)
{
    edges(s, n, (double)ta, xa, (double)tb, xb);
}

void vcd_pulses(sim_t *s, int n, cyc_t nco_t0, uint32_t acc0, uint64_t c)
{
    vcd_t *v = s->vcd;
    plant_axis_t *p = &s->plant.ax[n];
    axis_hw_t *a = &s->ax[n];
    int d = (a->ctrl & AX_CTRL_DIR) ? 1 : -1;
    cyc_t P = axb_step_period(s, n);
    cyc_t wid = P / 2 ? P / 2 : 1;
    int en = (a->ctrl & AX_CTRL_EN) && !s->sys.estop && !p->drive_fault;
    int64_t gen0 = p->gen - d * (int64_t)c;
    int64_t rot0 = p->cmd + p->off - (en ? d * (int64_t)c : 0);
    if (c > 1000000)
        c = 1000000;
    for (uint64_t j = 1; j <= c; j++) {
        cyc_t t = axb_step_pulse_time(s, n, nco_t0, acc0, j);
        put(v, units((double)t), AXS(n, A_STEP), 1);
        put(v, units((double)(t + wid)), AXS(n, A_STEP), 0);
        if (p->br_steps)
            look(v, units((double)t), AXS(n, A_COUNTER),
                 (uint32_t)((uint64_t)(gen0 + d * (int64_t)j + a->cnt_off) & 0xFFFFFFu));
        if (p->sync && en)
            switches(v, s, n, units((double)t), rot0 + d * (int64_t)j);
    }
    v->cur[AXS(n, A_STEP)] = 0;
    if (p->sync)
        v->k[n] = p->cmd + p->off;
}

/* ---- serial lines and SSI frames, laid out when they start --------------------- */
static void uart_char(vcd_t *v, int sig, cyc_t start, uint8_t byte)
{
    double bit = (double)UART_CHAR_CYC / 10.0;
    put(v, units((double)start), sig, 0);                       /* start bit */
    for (int i = 0; i < 8; i++)
        put(v, units((double)start + bit * (i + 1)), sig, (byte >> i) & 1u);
    put(v, units((double)start + bit * 9), sig, 1);              /* stop bit */
    v->cur[sig] = 1;
}

static void ssi_frame(vcd_t *v, sim_t *s, int n)
{
    axis_hw_t *p = &s->ax[n];                  /* the board's SSI receiver */
    double T = (double)(p->ssi_end - p->ssi_start) / SSI_FRAME_BITS;
    double t0 = (double)p->ssi_start;
    for (int k = 1; k <= SSI_FRAME_BITS; k++) {
        put(v, units(t0 + (k - 0.5) * T), AXS(n, A_SSI_CLK), 0);
        put(v, units(t0 + (k - 0.5) * T), AXS(n, A_SSI_DATA), (p->ssi_frame >> (SSI_FRAME_BITS - k)) & 1u);
        put(v, units(t0 + k * T), AXS(n, A_SSI_CLK), 1);   /* the receiver takes bit k here */
    }
    put(v, units((double)p->ssi_end), AXS(n, A_SSI_DATA), 1);
    v->cur[AXS(n, A_SSI_CLK)] = v->cur[AXS(n, A_SSI_DATA)] = 1;
}

/* ---- looking at the registers ---------------------------------------------------- */
static const int level_of_src[SRC_COUNT] = {IRQ_LEVEL_UART, IRQ_LEVEL_AXIS, IRQ_LEVEL_TIMER, IRQ_LEVEL_ESTOP, 0};

void vcd_handler(sim_t *s, cyc_t t)
{
    vcd_t *v = s->vcd;
    int lvl = s->nactive ? level_of_src[s->active[s->nactive - 1].src] : 0;
    look(v, units((double)t), S_HANDLER, (uint32_t)lvl);
}

static void registers(vcd_t *v, sim_t *s, uint64_t t, cyc_t now)
{
    unsigned lines = sim_irq_lines(s);
    look(v, t, S_IRQ4, (lines >> IRQ_LEVEL_UART) & 1u);
    look(v, t, S_IRQ5, (lines >> IRQ_LEVEL_AXIS) & 1u);
    look(v, t, S_IRQ6, (lines >> IRQ_LEVEL_TIMER) & 1u);
    look(v, t, S_IRQ7, (lines >> IRQ_LEVEL_ESTOP) & 1u);
    look(v, t, S_IPL, (uint32_t)sim_irq_level(s));
    look(v, t, S_DIGIT, s->sys.display & 0xFu);
    look(v, t, S_DP, !!(s->sys.display & SYS_DISPLAY_DP));
    look(v, t, S_LEDS, s->sys.leds);
    look(v, t, S_STOP, (uint32_t)!!s->sys.estop);
    uart_t *u = &s->uart;
    if (u->tx_busy && u->tx_done != v->tx_done) {
        v->tx_done = u->tx_done;
        uart_char(v, S_TXD, u->tx_done - UART_CHAR_CYC, u->tx_shift);
    }
    if (u->rx_done != CYC_NEVER && u->rx_done != v->rx_done && u->wire_tail != u->wire_head) {
        v->rx_done = u->rx_done;
        uart_char(v, S_RXD, u->rx_done - UART_CHAR_CYC, u->wire[u->wire_tail]);
    }
    for (int n = 0; n < NAX; n++) {
        axis_hw_t *a = &s->ax[n];
        plant_axis_t *p = &s->plant.ax[n];
        look(v, t, AXS(n, A_DAC), (uint32_t)(uint16_t)a->dac);
        look(v, t, AXS(n, A_RATE), a->rate);
        look(v, t, AXS(n, A_EN_N), (uint32_t)!((a->ctrl & AX_CTRL_EN) && !s->sys.estop));
        look(v, t, AXS(n, A_DIR), !!(a->ctrl & AX_CTRL_DIR));
        look(v, t, AXS(n, A_BOOST), !!(a->ctrl & AX_CTRL_BOOST));
        look(v, t, AXS(n, A_DF), (uint32_t)!(p->drive_fault ^ p->df_high));
        /* a counter cleared or set by the firmware: the axis is synced to now */
        if (p->t_sync == now && s->card != MAC4_CARD_SSI)
            look(v, t, AXS(n, A_COUNTER), a->counter & 0xFFFFFFu);
        if (s->card == MAC4_CARD_SSI && a->ssi_end > a->ssi_start && a->ssi_start != v->ssi_start[n]) {
            v->ssi_start[n] = a->ssi_start;
            ssi_frame(v, s, n);
        }
    }
}

/* Axis n is synced: its edges up to there, the piece in progress included
 * (before anything that happens at that instant, a counter cleared by the
 * access that synced it). */
void vcd_synced(sim_t *s, int n)
{
    vcd_t *v = s->vcd;
    plant_axis_t *p = &s->plant.ax[n];
    if (!is_servo(s) && p->sync) {      /* the rotor follows the pulses (vcd_pulses) */
        int64_t k = p->cmd + p->off;
        if (k != v->k[n])               /* moved by hand */
            switches(v, s, n, units((double)p->t_sync), k);
        v->k[n] = k;
        v->until[n] = (double)p->t_sync;
        return;
    }
    if (p->t1 != CYC_NEVER && p->t_sync > p->t0) {
        double tb = (double)p->t_sync;
        double xb = p->x0 + (p->x1 - p->x0) * (tb - (double)p->t0) / (double)(p->t1 - p->t0);
        edges(s, n, (double)p->t0, p->x0, tb, xb);
        return;
    }
    int64_t k = (int64_t)floor(x_units(s, n, p->x0) + 0.5);
    if (k != v->k[n])                   /* at rest, moved by hand */
        lines_at(v, s, n, units((double)p->t_sync), k);
    v->k[n] = k;
    if ((double)p->t_sync > v->until[n])
        v->until[n] = (double)p->t_sync;
}

/* Everything before the earliest time an axis is synced to. */
static void flush(sim_t *s)
{
    vcd_t *v = s->vcd;
    cyc_t upto = sim_now(s);
    for (int n = 0; n < NAX; n++)
        if (s->plant.ax[n].t_sync < upto)
            upto = s->plant.ax[n].t_sync;
    flush_to(v, units((double)upto));
}

void vcd_sample(sim_t *s)
{
    vcd_t *v = s->vcd;
    cyc_t now = sim_now(s);
    registers(v, s, units((double)now), now);
    if (v->nev > 65536)
        flush(s);
}

/* ---- open and close ---------------------------------------------------------------- */
static void make_id(char *id, int i)
{
    /* printable identifiers: ! .. ~ (94 symbols), two characters when needed */
    if (i < 94) {
        id[0] = (char)('!' + i);
        id[1] = 0;
    } else {
        id[0] = (char)('!' + i / 94);
        id[1] = (char)('!' + i % 94);
        id[2] = 0;
    }
}

static int select_signals(vcd_t *v, int card, const char *list, char *err, size_t errlen)
{
    if (!list || !*list || !strcmp(list, "all")) {
        for (int i = 0; i < NSIG; i++)
            v->on[i] = sig_exists(card, i);
        return 0;
    }
    char buf[1024];
    snprintf(buf, sizeof buf, "%s", list);
    for (char *t = strtok(buf, ","); t; t = strtok(NULL, ",")) {
        int found = 0;
        for (int i = 0; i < NSIG; i++) {
            char full[64];
            sig_name(i, full, sizeof full);
            const char *bare = strchr(full, '.') + 1;
            if (sig_exists(card, i) && (!strcmp(t, full) || !strcmp(t, bare))) {
                v->on[i] = 1;
                found = 1;
            }
        }
        if (!found) {
            snprintf(err, errlen, "vcd: no signal '%s' on this card (vcd signals lists them)", t);
            return -1;
        }
    }
    return 0;
}

int vcd_open(sim_t *s, const char *path, const char *signals, char *err, size_t errlen)
{
    vcd_close(s);
    vcd_t *v = calloc(1, sizeof *v);
    if (!v) {
        snprintf(err, errlen, "vcd: out of memory");
        return -1;
    }
    if (select_signals(v, s->card, signals, err, errlen)) {
        free(v);
        return -1;
    }
    v->f = fopen(path, "w");
    if (!v->f) {
        snprintf(err, errlen, "vcd: cannot write '%s'", path);
        free(v);
        return -1;
    }
    static const char *const cardname[3] = {"MAC4-INC", "MAC4-SSI", "MAC4-STP"};
    fprintf(v->f, "$version mac4sim, the emulated %s $end\n", cardname[s->card % 3]);
    fprintf(v->f, "$comment time 0 is the power-on reset; 625 units of 100 ps are one 68000 cycle at 16 MHz $end\n");
    fprintf(v->f, "$timescale 100ps $end\n$scope module mac4 $end\n");
    int id = 0;
    for (int scope = -1; scope < NAX; scope++) {
        int lo = scope < 0 ? 0 : AXS(scope, 0), hi = scope < 0 ? S_CARD_N : AXS(scope, S_AX_N);
        int any = 0;
        for (int i = lo; i < hi; i++)
            any |= v->on[i];
        if (!any)
            continue;
        if (scope < 0)
            fprintf(v->f, "$scope module card $end\n");
        else
            fprintf(v->f, "$scope module axis%d $end\n", scope + 1);
        for (int i = lo; i < hi; i++) {
            if (!v->on[i])
                continue;
            make_id(v->id[i], id++);
            const char *nm = i < S_CARD_N ? card_sigs[i].name : ax_sigs[(i - S_CARD_N) % S_AX_N].name;
            fprintf(v->f, "$var wire %d %s %s $end\n", sig_width(i), v->id[i], nm);
        }
        fprintf(v->f, "$upscope $end\n");
    }
    fprintf(v->f, "$upscope $end\n$enddefinitions $end\n");
    s->vcd = v;
    /* initial values: everything as it is now */
    cyc_t now = sim_now(s);
    uint64_t t = units((double)now);
    for (int i = 0; i < NSIG; i++)
        v->cur[i] = 0xFFFFFFFFu;     /* differs from every value: all are given */
    v->tx_done = s->uart.tx_done;
    v->rx_done = s->uart.rx_done;
    for (int n = 0; n < NAX; n++) {
        v->ssi_start[n] = s->ax[n].ssi_start;
        v->cur[AXS(n, A_SSI_CLK)] = v->cur[AXS(n, A_SSI_DATA)] = 0xFFFFFFFFu;
        look(v, t, AXS(n, A_SSI_CLK), 1);
        look(v, t, AXS(n, A_SSI_DATA), 1);
        look(v, t, AXS(n, A_STEP), 0);
        int64_t k = (int64_t)floor(plant_units(s, n, now) + 0.5);
        lines_at(v, s, n, t, k);
        if (s->card != MAC4_CARD_INC)
            look(v, t, AXS(n, A_COUNTER), s->ax[n].counter & 0xFFFFFFu);
        v->k[n] = k;
        v->until[n] = (double)now;
    }
    look(v, t, S_TXD, 1);
    look(v, t, S_RXD, 1);
    vcd_handler(s, now);
    registers(v, s, t, now);
    fprintf(v->f, "#%llu\n$dumpvars\n", (unsigned long long)t);
    qsort(v->ev, v->nev, sizeof *v->ev, by_time);
    for (size_t i = 0; i < v->nev; i++) {
        write_value(v, (int)v->ev[i].sig, v->ev[i].val);
        v->written[v->ev[i].sig] = v->ev[i].val;
        v->have_written[v->ev[i].sig] = 1;
    }
    fprintf(v->f, "$end\n");
    v->nev = 0;
    v->last_t = t;
    v->wrote_time = 1;
    return 0;
}

void vcd_close(sim_t *s)
{
    vcd_t *v = s->vcd;
    if (!v)
        return;
    flush(s);
    flush_to(v, UINT64_MAX);        /* what was laid out ahead (a character, a frame) */
    fclose(v->f);
    free(v->ev);
    free(v);
    s->vcd = NULL;
}
