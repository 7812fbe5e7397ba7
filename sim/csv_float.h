/* sim/csv_float.h - CSV output of 32-bit floats in the shortest decimal form that strtof reads
 * back to the same float (16.199999, not 16.199998855590820), the float counterpart of csv_num
 * for values computed in float as on the Mega (pid-replay --float, servo in float). */
#ifndef MOTIONSIM_CSV_FLOAT_H
#define MOTIONSIM_CSV_FLOAT_H

#include <stdio.h>

void csv_num_f32(FILE *f, float v);

#endif
