/* SerialOutQueue.h - serial output that never blocks: a Print whose bytes go into a RAM queue
 * (lib/src/byte_queue) and reach the port only as fast as the port's own transmit buffer takes
 * them without waiting (Print::availableForWrite(), HardwareSerial's 64-byte ring on the Mega).
 *
 * Why: at 9600 baud one byte takes 1.04 ms; Serial.print() blocks as soon as the 64-byte
 * hardware buffer is full, so a reply meeting the 86-byte status line held loop() (and the 20 ms
 * control step in it): control periods of up to 67 ms were measured in the emulator, 130 ms under
 * a flood of commands. With this queue a print costs only the formatting (a pass of loop() that
 * formats a '?' reply took at most 1.8 ms).
 *
 * Direct mode (set_direct(true): the stepper consoles while an axis steps): pump() hands the port
 * one byte at a time, only when the port's transmit buffer is empty and its data register free
 * (UDRE0), so that HardwareSerial writes it to UDR0 at once and its transmit interrupt never runs.
 * That interrupt costs about 128 cycles a byte (the core's handler saves every register it may
 * use), once a millisecond while a reply goes out at 9600 baud, and it nests in the step
 * interrupts: with three axes at 30,000 steps/s in phase it was the last straw for an edge 287
 * cycles late (make bench, the timing sweep). The price: a byte waits for the next pass of loop()
 * (a pass shorter than a byte's 1.04 ms loses nothing; the chip's second transmit register gives
 * a longer one a byte's grace).
 *
 * Rules for a sketch: call pump() on every pass of loop(); before producing output, check room()
 * and wait (do not read the next command, defer the status line) when the whole line would not
 * fit. A byte that does not fit is dropped and counted (dropped()), never waited for.
 */
#ifndef SERIAL_OUT_QUEUE_H
#define SERIAL_OUT_QUEUE_H

#include <Arduino.h>

#include <byte_queue.h>

#ifndef SERIAL_OUT_QUEUE_BYTES
#define SERIAL_OUT_QUEUE_BYTES 256
#endif

class SerialOutQueue : public Print {
public:
    explicit SerialOutQueue(Print &port) : port_(port), direct_(false) { (void)byte_queue_init(&q_, buf_, sizeof buf_); }

    virtual size_t write(uint8_t b) { return byte_queue_put(&q_, b); }
    using Print::write;

    /* Moves queued bytes to the port while it can take them without blocking. */
    void pump();

    uint16_t room() const { return byte_queue_room(&q_); }
    uint16_t queued() const { return byte_queue_count(&q_); }
    uint16_t dropped() const { return q_.dropped; }
    /* Direct mode (above): the bytes go to the port one per pump(), without its transmit interrupt. */
    void set_direct(bool on) { direct_ = on; }

private:
    Print &port_;
    bool direct_;
    byte_queue_t q_;
    uint8_t buf_[SERIAL_OUT_QUEUE_BYTES];
};

#endif
