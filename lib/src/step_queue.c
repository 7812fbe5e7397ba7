/* step_queue.c - the ring of step commands and the executor's start (see step_queue.h). */
#include "step_queue.h"

#define STEP_QUEUE_MASK ((uint8_t)(STEP_QUEUE_LEN - 1U))

#if (STEP_QUEUE_LEN & (STEP_QUEUE_LEN - 1U)) != 0 || STEP_QUEUE_LEN < 2U || STEP_QUEUE_LEN > 128U
#error "STEP_QUEUE_LEN must be a power of two from 2 to 128"
#endif

void step_queue_init(step_queue_t *q)
{
    q->head = 0;
    q->tail = 0;
}

uint8_t step_queue_used(const step_queue_t *q)
{
    return (uint8_t)((uint8_t)(q->head - q->tail) & STEP_QUEUE_MASK);
}

uint8_t step_queue_free(const step_queue_t *q)
{
    return (uint8_t)(STEP_QUEUE_MASK - step_queue_used(q));
}

uint8_t step_queue_push(step_queue_t *q, const step_cmd_t *c)
{
    uint8_t h = q->head;
    uint8_t next = (uint8_t)((h + 1U) & STEP_QUEUE_MASK);
    if (next == q->tail)
        return 0;
    q->cmd[h] = *c;
    q->head = next; /* one byte: the consumer sees the slot only once it is complete */
    return 1;
}

uint8_t step_queue_pop(step_queue_t *q, step_cmd_t *c)
{
    uint8_t t = q->tail;
    if (t == q->head)
        return 0;
    *c = q->cmd[t];
    q->tail = (uint8_t)((t + 1U) & STEP_QUEUE_MASK);
    return 1;
}

void step_queue_clear(step_queue_t *q)
{
    q->tail = q->head;
}

void step_exec_init(step_exec_t *x, uint32_t acc)
{
    x->acc = acc;
    x->rate = 0;
    x->add = 0;
    x->left = 0;
    x->flags = 0;
}
