/* ServoSerial.cpp - see ServoSerial.h. */
#include "ServoSerial.h"

#include <stdlib.h>

#include "PrintReal.h"

#include <line_reader.h>
#include <pctrl.h>
#include <text_parse.h>

bool ServoSerial::readCommand(ServoCommand &command)
{
    const char *line;
    bool got = false;
    queue_.pump();
    /* The status line first; no command is read while it waits, so it cannot be starved. */
    if (status_pending_) {
        flushStatus();
    } else {
        line = lines_.poll(); /* reads nothing unless REPLY_MAX_BYTES are free */
        if (line != NULL)
            got = parseLine(line, command);
    }
    queue_.pump();
    return got;
}

void ServoSerial::replyState(int32_t setpoint, int32_t position, float duty, float kp)
{
    printPosition(setpoint, position, duty);
    queue_.print(F(" kp="));
    print_real(queue_, kp, 6);
    queue_.println();
    queue_.pump();
}

void ServoSerial::replyState(int32_t setpoint, int32_t position, float duty, float kp, float ki, float kd)
{
    printPosition(setpoint, position, duty);
    queue_.print(F(" kp="));
    print_real(queue_, kp, 6);
    queue_.print(F(" ki="));
    print_real(queue_, ki, 6);
    queue_.print(F(" kd="));
    print_real(queue_, kd, 6);
    queue_.println();
    queue_.pump();
}

void ServoSerial::printStatus(uint32_t t_ms, int32_t setpoint, int32_t position, float duty)
{
    status_t_ms_ = t_ms;
    status_setpoint_ = setpoint;
    status_position_ = position;
    status_duty_ = duty;
    status_pending_ = true; /* written by the next readCommand() that finds room */
}

/* Writes the pending status line if it fits. */
void ServoSerial::flushStatus()
{
    if (queue_.room() < STATUS_MAX_BYTES)
        return;
    queue_.print(F("t_ms="));
    queue_.print(status_t_ms_);
    queue_.print(' ');
    printPosition(status_setpoint_, status_position_, status_duty_);
    queue_.println();
    status_pending_ = false;
}

/* "setpoint=<n> position=<n> error=<n> duty=<%>": the part the status and `?` lines share. */
void ServoSerial::printPosition(int32_t setpoint, int32_t position, float duty)
{
    queue_.print(F("setpoint="));
    queue_.print(setpoint);
    queue_.print(F(" position="));
    queue_.print(position);
    queue_.print(F(" error="));
    queue_.print(pctrl_error_counts(setpoint, position));
    queue_.print(F(" duty="));
    print_real(queue_, duty, 2);
}

bool ServoSerial::parseLine(const char *line, ServoCommand &command)
{
    const char *cursor = line;
    char word[LINE_READER_MAX + 1], value[LINE_READER_MAX + 1]; /* a word never overflows these */
    if (text_next_word(&cursor, word, sizeof word) < 0) {
        lines_.reply_error(MS_ERR_UNKNOWN_COMMAND);
        return false;
    }
    if (text_word_is(word, "?")) {
        if (!text_at_end(cursor)) {
            lines_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("'?' takes nothing after it"));
            return false;
        }
        command.what = ServoCommand::QUERY;
        return true;
    }
    if ((word[0] >= '0' && word[0] <= '9') || word[0] == '-' || word[0] == '+') {
        int32_t sp = 0;
        motion_status_t st;
        if (!text_at_end(cursor)) {
            lines_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("one setpoint per line"));
            return false;
        }
        st = text_parse_whole(word, -SERVO_SETPOINT_MAX_COUNTS, SERVO_SETPOINT_MAX_COUNTS, &sp);
        if (st != MS_OK) {
            lines_.reply_error(st, F("setpoint: whole counts -1000000..1000000"));
            return false;
        }
        queue_.print(F("OK setpoint="));
        queue_.println(sp);
        command.what = ServoCommand::SETPOINT;
        command.setpoint = sp;
        return true;
    }
    if (text_word_is(word, "move")) {
        if (text_next_word(&cursor, value, sizeof value) < 0) {
            lines_.reply_error(MS_ERR_NOT_A_NUMBER);
            return false;
        }
        return parseMove(value, cursor, command);
    }
    if (text_word_is(word, "kp") || (gains_ == KP_KI_KD && (text_word_is(word, "ki") || text_word_is(word, "kd")))) {
        if (text_next_word(&cursor, value, sizeof value) < 0) {
            lines_.reply_error(MS_ERR_NOT_A_NUMBER);
            return false;
        }
        return parseGain(word, value, cursor, command);
    }
    if (gains_ == KP_ONLY && (text_word_is(word, "ki") || text_word_is(word, "kd"))) {
        lines_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("the P controller has only kp"));
        return false;
    }
    lines_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("try <setpoint>, move <counts>, kp|ki|kd <value>, ?"));
    return false;
}

/* "kp|ki|kd <value>" with nothing after it: 0..1000 -> "OK <name>=<value>". */
bool ServoSerial::parseGain(const char *word, const char *value, const char *rest, ServoCommand &command)
{
    double v = 0;
    motion_status_t st;
    if (value[0] == '\0') {
        lines_.reply_error(MS_ERR_NOT_A_NUMBER, F("usage: kp|ki|kd <value>"));
        return false;
    }
    if (!text_at_end(rest)) {
        lines_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("one value after kp|ki|kd"));
        return false;
    }
    st = text_parse_real(value, -3.0e38, 3.0e38, &v);
    if (st == MS_OK && v < 0)
        st = MS_ERR_GAIN_NEGATIVE;
    if (st != MS_OK) {
        lines_.reply_error(st);
        return false;
    }
    /* the limit is compared with the decimal (text_parse.h): 1000.00001 is above it */
    if (text_parse_real(value, 0, SERVO_GAIN_MAX, &v) != MS_OK) {
        lines_.reply_error(MS_ERR_OUT_OF_RANGE, F("gains 0..1000"));
        return false;
    }
    command.what = word[1] == 'p' ? ServoCommand::KP : word[1] == 'i' ? ServoCommand::KI : ServoCommand::KD;
    command.gain = (float)v;
    queue_.print(F("OK "));
    queue_.print(word);
    queue_.print('=');
    print_real(queue_, command.gain, 6);
    queue_.println();
    return true;
}

/* "move <counts>" with nothing after it: -1000000..1000000 -> "OK move=<n>". */
bool ServoSerial::parseMove(const char *value, const char *rest, ServoCommand &command)
{
    int32_t to = 0;
    motion_status_t st;
    if (value[0] == '\0') {
        lines_.reply_error(MS_ERR_NOT_A_NUMBER, F("usage: move <counts>"));
        return false;
    }
    if (!text_at_end(rest)) {
        lines_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("one target after move"));
        return false;
    }
    st = text_parse_whole(value, -SERVO_SETPOINT_MAX_COUNTS, SERVO_SETPOINT_MAX_COUNTS, &to); /* as the setpoint */
    if (st != MS_OK) {
        lines_.reply_error(st, F("move: whole counts -1000000..1000000"));
        return false;
    }
    queue_.print(F("OK move="));
    queue_.println(to);
    command.what = ServoCommand::MOVE;
    command.setpoint = to;
    return true;
}
