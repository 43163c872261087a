/* Small helpers shared by the tests (host only: stdio and malloc are fine here). */
#ifndef ACTAG_TEST_UTIL_H
#define ACTAG_TEST_UTIL_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

/* Reads a published family file (comment lines start with '#'); returns the count. */
static inline int tu_read_codes(const char *path, uint32_t *codes, int cap)
{
    char line[256];
    int n = 0;
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#' || line[0] == '\n')
            continue;
        if (n < cap)
            codes[n] = (uint32_t)strtoul(line, NULL, 16);
        n++;
    }
    fclose(f);
    return n;
}

/* Reads a binary PGM (P5, maxval <= 255). Returns malloc'd pixels or NULL. */
static inline uint8_t *tu_read_pgm(const char *path, int *rows, int *cols)
{
    FILE *f = fopen(path, "rb");
    int w, h, maxv;
    uint8_t *px;
    if (!f)
        return NULL;
    if (fscanf(f, "P5 %d %d %d", &w, &h, &maxv) != 3 || maxv > 255 || w < 1 || h < 1) {
        fclose(f);
        return NULL;
    }
    fgetc(f);
    px = (uint8_t *)malloc((size_t)w * (size_t)h);
    if (px && fread(px, 1, (size_t)w * (size_t)h, f) != (size_t)w * (size_t)h) {
        free(px);
        px = NULL;
    }
    fclose(f);
    *rows = h;
    *cols = w;
    return px;
}

/* Whole file as a NUL-terminated malloc'd string (len may be NULL), or NULL. */
static inline char *tu_slurp(const char *path, long *len)
{
    FILE *f = fopen(path, "rb");
    char *buf;
    long n;
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    n = ftell(f);
    fseek(f, 0, SEEK_SET);
    buf = (char *)calloc((size_t)n + 1, 1);
    if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) {
        free(buf);
        buf = NULL;
    }
    fclose(f);
    if (len)
        *len = n;
    return buf;
}

#endif
