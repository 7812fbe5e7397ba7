/* SerialOutQueue.cpp - see SerialOutQueue.h. */
#include "SerialOutQueue.h"

void SerialOutQueue::pump()
{
    int free_slots = port_.availableForWrite();
    uint8_t b;
    if (direct_) {
        /* one byte, and only into an empty transmitter (its buffer empty, UDR0 free): HardwareSerial's
         * write() then puts it in UDR0 itself and never enables its transmit interrupt */
        if ((UCSR0A & _BV(UDRE0)) && free_slots >= SERIAL_TX_BUFFER_SIZE - 1 && byte_queue_get(&q_, &b))
            port_.write(b);
        return;
    }
    while (free_slots-- > 0 && byte_queue_get(&q_, &b))
        port_.write(b);
}
