/* FollowTarget - the RAMPS X axis goes where the serial line says: send a position in steps (a line,
 * e.g. 25000 or -3000). A new position while the axis moves replaces the target at once: the move
 * goes on from its speed to the new target (decelerating sooner, or stopping and coming back when
 * the new target lies behind), planned from a few milliseconds ahead, not after the queued steps.
 * Serial Monitor at 115200 baud, line ending "Newline".
 */
#include <MotionStepper.h>

Stepper x(Stepper::X);
static long typed = 0;
static bool negative = false, any = false;

void setup()
{
    Serial.begin(115200);
    x.setMaxSpeed(20000);
    x.setAcceleration(50000);
    x.begin();
    Serial.println(F("READY FollowTarget"));
}

void loop()
{
    long at;
    while (Serial.available()) {
        int ch = Serial.read();
        if (ch >= '0' && ch <= '9') {
            typed = typed * 10 + (ch - '0');
            any = true;
        } else if (ch == '-') {
            negative = true;
        } else if (ch == '\n') {
            if (any) {
                long target = negative ? -typed : typed;
                motion_status_t st = x.moveTo(target);
                if (st == MS_OK) {
                    Serial.print(F("MOVE "));
                    Serial.println(target);
                } else {
                    Serial.print(F("ERR "));
                    Serial.println(Stepper::statusText(st));
                }
            }
            typed = 0;
            negative = any = false;
        }
    }
    if (x.takeDone(at)) {
        Serial.print(F("DONE "));
        Serial.print(at);
        Serial.print(F(" underruns="));
        Serial.print(x.underruns());
        Serial.print(F(" missed="));
        Serial.println(x.cutsMissed());
    }
}
