/* Unit tests: filter_stream - the MovingAverageFilter sketch's stream line "t_ms,u,y" and its A0
 * scaling, which motionsim --stream reproduces byte for byte. */
#include "cmocka_all.h"

#include <math.h>
#include <string.h>

#include "filter_stream.h"

static void adc_codes_map_to_the_nearest_millivolt(void **state)
{
    uint16_t code;
    int16_t prev = -1;
    (void)state;
    assert_int_equal(fstream_adc10_to_mv(0), 0);
    assert_int_equal(fstream_adc10_to_mv(1), 5);      /* 4.888 mV */
    assert_int_equal(fstream_adc10_to_mv(512), 2502); /* 2502.44 mV */
    assert_int_equal(fstream_adc10_to_mv(1023), 5000);
    assert_int_equal(fstream_adc10_to_mv(1024), 5000); /* out of range: clamped */
    assert_int_equal(fstream_adc10_to_mv(65535), 5000);
    for (code = 0; code <= 1023; code++) {
        int16_t mv = fstream_adc10_to_mv(code);
        assert_true(fabs(mv - code * 5000.0 / 1023.0) < 0.5);
        assert_true(mv > prev);
        prev = mv;
    }
}

static void check_line(uint32_t t, int16_t u, int32_t y, const char *expect)
{
    char buf[FSTREAM_LINE_MAX + 1];
    memset(buf, '#', sizeof buf);
    assert_int_equal(fstream_format(buf, t, u, y), strlen(expect));
    assert_string_equal(buf, expect);
}

static void lines_have_fixed_decimals(void **state)
{
    (void)state;
    check_line(0, 0, 0, "0,0.000,0.000000");
    check_line(4500, 5000, 2500000, "4500,5.000,2.500000"); /* the moving-average-filter note: half-way */
    check_line(10, 5000, 5556, "10,5.000,0.005556");
    check_line(9000, 1234, 4999999, "9000,1.234,4.999999");
    check_line(20, -1, -500, "20,-0.001,-0.000500");
    check_line(30, -32767, 32767000, "30,-32.767,32.767000");
    check_line(4294967295u, -32767, -32767000, "4294967295,-32.767,-32.767000");
    check_line(7, 32767, -1, "7,32.767,-0.000001");
}

static void the_longest_line_fits_the_buffer(void **state)
{
    char buf[FSTREAM_LINE_MAX + 2];
    (void)state;
    buf[FSTREAM_LINE_MAX + 1] = 'Z';
    assert_true(fstream_format(buf, 4294967295u, -32768, INT32_MIN) <= FSTREAM_LINE_MAX);
    assert_string_equal(buf, "4294967295,-32.768,-2147.483648");
    assert_int_equal(buf[FSTREAM_LINE_MAX + 1], 'Z');
    assert_string_equal(FSTREAM_HEADER, "t_ms,u,y");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(adc_codes_map_to_the_nearest_millivolt),
        cmocka_unit_test(lines_have_fixed_decimals),
        cmocka_unit_test(the_longest_line_fits_the_buffer),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
