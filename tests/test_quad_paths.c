/* actag_quad_fit's fast paths (src/quad.c without ACTAG_QUAD_REFERENCE:
 * skipping along chains (ACTAG_QUAD_FORCE_SKIP, as on targets without a
 * vector unit), early exits from the counts) against its reference
 * loops (the same file compiled in here with ACTAG_QUAD_REFERENCE, under
 * another name): the same return code, the same bytes of actag_quad and the
 * same generator state afterwards, on random contours of many kinds: noisy
 * chains around parallelograms (most fit), random-walk blobs, polygons with
 * spikes, chains far from the origin or at negative coordinates, point sets
 * that are not chains (the fast paths must fall back), with random
 * parameters. */
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

/* The skipping claim loop, which the library uses only on targets without
 * a vector unit: compiled in a second time, every name renamed. */
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
    int rca, rcb;
    char msg[160];
    actag_rng_seed(&rb, seed);
    memset(&qb, 0x5a, sizeof qb);
    int v;
    rcb = actag_quad_fit_reference(pts, n, p, &rb, g_scratch, ACTAG_QUAD_SCRATCH_SIZE(n), &qb);
    for (v = 0; v < 2; v++) { /* the library, the skipping build */
        actag_rng_seed(&ra, seed);
        memset(&qa, 0x5a, sizeof qa);
        rca = (v ? actag_quad_fit_skip : actag_quad_fit)(pts, n, p, &ra, g_scratch,
                                                         ACTAG_QUAD_SCRATCH_SIZE(n), &qa);
        snprintf(msg, sizeof msg, "%s, %s trial %d: n %d, d %g, iterations %d / %d",
                 v ? "skipping" : "library", what, trial, n, (double)p->inlier_distance,
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
    UNITY_BEGIN();
    RUN_TEST(test_chains_around_quads);
    RUN_TEST(test_random_walk_blobs);
    RUN_TEST(test_not_chains);
    RUN_TEST(test_large_quads);
    RUN_TEST(test_edge_cases);
    return UNITY_END();
}
