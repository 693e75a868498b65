/*
 * profile.c - where the 68000's cycles go, measured by the emulator (no
 * firmware instrumentation): every instruction's cycles are charged to the
 * function that contains it, using the symbol table the build writes
 * (build/eprom/mac4-CARD.sym, from nm).  `profile on|off|reset|report [N]`,
 * and `profile pcs FILE`: the same cycles per instruction address of the
 * EPROM, for tools/annotate.py to lay beside the disassembly (the firmware
 * inlines most of its hot paths, so a function is often too coarse).
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "m68k.h"
#include "profile.h"
#include "idle.h"
#include "mac4_map.h"

int mac4_profiling;

typedef struct {
    uint32_t addr;
    char name[128];
    uint64_t cycles, calls;
} psym_t;

static psym_t *syms;
static unsigned nsyms;
static uint32_t last_pc;
static int last_cycles;
static int have_last;
/* per instruction of the EPROM (even addresses): cycles and executions */
static uint64_t pc_cycles[EPROM_SIZE / 2], pc_count[EPROM_SIZE / 2];

static int by_addr(const void *a, const void *b)
{
    uint32_t x = ((const psym_t *)a)->addr, y = ((const psym_t *)b)->addr;
    return x < y ? -1 : x > y;
}

int profile_load_symbols(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    char line[256];
    unsigned cap = 0;
    while (fgets(line, sizeof line, f)) {
        unsigned addr;
        char type, name[128];
        if (sscanf(line, "%x %c %127s", &addr, &type, name) != 3)
            continue;
        if (type != 'T' && type != 't')
            continue;
        if (nsyms == cap) {
            cap = cap ? cap * 2 : 256;
            psym_t *n = realloc(syms, cap * sizeof *syms);
            if (!n) {
                fclose(f);
                return -1;
            }
            syms = n;
        }
        syms[nsyms].addr = addr;
        snprintf(syms[nsyms].name, sizeof syms[nsyms].name, "%s", name);
        syms[nsyms].cycles = syms[nsyms].calls = 0;
        nsyms++;
    }
    fclose(f);
    if (nsyms)                  /* qsort(NULL, 0, ...) is undefined */
        qsort(syms, nsyms, sizeof *syms, by_addr);
    return (int)nsyms;
}

static psym_t *find(uint32_t pc)
{
    unsigned lo = 0, hi = nsyms;
    while (lo < hi) {
        unsigned mid = (lo + hi) / 2;
        if (syms[mid].addr <= pc)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo ? &syms[lo - 1] : NULL;
}

/* Added for harness/perf.c: a second per-instruction observer, which turns
 * the Musashi hook on without the per-function accounting. */
static int accounting;
static void (*instr_hook)(unsigned pc);

void profile_set_hook(void (*hook)(unsigned pc))
{
    instr_hook = hook;
    mac4_profiling = (accounting || instr_hook) | (mac4_profiling & MAC4_PROFILING_IDLE);
    mac4_hooks_update();
}

int profile_symbol(const char *name, uint32_t *addr)
{
    for (unsigned i = 0; i < nsyms; i++)
        if (!strcmp(syms[i].name, name)) {
            *addr = syms[i].addr;
            return 0;
        }
    return -1;
}

/* The cycles from the last instruction seen up to now go to it (and an
 * interrupt's acknowledge to the instruction it followed). */
static void charge(int now)
{
    if (have_last && now >= last_cycles) {
        psym_t *s = find(last_pc);
        if (s) {
            s->cycles += (uint64_t)(now - last_cycles);
            if (last_pc == s->addr)
                s->calls++;
        }
        uint32_t off = last_pc - EPROM_BASE;
        if (off < EPROM_SIZE) {
            pc_cycles[off / 2] += (uint64_t)(now - last_cycles);
            pc_count[off / 2]++;
        }
    }
}

void mac4_profile_instr(unsigned pc)
{
    if (mac4_profiling & MAC4_PROFILING_IDLE)
        mac4_idle_instr(pc);         /* the idle skip records (idle.c) */
    if (instr_hook)
        instr_hook(pc);
    if (!accounting)
        return;
    int now = m68k_cycles_run();
    charge(now);
    last_pc = pc;
    last_cycles = now;
    have_last = 1;
}

void profile_slice_start(void) { have_last = 0; }

/* The slice's last instruction, which no next hook call closes. */
void profile_slice_end(int ran)
{
    if (accounting)
        charge(ran);
    have_last = 0;
}

void profile_set(int on)
{
    accounting = on;
    mac4_profiling = (accounting || instr_hook) | (mac4_profiling & MAC4_PROFILING_IDLE);
    mac4_hooks_update();
    have_last = 0;
}

void profile_reset(void)
{
    for (unsigned i = 0; i < nsyms; i++)
        syms[i].cycles = syms[i].calls = 0;
    memset(pc_cycles, 0, sizeof pc_cycles);
    memset(pc_count, 0, sizeof pc_count);
}

int profile_pcs(const char *path)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    for (uint32_t i = 0; i < EPROM_SIZE / 2; i++)
        if (pc_count[i])
            fprintf(f, "%06x %llu %llu\n", (unsigned)(EPROM_BASE + 2 * i), (unsigned long long)pc_cycles[i],
                    (unsigned long long)pc_count[i]);
    return fclose(f) ? -1 : 0;
}

static int by_cycles(const void *a, const void *b)
{
    uint64_t x = ((const psym_t *)a)->cycles, y = ((const psym_t *)b)->cycles;
    return x < y ? 1 : x > y ? -1 : 0;
}

void profile_report(FILE *out, unsigned top)
{
    if (!nsyms) {
        fprintf(out, "profile: no symbols loaded\n");
        return;
    }
    psym_t *copy = malloc(nsyms * sizeof *copy);
    if (!copy)
        return;
    memcpy(copy, syms, nsyms * sizeof *copy);
    qsort(copy, nsyms, sizeof *copy, by_cycles);
    uint64_t total = 0;
    for (unsigned i = 0; i < nsyms; i++)
        total += copy[i].cycles;
    fprintf(out, "profile function              cycles     share   entries\n");
    for (unsigned i = 0; i < nsyms && i < top && copy[i].cycles; i++)
        fprintf(out, "profile %-24s %10llu  %6.2f%%  %8llu\n", copy[i].name,
                (unsigned long long)copy[i].cycles, total ? 100.0 * (double)copy[i].cycles / (double)total : 0.0,
                (unsigned long long)copy[i].calls);
    free(copy);
}
