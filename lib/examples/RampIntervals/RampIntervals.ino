/* RampIntervals - MotionCore's stepper ramp in a sketch of your own.
 *
 * Plans the lab's move (0 -> 50 steps, v0 = 1 step/s, vmax = 20 steps/s, a = 10 steps/s^2, a
 * 1 kHz timer) with the Leib ramp and prints, for each step, its number, the position after it,
 * the interval to it in timer ticks (as the ramp computes it, and rounded to whole ticks, what a
 * timer would count) and the phase. Nothing moves: no pins are used, any board with a serial port
 * runs it. Open the Serial Monitor at 9600 baud; send a number to plan a move to that position.
 *
 * To step a motor, wait whole_ticks timer ticks between steps (e.g. in a timer interrupt) and
 * pulse the step pin; the firmware's stepper sketches do exactly that. The same numbers come from
 *     motionsim ramp --algo leib --from 0 --to 50 --v0 1 --vmax 20 --accel 10 --tick-hz 1000
 * Change RAMP_ALGO_LEIB to RAMP_ALGO_EXACT or RAMP_ALGO_SIMPLISTIC to compare the ramps.
 */
#include <ramp.h>

const ramp_params_t params = {1.0, 20.0, 10.0, 1000}; /* v0, vmax (steps/s), accel (steps/s^2), timer Hz */
long position = 0;

const char *phaseName(ramp_phase_t p)
{
    return p == RAMP_ACCEL ? "accel" : p == RAMP_CRUISE ? "cruise" : p == RAMP_DECEL ? "decel" : "idle";
}

void printMove(long from, long to)
{
    ramp_t ramp;
    ramp_step_t s;
    if (ramp_plan(&ramp, RAMP_ALGO_LEIB, &params, from, to) != MS_OK) {
        Serial.println(F("ERR the ramp refused the move"));
        return;
    }
    Serial.print(F("move "));
    Serial.print(from);
    Serial.print(F(" -> "));
    Serial.print(to);
    Serial.print(F(" with the "));
    Serial.print(ramp_algo_name(RAMP_ALGO_LEIB));
    Serial.println(F(" ramp"));
    Serial.println(F("step,position,interval_ticks,whole_ticks,phase"));
    while (ramp_next(&ramp, &s)) {
        Serial.print(s.step);
        Serial.print(',');
        Serial.print(s.position);
        Serial.print(',');
        Serial.print(s.interval_ticks, 3);
        Serial.print(',');
        Serial.print(s.whole_ticks);
        Serial.print(',');
        Serial.println(phaseName(s.phase));
    }
    Serial.println(F("DONE"));
}

void setup()
{
    Serial.begin(9600);
    printMove(0, 50);
    position = 50;
}

void loop()
{
    if (Serial.available()) {
        long target = Serial.parseInt();
        while (Serial.available())
            Serial.read(); /* the rest of the line */
        printMove(position, target);
        position = target;
    }
}
