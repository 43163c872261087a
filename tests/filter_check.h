/* Shared by test_median.c and test_threshold.c, which check every code path
 * of a filter against a brute-force reference: their random images'
 * generator (xorshift32: the same numbers on every platform), the edge clamp
 * of the reference's window, buffers, constant images with padding, the
 * check of a filter's output (every pixel, and the destination padding the
 * caller filled with 0xA5 untouched), and, given the filter as an fc_filter
 * (its paths, reference, scratch size, offsets and fill kinds), the fill of
 * a case's image, the check of every path on an image and the tests both
 * run with their own numbers (wide strides, random images). */
#ifndef ACTAG_FILTER_CHECK_H
#define ACTAG_FILTER_CHECK_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "actag/common.h"
#include "unity.h"

static uint32_t rng_state;

static inline uint32_t rnd(void)
{
    uint32_t x = rng_state; /* xorshift32 */
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    rng_state = x;
    return x;
}

static inline int rnd_range(int lo, int hi) /* inclusive */
{
    return lo + (int)(rnd() % (uint32_t)(hi - lo + 1));
}

static inline int clamp(int v, int lo, int hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

/* n bytes of malloc, or the test fails. */
static inline void *fc_alloc(size_t n)
{
    void *p = malloc(n);
    TEST_ASSERT_NOT_NULL(p);
    return p;
}

/* rows x sstride bytes of level, the padding (columns cols..sstride-1) of
 * the other extreme, 255 - level. */
static inline void fc_fill_constant(uint8_t *img, int rows, int cols, int sstride, int level)
{
    int i;
    memset(img, level, (size_t)rows * (size_t)sstride);
    for (i = 0; i < rows; i++)
        memset(img + (size_t)i * (size_t)sstride + (size_t)cols, 255 - level,
               (size_t)(sstride - cols));
}

/* out against the reference want (rows x cols, both of row stride dstride):
 * every pixel equal, and the padding (columns cols..dstride-1) still 0xA5.
 * Fails the test with what, the pixel and both values. */
static inline void fc_check_output(const uint8_t *out, const uint8_t *want, int rows, int cols,
                                   int dstride, const char *what)
{
    char msg[320];
    int i, j;
    for (i = 0; i < rows; i++)
        for (j = 0; j < dstride; j++) {
            size_t k = (size_t)i * (size_t)dstride + (size_t)j;
            if (j < cols && out[k] != want[k]) {
                snprintf(msg, sizeof msg, "%s at (%d,%d): got %d want %d", what, i, j, out[k],
                         want[k]);
                TEST_FAIL_MESSAGE(msg);
            } else if (j >= cols && out[k] != 0xA5) {
                snprintf(msg, sizeof msg, "%s: padding written at (%d,%d)", what, i, j);
                TEST_FAIL_MESSAGE(msg);
            }
        }
}

/* ------------------------------------------------ the filter under test */

/* Fill kinds: the shared ones; a test's own kinds follow from FC_FILL_OWN. */
enum { FILL_UNIFORM, FILL_CONST, FILL_BINARY, FC_FILL_OWN };

/* What the checks below need to know of a filter and its test. */
typedef struct {
    /* The code paths: path p (0..npaths-1) is named names[p] and run by
     * run(p, ...) on src (rows x cols, row stride sstride) with radius R
     * (and offset, where the filter takes one) into dst (row stride
     * dstride) with scratch_size bytes of scratch; the filter's return
     * value. */
    int npaths;
    const char *const *names;
    int (*run)(int path, const uint8_t *src, int rows, int cols, int sstride, uint8_t *dst,
               int dstride, int R, int offset, void *scratch, size_t scratch_size);
    /* The brute-force reference: src filtered into out (row stride ostride). */
    void (*reference)(const uint8_t *src, int rows, int cols, int stride, int R, int offset,
                      uint8_t *out, int ostride);
    /* Bytes of scratch the paths get for a rows x cols image at radius R. */
    size_t (*scratch_size)(int rows, int cols, int R);
    /* Further checks of a case, given the reference's output want (row
     * stride wstride); NULL: none. */
    void (*more_checks)(const uint8_t *src, int rows, int cols, int sstride, int R, int offset,
                        const uint8_t *want, int wstride, const char *what);
    /* One random offset; NULL: the filter takes none (offset 0). */
    int (*draw_offset)(void);
    /* The test's fill kinds 0..nkinds-1: from FC_FILL_OWN on, pixel (i, j)
     * is own_pixel(kind, i, j, v), v being what own_draws (NULL: nothing)
     * drew for the image before its first pixel. */
    int nkinds;
    void (*own_draws)(int v[4]);
    uint8_t (*own_pixel)(int kind, int i, int j, const int v[4]);
} fc_filter;

/* img (rows x stride) of fill kind: one level drawn for FILL_CONST, then
 * the test's own draws; then row by row, left to right (the random numbers
 * fall on the same pixels on every platform), columns 0..cols-1 of the kind
 * and random bytes, which the filter must ignore, in the padding. */
static inline void fc_fill(const fc_filter *flt, uint8_t *img, int rows, int cols, int stride,
                           int kind)
{
    int i, j, v[4] = {0, 0, 0, 0};
    uint8_t c = (uint8_t)rnd();
    if (flt->own_draws)
        flt->own_draws(v);
    for (i = 0; i < rows; i++)
        for (j = 0; j < stride; j++) {
            uint8_t p;
            if (j >= cols)
                p = (uint8_t)rnd(); /* padding garbage: must be ignored */
            else if (kind == FILL_CONST)
                p = c;
            else if (kind == FILL_BINARY)
                p = (rnd() & 1u) ? 255 : 0;
            else if (kind >= FC_FILL_OWN)
                p = flt->own_pixel(kind, i, j, v);
            else
                p = (uint8_t)rnd();
            img[(size_t)i * (size_t)stride + (size_t)j] = p;
        }
}

/* Checks every path on a given image (stride sstride, padding already
 * filled by the caller) against the reference: with scratch_size bytes of
 * scratch filled with 0x5A (no path may rely on zeroed scratch), into an
 * output of row stride cols + dextra filled with 0xA5, each returns
 * ACTAG_OK and its output passes fc_check_output (every pixel, the
 * destination padding untouched); then the filter's more_checks. */
static inline void fc_check_image(const fc_filter *flt, const uint8_t *src, int rows, int cols,
                                  int sstride, int R, int offset, int dextra, const char *what)
{
    int dstride = cols + dextra, f;
    size_t dsize = (size_t)rows * (size_t)dstride;
    size_t scr = flt->scratch_size(rows, cols, R);
    uint8_t *want = (uint8_t *)fc_alloc(dsize);
    uint8_t *out = (uint8_t *)fc_alloc(dsize);
    uint8_t *scratch = (uint8_t *)fc_alloc(scr);
    char off[24] = "";
    char msg[240];

    if (flt->draw_offset)
        snprintf(off, sizeof off, " off=%d", offset);
    flt->reference(src, rows, cols, sstride, R, offset, want, dstride);
    for (f = 0; f < flt->npaths; f++) {
        memset(out, 0xA5, dsize);
        memset(scratch, 0x5A, scr);
        snprintf(msg, sizeof msg, "%s: %s %dx%d R=%d%s sstride=%d dstride=%d", flt->names[f],
                 what, rows, cols, R, off, sstride, dstride);
        TEST_ASSERT_EQUAL_INT_MESSAGE(
            ACTAG_OK, flt->run(f, src, rows, cols, sstride, out, dstride, R, offset, scratch, scr),
            msg);
        fc_check_output(out, want, rows, cols, dstride, msg);
    }
    if (flt->more_checks)
        flt->more_checks(src, rows, cols, sstride, R, offset, want, dstride, what);
    free(want);
    free(out);
    free(scratch);
}

/* One case: an image of fill kind (row stride cols + sextra) through
 * fc_check_image. */
static inline void fc_check_case(const fc_filter *flt, int rows, int cols, int R, int offset,
                                 int kind, int sextra, int dextra)
{
    int sstride = cols + sextra;
    uint8_t *src = (uint8_t *)fc_alloc((size_t)rows * (size_t)sstride);
    char what[32];
    fc_fill(flt, src, rows, cols, sstride, kind);
    snprintf(what, sizeof what, "kind=%d", kind);
    fc_check_image(flt, src, rows, cols, sstride, R, offset, dextra, what);
    free(src);
}

/* ------------------------------------------------ tests of both filters */

/* Strides much larger than cols (sub-images of a larger buffer), the
 * padding full of random bytes that must be neither read nor written:
 * trials random cases from seed, the radii in turn (6 of them). */
static inline void fc_test_wide_strides(const fc_filter *flt, uint32_t seed, int trials,
                                        const int radii[6])
{
    int t;
    rng_state = seed;
    for (t = 0; t < trials; t++) {
        int rows = rnd_range(1, 30), cols = rnd_range(1, 30);
        int sextra = rnd_range(30, 200), dextra = rnd_range(30, 200);
        int off = flt->draw_offset ? flt->draw_offset() : 0;
        int kind = (int)(rnd() % (uint32_t)flt->nkinds);
        fc_check_case(flt, rows, cols, radii[t % 6], off, kind, sextra, dextra);
    }
}

/* trials random cases from seed: sizes 1..max_size, every fourth radius
 * 0..max_radius and the others from radii (nradii of them), every third
 * of a random kind and the others uniform, padding on both sides or not. */
static inline void fc_test_random_images(const fc_filter *flt, uint32_t seed, int trials,
                                         int max_size, const int *radii, int nradii,
                                         int max_radius)
{
    int t;
    rng_state = seed;
    for (t = 0; t < trials; t++) {
        int rows = rnd_range(1, max_size), cols = rnd_range(1, max_size);
        int R = (t % 4 == 3) ? rnd_range(0, max_radius) : radii[rnd() % (uint32_t)nradii];
        int kind = (t % 3 == 0) ? (int)(rnd() % (uint32_t)flt->nkinds) : FILL_UNIFORM;
        int sextra = (t & 1) ? rnd_range(1, 9) : 0;
        int dextra = (t & 2) ? rnd_range(1, 9) : 0;
        int off = flt->draw_offset ? flt->draw_offset() : 0;
        fc_check_case(flt, rows, cols, R, off, kind, sextra, dextra);
    }
}

#endif
