#ifndef SCRIPT_H
#define SCRIPT_H
#include <stdio.h>
#include "sim.h"

typedef struct {
    const char *name;
    int line;
    int errors;
    int depth;           /* include nesting: 0 the script itself */
} script_t;

int script_line(script_t *sc, sim_t *s, char *line);   /* 1 on quit, -1 on error */
int script_run(script_t *sc, sim_t *s, FILE *in);      /* returns the error count */
long script_code(const char *tok);                     /* code or mnemonic, -1 if unknown */

/* helpers for command families in other files */
int script_parse_num(const char *t, long long *out);  /* decimal, 0x or $ hex; 0 ok */
int script_parse_real(const char *t, double *out);    /* decimal fraction [e exp]; 0 ok */
int script_parse_ms(const char *t, cyc_t *out);       /* decimal ms 0..3600000; 0 ok */
#define SCRIPT_LINE_MAX 1023                           /* characters of a line, newline aside */
int script_getline(script_t *sc, FILE *in, char *buf);  /* buf: SCRIPT_LINE_MAX + 2; 1, 0 end, -1 */
int script_check_file(FILE *f);                       /* -1: a directory */
extern int script_waits_timed_out;                     /* wait-display timeouts so far */
extern int script_includes;                            /* files included so far (at most 1000) */
int script_err(script_t *sc, const char *fmt, const char *arg);   /* returns -1 */

/* Command families beside their models: return SCRIPT_NOT_MINE for a command
 * they do not know, else 0 (done), 1 (quit) or -1 (error, via script_err). */
#define SCRIPT_NOT_MINE (-2)
int script_serial(script_t *sc, sim_t *s, char **tok, int n);   /* script_serial.c */
int script_plant(script_t *sc, sim_t *s, char **tok, int n);    /* script_plant.c */
int script_perf(script_t *sc, sim_t *s, char **tok, int n);     /* perf.c: perf ..., run-ticks */
int script_bench(script_t *sc, sim_t *s, char **tok, int n);    /* bench_script.c: gdb, vcd */

#endif
