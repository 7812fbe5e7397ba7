/* LabRamp - the ramp chosen per stepper: the RAMPS X axis goes out to 2000 on the lab's Leib ramp
 * (the handout's recurrence, lib's ramp_leib.c, as LeibRampStepper runs it) at v0 = 100, vmax = 4000
 * steps/s, accel = 8000 steps/s^2, and comes back on the lab's simplistic ramp from v0 = 1000 (its
 * deceleration creeps down to v0: from 100 it would take 10 s). Serial Monitor at
 * 9600 baud shows each call's answer: the refusals are statuses, nothing changes on them.
 * `motionsim ramp --algo leib --from 0 --to 2000 --v0 100 --vmax 4000 --accel 8000 --tick-hz 16000000
 * --integer-ticks` prints the steps' intervals tick for tick (the engine's timer runs at 16 MHz).
 */
#include <MotionStepper.h>

Stepper x(Stepper::X);
static uint8_t leg = 0; /* 0: going out (Leib), 1: coming back (simplistic), 2: done */

static void say(const __FlashStringHelper *call, motion_status_t st)
{
    Serial.print(call);
    Serial.print(F(": "));
    if (st == MS_OK)
        Serial.println(F("OK"));
    else
        Serial.println(Stepper::statusText(st));
}

void setup()
{
    Serial.begin(9600);
    say(F("setRamp(LEIB)"), x.setRamp(RAMP_ALGO_LEIB)); /* refused: the default vmax (10000) is above its limit */
    say(F("setMaxSpeed(4000)"), x.setMaxSpeed(4000));
    say(F("setMinSpeed(100)"), x.setMinSpeed(100));
    say(F("setAcceleration(8000)"), x.setAcceleration(8000));
    say(F("setRamp(LEIB)"), x.setRamp(RAMP_ALGO_LEIB));
    say(F("setMaxSpeed(20000)"), x.setMaxSpeed(20000)); /* above the Leib ramp's limit: refused */
    say(F("setRamp(SIGMOID)"), x.setRamp(RAMP_ALGO_SIGMOID)); /* refused: v0 100 is too slow for its 16-bit periods at 16 MHz */
    say(F("begin()"), x.begin());
    Serial.println(F("READY LabRamp"));
    say(F("moveTo(2000)"), x.moveTo(2000));
    say(F("setRamp(SIMPLISTIC) while moving"), x.setRamp(RAMP_ALGO_SIMPLISTIC));
}

void loop()
{
    long at;
    if (leg < 2 && x.takeDone(at)) {
        Serial.print(F("DONE "));
        Serial.print(at);
        Serial.print(F(" underruns="));
        Serial.println(x.underruns());
        if (leg == 0) {
            say(F("setRamp(SIMPLISTIC)"), x.setRamp(RAMP_ALGO_SIMPLISTIC));
            say(F("setMinSpeed(1000)"), x.setMinSpeed(1000));
            say(F("moveTo(0)"), x.moveTo(0));
        } else {
            Serial.println(F("FINISHED"));
        }
        leg++;
    }
}
