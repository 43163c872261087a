/* The grid-fit decoder's cell reads (fit_cells.h): the mean grey level of
 * every cell of an affine tag grid, by bilinear samples of the frame, and
 * the half-cell lattice the wide search's shifted grids share. Portable C,
 * with bit-identical SSE2 paths on x86-64 (tests/test_decode_lattice.c). */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "fit_cells.h"

#include <string.h>

#if ACTAG__FIT_SIMD
#include <emmintrin.h>
#endif

/* Forced inlining of the per-sample steps of the cell reads: GCC -O2 for
 * Cortex-M7 otherwise calls one sampler per sample with the choice of
 * sampler made at run time (about 50 instead of 35 instructions a sample). */
#if defined(__GNUC__)
#define FIT_INLINE __attribute__((always_inline)) static inline
#else
#define FIT_INLINE static inline
#endif

/* Bilinear grey level at (x, y), pixel centres on integers; edge pixels
 * are replicated outside the image. Only + - * decide it. Not inlined: the
 * cell reads take it only near the frame's edges. */
#if defined(__GNUC__)
__attribute__((noinline))
#endif
static float fsample(const fimg *im, float x, float y)
{
    int x0, y0, x1, y1;
    float fx, fy, v00, v01, v10, v11;
    const uint8_t *r0, *r1;
    if (!(x >= 0.0f))
        x = 0.0f;
    if (!(y >= 0.0f))
        y = 0.0f;
    if (x > (float)(im->cols - 1))
        x = (float)(im->cols - 1);
    if (y > (float)(im->rows - 1))
        y = (float)(im->rows - 1);
    x0 = (int)x;
    y0 = (int)y;
    fx = x - (float)x0;
    fy = y - (float)y0;
    x1 = x0 + 1 < im->cols ? x0 + 1 : x0;
    y1 = y0 + 1 < im->rows ? y0 + 1 : y0;
    r0 = im->img + (size_t)y0 * (size_t)im->stride;
    r1 = im->img + (size_t)y1 * (size_t)im->stride;
    v00 = (float)r0[x0];
    v01 = (float)r0[x1];
    v10 = (float)r1[x0];
    v11 = (float)r1[x1];
    v00 += (v01 - v00) * fx;
    v10 += (v11 - v10) * fx;
    return v00 + (v10 - v00) * fy;
}

/* A grid's sample pattern offsets, computed once a grid by the expressions
 * the cell reads used per cell (so the same floats): the 3x3 pattern's
 * offsets along a (ou, ov) and b (pu, pv), the 5-sample pattern's
 * diagonals (d1, d2). */
typedef struct fpat {
    float ou[3], ov[3], pu[3], pv[3];
    float dx1, dy1, dx2, dy2;
    /* a cell is read clamp-free when x0 - ex >= 1, x0 + ex <= xmax (and y):
     * its samples lie a pixel inside (fbox_inside, h = so) */
    float ex, ey, xmax, ymax;
    /* fsample_in's pixels (x0, y0), (x0 + 1, y0), (x0, y0 + 1), (x0 + 1, y0 + 1)
     * are r00[o] .. r11[o], o = y0 stride + x0: one address a sample */
    const uint8_t *r00, *r01, *r10, *r11;
} fpat;

/* fsample for a point known to lie in [0, cols-1) x [0, rows-1): the same
 * arithmetic without the clamps (the result is bit-identical there). */
FIT_INLINE float fsample_in(const fimg *im, const fpat *p, float x, float y)
{
    int x0 = (int)x, y0 = (int)y;
    float fx = x - (float)x0, fy = y - (float)y0, v00, v01, v10, v11;
    size_t o = (size_t)y0 * (size_t)im->stride + (size_t)x0;
    v00 = (float)p->r00[o];
    v01 = (float)p->r01[o];
    v10 = (float)p->r10[o];
    v11 = (float)p->r11[o];
    v00 += (v01 - v00) * fx;
    v10 += (v11 - v10) * fx;
    return v00 + (v10 - v00) * fy;
}

/* Do all points within h cells (along a and b) of (x, y) lie a pixel inside
 * the image? (Then fsample_in serves; the margin covers the rounding of the
 * points. NaN or infinite coordinates fail.) */
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

/* One grey sample: the clamp-free sampler when the whole grid (or cell)
 * lies a pixel inside the frame (bit-identical there, and cheaper). */
FIT_INLINE float fsample_at(const fimg *im, const fpat *p, int inside, float x, float y)
{
    return inside ? fsample_in(im, p, x, y) : fsample(im, x, y);
}

static void fpat_of(const fimg *im, const fgrid *gr, fpat *p)
{
    int a;
    for (a = 0; a < 3; a++) {
        float u = (float)(a - 1) * im->so;
        p->ou[a] = gr->ax * u;
        p->ov[a] = gr->ay * u;
        p->pu[a] = gr->bx * u;
        p->pv[a] = gr->by * u;
    }
    p->dx1 = im->so * (gr->ax + gr->bx);
    p->dy1 = im->so * (gr->ay + gr->by);
    p->dx2 = im->so * (gr->ax - gr->bx);
    p->dy2 = im->so * (gr->ay - gr->by);
    p->ex = ((gr->ax < 0.0f ? -gr->ax : gr->ax) + (gr->bx < 0.0f ? -gr->bx : gr->bx)) * im->so;
    p->ey = ((gr->ay < 0.0f ? -gr->ay : gr->ay) + (gr->by < 0.0f ? -gr->by : gr->by)) * im->so;
    p->xmax = (float)(im->cols - 2);
    p->ymax = (float)(im->rows - 2);
    p->r00 = p->r01 = p->r10 = p->r11 = im->img;
    if (im->rows >= 2 && im->cols >= 2) { /* else no cell lies a pixel inside: unused */
        p->r01 = im->img + 1;
        p->r10 = im->img + im->stride;
        p->r11 = im->img + im->stride + 1;
    }
}

/* The 5-sample mean (centre and the 4 diagonal points at +-so cell) of a
 * cell centred at (x0, y0), as fcells() reads it with im->fast. */
FIT_INLINE float fcell5(const fimg *im, const fpat *p, int inside, float x0, float y0)
{
    float s = fsample_at(im, p, inside, x0, y0) + fsample_at(im, p, inside, x0 + p->dx1, y0 + p->dy1) +
              fsample_at(im, p, inside, x0 - p->dx1, y0 - p->dy1) +
              fsample_at(im, p, inside, x0 + p->dx2, y0 + p->dy2) +
              fsample_at(im, p, inside, x0 - p->dx2, y0 - p->dy2);
    return s * 0.2f;
}

/* The 9-sample mean (3x3 pattern, +-so cell) of a cell centred at (x0, y0):
 * sample (a, b) at x0 + ou[a] + pu[b], summed b-major from 0. The a loop
 * written out keeps its sums in registers. */
FIT_INLINE float fcell9(const fimg *im, const fpat *p, int inside, float x0, float y0)
{
    float xa0 = x0 + p->ou[0], xa1 = x0 + p->ou[1], xa2 = x0 + p->ou[2];
    float ya0 = y0 + p->ov[0], ya1 = y0 + p->ov[1], ya2 = y0 + p->ov[2], s = 0.0f;
    int b;
    for (b = 0; b < 3; b++) {
        float pu = p->pu[b], pv = p->pv[b];
        s += fsample_at(im, p, inside, xa0 + pu, ya0 + pv);
        s += fsample_at(im, p, inside, xa1 + pu, ya1 + pv);
        s += fsample_at(im, p, inside, xa2 + pu, ya2 + pv);
    }
    return s * (1.0f / 9.0f);
}

/* One cell (fast: fcell5, else fcell9) of a grid that leaves the frame:
 * the clamp-free reads when the cell's samples (within so cell along a and
 * b of its centre) lie a pixel inside, the clamping ones otherwise. */
static float fcell_edge(const fimg *im, const fpat *p, int fast, float x0, float y0)
{
    if (x0 - p->ex >= 1.0f && x0 + p->ex <= p->xmax && y0 - p->ey >= 1.0f && y0 + p->ey <= p->ymax)
        return fast ? fcell5(im, p, 1, x0, y0) : fcell9(im, p, 1, x0, y0);
    return fast ? fcell5(im, p, 0, x0, y0) : fcell9(im, p, 0, x0, y0);
}

#if ACTAG__FIT_SIMD
/* x86-64 (SSE2): the reads of fcell5 and fcells_on four cells at
 * a time, one cell per lane. Every lane does exactly the scalar code's
 * float operations in the same order (vector addps / subps / mulps /
 * cvttps2dq / cvtdq2ps round per lane as the scalar SSE instructions do,
 * and fpmath.h rules out contraction), each cell's samples are summed in
 * the scalar order, so the cell means are bit-identical
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

/* The bilinear value of four points from their pixel pairs: lane i's row
 * pair starts at r0 + o[i] (bytes x0, x0 + 1) and r1 + q[i], fx and fy its
 * fractions; fsample's float operations in fsample's order. */
static inline __m128 flerp4(const uint8_t *r0, const int *o, const uint8_t *r1, const int *q,
                            __m128 fx, __m128 fy)
{
    __m128i byte = _mm_set1_epi32(0xff), w;
    __m128 v00, v01, v10, v11;
    /* lane i: bytes r0[x0], r0[x0 + 1], r1[x0], r1[x0 + 1] of its point */
    w = _mm_cvtsi32_si128(fld16(r0 + o[0]));
    w = _mm_insert_epi16(w, fld16(r1 + q[0]), 1);
    w = _mm_insert_epi16(w, fld16(r0 + o[1]), 2);
    w = _mm_insert_epi16(w, fld16(r1 + q[1]), 3);
    w = _mm_insert_epi16(w, fld16(r0 + o[2]), 4);
    w = _mm_insert_epi16(w, fld16(r1 + q[2]), 5);
    w = _mm_insert_epi16(w, fld16(r0 + o[3]), 6);
    w = _mm_insert_epi16(w, fld16(r1 + q[3]), 7);
    v00 = _mm_cvtepi32_ps(_mm_and_si128(w, byte));
    v01 = _mm_cvtepi32_ps(_mm_and_si128(_mm_srli_epi32(w, 8), byte));
    v10 = _mm_cvtepi32_ps(_mm_and_si128(_mm_srli_epi32(w, 16), byte));
    v11 = _mm_cvtepi32_ps(_mm_srli_epi32(w, 24));
    v00 = _mm_add_ps(v00, _mm_mul_ps(_mm_sub_ps(v01, v00), fx));
    v10 = _mm_add_ps(v10, _mm_mul_ps(_mm_sub_ps(v11, v10), fx));
    return _mm_add_ps(v00, _mm_mul_ps(_mm_sub_ps(v10, v00), fy));
}

/* fsample_in at four points (x, y) (wmul: 1 | stride << 16 per lane). Not
 * inlined: the 9 or 5 inlined copies of a cell read spill many vectors
 * (GCC 12 -O3: a 736-byte frame for fcells_simd, 496 without, same speed). */
#if defined(__GNUC__)
__attribute__((noinline))
#endif
static __m128 fsample4_in(const fimg *im, __m128i wmul, __m128 x, __m128 y)
{
    __m128i xi = _mm_cvttps_epi32(x), yi = _mm_cvttps_epi32(y);
    __m128 fx = _mm_sub_ps(x, _mm_cvtepi32_ps(xi)), fy = _mm_sub_ps(y, _mm_cvtepi32_ps(yi));
    const uint8_t *p = im->img;
    size_t st = (size_t)im->stride;
    int o[4];
    _mm_storeu_si128((__m128i *)(void *)o, _mm_madd_epi16(_mm_or_si128(xi, _mm_slli_epi32(yi, 16)), wmul));
    return flerp4(p, o, p + st, o, fx, fy);
}

/* fsample (the clamping sampler) at four points, for grids that leave the
 * frame; cols >= 2. The clamps are fsample's comparisons (cmpge maps NaN
 * to 0 as !(x >= 0) does; minps(c, x) is x > c ? c : x). The row pair is
 * y0, y1 = min(y0 + 1, rows - 1). For the column pair, loaded as two
 * adjacent bytes, x0 = cols - 1 (only at x = cols - 1, fx = 0) becomes
 * x0 = cols - 2, fx = 1: v00 + (v01 - v00) * 1 is then v01 = r[cols - 1]
 * exactly (small integers), as fsample's v00 + (v01 - v00) * 0 is v00, so
 * the row values, and the result, are bit-identical and no load leaves the
 * frame. */
typedef struct fclamp { /* fsample4_cl's limits, set once a grid (fclamp_of) */
    __m128 xmax, ymax;    /* cols - 1, rows - 1 */
    __m128i x0max, y0max; /* cols - 2, rows - 1 */
} fclamp;

static void fclamp_of(const fimg *im, fclamp *cl)
{
    cl->xmax = _mm_set1_ps((float)(im->cols - 1));
    cl->ymax = _mm_set1_ps((float)(im->rows - 1));
    cl->x0max = _mm_set1_epi32(im->cols - 2);
    cl->y0max = _mm_set1_epi32(im->rows - 1);
}

#if defined(__GNUC__)
__attribute__((noinline))
#endif
static __m128 fsample4_cl(const fimg *im, const fclamp *cl, __m128i wmul, __m128 x, __m128 y)
{
    __m128 zero = _mm_setzero_ps(), fx, fy;
    __m128i xi, yi, y1;
    const uint8_t *p = im->img;
    int o[4], q[4];
    x = _mm_and_ps(_mm_cmpge_ps(x, zero), x);
    y = _mm_and_ps(_mm_cmpge_ps(y, zero), y);
    x = _mm_min_ps(cl->xmax, x);
    y = _mm_min_ps(cl->ymax, y);
    xi = _mm_cvttps_epi32(x);
    yi = _mm_cvttps_epi32(y);
    /* x0 at most cols - 2 (signed compare: 0 <= x0 < cols) */
    xi = _mm_add_epi32(xi, _mm_cmpgt_epi32(xi, cl->x0max));
    /* y1 = y0 + 1 where y0 + 1 < rows */
    y1 = _mm_sub_epi32(yi, _mm_cmplt_epi32(yi, cl->y0max));
    fx = _mm_sub_ps(x, _mm_cvtepi32_ps(xi));
    fy = _mm_sub_ps(y, _mm_cvtepi32_ps(yi));
    _mm_storeu_si128((__m128i *)(void *)o, _mm_madd_epi16(_mm_or_si128(xi, _mm_slli_epi32(yi, 16)), wmul));
    _mm_storeu_si128((__m128i *)(void *)q, _mm_madd_epi16(_mm_or_si128(xi, _mm_slli_epi32(y1, 16)), wmul));
    return flerp4(p, o, p, q, fx, fy);
}

/* The SIMD counterpart of fsample_at (cl: the grid leaves the frame). */
static inline __m128 fsample4(const fimg *im, const fclamp *cl, __m128i wmul, __m128 x, __m128 y)
{
    return cl ? fsample4_cl(im, cl, wmul, x, y) : fsample4_in(im, wmul, x, y);
}

/* fcell5 of four cells centred at (x0, y0). */
static inline __m128 fcell5_4(const fimg *im, const fgrid *gr, const fclamp *cl, __m128i wmul,
                              __m128 x0, __m128 y0)
{
    __m128 dx1 = _mm_set1_ps(im->so * (gr->ax + gr->bx)), dy1 = _mm_set1_ps(im->so * (gr->ay + gr->by));
    __m128 dx2 = _mm_set1_ps(im->so * (gr->ax - gr->bx)), dy2 = _mm_set1_ps(im->so * (gr->ay - gr->by));
    __m128 s = fsample4(im, cl, wmul, x0, y0);
    s = _mm_add_ps(s, fsample4(im, cl, wmul, _mm_add_ps(x0, dx1), _mm_add_ps(y0, dy1)));
    s = _mm_add_ps(s, fsample4(im, cl, wmul, _mm_sub_ps(x0, dx1), _mm_sub_ps(y0, dy1)));
    s = _mm_add_ps(s, fsample4(im, cl, wmul, _mm_add_ps(x0, dx2), _mm_add_ps(y0, dy2)));
    s = _mm_add_ps(s, fsample4(im, cl, wmul, _mm_sub_ps(x0, dx2), _mm_sub_ps(y0, dy2)));
    return _mm_mul_ps(s, _mm_set1_ps(0.2f));
}

/* fcells_on(im, gr, k, m, !cl, skip), four cells at a time in row order
 * (the last group repeats the last cell in its spare lanes). Lane counters
 * cx, cy step by 4 cells, wrapping at most once a row as n >= 5. */
static inline void fcells_simd(const fimg *im, const fgrid *gr, int k, float *m, int skip,
                               const fclamp *cl)
{
    int i, j, a, b, n = k + 1, nn = n * n;
    float g = 0.5f * (float)n;
    __m128 ou[3], ov[3], pu[3], pv[3];
    __m128 half = _mm_set1_ps(0.5f), gv = _mm_set1_ps(g);
    __m128 mx = _mm_set1_ps(gr->mx), my = _mm_set1_ps(gr->my);
    __m128 ax = _mm_set1_ps(gr->ax), ay = _mm_set1_ps(gr->ay);
    __m128 bx = _mm_set1_ps(gr->bx), by = _mm_set1_ps(gr->by);
    __m128i wmul = _mm_set1_epi32(1 | im->stride << 16);
    __m128i cx = _mm_setr_epi32(0, 1, 2, 3), cy = _mm_setzero_si128();
    __m128i nv = _mm_set1_epi32(n), last = _mm_set1_epi32(n - 1), four = _mm_set1_epi32(4);
    for (a = 0; a < 3; a++) {
        float u = (float)(a - 1) * im->so;
        ou[a] = _mm_set1_ps(gr->ax * u);
        ov[a] = _mm_set1_ps(gr->ay * u);
        pu[a] = _mm_set1_ps(gr->bx * u);
        pv[a] = _mm_set1_ps(gr->by * u);
    }
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
            s = fcell5_4(im, gr, cl, wmul, x0, y0);
        } else {
            __m128 xa[3], ya[3]; /* x0 + ou[a], as the scalar sum's first step */
            for (a = 0; a < 3; a++) {
                xa[a] = _mm_add_ps(x0, ou[a]);
                ya[a] = _mm_add_ps(y0, ov[a]);
            }
            s = _mm_setzero_ps();
            for (b = 0; b < 3; b++)
                for (a = 0; a < 3; a++)
                    s = _mm_add_ps(s, fsample4(im, cl, wmul, _mm_add_ps(xa[a], pu[b]),
                                               _mm_add_ps(ya[a], pv[b])));
            s = _mm_mul_ps(s, _mm_set1_ps(1.0f / 9.0f));
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

/* Cells c0..c1 of a row of a grid inside the frame (fast: fcell5, else
 * fcell9), centres (xu[c] + xv, yu[c] + yv). */
FIT_INLINE void frow_in(const fimg *im, const fpat *p, const float *xu, const float *yu, float xv,
                        float yv, int c0, int c1, float *row, int fast)
{
    int c;
    for (c = c0; c <= c1; c++)
        row[c] = fast ? fcell5(im, p, 1, xu[c] + xv, yu[c] + yv)
                      : fcell9(im, p, 1, xu[c] + xv, yu[c] + yv);
}

/* fcells() without SIMD. inside: the whole grid lies a pixel inside the
 * frame (else each cell chooses its sampler, fcell_edge). A cell centre is
 * (mx + ax u0) + bx v0: the first sum once a column, bx v0 once a row. */
static void fcells_on(const fimg *im, const fgrid *gr, int k, float *m, int inside, int skip)
{
    int cx, cy, n = k + 1;
    float g = 0.5f * (float)n, xu[ACTAG_DECODE_MAX_K + 1], yu[ACTAG_DECODE_MAX_K + 1];
    fpat p;
    fpat_of(im, gr, &p);
    for (cx = 0; cx < n; cx++) {
        float u0 = (float)cx + 0.5f - g;
        xu[cx] = gr->mx + gr->ax * u0;
        yu[cx] = gr->my + gr->ay * u0;
    }
    for (cy = 0; cy < n; cy++) {
        float v0 = (float)cy + 0.5f - g, xv = gr->bx * v0, yv = gr->by * v0, *row = m + cy * n;
        /* erased data corners (skip) are not read */
        int c0 = skip && (cy == 0 || cy == k), c1 = k - c0;
        row[0] = row[k] = 0.0f;
        if (!inside) {
            for (cx = c0; cx <= c1; cx++)
                row[cx] = fcell_edge(im, &p, im->fast, xu[cx] + xv, yu[cx] + yv);
        } else if (im->fast) { /* one loop per kind of cell: no tests per cell */
            frow_in(im, &p, xu, yu, xv, yv, c0, c1, row, 1);
        } else {
            frow_in(im, &p, xu, yu, xv, yv, c0, c1, row, 0);
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
            fcells_simd(im, gr, k, m, skip, NULL);
        } else if (im->cols >= 2) { /* fsample4_cl's column pair */
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
        _mm_storeu_ps(q, fcell5_4(im, gr, cl, wmul, _mm_loadu_ps(xs), _mm_loadu_ps(ys)));
        for (j = 0; j < 4 && i + j < nq; j++)
            Q[at[j]] = q[j];
    }
}
#endif

void actag__fit_lattice(const fimg *im, const fgrid *gr, int k, int pi, int pj, float *Q)
{
    int c, r, n = k + 1, nc = n + 2 - pi;
    float g = 0.5f * (float)n, xu[FIT_LAT_MAX], yu[FIT_LAT_MAX];
    fpat p;
    /* the union of the shifted grids' sample points lies within g + 1 + so */
    int inside = fgrid_inside_h(im, gr, g + 1.0f + im->so);
#if ACTAG__FIT_SIMD
    if (im->simd && (inside || im->cols >= 2)) {
        fclamp cl;
        if (!inside)
            fclamp_of(im, &cl);
        flattice_simd(im, gr, k, pi, pj, Q, inside ? NULL : &cl);
        return;
    }
#endif
    fpat_of(im, gr, &p);
    for (c = 0; c < nc; c++) { /* a point is (mx + ax u) + bx v: the first sum once a column */
        float u = (float)c + 0.5f * (float)pi - 0.5f - g;
        xu[c] = gr->mx + gr->ax * u;
        yu[c] = gr->my + gr->ay * u;
    }
    for (r = 0; r < n + 2 - pj; r++) {
        float v = (float)r + 0.5f * (float)pj - 0.5f - g, xv = gr->bx * v, yv = gr->by * v;
        float *row = Q + r * FIT_LAT_MAX;
        if (inside) {
            frow_in(im, &p, xu, yu, xv, yv, 0, nc - 1, row, 1);
            continue;
        }
        for (c = 0; c < nc; c++)
            row[c] = fcell_edge(im, &p, 1, xu[c] + xv, yu[c] + yv);
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
 * equal bit for bit: every sample by the clamping fsample, the offsets and
 * the sums written per sample as the decoder first had them. */
static float fref_cell(const fimg *im, const fgrid *gr, float x0, float y0)
{
    float s = 0.0f;
    int a, b;
    if (im->fast) {
        float dx1 = im->so * (gr->ax + gr->bx), dy1 = im->so * (gr->ay + gr->by);
        float dx2 = im->so * (gr->ax - gr->bx), dy2 = im->so * (gr->ay - gr->by);
        s = fsample(im, x0, y0) + fsample(im, x0 + dx1, y0 + dy1) + fsample(im, x0 - dx1, y0 - dy1) +
            fsample(im, x0 + dx2, y0 + dy2) + fsample(im, x0 - dx2, y0 - dy2);
        return s * 0.2f;
    }
    for (b = 0; b < 3; b++)
        for (a = 0; a < 3; a++) {
            float u = (float)(a - 1) * im->so, w = (float)(b - 1) * im->so;
            s += fsample(im, x0 + gr->ax * u + gr->bx * w, y0 + gr->ay * u + gr->by * w);
        }
    return s * (1.0f / 9.0f);
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

#if ACTAG__FIT_SIMD
/* Test hook (tests/test_decode_lattice.c): decode_fit_test.h. */
int actag__fit_simd_cells(const uint8_t *img, int rows, int cols, int stride, const float g[6],
                          int k, float so, int what, float *portable, float *simd)
{
    fimg im;
    fgrid gr;
    float Q[FIT_LAT_MAX * FIT_LAT_MAX];
    int pass, pi = what & 1, pj = (what >> 1) & 1, n = k + 1, r, c;
    if (k < 4 || k > ACTAG_DECODE_MAX_K || what < 0 || what > 7 || what == 3 ||
        !actag__fit_simd_ok(rows, cols, stride))
        return ACTAG_ERR_PARAM;
    fhook_setup(img, rows, cols, stride, so, g, &im, &gr);
    im.fast = what == 1 || what >= 4;
    for (pass = 0; pass < 2; pass++) {
        float *out = pass ? simd : portable;
        im.simd = pass;
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
    return ACTAG_OK;
}
#endif
