/* MultiStepEngineAxisZ.cpp - multi_use_z(), called by the constructor of a Stepper on Z (MotionStepper's
 * Stepper.h): it registers Z's state, and referencing it links MultiStepEngineZ.S, Z's interrupt; a
 * sketch without a Stepper on Z links neither. Its ring is allocated by begin_axes. */
#include "MultiStepEngine.h"

extern "C" AxisState multi_axis_z; /* MultiStepEngineZ.S */

void multi_use_z(void)
{
    MultiStepEngine::attach(2, multi_axis_z);
}
