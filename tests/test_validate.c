/* The validators and their error details (validate.c): for every field of
 * actag_params, actag_tuning (with the quad and fit params), the geometry
 * and the frame, bad values are the documented error from actag_detect AND
 * actag_check names that field, its value and a rule; boundary values are
 * accepted and detection runs. Plus the hostile cases of issue 10 (huge
 * tag sizes, tiny azimuth steps, NaN/inf/negative/swapped ranges, apertures
 * 0 and above 2 pi, radii 0 and larger than the frame, corrections above
 * the limit, a workspace one byte too small), the stages calling the same
 * validators (quad, fit decoder, search), and the search's pixel counts
 * staying defined for any finite input. */
#include "unity.h"
#include "test_util.h"

#include "actag/actag.h"

#include <float.h>
#include <math.h>
#include <stddef.h>

void setUp(void) {}
void tearDown(void) {}

#define ROWS 40
#define COLS 64
static uint8_t g_ws[ACTAG_WORKSPACE_SIZE(ROWS, COLS)];
static uint8_t g_px[ROWS * COLS];
static float g_bearings[COLS];
static actag_family g_fam;

static void base(actag_frame *f, actag_sonar_geometry *g, actag_params *p)
{
    int r, c;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &g_fam));
    for (r = 0; r < ROWS; r++) /* a little structure so that every stage runs */
        for (c = 0; c < COLS; c++)
            g_px[r * COLS + c] = (uint8_t)(((r / 6 + c / 7) & 1) ? 200 : 30);
    tu_valid_input(g_px, ROWS, COLS, &g_fam, f, g, p);
}

static int nan_or_equal(double a, double b) { return (a != a && b != b) || a == b; }

/* Runs actag_detect and actag_check on the same input; both must agree on
 * the code; on an error the detail must name `field` with `value`. */
static void expect(const actag_frame *f, const actag_sonar_geometry *g, const actag_params *p,
                   size_t wss, int max_out, int code, const char *field, double value,
                   const char *what)
{
    actag_detection det[4];
    actag_error_detail d;
    char m[300];
    int n = actag_detect(f, g, p, g_ws, wss, det, max_out, NULL);
    int rc = actag_check(f, g, p, wss, max_out, &d);
    snprintf(m, sizeof m, "%s (field %s)", what, field ? field : "-");
    TEST_ASSERT_EQUAL_INT_MESSAGE(rc, d.code, m);
    if (code == ACTAG_OK) {
        TEST_ASSERT_TRUE_MESSAGE(n >= 0, m);
        TEST_ASSERT_EQUAL_INT_MESSAGE(ACTAG_OK, rc, m);
        TEST_ASSERT_NULL_MESSAGE(d.field, m);
        return;
    }
    TEST_ASSERT_EQUAL_INT_MESSAGE(code, n, m);
    TEST_ASSERT_EQUAL_INT_MESSAGE(code, rc, m);
    TEST_ASSERT_NOT_NULL_MESSAGE(d.field, m);
    if (strcmp(d.field, field) != 0) {
        snprintf(m, sizeof m, "%s: detail names '%s', expected '%s'", what, d.field, field);
        TEST_FAIL_MESSAGE(m);
    }
    TEST_ASSERT_TRUE_MESSAGE(nan_or_equal(d.value, value), m);
    TEST_ASSERT_NOT_NULL_MESSAGE(d.rule, m);
    TEST_ASSERT_TRUE_MESSAGE(strncmp(d.rule, "must ", 5) == 0, m);
}

/* ------------------------------------------------- one row per field */

enum kind { K_INT, K_FLOAT };

typedef struct field_case {
    const char *field;  /* as the detail names it */
    enum kind kind;
    size_t offset;      /* into actag_params */
    int code;           /* the error for the bad values */
    double bad[7];
    int nbad;
    double good[4];     /* boundary values that must be accepted */
    int ngood;
} field_case;

#define P(m) offsetof(actag_params, m)
#define NAN_ ((double)NAN)
#define INF_ ((double)INFINITY)

static const field_case param_cases[] = {
    {"tag_size", K_FLOAT, P(tag_size), ACTAG_ERR_PARAM, {0, -1, NAN_, INF_, -INF_, 1000, 1e30}, 7,
     {1e-30, 0.13, 2.1}, 3},
    {"max_bit_corrections", K_INT, P(max_bit_corrections), ACTAG_ERR_CORRECTIONS,
     {5, -2, 1000, -1000000}, 4, {-1, 0, 4}, 3},
    {"min_margin", K_FLOAT, P(min_margin), ACTAG_ERR_PARAM, {NAN_, INF_, 1.1e6, -1.1e6}, 4,
     {-1e6, 0, 1e6}, 3},
    {"handedness", K_INT, P(handedness), ACTAG_ERR_PARAM, {-1, 3, 99}, 3,
     {ACTAG_HANDEDNESS_ANY, ACTAG_HANDEDNESS_UNMIRRORED, ACTAG_HANDEDNESS_MIRRORED}, 3},
    {"tuning.median_radius", K_INT, P(tuning.median_radius), ACTAG_ERR_PARAM,
     {-1, ACTAG_MEDIAN_MAX_RADIUS + 1, 1000000}, 3, {0, 1, ACTAG_MEDIAN_MAX_RADIUS}, 3},
    {"tuning.median_per_range", K_INT, P(tuning.median_per_range), ACTAG_ERR_PARAM,
     {-1, 2, 1000000}, 3, {0, 1}, 2},
    {"tuning.threshold_radius", K_INT, P(tuning.threshold_radius), ACTAG_ERR_PARAM,
     {-1, ACTAG_MAX_THRESHOLD_RADIUS + 1}, 2, {0, ACTAG_MAX_THRESHOLD_RADIUS}, 2},
    {"tuning.threshold_offset", K_INT, P(tuning.threshold_offset), ACTAG_ERR_PARAM, {-256, 256},
     2, {-255, 0, 255}, 3},
    {"tuning.size_tolerance", K_FLOAT, P(tuning.size_tolerance), ACTAG_ERR_PARAM,
     {-0.001, 10, NAN_, INF_}, 4, {0, 9.99}, 2},
    {"tuning.min_area_fraction", K_FLOAT, P(tuning.min_area_fraction), ACTAG_ERR_PARAM,
     {-0.1, 1e6, NAN_, INF_}, 4, {0, 1.0}, 2},
    {"tuning.max_area_fraction", K_FLOAT, P(tuning.max_area_fraction), ACTAG_ERR_PARAM,
     {0.17, 1e6, NAN_, INF_, -1}, 5, {0.175, 999999}, 2}, /* >= the default min, 0.175 */
    {"tuning.quad.max_iterations", K_INT, P(tuning.quad.max_iterations), ACTAG_ERR_PARAM,
     {0, -1, ACTAG_QUAD_MAX_ITERATIONS + 1}, 3, {1, 2000}, 2},
    {"tuning.quad.sample_fraction", K_FLOAT, P(tuning.quad.sample_fraction), ACTAG_ERR_PARAM,
     {0, 1.0001, NAN_, -0.1}, 4, {1e-6, 1}, 2},
    {"tuning.quad.inlier_ratio", K_FLOAT, P(tuning.quad.inlier_ratio), ACTAG_ERR_PARAM,
     {0, 1.5, NAN_, -1}, 4, {1e-6, 1}, 2},
    {"tuning.quad.min_inlier_ratio", K_FLOAT, P(tuning.quad.min_inlier_ratio), ACTAG_ERR_PARAM,
     {0, 1.5, NAN_, -INF_}, 4, {1e-6, 1}, 2},
    {"tuning.quad.inlier_distance", K_FLOAT, P(tuning.quad.inlier_distance), ACTAG_ERR_PARAM,
     {0, 1e7, NAN_, INF_, -2.5}, 5, {1e-6, 1e6}, 2},
    {"tuning.quad.min_parallel_cos", K_FLOAT, P(tuning.quad.min_parallel_cos), ACTAG_ERR_PARAM,
     {-0.01, 1.01, NAN_}, 3, {0, 1}, 2},
    {"tuning.decode_mode", K_INT, P(tuning.decode_mode), ACTAG_ERR_PARAM, {-1, 2, 99}, 3,
     {ACTAG_DECODE_FIT, ACTAG_DECODE_BINARY}, 2},
    {"tuning.fit.level", K_FLOAT, P(tuning.fit.level), ACTAG_ERR_PARAM, {-0.01, 1.01, NAN_}, 3,
     {0, 1}, 2},
    {"tuning.fit.min_contrast", K_INT, P(tuning.fit.min_contrast), ACTAG_ERR_PARAM, {-1, 256}, 2,
     {0, 255}, 2},
    {"tuning.fit.sample_offset", K_FLOAT, P(tuning.fit.sample_offset), ACTAG_ERR_PARAM,
     {-0.01, 0.51, NAN_}, 3, {0, 0.5}, 2},
    {"tuning.fit.min_margin", K_FLOAT, P(tuning.fit.min_margin), ACTAG_ERR_PARAM,
     {NAN_, 1.1e6, -INF_}, 3, {-1e6, 1e6}, 2},
    {"tuning.fit.min_bit_margin", K_INT, P(tuning.fit.min_bit_margin), ACTAG_ERR_PARAM, {-1, 33},
     2, {0, 32}, 2},
    {"tuning.fit.min_bit_odds", K_INT, P(tuning.fit.min_bit_odds), ACTAG_ERR_PARAM,
     {0, 1000001, -5}, 3, {1, 1000000}, 2},
    {"tuning.fit.many_corrections", K_INT, P(tuning.fit.many_corrections), ACTAG_ERR_PARAM,
     {-1, 34}, 2, {0, 33}, 2},
    {"tuning.fit.many_corrections_margin", K_FLOAT, P(tuning.fit.many_corrections_margin),
     ACTAG_ERR_PARAM, {-0.01, 1.1e6, NAN_}, 3, {0, 1e6}, 2},
    {"tuning.fit.flags", K_INT, P(tuning.fit.flags), ACTAG_ERR_PARAM,
     {ACTAG_FIT_ONLY_UNMIRRORED | ACTAG_FIT_ONLY_MIRRORED,
      ACTAG_FIT_DEFAULT_FLAGS | ACTAG_FIT_ONLY_UNMIRRORED | ACTAG_FIT_ONLY_MIRRORED}, 2,
     {ACTAG_FIT_DEFAULT_FLAGS, ACTAG_FIT_DEFAULT_FLAGS | ACTAG_FIT_ONLY_UNMIRRORED,
      ACTAG_FIT_DEFAULT_FLAGS | ACTAG_FIT_ONLY_MIRRORED}, 3},
    {"tuning.min_structure", K_FLOAT, P(tuning.min_structure), ACTAG_ERR_PARAM,
     {-0.01, 1.01, NAN_}, 3, {0, 1}, 2},
    {"tuning.min_texture_contrast", K_FLOAT, P(tuning.min_texture_contrast), ACTAG_ERR_PARAM,
     {-0.01, 1.1e6, NAN_, INF_}, 4, {0, 1e6}, 2},
    {"tuning.min_side_fraction", K_FLOAT, P(tuning.min_side_fraction), ACTAG_ERR_PARAM,
     {-0.01, 2e6, NAN_}, 3, {0, 1.6}, 2},
    {"tuning.max_side_fraction", K_FLOAT, P(tuning.max_side_fraction), ACTAG_ERR_PARAM,
     {0.49, 2e6, NAN_, INF_}, 4, {0.5, 1e6}, 2},
    {"tuning.search_candidates", K_INT, P(tuning.search_candidates), ACTAG_ERR_PARAM,
     {-1, ACTAG_SEARCH_MAX + 1}, 2, {0, ACTAG_SEARCH_MAX}, 2},
    {"tuning.search_min_score", K_INT, P(tuning.search_min_score), ACTAG_ERR_PARAM, {-1, 256}, 2,
     {0, 255}, 2},
    {"tuning.search_max_corrections", K_INT, P(tuning.search_max_corrections), ACTAG_ERR_PARAM,
     {-1, -100}, 2, {0, 1000}, 2},
    {"tuning.search_min_margin", K_FLOAT, P(tuning.search_min_margin), ACTAG_ERR_PARAM,
     {NAN_, 1.1e6, -1.1e6}, 3, {-1e6, 1e6}, 2},
    {"tuning.refine_corners", K_INT, P(tuning.refine_corners), ACTAG_ERR_PARAM, {-1, 2, 99}, 3,
     {0, 1}, 2},
    {"tuning.limits.max_contours", K_INT, P(tuning.limits.max_contours), ACTAG_ERR_PARAM,
     {0, -1, -2147483648.0}, 3, {1, 2147483647.0}, 2},
    {"tuning.limits.max_contour_points", K_INT, P(tuning.limits.max_contour_points),
     ACTAG_ERR_PARAM, {0, -1, -2147483648.0}, 3, {1, 2147483647.0}, 2},
    {"tuning.limits.max_contour_iterations", K_INT, P(tuning.limits.max_contour_iterations),
     ACTAG_ERR_PARAM, {0, -1, -2147483648.0}, 3, {1, 2147483647.0}, 2},
    {"tuning.limits.max_frame_iterations", K_INT, P(tuning.limits.max_frame_iterations),
     ACTAG_ERR_PARAM, {0, -1, -2147483648.0}, 3, {1, 2147483647.0}, 2},
    {"tuning.limits.max_decodes", K_INT, P(tuning.limits.max_decodes), ACTAG_ERR_PARAM,
     {0, -1, -2147483648.0}, 3, {1, 2147483647.0}, 2},
    {"tuning.search_range_scale", K_FLOAT, P(tuning.search_range_scale), ACTAG_ERR_PARAM,
     {0.05, 4.01, NAN_, 0, -1}, 5, {0.0501, 4}, 2},
};
#define NPARAM_CASES ((int)(sizeof param_cases / sizeof param_cases[0]))

static void set_field(actag_params *p, const field_case *fc, double v)
{
    char *base_ptr = (char *)p + fc->offset;
    if (fc->kind == K_INT) {
        /* NaN and out-of-range values become the nearest int (no UB here) */
        int i = !(v == v) ? 0 : v >= 2147483647.0 ? 2147483647 : v <= -2147483648.0 ? (-2147483647 - 1) : (int)v;
        memcpy(base_ptr, &i, sizeof i);
    } else {
        float x = (float)v;
        memcpy(base_ptr, &x, sizeof x);
    }
}

static void test_every_params_and_tuning_field(void)
{
    int i, k;
    for (i = 0; i < NPARAM_CASES; i++) {
        const field_case *fc = &param_cases[i];
        for (k = 0; k < fc->nbad + fc->ngood; k++) {
            actag_frame f;
            actag_sonar_geometry g;
            actag_params p;
            int good = k >= fc->nbad;
            double v = good ? fc->good[k - fc->nbad] : fc->bad[k];
            char what[160];
            base(&f, &g, &p);
            set_field(&p, fc, v);
            snprintf(what, sizeof what, "%s = %g (%s)", fc->field, v, good ? "good" : "bad");
            /* the detail's value is the stored one (float fields round) */
            expect(&f, &g, &p, sizeof g_ws, 4, good ? ACTAG_OK : fc->code, fc->field,
                   fc->kind == K_FLOAT ? (double)(float)v : (double)(int)v, what);
        }
    }
}

/* actag_params_validate and actag_tuning_validate give the same verdicts,
 * with names relative to their argument. */
static void test_struct_validators_name_fields_relative_to_their_argument(void)
{
    actag_frame f;
    actag_sonar_geometry g;
    actag_params p;
    actag_error_detail d;
    base(&f, &g, &p);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_params_validate(&p, &d));
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, d.code);
    TEST_ASSERT_NULL(d.field);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_params_validate(&p, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_tuning_validate(&p.tuning, &d));
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_quad_params_validate(&p.tuning.quad, &d));
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_fit_params_validate(&p.tuning.fit, &d));

    p.tuning.quad.inlier_distance = 1e7f;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_params_validate(&p, &d));
    TEST_ASSERT_EQUAL_STRING("tuning.quad.inlier_distance", d.field);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_tuning_validate(&p.tuning, &d));
    TEST_ASSERT_EQUAL_STRING("quad.inlier_distance", d.field);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_quad_params_validate(&p.tuning.quad, &d));
    TEST_ASSERT_EQUAL_STRING("inlier_distance", d.field);
    TEST_ASSERT_TRUE(d.value == 1e7);
    TEST_ASSERT_EQUAL_STRING("must be a number of pixels > 0 and <= 1e6", d.rule);
    TEST_ASSERT_NULL(d.other);

    base(&f, &g, &p);
    p.tuning.fit.level = 2.0f;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_tuning_validate(&p.tuning, &d));
    TEST_ASSERT_EQUAL_STRING("fit.level", d.field);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_fit_params_validate(&p.tuning.fit, &d));
    TEST_ASSERT_EQUAL_STRING("level", d.field);

    base(&f, &g, &p);
    p.tuning.median_radius = -3;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_tuning_validate(&p.tuning, &d));
    TEST_ASSERT_EQUAL_STRING("median_radius", d.field);
    TEST_ASSERT_TRUE(d.value == -3.0);

    /* cross-field rules say which field they compare with, and its bound */
    base(&f, &g, &p);
    p.tuning.max_side_fraction = 0.25f;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_params_validate(&p, &d));
    TEST_ASSERT_EQUAL_STRING("tuning.max_side_fraction", d.field);
    TEST_ASSERT_EQUAL_STRING("tuning.min_side_fraction", d.other);
    TEST_ASSERT_TRUE(d.limit == 0.5);
    p.max_bit_corrections = 5;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_CORRECTIONS, actag_params_validate(&p, &d));
    TEST_ASSERT_EQUAL_STRING("max_bit_corrections", d.field);
    TEST_ASSERT_EQUAL_STRING("family", d.other);
    TEST_ASSERT_TRUE(d.limit == 4.0); /* AcTag24h10 corrects at most 4 */

    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_params_validate(NULL, &d));
    TEST_ASSERT_EQUAL_STRING("params", d.field);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_tuning_validate(NULL, &d));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_quad_params_validate(NULL, &d));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_fit_params_validate(NULL, &d));
    base(&f, &g, &p);
    p.family = NULL;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_params_validate(&p, &d));
    TEST_ASSERT_EQUAL_STRING("family", d.field);
}

/* An invalid family: ACTAG_ERR_FAMILY, naming the family. */
static void test_invalid_family(void)
{
    actag_frame f;
    actag_sonar_geometry g;
    actag_params p;
    actag_family bad;
    base(&f, &g, &p);
    bad = g_fam;
    bad.bits = 23;
    p.family = &bad;
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_ERR_FAMILY, "family", 0.0, "bits 23");
}

/* ------------------------------------------------------------ geometry */

typedef struct geo_case {
    const char *field;
    size_t offset; /* float member of actag_sonar_geometry */
    double bad[6];
    int nbad;
    double good[4];
    int ngood;
} geo_case;

#define G(m) offsetof(actag_sonar_geometry, m)

static const geo_case geo_cases[] = {
    /* NaN, inf, negative; 0 is allowed */
    {"geometry.min_range", G(min_range), {NAN_, INF_, -INF_, -0.001, 1.5, 2}, 6, {0, 1.4}, 2},
    {"geometry.max_range", G(max_range), {NAN_, INF_, -INF_}, 3, {0.2, 1e6}, 2},
    /* aperture 0, negative, 2 pi and above, NaN, and a step below 1e-6 rad
     * per column (63 columns apart) */
    {"geometry.aperture", G(aperture), {0, -1, 6.2832, 7, NAN_, 6.0e-5}, 6,
     {6.4e-5, 6.28318}, 2},
};
#define NGEO_CASES ((int)(sizeof geo_cases / sizeof geo_cases[0]))

static void test_every_geometry_field(void)
{
    int i, k;
    for (i = 0; i < NGEO_CASES; i++) {
        const geo_case *gc = &geo_cases[i];
        for (k = 0; k < gc->nbad + gc->ngood; k++) {
            actag_frame f;
            actag_sonar_geometry g;
            actag_params p;
            int good = k >= gc->nbad;
            double v = good ? gc->good[k - gc->nbad] : gc->bad[k];
            float x = (float)v;
            char what[160];
            base(&f, &g, &p);
            memcpy((char *)&g + gc->offset, &x, sizeof x);
            snprintf(what, sizeof what, "%s = %g (%s)", gc->field, v, good ? "good" : "bad");
            expect(&f, &g, &p, sizeof g_ws, 4, good ? ACTAG_OK : ACTAG_ERR_GEOMETRY, gc->field,
                   (double)x, what);
        }
    }
}

static void test_swapped_and_too_close_ranges(void)
{
    actag_frame f;
    actag_sonar_geometry g;
    actag_params p;
    actag_error_detail d;
    base(&f, &g, &p);
    g.min_range = 2.0f;
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_ERR_GEOMETRY, "geometry.min_range", 2.0, "swapped");
    actag_check(&f, &g, &p, sizeof g_ws, 4, &d);
    TEST_ASSERT_EQUAL_STRING("geometry.max_range", d.other);
    TEST_ASSERT_TRUE(d.limit == 1.5);
    TEST_ASSERT_EQUAL_STRING("must be below geometry.max_range", d.rule);
    g.min_range = 1.5f; /* equal */
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_ERR_GEOMETRY, "geometry.min_range", 1.5, "equal");
    /* 39 range steps must each be at least 1e-6 * max_range */
    g.min_range = 1.0f;
    g.max_range = 1.00001f; /* 2.6e-7 per row */
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_ERR_GEOMETRY, "geometry.max_range",
           (double)1.00001f, "rows too close in range");
    g.max_range = 1.0001f; /* 2.6e-6 per row: fine */
    p.tag_size = 0.01f;
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_OK, NULL, 0, "0.1 mm span");
    /* standalone: names relative to the geometry */
    g.min_range = 3.0f;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, actag_geometry_validate(&g, ROWS, COLS, &d));
    TEST_ASSERT_EQUAL_STRING("min_range", d.field);
    TEST_ASSERT_EQUAL_STRING("max_range", d.other);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_geometry_validate(NULL, ROWS, COLS, &d));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_geometry_validate(&g, 0, COLS, &d));
    TEST_ASSERT_EQUAL_STRING("rows", d.field);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_geometry_validate(&g, ROWS, ACTAG_MAX_DIM + 1, &d));
    TEST_ASSERT_EQUAL_STRING("cols", d.field);
}

static void test_flags(void)
{
    actag_frame f;
    actag_sonar_geometry g;
    actag_params p;
    base(&f, &g, &p);
    g.flags = 4u;
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_ERR_GEOMETRY, "geometry.flags", 4.0, "flag 4");
    g.flags = ACTAG_RANGE_ASCENDING | ACTAG_AZIMUTH_ASCENDING;
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_OK, NULL, 0, "both flags");
}

static void test_bearing_tables_name_the_entry(void)
{
    actag_frame f;
    actag_sonar_geometry g;
    actag_params p;
    actag_error_detail d;
    int c;
    base(&f, &g, &p);
    for (c = 0; c < COLS; c++)
        g_bearings[c] = 0.5f - 0.01f * (float)c;
    g.bearings = g_bearings;
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_OK, NULL, 0, "decreasing table");
    g_bearings[17] = g_bearings[15]; /* goes back up at 17 */
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_ERR_GEOMETRY, "geometry.bearings",
           (double)g_bearings[17], "non-monotonic");
    actag_check(&f, &g, &p, sizeof g_ws, 4, &d);
    TEST_ASSERT_EQUAL_INT(17, d.index);
    TEST_ASSERT_NOT_NULL(strstr(d.rule, "must be below the previous bearing"));
    TEST_ASSERT_EQUAL_STRING("geometry.bearings", d.other);
    TEST_ASSERT_TRUE(d.limit == (double)g_bearings[16]);
    g_bearings[17] = g_bearings[16]; /* repeated */
    actag_check(&f, &g, &p, sizeof g_ws, 4, &d);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, d.code);
    TEST_ASSERT_EQUAL_INT(17, d.index);
    g_bearings[17] = g_bearings[16] - 1e-7f; /* a tiny azimuth step */
    actag_check(&f, &g, &p, sizeof g_ws, 4, &d);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, d.code);
    TEST_ASSERT_EQUAL_INT(17, d.index);
    TEST_ASSERT_NOT_NULL(strstr(d.rule, "ACTAG_MIN_AZIMUTH_STEP"));
    TEST_ASSERT_TRUE(d.limit == (double)g_bearings[16]);
    for (c = 0; c < COLS; c++)
        g_bearings[c] = 0.5f - 0.01f * (float)c;
    g_bearings[40] = NAN;
    actag_check(&f, &g, &p, sizeof g_ws, 4, &d);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, d.code);
    TEST_ASSERT_EQUAL_INT(40, d.index);
    g_bearings[40] = INFINITY;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, actag_detect(&f, &g, &p, g_ws, sizeof g_ws, NULL, 0, NULL));
    /* a full turn or more */
    for (c = 0; c < COLS; c++)
        g_bearings[c] = 0.11f * (float)c; /* 6.93 rad */
    actag_check(&f, &g, &p, sizeof g_ws, 4, &d);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, d.code);
    TEST_ASSERT_EQUAL_INT(COLS - 1, d.index);
    for (c = 0; c < COLS; c++)
        g_bearings[c] = 0.099f * (float)c; /* 6.24 rad: fine */
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_OK, NULL, 0, "6.24 rad table");
}

/* Boundaries found by mutation testing (tools/mutate/mutate.py): the
 * largest finite bearings are numbers (refused for the table's span, not as
 * non-finite); two equal first bearings get the rule for a table of no
 * direction yet; a passing check resets every field of the detail. */
static void test_bearing_boundaries_and_a_reset_detail(void)
{
    actag_frame f;
    actag_sonar_geometry g;
    actag_params p;
    actag_error_detail d;
    int c;
    base(&f, &g, &p);
    g.bearings = g_bearings;
    for (c = 0; c < COLS; c++)
        g_bearings[c] = -0.5f + 0.01f * (float)c;
    g_bearings[0] = -FLT_MAX;
    actag_check(&f, &g, &p, sizeof g_ws, 4, &d);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, d.code);
    TEST_ASSERT_EQUAL_INT(COLS - 1, d.index); /* the span, at the last entry */
    TEST_ASSERT_TRUE(d.limit == (double)-FLT_MAX); /* against the first */
    TEST_ASSERT_TRUE(d.value == (double)g_bearings[COLS - 1]);
    g_bearings[0] = -0.5f;
    g_bearings[COLS - 1] = FLT_MAX;
    actag_check(&f, &g, &p, sizeof g_ws, 4, &d);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, d.code);
    TEST_ASSERT_EQUAL_INT(COLS - 1, d.index);
    TEST_ASSERT_NULL(strstr(d.rule, "finite"));
    g_bearings[COLS - 1] = -0.5f + 0.01f * (float)(COLS - 1);
    g_bearings[1] = g_bearings[0];
    actag_check(&f, &g, &p, sizeof g_ws, 4, &d);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, d.code);
    TEST_ASSERT_EQUAL_INT(1, d.index);
    TEST_ASSERT_NOT_NULL(strstr(d.rule, "must differ from the previous bearing (the table"));
    g_bearings[1] = -0.49f;
    {   /* two beams a full turn apart */
        static const float two[2] = {0.0f, 6.3f};
        actag_sonar_geometry g2 = g;
        g2.bearings = two;
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, actag_geometry_validate(&g2, ROWS, 2, &d));
        TEST_ASSERT_EQUAL_INT(1, d.index);
        TEST_ASSERT_TRUE(d.limit == 0.0);
        g2.bearings = two + 1; /* one beam: no span */
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_geometry_validate(&g2, ROWS, 1, NULL));
    }
    {   /* the limits themselves: a step of exactly ACTAG_MIN_AZIMUTH_STEP is
         * enough, a span of exactly 6.2831853f (2 pi in float) is a full turn */
        static const float least[2] = {0.0f, ACTAG_MIN_AZIMUTH_STEP};
        static const float turn[2] = {0.0f, 6.2831853f}, turn_down[2] = {6.2831853f, 0.0f};
        static const float below[2] = {0.0f, 6.283185f}, below_down[2] = {6.283185f, 0.0f};
        actag_sonar_geometry g2 = g;
        g2.bearings = least;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_geometry_validate(&g2, ROWS, 2, NULL));
        g2.bearings = turn;
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, actag_geometry_validate(&g2, ROWS, 2, NULL));
        g2.bearings = turn_down;
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, actag_geometry_validate(&g2, ROWS, 2, NULL));
        g2.bearings = below;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_geometry_validate(&g2, ROWS, 2, NULL));
        g2.bearings = below_down;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_geometry_validate(&g2, ROWS, 2, NULL));
    }
    /* an ascending table that turns back is told to go up (a descending one
     * down: test_bearing_tables_name_the_entry) */
    g_bearings[5] = g_bearings[3];
    actag_check(&f, &g, &p, sizeof g_ws, 4, &d);
    TEST_ASSERT_EQUAL_INT(5, d.index);
    TEST_ASSERT_NOT_NULL(strstr(d.rule, "must be above the previous bearing"));
    g_bearings[5] = -0.5f + 0.01f * 5.0f;
    /* the detail of the failure above is replaced, field by field */
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_check(&f, &g, &p, sizeof g_ws, 4, &d));
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, d.code);
    TEST_ASSERT_NULL(d.field);
    TEST_ASSERT_EQUAL_INT(-1, d.index);
    TEST_ASSERT_TRUE(d.value == 0.0);
    TEST_ASSERT_NULL(d.rule);
    TEST_ASSERT_NULL(d.other);
    TEST_ASSERT_TRUE(d.limit == 0.0);
}

/* --------------------------------------------------- frame-derived bounds */

static void test_huge_tag_size_is_rejected_against_the_range(void)
{
    actag_frame f;
    actag_sonar_geometry g;
    actag_params p;
    actag_error_detail d;
    float lim;
    base(&f, &g, &p);
    p.tag_size = 999.0f; /* under ACTAG_MAX_TAG_SIZE: the range decides */
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_ERR_PARAM, "tag_size", (double)999.0f, "999");
    actag_check(&f, &g, &p, sizeof g_ws, 4, &d);
    TEST_ASSERT_EQUAL_STRING("geometry.max_range", d.other);
    lim = 1.41421356f * g.max_range;
    TEST_ASSERT_TRUE(d.limit == (double)lim);
    p.tag_size = lim; /* the bound itself is fine */
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_OK, NULL, 0, "sqrt(2) max_range");
    p.tag_size = nextafterf(lim, 1e9f);
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_ERR_PARAM, "tag_size", (double)p.tag_size,
           "just above sqrt(2) max_range");
    /* actag_params_validate alone has no geometry: it accepts what is under
     * ACTAG_MAX_TAG_SIZE and refuses what the corner refinement would */
    p.tag_size = 999.0f;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_params_validate(&p, &d));
    p.tag_size = ACTAG_MAX_TAG_SIZE;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_params_validate(&p, &d));
    TEST_ASSERT_EQUAL_STRING("tag_size", d.field);
}

/* A sonar and tag scaled together are the same detection problem; a tag the
 * corner refinement refuses (tag_size >= ACTAG_MAX_TAG_SIZE) was reported
 * with its corners silently unrefined (review, seventeenth session): it is
 * an error naming tag_size now, and just under the bound it is accepted. */
static void test_tag_size_the_refinement_refuses_is_an_error(void)
{
    actag_frame f;
    actag_sonar_geometry g;
    actag_params p;
    actag_error_detail d;
    base(&f, &g, &p);
    g.min_range = 100.0f;
    g.max_range = 1500.0f;
    p.tag_size = ACTAG_MAX_TAG_SIZE;
    TEST_ASSERT_TRUE(p.tag_size <= 1.41421356f * g.max_range); /* the range rule allows it */
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_ERR_PARAM, "tag_size", (double)p.tag_size, "1000");
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_check(&f, &g, &p, sizeof g_ws, 4, &d));
    TEST_ASSERT_EQUAL_STRING("tag_size", d.field);
    p.tag_size = nextafterf(ACTAG_MAX_TAG_SIZE, 0.0f);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_check(&f, &g, &p, sizeof g_ws, 4, &d));
}

static void test_tiny_azimuth_steps(void)
{
    actag_frame f;
    actag_sonar_geometry g;
    actag_params p;
    actag_error_detail d;
    base(&f, &g, &p);
    g.aperture = 1e-9f;
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_ERR_GEOMETRY, "geometry.aperture", (double)1e-9f,
           "aperture 1e-9");
    actag_check(&f, &g, &p, sizeof g_ws, 4, &d);
    TEST_ASSERT_EQUAL_STRING("frame.cols", d.other);
    TEST_ASSERT_FLOAT_WITHIN(1e-9f, 63e-6f, (float)d.limit);
    /* one column: no step at all, any valid aperture */
    f.cols = 1;
    f.stride = 1;
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_OK, NULL, 0, "one column");
}

/* The search stage converts pixel counts to int: for any finite input that
 * must stay defined (capped), even when called directly without the
 * pipeline's validation. */
static void test_search_counts_stay_defined(void)
{
    static int16_t map[ACTAG_SEARCH_MAP_SIZE(ROWS, COLS) / 2];
    static uint32_t ii[ACTAG_SEARCH_INTEGRAL_SIZE(ROWS, COLS) / 4];
    actag_frame f;
    actag_sonar_geometry g;
    actag_params p;
    actag_search z;
    actag_point q[4];
    int i, n;
    const float sizes[] = {1e30f, 2.9e38f, 1e-30f};
    base(&f, &g, &p);
    g.min_range = 0.0f; /* the first rows are at (almost) zero range */
    for (i = 0; i < 3; i++) {
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_search_map(&z, g_px, ROWS, COLS, COLS, &g, sizes[i],
                                                          24, 0.75f, map, sizeof map, ii,
                                                          sizeof ii));
        n = 0;
        while (n < 20 && actag_search_next(&z, 0, &g, sizes[i], 0.75f, ROWS, COLS, q))
            n++;
        if (i < 2) /* a tag larger than the frame fits nowhere */
            TEST_ASSERT_EQUAL_INT(0, n);
    }
    /* and through the pipeline a huge tag is an error, not a search */
    p.tag_size = 3e38f;
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_ERR_PARAM, "tag_size", (double)3e38f, "3e38");
}

/* ---------------------------------------------------------------- frame */

static void test_frame_fields(void)
{
    actag_frame f;
    actag_sonar_geometry g;
    actag_params p;
    actag_error_detail d;
    base(&f, &g, &p);
    f.rows = 0;
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_ERR_SIZE, "frame.rows", 0, "rows 0");
    f.rows = ACTAG_MAX_DIM + 1;
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_ERR_SIZE, "frame.rows", ACTAG_MAX_DIM + 1, "rows max+1");
    f.rows = ROWS;
    f.cols = -5;
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_ERR_SIZE, "frame.cols", -5, "cols -5");
    f.cols = COLS;
    f.stride = COLS - 1;
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_ERR_SIZE, "frame.stride", COLS - 1, "stride < cols");
    actag_check(&f, &g, &p, sizeof g_ws, 4, &d);
    TEST_ASSERT_EQUAL_STRING("frame.cols", d.other);
    TEST_ASSERT_TRUE(d.limit == COLS);
    f.stride = COLS;
    f.depth = 12;
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_ERR_SIZE, "frame.depth", 12, "depth 12");
    f.depth = 8;
    /* one row and one column, the least frame */
    f.rows = 1;
    f.cols = 1;
    expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_OK, NULL, 0, "1 x 1");
    f.rows = ROWS;
    f.cols = COLS;
    if (sizeof(size_t) == 4) { /* 32-bit targets: addresses must not wrap */
        f.rows = 30000;
        f.stride = 1 << 20;
        actag_check(&f, &g, &p, (size_t)-1, 4, &d);
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, d.code);
        TEST_ASSERT_EQUAL_STRING("frame.stride", d.field);
    }
}

static void test_null_pointers(void)
{
    actag_frame f;
    actag_sonar_geometry g;
    actag_params p;
    actag_error_detail d;
    actag_detection det[2];
    base(&f, &g, &p);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_check(NULL, &g, &p, sizeof g_ws, 2, &d));
    TEST_ASSERT_EQUAL_STRING("frame", d.field);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_check(&f, NULL, &p, sizeof g_ws, 2, &d));
    TEST_ASSERT_EQUAL_STRING("geometry", d.field);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_check(&f, &g, NULL, sizeof g_ws, 2, &d));
    TEST_ASSERT_EQUAL_STRING("params", d.field);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_detect(NULL, &g, &p, g_ws, sizeof g_ws, det, 2, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_detect(&f, &g, &p, NULL, sizeof g_ws, det, 2, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_detect(&f, &g, &p, g_ws, sizeof g_ws, NULL, 2, NULL));
    f.data = NULL;
    expect(&f, &g, &p, sizeof g_ws, 2, ACTAG_ERR_NULL, "frame.data", 0.0, "data NULL");
    base(&f, &g, &p);
    p.family = NULL;
    expect(&f, &g, &p, sizeof g_ws, 2, ACTAG_ERR_NULL, "family", 0.0, "family NULL");
    /* no out array is fine with max_out 0 */
    base(&f, &g, &p);
    TEST_ASSERT_TRUE(actag_detect(&f, &g, &p, g_ws, sizeof g_ws, NULL, 0, NULL) >= 0);
    /* the detail pointer is optional everywhere */
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_check(&f, &g, &p, sizeof g_ws, 2, NULL));
}

static void test_max_out_and_workspace(void)
{
    actag_frame f;
    actag_sonar_geometry g;
    actag_params p;
    actag_error_detail d;
    size_t need;
    base(&f, &g, &p);
    expect(&f, &g, &p, sizeof g_ws, -1, ACTAG_ERR_PARAM, "max_out", -1, "max_out -1");
    need = actag_workspace_size(ROWS, COLS);
    TEST_ASSERT_EQUAL_UINT(sizeof g_ws, need);
    expect(&f, &g, &p, need - 1, 4, ACTAG_ERR_WORKSPACE, "workspace_size", (double)(need - 1),
           "one byte too small");
    actag_check(&f, &g, &p, need - 1, 4, &d);
    TEST_ASSERT_TRUE(d.limit == (double)need);
    expect(&f, &g, &p, need, 4, ACTAG_OK, NULL, 0, "exact workspace");
}

/* The order of the checks is actag_detect's: with several faults the code
 * is the first one's, in both. */
static void test_first_fault_wins_in_both(void)
{
    actag_frame f;
    actag_sonar_geometry g;
    actag_params p;
    base(&f, &g, &p);
    f.stride = 1;                        /* SIZE */
    p.tuning.median_radius = -1;         /* PARAM */
    g.aperture = 0.0f;                   /* GEOMETRY */
    expect(&f, &g, &p, 1, 4, ACTAG_ERR_SIZE, "frame.stride", 1, "size first");
    f.stride = COLS;
    expect(&f, &g, &p, 1, 4, ACTAG_ERR_PARAM, "tuning.median_radius", -1, "params second");
    p.tuning.median_radius = 2;
    expect(&f, &g, &p, 1, 4, ACTAG_ERR_GEOMETRY, "geometry.aperture", 0, "geometry third");
    g.aperture = 1.0f;
    expect(&f, &g, &p, 1, 4, ACTAG_ERR_WORKSPACE, "workspace_size", 1, "workspace last");
}

/* Random mixes of edge values: actag_detect fails exactly when actag_check
 * does, with the same code, and the struct validators agree with it. */
static void test_random_edge_values_agree(void)
{
    static const double edges[] = {0, -1, 1, 0.5, 1.5, 1e6, 1e7, -1e7, 1e-7, 2, 255, 256, 33,
                                   (double)NAN, (double)INFINITY, -(double)INFINITY};
    int t, errors = 0;
    tu_seed(77);
    for (t = 0; t < 400; t++) {
        actag_frame f;
        actag_sonar_geometry g;
        actag_params p;
        actag_error_detail d;
        actag_detection det[4];
        const field_case *fc;
        int n, rc, pv;
        uint32_t pick, e1, e2;
        base(&f, &g, &p);
        pick = tu_rand() % (uint32_t)NPARAM_CASES;
        e1 = tu_rand() % (uint32_t)(sizeof edges / sizeof edges[0]);
        fc = &param_cases[pick];
        set_field(&p, fc, edges[e1]);
        e2 = tu_rand() % (uint32_t)(sizeof edges / sizeof edges[0]);
        if (tu_rand() & 1u) {
            float x = (float)edges[e2];
            g.min_range = x >= 0.0f ? x * 0.1f : x;
        }
        n = actag_detect(&f, &g, &p, g_ws, sizeof g_ws, det, 4, NULL);
        rc = actag_check(&f, &g, &p, sizeof g_ws, 4, &d);
        pv = actag_params_validate(&p, NULL);
        if (n < 0)
            errors++;
        TEST_ASSERT_EQUAL_INT(d.code, rc);
        TEST_ASSERT_EQUAL_INT(rc, n < 0 ? n : ACTAG_OK);
        if (pv != ACTAG_OK) /* the params are checked before the geometry */
            TEST_ASSERT_EQUAL_INT(pv, rc);
        if (rc == ACTAG_OK)
            TEST_ASSERT_EQUAL_INT(ACTAG_OK, pv);
    }
    TEST_ASSERT_TRUE(errors > 50 && errors < 400); /* both outcomes were drawn */
}

/* ---------------------------------------------- stages use the validators */

static void test_quad_stage_rejects_what_the_validator_rejects(void)
{
    actag_ipoint pts[64];
    uint8_t scratch[ACTAG_QUAD_SCRATCH_SIZE(64)];
    actag_quad_params qp;
    actag_quad out;
    actag_rng rng;
    int i, k;
    static const float vals[] = {0.0f, 1.5f, 1e7f, -1.0f, 0.5f, 1.0f, 2.5f, 1e6f};
    for (i = 0; i < 64; i++) { /* a 16 x 16 square's border */
        int s = i / 16, t = i % 16;
        pts[i].x = (int16_t)(s == 0 ? t : s == 1 ? 16 : s == 2 ? 16 - t : 0);
        pts[i].y = (int16_t)(s == 0 ? 0 : s == 1 ? t : s == 2 ? 16 : 16 - t);
    }
    for (k = 0; k < 4 * 8 + 1; k++) {
        int rc, v;
        actag_quad_params_default(&qp);
        if (k < 32) {
            float x = vals[k % 8];
            switch (k / 8) {
            case 0: qp.min_inlier_ratio = x; break;
            case 1: qp.inlier_ratio = x; break;
            case 2: qp.inlier_distance = x; break;
            default: qp.sample_fraction = x; break;
            }
        } else {
            qp.min_inlier_ratio = NAN;
        }
        v = actag_quad_params_validate(&qp, NULL);
        actag_rng_seed(&rng, 1u);
        rc = actag_quad_fit(pts, 64, &qp, &rng, scratch, sizeof scratch, &out);
        if (v != ACTAG_OK)
            TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, rc);
        else
            TEST_ASSERT_TRUE(rc == ACTAG_OK || rc == ACTAG_ERR_NO_QUAD);
    }
}

static void test_fit_decoder_rejects_what_the_validator_rejects(void)
{
    actag_fit_params fp;
    actag_decode_result res;
    actag_point q[4] = {{20, 10}, {40, 10}, {40, 30}, {20, 30}};
    actag_frame f;
    actag_sonar_geometry g;
    actag_params p;
    int k;
    base(&f, &g, &p);
    for (k = 0; k < 9; k++) {
        int rc, v;
        actag_fit_params_default(&fp);
        switch (k) {
        case 0: fp.level = 1.5f; break;
        case 1: fp.min_contrast = 300; break;
        case 2: fp.sample_offset = NAN; break;
        case 3: fp.min_margin = INFINITY; break;
        case 4: fp.min_bit_margin = -1; break;
        case 5: fp.many_corrections = 34; break;
        case 6: fp.many_corrections_margin = -1.0f; break;
        case 7: fp.min_bit_odds = 0; break;
        default: break; /* valid */
        }
        v = actag_fit_params_validate(&fp, NULL);
        rc = actag_decode_quad_fit(g_px, ROWS, COLS, COLS, q, &g_fam, 2, &fp, &res);
        if (k < 8) {
            TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, v);
            TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, rc);
        } else {
            TEST_ASSERT_EQUAL_INT(ACTAG_OK, v);
            TEST_ASSERT_TRUE(rc == ACTAG_OK || rc == ACTAG_ERR_NO_MATCH);
        }
    }
}

/* Radii 0 and larger than the frame are valid: a correct (empty) result. */
static void test_radii_zero_and_larger_than_the_frame(void)
{
    actag_frame f;
    actag_sonar_geometry g;
    actag_params p;
    static const int radii[][2] = {{0, 0}, {ACTAG_MEDIAN_MAX_RADIUS, ACTAG_MAX_THRESHOLD_RADIUS},
                                   {0, ACTAG_MAX_THRESHOLD_RADIUS}, {100, 0}};
    int i;
    for (i = 0; i < 4; i++) {
        base(&f, &g, &p);
        f.rows = 10; /* smaller than both radii */
        f.cols = 12;
        f.stride = COLS;
        p.tuning.median_radius = radii[i][0];
        p.tuning.threshold_radius = radii[i][1];
        expect(&f, &g, &p, sizeof g_ws, 4, ACTAG_OK, NULL, 0, "radius vs small frame");
    }
}

/* actag_detect_multi: the first failing set's actag_check code. */
static void test_multi_reports_the_check_of_each_set(void)
{
    actag_frame f;
    actag_sonar_geometry g;
    actag_params p[2];
    actag_detection det[8];
    int counts[2];
    base(&f, &g, &p[0]);
    p[1] = p[0];
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_detect_multi(&f, &g, p, 2, g_ws, sizeof g_ws, det, 4,
                                                      counts));
    p[1].tuning.quad.min_inlier_ratio = 0.0f;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_detect_multi(&f, &g, p, 2, g_ws, sizeof g_ws,
                                                             det, 4, counts));
    p[1] = p[0];
    p[1].max_bit_corrections = 9;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_CORRECTIONS, actag_detect_multi(&f, &g, p, 2, g_ws,
                                                                   sizeof g_ws, det, 4, counts));
    p[1] = p[0];
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE, actag_detect_multi(&f, &g, p, 2, g_ws,
                                                                 sizeof g_ws - 1, det, 4, counts));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_detect_multi(&f, &g, p, 0, g_ws, sizeof g_ws,
                                                             det, 4, counts));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_every_params_and_tuning_field);
    RUN_TEST(test_struct_validators_name_fields_relative_to_their_argument);
    RUN_TEST(test_invalid_family);
    RUN_TEST(test_every_geometry_field);
    RUN_TEST(test_swapped_and_too_close_ranges);
    RUN_TEST(test_flags);
    RUN_TEST(test_bearing_tables_name_the_entry);
    RUN_TEST(test_bearing_boundaries_and_a_reset_detail);
    RUN_TEST(test_huge_tag_size_is_rejected_against_the_range);
    RUN_TEST(test_tag_size_the_refinement_refuses_is_an_error);
    RUN_TEST(test_tiny_azimuth_steps);
    RUN_TEST(test_search_counts_stay_defined);
    RUN_TEST(test_frame_fields);
    RUN_TEST(test_null_pointers);
    RUN_TEST(test_max_out_and_workspace);
    RUN_TEST(test_first_fault_wins_in_both);
    RUN_TEST(test_random_edge_values_agree);
    RUN_TEST(test_quad_stage_rejects_what_the_validator_rejects);
    RUN_TEST(test_fit_decoder_rejects_what_the_validator_rejects);
    RUN_TEST(test_radii_zero_and_larger_than_the_frame);
    RUN_TEST(test_multi_reports_the_check_of_each_set);
    return UNITY_END();
}
