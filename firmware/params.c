#include "params.h"

const pdesc_t pdesc[NPARAMS] = {
#define PARAM(id, mn, kind, wcode, cards, flags, min, max, def, units, desc) \
    [P_##id] = {(min), (max), (def), (wcode), PK_ID(kind), (flags), ON_THIS_CARD(cards)},
#include "commands.def"
};

int32_t par_w[NPARAMS][MAC4_NAXES];
int32_t par_a[NPARAMS][MAC4_NAXES];
uint16_t par_gen[MAC4_NAXES];

static void changed(unsigned axis, unsigned p)
{
    if (pdesc[p].flags & PF_CARD)
        for (unsigned a = 0; a < MAC4_NAXES; a++)
            par_gen[a]++;
    else
        par_gen[axis]++;
}

static unsigned slot(unsigned axis, unsigned p) { return (pdesc[p].flags & PF_CARD) ? 0 : axis; }
int32_t par(unsigned axis, unsigned p) { return par_a[p][slot(axis, p)]; }
int32_t par_written(unsigned axis, unsigned p) { return par_w[p][slot(axis, p)]; }

/* The per-axis parameters of each kind, listed once at reset: E and INIT
 * copy only those (a pass over all of pdesc[] costs about 5 000 cycles,
 * with interrupts masked). */
static uint16_t act_list[2][NPARAMS];      /* byte offsets of par_a[p][0] */
static uint8_t act_len[2];

void params_reset(void)
{
    act_len[PK_MODE] = act_len[PK_SYS] = 0;
    for (unsigned p = 0; p < NPARAMS; p++)
        if (!(pdesc[p].flags & PF_CARD) && pdesc[p].kind <= PK_SYS)
            act_list[pdesc[p].kind][act_len[pdesc[p].kind]++] = (uint16_t)(p * sizeof par_a[0]);
    for (unsigned p = 0; p < NPARAMS; p++)
        for (unsigned a = 0; a < MAC4_NAXES; a++)
            par_w[p][a] = par_a[p][a] = pdesc[p].def;
    for (unsigned a = 0; a < MAC4_NAXES; a++)
        par_gen[a]++;
}

int params_write(unsigned axis, unsigned p, int32_t v)
{
    if (v < pdesc[p].min || v > pdesc[p].max)
        return ERR_LIMIT;
    unsigned a = slot(axis, p);
    par_w[p][a] = v;
    if (pdesc[p].flags & PF_IMM) {
        par_a[p][a] = v;
        changed(axis, p);
    }
    return 0;
}

void params_activate(unsigned axis, uint8_t kind)
{
    const uint16_t *l = act_list[kind];
    uint8_t *a = (uint8_t *)&par_a[0][axis];
    const uint8_t *w = (const uint8_t *)&par_w[0][axis];
    for (const uint16_t *e = l + act_len[kind]; l < e;) {
        uint16_t off = *l++;
        *(int32_t *)(void *)(a + off) = *(const int32_t *)(const void *)(w + off);
    }
    par_gen[axis]++;
}
