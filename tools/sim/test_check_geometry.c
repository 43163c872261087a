/* actag_detect --check-geometry against ground truth: pool-sonar frames
 * rendered by actag-sim at 60 degrees with 0.130628571 m tags, detected
 * under a wrong aperture (52 degrees) and a wrong tag size (0.12 m), must
 * give back the aperture and the size they were rendered with; under the
 * true geometry the median chi2 is small and both scales are about 1. */
#define _POSIX_C_SOURCE 200809L
#include "unity.h"
#include "hostio.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void setUp(void) {}
void tearDown(void) {}

#define FRAMES ACTAG_BINARY_DIR "/check_geometry_frames"
#define GEO "--min-range 0.1 --max-range 1.5"

static char out_path[512];

/* actag_detect --check-geometry --json with args on the frames; returns the
 * geometry_check line (the last one), to be freed. */
static char *check(const char *args)
{
    char cmd[2048], *s, *line;
    snprintf(out_path, sizeof out_path, "%s/check_geometry_out.txt", ACTAG_BINARY_DIR);
    snprintf(cmd, sizeof cmd, "\"%s\" --check-geometry --json " GEO " %s \"%s\"/sim_*.pgm > \"%s\"",
             ACTAG_DETECT_PATH, args, FRAMES, out_path);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, hostio_run(cmd, NULL), cmd);
    s = (char *)hostio_slurp(out_path, NULL, NULL);
    TEST_ASSERT_NOT_NULL(s);
    line = strstr(s, "{\"geometry_check\": ");
    TEST_ASSERT_NOT_NULL_MESSAGE(line, "no geometry_check line");
    line = strchr(line, '\n');
    TEST_ASSERT_TRUE_MESSAGE(line != NULL && line[1] == '\0', "geometry_check is not the last line");
    return s;
}

static double num(const char *s, const char *key)
{
    char pat[64];
    const char *p;
    snprintf(pat, sizeof pat, "\"%s\": ", key);
    p = strstr(strstr(s, "{\"geometry_check\": "), pat);
    TEST_ASSERT_NOT_NULL_MESSAGE(p, key);
    return atof(p + strlen(pat));
}

static void test_recovers_the_rendered_geometry(void)
{
    char cmd[1024], *s;
    snprintf(cmd, sizeof cmd,
             "rm -rf \"%s\" && \"%s\" --pool --random 12 --seed 5 --out-dir \"%s\" > /dev/null",
             FRAMES, ACTAG_SIM_PATH, FRAMES);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, hostio_run(cmd, NULL), cmd);

    /* the true geometry: chi2 well under the 3 expected, scales about 1 */
    s = check("--aperture-deg 60");
    TEST_ASSERT_TRUE(num(s, "tags") >= 8);
    TEST_ASSERT_TRUE(num(s, "median_chi2") < 1.0);
    TEST_ASSERT_FLOAT_WITHIN(0.01f, 1.0f, (float)num(s, "azimuth_scale"));
    TEST_ASSERT_FLOAT_WITHIN(0.01f, 1.0f, (float)num(s, "tag_size_scale"));
    free(s);

    /* 52 degrees stated: the corners do not fit (chi2 above 3), and the
     * scan finds 60 degrees (azimuth scale 60 / 52) */
    s = check("--aperture-deg 52");
    TEST_ASSERT_TRUE(num(s, "median_chi2") > 3.0);
    TEST_ASSERT_FLOAT_WITHIN(1.0f, 60.0f, (float)num(s, "aperture_deg"));
    TEST_ASSERT_FLOAT_WITHIN(0.02f, (float)(60.0 / 52.0), (float)num(s, "azimuth_scale"));
    TEST_ASSERT_TRUE(num(s, "azimuth_scale_chi2") < 1.0);
    free(s);

    /* a 0.12 m tag stated: the scan finds the rendered 0.1306 m */
    s = check("--aperture-deg 60 --tag-size 0.12");
    TEST_ASSERT_TRUE(num(s, "median_chi2") > 3.0);
    TEST_ASSERT_FLOAT_WITHIN(0.0026f, 0.130628571f, (float)num(s, "tag_size"));
    TEST_ASSERT_TRUE(num(s, "tag_size_scale_chi2") < 1.0);
    free(s);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_recovers_the_rendered_geometry);
    return UNITY_END();
}
