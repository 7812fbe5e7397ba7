/* emu_motor.c - the servo sketches' hardware around the emulated chip: H-bridge + DC motor with a
 * quadrature encoder (the plant model motionsim uses, sim/plant_dcmotor.c) + LS7366R on SPI.
 *
 * Duty from the pins: the fraction of time the PWM pin was high over the last PWM period, a window
 * that slides with time. The window is the period of the emulated timer that drives the pin
 * (emu_pwm.c: 2.04 ms for analogWrite on timers 1, 3, 4, 5), or 2.04 ms (Arduino's 490 Hz) when no
 * emulated timer runs it. For a steady PWM wave the window holds exactly one period wherever it
 * starts, so the duty is exact at every instant; a new OCR value ramps in over one period; a pin
 * held still gives 0 % or 100 % one period later (analogWrite(0) or (255)); and a glitch (the
 * few cycles a pin follows PORT while analogWrite() reconnects it) counts for its own length only.
 * DIR gives the sign, BRAKE (when given) forces 0 %.
 * The plant is advanced by the emulated time between events, with the duty at the start of each
 * step: every edge of these pins, every SPI exchange with the counter, and every 1 ms; each 1 ms a
 * "motor <cycle> <duty_pct> <counts>" line is logged (counts = the encoder's x4 count, what an
 * LS7366R in x4 mode counts).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "emu.h"
#include "ls7366r.h"

#include "plant_dcmotor.h"

static avr_t *the_avr;
static ls7366r_t chip;
static int attached_chip;

/* encoder position (x4 counts) without a motor: set by the script's "encoder" command */
static int64_t manual_quad;

/* ---- motor state ---- */
static int have_motor;
static emu_motor_config_t cfg;
static uint64_t plant_cycle;    /* the plant has been advanced up to this cycle */
static int pwm_level;            /* the PWM pin's level now */
#define EDGE_RING 64              /* a window of one period holds 2 edges of a steady wave */
static uint64_t edge_cycle[EDGE_RING]; /* the PWM pin's last edges, newest at edge_head - 1 */
static unsigned edge_head, edge_count;
static uint64_t samples;
static double duty_min = 1e9, duty_max = -1e9;

static plant_dcmotor_t plant;

#define DEFAULT_WINDOW (510u * 64u) /* Arduino's analogWrite: 8-bit phase correct, clk/64 */

/* 0..1: the time the PWM pin was high in the window (now - one PWM period, now] */
static double pwm_fraction(uint64_t now)
{
    uint64_t window = emu_pwm_period(cfg.pwm);
    if (!window)
        window = DEFAULT_WINDOW;
    uint64_t from = now > window ? now - window : 0;
    uint64_t high = 0, end = now;
    int level = pwm_level;
    /* walk back over the edges: before each edge the pin had the other level */
    for (unsigned i = 0; i < edge_count && end > from; i++) {
        uint64_t c = edge_cycle[(edge_head + EDGE_RING - 1 - i) % EDGE_RING];
        if (c > end)
            c = end;
        uint64_t start = c > from ? c : from;
        if (level)
            high += end - start;
        end = start;
        level = !level;
    }
    if (level && end > from)
        high += end - from; /* the level before the oldest edge remembered */
    return now > from ? (double)high / (double)(now - from) : (double)pwm_level;
}

static double current_duty_pct(uint64_t now)
{
    if (cfg.have_brake && emu_pin_level(the_avr, cfg.brake) == (cfg.brake_high_active ? 1 : 0))
        return 0.0;
    double d = pwm_fraction(now);
    int dir = emu_pin_level(the_avr, cfg.dir);
    int positive = cfg.dir_high_positive ? dir : !dir;
    return (positive ? 100.0 : -100.0) * d;
}

/* the plant's LS7366R count wraps at 32 bits; unwrapped here so the chip model sees the motion */
static int64_t quad_unwrapped;
static int32_t quad_last;

static int64_t plant_quad(void)
{
    int32_t now = plant_dcmotor_count(&plant);
    quad_unwrapped += (int32_t)((uint32_t)now - (uint32_t)quad_last);
    quad_last = now;
    return quad_unwrapped;
}

/* advance the plant to `now` with the duty that held since the last event */
static void plant_advance(uint64_t now)
{
    if (!have_motor || now <= plant_cycle)
        return;
    double duty = current_duty_pct(plant_cycle);
    plant_dcmotor_advance(&plant, duty, (double)(now - plant_cycle) / EMU_F_CPU);
    plant_cycle = now;
}

static int64_t quad_now(uint64_t cycle)
{
    if (!have_motor)
        return manual_quad;
    plant_advance(cycle);
    return plant_quad();
}

void emu_encoder_set(int64_t quad)
{
    manual_quad = quad;
}

/* ---- LS7366R on SPI ---- */
static void ls_select(void *ctx, uint64_t cycle, int level)
{
    (void)ctx;
    ls7366r_select(&chip, level, quad_now(cycle));
}

static uint8_t ls_transfer(void *ctx, uint64_t cycle, uint8_t mosi)
{
    (void)ctx;
    return ls7366r_transfer(&chip, mosi, quad_now(cycle));
}

int emu_encoder_attach(avr_t *avr, emu_pin_t cs)
{
    the_avr = avr;
    ls7366r_init(&chip, quad_now(0));
    emu_spi_device_t dev = {.ctx = NULL, .select = ls_select, .transfer = ls_transfer};
    if (emu_spi_attach(avr, cs, &dev))
        return -1;
    attached_chip = 1;
    return 0;
}

/* ---- PWM measurement ---- */
static void pwm_edge(void *param, uint64_t cycle, int level)
{
    (void)param;
    plant_advance(cycle);
    edge_cycle[edge_head] = cycle;
    edge_head = (edge_head + 1) % EDGE_RING;
    if (edge_count < EDGE_RING)
        edge_count++;
    pwm_level = level;
}

static void other_edge(void *param, uint64_t cycle, int level)
{
    (void)param;
    (void)level;
    plant_advance(cycle); /* with the DIR/BRAKE levels before this edge (see emu_pin_listen) */
}

static avr_cycle_count_t motor_tick(struct avr_t *avr, avr_cycle_count_t when, void *param)
{
    (void)param;
    plant_advance(avr->cycle);
    double duty = current_duty_pct(avr->cycle);
    if (duty < duty_min)
        duty_min = duty;
    if (duty > duty_max)
        duty_max = duty;
    samples++;
    emu_log(avr->cycle, "motor", "%.3f %lld", duty, (long long)plant_quad());
    return when + EMU_F_CPU / 1000;
}

int emu_motor_attach(avr_t *avr, const emu_motor_config_t *c)
{
    the_avr = avr;
    cfg = *c;
    plant_dcmotor_params_t params;
    plant_dcmotor_default_params(&params);
    if (plant_dcmotor_init(&plant, &params))
        return -1;
    quad_last = plant_dcmotor_count(&plant);
    quad_unwrapped = quad_last;
    have_motor = 1;
    emu_pwm_attach(avr, cfg.pwm);
    if (emu_pin_listen(avr, cfg.pwm, pwm_edge, NULL) || emu_pin_listen(avr, cfg.dir, other_edge, NULL) ||
        (cfg.have_brake && emu_pin_listen(avr, cfg.brake, other_edge, NULL)))
        return -1;
    avr_cycle_timer_register(avr, EMU_F_CPU / 1000, motor_tick, NULL);
    return emu_encoder_attach(avr, cfg.cs);
}

void emu_motor_summary(uint64_t cycle)
{
    if (attached_chip)
        emu_log(cycle, "ls7366r", "spi_bytes=%llu mdr0=0x%02x mdr1=0x%02x count=%lu unsupported=%u",
                (unsigned long long)emu_spi_byte_count(), chip.mdr0, chip.mdr1,
                (unsigned long)ls7366r_count(&chip, quad_now(cycle)), chip.unsupported);
    if (have_motor)
        emu_log(cycle, "motorsum", "samples=%llu duty_min=%.3f duty_max=%.3f counts=%lld", (unsigned long long)samples,
                duty_min, duty_max, (long long)plant_quad());
}
