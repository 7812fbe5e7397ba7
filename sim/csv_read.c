/* sim/csv_read.c - reading CSV one line at a time (see csv_read.h). */
#include "csv_read.h"

#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

int csv_open(csv_reader_t *r, const char *path, int trim)
{
    memset(r, 0, sizeof *r);
    r->trim = trim;
    r->f = fopen(path, "r");
    return r->f != NULL ? 0 : -1;
}

static int is_blank(char c)
{
    return c == ' ' || c == '\t';
}

static char *trim_field(char *s)
{
    char *e;
    while (is_blank(*s))
        s++;
    e = s + strlen(s);
    while (e > s && (is_blank(e[-1]) || e[-1] == '\r'))
        *--e = '\0';
    return s;
}

int csv_next(csv_reader_t *r, const char **why)
{
    ssize_t got = getline(&r->line, &r->cap, r->f);
    size_t len, n = 0;
    char *p;
    if (got < 0) {
        if (ferror(r->f)) {
            *why = "read error";
            return -1;
        }
        return 0;
    }
    r->lineno++;
    len = (size_t)got;
    /* the string functions below would stop at a NUL byte: refuse it */
    if (memchr(r->line, '\0', len) != NULL) {
        *why = "contains a NUL byte (not a text file)";
        return -1;
    }
    if (len > 0 && r->line[len - 1] == '\n')
        r->line[--len] = '\0';
    if (len > 0 && r->line[len - 1] == '\r')
        r->line[--len] = '\0';
    r->len = len;
    for (p = r->line;; n++) {
        char *comma = strchr(p, ',');
        if (n == r->fields_cap) {
            size_t grow = r->fields_cap != 0 ? 2 * r->fields_cap : 16;
            char **f = (char **)realloc(r->fields, grow * sizeof *f);
            if (f == NULL) {
                *why = "out of memory";
                return -1;
            }
            r->fields = f;
            r->fields_cap = grow;
        }
        if (comma != NULL)
            *comma = '\0';
        r->fields[n] = r->trim ? trim_field(p) : p;
        if (comma == NULL)
            break;
        p = comma + 1;
    }
    r->n_fields = n + 1;
    return 1;
}

int csv_blank(const csv_reader_t *r)
{
    size_t i;
    for (i = 0; i < r->n_fields; i++) {
        const char *p = r->fields[i];
        while (is_blank(*p))
            p++;
        if (*p != '\0' || r->n_fields > 1)
            return 0;
    }
    return 1;
}

int csv_column(const csv_reader_t *r, const char *name)
{
    size_t i;
    for (i = 0; i < r->n_fields; i++)
        if (strcmp(r->fields[i], name) == 0)
            return (int)i;
    return -1;
}

const char *csv_duplicate_column(const csv_reader_t *r)
{
    size_t i, k;
    for (i = 0; i < r->n_fields; i++)
        for (k = 0; k < i; k++)
            if (strcmp(r->fields[i], r->fields[k]) == 0)
                return r->fields[i];
    return NULL;
}

void csv_close(csv_reader_t *r)
{
    if (r->f != NULL)
        fclose(r->f);
    free(r->line);
    free(r->fields);
    memset(r, 0, sizeof *r);
}
