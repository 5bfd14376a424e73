/* pgt: counter-based random numbers.
 *
 * Every random draw is a pure function of (seed id, stream, counter), so any backend and any
 * thread order draw the same numbers (no global generator). The mixer is a 64-bit finaliser in
 * the style of SplitMix64/Murmur3 fmix64 applied to a combination of the three inputs. */
#ifndef PGT_RNG_H
#define PGT_RNG_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

static inline uint64_t pgt_rng_mix64(uint64_t x) {
    x ^= x >> 30;
    x *= 0xBF58476D1CE4E5B9ull;
    x ^= x >> 27;
    x *= 0x94D049BB133111EBull;
    x ^= x >> 31;
    return x;
}

/* 64 random bits for (seed, stream, counter). */
static inline uint64_t pgt_rng_u64(uint32_t seed, uint32_t stream, uint64_t counter) {
    uint64_t k = pgt_rng_mix64(((uint64_t)seed << 32 | stream) + 0x9E3779B97F4A7C15ull);
    return pgt_rng_mix64(k ^ (counter * 0xD1B54A32D192ED03ull + 0x8CB92BA72F3D8DD7ull));
}

/* Uniform float in [0, 1) with 24 random bits (exact in float32). */
static inline float pgt_rng_float(uint32_t seed, uint32_t stream, uint64_t counter) {
    return (float)(pgt_rng_u64(seed, stream, counter) >> 40) * (1.0f / 16777216.0f);
}

/* Uniform double in [0, 1) with 53 random bits. */
static inline double pgt_rng_double(uint32_t seed, uint32_t stream, uint64_t counter) {
    return (double)(pgt_rng_u64(seed, stream, counter) >> 11) * (1.0 / 9007199254740992.0);
}

#ifdef __cplusplus
}
#endif

#endif
