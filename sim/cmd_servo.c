/* sim/cmd_servo.c - `motionsim servo`: the 20 ms position loop of the ProportionalClosedLoop and
 * PIDClosedLoop sketches (the lab handout sections 4.1-4.2) closed around the DC-motor plant
 * (sim/plant_dcmotor.h), with the same controller code and number format as the Mega:
 *
 *   at t_k = k x period:   position := encoder count (the LS7366R read that starts the period)
 *                          duty := P: pctrl_duty_pct (float)   PID: Compute() of pidv1_ctrl, float
 *                                  (PID_v1 set up as the sketch: limits -100..100, sample time =
 *                                  period, AUTOMATIC; the PID clock is t_k in ms)
 *   at t_k + latency:      the bridge gets duty_pwm_from_pct(duty): 8-bit PWM + polarity, i.e.
 *                          the plant sees +-pwm x 100/255 %
 * One CSV row per period: t_s,setpoint,position_counts,error_counts,duty_pct (the duty as the
 * controller computed it, before the 8-bit quantisation). The setpoint steps from the plant's
 * rest position 0 at t = 0. --metrics prints the step-response figures on stderr (stdout stays
 * pure CSV); see step_metrics() for the definitions (overshoot against the setpoint; rise and
 * settling time only when the trace has settled).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <stdlib.h>

#include "cli.h"
#include "commands.h"
#include "csv.h"
#include "csv_float.h"
#include "duty_pwm.h"
#include "pctrl.h"
#include "pidv1_ctrl.h"
#include "plant_dcmotor.h"
#include "smooth_move.h"

/* Time from the encoder sample to the new duty on the motor, as on the Mega (measured in simavr
 * at 16 MHz, see README "Servo timing"): the rest of the LS7366R read (~30 us at 4 MHz SPI), the
 * controller (PID Compute ~1550-1820 cycles, P ~310-370), duty -> PWM and analogWrite (~1530
 * cycles): about 0.2 ms of code; then the timer's double-buffered compare register takes the new
 * value only at the end of the running 490 Hz PWM period, on average half of 2.04 ms later. */
#define SERVO_DEFAULT_LATENCY_US 1200

enum { CTRL_P = 0, CTRL_PID = 1 };
enum { PREC_FLOAT = 0, PREC_DOUBLE = 1 };
enum { PROFILE_STEP = 0, PROFILE_SMOOTH = 1 };

/* --profile smooth's defaults: the servo sketches' `move` (counts/s, /s^2, /s^3) */
#define SERVO_MOVE_VMAX 3000.0
#define SERVO_MOVE_ACCEL 20000.0
#define SERVO_MOVE_JERK 400000.0

/* The trace counts as settled when its last SERVO_SETTLE_SAMPLES samples lie within the 2 % band
 * around the final one (so it moved less than the band during that window). */
#define SERVO_SETTLE_SAMPLES 10

typedef struct {
    double rise_time_s, overshoot_pct, settling_time_s, sse_counts, final_counts, peak_counts;
    int settled;
} metrics_t;

/* The time at which f(t) = (y(t) - y0)/(yf - y0) first reaches level, linearly interpolated
 * between samples; NaN if never. */
static double crossing_time(const double *t, const double *frac, size_t n, double level)
{
    size_t i;
    if (n > 0 && frac[0] >= level)
        return t[0];
    for (i = 1; i < n; i++)
        if (frac[i] >= level)
            return t[i - 1] + (level - frac[i - 1]) / (frac[i] - frac[i - 1]) * (t[i] - t[i - 1]);
    return NAN;
}

/* Step-response figures. y0 = the first sample, yf = the last, step = setpoint - y0:
 *   overshoot        the largest excursion beyond the setpoint in the step's direction, as
 *                    max(0, max_k sign(step) (y_k - setpoint)) / |step| x 100 %  (NaN if step = 0)
 *   steady-state error  setpoint - yf (counts)
 *   settled          the last SERVO_SETTLE_SAMPLES samples are all within the 2 % band
 *                    |y - yf| <= 0.02 |yf - y0|: otherwise the trace is still moving at the end
 *                    and yf is not a final value
 *   settling time    (settled only) the first sample time after which |y - yf| stays within
 *                    that band for good
 *   rise time        (settled only) 10 % -> 90 % of yf - y0, first crossings interpolated
 *                    between samples (MATLAB stepinfo's definitions relative to yf)
 * Unsettled, rise and settling time are NaN; rise time is NaN too if yf = y0. With friction a P
 * loop stops short of the setpoint: yf is where it stopped, the error says how far that is. */
static metrics_t step_metrics(const double *t, const double *y, size_t n, double setpoint)
{
    metrics_t m;
    double y0 = y[0], yf = y[n - 1], span = yf - y0, step = setpoint - y0;
    double dir = step >= 0 ? 1.0 : -1.0, excess = 0.0;
    double *frac;
    size_t i, last_out = 0;
    int outside = 0;
    m.final_counts = yf;
    m.sse_counts = setpoint - yf;
    m.peak_counts = y0;
    m.rise_time_s = m.settling_time_s = NAN;
    m.settled = 0;
    for (i = 0; i < n; i++) {
        if ((y[i] - y0) * dir > (m.peak_counts - y0) * dir)
            m.peak_counts = y[i];
        if ((y[i] - setpoint) * dir > excess)
            excess = (y[i] - setpoint) * dir;
    }
    m.overshoot_pct = step != 0.0 ? excess / fabs(step) * 100.0 : NAN;
    for (i = 0; i < n; i++)
        if (fabs(y[i] - yf) > 0.02 * fabs(span)) {
            last_out = i;
            outside = 1;
        }
    m.settled = n > SERVO_SETTLE_SAMPLES && (!outside || last_out < n - SERVO_SETTLE_SAMPLES);
    if (!m.settled)
        return m;
    m.settling_time_s = outside ? t[last_out + 1] - t[0] : 0.0;
    if (span == 0.0) /* it never left y0 (or came back to it): no rise */
        return m;
    frac = calloc(n, sizeof *frac);
    if (frac == NULL)
        return m;
    for (i = 0; i < n; i++)
        frac[i] = (y[i] - y0) / span;
    m.rise_time_s = crossing_time(t, frac, n, 0.9) - crossing_time(t, frac, n, 0.1);
    free(frac);
    return m;
}

int cmd_servo(int argc, char **argv)
{
    int ctrl = CTRL_P, precision = PREC_FLOAT, want_metrics = 0;
    int seen_ki = 0, seen_kd = 0, seen_precision = 0;
    int profile = PROFILE_STEP, seen_profile = 0, seen_shape[3] = {0, 0, 0};
    double mv_vmax = SERVO_MOVE_VMAX, mv_accel = SERVO_MOVE_ACCEL, mv_jerk = SERVO_MOVE_JERK;
    double peak_duty = 0.0, peak_track = 0.0;
    smooth_setpoint_t shaped;
    double kp = 0.02, ki = 0.0, kd = 0.0, duration_s = 3.0;
    int32_t setpoint = 1000, period_ms = 20, latency_us = SERVO_DEFAULT_LATENCY_US;
    const char *out_path = NULL;
    const cli_opt_t opts[] = {
        {"--ctrl", CLI_CHOICE, &ctrl, NULL, "controller: p (ProportionalClosedLoop) or pid (PIDClosedLoop); default p", "p|pid", NULL},
        {"--kp", CLI_DOUBLE, &kp, "X", "proportional gain, % duty per count (default 0.02, the lab's)", NULL, NULL},
        {"--ki", CLI_DOUBLE, &ki, "X", "integral gain, % per count-second (--ctrl pid only; default 0)", NULL, &seen_ki},
        {"--kd", CLI_DOUBLE, &kd, "X", "derivative gain, % per count/s (--ctrl pid only; default 0)", NULL, &seen_kd},
        {"--setpoint", CLI_INT32, &setpoint, "COUNTS", "position setpoint in encoder counts, |sp| <= 1000000 (default 1000)", NULL, NULL},
        {"--duration", CLI_DOUBLE, &duration_s, "S", "simulated time in s, 0 < S <= 3600 (default 3)", NULL, NULL},
        {"--period-ms", CLI_INT32, &period_ms, "MS", "control period in ms, 1..1000 (default 20, as the sketches)", NULL, NULL},
        {"--latency-us", CLI_INT32, &latency_us, "US", "encoder sample -> new duty at the motor, 0..period (default 1200)", NULL, NULL},
        {"--precision", CLI_CHOICE, &precision, NULL, "PID arithmetic: float (as on the Mega; default) or double (--ctrl pid only)", "float|double", &seen_precision},
        {"--metrics", CLI_FLAG, &want_metrics, NULL, "print rise time, overshoot, settling time, steady-state error on stderr", NULL, NULL},
        {"--profile", CLI_CHOICE, &profile, NULL, "setpoint: step (jumps at t = 0, the handout's) or smooth (the sketches' 'move': the filter-shaped move)", "step|smooth", &seen_profile},
        {"--vmax", CLI_DOUBLE, &mv_vmax, "CPS", "--profile smooth: command height, counts/s (default 3000)", NULL, &seen_shape[0]},
        {"--accel", CLI_DOUBLE, &mv_accel, "CPS2", "--profile smooth: peak acceleration, counts/s^2 (default 20000)", NULL, &seen_shape[1]},
        {"--jerk", CLI_DOUBLE, &mv_jerk, "CPS3", "--profile smooth: peak jerk, counts/s^3 (default 400000)", NULL, &seen_shape[2]},
        {"-o", CLI_STRING, &out_path, "FILE", "write the CSV to FILE instead of stdout", NULL, NULL},
    };
    const cli_spec_t spec = {
        "servo", "[--ctrl p|pid] [--kp X] [--ki X] [--kd X] [--setpoint COUNTS] [--duration S] [--precision float|double] [--metrics] [-o FILE]",
        "Closed-loop position control of the DC gearmotor + LS7366R encoder plant (Pololu 37D 30:1\n"
        "12 V, 64 counts/motor turn, on an L298P shield): samples the count every period, runs the\n"
        "sketch's controller (P, or PID_v1 behaviour in float), drives the plant with the 8-bit PWM\n"
        "duty after --latency-us. CSV: t_s,setpoint,position_counts,error_counts,duty_pct.\n"
        "--metrics: one line on stderr, 'metrics: rise_time_s=.. overshoot_pct=.. settling_time_s=..\n"
        "steady_state_error_counts=.. final_position_counts=.. peak_position_counts=.. settled=0|1'.\n"
        "With y0 the first and yf the last position: overshoot = the largest excursion beyond the\n"
        "setpoint in the step's direction / |setpoint - y0| x 100; steady-state error = setpoint - yf;\n"
        "settled=1 when the last 10 samples lie within 2 % of |yf - y0| around yf, else the run ended\n"
        "while still moving (settled=0, rise and settling time nan: run longer); settling time = the\n"
        "first time after which |y - yf| stays within that band; rise time = 10 % -> 90 % of yf - y0.\n"
        "--profile smooth: the setpoint follows the filter-shaped move to --setpoint (lib/src/smooth_move.h,\n"
        "as the sketches' 'move <counts>'; the CSV's setpoint column is the one in force each period);\n"
        "with --profile (step or smooth) --metrics adds peak_duty_pct (largest |duty|) and\n"
        "peak_tracking_error_counts (largest |setpoint in force - position|); overshoot and the\n"
        "other figures are against the final setpoint.",
        opts, sizeof opts / sizeof opts[0], 0};
    plant_dcmotor_params_t params;
    plant_dcmotor_t plant;
    pctrl_t pc;
    pidf_ctrl_t pf;
    pid_ctrl_t pd;
    float in_f = 0, out_f = 0, sp_f = 0;
    double in_d = 0, out_d = 0, sp_d = 0;
    double applied = 0.0, *t_log = NULL, *y_log = NULL;
    size_t n_steps, k;
    FILE *f;
    motion_status_t st = MS_OK;
    int rc = cli_parse(&spec, argc, argv, NULL, NULL);
    if (rc >= 0)
        return rc;
    /* options the P controller would silently ignore are refused */
    if (ctrl == CTRL_P && (seen_ki || seen_kd))
        return cli_error(argv[0], "%s needs --ctrl pid (the P controller has only kp)", seen_ki ? "--ki" : "--kd");
    if (ctrl == CTRL_P && seen_precision)
        return cli_error(argv[0], "--precision needs --ctrl pid (the P controller is float, as on the Mega)");
    if (profile != PROFILE_SMOOTH && (seen_shape[0] || seen_shape[1] || seen_shape[2]))
        return cli_error(argv[0], "%s needs --profile smooth", seen_shape[0] ? "--vmax" : seen_shape[1] ? "--accel" : "--jerk");
    if (profile == PROFILE_SMOOTH) {
        smooth_params_t mp;
        mp.vmax_sps = mv_vmax;
        mp.accel_sps2 = mv_accel;
        mp.jerk_sps3 = mv_jerk;
        mp.tick_hz = 1000000U;
        if (cli_float_range(mv_vmax) || cli_float_range(mv_accel) || cli_float_range(mv_jerk))
            return cli_error(argv[0], "--vmax/--accel/--jerk: does not fit a float (the sketches compute in float)");
        st = smooth_setpoint_init(&shaped, &mp, 0);
        if (st != MS_OK) {
            /* the statuses speak of a stepper's steps; the servo's unit is the encoder count */
            char text[160];
            const char *from = motion_status_text(st), *hit;
            size_t k = 0;
            while ((hit = strstr(from, "steps/s")) != NULL && k + (size_t)(hit - from) + 9 < sizeof text) {
                memcpy(text + k, from, (size_t)(hit - from));
                k += (size_t)(hit - from);
                memcpy(text + k, "counts/s", 8);
                k += 8;
                from = hit + 7;
            }
            snprintf(text + k, sizeof text - k, "%s", from);
            return cli_error(argv[0], "--profile smooth: %s", text);
        }
        (void)smooth_setpoint_move(&shaped, 0, setpoint);
    }
    if (kp < 0 || ki < 0 || kd < 0)
        return cli_error(argv[0], "%s: %s", kp < 0 ? "--kp" : ki < 0 ? "--ki" : "--kd", motion_status_text(MS_ERR_GAIN_NEGATIVE));
    if (kp > SERVO_GAIN_MAX || ki > SERVO_GAIN_MAX || kd > SERVO_GAIN_MAX)
        return cli_error(argv[0], "%s: gains must be at most %g", kp > SERVO_GAIN_MAX ? "--kp" : ki > SERVO_GAIN_MAX ? "--ki" : "--kd",
                         SERVO_GAIN_MAX);
    if (setpoint < -SERVO_SETPOINT_MAX_COUNTS || setpoint > SERVO_SETPOINT_MAX_COUNTS)
        return cli_error(argv[0], "--setpoint: %ld is outside -%ld..%ld counts", (long)setpoint,
                         (long)SERVO_SETPOINT_MAX_COUNTS, (long)SERVO_SETPOINT_MAX_COUNTS);
    if (!(duration_s > 0 && duration_s <= 3600))
        return cli_error(argv[0], "--duration: must be in 0 < S <= 3600 s");
    if (period_ms < 1 || period_ms > 1000)
        return cli_error(argv[0], "--period-ms: must be 1..1000 ms");
    if (latency_us < 0 || latency_us > period_ms * 1000)
        return cli_error(argv[0], "--latency-us: must be 0..%ld (the period)", (long)period_ms * 1000L);

    plant_dcmotor_default_params(&params);
    if (plant_dcmotor_init(&plant, &params) != 0)
        return cli_error(argv[0], "plant: %s", plant_dcmotor_check_params(&params));
    if (ctrl == CTRL_P) {
        st = pctrl_init(&pc, (float)kp);
    } else if (precision == PREC_FLOAT) {
        /* PIDClosedLoop: MotionPID myPID(&Input, &Output, &Setpoint, Kp, Ki, Kd, DIRECT) at
         * millis() = 0, then SetOutputLimits(-100, 100), SetSampleTime(20), SetMode(AUTOMATIC) */
        sp_f = (float)setpoint;
        st = pidf_init(&pf, &in_f, &out_f, &sp_f, (float)kp, (float)ki, (float)kd, PID_P_ON_E, PID_DIRECT, 0);
        if (st == MS_OK)
            st = pidf_set_output_limits(&pf, -100.0f, 100.0f);
        if (st == MS_OK)
            st = pidf_set_sample_time(&pf, period_ms);
        pidf_set_mode(&pf, PID_AUTOMATIC);
    } else {
        sp_d = (double)setpoint;
        st = pid_init(&pd, &in_d, &out_d, &sp_d, kp, ki, kd, PID_P_ON_E, PID_DIRECT, 0);
        if (st == MS_OK)
            st = pid_set_output_limits(&pd, -100.0, 100.0);
        if (st == MS_OK)
            st = pid_set_sample_time(&pd, period_ms);
        pid_set_mode(&pd, PID_AUTOMATIC);
    }
    if (st != MS_OK)
        return cli_error(argv[0], "%s", motion_status_text(st));

    n_steps = (size_t)floor(duration_s * 1000.0 / period_ms + 1e-9) + 1;
    t_log = malloc(n_steps * sizeof *t_log);
    y_log = malloc(n_steps * sizeof *y_log);
    if (t_log == NULL || y_log == NULL) {
        free(t_log);
        free(y_log);
        fprintf(stderr, "motionsim servo: out of memory\n");
        return CLI_EXIT_RUNTIME;
    }
    f = cli_open_output(argv[0], out_path);
    if (f == NULL) {
        free(t_log);
        free(y_log);
        return CLI_EXIT_RUNTIME;
    }
    fputs("t_s,setpoint,position_counts,error_counts,duty_pct\n", f);
    for (k = 0; k < n_steps; k++) {
        uint32_t t_ms = (uint32_t)(k * (size_t)period_ms);
        int32_t position = plant_dcmotor_count(&plant);
        int32_t sp_now = profile == PROFILE_SMOOTH ? smooth_setpoint_at(&shaped, t_ms) : setpoint;
        int32_t error = pctrl_error_counts(sp_now, position);
        double duty;
        sp_f = (float)sp_now;
        sp_d = (double)sp_now;
        if (ctrl == CTRL_P) {
            float d = pctrl_duty_pct(&pc, sp_now, position);
            duty = d;
        } else if (precision == PREC_FLOAT) {
            in_f = (float)position;
            (void)pidf_compute(&pf, t_ms);
            duty = out_f;
        } else {
            in_d = (double)position;
            (void)pid_compute(&pd, t_ms);
            duty = out_d;
        }
        t_log[k] = (double)t_ms / 1000.0;
        y_log[k] = position;
        csv_num(f, t_log[k]);
        fprintf(f, ",%ld,%ld,%ld,", (long)sp_now, (long)position, (long)error);
        if (fabs(duty) > peak_duty)
            peak_duty = fabs(duty);
        if (fabs((double)error) > peak_track)
            peak_track = fabs((double)error);
        if (ctrl == CTRL_PID && precision == PREC_DOUBLE)
            csv_num(f, duty);
        else
            csv_num_f32(f, (float)duty);
        fputc('\n', f);
        if (ferror(f))
            break; /* cli_close_output reports it */
        /* the old duty until the new one reaches the pin, then the new one to the next sample */
        plant_dcmotor_advance(&plant, applied, latency_us * 1e-6);
        applied = duty_pwm_applied_pct(duty_pwm_from_pct((float)duty));
        plant_dcmotor_advance(&plant, applied, period_ms * 1e-3 - latency_us * 1e-6);
    }
    rc = cli_close_output(argv[0], f, out_path);
    if (want_metrics && rc == CLI_EXIT_OK) {
        metrics_t m = step_metrics(t_log, y_log, n_steps, setpoint);
        fprintf(stderr,
                "metrics: rise_time_s=%.4f overshoot_pct=%.3f settling_time_s=%.4f steady_state_error_counts=%.0f "
                "final_position_counts=%.0f peak_position_counts=%.0f settled=%d",
                m.rise_time_s, m.overshoot_pct, m.settling_time_s, m.sse_counts, m.final_counts, m.peak_counts,
                m.settled);
        if (seen_profile)
            fprintf(stderr, " peak_duty_pct=%.2f peak_tracking_error_counts=%.0f", peak_duty, peak_track);
        fputc('\n', stderr);
    }
    free(t_log);
    free(y_log);
    return rc;
}
