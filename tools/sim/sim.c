/* Sonar simulator with ground truth (see sim.h). Host only: uses malloc. */
#include "sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SIM_PI 3.14159265358979f
#define SIM_MAX_PSF_RADIUS 255 /* beam spread kernel taps either side (sigma <= 100 px) */
#define SIM_LN2 0.69314718f

static int fail(char *err, const char *msg)
{
    if (err)
        snprintf(err, 256, "%s", msg);
    return -1;
}

void sim_appearance_default(sim_appearance *a)
{
    /* Tuned so that pool-geometry frames match the pool recording's
     * background level and foam/metal contrast (actag-sim --compare-real). */
    a->foam = 1.0f;
    a->foam_exp = 0.5f;
    a->metal_specular = 4.0f;
    a->metal_lobe = 0.12f;
    a->metal_diffuse = 0.10f;
    a->seabed = 0.06f;
    a->seabed_exp = 1.0f;
    a->spreading = 1.0f;
    a->spreading_r0 = 1.0f;
    /* Blueprint Oculus M1200d at 2.1 MHz: 0.4 degree beams, 2.5 mm range
     * resolution (Gaussian sigma = FWHM / 2.355), widened for the recording's
     * compression blur */
    a->psf_azimuth = 0.0035f;
    a->psf_range = 0.0025f;
    a->noise = 0.0006f;
    a->gain = 260.0f;
    a->band_rate = 1.0f;
    a->band_min = 0.25f;
    a->band_max = 2.0f;
    a->supersample = 3;
    a->looks = 2;
    a->speckle = 1;
}

void sim_view_params_default(sim_view_params *v)
{
    v->min_distance = 0.5f;
    v->max_distance = 5.0f;
    v->min_incidence = 30.0f * SIM_PI / 180.0f;
    v->max_incidence = 80.0f * SIM_PI / 180.0f;
    v->max_roll = 10.0f * SIM_PI / 180.0f;
    v->mirror_fraction = 0.5f;
    v->clutter = 4;
    v->max_yaw = SIM_PI;
}

/* ------------------------------------------------------------ small maths */

static float dot3(const float *a, const float *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* out = M v, M the 3 x 3 matrix whose element (i, j) is R[i * rs + j * cs]:
 * R itself (rs 3, cs 1) or its transpose (rs 1, cs 3). out may be v. */
static void mat_vec_strided(const float *R, int rs, int cs, const float *v, float *out)
{
    float o[3];
    int i;
    for (i = 0; i < 3; i++)
        o[i] = R[i * rs] * v[0] + R[i * rs + cs] * v[1] + R[i * rs + 2 * cs] * v[2];
    memcpy(out, o, sizeof o);
}

static void mat_vec(const float *R, const float *v, float *out) { mat_vec_strided(R, 3, 1, v, out); }

static void mat_t_vec(const float *R, const float *v, float *out) { mat_vec_strided(R, 1, 3, v, out); }

static void mat_mul(const float *A, const float *B, float *out)
{
    float t[9];
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            t[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
    memcpy(out, t, sizeof t);
}

static void mat_transpose(const float *A, float *out)
{
    float t[9];
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            t[3 * i + j] = A[3 * j + i];
    memcpy(out, t, sizeof t);
}

static void normalize3(float *v)
{
    float n = sqrtf(dot3(v, v));
    if (n > 0.0f) {
        v[0] /= n;
        v[1] /= n;
        v[2] /= n;
    }
}

static void cross3(const float *a, const float *b, float *out)
{
    float o0 = a[1] * b[2] - a[2] * b[1];
    float o1 = a[2] * b[0] - a[0] * b[2];
    float o2 = a[0] * b[1] - a[1] * b[0];
    out[0] = o0;
    out[1] = o1;
    out[2] = o2;
}

/* Rotation by angle about unit axis u (Rodrigues). */
static void mat_axis_angle(const float *u, float ang, float *R)
{
    float c = cosf(ang), s = sinf(ang), C = 1.0f - c;
    R[0] = c + u[0] * u[0] * C;
    R[1] = u[0] * u[1] * C - u[2] * s;
    R[2] = u[0] * u[2] * C + u[1] * s;
    R[3] = u[1] * u[0] * C + u[2] * s;
    R[4] = c + u[1] * u[1] * C;
    R[5] = u[1] * u[2] * C - u[0] * s;
    R[6] = u[2] * u[0] * C - u[1] * s;
    R[7] = u[2] * u[1] * C + u[0] * s;
    R[8] = c + u[2] * u[2] * C;
}

void sim_pose_from_rpy(float x, float y, float z, float roll, float pitch, float yaw,
                       sim_pose *out)
{
    float cr = cosf(roll), sr = sinf(roll), cp = cosf(pitch), sp = sinf(pitch);
    float cy = cosf(yaw), sy = sinf(yaw);
    /* R = Rz(yaw) Ry(pitch) Rx(roll) */
    out->R[0] = cy * cp;
    out->R[1] = cy * sp * sr - sy * cr;
    out->R[2] = cy * sp * cr + sy * sr;
    out->R[3] = sy * cp;
    out->R[4] = sy * sp * sr + cy * cr;
    out->R[5] = sy * sp * cr - cy * sr;
    out->R[6] = -sp;
    out->R[7] = cp * sr;
    out->R[8] = cp * cr;
    out->t[0] = x;
    out->t[1] = y;
    out->t[2] = z;
}

void sim_pose_rpy(const sim_pose *p, float rpy[3])
{
    const float *R = p->R;
    rpy[1] = asinf(fmaxf(-1.0f, fminf(1.0f, -R[6])));
    rpy[0] = atan2f(R[7], R[8]);
    rpy[2] = atan2f(R[3], R[0]);
}

uint32_t sim_frame_seed(uint32_t seed, uint32_t index)
{
    /* splitmix-style mixing: independent streams per frame, any thread order */
    uint64_t z = ((uint64_t)seed << 32) ^ (uint64_t)index ^ 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return (uint32_t)(z ^ (z >> 32));
}

static float urand(actag_rng *r) /* [0, 1) */
{
    return (float)(actag_rng_next(r) >> 8) * (1.0f / 16777216.0f);
}

static float urange(actag_rng *r, float lo, float hi) { return lo + (hi - lo) * urand(r); }

/* ------------------------------------------------------------ geometry */

static float azimuth_limit(const sim_sonar *s, float *lo, float *hi)
{
    if (s->geo.bearings) {
        float a = s->geo.bearings[0], b = s->geo.bearings[s->cols - 1];
        *lo = a < b ? a : b;
        *hi = a < b ? b : a;
    } else {
        *lo = -0.5f * s->geo.aperture;
        *hi = 0.5f * s->geo.aperture;
    }
    return *hi - *lo;
}

int sim_pixel_of(const sim_sonar *s, float range, float azimuth, float *x, float *y)
{
    int rows = s->rows, cols = s->cols, inside = 1;
    float step = rows > 1 ? (s->geo.max_range - s->geo.min_range) / (float)(rows - 1) : 1.0f;
    if (s->geo.flags & ACTAG_RANGE_ASCENDING)
        *y = (range - s->geo.min_range) / step;
    else
        *y = (s->geo.max_range - range) / step;
    if (s->geo.bearings) {
        const float *b = s->geo.bearings;
        int asc = cols > 1 && b[cols - 1] > b[0], lo = 0, hi = cols - 1, c0;
        /* the interval [c0, c0+1] containing azimuth (clamped at the ends) */
        while (hi - lo > 1) {
            int mid = (lo + hi) / 2;
            if ((b[mid] <= azimuth) == (asc != 0))
                lo = mid;
            else
                hi = mid;
        }
        c0 = cols > 1 ? lo : 0;
        if (cols == 1)
            *x = 0.0f;
        else
            *x = (float)c0 + (azimuth - b[c0]) / (b[c0 + 1] - b[c0]);
    } else {
        float half = 0.5f * s->geo.aperture;
        float astep = cols > 1 ? s->geo.aperture / (float)(cols - 1) : 1.0f;
        if (s->geo.flags & ACTAG_AZIMUTH_ASCENDING)
            *x = (azimuth + half) / astep;
        else
            *x = (half - azimuth) / astep;
    }
    if (!(*y >= -0.5f && *y <= (float)rows - 0.5f && *x >= -0.5f && *x <= (float)cols - 0.5f))
        inside = 0;
    return inside ? 0 : -1;
}

/* Tag-frame point (x, y, 0) in the sonar frame. */
static void tag_point(const sim_tag *t, float x, float y, float *p)
{
    float v[3];
    v[0] = x;
    v[1] = y;
    v[2] = 0.0f;
    mat_vec(t->pose.R, v, p);
    p[0] += t->pose.t[0];
    p[1] += t->pose.t[1];
    p[2] += t->pose.t[2];
}

static float tag_side(const sim_tag *t) /* full tag side, metres */
{
    int k = t->family.bits / 4;
    return t->tag_size * (float)(k + 1) / (float)(k - 3);
}

static void polar_of(const float *p, float *r, float *az, float *el)
{
    *r = sqrtf(dot3(p, p));
    *az = atan2f(p[1], p[0]);
    *el = *r > 0.0f ? asinf(fmaxf(-1.0f, fminf(1.0f, p[2] / *r))) : 0.0f;
}

void sim_truth_of(const sim_sonar *s, const sim_tag *tag, sim_truth *out)
{
    static const float cx[4] = {-0.5f, 0.5f, 0.5f, -0.5f}, cy[4] = {-0.5f, -0.5f, 0.5f, 0.5f};
    float alo, ahi, area = 0.0f, W = tag_side(tag), n[3], tn;
    int i, j;
    memset(out, 0, sizeof *out);
    out->id = tag->id;
    for (i = 0; i < 4; i++) {
        float p[3], el;
        tag_point(tag, cx[i] * tag->tag_size, cy[i] * tag->tag_size, p);
        polar_of(p, &out->range[i], &out->azimuth[i], &el);
        sim_pixel_of(s, out->range[i], out->azimuth[i], &out->px[i].x, &out->px[i].y);
    }
    /* Winding in (azimuth, range): positive = as printed in the reference
     * orientation (TL at far range and +azimuth side when upright). */
    for (i = 0; i < 4; i++) {
        j = (i + 1) & 3;
        area += out->azimuth[i] * out->range[j] - out->azimuth[j] * out->range[i];
    }
    out->mirrored = area < 0.0f;
    /* Visibility: the tag's outline (sampled) inside range/azimuth/elevation. */
    azimuth_limit(s, &alo, &ahi);
    out->visible = 1;
    /* the whole face, not only its outline: range and elevation can peak
     * inside it */
    for (i = 0; i <= 8 && out->visible; i++)
        for (j = 0; j <= 8; j++) {
            float p[3], r, az, el;
            tag_point(tag, ((float)i / 8.0f - 0.5f) * W, ((float)j / 8.0f - 0.5f) * W, p);
            polar_of(p, &r, &az, &el);
            if (r < s->geo.min_range || r > s->geo.max_range || az < alo || az > ahi ||
                fabsf(el) > 0.5f * s->vertical_aperture) {
                out->visible = 0;
                break;
            }
        }
    out->distance = sqrtf(dot3(tag->pose.t, tag->pose.t));
    n[0] = tag->pose.R[2];
    n[1] = tag->pose.R[5];
    n[2] = tag->pose.R[8];
    tn = out->distance > 0.0f ? dot3(tag->pose.t, n) / out->distance : 1.0f;
    out->incidence = acosf(fmaxf(-1.0f, fminf(1.0f, tn)));
}

int sim_corner_order_wrong(const actag_point det[4], const actag_point truth[4], float *mean_px)
{
    float best = 1e30f, ident = 0.0f, side = 0.0f;
    int j, n, m, bestp = 0, misplaced = 0;
    /* a corner that is no number is no right corner (every comparison
     * below would be false and call it well ordered) */
    for (n = 0; n < 4; n++)
        if (!isfinite(det[n].x) || !isfinite(det[n].y)) {
            if (mean_px)
                *mean_px = NAN;
            return 1;
        }
    /* the best of the 8 dihedral assignments of the detection's labels */
    for (j = 0; j < 8; j++) {
        float cost = 0.0f;
        for (n = 0; n < 4; n++) {
            int src = j < 4 ? (n + j) & 3 : (j - n + 8) & 3;
            cost += hypotf(det[src].x - truth[n].x, det[src].y - truth[n].y);
        }
        if (j == 0)
            ident = cost;
        if (cost < best) {
            best = cost;
            bestp = j;
        }
    }
    /* each corner nearest its own truth corner: the dihedral test alone
     * ties on a swapped pair (a bow-tie) and misses a single corner far off;
     * and near it, within SIM_CORNER_TOLERANCE of a side: a scaled quad
     * about the right centre is nearest its own corners too */
    for (n = 0; n < 4; n++)
        side += 0.25f * hypotf(truth[n].x - truth[(n + 1) & 3].x,
                               truth[n].y - truth[(n + 1) & 3].y);
    for (n = 0; n < 4; n++) {
        float own = hypotf(det[n].x - truth[n].x, det[n].y - truth[n].y);
        if (own > SIM_CORNER_TOLERANCE * side)
            misplaced = 1;
        for (m = 0; m < 4; m++)
            if (m != n && hypotf(det[n].x - truth[m].x, det[n].y - truth[m].y) < own)
                misplaced = 1;
    }
    if (mean_px)
        *mean_px = 0.25f * ident;
    return (bestp != 0 && ident > best + 4.0f) || misplaced;
}

/* ------------------------------------------------------------ rendering */

typedef struct {
    float n[3], d;  /* plane n . p = d */
    int kind;       /* 0 seabed, 1 tag */
    const sim_tag *tag;
    float half;     /* tag: half side */
    float cell;     /* tag: cell size */
    int k;
    uint8_t layout[SIM_MAX_K + 1][SIM_MAX_K + 1];
    int front;      /* tag: the sonar sees its face */
} surface;

typedef struct {
    const sim_sonar *s;
    const sim_scene *sc;
    const sim_appearance *a;
    surface surf[SIM_MAX_TAGS + 1];
    int nsurf;
    float half_v, dr;
    float prmin[SIM_MAX_PATCHES], prmax[SIM_MAX_PATCHES];
    float pamin[SIM_MAX_PATCHES], pamax[SIM_MAX_PATCHES];
} render_ctx;

static int inside_tag(const surface *S, const float *p, float *tx, float *ty)
{
    float q[3], v[3];
    const sim_tag *t = S->tag;
    v[0] = p[0] - t->pose.t[0];
    v[1] = p[1] - t->pose.t[1];
    v[2] = p[2] - t->pose.t[2];
    mat_t_vec(t->pose.R, v, q);
    *tx = q[0];
    *ty = q[1];
    return fabsf(q[0]) <= S->half && fabsf(q[1]) <= S->half;
}

/* Is the segment from the sonar to p (range r, unit direction u) blocked by a
 * tag other than `self`? */
static int shadowed(const render_ctx *c, const float *u, float r, int self)
{
    int i;
    for (i = 0; i < c->nsurf; i++) {
        const surface *S = &c->surf[i];
        float nu, th, p[3], tx, ty;
        if (S->kind != 1 || i == self)
            continue;
        nu = dot3(S->n, u);
        if (fabsf(nu) < 1e-6f)
            continue;
        th = S->d / nu;
        if (th <= 0.0f || th >= r - 2e-3f)
            continue;
        p[0] = u[0] * th;
        p[1] = u[1] * th;
        p[2] = u[2] * th;
        if (inside_tag(S, p, &tx, &ty))
            return 1;
    }
    return 0;
}

static float patch_gain(const render_ctx *c, const float *p, float r, float az)
{
    float g = 1.0f;
    int i;
    for (i = 0; i < c->sc->npatches; i++) {
        const sim_patch *P = &c->sc->patches[i];
        float v[3];
        if (r < c->prmin[i] || r > c->prmax[i] || az < c->pamin[i] || az > c->pamax[i])
            continue;
        v[0] = p[0] - P->centre[0];
        v[1] = p[1] - P->centre[1];
        v[2] = p[2] - P->centre[2];
        if (fabsf(dot3(v, P->axis[0])) <= P->half[0] && fabsf(dot3(v, P->axis[1])) <= P->half[1])
            g *= P->gain;
    }
    return g;
}

static float pow_fast(float x, float e)
{
    if (e == 1.0f)
        return x;
    if (e == 0.5f)
        return sqrtf(x);
    if (e == 2.0f)
        return x * x;
    if (e == 0.0f)
        return 1.0f;
    return powf(x, e);
}

/* Returned intensity density at range r along the beam at azimuth az
 * (ca, sa = its cosine and sine), before the spreading loss. */
static float intensity_at(const render_ctx *c, float r, float az, float ca, float sa)
{
    const sim_appearance *a = c->a;
    float total = 0.0f;
    float jmax = 2.0f * sqrtf(2.0f / (r * c->dr));
    int i, b;
    for (i = 0; i < c->nsurf; i++) {
        const surface *S = &c->surf[i];
        float A = S->n[0] * ca + S->n[1] * sa, B = S->n[2];
        float rho = sqrtf(A * A + B * B), q, sq, cps, sps;
        if (rho < 1e-9f)
            continue;
        q = S->d / (r * rho);
        if (q > 1.0f || q < -1.0f) {
            /* The arc misses the plane at this range, but may touch it
             * within the range bin (a surface at normal incidence returns
             * from one range only): then the tangent point, at full
             * density. */
            if ((q < 0.0f ? -q : q) * r / (r + 0.5f * c->dr) > 1.0f)
                continue;
            q = q > 0.0f ? 1.0f : -1.0f;
        }
        sq = sqrtf(1.0f - q * q);
        cps = A / rho;
        sps = B / rho;
        for (b = 0; b < 2; b++) {
            /* e = psi +- alpha, cos(alpha) = q, sin(alpha) = sq */
            float sgn = b ? -1.0f : 1.0f;
            float ce = cps * q - sps * sgn * sq, se = sps * q + cps * sgn * sq;
            float e, beam, J, sigma, u[3], cinc;
            if (b == 1 && sq < 1e-7f)
                break; /* tangent: one solution */
            if (ce <= 0.0f)
                continue; /* behind the sonar */
            e = atan2f(se, ce);
            if (fabsf(e) > 2.0f * c->half_v)
                continue;
            beam = expf(-SIM_LN2 * (e / c->half_v) * (e / c->half_v));
            J = sq > 1e-9f ? fabsf(S->d) / (r * r * rho * sq) : jmax;
            if (J > jmax)
                J = jmax;
            u[0] = ce * ca;
            u[1] = ce * sa;
            u[2] = se;
            cinc = fabsf(dot3(S->n, u));
            if (S->kind == 1) {
                float p[3], tx, ty;
                int cxi, cyi, white;
                p[0] = u[0] * r;
                p[1] = u[1] * r;
                p[2] = u[2] * r;
                if (!inside_tag(S, p, &tx, &ty))
                    continue;
                if (shadowed(c, u, r, i))
                    continue;
                cxi = (int)floorf((tx + S->half) / S->cell);
                cyi = (int)floorf((ty + S->half) / S->cell);
                if (cxi < 0) cxi = 0;
                if (cyi < 0) cyi = 0;
                if (cxi > S->k) cxi = S->k;
                if (cyi > S->k) cyi = S->k;
                white = S->front && S->layout[cyi][cxi];
                if (white) {
                    sigma = a->foam * pow_fast(cinc, a->foam_exp);
                } else {
                    float inc = acosf(fminf(1.0f, cinc));
                    sigma = a->metal_specular * expf(-(inc / a->metal_lobe) * (inc / a->metal_lobe)) +
                            a->metal_diffuse;
                }
            } else {
                float p[3];
                if (shadowed(c, u, r, -1))
                    continue;
                p[0] = u[0] * r;
                p[1] = u[1] * r;
                p[2] = u[2] * r;
                sigma = a->seabed * pow_fast(cinc, a->seabed_exp);
                if (c->sc->npatches)
                    sigma *= patch_gain(c, p, r, az);
            }
            total += sigma * beam * J;
        }
    }
    return total;
}

/* Gaussian kernel with sum of squares 1 (keeps the speckle's mean power). */
static int psf_kernel(float sigma, float *k, int maxr)
{
    int r = (int)ceilf(2.5f * sigma), i;
    float s2 = 0.0f;
    if (sigma <= 0.0f)
        r = 0;
    if (r > maxr)
        r = maxr;
    for (i = -r; i <= r; i++) {
        k[i + r] = sigma > 0.0f ? expf(-0.5f * (float)(i * i) / (sigma * sigma)) : 1.0f;
        s2 += k[i + r] * k[i + r];
    }
    s2 = 1.0f / sqrtf(s2);
    for (i = 0; i <= 2 * r; i++)
        k[i] *= s2;
    return r;
}

/* Along each row (azimuth): out[c] = sum_i k[i] in[c+i-kr], zero outside;
 * tap by tap so the inner loop vectorises. */
static void convolve_rows(float *v, float *tmp, int rows, int cols, const float *k, int kr)
{
    int r, c, i;
    for (r = 0; r < rows; r++) {
        float *row = v + (size_t)r * (size_t)cols;
        for (c = 0; c < cols; c++)
            tmp[c] = 0.0f;
        for (i = -kr; i <= kr; i++) {
            float w = k[i + kr];
            int c0 = i < 0 ? -i : 0, c1 = i > 0 ? cols - i : cols;
            for (c = c0; c < c1; c++)
                tmp[c] += w * row[c + i];
        }
        memcpy(row, tmp, (size_t)cols * sizeof *row);
    }
}

/* Along each column (range), row by row so memory is read in order; out is
 * a rows x cols buffer. */
static void convolve_cols(const float *v, float *out, int rows, int cols, const float *k, int kr)
{
    int r, c, i;
    for (r = 0; r < rows; r++) {
        float *o = out + (size_t)r * (size_t)cols;
        for (c = 0; c < cols; c++)
            o[c] = 0.0f;
        for (i = -kr; i <= kr; i++) {
            const float *src;
            float w = k[i + kr];
            if (r + i < 0 || r + i >= rows)
                continue;
            src = v + (size_t)(r + i) * (size_t)cols;
            for (c = 0; c < cols; c++)
                o[c] += w * src[c];
        }
    }
}

/* Unit-variance approximately Gaussian number (sum of four uniforms). */
static float gauss(actag_rng *g)
{
    uint32_t a = actag_rng_next(g), b = actag_rng_next(g);
    float s = (float)(a & 0xffff) + (float)(a >> 16) + (float)(b & 0xffff) + (float)(b >> 16);
    return (s * (1.0f / 65536.0f) - 2.0f) * 1.7320508f;
}

int sim_render(const sim_sonar *s, const sim_scene *scene, const sim_appearance *a,
               uint32_t seed, uint8_t *out, uint16_t *out16, int out_stride, char *err)
{
    render_ctx c;
    int rows, cols, i, r, col, ss;
    float *re, *im, *tmp, *rowgain, kern[2 * SIM_MAX_PSF_RADIUS + 1], *mean, *acc, *col_tmp, *caz, *saz;
    int look, nlooks = a->looks < 1 ? 1 : (a->looks > 8 ? 8 : a->looks);
    float *raz, *rr;
    uint8_t *super;
    actag_rng g;
    size_t n;
    if (!s || !scene || !a || (!out && !out16))
        return fail(err, "sim_render: NULL argument");
    rows = s->rows;
    cols = s->cols;
    if (rows < 2 || cols < 2 || out_stride < cols)
        return fail(err, "sim_render: frame must be at least 2 x 2 with stride >= cols");
    {
        actag_error_detail d;
        if (actag_geometry_validate(&s->geo, rows, cols, &d) != ACTAG_OK) {
            if (err)
                snprintf(err, 256, "sim_render: invalid sonar geometry: %s %s (got %g)",
                         d.field, d.rule, d.value);
            return -1;
        }
    }
    if (!(s->vertical_aperture > 0.0f) || s->vertical_aperture > SIM_PI)
        return fail(err, "sim_render: vertical aperture must be in (0, pi]");
    if (scene->ntags < 0 || scene->ntags > SIM_MAX_TAGS || scene->npatches < 0 ||
        scene->npatches > SIM_MAX_PATCHES)
        return fail(err, "sim_render: too many tags or patches");
    memset(&c, 0, sizeof c);
    c.s = s;
    c.sc = scene;
    c.a = a;
    c.half_v = 0.5f * s->vertical_aperture;
    c.dr = (s->geo.max_range - s->geo.min_range) / (float)(rows - 1);
    if (scene->has_seabed) {
        surface *S = &c.surf[c.nsurf++];
        memcpy(S->n, scene->seabed_n, sizeof S->n);
        S->d = scene->seabed_d;
        S->kind = 0;
    }
    for (i = 0; i < scene->ntags; i++) {
        const sim_tag *t = &scene->tags[i];
        surface *S = &c.surf[c.nsurf++];
        int x, y, k = t->family.bits / 4;
        if (k < 4 || k > SIM_MAX_K || t->id < 0 || t->id >= t->family.ncodes || !(t->tag_size > 0.0f))
            return fail(err, "sim_render: bad tag (family, id or size)");
        S->kind = 1;
        S->tag = t;
        S->k = k;
        S->n[0] = t->pose.R[2];
        S->n[1] = t->pose.R[5];
        S->n[2] = t->pose.R[8];
        S->d = dot3(S->n, t->pose.t);
        S->front = S->d > 0.0f;
        S->cell = t->tag_size / (float)(k - 3);
        S->half = 0.5f * S->cell * (float)(k + 1);
        for (y = 0; y <= k; y++)
            for (x = 0; x <= k; x++)
                S->layout[y][x] = (uint8_t)(actag_layout_cell(&t->family, t->id, x, y) == 1);
    }
    for (i = 0; i < scene->npatches; i++) {
        /* polar bounding box of the patch (its corners and centre, padded) */
        const sim_patch *P = &scene->patches[i];
        int j;
        c.prmin[i] = c.pamin[i] = 1e30f;
        c.prmax[i] = c.pamax[i] = -1e30f;
        for (j = 0; j < 9; j++) {
            float p[3], rr0, az0, el0, fu = (float)(j % 3 - 1), fv = (float)(j / 3 - 1);
            int q;
            for (q = 0; q < 3; q++)
                p[q] = P->centre[q] + fu * P->half[0] * P->axis[0][q] + fv * P->half[1] * P->axis[1][q];
            polar_of(p, &rr0, &az0, &el0);
            c.prmin[i] = fminf(c.prmin[i], rr0);
            c.prmax[i] = fmaxf(c.prmax[i], rr0);
            c.pamin[i] = fminf(c.pamin[i], az0);
            c.pamax[i] = fmaxf(c.pamax[i], az0);
        }
        c.prmin[i] -= 0.02f;
        c.prmax[i] += 0.02f;
        c.pamin[i] -= 0.02f;
        c.pamax[i] += 0.02f;
    }

    n = (size_t)rows * (size_t)cols;
    re = (float *)malloc(n * sizeof *re);
    mean = (float *)malloc(n * sizeof *mean);
    acc = (float *)malloc(n * sizeof *acc);
    col_tmp = (float *)malloc(n * sizeof *col_tmp);
    im = (float *)malloc(n * sizeof *im);
    tmp = (float *)malloc(2 * (size_t)(rows > cols ? rows : cols) * sizeof *tmp + 16);
    rowgain = (float *)malloc((size_t)rows * sizeof *rowgain);
    super = (uint8_t *)calloc(n, 1);
    raz = (float *)malloc((size_t)cols * 4 * sizeof *raz);
    caz = (float *)malloc((size_t)cols * 5 * 2 * sizeof *caz);
    saz = caz ? caz + (size_t)cols * 5 : NULL;
    rr = (float *)malloc((size_t)rows * 4 * sizeof *rr);
    if (!re || !im || !tmp || !rowgain || !super || !raz || !rr || !mean || !acc || !col_tmp || !caz) {
        free(caz); free(col_tmp); free(mean); free(acc); free(re); free(im); free(tmp); free(rowgain); free(super); free(raz); free(rr);
        return fail(err, "sim_render: out of memory");
    }
    ss = a->supersample < 1 ? 1 : (a->supersample > 4 ? 4 : a->supersample);
    /* Supersample only around tags (sharp foam/metal edges). */
    for (i = 0; i < scene->ntags; i++) {
        const sim_tag *t = &scene->tags[i];
        float W = tag_side(t), xmin = 1e30f, xmax = -1e30f, ymin = 1e30f, ymax = -1e30f;
        int u, v, y0, y1, x0, x1;
        for (u = 0; u <= 4; u++)
            for (v = 0; v <= 4; v++) {
                float p[3], rr0, az0, el0, x, y;
                tag_point(t, ((float)u / 4.0f - 0.5f) * W, ((float)v / 4.0f - 0.5f) * W, p);
                polar_of(p, &rr0, &az0, &el0);
                sim_pixel_of(s, rr0, az0, &x, &y);
                xmin = fminf(xmin, x);
                xmax = fmaxf(xmax, x);
                ymin = fminf(ymin, y);
                ymax = fmaxf(ymax, y);
            }
        x0 = (int)fmaxf(0.0f, xmin - 4.0f);
        x1 = (int)fminf((float)cols - 1.0f, xmax + 4.0f);
        y0 = (int)fmaxf(0.0f, ymin - 4.0f);
        y1 = (int)fminf((float)rows - 1.0f, ymax + 4.0f);
        for (v = y0; v <= y1; v++)
            for (u = x0; u <= x1; u++)
                super[(size_t)v * (size_t)cols + (size_t)u] = 1;
    }
    /* sub-pixel positions: index 0 = centre, 1..ss = supersample offsets */
    for (col = 0; col < cols; col++) {
        for (i = 0; i < ss; i++)
            raz[4 * col + i] = actag_geometry_azimuth(
                &s->geo, cols, (float)col + ((float)i + 0.5f) / (float)ss - 0.5f);
    }
    for (col = 0; col < cols; col++) {
        float az0 = actag_geometry_azimuth(&s->geo, cols, (float)col);
        caz[5 * col] = cosf(az0);
        saz[5 * col] = sinf(az0);
        for (i = 0; i < ss; i++) {
            caz[5 * col + 1 + i] = cosf(raz[4 * col + i]);
            saz[5 * col + 1 + i] = sinf(raz[4 * col + i]);
        }
    }
    for (r = 0; r < rows; r++)
        for (i = 0; i < ss; i++)
            rr[4 * r + i] = actag_geometry_range(&s->geo, rows,
                                                 (float)r + ((float)i + 0.5f) / (float)ss - 0.5f);

    /* mean intensity per pixel (kept in acc), then `looks` speckle fields */
    actag_rng_seed(&g, seed);
    for (r = 0; r < rows; r++) {
        float rc = actag_geometry_range(&s->geo, rows, (float)r);
        /* range 0 (a min range of 0): the nearest bin's centre, not infinity */
        float loss = a->spreading != 0.0f
                         ? powf(a->spreading_r0 / fmaxf(rc, 0.5f * c.dr), a->spreading)
                         : 1.0f;
        for (col = 0; col < cols; col++) {
            size_t idx = (size_t)r * (size_t)cols + (size_t)col;
            float I;
            if (super[idx] && ss > 1) {
                int u, v;
                I = 0.0f;
                for (v = 0; v < ss; v++)
                    for (u = 0; u < ss; u++)
                        I += intensity_at(&c, rr[4 * r + v], raz[4 * col + u],
                                          caz[5 * col + 1 + u], saz[5 * col + 1 + u]);
                I /= (float)(ss * ss);
            } else {
                I = intensity_at(&c, rc, actag_geometry_azimuth(&s->geo, cols, (float)col),
                                 caz[5 * col], saz[5 * col]);
            }
            mean[idx] = sqrtf((I * loss + a->noise) * 0.5f);
            acc[idx] = 0.0f;
        }
    }
    for (look = 0; look < nlooks; look++) {
        size_t idx;
        int kr;
        for (idx = 0; idx < n; idx++) {
            if (a->speckle) {
                re[idx] = mean[idx] * gauss(&g);
                im[idx] = mean[idx] * gauss(&g);
            } else { /* the mean field: the point spread's effect alone */
                re[idx] = mean[idx] * 1.41421356f;
                im[idx] = 0.0f;
            }
        }
        /* beam spread: azimuth (along a row) then range (along a column) */
        kr = psf_kernel(a->psf_azimuth /
                            actag_geometry_azimuth_step(&s->geo, cols, 0.5f * (float)cols),
                        kern, SIM_MAX_PSF_RADIUS);
        if (kr > 0) {
            convolve_rows(re, tmp, rows, cols, kern, kr);
            convolve_rows(im, tmp, rows, cols, kern, kr);
        }
        kr = psf_kernel(a->psf_range / c.dr, kern, SIM_MAX_PSF_RADIUS);
        if (kr > 0) {
            convolve_cols(re, col_tmp, rows, cols, kern, kr);
            for (idx = 0; idx < n; idx++)
                acc[idx] += col_tmp[idx] * col_tmp[idx];
            convolve_cols(im, col_tmp, rows, cols, kern, kr);
            for (idx = 0; idx < n; idx++)
                acc[idx] += col_tmp[idx] * col_tmp[idx];
        } else {
            for (idx = 0; idx < n; idx++)
                acc[idx] += re[idx] * re[idx] + im[idx] * im[idx];
        }
    }
    /* interference bands: constant-range gain changes */
    for (r = 0; r < rows; r++)
        rowgain[r] = 1.0f;
    {
        int nb = 0;
        float lim = a->band_rate;
        /* Poisson count by inversion */
        float p = expf(-lim), cum = p, u = urand(&g);
        while (u > cum && nb < 20) {
            nb++;
            p *= lim / (float)nb;
            cum += p;
        }
        for (i = 0; i < nb; i++) {
            float centre = urand(&g) * (float)rows, w = urange(&g, 1.0f, 6.0f);
            float lg = urange(&g, logf(a->band_min), logf(a->band_max));
            for (r = 0; r < rows; r++) {
                float d = ((float)r - centre) / w;
                if (d * d < 16.0f)
                    rowgain[r] *= expf(lg * expf(-d * d));
            }
        }
    }
    for (r = 0; r < rows; r++)
        for (col = 0; col < cols; col++) {
            size_t idx = (size_t)r * (size_t)cols + (size_t)col;
            float v = a->gain * rowgain[r] * sqrtf(acc[idx] / (float)nlooks);
            if (!(v >= 0.0f))
                v = 0.0f; /* NaN-safe before the integer casts */
            if (out16) {
                float v16 = v * 256.0f + 0.5f;
                out16[(size_t)r * (size_t)out_stride + (size_t)col] =
                    (uint16_t)(v16 > 65535.0f ? 65535.0f : v16);
            } else {
                float v8 = v + 0.5f;
                out[(size_t)r * (size_t)out_stride + (size_t)col] =
                    (uint8_t)(v8 > 255.0f ? 255.0f : v8);
            }
        }
    free(caz); free(col_tmp); free(mean); free(acc);
    free(re); free(im); free(tmp); free(rowgain); free(super); free(raz); free(rr);
    return 0;
}

/* ------------------------------------------------------------ protocol */

/* Sonar-from-world rotation looking from S toward the origin, then turned so
 * the origin appears at (azimuth da, elevation de), rolled about that line of
 * sight by roll. */
static void look_at(const float *S, float da, float de, float roll, float *Rsw)
{
    float f[3], y[3], z[3], Z[3] = {0.0f, 0.0f, 1.0f}, Rbase[9], Q[9], Rr[9], u[3];
    float Rz[9], Ry[9];
    f[0] = -S[0];
    f[1] = -S[1];
    f[2] = -S[2];
    normalize3(f);
    cross3(Z, f, y);
    if (dot3(y, y) < 1e-12f) {
        y[0] = 0.0f;
        y[1] = 1.0f;
        y[2] = 0.0f;
    }
    normalize3(y);
    cross3(f, y, z);
    /* Rbase: columns f, y, z (sonar axes in world) */
    Rbase[0] = f[0]; Rbase[1] = y[0]; Rbase[2] = z[0];
    Rbase[3] = f[1]; Rbase[4] = y[1]; Rbase[5] = z[1];
    Rbase[6] = f[2]; Rbase[7] = y[2]; Rbase[8] = z[2];
    /* Q = Rz(da) Ry(-de): maps (1,0,0) to the wanted direction; the sonar
     * frame is Q^T times the base frame's coordinates. */
    {
        sim_pose pz, py;
        sim_pose_from_rpy(0, 0, 0, 0, 0, da, &pz);
        sim_pose_from_rpy(0, 0, 0, 0, -de, 0, &py);
        memcpy(Rz, pz.R, sizeof Rz);
        memcpy(Ry, py.R, sizeof Ry);
    }
    mat_mul(Rz, Ry, Q);
    u[0] = Q[0];
    u[1] = Q[3];
    u[2] = Q[6];
    mat_axis_angle(u, roll, Rr);
    /* p_sonar = Rr * Q * Rbase^T * (p_world - S): the base line of sight
     * (1,0,0) lands on u, roll turns about u. */
    {
        float Bt[9], M[9];
        mat_transpose(Rbase, Bt);
        mat_mul(Q, Bt, M);
        mat_mul(Rr, M, Rsw);
    }
}

static void make_seabed(const float *Rsw, const float *S, float z_world, sim_scene *sc)
{
    float nw[3] = {0.0f, 0.0f, 1.0f};
    mat_vec(Rsw, nw, sc->seabed_n);
    sc->seabed_d = z_world - S[2];
    sc->has_seabed = 1;
}

static void add_clutter(const sim_sonar *s, const sim_view_params *v, actag_rng *g,
                        const float *Rsw, const float *S, const sim_tag *avoid, sim_scene *sc)
{
    int n = v->clutter > 0 ? (int)actag_rng_below(g, (uint32_t)(2 * v->clutter + 1)) : 0, i;
    float alo, ahi;
    azimuth_limit(s, &alo, &ahi);
    sc->npatches = 0;
    for (i = 0; i < n && sc->npatches < SIM_MAX_PATCHES; i++) {
        /* a random point of the seabed in the field of view */
        float r = urange(g, s->geo.min_range, s->geo.max_range), az = urange(g, alo, ahi);
        float A = sc->seabed_n[0] * cosf(az) + sc->seabed_n[1] * sinf(az), B = sc->seabed_n[2];
        float rho = sqrtf(A * A + B * B), q, e, p[3], nw[3], a1[3], a2[3], ang;
        sim_patch *P = &sc->patches[sc->npatches];
        int j;
        if (rho < 1e-6f)
            continue;
        q = sc->seabed_d / (r * rho);
        if (q < -1.0f || q > 1.0f)
            continue;
        e = atan2f(B, A) - acosf(q);
        if (fabsf(e) > 0.5f * s->vertical_aperture)
            e = atan2f(B, A) + acosf(q);
        if (fabsf(e) > s->vertical_aperture)
            continue;
        p[0] = r * cosf(e) * cosf(az);
        p[1] = r * cosf(e) * sinf(az);
        p[2] = r * sinf(e);
        if (avoid) {
            float d[3], W = tag_side(avoid);
            for (j = 0; j < 3; j++)
                d[j] = p[j] - avoid->pose.t[j];
            if (sqrtf(dot3(d, d)) < 0.75f * W + 0.1f)
                continue;
        }
        memcpy(P->centre, p, sizeof P->centre);
        /* in-plane axes: world x/y turned by a random angle, in the sonar frame */
        ang = urange(g, 0.0f, 2.0f * SIM_PI);
        nw[0] = cosf(ang);
        nw[1] = sinf(ang);
        nw[2] = 0.0f;
        mat_vec(Rsw, nw, a1);
        nw[0] = -sinf(ang);
        nw[1] = cosf(ang);
        mat_vec(Rsw, nw, a2);
        memcpy(P->axis[0], a1, sizeof a1);
        memcpy(P->axis[1], a2, sizeof a2);
        P->half[0] = urange(g, 0.01f, 0.12f);
        P->half[1] = urange(g, 0.01f, 0.12f);
        P->gain = expf(urange(g, logf(1.5f), logf(12.0f)));
        (void)S;
        sc->npatches++;
    }
}

static void random_sonar(const sim_sonar *s, const sim_view_params *v, actag_rng *g, float margin,
                         float *S, float *Rsw, float *dist, float *bearing)
{
    float alo, ahi, d, inc, beta, da, de, roll, amax, emax;
    azimuth_limit(s, &alo, &ahi);
    d = urange(g, v->min_distance, v->max_distance);
    inc = urange(g, v->min_incidence, v->max_incidence);
    beta = urange(g, 0.0f, 2.0f * SIM_PI);
    S[0] = d * sinf(inc) * cosf(beta);
    S[1] = d * sinf(inc) * sinf(beta);
    S[2] = d * cosf(inc);
    /* aim so the tag lands anywhere its whole outline fits */
    amax = 0.5f * (ahi - alo) - margin / d;
    emax = 0.5f * s->vertical_aperture - 0.5f * margin / d;
    da = 0.5f * (ahi + alo) + (amax > 0.0f ? urange(g, -amax, amax) : 0.0f);
    de = emax > 0.0f ? urange(g, -emax, emax) : 0.0f;
    roll = urange(g, -v->max_roll, v->max_roll);
    if (urand(g) < v->mirror_fraction) {
        roll += SIM_PI;
        de = -de;
    }
    look_at(S, da, de, roll, Rsw);
    *dist = d;
    *bearing = beta;
}

int sim_sample_view(const sim_sonar *s, const sim_view_params *v, uint32_t seed, sim_tag *tag,
                    sim_scene *scene)
{
    actag_rng g;
    int attempt;
    actag_rng_seed(&g, seed);
    for (attempt = 0; attempt < 200; attempt++) {
        float S[3], Rsw[9], Rwt[9], d, yaw, W = tag_side(tag), beta;
        float negS[3];
        sim_truth tr;
        random_sonar(s, v, &g, 0.75f * W, S, Rsw, &d, &beta);
        /* yaw = beta + pi/2: the printed top points away from the sonar */
        yaw = beta + 0.5f * SIM_PI + urange(&g, -v->max_yaw, v->max_yaw);
        /* tag in the world: face up (+Z), x = (cos yaw, sin yaw, 0), z = -Z */
        Rwt[0] = cosf(yaw); Rwt[1] = sinf(yaw);  Rwt[2] = 0.0f;
        Rwt[3] = sinf(yaw); Rwt[4] = -cosf(yaw); Rwt[5] = 0.0f;
        Rwt[6] = 0.0f;      Rwt[7] = 0.0f;       Rwt[8] = -1.0f;
        mat_mul(Rsw, Rwt, tag->pose.R);
        negS[0] = -S[0];
        negS[1] = -S[1];
        negS[2] = -S[2];
        mat_vec(Rsw, negS, tag->pose.t);
        sim_truth_of(s, tag, &tr);
        if (!tr.visible)
            continue;
        memset(scene, 0, sizeof *scene);
        scene->tags[0] = *tag;
        scene->ntags = 1;
        make_seabed(Rsw, S, -0.014f, scene);
        add_clutter(s, v, &g, Rsw, S, tag, scene);
        return 0;
    }
    return -1;
}

void sim_sample_empty(const sim_sonar *s, const sim_view_params *v, uint32_t seed,
                      sim_scene *scene)
{
    actag_rng g;
    float S[3], Rsw[9], d, beta;
    actag_rng_seed(&g, seed);
    random_sonar(s, v, &g, 0.0f, S, Rsw, &d, &beta);
    memset(scene, 0, sizeof *scene);
    make_seabed(Rsw, S, 0.0f, scene);
    add_clutter(s, v, &g, Rsw, S, NULL, scene);
}

void sim_sequence_view(const sim_sonar *s, const sim_view_params *v, uint32_t seed, int i, int n,
                       sim_tag *tag, sim_scene *scene)
{
    actag_rng g;
    float t = n > 1 ? (float)i / (float)(n - 1) : 0.0f, beta0, inc, h, rho0, rho1, rho, beta;
    float S[3], Rsw[9], Rwt[9], negS[3], yaw, dmid, wob;
    actag_rng_seed(&g, seed);
    beta0 = urange(&g, 0.0f, 2.0f * SIM_PI);
    yaw = urange(&g, 0.0f, 2.0f * SIM_PI);
    inc = 0.5f * (v->min_incidence + v->max_incidence);
    dmid = 0.5f * (v->min_distance + v->max_distance);
    h = dmid * cosf(inc);
    rho0 = v->max_distance * sinf(inc);
    rho1 = v->min_distance * sinf(inc);
    rho = rho0 + t * (rho1 - rho0);
    beta = beta0 + t * 40.0f * SIM_PI / 180.0f;
    S[0] = rho * cosf(beta);
    S[1] = rho * sinf(beta);
    S[2] = h;
    /* slow pointing wobble, as a vehicle's attitude */
    wob = 0.25f * sinf(2.0f * SIM_PI * 3.0f * t);
    look_at(S, wob * 0.3f * 0.5f * s->vertical_aperture, wob * 0.5f * s->vertical_aperture,
            v->max_roll * sinf(2.0f * SIM_PI * 2.0f * t), Rsw);
    Rwt[0] = cosf(yaw); Rwt[1] = sinf(yaw);  Rwt[2] = 0.0f;
    Rwt[3] = sinf(yaw); Rwt[4] = -cosf(yaw); Rwt[5] = 0.0f;
    Rwt[6] = 0.0f;      Rwt[7] = 0.0f;       Rwt[8] = -1.0f;
    mat_mul(Rsw, Rwt, tag->pose.R);
    negS[0] = -S[0];
    negS[1] = -S[1];
    negS[2] = -S[2];
    mat_vec(Rsw, negS, tag->pose.t);
    memset(scene, 0, sizeof *scene);
    scene->tags[0] = *tag;
    scene->ntags = 1;
    make_seabed(Rsw, S, -0.014f, scene);
    /* the same clutter layout in every frame of the pass (world-fixed) is
     * not modelled: each frame draws its own */
    actag_rng_seed(&g, sim_frame_seed(seed, (uint32_t)i));
    add_clutter(s, v, &g, Rsw, S, tag, scene);
}
