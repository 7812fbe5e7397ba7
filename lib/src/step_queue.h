/* step_queue.h - the step commands a planner hands to the step interrupt, the ring that carries
 * them, and the one function that executes a command step by step (the interrupt and motionsim
 * both call it, so the simulator shows exactly what the interrupt does).
 *
 * A command is a run of `count` steps with a linearly changing interval, in 16.16 fixed-point
 * timer ticks (the idea of Klipper's `interval, count, add` triples, with a fraction so that a
 * quadratic time law can be followed for many steps without rounding drift):
 *   step j (1..count) of the command happens at   acc_j = acc_(j-1) + rate_j,
 *   rate_1 = rate,  rate_(j+1) = rate_j + add;    the STEP edge is at whole tick floor(acc_j).
 * acc is an absolute timeline (modulo 2^32 in 1/65536 ticks, i.e. modulo 65536 whole ticks: the
 * 16-bit timer's own range), so a move never drifts from its plan however long it is.
 * A WIDE command is for slow steps (an interval of more than 65535 ticks): `rate` is then a whole
 * tick count (up to 2^32 - 1), add is 0, and the fraction of acc is left as it is.
 * Flags: STEP_CMD_REVERSE (the command's steps go in the negative direction), STEP_CMD_WIDE, and
 * the ramp phase (accel/cruise/decel) for status reports.
 * Cost on the AVR (gcc-avr 5.4 -Os, measured by `make bench`): step_exec_next is three 32-bit
 * additions, a 16-bit decrement and a few loads and stores; no multiply, no division, no float.
 * Ring: single producer (the planner in loop()) and single consumer (the interrupt), indices of
 * one byte each, so neither side needs to disable interrupts to push or pop.
 */
#ifndef STEP_QUEUE_H
#define STEP_QUEUE_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define STEP_CMD_REVERSE 0x01U
#define STEP_CMD_WIDE 0x02U
/* Bits 2-3: the ramp phase of the command's steps (ramp_phase_t: 1 accel, 2 cruise, 3 decel),
 * for `?` reports; the executor ignores them. */
#define STEP_CMD_PHASE_SHIFT 2U
#define STEP_CMD_PHASE_MASK 0x0CU
#define STEP_CMD_PHASE(flags) ((uint8_t)(((flags) & STEP_CMD_PHASE_MASK) >> STEP_CMD_PHASE_SHIFT))

/* The longest interval a normal (not WIDE) command can hold: 65535 ticks and a fraction. */
#define STEP_RATE_MAX 0xFFFFFFFFUL

typedef struct {
    uint32_t rate;  /* 16.16 ticks: interval of the first step (WIDE: whole ticks) */
    int32_t add;    /* 16.16 ticks added to the interval after each step (WIDE: 0) */
    uint16_t count; /* steps in the command, >= 1 */
    uint8_t flags;  /* STEP_CMD_* */
} step_cmd_t;

/* Commands in the ring: a power of two (index arithmetic by mask); one slot stays empty. */
#ifndef STEP_QUEUE_LEN
#define STEP_QUEUE_LEN 32U
#endif

typedef struct {
    step_cmd_t cmd[STEP_QUEUE_LEN];
    volatile uint8_t head; /* next slot the producer writes */
    volatile uint8_t tail; /* next slot the consumer reads */
} step_queue_t;

void step_queue_init(step_queue_t *q);
/* Commands waiting (not yet taken by the consumer). */
uint8_t step_queue_used(const step_queue_t *q);
uint8_t step_queue_free(const step_queue_t *q);
/* Producer: copies c into the ring; 0 when full (nothing changed). */
uint8_t step_queue_push(step_queue_t *q, const step_cmd_t *c);
/* Consumer: copies the oldest command into *c and removes it; 0 when empty. */
uint8_t step_queue_pop(step_queue_t *q, step_cmd_t *c);
/* Producer side, with the consumer stopped: drops everything. */
void step_queue_clear(step_queue_t *q);

/* The executor: the command in progress and the timeline. */
typedef struct {
    uint32_t acc;  /* 16.16 ticks: time of the last step made (absolute, modulo 2^32) */
    uint32_t rate; /* interval of the next step of the current command */
    int32_t add;
    uint16_t left; /* steps of the current command still to make */
    uint8_t flags; /* of the current command */
} step_exec_t;

/* Starts the executor at time acc (16.16 ticks) with no command. */
void step_exec_init(step_exec_t *x, uint32_t acc);

/* Loads command c (the executor must have no steps left). */
static inline void step_exec_load(step_exec_t *x, const step_cmd_t *c)
{
    x->rate = c->rate;
    x->add = c->add;
    x->left = c->count;
    x->flags = c->flags;
}

/* Advances to the next step of the current command (left > 0): returns the whole tick of its
 * edge (acc >> 16, modulo 2^16) for a normal command; for a WIDE command the tick too (the
 * whole interval is added; the caller counts out the 16-bit timer's wraps). */
static inline uint16_t step_exec_next(step_exec_t *x)
{
    if (x->flags & STEP_CMD_WIDE) {
        x->acc += x->rate << 16; /* whole ticks, modulo 2^16 in the upper half */
    } else {
        x->acc += x->rate;
        x->rate += (uint32_t)x->add;
    }
    x->left--;
    return (uint16_t)(x->acc >> 16);
}

/* The whole interval of a WIDE step (ticks), for counting out timer wraps. */
static inline uint32_t step_exec_wide_ticks(const step_exec_t *x)
{
    return x->rate;
}

#ifdef __cplusplus
}
#endif

#endif
