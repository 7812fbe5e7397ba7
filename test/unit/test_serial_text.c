/* Unit tests: motion_status, line_reader and text_parse - the pieces every sketch uses to turn
 * Serial Monitor input into commands, and to explain a rejection ("ERR <reason>"). */
#include "cmocka_all.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "line_reader.h"
#include "motion_status.h"
#include "text_parse.h"

/* ---- motion_status ---- */
static void status_every_code_has_a_distinct_sentence(void **state)
{
    int i, j;
    (void)state;
    for (i = 0; i < MS__COUNT; i++) {
        const char *a = motion_status_text((motion_status_t)i);
        assert_non_null(a);
        assert_true(strlen(a) > 1);
        for (j = 0; j < i; j++)
            assert_string_not_equal(a, motion_status_text((motion_status_t)j));
    }
    assert_string_equal(motion_status_text((motion_status_t)MS__COUNT), "unknown status");
}

/* Statuses added after the first release go at the end of the list (motion_status.h's rule), so
 * that no earlier one changes its number: MS_ERR_INPUT_OVERRUN was the last of the first list. */
static void status_later_additions_at_the_end_with_their_sentences(void **state)
{
    (void)state;
    assert_int_equal(MS_ERR_NOT_BEGUN, MS_ERR_INPUT_OVERRUN + 1);
    assert_int_equal(MS_ERR_NOT_SUPPORTED, MS_ERR_INPUT_OVERRUN + 2);
    assert_int_equal(MS_ERR_AXIS_TAKEN, MS_ERR_INPUT_OVERRUN + 3);
    assert_int_equal(MS_ERR_RAMP_NOT_HERE, MS_ERR_INPUT_OVERRUN + 4);
    assert_int_equal(MS_ERR_NO_PLANNER_TIMER, MS_ERR_INPUT_OVERRUN + 5);
    assert_int_equal(MS_ERR_NO_MEMORY, MS_ERR_INPUT_OVERRUN + 6);
    assert_int_equal(MS_ERR_RAMP_LIMIT, MS_ERR_INPUT_OVERRUN + 7);
    assert_int_equal(MS_ERR_ABOVE_LIMIT, MS_ERR_INPUT_OVERRUN + 8);
    assert_int_equal(MS__COUNT, MS_ERR_ABOVE_LIMIT + 1);
    /* the sentence must say what is wrong: begin() missing; a ramp that cannot do this; the axis
     * another Stepper holds; a ramp the constructor does not take and where to take it; the header that
     * links the planner's interrupt; SRAM and the stack's reserve; the ramp's limit and how to meet it;
     * a setter's limit and the calls that give it */
    assert_non_null(strstr(motion_status_text(MS_ERR_NOT_BEGUN), "begin() has not been called"));
    assert_non_null(strstr(motion_status_text(MS_ERR_NOT_SUPPORTED), "not supported by this ramp"));
    assert_non_null(strstr(motion_status_text(MS_ERR_AXIS_TAKEN), "another Stepper"));
    assert_non_null(strstr(motion_status_text(MS_ERR_RAMP_NOT_HERE), "setRamp(RAMP_ALGO_SMOOTH)"));
    assert_non_null(strstr(motion_status_text(MS_ERR_NO_PLANNER_TIMER), "#include <MotionStepper.h>"));
    assert_non_null(strstr(motion_status_text(MS_ERR_NO_MEMORY), "BOARD_STACK_RESERVE"));
    assert_non_null(strstr(motion_status_text(MS_ERR_RAMP_LIMIT), "STEPPER_MAX_SPS_"));
    assert_non_null(strstr(motion_status_text(MS_ERR_ABOVE_LIMIT), "maxSpeedLimit()"));
}

static void status_copy_truncates_and_terminates(void **state)
{
    char buf[8];
    (void)state;
    memset(buf, 'x', sizeof buf);
    assert_int_equal(motion_status_copy(MS_ERR_UNKNOWN_COMMAND, buf, sizeof buf), 7);
    assert_string_equal(buf, "unknown");
    assert_int_equal(motion_status_copy(MS_OK, buf, sizeof buf), 2);
    assert_string_equal(buf, "ok");
    assert_int_equal(motion_status_copy(MS_OK, NULL, 4), 0);
}

/* ---- line_reader ---- */
static int feed(line_reader_t *r, const char *bytes, size_t n, char lines[][48], int *errors, motion_status_t *last_err)
{
    int count = 0;
    size_t i;
    for (i = 0; i < n; i++) {
        motion_status_t e = MS_OK;
        line_event_t ev = line_reader_feed(r, (uint8_t)bytes[i], &e);
        if (ev == LINE_READY)
            strcpy(lines[count++], r->line);
        else if (ev == LINE_ERROR) {
            (*errors)++;
            *last_err = e;
        }
    }
    return count;
}

static void line_endings_cr_lf_crlf_all_end_one_line(void **state)
{
    line_reader_t r;
    char lines[8][48];
    int errors = 0;
    motion_status_t err = MS_OK;
    const char in[] = "100\r200\n300\r\n\r\n\n-5\r\n";
    (void)state;
    line_reader_init(&r);
    assert_int_equal(feed(&r, in, sizeof in - 1, lines, &errors, &err), 4);
    assert_string_equal(lines[0], "100");
    assert_string_equal(lines[1], "200");
    assert_string_equal(lines[2], "300");
    assert_string_equal(lines[3], "-5");
    assert_int_equal(errors, 0);
}

static void long_line_without_newline_gives_one_error_and_no_command(void **state)
{
    line_reader_t r;
    char lines[4][48];
    char big[1024];
    int errors = 0;
    motion_status_t err = MS_OK;
    (void)state;
    memset(big, '7', sizeof big);
    line_reader_init(&r);
    assert_int_equal(feed(&r, big, sizeof big, lines, &errors, &err), 0);
    assert_int_equal(errors, 1);
    assert_int_equal(err, MS_ERR_LINE_TOO_LONG);
    /* its terminator ends the discarded line; the next line is clean */
    assert_int_equal(feed(&r, "\n42\n", 4, lines, &errors, &err), 1);
    assert_string_equal(lines[0], "42");
    assert_int_equal(errors, 1);
}

static void line_of_exactly_max_length_is_accepted(void **state)
{
    line_reader_t r;
    char lines[2][48];
    char in[LINE_READER_MAX + 2];
    int errors = 0;
    motion_status_t err = MS_OK;
    (void)state;
    memset(in, 'a', LINE_READER_MAX);
    in[LINE_READER_MAX] = '\n';
    line_reader_init(&r);
    assert_int_equal(feed(&r, in, LINE_READER_MAX + 1, lines, &errors, &err), 1);
    assert_int_equal(strlen(lines[0]), LINE_READER_MAX);
    assert_int_equal(errors, 0);
}

static void binary_bytes_give_one_error_per_line(void **state)
{
    line_reader_t r;
    char lines[4][48];
    int errors = 0;
    motion_status_t err = MS_OK;
    const char in[] = "12\x00\xff\x01" "34\r\n" "?\r\n";
    (void)state;
    line_reader_init(&r);
    assert_int_equal(feed(&r, in, sizeof in - 1, lines, &errors, &err), 1);
    assert_int_equal(errors, 1);
    assert_int_equal(err, MS_ERR_BINARY);
    assert_string_equal(lines[0], "?");
}

/* Blank lines (only spaces and tabs, any length) are ignored like empty ones: no line, no error
 * (issue 12 item 5: one rule for every sketch, docs/serial.md). */
static void blank_lines_are_ignored_like_empty_ones(void **state)
{
    line_reader_t r;
    char lines[4][48];
    char in[160];
    int errors = 0;
    motion_status_t err = MS_OK;
    (void)state;
    memset(in, ' ', 100); /* longer than a line may be: still blank */
    strcpy(in + 100, "\r\n \t \n\t\r  kp 5\n");
    line_reader_init(&r);
    assert_int_equal(feed(&r, in, strlen(in), lines, &errors, &err), 1);
    assert_int_equal(errors, 0);
    assert_string_equal(lines[0], "kp 5"); /* leading blanks dropped */
}

/* Bytes lost before the next byte: the line in progress is discarded and reported once; the next
 * line is clean. A line already reported bad is not reported again. */
static void overrun_discards_the_line_it_hits(void **state)
{
    line_reader_t r;
    char lines[4][48];
    int errors = 0;
    motion_status_t err = MS_OK;
    (void)state;
    line_reader_init(&r);
    assert_int_equal(feed(&r, "kp 1", 4, lines, &errors, &err), 0);
    assert_int_equal(line_reader_overrun(&r), 1);
    assert_int_equal(feed(&r, "00\r\n?\n", 6, lines, &errors, &err), 1);
    assert_string_equal(lines[0], "?");
    /* at a line boundary: the next line is the one hit */
    assert_int_equal(line_reader_overrun(&r), 1);
    assert_int_equal(feed(&r, "5\n6\n", 4, lines, &errors, &err), 1);
    assert_string_equal(lines[0], "6");
    /* after a CR, the LF may be lost with the rest: the next line is still discarded, once */
    assert_int_equal(feed(&r, "7\r", 2, lines, &errors, &err), 1);
    assert_int_equal(line_reader_overrun(&r), 1);
    assert_int_equal(feed(&r, "8\n9\n", 4, lines, &errors, &err), 1);
    assert_string_equal(lines[0], "9");
    /* already bad: one reply per line */
    assert_int_equal(feed(&r, "1\x01", 2, lines, &errors, &err), 0);
    assert_int_equal(errors, 1);
    assert_int_equal(line_reader_overrun(&r), 0);
    assert_int_equal(feed(&r, "2\n3\n", 4, lines, &errors, &err), 1);
    assert_string_equal(lines[0], "3");
}

/* ---- text_parse ---- */
static void int32_accepts_whole_words_and_full_range(void **state)
{
    int32_t v = 0;
    (void)state;
    assert_int_equal(text_parse_int32("0", INT32_MIN, INT32_MAX, &v), MS_OK);
    assert_int_equal(v, 0);
    assert_int_equal(text_parse_int32("-50", INT32_MIN, INT32_MAX, &v), MS_OK);
    assert_int_equal(v, -50);
    assert_int_equal(text_parse_int32("+2147483647", INT32_MIN, INT32_MAX, &v), MS_OK);
    assert_int_equal(v, INT32_MAX);
    assert_int_equal(text_parse_int32("-2147483648", INT32_MIN, INT32_MAX, &v), MS_OK);
    assert_int_equal(v, INT32_MIN);
}

static void int32_rejects_junk_and_overflow_without_touching_output(void **state)
{
    int32_t v = 1234;
    (void)state;
    assert_int_equal(text_parse_int32("2147483648", INT32_MIN, INT32_MAX, &v), MS_ERR_OUT_OF_RANGE);
    assert_int_equal(text_parse_int32("-2147483649", INT32_MIN, INT32_MAX, &v), MS_ERR_OUT_OF_RANGE);
    assert_int_equal(text_parse_int32("99999999999999999999", INT32_MIN, INT32_MAX, &v), MS_ERR_OUT_OF_RANGE);
    assert_int_equal(text_parse_int32("12abc", INT32_MIN, INT32_MAX, &v), MS_ERR_NOT_A_NUMBER);
    assert_int_equal(text_parse_int32("99999999999999x", INT32_MIN, INT32_MAX, &v), MS_ERR_NOT_A_NUMBER);
    assert_int_equal(text_parse_int32("", INT32_MIN, INT32_MAX, &v), MS_ERR_NOT_A_NUMBER);
    assert_int_equal(text_parse_int32("-", INT32_MIN, INT32_MAX, &v), MS_ERR_NOT_A_NUMBER);
    assert_int_equal(text_parse_int32("1.5", INT32_MIN, INT32_MAX, &v), MS_ERR_NOT_A_NUMBER);
    assert_int_equal(text_parse_int32("101", -100, 100, &v), MS_ERR_OUT_OF_RANGE);
    assert_int_equal(v, 1234);
}

static void real_accepts_decimal_forms(void **state)
{
    double v = 0;
    (void)state;
    assert_int_equal(text_parse_real("2.5", 0, 10, &v), MS_OK);
    assert_true(v == 2.5);
    assert_int_equal(text_parse_real("-.5", -1, 1, &v), MS_OK);
    assert_true(v == -0.5);
    assert_int_equal(text_parse_real("1e3", 0, 1e4, &v), MS_OK);
    assert_true(v == 1000.0);
    assert_int_equal(text_parse_real("7.", 0, 10, &v), MS_OK);
    assert_true(v == 7.0);
}

static void real_rejects_junk_nan_inf_hex_and_range(void **state)
{
    double v = 42;
    (void)state;
    const char *bad[] = {"", ".", "-", "nan", "inf", "-inf", "0x10", "1.2.3", "1e", "1e+", " 1", "1 ", "e5", "abc"};
    size_t i;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++)
        assert_int_equal(text_parse_real(bad[i], -1e9, 1e9, &v), MS_ERR_NOT_A_NUMBER);
    assert_int_equal(text_parse_real("1e999", -1e9, 1e9, &v), MS_ERR_OUT_OF_RANGE);
    assert_int_equal(text_parse_real("5.01", 0, 5, &v), MS_ERR_OUT_OF_RANGE);
    assert_true(v == 42);
}

/* Limits that are whole numbers are compared with the decimal before rounding (issue 12 item 6):
 * these words round to the limit in double, yet lie beyond it; words just inside are accepted. */
static void real_limits_compare_the_decimal_before_rounding(void **state)
{
    static const struct {
        const char *word;
        double lo, hi;
        motion_status_t want;
    } cases[] = {
        {"5000.0000000000000001", 0, 5000, MS_ERR_OUT_OF_RANGE},
        {"10000000.000000000001", 0, 1e7, MS_ERR_OUT_OF_RANGE},
        {"1000.0000000000000001", 0, 1000, MS_ERR_OUT_OF_RANGE},
        {"5.00000000000000001e3", 0, 5000, MS_ERR_OUT_OF_RANGE},
        {"0.50000000000000000001e4", 0, 5000, MS_ERR_OUT_OF_RANGE},
        {"-100.00000000000000001", -100, 100, MS_ERR_OUT_OF_RANGE},
        {"4999.9999999999999999", 0, 5000, MS_OK},
        {"5000", 0, 5000, MS_OK},
        {"5000.000", 0, 5000, MS_OK},
        {"5e3", 0, 5000, MS_OK},
        {"500000e-2", 0, 5000, MS_OK},
        {"0005000.0", 0, 5000, MS_OK},
        {"-99.999999999999999999", -100, 100, MS_OK},
        {"-100.0", -100, 100, MS_OK},
        {"1.00000000000000000001", 0, 1, MS_ERR_OUT_OF_RANGE},
        {"0.99999999999999999999", 0, 1, MS_OK},
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        double v = -7;
        motion_status_t st = text_parse_real(cases[i].word, cases[i].lo, cases[i].hi, &v);
        if (st != cases[i].want)
            fail_msg("%s in [%g, %g]: status %d, want %d", cases[i].word, cases[i].lo, cases[i].hi, st, cases[i].want);
        if (st != MS_OK)
            assert_true(v == -7);
    }
}

/* A nonzero word below the smallest normal double is refused (underflow), not taken as 0 or a
 * subnormal; zero itself in any spelling is fine. */
static void real_refuses_underflow(void **state)
{
    static const char *const tiny[] = {"1e-400", "1e-320", "-2e-310", "0.0000001e-305", "1e-99999"};
    static const char *const zero[] = {"0", "-0.0", "0e-400", "0.000e99999"};
    double v = 3;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof tiny / sizeof tiny[0]; i++)
        assert_int_equal(text_parse_real(tiny[i], -1, 1, &v), MS_ERR_UNDERFLOW);
    assert_true(v == 3);
    assert_int_equal(text_parse_real("2.3e-308", -1, 1, &v), MS_OK); /* just above DBL_MIN */
    for (i = 0; i < sizeof zero / sizeof zero[0]; i++) {
        assert_int_equal(text_parse_real(zero[i], -1, 1, &v), MS_OK);
        assert_true(v == 0);
    }
}

static void uint32_full_range(void **state)
{
    uint32_t v = 9;
    (void)state;
    assert_int_equal(text_parse_uint32("4294967295", 0, UINT32_MAX, &v), MS_OK);
    assert_true(v == UINT32_MAX);
    assert_int_equal(text_parse_uint32("+0", 0, UINT32_MAX, &v), MS_OK);
    assert_true(v == 0);
    v = 9;
    assert_int_equal(text_parse_uint32("4294967296", 0, UINT32_MAX, &v), MS_ERR_OUT_OF_RANGE);
    assert_int_equal(text_parse_uint32("-1", 0, UINT32_MAX, &v), MS_ERR_NOT_A_NUMBER);
    assert_int_equal(text_parse_uint32("0x5", 0, UINT32_MAX, &v), MS_ERR_NOT_A_NUMBER);
    assert_int_equal(text_parse_uint32("", 0, UINT32_MAX, &v), MS_ERR_NOT_A_NUMBER);
    assert_int_equal(text_parse_uint32("11", 1, 10, &v), MS_ERR_OUT_OF_RANGE);
    assert_true(v == 9);
}

/* text_parse_real must return the correctly rounded value (avr-libc's strtod is not; see
 * text_parse.c). The oracle is the host C library's strtod, which is correctly rounded (glibc),
 * on words of every shape: short decimals (the exact fast path), long ones and big exponents. */
static void real_is_correctly_rounded_like_the_host_strtod(void **state)
{
    static const char *const fixed[] = {
        "0.05", "0.15", "0.9", "1.234", "7.7", "0.0005", "0.1", "0.3", "2.0004", "16777216",
        "16777217", "0.050000000", "-0.05", "500", "1005", "1e10", "1e-10", "1.5e-11", "123456.7",
        "0.000000001", "3.14159265358979", "99999999999", "0", "-0", "0e5", "000.0100", "1e+3",
    };
    char word[32];
    uint32_t seed = 12345;
    (void)state;
    for (size_t i = 0; i < sizeof fixed / sizeof fixed[0]; i++) {
        double v = -1.0, want = strtod(fixed[i], NULL);
        assert_int_equal(text_parse_real(fixed[i], -1e12, 1e12, &v), MS_OK);
        assert_memory_equal(&v, &want, sizeof v);
    }
    for (int i = 0; i < 200000; i++) {
        double v = -1.0, want;
        uint32_t m, frac, e;
        seed = seed * 1664525U + 1013904223U;
        m = seed >> 8;                    /* up to 8 digits */
        seed = seed * 1664525U + 1013904223U;
        frac = (seed >> 8) % 9U;          /* digits after the point */
        e = (seed >> 4) % 25U;            /* exponent -12 .. 12 */
        snprintf(word, sizeof word, "%u", (unsigned)m);
        if (frac > 0 && frac < strlen(word)) {
            size_t n = strlen(word);
            memmove(word + n - frac + 1, word + n - frac, frac + 1);
            word[n - frac] = '.';
        }
        if (e != 12)
            snprintf(word + strlen(word), sizeof word - strlen(word), "e%d", (int)e - 12);
        want = strtod(word, NULL);
        assert_int_equal(text_parse_real(word, -1e30, 1e30, &v), MS_OK);
        if (memcmp(&v, &want, sizeof v) != 0)
            fail_msg("'%s': %.17g, strtod %.17g", word, v, want);
    }
}

/* ---- text_parse_whole: targets and setpoints (issue 22 item 4) ---- */
typedef struct {
    const char *word;
    int32_t value;
} whole_case_t;

/* Each value worked out by hand from the decimal word (digits and exponent), no arithmetic of ours. */
static void whole_accepts_every_whole_number_word(void **state)
{
    static const whole_case_t cases[] = {
        {"1e3", 1000}, {"2.5e3", 2500}, {"+12", 12}, {"1000.0", 1000}, {"-0", 0}, {"0e999", 0},
        {"0.000", 0}, {"-0.0e-5", 0}, {"-1E3", -1000}, {".5e1", 5}, {"5.", 5}, {"0.0001e4", 1},
        {"12300e-2", 123}, {"1000000000000e-3", 1000000000}, {"1e9", 1000000000}, {"7", 7},
        {"2147483647", 2147483647}, {"-2147483648", INT32_MIN}, {"2.147483647e9", 2147483647},
        {"-2.147483648E+9", INT32_MIN}, {"21474836.47e2", 2147483647}, {"2147483647.000e0", 2147483647},
        /* beyond a float's 24 bits: exact, as the AVR's 32-bit double could not give them */
        {"16777217", 16777217}, {"1.6777217e7", 16777217}, {"2.147483583e9", 2147483583},
        {"-1.999999999e9", -1999999999}, {"000123", 123}, {"0.00123e5", 123},
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        int32_t v = 42;
        motion_status_t st = text_parse_whole(cases[i].word, INT32_MIN, INT32_MAX, &v);
        if (st != MS_OK || v != cases[i].value)
            fail_msg("'%s': status %d, %ld (want %ld)", cases[i].word, (int)st, (long)v, (long)cases[i].value);
    }
}

static void whole_refuses_fractions_overflow_and_junk_without_touching_output(void **state)
{
    static const char *const fractions[] = {"1.5", "1e-3", "2.0001", "-0.5", "1.00000000001e10", "0.1",
                                            "123456789012345.5", "5e-1", "1e-99999999"};
    static const char *const too_big[] = {"1e999", "99999999999", "2147483648", "-2147483649", "2.147483648e9",
                                          "1e10", "-1e10", "1e99999999999", "4294967296", "10000000000.0",
                                          "21474836.48e2", "-214748364.9e1"};
    static const char *const junk[] = {"", "-", "+", "1e", "e3", "1.2.3", "0x5", "nan", "inf", "12abc", " 1", "1 ",
                                       ".", "+.e1", "1e+", "1e3.0", "--1", "1_000"};
    int32_t v = 1234;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof fractions / sizeof fractions[0]; i++)
        if (text_parse_whole(fractions[i], INT32_MIN, INT32_MAX, &v) != TEXT_PARSE_NOT_WHOLE)
            fail_msg("'%s' is not whole", fractions[i]);
    for (i = 0; i < sizeof too_big / sizeof too_big[0]; i++)
        if (text_parse_whole(too_big[i], INT32_MIN, INT32_MAX, &v) != MS_ERR_OUT_OF_RANGE)
            fail_msg("'%s' is out of range", too_big[i]);
    for (i = 0; i < sizeof junk / sizeof junk[0]; i++)
        if (text_parse_whole(junk[i], INT32_MIN, INT32_MAX, &v) != MS_ERR_NOT_A_NUMBER)
            fail_msg("'%s' is not a number", junk[i]);
    /* the limits, inclusive */
    assert_int_equal(text_parse_whole("101", -100, 100, &v), MS_ERR_OUT_OF_RANGE);
    assert_int_equal(text_parse_whole("-1.01e2", -100, 100, &v), MS_ERR_OUT_OF_RANGE);
    assert_int_equal(text_parse_whole("1e6", -1000000, 999999, &v), MS_ERR_OUT_OF_RANGE);
    assert_int_equal(v, 1234);
    assert_int_equal(text_parse_whole("1e6", -1000000, 1000000, &v), MS_OK);
    assert_int_equal(v, 1000000);
    assert_int_equal(text_parse_whole("-1.0e6", -1000000, 1000000, &v), MS_OK);
    assert_int_equal(v, -1000000);
}

/* Every plain integer word means what text_parse_int32 says, and so do the same digits written
 * with a point and zeros, or as d.ddd e k: the forms are built here by moving characters only. */
static void whole_agrees_with_int32_on_rewritten_words(void **state)
{
    uint32_t x = 12345U;
    int k;
    (void)state;
    for (k = 0; k < 20000; k++) {
        char plain[16], form[40];
        const char *digits;
        int32_t want = 0, got = 0;
        size_t n;
        int32_t v;
        x = x * 1103515245U + 12345U; /* any int32, edges included below */
        v = k < 4 ? (k == 0 ? INT32_MIN : k == 1 ? INT32_MAX : k == 2 ? 0 : -1) : (int32_t)x >> (k % 31);
        snprintf(plain, sizeof plain, "%ld", (long)v);
        assert_int_equal(text_parse_int32(plain, INT32_MIN, INT32_MAX, &want), MS_OK);
        assert_int_equal(text_parse_whole(plain, INT32_MIN, INT32_MAX, &got), MS_OK);
        assert_int_equal(got, want);
        snprintf(form, sizeof form, "%s.000", plain);
        assert_int_equal(text_parse_whole(form, INT32_MIN, INT32_MAX, &got), MS_OK);
        assert_int_equal(got, want);
        /* sign, first digit, '.', the rest, 'e', the count of the rest */
        digits = plain[0] == '-' ? plain + 1 : plain;
        n = strlen(digits);
        snprintf(form, sizeof form, "%s%c.%se%u", plain[0] == '-' ? "-" : "+", digits[0], digits + 1,
                 (unsigned)(n - 1));
        if (text_parse_whole(form, INT32_MIN, INT32_MAX, &got) != MS_OK || got != want)
            fail_msg("'%s': %ld, want %ld", form, (long)got, (long)want);
        /* a nonzero digit after the last one: a fraction */
        snprintf(form, sizeof form, "%s.0001", plain);
        assert_int_equal(text_parse_whole(form, INT32_MIN, INT32_MAX, &got), TEXT_PARSE_NOT_WHOLE);
    }
}

static void words_split_on_blanks(void **state)
{
    const char *cur = "  set\tvmax  20 ";
    char w[8];
    (void)state;
    assert_int_equal(text_next_word(&cur, w, sizeof w), 3);
    assert_true(text_word_is(w, "set"));
    assert_int_equal(text_next_word(&cur, w, sizeof w), 4);
    assert_true(text_word_is(w, "vmax"));
    assert_false(text_word_is(w, "vma"));
    assert_false(text_at_end(cur));
    assert_int_equal(text_next_word(&cur, w, sizeof w), 2);
    assert_true(text_at_end(cur));
    assert_int_equal(text_next_word(&cur, w, sizeof w), 0);
    cur = "waytoolongword x";
    assert_int_equal(text_next_word(&cur, w, sizeof w), -1);
    assert_int_equal(text_next_word(&cur, w, sizeof w), 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(status_every_code_has_a_distinct_sentence),
        cmocka_unit_test(status_later_additions_at_the_end_with_their_sentences),
        cmocka_unit_test(status_copy_truncates_and_terminates),
        cmocka_unit_test(line_endings_cr_lf_crlf_all_end_one_line),
        cmocka_unit_test(long_line_without_newline_gives_one_error_and_no_command),
        cmocka_unit_test(line_of_exactly_max_length_is_accepted),
        cmocka_unit_test(binary_bytes_give_one_error_per_line),
        cmocka_unit_test(blank_lines_are_ignored_like_empty_ones),
        cmocka_unit_test(overrun_discards_the_line_it_hits),
        cmocka_unit_test(int32_accepts_whole_words_and_full_range),
        cmocka_unit_test(int32_rejects_junk_and_overflow_without_touching_output),
        cmocka_unit_test(real_accepts_decimal_forms),
        cmocka_unit_test(real_rejects_junk_nan_inf_hex_and_range),
        cmocka_unit_test(real_is_correctly_rounded_like_the_host_strtod),
        cmocka_unit_test(real_limits_compare_the_decimal_before_rounding),
        cmocka_unit_test(real_refuses_underflow),
        cmocka_unit_test(uint32_full_range),
        cmocka_unit_test(words_split_on_blanks),
        cmocka_unit_test(whole_accepts_every_whole_number_word),
        cmocka_unit_test(whole_refuses_fractions_overflow_and_junk_without_touching_output),
        cmocka_unit_test(whole_agrees_with_int32_on_rewritten_words),
    };
    return cmocka_run_group_tests_name("serial_text", tests, NULL, NULL);
}
