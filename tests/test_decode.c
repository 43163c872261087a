/* Decode stage: homography vs. a direct DLT solve, bit layout vs. the SPEC's
 * list, sampling vs. a brute-force sampler, rendered tags under all 8
 * dihedral transforms (+ affine/perspective warps), mirroring, bit flips
 * vs. a brute-force 8-orientation matcher, and error codes. */
#include "unity.h"
#include "test_util.h"

#include <math.h>

#include "actag/contours.h"
#include "actag/decode.h"
#include "actag/family.h"

void setUp(void) {}
void tearDown(void) {}

/* ------------------------------------------------------------------ helpers */

static double frand(double lo, double hi) { return lo + (hi - lo) * (double)tu_rand() / 4294967296.0; }

/* Sequence helpers written from the SPEC, independent of the library:
 * sequence position s is code bit bits-1-s. */
static int seq_get(uint32_t w, int bits, int s) { return (int)((w >> (bits - 1 - s)) & 1u); }
static uint32_t seq_set(uint32_t w, int bits, int s, int b)
{
    return b ? (w | (1u << (bits - 1 - s))) : (w & ~(1u << (bits - 1 - s)));
}
static uint32_t ref_rot(uint32_t w, int bits) /* rot90: sequence s <- s + k */
{
    uint32_t r = 0;
    int s;
    for (s = 0; s < bits; s++)
        r = seq_set(r, bits, s, seq_get(w, bits, (s + bits / 4) % bits));
    return r;
}
static uint32_t ref_mirror(uint32_t w, int bits) /* reflection: s <- -s */
{
    uint32_t r = 0;
    int s;
    for (s = 0; s < bits; s++)
        r = seq_set(r, bits, s, seq_get(w, bits, (bits - s) % bits));
    return r;
}
static uint32_t ref_rev(uint32_t w, int bits) /* SPEC's full reversal: s <- bits-1-s */
{
    uint32_t r = 0;
    int s;
    for (s = 0; s < bits; s++)
        r = seq_set(r, bits, s, seq_get(w, bits, bits - 1 - s));
    return r;
}

/* Cell (cx,cy) -> sequence index for a ring cell, derived independently
 * (walk the ring clockwise from the top-left cell). */
static int ring_index(int k, int cx, int cy)
{
    if (cy == 0 && cx < k)
        return cx;
    if (cx == k && cy < k)
        return k + cy;
    if (cy == k && cx > 0)
        return 2 * k + (k - cx);
    return 3 * k + (k - cy); /* cx == 0, cy in 1..k */
}

/* Colour of tag cell (cx,cy) of `code`: 1 white, 0 black. */
static int tag_cell(uint32_t code, int k, int cx, int cy)
{
    int ring = cx;
    if (cy < ring) ring = cy;
    if (k - cx < ring) ring = k - cx;
    if (k - cy < ring) ring = k - cy;
    if (ring == 0)
        return seq_get(code, 4 * k, ring_index(k, cx, cy));
    return ring == 1 ? 0 : 1;
}

/* 3x3 matrices in double, row-major. */
static void m3_mul(const double *a, const double *b, double *o)
{
    double t[9];
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            t[i * 3 + j] = a[i * 3] * b[j] + a[i * 3 + 1] * b[3 + j] + a[i * 3 + 2] * b[6 + j];
    memcpy(o, t, sizeof t);
}
static void m3_inv(const double *m, double *o)
{
    double a = m[0], b = m[1], c = m[2], d = m[3], e = m[4], f = m[5], g = m[6], h = m[7], i = m[8];
    double A = e * i - f * h, B = -(d * i - f * g), C = d * h - e * g;
    double det = a * A + b * B + c * C;
    o[0] = A / det; o[1] = -(b * i - c * h) / det; o[2] = (b * f - c * e) / det;
    o[3] = B / det; o[4] = (a * i - c * g) / det; o[5] = -(a * f - c * d) / det;
    o[6] = C / det; o[7] = -(a * h - b * g) / det; o[8] = (a * e - b * d) / det;
}
static double m3_apply(const double *m, double u, double v, double *x, double *y)
{
    double w = m[6] * u + m[7] * v + m[8];
    *x = (m[0] * u + m[1] * v + m[2]) / w;
    *y = (m[3] * u + m[4] * v + m[5]) / w;
    return w;
}

/* Direct linear transform: solve the 8x8 system for the homography mapping
 * src[i] -> dst[i] (h8 = 1), Gaussian elimination with partial pivoting. */
static int dlt(double src[4][2], double dst[4][2], double Hd[9])
{
    double A[8][9];
    int i, j, r, c;
    for (i = 0; i < 4; i++) {
        double u = src[i][0], v = src[i][1], x = dst[i][0], y = dst[i][1];
        double r0[9] = {u, v, 1, 0, 0, 0, -u * x, -v * x, x};
        double r1[9] = {0, 0, 0, u, v, 1, -u * y, -v * y, y};
        memcpy(A[2 * i], r0, sizeof r0);
        memcpy(A[2 * i + 1], r1, sizeof r1);
    }
    for (c = 0; c < 8; c++) {
        int p = c;
        for (r = c + 1; r < 8; r++)
            if (fabs(A[r][c]) > fabs(A[p][c]))
                p = r;
        if (fabs(A[p][c]) < 1e-12)
            return 0;
        for (j = 0; j < 9; j++) {
            double t = A[c][j];
            A[c][j] = A[p][j];
            A[p][j] = t;
        }
        for (r = 0; r < 8; r++) {
            if (r != c) {
                double f = A[r][c] / A[c][c];
                for (j = c; j < 9; j++)
                    A[r][j] -= f * A[c][j];
            }
        }
    }
    for (i = 0; i < 8; i++)
        Hd[i] = A[i][8] / A[i][i];
    Hd[8] = 1.0;
    return 1;
}

/* DLT homography from the tag grid to the image for quad corners 0..3. */
static int dlt_tag(const actag_point q[4], int k, double Hd[9])
{
    double src[4][2] = {{2, 2}, {0, 2}, {0, 0}, {2, 0}};
    double dst[4][2];
    int i;
    src[1][0] = src[2][0] = k - 1;
    src[2][1] = src[3][1] = k - 1;
    for (i = 0; i < 4; i++) {
        dst[i][0] = q[i].x;
        dst[i][1] = q[i].y;
    }
    return dlt(src, dst, Hd);
}

/* Least-squares affine map from the tag grid to the image for quad corners
 * 0..3: the 3x3 normal equations, solved by Gaussian elimination. */
static void lstsq_affine_tag(const actag_point q[4], int k, double Hd[9])
{
    double gu[4] = {2, 0, 0, 2}, gv[4] = {2, 2, 0, 0};
    int coord, i, r, c, j;
    gu[1] = gu[2] = k - 1;
    gv[2] = gv[3] = k - 1;
    for (coord = 0; coord < 2; coord++) {
        double A[3][4];
        memset(A, 0, sizeof A);
        for (i = 0; i < 4; i++) {
            double row[3] = {gu[i], gv[i], 1.0};
            double t = coord ? q[i].y : q[i].x;
            for (r = 0; r < 3; r++) {
                for (c = 0; c < 3; c++)
                    A[r][c] += row[r] * row[c];
                A[r][3] += row[r] * t;
            }
        }
        for (c = 0; c < 3; c++) {
            for (r = 0; r < 3; r++) {
                if (r != c) {
                    double f = A[r][c] / A[c][c];
                    for (j = c; j < 4; j++)
                        A[r][j] -= f * A[c][j];
                }
            }
        }
        for (r = 0; r < 3; r++)
            Hd[coord * 3 + r] = A[r][3] / A[r][r];
    }
    Hd[6] = 0.0;
    Hd[7] = 0.0;
    Hd[8] = 1.0;
}

/* Grid -> image transform of a rendered tag: image centre + warp(cell size *
 * dihedral(u - m, v - m)); `mirror` reflects x, `rot` turns by rot*90 deg. */
static void make_transform(int k, double cs, int rot, int mirror, double cx, double cy,
                           const double W[9], double T[9])
{
    double m = (k + 1) / 2.0;
    double C[9] = {1, 0, -m, 0, 1, -m, 0, 0, 1};
    double D[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    double S[9] = {0, 0, 0, 0, 0, 0, 0, 0, 1};
    double Tr[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    int i;
    for (i = 0; i < rot; i++) { /* (x,y) -> (-y, x): 90 deg clockwise on screen */
        double R[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1};
        m3_mul(R, D, D);
    }
    if (mirror) {
        double F[9] = {-1, 0, 0, 0, 1, 0, 0, 0, 1};
        m3_mul(F, D, D);
    }
    S[0] = S[4] = cs;
    Tr[2] = cx;
    Tr[5] = cy;
    m3_mul(D, C, T);
    m3_mul(S, T, T);
    m3_mul(W, T, T);
    m3_mul(Tr, T, T);
}

/* Renders the tag by inverse mapping every pixel centre; outside: black.
 * Padding bytes past cols are set white, so a stride bug shows. */
static void render(uint8_t *img, int rows, int cols, int stride, const double T[9], int k,
                   uint32_t code, uint8_t white)
{
    double Ti[9];
    int r, c;
    m3_inv(T, Ti);
    memset(img, 255, (size_t)rows * (size_t)stride);
    for (r = 0; r < rows; r++) {
        for (c = 0; c < cols; c++) {
            double u, v;
            double w = m3_apply(Ti, c, r, &u, &v);
            int val = 0;
            if (w > 0 && u >= 0 && v >= 0 && u < k + 1 && v < k + 1)
                val = tag_cell(code, k, (int)floor(u), (int)floor(v));
            img[(size_t)r * (size_t)stride + (size_t)c] = val ? white : 0;
        }
    }
}

/* The word a correct decoder must read clockwise from quad[0] (quad in
 * clockwise-on-screen order), computed through geometry only: my grid ->
 * image (DLT) -> tag grid (T^-1) -> printed cell. */
static uint32_t expected_observed(const double T[9], const actag_point q[4], int k, uint32_t code)
{
    double Hd[9], Ti[9];
    uint32_t w = 0;
    int s, cx = 0, cy = 0;
    TEST_ASSERT_TRUE(dlt_tag(q, k, Hd));
    m3_inv(T, Ti);
    for (s = 0; s < 4 * k; s++) {
        double x, y, u, v;
        /* find my cell of sequence s by scanning the ring */
        for (cy = 0; cy <= k; cy++)
            for (cx = 0; cx <= k; cx++)
                if ((cx == 0 || cy == 0 || cx == k || cy == k) && ring_index(k, cx, cy) == s)
                    goto found;
    found:
        m3_apply(Hd, cx + 0.5, cy + 0.5, &x, &y);
        m3_apply(Ti, x, y, &u, &v);
        w = seq_set(w, 4 * k, s, tag_cell(code, k, (int)floor(u), (int)floor(v)));
    }
    return w;
}

/* Brute-force decoder over the 8 physical orientations (4 rotations, each
 * optionally reflected): smallest distance per handedness; ties: lowest ID,
 * then lowest rotation; unmirrored wins a tie between handednesses. */
typedef struct oracle_res {
    int ok, id, hamming, mirrored, rotation, du, dm;
} oracle_res;
static oracle_res oracle(const uint32_t *codes, int n, int bits, uint32_t w, int maxc)
{
    oracle_res o;
    int best[2] = {1000, 1000}, bid[2] = {0, 0}, brot[2] = {0, 0};
    int h, i, r;
    memset(&o, 0, sizeof o);
    for (h = 0; h < 2; h++) {
        for (i = 0; i < n; i++) {
            uint32_t c = codes[i];
            for (r = 0; r < 4; r++) {
                uint32_t word = h ? ref_mirror(c, bits) : c;
                int d = tu_popcount(word ^ w);
                if (d < best[h]) {
                    best[h] = d;
                    bid[h] = i;
                    brot[h] = r;
                }
                c = ref_rot(c, bits);
            }
        }
    }
    h = best[1] < best[0] ? 1 : 0;
    o.ok = best[h] <= maxc;
    o.id = bid[h];
    o.hamming = best[h];
    o.mirrored = h;
    o.rotation = brot[h];
    o.du = best[0];
    o.dm = best[1];
    return o;
}

/* Families used by the render tests. */
typedef struct test_family {
    uint32_t codes[64];
    actag_family fam;
} test_family;

static void load_h10(test_family *tf)
{
    if (actag_family_get("AcTag24h10", &tf->fam) == ACTAG_OK) {
        TEST_ASSERT_EQUAL_INT(7, tf->fam.ncodes);
        memcpy(tf->codes, tf->fam.codes, 7 * sizeof(uint32_t));
    } else { /* generator not built: read the published file */
        char path[512];
        snprintf(path, sizeof path, "%s/families/AcTag24h10.txt", TU_DATA);
        TEST_ASSERT_EQUAL_INT(7, tu_read_codes(path, tf->codes, 64));
        tf->fam.name = "AcTag24h10";
        tf->fam.bits = 24;
        tf->fam.hamming = 10;
        tf->fam.ncodes = 7;
    }
    tf->fam.codes = tf->codes;
}

/* Smallest distance between any two of the 8 physical orientations of the
 * family's codes (same code included, identity excluded). */
static int physical_min_distance(const uint32_t *codes, int n, int bits)
{
    int i, j, a, b, best = 1000;
    for (i = 0; i < n; i++) {
        for (j = i; j < n; j++) {
            for (a = 0; a < 8; a++) {
                for (b = 0; b < 8; b++) {
                    uint32_t x = codes[i], y = codes[j];
                    int t, d;
                    if (i == j && a == b)
                        continue;
                    for (t = 0; t < (a & 3); t++) x = ref_rot(x, bits);
                    for (t = 0; t < (b & 3); t++) y = ref_rot(y, bits);
                    if (a & 4) x = ref_mirror(x, bits);
                    if (b & 4) y = ref_mirror(y, bits);
                    d = tu_popcount(x ^ y);
                    if (d < best)
                        best = d;
                }
            }
        }
    }
    return best;
}

/* A hand-made family of `bits` bits whose physical orientations are all at
 * least `h` apart (random codes, greedy). */
static void make_family(test_family *tf, int bits, int h, int n, const char *name)
{
    int count = 0, tries = 0;
    uint32_t mask = bits == 32 ? 0xffffffffu : ((1u << bits) - 1u);
    while (count < n && tries < 100000) {
        tf->codes[count] = tu_rand() & mask;
        tries++;
        if (physical_min_distance(tf->codes, count + 1, bits) >= h)
            count++;
    }
    TEST_ASSERT_EQUAL_INT(n, count);
    tf->fam.name = name;
    tf->fam.bits = bits;
    tf->fam.hamming = h;
    tf->fam.ncodes = n;
    tf->fam.codes = tf->codes;
}

/* ------------------------------------------------------------------ homography */

static int random_quad(actag_point q[4], double spread)
{
    /* a random parallelogram-ish quad with perturbed corners */
    double cx = frand(-50, 600), cy = frand(-50, 600), s = frand(4, 150);
    double a = frand(0, 6.283185307), sk = frand(0.5, 1.5);
    double base[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    int i;
    for (i = 0; i < 4; i++) {
        double x = base[i][0] * s * sk + frand(-spread, spread) * s;
        double y = base[i][1] * s + frand(-spread, spread) * s;
        q[i].x = (float)(cx + cos(a) * x - sin(a) * y);
        q[i].y = (float)(cy + sin(a) * x + cos(a) * y);
    }
    return 1;
}

/* Strict convexity in double, for the brute-force degeneracy reference. */
static int ref_convex(const actag_point q[4], double *minsin)
{
    int i, pos = 0, neg = 0;
    *minsin = 1.0;
    for (i = 0; i < 4; i++) {
        double e1x = (double)q[(i + 1) & 3].x - q[i].x, e1y = (double)q[(i + 1) & 3].y - q[i].y;
        double e2x = (double)q[(i + 2) & 3].x - q[(i + 1) & 3].x;
        double e2y = (double)q[(i + 2) & 3].y - q[(i + 1) & 3].y;
        double z = e1x * e2y - e1y * e2x;
        double sn = z / sqrt((e1x * e1x + e1y * e1y) * (e2x * e2x + e2y * e2y));
        if (fabs(sn) < *minsin)
            *minsin = fabs(sn);
        if (z > 0) pos++;
        if (z < 0) neg++;
    }
    return pos == 4 || neg == 4;
}

static void test_homography_vs_dlt(void)
{
    int t, nok = 0, nrej = 0;
    tu_seed(101);
    for (t = 0; t < 4000; t++) {
        actag_point q[4];
        float H[9];
        double Hd[9], minsin, wmin = 1e300;
        int bits = 16 + 4 * tu_range(0, 4), k = bits / 4, i, rc, conv;
        random_quad(q, t < 2000 ? 0.15 : 0.6);
        if (t % 2) { /* counter-clockwise order too */
            actag_point tmp = q[1];
            q[1] = q[3];
            q[3] = tmp;
        }
        rc = actag_tag_homography(q, bits, H);
        conv = ref_convex(q, &minsin);
        if (!conv || minsin < 2e-3) {
            if (!conv)
                TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, rc);
            continue; /* near the 1e-3 threshold: either answer is fine */
        }
        TEST_ASSERT_TRUE(dlt_tag(q, k, Hd));
        for (i = 0; i < 4; i++) { /* w at the corners of the whole grid */
            double u = (i == 1 || i == 2) ? k + 1 : 0, v = i >= 2 ? k + 1 : 0;
            double w = Hd[6] * u + Hd[7] * v + Hd[8];
            if (w < wmin)
                wmin = w;
        }
        if (wmin <= 1e-3 || wmin > 1e300) {
            if (wmin <= -1e-3)
                TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, rc);
            if (rc == ACTAG_ERR_PARAM)
                nrej++;
            continue;
        }
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, rc);
        nok++;
        /* corners exactly */
        {
            double gu[4] = {2, 0, 0, 2}, gv[4] = {2, 2, 0, 0};
            gu[1] = gu[2] = k - 1;
            gv[2] = gv[3] = k - 1;
            for (i = 0; i < 4; i++) {
                actag_point p;
                actag_homography_apply(H, (float)gu[i], (float)gv[i], &p);
                TEST_ASSERT_FLOAT_WITHIN(1e-3f + 2e-6f * fabsf(q[i].x), q[i].x, p.x);
                TEST_ASSERT_FLOAT_WITHIN(1e-3f + 2e-6f * fabsf(q[i].y), q[i].y, p.y);
            }
        }
        /* random grid points, including the whole data ring, vs. the DLT */
        for (i = 0; i < 20; i++) {
            double u = frand(0, k + 1), v = frand(0, k + 1), x, y, w, tol;
            actag_point p;
            w = m3_apply(Hd, u, v, &x, &y);
            actag_homography_apply(H, (float)u, (float)v, &p);
            /* float error grows with magnification 1/w */
            tol = 2e-3 + 2e-5 * (fabs(x) + fabs(y) + 100.0) / (w < 1 ? w : 1);
            TEST_ASSERT_FLOAT_WITHIN((float)tol, (float)x, p.x);
            TEST_ASSERT_FLOAT_WITHIN((float)tol, (float)y, p.y);
        }
    }
    TEST_ASSERT_GREATER_THAN_INT(1500, nok);
    TEST_ASSERT_GREATER_THAN_INT(5, nrej); /* strong perspective is rejected */
}

static void test_affine_vs_lstsq(void)
{
    int t, nok = 0, npar = 0;
    tu_seed(202);
    for (t = 0; t < 4000; t++) {
        actag_point q[4];
        float H[9], Hp[9];
        double Hd[9], minsin;
        int bits = 16 + 4 * tu_range(0, 4), k = bits / 4, i, rc, par = t % 4 == 0;
        random_quad(q, t < 2000 ? 0.15 : 0.6);
        if (par) { /* a parallelogram: affine == homography */
            q[3].x = q[0].x + (q[2].x - q[1].x);
            q[3].y = q[0].y + (q[2].y - q[1].y);
        }
        if (t % 2) {
            actag_point tmp = q[1];
            q[1] = q[3];
            q[3] = tmp;
        }
        rc = actag_tag_affine(q, bits, H);
        if (!ref_convex(q, &minsin) || minsin < 2e-3) {
            if (!ref_convex(q, &minsin))
                TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, rc);
            continue;
        }
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, rc); /* no perspective limit for affine */
        nok++;
        TEST_ASSERT_EQUAL_FLOAT(0.0f, H[6]);
        TEST_ASSERT_EQUAL_FLOAT(0.0f, H[7]);
        TEST_ASSERT_EQUAL_FLOAT(1.0f, H[8]);
        lstsq_affine_tag(q, k, Hd);
        for (i = 0; i < 20; i++) {
            double u = frand(0, k + 1), v = frand(0, k + 1), x, y;
            double tol = 2e-3 + 2e-6 * (fabs(Hd[0]) + fabs(Hd[1]) + fabs(Hd[3]) + fabs(Hd[4])) * (k + 1) +
                         1e-6 * (fabs(Hd[2]) + fabs(Hd[5]));
            actag_point p;
            m3_apply(Hd, u, v, &x, &y);
            actag_homography_apply(H, (float)u, (float)v, &p);
            TEST_ASSERT_FLOAT_WITHIN((float)tol, (float)x, p.x);
            TEST_ASSERT_FLOAT_WITHIN((float)tol, (float)y, p.y);
        }
        if (par && actag_tag_homography(q, bits, Hp) == ACTAG_OK) {
            npar++;
            for (i = 0; i < 4; i++) { /* corners land exactly, both maps agree */
                actag_point a, b;
                float u = (i == 1 || i == 2) ? (float)(k - 1) : 2.0f, v = i >= 2 ? (float)(k - 1) : 2.0f;
                actag_homography_apply(H, u, v, &a);
                actag_homography_apply(Hp, u, v, &b);
                TEST_ASSERT_FLOAT_WITHIN(2e-3f + 2e-6f * fabsf(q[i].x), q[i].x, a.x);
                TEST_ASSERT_FLOAT_WITHIN(2e-3f + 2e-6f * fabsf(q[i].y), q[i].y, a.y);
                TEST_ASSERT_FLOAT_WITHIN(2e-3f + 2e-6f * fabsf(q[i].x), b.x, a.x);
                TEST_ASSERT_FLOAT_WITHIN(2e-3f + 2e-6f * fabsf(q[i].y), b.y, a.y);
            }
        }
    }
    TEST_ASSERT_GREATER_THAN_INT(2000, nok);
    TEST_ASSERT_GREATER_THAN_INT(400, npar);
}

static void test_homography_degenerate(void)
{
    float H[9];
    actag_point sq[4] = {{10, 10}, {20, 10}, {20, 20}, {10, 20}};
    actag_point q[4];
    int i;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_tag_homography(sq, 24, H));
    /* every allowed size, nothing else */
    for (i = 0; i <= 40; i++) {
        int ok = i >= 16 && i <= 32 && i % 4 == 0;
        TEST_ASSERT_EQUAL_INT(ok ? ACTAG_OK : ACTAG_ERR_PARAM, actag_tag_homography(sq, i, H));
    }
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_tag_homography(NULL, 24, H));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_tag_homography(sq, 24, NULL));
    /* repeated point */
    memcpy(q, sq, sizeof q);
    q[1] = q[0];
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_tag_homography(q, 24, H));
    /* three collinear */
    memcpy(q, sq, sizeof q);
    q[1].x = 15;
    q[1].y = 15;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_tag_homography(q, 24, H));
    /* bow-tie (corners out of order) */
    memcpy(q, sq, sizeof q);
    q[1] = sq[2];
    q[2] = sq[1];
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_tag_homography(q, 24, H));
    /* non-convex (dart) */
    memcpy(q, sq, sizeof q);
    q[2].x = 12;
    q[2].y = 12;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_tag_homography(q, 24, H));
    /* all four equal, and zero-size */
    for (i = 0; i < 4; i++)
        q[i] = sq[0];
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_tag_homography(q, 24, H));
    /* NaN and inf */
    memcpy(q, sq, sizeof q);
    q[3].x = NAN;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_tag_homography(q, 24, H));
    q[3].x = INFINITY;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_tag_homography(q, 24, H));
    /* convex but so much perspective that the data ring crosses infinity:
     * a long thin trapezoid with nearly parallel-converging sides */
    {
        actag_point tr[4] = {{0, 0}, {100, 0}, {55, 10}, {45, 10}};
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_tag_homography(tr, 24, H));
    }
    /* a flat parallelogram: corner turn |sin| 8e-4 is degenerate, 1.2e-3 not */
    {
        actag_point fl[4] = {{0, 0}, {1000, 0}, {2000, 0.8f}, {1000, 0.8f}};
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_tag_homography(fl, 24, H));
        fl[2].y = fl[3].y = 1.2f;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_tag_homography(fl, 24, H));
    }
    /* counter-clockwise order is still a valid homography */
    q[0] = sq[0];
    q[1] = sq[3];
    q[2] = sq[2];
    q[3] = sq[1];
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_tag_homography(q, 24, H));
}

/* ------------------------------------------------------------------ layout */

static void test_bit_positions_spec_24(void)
{
    /* SPEC section 2: (x,y) relative to the white square's top-left cell */
    static const int spec[24][2] = {
        {-2, -2}, {-1, -2}, {0, -2}, {1, -2}, {2, -2}, {3, -2}, {4, -2}, {4, -1},
        {4, 0},   {4, 1},   {4, 2},  {4, 3},  {4, 4},  {3, 4},  {2, 4},  {1, 4},
        {0, 4},   {-1, 4},  {-2, 4}, {-2, 3}, {-2, 2}, {-2, 1}, {-2, 0}, {-2, -1}};
    actag_point pos[24];
    int sizes[3] = {5, 10, 12}, si, i;
    for (si = 0; si < 3; si++) {
        float cs = (float)sizes[si], ox = 100.0f, oy = 57.0f;
        actag_point q[4];
        q[0].x = ox; q[0].y = oy;
        q[1].x = ox + 3 * cs; q[1].y = oy;
        q[2].x = ox + 3 * cs; q[2].y = oy + 3 * cs;
        q[3].x = ox; q[3].y = oy + 3 * cs;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_decode_bit_positions(q, 24, pos));
        for (i = 0; i < 24; i++) {
            TEST_ASSERT_FLOAT_WITHIN(1e-3f, ox + ((float)spec[i][0] + 0.5f) * cs, pos[i].x);
            TEST_ASSERT_FLOAT_WITHIN(1e-3f, oy + ((float)spec[i][1] + 0.5f) * cs, pos[i].y);
        }
    }
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_decode_bit_positions(NULL, 24, pos));
}

/* Every size: ring_index (independent) vs. the library's positions on an
 * axis-aligned square, and a 90-degree turn of the square == rot90 of the
 * sequence (bit i's cell moves to bit i+k's cell). */
static void test_bit_positions_all_sizes(void)
{
    int bits;
    for (bits = 16; bits <= 32; bits += 4) {
        int k = bits / 4, s, cx, cy, hits = 0;
        float cs = 7.0f;
        actag_point q[4], pos[32], q2[4], pos2[32];
        q[0].x = 3 * cs; q[0].y = 3 * cs; /* grid origin at image (cs, cs) */
        q[1].x = (float)k * cs; q[1].y = 3 * cs;
        q[2].x = (float)k * cs; q[2].y = (float)k * cs;
        q[3].x = 3 * cs; q[3].y = (float)k * cs;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_decode_bit_positions(q, bits, pos));
        for (cy = 0; cy <= k; cy++) {
            for (cx = 0; cx <= k; cx++) {
                if (cx && cy && cx != k && cy != k)
                    continue;
                s = ring_index(k, cx, cy);
                TEST_ASSERT_FLOAT_WITHIN(1e-3f, cs + ((float)cx + 0.5f) * cs, pos[s].x);
                TEST_ASSERT_FLOAT_WITHIN(1e-3f, cs + ((float)cy + 0.5f) * cs, pos[s].y);
                hits++;
            }
        }
        TEST_ASSERT_EQUAL_INT(bits, hits);
        /* shifting the quad's start corner by one = reading from the next corner */
        q2[0] = q[1]; q2[1] = q[2]; q2[2] = q[3]; q2[3] = q[0];
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_decode_bit_positions(q2, bits, pos2));
        for (s = 0; s < bits; s++) {
            TEST_ASSERT_FLOAT_WITHIN(1e-3f, pos[(s + k) % bits].x, pos2[s].x);
            TEST_ASSERT_FLOAT_WITHIN(1e-3f, pos[(s + k) % bits].y, pos2[s].y);
        }
    }
}

static void test_mirror_function(void)
{
    int t, bits;
    tu_seed(7);
    for (bits = 16; bits <= 32; bits += 4) {
        uint32_t mask = bits == 32 ? 0xffffffffu : ((1u << bits) - 1u);
        for (t = 0; t < 2000; t++) {
            uint32_t w = tu_rand() & mask;
            uint32_t p = actag_decode_mirror(w, bits);
            TEST_ASSERT_EQUAL_HEX32(ref_mirror(w, bits), p);
            TEST_ASSERT_EQUAL_HEX32(w, actag_decode_mirror(p, bits));
            /* rev is the reflection followed by a one-cell shift: never a
             * reflection that maps corner cells to corner cells */
            TEST_ASSERT_EQUAL_HEX32(ref_rev(w, bits),
                                    ((p << 1) | (p >> (bits - 1))) & mask);
        }
    }
    TEST_ASSERT_EQUAL_HEX32(0x800000u, actag_decode_mirror(0x800000u, 24));
    TEST_ASSERT_EQUAL_HEX32(0x000001u, actag_decode_mirror(0x400000u, 24));
}

/* ------------------------------------------------------------------ sampling */

/* Brute-force read of the word in quad order, in double through the DLT.
 * Samples within 1e-3 px of a rounding boundary may go either way; returns
 * the words with every uncertain sample black (*lo) and white (*hi), and
 * the library must lie cell-wise between them. */
static void brute_read(const uint8_t *img, int rows, int cols, int stride, const double Hd[9],
                       int k, int *vote_lo, int *vote_hi)
{
    int s, a, b, cx, cy;
    for (s = 0; s < 4 * k; s++) {
        vote_lo[s] = vote_hi[s] = 0;
        for (cy = 0; cy <= k; cy++)
            for (cx = 0; cx <= k; cx++)
                if ((cx == 0 || cy == 0 || cx == k || cy == k) && ring_index(k, cx, cy) == s)
                    goto found;
    found:
        for (b = -1; b <= 1; b++) {
            for (a = -1; a <= 1; a++) {
                double x, y;
                int lo = 1, hi = 0, dx, dy;
                m3_apply(Hd, cx + 0.5 + 0.25 * a, cy + 0.5 + 0.25 * b, &x, &y);
                /* every pixel the point may round to (nearest pixel +-1e-3 px) */
                for (dy = -1; dy <= 1; dy++) {
                    for (dx = -1; dx <= 1; dx++) {
                        double ex = x + dx * 1e-3, ey = y + dy * 1e-3;
                        int c = (int)floor(ex + 0.5), r = (int)floor(ey + 0.5), v = 0;
                        if (ex >= -0.5 && ey >= -0.5 && c < cols && r < rows && c >= 0 && r >= 0)
                            v = img[(size_t)r * (size_t)stride + (size_t)c] != 0;
                        if (v < lo) lo = v;
                        if (v > hi) hi = v;
                    }
                }
                vote_lo[s] += lo;
                vote_hi[s] += hi;
            }
        }
    }
}

static void test_read_word_vs_brute_force(void)
{
    static uint8_t img[80 * 100];
    int t, checked = 0, uncertain = 0;
    tu_seed(2024);
    for (t = 0; t < 1500; t++) {
        int rows = tu_range(1, 70), cols = tu_range(1, 70), stride = cols + tu_range(0, 9);
        int bits = 16 + 4 * tu_range(0, 4), k = bits / 4, i, s, rc;
        int vlo[32], vhi[32];
        double minsin, Hd[9];
        uint32_t w = 0;
        actag_point q[4];
        int density = tu_range(0, 100);
        int model = t % 2 ? ACTAG_DECODE_PROJECTIVE : ACTAG_DECODE_AFFINE;
        /* edge cases: 1x1, 1xN, Nx1 */
        if (t % 10 == 0) rows = 1;
        if (t % 10 == 1) cols = 1, stride = 1 + tu_range(0, 3);
        for (i = 0; i < rows * stride; i++)
            img[i] = (uint8_t)(tu_range(0, 99) < density ? tu_range(1, 255) : 0);
        /* quads around/over the image, often larger than it */
        {
            double cx = frand(-10, cols + 10), cy = frand(-10, rows + 10), s0 = frand(1, 40);
            double base[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
            for (i = 0; i < 4; i++) {
                q[i].x = (float)(cx + base[i][0] * s0 + frand(-0.3, 0.3) * s0);
                q[i].y = (float)(cy + base[i][1] * s0 + frand(-0.3, 0.3) * s0);
            }
        }
        rc = actag_decode_read_word(img, rows, cols, stride, q, bits, model, &w);
        if (!ref_convex(q, &minsin) || minsin < 2e-3 || rc != ACTAG_OK) {
            if (rc != ACTAG_OK)
                TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, rc);
            continue;
        }
        if (model == ACTAG_DECODE_PROJECTIVE)
            TEST_ASSERT_TRUE(dlt_tag(q, k, Hd));
        else
            lstsq_affine_tag(q, k, Hd);
        brute_read(img, rows, cols, stride, Hd, k, vlo, vhi);
        for (s = 0; s < bits; s++) {
            int b = seq_get(w, bits, s);
            int blo = vlo[s] >= 5, bhi = vhi[s] >= 5;
            TEST_ASSERT_TRUE(b >= blo && b <= bhi);
            if (blo != bhi)
                uncertain++;
        }
        checked++;
    }
    TEST_ASSERT_GREATER_THAN_INT(1100, checked);
    TEST_ASSERT_LESS_THAN_INT(checked, uncertain); /* the tolerance rarely matters */
}

/* ------------------------------------------------------------------ renders */

typedef struct render_case {
    int rows, cols, stride, k;
    double T[9];
    actag_point printed[4]; /* image position of printed corner n */
    actag_point quad[4];    /* what the decoder gets */
    actag_point quad_cw[4]; /* same, clockwise on screen from quad[0] */
} render_case;

/* Sets up a random render of a (k+1)^2 tag: cell size 5..12 px, dihedral
 * transform (rot, mirror), optional warp; quad starts at a random corner,
 * clockwise on screen (sometimes counter-clockwise when ccw_ok). */
static void setup_case(render_case *rc, int k, int rot, int mirror, int warp, int ccw_ok)
{
    double W[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    double cs = frand(5, 12), ext = (k + 1) * cs, x, y;
    int n, start, ccw;
    if (warp) {
        W[0] = 1 + frand(-0.15, 0.15);
        W[1] = frand(-0.25, 0.25);
        W[3] = frand(-0.25, 0.25);
        W[4] = 1 + frand(-0.15, 0.15);
        if (warp > 1) { /* perspective: up to ~20 % scale change across the tag */
            W[6] = frand(-0.2, 0.2) / ext;
            W[7] = frand(-0.2, 0.2) / ext;
        }
    }
    rc->k = k;
    rc->cols = (int)(1.9 * ext) + tu_range(4, 20);
    rc->rows = (int)(1.9 * ext) + tu_range(4, 20);
    rc->stride = rc->cols + (tu_range(0, 2) == 0 ? tu_range(1, 13) : 0);
    {
        /* one draw per declarator, so in a fixed order (the order the x86-64
         * build used when they were call arguments: the last one first) */
        double oy = rc->rows / 2.0 + frand(-3, 3), ox = rc->cols / 2.0 + frand(-3, 3);
        make_transform(k, cs, rot, mirror, ox, oy, W, rc->T);
    }
    for (n = 0; n < 4; n++) {
        double gu = (n == 1 || n == 2) ? k - 1 : 2, gv = n >= 2 ? k - 1 : 2;
        m3_apply(rc->T, gu, gv, &x, &y);
        rc->printed[n].x = (float)x;
        rc->printed[n].y = (float)y;
    }
    /* printed corners are clockwise on screen unless mirrored */
    start = tu_range(0, 3);
    for (n = 0; n < 4; n++) {
        int idx = mirror ? (4 - n) & 3 : n;
        rc->quad_cw[n] = rc->printed[(idx + (mirror ? -start : start) + 8) & 3];
    }
    ccw = ccw_ok && tu_range(0, 2) == 0;
    for (n = 0; n < 4; n++)
        rc->quad[n] = ccw ? rc->quad_cw[(4 - n) & 3] : rc->quad_cw[n];
}

/* Decodes a render: perspective renders need the projective map; otherwise
 * the default (affine) entry point and both explicit models take turns. */
static int g_turn;
static int decode_render_with(const uint8_t *img, const render_case *rc,
                              const actag_family *fam, int maxc, int warp,
                              actag_decode_result *res);

/* decode_render_with, the result first filled with junk: every field the
 * binary decoders define is written (bit_margin and fit_corners were left
 * as they were, and the detector read fit_corners). */
static int decode_render(const uint8_t *img, const render_case *rc, const actag_family *fam,
                         int maxc, int warp, actag_decode_result *res)
{
    int rv;
    memset(res, 0x7f, sizeof *res);
    rv = decode_render_with(img, rc, fam, maxc, warp, res);
    if (rv == ACTAG_OK) {
        TEST_ASSERT_EQUAL_INT(0, res->bit_margin);
        TEST_ASSERT_EQUAL_MEMORY(res->corners, res->fit_corners, sizeof res->corners);
        TEST_ASSERT_TRUE(res->contrast == 0.0f && res->flip_weight == 0.0f &&
                         res->min_confidence == 0.0f);
    }
    return rv;
}

static int decode_render_with(const uint8_t *img, const render_case *rc,
                              const actag_family *fam, int maxc, int warp,
                              actag_decode_result *res)
{
    int turn = g_turn++ % 3;
    if (warp == 2 || turn == 1)
        return actag_decode_quad_ex(img, rc->rows, rc->cols, rc->stride, rc->quad, fam, maxc,
                                    ACTAG_DECODE_PROJECTIVE, res);
    if (turn == 2)
        return actag_decode_quad_ex(img, rc->rows, rc->cols, rc->stride, rc->quad, fam, maxc,
                                    ACTAG_DECODE_AFFINE, res);
    {
        /* the default map also through the bitmap entry point: same code,
         * same result, field by field */
        actag_decode_result rb;
        uint32_t *bm = (uint32_t *)malloc(ACTAG_BITMAP_SIZE(rc->rows, rc->cols));
        int rv = actag_decode_quad(img, rc->rows, rc->cols, rc->stride, rc->quad, fam, maxc, res);
        int rvb;
        TEST_ASSERT_NOT_NULL(bm);
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_bitmap_pack(img, rc->rows, rc->cols, rc->stride, bm));
        memset(&rb, 0, sizeof rb);
        rvb = actag_decode_quad_bitmap(bm, rc->rows, rc->cols, rc->quad, fam, maxc, &rb);
        TEST_ASSERT_EQUAL_INT(rv, rvb);
        if (rv == ACTAG_OK) {
            TEST_ASSERT_EQUAL_INT(res->id, rb.id);
            TEST_ASSERT_EQUAL_INT(res->hamming, rb.hamming);
            TEST_ASSERT_EQUAL_INT(res->mirrored, rb.mirrored);
            TEST_ASSERT_EQUAL_UINT32(res->observed, rb.observed);
            TEST_ASSERT_EQUAL_MEMORY(res->corners, rb.corners, sizeof rb.corners);
            TEST_ASSERT_TRUE(res->ring_black == rb.ring_black &&
                             res->interior_white == rb.interior_white &&
                             res->decision_margin == rb.decision_margin);
        }
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_decode_quad_bitmap(NULL, rc->rows, rc->cols,
                                                                       rc->quad, fam, maxc, &rb));
        free(bm);
        return rv;
    }
}

static void check_clean_decode(const render_case *rc, const actag_decode_result *res, int id,
                               int mirror)
{
    int n;
    TEST_ASSERT_EQUAL_INT(id, res->id);
    TEST_ASSERT_EQUAL_INT(0, res->hamming);
    TEST_ASSERT_EQUAL_INT(mirror, res->mirrored);
    for (n = 0; n < 4; n++) {
        TEST_ASSERT_FLOAT_WITHIN(0.01f, rc->printed[n].x, res->corners[n].x);
        TEST_ASSERT_FLOAT_WITHIN(0.01f, rc->printed[n].y, res->corners[n].y);
    }
    /* rotation names the printed corner at quad[0] */
    TEST_ASSERT_FLOAT_WITHIN(0.01f, rc->quad[0].x, res->corners[res->rotation].x);
    TEST_ASSERT_FLOAT_WITHIN(0.01f, rc->quad[0].y, res->corners[res->rotation].y);
    TEST_ASSERT_EQUAL_FLOAT(1.0f, res->ring_black);
    TEST_ASSERT_EQUAL_FLOAT(1.0f, res->interior_white);
}

static void run_family_renders(test_family *tf, int reps)
{
    static uint8_t img[260 * 280];
    int k = tf->fam.bits / 4, id, d, rep, maxc = actag_family_max_corrections(&tf->fam);
    for (id = 0; id < tf->fam.ncodes; id++) {
        for (d = 0; d < 8; d++) {
            for (rep = 0; rep < reps; rep++) {
                render_case rc;
                actag_decode_result res;
                int warp = rep % 3; /* none, affine, perspective */
                uint8_t white = (uint8_t)tu_range(1, 255);
                setup_case(&rc, k, d & 3, d >> 2, warp, 1);
                TEST_ASSERT_TRUE(rc.rows * rc.stride <= (int)sizeof img);
                render(img, rc.rows, rc.cols, rc.stride, rc.T, k, tf->codes[id], white);
                memset(&res, 0, sizeof res);
                TEST_ASSERT_EQUAL_INT(ACTAG_OK, decode_render(img, &rc, &tf->fam, 0, warp, &res));
                check_clean_decode(&rc, &res, id, d >> 2);
                TEST_ASSERT_EQUAL_HEX32(expected_observed(rc.T, rc.quad_cw, k, tf->codes[id]),
                                        res.observed);
                /* the same with all corrections allowed */
                TEST_ASSERT_EQUAL_INT(ACTAG_OK, decode_render(img, &rc, &tf->fam, maxc, warp, &res));
                check_clean_decode(&rc, &res, id, d >> 2);
            }
        }
    }
}

static void test_render_h10_all_orientations(void)
{
    test_family tf;
    tu_seed(31337);
    load_h10(&tf);
    run_family_renders(&tf, 6);
}

static void test_render_other_sizes(void)
{
    static test_family tf;
    int bits;
    tu_seed(99);
    for (bits = 16; bits <= 32; bits += 4) {
        make_family(&tf, bits, 5, 4, "handmade");
        run_family_renders(&tf, 3);
    }
}

/* The SPEC's rev(rot^j(c)) model does not describe a physically mirrored
 * tag read from a corner: on real mirrored renders of AcTag24h10 the
 * 8-orientation reversal matcher never finds the right code at distance 0,
 * while the reflection model always does. */
static void test_mirror_model_rev_vs_reflection(void)
{
    static uint8_t img[260 * 280];
    test_family tf;
    int id, d, rev_hits = 0, refl_hits = 0, total = 0;
    tu_seed(555);
    load_h10(&tf);
    for (id = 0; id < 7; id++) {
        for (d = 0; d < 4; d++) {
            render_case rc;
            actag_decode_result res;
            actag_match m;
            setup_case(&rc, 6, d, 1, 1, 0);
            render(img, rc.rows, rc.cols, rc.stride, rc.T, 6, tf.codes[id], 255);
            TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_decode_quad(img, rc.rows, rc.cols, rc.stride,
                                                              rc.quad, &tf.fam, 4, &res));
            if (actag_family_match(&tf.fam, res.observed, 0, &m) == ACTAG_OK && m.id == id)
                rev_hits++;
            if (res.id == id && res.mirrored == 1 && res.hamming == 0)
                refl_hits++;
            total++;
        }
    }
    TEST_ASSERT_EQUAL_INT(0, rev_hits);
    TEST_ASSERT_EQUAL_INT(total, refl_hits);
}

/* Bit flips: the decoder must agree with the brute-force 8-orientation
 * matcher; within half the physical minimum distance it must find the true
 * tag, corners included. */
static void run_flips(test_family *tf, int cases)
{
    static uint8_t img[260 * 280];
    int k = tf->fam.bits / 4, bits = tf->fam.bits, t;
    int maxc = actag_family_max_corrections(&tf->fam);
    int dphys = physical_min_distance(tf->codes, tf->fam.ncodes, bits);
    int safe = (dphys - 1) / 2, nomatch_beyond = 0, beyond = 0;
    for (t = 0; t < cases; t++) {
        render_case rc;
        actag_decode_result res;
        oracle_res o;
        int id = tu_range(0, tf->fam.ncodes - 1), d = tu_range(0, 7);
        int nflip = tu_range(0, maxc + 2), mc = tu_range(0, maxc), i, r;
        uint32_t flips = 0, w_exp;
        while (tu_popcount(flips) < nflip)
            flips |= 1u << tu_range(0, bits - 1);
        setup_case(&rc, k, d & 3, d >> 2, t % 3, 1);
        render(img, rc.rows, rc.cols, rc.stride, rc.T, k, tf->codes[id] ^ flips, 255);
        w_exp = expected_observed(rc.T, rc.quad_cw, k, tf->codes[id] ^ flips);
        o = oracle(tf->codes, tf->fam.ncodes, bits, w_exp, mc);
        memset(&res, 0, sizeof res);
        r = decode_render(img, &rc, &tf->fam, mc, t % 3, &res);
        if (!o.ok) {
            TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, r);
        } else {
            int margin;
            TEST_ASSERT_EQUAL_INT(ACTAG_OK, r);
            TEST_ASSERT_EQUAL_HEX32(w_exp, res.observed);
            TEST_ASSERT_EQUAL_INT(o.id, res.id);
            TEST_ASSERT_EQUAL_INT(o.hamming, res.hamming);
            TEST_ASSERT_EQUAL_INT(o.mirrored, res.mirrored);
            TEST_ASSERT_EQUAL_INT(o.rotation, res.rotation);
            margin = (o.mirrored ? o.du : o.dm);
            if (margin > maxc)
                margin = maxc + 1;
            TEST_ASSERT_EQUAL_INT(margin - o.hamming, res.mirror_margin);
        }
        if (nflip <= mc && nflip <= safe) { /* guaranteed: the true tag */
            TEST_ASSERT_EQUAL_INT(ACTAG_OK, r);
            TEST_ASSERT_EQUAL_INT(id, res.id);
            TEST_ASSERT_EQUAL_INT(nflip, res.hamming);
            TEST_ASSERT_EQUAL_INT(d >> 2, res.mirrored);
            for (i = 0; i < 4; i++) {
                TEST_ASSERT_FLOAT_WITHIN(0.01f, rc.printed[i].x, res.corners[i].x);
                TEST_ASSERT_FLOAT_WITHIN(0.01f, rc.printed[i].y, res.corners[i].y);
            }
        }
        if (nflip <= mc && !(d >> 2)) { /* unmirrored: the ID is always right */
            TEST_ASSERT_EQUAL_INT(ACTAG_OK, r);
            TEST_ASSERT_EQUAL_INT(id, res.id);
        }
        if (nflip > mc) { /* the true reading is never accepted */
            beyond++;
            if (r == ACTAG_OK)
                TEST_ASSERT_TRUE(res.hamming <= mc);
            else
                nomatch_beyond++;
        }
    }
    TEST_ASSERT_GREATER_THAN_INT(0, beyond);
    TEST_ASSERT_GREATER_THAN_INT(beyond / 2, nomatch_beyond);
}

static void test_bit_flips_h10(void)
{
    test_family tf;
    tu_seed(4242);
    load_h10(&tf);
    TEST_ASSERT_EQUAL_INT(4, actag_family_max_corrections(&tf.fam));
    /* the published h10 codes keep >= 6 bits between any two physical
     * orientations: 2 corrections are always unambiguous */
    TEST_ASSERT_EQUAL_INT(6, physical_min_distance(tf.codes, 7, 24));
    run_flips(&tf, TU_TRIALS(1200, 4));
}

static void test_bit_flips_h8_h6(void)
{
    static test_family tf;
    static uint32_t pub[500];
    char path[512];
    int f;
    const char *names[2] = {"AcTag24h8", "AcTag24h6"};
    const int hs[2] = {8, 6};
    tu_seed(777);
    for (f = 0; f < 2; f++) {
        int n;
        snprintf(path, sizeof path, "%s/families/%s.txt", TU_DATA, names[f]);
        n = tu_read_codes(path, pub, 500);
        TEST_ASSERT_GREATER_THAN_INT(40, n);
        if (n > 64)
            n = 64; /* a prefix of the family is a family too */
        if (n < 1)
            n = 1; /* unreachable after the assertion; keeps the bound visible */
        memcpy(tf.codes, pub, (size_t)n * sizeof(uint32_t));
        tf.fam.name = names[f];
        tf.fam.bits = 24;
        tf.fam.hamming = hs[f];
        tf.fam.ncodes = n;
        tf.fam.codes = tf.codes;
        if (f == 0) /* the whole h8 family: reflections come within 2 bits */
            TEST_ASSERT_EQUAL_INT(2, physical_min_distance(tf.codes, n, 24));
        run_flips(&tf, TU_TRIALS(300, 3));
    }
}

static void test_bit_flips_handmade_32(void)
{
    static test_family tf;
    tu_seed(3232);
    make_family(&tf, 32, 9, 5, "handmade32");
    run_flips(&tf, TU_TRIALS(300, 3));
}

/* ------------------------------------------------------------------ errors */

static void test_errors_and_edges(void)
{
    static uint8_t img[100 * 100];
    test_family tf;
    actag_decode_result res;
    actag_family bad;
    actag_point q[4] = {{40, 40}, {55, 40}, {55, 55}, {40, 55}};
    actag_point pos[24];
    float H[9];
    uint32_t w;
    int i;
    load_h10(&tf);
    memset(img, 0, sizeof img);
    /* NULLs */
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_decode_quad(NULL, 100, 100, 100, q, &tf.fam, 0, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_decode_quad(img, 100, 100, 100, NULL, &tf.fam, 0, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_decode_quad(img, 100, 100, 100, q, NULL, 0, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_decode_quad(img, 100, 100, 100, q, &tf.fam, 0, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_decode_read_word(NULL, 100, 100, 100, q, 24, ACTAG_DECODE_AFFINE, &w));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_decode_read_word(img, 100, 100, 100, NULL, 24, ACTAG_DECODE_AFFINE, &w));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_decode_read_word(img, 100, 100, 100, q, 24, ACTAG_DECODE_AFFINE, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_decode_bit_positions(q, 24, NULL));
    /* sizes */
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_decode_quad(img, 0, 100, 100, q, &tf.fam, 0, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_decode_quad(img, 100, 0, 100, q, &tf.fam, 0, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_decode_quad(img, -3, 100, 100, q, &tf.fam, 0, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_decode_quad(img, 100, 100, 99, q, &tf.fam, 0, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE,
                          actag_decode_quad(img, ACTAG_MAX_DIM + 1, 1, 1, q, &tf.fam, 0, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_decode_read_word(img, 10, 10, 9, q, 24, ACTAG_DECODE_AFFINE, &w));
    /* family and corrections */
    bad = tf.fam;
    bad.bits = 12;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_FAMILY, actag_decode_quad(img, 100, 100, 100, q, &bad, 0, &res));
    bad = tf.fam;
    bad.codes = NULL;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_FAMILY, actag_decode_quad(img, 100, 100, 100, q, &bad, 0, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_CORRECTIONS,
                          actag_decode_quad(img, 100, 100, 100, q, &tf.fam, -1, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_CORRECTIONS,
                          actag_decode_quad(img, 100, 100, 100, q, &tf.fam, 5, &res));
    /* degenerate quads */
    {
        actag_point dq[4];
        memcpy(dq, q, sizeof dq);
        dq[2] = dq[1];
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_decode_quad(img, 100, 100, 100, dq, &tf.fam, 0, &res));
        memcpy(dq, q, sizeof dq);
        dq[1] = q[2];
        dq[2] = q[1];
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_decode_quad(img, 100, 100, 100, dq, &tf.fam, 0, &res));
        dq[0].y = NAN;
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_decode_read_word(img, 100, 100, 100, dq, 24, ACTAG_DECODE_AFFINE, &w));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_decode_read_word(img, 100, 100, 100, q, 25, ACTAG_DECODE_AFFINE, &w));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_decode_bit_positions(q, 12, pos));
        /* unknown map model */
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_decode_read_word(img, 100, 100, 100, q, 24, 2, &w));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_decode_read_word(img, 100, 100, 100, q, 24, -1, &w));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM,
                              actag_decode_quad_ex(img, 100, 100, 100, q, &tf.fam, 0, 7, &res));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_tag_affine(NULL, 24, H));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_tag_affine(q, 24, NULL));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_tag_affine(q, 36, H));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_tag_affine(dq, 24, H));
    }
    /* constant images: all black reads 0, all white reads all ones; neither
     * is within 4 bits of an h10 code in any orientation */
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, actag_decode_quad(img, 100, 100, 100, q, &tf.fam, 4, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_decode_read_word(img, 100, 100, 100, q, 24, ACTAG_DECODE_AFFINE, &w));
    TEST_ASSERT_EQUAL_HEX32(0u, w);
    memset(img, 200, sizeof img);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, actag_decode_quad(img, 100, 100, 100, q, &tf.fam, 4, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_decode_read_word(img, 100, 100, 100, q, 24, ACTAG_DECODE_AFFINE, &w));
    TEST_ASSERT_EQUAL_HEX32(0xffffffu, w);
    /* 1x1, 1xN, Nx1 white images with a tag-sized quad: the data ring lies
     * outside (black) -> the zero word -> no match; quad far bigger than
     * the image likewise */
    {
        actag_point tiny[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
        actag_point huge[4] = {{-500, -500}, {500, -500}, {500, 500}, {-500, 500}};
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_decode_read_word(img, 1, 1, 1, tiny, 24, ACTAG_DECODE_PROJECTIVE, &w));
        TEST_ASSERT_EQUAL_HEX32(0u, w);
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, actag_decode_quad(img, 1, 1, 1, tiny, &tf.fam, 4, &res));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, actag_decode_quad(img, 1, 100, 100, tiny, &tf.fam, 4, &res));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, actag_decode_quad(img, 100, 1, 1, tiny, &tf.fam, 4, &res));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, actag_decode_quad(img, 100, 100, 100, huge, &tf.fam, 4, &res));
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_decode_read_word(img, 100, 100, 100, huge, 24, ACTAG_DECODE_AFFINE, &w));
        TEST_ASSERT_EQUAL_HEX32(0u, w);
    }
    /* a tag whose data ring is partly outside the image still decodes when
     * the missing cells are black in the code (corrections allowed) or are
     * within the correction budget; here: cut the render, compare to the
     * brute-force matcher */
    {
        /* views from the whole frame down to its top-left quarter: some cut
         * the data ring and still decode, smaller ones do not; each as the
         * oracle says. (The four views this test had were all too small to
         * decode, so the decoding branch never ran.) */
        static uint8_t big[200 * 200];
        render_case rc;
        oracle_res o;
        uint32_t w_full;
        int r, cut_read = 0, refused = 0;
        tu_seed(11);
        setup_case(&rc, 6, 0, 0, 0, 0);
        render(big, rc.rows, rc.cols, rc.stride, rc.T, 6, tf.codes[3], 255);
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_decode_read_word(big, rc.rows, rc.cols, rc.stride, rc.quad,
                                                               24, ACTAG_DECODE_AFFINE, &w_full));
        for (i = 0; i <= 40; i++) { /* view only the top-left part of the frame */
            int rows = rc.rows - i * (rc.rows / 80), cols = rc.cols - i * (rc.cols / 80);
            r = actag_decode_read_word(big, rows, cols, rc.stride, rc.quad, 24, ACTAG_DECODE_AFFINE, &w);
            TEST_ASSERT_EQUAL_INT(ACTAG_OK, r);
            o = oracle(tf.codes, 7, 24, w, 4);
            r = actag_decode_quad(big, rows, cols, rc.stride, rc.quad, &tf.fam, 4, &res);
            TEST_ASSERT_EQUAL_INT(o.ok ? ACTAG_OK : ACTAG_ERR_NO_MATCH, r);
            if (o.ok)
                TEST_ASSERT_EQUAL_INT(o.id, res.id);
            cut_read += o.ok && w != w_full; /* cells lost to the cut, still read */
            refused += !o.ok;
        }
        TEST_ASSERT_TRUE(cut_read >= 1);
        TEST_ASSERT_TRUE(refused >= 1);
    }
    TEST_ASSERT_EQUAL_INT(0, ACTAG_DECODE_SCRATCH_BYTES(530, 512));
}

/* Tags as small as 2 px per cell and as large as 40 px per cell, clean. */
static void test_scale_extremes(void)
{
    static uint8_t img[400 * 400];
    test_family tf;
    int id, ok = 0;
    tu_seed(8);
    load_h10(&tf);
    for (id = 0; id < 7; id++) {
        double cs[2] = {3.0, 40.0};
        int j;
        for (j = 0; j < 2; j++) {
            double W[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, T[9], x, y;
            actag_point quad[4];
            actag_decode_result res;
            int n, size = (int)(7 * cs[j] + 20);
            make_transform(6, cs[j], id & 3, 0, size / 2.0, size / 2.0, W, T);
            render(img, size, size, size, T, 6, tf.codes[id], 255);
            for (n = 0; n < 4; n++) {
                m3_apply(T, (n == 1 || n == 2) ? 5 : 2, n >= 2 ? 5 : 2, &x, &y);
                quad[n].x = (float)x;
                quad[n].y = (float)y;
            }
            if (actag_decode_quad(img, size, size, size, quad, &tf.fam, 0, &res) == ACTAG_OK &&
                res.id == id && res.rotation == 0 && res.mirrored == 0 &&
                res.corners[2].x == quad[2].x && res.corners[2].y == quad[2].y)
                ok++;
        }
    }
    TEST_ASSERT_EQUAL_INT(14, ok);
}

/* ------------------------------------------------------------------ real frame */

/* The SPEC's example sonar frame: brute-force median (radius 4) + adaptive
 * threshold (radius 8, offset 1), both edge padded, over the tag's region
 * (black elsewhere). The reference reports tag 0 with corners (x, y) TL
 * (314,145) TR (339,113) BR (280,103) BL (244,133): counter-clockwise on
 * screen, i.e. the tag appears MIRRORED in this frame. Given exactly those
 * corners, in any start corner and either winding, the decoder (default,
 * affine map) must report tag 0, mirrored, with 4 corrected bits (the
 * family's maximum), and the corners in exactly the reference's order. The
 * 4-point homography cannot read it (the reason affine is the default). */
static int clampi(int v, int lo, int hi) { return v < lo ? lo : (v > hi ? hi : v); }

static void test_real_example_frame(void)
{
    static const float ours[4][2] = {{314, 145}, {339, 113}, {280, 103}, {244, 133}};
    enum { R0 = 50, R1 = 200, C0 = 180, C1 = 420, M = 8 };
    static uint8_t med[(R1 - R0 + 2 * M) * (C1 - C0 + 2 * M)];
    static uint8_t *bin;
    char path[512];
    int rows = 0, cols = 0, r, c, st, ccw, mw = C1 - C0 + 2 * M;
    uint8_t *img;
    test_family tf;
    snprintf(path, sizeof path, "%s/exampleSonarImage.pgm", TU_DATA);
    img = tu_read_pgm(path, &rows, &cols);
    TEST_ASSERT_NOT_NULL(img);
    TEST_ASSERT_EQUAL_INT(463, rows);
    TEST_ASSERT_EQUAL_INT(620, cols);
    load_h10(&tf);
    for (r = R0 - M; r < R1 + M; r++) {
        for (c = C0 - M; c < C1 + M; c++) {
            int hist[256], dy, dx, acc = 0, v = 0;
            memset(hist, 0, sizeof hist);
            for (dy = -4; dy <= 4; dy++)
                for (dx = -4; dx <= 4; dx++)
                    hist[img[clampi(r + dy, 0, rows - 1) * cols + clampi(c + dx, 0, cols - 1)]]++;
            while (acc + hist[v] < 41) /* 41st of 81 */
                acc += hist[v++];
            med[(r - R0 + M) * mw + (c - C0 + M)] = (uint8_t)v;
        }
    }
    bin = (uint8_t *)calloc((size_t)rows * (size_t)cols, 1);
    TEST_ASSERT_NOT_NULL(bin);
    for (r = R0; r < R1; r++) {
        for (c = C0; c < C1; c++) {
            int mn = 255, mx = 0, dy, dx;
            for (dy = -M; dy <= M; dy++) {
                for (dx = -M; dx <= M; dx++) {
                    /* edge padding of the median image = clamped coordinates */
                    int rr = clampi(r + dy, 0, rows - 1), cc = clampi(c + dx, 0, cols - 1);
                    int v = med[(rr - R0 + M) * mw + (cc - C0 + M)];
                    if (v < mn) mn = v;
                    if (v > mx) mx = v;
                }
            }
            bin[r * cols + c] = (float)med[(r - R0 + M) * mw + (c - C0 + M)] >= (float)(mn + mx) / 2.0f - 1.0f;
        }
    }
    for (st = 0; st < 4; st++) {
        for (ccw = 0; ccw < 2; ccw++) {
            actag_point q[4];
            actag_decode_result res;
            actag_match m;
            int n;
            for (n = 0; n < 4; n++) { /* the reference's order is counter-clockwise */
                int idx = ccw ? (st + n) & 3 : (st - n + 4) & 3;
                q[n].x = ours[idx][0];
                q[n].y = ours[idx][1];
            }
            TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH,
                                  actag_decode_quad_ex(bin, rows, cols, cols, q, &tf.fam, 4,
                                                       ACTAG_DECODE_PROJECTIVE, &res));
            TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH,
                                  actag_decode_quad(bin, rows, cols, cols, q, &tf.fam, 3, &res));
            TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_decode_quad(bin, rows, cols, cols, q, &tf.fam, 4, &res));
            TEST_ASSERT_EQUAL_INT(0, res.id);
            TEST_ASSERT_EQUAL_INT(4, res.hamming);
            TEST_ASSERT_EQUAL_INT(1, res.mirrored);
            TEST_ASSERT_EQUAL_INT(1, res.mirror_margin); /* unmirrored reading: 5 bits off */
            for (n = 0; n < 4; n++) {
                TEST_ASSERT_EQUAL_FLOAT(ours[n][0], res.corners[n].x);
                TEST_ASSERT_EQUAL_FLOAT(ours[n][1], res.corners[n].y);
            }
            TEST_ASSERT_TRUE(res.ring_black > 0.8f);
            TEST_ASSERT_TRUE(res.interior_white > 0.6f);
            /* the SPEC's reversal model reads something else here */
            TEST_ASSERT_TRUE(actag_family_match(&tf.fam, res.observed, 4, &m) != ACTAG_OK ||
                             m.mirrored == 0 || m.hamming > 4);
        }
    }
    free(bin);
    free(img);
}

/* AcTag24h4 holds codes that are each other's mirror images (402 / 2046) and
 * mirror-symmetric codes (291): a mirrored 402 is indistinguishable from an
 * unmirrored 2046, and the tie rule reports the unmirrored reading. */
static void test_h4_mirror_ambiguity(void)
{
    static uint32_t codes[6300];
    static uint8_t img[260 * 280];
    char path[512];
    actag_family fam;
    render_case rc;
    actag_decode_result res;
    int n;
    snprintf(path, sizeof path, "%s/families/AcTag24h4.txt", TU_DATA);
    n = tu_read_codes(path, codes, 6300);
    TEST_ASSERT_EQUAL_INT(6261, n);
    fam.name = "AcTag24h4";
    fam.bits = 24;
    fam.hamming = 4;
    fam.ncodes = n;
    fam.codes = codes;
    tu_seed(4);
    setup_case(&rc, 6, 1, 1, 1, 1);
    render(img, rc.rows, rc.cols, rc.stride, rc.T, 6, codes[402], 255);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_decode_quad(img, rc.rows, rc.cols, rc.stride, rc.quad, &fam, 0, &res));
    TEST_ASSERT_EQUAL_INT(2046, res.id);
    TEST_ASSERT_EQUAL_INT(0, res.mirrored);
    TEST_ASSERT_EQUAL_INT(0, res.mirror_margin);
    /* unmirrored 402 is read correctly (the tie rule favours it) */
    setup_case(&rc, 6, 3, 0, 2, 1);
    render(img, rc.rows, rc.cols, rc.stride, rc.T, 6, codes[402], 255);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_decode_quad_ex(img, rc.rows, rc.cols, rc.stride, rc.quad,
                                                         &fam, 0, ACTAG_DECODE_PROJECTIVE, &res));
    TEST_ASSERT_EQUAL_INT(402, res.id);
    TEST_ASSERT_EQUAL_INT(0, res.mirrored);
    TEST_ASSERT_EQUAL_INT(0, res.mirror_margin);
    /* symmetric 291 mirrored: right ID, handedness reported unmirrored */
    setup_case(&rc, 6, 2, 1, 0, 1);
    render(img, rc.rows, rc.cols, rc.stride, rc.T, 6, codes[291], 255);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_decode_quad(img, rc.rows, rc.cols, rc.stride, rc.quad, &fam, 0, &res));
    TEST_ASSERT_EQUAL_INT(291, res.id);
    TEST_ASSERT_EQUAL_INT(0, res.mirrored);
    TEST_ASSERT_EQUAL_INT(0, res.mirror_margin);
    /* a regular code mirrored is fine */
    setup_case(&rc, 6, 2, 1, 1, 1);
    render(img, rc.rows, rc.cols, rc.stride, rc.T, 6, codes[5000], 255);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_decode_quad(img, rc.rows, rc.cols, rc.stride, rc.quad, &fam, 0, &res));
    TEST_ASSERT_EQUAL_INT(5000, res.id);
    TEST_ASSERT_EQUAL_INT(1, res.mirrored);
    for (n = 0; n < 4; n++) {
        TEST_ASSERT_FLOAT_WITHIN(0.01f, rc.printed[n].x, res.corners[n].x);
        TEST_ASSERT_FLOAT_WITHIN(0.01f, rc.printed[n].y, res.corners[n].y);
    }
}

/* ------------------------------------------------------------------ grid-fitting decoder */

/* Clean renders (no perspective) through actag_decode_quad_fit: every ID of
 * AcTag24h10 and a hand-made 16- and 32-bit family, all 8 orientations,
 * with the exact quad and with a quad off by up to a third of a cell and
 * 15 % in scale (the grid fit must recover). */
static void run_fit_renders(test_family *tf, int reps)
{
    static uint8_t img[260 * 280];
    int k = tf->fam.bits / 4, id, d, rep, n;
    int maxc = actag_family_max_corrections(&tf->fam);
    actag_fit_params fp;
    actag_fit_params_default(&fp);
    for (id = 0; id < tf->fam.ncodes; id++) {
        for (d = 0; d < 8; d++) {
            for (rep = 0; rep < reps; rep++) {
                render_case rc;
                actag_decode_result res;
                actag_point q[4], c0;
                double cs;
                uint8_t white = (uint8_t)tu_range(60, 255);
                int perturb = rep & 1;
                setup_case(&rc, k, d & 3, d >> 2, rep % 3 == 2 ? 1 : 0, 1);
                TEST_ASSERT_TRUE(rc.rows * rc.stride <= (int)sizeof img);
                render(img, rc.rows, rc.cols, rc.stride, rc.T, k, tf->codes[id], white);
                cs = sqrt((rc.quad[1].x - rc.quad[0].x) * (rc.quad[1].x - rc.quad[0].x) +
                          (rc.quad[1].y - rc.quad[0].y) * (rc.quad[1].y - rc.quad[0].y)) /
                     (k - 3);
                c0.x = 0.25f * (rc.quad[0].x + rc.quad[1].x + rc.quad[2].x + rc.quad[3].x);
                c0.y = 0.25f * (rc.quad[0].y + rc.quad[1].y + rc.quad[2].y + rc.quad[3].y);
                {
                    float sc = perturb ? (float)frand(0.87, 1.15) : 1.0f;
                    float dx = perturb ? (float)(frand(-0.33, 0.33) * cs) : 0.0f;
                    float dy = perturb ? (float)(frand(-0.33, 0.33) * cs) : 0.0f;
                    for (n = 0; n < 4; n++) {
                        q[n].x = c0.x + sc * (rc.quad[n].x - c0.x) + dx;
                        q[n].y = c0.y + sc * (rc.quad[n].y - c0.y) + dy;
                    }
                }
                memset(&res, 0, sizeof res);
                fp.flags = ACTAG_FIT_DEFAULT_FLAGS | (rep % 4 == 3 ? ACTAG_FIT_WIDE : 0);
                TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_decode_quad_fit(img, rc.rows, rc.cols,
                                                                      rc.stride, q, &tf->fam,
                                                                      perturb ? maxc : 0, &fp,
                                                                      &res));
                TEST_ASSERT_EQUAL_INT(id, res.id);
                TEST_ASSERT_EQUAL_INT(0, res.hamming);
                TEST_ASSERT_EQUAL_INT(d >> 2, res.mirrored);
                TEST_ASSERT_EQUAL_FLOAT(1.0f, res.ring_black);
                TEST_ASSERT_EQUAL_FLOAT(1.0f, res.interior_white);
                TEST_ASSERT_FLOAT_WITHIN(1.0f, (float)white, res.contrast + 0.5f);
                TEST_ASSERT_EQUAL_FLOAT(0.0f, res.flip_weight);
                for (n = 0; n < 4; n++) {
                    /* corners[] are the given quad's points in tag order;
                     * the fitted grid lands on the printed corners */
                    TEST_ASSERT_FLOAT_WITHIN((float)(0.3 * cs) + 0.6f, rc.printed[n].x,
                                             res.fit_corners[n].x);
                    TEST_ASSERT_FLOAT_WITHIN((float)(0.3 * cs) + 0.6f, rc.printed[n].y,
                                             res.fit_corners[n].y);
                    if (!perturb) {
                        TEST_ASSERT_FLOAT_WITHIN(0.01f, rc.printed[n].x, res.corners[n].x);
                        TEST_ASSERT_FLOAT_WITHIN(0.01f, rc.printed[n].y, res.corners[n].y);
                    }
                }
            }
        }
    }
}

static void test_fit_renders(void)
{
    test_family tf;
    tu_seed(71);
    load_h10(&tf);
    run_fit_renders(&tf, TU_EMULATED ? 4 : 8); /* reps 0-3: every kind of quad */
    make_family(&tf, 16, 5, 6, "hand16");
    run_fit_renders(&tf, 3);
    make_family(&tf, 32, 11, 6, "hand32");
    run_fit_renders(&tf, 3);
}

/* Brute-force reference of the fit decoder's matching on noise-free
 * two-level grids: the data ring painted from a random word, the quad
 * exact (no grid search). The reference: masked distance (the 4 corner
 * cells do not count) to every code in all 8 physical orientations. The
 * decoder accepts only the unique nearest reading within the corrections
 * (then with the reference's ID, distance, handedness and bit margin),
 * never a tie or a reading beyond the limit, and one that leads the
 * runner-up clearly (2 bits with at most 2 flipped, or 4 bits): always with
 * at most 1 flipped cell; with 2 or more, the stretched-grid check
 * (decode_fit.c) may find another template on a grid stretched along range
 * or a tag axis that explains the cells better than the reading's own (the
 * flipped cells are whole-cell errors, which spread partial mismatches
 * explain more cheaply) and refuse, a miss: in at most 1 of 50 of those
 * cases (2 of 357 on the host). */
/* Reference for actag_fit_bit_lead: x = odds h^b and y = (n - h)^b as
 * decimal numbers (base 10000 digits, least significant first), not the
 * library's binary limbs; the least b in 0..32 with x <= y, at least
 * margin, or 33. */
enum { REF_DIGITS = 60 }; /* 10^240 > 2^20 32^32 */
static void ref_dec_mul(int *a, int m)
{
    int i, carry = 0;
    for (i = 0; i < REF_DIGITS; i++) {
        int v = a[i] * m + carry;
        a[i] = v % 10000;
        carry = v / 10000;
    }
    TEST_ASSERT_EQUAL_INT(0, carry);
}

static int ref_bit_lead(int h, int n, int margin, int odds)
{
    int x[REF_DIGITS], y[REF_DIGITS], b, i;
    if (h == 0 || odds == 1)
        return margin;
    memset(x, 0, sizeof x);
    memset(y, 0, sizeof y);
    x[0] = odds % 10000;
    x[1] = odds / 10000;
    y[0] = 1;
    for (b = 0; b <= 32; b++) {
        int le = 1;
        if (b > 0) {
            ref_dec_mul(x, h);
            ref_dec_mul(y, n - h);
        }
        for (i = REF_DIGITS - 1; i >= 0; i--)
            if (x[i] != y[i]) {
                le = x[i] < y[i];
                break;
            }
        if (le)
            return b > margin ? b : margin;
    }
    return 33;
}

/* actag_fit_bit_lead against the decimal reference on every valid (hamming,
 * nbits) and a spread of margins and odds (ties included: odds 4, hamming 1,
 * nbits 3 needs exactly 2 bits), the examples decode.h gives, and 33 for
 * arguments out of range. */
static void test_bit_lead_vs_exact(void)
{
    static const int odds[] = {1, 2, 3, 4, 9, 10, 99, 100, 101, 1000, 4096, 999999, 1000000};
    int n, h, m, o;
    for (n = 1; n <= 32; n++)
        for (h = 0; h <= n; h++)
            for (m = 0; m <= 32; m += (m < 4 ? 1 : 14))
                for (o = 0; o < (int)(sizeof odds / sizeof odds[0]); o++) {
                    char msg[120];
                    snprintf(msg, sizeof msg, "hamming %d of %d, margin %d, odds %d", h, n, m,
                             odds[o]);
                    TEST_ASSERT_EQUAL_INT_MESSAGE(ref_bit_lead(h, n, m, odds[o]),
                                                  actag_fit_bit_lead(h, n, m, odds[o]), msg);
                }
    TEST_ASSERT_EQUAL_INT(2, actag_fit_bit_lead(1, 3, 0, 4)); /* 4 = 2^2: a tie passes */
    TEST_ASSERT_EQUAL_INT(2, actag_fit_bit_lead(1, 20, 2, 100));
    TEST_ASSERT_EQUAL_INT(3, actag_fit_bit_lead(2, 20, 2, 100));
    TEST_ASSERT_EQUAL_INT(3, actag_fit_bit_lead(3, 20, 2, 100));
    TEST_ASSERT_EQUAL_INT(4, actag_fit_bit_lead(4, 20, 2, 100));
    TEST_ASSERT_EQUAL_INT(2, actag_fit_bit_lead(2, 24, 2, 100));
    TEST_ASSERT_EQUAL_INT(3, actag_fit_bit_lead(3, 24, 2, 100));
    TEST_ASSERT_EQUAL_INT(2, actag_fit_bit_lead(0, 20, 2, 100));
    TEST_ASSERT_EQUAL_INT(33, actag_fit_bit_lead(10, 20, 2, 100));
    TEST_ASSERT_EQUAL_INT(2, actag_fit_bit_lead(10, 20, 2, 1)); /* the rule off */
    TEST_ASSERT_EQUAL_INT(33, actag_fit_bit_lead(-1, 20, 2, 100));
    TEST_ASSERT_EQUAL_INT(33, actag_fit_bit_lead(21, 20, 2, 100));
    TEST_ASSERT_EQUAL_INT(33, actag_fit_bit_lead(1, 0, 2, 100));
    TEST_ASSERT_EQUAL_INT(33, actag_fit_bit_lead(1, 33, 2, 100));
    TEST_ASSERT_EQUAL_INT(33, actag_fit_bit_lead(1, 20, -1, 100));
    TEST_ASSERT_EQUAL_INT(33, actag_fit_bit_lead(1, 20, 33, 100));
    TEST_ASSERT_EQUAL_INT(33, actag_fit_bit_lead(1, 20, 2, 0));
    TEST_ASSERT_EQUAL_INT(33, actag_fit_bit_lead(1, 20, 2, 1000001));
}

static void test_fit_matching_vs_brute_force(void)
{
    enum { CS = 9, MG = 6 };
    static uint8_t img[(8 * CS + 2 * MG) * (8 * CS + 2 * MG + 5)];
    test_family tf;
    int bits = 24, k = 6, side = (k + 1) * CS + 2 * MG, stride = side + 5, t;
    int checked = 0, accepted = 0, clear_flipped = 0, clear_refused = 0;
    uint32_t keep = 0xffffffu & ~((1u << 23) | (1u << 17) | (1u << 11) | (1u << 5));
    actag_fit_params fp;
    actag_point q[4];
    tu_seed(72);
    load_h10(&tf);
    actag_fit_params_default(&fp);
    fp.flags |= ACTAG_FIT_NO_SEARCH;
    q[0].x = (float)(MG + 2 * CS) - 0.5f;
    q[0].y = (float)(MG + 2 * CS) - 0.5f;
    q[1].x = (float)(MG + 5 * CS) - 0.5f;
    q[1].y = q[0].y;
    q[2].x = q[1].x;
    q[2].y = (float)(MG + 5 * CS) - 0.5f;
    q[3].x = q[0].x;
    q[3].y = q[2].y;
    for (t = 0; t < TU_TRIALS(3000, 6); t++) {
        uint32_t w;
        int r, c, maxc = tu_range(0, 4), best[2] = {99, 99}, bid[2] = {0, 0}, d1, d2;
        int h, i, rot, rcode, lead;
        actag_decode_result res;
        uint8_t lo = (uint8_t)tu_range(0, 100), hi = (uint8_t)tu_range(lo + 30, 255);
        /* a random word near a random code (so that many cases decode) */
        w = tf.codes[tu_range(0, 6)];
        for (rot = tu_range(0, 3); rot > 0; rot--)
            w = ref_rot(w, bits);
        if (tu_range(0, 1))
            w = ref_mirror(w, bits);
        for (i = tu_range(0, 7); i > 0; i--)
            w ^= 1u << tu_range(0, 23);
        memset(img, 0xee, sizeof img);
        for (r = 0; r < side; r++)
            for (c = 0; c < side; c++) {
                int cx = (c - MG) / CS, cy = (r - MG) / CS, v = 0;
                if (c >= MG && r >= MG && cx <= k && cy <= k) {
                    if (cx == 0 || cy == 0 || cx == k || cy == k)
                        v = seq_get(w, bits, ring_index(k, cx, cy));
                    else
                        v = (cx >= 2 && cx <= k - 2 && cy >= 2 && cy <= k - 2);
                }
                img[(size_t)r * (size_t)stride + (size_t)c] = v ? hi : lo;
            }
        /* the reference: masked distance of every reading (code, rotation,
         * handedness); the best, and the best of all the others */
        d1 = d2 = 99;
        for (h = 0; h < 2; h++)
            for (i = 0; i < 7; i++) {
                uint32_t cw = tf.codes[i];
                for (rot = 0; rot < 4; rot++) {
                    uint32_t o = h ? ref_mirror(cw, bits) : cw;
                    int d = tu_popcount((o ^ w) & keep);
                    if (d < d1) {
                        d2 = d1;
                        d1 = d;
                        bid[0] = i;
                        best[0] = h;
                    } else if (d < d2) {
                        d2 = d;
                    }
                    cw = ref_rot(cw, bits);
                }
            }
        rcode = actag_decode_quad_fit(img, side, side, stride, q, &tf.fam, maxc, &fp, &res);
        /* the lead in bits the reading needs (min_bit_margin, min_bit_odds) */
        lead = ref_bit_lead(d1, 20, fp.min_bit_margin, fp.min_bit_odds);
        if (rcode == ACTAG_OK) {
            /* whatever it accepts is the unique nearest reading, and leads
             * by the bits its corrections ask */
            TEST_ASSERT_TRUE(d1 <= maxc && d2 > d1 && d2 - d1 >= lead);
            TEST_ASSERT_EQUAL_INT(bid[0], res.id);
            TEST_ASSERT_EQUAL_INT(d1, res.hamming);
            TEST_ASSERT_EQUAL_INT(best[0], res.mirrored);
            TEST_ASSERT_EQUAL_HEX32(w, res.observed);
            TEST_ASSERT_EQUAL_INT(d2 - d1, res.bit_margin);
            accepted++;
        }
        if (d1 > maxc || d2 - d1 < lead) {
            TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, rcode);
        } else if ((d1 <= 2 && d2 - d1 >= 2) || d2 - d1 >= 4) {
            /* a clean two-level grid with a clear lead clears every margin
             * (4 flipped cells with a 2-bit lead may not: that is little
             * evidence, a likelihood ratio of about e^4.5 here) */
            char msg[200];
            actag_fit_params f2 = fp;
            actag_decode_result r2;
            int rc2;
            f2.min_margin = -1000.0f;
            rc2 = actag_decode_quad_fit(img, side, side, stride, q, &tf.fam, maxc, &f2, &r2);
            snprintf(msg, sizeof msg, "t %d d1 %d d2 %d maxc %d; without margin rc %d margin %.2f",
                     t, d1, d2, maxc, rc2, (double)r2.decision_margin);
            if (d1 <= 1) {
                TEST_ASSERT_EQUAL_INT_MESSAGE(ACTAG_OK, rcode, msg);
            } else {
                clear_flipped++;
                if (rcode != ACTAG_OK) {
                    TEST_ASSERT_EQUAL_INT_MESSAGE(ACTAG_ERR_NO_MATCH, rcode, msg);
                    clear_refused++;
                }
            }
        }
        checked++;
    }
    TEST_ASSERT_TRUE_MESSAGE(clear_refused * 50 <= clear_flipped,
                             "too many clear readings with flipped cells refused");
    TEST_ASSERT_GREATER_THAN_INT(TU_TRIALS(3000, 6) * 2 / 3, checked); /* host: 2000 */
    TEST_ASSERT_GREATER_THAN_INT(TU_TRIALS(3000, 6) / 6, accepted);    /* host: 500 */
    TEST_ASSERT_LESS_THAN_INT(checked, accepted);
}

static void test_fit_errors_and_edges(void)
{
    static uint8_t img[64 * 64];
    test_family tf;
    actag_fit_params fp, bad;
    actag_decode_result res;
    actag_point q[4] = {{20, 20}, {40, 20}, {40, 40}, {20, 40}};
    actag_point deg[4] = {{20, 20}, {40, 20}, {60, 20}, {20, 40}};
    load_h10(&tf);
    actag_fit_params_default(&fp);
    TEST_ASSERT_EQUAL_INT(ACTAG_FIT_DEFAULT_FLAGS, fp.flags);
    TEST_ASSERT_EQUAL_FLOAT(0.5f, fp.level);
    actag_fit_params_default(NULL); /* no crash */
    memset(img, 128, sizeof img);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_decode_quad_fit(NULL, 64, 64, 64, q, &tf.fam, 0, &fp, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_decode_quad_fit(img, 64, 64, 64, NULL, &tf.fam, 0, &fp, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_decode_quad_fit(img, 64, 64, 64, q, NULL, 0, &fp, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_decode_quad_fit(img, 64, 64, 64, q, &tf.fam, 0, NULL, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_decode_quad_fit(img, 64, 64, 64, q, &tf.fam, 0, &fp, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_decode_quad_fit(img, 64, 64, 63, q, &tf.fam, 0, &fp, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_decode_quad_fit(img, 0, 64, 64, q, &tf.fam, 0, &fp, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_CORRECTIONS, actag_decode_quad_fit(img, 64, 64, 64, q, &tf.fam, 5, &fp, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_CORRECTIONS, actag_decode_quad_fit(img, 64, 64, 64, q, &tf.fam, -1, &fp, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_decode_quad_fit(img, 64, 64, 64, deg, &tf.fam, 0, &fp, &res));
    bad = fp;
    bad.sample_offset = 0.6f;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_decode_quad_fit(img, 64, 64, 64, q, &tf.fam, 0, &bad, &res));
    bad = fp;
    bad.level = -0.1f;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_decode_quad_fit(img, 64, 64, 64, q, &tf.fam, 0, &bad, &res));
    bad = fp;
    bad.min_contrast = 256;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_decode_quad_fit(img, 64, 64, 64, q, &tf.fam, 0, &bad, &res));
    /* constant image: no contrast, no tag (with and without the searches) */
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, actag_decode_quad_fit(img, 64, 64, 64, q, &tf.fam, 4, &fp, &res));
    bad = fp;
    bad.flags |= ACTAG_FIT_WIDE;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, actag_decode_quad_fit(img, 64, 64, 64, q, &tf.fam, 4, &bad, &res));
    /* grid outside a tiny image: 1x1, 1xN, Nx1 */
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, actag_decode_quad_fit(img, 1, 1, 1, q, &tf.fam, 4, &fp, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, actag_decode_quad_fit(img, 1, 64, 64, q, &tf.fam, 4, &fp, &res));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, actag_decode_quad_fit(img, 64, 1, 1, q, &tf.fam, 4, &fp, &res));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_homography_vs_dlt);
    RUN_TEST(test_affine_vs_lstsq);
    RUN_TEST(test_homography_degenerate);
    RUN_TEST(test_bit_positions_spec_24);
    RUN_TEST(test_bit_positions_all_sizes);
    RUN_TEST(test_mirror_function);
    RUN_TEST(test_read_word_vs_brute_force);
    RUN_TEST(test_render_h10_all_orientations);
    RUN_TEST(test_render_other_sizes);
    RUN_TEST(test_mirror_model_rev_vs_reflection);
    RUN_TEST(test_bit_flips_h10);
    RUN_TEST(test_bit_flips_h8_h6);
    RUN_TEST(test_bit_flips_handmade_32);
    RUN_TEST(test_errors_and_edges);
    RUN_TEST(test_scale_extremes);
    RUN_TEST(test_real_example_frame);
    RUN_TEST(test_h4_mirror_ambiguity);
    RUN_TEST(test_fit_renders);
    RUN_TEST(test_bit_lead_vs_exact);
    RUN_TEST(test_fit_matching_vs_brute_force);
    RUN_TEST(test_fit_errors_and_edges);
    return UNITY_END();
}
