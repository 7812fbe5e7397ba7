/* Unit tests: the exact planner's commands depend on the profile alone, not on the planner's
 * history (lib/src/step_exact.c keeps the span rule's scale zfit, a function of C = 2F^2/a, from
 * one profile to the next while C stays, to make a stop cheaper on the AVR). Expected values: the
 * commands of a fresh planner given the same constants, position and plan: whatever the planner
 * did before with other constants must not show in them. */
#include "cmocka_all.h"

#include <stdio.h>
#include <string.h>

#include "step_exact.h"
#include "step_planner.h"

#include "closed_form.h" /* urand/lrand */

#define MAX_CMDS 20000U

typedef struct {
    step_cmd_t c[MAX_CMDS];
    uint32_t n;
} cmds_t;

static cmds_t got, want;

static void params(ramp_params_t *p, double vmax, double accel)
{
    p->tick_hz = 16000000UL;
    p->v0_sps = 0.0;
    p->vmax_sps = vmax;
    p->accel_sps2 = accel;
}

/* every command left, then a stop after `stop_after` commands (0: none) */
static void drain(step_planner_t *pl, cmds_t *out, uint32_t stop_after)
{
    step_cmd_t c;
    out->n = 0;
    while (out->n < MAX_CMDS && step_planner_next(pl, &c)) {
        out->c[out->n++] = c;
        if (stop_after != 0U && out->n == stop_after)
            step_planner_stop(pl);
    }
    assert_true(out->n < MAX_CMDS);
}

static void same(const cmds_t *a, const cmds_t *b, const char *what)
{
    uint32_t i;
    if (a->n != b->n)
        fail_msg("%s: %u commands, a fresh planner %u", what, (unsigned)a->n, (unsigned)b->n);
    for (i = 0; i < a->n; i++)
        if (a->c[i].rate != b->c[i].rate || a->c[i].add != b->c[i].add || a->c[i].count != b->c[i].count ||
            a->c[i].flags != b->c[i].flags)
            fail_msg("%s: command %u is (%lu %ld %u %02x), a fresh planner's (%lu %ld %u %02x)", what, (unsigned)i,
                     (unsigned long)a->c[i].rate, (long)a->c[i].add, a->c[i].count, a->c[i].flags,
                     (unsigned long)b->c[i].rate, (long)b->c[i].add, b->c[i].count, b->c[i].flags);
}

/* a move (and a stop in it) after a move and a stop at other parameters, against a fresh planner */
static void one_case(double vmax1, double accel1, double vmax2, double accel2, int32_t d1, int32_t d2, uint32_t stop1,
                     uint32_t stop2, const char *what)
{
    step_planner_t a, b;
    ramp_params_t p1, p2;
    int32_t pos;
    params(&p1, vmax1, accel1);
    params(&p2, vmax2, accel2);
    assert_int_equal(step_planner_init_trapezoid(&a, RAMP_ALGO_EXACT, &p1, 0), MS_OK);
    assert_int_equal(step_planner_move(&a, d1), MS_OK);
    drain(&a, &got, stop1);
    pos = step_planner_position(&a);
    assert_int_equal(step_planner_set_params(&a, &p2), MS_OK);
    assert_int_equal(step_planner_move(&a, pos + d2), MS_OK);
    drain(&a, &got, stop2);
    assert_int_equal(step_planner_init_trapezoid(&b, RAMP_ALGO_EXACT, &p2, pos), MS_OK);
    assert_int_equal(step_planner_move(&b, pos + d2), MS_OK);
    drain(&b, &want, stop2);
    same(&got, &want, what);
}

static void new_accel_after_a_stop(void **state)
{
    (void)state;
    /* the second move's spans are those of its own C: 50,000 -> 400,000 steps/s^2 */
    one_case(20000.0, 50000.0, 20000.0, 400000.0, 100000, 30000, 40, 0, "accel 50,000 then 400,000");
    one_case(20000.0, 400000.0, 20000.0, 50000.0, 100000, 30000, 40, 0, "accel 400,000 then 50,000");
    /* and a stop in the second move, from its cruise (the stop's spans from the new C) */
    one_case(25000.0, 50000.0, 25000.0, 300000.0, 100000, 60000, 40, 60, "a stop at the new accel");
}

static void random_histories(void **state)
{
    uint32_t i;
    char what[120];
    (void)state;
    for (i = 0; i < 200U; i++) {
        double v1 = urand(2000.0, 32000.0), a1 = lrand(5000.0, 400000.0);
        double v2 = urand(2000.0, 32000.0), a2 = lrand(5000.0, 400000.0);
        int32_t d1 = (int32_t)urand(50.0, 50000.0), d2 = (int32_t)urand(50.0, 50000.0);
        uint32_t s1 = (uint32_t)urand(0.0, 30.0), s2 = (uint32_t)urand(0.0, 30.0);
        if (urand(0.0, 1.0) < 0.5)
            d2 = -d2;
        snprintf(what, sizeof what, "case %u: %.0f/%.0f then %.0f/%.0f, %ld then %ld, stops after %u/%u", (unsigned)i,
                 v1, a1, v2, a2, (long)d1, (long)d2, (unsigned)s1, (unsigned)s2);
        one_case(v1, a1, v2, a2, d1, d2, s1, s2, what);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(new_accel_after_a_stop),
        cmocka_unit_test(random_histories),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
