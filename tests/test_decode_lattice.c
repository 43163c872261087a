/* The fit decoder's wide-search lattice (src/decode_fit.c, flattice): the
 * 5-sample cell means of a grid's 25 half-cell shifts read from one shared
 * lattice against the same shifts read grid by grid (the brute-force
 * reference), on random images and grids, inside the frame and across its
 * edges (edge replication). They may differ only by the rounding of the
 * sample coordinates. */
#include "../src/decode_fit_test.h"

#include "unity.h"
#include "test_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void setUp(void) {}
void tearDown(void) {}

#define R 96
#define C 120

static uint32_t lcg(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}

static float unif(uint32_t *s, float lo, float hi)
{
    return lo + (hi - lo) * (float)(lcg(s) & 0xffffu) / 65535.0f;
}

/* blocky random grey levels (cells of 3 px) with speckle: strong gradients */
static void fill_image(uint8_t *img, uint32_t *s)
{
    int r, c;
    for (r = 0; r < R; r++)
        for (c = 0; c < C; c++)
            img[r * C + c] = (uint8_t)(((unsigned)(r / 3 * 7 + c / 3 * 13) * 37u + (lcg(s) & 31u)) & 255u);
}

/* The largest difference of two neighbouring pixels (along a row or a
 * column) of the R x C test image. */
static int max_step(const uint8_t *img)
{
    int r, c, m = 0;
    for (r = 0; r < R; r++)
        for (c = 0; c < C; c++) {
            int v = img[r * C + c];
            if (c + 1 < C && abs(img[r * C + c + 1] - v) > m)
                m = abs(img[r * C + c + 1] - v);
            if (r + 1 < R && abs(img[(r + 1) * C + c] - v) > m)
                m = abs(img[(r + 1) * C + c] - v);
        }
    return m;
}

static long cells_read, cells_same;

/* Worst difference of a lattice cell from the same cell read directly,
 * over the 25 shifts. Both are the same fixed-point reads (fit_cells.c)
 * whose centres, computed in float along two paths, may truncate to
 * points 1/256 pixel apart in x and in y: every sample then moves by that
 * much, so a cell moves by at most (1/256 + 1/256) max_step grey levels. */
static float compare(const uint8_t *img, const float g[6], int k, float so)
{
    float lat[81], dir[81], worst = 0.0f;
    int i, j, c, n = k + 1;
    for (j = -2; j <= 2; j++)
        for (i = -2; i <= 2; i++) {
            TEST_ASSERT_EQUAL_INT(ACTAG_OK,
                                  actag__fit_shift_cells(img, R, C, C, g, k, so, i, j, lat, dir));
            for (c = 0; c < n * n; c++) {
                float d = fabsf(lat[c] - dir[c]);
                TEST_ASSERT_TRUE(dir[c] >= 0.0f && dir[c] <= 255.0f);
                cells_read++;
                cells_same += d == 0.0f;
                if (d > worst)
                    worst = d;
            }
        }
    return worst;
}

/* The bound of compare() for the image, with the float rounding of a
 * cell mean. */
static float lattice_bound(const uint8_t *img)
{
    return 2.0f * (float)max_step(img) / 256.0f + 1e-3f;
}

/* Random grids (cells 1.5-7 px, any rotation, sheared, k 4..8, sample
 * offsets 0..0.5) wholly inside the frame: the lattice equals the direct
 * reading within 0.02 grey levels. */
static void test_lattice_equals_direct_inside(void)
{
    static uint8_t img[R * C];
    uint32_t s = 12345u;
    int trial;
    cells_read = cells_same = 0;
    fill_image(img, &s);
    for (trial = 0; trial < 300; trial++) {
        int k = 4 + (int)(lcg(&s) % 5u);
        float cell = unif(&s, 1.5f, 7.0f), th = unif(&s, 0.0f, 6.2831853f);
        float sh = unif(&s, -0.4f, 0.4f), so = (float)(lcg(&s) % 5u) * 0.125f;
        float ext = cell * ((float)k + 4.0f) * 1.5f, g[6];
        g[2] = cell * cosf(th);
        g[3] = cell * sinf(th);
        g[4] = -cell * sinf(th) + sh * g[2];
        g[5] = cell * cosf(th) + sh * g[3];
        if (ext > 0.45f * (float)R)
            continue;
        g[0] = unif(&s, ext, (float)C - ext);
        g[1] = unif(&s, ext, (float)R - ext);
        TEST_ASSERT_TRUE(compare(img, g, k, so) <= lattice_bound(img));
    }
    /* a centre truncates to another point only when its two float values
     * straddle a multiple of 1/256 pixel: nearly every cell agrees bit for bit */
    printf("lattice against direct reads: %ld of %ld cells bit for bit\n", cells_same, cells_read);
    TEST_ASSERT_TRUE(cells_same > cells_read * 99 / 100);
}

/* Grids centred near or beyond the frame's edges and corners: edge
 * replication gives the same as grid by grid. */
static void test_lattice_equals_direct_at_edges(void)
{
    static uint8_t img[R * C];
    uint32_t s = 777u;
    int trial;
    fill_image(img, &s);
    for (trial = 0; trial < 300; trial++) {
        int k = 4 + (int)(lcg(&s) % 5u);
        float cell = unif(&s, 1.5f, 9.0f), th = unif(&s, 0.0f, 6.2831853f), g[6];
        g[2] = cell * cosf(th);
        g[3] = cell * sinf(th);
        g[4] = -cell * sinf(th);
        g[5] = cell * cosf(th);
        /* centre on a random border strip, partly off the frame */
        g[0] = (lcg(&s) & 1u) ? unif(&s, -20.0f, 25.0f) : unif(&s, (float)C - 25.0f, (float)C + 20.0f);
        g[1] = (lcg(&s) & 1u) ? unif(&s, -20.0f, 25.0f) : unif(&s, (float)R - 25.0f, (float)R + 20.0f);
        TEST_ASSERT_TRUE(compare(img, g, k, 0.2f) <= lattice_bound(img));
    }
}

/* A grid on an integer lattice of the pixels (axis-aligned, whole-pixel
 * cells, half-cell shifts on whole pixels): both readings are exact, so
 * they agree bit for bit. */
static void test_lattice_exact_on_pixel_grid(void)
{
    static uint8_t img[R * C];
    uint32_t s = 4242u;
    float g[6] = {60.0f, 48.0f, 4.0f, 0.0f, 0.0f, 4.0f};
    fill_image(img, &s);
    TEST_ASSERT_EQUAL_FLOAT(0.0f, compare(img, g, 6, 0.25f));
}

#define BR 530
#define BC 700
#define BS 712

/* A hook reading one grid two ways (actag__fit_simd_cells: portable and
 * SSE2; actag__fit_avx2_cells: portable and AVX2, 1 when the AVX2 path
 * read the grid; actag__fit_scalar_cells: straightforward and scalar). */
typedef int (*cells_hook)(const uint8_t *img, int rows, int cols, int stride, const float g[6],
                          int k, float so, int what, float *a, float *b);

/* Two cell reads of a hook, bit for bit: 9-sample cells, 5-sample cells,
 * erased data corners and the four lattice parity classes, on random grids
 * over a large frame of random bytes (most inside, some across its edges)
 * (row padding filled too: a wrong offset or lane order reads other bytes),
 * some on quarter-pixel coordinates (bilinear weights 0 and exact sums).
 * Returns how many grids the hook said its AVX2 path read. */
static long cells_equal_big_frame(cells_hook hook)
{
    static uint8_t img[BR * BS];
    static const int whats[7] = {0, 1, 2, 4, 5, 6, 7};
    uint32_t s = 2718u;
    int trial, i, nonzero = 0, trials = TU_TRIALS(3000, 10); /* the scalar reads run emulated too */
    long served = 0;
    for (i = 0; i < BR * BS; i++)
        img[i] = (uint8_t)(lcg(&s) & 255u);
    for (trial = 0; trial < trials; trial++) {
        int k = 4 + (int)(lcg(&s) % 5u), what = whats[lcg(&s) % 7u], n = k + 1, cnt, c, rc;
        float cell = unif(&s, 0.7f, 12.0f), th = unif(&s, 0.0f, 6.2831853f);
        float sh = unif(&s, -0.5f, 0.5f), so = unif(&s, 0.0f, 0.5f), g[6];
        float a[(ACTAG_DECODE_MAX_K + 3) * (ACTAG_DECODE_MAX_K + 3)];
        float b[(ACTAG_DECODE_MAX_K + 3) * (ACTAG_DECODE_MAX_K + 3)];
        g[2] = cell * cosf(th);
        g[3] = cell * sinf(th);
        g[4] = -cell * sinf(th) + sh * g[2];
        g[5] = cell * cosf(th) + sh * g[3];
        g[0] = unif(&s, 0.0f, (float)BC);
        g[1] = unif(&s, 0.0f, (float)BR);
        if (trial % 4 == 0) /* quarter-pixel points: axis-aligned, quarter-pixel cells */
            for (c = 0; c < 6; c++)
                g[c] = c == 3 || c == 4 ? 0.0f : floorf(g[c] * 4.0f) * 0.25f;
        memset(a, 0xa5, sizeof a);
        memset(b, 0x5a, sizeof b);
        rc = hook(img, BR, BC, BS, g, k, so, what, a, b);
        TEST_ASSERT_TRUE(rc == ACTAG_OK || rc == 1); /* inside or across the edges: both served */
        served += rc == 1;
        cnt = what < 4 ? n * n : (n + 2 - (what & 1)) * (n + 2 - ((what >> 1) & 1));
        TEST_ASSERT_EQUAL_MEMORY(a, b, (size_t)cnt * sizeof(float));
        for (c = 0; c < cnt; c++)
            nonzero += a[c] != 0.0f;
    }
    TEST_ASSERT_TRUE(nonzero > 50 * trials);
    return served;
}

/* One grid's two reads (hook) on one frame, bit for bit; 1 when the hook
 * said its AVX2 path read the grid, else 0. lanes: also require the cells
 * (lattice points) read to differ within every run of 8 consecutive ones
 * (the erased corners, 0, aside), so that a wrong lane of the eight (a
 * wrong cell, a lane order or a spare lane stored) shows in the
 * comparison. */
static int cells_check_lanes(cells_hook hook, const uint8_t *img, int rows, int cols, int stride,
                             const float g[6], int k, float so, int what, int lanes)
{
    float a[(ACTAG_DECODE_MAX_K + 3) * (ACTAG_DECODE_MAX_K + 3)];
    float b[(ACTAG_DECODE_MAX_K + 3) * (ACTAG_DECODE_MAX_K + 3)];
    int n = k + 1, cnt = what < 4 ? n * n : (n + 2 - (what & 1)) * (n + 2 - ((what >> 1) & 1)), rc, i, j;
    memset(a, 0xa5, sizeof a);
    memset(b, 0x5a, sizeof b);
    rc = hook(img, rows, cols, stride, g, k, so, what, a, b);
    TEST_ASSERT_TRUE(rc == ACTAG_OK || rc == 1);
    TEST_ASSERT_EQUAL_MEMORY(a, b, (size_t)cnt * sizeof(float));
    for (i = cnt * (int)sizeof(float); i < (int)sizeof b; i++) /* nothing stored past the reads */
        TEST_ASSERT_EQUAL_HEX8(0x5a, ((const uint8_t *)b)[i]);
    for (i = 0; lanes && i < cnt; i++)
        for (j = i + 1; j < cnt && j < i + 8; j++)
            TEST_ASSERT_TRUE(a[i] != a[j] || a[i] == 0.0f);
    return rc == 1;
}

static int cells_check(cells_hook hook, const uint8_t *img, int rows, int cols, int stride,
                       const float g[6], int k, float so, int what)
{
    return cells_check_lanes(hook, img, rows, cols, stride, g, k, so, what, 0);
}

/* Grids that leave the frame (the clamping SIMD sampler, the scalar reads'
 * choice of sampler per cell, fsample's edge replication): centred near
 * and beyond every edge and corner, across the whole frame, wholly outside; frames of 1..5 rows and columns allocated
 * to their last byte (an over-read shows under valgrind / ASan); sample
 * points on the last row and column exactly (quarter-pixel grids: x = cols - 1
 * where fsample's column pair degenerates); huge, infinite and NaN
 * coordinates. */
static long cells_equal_off_frame(cells_hook hook)
{
    static const int whats[7] = {0, 1, 2, 4, 5, 6, 7};
    static const float odd[6] = {1e30f, -1e30f, 3e9f, -3e9f, 0.0f, 0.0f};
    uint32_t s = 31415u;
    int trial, i, rows, cols;
    long served = 0;
    for (trial = 0; trial < TU_TRIALS(6000, 10); trial++) {
        int big = trial % 3 != 0, stride, k = 4 + (int)(lcg(&s) % 5u), what = whats[lcg(&s) % 7u];
        float cell, th, sh, so = unif(&s, 0.0f, 0.5f), g[6], ext;
        uint8_t *img;
        rows = big ? 20 + (int)(lcg(&s) % 100u) : 1 + (int)(lcg(&s) % 5u);
        cols = big ? 20 + (int)(lcg(&s) % 100u) : 1 + (int)(lcg(&s) % 5u);
        stride = cols + (int)(lcg(&s) % 4u);
        /* the last row ends the allocation at cols (no padding after it) */
        img = malloc((size_t)((rows - 1) * stride + cols));
        TEST_ASSERT_NOT_NULL(img);
        for (i = 0; i < (rows - 1) * stride + cols; i++)
            img[i] = (uint8_t)(lcg(&s) & 255u);
        cell = big ? unif(&s, 0.7f, 12.0f) : unif(&s, 0.05f, 2.0f);
        th = unif(&s, 0.0f, 6.2831853f);
        sh = unif(&s, -0.5f, 0.5f);
        g[2] = cell * cosf(th);
        g[3] = cell * sinf(th);
        g[4] = -cell * sinf(th) + sh * g[2];
        g[5] = cell * cosf(th) + sh * g[3];
        ext = cell * (float)(k + 3);
        switch (lcg(&s) % 4u) {
        case 0: /* anywhere from wholly outside to wholly inside */
            g[0] = unif(&s, -ext, (float)cols + ext);
            g[1] = unif(&s, -ext, (float)rows + ext);
            break;
        case 1: /* near a left or right edge */
            g[0] = (lcg(&s) & 1u) ? unif(&s, -3.0f, 3.0f) : unif(&s, (float)cols - 4.0f, (float)cols + 2.0f);
            g[1] = unif(&s, 0.0f, (float)rows);
            break;
        case 2: /* near a top or bottom edge */
            g[0] = unif(&s, 0.0f, (float)cols);
            g[1] = (lcg(&s) & 1u) ? unif(&s, -3.0f, 3.0f) : unif(&s, (float)rows - 4.0f, (float)rows + 2.0f);
            break;
        default: /* near a corner */
            g[0] = (lcg(&s) & 1u) ? unif(&s, -3.0f, 3.0f) : unif(&s, (float)cols - 4.0f, (float)cols + 2.0f);
            g[1] = (lcg(&s) & 1u) ? unif(&s, -3.0f, 3.0f) : unif(&s, (float)rows - 4.0f, (float)rows + 2.0f);
            break;
        }
        if (trial % 4 == 1) { /* quarter-pixel points, many on the last row / column */
            for (i = 0; i < 6; i++)
                g[i] = i == 3 || i == 4 ? 0.0f : floorf(g[i] * 4.0f) * 0.25f;
            so = (float)(lcg(&s) % 3u) * 0.25f;
        }
        if (trial % 50 == 7) { /* huge, infinite or NaN coordinates */
            g[0] = odd[lcg(&s) % 6u];
            g[1] = odd[lcg(&s) % 6u];
            i = (int)(lcg(&s) % 8u);
            if (i < 6)
                g[i] = i == 0 ? (float)NAN : i == 1 ? (float)INFINITY : i == 2 ? -(float)INFINITY : g[i] * 1e20f;
            if (lcg(&s) & 1u)
                g[(int)(lcg(&s) % 6u)] = (float)NAN;
        }
        served += cells_check(hook, img, rows, cols, stride, g, k, so, what);
        free(img);
    }
    return served;
}
/* The scalar reads (fcells_on, flattice: the Cortex-M path, hoisted
 * offsets and a sampler chosen per grid and per cell; on Cortex-M4/M7 the
 * DSP asm inside the frame) against the straightforward code, every sample
 * by the clamping sampler. */
static void test_scalar_cells_equal_straightforward(void)
{
    printf("scalar cell reads inside the frame: %s\n",
           actag__fit_dsp_reads() ? "Cortex-M DSP asm" : "portable C");
    cells_equal_big_frame(actag__fit_scalar_cells);
}

static void test_scalar_cells_equal_straightforward_off_frame(void)
{
    cells_equal_off_frame(actag__fit_scalar_cells);
}

#if ACTAG__FIT_SIMD
/* The x86-64 SSE2 cell reads (four cells a lane each) against the portable
 * scalar reads, on any processor (the hook keeps the AVX2 path off). */
static void test_simd_cells_equal_portable(void)
{
    printf("SSE2 cell reads (AVX2 path off) compared with the portable ones\n");
    cells_equal_big_frame(actag__fit_simd_cells);
}

static void test_simd_cells_equal_portable_off_frame(void)
{
    cells_equal_off_frame(actag__fit_simd_cells);
}

/* The reads as the decoder takes them on an AVX2 processor (eight cells a
 * lane each, grids inside the frame or leaving it; the lattice's SSE2
 * clamping sampler, and the SSE2 one of frames of a row or a column)
 * against the portable ones. */
static void test_avx2_cells_equal_portable(void)
{
    long served;
    if (!actag__fit_avx2_reads())
        TEST_IGNORE_MESSAGE("no AVX2 cell reads (compiled out, or not this processor)");
    served = cells_equal_big_frame(actag__fit_avx2_cells);
    printf("AVX2 cell reads compared with the portable ones: %ld of %d grids by the AVX2 path\n", served,
           TU_TRIALS(3000, 10));
    TEST_ASSERT_TRUE(served > TU_TRIALS(3000, 10) / 2);
}

static void test_avx2_cells_equal_portable_off_frame(void)
{
    long served;
    if (!actag__fit_avx2_reads())
        TEST_IGNORE_MESSAGE("no AVX2 cell reads (compiled out, or not this processor)");
    served = cells_equal_off_frame(actag__fit_avx2_cells);
    printf("AVX2 cell reads, grids leaving the frame: %ld of %d grids by the AVX2 path\n", served,
           TU_TRIALS(6000, 10));
    /* the cells (4 of the 7 whats) of frames of 2 rows and columns or more:
     * its clamping sampler (fsample8_cl), on every edge and corner */
    TEST_ASSERT_TRUE(served > TU_TRIALS(6000, 10) / 4);
}

/* Every lane of the AVX2 reads: grids inside frames of odd and even sizes
 * and strides (allocated to their last byte: a gather reading past it shows
 * under valgrind), anywhere inside and at the inside test's margin by each
 * edge and corner (fit_cells.c, fbox_inside: the farthest samples a pixel
 * inside), every `what`, k 4..8 (groups of eight cells ending in 1 to 8
 * used lanes), on random bytes, where every 8 consecutive cells read differ
 * (cells_check_lanes; but for the degenerate grids): a lane that read
 * another cell, or another lane order, fails the comparison. */
static void test_avx2_cells_every_lane(void)
{
    static const int whats[7] = {0, 1, 2, 4, 5, 6, 7};
    uint32_t s = 8191u;
    int trial, i, trials = TU_TRIALS(4000, 10);
    long served = 0;
    if (!actag__fit_avx2_reads())
        TEST_IGNORE_MESSAGE("no AVX2 cell reads (compiled out, or not this processor)");
    for (trial = 0; trial < trials; trial++) {
        int k = 4 + (int)(lcg(&s) % 5u), what = whats[lcg(&s) % 7u];
        int rows = 15 + (int)(lcg(&s) % 90u), cols = 15 + (int)(lcg(&s) % 90u);
        int stride = cols + (int)(lcg(&s) % 4u), bytes = (rows - 1) * stride + cols;
        float cell = unif(&s, 0.7f, 6.0f), th = unif(&s, 0.0f, 6.2831853f), sh = unif(&s, -0.4f, 0.4f);
        float so = unif(&s, 0.0f, 0.5f), h, ex, ey, d, g[6];
        /* every 8th grid degenerate (cells of 0 to 0.01 px) exactly at the
         * margin: its samples reach the frame's second last row and column
         * (x0 = cols - 2, y0 = rows - 2), the gathers' last bytes */
        int tiny = trial % 8 == 5;
        uint8_t *img = malloc((size_t)bytes);
        TEST_ASSERT_NOT_NULL(img);
        for (i = 0; i < bytes; i++)
            img[i] = (uint8_t)(lcg(&s) & 255u);
        /* the inside test's reach (fbox_inside's h: cells or lattice) */
        h = 0.5f * (float)(k + 1) + (what < 4 ? 0.0f : 1.0f) + so;
        if (tiny)
            cell = trial % 16 == 5 ? 0.0f : unif(&s, 0.0f, 0.01f);
        d = tiny ? 0.0f : 0.01f;
        for (;;) {
            g[2] = cell * cosf(th);
            g[3] = cell * sinf(th);
            g[4] = -cell * sinf(th) + sh * g[2];
            g[5] = cell * cosf(th) + sh * g[3];
            ex = (fabsf(g[2]) + fabsf(g[4])) * h;
            ey = (fabsf(g[3]) + fabsf(g[5])) * h;
            if (2.0f * ex < (float)cols - 3.1f && 2.0f * ey < (float)rows - 3.1f)
                break;
            cell *= 0.8f;
        }
        /* x and y each: anywhere inside, or at the margin by one edge */
        switch (lcg(&s) % 3u) {
        case 0:
            g[0] = unif(&s, 1.0f + ex, (float)(cols - 2) - ex);
            break;
        case 1:
            g[0] = 1.0f + ex + unif(&s, 0.0f, d);
            break;
        default:
            g[0] = (float)(cols - 2) - ex - unif(&s, 0.0f, d);
            break;
        }
        switch (lcg(&s) % 3u) {
        case 0:
            g[1] = unif(&s, 1.0f + ey, (float)(rows - 2) - ey);
            break;
        case 1:
            g[1] = 1.0f + ey + unif(&s, 0.0f, d);
            break;
        default:
            g[1] = (float)(rows - 2) - ey - unif(&s, 0.0f, d);
            break;
        }
        served += cells_check_lanes(actag__fit_avx2_cells, img, rows, cols, stride, g, k, so, what, !tiny);
        free(img);
    }
    printf("AVX2 lanes, grids inside odd frames: %ld of %d grids by the AVX2 path\n", served, trials);
    /* a few at the margin round to just outside (the clamping sampler) */
    TEST_ASSERT_TRUE(served > trials * 9 / 10);
}
#else
static void test_simd_cells_equal_portable(void)
{
    TEST_IGNORE_MESSAGE("no SIMD cell reads in this build");
}

static void test_simd_cells_equal_portable_off_frame(void)
{
    TEST_IGNORE_MESSAGE("no SIMD cell reads in this build");
}

static void test_avx2_cells_equal_portable(void)
{
    TEST_IGNORE_MESSAGE("no SIMD cell reads in this build");
}

static void test_avx2_cells_equal_portable_off_frame(void)
{
    TEST_IGNORE_MESSAGE("no SIMD cell reads in this build");
}

static void test_avx2_cells_every_lane(void)
{
    TEST_IGNORE_MESSAGE("no SIMD cell reads in this build");
}
#endif

/* The test's own bilinear sampler, in double: pixel centres on integers,
 * coordinates clamped to the frame, the edge pixel replicated. Written
 * apart from src/fit_cells.c, whose fsample the straightforward read
 * (`ref`) uses, so that a fault shared by every library path shows. */
static double brute_sample(const uint8_t *img, int rows, int cols, int stride, double x, double y)
{
    int x0, y0, x1, y1;
    double fx, fy, top, bot;
    x = x < 0.0 ? 0.0 : x > cols - 1 ? cols - 1 : x;
    y = y < 0.0 ? 0.0 : y > rows - 1 ? rows - 1 : y;
    x0 = (int)floor(x);
    y0 = (int)floor(y);
    x1 = x0 + 1 < cols ? x0 + 1 : x0;
    y1 = y0 + 1 < rows ? y0 + 1 : y0;
    fx = x - x0;
    fy = y - y0;
    top = img[y0 * stride + x0] * (1.0 - fx) + img[y0 * stride + x1] * fx;
    bot = img[y1 * stride + x0] * (1.0 - fx) + img[y1 * stride + x1] * fx;
    return top * (1.0 - fy) + bot * fy;
}

/* A coordinate in the decoder's fixed point (src/fit_cells.c): 1/256
 * pixel, truncated toward zero, clamped to +-2^20 pixels, NaN 0; in double,
 * where v * 256 and its truncation are exact. */
static double fix256(float v)
{
    double t = (double)v * 256.0;
    if (!(t >= -268435456.0))
        t = t < 0.0 ? -268435456.0 : 0.0;
    if (t > 268435456.0)
        t = 268435456.0;
    return t < 0.0 ? ceil(t) : floor(t);
}

/* Cell (cx, cy) of the (k+1)^2 grid g: the mean of the 3 x 3 pattern at
 * +-so cell (nine) or of the centre and the four diagonal points (five),
 * at the decoder's sample points: the centre as the decoder computes it in
 * float ((m + a u0) + b v0), the pattern's offsets (so along each axis, or
 * so along a +- b for five) in float, each in fixed point, the sample at
 * centre + offsets. */
static double brute_cell(const uint8_t *img, int rows, int cols, int stride, const float g[6],
                         int k, float so, int cx, int cy, int five)
{
    float h = 0.5f * (float)(k + 1), u = (float)cx + 0.5f - h, v = (float)cy + 0.5f - h;
    float xc = g[0] + g[2] * u, yc = g[1] + g[3] * u;
    double X, Y, s = 0.0;
    int a, b;
    xc = xc + g[4] * v;
    yc = yc + g[5] * v;
    X = fix256(xc);
    Y = fix256(yc);
    if (five) {
        static const int du[5] = {0, 1, -1, 1, -1}, dv[5] = {0, 1, -1, -1, 1};
        double d1x = fix256(so * (g[2] + g[4])), d1y = fix256(so * (g[3] + g[5]));
        double d2x = fix256(so * (g[2] - g[4])), d2y = fix256(so * (g[3] - g[5]));
        for (a = 0; a < 5; a++) {
            double ox = du[a] == dv[a] ? du[a] * d1x : du[a] * d2x;
            double oy = du[a] == dv[a] ? du[a] * d1y : du[a] * d2y;
            s += brute_sample(img, rows, cols, stride, (X + ox) / 256.0, (Y + oy) / 256.0);
        }
        return s / 5.0;
    }
    for (b = -1; b <= 1; b++)
        for (a = -1; a <= 1; a++)
            s += brute_sample(img, rows, cols, stride,
                              (X + a * fix256(g[2] * so) + b * fix256(g[4] * so)) / 256.0,
                              (Y + a * fix256(g[3] * so) + b * fix256(g[5] * so)) / 256.0);
    return s / 9.0;
}

/* Every cell read (9 and 5 samples, grids inside, across and beyond the
 * frame's edges, small frames) against brute_cell, within 0.001 grey levels
 * (the float rounding of a cell mean). */
static void test_cells_equal_brute_force(void)
{
    uint32_t s = 2718u;
    int trial, worst_trial = -1;
    double worst = 0.0;
    for (trial = 0; trial < TU_TRIALS(3000, 10); trial++) {
        int small = trial % 4 == 0, k = 4 + (int)(lcg(&s) % 5u), what = (int)(lcg(&s) % 2u);
        int rows = small ? 1 + (int)(lcg(&s) % 6u) : 20 + (int)(lcg(&s) % 80u);
        int cols = small ? 1 + (int)(lcg(&s) % 6u) : 20 + (int)(lcg(&s) % 80u);
        int stride = cols + (int)(lcg(&s) % 4u), n = k + 1, i, cx, cy;
        float cell = unif(&s, 1.0f, 8.0f), th = unif(&s, 0.0f, 6.2832f), sh = unif(&s, -0.4f, 0.4f);
        float so = unif(&s, 0.0f, 0.5f), g[6], ref[81], got[81];
        uint8_t *img = (uint8_t *)malloc((size_t)rows * (size_t)stride);
        TEST_ASSERT_NOT_NULL(img);
        for (i = 0; i < rows * stride; i++)
            img[i] = (uint8_t)(lcg(&s) & 255u);
        g[0] = unif(&s, -10.0f, (float)cols + 10.0f); /* centres in, at and beyond the edges */
        g[1] = unif(&s, -10.0f, (float)rows + 10.0f);
        g[2] = cell * cosf(th);
        g[3] = cell * sinf(th);
        g[4] = cell * (-sinf(th) + sh * cosf(th));
        g[5] = cell * (cosf(th) + sh * sinf(th));
        TEST_ASSERT_EQUAL_INT(ACTAG_OK,
                              actag__fit_scalar_cells(img, rows, cols, stride, g, k, so, what, ref, got));
        for (cy = 0; cy < n; cy++)
            for (cx = 0; cx < n; cx++) {
                double b = brute_cell(img, rows, cols, stride, g, k, so, cx, cy, what == 1);
                double d1 = fabs(b - ref[cy * n + cx]), d2 = fabs(b - got[cy * n + cx]);
                double d = d1 > d2 ? d1 : d2;
                if (d > worst) {
                    worst = d;
                    worst_trial = trial;
                }
            }
        free(img);
    }
    printf("cell reads against the double-precision brute force: worst %.4g grey levels (trial %d)\n",
           worst, worst_trial);
    TEST_ASSERT_TRUE(worst < 0.001);
}

static void test_lattice_hook_rejects_bad_arguments(void)
{
    static uint8_t img[R * C];
    float g[6] = {60.0f, 48.0f, 4.0f, 0.0f, 0.0f, 4.0f}, a[81], b[81];
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag__fit_shift_cells(img, R, C, C, g, 9, 0.2f, 0, 0, a, b));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag__fit_shift_cells(img, R, C, C, g, 6, 0.2f, 3, 0, a, b));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag__fit_shift_cells(img, R, C, C, g, 6, 0.2f, 0, -3, a, b));
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag__fit_scalar_cells(img, R, C, C, g, 6, 0.2f, 0, a, b));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag__fit_scalar_cells(img, R, C, C, g, 6, 0.2f, 3, a, b));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag__fit_scalar_cells(img, R, C, C, g, 9, 0.2f, 0, a, b));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag__fit_scalar_cells(img, R, C, C - 1, g, 6, 0.2f, 0, a, b));
#if ACTAG__FIT_SIMD
    {
        float far[6] = {3.0f, 48.0f, 4.0f, 0.0f, 0.0f, 4.0f}; /* crosses the left edge: served */
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag__fit_simd_cells(img, R, C, C, g, 6, 0.2f, 0, a, b));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag__fit_simd_cells(img, R, C, C, g, 6, 0.2f, 3, a, b));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag__fit_simd_cells(img, R, C, C, g, 9, 0.2f, 0, a, b));
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag__fit_simd_cells(img, R, C, C, far, 6, 0.2f, 0, a, b));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag__fit_simd_cells(img, R, C, 0, g, 6, 0.2f, 0, a, b));
    }
#endif
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_lattice_equals_direct_inside);
    RUN_TEST(test_lattice_equals_direct_at_edges);
    RUN_TEST(test_lattice_exact_on_pixel_grid);
    RUN_TEST(test_scalar_cells_equal_straightforward);
    RUN_TEST(test_scalar_cells_equal_straightforward_off_frame);
    RUN_TEST(test_simd_cells_equal_portable);
    RUN_TEST(test_simd_cells_equal_portable_off_frame);
    RUN_TEST(test_avx2_cells_equal_portable);
    RUN_TEST(test_avx2_cells_equal_portable_off_frame);
    RUN_TEST(test_avx2_cells_every_lane);
    RUN_TEST(test_cells_equal_brute_force);
    RUN_TEST(test_lattice_hook_rejects_bad_arguments);
    return UNITY_END();
}
