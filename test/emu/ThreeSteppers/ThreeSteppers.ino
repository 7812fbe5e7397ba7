// motion-sketch: library
/* ThreeSteppers - a test sketch (tools/emu/emu.mk builds it; test/emu/checks_library.py,
 * check_three_steppers): TS_N MotionStepper Steppers (X, Y, Z; 2 or 3) move 0 -> TS_D and back
 * twice, all at once, at TS_V steps/s and TS_A steps/s^2. It prints each call's status
 * ("setMaxSpeed X 0", ...), after each leg "ROUND <k> <position> u=<underruns> ..." for every axis.
 * Then every axis moves towards 1,000,000 ("MOVE 1000000"); when D3 goes low (the script's switch)
 * every axis gets stop() ("STOP"), and at rest "DONE <X's position> underruns=<X's underruns>",
 * "AT <position> u=<underruns> ..." for every axis, then FINISHED. D6 toggles on every pass of
 * loop(): the check measures how long loop() waits for the planner; D5 goes high just before the
 * stop() calls: the check measures the latency from the call as well as from the switch. Until 2026-12-05 three Steppers moving at once ran their queues dry thousands of
 * times, even at 10,000 steps/s, and a Z step could hold its STEP high for 18 ms
 * (BackgroundPlanner.h: MOTION_STEPPER_RETRY_COUNTS, MOTION_STEPPER_LEAD_MS_2/_3; Stepper.h:
 * MOTION_STEPPER_CMD_MS_3). */
#ifndef TS_N
#define TS_N 3
#endif
#ifndef TS_V
#define TS_V 10000
#endif
#ifndef TS_A
#define TS_A 50000
#endif
#ifndef TS_D
#define TS_D 20000L
#endif
#include <MotionStepper.h>

Stepper x(Stepper::X), y(Stepper::Y), z(Stepper::Z);
static Stepper *const all[3] = {&x, &y, &z};
static uint8_t leg = 0;
static bool stopped = false;

static void report(const __FlashStringHelper *what, uint8_t i, motion_status_t st)
{
    Serial.print(what);
    Serial.print(' ');
    Serial.print("XYZ"[i]);
    Serial.print(' ');
    Serial.println((int)st);
}

/* " <position> u=<underruns>" for every axis, then the line's end */
static void print_axes()
{
    for (uint8_t i = 0; i < TS_N; i++) {
        Serial.print(' ');
        Serial.print(all[i]->currentPosition());
        Serial.print(F(" u="));
        Serial.print(all[i]->underruns());
    }
    Serial.println();
}

static void go()
{
    long to = (leg & 1) ? 0L : TS_D;
    for (uint8_t i = 0; i < TS_N; i++)
        report(F("moveTo"), i, all[i]->moveTo(to));
}

void setup()
{
    Serial.begin(115200);
    pinMode(3, INPUT_PULLUP); /* the stop switch: closed = low */
    DDRH |= _BV(PH3);         /* D6: toggled on every pass of loop() (its turns, measured) */
    DDRE |= _BV(PE3);         /* D5: high from the first stop() call on (the latency from the call) */
    for (uint8_t i = 0; i < TS_N; i++) {
        report(F("setMaxSpeed"), i, all[i]->setMaxSpeed(TS_V));
        report(F("setAcceleration"), i, all[i]->setAcceleration(TS_A));
        report(F("begin"), i, all[i]->begin());
    }
    Serial.print(F("READY ThreeSteppers lead="));
    Serial.println(BackgroundPlanner::leadMs());
    go();
}

void loop()
{
    long at;
    bool moving = false;
    PINH = _BV(PH3); /* D6 toggles (writing 1 to PINx flips the pin) */
    for (uint8_t i = 0; i < TS_N; i++) {
        (void)all[i]->takeDone(at);
        if (all[i]->isRunning())
            moving = true;
    }
    if (leg == 4) {
        /* the run towards 1,000,000: stopped at the switch */
        if (!stopped && digitalRead(3) == LOW) {
            {
                /* D5 high: the stop() calls come now. The planner held off meanwhile (PlannerLock, as
                 * StopOnSwitch measures its calls): a tick due then comes right after the calls
                 * instead of between D5 and them (with three Steppers at 25,000 steps/s one tick fed
                 * the queues for 2.2 ms there, and loop() made its calls that much later: loop()'s
                 * wait, measured apart; the latency from the call is the calls' own) */
                PlannerLock calls;
                PORTE |= _BV(PE3);
                for (uint8_t i = 0; i < TS_N; i++)
                    (void)all[i]->stop();
            }
            stopped = true;
            Serial.println(F("STOP"));
        } else if (stopped && !moving) {
            Serial.print(F("DONE "));
            Serial.print(x.currentPosition());
            Serial.print(F(" underruns="));
            Serial.println(x.underruns());
            Serial.print(F("AT"));
            print_axes();
            Serial.println(F("FINISHED"));
            leg = 5;
        }
        return;
    }
    if (moving || leg > 4)
        return;
    Serial.print(F("ROUND "));
    Serial.print(leg);
    print_axes();
    if (++leg == 4) {
        Serial.println(F("MOVE 1000000"));
        for (uint8_t i = 0; i < TS_N; i++)
            report(F("moveTo"), i, all[i]->moveTo(1000000L));
    } else {
        go();
    }
}
