/* emu_timer.c - two corrections to libsimavr 1.6's timers, where it differs from the ATmega2560 and
 * the step engines meet the difference (a step one timer wrap, 65,536 ticks = 4.1 ms, late):
 *
 * 1. A compare match right after a wrap. simavr schedules a channel's compare event when OCRnx is
 *    written (if its time lies ahead in the current timer period) or at the overflow, for the
 *    period that starts then. At the overflow it keeps only events still ahead of the moment it
 *    runs, and it runs between instructions, up to a few cycles after the wrap: a compare register
 *    written before the wrap with a value of 0..3 or so is dropped until the next wrap. The chip's
 *    comparators run in hardware and lose nothing. Fix: the write handler of every OCRnxL (the byte
 *    whose write takes the 16-bit value) of Timers 1, 3, 4 and 5 is wrapped: due events are
 *    processed first (so the timer's period is current), then simavr's own handler runs; if the new
 *    match lies within the first 16 cycles of the next period, the compare interrupt is also raised
 *    at exactly that cycle here (raising it twice at one cycle sets one flag). A later write to the
 *    register withdraws that event.
 * 2. Writing TIFRn. On the chip a 1 clears that flag and a 0 leaves it alone (datasheet, "TIFRn");
 *    simavr clears every pending flag of the timer whatever the value, so a sketch that clears one
 *    channel's flag (TIFR1 = _BV(OCF1B)) loses another channel's pending match. Fix: the flags the
 *    written value leaves alone are raised again right after simavr's handler.
 * 3. A compare match right after a wrap that recurs, its compare value unchanged (a step engine
 *    counting the wraps of a long interval). At each overflow simavr schedules the new period's
 *    compare event only if it still lies ahead when its overflow handler runs, up to a few cycles
 *    after the wrap: a compare value of 0..3 or so is skipped for that period, and the step came a
 *    whole wrap late (make fuzz, seed 6: MultiAxisStepper's Y counting 13 wraps of a 56 ms
 *    interval with OCR1B = 1: one wrap lost, the step 4.1 ms late). Fix: EARLY_CYCLES + 1 cycles
 *    into every period of a timer in normal mode, a channel whose match lies within the first
 *    EARLY_CYCLES cycles, whose register was not written since the wrap (fix 1 covers those) and
 *    that has not matched since, has its compare interrupt raised then (the match log puts it at
 *    the cycle of the match).
 * And, on request (motionemu --matches), a log line for every compare match of Timer1's channels
 * (the time a step engine planned an edge for): "match <cycle> OC1A|OC1B|OC1C", the cycle the timer
 * reached the compare value (simavr raises it at the next instruction boundary, a few cycles on).
 */
#include <stdint.h>

#include <avr_timer.h>
#include <sim_avr.h>
#include <sim_cycle_timers.h>
#include <sim_interrupts.h>

#include "emu.h"

/* OCRnAL, OCRnBL, OCRnCL of Timers 1, 3, 4, 5 (data addresses, ATmega2560 datasheet's register summary) */
static const uint16_t ocr_low[] = {0x88, 0x8A, 0x8C, 0x98, 0x9A, 0x9C, 0xA8, 0xAA, 0xAC, 0x128, 0x12A, 0x12C};
#define N_OCR (sizeof ocr_low / sizeof ocr_low[0])
/* matches due this early in a period are the ones simavr's overflow can drop */
#define EARLY_CYCLES 16U

static struct {
    avr_io_write_t c;
    void *param; /* simavr's avr_timer_comp_t of the channel */
} simavr_write[N_OCR];

/* per channel, for fix 3: the cycles of its register's last write and of its last compare match */
static struct {
    avr_t *avr;
    uint64_t written, matched;
} chan[N_OCR];

static avr_cycle_count_t raise_compare(struct avr_t *avr, avr_cycle_count_t when, void *param)
{
    (void)when;
    avr_raise_interrupt(avr, &((avr_timer_comp_t *)param)->interrupt);
    return 0;
}

static void ocr_write(struct avr_t *avr, avr_io_addr_t addr, uint8_t v, void *param)
{
    uintptr_t i = (uintptr_t)param;
    avr_timer_comp_t *comp = simavr_write[i].param;
    avr_timer_t *t = comp->timer;
    avr_cycle_timer_process(avr);
    avr_cycle_timer_cancel(avr, raise_compare, comp);
    chan[i].written = avr->cycle;
    simavr_write[i].c(avr, addr, v, simavr_write[i].param);
    if (t->wgm_op_mode_kind == avr_timer_wgm_normal && t->tov_cycles > EARLY_CYCLES && comp->comp_cycles != 0 &&
        comp->comp_cycles <= EARLY_CYCLES && avr->cycle - t->tov_base >= comp->comp_cycles) {
        /* the match is in the next period, right after the wrap */
        avr_cycle_timer_register(avr, t->tov_base + t->tov_cycles + comp->comp_cycles - avr->cycle, raise_compare,
                                 comp);
    }
}

static int reraising; /* tifr_write is raising kept flags again: not compare matches */

/* TIFR0..TIFR5 (data addresses) */
static const uint16_t tifr[] = {0x35, 0x36, 0x37, 0x38, 0x39, 0x3A};
#define N_TIFR (sizeof tifr / sizeof tifr[0])

static struct {
    avr_io_write_t c;
    void *param; /* simavr's avr_timer_t */
} simavr_tifr[N_TIFR];

/* the vector's flag is set and the written value leaves it alone */
static int kept(struct avr_t *avr, const avr_int_vector_t *vec, uint8_t v)
{
    return vec->raised.reg != 0 && avr_regbit_get(avr, vec->raised) && !(v & (vec->raised.mask << vec->raised.bit));
}

static void tifr_write(struct avr_t *avr, avr_io_addr_t addr, uint8_t v, void *param)
{
    uintptr_t i = (uintptr_t)param;
    avr_timer_t *t = simavr_tifr[i].param;
    int keep_ov = kept(avr, &t->overflow, v), keep_ic = kept(avr, &t->icr, v);
    int keep_comp[AVR_TIMER_COMP_COUNT];
    for (int c = 0; c < AVR_TIMER_COMP_COUNT; c++)
        keep_comp[c] = kept(avr, &t->comp[c].interrupt, v);
    simavr_tifr[i].c(avr, addr, v, simavr_tifr[i].param);
    reraising = 1; /* not matches: flags that were set already */
    if (keep_ov)
        avr_raise_interrupt(avr, &t->overflow);
    if (keep_ic)
        avr_raise_interrupt(avr, &t->icr);
    for (int c = 0; c < AVR_TIMER_COMP_COUNT; c++)
        if (keep_comp[c])
            avr_raise_interrupt(avr, &t->comp[c].interrupt);
    reraising = 0;
}

/* Timer1's three channels (OCR1AL, OCR1BL, OCR1CL are ocr_low[0..2]) */
static struct match_watch {
    avr_t *avr;
    avr_timer_comp_t *comp;
    const char *name;
} match_watch[3];

static void match_raised(struct avr_irq_t *irq, uint32_t value, void *param)
{
    struct match_watch *w = param;
    avr_timer_t *t = w->comp->timer;
    uint64_t at = w->avr->cycle, exact = t->tov_base + w->comp->comp_cycles;
    (void)irq;
    if (!value || reraising)
        return;
    if (exact > at && exact - t->tov_cycles <= at)
        exact -= t->tov_cycles; /* a match at the very end of the last period, seen after the wrap */
    if (exact <= at && at - exact <= EARLY_CYCLES)
        at = exact; /* the cycle of the match itself */
    emu_log(at, "match", "%s", w->name);
}

int emu_timer_log_matches(avr_t *avr)
{
    static const char *const names[3] = {"OC1A", "OC1B", "OC1C"};
    for (int c = 0; c < 3; c++) {
        avr_timer_comp_t *comp = simavr_write[c].param;
        if (comp == 0)
            return -1;
        match_watch[c].avr = avr;
        match_watch[c].comp = comp;
        match_watch[c].name = names[c];
        avr_irq_register_notify(&comp->interrupt.irq[AVR_INT_IRQ_PENDING], match_raised, &match_watch[c]);
    }
    return 0;
}

static void chan_matched(struct avr_irq_t *irq, uint32_t value, void *param)
{
    uintptr_t i = (uintptr_t)param;
    (void)irq;
    if (value && !reraising)
        chan[i].matched = chan[i].avr->cycle;
}

/* fix 3, for the timer of channels first..first+2: runs EARLY_CYCLES + 1 cycles into each period */
static avr_cycle_count_t early_check(struct avr_t *avr, avr_cycle_count_t when, void *param)
{
    uintptr_t first = (uintptr_t)param;
    avr_timer_t *t = ((avr_timer_comp_t *)simavr_write[first].param)->timer;
    (void)when;
    if (t->tov_cycles == 0 || t->tov_base == 0)
        return avr->cycle + 1024U; /* not running yet */
    if (t->wgm_op_mode_kind == avr_timer_wgm_normal && t->tov_cycles > EARLY_CYCLES) {
        for (uintptr_t i = first; i < first + 3U; i++) {
            avr_timer_comp_t *comp = simavr_write[i].param;
            if (comp->comp_cycles != 0 && comp->comp_cycles <= EARLY_CYCLES &&
                avr->cycle >= t->tov_base + comp->comp_cycles && chan[i].written < t->tov_base &&
                chan[i].matched < t->tov_base)
                avr_raise_interrupt(avr, &comp->interrupt);
        }
    }
    if (t->tov_base + EARLY_CYCLES + 1U > avr->cycle)
        return t->tov_base + EARLY_CYCLES + 1U; /* this period's check is still to come */
    return t->tov_base + t->tov_cycles + EARLY_CYCLES + 1U;
}

int emu_timer_attach(avr_t *avr)
{
    for (uintptr_t i = 0; i < N_TIFR; i++) {
        uint16_t io = (uint16_t)(tifr[i] - 0x20);
        if (avr->io[io].w.c == 0 || avr->io[io].w.param == 0)
            return -1;
        simavr_tifr[i].c = avr->io[io].w.c;
        simavr_tifr[i].param = avr->io[io].w.param;
        avr->io[io].w.c = tifr_write;
        avr->io[io].w.param = (void *)i;
    }
    for (uintptr_t i = 0; i < N_OCR; i++) {
        uint16_t io = (uint16_t)(ocr_low[i] - 0x20); /* simavr's io[] index: data address - 0x20 */
        if (io >= MAX_IOs || avr->io[io].w.c == 0 || avr->io[io].w.param == 0)
            return -1;
        simavr_write[i].c = avr->io[io].w.c;
        simavr_write[i].param = avr->io[io].w.param;
        avr->io[io].w.c = ocr_write;
        avr->io[io].w.param = (void *)i;
        chan[i].avr = avr;
        avr_irq_register_notify(&((avr_timer_comp_t *)simavr_write[i].param)->interrupt.irq[AVR_INT_IRQ_PENDING],
                                chan_matched, (void *)i);
    }
    for (uintptr_t first = 0; first < N_OCR; first += 3)
        avr_cycle_timer_register(avr, 1024U, early_check, (void *)first);
    return 0;
}
