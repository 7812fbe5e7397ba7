// motion-sketch: library
/* GroupStop - a test sketch (tools/emu/emu.mk builds it; test/emu/checks_library.py, check_group_stop):
 * a StepperGroup of GS_N MotionStepper Steppers (X, Y and Z: 2 or 3) at GS_V steps/s and GS_A
 * steps/s^2 each moves on the line towards (1,000,000, 500,000[, -250,000]) ("MOVE"); when D3 goes low
 * (the script's switch) D5 goes high and the group gets stop() ("STOP"); at rest it prints "DONE" with
 * every axis's position and underruns, "MISSED" with the group's cutsMissed(), then FINISHED. The check measures from D5 when each axis's
 * deceleration began (the group's stop cuts the queues a few milliseconds ahead: StepperGroup.h,
 * MOTION_STEPPER_GROUP_CUT_US) and where the axes came to rest (on the line). With GS_SET_MS, Y's
 * setAcceleration(2 GS_A) that many ms after MOVE, while the group moves: its own new constants go
 * to its idle planner, where the group's stop planned ahead waits. */
#ifndef GS_N
#define GS_N 2
#endif
#ifndef GS_V
#define GS_V 20000
#endif
#ifndef GS_A
#define GS_A 50000
#endif
#include <MotionStepper.h>

Stepper x(Stepper::X), y(Stepper::Y), z(Stepper::Z);
static Stepper *const all[3] = {&x, &y, &z};
#if GS_N == 3
StepperGroup g(x, y, z);
#else
StepperGroup g(x, y);
#endif
static bool stopped = false, finished = false;
#ifdef GS_SET_MS
static uint32_t moved_ms;
static bool set_done = false;
#endif

static void report(const __FlashStringHelper *what, uint8_t i, motion_status_t st)
{
    Serial.print(what);
    Serial.print(' ');
    Serial.print("XYZ"[i]);
    Serial.print(' ');
    Serial.println((int)st);
}

void setup()
{
    Serial.begin(115200);
    pinMode(3, INPUT_PULLUP); /* the stop switch: closed = low */
    DDRE |= _BV(PE3);         /* D5: high at the stop() call */
    for (uint8_t i = 0; i < GS_N; i++) {
        report(F("setMaxSpeed"), i, all[i]->setMaxSpeed(GS_V));
        report(F("setAcceleration"), i, all[i]->setAcceleration(GS_A));
        report(F("begin"), i, all[i]->begin());
    }
    Serial.println(F("MOVE"));
#ifdef GS_SET_MS
    moved_ms = millis();
#endif
#if GS_N == 3
    Serial.println((int)g.moveTo(1000000L, 500000L, -250000L));
#else
    Serial.println((int)g.moveTo(1000000L, 500000L));
#endif
}

void loop()
{
    if (finished)
        return;
#ifdef GS_SET_MS
    if (!set_done && millis() - moved_ms >= GS_SET_MS) {
        (void)y.setAcceleration(2.0f * GS_A); /* (for its next move: the group's holds its own) */
        set_done = true;
    }
#endif
    if (!stopped && digitalRead(3) == LOW) {
        {
            PlannerLock call; /* the call's own time, as StopOnSwitch measures it */
            PORTE |= _BV(PE3);
            (void)g.stop();
        }
        stopped = true;
        Serial.println(F("STOP"));
    } else if (stopped && !g.isRunning()) {
        Serial.print(F("DONE"));
        for (uint8_t i = 0; i < GS_N; i++) {
            Serial.print(' ');
            Serial.print(all[i]->currentPosition());
            Serial.print(F(" u="));
            Serial.print(all[i]->underruns());
        }
        Serial.println();
        Serial.print(F("MISSED "));
        Serial.println(g.cutsMissed());
        Serial.println(F("FINISHED"));
        finished = true;
    }
}
