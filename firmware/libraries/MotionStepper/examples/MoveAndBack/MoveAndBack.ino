/* MoveAndBack - the RAMPS X axis to 10000 and back to 0, at 20,000 steps/s with 50,000 steps/s^2,
 * every step on the exact constant-acceleration ramp. Serial Monitor at 9600 baud shows what it does.
 * loop() only looks: the moves run by themselves (Timer1 steps, Timer3 plans: MotionStepper.h).
 */
#include <MotionStepper.h>

Stepper x(Stepper::X);
static uint8_t leg = 0; /* 0: going out, 1: coming back, 2: done */
static long farthest = 0;

static void report(const __FlashStringHelper *what, motion_status_t st)
{
    if (st == MS_OK)
        return;
    Serial.print(F("ERR "));
    Serial.print(what);
    Serial.print(F(": "));
    Serial.println(Stepper::statusText(st));
}

void setup()
{
    Serial.begin(9600);
    report(F("setMaxSpeed"), x.setMaxSpeed(20000));
    report(F("setAcceleration"), x.setAcceleration(50000));
    report(F("begin"), x.begin());
    Serial.println(F("READY MoveAndBack"));
    Serial.println(F("moveTo 10000"));
    report(F("moveTo"), x.moveTo(10000));
}

void loop()
{
    long at, p = x.currentPosition(); /* polled as fast as loop() turns: the steps do not mind */
    if (p > farthest)
        farthest = p;
    if (leg < 2 && x.takeDone(at)) {
        p = x.currentPosition(); /* the last step may have come after the read above */
        if (p > farthest)
            farthest = p;
        Serial.print(F("DONE "));
        Serial.print(at);
        Serial.print(F(" farthest="));
        Serial.print(farthest);
        Serial.print(F(" underruns="));
        Serial.println(x.underruns());
        if (leg == 0) {
            Serial.println(F("moveTo 0"));
            report(F("moveTo"), x.moveTo(0));
        } else {
            Serial.println(F("FINISHED"));
        }
        leg++;
    }
}
