/* actag_quad_fit's fast paths (src/quad.c without ACTAG_QUAD_REFERENCE:
 * skipping along chains (ACTAG_QUAD_FORCE_SKIP, as on targets without a
 * vector unit), early exits from the counts, the SSE2 and AVX2 loops on
 * x86 (the skipping copy also runs the SSE2 ones on an AVX2 machine), the
 * plain C ones (ACTAG_NO_SIMD)) against its reference loops (the same
 * file compiled in here with ACTAG_QUAD_REFERENCE, under another name):
 * the same return code, the same bytes of actag_quad and the same
 * generator state afterwards, on random contours of many kinds: noisy
 * chains around parallelograms (most fit), random-walk blobs, polygons with
 * spikes, chains far from the origin or at negative coordinates, point sets
 * that are not chains (the fast paths must fall back), with random
 * parameters. Then the SIMD helpers (claim, the sample walks, the inlier
 * count), SSE2 and AVX2, against the plain C ones on random input. */
#include "unity.h"
#include "test_util.h"

#include <math.h>
#include <string.h>

#include "actag/quad.h"

int actag_quad_fit_reference(const actag_ipoint *pts, int npoints, const actag_quad_params *params,
                             actag_rng *rng, void *scratch, size_t scratch_size, actag_quad *out);
void actag_quad_params_default_reference(actag_quad_params *p);
#define ACTAG_QUAD_REFERENCE 1
#define actag_quad_fit actag_quad_fit_reference
#define actag_quad_params_default actag_quad_params_default_reference
#include "../src/quad.c"
#undef actag_quad_fit
#undef actag_quad_params_default
#undef ACTAG_QUAD_REFERENCE

/* The fast paths in plain C (ACTAG_NO_SIMD), as targets without SSE2 run
 * them (the library here takes the SSE2 loops): compiled in again, every
 * name renamed; also the scalar side of the SIMD helpers' tests below. */
int actag_quad_fit_scalar(const actag_ipoint *pts, int npoints, const actag_quad_params *params,
                          actag_rng *rng, void *scratch, size_t scratch_size, actag_quad *out);
void actag_quad_params_default_scalar(actag_quad_params *p);
#define ACTAG_NO_SIMD 1
#define actag_quad_fit actag_quad_fit_scalar
#define actag_quad_params_default actag_quad_params_default_scalar
#define qsums qsums_scalar
#define qline qline_scalar
#define qquad qquad_scalar
#define qctx qctx_scalar
#define qsums32 qsums32_scalar
#define sums_add sums_add_scalar
#define sums32_add sums32_add_scalar
#define ratio_of ratio_of_scalar
#define count_min count_min_scalar
#define line_fit line_fit_scalar
#define pseudo_angle pseudo_angle_scalar
#define quad_from_lines quad_from_lines_scalar
#define quad_shape_ok quad_shape_ok_scalar
#define inlier_side inlier_side_scalar
#define quad_inliers quad_inliers_scalar
#define quad_support quad_support_scalar
#define quad_accept quad_accept_scalar
#define side_run side_run_scalar
#define side_sums side_sums_scalar
#define refine_and_accept refine_and_accept_scalar
#define claim_chain claim_chain_scalar
#define claim claim_scalar
#define walk_sums walk_sums_scalar
#define walk_raw walk_raw_scalar
#define walk_all walk_all_scalar
#define walk_far walk_far_scalar
#define walk_near walk_near_scalar
#define sample_line sample_line_scalar
#include "../src/quad.c"
#undef actag_quad_fit
#undef actag_quad_params_default
#undef ACTAG_NO_SIMD
#undef qsums
#undef qline
#undef qquad
#undef qctx
#undef qsums32
#undef sums_add
#undef sums32_add
#undef ratio_of
#undef count_min
#undef line_fit
#undef pseudo_angle
#undef quad_from_lines
#undef quad_shape_ok
#undef inlier_side
#undef quad_inliers
#undef quad_support
#undef quad_accept
#undef side_run
#undef side_sums
#undef refine_and_accept
#undef claim_chain
#undef claim
#undef walk_sums
#undef walk_raw
#undef walk_all
#undef walk_far
#undef walk_near
#undef sample_line

/* 1 if the library takes its AVX2 loops here (cpu_x86.h came with the
 * first copy). */
static int host_avx2(void)
{
#if ACTAG__AVX2
    return actag__cpu_avx2();
#else
    return 0;
#endif
}

/* The skipping copy asks g_avx2 instead: 0 runs its SSE2 loops on an AVX2
 * machine too. */
static int g_avx2;
static inline int test_cpu_avx2(void) { return g_avx2; }
#define actag__cpu_avx2 test_cpu_avx2

/* The skipping claim loop, which the library uses only on targets without
 * a vector unit: compiled in a third time, the names the reference copy
 * also defines renamed. With SSE2 it has the SSE2 and AVX2 loops too (the
 * claim loop on contours that are not chains): the SIMD helpers' tests
 * call them here. */
int actag_quad_fit_skip(const actag_ipoint *pts, int npoints, const actag_quad_params *params,
                        actag_rng *rng, void *scratch, size_t scratch_size, actag_quad *out);
void actag_quad_params_default_skip(actag_quad_params *p);
#define ACTAG_QUAD_FORCE_SKIP 1
#define actag_quad_fit actag_quad_fit_skip
#define actag_quad_params_default actag_quad_params_default_skip
#define qsums qsums_skip
#define qline qline_skip
#define qquad qquad_skip
#define qctx qctx_skip
#define sums_add sums_add_skip
#define ratio_of ratio_of_skip
#define count_min count_min_skip
#define line_fit line_fit_skip
#define pseudo_angle pseudo_angle_skip
#define quad_from_lines quad_from_lines_skip
#define quad_shape_ok quad_shape_ok_skip
#define quad_inliers quad_inliers_skip
#define quad_support quad_support_skip
#define quad_accept quad_accept_skip
#define side_sums side_sums_skip
#define refine_and_accept refine_and_accept_skip
#define claim claim_skip
#define walk_sums walk_sums_skip
#define sample_line sample_line_skip
#include "../src/quad.c"
#undef actag_quad_fit
#undef actag_quad_params_default

void setUp(void) {}
void tearDown(void) {}

#define MAXP 6000
static actag_ipoint g_raw[MAXP], g_pts[MAXP];
static unsigned char g_scratch[ACTAG_QUAD_SCRATCH_SIZE(MAXP)];

static double urand(void) { return (double)tu_rand() / 4294967296.0; }
static int irand(int lo, int hi) { return lo + (int)(tu_rand() % (uint32_t)(hi - lo + 1)); }

/* Joins consecutive raw points with 8-neighbour steps (a chain, as a border
 * follower gives), from (x0, y0) added to every point. Returns the count. */
static int chainify(const actag_ipoint *raw, int n, int x0, int y0, actag_ipoint *out, int cap)
{
    int i, m = 0, x, y;
    if (n < 1)
        return 0;
    x = raw[0].x;
    y = raw[0].y;
    for (i = 0; i < n && m < cap; i++) {
        int tx = raw[i].x, ty = raw[i].y;
        do {
            x += tx > x ? 1 : (tx < x ? -1 : 0);
            y += ty > y ? 1 : (ty < y ? -1 : 0);
            out[m].x = (int16_t)(x + x0);
            out[m].y = (int16_t)(y + y0);
            m++;
        } while ((x != tx || y != ty) && m < cap);
    }
    return m;
}

/* Points along a random convex quadrilateral (near a parallelogram when
 * skew is small) of sides about size, with noise sigma and spikes. */
static int polygon_points(double size, double skew, double sigma, double spikes, actag_ipoint *raw,
                          int cap)
{
    double cx[4], cy[4], a, s1, s2, sh;
    int j, n = 0;
    /* one draw per statement: a fixed order on every compiler */
    a = urand() * 6.2831853;
    s1 = size * (0.6 + 0.8 * urand());
    s2 = size * (0.6 + 0.8 * urand());
    sh = (urand() - 0.5) * 0.8;
    double ux = cos(a), uy = sin(a), vx = -uy + sh * ux, vy = ux + sh * uy;
    cx[0] = 0;
    cy[0] = 0;
    cx[1] = s1 * ux;
    cy[1] = s1 * uy;
    cx[2] = s1 * ux + s2 * vx;
    cy[2] = s1 * uy + s2 * vy;
    cx[3] = s2 * vx;
    cy[3] = s2 * vy;
    for (j = 0; j < 4; j++) {
        cx[j] += (urand() - 0.5) * skew * size + 2 * size;
        cy[j] += (urand() - 0.5) * skew * size + 2 * size;
    }
    for (j = 0; j < 4; j++) {
        double x0 = cx[j], y0 = cy[j], x1 = cx[(j + 1) & 3], y1 = cy[(j + 1) & 3];
        double len = hypot(x1 - x0, y1 - y0);
        int steps = (int)ceil(len), k;
        for (k = 0; k < steps && n < cap; k++) {
            double t = (double)k / steps, ex = 0, ey = 0;
            if (sigma > 0) {
                /* the order of draws within one expression is unspecified:
                 * one per statement */
                ex = urand();
                ex += urand();
                ex += urand();
                ex = (ex - 1.5) * 2 * sigma;
                ey = urand();
                ey += urand();
                ey += urand();
                ey = (ey - 1.5) * 2 * sigma;
            }
            if (urand() < spikes) {
                double h = 3 + 8 * urand();
                ex += (y1 - y0) / len * h;
                ey -= (x1 - x0) / len * h;
            }
            raw[n].x = (int16_t)floor(x0 + t * (x1 - x0) + ex + 0.5);
            raw[n].y = (int16_t)floor(y0 + t * (y1 - y0) + ey + 0.5);
            n++;
        }
    }
    return n;
}

/* A random walk (a blob outline, not a quad). */
static int walk_points(int n, actag_ipoint *raw)
{
    int i, x = 100, y = 100;
    for (i = 0; i < n; i++) {
        x += irand(-1, 1);
        y += irand(-1, 1);
        raw[i].x = (int16_t)x;
        raw[i].y = (int16_t)y;
    }
    return n;
}

static void random_params(actag_quad_params *p)
{
    actag_quad_params_default(p);
    switch (irand(0, 3)) {
    case 0:
        break; /* the library defaults */
    case 1:    /* actag_detect's */
        p->max_iterations = 100;
        break;
    default:
        p->max_iterations = irand(1, 300);
        p->sample_fraction = (float)(0.03 + 0.3 * urand());
        p->inlier_ratio = (float)(0.5 + 0.5 * urand());
        p->min_inlier_ratio = (float)(0.4 + 0.6 * urand());
        p->inlier_distance = (float)(0.3 + 6.0 * urand());
        p->min_parallel_cos = (float)(0.5 + 0.5 * urand());
        break;
    }
}

/* Both versions on the same input from the same generator state. */
static int compare(const actag_ipoint *pts, int n, const actag_quad_params *p, uint64_t seed,
                   const char *what, int trial)
{
    actag_rng ra, rb;
    actag_quad qa, qb;
    int rca = ACTAG_OK, rcb;
    char msg[160];
    actag_rng_seed(&rb, seed);
    memset(&qb, 0x5a, sizeof qb);
    int v;
    rcb = actag_quad_fit_reference(pts, n, p, &rb, g_scratch, ACTAG_QUAD_SCRATCH_SIZE(n), &qb);
    for (v = 0; v < 4; v++) { /* the library, the skipping build (SSE2, AVX2), plain C */
        static const char *const name[4] = {"library", "skipping SSE2", "skipping AVX2",
                                            "plain C"};
        if (v == 2 && !host_avx2())
            continue;
        g_avx2 = v == 2;
        actag_rng_seed(&ra, seed);
        memset(&qa, 0x5a, sizeof qa);
        rca = (v == 3 ? actag_quad_fit_scalar : v ? actag_quad_fit_skip : actag_quad_fit)(
            pts, n, p, &ra, g_scratch, ACTAG_QUAD_SCRATCH_SIZE(n), &qa);
        snprintf(msg, sizeof msg, "%s, %s trial %d: n %d, d %g, iterations %d / %d",
                 name[v], what, trial, n, (double)p->inlier_distance,
                 qa.iterations, qb.iterations);
        TEST_ASSERT_EQUAL_INT_MESSAGE(rcb, rca, msg);
        TEST_ASSERT_EQUAL_MEMORY_MESSAGE(&qb, &qa, sizeof qa, msg);
        TEST_ASSERT_EQUAL_MEMORY_MESSAGE(&rb, &ra, sizeof ra, msg);
    }
    return rca == ACTAG_OK;
}

static void test_chains_around_quads(void)
{
    int t, trials = TU_TRIALS(1500, 30), found = 0;
    tu_seed(11);
    for (t = 0; t < trials; t++) {
        actag_quad_params p;
        int nraw, n, x0 = irand(-200, 300), y0 = irand(-200, 300);
        /* one PRNG call per statement: an argument list's order is the compiler's */
        double size = 8 + 120 * urand(), skew, sigma, spikes;
        size = 8 + (size - 8) * urand();
        skew = urand() < 0.7 ? 0.0 : 0.4;
        skew *= urand();
        sigma = urand() < 0.3 ? 0.0 : 1.5;
        sigma *= urand();
        spikes = urand() < 0.5 ? 0.0 : 0.05;
        spikes *= urand();
        nraw = polygon_points(size, skew, sigma, spikes, g_raw, MAXP);
        if (t % 7 == 3) { /* far from the origin: larger float roundings */
            x0 = irand(20000, 32000);
            y0 = irand(-32000, -20000);
        }
        n = chainify(g_raw, nraw, x0 - (int)(2 * size), y0 - (int)(2 * size), g_pts, MAXP);
        random_params(&p);
        found += compare(g_pts, n, &p, (uint64_t)t + 1, "quad chain", t);
    }
    printf("quad chains: %d of %d fitted\n", found, trials);
    TEST_ASSERT_TRUE(found > trials / 4);
}

static void test_random_walk_blobs(void)
{
    int t, trials = TU_TRIALS(300, 30);
    tu_seed(12);
    for (t = 0; t < trials; t++) {
        actag_quad_params p;
        int n = irand(1, 1500);
        walk_points(n, g_pts);
        random_params(&p);
        compare(g_pts, n, &p, (uint64_t)t + 7, "random walk", t);
    }
}

static void test_not_chains(void)
{
    /* Polygons without chainify (gaps of several pixels), duplicates, and a
     * chain with one long jump: the fast paths must not assume steps <= 1. */
    int t, trials = TU_TRIALS(600, 30);
    tu_seed(13);
    for (t = 0; t < trials; t++) {
        actag_quad_params p;
        double size = 8 + 100 * urand(), skew, sigma;
        int n, i;
        skew = 0.1 * urand();
        sigma = urand();
        n = polygon_points(size, skew, sigma, 0.02, g_raw, MAXP);
        if (t % 3 == 0) { /* spread the points apart: steps of 2-3 px */
            for (i = 0; i < n; i++) {
                g_raw[i].x = (int16_t)(g_raw[i].x * 2 + irand(0, 1));
                g_raw[i].y = (int16_t)(g_raw[i].y * 2 + irand(0, 1));
            }
        } else if (t % 3 == 1) { /* a chain with one jump */
            n = chainify(g_raw, n, 0, 0, g_pts, MAXP);
            memcpy(g_raw, g_pts, (size_t)n * sizeof *g_raw);
            i = irand(0, n - 1);
            g_raw[i].x = (int16_t)(g_raw[i].x + irand(2, 30));
        }
        random_params(&p);
        compare(g_raw, n, &p, (uint64_t)t + 99, "not a chain", t);
    }
}

static void test_large_quads(void)
{
    /* Chains around quads of sides near 1000 px (up to MAXP points): moment
     * sums beyond 32 bits, where the fast sums fall back to 64 bits (the
     * walks too with large sample fractions). */
    int t, trials = TU_TRIALS(40, 10), found = 0;
    tu_seed(14);
    for (t = 0; t < trials; t++) {
        actag_quad_params p;
        double size = 900 + 100 * urand(), sigma = 1.5 * urand();
        int nraw = polygon_points(size, 0.1, sigma, 0.0, g_raw, MAXP);
        int n = chainify(g_raw, nraw, -(int)(2 * size), -(int)(2 * size), g_pts, MAXP);
        random_params(&p);
        if (t % 2)
            p.sample_fraction = (float)(0.5 + 0.5 * urand());
        found += compare(g_pts, n, &p, (uint64_t)t + 333, "large quad", t);
    }
    printf("large quads: %d of %d fitted\n", found, trials);
}

/* ---- The SIMD helpers against the plain C ones (the skipping copy has the
 * SSE2 loops on x86, the plain-C copy none), on random input: every length
 * 0..300 (none a multiple of the lane count required), coordinates up to
 * the int16 limits, labels of every density, lines that meet points at
 * exactly d, NaN and huge lines. The arrays end where the buffers end, so
 * a read past n is one past a global (ASan builds report it). */
#define HCAP 320
static actag_ipoint h_ptsb[HCAP];
static float h_fxb[HCAP], h_fyb[HCAP];
static unsigned char h_laba[HCAP], h_labb[HCAP];

typedef struct hset {
    int n;
    actag_ipoint *pts;
    float *fx, *fy;
    unsigned char *la, *lb; /* the two copies' labels */
    qctx ka;                /* the skipping copy's context (SSE2 or AVX2 loops) */
    qctx_scalar kb;         /* the plain-C copy's */
} hset;

/* Which loops the skipping copy's context k takes: AVX2 (v 1) or SSE2. */
#ifdef QUAD_AVX2
#define H_AVX2(k, v) ((k).avx2 = (v))
#else
#define H_AVX2(k, v) ((void)(v))
#endif

/* n random points (range: their spread, up to 65535) at a random offset,
 * labels claimed with probability pc. */
static void hset_make(hset *h, int n, int range, double pc, float d)
{
    int i, minx = 0, miny = 0, maxx = 0, maxy = 0, base_x, base_y;
    h->n = n;
    h->pts = h_ptsb + HCAP - n;
    h->fx = h_fxb + HCAP - n;
    h->fy = h_fyb + HCAP - n;
    h->la = h_laba + HCAP - n;
    h->lb = h_labb + HCAP - n;
    base_x = irand(-32768, 32767 - range);
    base_y = irand(-32768, 32767 - range);
    for (i = 0; i < n; i++) {
        h->pts[i].x = (int16_t)(base_x + irand(0, range));
        h->pts[i].y = (int16_t)(base_y + irand(0, range));
        if (i == 0 || h->pts[i].x < minx)
            minx = h->pts[i].x;
        if (i == 0 || h->pts[i].y < miny)
            miny = h->pts[i].y;
        if (i == 0 || h->pts[i].x > maxx)
            maxx = h->pts[i].x;
        if (i == 0 || h->pts[i].y > maxy)
            maxy = h->pts[i].y;
    }
    for (i = 0; i < n; i++) {
        h->fx[i] = (float)(h->pts[i].x - minx);
        h->fy[i] = (float)(h->pts[i].y - miny);
        h->la[i] = urand() < pc ? (unsigned char)irand(1, 4) : 0u;
        h->lb[i] = h->la[i];
    }
    memset(&h->ka, 0, sizeof h->ka);
    h->ka.pts = h->pts;
    h->ka.fx = h->fx;
    h->ka.fy = h->fy;
    h->ka.n = n;
    h->ka.ox = minx;
    h->ka.oy = miny;
    h->ka.bw = (float)(maxx - minx);
    h->ka.bh = (float)(maxy - miny);
    h->ka.ext = maxx - minx > maxy - miny ? maxx - minx : maxy - miny;
    h->ka.d = d;
    h->ka.d2 = d * d;
    h->ka.chain = 0; /* the plain claim loop, not claim_chain */
    memcpy(&h->kb, &h->ka, sizeof h->kb);
}

/* A line of some kind: through a point at a random angle, axis-parallel
 * through integers (points at exactly d), NaN, or far from every point. */
static qline h_line(const hset *h)
{
    qline l;
    int kind = irand(0, 9), i = h->n ? irand(0, h->n - 1) : 0;
    float px = h->n ? h->fx[i] : 0.0f, py = h->n ? h->fy[i] : 0.0f;
    if (kind < 5) {
        double a = urand() * 6.2831853;
        l.nx = (float)cos(a);
        l.ny = (float)sin(a);
        l.c = l.nx * px + l.ny * py + (float)(urand() - 0.5) * 4.0f;
    } else if (kind < 8) {
        l.nx = kind == 5 ? 1.0f : 0.0f;
        l.ny = kind == 5 ? 0.0f : (kind == 6 ? 1.0f : -1.0f);
        l.c = (kind == 5 ? px : l.ny * py) + (float)irand(-3, 3);
    } else if (kind == 8) {
        l.nx = NAN;
        l.ny = 0.6f;
        l.c = 1.0f;
    } else {
        l.nx = 0.8f;
        l.ny = -0.6f;
        l.c = urand() < 0.5 ? 1e30f : -INFINITY;
    }
    return l;
}

static void h_params(int t, int *n, int *range, double *pc, float *d)
{
    static const double pcs[6] = {0.0, 0.1, 0.5, 0.8, 0.97, 1.0};
    *n = t < 300 ? t % 40 : irand(0, 300);
    *range = t % 5 == 4 ? 65535 : irand(1, t % 5 == 3 ? 3000 : 120);
    *pc = pcs[irand(0, 5)];
    *d = irand(0, 1) ? (float)irand(1, 3) : (float)(0.2 + 5.0 * urand());
}

static void test_simd_claim(void)
{
    int t, trials = TU_TRIALS(3000, 30);
    char msg[120];
    tu_seed(21);
    for (t = 0; t < trials; t++) {
        hset h;
        qline l;
        qline_scalar lb;
        int n, range, need, ca, cb, v;
        double pc;
        float d;
        unsigned char tag = (unsigned char)irand(1, 4), lab0[HCAP];
        h_params(t, &n, &range, &pc, &d);
        hset_make(&h, n, range, pc, d);
        memcpy(lab0, h.la, (size_t)n);
        l = h_line(&h);
        memcpy(&lb, &l, sizeof lb);
        need = irand(0, 1) ? 0 : irand(1, n + 2);
        cb = claim_scalar(&h.kb, h.lb, &lb, tag, need);
        for (v = 0; v <= host_avx2(); v++) { /* SSE2, AVX2 */
            memcpy(h.la, lab0, (size_t)n);
            H_AVX2(h.ka, v);
            ca = claim(&h.ka, h.la, &l, tag, need);
            snprintf(msg, sizeof msg, "claim trial %d (%s): n %d, need %d, counts %d / %d", t,
                     v ? "AVX2" : "SSE2", n, need, ca, cb);
            if (ca == cb) {
                if (n)
                    TEST_ASSERT_EQUAL_MEMORY_MESSAGE(h.lb, h.la, (size_t)n, msg);
            } else { /* an early exit: both below need */
                TEST_ASSERT_TRUE_MESSAGE(need > 0 && ca < need && cb < need, msg);
            }
        }
    }
}

static void h_check_sums(const qsums *a, const qsums_scalar *b, const char *msg)
{
    TEST_ASSERT_TRUE_MESSAGE(a->n == b->n && a->sx == b->sx && a->sy == b->sy &&
                                 a->sxx == b->sxx && a->sxy == b->sxy && a->syy == b->syy,
                             msg);
}

/* walk_all and walk_near (the sample runs' sums) against walk_sums. */
static void test_simd_walks(void)
{
    int t, trials = TU_TRIALS(4000, 40);
    char msg[120];
    tu_seed(22);
    for (t = 0; t < trials; t++) {
        hset h;
        qsums sa;
        qsums_scalar sb, sr;
        int n, range, i, nfree = 0, m, start, e1a = -1, e2a = -1, e1b = -1, e2b = -1, small, q, v;
        double pc;
        float d;
        h_params(t, &n, &range, &pc, &d);
        if (pc > 0.97)
            pc = 0.97;
        hset_make(&h, n, range, pc, d);
        for (i = 0; i < n; i++)
            nfree += !h.la[i];
        if (nfree == 0)
            continue;
        m = irand(1, nfree);
        start = irand(0, n - 1);
        v = irand(0, host_avx2()); /* walk_near's loops: SSE2 or AVX2 */
        H_AVX2(h.ka, v);
        small = walk_all(&h.ka, h.la, start, m, &sa, &e1a, &e2a);
        TEST_ASSERT_EQUAL_INT(small, walk_all_scalar(&h.kb, h.lb, start, m, &sb, &e1b, &e2b));
        walk_sums_scalar(&h.kb, h.lb, start, m, NULL, &sr);
        snprintf(msg, sizeof msg, "walk trial %d (%s): n %d, m %d, start %d, ext %d", t,
                 v ? "AVX2" : "SSE2", n, m, start, h.ka.ext);
        h_check_sums(&sa, &sb, msg);
        h_check_sums(&sa, &sr, msg);
        if (!small)
            continue;
        /* SSE2 may end a walk past claimed points only */
        TEST_ASSERT_TRUE_MESSAGE(e1a >= e1b && e1a <= n && e2a >= e2b && e2a <= start, msg);
        for (i = e1b; i < e1a; i++)
            TEST_ASSERT_TRUE_MESSAGE(h.la[i] != 0, msg);
        for (i = e2b; i < e2a; i++)
            TEST_ASSERT_TRUE_MESSAGE(h.la[i] != 0, msg);
        for (q = 0; q < 4; q++) {
            qline l = h_line(&h);
            qline_scalar lb;
            qsums na = sa;
            qsums_scalar nb = sb;
            memcpy(&lb, &l, sizeof lb);
            walk_near(&h.ka, h.la, start, e1a, e2a, &l, &na);
            walk_near_scalar(&h.kb, h.lb, start, e1b, e2b, &lb, &nb);
            walk_sums_scalar(&h.kb, h.lb, start, m, &lb, &sr);
            h_check_sums(&na, &nb, msg);
            h_check_sums(&na, &sr, msg);
        }
    }
}

/* A quad for quad_inliers: random corners around the points, integer ones
 * (exact ties between sides, points at exactly d), two equal corners, or
 * a NaN or infinite corner (NaN projections: not reached by the fit,
 * whose corners are finite, but the lanes must agree there too). */
static void h_quad(const hset *h, qquad *q)
{
    int j, kind = irand(0, 4);
    float w = h->ka.bw + 4.0f, hh = h->ka.bh + 4.0f;
    memset(q, 0, sizeof *q);
    for (j = 0; j < 4; j++) {
        if (kind == 0) {
            q->x[j] = (float)(urand() * w) - 2.0f;
            q->y[j] = (float)(urand() * hh) - 2.0f;
        } else {
            q->x[j] = (float)irand(-2, (int)w);
            q->y[j] = (float)irand(-2, (int)hh);
        }
    }
    if (kind == 2) { /* an axis-parallel rectangle */
        q->x[1] = q->x[2];
        q->y[1] = q->y[0];
        q->x[3] = q->x[0];
        q->y[3] = q->y[2];
    }
    if (kind == 3)
        q->x[1] = q->x[0], q->y[1] = q->y[0];
    if (kind == 4) {
        j = irand(0, 3);
        if (irand(0, 1))
            q->x[j] = NAN;
        else
            q->y[j] = irand(0, 1) ? INFINITY : -INFINITY;
    }
}

#ifdef QUAD_SSE2
/* inliers_sse2's (avx2: inliers_avx2's) count and per-side extremes of
 * t against inlier_side's, over the points it covered. */
static void h_extremes(const hset *h, const qquad *q, int avx2, const char *msg)
{
    float ax[4], ay[4], ux[4], uy[4], len[4], lo[4], hi[4], slo[4], shi[4];
    int j, i, cnt = 0, scnt = 0, end, lanes = avx2 ? 8 : 4;
    for (j = 0; j < 4; j++) {
        int j1 = (j + 1) & 3;
        float ex = q->x[j1] - q->x[j], ey = q->y[j1] - q->y[j];
        float ln = actag_sqrtf(ex * ex + ey * ey);
        ax[j] = q->x[j];
        ay[j] = q->y[j];
        ux[j] = ln > 0.0f ? ex / ln : 0.0f;
        uy[j] = ln > 0.0f ? ey / ln : 0.0f;
        len[j] = lo[j] = slo[j] = ln;
        hi[j] = shi[j] = 0.0f;
    }
#ifdef QUAD_AVX2
    if (avx2)
        end = inliers_avx2(&h->ka, ax, ay, ux, uy, len, lo, hi, 0, &cnt);
    else
#endif
        end = inliers_sse2(&h->ka, ax, ay, ux, uy, len, lo, hi, 0, &cnt);
    TEST_ASSERT_EQUAL_INT_MESSAGE(h->n - h->n % lanes, end, msg);
    for (i = 0; i < end; i++) {
        float best = h->ka.d2, bt = 0.0f;
        int bj = -1;
        for (j = 0; j < 4; j++)
            inlier_side_scalar(h->fx[i], h->fy[i], ax[j], ay[j], ux[j], uy[j], len[j],
                               ux[j] * len[j], uy[j] * len[j], j, &best, &bj, &bt);
        if (bj < 0)
            continue;
        scnt++;
        slo[bj] = bt < slo[bj] ? bt : slo[bj];
        shi[bj] = bt > shi[bj] ? bt : shi[bj];
    }
    TEST_ASSERT_EQUAL_INT_MESSAGE(scnt, cnt, msg);
    for (j = 0; j < 4; j++) { /* equal values (a zero's sign may differ) */
        TEST_ASSERT_TRUE_MESSAGE(lo[j] == slo[j] || (lo[j] != lo[j] && slo[j] != slo[j]), msg);
        TEST_ASSERT_TRUE_MESSAGE(hi[j] == shi[j] || (hi[j] != hi[j] && shi[j] != shi[j]), msg);
    }
}
#endif

static void test_simd_inliers(void)
{
    int t, trials = TU_TRIALS(3000, 30);
    char msg[140];
    tu_seed(23);
    for (t = 0; t < trials; t++) {
        hset h;
        qquad q;
        qquad_scalar qb;
        int n, range, need, ca, cb, spa, spb = -1, v;
        double pc;
        float d;
        h_params(t, &n, &range, &pc, &d);
        if (range > 3000)
            range = 3000; /* points near the quad */
        hset_make(&h, n, range, 0.0, d * (float)irand(1, 3));
        h_quad(&h, &q);
        memcpy(&qb, &q, sizeof qb);
        need = irand(0, 1) ? 0 : irand(0, n + 1);
        cb = quad_inliers_scalar(&h.kb, &qb, &spb, need);
        for (v = 0; v <= host_avx2(); v++) { /* SSE2, AVX2 */
            H_AVX2(h.ka, v);
            spa = -1;
            ca = quad_inliers(&h.ka, &q, &spa, need);
            snprintf(msg, sizeof msg,
                     "inliers trial %d (%s): n %d, need %d, counts %d / %d, span %d / %d", t,
                     v ? "AVX2" : "SSE2", n, need, ca, cb, spa, spb);
            TEST_ASSERT_TRUE_MESSAGE((ca >= need) == (cb >= need), msg);
            if (ca >= need) {
                TEST_ASSERT_EQUAL_INT_MESSAGE(cb, ca, msg);
                TEST_ASSERT_EQUAL_INT_MESSAGE(spb, spa, msg);
            }
#ifdef QUAD_SSE2
            h_extremes(&h, &q, v, msg);
#endif
        }
    }
}

static void test_edge_cases(void)
{
    /* The fewest points, a single repeated point, a straight line, a
     * two-pixel-wide sliver, points at the int16 limits. */
    actag_quad_params p;
    int n, i;
    actag_quad_params_default(&p);
    for (n = 0; n < 20; n++) {
        for (i = 0; i < n; i++) {
            g_pts[i].x = 5;
            g_pts[i].y = -3;
        }
        compare(g_pts, n, &p, 1, "repeated point", n);
        for (i = 0; i < n; i++) {
            g_pts[i].x = (int16_t)i;
            g_pts[i].y = (int16_t)(i / 3);
        }
        compare(g_pts, n, &p, 2, "line", n);
    }
    for (n = 8; n < 400; n += 17) {
        for (i = 0; i < n; i++) {
            g_pts[i].x = (int16_t)(i < n / 2 ? i : n - i);
            g_pts[i].y = (int16_t)(i < n / 2 ? 0 : 1);
        }
        compare(g_pts, n, &p, 3, "sliver", n);
    }
    n = 0;
    for (i = 0; i < 300; i++) {
        g_raw[n].x = (int16_t)(i % 2 ? 32767 : -32768);
        g_raw[n].y = (int16_t)(i % 3 ? 32767 : -32768);
        n++;
    }
    compare(g_raw, n, &p, 4, "int16 limits", 0);
}

int main(void)
{
    /* say which loops the SIMD tests compare: on a machine without AVX2
     * only the SSE2 ones run (no silent pass) */
#if defined(__SSE2__) && !defined(ACTAG_NO_SIMD)
    printf("test_quad_paths: SIMD loops compared with the plain C: SSE2%s\n",
           host_avx2() ? " and AVX2" : " (no AVX2 on this processor or build)");
#else
    printf("test_quad_paths: no x86 SIMD in this build: the SIMD tests compare the plain C with itself\n");
#endif
    UNITY_BEGIN();
    RUN_TEST(test_chains_around_quads);
    RUN_TEST(test_random_walk_blobs);
    RUN_TEST(test_not_chains);
    RUN_TEST(test_large_quads);
    RUN_TEST(test_edge_cases);
    RUN_TEST(test_simd_claim);
    RUN_TEST(test_simd_walks);
    RUN_TEST(test_simd_inliers);
    return UNITY_END();
}
