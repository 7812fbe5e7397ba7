/* sim/csv_read.h - the one CSV reader of motionsim (`filter --input csv:FILE`, the `pid-replay`
 * vectors): plain comma-separated fields, no quoting, read one line at a time.
 *
 * What C strings cannot hold is refused, not misread: a line with a NUL byte is an error (with
 * getline and string functions, "2\09" would read as 2 and "\09" as a blank line). The line end
 * ("\n" or "\r\n") is removed; with `trim` set, blanks (spaces, tabs) around each field are too
 * (and a carriage return at its end).
 * A header that names a column twice is found by csv_duplicate_column (which of the two holds the
 * data would be a guess). The callers word their messages (file name, line number: r->lineno).
 * Also valid C++ (the MotionPID unit test compiles pid_vector.c, which uses it, as C++).
 */
#ifndef MOTIONSIM_CSV_READ_H
#define MOTIONSIM_CSV_READ_H

#include <stddef.h>
#include <stdio.h>

typedef struct {
    FILE *f;
    int trim;             /* remove blanks around fields */
    unsigned long lineno; /* of the line last read, from 1 */
    char *line;           /* the line last read, cut into the fields (NULs at the commas) */
    size_t len;           /* its length before cutting, without the line end */
    size_t cap;
    char **fields;        /* n_fields pointers into line */
    size_t n_fields;
    size_t fields_cap;
} csv_reader_t;

/* Opens path; 0, or -1 with errno set (the file cannot be read). */
int csv_open(csv_reader_t *r, const char *path, int trim);

/* Reads the next line and splits it: 1 with r->fields set (a blank line is one empty field, see
 * csv_blank), 0 at the end of the file, -1 on an error with its text in *why ("contains a NUL byte
 * (not a text file)", "read error", "out of memory") for the line r->lineno. */
int csv_next(csv_reader_t *r, const char **why);

/* Whether the line last read holds nothing but blanks. */
int csv_blank(const csv_reader_t *r);

/* The index of the field named `name` in the line last read (the header), or -1. */
int csv_column(const csv_reader_t *r, const char *name);

/* The first field of the line last read whose name an earlier field has too, or NULL. */
const char *csv_duplicate_column(const csv_reader_t *r);

void csv_close(csv_reader_t *r);

#endif
