/* RANSAC parallelogram fit to one contour (paper Algorithm 2); see quad.h. */
#include "actag/quad.h"

#include <math.h>
#include <string.h>

#if defined(__clang__)
/* Fused multiply-add would change results between x86 and ARM. (GCC in
 * -std=c99 mode does not contract; it warns about this pragma.) */
#pragma STDC FP_CONTRACT OFF
#endif

/* Adjacent sides must differ by at least asin(0.2) (11.5 degrees). */
#define QUAD_MIN_ADJ_SIN 0.2f
/* Unrefined quads below min_inlier_ratio minus this are not worth refining. */
#define QUAD_PROMISE 0.1f
/* Refinement passes (re-assign points to sides, refit, re-intersect). */
#define QUAD_REFINE_PASSES 8
/* Refinement stops once no corner moves by more than this (px). */
#define QUAD_CONVERGED 0.01f
/* Smallest band (px) around a side used for refitting it. */
#define QUAD_MIN_BAND 1.5f
/* Each side's nearest inliers must spread over this fraction of it. */
#define QUAD_MIN_SPAN 0.5f
#ifndef QUAD_TRIM
#define QUAD_TRIM 0.0f
#endif

/* Exact moment sums of integer points (relative to the contour origin). */
typedef struct qsums {
    int64_t n, sx, sy, sxx, sxy, syy;
} qsums;

/* The line nx*x + ny*y = c, (nx, ny) a unit normal. */
typedef struct qline {
    float nx, ny, c;
} qline;

/* A quad: line[j] and line[j+1] meet at corner j, so the side from corner j
 * to corner j+1 lies on line[j+1]. */
typedef struct qquad {
    qline line[4];
    float x[4], y[4];
} qquad;

/* Everything that stays fixed during one call. */
typedef struct qctx {
    const actag_ipoint *pts;
    int n;
    int ox, oy;       /* origin: bounding-box minimum */
    float bw, bh;     /* bounding-box extent (max - min) */
    float cx, cy;     /* centroid, relative to the origin */
    float d, d2;      /* inlier distance and its square */
    float ratio;      /* inlier fraction that ends the search at once */
    float min_ratio;  /* inlier fraction required of the best quad found */
    float pcos;       /* min |cos| between opposite sides */
} qctx;

void actag_quad_params_default(actag_quad_params *p)
{
    if (!p)
        return;
    p->max_iterations = 500;
    p->sample_fraction = 0.10f;
    p->inlier_ratio = 0.85f;
    p->min_inlier_ratio = 0.80f;
    p->inlier_distance = 2.5f;
    p->min_parallel_cos = 0.9f;
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

/* Total-least-squares line through the summed points. *msr receives the mean
 * squared perpendicular residual. Returns 0 when the points have no
 * direction (fewer than 2, all equal, or isotropic). The centred moments are
 * formed exactly in 64-bit integers: coordinates are < 2^16 and n < 2^15, so
 * n*sxx and sx*sx stay below 2^62. */
static int line_fit(const qsums *s, qline *l, float *msr)
{
    int64_t a64, b64, c64;
    float fn, inv, a, b, c, hd, r, dx, dy, len2, il;
    if (s->n < 2)
        return 0;
    a64 = s->n * s->sxx - s->sx * s->sx;
    b64 = s->n * s->sxy - s->sx * s->sy;
    c64 = s->n * s->syy - s->sy * s->sy;
    fn = (float)s->n;
    inv = 1.0f / (fn * fn);
    a = (float)a64 * inv; /* covariance matrix [a b; b c], pixels^2 */
    b = (float)b64 * inv;
    c = (float)c64 * inv;
    hd = 0.5f * (a - c);
    r = sqrtf(hd * hd + b * b);
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
    il = 1.0f / sqrtf(len2);
    l->nx = -dy * il;
    l->ny = dx * il;
    l->c = l->nx * ((float)s->sx / fn) + l->ny * ((float)s->sy / fn);
    if (msr) {
        float m = 0.5f * (a + c) - r;
        *msr = m > 0.0f ? m : 0.0f;
    }
    return 1;
}

/* Monotone stand-in for the angle of (dx, dy) in [0, 4): increases clockwise
 * on screen (y down). Only a division, so it is exact across platforms. */
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
 * sides long enough, corners near the contour, opposite sides parallel. */
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

/* Per-side extents from quad_inliers(). */
typedef struct qstats {
    float tmin[4], tmax[4]; /* extent along side j of the inliers nearest it */
    float len[4];           /* length of side j */
} qstats;

/* Counts the points within d of the quad's sides (side j runs from corner j
 * to corner j+1). With st non-NULL, also records how far along its nearest
 * side each inlier lies. */
static int quad_inliers(const qctx *k, const qquad *q, qstats *st)
{
    float ax[4], ay[4], ux[4], uy[4], len[4];
    int j, i, count = 0;
    for (j = 0; j < 4; j++) {
        int j1 = (j + 1) & 3;
        float ex = q->x[j1] - q->x[j], ey = q->y[j1] - q->y[j];
        float l = sqrtf(ex * ex + ey * ey);
        ax[j] = q->x[j];
        ay[j] = q->y[j];
        ux[j] = l > 0.0f ? ex / l : 0.0f;
        uy[j] = l > 0.0f ? ey / l : 0.0f;
        len[j] = l;
        if (st) {
            st->tmin[j] = l;
            st->tmax[j] = 0.0f;
            st->len[j] = l;
        }
    }
    for (i = 0; i < k->n; i++) {
        float px = (float)(k->pts[i].x - k->ox), py = (float)(k->pts[i].y - k->oy);
        float best = k->d2, bt = 0.0f;
        int bj = -1;
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
                bt = t;
                if (!st)
                    break; /* counting only: one side is enough */
            }
        }
        if (bj < 0)
            continue;
        count++;
        if (st) {
            float tc = bt < 0.0f ? 0.0f : (bt > len[bj] ? len[bj] : bt);
            st->tmin[bj] = tc < st->tmin[bj] ? tc : st->tmin[bj];
            st->tmax[bj] = tc > st->tmax[bj] ? tc : st->tmax[bj];
        }
    }
    return count;
}

static float ratio_of(int count, int n) { return (float)count / (float)n; }

/* Inlier ratio of the quad, or -1 unless every side is supported by its
 * nearest inliers over at least QUAD_MIN_SPAN of its length (a line fitted
 * to stray points can otherwise close a quad whose inlier count passes while
 * most of a short side is missed). */
static float quad_support(const qctx *k, const qquad *q)
{
    qstats st;
    float r = ratio_of(quad_inliers(k, q, &st), k->n);
    int j;
    for (j = 0; j < 4; j++)
        if (!(st.tmax[j] - st.tmin[j] >= QUAD_MIN_SPAN * st.len[j]))
            return -1.0f;
    return r;
}

/* Final acceptance: shape including parallel sides, support, inlier ratio. */
static int quad_accept(const qctx *k, const qquad *q, float *ratio)
{
    float r;
    if (!quad_shape_ok(k, q, 1))
        return 0;
    r = quad_support(k, q);
    if (!(r >= k->min_ratio))
        return 0;
    *ratio = r;
#ifdef QUAD_DEBUG
    {
        qstats st; int j; float ms = 1e9f, ex = 0, e;
        (void)quad_inliers(k, q, &st);
        for (j = 0; j < 4; j++) { float f = (st.tmax[j] - st.tmin[j]) / st.len[j]; ms = f < ms ? f : ms;
            e = -q->x[j]; ex = e > ex ? e : ex; e = q->x[j] - k->bw; ex = e > ex ? e : ex; e = -q->y[j]; ex = e > ex ? e : ex; e = q->y[j] - k->bh; ex = e > ex ? e : ex; }
        fprintf(stderr, "ACCEPT ratio %.3f minspan %.3f bbox_excess %.2f px (%.3f of extent)\n", r, ms, ex, ex / (k->bw > k->bh ? k->bw : k->bh));
    }
#endif
    return 1;
}

/* Moments of each side's stretch of the contour, for refitting its line.
 * Each corner is tied to its nearest contour point; side j is the run of
 * contour points between the points of corners j and j+1 (in the contour's
 * own direction), less QUAD_TRIM * d at either end (corner rounding), less
 * points farther than sqrt(band2[j]) from the side's current line. Using the
 * contour order, not distances, keeps a short side's points on that side even
 * when a poor first guess tilts it. Returns 0 if the corners' contour points
 * are not distinct and in cyclic order. */
static int side_sums(const qctx *k, const qquad *q, const float *band2, qsums *sums)
{
    int ci[4], j, i, fwd = 1, bwd = 1, tf = 0, tb = 0;
    float bd[4];
    for (j = 0; j < 4; j++) {
        bd[j] = 3.0e38f;
        ci[j] = 0;
    }
    for (i = 0; i < k->n; i++) {
        float px = (float)(k->pts[i].x - k->ox), py = (float)(k->pts[i].y - k->oy);
        for (j = 0; j < 4; j++) {
            float dx = px - q->x[j], dy = py - q->y[j], e2 = dx * dx + dy * dy;
            if (e2 < bd[j]) {
                bd[j] = e2;
                ci[j] = i;
            }
        }
    }
    for (j = 0; j < 4; j++) {
        int a = ci[j], b = ci[(j + 1) & 3];
        int f = b - a < 0 ? b - a + k->n : b - a, g = a - b < 0 ? a - b + k->n : a - b;
        fwd &= f > 0;
        bwd &= g > 0;
        tf += f;
        tb += g;
    }
    fwd &= tf == k->n;
    bwd &= tb == k->n;
    if (!fwd && !bwd)
        return 0;
#ifdef QUAD_DEBUG
    fprintf(stderr, "ci %d %d %d %d fwd %d\n", ci[0], ci[1], ci[2], ci[3], fwd);
#endif
    for (j = 0; j < 4; j++) {
        int a = ci[j], b = ci[(j + 1) & 3], step = fwd ? 1 : -1;
        const qline *l = &q->line[(j + 1) & 3], *la = &q->line[j], *lb = &q->line[(j + 2) & 3];
        float ex = q->x[(j + 1) & 3] - q->x[j], ey = q->y[(j + 1) & 3] - q->y[j];
        float len = sqrtf(ex * ex + ey * ey), ux, uy, trim = QUAD_TRIM * k->d;
        qsums *s = &sums[(j + 1) & 3];
        if (!(len > 0.0f))
            return 0;
        ux = ex / len;
        uy = ey / len;
        if (trim > 0.2f * len)
            trim = 0.2f * len;
        memset(s, 0, sizeof *s);
        for (i = a; i != b; i += step) {
            int x, y;
            float px, py, t, e, ea, eb;
            if (i < 0)
                i += k->n;
            else if (i >= k->n)
                i -= k->n;
            if (i == b)
                break;
            x = k->pts[i].x - k->ox;
            y = k->pts[i].y - k->oy;
            px = (float)x;
            py = (float)y;
            t = (px - q->x[j]) * ux + (py - q->y[j]) * uy;
            e = fabsf(l->nx * px + l->ny * py - l->c);
            /* Near a corner, leave out points that the adjacent side's
             * line explains better: they belong to that side. */
            ea = fabsf(la->nx * px + la->ny * py - la->c);
            eb = fabsf(lb->nx * px + lb->ny * py - lb->c);
            if (t >= trim && t <= len - trim && e * e <= band2[j] && e <= ea && e <= eb)
                sums_add(s, x, y);
        }
    }
    return 1;
}

/* Refines a quad whose unrefined inlier ratio passed: each side's line is
 * refitted (total least squares) to its stretch of the contour, the lines
 * are re-intersected, QUAD_REFINE_PASSES times. Writes the accepted quad
 * (refined, else unrefined) and its inlier ratio, or returns 0. */
static int refine_and_accept(const qctx *k, const qquad *q0, qquad *best, float *best_ratio)
{
    qquad cur = *q0;
    float band2[4], moved;
    int pass, j, refined = 0;
    for (j = 0; j < 4; j++)
        band2[j] = 4.0f * k->d2; /* first pass: the guess may be tilted */
    for (pass = 0; pass < QUAD_REFINE_PASSES; pass++) {
        qsums sums[4];
        qquad nq = cur;
        if (!side_sums(k, &cur, band2, sums))
            break;
        for (j = 0; j < 4; j++) {
            qline l;
            float msr;
            if (sums[(j + 1) & 3].n >= 3 && line_fit(&sums[(j + 1) & 3], &l, &msr)) {
                /* Next pass keeps points within 2.5 sigma of the side (at
                 * least QUAD_MIN_BAND px, at most d), so outliers just inside
                 * d stop tilting it. */
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
        moved = 0.0f;
        for (j = 0; j < 4; j++) {
            float dx = nq.x[j] - cur.x[j], dy = nq.y[j] - cur.y[j];
            moved = dx * dx + dy * dy > moved ? dx * dx + dy * dy : moved;
        }
#ifdef QUAD_DEBUG
        for (j = 0; j < 4; j++) fprintf(stderr, " pass %d side %d n %d band %.2f corner %.2f %.2f\n", pass, j, (int)sums[(j+1)&3].n, sqrtf(band2[j]), nq.x[j]+(float)k->ox, nq.y[j]+(float)k->oy);
#endif
        cur = nq;
        refined = 1;
        if (moved < QUAD_CONVERGED * QUAD_CONVERGED)
            break;
    }
#ifdef QUAD_DEBUG
    for (j = 0; j < 4; j++) fprintf(stderr, "q0 %.3f %.3f   cur %.3f %.3f\n", q0->x[j] + (float)k->ox, q0->y[j] + (float)k->oy, cur.x[j] + (float)k->ox, cur.y[j] + (float)k->oy);
#endif
    if (refined && quad_accept(k, &cur, best_ratio)) {
        *best = cur;
        return 1;
    }
    /* Acceptance test of the
     * full shape (its ratio and support passed already). */
    if (quad_accept(k, q0, best_ratio)) {
        *best = *q0;
        return 1;
    }
    return 0;
}

/* Sums of the unclaimed points met walking from index *i until m of them are
 * taken (cyclic); with line non-NULL, only those within d of it. */
static void walk_sums(const qctx *k, const unsigned char *lab, int start, int m,
                      const qline *line, qsums *s)
{
    int i = start, got = 0;
    memset(s, 0, sizeof *s);
    while (got < m) {
        if (!lab[i]) {
            int x = k->pts[i].x - k->ox, y = k->pts[i].y - k->oy;
            got++;
            if (!line) {
                sums_add(s, x, y);
            } else {
                float dist = line->nx * (float)x + line->ny * (float)y - line->c;
                if (dist <= k->d && dist >= -k->d)
                    sums_add(s, x, y);
            }
        }
        if (++i == k->n)
            i = 0;
    }
}

/* Line through a run of m unclaimed points from a random start: fitted, then
 * refitted without the run's points farther than d from the first fit (a
 * spike in the run would tilt it); (*mx, *my) is the refit points' centroid.
 * Returns 0 if fewer than half of the run lie within d of its first fit (it
 * wraps a corner or the border is ragged there). */
static int sample_line(const qctx *k, const unsigned char *lab, int start, int m, qline *l,
                       float *mx, float *my)
{
    qsums s;
    float msr;
    walk_sums(k, lab, start, m, NULL, &s);
    if (!line_fit(&s, l, &msr))
        return 0;
    /* If the squared residuals sum to under d^2, every point is within d
     * and the refit would change nothing (1 % margin for rounding). */
    if (msr * (float)s.n > 0.99f * k->d2) {
        qline l0 = *l;
        walk_sums(k, lab, start, m, &l0, &s);
        if (2 * s.n < m || !line_fit(&s, l, NULL))
            return 0;
    }
    *mx = (float)s.sx / (float)s.n;
    *my = (float)s.sy / (float)s.n;
    return 1;
}

int actag_quad_fit(const actag_ipoint *pts, int npoints, const actag_quad_params *params,
                   actag_rng *rng, void *scratch, size_t scratch_size, actag_quad *out)
{
    qctx k;
    unsigned char *lab;
    float *fx, *fy;
    int n, m, i, it, minx, miny, maxx, maxy;
    int64_t sx = 0, sy = 0;
    int have = 0;
    float d, promise, best_r0 = 0.0f, best_ratio = 0.0f;
    qquad best;

    if (!pts || !params || !rng || !scratch || !out)
        return ACTAG_ERR_NULL;
    d = params->inlier_distance;
    if (npoints < 0 || params->max_iterations < 1 ||
        !(params->sample_fraction > 0.0f && params->sample_fraction <= 1.0f) ||
        !(params->inlier_ratio > 0.0f && params->inlier_ratio <= 1.0f) ||
        !(params->min_inlier_ratio > 0.0f && params->min_inlier_ratio <= 1.0f) ||
        !(d > 0.0f && d < 1e18f) ||
        !(params->min_parallel_cos >= 0.0f && params->min_parallel_cos <= 1.0f))
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
    k.pts = pts;
    k.n = n;
    k.ox = minx;
    k.oy = miny;
    k.bw = (float)(maxx - minx);
    k.bh = (float)(maxy - miny);
    k.cx = (float)(sx - (int64_t)minx * n) / (float)n;
    k.cy = (float)(sy - (int64_t)miny * n) / (float)n;
    k.d = d;
    k.d2 = d * d;
    k.ratio = params->inlier_ratio;
    k.min_ratio = params->min_inlier_ratio < k.ratio ? params->min_inlier_ratio : k.ratio;
    promise = k.min_ratio - QUAD_PROMISE;
    k.pcos = params->min_parallel_cos;

    m = (int)(params->sample_fraction * (float)n + 0.5f);
    if (m < 3)
        m = 3;
    if (m > n)
        m = n;

    /* Scratch: x and y relative to the origin as floats (aligned), then one
     * claim label per point. */
    {
        size_t mis = (size_t)((uintptr_t)scratch & 3u);
        fx = (float *)(void *)((unsigned char *)scratch + (mis ? 4u - mis : 0u));
    }
    fy = fx + n;
    lab = (unsigned char *)(fy + n);
    for (i = 0; i < n; i++) {
        fx[i] = (float)(pts[i].x - k.ox);
        fy[i] = (float)(pts[i].y - k.oy);
    }
    for (it = 0; it < params->max_iterations; it++) {
        qquad q, cand;
        qline lines[4];
        float key[4], r0, r;
        int nfree = n, claimed = 0, line, ok = 1, order[4];

        memset(lab, 0, (size_t)n);
        for (line = 0; line < 4 && ok; line++) {
            qline l;
            float mx, my, lnx, lny, lc;
            int cnt = 0;
            unsigned char tag = (unsigned char)(line + 1);
            if (nfree < m) {
                ok = 0;
                break;
            }
            /* A run along the border: on a quad it usually lies on one side. */
            if (!sample_line(&k, lab, (int)actag_rng_below(rng, (uint32_t)n), m, &l, &mx, &my)) {
                ok = 0;
                break;
            }
            /* Claim the free points within d of the line (branch-free so
             * the compiler can vectorise it: this loop is most of the time). */
            lnx = l.nx;
            lny = l.ny;
            lc = l.c;
            for (i = 0; i < n; i++) {
                float dist = lnx * fx[i] + lny * fy[i] - lc;
                int in = (lab[i] == 0) & (dist <= d) & (dist >= -d);
                lab[i] = (unsigned char)(lab[i] | (in ? tag : 0u));
                cnt += in;
            }
            if (cnt < 2) {
                ok = 0;
                break;
            }
            nfree -= cnt;
            claimed += cnt;
            lines[line] = l;
            /* Any point on each side orders the sides around an interior
             * point; the run's centroid will do. */
            key[line] = pseudo_angle(mx - k.cx, my - k.cy);
        }
        /* A quad's side inliers are a subset of the points its lines
         * claimed: too few claimed points cannot make a promising quad or
         * beat the best one so far. */
        if (!ok)
            continue;
        r = ratio_of(claimed, n);
        if (r < promise || r <= best_r0)
            continue;

        /* Order the lines clockwise around the centroid (insertion sort). */
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
        r0 = quad_support(&k, &q);
        if (r0 < promise || r0 <= best_r0)
            continue;
        /* A new best unrefined quad: refine and test it. */
        best_r0 = r0;
        if (!refine_and_accept(&k, &q, &cand, &r))
            continue;
        if (r >= k.ratio) { /* good enough: stop here */
            best = cand;
            best_ratio = r;
            have = 1;
            it++;
            break;
        }
        if (!have || r > best_ratio) {
            best = cand;
            best_ratio = r;
            have = 1;
        }
    }
    out->iterations = it;
    if (have) {
        /* Start at the topmost corner (then leftmost), judged on the
         * returned coordinates so the rule holds exactly for them. */
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
        return ACTAG_OK;
    }
    return ACTAG_ERR_NO_QUAD;
}
