/*
 * cpu_native.c - the firmware compiled for the host, driven by the
 * emulator's scheduler like the 68000 (cpu_native.h explains the model).
 * Built once per card with -DMAC4_CARD=n and linked with build/native-CARD/fw.o.
 */
#include <setjmp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "cpu_native.h"
#include "periph.h"
#include "hal.h"
#include "fw.h"

/* harness/hal_native.c */
extern jmp_buf *hal_native_stop_jmp;
unsigned hal_native_irq_mask(void);

/* The firmware's static data, gathered into these sections by the build
 * (Makefile, "native"): reset to the initial values at every card reset,
 * as crt0 does on the 68000.  Weak: a section may be empty. */
extern char __start_mac4fw_data[] __attribute__((weak));
extern char __stop_mac4fw_data[] __attribute__((weak));
extern char __start_mac4fw_datarel[] __attribute__((weak));
extern char __stop_mac4fw_datarel[] __attribute__((weak));
extern char __start_mac4fw_bss[] __attribute__((weak));
extern char __stop_mac4fw_bss[] __attribute__((weak));

typedef struct {
    char *start, *stop, *copy;
} region_t;
static region_t data_r, datarel_r;

static size_t span(const char *start, const char *stop)
{
    uintptr_t a = (uintptr_t)start, b = (uintptr_t)stop;
    return a && b > a ? (size_t)(b - a) : 0;
}

/* Byte copies, not memcpy, and not checked: the native builds use ASan,
 * which would object to the red zones between the firmware's variables. */
__attribute__((no_sanitize_address)) static void copy_bytes(volatile char *dst, const volatile char *src, size_t n)
{
    for (size_t i = 0; i < n; i++)
        dst[i] = src[i];
}

static void snapshot(region_t *r, char *start, char *stop)
{
    r->start = start;
    r->stop = stop;
    size_t n = span(start, stop);
    if (n) {
        r->copy = malloc(n);
        if (!r->copy)
            abort();
        copy_bytes(r->copy, start, n);
    }
}

static void restore(const region_t *r)
{
    if (r->copy)
        copy_bytes(r->start, r->copy, (size_t)(r->stop - r->start));
}

__attribute__((no_sanitize_address)) static void statics_reset(void)
{
    static int taken;
    if (!taken) {
        taken = 1;
        snapshot(&data_r, __start_mac4fw_data, __stop_mac4fw_data);
        snapshot(&datarel_r, __start_mac4fw_datarel, __stop_mac4fw_datarel);
    }
    restore(&data_r);
    restore(&datarel_r);
    volatile char *bss = __start_mac4fw_bss;
    for (size_t i = 0, n = span(__start_mac4fw_bss, __stop_mac4fw_bss); i < n; i++)
        bss[i] = 0;
}

/* ---- state ----------------------------------------------------------------- */
static int in_slice, in_call;
static cyc_t elapsed;          /* cycles into the current slice */
static int ipl;                /* the interrupt level requested by the models */
static int need_boot;          /* reset seen: boot at the start of the next slice */
static int stopped;            /* the firmware stopped for good (hal_stop) */

static cyc_t native_elapsed(void)
{
    if (!in_slice)
        return 0;
    cyc_t e = elapsed;
    if (in_call)
        elapsed += NATIVE_CYC_CLOCK;
    return e;
}

/* Run one firmware entry point; 0, or -1 when it stopped the card. */
static int call(void (*fn)(void))
{
    jmp_buf jb;
    hal_native_stop_jmp = &jb;
    in_call = 1;
    if (setjmp(jb)) {
        in_call = 0;
        hal_native_stop_jmp = NULL;
        stopped = 1;
        return -1;
    }
    fn();
    in_call = 0;
    hal_native_stop_jmp = NULL;
    return 0;
}

static void stage1(void) { (void)fw_boot_stage1(); }

static void boot(sim_t *s)
{
    statics_reset();
    bus_write(s, SYS_CTRL, 0, 2);                /* crt0: release the boot overlay */
    if (call(stage1) == 0) {
        statics_reset();                         /* crt0: .data and .bss */
        call(fw_init);
    }
    elapsed += NATIVE_CYC_BOOT;
}

static void take_irq(sim_t *s, int level)
{
    static void (*const isr[8])(void) = {
        [IRQ_LEVEL_UART] = fw_isr_uart, [IRQ_LEVEL_AXIS] = fw_isr_axis,
        [IRQ_LEVEL_TIMER] = fw_isr_tick, [IRQ_LEVEL_ESTOP] = fw_isr_estop,
    };
    static const cyc_t cost[8] = {
        [IRQ_LEVEL_UART] = NATIVE_CYC_UART, [IRQ_LEVEL_AXIS] = NATIVE_CYC_AXIS,
        [IRQ_LEVEL_TIMER] = NATIVE_CYC_TICK, [IRQ_LEVEL_ESTOP] = NATIVE_CYC_ESTOP,
    };
    if (level == IRQ_LEVEL_ESTOP)
        estop_irq_ack(s);
    irq_enter(s, level);
    unsigned prev = hal_native_irq_mask();
    hal_irq_restore((unsigned)level);            /* the 68000 masks up to its level */
    int ok = isr[level] ? call(isr[level]) : (sim_fault(s, "native: no handler for level %d", level), 0);
    elapsed += cost[level] ? cost[level] : NATIVE_CYC_UART;
    if (ok == 0)
        hal_irq_restore(prev);                   /* RTE */
    irq_leave(s, 0);
    sim_update_irq(s);
}

static cyc_t native_execute(sim_t *s, cyc_t max)
{
    in_slice = 1;
    elapsed = 0;
    if (need_boot) {
        need_boot = 0;
        boot(s);
    }
    while (elapsed < max) {
        if (stopped) {
            /* hal_stop on the 68000: interrupts masked, retriggering the watchdog */
            bus_write(s, WDG_KICK, 0, 2);
            cyc_t step = max - elapsed < 1600 ? max - elapsed : 1600;
            elapsed += step;
            continue;
        }
        int level = ipl;
        if (level == IRQ_LEVEL_ESTOP || (level > 0 && (unsigned)level > hal_native_irq_mask())) {
            take_irq(s, level);
            continue;
        }
        call(fw_main_step);
        elapsed += NATIVE_CYC_MAIN;
    }
    cyc_t ran = elapsed;
    elapsed = 0;
    in_slice = 0;
    return ran;
}

static void native_reset(sim_t *s)
{
    s->cpu_elapsed = native_elapsed;
    s->cpu_pc = NULL;
    need_boot = 1;
    stopped = 0;
    in_call = in_slice = 0;
    elapsed = 0;
}

static void native_set_irq(int level) { ipl = level; }
static int native_halted(void) { return 0; }

const cpu_t cpu_native = {"native (" __VERSION__ ")", native_reset, native_execute, native_set_irq,
                          native_halted};

const cpu_t *mac4sim_native_cpu(void) { return &cpu_native; }

/* The emulator keeps some allocations for its lifetime: no leak report. */
const char *__asan_default_options(void);
const char *__asan_default_options(void) { return "detect_leaks=0"; }
int mac4sim_native_card(void) { return MAC4_CARD; }
