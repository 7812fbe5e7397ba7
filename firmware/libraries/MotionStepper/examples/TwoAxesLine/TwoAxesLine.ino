/* TwoAxesLine - the RAMPS X and Y axes together on straight lines (a StepperGroup): both start on
 * one tick, end together, and at every step each axis is within one step of the line; each keeps its
 * own limits (Y is slower here: the profile takes the tighter one). Serial Monitor at 9600 baud.
 */
#include <MotionStepper.h>

Stepper x(Stepper::X);
Stepper y(Stepper::Y);
StepperGroup xy(x, y);

static const long TARGETS[][2] = {{4000, 1500}, {1000, 3000}, {0, 0}};
static uint8_t leg = 0;

static void refused(const __FlashStringHelper *when, motion_status_t st)
{
    Serial.print(when);
    Serial.print(st == MS_OK ? F(": OK") : F(": ERR "));
    if (st != MS_OK)
        Serial.print(Stepper::statusText(st));
    Serial.println();
}

static void go()
{
    unsigned long t0 = micros();
    motion_status_t st = xy.moveTo(TARGETS[leg][0], TARGETS[leg][1]); /* planned by the planner interrupt */
    unsigned long took = micros() - t0;
    Serial.print(F("moveTo "));
    Serial.print(TARGETS[leg][0]);
    Serial.print(' ');
    Serial.print(TARGETS[leg][1]);
    Serial.print(F(" (returned in "));
    Serial.print(took);
    Serial.println(F(" us)"));
    if (st != MS_OK) {
        Serial.print(F("ERR "));
        Serial.println(Stepper::statusText(st));
    }
}

void setup()
{
    Serial.begin(9600);
    x.setMaxSpeed(10000);
    x.setAcceleration(20000);
    y.setMaxSpeed(5000);
    y.setAcceleration(20000);
    /* a group moves only once every member has begun: before that nothing moves */
    refused(F("group moveTo before begin()"), xy.moveTo(TARGETS[0][0], TARGETS[0][1]));
    x.begin();
    refused(F("group moveTo with only x begun"), xy.moveTo(TARGETS[0][0], TARGETS[0][1]));
    y.begin();
    Serial.println(F("READY TwoAxesLine"));
    go();
}

void loop()
{
    if (leg < 3 && xy.takeDone()) {
        Serial.print(F("DONE x="));
        Serial.print(x.currentPosition());
        Serial.print(F(" y="));
        Serial.print(y.currentPosition());
        Serial.print(F(" underruns="));
        Serial.println(x.underruns() + y.underruns());
        if (++leg < 3)
            go();
        else
            Serial.println(F("FINISHED"));
    }
}
