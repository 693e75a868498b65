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
#include <stdint.h>

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

#endif
