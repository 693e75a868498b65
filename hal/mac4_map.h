/*
 * mac4_map.h - GENERATED from board/mac4.toml by tools/genboard.py: do not edit;
 * change the description and run `make board` (docs/board.md).
 *
 * the local address map of the IPC processor card and the MAC4 axis
 * interface boards.
 *
 * Used by the firmware (through hal/), by hal/target and hal/native, and by
 * the emulator in harness/.  docs/memory-map.md explains every entry.  The
 * IPC schematic is not in the manual, so the decoding of the I/O space is
 * our design (docs/board.md); the DPRAM layout from $3000 on is the
 * manual's table 3.1 exactly.
 *
 * All I/O registers are 16 bits wide on even addresses (the IPC is a D16
 * card): access them with word moves only.
 */
#ifndef MAC4_MAP_H
#define MAC4_MAP_H

#ifdef __ASSEMBLER__
#define MAC4_U(x) x
#else
#define MAC4_U(x) x##UL
#endif

/* ---- clock ----------------------------------------------------------------- */
#define MAC4_CPU_HZ                    MAC4_U(16000000) /* 68000 at 16 MHz (manual 7.4) */
#define MAC4_CYCLES_PER_US             MAC4_U(16)

/* ---- card types (VER bits 24-31, manual table 6.1) ------------------------- */
#define MAC4_CARD_INC                  0
#define MAC4_CARD_SSI                  1
#define MAC4_CARD_STP                  2
#define MAC4_NAXES                     4

/* ---- DPRAM: 64 KiB, local view at $000000 ---------------------------------- */
/* $0000-$03FF exception vectors (copied from EPROM by crt0),
 * $0400-$2FFF monitor area: the boot stack lives at its top (manual 3.1).
 */
#define DPRAM_BASE                     MAC4_U(0x000000)
#define DPRAM_SIZE                     MAC4_U(0x10000)
#define DPRAM_VECTORS                  MAC4_U(0x0000)
#define DPRAM_MONITOR                  MAC4_U(0x0400)
#define DPRAM_BOOT_STACK_TOP           MAC4_U(0x3000)
/* Host-visible area, offsets as in manual table 3.1. */
#define DP_HOST_AREA                   MAC4_U(0x3000)
#define DP_AXIS_STRIDE                 MAC4_U(0x0400) /* axis n at $3000 + n*$400 */
#define DP_AXIS_DATA(n)                (MAC4_U(0x3000) + (n) * DP_AXIS_STRIDE)
#define DP_EXT_FLAG(n)                 (DP_AXIS_DATA(n) + MAC4_U(0x308)) /* interlock, bit 15 */
#define DP_EXT_POS(n)                  (DP_AXIS_DATA(n) + MAC4_U(0x30A)) /* 32-bit position */
/* Axis data the card publishes every tick at DP_AXIS_DATA(n) + (32-bit words): */
#define DPA_USTAT                      0x00 /* user status (RBS) */
#define DPA_SSTAT                      0x04 /* system status (RSS) */
#define DPA_POS                        0x08 /* actual position (RCP) */
#define DPA_SETPOINT                   0x0C /* position setpoint */
#define DPA_FERR                       0x10 /* following error (RFE) */
#define DPA_OUT                        0x14 /* output: DAC word or step rate (ROUT) */
#define DPA_VEL                        0x18 /* actual velocity per servo period (RAV) */
#define DPA_RAW                        0x1C /* raw measurement (RED) */
#define DP_CARD_DATA                   MAC4_U(0x4000) /* "internal axis data 1-4" */
#define DP_STOP_BITS                   MAC4_U(0x4600) /* bits 1,3,5,7: stop axis 1-4 */
#define DP_CMD_QUEUE                   MAC4_U(0x4700) /* command queue header */
#define DP_RSP_QUEUE                   MAC4_U(0x4800) /* response (output) queue */
#define DP_HOST_END                    MAC4_U(0xFFEE) /* last byte the manual uses */
#define DP_MAILBOX                     MAC4_U(0xFFFE) /* DPRAM interrupt mailbox (unused) */

/* Card data block at $4000 (our layout inside "internal axis data 1-4").
 * Each entry is a 32-bit big-endian word the host may read at any time.
 */
#define DPC_BOOT_STATE                 (DP_CARD_DATA + 0x00) /* last display value, $5 = ready */
#define DPC_BOOT_ERROR                 (DP_CARD_DATA + 0x04) /* 0, or error code DPC_ERR_* */
#define DPC_CRC_EXPECTED               (DP_CARD_DATA + 0x08) /* EPROM checksum stored by the build */
#define DPC_CRC_COMPUTED               (DP_CARD_DATA + 0x0C) /* EPROM checksum computed at boot */
#define DPC_FAULT_VECTOR               (DP_CARD_DATA + 0x10) /* unexpected exception: vector number */
#define DPC_FAULT_PC                   (DP_CARD_DATA + 0x14) /* ... its stacked PC */
#define DPC_FAULT_SR                   (DP_CARD_DATA + 0x18) /* ... its stacked SR */
#define DPC_FAULT_ADDR                 (DP_CARD_DATA + 0x1C) /* ... access address (bus/address error) */
#define DPC_RSP_LOST                   (DP_CARD_DATA + 0x20) /* responses lost, output queue full (4.6) */
#define DPC_QUEUE_ERRORS               (DP_CARD_DATA + 0x24) /* corrupt queue headers seen */
#define DPC_TICKS                      (DP_CARD_DATA + 0x28) /* servo ticks since reset */
#define DPC_VERSION                    (DP_CARD_DATA + 0x2C) /* VER word (table 6.1) */
#define DPC_RAM_BAD_ADDR               (DP_CARD_DATA + 0x30) /* first failing RAM address */
/* Serial line statistics (firmware/serial.c, docs/serial.md), counted since reset. */
#define DPC_SERIAL_RX_OK               (DP_CARD_DATA + 0x40) /* valid telegrams taken as commands */
#define DPC_SERIAL_NAKS                (DP_CARD_DATA + 0x44) /* NAKs the card sent (every cause) */
#define DPC_SERIAL_GARBAGE             (DP_CARD_DATA + 0x48) /* bytes outside any telegram, discarded */
#define DPC_SERIAL_OVERRUNS            (DP_CARD_DATA + 0x4C) /* received bytes lost: UART overrun or RX buffer full */
#define DPC_SERIAL_FRAMING             (DP_CARD_DATA + 0x50) /* characters with a framing error */
#define DPC_SERIAL_CMD_LOST            (DP_CARD_DATA + 0x54) /* valid telegrams refused (NAK): command FIFO full */
#define DPC_SERIAL_TX_OK               (DP_CARD_DATA + 0x58) /* response telegrams queued for sending */
#define DPC_SERIAL_TX_LOST             (DP_CARD_DATA + 0x5C) /* responses or NAKs dropped: TX buffer full */
#define DPC_PROFILE_LATE               (DP_CARD_DATA + 0x60) /* SP boundaries the profile generator missed */
#define DPC_SUPERVISE_LATE             (DP_CARD_DATA + 0x64) /* ticks the main loop supervised late */
/* The fault record (vector, PC, SR, access address at $4010-$401C) and its
 * count survive a watchdog reset (SYS_ST_WDG_RESET): after a fault the card
 * restarts when J11 is in, and the host reads why (docs/interpretations.md).
 */
#define DPC_FAULT_COUNT                (DP_CARD_DATA + 0x68) /* unexpected exceptions since power-on */
#define DPC_OSTAT                      (DP_CARD_DATA + 0x34) /* overall status (RAS) */
#define DPC_VME_IRQ_LOST               (DP_CARD_DATA + 0x38) /* VMEbus interrupts dropped (FIFO full) */
#define DPC_COMMANDS                   (DP_CARD_DATA + 0x3C) /* commands executed since reset */

#define DPC_ERR_NONE                   0
#define DPC_ERR_RAM                    2 /* shown as "2." */
#define DPC_ERR_CHECKSUM               3 /* shown as "3." */
#define DPC_ERR_EXCEPTION              15 /* shown as "F." */

/* Queue header, manual table 7.1: six 32-bit words, elements from +$18. */
#define QH_BASE                        0x00
#define QH_FRONT                       0x04 /* write index (set by enqueue) */
#define QH_REAR                        0x08 /* read index (set by dequeue) */
#define QH_FREE                        0x0C
#define QH_WIDTH                       0x10
#define QH_NEL                         0x14
#define Q_HEADER_SIZE                  0x18
#define Q_WIDTH                        10
#define Q_NEL                          10
/* Message layout, manual 3.4 / diagram 3.6-3.7. */
#define MSG_AXIS                       0
#define MSG_CODE                       2 /* 16 bits, big-endian */
#define MSG_PARAM                      4 /* 32 bits, big-endian */
#define MSG_SOURCE                     8 /* 0 VMEbus, 1 serial */
#define MSG_SRC_VME                    0
#define MSG_SRC_SERIAL                 1

/* ---- EPROM: 64 KiB, local $100000 ------------------------------------------ */
/* Two 27C256 (32 KiB x 8): even bytes on D8-D15, odd bytes on D0-D7
 * (tools/mkeprom.py).  Mirrored at $000000 for reads while SYS_CTRL_OVERLAY
 * is set (after every reset) so the 68000 can fetch its reset vectors.  The
 * last four bytes hold the CRC written by the build.
 */
#define EPROM_BASE                     MAC4_U(0x100000)
#define EPROM_SIZE                     MAC4_U(0x10000)
#define EPROM_CRC_OFFSET               MAC4_U(0xFFFC) /* CRC-16 word, then its complement */

/* ---- local SRAM: 32 KiB ---------------------------------------------------- */
#define SRAM_BASE                      MAC4_U(0x200000)
#define SRAM_SIZE                      MAC4_U(0x8000)

/* ---- VMEbus master window: 1 MiB of A24 space, page selects A23-A20 -------- */
#define VME_WIN_BASE                   MAC4_U(0xE00000)
#define VME_WIN_SIZE                   MAC4_U(0x100000)

/* ---- I/O space ------------------------------------------------------------- */
#define IO_BASE                        MAC4_U(0xF00000)

/* System control */
#define SYS_DISPLAY                    (IO_BASE + 0x000) /* W: bits 0-3 digit, bit 4 DP */
#define SYS_DISPLAY_DP                 0x10
#define SYS_LEDS                       (IO_BASE + 0x002) /* W: per axis n bits 4n.. (LED_*) */
#define SYS_LED_D                      0x1 /* axis disabled */
#define SYS_LED_P                      0x2 /* target position reached */
#define SYS_LED_F                      0x4 /* fault (STP) */
#define SYS_LED_SHIFT(n)               (4 * (n))
#define SYS_CTRL                       (IO_BASE + 0x004) /* RW */
#define SYS_CTRL_OVERLAY               0x0001 /* EPROM mirrored at 0; write 0 to release */
#define SYS_STATUS                     (IO_BASE + 0x006) /* R */
#define SYS_ST_STOP                    0x0001 /* /STOP emergency stop active */
#define SYS_ST_FC0                     0x0002
#define SYS_ST_FC1                     0x0004
#define SYS_ST_FC2                     0x0008
#define SYS_ST_FC_SHIFT                1
#define SYS_ST_J11                     0x0010 /* watchdog reset jumper J11 in (2.1.3) */
#define SYS_ST_WDG_RESET               0x0020 /* the last reset came from the watchdog */
#define SYS_ST_LEVEL_SHIFT             8 /* bits 8-10: VME IRQ level (LB1/LB2, table 2.1) */
#define SYS_ST_LEVEL_MASK              0x0700
#define SYS_BOARD_ID                   (IO_BASE + 0x008) /* R: axis board type, MAC4_CARD_* */

/* Periodic timer: level 6 autovector */
#define TMR_PERIOD                     (IO_BASE + 0x100) /* RW: period in us */
#define TMR_CTRL                       (IO_BASE + 0x102) /* RW */
#define TMR_CTRL_RUN                   0x0001
#define TMR_CTRL_IE                    0x0002
#define TMR_CTRL_SSI_WAIT              0x0004 /* SSI: the interrupt of an expiry waits until the SSI reads it
                                       * started (AX_CTRL_SSI_SYNC) are done: no polling in the tick */
#define TMR_STATUS                     (IO_BASE + 0x104) /* R: bit 0 expired; W 1 to acknowledge */
#define TMR_ST_EXPIRED                 0x0001
#define TMR_FREE_HI                    (IO_BASE + 0x108) /* R: free-running us counter, high word */
#define TMR_FREE_LO                    (IO_BASE + 0x10A) /* R: low word (latched by reading high) */

/* Serial UART (front panel, 4800 8N1, manual 3.3): level 4 autovector */
#define UART_DATA                      (IO_BASE + 0x200) /* R: received byte; W: byte to send */
#define UART_STATUS                    (IO_BASE + 0x202) /* R */
#define UART_ST_RXRDY                  0x0001
#define UART_ST_TXEMPTY                0x0002
#define UART_ST_OVERRUN                0x0004 /* cleared by reading UART_STATUS */
#define UART_ST_FRAMING                0x0008
#define UART_CTRL                      (IO_BASE + 0x204) /* RW */
#define UART_CTRL_RXIE                 0x0001
#define UART_CTRL_TXIE                 0x0002
#define UART_BAUD                      MAC4_U(4800)

/* VMEbus interrupter and master window page */
#define VIRQ_VECTOR                    (IO_BASE + 0x300) /* W: raise VME IRQ with this vector */
#define VIRQ_STATUS                    (IO_BASE + 0x302) /* R: bit 0 pending until host IACK */
#define VIRQ_ST_PENDING                0x0001
#define VME_PAGE                       (IO_BASE + 0x304) /* W: bits 0-3 = A23-A20 of the window */
#define VME_STATUS                     (IO_BASE + 0x306) /* R: bit 0 bus timeout since last read */
#define VME_ST_BERR                    0x0001

/* Hardware watchdog (2.1.3): resets the card when not retriggered for
 * WDG_TIMEOUT_US and jumper J11 is in.  MR stops retriggering it.
 */
#define WDG_KICK                       (IO_BASE + 0x400) /* W: any value retriggers */
#define WDG_TIMEOUT_US                 MAC4_U(100000)

/* Axis interface board: one block per axis */
#define AXIS_BASE                      (IO_BASE + 0x1000)
#define AXIS_STRIDE                    0x100
#define AX_REG(n, off)                 (AXIS_BASE + (n) * AXIS_STRIDE + (off))
#define AX_CNT_HI                      0x00 /* R: 24-bit position counter bits 16-23 (latches LO) */
#define AX_CNT_LO                      0x02 /* R: bits 0-15 */
#define AX_IDX_HI                      0x04 /* R: index latch bits 16-23 */
#define AX_IDX_LO                      0x06
#define AX_IN                          0x08 /* R: inputs, 1 = signal at 0 V (LED lit) */
#define AX_IN_IESP                     0x0001
#define AX_IN_IESN                     0x0002
#define AX_IN_RS                       0x0004
#define AX_IN_DF                       0x0008
#define AX_IN_IDX                      0x0010 /* index latched since last re-arm */
#define AX_IN_GRAY                     0x0020 /* SSI: J1 open, encoder is Gray coded */
#define AX_IN_SSI_BUSY                 0x0040
#define AX_IN_PULSE                    0x0080 /* STP: step-pulse interrupt pending */
#define AX_IN_BR_STEPS                 0x0100 /* STP: BR closed, counter counts steps */
#define AX_IN_PDONE                    0x0200 /* STP: the pulse down-counter reached 0 */
#define AX_IN_PULSE_OVR                0x0400 /* STP: a pulse came while AX_IN_PULSE was pending */
#define AX_CTRL                        0x0A /* RW */
#define AX_CTRL_EN                     0x0001 /* drive /EN low: axis enabled */
#define AX_CTRL_IDX_IE                 0x0002
#define AX_CTRL_IDX_ARM                0x0004 /* W 1: clear and re-arm index latch */
#define AX_CTRL_CNT_CLR                0x0008 /* W 1: clear position counter */
#define AX_CTRL_DIR                    0x0010 /* STP: 1 drives DIR to 0 V = positive; 0 (reset)
                                       * leaves it open collector = negative (table 2.12) */
#define AX_CTRL_BOOST                  0x0020 /* STP: 1 = BOOST output on (increased torque) */
#define AX_CTRL_TURBO                  0x0040 /* STP: step clock x10 (table 4.1) */
#define AX_CTRL_PULSE_IE               0x0080 /* STP: AX_IN_PULSE set by every output pulse, level 5 */
#define AX_CTRL_PULSE_ACK              0x0100 /* STP, W 1: clear AX_IN_PULSE and AX_IN_PULSE_OVR */
#define AX_CTRL_DONE_IE                0x0200 /* STP: interrupt when the pulse down-counter ends */
#define AX_CTRL_DONE_ACK               0x0400 /* STP, W 1: clear AX_IN_PDONE */
#define AX_CTRL_SSI_SYNC               0x0800 /* SSI: start a read at every expiry of the timer,
                                       * the sampling instant of the tick */
#define AX_DAC                         0x0C /* W: INC/SSI, signed 12 bit, -2048..2047 = -10..+10 V */
#define AX_RATE                        0x0C /* W: STP, 16-bit step rate */
#define AX_SSI_START                   0x0E /* W: start a 26-clock SSI read */
#define AX_SSI_HI                      0x10 /* R: SSI shift register bits 16-25 */
#define AX_SSI_LO                      0x12
/* The 26 received bits enter the shift register MSB first from bit 0
 * upwards, so after a read an N-bit encoder word sits left-aligned: its MSB
 * in bit 25, its LSB in bit 26-N, zeros below (the data line is low after
 * the LSB).  The firmware shifts right by <sc> = 26 - N (diagram 4.5).
 * While AX_IN_SSI_BUSY the register shows the bits shifted in so far.
 */
#define SSI_CLOCKS                     26
#define AX_PULSES                      0x14 /* RW: STP pulse down-counter: W n>0 emit exactly n more
                                      * pulses then stop (AX_IN_PDONE), W 0 free running;
                                      * R pulses still to come */
#define AX_CNT_LIVE                    0x16 /* R: counter bits 0-15, live (no latch): the tick's
                                      * 16-bit delta per servo period */

#define AXIS_IRQ_PENDING               (AXIS_BASE + 0x800) /* R: bit n index, bit 4+n pulse,
                                                    * bit 8+n pulse count done */
#define AXIS_IRQ_IDX(n)                (1u << (n))
#define AXIS_IRQ_PULSE(n)              (0x10u << (n))
#define AXIS_IRQ_DONE(n)               (0x100u << (n))

/* Step generator (STP, manual table 4.1): a 16-bit phase accumulator adds
 * AX_RATE at STP_CLK_HZ (x10 with TURBO) and emits a pulse at each carry,
 * so f = rate * STP_CLK_HZ / 65536 = rate * 0.7629 Hz (TURBO 7.629 Hz).
 */
#define STP_CLK_HZ                     MAC4_U(50000)
#define STP_CLK_HZ_TURBO               MAC4_U(500000)
#define STP_PULSE_US                   10 /* output pulse length, TURBO: 1 us */
#define STP_PULSE_US_TURBO             1

#define DAC_MIN                        (-2048)
#define DAC_MAX                        2047

/* ---- bus timing: what each access costs (docs/memory-map.md, "Bus timing") --- */
/* A 68000 bus cycle is 4 clocks with no wait state; every wait state adds
 * one clock.  Per window of the local map and per access kind, the wait
 * states the card's DTACK logic inserts (each window's wait above): defaults
 * chosen from the parts a 16 MHz card of 1993 would carry (docs/memory-map.md
 * says which and why); the manual gives none.  The emulator charges them per
 * bus cycle (a long access is two; harness/buswait.c) and takes others with
 * --wait-states.  MAC4_BUS_TIMING(X) lists X(name, base, size, read, write).
 */
/* A VME host's access to a DPRAM word holds that word for this many clocks
 * (its slave cycle, strobe to DTACK); the card's access to the same word in
 * that time waits for the rest of it (the dual-port parts' BUSY).
 */
#define MAC4_DPRAM_HOST_CLOCKS         6
/* The interrupt acknowledge: Musashi's 44-cycle interrupt assumes a 4-clock
 * IACK cycle.  Autovectored (the card's way, through VPA) it is a M6800
 * cycle synchronised to E (CLK/10, 6 clocks low, 4 high): 10 clocks when E
 * is in phase, 19 at worst; the model charges the worst, so every figure
 * bounds the card's.  Vectored, it is a 4-clock cycle with the
 * interrupter's wait states.
 */
#define MAC4_IACK_AUTOVECTOR_CLOCKS    19
#define MAC4_IACK_VECTORED_WAIT        2
/* The bus timer: a bus cycle no device acknowledges (no DTACK: an address outside
 * every window above, a write to the EPROM, a byte write to a word-wide I/O register) ends
 * with /BERR this many clocks after its start, and the 68000 takes a bus error (docs/board.md,
 * "Bus errors").  Well above the slowest cycle a device answers (the VMEbus window's 16 clocks,
 * plus a DPRAM word the host holds).
 */
#define MAC4_BUS_TIMEOUT_CLOCKS        64
#define MAC4_BUS_TIMING(X) \
    X("dpram",    DPRAM_BASE,           DPRAM_SIZE,                   1,   1) \
    X("eprom",    EPROM_BASE,           EPROM_SIZE,                   1,   1) \
    X("sram",     SRAM_BASE,            SRAM_SIZE,                    0,   0) \
    X("vme",      VME_WIN_BASE,         VME_WIN_SIZE,                12,  12) \
    X("sys",      IO_BASE + 0x000,      0x10,                         2,   2) \
    X("timer",    IO_BASE + 0x100,      0x10,                         2,   2) \
    X("uart",     IO_BASE + 0x200,      0x10,                         2,   2) \
    X("virq",     IO_BASE + 0x300,      0x10,                         2,   2) \
    X("watchdog", IO_BASE + 0x400,      0x02,                         2,   2) \
    X("axis",     AXIS_BASE,            MAC4_NAXES * AXIS_STRIDE,     3,   3) \
    X("axis-irq", AXIS_IRQ_PENDING,     0x02,                         3,   3)

/* ---- interrupt levels (autovectored) --------------------------------------- */
#define IRQ_LEVEL_ESTOP                7 /* /STOP, non-maskable */
#define IRQ_LEVEL_TIMER                6
#define IRQ_LEVEL_AXIS                 5
#define IRQ_LEVEL_UART                 4

/* ---- timing (manual 7.4) --------------------------------------------------- */
#define SERVO_PERIOD_US_SERVO          2500u /* INC/SSI controller 2.5 ms */
#define SERVO_PERIOD_US_STP            8000u /* STP controller 8 ms */
#define PROFILE_DIVIDER                4u /* profile generator every 4th tick */

#endif /* MAC4_MAP_H */
