/* smooth_move_avr.c - lib's filter-shaped move (lib/src/smooth_move.h) on the ATmega2560 (avr-gcc,
 * double = float): the first commands of a stepper move and the servo's setpoints over a `move`,
 * with the cycles each call takes (Timer1 at clk/8) and a checksum of what it computed. The same
 * file builds on the host (cycles then read 0); the check "smooth_move on the AVR" compares the
 * checksums: the smx_t arithmetic is integer work, so the bits must agree. Lines:
 *   "smooth cmds=<n> steps=<n> cyc_mean=<n> cyc_max=<n> sum=<hex>"
 *   "setpoint n=<n> cyc_max=<n> sum=<hex>"  then "end". */
#include <stdint.h>
#include <stdio.h>

#ifdef __AVR__
#include <avr/io.h>

#include "avr_uart.h"
static void timer_start(void)
{
    TCNT1 = 0;
    TIFR1 = _BV(TOV1);
}
static uint32_t timer_cycles(void) /* calls of up to 2 x 65536 x 8 cycles */
{
    uint32_t t = TCNT1;
    if (TIFR1 & _BV(TOV1))
        t += 65536UL;
    return t * 8U;
}
#else
static void timer_start(void)
{
}
static uint32_t timer_cycles(void)
{
    return 0;
}
static void println(const char *s)
{
    puts(s);
}
#endif
#include "smooth_move.h"

static uint32_t fnv(uint32_t h, const void *p, uint8_t n)
{
    const uint8_t *b = (const uint8_t *)p;
    while (n--) {
        h ^= *b++;
        h *= 16777619UL;
    }
    return h;
}

static void stepper(void)
{
    static smooth_move_t s;
    smooth_params_t p = {20000.0f, 40000.0f, 400000.0f, 16000000UL};
    step_cmd_t c;
    uint32_t cmds = 0, steps = 0, sum = 2166136261UL, cyc_sum = 0, cyc_max = 0;
    char line[120];
    if (smooth_move_init(&s, &p, 0) != MS_OK || smooth_move_to(&s, 20000) != MS_OK) {
        println("plan failed");
        return;
    }
    while (cmds < 40) {
        uint32_t dt;
        uint8_t more;
        timer_start();
        more = smooth_move_next(&s, &c);
        dt = timer_cycles();
        if (!more)
            break;
        cyc_sum += dt;
        if (dt > cyc_max)
            cyc_max = dt;
        cmds++;
        steps += c.count;
        sum = fnv(sum, &c.rate, 4);
        sum = fnv(sum, &c.add, 4);
        sum = fnv(sum, &c.count, 2);
        sum = fnv(sum, &c.flags, 1);
    }
    snprintf(line, sizeof line, "smooth cmds=%lu steps=%lu cyc_mean=%lu cyc_max=%lu sum=%08lx", (unsigned long)cmds,
             (unsigned long)steps, (unsigned long)(cyc_sum / (cmds ? cmds : 1)), (unsigned long)cyc_max,
             (unsigned long)sum);
    println(line);
}

static void servo(void)
{
    static smooth_setpoint_t sp;
    smooth_params_t p = {3000.0f, 20000.0f, 400000.0f, 1000000UL}; /* the servo sketches' move */
    uint32_t k, cyc_max = 0, sum = 2166136261UL;
    char line[100];
    if (smooth_setpoint_init(&sp, &p, 0) != MS_OK || smooth_setpoint_move(&sp, 0, 1000) != MS_OK) {
        println("setpoint failed");
        return;
    }
    for (k = 1; k <= 30; k++) {
        int32_t v;
        uint32_t dt;
        timer_start();
        v = smooth_setpoint_at(&sp, 20 * k);
        dt = timer_cycles();
        if (dt > cyc_max)
            cyc_max = dt;
        sum = fnv(sum, &v, 4);
    }
    snprintf(line, sizeof line, "setpoint n=30 cyc_max=%lu sum=%08lx", (unsigned long)cyc_max, (unsigned long)sum);
    println(line);
}

int main(void)
{
#ifdef __AVR__
    UBRR0 = 0; /* 1 Mbaud at 16 MHz */
    UCSR0A = _BV(U2X0);
    UCSR0B = _BV(TXEN0);
    TCCR1A = 0;
    TCCR1B = _BV(CS11); /* clk/8 */
#endif
    stepper();
    servo();
    println("end");
#ifdef __AVR__
    for (;;)
        ;
#else
    return 0;
#endif
}
