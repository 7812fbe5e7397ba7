// motion-sketch: stepper
/* SimplisticRampStepper - the lab's starting point (the lab handout §4.3.2): the step interval changes by a
 * fixed amount per step, which "nearly works": the speed creeps up, then the acceleration near vmax
 * is far too large. Kept to compare with LeibRampStepper on the same RAMPS 1.4 X axis and timer.
 *
 * Defaults are the lab's: v0 = 1 step/s, vmax = 20 steps/s, accel = 10 steps/s^2 (which sets the
 * number of accelerating steps, as for Leib). Serial Monitor at 9600 baud, "Both NL & CR":
 *   50            move to absolute position 50: "OK 0 50", then "DONE 50"
 *   ?             position, state and parameters on one line
 *   set v0 5      change v0 (> 0 here), vmax or accel between moves
 * Pins, timer and compile-time options: MotionBoard's StepperPins.h. The same ramp runs in
 * `motionsim ramp --algo simplistic`; `motionsim ramp --compare` shows how far it is from ideal.
 */
#include <StepperConsole.h>

static TrapezoidRamp ramp(RAMP_ALGO_SIMPLISTIC, 1.0, 20.0, 10.0, STEPPER_MAX_SPS_SIMPLISTIC, STEPPER_TICK_HZ_LAB);
static StepperConsole console(ramp);
/* Timer1's compare interrupt makes the steps the planner queued (StepEngine.h) */
#if !STEPPER_TIMED_LOOP
ISR(TIMER1_COMPA_vect, ISR_NAKED)
{
    StepEngine::on_step_timer(); /* jumps to the step routine, which returns from the interrupt */
}
#endif

void setup()
{
    console.begin(F("SimplisticRampStepper"));
}

void loop()
{
    console.poll();
}
