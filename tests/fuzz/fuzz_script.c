/*
 * fuzz_script.c - libFuzzer target: mac4sim's host-script reader (harness/
 * script*.c, docs/host-script.md), the whole vocabulary and include.
 *
 * Input: byte 0 picks the card (% 3), the rest is the script, read as
 * mac4sim reads --script FILE (script_getline, script_line).  It also lies
 * in the scratch directory (build/fuzz/scratch-script) as `self.mac4`, beside `a.mac4` (a few good
 * lines), `loop.mac4` (includes itself) and `deep.mac4` (includes a.mac4
 * through self.mac4), so `include` reaches nested files, loops, itself and
 * /dev/zero.  No CPU: a null one lets time pass (the script reader is the
 * subject here; the card as a 68000 is fuzz_card68k.c), with a budget of
 * emulated time per input after which the input ends.
 *
 * Properties, besides ASan/UBSan and libFuzzer's hang detection: no file is
 * written (fuzz_fopen.c refuses it), includes nest at most 8 deep, and the
 * reader's line count equals the lines it was given (up to where it stopped
 * at a line that is not text).
 */
#include <sys/stat.h>
#include "fuzz_emu.h"
#include "script.h"

int fz_files_open(void);
void fz_files_close_all(void);

static jmp_buf budget_jb;
static unsigned long slices;
#define SLICE_BUDGET 40000UL        /* ~20 s of emulated time at the host's 0.5 ms polls */

static cyc_t null_elapsed(void) { return 0; }
static uint32_t null_pc(void) { return 0; }
static void null_reset(sim_t *s)
{
    s->cpu_elapsed = null_elapsed;
    s->cpu_pc = null_pc;
}
static cyc_t null_execute(sim_t *s, cyc_t max)
{
    (void)s;
    if (fz_files_open() > 9)
        FZ_FAIL("%d script files open at once: include nests deeper than 8", fz_files_open());
    if (++slices > SLICE_BUDGET)
        longjmp(budget_jb, 1);
    return max;
}
static void null_irq(int level) { (void)level; }
static int null_halted(void) { return 0; }
static const cpu_t null_cpu = {"none (fuzz_script.c)", null_reset, null_execute, null_irq, null_halted};

/* Not a 68000: `gdb PORT` is refused instead of waiting for a debugger
 * (bench_script.c), the probes that need one too (perf.c). */
const cpu_t *mac4sim_native_cpu(void) { return &null_cpu; }

static void put(const char *name, const void *data, size_t n)
{
    FILE *f = fopen(name, "wb");
    if (!f || fwrite(data, 1, n, f) != n || fclose(f)) {
        perror(name);
        exit(2);
    }
}

/* The scratch directory, relative to the repository (make runs there): the
 * included files are found beside the script, "main.mac4" in it. */
#define DIR "build/fuzz/scratch-script"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    mkdir("build", 0777);
    mkdir("build/fuzz", 0777);
    mkdir(DIR, 0777);
    static const char a[] = "echo a\nrun 1\npeek32 0x4700\nstatus\n";
    static const char loop[] = "echo loop\ninclude loop.mac4\n";
    static const char deep[] = "include self.mac4\ninclude a.mac4\n";
    put(DIR "/a.mac4", a, sizeof a - 1);
    put(DIR "/loop.mac4", loop, sizeof loop - 1);
    put(DIR "/deep.mac4", deep, sizeof deep - 1);
    return 0;
}

/* The lines the reader should count: up to its stop at a line that is not
 * text (one longer than SCRIPT_LINE_MAX, a NUL), which it counts too. */
static int expected_lines(const uint8_t *p, size_t n)
{
    int lines = 0;
    size_t len = 0;
    for (size_t i = 0; i < n; i++) {
        if (len == 0)
            lines++;
        if (p[i] == 0 || (len == SCRIPT_LINE_MAX && p[i] != '\n'))
            return lines;
        len = p[i] == '\n' ? 0 : len + 1;
    }
    return lines;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    int card = data[0] % 3;
    put(DIR "/self.mac4", data + 1, size - 1);
    sim_init(&S, card);
    S.out = fz_null_out();
    sim_attach_cpu(&S, &null_cpu);
    slices = 0;
    script_waits_timed_out = 0;
    script_includes = 0;
    FILE *in = fopen(DIR "/self.mac4", "rb");
    script_t sc = {DIR "/main.mac4", 0, 0, 0};
    if (!setjmp(budget_jb)) {
        int quit = 0;
        char buf[SCRIPT_LINE_MAX + 2];
        int r;
        while (!quit && (r = script_getline(&sc, in, buf)) > 0)
            quit = script_line(&sc, &S, buf) > 0;
        if (!quit)
            FZ_CHECK(sc.line == expected_lines(data + 1, size - 1), "the reader counted %d lines of %d",
                     sc.line, expected_lines(data + 1, size - 1));
    }
    fclose(in);
    fz_files_close_all();    /* those of includes cut short by the budget */
    return 0;
}
