/* 6-DOF tag pose from one sonar detection (see actag/pose.h). */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/pose.h"
#include "pose_model.h"
#include "rotation.h"

#include <math.h>

#define P_PI 3.14159265f
#define P_NPAR ACTAG__POSE_NPAR
#define P_NRES ACTAG__POSE_NRES
#define P_PASSES 3
#define P_STARTS 5      /* start elevations across the band, at least */
#define P_STARTS_MAX 17 /* and at most: a band wider than 16 degrees gets one start
                         * per P_START_STEP up to 64 degrees, 17 spread over wider */
#define P_START_STEP 0.0698f /* rad (4 degrees): the elevation cost's local minima lie a
                              * few degrees apart; a 150 degree aperture (a 133 degree
                              * band) with 5 starts (33 degrees apart) settled in one 3.4
                              * degrees off, with 17 (8.3 degrees apart) it did not
                              * (test_pose) */

static int p_finite(float v) { return v == v && v < 3.0e38f && v > -3.0e38f; }

/* Are the n values v all finite (p_finite)? */
static int p_all_finite(const float *v, int n)
{
    int i;
    for (i = 0; i < n; i++)
        if (!p_finite(v[i]))
            return 0;
    return 1;
}

static float p_fabs(float a) { return a < 0.0f ? -a : a; }

static float p_wrap(float a) /* to (-pi, pi] */
{
    while (a > P_PI)
        a -= 2.0f * P_PI;
    while (a <= -P_PI)
        a += 2.0f * P_PI;
    return a;
}

void actag_pose_rotation_vector(const float Ra[9], const float Rb[9], float w[3])
{
    float Bt[9], M[9];
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            Bt[3 * i + j] = Rb[3 * j + i];
    actag__mat_mul(Ra, Bt, M);
    actag__rot_log(M, w);
}

float actag_pose_angle(const float Ra[9], const float Rb[9])
{
    float w[3];
    actag_pose_rotation_vector(Ra, Rb, w);
    return actag__norm3(w);
}

/* ------------------------------------------------------------ 6x6 linear algebra */

/* ------------------------------------------------------------ the model */

typedef actag__pose_model p_model;
typedef actag__pose_state p_state;

static const float p_cx[4] = {-0.5f, 0.5f, 0.5f, -0.5f}, p_cy[4] = {-0.5f, -0.5f, 0.5f, 0.5f};

static float p_elev(const float *p)
{
    float n = actag__norm3(p);
    return n > 0.0f ? actag__asin(p[2] / n) : 0.0f;
}

/* Gradient of elevation asin(p_z / |p|) with respect to p (0 on the z axis). */
static void p_elev_grad(const float *p, float *g)
{
    float r2 = actag__dot3(p, p), rho = actag_sqrtf(p[0] * p[0] + p[1] * p[1]);
    if (!(r2 > 0.0f) || !(rho > 0.0f)) {
        g[0] = g[1] = g[2] = 0.0f;
        return;
    }
    g[0] = -p[2] * p[0] / (rho * r2);
    g[1] = -p[2] * p[1] / (rho * r2);
    g[2] = rho / r2;
}

/* Band [lo, hi] of centre elevations that keep a square of side E s in the
 * aperture, and, when C (the fit's 6 x 6 covariance) is given, the variances
 * of its middle (vmid) and width (vw): the band's edges follow the fitted
 * tilt, which is itself uncertain. An edge is set by one corner k, e_k =
 * elev(R c_k + t) - elev(t); its gradient over (dt, w) is (g_k - g_0, q_k x
 * g_k) with g the elevation gradients at the corner and the centre. */
static void p_band_of(const p_model *m, const p_state *x, const float *C, float E, float *lo,
                      float *hi, float *vmid, float *vw)
{
    float e0 = p_elev(x->t), mn = 1e30f, mx = -1e30f, g0[3], G[4][P_NPAR];
    int k, j, i, kmn = 0, kmx = 0;
    p_elev_grad(x->t, g0);
    for (k = 0; k < 4; k++) {
        float c[3], q[3], p[3], g[3], w[3], e;
        c[0] = p_cx[k] * E * m->s;
        c[1] = p_cy[k] * E * m->s;
        c[2] = 0.0f;
        actag__mat_vec(x->R, c, q);
        for (j = 0; j < 3; j++)
            p[j] = q[j] + x->t[j];
        e = p_elev(p) - e0;
        p_elev_grad(p, g);
        actag__cross3(q, g, w);
        for (j = 0; j < 3; j++) {
            G[k][j] = g[j] - g0[j];
            G[k][3 + j] = w[j];
        }
        if (e < mn) {
            mn = e;
            kmn = k;
        }
        if (e > mx) {
            mx = e;
            kmx = k;
        }
    }
    *lo = -m->half_v - mn;
    *hi = m->half_v - mx;
    *vmid = *vw = 0.0f;
    if (C) { /* lo = -half - e_kmn, hi = half - e_kmx: their (co)variances */
        float vl = 0.0f, vh = 0.0f, c = 0.0f;
        for (i = 0; i < P_NPAR; i++)
            for (j = 0; j < P_NPAR; j++) {
                vl += G[kmn][i] * C[i * P_NPAR + j] * G[kmn][j];
                vh += G[kmx][i] * C[i * P_NPAR + j] * G[kmx][j];
                c += G[kmn][i] * C[i * P_NPAR + j] * G[kmx][j];
            }
        *vmid = 0.25f * (vl + vh + 2.0f * c);
        *vw = vl + vh - 2.0f * c;
        if (!(*vmid > 0.0f)) /* also NaN: no information */
            *vmid = 0.0f;
        if (!(*vw > 0.0f))
            *vw = 0.0f;
    }
}

/* Probability-like weight that a band of estimated width w and width sd sw
 * is not empty: a smoothstep over w / sw in [-2, 2], within 0.03 of the
 * normal distribution function there (our own: no libm erf). */
static float p_ramp(float w, float sw)
{
    float u;
    if (!(sw > 0.0f))
        return w > 0.0f ? 1.0f : 0.0f;
    u = 0.25f * (w / sw + 2.0f);
    if (!(u > 0.0f))
        return 0.0f;
    if (u >= 1.0f)
        return 1.0f;
    return u * u * (3.0f - 2.0f * u);
}

/* The elevation prior (m->mu, m->sp) at the state x, C its covariance or
 * NULL. The tag was seen: its outline (extent E) lies in the aperture, a
 * uniform prior over that band: mean its middle, variance width^2 / 12. The
 * band is computed from the fitted tilt, so its edges are uncertain too:
 * their sd (from C) is added, the middle's variance and the width's / 12,
 * so a band that only just fits cannot claim the elevation more closely
 * than the tilt knows its edges. When the outline's band may be empty (a
 * close or tall tag: a real beam's edge is soft) the inner square's band
 * takes over, and when that may be empty too a weak pull (sd half the
 * aperture) to its middle; the three are blended by how likely each band is
 * non-empty (p_ramp) and the blend's mean and variance taken, so the prior
 * moves continuously with the corners. lo, hi: the outline's band, or the
 * inner square's when the outline's is empty. Returns 1 when not even the
 * inner square fits (hi <= lo). */
static int p_set_prior(p_model *m, const p_state *x, const float *C, float *lo, float *hi)
{
    float wt[3], mu[3], var[3], tot = 0.0f, mean = 0.0f, v = 0.0f, l, h, vm, vw, w, r;
    int k, none;
    p_band_of(m, x, C, m->E, &l, &h, &vm, &vw);
    w = h - l;
    *lo = l;
    *hi = h;
    mu[0] = 0.5f * (l + h);
    var[0] = ((w > 0.0f ? w * w : 0.0f) + vw) * (1.0f / 12.0f) + vm;
    wt[0] = p_ramp(w, actag_sqrtf(vw));
    if (m->E > 1.0f) {
        p_band_of(m, x, C, 1.0f, &l, &h, &vm, &vw);
        if (!(*hi > *lo)) {
            *lo = l;
            *hi = h;
        }
        w = h - l;
        mu[1] = 0.5f * (l + h);
        var[1] = ((w > 0.0f ? w * w : 0.0f) + vw) * (1.0f / 12.0f) + vm;
        r = p_ramp(w, actag_sqrtf(vw));
    } else {
        mu[1] = mu[0];
        var[1] = var[0];
        r = 0.0f;
    }
    wt[1] = (1.0f - wt[0]) * r;
    wt[2] = (1.0f - wt[0]) * (1.0f - r);
    none = !(h > l);
    mu[2] = mu[1];
    var[2] = m->half_v * m->half_v;
    for (k = 0; k < 3; k++) {
        tot += wt[k];
        mean += wt[k] * mu[k];
    }
    mean /= tot;
    for (k = 0; k < 3; k++)
        v += wt[k] * (var[k] + (mu[k] - mean) * (mu[k] - mean));
    v /= tot;
    m->mu = mean;
    m->sp = actag_sqrtf(v);
    if (!(m->sp >= 1e-4f * m->half_v)) /* exact corners, C NULL: a band's width alone */
        m->sp = 1e-4f * m->half_v;
    return none;
}

/* Residuals f (P_NRES) and, when J != NULL, the Jacobian (P_NRES x P_NPAR).
 * Returns the sum of squares. */
float actag__pose_eval(const p_model *m, const p_state *x, float *f, float *J)
{
    float cost = 0.0f, tn, rho2, rho, e0;
    int i, j;
    for (i = 0; i < 4; i++) {
        float c[3], q[3], p[3], r, th, gr[3], ga[3], w[3];
        c[0] = p_cx[i] * m->s;
        c[1] = p_cy[i] * m->s;
        c[2] = 0.0f;
        actag__mat_vec(x->R, c, q);
        for (j = 0; j < 3; j++)
            p[j] = q[j] + x->t[j];
        r = actag__norm3(p);
        th = actag__atan2(p[1], p[0]);
        f[2 * i] = (r - m->r[i]) / m->sr;
        f[2 * i + 1] = p_wrap(th - m->az[i]) / m->sa;
        if (J) {
            float pr2 = p[0] * p[0] + p[1] * p[1];
            if (!(pr2 > 1e-20f))
                pr2 = 1e-20f;
            for (j = 0; j < 3; j++)
                gr[j] = (r > 0.0f ? p[j] / r : 0.0f) / m->sr;
            ga[0] = -p[1] / pr2 / m->sa;
            ga[1] = p[0] / pr2 / m->sa;
            ga[2] = 0.0f;
            /* d/dt = g; d/dw = q x g (p = exp([w]x) q + t) */
            for (j = 0; j < 3; j++) {
                J[(2 * i) * P_NPAR + j] = gr[j];
                J[(2 * i + 1) * P_NPAR + j] = ga[j];
            }
            actag__cross3(q, gr, w);
            for (j = 0; j < 3; j++)
                J[(2 * i) * P_NPAR + 3 + j] = w[j];
            actag__cross3(q, ga, w);
            for (j = 0; j < 3; j++)
                J[(2 * i + 1) * P_NPAR + 3 + j] = w[j];
        }
    }
    e0 = p_elev(x->t);
    f[8] = (e0 - m->mu) / m->sp;
    if (J) {
        tn = actag__norm3(x->t);
        rho2 = x->t[0] * x->t[0] + x->t[1] * x->t[1];
        rho = actag_sqrtf(rho2);
        if (tn > 0.0f && rho > 0.0f) {
            J[8 * P_NPAR + 0] = -x->t[2] * x->t[0] / (rho * tn * tn) / m->sp;
            J[8 * P_NPAR + 1] = -x->t[2] * x->t[1] / (rho * tn * tn) / m->sp;
            J[8 * P_NPAR + 2] = rho / (tn * tn) / m->sp;
        } else {
            J[8 * P_NPAR + 0] = J[8 * P_NPAR + 1] = J[8 * P_NPAR + 2] = 0.0f;
        }
        J[8 * P_NPAR + 3] = J[8 * P_NPAR + 4] = J[8 * P_NPAR + 5] = 0.0f;
    }
    /* the plane prior: the face centre's offset from the plane (d/dt = n,
     * d/dw = 0: the centre is t), and the face normal z = R e3 along n, its
     * components along the tangents u, v (d/dw of z = -[z]x, so d(u.z)/dw =
     * z x u); rows of an unused term stay zero and change no sum */
    for (i = 9; i < P_NRES; i++)
        f[i] = 0.0f;
    if (J)
        for (i = 9 * P_NPAR; i < P_NRES * P_NPAR; i++)
            J[i] = 0.0f;
    if (m->wd > 0.0f) {
        f[9] = (actag__dot3(m->n, x->t) - m->d) * m->wd;
        if (J)
            for (j = 0; j < 3; j++)
                J[9 * P_NPAR + j] = m->n[j] * m->wd;
    }
    if (m->wt > 0.0f) {
        float z[3], w[3];
        z[0] = x->R[2];
        z[1] = x->R[5];
        z[2] = x->R[8];
        f[10] = actag__dot3(m->u, z) * m->wt;
        f[11] = actag__dot3(m->v, z) * m->wt;
        if (J) {
            actag__cross3(z, m->u, w);
            for (j = 0; j < 3; j++)
                J[10 * P_NPAR + 3 + j] = w[j] * m->wt;
            actag__cross3(z, m->v, w);
            for (j = 0; j < 3; j++)
                J[11 * P_NPAR + 3 + j] = w[j] * m->wt;
        }
    }
    for (i = 0; i < P_NRES; i++)
        cost += f[i] * f[i];
    return cost;
}

/* The second-order term of the elevation arc, added to the position block of
 * the covariance. The poorly seen direction is the centre sliding along its
 * elevation arc (a sphere of fixed range): a slide by de moves the centre
 * r de along the arc's tangent, which (J^T J)^-1 holds, and r (1 - cos de)
 * ~ r de^2 / 2 toward the sonar, which a linear covariance cannot. With de
 * of sd s_e that is E[(r de^2 / 2)^2] = 3 r^2 s_e^4 / 4 along t / |t|;
 * without it the range sd is set by the corners alone (about 1 mm) and
 * the truth, a few degrees away on the same sphere, falls outside the 95 %
 * ellipsoid about one time in five (actag-eval, docs/pose.md). */
static void p_arc_term(const float *t, float *cov)
{
    float r2 = actag__dot3(t, t), rho2 = t[0] * t[0] + t[1] * t[1], rho, r, e[3], u[3], ve, c;
    int i, j;
    if (!(r2 > 0.0f) || !(rho2 > 0.0f))
        return;
    r = actag_sqrtf(r2);
    rho = actag_sqrtf(rho2);
    /* unit tangent of the elevation arc, and the unit range direction */
    e[0] = -t[2] * t[0] / (rho * r);
    e[1] = -t[2] * t[1] / (rho * r);
    e[2] = rho / r;
    for (i = 0; i < 3; i++)
        u[i] = t[i] / r;
    ve = 0.0f; /* variance along the tangent, m^2: r^2 s_e^2 */
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            ve += e[i] * cov[i * P_NPAR + j] * e[j];
    if (!(ve > 0.0f))
        return;
    c = 0.75f * ve * ve / r2; /* 3/4 r^2 s_e^4 */
    for (i = 0; i < 3; i++) /* the upper triangle, mirrored: exactly symmetric */
        for (j = i; j < 3; j++) {
            cov[i * P_NPAR + j] += c * u[i] * u[j];
            cov[j * P_NPAR + i] = cov[i * P_NPAR + j];
        }
}

void actag__pose_step(const p_state *x, const float *d, p_state *o)
{
    float dR[9];
    int j;
    for (j = 0; j < 3; j++)
        o->t[j] = x->t[j] + d[j];
    actag__rot_exp(d + 3, dR);
    actag__mat_mul(dR, x->R, o->R);
    { /* keep R orthonormal */
        float xa[3], ya[3];
        for (j = 0; j < 3; j++) {
            xa[j] = o->R[3 * j];
            ya[j] = o->R[3 * j + 1];
        }
        actag__rot_from_axes(xa, ya, o->R);
    }
}

/* Least squares min |A d - b| for an m x P_NPAR matrix A (row-major, m <=
 * P_NRES + P_NPAR), by Householder QR on column-scaled A (no normal
 * equations: their squared condition number would cost float digits).
 * A and b are overwritten: A's top P_NPAR rows hold R (upper triangle) of
 * the scaled A, sc the column scales. Returns 0, or -1 when A is rank
 * deficient. */
#define P_MAXR (P_NRES + P_NPAR)
static int p_lsq(float *A, float *b, int m, float *d, float *sc)
{
    int i, j, k;
    for (j = 0; j < P_NPAR; j++) {
        float n = 0.0f;
        for (i = 0; i < m; i++)
            n += A[i * P_NPAR + j] * A[i * P_NPAR + j];
        n = actag_sqrtf(n);
        if (!(n > 0.0f))
            return -1;
        sc[j] = 1.0f / n;
        for (i = 0; i < m; i++)
            A[i * P_NPAR + j] *= sc[j];
    }
    for (k = 0; k < P_NPAR; k++) {
        float alpha = 0.0f, vnorm2, beta;
        for (i = k; i < m; i++)
            alpha += A[i * P_NPAR + k] * A[i * P_NPAR + k];
        alpha = actag_sqrtf(alpha);
        if (!(alpha > 1e-6f))
            return -1;
        if (A[k * P_NPAR + k] > 0.0f)
            alpha = -alpha;
        /* v = x - alpha e1, stored in column k */
        A[k * P_NPAR + k] -= alpha;
        vnorm2 = 0.0f;
        for (i = k; i < m; i++)
            vnorm2 += A[i * P_NPAR + k] * A[i * P_NPAR + k];
        if (vnorm2 > 0.0f) {
            beta = 2.0f / vnorm2;
            for (j = k + 1; j < P_NPAR; j++) {
                float t = 0.0f;
                for (i = k; i < m; i++)
                    t += A[i * P_NPAR + k] * A[i * P_NPAR + j];
                t *= beta;
                for (i = k; i < m; i++)
                    A[i * P_NPAR + j] -= t * A[i * P_NPAR + k];
            }
            {
                float t = 0.0f;
                for (i = k; i < m; i++)
                    t += A[i * P_NPAR + k] * b[i];
                t *= beta;
                for (i = k; i < m; i++)
                    b[i] -= t * A[i * P_NPAR + k];
            }
        }
        A[k * P_NPAR + k] = alpha; /* R's diagonal; the rest of column k is scrap */
    }
    for (k = P_NPAR - 1; k >= 0; k--) {
        float v = b[k];
        for (j = k + 1; j < P_NPAR; j++)
            v -= A[k * P_NPAR + j] * d[j];
        d[k] = v / A[k * P_NPAR + k];
    }
    for (j = 0; j < P_NPAR; j++)
        d[j] *= sc[j];
    return 0;
}

/* Covariance (J^T J)^-1 from a Jacobian A (nres <= P_NRES rows of P_NPAR,
 * whitened residuals; overwritten), by its QR factor: (R^T R)^-1 = R^-1
 * R^-T, columns rescaled. The upper triangle is computed and mirrored, so
 * cov is exactly symmetric. Returns 0, or -1 when A is rank deficient or
 * an entry leaves the float range (the columns' rescaling can overflow
 * where the rank test, on the scaled columns, passed: a vertical aperture
 * of 1e-8 rad with four equal corners); cov untouched then. */
static int p_cov_of(float *A, int nres, float *cov)
{
    float b[P_NRES], d[P_NPAR], sc[P_NPAR], Ri[36], c[36];
    int i, j, k;
    for (i = 0; i < nres; i++)
        b[i] = 0.0f;
    if (p_lsq(A, b, nres, d, sc) != 0)
        return -1;
    for (i = 0; i < 36; i++)
        Ri[i] = 0.0f;
    for (j = 0; j < P_NPAR; j++) { /* column j of R^-1 */
        Ri[j * P_NPAR + j] = 1.0f / A[j * P_NPAR + j];
        for (i = j - 1; i >= 0; i--) {
            float v = 0.0f;
            for (k = i + 1; k <= j; k++)
                v += A[i * P_NPAR + k] * Ri[k * P_NPAR + j];
            Ri[i * P_NPAR + j] = -v / A[i * P_NPAR + i];
        }
    }
    for (i = 0; i < P_NPAR; i++)
        for (j = i; j < P_NPAR; j++) {
            float v = 0.0f;
            for (k = j; k < P_NPAR; k++)
                v += Ri[i * P_NPAR + k] * Ri[j * P_NPAR + k];
            c[i * P_NPAR + j] = v * sc[i] * sc[j];
            c[j * P_NPAR + i] = c[i * P_NPAR + j];
        }
    if (!p_all_finite(c, 36))
        return -1;
    for (i = 0; i < 36; i++)
        cov[i] = c[i];
    return 0;
}

/* The covariance of the fit at x (p_cov_of of its Jacobian). */
static int p_cov(const p_model *m, const p_state *x, float *cov)
{
    float f[P_NRES], A[P_NRES * P_NPAR];
    actag__pose_eval(m, x, f, A);
    return p_cov_of(A, P_NRES, cov);
}

/* The elevation prior at x: the band alone first, then widened by its
 * edges' uncertainty from the covariance there (p_set_prior). Returns
 * p_set_prior's "not even the inner square fits". */
static int p_prior_at(p_model *m, const p_state *x, float *lo, float *hi)
{
    float C[36];
    int none = p_set_prior(m, x, NULL, lo, hi);
    if (p_cov(m, x, C) == 0)
        none = p_set_prior(m, x, C, lo, hi);
    return none;
}

/* Levenberg-Marquardt on the 6 parameters; returns the trial steps used,
 * negated when the cap was reached without convergence. */
static int p_lm(const p_model *m, p_state *x, int max_it)
{
    float f[P_NRES], J[P_NRES * P_NPAR], A[P_MAXR * P_NPAR], b[P_MAXR], d[P_NPAR];
    float dg[P_NPAR], sc[P_NPAR], cost, lambda = 1e-3f, jd2 = 0.0f;
    int it, i, j, small;
    cost = actag__pose_eval(m, x, f, J);
    for (it = 1; it <= max_it; it++) {
        p_state y;
        float fy[P_NRES], cy;
        /* min |J d + f|^2 + lambda |diag(|J_col|) d|^2 (Marquardt's scaling) */
        for (j = 0; j < P_NPAR; j++) {
            float n = 0.0f;
            for (i = 0; i < P_NRES; i++)
                n += J[i * P_NPAR + j] * J[i * P_NPAR + j];
            dg[j] = actag_sqrtf(n * lambda);
        }
        for (i = 0; i < P_NRES * P_NPAR; i++)
            A[i] = J[i];
        for (i = 0; i < P_NRES; i++)
            b[i] = -f[i];
        for (i = 0; i < P_NPAR; i++) {
            for (j = 0; j < P_NPAR; j++)
                A[(P_NRES + i) * P_NPAR + j] = i == j ? dg[j] : 0.0f;
            b[P_NRES + i] = 0.0f;
        }
        if (p_lsq(A, b, P_MAXR, d, sc) != 0) {
            lambda *= 10.0f;
            if (lambda > 1e8f)
                return it;
            continue;
        }
        actag__pose_step(x, d, &y);
        cy = actag__pose_eval(m, &y, fy, NULL);
        /* Converged: a nearly undamped step shorter than 1e-3 of the
         * solution's sd (the covariance is (J^T J)^-1 of the normalised
         * residuals, so that is |J d| < 1e-3), or one shorter than 1e-2 sd
         * that the cost refuses: a linear model is not wrong over so short
         * a step, the refusal is the cost's float rounding (a corner range
         * of 4 m is rounded to 2e-4 of the default sd). A test on the gain
         * alone was met late or never near the minimum of good corners,
         * whose cost (~0.1) hides gains of 1e-7 of it: the steps crept along
         * the flat elevation valley (26 of 3000 noisy views flagged at 20
         * trial steps, all within 0.1 mm of the 100-step fit). */
        jd2 = 0.0f;
        for (i = 0; i < P_NRES; i++) {
            float v = 0.0f;
            for (j = 0; j < P_NPAR; j++)
                v += J[i * P_NPAR + j] * d[j];
            jd2 += v * v;
        }
        small = lambda < 1e-2f && jd2 < 1e-6f;
        if (cy <= cost) {
            float dt = actag_sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            float dw = actag_sqrtf(d[3] * d[3] + d[4] * d[4] + d[5] * d[5]);
            int done = small || ((cost - cy) <= 1e-7f * cost + 1e-12f && lambda < 1e-2f) ||
                       (dt < 1e-7f && dw < 1e-7f);
            *x = y;
            cost = actag__pose_eval(m, x, f, J);
            lambda = lambda * 0.1f > 1e-9f ? lambda * 0.1f : 1e-9f;
            if (done)
                return it;
        } else {
            if (lambda < 1e-2f && jd2 < 1e-4f)
                return it; /* the cost's rounding, not the model, refused it */
            lambda *= 10.0f;
            if (lambda > 1e8f)
                return it; /* no step improves: at the minimum to float precision */
        }
    }
    return -max_it;
}

/* ------------------------------------------------------------ start */

/* Pose from the corners assuming the centre at elevation e: the in-fan
 * components of the edges are measured, the elevation components follow
 * from the square (rank-one fit), signed so the face is toward the sonar. */
static void p_start(const p_model *m, float e, p_state *x, float *winding)
{
    float rbar = 0.0f, abar = 0.0f, q[4][2], ah[2], bh[2], A, B, C, lam, u[2], hn, ha, hb;
    float ur[3], ua[3], ue[3], se, ce, sa, ca, al[3], bl[3], zr, xa[3], ya[3];
    int i, j;
    for (i = 0; i < 4; i++) {
        rbar += 0.25f * m->r[i];
        abar += 0.25f * p_wrap(m->az[i] - m->az[0]);
    }
    abar = p_wrap(abar + m->az[0]);
    for (i = 0; i < 4; i++) {
        float s, c, d = p_wrap(m->az[i] - abar);
        actag__sincos(d, &s, &c);
        q[i][0] = m->r[i] * c;
        q[i][1] = m->r[i] * s;
    }
    for (j = 0; j < 2; j++) {
        ah[j] = 0.5f * ((q[1][j] - q[0][j]) + (q[2][j] - q[3][j]));
        bh[j] = 0.5f * ((q[3][j] - q[0][j]) + (q[2][j] - q[1][j]));
    }
    /* winding in (range, lateral): the elevation component of a x b */
    *winding = ah[0] * bh[1] - ah[1] * bh[0];
    A = m->s * m->s - (ah[0] * ah[0] + ah[1] * ah[1]);
    B = m->s * m->s - (bh[0] * bh[0] + bh[1] * bh[1]);
    C = -(ah[0] * bh[0] + ah[1] * bh[1]);
    lam = 0.5f * (A + B) + actag_sqrtf(0.25f * (A - B) * (A - B) + C * C);
    u[0] = C;
    u[1] = lam - A;
    if (u[0] * u[0] + u[1] * u[1] < (lam - B) * (lam - B) + C * C) {
        u[0] = lam - B;
        u[1] = C;
    }
    hn = actag_sqrtf(u[0] * u[0] + u[1] * u[1]);
    if (hn > 0.0f && lam > 0.0f) {
        float k = actag_sqrtf(lam) / hn;
        ha = u[0] * k;
        hb = u[1] * k;
    } else {
        ha = hb = 0.0f;
    }
    /* face toward the sonar: tag z (a x b) has a positive range component */
    zr = ah[1] * hb - ha * bh[1];
    if (zr < 0.0f) {
        ha = -ha;
        hb = -hb;
    }
    actag__sincos(abar, &sa, &ca);
    actag__sincos(e, &se, &ce);
    ur[0] = ca * ce; ur[1] = sa * ce; ur[2] = se;
    ua[0] = -sa;     ua[1] = ca;      ua[2] = 0.0f;
    ue[0] = -ca * se; ue[1] = -sa * se; ue[2] = ce;
    for (j = 0; j < 3; j++) {
        al[j] = ah[0] * ur[j] + ah[1] * ua[j] + ha * ue[j];
        bl[j] = bh[0] * ur[j] + bh[1] * ua[j] + hb * ue[j];
    }
    for (j = 0; j < 3; j++) {
        xa[j] = al[j];
        ya[j] = bl[j];
    }
    actag__rot_from_axes(xa, ya, x->R);
    for (j = 0; j < 3; j++)
        x->t[j] = rbar * ur[j];
}

/* ------------------------------------------------------------ plane prior */

/* The plane of params into m: unit normal, offset, tangents, weights.
 * Returns -1 when the plane is not finite, its normal is zero or its
 * offset |d| / |n| exceeds P_PLANE_MAX_D. */
#define P_PLANE_MAX_D 1.0e4f /* m: far beyond any sonar's range; a plane farther
                              * away pulls the fit to absurd distances */
static int p_plane_of(const actag_pose_params *p, p_model *m)
{
    float nn, big = 0.0f, n[3], a[3] = {0.0f, 0.0f, 0.0f};
    int j;
    if (!p_all_finite(p->plane, 4))
        return -1;
    /* divide by the largest |component| first: n . n of (0, 0, 1e-30)
     * underflows to 0 and of (0, 0, 1e20) overflows */
    for (j = 0; j < 3; j++)
        big = p_fabs(p->plane[j]) > big ? p_fabs(p->plane[j]) : big;
    if (!(big > 0.0f))
        return -1;
    for (j = 0; j < 3; j++)
        n[j] = p->plane[j] / big;
    nn = actag__norm3(n); /* 1 .. sqrt(3) */
    for (j = 0; j < 3; j++)
        m->n[j] = n[j] / nn;
    m->d = p->plane[3] / big / nn;
    if (!(p_fabs(m->d) <= P_PLANE_MAX_D)) /* also an overflow to inf */
        return -1;
    /* u: n x (the axis least along n), v = n x u */
    a[(m->n[0] < 0.0f ? -m->n[0] : m->n[0]) < 0.9f ? 0 : 1] = 1.0f;
    actag__cross3(m->n, a, m->u);
    nn = actag__norm3(m->u);
    for (j = 0; j < 3; j++)
        m->u[j] /= nn;
    actag__cross3(m->n, m->u, m->v);
    m->wd = p->plane_sd > 0.0f ? 1.0f / p->plane_sd : 0.0f;
    m->wt = p->plane_tilt_sd > 0.0f ? 1.0f / p->plane_tilt_sd : 0.0f;
    return 0;
}

/* Elevation k (0, 1) at which the ray of the corners' mean range and
 * azimuth meets the plane: n . (r (cos a cos e, sin a cos e, sin e)) = d,
 * i.e. A cos e + B sin e = d / r. Returns 0 when there is none within twice
 * the half aperture. */
static int p_plane_elevation(const p_model *m, int k, float *e)
{
    float rbar = 0.0f, abar = 0.0f, sa, ca, A, B, h, q, phi, al;
    int i;
    for (i = 0; i < 4; i++) {
        rbar += 0.25f * m->r[i];
        abar += 0.25f * p_wrap(m->az[i] - m->az[0]);
    }
    abar = p_wrap(abar + m->az[0]);
    actag__sincos(abar, &sa, &ca);
    A = m->n[0] * ca + m->n[1] * sa;
    B = m->n[2];
    h = actag_sqrtf(A * A + B * B);
    if (!(h > 0.0f) || !(rbar > 0.0f))
        return 0;
    q = m->d / (rbar * h);
    if (!(q >= -1.0f && q <= 1.0f))
        return 0;
    phi = actag__atan2(B, A);
    al = 0.5f * P_PI - actag__asin(q); /* acos(q) */
    *e = p_wrap(k ? phi - al : phi + al);
    return *e >= -4.0f * m->half_v && *e <= 4.0f * m->half_v;
}

/* ------------------------------------------------------------ public */

/* A usable noise sd: positive, finite, and 1 / sd^2 (a residual's weight in
 * the cost) finite: below about 5e-20 it overflows and the cost is inf. */
static int p_sd_ok(float sd)
{
    return p_finite(sd) && sd > 0.0f && p_finite(1.0f / (sd * sd));
}

void actag_pose_params_default(actag_pose_params *p, const actag_family *family,
                               float tag_size, float vertical_aperture)
{
    if (p == NULL)
        return;
    p->tag_size = tag_size;
    p->vertical_aperture = vertical_aperture;
    p->extent = 1.0f;
    if (family != NULL && family->bits >= 16) {
        int k = family->bits / 4;
        p->extent = (float)(k + 1) / (float)(k - 3);
    }
    p->range_sd = ACTAG_POSE_RANGE_SD;
    p->azimuth_sd = ACTAG_POSE_AZIMUTH_SD;
    p->max_iterations = 20;
    p->plane[0] = p->plane[1] = p->plane[2] = p->plane[3] = 0.0f;
    p->plane_sd = 0.0f;
    p->plane_tilt_sd = 0.0f;
}

/* The lengths the fit works with: corner ranges and the tag size within
 * these, so that squares and sums of them stay normal floats (a range of
 * 2e19 m overflowed them and came back as ACTAG_OK with an inf range and a
 * zero R; 1e-30 m underflowed to a range of 0). Far beyond any sonar's. */
#define P_MIN_LENGTH 1.0e-3f /* m */
#define P_MAX_LENGTH 1.0e4f  /* m, as P_PLANE_MAX_D */

static int p_length_ok(float v)
{
    return v >= P_MIN_LENGTH && v <= P_MAX_LENGTH; /* NaN fails */
}

int actag_pose_estimate(const float range[4], const float azimuth[4], int mirrored,
                        const actag_pose_params *p, actag_pose *out)
{
    p_model m;
    p_state x;
    float lo, hi, winding, f[P_NRES], res2 = 0.0f;
    int i, pass, it, total = 0, converged = 1, none;
    if (range == NULL || azimuth == NULL || p == NULL || out == NULL)
        return ACTAG_ERR_NULL;
    if (actag_fp_fuses())
        return ACTAG_ERR_BUILD;
    for (i = 0; i < 4; i++)
        if (!p_length_ok(range[i]) || !p_finite(azimuth[i]) ||
            !(azimuth[i] > -4.0f * P_PI && azimuth[i] < 4.0f * P_PI))
            return ACTAG_ERR_PARAM;
    if (!p_length_ok(p->tag_size) || !p_finite(p->vertical_aperture) ||
        !(p->vertical_aperture > 0.0f) || !(p->vertical_aperture < P_PI) ||
        !p_finite(p->extent) || !(p->extent >= 1.0f) ||
        !p_length_ok(p->extent * p->tag_size) || !p_sd_ok(p->range_sd) ||
        !p_sd_ok(p->azimuth_sd) || p->max_iterations < 1 || p->max_iterations > 100)
        return ACTAG_ERR_PARAM;
    if (!(p->plane_sd == 0.0f || p_sd_ok(p->plane_sd)) ||
        !(p->plane_tilt_sd == 0.0f || p_sd_ok(p->plane_tilt_sd)))
        return ACTAG_ERR_PARAM;
    m.wd = m.wt = 0.0f;
    if (p->plane_sd > 0.0f || p->plane_tilt_sd > 0.0f) {
        if (p_plane_of(p, &m) != 0)
            return ACTAG_ERR_PARAM;
    }
    for (i = 0; i < (int)sizeof *out; i++)
        ((unsigned char *)out)[i] = 0;
    for (i = 0; i < 4; i++) {
        m.r[i] = range[i];
        m.az[i] = azimuth[i];
    }
    m.s = p->tag_size;
    m.E = p->extent;
    m.half_v = 0.5f * p->vertical_aperture;
    m.sr = p->range_sd;
    m.sa = p->azimuth_sd;

    /* start on the horizontal plane for the band, then from 5-17 elevations
     * across it (the cost along the elevation arcs is flat and can have
     * two minima); the best fit goes on */
    p_start(&m, 0.0f, &x, &winding);
    p_prior_at(&m, &x, &lo, &hi);
    {
        float best = 3.0e38f, f0[P_NRES], es[P_STARTS_MAX + 2];
        float width = 2.0f * 1.73205081f * m.sp; /* the band's, from its sd */
        p_state x0 = x;
        int k, ns = 0, nstart = P_STARTS;
        while (nstart < P_STARTS_MAX && width > (float)(nstart - 1) * P_START_STEP)
            nstart++;
        for (k = 0; k < nstart; k++)
            es[ns++] = m.mu + m.sp * 1.73205081f * ((float)k / (float)(nstart - 1) * 2.0f - 1.0f);
        /* with a plane: also from the elevations where the centre's ray meets it */
        for (k = 0; k < 2 && m.wd > 0.0f; k++)
            if (p_plane_elevation(&m, k, &es[ns]))
                ns++;
        int front0 = 0;
        for (k = 0; k < ns; k++) {
            p_state y;
            float cy;
            int front;
            p_start(&m, es[k], &y, &winding);
            it = p_lm(&m, &y, p->max_iterations);
            total += it > 0 ? it : -it;
            cy = actag__pose_eval(&m, &y, f0, NULL);
            /* Every pose has a twin reflected in the horizontal plane whose
             * corners have the same ranges and azimuths (exactly: the twin
             * is a proper rotation of the same printed face); the twin shows
             * the sonar the tag's back. A fit whose face (z into the tag)
             * looks away from the sonar is taken only if no start gave one
             * that faces it (test_exact_corners_recover_the_pose). */
            front = y.R[2] * y.t[0] + y.R[5] * y.t[1] + y.R[8] * y.t[2] > 0.0f;
            if (!(cy < 3.0e38f)) /* a NaN or infinite cost is no fit */
                continue;
            if ((front && !front0) || (front == front0 && cy < best)) {
                best = cy;
                x0 = y;
                front0 = front;
            }
        }
        x = x0;
    }
    {
        float sd[2], rbar = 0.0f, sigma_pt, area_sd;
        for (i = 0; i < 4; i++)
            rbar += 0.25f * range[i];
        /* image area noise: about s * sqrt(2) * the corner's position sd */
        sd[0] = p->range_sd;
        sd[1] = rbar * p->azimuth_sd;
        sigma_pt = actag_sqrtf(sd[0] * sd[0] + sd[1] * sd[1]);
        area_sd = p->tag_size * 1.41421356f * sigma_pt;
        if ((winding < 0.0f ? -winding : winding) < 2.0f * area_sd)
            out->flags |= ACTAG_POSE_DEGENERATE;
        else if ((winding > 0.0f) != (mirrored != 0))
            out->flags |= ACTAG_POSE_MIRROR_CONFLICT;
    }
    /* refine: the prior at the fit, the fit with that prior, until the
     * prior no longer moves (at most P_PASSES fits) */
    for (pass = 0; pass < P_PASSES; pass++) {
        p_model mn = m;
        p_prior_at(&mn, &x, &lo, &hi);
        if (pass > 0 && converged && p_fabs(mn.mu - m.mu) < 1e-4f && p_fabs(mn.sp - m.sp) < 1e-4f)
            break;
        m.mu = mn.mu;
        m.sp = mn.sp;
        it = p_lm(&m, &x, p->max_iterations);
        converged = it > 0;
        total += it > 0 ? it : -it;
    }
    if (!converged)
        out->flags |= ACTAG_POSE_NOT_CONVERGED;
    { /* the band at the solution (the prior stays as last fitted) */
        p_model mn = m;
        none = p_prior_at(&mn, &x, &lo, &hi);
    }
    actag__pose_eval(&m, &x, f, NULL);
    if (p_cov(&m, &x, out->cov) != 0) {
        out->flags |= ACTAG_POSE_DEGENERATE | ACTAG_POSE_NO_COVARIANCE;
    } else {
        p_arc_term(x.t, out->cov);
        if (!p_all_finite(out->cov, 36)) { /* the arc's term overflowed: none, all zero */
            for (i = 0; i < 36; i++)
                out->cov[i] = 0.0f;
            out->flags |= ACTAG_POSE_DEGENERATE | ACTAG_POSE_NO_COVARIANCE;
        }
    }
    for (i = 0; i < 9; i++)
        out->R[i] = x.R[i];
    for (i = 0; i < 3; i++)
        out->t[i] = x.t[i];
    out->range = actag__norm3(x.t);
    out->azimuth = actag__atan2(x.t[1], x.t[0]);
    out->elevation = p_elev(x.t);
    out->elevation_lo = lo;
    out->elevation_hi = hi;
    out->iterations = total;
    out->chi2 = 0.0f;
    for (i = 0; i < 8; i++)
        out->chi2 += f[i] * f[i];
    for (i = 0; i < 4; i++) {
        float dr = f[2 * i] * m.sr, da = f[2 * i + 1] * m.sa * range[i];
        res2 += dr * dr + da * da;
    }
    out->residual = actag_sqrtf(0.25f * res2);
    if (none || out->elevation < lo - 2.0f * m.sp || out->elevation > hi + 2.0f * m.sp)
        out->flags |= ACTAG_POSE_ELEVATION;
    if (f[9] * f[9] > 9.0f || f[10] * f[10] + f[11] * f[11] > 9.0f)
        out->flags |= ACTAG_POSE_PLANE;
    return ACTAG_OK;
}

int actag_pose_from_detection(const actag_detection *d, const actag_pose_params *p,
                              actag_pose *out)
{
    if (d == NULL)
        return ACTAG_ERR_NULL;
    return actag_pose_estimate(d->range, d->azimuth, d->mirrored, p, out);
}

/* A rotation's entries finite and a translation within +-P_MAX_LENGTH m
 * (NaN fails): what a camera pose must hold. */
static int p_rt_ok(const float *R, const float *t)
{
    int i;
    for (i = 0; i < 9; i++)
        if (!p_finite(R[i]))
            return 0;
    for (i = 0; i < 3; i++)
        if (!(t[i] >= -P_MAX_LENGTH && t[i] <= P_MAX_LENGTH))
            return 0;
    return 1;
}

int actag_pose_from_camera(const float R_opt[9], const float t_opt[3], actag_pose *out)
{
    /* sensor = C optical: x = z_opt, y = -x_opt, z = -y_opt */
    static const float Cm[9] = {0.0f, 0.0f, 1.0f, -1.0f, 0.0f, 0.0f, 0.0f, -1.0f, 0.0f};
    int i;
    if (R_opt == NULL || t_opt == NULL || out == NULL)
        return ACTAG_ERR_NULL;
    if (!p_rt_ok(R_opt, t_opt))
        return ACTAG_ERR_PARAM;
    for (i = 0; i < (int)sizeof *out; i++)
        ((unsigned char *)out)[i] = 0;
    actag__mat_mul(Cm, R_opt, out->R);
    actag__mat_vec(Cm, t_opt, out->t);
    out->range = actag__norm3(out->t);
    out->azimuth = actag__atan2(out->t[1], out->t[0]);
    out->elevation = p_elev(out->t);
    out->flags = ACTAG_POSE_NO_COVARIANCE;
    return ACTAG_OK;
}

/* ------------------------------------------------------------ camera covariance */

#define P_MAX_FOCAL 1.0e6f  /* px, as the optical adapter's ACTAG_APRILTAG_MAX_FOCAL */
#define P_MAX_CENTRE 1.0e5f /* px, principal point */
#define P_MAX_PIXEL 1.0e7f  /* px, a measured corner */

int actag_pose_camera_covariance(const float corners[8], float fx, float fy, float cx, float cy,
                                 float pixel_sd, float tag_size, actag_pose *pose)
{
    /* optical = Cm^T sensor (Cm of actag_pose_from_camera): x_opt = -y,
     * y_opt = -z, z_opt = x */
    float J[8 * P_NPAR], q[4][3], cov[36], res2 = 0.0f, chi2 = 0.0f;
    int i, j;
    if (pose == NULL)
        return ACTAG_ERR_NULL;
    if (actag_fp_fuses())
        return ACTAG_ERR_BUILD;
    if (!(fx >= 1.0f && fx <= P_MAX_FOCAL) || !(fy >= 1.0f && fy <= P_MAX_FOCAL) ||
        !(cx >= -P_MAX_CENTRE && cx <= P_MAX_CENTRE) ||
        !(cy >= -P_MAX_CENTRE && cy <= P_MAX_CENTRE) ||
        !(pixel_sd >= ACTAG_POSE_PIXEL_SD_MIN && pixel_sd <= ACTAG_POSE_PIXEL_SD_MAX) || !p_length_ok(tag_size) ||
        !p_rt_ok(pose->R, pose->t))
        return ACTAG_ERR_PARAM;
    if (corners != NULL)
        for (i = 0; i < 8; i++)
            if (!(corners[i] >= -P_MAX_PIXEL && corners[i] <= P_MAX_PIXEL))
                return ACTAG_ERR_PARAM;
    for (i = 0; i < 36; i++)
        pose->cov[i] = 0.0f;
    pose->flags |= ACTAG_POSE_NO_COVARIANCE;
    pose->flags &= ~ACTAG_POSE_DEGENERATE; /* decided here for a camera pose */
    for (i = 0; i < 4; i++) {
        /* the corner Rc + t (sensor), its rows of d(u, v)/d(dt, w) */
        float c[3], rc[3], p[3], gu[3], gv[3], z;
        c[0] = p_cx[i] * tag_size;
        c[1] = p_cy[i] * tag_size;
        c[2] = 0.0f;
        actag__mat_vec(pose->R, c, rc);
        for (j = 0; j < 3; j++)
            p[j] = rc[j] + pose->t[j];
        q[i][0] = -p[1];
        q[i][1] = -p[2];
        q[i][2] = p[0];
        z = q[i][2];
        /* a corner at or behind the camera's plane: no projection */
        if (!(z > 1.0e-3f * tag_size)) {
            pose->flags |= ACTAG_POSE_DEGENERATE;
            return ACTAG_OK;
        }
        /* du/dp_sensor = du/dq Cm^T: du/dq = fx (1/z, 0, -x/z^2),
         * dv/dq = fy (0, 1/z, -y/z^2); q = (-p1, -p2, p0) */
        gu[0] = -fx * q[i][0] / (z * z);
        gu[1] = -fx / z;
        gu[2] = 0.0f;
        gv[0] = -fy * q[i][1] / (z * z);
        gv[1] = 0.0f;
        gv[2] = -fy / z;
        for (j = 0; j < 3; j++) {
            J[(2 * i) * P_NPAR + j] = gu[j] / pixel_sd;
            J[(2 * i + 1) * P_NPAR + j] = gv[j] / pixel_sd;
        }
        /* d p / d w = -[Rc]x: g . (w x Rc) = w . (Rc x g) */
        {
            float wu[3], wv[3];
            actag__cross3(rc, gu, wu);
            actag__cross3(rc, gv, wv);
            for (j = 0; j < 3; j++) {
                J[(2 * i) * P_NPAR + 3 + j] = wu[j] / pixel_sd;
                J[(2 * i + 1) * P_NPAR + 3 + j] = wv[j] / pixel_sd;
            }
        }
        if (corners != NULL) {
            float du = corners[2 * i] - (cx + fx * q[i][0] / z);
            float dv = corners[2 * i + 1] - (cy + fy * q[i][1] / z);
            float ex = du * z / fx, ey = dv * z / fy;
            chi2 += (du * du + dv * dv) / (pixel_sd * pixel_sd);
            res2 += ex * ex + ey * ey;
        }
    }
    if (corners != NULL) {
        pose->residual = actag_sqrtf(res2 / 4.0f);
        pose->chi2 = chi2;
    }
    if (p_cov_of(J, 8, cov) != 0) {
        /* some motion leaves the image unchanged to first order, or the
         * Jacobian left the float range (absurd geometry) */
        pose->flags |= ACTAG_POSE_DEGENERATE;
        return ACTAG_OK;
    }
    for (i = 0; i < 36; i++)
        pose->cov[i] = cov[i];
    pose->flags &= ~ACTAG_POSE_NO_COVARIANCE;
    return ACTAG_OK;
}
