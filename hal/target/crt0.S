/*
 * crt0.S - reset entry of the EPROM image.
 * The reset vectors are fetched through the boot overlay (EPROM mirrored at
 * $000000); _start runs from the real EPROM address, releases the overlay so
 * the DPRAM appears at $000000, and runs the boot stages of fw.h.
 */
#include "mac4_map.h"

    .section .text.start,"ax"
    .globl  _start
_start:
    move.w  #0x2700, %sr                /* supervisor, all interrupts masked */
    clr.w   SYS_CTRL                    /* release the boot overlay */
    lea     DPRAM_BOOT_STACK_TOP, %sp   /* stack in the DPRAM monitor area */
    jsr     fw_boot_stage1              /* $1, vectors, $2 RAM test */

    lea     __data_load, %a0            /* C runtime in the tested SRAM */
    lea     __data_start, %a1
    lea     __data_end, %a2
1:  cmpa.l  %a2, %a1
    bcc.s   2f
    move.w  (%a0)+, (%a1)+
    bra.s   1b
2:  lea     __bss_start, %a1
    lea     __bss_end, %a2
3:  cmpa.l  %a2, %a1
    bcc.s   4f
    clr.w   (%a1)+
    bra.s   3b
4:  lea     __stack_top, %sp
    jsr     fw_init                     /* $3 check sum ... $5 ready */
5:  jsr     fw_main_step
    bra.s   5b

    .section .note.GNU-stack,"",%progbits
