/* sstfile.c - the reader of the 68000 reference vector files (sstfile.h) */
#include "sstfile.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *const sst_reg_name[NREG] = {"d0", "d1", "d2", "d3", "d4", "d5", "d6", "d7", "a0", "a1",
                                        "a2", "a3", "a4", "a5", "a6", "usp", "ssp", "sr", "pc"};

uint32_t sst_le32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
uint16_t sst_le16(const uint8_t *p) { return (uint16_t)(p[0] | p[1] << 8); }

static uint32_t u32(sst_reader_t *r)
{
    if (r->end - r->p < 4) {
        r->bad = 1;
        return 0;
    }
    uint32_t v = sst_le32(r->p);
    r->p += 4;
    return v;
}

static int bad(sst_reader_t *r, const char *what)
{
    fprintf(stderr, "%s: %s: malformed vector file (%s at byte %ld)\n", r->prog, r->file, what,
            (long)(r->p - r->base));
    r->bad = 1;
    return -1;
}

uint8_t *sst_slurp(const char *prog, const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "%s: %s: %s\n", prog, path, strerror(errno));
        return NULL;
    }
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *b = n > 0 ? malloc((size_t)n) : NULL;
    if (!b || fread(b, 1, (size_t)n, f) != (size_t)n) {
        fprintf(stderr, "%s: %s: %s\n", prog, path, n == 0 ? "empty file" : "cannot read");
        fclose(f);
        free(b);
        return NULL;
    }
    fclose(f);
    *len = (size_t)n;
    return b;
}

int sst_open(sst_reader_t *r, const char *prog, const char *path, const uint8_t *buf, size_t len,
             uint32_t *count)
{
    *r = (sst_reader_t){buf, buf + len, buf, prog, path, 0};
    if (u32(r) != 0x1A3F5D71u || r->bad)
        return bad(r, "file magic");
    *count = u32(r);
    return r->bad ? bad(r, "test count") : 0;
}

static int read_state(sst_reader_t *r, sst_state_t *s)
{
    const uint8_t *start = r->p;
    uint32_t size = u32(r);
    if (u32(r) != 0x01234567u || r->bad)
        return bad(r, "state magic");
    for (int i = 0; i < NREG; i++)
        s->reg[i] = u32(r);
    s->prefetch[0] = u32(r);
    s->prefetch[1] = u32(r);
    s->nram = u32(r);
    if (r->bad || (uint64_t)s->nram * 6 > (uint64_t)(r->end - r->p))
        return bad(r, "state RAM");
    s->ram = r->p;
    r->p += s->nram * 6;
    if ((uint32_t)(r->p - start) != size)
        return bad(r, "state size");
    return 0;
}

int sst_read_test(sst_reader_t *r, sst_test_t *t, sst_tx_fn on_tx, void *ctx)
{
    const uint8_t *start = r->p;
    uint32_t size = u32(r);
    if (u32(r) != 0xABC12367u || r->bad || size > (uint32_t)(r->end - start))
        return bad(r, "test magic");
    const uint8_t *tend = start + size;
    u32(r);
    if (u32(r) != 0x89ABCDEFu)
        return bad(r, "name magic");
    uint32_t len = u32(r);
    if (r->bad || len > (uint32_t)(tend - r->p))
        return bad(r, "name");
    snprintf(t->name, sizeof t->name, "%.*s", (int)len, (const char *)r->p);
    r->p += len;
    if (read_state(r, &t->init) || read_state(r, &t->fin))
        return -1;
    u32(r);
    if (u32(r) != 0x456789ABu)
        return bad(r, "transactions magic");
    t->cycles = u32(r);
    uint32_t n = u32(r);
    t->reads = t->writes = 0;
    t->addr_error = t->tas = 0;
    for (uint32_t i = 0; i < n && !r->bad; i++) {
        if (r->p + 5 > tend)
            return bad(r, "transaction");
        uint8_t kind = r->p[0];
        r->p += 5;
        if (kind == SST_IDLE)
            continue;
        if (r->p + 20 > tend)
            return bad(r, "transaction");
        uint32_t address = sst_le32(r->p + 4);   /* after the function code */
        r->p += 20;
        switch (kind) {
        case SST_WRITE: t->writes++; break;
        case SST_READ: t->reads++; break;
        case SST_TAS: t->reads++; t->writes++; t->tas = 1; break;
        case SST_READ_AERR: case SST_WRITE_AERR: t->addr_error = 1; break;
        default: return bad(r, "transaction kind");
        }
        if (on_tx)
            on_tx(ctx, kind, address);
    }
    if (r->bad || r->p != tend)
        return bad(r, "test size");
    return 0;
}

int sst_close(sst_reader_t *r)
{
    return r->p == r->end ? 0 : bad(r, "trailing bytes");
}
