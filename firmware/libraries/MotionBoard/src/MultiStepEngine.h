/* MultiStepEngine.h - three step interrupts and their queues: X, Y and Z of a RAMPS 1.4 on Timer1's
 * compare channels A, B and C (pins: MultiAxisPins.h). Each axis has its own ring of step commands
 * (lib/src/step_queue.h), filled from loop() by its planner (an independent move: step_planner.h;
 * a coordinated one: step_coord.h), and its own interrupt that executes them.
 *
 * Each interrupt is "simple and dumb", as the single-axis engine's: at its compare match it raises
 * STEP, adds the command's add to the rate and the rate to the axis's timeline (step_exec_next's
 * arithmetic), lowers STEP (>= 2 us later) and arms its OCR1x for the next edge; at a new command
 * that turns, it writes DIR (while STEP is high, >= 1.5 us after its rising edge, which belongs to
 * the old direction). That path is MultiStepEngineIsr.inc, one copy per axis and itself the vector
 * of TIMER1_COMPA/B/C (a sketch using this engine defines no ISR for them); slow steps (an
 * interval of 32768 ticks or more, WIDE ones counted out in wraps of the 16-bit timer), a slow
 * command's start, the end of a move and an underrun take the rarer path in C (MultiStepEngine.cpp);
 * a late edge (armed in the past) is fired 2 us later by either path.
 * Why Timer1's three channels: one counter (TCNT1) is one timeline for all axes, so a coordinated
 * move starts every axis on the same tick (start_together) and their planned edges keep their
 * relation exactly; one timer's three vectors cost nothing more per step than three timers would.
 * Each axis's state is kept one step ahead (ahead form, MultiStepEngineIsr.inc): at a match the
 * interrupt arms the edge it computed at the step before, within a few instructions of STEP, then
 * computes the one after; its own compare interrupt stays masked meanwhile (in_step_interrupt()).
 * The interrupts nest: each raises its STEP in its first instructions, arms its next edge, then
 * enables interrupts, so an edge never waits for another axis's step, only for the short stretches
 * another axis's interrupt runs with interrupts off (some 35 cycles from its entry to its arming; up
 * to about 150 when its own next match came during its slot switch, whose rest then runs with them
 * off; up to about 180 in a C path's arming) and for the core's millis and serial interrupts, which do not
 * nest (a C path that would nest above another axis's masked step is put off: MultiStepEngineIsr.inc);
 * `make bench` measures it.
 * loop() calls service() for each axis: it keeps between two commands and MULTI_LEAD_MS of steps
 * queued ahead, so a stop takes effect within that time. The axes that step come first (the one
 * whose queue reaches least far ahead); a move not started yet gets commands only when none of them
 * needs one, so starting a move never starves a running one (issue 26). A queue that runs dry during a move is an
 * underrun: counted (underruns(), `?`), the motion resumes with the next command.
 */
#ifndef MULTI_STEP_ENGINE_H
#define MULTI_STEP_ENGINE_H

#include <Arduino.h>
#include <stdint.h>

#include <step_queue.h>

#include "MultiAxisPins.h"

#define MULTI_AXES 3U

/* Axes a sketch uses (begin()'s axes): only their state, ring and interrupt are linked. */
#define MULTI_AXIS_X 1U
#define MULTI_AXIS_Y 2U
#define MULTI_AXIS_Z 4U
#define MULTI_AXES_ALL 7U

/* MULTI_SLOTS (MultiAxisPins.h): commands each axis's ring holds (one is the interrupt's current
 * one); 18 bytes of SRAM each (from the heap, begin_axes), and 2 for loop()'s bookkeeping.
 * MULTI_X_ALONE_SLOTS: X's ring when it is the only axis and planned from loop() (MotionStepper's
 * BackgroundPlanner: the stepper sketches). */
/* A move starts stepping once this many commands are laid out (or its planner has no more), when no
 * other axis is stepping; while another is, once its ring is full (MULTI_SLOTS - 1 commands) or its
 * lead is laid out: its planning shares the CPU with theirs, so it starts with all it can bank. */
#ifndef MULTI_START_SLOTS
#define MULTI_START_SLOTS 24U
#endif
/* Steps kept queued ahead of each interrupt, in milliseconds (and at least two commands): how late a
 * stop or a new target takes effect. Long, because three axes accelerating at once, or the ends of
 * their decelerations (one command per step, each a whole exact plan), need more planning than the
 * CPU has at that moment: the queues are filled before it comes (`make bench`: shorter leads lose
 * the three-axis rate). */
#ifndef MULTI_LEAD_MS
#define MULTI_LEAD_MS 100U
#endif

/* A command as loop() lays it out for an interrupt (the first fields at the offsets
 * MultiStepEngineIsr.inc reads, checked in MultiStepEngine.cpp); the interrupt copies rate, add,
 * left and flags into its AxisState when it takes the slot. */
#define AXIS_SLOT_HAS_ADD 0 /* flags bits */
#define AXIS_SLOT_SLOW 1    /* WIDE, or an interval of 32768 ticks or more: the C path steps it */
#define AXIS_SLOT_FORWARD 2 /* DIR level */
#define AXIS_SLOT_TURN 3    /* DIR changes at this command */
#define AXIS_SLOT_WIDE 4    /* rate in whole ticks (step_queue.h's STEP_CMD_WIDE) */
#define AXIS_SLOT_PHASE_SHIFT 5 /* bits 5-6: the ramp phase (step_queue.h's STEP_CMD_PHASE), for `?` */
#define AXIS_SLOT_ADD16 7   /* add within -32768..32767: the interrupt adds two bytes */
struct AxisSlot {
    uint32_t rate;          /* +0  16.16 ticks, the first interval less add (WIDE: whole ticks) */
    int32_t add;            /* +4 */
    uint16_t left;          /* +8  its steps after the first */
    uint8_t flags;          /* +10 AXIS_SLOT_* bits */
    volatile uint8_t ready; /* +11 laid out by loop(), not yet taken by the interrupt */
    AxisSlot *other;        /* +12 the next slot of the ring */
    int32_t p_start;        /* position before the command's first step (it makes left + 1) */
};

/* AxisState.mode: zero on the common path (the axis's own STEP pin, a normal command). */
#define AXIS_MODE_OWN_OFF 0 /* WAITING, MASKED or DEFER: the entry does not raise the axis's own STEP */
#define AXIS_MODE_SLOW 1    /* the current command is slow: the C path steps it */
#define AXIS_MODE_MASKED 2  /* followers: STEP through mask_f/mask_l (a coordinated move) */
#define AXIS_MODE_WAITING 3 /* matches to let pass (a slow interval's wraps) before the step: no STEP */
#define AXIS_MODE_DEFER 4   /* the C path of the step just made put off (MultiStepEngineIsr.inc): no STEP */
#define AXIS_MODE_DEFERS 5  /* bits 5-6: how many times in a row it was put off (MultiStepEngineIsr.inc) */
#define AXIS_MODE_DEFER_ALL (_BV(AXIS_MODE_DEFER) | (3U << AXIS_MODE_DEFERS)) /* the put-off and its count */

/* What one axis's interrupt and loop() share (loop() reads it with interrupts off). The command
 * being stepped lives here (rate, add, left, flags), so the interrupt's common path reaches every
 * field at a fixed address. */
struct AxisState {
    uint32_t acc;               /* +0  the timeline, 16.16 ticks: in ahead form (a fast command, looked_ahead()) the
                                 *     edge after the one armed (OCR1x), which the next match arms; else the armed one */
    uint32_t rate;              /* +4  the current command's next interval less add (WIDE: whole ticks) */
    int32_t add;                /* +8 */
    volatile uint16_t left;     /* +12 its steps not yet armed (ahead form: not yet computed) */
    uint8_t flags;              /* +14 its AXIS_SLOT_* bits */
    volatile uint8_t mode;      /* +15 AXIS_MODE_* bits */
    AxisSlot *volatile cur;     /* +16 the slot being stepped (ahead form: that of the edge computed) */
    volatile uint16_t late;     /* +18 edges armed in the past (fired 2 us later) */
    uint8_t late_ticks;         /* +20 2 us in ticks */
    uint8_t mask_f;             /* +21 the STEP bits of PORTF this interrupt pulses: its axis's, and its followers' */
    uint8_t mask_l;             /* +22 the same in PORTL */
    volatile uint16_t wraps;
    volatile uint8_t running;
    volatile uint8_t finishing; /* the planner has queued the move's last command */
    volatile uint8_t done;      /* the move has ended (cleared by take_done) */
    volatile uint16_t underruns;
    volatile int32_t pos_rest;  /* position when not stepping */
    AxisSlot *slot;             /* its ring (the interrupt follows the slots' `other` links) */
    uint8_t g_any, g_off;       /* its GPIOR0 bits (MultiAxisPins.h) */
};
/* Each axis's state and interrupt are one object (MultiStepEngineX.S, Y.S, Z.S), linked only when
 * its multi_use_* (MultiStepEngineAxisX.cpp, ...) is called: by a Stepper's constructor. */
extern "C" void multi_use_x(void);
extern "C" void multi_use_y(void);
extern "C" void multi_use_z(void);

/* Where an axis's commands come from: next() hands out one (1) or none (0, for now or for good),
 * busy() says whether the planner still has some to hand out. */
struct AxisSource {
    uint8_t (*next)(void *ctx, step_cmd_t *c);
    uint8_t (*busy)(void *ctx);
    void *ctx;
};

class MultiStepEngine {
public:
    /* The axes registered (multi_use_*: a Stepper's constructor) begin: each gets its ring, from the
     * heap (x_alone commands, at least 3, when X is the only one, MULTI_SLOTS each otherwise; false:
     * no room on the heap, nothing begun), its pins as outputs (STEP low, DIR high, ENABLE low = on),
     * and Timer1 runs in normal mode at tick_hz: 16000000 (prescaler 1, MULTI_TICK_HZ) or 2000000
     * (prescaler 8: the lab ramps' STEPPER_TICK_HZ_LAB); any other value means 16 MHz. Step
     * commands are in these ticks. An axis not registered must not be passed to any call. */
    static bool begin_axes(uint32_t tick_hz, uint8_t x_alone = MULTI_SLOTS);
    /* multi_use_*: an axis's state, registered before begin_axes */
    static void attach(uint8_t axis, AxisState &s);
    /* The timeline's ticks per second, as begin() set it (timed-loop mode: 1000000). */
    static uint32_t tick_hz();

    /* Timed-loop mode (MULTI_TIMED_LOOP, from STEPPER_TIMED_LOOP = 1): makes X's steps that are due
     * by micros(); call on every pass of loop() (and service() calls it between commands). With
     * the step interrupts (every other build) it does nothing. */
#if MULTI_TIMED_LOOP
    static void poll();
#else
    static inline void poll() {}
#endif

    /* For an interrupt of low priority that enables interrupts to run long (MotionStepper's planner
     * tick): whether it has interrupted a step interrupt, which then waits for the whole of it (callable
     * with interrupts on: it reads Timer1 in one snapshot with them off). True while an axis's asm path runs (its own compare interrupt masked:
     * TIMSK1's OCIE1x clear while the axis runs) or its C path runs before it arms the next edge (the
     * match has come: OCR1x at or less than 4000 ticks before TCNT1, and its flag is clear). An axis
     * counting out wraps looks busy for 4000 ticks after each; one whose C path is put off (DEFER,
     * MultiStepEngineIsr.inc: up to 3 x 12 us) looks busy too. Timed-loop mode: false. */
#if MULTI_TIMED_LOOP
    static inline bool in_step_interrupt() { return false; }
#else
    static bool in_step_interrupt();
#endif

    /* loop()'s part for one axis: lays out at most max_cmds commands from src while the queue
     * needs them, starts the interrupt (unless the move is held for a common start) and marks the
     * move's end. Returns the number laid out. */
    static uint8_t service(uint8_t axis, const AxisSource &src, uint8_t max_cmds);

    /* How far ahead the axis's queue reaches (ticks), or UINT32_MAX when it needs nothing now:
     * the planner feeds the axis with the shortest queue first (while one has run dry: the one whose
     * next step past its queue is due soonest, interval_ticks). rest: the command running now
     * counts only what is left of it (an estimate: for a choice between axes), else whole. */
    static uint32_t queued_ticks(uint8_t axis, bool rest = false);
    /* Whether the axis's move is paused by an underrun (its queue ran dry), and the interval it steps
     * now (after an underrun: the last one), ticks. Read with interrupts on: for a choice between
     * axes. */
    static bool paused(uint8_t axis);
    static uint32_t interval_ticks(uint8_t axis);

    /* Axis follows master in a coordinated move where both move as far: master's interrupt pulses
     * both STEP pins at once (X and Y in one instruction), so the pair costs one interrupt and one
     * plan per step. Writes axis's DIR now (at rest, before the first step). unfollow: each alone. */
    static void follow(uint8_t master, uint8_t axis, bool forward);
    static void unfollow(uint8_t master);
    /* The position of an axis at rest (a follower's, after its master's move). */
    static void set_rest_position(uint8_t axis, int32_t pos);

    /* A move has enough laid out to start: MULTI_START_SLOTS commands (its ring full while another
     * axis steps, or when set_start_full(axis, true) asked for it), its lead, or everything its
     * planner has. */
    static bool ready_to_start(uint8_t axis, const AxisSource &src);
    /* The axis's moves start only with its ring full (or their lead laid out, or all of them):
     * for a planner whose first commands cost more than the time they cover (the smooth ramp's
     * near rest), the queue banks what it can before the first step. */
    static void set_start_full(uint8_t axis, bool full);

    /* Starts the held moves of the axes in mask (bit i: axis i) on one tick of Timer1. */
    static void start_together(uint8_t mask);

    /* Before a new plan of this axis: the move continues into it (CONTINUES, its end mark
     * withdrawn), the axis is at rest with no move open (AT_REST), or the move had just ended
     * (ENDED, with its final position: report it first). */
    enum Continuation { CONTINUES, AT_REST, ENDED };
    static Continuation extend(uint8_t axis, int32_t &ended_at);

    /* A move from rest has been planned: feed it and report its end (take_done). held: it waits
     * for start_together. keep: ring slots (at most a quarter of them) the planner leaves to the
     * commands stepped last, so that cut_mirror finds them (a StepperGroup's stop while accelerating;
     * early in a move the ring fills with short commands and reuses each slot as soon as it is
     * stepped). */
    static void open_move(uint8_t axis, bool held, uint8_t keep = 0);

    /* Stops the axis at once: no further step, its queue emptied; take_done reports the position. */
    static void halt(uint8_t axis);

    static bool moving(uint8_t axis);
    /* Its move has started stepping (and has not ended): its queue has a deadline. A move accepted but
     * not started yet (its first commands being laid out, or held for start_together) has none. */
    static bool stepping(uint8_t axis);
    static bool held(uint8_t axis);
    static int32_t position(uint8_t axis);
    static uint8_t phase(uint8_t axis); /* ramp_phase_t of the command being stepped; 0 at rest */
    static uint16_t underruns(uint8_t axis);
    static uint16_t late_edges(uint8_t axis);
    static bool take_done(uint8_t axis, int32_t &position);
    static bool done_pending(uint8_t axis); /* take_done would report the end (nothing changed) */

    /* For the MotionStepper library (docs/library.md); the console uses none of these. */
    /* A sketch's function that sets an axis's DIR instead of the engine (the lab's moveOneStep()):
     * hook(true) before steps forwards (position counting up), hook(false) before steps backwards;
     * called before the first step of every move (in start, from the planner's context) and at
     * every reversal (from the step interrupt's C path, after STEP has fallen: a command that turns
     * is stepped by the C path while a hook is set). Keep it short. NULL: the engine writes DIR. */
    typedef void (*DirectionHook)(bool forward);
    static void set_direction_hook(uint8_t axis, DirectionHook hook);
    /* The LED mirror (off until called): D13 (MultiAxisPins.h) toggles on every step X's interrupt
     * makes (STEPPER_LED_MIRROR of the one-axis sketches); costs X's interrupt 2 cycles a step when
     * off, 3 when on, Y's and Z's nothing. on: D13 becomes an output. */
    static void set_led_mirror(bool on);
    /* Steps kept queued ahead of each interrupt, ms (MULTI_LEAD_MS until called): how late a stop
     * or a new target takes effect; at least 1. */
    static void set_lead_ms(uint16_t ms);
    /* The speed being stepped now, steps/s: F (tick_hz()) over the interval armed last, signed by its
     * direction (DIR high = positive); 0 when the axis's own interrupt is not stepping (at rest, or a
     * follower: ask its master). */
    static float speed(uint8_t axis);

    /* Cutting the queue (a stop or a new target acting sooner than the lead: issue 23, the
     * MotionStepper library; docs/stepper-engine.md "Cutting the queue"), in two calls from the
     * planner's context, with interrupts on (the axis keeps stepping):
     * cut_find() chooses where: the first command laid out whose first step lies more than
     * min_ticks_ahead ticks after the edge armed now, keeping at least the command being stepped and
     * dropping at most max_steps steps (the planner's limit: the dropped ones must belong to its
     * current plan); it changes nothing, and tells what would be dropped: their steps, their time in
     * the executor's arithmetic (step_exec_next's sum, 2^-16 ticks: count rate + add count
     * (count - 1)/2, WIDE: count rate 2^16; lib's step_exact_cmd_time16, bit for bit) and the
     * count of the last command kept (the time only with time16: a few hundred cycles a command).
     * Returns 0 when there is no cut (not stepping, or nothing that far), else not 0.
     * The planner then goes back there and plans the new commands c[0..n-1] from there (taking its
     * time); cut_apply() drops those commands and lays c out in their place, if the interrupt is
     * still at least min_ticks_left ticks from them and the ring has room (else it changes nothing
     * and returns false: the planner's work is discarded and the queue goes on as it was).
     * Nothing else may lay out commands for the axis between the two calls. c's slots are made
     * off the ring first; the first dropped slot then becomes c[0] in one copy with interrupts off
     * (if the interrupt has not taken it: else nothing changes), so the interrupt never finds a
     * half-made or missing slot at the cut; the engine's bookkeeping (queue length and time,
     * positions, direction) then stands as if c had followed the kept ones all along, and the
     * move's end mark is withdrawn. The first MULTI_CUT_MAX_CMDS of c are made before the check
     * and put in place in one switch; the rest, if any, are laid out once the switch has come off
     * (as service() lays out commands, without its lead's bound: a stop planned ahead hands out
     * several milliseconds of its commands at once).
     * With split, the cut may also land inside a command stepped by the interrupt's common path (a
     * cruise's or, since 2026-12-06, a ramp's: not slow, not WIDE), the one being stepped included:
     * its steps beyond min_ticks_ahead are dropped too (r.split of them; r.last_count is then what
     * is kept of it), so that the cut lands one interval beyond min_ticks_ahead instead of at the
     * next command's start (a stop acts within a millisecond or so however long its commands are).
     * For a planner that can go back to any step of such a command (the exact ramp: lib's
     * step_exact_rewind). */
    enum { MULTI_CUT_MAX_CMDS = 4 };
    struct Cut {
        uint32_t steps;
        int64_t time16;
        uint16_t last_count;
        uint16_t split; /* steps dropped from the end of the slot before `first` (0: none) */
        uint8_t cmds; /* whole commands dropped (0 and no split: no cut) */
        uint8_t first; /* the first slot dropped (with split: the first slot after the one split) */
    };
    static uint8_t cut_find(uint8_t axis, uint32_t min_ticks_ahead, uint32_t max_steps, Cut &r, bool time16 = true,
                            bool split = false);
    static bool cut_apply(uint8_t axis, const Cut &r, uint32_t min_ticks_left, const step_cmd_t *c, uint8_t n);
    /* cut_find's cut (with split) moved later to drop exactly `drop` steps (a StepperGroup's stop in the
     * cruise cuts each axis where its own stop ends on the line; ramp: also inside an acceleration's
     * command, as its stop while accelerating, which reverses the kept ones); 0: that point lies closer
     * than min_ticks_ahead, or in a command that is not split (slow, WIDE, or a ramp's without ramp);
     * no time sum */
    static uint8_t cut_find_at(uint8_t axis, uint32_t min_ticks_ahead, uint32_t drop, Cut &r, bool ramp = false);
    /* A command made into its slot's form ahead of time (make_image), p_off: the position before its
     * first step less that before the first command's (the cut's, once laid out); make_image moves
     * p_off on past the command (the next one's) and returns the command's time in ticks (its
     * interval times its count, the ramp's change left out: a bound on how much to make). cut_apply with
     * images puts them all in place in its switch, with no work on them but a copy: a stop planned
     * ahead (MotionStepper's) keeps its commands so, and its cut's check comes right after the search
     * (with lay_out's work, 4 commands took 2,500 cycles of every stop's cut). */
    struct SlotImage {
        uint32_t rate; /* as AxisSlot's */
        int32_t add;
        uint16_t left;
        uint8_t flags; /* AXIS_SLOT_* but TURN (cut_apply sets it where the direction changes) */
        uint16_t dur;  /* the command's duration in the engine's books */
        int32_t p_off;
    };
    static uint32_t make_image(const step_cmd_t &c, SlotImage &m, int32_t &p_off);
    /* whether the ring has room for n commands after cut r (cut_apply refuses one without: a StepperGroup
     * checks every member's before its first switch) */
    static bool cut_fits(uint8_t axis, const Cut &r, uint8_t n);
    /* (the ring's room is checked for all n; the switch puts in the first `now` (at least 1), and
     * that is all: the rest, the engine's books and the other n - now images, waits for cut_finish,
     * which the caller must call before anything else is laid out for the axis or cut from its queue,
     * and before the interrupt has stepped those `now`: with two or three Steppers stopped at once,
     * once every axis's switch has come off. tail: what cut_finish needs, kept by the caller.) */
    struct CutTail {
        uint8_t first, cmds, n, next, forward;
        uint16_t dur_p; /* split: what is kept of the slot before first (0xFFFF: no split) */
        int32_t pos_end;
    };
    static bool cut_apply(uint8_t axis, const Cut &r, uint32_t min_ticks_left, const SlotImage *img, uint8_t n,
                          uint8_t now, CutTail &tail);
    static void cut_finish(uint8_t axis, const CutTail &tail, const SlotImage *img, uint8_t n);
    static void append_images(uint8_t axis, const SlotImage *img, uint8_t n);
    /* A stop while accelerating (from rest or after a new target), at once (lib's step_exact_stop_mirrored): the commands that
     * end at cut r (the last kept, then the ones before it, as long as the ring still holds them
     * unchanged), each reversed (its intervals in the opposite order), into c: at most max commands and
     * max_steps steps, until they cover min_ticks; steps: theirs. Returns how many (0: the ring does
     * not hold min_ticks of them, or they are not all the acceleration's); cut_apply then lays them
     * out at the cut, and the planner plans the rest of the stop while they run. */
    static uint8_t cut_mirror(uint8_t axis, const Cut &r, step_cmd_t *c, uint8_t max, uint32_t max_steps,
                              uint32_t min_ticks, uint32_t &steps);
};

#endif
