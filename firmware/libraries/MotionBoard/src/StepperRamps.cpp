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

/* ---- SCurveRamp ---- */
SCurveRamp::SCurveRamp(uint16_t len, uint16_t hold, float fmin_hz, float fmax_hz, float flex, float max_sps,
                       uint32_t timer_hz)
    : has_pending_(false), filling_(false), fill_i_(0), fill_pos_(0), accel_time_s_(0), f_first_(0), f_last_(0),
      max_sps_(max_sps)
{
    params_.len = len;
    params_.hold = hold;
    params_.fmin_hz = fmin_hz;
    params_.fmax_hz = fmax_hz;
    params_.flex = flex;
    params_.timer_hz = timer_hz;
    pending_ = params_;
}

motion_status_t SCurveRamp::fill(const ramp_sigmoid_params_t &p)
{
    motion_status_t st = ramp_sigmoid_fill(&p, table_, SCURVE_MAX_LEN);
    if (st != MS_OK)
        return st;
    params_ = p;
    table_done();
    return MS_OK;
}

/* what `?` reports of the table in force, kept so that `?` is answered during a refill too */
void SCurveRamp::table_done()
{
    accel_time_s_ = ramp_sigmoid_accel_time_s(&params_, table_);
    f_first_ = (double)params_.timer_hz / table_[0];
    f_last_ = (double)params_.timer_hz / table_[params_.len - 1U];
}

motion_status_t SCurveRamp::begin()
{
    motion_status_t st = ramp_sigmoid_check(&params_);
    return st != MS_OK ? st : fill(params_);
}

motion_status_t SCurveRamp::setup(step_planner_t &pl, int32_t pos)
{
    return step_planner_init_sigmoid(&pl, &params_, table_, SCURVE_MAX_LEN, pos);
}

bool SCurveRamp::apply(step_planner_t &pl, bool moving)
{
    if (moving)
        return false; /* the table the move is walking must not change under it: at_rest() */
    has_pending_ = true;
    at_rest(pl, step_planner_position(&pl));
    return true;
}

void SCurveRamp::at_rest(step_planner_t &pl, int32_t pos)
{
    if (!has_pending_)
        return;
    has_pending_ = false;
    fill_p_ = pending_; /* checked by set() */
    fill_i_ = 0;
    fill_pos_ = pos;
    filling_ = true;
    (void)busy(pl);
}

bool SCurveRamp::busy(step_planner_t &pl)
{
    uint8_t n;
    if (!filling_)
        return false;
    for (n = 0; n < 2U && fill_i_ < fill_p_.len; n++, fill_i_++)
        table_[fill_i_] = (uint16_t)ramp_sigmoid_period_ticks(&fill_p_, fill_i_);
    if (fill_i_ < fill_p_.len)
        return true;
    filling_ = false;
    params_ = fill_p_;
    table_done();
    (void)setup(pl, fill_pos_);
    return false;
}

motion_status_t SCurveRamp::set(const char *key, const char *value)
{
    ramp_sigmoid_params_t p = pending_;
    double v = 0.0;
    int32_t n = 0;
    motion_status_t st;
    if (text_word_is(key, "v0") || text_word_is(key, "vmax") || text_word_is(key, "flex")) {
        st = text_parse_real(value, -1e7, text_word_is(key, "flex") ? STEPPER_MAX_FLEX : (double)max_sps_, &v);
        if (st == MS_ERR_OUT_OF_RANGE && negative_word(value))
            v = -1.0; /* the table check names the problem with negative values */
        else if (st != MS_OK)
            return st;
        if (text_word_is(key, "v0"))
            p.fmin_hz = (float)v;
        else if (text_word_is(key, "vmax"))
            p.fmax_hz = (float)v;
        else
            p.flex = (float)v;
    } else if (text_word_is(key, "len") || text_word_is(key, "hold")) {
        int32_t hi = text_word_is(key, "len") ? (int32_t)SCURVE_MAX_LEN : 65535L;
        st = text_parse_int32(value, 0, hi, &n);
        if (st == MS_ERR_OUT_OF_RANGE && negative_word(value))
            n = 0; /* below the minimum: the table check says so (len >= 2, hold >= 1) */
        else if (st != MS_OK)
            return st;
        if (text_word_is(key, "len"))
            p.len = (uint16_t)n;
        else
            p.hold = (uint16_t)n;
    } else if (text_word_is(key, "accel")) {
        return MS_ERR_DERIVED_PARAM;
    } else {
        return MS_ERR_UNKNOWN_COMMAND;
    }
    /* checked now (the periods follow from the parameters), filled into the table at rest */
    st = ramp_sigmoid_check(&p);
    if (st != MS_OK)
        return st;
    if (p.fmax_hz > max_sps_)
        return MS_ERR_OUT_OF_RANGE;
    pending_ = p;
    has_pending_ = true;
    return MS_OK;
}

void SCurveRamp::print_param(Print &out, const char *key) const
{
    /* the value set (in force now, or from the next move when set while moving) */
    const ramp_sigmoid_params_t &p = has_pending_ ? pending_ : (filling_ ? fill_p_ : params_);
    out.print(key);
    out.print('=');
    if (text_word_is(key, "v0"))
        stepper_print_real(out, p.fmin_hz);
    else if (text_word_is(key, "vmax"))
        stepper_print_real(out, p.fmax_hz);
    else if (text_word_is(key, "flex"))
        stepper_print_real(out, p.flex);
    else if (text_word_is(key, "len"))
        out.print(p.len);
    else
        out.print(p.hold);
}

void SCurveRamp::print_limit(Print &out, const char *key) const
{
    if (text_word_is(key, "flex"))
        print_upper_limit(out, key, STEPPER_MAX_FLEX, F(""));
    else if (text_word_is(key, "len"))
        print_upper_limit(out, key, SCURVE_MAX_LEN, F(" entries"));
    else if (text_word_is(key, "hold"))
        print_upper_limit(out, key, 65535.0, F(" steps per entry"));
    else
        print_upper_limit(out, key, max_sps_, F(" steps/s"));
}

void SCurveRamp::print_params(Print &out) const
{
    /* the table's own end speeds: timer_hz / period[0] and timer_hz / period[len - 1] */
    double f_first = f_first_, f_last = f_last_;
    out.print(F(" algo=sigmoid "));
    print_param(out, "v0");
    out.print(' ');
    print_param(out, "vmax");
    out.print(F(" accel="));
    stepper_print_real(out, accel_time_s_ > 0 ? (f_last - f_first) / accel_time_s_ : 0.0);
    out.print(F(" tick_hz="));
    out.print(params_.timer_hz);
    out.print(F(" max_sps="));
    stepper_print_real(out, max_sps_);
    out.print(' ');
    print_param(out, "flex");
    out.print(' ');
    print_param(out, "len");
    out.print(' ');
    print_param(out, "hold");
    out.print(F(" accel_steps="));
    out.print(ramp_sigmoid_accel_steps(&params_));
    out.print(F(" accel_time_s="));
    stepper_print_real(out, accel_time_s_);
    out.print(F(" cruise_sps="));
    stepper_print_real(out, f_last);
}
