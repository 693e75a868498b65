/*
 * mac4sim - the emulated MAC4 card: boots the real EPROM image on a 68000
 * and lets a host script (or a person) drive it.  docs/host-script.md.
 */
#include <libgen.h>
#include <stdlib.h>
#include <string.h>
#include "cpu.h"
#include "script.h"
#include "profile.h"
#include "serial_host.h"
#include "buswait.h"
#include "gdbstub.h"
#include "panel.h"
#include "idle.h"

static sim_t card;

/* Defined only in the native builds (cpu_native.c, build/mac4sim-native-CARD):
 * there the firmware compiled for the host replaces the 68000. */
const cpu_t *mac4sim_native_cpu(void) __attribute__((weak));
int mac4sim_native_card(void) __attribute__((weak));

static void usage(FILE *f)
{
    fprintf(f,
            "usage: mac4sim [options]\n"
            "  --card inc|ssi|stp   card type (default inc)\n"
            "  --image PATH         EPROM image (default: eprom/mac4-CARD.bin beside mac4sim)\n"
            "  --script FILE        run host script FILE ('-' = stdin); default stdin\n"
            "  --timestamps         prefix every event with the emulated time\n"
            "  --irq-level N        VMEbus interrupt level of LB1/LB2 (1..7, default 3)\n"
            "  --j11 in|out         watchdog reset jumper J11 (default in)\n"
            "  --wait-states SPEC   bus timing (docs/memory-map.md, \"Bus timing\"): N for every\n"
            "                       region, or REGION[.read|.write]=N,... over the defaults\n"
            "                       of hal/mac4_map.h (regions: dpram eprom sram vme sys\n"
            "                       timer uart virq watchdog axis axis-irq unmapped)\n"
            "  --iack autovector|vectored  interrupt acknowledge (default autovector, via VPA)\n"
            "  --allow-faults       no exit status 3 or 4: faults are what the test wants\n"
            "  --no-fast            every emulator speedup off (same output, slower;\n"
            "                       docs/performance.md)\n"
            "  --idle-stats         at the end, on stderr: what the idle skip did\n"
            "                       (docs/performance.md, \"The idle skip\")\n"
            "  --serial-pty         front-panel serial line on a pseudo-terminal (prints\n"
            "                       'serial-pty /dev/pts/N'); after the script the card\n"
            "                       keeps running in real time until the pty is closed\n"
            "  --serial-pty-link PATH  the same, and a symbolic link PATH to the pty\n"
            "  --serial-tcp PORT    front-panel serial line as a raw byte stream on TCP\n"
            "                       127.0.0.1:PORT (0: any free port; prints 'serial-tcp N');\n"
            "                       after the script as --serial-pty, until the client closes\n"
            "  --serve-seconds N    serve the line for N seconds instead, keeping the card\n"
            "                       running while clients disconnect and reconnect\n"
            "  --serial-log FILE    write the serial session as a host script that replays it\n"
            "  --serve-seconds N    with --serial-pty: stop serving after N seconds\n"
            "  --gdb PORT           wait for gdb on 127.0.0.1:PORT (0: any free port; prints\n"
            "                       'gdb-port N') with the CPU stopped before its first\n"
            "                       instruction; after the script the card runs on in real\n"
            "                       time until gdb detaches (docs/debugging.md)\n"
            "  --panel PORT         the front panel as a web page on 127.0.0.1:PORT (0: any\n"
            "                       free port; prints 'panel-port N'); after the script the\n"
            "                       card runs on in real time (docs/debugging.md)\n"
            "                       --serve-seconds N bounds that too\n"
            "  --help               this text\n"
            "Exit status (the first that applies, in this order): 1 usage or script error,\n"
            "  3 the emulator saw a fault (a bus error, a double bus fault that halted the\n"
            "  CPU, ...), 4 the card ended stopped with an error (display X.: a boot step\n"
            "  failed, F.), 2 a wait-display timed out; else 0.\n");
}

/* A TCP port on 127.0.0.1 in decimal, 0..65535 (0: any free one); -1 if not. */
static int tcp_port(const char *val)
{
    long long p;
    return script_parse_num(val, &p) || p < 0 || p > 65535 ? -1 : (int)p;
}

int main(int argc, char **argv)
{
    const char *cardname = "inc", *image = NULL, *script = "-";
    buswait_init();
    if (mac4sim_native_card)
        cardname = mac4sim_native_card() == MAC4_CARD_STP ? "stp" : mac4sim_native_card() == MAC4_CARD_SSI ? "ssi" : "inc";
    int allow_faults = 0, timestamps = 0, level = 3, j11 = 1;
    serial_opts_t serial = {SERIAL_CONN_NONE, NULL, 0, NULL};   /* docs/serial.md */
    double serve_seconds = 0;
    int idle_stats_on = 0;       /* --idle-stats */
    int gdb_port = -1;           /* --gdb: docs/debugging.md */
    int panel_port = -1;         /* --panel: docs/debugging.md */
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *val = (i + 1 < argc) ? argv[i + 1] : NULL;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "--card") && val) {
            cardname = val;
            i++;
        } else if (!strcmp(a, "--image") && val) {
            image = val;
            i++;
        } else if (!strcmp(a, "--script") && val) {
            script = val;
            i++;
        } else if (!strcmp(a, "--irq-level") && val) {
            long long l;
            if (script_parse_num(val, &l) || l < 1 || l > 7) {
                fprintf(stderr, "mac4sim: bad --irq-level '%s' (1..7)\n", val);
                return 1;
            }
            level = (int)l;
            i++;
        } else if (!strcmp(a, "--j11") && val) {
            if (strcmp(val, "in") && strcmp(val, "out")) {
                fprintf(stderr, "mac4sim: bad --j11 '%s' (in or out)\n", val);
                return 1;
            }
            j11 = !strcmp(val, "in");
            i++;
        } else if (!strcmp(a, "--wait-states") && val) {
            char err[200];
            if (buswait_parse(val, err, sizeof err)) {
                fprintf(stderr, "mac4sim: %s\n", err);
                return 1;
            }
            i++;
        } else if (!strcmp(a, "--iack") && val) {
            if (buswait_parse_iack(val)) {
                fprintf(stderr, "mac4sim: bad --iack '%s' (autovector or vectored)\n", val);
                return 1;
            }
            i++;
        } else if (!strcmp(a, "--timestamps")) {
            timestamps = 1;
        } else if (!strcmp(a, "--no-fast")) {
            mac4_fast = 0;
        } else if (!strcmp(a, "--idle-stats")) {
            idle_stats_on = 1;
        } else if (!strcmp(a, "--allow-faults")) {
            allow_faults = 1;
        } else if (!strcmp(a, "--serial-pty") || (!strcmp(a, "--serial-pty-link") && val)) {
            if (serial.kind == SERIAL_CONN_TCP) {
                fprintf(stderr, "mac4sim: one serial connector: --serial-pty or --serial-tcp\n");
                return 1;
            }
            serial.kind = SERIAL_CONN_PTY;
            if (a[12]) {
                serial.pty_link = val;
                i++;
            }
        } else if (!strcmp(a, "--serial-tcp") && val) {
            int port = tcp_port(val);
            if (port < 0 || serial.kind == SERIAL_CONN_PTY) {
                fprintf(stderr, "mac4sim: bad --serial-tcp '%s' (a port 0..65535, 0: any; "
                        "not with --serial-pty)\n", val);
                return 1;
            }
            serial.kind = SERIAL_CONN_TCP;
            serial.tcp_port = port;
            i++;
        } else if (!strcmp(a, "--serial-log") && val) {
            serial.log = val;
            i++;
        } else if (!strcmp(a, "--gdb") && val) {
            gdb_port = tcp_port(val);
            if (gdb_port < 0 || mac4sim_native_cpu) {
                fprintf(stderr, "mac4sim: bad --gdb '%s' (a port 0..65535; the 68000 build only)\n", val);
                return 1;
            }
            i++;
        } else if (!strcmp(a, "--panel") && val) {
            panel_port = tcp_port(val);
            if (panel_port < 0) {
                fprintf(stderr, "mac4sim: bad --panel '%s' (a port 0..65535)\n", val);
                return 1;
            }
            i++;
        } else if (!strcmp(a, "--serve-seconds") && val) {
            if (script_parse_real(val, &serve_seconds) || !(serve_seconds > 0)) {
                fprintf(stderr, "mac4sim: bad --serve-seconds '%s'\n", val);
                return 1;
            }
            i++;
        } else {
            fprintf(stderr, "mac4sim: unknown or incomplete option '%s'\n", a);
            usage(stderr);
            return 1;
        }
    }
    int cardno = !strcmp(cardname, "inc") ? MAC4_CARD_INC : !strcmp(cardname, "ssi") ? MAC4_CARD_SSI
               : !strcmp(cardname, "stp") ? MAC4_CARD_STP : -1;
    if (cardno < 0 || level < 1 || level > 7) {
        fprintf(stderr, "mac4sim: bad --card or --irq-level\n");
        return 1;
    }
    if (mac4sim_native_card && cardno != mac4sim_native_card()) {
        fprintf(stderr, "mac4sim: this native build runs the %s firmware only\n",
                mac4sim_native_card() == MAC4_CARD_STP ? "stp" : mac4sim_native_card() == MAC4_CARD_SSI ? "ssi" : "inc");
        return 1;
    }
    char defimg[4096];
    if (!image) {
        char self[2048];
        snprintf(self, sizeof self, "%s", argv[0]);
        snprintf(defimg, sizeof defimg, "%s/eprom/mac4-%s.bin", dirname(self), cardname);
        image = defimg;
    }

    sim_init(&card, cardno);
    card.timestamps = timestamps;
    card.vme.level = (uint8_t)level;
    card.wdg.j11 = j11;
    int n = sim_load_image(&card, image);
    if (n < 0) {
        fprintf(stderr, "mac4sim: cannot load EPROM image '%s'%s\n", image,
                n == -2 ? " (empty or larger than 64 KiB)" : "");
        return 1;
    }
    {   /* symbols for `profile report`: the .sym the build writes beside the image */
        char sym[4200];
        snprintf(sym, sizeof sym, "%s", image);
        char *dot = strrchr(sym, '.');
        if (dot && !strcmp(dot, ".bin")) {
            strcpy(dot, ".sym");
            profile_load_symbols(sym);
        }
    }
    if (serial_host_init(&card, &serial))
        return 1;
    const cpu_t *cpu = serial_host_cpu(mac4sim_native_cpu ? mac4sim_native_cpu() : &cpu_m68k);
    if (panel_port >= 0) {
        char cj[4200];
        char self[2048];
        snprintf(self, sizeof self, "%s", argv[0]);
        snprintf(cj, sizeof cj, "%s/commands.json", dirname(self));
        if (panel_listen(&card, panel_port, cj))
            return 1;
        cpu = panel_cpu(cpu);
    }
    sim_attach_cpu(&card, cpu);

    FILE *in = strcmp(script, "-") ? fopen(script, "r") : stdin;
    if (!in || script_check_file(in)) {
        fprintf(stderr, "mac4sim: cannot open script '%s'%s\n", script, in ? " (a directory)" : "");
        return 1;
    }
    if (gdb_port >= 0 && gdbstub_attach(&card, gdb_port))
        return 1;
    script_t sc = {script, 0, 0, 0};
    int errors = serial_host_script_run(&sc, &card, in);
    if (in != stdin)
        fclose(in);
    if (errors)
        return 1;
    serial_host_serve(&card, serve_seconds);
    bench_serve(&card, serve_seconds);   /* while the panel is open or gdb attached */
    if (idle_stats_on)
        idle_print_stats(stderr);
    if (sim_halted)   /* a double bus fault, and no reset since (docs/board.md, "Bus errors") */
        fprintf(stderr, "mac4sim: the CPU is halted (double bus fault): only a reset restarts it\n");
    /* the card stopped with an error: a boot step (2., 3.) or F. (firmware/boot.c) */
    if (card.faults && !allow_faults)
        return 3;
    if ((card.sys.display & SYS_DISPLAY_DP) && card.sys.display != 0xFF && !allow_faults) {
        fprintf(stderr, "mac4sim: the card stopped with the display at %X.\n", card.sys.display & 0xF);
        return 4;
    }
    if (script_waits_timed_out) {
        fprintf(stderr, "mac4sim: %d wait-display timed out\n", script_waits_timed_out);
        return 2;
    }
    return 0;
}
