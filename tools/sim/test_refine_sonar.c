/* The sonar path of actag_refine_corners (refine.h with a geometry: the grid
 * affine in the fan plane plus the range curvature of a tag of known size) on
 * simulated pool frames without speckle (sim.h), where the true corners are
 * known: close views (0.5-1.2 m, where the fan's keystone and the curvature
 * are strongest), either handedness, every orientation flag and a bearing
 * table, starts up to a quarter cell off per corner. */
#include <math.h>
#include <string.h>

#include "sim.h"
#include "simio.h"
#include "test_util.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

#define DEGF 0.017453292f

/* The pool recording's sonar (simio.h) with an orientation and bearings. */
static void pool_sonar(sim_sonar *s, unsigned flags, const float *bearings)
{
    simio_pool_sonar(s);
    s->geo.flags = flags;
    s->geo.bearings = bearings;
}

/* The refined corners lie within 0.3 px of the truth (the starts up to 1.5
 * px off), 0.15 px on average, 3 times closer than an affine grid in pixels
 * fitted from the same start; the fit is deterministic. */
static void test_sonar_views(void)
{
    static uint8_t img[530 * 512];
    static float bt[512];
    sim_appearance a;
    sim_view_params v;
    actag_family fam;
    actag_refine_params rp;
    actag_rng r;
    int trial, i, n = 0;
    float worst = 0.0f, sum = 0.0f;
    for (i = 0; i < 512; i++) /* bearings slightly non-uniform, ascending */
        bt[i] = -30.0f * DEGF + 60.0f * DEGF * ((float)i / 511.0f) +
                0.002f * sinf(6.2831853f * (float)i / 511.0f);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
    sim_appearance_default(&a);
    a.speckle = 0;
    a.noise = 0.0f;
    a.band_rate = 0.0f;
    a.gain *= 0.25f; /* the mean field: no pixel saturates */
    sim_view_params_default(&v);
    v.min_distance = 0.5f;
    v.max_distance = 1.2f;
    v.clutter = 0;
    actag_refine_params_default(&rp);
    actag_rng_seed(&r, 17u);
    for (trial = 0; trial < 10; trial++) {
        int o = trial % 5, c, k = fam.bits / 4;
        sim_sonar s;
        sim_tag t;
        sim_scene sc;
        sim_truth tr;
        actag_point start[4], f1[4], f2[4];
        actag_refine_info info;
        float cell, e0, e1;
        pool_sonar(&s, o < 4 ? (unsigned)o : ACTAG_AZIMUTH_ASCENDING, o == 4 ? bt : NULL);
        memset(&t, 0, sizeof t);
        t.family = fam;
        t.id = (trial * 7) % fam.ncodes;
        t.tag_size = 0.130628571f;
        v.mirror_fraction = (float)(trial & 1);
        TEST_ASSERT_EQUAL_INT(0, sim_sample_view(&s, &v, 300u + (uint32_t)trial, &t, &sc));
        sim_truth_of(&s, &t, &tr);
        if (!tr.visible)
            continue;
        TEST_ASSERT_EQUAL_INT(0, sim_render(&s, &sc, &a, 9u, img, NULL, 512, NULL));
        /* the cell side in pixels, about: the inner square spans k - 3 cells */
        cell = 0.5f * (hypotf(tr.px[1].x - tr.px[0].x, tr.px[1].y - tr.px[0].y) +
                       hypotf(tr.px[3].x - tr.px[0].x, tr.px[3].y - tr.px[0].y)) /
               (float)(k - 3);
        for (c = 0; c < 4; c++) {
            float dx = (float)actag_rng_next(&r) / 4294967296.0f - 0.5f;
            float dy = (float)actag_rng_next(&r) / 4294967296.0f - 0.5f;
            float m = 0.5f * cell < 3.0f ? 0.5f * cell : 3.0f; /* <= 1.5 px per axis */
            start[c].x = tr.px[c].x + m * dx;
            start[c].y = tr.px[c].y + m * dy;
        }
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_refine_corners(img, 530, 512, 512, &s.geo,
                                                             t.tag_size, &fam, t.id, start, &rp,
                                                             f1, &info));
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_refine_corners(img, 530, 512, 512, &s.geo,
                                                             t.tag_size, &fam, t.id, start, &rp,
                                                             f2, NULL));
        TEST_ASSERT_EQUAL_MEMORY(f1, f2, sizeof f1);
        e0 = tu_max_corner_error(start, tr.px);
        e1 = tu_max_corner_error(f1, tr.px);
        for (c = 0; c < 4; c++)
            sum += hypotf(f1[c].x - tr.px[c].x, f1[c].y - tr.px[c].y);
        worst = e1 > worst ? e1 : worst;
        /* the same start fitted as an affine grid in pixels (no geometry):
         * the fan's keystone and the curvature leave pixels of error */
        if (actag_refine_corners(img, 530, 512, 512, NULL, 0.0f, &fam, t.id, start, &rp, f2,
                                 NULL) == ACTAG_OK)
            TEST_ASSERT_TRUE(tu_max_corner_error(f2, tr.px) > 3.0f * e1);
        TEST_ASSERT_TRUE(info.samples > 200);
        TEST_ASSERT_TRUE(e1 < e0);
        n++;
    }
    TEST_ASSERT_TRUE(n >= 8);
    TEST_ASSERT_FLOAT_WITHIN(0.3f, 0.0f, worst);
    TEST_ASSERT_FLOAT_WITHIN(0.15f, 0.0f, sum / (float)(4 * n));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_sonar_views);
    return UNITY_END();
}
