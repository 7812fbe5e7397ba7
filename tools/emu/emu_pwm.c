/* emu_pwm.c - phase-correct PWM on the output compare pins of Timers 1, 3, 4 and 5.
 *
 * Arduino's analogWrite() runs Timers 1-5 in "PWM, phase correct, 8-bit" (WGM = 1, TOP = 0xFF)
 * with clk/64, 490 Hz. simavr 1.6 implements none of the dual-slope modes of the 16-bit timers
 * (WGM 1, 2, 3 phase correct 8/9/10-bit; 8, 9 phase and frequency correct with TOP = ICRn or
 * OCRnA; 10, 11 phase correct with TOP = ICRn or OCRnA): the timer does not run and the OCnx
 * pins never move. This module produces those pins' waveform from the datasheet (ATmega2560
 * §17.9.4-17.9.5): the counter runs 0 -> TOP -> 0, one period = 2 * TOP timer clocks (8-bit,
 * clk/64: 510 * 64 = 32640 cycles); in non-inverting mode (COMnx = 2) OCnx is cleared on the
 * compare match while counting up and set on the match while counting down, so it is high for
 * 2 * OCR of the 2 * TOP clocks: duty = OCR / TOP (OCR = 0 always low, OCR >= TOP always high);
 * COMnx = 3 inverts it. OCRnx is double-buffered: it takes effect at TOP (phase correct) or at
 * BOTTOM (phase and frequency correct), where TOP itself is read again. Channel A cannot make PWM
 * while OCRnA is TOP (WGM 9, 11); that case is not emulated. The pin is driven only while its DDR bit is
 * set and COMnx != 0; otherwise it follows PORT again (analogWrite(pin, 0) and (pin, 255) are
 * digitalWrite()s). The counter is taken to start at 0 when its clock is switched on (Arduino's
 * init() does that at boot and never writes TCNTn). Writes to TCCRnA/B and ICRn are seen through
 * simavr's io-memory IRQs, so a COM change (analogWrite -> digitalWrite) acts on the cycle it is
 * written.
 * simavr runs the callbacks at the next instruction boundary (up to 4 cycles late), but the
 * edges are stamped with their exact compare-match cycle, as the hardware produces them.
 */
#include <stdlib.h>
#include <string.h>

#include "emu.h"

typedef struct {
    uint16_t tccra, tccrb, icr, ocr[3]; /* data addresses; 16-bit registers: low byte, high at +1 */
    struct {
        char port;
        uint8_t bit;
    } oc[3];
} timer_desc_t;

/* ATmega2560 datasheet register summary */
static const timer_desc_t timers[4] = {
    {0x80, 0x81, 0x86, {0x88, 0x8A, 0x8C}, {{'B', 5}, {'B', 6}, {'B', 7}}},      /* Timer1: D11 D12 D13 */
    {0x90, 0x91, 0x96, {0x98, 0x9A, 0x9C}, {{'E', 3}, {'E', 4}, {'E', 5}}},      /* Timer3: D5 D2 D3 */
    {0xA0, 0xA1, 0xA6, {0xA8, 0xAA, 0xAC}, {{'H', 3}, {'H', 4}, {'H', 5}}},      /* Timer4: D6 D7 D8 */
    {0x120, 0x121, 0x126, {0x128, 0x12A, 0x12C}, {{'L', 3}, {'L', 4}, {'L', 5}}}, /* Timer5: D46 D45 D44 */
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
    int running;              /* a dual-slope mode with a clock */
    int wgm;
    uint32_t prescale;
    uint32_t top;             /* TOP in effect */
    uint64_t t_start;         /* cycle of the current period's BOTTOM (tick 0) */
    uint16_t latch[3];        /* OCR values in effect */
    int driving[3];
    uint64_t next_event;      /* cycle of the scheduled callback (0 = none) */
} pwm_timer_t;

static pwm_timer_t state[4];
static avr_t *the_avr;

static uint32_t prescaler(uint8_t cs)
{
    static const uint32_t div[8] = {0, 1, 8, 64, 256, 1024, 0, 0}; /* 6, 7: external clock */
    return div[cs & 7];
}

static uint16_t read16(avr_t *avr, uint16_t addr)
{
    return (uint16_t)(avr->data[addr] | (avr->data[addr + 1] << 8));
}

static int dual_slope(int wgm)
{
    return wgm == 1 || wgm == 2 || wgm == 3 || (wgm >= 8 && wgm <= 11);
}

static uint32_t read_top(avr_t *avr, const pwm_timer_t *t)
{
    switch (t->wgm) {
    case 1: return 0xFF;
    case 2: return 0x1FF;
    case 3: return 0x3FF;
    case 8: case 10: return read16(avr, t->d->icr);
    default: return read16(avr, t->d->ocr[0]); /* 9, 11: OCRnA */
    }
}

/* the double-buffered registers take effect: at BOTTOM (WGM 8, 9) or at TOP (the others) */
static void latch(avr_t *avr, pwm_timer_t *t)
{
    t->top = read_top(avr, t);
    for (int ch = 0; ch < 3; ch++)
        t->latch[ch] = read16(avr, t->d->ocr[ch]);
}

static int top_is_icr(int wgm)
{
    return wgm == 8 || wgm == 10;
}

static int updates_at_bottom(const pwm_timer_t *t)
{
    return t->wgm == 8 || t->wgm == 9;
}

static uint64_t period_cycles(const pwm_timer_t *t)
{
    return 2ull * (t->top ? t->top : 1) * t->prescale;
}

/* tick within the current period, 0 .. 2 TOP - 1 */
static uint32_t tick_at(const pwm_timer_t *t, uint64_t cycle)
{
    return (uint32_t)((cycle - t->t_start) / t->prescale);
}

static int level_at(const pwm_timer_t *t, int ch, uint32_t tick)
{
    uint32_t top = t->top, l = t->latch[ch] > top ? top : t->latch[ch];
    int high = tick < top ? (tick < l) : (tick >= 2 * top - l);
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
        int top_is_a = ch == 0 && (t->wgm == 9 || t->wgm == 11);
        int drive = t->running && ddr && (com == 2 || com == 3) && !top_is_a;
        if (drive)
            emu_pin_drive(avr, pin, 1, level_at(t, ch, tick), cycle);
        else if (t->driving[ch])
            emu_pin_drive(avr, pin, 0, 0, cycle);
        t->driving[ch] = drive;
    }
}

/* the next cycle after `cycle` (within this period, or the next BOTTOM) at which an output may
 * change or the registers latch */
static uint64_t next_event_after(const pwm_timer_t *t, uint64_t cycle)
{
    uint32_t top = t->top ? t->top : 1;
    uint32_t cands[8];
    int n = 0;
    cands[n++] = top;
    cands[n++] = 2 * top;
    for (int ch = 0; ch < 3; ch++) {
        if (!t->used[ch])
            continue;
        uint32_t l = t->latch[ch] > top ? top : t->latch[ch];
        cands[n++] = l;
        cands[n++] = 2 * top - l;
    }
    uint64_t best = t->t_start + period_cycles(t);
    for (int i = 0; i < n; i++) {
        uint64_t at = t->t_start + (uint64_t)cands[i] * t->prescale;
        if (at > cycle && at < best)
            best = at;
    }
    return best;
}

static avr_cycle_count_t on_event(struct avr_t *avr, avr_cycle_count_t when, void *param)
{
    (void)when;
    pwm_timer_t *t = param;
    uint64_t due = t->next_event;
    if (!t->running || !due)
        return 0;
    if (due == t->t_start + period_cycles(t)) { /* BOTTOM: a new period */
        t->t_start = due;
        if (updates_at_bottom(t))
            latch(avr, t);
    } else if (due == t->t_start + (uint64_t)t->top * t->prescale && !updates_at_bottom(t)) {
        /* TOP: the new values hold from here; keep the elapsed half period consistent */
        uint32_t old_top = t->top;
        latch(avr, t);
        if (t->top != old_top) /* TOP changed: the down-count starts from the new TOP */
            t->t_start = due - (uint64_t)t->top * t->prescale;
    }
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
    uint32_t top = 0;
    if (dual_slope(wgm)) {
        t->wgm = wgm;
        top = read_top(avr, t);
    }
    /* TOP = 0 holds the counter at 0: no waveform. ICRn is not buffered, so a new ICRn value
     * (normally written once in setup) restarts the period here. */
    int run = dual_slope(wgm) && ps && top > 0;
    int restart = run && (!t->running || ps != t->prescale || (top_is_icr(wgm) && top != t->top));
    t->seen_a = a;
    t->seen_b = b;
    if (restart) {
        t->running = 1;
        t->prescale = ps;
        t->t_start = now;
        latch(avr, t);
        avr_cycle_timer_cancel(avr, on_event, t);
        t->next_event = next_event_after(t, now);
        avr_cycle_timer_register(avr, t->next_event - now, on_event, t);
    } else if (!run && t->running) {
        t->running = 0;
        avr_cycle_timer_cancel(avr, on_event, t);
        t->next_event = 0;
    }
    apply(t, now);
}

/* simavr raises an io-memory IRQ after every write to a watched register */
static void register_written(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    (void)value;
    pwm_timer_t *t = param;
    const timer_desc_t *d = t->d;
    avr_t *avr = the_avr;
    if (avr->data[d->tccra] != t->seen_a || avr->data[d->tccrb] != t->seen_b ||
        (top_is_icr(t->wgm) && read16(avr, d->icr) != (t->running ? t->top : 0)))
        reconfigure(t, avr->cycle);
}

static int watch_timer(avr_t *avr, pwm_timer_t *t)
{
    const uint16_t regs[4] = {t->d->tccra, t->d->tccrb, t->d->icr, (uint16_t)(t->d->icr + 1)};
    for (int i = 0; i < 4; i++) {
        avr_irq_t *irq = avr_iomem_getirq(avr, regs[i], NULL, AVR_IOMEM_IRQ_ALL);
        if (!irq)
            return -1;
        avr_irq_register_notify(irq, register_written, t);
    }
    return 0;
}

int emu_pwm_attach(avr_t *avr, emu_pin_t pin)
{
    the_avr = avr;
    for (int i = 0; i < 4; i++)
        for (int ch = 0; ch < 3; ch++)
            if (timers[i].oc[ch].port == pin.port && timers[i].oc[ch].bit == pin.bit) {
                state[i].used[ch] = 1;
                if (!state[i].d) {
                    state[i].d = &timers[i];
                    if (watch_timer(avr, &state[i]))
                        return -1;
                }
            }
    return 0;
}

uint64_t emu_pwm_period(emu_pin_t pin)
{
    for (int i = 0; i < 4; i++)
        for (int ch = 0; ch < 3; ch++)
            if (state[i].d && state[i].used[ch] && state[i].running && timers[i].oc[ch].port == pin.port &&
                timers[i].oc[ch].bit == pin.bit)
                return period_cycles(&state[i]);
    return 0;
}
