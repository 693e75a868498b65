/*
 * vectors.S - the 68000 exception vector table (at EPROM offset 0, copied
 * to the DPRAM at $0000 by hal_copy_vectors) and the interrupt entry stubs.
 * Every vector without a handler gets its own 8-byte stub that pushes its
 * vector number (the 68000 stacks none) and enters fw_fault: an unexpected
 * exception is recorded and shown as "F.", never a silent hang.
 */
#include "mac4_map.h"

    .section .vectors,"ax"
    .globl  _vectors
_vectors:
    .set    vnum, 0
    .rept   256
    .if     vnum == 0
    .long   DPRAM_BOOT_STACK_TOP        /* initial SSP: DPRAM monitor area */
    .elseif vnum == 1
    .long   _start                      /* initial PC */
    .elseif vnum == 24 + IRQ_LEVEL_UART
    .long   fw_isr_uart                 /* HAL_ISR: saves what it uses, ends in RTE */
    .elseif vnum == 24 + IRQ_LEVEL_AXIS
    .long   fw_isr_axis                 /* HAL_ISR */
    .elseif vnum == 24 + IRQ_LEVEL_TIMER
    .long   fw_isr_tick                 /* HAL_ISR; INC/SSI: tick_select may put fw_isr_tick_general here */
    .elseif vnum == 24 + IRQ_LEVEL_ESTOP
    .long   _isr_estop
    .else
    .long   _fault_stubs + 8 * vnum
    .endif
    .set    vnum, vnum + 1
    .endr

/* The tick bodies the timer's vector may enter (hal_set_tick_vector): the
 * servo cards' general one is weak, 0 on the STP, which has one body. */
    .section .rodata
    .globl  _tick_vectors
    .weak   fw_isr_tick_general
    .align  2
    .type   _tick_vectors, @object
    .size   _tick_vectors, 8
_tick_vectors:
    .long   fw_isr_tick
    .long   fw_isr_tick_general

    .text
/* Interrupt entries: save the registers the C ABI lets a callee clobber. */
    .macro  isr name, handler
    .globl  \name
\name:
    movem.l %d0-%d1/%a0-%a1, -(%sp)
    jsr     \handler
    movem.l (%sp)+, %d0-%d1/%a0-%a1
    rte
    .endm

    isr     _isr_estop, fw_isr_estop

    .globl  _fault_stubs
_fault_stubs:
    .set    vnum, 0
    .rept   256
    move.w  #vnum, -(%sp)               /* 4 bytes */
    bra.w   _fault_common               /* 4 bytes */
    .set    vnum, vnum + 1
    .endr

/* Stack: vector.w, then the exception frame.  Bus and address errors (2, 3)
 * stack the long group-0 frame: fc.w, address.l, ir.w, sr.w, pc.l. */
_fault_common:
    ori.w   #0x0700, %sr
    moveq   #0, %d0
    move.w  (%sp), %d0
    moveq   #0, %d1
    cmp.w   #2, %d0
    beq.s   1f
    cmp.w   #3, %d0
    beq.s   1f
    moveq   #0, %d2
    move.w  2(%sp), %d1                 /* sr */
    move.l  4(%sp), %a0                 /* pc */
    bra.s   2f
1:  move.l  4(%sp), %d2                 /* access address */
    move.w  10(%sp), %d1                /* sr */
    move.l  12(%sp), %a0                /* pc */
2:  move.l  %d2, -(%sp)                 /* fw_fault(vector, pc, sr, addr) */
    move.l  %d1, -(%sp)
    move.l  %a0, -(%sp)
    move.l  %d0, -(%sp)
    jsr     fw_fault
3:  bra.s   3b                          /* fw_fault does not return */

    .section .note.GNU-stack,"",%progbits
