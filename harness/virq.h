/* virq.h - the state of the VMEbus interrupter and of the master window's
 * page register (virq.c and the window's bus cycles in plant_vme.c). */
#ifndef VIRQ_H
#define VIRQ_H
#include <stdint.h>

typedef struct {
    uint8_t level;                 /* from LB1/LB2, table 2.1 */
    int pending;
    uint8_t vector;
    uint64_t iack_at;
    uint16_t page;
    int berr;
} vme_t;

#endif
