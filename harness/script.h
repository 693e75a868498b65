#ifndef SCRIPT_H
#define SCRIPT_H
#include <stdio.h>
#include "sim.h"

typedef struct {
    const char *name;
    int line;
    int errors;
} script_t;

int script_line(script_t *sc, sim_t *s, char *line);   /* 1 on quit, -1 on error */
int script_run(script_t *sc, sim_t *s, FILE *in);      /* returns the error count */
long script_code(const char *tok);                     /* code or mnemonic, -1 if unknown */

#endif
