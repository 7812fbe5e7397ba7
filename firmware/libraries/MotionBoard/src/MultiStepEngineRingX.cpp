/* MultiStepEngineRingX.cpp - X's ring of MULTI_SLOTS commands, registered by multi_use_x() (called
 * by MultiStepEngine::begin when the sketch begins X among other axes): referencing its state links
 * MultiStepEngineX.S, X's interrupt. */
#include "MultiStepEngine.h"

extern "C" AxisState multi_axis_x; /* MultiStepEngineX.S */

static AxisSlot s_ring_x[MULTI_SLOTS];
static uint16_t s_durations_x[MULTI_SLOTS];

void multi_use_x(void)
{
    MultiStepEngine::attach(0, multi_axis_x, s_ring_x, s_durations_x, MULTI_SLOTS);
}
