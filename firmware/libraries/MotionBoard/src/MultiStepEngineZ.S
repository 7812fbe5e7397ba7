/* MultiStepEngineZ.S - Z's step interrupt (Timer1 compare C) and its state: linked only when the
 * sketch begins Z (a Stepper on Z: multi_use_z, MultiStepEngineAxisZ.cpp; MultiStepEngineIsr.inc).
 * No interrupt in timed-loop mode (only X steps there). */
#include "MultiStepEngineIsr.inc"

AXIS_STATE multi_axis_z
#if !MULTI_TIMED_LOOP
AXIS_ISR multi_step_isr_z, TIMER1_COMPC_vect, multi_axis_z, 0, _SFR_MEM_ADDR(MULTI_Z_STEP_PORT), MULTI_Z_STEP_BIT, _SFR_MEM_ADDR(OCR1CL), _SFR_MEM_ADDR(OCR1CH), OCF1C, OCIE1C, multi_cold_z, MULTI_TRACE_Z_BIT, MULTI_G_OWNOFF_Z, MULTI_G_ANY_Z, 0, 0
#endif
