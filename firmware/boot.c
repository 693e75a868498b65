/*
 * boot.c - reset and initialisation (manual 2.5.2 table 2.16, 4, 7.3.3).
 * Display: $1 CPU initialised, $2 RAM test, $3 EPROM check sum, $5 ready.
 * A failing step stops the card showing its digit with the decimal point.
 */
#include "fw.h"
#include "hal.h"
#include "crc16.h"
#include "queue.h"
#include "card.h"

static void display(unsigned v)
{
    hal_wr16(SYS_DISPLAY, (uint16_t)v);
    hal_wr32(DPC_BOOT_STATE, v);
}

static void show_error(unsigned digit, uint32_t code)
{
    hal_irq_save();
    hal_wr32(DPC_BOOT_ERROR, code);
    display((digit & 0xFu) | SYS_DISPLAY_DP);
}

void fw_halt(unsigned digit, uint32_t code)
{
    show_error(digit, code);
    /* Stopped, but kept alive: the watchdog must not turn the error display
     * of a RAM or EPROM fault into a reset loop; the host reads the reason
     * at $4004. */
    hal_stop();
}

void fw_halt_for_watchdog(unsigned digit, uint32_t code)
{
    show_error(digit, code);
    hal_stop_no_kick();
}

/* Pattern for a RAM word: depends on every address line of the 32 KiB
 * SRAM (A1-A14) so that shorted or stuck address lines show up, not only
 * stuck data bits; the second pass inverts every bit. */
static uint16_t ram_pattern(uint32_t a) { return (uint16_t)((a >> 1) ^ 0x5A3Cu); }

/* Returns 0 or the first failing address. Uses no static data.  The words
 * are written and compared two at a time, as one long (the high word at a,
 * the low one at a + 2: the 68000 makes a long two word cycles), so the
 * loop's own instructions cost half as much per word; the patterns are
 * the words' own, as ram_pattern says.  The high halves count a >> 1, the
 * low halves a >> 1 plus 1: both step by 2 a long, with no carry between
 * them (a >> 1 of the SRAM's words stays below $4000 in 16 bits). */
static uint32_t ram_test(uint32_t base, uint32_t size)
{
    for (int pass = 0; pass < 2; pass++) {
        uint16_t k = (uint16_t)(ram_pattern(0) ^ (pass ? 0xFFFFu : 0u));
        uint32_t k2 = (uint32_t)k << 16 | k;
        uint32_t v0 = ((base >> 1) & 0xFFFFu) << 16 | (((base >> 1) + 1u) & 0xFFFFu), v = v0;
        for (uint32_t a = base; a < base + size; a += 4, v += 0x00020002u)
            hal_wr32(a, v ^ k2);
        hal_wr16(WDG_KICK, 0);
        v = v0;
        for (uint32_t a = base; a < base + size; a += 4, v += 0x00020002u) {
            uint32_t got = hal_rd32(a) ^ v ^ k2;
            if (got)
                return got >> 16 ? a : a + 2u;
        }
        hal_wr16(WDG_KICK, 0);
    }
    return 0;
}

int fw_boot_stage1(void)
{
    hal_wr16(WDG_KICK, 0);
    hal_copy_vectors();
    /* The card's part of the host area starts from zero: counters, status,
     * interlock flags and stop bits (manual 3.1); the queues follow later.
     * After a watchdog reset the fault record stays for the host to read. */
    uint32_t rec[4], faults = 0;
    int keep = (hal_rd16(SYS_STATUS) & SYS_ST_WDG_RESET) != 0;
    if (keep) {
        for (unsigned i = 0; i < 4; i++)
            rec[i] = hal_rd32(DPC_FAULT_VECTOR + 4u * i);
        faults = hal_rd32(DPC_FAULT_COUNT);
    }
    for (uint32_t a = DP_HOST_AREA; a < DP_CMD_QUEUE; a += 4)
        hal_wr32(a, 0);
    if (keep) {
        for (unsigned i = 0; i < 4; i++)
            hal_wr32(DPC_FAULT_VECTOR + 4u * i, rec[i]);
        hal_wr32(DPC_FAULT_COUNT, faults);
    }
    display(1);
    display(2);
    uint32_t bad = ram_test(SRAM_BASE, SRAM_SIZE);
    if (bad) {
        hal_wr32(DPC_RAM_BAD_ADDR, bad);
        fw_halt(2, DPC_ERR_RAM);
    }
    return 0;
}

/* The CRC of the EPROM's bytes from a (even) for 2 n bytes: both bytes of
 * a word per pass (the even and the odd chip), the CRC kept as its halves
 * (crc16.h): about 75 cycles a byte on the 68000, where the word-wise
 * crc16_update took 145. */
static uint16_t eprom_crc(uint16_t crc, uint32_t a, uint32_t n)
{
    uint8_t hi = (uint8_t)(crc >> 8), lo = (uint8_t)crc;
    do {
        crc16_step(&hi, &lo, hal_rd8(EPROM_BASE + a));
        crc16_step(&hi, &lo, hal_rd8(EPROM_BASE + a + 1u));
        a += 2u;
    } while (--n);
    return (uint16_t)((unsigned)hi << 8 | lo);
}

static int eprom_checksum_ok(void)
{
    crc16_init_table();
    uint16_t crc = CRC16_INIT;
    /* in blocks of 4 KiB, the watchdog kicked before each; the last stops
     * short of the CRC's four bytes */
    for (uint32_t b = 0; b < EPROM_CRC_OFFSET; b += 0x1000u) {
        hal_wr16(WDG_KICK, 0);
        uint32_t end = b + 0x1000u < EPROM_CRC_OFFSET ? b + 0x1000u : EPROM_CRC_OFFSET;
        crc = eprom_crc(crc, b, (end - b) / 2u);
    }
    uint16_t stored = hal_rd16(EPROM_BASE + EPROM_CRC_OFFSET);
    uint16_t inverse = hal_rd16(EPROM_BASE + EPROM_CRC_OFFSET + 2);
    hal_wr32(DPC_CRC_EXPECTED, stored);
    hal_wr32(DPC_CRC_COMPUTED, crc);
    return crc == stored && (uint32_t)stored + inverse == 0xFFFFu;  /* inverse == ~stored */
}

static void write_banner(void)
{
    /* The banner stands in the element area at $4818 while the queue is
     * empty (front == rear): host software polls for it, and the first
     * response overwrites it (docs/interpretations.md). */
    static const char banner[] = FW_BANNER;
    for (unsigned i = 0; i < sizeof banner; i++)
        hal_wr8(DP_RSP_QUEUE + Q_HEADER_SIZE + i, (uint8_t)banner[i]);
}

void fw_init(void)
{
    hal_wr32(DPC_BOOT_ERROR, DPC_ERR_NONE);
    display(3);
    if (!eprom_checksum_ok())
        fw_halt(3, DPC_ERR_CHECKSUM);

    card_reset();               /* outputs to reset state, default parameters */
    hal_wr32(DPC_VERSION, FW_VER_WORD);

    q_create(DP_CMD_QUEUE);
    q_create(DP_RSP_QUEUE);
    write_banner();
    card_start();               /* timer, serial line, interrupts on */
    display(5);                 /* ready: a host that sees $5 finds the card running */
}
