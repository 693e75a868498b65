/*
 * serial_host.c - the far end of the card's front-panel serial line.
 *
 * Towards the card, bytes go through uart_feed() (periph.c), which times
 * every character on the wire (2.083 ms at 4800 8N1).  Bytes the card sends
 * arrive one by one through the UART's on_tx callback, at the cycle their
 * stop bit ends; they are collected into groups printed as
 *     rx 10 02 00 00 A1 00 00 20 00 C1
 * A group ends when the line has been idle for more than two character
 * times, at the end of every script command (so at the end of every `run`),
 * or when 64 bytes are collected.
 *
 * --serial-pty: a pseudo-terminal in raw mode stands for the front-panel
 * connector.  What a program writes to its slave side goes to the card (and
 * is printed as `tx ...`), what the card sends is written to it.  After the
 * script, serial_host_serve() keeps the card running in real time.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>
#include "serial_host.h"

#define GROUP_MAX   64
#define IDLE_CYC    (2 * UART_CHAR_CYC)
#define PTY_POLL    MS_TO_CYC(1)           /* read the pty every emulated ms */

static uint8_t grp[GROUP_MAX];
static unsigned grp_n;
static cyc_t grp_last;                     /* when the last byte of the group ended */

static int pty_fd = -1;
static int peer_seen;                      /* the pty's slave side has been opened */
static cyc_t pty_next;
static unsigned long pty_dropped;

/* ---- card -> host ---------------------------------------------------------- */

void serial_host_flush(sim_t *s)
{
    if (!grp_n)
        return;
    char line[8 + 3 * GROUP_MAX];
    int k = snprintf(line, sizeof line, "rx");
    for (unsigned i = 0; i < grp_n; i++)
        k += snprintf(line + k, sizeof line - (size_t)k, " %02X", grp[i]);
    grp_n = 0;
    sim_printf(s, "%s\n", line);
}

/* 1 when a program has the pty's slave side open. */
static int pty_peer_open(void)
{
    struct pollfd p = {pty_fd, POLLIN, 0};
    if (poll(&p, 1, 0) < 0)
        return 0;
    if (!(p.revents & POLLHUP))
        peer_seen = 1;
    return !(p.revents & POLLHUP);
}

static void on_tx(void *ctx, uint8_t b)
{
    sim_t *s = ctx;
    cyc_t now = sim_now(s);
    if (grp_n && (now - grp_last > IDLE_CYC || grp_n == GROUP_MAX))
        serial_host_flush(s);
    grp[grp_n++] = b;
    grp_last = now;
    if (pty_fd >= 0) {
        /* Nobody at the connector: the byte goes nowhere, as on a real line. */
        if (pty_peer_open() && write(pty_fd, &b, 1) != 1 && !pty_dropped++)
            fprintf(stderr, "mac4sim: serial pty: peer not reading, bytes dropped\n");
    }
}

/* ---- host -> card ---------------------------------------------------------- */

static unsigned wire_room(sim_t *s)
{
    uart_t *u = &s->uart;
    return (u->wire_tail + UART_WIRE_SIZE - u->wire_head - 1) % UART_WIRE_SIZE;
}

int serial_host_tx(sim_t *s, const uint8_t *b, unsigned n)
{
    if (n > wire_room(s))
        return -1;
    uart_feed(s, b, n);
    return 0;
}

unsigned serial_host_encode(uint8_t axis, uint16_t code, uint32_t param, uint8_t *buf)
{
    const uint8_t d[7] = {axis, (uint8_t)(code >> 8), (uint8_t)code, (uint8_t)(param >> 24),
                          (uint8_t)(param >> 16), (uint8_t)(param >> 8), (uint8_t)param};
    unsigned n = 0, sum = 0;
    buf[n++] = 0x10;
    buf[n++] = 0x02;
    for (int i = 0; i < 7; i++) {
        sum += d[i];
        buf[n++] = d[i];
        if (d[i] == 0x10)
            buf[n++] = 0x10;
    }
    buf[n++] = (uint8_t)sum;
    if ((uint8_t)sum == 0x10)
        buf[n++] = 0x10;
    return n;
}

static void pty_read(sim_t *s)
{
    if (pty_fd < 0)
        return;
    uint8_t buf[GROUP_MAX];
    unsigned room = wire_room(s);          /* the rest waits in the pty */
    if (room == 0)
        return;
    ssize_t n = read(pty_fd, buf, room < sizeof buf ? room : sizeof buf);
    if (n <= 0)
        return;                            /* EAGAIN, or EIO: no peer */
    peer_seen = 1;
    char line[8 + 3 * GROUP_MAX];
    int k = snprintf(line, sizeof line, "tx");
    for (ssize_t i = 0; i < n; i++)
        k += snprintf(line + k, sizeof line - (size_t)k, " %02X", buf[i]);
    sim_printf(s, "%s\n", line);
    uart_feed(s, buf, (unsigned)n);
}

/* ---- the scheduler tap ------------------------------------------------------ */

static const cpu_t *inner;

static void tap(sim_t *s, cyc_t now)
{
    if (grp_n && now - grp_last > IDLE_CYC)
        serial_host_flush(s);
    if (pty_fd >= 0 && now >= pty_next) {
        pty_read(s);
        pty_next = now + PTY_POLL;
    }
}

static cyc_t tap_execute(sim_t *s, cyc_t max)
{
    cyc_t now = sim_now(s);
    tap(s, now);
    /* End the slice when the group becomes due, so it prints in order with
     * the other events. */
    if (grp_n) {
        cyc_t due = grp_last + IDLE_CYC + 1;
        if (due > now && due - now < max)
            max = due - now;
    }
    if (pty_fd >= 0 && pty_next > now && pty_next - now < max)
        max = pty_next - now;
    return inner->execute(s, max);
}

static void tap_reset(sim_t *s) { inner->reset(s); }
static void tap_set_irq(int level) { inner->set_irq(level); }
static int tap_halted(void) { return inner->halted(); }

static cpu_t tapped;

const cpu_t *serial_host_cpu(const cpu_t *c)
{
    inner = c;
    tapped = (cpu_t){c->name, tap_reset, tap_execute, tap_set_irq, tap_halted};
    return &tapped;
}

/* ---- script and serve loops ---------------------------------------------------- */

int serial_host_script_run(script_t *sc, sim_t *s, FILE *in)
{
    char buf[1024];
    while (fgets(buf, sizeof buf, in)) {
        sc->line++;
        int r = script_line(sc, s, buf);
        serial_host_flush(s);
        fflush(s->out);
        if (r > 0)
            break;
    }
    return sc->errors;
}

static double wall_seconds(const struct timespec *t0)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)(t.tv_sec - t0->tv_sec) + (double)(t.tv_nsec - t0->tv_nsec) * 1e-9;
}

void serial_host_serve(sim_t *s, double seconds)
{
    if (pty_fd < 0)
        return;
    struct timespec t0;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    cyc_t c0 = sim_now(s);
    for (;;) {
        pty_read(s);
        sim_run(s, MS_TO_CYC(1));
        double wall = wall_seconds(&t0);
        if (seconds > 0 && wall >= seconds)
            break;
        struct pollfd p = {pty_fd, POLLIN, 0};
        if (poll(&p, 1, 0) >= 0) {
            if (!(p.revents & POLLHUP))
                peer_seen = 1;
            else if (peer_seen && !(p.revents & POLLIN))
                break;                     /* the peer has closed and we have read it all */
        }
        double ahead = (double)(sim_now(s) - c0) / (double)MAC4_CPU_HZ - wall;
        if (ahead > 0) {
            struct timespec d = {(time_t)ahead, (long)((ahead - (double)(time_t)ahead) * 1e9)};
            nanosleep(&d, NULL);
        }
    }
    serial_host_flush(s);
    fflush(s->out);
}

/* ---- set-up ---------------------------------------------------------------------- */

static int make_pty(void)
{
    int fd = posix_openpt(O_RDWR | O_NOCTTY);
    if (fd < 0 || grantpt(fd) || unlockpt(fd)) {
        perror("mac4sim: serial pty");
        return -1;
    }
    const char *name = ptsname(fd);
    if (!name) {
        perror("mac4sim: serial pty");
        return -1;
    }
    /* Raw mode for whoever opens it: no echo, no line editing, no CR/LF
     * translation, 8 bits.  The settings stay with the pty. */
    int sl = open(name, O_RDWR | O_NOCTTY);
    struct termios t;
    if (sl < 0 || tcgetattr(sl, &t)) {
        perror("mac4sim: serial pty");
        return -1;
    }
    cfmakeraw(&t);
    cfsetispeed(&t, B4800);
    cfsetospeed(&t, B4800);
    tcsetattr(sl, TCSANOW, &t);
    close(sl);
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
    pty_fd = fd;
    printf("serial-pty %s\n", name);
    fflush(stdout);
    return 0;
}

int serial_host_init(sim_t *s, int pty)
{
    s->uart.on_tx = on_tx;
    s->uart.tx_ctx = s;
    grp_n = 0;
    return pty ? make_pty() : 0;
}
