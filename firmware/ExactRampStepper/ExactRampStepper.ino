// motion-sketch: stepper
/* ExactRampStepper - true constant acceleration on the RAMPS 1.4 X axis, fast (max_sps in `?`; the
 * rates measured by `make bench` are in docs/bench.md):
 * every step at round(F t_n) of t_n = (sqrt(v0^2 + 2 a n) - v0)/a (then the cruise line and the
 * mirrored deceleration), within one tick of F = 16 MHz, from the first step to the last.
 *
 * How: the sketch is a user of the MotionStepper library (docs/library.md): a Stepper on X, and
 * MotionConsole turning each serial line into one of its calls (a target -> x.moveTo(), stop ->
 * x.stop(), ! -> x.forceStop(), set -> x.setMaxSpeed() ...). Its planner (lib/src/step_planner.h,
 * step_exact.h) runs here in loop() (the console makes it so, BackgroundPlanner::planInLoop(): loop()
 * is the console's alone and never blocks, so no planner interrupt comes between the step
 * interrupts, and a Stepper alone may step up to max_sps) and keeps a queue of
 * step commands STEP_ENGINE_LEAD_MS ahead; Timer1's compare interrupt only takes the next command
 * and makes the step (MultiStepEngine.h, axis 0). A stop or a new target cuts the queue a few
 * milliseconds ahead (Stepper.h). Defaults: v0 = 0, vmax = 20,000 steps/s, accel = 50,000
 * steps/s^2. Serial Monitor at 9600 baud, "Both NL & CR":
 *   20000         move to absolute position 20000: "OK 0 20000", then "DONE 20000"
 *   5000          sent while moving: the move continues from its speed to 5000 (decelerating,
 *                 reversing and approaching if 5000 is behind); "OK <from> 5000", one DONE
 *   stop          decelerate to rest: "OK stop", then "DONE <position>"
 *   !             halt at once: "OK halt", then "DONE <position>"
 *   ?             position, state, parameters, underruns= (0 within the limits) late= (edges fired 2 us
 *                 late: a few near max_sps, docs/stepper-engine.md)
 *   set vmax 50000   v0, vmax (up to max_sps) or accel; while moving, from the next plan
 * Pins and compile-time options: MotionBoard's StepperPins.h. The same commands come out of
 * `motionsim ramp --algo exact --tick-hz 16000000 --queue`.
 */
#include <MotionConsole.h> // the serial console, and through it the MotionStepper library's Stepper

Stepper x(Stepper::X);           // the RAMPS 1.4 X axis: STEP D54, DIR D55, ENABLE D38; RAMP_ALGO_EXACT
static MotionConsole console(x); // the serial commands, each one a call of x; it plans in loop()


void setup()
{
    x.setMaxSpeed(20000);            // steps/s
    x.setAcceleration(50000);        // steps/s^2 (v0: the library's default, 0)
    x.begin();
    console.begin(F("ExactRampStepper"));
}

void loop()
{
    console.poll(); // serial commands, and the planner keeping the step queue ahead
}
