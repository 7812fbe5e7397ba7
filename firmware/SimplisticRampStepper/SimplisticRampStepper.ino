// motion-sketch: stepper
/* SimplisticRampStepper - the lab's starting point (the lab handout §4.3.2): the step interval
 * changes by a fixed amount per step, which "nearly works": the speed creeps up, then the
 * acceleration near vmax is far too large. Kept to compare with LeibRampStepper on the same
 * RAMPS 1.4 X axis and timer.
 *
 * Defaults are the lab's: v0 = 1 step/s, vmax = 20 steps/s, accel = 10 steps/s^2 (which sets the
 * number of accelerating steps, as for Leib). Serial Monitor at 9600 baud, "Both NL & CR":
 *   50            move to absolute position 50: "OK 0 50", then "DONE 50"
 *   ?             position, state and parameters on one line
 *   set v0 5      change v0 (> 0 here), vmax or accel (while moving: from the next plan)
 *   stop  !       decelerate to rest / halt at once (then "DONE <position>")
 *
 * Where the handout's code is in this sketch:
 *   "Pre-computation code"              preComputation() below: once for every move
 *   "On-the-fly step calculation"       computeNewSpeed() below: once for every step
 *   moveOneStep(), step 11              moveOneStep() below: its two lines set dirPin high for
 *                                       FWDS, low for BWDS; the engine calls it whenever the
 *                                       direction is set (a move's first step, a reversal)
 * The ramp functions run ahead of the motor, in loop() (the MotionStepper library's planner, which
 * the console runs on every pass); Timer1's compare interrupt only plays back the step commands the
 * planner made of their intervals. The arithmetic is lib's ramp_simplistic.c, the code `motionsim ramp --algo simplistic`
 * runs; `motionsim ramp --compare` shows how far it is from ideal. The sketch is a user of the
 * library's Stepper (docs/library.md), each serial command one of its calls. From setup()/loop() to
 * the STEP pin: this file, MotionConsole.cpp, Stepper.cpp, step_planner.c, MultiStepEngine.cpp,
 * MultiStepEngineIsr.inc (what each does: the list in LeibRampStepper.ino). Pins, timer and
 * compile-time options: StepperPins.h.
 */
#include <MotionConsole.h> // the serial console, and through it the MotionStepper library's Stepper
#include <ramp_simplistic.h>

// ---- the handout's constants: the defaults of `set v0|vmax|accel` ----
const float minSpeed = 1.0;        // v0, steps/s (> 0: the first interval is F/v0)
const float maxPermisSpeed = 20.0; // vmax, steps/s
const float maxAccel = 10.0;       // a, steps/s^2
// F, the timer ticks per second: STEPPER_TICK_HZ_LAB, 2,000,000 (Timer1 at 16 MHz / 8)

// ---- Pre-computation code, for a move of stepsToGo steps (S_tot) ----
//   S = acce1Steps = (v^2 - v0^2) / (2a), v = maxPermisSpeed; if 2S > S_tot: v = sqrt(v0^2 + a S_tot),
//   S = int(S_tot / 2) (as for Leib); p_max = F / v0, p_min = F / v, dp = (p_max - p_min) / S   eq. (1)
// into ramp->accel_steps (S), ->peak_sps (v), ->p_max, ->p_min, ->dp; and p = p_max for step 1.
motion_status_t preComputation(ramp_simplistic_t *ramp, const ramp_params_t *params, uint32_t stepsToGo)
{
    return ramp_simplistic_plan(ramp, params, stepsToGo);
}

// ---- On-the-fly step calculation code: the next interval p from the last one ----
//   p = p - dp accelerating, p + dp decelerating (never above p_max), unchanged at constant speed   eq. (2)
float computeNewSpeed(ramp_simplistic_t *ramp, ramp_phase_t phase)
{
    return ramp_simplistic_update(ramp, phase);
}

// ---- moveOneStep() (step 11): the direction pin, for the steps that follow ----
// The engine calls this with direction = FWDS or BWDS before the first step of every move and at
// every reversal (then inside the step interrupt); the STEP pulses come from the step interrupt.
const uint8_t dirPin = 55;  // RAMPS 1.4 X axis DIR (A1); the driver runs forwards when it is high
const bool FWDS = true;     // forwards: the position counts up
const bool BWDS = false;    // backwards
static_assert(dirPin == STEPPER_DIR_ARDUINO_PIN, "dirPin is the step engine's DIR pin (StepperPins.h)");

void moveOneStep(bool direction)
{
    if (direction == FWDS) digitalWrite(dirPin, HIGH);
    else digitalWrite(dirPin, LOW);
}

static const ramp_hooks_t labCode = {0, 0, preComputation, computeNewSpeed};
// the RAMPS 1.4 X axis (STEP D54, DIR D55, ENABLE D38) on the simplistic ramp with your two functions
Stepper x(Stepper::X, RAMP_ALGO_SIMPLISTIC, &labCode);
static MotionConsole console(x); // the serial commands, each one a call of x


void setup()
{
    Stepper::setTickRate(STEPPER_TICK_HZ_LAB); // F = 2 MHz (Timer1 at 16 MHz / 8), the handout's F
    x.setMinSpeed(minSpeed);                    // before begin(): this ramp's v0 must be above 0,
    x.setMaxSpeed(maxPermisSpeed);              //   and the library's default vmax (10,000) is above
    x.setAcceleration(maxAccel);                //   its limit (max_sps in `?`)
    x.setDirectionHook(moveOneStep);            // DIR is yours: the engine calls moveOneStep()
    x.begin();
    console.begin(F("SimplisticRampStepper"));
}

void loop()
{
    console.poll(); // serial commands, and the planner keeping the step queue ahead
}
