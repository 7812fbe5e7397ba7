/* StepperRamps.cpp - move planning and `set` parameters of the stepper sketches (see StepperRamps.h). */
#include "StepperRamps.h"

#include <stdlib.h>
#include <text_parse.h>

#include "StepCut.h"


void (*stepper_print_hook)() = 0;

/* A number word beyond the parser's range on the negative side ("-1e39"): refused below as any
 * negative value is, with the module's own sentence, not as "out of range" with an upper limit. */
static bool negative_word(const char *value)
{
    return value[0] == '-';
}

static void print_upper_limit(Print &out, const char *key, double limit, const __FlashStringHelper *unit)
{
    out.print(key);
    out.print(F(" at most "));
    stepper_print_real(out, limit);
    out.print(unit);
    out.print(F(" on this sketch"));
}

/* ---- TrapezoidRamp ---- */
static motion_status_t exact_init(step_planner_t *pl, ramp_algo_t, const ramp_params_t *p, const ramp_hooks_t *,
                                  int32_t pos)
{
    return step_planner_init_exact(pl, p, pos);
}
static motion_status_t exact_probe(ramp_algo_t, const ramp_params_t *p, const ramp_hooks_t *)
{
    step_planner_t probe; /* the exact planner checks its own limits */
    return step_planner_init_exact(&probe, p, 0);
}
static motion_status_t lab_probe(ramp_algo_t algo, const ramp_params_t *p, const ramp_hooks_t *hooks)
{
    /* a one-step move has the longest first interval of all moves: if it plans, every move does */
    ramp_t probe;
    return ramp_plan_hooked(&probe, algo, p, hooks, 0, 1);
}
/* the cut of the queue (StepCut.h) only for the exact ramp on Timer1 (the timed-loop build steps
 * from loop(), with no interrupt to cut ahead of) */
#if STEPPER_TIMED_LOOP
const TrapezoidRamp::Kind TrapezoidRamp::EXACT_KIND = {exact_init, exact_probe, 0};
#else
const TrapezoidRamp::Kind TrapezoidRamp::EXACT_KIND = {exact_init, exact_probe, step_cut_plan};
#endif
const TrapezoidRamp::Kind TrapezoidRamp::LAB_KIND = {step_planner_init_lab, lab_probe, 0};

TrapezoidRamp::TrapezoidRamp(const Kind *kind, ramp_algo_t algo, double v0_sps, double vmax_sps, double accel_sps2,
                             double max_sps, uint32_t tick_hz, const ramp_hooks_t *hooks)
    : kind_(kind), algo_(algo), max_sps_(max_sps), hooks_(hooks)
{
    params_.v0_sps = v0_sps;
    params_.vmax_sps = vmax_sps;
    params_.accel_sps2 = accel_sps2;
    params_.tick_hz = tick_hz;
}

motion_status_t TrapezoidRamp::setup(step_planner_t &pl, int32_t pos)
{
    return kind_->init(&pl, algo_, &params_, hooks_, pos);
}

bool TrapezoidRamp::apply(step_planner_t &pl, bool moving)
{
    (void)moving;
    (void)step_planner_set_params(&pl, &params_); /* checked by set() */
    return true;
}

motion_status_t TrapezoidRamp::set(const char *key, const char *value)
{
    ramp_params_t p = params_;
    double v = 0.0;
    double *field;
    double hi = max_sps_;
    motion_status_t st;
    if (text_word_is(key, "v0")) {
        field = &p.v0_sps;
        hi = max_v0();
    } else if (text_word_is(key, "vmax"))
        field = &p.vmax_sps;
    else if (text_word_is(key, "accel")) {
        field = &p.accel_sps2;
        hi = max_accel();
    } else
        return MS_ERR_UNKNOWN_COMMAND;
    st = text_parse_real(value, -1e7, hi, &v);
    if (st == MS_ERR_OUT_OF_RANGE && negative_word(value))
        v = -1.0; /* the module check below names the problem with negative values */
    else if (st != MS_OK)
        return st;
    *field = v;
    st = kind_->probe(algo_, &p, hooks_);
    if (st != MS_OK)
        return st;
    params_ = p;
    return MS_OK;
}

void TrapezoidRamp::print_param(Print &out, const char *key) const
{
    out.print(key);
    out.print('=');
    if (text_word_is(key, "v0"))
        stepper_print_real(out, params_.v0_sps);
    else if (text_word_is(key, "vmax"))
        stepper_print_real(out, params_.vmax_sps);
    else
        stepper_print_real(out, params_.accel_sps2);
}

void TrapezoidRamp::print_limit(Print &out, const char *key) const
{
    if (text_word_is(key, "accel"))
        print_upper_limit(out, key, max_accel(), F(" steps/s^2"));
    else if (text_word_is(key, "v0"))
        print_upper_limit(out, key, max_v0(), F(" steps/s"));
    else
        print_upper_limit(out, key, max_sps_, F(" steps/s"));
}

void TrapezoidRamp::print_params(Print &out) const
{
    out.print(F(" algo="));
    out.print(ramp_algo_name(algo_));
    out.print(' ');
    print_param(out, "v0");
    out.print(' ');
    print_param(out, "vmax");
    out.print(' ');
    print_param(out, "accel");
    out.print(F(" tick_hz="));
    out.print(params_.tick_hz);
    out.print(F(" max_sps="));
    stepper_print_real(out, max_sps_);
}
