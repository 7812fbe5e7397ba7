/* StepperRamps.h - the ramp of each axis of the step engine's own console (StepConsole.h: the
 * MultiAxisStepper sketch; the one-axis sketches are users of the MotionStepper library, whose
 * Stepper keeps its own parameters): how a move is planned and which parameters `set` changes. The
 * console talks to it through StepperRamp, and the step engine's planner (lib/src/step_planner.h)
 * gets the parameters from it.
 *
 *   TrapezoidRamp v0, vmax, accel -> lib/src/step_planner.h (exact: step_exact.h; the lab's ramps
 *                 through ramp.h)
 * (The sigmoid table of SCurveStepper, SCurveRamp until 2026-12-05, is now the library's Stepper's:
 * setRamp(RAMP_ALGO_SIGMOID).) The limits below (SCURVE_MAX_LEN, STEPPER_MAX_FLEX ...) are the
 * sketches' and the library's.
 * Every `set` checks the new parameter set with the lib module before keeping it (the longest
 * interval, the 16-bit periods, ...), so a rejected value changes nothing. A value above this
 * sketch's limit is MS_ERR_OUT_OF_RANGE, and the console adds the limit (print_limit):
 * "ERR number out of range: vmax at most 5000 steps/s on this sketch". A value far below any
 * sensible one (beyond the parser's range, e.g. -1e39) is refused as a negative value would be,
 * with the module's sentence ("minimum speed v0 must not be negative").
 */
#ifndef STEPPER_RAMPS_H
#define STEPPER_RAMPS_H

#include <Arduino.h>

#include "PrintReal.h"

#include <motion_status.h>
#include <ramp.h>
#include <step_planner.h>

#include "StepCut.h"
#include "StepperPins.h" /* STEP_ENGINE_LEAD_MS */

class StepperRamp {
public:
    /* Sets the step engine's planner up at rest at pos with this sketch's algorithm and parameters. */
    virtual motion_status_t setup(step_planner_t &pl, int32_t pos) = 0;
    /* `set <key> <value>`: checks and keeps the value (MS_ERR_UNKNOWN_COMMAND when key is not a
     * parameter here); the planner gets it through apply(). */
    virtual motion_status_t set(const char *key, const char *value) = 0;
    /* Hands the kept parameters to the planner: they take effect at its next plan (a new target or
     * a stop; while moving, the move in progress keeps its own). Returns false when they can only
     * apply once the axis is at rest (the S-curve table), which at_rest() then does. */
    virtual bool apply(step_planner_t &pl, bool moving) = 0;
    virtual void at_rest(step_planner_t &pl, int32_t pos) { (void)pl; (void)pos; }
    /* Background work that at_rest() started (the S-curve table's refill), a slice of about 1 ms
     * per call; true while it is not done. Meanwhile loop() keeps running and commands are
     * answered; a move waits for the end of the refill (a few hundred ms at most). */
    virtual bool busy(step_planner_t &pl) { (void)pl; return false; }
    /* " algo=... v0=... vmax=... accel=... tick_hz=... max_sps=..." for `?` (leading blank). */
    virtual void print_params(Print &out) const = 0;
    /* "key=value" of one parameter, for the OK reply to `set`. */
    virtual void print_param(Print &out, const char *key) const = 0;
    /* The largest value `set <key>` accepts, after "ERR number out of range: ", e.g.
     * "vmax at most 5000 steps/s on this sketch" (key: one `set` accepted). */
    virtual void print_limit(Print &out, const char *key) const = 0;
    /* The step timer's rate for this algorithm, ticks/s. */
    virtual uint32_t tick_hz() const = 0;
    /* How far ahead the step engine plans, ms (MultiStepEngine::set_lead_ms). */
    virtual uint16_t lead_ms() const { return STEP_ENGINE_LEAD_MS; }
    /* A stop or a new target planned from a cut of the queue (StepCut.h's step_cut_plan), for the
     * ramps that can (the exact one): NULL for the others, which act after the queued lead. */
    typedef bool (*CutFn)(uint8_t axis, step_planner_t *pl, bool stop, int32_t target, const StepCutTiming &t,
                          int32_t *from, uint16_t *missed);
    virtual CutFn cut() const { return 0; }

protected:
    ~StepperRamp() {}
};

/* Called between the slow steps of stepper_print_real (the console points it at the step engine's
 * service, so that formatting a long reply never lets the step queue run dry). */
extern void (*stepper_print_hook)();
/* Prints a real number with the fewest decimals (up to 6) that read back as the same value ("20",
 * "0.5", "333.3"), else with 7 significant digits ("1.234567e-01"): PrintReal.h. */
inline void stepper_print_real(Print &out, double v) { print_real_exact(out, v, stepper_print_hook); }

/* The largest acceleration `set accel` accepts on the trapezoid sketches, steps/s^2. The exact
 * ramp's is lower: far above it, near max_sps, its first commands span a step or two each and the
 * planner falls behind the step interrupt (underruns: found by `make fuzz`; twice this value was
 * already marginal; test/emu/checks_reliability.py checks the corners of the limits). */
#define STEPPER_MAX_ACCEL 1e7
#ifndef STEPPER_MAX_ACCEL_EXACT
#define STEPPER_MAX_ACCEL_EXACT 1e6
#endif
/* The exact ramp's largest start speed v0: a move from rest begins at v0 at once, before the
 * planner is far ahead; much above it the first commands come faster than it lays them out
 * (underruns found by a fresh-clone review at v0 35,000, vmax 70,000; test/emu/
 * checks_reliability.py checks the corners). No stepper starts that fast from rest anyway. */
#ifndef STEPPER_MAX_V0_EXACT
#define STEPPER_MAX_V0_EXACT 10000.0
#endif
/* The largest S-curve flexibility `set flex` accepts. */
#define STEPPER_MAX_FLEX 1000.0

class TrapezoidRamp : public StepperRamp {
public:
    /* algo: RAMP_ALGO_SIMPLISTIC, RAMP_ALGO_LEIB or RAMP_ALGO_EXACT; max_sps: the fastest step
     * rate `set` allows; tick_hz: the step timer (2 MHz for the lab's ramps, 16 MHz for exact);
     * hooks: the sketch's own pre-computation and computeNewSpeed() (ramp.h), or NULL for lib's. */
    inline __attribute__((always_inline)) TrapezoidRamp(ramp_algo_t algo, double v0_sps, double vmax_sps,
                                                        double accel_sps2, double max_sps, uint32_t tick_hz,
                                                        const ramp_hooks_t *hooks = 0)
        : TrapezoidRamp(algo == RAMP_ALGO_EXACT ? &EXACT_KIND : &LAB_KIND, algo, v0_sps, vmax_sps, accel_sps2,
                        max_sps, tick_hz, hooks)
    {
    }
    /* The planner's half a ramp uses (lib's step_planner_init_exact or _lab, and the check of a
     * parameter set): chosen by the algorithm in the inline constructor above, so a sketch whose
     * ramps are all exact, or all the lab's, links only that half of the planner. */
    struct Kind {
        motion_status_t (*init)(step_planner_t *pl, ramp_algo_t algo, const ramp_params_t *p, const ramp_hooks_t *hooks,
                                int32_t pos);
        motion_status_t (*probe)(ramp_algo_t algo, const ramp_params_t *p, const ramp_hooks_t *hooks);
        CutFn cut;
    };
    static const Kind EXACT_KIND, LAB_KIND;
    motion_status_t setup(step_planner_t &pl, int32_t pos) override;
    motion_status_t set(const char *key, const char *value) override;
    bool apply(step_planner_t &pl, bool moving) override;
    uint32_t tick_hz() const override { return params_.tick_hz; }
    CutFn cut() const override { return kind_->cut; }
    uint16_t lead_ms() const override
    {
        return algo_ == RAMP_ALGO_LEIB ? STEP_ENGINE_LEAD_MS_LEIB : STEP_ENGINE_LEAD_MS;
    }
    void print_params(Print &out) const override;
    void print_param(Print &out, const char *key) const override;
    void print_limit(Print &out, const char *key) const override;

private:
    TrapezoidRamp(const Kind *kind, ramp_algo_t algo, double v0_sps, double vmax_sps, double accel_sps2,
                  double max_sps, uint32_t tick_hz, const ramp_hooks_t *hooks);
    const Kind *kind_;
    ramp_algo_t algo_;
    ramp_params_t params_;
    double max_sps_;
    double max_accel() const { return algo_ == RAMP_ALGO_EXACT ? STEPPER_MAX_ACCEL_EXACT : STEPPER_MAX_ACCEL; }
    double max_v0() const
    {
        double v = algo_ == RAMP_ALGO_EXACT ? STEPPER_MAX_V0_EXACT : max_sps_;
        return v < max_sps_ ? v : max_sps_;
    }
    const ramp_hooks_t *hooks_;
};

#ifndef SCURVE_MAX_LEN
#define SCURVE_MAX_LEN 1000 /* table entries: 2 bytes of SRAM each */
#endif


#endif
