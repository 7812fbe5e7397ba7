/* StepperConsole.h - the one-axis stepper sketches' serial protocol on the step engine directly
 * (SCurveStepper: the RAMPS 1.4 X axis, axis 0 of the step engine, MultiStepEngine.h; the console
 * itself is StepConsole.h, shared with MultiAxisConsole). SimplisticRampStepper, LeibRampStepper and
 * ExactRampStepper speak the same protocol through the MotionStepper library's MotionConsole, on a
 * Stepper; SCurveStepper follows once the library has the sigmoid table. 9600 baud,
 * lines ending in CR, LF or CRLF, through MotionSerial; replies through a SerialOutQueue, so
 * printing never holds up the planner:
 *
 *   <integer>            absolute target (any int32): "OK <from> <to>", later "DONE <position>".
 *                        While moving, the move continues from its current speed to the new target
 *                        (no speed jump; a target behind, or closer than the stopping distance,
 *                        makes it decelerate, reverse and approach); "from" is where the new plan
 *                        starts; the replaced move gets no DONE, the new one does. If every
 *                        step of the move is already queued (it is about to end at rest), the
 *                        move keeps its DONE and the new one starts from its target after it:
 *                        "OK <old target> <to> (after DONE <old target>)", "DONE <old target>",
 *                        later "DONE <to>".
 *   stop                 decelerate at accel to rest: "OK stop", then "DONE <position>"
 *   !                    halt now, no further step: "OK halt", then "DONE <position>"
 *                        (either while idle: "OK stop (not moving)" / "OK halt (not moving)")
 *   ?                    one line: pos= target= state=idle|accel|cruise|decel algo= v0= vmax= accel=
 *                        tick_hz= max_sps= [sigmoid: flex= len= hold= accel_steps= accel_time_s=
 *                        cruise_sps=] underruns= late= mode=timer|loop
 *   set <key> <value>    "OK <key>=<value>" (keys: v0 vmax accel; SCurveStepper: v0 = fmin,
 *                        vmax = fmax, flex, len, hold; accel is derived there). While moving the
 *                        reply adds " (from the next plan)": the move in progress keeps its
 *                        parameters, the next target or stop uses the new ones (SCurveStepper: the
 *                        next move from rest, since its table is refilled then).
 *   READY <SketchName>   printed once at the end of setup
 * Anything else gets "ERR <reason>" and changes nothing. Every accepted move (an OK to a target)
 * ends in exactly one DONE unless a later target replaces it; the DONE of a move that ended just
 * before a new target is printed before that target's OK.
 */
#ifndef STEPPER_CONSOLE_H
#define STEPPER_CONSOLE_H

#include "StepConsole.h"

class StepperConsole : public StepConsole {
public:
    explicit StepperConsole(StepperRamp &ramp) : StepConsole(1, ramps_, &planner_, 0) { ramps_[0] = &ramp; }

    /* Serial at 9600 baud, the engine (X alone, at the ramp's tick rate), the planner; prints
     * "READY <name>". */
    void begin(const __FlashStringHelper *sketch_name)
    {
        MultiStepEngine::begin(ramps_[0]->tick_hz(), MULTI_AXIS_X);
        begin_console(sketch_name);
    }

private:
    StepperRamp *ramps_[1];
    step_planner_t planner_;
};

#endif
