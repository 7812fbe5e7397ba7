/* StepperDriver.h - steps one axis through a planned move (lib/src/ramp.h) from Timer1's compare
 * interrupt (or, with STEPPER_TIMED_LOOP = 1, from loop() on micros(), the lab's original way).
 *
 * The interrupt is "simple and dumb": at each step edge it raises STEP, arms the compare for the
 * next edge with the interval it computed one step earlier (so arming never waits for the float
 * maths), lowers STEP after the pulse, then asks the ramp for the interval after that (Leib: one
 * float multiply-add chain). Pins, tick rate and the early-arming/spin scheme: StepperPins.h.
 * Cost per step, measured in simavr (README "Stepper ramps: accuracy, timing and the firmware"):
 * 885 cycles cruising, 2,226 in a Leib acceleration step, including ~260 cycles of waiting for
 * the exact tick; this bounds the step rate each sketch accepts (StepperPins.h, max_sps).
 * Shared state is volatile and read with interrupts off (ATOMIC_BLOCK).
 */
#ifndef STEPPER_DRIVER_H
#define STEPPER_DRIVER_H

#include <stdint.h>

#include <ramp.h>

#include "StepperPins.h"

class StepperDriver {
public:
    /* Pins as outputs (STEP low, DIR high, ENABLE low = on, LED), Timer1 free-running at F. */
    static void begin();

    /* Starts the planned move from plan.from (which must be the current position: the driver
     * then owns the copy). DIR is set before the first step. Returns false (and does nothing) while
     * a move is running. A zero-length move finishes at once (take_done reports it). */
    static bool start(const ramp_t &plan);

    /* Timed-loop mode: makes the steps that are due; call it on every pass of loop().
     * With the timer it does nothing. */
    static void poll();

    static bool busy();
    static int32_t position();
    /* The phase of the step last made while moving; RAMP_IDLE when stopped. */
    static ramp_phase_t phase();
    /* True once after each move has ended, with the final position. */
    static bool take_done(int32_t &position);

    static uint32_t tick_hz() { return STEPPER_TICK_HZ; }

    /* The body of Timer1's compare-A interrupt (timer mode); see STEPPER_DRIVER_ISR. */
    static void on_compare_match();
};

/* The sketch owns the interrupt vector, so that sketches using Timer1 for something else can still
 * link MotionBoard: a stepper sketch writes STEPPER_DRIVER_ISR() once at file scope. */
#if STEPPER_TIMED_LOOP
#define STEPPER_DRIVER_ISR()
#else
#include <avr/interrupt.h>
#define STEPPER_DRIVER_ISR()                                                                         \
    ISR(TIMER1_COMPA_vect)                                                                           \
    {                                                                                                \
        StepperDriver::on_compare_match();                                                           \
    }
#endif

#endif
