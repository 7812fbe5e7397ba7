/* MotionSerial.h - serial command lines for the sketches (Arduino side of lib/line_reader).
 *
 * Reads whatever bytes Serial has (never blocks), assembles lines ending in CR, LF or CRLF,
 * answers a bad line (too long, non-printable bytes) with "ERR <reason>" at once, and hands
 * complete lines to the sketch. reply_error() prints "ERR <sentence for the status>" with the
 * sentence read from flash, so the sketches' error texts cost no SRAM.
 */
#ifndef MOTION_SERIAL_H
#define MOTION_SERIAL_H

#include <Arduino.h>

#include <line_reader.h>
#include <motion_status.h>

class MotionSerial {
public:
    explicit MotionSerial(Stream &port) : port_(port) { line_reader_init(&reader_); }

    /* Returns the next complete command line (valid until the next call), or NULL when none is
     * waiting. Reads at most max_bytes bytes per call so a flood cannot stall the caller. */
    const char *poll(uint8_t max_bytes = 64);

    /* "ERR <sentence>" */
    void reply_error(motion_status_t status);
    /* "ERR <sentence>: <detail>" with a detail string from flash, e.g. F("set what?") */
    void reply_error(motion_status_t status, const __FlashStringHelper *detail);

    Stream &port() { return port_; }

private:
    Stream &port_;
    line_reader_t reader_;
};

#endif
