/* BlockingLoop - a loop() that blocks for a second at a time (delay(1000)) while the RAMPS X axis
 * makes a 20,000-step move at 20,000 steps/s (50,000 steps/s^2): the steps do not wait for loop(),
 * Timer3's interrupt keeps the step queue planned (MotionStepper.h). Serial Monitor at 9600 baud:
 * once a second the position and speed, then the end of the move and the underruns (0).
 */
#include <MotionStepper.h>

Stepper x(Stepper::X);
static bool finished = false;

void setup()
{
    Serial.begin(9600);
    motion_status_t st = x.setMaxSpeed(20000);
    if (st == MS_OK)
        st = x.setAcceleration(50000);
    if (st == MS_OK)
        st = x.begin();
    if (st == MS_OK)
        st = x.moveTo(20000);
    Serial.println(F("READY BlockingLoop"));
    if (st != MS_OK) {
        Serial.print(F("ERR "));
        Serial.println(Stepper::statusText(st));
    } else {
        Serial.println(F("moveTo 20000, then delay(1000) in every loop()"));
    }
}

void loop()
{
    long at;
    delay(1000); /* a loop() busy with something else: the move goes on */
    if (finished)
        return;
    Serial.print(F("pos="));
    Serial.print(x.currentPosition());
    Serial.print(F(" speed="));
    Serial.println(x.speed(), 0);
    if (x.takeDone(at)) {
        Serial.print(F("DONE "));
        Serial.print(at);
        Serial.print(F(" underruns="));
        Serial.println(x.underruns());
        finished = true;
    }
}
