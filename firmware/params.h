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

#endif
