/* sim/pid_vector.h - the PID_v1 reference vectors (test/data/pid_v1/README.md):
 * load NAME.csv and its set-up NAME.json, and replay them through pidv1_ctrl in double or in float,
 * following the vectors' procedure exactly:
 *   set-up: clock := t0_ms; Input/Output/Setpoint := input0/output0/setpoint0; construct with
 *           kp, ki, kd, pon, direction; run the "setup" calls in order;
 *   per row: Input := input; Setpoint := setpoint; run the row's commands left to right;
 *           computed := Compute() at t_ms; report computed, Output and the controller state.
 * Numbers are parsed twice, with strtod and strtof, so each precision sees the correctly rounded
 * value of the decimal text (the float32/ files are written for float). Used by
 * `motionsim pid-replay` and by test/unit/test_pidv1_ctrl.c.
 *
 * Command syntax (the `command` column and the "setup" array): calls separated by ';', arguments
 * by spaces: Output:=v, SetMode(AUTOMATIC|MANUAL|n), SetTunings(Kp Ki Kd[ POn]) with POn
 * P_ON_E|P_ON_M|n, SetSampleTime(n), SetOutputLimits(min max),
 * SetControllerDirection(DIRECT|REVERSE|n). Anything else is an error naming file and line.
 */
#ifndef MOTIONSIM_PID_VECTOR_H
#define MOTIONSIM_PID_VECTOR_H

#include <stddef.h>
#include <stdint.h>

#include "pidv1_ctrl.h"

#define PV_MAX_CMDS 8

typedef struct {
    double d; /* strtod of the text */
    float f;  /* strtof of the text */
} pv_real_t;

typedef enum {
    PV_OUTPUT_SET,        /* Output:=x[0] */
    PV_SET_MODE,          /* SetMode(n) */
    PV_SET_TUNINGS,       /* SetTunings(x[0] x[1] x[2]) */
    PV_SET_TUNINGS_PON,   /* SetTunings(x[0] x[1] x[2] n) */
    PV_SET_SAMPLE_TIME,   /* SetSampleTime(n) */
    PV_SET_OUTPUT_LIMITS, /* SetOutputLimits(x[0] x[1]) */
    PV_SET_DIRECTION      /* SetControllerDirection(n) */
} pv_op_t;

typedef struct {
    pv_op_t op;
    pv_real_t x[3];
    int32_t n;
} pv_cmd_t;

typedef struct {
    uint32_t t_ms;
    pv_real_t input, setpoint;
    size_t n_cmds;
    pv_cmd_t cmds[PV_MAX_CMDS];
} pv_row_t;

typedef struct {
    /* set-up (NAME.json) */
    pv_real_t kp, ki, kd, input0, output0, setpoint0;
    int32_t pon, direction;
    uint32_t t0_ms;
    int32_t clock_bits;
    size_t n_setup;
    pv_cmd_t setup[PV_MAX_CMDS];
    char json_path[1024];
    /* rows (NAME.csv) */
    size_t n_rows;
    pv_row_t *rows;
    size_t n_cols;
    char **header;  /* n_cols names */
    char **cells;   /* n_rows x n_cols raw texts, row-major */
    char **lines;   /* the CSV's lines (sim/csv_read), which the names and cells point into */
    size_t n_lines;
} pv_vector_t;

/* Loads csv_path and the .json beside it (NAME.json in the same folder, or in the parent folder
 * when the CSV is in a float32/ folder). Returns 0, or -1 with one line in err (v is then empty).
 * A set-up with a negative kp, ki or kd is refused: PID_v1's constructor ignores such tunings and
 * leaves its working gains uninitialised (reference README, "Construction"). */
int pv_load(pv_vector_t *v, const char *csv_path, char *err, size_t err_n);
void pv_free(pv_vector_t *v);

/* The raw text of column col in row r (without the header line), or NULL without that column. */
const char *pv_cell(const pv_vector_t *v, size_t r, const char *col);

/* Replays every row; fn is called after each row's Compute(). Returns the constructor's status
 * (pid_init); anything but MS_OK means nothing was replayed. pv_load already refuses the one case
 * PID_v1's constructor rejects (a negative gain), so MS_OK is expected. */
typedef void (*pv_row_fn_double)(void *user, size_t row, int computed, double output, const pid_ctrl_t *c);
typedef void (*pv_row_fn_float)(void *user, size_t row, int computed, float output, const pidf_ctrl_t *c);
motion_status_t pv_replay_double(const pv_vector_t *v, pv_row_fn_double fn, void *user);
motion_status_t pv_replay_float(const pv_vector_t *v, pv_row_fn_float fn, void *user);

#endif
