/* emu_timer.c - keeps simavr's 16-bit timers from losing the compare match of a register armed for
 * the first few ticks after the timer's next wrap.
 *
 * Why: libsimavr 1.6 schedules a channel's compare event when OCRnx is written (if its time lies
 * ahead in the current timer period) or at the overflow, for the period that starts then. At the
 * overflow it keeps only events still ahead of the moment it runs, and it runs between
 * instructions, up to a few cycles after the wrap: a compare register written before the wrap with
 * a value of 0..3 or so (its match due right after the wrap) is dropped, and the channel next
 * matches one wrap (65,536 ticks at 16 MHz, 4.1 ms) later. The real ATmega2560 has no such loss: its
 * comparators run in hardware. The step engines meet it about once in 16,000 edges (an edge whose
 * tick lands at the start of a timer period): an edge one wrap late.
 * How: the write handler of every OCRnxL (the byte whose write takes the 16-bit value) of Timers 1,
 * 3, 4 and 5 is wrapped. Due events are processed first (so the timer's period is current), then
 * simavr's own handler runs; if the new match lies within the first 16 cycles of the next period,
 * the compare interrupt is also raised at exactly that cycle here (raising it twice at one cycle sets
 * one flag). A later write to the register withdraws that event.
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
    simavr_write[i].c(avr, addr, v, simavr_write[i].param);
    if (t->wgm_op_mode_kind == avr_timer_wgm_normal && t->tov_cycles > EARLY_CYCLES && comp->comp_cycles != 0 &&
        comp->comp_cycles <= EARLY_CYCLES && avr->cycle - t->tov_base >= comp->comp_cycles) {
        /* the match is in the next period, right after the wrap */
        avr_cycle_timer_register(avr, t->tov_base + t->tov_cycles + comp->comp_cycles - avr->cycle, raise_compare,
                                 comp);
    }
}

int emu_timer_attach(avr_t *avr)
{
    for (uintptr_t i = 0; i < N_OCR; i++) {
        uint16_t io = (uint16_t)(ocr_low[i] - 0x20); /* simavr's io[] index: data address - 0x20 */
        if (io >= MAX_IOs || avr->io[io].w.c == 0 || avr->io[io].w.param == 0)
            return -1;
        simavr_write[i].c = avr->io[io].w.c;
        simavr_write[i].param = avr->io[io].w.param;
        avr->io[io].w.c = ocr_write;
        avr->io[io].w.param = (void *)i;
    }
    return 0;
}
