/* Constant-time median filter (Perreault & Hebert 2007), see actag/median.h.
 *
 * Scratch layout (all uint8_t, no alignment needed), 272 bytes for each of
 * the H columns of a vertical strip (median_core: H >= min(cols, 256);
 * column c of the strip at index c, colf after the strip's coarse ones),
 * then the 16-bit ring (at least 2 rows of cols bytes):
 *   colc[c*16 + k]           cumulative coarse histogram of column c: the
 *                            number of its samples v with (v >> 4) <= k
 *   colf[(c*16 + b)*16 + k]  cumulative fine histogram of column c inside
 *                            coarse bin b: samples v with 16b <= v <= 16b+k
 * Cumulative (rather than plain) histograms make both median searches a
 * branch-free count of the lanes <= a rank (the lanes are nondecreasing),
 * and a column update a 16-lane add of a step mask. The fine histograms of
 * one column are contiguous, so sliding a column down touches one 256-byte
 * block (storing them bin-major instead was slower: 4 KiB aliasing).
 *
 * Work per pixel: one column update, one 16-lane slide of the coarse kernel
 * histogram, one of the fine kernel histogram of the median's coarse bin,
 * and two lane counts. When the median changes coarse bin, that bin's fine
 * histogram is caught up lazily from the column where it was last valid,
 * or rebuilt from its 2R+1 columns when that is cheaper; either way at most
 * 2 min(gap, R+1) column reads, so over a row each bin costs O(cols) and
 * the total per pixel is bounded independently of R.
 *
 * Speed (x86-64, SSE2 path, gcc -O3, one core): radii up to 7 take
 * median_rows16() (median_rows.h), a sliding histogram shared by 16 output rows: at
 * R = 4 on the 58 pool frames (530 x 512) 43.8 instructions per pixel
 * (callgrind), against 91.3 for the constant-time median_strip8 that
 * served them before (which had taken 124 to 89 with 8-bit kernel lanes),
 * and about 1.5x less time. Its cost depends on the content: the medians of
 * 16 neighbouring rows are found by a scan of the levels between them, so
 * images whose rows alternate between several far apart levels (synthetic
 * bands of 3-5 grey levels a few rows high) take up to about 2x the
 * constant-time path's instructions; every frame of bench/worst_bench
 * (checkerboards, speckle, blobs, stripes) takes fewer. Radii >= 8 use the
 * constant-time path (about 2 ms up to R = 16; 3 ms at R = 127, where the
 * O(R) set-up per row shows, with the whole frame in one strip; with the
 * minimum scratch, 256 column histograms, frames wider than 256 columns
 * take strips, up to ~1.7x the time at large radii: median_core,
 * median_strip_agg). The portable path computes the same bytes (tests
 * check both); for R <= 7 it uses median_quad() (median_quad.h; a sliding
 * histogram shared by four rows), which without SIMD is about 3x faster
 * than the constant-time scheme at R = 4, and on Cortex-M4/M7
 * median_quad_dsp(), which at R >= 3 takes eight rows a pass where it can
 * (oct_block; about 52 instructions per pixel at R = 4, -O2, 78 with four
 * rows). With NEON (AArch64, ARMv7-A) the vector paths are the SSE2 ones,
 * median_strip8, median_rows16 and median_net16, on the NEON primitives
 * of median_neon.h: the same bytes. On x86-64 processors with AVX2
 * (chosen at run time, cpu_x86.h) radii up to 7 take median_rows32
 * instead, the same code on 32 rows with 32-byte vectors (median_avx2.h):
 * 8.5 M instructions per pool frame at R = 4 against 11.9 M, 10-20 % less
 * time (bench/stage_bench, bench/actag_bench; the run-to-run spread is
 * wide; figures from before the networks below took R = 4).
 * At R = 4 (the paper's radius, the default) the vector paths take
 * sorting networks on 2 x 2 tiles of outputs instead (median_net.h, on
 * the networks of median_net9.h from tools/gen_median_net.py), one text
 * for both widths: median_net32 on AVX2 processors, 3.7 M instructions
 * per pool frame and 0.37 ms against median_rows32's 8.5 M and 0.85 ms,
 * side by side (2026-12-06); median_net16 with SSE2 or NEON, 8.5 M
 * against median_rows16's 12.0 M (callgrind, 58 frames) and 0.52-0.55
 * ms against 0.95-1.04 (-DACTAG_NO_AVX2 builds, side by side,
 * 2026-12-06).
 * Each keeps about 14 KB of stack (the shared pieces of two rows by 256
 * columns; gcc -fstack-usage: 13.8-14.2 KB on x86-64, AArch64, ARMv7),
 * in a frame of its own (not inlined). */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/median.h"
#include "cpu_x86.h"
#include "frame16.h"
#include "median_bands.h"

#include <string.h>

#if defined(__SSE2__) && !defined(ACTAG_NO_SIMD)
#define MEDIAN_SSE2 1
#include <emmintrin.h>
#elif defined(__ARM_NEON) && !defined(ACTAG_NO_SIMD) && !defined(__ARM_BIG_ENDIAN)
/* AArch64 and ARMv7-A with NEON (median_neon.h); little-endian only: the
 * medians are read back from vectors in memory as bytes (r16_store). */
#define MEDIAN_NEON 1
#endif
/* A 16-byte vector unit: median_strip8, median_rows16 and median_net16,
 * each written once for SSE2 and NEON. */
#if defined(MEDIAN_SSE2) || defined(MEDIAN_NEON)
#define MEDIAN_SIMD 1
#endif
/* x86-64 with a compiler that can build the AVX2 path (cpu_x86.h):
 * median_rows32 and median_net32 beside median_rows16 and median_net16,
 * chosen at run time (median_block). */
#if defined(MEDIAN_SSE2) && ACTAG__AVX2
#define MEDIAN_AVX2 1
#endif

/* Fine histogram of column c for coarse bin b. */
#define FINE(colf, c, b) ((colf) + ((size_t)(c) * 16u + (size_t)(b)) * 16u)

static int clampi(int v, int lo, int hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

/* ----------------------------------------------------------------------
 * Source rows. 8-bit frames are read in place; 16-bit frames are scaled to
 * 8 bits a row at a time into a ring of K rows in the scratch, and a row
 * still in the ring is not converted again. The scaling is the library's
 * (v * 255 + max / 2) / max, computed as a multiply and a shift that give
 * the exact quotient for every numerator below 2^24 (Granlund and
 * Montgomery 1994, theorem 4.2: m = floor(2^(24+l) / max) + 1 with
 * 2^l >= max; the numerator is at most 65535 * 255 + 32767 < 2^24).
 * ---------------------------------------------------------------------- */
#ifdef MEDIAN_AVX2
#define RING_MAX 48 /* median_rows32 reads up to 2R + 32 = 46 rows at once */
#else
#define RING_MAX 32
#endif

typedef struct {
    const uint8_t *src8;  /* 8-bit frame, or NULL */
    const uint8_t *src16; /* 16-bit frame (bytes; samples read with memcpy) */
    size_t stride;        /* src8: bytes; src16: samples */
    uint32_t half;        /* max / 2 */
    uint64_t magic;       /* see above (0 when max is 0) */
    unsigned shift;
    uint8_t *ring;        /* K rows of cols bytes */
    size_t cols;
    size_t c0, c1;        /* 16-bit: only columns c0 .. c1-1 are scaled */
    int k;
    int tag[RING_MAX];    /* row held by each ring slot, -1 for none */
} rowsrc;

/* Columns c0 .. c1-1 of the 16-bit row at p, scaled to 8 bits into d. */
static void scale_row16(const rowsrc *rs, const uint8_t *p, uint8_t *d)
{
    size_t c;
    for (c = rs->c0; c < rs->c1; c++) {
        uint32_t v = frame16_load(p + 2u * c);
        uint64_t q = ((uint64_t)(v * 255u + rs->half) * rs->magic) >> rs->shift;
        /* a sample above the given maximum (actag_median_filter_inplace's
         * max16) reads as white, not modulo 256 */
        d[c] = (uint8_t)(q > 255u ? 255u : q);
    }
}

/* Row r as 8-bit samples; for 16-bit frames not in ring slot `avoid` (so
 * that two rows fetched together do not evict each other), and only
 * columns c0 .. c1-1 of it are valid (the strip being filtered). */
static const uint8_t *get_row(rowsrc *rs, int r, int avoid)
{
    int slot, i;
    uint8_t *d;
    const uint8_t *p;
    if (rs->src8 != NULL)
        return rs->src8 + (size_t)r * rs->stride;
    for (i = 0; i < rs->k; i++)
        if (rs->tag[i] == r)
            return rs->ring + (size_t)i * rs->cols;
    slot = r % rs->k;
    if (slot == avoid)
        slot = (slot + 1) % rs->k;
    d = rs->ring + (size_t)slot * rs->cols;
    p = rs->src16 + 2u * (size_t)r * rs->stride;
    scale_row16(rs, p, d);
    rs->tag[slot] = r;
    return d;
}

/* The ring slot holding p (a row get_row returned), -1 for 8-bit frames. */
static int row_slot(const rowsrc *rs, const uint8_t *p)
{
    return rs->src8 != NULL ? -1 : (int)((size_t)(p - rs->ring) / rs->cols);
}

/* Sets up the 16-bit scaling by the frame's maximum mx: the multiplier. */
static void rowsrc_init16(rowsrc *rs, const uint8_t *src, size_t stride, uint32_t mx)
{
    unsigned l = 0;
    int r;
    rs->src8 = NULL;
    rs->src16 = src;
    rs->stride = stride;
    rs->half = mx / 2u;
    while (((uint32_t)1u << l) < mx)
        l++;
    rs->shift = 24u + l;
    rs->magic = mx ? ((uint64_t)1u << rs->shift) / mx + 1u : 0u;
    for (r = 0; r < RING_MAX; r++)
        rs->tag[r] = -1;
}

/* step_mask[t][k] = (k >= t): adding step_mask[t] to a cumulative
 * histogram adds one sample to bin t. */
static const uint8_t step_mask[16][16] = {
    {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1},
    {0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1},
    {0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1},
    {0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1},
    {0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1},
    {0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1},
    {0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1},
    {0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1},
    {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1},
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1},
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1},
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1},
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1},
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1},
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1},
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1}};

/* Adds one sample of level t (0..15) to a 16-lane cumulative histogram
 * (set-up only). */
static void step_add(uint8_t *cnt, unsigned t)
{
    int k;
    for (k = 0; k < 16; k++)
        cnt[k] = (uint8_t)(cnt[k] + step_mask[t][k]);
}

/* The 16-lane primitives (SSE2, NEON, portable). */
#include "median_lanes.h"

#ifndef MEDIAN_SIMD
#include "median_quad.h"
#endif /* !MEDIAN_SIMD */

/* Bytes of one column's histograms (16 coarse + 256 fine 8-bit lanes). */
#define COL_BYTES 272u

/* The column histograms of image columns hb .. hb+span-1 (stored from hist
 * on, coarse ones first, see the top of the file) for output row 0: rows
 * clamp(-R..R). For 16-bit frames, sets the ring to scale the strip's
 * columns only, with no row left in it. */
static void cols_init(rowsrc *rs, int rows, int R, size_t hb, size_t span, uint8_t *hist)
{
    uint8_t *const colc = hist;
    uint8_t *const colf = hist + span * 16u;
    int k;
    rs->c0 = hb;
    rs->c1 = hb + span;
    for (k = 0; k < RING_MAX; k++)
        rs->tag[k] = -1;
    memset(hist, 0, span * COL_BYTES);
    for (k = -R; k <= R; k++) {
        const uint8_t *s = get_row(rs, clampi(k, 0, rows - 1), -1) + hb;
        size_t c;
        for (c = 0; c < span; c++) {
            unsigned v = s[c];
            step_add(colc + c * 16u, v >> 4);
            step_add(FINE(colf, c, v >> 4), v & 15u);
        }
    }
}

/* Slides every column histogram from output row i-1 down to row i. (A
 * separate pass: doing it as the kernel reaches each column was slower.) */
static void cols_slide(rowsrc *rs, int rows, int R, int i, size_t hb, size_t span, uint8_t *hist)
{
    uint8_t *const colc = hist;
    uint8_t *const colf = hist + span * 16u;
    int rout = clampi(i - R - 1, 0, rows - 1);
    int rin = clampi(i + R, 0, rows - 1);
    if (rout != rin) {
        const uint8_t *so = get_row(rs, rout, -1);
        const uint8_t *si = get_row(rs, rin, row_slot(rs, so));
        size_t c;
        so += hb;
        si += hb;
        /* Byte offsets: bin v >> 4's fine block of a column is (v & 0xF0)
         * bytes after the column's first; FINE(colf, c, b) spelt out. */
        for (c = 0; c < span; c++) {
            unsigned vin = si[c], vout = so[c];
            uint8_t *cf = colf + c * 256u;
            col_update(colc + c * 16u, cf + (vin & 0xF0u), cf + (vout & 0xF0u), vin, vout);
        }
    }
}

/* The constant-time filter on the output columns hb+s0 .. hb+s1-1 of every
 * row, with the column histograms of image columns hb .. hb+span-1 only
 * (the strip and the R columns on each side that its windows and the first
 * kernel slide read, clamped to the image), stored from `hist` on. Column
 * indices below are relative to hb (dst too points at column hb), and cols
 * is the number of image columns from hb on: the clamp at the right edge
 * is cols - 1, and the clamp at 0 is only reached when hb is 0 (when hb >
 * 0, s0 = R + 1, so no window of the strip reaches left of hb). */
static void median_strip(rowsrc *rs, int rows, int cols, int s0, int s1, size_t hb, size_t span,
                         uint8_t *dst, size_t dstride, int R, uint8_t *hist)
{
    uint8_t *const colc = hist;
    uint8_t *const colf = hist + span * 16u;
    h16 hf[16];    /* parked fine kernel histograms, per coarse bin */
    int last[16];  /* column at which hf[b] was valid */
    h16 hc;        /* coarse kernel histogram */
    h16 cur;       /* fine kernel histogram of coarse bin curb */
    unsigned curb; /* coarse bin of the previous pixel's median */
    int i, j, k;
    /* Rank (0-based) of the median among the (2R+1)^2 samples. */
    const unsigned half = (unsigned)((2 * R + 1) * (2 * R + 1)) / 2u;

/* Histograms of column c (relative to hb). */
#define CC(c) (colc + (size_t)(c) * 16u)
#define CF(c, b) FINE(colf, c, b)

    cols_init(rs, rows, R, hb, span, hist);

    for (i = 0; i < rows; i++) {
        uint8_t *d = dst + (size_t)i * dstride;

        if (i > 0)
            cols_slide(rs, rows, R, i, hb, span, hist);

        /* Kernel histograms start at column s0-1 (columns clamp(s0-R-1 ..
         * s0+R-1)), so that the first slide gives column s0. cur starts as
         * bin 0's fine histogram; the other bins are rebuilt on first use. */
        h16_zero(&hc);
        h16_zero(&cur);
        curb = 0;
        for (k = s0 - R - 1; k <= s0 + R - 1; k++) {
            int c = clampi(k, 0, cols - 1);
            h16_add(&hc, CC(c));
            h16_add(&cur, CF(c, 0));
        }
        for (k = 0; k < 16; k++)
            last[k] = s0 - 2 * R - 2;

        for (j = s0; j < s1; j++) {
            unsigned b, f, below;
            int ca = j + R < cols ? j + R : cols - 1; /* column entering */
            int cr = j - R - 1 > 0 ? j - R - 1 : 0;   /* column leaving */
            h16 spec;

            h16_slide(&hc, &hc, CC(ca), CC(cr));
            /* Speculate that the median stays in coarse bin curb (it nearly
             * always does): sliding cur now, before the coarse search is
             * done, keeps the dependency chain per pixel short. */
            h16_slide(&spec, &cur, CF(ca, curb), CF(cr, curb));

            b = h16_count_le(&hc, half);
            if (b == curb) {
                cur = spec;
            } else {
                /* Park cur (valid at j-1); bring bin b's fine histogram up
                 * to column j from where it was parked, or rebuild it from
                 * its 2R+1 columns when that is cheaper. */
                int gap = j - last[b];
                hf[curb] = cur;
                last[curb] = j - 1;
                if (2 * gap > 2 * R + 1) {
                    h16_zero(&cur);
                    for (k = j - R; k <= j + R; k++)
                        h16_add(&cur, CF(clampi(k, 0, cols - 1), b));
                } else {
                    cur = hf[b];
                    for (k = last[b] + 1; k <= j; k++)
                        h16_slide(&cur, &cur, CF(k + R < cols ? k + R : cols - 1, b),
                                  CF(k - R - 1 > 0 ? k - R - 1 : 0, b));
                }
                curb = b;
            }

            /* below = samples in coarse bins < curb; the median is the sample
             * of rank half - below inside bin curb. */
            below = curb > 0 ? h16_get(&hc, curb - 1) : 0u;
            f = h16_count_le(&cur, half - below);
            d[j] = (uint8_t)(curb * 16u + f);
        }
    }
#undef CC
#undef CF
}

#ifdef MEDIAN_SIMD
/* Radii whose kernel holds at most 255 samples ((2R+1)^2 <= 225). */
#define MEDIAN_H8_MAX_R 7

/* bcast8[v]: 16 lanes of v, for the ranks 0 .. 112 (R <= 7). */
#define BC8(v) {v, v, v, v, v, v, v, v, v, v, v, v, v, v, v, v}
#define BC8x4(v) BC8(v), BC8((v) + 1), BC8((v) + 2), BC8((v) + 3)
#define BC8x16(v) BC8x4(v), BC8x4((v) + 4), BC8x4((v) + 8), BC8x4((v) + 12)
static const uint8_t bcast8[128][16] = {BC8x16(0),  BC8x16(16), BC8x16(32), BC8x16(48),
                                        BC8x16(64), BC8x16(80), BC8x16(96), BC8x16(112)};
#undef BC8x16
#undef BC8x4
#undef BC8

/* median_strip for R <= MEDIAN_H8_MAX_R: the same column histograms and
 * the same search, but the kernel histograms have 8-bit lanes (a kernel
 * holds (2R+1)^2 <= 225 samples; lanes wrap modulo 256 between the add
 * and the subtract of a slide, the results are exact), so a slide is one
 * add and one subtract of a register, and a search a min, a compare and a
 * mask (about half median_strip's instructions per pixel). Same output. */
static void median_strip8(rowsrc *rs, int rows, int cols, int s0, int s1, size_t hb, size_t span,
                          uint8_t *dst, size_t dstride, int R, uint8_t *hist)
{
    uint8_t *const colc = hist;
    uint8_t *const colf = hist + span * 16u;
    vu8 hf[16];     /* parked fine kernel histograms, per coarse bin */
    int last[16];       /* column at which hf[b] was valid */
    vu8 hc;         /* coarse kernel histogram */
    vu8 cur;        /* fine kernel histogram of coarse bin curb */
    uint8_t below[17];  /* below[b]: kernel samples in coarse bins < b */
    unsigned curb;      /* coarse bin of the previous pixel's median */
    int i, j, k;
    /* Rank (0-based) of the median among the (2R+1)^2 samples. */
    const unsigned half = (unsigned)((2 * R + 1) * (2 * R + 1)) / 2u;
    const vu8 vhalf = v_dup(half);

#define CC(c) (colc + (size_t)(c) * 16u)
#define CF(c, b) FINE(colf, c, b)

    cols_init(rs, rows, R, hb, span, hist);
    below[0] = 0;

    for (i = 0; i < rows; i++) {
        uint8_t *d = dst + (size_t)i * dstride;

        if (i > 0)
            cols_slide(rs, rows, R, i, hb, span, hist);

        /* As in median_strip: the kernels start at column s0-1. */
        hc = cur = v_zero();
        curb = 0;
        for (k = s0 - R - 1; k <= s0 + R - 1; k++) {
            int c = clampi(k, 0, cols - 1);
            hc = v_add(hc, load16(CC(c)));
            cur = v_add(cur, load16(CF(c, 0)));
        }
        for (k = 0; k < 16; k++)
            last[k] = s0 - 2 * R - 2;

        /* The column entering the kernel at pixel j is ca = min(j + R,
         * cols - 1), the one leaving cr = max(j - R - 1, 0): both move on
         * by one column per pixel, except ca from j = cols - 1 - R on and
         * cr up to j = R + 1, so the row is cut into at most three runs
         * with fixed pointer steps (no clamp per pixel). */
        for (j = s0; j < s1;) {
            const int ia = j < cols - 1 - R, ir = j >= R + 1;
            const size_t sa = ia ? 16u : 0u, sr = ir ? 16u : 0u;
            const size_t fa = ia ? 256u : 0u, fr = ir ? 256u : 0u;
            int jend = s1;
            const uint8_t *pca, *pcr, *pfa, *pfr;
            if (!ir && jend > R + 1)
                jend = R + 1;
            if (ia && jend > cols - 1 - R)
                jend = cols - 1 - R;
            pca = CC(j + R < cols ? j + R : cols - 1);
            pcr = CC(j - R - 1 > 0 ? j - R - 1 : 0);
            pfa = CF(j + R < cols ? j + R : cols - 1, 0);
            pfr = CF(j - R - 1 > 0 ? j - R - 1 : 0, 0);
            for (; j < jend; j++) {
                unsigned b, f;
                vu8 spec;

                hc = v_sub(v_add(hc, load16(pca)), load16(pcr));
                spec = v_sub(v_add(cur, load16(pfa + curb * 16u)),
                                    load16(pfr + curb * 16u));
                pca += sa;
                pcr += sr;
                pfa += fa;
                pfr += fr;

                b = h8_count_le(hc, vhalf);
                if (b == curb) {
                    cur = spec;
                } else {
                    int gap = j - last[b];
                    hf[curb] = cur;
                    last[curb] = j - 1;
                    if (2 * gap > 2 * R + 1) {
                        cur = v_zero();
                        for (k = j - R; k <= j + R; k++)
                            cur = v_add(cur, load16(CF(clampi(k, 0, cols - 1), b)));
                    } else {
                        cur = hf[b];
                        for (k = last[b] + 1; k <= j; k++)
                            cur = v_sub(
                                v_add(cur,
                                             load16(CF(k + R < cols ? k + R : cols - 1, b))),
                                load16(CF(k - R - 1 > 0 ? k - R - 1 : 0, b)));
                    }
                    curb = b;
                }

                /* The median is the sample of rank half - below[curb]
                 * inside coarse bin curb (below[b] = hc's lane b - 1). */
                store16(below + 1, hc);
                f = h8_count_le(cur, load16(bcast8[half - below[curb]]));
                d[j] = (uint8_t)(curb * 16u + f);
            }
        }
    }
#undef CC
#undef CF
}

/* ----------------------------------------------------------------------
 * Radii up to 7 with SSE2 or NEON: median_rows16, a sliding histogram
 * shared by 16 output rows; on x86-64 processors with AVX2 (chosen at run
 * time: median_block) median_rows32, the same code on 32 rows a pass with
 * 32-byte vectors: 2R + 32 row updates for 32 rows instead of 2 (2R + 16),
 * each from offsets computed 32 columns at a time, and one median scan for
 * 32 rows instead of two. Both from median_rows.h.
 * ---------------------------------------------------------------------- */
#define MEDIAN_ROWS_MAX_R 7

/* Where the scans of rb_medians start: lo <= the median of every lane of
 * the low group, hi >= that of every lane of the high group; when grouped,
 * the lanes whose median is >= mid form the high group. */
typedef struct {
    unsigned lo, hi, mid, grouped;
} rb_refs;

#define RB_FN_(x, n) x##n
#define RB_FN2(x, n) RB_FN_(x, n)
#define RB_FN(x) RB_FN2(x, RB_LANES)

/* median_rows16 on the 16-byte primitives above */
#define RB_LANES 16
#define RB_ATTR
#define v_load load16
#define v_store store16
#define v_hmin r16_hmin
#define v_hmax r16_hmax
#include "median_rows.h"
#undef RB_LANES
#undef RB_ATTR
#undef v_load
#undef v_store
#undef v_hmin
#undef v_hmax

#ifdef MEDIAN_AVX2
/* median_rows32: the same text on median_avx2.h's 32-byte primitives */
#include "median_avx2.h"
#define RB_LANES 32
#define RB_ATTR ACTAG__AVX2_TARGET
#define vu8 yu8
#define v_load y_load
#define v_store y_store
#define v_zero y_zero
#define v_dup y_dup
#define v_add y_add
#define v_sub y_sub
#define v_nonneg y_nonneg
#define v_select y_select
#define v_zip y_zip
#define v_hmin y_hmin
#define v_hmax y_hmax
#define lanes ylanes
#define lanes_all ylanes_all
#define lanes_none ylanes_none
#define lanes_any ylanes_any
#define lanes_not ylanes_not
#define lanes_nonneg ylanes_nonneg
#define lanes_any_neg ylanes_any_neg
#define lanes_all_neg ylanes_all_neg
#include "median_rows.h"
#undef RB_LANES
#undef RB_ATTR
#undef vu8
#undef v_load
#undef v_store
#undef v_zero
#undef v_dup
#undef v_add
#undef v_sub
#undef v_nonneg
#undef v_select
#undef v_zip
#undef v_hmin
#undef v_hmax
#undef lanes
#undef lanes_all
#undef lanes_none
#undef lanes_any
#undef lanes_not
#undef lanes_nonneg
#undef lanes_any_neg
#undef lanes_all_neg
#endif
#undef RB_FN
#undef RB_FN2
#undef RB_FN_
#endif /* MEDIAN_SIMD */

#ifdef MEDIAN_SIMD
/* ----------------------------------------------------------------------
 * Radius 4: median_net16 (SSE2, NEON) and, on x86-64 processors with
 * AVX2, median_net32: sorting networks on 2 x 2 tiles of outputs, one
 * tile a byte lane, from median_net.h (which explains the scheme) on the
 * vector primitives of each width. The same bytes as the histogram
 * paths.
 * ---------------------------------------------------------------------- */
#define MN_FN_(x, n) x##n
#define MN_FN2(x, n) MN_FN_(x, n)
#define MN_FN(x) MN_FN2(x, MN_LANES)

/* median_net16 on the 16-byte primitives (mn_split16, mn_zip16 beside
 * them); 256-column passes as with 32 lanes (a pass computes 4 positions
 * past its tiles: with 128-column passes 4.5 % more instructions on the
 * pool frames, about 2 % more time) */
#define MN_LANES 16
#define MN_NT 128
#define MN_V vu8
#define MN_MIN v_min
#define MN_MAX v_max
#define MN_LD load16
#define MN_ST store16
#define MN_ATTR
#include "median_net.h"

#ifdef MEDIAN_AVX2
/* median_net32: the same text on 32-byte vectors */
#define MN_LANES 32
#define MN_NT 128
#define MN_V __m256i
#define MN_MIN _mm256_min_epu8
#define MN_MAX _mm256_max_epu8
#define MN_LD(p) _mm256_loadu_si256((const __m256i *)(const void *)(p))
#define MN_ST(p, v) _mm256_storeu_si256((__m256i *)(void *)(p), (v))
#define MN_ATTR ACTAG__AVX2_TARGET

/* Bytes p[0], p[2], .. p[62] to e and p[1], .. p[63] to o. */
ACTAG__AVX2_TARGET static void mn_split32(const uint8_t *p, uint8_t *e, uint8_t *o)
{
    const __m256i lo = _mm256_set1_epi16(0x00FF);
    const __m256i a = MN_LD(p), b = MN_LD(p + 32);
    const __m256i ev = _mm256_packus_epi16(_mm256_and_si256(a, lo), _mm256_and_si256(b, lo));
    const __m256i od = _mm256_packus_epi16(_mm256_srli_epi16(a, 8), _mm256_srli_epi16(b, 8));
    /* packus works within 128-bit halves: quads a0 b0 a1 b1 -> a0 a1 b0 b1 */
    MN_ST(e, _mm256_permute4x64_epi64(ev, 0xD8));
    MN_ST(o, _mm256_permute4x64_epi64(od, 0xD8));
}

/* a0 b0 a1 b1 .. a31 b31 to d (unpack works within 128-bit halves) */
ACTAG__AVX2_TARGET static void mn_zip32(__m256i a, __m256i b, uint8_t *d)
{
    const __m256i lo = _mm256_unpacklo_epi8(a, b), hi = _mm256_unpackhi_epi8(a, b);
    MN_ST(d, _mm256_permute2x128_si256(lo, hi, 0x20));
    MN_ST(d + 32, _mm256_permute2x128_si256(lo, hi, 0x31));
}

#include "median_net.h"
#endif /* MEDIAN_AVX2 */
#undef MN_FN
#undef MN_FN2
#undef MN_FN_
#endif /* MEDIAN_SIMD */

/* Large radii (2R + 1 > H / 2 with H column histograms): strips of up to
 * H / 2 output columns s0 .. s1-1 (absolute here, W = s1 - s0 <= 2R + 1),
 * independent of R. A window position p stands for image column clamp(p).
 * Of the positions a kernel of the strip covers, only those that leave as
 * it slides, L = s0-R-1 .. s1-R-2, and those that enter, E = s0+R ..
 * s1+R-1, need a histogram each (image columns lb .. le and eb .. ee, at
 * most W each); the positions M = s1-R-1 .. s0+R-1 are in every kernel of
 * the strip (its first one at s0 - 1 included) and are kept as one sum,
 * with 16-bit counts (ac, af), slid down a sample per position and row. A
 * kernel is rebuilt from M's sum and the L and E columns it covers. The
 * counts are exact, so the output is that of median_strip. */
static void median_strip_agg(rowsrc *rs, int rows, int cols, int s0, int s1, uint8_t *dst,
                             size_t dstride, int R, uint8_t *hist)
{
    const int lb = clampi(s0 - R - 1, 0, cols - 1), le = clampi(s1 - R - 2, 0, cols - 1);
    const int eb = clampi(s0 + R, 0, cols - 1), ee = clampi(s1 + R - 1, 0, cols - 1);
    const int mlo = s1 - R - 1, mhi = s0 + R - 1; /* M; empty when W = 2R + 1 */
    const size_t nl = (size_t)(le - lb + 1), ne = (size_t)(ee - eb + 1);
    uint8_t *const colcl = hist, *const colfl = hist + nl * 16u;
    uint8_t *const colce = hist + nl * COL_BYTES, *const colfe = colce + ne * 16u;
    h16 ac, af[16]; /* M's coarse and fine histograms */
    h16 hf[16], hc, cur;
    int last[16];
    unsigned curb;
    int i, j, k, p;
    const unsigned half = (unsigned)((2 * R + 1) * (2 * R + 1)) / 2u;

    rs->c0 = (size_t)lb;
    rs->c1 = (size_t)ee + 1u;
    for (k = 0; k < RING_MAX; k++)
        rs->tag[k] = -1;

    /* Column histograms and M's sum for row 0: rows clamp(-R..R). */
    memset(hist, 0, (nl + ne) * COL_BYTES);
    h16_zero(&ac);
    for (k = 0; k < 16; k++)
        h16_zero(&af[k]);
    for (k = -R; k <= R; k++) {
        const uint8_t *s = get_row(rs, clampi(k, 0, rows - 1), -1);
        size_t c;
        for (c = 0; c < nl; c++) {
            unsigned v = s[(size_t)lb + c];
            step_add(colcl + c * 16u, v >> 4);
            step_add(FINE(colfl, c, v >> 4), v & 15u);
        }
        for (c = 0; c < ne; c++) {
            unsigned v = s[(size_t)eb + c];
            step_add(colce + c * 16u, v >> 4);
            step_add(FINE(colfe, c, v >> 4), v & 15u);
        }
        for (p = mlo; p <= mhi; p++) {
            unsigned v = s[clampi(p, 0, cols - 1)];
            h16_add(&ac, step_mask[v >> 4]);
            h16_add(&af[v >> 4], step_mask[v & 15u]);
        }
    }

    for (i = 0; i < rows; i++) {
        uint8_t *d = dst + (size_t)i * dstride;

        if (i > 0) {
            int rout = clampi(i - R - 1, 0, rows - 1);
            int rin = clampi(i + R, 0, rows - 1);
            if (rout != rin) {
                const uint8_t *so = get_row(rs, rout, -1);
                const uint8_t *si = get_row(rs, rin, row_slot(rs, so));
                size_t c;
                for (c = 0; c < nl; c++) {
                    unsigned vin = si[(size_t)lb + c], vout = so[(size_t)lb + c];
                    col_update(colcl + c * 16u, FINE(colfl, c, vin >> 4),
                               FINE(colfl, c, vout >> 4), vin, vout);
                }
                for (c = 0; c < ne; c++) {
                    unsigned vin = si[(size_t)eb + c], vout = so[(size_t)eb + c];
                    col_update(colce + c * 16u, FINE(colfe, c, vin >> 4),
                               FINE(colfe, c, vout >> 4), vin, vout);
                }
                for (p = mlo; p <= mhi; p++) {
                    int c2 = clampi(p, 0, cols - 1);
                    unsigned vin = si[c2], vout = so[c2];
                    h16_slide(&ac, &ac, step_mask[vin >> 4], step_mask[vout >> 4]);
                    h16_add(&af[vin >> 4], step_mask[vin & 15u]);
                    h16_sub(&af[vout >> 4], step_mask[vout & 15u]);
                }
            }
        }

        /* The kernel at s0 - 1: M's sum and the L positions. */
        hc = ac;
        cur = af[0];
        curb = 0;
        for (p = s0 - R - 1; p <= s1 - R - 2; p++) {
            size_t c = (size_t)(clampi(p, 0, cols - 1) - lb);
            h16_add(&hc, colcl + c * 16u);
            h16_add(&cur, FINE(colfl, c, 0));
        }
        for (k = 0; k < 16; k++)
            last[k] = s0 - 2 * R - 2;

        for (j = s0; j < s1; j++) {
            unsigned b, f, below;
            size_t ca = (size_t)((j + R < cols ? j + R : cols - 1) - eb); /* entering, in E */
            size_t cr = (size_t)((j - R - 1 > 0 ? j - R - 1 : 0) - lb);   /* leaving, in L */
            h16 spec;

            h16_slide(&hc, &hc, colce + ca * 16u, colcl + cr * 16u);
            h16_slide(&spec, &cur, FINE(colfe, ca, curb), FINE(colfl, cr, curb));
            b = h16_count_le(&hc, half);
            if (b == curb) {
                cur = spec;
            } else {
                int gap = j - last[b];
                hf[curb] = cur;
                last[curb] = j - 1;
                if (2 * gap > s1 - s0 + 1) {
                    /* positions j-R .. s1-R-2 (in L), M, s0+R .. j+R (in E) */
                    cur = af[b];
                    for (k = j - R; k <= s1 - R - 2; k++)
                        h16_add(&cur, FINE(colfl, clampi(k, 0, cols - 1) - lb, b));
                    for (k = s0 + R; k <= j + R; k++)
                        h16_add(&cur, FINE(colfe, clampi(k, 0, cols - 1) - eb, b));
                } else {
                    cur = hf[b];
                    for (k = last[b] + 1; k <= j; k++)
                        h16_slide(&cur, &cur, FINE(colfe, (k + R < cols ? k + R : cols - 1) - eb, b),
                                  FINE(colfl, (k - R - 1 > 0 ? k - R - 1 : 0) - lb, b));
                }
                curb = b;
            }
            below = curb > 0 ? h16_get(&hc, curb - 1) : 0u;
            f = h16_count_le(&cur, half - below);
            d[j] = (uint8_t)(curb * 16u + f);
        }
    }
}

/* The row-block median of the build (see median_core): its rows a pass,
 * the largest radius it serves, and the function. */
#if defined(MEDIAN_SIMD)
#define MEDIAN_BLOCK_ROWS 16
#define MEDIAN_BLOCK_MAX_R MEDIAN_ROWS_MAX_R
#define MEDIAN_BLOCK median_rows16
#elif defined(MEDIAN_DSP)
#define MEDIAN_BLOCK_ROWS 4
#define MEDIAN_BLOCK_MAX_R MEDIAN_QUAD_MAX_R
#define MEDIAN_BLOCK median_quad_dsp
#else
#define MEDIAN_BLOCK_ROWS 4
#define MEDIAN_BLOCK_MAX_R MEDIAN_QUAD_MAX_R
#define MEDIAN_BLOCK median_quad
#endif

/* Output rows y0 .. y1-1 by the row-block median: median_rows32 when the
 * processor has AVX2 and the block's 2R + 32 source rows are at hand (8-bit
 * rows, or a 16-bit ring that holds them all), else MEDIAN_BLOCK; at R = 4
 * with a vector unit the sorting networks instead (median_net32 or
 * median_net16: 10 source rows, which every ring given here holds). The
 * same bytes either way. */
static void median_block(rowsrc *rs, int rows, int cols, uint8_t *dst, size_t dstride, int R,
                         int y0, int y1)
{
#ifdef MEDIAN_AVX2
    if ((rs->src8 != NULL || rs->k >= 2 * R + 32) && actag__cpu_avx2()) {
        if (R == 4)
            median_net32(rs, rows, cols, dst, dstride, y0, y1);
        else
            median_rows32(rs, rows, cols, dst, dstride, R, y0, y1);
        return;
    }
#endif
#ifdef MEDIAN_SIMD
    if (R == 4) {
        median_net16(rs, rows, cols, dst, dstride, y0, y1);
        return;
    }
#endif
    MEDIAN_BLOCK(rs, rows, cols, dst, dstride, R, y0, y1);
}

/* Rows a pass of median_block's histogram paths on 8-bit rows (the unit
 * of the in-place bands' height; the R = 4 networks take two rows a pass
 * and, for an odd count, compute one more row and drop it). */
static int median_block_rows(void)
{
#ifdef MEDIAN_AVX2
    if (actag__cpu_avx2())
        return 32;
#endif
    return MEDIAN_BLOCK_ROWS;
}

/* The filter on checked arguments; 16-bit frames (rs->src8 NULL) are
 * scaled through the ring in the scratch after the column histograms. */
static int median_core(rowsrc *rs, int rows, int cols, uint8_t *dst, int dst_stride, int radius,
                       void *scratch, size_t scratch_size)
{
    size_t ucols, dstride, hcap;
    int i, s0, s1, R = radius;

    ucols = (size_t)cols;
    dstride = (size_t)dst_stride;
    rs->cols = ucols;
    rs->c0 = 0;
    rs->c1 = ucols;
    if (R == 0) {
        rs->ring = (uint8_t *)scratch;
        rs->k = 1;
        for (i = 0; i < rows; i++)
            memcpy(dst + (size_t)i * dstride, get_row(rs, i, -1), ucols);
        return ACTAG_OK;
    }
    /* Radii up to 7 are faster with a sliding histogram shared by a block
     * of output rows (no column histograms): 16 rows with SSE2 or NEON
     * (median_rows16), 4 without (median_quad, median_quad_dsp on Cortex-M).
     * For 16-bit frames the ring then has the whole scratch and must hold
     * the 2R + block rows a block reads (scratch / cols >= 2 + 69632 /
     * cols: true up to 2486 columns for 16-row blocks, 4352 for 4-row
     * ones); wider 16-bit frames take the constant-time path below (same
     * output). */
    if (R <= MEDIAN_BLOCK_MAX_R) {
        size_t nk = scratch_size / ucols;
        if (rs->src8 != NULL || nk >= (size_t)(2 * R + MEDIAN_BLOCK_ROWS)) {
            rs->ring = (uint8_t *)scratch;
            rs->k = nk < RING_MAX ? (int)nk : RING_MAX;
            median_block(rs, rows, cols, dst, dstride, R, 0, rows);
            return ACTAG_OK;
        }
    }

    /* As many column histograms as the scratch holds next to a ring of two
     * rows (at least min(cols, ACTAG_MEDIAN_HIST_COLS)); the ring gets the
     * rest, at least 2 rows. */
    hcap = (scratch_size - 2u * ucols) / COL_BYTES;
    if (hcap > ucols)
        hcap = ucols;
    {
        size_t nk = (scratch_size - hcap * COL_BYTES) / ucols;
        rs->ring = (uint8_t *)scratch + hcap * COL_BYTES;
        rs->k = nk < RING_MAX ? (int)nk : RING_MAX;
    }

    /* Large radii: strips of H / 2 columns whatever R (median_strip_agg),
     * when wider than those below. */
    if (ucols > hcap && hcap / 2u > hcap - 2u * (size_t)R - 1u) {
        int w = (int)(hcap / 2u);
        for (s0 = 0; s0 < cols; s0 = s1) {
            s1 = cols - s0 > w ? s0 + w : cols;
            median_strip_agg(rs, rows, cols, s0, s1, dst, dstride, R, (uint8_t *)scratch);
        }
        return ACTAG_OK;
    }

    /* Vertical strips: output columns s0 .. s1-1 need the histograms of
     * columns hb = max(0, s0-R-1) .. min(cols-1, s1-1+R), at most hcap of
     * them, so a strip is hcap - 2R - 1 >= 1 columns wide (hcap - R at
     * the left edge); one strip when all the columns fit. */
    for (s0 = 0; s0 < cols; s0 = s1) {
        int hb = s0 - R - 1 > 0 ? s0 - R - 1 : 0, he;
        if ((size_t)(cols - hb) <= hcap)
            s1 = cols;
        else
            s1 = hb + (int)hcap - R;
        he = s1 - 1 + R < cols ? s1 - 1 + R : cols - 1;
#ifdef MEDIAN_SIMD
        if (R <= MEDIAN_H8_MAX_R) {
            median_strip8(rs, rows, cols - hb, s0 - hb, s1 - hb, (size_t)hb,
                          (size_t)(he - hb + 1), dst + hb, dstride, R, (uint8_t *)scratch);
            continue;
        }
#endif
        median_strip(rs, rows, cols - hb, s0 - hb, s1 - hb, (size_t)hb, (size_t)(he - hb + 1),
                     dst + hb, dstride, R, (uint8_t *)scratch);
    }
    return ACTAG_OK;
}

/* Argument checks shared by both entry points. */
static int median_check(const void *src, int rows, int cols, int src_stride, const uint8_t *dst,
                        int dst_stride, int radius, const void *scratch, size_t scratch_size)
{
    if (src == NULL || dst == NULL || scratch == NULL)
        return ACTAG_ERR_NULL;
    if (rows < 1 || cols < 1 || rows > ACTAG_MAX_DIM || cols > ACTAG_MAX_DIM ||
        src_stride < cols || dst_stride < cols)
        return ACTAG_ERR_SIZE;
    if (radius < 0 || radius > ACTAG_MEDIAN_MAX_RADIUS || src == (const void *)dst)
        return ACTAG_ERR_PARAM;
    if (scratch_size < ACTAG_MEDIAN_SCRATCH_SIZE(rows, cols))
        return ACTAG_ERR_WORKSPACE;
    return ACTAG_OK;
}

int actag_median_filter(const uint8_t *src, int rows, int cols, int src_stride,
                        uint8_t *dst, int dst_stride, int radius,
                        void *scratch, size_t scratch_size)
{
    rowsrc rs;
    int rc = median_check(src, rows, cols, src_stride, dst, dst_stride, radius, scratch,
                          scratch_size);
    if (rc != ACTAG_OK)
        return rc;
    memset(&rs, 0, sizeof rs);
    rs.src8 = src;
    rs.stride = (size_t)src_stride;
    return median_core(&rs, rows, cols, dst, dst_stride, radius, scratch, scratch_size);
}

int actag_median_filter16(const void *src, int rows, int cols, int src_stride, uint8_t *dst,
                          int dst_stride, int radius, void *scratch, size_t scratch_size)
{
    return actag__median_filter16_max(src, 0u, rows, cols, src_stride, dst, dst_stride, radius,
                                      scratch, scratch_size);
}

int actag__median_filter16_max(const void *src, uint32_t max16, int rows, int cols,
                               int src_stride, uint8_t *dst, int dst_stride, int radius,
                               void *scratch, size_t scratch_size)
{
    rowsrc rs;
    int rc = median_check(src, rows, cols, src_stride, dst, dst_stride, radius, scratch,
                          scratch_size);
    if (rc != ACTAG_OK)
        return rc;
    if (max16 == 0u)
        max16 = frame16_max((const uint8_t *)src, rows, cols, (size_t)src_stride);
    memset(&rs, 0, sizeof rs);
    rowsrc_init16(&rs, (const uint8_t *)src, (size_t)src_stride, max16);
    return median_core(&rs, rows, cols, dst, dst_stride, radius, scratch, scratch_size);
}

/* ----------------------------------------------------------------------
 * In place (actag_median_filter_inplace): bands of H output rows. A band
 * [y0, y1) reads source rows [y0 - R, y1 + R); they are gathered (16-bit
 * ones scaled) into a contiguous copy in the scratch: the R rows above the
 * band from the previous band's copy (the frame no longer holds them), the
 * others from the frame, which the output has not reached yet. The block
 * median then writes the band's rows straight into the frame: output row y
 * takes bytes [y * cols, (y + 1) * cols), which lie before every source
 * row a later band reads (y1 * cols <= y1 * stride bytes for 8-bit frames,
 * and under half of that for 16-bit ones). Every output row is computed
 * once, as by actag_median_filter; the extra work is copying each source
 * row once, and the 2R halo rows once more per band.
 * ---------------------------------------------------------------------- */
/* The largest radius of b's bands. */
static int bands_max_radius(const actag__median_bands *b)
{
    int i, r = 0;
    for (i = 0; i < b->n; i++)
        if (b->radius[i] > r)
            r = b->radius[i];
    return r;
}

/* The in-place filter with bands (b checked: radii 0..7). */
static int median_inplace_core(void *frame, int depth, int rows, int cols, int stride,
                               uint32_t max16, const actag__median_bands *b, void *scratch,
                               size_t scratch_size)
{
    uint8_t *buf = (uint8_t *)frame, *tmp = (uint8_t *)scratch;
    size_t ucols = (size_t)cols, cap;
    rowsrc conv, rs;
    int R = bands_max_radius(b), H, blk, y0, y1, t0 = 0, t1 = 0, i;
    memset(&conv, 0, sizeof conv);
    if (depth == 16) {
        if (max16 == 0u)
            max16 = frame16_max(buf, rows, cols, (size_t)stride);
        rowsrc_init16(&conv, buf, (size_t)stride, max16);
        conv.c0 = 0;
        conv.c1 = ucols;
    }
    /* band height: what the copy holds besides the 2R halo rows (R the
     * largest radius), in whole blocks of median_block's rows (30 * cols
     * bytes hold at least one 16-row block at R = 7; with 32-row blocks
     * a band may hold fewer rows than a block: the block's lanes past the
     * band read clamped rows and are not stored, as at the frame's end) */
    cap = scratch_size / ucols;
    if (cap > (size_t)rows + 2u * (size_t)R)
        cap = (size_t)rows + 2u * (size_t)R;
    H = (int)cap - 2 * R;
    blk = median_block_rows();
    if (H > blk)
        H -= H % blk;
    memset(&rs, 0, sizeof rs);
    rs.src8 = tmp;
    rs.stride = ucols;
    rs.cols = ucols;
    rs.c1 = ucols;
    for (y0 = 0; y0 < rows; y0 = y1) {
        int s0 = y0 - R > 0 ? y0 - R : 0, s1, r, ya;
        y1 = rows - y0 > H ? y0 + H : rows;
        s1 = rows - y1 > R ? y1 + R : rows;
        /* rows s0 .. t1-1 are in the copy already (rows t0 .. t1-1) */
        r = s0;
        if (t1 > s0) {
            memmove(tmp, tmp + (size_t)(s0 - t0) * ucols, (size_t)(t1 - s0) * ucols);
            r = t1;
        }
        for (; r < s1; r++) {
            uint8_t *d = tmp + (size_t)(r - s0) * ucols;
            if (depth == 8)
                memcpy(d, buf + (size_t)r * (size_t)stride, ucols);
            else
                scale_row16(&conv, buf + 2u * (size_t)r * (size_t)stride, d);
        }
        t0 = s0;
        t1 = s1;
        /* the scratch after the copy: a ring for the block median's own use
         * (median_quad_dsp's copies of the clamped rows at the frame's top
         * and bottom; 8-bit rows are read from the copy, not the ring) */
        {
            size_t used = (size_t)(s1 - s0), all = scratch_size / ucols;
            rs.ring = all > used ? tmp + used * ucols : NULL;
            rs.k = all - used < RING_MAX ? (int)(all - used) : RING_MAX;
        }
        /* the output rows of each radius band: the copy holds the R >= its
         * radius rows around them (or the frame's edge is the copy's) */
        for (i = 0, ya = y0; ya < y1; i++) {
            int yb, rb;
            if (b->end[i] <= ya)
                continue;
            yb = b->end[i] < y1 ? b->end[i] : y1;
            rb = b->radius[i];
            if (rb == 0)
                memcpy(buf + (size_t)ya * ucols, tmp + (size_t)(ya - s0) * ucols,
                       (size_t)(yb - ya) * ucols);
            else
                median_block(&rs, s1 - s0, cols, buf + (size_t)s0 * ucols, ucols, rb, ya - s0,
                             yb - s0);
            ya = yb;
        }
    }
    return ACTAG_OK;
}

/* Are b's bands well formed (rows covered in order, radii 0..max_r)? */
static int bands_ok(const actag__median_bands *b, int rows, int max_r)
{
    int i, prev = 0;
    if (b->n < 1 || b->n > ACTAG__MEDIAN_BANDS_MAX || b->end[b->n - 1] != rows)
        return 0;
    for (i = 0; i < b->n; i++) {
        if (b->end[i] <= prev || b->radius[i] < 0 || b->radius[i] > max_r)
            return 0;
        prev = b->end[i];
    }
    return 1;
}

/* The in-place checks in the library's order: NULL, then sizes, then
 * parameters (depth, max16, the bands), then the scratch's size. */
static int inplace_check(const void *frame, int depth, int rows, int cols, int stride,
                         uint32_t max16, const actag__median_bands *b, const void *scratch,
                         size_t scratch_size)
{
    if (frame == NULL || scratch == NULL || b == NULL)
        return ACTAG_ERR_NULL;
    if (rows < 1 || cols < 1 || rows > ACTAG_MAX_DIM || cols > ACTAG_MAX_DIM || stride < cols)
        return ACTAG_ERR_SIZE;
    if (depth != 8 && depth != 16)
        return ACTAG_ERR_PARAM;
    if (depth == 16 && max16 > 65535u) /* no 16-bit sample is larger */
        return ACTAG_ERR_PARAM;
    if (!bands_ok(b, rows, ACTAG_MEDIAN_INPLACE_MAX_RADIUS))
        return ACTAG_ERR_PARAM;
    if (scratch_size < ACTAG_MEDIAN_INPLACE_SCRATCH_SIZE(cols))
        return ACTAG_ERR_WORKSPACE;
    return ACTAG_OK;
}

int actag_median_filter_inplace(void *frame, int depth, int rows, int cols, int stride,
                                uint32_t max16, int radius, void *scratch, size_t scratch_size)
{
    actag__median_bands b;
    int rc;
    b.n = 1;
    b.end[0] = rows;
    b.radius[0] = radius;
    rc = inplace_check(frame, depth, rows, cols, stride, max16, &b, scratch, scratch_size);
    if (rc != ACTAG_OK)
        return rc;
    return median_inplace_core(frame, depth, rows, cols, stride, max16, &b, scratch, scratch_size);
}

int actag__median_filter_inplace_bands(void *frame, int depth, int rows, int cols, int stride,
                                       uint32_t max16, const actag__median_bands *b,
                                       void *scratch, size_t scratch_size)
{
    int rc = inplace_check(frame, depth, rows, cols, stride, max16, b, scratch, scratch_size);
    if (rc != ACTAG_OK)
        return rc;
    return median_inplace_core(frame, depth, rows, cols, stride, max16, b, scratch, scratch_size);
}

int actag__median_filter_bands(const void *src, int depth, uint32_t max16, int rows, int cols,
                               int src_stride, uint8_t *dst, int dst_stride,
                               const actag__median_bands *b, void *scratch, size_t scratch_size)
{
    rowsrc rs;
    size_t ucols = (size_t)cols, nk;
    int rc, i, y0;
    /* the library's order: NULL, sizes, parameters, then the scratch */
    if (b == NULL || src == NULL || dst == NULL || scratch == NULL)
        return ACTAG_ERR_NULL;
    if (rows < 1 || cols < 1 || rows > ACTAG_MAX_DIM || cols > ACTAG_MAX_DIM ||
        src_stride < cols || dst_stride < cols)
        return ACTAG_ERR_SIZE;
    if (depth != 8 && depth != 16)
        return ACTAG_ERR_PARAM;
    if (b->n == 1 && b->end[0] == rows) { /* the plain filter, any radius */
        if (depth == 8)
            return actag_median_filter((const uint8_t *)src, rows, cols, src_stride, dst,
                                       dst_stride, b->radius[0], scratch, scratch_size);
        return actag__median_filter16_max(src, max16, rows, cols, src_stride, dst, dst_stride,
                                          b->radius[0], scratch, scratch_size);
    }
    if (!bands_ok(b, rows, MEDIAN_BLOCK_MAX_R < ACTAG_MEDIAN_INPLACE_MAX_RADIUS
                               ? MEDIAN_BLOCK_MAX_R : ACTAG_MEDIAN_INPLACE_MAX_RADIUS))
        return ACTAG_ERR_PARAM;
    rc = median_check(src, rows, cols, src_stride, dst, dst_stride, bands_max_radius(b), scratch,
                      scratch_size);
    if (rc != ACTAG_OK)
        return rc;
    memset(&rs, 0, sizeof rs);
    nk = scratch_size / ucols;
    if (depth == 8) {
        rs.src8 = (const uint8_t *)src;
        rs.stride = (size_t)src_stride;
    } else {
        /* the row-block paths' ring: 2R + block rows, what the in-place
         * filter's copy needs */
        if (scratch_size < ACTAG_MEDIAN_INPLACE_SCRATCH_SIZE(cols))
            return ACTAG_ERR_WORKSPACE;
        if (max16 == 0u)
            max16 = frame16_max((const uint8_t *)src, rows, cols, (size_t)src_stride);
        rowsrc_init16(&rs, (const uint8_t *)src, (size_t)src_stride, max16);
    }
    rs.cols = ucols;
    rs.c0 = 0;
    rs.c1 = ucols;
    rs.ring = (uint8_t *)scratch;
    rs.k = nk < RING_MAX ? (int)nk : RING_MAX;
    for (i = 0, y0 = 0; i < b->n; y0 = b->end[i++]) {
        if (b->radius[i] == 0) {
            int y;
            for (y = y0; y < b->end[i]; y++)
                memcpy(dst + (size_t)y * (size_t)dst_stride, get_row(&rs, y, -1), ucols);
        } else {
            median_block(&rs, rows, cols, dst, (size_t)dst_stride, b->radius[i], y0, b->end[i]);
        }
    }
    return ACTAG_OK;
}
