/* SmoothStart - a test sketch of the emulator suite (test/emu/checks_library.py, check_smooth_start),
 * not an example: the smooth ramp on the RAMPS X axis at its rate limit with a high acceleration and
 * jerk (20,000 steps/s, 60,000 steps/s^2, 400,000 steps/s^3), where the commands near rest cover a
 * step or two and cost more than the time they cover. Out to 20000, retargeted at 10000 to 25000,
 * back towards 0, stopped at 10000. Prints each call's status, each DONE with the underruns so far,
 * then FINISHED.
 * Built a second time (tools/emu/emu.mk, EMU_SMOOTHSTALL_ELF) with the smooth limit lifted and
 * SMOOTHSTART_VMAX 50000, SMOOTHSTART_ACCEL 250000, SMOOTHSTART_JERK 2500000: far beyond what the
 * smooth planner keeps up with, so the queue runs dry many times, and every time the engine must step
 * on (check_smooth_stall: once that stalled the axis for good, still "moving").
 */
#include <MotionStepper.h>

#ifndef SMOOTHSTART_VMAX
#define SMOOTHSTART_VMAX 20000
#endif
#ifndef SMOOTHSTART_ACCEL
#define SMOOTHSTART_ACCEL 60000
#endif
#ifndef SMOOTHSTART_JERK
#define SMOOTHSTART_JERK 400000
#endif

Stepper x(Stepper::X);
static uint8_t leg = 0;
static bool acted = false;

static void status(const __FlashStringHelper *what, motion_status_t st)
{
    Serial.print(what);
    Serial.print(F(" "));
    Serial.println((int)st);
}

void setup()
{
    Serial.begin(115200);
    status(F("setRamp"), x.setRamp(RAMP_ALGO_SMOOTH));
    status(F("setMaxSpeed"), x.setMaxSpeed(SMOOTHSTART_VMAX));
    status(F("setJerk"), x.setJerk(SMOOTHSTART_JERK));
    status(F("setAcceleration"), x.setAcceleration(SMOOTHSTART_ACCEL));
    status(F("begin"), x.begin());
    Serial.println(F("READY SmoothStart"));
    status(F("moveTo 20000"), x.moveTo(20000));
}

void loop()
{
    long at, p = x.currentPosition();
    if (!acted && leg == 0 && p >= 10000) {
        acted = true;
        status(F("moveTo 25000"), x.moveTo(25000));
    } else if (!acted && leg == 1 && p <= 10000) {
        acted = true;
        status(F("stop"), x.stop());
    }
    if (!x.takeDone(at))
        return;
    Serial.print(F("DONE "));
    Serial.print(at);
    Serial.print(F(" underruns="));
    Serial.println(x.underruns());
    leg++;
    acted = false;
    if (leg == 1)
        status(F("moveTo 0"), x.moveTo(0));
    else
        Serial.println(F("FINISHED"));
}
