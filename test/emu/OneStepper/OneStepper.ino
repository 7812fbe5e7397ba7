/* OneStepper - a test sketch for `make bench` (tools/bench/bench.py, "The MotionStepper library, one
 * Stepper"): the RAMPS X axis as a Stepper with the exact ramp (Timer3 plans in the background,
 * Timer1 steps), driven from the serial line as a maker's sketch would drive it, so that the bench
 * can run the stepper sketches' reference move on the library. 9600 baud, lines as the sketches':
 *   set vmax|accel|v0 <value>   "OK <key>" or "ERR <the library's sentence>"
 *   <target>                    moveTo: "OK <position> <target>", later "DONE <position>"
 *   ?                           pos= algo=exact v0= vmax= accel= tick_hz=16000000 underruns=
 * Built by the bench with its speed limit lifted (-DMULTI_MAX_SPS=...). Not an example: its replies
 * are only what the bench reads.
 */
#include <MotionStepper.h>
#include <MotionSerial.h>
#include <PrintReal.h>
#include <text_parse.h>

Stepper x(Stepper::X);
static MotionSerial serial(Serial);

static void handle(const char *line)
{
    const char *cursor = line;
    char word[LINE_READER_MAX + 1], key[LINE_READER_MAX + 1];
    int32_t target;
    double v = 0.0;
    motion_status_t st;
    if (text_next_word(&cursor, word, sizeof word) <= 0)
        return;
    if (text_word_is(word, "?")) {
        Serial.print(F("pos="));
        Serial.print(x.currentPosition());
        Serial.print(F(" algo=exact v0="));
        print_real_exact(Serial, x.minSpeed(), 0);
        Serial.print(F(" vmax="));
        print_real_exact(Serial, x.maxSpeed(), 0);
        Serial.print(F(" accel="));
        print_real_exact(Serial, x.acceleration(), 0);
        Serial.print(F(" tick_hz=16000000 underruns="));
        Serial.println(x.underruns());
        return;
    }
    if (text_word_is(word, "set")) {
        if (text_next_word(&cursor, key, sizeof key) <= 0 || text_next_word(&cursor, word, sizeof word) <= 0 ||
            !text_at_end(cursor)) {
            serial.reply_error(MS_ERR_UNKNOWN_COMMAND, F("set vmax|accel|v0 <value>"));
            return;
        }
        st = text_parse_real(word, -1e30, 1e30, &v);
        if (st == MS_OK)
            st = text_word_is(key, "vmax")    ? x.setMaxSpeed((float)v)
                 : text_word_is(key, "accel") ? x.setAcceleration((float)v)
                 : text_word_is(key, "v0")    ? x.setMinSpeed((float)v)
                                              : MS_ERR_UNKNOWN_COMMAND;
        if (st != MS_OK) {
            serial.reply_error(st);
            return;
        }
        Serial.print(F("OK "));
        Serial.println(key);
        return;
    }
    st = text_at_end(cursor) ? text_parse_whole(word, INT32_MIN, INT32_MAX, &target) : MS_ERR_NOT_A_NUMBER;
    if (st == MS_OK)
        st = x.moveTo(target);
    if (st != MS_OK) {
        serial.reply_error(st);
        return;
    }
    Serial.print(F("OK "));
    Serial.print(x.currentPosition());
    Serial.print(' ');
    Serial.println(target);
}

void setup()
{
    Serial.begin(9600);
    x.begin();
    Serial.println(F("READY OneStepper"));
}

void loop()
{
    long at;
    const char *line = serial.poll();
    if (line != NULL)
        handle(line);
    if (x.takeDone(at)) {
        Serial.print(F("DONE "));
        Serial.println(at);
    }
}
