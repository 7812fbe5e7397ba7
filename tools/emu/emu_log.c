/* emu_log.c - the event log: one line per event, "<tag> <cycle> <fields...>".
 * The format is documented in docs/emulator.md and read by tools/emu/emulog.py. */
#include <stdarg.h>
#include <string.h>
#include <time.h>

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

/* ---- the conversation, live (--echo) ---- */
static FILE *echo_file;
static uint64_t echo_last_wall_ms; /* when the last echo line was printed (for the progress lines) */

void emu_echo_open(FILE *f)
{
    echo_file = f;
    echo_last_wall_ms = emu_wall_ms();
}

int emu_echo_on(void)
{
    return echo_file != NULL;
}

static void echo_escaped(FILE *f, const uint8_t *s, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        uint8_t c = s[i];
        if (c == '\\')
            fputs("\\\\", f);
        else if (c >= 0x20 && c < 0x7f)
            fputc(c, f);
        else
            fprintf(f, "\\x%02x", c);
    }
}

void emu_echo(uint64_t cycle, char dir, const uint8_t *s, size_t n)
{
    if (!echo_file)
        return;
    fprintf(echo_file, "[%8.3f s] %c ", (double)cycle / EMU_F_CPU, dir);
    echo_escaped(echo_file, s, n);
    fputc('\n', echo_file);
    fflush(echo_file);
    echo_last_wall_ms = emu_wall_ms();
}

void emu_echo_note(uint64_t cycle, const char *fmt, ...)
{
    if (!echo_file)
        return;
    fprintf(echo_file, "[%8.3f s] ", (double)cycle / EMU_F_CPU);
    va_list ap;
    va_start(ap, fmt);
    vfprintf(echo_file, fmt, ap);
    va_end(ap);
    fputc('\n', echo_file);
    fflush(echo_file);
    echo_last_wall_ms = emu_wall_ms();
}

uint64_t emu_echo_quiet_ms(void)
{
    return emu_wall_ms() - echo_last_wall_ms;
}

uint64_t emu_wall_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (uint64_t)t.tv_sec * 1000u + (uint64_t)t.tv_nsec / 1000000u;
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
