/* Structure search: the integral-image score map against direct box sums
 * written here, the best-position picking and suppression, a synthetic tag,
 * strides, and errors. */
#include "unity.h"
#include "test_util.h"

#include "actag/search.h"

#include <limits.h>

void setUp(void) {}
void tearDown(void) {}

#define F ACTAG_SEARCH_FACTOR

/* The score at block (r, c), by direct summation (SEARCH.H's definition);
 * *num8 (if not NULL): the quotient's numerator, 8 (mean_in - mean_ring)
 * scaled by ni (no - ni) F^2 (0 where the position is not scored). */
static int ref_score_num(const uint8_t *img, int rows, int cols, int stride,
                         const actag_sonar_geometry *g, float tag, int bits, float rs, int r,
                         int c, long long *num8)
{
    int hr = rows / F, hc = cols / F, ir, ic, orr, oc, i, j, a, b;
    float y = (float)(F * r) + 0.5f * (float)(F - 1);
    float range = actag_geometry_range(g, rows, y);
    /* the azimuth step at the block's own column (a bearing table's varies) */
    float x = (float)(F * c) + 0.5f * (float)(F - 1);
    float daz = actag_geometry_azimuth_step(g, cols, x) * range;
    float w = (float)(bits / 4 - 3); /* white square, cells */
    float dr = actag_geometry_range_step(g, rows), cell = tag / w, cr, cc;
    long long si = 0, so = 0, ni, no, num, den, q;
    if (num8)
        *num8 = 0;
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
    if (num8)
        *num8 = num * 8;
    return (int)(q > 2040 ? 2040 : q < -2040 ? -2040 : q);
}

static int ref_score(const uint8_t *img, int rows, int cols, int stride,
                     const actag_sonar_geometry *g, float tag, int bits, float rs, int r, int c)
{
    return ref_score_num(img, rows, cols, stride, g, tag, bits, rs, r, c, NULL);
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
        float bearings[140];
        uint8_t *img = (uint8_t *)malloc((size_t)rows * (size_t)stride);
        size_t ms = ACTAG_SEARCH_MAP_SIZE(rows, cols), is = ACTAG_SEARCH_INTEGRAL_SIZE(rows, cols);
        void *map = malloc(ms), *ii = malloc(is);
        actag_search z;
        TEST_ASSERT_NOT_NULL(img);
        for (r = 0; r < rows * stride; r++) /* blobs and noise; padding included */
            img[r] = (uint8_t)((tu_rand() % 4u == 0u) ? tu_range(150, 255) : tu_range(0, 60));
        if (t % 3 == 1)
            g.flags = ACTAG_RANGE_ASCENDING;
        if (t % 4 >= 2) {
            /* a bearing table whose step grows 1.5-3x from the centre to
             * the edges (an Oculus-like fan): each column its own box */
            float span = 0.0f, gain = 0.5f + 0.01f * (float)tu_range(0, 150);
            for (c = 0; c < cols; c++) {
                float u = 2.0f * (float)c / (float)(cols - 1) - 1.0f; /* -1 .. 1 */
                bearings[c] = 0.5f * u + gain * u * u * u / 3.0f;
                span = bearings[c];
            }
            for (c = 0; c < cols; c++)
                bearings[c] *= 0.5f / span; /* +-0.5 rad */
            g.bearings = bearings;
        }
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

/* The block sums at full scale (every pixel 250-255: each 4-pixel row of a
 * block near 4 x 255, the sum of a block near 16 x 255) and from a frame
 * that starts at an odd address with an odd stride (the rows are read four
 * bytes at a time): the map equals the direct sums. */
static void test_block_sums_at_full_scale_and_odd_addresses(void)
{
    enum { R = 96, C = 101, S = 103 };
    static uint8_t buf[1 + R * S];
    static int16_t map[ACTAG_SEARCH_MAP_SIZE(R, C) / 2];
    static uint32_t ii[ACTAG_SEARCH_INTEGRAL_SIZE(R, C) / 4];
    const uint8_t *img = buf + 1;
    actag_sonar_geometry g = {0.5f, 2.0f, 0.6f, NULL, 0u};
    actag_search z;
    int i, r, c, scored = 0;
    tu_seed(31);
    for (i = 0; i < (int)sizeof buf; i++) /* a bright square in a frame near white */
        buf[i] = (uint8_t)tu_range(250, 255);
    for (r = 30; r < 60; r++)
        for (c = 30; c < 60; c++)
            buf[1 + r * S + c] = 255u;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_search_map(&z, img, R, C, S, &g, 0.05f, 24, 1.0f, map,
                                                     sizeof map, ii, sizeof ii));
    for (r = 0; r < z.hr; r++)
        for (c = 0; c < z.hc; c++) {
            int ref = ref_score(img, R, C, S, &g, 0.05f, 24, 1.0f, r, c);
            TEST_ASSERT_EQUAL_INT(ref, map[(size_t)r * (size_t)z.hc + (size_t)c]);
            scored += ref != INT16_MIN;
        }
    TEST_ASSERT_GREATER_THAN_INT(50, scored); /* positions were scored, not only refused */
    /* the integral's last entry: every block of the map at full scale */
    memset(buf, 255, sizeof buf);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_search_map(&z, img, R, C, S, &g, 0.05f, 24, 1.0f, map,
                                                     sizeof map, ii, sizeof ii));
    TEST_ASSERT_EQUAL_UINT32(16u * 255u * (uint32_t)(z.hr * z.hc),
                             ii[(size_t)z.hr * (size_t)(z.hc + 1) + (size_t)z.hc]);
}

/* Boxes of up to thousands of blocks over bright pixels: the score's
 * numerator exceeds 32 bits at the large tag's boxes (the map then divides
 * in 64 bits) and stays within them at the small tag's; both give the
 * direct sums' score. */
static void test_large_boxes_score_as_the_direct_sums(void)
{
    static const float tags[2] = {0.5f, 0.04f}; /* cells of about 10 and 1 blocks */
    int rows = 400, cols = 400, r, c, t, k, wide = 0, narrow = 0, negative = 0;
    actag_sonar_geometry g = {0.5f, 2.0f, 1.2f, NULL, ACTAG_RANGE_ASCENDING};
    size_t ms = ACTAG_SEARCH_MAP_SIZE(rows, cols), is = ACTAG_SEARCH_INTEGRAL_SIZE(rows, cols);
    uint8_t *img = (uint8_t *)malloc((size_t)rows * (size_t)cols);
    void *map = malloc(ms), *ii = malloc(is);
    actag_search z;
    TEST_ASSERT_NOT_NULL(img);
    TEST_ASSERT_NOT_NULL(map);
    TEST_ASSERT_NOT_NULL(ii);
    tu_seed(77);
    for (r = 0; r < rows; r++)
        for (c = 0; c < cols; c++) /* a bright square of the large tag's size, dark around */
            img[(size_t)r * (size_t)cols + (size_t)c] =
                (uint8_t)((r >= 130 && r < 270 && c >= 130 && c < 270) ? tu_range(180, 255)
                                                                      : tu_range(0, 40));
    for (k = 0; k < 2; k++) {
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_search_map(&z, img, rows, cols, cols, &g, tags[k], 24,
                                                         1.0f, map, ms, ii, is));
        for (t = 0; t < 300; t++) {
            long long num8;
            int ref;
            /* the large tag: near the square's centre (block 50, 50) */
            r = k == 0 ? tu_range(40, 60) : tu_range(0, z.hr - 1);
            c = k == 0 ? tu_range(40, 60) : tu_range(0, z.hc - 1);
            ref = ref_score_num(img, rows, cols, cols, &g, tags[k], 24, 1.0f, r, c, &num8);
            TEST_ASSERT_EQUAL_INT(ref, z.map[(size_t)r * (size_t)z.hc + (size_t)c]);
            if (ref != INT16_MIN) {
                wide += num8 > INT_MAX || num8 < -INT_MAX;
                narrow += num8 <= INT_MAX && num8 >= -INT_MAX;
                negative += num8 < 0 && num8 >= -INT_MAX; /* truncation toward zero */
            }
        }
    }
    /* both ways of dividing were checked */
    TEST_ASSERT_GREATER_THAN_INT(20, wide);
    TEST_ASSERT_GREATER_THAN_INT(20, narrow);
    TEST_ASSERT_GREATER_THAN_INT(5, negative);
    free(img);
    free(map);
    free(ii);
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
    /* centred on its block's centre, (F b + (F - 1) / 2) in full-resolution
     * pixels (search.h): a start 1.5 px off changes what the decoder reads */
    TEST_ASSERT_FLOAT_WITHIN(1e-3f, 0.0f,
                             fmodf(0.25f * (q[0].x + q[1].x + q[2].x + q[3].x) - 1.5f, 4.0f));
    TEST_ASSERT_FLOAT_WITHIN(1e-3f, 0.0f,
                             fmodf(0.25f * (q[0].y + q[1].y + q[2].y + q[3].y) - 1.5f, 4.0f));
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

/* Box sums are uint32 differences of the integral image: the ring of a box
 * of more than 2^32 / (16 x 255) blocks of white could sum past 2^32 and
 * wrap (a flat white frame of 4400 x 4400 with a 16-bit tag of 1.45 m
 * filling it scored up to 2040 and came back as a candidate). Such boxes
 * are not scored; one just below the limit on the same frame is, and
 * scores 0 on the flat frame. Host only: 19 MB of frame. */
static void test_box_too_large_for_the_integral_is_not_scored(void)
{
    enum { R = 4400, C = 4400 };
    const float tags[2] = {1.4532f, 1.36f}; /* outer boxes 1091^2, 1021^2 blocks */
    actag_sonar_geometry g;
    uint8_t *img;
    int16_t *map;
    uint32_t *ii;
    size_t ms = ACTAG_SEARCH_MAP_SIZE(R, C), is = ACTAG_SEARCH_INTEGRAL_SIZE(R, C);
    int t;
    if (TU_EMULATED)
        TEST_IGNORE_MESSAGE("host suite only (a 19 MB frame)");
    img = (uint8_t *)malloc((size_t)R * C);
    map = (int16_t *)malloc(ms);
    ii = (uint32_t *)malloc(is);
    TEST_ASSERT_TRUE(img != NULL && map != NULL && ii != NULL);
    memset(img, 255, (size_t)R * C);
    g.min_range = 100.0f; /* 1 mm rows, 1 mm beams at the middle rows */
    g.max_range = 100.0f + 0.001f * (float)(R - 1);
    g.aperture = (float)(C - 1) * 0.001f / 102.2f;
    g.bearings = NULL;
    g.flags = 0u;
    TEST_ASSERT_EQUAL_UINT32(1052688u, ACTAG_SEARCH_MAX_BOX_BLOCKS);
    for (t = 0; t < 2; t++) {
        actag_search z;
        actag_point q[4];
        long long ring;
        int r, c, scored = 0, nonzero = 0, orr, ir;
        float cr = tags[t] / actag_geometry_range_step(&g, R) / (float)F;
        orr = (int)(1.5f * cr + 0.5f); /* 16 bits: a white square of 1 cell */
        ir = (int)(0.5f * cr + 0.5f);
        ring = (long long)(2 * orr + 1) * (2 * orr + 1) - (long long)(2 * ir + 1) * (2 * ir + 1);
        /* the premise: the first tag's ring alone overflows, the second's box does not */
        if (t == 0)
            TEST_ASSERT_TRUE(ring > (long long)ACTAG_SEARCH_MAX_BOX_BLOCKS);
        else
            TEST_ASSERT_TRUE((2 * orr + 1) * (2 * orr + 1) <= (int)ACTAG_SEARCH_MAX_BOX_BLOCKS);
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_search_map(&z, img, R, C, C, &g, tags[t], 16, 1.0f,
                                                         map, ms, ii, is));
        for (r = 0; r < z.hr; r++)
            for (c = 0; c < z.hc; c++) {
                int v = z.map[(size_t)r * (size_t)z.hc + (size_t)c];
                scored += v != INT16_MIN;
                nonzero += v != INT16_MIN && v != 0;
            }
        TEST_ASSERT_EQUAL_INT(0, nonzero);
        if (t == 0) {
            TEST_ASSERT_EQUAL_INT(0, scored);
            TEST_ASSERT_EQUAL_INT(0, actag_search_next(&z, -2040, &g, tags[t], 1.0f, R, C, q));
        } else {
            TEST_ASSERT_TRUE(scored > 0);
            TEST_ASSERT_EQUAL_INT(0, actag_search_next(&z, 1, &g, tags[t], 1.0f, R, C, q));
            TEST_ASSERT_EQUAL_INT(1, actag_search_next(&z, 0, &g, tags[t], 1.0f, R, C, q));
        }
    }
    free(img);
    free(map);
    free(ii);
}

/* Any min_score ends the documented loop: INT16_MIN (unscored positions)
 * took the sentinel itself as a candidate forever, INT_MIN overflowed in
 * min_score - 1 (and found nothing); both now act as INT16_MIN + 1 and
 * take exactly the scored positions' picks. */
static void test_any_min_score_ends_the_loop(void)
{
    enum { R = 64, C = 64 };
    static uint8_t img[R * C];
    static int16_t map[ACTAG_SEARCH_MAP_SIZE(R, C) / 2];
    static uint32_t ii[ACTAG_SEARCH_INTEGRAL_SIZE(R, C) / 4];
    const int mins[3] = {INT16_MIN + 1, INT16_MIN, INT_MIN};
    actag_sonar_geometry g = {0.5f, 2.0f, 0.6f, NULL, 0u};
    actag_search z;
    actag_point q[4];
    int i, n[3];
    memset(img, 90, sizeof img);
    for (i = 0; i < 3; i++) {
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_search_map(&z, img, R, C, C, &g, 0.1f, 24, 1.0f, map,
                                                         sizeof map, ii, sizeof ii));
        n[i] = 0;
        while (n[i] < 1000 && actag_search_next(&z, mins[i], &g, 0.1f, 1.0f, R, C, q) == 1)
            n[i]++;
        TEST_ASSERT_TRUE(n[i] < 1000);
        TEST_ASSERT_EQUAL_INT(0, actag_search_next(&z, mins[i], &g, 0.1f, 1.0f, R, C, q));
    }
    TEST_ASSERT_TRUE(n[0] > 0); /* the flat frame has scored positions (0) */
    TEST_ASSERT_EQUAL_INT(n[0], n[1]);
    TEST_ASSERT_EQUAL_INT(n[0], n[2]);
}

/* Candidates at the last and the first scored block rows and columns (a
 * 32-bit tag: the blanked neighbourhood, 0.75 tag + 1 block either side,
 * reaches past the outer box, so past the map's edge there): exactly the
 * rows and columns within the neighbourhood are blanked, clipped to the
 * map, and nothing outside it is written (guards around the map). */
static void test_suppression_at_the_edges(void)
{
    enum { R = 160, C = 160, GUARD = 64 };
    static uint8_t img[R * C];
    static int16_t buf[GUARD + ACTAG_SEARCH_MAP_SIZE(R, C) / 2 + GUARD], before[R / F * (C / F)];
    static uint32_t ii[ACTAG_SEARCH_INTEGRAL_SIZE(R, C) / 4];
    const float dr = 0.005f, tag = 0.108f; /* 21.6 px: 5.4 blocks */
    int16_t *map = buf + GUARD;
    actag_sonar_geometry g;
    actag_search z;
    actag_point q[4];
    int r, c, i, pick;
    /* beams of 4.9 mm +- 1.3 %: 5.5 blocks per tag; the neighbourhood is
     * 5 blocks either side in both directions, 4.05 and 4.1 before the + 1
     * (a smaller factor than 1.5 makes it 4), the outer box 4 */
    g.min_range = 30.0f;
    g.max_range = 30.0f + dr * (float)(R - 1);
    g.aperture = (float)(C - 1) * (tag / 22.0f) / 30.4f;
    g.bearings = NULL;
    g.flags = 0u;
    tu_seed(9);
    for (r = 0; r < R; r++)
        for (c = 0; c < C; c++) {
            /* a bright square at the bottom right, a dimmer one at the top left */
            int br = r >= 133 && r < 155 && c >= 133 && c < 155;
            int tl = r >= 5 && r < 27 && c >= 5 && c < 27;
            img[(size_t)r * C + (size_t)c] =
                (uint8_t)(br ? tu_range(200, 230) : tl ? tu_range(150, 170) : tu_range(10, 40));
        }
    for (i = 0; i < GUARD; i++) {
        buf[i] = 0x5a5a;
        buf[GUARD + R / F * (C / F) + i] = 0x5a5a;
    }
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_search_map(&z, img, R, C, C, &g, tag, 32, 1.0f, map,
                                                     ACTAG_SEARCH_MAP_SIZE(R, C), ii, sizeof ii));
    for (pick = 0; pick < 2; pick++) {
        int br, bc, sr, sc;
        float x, y, daz;
        memcpy(before, map, sizeof before);
        TEST_ASSERT_EQUAL_INT(1, actag_search_next(&z, 8 * 40, &g, tag, 1.0f, R, C, q));
        x = 0.5f * (q[0].x + q[1].x);
        y = 0.5f * (q[1].y + q[2].y);
        bc = (int)(x / (float)F);
        br = (int)(y / (float)F);
        /* the last scored block (the outer box reaches the map's edge), then the first */
        TEST_ASSERT_EQUAL_INT(pick == 0 ? 35 : 4, br);
        TEST_ASSERT_EQUAL_INT(pick == 0 ? 35 : 4, bc);
        TEST_ASSERT_TRUE(before[br * z.hc + bc] != INT16_MIN);
        TEST_ASSERT_TRUE(pick == 0 ? before[(br + 1) * z.hc + bc] == INT16_MIN
                                   : before[(br - 1) * z.hc + bc] == INT16_MIN);
        TEST_ASSERT_TRUE(pick == 0 ? before[br * z.hc + bc + 1] == INT16_MIN
                                   : before[br * z.hc + bc - 1] == INT16_MIN);
        /* 0.75 tag either side, in blocks, + 1 */
        daz = actag_geometry_azimuth_step(&g, C, x) * actag_geometry_range(&g, R, y);
        sr = (int)(0.75f * tag / dr / (float)F) + 1;
        sc = (int)(0.75f * tag / daz / (float)F) + 1;
        TEST_ASSERT_EQUAL_INT(5, sr); /* beyond the outer box (4 blocks) */
        TEST_ASSERT_EQUAL_INT(5, sc);
        for (r = 0; r < z.hr; r++)
            for (c = 0; c < z.hc; c++) {
                int in = r >= br - sr && r <= br + sr && c >= bc - sc && c <= bc + sc;
                TEST_ASSERT_EQUAL_INT(in ? INT16_MIN : before[r * z.hc + c], map[r * z.hc + c]);
            }
    }
    for (i = 0; i < GUARD; i++) {
        TEST_ASSERT_EQUAL_INT(0x5a5a, buf[i]);
        TEST_ASSERT_EQUAL_INT(0x5a5a, buf[GUARD + R / F * (C / F) + i]);
    }
}

static void test_errors(void)
{
    static uint8_t img[64 * 64];
    static int16_t map[ACTAG_SEARCH_MAP_SIZE(64, 64) / 2 + 1]; /* room for an offset */
    static uint32_t ii[ACTAG_SEARCH_INTEGRAL_SIZE(64, 64) / 4 + 1];
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
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE, actag_search_map(&z, img, 64, 64, 64, &g, 0.1f, 24, 1.0f, map, sizeof map - 3, ii, sizeof ii));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE, actag_search_map(&z, img, 64, 64, 64, &g, 0.1f, 24, 1.0f, map, sizeof map, ii, sizeof ii - 5));
    {   /* the scratch is read as uint32_t, the map as int16_t: 4- and 2-byte aligned */
        uint8_t *mb = (uint8_t *)(void *)map, *ib = (uint8_t *)(void *)ii;
        size_t ms = sizeof map - 2, is = sizeof ii - 4;
        int o;
        for (o = 1; o < 4; o++)
            TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_search_map(&z, img, 64, 64, 64, &g, 0.1f, 24, 1.0f, map, ms, ib + o, is));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_search_map(&z, img, 64, 64, 64, &g, 0.1f, 24, 1.0f, mb + 1, ms, ii, is));
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_search_map(&z, img, 64, 64, 64, &g, 0.1f, 24, 1.0f, mb + 2, ms, ib + 4, is));
        /* checked after the pointers, before the rest */
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_search_map(&z, NULL, 64, 64, 64, &g, 0.1f, 24, 1.0f, mb + 1, ms, ii, is));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_search_map(&z, img, 64, 64, 64, &bad, 0.1f, 24, 1.0f, mb + 1, ms, ii, is));
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_map_equals_direct_sums);
    RUN_TEST(test_large_boxes_score_as_the_direct_sums);
    RUN_TEST(test_finds_a_synthetic_square);
    RUN_TEST(test_block_sums_at_full_scale_and_odd_addresses);
    RUN_TEST(test_box_too_large_for_the_integral_is_not_scored);
    RUN_TEST(test_any_min_score_ends_the_loop);
    RUN_TEST(test_suppression_at_the_edges);
    RUN_TEST(test_errors);
    return UNITY_END();
}
