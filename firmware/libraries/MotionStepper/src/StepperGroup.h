/* StepperGroup.h - straight-line moves of 2 or 3 Steppers (AccelStepper's MultiStepper, with
 * acceleration): every axis follows one constant-acceleration profile s(t) from 0 to 1
 * (lib/src/step_coord.h), so all start on one tick of Timer1, end together, and at every step edge
 * each axis is within one step of the line; each axis's own setMaxSpeed/setAcceleration/setMinSpeed
 * hold (the profile takes the tightest of them, scaled by how far each axis moves).
 *
 *   StepperGroup xy(x, y);   xy.moveTo(4000, 1000);   while (xy.isRunning()) ...
 *
 * moveTo refuses (nothing moves): MS_ERR_NOT_BEGUN before every member's begin(), MS_ERR_BUSY while a
 * member is moving (alone or in a group's move), MS_ERR_OUT_OF_RANGE for three targets to a group of
 * two. It returns at once: the plan is made by the planner interrupt at its next tick, and a plan
 * refused there (MS_ERR_COORD_RATIO: an axis moves too few steps for the longest, step_coord.h's
 * limit) ends the move at once without a step: takeDone() is true and lastStatus() tells why.
 * While the move runs, a member's moveTo is refused (MS_ERR_BUSY) and its stop()/forceStop() stop the
 * whole group (stop: every axis decelerates to rest on the line, within a step).
 */
#ifndef MOTION_STEPPER_STEPPER_GROUP_H
#define MOTION_STEPPER_STEPPER_GROUP_H

#include <Arduino.h>
#include <stdint.h>

#include <motion_status.h>
#include <step_coord.h>

#include <MultiStepEngine.h>

#include "Stepper.h"

/* A group's stop cuts its own axes' queues this many microseconds ahead for each axis with an
 * interrupt of its own in the move (the plan's work, some 4 ms of the AVR per axis: its rewind, its
 * part of the stop and its first commands), grown with the step interrupts' share of the CPU, as a
 * Stepper's plan at a cut: every axis is taken back to its cut
 * (lib's step_coord_rewind) and the stop on the line is planned from there (step_coord_stop). A cut
 * that the step interrupt came too close to is tried again twice as far ahead (STEP_CUT_TRIES cuts
 * in all); then, as with 0 here, the stop acts after the queued lead (40 ms with two Steppers, 100
 * with three). Only with the planner interrupt (a sketch that plans from loop(), MultiAxisStepper,
 * stops after the lead: its planner's work would hold loop() that long). */
#ifndef MOTION_STEPPER_GROUP_CUT_US
#define MOTION_STEPPER_GROUP_CUT_US 4500UL
#endif
/* ... while the master's speed changes (the rewind and the stop cost more there: two Steppers
 * accelerating at 7,500 steps/s took 11.3 ms, 9.2 ms cruising at 20,000) */
#ifndef MOTION_STEPPER_GROUP_CUT_SLOW_US
#define MOTION_STEPPER_GROUP_CUT_SLOW_US 6500UL
#endif
/* ... per axis with three, while the speed changes: the members' cuts are searched one after the
 * other (some 1.2 ms each), so the last lands farther along the line than the first, whose stop then
 * first accelerates to the common point on it (step_coord_stop) in commands of 16, 8, 4, 2 and 1
 * steps, each as costly to plan as any; with the other two axes' first commands to plan as well, the
 * 1 ms more per axis is their time (three Steppers at 15,000 steps/s, 50,000 steps/s^2, stopped 282
 * to 312 ms after the move began: with 6,500 X's queue ran dry after its cut at 2 or 3 moments of 180,
 * 2 ms apart; with 7,500 at none; test/emu/GroupStop, group-three-15k) */
#ifndef MOTION_STEPPER_GROUP_CUT_SLOW_3_US
#define MOTION_STEPPER_GROUP_CUT_SLOW_3_US 7500UL
#endif
/* ... and farther still when the stop asks more of the planner than its own time: the planner's time
 * per command (us, three axes near rest measured at 2.56 commands a millisecond: 2026-12-07, GroupStop
 * traced), times the stop's commands (lib's step_exact_decel_cmds, every own axis from its speed),
 * grown as above, less the stop's duration, is added to the distance (the cut leaves the queues that
 * much more to bank the stop's work: three Steppers at 10,000 steps/s and 100,000 steps/s^2 need
 * some 275 commands in the 100 ms of a stop; cut 20 ms ahead, every axis ran dry 10 times or more) */
#ifndef MOTION_STEPPER_GROUP_CMD_US
#define MOTION_STEPPER_GROUP_CMD_US 400UL
#endif
/* A stop while the group cruises, once every own axis's stop from the cruise is planned ahead
 * (StepperGroup::plan_stop_ahead), plans nothing at its cut (StepperGroup::stop_in_cruise): the cut lies
 * this many microseconds ahead per own axis (its search and switch, grown with the step interrupts'
 * share of the CPU), plus the margin, MOTION_STEPPER_GROUP_AHEAD_SWITCH_US for each member's switch
 * after the first and a cruise interval, plus the stop's bank (stop_bank_us); every own axis is cut at
 * the step from which its own stop ends on the line (MultiStepEngine::cut_find_at). Measured per axis
 * (2026-12-07, GroupStop traced: three Steppers at 10,000 steps/s): 0.3 ms for each search, 0.13-0.18 ms
 * for each switch, 0.23 ms before the first (with 400 here and 150 below, two Steppers at 20,000 steps/s
 * stopped at 300 moments: a later member's switch came too late once, its axis off the line). */
#ifndef MOTION_STEPPER_GROUP_CRUISE_US
#define MOTION_STEPPER_GROUP_CRUISE_US 500UL
#endif
#ifndef MOTION_STEPPER_GROUP_AHEAD_SWITCH_US
#define MOTION_STEPPER_GROUP_AHEAD_SWITCH_US 250UL
#endif
/* ... and each switch puts in the stop's first commands up to this many microseconds of them (the
 * rest, up to MOTION_STEPPER_STOP_SWITCH_US, once every member's switch has come off) */
#ifndef MOTION_STEPPER_GROUP_NOW_US
#define MOTION_STEPPER_GROUP_NOW_US 2500UL
#endif
/* A stop while the group accelerates (StepperGroup::stop_mirrored), as a Stepper's own (StepCut.h): every
 * own axis is cut at the same point of the line, and its acceleration's last commands, reversed, are laid
 * out there (MultiStepEngine::cut_mirror): no plan before the switches. The cut lies this many
 * microseconds ahead per own axis (its search, the reversal and the images: traced 2026-12-07 with three
 * Steppers at 10,000 steps/s, 0.25-0.3 ms for each search and as much for each reversal, the first
 * search 1 ms after the call; 900 us until the reversals grew with MIRROR_PLAN_US below, when a stop at
 * GroupStop's 195 ms moment needed a second try), grown with the step interrupts' share of the CPU, plus the margin,
 * MOTION_STEPPER_GROUP_AHEAD_SWITCH_US for each switch after the first and two intervals of the slowest
 * axis. The reversed commands must last MOTION_STEPPER_GROUP_MIRROR_PLAN_US per own axis (grown as
 * well): after the switches the rest of them is laid out (1 ms an axis) and the rest of each axis's stop
 * planned (lib's step_exact_stop_mirrored, 2 ms of the AVR an axis) while they run, and the feed then
 * catches up (with 3 ms here, three Steppers at 10,000 steps/s ran dry at 4 of 10 moments; with 4 ms,
 * and 4.5, in layouts of 2026-12-07, once, at GroupStop's 135 ms moment: the three axes' reversed
 * commands ran out together a few milliseconds after the feed resumed). 0: no such stop (planned at a
 * cut, stop_at_cut). */
#ifndef MOTION_STEPPER_GROUP_MIRROR_US
#define MOTION_STEPPER_GROUP_MIRROR_US 1000UL
#endif
#ifndef MOTION_STEPPER_GROUP_MIRROR_PLAN_US
#define MOTION_STEPPER_GROUP_MIRROR_PLAN_US 5000UL
#endif
/* Those reversed commands are the ones the ring still holds: early in a move the planner fills the
 * ring with the acceleration's short commands and reuses each slot as soon as it is stepped, and a
 * stop there found less than that (three Steppers at 10,000 steps/s, 125-140 ms after MOVE: 11.2-11.8
 * of the 12 ms they needed at 4 ms an axis) and was planned at a cut, 35 ms after the call. So while such a stop may come, the
 * planner leaves this many slots of each own axis's ring (MultiStepEngine::open_move) to the commands
 * stepped last. 0: none kept. */
#ifndef MOTION_STEPPER_GROUP_MIRROR_KEEP
#define MOTION_STEPPER_GROUP_MIRROR_KEEP 12U
#endif
static_assert(MOTION_STEPPER_GROUP_MIRROR_KEEP <= MULTI_SLOTS / 4, "MOTION_STEPPER_GROUP_MIRROR_KEEP: at most a quarter of the ring");
/* the stop's first commands laid out at the cut for each axis: up to this many (at most
 * MultiStepEngine::MULTI_CUT_MAX_CMDS), covering MOTION_STEPPER_CUT_NEW_US (the feed lays out the rest) */
#define MOTION_STEPPER_GROUP_CUT_CMDS 4U
/* the margin kept at each member's switch for each member's switch still to come after it, us (the
 * members are switched one after the other; once one is, the others must come off too) */
#ifndef MOTION_STEPPER_GROUP_SWITCH_US
#define MOTION_STEPPER_GROUP_SWITCH_US 300UL
#endif
class StepperGroup : public GroupMove {
public:
    StepperGroup(Stepper &a, Stepper &b);
    StepperGroup(Stepper &a, Stepper &b, Stepper &c);

    /* Absolute targets, in the order the members were given; a member left out (two targets for
     * three members) is not part of the move (it may go on moving alone). */
    motion_status_t moveTo(long a, long b);
    motion_status_t moveTo(long a, long b, long c);
    /* The members in `members` (bit j: the j-th member given to the constructor) to targets[j]; the
     * others are not part of the move. MS_ERR_OUT_OF_RANGE for no member, one this group lacks or
     * one beyond the array. (An array, not a pointer: with a pointer, moveTo(0, 0) would be
     * ambiguous, a literal 0 being a null pointer too.) */
    template <unsigned N> motion_status_t moveTo(const long (&targets)[N], uint8_t members)
    {
        return members >= (1U << N) ? MS_ERR_OUT_OF_RANGE : move_members(targets, members);
    }
    /* false from moveTo until the planner interrupt has planned it (then lastStatus() tells). */
    bool planned() const { return !plan_req_; }
    /* decelerate to rest on the line / halt every axis now; MS_ERR_NOT_BEGUN before every member's
     * begin() (as a Stepper's), MS_OK otherwise (nothing moving: nothing to do) */
    motion_status_t stop() override;
    motion_status_t forceStop() override;
    bool isRunning() const;
    /* true once when a move of the group has ended (every axis at rest); positions: each member's
     * currentPosition(). */
    bool takeDone();
    /* The status of the last move's plan (made by the planner interrupt within a millisecond or
     * so of moveTo: MS_ERR_COORD_RATIO shows here, the move then ended at once with no step). */
    motion_status_t lastStatus() const { return last_status_; }
    /* Stops (stop()) that acted after the queued lead instead of at a cut a few milliseconds ahead:
     * no room on the heap for the cut's first commands (taken at the group's first move), planned from
     * loop() (no planner interrupt), a stop whose work needs more bank than the lead, a cut refused or
     * missed on every try, or one after a member's part of the move has ended. 0 in a sketch whose
     * stops all come at a cut. */
    uint16_t cutsMissed() const { return cuts_missed_; }

private:
    friend class Stepper;
    friend class BackgroundPlanner;
    struct Ref {
        StepperGroup *group;
        uint8_t j;       /* index in the group (and in the coordinated plan) */
        uint8_t repeats; /* the member whose commands it repeats (moves as far: pulsed by its interrupt), or 0xFF */
        uint8_t clones;  /* members that repeat this one's */
    };
    motion_status_t move_members(const long *targets, uint8_t members);
    motion_status_t move_all(const long *targets, uint8_t members);
    int8_t index_of(uint8_t axis) const;
    motion_status_t begun() const;
    /* for Stepper and the planner interrupt (axis: the engine's axis number) */
    AxisSource source_of(uint8_t axis) override;
    int32_t position_of(uint8_t axis) override;
    int32_t target_of(uint8_t axis) override;
    uint8_t interrupt_of(uint8_t axis, bool &flip) override;
    void poll_start() override;
    void run_request() override;
    void execute_plan();
    void do_stop();
    enum { GROUP_CUT_NO, GROUP_CUT_DONE, GROUP_CUT_AGAIN };
    enum { SWITCH_NO_ROOM = 0x80 }; /* switch_cuts: above every member's bit */
    uint8_t stop_at_cut();
    uint32_t stop_bank_us(float grow, uint32_t ahead_us, const float v[]);
    step_exact_t &cut_keep(uint8_t j);
    void cut_release();
    void take_cut_room();
    void release();
    void axis_done(uint8_t axis, int32_t position) override;
    void plan_stop_ahead(uint8_t axis) override;
    uint8_t stop_in_cruise();
    uint8_t stop_mirrored();
    uint8_t switch_cuts(const MultiStepEngine::Cut cut[], const uint32_t at[], const uint8_t n_all[], const uint8_t n_now[],
                        const uint8_t n_room[], uint8_t count);
    void mirror_check();
    float cruise_speeds(float v[]) const;
    int32_t follower_position(uint8_t j, int32_t master_pos);
    static uint8_t coord_next(void *ctx, step_cmd_t *c);
    static uint8_t coord_busy(void *ctx);

    Stepper *member_[STEP_COORD_MAX_AXES];
    uint8_t n_;
    step_coord_t coord_;
    Ref ref_[STEP_COORD_MAX_AXES];
    volatile uint8_t mask_; /* members that move (bit j) */
    uint8_t own_;     /* of those, the ones stepped by their own interrupt */
    uint8_t ended_;   /* members whose part has ended */
    uint8_t ahead_;   /* own members whose stop from the cruise is planned ahead (plan_stop_ahead) */
    bool mirror_;     /* this move's stop while accelerating may be mirrored (mirror_check) */
    /* (the rest of it in the room_, on the heap: MultiAxisStepper's three Steppers keep their SRAM) */
    volatile bool starting_; /* held until every own axis has its first commands */
    volatile bool done_;
    volatile bool plan_req_; /* loop() asked for a move: the planner interrupt plans it */
    volatile bool stop_req_; /* loop() asked for a stop */
    uint8_t cut_tries_;      /* the stop's cuts tried */
    uint32_t cut_us_;        /* the next try's distance (0: the first's) */
    uint16_t cuts_missed_;   /* cutsMissed() */
    /* the stop's room at a cut (stop_at_cut), one part per member, from the heap at the first move with
     * the planner interrupt (the Steppers' begin() leave it: BackgroundPlanner::leaveForGroups) */
    struct CutRoom;
    static const uint16_t CUT_ROOM_BYTES;
    CutRoom *room_;
    motion_status_t last_status_;
    int32_t req_to_[STEP_COORD_MAX_AXES];
    int32_t end_[STEP_COORD_MAX_AXES];
};

#endif
