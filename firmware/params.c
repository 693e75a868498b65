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

void params_reset(void)
{
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
    for (unsigned p = 0; p < NPARAMS; p++)
        if (pdesc[p].kind == kind && !(pdesc[p].flags & PF_CARD))
            par_a[p][axis] = par_w[p][axis];
    par_gen[axis]++;
}
