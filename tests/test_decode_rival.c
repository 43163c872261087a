/* Two readings of one place that disagree (src/decode_fit_grids.h,
 * actag__fit_rival_explains; detect.c refuses a quad's reading when the
 * structure search's reading there explains the cells at least as well).
 * On rendered tags (any ID, plain or mirrored, clean or speckled) the right
 * reading must beat another ID, the other handedness and every other corner
 * order on the same corners, and lose to itself (a tie counts for the
 * rival); each residual, polished from the reading's own grid, is at most
 * the brute-force residual of that grid (cell means by the straightforward
 * sampler of decode_fit_test.h, a two-level least-squares fit written out
 * here); bad arguments are errors. And the corner completions of a blind
 * guess (src/readings.c, actag__complete_corner) against the arithmetic
 * written out in double on random quads and on boxes, points and kites
 * either side of the quarter-side rule. */
#include "../src/decode_fit_grids.h"
#include "../src/decode_fit_test.h"
#include "actag/render.h"
#include "actag/tag_grid.h"
#include "actag/family.h"
#include "actag/rng.h"
#include "../src/readings.h"

#include "unity.h"
#include "test_util.h"

#include <math.h>
#include <string.h>

void setUp(void) {}
void tearDown(void) {}

#define CELL 9
#define MARGIN 14
#define SIDE_MAX 160

static uint8_t g_img[SIDE_MAX * SIDE_MAX];

/* Tag `id` rendered (mirrored left-right if asked) with speckle of +-noise;
 * returns the side. */
static int make_tag(const actag_family *fam, int id, int mirror, int noise)
{
    static uint8_t t[SIDE_MAX * SIDE_MAX];
    int side = actag_render_side(fam->bits, CELL, MARGIN), r, c;
    TEST_ASSERT_TRUE(side > 0 && side <= SIDE_MAX);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_render_tag(fam, id, CELL, MARGIN, 40, 0, t, side,
                                                     sizeof t));
    for (r = 0; r < side; r++)
        for (c = 0; c < side; c++) {
            int v = (int)t[r * side + (mirror ? side - 1 - c : c)] * 3 / 4 + 20 +
                    tu_range(-noise, noise);
            g_img[r * side + c] = (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : v);
        }
    return side;
}

/* The white square's corners in tag order (TL TR BR BL as printed) of the
 * tag make_tag rendered. */
static void tag_corners(int bits, int side, int mirror, actag_point q[4])
{
    int k = bits / 4, i;
    float lo = (float)(MARGIN + 2 * CELL) - 0.5f, hi = (float)(MARGIN + (k - 1) * CELL) - 0.5f;
    static const int sx[4] = {0, 1, 1, 0}, sy[4] = {0, 0, 1, 1};
    for (i = 0; i < 4; i++) {
        float x = sx[i] ? hi : lo;
        q[i].x = mirror ? (float)(side - 1) - x : x;
        q[i].y = sy[i] ? hi : lo;
    }
}

/* Brute-force residual of the template of `code` on the grid of make_tag's
 * tag: 9-sample cell means by decode_fit_test.h's reference sampler, the
 * erased data corners left out, black and white levels by least squares. */
static float brute_rss(const actag_family *fam, uint32_t code, int side, int mirror,
                       const actag_fit_params *fp)
{
    float m[81], unused[81], g[6], sw = 0.0f, sb = 0.0f, ss = 0.0f;
    int k = fam->bits / 4, n = k + 1, cx, cy, nw = 0, nb = 0;
    int erase = (fp->flags & ACTAG_FIT_ERASE_CORNERS) != 0;
    float centre = (float)MARGIN + 0.5f * (float)(n * CELL) - 0.5f;
    g[0] = mirror ? (float)(side - 1) - centre : centre;
    g[1] = centre;
    g[2] = mirror ? -(float)CELL : (float)CELL;
    g[3] = 0.0f;
    g[4] = 0.0f;
    g[5] = (float)CELL;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag__fit_scalar_cells(g_img, side, side, side, g, k,
                                                            fp->sample_offset, 0, m, unused));
    for (cy = 0; cy < n; cy++)
        for (cx = 0; cx < n; cx++) {
            float v = m[cy * n + cx];
            if (erase && (cx == 0 || cx == k) && (cy == 0 || cy == k))
                continue;
            ss += v * v;
            if (actag_tag_cell_value(code, fam->bits, cx, cy)) {
                sw += v;
                nw++;
            } else {
                sb += v;
                nb++;
            }
        }
    return ss - sw * sw / (float)nw - sb * sb / (float)nb;
}

static void check_family(const char *name, int trials)
{
    actag_family fam;
    actag_fit_params fp;
    int t;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get(name, &fam));
    actag_fit_params_default(&fp);
    for (t = 0; t < trials; t++) {
        int id = tu_range(0, fam.ncodes - 1), other = tu_range(0, fam.ncodes - 2);
        int mirror = t & 1, noise = (t & 2) ? 12 : 0, side, i, s;
        actag_point q[4], alt[4];
        float r1, r2, ref;
        if (other >= id)
            other++;
        side = make_tag(&fam, id, mirror, noise);
        tag_corners(fam.bits, side, mirror, q);
        /* another ID on the same corners: the right reading wins both ways round */
        TEST_ASSERT_EQUAL_INT(0, actag__fit_rival_explains(g_img, side, side, side, &fam, &fp, id,
                                                           q, other, q, &r1, &r2));
        TEST_ASSERT_TRUE(r1 < r2);
        ref = brute_rss(&fam, fam.codes[id], side, mirror, &fp);
        TEST_ASSERT_TRUE(r1 <= ref * 1.0001f + 1e-3f);
        TEST_ASSERT_EQUAL_INT(1, actag__fit_rival_explains(g_img, side, side, side, &fam, &fp,
                                                           other, q, id, q, &r1, &r2));
        TEST_ASSERT_TRUE(r2 < r1);
        /* itself: a tie is the rival's */
        TEST_ASSERT_EQUAL_INT(1, actag__fit_rival_explains(g_img, side, side, side, &fam, &fp, id,
                                                           q, id, q, &r1, &r2));
        TEST_ASSERT_EQUAL_FLOAT(r1, r2);
        /* the other handedness (TR TL BL BR) and the three other corner orders */
        alt[0] = q[1];
        alt[1] = q[0];
        alt[2] = q[3];
        alt[3] = q[2];
        TEST_ASSERT_EQUAL_INT(0, actag__fit_rival_explains(g_img, side, side, side, &fam, &fp, id,
                                                           q, id, alt, &r1, &r2));
        for (s = 1; s < 4; s++) {
            for (i = 0; i < 4; i++)
                alt[i] = q[(i + s) & 3];
            TEST_ASSERT_EQUAL_INT(0, actag__fit_rival_explains(g_img, side, side, side, &fam,
                                                               &fp, id, q, id, alt, &r1, &r2));
        }
    }
}

static void test_right_reading_beats_rivals_24h10(void)
{
    tu_seed(11);
    check_family("AcTag24h10", 24);
}

static void test_right_reading_beats_rivals_other_sizes(void)
{
    tu_seed(12);
    check_family("AcTag28m10", 8);
    check_family("AcTag24h4", 8);
}

/* The template layouts the check builds (decode_fit.c's layout_of, written
 * side by side) against actag_tag_cell_value cell by cell: every code of
 * every built-in family in all 8 views. */
static void test_layouts_match_cell_values(void)
{
    static const char *const names[] = {"AcTag24h4", "AcTag24h10", "AcTag24m4", "AcTag28m4",
                                        "AcTag28m10"};
    size_t f;
    for (f = 0; f < sizeof names / sizeof names[0]; f++) {
        actag_family fam;
        int id, view, bits, k, cx, cy, i;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get(names[f], &fam));
        bits = fam.bits;
        k = bits / 4;
        for (id = 0; id < fam.ncodes; id++)
            for (view = 0; view < 8; view++) {
                uint8_t L[81];
                uint32_t e = fam.codes[id];
                memset(L, 0xaa, sizeof L);
                TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag__fit_layout(&fam, id, view, L));
                for (i = 0; i < (view & 3); i++)
                    e = actag_code_rot90(e, bits);
                if (view >> 2)
                    e = actag_code_mirror(e, bits);
                for (cy = 0; cy <= k; cy++)
                    for (cx = 0; cx <= k; cx++)
                        if (L[cy * (k + 1) + cx] != actag_tag_cell_value(e, bits, cx, cy)) {
                            TEST_FAIL_MESSAGE(names[f]);
                        }
            }
    }
}

/* actag__fit_rss_llr under the template check's noise model: the variance
 * is rss / (cells - 2), but at least (0.1 contrast)^2. Without the floor a
 * nearly perfect reading 1 made any lead an unbounded ratio (review,
 * seventeenth session: rss 10 vs 20 over 45 cells at contrast 100 gave 21.5
 * nats where the template check's formula gives 0.05). Brute force: the
 * formula written out here. */
static void test_rss_llr_uses_the_template_floor(void)
{
    actag_family fam;
    actag_fit_params fp;
    static const float rss[4] = {10.0f, 430.0f, 4300.0f, 0.0f};
    static const float contrast[3] = {100.0f, 20.0f, 0.0f};
    int i, j, nc;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
    actag_fit_params_default(&fp);
    nc = 7 * 7 - ((fp.flags & ACTAG_FIT_ERASE_CORNERS) ? 4 : 0);
    for (i = 0; i < 4; i++)
        for (j = 0; j < 3; j++) {
            float s2 = rss[i] / (float)(nc - 2), floor2 = 0.1f * contrast[j];
            float want, got = actag__fit_rss_llr(&fam, &fp, rss[i], rss[i] + 10.0f, contrast[j]);
            floor2 *= floor2;
            if (floor2 < 1e-6f)
                floor2 = 1e-6f;
            if (s2 < floor2)
                s2 = floor2;
            want = 0.5f * 10.0f / s2;
            TEST_ASSERT_FLOAT_WITHIN(1e-4f * want, want, got);
        }
    /* the reviewer's case */
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.05f, actag__fit_rss_llr(&fam, &fp, 10.0f, 20.0f, 100.0f));
}

/* The level-noise scores (decode_fit_test.h, actag__fit_level_devs;
 * ACTAG_FIT_LEVEL_NOISE and ACTAG_FIT_SEPARATE_NOISE) against the formulas
 * written out in double: the black and the white cells each about their
 * own mean; level: their sums of squares over the given variances plus
 * their counts times the variances' logs; separate: their counts times the
 * logs of their own variances, each at least the floor. Random cells,
 * layouts and variances at every grid size, with and without the erased
 * corners; then the edges: one class empty, a class of equal cells (the
 * floor), bright cells of small spread (a one-pass variance would lose
 * it), and the errors. */
static void level_devs_ref(const float *m, const uint8_t *L, int k, int erase, double floor2,
                           const float var[2], double *level, double *separate)
{
    int n = k + 1, cx, cy, w, cnt[2] = {0, 0};
    double sum[2] = {0.0, 0.0}, ss[2] = {0.0, 0.0};
    for (cy = 0; cy < n; cy++)
        for (cx = 0; cx < n; cx++) {
            if (erase && (cy == 0 || cy == k) && (cx == 0 || cx == k))
                continue;
            w = L[cy * n + cx] != 0;
            sum[w] += m[cy * n + cx];
            cnt[w]++;
        }
    for (cy = 0; cy < n; cy++)
        for (cx = 0; cx < n; cx++) {
            double d;
            if (erase && (cy == 0 || cy == k) && (cx == 0 || cx == k))
                continue;
            w = L[cy * n + cx] != 0;
            d = m[cy * n + cx] - sum[w] / cnt[w];
            ss[w] += d * d;
        }
    *level = *separate = 0.0;
    for (w = 0; w < 2; w++) {
        *level += ss[w] / var[w] + cnt[w] * log((double)var[w]);
        if (cnt[w]) {
            double v = ss[w] / cnt[w];
            *separate += cnt[w] * log(v < floor2 ? floor2 : v);
        }
    }
}

static void expect_level_devs(const float *m, const uint8_t *L, int k, int erase, float floor2,
                              const float var[2])
{
    float level = 0.0f, separate = 0.0f;
    double want_l, want_s;
    level_devs_ref(m, L, k, erase, floor2, var, &want_l, &want_s);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK,
                          actag__fit_level_devs(m, L, k, erase, floor2, var, &level, &separate));
    TEST_ASSERT_FLOAT_WITHIN((float)(1e-5 * fabs(want_l) + 1e-3), (float)want_l, level);
    TEST_ASSERT_FLOAT_WITHIN((float)(1e-5 * fabs(want_s) + 1e-3), (float)want_s, separate);
}

static void test_level_noise_scores_match_the_formulas(void)
{
    float m[81], var[2], level, separate;
    uint8_t L[81];
    int trial, k, i, erase;
    tu_seed(391);
    for (trial = 0; trial < 400; trial++) {
        float lo = (float)tu_range(0, 120), spread = (float)tu_range(0, 60);
        float floor2 = (float)tu_uniform(0.01, 100.0);
        k = tu_range(4, 8);
        erase = trial & 1;
        var[0] = (float)tu_uniform(0.5, 400.0);
        var[1] = (float)tu_uniform(0.5, 400.0);
        for (i = 0; i < (k + 1) * (k + 1); i++) {
            L[i] = (uint8_t)(tu_rand() & 1u);
            m[i] = lo + (L[i] ? (float)tu_range(20, 120) : 0.0f) +
                   (float)tu_uniform(-1.0, 1.0) * spread;
        }
        expect_level_devs(m, L, k, erase, floor2, var);
    }
    var[0] = 4.0f;
    var[1] = 9.0f;
    /* one class empty: only the other counts */
    for (i = 0; i < 81; i++) {
        L[i] = 1;
        m[i] = (float)(i % 7) * 10.0f;
    }
    expect_level_devs(m, L, 8, 0, 1.0f, var);
    memset(L, 0, sizeof L);
    expect_level_devs(m, L, 8, 1, 1.0f, var);
    /* equal cells: no squares, and the separate variances at the floor */
    for (i = 0; i < 49; i++) {
        L[i] = (uint8_t)(i & 1);
        m[i] = L[i] ? 200.0f : 30.0f;
    }
    TEST_ASSERT_EQUAL_INT(ACTAG_OK,
                          actag__fit_level_devs(m, L, 6, 0, 4.0f, var, &level, &separate));
    TEST_ASSERT_FLOAT_WITHIN(1e-3f, (float)(25.0 * log(4.0) + 24.0 * log(9.0)), level);
    TEST_ASSERT_FLOAT_WITHIN(1e-3f, (float)(49.0 * log(4.0)), separate);
    /* bright cells of small spread: 250 +- 0.5 */
    for (i = 0; i < 49; i++) {
        L[i] = (uint8_t)(i % 3 != 0);
        m[i] = L[i] ? 250.0f + (float)(i % 2) - 0.5f : 20.0f + (float)(i % 5);
    }
    var[1] = 0.25f;
    expect_level_devs(m, L, 6, 1, 0.01f, var);
    /* errors */
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL,
                          actag__fit_level_devs(NULL, L, 6, 0, 1.0f, var, &level, &separate));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL,
                          actag__fit_level_devs(m, NULL, 6, 0, 1.0f, var, &level, &separate));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL,
                          actag__fit_level_devs(m, L, 6, 0, 1.0f, NULL, &level, &separate));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL,
                          actag__fit_level_devs(m, L, 6, 0, 1.0f, var, NULL, &separate));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL,
                          actag__fit_level_devs(m, L, 6, 0, 1.0f, var, &level, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM,
                          actag__fit_level_devs(m, L, 3, 0, 1.0f, var, &level, &separate));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM,
                          actag__fit_level_devs(m, L, 9, 0, 1.0f, var, &level, &separate));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM,
                          actag__fit_level_devs(m, L, 6, 0, 0.0f, var, &level, &separate));
    var[0] = 0.0f;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM,
                          actag__fit_level_devs(m, L, 6, 0, 1.0f, var, &level, &separate));
}

static void test_errors(void)
{
    actag_family fam;
    actag_fit_params fp, bad;
    actag_point q[4];
    float r1, r2;
    int side;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
    actag_fit_params_default(&fp);
    side = make_tag(&fam, 0, 0, 0);
    tag_corners(fam.bits, side, 0, q);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag__fit_rival_explains(NULL, side, side, side, &fam,
                                                                    &fp, 0, q, 1, q, &r1, &r2));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag__fit_rival_explains(g_img, side, side, side, &fam,
                                                                    &fp, 0, q, 1, NULL, &r1, &r2));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag__fit_rival_explains(g_img, side, side, side, &fam,
                                                                    &fp, 0, q, 1, q, &r1, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag__fit_rival_explains(g_img, side, side, side, &fam,
                                                                     &fp, -1, q, 1, q, &r1, &r2));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM,
                          actag__fit_rival_explains(g_img, side, side, side, &fam, &fp, 0, q,
                                                    fam.ncodes, q, &r1, &r2));
    bad = fp;
    bad.sample_offset = 0.9f;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag__fit_rival_explains(g_img, side, side, side, &fam,
                                                                     &bad, 0, q, 1, q, &r1, &r2));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag__fit_rival_explains(g_img, 0, side, side, &fam,
                                                                     &fp, 0, q, 1, q, &r1, &r2));
    {
        uint8_t L[81];
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag__fit_layout(NULL, 0, 0, L));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag__fit_layout(&fam, 0, 0, NULL));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag__fit_layout(&fam, fam.ncodes, 0, L));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag__fit_layout(&fam, 0, 8, L));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag__fit_layout(&fam, -1, 0, L));
    }
    /* a degenerate quad (all corners at one point) has no grid */
    {
        actag_point z[4];
        memset(z, 0, sizeof z);
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM,
                              actag__fit_rival_explains(g_img, side, side, side, &fam, &fp, 0, z,
                                                        1, q, &r1, &r2));
    }
}

/* A random coordinate in [-50, 50) pixels, from one draw. */
static float coord(actag_rng *g)
{
    uint32_t u = actag_rng_next(g);
    return (float)((double)(u >> 8) / 16777216.0 * 100.0 - 50.0);
}

/* The completion of corner j of q in double: *moved2 the squared move,
 * *side2 the mean squared side. */
static void complete_ref(const actag_point q[4], int j, double t[2], double *moved2,
                         double *side2)
{
    int i;
    double s = 0.0;
    for (i = 0; i < 4; i++) {
        double dx = (double)q[(i + 1) & 3].x - (double)q[i].x;
        double dy = (double)q[(i + 1) & 3].y - (double)q[i].y;
        s += 0.25 * (dx * dx + dy * dy);
    }
    t[0] = (double)q[(j + 3) & 3].x + (double)q[(j + 1) & 3].x - (double)q[(j + 2) & 3].x;
    t[1] = (double)q[(j + 3) & 3].y + (double)q[(j + 1) & 3].y - (double)q[(j + 2) & 3].y;
    *moved2 = (t[0] - q[j].x) * (t[0] - q[j].x) + (t[1] - q[j].y) * (t[1] - q[j].y);
    *side2 = s;
}

static void test_corner_completions_match_the_arithmetic(void)
{
    actag_rng g;
    int n, j, c, decided = 0, completed = 0;
    actag_rng_seed(&g, 2026120736u);
    for (n = 0; n < 2000; n++) {
        actag_point q[4], t[4];
        for (c = 0; c < 4; c++) {
            q[c].x = coord(&g);
            q[c].y = coord(&g);
        }
        for (j = 0; j < 4; j++) {
            double ref[2], moved2, side2;
            int got = actag__complete_corner(q, j, t);
            complete_ref(q, j, ref, &moved2, &side2);
            for (c = 0; c < 4; c++)
                if (c != j) {
                    TEST_ASSERT_EQUAL_FLOAT(q[c].x, t[c].x);
                    TEST_ASSERT_EQUAL_FLOAT(q[c].y, t[c].y);
                }
            TEST_ASSERT_FLOAT_WITHIN(1e-3f, (float)ref[0], t[j].x);
            TEST_ASSERT_FLOAT_WITHIN(1e-3f, (float)ref[1], t[j].y);
            /* the rule, away from its float boundary */
            if (moved2 > 0.0626 * side2 || moved2 < 0.0624 * side2) {
                TEST_ASSERT_EQUAL_INT(moved2 >= 0.0625 * side2, got);
                decided++;
                completed += got;
            }
        }
    }
    /* both outcomes met (random quads are mostly far from parallelograms) */
    TEST_ASSERT_TRUE(decided > 7000);
    TEST_ASSERT_TRUE(completed > 0 && completed < decided);
}

static void test_corner_completions_leave_boxes_and_points(void)
{
    /* a turned rectangle, a sheared parallelogram and a point: no completion */
    static const actag_point box[4] = {{10.0f, 0.0f}, {40.0f, 20.0f}, {30.0f, 35.0f},
                                       {0.0f, 15.0f}};
    static const actag_point para[4] = {{0.0f, 0.0f}, {30.0f, 0.0f}, {42.0f, 20.0f},
                                        {12.0f, 20.0f}};
    static const actag_point point[4] = {{5.0f, 5.0f}, {5.0f, 5.0f}, {5.0f, 5.0f},
                                         {5.0f, 5.0f}};
    /* a square of side 40 with corner 2 pulled in by 12 px along x (a
     * quarter of the mean side is about 9.5 px): completed; by 8 px: not */
    static const actag_point kite12[4] = {{0.0f, 0.0f}, {40.0f, 0.0f}, {28.0f, 40.0f},
                                          {0.0f, 40.0f}};
    static const actag_point kite8[4] = {{0.0f, 0.0f}, {40.0f, 0.0f}, {32.0f, 40.0f},
                                         {0.0f, 40.0f}};
    actag_point t[4];
    int j;
    for (j = 0; j < 4; j++) {
        TEST_ASSERT_EQUAL_INT(0, actag__complete_corner(box, j, t));
        TEST_ASSERT_EQUAL_INT(0, actag__complete_corner(para, j, t));
        TEST_ASSERT_EQUAL_INT(0, actag__complete_corner(point, j, t));
    }
    TEST_ASSERT_EQUAL_INT(1, actag__complete_corner(kite12, 2, t));
    TEST_ASSERT_EQUAL_FLOAT(40.0f, t[2].x); /* the square's corner back */
    TEST_ASSERT_EQUAL_FLOAT(40.0f, t[2].y);
    TEST_ASSERT_EQUAL_INT(0, actag__complete_corner(kite8, 2, t));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_right_reading_beats_rivals_24h10);
    RUN_TEST(test_right_reading_beats_rivals_other_sizes);
    RUN_TEST(test_layouts_match_cell_values);
    RUN_TEST(test_rss_llr_uses_the_template_floor);
    RUN_TEST(test_level_noise_scores_match_the_formulas);
    RUN_TEST(test_errors);
    RUN_TEST(test_corner_completions_match_the_arithmetic);
    RUN_TEST(test_corner_completions_leave_boxes_and_points);
    return UNITY_END();
}
