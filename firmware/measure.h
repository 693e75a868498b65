/* measure.h - position measurement (manual 4.4, table 4.3). */
#ifndef MEASURE_H
#define MEASURE_H

void measure_axis(unsigned n);     /* read and process one axis */
void measure_init(unsigned n);     /* INIT: derive <ea>/<eb>/<ec>, zero relative position */

#endif
