/* test/unit/filter_testutil.h - helpers shared by the filter tests (header-only, static). */
#ifndef FILTER_TESTUTIL_H
#define FILTER_TESTUTIL_H

#include <stdint.h>

/* SplitMix64 of k: a counter-based pseudo-random generator, so any past sample can be regenerated
 * from its index (the no-drift tests recompute the last N inputs independently of the filter). */
static inline uint64_t tu_mix(uint64_t k)
{
    uint64_t z = k + 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* A full-scale sample in -32767..32767 for index k (seed selects the sequence). */
static inline int16_t tu_sample(uint64_t seed, uint64_t k)
{
    return (int16_t)((int32_t)((tu_mix(k ^ (seed << 40)) >> 32) % 65535u) - 32767);
}

/* The moving-average-filter note's input: 0 before k0, amplitude from k0 on (counts of the quantum). */
static inline int16_t tu_step(int16_t amplitude, uint32_t k0, uint32_t k)
{
    return k >= k0 ? amplitude : 0;
}

/* Square wave: amplitude for the first half of each period of 2*half samples, then 0. */
static inline int16_t tu_square(int16_t amplitude, uint32_t half, uint32_t k)
{
    return (k % (2u * half)) < half ? amplitude : 0;
}

#endif
