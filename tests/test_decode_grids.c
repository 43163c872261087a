/* A wide reading resumed from kept grids (src/decode_fit_grids.h): detect.c
 * reads a search candidate first without the template check and, when the
 * reading is reported, again with it from the grids the first reading found.
 * The brute-force reference is a fresh reading with the check
 * (actag_decode_quad_fit): the resumed one must return the same code and
 * the same result, byte for byte, on rendered tags (any ID, turned,
 * mirrored, speckled, quads off by up to 0.4 cell) and on clutter. */
#include "../src/decode_fit_grids.h"
#include "../src/decode_fit_test.h"
#include "actag/render.h"
#include "actag/tag_grid.h"

#include "unity.h"
#include "test_util.h"

#include <string.h>

void setUp(void) {}
void tearDown(void) {}

#define CELL 9
#define MARGIN 14
#define SIDE_MAX 160

static uint8_t g_img[SIDE_MAX * SIDE_MAX];

/* Tag `id` rendered, turned `turns` quarter turns, mirrored if asked, with
 * speckle; returns the side. */
static int make_tag(const actag_family *fam, int id, int turns, int mirror, int noise)
{
    static uint8_t t[SIDE_MAX * SIDE_MAX];
    int side = actag_render_side(fam->bits, CELL, MARGIN), r, c, q;
    TEST_ASSERT_TRUE(side > 0 && side <= SIDE_MAX);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_render_tag(fam, id, CELL, MARGIN, 40, 0, t, side,
                                                     sizeof t));
    for (r = 0; r < side; r++)
        for (c = 0; c < side; c++) {
            int rr = r, cc = mirror ? side - 1 - c : c, v;
            for (q = 0; q < turns; q++) { /* (rr, cc) -> (cc, side - 1 - rr) */
                int tmp = rr;
                rr = cc;
                cc = side - 1 - tmp;
            }
            v = (int)t[rr * side + cc] * 3 / 4 + 20 + tu_range(-noise, noise);
            g_img[r * side + c] = (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : v);
        }
    return side;
}

/* The white square's corners, each moved by up to `jitter` cells. */
static void make_quad(int bits, float jitter, actag_point q[4])
{
    int k = bits / 4, i;
    float lo = (float)(MARGIN + 2 * CELL) - 0.5f, hi = (float)(MARGIN + (k - 1) * CELL) - 0.5f;
    static const int sx[4] = {0, 1, 1, 0}, sy[4] = {0, 0, 1, 1};
    for (i = 0; i < 4; i++) {
        q[i].x = (sx[i] ? hi : lo) + jitter * (float)CELL * (float)tu_range(-1000, 1000) / 1000.0f;
        q[i].y = (sy[i] ? hi : lo) + jitter * (float)CELL * (float)tu_range(-1000, 1000) / 1000.0f;
    }
}

/* The reference against the resumed reading on one frame and quad. */
static int compare(const actag_family *fam, int side, const actag_point q[4], int corrections)
{
    actag_fit_params fp, tent;
    actag_decode_result ref, first, resumed;
    actag__fit_grids grids;
    int rc_ref, rc_first, rc;
    actag_fit_params_default(&fp);
    fp.flags |= ACTAG_FIT_WIDE;
    tent = fp;
    tent.flags &= ~ACTAG_FIT_VERIFY;
    memset(&ref, 0, sizeof ref);
    memset(&resumed, 0, sizeof resumed);
    rc_ref = actag_decode_quad_fit(g_img, side, side, side, q, fam, corrections, &fp, &ref);
    memset(&grids, 0, sizeof grids); /* state 0: not searched yet */
    rc_first = actag__decode_quad_fit_grids(g_img, side, side, side, q, fam, corrections, &tent,
                                            &first, &grids, NULL);
    TEST_ASSERT_TRUE(rc_first == ACTAG_OK || rc_first == ACTAG_ERR_NO_MATCH);
    TEST_ASSERT_TRUE(grids.state == 1 || grids.state == 2);
    rc = actag__decode_quad_fit_grids(g_img, side, side, side, q, fam, corrections, &fp,
                                      &resumed, &grids, NULL);
    TEST_ASSERT_EQUAL_INT(rc_ref, rc);
    if (rc == ACTAG_OK)
        TEST_ASSERT_EQUAL_MEMORY(&ref, &resumed, sizeof ref);
    return rc == ACTAG_OK;
}

static void test_resumed_reading_equals_a_fresh_one_on_tags(void)
{
    actag_family fam;
    int n, read = 0, trials = 0;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
    tu_seed(7);
    for (n = 0; n < 48; n++) {
        actag_point q[4];
        int side = make_tag(&fam, n % fam.ncodes, n % 4, (n / 4) % 2, 10 + n % 30);
        make_quad(fam.bits, 0.4f * (float)(n % 5) / 4.0f, q);
        read += compare(&fam, side, q, 3);
        trials++;
    }
    /* the comparison is about equal results, but most of these must read
     * (a suite where nothing reads would compare errors only) */
    TEST_ASSERT_TRUE_MESSAGE(read * 2 > trials, "most rendered tags read");
}

static void test_resumed_reading_equals_a_fresh_one_on_clutter(void)
{
    actag_family fam;
    int n, i, side = SIDE_MAX;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
    tu_seed(11);
    for (n = 0; n < 24; n++) {
        actag_point q[4];
        /* blocks of random grey the size of cells, and speckle */
        for (i = 0; i < side * side; i++) {
            int r = i / side, c = i % side;
            uint32_t h = (uint32_t)((r / CELL) * 131 + (c / CELL) * 71 + n * 977) * 2654435761u;
            g_img[i] = (uint8_t)(((h >> 24) & 0xc0u) + (uint32_t)tu_range(0, 63));
        }
        make_quad(fam.bits, 0.5f, q);
        compare(&fam, side, q, 3);
    }
}

/* A second reading with other corrections starts from the same grids too
 * (detect.c reads with the wide-search limit both times, but the grids do
 * not depend on it). */
static void test_resumed_reading_with_other_corrections(void)
{
    actag_family fam;
    int n;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h8", &fam));
    tu_seed(13);
    for (n = 0; n < 16; n++) {
        actag_point q[4];
        int side = make_tag(&fam, (n * 7) % fam.ncodes, n % 4, n % 2, 25);
        make_quad(fam.bits, 0.3f, q);
        compare(&fam, side, q, n % 4);
    }
}

/* A blind box's own grid after a hopeless start (grids->state 2: the quad's
 * own grid is the only one read): read with the chance bound's corrections
 * (AcTag24h10: 1), a fitted quad's with all of them. */
static void test_blind_box_after_a_hopeless_start(void)
{
    actag_family h10;
    actag_fit_params fp;
    actag_decode_result res;
    actag__fit_grids g;
    actag_point q[4];
    int side, i, flipped = 0;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &h10));
    actag_fit_params_default(&fp);
    fp.flags = (fp.flags | ACTAG_FIT_WIDE) & ~ACTAG_FIT_VERIFY;
    tu_seed(3);
    make_quad(24, 0.0f, q);
    /* AcTag24h10 with two data cells painted over: hamming 2, refused only
     * as a blind box's (at most 1 corrected bit); clean, read either way */
    side = make_tag(&h10, 3, 0, 0, 0);
    memset(&g, 0, sizeof g);
    g.state = 2;
    g.blind = 1;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag__decode_quad_fit_grids(g_img, side, side, side, q, &h10,
                                                                 3, &fp, &res, &g, NULL));
    TEST_ASSERT_EQUAL_INT(3, res.id);
    TEST_ASSERT_EQUAL_INT(0, res.hamming);
    for (i = 0; i < 24 && flipped < 2; i++) {
        int cx, cy, r, c, y0, x0, bright;
        actag_tag_bit_cell(24, i, &cx, &cy);
        if ((cx == 0 || cx == 6) && (cy == 0 || cy == 6))
            continue; /* an erased corner */
        y0 = MARGIN + cy * CELL;
        x0 = MARGIN + cx * CELL;
        bright = g_img[(y0 + CELL / 2) * side + x0 + CELL / 2] > 100;
        for (r = 0; r < CELL; r++)
            for (c = 0; c < CELL; c++)
                g_img[(y0 + r) * side + x0 + c] = (uint8_t)(bright ? 20 : 211);
        flipped++;
    }
    memset(&g, 0, sizeof g);
    g.state = 2;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag__decode_quad_fit_grids(g_img, side, side, side, q, &h10,
                                                                 3, &fp, &res, &g, NULL));
    TEST_ASSERT_EQUAL_INT(3, res.id);
    TEST_ASSERT_EQUAL_INT(2, res.hamming);
    g.blind = 1;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, actag__decode_quad_fit_grids(
                                                  g_img, side, side, side, q, &h10, 3, &fp, &res,
                                                  &g, NULL));
}

/* A blind box's corrections against a brute force: the ball volumes
 * V(nbits, t) counted word by word (every word of nbits bits whose
 * popcount is at most t), for small and the decoder's bit counts, every
 * family size of the built-in families and edge sizes; and the values the
 * docs give. */
static void test_blind_corrections_against_counted_balls(void)
{
    static const int sizes[] = {1, 6, 7, 9, 45, 48, 51, 453, 515, 661, 6261, 8910, 32768};
    static const int nb[] = {1, 2, 8, 12, 20}; /* 20: the bits read of 24-bit tags */
    size_t a, b;
    for (a = 0; a < sizeof nb / sizeof nb[0]; a++) {
        int n = nb[a], t;
        uint64_t vol[21] = {0}, w;
        for (w = 0; w < ((uint64_t)1u << n); w++) /* the ball volumes, counted */
            for (t = actag_popcount32((uint32_t)w); t <= n; t++)
                vol[t]++;
        for (b = 0; b < sizeof sizes / sizeof sizes[0]; b++) {
            int views, maxc;
            for (views = 4; views <= 8; views += 4)
                for (maxc = 0; maxc <= (n < 4 ? n : 4); maxc++) {
                    int want = -1;
                    for (t = 0; t <= maxc; t++)
                        if ((uint64_t)views * (uint64_t)sizes[b] * 100u * vol[t] <=
                            ((uint64_t)1u << n))
                            want = t;
                        else
                            break;
                    TEST_ASSERT_EQUAL_INT(want,
                                          actag__fit_blind_corrections(n, sizes[b], views, maxc));
                }
        }
    }
    /* decode.h and decode_fit_grids.h: 20 read bits, all 8 views, 3 corrections */
    TEST_ASSERT_EQUAL_INT(1, actag__fit_blind_corrections(20, 7, 8, 3));    /* AcTag24h10 */
    TEST_ASSERT_EQUAL_INT(2, actag__fit_blind_corrections(20, 1, 8, 3));    /* AcTag24m10 */
    TEST_ASSERT_EQUAL_INT(1, actag__fit_blind_corrections(20, 45, 8, 3));   /* AcTag24h8 */
    TEST_ASSERT_EQUAL_INT(0, actag__fit_blind_corrections(20, 453, 8, 3));  /* AcTag24h6 */
    TEST_ASSERT_EQUAL_INT(-1, actag__fit_blind_corrections(20, 6261, 8, 1)); /* AcTag24h4 */
    TEST_ASSERT_EQUAL_INT(1, actag__fit_blind_corrections(32, 32768, 8, 3));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag__fit_blind_corrections(0, 7, 8, 0));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag__fit_blind_corrections(20, 0, 8, 0));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag__fit_blind_corrections(20, 7, 6, 0));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag__fit_blind_corrections(20, 7, 8, -1));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag__fit_blind_corrections(20, 7, 8, 21));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_resumed_reading_equals_a_fresh_one_on_tags);
    RUN_TEST(test_resumed_reading_equals_a_fresh_one_on_clutter);
    RUN_TEST(test_resumed_reading_with_other_corrections);
    RUN_TEST(test_blind_corrections_against_counted_balls);
    RUN_TEST(test_blind_box_after_a_hopeless_start);
    return UNITY_END();
}
