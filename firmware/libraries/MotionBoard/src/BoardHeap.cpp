/* BoardHeap.cpp - see BoardHeap.h. */
#include "BoardHeap.h"

#include <avr/io.h>

extern "C" {
extern char __heap_start;                    /* the linker's: the first byte after .bss */
extern char *__brkval __attribute__((weak)); /* avr-libc malloc's top, when the sketch links malloc */
char *board_heap_top;
}

void *board_take(size_t n)
{
    char **top = &__brkval ? &__brkval : &board_heap_top;
    char *p = *top ? *top : &__heap_start;
    size_t room = (size_t)((char *)SP - p);
    if (p > (char *)SP || room < n || room - n < BOARD_HEAP_MARGIN)
        return NULL;
    *top = p + n;
    return p;
}
