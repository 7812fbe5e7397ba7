/* BoardHeap.h - memory that the step engine and the Stepper take once and never give back (the
 * step rings at begin(), a Stepper's stop planned ahead, the sigmoid's table, the smooth planner).
 *
 * board_take(n) takes n bytes from the heap, the free SRAM between the static data (__heap_start)
 * and the stack, as avr-libc's malloc would, without linking malloc and free (about 580 bytes of
 * flash that a one-axis sketch does not need). A sketch that uses malloc too (its own calls, String)
 * shares the heap safely: malloc's top (__brkval, a weak reference: 0 when malloc is not linked) is
 * then moved past the bytes taken, so malloc never hands them out; without malloc the top is
 * board_heap_top (0 until the first take; the emulator reads either to know where the heap ends).
 * NULL when fewer than n bytes plus the stack's reserve (BOARD_STACK_RESERVE, or more once
 * board_reserve_stack raised it) are left below the stack pointer (Stepper's begin() then refuses:
 * MS_ERR_NO_MEMORY). */
#ifndef BOARD_HEAP_H
#define BOARD_HEAP_H

#include <stddef.h>

/* The bytes kept for the stack below the stack pointer of the call that takes (begin(), from setup()):
 * the planner's interrupt (Timer3) plans on top of whatever loop() is doing, and the step interrupts'
 * C path and the core's interrupts nest on top of that. motionemu fails a run whose stack pointer
 * goes below the heap's top; make test's TightSram check runs a Stepper in a sketch left just this
 * much (setters while it moves: the deepest path measured, some 750 bytes below the top of SRAM) and
 * MultiAxisStepper (three Steppers: some 930 bytes left after its rings). With malloc's 32-byte margin,
 * which this was until 2026-12-06, a sketch whose static data left the rings just room enough began,
 * then its stack ran into them (corrupted commands: a move that never ended). A sketch whose loop()
 * goes deep should raise it, one whose stack is known to stay shallow may lower it:
 * -DBOARD_STACK_RESERVE=... (docs/library.md: SRAM and the stack) */
#ifndef BOARD_STACK_RESERVE
#define BOARD_STACK_RESERVE 896
#endif

extern "C" char *board_heap_top;

void *board_take(size_t n);
/* board_take(n), only where `more` bytes are left beside the reserve after it (for a later take that
 * must not be crowded out: a StepperGroup's room, taken at its first move, after the Steppers' begin()) */
void *board_take_leaving(size_t n, size_t more);
/* A deeper planner (the smooth ramp's): true if n more bytes can be taken with `keep` bytes left for the
 * stack, and from then on every take keeps at least that many; false (nothing changes) otherwise. */
bool board_reserve_stack(size_t keep, size_t n);

#endif
