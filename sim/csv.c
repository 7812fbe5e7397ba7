/* sim/csv.c - shortest round-trip number formatting for CSV output (see csv.h). */
#include "csv.h"

#include <math.h>
#include <stdlib.h>

void csv_num(FILE *f, double v)
{
    char buf[40];
    int prec;
    if (v == 0.0) { /* also turns -0 into 0 */
        fputs("0", f);
        return;
    }
    if (v == floor(v) && fabs(v) < 1e15) {
        fprintf(f, "%.0f", v);
        return;
    }
    for (prec = 1; prec <= 17; prec++) {
        snprintf(buf, sizeof buf, "%.*g", prec, v);
        if (strtod(buf, NULL) == v)
            break;
    }
    fputs(buf, f);
}

void csv_row(FILE *f, const double *values, int n)
{
    int i;
    for (i = 0; i < n; i++) {
        if (i > 0)
            fputc(',', f);
        csv_num(f, values[i]);
    }
    fputc('\n', f);
}
