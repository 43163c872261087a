/* Frames of held-out runs that once gave a wrong reading, rendered again by
 * actag-sim and detected by actag_detect: each must now be read right or not
 * at all. Frame F of an actag-eval run of seed S is frame F of `actag-sim
 * --seed S --random F+1` with the run's settings (actag-eval --help).
 *
 * Run 13004 frame 49 (bench/heldout_sweep.py --mix any, AcTag24m10; a
 * mirrored tag 0 at 2.12 m, turned about 40 degrees in the image): the
 * structure search's axis-aligned box settled on a grid across the tag's
 * cells that read tag 0 unmirrored, corners in the wrong order, hamming 3,
 * margin 5.5. detect.c's turned_rival_refuses (docs/decoder.md, "Blind
 * readings and turned starts") refuses it; with that rule off the reading
 * comes back (checked when this test was written, 2026-12-07).
 *
 * Run 15046 frame 412 (--mix any, the pool's sonar with rows ascending,
 * AcTag24m10; an unmirrored tag 0 at 1.13 m and 73 degrees, a diamond in
 * the image): the white square's contour lost its far corner, so the
 * contour's guess (its extreme points) had one corner inside the square;
 * the wide search from it settled on a flat grid across the tag that read
 * tag 0 mirrored, hamming 1, margin 16.9, past the turned starts. The
 * guess with that corner completed to the parallelogram through the other
 * three reads the tag's own grid (hamming 0), which refuses it; without
 * the completions the reading comes back (checked 2026-12-07). */
#define _POSIX_C_SOURCE 200809L
#include "unity.h"
#include "hostio.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void setUp(void) {}
void tearDown(void) {}

#define FRAMES ACTAG_BINARY_DIR "/heldout_regression_frames"

/* settings_any(13004) of bench/heldout_sweep.py */
#define RUN_13004                                                                           \
    "--rows 530 --cols 512 --min-range 0.1 --max-range 3.5 --min-distance 0.5 "            \
    "--max-distance 3 --gain 260 --noise 0.0012 --psf-azimuth 0.0035 --psf-range 0.0025 " \
    "--looks 3 --clutter 0 --foam 0.5 --metal-specular 8 --mirror-fraction 0.5 --bands 5 " \
    "--family AcTag24m10"

/* settings_any(15046) */
#define RUN_15046                                                                            \
    "--pool --range-ascending --gain 130 --noise 0.0003 --psf-azimuth 0.006 "                \
    "--psf-range 0.0015 --looks 4 --clutter 20 --foam 1 --metal-specular 8 "                \
    "--mirror-fraction 0 --bands 2 --family AcTag24m10"

static int count(const char *s, const char *what)
{
    int n = 0;
    while ((s = strstr(s, what)) != NULL) {
        n++;
        s += strlen(what);
    }
    return n;
}

static void test_run_13004_frame_49_is_not_read_in_the_wrong_handedness(void)
{
    char cmd[2048], path[512], *truth, *out, *frame49;
    snprintf(cmd, sizeof cmd,
             "rm -rf \"%s\" && \"%s\" --seed 13004 --random 50 " RUN_13004
             " --out-dir \"%s\" > /dev/null",
             FRAMES, ACTAG_SIM_PATH, FRAMES);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, hostio_run(cmd, NULL), cmd);

    /* the frame is the one the run saw: a mirrored tag 0 */
    snprintf(path, sizeof path, "%s/truth.jsonl", FRAMES);
    truth = (char *)hostio_slurp(path, NULL, NULL);
    TEST_ASSERT_NOT_NULL(truth);
    frame49 = strstr(truth, "\"frame\": 49,"); /* the last line */
    TEST_ASSERT_NOT_NULL_MESSAGE(frame49, "no frame 49 in truth.jsonl");
    TEST_ASSERT_NOT_NULL(strstr(frame49, "\"id\": 0, \"tag_size\""));
    TEST_ASSERT_NOT_NULL(strstr(frame49, "\"mirrored\": 1, \"visible\": 1, \"distance\": 2.117"));
    free(truth);

    snprintf(path, sizeof path, "%s/detect.json", FRAMES);
    snprintf(cmd, sizeof cmd,
             "\"%s\" --family AcTag24m10 --min-range 0.1 --max-range 3.5 --aperture-deg 60 "
             "--json \"%s\"/sim_0049.pgm > \"%s\"",
             ACTAG_DETECT_PATH, FRAMES, path);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, hostio_run(cmd, NULL), cmd);
    out = (char *)hostio_slurp(path, NULL, NULL);
    TEST_ASSERT_NOT_NULL(out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, "\"detections\": ["), out);
    /* read right (tag 0 mirrored, once) or not at all */
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, count(out, "\"mirrored\": false"), out);
    TEST_ASSERT_TRUE_MESSAGE(count(out, "\"id\": ") <= 1, out);
    TEST_ASSERT_EQUAL_INT_MESSAGE(count(out, "\"id\": "), count(out, "\"id\": 0,"), out);
    free(out);
}

static void test_run_15046_frame_412_is_not_read_in_the_wrong_handedness(void)
{
    char cmd[2048], path[512], *truth, *out, *frame;
    snprintf(cmd, sizeof cmd,
             "rm -rf \"%s\" && \"%s\" --seed 15046 --random 413 " RUN_15046
             " --out-dir \"%s\" > /dev/null",
             FRAMES, ACTAG_SIM_PATH, FRAMES);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, hostio_run(cmd, NULL), cmd);

    /* the frame is the one the run saw: an unmirrored tag 0 at 1.13 m */
    snprintf(path, sizeof path, "%s/truth.jsonl", FRAMES);
    truth = (char *)hostio_slurp(path, NULL, NULL);
    TEST_ASSERT_NOT_NULL(truth);
    frame = strstr(truth, "\"frame\": 412,"); /* the last line */
    TEST_ASSERT_NOT_NULL_MESSAGE(frame, "no frame 412 in truth.jsonl");
    TEST_ASSERT_NOT_NULL(strstr(frame, "\"id\": 0, \"tag_size\""));
    TEST_ASSERT_NOT_NULL(strstr(frame, "\"mirrored\": 0, \"visible\": 1, \"distance\": 1.129"));
    free(truth);

    snprintf(path, sizeof path, "%s/detect.json", FRAMES);
    snprintf(cmd, sizeof cmd,
             "\"%s\" --family AcTag24m10 --min-range 0.1 --max-range 1.5 --aperture-deg 60 "
             "--range-ascending --json \"%s\"/sim_0412.pgm > \"%s\"",
             ACTAG_DETECT_PATH, FRAMES, path);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, hostio_run(cmd, NULL), cmd);
    out = (char *)hostio_slurp(path, NULL, NULL);
    TEST_ASSERT_NOT_NULL(out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, "\"detections\": ["), out);
    /* read right (tag 0 unmirrored, once) or not at all */
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, count(out, "\"mirrored\": true"), out);
    TEST_ASSERT_TRUE_MESSAGE(count(out, "\"id\": ") <= 1, out);
    TEST_ASSERT_EQUAL_INT_MESSAGE(count(out, "\"id\": "), count(out, "\"id\": 0,"), out);
    free(out);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_run_13004_frame_49_is_not_read_in_the_wrong_handedness);
    RUN_TEST(test_run_15046_frame_412_is_not_read_in_the_wrong_handedness);
    return UNITY_END();
}
