/* smooth_move_avr.c - lib's filter-shaped move (lib/src/smooth_move.h) on the ATmega2560 (avr-gcc,
 * double = float): whole stepper moves (one stopped, others sent to a new target) and the servo's
 * setpoints over a `move`, with the cycles each call takes (Timer1 at clk/8) and a checksum of what it computed. The same
 * file builds on the host (cycles then read 0); the check "smooth_move on the AVR" compares the
 * checksums: the smx_t arithmetic is integer work and the float work is IEEE single precision
 * +, -, x, / on both (no libm but frexp/ldexp/sqrt, which are exact), so the bits must agree. Lines:
 *   "smooth <move> cmds=<n> steps=<n> cyc_mean=<n> cyc_max=<n> cyc_per_step=<n> load16=<x.y>% lead_us=<n>
 *    event_cyc=<n> sum=<hex>"
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

/* One reference move, planned to its end (with a stop or a new target after `at` steps when at
 * > 0): the cycles of each smooth_move_next, per command and per step; the planner's load, the
 * most cycles any 16 consecutive commands take over the ticks (= cycles at 16 MHz) they cover;
 * and the lead it needs, the most by which planning commands 1..k outlasts executing commands
 * 1..k-1 (planned that far ahead of the first step, no command comes late; the step interrupt's
 * own cycles not counted). */
static void stepper(const char *name, float vmax, float accel, float jerk, int32_t to, uint32_t at, int32_t then)
{
    static smooth_move_t s;
    smooth_params_t p = {vmax, accel, jerk, 16000000UL};
    step_cmd_t c;
    uint32_t cmds = 0, steps = 0, sum = 2166136261UL, cyc_max = 0, ring_c[16], ring_t[16], win_c = 0, win_t = 0;
    uint32_t load_pm = 0, ev_cyc = 0; /* per mille; cycles of the stop or new target */
    uint64_t cyc_sum = 0, tick_sum = 0;
    int64_t lead = 0; /* cycles the planner must be ahead at the start so no command comes late */
    uint8_t done = at == 0;
    char line[160];
    if (smooth_move_init(&s, &p, 0) != MS_OK || smooth_move_to(&s, to) != MS_OK) {
        println("plan failed");
        return;
    }
    for (;;) {
        uint32_t dt, ticks;
        uint8_t more;
        timer_start();
        more = smooth_move_next(&s, &c);
        dt = timer_cycles();
        if (!more)
            break;
        cyc_sum += dt;
        if ((int64_t)(cyc_sum - tick_sum) > lead) /* command k ready after C_k; needed at T_(k-1) */
            lead = (int64_t)(cyc_sum - tick_sum);
        if (dt > cyc_max)
            cyc_max = dt;
        ticks = (c.flags & STEP_CMD_WIDE) ? c.rate
                                          : (uint32_t)(((uint64_t)c.count * c.rate +
                                                        (int64_t)c.count * (c.count - 1) / 2 * c.add) >> 16);
        if (cmds >= 16) {
            win_c -= ring_c[cmds % 16];
            win_t -= ring_t[cmds % 16];
        }
        ring_c[cmds % 16] = dt;
        ring_t[cmds % 16] = ticks;
        win_c += dt;
        win_t += ticks;
        tick_sum += ticks;
        if (cmds >= 15 && win_t > 0 && (uint64_t)win_c * 1000U / win_t > load_pm)
            load_pm = (uint32_t)((uint64_t)win_c * 1000U / win_t);
        cmds++;
        steps += c.count;
        sum = fnv(sum, &c.rate, 4);
        sum = fnv(sum, &c.add, 4);
        sum = fnv(sum, &c.count, 2);
        sum = fnv(sum, &c.flags, 1);
        if (!done && steps >= at) {
            uint8_t ok = 1;
            done = 1;
            timer_start();
            if (then == 0)
                smooth_move_stop(&s);
            else
                ok = smooth_move_to(&s, then) == MS_OK;
            ev_cyc = timer_cycles();
            if (!ok)
                println("retarget failed");
        }
    }
    snprintf(line, sizeof line,
             "smooth %s cmds=%lu steps=%lu cyc_mean=%lu cyc_max=%lu cyc_per_step=%lu load16=%lu.%lu%% lead_us=%lu event_cyc=%lu "
             "sum=%08lx",
             name,
             (unsigned long)cmds, (unsigned long)steps, (unsigned long)(cyc_sum / (cmds ? cmds : 1)),
             (unsigned long)cyc_max, (unsigned long)(cyc_sum / (steps ? steps : 1)), (unsigned long)(load_pm / 10),
             (unsigned long)(load_pm % 10), (unsigned long)(lead / 16), (unsigned long)ev_cyc, (unsigned long)sum);
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
    /* A: 20,000 steps at up to 20,000 steps/s (tau1 0.5 s, tau2 0.1 s); B: 100,000 steps at up to
     * 50,000 steps/s (tau1 0.25 s, tau2 0.05 s); B stopped after 30,000 steps; A sent on to 30,000
     * after 10,000 steps (in its cruise), and sent to 8,000 after 1,000 steps (still accelerating) */
    stepper("A", 20000.0f, 40000.0f, 400000.0f, 20000, 0, 0);
    stepper("B", 50000.0f, 200000.0f, 4000000.0f, 100000, 0, 0);
    stepper("B-stop", 50000.0f, 200000.0f, 4000000.0f, 100000, 30000, 0);
    stepper("A-retarget", 20000.0f, 40000.0f, 400000.0f, 20000, 10000, 30000);
    stepper("A-retarget-early", 20000.0f, 40000.0f, 400000.0f, 20000, 1000, 8000);
    servo();
    println("end");
#ifdef __AVR__
    for (;;)
        ;
#else
    return 0;
#endif
}
