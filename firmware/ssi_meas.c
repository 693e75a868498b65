/*
 * ssi_meas.c - the MAC4-SSI's own encoder interface, the SSI receiver at P2
 * (<et> 1/2, 4.4.2.2), INIT's part of it: the hooks of card_variant.h, "the
 * card's own encoder".  The tick reads the receiver with measure.h's
 * measure_ssi_read; J1's Gray code status at every input change is ssi_card.h's.
 * The SSI image links it (Makefile, FW_SSI); the INC's and the STP's
 * counter is counter_meas.c.
 */
#include "fw.h"
#include "hal.h"
#include "card.h"
#include "params.h"
#include "measure.h"
#include "card_variant.h"

void measure_init_enc(unsigned n, meas_cfg_t *c, int32_t et, int32_t *eb, int32_t *ec)
{
    (void)ec;                        /* a written <ec> limits the range (6.3.8) */
    /* the code of the first reading is J1's now (the status follows at every input change) */
    axis_inputs_enc(axis_at[n], hal_rd16(AX_REG(n, AX_IN)));
    if (et > 2)
        return;
    /* the receiver delivers 26 - <sc> bits: <eb> is at most that */
    params_force(n, P_EA, (int32_t)(AX_REG(n, AX_SSI_HI) & 0xFFFFFFu), PS_IN_FORCE);
    int32_t bits = (int32_t)SSI_CLOCKS - PAR(n, SC);
    if (*eb > bits)
        *eb = bits;
    c->path = EXT_SSI;
    c->sc = (uint8_t)PAR(n, SC);
}

/* INIT's first reading: a read started now, right-justified (4.4.2.2),
 * within <eb>, Gray to binary with J1 set; the tick's is measure_ssi_read. */
int measure_read_enc(unsigned n, const meas_cfg_t *c, uint32_t *raw)
{
    hal_wr16(AX_REG(n, AX_SSI_START), 1);
    for (unsigned i = 0; (hal_rd16(AX_REG(n, AX_IN)) & AX_IN_SSI_BUSY) && i < 200; i++)
        ;
    uint32_t hi = hal_rd16(AX_REG(n, AX_SSI_HI));
    uint32_t v = (((hi << 16) | hal_rd16(AX_REG(n, AX_SSI_LO))) >> c->sc) & c->mask;
    if (axes[n].ustat & UB(GRAY))
        v = gray_to_binary(v);
    *raw = v;
    return 0;
}

/* The tick's measure_ssi_read; absolute, a path of its own on a linear axis and
 * on a circular one (the compensation table follows only the linear one as
 * relative: the circular one's motion is already the difference of two
 * readings, axis.h axis_kind_relative). */
uint8_t measure_kind_enc(int32_t et, int linear)
{
    if (et != 2)
        return MK_SSI;
    return linear ? MK_SSI_ABS : MK_SSI_CIRC;
}

/* The receiver reads the encoder at every timer expiry (the sampling
 * instant): the tick finds the value there, or nearly. */
void axis_prepare_enc(axis_t *x, unsigned n, int32_t et)
{
    uint16_t sync = et <= 2 ? AX_CTRL_SSI_SYNC : 0;
    axis_ctrl_set(x, (uint16_t)((x->ctrl & ~AX_CTRL_SSI_SYNC) | sync));
    hal_wr16(AX_REG(n, AX_CTRL), x->ctrl);
}
