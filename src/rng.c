/* PCG32 (XSH-RR): 64-bit LCG state, 32-bit permuted output. */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/rng.h"

#define ACTAG_PCG_MULT 6364136223846793005ull
#define ACTAG_PCG_INC 1442695040888963407ull /* odd: full period 2^64 */

void actag_rng_seed(actag_rng *r, uint32_t seed)
{
    /* Same warm-up as the PCG reference seeding, so seed 0 is as good as any. */
    r->state = 0u;
    (void)actag_rng_next(r);
    r->state += (uint64_t)seed;
    (void)actag_rng_next(r);
}

uint32_t actag_rng_next(actag_rng *r)
{
    uint64_t old = r->state;
    uint32_t xorshifted, rot;
    r->state = old * ACTAG_PCG_MULT + ACTAG_PCG_INC;
    xorshifted = (uint32_t)(((old >> 18) ^ old) >> 27);
    rot = (uint32_t)(old >> 59);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
}

uint32_t actag_rng_below(actag_rng *r, uint32_t n)
{
    uint64_t m;
    uint32_t low;
    if (n <= 1u)
        return 0u;
    /* The high word of x * n is uniform in [0, n) once the few low words
     * below 2^32 mod n are rejected. */
    m = (uint64_t)actag_rng_next(r) * n;
    low = (uint32_t)m;
    if (low < n) {
        uint32_t threshold = (uint32_t)(0u - n) % n; /* 2^32 mod n */
        while (low < threshold) {
            m = (uint64_t)actag_rng_next(r) * n;
            low = (uint32_t)m;
        }
    }
    return (uint32_t)(m >> 32);
}
