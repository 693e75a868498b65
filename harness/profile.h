/* profile.h - the emulator's instruction profile (harness/profile.c); not
 * firmware/profile.h, the profile generator */
#ifndef HARNESS_PROFILE_H
#define HARNESS_PROFILE_H
#include <stdio.h>
int profile_load_symbols(const char *path);   /* nm output; returns the count or -1 */
void profile_set(int on);
void profile_reset(void);
void profile_slice_start(void);
void profile_slice_end(int ran);             /* ran: the slice's cycles (m68k_execute) */
void profile_report(FILE *out, unsigned top);
int profile_pcs(const char *path);            /* per instruction: "pc cycles count"; 0 or -1 */
/* for harness/perf.c */
#include <stdint.h>
void profile_set_hook(void (*hook)(unsigned pc));          /* NULL: none */
int profile_symbol(const char *name, uint32_t *addr);     /* 0 when found */
#endif /* HARNESS_PROFILE_H */
