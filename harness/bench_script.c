/*
 * bench_script.c - host-script commands of the workbench (docs/debugging.md):
 *   gdb PORT                  wait for gdb on 127.0.0.1:PORT, the CPU stopped
 *   vcd FILE [SIGNALS]        a waveform dump from now (vcd.h)
 *   vcd off | vcd signals     close it | list the signals of this card
 */
#include <stdlib.h>
#include <string.h>
#include "vcd.h"
#include "script.h"
#include "gdbstub.h"
#include "cpu.h"

/* The 68000 build only: the native firmware has no instructions to stop at. */
const cpu_t *mac4sim_native_cpu(void) __attribute__((weak));

static void close_at_exit(void)
{
    if (g_sim)
        vcd_close(g_sim);
}

int script_bench(script_t *sc, sim_t *s, char **tok, int n)
{
    long long v;
    if (!strcmp(tok[0], "gdb")) {
        if (n != 2 || script_parse_num(tok[1], &v) || v < 0 || v > 65535)
            return script_err(sc, "usage: %s PORT (0..65535, 0: any free port)", "gdb");
        if (mac4sim_native_cpu)
            return script_err(sc, "%s: the native build has no 68000 to debug", "gdb");
        if (gdbstub_attach(s, (int)v))
            return script_err(sc, "%s: no debugger attached", "gdb");
        return 0;
    }
    if (!strcmp(tok[0], "vcd")) {
        if (n == 2 && !strcmp(tok[1], "off")) {
            vcd_close(s);
            return 0;
        }
        if (n == 2 && !strcmp(tok[1], "signals")) {
            vcd_list(s->out, s->card);
            return 0;
        }
        if (n < 2 || n > 3)
            return script_err(sc, "usage: %s FILE [SIGNAL,...|all] | off | signals", "vcd");
        char err[200];
        if (vcd_open(s, tok[1], n == 3 ? tok[2] : NULL, err, sizeof err))
            return script_err(sc, "%s", err);
        static int registered;
        if (!registered) {          /* the dump is complete at every exit */
            registered = 1;
            atexit(close_at_exit);
        }
        return 0;
    }
    return SCRIPT_NOT_MINE;
}
