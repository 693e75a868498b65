/* fuzz_fopen.h - forced into the harness objects of the emulator fuzz targets
 * (fuzz.mk: -include): every file the emulator opens goes through
 * fuzz_fopen.c, which keeps a fuzzed script from writing files or reading
 * anything but the scratch directory, /dev/zero and /dev/null. */
#ifndef _GNU_SOURCE
#define _GNU_SOURCE      /* as serial_host.c, gdbstub.c, panel.c define it */
#endif
#include <stdio.h>
FILE *fz_fopen(const char *path, const char *mode);
int fz_fclose(FILE *f);
#define fopen fz_fopen
#define fclose fz_fclose
