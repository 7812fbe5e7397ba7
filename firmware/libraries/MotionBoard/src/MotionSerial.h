/* MotionSerial.h - serial command lines for the sketches (Arduino side of lib/line_reader).
 *
 * Reads whatever bytes Serial has (never blocks), assembles lines ending in CR, LF or CRLF,
 * answers a bad line (too long, non-printable bytes) with "ERR <reason>" at once, and hands
 * complete lines to the sketch. reply_error() prints "ERR <sentence for the status>" with the
 * sentence read from flash, so the sketches' error texts cost no SRAM.
 *
 * Two ways to reply. MotionSerial(Serial): replies are printed straight to the port (they block
 * while the port's transmit buffer is full; the stepper and filter sketches). MotionSerial(Serial,
 * queue, reserve): replies go into a SerialOutQueue and poll() reads no byte while the queue has
 * less than `reserve` bytes free, so every reply a command can draw (the line errors here, and
 * the sketch's own replies, which must print to out()) always fits: input waits in the
 * SerialRx ring instead of output blocking the loop (the servo and stepper sketches).
 *
 * The rules every console built on it follows (docs/serial.md): a blank line (empty or only
 * spaces/tabs) is no line and gets no reply; every other line gets exactly one reply, or is counted
 * in an "ERR input overrun: N lines lost" reply. Input comes from Serial through SerialRx, which
 * moves the core's 63-byte receive buffer into a 128-byte ring on every poll() (and every
 * millisecond from an interrupt unless set_rx_interrupt(false)); the ring knows exactly which
 * bytes it had to refuse (lib/src/rx_ring.h). When the reader reaches a place where
 * input was lost it answers at once, before any later line: "ERR input overrun: <N> line(s) lost",
 * N the lines the loss touched (the line in progress, every line lost whole, and the line that goes
 * on past it, whose rest is discarded up to its terminator; a line already answered as bad is not
 * counted again). None of them is executed. A host that sends the next line only after the reply to
 * the previous one, or keeps fewer than 128 + 63 bytes in flight, never loses any.
 */
#ifndef MOTION_SERIAL_H
#define MOTION_SERIAL_H

#include <Arduino.h>

#include <line_reader.h>
#include <motion_status.h>

#include "SerialOutQueue.h"
#include "SerialRx.h"

class MotionSerial {
public:
    explicit MotionSerial(Stream &port)
        : port_(port), out_(port), queue_(0), reserve_(0), started_(false), rx_interrupt_(true)
    {
        line_reader_init(&reader_);
    }
    /* Replies through queue; input is read only while queue->room() >= reply_reserve_bytes. */
    MotionSerial(Stream &port, SerialOutQueue &queue, uint16_t reply_reserve_bytes)
        : port_(port), out_(queue), queue_(&queue), reserve_(reply_reserve_bytes), started_(false),
          rx_interrupt_(true)
    {
        line_reader_init(&reader_);
    }

    /* Returns the next complete command line (valid until the next call), or NULL when none is
     * waiting. Reads at most max_bytes bytes per call so a flood cannot stall the caller, and
     * with a queue none while its room is below the reserve. The first call starts SerialRx. */
    const char *poll(uint8_t max_bytes = 64);

    /* Before the first poll(): false = input drained by poll() alone, no interrupt (SerialRx.h;
     * the step-engine sketches, which call poll() on every pass of a loop() that never stops). */
    void set_rx_interrupt(bool on) { rx_interrupt_ = on; }

    /* Moves received input into the ring without reading a line: for a pass of loop() that does
     * not call poll() (a console busy printing), so that the core's buffer never fills. */
    void drain_input();

    /* "ERR <sentence>" */
    void reply_error(motion_status_t status);
    /* "ERR <sentence>: <detail>" with a detail string from flash, e.g. F("set what?") */
    void reply_error(motion_status_t status, const __FlashStringHelper *detail);
    /* Prints "ERR <sentence>: " and returns out() for a detail the caller formats, then println(). */
    Print &begin_error(motion_status_t status);

    Stream &port() { return port_; }
    /* Where replies go: the queue if there is one, else the port. (Input always comes from
     * Serial, through SerialRx.) */
    Print &out() { return out_; }

private:
    Stream &port_;
    Print &out_;
    SerialOutQueue *queue_;
    uint16_t reserve_;
    bool started_; /* SerialRx::begin() done (on the first poll, after the sketch's Serial.begin) */
    bool rx_interrupt_;
    line_reader_t reader_;
};

#endif
