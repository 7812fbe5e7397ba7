/* accdec_filter.h - one interface over the three acceleration/deceleration filters of the moving-average-filter note,
 * so motionsim and the MovingAverageFilter sketch run the very same code for any kind:
 *   ma   moving average, N1 = tau/Ts taps            (ma_filter.h,  linear acceleration)
 *   ma2  two moving averages in series, N1 + N2 taps (ma2_filter.h, S-curve acceleration)
 *   exp  first-order lag 1/(tau s + 1), N1 = tau/Ts  (exp_filter.h, exponential acceleration)
 *
 * Two phases, so a sketch can validate in loop() and switch inside its sample interrupt:
 * accdec_configure() checks the parameters and precomputes everything (it never touches a
 * running filter); accdec_start() puts a filter at rest with that configuration (cheap, no
 * floating point). Outputs are exact rationals: y[k] = q * num / den, den fixed per configuration
 * (N, 2 N1 N2 or 65536). Delay convention of ma_filter.h: step(u[k]) returns y[k], which depends
 * on u[k-1], u[k-2], ... only. AVR cost per sample: that of the kind plus a switch.
 */
#ifndef ACCDEC_FILTER_H
#define ACCDEC_FILTER_H

#include <stdint.h>

#include "exp_filter.h"
#include "ma2_filter.h"
#include "ma_filter.h"
#include "motion_status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum { ACCDEC_MA = 0, ACCDEC_MA2 = 1, ACCDEC_EXP = 2, ACCDEC_KIND_COUNT = 3 } accdec_kind_t;

typedef struct {
    accdec_kind_t kind;
    uint16_t taps1;      /* N1 = tau/Ts */
    uint16_t taps2;      /* N2 = tau2/Ts (ma2 only, else 0) */
    uint32_t gain_q31;   /* exp only: round(2^31 (1 - e^(-1/N1))), else 0 */
} accdec_config_t;

typedef struct {
    accdec_config_t cfg;
    union {
        ma_filter_t ma;
        ma2_filter_t ma2;
        exp_filter_t exp;
    } f;
} accdec_filter_t;

/* "ma", "ma2", "exp" (NULL for an invalid kind). */
const char *accdec_kind_name(accdec_kind_t kind);

/* Kind from its name. MS_ERR_NULL, MS_ERR_FILTER_KIND, or MS_OK (*kind untouched on error). */
motion_status_t accdec_kind_parse(const char *name, accdec_kind_t *kind);

/* Validates and precomputes: N1 = tau/Ts (and N2 = tau2/Ts for ma2; tau2 is ignored by the
 * other kinds) with filt_taps(), the ring-buffer taps against buf_len (ma: N1, ma2: N1 + N2,
 * exp: none), the exp gain. Any status of filt_taps(), MS_ERR_FILTER_KIND, MS_ERR_TOO_MANY_TAPS,
 * or MS_OK; *cfg untouched on error. */
motion_status_t accdec_configure(accdec_config_t *cfg, accdec_kind_t kind, double tau_s, double tau2_s,
                                 double ts_s, uint16_t buf_len);

/* Ring-buffer taps the configuration needs (0 for exp). */
uint16_t accdec_buffer_taps(const accdec_config_t *cfg);

/* y = q * num / den: den = N1 (ma), 2 N1 N2 (ma2), 65536 (exp). */
uint32_t accdec_den(const accdec_config_t *cfg);

/* Puts f at rest (every past sample 0) with cfg, using buf[0..buf_len) (may be NULL for exp).
 * The status of the kind's init (MS_ERR_NULL, MS_ERR_TOO_MANY_TAPS, ...) or MS_OK. */
motion_status_t accdec_start(accdec_filter_t *f, const accdec_config_t *cfg, int16_t *buf, uint16_t buf_len);

/* Back to rest with the same configuration. */
void accdec_reset(accdec_filter_t *f);

/* num of y[k] for the current instant k (before u[k] is given). */
int64_t accdec_peek(const accdec_filter_t *f);

/* One sample: returns num of y[k], then takes u = u[k] (a count of quanta). */
int64_t accdec_step(accdec_filter_t *f, int16_t u);

/* round(1000 * num / den), halves away from zero: y in thousandths of a quantum (microvolts when
 * q = 1 mV), computed in integers so the sketch and motionsim print the same digits.
 * A 64-bit division: about 900-1,600 cycles on the AVR (the sketch calls it in loop()). */
int32_t accdec_milli_quanta(int64_t num, uint32_t den);

#ifdef __cplusplus
}
#endif

#endif
