/*
 * cpu_native.h - the firmware compiled for the host as a CPU backend
 * (docs/performance.md, "Native and 68000 agree").
 *
 * The firmware (firmware, harness/hal_native.c, hal/target/runtime.c) is built for
 * one card into build/native-CARD/fw.o with only its entry points global,
 * and linked with the emulator into build/mac4sim-native-CARD.  The same
 * scheduler, bus, peripheral and plant models serve it; instead of
 * executing instructions it calls the firmware's entry points (fw.h), each
 * charged a fixed nominal number of cycles so that emulated time advances:
 *
 *   reset      the boot overlay released as crt0 does, the firmware's static
 *              data reset to its initial values (crt0's .data/.bss set-up),
 *              fw_boot_stage1() and fw_init()
 *   interrupt  when the requested level exceeds the firmware's mask
 *              (hal_native_irq_mask(); level 7 always, edge-triggered):
 *              fw_isr_tick/axis/uart/estop with the mask raised to the level,
 *              accounted by irq_enter/irq_leave like the 68000's
 *   otherwise  fw_main_step()
 *
 * A fatal stop (fw_halt -> hal_stop) longjmps out of the firmware: the card
 * then does nothing but retrigger the watchdog, as the 68000 build does.
 * While a firmware call runs, every look at the clock (sim_now) costs
 * NATIVE_CYC_CLOCK cycles, so polling loops see time pass.
 */
#ifndef CPU_NATIVE_H
#define CPU_NATIVE_H
#include "cpu.h"

#define NATIVE_CYC_BOOT   16000u   /* reset: both boot stages */
#define NATIVE_CYC_MAIN   200u     /* one pass of the main loop */
#define NATIVE_CYC_TICK   4000u    /* timer interrupt */
#define NATIVE_CYC_AXIS   400u     /* axis board interrupt */
#define NATIVE_CYC_UART   200u     /* serial interrupt */
#define NATIVE_CYC_ESTOP  200u     /* emergency stop interrupt */
#define NATIVE_CYC_CLOCK  4u       /* each sim_now() during a firmware call */

extern const cpu_t cpu_native;

/* For mac4sim.c (weak there, so the 68000-only build links without them). */
const cpu_t *mac4sim_native_cpu(void);
int mac4sim_native_card(void);     /* MAC4_CARD the firmware was built for */

#endif
