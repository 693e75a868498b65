/*
 * serial.h - the front-panel serial line (manual 3.3, 7.3.1), docs/serial.md.
 *
 * 4800 baud 8N1.  A telegram is DLE STX, seven data bytes (axis, code MSB,
 * code LSB, parameter MSB..LSB) in which every DLE ($10) is sent twice, and
 * a checksum: the low byte of the sum of the seven data bytes.  A broken
 * telegram is answered with a single NAK ($15).
 *
 * The UART interrupt only moves bytes between the UART and two ring
 * buffers; serial_poll() (main loop) decodes.  Valid commands wait in a small
 * FIFO of their own (source = MSG_SRC_SERIAL) until serial_get() takes them:
 * they never enter the DPRAM command queue, whose write index belongs to the
 * VME host (docs/interpretations.md, "Serial line").
 */
#ifndef SERIAL_H
#define SERIAL_H
#include "inline.h"
#include <stdint.h>
#include "queue.h"

/* ---- driver (cmd.c and the boot code) ----------------------------------- */
void serial_reset(void);                /* empty buffers, decoder to hunting, counters 0 */
/* main loop: decode received bytes (nothing to do, and no call, while the
 * line is quiet and no telegram is open) */
extern volatile uint8_t serial_rx_work;
void serial_poll_work(void);
static inline void serial_poll(void)
{
    if (serial_rx_work)
        serial_poll_work();
}
int serial_get(mac4_msg_t *m);          /* next decoded command (source 1): 1, or 0 if none */
extern uint8_t serial_fifo_count;
static inline int serial_pending(void) { return serial_fifo_count != 0; }   /* serial_get would give one */
void serial_send(const mac4_msg_t *m);  /* a response as a telegram */
/* The statistics, mirrored into the card data block (DPC_SERIAL_*):
 * serial.c's alone; inline here for the supervision after each tick, which
 * publishes two of the eight per tick, all of them every profile period. */
#define SERIAL_N_STATS 8u
extern uint32_t serial_stats[SERIAL_N_STATS];
FW_INLINE void serial_publish(unsigned phase)
{
    unsigned q = phase & 3u;
    const uint32_t *s = &serial_stats[2u * q];
    uint32_t d = DPC_SERIAL_RX_OK + 8u * q;
    hal_wr32(d, s[0]);
    hal_wr32(d + 4u, s[1]);
}
/* fw_isr_uart() (fw.h) is the level 4 interrupt: RX into the ring, TX out of it. */

/* ---- protocol constants ------------------------------------------------- */
#define SERIAL_DLE          0x10u
#define SERIAL_STX          0x02u
#define SERIAL_NAK          0x15u
#define SERIAL_DATA_LEN     7u                      /* axis, code (2), parameter (4) */
/* DLE STX, seven data bytes all doubled at worst, checksum doubled. */
#define SERIAL_TELEGRAM_MAX (2u + 2u * SERIAL_DATA_LEN + 2u)
/* A telegram that stalls this long between two bytes is dropped with a NAK
 * (a telegram takes 21 ms at 4800 baud; 100 ms is almost five of them). */
#define SERIAL_TIMEOUT_US   100000u

/* Buffer sizes (powers of two for the rings).  At 4800 baud a byte comes
 * every 2.08 ms, so RX_SIZE bytes are 260 ms of main-loop stall. */
#define SERIAL_RX_SIZE      128u
#define SERIAL_TX_SIZE      128u                    /* 7 worst-case telegrams */
#define SERIAL_FIFO_LEN     4u                      /* decoded commands waiting */

/* ---- pure codec (no hardware; unit-tested natively) ----------------------
 * No byte arrays indexed by constants: GCC 12 for m68k merges neighbouring
 * byte loads and stores into word and long moves even at odd addresses
 * (bswap and store-merging passes, -mstrict-align or not), which is an
 * address error on the 68000.  Bytes are shifted in and out of the message
 * fields instead. */
/* Encode m (axis, code, parameter; source ignored) as a telegram into buf,
 * which must hold SERIAL_TELEGRAM_MAX bytes.  Returns the length (10..18).
 * A checksum of $10 is sent doubled like a data byte (docs/serial.md). */
unsigned serial_encode(const mac4_msg_t *m, uint8_t *buf);
/* The checksum of seven data bytes: the low byte of their sum. */
uint8_t serial_checksum(const uint8_t data[SERIAL_DATA_LEN]);

/* Receive decoder, one byte at a time. */
#define SERIAL_DS_HUNT      0       /* between telegrams: looking for DLE */
#define SERIAL_DS_HUNT_DLE  1       /* a DLE that may start a header: STX next? */
#define SERIAL_DS_DATA      2       /* in the data field */
#define SERIAL_DS_DATA_DLE  3       /* a DLE in the data field: DLE (data) or STX (restart) next */
#define SERIAL_DS_CSUM      4       /* seven data bytes in, the checksum is next */
typedef struct {
    uint8_t state;                  /* SERIAL_DS_* */
    uint8_t n;                      /* data bytes so far, 0..7 */
    uint8_t sum;                    /* running checksum */
    uint8_t free_dles;              /* DLEs after a checksum of $10 that are not garbage */
    uint8_t axis;                   /* the data field, assembled as it arrives */
    uint16_t code;
    uint32_t param;
    uint32_t garbage;               /* bytes outside any telegram, since init */
} serial_dec_t;

/* Events of serial_dec_step / serial_dec_timeout. */
#define SERIAL_EV_NONE       0      /* byte taken, nothing to report */
#define SERIAL_EV_MSG        1      /* a valid telegram: *m filled (source 1) */
#define SERIAL_EV_CHECKSUM   2      /* checksum wrong: NAK */
#define SERIAL_EV_TRUNCATED  3      /* DLE STX inside a telegram: NAK, the new one is started */
#define SERIAL_EV_BROKEN     4      /* DLE followed by neither DLE nor STX: NAK */
#define SERIAL_EV_STALLED    5      /* serial_dec_timeout during a telegram: NAK */

void serial_dec_init(serial_dec_t *d);
int serial_dec_step(serial_dec_t *d, uint8_t b, mac4_msg_t *m);
/* Nothing arrived for SERIAL_TIMEOUT_US: drop what is in progress. */
int serial_dec_timeout(serial_dec_t *d);
/* 1 while a telegram or a possible telegram header is in progress. */
int serial_dec_busy(const serial_dec_t *d);

#endif
