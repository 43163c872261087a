/* The grid-fit decoder's cell reads (fit_cells.h): the mean grey level of
 * every cell of an affine tag grid, by bilinear samples of the frame, and
 * the half-cell lattice the wide search's shifted grids share. Portable C,
 * with bit-identical SSE2 paths on x86-64 (and AVX2 ones, chosen at run
 * time, for the cells of any grid and for lattices inside the frame) and
 * DSP asm on Cortex-M4/M7 for the
 * cells inside the frame (tests/test_decode_lattice.c).
 *
 * The samples are integer arithmetic (so the same on every core and under
 * any float flags, and cheap where a float conversion is not: on Cortex-M7
 * -O2 28 to 32 instructions a sample in C instead of 33 in float, 19 in the
 * DSP asm). A cell's centre, computed in float from the grid, and the
 * pattern's offsets from it, once a grid, are put in fixed point, 1/256
 * pixel, truncated toward zero (ffix); a sample point is the centre plus an
 * offset. At X = 256 x0 + fx (fx in
 * 0..255) and likewise Y, the sample is
 *     top = 256 p(x0, y0)     + (p(x0 + 1, y0)     - p(x0, y0))     fx
 *     bot = 256 p(x0, y0 + 1) + (p(x0 + 1, y0 + 1) - p(x0, y0 + 1)) fx
 *     v   = 256 top + (bot - top) fy            (grey level * 65536)
 * exactly, and a cell mean is the sum of its samples (an int32: 9 * 255 *
 * 65536 < 2^31) as a float times 1 / (65536 * samples). A point lies within
 * 3/256 pixel of the float point it stands for. Outside the frame the
 * point is clamped to it (edge pixels replicated). */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "fit_cells.h"

#include "cpu_x86.h" /* ACTAG__AVX2 */

#include <string.h>

#if ACTAG__FIT_SIMD
#include <emmintrin.h>
#endif

/* Cortex-M4/M7 (__ARM_FEATURE_SIMD32, little-endian): the clamp-free
 * cell reads by the DSP instructions (fcell9_dsp, fcell5_dsp); ACTAG_NO_DSP
 * selects the portable C there too. Only in Thumb-2 (the asm's LDRD takes
 * any two registers, ARM state an even-odd pair), with unaligned loads
 * allowed (not -mno-unaligned-access). */
#if defined(__ARM_FEATURE_SIMD32) && defined(__GNUC__) && !defined(ACTAG_NO_DSP) &&            \
    !defined(__ARM_BIG_ENDIAN) && defined(__thumb2__) && defined(__ARM_FEATURE_UNALIGNED)
#define FIT_DSP 1
#else
#define FIT_DSP 0
#endif

/* Forced inlining of the per-sample steps of the cell reads: GCC -O2 for
 * Cortex-M7 otherwise calls one sampler per sample with the choice of
 * sampler made at run time. */
#if defined(__GNUC__)
#define FIT_INLINE __attribute__((always_inline)) static inline
#else
#define FIT_INLINE static inline
#endif

/* Fixed-point coordinates: 1/256 pixel. FIX_MAX (2^28, i.e. 2^20 pixels)
 * bounds a converted centre or offset, so that a centre plus two offsets
 * cannot overflow an int32 (NaN and infinities clamp too). */
#define FIX_ONE 256.0f
#define FIX_MAX 268435456.0f

/* A coordinate (pixels) in fixed point, truncated toward zero, clamped to
 * +-FIX_MAX, NaN to 0 (so that ffix(-v) = -ffix(v) always). */
static int32_t ffix(float v)
{
    v *= FIX_ONE;
    if (!(v >= -FIX_MAX))
        v = v < 0.0f ? -FIX_MAX : 0.0f;
    if (v > FIX_MAX)
        v = FIX_MAX;
    return (int32_t)v;
}

/* Cell means from sample sums: 1 / (65536 * 9) and 1 / (65536 * 5). */
static const float fit_norm9 = 1.0f / (65536.0f * 9.0f);
static const float fit_norm5 = 1.0f / (65536.0f * 5.0f);

/* The bilinear value (grey * 65536, see the top of this file) at fixed
 * point (X, Y) in [0, (cols - 1) 256] x [0, (rows - 1) 256]; the pixel
 * pair of each row is (x0, x1) and the rows y0, y1. */
FIT_INLINE int32_t flerp(const uint8_t *r0, const uint8_t *r1, int x0, int x1, int32_t fx, int32_t fy)
{
    int32_t a = r0[x0], b = r0[x1], c = r1[x0], d = r1[x1];
    int32_t top = a * 256 + (b - a) * fx, bot = c * 256 + (d - c) * fx;
    return top * 256 + (bot - top) * fy;
}

/* The sample at fixed point (X, Y) anywhere: clamped to the frame, edge
 * pixels replicated. Not inlined: the cell reads take it only near the
 * frame's edges. */
#if defined(__GNUC__)
__attribute__((noinline))
#endif
static int32_t fsample(const fimg *im, int32_t X, int32_t Y)
{
    int32_t xl = (int32_t)(im->cols - 1) * 256, yl = (int32_t)(im->rows - 1) * 256;
    int x0, y0, x1, y1;
    X = X < 0 ? 0 : X > xl ? xl : X;
    Y = Y < 0 ? 0 : Y > yl ? yl : Y;
    x0 = (int)(X >> 8);
    y0 = (int)(Y >> 8);
    x1 = x0 + 1 < im->cols ? x0 + 1 : x0;
    y1 = y0 + 1 < im->rows ? y0 + 1 : y0;
    return flerp(im->img + (size_t)y0 * (size_t)im->stride, im->img + (size_t)y1 * (size_t)im->stride,
                 x0, x1, X & 255, Y & 255);
}

/* A grid's sample pattern, once a grid: the fixed-point offsets from a
 * cell's centre of the 3x3 pattern (sample a + 3 b, a and b in 0..2, at
 * (a - 1) ffix(so a-axis) + (b - 1) ffix(so b-axis)) and of the 5-sample
 * pattern's diagonals (+-ffix(so (a-axis + b-axis)), +-ffix(so (a-axis -
 * b-axis))). */
typedef struct fpat {
    int32_t dx9[9], dy9[9];
    int32_t dx5[4], dy5[4];
    /* a cell's samples all lie within ex9 / ey9 (ex5 / ey5) of its centre:
     * it is read clamp-free when they lie in [0, (cols - 1) 256) */
    int32_t ex9, ey9, ex5, ey5, xin, yin;
#if FIT_DSP
    /* the same offsets but the centre's as (dx, dy) pairs, one LDRD each
     * (fcell9_dsp, fcell5_dsp): samples 0..3 and 5..8, the 4 diagonals */
    int32_t xy9[16], xy5[8];
#endif
} fpat;

static int32_t fabs32(int32_t v)
{
    return v < 0 ? -v : v;
}

/* The pattern of the cell reads that follow: the 5-sample one (fast) or
 * the 3x3 (a grid is read with one of them; the other's fields are left
 * unset). */
static void fpat_of(const fimg *im, const fgrid *gr, int fast, fpat *p)
{
    int a, b;
    p->xin = (int32_t)(im->cols - 1) * 256;
    p->yin = (int32_t)(im->rows - 1) * 256;
    if (!fast) {
        /* the offsets at -so are those at +so negated: ffix truncates
         * toward zero, and a * -so is -(a * so) exactly */
        int32_t ou = ffix(gr->ax * im->so), ov = ffix(gr->ay * im->so);
        int32_t pu = ffix(gr->bx * im->so), pv = ffix(gr->by * im->so);
        p->ex9 = fabs32(ou) + fabs32(pu);
        p->ey9 = fabs32(ov) + fabs32(pv);
        for (b = 0; b < 3; b++)
            for (a = 0; a < 3; a++) {
                p->dx9[a + 3 * b] = (a - 1) * ou + (b - 1) * pu;
                p->dy9[a + 3 * b] = (a - 1) * ov + (b - 1) * pv;
            }
#if FIT_DSP
        for (a = 0; a < 4; a++) { /* sample 4 is the centre */
            p->xy9[2 * a] = p->dx9[a];
            p->xy9[2 * a + 1] = p->dy9[a];
            p->xy9[2 * a + 8] = p->dx9[a + 5];
            p->xy9[2 * a + 9] = p->dy9[a + 5];
        }
#endif
        return;
    }
    p->dx5[0] = ffix(im->so * (gr->ax + gr->bx));
    p->dy5[0] = ffix(im->so * (gr->ay + gr->by));
    p->dx5[2] = ffix(im->so * (gr->ax - gr->bx));
    p->dy5[2] = ffix(im->so * (gr->ay - gr->by));
    p->dx5[1] = -p->dx5[0];
    p->dy5[1] = -p->dy5[0];
    p->dx5[3] = -p->dx5[2];
    p->dy5[3] = -p->dy5[2];
    p->ex5 = fabs32(p->dx5[0]) > fabs32(p->dx5[2]) ? fabs32(p->dx5[0]) : fabs32(p->dx5[2]);
    p->ey5 = fabs32(p->dy5[0]) > fabs32(p->dy5[2]) ? fabs32(p->dy5[0]) : fabs32(p->dy5[2]);
#if FIT_DSP
    for (a = 0; a < 4; a++) {
        p->xy5[2 * a] = p->dx5[a];
        p->xy5[2 * a + 1] = p->dy5[a];
    }
#endif
}

/* fsample for a point in [0, (cols - 1) 256) x [0, (rows - 1) 256): the
 * same value without the clamps. */
FIT_INLINE int32_t fsample_in(const fimg *im, int32_t X, int32_t Y)
{
    const uint8_t *q = im->img + (size_t)(Y >> 8) * (size_t)im->stride + (size_t)(X >> 8);
    return flerp(q, q + im->stride, 0, 1, X & 255, Y & 255);
}

/* Do all points within h cells (along a and b) of (x, y) lie a pixel inside
 * the image? (Then fsample_in serves: the margin covers the fixed point's
 * 3/256 pixel. NaN or infinite coordinates fail.) */
static int fbox_inside(const fimg *im, const fgrid *gr, float x, float y, float h)
{
    float ex = ((gr->ax < 0.0f ? -gr->ax : gr->ax) + (gr->bx < 0.0f ? -gr->bx : gr->bx)) * h;
    float ey = ((gr->ay < 0.0f ? -gr->ay : gr->ay) + (gr->by < 0.0f ? -gr->by : gr->by)) * h;
    return x - ex >= 1.0f && x + ex <= (float)(im->cols - 2) && y - ey >= 1.0f &&
           y + ey <= (float)(im->rows - 2);
}

/* Do all of a grid's sample points lie a pixel inside the image? */
static int fgrid_inside_h(const fimg *im, const fgrid *gr, float h)
{
    return fbox_inside(im, gr, gr->mx, gr->my, h);
}

/* h: centre to the outermost samples of a (k+1)^2 grid, cells */
static int fgrid_inside(const fimg *im, const fgrid *gr, int k)
{
    return fgrid_inside_h(im, gr, 0.5f * (float)(k + 1) + im->so);
}

/* One sample: the clamp-free sampler when the whole grid (or cell) lies
 * inside the frame (the same value, cheaper). */
FIT_INLINE int32_t fsample_at(const fimg *im, int inside, int32_t X, int32_t Y)
{
    return inside ? fsample_in(im, X, Y) : fsample(im, X, Y);
}

#if FIT_DSP
/* fcell9 / fcell5 inside the frame in DSP instructions, one asm block a
 * cell (the C samples take about 28 instructions each on Cortex-M7 -O2, 32
 * where GCC spills; these 19). A sample at (x, y), fractions fx, fy, with
 * a, b / c, d the pixel pairs of rows y0 / y0 + 1, is
 *     v = 256 S1 + fx S2,  S1 = (256 - fy) a + fy c,
 *                          S2 = (256 - fy) (b - a) + fy (d - c),
 * which is flerp's 256 top + (bot - top) fy exactly (all integers). One
 * LDRH a row (unaligned), PKHBT and UXTB16 make the 16-bit lanes {a, c}
 * and {b, d}, SSUB16 {b - a, d - c}, and SMLAD / SMUAD weigh them by
 * {256 - fy, fy} (the word fy 65535 + 256: RSB, ADD): lanes and products
 * fit 16 and 32 bits. The cell's S1 and fx S2 are summed apart (s1, s2)
 * and its sum is 256 s1 + s2, below 2^31 as the C sum: the same int32.
 * The centre (X, Y) is read first (offsets (0, 0): no load, no adds), then
 * each (dx, dy) pair of the pattern (fpat's xy9, xy5) by one LDRD. */
#define FDSP_AT(px, py)                                                                            \
    "uxtb %[w], %[" py "]\n\t"                                                                    \
    "asr %[y], %[" py "], #8\n\t"                                                                 \
    "rsb %[w], %[w], %[w], lsl #16\n\t"                                                          \
    "add %[w], %[w], #256\n\t"                                                                   \
    "mla %[y], %[y], %[s], %[img]\n\t"                                                           \
    "add %[y], %[y], %[" px "], asr #8\n\t"                                                       \
    "uxtb %[x], %[" px "]\n\t"                                                                    \
    "ldrh %[t], [%[y]]\n\t"                                                                      \
    "ldrh %[y], [%[y], %[s]]\n\t"                                                                \
    "pkhbt %[t], %[t], %[y], lsl #16\n\t"                                                        \
    "uxtb16 %[y], %[t], ror #8\n\t"                                                              \
    "uxtb16 %[t], %[t]\n\t"                                                                      \
    "ssub16 %[y], %[y], %[t]\n\t"
/* the centre: s1 = S1, s2 = fx S2 */
#define FDSP_CENTRE                                                                                \
    FDSP_AT("X", "Y")                                                                              \
    "smuad %[s1], %[t], %[w]\n\t"                                                                \
    "smuad %[y], %[y], %[w]\n\t"                                                                 \
    "mul %[s2], %[x], %[y]\n\t"
/* pair i: s1 += S1, s2 += fx S2 */
#define FDSP_PAIR(i)                                                                               \
    "ldrd %[x], %[y], [%[d], #8*" #i "]\n\t"                                                     \
    "add %[x], %[x], %[X]\n\t"                                                                   \
    "add %[y], %[y], %[Y]\n\t" FDSP_AT("x", "y")                                                 \
    "smlad %[s1], %[t], %[w], %[s1]\n\t"                                                         \
    "smuad %[y], %[y], %[w]\n\t"                                                                 \
    "mla %[s2], %[x], %[y], %[s2]\n\t"
#define FDSP_SUM "add %[s2], %[s2], %[s1], lsl #8"
/* Eleven registers (six outputs, five inputs): a build that reserves two
 * more (a frame pointer: -fno-omit-frame-pointer, -O0; a PIC base: -fPIC
 * -msingle-pic-base, or -ffixed-r9) still has them (with thirteen, 18
 * instructions a sample, such builds failed with "impossible
 * constraints"). What the asm reads (the frame, the pattern) is declared by
 * a "memory" clobber: an array operand of the frame's size would be a
 * variable-length array type (-Wvla). */
#define FDSP_OPERANDS(pairs)                                                                       \
    : [x] "=&r"(x), [y] "=&r"(y), [w] "=&r"(w), [t] "=&r"(t), [s1] "=&r"(s1), [s2] "=&r"(s2)      \
    : [d] "r"(pairs), [X] "r"(X), [Y] "r"(Y), [img] "r"(im->img), [s] "r"(im->stride)             \
    : "memory"

FIT_INLINE int32_t fcell9_dsp(const fimg *im, const fpat *p, int32_t X, int32_t Y)
{
    int32_t x, y, w, t, s1, s2;
    __asm__(FDSP_CENTRE FDSP_PAIR(0) FDSP_PAIR(1) FDSP_PAIR(2) FDSP_PAIR(3) FDSP_PAIR(4)
                FDSP_PAIR(5) FDSP_PAIR(6) FDSP_PAIR(7) FDSP_SUM FDSP_OPERANDS(p->xy9));
    return s2;
}

FIT_INLINE int32_t fcell5_dsp(const fimg *im, const fpat *p, int32_t X, int32_t Y)
{
    int32_t x, y, w, t, s1, s2;
    __asm__(FDSP_CENTRE FDSP_PAIR(0) FDSP_PAIR(1) FDSP_PAIR(2) FDSP_PAIR(3) FDSP_SUM
                FDSP_OPERANDS(p->xy5));
    return s2;
}
#undef FDSP_AT
#undef FDSP_CENTRE
#undef FDSP_PAIR
#undef FDSP_SUM
#undef FDSP_OPERANDS
#endif

/* The 5-sample sum (centre and the 4 diagonal points) of the cell centred
 * at fixed point (X, Y). */
FIT_INLINE int32_t fcell5(const fimg *im, const fpat *p, int inside, int32_t X, int32_t Y)
{
#if FIT_DSP
    if (inside)
        return fcell5_dsp(im, p, X, Y);
#endif
    return fsample_at(im, inside, X, Y) + fsample_at(im, inside, X + p->dx5[0], Y + p->dy5[0]) +
           fsample_at(im, inside, X + p->dx5[1], Y + p->dy5[1]) +
           fsample_at(im, inside, X + p->dx5[2], Y + p->dy5[2]) +
           fsample_at(im, inside, X + p->dx5[3], Y + p->dy5[3]);
}

/* The 9-sample sum (3x3 pattern) of the cell centred at fixed point (X, Y). */
FIT_INLINE int32_t fcell9(const fimg *im, const fpat *p, int inside, int32_t X, int32_t Y)
{
    int32_t s = 0;
    int i;
#if FIT_DSP
    if (inside)
        return fcell9_dsp(im, p, X, Y);
#endif
    /* a loop: written out, Cortex-M7 -O2 spills and takes 15 % more */
    for (i = 0; i < 9; i++)
        s += fsample_at(im, inside, X + p->dx9[i], Y + p->dy9[i]);
    return s;
}

/* One cell's mean (fast: 5 samples, else 9) of a grid that leaves the
 * frame, centre (x, y) in pixels: the clamp-free reads when all of the
 * cell's samples lie inside, the clamping ones otherwise. */
static float fcell_edge(const fimg *im, const fpat *p, int fast, float x, float y)
{
    int32_t X = ffix(x), Y = ffix(y);
    int32_t ex = fast ? p->ex5 : p->ex9, ey = fast ? p->ey5 : p->ey9;
    int in = X - ex >= 0 && X + ex < p->xin && Y - ey >= 0 && Y + ey < p->yin;
    if (fast)
        return (float)(in ? fcell5(im, p, 1, X, Y) : fcell5(im, p, 0, X, Y)) * fit_norm5;
    return (float)(in ? fcell9(im, p, 1, X, Y) : fcell9(im, p, 0, X, Y)) * fit_norm9;
}

#if ACTAG__FIT_SIMD
/* x86-64 (SSE2): the reads of fcell5 and fcells_on four cells at a time,
 * one cell per lane, with the scalar code's integers (the products of
 * bot - top and fy, below 2^24, are formed exactly in float: SSE2 has no
 * 32-bit multiply), so the cell means are bit-identical
 * (tests/test_decode_lattice.c compares them). Grids inside the frame:
 * fsample4_in; grids that leave it: fsample4_cl (fsample's clamps). */

/* Can the lanes form a pixel's offset y * stride + x by one PMADDWD (signed
 * 16-bit x, y and stride)? rows and cols are at most ACTAG_MAX_DIM. */
int actag__fit_simd_ok(int rows, int cols, int stride)
{
    return rows <= 32767 && cols <= 32767 && stride > 0 && stride <= 32767;
}

/* Two adjacent bytes as one 16-bit lane value (its bits; a short, so that
 * GCC's -O0 macro form of _mm_insert_epi16 converts nothing that may not
 * fit: -Wconversion). */
static inline short fld16(const uint8_t *p)
{
    int16_t v;
    memcpy(&v, p, sizeof v);
    return v;
}

/* ffix of four coordinates. */
static inline __m128i ffix4(__m128 v)
{
    __m128 lo = _mm_set1_ps(-FIX_MAX), ok, neg;
    v = _mm_mul_ps(v, _mm_set1_ps(FIX_ONE));
    ok = _mm_cmpge_ps(v, lo); /* false for NaN, as !(v >= -FIX_MAX) */
    neg = _mm_cmplt_ps(v, _mm_setzero_ps()); /* false for NaN: 0 */
    v = _mm_or_ps(_mm_and_ps(ok, v), _mm_andnot_ps(ok, _mm_and_ps(neg, lo)));
    v = _mm_min_ps(v, _mm_set1_ps(FIX_MAX));
    return _mm_cvttps_epi32(v);
}

/* flerp of four points from their pixel pairs: lane i's row pair starts at
 * r0 + o[i] (bytes x0, x0 + 1) and r1 + q[i], fx (0..256) and fy (0..255)
 * its fractions. */
static inline __m128i flerp4(const uint8_t *r0, const int *o, const uint8_t *r1, const int *q,
                             __m128i fx, __m128i fy)
{
    __m128i byte = _mm_set1_epi32(0xff), w, a, b, c, d, top, bot;
    __m128 prod;
    /* lane i: bytes r0[x0], r0[x0 + 1], r1[x0], r1[x0 + 1] of its point */
    w = _mm_cvtsi32_si128(fld16(r0 + o[0]));
    w = _mm_insert_epi16(w, fld16(r1 + q[0]), 1);
    w = _mm_insert_epi16(w, fld16(r0 + o[1]), 2);
    w = _mm_insert_epi16(w, fld16(r1 + q[1]), 3);
    w = _mm_insert_epi16(w, fld16(r0 + o[2]), 4);
    w = _mm_insert_epi16(w, fld16(r1 + q[2]), 5);
    w = _mm_insert_epi16(w, fld16(r0 + o[3]), 6);
    w = _mm_insert_epi16(w, fld16(r1 + q[3]), 7);
    a = _mm_and_si128(w, byte);
    b = _mm_and_si128(_mm_srli_epi32(w, 8), byte);
    c = _mm_and_si128(_mm_srli_epi32(w, 16), byte);
    d = _mm_srli_epi32(w, 24);
    /* (b - a) fx by PMADDWD: the difference's high half (0 or -1) meets
     * fx's high half, 0 */
    top = _mm_add_epi32(_mm_slli_epi32(a, 8), _mm_madd_epi16(_mm_sub_epi32(b, a), fx));
    bot = _mm_add_epi32(_mm_slli_epi32(c, 8), _mm_madd_epi16(_mm_sub_epi32(d, c), fx));
    prod = _mm_mul_ps(_mm_cvtepi32_ps(_mm_sub_epi32(bot, top)), _mm_cvtepi32_ps(fy));
    return _mm_add_epi32(_mm_slli_epi32(top, 8), _mm_cvttps_epi32(prod));
}

/* fsample_in at four fixed points (wmul: 1 | stride << 16 per lane). Not
 * inlined: the 9 or 5 inlined copies of a cell read spill many vectors. */
#if defined(__GNUC__)
__attribute__((noinline))
#endif
static __m128i fsample4_in(const fimg *im, __m128i wmul, __m128i X, __m128i Y)
{
    __m128i f = _mm_set1_epi32(0xff);
    __m128i xi = _mm_srai_epi32(X, 8), yi = _mm_srai_epi32(Y, 8);
    const uint8_t *p = im->img;
    int o[4];
    _mm_storeu_si128((__m128i *)(void *)o, _mm_madd_epi16(_mm_or_si128(xi, _mm_slli_epi32(yi, 16)), wmul));
    return flerp4(p, o, p + im->stride, o, _mm_and_si128(X, f), _mm_and_si128(Y, f));
}

/* fsample (the clamping sampler) at four fixed points, for grids that leave
 * the frame; cols >= 2. The row pair is y0, y1 = min(y0 + 1, rows - 1).
 * For the column pair, loaded as two adjacent bytes, x0 = cols - 1 (only
 * at X = (cols - 1) 256, fx = 0) becomes x0 = cols - 2, fx = 256: 256 a +
 * (b - a) 256 is then 256 b, b = r[cols - 1], as fsample's 256 r[cols - 1],
 * so the value is the same and no load leaves the frame. */
typedef struct fclamp { /* fsample4_cl's limits, set once a grid (fclamp_of) */
    __m128i xl, yl;       /* (cols - 1) 256, (rows - 1) 256 */
    __m128i x0max, y0max; /* cols - 2, rows - 1 */
} fclamp;

static void fclamp_of(const fimg *im, fclamp *cl)
{
    cl->xl = _mm_set1_epi32((im->cols - 1) * 256);
    cl->yl = _mm_set1_epi32((im->rows - 1) * 256);
    cl->x0max = _mm_set1_epi32(im->cols - 2);
    cl->y0max = _mm_set1_epi32(im->rows - 1);
}

/* v clamped to [0, hi] lane by lane (SSE2 has no 32-bit min / max). */
static inline __m128i fclamp4(__m128i v, __m128i hi)
{
    __m128i over;
    v = _mm_andnot_si128(_mm_srai_epi32(v, 31), v);
    over = _mm_cmpgt_epi32(v, hi);
    return _mm_or_si128(_mm_andnot_si128(over, v), _mm_and_si128(over, hi));
}

#if defined(__GNUC__)
__attribute__((noinline))
#endif
static __m128i fsample4_cl(const fimg *im, const fclamp *cl, __m128i wmul, __m128i X, __m128i Y)
{
    __m128i f = _mm_set1_epi32(0xff), xi, yi, y1, fx, over;
    const uint8_t *p = im->img;
    int o[4], q[4];
    X = fclamp4(X, cl->xl);
    Y = fclamp4(Y, cl->yl);
    xi = _mm_srai_epi32(X, 8);
    yi = _mm_srai_epi32(Y, 8);
    fx = _mm_and_si128(X, f);
    /* x0 at most cols - 2, fx 256 there */
    over = _mm_cmpgt_epi32(xi, cl->x0max);
    xi = _mm_add_epi32(xi, over);
    fx = _mm_or_si128(fx, _mm_and_si128(over, _mm_set1_epi32(256)));
    /* y1 = y0 + 1 where y0 + 1 < rows */
    y1 = _mm_sub_epi32(yi, _mm_cmplt_epi32(yi, cl->y0max));
    _mm_storeu_si128((__m128i *)(void *)o, _mm_madd_epi16(_mm_or_si128(xi, _mm_slli_epi32(yi, 16)), wmul));
    _mm_storeu_si128((__m128i *)(void *)q, _mm_madd_epi16(_mm_or_si128(xi, _mm_slli_epi32(y1, 16)), wmul));
    return flerp4(p, o, p, q, fx, _mm_and_si128(Y, f));
}

/* The SIMD counterpart of fsample_at (cl: the grid leaves the frame). */
static inline __m128i fsample4(const fimg *im, const fclamp *cl, __m128i wmul, __m128i X, __m128i Y)
{
    return cl ? fsample4_cl(im, cl, wmul, X, Y) : fsample4_in(im, wmul, X, Y);
}

/* fcell5's means of four cells centred at (x0, y0) (pixels). */
static inline __m128 fcell5_4(const fimg *im, const fpat *p, const fclamp *cl, __m128i wmul,
                              __m128 x0, __m128 y0)
{
    __m128i X = ffix4(x0), Y = ffix4(y0), s;
    int i;
    s = fsample4(im, cl, wmul, X, Y);
    for (i = 0; i < 4; i++)
        s = _mm_add_epi32(s, fsample4(im, cl, wmul, _mm_add_epi32(X, _mm_set1_epi32(p->dx5[i])),
                                      _mm_add_epi32(Y, _mm_set1_epi32(p->dy5[i]))));
    return _mm_mul_ps(_mm_cvtepi32_ps(s), _mm_set1_ps(fit_norm5));
}

/* fcells_on(im, gr, k, m, !cl, skip), four cells at a time in row order
 * (the last group repeats the last cell in its spare lanes). Lane counters
 * cx, cy step by 4 cells, wrapping at most once a row as n >= 5. */
static inline void fcells_simd(const fimg *im, const fgrid *gr, int k, float *m, int skip,
                               const fclamp *cl)
{
    int i, j, n = k + 1, nn = n * n;
    float g = 0.5f * (float)n;
    fpat p;
    __m128 half = _mm_set1_ps(0.5f), gv = _mm_set1_ps(g);
    __m128 mx = _mm_set1_ps(gr->mx), my = _mm_set1_ps(gr->my);
    __m128 ax = _mm_set1_ps(gr->ax), ay = _mm_set1_ps(gr->ay);
    __m128 bx = _mm_set1_ps(gr->bx), by = _mm_set1_ps(gr->by);
    __m128i wmul = _mm_set1_epi32(1 | im->stride << 16);
    __m128i cx = _mm_setr_epi32(0, 1, 2, 3), cy = _mm_setzero_si128();
    __m128i nv = _mm_set1_epi32(n), last = _mm_set1_epi32(n - 1), four = _mm_set1_epi32(4);
    fpat_of(im, gr, im->fast, &p);
    for (i = 0; i < nn; i += 4) {
        float r[4];
        __m128i lx = cx, ly = cy, wrap;
        __m128 x0, y0, u0, v0, s;
        if (i + 4 > nn) { /* lanes past the last cell (cy == n): the last cell */
            __m128i over = _mm_cmpgt_epi32(ly, last);
            lx = _mm_or_si128(_mm_andnot_si128(over, lx), _mm_and_si128(over, last));
            ly = _mm_or_si128(_mm_andnot_si128(over, ly), _mm_and_si128(over, last));
        }
        /* u0 = (float)cx + 0.5f - g, x0 = mx + ax * u0 + bx * v0 */
        u0 = _mm_sub_ps(_mm_add_ps(_mm_cvtepi32_ps(lx), half), gv);
        v0 = _mm_sub_ps(_mm_add_ps(_mm_cvtepi32_ps(ly), half), gv);
        x0 = _mm_add_ps(_mm_add_ps(mx, _mm_mul_ps(ax, u0)), _mm_mul_ps(bx, v0));
        y0 = _mm_add_ps(_mm_add_ps(my, _mm_mul_ps(ay, u0)), _mm_mul_ps(by, v0));
        cx = _mm_add_epi32(cx, four);
        wrap = _mm_cmpgt_epi32(cx, last);
        cx = _mm_sub_epi32(cx, _mm_and_si128(wrap, nv));
        cy = _mm_sub_epi32(cy, wrap);
        if (im->fast) {
            s = fcell5_4(im, &p, cl, wmul, x0, y0);
        } else {
            __m128i X = ffix4(x0), Y = ffix4(y0), t = _mm_setzero_si128();
            for (j = 0; j < 9; j++)
                t = _mm_add_epi32(t, fsample4(im, cl, wmul, _mm_add_epi32(X, _mm_set1_epi32(p.dx9[j])),
                                              _mm_add_epi32(Y, _mm_set1_epi32(p.dy9[j]))));
            s = _mm_mul_ps(_mm_cvtepi32_ps(t), _mm_set1_ps(fit_norm9));
        }
        if (i + 4 <= nn) {
            _mm_storeu_ps(m + i, s);
        } else {
            _mm_storeu_ps(r, s);
            for (j = 0; i + j < nn; j++)
                m[i + j] = r[j];
        }
    }
    if (skip) /* erased data corners: not read */
        m[0] = m[k] = m[k * n] = m[k * n + k] = 0.0f;
}
#endif

#if ACTAG__AVX2
/* x86-64 with AVX2 (chosen at run time: im->avx2): the reads of grids
 * inside the frame eight cells at a time, one per lane, giving fsample_in's
 * integers (so the means are bit-identical: tests/test_decode_lattice.c).
 * Grids that leave the frame (frames of 2 rows and columns or more) have an
 * AVX2 clamping sampler too (fsample8_cl: the SSE2 one, fsample4_cl, took
 * 0.54 M instructions a pool frame and about 1.2 % of the run time; the
 * AVX2 one 0.25 M, and the pipeline 0.01-0.02 ms less a frame); lattices
 * that leave it keep the SSE2 one (1 % of its samples). No FMA: fpmath.h's
 * fp-contract=off holds for these functions too (even where the consumer
 * builds with -mfma), so the centres' multiplies and adds round as the
 * scalar code's. A sample v = 256 top + (bot - top) fy is formed as
 *     v = 256 S1 + fx S2,  S1 = (256 - fy) a + fy c,
 *                          S2 = (256 - fy) (b - a) + fy (d - c)
 * (the same integer, as fcell9_dsp's): S1 and S2 by one VPMADDWD each from
 * the 16-bit lanes {a, c} and {b - a, d - c} and the weights {256 - fy,
 * fy}, fx S2 by VPMULLD (|S2| <= 65280: no overflow). */

/* The pixel pairs by two 4-byte gathers a lane (VPGATHERDD): row y0 from
 * byte x0 (a, b the low two bytes), row y0 + 1 from byte x0 - 2 (c, d the
 * high two), and one word blend {a, b, c, d}. Scalar loads instead (two
 * 16-bit loads a lane joined in a register, VPINSRD) took 0.25 ms a pool
 * frame more (the whole pipeline 3.1 ms against 2.85).
 * No read leaves the frame's bytes [0, (rows - 1) stride + cols). A point
 * of a grid inside the frame is fsample_in's, X in [0, (cols - 1) 256) and
 * Y in [0, (rows - 1) 256), so 0 <= x0 <= cols - 2, 0 <= y0 <= rows - 2
 * (fgrid_inside asks a pixel of margin of the float points; the fixed point
 * lies within 3/256 pixel of them, so x0 = 0 is not excluded and row y0
 * may not be read from x0 - 2 at y0 = 0), and rows, cols >= 3. Row y0's
 * read ends at y0 stride + x0 + 3 <= (rows - 2) stride + cols + 1 <=
 * (rows - 1) stride + cols - 1, the frame's last byte, as stride >= cols
 * >= 2: it reaches into row y0 + 1 <= rows - 1 at most. Row y0 + 1's read
 * starts at (y0 + 1) stride + x0 - 2 >= stride - 2 >= 1 and ends at its
 * byte x0 + 1 <= cols - 1, fsample_in's own last byte.
 * test_avx2_cells_every_lane reads such points from frames allocated to
 * their last byte (valgrind_decode_lattice). */
ACTAG__AVX2_TARGET static inline __m256i fpairs8(const uint8_t *img, int stride, __m256i o)
{
    __m256i w0 = _mm256_i32gather_epi32((const int *)(const void *)img, o, 1);
    __m256i w1 = _mm256_i32gather_epi32((const int *)(const void *)(img + stride - 2), o, 1);
    return _mm256_blend_epi16(w0, w1, 0xaa);
}

/* fsample_in at eight fixed points (wmul: 1 | stride << 16 per lane). */
ACTAG__AVX2_TARGET static inline __m256i fsample8_in(const fimg *im, __m256i wmul, __m256i X, __m256i Y)
{
    __m256i f = _mm256_set1_epi32(0xff), xy, w, ac, d, fy, wt;
    /* offsets y0 stride + x0 by VPMADDWD, as fsample4_in */
    xy = _mm256_or_si256(_mm256_srai_epi32(X, 8), _mm256_slli_epi32(_mm256_srai_epi32(Y, 8), 16));
    w = fpairs8(im->img, im->stride, _mm256_madd_epi16(xy, wmul));
    ac = _mm256_and_si256(w, _mm256_set1_epi32(0x00ff00ff));
    d = _mm256_sub_epi16(_mm256_srli_epi16(w, 8), ac);
    fy = _mm256_and_si256(Y, f);
    /* {256 - fy, fy}: fy 65536 + 256 - fy */
    wt = _mm256_add_epi32(_mm256_sub_epi32(_mm256_slli_epi32(fy, 16), fy), _mm256_set1_epi32(256));
    return _mm256_add_epi32(_mm256_slli_epi32(_mm256_madd_epi16(ac, wt), 8),
                            _mm256_mullo_epi32(_mm256_madd_epi16(d, wt), _mm256_and_si256(X, f)));
}

/* The sums of eight cells (fast: fcell5's 5 samples, else fcell9's 9)
 * centred at (x0, y0) (pixels, inside the frame: ffix's clamps do nothing,
 * as in frow_in), as means. */
ACTAG__AVX2_TARGET static inline __m256 fcell_8(const fimg *im, const fpat *p, int fast, __m256i wmul,
                                                __m256 x0, __m256 y0)
{
    __m256 one = _mm256_set1_ps(FIX_ONE);
    __m256i X = _mm256_cvttps_epi32(_mm256_mul_ps(x0, one)), Y = _mm256_cvttps_epi32(_mm256_mul_ps(y0, one));
    __m256i s = fsample8_in(im, wmul, X, Y);
    int i;
    if (fast) {
        for (i = 0; i < 4; i++)
            s = _mm256_add_epi32(s, fsample8_in(im, wmul, _mm256_add_epi32(X, _mm256_set1_epi32(p->dx5[i])),
                                                _mm256_add_epi32(Y, _mm256_set1_epi32(p->dy5[i]))));
        return _mm256_mul_ps(_mm256_cvtepi32_ps(s), _mm256_set1_ps(fit_norm5));
    }
    for (i = 0; i < 9; i++) /* sample 4, the centre, read above */
        if (i != 4)
            s = _mm256_add_epi32(s, fsample8_in(im, wmul, _mm256_add_epi32(X, _mm256_set1_epi32(p->dx9[i])),
                                                _mm256_add_epi32(Y, _mm256_set1_epi32(p->dy9[i]))));
    return _mm256_mul_ps(_mm256_cvtepi32_ps(s), _mm256_set1_ps(fit_norm9));
}

/* ffix of eight coordinates (ffix4's steps: NaN 0, clamped to +-FIX_MAX). */
ACTAG__AVX2_TARGET static inline __m256i ffix8(__m256 v)
{
    __m256 lo = _mm256_set1_ps(-FIX_MAX), ok, neg;
    v = _mm256_mul_ps(v, _mm256_set1_ps(FIX_ONE));
    ok = _mm256_cmp_ps(v, lo, _CMP_GE_OQ);                  /* false for NaN */
    neg = _mm256_cmp_ps(v, _mm256_setzero_ps(), _CMP_LT_OQ); /* false for NaN: 0 */
    v = _mm256_or_ps(_mm256_and_ps(ok, v), _mm256_andnot_ps(ok, _mm256_and_ps(neg, lo)));
    v = _mm256_min_ps(v, _mm256_set1_ps(FIX_MAX));
    return _mm256_cvttps_epi32(v);
}

/* fsample (the clamping sampler) at eight fixed points, for grids that
 * leave the frame (rows, cols >= 2): fsample4_cl's clamps and column pair
 * (x0 = cols - 1 read as x0 = cols - 2 with fx = 256: the same value),
 * fsample8_in's arithmetic (fx = 256 included: |S2| 256 < 2^24). Rows y0
 * and y1 = min(y0 + 1, rows - 1): row y1's pair by a gather from its byte
 * x0 - 2 (y1 >= 1, so at or after byte stride - 2 >= 0; it ends at byte x0
 * + 1 <= cols - 1 of row y1), row y0's from byte x0 where y0 < rows - 1
 * (it ends at most at byte (rows - 2) stride + cols + 1, within row y0 +
 * 1, as in fpairs8); on the last row, y0 = y1, its pair is row y1's (that
 * lane's gather masked off: nothing read past the frame). */
ACTAG__AVX2_TARGET static inline __m256i fsample8_cl(const fimg *im, __m256i wmul, __m256i X, __m256i Y)
{
    __m256i f = _mm256_set1_epi32(0xff), zero = _mm256_setzero_si256();
    __m256i last = _mm256_set1_epi32(im->rows - 1), xi, yi, fx, fy, over, up, o, q, w0, w1, w, ac, d, wt;
    X = _mm256_min_epi32(_mm256_max_epi32(X, zero), _mm256_set1_epi32((im->cols - 1) * 256));
    Y = _mm256_min_epi32(_mm256_max_epi32(Y, zero), _mm256_set1_epi32((im->rows - 1) * 256));
    xi = _mm256_srai_epi32(X, 8);
    yi = _mm256_srai_epi32(Y, 8);
    fx = _mm256_and_si256(X, f);
    fy = _mm256_and_si256(Y, f);
    over = _mm256_cmpgt_epi32(xi, _mm256_set1_epi32(im->cols - 2)); /* x0 = cols - 1 */
    xi = _mm256_add_epi32(xi, over);
    fx = _mm256_or_si256(fx, _mm256_and_si256(over, _mm256_set1_epi32(256)));
    up = _mm256_cmpgt_epi32(last, yi); /* y0 < rows - 1: y1 = y0 + 1 */
    o = _mm256_madd_epi16(_mm256_or_si256(xi, _mm256_slli_epi32(yi, 16)), wmul);
    q = _mm256_madd_epi16(_mm256_or_si256(xi, _mm256_slli_epi32(_mm256_sub_epi32(yi, up), 16)), wmul);
    w1 = _mm256_i32gather_epi32((const int *)(const void *)im->img, _mm256_sub_epi32(q, _mm256_set1_epi32(2)), 1);
    w0 = _mm256_mask_i32gather_epi32(_mm256_srli_epi32(w1, 16), (const int *)(const void *)im->img, o, up, 1);
    w = _mm256_blend_epi16(w0, w1, 0xaa);
    ac = _mm256_and_si256(w, _mm256_set1_epi32(0x00ff00ff));
    d = _mm256_sub_epi16(_mm256_srli_epi16(w, 8), ac);
    wt = _mm256_add_epi32(_mm256_sub_epi32(_mm256_slli_epi32(fy, 16), fy), _mm256_set1_epi32(256));
    return _mm256_add_epi32(_mm256_slli_epi32(_mm256_madd_epi16(ac, wt), 8),
                            _mm256_mullo_epi32(_mm256_madd_epi16(d, wt), fx));
}

/* fcell_8 for grids that leave the frame: ffix's clamps on the centres,
 * the clamping sampler. */
ACTAG__AVX2_TARGET static inline __m256 fcell_8_cl(const fimg *im, const fpat *p, int fast, __m256i wmul,
                                                   __m256 x0, __m256 y0)
{
    __m256i X = ffix8(x0), Y = ffix8(y0), s = fsample8_cl(im, wmul, X, Y);
    int i;
    if (fast) {
        for (i = 0; i < 4; i++)
            s = _mm256_add_epi32(s, fsample8_cl(im, wmul, _mm256_add_epi32(X, _mm256_set1_epi32(p->dx5[i])),
                                                _mm256_add_epi32(Y, _mm256_set1_epi32(p->dy5[i]))));
        return _mm256_mul_ps(_mm256_cvtepi32_ps(s), _mm256_set1_ps(fit_norm5));
    }
    for (i = 0; i < 9; i++) /* sample 4, the centre, read above */
        if (i != 4)
            s = _mm256_add_epi32(s, fsample8_cl(im, wmul, _mm256_add_epi32(X, _mm256_set1_epi32(p->dx9[i])),
                                                _mm256_add_epi32(Y, _mm256_set1_epi32(p->dy9[i]))));
    return _mm256_mul_ps(_mm256_cvtepi32_ps(s), _mm256_set1_ps(fit_norm9));
}

/* Lane counters (c, r) of a row-major walk over rows of n >= 5 points, c
 * stepped by up to 8: brought back into 0..n-1 (at most twice, as
 * c < 3n). */
ACTAG__AVX2_TARGET static inline void fwrap8(__m256i *c, __m256i *r, __m256i n)
{
    __m256i last = _mm256_sub_epi32(n, _mm256_set1_epi32(1)), w;
    int t;
    for (t = 0; t < 2; t++) {
        w = _mm256_cmpgt_epi32(*c, last);
        *c = _mm256_sub_epi32(*c, _mm256_and_si256(w, n));
        *r = _mm256_sub_epi32(*r, w);
    }
}

/* The centres ((mx + ax u) + bx v, likewise y: the scalar code's order) of
 * the points (c, r) of a walk of nr rows of n points, u = c + cu, v = r +
 * cv; the lanes past the walk's end (r >= nr) take its last point. */
ACTAG__AVX2_TARGET static inline void fcentres8(const fgrid *gr, __m256i c, __m256i r, int n, int nr,
                                                float cu, float cv, __m256 *x0, __m256 *y0)
{
    __m256i over = _mm256_cmpgt_epi32(r, _mm256_set1_epi32(nr - 1));
    __m256 u, v;
    c = _mm256_blendv_epi8(c, _mm256_set1_epi32(n - 1), over);
    r = _mm256_blendv_epi8(r, _mm256_set1_epi32(nr - 1), over);
    u = _mm256_add_ps(_mm256_cvtepi32_ps(c), _mm256_set1_ps(cu));
    v = _mm256_add_ps(_mm256_cvtepi32_ps(r), _mm256_set1_ps(cv));
    *x0 = _mm256_add_ps(_mm256_add_ps(_mm256_set1_ps(gr->mx), _mm256_mul_ps(_mm256_set1_ps(gr->ax), u)),
                        _mm256_mul_ps(_mm256_set1_ps(gr->bx), v));
    *y0 = _mm256_add_ps(_mm256_add_ps(_mm256_set1_ps(gr->my), _mm256_mul_ps(_mm256_set1_ps(gr->ay), u)),
                        _mm256_mul_ps(_mm256_set1_ps(gr->by), v));
}

/* fcells_on(im, gr, k, m, 1, skip) for a grid inside the frame (cl 0), or
 * fcells_on(im, gr, k, m, 0, skip) for one that leaves it (cl 1: rows,
 * cols >= 2), eight cells at a time in row order; p: the grid's pattern,
 * fpat_of run by the caller (run from here, its SSE code met dirty upper
 * halves of the YMM registers, GCC putting no VZEROUPPER before the call,
 * and took a fifth of this function's time). */
ACTAG__AVX2_TARGET static void fcells_avx2(const fimg *im, const fgrid *gr, const fpat *p, int k,
                                           float *m, int skip, int cl)
{
    int i, n = k + 1, nn = n * n;
    /* u0 = cx + 1/2 - g: multiples of 1/2 below 16, exact in any order */
    float cu = 0.5f - 0.5f * (float)n;
    __m256i wmul = _mm256_set1_epi32(1 | im->stride << 16), nv = _mm256_set1_epi32(n);
    __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7), cx = lane, cy = _mm256_setzero_si256();
    fwrap8(&cx, &cy, nv);
    for (i = 0; i < nn; i += 8) {
        __m256 x0, y0, s;
        fcentres8(gr, cx, cy, n, n, cu, cu, &x0, &y0);
        cx = _mm256_add_epi32(cx, _mm256_set1_epi32(8));
        fwrap8(&cx, &cy, nv);
        s = cl ? fcell_8_cl(im, p, im->fast, wmul, x0, y0) : fcell_8(im, p, im->fast, wmul, x0, y0);
        if (i + 8 <= nn) /* else lanes 0..nn-i-1 (a tail loop became a memcpy call) */
            _mm256_storeu_ps(m + i, s);
        else
            _mm256_maskstore_ps(m + i, _mm256_cmpgt_epi32(_mm256_set1_epi32(nn - i), lane), s);
    }
    if (skip) /* erased data corners: not read */
        m[0] = m[k] = m[k * n] = m[k * n + k] = 0.0f;
}

/* flattice for a lattice inside the frame, eight points at a time in row
 * order (as flattice_simd); p: fpat_of(im, gr, 1), as for fcells_avx2. */
ACTAG__AVX2_TARGET static void flattice_avx2(const fimg *im, const fgrid *gr, const fpat *p, int k,
                                             int pi, int pj, float *Q)
{
    int i, r, n = k + 1, nc = n + 2 - pi, nr = n + 2 - pj, nq = nr * nc;
    /* u = c + pi/2 - 1/2 - g (likewise v): exact, as in fcells_avx2 */
    float g = 0.5f * (float)n, cu = 0.5f * (float)pi - 0.5f - g, cv = 0.5f * (float)pj - 0.5f - g;
    float q[FIT_LAT_MAX * FIT_LAT_MAX + 7];
    __m256i wmul = _mm256_set1_epi32(1 | im->stride << 16), nv = _mm256_set1_epi32(nc);
    __m256i cx = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7), cy = _mm256_setzero_si256();
    fwrap8(&cx, &cy, nv);
    for (i = 0; i < nq; i += 8) {
        __m256 x0, y0;
        fcentres8(gr, cx, cy, nc, nr, cu, cv, &x0, &y0);
        cx = _mm256_add_epi32(cx, _mm256_set1_epi32(8));
        fwrap8(&cx, &cy, nv);
        _mm256_storeu_ps(q + i, fcell_8(im, p, 1, wmul, x0, y0));
    }
    for (r = 0; r < nr; r++)
        memcpy(Q + r * FIT_LAT_MAX, q + r * nc, (size_t)nc * sizeof(float));
}
#endif

/* Cells c0..c1 of a row of a grid inside the frame (fast: fcell5, else
 * fcell9), centres (u[2c] + xv, u[2c + 1] + yv). */
FIT_INLINE void frow_in(const fimg *im, const fpat *p, const float *u, float xv,
                        float yv, int c0, int c1, float *row, int fast)
{
    int c;
    for (c = c0; c <= c1; c++) {
        /* ffix without its clamps: the grid lies inside the frame */
        int32_t X = (int32_t)((u[2 * c] + xv) * FIX_ONE), Y = (int32_t)((u[2 * c + 1] + yv) * FIX_ONE);
        row[c] = fast ? (float)fcell5(im, p, 1, X, Y) * fit_norm5
                      : (float)fcell9(im, p, 1, X, Y) * fit_norm9;
    }
}

/* fcells() without SIMD. inside: the whole grid lies a pixel inside the
 * frame (else each cell chooses its sampler, fcell_edge). A cell centre is
 * (mx + ax u0) + bx v0: the first sum once a column, bx v0 once a row. */
static void fcells_on(const fimg *im, const fgrid *gr, int k, float *m, int inside, int skip)
{
    int cx, cy, n = k + 1;
    float g = 0.5f * (float)n, u[2 * (ACTAG_DECODE_MAX_K + 1)];
    fpat p;
    fpat_of(im, gr, im->fast, &p);
    for (cx = 0; cx < n; cx++) {
        float u0 = (float)cx + 0.5f - g;
        u[2 * cx] = gr->mx + gr->ax * u0;
        u[2 * cx + 1] = gr->my + gr->ay * u0;
    }
    for (cy = 0; cy < n; cy++) {
        float v0 = (float)cy + 0.5f - g, xv = gr->bx * v0, yv = gr->by * v0, *row = m + cy * n;
        /* erased data corners (skip) are not read */
        int c0 = skip && (cy == 0 || cy == k), c1 = k - c0;
        row[0] = row[k] = 0.0f;
        if (!inside) {
            for (cx = c0; cx <= c1; cx++)
                row[cx] = fcell_edge(im, &p, im->fast, u[2 * cx] + xv, u[2 * cx + 1] + yv);
        } else if (im->fast) { /* one loop per kind of cell: no tests per cell */
            frow_in(im, &p, u, xv, yv, c0, c1, row, 1);
        } else {
            frow_in(im, &p, u, xv, yv, c0, c1, row, 0);
        }
    }
}

/* Mean grey level of every cell of the (k+1)^2 grid over a 3x3 sample
 * pattern (+-so cell; im->fast: the centre and the 4 diagonal points),
 * m[cy * (k+1) + cx]. */
void actag__fit_cells(const fimg *im, const fgrid *gr, int k, float *m, int skip)
{
#if ACTAG__FIT_SIMD
    if (im->simd) { /* one copy of the loops per sampler (cl null or not) */
        fclamp cl;
        if (fgrid_inside(im, gr, k)) {
#if ACTAG__AVX2
            if (im->avx2) {
                fpat p;
                fpat_of(im, gr, im->fast, &p);
                fcells_avx2(im, gr, &p, k, m, skip, 0);
                return;
            }
#endif
            fcells_simd(im, gr, k, m, skip, NULL);
        } else if (im->cols >= 2) { /* fsample4_cl's column pair */
#if ACTAG__AVX2
            if (im->avx2 && im->rows >= 2) { /* fsample8_cl's rows */
                fpat p;
                fpat_of(im, gr, im->fast, &p);
                fcells_avx2(im, gr, &p, k, m, skip, 1);
                return;
            }
#endif
            fclamp_of(im, &cl);
            fcells_simd(im, gr, k, m, skip, &cl);
        } else {
            fcells_on(im, gr, k, m, 0, skip);
        }
        return;
    }
#endif
    /* two copies of the loops, one per sampler (constant inside) */
    if (fgrid_inside(im, gr, k))
        fcells_on(im, gr, k, m, 1, skip);
    else
        fcells_on(im, gr, k, m, 0, skip);
}

/* The 25 half-cell shifts (i/2, j/2 cells, i, j in -2..2) of grid gr, in
 * its own cell coordinates, put every cell centre on one half-cell lattice:
 * cell cx of shift i sits at lattice column 2 cx + i + 2. Each lattice point
 * is read once (5 samples), 4-5 times fewer reads than grid by grid. The
 * shifts of one parity class (pi = i & 1, pj = j & 1) use one quarter of the
 * lattice, (k+3-pi) x (k+3-pj) points: Q[r * FIT_LAT_MAX + c] is lattice
 * column 2c + pi, row 2r + pj. The sample points equal those of the shifted
 * grids up to the rounding of their coordinates. */
#if ACTAG__FIT_SIMD
/* flattice, four lattice points at a time in row order (the last group
 * repeats the last point in its spare lanes); cl: not inside. */
static void flattice_simd(const fimg *im, const fgrid *gr, int k, int pi, int pj, float *Q,
                          const fclamp *cl)
{
    int i, j, n = k + 1, nc = n + 2 - pi, nq = (n + 2 - pj) * nc, c = 0, r = 0;
    float g = 0.5f * (float)n;
    __m128i wmul = _mm_set1_epi32(1 | im->stride << 16);
    fpat p;
    fpat_of(im, gr, 1, &p); /* the lattice: 5 samples a cell */
    for (i = 0; i < nq; i += 4) {
        float xs[4], ys[4], q[4];
        int at[4];
        for (j = 0; j < 4; j++) {
            float u = (float)c + 0.5f * (float)pi - 0.5f - g;
            float v = (float)r + 0.5f * (float)pj - 0.5f - g;
            xs[j] = gr->mx + gr->ax * u + gr->bx * v;
            ys[j] = gr->my + gr->ay * u + gr->by * v;
            at[j] = r * FIT_LAT_MAX + c;
            if (i + j + 1 < nq && ++c == nc) {
                c = 0;
                r++;
            }
        }
        _mm_storeu_ps(q, fcell5_4(im, &p, cl, wmul, _mm_loadu_ps(xs), _mm_loadu_ps(ys)));
        for (j = 0; j < 4 && i + j < nq; j++)
            Q[at[j]] = q[j];
    }
}
#endif

void actag__fit_lattice(const fimg *im, const fgrid *gr, int k, int pi, int pj, float *Q)
{
    int c, r, n = k + 1, nc = n + 2 - pi;
    float g = 0.5f * (float)n, cu[2 * FIT_LAT_MAX];
    fpat p;
    /* the union of the shifted grids' sample points lies within g + 1 + so */
    int inside = fgrid_inside_h(im, gr, g + 1.0f + im->so);
#if ACTAG__FIT_SIMD
    if (im->simd && (inside || im->cols >= 2)) {
        fclamp cl;
#if ACTAG__AVX2
        if (inside && im->avx2) {
            fpat_of(im, gr, 1, &p); /* the lattice: 5 samples a cell */
            flattice_avx2(im, gr, &p, k, pi, pj, Q);
            return;
        }
#endif
        if (!inside)
            fclamp_of(im, &cl);
        flattice_simd(im, gr, k, pi, pj, Q, inside ? NULL : &cl);
        return;
    }
#endif
    fpat_of(im, gr, 1, &p); /* the lattice: 5 samples a cell */
    for (c = 0; c < nc; c++) { /* a point is (mx + ax u) + bx v: the first sum once a column */
        float u = (float)c + 0.5f * (float)pi - 0.5f - g;
        cu[2 * c] = gr->mx + gr->ax * u;
        cu[2 * c + 1] = gr->my + gr->ay * u;
    }
    for (r = 0; r < n + 2 - pj; r++) {
        float v = (float)r + 0.5f * (float)pj - 0.5f - g, xv = gr->bx * v, yv = gr->by * v;
        float *row = Q + r * FIT_LAT_MAX;
        if (inside) {
            frow_in(im, &p, cu, xv, yv, 0, nc - 1, row, 1);
            continue;
        }
        for (c = 0; c < nc; c++)
            row[c] = fcell_edge(im, &p, 1, cu[2 * c] + xv, cu[2 * c + 1] + yv);
    }
}

/* Cell means m of shift (i, j) from its parity class's lattice Q. */
void actag__fit_lattice_cells(const float *Q, int k, int i, int j, float *m)
{
    int cx, cy, n = k + 1, oi = (i + 2) >> 1, oj = (j + 2) >> 1;
    for (cy = 0; cy < n; cy++)
        for (cx = 0; cx < n; cx++)
            m[cy * n + cx] = Q[(cy + oj) * FIT_LAT_MAX + cx + oi];
}

/* The test hooks' sampler and grid: the frame, sample offset so (5
 * samples a cell, SIMD where the frame allows) and g = {mx, my, ax, ay,
 * bx, by}. */
static void fhook_setup(const uint8_t *img, int rows, int cols, int stride, float so,
                        const float g[6], fimg *im, fgrid *gr)
{
    im->img = img;
    im->rows = rows;
    im->cols = cols;
    im->stride = stride;
    im->so = so;
    im->fast = 1;
#if ACTAG__FIT_SIMD
    im->simd = actag__fit_simd_ok(rows, cols, stride);
    im->avx2 = actag__fit_avx2_reads();
#endif
    gr->mx = g[0];
    gr->my = g[1];
    gr->ax = g[2];
    gr->ay = g[3];
    gr->bx = g[4];
    gr->by = g[5];
}

/* Test hook (tests/test_decode_lattice.c): the cell means of grid g =
 * {mx, my, ax, ay, bx, by} shifted by (i/2, j/2) cells, from the lattice
 * (lat) and read directly (direct), 5 samples a cell. */
int actag__fit_shift_cells(const uint8_t *img, int rows, int cols, int stride, const float g[6],
                           int k, float so, int i, int j, float *lat, float *direct)
{
    fimg im;
    fgrid gr, t;
    float Q[FIT_LAT_MAX * FIT_LAT_MAX];
    if (k < 4 || k > ACTAG_DECODE_MAX_K || i < -2 || i > 2 || j < -2 || j > 2)
        return ACTAG_ERR_PARAM;
    fhook_setup(img, rows, cols, stride, so, g, &im, &gr);
    actag__fit_lattice(&im, &gr, k, i & 1, j & 1, Q);
    actag__fit_lattice_cells(Q, k, i, j, lat);
    t = gr;
    t.mx += 0.5f * ((float)i * gr.ax + (float)j * gr.bx);
    t.my += 0.5f * ((float)i * gr.ay + (float)j * gr.by);
    actag__fit_cells(&im, &t, k, direct, 0);
    return ACTAG_OK;
}

/* The straightforward cell read the scalar ones (fcells_on, flattice) must
 * equal bit for bit: every sample by the clamping fsample, its fixed-point
 * offsets formed per sample from the grid. */
static float fref_cell(const fimg *im, const fgrid *gr, float x0, float y0)
{
    int32_t X = ffix(x0), Y = ffix(y0), s = 0;
    int a, b;
    if (im->fast) {
        int32_t dx1 = ffix(im->so * (gr->ax + gr->bx)), dy1 = ffix(im->so * (gr->ay + gr->by));
        int32_t dx2 = ffix(im->so * (gr->ax - gr->bx)), dy2 = ffix(im->so * (gr->ay - gr->by));
        s = fsample(im, X, Y) + fsample(im, X + dx1, Y + dy1) + fsample(im, X - dx1, Y - dy1) +
            fsample(im, X + dx2, Y + dy2) + fsample(im, X - dx2, Y - dy2);
        return (float)s * fit_norm5;
    }
    for (b = 0; b < 3; b++)
        for (a = 0; a < 3; a++) {
            float u = (float)(a - 1) * im->so, w = (float)(b - 1) * im->so;
            s += fsample(im, X + ffix(gr->ax * u) + ffix(gr->bx * w), Y + ffix(gr->ay * u) + ffix(gr->by * w));
        }
    return (float)s * fit_norm9;
}

/* Test hook (tests/test_decode_lattice.c): decode_fit_test.h. */
int actag__fit_scalar_cells(const uint8_t *img, int rows, int cols, int stride, const float g[6],
                            int k, float so, int what, float *ref, float *scalar)
{
    fimg im;
    fgrid gr;
    float Q[FIT_LAT_MAX * FIT_LAT_MAX];
    int pi = what & 1, pj = (what >> 1) & 1, n = k + 1, r, c, nr, nc;
    float gc = 0.5f * (float)n;
    if (k < 4 || k > ACTAG_DECODE_MAX_K || what < 0 || what > 7 || what == 3 || rows < 1 ||
        cols < 1 || stride < cols)
        return ACTAG_ERR_PARAM;
    fhook_setup(img, rows, cols, stride, so, g, &im, &gr);
#if ACTAG__FIT_SIMD
    im.simd = 0;
    im.avx2 = 0;
#endif
    im.fast = what == 1 || what >= 4;
    nr = what < 4 ? n : n + 2 - pj;
    nc = what < 4 ? n : n + 2 - pi;
    for (r = 0; r < nr; r++)
        for (c = 0; c < nc; c++) {
            /* a cell (u0 = c + 1/2 - g) or a lattice point (c + pi/2 - 1/2 - g) */
            float u = what < 4 ? (float)c + 0.5f - gc : (float)c + 0.5f * (float)pi - 0.5f - gc;
            float v = what < 4 ? (float)r + 0.5f - gc : (float)r + 0.5f * (float)pj - 0.5f - gc;
            int corner = (c == 0 || c == k) && (r == 0 || r == k);
            ref[r * nc + c] = what == 2 && corner ? 0.0f
                              : fref_cell(&im, &gr, gr.mx + gr.ax * u + gr.bx * v,
                                          gr.my + gr.ay * u + gr.by * v);
        }
    if (what < 4) {
        actag__fit_cells(&im, &gr, k, scalar, what == 2);
        return ACTAG_OK;
    }
    memset(Q, 0xa5, sizeof Q);
    actag__fit_lattice(&im, &gr, k, pi, pj, Q);
    for (r = 0; r < nr; r++)
        for (c = 0; c < nc; c++)
            *scalar++ = Q[r * FIT_LAT_MAX + c];
    return ACTAG_OK;
}

/* Test hook (tests/test_decode_lattice.c): decode_fit_test.h. */
int actag__fit_dsp_reads(void)
{
    return FIT_DSP;
}

/* Test hook and the decoder's choice (decode_fit_test.h): the run-time
 * check is cheap, but fimg_of asks it once a decode. */
int actag__fit_avx2_reads(void)
{
#if ACTAG__AVX2
    return actag__cpu_avx2();
#else
    return 0;
#endif
}

#if ACTAG__FIT_SIMD
/* The portable cell reads, then the SIMD ones (avx2: with the AVX2 path);
 * 1 when that path read the grid (cells of a grid inside the frame or of
 * a frame of 2 rows and columns or more, a lattice inside), else 0. */
static int fsimd_hook(const uint8_t *img, int rows, int cols, int stride, const float g[6], int k,
                      float so, int what, int avx2, float *portable, float *simd)
{
    fimg im;
    fgrid gr;
    float Q[FIT_LAT_MAX * FIT_LAT_MAX];
    int pass, pi = what & 1, pj = (what >> 1) & 1, n = k + 1, r, c, inside;
    if (k < 4 || k > ACTAG_DECODE_MAX_K || what < 0 || what > 7 || what == 3 ||
        !actag__fit_simd_ok(rows, cols, stride) || (avx2 && !actag__fit_avx2_reads()))
        return ACTAG_ERR_PARAM;
    fhook_setup(img, rows, cols, stride, so, g, &im, &gr);
    im.fast = what == 1 || what >= 4;
    /* actag__fit_cells' and actag__fit_lattice's test of the grid */
    inside = what < 4 ? fgrid_inside(&im, &gr, k) : fgrid_inside_h(&im, &gr, 0.5f * (float)n + 1.0f + so);
    for (pass = 0; pass < 2; pass++) {
        float *out = pass ? simd : portable;
        im.simd = pass;
        im.avx2 = pass && avx2;
        if (what < 4) {
            actag__fit_cells(&im, &gr, k, out, what == 2);
            continue;
        }
        memset(Q, pass ? 0x5a : 0xa5, sizeof Q); /* no value left from the other pass */
        actag__fit_lattice(&im, &gr, k, pi, pj, Q);
        for (r = 0; r < n + 2 - pj; r++)
            for (c = 0; c < n + 2 - pi; c++)
                *out++ = Q[r * FIT_LAT_MAX + c];
    }
    /* (the AVX2 path reads cells of grids leaving frames of 2 rows and
     * columns or more too, lattices only inside) */
    return avx2 && (inside || (what < 4 && rows >= 2 && cols >= 2));
}

/* Test hooks (tests/test_decode_lattice.c): decode_fit_test.h. */
int actag__fit_simd_cells(const uint8_t *img, int rows, int cols, int stride, const float g[6],
                          int k, float so, int what, float *portable, float *simd)
{
    return fsimd_hook(img, rows, cols, stride, g, k, so, what, 0, portable, simd);
}

int actag__fit_avx2_cells(const uint8_t *img, int rows, int cols, int stride, const float g[6],
                          int k, float so, int what, float *portable, float *avx2)
{
    return fsimd_hook(img, rows, cols, stride, g, k, so, what, 1, portable, avx2);
}
#endif
