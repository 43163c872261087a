/*
 * actag/rng.h -- a tiny seeded pseudo-random number generator.
 *
 * MANUAL
 *   The quadrilateral fitter (RANSAC) needs random numbers that are the same
 *   on every platform, so results are reproducible bit for bit on x86 and
 *   ARM. This is PCG32 (O'Neill's permuted congruential generator, XSH-RR
 *   output, 64-bit state, one fixed stream): integer arithmetic only, no
 *   global state, 8 bytes per generator. It is NOT cryptographic.
 *
 *     actag_rng r;
 *     actag_rng_seed(&r, 42);            // any seed, 0 included
 *     uint32_t a = actag_rng_next(&r);   // uniform in [0, 2^32)
 *     uint32_t i = actag_rng_below(&r, 10);  // uniform in [0, 10)
 *
 *   actag_rng_seed(r, s) gives the same stream as the PCG reference
 *   pcg32_srandom_r(r, s, 0xa02bdbf7bb3c0a7) (initstate = s, initseq =
 *   0xa02bdbf7bb3c0a7, i.e. increment 1442695040888963407).
 *
 *   The state is a plain value: copy it to fork a stream, store it to resume.
 *   None of these functions check for NULL (they are called in inner loops),
 *   and none has an error code.
 */
#ifndef ACTAG_RNG_H
#define ACTAG_RNG_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Generator state. Treat as opaque; initialise with actag_rng_seed(). */
typedef struct actag_rng {
    uint64_t state;
} actag_rng;

/* Resets *r to the start of the stream for this seed. Every seed is valid. */
void actag_rng_seed(actag_rng *r, uint32_t seed);

/* Next 32-bit output, uniform over [0, 2^32). */
uint32_t actag_rng_next(actag_rng *r);

/* Uniform integer in [0, n) without modulo bias (Lemire's multiply-and-reject;
 * on average fewer than 1 + n / 2^32 draws). Returns 0 without drawing when
 * n == 0 or n == 1. */
uint32_t actag_rng_below(actag_rng *r, uint32_t n);

#ifdef __cplusplus
}
#endif
#endif /* ACTAG_RNG_H */
