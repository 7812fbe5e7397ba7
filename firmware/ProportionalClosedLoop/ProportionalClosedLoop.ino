// motion-sketch: servo
/* ProportionalClosedLoop - closed-loop position control of a DC gearmotor with a proportional
 * controller (seed 003 section 4.1): every 20 ms the encoder position is read from the LS7366R
 * and the PWM duty is set to
 *     percentDutyCycle = Kp x (positionSetPoint - measuredPosition),  clamped to -100..+100 %
 * with Kp = 0.02 % per count by default. A number sent over the serial port sets the setpoint.
 *
 * Board: Arduino Mega 2560 + Arduino Motor Shield R3 (channel A) + LS7366R on SPI; pins in
 * MotionBoard/ServoPins.h. Serial 9600 baud, protocol in MotionBoard/ServoConsole.h:
 *   <counts> | kp <value> | ?      replies OK ... / ERR ...; "READY ProportionalClosedLoop" at boot;
 *   every second: t_ms=<ms> setpoint=<n> position=<n> error=<n> duty=<%>
 *
 * Timing: two loops scheduled "blink without delay" style on millis(), each by advancing its own
 * deadline by exactly one period (last += period), so neither drifts: the control loop every
 * 20 ms (sample the encoder, compute, write the PWM, in that order), the print loop every 1000 ms.
 *
 * Serial output never makes the control loop wait (MotionBoard/ServoConsole.h, SerialOutQueue.h):
 * every line goes into a 256-byte queue that console.poll() feeds to Serial only as fast as its
 * transmit buffer takes it; a command is read only when its longest reply fits in the queue
 * (otherwise it waits unread: back-pressure), and the status line is deferred until it fits (no
 * command is read meanwhile). At 9600 baud a blocking Serial.print() used to stretch control
 * periods to 67 ms when a reply met the status line; now they stay within the millis() jitter
 * (19.4-20.5 ms) while commands are answered.
 *
 * The same controller code (lib/src/pctrl.c, float) and PWM quantisation (lib/src/duty_pwm.c) run
 * in `motionsim servo --ctrl p`.
 */
#include <HBridge.h>
#include <LS7366R.h>
#include <ServoConsole.h>
#include <ServoPins.h>
#include <pctrl.h>

const uint32_t controlInterval = 20;  /* ms */
const uint32_t printInterval = 1000;  /* ms */
const float Kp = 0.02f;               /* % duty per count (the lab's value) */

LS7366R encoder(SERVO_PIN_ENCODER_CS);
HBridge motor(SERVO_PIN_PWM, SERVO_PIN_DIR, SERVO_PIN_BRAKE);
ServoConsole console(Serial, ServoConsole::P_ONLY); /* every line goes out through its queue: never blocks */

ServoState servo; /* setpoint, measured position, duty, gains */
pctrl_t controller;
uint32_t lastControlMs;
uint32_t lastPrintMs;

void controlLoop()
{
    servo.position_counts = encoder.read();
    servo.duty_pct = pctrl_duty_pct(&controller, servo.setpoint_counts, servo.position_counts);
    motor.setDuty(servo.duty_pct);
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
    servo.setpoint_counts = 0;
    servo.position_counts = encoder.read();
    servo.duty_pct = 0;
    servo.kp = Kp;
    servo.ki = servo.kd = 0;
    pctrl_init(&controller, Kp);
    lastControlMs = lastPrintMs = millis();
    console.ready(F("ProportionalClosedLoop"));
}

void loop()
{
    uint32_t now = millis();
    if (now - lastControlMs >= controlInterval) {
        lastControlMs += controlInterval;
        controlLoop();
    }
    if (now - lastPrintMs >= printInterval) {
        lastPrintMs += printInterval;
        printLoop();
    }
    if (console.poll(servo) == ServoConsole::GAINS_CHANGED)
        pctrl_set_kp(&controller, servo.kp); /* the console has already checked it */
}
