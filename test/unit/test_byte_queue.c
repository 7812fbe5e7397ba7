/* Unit tests: byte_queue, the FIFO behind the servo sketches' non-blocking serial output
 * (README "Servo timing"). Expectations from the FIFO contract itself: bytes come out in the
 * order they went in, across the wrap of the ring; a full queue refuses (and counts) instead of
 * overwriting; room + count = capacity at every step (checked against a model queue here).
 */
#include "cmocka_all.h"

#include <string.h>

#include "byte_queue.h"

static void init_refuses_bad_storage(void **state)
{
    byte_queue_t q;
    uint8_t buf[4];
    (void)state;
    assert_int_equal(byte_queue_init(&q, NULL, 4), MS_ERR_NULL);
    assert_int_equal(byte_queue_init(NULL, buf, 4), MS_ERR_NULL);
    assert_int_equal(byte_queue_init(&q, buf, 0), MS_ERR_BUFFER_TOO_SMALL);
    assert_int_equal(byte_queue_init(&q, buf, 4), MS_OK);
    assert_int_equal(byte_queue_count(&q), 0);
    assert_int_equal(byte_queue_room(&q), 4);
}

static void full_queue_refuses_and_counts(void **state)
{
    byte_queue_t q;
    uint8_t buf[3], b = 0;
    (void)state;
    assert_int_equal(byte_queue_init(&q, buf, 3), MS_OK);
    assert_int_equal(byte_queue_put(&q, 'a'), 1);
    assert_int_equal(byte_queue_put(&q, 'b'), 1);
    assert_int_equal(byte_queue_put(&q, 'c'), 1);
    assert_int_equal(byte_queue_room(&q), 0);
    assert_int_equal(byte_queue_put(&q, 'd'), 0); /* refused: 'a' is not overwritten */
    assert_int_equal(q.dropped, 1);
    assert_int_equal(byte_queue_get(&q, &b), 1);
    assert_int_equal(b, 'a');
    assert_int_equal(byte_queue_put(&q, 'e'), 1); /* wraps to index 0 */
    assert_int_equal(byte_queue_get(&q, &b), 1);
    assert_int_equal(b, 'b');
    assert_int_equal(byte_queue_get(&q, &b), 1);
    assert_int_equal(b, 'c');
    assert_int_equal(byte_queue_get(&q, &b), 1);
    assert_int_equal(b, 'e');
    b = 0x55;
    assert_int_equal(byte_queue_get(&q, &b), 0); /* empty: b untouched */
    assert_int_equal(b, 0x55);
    assert_int_equal(q.dropped, 1);
}

/* A long pseudo-random sequence of puts and gets against a plain array model. */
static void matches_a_model_fifo_across_many_wraps(void **state)
{
    enum { CAP = 7, STEPS = 20000 };
    byte_queue_t q;
    uint8_t buf[CAP], model[STEPS];
    size_t model_head = 0, model_tail = 0, i;
    uint32_t rng = 12345u, dropped = 0;
    uint8_t next = 0;
    (void)state;
    assert_int_equal(byte_queue_init(&q, buf, CAP), MS_OK);
    for (i = 0; i < STEPS; i++) {
        rng = rng * 1103515245u + 12345u;
        if ((rng >> 16) % 3 != 0) { /* put twice as often as get: the queue fills up */
            size_t queued = model_tail - model_head;
            uint8_t ok = byte_queue_put(&q, next);
            assert_int_equal(ok, queued < CAP);
            if (ok)
                model[model_tail++] = next;
            else
                dropped++;
            next++;
        } else {
            uint8_t b = 0;
            uint8_t ok = byte_queue_get(&q, &b);
            assert_int_equal(ok, model_tail > model_head);
            if (ok)
                assert_int_equal(b, model[model_head++]);
        }
        assert_int_equal(byte_queue_count(&q), model_tail - model_head);
        assert_int_equal(byte_queue_room(&q) + byte_queue_count(&q), CAP);
    }
    assert_int_equal(q.dropped, dropped > 65535 ? 65535 : dropped);
    assert_true(dropped > 100); /* the full case really was exercised */
}

static void dropped_counter_saturates(void **state)
{
    byte_queue_t q;
    uint8_t buf[1];
    uint32_t i;
    (void)state;
    assert_int_equal(byte_queue_init(&q, buf, 1), MS_OK);
    assert_int_equal(byte_queue_put(&q, 1), 1);
    for (i = 0; i < 70000u; i++)
        assert_int_equal(byte_queue_put(&q, 2), 0);
    assert_int_equal(q.dropped, 65535);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(init_refuses_bad_storage),
        cmocka_unit_test(full_queue_refuses_and_counts),
        cmocka_unit_test(matches_a_model_fifo_across_many_wraps),
        cmocka_unit_test(dropped_counter_saturates),
    };
    return cmocka_run_group_tests_name("byte_queue", tests, NULL, NULL);
}
