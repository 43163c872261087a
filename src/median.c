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
 * median_rows16() below, a sliding histogram shared by 16 output rows: at
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
 * check both); for R <= 7 it uses median_quad() below (a sliding
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

/* ----------------------------------------------------------------------
 * 16-lane primitives: an SSE2 version, a NEON one (median_neon.h) and a
 * portable one that compute the same integers.
 *
 * col_update(cc, fin, fout, vin, vout): remove value vout and add value vin
 *   in one column's histograms (cc its coarse histogram, fin/fout its fine
 *   histograms for the coarse bins of vin and vout, possibly the same
 *   block). The 8-bit lanes wrap modulo 256, but every final count is
 *   <= 2R+1 <= 255, so the result is exact.
 * h16: a kernel histogram, 16 lanes of 16-bit counts (<= 65025).
 *   h16_zero, h16_add (h += a), h16_sub (h -= a), h16_slide (d = h + a -
 *   r, never leaves 0..65025), h16_count_le (number of lanes <= rank of a nondecreasing
 *   histogram whose last lane exceeds rank: the bin holding the sample of
 *   that rank), h16_get (lane k).
 * ---------------------------------------------------------------------- */
#ifdef MEDIAN_SSE2

static __m128i load16(const uint8_t *p)
{
    return _mm_loadu_si128((const __m128i *)(const void *)p);
}

static void store16(uint8_t *p, __m128i v)
{
    _mm_storeu_si128((__m128i *)(void *)p, v);
}

/* (step_mask[v >> 4] is (v & 0xF0) bytes into the table, step_mask[v &
 * 15] (v << 4) & 0xF0: offsets the compiler does not find by itself.) */
static void col_update(uint8_t *cc, uint8_t *fin, uint8_t *fout, unsigned vin, unsigned vout)
{
    const uint8_t *sm = step_mask[0];
    store16(cc, _mm_sub_epi8(_mm_add_epi8(load16(cc), load16(sm + (vin & 0xF0u))),
                             load16(sm + (vout & 0xF0u))));
    store16(fin, _mm_add_epi8(load16(fin), load16(sm + ((vin << 4) & 0xF0u))));
    store16(fout, _mm_sub_epi8(load16(fout), load16(sm + ((vout << 4) & 0xF0u))));
}

/* Every lane is biased by 0x8000 so that signed compares order the counts
 * as unsigned; additions are unaffected by the bias (mod 2^16). */
typedef struct {
    __m128i lo, hi;
} h16;

static void h16_zero(h16 *h)
{
    h->lo = h->hi = _mm_set1_epi16((short)-32768);
}

static void h16_add(h16 *h, const uint8_t *a)
{
    const __m128i z = _mm_setzero_si128();
    __m128i va = load16(a);
    h->lo = _mm_add_epi16(h->lo, _mm_unpacklo_epi8(va, z));
    h->hi = _mm_add_epi16(h->hi, _mm_unpackhi_epi8(va, z));
}

static void h16_sub(h16 *h, const uint8_t *a)
{
    const __m128i z = _mm_setzero_si128();
    __m128i va = load16(a);
    h->lo = _mm_sub_epi16(h->lo, _mm_unpacklo_epi8(va, z));
    h->hi = _mm_sub_epi16(h->hi, _mm_unpackhi_epi8(va, z));
}

static void h16_slide(h16 *d, const h16 *h, const uint8_t *a, const uint8_t *r)
{
    const __m128i z = _mm_setzero_si128();
    __m128i va = load16(a), vr = load16(r);
    d->lo = _mm_sub_epi16(_mm_add_epi16(h->lo, _mm_unpacklo_epi8(va, z)), _mm_unpacklo_epi8(vr, z));
    d->hi = _mm_sub_epi16(_mm_add_epi16(h->hi, _mm_unpackhi_epi8(va, z)), _mm_unpackhi_epi8(vr, z));
}

static unsigned h16_count_le(const h16 *h, unsigned rank)
{
    const __m128i r = _mm_set1_epi16((short)((int)rank - 32768));
    /* The lanes > rank form a suffix: count the zero bits below it. */
    unsigned m = (unsigned)_mm_movemask_epi8(
        _mm_packs_epi16(_mm_cmpgt_epi16(h->lo, r), _mm_cmpgt_epi16(h->hi, r)));
#if defined(__GNUC__)
    return (unsigned)__builtin_ctz(m | 0x10000u);
#else
    unsigned n = 0;
    while (n < 16u && !(m & (1u << n)))
        n++;
    return n;
#endif
}

static unsigned h16_get(const h16 *h, unsigned k)
{
    uint16_t t[16];
    _mm_storeu_si128((__m128i *)(void *)t, h->lo);
    _mm_storeu_si128((__m128i *)(void *)(t + 8), h->hi);
    return (unsigned)t[k] ^ 0x8000u;
}

/* The vector operations median_strip8 and median_rows16 share with NEON
 * (median_neon.h has the same functions). */
typedef __m128i vu8;

static vu8 v_zero(void)
{
    return _mm_setzero_si128();
}

static vu8 v_dup(unsigned x)
{
    return _mm_set1_epi8((char)x);
}

static vu8 v_add(vu8 a, vu8 b)
{
    return _mm_add_epi8(a, b);
}

static vu8 v_sub(vu8 a, vu8 b)
{
    return _mm_sub_epi8(a, b);
}

/* 0xFF in the lanes that are >= 0 as signed bytes. */
static vu8 v_nonneg(vu8 a)
{
    return _mm_cmpgt_epi8(a, _mm_set1_epi8(-1));
}

/* m ? a : b, lane by lane (m: 0x00 or 0xFF lanes). */
static vu8 v_select(vu8 m, vu8 a, vu8 b)
{
    return _mm_or_si128(_mm_andnot_si128(m, b), _mm_and_si128(m, a));
}

/* Interleaves the bytes of a and b: lo = a0 b0 a1 b1 .. a7 b7, hi = a8 b8 ... */
static void v_zip(vu8 a, vu8 b, vu8 *lo, vu8 *hi)
{
    *lo = _mm_unpacklo_epi8(a, b);
    *hi = _mm_unpackhi_epi8(a, b);
}

/* Lane-wise unsigned min (median_net16). */
static vu8 v_min(vu8 a, vu8 b)
{
    return _mm_min_epu8(a, b);
}

/* Lane-wise unsigned max (median_net16). */
static vu8 v_max(vu8 a, vu8 b)
{
    return _mm_max_epu8(a, b);
}

/* Bytes p[0], p[2], .. p[30] to e and p[1], .. p[31] to o (median_net16):
 * the packs of the masked and shifted halves are in order. */
static void mn_split16(const uint8_t *p, uint8_t *e, uint8_t *o)
{
    const __m128i lo = _mm_set1_epi16(0x00FF);
    const __m128i a = load16(p), b = load16(p + 16);
    store16(e, _mm_packus_epi16(_mm_and_si128(a, lo), _mm_and_si128(b, lo)));
    store16(o, _mm_packus_epi16(_mm_srli_epi16(a, 8), _mm_srli_epi16(b, 8)));
}

/* a0 b0 a1 b1 .. a15 b15 to d (median_net16). */
static void mn_zip16(vu8 a, vu8 b, uint8_t *d)
{
    store16(d, _mm_unpacklo_epi8(a, b));
    store16(d + 16, _mm_unpackhi_epi8(a, b));
}

/* Lowest and highest lane. */
static unsigned r16_hmin(vu8 v)
{
    v = _mm_min_epu8(v, _mm_srli_si128(v, 8));
    v = _mm_min_epu8(v, _mm_srli_si128(v, 4));
    v = _mm_min_epu8(v, _mm_srli_si128(v, 2));
    v = _mm_min_epu8(v, _mm_srli_si128(v, 1));
    return (unsigned)_mm_cvtsi128_si32(v) & 0xFFu;
}

static unsigned r16_hmax(vu8 v)
{
    v = _mm_max_epu8(v, _mm_srli_si128(v, 8));
    v = _mm_max_epu8(v, _mm_srli_si128(v, 4));
    v = _mm_max_epu8(v, _mm_srli_si128(v, 2));
    v = _mm_max_epu8(v, _mm_srli_si128(v, 1));
    return (unsigned)_mm_cvtsi128_si32(v) & 0xFFu;
}

/* A set of lanes (r16_medians): bit p for lane p, tested against the sign
 * bits (movemask). */
typedef unsigned lanes;

static lanes lanes_all(void)
{
    return 0xFFFFu;
}

static lanes lanes_none(void)
{
    return 0u;
}

static int lanes_any(lanes s)
{
    return s != 0u;
}

static lanes lanes_not(lanes s)
{
    return 0xFFFFu & ~s;
}

/* The lanes of d that are >= 0 as signed bytes. */
static lanes lanes_nonneg(vu8 d)
{
    return ~(unsigned)_mm_movemask_epi8(d) & 0xFFFFu;
}

/* Is some lane of s negative in d (sign bit set)? */
static int lanes_any_neg(vu8 d, lanes s)
{
    return ((unsigned)_mm_movemask_epi8(d) & s) != 0u;
}

/* Is every lane of s negative in d? */
static int lanes_all_neg(vu8 d, lanes s)
{
    return ((unsigned)_mm_movemask_epi8(d) & s) == s;
}

/* Number of lanes <= rank in a nondecreasing 16-lane histogram of 8-bit
 * counts whose last lane exceeds rank (unsigned compare: min(h, r) == h). */
static unsigned h8_count_le(vu8 h, vu8 rank)
{
    unsigned m = (unsigned)_mm_movemask_epi8(_mm_cmpeq_epi8(_mm_min_epu8(h, rank), h));
    /* The lanes <= rank form a prefix: count the one bits below it. */
#if defined(__GNUC__)
    return (unsigned)__builtin_ctz(~m);
#else
    unsigned n = 0;
    while (n < 16u && (m & (1u << n)))
        n++;
    return n;
#endif
}

#elif defined(MEDIAN_NEON)
#include "median_neon.h"

#else /* portable */

/* Separate functions, each with restrict, because fin and fout may be the
 * same block. */
static void bytes_addsub(uint8_t *restrict d, const uint8_t *restrict a, const uint8_t *restrict b)
{
    int k;
    for (k = 0; k < 16; k++)
        d[k] = (uint8_t)(d[k] + a[k] - b[k]);
}

static void bytes_add(uint8_t *restrict d, const uint8_t *restrict a)
{
    int k;
    for (k = 0; k < 16; k++)
        d[k] = (uint8_t)(d[k] + a[k]);
}

static void bytes_sub(uint8_t *restrict d, const uint8_t *restrict a)
{
    int k;
    for (k = 0; k < 16; k++)
        d[k] = (uint8_t)(d[k] - a[k]);
}

static void col_update(uint8_t *cc, uint8_t *fin, uint8_t *fout, unsigned vin, unsigned vout)
{
    bytes_addsub(cc, step_mask[vin >> 4], step_mask[vout >> 4]);
    bytes_add(fin, step_mask[vin & 15u]);
    bytes_sub(fout, step_mask[vout & 15u]);
}

typedef struct {
    uint16_t v[16];
} h16;

static void h16_zero(h16 *h)
{
    int k;
    for (k = 0; k < 16; k++)
        h->v[k] = 0;
}

static void h16_add(h16 *h, const uint8_t *restrict a)
{
    int k;
    for (k = 0; k < 16; k++)
        h->v[k] = (uint16_t)(h->v[k] + a[k]);
}

static void h16_sub(h16 *h, const uint8_t *restrict a)
{
    int k;
    for (k = 0; k < 16; k++)
        h->v[k] = (uint16_t)(h->v[k] - a[k]);
}

static void h16_slide(h16 *d, const h16 *h, const uint8_t *restrict a, const uint8_t *restrict r)
{
    int k;
    for (k = 0; k < 16; k++)
        d->v[k] = (uint16_t)(h->v[k] + a[k] - r[k]);
}

static unsigned h16_count_le(const h16 *h, unsigned rank)
{
    /* Branch-free binary search for the first lane > rank (lane 15 is). */
    unsigned n = 0;
    n += (unsigned)((unsigned)h->v[n + 7] <= rank) << 3;
    n += (unsigned)((unsigned)h->v[n + 3] <= rank) << 2;
    n += (unsigned)((unsigned)h->v[n + 1] <= rank) << 1;
    n += (unsigned)h->v[n] <= rank;
    return n;
}

static unsigned h16_get(const h16 *h, unsigned k)
{
    return h->v[k];
}

#endif

#ifndef MEDIAN_SIMD
/* ----------------------------------------------------------------------
 * Radii up to 7: four output rows at a time, one histogram (Huang's
 * scheme, as above) for the four windows. hist[v] packs the four windows'
 * 8-bit counts of level v (a window holds (2R+1)^2 <= 225 samples); the
 * 2R+4 source rows of a block of four output rows enter the windows of the
 * rows they cover (mask[t], 0x01 per covered lane), so each sample costs
 * one histogram update for all four windows instead of up to four.
 * ---------------------------------------------------------------------- */
#define MEDIAN_QUAD_MAX_R 7

/* Cortex-M4/M7 (__ARM_FEATURE_SIMD32, little-endian, Thumb-2):
 * median_quad_dsp(); ACTAG_NO_DSP selects the portable median_quad() there
 * too. Thumb-2 only: the asm's LDRD/STRD take any two registers there, an
 * even-odd pair in ARM state (a Cortex-A build with -marm failed to
 * assemble). A build that keeps a frame pointer and reserves r9 as well
 * (-fno-omit-frame-pointer with -ffixed-r9, -msingle-pic-base or
 * -mpic-register=r9) leaves the column asm too few registers: define
 * ACTAG_NO_DSP there. */
#if defined(__ARM_FEATURE_SIMD32) && defined(__GNUC__) && !defined(ACTAG_NO_DSP) &&            \
    !defined(__ARM_BIG_ENDIAN) && defined(__thumb2__)
#define MEDIAN_DSP 1
#endif

/* mask8[t]: 0x01 in lane p when source row t of a block is in window p. */
static void quad_masks(int n, uint32_t *mask8, uint64_t *mask16)
{
    int t, p;
    for (t = 0; t < n + 3; t++) {
        uint32_t m8 = 0;
        uint64_t m16 = 0;
        for (p = 0; p < 4; p++) {
            if (p <= t && t <= p + n - 1) {
                m8 |= (uint32_t)1u << (8 * p);
                m16 |= (uint64_t)1u << (16 * p);
            }
        }
        mask8[t] = m8;
        if (mask16 != NULL)
            mask16[t] = m16;
    }
}

#ifdef MEDIAN_DSP
/* DSP path. leb packs the four windows' counts of samples <= their median
 * (8-bit lanes: at most 225), medb the four medians. A sample v changes
 * leb by the lanes where med[p] >= v: USUB8 (medb - v in each lane) sets
 * GE there and SEL picks the row's mask byte, 0 elsewhere; MUL broadcasts
 * v (GCC would spend two shifted adds). The lanes are added into leb as a
 * plain 32-bit word: carries between lanes cancel, because every lane ends
 * in 0..225 (the word is sum le[p] * 256^p modulo 2^32 throughout). The
 * median of window p then moves from med[p] while le[p] <= half (up) or
 * le[p] - hist_p[med[p]] > half (down); lane p of hist[m] is read as byte
 * 4m + p. Cost at R = 4, 530 x 512 (QEMU -icount, tools/budget), four-row
 * blocks only: 21.1 M instructions per frame on Cortex-M7 -O2 (about 78
 * per pixel: per column of a block, 2R+4 rows at 17 each and about 11 per
 * median), 21.7 M at -Os, 20.7 M on Cortex-M4 -O2; 30.1 M (111 per pixel)
 * before the asm blocks. With oct_block's eight-row blocks (below) on
 * every eight rows of a band: 14.2 M on M7 -O2 (about 52 per pixel),
 * 14.3 M at -Os, 14.2 M on M4 -O2 (18.4 M, 68 per pixel, with the blocks
 * taking the interior rows only and these per-sample compares). Stack:
 * 4.4 KiB (oct_block's 4 KiB of histogram entries). */
__attribute__((always_inline)) static inline uint32_t
le_lanes(unsigned v, uint32_t medb, uint32_t m)
{
    uint32_t r;
    __asm__("mul %0, %1, %5\n\tusub8 %0, %2, %0\n\tsel %0, %4, %3"
            : "=&r"(r)
            : "r"(v), "r"(medb), "r"(0u), "r"(m), "r"(0x01010101u)
            : "cc");
    return r;
}

/* Sample v of a row with mask m enters (+) or leaves (-) the windows. */
#define QSAMPLE(op, v, m)                                                                      \
    do {                                                                                       \
        hist[v] op (m);                                                                        \
        leb op le_lanes((v), medb, (m));                                                       \
    } while (0)

/* New median of window p from its old one (lane p of medb) and the count
 * of samples <= it (lane p of leb); adds both to nb, nl. */
#define QLANE(p, mout)                                                                         \
    do {                                                                                       \
        unsigned le_ = (leb >> (8 * (p))) & 0xFFu;                                             \
        const uint8_t *h_ = h8 + 4u * ((medb >> (8 * (p))) & 0xFFu);                           \
        if (le_ <= half) {                                                                     \
            do {                                                                               \
                h_ += 4;                                                                       \
                le_ += h_[p];                                                                  \
            } while (le_ <= half);                                                             \
        } else {                                                                               \
            unsigned c_ = h_[p];                                                               \
            while (le_ - c_ > half) {                                                          \
                le_ -= c_;                                                                     \
                h_ -= 4;                                                                       \
                c_ = h_[p];                                                                    \
            }                                                                                  \
        }                                                                                      \
        mout = (unsigned)(h_ - h8) >> 2;                                                       \
        nb |= (uint32_t)mout << (8 * (p));                                                     \
        nl |= (uint32_t)le_ << (8 * (p));                                                      \
    } while (0)

/* One source row of an interior block: its samples q[dq] entering and
 * q[0] leaving the windows of mask m; q moves to the next row. One asm
 * block, 17 instructions: GCC, given the C, rematerialises the constants
 * and re-extends the bytes (about 20). hist is written: "memory".
 * Always inlined: at -Os GCC calls it, with q and leb in memory. */
__attribute__((always_inline)) static inline void
quad_row(uint32_t *hist, const uint8_t **q, size_t dq, size_t sstride, uint32_t medb, uint32_t m,
         uint32_t *leb)
{
    uint32_t vi, vo, t;
    __asm__("ldrb %[vi], [%[q], %[dq]]\n\t"
            "ldrb %[vo], [%[q]]\n\t"
            "add %[q], %[q], %[ss]\n\t"
            "ldr %[t], [%[h], %[vi], lsl #2]\n\t"
            "add %[t], %[t], %[m]\n\t"
            "str %[t], [%[h], %[vi], lsl #2]\n\t"
            "ldr %[t], [%[h], %[vo], lsl #2]\n\t"
            "sub %[t], %[t], %[m]\n\t"
            "str %[t], [%[h], %[vo], lsl #2]\n\t"
            "mul %[vi], %[vi], %[k]\n\t"
            "usub8 %[vi], %[medb], %[vi]\n\t"
            "sel %[vi], %[m], %[z]\n\t"
            "add %[le], %[le], %[vi]\n\t"
            "mul %[vo], %[vo], %[k]\n\t"
            "usub8 %[vo], %[medb], %[vo]\n\t"
            "sel %[vo], %[m], %[z]\n\t"
            "sub %[le], %[le], %[vo]"
            : [vi] "=&r"(vi), [vo] "=&r"(vo), [t] "=&r"(t), [q] "+r"(*q), [le] "+r"(*leb)
            : [dq] "r"(dq), [ss] "r"(sstride), [h] "r"(hist), [medb] "r"(medb), [m] "r"(m),
              [k] "r"(0x01010101u), [z] "r"(0u)
            : "cc", "memory");
}

/* The median search of one window's lane as asm text (four-row blocks;
 * oct_block's OLANE is a variant): ES bytes per histogram entry (1 << LG).
 * Walk the cumulative count down while le - hist_p[m] > half (label 1), up
 * while le <= half (label 2); the moved median and count go back into
 * their lanes of medb and leb (BFI); label 4 is where the store follows. */
#define LANE_SEARCH_ASM(ES, LG)                                                                \
    "ubfx %[le], %[leb], #%c[sh], #8\n\t"                                                       \
    "ubfx %[m], %[medb], #%c[sh], #8\n\t"                                                       \
    "add %[h], %[h8], %[m], lsl #" #LG "\n\t"                                                   \
    "cmp %[le], %[half]\n\t"                                                                    \
    "bls 2f\n\t"                                                                                \
    "ldrb %[c], [%[h], #%c[lp]]\n\t"                                                            \
    "sub %[c], %[le], %[c]\n\t"                                                                 \
    "cmp %[c], %[half]\n\t"                                                                     \
    "bls 4f\n"                                                                                   \
    "1:\n\t"                                                                                    \
    "mov %[le], %[c]\n\t"                                                                       \
    "sub %[h], %[h], #" #ES "\n\t"                                                              \
    "ldrb %[c], [%[h], #%c[lp]]\n\t"                                                            \
    "sub %[c], %[le], %[c]\n\t"                                                                 \
    "cmp %[c], %[half]\n\t"                                                                     \
    "bhi 1b\n\t"                                                                                \
    "b 3f\n"                                                                                     \
    "2:\n\t"                                                                                    \
    "add %[h], %[h], #" #ES "\n\t"                                                              \
    "ldrb %[c], [%[h], #%c[lp]]\n\t"                                                            \
    "add %[le], %[le], %[c]\n\t"                                                                \
    "cmp %[le], %[half]\n\t"                                                                    \
    "bls 2b\n"                                                                                   \
    "3:\n\t"                                                                                    \
    "sub %[m], %[h], %[h8]\n\t"                                                                 \
    "lsr %[m], %[m], #" #LG "\n\t"                                                              \
    "bfi %[medb], %[m], #%c[sh], #8\n\t"                                                        \
    "bfi %[leb], %[le], #%c[sh], #8\n"                                                           \
    "4:\n\t"

/* QLANE for the interior columns as one asm block: lanes of medb and leb
 * updated in place (BFI) and only when the median moves, the median
 * stored by `store` (d: column pointer of output row 0, ds: dstride). The
 * usual case, no move, is 10 instructions. */
#define QLANE_ASM(lane, store)                                                                 \
    do {                                                                                       \
        uint32_t le_, m_, h_, c_;                                                              \
        __asm__(LANE_SEARCH_ASM(4, 2) store                                                    \
                : [le] "=&r"(le_), [m] "=&r"(m_), [h] "=&r"(h_), [c] "=&r"(c_),                \
                  [medb] "+r"(medb), [leb] "+r"(leb)                                           \
                : [h8] "r"(h8), [half] "r"(half), [d] "r"(dcol), [ds] "r"(dstride),            \
                  [sh] "i"(8 * (lane)), [lp] "i"(lane)                                         \
                : "cc", "memory");                                                             \
    } while (0)

/* Columns 1 .. cols-1 of a block whose 2R+4 source rows are all inside the
 * image at row0 + t * sstride: the masks are constants, one pointer walks
 * the rows, all four output rows are stored (a function of its own: fewer
 * live values, so fewer spills). */
static void quad_interior(uint32_t *hist, const uint8_t *row0, size_t sstride, uint8_t *d0,
                          size_t dstride, int cols, int R, uint32_t medb, uint32_t leb)
{
    const uint8_t *const h8 = (const uint8_t *)hist;
    const int n = 2 * R + 1;
    const unsigned half = (unsigned)(n * n) / 2u;
    const size_t midrows = (size_t)(n - 3) * sstride;
    /* Columns jm0 .. jm1-1 clamp neither the entering nor the leaving
     * column: there the leaving one is q and the entering one q + n. */
    const int jm0 = R + 1 < cols ? R + 1 : cols;
    const int jm1 = cols - R > jm0 ? cols - R : jm0;
    int j;

/* Column j: its samples q[dq] (entering) and q[0] (leaving) in each of
 * the 2R+4 rows from q, and the four medians stored from d. Rows 0-2 are
 * in windows 0..t, rows 3..n-1 in all four, rows n..n+2 in windows
 * t-n+1..3. */
#define QCOLUMN(q0, dq, d)                                                                     \
    do {                                                                                       \
        const uint8_t *q = (q0), *qe;                                                          \
        if ((dq) != 0) {                                                                       \
            quad_row(hist, &q, (dq), sstride, medb, 0x00000001u, &leb);                        \
            quad_row(hist, &q, (dq), sstride, medb, 0x00000101u, &leb);                        \
            quad_row(hist, &q, (dq), sstride, medb, 0x00010101u, &leb);                        \
            /* n - 3 = 2R - 2 rows, two a turn (less loop overhead) */                        \
            for (qe = q + midrows; q != qe;) {                                                 \
                quad_row(hist, &q, (dq), sstride, medb, 0x01010101u, &leb);                    \
                quad_row(hist, &q, (dq), sstride, medb, 0x01010101u, &leb);                    \
            }                                                                                  \
            quad_row(hist, &q, (dq), sstride, medb, 0x01010100u, &leb);                        \
            quad_row(hist, &q, (dq), sstride, medb, 0x01010000u, &leb);                        \
            quad_row(hist, &q, (dq), sstride, medb, 0x01000000u, &leb);                        \
        }                                                                                      \
        {                                                                                      \
            uint8_t *const dcol = (d);                                                         \
            QLANE_ASM(0, "strb %[m], [%[d]]");                                                 \
            QLANE_ASM(1, "strb %[m], [%[d], %[ds]]");                                          \
            QLANE_ASM(2, "add %[c], %[d], %[ds], lsl #1\n\tstrb %[m], [%[c]]");                \
            QLANE_ASM(3, "add %[c], %[d], %[ds], lsl #1\n\tstrb %[m], [%[c], %[ds]]");         \
        }                                                                                      \
    } while (0)

    for (j = 1; j < cols; j++) {
        const uint8_t *qc;
        uint8_t *d;
        if (j == jm0) {
            /* no clamps: one pointer for the rows, one for the output */
            for (qc = row0 + (jm0 - R - 1), d = d0 + jm0; qc != row0 + (jm1 - R - 1); qc++, d++)
                QCOLUMN(qc, (size_t)n, d);
            j = jm1;
            if (j == cols)
                break;
        }
        {
            size_t ca = (size_t)(j + R < cols ? j + R : cols - 1); /* column entering */
            size_t cr = (size_t)(j - R - 1 > 0 ? j - R - 1 : 0);   /* column leaving */
            QCOLUMN(row0 + cr, ca - cr, d0 + j);
        }
    }
#undef QCOLUMN
}
#undef QLANE_ASM

/* Eight output rows a pass (R >= 3, 8-bit frames; the block's 2R+8 source
 * rows sstride apart: in the frame, or a copy with the clamped rows
 * repeated, see median_quad_dsp). A level's histogram entry is four words:
 * the counts of windows 0-3 (lanes as in median_quad_dsp), an indicator
 * for them (lane p is 1 while the level is <= window p's median, else 0),
 * then the same two words for windows 4-7. A sample's change to the
 * counts le is its row's mask ANDed with the indicator word, loaded with
 * the counts (no AND where the row is in all four windows of a half): no
 * broadcast of the sample and no compare against the medians, the four-
 * row blocks' MUL/USUB8/SEL. The median searches keep the indicators in
 * step, one byte store for each level a median crosses. Source rows 4 ..
 * 2R+3 are in windows of both halves: one sample load, one LDM of the
 * entry and one STM of its first three words serve both (the LDM wants
 * its registers in order: four pinned ones, r0-r3), so a row there costs
 * 17-19 instructions against 2 x 17 for two four-row blocks; rows 0-3
 * touch only the low words, rows 2R+4 .. 2R+7 only the high ones (LDRD),
 * 13-15. R >= 3 gives the fixed row pattern the asm spells out (rows 4-6
 * full in the low half, 2R+1 .. 2R+3 full in the high half, 2R-6 rows
 * full in both); full masks are the immediate 0x01010101. At R = 4 on the
 * pool frames (M7 -O2) a column of eight outputs takes about 415
 * instructions: 285 for the rows, 118 for the medians (a third of them
 * move, 1.7-1.8 levels on average), 12 for the column; 533 with the
 * four-row blocks' compares and 8-byte entries (375 for the rows). */
#define OCT_MIN_R 3
/* Unoptimised builds keep a frame pointer and cannot give the column's asm
 * its 13 registers: four-row blocks only there. */
#if defined(__OPTIMIZE__)
#define MEDIAN_OCT 1
#endif

/* The state of a block's eight windows, in the words before hist (byte
 * offsets from it, so that the column asm reaches them from its one base
 * register): at -32 the counts le, a byte a window as the four-row
 * blocks' leb but biased by 127 - half (bit 7 set while le > half, and
 * the lanes stay in 15 .. 241: no carries between them); at -24 the
 * medians; at -16 sstride, the number of row pairs in all eight windows,
 * dstride; for the columns of one run at -48 their last output pointer,
 * at -40 what q steps back a column (the rows walk it down) and at -36
 * the step of dq. */
#define OCT_STATE_WORDS 12

#ifdef MEDIAN_OCT

/* A row in one half only (count word LB, entry offset OFF: 0 low, 8
 * high): sample q[dq] enters and q[0] leaves the windows of mask M (the
 * register p, with AND the indicators' AND, or all four: OK_). */
#define OROW1(M, AND, LB, OFF)                                                                 \
    "ldrb %[v], [%[q], %[dq]]\n\t"                                                             \
    "add %[v], %[h], %[v], lsl #4\n\t"                                                         \
    "ldrd %[c0], %[i0], [%[v], #" OFF "]\n\t"                                                  \
    "add %[c0], %[c0], " M "\n\t"                                                              \
    "str %[c0], [%[v], #" OFF "]\n\t" AND "add %[" LB "], %[" LB "], %[i0]\n\t"              \
    "ldrb %[v], [%[q]]\n\t"                                                                    \
    "add %[q], %[q], %[ss]\n\t"                                                                \
    "add %[v], %[h], %[v], lsl #4\n\t"                                                         \
    "ldrd %[c0], %[i0], [%[v], #" OFF "]\n\t"                                                  \
    "sub %[c0], %[c0], " M "\n\t"                                                              \
    "str %[c0], [%[v], #" OFF "]\n\t" AND "sub %[" LB "], %[" LB "], %[i0]\n\t"
#define OK_ "#0x01010101"
#define OP_ "%[p]"
#define OAND0 "and %[i0], %[i0], %[p]\n\t"
#define OAND1 "and %[i1], %[i1], %[p]\n\t"

/* One sample of a row in both halves (masks A low, B high; ANDA, ANDB
 * the indicators' AND for a partial mask, or nothing). The STM writes
 * the low indicator back unchanged. */
#define OSAMPLE2(LOAD, OP, A, ANDA, B, ANDB)                                                   \
    LOAD                                                                                       \
    "add %[v], %[h], %[v], lsl #4\n\t"                                                         \
    "ldm %[v], {%[c0], %[i0], %[c1], %[i1]}\n\t"                                               \
    OP " %[c0], %[c0], " A "\n\t"                                                              \
    OP " %[c1], %[c1], " B "\n\t"                                                              \
    "stm %[v], {%[c0], %[i0], %[c1]}\n\t" ANDA OP " %[ll], %[ll], %[i0]\n\t" ANDB OP          \
    " %[lh], %[lh], %[i1]\n\t"
#define OROW2(A, ANDA, B, ANDB)                                                                \
    OSAMPLE2("ldrb %[v], [%[q], %[dq]]\n\t", "add", A, ANDA, B, ANDB)                          \
    OSAMPLE2("ldrb %[v], [%[q]]\n\tadd %[q], %[q], %[ss]\n\t", "sub", A, ANDA, B, ANDB)

/* Median of window P (a digit; O: its byte in an entry) kept or moved one
 * level at a time as in LANE_SEARCH_ASM, from its count and median bytes.
 * With v = le - (half + 1) the sign of one SUBS/ADDS decides each step.
 * Each level crossed gets its indicator byte (O + 4): 0 going down (the
 * level leaves le), 1 going up (it joins). STORE stores the median (c0).
 * 8 instructions and the store when the median stays. */
#define OLANE(P, O, STORE)                                                                     \
    "ldrb %[v], [%[h], #(-32+" #P ")]\n\t"                                                     \
    "ldrb %[c0], [%[h], #(-24+" #P ")]\n\t"                                                    \
    "add %[i0], %[h], %[c0], lsl #4\n\t"                                                       \
    "subs %[v], %[v], #128\n\t"                                                                \
    "bmi 5f\n\t"                                                                               \
    "ldrb %[c1], [%[i0], #" #O "]\n\t"                                                         \
    "subs %[v], %[v], %[c1]\n\t"                                                               \
    "bmi 4f\n\t"                                                                               \
    "movs %[c0], #0\n"                                                                         \
    "1:\n\t"                                                                                   \
    "strb %[c0], [%[i0], #(4+" #O ")]\n\t"                                                     \
    "sub %[i0], %[i0], #16\n\t"                                                                \
    "ldrb %[c1], [%[i0], #" #O "]\n\t"                                                         \
    "subs %[v], %[v], %[c1]\n\t"                                                               \
    "bpl 1b\n\t"                                                                               \
    "add %[v], %[v], %[c1]\n\t"                                                                \
    "b 3f\n"                                                                                   \
    "5:\n\t"                                                                                   \
    "movs %[c0], #1\n"                                                                         \
    "2:\n\t"                                                                                   \
    "add %[i0], %[i0], #16\n\t"                                                                \
    "ldrb %[c1], [%[i0], #" #O "]\n\t"                                                         \
    "strb %[c0], [%[i0], #(4+" #O ")]\n\t"                                                     \
    "adds %[v], %[v], %[c1]\n\t"                                                               \
    "bmi 2b\n"                                                                                 \
    "3:\n\t"                                                                                   \
    "add %[v], %[v], #128\n\t"                                                                 \
    "sub %[c0], %[i0], %[h]\n\t"                                                               \
    "lsr %[c0], %[c0], #4\n\t"                                                                 \
    "strb %[c0], [%[h], #(-24+" #P ")]\n\t"                                                    \
    "strb %[v], [%[h], #(-32+" #P ")]\n"                                                       \
    "4:\n\t" STORE "\n\t"

/* Columns d .. dend-1 of a run where q0 and dq step by the same amounts
 * (the clamps at the frame's sides change them), as one asm block: no
 * register holds anything but the column's work (with separate blocks for
 * the rows and each median, GCC spent about 35 instructions a column on
 * spills and the clamps). Rows from q (entering sample at +dq); the
 * medians go to d + p * dstride (ll, lh, i1: rows 2, 4, 6). The asm
 * stores (histogram, state, medians) and its register outputs are dead:
 * volatile. */
__attribute__((always_inline)) static inline void oct_run(uint32_t *hist, const uint8_t *q,
                                                          size_t dq, uint8_t *d)
{
    register uint32_t c0 __asm__("r0"), i0 __asm__("r1"), c1 __asm__("r2"), i1 __asm__("r3");
    uint32_t v, p, ll, lh, ss;
    __asm__ volatile(
        "9:\n\t"
        "ldrd %[ll], %[lh], [%[h], #-32]\n\t"
        "ldr %[ss], [%[h], #-16]\n\t"
        "mov %[p], #1\n\t" OROW1(OP_, OAND0, "ll", "0")
        "movw %[p], #0x101\n\t" OROW1(OP_, OAND0, "ll", "0")
        "add %[p], %[p], #0x10000\n\t" OROW1(OP_, OAND0, "ll", "0")
        OROW1(OK_, "", "ll", "0")
        "mov %[p], #1\n\t" OROW2(OK_, "", OP_, OAND1)
        "movw %[p], #0x101\n\t" OROW2(OK_, "", OP_, OAND1)
        "add %[p], %[p], #0x10000\n\t" OROW2(OK_, "", OP_, OAND1)
        "ldr %[p], [%[h], #-12]\n\t"
        "cmp %[p], #0\n\t"
        "beq 8f\n"
        "7:\n\t" OROW2(OK_, "", OK_, "") OROW2(OK_, "", OK_, "")
        "subs %[p], %[p], #1\n\t"
        "bne 7b\n"
        "8:\n\t"
        "mov %[p], #0x01010101\n\t"
        "bic %[p], %[p], #0xFF\n\t" OROW2(OP_, OAND0, OK_, "")
        "bic %[p], %[p], #0x100\n\t" OROW2(OP_, OAND0, OK_, "")
        "mov %[p], #0x01000000\n\t" OROW2(OP_, OAND0, OK_, "")
        OROW1(OK_, "", "lh", "8")
        "mov %[p], #0x01010101\n\t"
        "bic %[p], %[p], #0xFF\n\t" OROW1(OP_, OAND0, "lh", "8")
        "bic %[p], %[p], #0x100\n\t" OROW1(OP_, OAND0, "lh", "8")
        "mov %[p], #0x01000000\n\t" OROW1(OP_, OAND0, "lh", "8")
        "strd %[ll], %[lh], [%[h], #-32]\n\t"
        "ldr %[ss], [%[h], #-8]\n\t"
        "add %[ll], %[d], %[ss], lsl #1\n\t"
        "add %[lh], %[d], %[ss], lsl #2\n\t"
        "add %[i1], %[lh], %[ss], lsl #1\n\t"
        OLANE(0, 0, "strb %[c0], [%[d]]")
        OLANE(1, 1, "strb %[c0], [%[d], %[ss]]")
        OLANE(2, 2, "strb %[c0], [%[ll]]")
        OLANE(3, 3, "strb %[c0], [%[ll], %[ss]]")
        OLANE(4, 8, "strb %[c0], [%[lh]]")
        OLANE(5, 9, "strb %[c0], [%[lh], %[ss]]")
        OLANE(6, 10, "strb %[c0], [%[i1]]")
        OLANE(7, 11, "strb %[c0], [%[i1], %[ss]]")
        "ldrd %[v], %[p], [%[h], #-40]\n\t"
        "sub %[q], %[q], %[v]\n\t"
        "add %[dq], %[dq], %[p]\n\t"
        "ldr %[v], [%[h], #-48]\n\t"
        "add %[d], %[d], #1\n\t"
        "cmp %[d], %[v]\n\t"
        "bne 9b"
        : [c0] "=&r"(c0), [i0] "=&r"(i0), [c1] "=&r"(c1), [i1] "=&r"(i1), [v] "=&r"(v),
          [p] "=&r"(p), [ll] "=&r"(ll), [lh] "=&r"(lh), [ss] "=&r"(ss), [q] "+r"(q),
          [dq] "+r"(dq), [d] "+r"(d)
        : [h] "r"(hist)
        : "cc", "memory");
}

/* Output rows i0 .. i0+7, source rows from row0 = row i0 - R (all inside
 * the image, sstride apart); hist: 1024 words of scratch after
 * OCT_STATE_WORDS. noinline: inlined into median_quad_dsp, GCC spilled
 * more around the asm (measured before oct_run). */
__attribute__((noinline)) static void oct_block(uint32_t *hist, const uint8_t *row0,
                                                size_t sstride, uint8_t *d0, size_t dstride,
                                                int cols, int R, const uint32_t *mask8)
{
    uint8_t *const h8 = (uint8_t *)hist;
    uint32_t *const st = hist - OCT_STATE_WORDS;
    const int n = 2 * R + 1, nt = n + 7;
    const unsigned half = (unsigned)(n * n) / 2u;
    int t, b, p, j;

    /* Windows of column 0: columns clamp(-R..R). The entries cleared 64
     * bytes a loop (memset took 7 instructions a 16 bytes, 0.1 M a frame
     * more): STM wants ascending registers. */
    {
        register uint32_t z0 __asm__("r0") = 0u, z1 __asm__("r1") = 0u;
        register uint32_t z2 __asm__("r2") = 0u, z3 __asm__("r3") = 0u;
        uint32_t *w = hist;
        __asm__ volatile("1:\n\t"
                         "stm %[w]!, {%[z0], %[z1], %[z2], %[z3]}\n\t"
                         "stm %[w]!, {%[z0], %[z1], %[z2], %[z3]}\n\t"
                         "stm %[w]!, {%[z0], %[z1], %[z2], %[z3]}\n\t"
                         "stm %[w]!, {%[z0], %[z1], %[z2], %[z3]}\n\t"
                         "cmp %[w], %[e]\n\t"
                         "bne 1b"
                         : [w] "+r"(w)
                         : [z0] "r"(z0), [z1] "r"(z1), [z2] "r"(z2), [z3] "r"(z3),
                           [e] "r"(hist + 1024)
                         : "cc", "memory");
    }
    for (t = 0; t < nt; t++) {
        const uint8_t *s = row0 + (size_t)t * sstride;
        const uint32_t ml = t <= n + 2 ? mask8[t] : 0u, mh = t >= 4 ? mask8[t - 4] : 0u;
        for (b = -R; b <= R; b++) {
            unsigned v = s[clampi(b, 0, cols - 1)];
            hist[4u * v] += ml;
            hist[4u * v + 2u] += mh;
        }
    }
    st[4] = st[5] = st[6] = st[7] = 0u;
    for (p = 0; p < 8; p++) {
        const unsigned o = (unsigned)p + ((unsigned)p & 4u); /* its count byte in an entry */
        const unsigned sh = 8u * ((unsigned)p & 3u);
        unsigned m = 0, le = h8[o];
        h8[o + 4u] = 1u;
        while (le <= half) {
            le += h8[16u * ++m + o];
            h8[16u * m + o + 4u] = 1u;
        }
        st[4 + p / 4] |= (uint32_t)(le + 127u - half) << sh;
        st[6 + p / 4] |= (uint32_t)m << sh;
        d0[(size_t)p * dstride] = (uint8_t)m;
    }
    st[8] = (uint32_t)sstride;
    st[9] = (uint32_t)(R - 3);
    st[10] = (uint32_t)dstride;

    /* Runs of columns between the points where a clamp starts or stops:
     * the leaving column cr = max(j - R - 1, 0) steps from column R + 1
     * on, the entering one ca = min(j + R, cols - 1) up to cols - R - 1. */
    for (j = 1; j < cols;) {
        const int ca = j + R < cols ? j + R : cols - 1, cr = j - R - 1 > 0 ? j - R - 1 : 0;
        const int a = j >= R + 1, i = j <= cols - R - 2;
        int je = cols;
        if (!a && R + 1 < je)
            je = R + 1;
        if (i && cols - R - 1 < je)
            je = cols - R - 1;
        st[0] = (uint32_t)(uintptr_t)(d0 + je);
        st[2] = (uint32_t)((size_t)nt * sstride - (size_t)a);
        st[3] = (uint32_t)(i - a);
        oct_run(hist, row0 + cr, (size_t)(ca - cr), d0 + j);
        j = je;
    }
}
#undef OLANE
#undef OROW1
#undef OSAMPLE2
#undef OROW2
#undef OK_
#undef OP_
#undef OAND0
#undef OAND1
#endif /* MEDIAN_OCT */

static void median_quad_dsp(rowsrc *rs, int rows, int cols, uint8_t *dst, size_t dstride, int R,
                            int y0, int y1)
{
    const size_t sstride = rs->src8 != NULL ? rs->stride : rs->cols;
    /* oct_block's state and 16-byte entries; four-row blocks: hist[v] */
    uint32_t entries[OCT_STATE_WORDS + 4 * 256];
    uint32_t *const hist = entries + OCT_STATE_WORDS;
    const uint8_t *const h8 = (const uint8_t *)hist;
    const uint8_t *rowp[2 * MEDIAN_QUAD_MAX_R + 4];
    uint32_t mask8[2 * MEDIAN_QUAD_MAX_R + 4];
    const int n = 2 * R + 1, nt = n + 3;
    const unsigned half = (unsigned)(n * n) / 2u;
    int i0, j, t, p, step;

    quad_masks(n, mask8, NULL);
    for (i0 = y0; i0 < y1; i0 += step) {
        uint32_t medb = 0, leb = 0;
        const int np = y1 - i0 < 4 ? y1 - i0 : 4; /* output rows in this block */
        uint8_t *const d0 = dst + (size_t)i0 * dstride;

#ifdef MEDIAN_OCT
        /* Eight rows at once (8-bit frames): from the frame where their
         * 2R+8 source rows are in it, else (top and bottom) from a copy of
         * them in the ring with the clamped rows repeated, when the ring is
         * free and large enough (not in place); at the end of the band its
         * last eight rows (a few computed twice: the same bytes). */
        if (R >= OCT_MIN_R && rs->src8 != NULL && y1 - y0 >= 8) {
            const int ib = y1 - i0 >= 8 ? i0 : y1 - 8, nt8 = 2 * R + 8;
            uint8_t *const db = dst + (size_t)ib * dstride;
            if (ib - R >= 0 && ib + 7 + R <= rows - 1) {
                oct_block(hist, rs->src8 + (size_t)(ib - R) * sstride, sstride, db, dstride,
                          cols, R, mask8);
                step = ib + 8 - i0;
                continue;
            }
            if (rs->ring != NULL && rs->k >= nt8) {
                for (t = 0; t < nt8; t++)
                    memcpy(rs->ring + (size_t)t * (size_t)cols,
                           rs->src8 + (size_t)clampi(ib - R + t, 0, rows - 1) * sstride,
                           (size_t)cols);
                oct_block(hist, rs->ring, (size_t)cols, db, dstride, cols, R, mask8);
                step = ib + 8 - i0;
                continue;
            }
        }
#endif
        step = 4;

        /* Windows of column 0: columns clamp(-R..R). */
        memset(hist, 0, 256u * sizeof *hist);
        for (t = 0; t < nt; t++) {
            const uint8_t *s;
            int b;
            rowp[t] = get_row(rs, clampi(i0 - R + t, 0, rows - 1), -1);
            s = rowp[t];
            for (b = -R; b <= R; b++)
                hist[s[clampi(b, 0, cols - 1)]] += mask8[t];
        }
        for (p = 0; p < 4; p++) {
            unsigned m = 0, le = h8[p];
            while (le <= half)
                le += h8[4u * ++m + (unsigned)p];
            medb |= (uint32_t)m << (8 * p);
            leb |= (uint32_t)le << (8 * p);
            if (p < np)
                d0[(size_t)p * dstride] = (uint8_t)m;
        }
        if (np == 4 && i0 - R >= 0 && i0 - R + nt - 1 <= rows - 1 &&
            rowp[nt - 1] == rowp[0] + (size_t)(nt - 1) * sstride) {
            quad_interior(hist, rowp[0], sstride, d0, dstride, cols, R, medb, leb);
            continue;
        }

        for (j = 1; j < cols; j++) {
            size_t ca = (size_t)(j + R < cols ? j + R : cols - 1); /* column entering */
            size_t cr = (size_t)(j - R - 1 > 0 ? j - R - 1 : 0);   /* column leaving */
            uint32_t nb = 0, nl = 0;
            unsigned m[4];
            for (t = 0; t < nt && ca != cr; t++) {
                unsigned vin = rowp[t][ca], vout = rowp[t][cr];
                QSAMPLE(+=, vin, mask8[t]);
                QSAMPLE(-=, vout, mask8[t]);
            }
            QLANE(0, m[0]);
            QLANE(1, m[1]);
            QLANE(2, m[2]);
            QLANE(3, m[3]);
            medb = nb;
            leb = nl;
            for (p = 0; p < np; p++)
                dst[(size_t)(i0 + p) * dstride + (size_t)j] = (uint8_t)m[p];
        }
    }
}
#undef QSAMPLE
#undef QLANE

#else /* !MEDIAN_DSP */
/* Portable: the number of samples below each window's median is updated
 * for all four at once with 16-bit lanes of a 64-bit word: lane p of medb
 * is med[p] + 255, so bit 8 of lane p of medb - v * 0x0001000100010001 is
 * (v < med[p]) and no lane borrows. */
#define LANES16 0x0001000100010001ull

/* bcast16[v]: v in each of four 16-bit lanes (a table: cheaper than the
 * multiply or shifts on both x86-64 and Cortex-M). */
#define BC1(v) ((uint64_t)(v) * LANES16)
#define BC4(v) BC1(v), BC1((v) + 1), BC1((v) + 2), BC1((v) + 3)
#define BC16(v) BC4(v), BC4((v) + 4), BC4((v) + 8), BC4((v) + 12)
#define BC64(v) BC16(v), BC16((v) + 16), BC16((v) + 32), BC16((v) + 48)
static const uint64_t bcast16_tab[256] = {BC64(0), BC64(64), BC64(128), BC64(192)};
#define bcast16(v) bcast16_tab[v]

static void median_quad(rowsrc *rs, int rows, int cols, uint8_t *dst, size_t dstride, int R,
                        int y0, int y1)
{
    uint32_t hist[256];
    const uint8_t *rowp[2 * MEDIAN_QUAD_MAX_R + 4];
    uint32_t mask8[2 * MEDIAN_QUAD_MAX_R + 4];
    uint64_t mask16[2 * MEDIAN_QUAD_MAX_R + 4];
    const int n = 2 * R + 1, nt = n + 3;
    const unsigned half = (unsigned)(n * n) / 2u;
    int i0, j, t, p;

    quad_masks(n, mask8, mask16);
    for (i0 = y0; i0 < y1; i0 += 4) {
        unsigned med[4], lt[4];
        uint64_t medb = 0;
        int np = y1 - i0 < 4 ? y1 - i0 : 4; /* output rows in this block */
        for (t = 0; t < nt; t++)
            rowp[t] = get_row(rs, clampi(i0 - R + t, 0, rows - 1), -1);

        /* Windows of column 0: columns clamp(-R..R). */
        memset(hist, 0, sizeof hist);
        for (t = 0; t < nt; t++) {
            const uint8_t *s = rowp[t];
            int b;
            for (b = -R; b <= R; b++)
                hist[s[clampi(b, 0, cols - 1)]] += mask8[t];
        }
        for (p = 0; p < 4; p++) {
            unsigned m = 0, l = 0, sh = 8u * (unsigned)p;
            while (l + ((hist[m] >> sh) & 0xFFu) <= half) {
                l += (hist[m] >> sh) & 0xFFu;
                m++;
            }
            med[p] = m;
            lt[p] = l;
            medb |= ((uint64_t)m + 255u) << (16 * p);
            if (p < np)
                dst[(size_t)(i0 + p) * dstride] = (uint8_t)m;
        }

        for (j = 1; j < cols; j++) {
            size_t ca = (size_t)(j + R < cols ? j + R : cols - 1); /* column entering */
            size_t cr = (size_t)(j - R - 1 > 0 ? j - R - 1 : 0);   /* column leaving */
            if (ca != cr) {
                /* acc collects 256 * the change of lt per 16-bit lane; the
                 * lanes start at 64 so that they never go negative (at most
                 * 2R+4 <= 18 samples leave a window in one step). */
                uint64_t acc = 64u * 256u * LANES16;
                for (t = 0; t < nt; t++) {
                    unsigned vin = rowp[t][ca], vout = rowp[t][cr];
                    uint64_t m16 = mask16[t];
                    uint32_t m8 = mask8[t];
                    if (t == 3 && n > 3) {
                        /* Rows 3 .. n-1 are in all four windows. */
                        for (; t < n; t++) {
                            vin = rowp[t][ca];
                            vout = rowp[t][cr];
                            hist[vin] += 0x01010101u;
                            hist[vout] -= 0x01010101u;
                            acc += (medb - bcast16(vin)) & (256u * LANES16);
                            acc -= (medb - bcast16(vout)) & (256u * LANES16);
                        }
                        vin = rowp[t][ca];
                        vout = rowp[t][cr];
                        m16 = mask16[t];
                        m8 = mask8[t];
                    }
                    hist[vin] += m8;
                    hist[vout] -= m8;
                    acc += (medb - bcast16(vin)) & (m16 << 8);
                    acc -= (medb - bcast16(vout)) & (m16 << 8);
                }
                acc >>= 8;
                medb = 0;
                for (p = 0; p < 4; p++) {
                    unsigned sh = 8u * (unsigned)p;
                    unsigned m = med[p];
                    unsigned l = lt[p] + (unsigned)((acc >> (16 * p)) & 0xFFFFu) - 64u;
                    if (l > half) {
                        do {
                            m--;
                            l -= (hist[m] >> sh) & 0xFFu;
                        } while (l > half);
                    } else {
                        while (l + ((hist[m] >> sh) & 0xFFu) <= half) {
                            l += (hist[m] >> sh) & 0xFFu;
                            m++;
                        }
                    }
                    med[p] = m;
                    lt[p] = l;
                    medb |= ((uint64_t)m + 255u) << (16 * p);
                }
            }
            for (p = 0; p < np; p++)
                dst[(size_t)(i0 + p) * dstride + (size_t)j] = (uint8_t)med[p];
        }
    }
}
#endif /* MEDIAN_DSP */

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
