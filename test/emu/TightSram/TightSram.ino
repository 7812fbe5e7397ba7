/* TightSram - a test sketch for the emulator suite (checks_library.py, check_tight_sram): a Stepper in
 * a sketch that has used up most of its SRAM. begin() takes the step ring and, where it fits too, the
 * stop planned ahead's room from the heap and must leave BOARD_STACK_RESERVE bytes (BoardHeap.h) below
 * the stack pointer for the stack, or refuse (MS_ERR_NO_MEMORY) and move nothing; when it begins, a move whose maximum speed is
 * set again every 5 ms (each setter plans a whole move on the stack, under the planner's interrupt)
 * must keep its stack out of the rings (motionemu fails the run otherwise). 9600 baud; lines:
 *   room         -> ROOM <bytes between the heap's top and the stack pointer>
 *   eat <n>      -> malloc so that about n bytes stay between them; ROOM <bytes>
 *   begin        -> BEGIN <status text> USED <bytes begin() took from the heap>
 *   move         -> MOVE <status text>; then DONE <position> underruns=<n> at rest
 */
#include <MotionStepper.h> // first: MotionBoard's headers after it (MotionStepper.h says why)
#include <BoardHeap.h>
#include <stdlib.h>
#include <string.h>

extern "C" char *__brkval;
extern "C" char __heap_start;

Stepper x(Stepper::X);
static char line[24];
static uint8_t len;
static bool moving;

static uint16_t heap_top()
{
    char *top = __brkval ? __brkval : (board_heap_top ? board_heap_top : &__heap_start);
    return (uint16_t)(uintptr_t)top;
}

static uint16_t room()
{
    return (uint16_t)(SP - heap_top());
}

static void command()
{
    if (!strcmp(line, "room")) {
    } else if (!strncmp(line, "eat ", 4)) {
        uint16_t keep = (uint16_t)atol(line + 4);
        uint16_t r = room();
        /* malloc's block header (2 bytes) and its own margin (__malloc_margin, 32) come on top */
        if (r > keep + 34U && !malloc(r - keep - 2U)) {
            Serial.println(F("ERR malloc"));
            return;
        }
    } else if (!strcmp(line, "begin")) {
        uint16_t before = heap_top();
        motion_status_t st = x.begin();
        Serial.print(F("BEGIN "));
        Serial.print(Stepper::statusText(st));
        Serial.print(F(" USED "));
        Serial.println(heap_top() - before);
        return;
    } else if (!strcmp(line, "move")) {
        motion_status_t st = x.moveTo(20000);
        Serial.print(F("MOVE "));
        Serial.println(Stepper::statusText(st));
        moving = st == MS_OK;
        return;
    } else {
        Serial.println(F("ERR unknown"));
        return;
    }
    Serial.print(F("ROOM "));
    Serial.println(room());
}

void setup()
{
    Serial.begin(9600);
    x.setMaxSpeed(20000);
    x.setAcceleration(50000);
    Serial.println(F("READY TightSram"));
}

void loop()
{
    static uint32_t last;
    while (Serial.available()) {
        char c = (char)Serial.read();
        if (c == '\n' || c == '\r') {
            line[len] = '\0';
            if (len)
                command();
            len = 0;
        } else if (len < sizeof line - 1) {
            line[len++] = c;
        }
    }
    if (!moving)
        return;
    if (x.isRunning()) {
        if (millis() - last >= 5) {
            last = millis();
            (void)x.setMaxSpeed(x.maxSpeed() == 20000.0f ? 19000.0f : 20000.0f);
        }
        return;
    }
    moving = false;
    Serial.print(F("DONE "));
    Serial.print(x.currentPosition());
    Serial.print(F(" underruns="));
    Serial.println(x.underruns());
}
