/* sim/plant_dcmotor.c - DC gearmotor + H-bridge + x4 quadrature encoder (see plant_dcmotor.h). */
#include "plant_dcmotor.h"

#include <math.h>
#include <stddef.h>

#define TWO_PI 6.283185307179586476925

/* Pololu 37D 12 V datasheet figures the defaults are derived from (see the header's table). */
#define DS_VOLTAGE_V 12.0
#define DS_STALL_CURRENT_A 5.5
#define DS_FREE_CURRENT_A 0.15
#define DS_FREE_RPM_OUTPUT 330.0
#define DS_GEAR_RATIO 30.0
#define DS_COUNTS_PER_REV 64.0

void plant_dcmotor_default_params(plant_dcmotor_params_t *p)
{
    double w_free = DS_FREE_RPM_OUTPUT * DS_GEAR_RATIO * TWO_PI / 60.0; /* 1036.7 rad/s */
    double friction_free_nm;
    p->supply_v = DS_VOLTAGE_V;
    p->bridge_drop_v = 2.0;
    p->deadband_pct = 2.0;
    p->resistance_ohm = DS_VOLTAGE_V / DS_STALL_CURRENT_A;
    p->k_v_s_per_rad = (DS_VOLTAGE_V - p->resistance_ohm * DS_FREE_CURRENT_A) / w_free;
    friction_free_nm = p->k_v_s_per_rad * DS_FREE_CURRENT_A;
    p->coulomb_nm = 1.0e-3;
    p->viscous_nm_s_per_rad = (friction_free_nm - p->coulomb_nm) / w_free;
    p->static_nm = 2.0e-3;
    p->inertia_kg_m2 = 2.0e-6;
    p->gear_ratio = DS_GEAR_RATIO;
    p->counts_per_rev = DS_COUNTS_PER_REV;
}

const char *plant_dcmotor_check_params(const plant_dcmotor_params_t *p)
{
    if (p == NULL)
        return "no parameters";
    if (!(isfinite(p->supply_v) && p->supply_v > 0))
        return "supply voltage must be a finite number > 0 V";
    if (!(isfinite(p->bridge_drop_v) && p->bridge_drop_v >= 0 && p->bridge_drop_v < p->supply_v))
        return "bridge drop must be >= 0 V and below the supply voltage";
    if (!(isfinite(p->deadband_pct) && p->deadband_pct >= 0 && p->deadband_pct < 100))
        return "dead band must be in 0 <= db < 100 %";
    if (!(isfinite(p->resistance_ohm) && p->resistance_ohm > 0))
        return "armature resistance must be > 0 ohm";
    if (!(isfinite(p->k_v_s_per_rad) && p->k_v_s_per_rad > 0))
        return "motor constant k must be > 0 V s/rad";
    if (!(isfinite(p->coulomb_nm) && p->coulomb_nm >= 0))
        return "Coulomb friction must be >= 0 N m";
    if (!(isfinite(p->viscous_nm_s_per_rad) && p->viscous_nm_s_per_rad >= 0))
        return "viscous friction must be >= 0 N m s/rad";
    if (!(isfinite(p->static_nm) && p->static_nm >= p->coulomb_nm))
        return "static friction must be >= the Coulomb friction";
    if (!(isfinite(p->inertia_kg_m2) && p->inertia_kg_m2 > 0))
        return "inertia must be > 0 kg m^2";
    if (!(isfinite(p->gear_ratio) && p->gear_ratio > 0))
        return "gear ratio must be > 0";
    if (!(isfinite(p->counts_per_rev) && p->counts_per_rev > 0))
        return "encoder counts per revolution must be > 0";
    return NULL;
}

int plant_dcmotor_init(plant_dcmotor_t *m, const plant_dcmotor_params_t *p)
{
    if (m == NULL || plant_dcmotor_check_params(p) != NULL)
        return -1;
    m->p = *p;
    m->omega_rad_s = 0.0;
    m->theta_counts = 0.0;
    m->t_s = 0.0;
    m->duty_pct = 0.0;
    return 0;
}

static double saturate_duty(double duty_pct)
{
    if (!(duty_pct == duty_pct)) /* NaN */
        return 0.0;
    if (duty_pct > 100.0)
        return 100.0;
    if (duty_pct < -100.0)
        return -100.0;
    return duty_pct;
}

double plant_dcmotor_voltage_v(const plant_dcmotor_params_t *p, double duty_pct)
{
    double u = saturate_duty(duty_pct);
    double mag = fabs(u);
    double eff;
    if (mag <= p->deadband_pct)
        return 0.0;
    eff = (mag - p->deadband_pct) * 100.0 / (100.0 - p->deadband_pct);
    return (u < 0 ? -eff : eff) / 100.0 * (p->supply_v - p->bridge_drop_v);
}

void plant_dcmotor_advance(plant_dcmotor_t *m, double duty_pct, double dt_s)
{
    const plant_dcmotor_params_t *p = &m->p;
    double v, drive_nm, damping, rate, to_counts, remaining;
    int events = 0;
    if (!(dt_s > 0.0)) /* also NaN */
        return;
    m->duty_pct = saturate_duty(duty_pct);
    v = plant_dcmotor_voltage_v(p, m->duty_pct);
    drive_nm = p->k_v_s_per_rad * v / p->resistance_ohm;   /* torque at standstill */
    damping = p->k_v_s_per_rad * p->k_v_s_per_rad / p->resistance_ohm + p->viscous_nm_s_per_rad;
    rate = damping / p->inertia_kg_m2;                      /* 1/tau */
    to_counts = p->counts_per_rev / TWO_PI;
    remaining = dt_s;
    /* At most: decelerate to zero, then start the other way (or stick): two segments. The
     * counter guards against a third from rounding. */
    while (remaining > 0.0 && events < 4) {
        double s, w_inf, w0 = m->omega_rad_s, decay, t;
        events++;
        if (w0 == 0.0) {
            if (fabs(drive_nm) <= p->static_nm)
                break; /* stuck for the rest of the step */
            s = drive_nm > 0 ? 1.0 : -1.0;
        } else {
            s = w0 > 0 ? 1.0 : -1.0;
        }
        w_inf = (drive_nm - p->coulomb_nm * s) / damping;
        t = remaining;
        if (w0 != 0.0 && w_inf * s < 0.0) {
            /* heading through zero: w(t) = 0 at t = tau ln((w0 - w_inf) / -w_inf) */
            double t_zero = log((w0 - w_inf) / -w_inf) / rate;
            if (t_zero < remaining) {
                t = t_zero;
                m->theta_counts += (w_inf * t - (w0 - w_inf) * expm1(-rate * t) / rate) * to_counts;
                m->omega_rad_s = 0.0;
                remaining -= t;
                continue;
            }
        }
        decay = expm1(-rate * t); /* e^(-t/tau) - 1, accurate for tiny t */
        m->theta_counts += (w_inf * t - (w0 - w_inf) * decay / rate) * to_counts;
        m->omega_rad_s = w_inf + (w0 - w_inf) * (decay + 1.0);
        /* never let rounding flip the sign past zero without the stick test */
        if (m->omega_rad_s * s < 0.0)
            m->omega_rad_s = 0.0;
        remaining = 0.0;
    }
    m->t_s += dt_s;
}

int32_t plant_dcmotor_count(const plant_dcmotor_t *m)
{
    double c = floor(m->theta_counts + 0.5);
    /* wrap to 32 bits: c mod 2^32 as uint32, then two's complement */
    double wrapped = fmod(c, 4294967296.0);
    uint32_t u;
    if (wrapped < 0)
        wrapped += 4294967296.0;
    u = (uint32_t)wrapped;
    if (u <= (uint32_t)INT32_MAX)
        return (int32_t)u;
    return -(int32_t)(~u) - 1;
}

double plant_dcmotor_speed_rad_s(const plant_dcmotor_t *m)
{
    return m->omega_rad_s;
}

double plant_dcmotor_output_rpm(const plant_dcmotor_t *m)
{
    return m->omega_rad_s * 60.0 / TWO_PI / m->p.gear_ratio;
}

double plant_dcmotor_current_a(const plant_dcmotor_t *m)
{
    return (plant_dcmotor_voltage_v(&m->p, m->duty_pct) - m->p.k_v_s_per_rad * m->omega_rad_s) / m->p.resistance_ohm;
}

void plant_dcmotor_set_position_counts(plant_dcmotor_t *m, double counts)
{
    m->theta_counts = counts;
    m->omega_rad_s = 0.0;
}
