/* MultiStepEngineAxisY.cpp - multi_use_y(), called by the constructor of a Stepper on Y (MotionStepper's
 * Stepper.h): it registers Y's state, and referencing it links MultiStepEngineY.S, Y's interrupt; a
 * sketch without a Stepper on Y links neither. Its ring is allocated by begin_axes. */
#include "MultiStepEngine.h"

extern "C" AxisState multi_axis_y; /* MultiStepEngineY.S */

void multi_use_y(void)
{
    MultiStepEngine::attach(1, multi_axis_y);
}
