// motion-sketch: multiaxis
/* MultiAxisStepper - the X, Y and Z drivers of a RAMPS 1.4, each a Stepper of the MotionStepper
 * library with the exact constant-acceleration ramp (every step planned within one tick of
 * F = 16 MHz of its time; the three step interrupts nest, so on the pins an edge waits for no other
 * axis's step), moved one at a time, several at once, or together on a straight line (a
 * StepperGroup). Wiring and limits: MotionBoard's MultiAxisPins.h; the rates measured by `make bench`
 * are in docs/bench.md; docs/multi-axis.md explains it all.
 *
 * How: the console (MotionConsole.h; its `move` part: MotionConsoleMove.cpp) carries out every line through the Steppers' and the group's
 * public calls (moveTo, stop, forceStop, the setters), as your own sketch would; the planner runs in
 * loop() (console.poll()) and keeps each axis's queue of step commands ahead; Timer1's three compare
 * interrupts (A: X, B: Y, C: Z, one timeline) only take the next command and make the step.
 * Defaults per axis: v0 = 0, vmax = 10,000 steps/s, accel = 10,000 steps/s^2 (three axes moving
 * independently at once stay clean at these; docs/bench.md has the ceilings).
 * Serial Monitor at 9600 baud, "Both NL & CR":
 *   x 20000          move X alone to 20000: "OK x 0 20000", later "DONE x 20000" (y, z likewise)
 *   move x1000 y500  X and Y together on the line from where they are to (1000, 500): both start
 *                    and end on one planned tick: "OK move x 0 1000 y 0 500", later "DONE move x 1000 y 500"
 *   stop  /  !       decelerate every axis to rest / halt at once (stop x, ! y: one axis)
 *   ?                one line per axis: position, target, state, limits, underruns= late=
 *   set y vmax 5000  v0, vmax (up to max_sps) or accel of one axis
 * The same commands come out of `motionsim move --x 1000 --y 500 --vmax 10000 --accel 10000`
 * (coordinated; motionsim's own defaults are faster) and `motionsim ramp --algo exact --tick-hz
 * 16000000 --queue` (an axis alone).
 */
#include <MotionStepper.h>
#include <MotionConsole.h>

static Stepper x(Stepper::X);
static Stepper y(Stepper::Y);
static Stepper z(Stepper::Z);
static StepperGroup xyz(x, y, z); /* `move`: straight lines */
static MotionConsole console(x, y, z, xyz);

void setup()
{
    x.setMaxSpeed(10000);     // steps/s, each axis
    x.setAcceleration(10000); // steps/s^2
    y.setMaxSpeed(10000);
    y.setAcceleration(10000);
    z.setMaxSpeed(10000);
    z.setAcceleration(10000);
    x.begin();
    y.begin();
    z.begin();
    console.begin(F("MultiAxisStepper"));
}

void loop()
{
    console.poll();
}
