/*
 * buswait.c - the bus timing table of hal/mac4_map.h at run time: the
 * page map, --wait-states, the DPRAM's contention with the VME host, the
 * interrupt acknowledge, and the counts `bus-stats` prints.
 */
#include <stdlib.h>
#include <string.h>
#include "buswait.h"

buswait_cfg_t buswait_cfg;
buswait_stats_t buswait_stats;
void (*buswait_sync)(void);
static void sync(void)
{
    if (buswait_sync)
        buswait_sync();
}
static uint8_t page[1u << 16];
const uint8_t *buswait_page = page;

const char *const buswait_names[BW_NREGIONS] = {
#define BW_NAME(name, base, size, rd, wr) name,
    MAC4_BUS_TIMING(BW_NAME)
#undef BW_NAME
    "unmapped",
};

static const struct { uint32_t base, size; uint8_t rd, wr; } table[] = {
#define BW_ROW(name, base, size, rd, wr) {(uint32_t)(base), (uint32_t)(size), rd, wr},
    MAC4_BUS_TIMING(BW_ROW)
#undef BW_ROW
};

static void defaults(void)
{
    memset(&buswait_cfg, 0, sizeof buswait_cfg);
    for (unsigned r = 0; r < sizeof table / sizeof table[0]; r++) {
        buswait_cfg.ws[r][0] = table[r].rd;
        buswait_cfg.ws[r][1] = table[r].wr;
    }
    buswait_cfg.iack = BW_IACK_AUTOVECTOR;
    buswait_cfg.iack_vectored_wait = MAC4_IACK_VECTORED_WAIT;
    buswait_cfg.host_clocks = MAC4_DPRAM_HOST_CLOCKS;
}

void buswait_init(void)
{
    static int done;
    if (done)
        return;
    done = 1;
    /* every 256-byte page belongs to one region (the I/O blocks are $100
     * apart; the smaller ones decode their page) */
    memset(page, BW_UNMAPPED, sizeof page);
    for (unsigned r = 0; r < sizeof table / sizeof table[0]; r++)
        for (uint32_t a = table[r].base; a < table[r].base + table[r].size; a += 0x100)
            page[a >> 8] = (uint8_t)r;
    defaults();
}

static int region_of(const char *name, size_t n)
{
    for (int r = 0; r < BW_NREGIONS; r++)
        if (strlen(buswait_names[r]) == n && !strncmp(buswait_names[r], name, n))
            return r;
    return -1;
}

static int num(const char *t, unsigned *out)
{
    char *end;
    long v = strtol(t, &end, 10);
    if (end == t || *end || v < 0 || v > 255)
        return -1;
    *out = (unsigned)v;
    return 0;
}

int buswait_parse(const char *spec, char *err, size_t errlen)
{
    buswait_init();
    unsigned v;
    if (!strcmp(spec, "default")) {
        defaults();
        return 0;
    }
    if (!num(spec, &v)) {                       /* N: every region, both kinds */
        for (int r = 0; r < BW_NREGIONS; r++)
            buswait_cfg.ws[r][0] = buswait_cfg.ws[r][1] = (uint8_t)v;
        buswait_cfg.iack_vectored_wait = v;
        return 0;
    }
    char buf[512];
    snprintf(buf, sizeof buf, "%s", spec);
    for (char *item = strtok(buf, ","); item; item = strtok(NULL, ",")) {
        char *eq = strchr(item, '=');
        if (!eq || num(eq + 1, &v)) {
            snprintf(err, errlen, "bad --wait-states item '%s' (REGION[.read|.write]=N, N 0..255)", item);
            return -1;
        }
        *eq = 0;
        char *dot = strchr(item, '.');
        int kinds = 3;                          /* bit 0 read, bit 1 write */
        if (dot) {
            kinds = !strcmp(dot + 1, "read") ? 1 : !strcmp(dot + 1, "write") ? 2 : 0;
            *dot = 0;
        }
        int r = region_of(item, strlen(item));
        if (r < 0 || !kinds) {
            snprintf(err, errlen, "unknown --wait-states region '%s' (see docs/memory-map.md, \"Bus timing\")", item);
            return -1;
        }
        if (kinds & 1)
            buswait_cfg.ws[r][0] = (uint8_t)v;
        if (kinds & 2)
            buswait_cfg.ws[r][1] = (uint8_t)v;
    }
    return 0;
}

int buswait_parse_iack(const char *spec)
{
    buswait_init();
    if (!strcmp(spec, "autovector"))
        buswait_cfg.iack = BW_IACK_AUTOVECTOR;
    else if (!strcmp(spec, "vectored"))
        buswait_cfg.iack = BW_IACK_VECTORED;
    else
        return -1;
    return 0;
}

void buswait_print(FILE *f)
{
    fprintf(f, "bus-timing");
    for (int r = 0; r < BW_NREGIONS; r++)
        fprintf(f, " %s=%u/%u", buswait_names[r], buswait_cfg.ws[r][0], buswait_cfg.ws[r][1]);
    fprintf(f, " iack=%s host_clocks=%u\n", buswait_cfg.iack == BW_IACK_AUTOVECTOR ? "autovector" : "vectored",
            buswait_cfg.host_clocks);
}

static buswait_stats_t marked;
static uint64_t marked_at;

void buswait_mark(uint64_t now)
{
    sync();
    marked = buswait_stats;
    marked_at = now;
}

static void print_stats(FILE *f, const buswait_stats_t *b);

void buswait_print_mark(FILE *f)
{
    fprintf(f, "bus-stats cycles=%llu at=display\n", (unsigned long long)marked_at);
    print_stats(f, &marked);
}

void buswait_print_stats(FILE *f)
{
    sync();
    print_stats(f, &buswait_stats);
}

static void print_stats(FILE *f, const buswait_stats_t *b)
{
    for (int r = 0; r < BW_NREGIONS; r++)
        if (b->cycles[r][0] || b->cycles[r][1])
            fprintf(f, "bus-stats %s reads=%llu writes=%llu wait_read=%llu wait_write=%llu\n", buswait_names[r],
                    (unsigned long long)b->cycles[r][0], (unsigned long long)b->cycles[r][1],
                    (unsigned long long)b->wait[r][0], (unsigned long long)b->wait[r][1]);
    fprintf(f, "bus-stats contention count=%llu clocks=%llu\n", (unsigned long long)b->contention,
            (unsigned long long)b->contention_clocks);
    fprintf(f, "bus-stats iack count=%llu clocks=%llu\n", (unsigned long long)b->iacks,
            (unsigned long long)b->iack_clocks);
}

void buswait_reset_stats(void)
{
    sync();
    memset(&buswait_stats, 0, sizeof buswait_stats);
}

/* The host's recent DPRAM accesses: word and the time it holds it. */
#define HOST_RING 64
static struct { uint64_t start, end; uint32_t word; } ring[HOST_RING];
static unsigned ring_head;
static uint64_t host_free;          /* the host's next access starts no earlier */

void buswait_host_access(uint64_t at, uint32_t off)
{
    uint64_t t = at > host_free ? at : host_free;
    host_free = t + buswait_cfg.host_clocks;
    ring[ring_head].start = t;
    ring[ring_head].end = host_free;
    ring[ring_head].word = off >> 1;
    ring_head = (ring_head + 1) % HOST_RING;
}

uint64_t buswait_host_free(void) { return host_free; }

unsigned buswait_dpram_contention(uint64_t now, uint32_t off)
{
    if (now >= host_free)
        return 0;
    for (unsigned i = 0; i < HOST_RING; i++)
        if (ring[i].word == off >> 1 && ring[i].start <= now && now < ring[i].end) {
            unsigned w = (unsigned)(ring[i].end - now);
            buswait_stats.contention++;
            buswait_stats.contention_clocks += w;
            return w;
        }
    return 0;
}

unsigned buswait_iack(void)
{
    unsigned extra = buswait_cfg.iack == BW_IACK_AUTOVECTOR ? MAC4_IACK_AUTOVECTOR_CLOCKS - 4u
                                                            : buswait_cfg.iack_vectored_wait;
    buswait_stats.iacks++;
    buswait_stats.iack_clocks += extra;
    return extra;
}
