/* PCG32 generator: known outputs, agreement with an independent reference
 * implementation, seeding, and unbiased bounded draws. */
#include "unity.h"
#include "test_util.h"

#include "actag/rng.h"

void setUp(void) {}
void tearDown(void) {}

/* Independent PCG32 reference with a selectable stream (increment). */
typedef struct ref_pcg {
    uint64_t state, inc;
} ref_pcg;
static uint32_t ref_next(ref_pcg *r)
{
    uint64_t old = r->state;
    uint32_t x, rot;
    r->state = old * 6364136223846793005ull + r->inc;
    x = (uint32_t)(((old >> 18) ^ old) >> 27);
    rot = (uint32_t)(old >> 59);
    return rot ? (x >> rot) | (x << (32u - rot)) : x;
}
static void ref_seed(ref_pcg *r, uint64_t initstate, uint64_t initseq)
{
    r->state = 0;
    r->inc = (initseq << 1) | 1u;
    (void)ref_next(r);
    r->state += initstate;
    (void)ref_next(r);
}

static void test_reference_matches_published_pcg32_demo(void)
{
    /* The PCG paper's pcg32-demo, seed 42 stream 54 -- checks the reference itself. */
    static const uint32_t expect[6] = {0xa15c02b7u, 0x7b47f409u, 0xba1d3330u,
                                       0x83d2f293u, 0xbfa4784bu, 0xcbed606eu};
    ref_pcg r;
    int i;
    ref_seed(&r, 42, 54);
    for (i = 0; i < 6; i++)
        TEST_ASSERT_EQUAL_HEX32(expect[i], ref_next(&r));
}

static void test_known_first_outputs(void)
{
    static const uint32_t seeds[3] = {0u, 1u, 42u};
    static const uint32_t expect[3][6] = {
        {0xe823a24eu, 0x7a7ecbd9u, 0x89fd6c06u, 0xae646aa8u, 0xcd3cf945u, 0x6204b303u},
        {0x54352d7fu, 0x6ac20236u, 0x0768dd4cu, 0x75560a43u, 0x4065d452u, 0x99b2e260u},
        {0xc2f57bd6u, 0x6b07c4a9u, 0x72b7b29bu, 0x44215383u, 0xf5af5eadu, 0x68beb632u}};
    int s, i;
    for (s = 0; s < 3; s++) {
        actag_rng r;
        actag_rng_seed(&r, seeds[s]);
        for (i = 0; i < 6; i++)
            TEST_ASSERT_EQUAL_HEX32(expect[s][i], actag_rng_next(&r));
    }
}

static void test_matches_reference_on_random_seeds(void)
{
    int t, i;
    tu_seed(1234);
    for (t = 0; t < 200; t++) {
        uint32_t seed = t < 3 ? (uint32_t)(t == 2 ? 0xffffffffu : (uint32_t)t) : tu_rand();
        actag_rng a;
        ref_pcg r;
        actag_rng_seed(&a, seed);
        ref_seed(&r, seed, 0xa02bdbf7bb3c0a7ull);
        for (i = 0; i < 1000; i++)
            TEST_ASSERT_EQUAL_HEX32(ref_next(&r), actag_rng_next(&a));
    }
}

static void test_same_seed_same_stream_different_seeds_differ(void)
{
    actag_rng a, b, c;
    int i, same = 0;
    actag_rng_seed(&a, 7);
    actag_rng_seed(&b, 7);
    actag_rng_seed(&c, 8);
    for (i = 0; i < 10000; i++) {
        uint32_t x = actag_rng_next(&a), y = actag_rng_next(&b), z = actag_rng_next(&c);
        TEST_ASSERT_EQUAL_HEX32(x, y);
        same += x == z;
    }
    TEST_ASSERT_LESS_THAN(3, same);
    /* Re-seeding restarts the stream; copying the state forks it. */
    actag_rng_seed(&a, 7);
    actag_rng_seed(&b, 7);
    (void)actag_rng_next(&a);
    c = a;
    TEST_ASSERT_EQUAL_HEX32(actag_rng_next(&a), actag_rng_next(&c));
    /* Seeds 0 and 1 do not start in a degenerate state. */
    actag_rng_seed(&a, 0);
    same = 0;
    for (i = 0; i < 64; i++)
        same += actag_rng_next(&a) == 0u;
    TEST_ASSERT_LESS_THAN(2, same);
}

static void test_below_edge_cases(void)
{
    actag_rng r, r2;
    int i;
    actag_rng_seed(&r, 3);
    r2 = r;
    TEST_ASSERT_EQUAL_UINT32(0u, actag_rng_below(&r, 0u));
    TEST_ASSERT_EQUAL_UINT32(0u, actag_rng_below(&r, 1u));
    /* n = 0 and 1 consume nothing. */
    TEST_ASSERT_EQUAL_HEX32(actag_rng_next(&r2), actag_rng_next(&r));
    for (i = 0; i < 100000; i++) {
        TEST_ASSERT_LESS_THAN(2u, actag_rng_below(&r, 2u));
        TEST_ASSERT_LESS_THAN(7u, actag_rng_below(&r, 7u));
        TEST_ASSERT_TRUE(actag_rng_below(&r, 0xffffffffu) < 0xffffffffu);
        TEST_ASSERT_TRUE(actag_rng_below(&r, 0x80000001u) < 0x80000001u);
    }
}

/* Brute-force reference for below(): Lemire's method, restated, drawing from
 * the reference generator; the library must make the same choices. */
static uint32_t ref_below(ref_pcg *r, uint32_t n)
{
    uint64_t m;
    uint32_t thr;
    if (n <= 1)
        return 0;
    thr = (uint32_t)((0x100000000ull) % n);
    for (;;) {
        m = (uint64_t)ref_next(r) * n;
        if ((uint32_t)m >= thr)
            return (uint32_t)(m >> 32);
    }
}

static void test_below_matches_reference(void)
{
    int t, i;
    tu_seed(99);
    for (t = 0; t < 50; t++) {
        uint32_t seed = tu_rand();
        actag_rng a;
        ref_pcg r;
        actag_rng_seed(&a, seed);
        ref_seed(&r, seed, 0xa02bdbf7bb3c0a7ull);
        for (i = 0; i < 2000; i++) {
            uint32_t n = (i % 3 == 0) ? tu_rand() : (i % 3 == 1) ? (uint32_t)tu_range(0, 1000)
                                                                 : 0xc0000000u + (uint32_t)(i & 7);
            TEST_ASSERT_EQUAL_UINT32(ref_below(&r, n), actag_rng_below(&a, n));
        }
        TEST_ASSERT_EQUAL_HEX32(ref_next(&r), actag_rng_next(&a));
    }
}

static void test_below_uniform_chi_square(void)
{
    static const uint32_t ns[4] = {2u, 10u, 37u, 200u};
    /* 0.1 % critical values of chi-square with n-1 degrees of freedom. */
    static const float crit[4] = {10.83f, 27.88f, 67.99f, 267.5f};
    int t;
    for (t = 0; t < 4; t++) {
        static long counts[200];
        actag_rng r;
        long draws = 200000, i;
        float expect, chi = 0.0f;
        uint32_t k;
        memset(counts, 0, sizeof counts);
        actag_rng_seed(&r, 2024u + (uint32_t)t);
        for (i = 0; i < draws; i++)
            counts[actag_rng_below(&r, ns[t])]++;
        expect = (float)draws / (float)ns[t];
        for (k = 0; k < ns[t]; k++) {
            float dlt = (float)counts[k] - expect;
            chi += dlt * dlt / expect;
        }
        TEST_ASSERT_TRUE_MESSAGE(chi < crit[t], "chi-square too large");
    }
}

static void test_below_is_not_modulo_biased(void)
{
    /* n = 3 * 2^30: plain modulo would land in [0, 2^30) half the time
     * instead of a third. */
    actag_rng r;
    long low = 0, i, draws = 300000;
    float frac;
    actag_rng_seed(&r, 5);
    for (i = 0; i < draws; i++)
        low += actag_rng_below(&r, 0xc0000000u) < 0x40000000u;
    frac = (float)low / (float)draws;
    TEST_ASSERT_FLOAT_WITHIN(0.005f, 1.0f / 3.0f, frac);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_reference_matches_published_pcg32_demo);
    RUN_TEST(test_known_first_outputs);
    RUN_TEST(test_matches_reference_on_random_seeds);
    RUN_TEST(test_same_seed_same_stream_different_seeds_differ);
    RUN_TEST(test_below_edge_cases);
    RUN_TEST(test_below_matches_reference);
    RUN_TEST(test_below_uniform_chi_square);
    RUN_TEST(test_below_is_not_modulo_biased);
    return UNITY_END();
}
