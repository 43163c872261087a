/* The AprilTag adapter's public functions (optical/include/actag/
 * actag_apriltag.h) against their documented failure values (issue 10:
 * every public function's error codes documented and each covered by a
 * test; the core library's are in tests/test_error_codes.c, the table of
 * both in docs/error_codes.md): each NULL / -1 / ACTAG_ERR_* return the
 * header lists, triggered once with a minimal input, and one successful
 * call per function, on one rendered AcTag24h10 tag (no ../shared data). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "unity.h"

#include "actag/actag_apriltag.h"
#include "actag/render.h"

#include <apriltag/apriltag.h>
#include <apriltag/common/image_u8.h>
#include <apriltag/common/zarray.h>

#define CELL 10
#define MARGIN 10
#define SIDE 90 /* 24 bits: 7 cells of 10 px plus two 10 px margins */

static apriltag_detector_t *g_td;
static uint8_t g_img[SIDE * SIDE];
static zarray_t *g_dets;

void setUp(void)
{
    g_td = NULL;
    g_dets = NULL;
}

void tearDown(void)
{
    if (g_dets)
        apriltag_detections_destroy(g_dets);
    if (g_td)
        apriltag_detector_destroy(g_td);
    g_dets = NULL;
    g_td = NULL;
}

/* a detector for AcTag24h10 and the detections of tag 0 rendered for a camera
 * (then inverted, as the manual says) */
static const apriltag_detection_t *detect_tag0(void)
{
    actag_family core;
    apriltag_detection_t *det;
    image_u8_t im = {.width = SIDE, .height = SIDE, .stride = SIDE, .buf = g_img};
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &core));
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_render_tag(&core, 0, CELL, MARGIN, 128, 1, g_img, SIDE,
                                                     sizeof g_img));
    actag_apriltag_invert(&im);
    g_td = apriltag_detector_create();
    TEST_ASSERT_NOT_NULL(g_td);
    g_td->nthreads = 1;
    g_td->quad_decimate = 1.0f;
    apriltag_detector_add_family_bits(g_td, actag_apriltag_family("AcTag24h10"), 0);
    g_dets = actag_apriltag_detect(g_td, &im);
    TEST_ASSERT_NOT_NULL(g_dets);
    TEST_ASSERT_EQUAL_INT(1, zarray_size(g_dets));
    zarray_get(g_dets, 0, &det);
    TEST_ASSERT_EQUAL_INT(0, det->id);
    return det;
}

static void test_family_and_names(void)
{
    int n = actag_apriltag_family_count(), i;
    TEST_ASSERT_EQUAL_INT(actag_family_count(), n);
    TEST_ASSERT_NULL(actag_apriltag_family(NULL));
    TEST_ASSERT_NULL(actag_apriltag_family("AcTag24h99"));
    TEST_ASSERT_NULL(actag_apriltag_family_name(-1));
    TEST_ASSERT_NULL(actag_apriltag_family_name(n));
    for (i = 0; i < n; i++) {
        const char *name = actag_apriltag_family_name(i);
        apriltag_family_t *f;
        TEST_ASSERT_NOT_NULL(name);
        f = actag_apriltag_family(name);
        TEST_ASSERT_NOT_NULL(f);
        TEST_ASSERT_EQUAL_INT(0, strcmp(name, f->name));
    }
}

static void test_family_create_and_destroy(void)
{
    apriltag_family_t *stat = actag_apriltag_family("AcTag24h10"), *copy;
    TEST_ASSERT_NULL(actag_apriltag_family_create(NULL));
    TEST_ASSERT_NULL(actag_apriltag_family_create("AcTag24h99"));
    copy = actag_apriltag_family_create("AcTag24h10");
    TEST_ASSERT_NOT_NULL(copy);
    TEST_ASSERT_TRUE(copy != stat);
    TEST_ASSERT_NULL(copy->impl);
    TEST_ASSERT_EQUAL_INT(0, strcmp(copy->name, stat->name));
    actag_apriltag_family_destroy(copy);
    actag_apriltag_family_destroy(NULL); /* ignored */
    actag_apriltag_family_destroy(stat); /* static: ignored, still usable */
    TEST_ASSERT_TRUE(actag_apriltag_family("AcTag24h10") == stat);
    TEST_ASSERT_EQUAL_INT(0, strcmp(stat->name, "AcTag24h10"));
}

static void test_max_bits_corrected(void)
{
    TEST_ASSERT_EQUAL_INT(-1, actag_apriltag_max_bits_corrected(NULL));
    TEST_ASSERT_EQUAL_INT(3, actag_apriltag_max_bits_corrected(actag_apriltag_family("AcTag24h10")));
    if (actag_apriltag_family("AcTag24h4"))
        TEST_ASSERT_EQUAL_INT(1, actag_apriltag_max_bits_corrected(actag_apriltag_family("AcTag24h4")));
}

static void test_detect(void)
{
    static uint8_t small[7 * 7];
    /* image_u8_t's sizes are const: one struct per bad case */
    image_u8_t im = {.width = 7, .height = 7, .stride = 7, .buf = small};
    image_u8_t nobuf = {.width = 7, .height = 7, .stride = 7, .buf = NULL};
    image_u8_t nowidth = {.width = 0, .height = 7, .stride = 7, .buf = small};
    image_u8_t negheight = {.width = 7, .height = -1, .stride = 7, .buf = small};
    image_u8_t narrow = {.width = 7, .height = 7, .stride = 6, .buf = small};
    zarray_t *z;
    g_td = apriltag_detector_create();
    TEST_ASSERT_NOT_NULL(g_td);
    g_td->nthreads = 1;
    apriltag_detector_add_family_bits(g_td, actag_apriltag_family("AcTag24h10"), 0);
    TEST_ASSERT_NULL(actag_apriltag_detect(NULL, &im));
    TEST_ASSERT_NULL(actag_apriltag_detect(g_td, NULL));
    TEST_ASSERT_NULL(actag_apriltag_detect(g_td, &nobuf));
    TEST_ASSERT_NULL(actag_apriltag_detect(g_td, &nowidth));
    TEST_ASSERT_NULL(actag_apriltag_detect(g_td, &negheight));
    TEST_ASSERT_NULL(actag_apriltag_detect(g_td, &narrow));
    /* under 4 * quad_decimate (2: 8) pixels: an empty array, not a crash */
    memset(small, 128, sizeof small);
    z = actag_apriltag_detect(g_td, &im);
    TEST_ASSERT_NOT_NULL(z);
    TEST_ASSERT_EQUAL_INT(0, zarray_size(z));
    apriltag_detections_destroy(z);
    apriltag_detector_destroy(g_td);
    g_td = NULL;
    /* success: the rendered tag */
    (void)detect_tag0();
}

static void test_invert(void)
{
    uint8_t px[6] = {0, 10, 255, 1, 2, 3};
    image_u8_t im = {.width = 3, .height = 1, .stride = 6, .buf = px};
    image_u8_t nobuf = {.width = 3, .height = 1, .stride = 6, .buf = NULL};
    actag_apriltag_invert(NULL); /* no-op */
    actag_apriltag_invert(&nobuf);
    actag_apriltag_invert(&im);
    TEST_ASSERT_EQUAL_UINT8(255, px[0]);
    TEST_ASSERT_EQUAL_UINT8(245, px[1]);
    TEST_ASSERT_EQUAL_UINT8(0, px[2]);
    TEST_ASSERT_EQUAL_UINT8(1, px[3]); /* beyond width: untouched */
}

static void test_corners_to_actag(void)
{
    const apriltag_detection_t *det = detect_tag0();
    double c[4][2] = {{7, 7}, {7, 7}, {7, 7}, {7, 7}};
    actag_apriltag_corners_to_actag(NULL, c); /* no-op: out untouched */
    TEST_ASSERT_EQUAL_FLOAT(7.0f, (float)c[0][0]);
    actag_apriltag_corners_to_actag(det, NULL); /* no-op */
    actag_apriltag_corners_to_actag(det, c);
    /* the white square spans columns/rows 30..59: top-left corner at (29.5, 29.5) */
    TEST_ASSERT_FLOAT_WITHIN(0.3f, 29.5f, (float)c[0][0]);
    TEST_ASSERT_FLOAT_WITHIN(0.3f, 29.5f, (float)c[0][1]);
    TEST_ASSERT_FLOAT_WITHIN(0.3f, 59.5f, (float)c[2][0]);
    TEST_ASSERT_FLOAT_WITHIN(0.3f, 59.5f, (float)c[2][1]);
}

static void test_pose(void)
{
    const apriltag_detection_t *det = detect_tag0();
    double R[9], t[3];
    R[0] = 42.0;
    TEST_ASSERT_EQUAL_FLOAT(-1.0f, (float)actag_apriltag_pose(NULL, 0.13, 500, 500, 44.5, 44.5, R, t));
    TEST_ASSERT_EQUAL_FLOAT(-1.0f, (float)actag_apriltag_pose(det, 0.13, 500, 500, 44.5, 44.5, NULL, t));
    TEST_ASSERT_EQUAL_FLOAT(-1.0f, (float)actag_apriltag_pose(det, 0.13, 500, 500, 44.5, 44.5, R, NULL));
    TEST_ASSERT_EQUAL_FLOAT(-1.0f, (float)actag_apriltag_pose(det, 0.0, 500, 500, 44.5, 44.5, R, t));
    TEST_ASSERT_EQUAL_FLOAT(-1.0f, (float)actag_apriltag_pose(det, 0.13, 0, 500, 44.5, 44.5, R, t));
    TEST_ASSERT_EQUAL_FLOAT(-1.0f, (float)actag_apriltag_pose(det, 0.13, 500, -1, 44.5, 44.5, R, t));
    TEST_ASSERT_EQUAL_FLOAT(42.0f, (float)R[0]); /* untouched */
    TEST_ASSERT_TRUE(actag_apriltag_pose(det, 0.13, 500, 500, 44.5, 44.5, R, t) >= 0.0);
    /* square on, 30 px for 0.13 m at f = 500 px: about 2.2 m ahead */
    TEST_ASSERT_FLOAT_WITHIN(0.2f, 2.17f, (float)t[2]);
}

static void test_pose_sensor(void)
{
    const apriltag_detection_t *det = detect_tag0();
    actag_pose pose;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_apriltag_pose_sensor(NULL, 0.13, 500, 500, 44.5, 44.5, &pose));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_apriltag_pose_sensor(det, 0.13, 500, 500, 44.5, 44.5, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_apriltag_pose_sensor(det, -0.13, 500, 500, 44.5, 44.5, &pose));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_apriltag_pose_sensor(det, 0.13, 0, 500, 44.5, 44.5, &pose));
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_apriltag_pose_sensor(det, 0.13, 500, 500, 44.5, 44.5, &pose));
    TEST_ASSERT_FLOAT_WITHIN(0.2f, 2.17f, pose.t[0]); /* x forward */
    TEST_ASSERT_EQUAL_UINT(ACTAG_POSE_NO_COVARIANCE, pose.flags);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_family_and_names);
    RUN_TEST(test_family_create_and_destroy);
    RUN_TEST(test_max_bits_corrected);
    RUN_TEST(test_detect);
    RUN_TEST(test_invert);
    RUN_TEST(test_corners_to_actag);
    RUN_TEST(test_pose);
    RUN_TEST(test_pose_sensor);
    return UNITY_END();
}
