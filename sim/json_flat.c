/* sim/json_flat.c - strict flat JSON reader (see json_flat.h). Grammar (RFC 8259, restricted):
 *   object = ws '{' ws [ member *( ws ',' ws member ) ] ws '}' ws EOF
 *   member = string ws ':' ws ( number | string | '[' ws [ string *( ws ',' ws string ) ] ws ']' )
 *   number = [ '-' ] ( '0' | [1-9][0-9]* ) [ '.' [0-9]+ ] [ ( 'e' | 'E' ) [ '+' | '-' ] [0-9]+ ]
 */
#include "json_flat.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

typedef struct {
    const char *p;
    int line;
    char *err;
    size_t err_n;
} jp_t;

static int jf_fail(jp_t *s, const char *fmt, ...)
{
    va_list ap;
    int k = snprintf(s->err, s->err_n, "line %d: ", s->line);
    if (k >= 0 && (size_t)k < s->err_n) {
        va_start(ap, fmt);
        vsnprintf(s->err + k, s->err_n - (size_t)k, fmt, ap);
        va_end(ap);
    }
    return -1;
}

static void skip_ws(jp_t *s)
{
    while (*s->p == ' ' || *s->p == '\t' || *s->p == '\n' || *s->p == '\r') {
        if (*s->p == '\n')
            s->line++;
        s->p++;
    }
}

static int is_digit(char c)
{
    return c >= '0' && c <= '9';
}

static int hex_value(char c)
{
    if (c >= '0' && c <= '9')
        return c - '0';
    if (c >= 'a' && c <= 'f')
        return c - 'a' + 10;
    if (c >= 'A' && c <= 'F')
        return c - 'A' + 10;
    return -1;
}

/* A string into out (at most JSON_FLAT_MAX_TEXT bytes). \uXXXX is accepted for ASCII only. */
static int parse_string(jp_t *s, char *out)
{
    size_t n = 0;
    if (*s->p != '"')
        return jf_fail(s, "expected a string in double quotes");
    s->p++;
    for (;;) {
        char c = *s->p;
        if (c == '\0' || c == '\n')
            return jf_fail(s, "unterminated string");
        if ((unsigned char)c < 0x20)
            return jf_fail(s, "control character in a string");
        s->p++;
        if (c == '"')
            break;
        if (c == '\\') {
            char e = *s->p++;
            switch (e) {
            case '"': c = '"'; break;
            case '\\': c = '\\'; break;
            case '/': c = '/'; break;
            case 'b': c = '\b'; break;
            case 'f': c = '\f'; break;
            case 'n': c = '\n'; break;
            case 'r': c = '\r'; break;
            case 't': c = '\t'; break;
            case 'u': {
                int v = 0, i;
                for (i = 0; i < 4; i++) {
                    int h = hex_value(*s->p);
                    if (h < 0)
                        return jf_fail(s, "bad \\u escape");
                    v = v * 16 + h;
                    s->p++;
                }
                if (v == 0 || v > 0x7f)
                    return jf_fail(s, "\\u escape outside ASCII 1..127 is not supported");
                c = (char)v;
                break;
            }
            default:
                return jf_fail(s, "bad escape '\\%c'", e != '\0' ? e : '0');
            }
        }
        if (n >= JSON_FLAT_MAX_TEXT)
            return jf_fail(s, "string longer than %d characters", JSON_FLAT_MAX_TEXT);
        out[n++] = c;
    }
    out[n] = '\0';
    return 0;
}

static int parse_number(jp_t *s, char *out)
{
    const char *start = s->p;
    size_t len;
    if (*s->p == '-')
        s->p++;
    if (*s->p == '0') {
        s->p++;
    } else if (is_digit(*s->p)) {
        while (is_digit(*s->p))
            s->p++;
    } else {
        return jf_fail(s, "expected a number, a string or an array of strings");
    }
    if (*s->p == '.') {
        s->p++;
        if (!is_digit(*s->p))
            return jf_fail(s, "malformed number: digits must follow '.'");
        while (is_digit(*s->p))
            s->p++;
    }
    if (*s->p == 'e' || *s->p == 'E') {
        s->p++;
        if (*s->p == '+' || *s->p == '-')
            s->p++;
        if (!is_digit(*s->p))
            return jf_fail(s, "malformed number: digits must follow the exponent");
        while (is_digit(*s->p))
            s->p++;
    }
    len = (size_t)(s->p - start);
    if (len > JSON_FLAT_MAX_TEXT)
        return jf_fail(s, "number longer than %d characters", JSON_FLAT_MAX_TEXT);
    memcpy(out, start, len);
    out[len] = '\0';
    return 0;
}

static int parse_value(jp_t *s, json_flat_member_t *m)
{
    if (*s->p == '"') {
        m->kind = JSON_FLAT_STRING;
        return parse_string(s, m->text);
    }
    if (*s->p == '[') {
        m->kind = JSON_FLAT_ARRAY;
        m->n_items = 0;
        s->p++;
        skip_ws(s);
        if (*s->p == ']') {
            s->p++;
            return 0;
        }
        for (;;) {
            if (m->n_items >= JSON_FLAT_MAX_ITEMS)
                return jf_fail(s, "more than %d items in an array", JSON_FLAT_MAX_ITEMS);
            if (*s->p != '"')
                return jf_fail(s, "arrays may hold only strings");
            if (parse_string(s, m->items[m->n_items]) != 0)
                return -1;
            m->n_items++;
            skip_ws(s);
            if (*s->p == ',') {
                s->p++;
                skip_ws(s);
                continue;
            }
            if (*s->p == ']') {
                s->p++;
                return 0;
            }
            return jf_fail(s, "expected ',' or ']' in an array");
        }
    }
    m->kind = JSON_FLAT_NUMBER;
    return parse_number(s, m->text);
}

int json_flat_parse(const char *text, json_flat_t *out, char *err, size_t err_n)
{
    jp_t s;
    s.p = text;
    s.line = 1;
    s.err = err;
    s.err_n = err_n;
    out->n = 0;
    skip_ws(&s);
    if (*s.p != '{')
        return jf_fail(&s, "expected '{' (a JSON object)");
    s.p++;
    skip_ws(&s);
    if (*s.p == '}') {
        s.p++;
    } else {
        for (;;) {
            json_flat_member_t *m;
            size_t i;
            if (out->n >= JSON_FLAT_MAX_KEYS)
                return jf_fail(&s, "more than %d keys", JSON_FLAT_MAX_KEYS);
            m = &out->m[out->n];
            if (parse_string(&s, m->key) != 0)
                return -1;
            for (i = 0; i < out->n; i++)
                if (strcmp(out->m[i].key, m->key) == 0)
                    return jf_fail(&s, "duplicate key \"%s\"", m->key);
            skip_ws(&s);
            if (*s.p != ':')
                return jf_fail(&s, "expected ':' after key \"%s\"", m->key);
            s.p++;
            skip_ws(&s);
            if (parse_value(&s, m) != 0)
                return -1;
            out->n++;
            skip_ws(&s);
            if (*s.p == ',') {
                s.p++;
                skip_ws(&s);
                continue;
            }
            if (*s.p == '}') {
                s.p++;
                break;
            }
            return jf_fail(&s, "expected ',' or '}' after the value of \"%s\"", m->key);
        }
    }
    skip_ws(&s);
    if (*s.p != '\0')
        return jf_fail(&s, "unexpected text after the object");
    return 0;
}

const json_flat_member_t *json_flat_get(const json_flat_t *j, const char *key)
{
    size_t i;
    for (i = 0; i < j->n; i++)
        if (strcmp(j->m[i].key, key) == 0)
            return &j->m[i];
    return NULL;
}
