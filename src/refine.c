/* Sub-pixel corners of a decoded tag: the known template fitted to the grey
 * image by Gauss-Newton over the tag's grid (see actag/refine.h). */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/refine.h"
#include "actag/decode.h"

#include <string.h>

#ifdef REFINE_DEBUG
#include <stdio.h>
#define DBG(...) fprintf(stderr, __VA_ARGS__)
#else
#define DBG(...) ((void)0)
#endif

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
} rgrid;

typedef struct rctx {
    const uint8_t *img;
    int rows, cols, stride;
    const actag_sonar_geometry *geo; /* NULL: plane = pixels */
    float ac;                        /* azimuth of the centre beam */
    float cell2;                     /* squared cell side, m^2 (0: no curvature) */
    int n;                           /* k + 1 cells per side */
    float g;                         /* grid centre, cells */
    float L[RN_MAX * RN_MAX];
    int x0, y0, x1, y1, step;        /* the pixel lattice */
    rgrid G0;                        /* the start grid: decides the pixel set */
    float lo, hi;                    /* grid range of the pixel set */
    float wu, wv;                    /* template edge half-widths, cells */
} rctx;

static int finite_f(float x) { return x == x && x - x == 0.0f; }

/* sin, cos of a small angle (|d| <= 0.6: Taylor, error < 1e-8) */
static void rsincos(float d, float *s, float *c)
{
    float d2 = d * d;
    *s = d * (1.0f - d2 / 6.0f * (1.0f - d2 / 20.0f * (1.0f - d2 / 42.0f * (1.0f - d2 / 72.0f))));
    *c = 1.0f - d2 / 2.0f * (1.0f - d2 / 12.0f * (1.0f - d2 / 30.0f * (1.0f - d2 / 56.0f)));
}

/* atan(t), |t| <= 0.7 (series, error < 2e-7 there) */
static float ratan(float t)
{
    float t2 = t * t, s = 0.0f;
    int i;
    for (i = 25; i >= 1; i -= 2)
        s = 1.0f / (float)i - t2 * s;
    return t * s;
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
    rsincos(d, &sn, &cs);
    *X = r * cs;
    *Y = r * sn;
    return 1;
}

/* Image column of azimuth a (inverse of actag_geometry_azimuth). */
static float rcolumn(const actag_sonar_geometry *geo, int cols, float a)
{
    if (geo->bearings != NULL) {
        const float *b = geo->bearings;
        int lo = 0, hi = cols - 1, up;
        if (cols < 2)
            return 0.0f;
        up = b[cols - 1] > b[0];
        while (hi - lo > 1) { /* the interval holding a (extrapolated at the ends) */
            int mid = (lo + hi) / 2;
            if ((b[mid] <= a) == (up != 0))
                lo = mid;
            else
                hi = mid;
        }
        return (float)lo + (a - b[lo]) / (b[lo + 1] - b[lo]);
    } else {
        float half = 0.5f * geo->aperture;
        float step = cols > 1 ? geo->aperture / (float)(cols - 1) : 1.0f;
        if (geo->flags & ACTAG_AZIMUTH_ASCENDING)
            return (a + half) / step;
        return (half - a) / step;
    }
}

/* Image row of range r. */
static float rrow(const actag_sonar_geometry *geo, int rows, float r)
{
    float step = actag_geometry_range_step(geo, rows);
    if (!(step > 0.0f))
        return 0.0f;
    if (geo->flags & ACTAG_RANGE_ASCENDING)
        return (r - geo->min_range) / step;
    return (geo->max_range - r) / step;
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
    a = c->ac + ratan(Y / X);
    p->x = rcolumn(c->geo, c->cols, a);
    p->y = rrow(c->geo, c->rows, r);
}

/* Q = cell^2 I - M'M, made positive semi-definite: w'Qw is the squared
 * out-of-fan (elevation) extent of grid offset w, which a tag of known size
 * needs beside its in-fan extent M w. */
static void rcurv(const rctx *c, rgrid *G)
{
    float a11, a12, a22, h, t, dsc, l1, l2;
    G->r0 = actag_sqrtf(G->p[0] * G->p[0] + G->p[1] * G->p[1]);
    G->Q[0] = G->Q[1] = G->Q[2] = 0.0f;
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

/* Is pixel (x, y) in the fixed set?  Its plane point and offset when so. */
static int rmember(const rctx *c, int x, int y, float *X, float *Y)
{
    float w[2], Ki[4];
    if (!rplane(c, (float)x, (float)y, X, Y) || !rinvert(&c->G0, *X, *Y, w, Ki))
        return 0;
    return w[0] + c->g >= c->lo && w[0] + c->g <= c->hi && w[1] + c->g >= c->lo &&
           w[1] + c->g <= c->hi;
}

/* Cubic step: 0 below -1, 1 above 1; its derivative. */
static float rstep(float z, float *dz)
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

/* Smoothed indicator of [0, 1] at t (half-width w), and d/dt. */
static float rind(float t, float w, float *d)
{
    float d0, d1, s0 = rstep(t / w, &d0), s1 = rstep((t - 1.0f) / w, &d1);
    *d = (d0 - d1) / w;
    return s0 - s1;
}

static float layout_at(const rctx *c, int cu, int cv)
{
    if (cu < 0 || cv < 0 || cu >= c->n || cv >= c->n)
        return 0.0f;
    return c->L[cv * c->n + cu];
}

/* Template P(u, v) and its gradient. */
static float rtemplate(const rctx *c, float u, float v, float *pu, float *pv)
{
    float fu = u < -2.0f ? -2.0f : u > (float)c->n + 2.0f ? (float)c->n + 2.0f : u;
    float fv = v < -2.0f ? -2.0f : v > (float)c->n + 2.0f ? (float)c->n + 2.0f : v;
    int iu = (int)(fu + 2.0f) - 2, iv = (int)(fv + 2.0f) - 2, a, b;
    float su[3], du[3], sv[3], dv[3], P = 0.0f, Pu = 0.0f, Pv = 0.0f;
    for (a = 0; a < 3; a++) {
        su[a] = rind(u - (float)(iu + a - 1), c->wu, &du[a]);
        sv[a] = rind(v - (float)(iv + a - 1), c->wv, &dv[a]);
    }
    for (b = 0; b < 3; b++)
        for (a = 0; a < 3; a++) {
            float l = layout_at(c, iu + a - 1, iv + b - 1);
            if (l == 0.0f)
                continue;
            P += l * su[a] * sv[b];
            Pu += l * du[a] * sv[b];
            Pv += l * su[a] * dv[b];
        }
    *pu = Pu;
    *pv = Pv;
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

/* The levels c for grid G (linear least squares) and the residual sum of
 * squares; 0 when singular. */
static int rlevels(const rctx *c, const rgrid *G, float cl[6], float *rss, int *count)
{
    float A[36], y[6], yy = 0.0f;
    int x, yq, i, j, nn = 0;
    float sn = 1.0f / (float)c->n;
    memset(A, 0, sizeof A);
    memset(y, 0, sizeof y);
    for (yq = c->y0; yq <= c->y1; yq += c->step) {
        const uint8_t *row = c->img + (size_t)yq * (size_t)c->stride;
        for (x = c->x0; x <= c->x1; x += c->step) {
            float X, Y, w[2], Ki[4], P, pu, pv, R[6], I;
            if (!rmember(c, x, yq, &X, &Y))
                continue;
            if (!rinvert(G, X, Y, w, Ki))
                return 0;
            P = rtemplate(c, w[0] + c->g, w[1] + c->g, &pu, &pv);
            R[0] = 1.0f;
            R[1] = P;
            R[4] = w[0] * sn;
            R[5] = w[1] * sn;
            R[2] = P * R[4];
            R[3] = P * R[5];
            I = (float)row[x] - 128.0f;
            for (i = 0; i < 6; i++) {
                for (j = 0; j <= i; j++)
                    A[i * 6 + j] += R[i] * R[j];
                y[i] += R[i] * I;
            }
            yy += I * I;
            nn++;
        }
    }
    if (nn < 16)
        return 0;
    for (i = 0; i < 6; i++) {
        for (j = 0; j < i; j++)
            A[j * 6 + i] = A[i * 6 + j];
        A[i * 6 + i] *= 1.0f + 1e-6f;
        A[i * 6 + i] += 1e-6f * (float)nn;
    }
    memcpy(cl, y, sizeof y);
    if (!rsolve(A, cl, 6))
        return 0;
    *rss = yy;
    for (i = 0; i < 6; i++)
        *rss -= cl[i] * y[i];
    if (*rss < 0.0f)
        *rss = 0.0f;
    *count = nn;
    return 1;
}

/* Normal equations of the grid's 6 numbers with the levels cl (and Q) held. */
static int rnormal(const rctx *c, const rgrid *G, const float cl[6], float JJ[36], float Jr[6])
{
    float sn = 1.0f / (float)c->n;
    int x, yq, i, j;
    memset(JJ, 0, 36 * sizeof(float));
    memset(Jr, 0, 6 * sizeof(float));
    for (yq = c->y0; yq <= c->y1; yq += c->step) {
        const uint8_t *row = c->img + (size_t)yq * (size_t)c->stride;
        for (x = c->x0; x <= c->x1; x += c->step) {
            float X, Y, w[2], Ki[4], P, pu, pv, up, vp, gain, Tu, Tv, h0, h1, J[6], r;
            if (!rmember(c, x, yq, &X, &Y))
                continue;
            if (!rinvert(G, X, Y, w, Ki))
                return 0;
            P = rtemplate(c, w[0] + c->g, w[1] + c->g, &pu, &pv);
            up = w[0] * sn;
            vp = w[1] * sn;
            gain = cl[1] + cl[2] * up + cl[3] * vp;
            r = (float)row[x] - 128.0f - (cl[0] + gain * P + cl[4] * up + cl[5] * vp);
            Tu = gain * pu + (cl[2] * P + cl[4]) * sn;
            Tv = gain * pv + (cl[3] * P + cl[5]) * sn;
            /* dw = -K^-1 (dm + dM w): dT/dm_i = -h_i, dT/dM_ij = -h_i w_j,
             * h = K^-T (Tu, Tv) */
            h0 = Ki[0] * Tu + Ki[2] * Tv;
            h1 = Ki[1] * Tu + Ki[3] * Tv;
            J[0] = -h0;
            J[1] = -h1;
            J[2] = -h0 * w[0];
            J[3] = -h1 * w[0];
            J[4] = -h0 * w[1];
            J[5] = -h1 * w[1];
            for (i = 0; i < 6; i++) {
                for (j = 0; j <= i; j++)
                    JJ[i * 6 + j] += J[i] * J[j];
                Jr[i] += J[i] * r;
            }
        }
    }
    for (i = 0; i < 6; i++)
        for (j = 0; j < i; j++)
            JJ[j * 6 + i] = JJ[i * 6 + j];
    return 1;
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
}

/* One Levenberg-Marquardt pass; returns the steps taken, -1 on failure. */
static int rpass(const rctx *c, rgrid *G, int max_it, float *rss_out, float cl_out[6],
                 int *count)
{
    float cl[6], rss, lambda = 1e-3f;
    int it, taken = 0;
    rcurv(c, G);
    if (!rlevels(c, G, cl, &rss, count))
        return -1;
    for (it = 0; it < max_it; it++) {
        float JJ[36], Jr[6], A[36], d[6];
        int i, tries, ok = 0;
        if (!rnormal(c, G, cl, JJ, Jr))
            return -1;
        for (tries = 0; tries < 4 && !ok; tries++) {
            rgrid T = *G;
            float cl2[6], rss2;
            int cnt;
            memcpy(A, JJ, sizeof A);
            memcpy(d, Jr, sizeof d);
            for (i = 0; i < 6; i++)
                A[i * 6 + i] = JJ[i * 6 + i] * (1.0f + lambda) + 1e-12f;
            if (!rsolve(A, d, 6)) {
                lambda *= 10.0f;
                continue;
            }
            for (i = 0; i < 6; i++)
                T.p[i] += d[i];
            rcurv(c, &T);
            if (rlevels(c, &T, cl2, &rss2, &cnt) && rss2 <= rss) {
                /* converged when no corner moves by 1e-3 of a cell */
                float mv = (d[0] * d[0] + d[1] * d[1]) +
                           4.0f * (d[2] * d[2] + d[3] * d[3] + d[4] * d[4] + d[5] * d[5]);
                float cs = G->p[2] * G->p[2] + G->p[3] * G->p[3];
                *G = T;
                memcpy(cl, cl2, sizeof cl);
                rss = rss2;
                lambda *= 0.1f;
                if (lambda < 1e-6f)
                    lambda = 1e-6f;
                ok = 1;
                taken++;
                if (mv < 1e-6f * cs)
                    it = max_it;
            } else {
                lambda *= 10.0f;
            }
        }
        if (!ok)
            break;
    }
    *rss_out = rss;
    memcpy(cl_out, cl, sizeof cl);
    return taken;
}

int actag_refine_corners(const uint8_t *img, int rows, int cols, int stride,
                         const actag_sonar_geometry *geometry, float tag_size,
                         const actag_family *family, int id, const actag_point corners[4],
                         const actag_refine_params *rp, actag_point out[4],
                         actag_refine_info *info)
{
    rctx c;
    rgrid G;
    float H[9], cl[6], rss = 0.0f, shift2 = 0.0f, cu[4], cv[4];
    actag_point pl[4], p[4];
    int k, bits, i, cx, cy, rc, count = 0, iters = 0, steps;
    uint32_t code;

    if (img == NULL || family == NULL || corners == NULL || rp == NULL || out == NULL)
        return ACTAG_ERR_NULL;
    if (rows < 1 || cols < 1 || rows > ACTAG_MAX_DIM || cols > ACTAG_MAX_DIM || stride < cols)
        return ACTAG_ERR_SIZE;
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
    if (geometry != NULL && !(tag_size > 0.0f && tag_size < 1e3f))
        return ACTAG_ERR_PARAM;
    for (i = 0; i < 4; i++) {
        if (!finite_f(corners[i].x) || !finite_f(corners[i].y))
            return ACTAG_ERR_PARAM;
        out[i] = corners[i];
    }
    k = bits / 4;
    memset(&c, 0, sizeof c);
    c.img = img;
    c.rows = rows;
    c.cols = cols;
    c.stride = stride;
    c.geo = geometry;
    c.n = k + 1;
    c.g = 0.5f * (float)c.n;
    c.lo = rp->margin;
    c.hi = (float)c.n - rp->margin;
    /* the layout as printed (corners are in tag order: no rotation) */
    code = family->codes[id];
    for (cy = 0; cy < c.n; cy++)
        for (cx = 0; cx < c.n; cx++)
            c.L[cy * c.n + cx] = (cx >= 2 && cy >= 2 && cx <= k - 2 && cy <= k - 2) ? 1.0f : 0.0f;
    for (i = 0; i < bits; i++) {
        int q = i / k, j = i % k;
        cx = q == 0 ? j : q == 1 ? k : q == 2 ? k - j : 0;
        cy = q == 0 ? 0 : q == 1 ? j : q == 2 ? k : k - j;
        c.L[cy * c.n + cx] = (float)((code >> (bits - 1 - i)) & 1u);
    }

    /* the start grid: the corners' affine fit in the fan plane */
    if (geometry != NULL) {
        float mx = 0.25f * (corners[0].x + corners[1].x + corners[2].x + corners[3].x);
        c.ac = actag_geometry_azimuth(geometry, cols, mx);
        c.cell2 = tag_size / (float)(k - 3);
        c.cell2 *= c.cell2;
    }
    for (i = 0; i < 4; i++)
        if (!rplane(&c, corners[i].x, corners[i].y, &pl[i].x, &pl[i].y))
            return ACTAG_ERR_PARAM;
    rc = actag_tag_affine(pl, bits, H);
    if (rc != ACTAG_OK)
        return rc;
    G.p[0] = H[0] * c.g + H[1] * c.g + H[2];
    G.p[1] = H[3] * c.g + H[4] * c.g + H[5];
    G.p[2] = H[0];
    G.p[3] = H[3];
    G.p[4] = H[1];
    G.p[5] = H[4];
    for (i = 0; i < 6; i++)
        if (!finite_f(G.p[i]))
            return ACTAG_ERR_PARAM;
    rcurv(&c, &G);
    c.G0 = G;
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
            u = c.lo + u * (c.hi - c.lo) - c.g;
            v = c.lo + v * (c.hi - c.lo) - c.g;
            rgrid_pixel(&c, &G, u, v, &q);
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
        c.x0 = bx0 < 0.0f ? 0 : (int)bx0 + 1;
        c.y0 = by0 < 0.0f ? 0 : (int)by0 + 1;
        c.x1 = bx1 > (float)(cols - 1) ? cols - 1 : (int)bx1;
        c.y1 = by1 > (float)(rows - 1) ? rows - 1 : (int)by1;
        if (c.x1 < c.x0 || c.y1 < c.y0)
            return ACTAG_ERR_NO_MATCH;
        /* the set covers about the corners' quad's area x ((hi - lo) / (k - 3))^2 */
        area = 0.5f * ((corners[2].x - corners[0].x) * (corners[3].y - corners[1].y) -
                       (corners[3].x - corners[1].x) * (corners[2].y - corners[0].y));
        area = (area < 0.0f ? -area : area) * (c.hi - c.lo) * (c.hi - c.lo) /
               (float)((k - 3) * (k - 3));
        c.step = 1;
        while ((float)(c.step * c.step) * (float)rp->max_samples < area && c.step < 64)
            c.step++;
    }

    /* pass 1: wide edges (a basin for corners a cell off); pass 2: the blur */
    rwidths(&c, &G, rp->blur, 0.4f);
    steps = rpass(&c, &G, rp->max_iterations, &rss, cl, &count);
    if (steps < 0) {
        DBG("refine: pass 1 failed\n");
        return ACTAG_ERR_NO_MATCH;
    }
    iters += steps;
    rwidths(&c, &G, rp->blur, 0.05f);
    steps = rpass(&c, &G, rp->max_iterations, &rss, cl, &count);
    if (steps < 0) {
        DBG("refine: pass 2 failed\n");
        return ACTAG_ERR_NO_MATCH;
    }
    iters += steps;

    /* acceptance: finite, same handedness, cell sides within 25 %, white
     * brighter than black, no corner moved more than max_shift cells */
    {
        const rgrid *S = &c.G0;
        float la = S->p[2] * S->p[2] + S->p[3] * S->p[3];
        float lb = S->p[4] * S->p[4] + S->p[5] * S->p[5];
        float la2 = G.p[2] * G.p[2] + G.p[3] * G.p[3];
        float lb2 = G.p[4] * G.p[4] + G.p[5] * G.p[5];
        for (i = 0; i < 6; i++)
            if (!finite_f(G.p[i]))
                return ACTAG_ERR_NO_MATCH;
        if ((G.p[2] * G.p[5] - G.p[4] * G.p[3]) * (S->p[2] * S->p[5] - S->p[4] * S->p[3]) <=
            0.0f)
            return ACTAG_ERR_NO_MATCH;
        if (la2 > 1.5625f * la || la2 < 0.5625f * la || lb2 > 1.5625f * lb ||
            lb2 < 0.5625f * lb) {
            DBG("refine: sides %g %g\n", (double)(la2 / la), (double)(lb2 / lb));
            return ACTAG_ERR_NO_MATCH;
        }
    }
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
