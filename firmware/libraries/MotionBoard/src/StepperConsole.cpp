/* StepperConsole.cpp - the stepper sketches' serial protocol (see StepperConsole.h). */
#include "StepperConsole.h"

#include <line_reader.h>
#include <text_parse.h>

void StepperConsole::begin(const __FlashStringHelper *sketch_name)
{
    Serial.begin(9600);
    StepperDriver::begin();
    target_ = StepperDriver::position();
    Serial.print(F("READY "));
    Serial.println(sketch_name);
}

void StepperConsole::poll()
{
    int32_t done_at;
    const char *line;
    StepperDriver::poll();
    if (StepperDriver::take_done(done_at)) {
        Serial.print(F("DONE "));
        Serial.println(done_at);
    }
    line = serial_.poll();
    if (line != NULL)
        handle(line);
}

void StepperConsole::handle(const char *line)
{
    const char *cursor = line;
    char word[LINE_READER_MAX + 1];
    int n = text_next_word(&cursor, word, sizeof word);
    if (n == 0)
        return; /* a line of blanks: nothing to do */
    if (text_word_is(word, "?")) {
        if (!text_at_end(cursor))
            serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("'?' takes no arguments"));
        else
            reply_status();
    } else if (text_word_is(word, "set")) {
        handle_set(cursor);
    } else if ((word[0] >= '0' && word[0] <= '9') || word[0] == '-' || word[0] == '+') {
        if (!text_at_end(cursor))
            serial_.reply_error(MS_ERR_NOT_A_NUMBER, F("one target per line"));
        else
            handle_target(word);
    } else {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("try <target>, ?, set v0|vmax|accel <value>"));
    }
}

void StepperConsole::handle_target(const char *word)
{
    int32_t to, from;
    ramp_t plan;
    motion_status_t st = text_parse_int32(word, INT32_MIN, INT32_MAX, &to);
    if (st != MS_OK) {
        serial_.reply_error(st, F("a target is a whole number of steps, -2147483648..2147483647"));
        return;
    }
    if (StepperDriver::busy()) {
        serial_.reply_error(MS_ERR_BUSY);
        return;
    }
    from = StepperDriver::position();
    st = ramp_.plan(plan, from, to);
    if (st != MS_OK) {
        serial_.reply_error(st);
        return;
    }
    target_ = to;
    StepperDriver::start(plan);
    Serial.print(F("OK "));
    Serial.print(from);
    Serial.print(' ');
    Serial.println(to);
}

void StepperConsole::handle_set(const char *cursor)
{
    char key[LINE_READER_MAX + 1], value[LINE_READER_MAX + 1];
    motion_status_t st;
    if (StepperDriver::busy()) {
        serial_.reply_error(MS_ERR_BUSY);
        return;
    }
    if (text_next_word(&cursor, key, sizeof key) <= 0) {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("set what? set <parameter> <value>"));
        return;
    }
    if (text_next_word(&cursor, value, sizeof value) <= 0) {
        serial_.reply_error(MS_ERR_NOT_A_NUMBER, F("set <parameter> <value>: the value is missing"));
        return;
    }
    if (!text_at_end(cursor)) {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("set takes one parameter and one value"));
        return;
    }
    st = ramp_.set(key, value);
    if (st == MS_ERR_UNKNOWN_COMMAND) {
        serial_.reply_error(st, F("no such parameter (see ?)"));
        return;
    }
    if (st == MS_ERR_OUT_OF_RANGE) {
        /* "ERR number out of range: vmax at most 5000 steps/s on this sketch" */
        ramp_.print_limit(serial_.begin_error(st), key);
        serial_.out().println();
        return;
    }
    if (st != MS_OK) {
        serial_.reply_error(st);
        return;
    }
    Serial.print(F("OK "));
    ramp_.print_param(Serial, key);
    Serial.println();
}

void StepperConsole::reply_status()
{
    Serial.print(F("pos="));
    Serial.print(StepperDriver::position());
    Serial.print(F(" target="));
    Serial.print(target_);
    Serial.print(F(" state="));
    Serial.print(ramp_phase_name(StepperDriver::phase()));
    ramp_.print_params(Serial);
#if STEPPER_TIMED_LOOP
    Serial.println(F(" mode=loop"));
#else
    Serial.println(F(" mode=timer"));
#endif
}
