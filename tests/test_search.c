/* Structure search: the integral-image score map against direct box sums
 * written here, the best-position picking and suppression, a synthetic tag,
 * strides, and errors. */
#include "unity.h"
#include "test_util.h"

#include "actag/search.h"

void setUp(void) {}
void tearDown(void) {}

#define F ACTAG_SEARCH_FACTOR

/* The score at block (r, c), by direct summation (SEARCH.H's definition). */
static int ref_score(const uint8_t *img, int rows, int cols, int stride,
                     const actag_sonar_geometry *g, float tag, int bits, float rs, int r, int c)
{
    int hr = rows / F, hc = cols / F, ir, ic, orr, oc, i, j, a, b;
    float y = (float)(F * r) + 0.5f * (float)(F - 1);
    float range = actag_geometry_range(g, rows, y);
    float daz = actag_geometry_azimuth_step(g, cols, 0.5f * (float)cols) * range;
    float w = (float)(bits / 4 - 3); /* white square, cells */
    float dr = actag_geometry_range_step(g, rows), cell = tag / w, cr, cc;
    long long si = 0, so = 0, ni, no, num, den, q;
    if (!(daz > 0.0f))
        return INT16_MIN;
    cr = cell * rs / dr / (float)F;
    cc = cell / daz / (float)F;
    ir = (int)(0.5f * w * cr + 0.5f);
    ic = (int)(0.5f * w * cc + 0.5f);
    orr = (int)((0.5f * w + 1.0f) * cr + 0.5f);
    oc = (int)((0.5f * w + 1.0f) * cc + 0.5f);
    if (ir < 1) ir = 1;
    if (ic < 1) ic = 1;
    if (orr <= ir) orr = ir + 1;
    if (oc <= ic) oc = ic + 1;
    if (!(r - orr >= 0 && r + orr < hr && c - oc >= 0 && c + oc < hc))
        return INT16_MIN;
    for (i = r - orr; i <= r + orr; i++)
        for (j = c - oc; j <= c + oc; j++) {
            long long block = 0;
            for (a = 0; a < F; a++)
                for (b = 0; b < F; b++)
                    block += img[(size_t)(F * i + a) * (size_t)stride + (size_t)(F * j + b)];
            so += block;
            if (i >= r - ir && i <= r + ir && j >= c - ic && j <= c + ic)
                si += block;
        }
    ni = (long long)(2 * ir + 1) * (2 * ic + 1);
    no = (long long)(2 * orr + 1) * (2 * oc + 1);
    num = si * (no - ni) - (so - si) * ni;
    den = ni * (no - ni) * F * F;
    q = num * 8 / den;
    return (int)(q > 2040 ? 2040 : q < -2040 ? -2040 : q);
}

static void test_map_equals_direct_sums(void)
{
    int t;
    tu_seed(21);
    for (t = 0; t < 12; t++) {
        int rows = tu_range(16, 140), cols = tu_range(16, 140), stride = cols + tu_range(0, 9);
        int r, c;
        float tag = 0.02f + (float)tu_range(0, 100) * 0.001f;
        int bits = (t % 2) ? 28 : 24; /* 28 bits: a 4-cell white square */
        actag_sonar_geometry g = {0.5f, 2.0f, 0.6f, NULL, 0u};
        uint8_t *img = (uint8_t *)malloc((size_t)rows * (size_t)stride);
        size_t ms = ACTAG_SEARCH_MAP_SIZE(rows, cols), is = ACTAG_SEARCH_INTEGRAL_SIZE(rows, cols);
        void *map = malloc(ms), *ii = malloc(is);
        actag_search z;
        TEST_ASSERT_NOT_NULL(img);
        for (r = 0; r < rows * stride; r++) /* blobs and noise; padding included */
            img[r] = (uint8_t)((tu_rand() % 4u == 0u) ? tu_range(150, 255) : tu_range(0, 60));
        if (t % 3 == 1)
            g.flags = ACTAG_RANGE_ASCENDING;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_search_map(&z, img, rows, cols, stride, &g, tag, bits, 0.75f,
                                                         map, ms, ii, is));
        TEST_ASSERT_EQUAL_INT(rows / F, z.hr);
        TEST_ASSERT_EQUAL_INT(cols / F, z.hc);
        for (r = 0; r < z.hr; r++)
            for (c = 0; c < z.hc; c++)
                TEST_ASSERT_EQUAL_INT(ref_score(img, rows, cols, stride, &g, tag, bits, 0.75f, r, c),
                                      z.map[(size_t)r * (size_t)z.hc + (size_t)c]);
        free(img);
        free(map);
        free(ii);
    }
}

/* A bright square of the tag's size in a dark, noisy frame is found first,
 * at its place; the next pick is elsewhere; a flat frame yields nothing. */
static void test_finds_a_synthetic_square(void)
{
    enum { R = 200, C = 240 };
    static uint8_t img[R * C];
    static int16_t map[ACTAG_SEARCH_MAP_SIZE(R, C) / 2];
    static uint32_t ii[ACTAG_SEARCH_INTEGRAL_SIZE(R, C) / 4];
    actag_sonar_geometry g;
    actag_search z;
    actag_point q[4], q2[4];
    float px = 0.13f / 30.0f, cx = 150.0f, cy = 80.0f;
    int r, c;
    g.min_range = 1.0f;
    g.max_range = 1.0f + (float)(R - 1) * px;
    g.aperture = (float)(C - 1) * px / 1.43f;
    g.bearings = NULL;
    g.flags = 0u;
    tu_seed(5);
    for (r = 0; r < R; r++)
        for (c = 0; c < C; c++) {
            int in = c >= (int)cx - 15 && c < (int)cx + 15 && r >= (int)cy - 15 && r < (int)cy + 15;
            img[(size_t)r * C + (size_t)c] = (uint8_t)(in ? tu_range(170, 230) : tu_range(10, 50));
        }
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_search_map(&z, img, R, C, C, &g, 0.13f, 24, 1.0f, map,
                                                     sizeof map, ii, sizeof ii));
    TEST_ASSERT_EQUAL_INT(1, actag_search_next(&z, 8 * 60, &g, 0.13f, 1.0f, R, C, q));
    TEST_ASSERT_FLOAT_WITHIN(4.0f, cx, 0.25f * (q[0].x + q[1].x + q[2].x + q[3].x));
    TEST_ASSERT_FLOAT_WITHIN(4.0f, cy, 0.25f * (q[0].y + q[1].y + q[2].y + q[3].y));
    TEST_ASSERT_TRUE(q[1].x > q[0].x && q[2].y > q[1].y && q[3].x < q[2].x); /* clockwise */
    TEST_ASSERT_FLOAT_WITHIN(3.0f, 30.0f, q[1].x - q[0].x);                   /* tag-sized */
    /* the neighbourhood is suppressed: nothing else of that contrast */
    TEST_ASSERT_EQUAL_INT(0, actag_search_next(&z, 8 * 60, &g, 0.13f, 1.0f, R, C, q2));
    /* flat frame: no contrast anywhere */
    memset(img, 90, sizeof img);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_search_map(&z, img, R, C, C, &g, 0.13f, 24, 1.0f, map,
                                                     sizeof map, ii, sizeof ii));
    TEST_ASSERT_EQUAL_INT(0, actag_search_next(&z, 1, &g, 0.13f, 1.0f, R, C, q));
}

static void test_errors(void)
{
    static uint8_t img[64 * 64];
    static uint8_t map[ACTAG_SEARCH_MAP_SIZE(64, 64)], ii[ACTAG_SEARCH_INTEGRAL_SIZE(64, 64)];
    actag_sonar_geometry g = {0.5f, 2.0f, 0.6f, NULL, 0u}, bad = g;
    actag_search z;
    bad.max_range = 0.1f;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_search_map(&z, img, 64, 64, 64, &g, 0.1f, 24, 1.0f, map, sizeof map, ii, sizeof ii));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_search_map(NULL, img, 64, 64, 64, &g, 0.1f, 24, 1.0f, map, sizeof map, ii, sizeof ii));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_search_map(&z, NULL, 64, 64, 64, &g, 0.1f, 24, 1.0f, map, sizeof map, ii, sizeof ii));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_search_map(&z, img, 64, 64, 64, &g, 0.1f, 24, 1.0f, NULL, sizeof map, ii, sizeof ii));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_search_map(&z, img, 64, 64, 63, &g, 0.1f, 24, 1.0f, map, sizeof map, ii, sizeof ii));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_search_map(&z, img, 15, 64, 64, &g, 0.1f, 24, 1.0f, map, sizeof map, ii, sizeof ii));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_search_map(&z, img, 64, 15, 64, &g, 0.1f, 24, 1.0f, map, sizeof map, ii, sizeof ii));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_search_map(&z, img, 64, 64, 64, &g, 0.0f, 24, 1.0f, map, sizeof map, ii, sizeof ii));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_search_map(&z, img, 64, 64, 64, &g, 0.1f, 24, -1.0f, map, sizeof map, ii, sizeof ii));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_search_map(&z, img, 64, 64, 64, &g, 0.1f, 26, 1.0f, map, sizeof map, ii, sizeof ii));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_search_map(&z, img, 64, 64, 64, &g, 0.1f, 36, 1.0f, map, sizeof map, ii, sizeof ii));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, actag_search_map(&z, img, 64, 64, 64, &bad, 0.1f, 24, 1.0f, map, sizeof map, ii, sizeof ii));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE, actag_search_map(&z, img, 64, 64, 64, &g, 0.1f, 24, 1.0f, map, sizeof map - 1, ii, sizeof ii));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE, actag_search_map(&z, img, 64, 64, 64, &g, 0.1f, 24, 1.0f, map, sizeof map, ii, sizeof ii - 1));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_map_equals_direct_sums);
    RUN_TEST(test_finds_a_synthetic_square);
    RUN_TEST(test_errors);
    return UNITY_END();
}
