/* BoardHeap.h - memory that the step engine and the Stepper take once and never give back (the
 * step rings at begin(), a Stepper's stop planned ahead, the sigmoid's table, the smooth planner).
 *
 * board_take(n) takes n bytes from the heap, the free SRAM between the static data (__heap_start)
 * and the stack, as avr-libc's malloc would, without linking malloc and free (about 580 bytes of
 * flash that a one-axis sketch does not need). A sketch that uses malloc too (its own calls, String)
 * shares the heap safely: malloc's top (__brkval, a weak reference: 0 when malloc is not linked) is
 * then moved past the bytes taken, so malloc never hands them out; without malloc the top is
 * board_heap_top (0 until the first take; the emulator reads either to know where the heap ends).
 * NULL when fewer than n bytes plus BOARD_HEAP_MARGIN (malloc's default margin) are left below the
 * stack pointer. */
#ifndef BOARD_HEAP_H
#define BOARD_HEAP_H

#include <stddef.h>

#define BOARD_HEAP_MARGIN 32

extern "C" char *board_heap_top;

void *board_take(size_t n);

#endif
