/* motion_status.h - one status type for every lib/ module, and one function that turns a status
 * into a sentence (shared by the sketches' "ERR <reason>" replies and motionsim's messages).
 *
 * Add a status by adding one X(...) line at the END of MOTION_STATUS_LIST (the numbers of the
 * existing ones stay as they are: code built against an older list keeps its meaning).
 * On AVR the sentences live in flash (PROGMEM), so they cost no SRAM; use motion_status_copy()
 * to get one into a RAM buffer on either platform. Cost: a table lookup and a string copy.
 */
#ifndef MOTION_STATUS_H
#define MOTION_STATUS_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define MOTION_STATUS_LIST(X)                                                                  \
    X(MS_OK, "ok")                                                                             \
    /* generic */                                                                              \
    X(MS_ERR_NULL, "a required argument is missing (NULL pointer)")                            \
    X(MS_ERR_NOT_FINITE, "a parameter is NaN or infinite")                                     \
    X(MS_ERR_BUFFER_TOO_SMALL, "the caller's buffer is too small for these parameters")       \
    /* stepper ramps */                                                                        \
    X(MS_ERR_ACCEL_NOT_POSITIVE, "acceleration must be greater than 0 steps/s^2")              \
    X(MS_ERR_V0_NEGATIVE, "minimum speed v0 must not be negative")                             \
    X(MS_ERR_VMAX_NOT_ABOVE_V0, "maximum speed vmax must be greater than minimum speed v0")    \
    X(MS_ERR_TICK_HZ_ZERO, "tick rate F must be greater than 0 ticks/s")                       \
    X(MS_ERR_INTERVAL_TOO_LONG, "a step interval would exceed 2^32-1 timer ticks")             \
    X(MS_ERR_LEN_TOO_SHORT, "table length must be at least 2")                                 \
    X(MS_ERR_FMAX_NOT_ABOVE_FMIN, "fmax must be greater than fmin")                            \
    X(MS_ERR_FMIN_TOO_LOW, "fmin is below timer_hz/65535: its period does not fit 16 bits (a Stepper: raise setMinSpeed or lower setTickRate)") \
    X(MS_ERR_PERIOD_OUT_OF_RANGE, "a timer period is outside 1..65535 ticks")                  \
    X(MS_ERR_HOLD_ZERO, "each table entry must be held for at least 1 timer period")           \
    X(MS_ERR_FLEX_NOT_POSITIVE, "S-curve flexibility must be greater than 0")                  \
    X(MS_ERR_VMAX_ABOVE_TICK_HZ, "maximum speed vmax must not exceed the tick rate F (1 step per tick)") \
    X(MS_ERR_V0_ZERO_SIMPLISTIC, "the simplistic ramp needs v0 > 0: its first interval is F/v0")  \
    X(MS_ERR_TABLE_MISSING, "the S-curve period table is missing or shorter than len")          \
    X(MS_ERR_ACCEL_PHASE_TOO_LONG, "reaching vmax from rest would take more than 2^34 timer ticks: raise accel or lower vmax") \
    X(MS_ERR_ACCEL_TOO_LOW, "acceleration too low for the exact planner: at least 8 steps/s^2 at a 16 MHz tick (0.5 at 2 MHz; 8 (tick rate / 16 MHz)^2, and at least 0.5)") \
    X(MS_ERR_DERIVED_PARAM, "derived here from fmin, fmax, len, hold and flex: set those instead") \
    X(MS_ERR_COORD_RATIO, "axes too unequal for a coordinated move: an axis moves too few steps for the longest one at this accel") \
    X(MS_ERR_JERK_NOT_POSITIVE, "jerk must be greater than 0 steps/s^3")                      \
    X(MS_ERR_JERK_TOO_LOW, "jerk too low: tau2 = accel/jerk exceeds tau1 = vmax/accel (jerk must be at least accel^2/vmax)") \
    X(MS_ERR_SMOOTH_REVERSE, "the target is behind where a stop now comes to rest: stop first") \
    X(MS_ERR_SMOOTH_TOO_MANY, "too many changes of the target within tau1 + tau2: wait or stop first") \
    X(MS_ERR_SMOOTH_TOO_LONG, "the move would end more than 2^46 timer ticks after its start") \
    /* acceleration/deceleration filters */                                                    \
    X(MS_ERR_TS_NOT_POSITIVE, "sample time Ts must be greater than 0 s")                       \
    X(MS_ERR_TAU_BELOW_TS, "time constant tau must be at least one sample time Ts")            \
    X(MS_ERR_TAU_NOT_MULTIPLE, "tau/Ts must be a whole number of samples")                     \
    X(MS_ERR_TOO_MANY_TAPS, "tau/Ts needs more taps than the buffer holds")                    \
    X(MS_ERR_QUANTUM_NOT_POSITIVE, "input quantum must be greater than 0")                     \
    X(MS_ERR_INPUT_OUT_OF_RANGE, "input is outside the filter's range")                        \
    X(MS_ERR_NOT_WHOLE_QUANTUM, "value must be a whole number of input quanta")                \
    X(MS_ERR_FILTER_KIND, "filter kind must be ma, ma2 or exp")                                \
    /* P and PID control */                                                                    \
    X(MS_ERR_GAIN_NEGATIVE, "gains must not be negative")                                      \
    X(MS_ERR_LIMITS_ORDER, "output minimum must be less than output maximum")                  \
    X(MS_ERR_SAMPLE_TIME, "sample time must be greater than 0 ms")                             \
    /* serial command lines (sketches) */                                                      \
    X(MS_ERR_LINE_TOO_LONG, "line too long")                                                   \
    X(MS_ERR_BINARY, "line contains a non-printable byte")                                     \
    X(MS_ERR_NOT_A_NUMBER, "not a number")                                                     \
    X(MS_ERR_OUT_OF_RANGE, "number out of range")                                              \
    X(MS_ERR_UNKNOWN_COMMAND, "unknown command")                                               \
    X(MS_ERR_BUSY, "busy: a move is in progress")                                              \
    X(MS_ERR_UNDERFLOW, "number too close to 0 (underflow)")                                    \
    X(MS_ERR_INPUT_OVERRUN, "input overrun")                                                   \
    /* added later: kept at the end so that no earlier status changes its number */            \
    X(MS_ERR_NOT_BEGUN, "begin() has not been called: nothing moves before it")                \
    X(MS_ERR_NOT_SUPPORTED, "not supported by this ramp algorithm (the exact ramp only)")     \
    X(MS_ERR_AXIS_TAKEN, "axis taken: another Stepper has begun on it")                         \
    X(MS_ERR_RAMP_NOT_HERE, "the constructor takes the exact, Leib, simplistic or sigmoid ramp: the smooth one comes with setRamp(RAMP_ALGO_SMOOTH)") \
    X(MS_ERR_NO_PLANNER_TIMER, "no planner interrupt: #include <MotionStepper.h>")         \
    X(MS_ERR_NO_MEMORY, "not enough SRAM: this Stepper's buffers and the stack's reserve (BOARD_STACK_RESERVE) do not fit") \
    X(MS_ERR_RAMP_LIMIT, "vmax or accel above this ramp's limit: lower them first (STEPPER_MAX_SPS_* in StepperPins.h; docs/library.md, setRamp)") \
    X(MS_ERR_ABOVE_LIMIT, "number out of range: above this Stepper's limit (maxSpeedLimit(), accelerationLimit() and minSpeedLimit() give it)")

#define MOTION_STATUS_ENUM_ITEM(id, text) id,
typedef enum { MOTION_STATUS_LIST(MOTION_STATUS_ENUM_ITEM) MS__COUNT } motion_status_t;
#undef MOTION_STATUS_ENUM_ITEM

/* The sentence for a status. On AVR the pointer is a PROGMEM address (read it with
 * pgm_read_byte or print it as a __FlashStringHelper); on the host an ordinary string.
 * An unknown value gives "unknown status". */
const char *motion_status_text(motion_status_t s);

/* Copies the sentence into buf (always NUL-terminated, truncated to n-1 characters) on any
 * platform. Returns the number of characters copied. */
size_t motion_status_copy(motion_status_t s, char *buf, size_t n);

#ifdef __cplusplus
}
#endif

#endif
