/* SmoothMove - the RAMPS X axis on the smooth (filter-shaped, jerk-limited) ramp: vmax 10,000 steps/s,
 * accel 20,000 steps/s^2, jerk 200,000 steps/s^3 (tau1 = vmax/accel = 0.5 s, tau2 = accel/jerk =
 * 0.1 s). Acceleration and jerk never above those, velocity and acceleration continuous, every step
 * on the law within a tick (docs/smooth-move.md). Serial Monitor at 115200 baud shows what it does:
 *   out to 20000 and back to 0;
 *   out to 20000 again, stop() at 8000: the velocity command goes to 0, the axis comes to rest
 *     smoothly (some 3000 steps further: vmax (tau1 + tau2) / 2);
 *   back towards 0, and at 9000 a new target farther on, -6000: the move continues from its speed
 *     and acceleration (no stop);
 *   out to 12000, and at 3000 a new target behind where a stop would come to rest, 1000: it stops
 *     smoothly, then comes back from rest;
 *   then at 20,000 steps/s (accel 40,000): out to 41000, retargeted at 20000 to 31000;
 *   back towards 0, halted by forceStop() at 25000 (no step after it), and from there to 0.
 * The first step of each move comes some 150 ms after moveTo() (the smooth planner banks its first
 * commands); a stop or a new target cuts the queue MOTION_STEPPER_SMOOTH_CUT_US (60 ms) ahead and
 * acts there (after the lead of 150 ms if planning it took longer: cutsMissed() counts those).
 * loop() only looks; at the end it prints cutsMissed() and its longest pass (the planner
 * interrupt's work at a move's start and after a cut holds loop() for tens of milliseconds:
 * docs/smooth-move.md has the figure).
 */
#include <MotionStepper.h>

Stepper x(Stepper::X);
static uint8_t leg = 0;
static bool acted = false; /* this leg's stop or new target has been given */
static unsigned long last_pass = 0, longest_pass = 0; /* micros() */

static void say(const __FlashStringHelper *what, motion_status_t st)
{
    Serial.print(what);
    Serial.print(F(": "));
    if (st == MS_OK)
        Serial.println(F("OK"));
    else
        Serial.println(Stepper::statusText(st));
}

static void go(long target)
{
    Serial.print(F("moveTo "));
    Serial.println(target);
    motion_status_t st = x.moveTo(target);
    if (st != MS_OK)
        say(F("moveTo"), st);
    acted = false;
}

/* the leg's stop or new target, once, when the position passes `at` (going up: >=, down: <=) */
static bool passed(long at, bool up)
{
    long p = x.currentPosition();
    if (acted || (up ? p < at : p > at))
        return false;
    acted = true;
    return true;
}

void setup()
{
    Serial.begin(115200);
    say(F("setMaxSpeed(10000)"), x.setMaxSpeed(10000));
    say(F("setAcceleration(20000)"), x.setAcceleration(20000));
    say(F("setJerk(0)"), x.setJerk(0));
    say(F("setJerk(NAN)"), x.setJerk(NAN));
    say(F("setJerk(30000)"), x.setJerk(30000)); /* below accel^2/vmax = 40000: tau2 > tau1 */
    say(F("setJerk(200000)"), x.setJerk(200000));
    say(F("setRamp(SMOOTH)"), x.setRamp(RAMP_ALGO_SMOOTH));
    say(F("setMaxSpeed(60000)"), x.setMaxSpeed(60000)); /* above STEPPER_MAX_SPS_SMOOTH */
    say(F("begin()"), x.begin());
    Serial.println(F("READY SmoothMove"));
    go(20000);
}

void loop()
{
    long at;
    unsigned long now = micros();
    if (last_pass != 0 && now - last_pass > longest_pass)
        longest_pass = now - last_pass; /* how long loop() waited for the planner interrupt */
    last_pass = now;
    if (leg == 2 && passed(8000, true)) {
        Serial.print(F("stop at "));
        Serial.println(x.currentPosition());
        motion_status_t st = x.stop();
        if (st != MS_OK)
            say(F("stop"), st);
    } else if (leg == 3 && passed(9000, false)) {
        Serial.print(F("retarget -6000 at "));
        Serial.println(x.currentPosition());
        say(F("moveTo(-6000)"), x.moveTo(-6000));
    } else if (leg == 4 && passed(3000, true)) {
        Serial.print(F("retarget 1000 at "));
        Serial.println(x.currentPosition());
        say(F("moveTo(1000)"), x.moveTo(1000));
        say(F("setRamp(EXACT) while moving"), x.setRamp(RAMP_ALGO_EXACT));
    } else if (leg == 5 && passed(20000, true)) {
        Serial.print(F("retarget 31000 at "));
        Serial.println(x.currentPosition());
        say(F("moveTo(31000)"), x.moveTo(31000));
    } else if (leg == 6 && passed(25000, false)) {
        motion_status_t st = x.forceStop();
        Serial.print(F("forceStop at "));
        Serial.println(x.currentPosition());
        if (st != MS_OK)
            say(F("forceStop"), st);
    }
    if (!x.takeDone(at))
        return;
    Serial.print(F("DONE "));
    Serial.print(at);
    Serial.print(F(" underruns="));
    Serial.println(x.underruns());
    leg++;
    if (leg == 1)
        go(0);
    else if (leg == 2)
        go(20000);
    else if (leg == 3)
        go(0);
    else if (leg == 4)
        go(12000);
    else if (leg == 5) {
        say(F("setMaxSpeed(20000)"), x.setMaxSpeed(20000));
        say(F("setAcceleration(40000)"), x.setAcceleration(40000));
        go(41000);
    } else if (leg == 6 || leg == 7)
        go(0);
    else {
        Serial.print(F("cutsMissed() "));
        Serial.print(x.cutsMissed());
        Serial.print(F(", longest loop() pass "));
        Serial.print(longest_pass);
        Serial.println(F(" us"));
        Serial.println(F("FINISHED"));
    }
}
