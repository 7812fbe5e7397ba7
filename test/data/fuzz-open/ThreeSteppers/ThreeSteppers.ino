// motion-sketch: library
/* ThreeSteppers - an open finding (test/data/fuzz-open/README.md), not a test: three MotionStepper
 * Steppers (X, Y, Z) move 0 -> CM_D and back twice, all three at once, at CM_V steps/s and CM_A
 * steps/s^2; after each leg a line "ROUND <k> u=<X underruns> u=<Y> u=<Z>", then FINISHED. */
#ifndef CM_N
#define CM_N 3
#endif
#ifndef CM_V
#define CM_V 10000
#endif
#ifndef CM_A
#define CM_A 50000
#endif
#ifndef CM_D
#define CM_D 20000L
#endif
#include <MotionStepper.h>
Stepper x(Stepper::X), y(Stepper::Y), z(Stepper::Z);
static Stepper *all[3] = {&x, &y, &z};
static uint8_t round_ = 0;
void go()
{
    long tg = (round_ & 1) ? 0L : CM_D;
    for (uint8_t i = 0; i < CM_N; i++) all[i]->moveTo(tg);
}
void setup()
{
    Serial.begin(115200);
    for (uint8_t i = 0; i < CM_N; i++) {
        all[i]->setMaxSpeed(CM_V);
        all[i]->setAcceleration(CM_A);
        all[i]->begin();
    }
    Serial.println(F("READY ThreeSteppers"));
    go();
}
void loop()
{
    long at;
    bool any = false;
    for (uint8_t i = 0; i < CM_N; i++) {
        (void)all[i]->takeDone(at);
        if (all[i]->isRunning()) any = true;
    }
    if (!any && round_ < 4) {
        Serial.print(F("ROUND ")); Serial.print(round_);
        for (uint8_t i = 0; i < CM_N; i++) { Serial.print(F(" u=")); Serial.print(all[i]->underruns()); }
        Serial.println();
        round_++;
        if (round_ == 4) { Serial.println(F("FINISHED")); return; }
        go();
    }
}
