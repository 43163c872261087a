/* RANSAC parallelogram fit to one contour (paper Algorithm 2); see quad.h. */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/quad.h"

#include "cpu_x86.h" /* ACTAG__AVX2 */

#include <math.h>
#include <string.h>

/* Cortex-M4/M7 (__ARM_FEATURE_SIMD32, little-endian, unaligned LDR): a
 * point's two coordinates by one load and the DSP multiply-accumulates of
 * halfwords in walk_raw(); ACTAG_NO_DSP selects the portable C there too
 * (the same sums modulo 2^32). */
#if defined(__ARM_FEATURE_SIMD32) && defined(__ARM_FEATURE_DSP) && defined(__GNUC__) &&        \
    !defined(ACTAG_NO_DSP) && !defined(__ARM_BIG_ENDIAN) && defined(__ARM_FEATURE_UNALIGNED)
#define QUAD_DSP 1
#else
#define QUAD_DSP 0
#endif

#if QUAD_DSP && !defined(QUAD_SMLA_DEFINED) /* tests/test_quad_paths.c includes this file twice */
#define QUAD_SMLA_DEFINED 1
/* SMLABB / SMLABT / SMLATT: acc + the product of the chosen signed
 * halfwords of a and b, modulo 2^32. Inline asm rather than arm_acle.h's
 * __smlabb etc., which GCC before 10 does not have. */
#define QUAD_SMLA(op)                                                                          \
    static inline uint32_t quad_##op(uint32_t a, uint32_t b, uint32_t acc)                     \
    {                                                                                          \
        uint32_t r;                                                                            \
        __asm__(#op " %0, %1, %2, %3" : "=r"(r) : "r"(a), "r"(b), "r"(acc));                  \
        return r;                                                                              \
    }
QUAD_SMLA(smlabb)
QUAD_SMLA(smlabt)
QUAD_SMLA(smlatt)
#undef QUAD_SMLA
#endif

/* The claim loop skips points along chains (claim() below) where the
 * compiler has no vector unit to vectorise the plain loop (Cortex-M, ...);
 * with one (SSE2, NEON, ...) the plain loop is cheaper (x86-64: 253 M vs
 * 284 M instructions over 20 pool frames). ACTAG_QUAD_FORCE_SKIP selects
 * the skipping anywhere (the tests check it); ACTAG_QUAD_REFERENCE keeps
 * every plain loop and no early exit. */
#if !defined(ACTAG_QUAD_REFERENCE) &&                                                          \
    (defined(ACTAG_QUAD_FORCE_SKIP) ||                                                         \
     !(defined(__SSE2__) || defined(__ARM_NEON) || defined(__ARM_FEATURE_MVE) ||              \
       defined(__riscv_vector) || defined(__ALTIVEC__)))
#define QUAD_SKIP 1
#endif

/* x86 SSE2 (every x86-64): the hot per-point loops four points a step,
 * each lane doing the scalar loop's float operations in the same order
 * (no FMA), the integer sums modulo 2^32 (any order); the scalar loops
 * finish each range. ACTAG_NO_SIMD selects the plain C. */
#if defined(__SSE2__) && !defined(ACTAG_NO_SIMD) && !defined(ACTAG_QUAD_REFERENCE)
#define QUAD_SSE2 1
#include <emmintrin.h>
#endif

/* x86-64 with AVX2 (chosen at run time, cpu_x86.h): claim, the far-point
 * sums and the inlier count eight points a step; no FMA (the target is
 * AVX2 alone). walk_raw stays SSE2 (its eight-point steps were slower). */
#if defined(QUAD_SSE2) && ACTAG__AVX2
#define QUAD_AVX2 1
#endif

/* Forced inlining of the fast paths' per-point helpers (loops called twice
 * for the two stretches of a cyclic run, the sides of quad_inliers). */
#if defined(__GNUC__)
#define QUAD_INLINE __attribute__((always_inline)) static inline
#else
#define QUAD_INLINE static inline
#endif

#ifdef QUAD_SSE2
/* Set bits of b in [0, 15] (SSE2 has no POPCNT): a nibble table. */
QUAD_INLINE int quad_pop4(int b) { return (int)((0x4332322132212110ull >> (4 * b)) & 15u); }

/* All ones in the lanes of the four labels at lab that are 0 (unclaimed). */
QUAD_INLINE __m128i quad_free4(const unsigned char *lab)
{
    uint32_t w;
    __m128i f;
    memcpy(&w, lab, sizeof w);
    f = _mm_cmpeq_epi8(_mm_cvtsi32_si128((int)w), _mm_setzero_si128());
    f = _mm_unpacklo_epi8(f, f);
    return _mm_unpacklo_epi16(f, f);
}

/* fabsf(nx * fx[i] + ny * fy[i] - c) of four points: the same roundings. */
QUAD_INLINE __m128 quad_adist4(const float *fx, const float *fy, __m128 nx, __m128 ny, __m128 c)
{
    const __m128 t = _mm_add_ps(_mm_mul_ps(nx, _mm_loadu_ps(fx)), _mm_mul_ps(ny, _mm_loadu_ps(fy)));
    return _mm_and_ps(_mm_sub_ps(t, c), _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff)));
}

/* The sum of the four 32-bit lanes, modulo 2^32. */
QUAD_INLINE uint32_t quad_hsum(__m128i v)
{
    v = _mm_add_epi32(v, _mm_shuffle_epi32(v, 0x4e));
    v = _mm_add_epi32(v, _mm_shuffle_epi32(v, 0xb1));
    return (uint32_t)_mm_cvtsi128_si32(v);
}

/* Raw moment sums of four points (x, y int16 pairs) masked by f, added to
 * s[0..4] = sum x, y, xx, xy, yy lanes (modulo 2^32): PMADDWD's 16-bit
 * products are exact. */
QUAD_INLINE void quad_sums4(const actag_ipoint *p, __m128i f, __m128i s[5])
{
    const __m128i v = _mm_and_si128(_mm_loadu_si128((const __m128i *)(const void *)p), f);
    const __m128i vx = _mm_and_si128(v, _mm_set1_epi32(0xffff)), vy = _mm_srli_epi32(v, 16);
    s[0] = _mm_add_epi32(s[0], _mm_madd_epi16(v, _mm_set1_epi32(1))); /* x * 1 + y * 0 */
    s[1] = _mm_add_epi32(s[1], _mm_srai_epi32(v, 16));
    s[2] = _mm_add_epi32(s[2], _mm_madd_epi16(vx, vx));
    s[3] = _mm_add_epi32(s[3], _mm_madd_epi16(vx, vy));
    s[4] = _mm_add_epi32(s[4], _mm_madd_epi16(vy, vy));
}
#endif

#ifdef QUAD_AVX2
/* quad_free4, quad_adist4 and quad_sums4 for eight points (s: 8-lane
 * sums). */
ACTAG__AVX2_TARGET static inline __m256i quad_free8(const unsigned char *lab)
{
    const __m256i b = _mm256_cvtepu8_epi32(_mm_loadl_epi64((const __m128i *)(const void *)lab));
    return _mm256_cmpeq_epi32(b, _mm256_setzero_si256());
}

ACTAG__AVX2_TARGET static inline __m256 quad_adist8(const float *fx, const float *fy, __m256 nx,
                                                     __m256 ny, __m256 c)
{
    const __m256 t = _mm256_add_ps(_mm256_mul_ps(nx, _mm256_loadu_ps(fx)),
                                   _mm256_mul_ps(ny, _mm256_loadu_ps(fy)));
    return _mm256_and_ps(_mm256_sub_ps(t, c), _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff)));
}

ACTAG__AVX2_TARGET static inline void quad_sums8(const actag_ipoint *p, __m256i f, __m256i s[5])
{
    const __m256i v = _mm256_and_si256(_mm256_loadu_si256((const __m256i *)(const void *)p), f);
    const __m256i vx = _mm256_and_si256(v, _mm256_set1_epi32(0xffff));
    const __m256i vy = _mm256_srli_epi32(v, 16);
    s[0] = _mm256_add_epi32(s[0], _mm256_madd_epi16(v, _mm256_set1_epi32(1)));
    s[1] = _mm256_add_epi32(s[1], _mm256_srai_epi32(v, 16));
    s[2] = _mm256_add_epi32(s[2], _mm256_madd_epi16(vx, vx));
    s[3] = _mm256_add_epi32(s[3], _mm256_madd_epi16(vx, vy));
    s[4] = _mm256_add_epi32(s[4], _mm256_madd_epi16(vy, vy));
}
#endif

/* Adjacent sides must differ by at least asin(0.2) (11.5 degrees). */
#define QUAD_MIN_ADJ_SIN 0.2f
/* Unrefined quads below min_inlier_ratio minus this are not refined. */
#define QUAD_PROMISE 0.1f
/* At most this many refinement passes ... */
#define QUAD_REFINE_PASSES 8
/* ... stopping once no corner moves by more than this (px). */
#define QUAD_CONVERGED 0.01f
/* Smallest band (px) around a side within which points refit it. */
#define QUAD_MIN_BAND 1.5f
/* Each side's nearest inliers must spread over this fraction of its length. */
#define QUAD_MIN_SPAN 0.5f

/* Exact moment sums of integer points (relative to the contour origin). */
typedef struct qsums {
    int64_t n, sx, sy, sxx, sxy, syy;
} qsums;

/* The line nx*x + ny*y = c, (nx, ny) a unit normal. */
typedef struct qline {
    float nx, ny, c;
} qline;

/* A quad: line[j] and line[j+1] meet at corner j, so side j, from corner j
 * to corner j+1, lies on line[j+1]. */
typedef struct qquad {
    qline line[4];
    float x[4], y[4];
} qquad;

/* Everything that stays fixed during one call. Coordinates are relative to
 * the contour's bounding-box minimum (ox, oy): small, so float keeps them
 * exact and results do not depend on where the contour is in the image. */
typedef struct qctx {
    const actag_ipoint *pts;
    const float *fx, *fy; /* relative coordinates as floats */
    int n;
    int ox, oy;      /* origin: bounding-box minimum */
    float bw, bh;    /* bounding-box extent (max - min) */
    int ext;         /* the larger extent, as an integer */
    float cx, cy;    /* centroid */
    float d, d2;     /* inlier distance and its square */
    float ratio;     /* inlier fraction that ends the search at once */
    float min_ratio; /* inlier fraction required of the best quad found */
    float pcos;      /* min |cos| between opposite sides */
    int chain;       /* consecutive points are at most 1 px apart in x and in y */
    int accept_min;  /* fewest inliers whose ratio passes min_ratio (n + 1: none) */
#ifdef QUAD_AVX2
    int avx2; /* 1: the AVX2 loops run (actag__cpu_avx2) */
#endif
} qctx;

void actag_quad_params_default(actag_quad_params *p)
{
    if (!p)
        return;
    p->max_iterations = 500;
    p->sample_fraction = 0.10f;
    p->inlier_ratio = 0.85f;
    p->inlier_distance = 2.5f;
    p->min_parallel_cos = 0.9f;
    p->min_inlier_ratio = 0.80f;
}

static void sums_add(qsums *s, int64_t x, int64_t y)
{
    s->n++;
    s->sx += x;
    s->sy += y;
    s->sxx += x * x;
    s->sxy += x * y;
    s->syy += y * y;
}

static float ratio_of(int count, int n) { return (float)count / (float)n; }

/* The fewest of n points c with ratio_of(c, n) >= lo and > above (n + 1 if
 * none): ratio_of grows with c (a correctly rounded quotient of a growing
 * numerator), so count >= count_min(...) decides exactly what the ratio
 * tests do. */
static int count_min(int n, float lo, float above)
{
    int a = 0, b = n + 1; /* the answer is in [a, b] */
    while (a < b) {
        int c = a + (b - a) / 2;
        float r = ratio_of(c, n);
        if (r >= lo && r > above)
            b = c;
        else
            a = c + 1;
    }
    return a;
}

/* Total-least-squares line through the summed points. *msr (if not NULL)
 * receives the mean squared perpendicular residual. Returns 0 when the
 * points have no direction (fewer than 2, all equal, or isotropic). The
 * centred moments are exact 64-bit integers: coordinates are < 2^16 and
 * n < 2^15, so n*sxx and sx*sx stay below 2^62. */
static int line_fit(const qsums *s, qline *l, float *msr)
{
    int64_t a64, b64, c64;
    float fn, inv, a, b, c, hd, r, dx, dy, len2, il;
    if (s->n < 2)
        return 0;
    a64 = s->n * s->sxx - s->sx * s->sx;
    b64 = s->n * s->sxy - s->sx * s->sy;
    c64 = s->n * s->syy - s->sy * s->sy;
    fn = actag_i64_to_f(s->n);
    inv = 1.0f / (fn * fn);
    a = actag_i64_to_f(a64) * inv; /* covariance matrix [a b; b c], pixels^2 */
    b = actag_i64_to_f(b64) * inv;
    c = actag_i64_to_f(c64) * inv;
    hd = 0.5f * (a - c);
    r = actag_sqrtf(hd * hd + b * b);
    /* Eigenvector of the larger eigenvalue, written so nothing cancels. */
    if (hd >= 0.0f) {
        dx = hd + r;
        dy = b;
    } else {
        dx = b;
        dy = r - hd;
    }
    len2 = dx * dx + dy * dy;
    if (!(len2 > 0.0f))
        return 0;
    il = 1.0f / actag_sqrtf(len2);
    l->nx = -dy * il;
    l->ny = dx * il;
    l->c = l->nx * (actag_i64_to_f(s->sx) / fn) + l->ny * (actag_i64_to_f(s->sy) / fn);
    if (msr) {
        float m = 0.5f * (a + c) - r;
        *msr = m > 0.0f ? m : 0.0f;
    }
    return 1;
}

/* Monotone stand-in for the angle of (dx, dy), in [0, 4): it increases
 * clockwise on screen (y down). Only a division, so exact on every platform. */
static float pseudo_angle(float dx, float dy)
{
    float s = fabsf(dx) + fabsf(dy), p;
    if (s == 0.0f)
        return 0.0f;
    p = dy / s;
    if (dx < 0.0f)
        return 2.0f - p;
    if (dy < 0.0f)
        return 4.0f + p;
    return p;
}

/* Intersects consecutive lines into corners; 0 if two adjacent lines are
 * too close to parallel. */
static int quad_from_lines(qquad *q)
{
    int j;
    for (j = 0; j < 4; j++) {
        const qline *a = &q->line[j], *b = &q->line[(j + 1) & 3];
        float det = a->nx * b->ny - a->ny * b->nx;
        if (!(fabsf(det) >= QUAD_MIN_ADJ_SIN))
            return 0;
        q->x[j] = (a->c * b->ny - b->c * a->ny) / det;
        q->y[j] = (a->nx * b->c - b->nx * a->c) / det;
    }
    return 1;
}

/* Shape tests that need no contour points: convex and clockwise on screen,
 * sides at least d long, corners near the contour's bounding box, and (if
 * parallel) opposite sides parallel. */
static int quad_shape_ok(const qctx *k, const qquad *q, int parallel)
{
    float margin = k->d + 0.25f * (k->bw > k->bh ? k->bw : k->bh);
    int j;
    for (j = 0; j < 4; j++) {
        int j1 = (j + 1) & 3, j2 = (j + 2) & 3;
        float ex = q->x[j1] - q->x[j], ey = q->y[j1] - q->y[j];
        float fx = q->x[j2] - q->x[j1], fy = q->y[j2] - q->y[j1];
        if (!(ex * ex + ey * ey >= k->d2))
            return 0;
        if (!(ex * fy - ey * fx > 0.0f))
            return 0;
        if (!(q->x[j] >= -margin && q->x[j] <= k->bw + margin && q->y[j] >= -margin &&
              q->y[j] <= k->bh + margin))
            return 0;
    }
    for (j = 0; j < 2 && parallel; j++) {
        const qline *a = &q->line[j], *b = &q->line[j + 2];
        if (!(fabsf(a->nx * b->nx + a->ny * b->ny) >= k->pcos))
            return 0;
    }
    return 1;
}

#ifndef ACTAG_QUAD_REFERENCE
/* One side of quad_inliers' loop, the same operations; u*l = ux * len and
 * uy * len, hoisted. */
QUAD_INLINE void inlier_side(float px, float py, float ax, float ay, float ux, float uy, float len,
                             float uxl, float uyl, int j, float *best, int *bj, float *bt)
{
    float vx = px - ax, vy = py - ay;
    float t = vx * ux + vy * uy, e2;
    if (t < 0.0f) {
        e2 = vx * vx + vy * vy;
    } else if (t > len) {
        float wx = vx - uxl, wy = vy - uyl;
        e2 = wx * wx + wy * wy;
    } else {
        float e = vx * uy - vy * ux;
        e2 = e * e;
    }
    if (e2 < *best || (*bj < 0 && e2 == *best)) {
        *best = e2;
        *bj = j;
        *bt = t < 0.0f ? 0.0f : (t > len ? len : t);
    }
}

#ifdef QUAD_SSE2
/* a where m is all ones, else b */
QUAD_INLINE __m128 quad_sel(__m128 m, __m128 a, __m128 b)
{
    return _mm_or_ps(_mm_and_ps(m, a), _mm_andnot_ps(m, b));
}

/* inlier_side() in four lanes, branch-free: the same operations, the
 * branches' conditions as masks (false for NaN as in C); *none: the
 * lanes whose *bj is still -1. */
QUAD_INLINE void inlier_side4(__m128 px, __m128 py, float ax, float ay, float ux, float uy,
                              float len, float uxl, float uyl, int j, __m128 *best, __m128i *bj,
                              __m128 *bt, __m128 *none)
{
    const __m128 vux = _mm_set1_ps(ux), vuy = _mm_set1_ps(uy), vlen = _mm_set1_ps(len);
    const __m128 vx = _mm_sub_ps(px, _mm_set1_ps(ax)), vy = _mm_sub_ps(py, _mm_set1_ps(ay));
    const __m128 t = _mm_add_ps(_mm_mul_ps(vx, vux), _mm_mul_ps(vy, vuy));
    const __m128 lt = _mm_cmplt_ps(t, _mm_setzero_ps()), gt = _mm_cmpgt_ps(t, vlen);
    const __m128 wx = _mm_sub_ps(vx, _mm_set1_ps(uxl)), wy = _mm_sub_ps(vy, _mm_set1_ps(uyl));
    const __m128 e = _mm_sub_ps(_mm_mul_ps(vx, vuy), _mm_mul_ps(vy, vux));
    const __m128 e2a = _mm_add_ps(_mm_mul_ps(vx, vx), _mm_mul_ps(vy, vy));
    const __m128 e2b = _mm_add_ps(_mm_mul_ps(wx, wx), _mm_mul_ps(wy, wy));
    const __m128 e2 = quad_sel(lt, e2a, quad_sel(gt, e2b, _mm_mul_ps(e, e)));
    const __m128 upd =
        _mm_or_ps(_mm_cmplt_ps(e2, *best), _mm_and_ps(*none, _mm_cmpeq_ps(e2, *best)));
    *best = quad_sel(upd, e2, *best);
    *bt = quad_sel(upd, _mm_andnot_ps(lt, quad_sel(gt, vlen, t)), *bt); /* +0 where t < 0 */
    *bj = _mm_castps_si128(
        quad_sel(upd, _mm_castsi128_ps(_mm_set1_epi32(j)), _mm_castsi128_ps(*bj)));
    *none = _mm_andnot_ps(upd, *none);
}

/* quad_inliers' loop (with span) four points a step from index 0, each
 * lane keeping its own minimum and maximum bt per side, folded into tmin
 * and tmax at the end by the same rule: in another order, which can change
 * only the sign of a zero result, and so no tmax - tmin >= x test. Adds to
 * *count; returns the index reached, or -1 once the count can no longer
 * reach need (the scalar test, made every fourth point: exiting later, or
 * not at all, still returns a count below need, which the callers reject
 * whatever *span says). */
QUAD_INLINE int inliers_sse2(const qctx *k, const float *ax, const float *ay, const float *ux,
                             const float *uy, const float *len, float *tmin, float *tmax,
                             int need, int *count)
{
    const float *fx = k->fx, *fy = k->fy;
    const int n = k->n;
    const __m128 d2 = _mm_set1_ps(k->d2), ones = _mm_castsi128_ps(_mm_set1_epi32(-1));
    __m128 lo[4], hi[4];
    int i, j, cnt = *count;
    for (j = 0; j < 4; j++) {
        lo[j] = _mm_set1_ps(len[j]);
        hi[j] = _mm_setzero_ps();
    }
    for (i = 0; i + 4 <= n; i += 4) {
        const __m128 px = _mm_loadu_ps(fx + i), py = _mm_loadu_ps(fy + i);
        __m128 best = d2, bt = _mm_setzero_ps(), none = ones;
        __m128i bj = _mm_set1_epi32(-1);
        if (cnt + (n - i) < need) {
            *count = cnt;
            return -1;
        }
        for (j = 0; j < 4; j++)
            inlier_side4(px, py, ax[j], ay[j], ux[j], uy[j], len[j], ux[j] * len[j],
                         uy[j] * len[j], j, &best, &bj, &bt, &none);
        cnt += 4 - quad_pop4(_mm_movemask_ps(none));
        for (j = 0; j < 4; j++) {
            const __m128 on = _mm_castsi128_ps(_mm_cmpeq_epi32(bj, _mm_set1_epi32(j)));
            lo[j] = quad_sel(on, _mm_min_ps(bt, lo[j]), lo[j]); /* bt < lo ? bt : lo */
            hi[j] = quad_sel(on, _mm_max_ps(bt, hi[j]), hi[j]); /* bt > hi ? bt : hi */
        }
    }
    for (j = 0; j < 4; j++) {
        float a[4], b[4];
        int q;
        _mm_storeu_ps(a, lo[j]);
        _mm_storeu_ps(b, hi[j]);
        for (q = 0; q < 4; q++) {
            tmin[j] = a[q] < tmin[j] ? a[q] : tmin[j];
            tmax[j] = b[q] > tmax[j] ? b[q] : tmax[j];
        }
    }
    *count = cnt;
    return i;
}
#endif

#ifdef QUAD_AVX2
ACTAG__AVX2_TARGET static inline __m256 quad_sel8(__m256 m, __m256 a, __m256 b)
{
    return _mm256_or_ps(_mm256_and_ps(m, a), _mm256_andnot_ps(m, b));
}

/* inlier_side4 in eight lanes (ordered compares: false for NaN). */
ACTAG__AVX2_TARGET static inline void inlier_side8(__m256 px, __m256 py, float ax, float ay,
                                                   float ux, float uy, float len, float uxl,
                                                   float uyl, int j, __m256 *best, __m256i *bj,
                                                   __m256 *bt, __m256 *none)
{
    const __m256 vux = _mm256_set1_ps(ux), vuy = _mm256_set1_ps(uy), vlen = _mm256_set1_ps(len);
    const __m256 vx = _mm256_sub_ps(px, _mm256_set1_ps(ax));
    const __m256 vy = _mm256_sub_ps(py, _mm256_set1_ps(ay));
    const __m256 t = _mm256_add_ps(_mm256_mul_ps(vx, vux), _mm256_mul_ps(vy, vuy));
    const __m256 lt = _mm256_cmp_ps(t, _mm256_setzero_ps(), _CMP_LT_OQ);
    const __m256 gt = _mm256_cmp_ps(t, vlen, _CMP_GT_OQ);
    const __m256 wx = _mm256_sub_ps(vx, _mm256_set1_ps(uxl));
    const __m256 wy = _mm256_sub_ps(vy, _mm256_set1_ps(uyl));
    const __m256 e = _mm256_sub_ps(_mm256_mul_ps(vx, vuy), _mm256_mul_ps(vy, vux));
    const __m256 e2a = _mm256_add_ps(_mm256_mul_ps(vx, vx), _mm256_mul_ps(vy, vy));
    const __m256 e2b = _mm256_add_ps(_mm256_mul_ps(wx, wx), _mm256_mul_ps(wy, wy));
    const __m256 e2 = quad_sel8(lt, e2a, quad_sel8(gt, e2b, _mm256_mul_ps(e, e)));
    const __m256 upd = _mm256_or_ps(_mm256_cmp_ps(e2, *best, _CMP_LT_OQ),
                                    _mm256_and_ps(*none, _mm256_cmp_ps(e2, *best, _CMP_EQ_OQ)));
    *best = quad_sel8(upd, e2, *best);
    *bt = quad_sel8(upd, _mm256_andnot_ps(lt, quad_sel8(gt, vlen, t)), *bt);
    *bj = _mm256_castps_si256(
        quad_sel8(upd, _mm256_castsi256_ps(_mm256_set1_epi32(j)), _mm256_castsi256_ps(*bj)));
    *none = _mm256_andnot_ps(upd, *none);
}

/* inliers_sse2 eight points a step: the same results. */
ACTAG__AVX2_TARGET static int inliers_avx2(const qctx *k, const float *ax, const float *ay,
                                           const float *ux, const float *uy, const float *len,
                                           float *tmin, float *tmax, int need, int *count)
{
    const float *fx = k->fx, *fy = k->fy;
    const int n = k->n;
    const __m256 d2 = _mm256_set1_ps(k->d2), ones = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
    __m256 lo[4], hi[4];
    int i, j, cnt = *count;
    for (j = 0; j < 4; j++) {
        lo[j] = _mm256_set1_ps(len[j]);
        hi[j] = _mm256_setzero_ps();
    }
    for (i = 0; i + 8 <= n; i += 8) {
        const __m256 px = _mm256_loadu_ps(fx + i), py = _mm256_loadu_ps(fy + i);
        __m256 best = d2, bt = _mm256_setzero_ps(), none = ones;
        __m256i bj = _mm256_set1_epi32(-1);
        int nm;
        if (cnt + (n - i) < need) {
            *count = cnt;
            return -1;
        }
        for (j = 0; j < 4; j++)
            inlier_side8(px, py, ax[j], ay[j], ux[j], uy[j], len[j], ux[j] * len[j],
                         uy[j] * len[j], j, &best, &bj, &bt, &none);
        nm = _mm256_movemask_ps(none);
        cnt += 8 - quad_pop4(nm & 15) - quad_pop4(nm >> 4);
        for (j = 0; j < 4; j++) {
            const __m256 on = _mm256_castsi256_ps(_mm256_cmpeq_epi32(bj, _mm256_set1_epi32(j)));
            lo[j] = quad_sel8(on, _mm256_min_ps(bt, lo[j]), lo[j]);
            hi[j] = quad_sel8(on, _mm256_max_ps(bt, hi[j]), hi[j]);
        }
    }
    for (j = 0; j < 4; j++) {
        float a[8], b[8];
        int q;
        _mm256_storeu_ps(a, lo[j]);
        _mm256_storeu_ps(b, hi[j]);
        for (q = 0; q < 8; q++) {
            tmin[j] = a[q] < tmin[j] ? a[q] : tmin[j];
            tmax[j] = b[q] > tmax[j] ? b[q] : tmax[j];
        }
    }
    *count = cnt;
    return i;
}
#endif
#endif

/* Counts the points within d of the quad's sides (segments). With span
 * non-NULL, also assigns each inlier to its nearest side and returns 1 in
 * *span only if on every side those inliers spread over at least
 * QUAD_MIN_SPAN of its length. Once the count can no longer reach need
 * (the caller rejects any smaller count), returns a count below need
 * (and *span 0) without looking at the rest (not under
 * ACTAG_QUAD_REFERENCE). */
static int quad_inliers(const qctx *k, const qquad *q, int *span, int need)
{
    float ax[4], ay[4], ux[4], uy[4], len[4], tmin[4], tmax[4];
    int j, i, count = 0;
    for (j = 0; j < 4; j++) {
        int j1 = (j + 1) & 3;
        float ex = q->x[j1] - q->x[j], ey = q->y[j1] - q->y[j];
        float l = actag_sqrtf(ex * ex + ey * ey);
        ax[j] = q->x[j];
        ay[j] = q->y[j];
        ux[j] = l > 0.0f ? ex / l : 0.0f;
        uy[j] = l > 0.0f ? ey / l : 0.0f;
        len[j] = l;
        tmin[j] = l;
        tmax[j] = 0.0f;
    }
#ifdef ACTAG_QUAD_REFERENCE
    (void)need;
#else
    if (span) {
        /* The sides unrolled, their figures in registers (GCC kept them on
         * the stack: 150 Cortex-M7 instructions a point); as below. */
        const float ax0 = ax[0], ay0 = ay[0], ux0 = ux[0], uy0 = uy[0], l0 = len[0];
        const float ax1 = ax[1], ay1 = ay[1], ux1 = ux[1], uy1 = uy[1], l1 = len[1];
        const float ax2 = ax[2], ay2 = ay[2], ux2 = ux[2], uy2 = uy[2], l2 = len[2];
        const float ax3 = ax[3], ay3 = ay[3], ux3 = ux[3], uy3 = uy[3], l3 = len[3];
        const float uxl0 = ux0 * l0, uyl0 = uy0 * l0, uxl1 = ux1 * l1, uyl1 = uy1 * l1;
        const float uxl2 = ux2 * l2, uyl2 = uy2 * l2, uxl3 = ux3 * l3, uyl3 = uy3 * l3;
        const float *fx = k->fx, *fy = k->fy, d2 = k->d2;
        const int n = k->n;
        i = 0;
#ifdef QUAD_AVX2
        if (k->avx2)
            i = inliers_avx2(k, ax, ay, ux, uy, len, tmin, tmax, need, &count);
        else
#endif
#ifdef QUAD_SSE2
            i = inliers_sse2(k, ax, ay, ux, uy, len, tmin, tmax, need, &count);
        if (i < 0) {
            *span = 0;
            return count;
        }
#endif
        for (; i < n; i++) {
            float px = fx[i], py = fy[i], best = d2, bt = 0.0f;
            int bj = -1;
            if (count + (n - i) < need) {
                *span = 0;
                return count;
            }
            inlier_side(px, py, ax0, ay0, ux0, uy0, l0, uxl0, uyl0, 0, &best, &bj, &bt);
            inlier_side(px, py, ax1, ay1, ux1, uy1, l1, uxl1, uyl1, 1, &best, &bj, &bt);
            inlier_side(px, py, ax2, ay2, ux2, uy2, l2, uxl2, uyl2, 2, &best, &bj, &bt);
            inlier_side(px, py, ax3, ay3, ux3, uy3, l3, uxl3, uyl3, 3, &best, &bj, &bt);
            if (bj < 0)
                continue;
            count++;
            tmin[bj] = bt < tmin[bj] ? bt : tmin[bj];
            tmax[bj] = bt > tmax[bj] ? bt : tmax[bj];
        }
        *span = 1;
        for (j = 0; j < 4; j++)
            if (!(tmax[j] - tmin[j] >= QUAD_MIN_SPAN * len[j]))
                *span = 0;
        return count;
    }
#endif
    for (i = 0; i < k->n; i++) {
        float px = k->fx[i], py = k->fy[i], best = k->d2, bt = 0.0f;
        int bj = -1;
#ifndef ACTAG_QUAD_REFERENCE
        if (count + (k->n - i) < need) {
            if (span)
                *span = 0;
            return count;
        }
#endif
        for (j = 0; j < 4; j++) {
            float vx = px - ax[j], vy = py - ay[j];
            float t = vx * ux[j] + vy * uy[j], e2;
            if (t < 0.0f) {
                e2 = vx * vx + vy * vy;
            } else if (t > len[j]) {
                float wx = vx - ux[j] * len[j], wy = vy - uy[j] * len[j];
                e2 = wx * wx + wy * wy;
            } else {
                float e = vx * uy[j] - vy * ux[j];
                e2 = e * e;
            }
            if (e2 < best || (bj < 0 && e2 == best)) {
                best = e2;
                bj = j;
                bt = t < 0.0f ? 0.0f : (t > len[j] ? len[j] : t);
                if (!span)
                    break; /* counting only: one side is enough */
            }
        }
        if (bj < 0)
            continue;
        count++;
        if (span) {
            tmin[bj] = bt < tmin[bj] ? bt : tmin[bj];
            tmax[bj] = bt > tmax[bj] ? bt : tmax[bj];
        }
    }
    if (span) {
        *span = 1;
        for (j = 0; j < 4; j++)
            if (!(tmax[j] - tmin[j] >= QUAD_MIN_SPAN * len[j]))
                *span = 0;
    }
    return count;
}

/* Inlier ratio of the quad, or -1 unless every side is supported by its
 * nearest inliers over at least QUAD_MIN_SPAN of its length (a line fitted
 * to stray points can otherwise close a quad whose inlier count passes while
 * most of a short side is missed). */
static float quad_support(const qctx *k, const qquad *q, int need)
{
    int span;
    float r = ratio_of(quad_inliers(k, q, &span, need), k->n);
    return span ? r : -1.0f;
}

/* Final acceptance: shape with parallel sides, support, inlier ratio. */
static int quad_accept(const qctx *k, const qquad *q, float *ratio)
{
    float r;
    if (!quad_shape_ok(k, q, 1))
        return 0;
    r = quad_support(k, q, k->accept_min);
    if (!(r >= k->min_ratio))
        return 0;
    *ratio = r;
    return 1;
}

#ifndef ACTAG_QUAD_REFERENCE
/* Moment sums of points in 32 bits (exact where the caller has bounded
 * them, or taken modulo 2^32 and corrected), and a point added to them. */
typedef struct qsums32 {
    uint32_t n, sx, sy, sxx, sxy, syy;
} qsums32;

QUAD_INLINE void sums32_add(qsums32 *t, uint32_t x, uint32_t y)
{
    t->n++;
    t->sx += x;
    t->sy += y;
    t->sxx += x * x;
    t->sxy += x * y;
    t->syy += y * y;
}

/* Adds to r (sums of relative coordinates as in walk_far)
 * the points of [a, b) that side_sums keeps for the side from (qx, qy)
 * along (ux, uy), on line l between la and lb: the same tests. */
QUAD_INLINE void side_run(const qctx *k, int a, int b, float qx, float qy, float ux, float uy,
                          float len, float band2, const qline *l, const qline *la,
                          const qline *lb, qsums32 *r)
{
    const float *fx = k->fx, *fy = k->fy;
    const float nx = l->nx, ny = l->ny, c = l->c, nax = la->nx, nay = la->ny, ca = la->c;
    const float nbx = lb->nx, nby = lb->ny, cb = lb->c;
    qsums32 t = *r; /* a local copy: its fields stay in registers */
    int i;
    for (i = a; i < b; i++) {
        float px = fx[i], py = fy[i];
        float u = (px - qx) * ux + (py - qy) * uy, e;
        if (!(u >= 0.0f && u <= len))
            continue;
        e = fabsf(nx * px + ny * py - c);
        if (!(e * e <= band2 && e <= fabsf(nax * px + nay * py - ca) &&
              e <= fabsf(nbx * px + nby * py - cb)))
            continue;
        sums32_add(&t, (uint32_t)px, (uint32_t)py);
    }
    *r = t;
}
#endif

/* Moments of each side's stretch of the contour, for refitting its line
 * (sums[i] belongs to line i). Each corner is tied to its nearest contour
 * point; side j is the run of contour points from corner j's point up to
 * (not including) corner j+1's, in the contour's own direction, keeping
 * those that project inside the side, lie within sqrt(band2[j]) of its
 * current line, and are no closer to either adjacent side's line (near a
 * corner such points belong to the other side). Using the contour order
 * rather than distances keeps a short side's points on that side even when a
 * poor first guess tilts it. Returns 0 if the corners' contour points are not
 * distinct and in cyclic order. */
static int side_sums(const qctx *k, const qquad *q, const float *band2, qsums *sums)
{
    int ci[4], j, i, fwd = 1, bwd = 1, tf = 0, tb = 0;
    float bd[4];
#ifndef ACTAG_QUAD_REFERENCE
    /* a side's sums over at most n points of relative coordinates <= ext
     * fit 32 bits: summed so (the same integers) */
    const uint64_t ext = (uint64_t)(k->ext > 0 ? k->ext : 0);
    const int small = (uint64_t)k->n * ext * ext <= UINT32_MAX;
#endif
    for (j = 0; j < 4; j++) {
        bd[j] = 3.0e38f;
        ci[j] = 0;
    }
#ifdef ACTAG_QUAD_REFERENCE
    for (i = 0; i < k->n; i++) {
        for (j = 0; j < 4; j++) {
            float dx = k->fx[i] - q->x[j], dy = k->fy[i] - q->y[j], e2 = dx * dx + dy * dy;
            if (e2 < bd[j]) {
                bd[j] = e2;
                ci[j] = i;
            }
        }
    }
#else
    {
        /* The corners unrolled, in registers; the same operations. */
        const float *fx = k->fx, *fy = k->fy;
        const float x0 = q->x[0], y0 = q->y[0], x1 = q->x[1], y1 = q->y[1];
        const float x2 = q->x[2], y2 = q->y[2], x3 = q->x[3], y3 = q->y[3];
        float b0 = bd[0], b1 = bd[1], b2 = bd[2], b3 = bd[3];
        int c0 = 0, c1 = 0, c2 = 0, c3 = 0;
        for (i = 0; i < k->n; i++) {
            float px = fx[i], py = fy[i], dx, dy, e2;
            dx = px - x0, dy = py - y0, e2 = dx * dx + dy * dy;
            if (e2 < b0)
                b0 = e2, c0 = i;
            dx = px - x1, dy = py - y1, e2 = dx * dx + dy * dy;
            if (e2 < b1)
                b1 = e2, c1 = i;
            dx = px - x2, dy = py - y2, e2 = dx * dx + dy * dy;
            if (e2 < b2)
                b2 = e2, c2 = i;
            dx = px - x3, dy = py - y3, e2 = dx * dx + dy * dy;
            if (e2 < b3)
                b3 = e2, c3 = i;
        }
        ci[0] = c0;
        ci[1] = c1;
        ci[2] = c2;
        ci[3] = c3;
    }
#endif
    for (j = 0; j < 4; j++) {
        int a = ci[j], b = ci[(j + 1) & 3];
        int f = b >= a ? b - a : b - a + k->n, g = a >= b ? a - b : a - b + k->n;
        fwd &= f > 0;
        bwd &= g > 0;
        tf += f;
        tb += g;
    }
    fwd &= tf == k->n;
    bwd &= tb == k->n;
    if (!fwd && !bwd)
        return 0;
    for (j = 0; j < 4; j++) {
        int a = ci[j], b = ci[(j + 1) & 3], cnt, left;
        const qline *l = &q->line[(j + 1) & 3], *la = &q->line[j], *lb = &q->line[(j + 2) & 3];
        float ex = q->x[(j + 1) & 3] - q->x[j], ey = q->y[(j + 1) & 3] - q->y[j];
        float len = actag_sqrtf(ex * ex + ey * ey), ux, uy;
        qsums *s = &sums[(j + 1) & 3];
        if (!(len > 0.0f))
            return 0;
        ux = ex / len;
        uy = ey / len;
        memset(s, 0, sizeof *s);
#ifndef ACTAG_QUAD_REFERENCE
        if (small) {
            /* The run as at most two ascending ranges: integer sums do not
             * depend on the order. */
            qsums32 r = {0u, 0u, 0u, 0u, 0u, 0u};
            int lo = fwd ? a : b + 1, hi = fwd ? b : a + 1; /* [lo, hi), cyclic */
            if (lo == k->n)
                lo = 0;
            if (lo < hi) {
                side_run(k, lo, hi, q->x[j], q->y[j], ux, uy, len, band2[j], l, la, lb, &r);
            } else {
                side_run(k, lo, k->n, q->x[j], q->y[j], ux, uy, len, band2[j], l, la, lb, &r);
                side_run(k, 0, hi, q->x[j], q->y[j], ux, uy, len, band2[j], l, la, lb, &r);
            }
            s->n = r.n;
            s->sx = r.sx;
            s->sy = r.sy;
            s->sxx = r.sxx;
            s->sxy = r.sxy;
            s->syy = r.syy;
            continue;
        }
#endif
        cnt = fwd ? (b >= a ? b - a : b - a + k->n) : (a >= b ? a - b : a - b + k->n);
        for (i = a, left = cnt; left > 0; left--) {
            float px = k->fx[i], py = k->fy[i];
            float t = (px - q->x[j]) * ux + (py - q->y[j]) * uy;
            float e = fabsf(l->nx * px + l->ny * py - l->c);
            float ea = fabsf(la->nx * px + la->ny * py - la->c);
            float eb = fabsf(lb->nx * px + lb->ny * py - lb->c);
            if (t >= 0.0f && t <= len && e * e <= band2[j] && e <= ea && e <= eb)
                sums_add(s, k->pts[i].x - k->ox, k->pts[i].y - k->oy);
            if (fwd)
                i = i + 1 == k->n ? 0 : i + 1;
            else
                i = i == 0 ? k->n - 1 : i - 1;
        }
    }
    return 1;
}

/* Refines a quad whose unrefined inlier ratio was promising: each side's
 * line is refitted (total least squares) to its stretch of the contour and
 * the lines are re-intersected, until the corners settle. The first pass
 * takes points within 2d of the guess, later ones within 2.5 sigma of the
 * side's last fit (at least QUAD_MIN_BAND, at most d px) so outliers just
 * inside d stop tilting it. Writes the accepted quad (refined, else the
 * unrefined one) and its inlier ratio, or returns 0. */
static int refine_and_accept(const qctx *k, const qquad *q0, qquad *out, float *out_ratio)
{
    qquad cur = *q0;
    float band2[4];
    int pass, j, refined = 0;
    for (j = 0; j < 4; j++)
        band2[j] = 4.0f * k->d2;
    for (pass = 0; pass < QUAD_REFINE_PASSES; pass++) {
        qsums sums[4];
        qquad nq = cur;
        float moved = 0.0f;
        if (!side_sums(k, &cur, band2, sums))
            break;
        for (j = 0; j < 4; j++) {
            qline l;
            float msr;
            if (sums[(j + 1) & 3].n >= 3 && line_fit(&sums[(j + 1) & 3], &l, &msr)) {
                float b2 = 6.25f * msr, lo = QUAD_MIN_BAND * QUAD_MIN_BAND;
                b2 = b2 < lo ? lo : b2;
                band2[j] = b2 < k->d2 ? b2 : k->d2;
                nq.line[(j + 1) & 3] = l;
            } else {
                band2[j] = k->d2;
            }
        }
        if (!quad_from_lines(&nq))
            break;
        for (j = 0; j < 4; j++) {
            float dx = nq.x[j] - cur.x[j], dy = nq.y[j] - cur.y[j];
            moved = dx * dx + dy * dy > moved ? dx * dx + dy * dy : moved;
        }
        cur = nq;
        refined = 1;
        if (moved < QUAD_CONVERGED * QUAD_CONVERGED)
            break;
    }
    if (refined && quad_accept(k, &cur, out_ratio)) {
        *out = cur;
        return 1;
    }
    if (quad_accept(k, q0, out_ratio)) {
        *out = *q0;
        return 1;
    }
    return 0;
}

#ifdef QUAD_SKIP
/* claim() on a chain (consecutive points at most 1 px apart in x and in y):
 * the loop skips the points that cannot be within d. The exact distance to
 * the line changes by at most s = |nx| + |ny| per step, and a computed
 * distance is within E of the exact one, E < 2^-24 (3 (bw + bh) + |c|) *
 * 1.01 (three roundings, |fx| <= bw, |fy| <= bh). So when the computed
 * |dist| of point i exceeds d + 2E + j s, the computed distances of points
 * i+1 .. i+j exceed d too. lim - d is far above 2E, and s is taken 1e-4
 * larger, which also covers the roundings of the step count. That count
 * lies between -lim (|dist| >= 0, inv < 1) and 2^19 (|dist| <= bw + bh +
 * |c|, the coordinates below 2^16 and |c| below 2^17): an int without a
 * range test; the loop ends once i passes n. need > 0 only where it is
 * checked. */
QUAD_INLINE int claim_chain(const qctx *k, unsigned char *restrict lab, const qline *l,
                            unsigned char tag, int need)
{
    const float *restrict fx = k->fx, *restrict fy = k->fy;
    const float lnx = l->nx, lny = l->ny, lc = l->c, d = k->d;
    const float lim = d + (1e-5f * (k->bw + k->bh + fabsf(lc)) + 1e-4f);
    const float inv = 1.0f / ((fabsf(lnx) + fabsf(lny)) * 1.0001f);
    const int n = k->n, stop = n - need;
    int i = 0, cnt = 0;
    while (i < n) {
        float a = fabsf(lnx * fx[i] + lny * fy[i] - lc);
        if (a <= d) {
            if (!lab[i]) {
                lab[i] = tag;
                cnt++;
            }
            i++;
        } else {
            int j = (int)((a - lim) * inv); /* points i+1 .. i+j are out */
            i += j > 0 ? j + 1 : 1;
            if (need > 0 && i - cnt > stop) /* cnt + (n - i) < need; checked here only: cheaper */
                return cnt;
        }
    }
    return cnt;
}
#endif

#ifdef QUAD_SSE2
/* Labels with tag the sixteen points at lab whose byte of m is all ones
 * and whose label is 0; returns acc plus their number (two 64-bit counts). */
QUAD_INLINE __m128i claim16(unsigned char *lab, __m128i m, __m128i vtag, __m128i acc)
{
    const __m128i lb = _mm_loadu_si128((const __m128i *)(const void *)lab);
    m = _mm_and_si128(m, _mm_cmpeq_epi8(lb, _mm_setzero_si128()));
    _mm_storeu_si128((__m128i *)(void *)lab, _mm_or_si128(lb, _mm_and_si128(m, vtag)));
    m = _mm_and_si128(m, _mm_set1_epi8(1));
    return _mm_add_epi64(acc, _mm_sad_epu8(m, _mm_setzero_si128()));
}

/* claim_sse2's steps of four points from i to the last four; adds their
 * count to *cnt, returns the index reached. */
QUAD_INLINE int claim4(const qctx *k, unsigned char *restrict lab, const qline *l,
                       unsigned char tag, int i, int *cnt)
{
    const __m128 nx = _mm_set1_ps(l->nx), ny = _mm_set1_ps(l->ny), c = _mm_set1_ps(l->c);
    const __m128 d = _mm_set1_ps(k->d);
    const __m128i zero = _mm_setzero_si128(), vtag = _mm_set1_epi8((char)tag);
    int c4 = 0;
    for (; i + 4 <= k->n; i += 4) {
        const __m128i m4 =
            _mm_castps_si128(_mm_cmple_ps(quad_adist4(k->fx + i, k->fy + i, nx, ny, c), d));
        uint32_t w;
        __m128i m, b;
        memcpy(&w, lab + i, sizeof w);
        b = _mm_cvtsi32_si128((int)w);
        m = _mm_packs_epi16(_mm_packs_epi32(m4, m4), zero); /* bytes 0-3 */
        m = _mm_and_si128(m, _mm_cmpeq_epi8(b, zero));
        w = (uint32_t)_mm_cvtsi128_si32(_mm_or_si128(b, _mm_and_si128(m, vtag)));
        memcpy(lab + i, &w, sizeof w);
        c4 += quad_pop4(_mm_movemask_epi8(m) & 15);
    }
    *cnt += c4;
    return i;
}

/* The two 64-bit counts of claim16's acc, added. */
QUAD_INLINE int claim_count(__m128i acc)
{
    return _mm_cvtsi128_si32(acc) + _mm_cvtsi128_si32(_mm_srli_si128(acc, 8));
}

/* claim()'s plain loop from index 0, sixteen points a step, then four;
 * returns the index reached, the count in *cnt. |dist| <= d is the plain
 * loop's dist <= d && dist >= -d (false for NaN). With need > 0, returns n
 * and a count below need once the count cannot reach need (checked each
 * sixteen points). */
QUAD_INLINE int claim_sse2(const qctx *k, unsigned char *restrict lab, const qline *l,
                           unsigned char tag, int need, int *cnt)
{
    const float *fx = k->fx, *fy = k->fy;
    const __m128 nx = _mm_set1_ps(l->nx), ny = _mm_set1_ps(l->ny), c = _mm_set1_ps(l->c);
    const __m128 d = _mm_set1_ps(k->d);
    const __m128i vtag = _mm_set1_epi8((char)tag);
    const int n = k->n;
    __m128i acc = _mm_setzero_si128();
    int i;
    for (i = 0; i + 16 <= n; i += 16) {
        const __m128i m0 =
            _mm_castps_si128(_mm_cmple_ps(quad_adist4(fx + i, fy + i, nx, ny, c), d));
        const __m128i m1 =
            _mm_castps_si128(_mm_cmple_ps(quad_adist4(fx + i + 4, fy + i + 4, nx, ny, c), d));
        const __m128i m2 =
            _mm_castps_si128(_mm_cmple_ps(quad_adist4(fx + i + 8, fy + i + 8, nx, ny, c), d));
        const __m128i m3 =
            _mm_castps_si128(_mm_cmple_ps(quad_adist4(fx + i + 12, fy + i + 12, nx, ny, c), d));
        acc = claim16(lab + i, _mm_packs_epi16(_mm_packs_epi32(m0, m1), _mm_packs_epi32(m2, m3)),
                      vtag, acc);
        if (need > 0 && claim_count(acc) + (n - i - 16) < need) {
            *cnt = claim_count(acc);
            return n;
        }
    }
    *cnt = claim_count(acc);
    return claim4(k, lab, l, tag, i, cnt);
}

#ifdef QUAD_AVX2
/* claim_sse2 with the sixteen-point steps in two 8-lane halves: the same
 * operations, results and early exit. */
ACTAG__AVX2_TARGET static int claim_avx2(const qctx *k, unsigned char *restrict lab,
                                         const qline *l, unsigned char tag, int need, int *cnt)
{
    const float *fx = k->fx, *fy = k->fy;
    const __m256 nx = _mm256_set1_ps(l->nx), ny = _mm256_set1_ps(l->ny);
    const __m256 c = _mm256_set1_ps(l->c), d = _mm256_set1_ps(k->d);
    const __m256 abs = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    const __m128i vtag = _mm_set1_epi8((char)tag);
    const int n = k->n;
    __m128i acc = _mm_setzero_si128();
    int i;
    for (i = 0; i + 16 <= n; i += 16) {
        const __m256 t0 = _mm256_add_ps(_mm256_mul_ps(nx, _mm256_loadu_ps(fx + i)),
                                        _mm256_mul_ps(ny, _mm256_loadu_ps(fy + i)));
        const __m256 t1 = _mm256_add_ps(_mm256_mul_ps(nx, _mm256_loadu_ps(fx + i + 8)),
                                        _mm256_mul_ps(ny, _mm256_loadu_ps(fy + i + 8)));
        /* |dist| <= d, ordered: false for NaN */
        const __m256i m0 = _mm256_castps_si256(
            _mm256_cmp_ps(_mm256_and_ps(_mm256_sub_ps(t0, c), abs), d, _CMP_LE_OQ));
        const __m256i m1 = _mm256_castps_si256(
            _mm256_cmp_ps(_mm256_and_ps(_mm256_sub_ps(t1, c), abs), d, _CMP_LE_OQ));
        /* words per 128-bit lane: m0 0-3, m1 0-3 | m0 4-7, m1 4-7; put in order */
        const __m256i w = _mm256_permute4x64_epi64(_mm256_packs_epi32(m0, m1), 0xd8);
        acc = claim16(lab + i,
                      _mm_packs_epi16(_mm256_castsi256_si128(w), _mm256_extracti128_si256(w, 1)),
                      vtag, acc);
        if (need > 0 && claim_count(acc) + (n - i - 16) < need) {
            *cnt = claim_count(acc);
            return n;
        }
    }
    *cnt = claim_count(acc);
    return claim4(k, lab, l, tag, i, cnt);
}
#endif
#endif

/* Labels the unclaimed points within d of line l with tag; returns their
 * number. The points with |dist| <= d are exactly those of the plain loop
 * (the reference below, kept for ACTAG_QUAD_REFERENCE and contours that are
 * not chains); on a chain claim_chain() skips the points that cannot be
 * that close. With need > 0, returns a count below need as soon as the
 * count can no longer reach need (the caller then rejects; the labels are
 * incomplete). */
static int claim(const qctx *k, unsigned char *restrict lab, const qline *l, unsigned char tag,
                 int need)
{
    const float *restrict fx = k->fx, *restrict fy = k->fy;
    const float lnx = l->nx, lny = l->ny, lc = l->c, d = k->d;
    const int n = k->n;
    int i = 0, cnt = 0;
#ifdef QUAD_SKIP
    if (k->chain) /* the first three lines' copy without the need test */
        return need > 0 ? claim_chain(k, lab, l, tag, need) : claim_chain(k, lab, l, tag, 0);
#endif
#if defined(QUAD_AVX2)
    if (k->avx2)
        i = claim_avx2(k, lab, l, tag, need, &cnt);
    else
        i = need > 0 ? claim_sse2(k, lab, l, tag, need, &cnt) : claim_sse2(k, lab, l, tag, 0, &cnt);
#elif defined(QUAD_SSE2)
    i = need > 0 ? claim_sse2(k, lab, l, tag, need, &cnt) : claim_sse2(k, lab, l, tag, 0, &cnt);
#elif !defined(QUAD_SKIP)
    (void)need;
#endif
    /* Branch-free so that compilers vectorise it. */
    for (; i < n; i++) {
        float dist = lnx * fx[i] + lny * fy[i] - lc;
        int in = (lab[i] == 0) & (dist <= d) & (dist >= -d);
        lab[i] = (unsigned char)(lab[i] | (in ? tag : 0u));
        cnt += in;
    }
    return cnt;
}

/* Sums of the unclaimed points met walking from index start until m of them
 * are taken (cyclic); with line non-NULL, only those within d of it. At
 * least m points are unclaimed. The count and the first sums fit 32 bits
 * (at most 32767 points of coordinates below 65536 relative to the
 * origin); the walk runs up to the end of the array, then from 0. The
 * second moments are summed in SQ, uint32_t where m products of two
 * coordinates cannot reach 2^32 (every contour of a tag-sized blob: the
 * same exact sums, in one register each instead of two; Cortex-M7 spilled
 * the 64-bit ones), else int64_t. */
#define WALK_SUMS(SQ)                                                                          \
    do {                                                                                       \
        int32_t cnt = 0, sx = 0, sy = 0;                                                       \
        SQ sxx = 0, sxy = 0, syy = 0;                                                          \
        int i = start, left = m;                                                               \
        while (left > 0) {                                                                     \
            if (!line) {                                                                       \
                for (; i < n && left > 0; i++) {                                               \
                    int32_t x, y;                                                              \
                    if (lab[i])                                                                \
                        continue;                                                              \
                    left--;                                                                    \
                    x = pts[i].x - ox;                                                         \
                    y = pts[i].y - oy;                                                         \
                    cnt++;                                                                     \
                    sx += x;                                                                   \
                    sy += y;                                                                   \
                    sxx += (SQ)x * (SQ)x;                                                      \
                    sxy += (SQ)x * (SQ)y;                                                      \
                    syy += (SQ)y * (SQ)y;                                                      \
                }                                                                              \
            } else {                                                                           \
                const float lnx = line->nx, lny = line->ny, lc = line->c, d = k->d;            \
                for (; i < n && left > 0; i++) {                                               \
                    float dist;                                                                \
                    int32_t x, y;                                                              \
                    if (lab[i])                                                                \
                        continue;                                                              \
                    left--;                                                                    \
                    dist = lnx * k->fx[i] + lny * k->fy[i] - lc;                               \
                    if (!(dist <= d && dist >= -d))                                            \
                        continue;                                                              \
                    x = pts[i].x - ox;                                                         \
                    y = pts[i].y - oy;                                                         \
                    cnt++;                                                                     \
                    sx += x;                                                                   \
                    sy += y;                                                                   \
                    sxx += (SQ)x * (SQ)x;                                                      \
                    sxy += (SQ)x * (SQ)y;                                                      \
                    syy += (SQ)y * (SQ)y;                                                      \
                }                                                                              \
            }                                                                                  \
            if (i == n)                                                                        \
                i = 0;                                                                         \
        }                                                                                      \
        s->n = cnt;                                                                            \
        s->sx = sx;                                                                            \
        s->sy = sy;                                                                            \
        s->sxx = (int64_t)sxx;                                                                 \
        s->sxy = (int64_t)sxy;                                                                 \
        s->syy = (int64_t)syy;                                                                 \
    } while (0)

static void walk_sums(const qctx *k, const unsigned char *lab, int start, int m,
                      const qline *line, qsums *s)
{
    const actag_ipoint *pts = k->pts;
    const int ox = k->ox, oy = k->oy, n = k->n;
    /* coordinates lie in [0, ext]: each product is at most ext^2 */
    const uint64_t ext = (uint64_t)(k->ext > 0 ? k->ext : 0);
#ifndef ACTAG_QUAD_REFERENCE /* the reference keeps the 64-bit sums only */
    if ((uint64_t)m * ext * ext <= UINT32_MAX)
        WALK_SUMS(uint32_t);
    else
#else
    (void)ext;
#endif
        WALK_SUMS(int64_t);
}
#undef WALK_SUMS

#ifndef ACTAG_QUAD_REFERENCE
#ifdef QUAD_SSE2
/* walk_raw's loop four points a step while a step takes at most *left
 * points (the scalar loop takes the rest); returns the index reached: when
 * *left reaches 0, up to three claimed points past the last one taken. */
QUAD_INLINE int walk_raw_sse2(const actag_ipoint *pts, const unsigned char *lab, int i, int b,
                              int *left, uint32_t r[5])
{
    __m128i s[5];
    int rest = *left, j;
    for (j = 0; j < 5; j++)
        s[j] = _mm_setzero_si128();
    for (; i + 4 <= b; i += 4) {
        const __m128i f = quad_free4(lab + i);
        const int c = quad_pop4(_mm_movemask_ps(_mm_castsi128_ps(f)));
        if (c > rest)
            break;
        quad_sums4(pts + i, f, s);
        rest -= c;
        if (rest == 0) {
            i += 4;
            break;
        }
    }
    for (j = 0; j < 5; j++)
        r[j] += quad_hsum(s[j]);
    *left = rest;
    return i;
}
#endif

/* Raw coordinate sums, modulo 2^32, of the unclaimed points met in [a, b)
 * until *left of them are taken; returns the index after the last one
 * taken (b if fewer; under QUAD_SSE2 possibly a few claimed points
 * further). Raw: no origin to subtract a point (walk_all() corrects the
 * sums once). */
QUAD_INLINE int walk_raw(const actag_ipoint *pts, const unsigned char *lab, int a, int b, int *left,
                         uint32_t r[5])
{
    uint32_t sx, sy, sxx, sxy, syy;
    int i = a, rest = *left;
#ifdef QUAD_SSE2
    i = walk_raw_sse2(pts, lab, a, b, &rest, r);
    if (rest == 0) {
        *left = 0;
        return i;
    }
#endif
    sx = r[0];
    sy = r[1];
    sxx = r[2];
    sxy = r[3];
    syy = r[4];
    for (; i < b; i++) {
#if QUAD_DSP
        uint32_t v;
        if (lab[i])
            continue;
        memcpy(&v, &pts[i], sizeof v); /* x the low half, y the high one */
        {
            const int32_t xs = (int16_t)v, ys = (int32_t)v >> 16; /* SXTAH, ASR */
            sx += (uint32_t)xs;
            sy += (uint32_t)ys;
        }
        sxx = quad_smlabb(v, v, sxx);
        sxy = quad_smlabt(v, v, sxy);
        syy = quad_smlatt(v, v, syy);
#else
        int32_t x, y;
        if (lab[i])
            continue;
        x = pts[i].x;
        y = pts[i].y;
        sx += (uint32_t)x;
        sy += (uint32_t)y;
        sxx += (uint32_t)(x * x);
        sxy += (uint32_t)(x * y);
        syy += (uint32_t)(y * y);
#endif
        if (--rest == 0) {
            i++;
            break;
        }
    }
    r[0] = sx;
    r[1] = sy;
    r[2] = sxx;
    r[3] = sxy;
    r[4] = syy;
    *left = rest;
    return i;
}

/* walk_sums(k, lab, start, m, NULL, s), where m products of two relative
 * coordinates stay below 2^32 (walk_sums' uint32_t case; else it calls
 * walk_sums): raw sums taken modulo 2^32 and corrected for the origin
 * once, modulo 2^32, are the relative ones exactly (each lies in
 * [0, 2^32)). The walk covers [start, *e1) and [0, *e2), at most once
 * around the contour (at least m points are unclaimed). Returns 0 if it
 * called walk_sums. */
static int walk_all(const qctx *k, const unsigned char *lab, int start, int m, qsums *s, int *e1,
                    int *e2)
{
    const uint64_t ext = (uint64_t)(k->ext > 0 ? k->ext : 0);
    uint32_t r[5] = {0u, 0u, 0u, 0u, 0u}, c = (uint32_t)m, ox, oy, sx, sy;
    int left = m;
    if ((uint64_t)m * ext * ext > UINT32_MAX) {
        walk_sums(k, lab, start, m, NULL, s);
        return 0;
    }
    *e1 = walk_raw(k->pts, lab, start, k->n, &left, r);
    *e2 = left ? walk_raw(k->pts, lab, 0, start, &left, r) : 0;
    ox = (uint32_t)k->ox;
    oy = (uint32_t)k->oy;
    sx = r[0] - c * ox; /* sum (x - ox) */
    sy = r[1] - c * oy;
    s->n = m;
    s->sx = sx;
    s->sy = sy;
    s->sxx = r[2] - ox * (r[0] + sx); /* sum (x - ox)^2 = sum x^2 - ox (2 sum x - m ox) */
    s->sxy = r[3] - oy * r[0] - ox * sy;
    s->syy = r[4] - oy * (r[1] + sy);
    return 1;
}

/* Adds to r (sums as walk_all's) the relative coordinates,
 * read from fx and fy (exact integers), of the unclaimed points in [a, b)
 * farther than d from l (or at a NaN distance: as walk_sums'
 * !(dist <= d && dist >= -d)). */
QUAD_INLINE void walk_far(const qctx *k, const unsigned char *lab, int a, int b, const qline *l,
                          qsums32 *r)
{
    const float *fx = k->fx, *fy = k->fy;
    const float lnx = l->nx, lny = l->ny, lc = l->c, d = k->d;
    qsums32 t = *r; /* a local copy: its fields stay in registers */
    int i;
    for (i = a; i < b; i++) {
        if (lab[i])
            continue;
        if (!(fabsf(lnx * fx[i] + lny * fy[i] - lc) <= d))
            sums32_add(&t, (uint32_t)fx[i], (uint32_t)fy[i]);
    }
    *r = t;
}

#ifdef QUAD_SSE2
/* walk_far's test and sums of the four points from index i, those with
 * keep all ones: adds to acc the raw sums (quad_sums4) of the far
 * unclaimed ones (acc[5]: minus their count). */
QUAD_INLINE void walk_far4(const qctx *k, const unsigned char *lab, int i, __m128i keep,
                           __m128 nx, __m128 ny, __m128 c, __m128 d, __m128i acc[6])
{
    /* !(|dist| <= d): true for NaN, as the scalar test */
    const __m128 far = _mm_cmpnle_ps(quad_adist4(k->fx + i, k->fy + i, nx, ny, c), d);
    const __m128i f =
        _mm_and_si128(_mm_and_si128(_mm_castps_si128(far), quad_free4(lab + i)), keep);
    quad_sums4(k->pts + i, f, acc);
    acc[5] = _mm_add_epi32(acc[5], f);
}

/* walk_far's loop over [i, b), branch-free, four points a step; the last
 * step reads the four points ending at b (or starting at 0), those
 * outside [i, b) masked. Returns the index reached (b unless n < 4). */
QUAD_INLINE int walk_far_sse2(const qctx *k, const unsigned char *lab, int i, int b,
                              const qline *l, __m128i acc[6])
{
    const __m128 nx = _mm_set1_ps(l->nx), ny = _mm_set1_ps(l->ny), c = _mm_set1_ps(l->c);
    const __m128 d = _mm_set1_ps(k->d);
    const __m128i all = _mm_set1_epi32(-1);
    for (; i + 4 <= b; i += 4)
        walk_far4(k, lab, i, all, nx, ny, c, d, acc);
    if (i < b && k->n >= 4) {
        const int at = b >= 4 ? b - 4 : 0;
        const __m128i idx = _mm_add_epi32(_mm_set1_epi32(at), _mm_set_epi32(3, 2, 1, 0));
        const __m128i keep = _mm_and_si128(_mm_cmpgt_epi32(idx, _mm_set1_epi32(i - 1)),
                                           _mm_cmplt_epi32(idx, _mm_set1_epi32(b)));
        walk_far4(k, lab, at, keep, nx, ny, c, d, acc);
        i = b;
    }
    return i;
}

#ifdef QUAD_AVX2
/* walk_far_sse2 eight points a step (the last step masked likewise) into
 * eight-lane sums, then folded into acc's four lanes. */
ACTAG__AVX2_TARGET static int walk_far_avx2(const qctx *k, const unsigned char *lab, int i, int b,
                                            const qline *l, __m128i acc[6])
{
    const __m256 nx = _mm256_set1_ps(l->nx), ny = _mm256_set1_ps(l->ny);
    const __m256 c = _mm256_set1_ps(l->c), d = _mm256_set1_ps(k->d);
    __m256i s[6];
    int j;
    for (j = 0; j < 6; j++)
        s[j] = _mm256_setzero_si256();
    while (i < b) {
        int at = i;
        __m256i keep = _mm256_set1_epi32(-1), f;
        if (i + 8 > b) {
            if (k->n < 8)
                break;
            at = b >= 8 ? b - 8 : 0;
            {
                const __m256i idx = _mm256_add_epi32(_mm256_set1_epi32(at),
                                                     _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
                keep = _mm256_and_si256(_mm256_cmpgt_epi32(idx, _mm256_set1_epi32(i - 1)),
                                        _mm256_cmpgt_epi32(_mm256_set1_epi32(b), idx));
            }
        }
        /* !(|dist| <= d): true for NaN, as the scalar test */
        f = _mm256_castps_si256(
            _mm256_cmp_ps(quad_adist8(k->fx + at, k->fy + at, nx, ny, c), d, _CMP_NLE_UQ));
        f = _mm256_and_si256(_mm256_and_si256(f, quad_free8(lab + at)), keep);
        quad_sums8(k->pts + at, f, s);
        s[5] = _mm256_add_epi32(s[5], f);
        i = at + 8 < b ? at + 8 : b;
    }
    for (j = 0; j < 6; j++)
        acc[j] = _mm_add_epi32(acc[j], _mm_add_epi32(_mm256_castsi256_si128(s[j]),
                                                     _mm256_extracti128_si256(s[j], 1)));
    return i;
}
#endif

/* Adds walk_far_sse2's sums to r, made relative to the origin as in
 * walk_all(). */
QUAD_INLINE void walk_far_fold(const qctx *k, const __m128i acc[6], qsums32 *r)
{
    const uint32_t m = 0u - quad_hsum(acc[5]), ox = (uint32_t)k->ox, oy = (uint32_t)k->oy;
    const uint32_t x = quad_hsum(acc[0]), y = quad_hsum(acc[1]), sx = x - m * ox, sy = y - m * oy;
    r->n += m;
    r->sx += sx;
    r->sy += sy;
    r->sxx += quad_hsum(acc[2]) - ox * (x + sx);
    r->sxy += quad_hsum(acc[3]) - oy * x - ox * sy;
    r->syy += quad_hsum(acc[4]) - oy * (y + sy);
}
#endif

/* walk_sums(k, lab, start, m, l, s) after walk_all() gave s, e1 and e2:
 * the same points, so the sums within d are those of all minus those of
 * the (fewer) points farther, which alone it adds up (relative sums below
 * 2^32 as walk_all's). */
static void walk_near(const qctx *k, const unsigned char *lab, int start, int e1, int e2,
                      const qline *l, qsums *s)
{
    qsums32 r = {0u, 0u, 0u, 0u, 0u, 0u};
#ifdef QUAD_SSE2
    __m128i acc[6];
    int j, i1, i2;
    for (j = 0; j < 6; j++)
        acc[j] = _mm_setzero_si128();
#ifdef QUAD_AVX2
    if (k->avx2) {
        i1 = walk_far_avx2(k, lab, start, e1, l, acc);
        i2 = walk_far_avx2(k, lab, 0, e2, l, acc);
    } else
#endif
    {
        i1 = walk_far_sse2(k, lab, start, e1, l, acc);
        i2 = walk_far_sse2(k, lab, 0, e2, l, acc);
    }
    walk_far_fold(k, acc, &r);
    walk_far(k, lab, i1, e1, l, &r); /* nothing left unless n < 8 */
    walk_far(k, lab, i2, e2, l, &r);
#else
    walk_far(k, lab, start, e1, l, &r);
    walk_far(k, lab, 0, e2, l, &r);
#endif
    s->n -= r.n;
    s->sx -= r.sx;
    s->sy -= r.sy;
    s->sxx -= r.sxx;
    s->sxy -= r.sxy;
    s->syy -= r.syy;
}
#endif

/* Line through a run of m unclaimed points from index start: fitted, then
 * refitted without the run's points farther than d from the first fit (a
 * spike in the run would tilt it); (*mx, *my) is the kept points' centroid.
 * Returns 0 if fewer than half of the run lie within d of its first fit (it
 * wraps a corner or the border is ragged there). */
static int sample_line(const qctx *k, const unsigned char *lab, int start, int m, qline *l,
                       float *mx, float *my)
{
    qsums s;
    float msr;
#ifdef ACTAG_QUAD_REFERENCE
    walk_sums(k, lab, start, m, NULL, &s);
#else
    int e1 = 0, e2 = 0, small = walk_all(k, lab, start, m, &s, &e1, &e2);
#endif
    if (!line_fit(&s, l, &msr))
        return 0;
    /* If the squared residuals sum to under d^2, every point is within d
     * and the refit would change nothing (1 % margin for rounding). */
    if (msr * actag_i64_to_f(s.n) > 0.99f * k->d2) {
        qline l0 = *l;
#ifndef ACTAG_QUAD_REFERENCE
        if (small)
            walk_near(k, lab, start, e1, e2, &l0, &s);
        else
#endif
            walk_sums(k, lab, start, m, &l0, &s);
        if (2 * s.n < m || !line_fit(&s, l, NULL))
            return 0;
    }
    *mx = actag_i64_to_f(s.sx) / actag_i64_to_f(s.n);
    *my = actag_i64_to_f(s.sy) / actag_i64_to_f(s.n);
    return 1;
}

int actag_quad_fit(const actag_ipoint *pts, int npoints, const actag_quad_params *params,
                   actag_rng *rng, void *scratch, size_t scratch_size, actag_quad *out)
{
    qctx k;
    qquad best;
    unsigned char *lab;
    float *fx, *fy;
    int n, m, i, it, minx, miny, maxx, maxy, have = 0, early = 0, claim_min;
    int64_t sx = 0, sy = 0;
    float d, promise, best_r0 = 0.0f, best_ratio = 0.0f;

    if (!pts || !params || !rng || !scratch || !out)
        return ACTAG_ERR_NULL;
    d = params->inlier_distance;
    if (npoints < 0 || actag_quad_params_validate(params, NULL) != ACTAG_OK)
        return ACTAG_ERR_PARAM;
    if (npoints > ACTAG_QUAD_MAX_POINTS)
        return ACTAG_ERR_SIZE;
    if (scratch_size < ACTAG_QUAD_SCRATCH_SIZE(npoints))
        return ACTAG_ERR_WORKSPACE;

    memset(out, 0, sizeof *out);
    n = npoints;
    if (n < ACTAG_QUAD_MIN_POINTS)
        return ACTAG_ERR_NO_QUAD;

    minx = maxx = pts[0].x;
    miny = maxy = pts[0].y;
    for (i = 0; i < n; i++) {
        int x = pts[i].x, y = pts[i].y;
        minx = x < minx ? x : minx;
        maxx = x > maxx ? x : maxx;
        miny = y < miny ? y : miny;
        maxy = y > maxy ? y : maxy;
        sx += x;
        sy += y;
    }
    /* Scratch: x and y relative to the origin as floats (4-byte aligned),
     * then one claim label per point. */
    {
        size_t mis = (size_t)((uintptr_t)scratch & 3u);
        fx = (float *)(void *)((unsigned char *)scratch + (mis ? 4u - mis : 0u));
    }
    fy = fx + n;
    lab = (unsigned char *)(fy + n);
    for (i = 0; i < n; i++) {
        fx[i] = (float)(pts[i].x - minx);
        fy[i] = (float)(pts[i].y - miny);
    }
    k.pts = pts;
    k.fx = fx;
    k.fy = fy;
    k.n = n;
    k.ox = minx;
    k.oy = miny;
    k.bw = (float)(maxx - minx);
    k.bh = (float)(maxy - miny);
    k.ext = maxx - minx > maxy - miny ? maxx - minx : maxy - miny;
    k.cx = actag_i64_to_f(sx - (int64_t)minx * n) / (float)n;
    k.cy = actag_i64_to_f(sy - (int64_t)miny * n) / (float)n;
    k.d = d;
    k.d2 = d * d;
    k.ratio = params->inlier_ratio;
    k.min_ratio = params->min_inlier_ratio < k.ratio ? params->min_inlier_ratio : k.ratio;
    k.pcos = params->min_parallel_cos;
    k.chain = 1;
#ifdef QUAD_AVX2
    k.avx2 = actag__cpu_avx2();
#endif
    for (i = 1; i < n; i++) {
        int dx = pts[i].x - pts[i - 1].x, dy = pts[i].y - pts[i - 1].y;
        if (dx < -1 || dx > 1 || dy < -1 || dy > 1)
            k.chain = 0;
    }
    promise = k.min_ratio - QUAD_PROMISE;

    k.accept_min = count_min(n, k.min_ratio, -1.0f);
    claim_min = count_min(n, promise, best_r0);

    m = (int)(params->sample_fraction * (float)n + 0.5f);
    if (m < 3)
        m = 3;
    if (m > n)
        m = n;

    for (it = 0; it < params->max_iterations; it++) {
        qquad q, cand;
        qline lines[4];
        float key[4], r;
        int nfree = n, claimed = 0, line, ok = 1, order[4];

        /* 1. Four lines, each from a run of still unclaimed points; each
         * claims the unclaimed points within d of it. */
        memset(lab, 0, (size_t)n);
        for (line = 0; line < 4 && ok; line++) {
            qline l;
            float mx, my;
            int cnt = 0;
            unsigned char tag = (unsigned char)(line + 1);
            if (nfree < m ||
                !sample_line(&k, lab, (int)actag_rng_below(rng, (uint32_t)n), m, &l, &mx, &my)) {
                ok = 0;
                break;
            }
            lines[line] = l;
            /* Any point of each side orders the sides around an interior
             * point; the run's centroid will do. */
            key[line] = pseudo_angle(mx - k.cx, my - k.cy);
#ifndef ACTAG_QUAD_REFERENCE
            if (line == 3)
                break; /* its claims are counted after step 3 */
#endif
            cnt = claim(&k, lab, &l, tag, 0);
            if (cnt < 2) {
                ok = 0;
                break;
            }
            nfree -= cnt;
            claimed += cnt;
        }
        if (!ok)
            continue;
#ifdef ACTAG_QUAD_REFERENCE
        /* 2. A quad's inliers are a subset of the points its lines
         * claimed: too few claimed points can neither promise a quad nor
         * beat the best unrefined quad so far. */
        r = ratio_of(claimed, n);
        if (r < promise || r <= best_r0)
            continue;
#endif

        /* 3. Order the lines clockwise around the centroid, intersect. */
        for (i = 0; i < 4; i++)
            order[i] = i;
        for (i = 1; i < 4; i++) {
            int j = i, t = order[i];
            while (j > 0 && key[order[j - 1]] > key[t]) {
                order[j] = order[j - 1];
                j--;
            }
            order[j] = t;
        }
        for (i = 0; i < 4; i++)
            q.line[i] = lines[order[i]];
        if (!quad_from_lines(&q) || !quad_shape_ok(&k, &q, 0))
            continue;
#ifndef ACTAG_QUAD_REFERENCE
        /* 2., after step 3 (every test of steps 1-3 only ends the
         * iteration, and the generator was drawn for all four lines, so
         * their order does not change the result): the fourth line's
         * claims, counted only until the total can no longer reach
         * claim_min, the count that step 2 of the reference accepts. */
        {
            int cnt = claim(&k, lab, &lines[3], 4u, claim_min - claimed > 2 ? claim_min - claimed : 2);
            if (cnt < 2 || claimed + cnt < claim_min)
                continue;
        }
#endif

        /* 4. Refine each new best unrefined quad and test it. */
        r = quad_support(&k, &q, claim_min);
        if (r < promise || r <= best_r0)
            continue;
        best_r0 = r;
        claim_min = count_min(n, promise, best_r0);
        if (!refine_and_accept(&k, &q, &cand, &r))
            continue;
        if (!have || r > best_ratio) {
            best = cand;
            best_ratio = r;
            have = 1;
        }
        if (r >= k.ratio) { /* good enough: stop here */
            it++;
            early = 1;
            break;
        }
    }
    out->iterations = it;
    out->stopped_early = early;
    if (!have)
        return ACTAG_ERR_NO_QUAD;
    {
        /* Start at the topmost corner (then leftmost), judged on the
         * returned coordinates so that the rule holds exactly for them. */
        actag_point c[4];
        int s0 = 0;
        for (i = 0; i < 4; i++) {
            c[i].x = best.x[i] + (float)k.ox;
            c[i].y = best.y[i] + (float)k.oy;
        }
        for (i = 1; i < 4; i++)
            if (c[i].y < c[s0].y || (c[i].y == c[s0].y && c[i].x < c[s0].x))
                s0 = i;
        for (i = 0; i < 4; i++)
            out->corners[i] = c[(s0 + i) & 3];
        out->inlier_ratio = best_ratio;
    }
    return ACTAG_OK;
}
