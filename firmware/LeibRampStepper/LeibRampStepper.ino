// motion-sketch: stepper
/* LeibRampStepper - the lab's Leib ramp (the lab handout §4.3.3: constant acceleration by one multiply-add
 * chain per step, no division) driving the X axis of a RAMPS 1.4 from Timer1's compare interrupt.
 *
 * Defaults are the lab's: v0 = 1 step/s, vmax = 20 steps/s, accel = 10 steps/s^2; watch the LED
 * (D13) flash faster, steady, slower. Serial Monitor at 9600 baud, "Both NL & CR":
 *   50            move to absolute position 50: "OK 0 50", then "DONE 50"
 *   ?             position, state and parameters on one line
 *   set vmax 800  change v0, vmax or accel between moves
 * Pins, timer and the compile-time options (STEPPER_TIMED_LOOP, STEPPER_LED_MIRROR, STEPPER_TRACE,
 * given to every file through FIRMWARE_DEFINES): MotionBoard's StepperPins.h. The same ramp runs
 * in `motionsim ramp --algo leib`.
 */
#include <StepperConsole.h>

static TrapezoidRamp ramp(RAMP_ALGO_LEIB, 1.0, 20.0, 10.0, STEPPER_MAX_SPS_LEIB, STEPPER_TICK_HZ_LAB);
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
    console.begin(F("LeibRampStepper"));
}

void loop()
{
    console.poll();
}
