/* emu_log.c - the event log: one line per event, "<tag> <cycle> <fields...>".
 * The format is documented in README.md (Emulator) and read by tools/emu/emulog.py. */
#include <stdarg.h>
#include <string.h>

#include "emu.h"

static FILE *log_file;
static int fail_count;

void emu_log_open(FILE *f)
{
    log_file = f;
}

void emu_log(uint64_t cycle, const char *tag, const char *fmt, ...)
{
    if (!log_file)
        return;
    fprintf(log_file, "%s %llu", tag, (unsigned long long)cycle);
    if (fmt && *fmt) {
        va_list ap;
        va_start(ap, fmt);
        fputc(' ', log_file);
        vfprintf(log_file, fmt, ap);
        va_end(ap);
    }
    fputc('\n', log_file);
}

void emu_log_text(uint64_t cycle, const char *tag, const uint8_t *s, size_t n)
{
    if (!log_file)
        return;
    FILE *f = log_file;
    fprintf(f, "%s %llu ", tag, (unsigned long long)cycle);
    for (size_t i = 0; i < n; i++) {
        uint8_t c = s[i];
        if (c == '\\')
            fputs("\\\\", f);
        else if (c >= 0x20 && c < 0x7f)
            fputc(c, f);
        else
            fprintf(f, "\\x%02x", c);
    }
    fputc('\n', f);
}

void emu_log_flush(void)
{
    if (log_file)
        fflush(log_file);
}

void emu_fail(uint64_t cycle, const char *kind, const char *fmt, ...)
{
    fail_count++;
    char text[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    emu_log(cycle, "fail", "%s %s", kind, text);
    fprintf(stderr, "motionemu: FAIL at %.6f s (cycle %llu): %s: %s\n", (double)cycle / EMU_F_CPU,
            (unsigned long long)cycle, kind, text);
}

int emu_fail_count(void)
{
    return fail_count;
}
