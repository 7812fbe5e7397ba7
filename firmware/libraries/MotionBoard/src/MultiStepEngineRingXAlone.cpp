/* MultiStepEngineRingXAlone.cpp - X's ring when X is the only axis the sketch begins (the one-axis
 * sketches: MultiStepEngine::begin(tick_hz, MULTI_AXIS_X)), MULTI_X_ALONE_SLOTS commands deep, as
 * StepEngine's was: the Leib planner makes about one command per step and banks 200 ms. */
#include "MultiStepEngine.h"

extern "C" AxisState multi_axis_x; /* MultiStepEngineX.S */

static_assert(MULTI_X_ALONE_SLOTS >= 3 && MULTI_X_ALONE_SLOTS <= 255, "ring indices are bytes");
static AxisSlot s_ring_x_alone[MULTI_X_ALONE_SLOTS];
static uint16_t s_durations_x_alone[MULTI_X_ALONE_SLOTS];

void multi_use_x_alone(void)
{
    MultiStepEngine::attach(0, multi_axis_x, s_ring_x_alone, s_durations_x_alone, MULTI_X_ALONE_SLOTS);
}
