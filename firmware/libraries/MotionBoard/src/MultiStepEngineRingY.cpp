/* MultiStepEngineRingY.cpp - Y's ring of MULTI_SLOTS commands, registered by multi_use_y() (called
 * by MultiStepEngine::begin when the sketch begins Y among other axes): referencing its state links
 * MultiStepEngineY.S, Y's interrupt. */
#include "MultiStepEngine.h"

extern "C" AxisState multi_axis_y; /* MultiStepEngineY.S */

static AxisSlot s_ring_y[MULTI_SLOTS];
static uint16_t s_durations_y[MULTI_SLOTS];

void multi_use_y(void)
{
    MultiStepEngine::attach(1, multi_axis_y, s_ring_y, s_durations_y, MULTI_SLOTS);
}
