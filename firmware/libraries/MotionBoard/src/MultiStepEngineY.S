/* MultiStepEngineY.S - Y's step interrupt (Timer1 compare B) and its state: linked only when the
 * sketch begins Y (a Stepper on Y: multi_use_y, MultiStepEngineAxisY.cpp; MultiStepEngineIsr.inc).
 * No interrupt in timed-loop mode (only X steps there). */
#include "MultiStepEngineIsr.inc"

AXIS_STATE multi_axis_y
#if !MULTI_TIMED_LOOP
AXIS_ISR multi_step_isr_y, TIMER1_COMPB_vect, multi_axis_y, 1, _SFR_IO_ADDR(MULTI_Y_STEP_PORT), MULTI_Y_STEP_BIT, _SFR_MEM_ADDR(OCR1BL), _SFR_MEM_ADDR(OCR1BH), OCF1B, OCIE1B, multi_cold_y, MULTI_TRACE_Y_BIT, MULTI_G_OWNOFF_Y, MULTI_G_ANY_Y, 0, _SFR_IO_ADDR(GPIOR2)
#endif
