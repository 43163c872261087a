/* The texture test (src/texture.h): actag__texture_contrast against a
 * brute-force reference in double written here (its own affine map, cell
 * means, background pairs and a sorted median), on random frames and
 * quads, and at its edges: flat backgrounds, cells leaving the frame, too
 * few pairs, bad input; and what it is for: a tag on speckle stands out,
 * the speckle itself does not. */
#include "unity.h"
#include "test_util.h"

#include "../src/texture.h"

#include <math.h>

void setUp(void) {}
void tearDown(void) {}

#define RW 96
#define CL 112
#define OUT 4 /* background cells beyond the data ring */

static uint8_t img[RW * CL];
static int ref_pairs; /* the background pairs ref_contrast counted last */

/* -1: unjudged; *near set: a sample lies within 5e-5 px of the frame's limit,
 * where float and double may disagree (the case is skipped) */
static double ref_sample(const uint8_t *g, int rows, int cols, double x, double y, int *near)
{
    int x0, y0;
    double fx, fy;
    const uint8_t *a;
    if (fabs(x) < 5e-5 || fabs(y) < 5e-5 || fabs(x - (cols - 1)) < 5e-5 ||
        fabs(y - (rows - 1)) < 5e-5)
        *near = 1;
    if (!(x >= 0.0 && y >= 0.0 && x < cols - 1 && y < rows - 1))
        return -1.0;
    x0 = (int)floor(x);
    y0 = (int)floor(y);
    fx = x - x0;
    fy = y - y0;
    a = g + (size_t)y0 * (size_t)cols + (size_t)x0;
    return (1 - fy) * ((1 - fx) * a[0] + fx * a[1]) + fy * ((1 - fx) * a[cols] + fx * a[cols + 1]);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* The texture contrast by definition (texture.h), in double; *near as
 * above. The affine map: the least-squares fit of the four corners to the
 * white square's grid corners (2,2), (k-1,2), (k-1,k-1), (2,k-1), which
 * for a square's corners is the mean of opposite sides. */
static double ref_contrast(const uint8_t *g, int rows, int cols, const actag_point q[4], int bits,
                           int *near)
{
    int k = bits / 4, n = k + 1 + 2 * OUT, cx, cy, i, nr = 0, nw = 0, np = 0;
    double ux, uy, vx, vy, ox, oy, side = k - 3, m[17][17], sr = 0, sw = 0, d2[600];
    *near = 0;
    if (bits < 16 || bits > 32 || bits % 4)
        return -1.0;
    for (i = 0; i < 4; i++)
        if (!(q[i].x == q[i].x && q[i].y == q[i].y))
            return -1.0;
    ux = ((q[1].x - q[0].x) + (q[2].x - q[3].x)) / 2 / side;
    uy = ((q[1].y - q[0].y) + (q[2].y - q[3].y)) / 2 / side;
    vx = ((q[3].x - q[0].x) + (q[2].x - q[1].x)) / 2 / side;
    vy = ((q[3].y - q[0].y) + (q[2].y - q[1].y)) / 2 / side;
    /* the corners' mean is the grid's centre (k+1)/2 */
    ox = (q[0].x + q[1].x + q[2].x + q[3].x) / 4 - ux * (k + 1) / 2.0 - vx * (k + 1) / 2.0;
    oy = (q[0].y + q[1].y + q[2].y + q[3].y) / 4 - uy * (k + 1) / 2.0 - vy * (k + 1) / 2.0;
    for (cy = 0; cy < n; cy++)
        for (cx = 0; cx < n; cx++) {
            double s = 0, u, v;
            int a, b, out = 0;
            for (b = 0; b < 3; b++)
                for (a = 0; a < 3; a++) {
                    double p;
                    u = cx - OUT + (2 * a + 1) / 6.0;
                    v = cy - OUT + (2 * b + 1) / 6.0;
                    p = ref_sample(g, rows, cols, ox + ux * u + vx * v, oy + uy * u + vy * v, near);
                    if (p < 0)
                        out = 1;
                    s += p;
                }
            m[cy][cx] = out ? -1.0 : s / 9;
        }
    for (cy = 0; cy < n; cy++)
        for (cx = 0; cx < n; cx++) {
            int gx = cx - OUT, gy = cy - OUT;
            int tag = gx >= -1 && gx <= k + 1 && gy >= -1 && gy <= k + 1;
            if (tag) {
                if (gx < 1 || gx > k - 1 || gy < 1 || gy > k - 1)
                    continue;
                if (m[cy][cx] < 0)
                    return -1.0;
                if (gx == 1 || gx == k - 1 || gy == 1 || gy == k - 1) {
                    sr += m[cy][cx];
                    nr++;
                } else {
                    sw += m[cy][cx];
                    nw++;
                }
                continue;
            }
            if (m[cy][cx] < 0)
                continue;
            /* the right and lower neighbours, when background and in the frame */
            if (cx + 1 < n && !(gx + 1 >= -1 && gx + 1 <= k + 1 && gy >= -1 && gy <= k + 1) &&
                m[cy][cx + 1] >= 0)
                d2[np++] = (m[cy][cx] - m[cy][cx + 1]) * (m[cy][cx] - m[cy][cx + 1]);
            if (cy + 1 < n && !(gx >= -1 && gx <= k + 1 && gy + 1 >= -1 && gy + 1 <= k + 1) &&
                m[cy + 1][cx] >= 0)
                d2[np++] = (m[cy][cx] - m[cy + 1][cx]) * (m[cy][cx] - m[cy + 1][cx]);
        }
    ref_pairs = np;
    if (np < ACTAG__TEXTURE_MIN_PAIRS || !nr || !nw)
        return -1.0;
    qsort(d2, (size_t)np, sizeof d2[0], cmp_double);
    if (!(d2[np / 2] > 0))
        return -1.0;
    return (sw / nw - sr / nr) / sqrt(d2[np / 2] / (2 * 0.4549364));
}

static void fill_noise(int lo, int hi)
{
    int i;
    for (i = 0; i < RW * CL; i++)
        img[i] = (uint8_t)tu_range(lo, hi);
}

/* A tag's cells drawn axis-aligned: white square corners at (x0, y0) and
 * (x0 + 3c, y0 + 3c) for 24 bits (cells of c px; the grid's cell 0 starts
 * at x0 - 2c); ring 10, interior 200, data cells 10 or 200 at random. */
static void draw_tag24(int x0, int y0, int c)
{
    int cx, cy, x, y;
    for (cy = 0; cy <= 6; cy++)
        for (cx = 0; cx <= 6; cx++) {
            int v = (cx == 0 || cy == 0 || cx == 6 || cy == 6) ? (tu_range(0, 1) ? 200 : 10)
                    : (cx == 1 || cy == 1 || cx == 5 || cy == 5) ? 10
                                                                  : 200;
            for (y = 0; y < c; y++)
                for (x = 0; x < c; x++) {
                    int px = x0 - 2 * c + cx * c + x, py = y0 - 2 * c + cy * c + y;
                    if (px >= 0 && py >= 0 && px < CL && py < RW)
                        img[py * CL + px] = (uint8_t)v;
                }
        }
}

/* The white square of draw_tag24 as corners, tag order, pixel centres:
 * the square spans pixels x0 .. x0 + 3c - 1, its corners' edges lie half a
 * pixel outside the first and last pixel centres. */
static void square_of(int x0, int y0, int c, actag_point q[4])
{
    float a = (float)x0 - 0.5f, b = (float)y0 - 0.5f, s = (float)(3 * c);
    q[0].x = a;
    q[0].y = b;
    q[1].x = a + s;
    q[1].y = b;
    q[2].x = a + s;
    q[2].y = b + s;
    q[3].x = a;
    q[3].y = b + s;
}

static void test_matches_the_reference_on_random_frames_and_quads(void)
{
    static const int bitss[5] = {16, 20, 24, 28, 32};
    int t, judged = 0, skipped = 0, n = 3000 / TU_STEP(10);
    tu_seed(101);
    for (t = 0; t < n; t++) {
        actag_point q[4];
        int bits = bitss[tu_range(0, 4)], i, near;
        double cxm = tu_uniform(-10, CL + 10), cym = tu_uniform(-10, RW + 10);
        double size = tu_uniform(3, 30), ang = tu_uniform(0, 6.2832);
        float got;
        double want;
        if (t % 50 == 0) { /* a new frame: noise, smooth or banded */
            int mode = tu_range(0, 2), x, y;
            fill_noise(0, 255);
            if (mode == 1)
                for (y = 0; y < RW; y++)
                    for (x = 1; x < CL; x++)
                        img[y * CL + x] = (uint8_t)((img[y * CL + x] + 3 * img[y * CL + x - 1]) / 4);
            if (mode == 2)
                for (y = 0; y < RW; y++)
                    for (x = 0; x < CL; x++)
                        img[y * CL + x] = (uint8_t)((y / 8) % 2 ? img[y * CL + x] / 8 : img[y * CL + x]);
        }
        for (i = 0; i < 4; i++) { /* a jittered square, turned (still convex) */
            double a = ang + i * 1.5708, j = size * 0.1;
            q[i].x = (float)(cxm + size * 0.7071 * cos(a) + tu_uniform(-j, j));
            q[i].y = (float)(cym + size * 0.7071 * sin(a) + tu_uniform(-j, j));
        }
        want = ref_contrast(img, RW, CL, q, bits, &near);
        got = actag__texture_contrast(img, RW, CL, q, bits);
        if (near) {
            skipped++;
            continue;
        }
        if (want == -1.0) {
            TEST_ASSERT_TRUE_MESSAGE(got == ACTAG__TEXTURE_UNJUDGED, "reference: unjudged");
            continue;
        }
        judged++;
        TEST_ASSERT_TRUE_MESSAGE(got != ACTAG__TEXTURE_UNJUDGED, "reference: judged");
        TEST_ASSERT_FLOAT_WITHIN_MESSAGE(1e-3f + 1e-3f * (float)fabs(want), (float)want, got,
                                         "texture contrast");
    }
    /* both kinds happened, and few cases sat on a frame limit */
    TEST_ASSERT_TRUE(judged > n / 5);
    TEST_ASSERT_TRUE(judged < n - n / 10);
    TEST_ASSERT_TRUE(skipped < n / 20);
}

static void test_a_tag_stands_out_and_the_speckle_does_not(void)
{
    actag_point q[4];
    int t, worst_i = 0;
    float worst = -1e30f, r;
    tu_seed(7);
    fill_noise(20, 60);
    draw_tag24(50, 40, 5);
    square_of(50, 40, 5, q);
    r = actag__texture_contrast(img, RW, CL, q, 24);
    TEST_ASSERT_TRUE_MESSAGE(r > 50.0f && r != ACTAG__TEXTURE_UNJUDGED, "a tag on speckle");
    /* the same grid anywhere on the noise alone: never above the default */
    fill_noise(20, 60);
    for (t = 0; t < 300; t++) {
        int x0 = tu_range(0, CL - 15), y0 = tu_range(0, RW - 15);
        square_of(x0, y0, tu_range(2, 6), q);
        r = actag__texture_contrast(img, RW, CL, q, 24);
        if (r != ACTAG__TEXTURE_UNJUDGED && r > worst) {
            worst = r;
            worst_i = t;
        }
    }
    (void)worst_i;
    TEST_ASSERT_TRUE_MESSAGE(worst > -1e30f, "some placements were judged");
    TEST_ASSERT_TRUE_MESSAGE(worst < ACTAG_MIN_TEXTURE_CONTRAST, "noise read as standing out");
}

static void test_unjudged_cases(void)
{
    actag_point q[4];
    int i;
    /* a flat background: no texture to compare with */
    memset(img, 50, sizeof img);
    draw_tag24(50, 40, 5);
    square_of(50, 40, 5, q);
    TEST_ASSERT_EQUAL_FLOAT(ACTAG__TEXTURE_UNJUDGED, actag__texture_contrast(img, RW, CL, q, 24));
    /* texture again: judged */
    tu_seed(3);
    fill_noise(0, 40);
    draw_tag24(50, 40, 5);
    TEST_ASSERT_TRUE(actag__texture_contrast(img, RW, CL, q, 24) < ACTAG__TEXTURE_UNJUDGED);
    /* a ring cell out of the frame (the square at the left edge) */
    square_of(3, 40, 5, q);
    TEST_ASSERT_EQUAL_FLOAT(ACTAG__TEXTURE_UNJUDGED, actag__texture_contrast(img, RW, CL, q, 24));
    /* a tag filling the frame: its background outside it */
    square_of(CL / 2 - 30, RW / 2 - 30, 20, q);
    TEST_ASSERT_EQUAL_FLOAT(ACTAG__TEXTURE_UNJUDGED, actag__texture_contrast(img, RW, CL, q, 24));
    /* bad input: a crossed quad (no grid map), NULL, bits */
    square_of(50, 40, 5, q);
    {
        actag_point s = q[1];
        q[1] = q[2];
        q[2] = s;
        TEST_ASSERT_EQUAL_FLOAT(ACTAG__TEXTURE_UNJUDGED, actag__texture_contrast(img, RW, CL, q, 24));
        q[2] = q[1];
        q[1] = s;
    }
    TEST_ASSERT_EQUAL_FLOAT(ACTAG__TEXTURE_UNJUDGED, actag__texture_contrast(NULL, RW, CL, q, 24));
    TEST_ASSERT_EQUAL_FLOAT(ACTAG__TEXTURE_UNJUDGED, actag__texture_contrast(img, RW, CL, NULL, 24));
    TEST_ASSERT_EQUAL_FLOAT(ACTAG__TEXTURE_UNJUDGED, actag__texture_contrast(img, RW, CL, q, 18));
    TEST_ASSERT_EQUAL_FLOAT(ACTAG__TEXTURE_UNJUDGED, actag__texture_contrast(img, RW, CL, q, 12));
    TEST_ASSERT_EQUAL_FLOAT(ACTAG__TEXTURE_UNJUDGED, actag__texture_contrast(img, RW, CL, q, 36));
    for (i = 0; i < 4; i++) {
        actag_point s = q[i];
        q[i].x = NAN;
        TEST_ASSERT_EQUAL_FLOAT(ACTAG__TEXTURE_UNJUDGED, actag__texture_contrast(img, RW, CL, q, 24));
        q[i] = s;
        q[i].y = INFINITY;
        TEST_ASSERT_EQUAL_FLOAT(ACTAG__TEXTURE_UNJUDGED, actag__texture_contrast(img, RW, CL, q, 24));
        q[i] = s;
    }
}

/* Where the pairs run out: a tag near the top-left corner of frames 37 to
 * 64 rows high and 36 to 64 columns wide, so that its background grows
 * from nothing, a row or column of cells at a time, below and to the
 * right: judged exactly when the reference counts at least
 * ACTAG__TEXTURE_MIN_PAIRS pairs. Those steps skip the boundary itself,
 * so two 20-bit placements found by a search over offsets and frame
 * sizes give exactly ACTAG__TEXTURE_MIN_PAIRS - 1 and
 * ACTAG__TEXTURE_MIN_PAIRS pairs (an off-by-one in the rule fails). */
static void check_placement(uint8_t *f, int rows, int cols, int x0, int y0, int bits, int *pairs)
{
    actag_point q[4];
    int i, near;
    double want;
    float got;
    for (i = 0; i < rows * cols; i++)
        f[i] = (uint8_t)tu_range(0, 60);
    for (i = 0; i < 12 * 12; i++) /* a bright white square */
        f[(y0 + i / 12) * cols + x0 + i % 12] = 200;
    square_of(x0, y0, 4, q);
    ref_pairs = 0;
    want = ref_contrast(f, rows, cols, q, bits, &near);
    got = actag__texture_contrast(f, rows, cols, q, bits);
    *pairs = near ? -1 : ref_pairs;
    if (near)
        return;
    if (want == -1.0) {
        TEST_ASSERT_EQUAL_FLOAT(ACTAG__TEXTURE_UNJUDGED, got);
    } else {
        TEST_ASSERT_TRUE(ref_pairs >= ACTAG__TEXTURE_MIN_PAIRS);
        TEST_ASSERT_FLOAT_WITHIN(1e-3f + 1e-3f * (float)fabs(want), (float)want, got);
    }
}

static void test_the_least_pairs_boundary(void)
{
    static uint8_t f[64 * 64];
    int rows, cols, pairs, judged = 0, unjudged = 0;
    tu_seed(5);
    for (rows = 37; rows <= 64; rows++)
        for (cols = 36; cols <= 64; cols++) {
            check_placement(f, rows, cols, 12, 12, 24, &pairs);
            judged += pairs >= ACTAG__TEXTURE_MIN_PAIRS;
            unjudged += pairs >= 0 && pairs < ACTAG__TEXTURE_MIN_PAIRS;
        }
    TEST_ASSERT_TRUE(judged > 0 && unjudged > 0);
    /* exactly at the boundary: 15 pairs unjudged, 16 judged */
    check_placement(f, 54, 48, 12, 18, 20, &pairs);
    TEST_ASSERT_EQUAL_INT(ACTAG__TEXTURE_MIN_PAIRS - 1, pairs);
    check_placement(f, 38, 50, 8, 8, 20, &pairs);
    TEST_ASSERT_EQUAL_INT(ACTAG__TEXTURE_MIN_PAIRS, pairs);
    {
        actag_point q[4];
        square_of(8, 8, 4, q);
        TEST_ASSERT_TRUE(actag__texture_contrast(f, 38, 50, q, 20) != ACTAG__TEXTURE_UNJUDGED);
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_matches_the_reference_on_random_frames_and_quads);
    RUN_TEST(test_a_tag_stands_out_and_the_speckle_does_not);
    RUN_TEST(test_unjudged_cases);
    RUN_TEST(test_the_least_pairs_boundary);
    return UNITY_END();
}
