/* 68000 side of hal.h: status-register access and the vector copy. */
#include "hal.h"

int hal_copy_vectors(void)
{
    /* The DPRAM holds the live vector table once the overlay is gone (3.1). */
    for (uint32_t i = 0; i < 256; i++)
        hal_wr32(DPRAM_VECTORS + 4 * i, hal_rd32(EPROM_BASE + 4 * i));
    return 0;
}

void hal_stop(void)
{
    hal_irq_save();
    for (;;)
        hal_wr16(WDG_KICK, 0);
}

void hal_stop_no_kick(void)
{
    hal_irq_save();
    for (;;)
        ;
}
