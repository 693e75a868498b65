/*
 * bus.c - the IPC's local bus as a table of address ranges, each answered
 * by a device and one of its register windows (a MAME-style address map),
 * its rows generated from the board description (bus_map.h).  68000 long accesses are two word cycles, high word first, as on
 * the card's 16-bit bus.  Accesses outside every region, writes to the
 * EPROM and byte writes to word-wide I/O registers are faults: reported
 * with the PC, never ignored.  They are also the bus cycles no device
 * acknowledges, which the card's bus timer ends with /BERR (docs/board.md,
 * "Bus errors"): bus_berr tells the 68000 (cpu_m68k.c), which takes the
 * bus error; a long access stops at the word that got it.
 */
#include <stdarg.h>
#include <string.h>
#include "sim.h"
#include "periph.h"
#include "cpu.h"

void sim_fault(sim_t *s, const char *fmt, ...)
{
    char msg[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    s->faults++;
    uint32_t pc = s->cpu_pc ? s->cpu_pc() & 0xFFFFFF : 0;   /* 24 address lines */
    sim_printf(s, "fault %s pc=$%06X\n", msg, pc);
    if (s->on_fault)
        s->on_fault(s);           /* gdb stops after the instruction, SIGSEGV (gdbstub.c) */
}

/* ---- memories ------------------------------------------------------------ */
static uint32_t mem_rd(const uint8_t *m, uint32_t off, int size)
{
    return size == 1 ? m[off] : (uint32_t)(m[off] << 8 | m[off + 1]);
}

static void mem_wr(uint8_t *m, uint32_t off, uint32_t v, int size)
{
    if (size == 1) {
        m[off] = (uint8_t)v;
    } else {
        m[off] = (uint8_t)(v >> 8);
        m[off + 1] = (uint8_t)v;
    }
}

static uint32_t dpram_rd(sim_t *s, uint32_t a, int size)
{
    if (s->sysctl & SYS_CTRL_OVERLAY)   /* boot overlay: EPROM at $000000 */
        return mem_rd(s->eprom, a, size);
    return mem_rd(s->dpram, a, size);
}
static void dpram_wr(sim_t *s, uint32_t a, uint32_t v, int size) { mem_wr(s->dpram, a, v, size); }
static uint32_t eprom_rd(sim_t *s, uint32_t a, int size) { return mem_rd(s->eprom, a, size); }
int bus_berr;                   /* a bus cycle got /BERR, at bus_berr_addr */
uint32_t bus_berr_addr;

static void berr(uint32_t addr)
{
    bus_berr = 1;
    bus_berr_addr = addr;
}

static void eprom_wr(sim_t *s, uint32_t a, uint32_t v, int size)
{
    (void)v;
    (void)size;
    /* the EPROMs' selects are decoded for reads only: no DTACK */
    sim_fault(s, "write to EPROM at $%06X", (unsigned)(EPROM_BASE + a));
    berr(EPROM_BASE + a);
}
static uint32_t sram_rd(sim_t *s, uint32_t a, int size)
{
    uint32_t v = mem_rd(s->sram, a, size);
    if (s->sram_fault_mask && (a & ~1u) == s->sram_fault_addr)
        v |= size == 1 ? (uint32_t)(s->sram_fault_mask >> ((a & 1) ? 0 : 8)) & 0xFF : s->sram_fault_mask;
    return v;
}
static void sram_wr(sim_t *s, uint32_t a, uint32_t v, int size) { mem_wr(s->sram, a, v, size); }

/* The memories: devices with one window and nothing else. */
const device_t dpram_device = {.name = "dpram", .win = {{dpram_rd, dpram_wr}}};
const device_t eprom_device = {.name = "eprom", .win = {{eprom_rd, eprom_wr}}};
const device_t sram_device = {.name = "sram", .win = {{sram_rd, sram_wr}}};

/* A row of the bus table: an address range, the device that answers there
 * and which of its register windows. */
typedef struct {
    uint32_t start, size;
    const char *name;
    const device_t *dev;
    int win;
    int word_io;                                                /* no byte writes */
} region_t;

static const region_t regions[] = {
#include "bus_map.h"          /* generated from board/mac4.toml (docs/board.md) */
};
#define NREGIONS (sizeof regions / sizeof regions[0])

static const region_t *find(uint32_t addr)
{
    for (unsigned i = 0; i < NREGIONS; i++)
        if (addr - regions[i].start < regions[i].size)
            return &regions[i];
    return NULL;
}

static uint32_t rd1(sim_t *s, uint32_t addr, int size)
{
    const region_t *r = find(addr);
    if (!r) {
        sim_fault(s, "unmapped read%d at $%06X", size * 8, (unsigned)addr);
        berr(addr);
        return size == 1 ? 0xFF : 0xFFFF;
    }
    uint32_t off = addr - r->start;
    const dev_window_t *w0 = &r->dev->win[r->win];
    if (!r->word_io)
        return w0->rd(s, off, size);
    /* I/O: a read may clear a flag (UART data, status), so re-evaluate IPL */
    uint32_t w = w0->rd(s, off & ~1u, 2);
    sim_update_irq(s);
    if (size == 1)   /* byte read of a word register */
        return (off & 1) ? (w & 0xFF) : (w >> 8);
    return w;
}

static void wr1(sim_t *s, uint32_t addr, uint32_t v, int size)
{
    const region_t *r = find(addr);
    if (!r) {
        sim_fault(s, "unmapped write%d at $%06X", size * 8, (unsigned)addr);
        berr(addr);
        return;
    }
    if (r->word_io && size == 1) {   /* the I/O decoder acknowledges word writes only */
        sim_fault(s, "byte write to word register at $%06X", (unsigned)addr);
        berr(addr);
        return;
    }
    r->dev->win[r->win].wr(s, addr - r->start, v, size);
    if (r->word_io)
        sim_update_irq(s);
}

uint64_t bus_reads;

uint32_t bus_read(sim_t *s, uint32_t addr, int size)
{
    bus_reads++;
    bus_berr = 0;
    addr &= 0xFFFFFF;                         /* 24 address lines */
    if (size == 4) {
        uint32_t hi = rd1(s, addr, 2);
        if (bus_berr)             /* the 68000 makes no second cycle */
            return hi << 16 | 0xFFFF;
        return hi << 16 | rd1(s, (addr + 2) & 0xFFFFFF, 2);
    }
    return rd1(s, addr, size);
}

void bus_write(sim_t *s, uint32_t addr, uint32_t v, int size)
{
    bus_berr = 0;
    addr &= 0xFFFFFF;
    if (size == 4) {
        wr1(s, addr, v >> 16, 2);
        if (!bus_berr)
            wr1(s, (addr + 2) & 0xFFFFFF, v & 0xFFFF, 2);
    } else {
        wr1(s, addr, v, size);
    }
    if (s->on_bus_write)          /* measurement (perf.c): after the whole write */
        s->on_bus_write(s, addr, v, size);
}

/* Would a bus cycle there be acknowledged?  No side effect (the check of a
 * handler's first words, cpu_m68k.c). */
int bus_decodes(uint32_t addr, int write, int size)
{
    const region_t *r = find(addr & 0xFFFFFF);
    if (!r)
        return 0;
    if (write && (r->dev == &eprom_device || (r->word_io && size == 1)))
        return 0;
    return 1;
}
