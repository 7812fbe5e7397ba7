// motion-sketch: stepper
/* SCurveStepper - the S-curve article's sigmoid S-curve: a table of timer periods from fmin to fmax along a
 * logistic curve, each entry held for `hold` steps, walked backwards to stop. The article changes
 * the period inside the step timer's own interrupt; here the planner lays the periods out in
 * loop() as step commands ahead of time, and Timer1's compare interrupt plays them back on the
 * same timer, so each period still starts exactly where the last one ended. RAMPS 1.4 X axis.
 *
 * Defaults: the article's shape (hold = 4, flex = 5, the middle of its "ideal 4-6") with a shorter table
 * (len = 250, so 1000 steps and about 1.3 s of acceleration) scaled to what the Mega steps
 * comfortably: fmin = 200, fmax = 4000 steps/s on the 2 MHz timer. Serial Monitor at 9600 baud:
 *   20000         move to absolute position 20000: "OK 0 20000", then "DONE 20000"
 *   ?             position, state, table parameters, acceleration time and steps
 *   set vmax 3000 v0 (= fmin), vmax (= fmax), flex, len, hold; the table is recomputed (about
 *                 0.1 s for 250 entries, up to 1000). `set accel` is refused: it follows from the others.
 * The sketch is a user of the MotionStepper library (docs/library.md): a Stepper on X with the
 * sigmoid ramp (x.setRamp(RAMP_ALGO_SIGMOID), its shape x.setSigmoid(flex, len, hold)), and
 * MotionConsole turning each serial line into one of its calls (set len -> x.setSigmoid(), a target
 * -> x.moveTo() ...). The table is refilled at rest, two entries per pass of loop(); a target sent
 * meanwhile waits for it. Pins, timer and compile-time options: MotionBoard's StepperPins.h. The
 * same table and stepping run in `motionsim ramp --algo sigmoid --timer-hz 2000000 --len 250 --fmin
 * 200 --fmax 4000 --flex 5 --hold 4`.
 */
#include <MotionConsole.h> // the serial console, and through it the MotionStepper library's Stepper

// the RAMPS 1.4 X axis (STEP D54, DIR D55, ENABLE D38) on the sigmoid ramp (only its planner linked)
Stepper x(Stepper::X, RAMP_ALGO_SIGMOID, 0);
static MotionConsole console(x); // the serial commands, each one a call of x; it plans in loop()

void setup()
{
    Stepper::setTickRate(STEPPER_TICK_HZ_LAB); // the 2 MHz timer: the table's periods count its ticks
    x.setMinSpeed(200);                        // fmin, steps/s (first: the sigmoid needs fmin > 0)
    x.setMaxSpeed(4000);                       // fmax, steps/s
    x.setSigmoid(5.0, 250, 4);                 // flex, len (table entries), hold (steps per entry)
    x.setRamp(RAMP_ALGO_SIGMOID);              // fills the table (about 0.1 s)
    x.begin();
    console.begin(F("SCurveStepper"));
}

void loop()
{
    console.poll();
}
