/* Bounded time (issue 10): every image-dependent loop of actag_detect stops
 * at its actag_limits value, and actag_stats counts each time a limit was
 * reached. Each limit is set low on a frame that needs more and its counter
 * checked (and that the default does not trip it); on the whole adversarial
 * set (tests/adversarial.h) the default limits hold the work (decoder calls,
 * RANSAC iterations, contours) within bounds, whatever the frame; invalid
 * limits are parameter errors; the defaults leave the example frame's
 * detection as it is. */
#include "unity.h"
#include "test_util.h"
#include "adversarial.h"

#include "actag/actag.h"

void setUp(void) {}
void tearDown(void) {}

#define EXAMPLE ACTAG_SOURCE_DIR "/data/exampleSonarImage.pgm"

static uint8_t g_ws[ACTAG_WORKSPACE_SIZE(ADV_ROWS, ADV_COLS)];
static uint8_t g_img[ADV_ROWS * ADV_COLS];
static actag_family g_fam;
static const actag_sonar_geometry g_geo = {0.1f, 1.5f, 1.0471976f, NULL, 0u};

static void params(actag_params *p)
{
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &g_fam));
    actag_params_default(p);
    p->family = &g_fam;
}

static int detect(const actag_params *p, actag_stats *st)
{
    actag_frame f = {g_img, ADV_ROWS, ADV_COLS, ADV_COLS, 8};
    actag_detection det[16];
    return actag_detect(&f, &g_geo, p, g_ws, sizeof g_ws, det, 16, st);
}

static void frame(const char *name)
{
    adv_spec v[48];
    int n = adv_specs(v, 0), i;
    for (i = 0; i < n; i++)
        if (strcmp(v[i].name, name) == 0) {
            adv_generate(&v[i], g_img);
            return;
        }
    TEST_FAIL_MESSAGE(name);
}

static void test_defaults_and_validation(void)
{
    actag_params p;
    int i;
    params(&p);
    TEST_ASSERT_EQUAL_INT(ACTAG_LIMIT_CONTOURS, p.tuning.limits.max_contours);
    TEST_ASSERT_EQUAL_INT(ACTAG_LIMIT_CONTOUR_POINTS, p.tuning.limits.max_contour_points);
    TEST_ASSERT_EQUAL_INT(ACTAG_LIMIT_CONTOUR_ITERATIONS, p.tuning.limits.max_contour_iterations);
    TEST_ASSERT_EQUAL_INT(ACTAG_LIMIT_FRAME_ITERATIONS, p.tuning.limits.max_frame_iterations);
    TEST_ASSERT_EQUAL_INT(ACTAG_LIMIT_DECODES, p.tuning.limits.max_decodes);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_params_validate(&p, NULL));
    for (i = 0; i < 5; i++) {
        actag_params q = p;
        int *f[5] = {&q.tuning.limits.max_contours, &q.tuning.limits.max_contour_points,
                     &q.tuning.limits.max_contour_iterations, &q.tuning.limits.max_frame_iterations,
                     &q.tuning.limits.max_decodes};
        *f[i] = 0;
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_params_validate(&q, NULL));
        *f[i] = -5;
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_params_validate(&q, NULL));
        *f[i] = 1;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_params_validate(&q, NULL));
    }
}

static void test_contours_examined(void)
{
    actag_params p;
    actag_stats st;
    params(&p);
    frame("blobs 4px gap 2 (7.5k)");
    TEST_ASSERT_EQUAL_INT(0, detect(&p, &st));
    TEST_ASSERT_TRUE(st.contours > 5000);
    TEST_ASSERT_EQUAL_INT(0, st.contour_cap);
    p.tuning.limits.max_contours = 100;
    TEST_ASSERT_EQUAL_INT(0, detect(&p, &st));
    TEST_ASSERT_EQUAL_INT(100, st.contours);
    TEST_ASSERT_EQUAL_INT(1, st.contour_cap);
}

/* The example frame into g_img (cut to its size, black beyond). */
static void example_frame(void)
{
    int rows = 0, cols = 0, r;
    uint8_t *img = tu_read_pgm(EXAMPLE, &rows, &cols);
    TEST_ASSERT_NOT_NULL(img);
    memset(g_img, 0, sizeof g_img);
    for (r = 0; r < rows && r < ADV_ROWS; r++)
        memcpy(g_img + (size_t)r * ADV_COLS, img + (size_t)r * (size_t)cols,
               (size_t)(cols < ADV_COLS ? cols : ADV_COLS));
    free(img);
}

static void test_points_per_contour(void)
{
    actag_params p;
    actag_stats st, st0;
    example_frame();
    params(&p);
    detect(&p, &st0);
    p.tuning.limits.max_contour_points = 20;
    detect(&p, &st);
    /* every border over 20 points is skipped now, and counted */
    TEST_ASSERT_TRUE(st.overflowed > st0.overflowed);
    TEST_ASSERT_EQUAL_INT(st0.contours, st.contours);
    TEST_ASSERT_EQUAL_INT(0, st.size_ok);
    TEST_ASSERT_EQUAL_INT(0, st.quads);
}

/* A border longer than the quad fit takes (ACTAG_QUAD_MAX_POINTS) is
 * skipped and counted in stats.overflowed even when max_contour_points and
 * the frame's ACTAG_CONTOUR_CAP allow it (before, it reached the quad fit,
 * which refused it without a count). A 12 x 17000 frame with a 6-row white
 * band along it: one border of about 34,000 points, CAP 68,112. */
static void test_border_longer_than_the_quad_fit_takes(void)
{
    enum { R = 12, C = 17000 };
    actag_params p;
    actag_stats st;
    actag_frame f;
    actag_detection det[4];
    size_t wsz = actag_workspace_size(R, C);
    uint8_t *img = (uint8_t *)malloc((size_t)R * C), *ws = (uint8_t *)malloc(wsz);
    int r, c;
    TEST_ASSERT_TRUE(ACTAG_CONTOUR_CAP(R, C) > (size_t)ACTAG_QUAD_MAX_POINTS);
    if (!img || !ws) {
        free(img);
        free(ws);
        TEST_IGNORE_MESSAGE("no memory for a 12 x 17000 frame and its workspace");
    }
    for (r = 0; r < R; r++)
        for (c = 0; c < C; c++)
            img[(size_t)r * C + (size_t)c] = (uint8_t)(r >= 3 && r <= 8 && c >= 5 && c < C - 5 ? 220 : 10);
    f.data = img;
    f.rows = R;
    f.cols = C;
    f.stride = C;
    f.depth = 8;
    params(&p);
    p.tuning.median_radius = 0;
    p.tuning.limits.max_contour_points = 0x7fffffff;
    TEST_ASSERT_EQUAL_INT(0, actag_detect(&f, &g_geo, &p, ws, wsz, det, 4, &st));
    TEST_ASSERT_TRUE(st.contours >= 1);
    TEST_ASSERT_EQUAL_INT(1, st.overflowed);
    TEST_ASSERT_EQUAL_INT(0, st.quads);
    free(img);
    free(ws);
}

static void test_ransac_iterations_per_contour_and_frame(void)
{
    actag_params p;
    actag_stats st, st0;
    params(&p);
    frame("small tag-sized squares");
    p.tuning.limits.max_decodes = 1000000; /* only RANSAC limited here */
    detect(&p, &st0);
    TEST_ASSERT_TRUE(st0.iterations > 1000);
    TEST_ASSERT_EQUAL_INT(0, st0.frame_budget);
    TEST_ASSERT_EQUAL_INT(0, st0.contour_budget);
    /* per frame */
    p.tuning.limits.max_frame_iterations = 250;
    detect(&p, &st);
    TEST_ASSERT_TRUE(st.iterations <= 250);
    TEST_ASSERT_TRUE(st.frame_budget > 0);
    /* per contour: below one fit's 100 iterations */
    p.tuning.limits.max_frame_iterations = ACTAG_LIMIT_FRAME_ITERATIONS;
    p.tuning.limits.max_contour_iterations = 30;
    detect(&p, &st);
    TEST_ASSERT_TRUE(st.contour_budget > 0);
    TEST_ASSERT_TRUE(st.contour_budget <= st.size_ok);
    TEST_ASSERT_TRUE(st.iterations <= 30 * st.size_ok);
    /* fits that ran all their iterations are counted with any limits */
    TEST_ASSERT_TRUE(st0.ransac_exhausted > 0);
}

/* A clean white square: every fit stops early on its first iteration. A
 * cap that is lowered but never reached is not a limit reached, and a fit
 * that stops on its last allowed iteration did not run out (review,
 * seventeenth session: both were counted). */
static void test_limits_counted_only_when_reached(void)
{
    actag_params p;
    actag_stats st;
    int r, c, i;
    memset(g_img, 0, sizeof g_img);
    for (r = 200; r < 245; r++)
        for (c = 200; c < 275; c++)
            g_img[(size_t)r * ADV_COLS + (size_t)c] = 200;
    params(&p);
    p.tuning.search_candidates = 0;
    detect(&p, &st);
    TEST_ASSERT_TRUE(st.quads >= 1);
    TEST_ASSERT_EQUAL_INT(st.quads, st.iterations); /* one iteration a fit */
    TEST_ASSERT_EQUAL_INT(0, st.ransac_exhausted);
    /* one iteration a fit allowed: it stops early on it */
    p.tuning.quad.max_iterations = 1;
    detect(&p, &st);
    TEST_ASSERT_TRUE(st.quads >= 1);
    TEST_ASSERT_EQUAL_INT(0, st.ransac_exhausted);
    /* the contour's, then the frame's cap lowered below quad.max_iterations,
     * far above what the fits use */
    for (i = 0; i < 2; i++) {
        params(&p);
        p.tuning.search_candidates = 0;
        *(i == 0 ? &p.tuning.limits.max_contour_iterations
                 : &p.tuning.limits.max_frame_iterations) = 50;
        detect(&p, &st);
        TEST_ASSERT_TRUE(st.quads >= 1);
        TEST_ASSERT_TRUE(st.iterations < 50);
        TEST_ASSERT_EQUAL_INT(0, st.contour_budget);
        TEST_ASSERT_EQUAL_INT(0, st.frame_budget);
    }
}

static void test_decoder_calls(void)
{
    actag_params p;
    actag_stats st;
    params(&p);
    frame("tag-sized squares");
    p.tuning.limits.max_decodes = 1000000;
    detect(&p, &st);
    TEST_ASSERT_TRUE(st.decodes > ACTAG_LIMIT_DECODES);
    TEST_ASSERT_EQUAL_INT(0, st.decode_cap);
    p.tuning.limits.max_decodes = 5;
    detect(&p, &st);
    TEST_ASSERT_EQUAL_INT(5, st.decodes);
    TEST_ASSERT_TRUE(st.decode_cap > 0);
    p.tuning.limits.max_decodes = ACTAG_LIMIT_DECODES;
    detect(&p, &st);
    TEST_ASSERT_EQUAL_INT(ACTAG_LIMIT_DECODES, st.decodes);
    TEST_ASSERT_TRUE(st.decode_cap > 0);
}

static void test_search_and_guess_limits_are_counted(void)
{
    actag_params p;
    actag_stats st;
    params(&p);
    frame("tag-sized squares");
    p.tuning.limits.max_decodes = 1000000;
    p.tuning.search_candidates = 1;
    detect(&p, &st);
    TEST_ASSERT_EQUAL_INT(1, st.searched);
    TEST_ASSERT_EQUAL_INT(1, st.search_cap); /* more bright squares than one */
    TEST_ASSERT_TRUE(st.guess_cap > 0);      /* more unread blobs than 16 guesses */
    p.tuning.search_candidates = 0;
    detect(&p, &st);
    TEST_ASSERT_EQUAL_INT(0, st.searched);
    TEST_ASSERT_EQUAL_INT(0, st.search_cap);
}

/* The limits' flags at their boundaries. contour_cap: a frame of exactly
 * max_contours borders was examined whole (0), one fewer cuts it (1).
 * search_cap: on a frame with N search candidates (2..7, all read at the
 * defaults), search_candidates N reads all (0); max_decodes N - 1 leaves
 * the last candidate undecoded (1; it was 0: the refused candidate had been
 * taken from the search, which then reported none left). */
static void test_limit_flags_at_their_boundaries(void)
{
    adv_spec v[48];
    actag_params p;
    actag_stats st, st0;
    int n = adv_specs(v, 0), i, found = 0;
    params(&p);
    frame("blobs 4px gap 2 (7.5k)");
    detect(&p, &st0);
    TEST_ASSERT_EQUAL_INT(0, st0.contour_cap);
    p.tuning.limits.max_contours = st0.contours;
    detect(&p, &st);
    TEST_ASSERT_EQUAL_INT(st0.contours, st.contours);
    TEST_ASSERT_EQUAL_INT(0, st.contour_cap);
    p.tuning.limits.max_contours = st0.contours - 1;
    detect(&p, &st);
    TEST_ASSERT_EQUAL_INT(st0.contours - 1, st.contours);
    TEST_ASSERT_EQUAL_INT(1, st.contour_cap);
    /* the adversarial frames, then the example frame, at rising least
     * scores until one has 2..7 candidates */
    for (i = 0; i <= n && !found; i++) {
        int ms;
        if (i < n)
            adv_generate(&v[i], g_img);
        else
            example_frame();
        for (ms = 4; ms <= 64 && !found; ms += 4) {
            params(&p);
            p.tuning.search_candidates = ACTAG_SEARCH_MAX;
            p.tuning.search_min_score = ms;
            p.tuning.limits.max_decodes = 1000000;
            detect(&p, &st0);
            if (st0.searched < 2 || st0.searched >= ACTAG_SEARCH_MAX || st0.search_cap)
                continue;
            found = 1;
            p.tuning.search_candidates = st0.searched;
            detect(&p, &st);
            TEST_ASSERT_EQUAL_INT(st0.searched, st.searched);
            TEST_ASSERT_EQUAL_INT(0, st.search_cap);
            p.tuning.limits.max_decodes = st0.searched - 1;
            detect(&p, &st);
            TEST_ASSERT_EQUAL_INT(st0.searched - 1, st.searched);
            TEST_ASSERT_EQUAL_INT(1, st.search_cap);
        }
    }
    TEST_ASSERT_TRUE_MESSAGE(found, "no frame with 2..7 search candidates");
}

/* Whatever the frame, the default limits bound the work. */
static void test_adversarial_set_within_the_default_limits(void)
{
    adv_spec v[48];
    actag_params p;
    int n = adv_specs(v, 0), i;
    params(&p);
    TEST_ASSERT_TRUE(n >= 25);
    for (i = 0; i < n; i++) {
        actag_stats st;
        int rc;
        adv_generate(&v[i], g_img);
        rc = detect(&p, &st);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, rc, v[i].name); /* no tag in any of them */
        TEST_ASSERT_TRUE_MESSAGE(st.decodes <= ACTAG_LIMIT_DECODES, v[i].name);
        TEST_ASSERT_TRUE_MESSAGE(st.iterations <= ACTAG_LIMIT_FRAME_ITERATIONS, v[i].name);
        TEST_ASSERT_TRUE_MESSAGE(st.contours <= ACTAG_LIMIT_CONTOURS, v[i].name);
    }
}

static void test_defaults_keep_the_example_detection(void)
{
    static uint8_t ws[ACTAG_WORKSPACE_SIZE(463, 620)];
    actag_params p;
    actag_stats st;
    actag_detection det[4];
    int rows = 0, cols = 0;
    uint8_t *img = tu_read_pgm(EXAMPLE, &rows, &cols);
    actag_frame f;
    const actag_sonar_geometry geo = {0.1f, 1.5f, 1.0472f, NULL, 0u};
    TEST_ASSERT_NOT_NULL(img);
    params(&p);
    f.data = img;
    f.rows = rows;
    f.cols = cols;
    f.stride = cols;
    f.depth = 8;
    TEST_ASSERT_EQUAL_INT(1, actag_detect(&f, &geo, &p, ws, sizeof ws, det, 4, &st));
    TEST_ASSERT_EQUAL_INT(0, det[0].id);
    TEST_ASSERT_EQUAL_INT(0, st.contour_cap + st.contour_budget + st.frame_budget + st.decode_cap);
    TEST_ASSERT_TRUE(st.decodes >= 1 && st.decodes <= ACTAG_LIMIT_DECODES);
    free(img);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_defaults_and_validation);
    RUN_TEST(test_contours_examined);
    RUN_TEST(test_points_per_contour);
    RUN_TEST(test_border_longer_than_the_quad_fit_takes);
    RUN_TEST(test_ransac_iterations_per_contour_and_frame);
    RUN_TEST(test_limits_counted_only_when_reached);
    RUN_TEST(test_decoder_calls);
    RUN_TEST(test_search_and_guess_limits_are_counted);
    RUN_TEST(test_limit_flags_at_their_boundaries);
    RUN_TEST(test_adversarial_set_within_the_default_limits);
    RUN_TEST(test_defaults_keep_the_example_detection);
    return UNITY_END();
}
