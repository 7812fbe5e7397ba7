/* sim/json_flat.h - a small strict reader for flat JSON objects, enough for the set-up files of
 * the PID_v1 reference vectors (reference/pid_v1/README.md, "NAME.json fields"):
 *
 *   { "kp": 0.02, "pon": "P_ON_E", "setup": ["SetOutputLimits(-100 100)", "SetSampleTime(20)"] }
 *
 * Values may be numbers (kept as their exact text, to be parsed later in the precision the
 * caller needs), strings, or arrays of strings. Anything else (nested objects, true/false/null,
 * arrays of numbers, duplicate keys, trailing text, bad escapes, control characters) is an
 * error with the line number. No allocation: the caller gives the storage.
 */
#ifndef MOTIONSIM_JSON_FLAT_H
#define MOTIONSIM_JSON_FLAT_H

#include <stddef.h>

#define JSON_FLAT_MAX_KEYS 24
#define JSON_FLAT_MAX_ITEMS 16 /* strings in one array */
#define JSON_FLAT_MAX_TEXT 96  /* characters in one key, number or string (without NUL) */

typedef enum { JSON_FLAT_NUMBER, JSON_FLAT_STRING, JSON_FLAT_ARRAY } json_flat_kind_t;

typedef struct {
    char key[JSON_FLAT_MAX_TEXT + 1];
    json_flat_kind_t kind;
    char text[JSON_FLAT_MAX_TEXT + 1]; /* NUMBER: its text as written; STRING: the decoded string */
    size_t n_items;                      /* ARRAY: the decoded strings */
    char items[JSON_FLAT_MAX_ITEMS][JSON_FLAT_MAX_TEXT + 1];
} json_flat_member_t;

typedef struct {
    size_t n;
    json_flat_member_t m[JSON_FLAT_MAX_KEYS];
} json_flat_t;

/* Parses text (NUL-terminated). Returns 0, or -1 with a message "line N: ..." in err. */
int json_flat_parse(const char *text, json_flat_t *out, char *err, size_t err_n);

/* The member named key, or NULL. */
const json_flat_member_t *json_flat_get(const json_flat_t *j, const char *key);

#endif
