/* SCurveStepper - seed 001's sigmoid S-curve: a table of timer periods from fmin to fmax along a
 * logistic curve, each entry held for `hold` steps, walked backwards to stop. As the seed stresses,
 * the period is changed inside the step timer's own interrupt (Timer1 here), never from another
 * timer. RAMPS 1.4 X axis.
 *
 * Defaults: the seed's shape (len = 1000 entries, hold = 4, flex = 5) scaled to what the Mega steps
 * comfortably: fmin = 200, fmax = 4000 steps/s on the 2 MHz timer. Serial Monitor at 9600 baud:
 *   20000         move to absolute position 20000: "OK 0 20000", then "DONE 20000"
 *   ?             position, state, table parameters, acceleration time and steps
 *   set vmax 3000 v0 (= fmin), vmax (= fmax), flex, len, hold; the table is recomputed (about
 *                 0.2 s for 1000 entries). `set accel` is refused: it follows from the others.
 * Pins, timer and compile-time options: MotionBoard's StepperPins.h. The same table and stepping
 * run in `motionsim ramp --algo sigmoid --timer-hz 2000000 --len 1000 --fmin 200 --fmax 4000
 * --flex 5 --hold 4`.
 */
#include <StepperConsole.h>

static SCurveRamp ramp(1000, 4, 200.0f, 4000.0f, 5.0f, STEPPER_MAX_SPS_SCURVE);
static StepperConsole console(ramp);

void setup()
{
    ramp.begin();
    console.begin(F("SCurveStepper"));
}

void loop()
{
    console.poll();
}
