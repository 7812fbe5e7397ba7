/* sim/csv_float.c - shortest round-trip float formatting (see csv_float.h). */
#include "csv_float.h"

#include <math.h>
#include <stdlib.h>

void csv_num_f32(FILE *f, float v)
{
    char buf[48];
    int prec;
    if (v == 0.0f) {
        fputs(signbit(v) ? "-0" : "0", f);
        return;
    }
    if (v == floorf(v) && fabsf(v) < 1e7f) {
        fprintf(f, "%.0f", (double)v);
        return;
    }
    for (prec = 1; prec <= 9; prec++) {
        snprintf(buf, sizeof buf, "%.*g", prec, (double)v);
        if (strtof(buf, NULL) == v)
            break;
    }
    fputs(buf, f);
}
