/* pctrl.h - proportional position controller, as in the lab's first closed loop (the lab handout
 * section 4.1): duty % = Kp x (setpoint - measured), clamped to -100 ... +100 %.
 *
 * Positions are encoder counts (int32, the LS7366R's 32-bit count); the error is taken as a
 * wrapping 32-bit difference, so it stays right across the counter's wrap as long as the true
 * error fits in int32. Kp is in % per count (the lab uses 0.02). Arithmetic is float on every
 * platform, so the host simulator computes exactly what the Mega computes.
 * Cost on the ATmega2560: one int32->float conversion, one float multiply, two compares
 * (roughly 150-200 cycles).
 */
#ifndef PCTRL_H
#define PCTRL_H

#include <stdint.h>

#include "motion_status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PCTRL_DUTY_MAX_PCT 100.0f

/* Limits shared by the servo sketches' serial commands and `motionsim servo`:
 * setpoints |sp| <= 10^6 counts (about 520 output turns of the 1920 counts/turn gearmotor) stay
 * exactly representable in float (< 2^24) with room for travel beyond them; gains 0..1000. */
#define SERVO_SETPOINT_MAX_COUNTS 1000000L
#define SERVO_GAIN_MAX 1000.0

typedef struct {
    float kp_pct_per_count; /* proportional gain, % duty per count of error */
} pctrl_t;

/* Sets the gain. MS_ERR_NOT_FINITE for NaN/inf, MS_ERR_GAIN_NEGATIVE for kp < 0; on error the
 * controller keeps its previous gain. (pctrl_init is the same call on a fresh controller, which
 * is left with kp = 0 on error.) */
motion_status_t pctrl_init(pctrl_t *c, float kp_pct_per_count);
motion_status_t pctrl_set_kp(pctrl_t *c, float kp_pct_per_count);

/* setpoint - measured as a wrapping 32-bit difference. */
int32_t pctrl_error_counts(int32_t setpoint_counts, int32_t measured_counts);

/* Kp x (setpoint - measured), clamped to [-100, +100] %, with the controller's gain. */
float pctrl_duty_pct(const pctrl_t *c, int32_t setpoint_counts, int32_t measured_counts);

/* The same with the gain given directly (ProportionalClosedLoop keeps Kp as its own variable);
 * pctrl_duty_pct is this call with c's gain. kp must be finite (the sketch's serial commands
 * accept 0..1000 only). */
float pctrl_kp_duty_pct(float kp_pct_per_count, int32_t setpoint_counts, int32_t measured_counts);

#ifdef __cplusplus
}
#endif

#endif
