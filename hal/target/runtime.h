#ifndef RUNTIME_H
#define RUNTIME_H
#include <stdint.h>
uint32_t rt_mul32(uint32_t a, uint32_t b);
uint32_t rt_udivmod32(uint32_t n, uint32_t d, uint32_t *rem);
int32_t rt_div32(int32_t n, int32_t d);
int32_t rt_mod32(int32_t n, int32_t d);
uint64_t rt_lshr64(uint64_t a, unsigned b);
uint64_t rt_shl64(uint64_t a, unsigned b);
int64_t rt_ashr64(int64_t a, unsigned b);
#endif
