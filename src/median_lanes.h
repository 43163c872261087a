/* median_lanes.h -- internal to median.c, which includes it once (no
 * include guard; it uses median.c's MEDIAN_SSE2 / MEDIAN_NEON choice and
 * step_mask): the 16-lane histogram primitives of the constant-time
 * median (median_strip, median_strip8, median_strip_agg), each written for
 * SSE2, for NEON (median_neon.h) and in portable C, all computing the same
 * integers. */

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
