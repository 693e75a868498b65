/* bus_map.h - GENERATED from board/mac4.toml by tools/genboard.py: do not edit.
 * The rows of the emulator's bus table (harness/bus.c): base, size, name,
 * read and write functions, word-wide I/O (no byte writes). */
{DPRAM_BASE, DPRAM_SIZE, "dpram", dpram_rd, dpram_wr, 0},
{EPROM_BASE, EPROM_SIZE, "eprom", eprom_rd, eprom_wr, 0},
{SRAM_BASE, SRAM_SIZE, "sram", sram_rd, sram_wr, 0},
{VME_WIN_BASE, VME_WIN_SIZE, "vme", vme_win_rd, vme_win_wr, 0},
{IO_BASE + 0x000, 0x10, "sys", sys_rd, sys_wr, 1},
{IO_BASE + 0x100, 0x10, "timer", tmr_rd, tmr_wr, 1},
{IO_BASE + 0x200, 0x10, "uart", uart_rd, uart_wr, 1},
{IO_BASE + 0x300, 0x10, "virq", virq_rd, virq_wr, 1},
{IO_BASE + 0x400, 0x02, "watchdog", wdg_rd, wdg_wr, 1},
{AXIS_BASE, MAC4_NAXES * AXIS_STRIDE, "axis", axis_rd, axis_wr, 1},
{AXIS_IRQ_PENDING, 0x02, "axis-irq", axis_irq_rd, axis_irq_wr, 1},
