/*
 * host.c - the VME host's side of the DPRAM: it enqueues commands (writing
 * only the command queue's front) and dequeues responses (writing only the
 * response queue's rear), exactly as manual 7.3.2 describes a host.
 */
#include "sim.h"
#include "buswait.h"

void (*dp_written)(void);

uint16_t dp_rd16(sim_t *s, uint32_t off)
{
    off &= 0xFFFE;
    return (uint16_t)(s->dpram[off] << 8 | s->dpram[off + 1]);
}

uint32_t dp_rd32(sim_t *s, uint32_t off)
{
    return (uint32_t)dp_rd16(s, off) << 16 | dp_rd16(s, off + 2);
}

void dp_wr16(sim_t *s, uint32_t off, uint16_t v)
{
    if (dp_written)           /* the CPU may read it (the idle skip, idle.c) */
        dp_written();
    off &= 0xFFFE;
    s->dpram[off] = (uint8_t)(v >> 8);
    s->dpram[off + 1] = (uint8_t)v;
}

void dp_wr32(sim_t *s, uint32_t off, uint32_t v)
{
    dp_wr16(s, off, (uint16_t)(v >> 16));
    dp_wr16(s, off + 2, (uint16_t)v);
}

/* The host's own accesses, each a D16 slave cycle on the DPRAM that holds
 * its word for a while (buswait.h: the card's access to it waits). */
static uint16_t h_rd16(sim_t *s, uint32_t off)
{
    buswait_host_access(sim_now(s), off);
    return dp_rd16(s, off);
}
static uint32_t h_rd32(sim_t *s, uint32_t off) { return (uint32_t)h_rd16(s, off) << 16 | h_rd16(s, off + 2); }
static void h_wr16(sim_t *s, uint32_t off, uint16_t v)
{
    buswait_host_access(sim_now(s), off);
    dp_wr16(s, off, v);
}
static void h_wr32(sim_t *s, uint32_t off, uint32_t v)
{
    h_wr16(s, off, (uint16_t)(v >> 16));
    h_wr16(s, off + 2, (uint16_t)v);
}

/* Returns 1 when queued, 0 when the queue is full, -1 when its header is
 * not one the host can use (not created yet, or corrupt). */
int host_send(sim_t *s, uint8_t axis, uint16_t code, uint32_t param, uint8_t source)
{
    uint32_t q = DP_CMD_QUEUE;
    uint32_t base = h_rd32(s, q + QH_BASE), width = h_rd32(s, q + QH_WIDTH);
    uint32_t nel = h_rd32(s, q + QH_NEL);
    uint32_t front = h_rd32(s, q + QH_FRONT), rear = h_rd32(s, q + QH_REAR);
    if (base != Q_HEADER_SIZE || width != Q_WIDTH || nel != Q_NEL || front >= nel || rear >= nel)
        return -1;
    uint32_t next = (front + 1) % nel;
    if (next == rear)
        return 0;
    uint32_t e = q + base + front * width;
    h_wr16(s, e + MSG_AXIS, (uint16_t)(axis << 8));
    h_wr16(s, e + MSG_CODE, code);
    h_wr32(s, e + MSG_PARAM, param);
    h_wr16(s, e + MSG_SOURCE, (uint16_t)(source << 8));
    h_wr32(s, q + QH_FRONT, next);
    return 1;
}

/* Dequeue and print every response waiting.  Returns how many. */
int host_poll_responses(sim_t *s)
{
    uint32_t q = DP_RSP_QUEUE;
    int n = 0;
    for (;;) {
        uint32_t base = h_rd32(s, q + QH_BASE), width = h_rd32(s, q + QH_WIDTH);
        uint32_t nel = h_rd32(s, q + QH_NEL);
        uint32_t front = h_rd32(s, q + QH_FRONT), rear = h_rd32(s, q + QH_REAR);
        if (base != Q_HEADER_SIZE || width != Q_WIDTH || nel != Q_NEL || front >= nel || rear >= nel)
            return n;
        if (front == rear)
            return n;
        uint32_t e = q + base + rear * width;
        sim_printf(s, "resp %u %u 0x%08X\n", h_rd16(s, e + MSG_AXIS) >> 8, h_rd16(s, e + MSG_CODE),
                   h_rd32(s, e + MSG_PARAM));
        h_wr32(s, q + QH_REAR, (rear + 1) % nel);
        n++;
    }
}
