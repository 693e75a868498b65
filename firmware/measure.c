/*
 * measure.c - position measurement, first stage of the tick (manual 4.4):
 * raw value -> significant bits <eb> -> relative (overflow-safe delta) or
 * absolute (range check against <ec>) -> measured position; the axis
 * position is that plus the axis offset <ao> (4.3.2).
 */
#include "fw.h"
#include "hal.h"
#include "mul16.h"
#include "card.h"
#include "params.h"
#include "measure.h"
#include "card_variant.h"
#include "axis.h"

meas_cfg_t meas_cfg[MAC4_NAXES];
static uint32_t eb_mask(int32_t eb) { return eb >= 32 ? 0xFFFFFFFFu : (((uint32_t)1 << eb) - 1u); }

/* The host's own DPRAM after manual table 3.1 (docs/memory-map.md): per
 * axis the flag field and counter content from $3308 + n*$400 to the end of
 * that axis' block, and the unused $4900-$FFEE.  Not the vector table and
 * monitor area, the axis data the card publishes, the card data block at
 * $4000, the stop bits or the queues. */
#define DP_FREE_START (DP_RSP_QUEUE + 0x100u)

static int dp_host_owned(uint32_t lo, uint32_t hi)          /* the bytes [lo, hi) */
{
    if (lo >= DP_FREE_START && hi <= DP_HOST_END + 1u)
        return 1;
    for (unsigned n = 0; n < MAC4_NAXES; n++)
        if (lo >= DP_EXT_FLAG(n) && hi <= DP_AXIS_DATA(n) + DP_AXIS_STRIDE)
            return 1;
    return 0;
}

/* May an external position be read at <ea> with <eb> significant bits
 * (<et> 3/4, table 4.3, 3.5.2)?  Even (68000 word accesses); below $10000
 * a DPRAM offset whose flag word at <ea>-2 and 32-bit value lie in the
 * host's DPRAM; otherwise a VMEbus A24 address, and with <eb> > 16 the LSW
 * at <ea>+2 in the same 1 MiB page of the master window.  eb 0: the width
 * is not known yet (UWEA). */
int measure_ea_ok(uint32_t ea, int32_t eb)
{
    if (ea & 1u)
        return 0;
    if (ea < DPRAM_SIZE)
        return ea >= 2u && dp_host_owned(ea - 2u, ea + 4u);
    if (ea > 0xFFFFFFu)
        return 0;
    return eb <= 16 || (ea & (VME_WIN_SIZE - 1u)) <= VME_WIN_SIZE - 4u;
}

/* 6.3.8, once: axis.h's axis_encoder_error_at */
void measure_encoder_error(unsigned n)
{
    axis_t *x = axis_at[n];
    PIN_PTR(x);
    axis_encoder_error_at(x, &meas_cfg[n], n);
}

/* The actual position from meas and <ao>, wrapped on a circular axis
 * (INIT, RCP's WAO, a justification's zero): main loop. */
void measure_set_pos(unsigned n)
{
    axis_t *x = &axes[n];
    int32_t pos = pos_add(x->meas, PAR(n, AO));
    if (!x->linear) {
        pos %= x->cr;          /* main loop only: a division is fine here */
        if (pos < 0)
            pos += x->cr;
    }
    measure_pos_set(x, pos);
}

void measure_init(unsigned n)
{
    axis_t *x = axis_at[n];
    meas_cfg_t *c = &meas_cfg[n];
    int32_t et = PAR(n, ET), eb = PAR(n, EB), ec = PAR(n, EC);
    c->path = EXT_NONE;                                 /* the tick's own path, or none */
    /* Table 4.3 "def." (docs/interpretations.md): the card's own encoder
     * (<et> 0-2) limits <eb> and <ec> to what it delivers (card_variant.h:
     * counter_meas.c, ssi_meas.c); a written <ec> limits the range (6.3.8).
     * Only the values in force change: UR.. reads back what the host wrote,
     * so a later INIT derives afresh. */
    measure_init_enc(n, c, et, &eb, &ec);
    if (et <= 2)
        params_force(n, P_EB, eb, PS_IN_FORCE);
    /* the range in force: <ec>, or 2^<eb> for 0 or anything larger */
    uint32_t lim = eb_mask(eb);
    if (ec > 0 && (uint32_t)ec - 1u < lim)
        lim = (uint32_t)ec - 1u;
    c->lim = lim;
    c->range = lim < eb_mask(eb) ? (int32_t)(lim + 1u) : 0;
    c->half = c->range >> 1;
    params_force(n, P_EC, lim < (uint32_t)INT32_MAX ? (int32_t)(lim + 1u) : 0, PS_IN_FORCE);   /* 0: 2^<eb> */
    /* where an external position is read; cmd.c refused INIT otherwise */
    uint32_t ea = (uint32_t)PAR(n, EA);
    if (et >= 3 && measure_ea_ok(ea, eb)) {             /* else EXT_NONE: an encoder error */
        if (ea < DPRAM_SIZE) {
            c->path = EXT_DPRAM;
            c->addr = ea;
        } else {
            c->path = eb <= 16 ? EXT_VME16 : EXT_VME32;
            c->page = (uint16_t)(ea >> 20);
            c->addr = VME_WIN_BASE + (ea & (VME_WIN_SIZE - 1u));
        }
    }
    c->abs = et == 2 || et == 4;
    c->mask = eb_mask(eb);
    c->sign = eb < 32 ? (uint32_t)1 << (eb - 1) : 0;
    c->failed = 0;
    /* A repeated INIT restarts a relative measurement at 0 (4.9). */
    x->meas = 0;
    x->vel = 0;
    uint32_t raw;
    if ((et <= 2 ? measure_read_enc(n, c, &raw) : measure_ext_read(x, n, c, &raw)) == 0) {
        raw &= eb_mask(eb);
        x->counter = x->raw = raw;
        if (et == 2 || et == 4)
            x->meas = (int32_t)raw;
    }
    measure_init_card(n);                               /* STP: ratio, tolerance, BR; meas in steps */
    axis_prepare(n);
    measure_set_pos(n);
}
