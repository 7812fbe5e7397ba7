/* step_planner_avr.c - lib's step planner on the ATmega2560 (avr-gcc, double = float): plans the
 * benchmark's reference moves and prints, per move, the cycles the planner spends per command and
 * per step (Timer1 at 16 MHz counts them), and a checksum of the commands, which the host compares
 * with the same planner built for the host (the bits must agree: integer and float arithmetic in
 * the same order). Lines: "move <algo> <vmax> cmds=<n> steps=<n> cyc_min=<n> cyc_mean=<n>
 * cyc_max=<n> sum=<hex>".
 * The same file builds on the host (cycles then read 0), to compare the sums by hand:
 *   cc -std=gnu11 -O2 -ffp-contract=off -Ilib/src test/emu/step_avr/step_planner_avr.c \
 *      lib/src/step_planner.c lib/src/step_exact.c lib/src/step_queue.c lib/src/ramp*.c \
 *      lib/src/motion_status.c -lm -o build/step_planner_host && build/step_planner_host */
#include <stdio.h>
#include <stdint.h>

#ifdef __AVR__
#include <avr/io.h>

#include "avr_uart.h"
#define CYCLES() TCNT1
#else
#define CYCLES() 0U
static void println(const char *s)
{
    puts(s);
}
#endif
#include "step_planner.h"

static uint32_t fnv(uint32_t h, const void *p, uint8_t n)
{
    const uint8_t *b = (const uint8_t *)p;
    while (n--) {
        h ^= *b++;
        h *= 16777619UL;
    }
    return h;
}

static void run(ramp_algo_t algo, float vmax, float accel, uint32_t tick_hz, int32_t d)
{
    static step_planner_t pl;
    ramp_params_t p;
    step_cmd_t c;
    uint32_t cmds = 0, steps = 0, sum = 2166136261UL, cyc_sum = 0, cyc_max = 0, cyc_min = 0xFFFFFFFFUL;
    char line[160];
    p.v0_sps = algo == RAMP_ALGO_EXACT ? 0.0 : 100.0;
    p.vmax_sps = vmax;
    p.accel_sps2 = accel;
    p.tick_hz = tick_hz;
    if (step_planner_init_trapezoid(&pl, algo, &p, 0) != MS_OK || step_planner_move(&pl, d) != MS_OK) {
        println("plan failed");
        return;
    }
    for (;;) {
        uint16_t t0, t1;
        uint8_t more;
        uint32_t dt;
        t0 = CYCLES();
        more = step_planner_next(&pl, &c);
        t1 = CYCLES();
        if (!more)
            break;
        dt = (uint16_t)(t1 - t0); /* every call is far below 65536 cycles */
        cyc_sum += dt;
        if (dt > cyc_max)
            cyc_max = dt;
        if (dt < cyc_min)
            cyc_min = dt;
        cmds++;
        steps += c.count;
        sum = fnv(sum, &c.rate, 4);
        sum = fnv(sum, &c.add, 4);
        sum = fnv(sum, &c.count, 2);
        sum = fnv(sum, &c.flags, 1);
    }
    snprintf(line, sizeof line, "move %s %lu cmds=%lu steps=%lu cyc_min=%lu cyc_mean=%lu cyc_max=%lu cyc_per_step=%lu sum=%08lx",
             ramp_algo_name(algo), (unsigned long)vmax, (unsigned long)cmds, (unsigned long)steps,
             (unsigned long)cyc_min, (unsigned long)(cyc_sum / (cmds ? cmds : 1)), (unsigned long)cyc_max,
             (unsigned long)(cyc_sum / (steps ? steps : 1)), (unsigned long)sum);
    println(line);
}

int main(void)
{
#ifdef __AVR__
    UBRR0 = 0; /* 1 Mbaud at 16 MHz: the harness reads as fast as it comes */
    UCSR0A = _BV(U2X0);
    UCSR0B = _BV(TXEN0);
    TCCR1A = 0;
    TCCR1B = _BV(CS10);
#endif
    run(RAMP_ALGO_EXACT, 20000.0f, 40000.0f, 16000000UL, 20000);
    run(RAMP_ALGO_EXACT, 100000.0f, 1000000.0f, 16000000UL, 20000);
    run(RAMP_ALGO_LEIB, 12000.0f, 14400.0f, 2000000UL, 20000);
    run(RAMP_ALGO_SIMPLISTIC, 30000.0f, 90000.0f, 2000000UL, 20000);
    println("end");
#ifdef __AVR__
    for (;;)
        ;
#else
    return 0;
#endif
}
