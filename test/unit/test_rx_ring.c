/* Unit tests: rx_ring, the serial input with exact loss accounting (docs/serial.md, "Input
 * overrun"). The oracle is the host's side: the lines it sent. A reader that follows the
 * documented rules (execute a complete line read intact; on a loss, drop the line in progress and,
 * when told, the rest of the line that goes on) must never execute a line the host did not send
 * whole, and every line sent must be either executed or counted in a loss report:
 *     executed + sum(loss.lines) = lines sent   (no blank lines sent, so the count is exact).
 */
#include "cmocka_all.h"

#include <stdlib.h>
#include <string.h>

#include "rx_ring.h"

#define MAX_LINES 4000
#define LINE_MAX 24

typedef struct {
    char sent[MAX_LINES][LINE_MAX + 1];
    uint32_t n_sent;
    uint32_t next_match; /* executed lines must be sent lines, in order */
    uint32_t executed;
    uint32_t lost_lines;
    uint32_t losses;
    char line[64];
    uint32_t len;
    int discarding; /* the rest of a damaged line */
    int after_cr;
} reader_t;

static void execute(reader_t *rd)
{
    uint32_t i;
    rd->line[rd->len] = '\0';
    for (i = rd->next_match; i < rd->n_sent; i++)
        if (strcmp(rd->sent[i], rd->line) == 0)
            break;
    if (i == rd->n_sent)
        fail_msg("executed a line never sent whole: '%s'", rd->line);
    rd->next_match = i + 1U;
    rd->executed++;
}

/* the documented reader: complete lines, CR, LF or CR LF */
static void reader_take(reader_t *rd, rx_event_t ev, uint8_t b, const rx_loss_t *loss)
{
    if (ev == RX_LOSS) {
        rd->losses++;
        rd->lost_lines += loss->lines;
        rd->len = 0; /* the line in progress is one of loss->lines */
        rd->discarding = loss->cont;
        rd->after_cr = loss->after_cr;
        return;
    }
    if (b == '\n' && rd->after_cr) {
        rd->after_cr = 0;
        return;
    }
    rd->after_cr = (b == '\r');
    if (b == '\r' || b == '\n') {
        if (!rd->discarding)
            execute(rd);
        rd->discarding = 0;
        rd->len = 0;
        return;
    }
    if (!rd->discarding) {
        assert_true(rd->len < sizeof rd->line - 1U);
        rd->line[rd->len++] = (char)b;
    }
}

static const char *const ENDS[] = {"\r\n", "\n", "\r"};

/* n lines of random printable words (never blank), random line ends; the producer puts bytes in
 * bursts and the consumer takes fewer on average, so the ring overflows again and again */
static void flood_case(unsigned seed, uint32_t n, int put_burst, int get_burst)
{
    static reader_t rd;
    rx_ring_t r;
    char stream[MAX_LINES * (LINE_MAX + 2)];
    uint32_t len = 0, pos = 0, i;
    srand(seed);
    memset(&rd, 0, sizeof rd);
    rx_ring_init(&r);
    for (i = 0; i < n; i++) {
        uint32_t l = 1U + (uint32_t)rand() % LINE_MAX, j;
        const char *e = ENDS[rand() % 3];
        for (j = 0; j < l; j++)
            rd.sent[i][j] = (char)('!' + rand() % 94);
        rd.sent[i][l] = '\0';
        memcpy(stream + len, rd.sent[i], l);
        len += l;
        memcpy(stream + len, e, strlen(e));
        len += (uint32_t)strlen(e);
    }
    rd.n_sent = n;
    while (pos < len || rx_ring_count(&r) > 0 || rx_ring_loss_ahead(&r)) {
        int k = rand() % (put_burst + 1), m = rand() % (get_burst + 1);
        for (; k > 0 && pos < len; k--)
            (void)rx_ring_put(&r, (uint8_t)stream[pos++]);
        if (pos >= len)
            m = 1000; /* the host has stopped: the reader catches up */
        for (; m > 0; m--) {
            uint8_t b = 0;
            rx_loss_t loss;
            rx_event_t ev = rx_ring_get(&r, &b, &loss);
            if (ev == RX_NONE)
                break;
            reader_take(&rd, ev, b, &loss);
        }
    }
    /* a line whose terminator was the last thing lost needs nothing more; one still in progress
     * cannot be: every line was terminated */
    assert_int_equal(rd.len, 0);
    if (rd.executed + rd.lost_lines != n)
        fail_msg("seed %u: %u lines sent, %u executed + %u counted lost in %u reports", seed, n, rd.executed,
                 rd.lost_lines, rd.losses);
    if (put_burst > get_burst * 2)
        assert_true(rd.losses > 0); /* the case did overflow the ring */
}

static void floods_are_accounted_exactly(void **state)
{
    unsigned s;
    (void)state;
    for (s = 1; s <= 40; s++) {
        flood_case(s, 2000, 40, 12); /* heavy overflow */
        flood_case(s + 1000, 2000, 20, 18); /* occasional */
        flood_case(s + 2000, 500, 300, 1); /* the ring full nearly all the time */
    }
}

static void no_loss_when_read_in_time(void **state)
{
    rx_ring_t r;
    uint8_t b = 0;
    rx_loss_t loss;
    uint32_t i;
    (void)state;
    rx_ring_init(&r);
    for (i = 0; i < 1000; i++) {
        assert_int_equal(rx_ring_put(&r, (uint8_t)('a' + i % 26)), 1);
        assert_int_equal(rx_ring_get(&r, &b, &loss), RX_BYTE);
        assert_int_equal(b, 'a' + i % 26);
    }
    assert_int_equal(rx_ring_get(&r, &b, &loss), RX_NONE);
}

/* the ring holds exactly RX_RING_BYTES; the next byte is lost and reported where it belonged */
static void loss_is_reported_where_it_happened(void **state)
{
    rx_ring_t r;
    uint8_t b = 0;
    rx_loss_t loss;
    uint32_t i;
    (void)state;
    rx_ring_init(&r);
    for (i = 0; i < RX_RING_BYTES; i++)
        assert_int_equal(rx_ring_put(&r, 'x'), 1);
    assert_int_equal(rx_ring_put(&r, 'y'), 0);  /* lost: the line goes on, no end among the lost */
    assert_int_equal(rx_ring_count(&r), RX_RING_BYTES);
    for (i = 0; i < RX_RING_BYTES; i++) {
        assert_false(rx_ring_loss_ahead(&r));
        assert_int_equal(rx_ring_get(&r, &b, &loss), RX_BYTE);
    }
    assert_true(rx_ring_loss_ahead(&r));
    assert_int_equal(rx_ring_get(&r, &b, &loss), RX_LOSS);
    assert_int_equal(loss.lines, 1);
    assert_int_equal(loss.cont, 1);
    assert_int_equal(rx_ring_get(&r, &b, &loss), RX_NONE);
    /* only the LF of a CR LF lost: no line touched */
    rx_ring_init(&r);
    for (i = 0; i < RX_RING_BYTES - 1U; i++)
        assert_int_equal(rx_ring_put(&r, 'x'), 1);
    assert_int_equal(rx_ring_put(&r, '\r'), 1);
    assert_int_equal(rx_ring_put(&r, '\n'), 0);
    for (i = 0; i < RX_RING_BYTES; i++)
        assert_int_equal(rx_ring_get(&r, &b, &loss), RX_BYTE);
    assert_int_equal(rx_ring_get(&r, &b, &loss), RX_LOSS);
    assert_int_equal(loss.lines, 0);
    assert_int_equal(loss.cont, 0);
    /* a mark (the UART's own buffer found full): one damaged line */
    rx_ring_init(&r);
    rx_ring_mark_loss(&r);
    assert_int_equal(rx_ring_get(&r, &b, &loss), RX_LOSS);
    assert_int_equal(loss.lines, 1);
    assert_int_equal(loss.cont, 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(no_loss_when_read_in_time),
        cmocka_unit_test(loss_is_reported_where_it_happened),
        cmocka_unit_test(floods_are_accounted_exactly),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
