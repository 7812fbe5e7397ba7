/* ServoConsole.cpp - see ServoConsole.h. */
#include "ServoConsole.h"

#include <stdlib.h>

#include <line_reader.h>
#include <pctrl.h>
#include <text_parse.h>

void ServoConsole::ready(const __FlashStringHelper *sketch_name)
{
    Print &out = serial_.out();
    out.print(F("READY "));
    out.println(sketch_name);
}

void ServoConsole::printReal(Print &out, float v, uint8_t decimals)
{
    char buf[24];
    char *end;
    if (!(v == v)) {
        out.print(F("nan"));
        return;
    }
    if (v > 1e9f || v < -1e9f) {
        out.print(v > 0 ? F("1e9+") : F("-1e9+"));
        return;
    }
    dtostrf(v, 1, decimals, buf);
    end = buf + strlen(buf);
    if (decimals > 0) {
        while (end > buf && end[-1] == '0')
            *--end = '\0';
        if (end > buf && end[-1] == '.')
            *--end = '\0';
    }
    if (strcmp(buf, "-0") == 0)
        strcpy(buf, "0");
    out.print(buf);
}

/* "setpoint=<n> position=<n> error=<n> duty=<%>": the part both lines share. */
static void printPositionFields(Print &out, const ServoState &s)
{
    out.print(F("setpoint="));
    out.print(s.setpoint_counts);
    out.print(F(" position="));
    out.print(s.position_counts);
    out.print(F(" error="));
    out.print(pctrl_error_counts(s.setpoint_counts, s.position_counts));
    out.print(F(" duty="));
    ServoConsole::printReal(out, s.duty_pct, 2);
}

void ServoConsole::queueStatus(uint32_t t_ms, const ServoState &s)
{
    status_t_ms_ = t_ms;
    status_state_ = s;
    status_pending_ = true; /* written by the next poll() that finds room */
}

/* Writes the pending status line if it fits. */
void ServoConsole::flushStatus()
{
    if (!status_pending_ || queue_.room() < STATUS_MAX_BYTES)
        return;
    Print &out = serial_.out();
    out.print(F("t_ms="));
    out.print(status_t_ms_);
    out.print(' ');
    printPositionFields(out, status_state_);
    out.println();
    status_pending_ = false;
}

void ServoConsole::printState(const ServoState &s)
{
    Print &out = serial_.out();
    printPositionFields(out, s);
    out.print(F(" kp="));
    printReal(out, s.kp, 6);
    if (kind_ == PID_GAINS) {
        out.print(F(" ki="));
        printReal(out, s.ki, 6);
        out.print(F(" kd="));
        printReal(out, s.kd, 6);
    }
    out.println();
}

ServoConsole::Event ServoConsole::handleGain(const char *name, const char *value, const char *rest, ServoState &s)
{
    double v = 0;
    motion_status_t st;
    if (value[0] == '\0') {
        serial_.reply_error(MS_ERR_NOT_A_NUMBER, F("usage: kp|ki|kd <value>"));
        return NOTHING;
    }
    if (!text_at_end(rest)) {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("one value after kp|ki|kd"));
        return NOTHING;
    }
    st = text_parse_real(value, -3.0e38, 3.0e38, &v);
    if (st == MS_OK && v < 0)
        st = MS_ERR_GAIN_NEGATIVE;
    if (st != MS_OK) {
        serial_.reply_error(st);
        return NOTHING;
    }
    /* the limit is compared with the decimal (text_parse.h): 1000.00001 is above it */
    if (text_parse_real(value, 0, SERVO_GAIN_MAX, &v) != MS_OK) {
        serial_.reply_error(MS_ERR_OUT_OF_RANGE, F("gains 0..1000"));
        return NOTHING;
    }
    Print &out = serial_.out();
    out.print(F("OK "));
    out.print(name);
    out.print('=');
    if (name[1] == 'p')
        s.kp = (float)v;
    else if (name[1] == 'i')
        s.ki = (float)v;
    else
        s.kd = (float)v;
    printReal(out, (float)v, 6);
    out.println();
    return GAINS_CHANGED;
}

ServoConsole::Event ServoConsole::poll(ServoState &s)
{
    const char *line;
    Event e = NOTHING;
    queue_.pump();
    /* The status line first; no command is read while it waits, so it cannot be starved. At
     * most one line is formatted per pass, which bounds the time a pass can take. */
    if (!status_pending_) {
        line = serial_.poll(); /* reads nothing unless REPLY_MAX_BYTES are free */
        if (line != NULL)
            e = handleLine(line, s);
    } else {
        flushStatus();
    }
    queue_.pump();
    return e;
}

ServoConsole::Event ServoConsole::handleLine(const char *line, ServoState &s)
{
    const char *cursor;
    char word[LINE_READER_MAX + 1], value[LINE_READER_MAX + 1]; /* a word never overflows these */
    int len;
    cursor = line;
    len = text_next_word(&cursor, word, sizeof word);
    if (len < 0) {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND);
        return NOTHING;
    }
    if (text_word_is(word, "?")) {
        if (!text_at_end(cursor)) {
            serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("'?' takes nothing after it"));
            return NOTHING;
        }
        printState(s);
        return NOTHING;
    }
    if ((word[0] >= '0' && word[0] <= '9') || word[0] == '-' || word[0] == '+') {
        int32_t sp = 0;
        motion_status_t st;
        if (!text_at_end(cursor)) {
            serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("one setpoint per line"));
            return NOTHING;
        }
        st = text_parse_int32(word, -SERVO_SETPOINT_MAX_COUNTS, SERVO_SETPOINT_MAX_COUNTS, &sp);
        if (st != MS_OK) {
            serial_.reply_error(st, F("setpoint: whole counts -1000000..1000000"));
            return NOTHING;
        }
        s.setpoint_counts = sp;
        serial_.out().print(F("OK setpoint="));
        serial_.out().println(sp);
        return SETPOINT_CHANGED;
    }
    if (text_word_is(word, "kp") || (kind_ == PID_GAINS && (text_word_is(word, "ki") || text_word_is(word, "kd")))) {
        char name[3] = {word[0], word[1], '\0'};
        len = text_next_word(&cursor, value, sizeof value);
        if (len < 0) {
            serial_.reply_error(MS_ERR_NOT_A_NUMBER);
            return NOTHING;
        }
        return handleGain(name, value, cursor, s);
    }
    if (kind_ == P_ONLY && (text_word_is(word, "ki") || text_word_is(word, "kd"))) {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("the P controller has only kp"));
        return NOTHING;
    }
    serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("try <setpoint>, kp|ki|kd <value>, ?"));
    return NOTHING;
}
