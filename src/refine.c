/* Sub-pixel corners of a decoded tag: the known template fitted to the grey
 * image by Gauss-Newton over the tag's grid (see actag/refine.h). */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/refine.h"
#include "actag/decode.h"
#include "frame16.h"
#include "refine_frame.h"
#include "refine_probe.h"
#include "trig.h"

#include <string.h>

/* x86 (SSE2): the sweeps' grid offsets for eight lattice rows side by side
 * (rwblock) and their normal equations four sums a vector (rflush4), the
 * scalar operations lane by lane (bit-identical; test_refine compares).
 * Every other target (Cortex-M) keeps the scalar code. */
#if defined(__SSE2__) && !defined(ACTAG_NO_SIMD)
#define RSSE2 1
#include <emmintrin.h>
#else
#define RSSE2 0
#endif

#ifdef REFINE_DEBUG
#include <stdio.h>
#define DBG(...) fprintf(stderr, __VA_ARGS__)
#else
#define DBG(...) ((void)0)
#endif

/* Convergence: no corner moves by more than this many cells (pass 1: the
 * basin; pass 2: the corners; the steps shrink at least twofold, so the
 * corners stop within about this much of the fit's minimum). */
#define RTOL1 0.03f
#define RTOL2 0.003f
/* Sparser lattices: pass 1 and the levels keep at least this many pixels
 * (every sub-th lattice row and column, sub 1..4). */
#define RSUB1 250
#define RSUBL 300
#define RK_MAX ACTAG_DECODE_MAX_K
#define RN_MAX (RK_MAX + 1)

void actag_refine_params_default(actag_refine_params *rp)
{
    if (rp == NULL)
        return;
    rp->blur = 2.0f;
    rp->margin = 0.3f;
    rp->max_iterations = 8;
    rp->max_shift = 1.0f;
    rp->max_samples = 6000;
}

/* The grid: the point of grid offset w = (u - g, v - g) lies at
 *   F(w) = m + M w + e1 (w' Q w) / (2 |m|)
 * in the plane coordinates (X, Y) of the fan: X toward the tag along the
 * centre beam, Y across it (metres; pixels without a geometry, Q = 0).
 * p = (m1, m2, M11, M21, M12, M22): M's columns are the cell vectors. */
typedef struct rgrid {
    float p[6];
    float Q[3]; /* Q11, Q12, Q22 */
    float r0;   /* |m| */
    /* for dQ/dM: qcase 0 (Q = 0), 1 (Q = cell^2 I - M'M), 2 (its positive
     * part l1 v v', v[] a unit vector, kap = l1 / (l1 - l2)) */
    int qcase;
    float v[2], kap;
} rgrid;

#define RROW_MAX 128 /* lattice rows */
#define RCOL_MAX 255 /* lattice columns (uint8_t intervals) */
#define RL_PAD (RN_MAX + 2) /* the layout with a ring of zero cells */
#define RDIR_MAX 128 /* lattice columns whose directions are cached (stack) */

typedef struct rctx {
    const uint8_t *img;              /* 8- or 16-bit pixels (bytes) */
    int depth;                       /* 8 or 16 */
    uint32_t max16;                  /* 16-bit: the image's maximum (0: all 0) */
    int rows, cols, stride;
    const actag_sonar_geometry *geo; /* NULL: plane = pixels */
    float ac;                        /* azimuth of the centre beam */
    float cell2;                     /* squared cell side, m^2 (0: no curvature) */
    int n;                           /* k + 1 cells per side */
    float g;                         /* grid centre, cells */
    float Lp[RL_PAD * RL_PAD];       /* layout, cell (u, v) at [(v + 1) RL_PAD + u + 1] */
    int x0, y0, x1, y1, step;        /* the pixel lattice */
    int nrow;                        /* lattice rows */
    uint8_t ja[RROW_MAX], jb[RROW_MAX]; /* each lattice row's members: columns ja..jb */
    rgrid G0;                        /* the start grid: decides the pixel set */
    float lo, hi;                    /* grid range of the pixel set */
    float wu, wv;                    /* template edge half-widths, cells */
    float iwu, iwv;                  /* their inverses */
    float rx, ry, ra[4];             /* level ramps: (u', v') = ra (X - rx, Y - ry) */
    int ndir;                        /* lattice columns 0..ndir-1 have dir[] (all near
                                        enough the centre beam) */
    float dir[2 * RDIR_MAX];         /* their cos, sin off the centre beam (rcolumn_dir) */
} rctx;

static int finite_f(float x) { return x == x && x - x == 0.0f; }

/* Forced inlining of the sweeps' per-pixel steps: GCC -O2 for Cortex-M7
 * otherwise calls some per pixel, and every call spills the sweep's
 * constants (floats held in caller-saved registers) to the stack.
 * RUNLIKELY marks a sweep's rare branches (a column past the direction
 * cache, a full batch for rflush). */
#if defined(__GNUC__)
#define RINLINE __attribute__((always_inline)) static inline
#define RUNLIKELY(x) __builtin_expect(!!(x), 0)
#else
#define RINLINE static inline
#define RUNLIKELY(x) (x)
#endif

/* A 16-bit pixel on the detector's 8-bit scale (actag.h: 16-bit frames are
 * scaled by their maximum, rounded), so a 16-bit frame refines exactly as
 * its 8-bit conversion does. */
static uint32_t rscale16(const struct rctx *c, const uint8_t *p)
{
    return c->max16 ? (frame16_load(p) * 255u + c->max16 / 2u) / c->max16 : 0u;
}

/* Fan-plane coordinates of pixel (x, y); 0 when too far off the centre beam. */
static int rplane(const rctx *c, float x, float y, float *X, float *Y)
{
    float r, d, sn, cs;
    if (c->geo == NULL) {
        *X = x;
        *Y = y;
        return 1;
    }
    r = actag_geometry_range(c->geo, c->rows, y);
    d = actag_geometry_azimuth(c->geo, c->cols, x) - c->ac;
    if (!(d >= -0.6f && d <= 0.6f))
        return 0;
    actag__sincos_small(d, &sn, &cs);
    *X = r * cs;
    *Y = r * sn;
    return 1;
}

/* Pixel of fan-plane point (X, Y). */
static void rpixel(const rctx *c, float X, float Y, actag_point *p)
{
    float r, a;
    if (c->geo == NULL) {
        p->x = X;
        p->y = Y;
        return;
    }
    r = actag_sqrtf(X * X + Y * Y);
    a = c->ac + actag__atan_small(Y / X);
    p->x = actag_geometry_column(c->geo, c->cols, a);
    p->y = actag_geometry_row(c->geo, c->rows, r);
}

/* Q = cell^2 I - M'M, made positive semi-definite: w'Qw is the squared
 * out-of-fan (elevation) extent of grid offset w, which a tag of known size
 * needs beside its in-fan extent M w. */
static void rcurv(const rctx *c, rgrid *G)
{
    float a11, a12, a22, h, t, dsc, l1, l2;
    G->r0 = actag_sqrtf(G->p[0] * G->p[0] + G->p[1] * G->p[1]);
    G->Q[0] = G->Q[1] = G->Q[2] = 0.0f;
    G->qcase = 0;
    if (c->cell2 <= 0.0f || !(G->r0 > 0.0f))
        return;
    a11 = c->cell2 - (G->p[2] * G->p[2] + G->p[3] * G->p[3]);
    a12 = -(G->p[2] * G->p[4] + G->p[3] * G->p[5]);
    a22 = c->cell2 - (G->p[4] * G->p[4] + G->p[5] * G->p[5]);
    h = 0.5f * (a11 - a22);
    t = 0.5f * (a11 + a22);
    dsc = actag_sqrtf(h * h + a12 * a12);
    l1 = t + dsc; /* larger eigenvalue */
    l2 = t - dsc;
    if (l1 <= 0.0f)
        return;
    if (l2 >= 0.0f) {
        G->Q[0] = a11;
        G->Q[1] = a12;
        G->Q[2] = a22;
        G->qcase = 1;
        return;
    }
    /* keep the positive part: l1 v v' */
    {
        float vx = a12, vy = l1 - a11, nv;
        if (h > 0.0f) {
            vx = l1 - a22;
            vy = a12;
        }
        nv = vx * vx + vy * vy;
        if (!(nv > 0.0f))
            return;
        G->Q[0] = l1 * vx * vx / nv;
        G->Q[1] = l1 * vx * vy / nv;
        G->Q[2] = l1 * vy * vy / nv;
        nv = actag_sqrtf(nv);
        G->v[0] = vx / nv;
        G->v[1] = vy / nv;
        G->kap = l1 / (l1 - l2);
        G->qcase = 2;
    }
}

/* Grid offset w of plane point (X, Y), and K^-1, K = dF/dw at w.
 * 0 when singular. */
static int rinvert(const rgrid *G, float X, float Y, float w[2], float Ki[4])
{
    float dx = X - G->p[0], dy = Y - G->p[1], det, inv[4];
    float k11 = G->p[2], k12 = G->p[4], k21 = G->p[3], k22 = G->p[5];
    int it;
    det = k11 * k22 - k12 * k21;
    if (!finite_f(det) || det == 0.0f)
        return 0;
    inv[0] = k22 / det;
    inv[1] = -k12 / det;
    inv[2] = -k21 / det;
    inv[3] = k11 / det;
    w[0] = inv[0] * dx + inv[1] * dy;
    w[1] = inv[2] * dx + inv[3] * dy;
    if (G->Q[0] == 0.0f && G->Q[1] == 0.0f && G->Q[2] == 0.0f) {
        memcpy(Ki, inv, sizeof inv);
        return 1;
    }
    for (it = 0; it < 3; it++) { /* w = M^-1 (d - e1 q(w)) */
        float q = (w[0] * (G->Q[0] * w[0] + G->Q[1] * w[1]) +
                   w[1] * (G->Q[1] * w[0] + G->Q[2] * w[1])) / (2.0f * G->r0);
        w[0] = inv[0] * (dx - q) + inv[1] * dy;
        w[1] = inv[2] * (dx - q) + inv[3] * dy;
    }
    /* K = M + e1 (Q w / r0)' */
    k11 += (G->Q[0] * w[0] + G->Q[1] * w[1]) / G->r0;
    k12 += (G->Q[1] * w[0] + G->Q[2] * w[1]) / G->r0;
    det = k11 * k22 - k12 * k21;
    if (!finite_f(det) || det == 0.0f)
        return 0;
    Ki[0] = k22 / det;
    Ki[1] = -k12 / det;
    Ki[2] = -k21 / det;
    Ki[3] = k11 / det;
    return 1;
}

static void rforward(const rgrid *G, float w0, float w1, float *X, float *Y)
{
    float q = G->r0 > 0.0f ? (w0 * (G->Q[0] * w0 + G->Q[1] * w1) +
                              w1 * (G->Q[1] * w0 + G->Q[2] * w1)) / (2.0f * G->r0)
                           : 0.0f;
    *X = G->p[0] + G->p[2] * w0 + G->p[4] * w1 + q;
    *Y = G->p[1] + G->p[3] * w0 + G->p[5] * w1;
}

/* The plane -> grid inverse of a grid, its per-grid constants:
 *   w = M^-1 (d - e1 q(w)),  d = (X, Y) - m,  q(w) = w'Qw / (2 r0),
 * solved by 3 fixed-point steps from the affine w (as rinvert), and the
 * Jacobian K = dF/dw = M + e1 (Q w / r0)'. */
typedef struct rmap {
    float m0, m1, inv[4];   /* m, M^-1 */
    float qa, qb, qc;       /* Q / (2 r0) */
    float ka, kb, kc;       /* Q / r0 */
    float k11, k12, k21, k22, idet; /* K and 1/det K when flat (no Q) */
    int curved;
    /* dq/dp (q = w'Qw / (2 r0)): dq/dm = -q m / r0^2; d(w'Qw)/dM = -2 M Gw,
     * Gw = w w' (qcase 1) or s^2 v v' + kap s t (u v' + v u') (qcase 2,
     * s = v'w, t = u'w, u = v turned 90 degrees) */
    int qcase;
    float mr0, mr1;         /* m / r0^2 */
    float M[4], ir0;        /* M11, M21, M12, M22; 1 / r0 */
    float v[2], u[2], kap, Mv[2], Mu[2];
} rmap;

RINLINE int rmap_init(const rgrid *G, rmap *q)
{
    float det = G->p[2] * G->p[5] - G->p[4] * G->p[3];
    memset(q, 0, sizeof *q); /* the curvature's fields too when flat (unread) */
    if (!finite_f(det) || det == 0.0f)
        return 0;
    q->m0 = G->p[0];
    q->m1 = G->p[1];
    q->inv[0] = G->p[5] / det;
    q->inv[1] = -G->p[4] / det;
    q->inv[2] = -G->p[3] / det;
    q->inv[3] = G->p[2] / det;
    q->k11 = G->p[2];
    q->k12 = G->p[4];
    q->k21 = G->p[3];
    q->k22 = G->p[5];
    q->idet = 1.0f / det;
    q->curved = !(G->Q[0] == 0.0f && G->Q[1] == 0.0f && G->Q[2] == 0.0f);
    q->qa = q->qb = q->qc = q->ka = q->kb = q->kc = 0.0f;
    q->qcase = q->curved ? G->qcase : 0;
    if (q->curved) {
        int i;
        q->ir0 = 1.0f / G->r0;
        q->mr0 = G->p[0] * q->ir0 * q->ir0;
        q->mr1 = G->p[1] * q->ir0 * q->ir0;
        for (i = 0; i < 4; i++)
            q->M[i] = G->p[2 + i];
        q->v[0] = G->v[0];
        q->v[1] = G->v[1];
        q->u[0] = -G->v[1];
        q->u[1] = G->v[0];
        q->kap = G->kap;
        q->Mv[0] = q->M[0] * q->v[0] + q->M[2] * q->v[1];
        q->Mv[1] = q->M[1] * q->v[0] + q->M[3] * q->v[1];
        q->Mu[0] = q->M[0] * q->u[0] + q->M[2] * q->u[1];
        q->Mu[1] = q->M[1] * q->u[0] + q->M[3] * q->u[1];
        float h = 0.5f / G->r0, k = 1.0f / G->r0;
        q->qa = G->Q[0] * h;
        q->qb = G->Q[1] * h;
        q->qc = G->Q[2] * h;
        q->ka = G->Q[0] * k;
        q->kb = G->Q[1] * k;
        q->kc = G->Q[2] * k;
    }
    return 1;
}

/* Grid offset w of plane point (X, Y): the fixed point t = q(w),
 * w = M^-1 (d - e1 t), iterated nit times from t0 (0, or a neighbour's t:
 * the curvature changes little from pixel to pixel). Returns the last t. */
RINLINE float rmap_w(const rmap *q, float X, float Y, float w[2], float t0, int nit)
{
    float dx = X - q->m0, dy = Y - q->m1;
    float a0 = q->inv[0] * dx + q->inv[1] * dy, a1 = q->inv[2] * dx + q->inv[3] * dy;
    float w0 = a0, w1 = a1, t = 0.0f;
    if (q->curved) {
        int it;
        w0 = a0 - t0 * q->inv[0];
        w1 = a1 - t0 * q->inv[2];
        for (it = 0; it < nit; it++) {
            t = w0 * (q->qa * w0 + q->qb * w1) + w1 * (q->qb * w0 + q->qc * w1);
            w0 = a0 - t * q->inv[0];
            w1 = a1 - t * q->inv[2];
        }
    }
    w[0] = w0;
    w[1] = w1;
    return t;
}

/* The sweep's rmap_w: 2 steps from t0 (unrolled), or at a row's first
 * pixel 3 from 0, whose first step gives the t the other two start from. */
RINLINE float rmap_wrow(const rmap *q, float X, float Y, float t0, int first, float *pw0,
                        float *pw1)
{
    float dx = X - q->m0, dy = Y - q->m1;
    float a0 = q->inv[0] * dx + q->inv[1] * dy, a1 = q->inv[2] * dx + q->inv[3] * dy;
    float w0 = a0, w1 = a1, t = 0.0f;
    if (q->curved) {
        if (first) {
            w0 = a0 - 0.0f * q->inv[0];
            w1 = a1 - 0.0f * q->inv[2];
            t0 = w0 * (q->qa * w0 + q->qb * w1) + w1 * (q->qb * w0 + q->qc * w1);
        }
        w0 = a0 - t0 * q->inv[0];
        w1 = a1 - t0 * q->inv[2];
        t = w0 * (q->qa * w0 + q->qb * w1) + w1 * (q->qb * w0 + q->qc * w1);
        w0 = a0 - t * q->inv[0];
        w1 = a1 - t * q->inv[2];
        t = w0 * (q->qa * w0 + q->qb * w1) + w1 * (q->qb * w0 + q->qc * w1);
        w0 = a0 - t * q->inv[0];
        w1 = a1 - t * q->inv[2];
    }
    *pw0 = w0;
    *pw1 = w1;
    return t;
}

/* cos and sin of lattice column j's azimuth off the centre beam; returns
 * 0 (cos -1) when the column is too far off it. Needs the geometry. */
static int rcolumn_dir(const rctx *c, int j, float *cs, float *sn)
{
    float d = actag_geometry_azimuth(c->geo, c->cols, (float)(c->x0 + j * c->step)) - c->ac;
    if (!(d >= -0.6f && d <= 0.6f)) {
        *cs = -1.0f;
        *sn = 0.0f;
        return 0;
    }
    actag__sincos_small(d, sn, cs);
    return 1;
}

/* Fan-plane point of lattice row (range r or pixel row y) and column j
 * (x0 + j step): the column's direction from the cache where it holds it
 * (the same floats rcolumn_dir gives; columns 0..ndir-1, all near enough
 * the centre beam: ndir is 0 without a geometry). */
RINLINE int rlattice_plane(const rctx *c, float rr, int j, float *X, float *Y)
{
    float sn, cs;
    if (j < c->ndir) {
        cs = c->dir[2 * j];
        sn = c->dir[2 * j + 1];
    } else if (c->geo == NULL) {
        *X = (float)(c->x0 + j * c->step);
        *Y = rr;
        return 1;
    } else if (!rcolumn_dir(c, j, &cs, &sn)) {
        return 0;
    }
    *X = rr * cs;
    *Y = rr * sn;
    return 1;
}

/* Range of pixel row y (or y itself without a geometry). */
static float rrange(const rctx *c, int y)
{
    return c->geo == NULL ? (float)y : actag_geometry_range(c->geo, c->rows, (float)y);
}

/* Is lattice point (column j, range rr) in the pixel set: its grid
 * position under the start grid within [lo, hi] in u and v. */
static int rmember(const rctx *c, const rmap *q0, float rr, int j)
{
    float X, Y, w[2];
    if (!rlattice_plane(c, rr, j, &X, &Y))
        return 0;
    rmap_w(q0, X, Y, w, 0.0f, 3);
    return w[0] + c->g >= c->lo && w[0] + c->g <= c->hi && w[1] + c->g >= c->lo &&
           w[1] + c->g <= c->hi;
}

/* Cubic step: 0 below -1, 1 above 1; its derivative. */
RINLINE float rstep(float z, float *dz)
{
    if (z <= -1.0f) {
        *dz = 0.0f;
        return 0.0f;
    }
    if (z >= 1.0f) {
        *dz = 0.0f;
        return 1.0f;
    }
    *dz = 0.75f * (1.0f - z * z);
    return 0.5f + z * (0.75f - 0.25f * z * z);
}

/* The cell of a finite t: floor(t) clamped to the tag, 0..n-1 (nhi = n + 1),
 * as (int)(t + 2) - 2 with t + 2 rounded (a t just below an integer can
 * round up to it). Clamping t + 2 to [2, n + 1] first gives the cell the
 * clamped int would, and keeps the conversion in range. */
RINLINE int rcell(float t, float nhi)
{
    float s = t + 2.0f;
    s = s < 2.0f ? 2.0f : s;
    s = s > nhi ? nhi : s;
    return (int)s - 2;
}

/* The smoothed indicators of cells i - 1, i, i + 1 at t (i = rcell(t)),
 * edge half-width 1/iw < 1 cell, from z = (t - i) iw, and their
 * derivatives: with f = t - i in [0, 1) only the steps at f and f - 1 are
 * not flat, so s = (1 - A, A - B, B), A = step(f iw), B = step((f - 1) iw).
 * When i was clamped the cells where this differs from the indicator are
 * outside the tag, where the layout is 0. */
RINLINE void rind3(float z, float iw, float s[3], float ds[3])
{
    float A, B, dA, dB;
    A = rstep(z, &dA);
    B = rstep(z - iw, &dB);
    s[0] = 1.0f - A;
    s[1] = A - B;
    s[2] = B;
    ds[0] = -dA * iw;
    ds[1] = (dA - dB) * iw;
    ds[2] = dB * iw;
}

/* One row of rtemplate's 3 x 3 cells: the row's smoothed value and its u
 * derivative. */
RINLINE void rrow3(const float *row, const float su[3], const float du[3], float *rs, float *rd)
{
    *rs = row[0] * su[0] + row[1] * su[1] + row[2] * su[2];
    if (rd != NULL)
        *rd = row[0] * du[0] + row[1] * du[1] + row[2] * du[2];
}

/* Template P(u, v) and its gradient (pu NULL: P only) near a cell's edge,
 * from the 3 x 3 layout cells about the pixel's (L: cell (iu - 1, iv - 1))
 * and z = (u - iu) iwu, (v - iv) iwv. On an axis whose z is flat (away from
 * both steps, uflat or vflat: not both) rind3 gives exactly s = (0, 1, 0),
 * ds = (-0, 0, 0), so the full sums below reduce to the terms kept here:
 * uflat, each row's value is its middle cell (0 or 1, exactly) and its u
 * derivative +0; vflat, the middle row's terms (the others are +-0 times
 * finite numbers, which leave a sum begun at +0 unchanged). */
RINLINE float rtemplate(const float *L, float zu, float zv, float iwu, float iwv, int uflat,
                        int vflat, float *pu, float *pv)
{
    float su[3], du[3], sv[3], dv[3], rs[3], rd[3], P;
    if (uflat) {
        const float c0 = L[1], c1 = L[RL_PAD + 1], c2 = L[2 * RL_PAD + 1];
        rind3(zv, iwv, sv, dv);
        P = 0.0f + sv[0] * c0 + sv[1] * c1 + sv[2] * c2;
        if (pu != NULL) {
            *pu = 0.0f;
            *pv = 0.0f + dv[0] * c0 + dv[1] * c1 + dv[2] * c2;
        }
        return P;
    }
    rind3(zu, iwu, su, du);
    if (vflat) {
        rrow3(L + RL_PAD, su, du, &rs[1], pu != NULL ? &rd[1] : NULL);
        if (pu != NULL) {
            *pu = 0.0f + rd[1];
            *pv = 0.0f;
        }
        return 0.0f + rs[1];
    }
    rind3(zv, iwv, sv, dv);
    rrow3(L, su, du, &rs[0], pu != NULL ? &rd[0] : NULL);
    rrow3(L + RL_PAD, su, du, &rs[1], pu != NULL ? &rd[1] : NULL);
    rrow3(L + 2 * RL_PAD, su, du, &rs[2], pu != NULL ? &rd[2] : NULL);
    P = 0.0f + sv[0] * rs[0] + sv[1] * rs[1] + sv[2] * rs[2];
    if (pu != NULL) {
        *pu = 0.0f + sv[0] * rd[0] + sv[1] * rd[1] + sv[2] * rd[2];
        *pv = 0.0f + dv[0] * rs[0] + dv[1] * rs[1] + dv[2] * rs[2];
    }
    return P;
}

/* Solves the n x n symmetric positive system A x = y (Cholesky, A row-major,
 * overwritten). 0 when not positive definite. */
static int rsolve(float *A, float *y, int n)
{
    int i, j, k;
    for (j = 0; j < n; j++) {
        float d = A[j * n + j];
        for (k = 0; k < j; k++)
            d -= A[j * n + k] * A[j * n + k];
        if (!(d > 0.0f))
            return 0;
        d = actag_sqrtf(d);
        A[j * n + j] = d;
        for (i = j + 1; i < n; i++) {
            float s = A[i * n + j];
            for (k = 0; k < j; k++)
                s -= A[i * n + k] * A[j * n + k];
            A[i * n + j] = s / d;
        }
    }
    for (i = 0; i < n; i++) {
        float s = y[i];
        for (k = 0; k < i; k++)
            s -= A[i * n + k] * y[k];
        y[i] = s / A[i * n + i];
    }
    for (i = n - 1; i >= 0; i--) {
        float s = y[i];
        for (k = i + 1; k < n; k++)
            s -= A[k * n + i] * y[k];
        y[i] = s / A[i * n + i];
    }
    return 1;
}

/* Packed upper triangle of a symmetric 6 x 6 matrix, row by row. */
#define RNJ 21

/* One pass over the pixel set at grid G, mode one of: RS_LEVELS, the levels' normal
 * equations (R'R, R'I, I'I: the best levels for G and their residual sum of
 * squares); RS_GRID, the residual sum of squares rss with the levels cl
 * and the grid's normal equations J'J, J'r. */
#define RS_LEVELS 1
#define RS_GRID 2
typedef struct rsums {
    float A[RNJ], b[6]; /* R'R, R'I (levels) or J'J, J'r (grid) */
    float ss;           /* I'I (levels) or rss (grid) */
    int n;
} rsums;

/* Rows (J, r) a sweep buffers before rflush adds their products; their
 * width (SSE2: a pad float, so that a row is two vectors). */
#define RBATCH 4
#define RJW (7 + RSSE2)

/* Adds J J' and J r of the buffered rows Jb[k] = (J, r), k < nb, to the
 * packed sums, row after row: each sum gets the same additions in the same
 * order as when every pixel added its products at once, but holds its
 * running value in a register over the batch (two groups: the sums of the
 * J0..J2 rows of J J', then those of J3..J5) instead of a load and a store
 * per pixel and sum. */
#if !RSSE2
static void rflush(float *A, float *y, float Jb[RBATCH][RJW], int nb)
{
    int k;
    {
        float a0 = A[0], a1 = A[1], a2 = A[2], a3 = A[3], a4 = A[4], a5 = A[5];
        float a6 = A[6], a7 = A[7], a8 = A[8], a9 = A[9], a10 = A[10];
        float a11 = A[11], a12 = A[12], a13 = A[13], a14 = A[14];
        float y0 = y[0], y1 = y[1], y2 = y[2];
        for (k = 0; k < nb; k++) {
            const float j0 = Jb[k][0], j1 = Jb[k][1], j2 = Jb[k][2], j3 = Jb[k][3],
                        j4 = Jb[k][4], j5 = Jb[k][5], r = Jb[k][6];
            a0 += j0 * j0;
            a1 += j0 * j1;
            a2 += j0 * j2;
            a3 += j0 * j3;
            a4 += j0 * j4;
            a5 += j0 * j5;
            a6 += j1 * j1;
            a7 += j1 * j2;
            a8 += j1 * j3;
            a9 += j1 * j4;
            a10 += j1 * j5;
            a11 += j2 * j2;
            a12 += j2 * j3;
            a13 += j2 * j4;
            a14 += j2 * j5;
            y0 += j0 * r;
            y1 += j1 * r;
            y2 += j2 * r;
        }
        A[0] = a0;
        A[1] = a1;
        A[2] = a2;
        A[3] = a3;
        A[4] = a4;
        A[5] = a5;
        A[6] = a6;
        A[7] = a7;
        A[8] = a8;
        A[9] = a9;
        A[10] = a10;
        A[11] = a11;
        A[12] = a12;
        A[13] = a13;
        A[14] = a14;
        y[0] = y0;
        y[1] = y1;
        y[2] = y2;
    }
    {
        float a15 = A[15], a16 = A[16], a17 = A[17], a18 = A[18], a19 = A[19], a20 = A[20];
        float y3 = y[3], y4 = y[4], y5 = y[5];
        for (k = 0; k < nb; k++) {
            const float j3 = Jb[k][3], j4 = Jb[k][4], j5 = Jb[k][5], r = Jb[k][6];
            a15 += j3 * j3;
            a16 += j3 * j4;
            a17 += j3 * j5;
            a18 += j4 * j4;
            a19 += j4 * j5;
            a20 += j5 * j5;
            y3 += j3 * r;
            y4 += j4 * r;
            y5 += j5 * r;
        }
        A[15] = a15;
        A[16] = a16;
        A[17] = a17;
        A[18] = a18;
        A[19] = a19;
        A[20] = a20;
        y[3] = y3;
        y[4] = y4;
        y[5] = y5;
    }
}

#else
/* rflush four sums a vector: with v0 = (j0, j1, j2, j3), v1 = (j4, j5, r,
 * pad), acc[2a] += ja v0, acc[2a + 1] += ja v1 (a < 4), acc[4 + a] += ja v1
 * (a = 4, 5): every sum of J J' and J r (and some unused ones) gets the
 * products of rflush, in the same order (x * y and y * x are the same
 * float). rsums4 reads them out. */
static void rflush4(__m128 acc[10], float Jb[RBATCH][RJW], int nb)
{
    __m128 a0 = acc[0], a1 = acc[1], a2 = acc[2], a3 = acc[3], a4 = acc[4];
    __m128 a5 = acc[5], a6 = acc[6], a7 = acc[7], a8 = acc[8], a9 = acc[9];
    int k;
    for (k = 0; k < nb; k++) {
        const __m128 v0 = _mm_loadu_ps(Jb[k]), v1 = _mm_loadu_ps(Jb[k] + 4);
        __m128 b = _mm_shuffle_ps(v0, v0, 0x00);
        a0 = _mm_add_ps(a0, _mm_mul_ps(b, v0));
        a1 = _mm_add_ps(a1, _mm_mul_ps(b, v1));
        b = _mm_shuffle_ps(v0, v0, 0x55);
        a2 = _mm_add_ps(a2, _mm_mul_ps(b, v0));
        a3 = _mm_add_ps(a3, _mm_mul_ps(b, v1));
        b = _mm_shuffle_ps(v0, v0, 0xaa);
        a4 = _mm_add_ps(a4, _mm_mul_ps(b, v0));
        a5 = _mm_add_ps(a5, _mm_mul_ps(b, v1));
        b = _mm_shuffle_ps(v0, v0, 0xff);
        a6 = _mm_add_ps(a6, _mm_mul_ps(b, v0));
        a7 = _mm_add_ps(a7, _mm_mul_ps(b, v1));
        b = _mm_shuffle_ps(v1, v1, 0x00);
        a8 = _mm_add_ps(a8, _mm_mul_ps(b, v1));
        b = _mm_shuffle_ps(v1, v1, 0x55);
        a9 = _mm_add_ps(a9, _mm_mul_ps(b, v1));
    }
    acc[0] = a0;
    acc[1] = a1;
    acc[2] = a2;
    acc[3] = a3;
    acc[4] = a4;
    acc[5] = a5;
    acc[6] = a6;
    acc[7] = a7;
    acc[8] = a8;
    acc[9] = a9;
}

/* rflush4's sums as rflush packs them: J J' (upper triangle, row by row)
 * and J r. */
static void rsums4(const __m128 acc[10], float *A, float *y)
{
    /* lanes of acc[m] at t[4 m] */
    static const unsigned char ia[RNJ] = {0,  1,  2,  3,  4,  5,  9,  10, 11, 12, 13,
                                          18, 19, 20, 21, 27, 28, 29, 32, 33, 37};
    static const unsigned char iy[6] = {6, 14, 22, 30, 34, 38};
    float t[40];
    int m;
    for (m = 0; m < 10; m++)
        _mm_storeu_ps(t + 4 * m, acc[m]);
    for (m = 0; m < RNJ; m++)
        A[m] = t[ia[m]];
    for (m = 0; m < 6; m++)
        y[m] = t[iy[m]];
}

/* Lattice rows whose grid offsets rwblock computes side by side, and
 * their most pixels (longer rows: scalar steps). */
#define RLANES 8
#define RWMAX 128

/* rmap_wrow's t = w'Qw / (2 r0), four lanes. */
static inline __m128 rq4(__m128 w0, __m128 w1, __m128 qa, __m128 qb, __m128 qc)
{
    return _mm_add_ps(_mm_mul_ps(w0, _mm_add_ps(_mm_mul_ps(qa, w0), _mm_mul_ps(qb, w1))),
                      _mm_mul_ps(w1, _mm_add_ps(_mm_mul_ps(qb, w0), _mm_mul_ps(qc, w1))));
}

/* The grid offsets rsweep_mode's rmap_wrow gives the pixels of lattice
 * rows i, i + sub, ... (RLANES of them, those below nrow): pixel k of row
 * i + l sub at wb[k][0][l] (w0), wb[k][1][l] (w1). One row a lane, the
 * same operations as rmap_wrow's in each: each pixel's t starts the next
 * one's steps, a chain of dependent multiplies and adds, which the rows
 * now run side by side; also the level ramps' (up, vp) at wb[k][2..3][l].
 * 1 when done; 0 (scalar steps) for a flat grid (no chain), a row past the
 * direction cache or longer than RWMAX; -1 when a pixel's w is not finite
 * (the pixel loop would return 0 there: the sweep fails whatever the
 * pixels before it add). */
static int rwblock(const rctx *c, const rmap *q, int i, int sub, float wb[][4][RLANES])
{
    const float *d[RLANES];
    float rr[RLANES];
    int nk[RLANES], l, k, h, kmax = 0;
    const __m128 m0 = _mm_set1_ps(q->m0), m1 = _mm_set1_ps(q->m1);
    const __m128 i0 = _mm_set1_ps(q->inv[0]), i1 = _mm_set1_ps(q->inv[1]);
    const __m128 i2 = _mm_set1_ps(q->inv[2]), i3 = _mm_set1_ps(q->inv[3]);
    const __m128 qa = _mm_set1_ps(q->qa), qb = _mm_set1_ps(q->qb), qc = _mm_set1_ps(q->qc);
    const __m128 rx = _mm_set1_ps(c->rx), ry = _mm_set1_ps(c->ry);
    const __m128 ra0 = _mm_set1_ps(c->ra[0]), ra1 = _mm_set1_ps(c->ra[1]);
    const __m128 ra2 = _mm_set1_ps(c->ra[2]), ra3 = _mm_set1_ps(c->ra[3]);
    const __m128 zero = _mm_setzero_ps();
    __m128 t[RLANES / 4];
    if (!q->curved)
        return 0;
    for (l = 0; l < RLANES; l++) {
        int r = i + l * sub, j = 0, jb = -1;
        if (r < c->nrow) {
            j = (c->ja[r] + sub - 1) / sub * sub;
            jb = c->jb[r];
        }
        nk[l] = 0;
        rr[l] = 0.0f;
        d[l] = c->dir; /* a lane past its row's end reads a valid column */
        if (j <= jb) {
            if (jb >= c->ndir || (jb - j) / sub >= RWMAX)
                return 0;
            nk[l] = (jb - j) / sub + 1;
            rr[l] = rrange(c, c->y0 + r * c->step);
            d[l] = c->dir + 2 * j;
        }
        kmax = nk[l] > kmax ? nk[l] : kmax;
    }
    for (k = 0; k < kmax; k++) {
        int bad = 0; /* lanes with a w not finite */
        for (h = 0; h < RLANES / 4; h++) {
            const int o = 4 * h;
            const __m128 rv = _mm_loadu_ps(rr + o);
            const __m128 X = _mm_mul_ps(rv, _mm_set_ps(d[o + 3][0], d[o + 2][0], d[o + 1][0],
                                                       d[o][0]));
            const __m128 Y = _mm_mul_ps(rv, _mm_set_ps(d[o + 3][1], d[o + 2][1], d[o + 1][1],
                                                       d[o][1]));
            const __m128 dx = _mm_sub_ps(X, m0), dy = _mm_sub_ps(Y, m1);
            const __m128 a0 = _mm_add_ps(_mm_mul_ps(i0, dx), _mm_mul_ps(i1, dy));
            const __m128 a1 = _mm_add_ps(_mm_mul_ps(i2, dx), _mm_mul_ps(i3, dy));
            __m128 w0, w1, tt;
            if (k == 0) { /* a row's first pixel: 3 steps from 0 */
                const __m128 z = _mm_setzero_ps();
                w0 = _mm_sub_ps(a0, _mm_mul_ps(z, i0));
                w1 = _mm_sub_ps(a1, _mm_mul_ps(z, i2));
                t[h] = rq4(w0, w1, qa, qb, qc);
            }
            w0 = _mm_sub_ps(a0, _mm_mul_ps(t[h], i0));
            w1 = _mm_sub_ps(a1, _mm_mul_ps(t[h], i2));
            tt = rq4(w0, w1, qa, qb, qc);
            w0 = _mm_sub_ps(a0, _mm_mul_ps(tt, i0));
            w1 = _mm_sub_ps(a1, _mm_mul_ps(tt, i2));
            tt = rq4(w0, w1, qa, qb, qc);
            w0 = _mm_sub_ps(a0, _mm_mul_ps(tt, i0));
            w1 = _mm_sub_ps(a1, _mm_mul_ps(tt, i2));
            t[h] = tt;
            _mm_storeu_ps(&wb[k][0][o], w0);
            _mm_storeu_ps(&wb[k][1][o], w1);
            /* the level ramps' coordinates, as the pixel loop's */
            _mm_storeu_ps(&wb[k][2][o], _mm_add_ps(_mm_mul_ps(ra0, _mm_sub_ps(X, rx)),
                                                   _mm_mul_ps(ra1, _mm_sub_ps(Y, ry))));
            _mm_storeu_ps(&wb[k][3][o], _mm_add_ps(_mm_mul_ps(ra2, _mm_sub_ps(X, rx)),
                                                   _mm_mul_ps(ra3, _mm_sub_ps(Y, ry))));
            bad |= _mm_movemask_ps(_mm_cmpneq_ps(
                       _mm_add_ps(_mm_sub_ps(w0, w0), _mm_sub_ps(w1, w1)), zero)) << o;
        }
        for (l = 0; l < RLANES; l++) {
            if (k < nk[l] && (bad >> l & 1))
                return -1;
            if (k + 1 < nk[l])
                d[l] += 2 * sub;
        }
    }
    return 1;
}
#endif

/* One pass over the pixel set in one mode, a constant where this is
 * inlined (the other mode's work and tests leave the pixel loop). The
 * sweep's constants are read into locals once; the pixel loop stores only
 * to Jb, and rflush adds its rows to S. */
RINLINE int rsweep_mode(const rctx *c, const rgrid *G, const float cl[6], int sub, int mode,
                        rsums *S)
{
    rmap q;
    float Jb[RBATCH][RJW]; /* rows for rflush */
#if RSSE2
    __m128 acc[10]; /* rflush4's sums */
    float wb[RWMAX][4][RLANES]; /* rwblock's grid offsets and ramps */
    int wblk = 0;
#endif
    const float g = c->g, iwu = c->iwu, iwv = c->iwv, nhi = (float)(c->n + 1);
    const float rx = c->rx, ry = c->ry, ra0 = c->ra[0], ra1 = c->ra[1], ra2 = c->ra[2],
                ra3 = c->ra[3];
    float cl0 = 0.0f, cl1 = 0.0f, cl2 = 0.0f, cl3 = 0.0f, cl4 = 0.0f, cl5 = 0.0f, ss = 0.0f;
    float fu = 0.0f, fv = 0.0f; /* the last pixel's cell (any cell of the tag to start) */
    const float *L = c->Lp;    /* its layout: cell (fu - 1, fv - 1) */
    const float *dir = c->dir;
    const int ndir = c->ndir, x0 = c->x0, step = c->step, deep = c->depth == 16;
    int i, n = 0, nb = 0;
    memset(S, 0, sizeof *S);
    if (!rmap_init(G, &q))
        return 0;
#if RSSE2
    memset(Jb, 0, sizeof Jb); /* the pads */
    for (i = 0; i < 10; i++)
        acc[i] = _mm_setzero_ps();
#define RFLUSH() rflush4(acc, Jb, nb)
#else
#define RFLUSH() rflush(S->A, S->b, Jb, nb)
#endif
    if (mode == RS_GRID) { /* the levels sweep passes cl unset */
        cl0 = cl[0];
        cl1 = cl[1];
        cl2 = cl[2];
        cl3 = cl[3];
        cl4 = cl[4];
        cl5 = cl[5];
    }
    for (i = 0; i < c->nrow; i += sub) {
        int y = c->y0 + i * c->step, j = c->ja[i], jb = c->jb[i], first = 1;
        const uint8_t *row = c->img + (size_t)y * (size_t)c->stride * (size_t)(c->depth / 8);
        float rr = rrange(c, y), tq = 0.0f;
#if RSSE2
        int kw = 0, lw = i / sub % RLANES;
        if (lw == 0 && (wblk = rwblock(c, &q, i, sub, wb)) < 0)
            return 0;
#endif
        j = (j + sub - 1) / sub * sub;
        for (; j <= jb; j += sub) {
            int x = x0 + j * step, edge;
            float X, Y, w0, w1, u, v, zu, zv, P, pu = 0.0f, pv = 0.0f, up, vp, I;
#if RSSE2
            if (wblk) { /* rwblock's, all finite */
                w0 = wb[kw][0][lw];
                w1 = wb[kw][1][lw];
                up = wb[kw][2][lw];
                vp = wb[kw][3][lw];
                kw++;
            } else
#endif
            {
                if (!RUNLIKELY(j >= ndir)) { /* rlattice_plane's common case */
                    X = rr * dir[2 * j];
                    Y = rr * dir[2 * j + 1];
                } else if (!rlattice_plane(c, rr, j, &X, &Y)) {
                    continue;
                }
                /* 3 steps from the affine w at a row's first pixel, then 2
                 * from the previous pixel's curvature */
                tq = rmap_wrow(&q, X, Y, tq, first, &w0, &w1);
                first = 0;
                /* the curved inverse diverged (a trial grid bent too far):
                 * no grid offset for this pixel, so no such grid (the sum
                 * is NaN unless both are finite) */
                if (!((w0 - w0) + (w1 - w1) == 0.0f))
                    return 0;
#if RSSE2
                up = ra0 * (X - rx) + ra1 * (Y - ry); /* as below */
                vp = ra2 * (X - rx) + ra3 * (Y - ry);
#endif
            }
            u = w0 + g;
            v = w1 + g;
            /* inside one cell, away from its edges: P is the cell's, no
             * gradient. Tried first in the last pixel's cell (fu, fv, L),
             * where most pixels are: passing the test there puts u above
             * fu and below fu + 0.96 (the half-width 1/iwu is at least
             * 0.05 cell, rwidths), so that rcell(u) is fu; v likewise */
            zu = (u - fu) * iwu;
            zv = (v - fv) * iwv;
            edge = !(zu >= 1.0f && zu - iwu <= -1.0f && zv >= 1.0f && zv - iwv <= -1.0f);
            if (edge) {
                int iu = rcell(u, nhi), iv = rcell(v, nhi), uflat, vflat;
                fu = (float)iu;
                fv = (float)iv;
                L = c->Lp + iv * RL_PAD + iu; /* cell (iu - 1, iv - 1) */
                zu = (u - fu) * iwu;
                zv = (v - fv) * iwv;
                uflat = zu >= 1.0f && zu - iwu <= -1.0f;
                vflat = zv >= 1.0f && zv - iwv <= -1.0f;
                edge = !(uflat && vflat);
                if (edge)
                    P = rtemplate(L, zu, zv, iwu, iwv, uflat, vflat,
                                  mode == RS_GRID ? &pu : NULL, &pv);
                else
                    P = L[RL_PAD + 1];
            } else {
                P = L[RL_PAD + 1];
            }
#if !RSSE2
            /* the level ramps' coordinates: the start grid's (affine), fixed */
            up = ra0 * (X - rx) + ra1 * (Y - ry);
            vp = ra2 * (X - rx) + ra3 * (Y - ry);
#endif
            I = (deep ? (float)rscale16(c, row + 2 * x) : (float)row[x]) - 128.0f;
            n++;
            if (mode == RS_LEVELS) {
                float *R = Jb[nb];
                R[0] = 1.0f;
                R[1] = P;
                R[2] = P * up;
                R[3] = P * vp;
                R[4] = up;
                R[5] = vp;
                R[6] = I;
                if (RUNLIKELY(++nb == RBATCH)) {
                    RFLUSH();
                    nb = 0;
                }
                ss += I * I;
            } else {
                float gain = cl1 + cl2 * up + cl3 * vp;
                float r = I - (cl0 + gain * P + cl4 * up + cl5 * vp), Tu, Tv, *J = Jb[nb];
                float k11 = q.k11, k12 = q.k12, id = q.idet, h0, h1;
                ss += r * r;
                if (!edge || (pu == 0.0f && pv == 0.0f))
                    continue; /* inside a cell: the grid does not move the model */
                /* dw = -K^-1 (dm + dM w): dT/dm_i = -h_i, dT/dM_ij = -h_i w_j,
                 * h = K^-T (Tu, Tv) */
                Tu = gain * pu;
                Tv = gain * pv;
                if (q.curved) {
                    float det;
                    k11 += q.ka * w0 + q.kb * w1;
                    k12 += q.kb * w0 + q.kc * w1;
                    det = k11 * q.k22 - k12 * q.k21;
                    if (!finite_f(det) || det == 0.0f)
                        return 0;
                    id = 1.0f / det;
                }
                h0 = (q.k22 * Tu - q.k21 * Tv) * id;
                h1 = (k11 * Tv - k12 * Tu) * id;
                J[0] = -h0;
                J[1] = -h1;
                J[2] = -h0 * w0;
                J[3] = -h1 * w0;
                J[4] = -h0 * w1;
                J[5] = -h1 * w1;
                if (q.qcase != 0) {
                    /* Q and r0 move with the grid: F's e1 part q(w) too */
                    float qq = w0 * (q.qa * w0 + q.qb * w1) + w1 * (q.qb * w0 + q.qc * w1);
                    float g0 = -h0 * q.ir0, a0, a1, b0, b1, e0, e1;
                    if (q.qcase == 1) { /* -MG/r0 = -(M w) w' / r0 */
                        a0 = q.M[0] * w0 + q.M[2] * w1;
                        a1 = q.M[1] * w0 + q.M[3] * w1;
                        J[2] -= g0 * a0 * w0;
                        J[3] -= g0 * a1 * w0;
                        J[4] -= g0 * a0 * w1;
                        J[5] -= g0 * a1 * w1;
                    } else {
                        float sv = q.v[0] * w0 + q.v[1] * w1;
                        float tu = q.u[0] * w0 + q.u[1] * w1;
                        float kst = q.kap * sv * tu, s2 = sv * sv;
                        a0 = s2 * q.v[0] + kst * q.u[0]; /* MG = Mv a' + Mu b' */
                        a1 = s2 * q.v[1] + kst * q.u[1];
                        b0 = kst * q.v[0];
                        b1 = kst * q.v[1];
                        e0 = q.Mv[0] * a0 + q.Mu[0] * b0; /* (MG)_i0 */
                        e1 = q.Mv[1] * a0 + q.Mu[1] * b0;
                        J[2] -= g0 * e0;
                        J[3] -= g0 * e1;
                        e0 = q.Mv[0] * a1 + q.Mu[0] * b1; /* (MG)_i1 */
                        e1 = q.Mv[1] * a1 + q.Mu[1] * b1;
                        J[4] -= g0 * e0;
                        J[5] -= g0 * e1;
                    }
                    J[0] += h0 * qq * q.mr0;
                    J[1] += h0 * qq * q.mr1;
                }
                J[6] = r;
                if (RUNLIKELY(++nb == RBATCH)) {
                    RFLUSH();
                    nb = 0;
                }
            }
        }
    }
    RFLUSH();
#undef RFLUSH
#if RSSE2
    rsums4(acc, S->A, S->b);
#endif
    S->ss = ss;
    S->n = n;
    return n >= 16;
}

/* The two sweeps, each its own function (not one with both inlined: their
 * frames would add up on the stack). On failure S's sums are not the
 * sweep's (the callers drop them). */
#if defined(__GNUC__)
__attribute__((noinline))
#endif
static int rsweep_levels(const rctx *c, const rgrid *G, int sub, rsums *S)
{
    return rsweep_mode(c, G, NULL, sub, RS_LEVELS, S);
}

#if defined(__GNUC__)
__attribute__((noinline))
#endif
static int rsweep_grid(const rctx *c, const rgrid *G, const float cl[6], int sub, rsums *S)
{
    return rsweep_mode(c, G, cl, sub, RS_GRID, S);
}

/* The damped step d: (A + lambda diag A) d = y, A packed (RNJ), solved
 * scaled to a unit diagonal. 0 when singular. */
static int rdamped(const float Ap[RNJ], const float y[6], float lambda, float d[6])
{
    float A[36], s[6];
    int i, j, k;
    for (i = 0, k = 0; i < 6; i++) {
        float v = Ap[k];
        s[i] = v > 0.0f ? 1.0f / actag_sqrtf(v) : 1.0f;
        k += 6 - i;
    }
    for (i = 0, k = 0; i < 6; i++) {
        for (j = i; j < 6; j++, k++)
            A[i * 6 + j] = A[j * 6 + i] = Ap[k] * s[i] * s[j];
        A[i * 6 + i] = A[i * 6 + i] * (1.0f + lambda) + 1e-9f;
        d[i] = y[i] * s[i];
    }
    if (!rsolve(A, d, 6))
        return 0;
    for (i = 0; i < 6; i++)
        d[i] *= s[i];
    return 1;
}

/* The best levels for the sweep's grid and their residual sum of squares. */
static int rbest(const rsums *S, float cl[6], float *rss)
{
    int i;
    if (!rdamped(S->A, S->b, 1e-6f, cl))
        return 0;
    *rss = S->ss;
    for (i = 0; i < 6; i++)
        *rss -= cl[i] * S->b[i];
    if (*rss < 0.0f)
        *rss = 0.0f;
    return 1;
}

/* Grid steps' inner product: squared corner moves, about (cells^2 x |a|^2). */
static float rdot(const float a[6], const float b[6])
{
    return a[0] * b[0] + a[1] * b[1] +
           4.0f * (a[2] * b[2] + a[3] * b[3] + a[4] * b[4] + a[5] * b[5]);
}

/* One pass: the levels fitted to the grid on every lsub-th lattice row and
 * column and held, then Levenberg-Marquardt over the grid on every sub-th,
 * one sweep per step (the sweep at a trial grid gives its residual, which
 * judges the step, and the next step's normal equations). Converged when
 * no corner moves by more than tol cells. Returns the steps taken, -1 on
 * failure. */
static int rpass(const rctx *c, rgrid *G, float cl[6], int sub, int lsub, int max_it, float tol,
                 float *rss_out, int *count)
{
    rsums S, S2;
    float lambda = 1e-3f, tol2 = tol * tol, rss, dprev[6] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
    int it, taken = 0, have_prev = 0;
    rcurv(c, G);
    /* the levels (6 numbers: a sparser lattice does) for the grid, then
     * held through the pass */
    if (!rsweep_levels(c, G, lsub, &S) || !rbest(&S, cl, &rss) ||
        !rsweep_grid(c, G, cl, sub, &S))
        return -1;
    *count = S.n;
    for (it = 0; it < max_it; it++) {
        int i, tries, ok = 0, noext = 0;
        for (tries = 0; tries < 5 && !ok; tries++) {
            rgrid T = *G;
            float d[6], mv, cs, ext = 1.0f;
            if (!rdamped(S.A, S.b, lambda, d)) {
                lambda *= 10.0f;
                continue;
            }
            /* the largest corner move, about */
            mv = rdot(d, d);
            cs = G->p[2] * G->p[2] + G->p[3] * G->p[3];
            if (have_prev && !noext) {
                /* linear convergence (the residuals are not small): steps
                 * along one line shrinking by rho add up to 1 / (1 - rho) */
                float dp = rdot(d, dprev), pp = rdot(dprev, dprev);
                if (dp > 0.0f && dp * dp > 0.81f * mv * pp && mv < 0.64f * pp) {
                    float rho = actag_sqrtf(mv / pp);
                    ext = 1.0f / (1.0f - rho);
                }
            }
            for (i = 0; i < 6; i++)
                T.p[i] += ext * d[i];
            rcurv(c, &T);
            DBG("refine:  step %d.%d lambda %g ext %g move %g cells rss %g\n", it, tries,
                (double)lambda, (double)ext, (double)actag_sqrtf(mv / cs), (double)S.ss);
            if (mv < tol2 * cs) { /* converged: a step too small to test */
                *G = T;
                taken++;
                it = max_it;
                ok = 1;
                break;
            }
            if (rsweep_grid(c, &T, cl, sub, &S2) && S2.ss <= S.ss) {
                *G = T;
                S = S2;
                lambda *= 0.1f;
                if (lambda < 1e-6f)
                    lambda = 1e-6f;
                ok = 1;
                taken++;
                have_prev = ext == 1.0f;
                memcpy(dprev, d, sizeof d);
            } else if (ext > 1.0f) {
                noext = 1;
            } else {
                lambda *= 10.0f;
            }
        }
        if (!ok)
            break;
    }
    *rss_out = S.ss;
    return taken;
}

/* Pixel of grid offset w. */
static void rgrid_pixel(const rctx *c, const rgrid *G, float w0, float w1, actag_point *p)
{
    float X, Y;
    rforward(G, w0, w1, &X, &Y);
    rpixel(c, X, Y, p);
}

/* Edge half-widths in cells for a blur of `px` pixels across each grid
 * direction's lines (from the grid's pixel Jacobian at its centre). */
static void rwidths(rctx *c, const rgrid *G, float px, float cells_min)
{
    actag_point p0, p1, q0, q1;
    float ax, ay, bx, by, det;
    rgrid_pixel(c, G, -0.5f, 0.0f, &p0);
    rgrid_pixel(c, G, 0.5f, 0.0f, &p1);
    rgrid_pixel(c, G, 0.0f, -0.5f, &q0);
    rgrid_pixel(c, G, 0.0f, 0.5f, &q1);
    ax = p1.x - p0.x;
    ay = p1.y - p0.y;
    bx = q1.x - q0.x;
    by = q1.y - q0.y;
    det = ax * by - bx * ay;
    if (!finite_f(det) || det == 0.0f) {
        c->wu = c->wv = 0.5f;
        c->iwu = c->iwv = 2.0f;
        return;
    }
    /* |grad u| = |row 1 of the inverse|, |grad v| = |row 2| */
    c->wu = px * actag_sqrtf(by * by + bx * bx) / (det < 0.0f ? -det : det);
    c->wv = px * actag_sqrtf(ay * ay + ax * ax) / (det < 0.0f ? -det : det);
    if (c->wu < cells_min)
        c->wu = cells_min;
    if (c->wv < cells_min)
        c->wv = cells_min;
    if (c->wu > 0.9f)
        c->wu = 0.9f;
    if (c->wv > 0.9f)
        c->wv = 0.9f;
    c->iwu = 1.0f / c->wu;
    c->iwv = 1.0f / c->wv;
}

/* A cell side grown by more than 25 % from the start, from l2 to l2n
 * (squared): accepted when it is still a side a tag of this size can show.
 * The sonar's projection along the elevation arcs only shortens the tag's
 * sides, so a fitted side up to the cell size (10 % more for the noise) is
 * a possible view even when the start was too short (a RANSAC quad of a
 * white square thinned in range); a longer one is a fit gone astray. At
 * most 50 % growth. Without a geometry the size is unknown: refused. */
static int rgrown_ok(float cell2, float l2, float l2n)
{
    return cell2 > 0.0f && l2n <= 1.21f * cell2 && l2n <= 2.25f * l2;
}

/* The fitted grid g against the start s (rgrid.p): finite, the same
 * handedness, each cell side within 25 % of the start's or grown as
 * rgrown_ok allows (cell2: the tag's squared cell side, 0 without a
 * geometry). */
static int rshape_ok(float cell2, const float s[6], const float g[6])
{
    float la = s[2] * s[2] + s[3] * s[3];
    float lb = s[4] * s[4] + s[5] * s[5];
    float la2 = g[2] * g[2] + g[3] * g[3];
    float lb2 = g[4] * g[4] + g[5] * g[5];
    int i;
    for (i = 0; i < 6; i++)
        if (!finite_f(g[i]))
            return 0;
    if ((g[2] * g[5] - g[4] * g[3]) * (s[2] * s[5] - s[4] * s[3]) <= 0.0f)
        return 0;
    if (la2 < 0.5625f * la || lb2 < 0.5625f * lb ||
        (la2 > 1.5625f * la && !rgrown_ok(cell2, la, la2)) ||
        (lb2 > 1.5625f * lb && !rgrown_ok(cell2, lb, lb2))) {
        DBG("refine: sides %g %g\n", (double)(la2 / la), (double)(lb2 / lb));
        return 0;
    }
    return 1;
}

int actag__refine_shape_ok(const float start[6], const float fit[6], float cell2)
{
    return rshape_ok(cell2, start, fit);
}

int actag_refine_corners(const uint8_t *img, int rows, int cols, int stride,
                         const actag_sonar_geometry *geometry, float tag_size,
                         const actag_family *family, int id, const actag_point corners[4],
                         const actag_refine_params *rp, actag_point out[4],
                         actag_refine_info *info)
{
    return actag_refine_corners_depth(img, 8, rows, cols, stride, geometry, tag_size, family, id,
                                      corners, rp, out, info);
}

int actag_refine_corners_depth(const void *img, int depth, int rows, int cols, int stride,
                               const actag_sonar_geometry *geometry, float tag_size,
                               const actag_family *family, int id, const actag_point corners[4],
                               const actag_refine_params *rp, actag_point out[4],
                               actag_refine_info *info)
{
    /* a caller's geometry is checked here (the detector checked its own) */
    if (geometry != NULL && img != NULL && family != NULL && corners != NULL && rp != NULL &&
        out != NULL && rows >= 1 && cols >= 1 && rows <= ACTAG_MAX_DIM && cols <= ACTAG_MAX_DIM &&
        actag_geometry_validate(geometry, rows, cols, NULL) != ACTAG_OK)
        return ACTAG_ERR_GEOMETRY;
    return actag__refine_corners_max16(img, depth, 0u, rows, cols, stride, geometry, tag_size,
                                       family, id, corners, rp, out, info);
}

/* The refinement's context (*c) and start grid (*G) for a tag of family's
 * code id at corners (tag order; checked by the caller): the layout, the
 * start grid (the corners' affine fit in the fan plane), the level ramps,
 * the pixel set and its lattice; *count its pixels. ACTAG_OK, or
 * ACTAG_ERR_PARAM / ACTAG_ERR_NO_MATCH as actag_refine_corners says. */
#if defined(__GNUC__)
__attribute__((noinline)) /* one copy for the refinement and the probe */
#endif
static int rsetup(rctx *c, rgrid *G, int *count, const void *img, int depth, uint32_t max16,
                  int rows, int cols, int stride, const actag_sonar_geometry *geometry,
                  float tag_size, const actag_family *family, int id,
                  const actag_point corners[4], const actag_refine_params *rp)
{
    float H[9];
    actag_point pl[4];
    int k, bits = family->bits, i, cx, cy, rc;
    uint32_t code;
    *count = 0;
    k = bits / 4;
    memset(c, 0, sizeof *c);
    c->img = (const uint8_t *)img;
    c->depth = depth;
    if (depth == 16)
        c->max16 = max16 ? max16 : frame16_max(c->img, rows, cols, (size_t)stride);
    c->rows = rows;
    c->cols = cols;
    c->stride = stride;
    c->geo = geometry;
    c->n = k + 1;
    c->g = 0.5f * (float)c->n;
    c->lo = rp->margin;
    c->hi = (float)c->n - rp->margin;
    /* the layout as printed (corners are in tag order: no rotation) */
    code = family->codes[id];
    for (cy = 0; cy < c->n; cy++)
        for (cx = 0; cx < c->n; cx++)
            c->Lp[(cy + 1) * RL_PAD + cx + 1] =
                (cx >= 2 && cy >= 2 && cx <= k - 2 && cy <= k - 2) ? 1.0f : 0.0f;
    for (i = 0; i < bits; i++) {
        int q = i / k, j = i % k;
        cx = q == 0 ? j : q == 1 ? k : q == 2 ? k - j : 0;
        cy = q == 0 ? 0 : q == 1 ? j : q == 2 ? k : k - j;
        c->Lp[(cy + 1) * RL_PAD + cx + 1] = (float)((code >> (bits - 1 - i)) & 1u);
    }

    /* the start grid: the corners' affine fit in the fan plane */
    if (geometry != NULL) {
        float mx = 0.25f * (corners[0].x + corners[1].x + corners[2].x + corners[3].x);
        c->ac = actag_geometry_azimuth(geometry, cols, mx);
        c->cell2 = tag_size / (float)(k - 3);
        c->cell2 *= c->cell2;
    }
    for (i = 0; i < 4; i++)
        if (!rplane(c, corners[i].x, corners[i].y, &pl[i].x, &pl[i].y))
            return ACTAG_ERR_PARAM;
    rc = actag_tag_affine(pl, bits, H);
    if (rc != ACTAG_OK)
        return rc;
    G->p[0] = H[0] * c->g + H[1] * c->g + H[2];
    G->p[1] = H[3] * c->g + H[4] * c->g + H[5];
    G->p[2] = H[0];
    G->p[3] = H[3];
    G->p[4] = H[1];
    G->p[5] = H[4];
    for (i = 0; i < 6; i++)
        if (!finite_f(G->p[i]))
            return ACTAG_ERR_PARAM;
    rcurv(c, G);
    c->G0 = *G;
    {
        /* the level ramps' frame: the start grid's affine coordinates / (k + 1) */
        float det = G->p[2] * G->p[5] - G->p[4] * G->p[3], s = 1.0f / (float)c->n;
        if (!finite_f(det) || det == 0.0f)
            return ACTAG_ERR_PARAM;
        c->rx = G->p[0];
        c->ry = G->p[1];
        c->ra[0] = G->p[5] / det * s;
        c->ra[1] = -G->p[4] / det * s;
        c->ra[2] = -G->p[3] / det * s;
        c->ra[3] = G->p[2] / det * s;
    }
    {
        /* the pixel box: the start outline's pixels (its sides are nearly
         * straight: a 2 pixel pad), clipped to the image */
        float bx0 = 1e30f, bx1 = -1e30f, by0 = 1e30f, by1 = -1e30f, area;
        int j;
        for (j = 0; j < 8; j++) {
            float t = j < 4 ? 0.0f : 0.5f;
            int e = j & 3;
            float u = e == 0 ? t : e == 1 ? 1.0f : e == 2 ? 1.0f - t : 0.0f;
            float v = e == 0 ? 0.0f : e == 1 ? t : e == 2 ? 1.0f : 1.0f - t;
            actag_point q;
            u = c->lo + u * (c->hi - c->lo) - c->g;
            v = c->lo + v * (c->hi - c->lo) - c->g;
            rgrid_pixel(c, G, u, v, &q);
            if (!finite_f(q.x) || !finite_f(q.y))
                return ACTAG_ERR_PARAM;
            bx0 = q.x < bx0 ? q.x : bx0;
            bx1 = q.x > bx1 ? q.x : bx1;
            by0 = q.y < by0 ? q.y : by0;
            by1 = q.y > by1 ? q.y : by1;
        }
        bx0 -= 2.0f;
        by0 -= 2.0f;
        bx1 += 2.0f;
        by1 += 2.0f;
        if (!(bx0 < (float)cols && by0 < (float)rows && bx1 >= 0.0f && by1 >= 0.0f))
            return ACTAG_ERR_NO_MATCH;
        c->x0 = bx0 < 0.0f ? 0 : (int)bx0 + 1;
        c->y0 = by0 < 0.0f ? 0 : (int)by0 + 1;
        c->x1 = bx1 > (float)(cols - 1) ? cols - 1 : (int)bx1;
        c->y1 = by1 > (float)(rows - 1) ? rows - 1 : (int)by1;
        if (c->x1 < c->x0 || c->y1 < c->y0)
            return ACTAG_ERR_NO_MATCH;
        /* the set covers about the corners' quad's area x ((hi - lo) / (k - 3))^2 */
        area = 0.5f * ((corners[2].x - corners[0].x) * (corners[3].y - corners[1].y) -
                       (corners[3].x - corners[1].x) * (corners[2].y - corners[0].y));
        area = (area < 0.0f ? -area : area) * (c->hi - c->lo) * (c->hi - c->lo) /
               (float)((k - 3) * (k - 3));
        c->step = 1;
        while (((float)(c->step * c->step) * (float)rp->max_samples < area ||
                (c->x1 - c->x0) / c->step >= RCOL_MAX || (c->y1 - c->y0) / c->step >= RROW_MAX) &&
               c->step < 1024)
            c->step++;
    }
    {
        /* the pixel set: each lattice row's members from the first to the
         * last (the set is convex: an affine image of a square, mildly bent) */
        rmap q0;
        int ncol = (c->x1 - c->x0) / c->step + 1, r;
        if (!rmap_init(&c->G0, &q0))
            return ACTAG_ERR_NO_MATCH;
        /* every sweep visits the same columns: their directions once (up
         * to the first too far off the centre beam: rlattice_plane asks
         * rcolumn_dir for the columns past ndir) */
        c->ndir = 0;
        if (c->geo != NULL) {
            int nd = ncol < RDIR_MAX ? ncol : RDIR_MAX;
            while (c->ndir < nd &&
                   rcolumn_dir(c, c->ndir, &c->dir[2 * c->ndir], &c->dir[2 * c->ndir + 1]))
                c->ndir++;
        }
        c->nrow = (c->y1 - c->y0) / c->step + 1;
        for (r = 0; r < c->nrow; r++) {
            float rr = rrange(c, c->y0 + r * c->step);
            int a = 0, b = ncol - 1;
            while (a < ncol && !rmember(c, &q0, rr, a))
                a++;
            while (b > a && !rmember(c, &q0, rr, b))
                b--;
            if (a < ncol) {
                c->ja[r] = (uint8_t)a;
                c->jb[r] = (uint8_t)b;
                (*count) += b - a + 1;
            } else {
                c->ja[r] = 1;
                c->jb[r] = 0;
            }
        }
        if ((*count) < 16)
            return ACTAG_ERR_NO_MATCH;
    }
    return ACTAG_OK;
}

int actag__refine_corners_max16(const void *img, int depth, uint32_t max16, int rows, int cols,
                                int stride, const actag_sonar_geometry *geometry, float tag_size,
                                const actag_family *family, int id, const actag_point corners[4],
                                const actag_refine_params *rp, actag_point out[4],
                                actag_refine_info *info)
{
    rctx c;
    rgrid G;
    float cl[6], rss = 0.0f, shift2 = 0.0f, cu[4], cv[4];
    actag_point p[4];
    int k, bits, i, rc, count = 0, iters = 0, steps, lsub;

    if (img == NULL || family == NULL || corners == NULL || rp == NULL || out == NULL)
        return ACTAG_ERR_NULL;
    if (rows < 1 || cols < 1 || rows > ACTAG_MAX_DIM || cols > ACTAG_MAX_DIM || stride < cols)
        return ACTAG_ERR_SIZE;
    if (depth != 8 && depth != 16)
        return ACTAG_ERR_PARAM;
    if (info)
        memset(info, 0, sizeof *info);
    bits = family->bits;
    if (bits < 16 || bits > 4 * RK_MAX || bits % 4 != 0 || family->codes == NULL || id < 0 ||
        id >= family->ncodes)
        return ACTAG_ERR_PARAM;
    if (!(rp->blur >= 0.25f && rp->blur <= 20.0f) || !(rp->margin >= 0.0f && rp->margin <= 1.0f) ||
        rp->max_iterations < 1 || rp->max_iterations > 50 ||
        !(rp->max_shift > 0.0f && rp->max_shift <= 2.0f) || rp->max_samples < 64 ||
        rp->max_samples > 100000)
        return ACTAG_ERR_PARAM;
    if (geometry != NULL && !(tag_size > 0.0f && tag_size < ACTAG_MAX_TAG_SIZE))
        return ACTAG_ERR_PARAM;
    for (i = 0; i < 4; i++) /* all checked before out is written */
        if (!finite_f(corners[i].x) || !finite_f(corners[i].y))
            return ACTAG_ERR_PARAM;
    for (i = 0; i < 4; i++)
        out[i] = corners[i];
    k = bits / 4;
    rc = rsetup(&c, &G, &count, img, depth, max16, rows, cols, stride, geometry, tag_size, family,
                id, corners, rp);
    if (rc != ACTAG_OK)
        return rc;

    /* pass 1: wide edges (a basin for corners a cell off) on every sub-th
     * lattice row and column, sub leaving at least RSUB1 pixels; pass 2: the
     * blur, every pixel */
    rwidths(&c, &G, rp->blur, 0.4f);
    {
        int sub = 1;
        while (sub < 4 && count >= (sub + 1) * (sub + 1) * RSUB1)
            sub++;
        lsub = 1;
        while (lsub < 4 && count >= (lsub + 1) * (lsub + 1) * RSUBL)
            lsub++;
        steps = rpass(&c, &G, cl, sub, sub, rp->max_iterations, RTOL1, &rss, &count);
    }
    if (steps < 0) {
        DBG("refine: pass 1 failed\n");
        return ACTAG_ERR_NO_MATCH;
    }
    iters += steps;
    DBG("refine: lattice step %d, pass 1: %d steps, %d pixels\n", c.step, steps, count);
    rwidths(&c, &G, rp->blur, 0.05f);
    steps = rpass(&c, &G, cl, 1, lsub, rp->max_iterations, RTOL2, &rss, &count);
    if (steps < 0) {
        DBG("refine: pass 2 failed\n");
        return ACTAG_ERR_NO_MATCH;
    }
    iters += steps;
    DBG("refine: pass 2: %d steps, %d pixels\n", steps, count);

    /* acceptance: finite, same handedness, cell sides within 25 % (or grown
     * to at most the tag's own cell size: rgrown_ok), white brighter than
     * black, no corner moved more than max_shift cells */
    if (!rshape_ok(c.cell2, c.G0.p, G.p))
        return ACTAG_ERR_NO_MATCH;
    if (!(cl[1] > 0.0f))
        return ACTAG_ERR_NO_MATCH;
    cu[0] = cu[3] = cv[0] = cv[1] = 2.0f - c.g;
    cu[1] = cu[2] = cv[2] = cv[3] = (float)(k - 1) - c.g;
    for (i = 0; i < 4; i++) {
        float X, Y, w[2], Ki[4], d2;
        rforward(&G, cu[i], cv[i], &X, &Y);
        rpixel(&c, X, Y, &p[i]);
        if (!finite_f(p[i].x) || !finite_f(p[i].y) || !rinvert(&c.G0, X, Y, w, Ki))
            return ACTAG_ERR_NO_MATCH;
        d2 = (w[0] - cu[i]) * (w[0] - cu[i]) + (w[1] - cv[i]) * (w[1] - cv[i]);
        shift2 = d2 > shift2 ? d2 : shift2;
    }
    if (shift2 > rp->max_shift * rp->max_shift) {
        DBG("refine: shift %g cells\n", (double)actag_sqrtf(shift2));
        return ACTAG_ERR_NO_MATCH;
    }
    if (info) {
        info->samples = count;
        info->iterations = iters;
        info->rms = count > 0 ? actag_sqrtf(rss / (float)count) : 0.0f;
        info->contrast = cl[1];
        info->shift = actag_sqrtf(shift2);
    }
    for (i = 0; i < 4; i++)
        out[i] = p[i];
    return ACTAG_OK;
}

int actag__refine_probe(const uint8_t *img, int rows, int cols, int stride,
                        const actag_sonar_geometry *geometry, float tag_size,
                        const actag_family *family, int id, const actag_point corners[4],
                        float blur, const float dp[6], float *rss, float b[6], float A[21],
                        float start[6])
{
    actag_refine_params rp;
    actag_point out[4];
    rctx c;
    rgrid G, T;
    rsums S;
    float cl[6], r0;
    int i, rc, count;
    if (img == NULL || family == NULL || corners == NULL || dp == NULL || rss == NULL ||
        b == NULL || A == NULL)
        return ACTAG_ERR_NULL;
    actag_refine_params_default(&rp);
    rp.blur = blur;
    /* the public entry's checks, on a copy of the corners it would write */
    if (rows < 1 || cols < 1 || rows > ACTAG_MAX_DIM || cols > ACTAG_MAX_DIM || stride < cols)
        return ACTAG_ERR_SIZE;
    if (family->bits < 16 || family->bits > 4 * RK_MAX || family->bits % 4 != 0 ||
        family->codes == NULL || id < 0 || id >= family->ncodes ||
        !(blur >= 0.25f && blur <= 20.0f) ||
        (geometry != NULL && !(tag_size > 0.0f && tag_size < ACTAG_MAX_TAG_SIZE)))
        return ACTAG_ERR_PARAM;
    for (i = 0; i < 4; i++) {
        if (!finite_f(corners[i].x) || !finite_f(corners[i].y))
            return ACTAG_ERR_PARAM;
        out[i] = corners[i];
    }
    rc = rsetup(&c, &G, &count, img, 8, 0u, rows, cols, stride, geometry, tag_size, family, id,
                out, &rp);
    if (rc != ACTAG_OK)
        return rc;
    rwidths(&c, &G, rp.blur, 0.05f);
    rcurv(&c, &G);
    if (!rsweep_levels(&c, &G, 1, &S) || !rbest(&S, cl, &r0))
        return ACTAG_ERR_NO_MATCH;
    T = G;
    for (i = 0; i < 6; i++)
        T.p[i] += dp[i];
    rcurv(&c, &T);
    if (!rsweep_grid(&c, &T, cl, 1, &S))
        return ACTAG_ERR_NO_MATCH;
    *rss = S.ss;
    memcpy(b, S.b, sizeof S.b);
    memcpy(A, S.A, sizeof S.A);
    if (start != NULL)
        memcpy(start, G.p, sizeof G.p);
    return ACTAG_OK;
}
