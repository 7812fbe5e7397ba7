/* MultiStepEngineIsr.S - the common path of the three step interrupts (see MultiStepEngine.h): one
 * step of a normal command, i.e. step_exec_next (lib/src/step_queue.h) on the command the axis's
 * state holds:
 *   STEP high; left--; acc += rate; OCR1x = acc >> 16; rate += add; late?; STEP low
 * and, when the command is used up, the switch to the next slot if loop() has laid it out (its
 * rate, add, left and flags copied into the state; DIR written if it turns, at least 1.5 us after
 * the last STEP edge of the old direction and long before the first of the new). Slow commands,
 * wraps to count out and a missing next command jump to the axis's C path (MultiStepEngine.cpp)
 * with the registers restored as they were at the interrupt's entry.
 * Cost: the state's mode byte is zero on the common path, so one test chooses it; the axis's own
 * STEP pin is raised (sbi) at the same cycle after the compare match on every path of an axis
 * stepping alone; the master of a coordinated move (mode AXIS_MODE_MASKED) raises its STEP and
 * its followers' through the state's masks, one write per port, at the same cycle on each of its
 * paths; while wraps are counted out nothing is raised. One routine per axis, written once as the
 * macro below: its arguments are the axis's state, pins, compare register and flag, and C path.
 * Registers: r24, r25 and SREG kept in GPIOR0..2 while the interrupt runs (one cycle each way
 * instead of a push and a pop; the three step interrupts do not nest and no other code of the sketch
 * uses the GPIORs), r26, r27 (r30, r31 at a switch) pushed. The path for a master with followers is a
 * second copy of the step (STEP_BODY m = 1), so the common path has no branch for it at the end.
 * A port outside the I/O space (Z's PORTL) is read-modify-written through r25/r24: interrupts are
 * off here, and loop() writes it only in atomic blocks.
 */
#include <avr/io.h>
#include "MultiAxisPins.h"

/* the three axes' state (struct AxisState, MultiStepEngine.h): reserved here, zeroed at start-up */
    .section .bss.multi_axis,"aw",@nobits
    .global multi_axis_x
    .type multi_axis_x, @object
    .size multi_axis_x, MULTI_AXIS_STATE_BYTES
multi_axis_x:
    .skip MULTI_AXIS_STATE_BYTES
    .global multi_axis_y
    .type multi_axis_y, @object
    .size multi_axis_y, MULTI_AXIS_STATE_BYTES
multi_axis_y:
    .skip MULTI_AXIS_STATE_BYTES
    .global multi_axis_z
    .type multi_axis_z, @object
    .size multi_axis_z, MULTI_AXIS_STATE_BYTES
multi_axis_z:
    .skip MULTI_AXIS_STATE_BYTES
    .global __do_clear_bss

/* AxisState offsets */
#define ACC 0
#define RATE 4
#define ADD 8
#define LEFT 12
#define FLAGS 14
#define MODE 15
#define CUR 16
#define LATE 18
#define LATE_TICKS 20
#define MASK_F 21
#define MASK_L 22
/* AxisSlot offsets */
#define S_RATE 0
#define S_ADD 4
#define S_LEFT 8
#define S_FLAGS 10
#define S_READY 11
#define S_OTHER 12
#define F_HAS_ADD 0
#define F_SLOW 1
#define F_FORWARD 2
#define F_TURN 3
/* mode bits */
#define M_OWN_OFF 0 /* the axis's own STEP is not raised at the entry (WAITING or MASKED) */
#define M_SLOW 1
#define M_MASKED 2
#define M_WAITING 3

/* a bit of a port: io = 1 for the I/O space (port = I/O address), 0 for a memory address (uses reg) */
.macro PIN_HIGH io, port, bit, reg
.if \io
    sbi \port, \bit
.else
    lds \reg, \port
    ori \reg, (1 << \bit)
    sts \port, \reg
.endif
.endm
.macro PIN_LOW io, port, bit, reg
.if \io
    cbi \port, \bit
.else
    lds \reg, \port
    andi \reg, ~(1 << \bit) & 0xFF
    sts \port, \reg
.endif
.endm

.macro TRACE_HIGH
#if MULTI_TRACE
    sbi _SFR_IO_ADDR(MULTI_TRACE_PORT), MULTI_TRACE_BIT
#endif
.endm
.macro TRACE_LOW
#if MULTI_TRACE
    cbi _SFR_IO_ADDR(MULTI_TRACE_PORT), MULTI_TRACE_BIT
#endif
.endm

/* st += src (4 bytes, state fields; lds/sts leave the carry alone) through r24, r25 */
.macro ADD32_STATE dst, src
    lds r24, \dst
    lds r25, \src
    add r24, r25
    sts \dst, r24
    lds r24, \dst + 1
    lds r25, \src + 1
    adc r24, r25
    sts \dst + 1, r24
    lds r24, \dst + 2
    lds r25, \src + 2
    adc r24, r25
    sts \dst + 2, r24
    lds r24, \dst + 3
    lds r25, \src + 3
    adc r24, r25
    sts \dst + 3, r24
.endm

/* One copy of the step path: m = 0 for an axis stepping alone (its own STEP lowered by cbi at the
 * end), m = 1 for a master with followers (every STEP of the masks lowered). The switch of slots
 * (m = 1: before the step, reached through a jump next to the branch; m = 0: before the entry),
 * then the step, then the rarer late edge. */
.macro STEP_BODY name, m, st, io, step_port, step_bit, dir_port, dir_bit, ocrl, ocrh, ocf
.if \m
    rjmp .L\name\()_left\m
.L\name\()_switch\m:
    SWITCH_SLOT \name, \m, \st, \io, \dir_port, \dir_bit
.L\name\()_tramp\m:
    rjmp .L\name\()_switch\m
.endif
.L\name\()_left\m:
    lds r24, \st + LEFT          /* left-- (a borrow: the command is used up) */
    lds r25, \st + LEFT + 1
    sbiw r24, 1
    brcs .L\name\()_tramp\m
    sts \st + LEFT + 1, r25
    sts \st + LEFT, r24
.L\name\()_acc\m:
    push r26
    push r27
    /* acc += rate; the edge, acc >> 16, into r27:r26 and OCR1x (high byte first, through TEMP) */
    lds r24, \st + ACC
    lds r25, \st + RATE
    add r24, r25
    sts \st + ACC, r24
    lds r24, \st + ACC + 1
    lds r25, \st + RATE + 1
    adc r24, r25
    sts \st + ACC + 1, r24
    lds r26, \st + ACC + 2
    lds r25, \st + RATE + 2
    adc r26, r25
    sts \st + ACC + 2, r26
    lds r27, \st + ACC + 3
    lds r25, \st + RATE + 3
    adc r27, r25
    sts \st + ACC + 3, r27
    sts \ocrh, r27
    sts \ocrl, r26
    /* rate += add, when the command has one */
    lds r24, \st + FLAGS
    sbrs r24, F_HAS_ADD
    rjmp .L\name\()_late\m
    ADD32_STATE \st + RATE, \st + ADD
.L\name\()_late\m:
    /* late? edge - TCNT1 <= 0 (TCNT1L first: it latches the high byte) */
    lds r24, _SFR_MEM_ADDR(TCNT1L)
    lds r25, _SFR_MEM_ADDR(TCNT1H)
    sub r26, r24
    sbc r27, r25
    brmi .L\name\()_rearm\m
    breq .L\name\()_rearm\m
.L\name\()_low\m:
.if \m
    /* every STEP of the masks low */
    lds r25, \st + MASK_F
    com r25
    in r24, _SFR_IO_ADDR(PORTF)
    and r24, r25
    out _SFR_IO_ADDR(PORTF), r24
    lds r25, \st + MASK_L
    com r25
    lds r24, _SFR_MEM_ADDR(PORTL)
    and r24, r25
    sts _SFR_MEM_ADDR(PORTL), r24
.else
    PIN_LOW \io, \step_port, \step_bit, r24
.endif
    TRACE_LOW
    pop r27
    pop r26
    in r25, _SFR_IO_ADDR(GPIOR2)
    in r24, _SFR_IO_ADDR(GPIOR1)
    out _SFR_IO_ADDR(SREG), r24
    in r24, _SFR_IO_ADDR(GPIOR0)
    reti
.L\name\()_rearm\m:
    /* armed in the past (an overload): unless the match came meanwhile, fire 2 us from now */
    sbic _SFR_IO_ADDR(TIFR1), \ocf
    rjmp .L\name\()_low\m
    lds r24, _SFR_MEM_ADDR(TCNT1L)
    lds r25, _SFR_MEM_ADDR(TCNT1H)
    lds r26, \st + LATE_TICKS
    add r24, r26
    clr r26
    adc r25, r26
    sts \ocrh, r25
    sts \ocrl, r24
    lds r24, \st + LATE
    lds r25, \st + LATE + 1
    adiw r24, 1
    sts \st + LATE + 1, r25
    sts \st + LATE, r24
    rjmp .L\name\()_low\m
.endm

/* The command is used up: take the next slot if it is laid out and not slow (its rate, add, left and
 * flags into the state, DIR written if it turns: STEP rose for the old direction more than 1.5 us
 * ago), then make its first step; otherwise the C path (the end, an underrun, a slow command). */
.macro SWITCH_SLOT name, m, st, io, dir_port, dir_bit
    push r30
    push r31
    lds r30, \st + CUR
    lds r31, \st + CUR + 1
    ldd r24, Z + S_OTHER
    ldd r25, Z + S_OTHER + 1
    movw r30, r24
    ldd r24, Z + S_READY
    tst r24
    breq .L\name\()_none\m
    ldd r24, Z + S_FLAGS
    sbrc r24, F_SLOW
    rjmp .L\name\()_none\m
    clr r25
    std Z + S_READY, r25
    sts \st + CUR + 1, r31
    sts \st + CUR, r30
    sts \st + FLAGS, r24
    ldd r25, Z + S_LEFT
    sts \st + LEFT, r25
    ldd r25, Z + S_LEFT + 1
    sts \st + LEFT + 1, r25
    ldd r25, Z + S_RATE
    sts \st + RATE, r25
    ldd r25, Z + S_RATE + 1
    sts \st + RATE + 1, r25
    ldd r25, Z + S_RATE + 2
    sts \st + RATE + 2, r25
    ldd r25, Z + S_RATE + 3
    sts \st + RATE + 3, r25
    ldd r25, Z + S_ADD
    sts \st + ADD, r25
    ldd r25, Z + S_ADD + 1
    sts \st + ADD + 1, r25
    ldd r25, Z + S_ADD + 2
    sts \st + ADD + 2, r25
    ldd r25, Z + S_ADD + 3
    sts \st + ADD + 3, r25
    sbrs r24, F_TURN
    rjmp .L\name\()_dirset\m
    sbrc r24, F_FORWARD
    rjmp .L\name\()_fwd\m
    PIN_LOW \io, \dir_port, \dir_bit, r24
    rjmp .L\name\()_dirset\m
.L\name\()_fwd\m:
    PIN_HIGH \io, \dir_port, \dir_bit, r24
.L\name\()_dirset\m:
    pop r31
    pop r30
    rjmp .L\name\()_acc\m
.L\name\()_none\m:
    pop r31
    pop r30
    rjmp .L\name\()_cold
.endm

.macro AXIS_ISR name, st, io, step_port, step_bit, dir_port, dir_bit, ocrl, ocrh, ocf, cold
    .section .text.\name,"ax",@progbits
    .global \name
    /* out of the common path, placed before the entry so that its short branches reach */
.L\name\()_switch0:
    SWITCH_SLOT \name, 0, \st, \io, \dir_port, \dir_bit
.L\name\()_cold:
    /* the registers as at the entry, then the C path */
    in r25, _SFR_IO_ADDR(GPIOR2)
    in r24, _SFR_IO_ADDR(GPIOR1)
    out _SFR_IO_ADDR(SREG), r24
    in r24, _SFR_IO_ADDR(GPIOR0)
    jmp \cold
.L\name\()_other:
    /* mode not zero: wraps to count, a slow command, or followers */
    sbrc r24, M_WAITING
    rjmp .L\name\()_cold         /* counting out a slow interval's wraps: no step at this match */
    bst r24, M_SLOW
    sbrs r24, M_MASKED
    rjmp .L\name\()_trace
    /* the axis's own STEP and its followers' together: one write per port */
    lds r25, \st + MASK_F
    in r24, _SFR_IO_ADDR(PORTF)
    or r24, r25
    out _SFR_IO_ADDR(PORTF), r24
    lds r25, \st + MASK_L
    lds r24, _SFR_MEM_ADDR(PORTL)
    or r24, r25
    sts _SFR_MEM_ADDR(PORTL), r24
.L\name\()_trace:
    TRACE_HIGH
    brts .L\name\()_cold         /* a slow command: the C path steps it (STEP is high) */
    rjmp .L\name\()_left1
.L\name\()_tramp0:
    rjmp .L\name\()_switch0
\name:
    out _SFR_IO_ADDR(GPIOR0), r24
    in r24, _SFR_IO_ADDR(SREG)
    out _SFR_IO_ADDR(GPIOR1), r24
    out _SFR_IO_ADDR(GPIOR2), r25
    lds r24, \st + MODE
.if \io
    sbrs r24, M_OWN_OFF
    sbi \step_port, \step_bit    /* STEP high (not while counting out wraps; followers: below) */
.else
    sbrc r24, M_OWN_OFF
    rjmp .L\name\()_test
    PIN_HIGH 0, \step_port, \step_bit, r25
.L\name\()_test:
.endif
    tst r24
    brne .L\name\()_other
    TRACE_HIGH
    STEP_BODY \name, 0, \st, \io, \step_port, \step_bit, \dir_port, \dir_bit, \ocrl, \ocrh, \ocf
    STEP_BODY \name, 1, \st, \io, \step_port, \step_bit, \dir_port, \dir_bit, \ocrl, \ocrh, \ocf
.endm

AXIS_ISR multi_step_isr_x, multi_axis_x, 1, _SFR_IO_ADDR(MULTI_X_STEP_PORT), MULTI_X_STEP_BIT, _SFR_IO_ADDR(MULTI_X_DIR_PORT), MULTI_X_DIR_BIT, _SFR_MEM_ADDR(OCR1AL), _SFR_MEM_ADDR(OCR1AH), OCF1A, __vector_multi_cold_x
AXIS_ISR multi_step_isr_y, multi_axis_y, 1, _SFR_IO_ADDR(MULTI_Y_STEP_PORT), MULTI_Y_STEP_BIT, _SFR_IO_ADDR(MULTI_Y_DIR_PORT), MULTI_Y_DIR_BIT, _SFR_MEM_ADDR(OCR1BL), _SFR_MEM_ADDR(OCR1BH), OCF1B, __vector_multi_cold_y
AXIS_ISR multi_step_isr_z, multi_axis_z, 0, _SFR_MEM_ADDR(MULTI_Z_STEP_PORT), MULTI_Z_STEP_BIT, _SFR_MEM_ADDR(MULTI_Z_DIR_PORT), MULTI_Z_DIR_BIT, _SFR_MEM_ADDR(OCR1CL), _SFR_MEM_ADDR(OCR1CH), OCF1C, __vector_multi_cold_z
