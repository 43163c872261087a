/* The library's own trigonometry and rotations (src/trig.h, src/rotation.h)
 * against libm in double, over each function's stated domain, at random and
 * at the edges of its branches. */
#include "../src/rotation.h"

#include "unity.h"
#include "test_util.h"

#include "actag/pose.h"

#include <math.h>

#define PI 3.14159265358979323846

void setUp(void) {}
void tearDown(void) {}

/* |got - want| <= tol, with the values in the message (this Unity is built
 * without its double assertions) */
#define NEAR(tol, want, got)                                                                      \
    do {                                                                                          \
        double want_ = (want), got_ = (got);                                                      \
        char m_[160];                                                                             \
        snprintf(m_, sizeof m_, "%s: want %.9g, got %.9g (tolerance %.3g)", #got, want_, got_,    \
                 (double)(tol));                                                                  \
        TEST_ASSERT_TRUE_MESSAGE(fabs(got_ - want_) <= (tol), m_);                                \
    } while (0)

static void test_sincos(void)
{
    static const float edge[] = {0.0f, -0.0f, 0.78539819f, 0.78539813f, -0.78539819f,
                                 1.57079637f, 3.14159274f, -3.14159274f, 4.71238899f,
                                 1000.0f, -4096.5f, 8388607.0f, -8388607.0f};
    float s, c;
    int t, i;
    tu_seed(81);
    /* within the first octant's reach (no reduction): 2e-7 (2 ulps of 1) */
    for (t = 0; t < TU_TRIALS(200000, 20); t++) {
        float x = (float)tu_uniform(-0.785, 0.785);
        actag__sincos(x, &s, &c);
        NEAR(2e-7, sin((double)x), s);
        NEAR(2e-7, cos((double)x), c);
    }
    /* a few turns, every quadrant (the reduction's low part matters here:
     * with its sign flipped, 5.6e-7): 2e-7 */
    for (t = 0; t < TU_TRIALS(200000, 20); t++) {
        float x = (float)tu_uniform(-8.0, 8.0);
        actag__sincos(x, &s, &c);
        NEAR(2e-7, sin((double)x), s);
        NEAR(2e-7, cos((double)x), c);
    }
    /* far out, the quadrant count's product rounds: within an ulp of x
     * (the angle itself is no better known) */
    for (t = 0; t < TU_TRIALS(100000, 20); t++) {
        float x = (float)tu_uniform(-5000.0, 5000.0);
        double ulp = ldexp(1.0, ilogb(x) - 23);
        actag__sincos(x, &s, &c);
        NEAR(ulp + 3e-7, sin((double)x), s);
        NEAR(ulp + 3e-7, cos((double)x), c);
    }
    for (i = 0; i < (int)(sizeof edge / sizeof edge[0]); i++) {
        double ulp = edge[i] != 0.0f ? ldexp(1.0, ilogb(edge[i]) - 23) : 0.0;
        actag__sincos(edge[i], &s, &c);
        NEAR(ulp + 3e-7, sin((double)edge[i]), s);
        NEAR(ulp + 3e-7, cos((double)edge[i]), c);
        TEST_ASSERT_TRUE(s * s + c * c > 0.999999f && s * s + c * c < 1.000001f);
    }
    /* no angle left (2^23 and beyond), infinities and NaN: taken as 0 */
    actag__sincos(8388608.0f, &s, &c);
    TEST_ASSERT_TRUE(s == 0.0f && c == 1.0f);
    actag__sincos(-8388608.0f, &s, &c);
    TEST_ASSERT_TRUE(s == 0.0f && c == 1.0f);
    actag__sincos(-INFINITY, &s, &c);
    TEST_ASSERT_TRUE(s == 0.0f && c == 1.0f);
    actag__sincos(NAN, &s, &c);
    TEST_ASSERT_TRUE(s == 0.0f && c == 1.0f);
}

static void test_atan2_and_asin(void)
{
    int t;
    tu_seed(82);
    /* every quadrant, magnitudes 1e-30 to 1e30: within 3.5e-7 (1.5 ulps of pi) */
    for (t = 0; t < TU_TRIALS(300000, 20); t++) {
        double my = pow(10.0, tu_uniform(t % 3 ? -3.0 : -30.0, t % 3 ? 3.0 : 30.0));
        double mx = pow(10.0, tu_uniform(t % 3 ? -3.0 : -30.0, t % 3 ? 3.0 : 30.0));
        float y = (float)(tu_rand() & 1u ? my : -my), x = (float)(tu_rand() & 1u ? mx : -mx);
        NEAR(3.5e-7, atan2((double)y, (double)x), actag__atan2(y, x));
    }
    /* the axes and the diagonals (the branch between |y| <= |x| and above) */
    TEST_ASSERT_TRUE(actag__atan2(0.0f, 0.0f) == 0.0f);
    NEAR(3.5e-7, 0.0, actag__atan2(0.0f, 2.0f));
    NEAR(3.5e-7, PI, actag__atan2(0.0f, -2.0f));
    NEAR(3.5e-7, PI / 2, actag__atan2(2.0f, 0.0f));
    NEAR(3.5e-7, -PI / 2, actag__atan2(-2.0f, 0.0f));
    NEAR(3.5e-7, PI / 4, actag__atan2(3.0f, 3.0f));
    NEAR(3.5e-7, -3 * PI / 4, actag__atan2(-3.0f, -3.0f));
    NEAR(3.5e-7, atan2(0.267949194, 1.0), actag__atan2(0.267949194f, 1.0f));
    NEAR(3.5e-7, atan2(0.2679492, 1.0), actag__atan2(0.2679492f, 1.0f));
    /* asin over [-1, 1] (near 1 too), and clamped outside */
    for (t = 0; t < TU_TRIALS(200000, 20); t++) {
        float v = t % 4 ? (float)tu_uniform(-1.0, 1.0) : (float)(1.0 - tu_uniform(0.0, 1e-4));
        NEAR(3.5e-7, asin((double)v), actag__asin(v));
    }
    NEAR(3.5e-7, PI / 2, actag__asin(1.5f));
    NEAR(3.5e-7, -PI / 2, actag__asin(-1.5f));
    NEAR(3.5e-7, -PI / 2, actag__asin(-1.0f));
}

static void test_small_angle_forms(void)
{
    float s, c;
    int t;
    tu_seed(83);
    /* sin, cos for |d| <= 0.6 (both series: under 0.2 and above) */
    for (t = 0; t < TU_TRIALS(200000, 20); t++) {
        float d = t % 2 ? (float)tu_uniform(-0.6, 0.6) : (float)tu_uniform(-0.2, 0.2);
        actag__sincos_small(d, &s, &c);
        NEAR(1e-7, sin((double)d), s);
        NEAR(1e-7, cos((double)d), c);
    }
    /* atan: under 1e-7 to |t| = 0.6, 1e-6 to tan 0.6 = 0.684 (the
     * refinement's widest), 2e-6 to 0.7 */
    for (t = 0; t < TU_TRIALS(200000, 20); t++) {
        float a = (float)tu_uniform(-0.6, 0.6), b = (float)tu_uniform(-0.6841, 0.6841), e = (float)tu_uniform(-0.7, 0.7);
        NEAR(1e-7, atan((double)a), actag__atan_small(a));
        NEAR(1e-6, atan((double)b), actag__atan_small(b));
        NEAR(2e-6, atan((double)e), actag__atan_small(e));
    }
}

/* R = exp([w]x) in double (Rodrigues), row-major. */
static void rodrigues(const double w[3], double R[9])
{
    double th = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]), a, b;
    a = th > 0.0 ? sin(th) / th : 1.0;
    b = th > 0.0 ? (1.0 - cos(th)) / (th * th) : 0.5;
    R[0] = 1.0 - b * (w[1] * w[1] + w[2] * w[2]);
    R[1] = -a * w[2] + b * w[0] * w[1];
    R[2] = a * w[1] + b * w[0] * w[2];
    R[3] = a * w[2] + b * w[0] * w[1];
    R[4] = 1.0 - b * (w[0] * w[0] + w[2] * w[2]);
    R[5] = -a * w[0] + b * w[1] * w[2];
    R[6] = -a * w[1] + b * w[0] * w[2];
    R[7] = a * w[0] + b * w[1] * w[2];
    R[8] = 1.0 - b * (w[0] * w[0] + w[1] * w[1]);
}

/* A random rotation vector of angle in [lo, hi] (radians). */
static void random_w(double lo, double hi, double w[3])
{
    double u[3], n = 0.0, th = tu_uniform(lo, hi);
    int i;
    do {
        for (i = 0; i < 3; i++)
            u[i] = tu_uniform(-1.0, 1.0);
        n = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    } while (n < 0.1 || n > 1.0);
    for (i = 0; i < 3; i++)
        w[i] = th * u[i] / n;
}

static void test_rotations(void)
{
    int t, i;
    tu_seed(84);
    for (t = 0; t < TU_TRIALS(50000, 20); t++) {
        /* angles from 1e-6 rad (the series branch) to pi - 1e-3 */
        double w[3], Rd[9];
        float wf[3], R[9], back[9], v[3];
        random_w(t % 5 == 0 ? 0.0 : 1e-6, t % 5 == 0 ? 1e-4 : 3.1405, w);
        for (i = 0; i < 3; i++)
            wf[i] = (float)w[i];
        rodrigues(w, Rd);
        actag__rot_exp(wf, R);
        for (i = 0; i < 9; i++)
            NEAR(1e-6, Rd[i], R[i]);
        /* the inverse: the angle back within 1e-6 (near pi the axis comes
         * from the symmetric part) */
        actag__rot_log(R, v);
        for (i = 0; i < 3; i++)
            NEAR(t % 5 == 0 ? 1e-6 : 2e-5, w[i], v[i]);
        /* and through the public difference of two rotations */
        for (i = 0; i < 9; i++)
            back[i] = (float)(i % 4 == 0);
        actag_pose_rotation_vector(R, back, v);
        for (i = 0; i < 3; i++)
            NEAR(t % 5 == 0 ? 1e-6 : 2e-5, w[i], v[i]);
    }
    /* half turns about each axis and a diagonal: the axis from the
     * symmetric part, the sign from the antisymmetric (here 0: either
     * sign is the same rotation) */
    for (t = 0; t < 4; t++) {
        double w[3] = {0.0, 0.0, 0.0}, Rd[9];
        float R[9], v[3], th;
        if (t < 3)
            w[t] = PI;
        else
            w[0] = w[1] = w[2] = PI / sqrt(3.0);
        rodrigues(w, Rd);
        for (i = 0; i < 9; i++)
            R[i] = (float)Rd[i];
        actag__rot_log(R, v);
        th = actag__norm3(v);
        NEAR(1e-5, PI, th);
        for (i = 0; i < 3; i++)
            NEAR(1e-4, fabs(w[i]), fabs((double)v[i]));
    }
}

static void test_frames_and_products(void)
{
    int t, i, j;
    tu_seed(85);
    for (t = 0; t < TU_TRIALS(20000, 20); t++) {
        float xa[3], ya[3], R[9], n, v[3], o[3], M[9], Rt[9];
        for (i = 0; i < 3; i++) {
            xa[i] = (float)tu_uniform(-2.0, 2.0);
            ya[i] = (float)tu_uniform(-2.0, 2.0);
        }
        if (t % 10 == 0) /* y along x: any perpendicular */
            for (i = 0; i < 3; i++)
                ya[i] = 3.0f * xa[i];
        if (t % 10 == 1) /* y 1-6 degrees off x */
            for (i = 0; i < 3; i++)
                ya[i] = xa[i] + (float)tu_uniform(-0.05, 0.05) * actag__norm3(xa);
        if (t % 10 == 2) /* y zero */
            ya[0] = ya[1] = ya[2] = 0.0f;
        actag__rot_from_axes(xa, ya, R);
        /* orthonormal, right-handed, first column along xa, second in the
         * plane of xa and ya on ya's side */
        for (i = 0; i < 3; i++)
            for (j = 0; j < 3; j++) {
                double d = R[i] * R[j] + R[3 + i] * R[3 + j] + R[6 + i] * R[6 + j];
                NEAR(2e-6, i == j ? 1.0 : 0.0, d);
            }
        n = actag__norm3(xa);
        for (i = 0; i < 3; i++)
            NEAR(2e-6, xa[i] / n, R[3 * i]);
        {
            float c0[3] = {R[0], R[3], R[6]}, c1[3] = {R[1], R[4], R[7]}, c2[3] = {R[2], R[5], R[8]};
            actag__cross3(c0, c1, o);
            for (i = 0; i < 3; i++)
                NEAR(2e-6, c2[i], o[i]);
            if (t % 10 > 2)
                TEST_ASSERT_TRUE(actag__dot3(c1, ya) > 0.0f);
        }
        /* products: R v against the sums, R R^T = I */
        for (i = 0; i < 3; i++)
            v[i] = (float)tu_uniform(-5.0, 5.0);
        actag__mat_vec(R, v, o);
        for (i = 0; i < 3; i++)
            NEAR(1e-5, (double)R[3 * i] * v[0] + (double)R[3 * i + 1] * v[1] +
                                                (double)R[3 * i + 2] * v[2],
                                      o[i]);
        for (i = 0; i < 3; i++)
            for (j = 0; j < 3; j++)
                Rt[3 * i + j] = R[3 * j + i];
        actag__mat_mul(R, Rt, M);
        for (i = 0; i < 9; i++)
            NEAR(3e-6, i % 4 == 0 ? 1.0 : 0.0, M[i]);
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_sincos);
    RUN_TEST(test_atan2_and_asin);
    RUN_TEST(test_small_angle_forms);
    RUN_TEST(test_rotations);
    RUN_TEST(test_frames_and_products);
    return UNITY_END();
}
