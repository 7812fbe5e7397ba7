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
 *   moveOneStep(), with dirPin (11)     the step interrupt (StepEngineIsr.S): STEP, and DIR high
 *                                       for forwards (FWDS), low for backwards, before the step
 * Both functions run in loop(), ahead of the motor: the planner (step_planner.h) turns their
 * intervals into step commands, and Timer1's compare interrupt only plays those back, so the
 * float arithmetic never delays a step. The arithmetic itself is lib's ramp_leib.c, the code
 * `motionsim ramp --algo leib` runs: change it here and the board follows your version.
 * The files behind this sketch: StepperConsole.h (the serial commands), StepEngine.h (the queue
 * and the step interrupt), step_planner.h (moves into step commands), ramp_leib.h (the ramp).
 * Pins, timer and the compile-time options (STEPPER_TIMED_LOOP, STEPPER_LED_MIRROR,
 * STEPPER_TRACE, given to every file through FIRMWARE_DEFINES): MotionBoard's StepperPins.h.
 */
#include <StepperConsole.h>
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

static const ramp_hooks_t labCode = {preComputation, computeNewSpeed, 0, 0};
static TrapezoidRamp ramp(RAMP_ALGO_LEIB, minSpeed, maxPermisSpeed, maxAccel, STEPPER_MAX_SPS_LEIB,
                          STEPPER_TICK_HZ_LAB, &labCode);
static StepperConsole console(ramp);

// Timer1's compare interrupt: makes the steps the planner queued (StepEngine.h)
#if !STEPPER_TIMED_LOOP
ISR(TIMER1_COMPA_vect, ISR_NAKED)
{
    StepEngine::on_step_timer(); /* jumps to the step routine, which returns from the interrupt */
}
#endif

void setup()
{
    console.begin(F("LeibRampStepper"));
}

void loop()
{
    console.poll(); // serial commands, and the planner keeping the step queue ahead
}
