/* emu_pwm.c - phase-correct PWM on the output compare pins of Timers 1, 3, 4 and 5.
 *
 * Arduino's analogWrite() runs Timers 1-5 in "PWM, phase correct, 8-bit" (WGM = 1, TOP = 0xFF)
 * with clk/64, 490 Hz. simavr 1.6 does not implement that mode for the ATmega2560: the timer does
 * not run and the OCnx pins never move. This module produces those pins' waveform from the
 * datasheet (ATmega2560 §17.9.4): the counter runs 0 -> 255 -> 0, one period = 510 timer clocks
 * (510 * 64 = 32640 cycles); in non-inverting mode (COMnx = 2) OCnx is cleared on the compare
 * match while counting up and set on the match while counting down, so it is high for 2 * OCR of
 * the 510 clocks: duty = OCR / 255 (OCR = 0 always low, 255 always high); COMnx = 3 inverts it.
 * OCRnx is double-buffered and takes effect at TOP. The pin is driven only while its DDR bit is
 * set and COMnx != 0; otherwise it follows PORT again (analogWrite(pin, 0) and (pin, 255) are
 * digitalWrite()s). The counter is taken to start at 0 when its clock is switched on (Arduino's
 * init() does that at boot and never writes TCNTn). TCCRnA/B are checked after every
 * instruction, so a COM change (analogWrite -> digitalWrite) acts on the cycle it is written.
 * Edges land on instruction boundaries (a few cycles late at most), like simavr's own timers.
 */
#include <stdlib.h>
#include <string.h>

#include "emu.h"

typedef struct {
    uint16_t tccra, tccrb, ocr[3]; /* data addresses; ocr[i] = low byte, high byte at +1 */
    struct {
        char port;
        uint8_t bit;
    } oc[3];
} timer_desc_t;

/* ATmega2560 datasheet register summary */
static const timer_desc_t timers[4] = {
    {0x80, 0x81, {0x88, 0x8A, 0x8C}, {{'B', 5}, {'B', 6}, {'B', 7}}},    /* Timer1: D11 D12 D13 */
    {0x90, 0x91, {0x98, 0x9A, 0x9C}, {{'E', 3}, {'E', 4}, {'E', 5}}},    /* Timer3: D5 D2 D3 */
    {0xA0, 0xA1, {0xA8, 0xAA, 0xAC}, {{'H', 3}, {'H', 4}, {'H', 5}}},    /* Timer4: D6 D7 D8 */
    {0x120, 0x121, {0x128, 0x12A, 0x12C}, {{'L', 3}, {'L', 4}, {'L', 5}}}, /* Timer5: D46 D45 D44 */
};

/* PORTx data addresses: DDRx = PORTx - 1 */
static uint16_t port_addr(char port)
{
    static const uint16_t addr[] = {0x22, 0x25, 0x28, 0x2B, 0x2E, 0x31, 0x34, 0x102, 0, 0x105, 0x108, 0x10B};
    return addr[port - 'A'];
}

typedef struct {
    const timer_desc_t *d;
    int used[3];
    uint8_t seen_a, seen_b;   /* TCCRnA/B as last looked at */
    int running;              /* mode 1 with a clock */
    uint32_t prescale;
    uint64_t t_start;         /* cycle of count 0, tick 0 */
    uint16_t latch[3];        /* OCR values in effect (latched at TOP) */
    int driving[3];
    uint64_t next_event;      /* cycle of the scheduled callback (0 = none) */
} pwm_timer_t;

static pwm_timer_t state[4];
static int active;
static avr_t *the_avr;

static uint32_t prescaler(uint8_t cs)
{
    static const uint32_t div[8] = {0, 1, 8, 64, 256, 1024, 0, 0}; /* 6, 7: external clock */
    return div[cs & 7];
}

static uint16_t read_ocr(avr_t *avr, const timer_desc_t *d, int ch)
{
    return (uint16_t)(avr->data[d->ocr[ch]] | (avr->data[d->ocr[ch] + 1] << 8));
}

/* tick within the period, 0..509 */
static uint32_t tick_at(const pwm_timer_t *t, uint64_t cycle)
{
    return (uint32_t)(((cycle - t->t_start) / t->prescale) % 510);
}

static int level_at(const pwm_timer_t *t, int ch, uint32_t tick)
{
    uint32_t l = t->latch[ch] > 255 ? 255 : t->latch[ch];
    int high = tick < 255 ? (tick < l) : (tick >= 510 - l);
    int com = (t->seen_a >> (6 - 2 * ch)) & 3;
    return com == 3 ? !high : high;
}

static void apply(pwm_timer_t *t, uint64_t cycle)
{
    avr_t *avr = the_avr;
    uint32_t tick = t->running ? tick_at(t, cycle) : 0;
    for (int ch = 0; ch < 3; ch++) {
        if (!t->used[ch])
            continue;
        emu_pin_t pin = {t->d->oc[ch].port, t->d->oc[ch].bit};
        int com = (t->seen_a >> (6 - 2 * ch)) & 3;
        int ddr = (avr->data[port_addr(pin.port) - 1] >> pin.bit) & 1;
        int drive = t->running && ddr && (com == 2 || com == 3);
        if (drive)
            emu_pin_drive(avr, pin, 1, level_at(t, ch, tick));
        else if (t->driving[ch])
            emu_pin_drive(avr, pin, 0, 0);
        t->driving[ch] = drive;
    }
}

/* the next cycle after `cycle` at which some output may change or the latch is due */
static uint64_t next_event_after(const pwm_timer_t *t, uint64_t cycle)
{
    uint64_t period = 510ull * t->prescale;
    uint64_t base = t->t_start + ((cycle - t->t_start) / period) * period; /* this period's tick 0 */
    uint32_t cands[8];
    int n = 0;
    cands[n++] = 255;
    cands[n++] = 510;
    for (int ch = 0; ch < 3; ch++) {
        if (!t->used[ch])
            continue;
        uint32_t l = t->latch[ch] > 255 ? 255 : t->latch[ch];
        cands[n++] = l;
        cands[n++] = 510 - l;
    }
    uint64_t best = UINT64_MAX;
    for (int i = 0; i < n; i++) {
        uint64_t at = base + (uint64_t)cands[i] * t->prescale;
        if (at > cycle && at < best)
            best = at;
    }
    return best;
}

static avr_cycle_count_t on_event(struct avr_t *avr, avr_cycle_count_t when, void *param);

static void schedule(pwm_timer_t *t, uint64_t now)
{
    if (!t->running) {
        t->next_event = 0;
        return;
    }
    t->next_event = next_event_after(t, now);
    avr_cycle_timer_register(the_avr, t->next_event - now, on_event, t);
}

static avr_cycle_count_t on_event(struct avr_t *avr, avr_cycle_count_t when, void *param)
{
    (void)when;
    pwm_timer_t *t = param;
    uint64_t due = t->next_event;
    if (!t->running || !due)
        return 0;
    uint64_t period = 510ull * t->prescale;
    if ((due - t->t_start) % period == 255ull * t->prescale) /* TOP: double-buffered OCR takes effect */
        for (int ch = 0; ch < 3; ch++)
            t->latch[ch] = read_ocr(avr, t->d, ch);
    apply(t, due);
    t->next_event = next_event_after(t, due);
    return t->next_event; /* absolute cycle of the next call */
}

static void reconfigure(pwm_timer_t *t, uint64_t now)
{
    avr_t *avr = the_avr;
    uint8_t a = avr->data[t->d->tccra], b = avr->data[t->d->tccrb];
    int wgm = (a & 3) | ((b >> 1) & 0x0c);
    uint32_t ps = prescaler(b);
    int run = (wgm == 1) && ps;
    int was_running = t->running;
    int restart = run && (!was_running || ps != t->prescale);
    t->seen_a = a;
    t->seen_b = b;
    if (restart) {
        t->running = 1;
        t->prescale = ps;
        t->t_start = now;
        for (int ch = 0; ch < 3; ch++)
            t->latch[ch] = read_ocr(avr, t->d, ch);
        avr_cycle_timer_cancel(avr, on_event, t);
        schedule(t, now);
    } else if (!run && was_running) {
        t->running = 0;
        avr_cycle_timer_cancel(avr, on_event, t);
        t->next_event = 0;
    }
    apply(t, now);
}

void emu_pwm_poll(avr_t *avr)
{
    if (!active)
        return;
    for (int i = 0; i < 4; i++) {
        pwm_timer_t *t = &state[i];
        if (t->d && (avr->data[t->d->tccra] != t->seen_a || avr->data[t->d->tccrb] != t->seen_b))
            reconfigure(t, avr->cycle);
    }
}

int emu_pwm_attach(avr_t *avr, emu_pin_t pin)
{
    the_avr = avr;
    for (int i = 0; i < 4; i++)
        for (int ch = 0; ch < 3; ch++)
            if (timers[i].oc[ch].port == pin.port && timers[i].oc[ch].bit == pin.bit) {
                state[i].d = &timers[i];
                state[i].used[ch] = 1;
                active = 1;
            }
    return 0;
}
