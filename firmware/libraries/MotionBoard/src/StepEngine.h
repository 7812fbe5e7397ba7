/* StepEngine.h - the step interrupt and its queue: executes the step commands the planner
 * (lib/src/step_planner.h) puts into a step_queue_t, on Timer1's compare A, for the X axis of a
 * RAMPS 1.4 (pins: StepperPins.h).
 *
 * "Simple and dumb": at each compare match the interrupt raises STEP, adds the command's rate to
 * the timeline and its add to the rate (step_exec_next's arithmetic: no float, no division, no
 * planner call), arms OCR1A for the next edge and lowers STEP; when the command is used up it
 * switches to the next slot of the ring, which loop() has already laid out. That
 * path is StepEngineIsr.S (`make bench` measures its cycles); slow steps (an interval of 32768
 * ticks or more, WIDE ones counted out in whole wraps of the 16-bit timer), the move's end, an
 * underrun, a late edge and a command that reverses take the rarer path in C (StepEngine.cpp).
 * STEP rises at the same cycle after the compare match on both paths, stays high >= 2 us, and DIR
 * changes only after it falls.
 * DIR: set before the first step of a move from rest (in loop()) and at a reversal (the C path,
 * after the last step of the old direction), by the sketch's direction hook when it registered
 * one (set_direction_hook: the lab sketches' moveOneStep(bool direction), whose two lines write
 * dirPin), otherwise by the engine itself (high = forwards). The assembly path never writes DIR. An edge that would already be in the past when armed (only an overload can cause it)
 * is counted as late and fires 2 us later instead of a timer wrap later.
 * Timing: F = 16 MHz (prescaler 1: ExactRampStepper) or 2 MHz (prescaler 8: the lab's ramps).
 * An edge is late by the time another interrupt holds the CPU at its compare match (the core's
 * millis and serial interrupts); `make bench` measures the worst case (docs/bench.md).
 * The planner runs in loop() (service(), called by the console): it keeps the queue between two
 * commands and STEP_ENGINE_LEAD_MS of steps ahead, so a stop or a new target takes effect within
 * that time. A queue that runs dry during a move is an underrun: counted (underruns(), `?`), and
 * the motion resumes with the next command.
 * Timed-loop mode (STEPPER_TIMED_LOOP = 1, the lab's original structure): no interrupt; poll()
 * from loop() makes the steps that are due by micros() (F = 1 MHz).
 */
#ifndef STEP_ENGINE_H
#define STEP_ENGINE_H

#include <Arduino.h>
#include <stdint.h>

#include <step_planner.h>
#include <step_queue.h> /* step_cmd_t */

#include "StepperPins.h"

/* Commands the queue holds (one is the interrupt's current one); 25 bytes of SRAM each. */
#ifndef STEP_ENGINE_SLOTS
#define STEP_ENGINE_SLOTS 96U
#endif

/* A move starts stepping once this many commands are laid out (or the planner has no more, or
 * the lead is reached): the first steps of an exact ramp cost the most planning per step. */
#ifndef STEP_ENGINE_START_SLOTS
#define STEP_ENGINE_START_SLOTS 24U
#endif

/* Steps kept queued ahead of the interrupt, in milliseconds (and at least two commands), as far
 * as the slots reach: a stop or a new target takes effect after them. The Leib ramp's float
 * update costs nearly a whole step's time near its top rate, so its sketch banks more
 * (StepperRamp::lead_ms). */
#ifndef STEP_ENGINE_LEAD_MS
#define STEP_ENGINE_LEAD_MS 100U
#endif
#ifndef STEP_ENGINE_LEAD_MS_LEIB
#define STEP_ENGINE_LEAD_MS_LEIB 200U
#endif

/* A command as the interrupt executes it. The queue is a ring of slots: loop() lays commands out
 * ahead of the interrupt (marking each ready), the interrupt moves on to the next slot (one
 * pointer) when the current one is used up. The first fields are read by StepEngineIsr.S at
 * fixed offsets (checked in StepEngine.cpp). */
#define STEP_SLOT_HAS_ADD 0 /* flags bits */
#define STEP_SLOT_SLOW 1    /* WIDE, or an interval of 32768 ticks or more: the C path steps it */
#define STEP_SLOT_FORWARD 2 /* DIR level */
#define STEP_SLOT_TURN 3    /* DIR changes at this command */
struct StepSlot {
    uint32_t rate;            /* +0  16.16 ticks (WIDE: whole ticks) */
    int32_t add;              /* +4 */
    volatile uint16_t left;   /* +8  steps not yet armed */
    uint8_t flags;            /* +10 STEP_SLOT_* bits */
    volatile uint8_t ready;   /* +11 filled by loop(), not yet taken by the interrupt */
    StepSlot *other;          /* +12 the next slot of the ring */
    int32_t p_start;          /* position before the command's first step */
    uint16_t count;           /* steps of the command */
    uint8_t cmd_flags;        /* the step_cmd_t flags (WIDE, REVERSE, phase) */
};

/* What the interrupt and loop() share (loop() reads it with interrupts off). */
struct StepEngineState {
    uint32_t acc;               /* +0 the timeline: time of the armed edge, 16.16 ticks */
    StepSlot *volatile cur;     /* +4 the slot being stepped */
    volatile uint8_t waiting;   /* +6 matches to let pass (a slow interval's wraps) before the step */
    volatile uint16_t late;     /* +7 edges armed in the past (fired 2 us later) */
    uint8_t late_ticks;         /* +9 2 us in timer ticks: how soon a late edge fires */
    volatile uint16_t wraps;    /* wraps still to wait */
    volatile uint8_t running;   /* the compare interrupt is stepping */
    volatile uint8_t finishing; /* the planner has queued the move's last command */
    volatile uint8_t done;      /* the move has ended (cleared by take_done) */
    volatile uint8_t starved;   /* stopped by an underrun, waiting for commands */
    volatile uint16_t underruns;
    volatile int32_t pos_rest;  /* position when not stepping */
    StepSlot slot[STEP_ENGINE_SLOTS]; /* the queue: a ring, each slot's `other` is the next one */
};
extern "C" StepEngineState step_engine;

class StepEngine {
public:
    /* Pins as outputs (STEP low, DIR high, ENABLE low = on, LED), Timer1 in normal mode at
     * tick_hz: 16000000 or 2000000 (timed-loop mode: always 1000000). */
    static void begin(uint32_t tick_hz, uint16_t lead_ms = STEP_ENGINE_LEAD_MS);

    /* The sketch's function that sets DIR: hook(true) before steps forwards (position counting up),
     * hook(false) before steps backwards; called once before the first step of every move from rest
     * and once at every reversal (from the step interrupt's C path, after STEP has fallen, before
     * the first step the other way), never per step. It runs inside the interrupt then: keep it short
     * (two digitalWrite()s are). Without a hook (NULL, the default)
     * the engine writes DIR itself. If the hook leaves DIR alone, the motor turns one way only while
     * the position still counts both ways: the lab exercise (the lab handout, moveOneStep()). */
    typedef void (*DirectionHook)(bool forward);
    static void set_direction_hook(DirectionHook hook);
    static uint32_t tick_hz();

    /* loop()'s part: moves commands from the planner into the queue while it needs them, starts
     * the interrupt, and marks the move's end once the planner has nothing more. */
    static void service(step_planner_t &planner);

    /* Before a new target or a stop is planned: whether a move is in progress and continues
     * into the new plan (CONTINUES: its end mark is withdrawn, so the replaced move gets no DONE),
     * the axis is at rest with no move open (AT_REST), or the move had just ended (ENDED, with its
     * final position: report its DONE first). Decided with interrupts off, so no end is lost. */
    enum Continuation { CONTINUES, AT_REST, ENDED };
    static Continuation extend(int32_t &ended_at);

    /* A move from rest has been planned: feed it (service) and report its end (take_done). */
    static void open_move();

    /* Stops at once: no further step, the queue emptied; take_done reports the position. */
    static void halt();

    /* A move is open: accepted and not yet reported done. */
    static bool moving();
    static int32_t position();
    /* Phase (ramp_phase_t) of the command being stepped; RAMP_IDLE when not stepping. */
    static uint8_t phase();
    static uint16_t underruns();
    static uint16_t late_edges();
    /* True once after each move has ended, with the final position. */
    static bool take_done(int32_t &position);

    /* Timed-loop mode: makes the steps that are due; call on every pass of loop(). */
    static void poll();

    /* The body of ISR(TIMER1_COMPA_vect, ISR_NAKED): jumps to the step routine
     * (StepEngineIsr.S), which saves what it uses and returns from the interrupt itself. */
    static inline void on_step_timer() __attribute__((always_inline))
    {
        asm volatile("jmp step_engine_isr" ::);
    }
};

#endif
