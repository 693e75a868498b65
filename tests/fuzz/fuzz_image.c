/*
 * fuzz_image.c - libFuzzer target: the EPROM image loader (sim_load_image,
 * what `mac4sim --image` does) and the boot of what it loaded.
 *
 * Input: byte 0 = mode: card (mode % 3); bit 2 (mode & 4): the card's own
 * image from the build with the rest of the input as patches, three bytes
 * each (offset hi, offset lo, xor mask), else the rest of the input is the
 * image file itself; bit 3 with a file: padded with $FF to 64 KiB + 1 (one
 * byte too many for the socket).
 *
 * Properties: the loader answers -2 for an empty file or one larger than
 * 64 KiB and else loads exactly the file's bytes, the rest of the socket
 * blank ($FF); the emulator boots anything for 700 ms of emulated time
 * without a crash or a hang (ASan, UBSan, libFuzzer's timeout); an image
 * that differs from the build's never gets the card ready: the display never
 * shows 5, the EPROM checksum (3, firmware/boot.c) stops it; a CPU halted by
 * a double bus fault reports it once and nothing more until the next reset
 * (the watchdog's, 100 ms on: docs/board.md, "Bus errors").
 */
#include <unistd.h>
#include <sys/stat.h>
#include "fuzz_emu.h"

static uint8_t good[3][EPROM_SIZE];
static size_t good_n[3];
static char path[600];

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    for (int c = 0; c < 3; c++) {
        memset(good[c], 0xFF, EPROM_SIZE);
        good_n[c] = fz_card_image(c, good[c]);
    }
    mkdir("build", 0777);
    mkdir("build/fuzz", 0777);
    snprintf(path, sizeof path, "build/fuzz/scratch-image-%d.bin", (int)getpid());   /* relative: fuzz_fopen.c */
    return 0;
}

static uint8_t img[EPROM_SIZE + 1];
/* A guard, no longer the way out of a storm of bus errors (those end in
 * the double fault's halt): the faults that are no bus error, an access
 * to a register a device does not define inside its window, which the card
 * acknowledges, repeated by a loop at every instruction, would print a
 * million lines in 700 ms. */
#define FZ_FAULT_STORM 20000u

/* The check sum of boot step 3 as tools/mkeprom.py makes it (CRC-16/CCITT,
 * bit by bit here): a changed image that still passes it is a collision a
 * 16-bit check cannot see, not a finding. */
static int checksum_passes(const uint8_t *e)
{
    uint16_t crc = 0xFFFF;
    for (unsigned i = 0; i < EPROM_CRC_OFFSET; i++) {
        crc ^= (uint16_t)(e[i] << 8);
        for (int k = 0; k < 8; k++)
            crc = (uint16_t)(crc & 0x8000 ? crc << 1 ^ 0x1021 : crc << 1);
    }
    unsigned stored = (unsigned)e[EPROM_CRC_OFFSET] << 8 | e[EPROM_CRC_OFFSET + 1];
    unsigned inverse = (unsigned)e[EPROM_CRC_OFFSET + 2] << 8 | e[EPROM_CRC_OFFSET + 3];
    return crc == stored && stored + inverse == 0xFFFF;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    int mode = data[0], card = mode % 3;
    size_t n;
    if (mode & 4) {                        /* the build's image, patched */
        n = good_n[card];
        memcpy(img, good[card], n);
        for (size_t i = 1; i + 2 < size; i += 3) {
            size_t off = (size_t)(data[i] << 8 | data[i + 1]);
            if (off < n)
                img[off] ^= data[i + 2];
        }
    } else {
        n = size - 1 > EPROM_SIZE + 1 ? EPROM_SIZE + 1 : size - 1;
        memcpy(img, data + 1, n);
        if (mode & 8) {
            memset(img + n, 0xFF, EPROM_SIZE + 1 - n);
            n = EPROM_SIZE + 1;
        }
    }
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(img, 1, n, f) != n || fclose(f)) {
        perror(path);
        exit(2);
    }
    sim_init(&S, card);
    S.out = fz_null_out();
    int r = sim_load_image(&S, path);
    remove(path);
    if (n == 0 || n > EPROM_SIZE) {
        FZ_CHECK(r == -2, "a file of %zu bytes loaded: %d", n, r);
        return 0;
    }
    FZ_CHECK(r == (int)n, "a file of %zu bytes loaded as %d", n, r);
    FZ_CHECK(!memcmp(S.eprom, img, n), "the EPROM differs from the file");
    for (size_t i = n; i < EPROM_SIZE; i++)
        FZ_CHECK(S.eprom[i] == 0xFF, "socket byte $%04zX beyond the file is $%02X", i, S.eprom[i]);
    int same = n == good_n[card] && !memcmp(img, good[card], n);
    int changed = !same && !checksum_passes(S.eprom);    /* the checksum must catch it */
    S.host_reads = 0;
    sim_attach_cpu(&S, &cpu_m68k);
    uint64_t halt_faults = 0, halt_resets = ~0ull;
    for (int ms = 0; ms < 700; ms++) {
        sim_run(&S, MS_TO_CYC(1));
        if (sim_halted && S.resets == halt_resets)   /* halted since the last ms, no reset */
            FZ_CHECK(S.faults == halt_faults, "%llu faults while the CPU was halted",
                     (unsigned long long)(S.faults - halt_faults));
        halt_faults = S.faults;
        halt_resets = sim_halted ? S.resets : ~0ull;
        if (changed)
            FZ_CHECK(S.sys.display != 5, "a changed image got the card ready (display 5 after %d ms)", ms);
        if ((S.sys.display & SYS_DISPLAY_DP) && S.sys.display != 0xFF)
            break;                        /* stopped with an error */
        if (!changed && S.sys.display == 5)
            break;
        if (S.faults > FZ_FAULT_STORM)      /* the guard above */
            break;
    }
    if (same)
        FZ_CHECK(S.sys.display == 5 && S.faults == 0, "the build's image did not boot (display %X)", S.sys.display);
    return 0;
}
