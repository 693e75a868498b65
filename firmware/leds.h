/* leds.h - one axis' LEDs, the one body of the supervision
 * (supervise.c leds) and of the floor's reference models (bench/floor). */
#ifndef LEDS_H
#define LEDS_H
#include "inline.h"
#include "hal.h"
#include "card.h"
#include "params.h"
#include "card_variant.h"

/* The LEDs the firmware drives (2.5.3; the limit and reference LEDs follow
 * the input levels in hardware): D disabled, P pos_end, F the drive fault
 * signal as the card recognises it with the polarity <df> in force (UWSO),
 * whatever its level; on the STP F also shows an unacknowledged error
 * (7.1.2 led_fault). */
/* One axis' LEDs into l: inlined four times with a constant n (absolute
 * addresses, the bits immediate). */
FW_INLINE uint16_t axis_leds(uint16_t l, unsigned n)
{
    const axis_t *x = &axes[n];
    if (x->mode == M_DISABLE)
        l |= (uint16_t)(SYS_LED_D << SYS_LED_SHIFT(n));
    if (x->ustat & UB(POS_END))
        l |= (uint16_t)(SYS_LED_P << SYS_LED_SHIFT(n));
    int32_t df = PAR(n, DF);
    uint16_t df_on = 0;
    if (df != 0) {
        df_on = hal_rd16(AX_REG(n, AX_IN)) & AX_IN_DF;
        if (df == 2)
            df_on ^= AX_IN_DF;                    /* <df> 2: the signal high active */
    }
    if (df_on || card_led_fault(x))
        l |= (uint16_t)(SYS_LED_F << SYS_LED_SHIFT(n));
    return l;
}

#endif
