/* Tests for actag_refine_corners (refine.h) on synthetic tags drawn under
 * known affine maps, against the true corners and against a brute-force
 * search of the best-fitting shift of the true map. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "actag/actag.h"
#include "actag/render.h"
#include "../src/refine_frame.h"
#include "test_util.h"
#include "unity.h"

/* The portable refinement (no SSE2 paths), compiled into this test under
 * other names, so that the library's x86 paths are compared with it bit for
 * bit (test_simd_*); elsewhere both are the same code. */
void actag_refine_params_default_portable(actag_refine_params *rp);
int actag_refine_corners_portable(const uint8_t *img, int rows, int cols, int stride,
                                  const actag_sonar_geometry *geometry, float tag_size,
                                  const actag_family *family, int id,
                                  const actag_point corners[4], const actag_refine_params *rp,
                                  actag_point out[4], actag_refine_info *info);
int actag_refine_corners_depth_portable(const void *img, int depth, int rows, int cols,
                                        int stride, const actag_sonar_geometry *geometry,
                                        float tag_size, const actag_family *family, int id,
                                        const actag_point corners[4],
                                        const actag_refine_params *rp, actag_point out[4],
                                        actag_refine_info *info);
int actag__refine_corners_max16_portable(const void *img, int depth, uint32_t max16, int rows,
                                         int cols, int stride,
                                         const actag_sonar_geometry *geometry, float tag_size,
                                         const actag_family *family, int id,
                                         const actag_point corners[4],
                                         const actag_refine_params *rp, actag_point out[4],
                                         actag_refine_info *info);
int actag__refine_shape_ok_portable(const float start[6], const float fit[6], float cell2);
/* whether the library's copy has the SSE2 sweeps (printed by main) */
#if defined(__SSE2__) && !defined(ACTAG_NO_SIMD)
#define RT_LIBRARY_SSE2 1
#else
#define RT_LIBRARY_SSE2 0
#endif
#define ACTAG_NO_SIMD 1
#define actag_refine_params_default actag_refine_params_default_portable
#define actag_refine_corners actag_refine_corners_portable
#define actag_refine_corners_depth actag_refine_corners_depth_portable
#define actag__refine_corners_max16 actag__refine_corners_max16_portable
#define actag__refine_shape_ok actag__refine_shape_ok_portable
#define actag__refine_probe actag__refine_probe_portable
#include "../src/refine.c"
#undef actag__refine_probe
#undef actag_refine_params_default
#undef actag_refine_corners
#undef actag_refine_corners_depth
#undef actag__refine_corners_max16
#undef actag__refine_shape_ok

void setUp(void) {}
void tearDown(void) {}

#define RT_ROWS 160
#define RT_COLS 200
#define RT_SS 4 /* supersampling per pixel side */

static actag_family g_fam;
static uint8_t g_img[RT_ROWS * RT_COLS];

typedef struct {
    float m[2], a[2], b[2]; /* grid offset (u - g, v - g) -> m + a du + b dv, pixels */
} amap;

static float frand(actag_rng *r) { return (float)actag_rng_next(r) / 4294967296.0f; }

/* Layout value of grid point (u, v) (cells), 0 outside the tag. */
static int layout_at(int id, float u, float v)
{
    int k = g_fam.bits / 4;
    if (u < 0.0f || v < 0.0f || u >= (float)(k + 1) || v >= (float)(k + 1))
        return 0;
    return actag_layout_cell(&g_fam, id, (int)u, (int)v);
}

/* Draws tag `id` under map M (white 40 + 160, black 40, background 30),
 * pixel values the mean over RT_SS^2 subsamples, plus uniform noise of
 * +-noise grey levels. */
static void draw(int id, const amap *M, float noise, actag_rng *r)
{
    int k = g_fam.bits / 4, x, y, sx, sy;
    float g = 0.5f * (float)(k + 1);
    float det = M->a[0] * M->b[1] - M->b[0] * M->a[1];
    for (y = 0; y < RT_ROWS; y++)
        for (x = 0; x < RT_COLS; x++) {
            float s = 0.0f, val;
            for (sy = 0; sy < RT_SS; sy++)
                for (sx = 0; sx < RT_SS; sx++) {
                    float px = (float)x - 0.5f + ((float)sx + 0.5f) / RT_SS;
                    float py = (float)y - 0.5f + ((float)sy + 0.5f) / RT_SS;
                    float dx = px - M->m[0], dy = py - M->m[1];
                    float u = g + (M->b[1] * dx - M->b[0] * dy) / det;
                    float v = g + (-M->a[1] * dx + M->a[0] * dy) / det;
                    int in = u >= 0.0f && v >= 0.0f && u < (float)(k + 1) && v < (float)(k + 1);
                    s += in ? 40.0f + 160.0f * (float)layout_at(id, u, v) : 30.0f;
                }
            val = s / (float)(RT_SS * RT_SS) + noise * (2.0f * frand(r) - 1.0f);
            g_img[y * RT_COLS + x] = (uint8_t)(val < 0.0f ? 0 : val > 255.0f ? 255 : val + 0.5f);
        }
}

/* White-square corner c (tag order) under M. */
static actag_point corner_of(const amap *M, int c)
{
    int k = g_fam.bits / 4;
    float g = 0.5f * (float)(k + 1);
    float u = (c == 0 || c == 3) ? 2.0f : (float)(k - 1);
    float v = c < 2 ? 2.0f : (float)(k - 1);
    actag_point p;
    p.x = M->m[0] + M->a[0] * (u - g) + M->b[0] * (v - g);
    p.y = M->m[1] + M->a[1] * (u - g) + M->b[1] * (v - g);
    return p;
}

/* A random map: cells of 7-11 pixels, any rotation, up to 25 % shear and
 * aspect, the tag inside the image; mirrored (b turned the other way) when
 * asked. */
static void random_map(actag_rng *r, int mirrored, amap *M)
{
    float cell = 7.0f + 4.0f * frand(r), th = 6.2831853f * frand(r);
    float asp = 0.8f + 0.4f * frand(r), sh = 0.5f * (frand(r) - 0.5f);
    float c = cosf(th), s = sinf(th);
    M->a[0] = cell * c;
    M->a[1] = cell * s;
    M->b[0] = cell * asp * (-s + sh * c);
    M->b[1] = cell * asp * (c + sh * s);
    if (mirrored) {
        M->b[0] = -M->b[0];
        M->b[1] = -M->b[1];
    }
    M->m[0] = 0.5f * RT_COLS + 6.0f * (frand(r) - 0.5f);
    M->m[1] = 0.5f * RT_ROWS + 6.0f * (frand(r) - 0.5f);
}

/* Corners perturbed by up to `cells` of a cell in x and y each. */
static void perturb(const actag_point t[4], float cell, float cells, actag_rng *r,
                    actag_point out[4])
{
    int c;
    for (c = 0; c < 4; c++) {
        out[c].x = t[c].x + cells * cell * (2.0f * frand(r) - 1.0f);
        out[c].y = t[c].y + cells * cell * (2.0f * frand(r) - 1.0f);
    }
}

/* Noise-free and noisy tags, either handedness, starts up to 0.35 cell off
 * per corner: the refined corners lie within 0.15 px (clean) / 0.35 px
 * (noise +-40 grey levels) of the truth. */
static void test_recovers_true_corners(void)
{
    actag_refine_params rp;
    actag_rng r;
    int i, ok = 0;
    float worst_clean = 0.0f, worst_noisy = 0.0f;
    actag_refine_params_default(&rp);
    actag_rng_seed(&r, 7u);
    for (i = 0; i < 24; i++) {
        amap M;
        actag_point t[4], s[4], f[4];
        int id = (int)actag_rng_below(&r, (uint32_t)g_fam.ncodes), c, rc;
        float noise = (i & 1) ? 40.0f : 0.0f, e;
        random_map(&r, (i >> 1) & 1, &M);
        draw(id, &M, noise, &r);
        for (c = 0; c < 4; c++)
            t[c] = corner_of(&M, c);
        perturb(t, 7.0f, 0.35f, &r, s);
        rc = actag_refine_corners(g_img, RT_ROWS, RT_COLS, RT_COLS, NULL, 0.0f, &g_fam, id, s,
                                  &rp, f, NULL);
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, rc);
        e = tu_max_corner_error(f, t);
        if (noise > 0.0f)
            worst_noisy = e > worst_noisy ? e : worst_noisy;
        else
            worst_clean = e > worst_clean ? e : worst_clean;
        ok++;
    }
    TEST_ASSERT_EQUAL_INT(24, ok);
    TEST_ASSERT_FLOAT_WITHIN(0.15f, 0.0f, worst_clean);
    TEST_ASSERT_FLOAT_WITHIN(0.35f, 0.0f, worst_noisy);
}

/* Brute force: the best shift of the true map on a 0.05 px lattice within
 * +-1.5 px, by the sum of squared differences between the noisy image and
 * the clean drawing at that shift; the refinement (started 0.3 cell off)
 * finds the same place within 0.1 px. */
static void test_agrees_with_brute_force_shift(void)
{
    static uint8_t clean[RT_ROWS * RT_COLS], noisy[RT_ROWS * RT_COLS];
    actag_refine_params rp;
    actag_rng r;
    int i;
    actag_refine_params_default(&rp);
    actag_rng_seed(&r, 11u);
    for (i = 0; i < 3; i++) {
        amap M, S;
        actag_point t[4], s[4], f[4];
        int id = (int)actag_rng_below(&r, (uint32_t)g_fam.ncodes), c, jx, jy, rc;
        float best = 1e30f, bx = 0.0f, by = 0.0f, fx = 0.0f, fy = 0.0f;
        random_map(&r, i == 1, &M);
        draw(id, &M, 30.0f, &r);
        memcpy(noisy, g_img, sizeof noisy);
        for (jy = -6; jy <= 6; jy++) /* coarse: 0.25 px */
            for (jx = -6; jx <= 6; jx++) {
                float sx = 0.25f * (float)jx, sy = 0.25f * (float)jy, ssd = 0.0f;
                int p;
                S = M;
                S.m[0] += sx;
                S.m[1] += sy;
                draw(id, &S, 0.0f, &r);
                memcpy(clean, g_img, sizeof clean);
                for (p = 0; p < RT_ROWS * RT_COLS; p++) {
                    float d = (float)noisy[p] - (float)clean[p];
                    ssd += d * d;
                }
                if (ssd < best) {
                    best = ssd;
                    bx = sx;
                    by = sy;
                }
            }
        {
            float cx = bx, cy = by;
            for (jy = -5; jy <= 5; jy++) /* fine: 0.05 px around the coarse best */
                for (jx = -5; jx <= 5; jx++) {
                    float sx = cx + 0.05f * (float)jx, sy = cy + 0.05f * (float)jy, ssd = 0.0f;
                    int p;
                    S = M;
                    S.m[0] += sx;
                    S.m[1] += sy;
                    draw(id, &S, 0.0f, &r);
                    for (p = 0; p < RT_ROWS * RT_COLS; p++) {
                        float d = (float)noisy[p] - (float)g_img[p];
                        ssd += d * d;
                    }
                    if (ssd < best) {
                        best = ssd;
                        bx = sx;
                        by = sy;
                    }
                }
        }
        for (c = 0; c < 4; c++)
            t[c] = corner_of(&M, c);
        perturb(t, 7.0f, 0.3f, &r, s);
        rc = actag_refine_corners(noisy, RT_ROWS, RT_COLS, RT_COLS, NULL, 0.0f, &g_fam, id, s, &rp,
                                  f, NULL);
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, rc);
        for (c = 0; c < 4; c++) {
            fx += 0.25f * (f[c].x - t[c].x);
            fy += 0.25f * (f[c].y - t[c].y);
        }
        TEST_ASSERT_FLOAT_WITHIN(0.1f, bx, fx);
        TEST_ASSERT_FLOAT_WITHIN(0.1f, by, fy);
    }
}

/* A start in a wrong place (no tag there), a wrong ID's template on a clean
 * tag far off, and bad arguments: the start corners come back. */
static void test_refusals_and_errors(void)
{
    actag_refine_params rp, bad;
    actag_point s[4], f[4];
    amap M;
    actag_rng r;
    int c;
    actag_refine_params_default(&rp);
    actag_rng_seed(&r, 3u);
    memset(g_img, 90, sizeof g_img); /* flat: no tag */
    random_map(&r, 0, &M);
    for (c = 0; c < 4; c++)
        s[c] = corner_of(&M, c);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, actag_refine_corners(g_img, RT_ROWS, RT_COLS, RT_COLS,
                                                                   NULL, 0.0f, &g_fam, 0, s, &rp,
                                                                   f, NULL));
    TEST_ASSERT_EQUAL_MEMORY(s, f, sizeof s);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_refine_corners(NULL, RT_ROWS, RT_COLS, RT_COLS,
                                                               NULL, 0.0f, &g_fam, 0, s, &rp, f,
                                                               NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_refine_corners(g_img, RT_ROWS, RT_COLS, RT_COLS,
                                                               NULL, 0.0f, &g_fam, 0, s, NULL, f,
                                                               NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_refine_corners(g_img, RT_ROWS, RT_COLS, RT_COLS - 1,
                                                               NULL, 0.0f, &g_fam, 0, s, &rp, f,
                                                               NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_refine_corners(g_img, RT_ROWS, RT_COLS, RT_COLS,
                                                                NULL, 0.0f, &g_fam,
                                                                g_fam.ncodes, s, &rp, f, NULL));
    bad = rp;
    bad.blur = 0.0f;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_refine_corners(g_img, RT_ROWS, RT_COLS, RT_COLS,
                                                                NULL, 0.0f, &g_fam, 0, s, &bad, f,
                                                                NULL));
    bad = rp;
    bad.max_shift = 3.0f;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_refine_corners(g_img, RT_ROWS, RT_COLS, RT_COLS,
                                                                NULL, 0.0f, &g_fam, 0, s, &bad, f,
                                                                NULL));
    {   /* a caller's geometry is validated (it was used unchecked), and
         * tag_size checked with it; the documented defaults hold */
        actag_sonar_geometry geo = {0.1f, 1.5f, 1.0472f, NULL, 0u};
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM,
                              actag_refine_corners(g_img, RT_ROWS, RT_COLS, RT_COLS, &geo, 0.0f,
                                                   &g_fam, 0, s, &rp, f, NULL));
        geo.min_range = 2.0f; /* above max_range */
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY,
                              actag_refine_corners(g_img, RT_ROWS, RT_COLS, RT_COLS, &geo, 0.13f,
                                                   &g_fam, 0, s, &rp, f, NULL));
        geo.min_range = (float)NAN;
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY,
                              actag_refine_corners(g_img, RT_ROWS, RT_COLS, RT_COLS, &geo, 0.13f,
                                                   &g_fam, 0, s, &rp, f, NULL));
        TEST_ASSERT_EQUAL_FLOAT(1.0f, rp.max_shift);
        TEST_ASSERT_EQUAL_FLOAT(2.0f, rp.blur);
        TEST_ASSERT_EQUAL_FLOAT(0.3f, rp.margin);
        TEST_ASSERT_EQUAL_INT(8, rp.max_iterations);
        TEST_ASSERT_EQUAL_INT(6000, rp.max_samples);
    }
    {   /* a non-finite third corner: refused before out is written (the
         * first two corners had been copied, review of 2026-12-07) */
        actag_point nf[4], sentinel[4];
        memcpy(nf, s, sizeof nf);
        nf[2].y = (float)NAN;
        for (c = 0; c < 4; c++)
            sentinel[c].x = sentinel[c].y = -7.0f;
        memcpy(f, sentinel, sizeof f);
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM,
                              actag_refine_corners(g_img, RT_ROWS, RT_COLS, RT_COLS, NULL, 0.0f,
                                                   &g_fam, 0, nf, &rp, f, NULL));
        TEST_ASSERT_EQUAL_MEMORY(sentinel, f, sizeof f);
    }
    s[2] = s[0]; /* degenerate quad */
    TEST_ASSERT_TRUE(actag_refine_corners(g_img, RT_ROWS, RT_COLS, RT_COLS, NULL, 0.0f, &g_fam, 0,
                                          s, &rp, f, NULL) < 0);
}

/* A noise frame with a sonar geometry where a trial grid of the fit bends
 * so far that its curved inverse (the fixed point of the range curvature)
 * diverges to NaN: that grid is refused, and the fit ends defined (no
 * NaN reaches an int conversion: the sanitizer build checks), with a
 * result or NO_MATCH and finite corners. The frame's noise is xorshift64
 * from seed 2, the reviewer's case. */
static void test_diverging_curved_inverse_is_refused(void)
{
    static const uint32_t codes[1] = {0x12345u};
    static uint8_t img[57 * 17];
    const actag_sonar_geometry geo = {0.8f, 4.3f, 0.11f, NULL, 0u};
    const actag_point start[4] = {{4.26f, 35.71f}, {10.11f, 47.73f}, {-1.35f, 54.06f},
                                  {-8.10f, 42.71f}};
    actag_point out[4];
    actag_refine_params rp;
    actag_family f;
    uint64_t st = 2u * 0x9E3779B97F4A7C15ull;
    size_t i;
    int rc, c;
    memset(&f, 0, sizeof f);
    f.bits = 20;
    f.ncodes = 1;
    f.codes = codes;
    f.hamming = 1;
    for (i = 0; i < sizeof img; i++) {
        st ^= st << 13;
        st ^= st >> 7;
        st ^= st << 17;
        img[i] = (uint8_t)(st >> 11);
    }
    actag_refine_params_default(&rp);
    rc = actag_refine_corners(img, 57, 17, 17, &geo, 0.8f, &f, 0, start, &rp, out, NULL);
    TEST_ASSERT_TRUE(rc == ACTAG_OK || rc == ACTAG_ERR_NO_MATCH);
    for (c = 0; c < 4; c++)
        TEST_ASSERT_TRUE(isfinite(out[c].x) && isfinite(out[c].y));
}

/* A rendered tag of 8 px cells (axis-aligned, so a cell is 8 px in both
 * directions) and a start moved by a pure translation (2, 1.5) px: every
 * corner moves back by the same 2.5 px, and info.shift reports it in
 * cells (0.31), the unit of max_shift, not in pixels. */
static void test_info_shift_is_in_cells(void)
{
    enum { CELL = 8, MARGIN = 20 };
    static uint8_t img[RT_ROWS * RT_COLS];
    int side = actag_render_side(g_fam.bits, CELL, MARGIN), k = g_fam.bits / 4, c;
    float a = (float)(MARGIN + 2 * CELL) - 0.5f, b = (float)(MARGIN + (k - 1) * CELL) - 0.5f;
    actag_point t[4], s[4], f[4];
    actag_refine_params rp;
    actag_refine_info info;
    float moved = 0.0f;
    TEST_ASSERT_TRUE(side <= RT_COLS && side * side <= (int)sizeof img);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_render_tag(&g_fam, 3, CELL, MARGIN, 60, 0, img, side,
                                                     sizeof img));
    t[0].x = a; t[0].y = a;
    t[1].x = b; t[1].y = a;
    t[2].x = b; t[2].y = b;
    t[3].x = a; t[3].y = b;
    for (c = 0; c < 4; c++) {
        s[c].x = t[c].x + 2.0f;
        s[c].y = t[c].y + 1.5f;
    }
    actag_refine_params_default(&rp);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_refine_corners(img, side, side, side, NULL, 0.0f, &g_fam,
                                                         3, s, &rp, f, &info));
    TEST_ASSERT_FLOAT_WITHIN(0.25f, 0.0f, tu_max_corner_error(f, t));
    for (c = 0; c < 4; c++) {
        float d = hypotf(f[c].x - s[c].x, f[c].y - s[c].y);
        moved = d > moved ? d : moved;
    }
    TEST_ASSERT_FLOAT_WITHIN(0.01f, moved / (float)CELL, info.shift);
    TEST_ASSERT_FLOAT_WITHIN(0.02f, 2.5f / (float)CELL, info.shift);
}

/* The rendered tag of test_info_shift_is_in_cells (id 3, 8 px cells, 20 px
 * margin) and its true white-square corners. */
static int render_tag3(uint8_t *img, size_t size, actag_point t[4])
{
    int side = actag_render_side(g_fam.bits, 8, 20), k = g_fam.bits / 4;
    float a = (float)(20 + 2 * 8) - 0.5f, b = (float)(20 + (k - 1) * 8) - 0.5f;
    TEST_ASSERT_TRUE((size_t)side * (size_t)side <= size);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_render_tag(&g_fam, 3, 8, 20, 60, 0, img, side, size));
    t[0].x = a; t[0].y = a;
    t[1].x = b; t[1].y = a;
    t[2].x = b; t[2].y = b;
    t[3].x = a; t[3].y = b;
    return side;
}

/* A start about 0.4 cell off: accepted with the default max_shift, refused
 * (NO_MATCH, the start corners copied to out) once max_shift is below the
 * fit's own move, accepted again just above it. */
static void test_refuses_a_move_above_max_shift(void)
{
    static uint8_t img[100 * 100];
    static const float off[4][2] = {{3.0f, 2.0f}, {2.5f, -3.0f}, {-3.0f, 2.5f}, {3.0f, 3.0f}};
    actag_point t[4], s[4], f[4];
    actag_refine_params rp;
    actag_refine_info info;
    int side = render_tag3(img, sizeof img, t), c;
    float moved;
    for (c = 0; c < 4; c++) {
        s[c].x = t[c].x + off[c][0];
        s[c].y = t[c].y + off[c][1];
    }
    actag_refine_params_default(&rp);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_refine_corners(img, side, side, side, NULL, 0.0f, &g_fam,
                                                         3, s, &rp, f, &info));
    TEST_ASSERT_FLOAT_WITHIN(0.25f, 0.0f, tu_max_corner_error(f, t));
    moved = info.shift;
    TEST_ASSERT_TRUE(moved > 0.3f && moved < 1.0f);
    rp.max_shift = 0.9f * moved;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, actag_refine_corners(img, side, side, side, NULL, 0.0f,
                                                                   &g_fam, 3, s, &rp, f, NULL));
    TEST_ASSERT_EQUAL_MEMORY(s, f, sizeof s);
    rp.max_shift = 1.01f * moved;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_refine_corners(img, side, side, side, NULL, 0.0f, &g_fam,
                                                         3, s, &rp, f, NULL));
}

/* Starts scaled about the tag's centre: the fit finds the true square, but
 * from 1.35 times its size its sides shrink to 0.55 of the start's squared
 * (below 0.75^2), and from 0.72 they grow to 1.9 of them (without a
 * geometry no growth beyond 25 % is allowed): both refused, the start
 * corners copied to out. A start 1.1 times the size is within the rule and
 * accepted. max_shift at its largest, so that only the side rule refuses. */
static void test_refuses_sides_changed_beyond_25_percent(void)
{
    static uint8_t img[100 * 100];
    static const float scale[3] = {1.35f, 0.72f, 1.1f};
    actag_point t[4], s[4], f[4];
    actag_refine_params rp;
    int side = render_tag3(img, sizeof img, t), c, i;
    float cx = 0.5f * (t[0].x + t[2].x), cy = 0.5f * (t[0].y + t[2].y);
    actag_refine_params_default(&rp);
    rp.max_shift = 2.0f;
    for (i = 0; i < 3; i++) {
        int rc;
        for (c = 0; c < 4; c++) {
            s[c].x = cx + scale[i] * (t[c].x - cx);
            s[c].y = cy + scale[i] * (t[c].y - cy);
        }
        rc = actag_refine_corners(img, side, side, side, NULL, 0.0f, &g_fam, 3, s, &rp, f, NULL);
        if (i < 2) {
            TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, rc);
            TEST_ASSERT_EQUAL_MEMORY(s, f, sizeof s);
        } else {
            TEST_ASSERT_EQUAL_INT(ACTAG_OK, rc);
            TEST_ASSERT_FLOAT_WITHIN(0.25f, 0.0f, tu_max_corner_error(f, t));
        }
    }
}

/* The acceptance's shape rules at their boundaries (a fitted grid against
 * its start, refine_frame.h): the handedness, each side's 25 % (squared:
 * 0.5625 .. 1.5625), growth with a geometry up to 1.21 cell^2 and 2.25
 * times the start, non-finite grids. The fit itself never flipped in a
 * search over thousands of starts (a flip within max_shift needs a nearly
 * degenerate grid, which the side rule refuses first), so the handedness
 * rule is checked here. And a start in the mirrored corner order refines
 * to corners in that order: the stage never changes the handedness. */
static void test_shape_rules(void)
{
    static uint8_t img[100 * 100];
    const float st[6] = {50.0f, 50.0f, 8.0f, 0.0f, 0.0f, 8.0f};
    float g[6];
    actag_point t[4], s[4], f[4];
    actag_refine_params rp;
    int side, c;
    float a0, a1;
#define SHAPE(m0, m1, ax, ay, bx, by, cell2)                                                       \
    (g[0] = (m0), g[1] = (m1), g[2] = (ax), g[3] = (ay), g[4] = (bx), g[5] = (by),                 \
     actag__refine_shape_ok(st, g, (cell2)))
    TEST_ASSERT_EQUAL_INT(1, SHAPE(51.0f, 49.0f, 8.0f, 0.0f, 0.0f, 8.0f, 0.0f));
    /* mirrored: b turned over, a tilted toward it (no length changed) */
    TEST_ASSERT_EQUAL_INT(0, SHAPE(50.0f, 50.0f, 8.0f, 0.0f, 0.0f, -8.0f, 0.0f));
    TEST_ASSERT_EQUAL_INT(0, SHAPE(50.0f, 50.0f, 0.0f, 8.0f, 8.0f, 0.0f, 0.0f));
    TEST_ASSERT_EQUAL_INT(0, SHAPE(50.0f, 50.0f, 8.0f, 0.0f, 8.0f, 0.0f, 0.0f)); /* degenerate */
    /* each side within 25 % of the start's, squared 0.5625 .. 1.5625 */
    TEST_ASSERT_EQUAL_INT(1, SHAPE(50.0f, 50.0f, 6.08f, 0.0f, 0.0f, 8.0f, 0.0f));  /* 0.5776 */
    TEST_ASSERT_EQUAL_INT(0, SHAPE(50.0f, 50.0f, 5.92f, 0.0f, 0.0f, 8.0f, 0.0f));  /* 0.5476 */
    TEST_ASSERT_EQUAL_INT(1, SHAPE(50.0f, 50.0f, 8.0f, 0.0f, 0.0f, 6.08f, 0.0f));
    TEST_ASSERT_EQUAL_INT(0, SHAPE(50.0f, 50.0f, 8.0f, 0.0f, 0.0f, 5.92f, 0.0f));
    TEST_ASSERT_EQUAL_INT(1, SHAPE(50.0f, 50.0f, 9.92f, 0.0f, 0.0f, 8.0f, 0.0f));  /* 1.5376 */
    TEST_ASSERT_EQUAL_INT(0, SHAPE(50.0f, 50.0f, 10.08f, 0.0f, 0.0f, 8.0f, 0.0f)); /* 1.5876 */
    TEST_ASSERT_EQUAL_INT(1, SHAPE(50.0f, 50.0f, 8.0f, 0.0f, 0.0f, 9.92f, 0.0f));
    TEST_ASSERT_EQUAL_INT(0, SHAPE(50.0f, 50.0f, 8.0f, 0.0f, 0.0f, 10.08f, 0.0f));
    /* growth by 1.45 (2.1025 squared, 134.56): up to 1.21 cell^2 */
    TEST_ASSERT_EQUAL_INT(0, SHAPE(50.0f, 50.0f, 11.6f, 0.0f, 0.0f, 8.0f, 0.0f));
    TEST_ASSERT_EQUAL_INT(1, SHAPE(50.0f, 50.0f, 11.6f, 0.0f, 0.0f, 8.0f, 120.0f)); /* 145.2 */
    TEST_ASSERT_EQUAL_INT(0, SHAPE(50.0f, 50.0f, 11.6f, 0.0f, 0.0f, 8.0f, 110.0f)); /* 133.1 */
    TEST_ASSERT_EQUAL_INT(1, SHAPE(50.0f, 50.0f, 8.0f, 0.0f, 0.0f, 11.6f, 120.0f));
    TEST_ASSERT_EQUAL_INT(0, SHAPE(50.0f, 50.0f, 8.0f, 0.0f, 0.0f, 11.6f, 110.0f));
    /* and at most 2.25 times the start's, whatever the cell: 1.55 is 2.4025 */
    TEST_ASSERT_EQUAL_INT(0, SHAPE(50.0f, 50.0f, 12.4f, 0.0f, 0.0f, 8.0f, 400.0f));
    TEST_ASSERT_EQUAL_INT(1, SHAPE(50.0f, 50.0f, 11.92f, 0.0f, 0.0f, 8.0f, 400.0f)); /* 2.2201 */
    TEST_ASSERT_EQUAL_INT(0, SHAPE(50.0f, 50.0f, 8.0f, 0.0f, 0.0f, 12.4f, 400.0f));
    TEST_ASSERT_EQUAL_INT(0, SHAPE((float)NAN, 50.0f, 8.0f, 0.0f, 0.0f, 8.0f, 0.0f));
    TEST_ASSERT_EQUAL_INT(0, SHAPE(50.0f, 50.0f, 8.0f, 0.0f, 0.0f, (float)INFINITY, 400.0f));
#undef SHAPE
    side = render_tag3(img, sizeof img, t);
    s[0] = t[1];
    s[1] = t[0];
    s[2] = t[3];
    s[3] = t[2];
    for (c = 0; c < 4; c++)
        s[c].x += 1.5f;
    actag_refine_params_default(&rp);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_refine_corners(img, side, side, side, NULL, 0.0f, &g_fam,
                                                         3, s, &rp, f, NULL));
    /* each corner near its own start corner (the square's side is 24 px) */
    for (c = 0; c < 4; c++)
        TEST_ASSERT_FLOAT_WITHIN(4.0f, 0.0f, hypotf(f[c].x - s[c].x + 1.5f, f[c].y - s[c].y));
    a0 = (s[1].x - s[0].x) * (s[3].y - s[0].y) - (s[1].y - s[0].y) * (s[3].x - s[0].x);
    a1 = (f[1].x - f[0].x) * (f[3].y - f[0].y) - (f[1].y - f[0].y) * (f[3].x - f[0].x);
    TEST_ASSERT_TRUE(a0 < 0.0f && a1 < 0.0f);
}

/* Same input, same bits. */
static void test_deterministic(void)
{
    actag_refine_params rp;
    actag_point t[4], s[4], f1[4], f2[4];
    actag_refine_info i1, i2;
    amap M;
    actag_rng r;
    int c;
    actag_refine_params_default(&rp);
    actag_rng_seed(&r, 5u);
    random_map(&r, 0, &M);
    draw(3, &M, 20.0f, &r);
    for (c = 0; c < 4; c++)
        t[c] = corner_of(&M, c);
    perturb(t, 7.0f, 0.2f, &r, s);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_refine_corners(g_img, RT_ROWS, RT_COLS, RT_COLS, NULL,
                                                         0.0f, &g_fam, 3, s, &rp, f1, &i1));
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_refine_corners(g_img, RT_ROWS, RT_COLS, RT_COLS, NULL,
                                                         0.0f, &g_fam, 3, s, &rp, f2, &i2));
    TEST_ASSERT_EQUAL_MEMORY(f1, f2, sizeof f1);
    TEST_ASSERT_TRUE(i1.samples > 1000);
    TEST_ASSERT_TRUE(i1.contrast > 100.0f && i1.contrast < 200.0f);
}

/* A 16-bit image (any scale, odd address, padded stride) refines exactly as
 * its 8-bit conversion by the detector's rule (v * 255 + max / 2) / max,
 * and depth 8 is actag_refine_corners itself; other depths are refused. */
static void test_sixteen_bit_equals_its_conversion(void)
{
    static uint8_t buf16[2u * RT_ROWS * (RT_COLS + 3) + 1];
    static uint8_t img8[RT_ROWS * RT_COLS];
    actag_refine_params rp;
    actag_rng r;
    int i;
    actag_refine_params_default(&rp);
    actag_rng_seed(&r, 11u);
    for (i = 0; i < 6; i++) {
        amap M;
        actag_point t[4], s[4], f8[4], f16[4], fd[4];
        int id = (int)actag_rng_below(&r, (uint32_t)g_fam.ncodes), c, x, y, stride = RT_COLS + 3;
        uint32_t gain = 1u + actag_rng_below(&r, 257u), mx = 0;
        uint8_t *p16 = buf16 + 1; /* odd address */
        random_map(&r, i & 1, &M);
        draw(id, &M, 30.0f, &r);
        for (y = 0; y < RT_ROWS; y++)
            for (x = 0; x < stride; x++) {
                /* padding at full scale: it must not count as the maximum */
                uint16_t v = (uint16_t)(x < RT_COLS ? g_img[y * RT_COLS + x] * gain : 65535u);
                if (x < RT_COLS && v > mx)
                    mx = v;
                memcpy(p16 + 2 * (y * stride + x), &v, 2);
            }
        for (y = 0; y < RT_ROWS; y++)
            for (x = 0; x < RT_COLS; x++) {
                uint32_t v = g_img[y * RT_COLS + x] * gain;
                img8[y * RT_COLS + x] = (uint8_t)((v * 255u + mx / 2u) / mx);
            }
        for (c = 0; c < 4; c++)
            t[c] = corner_of(&M, c);
        perturb(t, 7.0f, 0.3f, &r, s);
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_refine_corners(img8, RT_ROWS, RT_COLS, RT_COLS, NULL,
                                                             0.0f, &g_fam, id, s, &rp, f8, NULL));
        TEST_ASSERT_EQUAL_INT(ACTAG_OK,
                              actag_refine_corners_depth(p16, 16, RT_ROWS, RT_COLS, stride, NULL,
                                                         0.0f, &g_fam, id, s, &rp, f16, NULL));
        TEST_ASSERT_EQUAL_MEMORY(f8, f16, sizeof f8);
        /* the frame's maximum handed in (actag_detect's one scan per frame):
         * the scale is the one given, here twice the frame's own */
        for (y = 0; y < RT_ROWS; y++)
            for (x = 0; x < RT_COLS; x++) {
                uint32_t v = g_img[y * RT_COLS + x] * gain;
                img8[y * RT_COLS + x] = (uint8_t)((v * 255u + mx) / (2u * mx));
            }
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_refine_corners(img8, RT_ROWS, RT_COLS, RT_COLS, NULL,
                                                             0.0f, &g_fam, id, s, &rp, f8, NULL));
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag__refine_corners_max16(p16, 16, 2u * mx, RT_ROWS,
                                                                    RT_COLS, stride, NULL, 0.0f,
                                                                    &g_fam, id, s, &rp, fd, NULL));
        TEST_ASSERT_EQUAL_MEMORY(f8, fd, sizeof f8);
        for (y = 0; y < RT_ROWS; y++) /* back to the frame's own scale */
            for (x = 0; x < RT_COLS; x++) {
                uint32_t v = g_img[y * RT_COLS + x] * gain;
                img8[y * RT_COLS + x] = (uint8_t)((v * 255u + mx / 2u) / mx);
            }
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_refine_corners(img8, RT_ROWS, RT_COLS, RT_COLS, NULL,
                                                             0.0f, &g_fam, id, s, &rp, f8, NULL));
        TEST_ASSERT_EQUAL_INT(ACTAG_OK,
                              actag_refine_corners_depth(img8, 8, RT_ROWS, RT_COLS, RT_COLS, NULL,
                                                         0.0f, &g_fam, id, s, &rp, fd, NULL));
        TEST_ASSERT_EQUAL_MEMORY(f8, fd, sizeof f8);
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM,
                              actag_refine_corners_depth(img8, 12, RT_ROWS, RT_COLS, RT_COLS, NULL,
                                                         0.0f, &g_fam, id, s, &rp, fd, NULL));
    }
}

/* The library's refinement and the portable one on the same input: the
 * same return code, corners and info, bit for bit. Counts the cases and
 * those refined (ACTAG_OK). */
static void same_paths(const void *img, int depth, int rows, int cols, int stride,
                       const actag_sonar_geometry *geo, float tag_size, int id,
                       const actag_point s[4], const actag_refine_params *rp, int count[2])
{
    actag_point fa[4], fb[4];
    actag_refine_info ia, ib;
    int ra, rb;
    memset(&ia, 0, sizeof ia);
    memset(&ib, 0, sizeof ib);
    ra = actag__refine_corners_max16(img, depth, 0u, rows, cols, stride, geo, tag_size, &g_fam,
                                     id, s, rp, fa, &ia);
    rb = actag__refine_corners_max16_portable(img, depth, 0u, rows, cols, stride, geo, tag_size,
                                              &g_fam, id, s, rp, fb, &ib);
    TEST_ASSERT_EQUAL_INT(rb, ra);
    TEST_ASSERT_EQUAL_MEMORY(fb, fa, sizeof fa);
    TEST_ASSERT_EQUAL_MEMORY(&ib, &ia, sizeof ia);
    count[0]++;
    count[1] += ra == ACTAG_OK;
}

/* Tags drawn under random maps, refined in a sonar fan (curved grids: the
 * x86 sweeps' lane-wise paths) of random size, aperture (up to 200 degrees,
 * beyond the refinement's +-0.6 rad column cache), orientation and tag
 * size; starts up to 0.6 cell off, some outside the frame; 8 and 16 bits;
 * lattices of every sparseness (max_samples); pure noise too (grids that
 * diverge): the library's refinement and the portable one agree bit for
 * bit. */
static void test_simd_equals_portable_synthetic(void)
{
    static uint8_t img16[2 * RT_ROWS * RT_COLS];
    actag_rng r;
    int i, count[2] = {0, 0}, n = TU_TRIALS(240, 8);
    actag_rng_seed(&r, 27u);
    for (i = 0; i < n; i++) {
        amap M;
        actag_point t[4], s[4];
        actag_refine_params rp;
        actag_sonar_geometry geo;
        int id = (int)actag_rng_below(&r, (uint32_t)g_fam.ncodes), c, k = g_fam.bits / 4;
        float mpp = 0.002f + 0.004f * frand(&r), cell;
        random_map(&r, i & 1, &M);
        draw(id, &M, (i % 3) * 25.0f, &r);
        if (i % 17 == 5) /* noise alone */
            for (c = 0; c < RT_ROWS * RT_COLS; c++)
                g_img[c] = (uint8_t)actag_rng_below(&r, 256u);
        geo.min_range = 0.2f + 2.0f * frand(&r);
        geo.max_range = geo.min_range + (float)(RT_ROWS - 1) * mpp;
        geo.aperture = (i % 5 == 0 ? 3.5f : 1.0f) * (float)(RT_COLS - 1) * mpp /
                       (0.5f * (geo.min_range + geo.max_range)) * (0.7f + 0.6f * frand(&r));
        if (geo.aperture > 3.1f)
            geo.aperture = 3.1f;
        geo.bearings = NULL;
        geo.flags = (unsigned)(i & 3);
        cell = sqrtf(M.a[0] * M.a[0] + M.a[1] * M.a[1]);
        for (c = 0; c < 4; c++)
            t[c] = corner_of(&M, c);
        perturb(t, cell, i % 7 == 3 ? 0.6f : 0.3f, &r, s);
        if (i % 11 == 4) /* a start partly outside the frame */
            for (c = 0; c < 4; c++)
                s[c].x += 0.45f * (float)RT_COLS;
        actag_refine_params_default(&rp);
        rp.max_samples = i % 4 == 1 ? 200 + (int)actag_rng_below(&r, 800u) : 6000;
        /* the tag's white square in metres, 0.7 to 1.3 times its drawn size */
        {
            float ts = (float)(k - 3) * cell * mpp * (0.7f + 0.6f * frand(&r));
            if (i % 6 == 2) {
                int x, y;
                for (y = 0; y < RT_ROWS; y++)
                    for (x = 0; x < RT_COLS; x++) {
                        uint16_t v = (uint16_t)(g_img[y * RT_COLS + x] * 251u + (unsigned)(x % 7));
                        memcpy(img16 + 2 * (y * RT_COLS + x), &v, 2);
                    }
                same_paths(img16, 16, RT_ROWS, RT_COLS, RT_COLS, &geo, ts, id, s, &rp, count);
            } else {
                same_paths(g_img, 8, RT_ROWS, RT_COLS, RT_COLS, &geo, ts, id, s, &rp, count);
            }
        }
    }
    /* most cases refined: the comparison covers full fits, not refusals */
    TEST_ASSERT_TRUE(count[1] * 2 > count[0]);
}

/* The pool frames of data/pool-video in the four orientations: the
 * refinements of actag_detect's detections from starts moved by up to two
 * pixels, 8-bit and 16-bit, dense and sparse lattices, agree bit for bit. */
static void test_simd_equals_portable_pool(void)
{
    static const char *const frames[] = {"f_0001.pgm", "f_0011.pgm", "f_0291.pgm",
                                         "f_0421.pgm", "f_0491.pgm", "f_0561.pgm"};
    int f, count[2] = {0, 0};
    for (f = 0; f < 6; f += TU_STEP(3)) {
        char path[1024];
        int rows, cols, o, i;
        uint8_t *img, *img16, *ws;
        size_t wsize;
        actag_params p;
        snprintf(path, sizeof path, "%s/pool-video/%s", TU_DATA, frames[f]);
        img = tu_read_pgm(path, &rows, &cols);
        TEST_ASSERT_NOT_NULL(img);
        img16 = (uint8_t *)malloc(2u * (size_t)rows * (size_t)cols);
        wsize = actag_workspace_size(rows, cols);
        ws = (uint8_t *)malloc(wsize);
        TEST_ASSERT_TRUE(img16 != NULL && ws != NULL);
        for (i = 0; i < rows * cols; i++) {
            uint16_t v = (uint16_t)(img[i] * 97u + (unsigned)(i % 13));
            memcpy(img16 + 2 * i, &v, 2);
        }
        actag_params_default(&p);
        p.family = &g_fam;
        for (o = 0; o < 4; o++) {
            const actag_sonar_geometry geo = {0.1f, 1.5f, 1.0472f, NULL, (unsigned)o};
            actag_detection det[8];
            actag_frame fr;
            int n, d, v;
            fr.data = img;
            fr.rows = rows;
            fr.cols = cols;
            fr.stride = cols;
            fr.depth = 8;
            n = actag_detect(&fr, &geo, &p, ws, wsize, det, 8, NULL);
            TEST_ASSERT_TRUE(n >= 0);
            for (d = 0; d < n; d++)
                for (v = 0; v < 6; v++) {
                    actag_refine_params rp;
                    actag_point s[4];
                    int c;
                    actag_refine_params_default(&rp);
                    if (v >= 3)
                        rp.max_samples = 300 + 700 * v;
                    for (c = 0; c < 4; c++) {
                        s[c].x = det[d].corners[c].x + 0.7f * (float)((v * 7 + c * 3) % 5 - 2);
                        s[c].y = det[d].corners[c].y + 0.6f * (float)((v * 5 + c * 11) % 5 - 2);
                    }
                    if (v & 1)
                        same_paths(img16, 16, rows, cols, cols, &geo, p.tag_size, det[d].id, s,
                                   &rp, count);
                    else
                        same_paths(img, 8, rows, cols, cols, &geo, p.tag_size, det[d].id, s, &rp,
                                   count);
                }
        }
        free(img);
        free(img16);
        free(ws);
    }
    TEST_ASSERT_TRUE(count[1] >= 20 && count[1] * 4 > count[0] * 3);
}

int main(void)
{
    printf("test_refine: %s\n", RT_LIBRARY_SSE2 ? "the library's SSE2 sweeps compared with the portable copy"
                                               : "no SSE2 sweeps in this build: test_simd_* compare the portable code with itself");
    UNITY_BEGIN();
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &g_fam));
    RUN_TEST(test_recovers_true_corners);
    RUN_TEST(test_agrees_with_brute_force_shift);
    RUN_TEST(test_refusals_and_errors);
    RUN_TEST(test_diverging_curved_inverse_is_refused);
    RUN_TEST(test_deterministic);
    RUN_TEST(test_info_shift_is_in_cells);
    RUN_TEST(test_refuses_a_move_above_max_shift);
    RUN_TEST(test_refuses_sides_changed_beyond_25_percent);
    RUN_TEST(test_shape_rules);
    RUN_TEST(test_sixteen_bit_equals_its_conversion);
    RUN_TEST(test_simd_equals_portable_synthetic);
    RUN_TEST(test_simd_equals_portable_pool);
    return UNITY_END();
}
