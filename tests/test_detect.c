/* End-to-end sonar detection on the real frames, plus the API contract:
 * errors, workspace bounds, strides, 16-bit input, orientation flags, bearing
 * tables and determinism. The example frame and the pool subset ship in data/;
 * with --full-data, the 58 pool frames of the full data set (test_detect_full_data). */
#include "unity.h"
#include "test_util.h"

#include "actag/actag.h"

#include <math.h>

void setUp(void) {}
void tearDown(void) {}

/* Compile-time workspace, as firmware would declare it. */
static uint8_t g_ws[ACTAG_WORKSPACE_SIZE(463, 620)];

static uint8_t *g_img;
static int g_rows, g_cols;
static actag_family g_fam;
static actag_params g_p;
static const actag_sonar_geometry g_geo = {0.1f, 1.5f, 1.0472f, NULL, 0u};

/* SPEC section 6: the reference's corners, (row, col), tag order. */
static const float ref_rc[4][2] = {{145, 314}, {113, 339}, {103, 280}, {133, 244}};
static const float ref_polar[4][2] = {
    {1.0606f, -0.0076f}, {1.1576f, -0.0499f}, {1.1879f, 0.0499f}, {1.0970f, 0.1108f}};

static void load_example(void)
{
    if (g_img)
        return;
    g_img = tu_read_pgm(TU_DATA "/exampleSonarImage.pgm", &g_rows, &g_cols);
    TEST_ASSERT_NOT_NULL_MESSAGE(g_img, "cannot read exampleSonarImage.pgm");
    TEST_ASSERT_EQUAL_INT(463, g_rows);
    TEST_ASSERT_EQUAL_INT(620, g_cols);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &g_fam));
    actag_params_default(&g_p);
    g_p.family = &g_fam;
}

static int detect8(const uint8_t *px, int stride, const actag_sonar_geometry *geo,
                   actag_detection *det, int max_out)
{
    actag_frame f;
    f.data = px;
    f.rows = g_rows;
    f.cols = g_cols;
    f.stride = stride;
    f.depth = 8;
    return actag_detect(&f, geo, &g_p, g_ws, sizeof g_ws, det, max_out, NULL);
}

static void test_example_frame_gives_tag0_at_reference_corners(void)
{
    actag_detection det[8];
    int n, c;
    load_example();
    n = detect8(g_img, g_cols, &g_geo, det, 8);
    TEST_ASSERT_EQUAL_INT(1, n);
    TEST_ASSERT_EQUAL_INT(0, det[0].id);
    /* the reading the README shows: mirrored, 2 corrected bits, a margin
     * well above the least (nothing else checked a detection's hamming: a
     * detection reported with hamming + 100 passed) */
    TEST_ASSERT_EQUAL_INT(1, det[0].mirrored);
    TEST_ASSERT_EQUAL_INT(2, det[0].hamming);
    TEST_ASSERT_TRUE(det[0].decision_margin >= 10.0f * g_p.min_margin);
    /* refined corners (refine.h): within 4.5 pixels of the reference's quad
     * corners, which rest on the bloomed white blob's contour (the third
     * corner is 4.0 px off in column) */
    for (c = 0; c < 4; c++) {
        TEST_ASSERT_FLOAT_WITHIN(4.5f, ref_rc[c][0], det[0].corners[c].y);
        TEST_ASSERT_FLOAT_WITHIN(4.5f, ref_rc[c][1], det[0].corners[c].x);
        TEST_ASSERT_FLOAT_WITHIN(0.02f, ref_polar[c][0], det[0].range[c]);
        TEST_ASSERT_FLOAT_WITHIN(0.02f, ref_polar[c][1], det[0].azimuth[c]);
    }
    /* without the refinement, the quad's corners: within 2 pixels */
    g_p.tuning.refine_corners = 0;
    n = detect8(g_img, g_cols, &g_geo, det, 8);
    g_p.tuning.refine_corners = 1;
    TEST_ASSERT_EQUAL_INT(1, n);
    TEST_ASSERT_EQUAL_INT(0, det[0].id);
    for (c = 0; c < 4; c++) {
        TEST_ASSERT_FLOAT_WITHIN(2.0f, ref_rc[c][0], det[0].corners[c].y);
        TEST_ASSERT_FLOAT_WITHIN(2.0f, ref_rc[c][1], det[0].corners[c].x);
        TEST_ASSERT_FLOAT_WITHIN(0.01f, ref_polar[c][0], det[0].range[c]);
        TEST_ASSERT_FLOAT_WITHIN(0.01f, ref_polar[c][1], det[0].azimuth[c]);
    }
}

static void test_deterministic_and_seed_owned_by_call(void)
{
    actag_detection a[8], b[8];
    int na, nb;
    load_example();
    memset(a, 0, sizeof a);
    memset(b, 0, sizeof b);
    na = detect8(g_img, g_cols, &g_geo, a, 8);
    nb = detect8(g_img, g_cols, &g_geo, b, 8);
    TEST_ASSERT_EQUAL_INT(na, nb);
    TEST_ASSERT_EQUAL_MEMORY(a, b, sizeof a);
}

static void test_stride_with_garbage_padding(void)
{
    actag_detection a[8], b[8];
    int stride = g_cols + 37, r, na, nb;
    uint8_t *big;
    load_example();
    big = (uint8_t *)malloc((size_t)stride * (size_t)g_rows);
    TEST_ASSERT_NOT_NULL(big);
    tu_seed(11);
    for (r = 0; r < stride * g_rows; r++)
        big[r] = (uint8_t)tu_rand();
    for (r = 0; r < g_rows; r++)
        memcpy(big + (size_t)r * (size_t)stride, g_img + (size_t)r * (size_t)g_cols, (size_t)g_cols);
    memset(a, 0, sizeof a);
    memset(b, 0, sizeof b);
    na = detect8(g_img, g_cols, &g_geo, a, 8);
    nb = detect8(big, stride, &g_geo, b, 8);
    free(big);
    TEST_ASSERT_EQUAL_INT(na, nb);
    TEST_ASSERT_EQUAL_MEMORY(a, b, sizeof a);
}

static void test_16bit_frame_matches_8bit(void)
{
    /* A 16-bit frame is scaled by its own maximum M into 8 bits:
     * v8 = (v * 255 + M/2) / M. The 16-bit frame img * 257 must therefore
     * give exactly what the 8-bit frame (img * 255 + m/2) / m gives. */
    actag_detection a[8], b[8];
    actag_frame f;
    uint16_t *px16;
    uint8_t *norm8;
    int i, na, nb, n;
    unsigned m = 0;
    load_example();
    n = g_rows * g_cols;
    px16 = (uint16_t *)malloc((size_t)n * 2u);
    norm8 = (uint8_t *)malloc((size_t)n);
    TEST_ASSERT_NOT_NULL(px16);
    TEST_ASSERT_NOT_NULL(norm8);
    for (i = 0; i < n; i++)
        if (g_img[i] > m)
            m = g_img[i];
    TEST_ASSERT_GREATER_THAN(0, m);
    for (i = 0; i < n; i++) {
        px16[i] = (uint16_t)(g_img[i] * 257u);
        norm8[i] = (uint8_t)((g_img[i] * 255u + m / 2u) / m);
    }
    memset(a, 0, sizeof a);
    memset(b, 0, sizeof b);
    na = detect8(norm8, g_cols, &g_geo, a, 8);
    f.data = px16;
    f.rows = g_rows;
    f.cols = g_cols;
    f.stride = g_cols;
    f.depth = 16;
    nb = actag_detect(&f, &g_geo, &g_p, g_ws, sizeof g_ws, b, 8, NULL);
    TEST_ASSERT_EQUAL_INT(1, na);
    TEST_ASSERT_EQUAL_INT(na, nb);
    TEST_ASSERT_EQUAL_MEMORY(a, b, sizeof a);
    free(px16);
    free(norm8);
}

/* The example frame in orientation `mode` (bit 0: rows flipped, bit 1:
 * columns flipped) into flip, and the geometry flags that say so. */
static unsigned flip_example(int mode, uint8_t *flip)
{
    int r, c, fr = mode & 1, fc = mode >> 1;
    for (r = 0; r < g_rows; r++)
        for (c = 0; c < g_cols; c++)
            flip[(size_t)(fr ? g_rows - 1 - r : r) * (size_t)g_cols +
                 (size_t)(fc ? g_cols - 1 - c : c)] = g_img[(size_t)r * (size_t)g_cols + (size_t)c];
    return (fr ? ACTAG_RANGE_ASCENDING : 0u) | (fc ? ACTAG_AZIMUTH_ASCENDING : 0u);
}

/* Flipping the frame and saying so with the flags gives the same tag, the
 * same polar corners and the same mirrored flag. */
static void test_orientation_flags(void)
{
    actag_detection a[8], b[8];
    actag_sonar_geometry g2 = g_geo;
    uint8_t *flip;
    int k, na, nb, mode;
    load_example();
    flip = (uint8_t *)malloc((size_t)g_rows * (size_t)g_cols);
    TEST_ASSERT_NOT_NULL(flip);
    na = detect8(g_img, g_cols, &g_geo, a, 8);
    TEST_ASSERT_EQUAL_INT(1, na);
    for (mode = 1; mode <= 3; mode++) {
        g2.flags = flip_example(mode, flip);
        nb = detect8(flip, g_cols, &g2, b, 8);
        TEST_ASSERT_EQUAL_INT(1, nb);
        TEST_ASSERT_EQUAL_INT(a[0].id, b[0].id);
        TEST_ASSERT_EQUAL_INT(a[0].mirrored, b[0].mirrored);
        for (k = 0; k < 4; k++) {
            TEST_ASSERT_FLOAT_WITHIN(0.006f, a[0].range[k], b[0].range[k]);
            TEST_ASSERT_FLOAT_WITHIN(0.006f, a[0].azimuth[k], b[0].azimuth[k]);
        }
    }
    free(flip);
}

/* The handedness prior (actag_params.handedness) in every frame
 * orientation: the tag's own handedness keeps it (same ID, corners within a
 * pixel), the other one removes it, and the paper's binary decoder obeys it
 * too. */
static void test_handedness_prior(void)
{
    actag_detection a[8], b[8];
    actag_sonar_geometry g2 = g_geo;
    actag_params keep = g_p;
    uint8_t *flip;
    int k, na, mode, dm;
    load_example();
    flip = (uint8_t *)malloc((size_t)g_rows * (size_t)g_cols);
    TEST_ASSERT_NOT_NULL(flip);
    na = detect8(g_img, g_cols, &g_geo, a, 8);
    TEST_ASSERT_EQUAL_INT(1, na);
    for (dm = 0; dm < 2; dm++)
        for (mode = 0; mode <= 3; mode++) {
            g2.flags = flip_example(mode, flip);
            g_p.tuning.decode_mode = dm ? ACTAG_DECODE_BINARY : ACTAG_DECODE_FIT;
            g_p.handedness = a[0].mirrored ? ACTAG_HANDEDNESS_MIRRORED : ACTAG_HANDEDNESS_UNMIRRORED;
            if (dm == 0) {
                TEST_ASSERT_EQUAL_INT(1, detect8(flip, g_cols, &g2, b, 8));
                TEST_ASSERT_EQUAL_INT(a[0].id, b[0].id);
                TEST_ASSERT_EQUAL_INT(a[0].mirrored, b[0].mirrored);
                for (k = 0; k < 4; k++) {
                    TEST_ASSERT_FLOAT_WITHIN(0.006f, a[0].range[k], b[0].range[k]);
                    TEST_ASSERT_FLOAT_WITHIN(0.006f, a[0].azimuth[k], b[0].azimuth[k]);
                }
            } else {
                /* the paper's binary decoder reads the example tag too */
                TEST_ASSERT_EQUAL_INT(1, detect8(flip, g_cols, &g2, b, 8));
                TEST_ASSERT_EQUAL_INT(a[0].id, b[0].id);
                TEST_ASSERT_EQUAL_INT(a[0].mirrored, b[0].mirrored);
            }
            g_p.handedness = a[0].mirrored ? ACTAG_HANDEDNESS_UNMIRRORED : ACTAG_HANDEDNESS_MIRRORED;
            TEST_ASSERT_EQUAL_INT(0, detect8(flip, g_cols, &g2, b, 8));
            g_p = keep;
        }
    free(flip);
}

static void test_bearing_table_equivalent_to_aperture(void)
{
    actag_detection a[8], b[8];
    actag_sonar_geometry g2 = g_geo;
    static float bearings[620];
    int c, na, nb;
    load_example();
    for (c = 0; c < g_cols; c++)
        bearings[c] = 0.5f * 1.0472f - (float)c * 1.0472f / 619.0f;
    g2.bearings = bearings;
    na = detect8(g_img, g_cols, &g_geo, a, 8);
    nb = detect8(g_img, g_cols, &g2, b, 8);
    TEST_ASSERT_EQUAL_INT(na, nb);
    TEST_ASSERT_EQUAL_INT(1, nb);
    /* the refinement's iterations carry the tables' last-bit differences:
     * 1e-4 rad is 0.06 beam */
    for (c = 0; c < 4; c++)
        TEST_ASSERT_FLOAT_WITHIN(1e-4f, a[0].azimuth[c], b[0].azimuth[c]);
}

static void test_errors_and_workspace_bounds(void)
{
    actag_detection det[4];
    actag_frame f;
    actag_stats st;
    actag_params p;
    actag_sonar_geometry bad = g_geo;
    size_t need;
    load_example();
    f.data = g_img;
    f.rows = g_rows;
    f.cols = g_cols;
    f.stride = g_cols;
    f.depth = 8;
    need = actag_workspace_size(g_rows, g_cols);
    TEST_ASSERT_EQUAL_UINT(ACTAG_WORKSPACE_SIZE(463, 620), need);
    TEST_ASSERT_EQUAL_UINT(sizeof g_ws, need);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE, actag_detect(&f, &g_geo, &g_p, g_ws, need - 1, det, 4, NULL));
    TEST_ASSERT_EQUAL_INT(1, actag_detect(&f, &g_geo, &g_p, g_ws, need, det, 4, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_detect(NULL, &g_geo, &g_p, g_ws, need, det, 4, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_detect(&f, NULL, &g_p, g_ws, need, det, 4, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_detect(&f, &g_geo, NULL, g_ws, need, det, 4, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_detect(&f, &g_geo, &g_p, NULL, need, det, 4, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_detect(&f, &g_geo, &g_p, g_ws, need, NULL, 4, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_detect(&f, &g_geo, &g_p, g_ws, need, det, -1, NULL));
    /* max_out 0: nothing written, the tag is counted as dropped */
    TEST_ASSERT_EQUAL_INT(0, actag_detect(&f, &g_geo, &g_p, g_ws, need, NULL, 0, &st));
    TEST_ASSERT_EQUAL_INT(1, st.dropped);
    f.stride = g_cols - 1;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_detect(&f, &g_geo, &g_p, g_ws, need, det, 4, NULL));
    f.stride = g_cols;
    f.depth = 12;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_detect(&f, &g_geo, &g_p, g_ws, need, det, 4, NULL));
    f.depth = 8;
    f.rows = 0;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_detect(&f, &g_geo, &g_p, g_ws, need, det, 4, NULL));
    f.rows = g_rows;
    bad.max_range = 0.05f;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, actag_detect(&f, &bad, &g_p, g_ws, need, det, 4, NULL));
    p = g_p;
    p.max_bit_corrections = 5; /* h10 allows 4 */
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_CORRECTIONS, actag_detect(&f, &g_geo, &p, g_ws, need, det, 4, NULL));
    p = g_p;
    p.family = NULL;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_detect(&f, &g_geo, &p, g_ws, need, det, 4, NULL));
    p = g_p;
    p.tag_size = 0.0f;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_detect(&f, &g_geo, &p, g_ws, need, det, 4, NULL));
    p = g_p;
    p.tuning.median_radius = -1;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_detect(&f, &g_geo, &p, g_ws, need, det, 4, NULL));
    p = g_p;
    p.tuning.quad.inlier_ratio = 1.5f;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_detect(&f, &g_geo, &p, g_ws, need, det, 4, NULL));
    TEST_ASSERT_EQUAL_UINT(0, actag_workspace_size(0, 5));
    TEST_ASSERT_NULL(actag_workspace_bitmap(NULL, 5, 5));
}

static void test_tiny_and_constant_frames(void)
{
    static const int sizes[][2] = {{1, 1}, {1, 7}, {9, 1}, {2, 2}, {40, 3}};
    uint8_t px[400];
    actag_detection det[4];
    actag_frame f;
    int i, v;
    load_example();
    for (i = 0; i < 5; i++)
        for (v = 0; v < 256; v += 255) {
            memset(px, v, sizeof px);
            f.data = px;
            f.rows = sizes[i][0];
            f.cols = sizes[i][1];
            f.stride = f.cols;
            f.depth = 8;
            TEST_ASSERT_EQUAL_INT(0, actag_detect(&f, &g_geo, &g_p, g_ws, sizeof g_ws, det, 4, NULL));
        }
}

/* The 58 pool frames (every 10th of the reference's recording). Classes
 * judged by eye on full-resolution crops of every frame: */
static int pool_class(int frame)
{
    static const int tag_free[] = {11, 111, 211, 321, 421, 521};
    static const int partial[] = {331, 341, 351, 361, 371}; /* part of the tag out of view */
    int i;
    for (i = 0; i < 6; i++)
        if (frame == tag_free[i])
            return 0;
    for (i = 0; i < 5; i++)
        if (frame == partial[i])
            return 1;
    return 2; /* the whole tag pattern is visible */
}

/* Detection on the pool frames numbered frames[0..nframes-1] in the folder dir
 * (f_NNNN.pgm), stored as recorded or (flags) the other way round. */
static int run_pool(const char *dir, const int *frames, int nframes, unsigned flags,
                    int *visible, int *found, int *wrong, int *in_tag_free)
{
    static uint8_t ws[ACTAG_WORKSPACE_SIZE(530, 512)];
    static uint8_t flipped[530 * 512];
    int i;
    actag_family fam;
    actag_params p;
    actag_sonar_geometry g = {0.1f, 1.5f, 1.0472f, NULL, 0u};
    g.flags = flags;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
    actag_params_default(&p);
    p.family = &fam;
    *visible = *found = *wrong = *in_tag_free = 0;
    for (i = 0; i < nframes; i++) {
        char path[512];
        int rows = 0, cols = 0, n, k, frame = frames[i], cls = pool_class(frame), hit = 0;
        uint8_t *img;
        actag_frame f;
        actag_detection det[8];
        snprintf(path, sizeof path, "%s/f_%04d.pgm", dir, frame);
        img = tu_read_pgm(path, &rows, &cols);
        TEST_ASSERT_EQUAL_INT(530, rows);
        TEST_ASSERT_EQUAL_INT(512, cols);
        if (flags) { /* the same frame stored the other way round */
            int r, c;
            for (r = 0; r < rows; r++)
                for (c = 0; c < cols; c++)
                    flipped[(size_t)((flags & ACTAG_RANGE_ASCENDING) ? rows - 1 - r : r) * 512u +
                            (size_t)((flags & ACTAG_AZIMUTH_ASCENDING) ? cols - 1 - c : c)] =
                        img[(size_t)r * 512u + (size_t)c];
            memcpy(img, flipped, sizeof flipped);
        }
        f.data = img;
        f.rows = rows;
        f.cols = cols;
        f.stride = cols;
        f.depth = 8;
        n = actag_detect(&f, &g, &p, ws, sizeof ws, det, 8, NULL);
        TEST_ASSERT_GREATER_OR_EQUAL(0, n);
        for (k = 0; k < n; k++) {
            if (det[k].id != 0)
                (*wrong)++;
            else
                hit = 1;
        }
        if (cls == 0)
            *in_tag_free += n;
        if (cls == 2) {
            (*visible)++;
            *found += hit;
        }
        free(img);
    }
    return 0;
}

/* Tag 0 in at least 34 of the 47 frames where the whole tag is visible,
 * no wrong ID anywhere, nothing in the tag-free frames. (39 before the
 * decoder's template check and look-elsewhere-corrected decision margins,
 * which removed every wrong ID and mirrored-flag error on 1,000 simulated
 * views in each of two settings; the readings lost here had hamming 3 or a
 * likelihood ratio below the allowance.) */
static int g_all_frames[58];

static void test_pool_frames(void)
{
    int visible, found, wrong, tag_free;
    char msg[128];
    run_pool(TU_FULL_DATA "/sonar/pool-video", g_all_frames, 58, 0u, &visible, &found, &wrong,
             &tag_free);
    snprintf(msg, sizeof msg, "tag 0 in %d of %d visible frames, %d wrong, %d in tag-free",
             found, visible, wrong, tag_free);
    TEST_MESSAGE(msg);
    TEST_ASSERT_EQUAL_INT(47, visible);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, wrong, msg);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, tag_free, msg);
    TEST_ASSERT_GREATER_OR_EQUAL_MESSAGE(34, found, msg);
}

/* The same frames stored nearest-range-first and most-negative-bearing
 * first (what many drivers emit), said so with the flags. */
static void test_pool_frames_other_orientation(void)
{
    int visible, found, wrong, tag_free;
    char msg[128];
    if (TU_EMULATED) /* another minute under QEMU; test_pool_frames runs all 58 there */
        TEST_IGNORE_MESSAGE("host suite only (emulated: the stored orientation in test_pool_frames)");
    run_pool(TU_FULL_DATA "/sonar/pool-video", g_all_frames, 58,
             ACTAG_RANGE_ASCENDING | ACTAG_AZIMUTH_ASCENDING, &visible, &found, &wrong, &tag_free);
    snprintf(msg, sizeof msg, "flipped: tag 0 in %d of %d visible frames, %d wrong, %d in tag-free",
             found, visible, wrong, tag_free);
    TEST_MESSAGE(msg);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, wrong, msg);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, tag_free, msg);
    TEST_ASSERT_GREATER_OR_EQUAL_MESSAGE(34, found, msg); /* 37 before the template check */
}

/* The pool frames that ship in data/pool-video (data/README.md): tag 0 in each
 * of the four tagged ones, both storage orientations, and nothing else; nothing
 * in the two tag-free ones. */
static void test_pool_subset(void)
{
    static const int frames[6] = {1, 11, 291, 421, 491, 561};
    int o, visible, found, wrong, tag_free;
    for (o = 0; o < 2; o++) {
        char msg[160];
        run_pool(TU_DATA "/pool-video", frames, 6,
                 o ? ACTAG_RANGE_ASCENDING | ACTAG_AZIMUTH_ASCENDING : 0u, &visible, &found,
                 &wrong, &tag_free);
        snprintf(msg, sizeof msg, "%s: tag 0 in %d of %d tagged frames, %d wrong, %d in tag-free",
                 o ? "flipped" : "as recorded", found, visible, wrong, tag_free);
        TEST_MESSAGE(msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(4, visible, msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(4, found, msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, wrong, msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, tag_free, msg);
    }
}

/* ---- actag_detect_inplace: the same detections from a 128 KiB workspace ---- */

/* Sized for the largest frame here (530 x 620): one workspace serves all. */
static uint8_t g_ws_ip[ACTAG_WORKSPACE_SIZE_INPLACE(530, 620)];

/* actag_detect and actag_detect_inplace on the same pixels (depth 8 or 16,
 * row stride `stride` samples): with the corner refinement off the outputs
 * and statistics are equal byte for byte; with it on (the default) the same
 * tags, IDs, handedness, hamming, support and margins, the corners within
 * 2.5 pixels (refined on the filtered frame instead of the raw one; on the
 * 4 x 58 pool frames the 580 corners moved by 0.64 px median, 1.52 at the
 * 99th percentile, 2.13 at most). Returns the number of detections. */
static int compare_inplace(const void *px, int depth, int rows, int cols, int stride,
                           const actag_sonar_geometry *geo, const char *what)
{
    size_t bytes = (size_t)rows * (size_t)stride * (depth == 16 ? 2u : 1u);
    uint8_t *copy = (uint8_t *)malloc(bytes);
    actag_detection a[8], b[8];
    actag_stats sa, sb;
    actag_frame f, fc;
    actag_params p = g_p;
    int refine, na = 0, nb, k, c;
    char msg[200];
    TEST_ASSERT_NOT_NULL(copy);
    f.data = px;
    f.rows = rows;
    f.cols = cols;
    f.stride = stride;
    f.depth = depth;
    fc = f;
    fc.data = copy;
    for (refine = 0; refine <= 1; refine++) {
        p.tuning.refine_corners = refine;
        memset(a, 0, sizeof a);
        memset(b, 0, sizeof b);
        memcpy(copy, px, bytes);
        na = actag_detect(&f, geo, &p, g_ws, sizeof g_ws, a, 8, &sa);
        nb = actag_detect_inplace(&fc, geo, &p, g_ws_ip, sizeof g_ws_ip, b, 8, &sb);
        snprintf(msg, sizeof msg, "%s, refine %d: %d tags, in place %d", what, refine, na, nb);
        TEST_ASSERT_GREATER_OR_EQUAL_MESSAGE(0, na, msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(na, nb, msg);
        TEST_ASSERT_EQUAL_MEMORY_MESSAGE(&sa, &sb, sizeof sa, msg);
        if (!refine) {
            TEST_ASSERT_EQUAL_MEMORY_MESSAGE(a, b, sizeof a, msg);
            continue;
        }
        for (k = 0; k < na; k++) {
            TEST_ASSERT_EQUAL_INT_MESSAGE(a[k].id, b[k].id, msg);
            TEST_ASSERT_EQUAL_INT_MESSAGE(a[k].hamming, b[k].hamming, msg);
            TEST_ASSERT_EQUAL_INT_MESSAGE(a[k].mirrored, b[k].mirrored, msg);
            TEST_ASSERT_EQUAL_MEMORY_MESSAGE(&a[k].inlier_ratio, &b[k].inlier_ratio,
                                             sizeof a[k].inlier_ratio, msg);
            TEST_ASSERT_EQUAL_MEMORY_MESSAGE(&a[k].decision_margin, &b[k].decision_margin,
                                             sizeof a[k].decision_margin, msg);
            for (c = 0; c < 4; c++) {
                TEST_ASSERT_FLOAT_WITHIN_MESSAGE(2.5f, a[k].corners[c].x, b[k].corners[c].x, msg);
                TEST_ASSERT_FLOAT_WITHIN_MESSAGE(2.5f, a[k].corners[c].y, b[k].corners[c].y, msg);
            }
        }
    }
    free(copy);
    return na;
}

static void test_inplace_same_detections(void)
{
    uint8_t *flip;
    uint16_t *px16;
    actag_sonar_geometry g2 = g_geo;
    int mode, i, n = 0;
    load_example();
    TEST_ASSERT_TRUE(ACTAG_WORKSPACE_SIZE_INPLACE(530, 512) <= 131072u); /* a 128 KiB DTCM */
    TEST_ASSERT_EQUAL_UINT(ACTAG_WORKSPACE_SIZE_INPLACE(530, 512),
                           actag_workspace_size_inplace(530, 512));
    flip = (uint8_t *)malloc((size_t)g_rows * (size_t)g_cols);
    px16 = (uint16_t *)malloc((size_t)g_rows * (size_t)g_cols * 2u);
    TEST_ASSERT_TRUE(flip && px16);
    for (mode = 0; mode < 4; mode++) {
        char what[64];
        g2.flags = flip_example(mode, flip);
        snprintf(what, sizeof what, "example frame, orientation %d", mode);
        n += compare_inplace(flip, 8, g_rows, g_cols, g_cols, &g2, what);
    }
    TEST_ASSERT_EQUAL_INT(4, n); /* the tag, in each orientation */
    /* 16-bit samples (the filter scales them as it copies source rows) */
    for (i = 0; i < g_rows * g_cols; i++)
        px16[i] = (uint16_t)(g_img[i] * 251u + (unsigned)(i % 7));
    TEST_ASSERT_EQUAL_INT(1, compare_inplace(px16, 16, g_rows, g_cols, g_cols, &g_geo,
                                             "example frame, 16-bit"));
    free(flip);
    free(px16);
}

/* The in-place entry's own checks: the median radius it supports, its
 * workspace size; on such errors the caller's pixels are untouched. */
static void test_inplace_errors(void)
{
    actag_frame f;
    actag_params p = g_p;
    actag_detection det[8];
    actag_error_detail d;
    uint8_t *copy;
    load_example();
    copy = (uint8_t *)malloc((size_t)g_rows * (size_t)g_cols);
    TEST_ASSERT_NOT_NULL(copy);
    memcpy(copy, g_img, (size_t)g_rows * (size_t)g_cols);
    f.data = copy;
    f.rows = g_rows;
    f.cols = g_cols;
    f.stride = g_cols;
    f.depth = 8;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE,
                          actag_detect_inplace(&f, &g_geo, &p, g_ws_ip,
                                               actag_workspace_size_inplace(g_rows, g_cols) - 1u,
                                               det, 8, NULL));
    p.tuning.median_radius = ACTAG_MEDIAN_INPLACE_MAX_RADIUS + 1;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_check(&f, &g_geo, &p, sizeof g_ws, 8, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM,
                          actag_check_inplace(&f, &g_geo, &p, sizeof g_ws_ip, 8, &d));
    TEST_ASSERT_EQUAL_STRING("tuning.median_radius", d.field);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM,
                          actag_detect_inplace(&f, &g_geo, &p, g_ws_ip, sizeof g_ws_ip, det, 8,
                                               NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL,
                          actag_detect_inplace(&f, &g_geo, &g_p, NULL, sizeof g_ws_ip, det, 8,
                                               NULL));
    /* no output array for 8 detections */
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL,
                          actag_detect_inplace(&f, &g_geo, &g_p, g_ws_ip, sizeof g_ws_ip, NULL, 8,
                                               NULL));
    /* a frame size or geometry the library refuses */
    {
        actag_frame f2 = f;
        actag_sonar_geometry g2 = g_geo;
        f2.stride = f.cols - 1;
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE,
                              actag_detect_inplace(&f2, &g_geo, &g_p, g_ws_ip, sizeof g_ws_ip,
                                                   det, 8, NULL));
        g2.max_range = g2.min_range;
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY,
                              actag_detect_inplace(&f, &g2, &g_p, g_ws_ip, sizeof g_ws_ip, det,
                                                   8, NULL));
    }
    TEST_ASSERT_EQUAL_MEMORY(g_img, copy, (size_t)g_rows * (size_t)g_cols);
    TEST_ASSERT_EQUAL_UINT(0u, actag_workspace_size_inplace(0, 5));
    free(copy);
}

/* The pool frames (numbers frames[0..n-1] in dir) in all four storage
 * orientations through compare_inplace; returns the tags found. */
static int inplace_pool(const char *dir, const int *frames, int n)
{
    static uint8_t flipped[530 * 512];
    int i, o, found = 0;
    load_example(); /* g_p */
    for (i = 0; i < n; i++)
        for (o = 0; o < 4; o++) {
            char path[512], what[64];
            int rows = 0, cols = 0, r, c;
            actag_sonar_geometry g = {0.1f, 1.5f, 1.0472f, NULL, 0u};
            uint8_t *img;
            if (TU_EMULATED && o != 0 && o != 3 && i % 4 != 0)
                continue; /* under QEMU: two orientations, every 4th frame all four */
            snprintf(path, sizeof path, "%s/f_%04d.pgm", dir, frames[i]);
            img = tu_read_pgm(path, &rows, &cols);
            TEST_ASSERT_EQUAL_INT(530, rows);
            TEST_ASSERT_EQUAL_INT(512, cols);
            g.flags = ((o & 1) ? ACTAG_RANGE_ASCENDING : 0u) | ((o & 2) ? ACTAG_AZIMUTH_ASCENDING : 0u);
            for (r = 0; r < rows; r++)
                for (c = 0; c < cols; c++)
                    flipped[(size_t)((o & 1) ? rows - 1 - r : r) * 512u +
                            (size_t)((o & 2) ? cols - 1 - c : c)] = img[(size_t)r * 512u + (size_t)c];
            snprintf(what, sizeof what, "f_%04d orientation %d", frames[i], o);
            found += compare_inplace(flipped, 8, rows, cols, cols, &g, what);
            free(img);
        }
    return found;
}

static void test_inplace_pool_subset(void)
{
    static const int frames[6] = {1, 11, 291, 421, 491, 561};
    /* frames 11 and 421 are tag-free; the other four show tag 0 in every
     * orientation (under QEMU: 2 orientations, frames 1 and 491 all 4) */
    TEST_ASSERT_EQUAL_INT(TU_EMULATED ? 12 : 16, inplace_pool(TU_DATA "/pool-video", frames, 6));
}

static void test_inplace_pool_frames(void)
{
    char msg[64];
    int found = inplace_pool(TU_FULL_DATA "/sonar/pool-video", g_all_frames, 58);
    snprintf(msg, sizeof msg, "in place and not: %d tags in 4 x 58 frames", found);
    TEST_MESSAGE(msg);
    /* 148 at the session of this check (37 of 47 visible per orientation);
     * issue 8's worst seen is 34 per orientation: at least 35 x 4 here
     * (under QEMU fewer orientations run) */
    TEST_ASSERT_GREATER_OR_EQUAL(TU_EMULATED ? 1 : 140, found);
}

int main(int argc, char **argv)
{
    int i;
    UNITY_BEGIN();
    if (tu_full_data(argc, argv)) {
        for (i = 0; i < 58; i++)
            g_all_frames[i] = 1 + 10 * i;
        RUN_TEST(test_pool_frames);
        RUN_TEST(test_pool_frames_other_orientation);
        RUN_TEST(test_inplace_pool_frames);
        return UNITY_END();
    }
    RUN_TEST(test_example_frame_gives_tag0_at_reference_corners);
    RUN_TEST(test_deterministic_and_seed_owned_by_call);
    RUN_TEST(test_stride_with_garbage_padding);
    RUN_TEST(test_16bit_frame_matches_8bit);
    RUN_TEST(test_orientation_flags);
    RUN_TEST(test_handedness_prior);
    RUN_TEST(test_bearing_table_equivalent_to_aperture);
    RUN_TEST(test_errors_and_workspace_bounds);
    RUN_TEST(test_tiny_and_constant_frames);
    RUN_TEST(test_pool_subset);
    RUN_TEST(test_inplace_same_detections);
    RUN_TEST(test_inplace_errors);
    RUN_TEST(test_inplace_pool_subset);
    free(g_img);
    return UNITY_END();
}
