/* rx_ring.c - serial input with exact loss accounting (see rx_ring.h). */
#include "rx_ring.h"

#define MASK (RX_RING_BYTES - 1U)

void rx_ring_init(rx_ring_t *r)
{
    r->head = 0;
    r->tail = 0;
    r->lost = 0;
    r->lost_start = 0;
    r->lost_end = 0;
    r->lost_clean = 0;
    r->lost_cr = 0;
    r->lost_ends = 0;
    r->ends_after = 0;
    r->put_cr = 0;
}

uint8_t rx_ring_put(rx_ring_t *r, uint8_t byte)
{
    uint8_t tail = r->tail;
    uint8_t is_end = (byte == '\r' || (byte == '\n' && !r->put_cr));
    r->put_cr = (byte == '\r');
    if ((uint8_t)(tail - r->head) < RX_RING_BYTES) {
        r->buf[tail & MASK] = byte;
        r->tail = (uint8_t)(tail + 1U); /* published after the byte */
        if (r->lost && is_end && r->ends_after != 0xFFU)
            r->ends_after++; /* in the stretch if another byte is lost before the reader comes */
        return 1;
    }
    if (!r->lost) {
        r->lost_start = tail;
        r->lost_ends = 0;
    } else if (r->lost_ends <= 0xFFFFU - 0xFFU) {
        r->lost_ends += r->ends_after; /* the bytes stored since the last loss are in the stretch */
    }
    r->ends_after = 0;
    r->lost_end = tail;
    if (is_end && r->lost_ends != 0xFFFFU)
        r->lost_ends++;
    r->lost_clean = (byte == '\r' || byte == '\n');
    r->lost_cr = (byte == '\r');
    r->lost = 1; /* last: the consumer reads lost_start only once this is set */
    return 0;
}

void rx_ring_mark_loss(rx_ring_t *r)
{
    uint8_t tail = r->tail;
    if (!r->lost) {
        r->lost_start = tail;
        r->lost_ends = 0;
    } else if (r->lost_ends <= 0xFFFFU - 0xFFU) {
        r->lost_ends += r->ends_after;
    }
    r->ends_after = 0;
    r->lost_end = tail;
    r->lost_clean = 0;
    r->lost_cr = 0;
    r->put_cr = 0;
    r->lost = 1;
}

uint8_t rx_ring_count(const rx_ring_t *r)
{
    return (uint8_t)(r->tail - r->head);
}

uint8_t rx_ring_loss_ahead(const rx_ring_t *r)
{
    return r->lost && r->lost_start == r->head;
}

rx_event_t rx_ring_get(rx_ring_t *r, uint8_t *byte, rx_loss_t *loss)
{
    uint8_t head = r->head;
    if (r->lost && r->lost_start == head) {
        /* the damaged stretch: its line ends were counted as it came (lost bytes and the bytes
         * stored among them); those stored bytes are skipped */
        uint16_t lines = r->lost_ends;
        head = r->lost_end;
        if (!r->lost_clean && lines != 0xFFFFU)
            lines++; /* the line that goes on past the stretch */
        loss->lines = lines;
        loss->cont = !r->lost_clean;
        loss->after_cr = r->lost_cr;
        r->lost = 0;
        r->head = head;
        return RX_LOSS;
    }
    if (head == r->tail)
        return RX_NONE;
    *byte = r->buf[head & MASK];
    r->head = (uint8_t)(head + 1U);
    return RX_BYTE;
}
