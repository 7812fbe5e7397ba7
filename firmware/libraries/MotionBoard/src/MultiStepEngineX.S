/* MultiStepEngineX.S - X's step interrupt (Timer1 compare A) and its state: linked only when the
 * sketch begins X (a Stepper on X: multi_use_x, MultiStepEngineAxisX.cpp; MultiStepEngineIsr.inc). */
#include "MultiStepEngineIsr.inc"

AXIS_STATE multi_axis_x
#if !MULTI_TIMED_LOOP
AXIS_ISR multi_step_isr_x, TIMER1_COMPA_vect, multi_axis_x, 1, _SFR_IO_ADDR(MULTI_X_STEP_PORT), MULTI_X_STEP_BIT, _SFR_MEM_ADDR(OCR1AL), _SFR_MEM_ADDR(OCR1AH), OCF1A, OCIE1A, multi_cold_x, MULTI_TRACE_X_BIT, MULTI_G_OWNOFF_X, MULTI_G_ANY_X, 1, _SFR_IO_ADDR(GPIOR1)
#endif
