// motion-sketch: servo
/* PIDClosedLoop - position control of a DC gearmotor with the Arduino PID library's controller
 * (the lab handout, section 4.2): Input is the measured position (LS7366R counts), Output the
 * PWM duty in %, Setpoint the position setpoint. Every 20 ms controlLoop() reads the encoder,
 * calls myPID.Compute() and drives the motor with Output; every 1000 ms printLoop() prints one
 * status line. A number sent over the serial port is the new Setpoint (a step, as in the handout);
 * "move <counts>" makes Setpoint travel there along the filter-shaped move instead (smooth_move.h,
 * docs/servo.md); "kp|ki|kd <value>" retunes the PID; "?" prints the state (9600 baud; the
 * protocol is in MotionBoard/ServoSerial.h).
 *
 * Board: Arduino Mega 2560 + Arduino Motor Shield R3 (channel A) + LS7366R on SPI; the pins are
 * below, under "the pins". The files behind this sketch (with it, five to read end to end):
 *   LS7366R.h     encoder.read(): the 32-bit count over SPI
 *   HBridge.h     motor.setDuty(%): 8-bit PWM on D3 and the direction pin D12
 *   MotionPID.h   the PID: PID_v1 1.2.1's class and behaviour, bit for bit (lib/, docs/pid_v1.md;
 *                 the code `motionsim servo --ctrl pid` runs)
 *   ServoSerial.h reads and answers the command lines; output never makes the loops wait; it
 *                 brings in smooth_move.h, the shaped setpoint of `move` (smooth_setpoint_*)
 * With the real PID library installed, FIRMWARE_DEFINES="-DUSE_REAL_PID_V1=1" builds this sketch
 * against PID_v1.h instead (docs/servo.md).
 *
 * Why the PID reads the period's scheduled start as its clock: Compute() only computes when
 * millis() - lastTime >= SampleTime. millis() steps by 1.024 ms and skips a value about every
 * 42 ms, so a loop entered 1 ms late is followed by one only 19 ms after it, which Compute()
 * would refuse: a period without control. With SetClock(controlClock) (a MotionPID extension)
 * the PID's clock advances by exactly 20 ms per period and every period computes. The real
 * PID_v1 reads millis() itself, so that build instead retries Compute() on the next passes of
 * loop() until it accepts (docs/servo.md, "Servo timing").
 */
#include <HBridge.h>
#include <LS7366R.h>
#include <ServoSerial.h>

#if USE_REAL_PID_V1
#include <PID_v1.h>
#else
#include <MotionPID.h>
typedef MotionPID PID; // PID_v1's class name for our PID_v1-identical controller
#endif

// ---- the controller ----
double Kp = 0.02, Ki = 0, Kd = 0;
double Setpoint = 0; // position setpoint, counts
double Input = 0;    // measured position, counts
double Output = 0;   // PWM duty, %
long measuredPosition = 0; // the count as read (Input is its double copy for the PID)
PID myPID(&Input, &Output, &Setpoint, Kp, Ki, Kd, DIRECT);

// ---- "move <counts>": Setpoint follows the filter-shaped move of smooth_move.h (a velocity
//      command of moveVmax through two moving averages, tau1 = vmax/accel, tau2 = accel/jerk) ----
const float moveVmax = 3000;   // counts/s
const float moveAccel = 20000; // counts/s^2: tau1 = 0.15 s
const float moveJerk = 400000; // counts/s^3: tau2 = 0.05 s
smooth_setpoint_t shapedMove;

// ---- timing: two loops, each advanced by exactly one period so neither drifts ----
const int controlInterval = 20;           // ms: the control period and the PID's sample time
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
ServoSerial servoSerial(Serial, ServoSerial::KP_KI_KD);

// The shaped move's clock: the scheduled start of this control period (the real PID_v1 build:
// millis(), as its Compute()).
unsigned long setpointClock()
{
#if USE_REAL_PID_V1
    return millis();
#else
    return lastControlTime;
#endif
}

// Every 20 ms: sample the encoder, compute, drive the motor. False if Compute() declined.
bool controlLoop()
{
    measuredPosition = encoder.read();
    Input = measuredPosition;
    if (smooth_setpoint_moving(&shapedMove))
        Setpoint = smooth_setpoint_at(&shapedMove, setpointClock());
    if (!myPID.Compute())
        return false;
    motor.setDuty(Output);
    return true;
}

// Every 1000 ms: "t_ms=<scheduled time> setpoint=<n> position=<n> error=<n> duty=<%>".
void printLoop()
{
    servoSerial.printStatus(lastPrintTime, (long)Setpoint, measuredPosition, Output);
}

// On every pass: one command line, already checked (and answered "OK ...") by servoSerial.
void serialCommands()
{
    ServoCommand command;
    if (!servoSerial.readCommand(command))
        return;
    switch (command.what) {
    case ServoCommand::SETPOINT:
        Setpoint = command.setpoint;
        smooth_setpoint_jump(&shapedMove, command.setpoint);
        break;
    case ServoCommand::MOVE: // from the Setpoint in force, starting this control period
        smooth_setpoint_move(&shapedMove, setpointClock(), command.setpoint);
        break;
    case ServoCommand::KP:
        Kp = command.gain;
        myPID.SetTunings(Kp, Ki, Kd);
        break;
    case ServoCommand::KI:
        Ki = command.gain;
        myPID.SetTunings(Kp, Ki, Kd);
        break;
    case ServoCommand::KD:
        Kd = command.gain;
        myPID.SetTunings(Kp, Ki, Kd);
        break;
    case ServoCommand::QUERY:
        servoSerial.replyState((long)Setpoint, measuredPosition, Output, Kp, Ki, Kd);
        break;
    }
}

#if !USE_REAL_PID_V1
// The PID's clock: the scheduled start of the current control period.
uint32_t controlClock()
{
    return lastControlTime;
}
#endif

void setup()
{
    Serial.begin(9600);
    motor.begin();
    if (!encoder.begin())
        servoSerial.out().println(F("WARN encoder: the LS7366R does not answer on SPI (CS D53)"));
    measuredPosition = encoder.read();
    Input = measuredPosition;
    lastControlTime = lastPrintTime = millis();
    { // after the loops' clocks start: its set-up takes a few ms on the AVR
        smooth_params_t shape = {moveVmax, moveAccel, moveJerk, 1000000UL}; // microsecond ticks
        smooth_setpoint_init(&shapedMove, &shape, (int32_t)Setpoint);
    }
#if !USE_REAL_PID_V1
    myPID.SetClock(controlClock);
#endif
    myPID.SetOutputLimits(-100, 100);
    myPID.SetSampleTime(controlInterval);
    myPID.SetMode(AUTOMATIC);
    servoSerial.out().println(F("READY PIDClosedLoop"));
}

void loop()
{
    unsigned long now = millis();
#if USE_REAL_PID_V1
    if (now - lastControlTime >= (unsigned long)controlInterval && controlLoop())
        lastControlTime = now; // never later than PID_v1's own lastTime
#else
    if (now - lastControlTime >= (unsigned long)controlInterval) {
        lastControlTime += controlInterval;
        controlLoop();
    }
#endif
    if (now - lastPrintTime >= printInterval) {
        lastPrintTime += printInterval;
        printLoop();
    }
    serialCommands();
}
