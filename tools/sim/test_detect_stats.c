/* actag_detect's counts of what max_out leaves out (actag.h: stats.dropped
 * counts tags beyond max_out, once per tag; a tag's other readings count in
 * stats.duplicates), on simulated frames of the paper's evaluation protocol
 * (actag-eval's default sonar, AcTag24h10, tags 2.5-5 m away, where one
 * tag is often read twice, from two contours).
 *
 * Regression (review of 2026-12-07): a second reading of a tag that did
 * not fit out[] matched nothing written and counted as another dropped
 * tag, so with max_out 0 one tag read twice gave dropped 2, duplicates 0
 * (actag-sim --random 400 --seed 12 --min-distance 2.5, frame 205;
 * actag-eval's frame F is actag-sim's frame F of the same seed). */
#include "unity.h"
#include "sim.h"
#include "simio.h"

#include <stdlib.h>
#include <string.h>

void setUp(void) {}
void tearDown(void) {}

/* frames 190-229 of the run: frame 205 reads its tag twice (the only one
 * of frames 0-399), the others once or not at all */
enum { FIRST = 190, FRAMES = 40 };

static void test_dropped_counts_tags_not_readings(void)
{
    sim_sonar s;
    sim_view_params v;
    sim_appearance a;
    actag_family fam;
    actag_params p;
    actag_detection det[16];
    size_t wsz;
    uint8_t *img;
    void *ws;
    int i, twice = 0, read = 0;
    char err[256];
    simio_opt_defaults(0, NULL, &s, &v, &a); /* actag-eval's defaults */
    s.geo.aperture = 60.0f * 3.14159265f / 180.0f;
    v.min_distance = 2.5f;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
    actag_params_default(&p);
    p.family = &fam;
    p.tag_size = 0.130628571f;
    wsz = actag_workspace_size(s.rows, s.cols);
    ws = malloc(wsz);
    img = (uint8_t *)malloc((size_t)s.rows * (size_t)s.cols);
    TEST_ASSERT_NOT_NULL(ws);
    TEST_ASSERT_NOT_NULL(img);
    for (i = FIRST; i < FIRST + FRAMES; i++) {
        uint32_t fs = sim_frame_seed(12u, (uint32_t)i);
        sim_tag tag;
        sim_scene sc;
        actag_frame fr;
        actag_stats all, none, one;
        int n, n0, n1;
        memset(&tag, 0, sizeof tag);
        tag.family = fam;
        tag.tag_size = p.tag_size;
        tag.id = simio_random_id(fs, fam.ncodes);
        if (sim_sample_view(&s, &v, fs, &tag, &sc) != 0)
            continue;
        TEST_ASSERT_EQUAL_INT(0, sim_render(&s, &sc, &a, fs, img, NULL, s.cols, err));
        fr.data = img;
        fr.rows = s.rows;
        fr.cols = s.cols;
        fr.stride = s.cols;
        fr.depth = 8;
        n = actag_detect(&fr, &s.geo, &p, ws, wsz, det, 16, &all);
        TEST_ASSERT_TRUE(n >= 0 && n <= 8); /* at most 8 tags: below the 8 places */
        TEST_ASSERT_EQUAL_INT(0, all.dropped);
        n0 = actag_detect(&fr, &s.geo, &p, ws, wsz, NULL, 0, &none);
        TEST_ASSERT_EQUAL_INT(0, n0);
        TEST_ASSERT_EQUAL_INT_MESSAGE(n, none.dropped, "max_out 0: every tag dropped, once");
        TEST_ASSERT_EQUAL_INT_MESSAGE(all.duplicates, none.duplicates,
                                      "duplicates do not depend on max_out");
        TEST_ASSERT_EQUAL_INT(all.decoded, none.decoded);
        if (n > 0) {
            n1 = actag_detect(&fr, &s.geo, &p, ws, wsz, det, 1, &one);
            TEST_ASSERT_EQUAL_INT(1, n1);
            TEST_ASSERT_EQUAL_INT(n - 1, one.dropped);
            TEST_ASSERT_EQUAL_INT(all.duplicates, one.duplicates);
            read++;
        }
        twice += all.duplicates > 0;
    }
    /* the case in question occurred (else the test could not fail) */
    TEST_ASSERT_TRUE_MESSAGE(twice > 0, "no frame had a tag read twice");
    TEST_ASSERT_TRUE(read > FRAMES / 10);
    free(img);
    free(ws);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_dropped_counts_tags_not_readings);
    return UNITY_END();
}
