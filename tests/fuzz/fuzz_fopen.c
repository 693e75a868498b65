/*
 * fuzz_fopen.c - the files the emulator may open under the fuzz targets on
 * the emulator (fuzz_fopen.h): reading a relative path (the target's
 * scratch directory is the current one), the build's EPROM images, /dev/zero
 * and /dev/null; writing /dev/null only (trace, vcd, profile pcs, perf ticks
 * FILE are refused as a missing directory would be).  The files still open
 * when an input is cut short are closed by fz_files_close_all().
 */
#include <errno.h>
#include <string.h>
#include <stdio.h>

#define FZ_MAXFILES 64
static FILE *open_files[FZ_MAXFILES];
const char *fz_fopen_allowed_dir;   /* an absolute directory readable too (the EPROM images) */

static int allowed(const char *path, const char *mode)
{
    int reading = mode[0] == 'r' && !strchr(mode, '+');
    if (!strcmp(path, "/dev/null"))
        return 1;
    if (!reading)
        return 0;
    if (!strcmp(path, "/dev/zero"))
        return 1;
    if (fz_fopen_allowed_dir && !strncmp(path, fz_fopen_allowed_dir, strlen(fz_fopen_allowed_dir)) &&
        !strstr(path, ".."))
        return 1;
    return path[0] != '/' && !strstr(path, "..") && strncmp(path, "-", 2);
}

FILE *fz_fopen(const char *path, const char *mode)
{
    if (!allowed(path, mode)) {
        errno = EACCES;
        return NULL;
    }
    for (int i = 0; i < FZ_MAXFILES; i++)
        if (!open_files[i]) {
            FILE *f = fopen(path, mode);
            open_files[i] = f;
            return f;
        }
    errno = EMFILE;
    return NULL;
}

int fz_fclose(FILE *f)
{
    for (int i = 0; i < FZ_MAXFILES; i++)
        if (open_files[i] == f && f)
            open_files[i] = NULL;
    return fclose(f);
}

/* How many are open now (an include nested 8 deep has 8). */
int fz_files_open(void)
{
    int n = 0;
    for (int i = 0; i < FZ_MAXFILES; i++)
        n += open_files[i] != NULL;
    return n;
}

void fz_files_close_all(void)
{
    for (int i = 0; i < FZ_MAXFILES; i++)
        if (open_files[i]) {
            fclose(open_files[i]);
            open_files[i] = NULL;
        }
}
