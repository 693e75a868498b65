/* bus_map.h - GENERATED from board/mac4.toml by tools/genboard.py: do not edit.
 * The rows of the emulator's bus table (harness/bus.c): base, size, name,
 * the device that answers and which of its register windows, word-wide I/O
 * (no byte writes). */
{DPRAM_BASE, DPRAM_SIZE, "dpram", &dpram_device, 0, 0},
{EPROM_BASE, EPROM_SIZE, "eprom", &eprom_device, 0, 0},
{SRAM_BASE, SRAM_SIZE, "sram", &sram_device, 0, 0},
{VME_WIN_BASE, VME_WIN_SIZE, "vme", &vme_device, 1, 0},
{IO_BASE + 0x000, 0x10, "sys", &sys_device, 0, 1},
{IO_BASE + 0x100, 0x10, "timer", &tmr_device, 0, 1},
{IO_BASE + 0x200, 0x10, "uart", &uart_device, 0, 1},
{IO_BASE + 0x300, 0x10, "virq", &vme_device, 0, 1},
{IO_BASE + 0x400, 0x02, "watchdog", &wdg_device, 0, 1},
{AXIS_BASE, MAC4_NAXES * AXIS_STRIDE, "axis", &axisboard_device, 0, 1},
{AXIS_IRQ_PENDING, 0x02, "axis-irq", &axisboard_device, 1, 1},
