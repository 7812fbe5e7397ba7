/* MultiAxisPins.h - the one place for MultiAxisStepper's pins, timer and limits: the X, Y and Z
 * drivers of a RAMPS 1.4 (all in the Mega's pin header), stepped by Timer1's three compare
 * channels (MultiStepEngine.h).
 *
 *   axis  STEP          DIR           ENABLE (low = on)   compare channel (one timeline, TCNT1)
 *   X     D54 (A0) PF0  D55 (A1) PF1  D38 PD7             OCR1A, TIMER1_COMPA_vect
 *   Y     D60 (A6) PF6  D61 (A7) PF7  D56 (A2) PF2        OCR1B, TIMER1_COMPB_vect
 *   Z     D46 PL3       D48 PL1       D62 (A8) PK0        OCR1C, TIMER1_COMPC_vect
 *   TRACE D40 PG1 (X), D41 PG0 (Y), D39 PG2 (Z): only with MULTI_TRACE = 1, high while that axis's step
 *         interrupt runs, including the time other interrupts nested in it take (`make bench`)
 * STEP: rising edge = one step, high >= 2 us; DIR: high = forward (position counts up), written
 * before the first step of a move, and where a move turns, at least 1.5 us after the last STEP edge
 * of the old direction (while that pulse is high) and long before the first of the new. PORTF and PORTG are in the I/O space
 * (single-instruction sbi/cbi); PORTL is not, so Z's pins are read-modify-written, only with
 * interrupts off (in its interrupt, or in an atomic block).
 * Timer1 runs at F = 16 MHz (prescaler 1, one tick per CPU cycle) in normal mode; the three
 * channels share TCNT1, so a coordinated move starts every axis on one timeline.
 */
#ifndef MULTI_AXIS_PINS_H
#define MULTI_AXIS_PINS_H

#include <avr/io.h>

/* A build with STEPPER_TRACE=1 (what `make bench` gives the one-axis sketches) traces X's step
 * interrupt on D40, as StepEngine did: the same pin as MULTI_TRACE's X. */
#if !defined(MULTI_TRACE) && defined(STEPPER_TRACE)
#if STEPPER_TRACE
#define MULTI_TRACE 1
#endif
#endif
#ifndef MULTI_TRACE
#define MULTI_TRACE 0
#endif
/* Timed-loop mode (STEPPER_TIMED_LOOP = 1, the lab's original structure): no step interrupt; loop()
 * calls MultiStepEngine::poll(), which makes X's steps that are due by micros() (F = 1 MHz). */
#if defined(STEPPER_TIMED_LOOP) && !defined(MULTI_TIMED_LOOP)
#if STEPPER_TIMED_LOOP
#define MULTI_TIMED_LOOP 1
#endif
#endif
#ifndef MULTI_TIMED_LOOP
#define MULTI_TIMED_LOOP 0
#endif

#define MULTI_X_STEP_PORT PORTF
#define MULTI_X_STEP_BIT 0 /* D54 */
#define MULTI_X_DIR_PORT PORTF
#define MULTI_X_DIR_BIT 1 /* D55 */
#define MULTI_X_ENABLE_PORT PORTD
#define MULTI_X_ENABLE_DDR DDRD
#define MULTI_X_ENABLE_BIT 7 /* D38 */

#define MULTI_Y_STEP_PORT PORTF
#define MULTI_Y_STEP_BIT 6 /* D60 */
#define MULTI_Y_DIR_PORT PORTF
#define MULTI_Y_DIR_BIT 7 /* D61 */
#define MULTI_Y_ENABLE_PORT PORTF
#define MULTI_Y_ENABLE_DDR DDRF
#define MULTI_Y_ENABLE_BIT 2 /* D56 */

#define MULTI_Z_STEP_PORT PORTL
#define MULTI_Z_STEP_BIT 3 /* D46 */
#define MULTI_Z_DIR_PORT PORTL
#define MULTI_Z_DIR_BIT 1 /* D48 */
#define MULTI_Z_ENABLE_PORT PORTK
#define MULTI_Z_ENABLE_DDR DDRK
#define MULTI_Z_ENABLE_BIT 0 /* D62 */

#define MULTI_TRACE_PORT PORTG
#define MULTI_TRACE_DDR DDRG
#define MULTI_TRACE_X_BIT 1 /* D40 */
#define MULTI_TRACE_Y_BIT 0 /* D41 */
#define MULTI_TRACE_Z_BIT 2 /* D39 */

/* LED  D13 PB7: with set_led_mirror(true), toggles on every step X's interrupt makes (writing 1 to a
 *      PINx bit toggles the output): the lab watches it blink at half the step rate */
#define MULTI_LED_PIN PINB
#define MULTI_LED_DDR DDRB
#define MULTI_LED_BIT 7 /* D13 */

#define MULTI_TICK_HZ 16000000UL

/* GPIOR0 (the one bit-addressable general-purpose I/O register: sbi, cbi, sbis, sbic touch no
 * register and no flag) belongs to the step interrupts (MultiStepEngineIsr.inc), which read it before
 * saving a register: ANY is a copy of "the axis's mode byte is not zero" (not the common path);
 * OWNOFF is set when a match of the axis must not raise its STEP: its mode's AXIS_MODE_OWN_OFF (and,
 * harmlessly, while it is not running; ANY too then: a match of an axis not running takes the C
 * path, which does nothing); LED_X mirrors X's steps on D13. No other code of the sketch may use
 * GPIOR0. GPIOR1 and GPIOR2 belong to X's and Y's step paths too (each keeps r26 there while it
 * runs: one cycle each way instead of a push and a pop); no other code may use them either. */
#define MULTI_G_ANY_X 0
#define MULTI_G_ANY_Y 1
#define MULTI_G_ANY_Z 2
#define MULTI_G_OWNOFF_X 3
#define MULTI_G_OWNOFF_Y 4
#define MULTI_G_OWNOFF_Z 5
#define MULTI_G_LED_X 6 /* set_led_mirror(true): X's interrupt toggles the LED at each of its steps */

/* The fastest vmax `set` accepts per axis (steps/s): at or below the highest rate at which three
 * independent moves at once (each axis with its own plan and interrupt, issue 13's case) are clean
 * in `make bench` (docs/bench.md, "MultiAxisStepper: several axes at once") whatever the timing of
 * the host's targets (its sweep: back to back, 1, 5, 20 ms apart, each after the OK of the one
 * before, a `?` or a `set` between them; issue 26): a rung above, the three step interrupts,
 * nesting, sometimes take longer than one step interval, and an axis arms its next edge late
 * (`late=` in `?`) at some of those timings. That ceiling is 30,000 since 2026-12-06 (the console's
 * replies no longer go through the transmit interrupt while an axis steps); the limit stays at
 * 25,000, where the library's three Steppers (which share it) are checked and a coordinated move of
 * unequal axes (its axes' edges often on one tick) was clean in that build (docs/multi-axis.md); a
 * diagonal (axes moving as far, one plan, one interrupt) and one or two axes alone are clean well
 * above it. Above this rate edges come late, the queues can run dry (counted as underruns in `?`)
 * and a coordinated move can leave its line. Override at compile time, e.g. -DMULTI_MAX_SPS=50000
 * for a machine that only moves diagonals or two axes at a time. */
#ifndef MULTI_MAX_SPS
#define MULTI_MAX_SPS 25000.0
#endif

/* The step engine's queues (MultiStepEngine.h): commands each axis's ring holds, and the size of
 * one axis's state (38 bytes: its ring is apart, from the heap, 18 bytes a slot and 2 of
 * bookkeeping), which MultiStepEngineX.S, Y.S and Z.S reserve. Deep,
 * because the end of a deceleration is one command per step (each a whole exact plan) on every axis
 * at once: the queues must hold them before that end comes; three rings of 64 take 3.5 KB of the
 * 8 KB of SRAM. */
#ifndef MULTI_SLOTS
#define MULTI_SLOTS 64
#endif
/* X's ring when it is the only axis and planned from loop() (the one-axis sketches): at most 255 */
#ifndef MULTI_X_ALONE_SLOTS
#define MULTI_X_ALONE_SLOTS 96
#endif
#define MULTI_AXIS_STATE_BYTES 38

#endif
