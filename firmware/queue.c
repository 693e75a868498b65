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

/* The host may write anything into the header; the card trusts only the
 * fixed values of table 7.1 and indices inside 0..nel-1, so no access can
 * leave the element area.  The header is read once: the indices checked
 * are the indices used (a host writing between a check and a second read
 * could otherwise steer the card out of the queue). */
static int q_header(uint32_t q, uint32_t *front, uint32_t *rear)
{
    if (hal_rd32(q + QH_BASE) != Q_HEADER_SIZE || hal_rd32(q + QH_WIDTH) != Q_WIDTH ||
        hal_rd32(q + QH_NEL) != Q_NEL)
        return Q_CORRUPT;
    uint32_t f = hal_rd32(q + QH_FRONT), r = hal_rd32(q + QH_REAR);
    if (f >= Q_NEL || r >= Q_NEL)
        return Q_CORRUPT;
    *front = f;
    *rear = r;
    return 0;
}

int q_check(uint32_t q)
{
    uint32_t f, r;
    return q_header(q, &f, &r);
}

static uint32_t q_elem(uint32_t q, uint32_t i) { return q + Q_HEADER_SIZE + i * Q_WIDTH; }

int q_get(uint32_t q, mac4_msg_t *m)
{
    uint32_t front, rear;
    if (q_header(q, &front, &rear))
        return Q_CORRUPT;
    if (front == rear)
        return Q_EMPTY;
    uint32_t e = q_elem(q, rear);
    m->axis = hal_rd8(e + MSG_AXIS);
    m->code = hal_rd16(e + MSG_CODE);
    m->param = hal_rd32(e + MSG_PARAM);
    m->source = hal_rd8(e + MSG_SOURCE);
    hal_wr32(q + QH_REAR, q_next(rear, Q_NEL));
    return Q_OK;
}

int q_put(uint32_t q, const mac4_msg_t *m)
{
    uint32_t front, rear;
    if (q_header(q, &front, &rear))
        return Q_CORRUPT;
    uint32_t next = q_next(front, Q_NEL);
    if (next == rear)
        return Q_FULL;
    uint32_t e = q_elem(q, front);
    hal_wr8(e + MSG_AXIS, m->axis);
    hal_wr8(e + MSG_AXIS + 1, 0);
    hal_wr16(e + MSG_CODE, m->code);
    hal_wr32(e + MSG_PARAM, m->param);
    hal_wr8(e + MSG_SOURCE, m->source);
    hal_wr8(e + MSG_SOURCE + 1, 0);
    /* Element first, index last: the host never sees a half-written message. */
    hal_wr32(q + QH_FRONT, next);
    return Q_OK;
}
