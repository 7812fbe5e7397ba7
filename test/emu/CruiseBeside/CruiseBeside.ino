// motion-sketch: library
/* CruiseBeside - a test sketch (tools/emu/emu.mk builds it; test/emu/checks_library.py,
 * check_cruise_beside): three Steppers, X, Y and Z, each at 25,000 steps/s and 200,000 steps/s^2, X
 * towards 60000, Y towards -60000 and Z towards 40000, started 50 ms apart. Once all cruise, X gets a
 * target behind it (it stops and comes back to 0) and Y a stop(), one call after the other; Z gets
 * nothing. Two exact decelerations this steep at once ask more of the planner than there is near rest
 * (their queues run dry there: docs/stop-latency.md), and the planner must still keep Z's queue fed:
 * until 2026-12-07 it fed the two dry queues first at every pick, and Z, cruising, stood still for
 * 20-33 ms. At rest it prints each axis's position and underruns, then FINISHED. */
#include <MotionStepper.h>

Stepper x(Stepper::X), y(Stepper::Y), z(Stepper::Z);
static Stepper *const all[3] = {&x, &y, &z};
static uint8_t phase = 0;
static uint32_t t0;

void setup()
{
    Serial.begin(115200);
    for (uint8_t i = 0; i < 3; i++) {
        (void)all[i]->setMaxSpeed(25000);
        (void)all[i]->setAcceleration(200000);
        if (all[i]->begin() != MS_OK)
            Serial.println(F("begin refused"));
    }
    Serial.println(F("READY CruiseBeside"));
    (void)x.moveTo(60000);
    delay(50);
    (void)y.moveTo(-60000);
    delay(50);
    (void)z.moveTo(40000);
    t0 = millis();
}

void loop()
{
    if (phase == 0 && millis() - t0 >= 500) {
        motion_status_t a = x.moveTo(0), b = y.stop(); /* back to back, printed after */
        Serial.print(F("CALLS "));
        Serial.print((int)a);
        Serial.print(' ');
        Serial.println((int)b);
        phase = 1;
    } else if (phase == 1 && !x.isRunning() && !y.isRunning() && !z.isRunning()) {
        Serial.print(F("DONE"));
        for (uint8_t i = 0; i < 3; i++) {
            Serial.print(' ');
            Serial.print(all[i]->currentPosition());
            Serial.print(F(" u="));
            Serial.print(all[i]->underruns());
        }
        Serial.println();
        Serial.println(F("FINISHED"));
        phase = 2;
    }
}
