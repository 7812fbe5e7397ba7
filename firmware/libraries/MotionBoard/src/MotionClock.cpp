/* MotionClock.cpp - the millisecond clock lib/ modules ask for (motion_clock_ms(), declared in
 * lib/src/MotionPID.h): on the board it is Arduino's millis(). lib/ cannot call millis() itself
 * (no Arduino.h there), so this thin adapter lives in the board library. */
#include <Arduino.h>

#include <MotionPID.h>

extern "C" uint32_t motion_clock_ms(void)
{
    return millis();
}
