/*
 * script.c - the host script language of mac4sim (docs/host-script.md).
 * One command per line, '#' starts a comment.  Everything the card does
 * that a host could see is printed as it happens (resp, display, vme-irq,
 * rx, fault ...).
 */
#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <limits.h>
#include <string.h>
#include <sys/stat.h>
#include "script.h"
#include "cpu.h"
#include "periph.h"
#include "profile.h"
#include "buswait.h"
#include "plant.h"

/* A line holds at most 1023 characters (SCRIPT_LINE_MAX), so at most 512
 * tokens: a line can never have more than MAXTOK. */
#define MAXTOK (SCRIPT_LINE_MAX / 2 + 2)

/* The one number reader of the script vocabulary and of mac4sim's options.
 * Integers: [+-] then decimal digits, or 0x / $ and hexadecimal digits.  A
 * leading zero is decimal (0100 is one hundred, as in mac4host); nothing
 * else (spaces, octal, 0b, a trailing letter) is a number. */
int script_parse_num(const char *t, long long *out)
{
    int neg = 0, base = 10;
    const char *p = t;
    if (*p == '+' || *p == '-')
        neg = *p++ == '-';
    if (p[0] == '$') {
        base = 16;
        p++;
    } else if (p[0] == '0' && (p[1] == 'x' || p[1] == 'X')) {
        base = 16;
        p += 2;
    }
    if (!*p)
        return -1;
    unsigned long long v = 0;
    for (; *p; p++) {
        int d = isdigit((unsigned char)*p) ? *p - '0'
              : base == 16 && isxdigit((unsigned char)*p) ? tolower((unsigned char)*p) - 'a' + 10 : -1;
        if (d < 0)
            return -1;
        if (v > (ULLONG_MAX - (unsigned)d) / (unsigned)base)
            return -1;
        v = v * (unsigned)base + (unsigned)d;
    }
    if (v > (unsigned long long)LLONG_MAX + (unsigned)neg)
        return -1;
    *out = neg ? (long long)(0 - v) : (long long)v;
    return 0;
}

/* Real numbers (times, plant parameters): [+-] digits [. digits] [e [+-] digits],
 * decimal only: no hexadecimal, no nan or inf. */
int script_parse_real(const char *t, double *out)
{
    const char *p = t;
    int digits = 0;
    if (*p == '+' || *p == '-')
        p++;
    for (; isdigit((unsigned char)*p); p++)
        digits++;
    if (*p == '.')
        for (p++; isdigit((unsigned char)*p); p++)
            digits++;
    if (!digits)
        return -1;
    if (*p == 'e' || *p == 'E') {
        p++;
        if (*p == '+' || *p == '-')
            p++;
        if (!isdigit((unsigned char)*p))
            return -1;
        while (isdigit((unsigned char)*p))
            p++;
    }
    if (*p)
        return -1;
    double v = strtod(t, NULL);
    if (!(v > -1e300 && v < 1e300))
        return -1;
    *out = v;
    return 0;
}

/* Milliseconds of emulated time, 0 to one hour. */
int script_parse_ms(const char *t, cyc_t *out)
{
    double ms;
    if (script_parse_real(t, &ms) || !(ms >= 0 && ms <= 3.6e6))
        return -1;
    *out = (cyc_t)(ms * 16000.0 + 0.5);
    return 0;
}

int script_err(script_t *sc, const char *fmt, const char *arg)
{
    fprintf(stderr, "%s:%d: ", sc->name, sc->line);
    fprintf(stderr, fmt, arg);
    fputc('\n', stderr);
    sc->errors++;
    return -1;
}

/* A DPRAM offset for an access of w bytes: all of it inside the DPRAM (a
 * long at $FFFE does not wrap round to the vectors at 0). */
static int dp_off(script_t *sc, const char *t, uint32_t *off, int w)
{
    long long v;
    if (script_parse_num(t, &v) || v < 0 || v > (long long)DPRAM_SIZE - w)
        return script_err(sc, w == 4 ? "bad DPRAM offset '%s' for a long (0..0xFFFC)"
                          : w == 2 ? "bad DPRAM offset '%s' for a word (0..0xFFFE)"
                          : "bad DPRAM offset '%s' (0..0xFFFF)", t);
    if (w > 1 && (v & 1))
        return script_err(sc, "odd DPRAM offset '%s' for a word access", t);
    *off = (uint32_t)v;
    return 0;
}

static int cmd_send(script_t *sc, sim_t *s, char **tok, int n)
{
    long long axis, param = 0;
    if (n < 3 || n > 4)
        return script_err(sc, "usage: %s AXIS CODE [PARAM]", "send");
    if (script_parse_num(tok[1], &axis) || axis < 0 || axis > 255)
        return script_err(sc, "bad axis '%s' (0..255)", tok[1]);
    long code = script_code(tok[2]);
    if (code < 0)
        return script_err(sc, "unknown code or mnemonic '%s'", tok[2]);
    if (n == 4 && (script_parse_num(tok[3], &param) || param < -2147483648LL || param > 0xFFFFFFFFLL))
        return script_err(sc, "bad parameter '%s' (32 bits)", tok[3]);
    /* A real host waits while the queue is full: so do we, up to 1 s. */
    for (int waited = 0;; waited++) {
        int r = host_send(s, (uint8_t)axis, (uint16_t)code, (uint32_t)param, MSG_SRC_VME);
        if (r == 1)
            return 0;
        if (r < 0)
            return script_err(sc, "%s: command queue header unusable, not sent", "send");
        if (waited >= 1000)
            return script_err(sc, "%s: command queue full for 1 s, not sent", "send");
        sim_run(s, MS_TO_CYC(1));
    }
}

static void print_queue(sim_t *s, const char *name, uint32_t q)
{
    sim_printf(s, "queue %s $%04X base=$%X front=%u rear=%u free=%u width=$%X nel=$%X\n", name, q,
               dp_rd32(s, q + QH_BASE), dp_rd32(s, q + QH_FRONT), dp_rd32(s, q + QH_REAR),
               dp_rd32(s, q + QH_FREE), dp_rd32(s, q + QH_WIDTH), dp_rd32(s, q + QH_NEL));
}

/* on|1 -> 1, off|0 -> 0, anything else -1 (in|out for a jumper: jumper_in) */
static int on_off(const char *t) { return !strcmp(t, "on") || !strcmp(t, "1") ? 1 : !strcmp(t, "off") || !strcmp(t, "0") ? 0 : -1; }
static int jumper_in(const char *t) { return !strcmp(t, "in") ? 1 : !strcmp(t, "out") ? 0 : -1; }

int script_waits_timed_out;

int script_line(script_t *sc, sim_t *s, char *line)
{
    char *hash = strchr(line, '#');
    if (hash)
        *hash = 0;
    char *tok[MAXTOK];
    int n = 0;
    for (char *p = strtok(line, " \t\r\n"); p; p = strtok(NULL, " \t\r\n")) {
        if (n == MAXTOK)
            return script_err(sc, "more than %s words on the line", "512");
        tok[n++] = p;
    }
    if (n == 0)
        return 0;
    const char *c = tok[0];
    long long v;
    uint32_t off;
    cyc_t cyc;

    if (!strcmp(c, "send"))
        return cmd_send(sc, s, tok, n);
    if (!strcmp(c, "run")) {
        if (n != 2 || script_parse_ms(tok[1], &cyc))
            return script_err(sc, "usage: %s MS (decimal milliseconds, 0..3600000)", "run");
        sim_run(s, cyc);
        return 0;
    }
    if (!strcmp(c, "peek8") || !strcmp(c, "peek16") || !strcmp(c, "peek32")) {
        int w = c[4] == '8' ? 1 : c[4] == '1' ? 2 : 4;
        if (n != 2 || dp_off(sc, tok[1], &off, w))
            return n != 2 ? script_err(sc, "usage: %s ADDR", c) : -1;
        uint32_t val = w == 1 ? s->dpram[off] : w == 2 ? dp_rd16(s, off) : dp_rd32(s, off);
        sim_printf(s, "%s 0x%04X 0x%0*X\n", c, off, w * 2, val);
        return 0;
    }
    if (!strcmp(c, "poke8") || !strcmp(c, "poke16") || !strcmp(c, "poke32")) {
        int w = c[4] == '8' ? 1 : c[4] == '1' ? 2 : 4;
        if (n != 3)
            return script_err(sc, "usage: %s ADDR VALUE", c);
        if (dp_off(sc, tok[1], &off, w))
            return -1;
        if (script_parse_num(tok[2], &v))
            return script_err(sc, "bad value '%s'", tok[2]);
        if (w == 1) {
            s->dpram[off] = (uint8_t)v;
            if (dp_written)
                dp_written();
        } else if (w == 2)
            dp_wr16(s, off, (uint16_t)v);
        else
            dp_wr32(s, off, (uint32_t)v);
        return 0;
    }
    if (!strcmp(c, "wait-display")) {
        long long want;
        cyc_t limit = MS_TO_CYC(5000), waited;
        if (n < 2 || n > 3 || script_parse_num(tok[1], &want) || want < 0 || want > 15 ||
            (n == 3 && script_parse_ms(tok[2], &limit)))
            return script_err(sc, "usage: %s DIGIT [MS] (digit 0..15, decimal ms 0..3600000)", c);
        for (waited = 0;; waited += US_TO_CYC(100)) {
            if ((s->sys.display & 0xF) == want && !(s->sys.display & SYS_DISPLAY_DP))
                return 0;
            if (waited >= limit)
                break;
            sim_run(s, US_TO_CYC(100));
        }
        sim_printf(s, "timeout wait-display %s\n", tok[1]);
        script_waits_timed_out++;     /* mac4sim's exit status 2 */
        return 0;
    }
    if (!strcmp(c, "queues")) {
        print_queue(s, "command", DP_CMD_QUEUE);
        print_queue(s, "response", DP_RSP_QUEUE);
        return 0;
    }
    if (!strcmp(c, "banner")) {
        char b[16];
        unsigned i;
        for (i = 0; i < sizeof b - 1 && s->dpram[DP_RSP_QUEUE + Q_HEADER_SIZE + i]; i++)
            b[i] = (char)s->dpram[DP_RSP_QUEUE + Q_HEADER_SIZE + i];
        b[i] = 0;
        /* print the copyright sign (Latin-1 $A9) readably */
        char *sign = strchr(b, (char)0xA9);
        if (sign) {
            *sign = 0;
            sim_printf(s, "banner \"%s(C)%s\"\n", b, sign + 1);
        } else {
            sim_printf(s, "banner \"%s\"\n", b);
        }
        return 0;
    }
    if (!strcmp(c, "profile")) {
        if (n >= 2 && (!strcmp(tok[1], "on") || !strcmp(tok[1], "off"))) {
            profile_set(!strcmp(tok[1], "on"));
            return 0;
        }
        if (n >= 2 && !strcmp(tok[1], "reset")) {
            profile_reset();
            return 0;
        }
        if (n >= 2 && !strcmp(tok[1], "report")) {
            long long top = 20;
            if (n > 3 || (n == 3 && (script_parse_num(tok[2], &top) || top < 1 || top > 100000)))
                return script_err(sc, "usage: %s report [N]", c);
            profile_report(s->out, (unsigned)top);
            return 0;
        }
        if (n == 3 && !strcmp(tok[1], "pcs")) {
            if (profile_pcs(tok[2]))
                return script_err(sc, "profile pcs: cannot write '%s'", tok[2]);
            return 0;
        }
        return script_err(sc, "usage: %s on|off|reset|report [N]|pcs FILE", c);
    }
    if (!strcmp(c, "bus-stats")) {       /* bus cycles and wait states by region (buswait.h) */
        if (n == 2 && !strcmp(tok[1], "reset")) {
            buswait_reset_stats();
            return 0;
        }
        if (n == 2 && !strcmp(tok[1], "display")) {   /* as they were at the display's last change */
            buswait_print(s->out);
            buswait_print_mark(s->out);
            return 0;
        }
        if (n != 1)
            return script_err(sc, "usage: %s [reset|display]", c);
        buswait_print(s->out);
        sim_printf(s, "bus-stats cycles=%llu\n", (unsigned long long)sim_now(s));
        buswait_print_stats(s->out);
        return 0;
    }
    if (!strcmp(c, "irqstats")) {
        irq_print_table(s, s->out);
        return 0;
    }
    if (!strcmp(c, "status")) {
        cyc_t now = sim_now(s);
        sim_printf(s, "status time=%.3fms cycles=%llu display=%X%s faults=%llu resets=%llu\n",
                   (double)now / 16000.0, (unsigned long long)now, s->sys.display & 0xF,
                   (s->sys.display & SYS_DISPLAY_DP) ? "." : "", (unsigned long long)s->faults,
                   (unsigned long long)s->resets);
        return 0;
    }
    if (!strcmp(c, "outputs")) {
        for (int a = 0; a < MAC4_NAXES; a++)
            sim_printf(s, "output %d en=%d dac=%d rate=%u dir=%d boost=%d\n", a,
                       (s->ax[a].ctrl & AX_CTRL_EN) && !s->sys.estop, s->ax[a].dac, s->ax[a].rate,
                       !!(s->ax[a].ctrl & AX_CTRL_DIR), !!(s->ax[a].ctrl & AX_CTRL_BOOST));
        return 0;
    }
    if (!strcmp(c, "leds")) {
        /* the register word, then the six LEDs of each axis that are lit
         * (2.5.3): D, P, F from the register, the limit and reference LEDs
         * from the input levels (lit at 0 V: AX_IN bit set), as in hardware */
        char buf[160];
        int k = snprintf(buf, sizeof buf, "leds 0x%04X stop=%d", s->sys.leds, s->sys.estop);
        for (int a = 0; a < 4; a++) {
            unsigned lit = axisboard_leds(s, a);
            k += snprintf(buf + k, sizeof buf - (size_t)k, " %d=", a);
            int any = 0;
            for (unsigned i = 0; i < AXIS_NLEDS; i++)
                if (lit & (1u << i)) {
                    k += snprintf(buf + k, sizeof buf - (size_t)k, "%s%s", any ? "," : "", axis_leds[i].name);
                    any = 1;
                }
            if (!any)
                k += snprintf(buf + k, sizeof buf - (size_t)k, "-");
        }
        sim_printf(s, "%s\n", buf);
        return 0;
    }
    if (!strcmp(c, "host")) {
        if (n != 3 || strcmp(tok[1], "read") || on_off(tok[2]) < 0)
            return script_err(sc, "usage: %s read on|off", c);
        s->host_reads = on_off(tok[2]);
        return 0;
    }
    if (!strcmp(c, "estop")) {
        if (n != 2 || on_off(tok[1]) < 0)
            return script_err(sc, "usage: %s on|off", c);
        estop_set(s, on_off(tok[1]));
        sim_update_irq(s);
        return 0;
    }
    if (!strcmp(c, "fc")) {
        if (n != 2 || script_parse_num(tok[1], &v) || v < 0 || v > 7)
            return script_err(sc, "usage: %s 0..7", c);
        s->sys.fc = (uint8_t)v;
        return 0;
    }
    if (!strcmp(c, "jumper")) {
        if (n != 3 || strcmp(tok[1], "j11") || jumper_in(tok[2]) < 0)
            return script_err(sc, "usage: %s j11 in|out", c);
        s->wdg.j11 = jumper_in(tok[2]);
        return 0;
    }
    if (!strcmp(c, "reset")) {
        sim_reset(s, "button");
        return 0;
    }
    if (!strcmp(c, "echo")) {   /* text for people: never timestamped */
        for (int i = 1; i < n; i++)
            fprintf(s->out, "%s%s", tok[i], i + 1 < n ? " " : "");
        fprintf(s->out, "\n");
        return 0;
    }
    if (!strcmp(c, "quit"))
        return 1;
    /* command families that live beside their models */
    static int (*const ext[])(script_t *, sim_t *, char **, int) = {script_serial, script_plant,
                                                                      script_perf, script_bench};
    for (unsigned i = 0; i < sizeof ext / sizeof ext[0]; i++) {
        int r = ext[i](sc, s, tok, n);
        if (r != SCRIPT_NOT_MINE)
            return r;
    }
    return script_err(sc, "unknown command '%s' (see docs/host-script.md)", c);
}

/* The next line of a script into buf (SCRIPT_LINE_MAX + 2 bytes): 1, or 0 at
 * the end.  A line longer than SCRIPT_LINE_MAX, a NUL byte or a read error
 * is not a script: an error with its line number, and -1 (the caller stops
 * reading, so /dev/zero or a binary file ends at once). */
int script_getline(script_t *sc, FILE *in, char *buf)
{
    size_t len = 0;
    int c;
    while ((c = getc(in)) != EOF) {
        if (len == 0)
            sc->line++;
        if (c == 0)
            return script_err(sc, "a NUL byte in the line (%s)", "not a text file?");
        if (len == SCRIPT_LINE_MAX && c != '\n')
            return script_err(sc, "line longer than %s characters", "1023");
        buf[len++] = (char)c;
        if (c == '\n')
            break;
    }
    buf[len] = 0;
    if (c == EOF && ferror(in))
        return script_err(sc, "cannot read the script (%s)", "a directory?");
    return len > 0;
}

/* A script file to read: 0, or -1 if f is a directory (which fopen opens). */
int script_check_file(FILE *f)
{
    struct stat st;
    return fstat(fileno(f), &st) == 0 && S_ISDIR(st.st_mode) ? -1 : 0;
}

int script_run(script_t *sc, sim_t *s, FILE *in)
{
    char buf[SCRIPT_LINE_MAX + 2];
    while (script_getline(sc, in, buf) > 0) {
        int r = script_line(sc, s, buf);
        if (r > 0)
            break;
    }
    return sc->errors;
}
