/*
 * panel.h - the card's front panel as a live web page (docs/debugging.md,
 * "Front panel"): `mac4sim --panel PORT` serves it on 127.0.0.1.
 */
#ifndef PANEL_H
#define PANEL_H
#include "cpu.h"

/* Listen on 127.0.0.1:port (0: any free port), print `panel-port N`.
 * commands_json: build/commands.json, served to the page for the names of
 * the status bits.  0, or -1 with a message on stderr. */
int panel_listen(sim_t *s, int port, const char *commands_json);
int panel_active(void);

/* A CPU that runs `inner` and answers the page between slices (at most
 * once per emulated millisecond); the buttons act there. */
const cpu_t *panel_cpu(const cpu_t *inner);

/* Answer whatever the page asked (the paced loop calls it every ms). */
void panel_poll(sim_t *s);

/* After the script: run the card paced to the wall clock while the panel
 * is open or gdb attached, for at most `seconds` (> 0) of wall time. */
void bench_serve(sim_t *s, double seconds);

#endif
