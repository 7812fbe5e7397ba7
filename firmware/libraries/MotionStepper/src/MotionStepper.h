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

#include "IncludedFirst.h" /* first: MotionBoard's headers must come after (it says why) */

#include "BackgroundPlanner.h"
#include "Stepper.h"
#include "StepperGroup.h"

/* Links Timer3's planner interrupt (BackgroundPlannerTimer.cpp, a member of this library's archive)
 * into the sketch: the Steppers plan in the background (a sketch that includes only MotionConsole.h
 * plans in loop() and links none of it; Stepper::begin() without it: MS_ERR_NO_PLANNER_TIMER). */
bool planner_timer_start();
static bool (*const motion_stepper_links_planner_timer)() __attribute__((used)) = planner_timer_start;

#endif
