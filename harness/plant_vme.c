/*
 * plant_vme.c - the VMEbus master window (local $E00000-$EFFFFF, VME_PAGE
 * supplies A23-A20) and a small table of VME slave boards behind it.
 *
 * The one board type so far is an absolute encoder board coupled to an
 * axis' shaft (manual 7.2, MAC4-SSI: UWET 4, UWEA $80C000, UWEB 14).  It
 * presents its value big-endian at its base address: one 16-bit word when
 * it has up to 16 bits, else two words, MSW at base and LSW at base+2.
 * Reading the LSW latches the whole value and the following MSW read returns
 * the latched upper half, so the firmware's order (LSW at <ea>+2 first, then
 * MSW at <ea>, manual 4.4.2.1) reads a consistent value.  Writes are
 * acknowledged and ignored.  The window's bus cycles (the page register, the
 * bus timer that ends a cycle no board answers) are the VME interrupter's
 * (virq.c).
 */
#include "sim.h"
#include "periph.h"
#include "plant.h"

static uint32_t board_size(const plant_vme_t *b) { return b->bits <= 16 ? 2u : 4u; }

static plant_vme_t *find_board(sim_t *s, uint32_t addr)
{
    for (int i = 0; i < PLANT_NVME; i++) {
        plant_vme_t *b = &s->plant.vme[i];
        if (b->used && addr - b->base < board_size(b))
            return b;
    }
    return NULL;
}

/* The encoder's value at time t: floor(revolutions * res + 0.5) + offset,
 * wrapping after `turns` revolutions (single-turn: 1) and at 2^bits. */
uint32_t plant_vme_value(sim_t *s, const plant_vme_t *b, cyc_t t)
{
    plant_sync(s, b->axis, t);
    double u = (b->motor_shaft == PLANT_VME_LOAD ? plant_load_units(s, b->axis, t) : plant_units(s, b->axis, t)) /
               plant_units_per_rev(s, b->axis);   /* output revs (or the load's, in the same units) */
    if (b->motor_shaft == 1)
        u *= s->plant.ax[b->axis].gear;
    double c = u * b->res + 0.5;
    int64_t v = (int64_t)c;
    if ((double)v > c)
        v--;
    v += b->offset;
    uint64_t mask = b->bits >= 32 ? 0xFFFFFFFFull : (1ull << b->bits) - 1;
    if (b->turns) {
        int64_t mod = (int64_t)(b->turns * (uint64_t)(b->res + 0.5));
        if (mod > 0) {
            v %= mod;
            if (v < 0)
                v += mod;
        }
    }
    return (uint32_t)((uint64_t)v & mask);
}

int plant_vme_add(sim_t *s, uint32_t base, int axis, int bits, double res, uint64_t turns,
                  int64_t offset, int motor_shaft)
{
    if ((base & 1) || base > 0xFFFFFC || axis < 0 || axis >= MAC4_NAXES || bits < 1 || bits > 32 ||
        !(res > 0))
        return -1;
    plant_vme_remove(s, base);
    for (int i = 0; i < PLANT_NVME; i++) {
        plant_vme_t *b = &s->plant.vme[i];
        if (b->used)
            continue;
        b->used = 1;
        b->base = base;
        b->axis = axis;
        b->bits = bits;
        b->res = res;
        b->turns = turns;
        b->offset = offset;
        b->motor_shaft = motor_shaft;
        b->latched = 0;
        return 0;
    }
    return -2;   /* table full */
}

int plant_vme_remove(sim_t *s, uint32_t base)
{
    for (int i = 0; i < PLANT_NVME; i++)
        if (s->plant.vme[i].used && s->plant.vme[i].base == base) {
            s->plant.vme[i].used = 0;
            return 0;
        }
    return -1;
}

static uint32_t board_rd16(sim_t *s, plant_vme_t *b, uint32_t reg)
{
    cyc_t now = sim_now(s);
    if (board_size(b) == 2)
        return plant_vme_value(s, b, now) & 0xFFFF;
    if (reg == 2) {
        b->latch = plant_vme_value(s, b, now);
        b->latched = 1;
        return b->latch & 0xFFFF;
    }
    uint32_t v = b->latched ? b->latch : plant_vme_value(s, b, now);
    b->latched = 0;
    return v >> 16;
}

/* A read of the word at A24 address addr (even): 0 when no board answers. */
int plant_vme_rd16(sim_t *s, uint32_t addr, uint32_t *w)
{
    plant_vme_t *b = find_board(s, addr);
    if (!b)
        return 0;
    *w = board_rd16(s, b, (addr - b->base) & ~1u);
    return 1;
}

/* A write: acknowledged and ignored by a board; 0 when none answers. */
int plant_vme_wr16(sim_t *s, uint32_t addr) { return find_board(s, addr) != NULL; }
