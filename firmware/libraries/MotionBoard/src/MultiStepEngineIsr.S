/* MultiStepEngineIsr.S - the common path of the three step interrupts (see MultiStepEngine.h): one
 * step of a normal command, i.e. step_exec_next (lib/src/step_queue.h) on the command the axis's
 * state holds:
 *   STEP high; left--; rate += add; acc += rate; STEP low; OCR1x = acc >> 16; late?
 * (the state's rate is the next interval less add, laid out so by MultiStepEngine.cpp, so that the
 * new edge comes out of the last addition in two registers)
 * and, when the command is used up, the switch to the next slot if loop() has laid it out (its
 * rate, add, left and flags copied into the state; DIR written if it turns, at least 1.5 us after
 * the last STEP edge of the old direction and long before the first of the new). Slow commands,
 * wraps to count out and a missing next command call the axis's C path (MultiStepEngine.cpp).
 *
 * The three interrupts nest, so that an edge never waits for another axis's step: each raises its
 * STEP in its first instructions and enables interrupts (sei); the step's arithmetic may then be
 * interrupted by another axis's edge. Only those first instructions, the short stretches that touch
 * shared hardware (PORTL is read-modify-written) and the end run with interrupts off: the end arms
 * the new edge (OCR1x: Timer1's 16-bit registers share one TEMP byte) and tests whether it is
 * already late, so an axis's next match never comes while its own interrupt runs and the
 * interrupt never nests in itself. An edge due in one of those stretches waits a few dozen cycles
 * at most (`make bench` measures it). The C path (rare: the start and end of a move, slow steps,
 * wraps) is called with interrupts on too, and turns them off when it arms.
 * Cost: GPIOR0 holds copies of the mode byte (MultiAxisPins.h): ANY (mode not zero: not the
 * common path) and OWNOFF (no STEP of its own at this match) for each axis, so that the entry
 * raises STEP and chooses its path before saving a register (Z's STEP, in PORTL, needs one). The
 * axis's own STEP pin is raised at the same cycle after the
 * compare match on every path of an axis stepping alone; the master of a coordinated move (mode
 * AXIS_MODE_MASKED) raises its STEP and its followers' through the state's masks, one write per
 * port, with interrupts still off; while wraps are counted out nothing is raised. One routine per
 * axis, written once as the macro below: its arguments are the axis's state, pins, compare
 * register and flag, GPIOR0 bits and C path. Each routine is its interrupt's vector itself
 * (TIMER1_COMPA/B/C_vect: the vector table jumps straight to it, three cycles sooner than through
 * an ISR() in the sketch). Registers: r24, SREG, r25, r26 (r30, r31 at a switch) pushed. The path
 * for a master with followers is a second copy of the step (STEP_BODY m = 1), so the common path
 * has no branch for it at the end.
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
#define F_ADD16 7 /* add within -32768..32767 */
/* mode bits */
#define M_OWN_OFF 0 /* the axis's own STEP is not raised at the entry (WAITING or MASKED) */
#define M_SLOW 1
#define M_MASKED 2
#define M_WAITING 3

#define G0 _SFR_IO_ADDR(GPIOR0)

/* a bit of a port: io = 1 for the I/O space (port = I/O address), 0 for a memory address (uses reg;
 * interrupts must be off, as in the entry and the exit) */
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
/* the same where interrupts are on: a read-modify-write with them off around it */
.macro PIN_HIGH_NESTED io, port, bit, reg
.if \io
    sbi \port, \bit
.else
    cli
    PIN_HIGH 0, \port, \bit, \reg
    sei
.endif
.endm
.macro PIN_LOW_NESTED io, port, bit, reg
.if \io
    cbi \port, \bit
.else
    cli
    PIN_LOW 0, \port, \bit, \reg
    sei
.endif
.endm

/* TRACE (MULTI_TRACE builds, for `make bench`): each axis's pin is high while its step interrupt
 * runs (other interrupts nested in it included); the pins' union is the CPU's time in step
 * interrupts. */
.macro TRACE_HIGH bit
#if MULTI_TRACE
    sbi _SFR_IO_ADDR(MULTI_TRACE_PORT), \bit
#endif
.endm
.macro TRACE_LOW bit
#if MULTI_TRACE
    cbi _SFR_IO_ADDR(MULTI_TRACE_PORT), \bit
#endif
.endm

/* the LED mirror (led = 1: X's interrupt only): D13 toggles at a step while GPIOR0's LED_X bit is set
 * (MultiStepEngine::set_led_mirror); 2 cycles when off, 3 when on (writing 1 to PINB7 toggles it) */
.macro LED_MIRROR led
.if \led
    sbic G0, MULTI_G_LED_X
    sbi _SFR_IO_ADDR(MULTI_LED_PIN), MULTI_LED_BIT
.endif
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

/* left's high byte when the low one borrows (once in 256 steps): a borrow there too means the
 * command is used up (the switch); r24 holds the low byte, 0xFF */
.macro LEFT_HIGH name, m, st
.L\name\()_lefthi\m:
    lds r25, \st + LEFT + 1
    subi r25, 1
    brcc 1f
    rjmp .L\name\()_switch\m
1:
    sts \st + LEFT + 1, r25
    sts \st + LEFT, r24
    rjmp .L\name\()_acc\m
.endm

/* One copy of the step path (interrupts on; r24, SREG and r25 pushed): m = 0 for an axis
 * stepping alone (its own STEP lowered at the end), m = 1 for a master with followers (every STEP
 * of the masks lowered). The switch of slots and left's high byte (m = 1: here, jumped over;
 * m = 0: before the entry), then the step, the exit, then the rarer late edge. */
.macro STEP_BODY name, m, st, io, step_port, step_bit, dir_port, dir_bit, ocrl, ocrh, ocf, trace
.if \m
    rjmp .L\name\()_left\m
.L\name\()_switch\m:
    SWITCH_SLOT \name, \m, \st, \io, \dir_port, \dir_bit
    LEFT_HIGH \name, \m, \st
.endif
.L\name\()_left\m:
    lds r24, \st + LEFT          /* left-- */
    subi r24, 1
    brcs .L\name\()_lefthi\m
    sts \st + LEFT, r24
.L\name\()_acc\m:
    push r26
    /* rate += add, when the command has one */
    lds r24, \st + FLAGS
    sbrs r24, F_HAS_ADD
    rjmp .L\name\()_rate\m
    sbrs r24, F_ADD16
    rjmp .L\name\()_add32\m
    /* add within 16 bits (near speed, the common case): two bytes, then the upper half only on a
     * carry of a positive add or no carry of a negative one (r25: add's sign byte) */
    lds r24, \st + RATE
    lds r25, \st + ADD
    add r24, r25
    sts \st + RATE, r24
    lds r24, \st + RATE + 1
    lds r25, \st + ADD + 1
    adc r24, r25
    sts \st + RATE + 1, r24
    brcs .L\name\()_carry\m
    sbrs r25, 7
    rjmp .L\name\()_rate\m
    lds r24, \st + RATE + 2     /* negative, no carry: the upper half less 1 */
    lds r25, \st + RATE + 3
    sbiw r24, 1
    rjmp .L\name\()_upper\m
.L\name\()_carry\m:
    sbrc r25, 7
    rjmp .L\name\()_rate\m
    lds r24, \st + RATE + 2     /* positive with a carry: the upper half plus 1 */
    lds r25, \st + RATE + 3
    adiw r24, 1
.L\name\()_upper\m:
    sts \st + RATE + 3, r25
    sts \st + RATE + 2, r24
    rjmp .L\name\()_rate\m
.L\name\()_add32\m:
    ADD32_STATE \st + RATE, \st + ADD
.L\name\()_rate\m:
    /* acc += rate; the edge, acc >> 16, in r25:r24 */
    lds r24, \st + ACC
    lds r26, \st + RATE
    add r24, r26
    sts \st + ACC, r24
    lds r24, \st + ACC + 1
    lds r26, \st + RATE + 1
    adc r24, r26
    sts \st + ACC + 1, r24
    lds r24, \st + ACC + 2
    lds r26, \st + RATE + 2
    adc r24, r26
    sts \st + ACC + 2, r24
    lds r25, \st + ACC + 3
    lds r26, \st + RATE + 3
    adc r25, r26
    sts \st + ACC + 3, r25
.if \m == 0 && \io
    cbi \step_port, \step_bit     /* STEP low (more than 2 us after it rose) */
.endif
    /* Interrupts off: the new edge is armed (OCR1x, high byte first through TEMP, which every
     * 16-bit register of Timer1 shares) only now that the step is done, so this axis's next match
     * never comes while its own step runs; late? edge - TCNT1 <= 0 (TCNT1L first: it latches the
     * high byte). Interrupts stay off to the reti (SREG is restored after the pops; the reti sets
     * the I bit): an overloaded axis, whose next match is already due, steps again only after
     * this interrupt has returned, so its interrupts never pile up on the stack. */
    cli
    sts \ocrh, r25
    sts \ocrl, r24
    lds r26, _SFR_MEM_ADDR(TCNT1L)
    sub r24, r26
    lds r26, _SFR_MEM_ADDR(TCNT1H)
    sbc r25, r26
    brmi .L\name\()_rearm\m
    breq .L\name\()_rearm\m
.L\name\()_low\m:
.if \m
    /* every STEP of the masks low (read-modify-write: interrupts off) */
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
.elseif \io == 0
    PIN_LOW 0, \step_port, \step_bit, r24
.endif
    TRACE_LOW \trace
    pop r26
    pop r25
    pop r24
    andi r24, 0x7F               /* SREG as at the entry, the I bit clear until the reti */
    out _SFR_IO_ADDR(SREG), r24
    pop r24
    reti
.L\name\()_rearm\m:
    /* armed in the past (an overload): unless its match came meanwhile, fire 2 us from now */
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
    PIN_LOW_NESTED \io, \dir_port, \dir_bit, r24
    rjmp .L\name\()_dirset\m
.L\name\()_fwd\m:
    PIN_HIGH_NESTED \io, \dir_port, \dir_bit, r24
.L\name\()_dirset\m:
    pop r31
    pop r30
    rjmp .L\name\()_acc\m
.L\name\()_none\m:
    pop r31
    pop r30
    rjmp .L\name\()_cold
.endm

/* io: the STEP port is in the I/O space (X, Y: the entry raises STEP before saving a register, by
 * the GPIOR0 copy `ownoff`); Z's PORTL is read-modify-written. any: the GPIOR0 copy of "mode not
 * zero"; trace: the axis's TRACE bit. */
.macro AXIS_ISR name, vector, st, io, step_port, step_bit, dir_port, dir_bit, ocrl, ocrh, ocf, cold, trace, ownoff, any, led
    .section .text.\name,"ax",@progbits
    .global \name
    .global \vector
    /* out of the common path, placed before the entry so that its short branches reach */
.L\name\()_switch0:
    SWITCH_SLOT \name, 0, \st, \io, \dir_port, \dir_bit
    LEFT_HIGH \name, 0, \st
\vector:
\name:
.if \io
    sbis G0, \ownoff
    sbi \step_port, \step_bit    /* STEP high (not while counting out wraps; followers: later) */
.else
    sbic G0, \ownoff
    rjmp .L\name\()_own_off
    push r24
    in r24, _SFR_IO_ADDR(SREG)
    push r24
    PIN_HIGH 0, \step_port, \step_bit, r24   /* STEP high (read-modify-write, registers saved) */
.endif
    TRACE_HIGH \trace
.if \io
    sbic G0, \any
    rjmp .L\name\()_any
    LED_MIRROR \led
    sei                          /* the common path: another axis's edge may interrupt from here */
    push r24
    in r24, _SFR_IO_ADDR(SREG)
    push r24
    push r25
.else
    push r25
    sbic G0, \any
    rjmp .L\name\()_other
    sei                          /* the common path: another axis's edge may interrupt from here */
.endif
    STEP_BODY \name, 0, \st, \io, \step_port, \step_bit, \dir_port, \dir_bit, \ocrl, \ocrh, \ocf, \trace
    STEP_BODY \name, 1, \st, \io, \step_port, \step_bit, \dir_port, \dir_bit, \ocrl, \ocrh, \ocf, \trace
.L\name\()_cold:
    /* the C path (MultiStepEngine.cpp), called as a function with interrupts on and the registers
     * it may change saved; it returns with interrupts off (from the arming of the next edge on) */
    sei
    push r0
    push r1
    push r18
    push r19
    push r20
    push r21
    push r22
    push r23
    push r26
    push r27
    push r30
    push r31
    clr r1
    call \cold
    pop r31
    pop r30
    pop r27
    pop r26
    pop r23
    pop r22
    pop r21
    pop r20
    pop r19
    pop r18
    pop r1
    pop r0
    TRACE_LOW \trace
    pop r25
    pop r24
    andi r24, 0x7F               /* SREG as at the entry, the I bit clear until the reti */
    out _SFR_IO_ADDR(SREG), r24
    pop r24
    reti
.if \io == 0
.L\name\()_own_off:
    /* counting out wraps, or a master with followers: no STEP of its own here */
    push r24
    in r24, _SFR_IO_ADDR(SREG)
    push r24
    push r25
    TRACE_HIGH \trace
    rjmp .L\name\()_other
.endif
.if \io
.L\name\()_any:
    /* interrupts off: save as the common path does */
    push r24
    in r24, _SFR_IO_ADDR(SREG)
    push r24
    push r25
.endif
.L\name\()_other:
    /* mode not zero (interrupts off): wraps to count or a slow command (the C path), or followers:
     * a master raises its STEP and its followers' here */
    lds r24, \st + MODE
    sbrc r24, M_WAITING
    rjmp .L\name\()_cold         /* counting out a slow interval's wraps: no step at this match */
    sbrs r24, M_MASKED
    rjmp .L\name\()_cold         /* a slow command: the C path steps it (STEP is high) */
    /* the axis's own STEP and its followers' together: one write per port */
    lds r25, \st + MASK_F
    in r24, _SFR_IO_ADDR(PORTF)
    or r24, r25
    out _SFR_IO_ADDR(PORTF), r24
    lds r25, \st + MASK_L
    lds r24, _SFR_MEM_ADDR(PORTL)
    or r24, r25
    sts _SFR_MEM_ADDR(PORTL), r24
    lds r24, \st + MODE
    sbrc r24, M_SLOW
    rjmp .L\name\()_cold         /* (the C path mirrors its steps on the LED itself) */
    LED_MIRROR \led
    sei
    rjmp .L\name\()_left1
.endm

/* the three interrupts (none in timed-loop mode: MultiStepEngineLoop.cpp steps X from loop()) */
#if !MULTI_TIMED_LOOP
AXIS_ISR multi_step_isr_x, TIMER1_COMPA_vect, multi_axis_x, 1, _SFR_IO_ADDR(MULTI_X_STEP_PORT), MULTI_X_STEP_BIT, _SFR_IO_ADDR(MULTI_X_DIR_PORT), MULTI_X_DIR_BIT, _SFR_MEM_ADDR(OCR1AL), _SFR_MEM_ADDR(OCR1AH), OCF1A, multi_cold_x, MULTI_TRACE_X_BIT, MULTI_G_OWNOFF_X, MULTI_G_ANY_X, 1
AXIS_ISR multi_step_isr_y, TIMER1_COMPB_vect, multi_axis_y, 1, _SFR_IO_ADDR(MULTI_Y_STEP_PORT), MULTI_Y_STEP_BIT, _SFR_IO_ADDR(MULTI_Y_DIR_PORT), MULTI_Y_DIR_BIT, _SFR_MEM_ADDR(OCR1BL), _SFR_MEM_ADDR(OCR1BH), OCF1B, multi_cold_y, MULTI_TRACE_Y_BIT, MULTI_G_OWNOFF_Y, MULTI_G_ANY_Y, 0
AXIS_ISR multi_step_isr_z, TIMER1_COMPC_vect, multi_axis_z, 0, _SFR_MEM_ADDR(MULTI_Z_STEP_PORT), MULTI_Z_STEP_BIT, _SFR_MEM_ADDR(MULTI_Z_DIR_PORT), MULTI_Z_DIR_BIT, _SFR_MEM_ADDR(OCR1CL), _SFR_MEM_ADDR(OCR1CH), OCF1C, multi_cold_z, MULTI_TRACE_Z_BIT, MULTI_G_OWNOFF_Z, MULTI_G_ANY_Z, 0
#endif
