/*
 * panel.c - the front panel as a web page (docs/debugging.md, "Front
 * panel"): a small HTTP server on 127.0.0.1, answered between the CPU's
 * slices, so the page shows the card as it is at that emulated moment.
 *
 *   GET  /               the page (panel_page.h)
 *   GET  /state          JSON: display, STOP LED, the six LEDs of each axis
 *                        (axisboard_leds: the same source as `leds`), the
 *                        axis data the card publishes (DPA_*), time, resets
 *   GET  /commands.json  build/commands.json: the names of the status bits
 *   POST /reset          the reset button
 *   POST /stop           the /STOP input, toggled
 */
#define _GNU_SOURCE
#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>
#include "panel.h"
#include "periph.h"
#include "gdbstub.h"
#include "panel_page.h"

static int lfd = -1;
static char *commands;               /* build/commands.json */
static size_t commands_len;
static cyc_t next_poll;
static int want_reset, want_stop;

#define NLOG 16
static char dlog[NLOG][8];           /* the display since the last reset */
static unsigned ndlog;
static uint16_t last_display = 0xFFFF;
static uint64_t last_resets;

#define NCLI 8
static struct {
    int fd;
    char buf[2048];
    size_t n;
} cli[NCLI];

int panel_active(void) { return lfd >= 0; }

static void track_display(sim_t *s);

int panel_listen(sim_t *s, int port, const char *commands_json)
{
    for (int i = 0; i < NCLI; i++)
        cli[i].fd = -1;
    FILE *f = fopen(commands_json, "rb");
    if (f) {
        fseek(f, 0, SEEK_END);
        long n = ftell(f);
        fseek(f, 0, SEEK_SET);
        commands = malloc(n > 0 ? (size_t)n : 1);
        if (commands && n > 0 && fread(commands, 1, (size_t)n, f) == (size_t)n)
            commands_len = (size_t)n;
        fclose(f);
    }
    if (!commands_len)
        fprintf(stderr, "mac4sim: panel: no %s: status bits shown as numbers\n", commands_json);
    lfd = socket(AF_INET, SOCK_STREAM, 0);
    int one = 1;
    struct sockaddr_in sa = {0};
    sa.sin_family = AF_INET;
    sa.sin_port = htons((uint16_t)port);
    sa.sin_addr.s_addr = htonl(INADDR_LOOPBACK);   /* 127.0.0.1 only */
    if (lfd < 0 || setsockopt(lfd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) ||
        bind(lfd, (struct sockaddr *)&sa, sizeof sa) || listen(lfd, 8)) {
        fprintf(stderr, "mac4sim: panel: cannot listen on 127.0.0.1:%d: %s\n", port, strerror(errno));
        if (lfd >= 0)
            close(lfd);
        lfd = -1;
        return -1;
    }
    fcntl(lfd, F_SETFL, fcntl(lfd, F_GETFL) | O_NONBLOCK);
    s->on_display = track_display;
    socklen_t sl = sizeof sa;
    getsockname(lfd, (struct sockaddr *)&sa, &sl);
    printf("panel-port %u\n", ntohs(sa.sin_port));
    fflush(stdout);
    return 0;
}

/* ---- answers ------------------------------------------------------------- */
static void reply(int fd, const char *status, const char *type, const char *body, size_t len)
{
    char h[256];
    int k = snprintf(h, sizeof h,
                     "HTTP/1.1 %s\r\nContent-Type: %s\r\nContent-Length: %zu\r\nCache-Control: no-store\r\n"
                     "Connection: close\r\n\r\n", status, type, len);
    int fl = fcntl(fd, F_GETFL);
    fcntl(fd, F_SETFL, fl & ~O_NONBLOCK);          /* small answers over loopback */
    struct timeval tv = {1, 0};
    setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
    if (send(fd, h, (size_t)k, MSG_NOSIGNAL) == k && len)
        send(fd, body, len, MSG_NOSIGNAL);
}

static void track_display(sim_t *s)
{
    if (s->resets != last_resets) {
        last_resets = s->resets;
        ndlog = 0;
        last_display = 0xFFFF;
    }
    if (s->sys.display == last_display)
        return;
    last_display = s->sys.display;
    if (s->sys.display == 0xFF)
        return;                     /* blank after reset */
    if (ndlog == NLOG) {
        memmove(dlog[0], dlog[1], sizeof dlog - sizeof dlog[0]);
        ndlog--;
    }
    snprintf(dlog[ndlog++], sizeof dlog[0], "%X%s", s->sys.display & 0xF, (s->sys.display & SYS_DISPLAY_DP) ? "." : "");
}

static size_t state_json(sim_t *s, char *b, size_t cap)
{
    static const char *const cardname[3] = {"inc", "ssi", "stp"};
    size_t k = 0;
#define OUT(...) k += (size_t)snprintf(b + k, k < cap ? cap - k : 0, __VA_ARGS__)
    OUT("{\"card\":\"%s\",\"t_ms\":%.3f,\"resets\":%llu,", cardname[s->card % 3], (double)sim_now(s) / 16000.0,
        (unsigned long long)s->resets);
    OUT("\"display\":{\"digit\":%u,\"dp\":%s,\"blank\":%s},", s->sys.display & 0xFu,
        (s->sys.display & SYS_DISPLAY_DP) && s->sys.display != 0xFF ? "true" : "false", s->sys.display == 0xFF ? "true" : "false");
    OUT("\"display_log\":[");
    for (unsigned i = 0; i < ndlog; i++)
        OUT("%s\"%s\"", i ? "," : "", dlog[i]);
    OUT("],\"stop\":%s,\"led_names\":[", s->sys.estop ? "true" : "false");
    for (unsigned i = 0; i < AXIS_NLEDS; i++)
        OUT("%s\"%s\"", i ? "," : "", axis_leds[i].name);
    OUT("],\"axes\":[");
    for (int n = 0; n < MAC4_NAXES; n++) {
        uint32_t d = DP_AXIS_DATA((uint32_t)n);   /* as a host reads what the card publishes */
        OUT("%s{\"leds\":%u,\"ustat\":%u,\"pos\":%d,\"ferr\":%d,\"setpoint\":%d}", n ? "," : "", axisboard_leds(s, n),
            dp_rd32(s, d + DPA_USTAT), (int32_t)dp_rd32(s, d + DPA_POS), (int32_t)dp_rd32(s, d + DPA_FERR),
            (int32_t)dp_rd32(s, d + DPA_SETPOINT));
    }
    OUT("]}");
#undef OUT
    return k < cap ? k : cap - 1;
}

static void answer(sim_t *s, int i)
{
    char method[8] = "", path[128] = "";
    sscanf(cli[i].buf, "%7s %127s", method, path);
    char *q = strchr(path, '?');
    if (q)
        *q = 0;
    int fd = cli[i].fd;
    if (!strcmp(method, "GET") && (!strcmp(path, "/") || !strcmp(path, "/index.html"))) {
        reply(fd, "200 OK", "text/html; charset=utf-8", panel_page, sizeof panel_page - 1);
    } else if (!strcmp(method, "GET") && !strcmp(path, "/state")) {
        static char b[4096];
        size_t n = state_json(s, b, sizeof b);
        reply(fd, "200 OK", "application/json", b, n);
    } else if (!strcmp(method, "GET") && !strcmp(path, "/commands.json") && commands_len) {
        reply(fd, "200 OK", "application/json", commands, commands_len);
    } else if (!strcmp(method, "POST") && !strcmp(path, "/reset")) {
        want_reset = 1;
        reply(fd, "200 OK", "application/json", "{}", 2);
    } else if (!strcmp(method, "POST") && !strcmp(path, "/stop")) {
        want_stop = 1;
        reply(fd, "200 OK", "application/json", "{}", 2);
    } else if (!strcmp(path, "/favicon.ico")) {
        reply(fd, "204 No Content", "text/plain", "", 0);
    } else {
        reply(fd, "404 Not Found", "text/plain", "not here\n", 9);
    }
    close(fd);
    cli[i].fd = -1;
}

void panel_poll(sim_t *s)
{
    if (lfd < 0)
        return;
    track_display(s);
    for (;;) {                      /* new connections */
        int fd = accept(lfd, NULL, NULL);
        if (fd < 0)
            break;
        int i;
        for (i = 0; i < NCLI && cli[i].fd >= 0; i++)
            ;
        if (i == NCLI) {
            close(fd);
            continue;
        }
        fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
        cli[i].fd = fd;
        cli[i].n = 0;
    }
    for (int i = 0; i < NCLI; i++) {
        if (cli[i].fd < 0)
            continue;
        ssize_t r = recv(cli[i].fd, cli[i].buf + cli[i].n, sizeof cli[i].buf - 1 - cli[i].n, 0);
        if (r == 0 || (r < 0 && errno != EAGAIN && errno != EWOULDBLOCK)) {
            close(cli[i].fd);
            cli[i].fd = -1;
            continue;
        }
        if (r > 0)
            cli[i].n += (size_t)r;
        cli[i].buf[cli[i].n] = 0;
        if (strstr(cli[i].buf, "\r\n\r\n") || cli[i].n >= sizeof cli[i].buf - 1)
            answer(s, i);           /* the requests carry no body we need */
    }
}

/* ---- between slices ----------------------------------------------------------- */
static const cpu_t *inner;
static cpu_t tapped;

static cyc_t tap_execute(sim_t *s, cyc_t max)
{
    cyc_t now = sim_now(s);
    if (now >= next_poll) {
        next_poll = now + MS_TO_CYC(1);
        panel_poll(s);
    }
    if (want_stop) {                /* as the script's `estop on|off` */
        want_stop = 0;
        estop_set(s, !s->sys.estop);
        sim_update_irq(s);
    }
    if (want_reset) {               /* as the script's `reset`; the scheduler looks again */
        want_reset = 0;
        sim_reset(s, "button");
        return 1;
    }
    return inner->execute(s, max);
}
static void tap_reset(sim_t *s) { inner->reset(s); }
static void tap_set_irq(int level) { inner->set_irq(level); }
static int tap_halted(void) { return inner->halted(); }

const cpu_t *panel_cpu(const cpu_t *c)
{
    inner = c;
    tapped = (cpu_t){c->name, tap_reset, tap_execute, tap_set_irq, tap_halted};
    return &tapped;
}

/* ---- the paced loop after the script -------------------------------------------- */
static double wall(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

void bench_serve(sim_t *s, double seconds)
{
    if (!panel_active() && !gdbstub_attached())
        return;
    double w0 = wall();
    double stopped0 = gdbstub_stopped_seconds();
    cyc_t c0 = sim_now(s);
    while (panel_active() || gdbstub_attached()) {
        double w = wall() - w0;
        if (seconds > 0 && w >= seconds)
            break;
        sim_run(s, MS_TO_CYC(1));
        panel_poll(s);
        /* emulated time follows the wall clock, less the time gdb held the CPU */
        double ahead = (double)(sim_now(s) - c0) / (double)MAC4_CPU_HZ -
                       (wall() - w0 - (gdbstub_stopped_seconds() - stopped0));
        if (ahead > 0) {
            struct timespec d = {(time_t)ahead, (long)((ahead - (double)(time_t)ahead) * 1e9)};
            nanosleep(&d, NULL);
        }
    }
    fflush(s->out);
}
