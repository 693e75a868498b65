/*
 * vme_irq.c - the card's VMEbus interrupter (4.6): one request is held
 * until the host's IACK, more wait in a FIFO here; vector 0 means off.
 */
#include "hal.h"
#include "card.h"

#define VIRQ_FIFO 16u
static uint8_t virq_fifo[VIRQ_FIFO];
static uint8_t virq_head;
volatile uint8_t vme_irq_waiting;      /* virq_tail != virq_head: see vme_irq_service() */
static uint8_t virq_tail;
uint32_t virq_lost;                    /* DPC_VME_IRQ_LOST, kept in RAM (published every tick) */

void vme_irq(uint8_t vector)
{
    if (vector == 0)
        return;                                   /* vector 0: interrupt off */
    unsigned prev = hal_irq_save();
    uint8_t next = (uint8_t)((virq_head + 1u) % VIRQ_FIFO);
    if (next == virq_tail) {
        hal_wr32(DPC_VME_IRQ_LOST, ++virq_lost);
    } else {
        virq_fifo[virq_head] = vector;
        virq_head = next;
        vme_irq_waiting = 1;
    }
    vme_irq_service();
    hal_irq_restore(prev);
}

void vme_irq_service_do(void)
{
    unsigned prev = hal_irq_save();
    if (virq_tail != virq_head && !(hal_rd16(VIRQ_STATUS) & VIRQ_ST_PENDING)) {
        hal_wr16(VIRQ_VECTOR, virq_fifo[virq_tail]);
        virq_tail = (uint8_t)((virq_tail + 1u) % VIRQ_FIFO);
    }
    vme_irq_waiting = virq_tail != virq_head;
    hal_irq_restore(prev);
}

void vme_irq_reset(void)
{
    virq_head = virq_tail = 0;
    virq_lost = 0;
    vme_irq_waiting = 0;
}
