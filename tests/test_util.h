/* Small helpers shared by the tests in tests/ and tools/sim/ (host only: stdio and malloc are
 * fine here). File reading goes through the host I/O library tools/hostio;
 * these wrappers fail the running Unity test with hostio's message (file and
 * value at fault) instead of returning NULL.
 *
 * Data: TU_DATA is the subset that ships in the repository (data/README.md);
 * TU_FULL_DATA the full data set beside it (../shared/data by default), read
 * only by the tests a program runs when called with --full-data
 * (tu_full_data()); CTest registers those as <name>_full_data and reports
 * them skipped when the full set is absent (cmake/unity.cmake). */
#ifndef ACTAG_TEST_UTIL_H
#define ACTAG_TEST_UTIL_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "actag/actag.h"
#include "actag/common.h"
#include "hostio.h"
#include "unity.h"

#define TU_DATA ACTAG_SOURCE_DIR "/data"
#define TU_FULL_DATA ACTAG_SHARED_DIR "/data"

/* 1 when the program was called with --full-data. */
static inline int tu_full_data(int argc, char **argv)
{
    return argc > 1 && strcmp(argv[1], "--full-data") == 0;
}

/* The emulated suites (a cross build with cmake/toolchains/cortex-m*.cmake,
 * run by CTest under qemu-system-arm, defines ACTAG_TEST_EMULATED; about 50
 * to 100 times slower than the host): TU_EMULATED is 1 there, and
 * TU_TRIALS(n, d) turns a count of random trials n into n / d (at least 1).
 * Every kind of case still runs there; the host suite runs them all. */
#ifdef ACTAG_TEST_EMULATED
#define TU_EMULATED 1
#else
#define TU_EMULATED 0
#endif
#define TU_TRIALS(n, d) (TU_EMULATED ? ((n) / (d) > 0 ? (n) / (d) : 1) : (n))
/* Every step-th of n items under emulation (every one on the host). */
#define TU_STEP(step) (TU_EMULATED ? (step) : 1)

/* Deterministic test PRNG (xorshift64*), independent of the library's. */
static uint64_t tu_state = 0x9e3779b97f4a7c15ull;
static inline void tu_seed(uint64_t s) { tu_state = s ? s : 0x9e3779b97f4a7c15ull; }
static inline uint32_t tu_rand(void)
{
    tu_state ^= tu_state >> 12;
    tu_state ^= tu_state << 25;
    tu_state ^= tu_state >> 27;
    return (uint32_t)((tu_state * 0x2545f4914f6cdd1dull) >> 32);
}
static inline int tu_range(int lo, int hi) /* inclusive */
{
    return lo + (int)(tu_rand() % (uint32_t)(hi - lo + 1));
}
/* A double in [lo, hi] (both ends included) from the same PRNG. */
static inline double tu_uniform(double lo, double hi)
{
    return lo + (hi - lo) * (double)tu_rand() / 4294967295.0;
}

/* Set bits of v: the tests' reference, independent of actag_popcount32. */
static inline int tu_popcount(uint32_t v)
{
    int n = 0;
    for (; v; v &= v - 1)
        n++;
    return n;
}

/* A published family file (hostio_read_codes); returns the number of codes. */
static inline int tu_read_codes(const char *path, uint32_t *codes, int cap)
{
    char err[HOSTIO_ERRLEN];
    size_t n = 0;
    if (hostio_read_codes(path, codes, (size_t)cap, &n, err) != HOSTIO_OK)
        TEST_FAIL_MESSAGE(err);
    return (int)n;
}

/* An 8-bit binary PGM (hostio_pgm_read): malloc'd pixels, stride = cols. */
static inline uint8_t *tu_read_pgm(const char *path, int *rows, int *cols)
{
    char err[HOSTIO_ERRLEN];
    hostio_image im;
    if (hostio_pgm_read(path, &im, err) != HOSTIO_OK)
        TEST_FAIL_MESSAGE(err);
    if (im.depth != 8) {
        hostio_image_free(&im);
        TEST_FAIL_MESSAGE("expected an 8-bit PGM");
    }
    *rows = im.rows;
    *cols = im.cols;
    return (uint8_t *)im.data;
}

/* Whole file as a NUL-terminated malloc'd string (hostio_slurp); len may be NULL. */
static inline char *tu_slurp(const char *path, size_t *len)
{
    char err[HOSTIO_ERRLEN];
    char *s = (char *)hostio_slurp(path, len, err);
    if (!s)
        TEST_FAIL_MESSAGE(err);
    return s;
}

/* Runs a shell command line (hostio_run); its exit status, or -1. */
static inline int tu_run(const char *cmd)
{
    return hostio_run(cmd, NULL);
}

#ifdef ACTAG_FAMILYGEN_PATH
/* Runs actag-familygen with args (shell syntax: redirections allowed). */
static inline int tu_run_gen(const char *args)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "\"%s\" %s", ACTAG_FAMILYGEN_PATH, args);
    return tu_run(cmd);
}
#else
/* Cross builds (the emulated suites): actag-familygen is a host program, so
 * the tests that run it run in the host suite only. There a generator
 * test's main() returns tu_main_without_generator(__FILE__) (familygen_test.h
 * has that main() for the actag-familygen tests): one test that reports
 * IGNORE, and exit status 77, which CTest shows as skipped (SKIP_RETURN_CODE). */
static inline void test_needs_the_host_generator(void)
{
    TEST_IGNORE_MESSAGE("actag-familygen is a host program: see the host suite");
}

static inline int tu_main_without_generator(const char *file)
{
    UnityBegin(file);
    RUN_TEST(test_needs_the_host_generator);
    return UNITY_END() == 0 ? 77 : 1;
}
#endif

/* A valid input to start the checks of bad arguments from: an 8-bit frame
 * over px (rows x cols, stride cols), the pool sonar's geometry (0.1-1.5 m,
 * 1.0472 rad, reference orientation) and actag_params_default with family
 * fam. */
static inline void tu_valid_input(uint8_t *px, int rows, int cols, const actag_family *fam,
                                  actag_frame *f, actag_sonar_geometry *g, actag_params *p)
{
    f->data = px;
    f->rows = rows;
    f->cols = cols;
    f->stride = cols;
    f->depth = 8;
    g->min_range = 0.1f;
    g->max_range = 1.5f;
    g->aperture = 1.0472f;
    g->bearings = NULL;
    g->flags = 0u;
    actag_params_default(p);
    p->family = fam;
}

/* The largest distance (pixels) between corresponding corners of two quads. */
static inline float tu_max_corner_error(const actag_point a[4], const actag_point b[4])
{
    float e = 0.0f;
    int c;
    for (c = 0; c < 4; c++) {
        float d = hypotf(a[c].x - b[c].x, a[c].y - b[c].y);
        e = d > e ? d : e;
    }
    return e;
}

#endif
