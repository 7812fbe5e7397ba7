/* SerialRx.h - Serial's input, drained every millisecond into lib's rx_ring (exact accounting of
 * lost input, rx_ring.h), for MotionSerial.
 *
 * The Arduino core keeps received bytes in a 63-byte buffer and drops, without a trace, what
 * arrives while it is full; a sketch busy for more than 65 ms at 9600 baud (5.5 ms at 115200) would
 * lose input and not know where. Here every byte the core has is moved into a 128-byte ring on
 * every pass of loop() (MotionSerial::poll), whatever else the sketch is waiting for, and in the
 * servo and filter sketches also by Timer0's compare-B interrupt (Timer0 already runs for millis(),
 * 976.5625 Hz; compare B is otherwise unused: only analogWrite on D4 would use it), so the core's
 * buffer never fills; if the sketch falls further behind, the ring refuses bytes and records exactly
 * which (rx_ring.h). If the core's buffer is ever found full, that is recorded as a loss too (of one
 * line, the most the board can tell). The interrupt re-enables interrupts in its first instruction
 * (ISR_NOBLOCK); even so its entry can hold a step edge back by about 10 cycles, which at 90,000
 * steps/s made 25 more edges miss their 0.5 us in the bench's reference move: the step-engine
 * sketches, whose loop() never stops for 65 ms, drain from loop() alone. Cost: about 60 cycles per
 * drain with nothing to move, plus about 60 per byte; 138 bytes of SRAM.
 */
#ifndef SERIAL_RX_H
#define SERIAL_RX_H

#include <Arduino.h>

#include <rx_ring.h>

namespace SerialRx {
/* Starts (idempotent; Serial.begin() first). interrupt: also drain from Timer0's compare-B
 * interrupt every 1.024 ms, for a sketch whose loop() may stop longer than the core's buffer lasts
 * (65 ms at 9600 baud); false: only loop() drains (drain(), get()), for the step-engine sketches,
 * whose loop() never stops that long and whose step interrupt should meet no other one. */
void begin(bool interrupt);
/* Moves what the core holds into the ring; loop() calls it on every pass (MotionSerial::poll). */
void drain();
/* The next byte or loss record (rx_ring_get), read safely against the drain. */
rx_event_t get(uint8_t &byte, rx_loss_t &loss);
}

#endif
