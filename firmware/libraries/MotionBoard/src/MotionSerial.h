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
 * the sketch's own replies, which must print to out()) always fits: input waits in the port's
 * receive buffer instead of output blocking the loop (the servo sketches).
 *
 * The rules every console built on it follows (docs/serial.md): a blank line (empty or only
 * spaces/tabs) is no line and gets no reply; every other line gets exactly one reply. Receive
 * overrun: Serial's receive buffer holds SERIAL_RX_BUFFER_SIZE - 1 = 63 bytes on the Mega and the
 * core drops, silently, every byte that arrives while it is full. poll() checks for a full buffer
 * before it reads; when it finds one, the bytes up to that point are intact, and the line that
 * goes on past it (the one in progress there, or the next) may have lost bytes: it is answered
 * "ERR input overrun" once, when its first byte past the point is read, and not executed (its rest
 * is discarded up to its terminator). Lines lost whole get no reply. A host that sends the next
 * line only after the reply to the previous one never fills the buffer.
 */
#ifndef MOTION_SERIAL_H
#define MOTION_SERIAL_H

#include <Arduino.h>

#include <line_reader.h>
#include <motion_status.h>

#include "SerialOutQueue.h"

class MotionSerial {
public:
    explicit MotionSerial(Stream &port)
        : port_(port), out_(port), queue_(0), reserve_(0), rx_full_(DEFAULT_RX_FULL), first_left_(0),
          last_left_(0), pending_(0)
    {
        line_reader_init(&reader_);
    }
    /* Replies through queue; input is read only while queue->room() >= reply_reserve_bytes. */
    MotionSerial(Stream &port, SerialOutQueue &queue, uint16_t reply_reserve_bytes)
        : port_(port), out_(queue), queue_(&queue), reserve_(reply_reserve_bytes), rx_full_(DEFAULT_RX_FULL),
          first_left_(0), last_left_(0), pending_(0)
    {
        line_reader_init(&reader_);
    }

    /* Bytes port.available() reports when its receive buffer is full (overrun detection above).
     * Default: a HardwareSerial port's SERIAL_RX_BUFFER_SIZE - 1; 0 turns the detection off (for
     * a Stream that never drops input). */
    void set_rx_full_bytes(uint8_t n) { rx_full_ = n; }

    /* Returns the next complete command line (valid until the next call), or NULL when none is
     * waiting. Reads at most max_bytes bytes per call so a flood cannot stall the caller, and
     * with a queue none while its room is below the reserve. */
    const char *poll(uint8_t max_bytes = 64);

    /* "ERR <sentence>" */
    void reply_error(motion_status_t status);
    /* "ERR <sentence>: <detail>" with a detail string from flash, e.g. F("set what?") */
    void reply_error(motion_status_t status, const __FlashStringHelper *detail);
    /* Prints "ERR <sentence>: " and returns out() for a detail the caller formats, then println(). */
    Print &begin_error(motion_status_t status);

    Stream &port() { return port_; }
    /* Where replies go: the queue if there is one, else the port. */
    Print &out() { return out_; }

private:
#ifdef SERIAL_RX_BUFFER_SIZE
    static const uint8_t DEFAULT_RX_FULL = (uint8_t)(SERIAL_RX_BUFFER_SIZE - 1);
#else
    static const uint8_t DEFAULT_RX_FULL = 63;
#endif
    void check_overrun(int avail);
    /* Counts one byte read; true when bytes may have been lost just before it. */
    bool lost_before_next();

    Stream &port_;
    Print &out_;
    SerialOutQueue *queue_;
    uint16_t reserve_;
    uint8_t rx_full_;
    /* Bytes still to read before a point where input may have been lost: the first such point
     * (pending_ bit 0) and the latest one found after it (bit 1). */
    uint8_t first_left_, last_left_;
    uint8_t pending_;
    line_reader_t reader_;
};

#endif
