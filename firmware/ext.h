/*
 * ext.h - the extensions after the Turbo PMAC (docs/extensions.md): position
 * compensation tables (ext_comp.c) and position compare (ext_compare.c),
 * their commands (ext.c, codes 210 on in commands.def).  All off by default.
 *
 * None of them runs in the tick: they work in the main loop after each
 * tick, in slices (ext_slice), started by the supervision
 * (card_supervise_tick calls ext_supervise while one is on), so a tick
 * costs the same with them on or off, and the main loop pays one test of
 * ext_on per tick and one of ext_due per pass while all are off.
 */
#ifndef EXT_H
#define EXT_H
#include "inline.h"
#include <stdint.h>
#include "fw.h"
#include "mac4_map.h"
#include "status.h"

/* ---- compensation tables (PMAC DEFINE COMP, I30, I51) ---------------------
 * One table per target axis: (r+1)(c+1) grid values, e[0] the origin (the
 * implied zero, or with wrap the last entry), e[i (c+1) + j] the
 * correction at column j (row source j x <crs>/c) of row i (column source
 * i x <ccs>/r), in 1/16 count.  r = 0: a one-dimensional table. */
#define EXT_COMP_MAX 256
#define EXT_ENTRY_MIN (-16384)
#define EXT_ENTRY_MAX 16383

/* One source of a table: where it is in the table's cell grid, kept
 * from tick to tick without a division (ext_cell_move). */
typedef struct {
    int32_t pos;        /* the source position last seen */
    int32_t cell;       /* cell index, unbounded (pos = cell * sp + off + origin 0) */
    uint16_t off;       /* 0 .. sp-1 */
    uint16_t sp;        /* spacing: span / cells */
    uint16_t cells;     /* c (row source) or r (column source) */
    uint8_t wrap;
} ext_cell_t;

typedef struct {
    int16_t e[EXT_COMP_MAX];
    uint16_t n;         /* entries the host loads: (r+1)(c+1) - 1 */
    uint16_t loaded;    /* highest entry written + 1 */
    uint16_t ptr;       /* the entry CENT writes and RCEN reads, 0 = the first */
    uint8_t rows, cols, wrap;
    uint8_t defined, on;
    uint8_t src_r, src_c;   /* source axes */
    uint8_t des_r, des_c;   /* source by desired position (the setpoint) */
    uint8_t valid;          /* the cells below follow the sources */
    ext_cell_t cr, cc;      /* the row source and the column source */
    int32_t cor;            /* the table's correction in force, 1/16 count */
    int32_t ccomp;          /* ... in whole counts, rounded */
    int32_t cin;            /* what is added to the axis' measured position: the table's
                             * and the feedback processing's (ext_axis_correct) */
    /* the axis measured absolutely on a linear axis: tracked as relative
     * while a correction is on, so that it stays in meas */
    uint8_t rel, abs_saved, mk_saved;
} ext_comp_t;

extern ext_comp_t ext_comp[MAC4_NAXES];
extern ext_comp_t *const ext_comp_at[MAC4_NAXES];

/* The pure part, shared with the native unit tests: the grid value
 * interpolated in a cell (row i, column j, offsets f/sp and g/sp), and
 * the source's cell kept up to date for a new position. */
void ext_cell_set(ext_cell_t *c, int32_t pos);              /* from scratch (one division) */
void ext_cell_move(ext_cell_t *c, int32_t pos);             /* from the last position */
int32_t ext_comp_value(const ext_comp_t *t);                /* the correction at the cells, 1/16 count */
/* The interpolation (b - a) x f / sp rounded to nearest, |b - a| < 2^15, f < sp. */
int32_t ext_lerp(int32_t a, int32_t b, uint16_t f, uint16_t sp);

/* ---- position compare ----------------------------------------------------- */
typedef struct {
    uint8_t armed;      /* PCON 1 */
    uint8_t irq_done;   /* once (<pcn> 0): the interrupt has come */
    int64_t p0, n, last_pt;   /* first point, repeat (0: once), last point of the window */
    int64_t lo, hi;     /* the positions at which idx holds: lo <= p < hi */
    int32_t idx;        /* compare points at or below the position */
    int32_t k;          /* points in the window (1 once) */
    uint32_t crossings; /* RPCC */
    uint32_t irqs;      /* RPCI */
} ext_pc_t;

extern ext_pc_t ext_pc[MAC4_NAXES];
/* Compare points at or below p, and the range of positions where that holds. */
void ext_pc_locate(ext_pc_t *c, int64_t p);
/* The crossings from the last position to p (updates the state). */
uint32_t ext_pc_cross(ext_pc_t *c, int64_t p);

/* ---- feedback processing (ext_feedback.c): the conversion table --------- */
#define EXT_FB_N 8
enum { FB_OFF = 0x0, FB_PARALLEL = 0x3, FB_TRACK = 0xB, FB_EXP = 0xD, FB_SUM = 0xE };
#define FB_SRC_ENTRY 0x00   /* + entry: its result */
#define FB_SRC_MEAS 0x10    /* + axis: its measured position, without its corrections */
#define FB_SRC_COUNTER 0x20 /* + axis: its counter content (RCT) */
typedef struct {
    uint32_t setup, w1, w2;
    int32_t result;     /* counts (RFBR) */
    int32_t qi;         /* filters: the output, counts ... */
    uint16_t qf;        /* ... and its fraction, Q16 */
    int32_t iq;         /* tracking filter: the integrator, Q16 counts per cycle */
    uint32_t last;      /* $3: the field the result stands at */
    uint8_t started;
} ext_fb_t;
extern ext_fb_t ext_fb[EXT_FB_N];
void ext_fb_step(ext_fb_t *e);              /* one cycle of one entry */
int ext_fb_setup(unsigned k, uint32_t setup);  /* FBS: checks the words, starts the entry */
int32_t ext_fb_source(unsigned code);
extern uint8_t ext_fb_sel;                 /* FBX */

/* ---- the card's hooks --------------------------------------------------- */
/* bit n: axis n's table is on; bit 4 + n: axis n's compare is armed;
 * EXT_FB_ON: an entry of the conversion table is on */
#define EXT_FB_ON 0x100u
extern uint16_t ext_on;
void ext_reset(void);                   /* card reset: all off */
void ext_axis_init(unsigned n);         /* INIT of axis n: its measurement was reset */
void ext_supervise_do(void);            /* after each tick's supervision, while ext_on: the slices due */
FW_INLINE void ext_supervise(void)
{
    if (ext_on)
        ext_supervise_do();
}
/* The budget: what the extensions switched on cost per tick, as measured
 * on four moving axes (tools/perfscen.py, the ext_* scenarios, and the
 * kinds one by one; docs/extensions.md), rounded up; tests/timing holds
 * every scenario's cost within what is charged for it.  The command that
 * would exceed the budget is refused with 163 (CON 1, PCON 1, FBS). */
#define EXT_W_ROUND 2500u       /* the round itself, once anything is on: four axis slices */
#define EXT_W_TABLE2 3600u      /* a 2-D table, its axis' correction */
#define EXT_W_TABLE1 2100u      /* a 1-D table */
#define EXT_W_COMPARE 2800u     /* an armed compare, an interrupt per tick */
#define EXT_W_FB_FILTER 2100u   /* a $D or $B entry */
#define EXT_W_FB_SIMPLE 800u    /* a $3 or $E entry */
#define EXT_W_FB_AXES 4600u     /* the table's two slices and the four axes' corrections, once an entry is on */
/* What the main loop has per tick beside its own work, four axes moving:
 * with the host quiet no round is late (REXL) and with a host sending
 * back to back every command is answered within 2 ms (tests/timing). */
#define EXT_BUDGET CARDSEL(20000u, 20000u, 48000u)
uint32_t ext_load(void);                /* cycles per tick of what is on */
int ext_fits(uint32_t more);            /* ext_load() + more within EXT_BUDGET */

/* Main loop, once per pass: the slices of the work after the tick
 * (ext.c) due, up to a command waiting; one test while none is. */
#define EXT_SLICES 6
extern volatile uint8_t ext_due;
extern uint16_t ext_late;               /* rounds late: the next tick came first (REXL) */
void ext_slice(void);
void ext_work_do(void);                 /* slices while no command waits */
FW_INLINE void ext_work(void)
{
    if (ext_due)
        ext_work_do();
}
/* The commands (cmd.c): a general instruction with index ci (CI_*),
 * a read; ERR_SYNTAX for an index that is none of ours. */
int ext_general(int ci, unsigned a, uint32_t p);
uint32_t ext_read(unsigned ci, unsigned a);
/* ext_compare.c, ext_comp.c: one axis after each tick, interrupts masked */
void ext_comp_apply(unsigned n);
void ext_axis_correct(unsigned n, int32_t fb, int fb_on);
void ext_pc_check(unsigned n);
int ext_comp_define(unsigned a);
int ext_comp_entry(unsigned a, int32_t v);
int ext_comp_pointer(unsigned a, uint32_t p);
uint32_t ext_comp_sum(unsigned a);
void ext_comp_init(unsigned n);
int ext_comp_switch(unsigned a, uint32_t on);
int ext_pc_arm(unsigned a, uint32_t on);

#endif
