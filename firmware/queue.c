#include "queue.h"
#include "hal.h"

void q_create(uint32_t q)
{
    /* queueopen() of manual 7.3.2: executed by the card only.  The DPRAM
     * keeps the old header across a reset and the host may be polling it:
     * the header is made invalid first and valid last, so the host never
     * sees a sane header whose front and rear differ over stale elements
     * (new front with the old rear, or the reverse). */
    hal_wr32(q + QH_BASE, 0);
    hal_wr32(q + QH_FRONT, 0);
    hal_wr32(q + QH_REAR, 0);
    hal_wr32(q + QH_FREE, 0);
    hal_wr32(q + QH_WIDTH, Q_WIDTH);
    hal_wr32(q + QH_NEL, Q_NEL);
    hal_wr32(q + QH_BASE, Q_HEADER_SIZE);
}

/* Any queue, by address (the command path uses the inline q_get_at and
 * q_put_at of queue.h with the address known at compile time). */
int q_check(uint32_t q)
{
    uint32_t f, r;
    return q_header_at(q, &f, &r);
}

int q_get(uint32_t q, mac4_msg_t *m) { return q_get_at(q, m, 1); }

int q_put(uint32_t q, const mac4_msg_t *m) { return q_put_at(q, m->axis, m->code, m->param, m->source); }
