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
 *   B DONE <position>                   a move to 40000, stop() 300 ms in and moveTo(40000) right
 *                                       after it: the stop is withdrawn, the move ends at 40000
 *   C SPEED <speed()>                   a move to 0 with moveTo(0) on every pass; 600 ms in (at
 *                                       20,000 steps/s) setMaxSpeed(10000): the next moveTo(0) plans
 *                                       again with it; speed() 300 ms after the set (-10,000)
 *   C DONE <position>
 *   FINISHED
 * Until 2026-12-07 every call replanned the move (0.8 ms of the planner interrupt each), and at rest
 * every call was a move of no step: a loop() that called it until isRunning() went false never
 * left. */
#include <MotionStepper.h>

Stepper x(Stepper::X);
static uint8_t phase;
static unsigned long t0;

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
        (void)x.moveTo(40000);
        t0 = millis();
        phase = 3;
    } else if (phase == 3) {
        if (millis() - t0 >= 300) {
            (void)x.stop();
            (void)x.moveTo(40000); /* the target in force, but a stop was asked: the move goes on */
            phase = 4;
        }
    } else if (phase == 4) {
        if (x.takeDone(at)) {
            Serial.print(F("B DONE "));
            Serial.println(at);
            (void)x.setMaxSpeed(20000); /* the value in force: changes nothing */
            (void)x.moveTo(0);
            t0 = millis();
            phase = 5;
        }
    } else if (phase == 5 || phase == 6) {
        (void)x.moveTo(0); /* on every pass */
        if (phase == 5 && millis() - t0 >= 600) {
            (void)x.setMaxSpeed(10000); /* while moving: the next moveTo() plans with it */
            t0 = millis();
            phase = 6;
        } else if (phase == 6 && millis() - t0 >= 300) {
            Serial.print(F("C SPEED "));
            Serial.println(x.speed(), 0);
            phase = 7;
        }
    } else if (phase == 7) {
        if (x.takeDone(at)) {
            Serial.print(F("C DONE "));
            Serial.println(at);
            Serial.println(F("FINISHED"));
            phase = 8;
        }
    }
}
