/* MultiStepEngineAxisX.cpp - multi_use_x(), called by the constructor of a Stepper on X (MotionStepper's
 * Stepper.h): it registers X's state, and referencing it links MultiStepEngineX.S, X's interrupt; a
 * sketch without a Stepper on X links neither. Its ring is allocated by begin_axes. */
#include "MultiStepEngine.h"

extern "C" AxisState multi_axis_x; /* MultiStepEngineX.S */

void multi_use_x(void)
{
    MultiStepEngine::attach(0, multi_axis_x);
}
