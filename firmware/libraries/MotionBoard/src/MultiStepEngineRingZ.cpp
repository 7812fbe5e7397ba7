/* MultiStepEngineRingZ.cpp - Z's ring of MULTI_SLOTS commands, registered by multi_use_z() (called
 * by MultiStepEngine::begin when the sketch begins Z among other axes): referencing its state links
 * MultiStepEngineZ.S, Z's interrupt. */
#include "MultiStepEngine.h"

extern "C" AxisState multi_axis_z; /* MultiStepEngineZ.S */

static AxisSlot s_ring_z[MULTI_SLOTS];
static uint16_t s_durations_z[MULTI_SLOTS];

void multi_use_z(void)
{
    MultiStepEngine::attach(2, multi_axis_z, s_ring_z, s_durations_z, MULTI_SLOTS);
}
