/* measure.h - position measurement (manual 4.4, table 4.3). */
#ifndef MEASURE_H
#define MEASURE_H
#include <stdint.h>

void measure_axis(unsigned n);     /* read and process one axis */
void measure_init(unsigned n);     /* INIT: derive <ea>/<eb>/<ec>, zero relative position */
/* May an external position (<et> 3/4) be read at <ea> with <eb> significant
 * bits (eb 0: not known yet)?  The rule of docs/interpretations.md. */
int measure_ea_ok(uint32_t ea, int32_t eb);

#endif
