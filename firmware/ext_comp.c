/*
 * ext_comp.c - position compensation tables after the Turbo PMAC's DEFINE
 * COMP (one- and two-dimensional), I30 (wrap) and I51 (on/off); what
 * differs from the PMAC and why: docs/extensions.md.
 *
 * The correction is found after each tick, in the supervision, from the
 * sources' positions of that tick, and added (in whole counts) to the
 * target axis' measured and displayed position: the controller, the
 * following error, the limits and pos_end all see the corrected position
 * from the next tick on, and the tick itself does not change.  The cell of
 * each source in the table is followed from tick to tick without a
 * division (ext_cell_move), the interpolation is done only when a source
 * moved: a table costs nothing on an axis at rest.
 */
/* The extensions run after every tick: their hot paths compiled for speed
 * (the rest of the firmware for size, Makefile OPT68). */
#pragma GCC optimize("O2")
#include "inline.h"
#include "fw.h"
#include "hal.h"
#include "mul16.h"
#include "card.h"
#include "axis.h"
#include "params.h"
#include "measure.h"
#include "crc16.h"
#include "ext.h"
#include "cmd_mask.h"

ext_comp_t ext_comp[MAC4_NAXES];
/* &ext_comp[n] by a table, as axis_at[] (card.h) */
ext_comp_t *const ext_comp_at[MAC4_NAXES] = {&ext_comp[0], &ext_comp[1], &ext_comp[2], &ext_comp[3]};

/* ---- the arithmetic (unit-tested natively against a double model) --------- */
FW_INLINE int32_t lerp(int32_t a, int32_t b, uint16_t f, uint16_t sp)
{
    int32_t d = b - a;
    if (d == 0 || f == 0)
        return a;
    uint16_t ad = (uint16_t)(d < 0 ? -d : d);
    /* |d| f / sp + 1/2: below |d| < 2^15, one DIVU.W */
    uint16_t q = (uint16_t)divu16(mulu16(ad, f) + (sp >> 1), sp);
    return d < 0 ? a - q : a + q;
}

int32_t ext_lerp(int32_t a, int32_t b, uint16_t f, uint16_t sp) { return lerp(a, b, f, sp); }

void ext_cell_set(ext_cell_t *c, int32_t pos)
{
    int32_t sp = c->sp, cell = pos / sp, off = pos - cell * sp;
    if (off < 0) {
        off += sp;
        cell--;
    }
    if (c->wrap) {
        cell %= (int32_t)c->cells;
        if (cell < 0)
            cell += c->cells;
    }
    c->pos = pos;
    c->cell = cell;
    c->off = (uint16_t)off;
}

FW_INLINE void cell_move(ext_cell_t *c, int32_t pos)
{
    int32_t d = pos_sub(pos, c->pos);
    int32_t sp = c->sp;
    if (d > 2 * sp || d < -2 * sp) {              /* far (a jump, INIT): from scratch */
        ext_cell_set(c, pos);
        return;
    }
    int32_t off = (int32_t)c->off + d, cell = c->cell;
    while (off >= sp) {
        off -= sp;
        cell++;
    }
    while (off < 0) {
        off += sp;
        cell--;
    }
    if (c->wrap) {
        if (cell >= (int32_t)c->cells)
            cell -= c->cells;
        else if (cell < 0)
            cell += c->cells;
    } else if (cell > 0x3FFFFFFF || cell < -0x3FFFFFFF) {
        cell = cell < 0 ? -0x3FFFFFFF : 0x3FFFFFFF;  /* far beyond the edge: stays at the edge */
    }
    c->pos = pos;
    c->cell = cell;
    c->off = (uint16_t)off;
}

void ext_cell_move(ext_cell_t *c, int32_t pos) { cell_move(c, pos); }

/* The grid index and offset of a source: beyond the span the edge value
 * without wrap (the PMAC always rolls over; docs/extensions.md). */
FW_INLINE void cell_at(const ext_cell_t *c, unsigned *j, uint16_t *f)
{
    if (c->cell < 0) {
        *j = 0;
        *f = 0;
    } else if (c->cell >= (int32_t)c->cells) {
        *j = c->cells;
        *f = 0;
    } else {
        *j = (unsigned)c->cell;
        *f = c->off;
    }
}

FW_INLINE int32_t comp_value(const ext_comp_t *t)
{
    unsigned j, i = 0;
    uint16_t f, g = 0;
    cell_at(&t->cr, &j, &f);
    uint16_t stride = (uint16_t)(t->cols + 1u);
    const int16_t *row = &t->e[0];
    if (t->rows) {
        cell_at(&t->cc, &i, &g);
        row += mulu16((uint16_t)i, stride);
    }
    unsigned j1 = f ? j + 1u : j;
    int32_t a = lerp(row[j], row[j1], f, t->cr.sp);
    if (!g)
        return a;
    const int16_t *next = row + stride;
    int32_t b = lerp(next[j], next[j1], f, t->cr.sp);
    return lerp(a, b, g, t->cc.sp);
}

int32_t ext_comp_value(const ext_comp_t *t) { return comp_value(t); }

/* ---- the axis' position and its correction --------------------------------- */
/* A source's position as the table reads it, in the frame of RCP (with
 * <ao>): the actual position without the source's own correction (the
 * encoder's), or the setpoint of the last tick (desired). */
FW_INLINE int32_t source_pos(unsigned s, int desired)
{
    const axis_t *x = axis_at[s];
    int32_t p = desired ? x->setpoint : pos_sub(x->meas, ext_comp_at[s]->cin);
    return pos_add(p, par_a[P_AO][s]);
}

/* The axis' measured position switched between absolute (the reading is
 * the position, as INIT set it up) and relative tracking of the same
 * reading, which keeps a correction added to it (measure.h, measure_delta_k). */
static void track_relative(unsigned n, int on)
{
    ext_comp_t *t = &ext_comp[n];
    axis_t *x = axis_at[n];
    meas_cfg_t *c = &meas_cfg[n];
    t->rel = (uint8_t)on;
    if (on) {
        t->abs_saved = c->abs && x->linear;
        if (!t->abs_saved)
            return;
        c->abs = 0;
        t->mk_saved = x->mk;
        axis_kind_relative(x);
    } else if (t->abs_saved) {
        t->abs_saved = 0;
        c->abs = 1;
        axis_kind_restore(x, t->mk_saved);
    }
}

static inline void correct_by(unsigned n, int32_t d)
{
    axis_t *x = axis_at[n];
    measure_meas_set(x, pos_add(x->meas, d));
    axis_moved_by(x, d);                         /* RAV and the position with it (axis.h) */
}

void ext_comp_apply(unsigned n)
{
    ext_comp_t *t = ext_comp_at[n];
    int32_t pr = source_pos(t->src_r, t->des_r);
    int changed = 0;
    if (!t->valid) {
        ext_cell_set(&t->cr, pr);
        if (t->rows)
            ext_cell_set(&t->cc, source_pos(t->src_c, t->des_c));
        t->valid = 1;
        changed = 1;
    } else {
        if (pr != t->cr.pos) {
            cell_move(&t->cr, pr);
            changed = 1;
        }
        if (t->rows) {
            int32_t pc = source_pos(t->src_c, t->des_c);
            if (pc != t->cc.pos) {
                cell_move(&t->cc, pc);
                changed = 1;
            }
        }
    }
    if (!changed)
        return;
    t->cor = comp_value(t);
    t->ccomp = (t->cor + 8) >> 4;                 /* whole counts, rounded */
}

/* The table's correction and the feedback processing's fb (fb_on: the
 * axis takes an entry's result) into the axis' measured position. */
void ext_axis_correct(unsigned n, int32_t fb, int fb_on)
{
    ext_comp_t *t = ext_comp_at[n];
    int active = t->on || fb_on;
    if (active && !t->rel && axis_initialised(n))
        track_relative(n, 1);
    int32_t total = pos_add(t->on ? t->ccomp : 0, fb);
    if (total != t->cin) {
        correct_by(n, pos_sub(total, t->cin));
        t->cin = total;
    }
    if (!active && t->rel)
        track_relative(n, 0);
}

/* ---- the commands -------------------------------------------------------- */
static unsigned src_axis(unsigned a, int32_t v) { return v >= MAC4_NAXES ? a : (unsigned)v; }

static int define(unsigned a, ext_comp_t *t);
int ext_comp_define(unsigned a)
{
    ext_comp_t *t = &ext_comp[a];
    if (t->on)
        return ERR_LOGICAL;                       /* CON 0 first, as the PMAC's DELETE COMP */
    /* The table is off: neither the tick nor the supervision reads it, so
     * the divisions and the clearing run with interrupts enabled (commands
     * run masked, cmd.c: execute_and_respond) */
    cmd_unmask();
    int r_ = define(a, t);
    cmd_remask();
    return r_;
}

static int define(unsigned a, ext_comp_t *t)
{
    int32_t r = PAR(a, CRW), c = PAR(a, CCL), rs = PAR(a, CRS), cs = PAR(a, CCS);
    if ((r + 1) * (c + 1) > EXT_COMP_MAX)
        return ERR_LIMIT;
    if (rs % c || rs / c > 65535)
        return ERR_LIMIT;                         /* the spacing a whole number of counts */
    if (r && (cs % r || cs / r > 65535))
        return ERR_LIMIT;
    for (unsigned k = 0; k < EXT_COMP_MAX; k++)
        t->e[k] = 0;
    t->rows = (uint8_t)r;
    t->cols = (uint8_t)c;
    t->n = (uint16_t)((r + 1) * (c + 1) - 1);
    t->loaded = t->ptr = 0;
    t->wrap = (uint8_t)PAR(a, CWR);
    t->src_r = (uint8_t)src_axis(a, PAR(a, CRA));
    t->src_c = (uint8_t)src_axis(a, PAR(a, CCA));
    t->des_r = (PAR(a, CSD) & 1) != 0;
    t->des_c = (PAR(a, CSD) & 2) != 0;
    t->cr = (ext_cell_t){.sp = (uint16_t)(rs / c), .cells = (uint16_t)c, .wrap = t->wrap};
    t->cc = (ext_cell_t){.sp = (uint16_t)(r ? cs / r : 1), .cells = (uint16_t)(r ? r : 1), .wrap = t->wrap};
    t->defined = 1;
    t->valid = 0;
    t->cor = t->cin = 0;
    return 0;
}

int ext_comp_entry(unsigned a, int32_t v)
{
    ext_comp_t *t = &ext_comp[a];
    if (!t->defined || t->on || t->ptr >= t->n)
        return ERR_LOGICAL;
    if (v < EXT_ENTRY_MIN || v > EXT_ENTRY_MAX)
        return ERR_LIMIT;
    t->e[t->ptr + 1u] = (int16_t)v;
    t->ptr++;
    if (t->ptr > t->loaded)
        t->loaded = t->ptr;
    if (t->ptr == t->n && t->wrap)
        t->e[0] = (int16_t)v;                     /* I30: the last entry is the correction at 0 too */
    return 0;
}

int ext_comp_pointer(unsigned a, uint32_t p)
{
    ext_comp_t *t = &ext_comp[a];
    if (!t->defined)
        return ERR_LOGICAL;
    if (p > t->n)
        return ERR_LIMIT;
    t->ptr = (uint16_t)p;
    return 0;
}

uint32_t ext_comp_sum(unsigned a)
{
    const ext_comp_t *t = &ext_comp[a];
    uint16_t crc = CRC16_INIT;
    for (unsigned k = 1; k <= t->loaded; k++) {
        uint16_t w = (uint16_t)t->e[k];
        crc = crc16_update(crc16_update(crc, (uint8_t)(w >> 8)), (uint8_t)w);
    }
    return (uint32_t)t->loaded << 16 | crc;
}

int ext_comp_switch(unsigned a, uint32_t on)
{
    ext_comp_t *t = &ext_comp[a];
    axis_t *x = axis_at[a];
    if (on > 1)
        return ERR_LIMIT;
    if (on) {
        if (!t->defined || t->loaded != t->n)
            return ERR_LOGICAL;                   /* every entry first */
        if (t->on)
            return 0;
        /* a command, masked (cmd.c): the budget is main-loop state no
         * interrupt reads, worked out with interrupts enabled (as
         * ext_compare.c's ext_pc_arm) */
        cmd_unmask();
        int fits = ext_fits(t->rows ? EXT_W_TABLE2 : EXT_W_TABLE1);
        cmd_remask();
        if (!fits)
            return ERR_LOGICAL;                   /* beyond the extensions' budget (ext.h) */
        unsigned prev = hal_irq_save();
        t->valid = 0;
        t->cor = t->ccomp = 0;
        t->on = 1;
        ext_on |= (uint16_t)(1u << a);
        x->ustat |= UB(COMP_ON);
        hal_irq_restore(prev);
        return 0;                                 /* applied from the next supervision on */
    }
    if (!t->on)
        return 0;
    /* the correction leaves the measured position now (a command runs
     * masked), not at the next supervision */
    t->on = 0;
    t->cor = t->ccomp = 0;
    ext_on &= (uint16_t)~(1u << a);
    x->ustat &= ~UB(COMP_ON);
    int fbe = (ext_on & EXT_FB_ON) ? par_a[P_FBE][a] : 0;
    ext_axis_correct(a, fbe ? ext_fb[fbe - 1].result : 0, fbe != 0);
    return 0;
}

/* INIT reset the measurement: the correction is no longer in it, and an
 * absolute one is absolute again */
void ext_comp_init(unsigned n)
{
    ext_comp_t *t = &ext_comp[n];
    t->cin = t->cor = t->ccomp = 0;
    t->valid = 0;
    t->abs_saved = 0;
    t->rel = 0;                                   /* measure_init set the measurement up afresh */
}
