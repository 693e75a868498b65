/* script_serial.c - host-script commands of the serial line (docs/host-script.md). */
#include "script.h"

int script_serial(script_t *sc, sim_t *s, char **tok, int n)
{
    (void)sc;
    (void)s;
    (void)tok;
    (void)n;
    return SCRIPT_NOT_MINE;
}
