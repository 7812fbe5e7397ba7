// motion-sketch: library
/* SameTarget - a test sketch (tools/emu/emu.mk builds it; test/emu/checks_library.py,
 * check_same_target): loop() calls x.moveTo(20000) on every pass while X moves there (20,000
 * steps/s, 50,000 steps/s^2), as a maker's loop() calls moveTo() with a knob's or a joystick's
 * value. The target in force changes nothing, so each call must cost microseconds, and the move
 * must end as planned. D6 toggles on every pass (the check counts the passes). Prints
 *   READY SameTarget
 *   ENDED <position> underruns=<n>      the first pass that finds isRunning() false
 *   DONE <position>                     its end (takeDone), once
 *   REST <isRunning()> <takeDone()>     5 ms after moveTo(20000) at rest, where X is: nothing
 *                                       changes (no move, no end to take): "REST 0 0"
 *   FINISHED
 * Until 2026-12-07 every call replanned the move (0.8 ms of the planner interrupt each), and at rest
 * every call was a move of no step: a loop() that called it until isRunning() went false never
 * left. */
#include <MotionStepper.h>

Stepper x(Stepper::X);
static uint8_t phase;

void setup()
{
    Serial.begin(115200);
    DDRH |= _BV(PH3); /* D6: toggled on every pass of loop() */
    (void)x.setMaxSpeed(20000);
    (void)x.setAcceleration(50000);
    (void)x.begin();
    Serial.println(F("READY SameTarget"));
    (void)x.moveTo(20000);
}

void loop()
{
    long at;
    PINH = _BV(PH3); /* D6 toggles (writing 1 to PINx flips the pin) */
    if (phase == 0) {
        (void)x.moveTo(20000); /* the target in force */
        if (!x.isRunning()) {
            Serial.print(F("ENDED "));
            Serial.print(x.currentPosition());
            Serial.print(F(" underruns="));
            Serial.println(x.underruns());
            phase = 1;
        }
    } else if (phase == 1) {
        if (x.takeDone(at)) {
            Serial.print(F("DONE "));
            Serial.println(at);
            (void)x.moveTo(20000); /* at rest, where it is */
            phase = 2;
        }
    } else if (phase == 2) {
        delay(5);
        Serial.print(F("REST "));
        Serial.print(x.isRunning() ? 1 : 0);
        Serial.print(' ');
        Serial.println(x.takeDone(at) ? 1 : 0);
        Serial.println(F("FINISHED"));
        phase = 3;
    }
}
