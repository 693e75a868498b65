/*
 * gdbstub.c - GDB remote serial protocol for the emulated 68000
 * (docs/debugging.md).
 *
 * Stopping exactly: the Musashi instruction hook (musashi_cnf.h) asks
 * mac4_gdb_instr() before every instruction; when it answers 1 the hook
 * leaves m68k_execute's loop with `break`, before the instruction is
 * fetched, so the instruction at the breakpoint has not run.  cpu_m68k.c
 * then serves gdb from inside the scheduler's slice (no model runs, emulated
 * time stands still) and resumes the same slice with its remaining cycles.
 * m68k_execute samples the interrupt lines when it is entered; a resumed
 * slice must not, or an interrupt raised by the firmware inside the slice
 * would be taken earlier than without the stop.  So the lines are hidden
 * from that entry and given back at the first instruction's hook: the run
 * with stops is the run without them, cycle for cycle (the system test
 * compares the two).
 *
 * Breakpoints (Z0 software, Z1 hardware: the same here) live in a bitmap of
 * the stub; nothing is written into the EPROM.  Watchpoints (Z2 write, Z3
 * read, Z4 access) on any CPU data access, reported after the instruction
 * that made it.  Memory for gdb: EPROM (read only), SRAM and DPRAM as the
 * 68000 sees them; the I/O registers are refused (reading some of them has
 * side effects: `axreg` in the script reads them deliberately).
 */
#define _GNU_SOURCE
#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>
#include "m68k.h"
#include "m68kcpu.h"
#include "cpu.h"
#include "gdbstub.h"

int mac4_gdb_on;
int mac4_gdb_watching;

static int lfd = -1, cfd = -1;
static sim_t *gs;

/* ---- run control state ------------------------------------------------ */
enum { RUN_STOPPED, RUN_CONTINUE, RUN_STEP };
static int run_mode = RUN_STOPPED;
static int stop_now;                /* stop before the next instruction (Ctrl-C, watchpoint) */
static int stop_sig;                /* its signal */
static char stop_extra[64];         /* watch:ADDR; */
static int broke;                   /* the hook ended m68k_execute */
static int first_pending;           /* the instruction we stopped before runs first */
static unsigned stop_pc;
static int hide_irq;                /* resumed slice: the lines come back at the first hook */
static unsigned saved_level, saved_nmi;
static cyc_t next_poll;             /* emulated time of the next Ctrl-C poll while running */
static double stopped_wall;         /* wall seconds spent stopped */
static long long slice_left = -(1LL << 62); /* cycles the scheduler slice had left at the stop
                                             * (monitor slice); no slice yet at attach */

/* breakpoints: one bit per even address of the 24-bit space */
static uint8_t bp_map[(1u << 24) / 2 / 8];
static unsigned bp_count;

#define NWATCH 8
typedef struct {
    unsigned addr, len;
    int type;                       /* 2 write, 3 read, 4 access */
} watch_t;
static watch_t watches[NWATCH];
static unsigned nwatch;

static int bp_at(unsigned pc)
{
    pc &= 0xFFFFFE;
    return (bp_map[pc >> 4] >> ((pc >> 1) & 7)) & 1;
}

static void bp_set(unsigned a, int on)
{
    a &= 0xFFFFFE;
    uint8_t bit = (uint8_t)(1u << ((a >> 1) & 7));
    if (on && !(bp_map[a >> 4] & bit)) {
        bp_map[a >> 4] |= bit;
        bp_count++;
    } else if (!on && (bp_map[a >> 4] & bit)) {
        bp_map[a >> 4] &= (uint8_t)~bit;
        bp_count--;
    }
}

static double wall_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

double gdbstub_stopped_seconds(void) { return stopped_wall; }
int gdbstub_attached(void) { return cfd >= 0; }

/* ---- the hook --------------------------------------------------------- */
int mac4_gdb_instr(unsigned pc)
{
    if (hide_irq) {                 /* the first instruction of a resumed slice */
        m68ki_cpu.int_level = saved_level;
        m68ki_cpu.nmi_pending = saved_nmi;
        hide_irq = 0;
    }
    if (cfd < 0) {                  /* detached */
        mac4_gdb_on = 0;
        mac4_hooks_update();
        first_pending = 0;
        return 0;
    }
    if (first_pending) {
        first_pending = 0;
        if (pc == stop_pc)
            return 0;               /* the instruction we stopped before */
    }
    if (run_mode == RUN_STEP && !stop_now) {
        stop_now = 1;
        stop_sig = 5;
    }
    if (!stop_now && bp_count && bp_at(pc)) {
        stop_now = 1;
        stop_sig = 5;
        snprintf(stop_extra, sizeof stop_extra, "swbreak:;");
    }
    if (!stop_now)
        return 0;
    broke = 1;
    return 1;
}

/* The emulator saw a fault (bus.c sim_fault, s->on_fault): stop before the
 * next instruction. */
static void gdbstub_fault(sim_t *s)
{
    (void)s;
    if (cfd < 0 || stop_now)
        return;
    stop_now = 1;
    stop_sig = 11;                  /* SIGSEGV: what a real card would not survive */
    stop_extra[0] = 0;
}

void gdbstub_access(unsigned addr, int size, int write)
{
    addr &= 0xFFFFFF;
    for (unsigned i = 0; i < nwatch; i++) {
        watch_t *w = &watches[i];
        if (addr + (unsigned)size <= w->addr || addr >= w->addr + w->len)
            continue;
        if ((w->type == 2 && !write) || (w->type == 3 && write))
            continue;
        if (stop_now)
            return;
        stop_now = 1;
        stop_sig = 5;
        snprintf(stop_extra, sizeof stop_extra, "%s:%x;", w->type == 2 ? "watch" : w->type == 3 ? "rwatch" : "awatch",
                 w->addr);
        return;                     /* the hook stops before the next instruction */
    }
}

/* ---- packets ---------------------------------------------------------- */
static const char hexd[] = "0123456789abcdef";

static int hexv(int c)
{
    if (c >= '0' && c <= '9')
        return c - '0';
    if (c >= 'a' && c <= 'f')
        return c - 'a' + 10;
    if (c >= 'A' && c <= 'F')
        return c - 'A' + 10;
    return -1;
}

static void drop_connection(void)
{
    if (cfd >= 0)
        close(cfd);
    cfd = -1;
    /* mac4_gdb_on stays until the next instruction's hook, which gives
     * back the interrupt lines of a resumed slice and turns itself off */
    mac4_gdb_watching = 0;
    nwatch = 0;
    memset(bp_map, 0, sizeof bp_map);
    bp_count = 0;
    run_mode = RUN_CONTINUE;
    stop_now = 0;
}

static int send_all(const char *b, size_t n)
{
    while (n) {
        ssize_t k = send(cfd, b, n, MSG_NOSIGNAL);
        if (k <= 0) {
            if (k < 0 && errno == EINTR)
                continue;
            return -1;
        }
        b += k;
        n -= (size_t)k;
    }
    return 0;
}

static void put_packet(const char *data)
{
    if (cfd < 0)
        return;
    size_t n = strlen(data);
    char *b = malloc(n + 5);
    if (!b)
        return;
    unsigned sum = 0;
    b[0] = '$';
    for (size_t i = 0; i < n; i++) {
        b[1 + i] = data[i];
        sum += (unsigned char)data[i];
    }
    b[n + 1] = '#';
    b[n + 2] = hexd[(sum >> 4) & 15];
    b[n + 3] = hexd[sum & 15];
    b[n + 4] = 0;
    if (send_all(b, n + 4))
        drop_connection();
    free(b);
}

/* One byte from gdb; timeout_ms < 0 blocks.  -1 closed, -2 timeout. */
static int get_byte(int timeout_ms)
{
    if (cfd < 0)
        return -1;
    struct pollfd p = {cfd, POLLIN, 0};
    int r = poll(&p, 1, timeout_ms);
    if (r == 0)
        return -2;
    if (r < 0)
        return errno == EINTR ? -2 : -1;
    unsigned char c;
    ssize_t k = recv(cfd, &c, 1, 0);
    if (k <= 0)
        return -1;
    return c;
}

#define PKT_MAX 8192
static char pkt[PKT_MAX + 1];

/* The next packet into pkt (acknowledged); 0x03 returns 3; -1 closed. */
static int get_packet(void)
{
    for (;;) {
        int c = get_byte(-1);
        if (c < 0)
            return -1;
        if (c == 3)
            return 3;
        if (c != '$')
            continue;               /* acks, noise */
        size_t n = 0;
        unsigned sum = 0;
        for (;;) {
            c = get_byte(-1);
            if (c < 0)
                return -1;
            if (c == '#')
                break;
            if (n < PKT_MAX)
                pkt[n++] = (char)c;
            sum += (unsigned)c;
        }
        int h = get_byte(-1), l = get_byte(-1);
        if (h < 0 || l < 0)
            return -1;
        pkt[n] = 0;
        if (hexv(h) < 0 || hexv(l) < 0 || (unsigned)(hexv(h) << 4 | hexv(l)) != (sum & 0xFF)) {
            send_all("-", 1);
            continue;
        }
        send_all("+", 1);
        return 1;
    }
}

/* ---- memory as the 68000 sees it, without side effects ------------------- */
static uint8_t *mem_byte(unsigned a, int write)
{
    sim_t *s = gs;
    a &= 0xFFFFFF;
    if (a - EPROM_BASE < EPROM_SIZE)
        return write ? NULL : &s->eprom[a - EPROM_BASE];
    if (a < DPRAM_SIZE) {
        if (!write && (s->sysctl & SYS_CTRL_OVERLAY))
            return &s->eprom[a];    /* boot overlay: the EPROM at $000000 for reads */
        return &s->dpram[a];
    }
    if (a - SRAM_BASE < SRAM_SIZE)
        return &s->sram[a - SRAM_BASE];
    return NULL;
}

/* ---- registers: d0-d7, a0-a7, sr, pc (target.xml) ------------------------ */
#define NREGS 18
static const m68k_register_t reg_ids[NREGS] = {
    M68K_REG_D0, M68K_REG_D1, M68K_REG_D2, M68K_REG_D3, M68K_REG_D4, M68K_REG_D5,
    M68K_REG_D6, M68K_REG_D7, M68K_REG_A0, M68K_REG_A1, M68K_REG_A2, M68K_REG_A3,
    M68K_REG_A4, M68K_REG_A5, M68K_REG_A6, M68K_REG_A7, M68K_REG_SR, M68K_REG_PC};

static const char target_xml[] =
    "<?xml version=\"1.0\"?>\n<!DOCTYPE target SYSTEM \"gdb-target.dtd\">\n"
    "<target version=\"1.0\"><architecture>m68k:68000</architecture>\n"
    "<feature name=\"org.gnu.gdb.m68k.core\">\n"
    "<reg name=\"d0\" bitsize=\"32\"/><reg name=\"d1\" bitsize=\"32\"/><reg name=\"d2\" bitsize=\"32\"/>\n"
    "<reg name=\"d3\" bitsize=\"32\"/><reg name=\"d4\" bitsize=\"32\"/><reg name=\"d5\" bitsize=\"32\"/>\n"
    "<reg name=\"d6\" bitsize=\"32\"/><reg name=\"d7\" bitsize=\"32\"/>\n"
    "<reg name=\"a0\" bitsize=\"32\" type=\"data_ptr\"/><reg name=\"a1\" bitsize=\"32\" type=\"data_ptr\"/>\n"
    "<reg name=\"a2\" bitsize=\"32\" type=\"data_ptr\"/><reg name=\"a3\" bitsize=\"32\" type=\"data_ptr\"/>\n"
    "<reg name=\"a4\" bitsize=\"32\" type=\"data_ptr\"/><reg name=\"a5\" bitsize=\"32\" type=\"data_ptr\"/>\n"
    "<reg name=\"fp\" bitsize=\"32\" type=\"data_ptr\"/><reg name=\"sp\" bitsize=\"32\" type=\"data_ptr\"/>\n"
    "<reg name=\"ps\" bitsize=\"32\"/><reg name=\"pc\" bitsize=\"32\" type=\"code_ptr\"/>\n"
    "</feature></target>\n";

static void hex32(char *o, uint32_t v)
{
    for (int i = 0; i < 8; i++)
        o[i] = hexd[(v >> (28 - 4 * i)) & 15];
}

static int parse_hex(const char **p, unsigned long *v)
{
    const char *q = *p;
    unsigned long x = 0;
    int n = 0;
    while (hexv(*q) >= 0) {
        x = x << 4 | (unsigned)hexv(*q++);
        n++;
    }
    *p = q;
    *v = x;
    return n ? 0 : -1;
}

/* CRC-32 as gdb's compare-sections computes it (polynomial $04C11DB7, MSB first) */
static uint32_t crc32_gdb(unsigned a, unsigned long len, int *bad)
{
    uint32_t crc = 0xFFFFFFFFu;
    for (unsigned long i = 0; i < len; i++) {
        uint8_t *m = mem_byte(a + (unsigned)i, 0);
        if (!m) {
            *bad = 1;
            return 0;
        }
        crc ^= (uint32_t)*m << 24;
        for (int k = 0; k < 8; k++)
            crc = (crc & 0x80000000u) ? (crc << 1) ^ 0x04C11DB7u : crc << 1;
    }
    return crc;
}

static void monitor(const char *hexcmd)
{
    char cmd[256];
    size_t n = 0;
    while (hexcmd[0] && hexcmd[1] && n < sizeof cmd - 1) {
        cmd[n++] = (char)(hexv(hexcmd[0]) << 4 | hexv(hexcmd[1]));
        hexcmd += 2;
    }
    cmd[n] = 0;
    char text[256];
    if (!strcmp(cmd, "time")) {
        cyc_t now = sim_now(gs);
        snprintf(text, sizeof text, "time %.6f ms cycles %llu\n", (double)now / 16000.0, (unsigned long long)now);
    } else if (!strcmp(cmd, "slice")) {
        if (slice_left == -(1LL << 62))
            snprintf(text, sizeof text, "no slice yet\n");
        else
            snprintf(text, sizeof text, "slice-left %lld\n", slice_left);
    } else {
        snprintf(text, sizeof text, "monitor commands: time (emulated time and 68000 cycles), "
                 "slice (cycles left in the scheduler slice; <= 0: the next instruction still runs in it)\n");
    }
    char out[2 + 2 * sizeof text];
    out[0] = 'O';
    size_t k = 1;
    for (size_t i = 0; text[i]; i++) {
        out[k++] = hexd[((unsigned char)text[i]) >> 4];
        out[k++] = hexd[text[i] & 15];
    }
    out[k] = 0;
    put_packet(out);
    put_packet("OK");
}

static void stop_reply(void)
{
    char r[96];
    snprintf(r, sizeof r, "T%02x%s", stop_sig ? stop_sig : 5, stop_extra);
    put_packet(r);
}

/* Serve packets with the CPU stopped until gdb resumes it (continue, step,
 * detach) or goes away. */
static void serve(void)
{
    double t0 = wall_now();
    static char out[PKT_MAX + 1];
    run_mode = RUN_STOPPED;
    while (cfd >= 0 && run_mode == RUN_STOPPED) {
        int r = get_packet();
        if (r < 0) {
            drop_connection();
            break;
        }
        if (r == 3)
            continue;               /* already stopped */
        const char *p = pkt + 1;
        unsigned long a, len;
        switch (pkt[0]) {
        case '?':
            stop_reply();
            break;
        case 'g': {
            for (int i = 0; i < NREGS; i++)
                hex32(out + 8 * i, m68k_get_reg(NULL, reg_ids[i]));
            out[8 * NREGS] = 0;
            put_packet(out);
            break;
        }
        case 'G': {
            if (strlen(p) < 8 * NREGS) {
                put_packet("E01");
                break;
            }
            for (int i = 0; i < NREGS; i++) {
                const char *q = p + 8 * i;
                char tmp[9];
                memcpy(tmp, q, 8);
                tmp[8] = 0;
                m68k_set_reg(reg_ids[i], (unsigned)strtoul(tmp, NULL, 16));
            }
            put_packet("OK");
            break;
        }
        case 'p':
            if (parse_hex(&p, &a) || a >= NREGS) {
                put_packet("E01");
                break;
            }
            hex32(out, m68k_get_reg(NULL, reg_ids[a]));
            out[8] = 0;
            put_packet(out);
            break;
        case 'P': {
            unsigned long v;
            if (parse_hex(&p, &a) || *p++ != '=' || parse_hex(&p, &v) || a >= NREGS) {
                put_packet("E01");
                break;
            }
            m68k_set_reg(reg_ids[a], (unsigned)v);
            put_packet("OK");
            break;
        }
        case 'm':
            if (parse_hex(&p, &a) || *p++ != ',' || parse_hex(&p, &len) || len > PKT_MAX / 2) {
                put_packet("E01");
                break;
            }
            {
                size_t k = 0;
                for (unsigned long i = 0; i < len; i++) {
                    uint8_t *m = mem_byte((unsigned)(a + i), 0);
                    if (!m)
                        break;
                    out[k++] = hexd[*m >> 4];
                    out[k++] = hexd[*m & 15];
                }
                out[k] = 0;
                put_packet(k ? out : "E0e");
            }
            break;
        case 'M': {
            if (parse_hex(&p, &a) || *p++ != ',' || parse_hex(&p, &len) || *p++ != ':' ||
                strlen(p) < 2 * len) {
                put_packet("E01");
                break;
            }
            int bad = 0;
            for (unsigned long i = 0; i < len; i++)
                if (!mem_byte((unsigned)(a + i), 1))
                    bad = 1;
            if (bad) {                  /* the EPROM and the I/O registers are not written */
                put_packet("E0e");
                break;
            }
            for (unsigned long i = 0; i < len; i++)
                *mem_byte((unsigned)(a + i), 1) = (uint8_t)(hexv(p[2 * i]) << 4 | hexv(p[2 * i + 1]));
            put_packet("OK");
            break;
        }
        case 'Z':
        case 'z': {
            int type = pkt[1] - '0';
            p = pkt + 2;
            if (*p++ != ',' || parse_hex(&p, &a) || *p++ != ',' || parse_hex(&p, &len) || type < 0 || type > 4) {
                put_packet("E01");
                break;
            }
            if (type <= 1) {
                bp_set((unsigned)a, pkt[0] == 'Z');
                put_packet("OK");
                break;
            }
            if (pkt[0] == 'Z') {
                if (nwatch == NWATCH) {
                    put_packet("E1c");
                    break;
                }
                watches[nwatch++] = (watch_t){(unsigned)a & 0xFFFFFF, (unsigned)len, type};
            } else {
                for (unsigned i = 0; i < nwatch; i++)
                    if (watches[i].addr == (a & 0xFFFFFF) && watches[i].len == len && watches[i].type == type) {
                        watches[i] = watches[--nwatch];
                        break;
                    }
            }
            mac4_gdb_watching = nwatch > 0;
            put_packet("OK");
            break;
        }
        case 'c':
        case 's':
            if (*p && !parse_hex(&p, &a))
                m68k_set_reg(M68K_REG_PC, (unsigned)a);
            run_mode = pkt[0] == 'c' ? RUN_CONTINUE : RUN_STEP;
            break;
        case 'D':
            put_packet("OK");
            drop_connection();
            break;
        case 'k':
            fflush(gs->out);
            drop_connection();
            exit(0);
        case 'H':
            put_packet("OK");
            break;
        case 'T':
            put_packet("OK");
            break;
        case 'q':
            if (!strncmp(pkt, "qSupported", 10)) {
                put_packet("PacketSize=2000;qXfer:features:read+;swbreak+;hwbreak+");
            } else if (!strncmp(pkt, "qXfer:features:read:target.xml:", 31)) {
                p = pkt + 31;
                if (parse_hex(&p, &a) || *p++ != ',' || parse_hex(&p, &len)) {
                    put_packet("E01");
                    break;
                }
                size_t tl = sizeof target_xml - 1;
                if (a >= tl) {
                    put_packet("l");
                    break;
                }
                if (len > PKT_MAX - 2)
                    len = PKT_MAX - 2;
                size_t k = tl - a < len ? tl - a : len;
                out[0] = a + k >= tl ? 'l' : 'm';
                memcpy(out + 1, target_xml + a, k);   /* no '$', '#' or '}' in it */
                out[k + 1] = 0;
                put_packet(out);
            } else if (!strcmp(pkt, "qAttached")) {
                put_packet("1");    /* gdb detaches at quit, the card runs on */
            } else if (!strncmp(pkt, "qCRC:", 5)) {
                p = pkt + 5;
                int bad = 0;
                if (parse_hex(&p, &a) || *p++ != ',' || parse_hex(&p, &len)) {
                    put_packet("E01");
                    break;
                }
                uint32_t c = crc32_gdb((unsigned)a, len, &bad);
                snprintf(out, sizeof out, bad ? "E0e" : "C%08x", (unsigned)c);
                put_packet(out);
            } else if (!strncmp(pkt, "qRcmd,", 6)) {
                monitor(pkt + 6);
            } else if (!strcmp(pkt, "qC")) {
                put_packet("QC1");
            } else if (!strcmp(pkt, "qfThreadInfo")) {
                put_packet("m1");
            } else if (!strcmp(pkt, "qsThreadInfo")) {
                put_packet("l");
            } else {
                put_packet("");
            }
            break;
        default:
            put_packet("");         /* not supported: gdb falls back (vCont, X ...) */
            break;
        }
    }
    stopped_wall += wall_now() - t0;
}

/* The CPU stops here; report it and serve gdb until it resumes. */
static void stop_and_serve(void)
{
    stop_pc = m68k_get_reg(NULL, M68K_REG_PC);
    stop_reply();
    stop_now = 0;
    stop_sig = 0;
    stop_extra[0] = 0;
    serve();
    if (cfd >= 0)
        first_pending = 1;
    next_poll = sim_now(gs) + MS_TO_CYC(1);
}

/* ---- hooks of cpu_m68k.c ------------------------------------------------- */
void gdbstub_slice_start(sim_t *s, long long budget)
{
    (void)s;
    slice_left = budget;
    if (cfd < 0) {
        mac4_gdb_on = 0;            /* detached between slices */
        mac4_hooks_update();
        return;
    }
    if (!stop_now && sim_now(gs) >= next_poll) {   /* Ctrl-C from gdb, a closed connection */
        next_poll = sim_now(gs) + MS_TO_CYC(1);
        struct pollfd p = {cfd, POLLIN, 0};
        if (poll(&p, 1, 0) > 0) {
            int c = get_byte(0);
            if (c == 3) {
                stop_now = 1;
                stop_sig = 2;
            } else if (c == -1) {
                drop_connection();
                return;
            }
        }
    }
    if (stop_now && !(m68ki_cpu.stopped & STOP_LEVEL_HALT))
        stop_and_serve();          /* between slices: no instruction is half done */
}

int gdbstub_stopped_in_slice(void)
{
    int b = broke;
    broke = 0;
    return b;
}

void gdbstub_serve_stop(sim_t *s, long long left)
{
    (void)s;
    slice_left = left;
    stop_and_serve();
}

void gdbstub_resume_in_slice(void)
{
    if (!mac4_gdb_on)
        return;
    /* the same slice goes on: hide the interrupt lines from m68k_execute's
     * entry, the first instruction's hook gives them back */
    saved_level = m68ki_cpu.int_level;
    saved_nmi = m68ki_cpu.nmi_pending;
    m68ki_cpu.int_level = 0;
    m68ki_cpu.nmi_pending = 0;
    hide_irq = 1;
}

/* ---- attach and the serve loop after the script ------------------------------ */
int gdbstub_attach(sim_t *s, int port)
{
    gs = s;
    if (cfd >= 0) {
        fprintf(stderr, "mac4sim: gdb: a debugger is already attached\n");
        return -1;
    }
    if (lfd < 0) {
        lfd = socket(AF_INET, SOCK_STREAM, 0);
        int one = 1;
        setsockopt(lfd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
        struct sockaddr_in sa = {0};
        sa.sin_family = AF_INET;
        sa.sin_port = htons((uint16_t)port);
        sa.sin_addr.s_addr = htonl(INADDR_LOOPBACK);   /* 127.0.0.1 only */
        if (lfd < 0 || bind(lfd, (struct sockaddr *)&sa, sizeof sa) || listen(lfd, 1)) {
            fprintf(stderr, "mac4sim: gdb: cannot listen on 127.0.0.1:%d: %s\n", port, strerror(errno));
            if (lfd >= 0)
                close(lfd);
            lfd = -1;
            return -1;
        }
    }
    struct sockaddr_in sa;
    socklen_t sl = sizeof sa;
    getsockname(lfd, (struct sockaddr *)&sa, &sl);
    printf("gdb-port %u\n", ntohs(sa.sin_port));
    fflush(stdout);
    do
        cfd = accept(lfd, NULL, NULL);
    while (cfd < 0 && errno == EINTR);
    if (cfd < 0) {
        fprintf(stderr, "mac4sim: gdb: accept: %s\n", strerror(errno));
        return -1;
    }
    int one = 1;
    setsockopt(cfd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    mac4_gdb_on = 1;
    mac4_hooks_update();
    s->on_fault = gdbstub_fault;
    stop_sig = 5;
    stop_pc = m68k_get_reg(NULL, M68K_REG_PC);
    /* stopped between instructions: serve until gdb continues */
    serve();
    if (cfd >= 0)
        first_pending = 1;
    next_poll = sim_now(s) + MS_TO_CYC(1);
    return 0;
}
