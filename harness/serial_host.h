/*
 * serial_host.h - the far end of the card's front-panel serial line
 * (docs/serial.md, docs/host-script.md): what the host script feeds in with
 * `tx`, what the card sends printed as `rx` groups, and optionally a
 * pseudo-terminal (--serial-pty) or TCP socket (--serial-tcp) that a real
 * program can open.
 */
#ifndef SERIAL_HOST_H
#define SERIAL_HOST_H
#include <stdio.h>
#include "cpu.h"
#include "script.h"

/* The connector of the front-panel line (docs/serial.md). */
enum { SERIAL_CONN_NONE, SERIAL_CONN_PTY, SERIAL_CONN_TCP };
typedef struct {
    int kind;                  /* SERIAL_CONN_* */
    const char *pty_link;      /* --serial-pty-link PATH: a symbolic link to the pty */
    int tcp_port;              /* --serial-tcp PORT on 127.0.0.1 (0: the system picks) */
    const char *log;           /* --serial-log FILE: the session as a host script */
} serial_opts_t;

/* Install the UART's on_tx callback; create the connector and print its
 * first line ("serial-pty /dev/pts/N", "serial-tcp PORT").  Call after
 * sim_init.  Returns 0, or -1 (message on stderr) when it cannot be made. */
int serial_host_init(sim_t *s, const serial_opts_t *o);

/* A CPU that runs `inner` but lets the serial line look at the clock at
 * every scheduler slice: an `rx` group is printed as soon as the line has
 * been idle for two character times, and the pty is read.  Attach this one
 * instead of `inner`. */
const cpu_t *serial_host_cpu(const cpu_t *inner);

/* script_run with the pending `rx` group printed after every command (so it
 * comes out at the end of every `run`) and the output flushed. */
int serial_host_script_run(script_t *sc, sim_t *s, FILE *in);

/* With a connector: keep the card running paced to wall-clock time.  With
 * `seconds` > 0 for that long, while programs connect and disconnect; else
 * until the first program that opened the connector has closed it.
 * Nothing to do without a connector. */
void serial_host_serve(sim_t *s, double seconds);

/* Print the bytes the card sent since the last group, if any. */
void serial_host_flush(sim_t *s);

/* Bytes towards the card, over the modelled line.  Returns 0, or -1 when
 * the emulator's line buffer cannot take them all (nothing is sent). */
int serial_host_tx(sim_t *s, const uint8_t *b, unsigned n);

/* A telegram for axis/code/param, written independently of the firmware's
 * encoder.  buf holds 18 bytes; returns the length. */
unsigned serial_host_encode(uint8_t axis, uint16_t code, uint32_t param, uint8_t *buf);

#endif
