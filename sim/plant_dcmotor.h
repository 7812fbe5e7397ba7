/* sim/plant_dcmotor.h - a small 12 V DC gearmotor driven by PWM duty through an H-bridge, with a
 * quadrature encoder on the motor shaft counted x4 by an LS7366R: the plant the servo sketches
 * (the lab handout sections 4.1-4.2) control. Shared by `motionsim servo`, the unit tests and the
 * ATmega2560 emulator harness (which drives it from the sketch's PWM/DIR pins).
 *
 * Model (everything referred to the motor shaft, SI units):
 *   duty u in %, saturated to [-100, 100]; dead zone of +-deadband_pct:
 *     u_eff = 0 if |u| <= db, else sign(u) (|u| - db) 100 / (100 - db)
 *   armature voltage      V = u_eff/100 (supply_v - bridge_drop_v)
 *   current (quasi-static, L/R ~ 0.5 ms << 20 ms control period, not modelled)
 *                         i = (V - k w) / R
 *   J dw/dt = k i - b w - Tc sign(w)                    while turning (w != 0)
 *   at rest (w = 0) the shaft stays stuck while |k V / R| <= Ts (static friction, breakaway),
 *   otherwise it starts in the direction of k V / R.
 *   Position: theta (rad) integrates w; encoder count = floor(theta 64/(2 pi) + 1/2), i.e. the
 *   LS7366R's x4 count of a 64 counts/rev encoder whose state edges lie half a count either side
 *   of the start position; it is reported as a wrapping 32-bit counter (int32).
 *
 * Integration is exact: between events the speed obeys a linear ODE with constant coefficients,
 *   w(t) = w_inf + (w0 - w_inf) e^(-t/tau),  tau = J / (k^2/R + b),  w_inf = (k V/R - Tc s)/(k^2/R + b)
 * and theta is its closed-form integral; the only events (speed reaching zero, where the stick/
 * breakaway test is made) are solved for analytically. So any step, 1 us or 1 s, gives the same
 * answer to rounding; no sub-steps are needed and the cost per call is a few exp() calls.
 *
 * Duty is the PWM duty averaged over the step (the mean of the pin's high time over whole PWM
 * periods, signed by DIR). The model has no electrical dynamics, so feeding the instantaneous
 * 0 %/100 % pin level at a sub-PWM-period resolution is NOT equivalent: the dead zone and the
 * breakaway test act on the mean drive. An emulator should measure the duty over each PWM period
 * (or read the timer's compare register) and hold it for the next period.
 *
 * Default parameters: a Pololu 37D metal gearmotor, 12 V, 30:1, with 64 CPR motor-shaft encoder
 * (Pololu item #4752, pololu.com/product/4752; the figures are from Pololu's 37D comparison table,
 * where the 30:1 row lists #4742 without and #4752 with encoder, and the "37D Metal Gearmotors"
 * datasheet), driven by an Arduino Motor Shield R3 (L298P) from a 12 V supply. Datasheet figures
 * at 12 V: 330 rpm and 0.15 A free-run (9900 rpm at the motor), 5.5 A stall (extrapolated), 64
 * counts per motor revolution = 1920 per output revolution, "can begin rotating at voltages as low
 * as 1 V".
 *
 *   parameter            default      source / derivation
 *   supply_v             12.0 V       the motor's rated voltage
 *   bridge_drop_v        2.0 V        L298 bipolar bridge: 1.5-2.5 V total saturation drop
 *   deadband_pct         2.0 %        brush contact drop ~0.2 V of the 10 V available (estimate)
 *   resistance_ohm       2.18 ohm     R = 12 V / 5.5 A stall current
 *   k_v_s_per_rad        0.01126      k = (12 V - R 0.15 A) / (9900 rpm = 1036.7 rad/s) (back-EMF
 *                                     constant in V s/rad = torque constant in N m/A)
 *   coulomb_nm           1.0e-3 N m   part of the free-run friction k 0.15 A = 1.69e-3 N m
 *   viscous_nm_s_per_rad 6.65e-7      the rest of it at free-run speed: (1.69e-3 - 1.0e-3)/1036.7
 *   static_nm            2.0e-3 N m   breakaway: 0.39 V at rest (the datasheet: starts at <= 1 V)
 *   inertia_kg_m2        2.0e-6       rotor (~40 g iron core, r ~ 10 mm) + gear train + light load,
 *                                     an estimate: mechanical time constant tau = 34 ms
 *   gear_ratio           30           output revolutions = motor revolutions / 30
 *   counts_per_rev       64           LS7366R x4 counts per motor revolution
 * With these, the defaults reproduce the datasheet's 9900 rpm free-run at 12 V without the
 * bridge (by construction: k and the friction split come from that point) and 5.5 A stall. On
 * the shield, 100 % duty gives 861 rad/s (8220 rpm motor, 274 rpm output, ~8770 counts/s); the
 * motor breaks away at 5.8 % duty and, once turning, keeps turning down to 3.9 % duty.
 *
 * Limitation - no bridge current limit. The L298 is rated 2 A DC per bridge (2.5 A repetitive, 3 A
 * non-repetitive 100 us peaks; the Motor Shield R3 states 2 A per channel) and has no current
 * limiting of its own. The model draws whatever i = (V - k w)/R gives: at 100 % duty from
 * standstill 10 V / 2.18 ohm = 4.58 A, above 2 A for the first 30 ms of the run-up; at standstill
 * any duty above 44.8 % exceeds 2 A (a stalled shaft would stay there). The real bridge's
 * saturation drop also grows with current (L298 datasheet, "typical saturation voltage vs. output
 * current"), where the model keeps a fixed 2 V, so large duty steps from rest (e.g. Kp 0.1 on a
 * 1000-count step: 100 %) accelerate somewhat faster in the model than on a real shield, which
 * would run outside its rating or shut down thermally. Not modelled because the part's behaviour
 * beyond its rating is not specified.
 */
#ifndef PLANT_DCMOTOR_H
#define PLANT_DCMOTOR_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    double supply_v;             /* H-bridge supply */
    double bridge_drop_v;        /* bridge saturation drop while conducting (subtracted from supply) */
    double deadband_pct;         /* |duty| at or below this gives no voltage, 0 <= db < 100 */
    double resistance_ohm;       /* armature resistance R */
    double k_v_s_per_rad;        /* back-EMF constant = torque constant k (N m/A) */
    double coulomb_nm;           /* kinetic (Coulomb) friction torque Tc at the motor shaft */
    double viscous_nm_s_per_rad; /* viscous friction b */
    double static_nm;            /* breakaway torque Ts >= Tc */
    double inertia_kg_m2;        /* total inertia J referred to the motor shaft */
    double gear_ratio;           /* motor revolutions per output revolution */
    double counts_per_rev;       /* encoder counts per motor revolution after x4 decoding */
} plant_dcmotor_params_t;

typedef struct {
    plant_dcmotor_params_t p;
    double omega_rad_s;   /* motor shaft speed */
    double theta_counts;  /* motor shaft angle in encoder counts (continuous) */
    double t_s;           /* time advanced so far */
    double duty_pct;      /* the duty of the last advance (after saturation), for reports */
} plant_dcmotor_t;

/* The Pololu 37D 30:1 12 V + Motor Shield R3 values in the table above. */
void plant_dcmotor_default_params(plant_dcmotor_params_t *p);

/* NULL when the parameters are usable, else a sentence naming the first bad one. */
const char *plant_dcmotor_check_params(const plant_dcmotor_params_t *p);

/* At rest at count 0, time 0. Returns 0, or -1 (m untouched) if the parameters are bad. */
int plant_dcmotor_init(plant_dcmotor_t *m, const plant_dcmotor_params_t *p);

/* Advances by dt_s (any size; dt_s <= 0 or NaN does nothing) with the mean duty duty_pct
 * (saturated to +-100 %, NaN counts as 0) held for the whole step. */
void plant_dcmotor_advance(plant_dcmotor_t *m, double duty_pct, double dt_s);

/* The LS7366R's count now: floor(theta_counts + 1/2) wrapped to 32 bits. */
int32_t plant_dcmotor_count(const plant_dcmotor_t *m);

/* Other readings. */
double plant_dcmotor_speed_rad_s(const plant_dcmotor_t *m);   /* motor shaft */
double plant_dcmotor_output_rpm(const plant_dcmotor_t *m);    /* gearbox output shaft */
double plant_dcmotor_voltage_v(const plant_dcmotor_params_t *p, double duty_pct); /* V for a duty */
double plant_dcmotor_current_a(const plant_dcmotor_t *m);     /* at the last duty */

/* Sets the shaft angle (in counts) at rest, e.g. to start near the 32-bit wrap in a test. */
void plant_dcmotor_set_position_counts(plant_dcmotor_t *m, double counts);

#ifdef __cplusplus
}
#endif

#endif
