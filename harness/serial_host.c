/*
 * serial_host.c - the far end of the card's front-panel serial line.
 *
 * Towards the card, bytes go through uart_feed() (uart.c), which times
 * every character on the wire (2.083 ms at 4800 8N1).  Bytes the card sends
 * arrive one by one through the UART's on_tx callback, at the cycle their
 * stop bit ends; they are collected into groups printed as
 *     rx 10 02 00 00 A1 00 00 20 00 C1
 * A group ends when the line has been idle for more than two character
 * times, at the end of every script command (so at the end of every `run`),
 * or when 64 bytes are collected.
 *
 * The connector (docs/serial.md): a pseudo-terminal in raw mode
 * (--serial-pty, with a fixed name by --serial-pty-link), or a TCP socket
 * on 127.0.0.1 carrying the raw byte stream (--serial-tcp, as QEMU's
 * `-serial tcp`).  What a program writes goes to the card (and is printed
 * as `tx ...`), what the card sends is written back.  After the script,
 * serial_host_serve() keeps the card running in real time.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <arpa/inet.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>
#include "serial_host.h"

#define GROUP_MAX   64
#define IDLE_CYC    (2 * UART_CHAR_CYC)
#define PTY_POLL    MS_TO_CYC(1)           /* read the connector every emulated ms */
#define LINE_POLL   MS_TO_CYC(100)         /* look at the pty's line settings */

static uint8_t grp[GROUP_MAX];
static unsigned grp_n;
static cyc_t grp_last;                     /* when the last byte of the group ended */

/* The connector.  conn_fd is the pty's master side, or the TCP client while
 * one is connected (listen_fd listens for the next). */
static int conn_kind = SERIAL_CONN_NONE;
static int conn_fd = -1;
static int listen_fd = -1;
static int peer_seen;                      /* a program has opened the pty / connected */
static int peer_gone;                      /* ... and closed it again */
static cyc_t pty_next;
static unsigned long pty_dropped;
static char link_path[4096];               /* --serial-pty-link, removed at exit */
static int line_bad = -1;                  /* the pty's settings were not 4800 8N1 */
static cyc_t line_next;

/* --serial-log: a host script of the session that replays it. */
static FILE *slog;
static cyc_t slog_at;                      /* emulated time the log has reached */

/* ---- the session log ---------------------------------------------------------
 * Script lines as they are read, bytes from the connector as `tx` after a
 * `run` to the cycle they arrived at, what the card sent as `# rx` comments:
 * the emulator being deterministic, `mac4sim --script LOG` gives the same
 * card answers (docs/serial.md). */

/* `run MS` up to now, MS exact to the cycle (1/16 000 ms). */
static void slog_run(sim_t *s)
{
    cyc_t now = sim_now(s);
    if (!slog || now <= slog_at)
        return;
    cyc_t d = now - slog_at;
    fprintf(slog, "run %llu.%07llu\n", (unsigned long long)(d / 16000u),
            (unsigned long long)(d % 16000u * 625u));
    slog_at = now;
}

/* A script command that only lets time pass: logged as a comment, the time
 * it ran as `run` around what came in meanwhile. */
static int time_command(const char *line)
{
    char w[16];
    if (sscanf(line, " %15s", w) != 1)
        return 0;
    return !strcmp(w, "run") || !strcmp(w, "wait-display") || !strcmp(w, "run-ticks");
}

/* Before a script line runs: the line, verbatim or as a comment. */
static void slog_line(sim_t *s, const char *line, int is_time)
{
    if (!slog)
        return;
    slog_run(s);
    fprintf(slog, "%s%s", is_time ? "# " : "", line);
    size_t n = strlen(line);
    if (n == 0 || line[n - 1] != '\n')
        fputc('\n', slog);
    fflush(slog);
}

/* After it: a time command's rest of time; any other line's time is its own
 * and comes again when the log replays it. */
static void slog_line_done(sim_t *s, int is_time)
{
    if (!slog)
        return;
    if (is_time)
        slog_run(s);
    else
        slog_at = sim_now(s);
}

static void slog_bytes(sim_t *s, const char *what, const uint8_t *b, size_t n)
{
    if (!slog)
        return;
    slog_run(s);
    fputs(what, slog);
    for (size_t i = 0; i < n; i++)
        fprintf(slog, " %02X", b[i]);
    fputc('\n', slog);
    fflush(slog);
}

/* ---- card -> host ---------------------------------------------------------- */

void serial_host_flush(sim_t *s)
{
    if (!grp_n)
        return;
    char line[8 + 3 * GROUP_MAX];
    int k = snprintf(line, sizeof line, "rx");
    for (unsigned i = 0; i < grp_n; i++)
        k += snprintf(line + k, sizeof line - (size_t)k, " %02X", grp[i]);
    if (slog) {
        fprintf(slog, "# %s\n", line);
        fflush(slog);
    }
    grp_n = 0;
    sim_printf(s, "%s\n", line);
}

/* 1 when a program has the connector open. */
static int peer_open(void)
{
    if (conn_kind == SERIAL_CONN_TCP)
        return conn_fd >= 0;
    if (conn_fd < 0)
        return 0;
    struct pollfd p = {conn_fd, POLLIN, 0};
    if (poll(&p, 1, 0) < 0)
        return 0;
    if (!(p.revents & POLLHUP))
        peer_seen = 1;
    return !(p.revents & POLLHUP);
}

static void tcp_drop(sim_t *s, const char *why)
{
    close(conn_fd);
    conn_fd = -1;
    peer_gone = 1;
    sim_printf(s, "serial-tcp closed (%s)\n", why);
}

static void on_tx(void *ctx, uint8_t b)
{
    sim_t *s = ctx;
    cyc_t now = sim_now(s);
    if (grp_n && (now - grp_last > IDLE_CYC || grp_n == GROUP_MAX))
        serial_host_flush(s);
    grp[grp_n++] = b;
    grp_last = now;
    /* Nobody at the connector: the byte goes nowhere, as on a real line. */
    if (!peer_open())
        return;
    if (conn_kind == SERIAL_CONN_TCP) {
        ssize_t w = send(conn_fd, &b, 1, MSG_DONTWAIT | MSG_NOSIGNAL);
        if (w < 0 && errno != EAGAIN && errno != EWOULDBLOCK)
            tcp_drop(s, strerror(errno));
        else if (w != 1 && !pty_dropped++)
            fprintf(stderr, "mac4sim: serial tcp: peer not reading, bytes dropped\n");
    } else if (write(conn_fd, &b, 1) != 1 && !pty_dropped++) {
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

/* The pty's line as the program at its other end set it (Linux shares one
 * termios between the two sides).  Said once whenever it changes between
 * 4800 8N1 and anything else: at another setting a real card would see
 * garbage, so bytes are still passed on but the line says so. */
static void pty_check_line(sim_t *s)
{
    struct termios t;
    if (tcgetattr(conn_fd, &t))
        return;
    speed_t sp = cfgetospeed(&t);
    int bits = (t.c_cflag & CSIZE) == CS8 ? 8 : (t.c_cflag & CSIZE) == CS7 ? 7
             : (t.c_cflag & CSIZE) == CS6 ? 6 : 5;
    char par = !(t.c_cflag & PARENB) ? 'N' : (t.c_cflag & PARODD) ? 'O' : 'E';
    int stop = t.c_cflag & CSTOPB ? 2 : 1;
    int bad = sp != B4800 || bits != 8 || par != 'N' || stop != 1;
    if (bad == line_bad)
        return;
    if (bad || line_bad == 1) {
        static const struct { speed_t sp; unsigned baud; } tab[] = {
            {B50, 50}, {B75, 75}, {B110, 110}, {B134, 134}, {B150, 150}, {B200, 200},
            {B300, 300}, {B600, 600}, {B1200, 1200}, {B1800, 1800}, {B2400, 2400},
            {B4800, 4800}, {B9600, 9600}, {B19200, 19200}, {B38400, 38400},
            {B57600, 57600}, {B115200, 115200}, {B230400, 230400}};
        unsigned baud = 0;
        for (size_t i = 0; i < sizeof tab / sizeof tab[0]; i++)
            if (tab[i].sp == sp)
                baud = tab[i].baud;
        sim_printf(s, "serial-pty line %u %d%c%d%s\n", baud, bits, par, stop,
                   bad ? " (not the card's 4800 8N1)" : "");
    }
    line_bad = bad;
}

static void tcp_accept(sim_t *s)
{
    for (;;) {
        int fd = accept(listen_fd, NULL, NULL);
        if (fd < 0)
            return;                        /* EAGAIN: nobody waiting */
        if (conn_fd >= 0) {
            /* The one before may have gone with nothing left to read. */
            struct pollfd p = {conn_fd, POLLIN | POLLRDHUP, 0};
            if (poll(&p, 1, 0) == 1 && (p.revents & (POLLRDHUP | POLLHUP | POLLERR))
                && recv(conn_fd, (char[1]){0}, 1, MSG_PEEK | MSG_DONTWAIT) <= 0)
                tcp_drop(s, "by the client");
        }
        if (conn_fd >= 0) {
            /* One cable at a time: a second program is told at once. */
            close(fd);
            sim_printf(s, "serial-tcp refused a second client\n");
            continue;
        }
        int one = 1;
        setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
        conn_fd = fd;
        peer_seen = 1;
        peer_gone = 0;
        sim_printf(s, "serial-tcp connected\n");
    }
}

static void conn_read_fd(sim_t *s)
{
    if (conn_kind == SERIAL_CONN_PTY && sim_now(s) >= line_next) {
        pty_check_line(s);
        line_next = sim_now(s) + LINE_POLL;
    }
    uint8_t buf[GROUP_MAX];
    unsigned room = wire_room(s);          /* the rest waits in the pty / socket */
    if (room == 0)
        return;
    ssize_t n = read(conn_fd, buf, room < sizeof buf ? room : sizeof buf);
    if (n == 0 && conn_kind == SERIAL_CONN_TCP) {
        tcp_drop(s, "by the client");
        return;
    }
    if (n < 0 && conn_kind == SERIAL_CONN_TCP && errno != EAGAIN && errno != EWOULDBLOCK) {
        tcp_drop(s, strerror(errno));
        return;
    }
    if (n <= 0)
        return;                            /* EAGAIN, or EIO: no peer on the pty */
    peer_seen = 1;
    if (conn_kind == SERIAL_CONN_PTY)
        pty_check_line(s);
    char line[8 + 3 * GROUP_MAX];
    int k = snprintf(line, sizeof line, "tx");
    for (ssize_t i = 0; i < n; i++)
        k += snprintf(line + k, sizeof line - (size_t)k, " %02X", buf[i]);
    slog_bytes(s, "tx", buf, (size_t)n);
    sim_printf(s, "%s\n", line);
    uart_feed(s, buf, (unsigned)n);
}

static void conn_read(sim_t *s)
{
    if (conn_kind == SERIAL_CONN_TCP)
        tcp_accept(s);
    if (conn_fd >= 0)
        conn_read_fd(s);
}

/* ---- the scheduler tap ------------------------------------------------------ */

static const cpu_t *inner;

static void tap(sim_t *s, cyc_t now)
{
    if (grp_n && now - grp_last > IDLE_CYC)
        serial_host_flush(s);
    if (conn_kind != SERIAL_CONN_NONE && now >= pty_next) {
        conn_read(s);
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
    if (conn_kind != SERIAL_CONN_NONE && pty_next > now && pty_next - now < max)
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
    char buf[SCRIPT_LINE_MAX + 2];
    while (script_getline(sc, in, buf) > 0) {
        int is_time = time_command(buf);
        slog_line(s, buf, is_time);
        int r = script_line(sc, s, buf);
        serial_host_flush(s);
        slog_line_done(s, is_time);
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

/* The program at the connector has closed it and everything it sent has
 * been read. */
static int peer_done(void)
{
    if (!peer_seen)
        return 0;
    if (conn_kind == SERIAL_CONN_TCP)
        return peer_gone && conn_fd < 0;
    struct pollfd p = {conn_fd, POLLIN, 0};
    if (poll(&p, 1, 0) < 0)
        return 0;
    return (p.revents & POLLHUP) && !(p.revents & POLLIN);
}

void serial_host_serve(sim_t *s, double seconds)
{
    if (conn_kind == SERIAL_CONN_NONE)
        return;
    struct timespec t0;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    cyc_t c0 = sim_now(s);
    for (;;) {
        conn_read(s);
        pty_next = sim_now(s) + PTY_POLL;
        sim_run(s, MS_TO_CYC(1));
        double wall = wall_seconds(&t0);
        /* With --serve-seconds the card keeps running, and keeps its state,
         * while programs disconnect and others connect; without, it stops
         * when the first program is done (docs/serial.md). */
        if (seconds > 0 ? wall >= seconds : peer_done())
            break;
        double ahead = (double)(sim_now(s) - c0) / (double)MAC4_CPU_HZ - wall;
        if (ahead > 0) {
            struct timespec d = {(time_t)ahead, (long)((ahead - (double)(time_t)ahead) * 1e9)};
            nanosleep(&d, NULL);
        }
    }
    serial_host_flush(s);
    slog_run(s);
    fflush(s->out);
}

/* ---- set-up ---------------------------------------------------------------------- */

static void remove_link(void)
{
    if (link_path[0])
        unlink(link_path);
}

static int make_link(const char *name, const char *path)
{
    struct stat st;
    if (!lstat(path, &st)) {
        if (!S_ISLNK(st.st_mode)) {
            fprintf(stderr, "mac4sim: --serial-pty-link: %s exists and is not a symbolic link\n",
                    path);
            return -1;
        }
        unlink(path);                      /* left by an earlier run */
    }
    if (symlink(name, path)) {
        fprintf(stderr, "mac4sim: --serial-pty-link %s: %s\n", path, strerror(errno));
        return -1;
    }
    snprintf(link_path, sizeof link_path, "%s", path);
    atexit(remove_link);
    return 0;
}

static int make_pty(const char *link)
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
    if (link && make_link(name, link))
        return -1;
    conn_fd = fd;
    conn_kind = SERIAL_CONN_PTY;
    line_bad = 0;
    printf("serial-pty %s\n", name);
    if (link)
        printf("serial-pty-link %s\n", link);
    fflush(stdout);
    return 0;
}

static int make_tcp(int port)
{
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    int one = 1;
    struct sockaddr_in a = {0};
    a.sin_family = AF_INET;
    a.sin_port = htons((uint16_t)port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);       /* 127.0.0.1 only */
    socklen_t len = sizeof a;
    if (fd < 0 || setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one)
        || bind(fd, (struct sockaddr *)&a, sizeof a) || listen(fd, 1)
        || getsockname(fd, (struct sockaddr *)&a, &len)) {
        fprintf(stderr, "mac4sim: --serial-tcp %d: %s\n", port, strerror(errno));
        return -1;
    }
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
    listen_fd = fd;
    conn_kind = SERIAL_CONN_TCP;
    printf("serial-tcp %u\n", ntohs(a.sin_port));
    fflush(stdout);
    return 0;
}

int serial_host_init(sim_t *s, const serial_opts_t *o)
{
    s->uart.on_tx = on_tx;
    s->uart.tx_ctx = s;
    grp_n = 0;
    if (o->log) {
        slog = fopen(o->log, "w");
        if (!slog) {
            fprintf(stderr, "mac4sim: --serial-log %s: %s\n", o->log, strerror(errno));
            return -1;
        }
        fprintf(slog, "# mac4sim serial session: replay with mac4sim --card CARD --script %s\n"
                "# (what the card sent is in `# rx` comments)\n", o->log);
        slog_at = sim_now(s);
    }
    if (o->kind == SERIAL_CONN_PTY)
        return make_pty(o->pty_link);
    if (o->kind == SERIAL_CONN_TCP)
        return make_tcp(o->tcp_port);
    return 0;
}
