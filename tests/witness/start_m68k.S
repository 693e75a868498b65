/* start_m68k.S - process entry of the 68000 witness (Linux: sp -> argc). */
    .text
    .globl  _start
_start:
    jsr     w_start
1:  bra.s   1b
