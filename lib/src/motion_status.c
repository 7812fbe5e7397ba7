/* motion_status.c - status sentences (see motion_status.h). */
#include "motion_status.h"

#ifdef __AVR__
#include <avr/pgmspace.h>
#define MS_FLASH PROGMEM
#else
#define MS_FLASH
#endif

#define MS_TEXT_DEF(id, text) static const char id##_text[] MS_FLASH = text;
MOTION_STATUS_LIST(MS_TEXT_DEF)
#undef MS_TEXT_DEF

#define MS_TEXT_PTR(id, text) id##_text,
static const char *const ms_texts[MS__COUNT] MS_FLASH = {MOTION_STATUS_LIST(MS_TEXT_PTR)};
#undef MS_TEXT_PTR

static const char ms_unknown[] MS_FLASH = "unknown status";

const char *motion_status_text(motion_status_t s)
{
    if ((unsigned)s >= (unsigned)MS__COUNT)
        return ms_unknown;
#ifdef __AVR__
    return (const char *)pgm_read_word(&ms_texts[s]);
#else
    return ms_texts[s];
#endif
}

size_t motion_status_copy(motion_status_t s, char *buf, size_t n)
{
    const char *src = motion_status_text(s);
    size_t i = 0;
    if (buf == NULL || n == 0)
        return 0;
    for (; i + 1 < n; i++) {
#ifdef __AVR__
        char c = (char)pgm_read_byte(src + i);
#else
        char c = src[i];
#endif
        if (c == '\0')
            break;
        buf[i] = c;
    }
    buf[i] = '\0';
    return i;
}
