/* MotionStepper.h - the MotionStepper library: exact constant-acceleration steppers on a RAMPS 1.4
 * (Arduino Mega 2560) for your own sketch, with loop() free.
 *
 *   #include <MotionStepper.h>
 *   Stepper x(Stepper::X);              one RAMPS axis (X, Y, Z): Stepper.h
 *   StepperGroup xy(x, y);              straight-line moves of 2-3 of them: StepperGroup.h
 * and, for a sketch driven from the Serial Monitor as the stepper sketches are (#include
 * <MotionConsole.h>, which brings Stepper.h; with a StepperGroup, after this header):
 * MotionConsole console(x), the sketches' protocol carried out through x's calls (the one-axis
 * stepper sketches include MotionConsole.h alone; it plans from loop(), below).
 *
 * Timer1 (compare A/B/C) makes the steps (MotionBoard's MultiStepEngine), Timer3 plans them in the
 * background (BackgroundPlanner.h); both are taken (with BackgroundPlanner::planInLoop(), as a
 * MotionConsole makes it, the planning runs from loop() and Timer3 stays free). docs/library.md
 * explains it all, with a table
 * of AccelStepper's and FastAccelStepper's calls and ours.
 */
#ifndef MOTION_STEPPER_H
#define MOTION_STEPPER_H

/* arduino-cli links the libraries in the order in which the sketch's #includes first name them, and
 * MotionBoard (an archive: a sketch links only the parts it uses) must come after this library: with
 * one of its headers included first, the step engine's parts stay unlinked ("undefined reference to
 * `step_cut_plan'" and the like). Hence, in a sketch: this header (or the other of MotionStepper.h and
 * MotionConsole.h) before any of MotionBoard's. */
#if !defined(MOTION_STEPPER_INCLUDED_FIRST) &&                                                                  \
    (defined(BOARD_HEAP_H) || defined(MOTION_SERIAL_H) || defined(MULTI_AXIS_PINS_H) || defined(MULTI_STEP_ENGINE_H) || \
     defined(MOTIONBOARD_PRINT_REAL_H) || defined(SERIAL_OUT_QUEUE_H) || defined(SERIAL_RX_H) || defined(STEP_CUT_H) || \
     defined(STEPPER_PINS_H) || defined(FILTER_PINS_H) || defined(HBRIDGE_H) || defined(LS7366R_H) ||                \
     defined(SERVO_SERIAL_H))
#error "#include <MotionStepper.h> or <MotionConsole.h> before MotionBoard's headers (MotionSerial.h, StepperPins.h, ...): arduino-cli links the libraries in the order the sketch's #includes name them"
#endif
#define MOTION_STEPPER_INCLUDED_FIRST

#include "BackgroundPlanner.h"
#include "Stepper.h"
#include "StepperGroup.h"

#endif
