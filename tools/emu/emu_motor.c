/* emu_motor.c - the servo sketches' hardware around the emulated chip: H-bridge + DC motor with a
 * quadrature encoder (the plant model motionsim uses, sim/plant_dcmotor.c) + LS7366R on SPI.
 *
 * Duty from the pins: the PWM pin's edges are timed; at each rising edge the period just ended
 * gives duty = high time / period, held until the next rising edge. When the pin holds still for
 * longer than two periods (the last one seen, or 4.1 ms = two periods of Arduino's 490 Hz PWM
 * before any), it is a constant level: analogWrite(0) or (255) give 0 % or 100 %; when PWM starts
 * again that level holds until its first full period. DIR gives the sign, BRAKE (when given)
 * forces 0 %.
 * The plant is advanced by the emulated time between events: every edge of these pins, every SPI
 * exchange with the counter, and every 1 ms; each 1 ms a "motor <cycle> <duty_pct> <counts>" line
 * is logged (counts = the encoder's x4 count, what an LS7366R in x4 mode counts).
 * The duty of a PWM period is known at its end and applied from there on, a lag of one period
 * (about 2 ms at 490 Hz), the same order as the chip's own buffered OCR update.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "emu.h"
#include "ls7366r.h"

#if __has_include("plant_dcmotor.h")
#include "plant_dcmotor.h"
#define EMU_HAVE_PLANT 1
#else
#define EMU_HAVE_PLANT 0
#endif

static avr_t *the_avr;
static ls7366r_t chip;
static int attached_chip;

/* encoder position (x4 counts) without a motor: set by the script's "encoder" command */
static int64_t manual_quad;

/* ---- motor state ---- */
static int have_motor;
static emu_motor_config_t cfg;
static uint64_t plant_cycle;    /* the plant has been advanced up to this cycle */
static int pwm_level;
static uint64_t last_rise, last_fall, last_edge;
static int have_rise;
static uint64_t period_cycles;  /* last full PWM period */
static double pwm_duty;         /* 0..1, last full period */
static uint64_t samples;
static double duty_min = 1e9, duty_max = -1e9;

#if EMU_HAVE_PLANT
static plant_dcmotor_t plant;
#endif

/* a pin that has not moved for this long is a constant level, not PWM */
static uint64_t still_cycles(void)
{
    return period_cycles ? 2 * period_cycles : (uint64_t)(0.0041 * EMU_F_CPU);
}

/* 0..1: the last full period's duty, or the constant level once the pin has held still */
static double pwm_fraction(uint64_t now)
{
    if (now - last_edge > still_cycles())
        return pwm_level ? 1.0 : 0.0;
    return pwm_duty;
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
#if EMU_HAVE_PLANT
static int32_t quad_last;
#endif

static int64_t plant_quad(void)
{
#if EMU_HAVE_PLANT
    int32_t now = plant_dcmotor_count(&plant);
    quad_unwrapped += (int32_t)((uint32_t)now - (uint32_t)quad_last);
    quad_last = now;
#endif
    return quad_unwrapped;
}

/* advance the plant to `now` with the duty that held since the last event */
static void plant_advance(uint64_t now)
{
    if (!have_motor || now <= plant_cycle)
        return;
    double duty = current_duty_pct(plant_cycle);
#if EMU_HAVE_PLANT
    plant_dcmotor_advance(&plant, duty, (double)(now - plant_cycle) / EMU_F_CPU);
#else
    (void)duty;
#endif
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
    if (cycle - last_edge > still_cycles()) {
        /* PWM (re)starts after a constant level: that level holds until a full period is seen */
        pwm_duty = pwm_level ? 1.0 : 0.0;
        have_rise = 0;
    }
    if (level) {
        if (have_rise && last_fall > last_rise) {
            period_cycles = cycle - last_rise;
            pwm_duty = (double)(last_fall - last_rise) / (double)period_cycles;
        }
        last_rise = cycle;
        have_rise = 1;
    } else {
        last_fall = cycle;
    }
    last_edge = cycle;
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
#if !EMU_HAVE_PLANT
    (void)c;
    (void)avr;
    (void)pwm_edge;
    (void)other_edge;
    (void)motor_tick;
    fprintf(stderr, "motionemu: built without sim/plant_dcmotor.h: no motor model\n");
    return -1;
#else
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
#endif
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
