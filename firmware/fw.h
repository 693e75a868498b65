/*
 * fw.h - the firmware's entry points.  On the 68000 crt0 and the vector
 * stubs in hal/target call them; in the native build the emulator's
 * scheduler calls them directly (harness/cpu_native.c).
 */
#ifndef FW_H
#define FW_H
#include <stdint.h>

#ifndef MAC4_CARD
#error "MAC4_CARD must be defined (0 INC, 1 SSI, 2 STP)"
#endif

/* Reset, stage 1: display $1, vectors, display $2 and the RAM test.
 * Uses no static data (runs before .data/.bss exist).  Returns 0, or stops
 * the card with "2." on a RAM fault. */
int fw_boot_stage1(void);
/* Reset, stage 2: display $3 EPROM check sum, defaults, queues, banner,
 * display $5, timers and interrupts on. */
void fw_init(void);
/* One pass of the main loop: watchdog, serial, command queue. */
void fw_main_step(void);
/* Interrupt sources. */
void fw_isr_tick(void);     /* periodic timer, level 6 */
void fw_isr_tick_general(void);   /* INC/SSI: the same with the general filter (tick_select) */
void fw_isr_axis(void);     /* axis board (index, step pulses), level 5 */
void fw_isr_uart(void);     /* serial line, level 4 */
void fw_isr_estop(void);    /* /STOP, level 7 */
/* An unexpected exception: record it in the DPRAM (kept across the
 * watchdog's reset), show "F." and stop retriggering the watchdog: with J11
 * in it restarts the card, with J11 out "F." stays. */
void fw_fault(uint16_t vector, uint32_t pc, uint16_t sr, uint32_t addr) __attribute__((noreturn));
/* Stop the card showing digit d with the decimal point (error at step d). */
void fw_halt(unsigned digit, uint32_t code) __attribute__((noreturn));
/* The same, but leave the card to the hardware watchdog (2.1.3). */
void fw_halt_for_watchdog(unsigned digit, uint32_t code) __attribute__((noreturn));

/* Firmware version (VER, manual table 6.1): the manual's releases. */
#if MAC4_CARD == 2
#define FW_VERSION 2
#define FW_RELEASE 2
#define HW_RELEASE 'A'
#elif MAC4_CARD == 1
#define FW_VERSION 4
#define FW_RELEASE 2
#define HW_RELEASE 'A'
#else
#define FW_VERSION 4
#define FW_RELEASE 2
#define HW_RELEASE 'D'
#endif
#define FW_VER_WORD (((uint32_t)MAC4_CARD << 24) | ((uint32_t)HW_RELEASE << 16) | \
                     ((uint32_t)FW_VERSION << 8) | (uint32_t)FW_RELEASE)

#define FW_BANNER "MACCON \xA9" "1993"  /* manual 4: host waits for it at $4818 */

#endif
