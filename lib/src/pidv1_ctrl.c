/* pidv1_ctrl.c - PID_v1 1.2.1 behaviour in double (pid_*) and in float (pidf_*); see pidv1_ctrl.h.
 * The body is written once in pidv1_ctrl_body.h and instantiated here for each number type. On the
 * AVR both instances are float and the linker drops the one a sketch does not call. */
#include "pidv1_ctrl.h"

#define PID_REAL double
#define PID_FN(name) pid_##name
#define PID_T pid_ctrl_t
#include "pidv1_ctrl_body.h"
#undef PID_REAL
#undef PID_FN
#undef PID_T

#define PID_REAL float
#define PID_FN(name) pidf_##name
#define PID_T pidf_ctrl_t
#include "pidv1_ctrl_body.h"
#undef PID_REAL
#undef PID_FN
#undef PID_T
