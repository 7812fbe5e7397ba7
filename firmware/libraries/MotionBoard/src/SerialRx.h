/* SerialRx.h - Serial's input, drained every millisecond into lib's rx_ring (exact accounting of
 * lost input, rx_ring.h), for MotionSerial.
 *
 * The Arduino core keeps received bytes in a 63-byte buffer and drops, without a trace, what
 * arrives while it is full; a sketch busy for more than 65 ms at 9600 baud (5.5 ms at 115200) would
 * lose input and not know where. Here Timer0's compare-B interrupt (Timer0 already runs for
 * millis(), 976.5625 Hz; compare B is otherwise unused: only analogWrite on D4 would use it) moves
 * every byte the core has into a 128-byte ring, so the core's buffer never fills; if the loop falls
 * further behind, the ring refuses bytes and records exactly which (rx_ring.h). If the core's
 * buffer is ever found full (interrupts held off for tens of ms), that is recorded as a loss too.
 * The interrupt re-enables interrupts in its first instruction (ISR_NOBLOCK): a step interrupt
 * waits for it a few cycles at most. Cost: about 60 cycles per millisecond idle, plus about 60 per
 * byte; 138 bytes of SRAM.
 */
#ifndef SERIAL_RX_H
#define SERIAL_RX_H

#include <Arduino.h>

#include <rx_ring.h>

namespace SerialRx {
/* Starts the drain (idempotent); Serial.begin() must have been called. */
void begin();
/* The next byte or loss record (rx_ring_get), read safely against the drain. */
rx_event_t get(uint8_t &byte, rx_loss_t &loss);
}

#endif
