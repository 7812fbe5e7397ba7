/* PidOnly - a sketch in the style of PID_v1's examples that includes only MotionPID.h (library
 * MotionCore, lib/) and no board library: it must build and run with MotionPID's default clock,
 * millis(). Written by us for test/cli/test_firmware_options.py; it drives a made-up first-order
 * plant so that the output changes, and prints "t=<millis> out=<Output>" after every computation.
 */
#include <MotionPID.h>
typedef MotionPID PID; /* the one-line switch from PID_v1 */

double Setpoint = 100, Input = 0, Output = 0;
PID myPID(&Input, &Output, &Setpoint, 2, 5, 1, DIRECT);

void setup()
{
    Serial.begin(115200);
    myPID.SetSampleTime(20);
    myPID.SetMode(AUTOMATIC);
    Serial.println(F("READY PidOnly"));
}

void loop()
{
    static uint8_t lines;
    if (myPID.Compute() && lines < 10) {
        Input += (Output - Input) * 0.1;
        Serial.print(F("t="));
        Serial.print(millis());
        Serial.print(F(" out="));
        Serial.println(Output);
        lines++;
    }
}
