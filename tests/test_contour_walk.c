/* The contour scanner's walks (the table k_walk, two walkers per border,
 * the backward walker's bounded buffer) and its raster scan (candidates of
 * whole words, checked again one at a time) against the scanner they
 * replaced (tests/contours_ref.h): the same return codes, contours, points,
 * counts, boxes, areas, scanner state and marks after every call, on random
 * and edge-case bitmaps (widths around multiples of 32, all white, all
 * black, checkerboards, one-pixel blobs and holes, blobs touching every
 * border, rings, noise) and real frames, with buffers of several sizes. The
 * library is checked as built, and the source again with a backward buffer
 * of a few steps, so that borders outgrow it; k_walk against the sweep it
 * stands for. */
#include "unity.h"
#include "test_util.h"

#include "actag/actag.h"

/* The source under other names, its backward buffer 3 steps long. */
#define WALK_BACK_MAX 3
#define actag_bitmap_pack small_bitmap_pack
#define actag_bitmap_unpack small_bitmap_unpack
#define actag_contour_scanner_init small_contour_scanner_init
#define actag_contour_next small_contour_next
#include "../src/contours.c"
#undef actag_bitmap_pack
#undef actag_bitmap_unpack
#undef actag_contour_scanner_init
#undef actag_contour_next

#include "contours_ref.h"

void setUp(void) {}
void tearDown(void) {}

typedef int (*next_fn)(actag_contour_scanner *, actag_ipoint *, int, actag_contour_info *);

/* ------------------------------------------------------------ the table */

/* Bit of the walk's neighbourhood (k_walk's nb) of each direction. */
static const int nb_bit[8] = {4, 2, 1, 0, 3, 5, 6, 7};

static int white_dir(unsigned nb, int d)
{
    return (int)(nb >> nb_bit[d & 7] & 1u);
}

/* Every entry that can occur is the sweep of Suzuki-Abe's steps 3.3 and
 * 3.4 (k_walk[0], the previous pixel white; k_walk[1], the next pixel
 * white), or of step 3.1 (k_walk[1], bits 0..2, the next pixel black), done
 * here one direction at a time. */
static void test_walk_table(void)
{
    int din, dout, nb, k, forward = 0, backward = 0;
    for (din = 0; din < 8; din++)
        for (nb = 0; nb < 256; nb++) {
            int prev = (din + 4) & 7, east = 0;
            if (!white_dir((unsigned)nb, prev))
                continue;
            /* counterclockwise from just after the previous pixel */
            for (k = 1; !white_dir((unsigned)nb, prev + k); k++)
                if (((prev + k) & 7) == 0)
                    east = 1; /* passed over the black east neighbour */
            TEST_ASSERT_EQUAL_INT(((prev + k) & 7) | east << 3, k_walk[0][din << 8 | nb]);
            forward++;
        }
    for (dout = 0; dout < 8; dout++)
        for (nb = 1; nb < 256; nb++) {
            int t = k_walk[1][dout << 8 | nb];
            /* clockwise from just before the next pixel, dout itself last */
            for (k = 1; !white_dir((unsigned)nb, dout - k); k++)
                ;
            TEST_ASSERT_EQUAL_INT((dout - k + 4) & 7, t & 7);
            if (white_dir((unsigned)nb, dout)) {
                /* the step undone: the forward step from there, the same
                 * east mark */
                TEST_ASSERT_EQUAL_INT(dout | (t & 8), k_walk[0][(t & 7) << 8 | nb]);
                backward++;
            }
        }
    TEST_ASSERT_EQUAL_INT(8 * 128, forward);
    TEST_ASSERT_EQUAL_INT(8 * 128, backward);
}

/* -------------------------------------------------------------- bitmaps */

static void setpx(uint32_t *bm, int cols, int r, int c, int v)
{
    size_t b = (size_t)(c + 1), i = (size_t)(r + 1) * ACTAG_BITMAP_WORDS(cols) + b / 32u;
    if (v)
        bm[i] |= (uint32_t)1u << (b % 32u);
    else
        bm[i] &= ~((uint32_t)1u << (b % 32u));
}

/* A bitmap of exactly ACTAG_BITMAP_SIZE bytes (reading past it is visible
 * under ASan), padding black. */
static uint32_t *bitmap_new(int rows, int cols)
{
    uint32_t *bm = (uint32_t *)calloc(ACTAG_BITMAP_SIZE(rows, cols), 1);
    TEST_ASSERT_NOT_NULL(bm);
    return bm;
}

#define BIG_CAP (1 << 17) /* more than any border here has points */
static actag_ipoint g_pa[BIG_CAP + 8], g_pb[BIG_CAP + 8];

/* The scanner under test (next) against the reference, with buffer
 * capacity cap: everything equal after every call. Returns the contours. */
static int compare_cap(const uint32_t *bm, int rows, int cols, next_fn next, int cap)
{
    const size_t size = ACTAG_BITMAP_SIZE(rows, cols);
    uint32_t *ma = (uint32_t *)malloc(size), *mb = (uint32_t *)malloc(size);
    actag_contour_scanner sa, sb;
    /* a border takes each of a pixel's 8 steps out at most once */
    const int most = 8 * rows * cols < cap ? 8 * rows * cols : cap;
    int n = 0, ra, rb, i;
    TEST_ASSERT_TRUE(ma && mb);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_contour_scanner_init(&sa, bm, ma, rows, cols));
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_contour_scanner_init(&sb, bm, mb, rows, cols));
    for (i = 0; i < most + 8; i++) {
        g_pa[i].x = g_pb[i].x = -7;
        g_pa[i].y = g_pb[i].y = -9;
    }
    do {
        actag_contour_info ia, ib;
        memset(&ia, 0xa5, sizeof ia);
        memset(&ib, 0xa5, sizeof ib);
        ra = ref_contour_next(&sa, cap ? g_pa : NULL, cap, &ia);
        rb = next(&sb, cap ? g_pb : NULL, cap, &ib);
        TEST_ASSERT_EQUAL_INT(ra, rb);
        TEST_ASSERT_EQUAL_INT(sa.r, sb.r);
        TEST_ASSERT_EQUAL_INT(sa.c, sb.c);
        TEST_ASSERT_EQUAL_INT(sa.holes, sb.holes);
        TEST_ASSERT_EQUAL_MEMORY(ma, mb, size);
        if (ra == 1) {
            TEST_ASSERT_EQUAL_INT(ia.npoints, ib.npoints);
            TEST_ASSERT_EQUAL_INT(ia.stored, ib.stored);
            TEST_ASSERT_EQUAL_INT(ia.overflow, ib.overflow);
            TEST_ASSERT_EQUAL_INT(ia.min_x, ib.min_x);
            TEST_ASSERT_EQUAL_INT(ia.max_x, ib.max_x);
            TEST_ASSERT_EQUAL_INT(ia.min_y, ib.min_y);
            TEST_ASSERT_EQUAL_INT(ia.max_y, ib.max_y);
            TEST_ASSERT_EQUAL_MEMORY(&ia.area, &ib.area, sizeof ia.area);
            /* the points stored, and nothing written after them */
            TEST_ASSERT_EQUAL_MEMORY(g_pa, g_pb, (size_t)(ia.stored + 8) * sizeof(actag_ipoint));
            n++;
        }
    } while (ra == 1);
    free(ma);
    free(mb);
    return n;
}

/* compare_cap() with a buffer big enough for every border and a few
 * small ones, for the library and the short backward buffer; returns the
 * contours. */
static int compare(const uint32_t *bm, int rows, int cols)
{
    static const int caps[4] = {0, 1, 3, 17};
    int n = compare_cap(bm, rows, cols, actag_contour_next, BIG_CAP), i;
    TEST_ASSERT_EQUAL_INT(n, compare_cap(bm, rows, cols, small_contour_next, BIG_CAP));
    for (i = 0; i < 4; i++) {
        compare_cap(bm, rows, cols, actag_contour_next, caps[i]);
        compare_cap(bm, rows, cols, small_contour_next, caps[i]);
    }
    return n;
}

/* Pixel patterns: each (r, c) of a rows x cols bitmap white or not. */
enum { P_RANDOM, P_WHITE, P_BLACK, P_CHECKER, P_CHECKER1, P_DOTS, P_HOLES, P_FRAME, P_RINGS,
       P_BLOBBY, P_N };

static int pattern_px(int p, int r, int c, int rows, int cols, int permille)
{
    switch (p) {
    case P_RANDOM:
        return tu_range(0, 999) < permille;
    case P_WHITE:
        return 1;
    case P_BLACK:
        return 0;
    case P_CHECKER:
        return (r + c) % 2 == 0;
    case P_CHECKER1:
        return (r + c) % 2 == 1;
    case P_DOTS: /* one-pixel blobs, some touching diagonally */
        return r % 2 == 0 && c % 2 == 0 && tu_range(0, 3) > 0;
    case P_HOLES: /* one-pixel holes, and some of two pixels */
        return !((r % 2 == 1 && c % 2 == 1 && tu_range(0, 3) > 0) ||
                 (r % 4 == 1 && c % 4 == 2 && tu_range(0, 1)));
    case P_FRAME: /* touching every border, with holes inside */
        return r == 0 || c == 0 || r == rows - 1 || c == cols - 1 || tu_range(0, 999) < permille;
    case P_RINGS: { /* concentric rings */
        int d = r < c ? r : c;
        if (rows - 1 - r < d)
            d = rows - 1 - r;
        if (cols - 1 - c < d)
            d = cols - 1 - c;
        return d % 2 == 0;
    }
    default:
        return 0;
    }
}

/* A bitmap of pattern p, with a few pixels flipped (flip per mille). */
static uint32_t *pattern_bitmap(int p, int rows, int cols, int permille, int flip)
{
    uint32_t *bm = bitmap_new(rows, cols);
    int r, c;
    if (p == P_BLOBBY) {
        /* box-blurred noise thresholded: blobs of many sizes, with holes */
        int *v = (int *)malloc((size_t)rows * (size_t)cols * sizeof(int)), dr, dc;
        TEST_ASSERT_NOT_NULL(v);
        for (r = 0; r < rows * cols; r++)
            v[r] = tu_range(0, 999);
        for (r = 0; r < rows; r++)
            for (c = 0; c < cols; c++) {
                int s = 0, n = 0;
                for (dr = -2; dr <= 2; dr++)
                    for (dc = -2; dc <= 2; dc++)
                        if (r + dr >= 0 && r + dr < rows && c + dc >= 0 && c + dc < cols) {
                            s += v[(r + dr) * cols + c + dc];
                            n++;
                        }
                setpx(bm, cols, r, c, s < permille * n);
            }
        free(v);
    } else {
        for (r = 0; r < rows; r++)
            for (c = 0; c < cols; c++)
                setpx(bm, cols, r, c, pattern_px(p, r, c, rows, cols, permille));
    }
    for (r = 0; r < rows; r++)
        for (c = 0; c < cols; c++)
            if (tu_range(0, 999) < flip)
                setpx(bm, cols, r, c, !actag_bitmap_get(bm, cols, r, c));
    return bm;
}

/* compare() on a bitmap of pattern p: blobby patterns draw their own
 * density near the threshold (one draw, after the caller's). */
static int compare_pattern(int p, int rows, int cols, int permille, int flip)
{
    uint32_t *bm;
    int n;
    if (p == P_BLOBBY)
        permille = tu_range(420, 580);
    bm = pattern_bitmap(p, rows, cols, permille, flip);
    n = compare(bm, rows, cols);
    free(bm);
    return n;
}

static void test_patterns(void)
{
    /* widths 1 .. 70 and around multiples of 32 (a row of 1, 2 or 3 words,
     * the neighbourhood across a word boundary) */
    int it, total = 0;
    const int iters = TU_TRIALS(6000, 20);
    tu_seed(2718);
    for (it = 0; it < iters; it++) {
        int p = it % P_N, rows = tu_range(1, it % 4 ? 12 : 40), cols;
        int permille = tu_range(300, 700), flip = it % 3 ? 0 : tu_range(1, 60);
        if (it % 5 == 0) { /* one draw a statement: the same inputs on every compiler */
            int words = tu_range(1, 2);
            cols = 32 * words + tu_range(-3, 2);
        } else
            cols = tu_range(1, it % 3 ? 70 : 8);
        total += compare_pattern(p, rows, cols, permille, flip);
    }
    TEST_ASSERT_GREATER_THAN(iters, total);
}

/* Wide rows (540 .. 1100 columns: 18 or more words, where the raster
 * scan handles a row's last word apart from its full chunks of 16) with
 * few rows, every pattern, the library and the short backward buffer (a
 * review's mutation of the last word's scan passed the narrower cases). */
static void test_wide_rows(void)
{
    int it, total = 0;
    const int iters = TU_TRIALS(300, 12);
    tu_seed(1618);
    for (it = 0; it < iters; it++) {
        int p = it % P_N, rows = tu_range(1, 8), cols = tu_range(540, 1100);
        int permille = tu_range(300, 700), flip = it % 3 ? 0 : tu_range(1, 60);
        total += compare_pattern(p, rows, cols, permille, flip);
    }
    TEST_ASSERT_GREATER_THAN(iters, total);
}

/* Large blobs: borders of thousands of points, longer than twice the
 * library's backward buffer (WALK_BACK_MAX in src/contours.c, 2048). */
static void test_long_borders(void)
{
    int it;
    tu_seed(31415);
    for (it = 0; it < TU_TRIALS(6, 3); it++) {
        int rows = 300 + 40 * it, cols = 280 + 37 * it, n;
        uint32_t *bm = pattern_bitmap(it % 2 ? P_BLOBBY : P_RINGS, rows, cols, 560, it % 2 ? 0 : 2);
        n = compare_cap(bm, rows, cols, actag_contour_next, BIG_CAP);
        TEST_ASSERT_GREATER_THAN(0, n);
        compare_cap(bm, rows, cols, actag_contour_next, 4096);
        compare_cap(bm, rows, cols, small_contour_next, 100);
        free(bm);
    }
    /* one border of about 4 * 1100 points (the filled square's edge) */
    {
        const int size = 1100;
        uint32_t *bm = bitmap_new(size, size);
        int r, c;
        for (r = 0; r < size; r++)
            for (c = 0; c < size; c++)
                setpx(bm, size, r, c, r > 0 && c > 0 && (r != size / 2 || c % 97 != 5));
        uint32_t *mk = (uint32_t *)malloc(ACTAG_BITMAP_SIZE(size, size));
        actag_contour_scanner sc;
        actag_contour_info info;
        TEST_ASSERT_EQUAL_INT(1, compare_cap(bm, size, size, actag_contour_next, BIG_CAP));
        compare_cap(bm, size, size, actag_contour_next, 3000);
        TEST_ASSERT_NOT_NULL(mk);
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_contour_scanner_init(&sc, bm, mk, size, size));
        TEST_ASSERT_EQUAL_INT(1, actag_contour_next(&sc, NULL, 0, &info));
        TEST_ASSERT_GREATER_THAN(2 * 2048, info.npoints);
        free(mk);
        free(bm);
    }
}

/* Real frames, thresholded by the library (as actag_detect does) and at
 * fixed levels, and flipped (the detector's range and azimuth options). */
static void test_real_frames(void)
{
    static const char *const frames[3] = {"f_0001.pgm", "f_0291.pgm", "f_0561.pgm"};
    int f;
    for (f = 0; f < (TU_EMULATED ? 1 : 3); f++) {
        char path[600];
        int rows = 0, cols = 0, r, c, flip, v;
        uint8_t *px;
        actag_params p;
        size_t scratch_size;
        void *scratch;
        uint32_t *bin, *bm;
        snprintf(path, sizeof path, "%s/pool-video/%s", TU_DATA, frames[f]);
        px = tu_read_pgm(path, &rows, &cols);
        TEST_ASSERT_NOT_NULL(px);
        actag_params_default(&p);
        scratch_size = ACTAG_THRESHOLD_BITMAP_SCRATCH_SIZE_R(rows, cols, p.tuning.threshold_radius);
        scratch = malloc(scratch_size);
        bin = bitmap_new(rows, cols);
        TEST_ASSERT_NOT_NULL(scratch);
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_adaptive_threshold_bitmap(
                                            px, rows, cols, cols, bin, p.tuning.threshold_radius,
                                            p.tuning.threshold_offset, scratch, scratch_size));
        for (flip = 0; flip < (TU_EMULATED ? 1 : 4); flip++) {
            bm = bitmap_new(rows, cols);
            for (r = 0; r < rows; r++)
                for (c = 0; c < cols; c++)
                    setpx(bm, cols, r, c,
                          actag_bitmap_get(bin, cols, flip & 1 ? rows - 1 - r : r,
                                           flip & 2 ? cols - 1 - c : c));
            TEST_ASSERT_GREATER_THAN(100, compare_cap(bm, rows, cols, actag_contour_next, BIG_CAP));
            compare_cap(bm, rows, cols, actag_contour_next, 4096);
            compare_cap(bm, rows, cols, small_contour_next, 64);
            free(bm);
        }
        for (v = 20; v <= 60; v += 40) {
            bm = bitmap_new(rows, cols);
            for (r = 0; r < rows; r++)
                for (c = 0; c < cols; c++)
                    setpx(bm, cols, r, c, px[(size_t)r * (size_t)cols + (size_t)c] >= v);
            TEST_ASSERT_GREATER_THAN(10, compare_cap(bm, rows, cols, actag_contour_next, BIG_CAP));
            free(bm);
        }
        free(bin);
        free(scratch);
        free(px);
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_walk_table);
    RUN_TEST(test_patterns);
    RUN_TEST(test_wide_rows);
    RUN_TEST(test_long_borders);
    RUN_TEST(test_real_frames);
    return UNITY_END();
}
