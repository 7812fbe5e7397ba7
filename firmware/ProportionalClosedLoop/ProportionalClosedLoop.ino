// motion-sketch: servo
/* ProportionalClosedLoop - position control of a DC gearmotor with a proportional controller
 * (the lab handout, section 4.1). Every 20 ms controlLoop() reads the motor's position from the
 * LS7366R encoder counter and sets the PWM duty to
 *     percentDutyCycle = Kp x (positionSetPoint - measuredPosition),  clamped to -100..+100 %
 * and every 1000 ms printLoop() prints one status line. A number sent over the serial port is
 * the new setpoint (a step, as in the handout); "move <counts>" makes the setpoint travel there
 * along the filter-shaped move instead (smooth_move.h, docs/servo.md); "kp <value>" retunes Kp;
 * "?" prints the state (9600 baud, line endings CR, LF or both; the protocol is in
 * MotionBoard/ServoSerial.h, docs/serial.md).
 *
 * Board: Arduino Mega 2560 + Arduino Motor Shield R3 (channel A) + LS7366R on SPI; the pins are
 * below, under "the pins". The files behind this sketch (with it, five to read end to end):
 *   LS7366R.h     encoder.read(): the 32-bit count over SPI
 *   HBridge.h     motor.setDuty(%): 8-bit PWM on D3 and the direction pin D12
 *   pctrl.h       pctrl_kp_duty_pct(): the P law above (lib/, the code `motionsim servo` runs)
 *   ServoSerial.h reads and answers the command lines; output never makes the loops wait; it
 *                 brings in smooth_move.h, the shaped setpoint of `move` (smooth_setpoint_*)
 */
#include <HBridge.h>
#include <LS7366R.h>
#include <ServoSerial.h>
#include <pctrl.h>

// ---- the controller ----
float Kp = 0.02;            // % duty per count of error (the lab's value)
long positionSetPoint = 0;  // counts
long measuredPosition = 0;  // counts
float percentDutyCycle = 0; // -100..+100 %

// ---- "move <counts>": the setpoint follows the filter-shaped move of smooth_move.h (a velocity
//      command of moveVmax through two moving averages, tau1 = vmax/accel, tau2 = accel/jerk) ----
const float moveVmax = 3000;   // counts/s
const float moveAccel = 20000; // counts/s^2: tau1 = 0.15 s
const float moveJerk = 400000; // counts/s^3: tau2 = 0.05 s
smooth_setpoint_t shapedMove;

// ---- timing: two loops, each advanced by exactly one period so neither drifts ----
const unsigned long controlInterval = 20; // ms
const unsigned long printInterval = 1000; // ms
unsigned long lastControlTime;
unsigned long lastPrintTime;

// ---- the pins: Arduino Mega 2560 + Arduino Motor Shield R3 (L298P, channel A) + LS7366R ----
//   LS7366R quadrature counter on the hardware SPI bus: MISO D50, MOSI D51, SCK D52, and its
//     /SS (chip select) on D53, the Mega's SS pin (an output anyway for an SPI master)
//   Motor Shield R3 channel A: PWM (EN A) D3 (Timer3, 490 Hz), DIR A D12 (high = positive duty),
//     BRAKE A D9 (held low: brake off); its current sense A0 is not used
// Wire the encoder so that positive duty makes the count increase; if it runs the other way,
// swap the encoder's A and B lines (or the motor leads). The emulator reads these four lines.
const uint8_t SERVO_PIN_ENCODER_CS = 53;
const uint8_t SERVO_PIN_PWM = 3;
const uint8_t SERVO_PIN_DIR = 12;
const uint8_t SERVO_PIN_BRAKE = 9;

// ---- the board ----
LS7366R encoder(SERVO_PIN_ENCODER_CS);
HBridge motor(SERVO_PIN_PWM, SERVO_PIN_DIR, SERVO_PIN_BRAKE);
ServoSerial servoSerial(Serial, ServoSerial::KP_ONLY);

// Every 20 ms: sample the encoder, compute the duty, drive the motor (in that order).
void controlLoop()
{
    measuredPosition = encoder.read();
    if (smooth_setpoint_moving(&shapedMove))
        positionSetPoint = smooth_setpoint_at(&shapedMove, lastControlTime);
    percentDutyCycle = pctrl_kp_duty_pct(Kp, positionSetPoint, measuredPosition);
    motor.setDuty(percentDutyCycle);
}

// Every 1000 ms: "t_ms=<scheduled time> setpoint=<n> position=<n> error=<n> duty=<%>".
void printLoop()
{
    servoSerial.printStatus(lastPrintTime, positionSetPoint, measuredPosition, percentDutyCycle);
}

// On every pass: one command line, already checked (and answered "OK ...") by servoSerial.
void serialCommands()
{
    ServoCommand command;
    if (!servoSerial.readCommand(command))
        return;
    switch (command.what) {
    case ServoCommand::SETPOINT:
        positionSetPoint = command.setpoint;
        smooth_setpoint_jump(&shapedMove, command.setpoint);
        break;
    case ServoCommand::MOVE: // from the setpoint in force, starting this control period
        smooth_setpoint_move(&shapedMove, lastControlTime, command.setpoint);
        break;
    case ServoCommand::KP:
        Kp = command.gain;
        break;
    case ServoCommand::QUERY:
        servoSerial.replyState(positionSetPoint, measuredPosition, percentDutyCycle, Kp);
        break;
    default: // KI, KD: refused by a KP_ONLY servoSerial
        break;
    }
}

void setup()
{
    Serial.begin(9600);
    motor.begin();
    if (!encoder.begin())
        servoSerial.out().println(F("WARN encoder: the LS7366R does not answer on SPI (CS D53)"));
    measuredPosition = encoder.read();
    lastControlTime = lastPrintTime = millis();
    { // after the loops' clocks start: its set-up takes a few ms on the AVR
        smooth_params_t shape = {moveVmax, moveAccel, moveJerk, 1000000UL}; // microsecond ticks
        smooth_setpoint_init(&shapedMove, &shape, positionSetPoint);
    }
    servoSerial.out().println(F("READY ProportionalClosedLoop"));
}

void loop()
{
    unsigned long now = millis();
    if (now - lastControlTime >= controlInterval) {
        lastControlTime += controlInterval;
        controlLoop();
    }
    if (now - lastPrintTime >= printInterval) {
        lastPrintTime += printInterval;
        printLoop();
    }
    serialCommands();
}
