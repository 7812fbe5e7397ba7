/* SerialOutQueue.cpp - see SerialOutQueue.h. */
#include "SerialOutQueue.h"

void SerialOutQueue::pump()
{
    int free_slots = port_.availableForWrite();
    uint8_t b;
    while (free_slots-- > 0 && byte_queue_get(&q_, &b))
        port_.write(b);
}
