/* text_parse.h - strict parsing of the words and numbers in a command line (sketch serial
 * protocols). Pure logic, no stdio. A number must be the whole word: "12", "-7", "2.5", "1e3";
 * "12abc", "", "1.2.3", "nan", "inf" and overflowing values are rejected with a status, and the
 * output is left untouched on error. Cost on the AVR (measured by the emulator check
 * test/emu/checks_text_parse.py): text_parse_real about 1,440 cycles (90 us) per number, up
 * to 3,300 for short decimals and 6,700 beyond them.
 */
#ifndef TEXT_PARSE_H
#define TEXT_PARSE_H

#include <stddef.h>
#include <stdint.h>

#include "motion_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Skips leading blanks, then copies the next blank-separated word of *cursor into word
 * (NUL-terminated, at most n-1 characters) and advances *cursor past it. Returns the word's
 * length, 0 at the end of the text, or -1 when the word does not fit (it is then skipped). */
int text_next_word(const char **cursor, char *word, size_t n);

/* True when only blanks remain at cursor. */
int text_at_end(const char *cursor);

/* Whole-word integer in [lo, hi]: optional sign, decimal digits only.
 * MS_ERR_NOT_A_NUMBER, MS_ERR_OUT_OF_RANGE, or MS_OK. */
motion_status_t text_parse_int32(const char *word, int32_t lo, int32_t hi, int32_t *out);

/* Whole-word number whose value is a whole number, in [lo, hi] (targets and setpoints: "1e3",
 * "2.5e3", "+12", "1000.0", "-0" are numbers of steps as "1000", "2500", "12", "1000", "0").
 * The word has text_parse_real's shape ([sign] digits [. digits] [e [sign] digits]) and is
 * evaluated exactly, in integers (the digits and the exponent are counted, never rounded through
 * a float: every int32 is exact, on the AVR too, where double is a 32-bit float).
 * MS_OK with *out set; MS_ERR_NOT_A_NUMBER for a word of another shape; TEXT_PARSE_NOT_WHOLE for
 * a number with a nonzero fraction ("1.5", "1e-3", "2.0001"); MS_ERR_OUT_OF_RANGE for a whole
 * number outside [lo, hi], however large ("1e999", "99999999999"). *out is untouched on error. */
motion_status_t text_parse_whole(const char *word, int32_t lo, int32_t hi, int32_t *out);

/* What text_parse_whole returns for a number that is not whole. motion_status.h has no sentence
 * of its own for it yet, so it is "not a number", and the caller's detail says what has to be
 * whole ("ERR not a number: a target is a whole number of steps, ..."). */
#define TEXT_PARSE_NOT_WHOLE MS_ERR_NOT_A_NUMBER

/* Whole-word unsigned integer in [lo, hi]: optional '+', decimal digits only. */
motion_status_t text_parse_uint32(const char *word, uint32_t lo, uint32_t hi, uint32_t *out);

/* Whole-word decimal number in [lo, hi]: [sign] digits [. digits] [e [sign] digits], at least
 * one digit in the mantissa; finite. MS_ERR_NOT_A_NUMBER, MS_ERR_OUT_OF_RANGE, MS_ERR_UNDERFLOW
 * (a nonzero word whose magnitude is below the smallest normal double: DBL_MIN, 2.2e-308, on
 * the host; on the AVR, where double is float, FLT_MIN, 1.2e-38), or MS_OK.
 * Limits that are whole numbers (|limit| < 2^31) are compared with the decimal word itself, before
 * rounding: with hi = 5000, "5000.0001" is refused even where it rounds to 5000 (a float), and
 * "4999.99999" is accepted (as the float it rounds to). Other limits are compared with the
 * rounded value.
 * Correctly rounded for up to 8 significant digits (< 2^24) and decimal exponents within +-10
 * (one exact multiply or divide), beyond that as the C library's strtod; avr-libc's strtod alone
 * is one unit off for words such as "0.05", so the board would otherwise run other numbers than
 * motionsim. */
motion_status_t text_parse_real(const char *word, double lo, double hi, double *out);

/* The scan under text_parse_real without limits: MS_OK with *out set, MS_ERR_NOT_A_NUMBER,
 * MS_ERR_OUT_OF_RANGE (overflow: beyond the largest finite double) or MS_ERR_UNDERFLOW. */
motion_status_t text_scan_real(const char *word, double *out);

/* Case-sensitive word equality, for command names. */
int text_word_is(const char *word, const char *name);

#ifdef __cplusplus
}
#endif

#endif
