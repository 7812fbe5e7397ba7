/* StepperSmooth.cpp - setRamp(RAMP_ALGO_SMOOTH): the one place that names lib's smooth planner and
 * its cut's backup (MotionBoard's StepCut.h), so that a sketch that never asks for the smooth ramp
 * links none of smooth_move (see Stepper.h). */
#include "Stepper.h"

#include <BoardHeap.h>
#include <StepCut.h>

#include <stdlib.h>

/* setRamp(RAMP_ALGO_SMOOTH): the only place that names lib's smooth planner, so that a sketch that
 * never asks for it links none of smooth_move */
motion_status_t Stepper::set_ramp_smooth()
{
    if (isRunning())
        return MS_ERR_BUSY;
    smooth_check_ = step_planner_smooth_check;
    smooth_init_ = step_planner_init_smooth;
    cuts_ = &CUTS; /* its stops and new targets cut the queue */
    smooth_jerk_ = step_planner_set_jerk;
    if (!smooth_) {
        /* checked first, so that a refusal allocates nothing */
        if (params_.vmax_sps > (float)STEPPER_MAX_SPS_SMOOTH)
            return MS_ERR_RAMP_LIMIT;
        motion_status_t st = smooth_check_(&params_, (double)jerk_);
        if (st != MS_OK)
            return st;
        /* its planner, and (once for all Steppers) the copy a cut of its queue keeps (StepCut.h), with
         * its deeper stack, all or nothing (32 bytes more: the takes below run a few frames deeper) */
        static step_smooth_t *backup;
        if (!board_reserve_stack(MOTION_STEPPER_SMOOTH_STACK, (backup ? 1U : 2U) * sizeof(step_smooth_t) + 32U))
            return MS_ERR_NO_MEMORY;
        if (!backup) {
            backup = static_cast<step_smooth_t *>(board_take(sizeof(step_smooth_t)));
            if (!backup)
                return MS_ERR_NO_MEMORY; /* no room on the heap */
            step_cut_smooth_backup(backup);
        }
        smooth_ = static_cast<step_smooth_t *>(board_take(sizeof(step_smooth_t)));
        if (!smooth_)
            return MS_ERR_NO_MEMORY; /* no room on the heap for its planner */
    }
    motion_status_t st = switch_ramp(RAMP_ALGO_SMOOTH, 0);
    if (st == MS_OK && BackgroundPlanner::leadMs() < MOTION_STEPPER_SMOOTH_LEAD_MS)
        (void)BackgroundPlanner::setLeadMs(MOTION_STEPPER_SMOOTH_LEAD_MS); /* its planner needs the bank */
    if (st == MS_OK)
        BackgroundPlanner::shareLongTicks(); /* its ticks can last long: loop() gets turns */
    return st;
}
