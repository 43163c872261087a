/* The median's radius per range band (src/median_bands.c, actag_tuning.
 * median_per_range): the rule against a row-by-row brute force on random
 * geometries, and actag_detect's filtered frame against the plain filter at
 * each band's radius (out of place, in place, and actag_detect_multi with
 * sets of other bands). */
#include "unity.h"
#include "test_util.h"

#include "actag/actag.h"
#include "actag/geometry.h"
#include "actag/median.h"
#include "../src/median_bands.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void setUp(void) {}
void tearDown(void) {}

static float frand(float lo, float hi)
{
    return lo + (hi - lo) * (float)tu_rand() / 4294967295.0f;
}

static actag_family family_of(const char *name)
{
    actag_family f;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get(name, &f));
    return f;
}

/* The radius of row y by the rule, computed for the row alone: the largest
 * r in 2..r0 whose window, 2 r + 1 pixels, spans at most half the cell's
 * width in beams plus 2 (2 when none does; r0 when r0 < 2). */
static int brute_radius(const actag_sonar_geometry *g, int rows, int cols, const actag_params *p,
                        int y)
{
    int r0 = p->tuning.median_radius, r;
    float a0, a1, step, w, cell;
    if (!p->tuning.median_per_range || r0 < 1 || r0 > ACTAG_MEDIAN_INPLACE_MAX_RADIUS || cols < 2)
        return r0;
    a0 = actag_geometry_azimuth(g, cols, 0.0f);
    a1 = actag_geometry_azimuth(g, cols, (float)(cols - 1));
    step = fabsf(a0 - a1) / (float)(cols - 1);
    w = actag_geometry_range(g, rows, (float)y) * step;
    if (!(w > 0.0f))
        return r0;
    cell = p->tag_size / (float)(p->family->bits / 4 - 3) / w;
    if (r0 < 2)
        return r0;
    for (r = r0; r > 2; r--)
        if (2.0 * (double)r + 1.0 <= 0.5 * (double)cell + 2.0) /* exact: no float tie */
            return r;
    return 2;
}

/* b: a partition of the rows into maximal runs, each row at its brute-force
 * radius. */
static void check_rule(const actag_sonar_geometry *g, int rows, int cols, const actag_params *p)
{
    actag__median_bands b;
    int i, y = 0;
    actag__median_bands_of(g, rows, cols, p, &b);
    TEST_ASSERT_TRUE(b.n >= 1 && b.n <= ACTAG__MEDIAN_BANDS_MAX);
    TEST_ASSERT_EQUAL_INT(rows, b.end[b.n - 1]);
    for (i = 0; i < b.n; i++) {
        TEST_ASSERT_TRUE(b.end[i] > y);
        if (i > 0)
            TEST_ASSERT_TRUE(b.radius[i] != b.radius[i - 1]); /* maximal runs */
        for (; y < b.end[i]; y++)
            TEST_ASSERT_EQUAL_INT(brute_radius(g, rows, cols, p, y), b.radius[i]);
    }
}

static void test_rule_equals_brute_force(void)
{
    static const char *const names[] = {"AcTag24h10", "AcTag28m10", "AcTag24m4"};
    actag_family fams[3];
    float bearings[600];
    int k, i, trials = TU_TRIALS(400, 8);
    tu_seed(0x3ED1u);
    for (i = 0; i < 3; i++)
        fams[i] = family_of(names[i]);
    for (k = 0; k < trials; k++) {
        actag_sonar_geometry g;
        actag_params p;
        int rows = tu_range(1, 600), cols = tu_range(1, 600);
        memset(&g, 0, sizeof g);
        g.min_range = tu_range(0, 3) == 0 ? 0.0f : frand(0.0f, 2.0f);
        g.max_range = g.min_range + frand(0.1f, 20.0f);
        g.aperture = frand(0.1f, 2.5f);
        /* one draw per statement: the order of the draws is fixed */
        g.flags = tu_rand() & 1u ? ACTAG_RANGE_ASCENDING : 0;
        if (tu_rand() & 1u)
            g.flags |= ACTAG_AZIMUTH_ASCENDING;
        if (k % 4 == 3 && cols >= 2) { /* a bearing table with uneven beams */
            float a = -0.5f * g.aperture;
            for (i = 0; i < cols; i++) {
                bearings[i] = a;
                a += g.aperture / (float)cols * frand(0.5f, 1.5f);
            }
            g.bearings = bearings;
            g.flags &= ~ACTAG_AZIMUTH_ASCENDING;
        }
        actag_params_default(&p);
        p.family = &fams[k % 3];
        p.tag_size = frand(0.02f, 0.6f);
        p.tuning.median_radius = tu_range(0, 9);
        p.tuning.median_per_range = k % 5 != 0;
        check_rule(&g, rows, cols, &p);
    }
}

/* The rule's boundaries: radius r from cells of 4 r - 2 pixels, never
 * below 2 (NaN and negative widths included), never above r0, and r0
 * itself when it is below 2. */
static void test_radius_for_cell_boundaries(void)
{
    TEST_ASSERT_EQUAL_INT(2, actag__median_radius_for_cell(0.0f, 4));
    TEST_ASSERT_EQUAL_INT(2, actag__median_radius_for_cell(-5.0f, 4));
    TEST_ASSERT_EQUAL_INT(2, actag__median_radius_for_cell(NAN, 4));
    TEST_ASSERT_EQUAL_INT(2, actag__median_radius_for_cell(-INFINITY, 4));
    TEST_ASSERT_EQUAL_INT(2, actag__median_radius_for_cell(nextafterf(10.0f, 0.0f), 4));
    TEST_ASSERT_EQUAL_INT(3, actag__median_radius_for_cell(10.0f, 4));
    TEST_ASSERT_EQUAL_INT(3, actag__median_radius_for_cell(nextafterf(14.0f, 0.0f), 4));
    TEST_ASSERT_EQUAL_INT(4, actag__median_radius_for_cell(14.0f, 4));
    TEST_ASSERT_EQUAL_INT(4, actag__median_radius_for_cell(1e30f, 4));
    TEST_ASSERT_EQUAL_INT(4, actag__median_radius_for_cell(INFINITY, 4));
    TEST_ASSERT_EQUAL_INT(7, actag__median_radius_for_cell(26.0f, 7));
    TEST_ASSERT_EQUAL_INT(6, actag__median_radius_for_cell(25.9f, 7));
    TEST_ASSERT_EQUAL_INT(3, actag__median_radius_for_cell(1e30f, 3));
    TEST_ASSERT_EQUAL_INT(1, actag__median_radius_for_cell(0.5f, 1));
    TEST_ASSERT_EQUAL_INT(1, actag__median_radius_for_cell(100.0f, 1));
    TEST_ASSERT_EQUAL_INT(0, actag__median_radius_for_cell(100.0f, 0));
}

/* The two sonars the library is measured on: the pool recording's keeps
 * radius 4 everywhere (its cells are 14 beams or wider), so its detections
 * are those of the fixed radius; the paper's sonar takes 2 beyond 2.12 m
 * and 3 beyond 1.52 m. */
static void test_the_pool_sonar_keeps_its_radius_and_the_paper_sonar_bands(void)
{
    actag_family f = family_of("AcTag24h10");
    actag_sonar_geometry g;
    actag_params p;
    actag__median_bands b;
    memset(&g, 0, sizeof g);
    g.min_range = 0.1f;
    g.max_range = 1.5f;
    g.aperture = 60.0f * 3.14159265f / 180.0f;
    actag_params_default(&p);
    p.family = &f;
    TEST_ASSERT_EQUAL_INT(1, p.tuning.median_per_range);
    actag__median_bands_of(&g, 530, 512, &p, &b);
    TEST_ASSERT_EQUAL_INT(1, b.n);
    TEST_ASSERT_EQUAL_INT(4, b.radius[0]);
    g.max_range = 5.0f; /* row 0 is the farthest */
    actag__median_bands_of(&g, 1024, 512, &p, &b);
    TEST_ASSERT_EQUAL_INT(3, b.n);
    TEST_ASSERT_EQUAL_INT(2, b.radius[0]);
    TEST_ASSERT_EQUAL_INT(3, b.radius[1]);
    TEST_ASSERT_EQUAL_INT(4, b.radius[2]);
    TEST_ASSERT_FLOAT_WITHIN(0.01f, 2.12f, actag_geometry_range(&g, 1024, (float)b.end[0]));
    TEST_ASSERT_FLOAT_WITHIN(0.01f, 1.52f, actag_geometry_range(&g, 1024, (float)b.end[1]));
    check_rule(&g, 1024, 512, &p);
    p.tuning.median_per_range = 0;
    actag__median_bands_of(&g, 1024, 512, &p, &b);
    TEST_ASSERT_EQUAL_INT(1, b.n);
    TEST_ASSERT_EQUAL_INT(4, b.radius[0]);
}

/* A speckled frame with bright blocks, rows x cols. */
static uint8_t *speckle(int rows, int cols)
{
    uint8_t *img = (uint8_t *)malloc((size_t)rows * (size_t)cols);
    int r, c;
    TEST_ASSERT_NOT_NULL(img);
    for (r = 0; r < rows; r++)
        for (c = 0; c < cols; c++)
            img[(size_t)r * (size_t)cols + (size_t)c] =
                (uint8_t)((r / 6 + c / 5) % 4 == 0 ? 140 + tu_rand() % 110u : tu_rand() % 70u);
    return img;
}

/* What each band's rows must hold: the plain filter at the band's radius. */
static void expected_filtered(const uint8_t *img, int rows, int cols, const actag__median_bands *b,
                              uint8_t *want)
{
    size_t scr = ACTAG_MEDIAN_SCRATCH_SIZE(rows, cols), n = (size_t)rows * (size_t)cols;
    uint8_t *full = (uint8_t *)malloc(n), *s = (uint8_t *)malloc(scr);
    int i, y0 = 0;
    TEST_ASSERT_TRUE(full && s);
    for (i = 0; i < b->n; y0 = b->end[i++]) {
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_median_filter(img, rows, cols, cols, full, cols,
                                                            b->radius[i], s, scr));
        memcpy(want + (size_t)y0 * (size_t)cols, full + (size_t)y0 * (size_t)cols,
               (size_t)(b->end[i] - y0) * (size_t)cols);
    }
    free(full);
    free(s);
}

static void test_detect_filters_each_band_at_its_radius(void)
{
    const int rows = 1024, cols = 160;
    actag_family f24 = family_of("AcTag24h10"), f28 = family_of("AcTag28m10");
    actag_sonar_geometry g;
    actag_params p[3];
    actag_frame fr;
    actag__median_bands b[3];
    actag_detection det[12];
    int counts[3], i;
    size_t wss = actag_workspace_size(rows, cols), n = (size_t)rows * (size_t)cols;
    uint8_t *ws = (uint8_t *)malloc(wss), *img, *want = (uint8_t *)malloc(n);
    uint8_t *copy = (uint8_t *)malloc(n), *iws = (uint8_t *)malloc(actag_workspace_size_inplace(rows, cols));
    TEST_ASSERT_TRUE(ws && want && copy && iws);
    tu_seed(0xF17Eu);
    img = speckle(rows, cols);
    memset(&g, 0, sizeof g);
    g.min_range = 0.1f;
    g.max_range = 5.0f;
    g.aperture = 20.0f * 3.14159265f / 180.0f; /* 160 beams: bands 2, 3, 4 */
    memset(&fr, 0, sizeof fr);
    fr.data = img;
    fr.rows = rows;
    fr.cols = cols;
    fr.stride = cols;
    fr.depth = 8;
    for (i = 0; i < 3; i++) {
        actag_params_default(&p[i]);
        p[i].family = i == 1 ? &f28 : &f24;
    }
    p[2].tuning.median_per_range = 0;
    for (i = 0; i < 3; i++)
        actag__median_bands_of(&g, rows, cols, &p[i], &b[i]);
    TEST_ASSERT_TRUE(b[0].n >= 2); /* the test needs bands */
    TEST_ASSERT_FALSE(actag__median_bands_equal(&b[0], &b[1]));
    TEST_ASSERT_EQUAL_INT(1, b[2].n);
    for (i = 0; i < 3; i++) {
        int k;
        TEST_ASSERT_TRUE(actag_detect(&fr, &g, &p[i], ws, wss, det, 4, NULL) >= 0);
        expected_filtered(img, rows, cols, &b[i], want);
        TEST_ASSERT_EQUAL_UINT8_ARRAY(want, actag_workspace_filtered(ws, rows, cols), n);
        /* actag_detect_multi with sets 0..i: the last set's filtered frame
         * is the workspace's (each set is filtered for when its bands
         * differ from the previous set's) */
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_detect_multi(&fr, &g, p, i + 1, ws, wss, det, 4,
                                                           counts));
        TEST_ASSERT_EQUAL_UINT8_ARRAY(want, actag_workspace_filtered(ws, rows, cols), n);
        for (k = 0; k <= i; k++)
            TEST_ASSERT_TRUE(counts[k] >= 0);
        /* in place: the frame becomes the same filtered frame */
        memcpy(copy, img, n);
        fr.data = copy;
        TEST_ASSERT_TRUE(actag_detect_inplace(&fr, &g, &p[i], iws,
                                              actag_workspace_size_inplace(rows, cols), det, 4,
                                              NULL) >= 0);
        TEST_ASSERT_EQUAL_UINT8_ARRAY(want, copy, n);
        fr.data = img;
    }
    free(ws);
    free(iws);
    free(img);
    free(want);
    free(copy);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_rule_equals_brute_force);
    RUN_TEST(test_radius_for_cell_boundaries);
    RUN_TEST(test_the_pool_sonar_keeps_its_radius_and_the_paper_sonar_bands);
    RUN_TEST(test_detect_filters_each_band_at_its_radius);
    return UNITY_END();
}
