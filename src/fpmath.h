/*
 * fpmath.h -- internal: the same floating-point results whatever compiler
 * flags a project builds the library's sources with. Every src/ file
 * includes it first. Checked by .ci/fpcontract: the Cortex-M7 library at
 * -std=gnu99 -ffp-contract=fast gives the x86 build's armcheck report (and
 * without the pragma below it does not), and host GCC and Clang builds
 * under the flags of 1. and 2. give the CMake build's actag_detect output
 * or are refused as said there.
 *
 * 1. No fused multiply-add. GCC contracts a*b+c into one fused operation
 *    (a single rounding) wherever the target has one (Cortex-M4F/M7 VFMA,
 *    x86 FMA3 with -march=haswell and later) unless -ffp-contract=off is
 *    given; its default in the GNU dialects (-std=gnu99, what most firmware
 *    IDEs use) is -ffp-contract=fast, and GCC ignores the standard
 *    "#pragma STDC FP_CONTRACT OFF" (with a warning). Contraction would move
 *    corners in the last bits against the x86 build and could flip a
 *    decision near a threshold. So: the GCC pragma that sets the option for
 *    the rest of the file, the standard pragma for Clang and other
 *    compilers. Clang's -ffp-contract=fast ignores the standard pragma
 *    by definition (clang 14, -march=haswell: a*b+c here becomes vfmadd;
 *    its fast-honor-pragmas is refused as an unsupported argument), so
 *    actag_fp_fuses() below finds such a build at run time and the entry
 *    points (actag_check, hence actag_detect and the tracker, and
 *    actag_pose_estimate) return ACTAG_ERR_BUILD. The shipped CMake passes
 *    -ffp-contract=off to GCC and Clang alike.
 * 2. The other flags that change float results: GCC's -freciprocal-math,
 *    -fassociative-math, -funsafe-math-optimizations and
 *    -ffinite-math-only (which would compile the validators' NaN checks
 *    out) are reset for these files by the same GCC pragma, and Clang's
 *    on x86 by "float_control(precise, on)" but for -ffinite-math-only,
 *    which is refused at compile time. Clang ignores float_control on ARM
 *    and AArch64: there "clang fp reassociate(off)" stops reassociation
 *    and actag_fp_fuses() also finds divisions rewritten as reciprocal
 *    products (-freciprocal-math, -funsafe-math-optimizations), so such a
 *    build is refused at run time too. -ffast-math (__FAST_MATH__) and
 *    x87 excess precision (FLT_EVAL_METHOD != 0: i386 without -msse2
 *    -mfpmath=sse) are refused at compile time.
 * 3. No errno. libm's sqrtf and logf set errno on a domain error, and on
 *    newlib that pulls the reentrancy structure (impure_data, ~1 KB of
 *    .data) into every firmware; GCC only inlines sqrtf without a call
 *    under -fno-math-errno. actag_sqrtf and actag_logf need no libm on
 *    Cortex-M: sqrtf is the FPU's VSQRT.F32 (correctly rounded, as x86's
 *    SQRTSS and glibc's sqrtf), an exact integer square root on cores
 *    without one; logf is computed here (deterministic on every platform,
 *    correctly rounded but for inputs within 1e-15 of a rounding boundary,
 *    see actag_logf).
 */
#ifndef ACTAG_SRC_FPMATH_H
#define ACTAG_SRC_FPMATH_H

/* Before any other header, so every function of the file gets it. GCC:
 * the options that change float results, reset for the rest of the file
 * (a project's -freciprocal-math, -funsafe-math-optimizations,
 * -fassociative-math or -ffinite-math-only then leave these sources
 * alone). Clang: precise semantics for the file where it honours
 * float_control (x86, PowerPC, SystemZ: undoes the reciprocal,
 * reassociation and unsafe-math flags; clang 11 and later); elsewhere (ARM,
 * AArch64, RISC-V) only reassociation can be switched off by a pragma
 * (clang 12), and its -freciprocal-math (or -funsafe-math-optimizations,
 * which implies it) is caught at run time with -ffp-contract=fast
 * (actag_fp_fuses); its -ffinite-math-only is refused below. */
#if defined(__clang__)
/* float_control is honoured on some targets only (clang 14: x86, PowerPC,
 * SystemZ; ignored with a warning on ARM, AArch64 and RISC-V, hence the
 * diagnostic kept quiet): where it is ignored, reassociation is switched
 * off below and reciprocal rewrites are caught at run time
 * (actag_fp_fuses). Apple's clang 12 is LLVM 10, without "fp reassociate". */
#if __clang_major__ >= 11
#pragma clang diagnostic push
#pragma clang diagnostic ignored "-Wignored-pragmas"
#pragma float_control(precise, on)
#pragma clang diagnostic pop
#endif
#if __clang_major__ >= 13 || (__clang_major__ >= 12 && !defined(__apple_build_version__))
#pragma clang fp reassociate(off)
#endif
#pragma STDC FP_CONTRACT OFF
#elif defined(__GNUC__)
#pragma GCC optimize("fp-contract=off", "no-unsafe-math-optimizations", "no-associative-math", \
                     "no-reciprocal-math", "signed-zeros", "trapping-math", "no-finite-math-only")
#else
#pragma STDC FP_CONTRACT OFF
#endif

#include <float.h>
#include <stdint.h>
#include <string.h>

#if defined(__FAST_MATH__)
#error "actag: built with -ffast-math; results would differ between platforms (drop it for the actag sources)"
#endif
#if defined(__clang__) && defined(__FINITE_MATH_ONLY__) && __FINITE_MATH_ONLY__
#error "actag: built with -ffinite-math-only; the NaN checks of the validators would be compiled out (drop it for the actag sources)"
#endif
/* 16: GCC 12 with AVX512-FP16 (-march=native on such a CPU) in a GNU
 * dialect; it concerns _Float16 only, float is still evaluated as float */
#if defined(FLT_EVAL_METHOD) && FLT_EVAL_METHOD != 0 && FLT_EVAL_METHOD != -1 && FLT_EVAL_METHOD != 16
#error "actag: float arithmetic in excess precision (FLT_EVAL_METHOD != 0); on i386 use -msse2 -mfpmath=sse"
#endif

#if defined(__GNUC__) && defined(__arm__) && defined(__ARM_FP) && (__ARM_FP & 4) && !defined(__SOFTFP__)
#define ACTAG__VSQRT 1 /* single-precision FPU with the hard or softfp ABI */
#elif defined(__arm__) || defined(__thumb__)
#define ACTAG__SOFT_SQRT 1 /* no FPU: libm's sqrtf would set errno */
#else
#include <math.h>
#endif

/* Correctly rounded square root of a float (round to nearest even), from
 * its bits only; NaN for x < 0 (and NaN in), +-0 and +inf unchanged. */
static inline float actag_sqrtf_soft(float x)
{
    uint32_t u, m, q, r, b;
    int e;
    memcpy(&u, &x, sizeof u);
    if ((u & 0x7fffffffu) == 0u || u == 0x7f800000u || (u & 0x7fffffffu) > 0x7f800000u)
        return x; /* +-0, +inf, NaN */
    if (u & 0x80000000u) {
        u = 0x7fc00000u; /* sqrt of a negative number */
        memcpy(&x, &u, sizeof x);
        return x;
    }
    e = (int)(u >> 23);
    m = u & 0x7fffffu;
    if (e == 0) { /* subnormal: normalise */
        e = 1;
        while ((m & 0x800000u) == 0u) {
            m <<= 1;
            e--;
        }
    } else {
        m |= 0x800000u;
    }
    e -= 127;          /* x = m * 2^(e - 23), m in [2^23, 2^24) */
    if (e & 1) {       /* make the exponent even */
        m <<= 1;
        e--;
    }
    /* sqrt(m * 2^25) has 24 or 25 bits: bit-by-bit integer root of m << 25
     * (up to 50 bits), done as a 64-bit remainder */
    {
        uint64_t rem = (uint64_t)m << 25, root = 0, bit = (uint64_t)1 << 48;
        while (bit > rem)
            bit >>= 2;
        while (bit != 0u) {
            if (rem >= root + bit) {
                rem -= root + bit;
                root = (root >> 1) + bit;
            } else {
                root >>= 1;
            }
            bit >>= 2;
        }
        q = (uint32_t)root; /* floor(sqrt(m << 25)), in [2^24, 2^25) */
        r = rem != 0u;      /* inexact */
    }
    /* q has one guard bit below the 24 result bits; the sticky bit is r */
    b = q & 1u;
    q >>= 1;
    if (b && (r || (q & 1u)))
        q++; /* round to nearest, ties to even (a tie needs r == 0) */
    e = e / 2 + 127;
    if (q == 0x1000000u) { /* rounded up to the next power of two */
        q >>= 1;
        e++;
    }
    u = ((uint32_t)e << 23) | (q & 0x7fffffu);
    memcpy(&x, &u, sizeof x);
    return x;
}

/* sqrtf without errno: the same correctly rounded result on every platform. */
static inline float actag_sqrtf(float x)
{
#if defined(ACTAG__VSQRT)
    float r;
    __asm__("vsqrt.f32 %0, %1" : "=t"(r) : "t"(x));
    return r;
#elif defined(ACTAG__SOFT_SQRT)
    return actag_sqrtf_soft(x);
#else
    return sqrtf(x);
#endif
}

/* (float)v, the same value, without the 64-bit conversion helper where v
 * fits 32 bits: 32-bit cores (Cortex-M) convert an int64 by a libgcc call
 * (__aeabi_l2f, about 40 instructions); an int32 converts in one. Both
 * round the same integer to nearest, so the result is identical. */
static inline float actag_i64_to_f(int64_t v)
{
    return v >= INT32_MIN && v <= INT32_MAX ? (float)(int32_t)v : (float)v;
}

/* Natural logarithm of x > 0 (NaN for x < 0 or NaN, -inf for 0, +inf for
 * +inf), without errno or libm: x = m 2^e with m in [sqrt(1/2), sqrt(2)),
 * ln x = e ln 2 + 2 atanh(s), s = (m - 1) / (m + 1), |s| < 0.172, by its
 * series to s^23 in double (relative error < 1e-16), then rounded once to
 * float. Identical on every IEEE platform (no contraction, see above). */
static inline float actag_logf(float x)
{
    uint32_t u;
    int e;
    double m, s, s2, t, ln;
    float r;
    memcpy(&u, &x, sizeof u);
    if ((u & 0x7fffffffu) == 0u) {
        u = 0xff800000u; /* -inf */
        memcpy(&r, &u, sizeof r);
        return r;
    }
    if ((u & 0x80000000u) || (u & 0x7fffffffu) > 0x7f800000u) {
        u = 0x7fc00000u;
        memcpy(&r, &u, sizeof r);
        return r;
    }
    if (u == 0x7f800000u)
        return x;
    e = (int)(u >> 23) - 127;
    if (e == -127) { /* subnormal */
        uint32_t mm = u & 0x7fffffu;
        e = -126;
        while ((mm & 0x800000u) == 0u) {
            mm <<= 1;
            e--;
        }
        m = (double)(mm & 0x7fffffu) / 8388608.0 + 1.0;
    } else {
        m = (double)(u & 0x7fffffu) / 8388608.0 + 1.0; /* [1, 2) */
    }
    if (m > 1.4142135623730951) {
        m *= 0.5;
        e++;
    }
    s = (m - 1.0) / (m + 1.0);
    s2 = s * s;
    t = 1.0 / 23.0;
    t = t * s2 + 1.0 / 21.0;
    t = t * s2 + 1.0 / 19.0;
    t = t * s2 + 1.0 / 17.0;
    t = t * s2 + 1.0 / 15.0;
    t = t * s2 + 1.0 / 13.0;
    t = t * s2 + 1.0 / 11.0;
    t = t * s2 + 1.0 / 9.0;
    t = t * s2 + 1.0 / 7.0;
    t = t * s2 + 1.0 / 5.0;
    t = t * s2 + 1.0 / 3.0;
    t = t * s2;
    /* ln 2 = 0.693147180369123816490 + 1.90821492927058770002e-10: the
     * first part has 32 significant bits, so e * it is exact */
    ln = (double)e * 6.93147180369123816490e-01;
    ln += 2.0 * s + (2.0 * s * t + (double)e * 1.90821492927058770002e-10);
    return (float)ln;
}

/* Does this build fuse a multiply and an add into one rounding? Clang's
 * -ffp-contract=fast ignores the pragmas above (GCC's honours them), and
 * fused operations move corners and can flip decisions. (1 + 2^-12)^2 =
 * 1 + 2^-11 + 2^-24: the rounded product drops the 2^-24 (a tie, to even),
 * which a fused a * b - p keeps. The operands are volatile reads, so the
 * compiler cannot fold the test away or share the two products. (Kept
 * apart from the test below: merged into one expression with it, clang
 * 14 -march=haswell -ffp-contract=fast no longer fused this one.) */
static inline int actag__fp_fma(void)
{
    volatile float va = 1.000244140625f, vb = 1.000244140625f, vp;
    float a = va, b = vb, p;
    vp = a * b;
    p = vp;
    a = va;
    b = vb;
    return a * b - p != 0.0f;
}

/* Does this build turn divisions into products with a reciprocal? Clang's
 * -freciprocal-math or -funsafe-math-optimizations on ARM, AArch64 or
 * RISC-V, where its float_control pragma is ignored (clang 14: the pose's results
 * changed). 10/3, 20/3 and 40/3 round down, 10, 20 and 40 times float(1/3)
 * up; three quotients by one divisor and one by a constant are the shapes
 * clang rewrites (AArch64 from three uses, ARM the constant). Volatile
 * operands; the comparisons combined without branches, which would put the
 * quotients in separate blocks (clang rewrites repeated divisors within
 * one). */
static inline int actag__fp_reciprocal(void)
{
    volatile float vx = 10.0f, vy = 20.0f, vw = 40.0f, vz = 3.0f;
    float x = vx, y = vy, w = vw, z = vz;
    return (x / z != 0x1.aaaaaap+1f) | (y / z != 0x1.aaaaaap+2f) | (w / z != 0x1.aaaaaap+3f) |
           (x / 3.0f != 0x1.aaaaaap+1f);
}

/* Nonzero when this build rounds float arithmetic other than IEEE's way
 * in one of the two ways above (the entry points then return
 * ACTAG_ERR_BUILD): ACTAG__FP_FMA | ACTAG__FP_RECIPROCAL, which says which. */
#define ACTAG__FP_FMA 1
#define ACTAG__FP_RECIPROCAL 2
static inline int actag_fp_fuses(void)
{
    int r = actag__fp_fma() ? ACTAG__FP_FMA : 0;
    if (actag__fp_reciprocal())
        r |= ACTAG__FP_RECIPROCAL;
    return r;
}

#endif
