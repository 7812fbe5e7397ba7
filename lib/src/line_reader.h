/* line_reader.h - assembles serial bytes into command lines, as the Arduino Serial Monitor sends
 * them with any line ending: CR, LF or CRLF ("Both NL & CR"). Pure logic: the sketch feeds it
 * each byte it reads from Serial.
 *
 * A line ends at CR or LF; the LF of a CRLF pair is swallowed. Leading blanks (space, TAB) are
 * dropped, so a blank line (empty, or only spaces and tabs, of any length) is no line at all: it
 * is ignored and gets no reply, on every sketch (docs/serial.md). A line longer than
 * LINE_READER_MAX characters from its first non-blank one, or one holding a byte outside
 * printable ASCII (space..'~' and TAB), is reported as an error as soon as the offending byte
 * arrives, once, and the rest of that line is discarded up to its terminator, so a 1 KB line
 * without a newline gives one error and never a partial command. line_reader_overrun() does the
 * same for a line some of whose bytes may have been lost. Cost: a few comparisons per byte;
 * 44 bytes SRAM.
 */
#ifndef LINE_READER_H
#define LINE_READER_H

#include <stdint.h>

#include "motion_status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define LINE_READER_MAX 40 /* characters in a line, without its terminator */

typedef enum {
    LINE_PENDING = 0, /* nothing to do yet */
    LINE_READY,       /* a complete line is in reader->line (NUL-terminated) */
    LINE_ERROR        /* the current line is bad: *err says why; its rest will be discarded */
} line_event_t;

typedef struct {
    char line[LINE_READER_MAX + 1];
    uint8_t len;
    uint8_t discarding; /* 1 after an error, until the line's terminator */
    uint8_t after_cr;   /* last byte was CR: a following LF belongs to it */
} line_reader_t;

void line_reader_init(line_reader_t *r);

/* Feeds one byte. On LINE_READY the line stays valid until the next call. */
line_event_t line_reader_feed(line_reader_t *r, uint8_t byte, motion_status_t *err);

/* Input bytes may have been lost just before the next byte fed (a receive buffer overflowed): the
 * line in progress, or the next one if none is, is discarded up to its terminator. Returns 1 when
 * the caller should report it (MS_ERR_INPUT_OVERRUN), 0 when that line was already reported as
 * bad (one reply per line). */
uint8_t line_reader_overrun(line_reader_t *r);

/* Input was lost here (rx_ring.h's loss record): the line in progress is dropped; when rest_lost,
 * the bytes that follow are the rest of a damaged line and are discarded up to its terminator;
 * after_cr: the lost stretch ended in CR (a following LF is its CR LF). Returns 1 when the line in
 * progress had already been answered as bad (the caller must not count it again). */
uint8_t line_reader_lost(line_reader_t *r, uint8_t rest_lost, uint8_t after_cr);

#ifdef __cplusplus
}
#endif

#endif
