/* byte_queue.h - a fixed-size FIFO of bytes in caller-provided storage (a ring buffer), for
 * output that must never make its producer wait: the servo sketches queue their serial replies
 * here and feed the UART only as much as it can take without blocking (MotionBoard's
 * SerialOutQueue). Pure logic, no interrupts: producer and consumer run in the same context.
 *
 * put stores one byte, or refuses it when the queue is full (counted in `dropped`, so a caller
 * that reserves room first can check that it never happens); get takes the oldest byte.
 * Cost: a few compare/increment instructions per byte (no division: the indices wrap by
 * comparison, which matters on the AVR, where a 32-bit % costs ~600 cycles); SRAM = the storage
 * + 12 bytes.
 */
#ifndef BYTE_QUEUE_H
#define BYTE_QUEUE_H

#include <stdint.h>

#include "motion_status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    uint8_t *buf;
    uint16_t capacity; /* bytes of storage */
    uint16_t head;     /* index of the oldest byte */
    uint16_t tail;     /* index where the next byte goes */
    uint16_t count;    /* bytes queued */
    uint16_t dropped;  /* bytes refused because the queue was full (saturates at 65535) */
} byte_queue_t;

/* Empty queue over storage[0..capacity-1]. MS_ERR_NULL without storage, MS_ERR_BUFFER_TOO_SMALL
 * for capacity 0 (q is then untouched). */
motion_status_t byte_queue_init(byte_queue_t *q, uint8_t *storage, uint16_t capacity);

uint16_t byte_queue_count(const byte_queue_t *q); /* bytes waiting */
uint16_t byte_queue_room(const byte_queue_t *q);  /* bytes that put() would still accept */

/* 1 when stored; 0 when full (the byte is dropped and counted). */
uint8_t byte_queue_put(byte_queue_t *q, uint8_t byte);

/* 1 with the oldest byte in *byte; 0 when empty (*byte untouched). */
uint8_t byte_queue_get(byte_queue_t *q, uint8_t *byte);

#ifdef __cplusplus
}
#endif

#endif
