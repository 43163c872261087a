/* The physical size filter and the first guesses of a blob's grid
 * (src/size_filter.h): each rule at its exact boundary, on a geometry whose
 * steps are exact in float (1 m a row; 1 m a column at 64 m), and against
 * references written here on random input. */
#include "unity.h"
#include "test_util.h"

#include "../src/search_box.h"
#include "../src/size_filter.h"

#include <math.h>

void setUp(void) {}
void tearDown(void) {}

/* 129 rows of 1 m from 128 m (row 0) to 0 m (row 128); 101 beams over
 * 100/64 rad, 1/64 rad apart: at row 64 (64 m) a beam is 1 m wide. */
#define ROWS 129
#define COLS 101
static const actag_sonar_geometry G = {0.0f, 128.0f, 1.5625f, NULL, 0u};

static actag_family fam24;

/* Parameters whose size rules give exact float bounds: a tag whose white
 * square's diagonal is 8 m (8 rows, 8 beams at 64 m), size tolerance 0.25,
 * area fractions 0.25 and 1. */
static actag_params exact_params(void)
{
    actag_params p;
    float t = 8.0f / 1.41421356f;
    int i;
    actag_params_default(&p);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam24));
    p.family = &fam24;
    /* the float nearest 8 / sqrt(2) whose product with the filter's
     * 1.41421356f is 8 exactly */
    for (i = 0; i < 8 && t * 1.41421356f != 8.0f; i++)
        t = nextafterf(t, t * 1.41421356f < 8.0f ? 100.0f : 0.0f);
    TEST_ASSERT_TRUE_MESSAGE(t * 1.41421356f == 8.0f, "no tag size with a diagonal of exactly 8");
    p.tag_size = t;
    p.tuning.size_tolerance = 0.25f;
    p.tuning.min_area_fraction = 0.25f;
    p.tuning.max_area_fraction = 1.0f;
    return p;
}

/* A contour's description: bounding box x0..x1, y0..y1 (inclusive), area. */
static actag_contour_info box(int x0, int x1, int y0, int y1, float area)
{
    actag_contour_info ci;
    memset(&ci, 0, sizeof ci);
    ci.min_x = x0;
    ci.max_x = x1;
    ci.min_y = y0;
    ci.max_y = y1;
    ci.area = area;
    ci.npoints = ci.stored = 4;
    return ci;
}

static void test_the_geometry_is_exact(void)
{
    /* the premises of the boundary tests below */
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_geometry_validate(&G, ROWS, COLS, NULL));
    TEST_ASSERT_TRUE(actag_geometry_range_step(&G, ROWS) == 1.0f);
    TEST_ASSERT_TRUE(actag_geometry_range(&G, ROWS, 64.0f) == 64.0f);
    TEST_ASSERT_TRUE(actag_geometry_range(&G, ROWS, 63.5f) == 64.5f);
    TEST_ASSERT_TRUE(actag_geometry_azimuth_step(&G, COLS, 50.0f) == 0.015625f);
    TEST_ASSERT_TRUE(actag_geometry_azimuth_step(&G, COLS, 49.5f) == 0.015625f);
}

static void test_size_plausible_at_its_bounds(void)
{
    actag_params p = exact_params();
    actag_contour_info ci;
    /* range extent: at most 8 x 1.25 = 10 rows (centre row 63.5; 5 beams) */
    ci = box(48, 52, 59, 68, 40.0f);
    TEST_ASSERT_EQUAL_INT(1, actag__size_plausible(&ci, &G, &p, ROWS, COLS));
    ci = box(48, 52, 58, 68, 40.0f); /* 11 rows */
    TEST_ASSERT_EQUAL_INT(0, actag__size_plausible(&ci, &G, &p, ROWS, COLS));
    /* azimuth extent: at most 10 beams at 64 m (centre row 64; 5 rows) */
    ci = box(45, 54, 62, 66, 40.0f);
    TEST_ASSERT_EQUAL_INT(1, actag__size_plausible(&ci, &G, &p, ROWS, COLS));
    ci = box(45, 55, 62, 66, 40.0f);
    TEST_ASSERT_EQUAL_INT(0, actag__size_plausible(&ci, &G, &p, ROWS, COLS));
    /* area: within [0.25 x 0.75, 1 x 1.25] x 64 = [12, 80] pixels^2 */
    ci = box(48, 52, 62, 66, 12.0f);
    TEST_ASSERT_EQUAL_INT(1, actag__size_plausible(&ci, &G, &p, ROWS, COLS));
    ci.area = nextafterf(12.0f, 0.0f);
    TEST_ASSERT_EQUAL_INT(0, actag__size_plausible(&ci, &G, &p, ROWS, COLS));
    ci.area = 80.0f;
    TEST_ASSERT_EQUAL_INT(1, actag__size_plausible(&ci, &G, &p, ROWS, COLS));
    ci.area = nextafterf(80.0f, 1000.0f);
    TEST_ASSERT_EQUAL_INT(0, actag__size_plausible(&ci, &G, &p, ROWS, COLS));
    /* the tolerance widens both: 0.5 gives 12 rows and 8 pixels^2 */
    p.tuning.size_tolerance = 0.5f;
    ci = box(48, 52, 58, 69, 8.0f);
    TEST_ASSERT_EQUAL_INT(1, actag__size_plausible(&ci, &G, &p, ROWS, COLS));
    /* no azimuth step where the range is 0 (the last row): refused, though
     * the box would pass with the tolerance of 0.5 */
    ci = box(48, 52, 128, 128, 40.0f);
    TEST_ASSERT_EQUAL_INT(0, actag__size_plausible(&ci, &G, &p, ROWS, COLS));
}

static void test_merged_box_at_its_bounds(void)
{
    actag_params p = exact_params();
    actag_contour_info ci;
    actag_point q[4], ref[4];
    int i;
    /* too large in azimuth (more than 10 beams) but at most 2.5 x 8 = 20 */
    ci = box(40, 59, 60, 68, 100.0f);
    TEST_ASSERT_EQUAL_INT(1, actag__merged_box(&ci, &G, &p, ROWS, COLS, q));
    /* the box is the search's white square at the blob's centre */
    actag__search_box(&G, ROWS, COLS, 49.5f, 64.0f, p.tag_size, p.tuning.search_range_scale, ref,
                      NULL, NULL);
    for (i = 0; i < 4; i++) {
        TEST_ASSERT_TRUE(q[i].x == ref[i].x);
        TEST_ASSERT_TRUE(q[i].y == ref[i].y);
    }
    ci = box(40, 60, 60, 68, 100.0f); /* 21 beams */
    TEST_ASSERT_EQUAL_INT(0, actag__merged_box(&ci, &G, &p, ROWS, COLS, q));
    /* a white square's size is not a merged blob */
    ci = box(45, 54, 60, 68, 100.0f);
    TEST_ASSERT_EQUAL_INT(0, actag__merged_box(&ci, &G, &p, ROWS, COLS, q));
    /* area within [0.25, 3] x 64 = [16, 192] pixels^2 */
    ci = box(40, 59, 60, 68, 192.0f);
    TEST_ASSERT_EQUAL_INT(1, actag__merged_box(&ci, &G, &p, ROWS, COLS, q));
    ci.area = nextafterf(192.0f, 1000.0f);
    TEST_ASSERT_EQUAL_INT(0, actag__merged_box(&ci, &G, &p, ROWS, COLS, q));
    ci.area = 16.0f;
    TEST_ASSERT_EQUAL_INT(1, actag__merged_box(&ci, &G, &p, ROWS, COLS, q));
    ci.area = nextafterf(16.0f, 0.0f);
    TEST_ASSERT_EQUAL_INT(0, actag__merged_box(&ci, &G, &p, ROWS, COLS, q));
    /* too large in range: more than 10 rows, at most 20 (centre row 63.5) */
    ci = box(48, 52, 54, 73, 100.0f);
    TEST_ASSERT_EQUAL_INT(1, actag__merged_box(&ci, &G, &p, ROWS, COLS, q));
    ci = box(48, 52, 53, 73, 100.0f);
    TEST_ASSERT_EQUAL_INT(0, actag__merged_box(&ci, &G, &p, ROWS, COLS, q));
    /* only where cells are narrower than 10 beams: a 24-bit tag's cell is
     * a third of its white square, 29 / 3 = 9.7 beams at 64 m, 31 / 3 =
     * 10.3 (each blob 100 x 9 pixels, too large but within 2.5 times) */
    p.tag_size = 29.0f;
    ci = box(0, 99, 60, 68, 2000.0f);
    TEST_ASSERT_EQUAL_INT(1, actag__merged_box(&ci, &G, &p, ROWS, COLS, q));
    p.tag_size = 31.0f;
    TEST_ASSERT_EQUAL_INT(0, actag__merged_box(&ci, &G, &p, ROWS, COLS, q));
}

/* The quad (x0, y0) (x1, y0) (x1, y1) (x0, y1). */
static void rect(float x0, float y0, float x1, float y1, actag_point q[4])
{
    q[0].x = x0; q[0].y = y0;
    q[1].x = x1; q[1].y = y0;
    q[2].x = x1; q[2].y = y1;
    q[3].x = x0; q[3].y = y1;
}

/* The reference: each side in metres in double from the geometry's range
 * and azimuth of its corners; -1 when a side lies within rel of a bound
 * (float rounding may decide it either way), else 1 or 0. */
static int sides_ref(const actag_point q[4], double lo, double hi, double rel)
{
    int i, ok = 1;
    for (i = 0; i < 4; i++) {
        int j = (i + 1) & 3;
        double ri = actag_geometry_range(&G, ROWS, q[i].y), rj = actag_geometry_range(&G, ROWS, q[j].y);
        double ai = actag_geometry_azimuth(&G, COLS, q[i].x), aj = actag_geometry_azimuth(&G, COLS, q[j].x);
        double l = sqrt((ri - rj) * (ri - rj) + ((ai - aj) * 0.5 * (ri + rj)) * ((ai - aj) * 0.5 * (ri + rj)));
        if (fabs(l - lo) <= rel * lo || fabs(l - hi) <= rel * hi)
            return -1;
        if (l < lo || l > hi)
            ok = 0;
    }
    return ok;
}

static void test_sides_plausible_at_its_bounds_and_at_random(void)
{
    actag_params p = exact_params();
    actag_point q[4];
    int t, decided = 0, refused = 0;
    p.tag_size = 8.0f; /* sides within [0.5, 1.6] x 8 = [4, 12.8] m */
    /* a side along range of exactly 4 rows is 4 m: accepted */
    rect(46.0f, 62.0f, 54.0f, 66.0f, q);
    TEST_ASSERT_EQUAL_INT(1, actag__sides_plausible(q, &G, &p, ROWS, COLS));
    rect(46.0f, 62.0f, 54.0f, 65.99f, q);
    TEST_ASSERT_EQUAL_INT(0, actag__sides_plausible(q, &G, &p, ROWS, COLS));
    /* along azimuth at 64 m: 12.79 beams accepted, 12.81 not */
    rect(40.0f, 64.0f, 52.79f, 68.0f, q);
    TEST_ASSERT_EQUAL_INT(1, actag__sides_plausible(q, &G, &p, ROWS, COLS));
    rect(40.0f, 64.0f, 52.81f, 68.0f, q);
    TEST_ASSERT_EQUAL_INT(0, actag__sides_plausible(q, &G, &p, ROWS, COLS));
    /* a NaN corner is no side at all */
    rect(46.0f, 62.0f, 54.0f, 66.0f, q);
    q[2].x = NAN;
    TEST_ASSERT_EQUAL_INT(0, actag__sides_plausible(q, &G, &p, ROWS, COLS));
    /* random quads against the reference */
    tu_seed(71);
    for (t = 0; t < TU_TRIALS(3000, 10); t++) {
        /* squares of 3-14 pixels (about metres here) at any turn, each
         * corner moved by up to a pixel: about half within the bounds */
        float cx = (float)tu_range(3000, 7000) * 0.01f, cy = (float)tu_range(5000, 7800) * 0.01f;
        float h = (float)tu_range(150, 700) * 0.01f, th = (float)tu_range(0, 6283) * 0.001f;
        int i, want;
        for (i = 0; i < 4; i++) {
            float a = th + 1.5707963f * (float)i;
            q[i].x = cx + h * 1.41421356f * cosf(a) + (float)tu_range(-100, 100) * 0.01f;
            q[i].y = cy + h * 1.41421356f * sinf(a) + (float)tu_range(-100, 100) * 0.01f;
        }
        want = sides_ref(q, 4.0, 12.8, 1e-5);
        if (want < 0)
            continue;
        decided++;
        refused += want == 0;
        TEST_ASSERT_EQUAL_INT_MESSAGE(want, actag__sides_plausible(q, &G, &p, ROWS, COLS),
                                      "random quad");
    }
    /* both outcomes were tried, many times */
    TEST_ASSERT_TRUE(refused > decided / 10 && refused < decided - decided / 10);
}

/* Squared distance, in integers (exact). */
static long d2i(long x0, long y0, long x1, long y1)
{
    return (x1 - x0) * (x1 - x0) + (y1 - y0) * (y1 - y0);
}

static void check_extreme_quad(const actag_ipoint *pts, int n)
{
    actag_point q[4];
    int got = actag__extreme_quad(pts, n, q), i;
    double cx = 0.0, cy = 0.0, best = -1.0, d0;
    long x0, y0, x2, y2, dx, dy, far = -1, hi = 0, lo = 0;
    int i1 = -1, i3 = -1, i2 = -1;
    if (n < 4) {
        TEST_ASSERT_EQUAL_INT(0, got);
        return;
    }
    /* q[0]: a point (nearly) farthest from the centroid; float rounding
     * may pick another of nearly the same distance */
    for (i = 0; i < n; i++) {
        cx += pts[i].x;
        cy += pts[i].y;
    }
    cx /= n;
    cy /= n;
    for (i = 0; i < n; i++) {
        double d = (pts[i].x - cx) * (pts[i].x - cx) + (pts[i].y - cy) * (pts[i].y - cy);
        if (d > best)
            best = d;
    }
    if (!got) {
        /* only when every point lies on the line from a farthest point
         * q[0] to the first point farthest from it, or on one side of it */
        int i0, one_sided = 0;
        for (i0 = 0; i0 < n && !one_sided; i0++) {
            double d = (pts[i0].x - cx) * (pts[i0].x - cx) + (pts[i0].y - cy) * (pts[i0].y - cy);
            int pos = 0, neg = 0;
            if (d < best * (1.0 - 1e-5) - 1e-3)
                continue;
            far = -1;
            for (i = 0; i < n; i++) {
                long e = d2i(pts[i0].x, pts[i0].y, pts[i].x, pts[i].y);
                if (e > far) {
                    far = e;
                    i2 = i;
                }
            }
            dx = pts[i2].x - pts[i0].x;
            dy = pts[i2].y - pts[i0].y;
            for (i = 0; i < n; i++) {
                long c = dx * (pts[i].y - pts[i0].y) - dy * (pts[i].x - pts[i0].x);
                pos |= c > 0;
                neg |= c < 0;
            }
            one_sided = !(pos && neg);
        }
        TEST_ASSERT_TRUE_MESSAGE(one_sided, "no guess from points on both sides of the line");
        return;
    }
    x0 = (long)q[0].x;
    y0 = (long)q[0].y;
    d0 = (x0 - cx) * (x0 - cx) + (y0 - cy) * (y0 - cy);
    TEST_ASSERT_TRUE_MESSAGE(d0 >= best * (1.0 - 1e-5) - 1e-3, "q[0] is not the farthest point");
    /* q[2]: the first point farthest from q[0] (exact in float too) */
    for (i = 0; i < n; i++) {
        long d = d2i(x0, y0, pts[i].x, pts[i].y);
        if (d > far) {
            far = d;
            i2 = i;
        }
    }
    x2 = pts[i2].x;
    y2 = pts[i2].y;
    TEST_ASSERT_EQUAL_FLOAT(x2, q[2].x);
    TEST_ASSERT_EQUAL_FLOAT(y2, q[2].y);
    /* q[1] and q[3]: the first points of the largest positive and the most
     * negative cross product off the line q[0] q[2] */
    dx = x2 - x0;
    dy = y2 - y0;
    for (i = 0; i < n; i++) {
        long s = dx * (pts[i].y - y0) - dy * (pts[i].x - x0);
        if (s > hi) {
            hi = s;
            i1 = i;
        }
        if (s < lo) {
            lo = s;
            i3 = i;
        }
    }
    TEST_ASSERT_TRUE(i1 >= 0 && i3 >= 0);
    TEST_ASSERT_EQUAL_FLOAT(pts[i1].x, q[1].x);
    TEST_ASSERT_EQUAL_FLOAT(pts[i1].y, q[1].y);
    TEST_ASSERT_EQUAL_FLOAT(pts[i3].x, q[3].x);
    TEST_ASSERT_EQUAL_FLOAT(pts[i3].y, q[3].y);
}

static void test_extreme_quad_against_a_reference(void)
{
    actag_ipoint pts[64];
    int t, n, i;
    /* the corners of a square: all four, in order around it */
    static const actag_ipoint sq[5] = {{10, 10}, {20, 10}, {20, 20}, {10, 20}, {15, 15}};
    actag_point q[4];
    TEST_ASSERT_EQUAL_INT(1, actag__extreme_quad(sq, 5, q));
    check_extreme_quad(sq, 5);
    TEST_ASSERT_TRUE(q[0].x != q[2].x && q[0].y != q[2].y); /* opposite corners */
    /* a triangle's border: its third corner on one side of the line
     * through the other two, nothing on the other side: no guess */
    {
        static const actag_ipoint tri[6] = {{0, 0}, {10, 0}, {20, 0}, {10, 10}, {5, 5}, {15, 5}};
        TEST_ASSERT_EQUAL_INT(0, actag__extreme_quad(tri, 6, q));
        check_extreme_quad(tri, 6);
    }
    /* fewer than 4 points, and points on one line */
    check_extreme_quad(sq, 3);
    for (i = 0; i < 6; i++) {
        pts[i].x = (int16_t)(3 * i);
        pts[i].y = (int16_t)(2 * i + 1);
    }
    TEST_ASSERT_EQUAL_INT(0, actag__extreme_quad(pts, 6, q));
    check_extreme_quad(pts, 6);
    /* random sets: small (many ties), clustered, with repeated points */
    tu_seed(72);
    for (t = 0; t < TU_TRIALS(4000, 10); t++) {
        int span = t % 3 == 0 ? 4 : (t % 3 == 1 ? 40 : 400);
        n = tu_range(0, 64);
        for (i = 0; i < n; i++) {
            if (i > 0 && tu_range(0, 9) == 0) {
                pts[i] = pts[tu_range(0, i - 1)];
            } else {
                pts[i].x = (int16_t)tu_range(0, span);
                pts[i].y = (int16_t)tu_range(0, span);
            }
        }
        check_extreme_quad(pts, n);
    }
}

static void test_guess_on_border(void)
{
    actag_point q[4];
    int t, i;
    rect(1.0f, 1.0f, (float)COLS - 2.0f, (float)ROWS - 2.0f, q);
    TEST_ASSERT_EQUAL_INT(0, actag__guess_on_border(q, ROWS, COLS));
    /* each edge at its last pixel centre, and just inside it */
    for (i = 0; i < 4; i++) {
        actag_point r[4];
        memcpy(r, q, sizeof r);
        if (i == 0) r[0].x = 0.0f;
        if (i == 1) r[1].y = 0.0f;
        if (i == 2) r[2].x = (float)COLS - 1.0f;
        if (i == 3) r[3].y = (float)ROWS - 1.0f;
        TEST_ASSERT_EQUAL_INT(1, actag__guess_on_border(r, ROWS, COLS));
        if (i == 0) r[0].x = 0.01f;
        if (i == 1) r[1].y = 0.01f;
        if (i == 2) r[2].x = (float)COLS - 1.5f;
        if (i == 3) r[3].y = (float)ROWS - 1.5f;
        TEST_ASSERT_EQUAL_INT(0, actag__guess_on_border(r, ROWS, COLS));
    }
    /* random corners against the rule */
    tu_seed(73);
    for (t = 0; t < TU_TRIALS(2000, 10); t++) {
        int want = 0;
        for (i = 0; i < 4; i++) {
            q[i].x = (float)tu_range(-200, (COLS + 1) * 100) * 0.01f;
            q[i].y = (float)tu_range(-200, (ROWS + 1) * 100) * 0.01f;
            want |= !(q[i].x > 0.0f && q[i].y > 0.0f && q[i].x < (float)(COLS - 1) &&
                      q[i].y < (float)(ROWS - 1));
        }
        TEST_ASSERT_EQUAL_INT(want, actag__guess_on_border(q, ROWS, COLS));
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_the_geometry_is_exact);
    RUN_TEST(test_size_plausible_at_its_bounds);
    RUN_TEST(test_merged_box_at_its_bounds);
    RUN_TEST(test_sides_plausible_at_its_bounds_and_at_random);
    RUN_TEST(test_extreme_quad_against_a_reference);
    RUN_TEST(test_guess_on_border);
    return UNITY_END();
}
