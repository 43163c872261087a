/* Tests for actag_adaptive_threshold against a brute-force reference. */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "actag/threshold.h"
#include "unity.h"
#include "test_util.h"
#include "filter_check.h"

/* The portable (non-SIMD) code path, compiled into this test under another
 * name so that both paths are checked on any machine. */
int actag_adaptive_threshold_portable(const uint8_t *src, int rows, int cols, int src_stride,
                                      uint8_t *dst, int dst_stride, int radius, int offset,
                                      void *scratch, size_t scratch_size);
#define ACTAG_NO_SIMD 1
/* The variant for targets without a vector unit (SWAR row operations, fused
 * horizontal pass), which is what ACTAG_NO_SIMD gives on Cortex-M; on
 * hosts with SSE2 or NEON the library itself checks the byte loops (its
 * SIMD tails) and block_prefix_suffix. */
#define ACTAG_FORCE_SWAR 1
#define actag_adaptive_threshold actag_adaptive_threshold_portable
#define actag_adaptive_threshold_bitmap actag_adaptive_threshold_bitmap_portable
#include "../src/threshold.c"
#undef actag_adaptive_threshold
#undef actag_adaptive_threshold_bitmap

/* The same variant with 4-byte words (what 32-bit cores such as Cortex-M
 * use), compiled in a second time with its static names renamed. */
int actag_adaptive_threshold_swar32(const uint8_t *src, int rows, int cols, int src_stride,
                                    uint8_t *dst, int dst_stride, int radius, int offset,
                                    void *scratch, size_t scratch_size);
#undef THRESHOLD_SCALAR
#undef WORD_ONES
#undef WORD_HIGH
#define ACTAG_SWAR_WORD32 1
#define min8 min8_w32
#define max8 max8_w32
#define word_t word32_t
#define ldw ldw_w32
#define stw stw_w32
#define lt_mask lt_mask_w32
#define minw minw_w32
#define maxw maxw_w32
#define minmax_rows minmax_rows_w32
#define row_threshold row_threshold_w32
#define gew gew_w32
#define double_pass double_pass_w32
#define row_threshold_doubling row_threshold_doubling_w32
#undef THRESHOLD_DSP
#undef THRESHOLD_DSP_ASM
#undef THRESHOLD_DOUBLING
#undef THRESHOLD_R8
#define avgw avgw_w32
#define qaddw qaddw_w32
#define qsubw qsubw_w32
#define vertical_fused vertical_fused_w32
#define min4w min4w_w32
#define ge_top4 ge_top4_w32
#define row_r8_words32_asm row_r8_words32_asm_w32
#define vertical_fused_asm vertical_fused_asm_w32
#define suffix_rows_asm suffix_rows_asm_w32
#define row_r8_steps_asm row_r8_steps_asm_w32
#define max4w max4w_w32
#define row_r8_bitmap row_r8_bitmap_w32
#define pack_row pack_row_w32
#define gather4 gather4_w32
#define vertical_window vertical_window_w32
#define threshold_core threshold_core_w32
#define actag_adaptive_threshold actag_adaptive_threshold_swar32
#define actag_adaptive_threshold_bitmap actag_adaptive_threshold_bitmap_swar32
#include "../src/threshold.c"
#undef actag_adaptive_threshold
#undef actag_adaptive_threshold_bitmap

/* 4-byte words with the horizontal pass by doubling (what Cortex-M4/M7
 * use with their DSP min/max; here with the portable words). */
int actag_adaptive_threshold_dbl32(const uint8_t *src, int rows, int cols, int src_stride,
                                   uint8_t *dst, int dst_stride, int radius, int offset,
                                   void *scratch, size_t scratch_size);
#undef THRESHOLD_SCALAR
#undef THRESHOLD_DSP
#undef THRESHOLD_DSP_ASM
#undef THRESHOLD_DOUBLING
#undef WORD_ONES
#undef WORD_HIGH
#undef min8
#undef max8
#undef word_t
#undef ldw
#undef stw
#undef lt_mask
#undef minw
#undef maxw
#undef minmax_rows
#undef row_threshold
#undef gew
#undef double_pass
#undef row_threshold_doubling
#undef pack_row
#undef gather4
#undef vertical_window
#undef threshold_core
#undef THRESHOLD_R8
#undef avgw
#undef qaddw
#undef qsubw
#undef vertical_fused
#undef min4w
#undef ge_top4
#undef row_r8_words32_asm
#undef vertical_fused_asm
#undef suffix_rows_asm
#undef row_r8_steps_asm
#undef max4w
#undef row_r8_bitmap
#define avgw avgw_d32
#define qaddw qaddw_d32
#define qsubw qsubw_d32
#define vertical_fused vertical_fused_d32
#define min4w min4w_d32
#define ge_top4 ge_top4_d32
#define row_r8_words32_asm row_r8_words32_asm_d32
#define vertical_fused_asm vertical_fused_asm_d32
#define suffix_rows_asm suffix_rows_asm_d32
#define row_r8_steps_asm row_r8_steps_asm_d32
#define max4w max4w_d32
#define row_r8_bitmap row_r8_bitmap_d32
#define pack_row pack_row_d32
#define gather4 gather4_d32
#define vertical_window vertical_window_d32
#define threshold_core threshold_core_d32
#define ACTAG_THRESHOLD_DOUBLING 1
#define min8 min8_d32
#define max8 max8_d32
#define word_t word_d32_t
#define ldw ldw_d32
#define stw stw_d32
#define lt_mask lt_mask_d32
#define minw minw_d32
#define maxw maxw_d32
#define minmax_rows minmax_rows_d32
#define row_threshold row_threshold_d32
#define gew gew_d32
#define double_pass double_pass_d32
#define row_threshold_doubling row_threshold_doubling_d32
#define actag_adaptive_threshold actag_adaptive_threshold_dbl32
#define actag_adaptive_threshold_bitmap actag_adaptive_threshold_bitmap_dbl32
#include "../src/threshold.c"
#undef actag_adaptive_threshold
#undef actag_adaptive_threshold_bitmap

int actag_adaptive_threshold_bitmap_portable(const uint8_t *src, int rows, int cols,
                                             int src_stride, uint32_t *bitmap, int radius,
                                             int offset, void *scratch, size_t scratch_size);
int actag_adaptive_threshold_bitmap_swar32(const uint8_t *src, int rows, int cols, int src_stride,
                                           uint32_t *bitmap, int radius, int offset,
                                           void *scratch, size_t scratch_size);
int actag_adaptive_threshold_bitmap_dbl32(const uint8_t *src, int rows, int cols, int src_stride,
                                          uint32_t *bitmap, int radius, int offset, void *scratch,
                                          size_t scratch_size);

typedef int (*threshold_fn)(const uint8_t *, int, int, int, uint8_t *, int, int, int, void *, size_t);
typedef int (*threshold_bitmap_fn)(const uint8_t *, int, int, int, uint32_t *, int, int, void *,
                                   size_t);

#define NFNS 4
static const threshold_fn FNS[NFNS] = {actag_adaptive_threshold, actag_adaptive_threshold_portable,
                                       actag_adaptive_threshold_swar32, actag_adaptive_threshold_dbl32};
static const threshold_bitmap_fn BFNS[NFNS] = {
    actag_adaptive_threshold_bitmap, actag_adaptive_threshold_bitmap_portable,
    actag_adaptive_threshold_bitmap_swar32, actag_adaptive_threshold_bitmap_dbl32};
static const char *const FN_NAMES[NFNS] = {"library", "portable", "portable-32-bit-words",
                                           "portable-32-bit-words-doubling"};

void setUp(void) {}
void tearDown(void) {}

/* ------------------------------------------------------------ helpers */

/* Reference: min and max over the clamped (edge-replicated) window, then
 * 2x >= mn + mx - 2 offset in 64-bit arithmetic (any int offset). */
static void brute_threshold(const uint8_t *src, int rows, int cols, int stride, int R, int offset,
                            uint8_t *out, int ostride)
{
    int i, j, a, b;
    /* Windows past the border only repeat edge pixels; cap the loops so
     * that huge radii stay cheap without changing the clamped window. */
    int ra = R < rows ? R : rows, rb = R < cols ? R : cols;
    for (i = 0; i < rows; i++) {
        for (j = 0; j < cols; j++) {
            int mn = 255, mx = 0;
            int x = src[(size_t)i * (size_t)stride + (size_t)j];
            for (a = -ra; a <= ra; a++) {
                const uint8_t *row = src + (size_t)clamp(i + a, 0, rows - 1) * (size_t)stride;
                for (b = -rb; b <= rb; b++) {
                    int v = row[clamp(j + b, 0, cols - 1)];
                    if (v < mn)
                        mn = v;
                    if (v > mx)
                        mx = v;
                }
            }
            out[(size_t)i * (size_t)ostride + (size_t)j] =
                (uint8_t)(2LL * x >= (long long)mn + mx - 2LL * offset);
        }
    }
}

enum { FILL_FEW = FC_FILL_OWN, FILL_GRADIENT, FILL_BLOBS, FILL_N };

static uint8_t own_pixel(int kind, int i, int j, const int v[4])
{
    (void)v; /* nothing drawn before the pixels but the constant level */
    switch (kind) {
    case FILL_FEW: return (uint8_t)(100 + (int)(rnd() % 4u));
    case FILL_GRADIENT: return (uint8_t)((i * 5 + j * 3) & 255);
    case FILL_BLOBS:
        return (uint8_t)(((i / 4 + j / 6) % 3 == 0) ? 150 + (int)(rnd() % 100u) : (int)(rnd() % 40u));
    default: return (uint8_t)rnd();
    }
}

static int random_offset(void)
{
    static const int special[] = {0, 1, -1, 2, -2, 255, 256, -255, -256, -257, 300, INT_MAX, INT_MIN};
    if (rnd() % 3u == 0)
        return special[rnd() % (sizeof special / sizeof special[0])];
    return rnd_range(-20, 20);
}

/* The bitmap variant of every path on src against want (the reference's
 * bytes, stride wstride): each pixel bit, every padding bit 0, with the
 * exact scratch size (one byte less fails and writes nothing). */
static void check_bitmap(const uint8_t *src, int rows, int cols, int sstride, int R, int offset,
                         const uint8_t *want, int wstride, const char *what)
{
    size_t n = ACTAG_BITMAP_SIZE(rows, cols), wpr = ACTAG_BITMAP_WORDS(cols), b;
    size_t scr = ACTAG_THRESHOLD_BITMAP_SCRATCH_SIZE_R(rows, cols, R);
    uint32_t *bm = (uint32_t *)fc_alloc(n);
    uint8_t *scratch = (uint8_t *)fc_alloc(scr);
    char msg[320];
    int f, r;
    for (f = 0; f < NFNS; f++) {
        memset(bm, 0xA5, n);
        memset(scratch, 0x5A, scr);
        snprintf(msg, sizeof msg, "bitmap %s: %s", FN_NAMES[f], what);
        TEST_ASSERT_EQUAL_INT_MESSAGE(ACTAG_ERR_WORKSPACE,
                                      BFNS[f](src, rows, cols, sstride, bm, R, offset, scratch,
                                              scr - 1), msg);
        TEST_ASSERT_EQUAL_HEX32_MESSAGE(0xA5A5A5A5u, bm[0], msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(
            ACTAG_OK, BFNS[f](src, rows, cols, sstride, bm, R, offset, scratch, scr), msg);
        for (r = -1; r <= rows; r++)
            for (b = 0; b < 32u * wpr; b++) {
                int c = (int)b - 1;
                unsigned got = (bm[(size_t)(r + 1) * wpr + b / 32u] >> (b % 32u)) & 1u;
                unsigned exp = r >= 0 && r < rows && c >= 0 && c < cols
                                   ? want[(size_t)r * (size_t)wstride + (size_t)c]
                                   : 0u;
                if (got != exp) {
                    snprintf(msg, sizeof msg, "bitmap %s: %s at (%d,%d): got %u want %u",
                             FN_NAMES[f], what, r, c, got, exp);
                    TEST_FAIL_MESSAGE(msg);
                }
            }
    }
    free(bm);
    free(scratch);
}

static int run_path(int path, const uint8_t *src, int rows, int cols, int sstride, uint8_t *dst,
                    int dstride, int R, int offset, void *scratch, size_t scratch_size)
{
    return FNS[path](src, rows, cols, sstride, dst, dstride, R, offset, scratch, scratch_size);
}

/* The exact radius-specific size, within the documented bound for any radius. */
static size_t scratch_size(int rows, int cols, int R)
{
    size_t scr = ACTAG_THRESHOLD_SCRATCH_SIZE_R(rows, cols, R);
    TEST_ASSERT_TRUE(scr <= ACTAG_THRESHOLD_SCRATCH_SIZE(rows, cols));
    return scr;
}

/* After every path: the bitmap variants (check_bitmap). */
static void more_checks(const uint8_t *src, int rows, int cols, int sstride, int R, int offset,
                        const uint8_t *want, int wstride, const char *what)
{
    char msg[200];
    snprintf(msg, sizeof msg, "%s %dx%d R=%d off=%d sstride=%d", what, rows, cols, R, offset,
             sstride);
    check_bitmap(src, rows, cols, sstride, R, offset, want, wstride, msg);
}

/* Every path against the brute-force reference with the exact
 * radius-specific scratch size, then the bitmap variants; images and cases
 * through fc_fill, fc_check_image and fc_check_case (filter_check.h). */
static const fc_filter FILTER = {
    .npaths = NFNS, .names = FN_NAMES, .run = run_path, .reference = brute_threshold,
    .scratch_size = scratch_size, .more_checks = more_checks, .draw_offset = random_offset,
    .nkinds = FILL_N, .own_pixel = own_pixel};

/* One case: an image of fill kind (row stride cols + sextra) through
 * fc_check_image. */
static void check_case(int rows, int cols, int R, int offset, int kind, int sextra, int dextra)
{
    fc_check_case(&FILTER, rows, cols, R, offset, kind, sextra, dextra);
}

/* ------------------------------------------------------------ tests */

static void test_every_width_and_radius(void)
{
    /* Every width 1..40 at every radius 0..22 (so that the row splits into
     * one or more blocks of 2R+1 with every remainder, the window reaches
     * both borders, one, or none), few rows, random pixels and offsets. */
    int cols, R;
    rng_state = 0x5EEDu;
    for (cols = 1; cols <= 40; cols++)
        for (R = 0; R <= 22; R++) {
            int rows = rnd_range(1, 5);
            int off = random_offset();
            check_case(rows, cols, R, off, FILL_UNIFORM, cols & 1, (cols >> 1) & 1);
        }
}

static void test_constant_and_extreme_images(void)
{
    /* All-equal images (0, 255, a middle level): every output is
     * offset >= 0; images of only 0 and 255 in stripes and checkerboards.
     * Shapes include 1 x N and N x 1; radii 0 to far beyond the image. */
    static const int levels[] = {0, 255, 77};
    static const int shapes[][2] = {{1, 1}, {1, 45}, {45, 1}, {2, 33}, {33, 2}, {19, 27}, {40, 64}};
    static const int radii[] = {0, 1, 2, 3, 7, 8, 9, 16, 32, 1000};
    static const int offs[] = {-1, 0, 1, 128, -255};
    uint8_t *img = (uint8_t *)fc_alloc(40u * 80u);
    size_t a, b, r;
    int i, j;
    for (a = 0; a < sizeof shapes / sizeof shapes[0]; a++) {
        int rows = shapes[a][0], cols = shapes[a][1], sstride = cols + 9;
        for (r = 0; r < sizeof radii / sizeof radii[0]; r++) {
            int R = radii[r];
            int off = offs[(a + r) % 5];
            for (b = 0; b < 3; b++) {
                fc_fill_constant(img, rows, cols, sstride, levels[b]);
                fc_check_image(&FILTER, img, rows, cols, sstride, R, off, 2, "constant");
            }
            for (b = 0; b < 4; b++) {
                for (i = 0; i < rows; i++)
                    for (j = 0; j < sstride; j++) {
                        int on;
                        switch (b) {
                        case 0: on = (j / (R % 7 + 1)) & 1; break;      /* vertical stripes */
                        case 1: on = (i / (R % 5 + 1)) & 1; break;      /* horizontal stripes */
                        case 2: on = (i + j) & 1; break;                /* checkerboard */
                        default: on = i == rows / 2 && j == cols / 2; break; /* one bright pixel */
                        }
                        img[(size_t)i * (size_t)sstride + (size_t)j] = on ? 255 : 0;
                    }
                fc_check_image(&FILTER, img, rows, cols, sstride, R, off, 0, "0/255 pattern");
            }
        }
    }
    free(img);
}

static void test_wide_strides(void)
{
    static const int radii[6] = {0, 1, 3, 8, 16, 100};
    fc_test_wide_strides(&FILTER, 0xFACEu, 30, radii);
}

static void test_random_images(void)
{
    static const int radii[] = {0, 1, 2, 3, 4, 8};
    fc_test_random_images(&FILTER, 0xC0FFEEu, 400, 50, radii, 6, 60);
}

static void test_every_radius_and_shape(void)
{
    /* Every radius 0..20 on sizes around the block length 2R+1, so that the
     * last block is full, short by one, or a single sample, in both
     * directions. */
    int R, d;
    rng_state = 0xABCDu;
    for (R = 0; R <= 20; R++) {
        int w = 2 * R + 1;
        for (d = -1; d <= 1; d++) {
            int n1 = clamp(w + d, 1, 100), n2 = clamp(2 * w + d, 1, 100);
            check_case(n1, n2, R, random_offset(), FILL_UNIFORM, 1, 2);
            check_case(n2, n1, R, random_offset(), FILL_UNIFORM, 0, 0);
            check_case(n2 + 1, 3 * w + d > 0 ? 3 * w + d : 1, R, 0, FILL_BLOBS, 2, 0);
        }
    }
}

static void test_offsets(void)
{
    /* Offsets around the clamping bounds and the int extremes. */
    static const int offs[] = {INT_MIN, -100000, -511, -510, -257, -256, -255, -128, -1, 0,
                               1, 2, 127, 254, 255, 256, 510, 511, 100000, INT_MAX};
    size_t k;
    rng_state = 17u;
    for (k = 0; k < sizeof offs / sizeof offs[0]; k++) {
        check_case(17, 23, 2, offs[k], FILL_UNIFORM, 1, 1);
        check_case(9, 12, 1, offs[k], FILL_BINARY, 0, 0);
        check_case(9, 12, 3, offs[k], FILL_CONST, 0, 3);
    }
}

static void test_thin_images(void)
{
    static const int radii[] = {0, 1, 2, 4, 8, 33, 1000};
    int r, n;
    rng_state = 555u;
    for (r = 0; r < 7; r++) {
        check_case(1, 1, radii[r], random_offset(), FILL_UNIFORM, 0, 0);
        check_case(1, 1, radii[r], random_offset(), FILL_UNIFORM, 4, 4);
        for (n = 2; n <= 80; n += 13) {
            check_case(1, n, radii[r], random_offset(), FILL_UNIFORM, 2, 1);
            check_case(n, 1, radii[r], random_offset(), FILL_UNIFORM, 1, 2);
            int off = random_offset(); /* one PRNG call per statement: */
            int kind = (int)(rnd() % FILL_N); /* argument order is unspecified */
            check_case(2, n, radii[r], off, kind, 0, 0);
            off = random_offset();
            kind = (int)(rnd() % FILL_N);
            check_case(n, 2, radii[r], off, kind, 0, 0);
        }
    }
}

static void test_radius_beyond_image(void)
{
    int t;
    rng_state = 2024u;
    for (t = 0; t < 20; t++) {
        int rows = rnd_range(1, 30), cols = rnd_range(1, 30);
        int R = rnd_range(30, 5000);
        int off = random_offset();
        int kind = (int)(rnd() % FILL_N);
        check_case(rows, cols, R, off, kind, t & 3, (t >> 2) & 3);
    }
    check_case(7, 5, INT_MAX, 1, FILL_UNIFORM, 1, 1);
    check_case(1, 9, INT_MAX, -1, FILL_UNIFORM, 0, 0);
}

static void test_wide_rows(void)
{
    /* Rows much longer than the SIMD width, with tails of every length. */
    int c;
    rng_state = 8u;
    for (c = 64; c <= 80; c++)
        check_case(20, c, 8, 1, FILL_BLOBS, c & 3, (c >> 2) & 3);
    check_case(40, 600, 8, 1, FILL_UNIFORM, 5, 3);
    check_case(600, 40, 8, 1, FILL_UNIFORM, 0, 0);
}

static void test_radius8_rows(void)
{
    /* Radius 8 (the detector's) into a bitmap has its own code: rows of
     * words with tails of every length, the Cortex-M DSP path's row
     * lengths (268..1008) and their neighbours, offsets of both signs. */
    static const int widths[] = {16, 17, 18, 19, 31, 32, 33, 35, 267, 268, 269, 271, 300,
                                 512, 530, 1005, 1008, 1009};
    static const int offsets[] = {1, 0, -1, 2, -2, 7, -9, 255, -256, 100, -100};
    size_t w;
    rng_state = 88u;
    for (w = 0; w < sizeof widths / sizeof widths[0]; w++) {
        int c = widths[w];
        check_case(19 + (int)(w % 5u) * 7, c, 8, offsets[w % (sizeof offsets / sizeof offsets[0])],
                   (int)(w % 6u), (int)(w & 3u), 0);
        check_case(9 + (int)(w % 3u), c, 8, offsets[(w + 5u) % (sizeof offsets / sizeof offsets[0])],
                   FILL_UNIFORM, 0, 1);
    }
}

static void test_every_width_to_70(void)
{
    /* The SSE2 row path (x86-64 builds) takes rows from about 22 to 112
     * columns on, by radius and by output (bytes or bitmap: its two lines
     * must fit in the scratch); narrower rows take the van Herk rows. Every
     * width 1..70 on both sides of those limits, at radii on both sides of
     * the steps of its doubling (extrema over h = 1, 2, 4, 8, 16, 32
     * samples), 1 to 4 rows, source and destination strides beyond cols,
     * offsets of both signs and beyond the clamping bounds. */
    static const int radii[] = {1, 2, 3, 4, 5, 6, 8, 11, 12, 16, 17, 23, 24};
    int cols, k;
    rng_state = 0x70u;
    for (cols = 1; cols <= 70; cols++)
        for (k = 0; k < (int)(sizeof radii / sizeof radii[0]); k++) {
            int rows = rnd_range(1, 4);
            int off = random_offset();
            int kind = (int)(rnd() % FILL_N);
            int spad = (cols + k) % 3 == 0 ? 0 : rnd_range(1, 40); /* one call a statement */
            int dpad = (cols + k) % 4 == 0 ? rnd_range(1, 9) : 0;
            check_case(rows, cols, radii[k], off, kind, spad, dpad);
        }
}

static void test_wide_rows_every_radius(void)
{
    /* Wider rows at larger radii (the SSE2 row path's limits up to 112
     * columns at R = 33), tails of every length of the vectors; at the
     * smaller radii enough rows for the vertical blocks of 2R + 1 rows to
     * repeat. */
    static const int radii[] = {7, 8, 9, 17, 20, 24, 32, 33, 40};
    int cols, k;
    rng_state = 0x71u;
    for (k = 0; k < (int)(sizeof radii / sizeof radii[0]); k++)
        for (cols = 60 + k; cols <= 140; cols += 7) {
            int R = radii[k];
            int rows = cols % 3 == 0 || R > 9 ? rnd_range(1, 6) : rnd_range(2 * R + 2, 3 * R + 4);
            int off = random_offset();
            int kind = (int)(rnd() % FILL_N);
            check_case(rows, cols, R, off, kind, cols % 2 ? 3 : 0, cols % 5 == 0 ? 1 : 0);
        }
}

static void test_output_is_binary(void)
{
    /* Output bytes are exactly 0 or 1 (covered by the comparisons above,
     * stated here on its own); also a constant image: mn = mx = x, so
     * the answer is offset >= 0 everywhere. */
    uint8_t src[12 * 13], dst[12 * 13];
    uint8_t scratch[ACTAG_THRESHOLD_SCRATCH_SIZE(12, 13)];
    int f;
    size_t k;
    memset(src, 77, sizeof src);
    for (f = 0; f < NFNS; f++) {
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, FNS[f](src, 12, 13, 13, dst, 13, 3, 0, scratch, sizeof scratch));
        for (k = 0; k < sizeof dst; k++)
            TEST_ASSERT_EQUAL_UINT8(1, dst[k]);
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, FNS[f](src, 12, 13, 13, dst, 13, 3, -1, scratch, sizeof scratch));
        for (k = 0; k < sizeof dst; k++)
            TEST_ASSERT_EQUAL_UINT8(0, dst[k]);
    }
    rng_state = 3u;
    fc_fill(&FILTER, src, 12, 13, 13, FILL_UNIFORM);
    for (f = 0; f < NFNS; f++) {
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, FNS[f](src, 12, 13, 13, dst, 13, 2, 5, scratch, sizeof scratch));
        for (k = 0; k < sizeof dst; k++)
            TEST_ASSERT_TRUE(dst[k] == 0 || dst[k] == 1);
    }
}


static void test_real_sonar_frame(void)
{
    /* A full 530 x 512 pool frame at the paper's radius 8, offset 1. */
    int rows, cols;
    uint8_t *img = tu_read_pgm(TU_DATA "/pool-video/f_0011.pgm", &rows, &cols);
    fc_check_image(&FILTER, img, rows, cols, cols, 8, 1, 0, "pool frame f_0011");
    free(img);
}

static void test_scratch_sizes(void)
{
    /* The documented values, and size-1 fails / exact size works for the
     * radius-specific size. */
    uint8_t src[10 * 11], dst[10 * 11];
    uint8_t scratch[ACTAG_THRESHOLD_SCRATCH_SIZE(10, 11)];
    int f, R;
    TEST_ASSERT_EQUAL_size_t(20480u, ACTAG_THRESHOLD_SCRATCH_SIZE_R(530, 512, 8));
    TEST_ASSERT_EQUAL_size_t(545792u, ACTAG_THRESHOLD_SCRATCH_SIZE(530, 512));
    TEST_ASSERT_EQUAL_size_t((2u * 10u + 6u) * 11u, sizeof scratch);
    TEST_ASSERT_EQUAL_size_t(sizeof scratch, ACTAG_THRESHOLD_SCRATCH_SIZE_R(10, 11, 5));
    TEST_ASSERT_EQUAL_size_t(sizeof scratch, ACTAG_THRESHOLD_SCRATCH_SIZE_R(10, 11, INT_MAX));
    TEST_ASSERT_EQUAL_size_t(8u * 11u, ACTAG_THRESHOLD_SCRATCH_SIZE_R(10, 11, 0));
    rng_state = 11u;
    fc_fill(&FILTER, src, 10, 11, 11, FILL_UNIFORM);
    for (f = 0; f < NFNS; f++) {
        for (R = 0; R <= 6; R++) {
            size_t need = ACTAG_THRESHOLD_SCRATCH_SIZE_R(10, 11, R);
            TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE,
                                  FNS[f](src, 10, 11, 11, dst, 11, R, 1, scratch, need - 1));
            TEST_ASSERT_EQUAL_INT(ACTAG_OK, FNS[f](src, 10, 11, 11, dst, 11, R, 1, scratch, need));
        }
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, FNS[f](src, 10, 11, 11, dst, 11, 1000, 1, scratch, sizeof scratch));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE,
                              FNS[f](src, 10, 11, 11, dst, 11, 1000, 1, scratch, sizeof scratch - 1));
    }
}

static void test_errors(void)
{
    uint8_t src[6 * 7], dst[6 * 7], dst_before[6 * 7];
    uint8_t scratch[ACTAG_THRESHOLD_SCRATCH_SIZE(6, 7)];
    size_t scr = sizeof scratch;
    int f;

    rng_state = 5u;
    fc_fill(&FILTER, src, 6, 7, 7, FILL_UNIFORM);
    for (f = 0; f < NFNS; f++) {
        threshold_fn fn = FNS[f];
        memset(dst, 0x77, sizeof dst);
        memcpy(dst_before, dst, sizeof dst);

        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, fn(NULL, 6, 7, 7, dst, 7, 1, 1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, fn(src, 6, 7, 7, NULL, 7, 1, 1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, fn(src, 6, 7, 7, dst, 7, 1, 1, NULL, scr));

        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, fn(src, 0, 7, 7, dst, 7, 1, 1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, fn(src, 6, 0, 7, dst, 7, 1, 1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, fn(src, -2, 7, 7, dst, 7, 1, 1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, fn(src, 6, -1, 7, dst, 7, 1, 1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, fn(src, ACTAG_MAX_DIM + 1, 7, 7, dst, 7, 1, 1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE,
                              fn(src, 6, ACTAG_MAX_DIM + 1, ACTAG_MAX_DIM + 1, dst, ACTAG_MAX_DIM + 1, 1, 1,
                                 scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, fn(src, 6, 7, 6, dst, 7, 1, 1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, fn(src, 6, 7, 7, dst, 6, 1, 1, scratch, scr));

        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, fn(src, 6, 7, 7, dst, 7, -1, 1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, fn(src, 6, 7, 7, dst, 7, INT_MIN, 1, scratch, scr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, fn(dst, 6, 7, 7, dst, 7, 1, 1, scratch, scr));

        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE, fn(src, 6, 7, 7, dst, 7, 1, 1, scratch, 0));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE,
                              fn(src, 6, 7, 7, dst, 7, 100, 1, scratch, ACTAG_THRESHOLD_SCRATCH_SIZE(6, 7) - 1));
        TEST_ASSERT_EQUAL_MEMORY(dst_before, dst, sizeof dst);

        TEST_ASSERT_EQUAL_INT(ACTAG_OK, fn(src, 6, 7, 7, dst, 7, 100, 1, scratch, scr));
    }
    for (f = 0; f < NFNS; f++) {
        threshold_bitmap_fn fn = BFNS[f];
        uint32_t bm[ACTAG_BITMAP_SIZE(6, 7) / 4];
        uint8_t big[ACTAG_THRESHOLD_SCRATCH_SIZE(6, 7) + 7];
        size_t bscr = sizeof big;
        memset(bm, 0x77, sizeof bm);
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, fn(NULL, 6, 7, 7, bm, 1, 1, big, bscr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, fn(src, 6, 7, 7, NULL, 1, 1, big, bscr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, fn(src, 6, 7, 7, bm, 1, 1, NULL, bscr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, fn(src, 0, 7, 7, bm, 1, 1, big, bscr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, fn(src, 6, 7, 6, bm, 1, 1, big, bscr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, fn(src, 6, 7, 7, bm, -1, 1, big, bscr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM,
                              fn(src, 6, 7, 7, (uint32_t *)(void *)src, 1, 1, big, bscr));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE,
                              fn(src, 6, 7, 7, bm, 100, 1, big, ACTAG_THRESHOLD_SCRATCH_SIZE(6, 7)));
        TEST_ASSERT_EQUAL_HEX32(0x77777777u, bm[0]);
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, fn(src, 6, 7, 7, bm, 100, 1, big, bscr));
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_random_images);
    RUN_TEST(test_every_radius_and_shape);
    RUN_TEST(test_offsets);
    RUN_TEST(test_thin_images);
    RUN_TEST(test_radius_beyond_image);
    RUN_TEST(test_wide_rows);
    RUN_TEST(test_radius8_rows);
    RUN_TEST(test_every_width_and_radius);
    RUN_TEST(test_every_width_to_70);
    RUN_TEST(test_wide_rows_every_radius);
    RUN_TEST(test_constant_and_extreme_images);
    RUN_TEST(test_wide_strides);
    RUN_TEST(test_output_is_binary);
    RUN_TEST(test_real_sonar_frame);
    RUN_TEST(test_scratch_sizes);
    RUN_TEST(test_errors);
    return UNITY_END();
}
