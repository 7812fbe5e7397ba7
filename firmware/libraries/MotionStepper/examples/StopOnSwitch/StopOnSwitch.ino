/* StopOnSwitch - limit switches read in loop(): the RAMPS X axis runs towards a far target; when
 * the STOP switch closes it decelerates to rest (stop()), when the HALT switch closes it stops at
 * once (forceStop()). After each end it sets off the other way. Serial Monitor at 9600 baud.
 *
 * Wiring: the RAMPS 1.4 X endstop connectors, each switch between the signal pin and GND (the
 * pin's pull-up holds it high while open, a closed switch reads low): STOP on X-min (D3), HALT on
 * X-max (D2). The ATmega2560 emulator closes them with its 'pin D3 0' script command
 * (test/emu/checks_library.py). The library's planner takes Timer3, which only costs D2 and D3
 * their analogWrite(): digitalRead() is theirs.
 * Send a number (steps/s, a line) to change the speed of the moves that follow (20,000 at the start).
 */
#include <MotionStepper.h>

Stepper x(Stepper::X);
static const uint8_t STOP_PIN = 3; /* RAMPS X-min */
static const uint8_t HALT_PIN = 2; /* RAMPS X-max */
static const long FAR = 1000000L;
static bool stop_was = false, halt_was = false;
static long direction = 1;
static long typed = 0; /* digits of a speed line so far */
static bool digits, junk; /* the line has a digit; it has something else */

static bool closed(uint8_t pin)
{
    return digitalRead(pin) == LOW;
}

static void set_off()
{
    unsigned long t0, took;
    motion_status_t st;
    {
        /* the call's own time: the planner interrupt, which plans the move right after it (a few
         * milliseconds after a new speed, preempting loop()), is held off until the lock goes (without
         * the lock, where it came 8 us after the call was a matter of the code's layout: 20 us in one
         * build, 3,650 us in the next) */
        PlannerLock measuring;
        t0 = micros();
        st = x.moveTo(direction * FAR);
        took = micros() - t0;
    }
    Serial.print(F("MOVE towards "));
    Serial.print(direction * FAR);
    Serial.print(F(" (moveTo() returned in "));
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
    pinMode(STOP_PIN, INPUT_PULLUP);
    pinMode(HALT_PIN, INPUT_PULLUP);
    x.setMaxSpeed(20000);
    x.setAcceleration(50000);
    x.begin();
    Serial.println(F("READY StopOnSwitch"));
    set_off();
}

void loop()
{
    long at;
    bool s = closed(STOP_PIN), h = closed(HALT_PIN);
    if (s && !stop_was && x.isRunning()) {
        unsigned long t0, took;
        {
            /* the call's own time: the planner interrupt, which plans the deceleration right after
             * it (a millisecond or two, preempting loop()), is held off until the lock goes */
            PlannerLock measuring;
            t0 = micros();
            x.stop(); /* returns at once: the planner interrupt plans the deceleration */
            took = micros() - t0;
        }
        Serial.print(F("STOP switch at "));
        Serial.print(x.currentPosition());
        Serial.print(F(" (stop() returned in "));
        Serial.print(took);
        Serial.println(F(" us)"));
    }
    if (h && !halt_was && x.isRunning()) {
        unsigned long t0, took;
        {
            PlannerLock measuring; /* as for stop() */
            t0 = micros();
            x.forceStop();
            took = micros() - t0;
        }
        Serial.print(F("HALT switch at "));
        Serial.print(x.currentPosition());
        Serial.print(F(" (forceStop() returned in "));
        Serial.print(took);
        Serial.println(F(" us)"));
    }
    stop_was = s;
    halt_was = h;
    while (Serial.available()) {
        int ch = Serial.read();
        if (ch >= '0' && ch <= '9') {
            if (typed < 10000000L) /* beyond any speed: kept there, refused below */
                typed = typed * 10 + (ch - '0');
            digits = true;
        } else if (ch != '\n' && ch != '\r') {
            junk = true; /* not a number: the whole line is refused */
        } else if (ch == '\n') {
            motion_status_t st = junk || !digits ? MS_ERR_NOT_A_NUMBER : x.setMaxSpeed((float)typed);
            if (st == MS_OK) {
                Serial.print(F("SPEED "));
                Serial.println(typed);
            } else {
                Serial.print(F("ERR "));
                Serial.println(Stepper::statusText(st));
            }
            typed = 0;
            digits = junk = false;
        }
    }
    if (x.takeDone(at)) {
        Serial.print(F("DONE "));
        Serial.print(at);
        Serial.print(F(" underruns="));
        Serial.println(x.underruns());
        delay(200);
        direction = -direction;
        set_off();
    }
}
