/*
 * queue.h - the command and response queues in the DPRAM (manual 3.2,
 * 7.3.2, table 7.1): ring buffers of nel = 10 elements of width 10 bytes
 * behind a header of six 32-bit words.  front is the write index, rear the
 * read index; at most nel-1 elements are in use.  The card writes only the
 * command queue's rear and the response queue's front (besides creating
 * both at boot).
 */
#ifndef QUEUE_H
#define QUEUE_H
#include "inline.h"
#include <stdint.h>
#include "hal.h"

/* Keep an address in an address register, so the field accesses become
 * displacements from it (68000 target; nothing natively). */
#if defined(HAL_TARGET)
#define IN_ADDR_REG(v) __asm__("" : "+a"(v))
#else
#define IN_ADDR_REG(v) ((void)0)
#endif

typedef struct {
    uint8_t axis;
    uint16_t code;
    uint32_t param;
    uint8_t source;
} mac4_msg_t;

/* Results of q_get / q_put. */
#define Q_OK       1
#define Q_EMPTY    0   /* q_get: nothing to read */
#define Q_FULL     0   /* q_put: no room */
#define Q_CORRUPT  (-1) /* header fails q_check: nothing read or written */

/* Pure index arithmetic (unit-tested on the host). */
static inline uint32_t q_next(uint32_t i, uint32_t nel) { return (i + 1u == nel) ? 0u : i + 1u; }
static inline uint32_t q_used(uint32_t front, uint32_t rear, uint32_t nel)
{
    return (front >= rear) ? front - rear : nel - rear + front;
}

void q_create(uint32_t q);
int q_check(uint32_t q);            /* 0 if the header is sane, else Q_CORRUPT */
int q_get(uint32_t q, mac4_msg_t *m);
int q_put(uint32_t q, const mac4_msg_t *m);

/* ---- the same, inline for a queue address known at compile time -------
 * (the command path: DP_CMD_QUEUE / DP_RSP_QUEUE become absolute short
 * addresses, the element is moved field by field in word and long moves at
 * even addresses, and nothing is read twice).
 *
 * The host may write anything into the header; the card trusts only the
 * fixed values of table 7.1 and indices inside 0..nel-1, so no access can
 * leave the element area.  The header is read once: the indices checked
 * are the indices used (a host writing between a check and a second read
 * could otherwise steer the card out of the queue). */
FW_INLINE int q_header_at(uint32_t q, uint32_t *front, uint32_t *rear)
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

/* Byte offset of element i (0..9) from the queue's start: 24 + 10 i.  In
 * 32 bits: GCC makes 10 i four adds in the address register, where a
 * 16-bit offset costs a zero extension on top (no multiply either way). */
static inline uint32_t q_elem_off(uint32_t i)
{
    return Q_HEADER_SIZE + i * Q_WIDTH;
}

/* The element at rear read: rear on to the next, which gives the element
 * back to the host. */
FW_INLINE void q_rear_on(uint32_t q, uint32_t rear)
{
    hal_wr32(q + QH_REAR, rear == Q_NEL - 1u ? 0u : rear + 1u);
}

/* Take the element at rear (the header checked, front != rear); its
 * source byte only when want_source (the command path answers a VME
 * command on the VMEbus whatever that byte says). */
FW_INLINE void q_take_at(uint32_t q, uint32_t rear, mac4_msg_t *m,
                                                            int want_source)
{
    uint32_t e = q + q_elem_off(rear);
    IN_ADDR_REG(e);
    m->axis = hal_rd8(e + MSG_AXIS);
    m->code = hal_rd16(e + MSG_CODE);
    m->param = hal_rd32(e + MSG_PARAM);
    if (want_source)
        m->source = hal_rd8(e + MSG_SOURCE);
    q_rear_on(q, rear);
}

FW_INLINE int q_get_at(uint32_t q, mac4_msg_t *m, int want_source)
{
    uint32_t front, rear;
    if (q_header_at(q, &front, &rear))
        return Q_CORRUPT;
    if (front == rear)
        return Q_EMPTY;
    q_take_at(q, rear, m, want_source);
    return Q_OK;
}

/* The message as scalars, so that a constant source costs nothing. */
FW_INLINE int q_put_at(uint32_t q, uint8_t axis, uint16_t code, uint32_t param,
                                                          uint8_t source)
{
    uint32_t front, rear;
    if (q_header_at(q, &front, &rear))
        return Q_CORRUPT;
    uint32_t next = front == Q_NEL - 1u ? 0u : front + 1u;
    if (next == rear)
        return Q_FULL;
    uint32_t e = q + q_elem_off(front);
    IN_ADDR_REG(e);
    /* the element's five words: axis and an empty byte, code, parameter
     * (two words in one long move), source and an empty byte */
    hal_wr16(e + MSG_AXIS, (uint16_t)((uint16_t)axis << 8));
    hal_wr16(e + MSG_CODE, code);
    hal_wr32(e + MSG_PARAM, param);
    hal_wr16(e + MSG_SOURCE, (uint16_t)((uint16_t)source << 8));
    /* Element first, index last: the host never sees a half-written message. */
    hal_wr32(q + QH_FRONT, next);
    return Q_OK;
}

#endif
