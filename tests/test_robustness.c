/* Hostile input to actag_detect (issue 10), one named test each: zero, one
 * and maximum rows/cols, stride < cols, NULL pointers, NaN / infinite /
 * negative / swapped ranges, apertures 0 and above 2 pi, bad bearing
 * tables, radii 0 and larger than the frame, corrections above the limit,
 * a workspace one byte too small, all-white / all-black / noise frames,
 * odd-address 16-bit frames, tight frame buffers, a huge tag size and a
 * tiny azimuth step. Each gives its documented error or a correct empty
 * result, leaves the frame untouched, and (sanitizer build) reads nothing
 * outside the buffers. */
#include "unity.h"
#include "test_util.h"

#include "actag/actag.h"

#include <math.h>

void setUp(void) {}
void tearDown(void) {}

#define EXAMPLE ACTAG_SOURCE_DIR "/data/exampleSonarImage.pgm"

static actag_family g_fam;
static actag_params g_p;
static const actag_sonar_geometry g_geo = {0.1f, 1.5f, 1.0472f, NULL, 0u};

static void defaults(void)
{
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &g_fam));
    actag_params_default(&g_p);
    g_p.family = &g_fam;
}

/* actag_detect on a rows x cols 8-bit frame of value v (or noise when v <
 * 0) with a malloc'd workspace of exactly the needed size; checks the frame
 * is unchanged and, on success, that nothing was found. */
static int run8(int rows, int cols, int stride, int v, const actag_sonar_geometry *geo,
                const actag_params *p, actag_stats *st)
{
    size_t n = rows > 0 && stride > 0 ? (size_t)(rows - 1) * (size_t)stride + (size_t)(cols > 0 ? cols : 1) : 1;
    size_t wsz = actag_workspace_size(rows, cols);
    uint8_t *img = (uint8_t *)malloc(n), *copy = (uint8_t *)malloc(n);
    void *ws = malloc(wsz ? wsz : 1);
    actag_frame f;
    actag_detection det[4];
    size_t i;
    int rc;
    TEST_ASSERT_NOT_NULL(img);
    TEST_ASSERT_NOT_NULL(copy);
    TEST_ASSERT_NOT_NULL(ws);
    for (i = 0; i < n; i++)
        img[i] = (uint8_t)(v >= 0 ? v : (int)(tu_rand() & 255u));
    memcpy(copy, img, n);
    f.data = img;
    f.rows = rows;
    f.cols = cols;
    f.stride = stride;
    f.depth = 8;
    rc = actag_detect(&f, geo, p, ws, wsz, det, 4, st);
    TEST_ASSERT_EQUAL_MEMORY(copy, img, n);
    free(img);
    free(copy);
    free(ws);
    return rc;
}

static void test_zero_one_and_maximum_rows_cols(void)
{
    actag_stats st;
    defaults();
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, run8(0, 64, 64, 0, &g_geo, &g_p, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, run8(64, 0, 0, 0, &g_geo, &g_p, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, run8(-1, 64, 64, 0, &g_geo, &g_p, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, run8(ACTAG_MAX_DIM + 1, 2, 2, 0, &g_geo, &g_p, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, run8(2, ACTAG_MAX_DIM + 1, ACTAG_MAX_DIM + 1, 0, &g_geo, &g_p, NULL));
    TEST_ASSERT_EQUAL_UINT(0, actag_workspace_size(0, 5));
    TEST_ASSERT_EQUAL_UINT(0, actag_workspace_size(5, ACTAG_MAX_DIM + 1));
    /* one row, one column, one pixel: a correct empty result */
    TEST_ASSERT_EQUAL_INT(0, run8(1, 64, 64, -1, &g_geo, &g_p, &st));
    TEST_ASSERT_EQUAL_INT(0, run8(64, 1, 1, -1, &g_geo, &g_p, &st));
    TEST_ASSERT_EQUAL_INT(0, run8(1, 1, 1, 200, &g_geo, &g_p, &st));
    /* the largest sides, with the other one small */
    TEST_ASSERT_EQUAL_INT(0, run8(ACTAG_MAX_DIM, 2, 2, -1, &g_geo, &g_p, &st));
    TEST_ASSERT_EQUAL_INT(0, run8(3, ACTAG_MAX_DIM, ACTAG_MAX_DIM, -1, &g_geo, &g_p, &st));
    TEST_ASSERT_EQUAL_INT(0, st.decoded);
}

static void test_stride_smaller_than_cols(void)
{
    defaults();
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, run8(32, 32, 31, 0, &g_geo, &g_p, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, run8(32, 32, -32, 0, &g_geo, &g_p, NULL));
    TEST_ASSERT_EQUAL_INT(0, run8(32, 32, 32, 0, &g_geo, &g_p, NULL));
    TEST_ASSERT_EQUAL_INT(0, run8(32, 32, 1000, -1, &g_geo, &g_p, NULL)); /* tight buffer */
}

static void test_null_pointers(void)
{
    static uint8_t img[32 * 32], ws[ACTAG_WORKSPACE_SIZE(32, 32)];
    actag_frame f = {img, 32, 32, 32, 8}, fnull = {NULL, 32, 32, 32, 8};
    actag_detection det[2];
    actag_params nofam;
    actag_stats st;
    defaults();
    nofam = g_p;
    nofam.family = NULL;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_detect(NULL, &g_geo, &g_p, ws, sizeof ws, det, 2, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_detect(&fnull, &g_geo, &g_p, ws, sizeof ws, det, 2, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_detect(&f, NULL, &g_p, ws, sizeof ws, det, 2, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_detect(&f, &g_geo, NULL, ws, sizeof ws, det, 2, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_detect(&f, &g_geo, &nofam, ws, sizeof ws, det, 2, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_detect(&f, &g_geo, &g_p, NULL, sizeof ws, det, 2, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_detect(&f, &g_geo, &g_p, ws, sizeof ws, NULL, 2, NULL));
    /* no output array is fine with max_out 0, stats may be NULL */
    TEST_ASSERT_EQUAL_INT(0, actag_detect(&f, &g_geo, &g_p, ws, sizeof ws, NULL, 0, &st));
    TEST_ASSERT_EQUAL_INT(0, actag_detect(&f, &g_geo, &g_p, ws, sizeof ws, det, 2, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_detect(&f, &g_geo, &g_p, ws, sizeof ws, det, -1, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_params_validate(NULL, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_geometry_validate(NULL, 32, 32, NULL));
    TEST_ASSERT_NULL(actag_workspace_bitmap(NULL, 32, 32));
    TEST_ASSERT_NULL(actag_workspace_filtered(ws, 0, 32));
}

static void test_nan_infinite_negative_and_swapped_ranges(void)
{
    static const float bad[][2] = {{NAN, 1.5f}, {0.1f, NAN}, {INFINITY, 1.5f}, {0.1f, INFINITY},
                                   {-INFINITY, 1.5f}, {-0.1f, 1.5f}, {1.5f, 0.1f},
                                   {0.5f, 0.5f}, {0.0f, 0.0f}, {0.1f, -1.0f}};
    int i;
    defaults();
    for (i = 0; i < (int)(sizeof bad / sizeof bad[0]); i++) {
        actag_sonar_geometry g = g_geo;
        char msg[64];
        g.min_range = bad[i][0];
        g.max_range = bad[i][1];
        snprintf(msg, sizeof msg, "ranges %g %g", (double)bad[i][0], (double)bad[i][1]);
        TEST_ASSERT_EQUAL_INT_MESSAGE(ACTAG_ERR_GEOMETRY, run8(48, 48, 48, -1, &g, &g_p, NULL), msg);
    }
    {
        actag_sonar_geometry g = g_geo;
        g.min_range = 0.0f; /* range 0 at the nearest row is valid */
        TEST_ASSERT_EQUAL_INT(0, run8(48, 48, 48, -1, &g, &g_p, NULL));
    }
}

static void test_aperture_zero_or_above_two_pi(void)
{
    static const float bad[] = {0.0f, -0.5f, NAN, INFINITY, 6.2831855f, 7.0f, 1e30f};
    static float bearings[48];
    int i;
    defaults();
    for (i = 0; i < (int)(sizeof bad / sizeof bad[0]); i++) {
        actag_sonar_geometry g = g_geo;
        g.aperture = bad[i];
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, run8(48, 48, 48, -1, &g, &g_p, NULL));
    }
    {
        actag_sonar_geometry g = g_geo;
        g.aperture = 6.28f; /* just below 2 pi */
        TEST_ASSERT_EQUAL_INT(0, run8(48, 48, 48, -1, &g, &g_p, NULL));
        /* with a bearing table the aperture is not used */
        for (i = 0; i < 48; i++)
            bearings[i] = 0.5f - 0.02f * (float)i;
        g.aperture = 0.0f;
        g.bearings = bearings;
        TEST_ASSERT_EQUAL_INT(0, run8(48, 48, 48, -1, &g, &g_p, NULL));
        /* not strictly monotonic, a NaN, an infinity */
        bearings[20] = bearings[19];
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, run8(48, 48, 48, -1, &g, &g_p, NULL));
        bearings[20] = bearings[18];
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, run8(48, 48, 48, -1, &g, &g_p, NULL));
        bearings[20] = NAN;
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, run8(48, 48, 48, -1, &g, &g_p, NULL));
        bearings[20] = -INFINITY;
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, run8(48, 48, 48, -1, &g, &g_p, NULL));
        g.bearings = NULL;
        g.flags = 4u; /* unknown flag */
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, run8(48, 48, 48, -1, &g, &g_p, NULL));
    }
}

static void test_radii_zero_and_larger_than_the_frame(void)
{
    actag_params p;
    defaults();
    p = g_p;
    p.tuning.median_radius = 0;
    p.tuning.threshold_radius = 0;
    TEST_ASSERT_EQUAL_INT(0, run8(48, 48, 48, -1, &g_geo, &p, NULL));
    p.tuning.median_radius = ACTAG_MEDIAN_MAX_RADIUS; /* 127 on a 16 x 16 frame */
    p.tuning.threshold_radius = ACTAG_MAX_THRESHOLD_RADIUS;
    TEST_ASSERT_EQUAL_INT(0, run8(16, 16, 16, -1, &g_geo, &p, NULL));
    TEST_ASSERT_EQUAL_INT(0, run8(2, 300, 300, -1, &g_geo, &p, NULL));
    p.tuning.median_radius = ACTAG_MEDIAN_MAX_RADIUS + 1;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, run8(48, 48, 48, -1, &g_geo, &p, NULL));
    p.tuning.median_radius = -1;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, run8(48, 48, 48, -1, &g_geo, &p, NULL));
    p.tuning.median_radius = 4;
    p.tuning.threshold_radius = ACTAG_MAX_THRESHOLD_RADIUS + 1;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, run8(48, 48, 48, -1, &g_geo, &p, NULL));
    p.tuning.threshold_radius = -1;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, run8(48, 48, 48, -1, &g_geo, &p, NULL));
}

static void test_corrections_above_the_limit(void)
{
    actag_params p;
    int maxc;
    defaults();
    p = g_p;
    maxc = actag_family_max_corrections(&g_fam);
    p.max_bit_corrections = maxc + 1;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_CORRECTIONS, run8(48, 48, 48, -1, &g_geo, &p, NULL));
    p.max_bit_corrections = -2;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_CORRECTIONS, run8(48, 48, 48, -1, &g_geo, &p, NULL));
    p.max_bit_corrections = maxc;
    TEST_ASSERT_EQUAL_INT(0, run8(48, 48, 48, -1, &g_geo, &p, NULL));
    p.max_bit_corrections = ACTAG_CORRECTIONS_AUTO;
    TEST_ASSERT_EQUAL_INT(0, run8(48, 48, 48, -1, &g_geo, &p, NULL));
}

static void test_workspace_one_byte_too_small(void)
{
    static uint8_t img[40 * 50];
    actag_frame f = {img, 40, 50, 50, 8};
    size_t need = actag_workspace_size(40, 50);
    uint8_t *ws = (uint8_t *)malloc(need + 1);
    actag_detection det[2];
    defaults();
    TEST_ASSERT_NOT_NULL(ws);
    TEST_ASSERT_EQUAL_UINT(ACTAG_WORKSPACE_SIZE(40, 50), need);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE, actag_detect(&f, &g_geo, &g_p, ws, need - 1, det, 2, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE, actag_detect(&f, &g_geo, &g_p, ws, 0, det, 2, NULL));
    TEST_ASSERT_EQUAL_INT(0, actag_detect(&f, &g_geo, &g_p, ws, need, det, 2, NULL));
    /* any alignment: an odd address works */
    TEST_ASSERT_EQUAL_INT(0, actag_detect(&f, &g_geo, &g_p, ws + 1, need, det, 2, NULL));
    free(ws);
}

/* Uniform and noise frames, 8 and 16 bit: no tags, no error. */
static void test_all_white_all_black_and_noise_frames(void)
{
    static uint8_t ws[ACTAG_WORKSPACE_SIZE(200, 180)];
    static uint16_t img16[200 * 180];
    actag_detection det[4];
    actag_stats st;
    int v, i;
    defaults();
    for (v = 0; v < 3; v++) {
        int val = v == 0 ? 255 : v == 1 ? 0 : -1;
        actag_frame f;
        TEST_ASSERT_EQUAL_INT(0, run8(200, 180, 180, val, &g_geo, &g_p, &st));
        for (i = 0; i < 200 * 180; i++)
            img16[i] = (uint16_t)(val == 255 ? 65535 : val == 0 ? 0 : (int)(tu_rand() & 0xffffu));
        f.data = img16;
        f.rows = 200;
        f.cols = 180;
        f.stride = 180;
        f.depth = 16;
        TEST_ASSERT_EQUAL_INT(0, actag_detect(&f, &g_geo, &g_p, ws, sizeof ws, det, 4, &st));
        TEST_ASSERT_EQUAL_INT(0, st.decoded);
        f.depth = 12;
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_detect(&f, &g_geo, &g_p, ws, sizeof ws, det, 4, NULL));
    }
}

/* A 16-bit frame at an odd address (e.g. behind a 1-byte packet header):
 * read safely (no misaligned uint16_t load; the sanitizer build checks) and
 * detected exactly as the aligned copy. */
static void test_odd_address_16bit_frame(void)
{
    static uint8_t ws[ACTAG_WORKSPACE_SIZE(463, 620)];
    int rows = 0, cols = 0, i;
    uint8_t *img = tu_read_pgm(EXAMPLE, &rows, &cols), *raw;
    uint16_t *al;
    actag_frame f;
    actag_detection a[4], b[4];
    int na, nb;
    defaults();
    TEST_ASSERT_NOT_NULL(img);
    al = (uint16_t *)malloc((size_t)rows * (size_t)cols * 2u);
    raw = (uint8_t *)malloc((size_t)rows * (size_t)cols * 2u + 1u);
    TEST_ASSERT_NOT_NULL(al);
    TEST_ASSERT_NOT_NULL(raw);
    for (i = 0; i < rows * cols; i++) {
        al[i] = (uint16_t)(img[i] * 257u + (uint16_t)(i & 7));
        memcpy(raw + 1 + 2 * (size_t)i, &al[i], 2); /* host order, odd address */
    }
    f.rows = rows;
    f.cols = cols;
    f.stride = cols;
    f.depth = 16;
    f.data = al;
    na = actag_detect(&f, &g_geo, &g_p, ws, sizeof ws, a, 4, NULL);
    f.data = raw + 1;
    nb = actag_detect(&f, &g_geo, &g_p, ws, sizeof ws, b, 4, NULL);
    TEST_ASSERT_EQUAL_INT(1, na);
    TEST_ASSERT_EQUAL_INT(0, a[0].id);
    TEST_ASSERT_EQUAL_INT(na, nb);
    TEST_ASSERT_EQUAL_MEMORY(a, b, sizeof a[0] * (size_t)na);
    free(img);
    free(al);
    free(raw);
}

/* The frame buffer may end at the last pixel (no padding after the last
 * row): with stride > cols the example frame in a tight malloc'd buffer
 * gives its tag (the sanitizer build catches any read past the end). */
static void test_tight_frame_buffer(void)
{
    static uint8_t ws[ACTAG_WORKSPACE_SIZE(463, 620)];
    int rows = 0, cols = 0, r, stride = 700;
    uint8_t *img = tu_read_pgm(EXAMPLE, &rows, &cols), *tight;
    actag_frame f;
    actag_detection det[4];
    defaults();
    TEST_ASSERT_NOT_NULL(img);
    tight = (uint8_t *)malloc((size_t)(rows - 1) * (size_t)stride + (size_t)cols);
    TEST_ASSERT_NOT_NULL(tight);
    for (r = 0; r < rows; r++)
        memcpy(tight + (size_t)r * (size_t)stride, img + (size_t)r * (size_t)cols, (size_t)cols);
    f.data = tight;
    f.rows = rows;
    f.cols = cols;
    f.stride = stride;
    f.depth = 8;
    TEST_ASSERT_EQUAL_INT(1, actag_detect(&f, &g_geo, &g_p, ws, sizeof ws, det, 4, NULL));
    TEST_ASSERT_EQUAL_INT(0, det[0].id);
    free(img);
    free(tight);
}

/* Issue 10: a huge tag size or a tiny azimuth step made search.c convert an
 * out-of-range float to int (undefined; INT_MIN on x86, saturation on ARM).
 * Now a parameter error or a correct empty result, the same everywhere
 * (the sanitizer build traps any float-to-int overflow). */
static void test_huge_tag_size_and_tiny_azimuth_step(void)
{
    static const float sizes[] = {1e30f, 3.0e38f, 1e6f, 1e-30f};
    actag_params p;
    actag_sonar_geometry g = g_geo;
    int i, rc;
    defaults();
    p = g_p;
    for (i = 0; i < (int)(sizeof sizes / sizeof sizes[0]); i++) {
        p.tag_size = sizes[i];
        rc = run8(96, 96, 96, -1, &g_geo, &p, NULL);
        /* a tag larger than sqrt(2) x max_range is refused (actag.h); a
         * tiny one is valid and finds nothing */
        if (sizes[i] > 1.0f)
            TEST_ASSERT_EQUAL_INT_MESSAGE(ACTAG_ERR_PARAM, rc, "huge tag_size");
        else
            TEST_ASSERT_EQUAL_INT_MESSAGE(0, rc, "tiny tag_size");
    }
    /* apertures whose azimuth step underflows are a geometry error */
    g.aperture = 1e-30f;
    rc = run8(96, 96, 96, -1, &g, &g_p, NULL);
    TEST_ASSERT_EQUAL_INT_MESSAGE(ACTAG_ERR_GEOMETRY, rc, "tiny aperture");
    g.aperture = 1e-7f;
    rc = run8(96, 96, 96, -1, &g, &g_p, NULL);
    TEST_ASSERT_EQUAL_INT_MESSAGE(ACTAG_ERR_GEOMETRY, rc, "small aperture");
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_zero_one_and_maximum_rows_cols);
    RUN_TEST(test_stride_smaller_than_cols);
    RUN_TEST(test_null_pointers);
    RUN_TEST(test_nan_infinite_negative_and_swapped_ranges);
    RUN_TEST(test_aperture_zero_or_above_two_pi);
    RUN_TEST(test_radii_zero_and_larger_than_the_frame);
    RUN_TEST(test_corrections_above_the_limit);
    RUN_TEST(test_workspace_one_byte_too_small);
    RUN_TEST(test_all_white_all_black_and_noise_frames);
    RUN_TEST(test_odd_address_16bit_frame);
    RUN_TEST(test_tight_frame_buffer);
    RUN_TEST(test_huge_tag_size_and_tiny_azimuth_step);
    return UNITY_END();
}
