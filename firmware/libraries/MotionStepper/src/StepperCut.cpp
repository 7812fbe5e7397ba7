/* StepperCut.cpp - a Stepper's stops and new targets at a cut of its queue (MotionBoard's StepCut.h):
 * the stop planned ahead from the cruise, its lay-out at a cut, a plan at a cut, the retries of a
 * cut that came too late (see Stepper.h). The cuts are linked with the exact and the smooth ramp
 * (Stepper's CUTS); every Stepper links the stop planned ahead's room (stop_ahead_begin, _reset). */
#include "Stepper.h"
#include "StepperGroup.h"

#include <BoardHeap.h>
#include <StepCut.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

static_assert(MOTION_STEPPER_STOP_AHEAD_CMDS >= 1 && MOTION_STEPPER_STOP_AHEAD_CMDS < MULTI_SLOTS / 2,
              "the stop planned ahead is laid out by cut_apply at once: a few commands of the ring");

/* the stop from the cruise, planned ahead (prepare_stop) from position `from`: the planner's state
 * after it and its first commands; valid for any profile whose constants, direction and cruise
 * speed are exact's (k, dir) and up */
struct Stepper::StopAhead {
    step_exact_t exact;
    /* its first commands made into the engine's slot form (MultiStepEngine::make_image): laid out at
     * the cut with no work but a copy */
    MultiStepEngine::SlotImage img[MOTION_STEPPER_STOP_AHEAD_CMDS];
    uint64_t up;
    int32_t from, pos, target;
    /* the cut's distance (us) with 1, 2, 3 axes stepping (stop_in_cruise), and twice the steps vmax
     * makes in it */
    uint16_t ahead_us[3], ahead_steps[3];
    /* the images, and the first of them that cover MOTION_STEPPER_STOP_SWITCH_US: the cut's switch puts
     * these in, adopt_cut the rest */
    uint8_t n, now, active;
    /* a cut done, its second half not yet (adopt_cut): where it landed, and the target after it */
    uint8_t pending, then;
    int32_t at, to;
    MultiStepEngine::CutTail tail;
};

static_assert(MOTION_STEPPER_CUT_CRUISE_US <= 20000UL, "the stop planned ahead keeps its cut distances in 16 bits");

/* the exact ramp's constants the same (the stop planned ahead is for them): four bytes at a time
 * (avr-libc's memcmp takes a byte at a time, 414 cycles here: once per tick for every cruising Stepper,
 * prepare_stop, and in every stop's turn) */
#if MOTION_STEPPER_CUT_US && !MULTI_TIMED_LOOP
typedef uint32_t __attribute__((may_alias)) words_t;
static_assert(sizeof(step_exact_consts_t) % 4U == 0, "the constants compared four bytes at a time");
static bool same_consts(const step_exact_consts_t &a, const step_exact_consts_t &b)
{
    const words_t *p = reinterpret_cast<const words_t *>(&a), *q = reinterpret_cast<const words_t *>(&b);
    for (uint8_t i = 0; i < sizeof a / 4U; i++)
        if (p[i] != q[i])
            return false;
    return true;
}
#endif

/* how much longer than with one Stepper at 20,000 steps/s a cut's work takes at this many steps/s of
 * all axes together, each step's interrupt taking cycles_per_step: it runs beside the step
 * interrupts, so its time grows as 1/(1 - their share of the CPU) (Stepper.h, MOTION_STEPPER_CUT_SHARE;
 * the share taken at most 0.9); 1 at or below that share */
#if !MULTI_TIMED_LOOP
static float grow_at(float steps_per_s, float cycles_per_step)
{
    float share = steps_per_s * (cycles_per_step / (float)F_CPU);
    if (share <= MOTION_STEPPER_CUT_SHARE)
        return 1.0f;
    return (1.0f - MOTION_STEPPER_CUT_SHARE) / (1.0f - (share < 0.9f ? share : 0.9f));
}
#endif

const Stepper::Cuts Stepper::CUTS = {Stepper::cuts_at, Stepper::cuts_cruise, Stepper::cuts_prepare, Stepper::cuts_adopt};

/* begin(), with the planner interrupt, after the rings: the stop planned ahead's room on the heap
 * (about 430 bytes; planned from loop(), planInLoop, only a Stepper alone takes it, at its first
 * cruise: prepare_stop; the three Steppers of a sketch that plans so keep their SRAM for the stack).
 * False: no room beside the StepperGroups' rooms (BackgroundPlanner::leaveForGroups): the Stepper
 * then plans its stop from the cruise at a cut. */
bool Stepper::stop_ahead_begin()
{
#if MOTION_STEPPER_CUT_US && !MULTI_TIMED_LOOP
    stop_ = static_cast<StopAhead *>(board_take_leaving(sizeof(StopAhead), BackgroundPlanner::groupBytes()));
    if (!stop_)
        return false;
    stop_->n = 0;
    stop_->pending = 0;
#endif
    return true;
}

void Stepper::stop_ahead_reset()
{
    stop_->n = 0;
    stop_->pending = 0;
}

/* planner interrupt, after it has laid out commands: while a Stepper cruises (its planner in the
 * cruise of an exact profile, parameters unchanged), the stop from there is planned ahead, unless
 * it is already for these constants, direction and speed. A stop from the cruise is one profile
 * wherever it starts: the planner's state after it and its commands differ only by the position
 * (checked on the host: 496 random profiles, a stop at two cruise boundaries each, natural and
 * rewound, every command the same). */
void Stepper::prepare_stop()
{
#if MOTION_STEPPER_CUT_US && !MULTI_TIMED_LOOP
    if (group_) {
        group_->plan_stop_ahead(axis_); /* (in a group's move: the group's stop, in this room) */
        return;
    }
    const step_exact_t &e = planner_.exact;
    if (planner_.algo != RAMP_ALGO_EXACT || planner_.params_new || !e.moving || e.y != 0 ||
        !(e.n > e.n1 && e.n < e.n2))
        return;
    /* planned from loop(), a Stepper alone (ExactRampStepper's console) takes its room at its first
     * cruise (about 400 bytes of the heap; MultiAxisStepper's three keep their SRAM for the stack):
     * its serial `stop` or a target behind in the cruise then cuts 450 us ahead and more with the
     * speed, not 5 ms (until 2026-12-06: 5.6 and 10.5 ms after the line at 20,000 steps/s) */
    if (!stop_ && (!BackgroundPlanner::inLoop() || BackgroundPlanner::steppers() != 1 || !stop_ahead_begin()))
        return;
    if (stop_->pending)
        return; /* (not before the cut's second half: adopt_cut, which the feed calls first) */
    if (stop_->n != 0 && stop_->up == e.up && stop_->exact.dir == e.dir && stop_->exact.max_cmd_ticks == e.max_cmd_ticks &&
        same_consts(stop_->exact.k, e.k))
        return;
    if (BackgroundPlanner::inLoop() && fabs(MultiStepEngine::speed(axis_)) > MOTION_STEPPER_CUT_MAX_SPS)
        return; /* planned from loop(): no cut that fast (stop_in_cruise), and loop() keeps its time */
    step_planner_t &s_scratch = step_cut_scratch();
    s_scratch = planner_;
    step_planner_stop(&s_scratch);
    stop_->n = 0;
    {
        /* its first MOTION_STEPPER_STOP_AHEAD_US (as step_cut_first_cmds hands them out), as images */
        const uint32_t until = (uint32_t)BackgroundPlanner::ticksPerUs() *
                               (BackgroundPlanner::steppers() >= 2 ? MOTION_STEPPER_STOP_AHEAD_US : MOTION_STEPPER_STOP_AHEAD_1_US);
        const uint32_t switch_until = (uint32_t)BackgroundPlanner::ticksPerUs() * MOTION_STEPPER_STOP_SWITCH_US;
        uint32_t ticks = 0;
        int32_t off = 0;
        uint8_t n = 0, now = 0;
        step_cmd_t c;
        while (n < MOTION_STEPPER_STOP_AHEAD_CMDS && ticks < until && step_planner_next(&s_scratch, &c)) {
            ticks += MultiStepEngine::make_image(c, stop_->img[n++], off);
            if (now == 0 && ticks >= switch_until)
                now = n;
        }
        stop_->now = now ? now : n;
        stop_->n = n;
    }
    stop_->exact = s_scratch.exact;
    stop_->up = e.up;
    stop_->from = planner_.pos;
    stop_->pos = s_scratch.pos;
    stop_->target = s_scratch.target;
    stop_->active = s_scratch.active;
    /* the cut's search and lay-out run beside the step interrupts: their time grows as 1/(1 - the
     * interrupts' share of the CPU), that share taken as this cruise's speed (vmax: planned a lead
     * before the axis gets there) on every axis stepping (counted at the stop: computed there from the
     * engine's speeds, with floats, it took 0.5 ms with three Steppers at 25,000 steps/s); an axis
     * slower than the others may miss its first try and take the next, twice as far */
    for (uint8_t n = 1; n <= 3; n++) {
        float us = MOTION_STEPPER_CUT_CRUISE_US > MOTION_STEPPER_CUT_MARGIN_US
                       ? (float)MOTION_STEPPER_CUT_MARGIN_US +
                             (float)(MOTION_STEPPER_CUT_CRUISE_US - MOTION_STEPPER_CUT_MARGIN_US) *
                                 grow_at(n * params_.vmax_sps, MOTION_STEPPER_CUT_CRUISE_STEP_CYCLES)
                       : (float)MOTION_STEPPER_CUT_CRUISE_US; /* (a test build's cut inside its margin: as it is) */
        stop_->ahead_us[n - 1] = (uint16_t)us;
        stop_->ahead_steps[n - 1] = (uint16_t)(params_.vmax_sps * us * 2e-6f) + 1U;
    }
#endif
}

/* planner interrupt: a stop in the cruise with the stop planned ahead for it: a cut
 * MOTION_STEPPER_CUT_CRUISE_US ahead (its part beyond the margin grown with the step interrupts'
 * share of the CPU: prepare_stop), in the cruise, and that stop laid out there. then: a new
 * target `to` that lies behind the cut (a reversal: lib's step_planner_move then plans that same
 * stop, and the move to `to` from rest after it); one that does not is left to plan_at_cut. False:
 * nothing changed. */
bool Stepper::stop_in_cruise(bool then, int32_t to)
{
#if MOTION_STEPPER_CUT_US && !MULTI_TIMED_LOOP
    const step_exact_t &e = planner_.exact;
    MultiStepEngine::Cut cut;
    uint32_t nb;
    int32_t dp;
    if (!stop_ || stop_->n == 0 || stop_->pending || planner_.algo != RAMP_ALGO_EXACT || planner_.params_new || e.y != 0 || e.n <= e.n1 ||
        stop_->up != e.up || stop_->exact.dir != e.dir ||
        stop_->exact.max_cmd_ticks != e.max_cmd_ticks || !same_consts(stop_->exact.k, e.k))
        return false;
    const uint32_t tpu = BackgroundPlanner::ticksPerUs();
    uint32_t ahead_us = MOTION_STEPPER_CUT_CRUISE_US, margin_us = MOTION_STEPPER_CUT_MARGIN_US;
    if (BackgroundPlanner::inLoop()) {
        /* planned from loop() (a console sketch's Stepper alone, MotionConsole::begin): no cut
         * above MOTION_STEPPER_CUT_MAX_SPS, and the margin grows with the speed as plan_at_cut's
         * (the step interrupt takes up to half the CPU there) */
        float v = fabs(MultiStepEngine::speed(axis_));
        if (v > MOTION_STEPPER_CUT_MAX_SPS)
            return false;
        uint16_t more = (uint16_t)(v * 0.015f);
        ahead_us += more;
        margin_us += more;
    } else {
        /* the search and the lay-out beside the step interrupts: with three Steppers at 25,000
         * steps/s a try took 0.8-1.2 ms, so a cut 600 us ahead came too late and the stop took
         * the second try (2.4 ms after the call); the part beyond the margin grows with the
         * interrupts' share (prepare_stop) */
        uint8_t n = 0;
        for (uint8_t i = 0; i < 3; i++)
            n = (uint8_t)(n + (MultiStepEngine::stepping(i) ? 1U : 0U));
        n = n > 0 ? n - 1U : 0U;
        ahead_us = stop_->ahead_us[n];
        /* the axis still steps its acceleration, more of it than it can step before the cut even at
         * vmax (the planner reached the cruise a lead ahead of it): the cut would land there, and
         * its search would only find that out (with three Steppers at 25,000 steps/s, the last one
         * started still accelerating at the stop: 0.44 ms lost before its own stop, plan_at_cut's) */
        uint32_t queued = (uint32_t)labs(planner_.pos - MultiStepEngine::position(axis_));
        if (queued < e.n && e.n - queued + stop_->ahead_steps[n] < e.n1)
            return false;
    }
    /* a cut the step interrupt came too close to is tried again twice as far ahead (STEP_CUT_TRIES
     * cuts in all): each try costs only the search and the lay-out, 0.4 ms or so with two Steppers
     * at 20,000 steps/s, as much as the first cut leaves it; until 2026-12-05 one miss sent the stop
     * to a plan at a 4 ms cut, which took longer than that there, and it waited for the 40 ms lead) */
    for (uint8_t k = 0;; k++) {
        step_cut_trace(true);
        if (k == STEP_CUT_TRIES ||
            MultiStepEngine::cut_find(axis_, tpu * (ahead_us << k), e.n - 1U, cut, false, true) == 0) {
            step_cut_trace(false);
            return false;
        }
        /* the kept commands end in the cruise: its last one starts there, and nothing of the
         * deceleration is kept */
        nb = e.n - cut.steps;
        /* the position at the cut */
        dp = planner_.pos + (e.dir < 0 ? (int32_t)cut.steps : -(int32_t)cut.steps);
        if (nb - cut.last_count < e.n1 || nb > e.n2 || (then && (e.dir > 0 ? to > dp : to < dp))) {
            step_cut_trace(false);
            return false; /* not in the cruise, or a target ahead of the cut (a plan of its own) */
        }
        if (MultiStepEngine::cut_apply(axis_, cut, tpu * margin_us, stop_->img, stop_->n, stop_->now, stop_->tail))
            break;
        step_cut_trace(false); /* too late */
    }
    /* the switch has come off: the rest (the engine's books and the dropped slots, the stop's other
     * commands, the planner's state after them) waits for adopt_cut, which the tick calls before it
     * lays out or plans anything (BackgroundPlanner::finishCuts): with two or three Steppers stopped at
     * once the next axis's cut comes first (the 200-byte copy alone took 1,200 cycles of every axis's
     * turn, the books some 1,400) */
    plan_from_ = dp;
    stop_->at = dp;
    stop_->then = then ? 1U : 0U;
    stop_->to = to;
    stop_->pending = 1;
    step_cut_trace(false);
    return true;
#else
    (void)then;
    (void)to;
    return false;
#endif
}

static_assert(MOTION_STEPPER_GROUP_CUT_CMDS <= STEP_CUT_MAX_CMDS, "cut_apply switches at most MULTI_CUT_MAX_CMDS commands");

/* a member's part of a group's room for its stop at a cut (StepperGroup.h): the stop's first commands
 * as slot images, the second half of the switch, a smooth planner's pointer kept aside */
struct StepperGroup::CutRoom {
    MultiStepEngine::SlotImage img[MOTION_STEPPER_GROUP_CUT_CMDS];
    MultiStepEngine::CutTail tail;
    step_smooth_t *smooth;
    bool smooth_kept;
    /* the stop from the cruise planned ahead (plan_stop_ahead): planned from ahead_from, to rest at
     * ahead_to, its first ahead_n commands in img (the cut's switch puts in ahead_now of them); the
     * cut's distance in this axis's cruise steps, and its cruise's interval (us) */
    int32_t ahead_from, ahead_to;
    uint16_t ahead_steps, ahead_iv_us;
    uint8_t ahead_n, ahead_now;
};

const uint16_t StepperGroup::CUT_ROOM_BYTES = sizeof(StepperGroup::CutRoom);

/* loop() (moveTo): the room, once, at the group's first move with the planner interrupt */
void StepperGroup::take_cut_room()
{
    if (room_ || BackgroundPlanner::inLoop())
        return;
    room_ = static_cast<CutRoom *>(board_take(n_ * sizeof(CutRoom)));
    if (room_)
        for (uint8_t j = 0; j < n_; j++)
            room_[j].smooth_kept = false;
}

/* each member's speed on the line at the move's vmax (steps/s, the master's vmax), and their sum over
 * the moving members: the step interrupts' load in the cruise */
float StepperGroup::cruise_speeds(float v[]) const
{
    float sum = 0.0f;
    for (uint8_t j = 0; j < n_; j++) {
        v[j] = coord_.profile.vmax_sps * (float)coord_.d[j] / (float)coord_.d[coord_.master];
        if (mask_ & (1U << j))
            sum += v[j];
    }
    return sum;
}

/* what the stop's commands ask of the planner beyond the stop's own duration, us (0: no more than it),
 * for a cut ahead_us ahead, the members' speeds now v[] (steps/s, not negative):
 * MOTION_STEPPER_GROUP_CMD_US (grown) for each command lib's step_exact_decel_cmds expects of every own
 * axis decelerating from its speed at the cut, less the master's time to stop from there. The master's
 * speed at the cut: now, plus its acceleration for ahead_us, at most vmax (while accelerating it still
 * grows until the cut; in the cruise it is vmax); every other axis's in proportion. */
uint32_t StepperGroup::stop_bank_us(float grow, uint32_t ahead_us, const float v[])
{
    const float a = coord_.profile.accel_sps2, vm = v[coord_.master];
    float at = vm + a * (float)ahead_us * 1.0e-6f;
    uint32_t cmds = 0;
    if (at > coord_.profile.vmax_sps)
        at = coord_.profile.vmax_sps;
    const float scale = vm > 0.0f ? at / vm : 1.0f;
    for (uint8_t j = 0; j < n_; j++)
        if (own_ & (1U << j))
            cmds += step_exact_decel_cmds(&coord_.ax[j], v[j] * scale);
    const float work_us = (float)cmds * (float)MOTION_STEPPER_GROUP_CMD_US * grow, stop_us = at / a * 1.0e6f;
    return work_us > stop_us ? (uint32_t)(work_us - stop_us) : 0U;
}

/* planner interrupt (StepperGroup::do_stop): a group's stop at a cut of its own axes' queues,
 * MOTION_STEPPER_GROUP_CUT_US ahead per axis (_SLOW_US while the speed changes; grown with the step
 * interrupts' share of the CPU) and farther by what the stop's commands ask of the planner beyond
 * their own time (stop_bank_us; a cut that would land beyond the lead is not tried), instead of after
 * the queued lead. Every own axis (a member that
 * repeats the master's commands is pulsed by its interrupt, and cut with it) is taken back to where
 * its cut lands (lib's step_coord_rewind: as if it had handed out only the kept commands), the stop
 * on the line is planned from there (step_coord_stop) and each axis's first commands, made into slot
 * images, are switched in one member after the other, each keeping the margin plus
 * MOTION_STEPPER_GROUP_SWITCH_US for every switch still to come. Each axis's state before the cut
 * waits in its member's own planner (idle while the group moves: its exact constants are converted
 * again at its next move from rest, params_new; a smooth planner's pointer is put back).
 * GROUP_CUT_DONE: done; GROUP_CUT_AGAIN: the first switch came too late, nothing changed, try again
 * twice as far ahead; GROUP_CUT_NO: nothing changed (not moving, nothing queued that far, a rewind
 * refused): the caller stops after the queued lead. Should a later member's switch come too late (not
 * seen in the checks: the margin covers the switches before it), that axis keeps its queue and stops
 * after it, towards the same point of the line (step_coord_stop's rule, from its own state). */
uint8_t StepperGroup::stop_at_cut()
{
#if MOTION_STEPPER_CUT_US && MOTION_STEPPER_GROUP_CUT_US && !MULTI_TIMED_LOOP
    MultiStepEngine::Cut cut[STEP_COORD_MAX_AXES];
    int32_t to_saved[STEP_COORD_MAX_AXES];
    uint8_t n_img[STEP_COORD_MAX_AXES];
    const uint32_t tpu = BackgroundPlanner::ticksPerUs();
    uint8_t j, count = 0, done = 0;
    ahead_ = 0; /* (cut_keep takes the members' planners) */
    if (!room_)
        return GROUP_CUT_NO; /* no room on the heap at its first move */
    for (j = 0; j < n_; j++) {
        if (!(own_ & (1U << j)))
            continue;
        if (!coord_.ax[j].moving || coord_.ax[j].n < 2U)
            return GROUP_CUT_NO;
        count++;
    }
    if (count == 0 || BackgroundPlanner::inLoop())
        return GROUP_CUT_NO;
    uint32_t ahead_us = cut_us_;
    if (ahead_us == 0) {
        float v[STEP_COORD_MAX_AXES];
        for (j = 0; j < n_; j++)
            v[j] = (own_ & (1U << j)) || j == coord_.master ? fabs(MultiStepEngine::speed(member_[j]->axis_)) : 0.0f;
        /* the master's speed changing (the cut lands in a ramp: a costlier rewind and stop, and at a
         * command's start) or not */
        const bool cruise = v[coord_.master] >= 0.98f * coord_.profile.vmax_sps;
        const uint32_t lead_us = (uint32_t)BackgroundPlanner::leadMs() * 1000UL;
        float grow = grow_at(BackgroundPlanner::stepRate(), MOTION_STEPPER_STEP_CYCLES);
        if (grow < 1.0f)
            grow = 1.0f;
        const uint32_t per_axis = cruise ? MOTION_STEPPER_GROUP_CUT_US
                                  : count >= 3U ? MOTION_STEPPER_GROUP_CUT_SLOW_3_US
                                                : MOTION_STEPPER_GROUP_CUT_SLOW_US;
        ahead_us = (uint32_t)((float)(per_axis * count) * grow);
        /* the bank for the stop's work, from the speed at this cut, then (if any) at the cut that far
         * ahead (the distance above, less the plan's own time, leaves the queues the few milliseconds
         * more that the stop's last commands, a step each, need); beyond the lead nothing is cut (and
         * no search's time lost: the stop after the lead needs all of the planner) */
        uint32_t bank = stop_bank_us(grow, ahead_us, v);
        if (bank != 0U && ahead_us + bank < lead_us) {
            const uint32_t bank2 = stop_bank_us(grow, ahead_us + bank, v);
            if (bank2 > bank)
                bank = bank2;
        }
        ahead_us += bank;
        if (ahead_us >= lead_us)
            return GROUP_CUT_NO;
    }
    BackgroundPlanner::finishCuts(); /* another Stepper's cut in the cruise: its second half first */
    BackgroundPlanner::feedBeforePlan(); /* the other queues last through the plan (before the search) */
    step_cut_trace(true);
    /* where each own axis can be cut: its first command whose first step lies that far ahead, or in
     * a cruise the first step (the exact ramp goes back to any step of its cruise) */
    for (j = 0; j < n_; j++)
        if ((own_ & (1U << j)) &&
            MultiStepEngine::cut_find(member_[j]->axis_, tpu * ahead_us, coord_.ax[j].n - 1U, cut[j], true, true) == 0) {
            step_cut_trace(false);
            return GROUP_CUT_NO;
        }
    for (j = 0; j < n_; j++) {
        to_saved[j] = coord_.to[j];
        if (own_ & (1U << j))
            cut_keep(j) = coord_.ax[j]; /* put back if the cut does not come off */
    }
    uint8_t result = GROUP_CUT_NO;
    for (j = 0; j < n_; j++) {
        if (!(own_ & (1U << j)))
            continue;
        motion_status_t st = step_coord_rewind(&coord_, j, cut[j].steps, cut[j].time16, cut[j].last_count);
        if (st != MS_OK && cut[j].split != 0 &&
            MultiStepEngine::cut_find(member_[j]->axis_, tpu * ahead_us, coord_.ax[j].n - 1U, cut[j]) != 0)
            st = step_coord_rewind(&coord_, j, cut[j].steps, cut[j].time16, cut[j].last_count);
        if (st != MS_OK)
            goto put_back;
    }
    step_coord_stop(&coord_);
    /* each own axis's first commands of the stop (MOTION_STEPPER_CUT_NEW_US of them), as slot images */
    for (j = 0; j < n_; j++) {
        if (!(own_ & (1U << j)))
            continue;
        const uint32_t until = tpu * MOTION_STEPPER_CUT_NEW_US;
        uint32_t ticks = 0;
        int32_t off = 0;
        uint8_t n = 0;
        step_cmd_t c;
        while (n < MOTION_STEPPER_GROUP_CUT_CMDS && ticks < until && step_coord_next(&coord_, j, &c)) {
            ticks += MultiStepEngine::make_image(c, room_[j].img[n++], off);
        }
        if (n == 0)
            goto put_back; /* (an axis with no step left after its cut: stopped after the lead) */
        n_img[j] = n;
    }
    /* the switches, one member after the other */
    {
        uint8_t after = count;
        for (j = 0; j < n_; j++) {
            if (!(own_ & (1U << j)))
                continue;
            after--;
            const uint32_t margin_us = MOTION_STEPPER_CUT_MARGIN_US + (uint32_t)after * MOTION_STEPPER_GROUP_SWITCH_US;
            if (MultiStepEngine::cut_apply(member_[j]->axis_, cut[j], tpu * margin_us, room_[j].img, n_img[j], n_img[j],
                                           room_[j].tail)) {
                done |= (uint8_t)(1U << j);
                continue;
            }
            if (done == 0) {
                /* too late, nothing changed: again twice as far ahead, or after the lead */
                cut_us_ = 2U * ahead_us;
                result = ++cut_tries_ < STEP_CUT_TRIES ? GROUP_CUT_AGAIN : GROUP_CUT_NO;
                goto put_back;
            }
            /* a later member too late: it keeps its queue, and stops after it towards the same point */
            step_exact_t &e = coord_.ax[j];
            e = cut_keep(j);
            if (step_exact_plan(&e, coord_.to[j]) != MS_OK)
                step_exact_stop(&e);
            coord_.to[j] = e.d > e.n ? ramp_position_after(e.pos, e.dir, e.d - e.n) : e.pos;
        }
    }
    for (j = 0; j < n_; j++)
        if (done & (1U << j))
            MultiStepEngine::cut_finish(member_[j]->axis_, room_[j].tail, room_[j].img, n_img[j]);
    cut_release();
    step_cut_trace(false);
    return GROUP_CUT_DONE;
put_back:
    for (j = 0; j < n_; j++) {
        coord_.to[j] = to_saved[j];
        if (own_ & (1U << j))
            coord_.ax[j] = cut_keep(j);
    }
    cut_release();
    step_cut_trace(false);
    return result;
#else
    return GROUP_CUT_NO;
#endif
}

/* planner interrupt, at its tick's end (Stepper::prepare_stop of each member): while the group's move
 * cruises, own member j's stop from the cruise planned ahead (as a Stepper's own, prepare_stop): its
 * first commands (up to MOTION_STEPPER_GROUP_CUT_CMDS, within MOTION_STEPPER_STOP_SWITCH_US; the
 * switch puts in those of the first MOTION_STEPPER_GROUP_NOW_US) as slot images in the group's room,
 * the state after them in the member's own planner (idle while it moves in the group, as stop_at_cut's
 * cut_keep; its constants are converted again at its next move from rest). Once per move (the group's
 * constants do not change within one); exact members only. Once every own member's is planned, the
 * cut's distance in each axis's cruise steps. */
void StepperGroup::plan_stop_ahead(uint8_t axis)
{
#if MOTION_STEPPER_CUT_US && MOTION_STEPPER_GROUP_CUT_US && !MULTI_TIMED_LOOP
    int8_t jj = index_of(axis);
    if (jj < 0 || !room_ || starting_ || stop_req_ || plan_req_ || BackgroundPlanner::inLoop())
        return;
    const uint8_t j = (uint8_t)jj, bit = (uint8_t)(1U << j);
    step_planner_t &pl = member_[j]->planner_;
    const step_exact_t &e = coord_.ax[j];
    if (!(own_ & bit) || (ahead_ & bit) || pl.algo != RAMP_ALGO_EXACT || !e.moving || e.y != 0 ||
        !(e.n > e.n1 && e.n < e.n2))
        return;
    step_exact_t &x = pl.exact;
    x = e;
    pl.params_new = 1;
    step_exact_stop(&x);
    const uint32_t until = (uint32_t)BackgroundPlanner::ticksPerUs() * MOTION_STEPPER_STOP_SWITCH_US;
    uint32_t ticks = 0;
    int32_t off = 0;
    uint8_t n = 0;
    step_cmd_t c;
    room_[j].ahead_from = e.pos;
    room_[j].ahead_to = x.d > x.n ? ramp_position_after(x.pos, x.dir, x.d - x.n) : x.pos;
    const uint32_t now_until = (uint32_t)BackgroundPlanner::ticksPerUs() * MOTION_STEPPER_GROUP_NOW_US;
    uint8_t now = 0;
    while (n < MOTION_STEPPER_GROUP_CUT_CMDS && ticks < until && step_exact_next(&x, &c)) {
        ticks += MultiStepEngine::make_image(c, room_[j].img[n++], off);
        if (now == 0 && ticks >= now_until)
            now = n;
    }
    room_[j].ahead_n = n;
    room_[j].ahead_now = now ? now : n;
    if (n == 0)
        return;
    ahead_ |= bit;
    if (ahead_ == own_) {
        /* the cut's distance (stop_in_cruise): its searches and switches run beside the step
         * interrupts, whose share of the CPU is taken at the cruise speeds of every moving member */
        float v[STEP_COORD_MAX_AXES];
        const float sum = cruise_speeds(v);
        uint8_t count = 0;
        for (uint8_t i = 0; i < n_; i++)
            if (own_ & (1U << i))
                count++;
        float grow = grow_at(sum, MOTION_STEPPER_CUT_CRUISE_STEP_CYCLES);
        if (grow < 1.0f)
            grow = 1.0f;
        uint32_t ahead_us = MOTION_STEPPER_CUT_MARGIN_US + (uint32_t)(count - 1U) * MOTION_STEPPER_GROUP_AHEAD_SWITCH_US +
                            (uint32_t)((float)(MOTION_STEPPER_GROUP_CRUISE_US * count) * grow);
        /* and farther by the bank the stop's commands need beyond their own time (stop_bank_us, as a
         * stop planned at a cut: at steep accelerations a stop is short and dense); none beyond the
         * lead (then the stop is planned at a cut) */
        const float grow_b = grow_at(sum, MOTION_STEPPER_STEP_CYCLES);
        ahead_us += stop_bank_us(grow_b < 1.0f ? 1.0f : grow_b, ahead_us, v);
        if (ahead_us >= (uint32_t)BackgroundPlanner::leadMs() * 1000UL) {
            room_[coord_.master].ahead_steps = 0; /* (stop_in_cruise: none) */
            return;
        }
        const float ahead_s = 1.0e-6f * (float)ahead_us;
        /* each own axis's cruise steps in that time, rounded up, and one more (the interrupt works out
         * the interval after the step it arms: a cut must lie an interval beyond the margin) */
        for (uint8_t i = 0; i < n_; i++) {
            room_[i].ahead_steps = (uint16_t)(ahead_s * v[i]) + 2U;
            room_[i].ahead_iv_us = v[i] > 16.0f ? (uint16_t)(1.0e6f / v[i]) + 1U : 0xFFFFU;
        }
    }
#else
    (void)axis;
#endif
}

/* planner interrupt (stop_in_cruise, stop_mirrored): the own axes' cuts switched in one member after the
 * other from the soonest on (axis j's step at[j] comes when the line's parameter is at[j] / d_j; the
 * interrupt works out the interval of the step after the one it arms, so a cut comes too late once its
 * last kept step is armed), each keeping the margin plus MOTION_STEPPER_GROUP_AHEAD_SWITCH_US for every
 * switch still to come: the first, which may come too late and then changes nothing, keeps the largest.
 * Member j's switch: its room's images, n_all[j] commands (the ring's room checked for those), the first
 * n_now[j] put in, then (every switch done) the rest of its n_room[j] images (cut_finish). Returns the
 * members switched; 0: the first came too late, nothing changed; SWITCH_NO_ROOM: a member's ring has no
 * room for its commands, nothing changed. A later member too late keeps its queue and stops after it,
 * off the line. */
uint8_t StepperGroup::switch_cuts(const MultiStepEngine::Cut cut[], const uint32_t at[], const uint8_t n_all[],
                                  const uint8_t n_now[], const uint8_t n_room[], uint8_t count)
{
#if MOTION_STEPPER_CUT_US && MOTION_STEPPER_GROUP_CUT_US && !MULTI_TIMED_LOOP
    const uint32_t tpu = BackgroundPlanner::ticksPerUs();
    uint8_t order[STEP_COORD_MAX_AXES], no = 0, done = 0, after = count, j;
    for (j = 0; j < n_; j++)
        if (own_ & (1U << j)) {
            uint8_t i = no++;
            for (; i > 0 && (uint64_t)at[order[i - 1]] * coord_.d[j] > (uint64_t)at[j] * coord_.d[order[i - 1]]; i--)
                order[i] = order[i - 1];
            order[i] = j;
        }
    /* every member's ring has room for its commands, or none is switched (a later member refused for
     * that would stop off the line; a cut farther ahead drops fewer commands: no use trying again) */
    for (uint8_t i = 0; i < no; i++)
        if (!MultiStepEngine::cut_fits(member_[order[i]]->axis_, cut[order[i]], n_all[order[i]]))
            return SWITCH_NO_ROOM;
    for (uint8_t i = 0; i < no; i++) {
        j = order[i];
        after--;
        const uint32_t margin_us = MOTION_STEPPER_CUT_MARGIN_US + (uint32_t)after * MOTION_STEPPER_GROUP_AHEAD_SWITCH_US;
        if (MultiStepEngine::cut_apply(member_[j]->axis_, cut[j], tpu * margin_us, room_[j].img, n_all[j], n_now[j],
                                       room_[j].tail)) {
            done |= (uint8_t)(1U << j);
            continue;
        }
        if (done == 0)
            return 0;
        step_exact_t &e = coord_.ax[j];
        step_exact_stop(&e);
        coord_.to[j] = e.d > e.n ? ramp_position_after(e.pos, e.dir, e.d - e.n) : e.pos;
    }
    for (j = 0; j < n_; j++)
        if (done & (1U << j))
            MultiStepEngine::cut_finish(member_[j]->axis_, room_[j].tail, room_[j].img, n_room[j]);
    return done;
#else
    (void)cut;
    (void)at;
    (void)n_all;
    (void)n_now;
    (void)n_room;
    (void)count;
    return 0;
#endif
}

/* planner interrupt (do_stop, first): a stop while the group cruises, every own member's stop from the
 * cruise planned ahead (plan_stop_ahead): nothing is planned at the cut. The point of the line where
 * all come to rest is the farthest of the own axes' soonest rests from a cut MOTION_STEPPER_GROUP_CRUISE_US
 * per own axis ahead (grown with the step interrupts' share of the CPU, plus the switches' margins and
 * an interval: plan_stop_ahead), s steps of axis f from the move's start; every own axis j is cut at
 * the step from which its own stop from the cruise ends at round(d_j s / d_f), on the line
 * (MultiStepEngine::cut_find_at), and the cuts are switched one member after the other, the soonest
 * first. The cuts land within a step's time of each other, and every axis decelerates on its own law
 * from its cruise speed (the members' speeds are in the line's ratio). A first switch too late, or a
 * cut too close at its search: again twice as far ahead (STEP_CUT_TRIES in all). GROUP_CUT_DONE, or
 * GROUP_CUT_NO (nothing changed: not planned ahead, a cut outside the cruise, every try too late): the
 * caller plans the stop at a cut. A later member's switch too late (not seen: the margins): that
 * axis keeps its queue and stops after it, off the line. With the stop's bank (plan_stop_ahead: steep
 * accelerations) the cut lies farther ahead by that much. */
uint8_t StepperGroup::stop_in_cruise()
{
#if MOTION_STEPPER_CUT_US && MOTION_STEPPER_GROUP_CUT_US && !MULTI_TIMED_LOOP
    MultiStepEngine::Cut cut[STEP_COORD_MAX_AXES];
    uint32_t kc[STEP_COORD_MAX_AXES], stop_steps[STEP_COORD_MAX_AXES];
    const uint32_t tpu = BackgroundPlanner::ticksPerUs();
    uint8_t j, count = 0;
    if (!room_ || own_ == 0 || ahead_ != own_ || room_[coord_.master].ahead_steps == 0 || BackgroundPlanner::inLoop())
        return GROUP_CUT_NO;
    for (j = 0; j < n_; j++)
        if (own_ & (1U << j)) {
            /* a member's setMaxSpeed/setAcceleration/setMinSpeed during the move writes its own
             * constants into its idle planner, where the stop planned ahead waits: then no more */
            const step_exact_t &x = member_[j]->planner_.exact;
            if (x.max_cmd_ticks != coord_.ax[j].max_cmd_ticks || !same_consts(x.k, coord_.ax[j].k)) {
                ahead_ = 0;
                return GROUP_CUT_NO;
            }
            count++;
            stop_steps[j] = ramp_distance(room_[j].ahead_from, room_[j].ahead_to);
        }
    const uint32_t search_us = MOTION_STEPPER_CUT_MARGIN_US + (uint32_t)count * MOTION_STEPPER_GROUP_AHEAD_SWITCH_US;
    BackgroundPlanner::finishCuts(); /* another Stepper's cut in the cruise: its second half first */
    for (uint8_t k = 0; k < STEP_CUT_TRIES; k++) {
        step_cut_trace(true);
        /* the point of the line where all come to rest: the farthest of the axes' soonest rests from a
         * cut ahead_us_ (2^k times that) ahead (each axis's steps made now, plus its cruise's steps in
         * that time, plus its stop's), as step_coord_stop chooses it; the others reach it from a cut
         * a little farther ahead */
        uint8_t far = 0xFF;
        uint32_t far_k = 0;
        for (j = 0; j < n_; j++) {
            if (!(own_ & (1U << j)))
                continue;
            const uint32_t r = ramp_distance(coord_.from[j], MultiStepEngine::position(member_[j]->axis_)) +
                               ((uint32_t)room_[j].ahead_steps << k) + stop_steps[j];
            if (far == 0xFF || (uint64_t)r * coord_.d[far] > (uint64_t)far_k * coord_.d[j]) {
                far = j;
                far_k = r;
            }
        }
        bool late = false, ok = true;
        for (j = 0; j < n_ && ok && !late; j++) {
            if (!(own_ & (1U << j)))
                continue;
            const step_exact_t &e = coord_.ax[j];
            const uint32_t want = j == far ? far_k : (uint32_t)(((uint64_t)coord_.d[j] * far_k + coord_.d[far] / 2U) / coord_.d[far]);
            const uint32_t made = ramp_distance(coord_.from[j], e.pos);
            kc[j] = want - stop_steps[j];
            if (want > coord_.d[j] || want < stop_steps[j] || kc[j] >= made || made - kc[j] >= e.n ||
                e.n - (made - kc[j]) <= e.n1)
                ok = false; /* (not in the cruise: planned at a cut) */
            else if (MultiStepEngine::cut_find_at(member_[j]->axis_, tpu * (search_us + room_[j].ahead_iv_us), made - kc[j], cut[j]) == 0)
                late = true; /* too close (or not in a cruise's command: the next try finds out) */
            else if (e.n - cut[j].steps - cut[j].last_count < e.n1 || e.n - cut[j].steps > e.n2)
                ok = false; /* the kept queue does not end in the cruise */
        }
        if (!ok) {
            step_cut_trace(false);
            return GROUP_CUT_NO;
        }
        if (late) {
            step_cut_trace(false);
            continue;
        }
        uint8_t n_all[STEP_COORD_MAX_AXES], n_now[STEP_COORD_MAX_AXES];
        for (j = 0; j < n_; j++)
            if (own_ & (1U << j)) {
                n_all[j] = room_[j].ahead_n;
                n_now[j] = room_[j].ahead_now;
            }
        const uint8_t done = switch_cuts(cut, kc, n_all, n_now, n_all, count);
        if (done == 0 || done == SWITCH_NO_ROOM) {
            step_cut_trace(false);
            if (done == 0)
                continue; /* too late: again farther ahead */
            return GROUP_CUT_NO;
        }
        for (j = 0; j < n_; j++) {
            if (!(done & (1U << j)))
                continue;
            step_exact_t &e = coord_.ax[j];
            const int32_t dp = ramp_position_after(coord_.from[j], e.dir, kc[j]) - room_[j].ahead_from;
            e = member_[j]->planner_.exact;
            e.pos += dp;
            coord_.to[j] = room_[j].ahead_to + dp;
        }
        ahead_ = 0;
        step_cut_trace(false);
        return GROUP_CUT_DONE;
    }
    step_cut_trace(false);
    return GROUP_CUT_NO;
#else
    return GROUP_CUT_NO;
#endif
}

/* planner interrupt (execute_plan): whether this move's stop while it accelerates may be mirrored. The
 * planner must keep up with the stop's commands beyond the reversed ones, which bank only a few
 * milliseconds: not where a stop from vmax asks more of it than its own time (stop_bank_us: steep
 * accelerations, where a stop is short and dense; three Steppers at 10,000 steps/s and 100,000 steps/s^2
 * ran dry 4-28 times a stop mirrored, 2026-12-07); nor without the room for a cut's images, with a master
 * that follows, or planned from loop(). About 1.5 ms of the AVR, once per move, and only where a stop
 * may be mirrored (a plan in loop() does without it). */
void StepperGroup::mirror_check()
{
    mirror_ = false;
#if MOTION_STEPPER_CUT_US && MOTION_STEPPER_GROUP_CUT_US && MOTION_STEPPER_CUT_MIRROR_US && MOTION_STEPPER_GROUP_MIRROR_US && \
    !MULTI_TIMED_LOOP
    if (!room_ || !(own_ & (1U << coord_.master)) || BackgroundPlanner::inLoop())
        return; /* no room for a cut's images, the master follows, or planned from loop(): none */
    float v[STEP_COORD_MAX_AXES];
    float grow = grow_at(cruise_speeds(v), MOTION_STEPPER_STEP_CYCLES);
    mirror_ = stop_bank_us(grow < 1.0f ? 1.0f : grow, 0, v) == 0U;
#endif
}

/* planner interrupt (do_stop, after stop_in_cruise): a stop while the group accelerates, as a Stepper's own
 * (step_cut_mirror): no plan before the switches. The meeting point: the master's step n_m that its
 * speed (and acceleration) reach MOTION_STEPPER_GROUP_MIRROR_US per own axis ahead (grown with the step
 * interrupts' share of the CPU), plus the switches' margins and two intervals of the slowest own axis;
 * every own axis j is cut at its step round(d_j n_m / d_m) (MultiStepEngine::cut_find_at, inside an
 * acceleration's command too), all at one point of the line within half a step. From there each axis's
 * stop is its acceleration reversed (lib's step_exact_stop_mirrored: on the law; from rest it ends at
 * 2 n_j, on the line within a step): its last commands, reversed (MultiStepEngine::cut_mirror, in the
 * cut's scratch), at least MOTION_STEPPER_GROUP_MIRROR_PLAN_US per own axis of them (grown), are switched
 * in one member after the other, the soonest cut first (the first few as slot images in the group's
 * room; the rest laid out once every switch has come off), and the rest of each stop is planned while
 * they run. A first switch too late, or a point too close at its search: again twice as far ahead
 * (STEP_CUT_TRIES in all). GROUP_CUT_DONE, or GROUP_CUT_NO (no queue changed: a move not to mirror (mirror_check),
 * not accelerating, a point outside the acceleration or at its first steps, the ring no longer holds
 * enough of it, every try too late): stop_at_cut then plans it. A later member's switch too late (not
 * seen in the sweeps: the margins) keeps that axis's queue, and it stops after it, off the line. */
uint8_t StepperGroup::stop_mirrored()
{
#if MOTION_STEPPER_CUT_US && MOTION_STEPPER_GROUP_CUT_US && MOTION_STEPPER_CUT_MIRROR_US && MOTION_STEPPER_GROUP_MIRROR_US && \
    !MULTI_TIMED_LOOP
    MultiStepEngine::Cut cut[STEP_COORD_MAX_AXES];
    /* each own axis's step where its cut lands, its reversed commands and how many of them the switch
     * puts in, their steps (and the images'), the time in the executor of those laid out */
    uint32_t nj[STEP_COORD_MAX_AXES], steps[STEP_COORD_MAX_AXES], img_steps[STEP_COORD_MAX_AXES];
    uint8_t n_all[STEP_COORD_MAX_AXES], n_img[STEP_COORD_MAX_AXES];
    int64_t t16[STEP_COORD_MAX_AXES];
    const uint32_t tpu = BackgroundPlanner::ticksPerUs();
    const uint8_t m = coord_.master;
    uint8_t j, count = 0;
    if (!mirror_ || BackgroundPlanner::inLoop())
        return GROUP_CUT_NO;
    uint32_t d_min = coord_.d[m];
    for (j = 0; j < n_; j++)
        if (own_ & (1U << j)) {
            const step_exact_t &e = coord_.ax[j];
            if (!e.moving || e.a_down || e.n1 < 8U)
                return GROUP_CUT_NO;
            if (coord_.d[j] < d_min)
                d_min = coord_.d[j];
            count++;
        }
    /* the master still accelerating (the planner may be in the cruise already, a lead ahead of it) */
    const float v = fabs(MultiStepEngine::speed(member_[m]->axis_));
    if (!(v < 0.98f * coord_.profile.vmax_sps))
        return GROUP_CUT_NO;
    /* the slowest own axis's interval, twice: the step interrupt works out the interval of the step after
     * the one it arms, so a cut comes too late once its last kept step is armed, an interval before it;
     * and an axis's point may lie half an interval before the master's (three Steppers at 10,000 steps/s:
     * without it Z's search or switch came too late at nearly every first try) */
    const float v_min = v * (float)d_min / (float)coord_.d[m];
    if (!(v_min > 100.0f))
        return GROUP_CUT_NO; /* (an interval of 10 ms or more: the cut would lie that far) */
    float grow = grow_at(BackgroundPlanner::stepRate(), MOTION_STEPPER_STEP_CYCLES);
    if (grow < 1.0f)
        grow = 1.0f;
    const uint32_t ahead_us = MOTION_STEPPER_CUT_MARGIN_US + (uint32_t)(count - 1U) * MOTION_STEPPER_GROUP_AHEAD_SWITCH_US +
                              (uint32_t)((float)(MOTION_STEPPER_GROUP_MIRROR_US * count) * grow + 2.0e6f / v_min);
    const uint32_t min_ticks = tpu * (uint32_t)((float)(MOTION_STEPPER_GROUP_MIRROR_PLAN_US * count) * grow);
    step_cmd_t *const c = step_cut_cmds();
    BackgroundPlanner::finishCuts(); /* another Stepper's cut in the cruise: its second half first */
    ahead_ = 0; /* (the images below take the room of the stop planned ahead) */
    for (uint8_t k = 0; k < STEP_CUT_TRIES; k++) {
        step_cut_trace(true);
        /* the master's step that far ahead (its queue holds the planner's steps beyond its position) */
        const step_exact_t &em = coord_.ax[m];
        const uint32_t queued = ramp_distance(MultiStepEngine::position(member_[m]->axis_), em.pos);
        if (queued >= em.n) {
            step_cut_trace(false);
            return GROUP_CUT_NO;
        }
        const float s = 1.0e-6f * (float)(ahead_us << k);
        const uint32_t n_m = em.n - queued + (uint32_t)(s * (v + 0.5f * coord_.profile.accel_sps2 * s)) + 2U;
        bool late = false;
        /* every axis's cut first (the searches), then the reversals: the last search comes sooner */
        for (j = 0; j < n_ && !late; j++) {
            if (!(own_ & (1U << j)))
                continue;
            const step_exact_t &e = coord_.ax[j];
            const uint32_t n = j == m ? n_m : (uint32_t)(((uint64_t)coord_.d[j] * n_m + coord_.d[m] / 2U) / coord_.d[m]);
            if (n >= e.n || !step_exact_mirror_ok(&e, n)) {
                step_cut_trace(false);
                return GROUP_CUT_NO; /* outside the acceleration, or at its first steps */
            }
            nj[j] = n;
            /* (searched from a quarter as far: the queue's time is reckoned from its commands' durations,
             * a few steps off either way) */
            late = MultiStepEngine::cut_find_at(member_[j]->axis_, tpu * (ahead_us << k) / 4U, e.n - n, cut[j], true) == 0;
        }
        for (j = 0; j < n_ && !late; j++) {
            if (!(own_ & (1U << j)))
                continue;
            /* its acceleration's last commands reversed: enough to plan the rest of every stop meanwhile */
            n_all[j] = MultiStepEngine::cut_mirror(member_[j]->axis_, cut[j], c, STEP_CUT_SCRATCH_CMDS, nj[j] - 2U, min_ticks,
                                                    steps[j]);
            if (n_all[j] == 0) {
                step_cut_trace(false);
                return GROUP_CUT_NO; /* the ring no longer holds that much of it */
            }
            n_img[j] = n_all[j] < MOTION_STEPPER_GROUP_CUT_CMDS ? n_all[j] : (uint8_t)MOTION_STEPPER_GROUP_CUT_CMDS;
            int32_t off = 0;
            t16[j] = 0;
            img_steps[j] = 0;
            for (uint8_t i = 0; i < n_img[j]; i++) {
                (void)MultiStepEngine::make_image(c[i], room_[j].img[i], off);
                t16[j] += step_exact_cmd_time16(&c[i]);
                img_steps[j] += c[i].count;
            }
        }
        if (late) {
            step_cut_trace(false);
            continue;
        }
        /* (the ring's room checked for all the reversed commands: the rest are laid out after the
         * switches) */
        const uint8_t done = switch_cuts(cut, nj, n_all, n_img, n_img, count);
        if (done == 0 || done == SWITCH_NO_ROOM) {
            step_cut_trace(false);
            if (done == 0)
                continue; /* too late: again farther ahead */
            return GROUP_CUT_NO;
        }
        /* the reversed commands beyond the images (the ring still holds the kept ones as they were: the
         * same again; should it not, the images' alone), their time, then the rest of each stop from there */
        for (j = 0; j < n_; j++) {
            if (!(done & (1U << j)))
                continue;
            uint32_t got;
            const uint8_t all = MultiStepEngine::cut_mirror(member_[j]->axis_, cut[j], c, STEP_CUT_SCRATCH_CMDS, nj[j] - 2U,
                                                            min_ticks, got);
            if (all != n_all[j] || got != steps[j]) {
                steps[j] = img_steps[j]; /* (not seen: nothing changes those slots meanwhile) */
                continue;
            }
            for (uint8_t i = n_img[j]; i < all; i++)
                t16[j] += step_exact_cmd_time16(&c[i]);
            for (uint8_t i = n_img[j]; i < all;) {
                uint8_t n = 0;
                int32_t off = 0;
                for (; n < MOTION_STEPPER_GROUP_CUT_CMDS && i < all; n++, i++)
                    (void)MultiStepEngine::make_image(c[i], room_[j].img[n], off);
                MultiStepEngine::append_images(member_[j]->axis_, room_[j].img, n);
            }
        }
        for (j = 0; j < n_; j++) {
            if (!(done & (1U << j)))
                continue;
            step_exact_t &e = coord_.ax[j];
            /* (not refused: step_exact_mirror_ok above, and steps <= n - 2) */
            (void)step_exact_stop_mirrored(&e, nj[j], steps[j], t16[j]);
            coord_.to[j] = e.d > e.n ? ramp_position_after(e.pos, e.dir, e.d - e.n) : e.pos;
        }
        /* the feed catches up past its commands a tick while a queue runs low, for as long as the stop
         * lasts: from the call, the cut's distance, then the master's stop (from its speed now, twice
         * that distance later: at most that long) */
        const float stop_ms = 1000.0f * v / coord_.profile.accel_sps2 + 20.0f + 2.0e-3f * (float)(ahead_us << k);
        uint8_t axes = 0;
        for (j = 0; j < n_; j++)
            if (own_ & (1U << j))
                axes |= (uint8_t)(1U << member_[j]->axis_);
        BackgroundPlanner::catchUp(stop_ms < 60000.0f ? (uint16_t)stop_ms : 60000U, axes);
        step_cut_trace(false);
        return GROUP_CUT_DONE;
    }
    step_cut_trace(false);
    return GROUP_CUT_NO;
#else
    return GROUP_CUT_NO;
#endif
}

/* where stop_at_cut keeps member j's state before its cut: its own planner's state (a union), idle
 * while it moves in the group; a smooth planner's pointer to its state is kept aside meanwhile */
step_exact_t &StepperGroup::cut_keep(uint8_t j)
{
    step_planner_t &pl = member_[j]->planner_;
    if (pl.algo == RAMP_ALGO_SMOOTH && !room_[j].smooth_kept) {
        room_[j].smooth = pl.smooth;
        room_[j].smooth_kept = true;
    }
    return pl.exact;
}

/* the members' planners again as they were, but their exact state: its constants are converted again
 * at the next move from rest (params_new) */
void StepperGroup::cut_release()
{
    for (uint8_t j = 0; j < n_; j++) {
        if (!(own_ & (1U << j)))
            continue;
        step_planner_t &pl = member_[j]->planner_;
        if (room_[j].smooth_kept) {
            pl.smooth = room_[j].smooth;
            room_[j].smooth_kept = false;
        } else if (pl.algo == RAMP_ALGO_EXACT) {
            pl.params_new = 1;
        }
    }
}

/* planner interrupt, before the tick lays out or plans anything (BackgroundPlanner::finishCuts): the
 * second half of a cut in the cruise (stop_in_cruise): the engine's books (MultiStepEngine::cut_finish),
 * the stop's commands beyond the switch's laid out, and the planner put where the stop planned ahead,
 * moved to the cut, leaves it */
void Stepper::adopt_cut()
{
#if MOTION_STEPPER_CUT_US && !MULTI_TIMED_LOOP
    if (!stop_ || !stop_->pending)
        return;
    stop_->pending = 0;
    MultiStepEngine::cut_finish(axis_, stop_->tail, stop_->img, stop_->n);
    int32_t dp = stop_->at - stop_->from;
    planner_.exact = stop_->exact;
    planner_.exact.pos += dp;
    planner_.pos = stop_->pos + dp;
    planner_.target = stop_->then ? stop_->to : stop_->target + dp;
    planner_.active = stop_->active;
    planner_.has_then = stop_->then;
    planner_.then_target = stop_->to;
#endif
}

/* planner interrupt: a stop (REQ_STOP) or a new target (REQ_MOVE) while moving, planned from where the
 * engine can cut its queue, MOTION_STEPPER_CUT_US from now: the planner goes back to where
 * the kept commands end (step_planner_rewind: bit for bit as if it had planned only those), plans the
 * stop or the move from there and hands out its first commands, which the engine lays out in place
 * of the dropped ones, if the step interrupt has not come too close to them meanwhile. True when so;
 * false when nothing changed (not stepping, nothing queued that far, parameters set since the
 * profile was planned, the planner refuses the cut, or the planning took too long): then it is
 * planned after the steps already queued, as without a cut. */
bool Stepper::plan_at_cut(uint8_t req, int32_t target)
{
#if MULTI_TIMED_LOOP
    (void)req;
    (void)target;
    return false; /* loop() makes the steps: no interrupt to cut ahead of */
#else
    static const StepCutTiming TIMING = {16, MOTION_STEPPER_CUT_US, MOTION_STEPPER_CUT_SLOW_US,
                                         MOTION_STEPPER_CUT_MARGIN_US, MOTION_STEPPER_CUT_NEW_US, MOTION_STEPPER_CUT_CMDS,
                                         MOTION_STEPPER_CUT_THEN_MIN_US, MOTION_STEPPER_SMOOTH_CUT_US,
                                         MOTION_STEPPER_CUT_MIRROR_US};
    static const StepCutTiming LOOP_TIMING = {16, MOTION_STEPPER_LOOP_CUT_US, MOTION_STEPPER_LOOP_CUT_SLOW_US,
                                              MOTION_STEPPER_CUT_MARGIN_US, MOTION_STEPPER_LOOP_CUT_NEW_US,
                                              MOTION_STEPPER_CUT_CMDS, MOTION_STEPPER_CUT_THEN_MIN_US,
                                              MOTION_STEPPER_SMOOTH_CUT_US, MOTION_STEPPER_CUT_MIRROR_US};
    StepCutTiming timing = TIMING;
    /* the other axes' cuts in the cruise this tick first get their second half (their switch put in
     * MOTION_STEPPER_STOP_SWITCH_US of their stop; this plan may take milliseconds) */
    BackgroundPlanner::finishCuts();
    if (BackgroundPlanner::inLoop()) {
        /* a Stepper alone may step up to STEPPER_MAX_SPS_EXACT there (the interrupt's, MULTI_MAX_SPS) */
        float v = fabs(MultiStepEngine::speed(axis_));
        if (v > MOTION_STEPPER_CUT_MAX_SPS) {
            cut_retry_us_ = 0;
            return false;
        }
        timing = LOOP_TIMING;
        if (timing.margin_us != 0)
            timing.margin_us = (uint16_t)(timing.margin_us + v * 0.015f);
        /* loop() may be busy elsewhere between its passes: the mirror's cut as far beyond the margin */
        timing.ahead_mirror_us = MOTION_STEPPER_CUT_MIRROR_US ? (uint16_t)(timing.margin_us + MOTION_STEPPER_CUT_MIRROR_US) : 0;
    }
    {
        /* the plan runs beside the step interrupts: with the axes fast its time grows as 1/(1 - their
         * share of the CPU), and a cut the plan cannot meet is tried again only after the next tick's
         * feed, milliseconds later (until 2026-12-06 three Steppers at 25,000 steps/s, one still
         * accelerating at the switch: its plan took 10 ms, missed the 4 ms cut, and its deceleration
         * began 55-60 ms after the switch; test/emu/ThreeSteppers, three-25k; Stepper.h) */
        float grow = grow_at(BackgroundPlanner::stepRate(), MOTION_STEPPER_STEP_CYCLES);
        if (grow > 1.0f) {
            timing.ahead_us = (uint16_t)(timing.ahead_us * grow);
            timing.ahead_slow_us = (uint16_t)(timing.ahead_slow_us * grow);
            timing.ahead_mirror_us = (uint16_t)(timing.ahead_mirror_us * grow);
        }
    }
    timing.ticks_per_us = BackgroundPlanner::ticksPerUs(); /* the timer's (setTickRate) */
    /* a stop while accelerating (or a target behind: that stop, then the move back) takes no plan
     * before its cut (with three Steppers at 25,000
     * steps/s the other queues' feeding before a plan took some 14 ms): the acceleration's last commands
     * reversed, at least MOTION_STEPPER_MIRROR_MIN_US of them, and with two or three Steppers enough to
     * outlast the other queues' feeding up to MOTION_STEPPER_PLAN_SAFE_MS, which comes next (this
     * axis's planner left as it is), then the rest of the stop planned (with three Steppers at 25,000
     * steps/s, when that plan came first, the other axes' queues, a few milliseconds after their own
     * cuts, ran dry during it) */
#if MOTION_STEPPER_CUT_MIRROR_US
    {
        StepCutMirror rest;
        /* (as the cut's distance, grown with the step interrupts' share of the CPU) */
        uint32_t min_us = MOTION_STEPPER_MIRROR_MIN_US * (uint32_t)timing.ahead_mirror_us / MOTION_STEPPER_CUT_MIRROR_US;
        if (BackgroundPlanner::steppers() >= 2 && min_us < MOTION_STEPPER_PLAN_SAFE_MS * 1000UL + 6000UL)
            min_us = MOTION_STEPPER_PLAN_SAFE_MS * 1000UL + 6000UL;
        if ((req == REQ_STOP || req == REQ_MOVE) && cut_retry_us_ == 0 &&
            step_cut_mirror(axis_, &planner_, timing, min_us, req == REQ_MOVE, target, &plan_from_, &rest)) {
            if (!BackgroundPlanner::inLoop())
                BackgroundPlanner::feedBeforePlan(axis_);
            step_cut_mirror_rest(&planner_, rest);
            return true;
        }
    }
#endif
    if (!BackgroundPlanner::inLoop())
        BackgroundPlanner::feedBeforePlan(); /* the other queues last through the plan */
    return step_cut_plan(axis_, &planner_, req == REQ_STOP, target, timing, &plan_from_, &cuts_missed_, &cut_retry_us_);
#endif
}

/* planner interrupt, after a cut that came too late (plan_at_cut: cut_retry_us_ set): true to try
 * again at the next pass (the other axes' queues fed meanwhile: a retry in the same pass kept them
 * waiting, and with two Steppers at 20,000 steps/s one ran dry), up to STEP_CUT_TRIES cuts in all;
 * false: it is planned after the queued steps now (cutsMissed() counts it when a retry was asked). */
bool Stepper::cut_again()
{
    if (cut_retry_us_ != 0 && ++cut_tries_ < STEP_CUT_TRIES)
        return true;
    if (cut_retry_us_ != 0)
        cuts_missed_++;
    cut_retry_us_ = 0;
    cut_tries_ = 0;
    return false;
}
