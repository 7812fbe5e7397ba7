/* StepEngineIsr.S - the step interrupt's common path (see StepEngine.h): one step of a normal
 * command, i.e. step_exec_next (lib/src/step_queue.h) in assembly on the current slot:
 *   acc += rate; OCR1A = acc >> 16; rate += add; left--
 * and, when the slot is used up, the switch to the other slot if loop() has filled it. Slow
 * commands and a missing next command jump to the C path (StepEngine.cpp) with the
 * registers restored as they were at the interrupt's entry. STEP rises at the same cycle after
 * the compare match whichever path follows. This path never touches DIR: a command that turns
 * (STEP_SLOT_TURN) is taken by the C path, which sets DIR through the sketch's direction hook
 * (its moveOneStep(), StepEngine::set_direction_hook) or, without one, by itself.
 * Registers: r24, r25, r26, r27, r30, r31 and SREG, saved here.
 */
#include <avr/io.h>
#include "StepperPins.h"

#define ACC (step_engine + 0)
#define CUR (step_engine + 4)
#define WAITING (step_engine + 6)
#define LATE (step_engine + 7)
#define LATE_TICKS (step_engine + 9)
/* StepSlot offsets */
#define S_RATE 0
#define S_ADD 4
#define S_LEFT 8
#define S_FLAGS 10
#define S_READY 11
#define S_OTHER 12
#define F_HAS_ADD 0
#define F_SLOW 1
#define F_TURN 3

    .section .text.step_engine_isr,"ax",@progbits
    .global step_engine_isr
step_engine_isr:
    push r24
    in r24, _SFR_IO_ADDR(SREG)
    push r24
    lds r24, WAITING
    tst r24
    breq stepping
    rjmp to_cold                 /* counting out a slow interval's wraps: no step at this match */
stepping:
    sbi _SFR_IO_ADDR(STEPPER_STEP_PORT), STEPPER_STEP_BIT
#if STEPPER_TRACE
    sbi _SFR_IO_ADDR(STEPPER_TRACE_PORT), STEPPER_TRACE_BIT
#endif
#if STEPPER_LED_MIRROR
    ldi r24, (1 << STEPPER_LED_BIT)
    out _SFR_IO_ADDR(STEPPER_LED_PIN), r24
#endif
    push r25
    push r30
    push r31
    lds r30, CUR
    lds r31, CUR + 1
    ldd r24, Z + S_FLAGS
    sbrc r24, F_SLOW
    rjmp to_cold_z               /* a slow command: the C path steps it */
    ldd r24, Z + S_LEFT
    ldd r25, Z + S_LEFT + 1
    sbiw r24, 1
    brcs next_slot
    std Z + S_LEFT + 1, r25
    std Z + S_LEFT, r24
    rjmp arm
next_slot:
    /* the slot is used up: take the other one if it is ready, not slow and keeps the direction */
    ldd r24, Z + S_OTHER
    ldd r25, Z + S_OTHER + 1
    movw r30, r24
    ldd r24, Z + S_READY
    tst r24
    brne take_it
    rjmp to_cold_z               /* nothing ready: the end, or an underrun */
take_it:
    ldd r24, Z + S_FLAGS
    andi r24, (1 << F_SLOW) | (1 << F_TURN)
    breq take_fast
    rjmp to_cold_z               /* slow, or DIR changes: the C path takes it */
take_fast:
    clr r25
    std Z + S_READY, r25
    sts CUR + 1, r31
    sts CUR, r30
arm:
    push r26
    push r27
    /* acc += rate, byte by byte (lds/ldd/sts leave the carry alone) */
    lds r24, ACC
    ldd r25, Z + S_RATE
    add r24, r25
    sts ACC, r24
    lds r24, ACC + 1
    ldd r25, Z + S_RATE + 1
    adc r24, r25
    sts ACC + 1, r24
    lds r26, ACC + 2
    ldd r25, Z + S_RATE + 2
    adc r26, r25
    sts ACC + 2, r26
    lds r27, ACC + 3
    ldd r25, Z + S_RATE + 3
    adc r27, r25
    sts ACC + 3, r27
    sts _SFR_MEM_ADDR(OCR1AH), r27 /* high byte first (through TEMP) */
    sts _SFR_MEM_ADDR(OCR1AL), r26
    /* rate += add, when the command has one */
    ldd r24, Z + S_FLAGS
    sbrs r24, F_HAS_ADD
    rjmp no_add
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
no_add:
    cbi _SFR_IO_ADDR(STEPPER_STEP_PORT), STEPPER_STEP_BIT
    /* late? edge - TCNT1 <= 0 (TCNT1L first: it latches the high byte) */
    lds r24, _SFR_MEM_ADDR(TCNT1L)
    lds r25, _SFR_MEM_ADDR(TCNT1H)
    sub r26, r24
    sbc r27, r25
    brmi late
    brne in_time
late:
    /* armed in the past (an overload): unless the match came meanwhile, fire 2 us from now */
    sbic _SFR_IO_ADDR(TIFR1), OCF1A
    rjmp in_time
    lds r24, _SFR_MEM_ADDR(TCNT1L)
    lds r25, _SFR_MEM_ADDR(TCNT1H)
    lds r26, LATE_TICKS
    add r24, r26
    clr r26
    adc r25, r26
    sts _SFR_MEM_ADDR(OCR1AH), r25
    sts _SFR_MEM_ADDR(OCR1AL), r24
    lds r24, LATE
    lds r25, LATE + 1
    adiw r24, 1
    sts LATE + 1, r25
    sts LATE, r24
in_time:
#if STEPPER_TRACE
    cbi _SFR_IO_ADDR(STEPPER_TRACE_PORT), STEPPER_TRACE_BIT
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
to_cold_z:
    pop r31
    pop r30
    pop r25
to_cold:
    pop r24
    out _SFR_IO_ADDR(SREG), r24
    pop r24
    jmp __vector_step_engine_cold
