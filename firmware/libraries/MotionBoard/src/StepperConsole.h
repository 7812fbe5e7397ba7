/* StepperConsole.h - the serial protocol shared by the three stepper sketches (9600 baud, lines
 * ending in CR, LF or CRLF, through MotionSerial):
 *
 *   <integer>            absolute target (any int32): "OK <from> <to>", later "DONE <position>"
 *                        when the move has ended (at once for a target equal to the position)
 *   ?                    one line: pos= target= state=idle|accel|cruise|decel algo= v0= vmax= accel=
 *                        tick_hz= max_sps= [sigmoid: flex= len= hold= accel_steps= accel_time_s=
 *                        cruise_sps=] mode=timer|loop
 *   set <key> <value>    between moves: "OK <key>=<value>" (keys: v0 vmax accel; SCurveStepper:
 *                        v0 = fmin, vmax = fmax, flex, len, hold; accel is derived there)
 *   READY <SketchName>   printed once at the end of setup
 * Anything else, or a target or `set` while moving, gets "ERR <reason>" and changes nothing; a
 * `set` value above this sketch's limit says which ("ERR number out of range: vmax at most 5000
 * steps/s on this sketch", StepperRamp::print_limit).
 * Position and state are read from the interrupt's variables atomically (StepperDriver).
 */
#ifndef STEPPER_CONSOLE_H
#define STEPPER_CONSOLE_H

#include <Arduino.h>

#include "MotionSerial.h"
#include "StepperDriver.h"
#include "StepperRamps.h"

class StepperConsole {
public:
    explicit StepperConsole(StepperRamp &ramp) : ramp_(ramp), serial_(Serial), target_(0) {}

    /* Serial at 9600 baud, the driver's pins and timer; prints "READY <name>". */
    void begin(const __FlashStringHelper *sketch_name);

    /* Call on every pass of loop(): steps (timed-loop mode), DONE reports, command lines. */
    void poll();

private:
    void handle(const char *line);
    void handle_target(const char *word);
    void handle_set(const char *cursor);
    void reply_status();

    StepperRamp &ramp_;
    MotionSerial serial_;
    int32_t target_;
};

#endif
