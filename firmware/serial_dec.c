/*
 * serial_dec.c - the serial line's telegram decoder (manual 3.3,
 * docs/serial.md): a state machine fed one received byte at a time by the
 * driver's main-loop part (serial.c), which answers its events (a command,
 * a wrong checksum, a broken, cut-short or stalled telegram).  No hardware,
 * no state of its own: unit-tested natively (tests/unit/test_serial.c).
 */
#include "fw.h"
#include "serial.h"

uint8_t serial_checksum(const uint8_t data[SERIAL_DATA_LEN])
{
    unsigned sum = 0;
    for (unsigned i = 0; i < SERIAL_DATA_LEN; i++)
        sum += data[i];
    return (uint8_t)sum;
}

void serial_dec_init(serial_dec_t *d)
{
    d->state = SERIAL_DS_HUNT;
    d->n = 0;
    d->sum = 0;
    d->free_dles = 0;
    d->axis = 0;
    d->code = 0;
    d->param = 0;
    d->garbage = 0;
}

int serial_dec_busy(const serial_dec_t *d) { return d->state != SERIAL_DS_HUNT; }

static void start_telegram(serial_dec_t *d)
{
    d->state = SERIAL_DS_DATA;
    d->n = 0;
    d->sum = 0;
    d->free_dles = 0;
}

static void data_byte(serial_dec_t *d, uint8_t b)
{
    if (d->n == 0)
        d->axis = b;
    else if (d->n < 3)
        d->code = (uint16_t)(d->code << 8 | b);
    else
        d->param = d->param << 8 | b;
    d->n++;
    d->sum = (uint8_t)(d->sum + b);
    d->state = (d->n == SERIAL_DATA_LEN) ? SERIAL_DS_CSUM : SERIAL_DS_DATA;
}

/* The DLE held in HUNT_DLE turned out not to start a header.  It is garbage
 * unless it is the checksum $10 itself or that checksum's doubling. */
static void drop_held_dle(serial_dec_t *d)
{
    if (d->free_dles)
        d->free_dles--;
    else
        d->garbage++;
}

int serial_dec_step(serial_dec_t *d, uint8_t b, mac4_msg_t *m)
{
    switch (d->state) {
    case SERIAL_DS_HUNT_DLE:
        if (b == SERIAL_STX) {
            start_telegram(d);
        } else if (b == SERIAL_DLE) {
            drop_held_dle(d);            /* the new DLE is the candidate now */
        } else {
            drop_held_dle(d);
            d->free_dles = 0;
            d->garbage++;
            d->state = SERIAL_DS_HUNT;
        }
        return SERIAL_EV_NONE;

    case SERIAL_DS_DATA:
        if (b == SERIAL_DLE)
            d->state = SERIAL_DS_DATA_DLE;
        else
            data_byte(d, b);
        return SERIAL_EV_NONE;

    case SERIAL_DS_DATA_DLE:
        if (b == SERIAL_DLE) {           /* a doubled DLE: one data byte $10 */
            data_byte(d, SERIAL_DLE);
            return SERIAL_EV_NONE;
        }
        if (b == SERIAL_STX) {           /* a new header: the telegram before was cut short */
            start_telegram(d);
            return SERIAL_EV_TRUNCATED;
        }
        d->state = SERIAL_DS_HUNT;       /* DLE + anything else: broken; b belongs to it */
        return SERIAL_EV_BROKEN;

    case SERIAL_DS_CSUM: {
        int ev = (b == d->sum) ? SERIAL_EV_MSG : SERIAL_EV_CHECKSUM;
        if (ev == SERIAL_EV_MSG) {
            m->axis = d->axis;
            m->code = d->code;
            m->param = d->param;
            m->source = MSG_SRC_SERIAL;
        }
        if (b == SERIAL_DLE) {
            /* A checksum byte $10 may be followed by its doubling DLE (we send
             * it so), or directly by the next header; hold it as a possible
             * header DLE, and do not count it or one doubling as garbage. */
            d->state = SERIAL_DS_HUNT_DLE;
            d->free_dles = 2;
        } else {
            d->state = SERIAL_DS_HUNT;
        }
        return ev;
    }

    default:                             /* SERIAL_DS_HUNT, or a corrupt state */
        d->free_dles = 0;
        if (b == SERIAL_DLE) {
            d->state = SERIAL_DS_HUNT_DLE;
        } else {
            d->state = SERIAL_DS_HUNT;
            d->garbage++;
        }
        return SERIAL_EV_NONE;
    }
}

int serial_dec_timeout(serial_dec_t *d)
{
    int ev = SERIAL_EV_NONE;
    if (d->state == SERIAL_DS_HUNT_DLE)
        drop_held_dle(d);                /* a lone DLE, no telegram followed */
    else if (d->state != SERIAL_DS_HUNT)
        ev = SERIAL_EV_STALLED;
    d->state = SERIAL_DS_HUNT;
    d->free_dles = 0;
    return ev;
}
