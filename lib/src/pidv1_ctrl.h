/* pidv1_ctrl.h - PID controller with the exact behaviour of the Arduino PID library PID_v1 1.2.1
 * (Brett Beauregard), as a C module: the same sample-time gating, gain scaling, integral clamp,
 * derivative on measurement, P_ON_E/P_ON_M, MANUAL/AUTOMATIC with its Initialize, direction
 * quirks and argument checks, in the same order of operations (P + (I - D)), so it reproduces
 * vectors recorded from the real library bit for bit (test/data/pid_v1/, the lab handout section 4.2).
 *
 * One computation (when AUTOMATIC and now - last_time >= sample_time, unsigned, wrap-safe):
 *   error = setpoint - input;  d_input = input - last_input
 *   output_sum += ki*error;  [P_ON_M: output_sum -= kp*d_input];  clamp output_sum to limits
 *   output = (P_ON_E ? kp*error : 0) + (output_sum - kd*d_input);  clamp;  *output_var = output
 *   last_input = input;  last_time = now          (the elapsed time is never used in the sums)
 * Working gains: kp = Kp, ki = Ki*T, kd = Kd/T with T = sample_time_ms/1000, negated when the
 * direction is REVERSE; set_sample_time rescales ki and kd by new/old instead of recomputing.
 *
 * Two builds of one body (pidv1_ctrl_body.h): pid_* in double and pidf_* in float, so a host program
 * can run both precisions; on the AVR double is float, so pid_* there is what the Mega runs.
 * Clock: unsigned 32-bit milliseconds passed in by the caller (millis() on the board).
 * Units: whatever the linked variables use (here encoder counts in, PWM duty % out).
 * Cost on the ATmega2560 (float): one computation is ~10 float multiply/adds, see README figures.
 *
 * Rejections (the call is ignored exactly as PID_v1 ignores it; the C API also says why):
 *   set_tunings with any gain < 0 -> MS_ERR_GAIN_NEGATIVE (the POn argument is ignored too)
 *   set_output_limits with min >= max -> MS_ERR_LIMITS_ORDER
 *   set_sample_time with ms <= 0 -> MS_ERR_SAMPLE_TIME
 * Not validated, as in PID_v1: mode (only 1 is AUTOMATIC), direction (only 1 is REVERSE),
 * POn (only 1 is P_ON_E), NaN/infinite gains and limits. Callers validate user input first.
 */
#ifndef PIDV1_CTRL_H
#define PIDV1_CTRL_H

#include <stdint.h>

#include "motion_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* PID_v1's constants (same values). */
#define PID_MANUAL 0
#define PID_AUTOMATIC 1
#define PID_DIRECT 0
#define PID_REVERSE 1
#define PID_P_ON_M 0
#define PID_P_ON_E 1

/* The controller state, for real = double (pid_ctrl_t) or float (pidf_ctrl_t). Fields are
 * public for inspection (tests compare them with the reference vectors); change them only
 * through the functions. output_sum and last_input are 0 until the first MANUAL->AUTOMATIC
 * switch (PID_v1 leaves them uninitialised). */
#define PID_V1_STATE(real)                                                                     \
    struct {                                                                                   \
        real *input;                 /* linked variables (PID_v1's myInput/myOutput/mySetpoint) */ \
        real *output;                                                                          \
        real *setpoint;                                                                        \
        real disp_kp, disp_ki, disp_kd; /* last accepted user gains (GetKp/GetKi/GetKd) */      \
        real kp, ki, kd;             /* working gains: scaled by the sample time, signed */     \
        real output_sum;             /* integral accumulator, in output units */               \
        real last_input;                                                                       \
        real out_min, out_max;                                                                 \
        uint32_t last_time_ms;                                                                 \
        uint32_t sample_time_ms;                                                               \
        int32_t direction;           /* stored as given (GetDirection) */                      \
        int32_t p_on;                /* stored POn as given */                                 \
        uint8_t p_on_e;              /* 1 when POn == P_ON_E */                                \
        uint8_t in_auto;             /* 1 = AUTOMATIC */                                       \
    }

typedef PID_V1_STATE(double) pid_ctrl_t;
typedef PID_V1_STATE(float) pidf_ctrl_t;

/* The API, declared for both precisions. For pid_* read real = double, for pidf_* float.
 *
 * init: PID_v1's constructor PID(Input, Output, Setpoint, Kp, Ki, Kd, POn, Direction) at time
 *   now_ms: MANUAL, limits 0..255, sample time 100 ms, direction stored, tunings applied,
 *   last_time = now_ms - 100. The linked variables are not touched. MS_ERR_NULL if a pointer
 *   is NULL (nothing is written). With a negative gain the tunings are rejected as in PID_v1
 *   (MS_ERR_GAIN_NEGATIVE); where PID_v1 leaves its members unset this module gives them the
 *   values they have in a zero-initialised (global) PID_v1 object: gains 0 and POn 0 = P_ON_M,
 *   so a later 3-argument set_tunings computes proportional-on-measurement, as PID_v1 does.
 * compute: PID_v1's Compute() at time now_ms; returns 1 when it computed, else 0.
 * set_mode: only PID_AUTOMATIC (1) selects AUTOMATIC; MANUAL->AUTOMATIC runs Initialize
 *   (output_sum := *output clamped to the limits, last_input := *input).
 * set_output_limits: ignored unless min < max; in AUTOMATIC also clamps *output and output_sum.
 * set_tunings: 3-argument form keeps the stored POn; set_tunings_pon is the 4-argument form.
 * set_sample_time: ignored unless ms > 0; rescales ki by new/old and kd by old/new.
 * set_direction: negates the working gains only when AUTOMATIC and d differs; always stores d.
 */
#define PID_V1_API(real, P, T)                                                                       \
    motion_status_t P##init(T *c, real *input, real *output, real *setpoint, real kp, real ki, real kd, \
                            int32_t p_on, int32_t direction, uint32_t now_ms);                       \
    uint8_t P##compute(T *c, uint32_t now_ms);                                                       \
    void P##set_mode(T *c, int32_t mode);                                                            \
    motion_status_t P##set_output_limits(T *c, real out_min, real out_max);                          \
    motion_status_t P##set_tunings(T *c, real kp, real ki, real kd);                                 \
    motion_status_t P##set_tunings_pon(T *c, real kp, real ki, real kd, int32_t p_on);               \
    motion_status_t P##set_sample_time(T *c, int32_t sample_time_ms);                                \
    void P##set_direction(T *c, int32_t direction);                                                  \
    real P##get_kp(const T *c);                                                                      \
    real P##get_ki(const T *c);                                                                      \
    real P##get_kd(const T *c);                                                                      \
    int32_t P##get_mode(const T *c);                                                                 \
    int32_t P##get_direction(const T *c);

PID_V1_API(double, pid_, pid_ctrl_t)
PID_V1_API(float, pidf_, pidf_ctrl_t)

#ifdef __cplusplus
}
#endif

#endif
