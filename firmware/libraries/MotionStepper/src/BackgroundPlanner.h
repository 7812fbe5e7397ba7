/* BackgroundPlanner.h - keeps the step queues of the Steppers planned without loop(): Timer3's
 * compare A interrupt, every millisecond, lays out step commands (lib's planners, step_planner.h and
 * step_coord.h) into MotionBoard's MultiStepEngine queues, starts moves and collects their ends.
 *
 * The interrupt's code is BackgroundPlannerTimer.cpp, linked by MotionStepper.h (a sketch that plans
 * in loop(), planInLoop(), and includes only MotionConsole.h has none of it).
 *
 * Timer3 is taken (CTC mode, prescaler 64, OCR3A = 249: 1 kHz): analogWrite() on D2, D3 and D5 (its
 * PWM pins) no longer works, and no other code may reprogram Timer3. Timer1 belongs to the step
 * interrupts (MultiStepEngine.h): no analogWrite() on D11, D12, D13 either; GPIOR0 is the engine's.
 *
 * The tick runs with interrupts enabled (as ISR_NOBLOCK would), so a step interrupt (Timer1) is never
 * delayed by planning, nor are the core's millis and serial interrupts. Its vector enables them
 * after a check of about 30 cycles that saves two registers only, not at its first instruction:
 * the step interrupts themselves enable interrupts early (so that the axes nest), and a tick that
 * came inside one of them would hold its next edge back for the whole tick; such a tick returns and
 * comes back 16 us later, then later and later (MOTION_STEPPER_RETRY_COUNTS), in about 50 cycles. A guard makes a tick that comes while the previous one still runs (at a move's start,
 * planning can take longer than 1 ms) return at once. Calls from loop() that change a planner keep
 * the tick from starting (PlannerLock) for their own few hundred microseconds at most; they never
 * wait for it.
 *
 * Lead: each stepping axis keeps leadMs() of steps queued ahead (setLeadMs, default
 * MOTION_STEPPER_LEAD_MS). A stop() or a new target of a Stepper cuts the queue
 * (Stepper.h's MOTION_STEPPER_CUT_US) and acts sooner; a StepperGroup's acts after the steps already
 * queued (docs/library.md has the measured figures). 10 ms, because a plan costs up to about
 * 4 ms of the AVR (a stop at 20,000 steps/s, made by the tick while the queue runs on) and a
 * coordinated move's commands cover up to 4 ms each: at 8 ms a StepperGroup move of the TwoAxesLine
 * example ran dry once, at 6 ms a stop() at 20,000 steps/s did too (emulator, test/emu/checks_library.py).
 */
#ifndef MOTION_STEPPER_BACKGROUND_PLANNER_H
#define MOTION_STEPPER_BACKGROUND_PLANNER_H

#include <Arduino.h>
#include <stdint.h>

#include <MultiAxisPins.h> /* MULTI_TIMED_LOOP, MULTI_TICK_HZ */

#ifndef MOTION_STEPPER_LEAD_MS
#define MOTION_STEPPER_LEAD_MS 10U
#endif
/* The lead is at least this with two / three Steppers begun, ms. Their moves from rest start and end
 * together, and near rest each command (a step or two) costs more of the AVR than the time it
 * covers: the queues must bank ahead what the CPU cannot make at that moment. Measured
 * (test/emu/ThreeSteppers, four 20,000-step legs at once, 25,000 steps/s and 200,000 steps/s^2):
 * two Steppers with a 10 ms lead ran dry 236 / 204 times, with 40 ms never; three with 40 ms 86 / 43
 * / 29 times, with 100 ms never (the MultiAxisStepper sketch's lead, MULTI_LEAD_MS). */
#ifndef MOTION_STEPPER_LEAD_MS_2
#define MOTION_STEPPER_LEAD_MS_2 40U
#endif
#ifndef MOTION_STEPPER_LEAD_MS_3
#define MOTION_STEPPER_LEAD_MS_3 100U
#endif
/* commands laid out per tick (the axis whose queue reaches least far ahead first): the tick stops
 * choosing once it has laid out this many, so the last choice may add up to
 * MOTION_STEPPER_CMDS_PER_PICK - 1 more (capping that last choice instead left three Steppers'
 * simultaneous stop at 10,000 steps/s a command short: one underrun) */
#ifndef MOTION_STEPPER_CMDS_PER_TICK
#define MOTION_STEPPER_CMDS_PER_TICK 24U
#endif
/* Once a Stepper has taken the smooth ramp (shareLongTicks()), a tick that has run this long (us) stops laying
 * out commands once every stepping queue holds at least half the lead: loop() then gets its turn
 * before the next tick (Timer3's next millisecond). Without it, the smooth ramp's planner, whose
 * commands can cost milliseconds each, held loop() for up to 184 ms while it banked its 150 ms lead
 * again after a cut of the queue (the SmoothMove example). Below half the lead the tick goes on (the
 * queue comes first): with a quarter or a third as that bound, make bench's 50,000 steps/s smooth
 * move ran dry 5 times / once near rest. Only with the smooth ramp: for all ramps it made three exact
 * Steppers' stop at 10,000 steps/s run dry once and two Steppers' stop at 20,000 steps/s miss its
 * cut (test/emu/ThreeSteppers). */
#ifndef MOTION_STEPPER_TICK_US
#define MOTION_STEPPER_TICK_US 2000UL
#endif
/* commands laid out for the axis chosen before choosing again (choosing looks at every axis's queue:
 * about as costly as a command of the cruise) */
/* With two or three Steppers, a tick that carries out a stop or a new target feeds the queues only
 * up to this many ms before the next axis's request and before it returns (the next tick feeds
 * them up to the lead), so that loop() gets its turn to ask for the next axis's stop: the stops
 * of three Steppers at once come one after the other, each about a millisecond. Until 2026-12-06 the tick
 * fed every queue up to the lead after each request: with three Steppers at 10,000 steps/s it ran
 * for tens of milliseconds before loop() could call the second axis's stop(), whose deceleration
 * began 24 ms after the switch (the third's 37 ms; test/emu/ThreeSteppers). */
#ifndef MOTION_STEPPER_URGENT_MS
#define MOTION_STEPPER_URGENT_MS 4U
#endif
/* ... and before a stop or a new target planned at a cut (not the stop planned ahead: a plan that
 * can take ten milliseconds with three Steppers at 25,000 steps/s) the other queues are fed up to
 * this many ms (with 10, that plan ran two of them dry). */
#ifndef MOTION_STEPPER_PLAN_SAFE_MS
#define MOTION_STEPPER_PLAN_SAFE_MS 20U
#endif
/* ... but during a StepperGroup's stop while accelerating (catchUp: the acceleration's last commands
 * reversed, the rest of the stop planned while they run), while a stepping queue holds less than this
 * many ms, the tick goes on laying out commands past MOTION_STEPPER_CMDS_PER_TICK, up to
 * MOTION_STEPPER_LOW_TICKS times as many (the queue comes first): without it three Steppers at 10,000
 * steps/s ran dry once or twice at 4 of 8 such stops, the tick returning with a queue a millisecond
 * from empty. Only then: for every feed it held loop() 4 ms longer after three Steppers' own stops,
 * and their deceleration began later (test/emu/ThreeSteppers). Past that many, it stops only once the
 * least queue holds half of LOW_MS, or at twice that many (loop() and the other axes' requests wait
 * meanwhile; only the group's axes: a Stepper moving alone beside the group gets its tick's share): at the end
 * of such a stop (commands of two or three steps, each
 * some 250 us to plan, the planner near its limit), three Steppers at 10,000 steps/s reached the 72
 * with X's queue at 1.75 ms, the tick returned, and X ran dry before the next (a build of 2026-12-07,
 * GroupStop's moment at 150 ms) */
#ifndef MOTION_STEPPER_LOW_MS
#define MOTION_STEPPER_LOW_MS 4U
#endif
#ifndef MOTION_STEPPER_LOW_TICKS
#define MOTION_STEPPER_LOW_TICKS 3U
#endif
#ifndef MOTION_STEPPER_CMDS_PER_PICK
#define MOTION_STEPPER_CMDS_PER_PICK 3U
#endif
/* A tick that came inside a step interrupt comes back this many counts of Timer3 (4 us each) later,
 * then twice as late at each retry that lands in one again (up to 62 counts, 248 us), until a tick
 * runs. Not a fixed 2 counts (8 us, as until 2026-12-05): this interrupt's entry and exit cost about
 * 200 cycles then (it saved every register the tick may use; 50 since its vector checks first,
 * BackgroundPlanner.cpp), so the step interrupt it waited for got one
 * instruction per retry and took tens of milliseconds to end (a Z step held its STEP high for 18 ms
 * with three Steppers moving). Not a fixed 16 us either: a step interrupt that had fallen behind (its
 * edges made back to back until it catches up) kept meeting the retries, lost a quarter of the CPU to
 * them and never caught up, and the planner starved (three Steppers at 20,000 steps/s: 3,679 edges
 * made back to back, underruns). Nor a fixed 100 us: two step intervals at 20,000 steps/s, and the
 * retry met the next step interrupt every time (BlockingLoop ran dry). */
#ifndef MOTION_STEPPER_RETRY_COUNTS
#define MOTION_STEPPER_RETRY_COUNTS 4U
#endif
/* kick() (a stop or a new target from loop()) brings the tick this many counts of Timer3 (4 us
 * each) ahead, unless it comes sooner anyway: loop()'s next few calls (the other axes' stop(), as
 * a limit switch's handler makes them) come first and are carried out by the same tick. Until
 * 2026-12-06 2 counts: the tick came between the second and the third stop() of three Steppers,
 * and at times the third's deceleration began 15 ms after the first's. */
#ifndef MOTION_STEPPER_KICK_COUNTS
#define MOTION_STEPPER_KICK_COUNTS 12U
#endif
/* MOTION_STEPPER_TRACE = 1: D4 (PG5) is high while a planner tick runs (nested interrupts included);
 * 2: D4 is high from a stop's or a new target's cut of the queue (Stepper::plan_at_cut) until the
 * new plan's first commands are laid out (what MOTION_STEPPER_CUT_US must cover) */
#ifndef MOTION_STEPPER_TRACE
#define MOTION_STEPPER_TRACE 0
#endif

class Stepper;
class StepperGroup;

class BackgroundPlanner {
public:
    /* The step engine (the rings, pins, Timer1) and Timer3's interrupt; once (later calls do nothing).
     * False: no room on the heap for the rings (nothing begun). */
    static bool begin();
    static bool running() { return begun_; }
    /* Steps kept queued ahead of each axis, ms (1..1000; from the next command laid out). The lead in
     * force is at least MOTION_STEPPER_LEAD_MS_2 / _3 with two / three Steppers begun. */
    static bool setLeadMs(uint16_t ms);
    static uint16_t leadMs();
    /* The step timer's ticks per second (Stepper::setTickRate): 16 MHz by default, 2 MHz for the
     * lab's ramps; 1 MHz in timed-loop mode (micros()). */
    static uint32_t tickHz() { return tick_hz_; }
    /* the same per microsecond (16, 2 or 1), kept: a 32-bit division costs the planner interrupt
     * some 600 cycles, which a cut planned 600 us ahead cannot spare */
    static uint8_t ticksPerUs() { return tpu_; }
    static bool setTickHz(uint32_t hz);
    /* (planner interrupt) for the next `ms` ticks a tick feeds a stepping queue of the engine's axes
     * `axes` (a bit each) that holds less than MOTION_STEPPER_LOW_MS past its
     * MOTION_STEPPER_CMDS_PER_TICK commands (StepperGroup::stop_mirrored: the rest of the stop's
     * commands, planned late); another catch-up meanwhile adds its axes */
    static void catchUp(uint16_t ms, uint8_t axes);

    /* Planning from loop() instead of Timer3's interrupt, for a sketch whose loop() never blocks and
     * calls poll() on every pass (the stepper sketches' console, MotionConsole.h): call it before
     * the first begin(); false after. Timer3 then stays free and no planner interrupt enters
     * between the step interrupts (those of ExactRampStepper at 100,000 steps/s); a Stepper alone
     * may then step up to STEPPER_MAX_SPS_EXACT (Stepper.h's setMaxSpeed). A loop() that blocks
     * (delay()) starves the queue in this mode: the default, the interrupt, is the one for that. */
    static bool planInLoop();
    static bool inLoop() { return in_loop_; }
    /* Whether Timer3's interrupt is linked into the sketch (BackgroundPlannerTimer.cpp: MotionStepper.h
     * links it; a sketch that includes only MotionConsole.h plans in loop() and has none). */
    static bool timerLinked();
    /* With planInLoop() (and in timed-loop mode, STEPPER_TIMED_LOOP = 1, where loop() also makes X's
     * steps that are due by micros()): the planner's tick, on every pass of loop(). Otherwise it
     * does nothing: the interrupt plans, loop() is free. */
    static void poll();

    /* The heap a StepperGroup made takes at its first move (its stop's room, StepperGroup.h): the
     * Steppers' begin() leave it when they take their stop planned ahead's room. */
    static void leaveForGroups(uint16_t bytes) { group_bytes_ = (uint16_t)(group_bytes_ + bytes); }
    static uint16_t groupBytes() { return group_bytes_; }

    /* Steppers begun (their axes claimed): 0 to 3. */
    static uint8_t steppers() { return count_; }
    /* The steps per second of all the Steppers' axes together now: their step interrupts' load. */
    static float stepRate();

    /* Registers s as the stepper of its axis; false when another holds it. */
    static bool claim(uint8_t axis, Stepper *s);
    static Stepper *stepper(uint8_t axis) { return axis < 3 ? axes_[axis] : 0; }

    /* Brings the next tick forward to within about 50 us (a stop or a new target left by loop()):
     * it then acts without waiting up to a millisecond for the tick. Under a PlannerLock the unlock
     * brings it (8 us after the unlock). */
    static void kick();

    /* From now on a tick that has run MOTION_STEPPER_TICK_US stops laying out commands once every
     * stepping queue holds half the lead (setRamp(RAMP_ALGO_SMOOTH) turns it on: its commands can
     * cost milliseconds each). It stays on, for every axis, also after a Stepper goes back to
     * another ramp (as the smooth ramp's lead does); a sketch that never takes the smooth ramp
     * keeps its ticks as they were. */
    static void shareLongTicks() { share_ = true; }

    /* One tick's work (the interrupt calls it; public for the vector only). */
    static void tick();
    /* The tick's part, for a Stepper about to plan at a cut (its run_request): every stepping queue
     * fed up to MOTION_STEPPER_PLAN_SAFE_MS first, when there are two or three Steppers (but axis
     * except's: a stop laid out reversed, whose planner plans the rest after this; StepCut.h). */
    static void feedBeforePlan(uint8_t except = 3);
    /* The tick's part: the second half of every cut in the cruise done this tick (Stepper::adopt_cut),
     * before anything is laid out or planned at a cut. */
    static void finishCuts();

private:
    static void feed(uint32_t up_to, uint8_t except = 3);
    static void collect_done();
    static void apply_lead();
    static Stepper *axes_[3];
    static uint8_t count_;
    static bool begun_;
    static uint16_t lead_ms_;
    static bool share_;
    static uint32_t tick_hz_;
    static uint8_t tpu_;
    static bool in_loop_;
    static uint16_t catch_ticks_;
    static uint8_t catch_mask_; /* the engine's axes that catch up (catchUp) */
    static uint16_t group_bytes_;
};

/* What the planner interrupt's vector (BackgroundPlannerTimer.cpp) and BackgroundPlanner.cpp share;
 * not for sketches. */
struct PlannerIrqState {
    volatile uint8_t in_tick;      /* a tick under way: the re-entrancy guard */
    volatile uint8_t locks;        /* PlannerLocks alive */
    volatile uint8_t deferred;     /* a tick came while loop() held a lock */
    volatile uint8_t deferrals;    /* ticks deferred by locks in a row */
    volatile uint8_t step_mask[3]; /* each claimed axis's STEP bit in its port (0: no Stepper there): the
                                      vector's test of a step interrupt under way looks at these alone,
                                      so that a sketch may drive the other axes' STEP pins */
    uint8_t retry;                 /* Timer3 counts to the next retry */
};
extern PlannerIrqState planner_irq;

/* Holds the planner interrupt off while it lives (loop()'s changes to a planner): the planner
 * interrupt is not running when loop() runs (it preempts loop(), never the other way), so keeping it
 * from starting is all the synchronisation the planners need; a tick that comes meanwhile comes back 8 us
 * after the unlock (the third in a row deferred so runs at the unlock, in the caller: with
 * interrupts on, so do not hold a lock with them off). Nests. */
class PlannerLock {
public:
    PlannerLock();
    ~PlannerLock();
    PlannerLock(const PlannerLock &) = delete;
    PlannerLock &operator=(const PlannerLock &) = delete;
};

#endif
