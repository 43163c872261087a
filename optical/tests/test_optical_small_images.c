/* actag_apriltag_detect() on images too small for AprilTag 3.3 (issue 10:
 * actag_detect_optical crashed inside libapriltag on images under about 8
 * rows): every size from 1 x 1 to 24 x 24 at several quad_decimate values
 * gives an array (empty below 4 * decimate pixels), never a crash or an
 * out-of-bounds read (the sanitizer build checks the latter); NULL
 * arguments give NULL. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "unity.h"

#include "actag/actag_apriltag.h"

#include <apriltag/apriltag.h>
#include <apriltag/common/image_u8.h>
#include <apriltag/common/zarray.h>

static apriltag_detector_t *g_td;

void setUp(void)
{
    g_td = apriltag_detector_create();
    TEST_ASSERT_NOT_NULL(g_td);
    g_td->nthreads = 1;
    apriltag_detector_add_family_bits(g_td, actag_apriltag_family("AcTag24h10"), 2);
}

void tearDown(void)
{
    if (g_td)
        apriltag_detector_destroy(g_td);
    g_td = NULL;
}

static void test_every_small_size_and_decimation(void)
{
    static const float dec[] = {1.0f, 1.5f, 2.0f, 3.0f, 4.0f, 0.0f, -2.0f};
    static uint8_t buf[24 * 24];
    int d, w, h, i, empty = 0, run = 0;
    for (i = 0; i < (int)sizeof buf; i++)
        buf[i] = (uint8_t)((i * 37u) ^ (i >> 3));
    for (d = 0; d < (int)(sizeof dec / sizeof dec[0]); d++) {
        float eff = dec[d] > 1.0f ? dec[d] : 1.0f;
        g_td->quad_decimate = dec[d];
        for (h = 1; h <= 24; h++)
            for (w = 1; w <= 24; w++) {
                image_u8_t im = {.width = w, .height = h, .stride = w, .buf = buf};
                zarray_t *dets = actag_apriltag_detect(g_td, &im);
                TEST_ASSERT_NOT_NULL(dets);
                if ((float)w < 4.0f * eff || (float)h < 4.0f * eff) {
                    TEST_ASSERT_EQUAL_INT(0, zarray_size(dets));
                    empty++;
                } else {
                    run++;
                }
                apriltag_detections_destroy(dets);
            }
    }
    /* both branches were taken: small images skipped, larger ones detected */
    TEST_ASSERT_TRUE(empty > 0);
    TEST_ASSERT_TRUE(run > 0);
}

static void test_null_and_bad_images(void)
{
    static uint8_t buf[64];
    image_u8_t im = {.width = 8, .height = 8, .stride = 8, .buf = buf};
    image_u8_t nobuf = {.width = 8, .height = 8, .stride = 8, .buf = NULL};
    image_u8_t zero = {.width = 0, .height = 8, .stride = 8, .buf = buf};
    image_u8_t narrow = {.width = 8, .height = 8, .stride = 4, .buf = buf};
    TEST_ASSERT_NULL(actag_apriltag_detect(NULL, &im));
    TEST_ASSERT_NULL(actag_apriltag_detect(g_td, NULL));
    TEST_ASSERT_NULL(actag_apriltag_detect(g_td, &nobuf));
    TEST_ASSERT_NULL(actag_apriltag_detect(g_td, &zero));
    TEST_ASSERT_NULL(actag_apriltag_detect(g_td, &narrow));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_every_small_size_and_decimation);
    RUN_TEST(test_null_and_bad_images);
    return UNITY_END();
}
