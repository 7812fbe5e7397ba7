// motion-sketch: stepper
/* LeibRampStepper - the lab's Leib ramp (the lab handout §4.3.3: constant acceleration by one
 * multiply-add chain per step, no division) on the X axis of a RAMPS 1.4.
 *
 * Defaults are the lab's: v0 = 1 step/s, vmax = 20 steps/s, accel = 10 steps/s^2; watch the LED
 * (D13) flash faster, steady, slower. Serial Monitor at 9600 baud, "Both NL & CR":
 *   50            move to absolute position 50: "OK 0 50", then "DONE 50"
 *   ?             position, state and parameters on one line
 *   set vmax 800  change v0, vmax or accel (while moving: from the next plan)
 *   stop  !       decelerate to rest / halt at once (then "DONE <position>")
 *
 * Where the handout's code is in this sketch:
 *   "Pre-computation code", steps 1-5   preComputation() below: once for every move
 *   "On-the-fly step calculation", 6    computeNewSpeed() below: once for every step
 *   moveOneStep(), step 11              moveOneStep() below: its two lines set dirPin high for
 *                                       FWDS, low for BWDS; the engine calls it whenever the
 *                                       direction is set (a move's first step, a reversal). Delete
 *                                       them and the motor runs one way only, as the handout says.
 * The two ramp functions run ahead of the motor, in loop() (the MotionStepper library's planner,
 * which the console runs on every pass): the planner turns their intervals into step commands, and
 * Timer1's compare interrupt only plays those back (the STEP pulses), so the float arithmetic never
 * delays a step. The arithmetic itself is lib's ramp_leib.c, the code `motionsim ramp --algo leib`
 * runs: change it here and the board follows your version.
 *
 * The sketch is a user of the MotionStepper library's Stepper, as your own sketch would be
 * (docs/library.md): it is made with its ramp (your two functions: only the lab's planner is
 * linked), setup() gives it the handout's parameters and your moveOneStep(); the console turns each serial command into one of its calls (a target ->
 * x.moveTo(), stop -> x.stop(), ! -> x.forceStop(), set -> x.setMaxSpeed() ...). Following this
 * sketch from setup()/loop() to the STEP pin takes these 5 files (each names the few-line glue it
 * hands over through):
 *   1. LeibRampStepper.ino (this file)  setup(), loop(), the three functions of the handout
 *   2. MotionConsole.cpp    poll(): a target line -> x.moveTo(target) (as move_to(target, true):
 *                           every line planned, the target in force too), then its "OK" once planned
 *   3. Stepper.cpp          moveTo() leaves the request; run_request(), called by the planner's
 *                           tick (BackgroundPlanner.cpp: tick(), run by console.poll()), plans it
 *                           with step_planner_move(), and the tick hands the commands to X's
 *                           queue (MultiStepEngine::service(), MultiStepEngine.cpp)
 *   4. step_planner.c       a move into step commands: for each interval it asks ramp.c's
 *                           ramp_next_ticks(), which calls your computeNewSpeed() (and your
 *                           preComputation() once for every move)
 *   5. MultiStepEngineIsr.inc  the step interrupt itself (Timer1 compare A, made for X by
 *                           MultiStepEngineX.S): STEP high, the next edge, STEP low. At a move's
 *                           start and at a reversal set_dir() of MultiStepEngineInternal.h calls
 *                           your moveOneStep() (through the Stepper, x.setDirectionHook)
 * Pins, timer and the compile-time options (STEPPER_TIMED_LOOP, STEPPER_LED_MIRROR, STEPPER_TRACE,
 * given to every file through FIRMWARE_DEFINES) are in MotionBoard's StepperPins.h: STEP D54, DIR
 * D55, ENABLE D38 (the RAMPS 1.4 X axis). With STEPPER_TIMED_LOOP = 1 (the lab's original structure)
 * loop() makes the steps itself: console.poll() calls BackgroundPlanner::poll().
 */
#include <MotionConsole.h> // the serial console, and through it the MotionStepper library's Stepper
#include <ramp_leib.h>

// ---- the handout's constants: the defaults of `set v0|vmax|accel` ----
const float minSpeed = 1.0;        // v0, steps/s
const float maxPermisSpeed = 20.0; // vmax, steps/s
const float maxAccel = 10.0;       // a, steps/s^2
// F, the timer ticks per second: STEPPER_TICK_HZ_LAB, 2,000,000 (Timer1 at 16 MHz / 8)

// ---- Pre-computation code (steps 1-5), for a move of stepsToGo steps (S_tot) ----
//   1. S = acce1Steps = (v^2 - v0^2) / (2a), with v = maxPermisSpeed            eq. (3)
//   2. if 2S > S_tot: v = sqrt(v0^2 + a S_tot), S = int(S_tot / 2)             eqs. (4), (5)
//   3. p1 = F / sqrt(v0^2 + 2a)   4. ps = F / v   5. R = a / F^2               eqs. (6)-(8)
// into ramp->accel_steps (S), ->peak_sps (v), ->p1, ->ps, ->r (R); and p = p1 for step 1.
motion_status_t preComputation(ramp_leib_t *ramp, const ramp_params_t *params, uint32_t stepsToGo)
{
    return ramp_leib_plan(ramp, params, stepsToGo);
}

// ---- On-the-fly step calculation code (step 6): the next interval p from the last one ----
//   a. m = -R accelerating, +R decelerating, 0 at constant speed             eqs. (9)-(11)
//   b. q = m p p      c. p = p (1 + q + 1.5 q q)      d. p never above p1     eqs. (12), (13)
// phase says which of the three situations this step is; returns the new p (ticks).
float computeNewSpeed(ramp_leib_t *ramp, ramp_phase_t phase)
{
    return ramp_leib_update(ramp, phase);
}

// ---- moveOneStep() (step 11): the direction pin, for the steps that follow ----
// The engine calls this with direction = FWDS or BWDS before the first step of every move and at
// every reversal (then inside the step interrupt, after the last step the old way); the STEP pulses
// themselves come from the step interrupt (MultiStepEngineIsr.inc), up to thousands a second.
const uint8_t dirPin = 55;  // RAMPS 1.4 X axis DIR (A1); the driver runs forwards when it is high
const bool FWDS = true;     // forwards: the position counts up
const bool BWDS = false;    // backwards
static_assert(dirPin == STEPPER_DIR_ARDUINO_PIN, "dirPin is the step engine's DIR pin (StepperPins.h)");

void moveOneStep(bool direction)
{
    if (direction == FWDS) digitalWrite(dirPin, HIGH);
    else digitalWrite(dirPin, LOW);
}

static const ramp_hooks_t labCode = {preComputation, computeNewSpeed, 0, 0};
// the RAMPS 1.4 X axis (STEP D54, DIR D55, ENABLE D38) on the Leib ramp with your two functions
Stepper x(Stepper::X, RAMP_ALGO_LEIB, &labCode);
static MotionConsole console(x); // the serial commands, each one a call of x


void setup()
{
    Stepper::setTickRate(STEPPER_TICK_HZ_LAB); // F = 2 MHz (Timer1 at 16 MHz / 8), the handout's F
    x.setMaxSpeed(maxPermisSpeed);              // before begin(): the library's default (10,000) is
    x.setMinSpeed(minSpeed);                    //   above the Leib ramp's limit (max_sps in `?`)
    x.setAcceleration(maxAccel);
    x.setDirectionHook(moveOneStep);            // DIR is yours: the engine calls moveOneStep()
    x.begin();
    console.begin(F("LeibRampStepper"));
}

void loop()
{
    console.poll(); // serial commands, and the planner keeping the step queue ahead
}
