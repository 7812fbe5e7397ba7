/* SerialRx.cpp - see SerialRx.h. */
#include "SerialRx.h"

#include <util/atomic.h>

static rx_ring_t ring;
static volatile uint8_t draining;

static bool started;

void SerialRx::begin(bool interrupt)
{
    if (started)
        return;
    started = true;
    rx_ring_init(&ring);
    if (interrupt) {
        OCR0B = 128; /* half way between two overflows (millis) */
        TIFR0 = _BV(OCF0B);
        TIMSK0 |= _BV(OCIE0B);
    }
}

/* moves what the core has received into the ring (from loop() or the interrupt; never both) */
void SerialRx::drain()
{
    int n;
    if (draining)
        return; /* the interrupt came while loop() was draining: loop() finishes it */
    draining = 1;
    n = Serial.available();
    if (n > 0) {
        bool full = n >= SERIAL_RX_BUFFER_SIZE - 1;
        while (n-- > 0)
            (void)rx_ring_put(&ring, (uint8_t)Serial.read());
        if (full)
            rx_ring_mark_loss(&ring); /* the core may have dropped what came next */
    }
    draining = 0;
}

rx_event_t SerialRx::get(uint8_t &byte, rx_loss_t &loss)
{
    rx_event_t ev;
    if (rx_ring_count(&ring) == 0)
        drain(); /* take what has come at once, not at the next interrupt */
    if (!rx_ring_loss_ahead(&ring))
        return rx_ring_get(&ring, &byte, &loss); /* a byte, or none: safe while the drain runs */
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        ev = rx_ring_get(&ring, &byte, &loss); /* the record is taken whole */
    }
    return ev;
}

ISR(TIMER0_COMPB_vect, ISR_NOBLOCK)
{
    SerialRx::drain();
}
