/* line_reader.c - serial line assembly (see line_reader.h). */
#include "line_reader.h"

void line_reader_init(line_reader_t *r)
{
    r->len = 0;
    r->discarding = 0;
    r->after_cr = 0;
    r->line[0] = '\0';
}

line_event_t line_reader_feed(line_reader_t *r, uint8_t byte, motion_status_t *err)
{
    uint8_t was_cr = r->after_cr;
    r->after_cr = (byte == '\r');
    if (byte == '\r' || byte == '\n') {
        uint8_t len = r->len;
        uint8_t discarded = r->discarding;
        if (byte == '\n' && was_cr)
            return LINE_PENDING; /* second half of CRLF */
        r->len = 0;
        r->discarding = 0;
        if (discarded || len == 0)
            return LINE_PENDING; /* end of a reported bad line, or an empty line */
        r->line[len] = '\0';
        return LINE_READY;
    }
    if (r->discarding)
        return LINE_PENDING;
    if (r->len == 0 && (byte == ' ' || byte == '\t'))
        return LINE_PENDING; /* leading blank: a blank line stays empty and is ignored */
    if (!((byte >= 0x20 && byte <= 0x7E) || byte == '\t')) {
        r->discarding = 1;
        r->len = 0;
        if (err != 0)
            *err = MS_ERR_BINARY;
        return LINE_ERROR;
    }
    if (r->len >= LINE_READER_MAX) {
        r->discarding = 1;
        r->len = 0;
        if (err != 0)
            *err = MS_ERR_LINE_TOO_LONG;
        return LINE_ERROR;
    }
    r->line[r->len++] = (char)byte;
    return LINE_PENDING;
}

uint8_t line_reader_overrun(line_reader_t *r)
{
    uint8_t already = r->discarding;
    r->discarding = 1;
    r->len = 0;
    r->after_cr = 0; /* the LF of a CRLF may have been lost with the rest */
    return (uint8_t)!already;
}

uint8_t line_reader_lost(line_reader_t *r, uint8_t rest_lost, uint8_t after_cr)
{
    uint8_t already = r->discarding;
    r->discarding = rest_lost ? 1U : 0U;
    r->len = 0;
    r->after_cr = after_cr ? 1U : 0U;
    return already;
}
