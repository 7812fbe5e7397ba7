/* pid_v1_avr.c - replays the PID_v1 float32 reference vectors through lib's PID module, built by
 * avr-gcc for the ATmega2560 (where double is float, so pid_* is what the Mega runs), and reports
 * every row that differs from the vector bit for bit. Runs in the emulator (build/motionemu):
 * test/emu/checks_pid.py starts it and reads its serial lines.
 *
 * The tables (build/emu/pid_vectors.h) come from test/emu/pid_avr/gen_pid_vectors.py; the module
 * is lib/src/pidv1_ctrl.c (tools/emu/emu.mk).
 * Replay, as sim/pid_vector.c does on the host: construct with the set-up, run its calls; per row
 * Input := input, Setpoint := setpoint, the row's calls left to right, computed := Compute(t_ms);
 * then computed, mode, last_time_ms and the float columns are compared.
 *
 * Serial (UART0 at 2 Mbaud, 8N1): "READY pid_v1_avr", one "MISMATCH ..." line per differing value
 * (the first 40), "VECTOR <name> rows=<n> values=<n> mismatches=<n>" per vector and
 * "DONE rows=<n> values=<n> mismatches=<n>".
 */
#include <avr/io.h>
#include <avr/pgmspace.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "avr_uart.h"
#include "pidv1_ctrl.h"
#include "pid_vectors.h"

static float f_of(uint32_t bits)
{
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

static uint32_t bits_of(float f)
{
    uint32_t b;
    memcpy(&b, &f, sizeof b);
    return b;
}

static uint32_t mismatches, values;
static char line[96];

static void mismatch(const char *vec, uint16_t row, uint32_t t_ms, const char *col, uint32_t want, uint32_t got)
{
    if (mismatches++ < 40) {
        snprintf(line, sizeof line, "MISMATCH %s row %u t_ms=%lu %s want 0x%08lx got 0x%08lx", vec, row,
                 (unsigned long)t_ms, col, (unsigned long)want, (unsigned long)got);
        println(line);
    }
}

static void apply(pid_ctrl_t *c, double *out, uint16_t index)
{
    pv_cmd_t k;
    memcpy_PF(&k, pgm_get_far_address(pv_cmds) + (uint32_t)index * sizeof k, sizeof k);
    switch (k.op) {
    case PV_OUTPUT_SET: *out = f_of(k.x[0]); break;
    case PV_SET_MODE: pid_set_mode(c, k.n); break;
    case PV_SET_TUNINGS: (void)pid_set_tunings(c, f_of(k.x[0]), f_of(k.x[1]), f_of(k.x[2])); break;
    case PV_SET_TUNINGS_PON: (void)pid_set_tunings_pon(c, f_of(k.x[0]), f_of(k.x[1]), f_of(k.x[2]), k.n); break;
    case PV_SET_SAMPLE_TIME: (void)pid_set_sample_time(c, k.n); break;
    case PV_SET_OUTPUT_LIMITS: (void)pid_set_output_limits(c, f_of(k.x[0]), f_of(k.x[1])); break;
    case PV_SET_DIRECTION: pid_set_direction(c, k.n); break;
    default: println("ERR unknown command in the table"); break;
    }
}

static void replay(uint8_t vi, uint32_t *rows_done)
{
    pv_vec_t v;
    pid_ctrl_t c;
    double in, out, sp;
    uint32_t mism0 = mismatches, values0 = values;
    uint16_t i, k;
    memcpy_PF(&v, pgm_get_far_address(pv_vecs) + (uint32_t)vi * sizeof v, sizeof v);
    in = f_of(v.input0);
    out = f_of(v.output0);
    sp = f_of(v.setpoint0);
    (void)pid_init(&c, &in, &out, &sp, f_of(v.kp), f_of(v.ki), f_of(v.kd), v.pon, v.direction, v.t0_ms);
    for (k = 0; k < v.n_setup; k++)
        apply(&c, &out, (uint16_t)(v.setup_first + k));
    for (i = 0; i < v.n_rows; i++) {
        pv_row_t r;
        uint8_t computed;
        double got[PV_N_REAL];
        memcpy_PF(&r, pv_row_addr(vi, i), sizeof r);
        in = f_of(r.input);
        sp = f_of(r.setpoint);
        for (k = 0; k < r.n_cmds; k++)
            apply(&c, &out, (uint16_t)(r.cmd_first + k));
        computed = pid_compute(&c, r.t_ms);
        /* row numbers as in the CSV file (its line 2 is row 1) */
        values += 3;
        if (computed != r.computed)
            mismatch(v.name, (uint16_t)(i + 1), r.t_ms, "computed", r.computed, computed);
        if ((uint8_t)pid_get_mode(&c) != r.mode)
            mismatch(v.name, (uint16_t)(i + 1), r.t_ms, "mode", r.mode, (uint32_t)pid_get_mode(&c));
        if (c.last_time_ms != r.last_time_ms)
            mismatch(v.name, (uint16_t)(i + 1), r.t_ms, "last_time_ms", r.last_time_ms, c.last_time_ms);
        got[0] = out;
        got[1] = c.output_sum;
        got[2] = c.last_input;
        got[3] = c.kp;
        got[4] = c.ki;
        got[5] = c.kd;
        for (k = 0; k < PV_N_REAL; k++) {
            if (!(r.have & (1U << k)))
                continue;
            values++;
            if (bits_of(got[k]) != r.expect[k])
                mismatch(v.name, (uint16_t)(i + 1), r.t_ms, pv_real_names[k], r.expect[k], bits_of(got[k]));
        }
        (*rows_done)++;
    }
    snprintf(line, sizeof line, "VECTOR %s rows=%u values=%lu mismatches=%lu", v.name, v.n_rows,
             (unsigned long)(values - values0), (unsigned long)(mismatches - mism0));
    println(line);
}

int main(void)
{
    uint32_t rows = 0;
    uint8_t vi;
    /* double must be the 32-bit float here, or this would not test what the Mega runs */
    typedef char double_is_float[sizeof(double) == sizeof(float) ? 1 : -1];
    (void)sizeof(double_is_float);
    UCSR0A = _BV(U2X0);
    UBRR0 = 0; /* 2 Mbaud: 16 MHz / (8 * 1) */
    UCSR0C = _BV(UCSZ01) | _BV(UCSZ00);
    UCSR0B = _BV(TXEN0);
    println("READY pid_v1_avr");
    for (vi = 0; vi < PV_N_VECTORS; vi++)
        replay(vi, &rows);
    snprintf(line, sizeof line, "DONE rows=%lu values=%lu mismatches=%lu", (unsigned long)rows, (unsigned long)values,
             (unsigned long)mismatches);
    println(line);
    for (;;)
        ;
}
