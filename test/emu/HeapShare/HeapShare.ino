/* HeapShare - a test sketch for the emulator suite (checks_library.py, check_heap_share): a maker's
 * sketch that uses malloc and free (as String does) beside a Stepper, whose begin() takes its step
 * ring and its stop planned ahead from the heap with board_take (BoardHeap.h). With malloc linked,
 * board_take must move malloc's top (__brkval) past what it takes, so that neither hands out the
 * other's bytes. Each block is filled with its own byte, a move of 20,000 steps at 20,000 steps/s
 * runs, and every block is read back. 9600 baud; prints
 *   BLOCK <name> <first address> <bytes>     a (malloc, freed before d), rings (board_take in
 *                                            begin()), b (malloc), t (board_take), c, d (malloc)
 *   TOP brkval=<__brkval> board=<board_heap_top>
 *   DONE <position> underruns=<n>
 *   FILL ok | FILL bad <name> at <offset>
 */
#include <MotionStepper.h> // first: MotionBoard's headers after it (MotionStepper.h says why)
#include <BoardHeap.h>
#include <stdlib.h>
#include <string.h>

extern "C" char *__brkval;

Stepper x(Stepper::X);

struct Block {
    const char *name;
    uint8_t *p;
    uint16_t n;
    uint8_t fill;
};
static Block blocks[5];
static uint8_t nblocks;

static uint8_t *keep(const char *name, void *p, uint16_t n, uint8_t fill)
{
    Serial.print(F("BLOCK "));
    Serial.print(name);
    Serial.print(' ');
    Serial.print((uint16_t)(uintptr_t)p);
    Serial.print(' ');
    Serial.println(n);
    if (p && fill) {
        memset(p, fill, n);
        blocks[nblocks++] = {name, static_cast<uint8_t *>(p), n, fill};
    }
    return static_cast<uint8_t *>(p);
}

void setup()
{
    Serial.begin(9600);
    Serial.println(F("READY HeapShare"));
    void *a = malloc(200);
    (void)keep("a", a, 200, 0); /* freed below: its bytes are d's */
    char *before = __brkval;
    x.setMaxSpeed(20000);
    x.setAcceleration(50000);
    if (x.begin() != MS_OK)
        Serial.println(F("ERR begin"));
    (void)keep("rings", before, (uint16_t)(__brkval - before), 0);
    (void)keep("b", malloc(120), 120, 0xB5);
    (void)keep("t", board_take(50), 50, 0x7C);
    (void)keep("c", malloc(60), 60, 0xC3);
    free(a);
    (void)keep("d", malloc(150), 150, 0xD2);
    Serial.print(F("TOP brkval="));
    Serial.print((uint16_t)(uintptr_t)__brkval);
    Serial.print(F(" board="));
    Serial.println((uint16_t)(uintptr_t)board_heap_top);
    x.moveTo(20000);
}

void loop()
{
    static bool reported;
    if (reported || x.isRunning())
        return;
    reported = true;
    Serial.print(F("DONE "));
    Serial.print(x.currentPosition());
    Serial.print(F(" underruns="));
    Serial.println(x.underruns());
    for (uint8_t k = 0; k < nblocks; k++)
        for (uint16_t i = 0; i < blocks[k].n; i++)
            if (blocks[k].p[i] != blocks[k].fill) {
                Serial.print(F("FILL bad "));
                Serial.print(blocks[k].name);
                Serial.print(F(" at "));
                Serial.println(i);
                return;
            }
    Serial.println(F("FILL ok"));
}
