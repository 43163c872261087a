/* Shared by test_median.c and test_threshold.c, which check every code path
 * of a filter against a brute-force reference: their random images'
 * generator (xorshift32: the same numbers on every platform), the edge clamp
 * of the reference's window, buffers, constant images with padding, and the
 * check of a filter's output (every pixel, and the destination padding the
 * caller filled with 0xA5 untouched). */
#ifndef ACTAG_FILTER_CHECK_H
#define ACTAG_FILTER_CHECK_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

#endif
