/* Tests for actag_median_filter against a brute-force reference. */
/* first: whether the library has and takes the AVX2 path (printed), before
 * the portable copy below defines ACTAG_NO_SIMD */
#include "../src/cpu_x86.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "actag/median.h"
#include "unity.h"
#include "test_util.h"
#include "filter_check.h"
#include "../src/frame16.h" /* actag__median_filter16_max, the library's */
#include "../src/median_bands.h" /* the radius bands, the library's */

/* The library's filter without its AVX2 path (median_sse2_copy.c): on an
 * x86-64 processor with AVX2 the library takes median_rows32 (median_net32
 * at R = 4) and this copy median_rows16 (median_net16 at R = 4); elsewhere
 * both take the same path. */
int actag_median_filter_sse2(const uint8_t *src, int rows, int cols, int src_stride,
                             uint8_t *dst, int dst_stride, int radius, void *scratch,
                             size_t scratch_size);
int actag_median_filter16_sse2(const void *src, int rows, int cols, int src_stride,
                               uint8_t *dst, int dst_stride, int radius, void *scratch,
                               size_t scratch_size);
int actag__median_filter16_max_sse2(const void *src, uint32_t max16, int rows, int cols,
                                    int src_stride, uint8_t *dst, int dst_stride, int radius,
                                    void *scratch, size_t scratch_size);
int actag_median_filter_inplace_sse2(void *frame, int depth, int rows, int cols, int stride,
                                     uint32_t max16, int radius, void *scratch,
                                     size_t scratch_size);
int actag__median_filter_bands_sse2(const void *src, int depth, uint32_t max16, int rows,
                                    int cols, int src_stride, uint8_t *dst, int dst_stride,
                                    const actag__median_bands *b, void *scratch,
                                    size_t scratch_size);
int actag__median_filter_inplace_bands_sse2(void *frame, int depth, int rows, int cols,
                                            int stride, uint32_t max16,
                                            const actag__median_bands *b, void *scratch,
                                            size_t scratch_size);

/* The portable (non-SIMD) code path, compiled into this test under another
 * name so that both paths are checked on any machine: without SSE2 on
 * x86-64, without the DSP instructions (median_quad_dsp) on Cortex-M4/M7. */
int actag_median_filter_portable(const uint8_t *src, int rows, int cols, int src_stride,
                                 uint8_t *dst, int dst_stride, int radius,
                                 void *scratch, size_t scratch_size);
#define ACTAG_NO_SIMD 1
#define ACTAG_NO_DSP 1
int actag_median_filter16_portable(const void *src, int rows, int cols, int src_stride,
                                   uint8_t *dst, int dst_stride, int radius, void *scratch,
                                   size_t scratch_size);
int actag__median_filter16_max_portable(const void *src, uint32_t max16, int rows, int cols,
                                        int src_stride, uint8_t *dst, int dst_stride, int radius,
                                        void *scratch, size_t scratch_size);
#define actag_median_filter actag_median_filter_portable
#define actag_median_filter16 actag_median_filter16_portable
#define actag__median_filter16_max actag__median_filter16_max_portable
int actag_median_filter_inplace_portable(void *frame, int depth, int rows, int cols, int stride,
                                         uint32_t max16, int radius, void *scratch,
                                         size_t scratch_size);
#define actag_median_filter_inplace actag_median_filter_inplace_portable
int actag__median_filter_bands_portable(const void *src, int depth, uint32_t max16, int rows,
                                        int cols, int src_stride, uint8_t *dst, int dst_stride,
                                        const actag__median_bands *b, void *scratch,
                                        size_t scratch_size);
int actag__median_filter_inplace_bands_portable(void *frame, int depth, int rows, int cols,
                                                int stride, uint32_t max16,
                                                const actag__median_bands *b, void *scratch,
                                                size_t scratch_size);
#define actag__median_filter_bands actag__median_filter_bands_portable
#define actag__median_filter_inplace_bands actag__median_filter_inplace_bands_portable
#include "../src/median.c"
#undef actag__median_filter_bands
#undef actag__median_filter_inplace_bands
#undef actag_median_filter
#undef actag_median_filter16
#undef actag__median_filter16_max
#undef actag_median_filter_inplace

typedef int (*median_fn)(const uint8_t *, int, int, int, uint8_t *, int, int, void *, size_t);

/* The paths every check runs: the library (AVX2 where it may), the same
 * without AVX2, the portable C. */
#define NPATHS 3
static const median_fn FNS[NPATHS] = {actag_median_filter, actag_median_filter_sse2,
                                      actag_median_filter_portable};
static const char *const FN_NAMES[NPATHS] = {"library", "sse2", "portable"};

void setUp(void) {}
void tearDown(void) {}

/* ------------------------------------------------------------ helpers */

/* Reference: histogram of the clamped window, then the middle element. */
static void brute_median(const uint8_t *src, int rows, int cols, int stride, int R, uint8_t *out,
                         int ostride)
{
    int i, j, a, b;
    long n = (long)(2 * R + 1) * (2 * R + 1);
    for (i = 0; i < rows; i++) {
        for (j = 0; j < cols; j++) {
            long hist[256];
            long cum = 0;
            int v;
            memset(hist, 0, sizeof hist);
            for (a = -R; a <= R; a++) {
                const uint8_t *row = src + (size_t)clamp(i + a, 0, rows - 1) * (size_t)stride;
                for (b = -R; b <= R; b++)
                    hist[row[clamp(j + b, 0, cols - 1)]]++;
            }
            for (v = 0; v < 256; v++) {
                cum += hist[v];
                if (cum > n / 2)
                    break;
            }
            out[(size_t)i * (size_t)ostride + (size_t)j] = (uint8_t)v;
        }
    }
}

enum { FILL_ONEBIN = FC_FILL_OWN, FILL_TWOBINS, FILL_GRADIENT, FILL_BLOBS, FILL_N };

/* Drawn for each image before its pixels: a coarse bin, two levels. */
static void own_draws(int v[4])
{
    v[0] = rnd_range(0, 15) * 16;
    v[1] = rnd_range(0, 255);
    v[2] = rnd_range(0, 255);
}

static uint8_t own_pixel(int kind, int i, int j, const int v[4])
{
    switch (kind) {
    case FILL_ONEBIN: return (uint8_t)(v[0] + (int)(rnd() & 15u));
    case FILL_TWOBINS: return (uint8_t)((rnd() & 1u) ? v[1] : v[2]);
    case FILL_GRADIENT: return (uint8_t)((i * 7 + j * 3 + (int)(rnd() % 5u)) & 255);
    case FILL_BLOBS:
        /* Dark speckle with bright patches: sonar-like. */
        return (uint8_t)(((i / 5 + j / 7) % 3 == 0) ? 150 + (int)(rnd() % 100u) : (int)(rnd() % 40u));
    default: return (uint8_t)rnd();
    }
}

/* Bytes given to the filters beyond ACTAG_MEDIAN_SCRATCH_SIZE by
 * fc_check_image (more scratch: more column histograms, wider strips). */
static size_t scratch_extra;

static int run_path(int path, const uint8_t *src, int rows, int cols, int sstride, uint8_t *dst,
                    int dstride, int R, int offset, void *scratch, size_t scratch_size)
{
    (void)offset; /* the median filter takes none */
    return FNS[path](src, rows, cols, sstride, dst, dstride, R, scratch, scratch_size);
}

static void reference(const uint8_t *src, int rows, int cols, int stride, int R, int offset,
                      uint8_t *out, int ostride)
{
    (void)offset;
    brute_median(src, rows, cols, stride, R, out, ostride);
}

static size_t scratch_size(int rows, int cols, int R)
{
    (void)rows; /* the size depends on the width only */
    (void)R;
    return ACTAG_MEDIAN_SCRATCH_SIZE(rows, cols) + scratch_extra;
}

/* Every path against the brute-force reference, with scratch_extra bytes of
 * scratch beyond ACTAG_MEDIAN_SCRATCH_SIZE; images and cases through
 * fc_fill, fc_check_image and fc_check_case (filter_check.h). */
static const fc_filter FILTER = {
    .npaths = NPATHS, .names = FN_NAMES, .run = run_path, .reference = reference,
    .scratch_size = scratch_size, .nkinds = FILL_N, .own_draws = own_draws, .own_pixel = own_pixel};

/* One case: an image of fill kind (row stride cols + sextra) through
 * fc_check_image. */
static void check_case(int rows, int cols, int R, int kind, int sextra, int dextra)
{
    fc_check_case(&FILTER, rows, cols, R, 0, kind, sextra, dextra);
}

/* ------------------------------------------------------------ tests */

static void test_partial_row_blocks(void)
{
    /* The portable path works on blocks of four output rows: every row
     * count 1..13 (blocks of 1, 2, 3 and 4 rows at the bottom) at every
     * radius 1..8 and several fills, with and without padding. */
    int rows, R;
    rng_state = 0x51DEu;
    for (rows = 1; rows <= 13; rows++)
        for (R = 1; R <= 8; R++) {
            int cols = rnd_range(1, 45);
            int kind = (int)(rnd() % FILL_N);
            check_case(rows, cols, R, kind, (rows + R) & 3, R & 1);
        }
}

static void test_constant_and_extreme_images(void)
{
    /* All-equal images (0, 255 and a middle level): the median is that
     * level; images of only 0 and 255 in stripes and checkerboards, where
     * the median jumps between the extremes from one pixel to the next. */
    static const int levels[] = {0, 255, 128};
    static const int shapes[][2] = {{1, 1}, {1, 37}, {37, 1}, {2, 50}, {50, 2}, {23, 31}, {64, 64}};
    static const int radii[] = {0, 1, 2, 3, 4, 5, 7, 8, 9, 16, 127};
    uint8_t *img = (uint8_t *)fc_alloc(64u * 80u);
    size_t a, b, r;
    int i, j;
    for (a = 0; a < sizeof shapes / sizeof shapes[0]; a++) {
        int rows = shapes[a][0], cols = shapes[a][1], sstride = cols + 7;
        for (r = 0; r < sizeof radii / sizeof radii[0]; r++) {
            int R = radii[r];
            /* emulated: the 255 x 255 brute-force windows on the small shapes only */
            if (TU_EMULATED && R > 64 && rows * cols > 100)
                continue;
            for (b = 0; b < 3; b++) {
                fc_fill_constant(img, rows, cols, sstride, levels[b]);
                fc_check_image(&FILTER, img, rows, cols, sstride, R, 0, 3, "constant");
            }
            for (b = 0; b < 4; b++) {
                for (i = 0; i < rows; i++)
                    for (j = 0; j < sstride; j++) {
                        int on;
                        switch (b) {
                        case 0: on = (j / (R + 1)) & 1; break;          /* vertical stripes */
                        case 1: on = (i / (R + 1)) & 1; break;          /* horizontal stripes */
                        case 2: on = (i + j) & 1; break;                /* checkerboard */
                        default: on = ((i / 3) + (j / 5)) % 3 == 0; break; /* blocks */
                        }
                        img[(size_t)i * (size_t)sstride + (size_t)j] = on ? 255 : 0;
                    }
                fc_check_image(&FILTER, img, rows, cols, sstride, R, 0, 0, "0/255 pattern");
            }
        }
    }
    free(img);
}

static void test_wide_strides(void)
{
    static const int radii[6] = {0, 1, 4, 7, 8, 20};
    fc_test_wide_strides(&FILTER, 0xD00Du, 24, radii);
}

static void test_every_small_radius_random(void)
{
    /* Every radius 0..15 on random images with random sizes (the portable
     * path's four-row histogram covers 1..7, the constant-time one above). */
    int R, t;
    rng_state = 0x7E57u;
    for (R = 0; R <= 15; R++)
        for (t = 0; t < 6; t++) {
            int rows = rnd_range(1, 60), cols = rnd_range(1, 60);
            int kind = t < 3 ? FILL_UNIFORM : (int)(rnd() % FILL_N);
            check_case(rows, cols, R, kind, t & 1 ? 3 : 0, t & 2 ? 2 : 0);
        }
}

static void test_every_width_small_radii(void)
{
    /* The SSE2 path at R <= 7 (8-bit kernel histograms, median_strip8)
     * cuts each row into runs by where the entering and the leaving
     * column stop being clamped (j = cols - 1 - R and j = R + 1): every
     * width from 1 to 2R + 20 (runs empty, overlapping, one pixel long,
     * all three) at R = 1..8, with fills that move the median across
     * coarse bins, at row counts below and above 2R + 1. */
    int R, cols;
    rng_state = 0xC015u;
    for (R = 1; R <= 8; R++)
        for (cols = 1; cols <= 2 * R + 20; cols++) {
            int rows = (cols & 1) ? rnd_range(1, 2 * R) : rnd_range(2 * R + 1, 2 * R + 9);
            int kind = cols % 3 == 0 ? FILL_UNIFORM : (int)(rnd() % FILL_N);
            check_case(rows, cols, R, kind, cols & 3, (cols >> 2) & 1);
        }
}

static void test_sixteen_row_blocks(void)
{
    /* The SSE2 path at R <= 7 filters blocks of 16 output rows (a 16-lane
     * histogram; rows not a multiple of 16 leave a partial block) and
     * writes the medians through 16 x 16 transposes (columns not a
     * multiple of 16 leave a partial group): every row count 1..40 and
     * every width 1..70 at every radius 1..7, the other size random,
     * random fills, strides beyond cols on both sides. */
    int n, R, step = TU_EMULATED ? 5 : 1;
    rng_state = 0x16B0u;
    for (R = 1; R <= 7; R++) {
        for (n = 1; n <= 40; n += step) {
            int cols = rnd_range(1, 70);
            int kind = (int)(rnd() % FILL_N);
            check_case(n, cols, R, kind, n & 1 ? rnd_range(1, 20) : 0, n & 2 ? 3 : 0);
        }
        for (n = 1; n <= 70; n += step) {
            int rows = rnd_range(1, 40);
            int kind = n % 3 == 0 ? FILL_UNIFORM : (int)(rnd() % FILL_N);
            check_case(rows, n, R, kind, n & 2 ? rnd_range(1, 20) : 0, n & 1 ? 5 : 0);
        }
    }
}

static void test_eight_row_blocks(void)
{
    /* Cortex-M DSP path at R = 3..7: blocks of eight output rows where
     * their 2R+8 source rows are inside the frame, four-row blocks at the
     * top and bottom. Row counts from 2R+7 (no eight-row block) to 2R+26
     * (several, then 0-3 and 4-7 rows left for the four-row blocks), widths
     * from 1 (every column clamped on both sides) past 2R+2, all fills
     * (constant, binary, random, ...), with and without padding. */
    int R, extra, w;
    rng_state = 0x0C7Au;
    for (R = 1; R <= 7; R++)
        for (extra = 0; extra <= 19; extra += TU_EMULATED ? 3 : 1)
            for (w = 0; w < 4; w++) {
                static const int fixed[3] = {1, 2, 3};
                int rows = 2 * R + 7 + extra;
                int cols = w < 3 ? fixed[w] + (w == 2 ? 2 * R : 0) : rnd_range(R + 1, 48);
                int kind = (extra + w) % FILL_N;
                check_case(rows, cols, R, kind, w & 1 ? rnd_range(1, 9) : 0, extra & 1 ? 3 : 0);
            }
}

static void test_far_apart_medians(void)
{
    /* Windows of one 16-row block whose medians lie far apart (bright and
     * dark bands across the rows, checkerboards whose cells swap the
     * bands' medians from column to column, several levels of bands):
     * the SSE2 path's scans then split the block's rows into two groups,
     * the high one scanned down from its highest median, and regroup them
     * when they change sides. Bands of every height 1..9 at R = 1..7. */
    static const uint8_t levels4[4] = {0, 85, 170, 255};
    int R, band, shape;
    uint8_t *img = (uint8_t *)fc_alloc(48u * 90u);
    rng_state = 0xFA2Au;
    for (R = 1; R <= 7; R++)
        for (band = 1; band <= 9; band += TU_EMULATED ? 4 : 1)
            for (shape = 0; shape < 5; shape++) {
                int rows = rnd_range(17, 48), cols = rnd_range(20, 80), sstride = cols + 3;
                int i, j;
                for (i = 0; i < rows; i++)
                    for (j = 0; j < sstride; j++) {
                        int v;
                        switch (shape) {
                        case 0: v = ((i / band) & 1) ? 255 : 0; break; /* bands */
                        case 1: v = (((i / band) + (j / (R + band))) & 1) ? 255 : 0; break;
                        case 2: v = levels4[(i / band) % 4] ^ (int)(rnd() & 3u); break;
                        case 3: /* dark noise and bright noise bands */
                            v = ((i / band) & 1) ? 200 + (int)(rnd() % 56u) : (int)(rnd() % 30u);
                            break;
                        default: /* bands that end part way along the row */
                            v = ((i / band) & 1) && j < cols / 2 ? 250 : (j * 3) & 31;
                            break;
                        }
                        img[(size_t)i * (size_t)sstride + (size_t)j] = (uint8_t)v;
                    }
                fc_check_image(&FILTER, img, rows, cols, sstride, R, 0, 2, "far-apart medians");
            }
    free(img);
}

static void test_random_images(void)
{
    static const int radii[] = {0, 1, 2, 3, 4, 5, 8};
    fc_test_random_images(&FILTER, 0x12345678u, 300, 40, radii, 7, 20);
}

static void test_value_patterns(void)
{
    /* Every fill (constant, only 0/255, one coarse bin, two levels, ...) at
     * the radii the detector uses; these steer the median through the
     * lazy fine-histogram paths (same bin, catch-up, rebuild). */
    int kind, R;
    rng_state = 0xBEEFu;
    for (kind = 0; kind < FILL_N; kind++)
        for (R = 0; R <= 9; R++) {
            int rows = rnd_range(10, 30); /* one PRNG call per statement: */
            int cols = rnd_range(10, 60); /* argument order is unspecified */
            check_case(rows, cols, R, kind, 3, 5);
        }
}

static void test_thin_images(void)
{
    static const int radii[] = {0, 1, 2, 4, 8, 33, 127};
    int r, n;
    rng_state = 777u;
    for (r = 0; r < 7; r++) {
        check_case(1, 1, radii[r], FILL_UNIFORM, 0, 0);
        check_case(1, 1, radii[r], FILL_UNIFORM, 5, 5);
        for (n = 2; n <= 40; n += 19) {
            check_case(1, n, radii[r], FILL_UNIFORM, 2, 1);
            check_case(n, 1, radii[r], FILL_UNIFORM, 1, 2);
            check_case(2, n, radii[r], (int)(rnd() % FILL_N), 0, 0);
            check_case(n, 2, radii[r], (int)(rnd() % FILL_N), 0, 0);
        }
    }
}

static void test_radius_beyond_image(void)
{
    int t;
    rng_state = 4242u;
    for (t = 0; t < 12; t++) {
        int rows = rnd_range(1, 9), cols = rnd_range(1, 9);
        int R = rnd_range(10, ACTAG_MEDIAN_MAX_RADIUS);
        check_case(rows, cols, R, (int)(rnd() % FILL_N), t & 3, (t >> 2) & 3);
    }
    check_case(3, 4, ACTAG_MEDIAN_MAX_RADIUS, FILL_UNIFORM, 1, 1);
    check_case(5, 5, ACTAG_MEDIAN_MAX_RADIUS, FILL_BINARY, 0, 0);
}

static void test_wide_and_tall(void)
{
    /* Long rows: many kernel steps per row, so parked fine histograms get
     * caught up over long and short gaps; large radii on wider images. */
    rng_state = 99u;
    check_case(6, 700, 4, FILL_BLOBS, 3, 0);
    check_case(6, 700, 4, FILL_TWOBINS, 0, 3);
    check_case(5, 600, 40, FILL_UNIFORM, 0, 0);
    check_case(4, 300, ACTAG_MEDIAN_MAX_RADIUS, FILL_BLOBS, 1, 1);
    check_case(300, 5, 40, FILL_GRADIENT, 1, 1);
    check_case(60, 70, 16, FILL_BLOBS, 7, 9);
}

static void test_max_counts(void)
{
    /* R = 127 on a constant image: every column counter reaches 255 and the
     * kernel counters 65025, the documented limits. */
    int t;
    rng_state = 31337u;
    for (t = 0; t < 3; t++) {
        int rows = rnd_range(1, 6); /* one PRNG call per statement */
        int cols = rnd_range(1, 6);
        check_case(rows, cols, ACTAG_MEDIAN_MAX_RADIUS, FILL_CONST, 0, 0);
    }
    check_case(1, 1, ACTAG_MEDIAN_MAX_RADIUS, FILL_CONST, 0, 0);
}


/* ------------------------------------------------------------ strips
 * Frames wider than the H column histograms the scratch holds (H = 256 at
 * the minimum size) are filtered in vertical strips (median.c:
 * median_core). For R < 64 (at H = 256) a strip's histograms cover it and
 * R + 1 columns left, R right: the first strip is H - R columns wide, the
 * others H - 2R - 1, the last the one whose columns hb = s0 - R - 1 ..
 * cols - 1 all fit. For larger R (H / 2 > H - 2R - 1) strips are H / 2
 * wide, the columns that every window of the strip covers summed in one
 * histogram (median_strip_agg). The SSE2 path uses the strips at every
 * R >= 1, the portable one at R >= 8 (and for 16-bit frames too wide for
 * its 4-row ring). */

/* Number of strips for cols columns (the same rule as median_core). */
static int strip_count(int cols, int R, int hcap)
{
    int s0 = 0, s1, n = 0;
    if (cols <= hcap)
        return 1;
    if (hcap / 2 > hcap - 2 * R - 1)
        return (cols + hcap / 2 - 1) / (hcap / 2);
    for (; s0 < cols; s0 = s1, n++) {
        int hb = s0 - R - 1 > 0 ? s0 - R - 1 : 0;
        s1 = cols - hb <= hcap ? cols : hb + hcap - R;
    }
    return n;
}

/* The largest width that needs at most n strips. */
static int strip_threshold(int n, int R, int hcap)
{
    int cols = 1;
    while (strip_count(cols + 1, R, hcap) <= n)
        cols++;
    return cols;
}

static void test_strip_boundaries(void)
{
    /* Widths at each strip threshold -1, 0, +1 (one more strip past each),
     * radii of both paths, fills that move the median across coarse bins
     * (the lazy fine histograms restart at each strip), odd strides. */
    static const int radii[] = {1, 4, 7, 8, 13};
    size_t r;
    int k, d;
    rng_state = 0x5781Bu;
    for (r = 0; r < sizeof radii / sizeof radii[0]; r++) {
        int R = radii[r];
        for (k = 1; k <= 3; k++) {
            int T = strip_threshold(k, R, ACTAG_MEDIAN_HIST_COLS);
            for (d = -1; d <= 1; d++) {
                int kind = d == 0 ? FILL_UNIFORM : (d < 0 ? FILL_BLOBS : FILL_TWOBINS);
                check_case(2 * R + 3, T + d, R, kind, d & 1, 1);
            }
        }
    }
    TEST_ASSERT_EQUAL_INT(256, strip_threshold(1, 4, 256));
    TEST_ASSERT_EQUAL_INT(503, strip_threshold(2, 4, 256));
}

static void test_large_radius_strips(void)
{
    /* Large radii: R = 63, the narrowest strips of the first kind (129
     * columns), and R >= 64, strips of 128 columns with the shared columns
     * summed (at R = 127 all but 2 of a window's 255 columns), so most
     * windows span several strips and reach both edges' clamping in some
     * rows. Fills that move the median across coarse bins at these radii
     * (gradients, blobs) as well as uniform noise. */
    static const int radii[] = {63, 64, 100, 127};
    size_t r;
    int k;
    rng_state = 0xA77u;
    for (r = 0; r < sizeof radii / sizeof radii[0]; r++) {
        int R = radii[r];
        int rows = TU_EMULATED ? 2 : 3;
        for (k = 1; k <= (TU_EMULATED ? 1 : 2); k++) {
            int T = strip_threshold(k, R, ACTAG_MEDIAN_HIST_COLS);
            check_case(rows, T, R, FILL_GRADIENT, 1, 0);
            check_case(rows, T + 1, R, k == 1 ? FILL_BLOBS : FILL_UNIFORM, 0, 3);
        }
    }
    if (!TU_EMULATED) {
        check_case(2 * 64 + 5, 260, 64, FILL_GRADIENT, 0, 0); /* rows slide too */
        check_case(7, 385, 127, FILL_BLOBS, 0, 0);            /* last strip 1 column */
    }
    TEST_ASSERT_EQUAL_INT(384, strip_threshold(3, 127, 256));
    TEST_ASSERT_EQUAL_INT(2 * 256 - 2 * 63 - 1, strip_threshold(2, 63, 256));
}

static void test_strips_with_more_scratch(void)
{
    /* Scratch beyond the minimum buys more column histograms: other strip
     * widths, the same output (including one strip for the whole frame). */
    static const size_t extra[] = {1, 271, 272, 272 * 7 + 5, 272 * 300};
    size_t e;
    rng_state = 0x3C3Cu;
    for (e = 0; e < sizeof extra / sizeof extra[0]; e++) {
        scratch_extra = extra[e];
        check_case(11, 530, 4, FILL_BLOBS, 1, 2);
        check_case(19, 541, 9, FILL_UNIFORM, 0, 0);
        if (!TU_EMULATED)
            check_case(3, 541, 90, FILL_GRADIENT, 0, 0);
    }
    scratch_extra = 0;
}

static void test_strips_real_frame_wide(void)
{
    /* A pool frame side by side with its mirror image (530 x 1024, 5
     * strips at R = 4): bit-identical to the brute force. */
    int rows, cols, i, j;
    uint8_t *img = tu_read_pgm(TU_DATA "/pool-video/f_0001.pgm", &rows, &cols);
    uint8_t *wide;
    int wr = TU_EMULATED ? 40 : rows;
    TEST_ASSERT_NOT_NULL(img);
    wide = (uint8_t *)fc_alloc((size_t)wr * (size_t)cols * 2u + 3u);
    for (i = 0; i < wr; i++)
        for (j = 0; j < cols; j++) {
            uint8_t v = img[(size_t)(i + (rows - wr) / 2) * (size_t)cols + (size_t)j];
            wide[(size_t)i * (size_t)cols * 2u + (size_t)j] = v;
            wide[(size_t)i * (size_t)cols * 2u + (size_t)(2 * cols - 1 - j)] = v;
        }
    TEST_ASSERT_EQUAL_INT(5, strip_count(2 * cols, 4, ACTAG_MEDIAN_HIST_COLS));
    fc_check_image(&FILTER, wide, wr, 2 * cols - 1, 2 * cols, 4, 0, 1, "mirrored pool frame");
    free(wide);
    free(img);
}

static void test_real_sonar_frame(void)
{
    /* A full 530 x 512 pool frame at the paper's radius 4. */
    int rows, cols;
    uint8_t *img = tu_read_pgm(TU_DATA "/pool-video/f_0001.pgm", &rows, &cols);
    scratch_extra = 0; /* the exact scratch size */
    fc_check_image(&FILTER, img, rows, cols, cols, 4, 0, 0, "pool frame f_0001");
    free(img);
}

/* 16-bit frames: actag_median_filter16 (library and portable) against the
 * documented scaling, v8 = (v * 255 + max / 2) / max by division, followed
 * by the brute-force median; odd addresses, strides in samples, widths
 * around the ring's and the histograms' sizes, radii of both paths. */
typedef int (*median16_fn)(const void *, int, int, int, uint8_t *, int, int, void *, size_t);
typedef int (*median16max_fn)(const void *, uint32_t, int, int, int, uint8_t *, int, int, void *,
                               size_t);

/* rowwise: samples near 97 r (mod maxv + 1) in row r instead of uniform,
 * so that neighbouring output rows have different medians. */
static void check16_rows(int rows, int cols, int R, uint32_t maxv, int sextra, int rowwise)
{
    static const median16_fn F16[NPATHS] = {actag_median_filter16, actag_median_filter16_sse2,
                                            actag_median_filter16_portable};
    int stride = cols + sextra, f, r, c;
    size_t n = (size_t)rows * (size_t)stride, scr = ACTAG_MEDIAN_SCRATCH_SIZE(rows, cols);
    uint8_t *raw = (uint8_t *)malloc(2u * n + 1u), *src = raw + 1; /* odd address */
    /* calloc: GCC cannot prove the scaling loop below writes every byte */
    uint8_t *s8 = (uint8_t *)calloc((size_t)rows * (size_t)cols, 1);
    uint8_t *want = (uint8_t *)malloc((size_t)rows * (size_t)cols);
    uint8_t *out = (uint8_t *)malloc((size_t)rows * (size_t)cols);
    uint8_t *scratch = (uint8_t *)malloc(scr);
    uint32_t mx = 0;
    char msg[160];
    TEST_ASSERT_TRUE(raw && s8 && want && out && scratch);
    for (r = 0; r < rows; r++)
        for (c = 0; c < stride; c++) {
            uint16_t v = (uint16_t)(maxv ? rnd() % (maxv + 1u) : 0u);
            if (rowwise)
                v = (uint16_t)(((uint32_t)r * 97u + v % 13u) % (maxv + 1u));
            if (c < cols && v > mx)
                mx = v;
            memcpy(src + 2u * ((size_t)r * (size_t)stride + (size_t)c), &v, 2);
        }
    for (r = 0; r < rows; r++)
        for (c = 0; c < cols; c++) {
            uint16_t v;
            memcpy(&v, src + 2u * ((size_t)r * (size_t)stride + (size_t)c), 2);
            s8[(size_t)r * (size_t)cols + (size_t)c] =
                (uint8_t)(mx ? ((uint32_t)v * 255u + mx / 2u) / mx : 0u);
        }
    brute_median(s8, rows, cols, cols, R, want, cols);
    for (f = 0; f < NPATHS; f++) {
        memset(out, 0xA5, (size_t)rows * (size_t)cols);
        memset(scratch, 0x5A, scr);
        snprintf(msg, sizeof msg, "16-bit %s: %dx%d R=%d max=%u", FN_NAMES[f], rows, cols, R,
                 (unsigned)maxv);
        TEST_ASSERT_EQUAL_INT_MESSAGE(
            ACTAG_OK, F16[f](src, rows, cols, stride, out, cols, R, scratch, scr), msg);
        TEST_ASSERT_EQUAL_MEMORY_MESSAGE(want, out, (size_t)rows * (size_t)cols, msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(ACTAG_ERR_WORKSPACE,
                                      F16[f](src, rows, cols, stride, out, cols, R, scratch,
                                             scr - 1), msg);
    }
    if (mx > 0u) {
        /* a maximum handed in (actag_detect's one scan per frame) is the
         * scale used: here twice the frame's own */
        static const median16max_fn M16[NPATHS] = {actag__median_filter16_max,
                                                   actag__median_filter16_max_sse2,
                                                   actag__median_filter16_max_portable};
        for (r = 0; r < rows; r++)
            for (c = 0; c < cols; c++) {
                uint16_t v;
                memcpy(&v, src + 2u * ((size_t)r * (size_t)stride + (size_t)c), 2);
                s8[(size_t)r * (size_t)cols + (size_t)c] =
                    (uint8_t)(((uint32_t)v * 255u + mx) / (2u * mx));
            }
        brute_median(s8, rows, cols, cols, R, want, cols);
        for (f = 0; f < NPATHS; f++) {
            memset(out, 0xA5, (size_t)rows * (size_t)cols);
            snprintf(msg, sizeof msg, "16-bit %s, max handed in: %dx%d R=%d max=%u", FN_NAMES[f],
                     rows, cols, R, (unsigned)maxv);
            TEST_ASSERT_EQUAL_INT_MESSAGE(ACTAG_OK,
                                          M16[f](src, 2u * mx, rows, cols, stride, out, cols, R,
                                                 scratch, scr),
                                          msg);
            TEST_ASSERT_EQUAL_MEMORY_MESSAGE(want, out, (size_t)rows * (size_t)cols, msg);
        }
    }
    free(raw);
    free(s8);
    free(want);
    free(out);
    free(scratch);
}

static void check16(int rows, int cols, int R, uint32_t maxv, int sextra)
{
    check16_rows(rows, cols, R, maxv, sextra, 0);
}

static void test_16bit_frames(void)
{
    static const int radii[] = {0, 1, 2, 4, 7, 8, 13};
    static const uint32_t maxes[] = {0, 1, 2, 255, 256, 1000, 4095, 65535};
    int i, k;
    rng_state = 1616u;
    for (i = 0; i < (int)(sizeof radii / sizeof radii[0]); i++)
        for (k = 0; k < (int)(sizeof maxes / sizeof maxes[0]); k++) {
            int rows = rnd_range(1, 40); /* one PRNG call per statement */
            int cols = rnd_range(1, 70);
            int pad = rnd_range(0, 3);
            check16(rows, cols, radii[i], maxes[k], pad);
        }
    check16(530, 300, 4, 65535, 0); /* a frame-sized case, 8-row ring blocks */
    check16(37, 300, 8, 4095, 5);   /* the constant-time path, 2-row ring */
    check16(1, 1, 4, 65535, 0);
    /* strips: 16-bit rows are scaled per strip (its columns only) */
    check16(21, 257, 4, 65535, 1);  /* two strips on the SSE2 path */
    check16(23, 504, 4, 4095, 0);   /* three */
    check16(21, 496, 8, 1000, 3);   /* two on both paths, the ring reused */
    check16(3, 300, 127, 65535, 1); /* strips with the shared columns summed */
    check16(5, 385, 64, 4095, 0);
    /* the portable 4-row path needs 2R+4 ring rows in the scratch: up to
     * 4352 columns at R = 7; wider frames take the constant-time path */
    check16(4, 4352, 7, 65535, 0);
    check16(4, 4353, 7, 65535, 0);
    check16(9, 4353, 2, 300, 1);
    /* the SSE2 16-row path needs 2R+16 ring rows: up to 2486 columns at
     * R = 7 (3165 at R = 4); wider frames take the constant-time path */
    check16(40, 2486, 7, 65535, 0);
    check16(40, 2487, 7, 65535, 2);
    check16(35, 3165, 4, 4095, 0);
    check16(35, 3166, 4, 4095, 1);
    check16(40, 70, 3, 65535, 3); /* a partial block of 8 rows, the ring reused */
}

/* The multiply-shift scaling equals the division for every maximum. */
static void test_16bit_scaling_exact(void)
{
    uint32_t mx;
    for (mx = 1; mx <= 65535u; mx++) {
        rowsrc rs;
        uint8_t one[2];
        uint32_t probes[6], i;
        uint16_t v16 = (uint16_t)mx;
        memcpy(one, &v16, 2);
        memset(&rs, 0, sizeof rs);
        rowsrc_init16(&rs, one, 1, mx); /* a 1-pixel frame of value mx */
        probes[0] = 0;
        probes[1] = 1u % (mx + 1u);
        probes[2] = mx / 2u;
        probes[3] = mx - 1u;
        probes[4] = mx;
        probes[5] = rnd() % (mx + 1u);
        for (i = 0; i < 6; i++) {
            uint32_t v = probes[i], want = (v * 255u + mx / 2u) / mx;
            uint32_t got = (uint32_t)(((uint64_t)(v * 255u + rs.half) * rs.magic) >> rs.shift);
            if (got != want) {
                char msg[80];
                snprintf(msg, sizeof msg, "max %u v %u: got %u want %u", (unsigned)mx,
                         (unsigned)v, (unsigned)got, (unsigned)want);
                TEST_FAIL_MESSAGE(msg);
            }
        }
    }
    { /* every sample for a few maxima */
        static const uint32_t some[] = {3, 255, 257, 1023, 40000, 65535};
        int k;
        for (k = 0; k < 6; k++) {
            rowsrc rs;
            uint8_t one[2];
            uint16_t v16 = (uint16_t)some[k];
            uint32_t v;
            memcpy(one, &v16, 2);
            rowsrc_init16(&rs, one, 1, some[k]);
            for (v = 0; v <= some[k]; v++)
                TEST_ASSERT_EQUAL_UINT32((v * 255u + some[k] / 2u) / some[k],
                                         (uint32_t)(((uint64_t)(v * 255u + rs.half) * rs.magic) >>
                                                    rs.shift));
        }
    }
}

/* ------------------------------------------------------------ in place */

typedef int (*inplace_fn)(void *, int, int, int, int, uint32_t, int, void *, size_t);
static const inplace_fn FIP[NPATHS] = {actag_median_filter_inplace,
                                       actag_median_filter_inplace_sse2,
                                       actag_median_filter_inplace_portable};

/* A random frame for the in-place and banded checks at orig + 1 (an odd
 * address for 16-bit samples): depth 8, speckle with bright blocks; depth
 * 16, uniform samples up to maxv. Row stride `stride` samples. s8 gets its
 * 8-bit reading (16-bit: scaled by the division the manual gives) with
 * stride cols; returns the largest 16-bit sample (0 for depth 8). */
static uint32_t random_frame(int depth, int rows, int cols, int stride, uint32_t maxv,
                             uint8_t *orig, uint8_t *s8)
{
    uint32_t mx = 0;
    int r, c;
    for (r = 0; r < rows; r++)
        for (c = 0; c < stride; c++) {
            size_t o = (size_t)r * (size_t)stride + (size_t)c;
            if (depth == 8) {
                orig[1 + o] = (uint8_t)((r / 3 + c / 4) % 3 == 0 ? 150 + (int)(rnd() % 100u)
                                                                : (int)(rnd() % 60u));
                if (c < cols)
                    s8[(size_t)r * (size_t)cols + (size_t)c] = orig[1 + o];
            } else {
                uint16_t v = (uint16_t)(maxv ? rnd() % (maxv + 1u) : 0u);
                if (c < cols && v > mx)
                    mx = v;
                memcpy(orig + 1 + 2u * o, &v, 2);
            }
        }
    if (depth == 16)
        for (r = 0; r < rows; r++)
            for (c = 0; c < cols; c++) {
                uint16_t v;
                memcpy(&v, orig + 1 + 2u * ((size_t)r * (size_t)stride + (size_t)c), 2);
                s8[(size_t)r * (size_t)cols + (size_t)c] =
                    (uint8_t)(mx ? ((uint32_t)v * 255u + mx / 2u) / mx : 0u);
            }
    return mx;
}

/* actag_median_filter_inplace on a random frame (depth 8 or 16, row stride
 * cols + sextra samples, largest sample maxv for 16-bit frames) against the
 * brute-force median of the frame (16-bit: scaled by the division the
 * manual gives, with max16 passed as given or 0 = found by the filter), on
 * every path, with `scratch` bytes of scratch (bands of a few rows at the
 * least scratch). The output is the first rows * cols bytes, stride cols. */
static void check_inplace(int depth, int rows, int cols, int R, uint32_t maxv, int pass_max,
                          int sextra, size_t scratch)
{
    int stride = cols + sextra, f;
    size_t bps = depth == 16 ? 2u : 1u, n = (size_t)rows * (size_t)stride * bps;
    uint8_t *orig = (uint8_t *)malloc(n + 1u), *raw = (uint8_t *)malloc(n + 1u);
    uint8_t *s8 = (uint8_t *)calloc((size_t)rows * (size_t)cols, 1);
    uint8_t *want = (uint8_t *)malloc((size_t)rows * (size_t)cols);
    uint8_t *scr = (uint8_t *)malloc(scratch);
    uint32_t mx;
    char msg[160];
    TEST_ASSERT_TRUE(orig && raw && s8 && want && scr);
    mx = random_frame(depth, rows, cols, stride, maxv, orig, s8);
    brute_median(s8, rows, cols, cols, R, want, cols);
    for (f = 0; f < NPATHS; f++) {
        memcpy(raw, orig, n + 1u); /* raw + 1: an odd address for 16-bit samples */
        memset(scr, 0x5A, scratch);
        snprintf(msg, sizeof msg, "in place %s: depth %d %dx%d stride %d R=%d scratch %lu",
                 FN_NAMES[f], depth, rows, cols, stride, R, (unsigned long)scratch);
        TEST_ASSERT_EQUAL_INT_MESSAGE(ACTAG_OK, FIP[f](raw + 1, depth, rows, cols, stride,
                                                       pass_max ? mx : 0u, R, scr, scratch),
                                      msg);
        TEST_ASSERT_EQUAL_UINT8_ARRAY_MESSAGE(want, raw + 1, (size_t)rows * (size_t)cols, msg);
    }
    free(orig);
    free(raw);
    free(s8);
    free(want);
    free(scr);
}

static void test_inplace_equals_brute_force(void)
{
    /* every radius the in-place filter takes, both depths, strides from
     * cols, heights from 1 across several bands at the least scratch (bands
     * of 16 rows or fewer), partial blocks, and more scratch (taller bands) */
    int R, k, trials = TU_TRIALS(12, 4);
    rng_state = 0x1A9Cu;
    for (R = 0; R <= ACTAG_MEDIAN_INPLACE_MAX_RADIUS; R++)
        for (k = 0; k < trials; k++) {
            int depth = k & 1 ? 16 : 8, rows = rnd_range(1, 75), cols = rnd_range(1, 40);
            size_t least = ACTAG_MEDIAN_INPLACE_SCRATCH_SIZE(cols);
            size_t scratch = k % 3 == 0 ? least : least + (size_t)rnd_range(1, 40 * cols);
            check_inplace(depth, rows, cols, R, k % 4 == 1 ? 255u : 65535u, k % 5 == 0,
                          rnd_range(0, 3), scratch);
        }
    check_inplace(8, 530, 64, 4, 0, 0, 0, ACTAG_MEDIAN_INPLACE_SCRATCH_SIZE(64));
    check_inplace(16, 97, 33, 7, 4095, 1, 2, ACTAG_MEDIAN_INPLACE_SCRATCH_SIZE(33));
    check_inplace(16, 40, 20, 3, 0, 0, 1, ACTAG_MEDIAN_INPLACE_SCRATCH_SIZE(20)); /* all zero */
    check_inplace(8, 1, 1, 7, 0, 0, 0, ACTAG_MEDIAN_INPLACE_SCRATCH_SIZE(1));
}

static void test_thirty_two_row_blocks(void)
{
    /* The AVX2 path at R <= 7 filters blocks of 32 output rows (a 32-lane
     * histogram, one byte lane per output row) and writes the medians
     * through 32 x 32 transposes: every height 1..70 (one to three blocks,
     * the last one partial or not) at every radius 0..7, widths from 1 past
     * 64 (partial transpose groups, chunks of 64 columns), on frames whose
     * rows have different medians (row i near level 7 i: a lane lost,
     * swapped, or stored in another row fails) and on random ones; 8-bit,
     * 16-bit (the ring of rows) and in place (bands shorter than a block). */
    int R, h, step = TU_EMULATED ? 9 : 1;
    uint8_t *img = (uint8_t *)fc_alloc(70u * 150u);
    rng_state = 0x32B0u;
    for (R = 0; R <= 7; R++)
        for (h = 1; h <= 70; h += step) {
            int cols = rnd_range(1, 140), sstride = cols + (h & 3), i, j;
            for (i = 0; i < h; i++)
                for (j = 0; j < sstride; j++)
                    img[(size_t)i * (size_t)sstride + (size_t)j] =
                        (uint8_t)((i * 7 + (int)(rnd() % 5u) + ((j / 9) & 1) * 3) & 255);
            fc_check_image(&FILTER, img, h, cols, sstride, R, 0, h & 4 ? 3 : 0, "rows differ");
            {
                /* one draw a statement: the order is the same on every compiler */
                int cw = rnd_range(1, 70);
                int fill = (int)(rnd() % FILL_N);
                check_case(h, cw, R, fill, h & 1, 0);
            }
            if (h % 3 == R % 3) {
                int c16 = rnd_range(1, 50);
                int sx = rnd_range(0, 2);
                check16_rows(h, c16, R, 4095u, sx, 1);
            }
            if (h % 3 == (R + 1) % 3) {
                int depth = h & 1 ? 16 : 8, ci = rnd_range(1, 40);
                size_t least = ACTAG_MEDIAN_INPLACE_SCRATCH_SIZE(ci);
                size_t more = least + (size_t)rnd_range(0, 60 * ci);
                check_inplace(depth, h, ci, R, 65535u, 0, h & 3, h & 2 ? more : least);
            }
        }
    free(img);
}

static void test_radius_four_network(void)
{
    /* At radius 4 the vector paths take sorting networks on 2 x 2 tiles:
     * median_net32 (x86-64 with AVX2: the library) and median_net16 (SSE2,
     * NEON: the sse2 path), two rows and up to 256 columns a pass, in
     * whole vectors of 32 or 16 tiles (64 or 32 columns), the frame's
     * edges through a clamped copy: every width 1..200 (one pass, copied
     * with both edges clamped, a last vector with 1..64 columns), heights
     * 1..12 (odd ones drop the pass's second row) and taller, every fill
     * (the few-level ones make ties), strides beyond cols; then widths of
     * two and three passes, the last one of one vector or more, whole or
     * not. */
    static const int wide[] = {255, 256, 257, 270, 288, 289, 300, 319, 320, 321,
                               383, 385, 448, 511, 512, 513, 530, 545, 600, 767};
    int cols, k, step = TU_EMULATED ? 7 : 1;
    rng_state = 0x9E7u;
    for (cols = 1; cols <= 200; cols += step) {
        int rows = cols <= 12 ? cols : rnd_range(1, 30);
        int kind = (int)(rnd() % FILL_N);
        check_case(rows, cols, 4, kind, cols & 3 ? rnd_range(1, 9) : 0, cols & 4 ? 2 : 0);
    }
    for (k = 0; k < (int)(sizeof wide / sizeof wide[0]); k += TU_EMULATED ? 3 : 1) {
        int rows = rnd_range(1, 12);
        int kind = (int)(rnd() % FILL_N);
        check_case(rows, wide[k], 4, kind, k & 1 ? rnd_range(1, 9) : 0, k & 2 ? 2 : 0);
    }
    /* 16-bit rows from the scaled ring: wide enough for passes that read
     * the ring's rows directly (no edge copy), narrow enough for a ring of
     * the 40 rows median_net32 asks for */
    check16(9, 600, 4, 4095u, 3);
    check16(6, 767, 4, 65535u, 0);
}

static void test_inplace_errors(void)
{
    uint8_t img[64], scr[ACTAG_MEDIAN_INPLACE_SCRATCH_SIZE(8)], before[64];
    int i;
    for (i = 0; i < 64; i++)
        img[i] = before[i] = (uint8_t)(i * 37);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_median_filter_inplace(NULL, 8, 8, 8, 8, 0, 1, scr, sizeof scr));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_median_filter_inplace(img, 8, 8, 8, 8, 0, 1, NULL, sizeof scr));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_median_filter_inplace(img, 8, 0, 8, 8, 0, 1, scr, sizeof scr));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_median_filter_inplace(img, 8, 8, 8, 7, 0, 1, scr, sizeof scr));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_median_filter_inplace(img, 12, 8, 8, 8, 0, 1, scr, sizeof scr));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_median_filter_inplace(img, 8, 8, 8, 8, 0, -1, scr, sizeof scr));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_median_filter_inplace(img, 8, 8, 8, 8, 0, ACTAG_MEDIAN_INPLACE_MAX_RADIUS + 1, scr, sizeof scr));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE, actag_median_filter_inplace(img, 8, 8, 8, 8, 0, 1, scr, sizeof scr - 1));
    TEST_ASSERT_EQUAL_UINT8_ARRAY(before, img, 64); /* untouched on error */
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_median_filter_inplace(img, 8, 8, 8, 8, 0, 1, scr, sizeof scr));
}

/* ------------------------------------------------------------ radius bands */

typedef int (*bands_fn)(const void *, int, uint32_t, int, int, int, uint8_t *, int,
                        const actag__median_bands *, void *, size_t);
typedef int (*bands_inplace_fn)(void *, int, int, int, int, uint32_t,
                                const actag__median_bands *, void *, size_t);
static const bands_fn FB[NPATHS] = {actag__median_filter_bands, actag__median_filter_bands_sse2,
                                    actag__median_filter_bands_portable};
static const bands_inplace_fn FBI[NPATHS] = {actag__median_filter_inplace_bands,
                                             actag__median_filter_inplace_bands_sse2,
                                             actag__median_filter_inplace_bands_portable};

/* Random bands over rows: 1..8 of them (never more than rows), radii 0..7 in
 * any order (the library's rule makes them monotone; the filter must not
 * depend on it). */
static void random_bands(int rows, actag__median_bands *b)
{
    int i, n = rnd_range(1, rows < ACTAG__MEDIAN_BANDS_MAX ? rows : ACTAG__MEDIAN_BANDS_MAX),
           prev = 0;
    b->n = n;
    for (i = 0; i < n; i++) {
        /* leave at least one row for each band after this one */
        int hi = rows - (n - 1 - i);
        b->end[i] = i == n - 1 ? rows : rnd_range(prev + 1, hi);
        b->radius[i] = rnd_range(0, ACTAG_MEDIAN_INPLACE_MAX_RADIUS);
        prev = b->end[i];
    }
}

/* The reference: each band's rows from the brute-force median of the whole
 * frame at the band's radius. */
static void brute_bands(const uint8_t *s8, int rows, int cols, const actag__median_bands *b,
                        uint8_t *want)
{
    uint8_t *full = (uint8_t *)malloc((size_t)rows * (size_t)cols);
    int i, y0 = 0;
    TEST_ASSERT_NOT_NULL(full);
    for (i = 0; i < b->n; y0 = b->end[i++]) {
        brute_median(s8, rows, cols, cols, b->radius[i], full, cols);
        memcpy(want + (size_t)y0 * (size_t)cols, full + (size_t)y0 * (size_t)cols,
               (size_t)(b->end[i] - y0) * (size_t)cols);
    }
    free(full);
}

/* Every path of the banded filter, out of place and in place, on a random
 * frame of depth 8 or 16 (row stride cols + sextra), against brute_bands. */
static void check_bands(int depth, int rows, int cols, const actag__median_bands *b, int sextra,
                        size_t inplace_extra, int pass_max)
{
    int stride = cols + sextra, f;
    size_t bps = depth == 16 ? 2u : 1u, n = (size_t)rows * (size_t)stride * bps;
    size_t scr = ACTAG_MEDIAN_SCRATCH_SIZE(rows, cols);
    size_t iscr = ACTAG_MEDIAN_INPLACE_SCRATCH_SIZE(cols) + inplace_extra;
    uint8_t *orig = (uint8_t *)malloc(n + 1u), *raw = (uint8_t *)malloc(n + 1u);
    uint8_t *s8 = (uint8_t *)calloc((size_t)rows * (size_t)cols, 1);
    uint8_t *want = (uint8_t *)malloc((size_t)rows * (size_t)cols);
    uint8_t *out = (uint8_t *)malloc((size_t)rows * (size_t)cols);
    uint8_t *scratch = (uint8_t *)malloc(scr > iscr ? scr : iscr);
    char msg[200];
    TEST_ASSERT_TRUE(orig && raw && s8 && want && out && scratch);
    uint32_t mx = random_frame(depth, rows, cols, stride, 4095u, orig, s8);
    brute_bands(s8, rows, cols, b, want);
    for (f = 0; f < NPATHS; f++) {
        snprintf(msg, sizeof msg, "bands %s: depth %d %dx%d stride %d, %d bands, first R=%d",
                 FN_NAMES[f], depth, rows, cols, stride, b->n, b->radius[0]);
        memset(out, 0xA5, (size_t)rows * (size_t)cols);
        memset(scratch, 0x5A, scr);
        TEST_ASSERT_EQUAL_INT_MESSAGE(ACTAG_OK, FB[f](orig + 1, depth, pass_max ? mx : 0u, rows,
                                                      cols, stride, out, cols, b, scratch, scr),
                                      msg);
        TEST_ASSERT_EQUAL_UINT8_ARRAY_MESSAGE(want, out, (size_t)rows * (size_t)cols, msg);
        memcpy(raw, orig, n + 1u);
        memset(scratch, 0x5A, iscr);
        TEST_ASSERT_EQUAL_INT_MESSAGE(ACTAG_OK, FBI[f](raw + 1, depth, rows, cols, stride,
                                                       pass_max ? mx : 0u, b, scratch, iscr),
                                      msg);
        TEST_ASSERT_EQUAL_UINT8_ARRAY_MESSAGE(want, raw + 1, (size_t)rows * (size_t)cols, msg);
    }
    free(orig);
    free(raw);
    free(s8);
    free(want);
    free(out);
    free(scratch);
}

static void three_bands(actag__median_bands *b, int e0, int e1, int e2, int r0, int r1, int r2)
{
    b->n = 3;
    b->end[0] = e0;
    b->end[1] = e1;
    b->end[2] = e2;
    b->radius[0] = r0;
    b->radius[1] = r1;
    b->radius[2] = r2;
}

static void test_bands_equal_brute_force(void)
{
    /* random bands, both depths, strides, in-place bands at the least
     * scratch and with more; band edges inside and across row blocks */
    int k, trials = TU_TRIALS(60, 15);
    actag__median_bands b;
    rng_state = 0xB4D5u;
    for (k = 0; k < trials; k++) {
        /* one draw per statement: the order of the draws is fixed */
        int rows = rnd_range(1, 90), cols = rnd_range(1, 40), sextra;
        size_t extra = 0;
        random_bands(rows, &b);
        sextra = rnd_range(0, 3);
        if (k % 3 != 0)
            extra = (size_t)rnd_range(1, 40 * cols);
        check_bands(k & 1 ? 16 : 8, rows, cols, &b, sextra, extra, k % 4 == 1);
    }
    /* the library's shape: radii falling with range, a frame of pool width */
    three_bands(&b, 200, 333, 530, 2, 3, 4);
    check_bands(8, 530, 64, &b, 0, 0, 0);
    check_bands(16, 530, 48, &b, 1, 0, 1);
    /* one band of one row each */
    three_bands(&b, 1, 2, 3, 7, 0, 1);
    check_bands(8, 3, 17, &b, 0, 0, 0);
}

static void test_bands_errors(void)
{
    enum { WIDE = 2600 }; /* 16-bit: the ring of 30 rows exceeds the plain scratch */
    uint8_t img[64], before[64], out[64], scr[ACTAG_MEDIAN_SCRATCH_SIZE(8, 8)];
    static uint16_t wide16[2 * WIDE];
    static uint8_t wide_out[2 * WIDE], wide_scr[ACTAG_MEDIAN_SCRATCH_SIZE(2, WIDE)];
    actag__median_bands b, bad;
    int f, i;
    for (i = 0; i < 64; i++)
        img[i] = before[i] = (uint8_t)(i * 37);
    b.n = 2;
    b.end[0] = 3;
    b.end[1] = 8;
    b.radius[0] = 1;
    b.radius[1] = 2;
    for (f = 0; f < NPATHS; f++) {
        memset(out, 0xA5, sizeof out);
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, FB[f](img, 8, 0, 8, 8, 8, out, 8, NULL, scr, sizeof scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, FB[f](NULL, 12, 0, 8, 8, 8, out, 8, &b, scr, sizeof scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, FBI[f](img, 8, 8, 8, 8, 0, NULL, scr, sizeof scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, FB[f](img, 12, 0, 0, 8, 8, out, 8, &b, scr, sizeof scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, FB[f](img, 12, 0, 8, 8, 8, out, 8, &b, scr, sizeof scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE, FB[f](img, 8, 0, 8, 8, 8, out, 8, &b, scr, sizeof scr - 1));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE, FBI[f](img, 8, 8, 8, 8, 0, &b, scr, ACTAG_MEDIAN_INPLACE_SCRATCH_SIZE(8) - 1));
        /* malformed: not ending at rows, not increasing, no band, too many,
         * a radius beyond the row-block paths'; a parameter error comes
         * before a short scratch */
        bad = b;
        bad.end[1] = 7;
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, FB[f](img, 8, 0, 8, 8, 8, out, 8, &bad, scr, sizeof scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, FB[f](img, 8, 0, 8, 8, 8, out, 8, &bad, scr, 1));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, FBI[f](img, 8, 8, 8, 8, 0, &bad, scr, sizeof scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, FBI[f](img, 8, 8, 8, 8, 0, &bad, scr, 1));
        bad = b;
        bad.end[0] = 8;
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, FB[f](img, 8, 0, 8, 8, 8, out, 8, &bad, scr, sizeof scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, FBI[f](img, 8, 8, 8, 8, 0, &bad, scr, sizeof scr));
        bad = b;
        bad.n = 0;
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, FB[f](img, 8, 0, 8, 8, 8, out, 8, &bad, scr, sizeof scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, FBI[f](img, 8, 8, 8, 8, 0, &bad, scr, sizeof scr));
        bad.n = ACTAG__MEDIAN_BANDS_MAX + 1;
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, FB[f](img, 8, 0, 8, 8, 8, out, 8, &bad, scr, sizeof scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, FBI[f](img, 8, 8, 8, 8, 0, &bad, scr, sizeof scr));
        bad = b;
        bad.radius[1] = ACTAG_MEDIAN_INPLACE_MAX_RADIUS + 1;
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, FB[f](img, 8, 0, 8, 8, 8, out, 8, &bad, scr, sizeof scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, FBI[f](img, 8, 8, 8, 8, 0, &bad, scr, sizeof scr));
        /* outputs untouched on error: the in-place frame and dst */
        TEST_ASSERT_EQUAL_UINT8_ARRAY(before, img, 64);
        for (i = 0; i < 64; i++)
            TEST_ASSERT_EQUAL_HEX8(0xA5, out[i]);
        /* a 16-bit frame wider than the plain scratch's ring of 30 rows */
        bad = b;
        bad.end[0] = 1;
        bad.end[1] = 2;
        memset(wide_out, 0xA5, sizeof wide_out);
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE, FB[f](wide16, 16, 0, 2, WIDE, WIDE, wide_out, WIDE,
                                                         &bad, wide_scr, sizeof wide_scr));
        for (i = 0; i < 2 * WIDE; i++)
            TEST_ASSERT_EQUAL_HEX8(0xA5, wide_out[i]);
    }
}

static void test_errors(void)
{
    uint8_t src[6 * 7], dst[6 * 7], dst_before[6 * 7];
    uint8_t scratch[ACTAG_MEDIAN_SCRATCH_SIZE(6, 7)];
    size_t scr = sizeof scratch;
    int f;

    TEST_ASSERT_EQUAL_size_t(7u * 274u, scr);
    /* 272 bytes per column up to 256 columns, then 2 per column */
    TEST_ASSERT_EQUAL_size_t(256u * 274u, ACTAG_MEDIAN_SCRATCH_SIZE(1, 256));
    TEST_ASSERT_EQUAL_size_t(256u * 272u + 257u * 2u, ACTAG_MEDIAN_SCRATCH_SIZE(1, 257));
    TEST_ASSERT_EQUAL_size_t(70656u, ACTAG_MEDIAN_SCRATCH_SIZE(530, 512));
    rng_state = 5u;
    fc_fill(&FILTER, src, 6, 7, 7, FILL_UNIFORM);
    for (f = 0; f < NPATHS; f++) {
        median_fn fn = FNS[f];
        memset(dst, 0x77, sizeof dst);
        memcpy(dst_before, dst, sizeof dst);

        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, fn(NULL, 6, 7, 7, dst, 7, 1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, fn(src, 6, 7, 7, NULL, 7, 1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, fn(src, 6, 7, 7, dst, 7, 1, NULL, scr));

        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, fn(src, 0, 7, 7, dst, 7, 1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, fn(src, 6, 0, 7, dst, 7, 1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, fn(src, -1, 7, 7, dst, 7, 1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, fn(src, 6, -3, 7, dst, 7, 1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, fn(src, ACTAG_MAX_DIM + 1, 7, 7, dst, 7, 1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE,
                              fn(src, 6, ACTAG_MAX_DIM + 1, ACTAG_MAX_DIM + 1, dst, ACTAG_MAX_DIM + 1, 1,
                                 scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, fn(src, 6, 7, 6, dst, 7, 1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, fn(src, 6, 7, 7, dst, 6, 1, scratch, scr));

        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, fn(src, 6, 7, 7, dst, 7, -1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM,
                              fn(src, 6, 7, 7, dst, 7, ACTAG_MEDIAN_MAX_RADIUS + 1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, fn(dst, 6, 7, 7, dst, 7, 1, scratch, scr));

        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE, fn(src, 6, 7, 7, dst, 7, 1, scratch, scr - 1));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE, fn(src, 6, 7, 7, dst, 7, 0, scratch, 0));
        /* Nothing was written by the failing calls. */
        TEST_ASSERT_EQUAL_MEMORY(dst_before, dst, sizeof dst);

        /* Exact size works, for the smallest and the largest radius. */
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, fn(src, 6, 7, 7, dst, 7, 1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, fn(src, 6, 7, 7, dst, 7, 0, scratch, scr));
        TEST_ASSERT_EQUAL_MEMORY(src, dst, sizeof dst); /* R = 0 copies */
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, fn(src, 6, 7, 7, dst, 7, ACTAG_MEDIAN_MAX_RADIUS, scratch, scr));
    }
}

int main(void)
{
#if ACTAG__AVX2
    const int avx2 = actag__cpu_avx2();
#else
    const int avx2 = 0;
#endif
    printf("test_median: the library's row-block median (radii 1..7) is %s\n",
           avx2 ? "median_rows32, at R = 4 median_net32 (AVX2); the sse2 path median_rows16, "
                  "at R = 4 median_net16"
                : "not the AVX2 one (library and sse2 paths alike)");
    UNITY_BEGIN();
    RUN_TEST(test_random_images);
    RUN_TEST(test_value_patterns);
    RUN_TEST(test_thin_images);
    RUN_TEST(test_radius_beyond_image);
    RUN_TEST(test_wide_and_tall);
    RUN_TEST(test_max_counts);
    RUN_TEST(test_partial_row_blocks);
    RUN_TEST(test_sixteen_row_blocks);
    RUN_TEST(test_eight_row_blocks);
    RUN_TEST(test_far_apart_medians);
    RUN_TEST(test_constant_and_extreme_images);
    RUN_TEST(test_wide_strides);
    RUN_TEST(test_every_small_radius_random);
    RUN_TEST(test_every_width_small_radii);
    RUN_TEST(test_strip_boundaries);
    RUN_TEST(test_large_radius_strips);
    RUN_TEST(test_strips_with_more_scratch);
    RUN_TEST(test_strips_real_frame_wide);
    RUN_TEST(test_real_sonar_frame);
    RUN_TEST(test_16bit_frames);
    RUN_TEST(test_16bit_scaling_exact);
    RUN_TEST(test_inplace_equals_brute_force);
    RUN_TEST(test_thirty_two_row_blocks);
    RUN_TEST(test_radius_four_network);
    RUN_TEST(test_inplace_errors);
    RUN_TEST(test_bands_equal_brute_force);
    RUN_TEST(test_bands_errors);
    RUN_TEST(test_errors);
    return UNITY_END();
}
