#include "params.h"

const pdesc_t pdesc[NPARAMS] = {
#define PARAM(id, mn, kind, wcode, cards, flags, min, max, def, units, desc) \
    [P_##id] = {(min), (max), (def), (wcode), PK_ID(kind), (flags), ON_THIS_CARD(cards)},
#include "commands.def"
};

int32_t par_w[NPARAMS][MAC4_NAXES];
int32_t par_a[NPARAMS][MAC4_NAXES];
uint16_t par_gen[MAC4_NAXES];

static unsigned slot(unsigned axis, unsigned p) { return (pdesc[p].flags & PF_CARD) ? 0 : axis; }
int32_t par(unsigned axis, unsigned p) { return par_a[p][slot(axis, p)]; }
int32_t par_written(unsigned axis, unsigned p) { return par_w[p][slot(axis, p)]; }

/* The per-axis system parameters, listed once at reset: INIT copies only
 * those (a pass over all of pdesc[] costs about 5 000 cycles, with
 * interrupts masked). */
static uint16_t sys_list[NPARAMS];         /* byte offsets of par_a[p][0] */
static uint8_t sys_len;
_Static_assert(NPARAMS < 256, "parameter numbers are bytes in the lists below");
/* The mode parameters written since the last E, per axis: E copies only
 * those (the others are in force already: par_w and par_a of a mode
 * parameter differ only after a write here). */
static uint8_t mode_dirty[NPARAMS][MAC4_NAXES];    /* [k][a]: axis a's k-th (k*4 + a: no product) */
static uint8_t mode_dirty_n[MAC4_NAXES];
static uint8_t mode_listed[NPARAMS][MAC4_NAXES];

void params_reset(void)
{
    for (unsigned a = 0; a < MAC4_NAXES; a++)
        mode_dirty_n[a] = 0;
    for (unsigned p = 0; p < NPARAMS; p++)
        for (unsigned a = 0; a < MAC4_NAXES; a++)
            mode_listed[p][a] = 0;
    sys_len = 0;
    for (unsigned p = 0; p < NPARAMS; p++)
        if (!(pdesc[p].flags & PF_CARD) && pdesc[p].kind == PK_SYS)
            sys_list[sys_len++] = (uint16_t)(p * sizeof par_a[0]);
    for (unsigned p = 0; p < NPARAMS; p++)
        for (unsigned a = 0; a < MAC4_NAXES; a++)
            par_w[p][a] = par_a[p][a] = pdesc[p].def;
    for (unsigned a = 0; a < MAC4_NAXES; a++)
        par_gen[a]++;
}

void params_write(unsigned axis, unsigned p, int32_t v)
{
    const pdesc_t *d = &pdesc[p];
    uint8_t flags = d->flags;
    unsigned a = (flags & PF_CARD) ? 0 : axis;
    par_w[p][a] = v;
    if (flags & PF_IMM) {
        par_a[p][a] = v;                          /* read where used, never cached: par_gen stays */
    } else if (d->kind == PK_MODE && !(flags & PF_CARD) && !mode_listed[p][a]) {
        mode_listed[p][a] = 1;
        mode_dirty[mode_dirty_n[a]++][a] = (uint8_t)p;
    }
}

void params_activate(unsigned axis, uint8_t kind)
{
    if (kind == PK_MODE) {
        for (unsigned i = mode_dirty_n[axis]; i--;) {
            unsigned p = mode_dirty[i][axis];
            par_a[p][axis] = par_w[p][axis];
            mode_listed[p][axis] = 0;
        }
        mode_dirty_n[axis] = 0;
        par_gen[axis]++;
        return;
    }
    const uint16_t *l = sys_list;
    uint8_t *a = (uint8_t *)&par_a[0][axis];
    const uint8_t *w = (const uint8_t *)&par_w[0][axis];
    for (const uint16_t *e = l + sys_len; l < e;) {
        uint16_t off = *l++;
        *(int32_t *)(void *)(a + off) = *(const int32_t *)(const void *)(w + off);
    }
    par_gen[axis]++;
}
