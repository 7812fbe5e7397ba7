/* ApiTour - most Stepper calls once, with what they answer: the refusals (their statuses print as the
 * sketches' serial ERR sentences), the limits, direction inversion, auto-disable, a direction hook,
 * a new target while moving, setCurrentPosition and move, DIR and ENABLE on other pins, homing with
 * forceStop() and setCurrentPosition(0), AccelStepper's distanceToGo() == 0. The RAMPS X
 * axis; Serial Monitor at 9600. The hook writes D32 (a free pin): with a hook, the engine leaves DIR
 * (D55) alone.
 */
#include <MotionStepper.h>
#include <limits.h> /* LONG_MIN */

Stepper x(Stepper::X);
Stepper x2(Stepper::X); /* a second Stepper for the same axis: its begin() is refused */
/* made with a ramp: the lab's Leib ramp at the library's default vmax (above that ramp's limit), the
 * sigmoid without its table (no setRamp), and the smooth ramp, which this constructor does not take:
 * their begin()s are refused */
Stepper x3(Stepper::X, RAMP_ALGO_LEIB, 0);
Stepper x4(Stepper::X, RAMP_ALGO_SIGMOID, 0);
Stepper x5(Stepper::X, RAMP_ALGO_SMOOTH, 0);
static const uint8_t HOOK_PIN = 32;

static void say(const __FlashStringHelper *call, motion_status_t st)
{
    Serial.print(call);
    Serial.print(F(": "));
    if (st == MS_OK) {
        Serial.println(F("OK"));
    } else {
        Serial.print(F("ERR "));
        Serial.println(Stepper::statusText(st));
    }
}

static void my_direction(bool forward)
{
    digitalWrite(HOOK_PIN, forward ? HIGH : LOW);
}

static void wait_done()
{
    long at;
    while (!x.takeDone(at)) {
    }
    Serial.print(F("DONE "));
    Serial.print(at);
    Serial.print(F(" position="));
    Serial.print(x.currentPosition());
    Serial.print(F(" underruns="));
    Serial.println(x.underruns());
    Serial.flush(); /* the line sent before the next move's first step (the check splits the moves there) */
}

void setup()
{
    Serial.begin(9600);
    pinMode(HOOK_PIN, OUTPUT);
    Serial.println(F("READY ApiTour"));
    say(F("moveTo(100) before begin()"), x.moveTo(100));
    say(F("move(100) before begin()"), x.move(100));
    say(F("stop() before begin()"), x.stop());
    say(F("forceStop() before begin()"), x.forceStop());
    say(F("setCurrentPosition(5) before begin()"), x.setCurrentPosition(5));
    say(F("setMaxSpeed(30000)"), x.setMaxSpeed(30000));
    say(F("setMaxSpeed(NAN)"), x.setMaxSpeed(NAN));
    say(F("setMaxSpeed(0.0001)"), x.setMaxSpeed(0.0001)); /* one step per 2.8 hours */
    say(F("setAcceleration(2000000)"), x.setAcceleration(2000000));
    say(F("setAcceleration(4)"), x.setAcceleration(4));
    say(F("setAcceleration(9.3)"), x.setAcceleration(9.3)); /* 10,000 steps/s would take 2^34 ticks and more */
    say(F("setMinSpeed(20000)"), x.setMinSpeed(20000));
    say(F("setMinSpeed(5000)"), x.setMinSpeed(5000));
    say(F("setMaxSpeed(4000)"), x.setMaxSpeed(4000));
    say(F("setMinSpeed(0)"), x.setMinSpeed(0));
    say(F("setMaxSpeed(8000)"), x.setMaxSpeed(8000));
    say(F("setAcceleration(40000)"), x.setAcceleration(40000));
    say(F("begin()"), x.begin());
    say(F("begin() of a second X"), x2.begin());
    say(F("begin() of a Leib Stepper at vmax 10000"), x3.begin());
    say(F("begin() of a Stepper made with the sigmoid"), x4.begin());
    say(F("begin() of a Stepper made with the smooth ramp"), x5.begin());

    /* inverted, auto-disable: counting down is DIR high, ENABLE only while moving */
    say(F("setDirectionInverted(true)"), x.setDirectionInverted(true));
    x.setAutoDisable(true);
    say(F("moveTo(-2000)"), x.moveTo(-2000));
    delay(100);
    say(F("setCurrentPosition(5) while moving"), x.setCurrentPosition(5));
    say(F("setDirectionInverted(false) while moving"), x.setDirectionInverted(false));
    Serial.print(F("speed "));
    Serial.print(x.speed(), 0);
    Serial.print(F(" target "));
    Serial.println(x.targetPosition());
    wait_done();

    /* a hook drives the direction; a new target behind turns the move */
    say(F("setDirectionInverted(false)"), x.setDirectionInverted(false));
    say(F("setDirectionHook"), x.setDirectionHook(my_direction));
    say(F("moveTo(-3000)"), x.moveTo(-3000));
    delay(100);
    say(F("moveTo(0) while moving"), x.moveTo(0));
    wait_done();
    say(F("setDirectionHook(NULL)"), x.setDirectionHook(NULL));

    say(F("setCurrentPosition(100)"), x.setCurrentPosition(100));
    Serial.print(F("position "));
    Serial.println(x.currentPosition());
    say(F("move(-300)"), x.move(-300));
    Serial.print(F("target "));
    Serial.print(x.targetPosition());
    Serial.print(F(" distanceToGo "));
    Serial.println(x.distanceToGo());
    wait_done();

    /* a driver wired elsewhere: DIR on D34, ENABLE on D36 (auto-disable still on) */
    say(F("setDirectionPin(200)"), x.setDirectionPin(200));
    say(F("setEnablePin(200)"), x.setEnablePin(200));
    say(F("setDirectionPin(34)"), x.setDirectionPin(34));
    say(F("setEnablePin(36)"), x.setEnablePin(36));
    say(F("move(500)"), x.move(500));
    say(F("setDirectionPin(55) while moving"), x.setDirectionPin(55));
    wait_done();
    say(F("stop() at rest"), x.stop());
    say(F("forceStop() at rest"), x.forceStop());

    /* homing: forceStop() at a switch, and that point becomes 0 at once (setCurrentPosition() takes
     * the halt itself: no wait for isRunning()); then AccelStepper's end test, distanceToGo() == 0
     * from the move's last step on. Each pair of calls runs before its statuses print (at 9600 baud a
     * print can wait for the serial line longer than the planner takes to see the end) */
    say(F("move(1000) to home"), x.move(1000));
    delay(30);
    motion_status_t halt = x.forceStop();
    motion_status_t zero = x.setCurrentPosition(0);
    say(F("forceStop() homing"), halt);
    say(F("setCurrentPosition(0) right after forceStop()"), zero);
    wait_done(); /* the halt: where it stopped, before the new zero */
    say(F("move(200)"), x.move(200));
    while (x.distanceToGo() != 0) {
    }
    zero = x.setCurrentPosition(0);
    say(F("setCurrentPosition(0) at distanceToGo() 0"), zero);
    wait_done();

    /* near the ends of a long's range: targets the axis cannot be sent to are refused, nothing moves */
    say(F("setCurrentPosition(2147483000)"), x.setCurrentPosition(2147483000L));
    say(F("move(2000) beyond LONG_MAX"), x.move(2000));
    say(F("moveTo(-2147483000), more than 2^31 - 1 steps away"), x.moveTo(-2147483000L));
    say(F("setDirectionInverted(true) there"), x.setDirectionInverted(true));
    say(F("setCurrentPosition(LONG_MIN) inverted"), x.setCurrentPosition(LONG_MIN));
    say(F("setDirectionInverted(false) there"), x.setDirectionInverted(false));
    Serial.print(F("at the end: position "));
    Serial.print(x.currentPosition());
    Serial.print(F(" target "));
    Serial.println(x.targetPosition());
    Serial.println(F("FINISHED"));
}

void loop()
{
}
