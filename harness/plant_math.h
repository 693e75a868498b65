/* plant_math.h - the arithmetic of the plant and the axis boards, without
 * libm (the unit and fuzz targets link the harness without it). */
#ifndef PLANT_MATH_H
#define PLANT_MATH_H
#include <stdint.h>

#define TWO_PI 6.283185307179586
#define PLANT_CPU_HZ 16000000.0

static inline double clampd(double x, double lo, double hi) { return x < lo ? lo : x > hi ? hi : x; }
static inline double fabs_(double x) { return x < 0 ? -x : x; }
static inline double floor_(double x)
{
    if (x >= 4.0e18 || x <= -4.0e18 || x != x)
        return x != x ? 0.0 : x;
    double d = (double)(int64_t)x;
    return d > x ? d - 1.0 : d;
}
static inline double ceil_(double x) { return -floor_(-x); }
static inline int64_t ifloor(double x) { return (int64_t)clampd(floor_(x), -4.0e18, 4.0e18); }
static inline int64_t iround(double x) { return ifloor(x + 0.5); }
static inline double sgn(double x) { return (x > 0) - (x < 0); }

#endif
