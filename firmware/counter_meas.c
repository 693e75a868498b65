/*
 * counter_meas.c - the card's own encoder when it is the internal 24-bit
 * counter (MAC4-INC <et> 1; MAC4-STP <et> 0/1, steps or the motor's
 * encoder, table 4.3): INIT's part, the hooks of card_variant.h, "the
 * card's own encoder".  The tick reads the counter with measure.h's
 * measure_counter.  The INC and STP images link it (Makefile, FW_INC,
 * FW_STP); the SSI's receiver is ssi_meas.c.
 */
#include "fw.h"
#include "hal.h"
#include "card.h"
#include "params.h"
#include "measure.h"
#include "card_variant.h"

/* Table 4.3 "def." (docs/interpretations.md): the counter is 24 bits
 * whatever was written, its range 2^24. */
void measure_init_enc(unsigned n, meas_cfg_t *c, int32_t et, int32_t *eb, int32_t *ec)
{
    (void)c;                        /* the counter's path is the tick's own (EXT_NONE) */
    if (et > 2)
        return;
    params_force(n, P_EA, (int32_t)(AX_REG(n, AX_CNT_HI) & 0xFFFFFFu), PS_IN_FORCE);
    *eb = 24;
    *ec = 0;
}

int measure_read_enc(unsigned n, const meas_cfg_t *c, uint32_t *raw)
{
    (void)c;
    uint32_t hi = hal_rd16(AX_REG(n, AX_CNT_HI));   /* latches LO */
    *raw = (hi << 16) | hal_rd16(AX_REG(n, AX_CNT_LO));
    return 0;
}

/* <et> 0/1: the tick's counter path; anything else is the external one. */
uint8_t measure_kind_enc(int32_t et, int linear)
{
    (void)linear;
    return et <= 1 ? MK_COUNTER : MK_OTHER;
}

void axis_prepare_enc(axis_t *x, unsigned n, int32_t et)
{
    (void)x; (void)n; (void)et;     /* the counter counts without a set-up */
}
