/* text_parse_avr.c - feeds decimal words to lib's text_parse_real, built by avr-gcc for the
 * ATmega2560 (double is float there, and strtod is avr-libc's), and reports every word whose float
 * differs from the nearest float bit for bit. Runs in the emulator (build/motionemu):
 * test/emu/checks_text_parse.py starts it and reads its serial lines.
 *
 * The table (build/emu/real_words.h) comes from test/emu/text_parse_avr/gen_real_words.py: each
 * word, the bits of its nearest float (computed exactly in Python) and its class: exact (text_parse.h
 * promises the nearest float) or fallback (strtod's result, counted only). Timer1 runs at the CPU
 * clock and times each call, so the cost per number is measured too.
 *
 * Serial (UART0 at 2 Mbaud, 8N1): "READY text_parse_avr", one line per differing word
 * "MISMATCH <class> <index> <word> want 0x<bits> got 0x<bits> status <n>" (status 0 = MS_OK),
 * "CYCLES exact_mean=<n> exact_max=<n> fallback_mean=<n> fallback_max=<n>" (cycles of one
 * text_parse_real call; 65535 means at least that many), and last "DONE words=<n> exact=<n>
 * exact_mismatches=<n> fallback=<n> fallback_mismatches=<n> fallback_max_ulps=<n> rejected=<n>".
 */
#include <avr/io.h>
#include <avr/pgmspace.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "avr_uart.h"
#include "real_words.h"
#include "text_parse.h"

static uint32_t bits_of(double f)
{
    uint32_t b;
    memcpy(&b, &f, sizeof b);
    return b;
}

/* cycles of one call (Timer1 at clk/1; 65535 when it overflowed) */
static uint16_t timed_parse(const char *word, double *v, motion_status_t *st)
{
    uint16_t t;
    TCNT1 = 0;
    TIFR1 = _BV(TOV1);
    *st = text_parse_real(word, -INFINITY, INFINITY, v);
    t = TCNT1;
    return (TIFR1 & _BV(TOV1)) ? 0xFFFFU : t;
}

static char line[128];

/* Limits and underflow on the float target (issue 12 item 6): each word with its limits and the
 * status the decimal itself calls for. Every "beyond" word here rounds to the limit in float. */
typedef struct {
    const char *word;
    float lo, hi;
    motion_status_t want;
} limit_case_t;
static const limit_case_t limit_cases[] = {
    {"5000.0001", 0, 5000, MS_ERR_OUT_OF_RANGE},   /* stepper vmax */
    {"10000000.1", 0, 1e7f, MS_ERR_OUT_OF_RANGE},  /* stepper accel */
    {"1000.00001", 0, 1000, MS_ERR_OUT_OF_RANGE},  /* servo gains */
    {"5.0000001", 0, 5, MS_ERR_OUT_OF_RANGE},      /* filter u */
    {"-100.000001", -100, 100, MS_ERR_OUT_OF_RANGE},
    {"4999.9999", 0, 5000, MS_OK},
    {"5000", 0, 5000, MS_OK},
    {"1e-46", -1, 1, MS_ERR_UNDERFLOW},
    {"1e-400", -1, 1, MS_ERR_UNDERFLOW},
    {"-1e-39", -1, 1, MS_ERR_UNDERFLOW},           /* a float subnormal */
    {"2e-38", -1, 1, MS_OK},                       /* above FLT_MIN */
    {"0e-400", -1, 1, MS_OK},
};

static void check_limits(void)
{
    uint16_t i, bad = 0;
    for (i = 0; i < sizeof limit_cases / sizeof limit_cases[0]; i++) {
        double v = 0.0;
        motion_status_t st = text_parse_real(limit_cases[i].word, limit_cases[i].lo, limit_cases[i].hi, &v);
        if (st != limit_cases[i].want) {
            bad++;
            snprintf(line, sizeof line, "LIMIT %s status %d want %d", limit_cases[i].word, (int)st,
                     (int)limit_cases[i].want);
            println(line);
        }
    }
    snprintf(line, sizeof line, "LIMITS cases=%u mismatches=%u", i, bad);
    println(line);
}

int main(void)
{
    uint16_t i, n_exact = 0, n_fallback = 0, exact_bad = 0, fallback_bad = 0, rejected = 0;
    uint16_t exact_max = 0, fallback_max = 0;
    uint32_t exact_sum = 0, fallback_sum = 0, max_ulps = 0;
    /* double must be the 32-bit float here, or this would not test what the Mega runs */
    typedef char double_is_float[sizeof(double) == sizeof(float) ? 1 : -1];
    (void)sizeof(double_is_float);
    UCSR0A = _BV(U2X0);
    UBRR0 = 0; /* 2 Mbaud: 16 MHz / (8 * 1) */
    UCSR0C = _BV(UCSZ01) | _BV(UCSZ00);
    UCSR0B = _BV(TXEN0);
    TCCR1A = 0;
    TCCR1B = _BV(CS10);
    println("READY text_parse_avr");
    for (i = 0; i < RW_N_WORDS; i++) {
        rw_entry_t e;
        double v = 0.0;
        motion_status_t st;
        uint16_t cycles;
        uint32_t got;
        memcpy_PF(&e, pgm_get_far_address(rw_words) + (uint32_t)i * sizeof e, sizeof e);
        e.word[RW_WORD_MAX] = '\0';
        cycles = timed_parse(e.word, &v, &st);
        got = bits_of(v);
        if (e.exact) {
            n_exact++;
            exact_sum += cycles;
            if (cycles > exact_max)
                exact_max = cycles;
        } else {
            n_fallback++;
            fallback_sum += cycles;
            if (cycles > fallback_max)
                fallback_max = cycles;
        }
        if (st != MS_OK)
            rejected++;
        if (st != MS_OK || got != e.bits) {
            if (e.exact) {
                exact_bad++;
            } else {
                /* units in the last place: same-sign floats are ordered like their bit patterns */
                uint32_t d = got > e.bits ? got - e.bits : e.bits - got;
                fallback_bad++;
                if (st == MS_OK && d > max_ulps)
                    max_ulps = d;
            }
            snprintf(line, sizeof line, "MISMATCH %s %u %s want 0x%08lx got 0x%08lx status %d",
                     e.exact ? "exact" : "fallback", i, e.word, (unsigned long)e.bits, (unsigned long)got, (int)st);
            println(line);
        }
    }
    snprintf(line, sizeof line, "CYCLES exact_mean=%lu exact_max=%u fallback_mean=%lu fallback_max=%u",
             (unsigned long)(n_exact ? exact_sum / n_exact : 0), exact_max,
             (unsigned long)(n_fallback ? fallback_sum / n_fallback : 0), fallback_max);
    println(line);
    check_limits();
    snprintf(line, sizeof line,
             "DONE words=%u exact=%u exact_mismatches=%u fallback=%u fallback_mismatches=%u fallback_max_ulps=%lu "
             "rejected=%u",
             i, n_exact, exact_bad, n_fallback, fallback_bad, (unsigned long)max_ulps, rejected);
    println(line);
    for (;;)
        ;
}
