/*
 * params.h - the parameter store, generated from commands.def.
 * Every axis has the values the host wrote (par_w: what R.. reads back) and
 * the values in force (par_a): mode parameters move across at E, system
 * parameters at INIT, PF_IMM ones at once.  PF_CARD parameters live in the
 * slot of axis 0.
 */
#ifndef PARAMS_H
#define PARAMS_H
#include <stdint.h>
#include "status.h"

enum {
#define PARAM(id, mn, kind, wcode, cards, flags, min, max, def, units, desc) P_##id,
#include "commands.def"
    NPARAMS
};

enum { PK_MODE, PK_SYS };
#define PK_ID(kind) PK_##kind

typedef struct {
    int32_t min, max, def;
    uint16_t wcode;
    uint8_t kind;   /* PK_MODE or PK_SYS */
    uint8_t flags;  /* PF_* */
    uint8_t avail;  /* exists on this card */
} pdesc_t;

/* Flags known at compile time, so PAR() in the tick costs one load. */
enum {
#define PARAM(id, mn, kind, wcode, cards, flags, min, max, def, units, desc) PFLAGS_##id = (flags),
#include "commands.def"
};

extern const pdesc_t pdesc[NPARAMS];
/* Parameter-major, so that axis n of parameter p is p*16 + n*4 bytes in. */
extern int32_t par_w[NPARAMS][MAC4_NAXES];
extern int32_t par_a[NPARAMS][MAC4_NAXES];
/* Counts the activations of par_a (E, INIT), so that values derived from
 * it can be cached (the profile generator's Q16 velocities, motion.c), per
 * axis.  Immediate parameters (PF_IMM: <vt>, <at>, <da>, <wd>, the
 * vectors, <zp>) are read where they are used and never cached, so their
 * writes leave it. */
extern uint16_t par_gen[MAC4_NAXES];

/* The value in force / as written, for a parameter named at compile time;
 * card-wide parameters (PF_CARD) live in the slot of axis 0. */
#define PAR(n, id) par_a[P_##id][(PFLAGS_##id & PF_CARD) ? 0u : (n)]
#define PAR_W(n, id) par_w[P_##id][(PFLAGS_##id & PF_CARD) ? 0u : (n)]

void params_reset(void);                    /* defaults, all axes */
/* The same for a parameter chosen at run time (command dispatch). */
int32_t par(unsigned axis, unsigned p);
int32_t par_written(unsigned axis, unsigned p);
/* v within the parameter's range: the command's first check (cmd.c write_param) */
void params_write(unsigned axis, unsigned p, int32_t v);
void params_activate(unsigned axis, uint8_t kind);       /* E: PK_MODE, INIT: PK_SYS */
/* A value the card sets itself, not the host (no range check, no wait for
 * E or INIT): in force at once, and with PS_WRITTEN read back by R.. too.
 * PS_IN_FORCE: INIT's derived <ea>/<eb>/<ec> (table 4.3; UR.. keeps what
 * the host wrote, so a later INIT derives afresh).  PS_WRITTEN: <ao> from
 * <zp> or a justification (4.3.2, 4.9), <lv> following a lower <ssf>
 * (4.8.3).  Per-axis parameters only (the card derives no PF_CARD one);
 * par_gen stays: no cached value (motion.c vq) depends on these.  Inline:
 * two stores where the call would cost more. */
enum { PS_IN_FORCE, PS_WRITTEN };
static inline void params_force(unsigned axis, unsigned p, int32_t v, int how)
{
    par_a[p][axis] = v;
    if (how == PS_WRITTEN)
        par_w[p][axis] = v;
}

#endif
