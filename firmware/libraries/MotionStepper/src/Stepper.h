/* Stepper.h - one RAMPS 1.4 stepper axis (X, Y or Z) with the exact constant-acceleration ramp,
 * called as AccelStepper's and FastAccelStepper's users call theirs (docs/library.md has the table).
 *
 *   Stepper x(Stepper::X);
 *   setup():  x.setMaxSpeed(20000); x.setAcceleration(50000); x.begin(); x.moveTo(10000);
 *   loop():   if (!x.isRunning()) ...   (loop() is free: Timer3 plans, Timer1 steps)
 *
 * Units: positions in steps (long), speeds in steps/s, acceleration in steps/s^2. Every call that
 * can refuse returns a motion_status_t (lib's motion_status.h): MS_OK, or the reason, and then it has
 * changed nothing; statusText() gives the same sentence as the sketches' serial "ERR" lines.
 * Limits (those of the MultiAxisStepper sketch): setMaxSpeed up to MULTI_MAX_SPS (MultiAxisPins.h; the
 * lab's ramps of setRamp: STEPPER_MAX_SPS_LEIB / _SIMPLISTIC; a sketch with one Stepper that plans
 * from loop(), BackgroundPlanner::planInLoop(), as ExactRampStepper: STEPPER_MAX_SPS_EXACT),
 * setAcceleration up to STEPPER_MAX_ACCEL_EXACT, setMinSpeed up to STEPPER_MAX_V0_EXACT
 * (StepperPins.h); above them MS_ERR_ABOVE_LIMIT, never a silent clamp; parameter sets the exact
 * planner refuses (vmax not above v0, accel below 8 steps/s^2, ...) get its own status. New
 * parameters take effect at the next moveTo/move/stop (the move in progress keeps its own).
 * Before begin() nothing moves: moveTo, move, stop, forceStop, setCurrentPosition return
 * MS_ERR_NOT_BEGUN ("begin() has not been called"); the setters only keep their values.
 * Call the methods from loop() or setup() (not from an interrupt).
 *
 * Pins (the RAMPS board's, MultiAxisPins.h): X STEP D54 DIR D55 EN D38; Y STEP D60 DIR D61 EN D56;
 * Z STEP D46 DIR D48 EN D62. STEP is fixed (the step interrupt writes its port); DIR and ENABLE can
 * move to other pins (setDirectionPin, setEnablePin), and polarity can change: setDirectionInverted(true)
 * makes DIR low count up (a motor wired the other way), setEnableActiveHigh(true) for drivers enabled
 * by a high EN (RAMPS's A4988/DRV8825 are enabled low: the default).
 */
#ifndef MOTION_STEPPER_STEPPER_H
#define MOTION_STEPPER_STEPPER_H

#include <Arduino.h>
#include <stdint.h>

#include <motion_status.h>
#include <ramp_sigmoid.h>
#include <step_planner.h>

#include <MultiAxisPins.h>
#include <MultiStepEngine.h>
#include <StepperPins.h> /* STEPPER_MAX_ACCEL_EXACT, STEPPER_MAX_V0_EXACT, SCURVE_MAX_LEN */

#include "BackgroundPlanner.h"

/* What the planner and a Stepper ask of the coordinated move the Stepper's axis is part of (a
 * StepperGroup, StepperGroup.h), engine axis numbers and positions: virtual, so that a sketch without
 * a StepperGroup links none of it (only the group's constructor references its table: the exact
 * coordinated planner, lib's step_coord.c, about 8 KB of flash, stays out of the one-axis sketches). */
class GroupMove {
public:
    virtual AxisSource source_of(uint8_t axis) = 0;     /* the axis's commands in the move */
    virtual int32_t position_of(uint8_t axis) = 0;
    virtual int32_t target_of(uint8_t axis) = 0;
    virtual uint8_t interrupt_of(uint8_t axis, bool &flip) = 0; /* the axis whose interrupt steps it */
    virtual void poll_start() = 0;                      /* planner: start the axes together */
    virtual void run_request() = 0;                     /* planner: loop()'s move or stop */
    virtual void axis_done(uint8_t axis, int32_t position) = 0; /* planner: an axis's part ended */
    virtual void plan_stop_ahead(uint8_t axis) = 0;     /* planner: the stop from the cruise, ahead */
    virtual motion_status_t stop() = 0;
    virtual motion_status_t forceStop() = 0;

protected:
    ~GroupMove() {}
};
class StepperGroup;

/* The smooth ramp's highest vmax (setMaxSpeed: MS_ERR_ABOVE_LIMIT above; setRamp(RAMP_ALGO_SMOOTH): MS_ERR_RAMP_LIMIT):
 * the highest rate `make bench` measures clean (docs/bench.md, "Highest clean rate of the smooth
 * ramp": the reference move with accel vmax^2/10,000 and jerk 2 accel^2/vmax; at 60,000 steps/s its
 * planner falls behind near rest, docs/smooth-move.md). */
#ifndef STEPPER_MAX_SPS_SMOOTH
#define STEPPER_MAX_SPS_SMOOTH 50000.0
#endif
/* setRamp(RAMP_ALGO_SMOOTH) raises BackgroundPlanner's lead (all axes) to at least this, ms: the
 * smooth planner's commands near rest and at the knots cost more than the time they cover (smx
 * solves of up to 8 ms each), and a stop or a new target is planned in 13-22 ms, so the queue must
 * bank that much ahead (the SmoothMove check: underruns with less). 150, not 100 (until
 * 2026-12-05): near the end of a move from 40,000 steps/s each step was a command that cost the AVR
 * more than the time it covered, and with 100 ms banked the queue ran dry there (make bench's
 * smooth ladder); at 50,000 steps/s it still runs dry with 100 ms (125 was clean). A move from rest waits for its ring to fill or this much, so its first step
 * comes later too (docs/smooth-move.md has both figures measured). */
#ifndef MOTION_STEPPER_SMOOTH_LEAD_MS
#define MOTION_STEPPER_SMOOTH_LEAD_MS 150U
#endif
/* The stack the smooth ramp keeps below the stack pointer of setRamp(RAMP_ALGO_SMOOTH) and of every take
 * from the heap after it (BoardHeap.h's BOARD_STACK_RESERVE for the other ramps): its planner, in the
 * planner's interrupt, is deeper (make test's runs of SmoothMove: some 2,300 bytes below the top of
 * SRAM, motionemu's stack_max) */
#ifndef MOTION_STEPPER_SMOOTH_STACK
#define MOTION_STEPPER_SMOOTH_STACK 2368U
#endif
#ifndef STEPPER_DEFAULT_JERK
#define STEPPER_DEFAULT_JERK 100000.0
#endif

/* A stop() or a new target while moving cuts the queue (MotionBoard's StepCut.h): the commands
 * whose first step lies more than MOTION_STEPPER_CUT_US (a stop from the cruise) or
 * MOTION_STEPPER_CUT_SLOW_US (a stop while the speed changes, a new target; a stop or a target
 * behind while accelerating is reversed instead, StepCut.h's step_cut_mirror)
 * ahead are dropped and the stop or the new move starts there, so it acts after about this time
 * instead of after the lead. The planner interrupt plans it meanwhile and the cut is made only if
 * that plan is ready MOTION_STEPPER_CUT_MARGIN_US before the step where it lands; a plan that
 * takes longer is discarded and made again at a cut twice as far ahead (StepCut.h's STEP_CUT_TRIES
 * cuts in all), and only when none comes off, after the steps already queued (cutsMissed() counts
 * that). No cut when parameters were set since the move was planned (their conversion costs
 * milliseconds more). docs/library.md has the measured times. MOTION_STEPPER_CUT_US 0: no cut.
 * StepperCut.cpp carries the cuts out (it and StepperSmooth.cpp include StepCut.h). */
/* The smooth ramp's stop and new targets cut its queue too, this many microseconds ahead: its plans
 * cost tens of milliseconds (the law's cursor taken back to the cut and step k's time solved, the
 * stop or the new target with its jerk rule, the first commands). 0: no cut (they act after the
 * lead, MOTION_STEPPER_SMOOTH_LEAD_MS). */
#ifndef MOTION_STEPPER_SMOOTH_CUT_US
#define MOTION_STEPPER_SMOOTH_CUT_US 60000UL
#endif
/* A stop from the cruise is the same profile wherever the cut lands (only the position differs):
 * the planner interrupt plans it ahead, once the cruise has begun, and a stop() in the cruise then
 * only cuts and lays it out: this many microseconds ahead (the cut itself must be ready
 * MOTION_STEPPER_CUT_MARGIN_US before it lands, else the stop is planned at a cut as any other;
 * with two or three Steppers the part beyond the margin grows with the step interrupts' share of the
 * CPU, below).
 * The cut lands one interval beyond it, inside the cruise command that holds that step
 * (MultiStepEngine::cut_find's split): StopOnSwitch's stop latency under 1 ms (docs/stop-latency.md;
 * until 2026-12-06 the cut waited for the next command: 2.0-2.1 ms with 1 ms commands). 450, not 600
 * as until 2026-12-07: the stop's commands are kept in the engine's slot form (MultiStepEngine::
 * make_image), so from the search's reckoning to the switch a try takes 0.2 ms with three Steppers at
 * 10,000 steps/s and 0.35 ms at 25,000 (it laid out four commands there before). */
#ifndef MOTION_STEPPER_CUT_CRUISE_US
#define MOTION_STEPPER_CUT_CRUISE_US 450UL
#endif
/* The stop planned ahead covers this many microseconds of its steps (at most
 * MOTION_STEPPER_STOP_AHEAD_CMDS commands in the engine's slot form, 17 bytes each on the heap), all
 * laid out at the cut (the first MOTION_STEPPER_STOP_SWITCH_US of them by its switch, below):
 * planned while the move cruised, they cost the stop no planning, and with two or three Steppers
 * stopped at once the next one's cut comes before more of this one's deceleration must be planned
 * (with 1 ms, as the cuts planned at a stop: each axis's stop waited for a few milliseconds of the
 * one before's commands, and at 25,000 steps/s the second axis's deceleration began 3-5 ms after
 * the switch; BackgroundPlanner::tick). */
#ifndef MOTION_STEPPER_STOP_AHEAD_US
#define MOTION_STEPPER_STOP_AHEAD_US 10000UL
#endif
#ifndef MOTION_STEPPER_STOP_AHEAD_CMDS
#define MOTION_STEPPER_STOP_AHEAD_CMDS 12U
#endif
/* ... and with a Stepper alone, this many (no other axis's cut comes before the planner goes on with
 * the stop: planning 10 ms of it ahead cost one Stepper at 90,000 steps/s its clean cruise in
 * make bench, a queue run dry early in the cruise, once the commands were also made into slot images) */
#ifndef MOTION_STEPPER_STOP_AHEAD_1_US
#define MOTION_STEPPER_STOP_AHEAD_1_US 5000UL
#endif
/* Of those, the cut's switch puts in the ones that cover this many microseconds (a copy of each), the
 * rest comes once every axis stopped at once has had its switch (Stepper::adopt_cut): the interrupt
 * must not step that far first (the other axes' cuts take up to 1.2 ms each with three Steppers at
 * 25,000 steps/s, and an axis still accelerating plans its stop in some 2.5 ms before it feeds the
 * queues). */
#ifndef MOTION_STEPPER_STOP_SWITCH_US
#define MOTION_STEPPER_STOP_SWITCH_US 6000UL
#endif
static_assert(MOTION_STEPPER_STOP_SWITCH_US <= MOTION_STEPPER_STOP_AHEAD_US,
              "the switch puts in part of the stop planned ahead");

/* No cut above this speed (steps/s): the stop or the new target acts after the queued lead (the
 * sketches' console's rule since `make fuzz` seed 11: at 89,000 steps/s a target behind cut the
 * queue and the axis stalled 12.6 ms, the step interrupt leaving the planner a quarter of the
 * processor). Only a Stepper alone planned from loop() steps that fast (setMaxSpeed). */
#ifndef MOTION_STEPPER_CUT_MAX_SPS
#define MOTION_STEPPER_CUT_MAX_SPS 60000.0f
#endif
/* Planned from loop() (BackgroundPlanner::planInLoop(), the stepper sketches' console), a cut lands
 * farther ahead and its first commands cover more: loop() may be busy for a few milliseconds
 * elsewhere (a reply formatted) before it plans again, and a Stepper alone steps up to
 * STEPPER_MAX_SPS_EXACT, where the step interrupt takes half the processor; the margin grows by
 * 15 us per 1,000 steps/s (with 200 us alone, at 60,000 steps/s and accel 1e6 the interrupt reached
 * the cut first: an underrun). These are the values ExactRampStepper's console used before it
 * became a user of this library (a stop from the cruise 5 ms ahead, one while the speed changes or a
 * new target 6 ms, 3 ms of first commands: with 1 ms `make fuzz` seed 7 found a step 1 ms late). */
#ifndef MOTION_STEPPER_LOOP_CUT_US
#define MOTION_STEPPER_LOOP_CUT_US 5000U
#endif
#ifndef MOTION_STEPPER_LOOP_CUT_SLOW_US
#define MOTION_STEPPER_LOOP_CUT_SLOW_US 6000U
#endif
#ifndef MOTION_STEPPER_LOOP_CUT_NEW_US
#define MOTION_STEPPER_LOOP_CUT_NEW_US 3000U
#endif

/* A plan at a cut runs beside the step interrupts, which take some MOTION_STEPPER_STEP_CYCLES cycles of
 * the CPU per step (docs/bench.md: 133-137 per step, plus the entries of nested ones), so its time
 * grows as 1/(1 - their share of the CPU). The cut distances above are made for a share up to
 * MOTION_STEPPER_CUT_SHARE (one Stepper at 20,000 steps/s): above it they grow by
 * (1 - MOTION_STEPPER_CUT_SHARE) / (1 - share), the share taken at most 0.9 (a plan at a cut: the
 * axes' speeds then; the stop planned ahead: only its distance beyond the margin, the share taken as
 * its cruise speed times the axes stepping at the stop). */
#ifndef MOTION_STEPPER_STEP_CYCLES
#define MOTION_STEPPER_STEP_CYCLES 160.0f
#endif
/* The stop planned ahead's cut (a search and a lay-out, no plan) takes its share from the step
 * interrupts' cycles per step as make bench measures them with three axes (docs/bench.md, "ISR cycles
 * per step": 127-134), not the plans' margin above: with 160 its cut lay 1.5 ms ahead with three
 * Steppers at 25,000 steps/s, and X's deceleration began up to 4.1 ms after its stop() call (a try
 * there takes about 1 ms; test/emu/ThreeSteppers) */
#ifndef MOTION_STEPPER_CUT_CRUISE_STEP_CYCLES
#define MOTION_STEPPER_CUT_CRUISE_STEP_CYCLES 130.0f
#endif
#ifndef MOTION_STEPPER_CUT_SHARE
#define MOTION_STEPPER_CUT_SHARE 0.2f
#endif

/* The longest time one command of the exact ramp's cruise covers, ms: a stop or a new target cuts the
 * queue inside such a command (MultiStepEngine::cut_find's split: one interval beyond the cut's
 * distance), so its length costs no latency, and each command costs the planner interrupt some
 * 3,000 cycles laid out. Until 2026-12-06 the cut landed at the next command's start and the cruise
 * took commands of 1 ms (2 ms with three Steppers), the planner interrupt's largest load in a cruise. */
#ifndef MOTION_STEPPER_CRUISE_MS
#define MOTION_STEPPER_CRUISE_MS 4U
#endif
/* The longest time one step command of the lab ramps covers with one or two Steppers begun, ms (a
 * cruise is cut into such commands): with the lead, what their stop waits for. */
#ifndef MOTION_STEPPER_CMD_MS
#define MOTION_STEPPER_CMD_MS 1U
#endif
/* The same with three Steppers begun, ms: three queues of 1 ms commands cost more of the AVR than
 * there is (a cruise command costs the planner interrupt some 3,000 cycles, laid out; with the exact
 * ramp's 1 ms commands at 10,000 steps/s the ticks ran back to back, 93 % of the time, and every axis
 * ran dry hundreds of times), so the lab ramps' cruise takes commands of 2 ms with three Steppers. */
#ifndef MOTION_STEPPER_CMD_MS_3
#define MOTION_STEPPER_CMD_MS_3 2U
#endif

class Stepper {
public:
    enum Axis : uint8_t { X = 0, Y = 1, Z = 2 };
    /* hook(true) before steps that count up, hook(false) before steps that count down */
    typedef void (*DirectionHook)(bool forward);

    /* The axis's step interrupt is linked into the sketch only when a Stepper is made for it (the
     * constructor names it): a sketch with a Stepper X alone carries one interrupt, not three. Its
     * moves follow the exact ramp (RAMP_ALGO_EXACT) until setRamp() says otherwise. */
    explicit inline __attribute__((always_inline)) Stepper(Axis axis) : Stepper(axis, 0)
    {
        use_axis(axis);
        exact_init_ = step_planner_init_exact;
        exact_check_ = step_exact_check;
        cuts_ = &CUTS;
    }
    /* A Stepper whose moves follow another ramp from the start, so that the sketch links the exact
     * planner and the queue's cuts (some 33 KB of flash) only if it names the exact ramp
     * (setRamp(RAMP_ALGO_EXACT)): RAMP_ALGO_LEIB or RAMP_ALGO_SIMPLISTIC with hooks as for setRamp()
     * (the lab's preComputation() and computeNewSpeed(), or NULL for lib's), as Stepper(axis) and
     * setRamp(algo, hooks) before begin() (LeibRampStepper, SimplisticRampStepper);
     * RAMP_ALGO_SIGMOID (hooks NULL): the setters check for the sigmoid from the start, and
     * setRamp(RAMP_ALGO_SIGMOID) must fill its table before begin() (SCurveStepper); RAMP_ALGO_EXACT:
     * as Stepper(axis). begin() refuses any other algo (MS_ERR_RAMP_NOT_HERE), parameters in force
     * that the ramp does not take then (vmax above its limit: set it first; MS_ERR_RAMP_LIMIT), and the sigmoid without
     * its table (MS_ERR_TABLE_MISSING). */
    inline __attribute__((always_inline)) Stepper(Axis axis, ramp_algo_t algo, const ramp_hooks_t *hooks)
        : Stepper(axis, 0)
    {
        use_axis(axis);
        if (algo == RAMP_ALGO_LEIB || algo == RAMP_ALGO_SIMPLISTIC) {
            lab_init_ = algo == RAMP_ALGO_LEIB ? step_planner_init_leib : step_planner_init_simplistic;
            lab_probe_ = algo == RAMP_ALGO_LEIB ? ramp_plan_leib : ramp_plan_simplistic;
            algo_ = algo;
            ramp_hooks_ = hooks;
        } else if (algo == RAMP_ALGO_SIGMOID) {
            sigmoid_check_ = ramp_sigmoid_check; /* the table comes with setRamp(RAMP_ALGO_SIGMOID) */
            sigmoid_shape_ = sigmoid_shape;
            algo_ = algo;
        } else if (algo == RAMP_ALGO_EXACT) {
            exact_init_ = step_planner_init_exact;
            exact_check_ = step_exact_check;
            cuts_ = &CUTS;
        } else {
            begin_status_ = MS_ERR_RAMP_NOT_HERE; /* the smooth ramp: setRamp(RAMP_ALGO_SMOOTH) */
        }
    }

    /* Takes the axis (MS_ERR_AXIS_TAKEN if another Stepper has it), sets up the engine and the planner
     * (once for all: the first begin() takes every Stepper's ring of step commands from the heap,
     * 64 commands of 20 bytes each, 96 for a Stepper alone on X planned from loop(), as the stepper
     * sketches' console plans; MS_ERR_NO_MEMORY if
     * there is no room with BoardHeap.h's BOARD_STACK_RESERVE left for the stack), ENABLE as set (enabled unless auto-disable is on), position 0. */
    motion_status_t begin();

    /* Limits for the next plan; MS_ERR_ABOVE_LIMIT above this library's limits for the ramp taken
     * (maxSpeedLimit(), accelerationLimit(), minSpeedLimit() tell them: on the exact ramp MULTI_MAX_SPS,
     * STEPPER_MAX_ACCEL_EXACT and STEPPER_MAX_V0_EXACT; docs/library.md has the others). */
    motion_status_t setMaxSpeed(float steps_per_s);          /* vmax > v0 */
    motion_status_t setAcceleration(float steps_per_s2);     /* > 0 (exact ramp: >= 8 and >= vmax F / 2^34) */
    motion_status_t setMinSpeed(float steps_per_s);          /* v0: 0 <= v0 < vmax */
    /* The ramp this stepper's moves follow; idle only (MS_ERR_BUSY while moving), before or after
     * begin(), nothing changes on a refusal:
     *   RAMP_ALGO_EXACT       (default) every step on true constant acceleration, within one tick;
     *                         its stop() and new targets cut the queue (the smooth ramp's too)
     *   RAMP_ALGO_LEIB        the lab's Leib recurrence (lib's ramp_leib.c, the LeibRampStepper sketch)
     *   RAMP_ALGO_SIMPLISTIC  the lab's starting point (its interval changes by a fixed amount)
     * hooks: the lab's own preComputation()/computeNewSpeed() for the lab's ramps (ramp.h's
     * ramp_hooks_t, as LeibRampStepper passes them), NULL for lib's. The lab's ramps plan every step
     * (float arithmetic), so their vmax is limited to STEPPER_MAX_SPS_LEIB / _SIMPLISTIC
     * (StepperPins.h; setMaxSpeed refuses more: MS_ERR_ABOVE_LIMIT; setRamp: MS_ERR_RAMP_LIMIT); the parameters in
     * force must suit the new ramp (its own status otherwise). A StepperGroup's moves are always exact.
     *   RAMP_ALGO_SIGMOID     the S-curve article's sigmoid: a table of timer periods from minSpeed()
     *                         (fmin) to maxSpeed() (fmax) along a logistic curve (setSigmoid: flex, len
     *                         entries, each held for hold steps), walked backwards to stop (the
     *                         SCurveStepper sketch). vmax up to STEPPER_MAX_SPS_SCURVE; the acceleration
     *                         follows from the table (acceleration() tells it; setAcceleration:
     *                         MS_ERR_DERIVED_PARAM). The table (2 bytes per entry, SCURVE_MAX_LEN
     *                         entries) is allocated from the heap at the first setRamp(SIGMOID) and
     *                         filled then (about 6,500 cycles per entry: 0.1 s for 250); a change of
     *                         minSpeed, maxSpeed or the shape refills it at rest, a few entries per
     *                         planner tick (while moving: at the move's end), and a moveTo() waits
     *                         for the refill. No cut: a stop or a new target acts after the lead. */
    /*   RAMP_ALGO_SMOOTH      the filter-shaped, jerk-limited move (lib's smooth_move.h): the velocity
     *                         command through two moving averages tau1 = vmax/accel, tau2 = accel/jerk
     *                         (setJerk); |acceleration| <= accel, |jerk| <= jerk, velocity and
     *                         acceleration continuous, every step within a tick of the law. vmax up to
     *                         STEPPER_MAX_SPS_SMOOTH; v0 is not used (it starts and ends at rest). A
     *                         stop() sends the command to 0 and a new target continues from the
     *                         filter's state, both from a cut of the queue
     *                         MOTION_STEPPER_SMOOTH_CUT_US ahead (after the lead when that plan is
     *                         not ready in time: cutsMissed(), or when the move's last command is
     *                         queued already) (and up to
     *                         tau1 + tau2 later where acting then would exceed the jerk: a stop near
     *                         the end of an acceleration, which then comes to rest farther; a new
     *                         target no time keeps within it is a stop and a move from rest;
     *                         forceStop() halts at once; docs/smooth-move.md). Its planner
     *                         (about 1 KB) is allocated from the heap at the first setRamp(SMOOTH) of a
     *                         Stepper, with (once for all) the copy a cut keeps (another 1 KB;
     *                         MS_ERR_NO_MEMORY if there is no room), and kept; a sketch
     *                         that never asks for it does not link it. Its first step comes about 0.15 s
     *                         after moveTo() from rest (the ring is filled first; docs/smooth-move.md). */
    inline __attribute__((always_inline)) motion_status_t setRamp(ramp_algo_t algo, const ramp_hooks_t *hooks = 0)
    {
        if (algo == RAMP_ALGO_EXACT) {
            exact_init_ = step_planner_init_exact; /* only here and in Stepper(axis): see the constructors */
            exact_check_ = step_exact_check;
            cuts_ = &CUTS;
        }
        return algo == RAMP_ALGO_SMOOTH ? set_ramp_smooth() : set_ramp(algo, hooks);
    }
    ramp_algo_t ramp() const { return algo_; }
    /* The smooth ramp's peak jerk, steps/s^3 (default STEPPER_DEFAULT_JERK): > 0 and at least
     * accel^2/vmax of the parameters in force (tau2 <= tau1), else MS_ERR_NOT_FINITE,
     * MS_ERR_JERK_NOT_POSITIVE or MS_ERR_JERK_TOO_LOW and nothing changes. Kept for the smooth ramp
     * whatever the ramp in force; while the smooth ramp moves, from its next move from rest. While it
     * is the ramp in force, setMaxSpeed/setAcceleration refuse values that would make the jerk too
     * low (MS_ERR_JERK_TOO_LOW). */
    motion_status_t setJerk(float steps_per_s3);
    float jerk() const { return jerk_; }
    /* The sigmoid ramp's shape (RAMP_ALGO_SIGMOID; kept whatever the ramp in force, default flex 5,
     * len 250, hold 4): flex > 0 up to STEPPER_MAX_FLEX, len 2 to SCURVE_MAX_LEN entries, hold >= 1
     * steps per entry; with minSpeed()/maxSpeed() a table the article's check accepts (its status
     * otherwise: nothing changes). */
    motion_status_t setSigmoid(float flex, uint16_t len, uint16_t hold);
    float sigmoidFlex() const { return sig_flex_; }
    uint16_t sigmoidLen() const { return sig_len_; }
    uint16_t sigmoidHold() const { return sig_hold_; }
    /* The table in force (false: not the sigmoid ramp): the steps and seconds of its acceleration,
     * and its end speed (fmax as the timer's whole periods give it). */
    struct SigmoidFigures {
        uint32_t accelSteps;
        float accelTimeS;
        float cruiseSps;
    };
    bool sigmoidFigures(SigmoidFigures &f) const;
    float maxSpeed() const { return params_.vmax_sps; }
    float acceleration() const { return params_.accel_sps2; }
    float minSpeed() const { return params_.v0_sps; }

    /* Move to an absolute position / by a distance from the target in force (as FastAccelStepper's
     * move; AccelStepper's counts from the current position: the same at rest, not while moving).
     * MS_ERR_OUT_OF_RANGE for a target beyond a long's range (move) or farther than 2^31 - 1 steps
     * from where the axis is (distanceToGo() could not tell it), and LONG_MIN with DIR inverted.
     * While moving, the move continues from its speed to the new target (no stop in between when
     * it lies ahead beyond the stopping distance); MS_ERR_BUSY while in a StepperGroup's move.
     * While moving to `target` already (targetPosition()), with no stop asked and no v0, vmax or
     * accel set since its plan, nothing changes, nor at rest where the axis is (no move, no
     * takeDone, as AccelStepper's): a loop() may call moveTo() on every pass (as AccelStepper's and
     * FastAccelStepper's users do with a knob or a joystick) at no cost.
     * Returns at once (a few microseconds); the planner interrupt, brought forward, plans it about
     * 50 us later (MOTION_STEPPER_KICK_COUNTS). */
    motion_status_t moveTo(long target);
    motion_status_t move(long distance);
    /* Decelerate to rest at the acceleration in force, from the step where the queue is cut
     * (MOTION_STEPPER_CUT_US ahead; docs/library.md has the measured latency). */
    motion_status_t stop();
    /* Halt now: no further step (the position keeps every step made). */
    motion_status_t forceStop();

    /* A move is accepted and not yet ended. */
    bool isRunning() const;
    long currentPosition() const;
    /* Idle only (MS_ERR_BUSY while moving or while a target waits): the position is now `position`
     * (nothing moves). A move whose last step is made, or that forceStop() halted, counts as idle: the
     * call takes its end (takeDone reports it), as the planner interrupt would within a millisecond,
     * so `forceStop(); setCurrentPosition(0);` and `if (distanceToGo() == 0) setCurrentPosition(0);`
     * are taken at once (not in a StepperGroup's move: MS_ERR_BUSY until the group collects its end). */
    motion_status_t setCurrentPosition(long position);
    long targetPosition() const;
    /* targetPosition() - currentPosition(), steps (AccelStepper's distanceToGo) */
    long distanceToGo() const { return targetPosition() - currentPosition(); }
    /* The speed being stepped now, steps/s, negative counting down; 0 at rest. */
    float speed() const;
    /* The end of a move: true once for each move that came to rest (a move replaced by a new
     * target does not end), with where it ended. Call it from loop(). */
    bool takeDone(long &position);
    /* The status of the last move planned (a moveTo() that changed nothing, the target in force
     * while moving: MS_OK; moveTo/move are planned by the planner interrupt within
     * a millisecond or so of the call, after their checks: a plan the exact planner refuses there,
     * which valid parameters never give, leaves the axis as it was and shows here). */
    motion_status_t lastStatus() const { return last_status_; }
    /* Steps the queue ran dry before they were planned (0 on a healthy machine). */
    uint16_t underruns() const;
    /* STEP edges armed after their planned time had passed (made 2 us later: the step interrupt came
     * too late to arm them; an edge only held up by another interrupt is not counted); a few near the
     * engine's top rate, none at the rates the checks run. */
    uint16_t lateEdges() const;
    /* Where the move being stepped is in its ramp: RAMP_IDLE at rest, else RAMP_ACCEL, RAMP_CRUISE or
     * RAMP_DECEL (ramp.h; FastAccelStepper's rampState(); a move just asked and not yet stepping:
     * RAMP_ACCEL). */
    ramp_phase_t rampState() const;

    /* How the last moveTo()/move() was planned, once the planner interrupt has planned it (false
     * until then: within about a millisecond of the call, longer while it plans another move).
     * from: where the new plan starts (the step where the queue was cut, or where the steps queued
     * before the call end); afterDone: every step of the move in progress was queued already, so
     * that move ends at its target with its own end (takeDone) and the new one starts from there
     * (from is that target). doneBefore: an end not taken yet (takeDone) was there when it was
     * planned: it belongs to a move before this one (an end that comes later is this move's or the
     * one it waits for). lastStatus() tells whether the plan was taken. */
    struct PlanStart {
        long from;
        bool afterDone;
        bool doneBefore;
    };
    bool planStart(PlanStart &start) const;

    /* This library's limits for the ramp in force (the setters refuse more: MS_ERR_ABOVE_LIMIT). */
    float maxSpeedLimit() const { return vmax_limit(); }
    float accelerationLimit() const;
    float minSpeedLimit() const;

    /* The step timer's ticks per second, for every Stepper (the engine has one timeline):
     * 16,000,000 (the default: every step within 1/16 us of its time) or 2,000,000 (Timer1 at
     * 16 MHz / 8, the lab's F: the lab's ramps count their intervals in its ticks, as the
     * LeibRampStepper sketch does). Only before the first begin() (MS_ERR_BUSY after; any other
     * value MS_ERR_OUT_OF_RANGE). With STEPPER_TIMED_LOOP = 1 (no step interrupt: loop() makes the
     * steps by micros(), BackgroundPlanner::poll()) the only rate is 1,000,000. */
    static motion_status_t setTickRate(uint32_t ticks_per_s);
    static uint32_t tickRate();
    /* Stops and new targets that could not cut the queue in time (their plan was late at every cut
     * tried, or the planner refused the cut): they acted after the lead instead. */
    uint16_t cutsMissed() const { return cuts_missed_; }

    /* ENABLE: on / off now; auto-disable: off after each move ends, on before each starts. */
    void enableOutputs();
    void disableOutputs();
    void setAutoDisable(bool on);
    /* DIR's polarity: idle only (MS_ERR_BUSY while moving). */
    motion_status_t setDirectionInverted(bool inverted);
    /* ENABLE's polarity (low enables a RAMPS driver: false, the default), at once. */
    void setEnableActiveHigh(bool active_high);
    /* Your function sets DIR (the lab's moveOneStep(bool)): called before the first step of every
     * move and at every reversal, from the engine (an interrupt: keep it short, e.g. a digitalWrite);
     * NULL: the engine writes DIR. Idle only. */
    motion_status_t setDirectionHook(DirectionHook hook);
    /* Other pins for DIR and ENABLE (a driver wired elsewhere than the RAMPS socket), by their
     * Arduino pin number; idle only (MS_ERR_BUSY while moving), MS_ERR_OUT_OF_RANGE for a pin the
     * Mega does not have. STEP stays the axis's (the step interrupt writes its port directly).
     * DIR on another pin is written as a direction hook writes it (digitalWrite before the first step
     * of every move and at every reversal; high = counting up in the engine's sense, so with
     * setDirectionInverted(true) high counts down), unless a hook is set, which then has it; the
     * RAMPS DIR pin is left alone. ENABLE on another pin follows enableOutputs()/auto-disable and
     * setEnableActiveHigh; the RAMPS ENABLE pin keeps the level it had. A new pin is set up at once,
     * before begin() too (DIR an output, ENABLE at its level). directionPin(), enablePin(): the pins
     * in use. */
    motion_status_t setDirectionPin(uint8_t pin);
    motion_status_t setEnablePin(uint8_t pin);
    uint8_t directionPin() const;
    uint8_t enablePin() const { return en_pin_; }

    uint8_t axis() const { return axis_; }
    /* The sentence of a status, as after "ERR " in the sketches' serial replies (a flash string). */
    static const __FlashStringHelper *statusText(motion_status_t status);

private:
    Stepper(Axis axis, int); /* the fields */
    inline __attribute__((always_inline)) static void use_axis(Axis axis)
    {
        if (axis == X)
            multi_use_x();
        else if (axis == Y)
            multi_use_y();
        else
            multi_use_z();
    }
    /* the exact planner's entry, set by Stepper(axis) and setRamp(RAMP_ALGO_EXACT) (null in a sketch
     * that never names the exact ramp: it links none of it) */
    static motion_status_t (*exact_init_)(step_planner_t *pl, const ramp_params_t *params, int32_t pos);
    static motion_status_t (*exact_check_)(const ramp_params_t *params); /* a setter's check (little stack) */
    /* the cuts of the queue (stop_in_cruise, plan_at_cut, prepare_stop: StepperCut.cpp), for the exact and
     * the smooth ramp only: set with them, so that a sketch on a lab ramp alone links none of it */
    struct Cuts {
        bool (*at_cut)(Stepper &s, uint8_t req, int32_t target);
        bool (*in_cruise)(Stepper &s, bool then, int32_t to);
        void (*prepare)(Stepper &s);
        void (*adopt)(Stepper &s);
    };
    static const Cuts CUTS;
    static const Cuts *cuts_;
    static bool cuts_at(Stepper &s, uint8_t req, int32_t target) { return s.plan_at_cut(req, target); }
    static bool cuts_cruise(Stepper &s, bool then, int32_t to) { return s.stop_in_cruise(then, to); }
    static void cuts_prepare(Stepper &s) { s.prepare_stop(); }
    static void cuts_adopt(Stepper &s) { s.adopt_cut(); }
    bool cut_in_cruise(bool then, int32_t to) { return cuts_ && cuts_->in_cruise(*this, then, to); }
    bool cut_plan(uint8_t req, int32_t target) { return cuts_ && cuts_->at_cut(*this, req, target); }
    void plan_stop_ahead()
    {
        if (cuts_)
            cuts_->prepare(*this);
    }
    void cut_second_half()
    {
        if (cuts_)
            cuts_->adopt(*this);
    }
    friend class BackgroundPlanner;
    friend class MotionConsole;
    friend class StepperGroup;
    /* moveTo(); replan: also to the target in force and to where the axis rests (the consoles: every
     * target line is planned, gets its OK from the plan and its DONE, a move of no step included) */
    motion_status_t move_to(long target, bool replan);
    enum { REQ_NONE, REQ_MOVE, REQ_STOP };
    AxisSource source();
    GroupMove *group_now() const;
    /* planner interrupt: carries out req_; true when a stop or a target behind came off at a cut in the
     * cruise with the stop planned ahead (stop_in_cruise: its commands laid out for 10 ms, no plan) */
    bool run_request();
    bool plan_at_cut(uint8_t req, int32_t target); /* planner interrupt: a stop or a move from a cut */
    bool cut_again();                              /* planner interrupt: try that cut again later? */
    bool beyond_plan(int32_t to) const;            /* a new target the queue needs no cut for */
    bool stop_in_cruise(bool then, int32_t to);    /* planner interrupt: the stop planned ahead, at a cut */
    void prepare_stop();                           /* planner interrupt: plans that stop ahead */
    void adopt_cut();                              /* planner interrupt: the second half of that stop's cut */
    void engine_done(int32_t position); /* planner interrupt (or setCurrentPosition, locked): the move ended */
    void record_done(int32_t engine_position);
    void write_enable(bool on);
    int32_t to_engine(long user) const { return inverted_ ? -(int32_t)user : (int32_t)user; }
    /* a position the engine can take: not LONG_MIN with DIR inverted (its negation does not fit) */
    bool fits_engine(long user) const { return !(inverted_ && user == INT32_MIN); }
    /* a target the axis can be sent to: the engine holds it, and distanceToGo() its distance */
    bool reachable(long user) const;
    long to_user(int32_t engine) const { return inverted_ ? -(long)engine : (long)engine; }
    motion_status_t set_param(float value, float limit, uint8_t which);
    float vmax_limit() const;
    motion_status_t probe(ramp_algo_t algo, const ramp_hooks_t *hooks, const ramp_params_t &p) const;
    motion_status_t set_ramp(ramp_algo_t algo, const ramp_hooks_t *hooks);
    motion_status_t set_ramp_smooth();
    /* the sigmoid ramp (heap: its table): set by set_ramp_sigmoid, so that a sketch that never asks
     * for it links none of it */
    struct Sigmoid;
    motion_status_t set_ramp_sigmoid();
    ramp_sigmoid_params_t sigmoid_params(const ramp_params_t &p) const { return sigmoid_params(p, sig_flex_, sig_len_, sig_hold_); }
    static ramp_sigmoid_params_t sigmoid_params(const ramp_params_t &p, float flex, uint16_t len, uint16_t hold);
    void sigmoid_changed(); /* a parameter of the table changed: refill now (at rest) or at the end */
    void sigmoid_refill_start();
    static void sigmoid_slice(Stepper &s); /* planner interrupt: a few entries of the refill */
    void refill_tick();                    /* planner interrupt: the slice, if a refill runs */
    static void (*sigmoid_slice_)(Stepper &s);
    static motion_status_t (*sigmoid_check_)(const ramp_sigmoid_params_t *p);
    /* setSigmoid as MotionConsole's `set flex|len|hold` calls it, for whatever Stepper it was given:
     * through a pointer set with the sigmoid (the constructor, set_ramp_sigmoid), so that a sketch
     * that never uses it links none of its code (MS_ERR_NOT_SUPPORTED then; the console asks only
     * a Stepper on the sigmoid) */
    static motion_status_t sigmoid_shape(Stepper &s, float flex, uint16_t len, uint16_t hold);
    static motion_status_t (*sigmoid_shape_)(Stepper &s, float flex, uint16_t len, uint16_t hold);
    motion_status_t set_sigmoid_in_use(float flex, uint16_t len, uint16_t hold)
    {
        return sigmoid_shape_ ? sigmoid_shape_(*this, flex, len, hold) : MS_ERR_NOT_SUPPORTED;
    }
    static motion_status_t (*sigmoid_init_)(step_planner_t *pl, const ramp_sigmoid_params_t *p, const uint16_t *table,
                                            uint16_t table_len, int32_t pos);
    motion_status_t switch_ramp(ramp_algo_t algo, const ramp_hooks_t *hooks);
    /* the smooth ramp's lib calls, set by set_ramp_smooth (a sketch without it links none of them) */
    static motion_status_t (*smooth_check_)(const ramp_params_t *params, double jerk_sps3);
    static motion_status_t (*smooth_init_)(step_planner_t *pl, const ramp_params_t *params, double jerk_sps3,
                                           step_smooth_t *store, int32_t pos);
    static motion_status_t (*smooth_jerk_)(step_planner_t *pl, double jerk_sps3);
    motion_status_t init_planner(int32_t pos);
    void set_cmd_length();
    static void call_hook(uint8_t axis, bool forward);
    static void hook_x(bool forward);
    static void hook_y(bool forward);
    static void hook_z(bool forward);

    static uint8_t made_; /* Steppers constructed: a Stepper alone may step faster (vmax_limit) */
    uint8_t axis_;
    bool begun_;
    bool inverted_;
    bool enable_high_;
    bool enabled_;
    bool auto_disable_;
    volatile bool done_;
    volatile bool has_next_;
    bool keep_done_; /* the next move from rest keeps an end not taken (a target that waited for it) */
    volatile uint8_t req_; /* REQ_*: what loop() asked the planner interrupt to do */
    int32_t done_pos_;    /* engine coordinates */
    int32_t next_target_; /* engine coordinates: the target accepted while the last steps ran */
    int32_t req_target_;  /* engine coordinates: REQ_MOVE's target */
    int32_t plan_from_;   /* engine coordinates: where the last move planned starts (planStart) */
    bool plan_after_done_;
    bool plan_done_before_;
    motion_status_t last_status_;
    uint16_t cuts_missed_;
    uint32_t cut_retry_us_; /* a cut that came too late: the distance of its next try (0: none) */
    uint8_t cut_tries_;
    /* v0, vmax or accel set since the last plan (set_param; run_request clears it): a moveTo() of the
     * target in force then replans with them, where otherwise it changes nothing */
    bool set_since_plan_;
    /* the stop from the cruise, planned ahead (prepare_stop: StepperCut.cpp), from the heap at begin()
     * with the planner interrupt only (stop_ahead_begin), after the rings and where there is room for
     * it (null otherwise: the stop from the cruise is planned at a cut); a StepperGroup's stop at a cut
     * keeps its members' states there (a member of a group's move plans no stop ahead) */
    struct StopAhead;
    bool stop_ahead_begin();
    void stop_ahead_reset();
    StopAhead *stop_;
    DirectionHook hook_;
    uint8_t dir_pin_; /* 0xFF: the axis's own, written by the engine */
    uint8_t en_pin_;
    void install_hook();
    ramp_algo_t algo_;
    const ramp_hooks_t *ramp_hooks_;
    GroupMove *volatile group_; /* the coordinated move this axis is part of, or none */
    ramp_params_t params_;
    float jerk_;
    step_smooth_t *smooth_; /* the smooth ramp's planner state (heap), or none yet */
    Sigmoid *sig_;          /* the sigmoid ramp's table (heap), or none yet */
    float sig_flex_;
    uint16_t sig_len_, sig_hold_;
    step_planner_t planner_;
    motion_status_t begin_status_; /* a constructor's refusal, returned by begin() */
    /* the lab ramps' lib calls, this Stepper's: set by set_ramp (both ramps) or by the constructor
     * with a lab ramp (that one only: LeibRampStepper links no simplistic code); a sketch that names
     * no lab ramp links none of them */
    motion_status_t (*lab_init_)(step_planner_t *pl, ramp_algo_t algo, const ramp_params_t *params,
                                 const ramp_hooks_t *hooks, int32_t pos);
    motion_status_t (*lab_probe_)(ramp_t *r, ramp_algo_t algo, const ramp_params_t *params,
                                  const ramp_hooks_t *hooks, int32_t from, int32_t to);
};

#endif
