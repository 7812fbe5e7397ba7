/* byte_queue.c - fixed-size byte FIFO (see byte_queue.h). */
#include "byte_queue.h"

motion_status_t byte_queue_init(byte_queue_t *q, uint8_t *storage, uint16_t capacity)
{
    if (q == 0 || storage == 0)
        return MS_ERR_NULL;
    if (capacity == 0)
        return MS_ERR_BUFFER_TOO_SMALL;
    q->buf = storage;
    q->capacity = capacity;
    q->head = 0;
    q->tail = 0;
    q->count = 0;
    q->dropped = 0;
    return MS_OK;
}

uint16_t byte_queue_count(const byte_queue_t *q)
{
    return q->count;
}

uint16_t byte_queue_room(const byte_queue_t *q)
{
    return (uint16_t)(q->capacity - q->count);
}

uint8_t byte_queue_put(byte_queue_t *q, uint8_t byte)
{
    if (q->count == q->capacity) {
        if (q->dropped != UINT16_MAX)
            q->dropped++;
        return 0;
    }
    q->buf[q->tail] = byte;
    q->tail = (uint16_t)(q->tail + 1 == q->capacity ? 0 : q->tail + 1);
    q->count++;
    return 1;
}

uint8_t byte_queue_get(byte_queue_t *q, uint8_t *byte)
{
    if (q->count == 0)
        return 0;
    *byte = q->buf[q->head];
    q->head = (uint16_t)(q->head + 1 == q->capacity ? 0 : q->head + 1);
    q->count--;
    return 1;
}
