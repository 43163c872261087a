/* src/fpmath.h: the library's errno-free square root and logarithm against
 * libm (brute force over spread samples of every float exponent, and the
 * special values), its int64 conversion against the plain cast. Its
 * contraction guard is checked by .ci/fpcontract. */
#include "../src/fpmath.h"

#include "unity.h"
#include "test_util.h"

#include "actag/family.h"

#include <math.h>

void setUp(void) {}
void tearDown(void) {}

static float from_bits(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static uint32_t to_bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

/* Every positive finite float in steps (TU: fewer under emulation), the
 * subnormals, both ends of every binade: the integer root equals libm's
 * sqrtf (correctly rounded, IEEE 754) bit for bit, and so does
 * actag_sqrtf (VSQRT.F32 on the Cortex-M builds). */
static void test_sqrt_equals_libm(void)
{
    uint32_t u, step = TU_EMULATED ? 9973u : 997u;
    long n = 0;
    for (u = 0; u < 0x7f800000u; u += step) {
        float x = from_bits(u), want = sqrtf(x);
        TEST_ASSERT_EQUAL_HEX32(to_bits(want), to_bits(actag_sqrtf_soft(x)));
        TEST_ASSERT_EQUAL_HEX32(to_bits(want), to_bits(actag_sqrtf(x)));
        n++;
    }
    for (u = 1; u < 0x00800000u; u = u * 3u + 1u) { /* subnormals */
        float x = from_bits(u);
        TEST_ASSERT_EQUAL_HEX32(to_bits(sqrtf(x)), to_bits(actag_sqrtf_soft(x)));
    }
    for (u = 0x00800000u; u < 0x7f800000u; u += 0x00800000u) { /* binade edges */
        TEST_ASSERT_EQUAL_HEX32(to_bits(sqrtf(from_bits(u))), to_bits(actag_sqrtf_soft(from_bits(u))));
        TEST_ASSERT_EQUAL_HEX32(to_bits(sqrtf(from_bits(u - 1u))),
                                to_bits(actag_sqrtf_soft(from_bits(u - 1u))));
    }
    TEST_ASSERT_EQUAL_HEX32(0x00000000u, to_bits(actag_sqrtf_soft(0.0f)));
    TEST_ASSERT_EQUAL_HEX32(0x80000000u, to_bits(actag_sqrtf_soft(-0.0f)));
    TEST_ASSERT_EQUAL_HEX32(0x7f800000u, to_bits(actag_sqrtf_soft(from_bits(0x7f800000u))));
    TEST_ASSERT_TRUE(isnan(actag_sqrtf_soft(-1.0f)));
    TEST_ASSERT_TRUE(isnan(actag_sqrtf_soft(from_bits(0x7fc00000u))));
    TEST_ASSERT_TRUE(isnan(actag_sqrtf(-1.0f)));
    TEST_ASSERT_GREATER_THAN(TU_EMULATED ? 200000 : 2000000, n);
}

/* actag_logf is the float nearest to log(x) in double (a tie within 1e-9
 * of a float's spacing may go either way), over every binade. */
static void test_log_correctly_rounded(void)
{
    uint32_t u, step = TU_EMULATED ? 99991u : 9973u;
    long ties = 0, n = 0;
    for (u = 1; u < 0x7f800000u; u += step) {
        float x = from_bits(u), got = actag_logf(x);
        double exact = log((double)x);
        float near = (float)exact;
        if (to_bits(got) != to_bits(near)) {
            /* only allowed when exact lies (almost) half-way between them */
            double mid = 0.5 * ((double)got + (double)near);
            double spacing = fabs((double)got - (double)near);
            TEST_ASSERT_TRUE_MESSAGE(fabs(exact - mid) <= 1e-9 * spacing, "logf not nearest");
            ties++;
        }
        n++;
    }
    TEST_ASSERT_LESS_THAN(n / 10000 + 2, ties);
    TEST_ASSERT_EQUAL_HEX32(0xff800000u, to_bits(actag_logf(0.0f)));
    TEST_ASSERT_EQUAL_HEX32(0x7f800000u, to_bits(actag_logf(from_bits(0x7f800000u))));
    TEST_ASSERT_EQUAL_HEX32(0u, to_bits(actag_logf(1.0f)));
    TEST_ASSERT_TRUE(isnan(actag_logf(-2.0f)));
    TEST_ASSERT_TRUE(isnan(actag_logf(from_bits(0x7fc00000u))));
}

/* The decoder's look-elsewhere allowance, ln(8 ncodes [x 165]), has the
 * same value it had with libm's logf for every built-in family (x86 glibc;
 * under emulation newlib's logf, also equal here). */
static void test_log_of_builtin_family_sizes(void)
{
    int i, w;
    for (i = 0; i < actag_family_count(); i++) {
        actag_family f;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get_at(i, &f));
        for (w = 0; w < 2; w++) {
            float x = 8.0f * (float)f.ncodes * (w ? 165.0f : 1.0f);
            TEST_ASSERT_EQUAL_HEX32_MESSAGE(to_bits(logf(x)), to_bits(actag_logf(x)), f.name);
        }
    }
}

/* actag_i64_to_f equals (float) of the int64 at the int32 limits, on both
 * sides of them, at values that round (beyond 2^24) and at random ones. */
static void test_i64_to_f_equals_the_cast(void)
{
    static const int64_t edge[] = {0, 1, -1, 16777216, 16777217, -16777217, 33554431,
                                   INT32_MAX, INT32_MAX - 1, (int64_t)INT32_MAX + 1,
                                   INT32_MIN, (int64_t)INT32_MIN + 1, (int64_t)INT32_MIN - 1,
                                   INT64_MAX, INT64_MIN, (int64_t)1 << 40, -((int64_t)1 << 40) - 3};
    size_t i;
    int t;
    for (i = 0; i < sizeof edge / sizeof edge[0]; i++)
        TEST_ASSERT_EQUAL_UINT32(to_bits((float)edge[i]), to_bits(actag_i64_to_f(edge[i])));
    tu_seed(5);
    for (t = 0; t < 100000; t++) {
        /* magnitudes spread over 0 .. 2^40 */
        int64_t v = (int64_t)(tu_rand() >> (t % 32)) << (t % 9);
        if (t & 1)
            v = -v;
        TEST_ASSERT_EQUAL_UINT32(to_bits((float)v), to_bits(actag_i64_to_f(v)));
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_sqrt_equals_libm);
    RUN_TEST(test_log_correctly_rounded);
    RUN_TEST(test_log_of_builtin_family_sizes);
    RUN_TEST(test_i64_to_f_equals_the_cast);
    return UNITY_END();
}
