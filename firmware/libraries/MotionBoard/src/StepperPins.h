/* StepperPins.h - the one place for the stepper sketches' pins, timer and timing constants
 * (SimplisticRampStepper, LeibRampStepper, SCurveStepper). Wiring: the X axis of a RAMPS 1.4.
 *
 *   signal   Arduino pin  port bit  meaning
 *   STEP     D54 (A0)     PF0       rising edge = one step; the pulse is high >= 2 us
 *                                   (A4988 needs 1 us, DRV8825 1.9 us, TB6600 2.2 us)
 *   DIR      D55 (A1)     PF1       high = forward (position counts up); written before the
 *                                   first step of a move (> 100 us ahead at any allowed speed)
 *   ENABLE   D38          PD7       active low: driven low in setup (driver on, holding torque)
 *   LED      D13          PB7       toggles on every step when STEPPER_LED_MIRROR = 1 (default):
 *                                   the lab watches it flash faster, steady, slower. A 2.5 us pulse
 *                                   would be invisible, so it toggles (blinks at half the step rate)
 *   TRACE    D40          PG1       only with STEPPER_TRACE = 1: high while the step interrupt
 *                                   runs (ISR timing in the emulator or on a scope)
 * To move the axis, change the port/bit pairs below (and the pin numbers in this table).
 *
 * Step timing (default, STEPPER_TIMED_LOOP = 0): Timer1 (16-bit) in normal mode with prescaler 8,
 * so F = STEPPER_TICK_HZ = 16 MHz / 8 = 2,000,000 ticks/s (0.5 us). Each step edge is scheduled on
 * an absolute timeline (edge_n = edge_(n-1) + interval_n, modulo 2^16, no drift); intervals longer
 * than 65535 ticks are counted out over several compare matches, never truncated. The compare
 * interrupt is armed STEPPER_EARLY_TICKS before the edge and spins on TCNT1 until the exact tick,
 * so the latency of other interrupts (Timer0's millis, the USART) cannot move an edge: every rising
 * edge falls on its tick, within the few cycles of one spin-loop pass (< 1 tick).
 * Intervals: the ramp's float interval p becomes whole ticks by ramp_ticks_from_float() (nearest
 * tick, halves up), the same function `motionsim ramp --integer-ticks` uses, so
 *   motionsim ramp --algo leib --from A --to B --v0 V0 --vmax VMAX --accel A --tick-hz 2000000 --integer-ticks
 * prints the firmware's intervals tick for tick (simplistic the same; SCurveStepper: --algo sigmoid
 * --timer-hz 2000000 with its len/fmin/fmax/flex/hold). t = 0 is when the move is armed, a few us
 * after the target line arrives; DIR changes (if it does) within 1 us of t = 0.
 *
 * Timed-loop mode (STEPPER_TIMED_LOOP = 1, the lab's original structure): loop() compares micros()
 * with the next deadline; F = 1,000,000 ticks/s. Each step is late by 0 to 4 us (micros() counts in
 * 4 us) plus the longest pass of loop(); a serial reply that fills the 64-byte transmit buffer at
 * 9600 baud can hold loop() for tens of ms, so this mode is for comparison, not for real motors.
 */
#ifndef STEPPER_PINS_H
#define STEPPER_PINS_H

#include <avr/io.h>
#include <stdint.h>

#ifndef STEPPER_LED_MIRROR
#define STEPPER_LED_MIRROR 1
#endif
#ifndef STEPPER_TIMED_LOOP
#define STEPPER_TIMED_LOOP 0
#endif
#ifndef STEPPER_TRACE
#define STEPPER_TRACE 0
#endif

/* pins (RAMPS 1.4 X axis) */
#define STEPPER_STEP_PORT PORTF
#define STEPPER_STEP_DDR DDRF
#define STEPPER_STEP_BIT 0 /* D54 */
#define STEPPER_DIR_PORT PORTF
#define STEPPER_DIR_DDR DDRF
#define STEPPER_DIR_BIT 1 /* D55 */
#define STEPPER_ENABLE_PORT PORTD
#define STEPPER_ENABLE_DDR DDRD
#define STEPPER_ENABLE_BIT 7 /* D38, active low */
#define STEPPER_LED_PIN PINB /* writing 1 to a PINx bit toggles the output */
#define STEPPER_LED_DDR DDRB
#define STEPPER_LED_BIT 7 /* D13 */
#define STEPPER_TRACE_PORT PORTG
#define STEPPER_TRACE_DDR DDRG
#define STEPPER_TRACE_BIT 1 /* D40 */

/* timing */
#if STEPPER_TIMED_LOOP
#define STEPPER_TICK_HZ 1000000UL /* micros() */
#else
#define STEPPER_TICK_HZ 2000000UL /* Timer1, 16 MHz / prescaler 8 */
#endif
/* The compare interrupt fires this many ticks before the edge and waits for it: more than the
 * worst delay before it reaches its wait (another interrupt in progress - the USART transmit
 * interrupt is the longest, 128 cycles - plus its own register saving: about 210 cycles = 26 ticks,
 * measured in simavr; README "Stepper ramps: accuracy, timing and the firmware"). */
#define STEPPER_EARLY_TICKS 40U
/* STEP stays high until TCNT1 is this many ticks past the edge: >= 2 us after the rising edge. */
#define STEPPER_PULSE_TICKS 5U

/* The fastest step rate each sketch accepts for vmax (steps/s): the step interrupt must finish
 * before the next edge with room left for loop() and serial. Measured per step: Leib 2,226 cycles
 * while ramping (ceiling 7,200 steps/s), simplistic 1,293 (12,400), S-curve 978 (16,400); the
 * limits keep the interrupt under 70 % of the CPU (README "Stepper ramps: accuracy, timing ..."). */
#if STEPPER_TIMED_LOOP
#define STEPPER_MAX_SPS_SIMPLISTIC 2000.0
#define STEPPER_MAX_SPS_LEIB 2000.0
#define STEPPER_MAX_SPS_SCURVE 2000.0
#else
#define STEPPER_MAX_SPS_SIMPLISTIC 8000.0
#define STEPPER_MAX_SPS_LEIB 5000.0
#define STEPPER_MAX_SPS_SCURVE 10000.0
#endif

#endif
