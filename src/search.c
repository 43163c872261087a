/* Structure search (see search.h): box contrast of a bright square inside a
 * dark ring at the tag's physical size, on a block-averaged frame. */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/search.h"

#include "search_box.h"

#include <string.h>

#if defined(__ARM_FEATURE_SIMD32) && defined(__GNUC__) && !defined(ACTAG_NO_DSP)
#define SEARCH_DSP 1
#endif

/* x86-64 (SSE2, the baseline): the block sums, a uniform fan's row scores
 * and the best position's scan four or eight lanes at a time, the same
 * integers (see each). */
#if defined(__SSE2__) && !defined(ACTAG_NO_SIMD)
#define SEARCH_SSE2 1
#include <emmintrin.h>
#endif

#if ACTAG_SEARCH_FACTOR != 4
#error "block_sum4 sums 4 x 4 blocks"
#endif

static uint32_t box_sum(const actag_search *z, int r0, int c0, int r1, int c1)
{
    /* rows r0..r1-1, cols c0..c1-1, clamped */
    size_t w = (size_t)z->hc + 1u;
    if (r0 < 0) r0 = 0;
    if (c0 < 0) c0 = 0;
    if (r1 > z->hr) r1 = z->hr;
    if (c1 > z->hc) c1 = z->hc;
    if (r1 <= r0 || c1 <= c0)
        return 0u;
    return z->ii[(size_t)r1 * w + (size_t)c1] - z->ii[(size_t)r0 * w + (size_t)c1] -
           z->ii[(size_t)r1 * w + (size_t)c0] + z->ii[(size_t)r0 * w + (size_t)c0];
}

/* The 16 pixels of the 4 x 4 block at a (ACTAG_SEARCH_FACTOR 4), a row of
 * four bytes at a time: with the Cortex-M DSP extension one USADA8 a row
 * (the byte loop took about 88 Cortex-M7 instructions a block, 1.5 M a
 * 530 x 512 frame); elsewhere two byte-pair lanes of a 32-bit word (each at
 * most 4 x 2 x 255), folded once. The same integer sum either way. */
#ifdef SEARCH_DSP
static uint32_t block_sum4(const uint8_t *a, size_t stride)
{
    uint32_t s = 0u, v;
    int i;
    for (i = 0; i < 4; i++, a += stride) {
        memcpy(&v, a, sizeof v); /* one LDR where unaligned loads are allowed */
        /* USADA8 (inline asm: arm_acle.h's __usada8 needs GCC 10) */
        __asm__("usada8 %0, %1, %2, %3" : "=r"(s) : "r"(v), "r"(0u), "r"(s));
    }
    return s;
}
#else
static uint32_t block_sum4(const uint8_t *a, size_t stride)
{
    uint32_t t = 0u, v;
    int i;
    for (i = 0; i < 4; i++, a += stride) {
        memcpy(&v, a, sizeof v); /* byte order does not matter: all four are summed */
        t += (v & 0x00FF00FFu) + ((v >> 8) & 0x00FF00FFu);
    }
    return (t & 0xFFFFu) + (t >> 16);
}
#endif

#ifdef SEARCH_SSE2
/* Integral-image row r + 1 (cur) of block row r, whose pixel rows start at
 * a: blocks 0.. four at a time (16 bytes of each of the 4 rows; blocks
 * below hc only, so no byte past 4 hc <= cols), cur[c + 1] = prev[c + 1] +
 * the row's running sum, in uint32 as the scalar loop; returns the first
 * block left and its running sum in *run. */
static int block_rows_sse2(const uint8_t *a, size_t stride, int hc, const uint32_t *prev,
                           uint32_t *cur, uint32_t *run)
{
    const __m128i zero = _mm_setzero_si128(), ones = _mm_set1_epi16(1);
    __m128i r = _mm_set1_epi32((int)*run);
    int c;
    for (c = 0; c + 4 <= hc; c += 4) {
        const uint8_t *p = a + 4 * (size_t)c;
        __m128i lo = zero, hi = zero, s01, s23, t;
        int i;
        for (i = 0; i < 4; i++, p += stride) { /* column sums of the 4 rows, 16 bits */
            __m128i v = _mm_loadu_si128((const __m128i *)(const void *)p);
            lo = _mm_add_epi16(lo, _mm_unpacklo_epi8(v, zero));
            hi = _mm_add_epi16(hi, _mm_unpackhi_epi8(v, zero));
        }
        /* pairs of columns, then pairs of pairs: the four block sums */
        s01 = _mm_madd_epi16(lo, ones);
        s23 = _mm_madd_epi16(hi, ones);
        t = _mm_add_epi32(_mm_castps_si128(_mm_shuffle_ps(_mm_castsi128_ps(s01), _mm_castsi128_ps(s23), 0x88)),
                          _mm_castps_si128(_mm_shuffle_ps(_mm_castsi128_ps(s01), _mm_castsi128_ps(s23), 0xdd)));
        /* running sums within the four, plus the run so far */
        t = _mm_add_epi32(t, _mm_slli_si128(t, 4));
        t = _mm_add_epi32(t, _mm_slli_si128(t, 8));
        t = _mm_add_epi32(t, r);
        r = _mm_shuffle_epi32(t, 0xff);
        _mm_storeu_si128((__m128i *)(void *)(cur + c + 1),
                         _mm_add_epi32(t, _mm_loadu_si128((const __m128i *)(const void *)(prev + c + 1))));
    }
    *run = (uint32_t)_mm_cvtsi128_si32(r);
    return c;
}
#endif

static int finite_pos(float v) { return v == v && v > 0.0f && v < 3.0e38f; }

/* A pixel count from a float that may be huge, infinite or NaN (an absurd
 * tag size or azimuth step): truncated like (int)v, but saturating at cap
 * (and at 0 from below) instead of converting an out-of-range float, which
 * is undefined and gives INT_MIN on x86, saturation on ARM. */
static int px_count(float v, int cap)
{
    if (!(v < (float)cap))
        return cap;
    if (!(v > 0.0f))
        return 0;
    return (int)v;
}

/* A position's inner (white square) and outer (ring) box half-sizes in
 * blocks. */
typedef struct search_box {
    int ir, ic, orr, oc;
} search_box;

/* The boxes at a block row whose cell spans cr blocks along range, where
 * the azimuth step times the range is daz (m a column). 0 when there is no
 * azimuth step, or when the outer box could sum past the uint32 integral
 * image (then the position is not scored; no int overflow: orr, oc <= 8195). */
static int box_of(float cr, float daz, float cell, float half_in, int hr, int hc, search_box *b)
{
    float cc;
    if (!(daz > 0.0f))
        return 0;
    cc = cell / daz / (float)ACTAG_SEARCH_FACTOR; /* low-res pixels per cell along azimuth */
    /* boxes larger than the map leave it anyway: saturate there */
    b->ir = px_count(half_in * cr + 0.5f, hr + 1);
    b->ic = px_count(half_in * cc + 0.5f, hc + 1);
    b->orr = px_count((half_in + 1.0f) * cr + 0.5f, hr + 2);
    b->oc = px_count((half_in + 1.0f) * cc + 0.5f, hc + 2);
    if (b->ir < 1) b->ir = 1;
    if (b->ic < 1) b->ic = 1;
    if (b->orr <= b->ir) b->orr = b->ir + 1;
    if (b->oc <= b->ic) b->oc = b->ic + 1;
    return (uint32_t)((2 * b->orr + 1) * (2 * b->oc + 1)) <= ACTAG_SEARCH_MAX_BOX_BLOCKS;
}

/* The score of block (r, c) with boxes b: 8 * (mean_in - mean_ring) in grey
 * levels, clamped; INT16_MIN when the outer box leaves the map. */
#if defined(__GNUC__)
__attribute__((always_inline)) /* -Os otherwise calls it per position (+0.7 M a frame) */
#endif
static inline int16_t box_score(const actag_search *z, const search_box *b, int r, int c)
{
    uint32_t si, so;
    int32_t ni, no;
    int64_t num, den, q;
    if (!(r - b->orr >= 0 && r + b->orr < z->hr && c - b->oc >= 0 && c + b->oc < z->hc))
        return INT16_MIN;
    si = box_sum(z, r - b->ir, c - b->ic, r + b->ir + 1, c + b->ic + 1);
    so = box_sum(z, r - b->orr, c - b->oc, r + b->orr + 1, c + b->oc + 1);
    ni = (2 * b->ir + 1) * (2 * b->ic + 1);
    no = (2 * b->orr + 1) * (2 * b->oc + 1);
    /* sums are of F^2 pixels */
    num = (int64_t)si * (no - ni) - (int64_t)(so - si) * ni;
    den = (int64_t)ni * (no - ni) * ACTAG_SEARCH_FACTOR * ACTAG_SEARCH_FACTOR;
    num *= 8;
    /* the same quotient (both truncate toward zero) without the 64-bit
     * division helper of 32-bit cores where the operands fit 32 bits */
    if (num >= -INT32_MAX && num <= INT32_MAX && den <= INT32_MAX)
        q = (int32_t)num / (int32_t)den;
    else
        q = num / den;
    return (int16_t)(q > 2040 ? 2040 : q < -2040 ? -2040 : q);
}

#ifdef SEARCH_SSE2
/* Two lanes of box_score's quotient from the inner and outer sums si, so
 * (their low two 32-bit lanes) in double: num = si nd - (so - si) ni and
 * den = 2 ni nd (the quotient 8 num / 16 ni nd reduced) are integers below
 * 2^53 (si <= 4080 ni, nd + ni = no <= ACTAG_SEARCH_MAX_BOX_BLOCKS), so
 * exact, and so is the truncated quotient: the rounded division errs by
 * less than |num| 2^-53 / den < 1 / den, the least distance of a
 * fractional num / den from an integer. The same integer as the int32 and
 * int64 divisions; clamped to +-2040 as int32 lanes. */
static __m128d u32_pd(__m128i v) /* the low two lanes, unsigned */
{
    return _mm_add_pd(_mm_cvtepi32_pd(_mm_xor_si128(v, _mm_set1_epi32(INT32_MIN))),
                      _mm_set1_pd(2147483648.0));
}

static __m128i quot2_sse2(__m128i si, __m128i so, __m128d nd, __m128d ni, __m128d den)
{
    __m128d num = _mm_sub_pd(_mm_mul_pd(u32_pd(si), nd), _mm_mul_pd(u32_pd(_mm_sub_epi32(so, si)), ni));
    return _mm_cvttpd_epi32(_mm_div_pd(num, den));
}

/* Columns c0.. of score_row's run (both boxes inside the map) four at a
 * time, whatever the size of its products; returns the first column left
 * (fewer than four before c1). */
static int score_run_sse2(const uint32_t *ia, const uint32_t *ib, const uint32_t *oa,
                          const uint32_t *ob, int ic, int oc, int32_t ni, int32_t no, int c0,
                          int c1, int16_t *row)
{
    const __m128d nd = _mm_set1_pd((double)(no - ni)), niv = _mm_set1_pd((double)ni);
    const __m128d den = _mm_set1_pd(2.0 * (double)ni * (double)(no - ni));
    const __m128i hi = _mm_set1_epi32(2040), lo = _mm_set1_epi32(-2040);
    int c;
    for (c = c0; c + 4 <= c1; c += 4) {
#define SEARCH_LD(p) _mm_loadu_si128((const __m128i *)(const void *)(p))
        /* the box sums as uint32 (below 2^32: ACTAG_SEARCH_MAX_BOX_BLOCKS) */
        __m128i si = _mm_add_epi32(_mm_sub_epi32(_mm_sub_epi32(SEARCH_LD(ib + c + ic + 1), SEARCH_LD(ia + c + ic + 1)),
                                                 SEARCH_LD(ib + c - ic)),
                                   SEARCH_LD(ia + c - ic));
        __m128i so = _mm_add_epi32(_mm_sub_epi32(_mm_sub_epi32(SEARCH_LD(ob + c + oc + 1), SEARCH_LD(oa + c + oc + 1)),
                                                 SEARCH_LD(ob + c - oc)),
                                   SEARCH_LD(oa + c - oc));
#undef SEARCH_LD
        __m128i q01 = quot2_sse2(si, so, nd, niv, den);
        __m128i q23 = quot2_sse2(_mm_shuffle_epi32(si, 0x0e), _mm_shuffle_epi32(so, 0x0e), nd, niv, den);
        __m128i q = _mm_unpacklo_epi64(q01, q23), over, under;
        over = _mm_cmpgt_epi32(q, hi);
        q = _mm_or_si128(_mm_andnot_si128(over, q), _mm_and_si128(over, hi));
        under = _mm_cmplt_epi32(q, lo);
        q = _mm_or_si128(_mm_andnot_si128(under, q), _mm_and_si128(under, lo));
        _mm_storel_epi64((__m128i *)(void *)(row + c), _mm_packs_epi32(q, q));
    }
    return c;
}
#endif

/* box_score over block row r of a uniform fan (one box b for the row), into
 * row[0..hc-1]: the same scores. The scored positions are one run of
 * columns, where both boxes lie inside the map (box_sum's clamps never
 * act), and where the largest numerator fits 32 bits (every block sums to
 * at most 16 x 255) the arithmetic is 32-bit: the same quotient, without
 * the per-position bounds tests and 64-bit products (Cortex-M7: 1.3 M
 * instructions a 530 x 512 frame before). */
static void score_row(const actag_search *z, const search_box *b, int r, int16_t *row)
{
    const int hc = z->hc, ir = b->ir, ic = b->ic, orr = b->orr, oc = b->oc;
    const size_t w = (size_t)hc + 1u;
    int c, c0 = oc, c1 = hc - oc;
    int32_t ni, no;
    int64_t top;
    const uint32_t *ia, *ib, *oa, *ob;
    if (!(r - orr >= 0 && r + orr < z->hr) || c1 <= c0)
        c0 = c1 = hc;
    for (c = 0; c < c0; c++)
        row[c] = INT16_MIN;
    for (c = c1; c < hc; c++)
        row[c] = INT16_MIN;
    if (c0 >= c1)
        return;
    ni = (2 * ir + 1) * (2 * ic + 1);
    no = (2 * orr + 1) * (2 * oc + 1);
    top = (int64_t)8 * 16 * 255 * ni * (no - ni);
#ifdef SEARCH_SSE2
    /* four columns at a time in double (products of either size) */
    c0 = score_run_sse2(z->ii + (size_t)(r - ir) * w, z->ii + (size_t)(r + ir + 1) * w,
                        z->ii + (size_t)(r - orr) * w, z->ii + (size_t)(r + orr + 1) * w, ic, oc,
                        ni, no, c0, c1, row);
#endif
    if (top > INT32_MAX) {
        for (c = c0; c < c1; c++)
            row[c] = box_score(z, b, r, c);
        return;
    }
    ia = z->ii + (size_t)(r - ir) * w;
    ib = z->ii + (size_t)(r + ir + 1) * w;
    oa = z->ii + (size_t)(r - orr) * w;
    ob = z->ii + (size_t)(r + orr + 1) * w;
    {
        const int32_t nd = no - ni, den = ni * nd * ACTAG_SEARCH_FACTOR * ACTAG_SEARCH_FACTOR;
        for (c = c0; c < c1; c++) {
            int32_t si = (int32_t)(ib[c + ic + 1] - ia[c + ic + 1] - ib[c - ic] + ia[c - ic]);
            int32_t so = (int32_t)(ob[c + oc + 1] - oa[c + oc + 1] - ob[c - oc] + oa[c - oc]);
            int32_t q = 8 * (si * nd - (so - si) * ni) / den;
            row[c] = (int16_t)(q > 2040 ? 2040 : q < -2040 ? -2040 : q);
        }
    }
}

int actag_search_map(actag_search *z, const uint8_t *img, int rows, int cols, int stride,
                     const actag_sonar_geometry *g, float tag_size, int bits, float range_scale,
                     void *mapmem, size_t mapmem_size, void *scratch, size_t scratch_size)
{
    int r, c, hr, hc, rc;
    size_t w;
    float dr;
    if (z == NULL || img == NULL || g == NULL || mapmem == NULL || scratch == NULL)
        return ACTAG_ERR_NULL;
    /* read and written as uint32_t and int16_t */
    if (((uintptr_t)scratch & 3u) != 0u || ((uintptr_t)mapmem & 1u) != 0u)
        return ACTAG_ERR_PARAM;
    rc = actag_geometry_validate(g, rows, cols, NULL);
    if (rc != ACTAG_OK)
        return rc;
    if (stride < cols)
        return ACTAG_ERR_SIZE;
    if (!finite_pos(tag_size) || !finite_pos(range_scale) || bits < 16 || bits > 32 || bits % 4 != 0)
        return ACTAG_ERR_PARAM;
    hr = rows / ACTAG_SEARCH_FACTOR;
    hc = cols / ACTAG_SEARCH_FACTOR;
    if (hr < 4 || hc < 4)
        return ACTAG_ERR_SIZE;
    if (scratch_size < ACTAG_SEARCH_INTEGRAL_SIZE(rows, cols) ||
        mapmem_size < ACTAG_SEARCH_MAP_SIZE(rows, cols))
        return ACTAG_ERR_WORKSPACE;
    w = (size_t)hc + 1u;
    dr = actag_geometry_range_step(g, rows);
    z->hr = hr;
    z->hc = hc;
    z->ii = (uint32_t *)scratch;
    z->map = (int16_t *)mapmem;
    for (c = 0; c <= hc; c++)
        z->ii[c] = 0u;
    for (r = 0; r < hr; r++) {
        uint32_t run = 0u;
        uint32_t *prev = z->ii + (size_t)r * w, *cur = prev + w;
        const uint8_t *a = img + (size_t)(ACTAG_SEARCH_FACTOR * r) * (size_t)stride;
        cur[0] = 0u;
        c = 0;
#ifdef SEARCH_SSE2
        c = block_rows_sse2(a, (size_t)stride, hc, prev, cur, &run);
        a += (size_t)c * ACTAG_SEARCH_FACTOR;
#endif
        for (; c < hc; c++, a += ACTAG_SEARCH_FACTOR) {
            run += block_sum4(a, (size_t)stride);
            cur[c + 1] = prev[c + 1] + run;
        }
    }
    for (r = 0; r < hr; r++) {
        float y = (float)(ACTAG_SEARCH_FACTOR * r) + 0.5f * (float)(ACTAG_SEARCH_FACTOR - 1);
        float range = actag_geometry_range(g, rows, y);
        /* the white square is k-3 cells wide; the ring box one cell more */
        float cell = tag_size / (float)(bits / 4 - 3), half_in = 0.5f * (float)(bits / 4 - 3);
        float cr = cell * range_scale / dr / (float)ACTAG_SEARCH_FACTOR; /* low-res pixels per cell along range */
        int16_t *row = z->map + (size_t)r * (size_t)hc;
        search_box b;
        if (g->bearings == NULL) {
            /* a uniform fan has one azimuth step: one box for the row */
            if (!box_of(cr, actag_geometry_azimuth_step(g, cols, 0.5f * (float)cols) * range, cell,
                        half_in, hr, hc, &b)) {
                for (c = 0; c < hc; c++)
                    row[c] = INT16_MIN;
                continue;
            }
            score_row(z, &b, r, row);
            continue;
        }
        for (c = 0; c < hc; c++) {
            /* a bearing table's step at the block's own column, as
             * actag_search_next sizes its quad there */
            float x = (float)(ACTAG_SEARCH_FACTOR * c) + 0.5f * (float)(ACTAG_SEARCH_FACTOR - 1);
            row[c] = box_of(cr, actag_geometry_azimuth_step(g, cols, x) * range, cell, half_in, hr,
                            hc, &b)
                         ? box_score(z, &b, r, c)
                         : INT16_MIN;
        }
    }
    return ACTAG_OK;
}

#ifdef SEARCH_SSE2
/* The scan for the best position, as the row-major one: the first of the
 * map's n scores holding the largest one, when that is above `best`
 * (*br, *bc then its row and column in rows of hc; else untouched).
 * Returns the new best. The largest score first (8 lanes), then its first
 * place. */
static int best_sse2(const int16_t *map, size_t n, int best, int hc, int *br, int *bc)
{
    __m128i mx = _mm_set1_epi16(INT16_MIN), v;
    size_t i, at;
    int m, k;
    for (i = 0; i + 8u <= n; i += 8u)
        mx = _mm_max_epi16(mx, _mm_loadu_si128((const __m128i *)(const void *)(map + i)));
    mx = _mm_max_epi16(mx, _mm_shuffle_epi32(mx, 0x4e));
    mx = _mm_max_epi16(mx, _mm_shuffle_epi32(mx, 0xb1));
    mx = _mm_max_epi16(mx, _mm_shufflelo_epi16(mx, 0xb1));
    m = (int16_t)_mm_cvtsi128_si32(mx);
    for (at = i; at < n; at++)
        if (map[at] > m)
            m = map[at];
    if (!(m > best))
        return best;
    v = _mm_set1_epi16((short)m);
    for (at = 0; at + 8u <= n; at += 8u) {
        k = _mm_movemask_epi8(_mm_cmpeq_epi16(_mm_loadu_si128((const __m128i *)(const void *)(map + at)), v));
        if (k) { /* two mask bits a lane: the first lane set */
            for (; !(k & 1); k >>= 2)
                at++;
            break;
        }
    }
    while (map[at] != m) /* (in the last n % 8 when no vector holds it) */
        at++;
    *br = (int)(at / (size_t)hc);
    *bc = (int)(at % (size_t)hc);
    return m;
}
#endif

/* Takes the best remaining position (score >= min), suppresses its
 * neighbourhood, and returns the axis-aligned white-square quad (full
 * resolution). Returns 0 when nothing is left. */
int actag_search_next(actag_search *z, int min_score, const actag_sonar_geometry *g,
                      float tag_size, float range_scale, int rows, int cols,
                      actag_point quad[4])
{
    int r, c, br = -1, bc = -1, best;
    float y, x, hr_px, hc_px;
    /* INT16_MIN marks unscored positions: never a candidate (and no
     * overflow in min_score - 1) */
    if (min_score < INT16_MIN + 1)
        min_score = INT16_MIN + 1;
    best = min_score - 1;
#ifdef SEARCH_SSE2
    best = best_sse2(z->map, (size_t)z->hr * (size_t)z->hc, best, z->hc, &br, &bc);
#else
    for (r = 0; r < z->hr; r++) {
        const int16_t *m = z->map + (size_t)r * (size_t)z->hc;
        for (c = 0; c < z->hc; c++)
            if (m[c] > best) {
                best = m[c];
                br = r;
                bc = c;
            }
    }
#endif
    if (br < 0)
        return 0;
    y = (float)(ACTAG_SEARCH_FACTOR * br) + 0.5f * (float)(ACTAG_SEARCH_FACTOR - 1);
    x = (float)(ACTAG_SEARCH_FACTOR * bc) + 0.5f * (float)(ACTAG_SEARCH_FACTOR - 1);
    actag__search_box(g, rows, cols, x, y, tag_size, range_scale, quad, &hr_px, &hc_px);
    {
        int sr = px_count(hr_px * 1.5f / (float)ACTAG_SEARCH_FACTOR, z->hr) + 1,
            sc = px_count(hc_px * 1.5f / (float)ACTAG_SEARCH_FACTOR, z->hc) + 1;
        int r0 = br - sr, r1 = br + sr, c0 = bc - sc, c1 = bc + sc;
        if (r0 < 0) r0 = 0;
        if (c0 < 0) c0 = 0;
        if (r1 >= z->hr) r1 = z->hr - 1;
        if (c1 >= z->hc) c1 = z->hc - 1;
        for (r = r0; r <= r1; r++)
            for (c = c0; c <= c1; c++)
                z->map[(size_t)r * (size_t)z->hc + (size_t)c] = INT16_MIN;
    }
    return 1;
}

void actag__search_box(const actag_sonar_geometry *g, int rows, int cols, float x, float y,
                       float tag_size, float range_scale, actag_point quad[4], float *hr,
                       float *hc)
{
    float daz = actag_geometry_azimuth_step(g, cols, x) * actag_geometry_range(g, rows, y);
    float hr_px = 0.5f * tag_size * range_scale / actag_geometry_range_step(g, rows);
    float hc_px = 0.5f * tag_size / daz;
    quad[0].x = x - hc_px; quad[0].y = y - hr_px;
    quad[1].x = x + hc_px; quad[1].y = y - hr_px;
    quad[2].x = x + hc_px; quad[2].y = y + hr_px;
    quad[3].x = x - hc_px; quad[3].y = y + hr_px;
    if (hr)
        *hr = hr_px;
    if (hc)
        *hc = hc_px;
}

