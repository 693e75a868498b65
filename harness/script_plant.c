/* script_plant.c - host-script commands of the plant models (docs/host-script.md,
 * "Plant"; the models are described in docs/plant.md). */
#include <stdlib.h>
#include <string.h>
#include "script.h"
#include "cpu.h"
#include "plant.h"

static int parse_axis(script_t *sc, const char *t, int *n)
{
    long long v;
    if (script_parse_num(t, &v) || v < 0 || v >= MAC4_NAXES)
        return script_err(sc, "bad axis '%s' (0..3)", t);
    *n = (int)v;
    return 0;
}

static int parse_double(script_t *sc, const char *t, double *out, double min, double max)
{
    double v;
    if (script_parse_real(t, &v) || !(v >= min && v <= max))
        return script_err(sc, "bad or out-of-range number '%s'", t);
    *out = v;
    return 0;
}

static int parse_int(script_t *sc, const char *t, long long *out, long long min, long long max)
{
    if (script_parse_num(t, out) || *out < min || *out > max)
        return script_err(sc, "bad or out-of-range number '%s'", t);
    return 0;
}

/* Changing the sensor mapping must not make a relative counter jump. */
typedef struct {
    uint32_t counter;
} edit_t;

static edit_t edit_begin(sim_t *s, int n)
{
    edit_t e = {axb_counter(s, n, sim_now(s))};
    return e;
}

static void edit_end(sim_t *s, int n, edit_t e)
{
    plant_changed(s, n);
    if (s->card != MAC4_CARD_SSI)
        axb_counter_set(s, n, sim_now(s), e.counter);
}

static void print_axis(sim_t *s, int n)
{
    char buf[512];
    plant_format(s, n, buf, sizeof buf);
    sim_printf(s, "%s\n", buf);
}

/* plant AXIS motor KEY VALUE ... */
static int cmd_motor(script_t *sc, sim_t *s, int n, char **tok, int nt)
{
    plant_sync(s, n, sim_now(s));   /* before copying: the copy includes the state */
    plant_axis_t *p = &s->plant.ax[n], c = *p;
    if (nt < 2 || nt % 2)
        return script_err(sc, "usage: %s", "plant AXIS motor KEY VALUE ... (rpm tau inertia kt imax visc "
                                            "coulomb load amps mode)");
    for (int i = 0; i < nt; i += 2) {
        const char *k = tok[i], *v = tok[i + 1];
        double d = 0;
        if (!strcmp(k, "mode")) {
            if (!strcmp(v, "velocity"))
                c.amp = PLANT_AMP_VELOCITY;
            else if (!strcmp(v, "current"))
                c.amp = PLANT_AMP_CURRENT;
            else
                return script_err(sc, "bad amplifier mode '%s' (velocity|current)", v);
            continue;
        }
        if (!strcmp(k, "load")) {
            if (parse_double(sc, v, &c.load, -1e6, 1e6))
                return -1;
            continue;
        }
        if (parse_double(sc, v, &d, 0.0, 1e9))
            return -1;
        if (!strcmp(k, "rpm") && d > 0)
            c.rpm10 = d;
        else if (!strcmp(k, "tau") && d > 0)
            c.tau = d / 1000.0;
        else if (!strcmp(k, "inertia") && d > 0)
            c.inertia = d;
        else if (!strcmp(k, "kt") && d > 0)
            c.kt = d;
        else if (!strcmp(k, "imax") && d > 0)
            c.imax = d;
        else if (!strcmp(k, "amps"))
            c.amps10 = d;
        else if (!strcmp(k, "visc"))
            c.visc = d;
        else if (!strcmp(k, "coulomb"))
            c.coulomb = d;
        else
            return script_err(sc, "bad motor parameter or value near '%s'", k);
    }
    *p = c;
    plant_changed(s, n);
    return 0;
}

static int cmd_plant(script_t *sc, sim_t *s, char **tok, int nt)
{
    int n = 0;
    if (nt == 1) {
        for (int a = 0; a < MAC4_NAXES; a++)
            print_axis(s, a);
        return 0;
    }
    if (parse_axis(sc, tok[1], &n))
        return -1;
    if (nt == 2) {
        print_axis(s, n);
        return 0;
    }
    plant_axis_t *p = &s->plant.ax[n];
    const char *what = tok[2];
    if (!strcmp(what, "motor"))
        return cmd_motor(sc, s, n, tok + 3, nt - 3);
    if (!strcmp(what, "gear")) {
        double g = 1;
        if (nt != 4 || parse_double(sc, tok[3], &g, 1e-6, 1e6))
            return nt != 4 ? script_err(sc, "usage: %s", "plant AXIS gear RATIO") : -1;
        edit_t e = edit_begin(s, n);
        if (s->card != MAC4_CARD_STP)   /* keep the output shaft where it is */
            p->x0 = p->x1 = p->x0 / p->gear * g;
        p->gear = g;
        edit_end(s, n, e);
        return 0;
    }
    if (!strcmp(what, "encoder")) {
        long long lines = p->lines, index = p->index;
        for (int i = 3; i < nt; i += 2) {
            if (i + 1 >= nt)
                return script_err(sc, "usage: %s", "plant AXIS encoder [lines N] [index I]");
            if (!strcmp(tok[i], "lines")) {
                if (parse_int(sc, tok[i + 1], &lines, 1, 1000000))
                    return -1;
            } else if (!strcmp(tok[i], "index")) {
                if (parse_int(sc, tok[i + 1], &index, 0, 3999999))
                    return -1;
            } else {
                return script_err(sc, "bad encoder parameter '%s' (lines, index)", tok[i]);
            }
        }
        if (index >= 4 * lines)
            return script_err(sc, "index increment %s beyond one revolution (4 x lines)", tok[nt - 1]);
        edit_t e = edit_begin(s, n);
        p->lines = (uint32_t)lines;
        p->index = (uint32_t)index;
        edit_end(s, n, e);
        return 0;
    }
    if (!strcmp(what, "ssi")) {
        long long bits = p->ssi_bits;
        double res = p->ssi_res;
        int gray = s->ax[n].gray;
        for (int i = 3; i < nt; i++) {
            if (!strcmp(tok[i], "gray"))
                gray = 1;
            else if (!strcmp(tok[i], "binary"))
                gray = 0;
            else if (!strcmp(tok[i], "bits") && i + 1 < nt) {
                if (parse_int(sc, tok[++i], &bits, 1, 24))
                    return -1;
            } else if (!strcmp(tok[i], "res") && i + 1 < nt) {
                if (parse_double(sc, tok[++i], &res, 1e-3, 1e9))
                    return -1;
            } else
                return script_err(sc, "usage: %s", "plant AXIS ssi [bits N] [gray|binary] [res COUNTS]");
        }
        plant_sync(s, n, sim_now(s));
        p->ssi_bits = (int)bits;
        p->ssi_res = res;
        s->ax[n].gray = gray;
        plant_changed(s, n);
        return 0;
    }
    if (!strcmp(what, "wiring")) {
        if (nt != 4 || (strcmp(tok[3], "normal") && strcmp(tok[3], "reversed")))
            return script_err(sc, "usage: %s", "plant AXIS wiring normal|reversed");
        if (s->card == MAC4_CARD_STP)
            return script_err(sc, "%s: the servo cards only (MAC4-INC, MAC4-SSI)", "plant AXIS wiring");
        plant_sync(s, n, sim_now(s));
        p->reversed = !strcmp(tok[3], "reversed");
        plant_changed(s, n);
        return 0;
    }
    if (!strcmp(what, "pos")) {
        double u = 0;
        if (nt != 4 || parse_double(sc, tok[3], &u, -1e15, 1e15))
            return nt != 4 ? script_err(sc, "usage: %s", "plant AXIS pos POSITION") : -1;
        plant_set_position(s, n, u);
        return 0;
    }
    if (!strcmp(what, "leadscrew")) {
        /* the load behind a leadscrew with a known error (docs/plant.md) */
        const char *usage = "plant AXIS leadscrew AMP PITCH [PPM] | plant AXIS leadscrew off";
        if (nt == 4 && !strcmp(tok[3], "off")) {
            p->lead_amp = p->lead_pitch = p->lead_ppm = 0.0;
            return 0;
        }
        double amp = 0, pitch = 0, ppm = 0;
        if (nt < 5 || nt > 6)
            return script_err(sc, "usage: %s", usage);
        if (parse_double(sc, tok[3], &amp, -1e9, 1e9) || parse_double(sc, tok[4], &pitch, 1e-3, 1e15) ||
            (nt == 6 && parse_double(sc, tok[5], &ppm, -1e5, 1e5)))
            return -1;
        p->lead_amp = amp;
        p->lead_pitch = pitch;
        p->lead_ppm = ppm;
        return 0;
    }
    if (!strcmp(what, "defaults")) {
        edit_t e = edit_begin(s, n);
        double x = plant_units(s, n, sim_now(s));
        plant_params_defaults(s, n);
        s->ax[n].gray = s->card == MAC4_CARD_SSI;
        if (s->card != MAC4_CARD_STP)   /* keep the output shaft where it is */
            p->x0 = p->x1 = x / plant_units_per_rev(s, n) * p->gear;
        edit_end(s, n, e);
        return 0;
    }
    return script_err(sc, "unknown plant command '%s' (motor gear encoder ssi wiring pos leadscrew defaults)", what);
}

static int cmd_stepper(script_t *sc, sim_t *s, char **tok, int nt)
{
    int n = 0;
    if (nt < 2 || parse_axis(sc, tok[1], &n))
        return nt < 2 ? script_err(sc, "usage: %s", "stepper AXIS KEY VALUE ...") : -1;
    edit_t e = edit_begin(s, n);   /* syncs before the copy */
    plant_axis_t *p = &s->plant.ax[n], c = *p;
    if (nt < 4 || nt % 2)
        return script_err(sc, "usage: %s", "stepper AXIS KEY VALUE ... (steps ssf accel fmax boost)");
    for (int i = 2; i < nt; i += 2) {
        double d = 0;
        if (parse_double(sc, tok[i + 1], &d, 0.0, 1e9))
            return -1;
        if (!strcmp(tok[i], "steps") && d >= 1)
            c.steps_rev = d;
        else if (!strcmp(tok[i], "ssf") && d > 0)
            c.ssf = d;
        else if (!strcmp(tok[i], "accel") && d > 0)
            c.accel = d;
        else if (!strcmp(tok[i], "fmax"))
            c.fmax = d;
        else if (!strcmp(tok[i], "boost") && d > 0)
            c.boost = d;
        else
            return script_err(sc, "bad stepper parameter or value near '%s'", tok[i]);
    }
    *p = c;
    edit_end(s, n, e);
    return 0;
}

static int cmd_switch(script_t *sc, sim_t *s, char **tok, int nt)
{
    int n = 0;
    static const char *const usage =
        "switch AXIS lp|ln POS [low|high], switch AXIS ref POS WIDTH [low|high], "
        "switch AXIS lp|ln|ref off, switch AXIS df low|high";
    if (nt < 3 || parse_axis(sc, tok[1], &n))
        return nt < 3 ? script_err(sc, "usage: %s", usage) : -1;
    plant_axis_t *p = &s->plant.ax[n];
    const char *w = tok[2];
    int which = !strcmp(w, "lp") ? PLANT_SW_LP : !strcmp(w, "ln") ? PLANT_SW_LN : !strcmp(w, "ref") ? PLANT_SW_REF : -1;
    plant_sync(s, n, sim_now(s));
    if (!strcmp(w, "df")) {
        if (nt != 4 || (strcmp(tok[3], "low") && strcmp(tok[3], "high")))
            return script_err(sc, "usage: %s", usage);
        p->df_high = !strcmp(tok[3], "high");
        return 0;
    }
    if (which < 0)
        return script_err(sc, "usage: %s", usage);
    plant_switch_t sw = p->sw[which];
    if (nt == 4 && !strcmp(tok[3], "off")) {
        p->sw[which].used = 0;
        return 0;
    }
    int i = 3;
    long long pos, width = 1;
    if (nt <= i || parse_int(sc, tok[i++], &pos, -(1LL << 50), 1LL << 50))
        return nt <= 3 ? script_err(sc, "usage: %s", usage) : -1;
    if (which == PLANT_SW_REF) {
        if (nt <= i || parse_int(sc, tok[i++], &width, 1, 1LL << 50))
            return nt <= 4 ? script_err(sc, "usage: %s", usage) : -1;
    }
    sw.high = 0;
    if (i < nt) {
        if (!strcmp(tok[i], "high"))
            sw.high = 1;
        else if (strcmp(tok[i], "low"))
            return script_err(sc, "usage: %s", usage);
        i++;
    }
    if (i != nt)
        return script_err(sc, "usage: %s", usage);
    sw.used = 1;
    sw.pos = pos;
    sw.width = width;
    p->sw[which] = sw;
    return 0;
}

static int cmd_fault(script_t *sc, sim_t *s, char **tok, int nt)
{
    int n = 0;
    if (nt < 4 || parse_axis(sc, tok[1], &n))
        return nt < 4 ? script_err(sc, "usage: %s", "fault AXIS drive on|off, fault AXIS encoder "
                                                    "frozen|jump N|stuck0|stuck1|off")
                      : -1;
    if (!strcmp(tok[2], "drive") && nt == 4) {
        int on = !strcmp(tok[3], "on");
        if (!on && strcmp(tok[3], "off"))
            return script_err(sc, "usage: %s", "fault AXIS drive on|off");
        plant_sync(s, n, sim_now(s));
        s->plant.ax[n].drive_fault = on;
        plant_inputs(s, n, sim_now(s));
        sim_update_irq(s);
        return 0;
    }
    if (!strcmp(tok[2], "encoder")) {
        const char *m = tok[3];
        if (!strcmp(m, "jump") && nt == 5) {
            long long by;
            if (parse_int(sc, tok[4], &by, -(1LL << 40), 1LL << 40))
                return -1;
            plant_enc_jump(s, n, by);
            return 0;
        }
        int mode = !strcmp(m, "frozen") ? PLANT_ENC_FROZEN : !strcmp(m, "stuck0") ? PLANT_ENC_STUCK0
                 : !strcmp(m, "stuck1") ? PLANT_ENC_STUCK1 : !strcmp(m, "off") ? PLANT_ENC_OK : -1;
        if (mode < 0 || nt != 4)
            return script_err(sc, "usage: %s", "fault AXIS encoder frozen|jump N|stuck0|stuck1|off");
        plant_set_enc_fault(s, n, mode);
        return 0;
    }
    return script_err(sc, "unknown fault '%s' (drive, encoder)", tok[2]);
}

static int cmd_vme_encoder(script_t *sc, sim_t *s, char **tok, int nt)
{
    long long base, axis, bits = 16, turns = 1, offset = 0;
    double res = -1;
    int motor = 0;
    static const char *const usage =
        "vme-encoder ADDR AXIS [bits N] [res COUNTS] [turns T] [offset V] [shaft motor|output|load], "
        "vme-encoder ADDR off";
    if (nt < 3 || parse_int(sc, tok[1], &base, 0, 0xFFFFFE))
        return nt < 3 ? script_err(sc, "usage: %s", usage) : -1;
    if (nt == 3 && !strcmp(tok[2], "off")) {
        if (plant_vme_remove(s, (uint32_t)base))
            return script_err(sc, "no VME board at %s", tok[1]);
        return 0;
    }
    if (parse_int(sc, tok[2], &axis, 0, MAC4_NAXES - 1))
        return -1;
    for (int i = 3; i < nt; i += 2) {
        if (i + 1 >= nt)
            return script_err(sc, "usage: %s", usage);
        const char *k = tok[i], *v = tok[i + 1];
        if (!strcmp(k, "bits")) {
            if (parse_int(sc, v, &bits, 1, 32))
                return -1;
        } else if (!strcmp(k, "res")) {
            if (parse_double(sc, v, &res, 1e-3, 4.3e9))
                return -1;
        } else if (!strcmp(k, "turns")) {
            if (parse_int(sc, v, &turns, 0, 1LL << 32))
                return -1;
        } else if (!strcmp(k, "offset")) {
            if (parse_int(sc, v, &offset, -(1LL << 40), 1LL << 40))
                return -1;
        } else if (!strcmp(k, "shaft")) {
            if (strcmp(v, "motor") && strcmp(v, "output") && strcmp(v, "load"))
                return script_err(sc, "usage: %s", usage);
            motor = !strcmp(v, "motor") ? 1 : !strcmp(v, "load") ? PLANT_VME_LOAD : 0;
        } else {
            return script_err(sc, "usage: %s", usage);
        }
    }
    if (res < 0)
        res = bits >= 32 ? 4294967296.0 : (double)(1ULL << bits);
    int r = plant_vme_add(s, (uint32_t)base, (int)axis, (int)bits, res, (uint64_t)turns, offset, motor);
    if (r == -2)
        return script_err(sc, "%s: VME board table full", "vme-encoder");
    if (r)
        return script_err(sc, "bad VME encoder at %s (even A24 address)", tok[1]);
    return 0;
}

static void cmd_vme_boards(sim_t *s)
{
    for (int i = 0; i < PLANT_NVME; i++) {
        const plant_vme_t *b = &s->plant.vme[i];
        if (!b->used)
            continue;
        sim_printf(s, "vme-encoder $%06X axis=%d bits=%d res=%.0f turns=%llu offset=%lld shaft=%s value=%u\n",
                   (unsigned)b->base, b->axis, b->bits, b->res, (unsigned long long)b->turns,
                   (long long)b->offset, b->motor_shaft == PLANT_VME_LOAD ? "load" : b->motor_shaft ? "motor" : "output",
                   plant_vme_value(s, b, sim_now(s)));
    }
}

/* trace AXIS FILE [US|tick] [card], trace AXIS off, trace off */
static int cmd_trace(script_t *sc, sim_t *s, char **tok, int nt)
{
    int n = 0;
    static const char *const usage = "trace AXIS FILE [US|tick] [card], trace AXIS off, trace off";
    if (nt == 2 && !strcmp(tok[1], "off")) {
        for (int a = 0; a < MAC4_NAXES; a++)
            plant_trace_stop(s, a);
        return 0;
    }
    if (nt < 3 || nt > 5 || parse_axis(sc, tok[1], &n))
        return (nt < 3 || nt > 5) ? script_err(sc, "usage: %s", usage) : -1;
    if (nt == 3 && !strcmp(tok[2], "off")) {
        plant_trace_stop(s, n);
        return 0;
    }
    long long us = 1000;
    int tick = 0, card = 0, have_iv = 0;
    for (int i = 3; i < nt; i++) {
        if (!strcmp(tok[i], "card") && !card) {
            card = 1;
        } else if (!strcmp(tok[i], "tick") && !have_iv) {
            tick = have_iv = 1;
        } else if (!have_iv && !card) {
            if (parse_int(sc, tok[i], &us, 1, 60000000))
                return -1;
            have_iv = 1;
        } else {
            return script_err(sc, "usage: %s", usage);
        }
    }
    if (plant_trace_start_ex(s, n, tok[2], (cyc_t)us * MAC4_CYCLES_PER_US, tick, card))
        return script_err(sc, "cannot open trace file '%s'", tok[2]);
    return 0;
}

/* include FILE: the script lines of FILE, as if they stood here (plant
 * scenarios, tests/scenarios/).  A relative FILE is looked for beside the
 * including script first, then in the current directory. */
#define INCLUDE_DEPTH 8
/* Files that include themselves more than once a file multiply at every
 * level (10 lines of `include self` 8 deep would be 10^8 files): a run opens
 * at most INCLUDE_FILES included files in all. */
#define INCLUDE_FILES 1000
int script_includes;

static FILE *open_beside(const char *including, const char *file, char *used, size_t len)
{
    FILE *f = NULL;
    const char *slash = strrchr(including, '/');
    if (file[0] != '/' && slash && strcmp(including, "-")) {
        snprintf(used, len, "%.*s/%s", (int)(slash - including), including, file);
        f = fopen(used, "r");
    }
    if (!f) {
        snprintf(used, len, "%s", file);
        f = fopen(used, "r");
    }
    return f;
}

static int cmd_include(script_t *sc, sim_t *s, char **tok, int nt)
{
    if (nt != 2)
        return script_err(sc, "usage: %s", "include FILE");
    if (sc->depth >= INCLUDE_DEPTH)
        return script_err(sc, "include: nested deeper than 8 (a loop?) at '%s'", tok[1]);
    if (script_includes >= INCLUDE_FILES)
        return script_err(sc, "include: more than 1000 files included in all (a runaway?) at '%s'", tok[1]);
    char path[2048];
    FILE *f = open_beside(sc->name, tok[1], path, sizeof path);
    if (!f)
        return script_err(sc, "include: cannot open '%s'", tok[1]);
    if (script_check_file(f)) {
        fclose(f);
        return script_err(sc, "include: '%s' is a directory", tok[1]);
    }
    script_includes++;
    script_t inner = {path, 0, 0, sc->depth + 1};
    char buf[SCRIPT_LINE_MAX + 2];
    int r = 0;
    while (script_getline(&inner, f, buf) > 0) {
        r = script_line(&inner, s, buf);
        if (r > 0)
            break;
    }
    fclose(f);
    sc->errors += inner.errors;      /* reported with the included file's name and line */
    return r > 0 ? 1 : inner.errors ? -1 : 0;
}

/* axreg AXIS REG [VALUE]: read or write an axis-board register as the
 * 68000 would (a test hook; the firmware owns these registers). */
static const struct {
    const char *name;
    uint32_t off;
} axregs[] = {
    {"cnt_hi", AX_CNT_HI}, {"cnt_lo", AX_CNT_LO}, {"idx_hi", AX_IDX_HI}, {"idx_lo", AX_IDX_LO},
    {"in", AX_IN}, {"ctrl", AX_CTRL}, {"dac", AX_DAC}, {"rate", AX_RATE},
    {"ssi_start", AX_SSI_START}, {"ssi_hi", AX_SSI_HI}, {"ssi_lo", AX_SSI_LO}, {"pulses", AX_PULSES},
};

static int cmd_axreg(script_t *sc, sim_t *s, char **tok, int nt)
{
    int n = 0;
    long long v;
    if (nt < 3 || nt > 4 || parse_axis(sc, tok[1], &n))
        return (nt < 3 || nt > 4) ? script_err(sc, "usage: %s", "axreg AXIS REG [VALUE]") : -1;
    const char *r = tok[2];
    uint32_t addr;
    if (!strcmp(r, "irq")) {
        addr = AXIS_IRQ_PENDING;
    } else {
        unsigned i;
        for (i = 0; i < sizeof axregs / sizeof axregs[0]; i++)
            if (!strcmp(r, axregs[i].name))
                break;
        if (i == sizeof axregs / sizeof axregs[0])
            return script_err(sc, "unknown axis register '%s' (cnt_hi cnt_lo idx_hi idx_lo in ctrl dac "
                                  "rate ssi_start ssi_hi ssi_lo pulses irq)", r);
        addr = AX_REG((uint32_t)n, axregs[i].off);
    }
    if (nt == 4) {
        if (script_parse_num(tok[3], &v) || v < -32768 || v > 0xFFFF)
            return script_err(sc, "bad register value '%s' (16 bits)", tok[3]);
        bus_write(s, addr, (uint32_t)v & 0xFFFF, 2);
        return 0;
    }
    sim_printf(s, "axreg %d %s 0x%04X\n", n, r, (unsigned)bus_read(s, addr, 2));
    return 0;
}

int script_plant(script_t *sc, sim_t *s, char **tok, int n)
{
    const char *c = tok[0];
    int axis = 0;
    long long v;
    if (!strcmp(c, "plant"))
        return cmd_plant(sc, s, tok, n);
    if (!strcmp(c, "stepper"))
        return cmd_stepper(sc, s, tok, n);
    if (!strcmp(c, "switch"))
        return cmd_switch(sc, s, tok, n);
    if (!strcmp(c, "fault"))
        return cmd_fault(sc, s, tok, n);
    if (!strcmp(c, "vme-encoder"))
        return cmd_vme_encoder(sc, s, tok, n);
    if (!strcmp(c, "vme-boards")) {
        cmd_vme_boards(s);
        return 0;
    }
    if (!strcmp(c, "trace"))
        return cmd_trace(sc, s, tok, n);
    if (!strcmp(c, "include"))
        return cmd_include(sc, s, tok, n);
    if (!strcmp(c, "axreg"))
        return cmd_axreg(sc, s, tok, n);
    if (!strcmp(c, "ssi-clock")) {
        if (n != 2 || strlen(tok[1]) != 1 || tok[1][0] < 'A' || tok[1][0] > 'D')
            return script_err(sc, "usage: %s", "ssi-clock A|B|C|D (jumper J2: 93.75, 187.5, 375, 750 kHz)");
        s->ssi_clock = tok[1][0] - 'A';
        return 0;
    }
    if (!strcmp(c, "br")) {
        if (n != 3 || parse_axis(sc, tok[1], &axis))
            return n != 3 ? script_err(sc, "usage: %s", "br AXIS steps|encoder") : -1;
        if (s->card != MAC4_CARD_STP)
            return script_err(sc, "%s: the solder bridge BR is on the MAC4-STP only", "br");
        if (strcmp(tok[2], "steps") && strcmp(tok[2], "encoder"))
            return script_err(sc, "usage: %s", "br AXIS steps|encoder");
        edit_t e = edit_begin(s, axis);
        s->plant.ax[axis].br_steps = !strcmp(tok[2], "steps");
        edit_end(s, axis, e);
        return 0;
    }
    if (!strcmp(c, "counter")) {
        if (n != 3 || parse_axis(sc, tok[1], &axis))
            return n != 3 ? script_err(sc, "usage: %s", "counter AXIS VALUE") : -1;
        if (script_parse_num(tok[2], &v) || v < -(1LL << 31) || v > 0xFFFFFFFFLL)
            return script_err(sc, "bad counter value '%s'", tok[2]);
        axb_counter_set(s, axis, sim_now(s), (uint32_t)((uint64_t)v & 0xFFFFFF));
        return 0;
    }
    return SCRIPT_NOT_MINE;
}
