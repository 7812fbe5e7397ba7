/* MultiStepEngineIsr.S - the common path of the three step interrupts (see MultiStepEngine.h): one
 * step of a normal command, i.e. step_exec_next (lib/src/step_queue.h) on the axis's current slot:
 *   acc += rate; OCR1x = acc >> 16; rate += add; left--
 * and, when the slot is used up, the switch to the next slot if loop() has laid it out. Slow
 * commands and a missing next command jump to the axis's C path (MultiStepEngine.cpp) with the
 * registers restored as they were at the interrupt's entry. STEP rises at the same cycle after the
 * compare match whichever path follows. One routine per axis, written once as the macro below:
 * its arguments are the axis's state, pins, compare register and flag, and C path.
 * STEP: the pins in the state's mask_f (PORTF) and mask_l (PORTL): the axis's own, and those of
 * the axes that follow it in a coordinated move.
 * Registers: r24, r25, r26, r27, r30, r31 and SREG, saved here; the T flag marks a switch.
 * A port outside the I/O space (Z's PORTL) is read-modify-written through r24/r25: interrupts are
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
#define CUR 4
#define WAITING 6
#define LATE 7
#define LATE_TICKS 9
#define MASK_F 10
#define MASK_L 11
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

/* a bit of a port: io = 1 for the I/O space (port = I/O address), 0 for a memory address (uses r24) */
.macro PIN_HIGH io, port, bit
.if \io
    sbi \port, \bit
.else
    lds r24, \port
    ori r24, (1 << \bit)
    sts \port, r24
.endif
.endm
.macro PIN_LOW io, port, bit
.if \io
    cbi \port, \bit
.else
    lds r24, \port
    andi r24, ~(1 << \bit) & 0xFF
    sts \port, r24
.endif
.endm

.macro AXIS_ISR name, st, io, step_port, step_bit, dir_port, dir_bit, ocrl, ocrh, ocf, cold
    .section .text.\name,"ax",@progbits
    .global \name
\name:
    push r24
    in r24, _SFR_IO_ADDR(SREG)
    push r24
    lds r24, \st + WAITING
    tst r24
    breq 1f
    rjmp 9f                      /* counting out a slow interval's wraps: no step at this match */
1:
    /* STEP high: the axis's pin and its followers' (one write per port) */
    push r25
    lds r25, \st + MASK_F
    in r24, _SFR_IO_ADDR(PORTF)
    or r24, r25
    out _SFR_IO_ADDR(PORTF), r24
    lds r25, \st + MASK_L
    lds r24, _SFR_MEM_ADDR(PORTL)
    or r24, r25
    sts _SFR_MEM_ADDR(PORTL), r24
#if MULTI_TRACE
    sbi _SFR_IO_ADDR(MULTI_TRACE_PORT), MULTI_TRACE_BIT
#endif
    push r30
    push r31
    lds r30, \st + CUR
    lds r31, \st + CUR + 1
    ldd r24, Z + S_FLAGS
    sbrc r24, F_SLOW
    rjmp 8f                      /* a slow command: the C path steps it */
    ldd r24, Z + S_LEFT
    ldd r25, Z + S_LEFT + 1
    sbiw r24, 1
    brcs 2f
    std Z + S_LEFT + 1, r25
    std Z + S_LEFT, r24
    clt
    rjmp 3f
2:
    /* the slot is used up: take the next one if it is ready and not slow */
    ldd r24, Z + S_OTHER
    ldd r25, Z + S_OTHER + 1
    movw r30, r24
    ldd r24, Z + S_READY
    tst r24
    brne 4f
    rjmp 8f                      /* nothing ready: the end, or an underrun */
4:
    ldd r24, Z + S_FLAGS
    sbrc r24, F_SLOW
    rjmp 8f
    clr r25
    std Z + S_READY, r25
    sts \st + CUR + 1, r31
    sts \st + CUR, r30
    set                          /* T: switched (DIR may change below) */
3:
    push r26
    push r27
    /* acc += rate, byte by byte (lds/ldd/sts leave the carry alone) */
    lds r24, \st + ACC
    ldd r25, Z + S_RATE
    add r24, r25
    sts \st + ACC, r24
    lds r24, \st + ACC + 1
    ldd r25, Z + S_RATE + 1
    adc r24, r25
    sts \st + ACC + 1, r24
    lds r26, \st + ACC + 2
    ldd r25, Z + S_RATE + 2
    adc r26, r25
    sts \st + ACC + 2, r26
    lds r27, \st + ACC + 3
    ldd r25, Z + S_RATE + 3
    adc r27, r25
    sts \st + ACC + 3, r27
    sts \ocrh, r27               /* high byte first (through TEMP) */
    sts \ocrl, r26
    /* rate += add, when the command has one */
    ldd r24, Z + S_FLAGS
    sbrs r24, F_HAS_ADD
    rjmp 5f
    ldd r24, Z + S_RATE
    ldd r25, Z + S_ADD
    add r24, r25
    std Z + S_RATE, r24
    ldd r24, Z + S_RATE + 1
    ldd r25, Z + S_ADD + 1
    adc r24, r25
    std Z + S_RATE + 1, r24
    ldd r24, Z + S_RATE + 2
    ldd r25, Z + S_ADD + 2
    adc r24, r25
    std Z + S_RATE + 2, r24
    ldd r24, Z + S_RATE + 3
    ldd r25, Z + S_ADD + 3
    adc r24, r25
    std Z + S_RATE + 3, r24
5:
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
    /* a new command may turn: DIR after STEP has fallen */
    brtc 6f
    ldd r25, Z + S_FLAGS
    sbrs r25, F_TURN
    rjmp 6f
    sbrc r25, F_FORWARD
    rjmp 10f
    PIN_LOW \io, \dir_port, \dir_bit
    rjmp 6f
10:
    PIN_HIGH \io, \dir_port, \dir_bit
6:
    /* late? edge - TCNT1 <= 0 (TCNT1L first: it latches the high byte) */
    lds r24, _SFR_MEM_ADDR(TCNT1L)
    lds r25, _SFR_MEM_ADDR(TCNT1H)
    sub r26, r24
    sbc r27, r25
    brmi 7f
    brne 11f
7:
    /* armed in the past (an overload): unless the match came meanwhile, fire 2 us from now */
    sbic _SFR_IO_ADDR(TIFR1), \ocf
    rjmp 11f
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
11:
#if MULTI_TRACE
    cbi _SFR_IO_ADDR(MULTI_TRACE_PORT), MULTI_TRACE_BIT
#endif
    pop r27
    pop r26
    pop r31
    pop r30
    pop r25
    pop r24
    out _SFR_IO_ADDR(SREG), r24
    pop r24
    reti
8:
    pop r31
    pop r30
    pop r25
9:
    pop r24
    out _SFR_IO_ADDR(SREG), r24
    pop r24
    jmp \cold
.endm

AXIS_ISR multi_step_isr_x, multi_axis_x, 1, _SFR_IO_ADDR(MULTI_X_STEP_PORT), MULTI_X_STEP_BIT, _SFR_IO_ADDR(MULTI_X_DIR_PORT), MULTI_X_DIR_BIT, _SFR_MEM_ADDR(OCR1AL), _SFR_MEM_ADDR(OCR1AH), OCF1A, __vector_multi_cold_x
AXIS_ISR multi_step_isr_y, multi_axis_y, 1, _SFR_IO_ADDR(MULTI_Y_STEP_PORT), MULTI_Y_STEP_BIT, _SFR_IO_ADDR(MULTI_Y_DIR_PORT), MULTI_Y_DIR_BIT, _SFR_MEM_ADDR(OCR1BL), _SFR_MEM_ADDR(OCR1BH), OCF1B, __vector_multi_cold_y
AXIS_ISR multi_step_isr_z, multi_axis_z, 0, _SFR_MEM_ADDR(MULTI_Z_STEP_PORT), MULTI_Z_STEP_BIT, _SFR_MEM_ADDR(MULTI_Z_DIR_PORT), MULTI_Z_DIR_BIT, _SFR_MEM_ADDR(OCR1CL), _SFR_MEM_ADDR(OCR1CH), OCF1C, __vector_multi_cold_z
