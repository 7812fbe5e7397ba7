/* BoardHeap.cpp - see BoardHeap.h. */
#include "BoardHeap.h"

#include <avr/io.h>

extern "C" {
extern char __heap_start;                    /* the linker's: the first byte after .bss */
extern char *__brkval __attribute__((weak)); /* avr-libc malloc's top, when the sketch links malloc */
char *board_heap_top;
}

static size_t reserve = BOARD_STACK_RESERVE; /* raised by board_reserve_stack, never lowered */

/* the heap's top: malloc's when linked, else board_heap_top (0: nothing taken yet) */
static char **heap_top()
{
    return &__brkval ? &__brkval : &board_heap_top;
}

static bool fits(const char *p, size_t n, size_t keep)
{
    size_t room = (size_t)((char *)SP - p);
    return p <= (char *)SP && room >= n && room - n >= keep;
}

void *board_take_leaving(size_t n, size_t more)
{
    char **top = heap_top();
    char *p = *top ? *top : &__heap_start;
    if (!fits(p, n + more, reserve))
        return NULL;
    *top = p + n;
    return p;
}

void *board_take(size_t n)
{
    return board_take_leaving(n, 0);
}

bool board_reserve_stack(size_t keep, size_t n)
{
    char **top = heap_top();
    if (keep <= reserve)
        keep = reserve;
    if (!fits(*top ? *top : &__heap_start, n, keep))
        return false;
    reserve = keep;
    return true;
}
