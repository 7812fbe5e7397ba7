/* StepperGroup.cpp - coordinated straight-line moves of 2-3 Steppers (see StepperGroup.h), on
 * MultiStepEngine as the MultiAxisStepper console does them: each member's part of the plan
 * (step_coord_t) is its command source; a member moving as far as the master follows the master's
 * interrupt; the own axes start on one tick (start_together). State shared with the planner
 * interrupt changes under a PlannerLock. Positions and targets here are the engine's. */
#include "StepperGroup.h"

#include "BackgroundPlanner.h"
#include "Stepper.h"

StepperGroup::StepperGroup(Stepper &a, Stepper &b)
    : n_(2), mask_(0), own_(0), ended_(0), ahead_(0), mirror_(false), starting_(false), done_(false), plan_req_(false), stop_req_(false),
      cut_tries_(0), cut_us_(0), cuts_missed_(0), room_(0), last_status_(MS_OK)
{
    member_[0] = &a;
    member_[1] = &b;
    member_[2] = 0;
    BackgroundPlanner::leaveForGroups((uint16_t)(2U * CUT_ROOM_BYTES));
}

StepperGroup::StepperGroup(Stepper &a, Stepper &b, Stepper &c)
    : n_(3), mask_(0), own_(0), ended_(0), ahead_(0), mirror_(false), starting_(false), done_(false), plan_req_(false), stop_req_(false),
      cut_tries_(0), cut_us_(0), cuts_missed_(0), room_(0), last_status_(MS_OK)
{
    member_[0] = &a;
    member_[1] = &b;
    member_[2] = &c;
    BackgroundPlanner::leaveForGroups((uint16_t)(3U * CUT_ROOM_BYTES));
}

int8_t StepperGroup::index_of(uint8_t axis) const
{
    for (uint8_t j = 0; j < n_; j++)
        if (member_[j]->axis_ == axis)
            return (int8_t)j;
    return -1;
}

uint8_t StepperGroup::coord_next(void *ctx, step_cmd_t *c)
{
    Ref *r = static_cast<Ref *>(ctx);
    if (r->repeats != 0xFF)
        return 0; /* it follows another member's interrupt: no commands of its own */
    return step_coord_next(&r->group->coord_, r->j, c);
}

uint8_t StepperGroup::coord_busy(void *ctx)
{
    Ref *r = static_cast<Ref *>(ctx);
    return step_coord_busy(&r->group->coord_, r->repeats != 0xFF ? r->repeats : r->j);
}

AxisSource StepperGroup::source_of(uint8_t axis)
{
    AxisSource s;
    int8_t j = index_of(axis);
    s.next = coord_next;
    s.busy = coord_busy;
    s.ctx = &ref_[j < 0 ? 0 : j];
    return s;
}

motion_status_t StepperGroup::moveTo(long a, long b)
{
    long t[2] = {a, b};
    return move_all(t, 3U);
}

motion_status_t StepperGroup::moveTo(long a, long b, long c)
{
    long t[3] = {a, b, c};
    if (n_ < 3)
        return MS_ERR_OUT_OF_RANGE;
    return move_all(t, 7U);
}

motion_status_t StepperGroup::move_members(const long *targets, uint8_t members)
{
    if (members == 0 || members >= (1U << n_))
        return MS_ERR_OUT_OF_RANGE;
    return move_all(targets, members);
}

/* loop(): the checks and the request; the plan (milliseconds per axis) is made by the planner
 * interrupt (execute_plan) */
motion_status_t StepperGroup::move_all(const long *targets, uint8_t members)
{
    uint8_t mask = 0;
    if (mask_ != 0)
        return MS_ERR_BUSY; /* a move of the group under way (its members may be elsewhere) */
    for (uint8_t j = 0; j < n_; j++) {
        if (!member_[j]->begun_)
            return MS_ERR_NOT_BEGUN;
        for (uint8_t k = 0; k < j; k++)
            if (member_[k]->axis_ == member_[j]->axis_)
                return MS_ERR_BUSY; /* the same axis twice */
    }
    take_cut_room(); /* (the heap, once: loop()'s) */
    PlannerLock lock;
    for (uint8_t j = 0; j < n_; j++) {
        Stepper &s = *member_[j];
        int32_t from;
        if (!(members & (1U << j)))
            continue; /* not in this move: it may move alone */
        if (s.isRunning())
            return MS_ERR_BUSY;
        if (!s.reachable(targets[j]))
            return MS_ERR_OUT_OF_RANGE; /* (Stepper::moveTo's rule) */
        from = MultiStepEngine::position(s.axis_);
        req_to_[j] = s.to_engine(targets[j]);
        if (req_to_[j] != from)
            mask |= (uint8_t)(1U << j);
    }
    done_ = false;
    if (mask == 0) {
        /* every member is there already: nothing moves, and the move is done at once */
        done_ = true;
        last_status_ = MS_OK;
        return MS_OK;
    }
    for (uint8_t j = 0; j < n_; j++) {
        ref_[j].repeats = 0xFF;
        ref_[j].clones = 0;
        if (!(mask & (1U << j)))
            continue;
        Stepper &s = *member_[j];
        s.has_next_ = false;
        s.done_ = false;
        if (s.auto_disable_)
            s.write_enable(true);
        s.group_ = this;
    }
    own_ = 0;
    starting_ = false;
    mask_ = mask;
    plan_req_ = true;
    return MS_OK;
}

/* the moving members back on their own, nothing moved (a plan refused, or a stop before it ran) */
void StepperGroup::release()
{
    for (uint8_t j = 0; j < n_; j++) {
        Stepper &s = *member_[j];
        if (!(mask_ & (1U << j)))
            continue;
        s.group_ = 0;
        if (s.auto_disable_)
            s.write_enable(false);
    }
    mask_ = 0;
    own_ = 0;
    plan_req_ = false;
    starting_ = false;
    done_ = true;
}

/* planner interrupt: loop()'s requests */
void StepperGroup::run_request()
{
    if (plan_req_) {
        plan_req_ = false;
        execute_plan();
    }
    if (stop_req_) {
        stop_req_ = false;
        do_stop();
    }
}

void StepperGroup::execute_plan()
{
    int32_t from[STEP_COORD_MAX_AXES];
    ramp_params_t p[STEP_COORD_MAX_AXES];
    uint8_t mask = mask_;
    motion_status_t st;
    for (uint8_t j = 0; j < n_; j++) {
        from[j] = MultiStepEngine::position(member_[j]->axis_);
        p[j] = member_[j]->params_;
        if (!(mask & (1U << j)))
            req_to_[j] = from[j]; /* not in the move (it may be moving alone): no step, no limit */
    }
    st = step_coord_plan(&coord_, n_, p, from, req_to_);
    last_status_ = st;
    if (st != MS_OK) {
        release();
        return;
    }
    ended_ = 0;
    ahead_ = 0;
    for (uint8_t j = 0; j < n_; j++) {
        uint8_t m = coord_.master;
        ref_[j].group = this;
        ref_[j].j = j;
        ref_[j].repeats = (j != m && (mask & (1U << j)) && coord_.d[j] == coord_.d[m]) ? m : 0xFF;
        ref_[j].clones = 0;
        end_[j] = from[j];
    }
    for (uint8_t j = 0; j < n_; j++)
        if (ref_[j].repeats != 0xFF)
            ref_[ref_[j].repeats].clones |= (uint8_t)(1U << j);
    own_ = 0;
    for (uint8_t j = 0; j < n_; j++)
        if ((mask & (1U << j)) && ref_[j].repeats == 0xFF)
            own_ |= (uint8_t)(1U << j);
    mirror_check();
    /* (while this move's stop may be mirrored: its reversed commands kept in the rings) */
    const uint8_t keep = mirror_ ? (uint8_t)MOTION_STEPPER_GROUP_MIRROR_KEEP : 0U;
    for (uint8_t j = 0; j < n_; j++) {
        Stepper &s = *member_[j];
        if (!(mask & (1U << j)))
            continue;
        if (ref_[j].repeats != 0xFF)
            MultiStepEngine::follow(member_[ref_[j].repeats]->axis_, s.axis_, req_to_[j] > from[j]);
        else
            MultiStepEngine::open_move(s.axis_, true, keep);
    }
    starting_ = true;
}

/* planner interrupt: start the own axes together once each has its first commands */
void StepperGroup::poll_start()
{
    uint8_t axes = 0;
    if (!starting_)
        return;
    for (uint8_t j = 0; j < n_; j++) {
        if (!(own_ & (1U << j)))
            continue;
        if (!MultiStepEngine::ready_to_start(member_[j]->axis_, source_of(member_[j]->axis_)))
            return;
        axes |= (uint8_t)(1U << member_[j]->axis_);
    }
    MultiStepEngine::start_together(axes);
    starting_ = false;
}

int32_t StepperGroup::follower_position(uint8_t j, int32_t master_pos)
{
    uint8_t m = ref_[j].repeats;
    int32_t k = master_pos - coord_.from[m];
    if (k < 0)
        k = -k;
    return coord_.to[j] < coord_.from[j] ? coord_.from[j] - k : coord_.from[j] + k;
}

/* planner interrupt (or a stop from loop()): an own axis's part has ended at position */
void StepperGroup::axis_done(uint8_t axis, int32_t position)
{
    int8_t j = index_of(axis);
    if (j < 0)
        return;
    end_[j] = position;
    ended_ |= (uint8_t)(1U << j);
    for (uint8_t i = 0; i < n_; i++) {
        if (ref_[j].clones & (1U << i)) {
            /* its followers made as many steps, each in its own direction */
            end_[i] = follower_position(i, position);
            MultiStepEngine::set_rest_position(member_[i]->axis_, end_[i]);
            ended_ |= (uint8_t)(1U << i);
        }
    }
    if (ref_[j].clones)
        MultiStepEngine::unfollow(axis);
    if ((ended_ & mask_) != mask_)
        return;
    for (uint8_t i = 0; i < n_; i++) {
        Stepper &s = *member_[i];
        if (!(mask_ & (1U << i)))
            continue;
        step_planner_halt(&s.planner_, end_[i]); /* at rest there, alone again */
        s.group_ = 0;
        s.record_done(end_[i]);
        ref_[i].repeats = 0xFF;
        ref_[i].clones = 0;
    }
    mask_ = 0;
    own_ = 0;
    starting_ = false;
    done_ = true;
}

/* MS_ERR_NOT_BEGUN until every member's begin(), as a Stepper's stop() and forceStop() */
motion_status_t StepperGroup::begun() const
{
    for (uint8_t j = 0; j < n_; j++)
        if (!member_[j]->begun_)
            return MS_ERR_NOT_BEGUN;
    return MS_OK;
}

motion_status_t StepperGroup::stop()
{
    if (begun() != MS_OK)
        return MS_ERR_NOT_BEGUN;
    PlannerLock lock;
    if (mask_ == 0)
        return MS_OK;
    if (plan_req_) {
        release(); /* not planned yet: nothing moves */
        return MS_OK;
    }
    stop_req_ = true; /* a replan of every axis: the planner interrupt makes it */
    cut_tries_ = 0;
    cut_us_ = 0;
    BackgroundPlanner::kick(); /* within microseconds, not at the next tick (Stepper::stop's lock defers it) */
    return MS_OK;
}

/* planner interrupt */
void StepperGroup::do_stop()
{
    if (mask_ == 0)
        return;
    if (starting_) {
        /* not started yet: nothing has stepped, stand still */
        for (uint8_t j = 0; j < n_; j++)
            if (own_ & (1U << j)) {
                uint8_t a = member_[j]->axis_;
                MultiStepEngine::halt(a);
                step_coord_halt(&coord_, j, MultiStepEngine::position(a));
            }
        starting_ = false;
        return;
    }
    uint8_t m = coord_.master;
    bool back[STEP_COORD_MAX_AXES];
    for (uint8_t j = 0; j < n_; j++)
        back[j] = coord_.to[j] < coord_.from[j];
    /* in the cruise, the stop planned ahead at a cut a few milliseconds ahead (farther by the stop's
     * bank at steep accelerations); while accelerating, the acceleration's last commands reversed at a
     * cut a few milliseconds ahead (stop_mirrored); else at a cut of the queues some milliseconds ahead
     * per axis, planned there (StepperCut.cpp); or after the queued lead */
    uint8_t cut = cut_us_ == 0 ? stop_in_cruise() : (uint8_t)GROUP_CUT_NO;
    if (cut != GROUP_CUT_DONE && cut_us_ == 0)
        cut = stop_mirrored();
    if (cut != GROUP_CUT_DONE)
        cut = stop_at_cut();
    if (cut == GROUP_CUT_AGAIN) {
        stop_req_ = true; /* farther ahead, at the next request pass */
        return;
    }
    if (cut == GROUP_CUT_NO) {
        step_coord_stop(&coord_);
        cuts_missed_++;
    }
    /* a follower stops with its master, as far */
    for (uint8_t j = 0; j < n_; j++) {
        if (ref_[j].repeats == m) {
            int32_t k = coord_.to[m] - coord_.from[m];
            if (k < 0)
                k = -k;
            coord_.to[j] = back[j] ? coord_.from[j] - k : coord_.from[j] + k;
        }
    }
}

motion_status_t StepperGroup::forceStop()
{
    if (begun() != MS_OK)
        return MS_ERR_NOT_BEGUN;
    PlannerLock lock;
    if (mask_ == 0)
        return MS_OK;
    stop_req_ = false;
    if (plan_req_) {
        release();
        return MS_OK;
    }
    for (uint8_t j = 0; j < n_; j++) {
        if (!(own_ & (1U << j)))
            continue;
        uint8_t a = member_[j]->axis_;
        MultiStepEngine::halt(a); /* each end is collected by the planner interrupt */
        step_coord_halt(&coord_, j, MultiStepEngine::position(a));
    }
    starting_ = false;
    return MS_OK;
}

bool StepperGroup::isRunning() const
{
    return mask_ != 0; /* one byte: polling needs no lock */
}

bool StepperGroup::takeDone()
{
    if (!done_)
        return false;
    PlannerLock lock;
    if (!done_)
        return false;
    done_ = false;
    return true;
}

int32_t StepperGroup::position_of(uint8_t axis)
{
    int8_t j = index_of(axis);
    if (j >= 0 && ref_[j].repeats != 0xFF)
        return follower_position((uint8_t)j, MultiStepEngine::position(member_[ref_[j].repeats]->axis_));
    return MultiStepEngine::position(axis);
}

int32_t StepperGroup::target_of(uint8_t axis)
{
    int8_t j = index_of(axis);
    if (j < 0)
        return MultiStepEngine::position(axis);
    return plan_req_ ? req_to_[j] : step_coord_target(&coord_, (uint8_t)j);
}

/* the engine axis whose interrupt steps this member, and whether its direction is the opposite */
uint8_t StepperGroup::interrupt_of(uint8_t axis, bool &flip)
{
    int8_t j = index_of(axis);
    flip = false;
    if (j < 0 || ref_[j].repeats == 0xFF)
        return axis;
    uint8_t m = ref_[j].repeats;
    flip = (coord_.to[j] < coord_.from[j]) != (coord_.to[m] < coord_.from[m]);
    return member_[m]->axis_;
}
