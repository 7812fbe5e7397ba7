/* IncludedFirst.h - the check that MotionStepper.h and MotionConsole.h make before anything else.
 *
 * arduino-cli links the libraries in the order in which the sketch's #includes first name them, and
 * MotionBoard (an archive: a sketch links only the parts it uses) must come after this library: with
 * one of its headers included first, the step engine's parts stay unlinked ("undefined reference to
 * `step_cut_plan'" and the like). Hence, in a sketch: MotionStepper.h or MotionConsole.h before any
 * of MotionBoard's headers (test/cli/test_include_order.py). No include guard: each of the two
 * headers includes it first, and the second finds MOTION_STEPPER_INCLUDED_FIRST set. */
#if !defined(MOTION_STEPPER_INCLUDED_FIRST) &&                                                                  \
    (defined(BOARD_HEAP_H) || defined(MOTION_SERIAL_H) || defined(MULTI_AXIS_PINS_H) || defined(MULTI_STEP_ENGINE_H) || \
     defined(MOTIONBOARD_PRINT_REAL_H) || defined(SERIAL_OUT_QUEUE_H) || defined(SERIAL_RX_H) || defined(STEP_CUT_H) || \
     defined(STEPPER_PINS_H) || defined(FILTER_PINS_H) || defined(HBRIDGE_H) || defined(LS7366R_H) ||                \
     defined(SERVO_SERIAL_H))
#error "#include <MotionStepper.h> or <MotionConsole.h> before MotionBoard's headers (MotionSerial.h, StepperPins.h, ...): arduino-cli links the libraries in the order the sketch's #includes name them"
#endif
#define MOTION_STEPPER_INCLUDED_FIRST
