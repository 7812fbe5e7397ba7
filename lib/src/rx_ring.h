/* rx_ring.h - the serial input between the receive interrupt side and the command reader, with
 * exact accounting of lost input. Pure logic: the board (MotionBoard's SerialRx) moves every byte
 * the UART received into it from a timer interrupt (rx_ring_put), and the sketch's reader takes
 * them in loop() (rx_ring_get); motionsim and the unit tests drive it the same way.
 *
 * Why: the Arduino core drops, silently, every byte that arrives while its 63-byte receive buffer
 * is full, so a sketch that reads late cannot tell which bytes were lost, nor whether any were. A
 * drain that runs every millisecond keeps the core's buffer from ever filling (at 9600 baud one
 * byte arrives per millisecond, at 115200 about 12), and the one place left where input can be lost
 * is this ring, which knows exactly which bytes it refused.
 *
 * A loss record: when a byte finds the ring full it is counted, not stored. The record holds where
 * in the stream the first lost byte belonged (before the byte stored next), how many line ends
 * (CR, or LF not right after CR) were among the lost bytes, and whether the last lost byte ended a
 * line. Further losses before the reader has reached the record extend it: the bytes stored
 * between them belong to the damaged stretch too (their line ends are counted as well, and the
 * reader skips them). When the reader reaches the record, rx_ring_get returns RX_LOSS with
 *     lines = the lines the stretch touched: every line end in it, plus one for the line that goes
 *             on past it unless the stretch ended a line,
 * and positions the stream after the stretch; `cont` says the line that follows continues a damaged
 * line (its rest up to its terminator must be discarded, it is counted in `lines` already) and
 * `after_cr` that the stretch ended in CR (a following LF is the rest of CR LF). The line in
 * progress when the stretch began is one of `lines`: the reader discards it.
 * A blank line inside the stretch is counted as a line (the ring cannot know it was blank).
 *
 * Concurrency: one producer (an interrupt) and one consumer (loop()). Indices are 8-bit and only
 * the producer writes `tail`, only the consumer `head`. rx_ring_get reads the loss record while the
 * producer may extend it: the caller runs rx_ring_get with the producer's interrupt held off (a few
 * dozen cycles) or only when rx_ring_loss_ahead() says no record is waiting at the head.
 * Cost: put about 30 cycles, get about 25 on the AVR; SRAM RX_RING_BYTES + 10.
 */
#ifndef RX_RING_H
#define RX_RING_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define RX_RING_BYTES 128U /* a power of two, at most 128 (8-bit free-running indices) */

typedef struct {
    uint8_t buf[RX_RING_BYTES];
    volatile uint8_t head; /* consumer: bytes taken (free-running) */
    volatile uint8_t tail; /* producer: bytes stored (free-running) */
    /* the loss record, written by the producer, taken (cleared) by the consumer */
    volatile uint8_t lost;       /* a record is waiting */
    volatile uint8_t lost_start; /* tail when the first byte of the stretch was lost */
    volatile uint8_t lost_end;   /* tail when the last one was */
    volatile uint8_t lost_clean; /* the last lost byte ended a line (CR or LF) */
    volatile uint8_t lost_cr;    /* ... and it was CR */
    volatile uint16_t lost_ends; /* line ends among the lost bytes (saturates) */
    volatile uint8_t ends_after; /* line ends stored since the last lost byte (saturates) */
    uint8_t put_cr;              /* producer: the last byte put was CR */
} rx_ring_t;

typedef enum {
    RX_NONE = 0, /* nothing waiting */
    RX_BYTE,     /* *byte is the next byte */
    RX_LOSS      /* input was lost here: *loss says how much */
} rx_event_t;

typedef struct {
    uint16_t lines;   /* lines the lost stretch touched (see above) */
    uint8_t cont;     /* the bytes that follow are the rest of a damaged line */
    uint8_t after_cr; /* the stretch ended in CR */
} rx_loss_t;

void rx_ring_init(rx_ring_t *r);

/* Producer: stores byte, or counts it lost (0) when the ring is full. */
uint8_t rx_ring_put(rx_ring_t *r, uint8_t byte);

/* Producer: input may have been lost before the next byte put, contents unknown (the board's
 * UART buffer was found full): a loss record of one damaged line. */
void rx_ring_mark_loss(rx_ring_t *r);

/* Bytes waiting. */
uint8_t rx_ring_count(const rx_ring_t *r);

/* A loss record waits at the head (rx_ring_get would return RX_LOSS). */
uint8_t rx_ring_loss_ahead(const rx_ring_t *r);

/* Consumer: the next byte, a loss, or nothing (see above for when to hold the producer off). */
rx_event_t rx_ring_get(rx_ring_t *r, uint8_t *byte, rx_loss_t *loss);

#ifdef __cplusplus
}
#endif

#endif
