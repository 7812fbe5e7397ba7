/* sim/pid_vector.c - PID_v1 reference vectors: loading and replay (see pid_vector.h).
 * Also valid C++ (the MotionPID unit test compiles it into a C++ program). */
#include "pid_vector.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "csv_read.h"
#include "text_parse.h"

#define PV_MAX_FILE (64L * 1024L * 1024L)

static int pv_err(char *err, size_t n, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int pv_err(char *err, size_t n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, n, fmt, ap);
    va_end(ap);
    return -1;
}

/* A whole file (the JSON set-up) into a NUL-terminated malloc'd buffer. */
static char *read_file(const char *path, char *err, size_t err_n)
{
    FILE *f = fopen(path, "rb");
    char *buf = NULL;
    long size;
    if (f == NULL) {
        pv_err(err, err_n, "cannot read '%s': %s", path, strerror(errno));
        return NULL;
    }
    if (fseek(f, 0, SEEK_END) != 0 || (size = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) != 0) {
        pv_err(err, err_n, "cannot read '%s': not a regular file", path);
        fclose(f);
        return NULL;
    }
    if (size > PV_MAX_FILE) {
        pv_err(err, err_n, "'%s' is larger than %ld bytes", path, PV_MAX_FILE);
        fclose(f);
        return NULL;
    }
    buf = (char *)malloc((size_t)size + 1);
    if (buf == NULL || fread(buf, 1, (size_t)size, f) != (size_t)size) {
        pv_err(err, err_n, "cannot read '%s'", path);
        free(buf);
        fclose(f);
        return NULL;
    }
    fclose(f);
    buf[size] = '\0';
    if (strlen(buf) != (size_t)size) {
        pv_err(err, err_n, "'%s' contains a NUL byte (not a text file)", path);
        free(buf);
        return NULL;
    }
    return buf;
}

/* A decimal number: [sign] digits [. digits] [e [sign] digits], whole text, finite, not
 * underflowing (lib's text_scan_real); the float from strtof of the same text, so each precision
 * gets the correctly rounded value of the decimal. */
static int parse_real(const char *s, pv_real_t *out)
{
    char *end;
    double d;
    float f;
    if (text_scan_real(s, &d) != MS_OK)
        return -1;
    f = strtof(s, &end);
    if (*end != '\0' || !isfinite(f))
        return -1;
    out->d = d;
    out->f = f;
    return 0;
}

static int parse_int32(const char *s, int32_t *out)
{
    return text_parse_int32(s, INT32_MIN, INT32_MAX, out) == MS_OK ? 0 : -1;
}

static int parse_uint32(const char *s, uint32_t *out)
{
    return text_parse_uint32(s, 0, UINT32_MAX, out) == MS_OK ? 0 : -1;
}

/* A symbolic or numeric integer argument. */
static int parse_symbol(const char *s, const char *name0, const char *name1, int32_t *out)
{
    if (strcmp(s, name0) == 0) {
        *out = 0;
        return 0;
    }
    if (strcmp(s, name1) == 0) {
        *out = 1;
        return 0;
    }
    return parse_int32(s, out);
}

/* One call, e.g. "SetTunings(0.5 1 0.05)" or "Output:=37.5" (text is modified). */
static int parse_call(char *text, pv_cmd_t *c, char *err, size_t err_n)
{
    char *open, *close, *args[5];
    size_t n_args = 0;
    char *p;
    memset(c, 0, sizeof *c);
    if (strncmp(text, "Output:=", 8) == 0) {
        c->op = PV_OUTPUT_SET;
        if (parse_real(text + 8, &c->x[0]) != 0)
            return pv_err(err, err_n, "'%s': the value is not a finite number", text);
        return 0;
    }
    open = strchr(text, '(');
    close = strrchr(text, ')');
    if (open == NULL || close == NULL || close < open || close[1] != '\0')
        return pv_err(err, err_n, "'%s' is not a call NAME(ARGS) or Output:=VALUE", text);
    *open = '\0';
    *close = '\0';
    p = open + 1;
    while (*p != '\0') {
        if (n_args == 5)
            return pv_err(err, err_n, "%s(): too many arguments", text);
        args[n_args++] = p;
        while (*p != '\0' && *p != ' ')
            p++;
        if (*p == ' ') {
            *p++ = '\0';
            if (*p == '\0' || *p == ' ')
                return pv_err(err, err_n, "%s(): arguments must be separated by one space", text);
        }
    }
#define NEED_ARGS(k)                                                                              \
    do {                                                                                          \
        if (n_args != (k))                                                                        \
            return pv_err(err, err_n, "%s() takes %d argument%s, got %zu", text, (k), (k) == 1 ? "" : "s", n_args); \
    } while (0)
    if (strcmp(text, "SetMode") == 0) {
        NEED_ARGS(1);
        c->op = PV_SET_MODE;
        if (parse_symbol(args[0], "MANUAL", "AUTOMATIC", &c->n) != 0)
            return pv_err(err, err_n, "SetMode(%s): not AUTOMATIC, MANUAL or an integer", args[0]);
        return 0;
    }
    if (strcmp(text, "SetTunings") == 0) {
        size_t i;
        if (n_args != 3 && n_args != 4)
            return pv_err(err, err_n, "SetTunings() takes 3 or 4 arguments, got %zu", n_args);
        c->op = n_args == 3 ? PV_SET_TUNINGS : PV_SET_TUNINGS_PON;
        for (i = 0; i < 3; i++)
            if (parse_real(args[i], &c->x[i]) != 0)
                return pv_err(err, err_n, "SetTunings(): '%s' is not a finite number", args[i]);
        if (n_args == 4 && parse_symbol(args[3], "P_ON_M", "P_ON_E", &c->n) != 0)
            return pv_err(err, err_n, "SetTunings(): POn '%s' is not P_ON_E, P_ON_M or an integer", args[3]);
        return 0;
    }
    if (strcmp(text, "SetSampleTime") == 0) {
        NEED_ARGS(1);
        c->op = PV_SET_SAMPLE_TIME;
        if (parse_int32(args[0], &c->n) != 0)
            return pv_err(err, err_n, "SetSampleTime(%s): not an integer", args[0]);
        return 0;
    }
    if (strcmp(text, "SetOutputLimits") == 0) {
        NEED_ARGS(2);
        c->op = PV_SET_OUTPUT_LIMITS;
        if (parse_real(args[0], &c->x[0]) != 0 || parse_real(args[1], &c->x[1]) != 0)
            return pv_err(err, err_n, "SetOutputLimits(%s %s): not two finite numbers", args[0], args[1]);
        return 0;
    }
    if (strcmp(text, "SetControllerDirection") == 0) {
        NEED_ARGS(1);
        c->op = PV_SET_DIRECTION;
        if (parse_symbol(args[0], "DIRECT", "REVERSE", &c->n) != 0)
            return pv_err(err, err_n, "SetControllerDirection(%s): not DIRECT, REVERSE or an integer", args[0]);
        return 0;
    }
#undef NEED_ARGS
    return pv_err(err, err_n, "unknown call '%s()'", text);
}

/* The command column: calls separated by ';' (empty = none). text is modified. */
static int parse_commands(char *text, pv_cmd_t *cmds, size_t *n, char *err, size_t err_n)
{
    char *p = text;
    *n = 0;
    if (*p == '\0')
        return 0;
    for (;;) {
        char *semi = strchr(p, ';');
        if (semi != NULL)
            *semi = '\0';
        if (*p == '\0')
            return pv_err(err, err_n, "empty call between ';'");
        if (*n >= PV_MAX_CMDS)
            return pv_err(err, err_n, "more than %d calls", PV_MAX_CMDS);
        if (parse_call(p, &cmds[*n], err, err_n) != 0)
            return -1;
        (*n)++;
        if (semi == NULL)
            return 0;
        p = semi + 1;
    }
}

/* A JSON number as the decimal text it stands for: cJSON keeps only the double, so its shortest
 * form of at most 15 significant digits is taken (the decimal as written for any number with up to
 * 15 digits, which every set-up has); a double that needs more is refused, since its float could
 * then differ from the one of the text in the file. */
static int json_number_text(const cJSON *item, char *buf, size_t n)
{
    int prec;
    for (prec = 1; prec <= 15; prec++) {
        snprintf(buf, n, "%.*g", prec, item->valuedouble);
        if (strtod(buf, NULL) == item->valuedouble)
            return 0;
    }
    return -1;
}

static int json_real(const cJSON *j, const char *key, pv_real_t *out, char *err, size_t err_n)
{
    char text[40];
    const cJSON *m = cJSON_GetObjectItemCaseSensitive(j, key);
    if (m == NULL)
        return pv_err(err, err_n, "key \"%s\" is missing", key);
    if (!cJSON_IsNumber(m))
        return pv_err(err, err_n, "\"%s\": expected a number", key);
    if (json_number_text(m, text, sizeof text) != 0 || parse_real(text, out) != 0)
        return pv_err(err, err_n, "\"%s\" must be a finite number of at most 15 significant digits", key);
    return 0;
}

/* A whole JSON number in [lo, hi]. */
static int json_whole(const cJSON *m, double lo, double hi, double *out)
{
    if (!cJSON_IsNumber(m) || m->valuedouble != floor(m->valuedouble) || m->valuedouble < lo || m->valuedouble > hi)
        return -1;
    *out = m->valuedouble;
    return 0;
}

/* Line and column of a position in text, for a syntax error. */
/* Up to 12 bytes of the text at `at`, for an error line: a line end, tab or other control byte and
 * any byte over 0x7e written as \n, \r, \t or \xNN, so that the message stays one line. */
static void near_text(const char *at, char *out, size_t n)
{
    size_t k = 0;
    int i;
    for (i = 0; i < 12 && at[i] != '\0' && k + 5 < n; i++) {
        unsigned char c = (unsigned char)at[i];
        if (c == '\n' || c == '\r' || c == '\t')
            k += (size_t)snprintf(out + k, n - k, "\\%c", c == '\n' ? 'n' : c == '\r' ? 'r' : 't');
        else if (c < 0x20 || c > 0x7e)
            k += (size_t)snprintf(out + k, n - k, "\\x%02x", c);
        else
            out[k++] = (char)c;
    }
    out[k] = '\0';
}

static void text_position(const char *text, const char *at, int *line, int *col)
{
    const char *p;
    *line = 1;
    *col = 1;
    for (p = text; p < at && *p != '\0'; p++) {
        if (*p == '\n') {
            (*line)++;
            *col = 1;
        } else {
            (*col)++;
        }
    }
}

static int load_json(pv_vector_t *v, const char *path, char *err, size_t err_n)
{
    static const char *const known[] = {"kp", "ki", "kd", "pon", "direction", "t0_ms", "input0",
                                        "output0", "setpoint0", "setup", "clock_bits"};
    char msg[256];
    char *text = read_file(path, err, err_n);
    const char *end = NULL;
    cJSON *j;
    const cJSON *m, *a, *b;
    size_t i, k;
    double whole;
    int rc = -1;
    if (text == NULL)
        return -1;
    j = cJSON_ParseWithOpts(text, &end, 1);
    if (j == NULL) {
        int line, col;
        char near[64];
        const char *at = end != NULL ? end : cJSON_GetErrorPtr();
        text_position(text, at != NULL ? at : text, &line, &col);
        near_text(at != NULL && *at != '\0' ? at : "the end", near, sizeof near);
        pv_err(err, err_n, "%s line %d column %d: not valid JSON (near '%s')", path, line, col, near);
        free(text);
        return -1;
    }
    if (!cJSON_IsObject(j)) {
        pv_err(err, err_n, "%s: the set-up must be one JSON object {...}", path);
        goto done;
    }
    for (a = j->child; a != NULL; a = a->next) {
        int ok = 0;
        for (k = 0; k < sizeof known / sizeof known[0]; k++)
            ok |= strcmp(a->string, known[k]) == 0;
        if (!ok) {
            pv_err(err, err_n, "%s: unknown key \"%s\"", path, a->string);
            goto done;
        }
        for (b = j->child; b != a; b = b->next) {
            if (strcmp(a->string, b->string) == 0) {
                pv_err(err, err_n, "%s: duplicate key \"%s\"", path, a->string);
                goto done;
            }
        }
    }
    if (json_real(j, "kp", &v->kp, msg, sizeof msg) != 0 || json_real(j, "ki", &v->ki, msg, sizeof msg) != 0 ||
        json_real(j, "kd", &v->kd, msg, sizeof msg) != 0 || json_real(j, "input0", &v->input0, msg, sizeof msg) != 0 ||
        json_real(j, "output0", &v->output0, msg, sizeof msg) != 0 ||
        json_real(j, "setpoint0", &v->setpoint0, msg, sizeof msg) != 0) {
        pv_err(err, err_n, "%s: %s", path, msg);
        goto done;
    }
    /* PID_v1's constructor passes the gains to SetTunings, which ignores the whole call when one
     * is negative: the working gains and POn are then left uninitialised (reference README,
     * "Construction"), so the library has no defined behaviour to replay. */
    if (v->kp.d < 0 || v->ki.d < 0 || v->kd.d < 0) {
        pv_err(err, err_n,
               "%s: \"%s\" is negative: PID_v1's constructor rejects negative gains and leaves its "
               "working gains undefined, so there is nothing to replay",
               path, v->kp.d < 0 ? "kp" : v->ki.d < 0 ? "ki" : "kd");
        goto done;
    }
    m = cJSON_GetObjectItemCaseSensitive(j, "pon");
    if (!cJSON_IsString(m) || parse_symbol(m->valuestring, "P_ON_M", "P_ON_E", &v->pon) != 0) {
        pv_err(err, err_n, "%s: \"pon\" must be \"P_ON_E\" or \"P_ON_M\"", path);
        goto done;
    }
    m = cJSON_GetObjectItemCaseSensitive(j, "direction");
    if (!cJSON_IsString(m) || parse_symbol(m->valuestring, "DIRECT", "REVERSE", &v->direction) != 0) {
        pv_err(err, err_n, "%s: \"direction\" must be \"DIRECT\" or \"REVERSE\"", path);
        goto done;
    }
    if (json_whole(cJSON_GetObjectItemCaseSensitive(j, "t0_ms"), 0, 4294967295.0, &whole) != 0) {
        pv_err(err, err_n, "%s: \"t0_ms\" must be a whole number 0..4294967295", path);
        goto done;
    }
    v->t0_ms = (uint32_t)whole;
    v->clock_bits = 32;
    m = cJSON_GetObjectItemCaseSensitive(j, "clock_bits");
    if (m != NULL) {
        if (json_whole(m, 32, 64, &whole) != 0 || (whole != 32 && whole != 64)) {
            pv_err(err, err_n, "%s: \"clock_bits\" must be 32 or 64", path);
            goto done;
        }
        v->clock_bits = (int32_t)whole;
    }
    m = cJSON_GetObjectItemCaseSensitive(j, "setup");
    if (!cJSON_IsArray(m)) {
        pv_err(err, err_n, "%s: \"setup\" must be an array of calls", path);
        goto done;
    }
    if (cJSON_GetArraySize(m) > PV_MAX_CMDS) {
        pv_err(err, err_n, "%s: more than %d set-up calls", path, PV_MAX_CMDS);
        goto done;
    }
    v->n_setup = 0;
    i = 0;
    for (a = m->child; a != NULL; a = a->next) {
        char call[256];
        size_t n1 = 0;
        i++;
        if (!cJSON_IsString(a)) {
            pv_err(err, err_n, "%s: \"setup\" holds only strings (calls); item %zu is not one", path, i);
            goto done;
        }
        if (strlen(a->valuestring) >= sizeof call) {
            pv_err(err, err_n, "%s: setup item %zu is longer than %zu characters", path, i, sizeof call - 1);
            goto done;
        }
        strcpy(call, a->valuestring);
        msg[0] = '\0';
        if (parse_commands(call, &v->setup[v->n_setup], &n1, msg, sizeof msg) != 0 || n1 != 1) {
            pv_err(err, err_n, "%s: setup item %zu: %s", path, i, n1 != 1 && msg[0] == '\0' ? "one call expected" : msg);
            goto done;
        }
        v->n_setup++;
    }
    rc = 0;
done:
    cJSON_Delete(j);
    free(text);
    return rc;
}

/* NAME.csv -> NAME.json beside it, else ../NAME.json when the CSV is in a float32/ folder. */
static int find_json(const char *csv_path, char *out, size_t n, char *err, size_t err_n)
{
    size_t len = strlen(csv_path);
    const char *slash = strrchr(csv_path, '/');
    const char *base = slash != NULL ? slash + 1 : csv_path;
    size_t dir_len = (size_t)(base - csv_path);
    FILE *f;
    if (len < 5 || strcmp(csv_path + len - 4, ".csv") != 0)
        return pv_err(err, err_n, "'%s': a vector file name ends in .csv", csv_path);
    if (len + 2 > n)
        return pv_err(err, err_n, "'%s': path too long", csv_path);
    memcpy(out, csv_path, len - 4);
    strcpy(out + len - 4, ".json");
    f = fopen(out, "r");
    if (f != NULL) {
        fclose(f);
        return 0;
    }
    /* float32/NAME.csv -> NAME.json one folder up */
    if (dir_len >= 8 && strncmp(base - 8, "float32/", 8) == 0 && (dir_len == 8 || base[-9] == '/')) {
        size_t stem = strlen(base) - 4;
        if (dir_len - 8 + stem + 6 > n)
            return pv_err(err, err_n, "'%s': path too long", csv_path);
        memcpy(out, csv_path, dir_len - 8);
        memcpy(out + dir_len - 8, base, stem);
        strcpy(out + dir_len - 8 + stem, ".json");
        f = fopen(out, "r");
        if (f != NULL) {
            fclose(f);
            return 0;
        }
    }
    return pv_err(err, err_n, "no set-up file for '%s' (looked for NAME.json beside it%s)", csv_path,
                  dir_len >= 8 && strncmp(base - 8, "float32/", 8) == 0 ? " and one folder up" : "");
}

static int col_index(const pv_vector_t *v, const char *name)
{
    size_t i;
    for (i = 0; i < v->n_cols; i++)
        if (strcmp(v->header[i], name) == 0)
            return (int)i;
    return -1;
}

/* Fails pv_load: the message is formatted first (it may quote cells of v), then v is freed. */
static int pv_fail(pv_vector_t *v, char *err, size_t n, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
static int pv_fail(pv_vector_t *v, char *err, size_t n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, n, fmt, ap);
    va_end(ap);
    pv_free(v);
    return -1;
}

/* A copy of the line last read (cut into its fields) that v keeps; the fields' pointers are moved
 * into it, at fields. NULL when out of memory. */
static char **keep_line(pv_vector_t *v, const csv_reader_t *r, char **fields)
{
    size_t i;
    char *copy;
    char **lines = (char **)realloc(v->lines, (v->n_lines + 1) * sizeof *lines);
    if (lines == NULL)
        return NULL;
    v->lines = lines;
    copy = (char *)malloc(r->len + 1);
    if (copy == NULL)
        return NULL;
    memcpy(copy, r->line, r->len + 1);
    v->lines[v->n_lines++] = copy;
    for (i = 0; i < r->n_fields; i++)
        fields[i] = copy + (r->fields[i] - r->line);
    return fields;
}

int pv_load(pv_vector_t *v, const char *csv_path, char *err, size_t err_n)
{
    char msg[256];
    csv_reader_t rd;
    const char *why = NULL;
    size_t r, cap_rows = 0, len = strlen(csv_path), bytes = 0;
    int got, c_t, c_in, c_sp, c_cmd;
    memset(v, 0, sizeof *v);
    if (len < 5 || strcmp(csv_path + len - 4, ".csv") != 0)
        return pv_err(err, err_n, "'%s': a vector file name ends in .csv", csv_path);
    /* the vector itself first: a missing CSV is "cannot read", whatever the .json */
    if (csv_open(&rd, csv_path, 0) != 0)
        return pv_err(err, err_n, "cannot read '%s': %s", csv_path, strerror(errno));
#define PV_FAIL(...)                                                                              \
    do {                                                                                          \
        pv_fail(v, err, err_n, __VA_ARGS__);                                                      \
        csv_close(&rd);                                                                           \
        return -1;                                                                                \
    } while (0)
    if (find_json(csv_path, v->json_path, sizeof v->json_path, err, err_n) != 0 ||
        load_json(v, v->json_path, err, err_n) != 0) {
        pv_free(v);
        csv_close(&rd);
        return -1;
    }
    /* header */
    got = csv_next(&rd, &why);
    if (got < 0)
        PV_FAIL("%s:%lu: %s", csv_path, rd.lineno, why);
    if (got == 0 || rd.len == 0)
        PV_FAIL("%s:1: empty header line", csv_path);
    {
        const char *twice = csv_duplicate_column(&rd);
        /* a column named twice: which one holds the data would be a guess (as `motionsim filter`) */
        if (twice != NULL)
            PV_FAIL("%s:1: the header names column '%s' twice", csv_path, twice);
    }
    c_t = csv_column(&rd, "t_ms");
    c_in = csv_column(&rd, "input");
    c_sp = csv_column(&rd, "setpoint");
    c_cmd = csv_column(&rd, "command");
    if (c_t < 0 || c_in < 0 || c_sp < 0 || c_cmd < 0)
        PV_FAIL("%s:1: the header needs columns t_ms, input, setpoint and command", csv_path);
    v->n_cols = rd.n_fields;
    v->header = (char **)malloc(v->n_cols * sizeof *v->header);
    if (v->header == NULL || keep_line(v, &rd, v->header) == NULL)
        PV_FAIL("out of memory");
    bytes = rd.len;
    r = 0;
    while ((got = csv_next(&rd, &why)) > 0) {
        char **f;
        pv_row_t *row;
        char cmd_copy[1024];
        unsigned long lineno = rd.lineno;
        bytes += rd.len + 1;
        if (bytes > (size_t)PV_MAX_FILE)
            PV_FAIL("'%s' is larger than %ld bytes", csv_path, PV_MAX_FILE);
        if (rd.len == 0)
            PV_FAIL("%s:%lu: empty line", csv_path, lineno);
        if (rd.n_fields != v->n_cols)
            PV_FAIL("%s:%lu: %zu fields, the header has %zu", csv_path, lineno, rd.n_fields, v->n_cols);
        if (r == cap_rows) {
            size_t grow = cap_rows != 0 ? 2 * cap_rows : 256;
            pv_row_t *rows = (pv_row_t *)realloc(v->rows, grow * sizeof *rows);
            char **cells;
            if (rows == NULL)
                PV_FAIL("out of memory");
            v->rows = rows;
            cells = (char **)realloc(v->cells, grow * v->n_cols * sizeof *cells);
            if (cells == NULL)
                PV_FAIL("out of memory");
            v->cells = cells;
            cap_rows = grow;
        }
        f = keep_line(v, &rd, &v->cells[r * v->n_cols]);
        if (f == NULL)
            PV_FAIL("out of memory");
        row = &v->rows[r];
        memset(row, 0, sizeof *row);
        if (parse_uint32(f[c_t], &row->t_ms) != 0)
            PV_FAIL("%s:%lu: t_ms '%s' is not a whole number 0..4294967295", csv_path, lineno, f[c_t]);
        if (parse_real(f[c_in], &row->input) != 0 || parse_real(f[c_sp], &row->setpoint) != 0)
            PV_FAIL("%s:%lu: input and setpoint must be finite numbers", csv_path, lineno);
        if (strlen(f[c_cmd]) >= sizeof cmd_copy)
            PV_FAIL("%s:%lu: command too long", csv_path, lineno);
        strcpy(cmd_copy, f[c_cmd]);
        if (parse_commands(cmd_copy, row->cmds, &row->n_cmds, msg, sizeof msg) != 0)
            PV_FAIL("%s:%lu: %s", csv_path, lineno, msg);
        r++;
    }
    if (got < 0)
        PV_FAIL("%s:%lu: %s", csv_path, rd.lineno, why);
#undef PV_FAIL
    csv_close(&rd);
    v->n_rows = r;
    if (r == 0)
        return pv_fail(v, err, err_n, "%s: no data rows", csv_path);
    return 0;
}

void pv_free(pv_vector_t *v)
{
    size_t i;
    for (i = 0; i < v->n_lines; i++)
        free(v->lines[i]);
    free(v->lines);
    free(v->rows);
    free(v->cells);
    free(v->header);
    v->lines = NULL;
    v->n_lines = 0;
    v->rows = NULL;
    v->cells = NULL;
    v->header = NULL;
    v->n_rows = v->n_cols = 0;
}

const char *pv_cell(const pv_vector_t *v, size_t r, const char *col)
{
    int c = col_index(v, col);
    if (c < 0 || r >= v->n_rows)
        return NULL;
    return v->cells[r * v->n_cols + (size_t)c];
}

/* The replay, once per precision: M is the pv_real_t member (d or f), P the pidv1_ctrl function prefix,
 * Q the prefix of the local functions. */
#define PV_REPLAY_BODY(real, M, P, T, FN, Q)                                                          \
    static void Q##apply(T *c, real *out, const pv_cmd_t *cmd)                                   \
    {                                                                                            \
        switch (cmd->op) {                                                                       \
        case PV_OUTPUT_SET: *out = cmd->x[0].M; break;                                           \
        case PV_SET_MODE: P##set_mode(c, cmd->n); break;                                         \
        case PV_SET_TUNINGS: (void)P##set_tunings(c, cmd->x[0].M, cmd->x[1].M, cmd->x[2].M); break; \
        case PV_SET_TUNINGS_PON:                                                                 \
            (void)P##set_tunings_pon(c, cmd->x[0].M, cmd->x[1].M, cmd->x[2].M, cmd->n);          \
            break;                                                                               \
        case PV_SET_SAMPLE_TIME: (void)P##set_sample_time(c, cmd->n); break;                     \
        case PV_SET_OUTPUT_LIMITS: (void)P##set_output_limits(c, cmd->x[0].M, cmd->x[1].M); break; \
        case PV_SET_DIRECTION: P##set_direction(c, cmd->n); break;                               \
        }                                                                                        \
    }                                                                                            \
    static motion_status_t Q##replay(const pv_vector_t *v, FN fn, void *user)                   \
    {                                                                                            \
        T c;                                                                                     \
        real in = v->input0.M, out = v->output0.M, sp = v->setpoint0.M;                          \
        size_t r, k;                                                                             \
        motion_status_t st =                                                                     \
            P##init(&c, &in, &out, &sp, v->kp.M, v->ki.M, v->kd.M, v->pon, v->direction, v->t0_ms); \
        if (st != MS_OK) /* PID_v1 would be left with undefined gains (pv_load refuses that) */  \
            return st;                                                                           \
        for (k = 0; k < v->n_setup; k++)                                                         \
            Q##apply(&c, &out, &v->setup[k]);                                                    \
        for (r = 0; r < v->n_rows; r++) {                                                        \
            const pv_row_t *row = &v->rows[r];                                                   \
            int computed;                                                                        \
            in = row->input.M;                                                                   \
            sp = row->setpoint.M;                                                                \
            for (k = 0; k < row->n_cmds; k++)                                                    \
                Q##apply(&c, &out, &row->cmds[k]);                                               \
            computed = P##compute(&c, row->t_ms);                                                \
            fn(user, r, computed, out, &c);                                                      \
        }                                                                                        \
        return MS_OK;                                                                            \
    }

PV_REPLAY_BODY(double, d, pid_, pid_ctrl_t, pv_row_fn_double, pvd_)
PV_REPLAY_BODY(float, f, pidf_, pidf_ctrl_t, pv_row_fn_float, pvf_)

motion_status_t pv_replay_double(const pv_vector_t *v, pv_row_fn_double fn, void *user)
{
    return pvd_replay(v, fn, user);
}

motion_status_t pv_replay_float(const pv_vector_t *v, pv_row_fn_float fn, void *user)
{
    return pvf_replay(v, fn, user);
}
