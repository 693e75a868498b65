/*
 * inline.h - FW_INLINE, the one way the firmware asks for a function's body
 * at its call site.  A hot path is written once and inlined with constant
 * arguments: the tick's and the supervision's four axes then address their
 * registers and state as constants (docs/firmware.md).  Everything else is
 * left to the compiler's -Os.
 */
#ifndef INLINE_H
#define INLINE_H
#define FW_INLINE static inline __attribute__((always_inline))
#endif
