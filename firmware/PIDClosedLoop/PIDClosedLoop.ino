// motion-sketch: servo
/* PIDClosedLoop - closed-loop position control of a DC gearmotor with a PID controller that
 * behaves exactly like the Arduino PID library PID_v1 1.2.1 (seed 003 section 4.2): Input is the
 * measured position (LS7366R counts), Output the PWM duty in %, Setpoint the position setpoint;
 * SetOutputLimits(-100, 100), SetSampleTime(20), SetMode(AUTOMATIC), Ki = Kd = 0 by default.
 *
 * Board: Arduino Mega 2560 + Arduino Motor Shield R3 (channel A) + LS7366R on SPI; pins in
 * MotionBoard/ServoPins.h. Serial 9600 baud, protocol in MotionBoard/ServoConsole.h:
 *   <counts> | kp|ki|kd <value> | ?    replies OK ... / ERR ...; "READY PIDClosedLoop" at boot;
 *   every second: t_ms=<ms> setpoint=<n> position=<n> error=<n> duty=<%>
 *
 * The controller: by default MotionPID (lib/src/MotionPID.h), our PID_v1-identical class, so the
 * sketch builds without the Arduino library manager. With the real library installed, one
 * switch builds this sketch against it instead:
 *     FIRMWARE_DEFINES="-DUSE_REAL_PID_V1=1" make firmware        (or #define USE_REAL_PID_V1 1)
 *
 * Timing, and why every 20 ms period computes. PID_v1's Compute() only acts when
 * millis() - lastTime >= SampleTime, and then sets lastTime = millis(). Arduino's millis() steps
 * by 1.024 ms and skips one value about every 42 ms, so a 20 ms loop scheduled on millis() is
 * sometimes entered 1 ms late (millis() jumped past the deadline); the next period, on time,
 * then sees only 19 ms since lastTime and Compute() refuses it: a whole period without control.
 *  - MotionPID build: the control loop is scheduled without drift (last += 20 on millis()), and
 *    the PID reads its time from the scheduled start of the period (SetClock(controlClock))
 *    instead of raw millis(). Consecutive periods are then exactly 20 ms apart on the PID's
 *    clock, so Compute() acts in every period; its semantics (gating, lastTime = now, gains
 *    scaled by the nominal 20 ms) are untouched - only the clock it reads is exact.
 *  - Real PID_v1 build (its clock is millis() and cannot be changed): the sketch lets PID_v1
 *    keep its own schedule, as the library's examples do: whenever millis() - lastCompute >= 20
 *    it samples the encoder and calls Compute(), and repeats that on the following passes of
 *    loop() until Compute() accepts. No period is lost; PID_v1's periods are 20 or 21 ms and
 *    drift against the wall clock by about 1 ms in 42 periods (PID_v1's known behaviour).
 * The print loop is scheduled like the control loop (last += 1000) in both builds.
 *
 * Serial output never makes the control loop wait (MotionBoard/ServoConsole.h, SerialOutQueue.h):
 * every line goes into a 256-byte queue that console.poll() feeds to Serial only as fast as its
 * transmit buffer takes it; a command is read only when its longest reply fits in the queue
 * (otherwise it waits unread: back-pressure), and the status line is deferred until it fits (no
 * command is read meanwhile). At 9600 baud a blocking Serial.print() used to stretch control
 * periods to 67 ms when a reply met the status line; now they stay within the millis() jitter
 * (19.4-20.5 ms) while commands are answered.
 *
 * The same code and number format run in `motionsim servo --ctrl pid` (float, as here).
 */
#include <HBridge.h>
#include <LS7366R.h>
#include <ServoConsole.h>
#include <ServoPins.h>

#if USE_REAL_PID_V1
#include <PID_v1.h>
typedef PID ServoPID;
#else
#include <MotionPID.h>
typedef MotionPID ServoPID;
#endif

const int controlInterval = 20;       /* ms: the PID sample time and the control period */
const uint32_t printInterval = 1000;  /* ms */
const double minPercent = -100;
const double maxPercent = 100;

double Kp = 0.02, Ki = 0, Kd = 0;
double Input;    /* measured position, counts */
double Output;   /* PWM duty, % */
double Setpoint; /* position setpoint, counts */
ServoPID myPID(&Input, &Output, &Setpoint, Kp, Ki, Kd, DIRECT);

LS7366R encoder(SERVO_PIN_ENCODER_CS);
HBridge motor(SERVO_PIN_PWM, SERVO_PIN_DIR, SERVO_PIN_BRAKE);
ServoConsole console(Serial, ServoConsole::PID_GAINS); /* every line goes out through its queue: never blocks */

ServoState servo; /* what the console shows and changes */
uint32_t lastControlMs;
uint32_t lastPrintMs;

#if !USE_REAL_PID_V1
/* The PID's clock: the scheduled start of the current control period. */
uint32_t controlClock()
{
    return lastControlMs;
}
#endif

/* Sample, compute, drive: one control period. Returns false if PID_v1 declined to compute. */
bool controlLoop()
{
    servo.position_counts = encoder.read();
    Input = servo.position_counts;
    if (!myPID.Compute())
        return false;
    servo.duty_pct = (float)Output;
    motor.setDuty(servo.duty_pct);
    return true;
}

void printLoop()
{
    console.queueStatus(lastPrintMs, servo);
}

void setup()
{
    Serial.begin(9600);
    motor.begin();
    if (!encoder.begin())
        console.out().println(F("WARN encoder: the LS7366R does not answer on SPI (CS D53)"));
    Setpoint = 0;
    Input = encoder.read();
    Output = 0;
    servo.setpoint_counts = 0;
    servo.position_counts = (int32_t)Input;
    servo.duty_pct = 0;
    servo.kp = (float)Kp;
    servo.ki = (float)Ki;
    servo.kd = (float)Kd;
    lastControlMs = lastPrintMs = millis();
#if !USE_REAL_PID_V1
    myPID.SetClock(controlClock);
#endif
    myPID.SetOutputLimits(minPercent, maxPercent);
    myPID.SetSampleTime(controlInterval);
    myPID.SetMode(AUTOMATIC);
    console.ready(F("PIDClosedLoop"));
}

void loop()
{
    uint32_t now = millis();
#if USE_REAL_PID_V1
    if (now - lastControlMs >= (uint32_t)controlInterval && controlLoop())
        lastControlMs = now; /* never later than PID_v1's own lastTime */
#else
    if (now - lastControlMs >= (uint32_t)controlInterval) {
        lastControlMs += controlInterval;
        controlLoop();
    }
#endif
    if (now - lastPrintMs >= printInterval) {
        lastPrintMs += printInterval;
        printLoop();
    }
    switch (console.poll(servo)) {
    case ServoConsole::SETPOINT_CHANGED:
        Setpoint = servo.setpoint_counts;
        break;
    case ServoConsole::GAINS_CHANGED:
        Kp = servo.kp;
        Ki = servo.ki;
        Kd = servo.kd;
        myPID.SetTunings(Kp, Ki, Kd); /* values already checked: never negative */
        break;
    default:
        break;
    }
}
