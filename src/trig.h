/* Float trigonometry from sums, products and sqrtf only (internal): libm's
 * sinf/atan2f differ in the last bits between C libraries, and the
 * library's results must not. Used by pose.c (any angle) and refine.c
 * (the small-angle forms, on its hot path); tested against libm in double
 * by tests/test_trig.c over each function's stated domain. Static, so
 * each caller compiles them as its own, as before; a file that includes
 * this header includes fpmath.h first (this header does so itself). */
#ifndef ACTAG_TRIG_H
#define ACTAG_TRIG_H

#include "fpmath.h"

/* Static functions, not inline: the compiler inlines them where it would
 * have inlined the file-local functions they were (pose.c grew 5 KB on the
 * Cortex-M4 with "inline"), and says nothing of the ones a file does not
 * call. */
#if defined(__GNUC__)
#define ACTAG__INTERNAL static __attribute__((unused))
#else
#define ACTAG__INTERNAL static
#endif

#define ACTAG__PIO2_HI 1.57079637e+00f  /* float(pi/2) */
#define ACTAG__PIO2_LO -4.37113883e-08f /* pi/2 - ACTAG__PIO2_HI */

/* sin and cos of r, |r| <= pi/4 */
ACTAG__INTERNAL float actag__sin_k(float r)
{
    float z = r * r;
    return r + r * z * (-1.66666672e-01f +
                        z * (8.33333377e-03f + z * (-1.98412701e-04f + z * 2.75573188e-06f)));
}

ACTAG__INTERNAL float actag__cos_k(float r)
{
    float z = r * r;
    return 1.0f + z * (-0.5f + z * (4.16666679e-02f +
                                    z * (-1.38888892e-03f + z * (2.48015876e-05f -
                                                                 z * 2.75573188e-07f))));
}

/* sin and cos together; accurate for |x| up to a few thousand radians and
 * defined for any x. Past 2^23 floats are a radian or more apart (no angle
 * is left in them) and past 3.4e9 the quadrant count overflows the int: a
 * float-to-int conversion out of range is undefined behaviour, and x86 and
 * ARM then give different results (garbage corners fitted with tiny sds
 * steered a rotation step there). Such an x, or a NaN, is taken as 0. */
ACTAG__INTERNAL void actag__sincos(float x, float *s, float *c)
{
    float kf, r, sr, cr;
    int k;
    if (!(x > -8388608.0f && x < 8388608.0f))
        x = 0.0f;
    kf = x * 0.636619772f;
    kf = kf >= 0.0f ? kf + 0.5f : kf - 0.5f;
    k = (int)kf;
    r = (x - (float)k * ACTAG__PIO2_HI) - (float)k * ACTAG__PIO2_LO;
    sr = actag__sin_k(r);
    cr = actag__cos_k(r);
    switch (k & 3) {
    case 0: *s = sr; *c = cr; break;
    case 1: *s = cr; *c = -sr; break;
    case 2: *s = -sr; *c = -cr; break;
    default: *s = -cr; *c = sr; break;
    }
}

/* atan(x), |x| <= 1 */
ACTAG__INTERNAL float actag__atan01(float x)
{
    const float t15 = 0.267949194f, sqrt3 = 1.73205081f, pio6 = 0.523598776f;
    float off = 0.0f, z;
    int neg = x < 0.0f; /* an int: Clang's -Wconversion refuses a float tested as a bool */
    if (neg)
        x = -x;
    if (x > t15) {
        x = (x * sqrt3 - 1.0f) / (x + sqrt3);
        off = pio6;
    }
    z = x * x;
    x = off + x * (1.0f + z * (-3.33333343e-01f +
                               z * (2.00000003e-01f +
                                    z * (-1.42857149e-01f +
                                         z * (1.11111112e-01f - z * 9.09090936e-02f)))));
    return neg ? -x : x;
}

ACTAG__INTERNAL float actag__atan2(float y, float x)
{
    float ax = x < 0.0f ? -x : x, ay = y < 0.0f ? -y : y, a;
    if (ax == 0.0f && ay == 0.0f)
        return 0.0f;
    if (ay <= ax)
        a = actag__atan01(ay / ax);
    else
        a = (ACTAG__PIO2_HI - actag__atan01(ax / ay)) + ACTAG__PIO2_LO; /* pi/2 - atan(ax / ay) */
    if (x < 0.0f)
        a = (2.0f * ACTAG__PIO2_HI - a) + 2.0f * ACTAG__PIO2_LO; /* pi - a */
    return y < 0.0f ? -a : a;
}

ACTAG__INTERNAL float actag__asin(float v)
{
    if (v > 1.0f)
        v = 1.0f;
    if (v < -1.0f)
        v = -1.0f;
    return actag__atan2(v, actag_sqrtf((1.0f - v) * (1.0f + v)));
}

/* sin, cos of a small angle (|d| <= 0.6: Taylor, error < 1e-8; |d| < 0.2,
 * most pixels of a tag about its centre beam: two terms fewer, error
 * < 3e-9) */
ACTAG__INTERNAL void actag__sincos_small(float d, float *s, float *c)
{
    const float i6 = 1.0f / 6.0f, i20 = 1.0f / 20.0f, i42 = 1.0f / 42.0f, i72 = 1.0f / 72.0f;
    const float i12 = 1.0f / 12.0f, i30 = 1.0f / 30.0f, i56 = 1.0f / 56.0f;
    float d2 = d * d;
    if (d2 < 0.04f) {
        *s = d * (1.0f - d2 * i6 * (1.0f - d2 * i20));
        *c = 1.0f - d2 * 0.5f * (1.0f - d2 * i12 * (1.0f - d2 * i30));
        return;
    }
    *s = d * (1.0f - d2 * i6 * (1.0f - d2 * i20 * (1.0f - d2 * i42 * (1.0f - d2 * i72))));
    *c = 1.0f - d2 * 0.5f * (1.0f - d2 * i12 * (1.0f - d2 * i30 * (1.0f - d2 * i56)));
}

/* atan(t), |t| <= 0.7: the series to t^25; error under 1e-7 to |t| = 0.6,
 * 1e-6 to tan 0.6 = 0.684 (the refinement's widest, refine.c: an azimuth
 * error of a micrometre at a metre), 1.7e-6 at 0.7 (test_trig; this said
 * 2e-7 to 0.7 before it was measured) */
ACTAG__INTERNAL float actag__atan_small(float t)
{
    float t2 = t * t, s = 0.0f;
    int i;
    for (i = 25; i >= 1; i -= 2)
        s = 1.0f / (float)i - t2 * s;
    return t * s;
}

#endif
