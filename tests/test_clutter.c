/* Clutter that has fooled AcTag detectors, generated: random small
 * rectangles (6-14 px), combs of tag-cell-sized teeth, grids of tag-sized
 * white squares at several gaps (neighbours fall where data bits are read)
 * and sizes, and pure speckle. Every built-in family at its default
 * corrections, all four frame orientations, several RANSAC seeds: zero
 * detections (issue: detections you can trust). A generator check makes
 * sure the shapes are really drawn (a test of an empty frame cannot fail). */
#include "unity.h"

#include "actag/actag.h"

#include <stdio.h>
#include <string.h>

void setUp(void) {}
void tearDown(void) {}

#define CR 530
#define CC 512
#define MAXFAM 16

static uint8_t g_ws[ACTAG_WORKSPACE_SIZE(CR, CC)];
static uint8_t g_frame[CR * CC], g_flip[CR * CC];

/* Pool geometry (0.1-1.5 m, 60 degrees): a tag's white square of 0.1306 m
 * is ~49 rows by ~71 columns at 0.9 m range (row ~227). */
#define TAG_ROWS 49
#define TAG_COLS 71

static float urand(actag_rng *r) { return (float)actag_rng_below(r, 1u << 20) / 1048576.0f; }

/* Speckled background: a dim seabed. */
static void background(actag_rng *r)
{
    int i;
    for (i = 0; i < CR * CC; i++)
        g_frame[i] = (uint8_t)(10.0f + 40.0f * urand(r));
}

/* A bright speckled rectangle (centre cx, cy; half sides hw, hh; turned by
 * the unit vector (c, s)). */
static void rect(actag_rng *r, float cx, float cy, float hw, float hh, float c, float s)
{
    int x, y;
    float ext = hw + hh + 1.0f;
    for (y = (int)(cy - ext); y <= (int)(cy + ext); y++)
        for (x = (int)(cx - ext); x <= (int)(cx + ext); x++) {
            float dx, dy, u, v;
            if (x < 0 || y < 0 || x >= CC || y >= CR)
                continue;
            dx = (float)x - cx;
            dy = (float)y - cy;
            u = c * dx + s * dy;
            v = -s * dx + c * dy;
            if (u >= -hw && u <= hw && v >= -hh && v <= hh)
                g_frame[y * CC + x] = (uint8_t)(120.0f + 120.0f * urand(r));
        }
}

static long bright_pixels(void)
{
    long n = 0;
    int i;
    for (i = 0; i < CR * CC; i++)
        n += g_frame[i] >= 120;
    return n;
}

/* Runs every built-in family at its defaults on g_frame in the four
 * orientations (the frame flipped together with the geometry's flags);
 * fails on any detection. */
static void expect_nothing(const char *what, uint32_t seed)
{
    actag_family fams[MAXFAM];
    actag_params p[MAXFAM];
    actag_detection det[MAXFAM * 4];
    int counts[MAXFAM], nf = actag_family_count(), i, o, y, x;
    char msg[160];
    TEST_ASSERT_TRUE(nf > 0 && nf <= MAXFAM);
    for (i = 0; i < nf; i++) {
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get_at(i, &fams[i]));
        actag_params_default(&p[i]);
        p[i].family = &fams[i];
        p[i].seed = seed;
    }
    for (o = 0; o < 4; o++) {
        actag_sonar_geometry g = {0.1f, 1.5f, 1.0472f, NULL, 0u};
        actag_frame f;
        int rf = o & 1, cf = (o >> 1) & 1;
        if (rf)
            g.flags |= ACTAG_RANGE_ASCENDING;
        if (cf)
            g.flags |= ACTAG_AZIMUTH_ASCENDING;
        for (y = 0; y < CR; y++)
            for (x = 0; x < CC; x++)
                g_flip[(rf ? CR - 1 - y : y) * CC + (cf ? CC - 1 - x : x)] = g_frame[y * CC + x];
        f.data = g_flip;
        f.rows = CR;
        f.cols = CC;
        f.stride = CC;
        f.depth = 8;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_detect_multi(&f, &g, p, nf, g_ws, sizeof g_ws,
                                                           det, 4, counts));
        for (i = 0; i < nf; i++) {
            snprintf(msg, sizeof msg, "%s, seed %u, orientation %d: %s read ID %d", what,
                     (unsigned)seed, o, fams[i].name, counts[i] > 0 ? det[i * 4].id : -1);
            TEST_ASSERT_EQUAL_INT_MESSAGE(0, counts[i], msg);
        }
    }
}

static void test_random_small_rectangles(void)
{
    uint32_t seed;
    for (seed = 1; seed <= 4; seed++) {
        actag_rng r;
        int i;
        actag_rng_seed(&r, 1000u + seed);
        background(&r);
        for (i = 0; i < 400; i++) {
            float cx = 20.0f + urand(&r) * (float)(CC - 40);
            float cy = 20.0f + urand(&r) * (float)(CR - 40);
            float hw = 3.0f + 4.0f * urand(&r), hh = 3.0f + 4.0f * urand(&r);
            float a = urand(&r) * 2.0f - 1.0f; /* a turn of up to ~+-57 degrees */
            float c = 1.0f - 0.5f * a * a, s = a;
            float nrm = c * c + s * s;
            /* normalise (c, s) without libm: one Newton step from 1 */
            float inv = 1.5f - 0.5f * nrm;
            rect(&r, cx, cy, hw, hh, c * inv, s * inv);
        }
        TEST_ASSERT_TRUE_MESSAGE(bright_pixels() > 20000, "rectangles not drawn");
        expect_nothing("400 rectangles of 6-14 px", seed);
    }
}

/* Combs: a spine of a tag's width with teeth one tag cell wide, one cell
 * apart (the AcTag24 cell: a third of the white square). */
static void test_combs(void)
{
    static const float scale[3] = {0.8f, 1.0f, 1.25f};
    int si;
    for (si = 0; si < 3; si++) {
        actag_rng r;
        float cw = (float)TAG_COLS / 3.0f * scale[si], ch = (float)TAG_ROWS / 3.0f * scale[si];
        int t, j;
        actag_rng_seed(&r, 2000u + (uint32_t)si);
        background(&r);
        for (j = 0; j < 3; j++) {
            float x0 = 40.0f + (float)j * 160.0f, y0 = 120.0f + (float)j * 110.0f;
            /* spine: 7 cells long, one cell high */
            rect(&r, x0 + 3.5f * cw, y0 + 0.5f * ch, 3.5f * cw, 0.5f * ch, 1.0f, 0.0f);
            for (t = 0; t < 4; t++) /* teeth below the spine */
                rect(&r, x0 + (2.0f * (float)t + 0.5f) * cw, y0 + 2.0f * ch, 0.5f * cw, 1.0f * ch,
                     1.0f, 0.0f);
        }
        TEST_ASSERT_TRUE_MESSAGE(bright_pixels() > 5000, "combs not drawn");
        expect_nothing("combs", (uint32_t)si + 1u);
    }
}

/* Grids of tag-sized white squares, gaps 0.2-0.5 square, sizes 0.8-1.2. */
static void test_grids_of_tag_sized_squares(void)
{
    static const float gaps[4] = {0.2f, 0.3f, 0.4f, 0.5f};
    static const float sizes[3] = {0.8f, 1.0f, 1.2f};
    int gi, si;
    for (gi = 0; gi < 4; gi++)
        for (si = 0; si < 3; si++) {
            actag_rng r;
            float w = (float)TAG_COLS * sizes[si], h = (float)TAG_ROWS * sizes[si];
            float px = w * (1.0f + gaps[gi]), py = h * (1.0f + gaps[gi]);
            int i, j;
            char what[64];
            actag_rng_seed(&r, 3000u + (uint32_t)(gi * 3 + si));
            background(&r);
            for (j = 0; j * py + h < (float)CR - 30.0f; j++)
                for (i = 0; i * px + w < (float)CC - 10.0f; i++)
                    rect(&r, 10.0f + (float)i * px + 0.5f * w, 30.0f + (float)j * py + 0.5f * h,
                         0.5f * w, 0.5f * h, 1.0f, 0.0f);
            TEST_ASSERT_TRUE_MESSAGE(bright_pixels() > 40000, "grid not drawn");
            snprintf(what, sizeof what, "grid, gap %.1f, size %.1f", (double)gaps[gi],
                     (double)sizes[si]);
            expect_nothing(what, (uint32_t)(gi * 3 + si) + 1u);
        }
}

static void test_pure_speckle(void)
{
    uint32_t seed;
    for (seed = 1; seed <= 4; seed++) {
        actag_rng r;
        int i;
        actag_rng_seed(&r, 4000u + seed);
        for (i = 0; i < CR * CC; i++) { /* bright, full-range speckle */
            float u = urand(&r); /* one draw per statement: fixed order */
            g_frame[i] = (uint8_t)(255.0f * u * urand(&r));
        }
        expect_nothing("speckle", seed);
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_random_small_rectangles);
    RUN_TEST(test_combs);
    RUN_TEST(test_grids_of_tag_sized_squares);
    RUN_TEST(test_pure_speckle);
    return UNITY_END();
}
