/* sim/csv.h - CSV output helpers for motionsim.
 *
 * Numbers are written in the shortest decimal form that reads back to the same double
 * (so a CSV holds the exact values the simulation computed, yet stays readable: 0.1, not
 * 0.10000000000000001). Integers are written as integers.
 */
#ifndef MOTIONSIM_CSV_H
#define MOTIONSIM_CSV_H

#include <stdio.h>

/* Writes v in shortest round-trip form (no trailing separator). */
void csv_num(FILE *f, double v);

/* Writes n numbers separated by commas and ends the line. */
void csv_row(FILE *f, const double *values, int n);

#endif
