/*
 * sstfile.h - the reader of the SingleStepTests m68000 vector files (the
 * binary format of ../shared/m68000-tests/README.md), one for the two tools
 * that read them: the conformance lane (sst.c) and the bus-timing check
 * (tests/timing/busvectors.c).
 */
#ifndef SSTFILE_H
#define SSTFILE_H
#include <stddef.h>
#include <stdint.h>

/* the registers of a state, in the file's order */
enum { R_D0 = 0, R_A0 = 8, R_USP = 15, R_SSP = 16, R_SR = 17, R_PC = 18, NREG = 19 };
extern const char *const sst_reg_name[NREG];

typedef struct {
    uint32_t reg[NREG];
    uint32_t prefetch[2];
    uint32_t nram;
    const uint8_t *ram;   /* nram entries of u32 address, u16 word (little-endian) */
} sst_state_t;

/* the transaction kinds */
enum { SST_IDLE = 0, SST_WRITE = 1, SST_READ = 2, SST_TAS = 3, SST_READ_AERR = 4, SST_WRITE_AERR = 5 };

typedef struct {
    char name[128];
    sst_state_t init, fin;
    uint32_t cycles, reads, writes;   /* the reference's length and bus cycles */
    int addr_error;                   /* the reference ends in an address error */
    int tas;                          /* it has a read-modify-write cycle */
} sst_test_t;

typedef struct {
    const uint8_t *p, *end, *base;
    const char *prog, *file;   /* for the messages: "PROG: FILE: ..." */
    int bad;
} sst_reader_t;

/* called for every bus transaction (not the idle stretches) of a test */
typedef void (*sst_tx_fn)(void *ctx, unsigned kind, uint32_t address);

uint32_t sst_le32(const uint8_t *p);
uint16_t sst_le16(const uint8_t *p);
/* the whole file, or NULL with a message on stderr */
uint8_t *sst_slurp(const char *prog, const char *path, size_t *len);
/* 0 and the number of tests when the file header is right, -1 with a message */
int sst_open(sst_reader_t *r, const char *prog, const char *path, const uint8_t *buf, size_t len,
             uint32_t *count);
/* the next test record; -1 with a message on a malformed one */
int sst_read_test(sst_reader_t *r, sst_test_t *t, sst_tx_fn on_tx, void *ctx);
/* 0 when the file ends after its last record, -1 with a message */
int sst_close(sst_reader_t *r);
#endif
