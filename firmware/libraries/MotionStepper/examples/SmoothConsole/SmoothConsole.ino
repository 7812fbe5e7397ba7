/* SmoothConsole - jerk-limited moves of the RAMPS X axis from the Serial Monitor: the smooth ramp
 * (setRamp(RAMP_ALGO_SMOOTH): the velocity command through the moving-average-filter note's two
 * moving averages, tau1 = vmax/accel, tau2 = accel/jerk) with the stepper sketches' commands and
 * `set jerk`. Serial Monitor at 115200 baud, any line ending:
 *   20000              move to absolute position 20000: "OK 20000", later "DONE 20000"; sent while
 *                      moving, the move goes on from its speed and acceleration to the new target
 *                      (or stops and comes back, for one behind); the replaced move gets no DONE
 *   stop               the velocity command goes to 0: "OK stop", later "DONE <position>"
 *   !                  halt now, no further step: "OK halt", later "DONE <position>"
 *                      (at rest: "OK stop (not moving)", "OK halt (not moving)", no DONE)
 *   ?                  pos= target= state=idle|moving speed= algo=smooth vmax= accel= jerk=
 *                      max_sps= underruns=
 *   set jerk 200000    also vmax and accel: "OK jerk=200000"; sent while moving, from the next move
 *                      from rest (the move in progress keeps its own)
 * A refused line gets "ERR <reason>" (the library's sentences, Stepper::statusText) and changes
 * nothing: a jerk of 0, "nan", a jerk below accel^2/vmax (tau2 longer than tau1), a vmax above the
 * smooth ramp's limit (max_sps), a target that is not one whole number. A target the planner cannot
 * take when it plans it (more than six changes of the command within tau1 + tau2: "too many
 * changes") gets its "OK" first and that "ERR" a moment later; the move goes on to the target before.
 * Defaults: vmax 20,000 steps/s, accel 40,000 steps/s^2, jerk 200,000 steps/s^3 (the parameters the
 * emulator checks verify clean; with a higher acceleration or jerk the planner can fall behind and
 * steps come late: underruns= in `?`, docs/smooth-move.md's known limit).
 * A stop or a new target cuts the queue and acts about 60 ms later (MOTION_STEPPER_SMOOTH_CUT_US;
 * after the lead, up to 0.15 s, when its plan is not ready in time); the first step comes about
 * 0.14 s after a move from rest is asked for. Replies can come tens of milliseconds after their line:
 * while the planner interrupt plans the smooth ramp's costly commands (a start, a cut), loop() waits
 * for it (the input is kept meanwhile: MotionSerial, as the sketches' consoles read it; a line lost
 * all the same is answered "ERR input overrun").
 */
#include <MotionStepper.h>
#include <MotionSerial.h>
#include <PrintReal.h>
#include <text_parse.h>

Stepper x(Stepper::X);
static MotionSerial serial(Serial);
static motion_status_t reported = MS_OK; /* the planner's last refusal already answered */

/* "ERR <the library's sentence>[: detail]" */
static void reply_error(motion_status_t st, const __FlashStringHelper *detail = 0)
{
    if (detail)
        serial.reply_error(st, detail);
    else
        serial.reply_error(st);
}

static void print_param(const char *key)
{
    Serial.print(key);
    Serial.print('=');
    if (text_word_is(key, "vmax"))
        print_real_exact(Serial, x.maxSpeed(), 0);
    else if (text_word_is(key, "accel"))
        print_real_exact(Serial, x.acceleration(), 0);
    else
        print_real_exact(Serial, x.jerk(), 0);
}

/* set <vmax|accel|jerk> <value> */
static void handle_set(const char *cursor)
{
    char key[LINE_READER_MAX + 1], value[LINE_READER_MAX + 1];
    double v;
    motion_status_t st;
    if (text_next_word(&cursor, key, sizeof key) <= 0 || text_next_word(&cursor, value, sizeof value) <= 0 ||
        !text_at_end(cursor)) {
        reply_error(MS_ERR_UNKNOWN_COMMAND, F("set vmax|accel|jerk <value>"));
        return;
    }
    if (!text_word_is(key, "vmax") && !text_word_is(key, "accel") && !text_word_is(key, "jerk")) {
        reply_error(MS_ERR_UNKNOWN_COMMAND, F("no such parameter (vmax, accel, jerk)"));
        return;
    }
    st = text_parse_real(value, -1e30, 1e30, &v);
    if (st == MS_OK) {
        if (text_word_is(key, "vmax"))
            st = x.setMaxSpeed((float)v);
        else if (text_word_is(key, "accel"))
            st = x.setAcceleration((float)v);
        else
            st = x.setJerk((float)v);
    }
    if (st == MS_ERR_ABOVE_LIMIT && text_word_is(key, "vmax")) {
        /* as the sketches' consoles say it: "ERR number out of range: vmax at most ..." */
        Serial.print(F("ERR "));
        Serial.print(Stepper::statusText(MS_ERR_OUT_OF_RANGE));
        Serial.print(F(": vmax at most "));
        print_real_exact(Serial, STEPPER_MAX_SPS_SMOOTH, 0);
        Serial.println(F(" steps/s on the smooth ramp"));
        return;
    }
    if (st != MS_OK) {
        reply_error(st);
        return;
    }
    Serial.print(F("OK "));
    print_param(key);
    Serial.println();
}

static void print_status()
{
    Serial.print(F("pos="));
    Serial.print(x.currentPosition());
    Serial.print(F(" target="));
    Serial.print(x.targetPosition());
    Serial.print(x.isRunning() ? F(" state=moving speed=") : F(" state=idle speed="));
    print_real_exact(Serial, x.speed(), 0);
    Serial.print(F(" algo=smooth "));
    print_param("vmax");
    Serial.print(' ');
    print_param("accel");
    Serial.print(' ');
    print_param("jerk");
    Serial.print(F(" max_sps="));
    print_real_exact(Serial, STEPPER_MAX_SPS_SMOOTH, 0);
    Serial.print(F(" underruns="));
    Serial.println(x.underruns());
}

static void handle(const char *line)
{
    const char *cursor = line;
    char word[LINE_READER_MAX + 1];
    int32_t target;
    motion_status_t st;
    if (text_next_word(&cursor, word, sizeof word) <= 0)
        return;
    if (text_word_is(word, "?") && text_at_end(cursor)) {
        print_status();
    } else if (text_word_is(word, "set")) {
        handle_set(cursor);
    } else if ((text_word_is(word, "stop") || text_word_is(word, "!")) && text_at_end(cursor)) {
        bool halt = word[0] == '!';
        bool was = x.isRunning();
        st = halt ? x.forceStop() : x.stop();
        if (st != MS_OK) {
            reply_error(st);
            return;
        }
        Serial.print(halt ? F("OK halt") : F("OK stop"));
        Serial.println(was ? F("") : F(" (not moving)"));
    } else if ((word[0] >= '0' && word[0] <= '9') || word[0] == '-' || word[0] == '+') {
        st = text_at_end(cursor) ? text_parse_whole(word, INT32_MIN, INT32_MAX, &target) : MS_ERR_NOT_A_NUMBER;
        if (st != MS_OK) {
            reply_error(st, F("a target is one whole number of steps, -2147483648..2147483647"));
            return;
        }
        st = x.moveTo(target);
        if (st != MS_OK) {
            reply_error(st);
            return;
        }
        Serial.print(F("OK "));
        Serial.println(target);
        if (!x.isRunning() && x.currentPosition() == target) {
            /* where X rests: moveTo() changes nothing (no move, no end to take), the DONE is now */
            Serial.print(F("DONE "));
            Serial.println(target);
        }
    } else {
        reply_error(MS_ERR_UNKNOWN_COMMAND, F("try <target>, stop, !, ?, set vmax|accel|jerk <value>"));
    }
}

void setup()
{
    Serial.begin(115200);
    x.setRamp(RAMP_ALGO_SMOOTH);
    x.setMaxSpeed(20000);
    x.setJerk(200000); /* before the acceleration: the jerk in force must be at least accel^2/vmax */
    x.setAcceleration(40000);
    x.begin();
    Serial.println(F("READY SmoothConsole"));
}

void loop()
{
    long at;
    motion_status_t st;
    const char *line = serial.poll(); /* a bad line (too long, not printable, lost) is answered there */
    if (line != NULL)
        handle(line);
    st = x.lastStatus();
    if (st != MS_OK && st != reported)
        reply_error(st, F("the last target was not taken: the move goes on to the one before"));
    reported = st;
    if (x.takeDone(at)) {
        Serial.print(F("DONE "));
        Serial.println(at);
    }
}
