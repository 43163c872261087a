/* Structure search (see search.h): box contrast of a bright square inside a
 * dark ring at the tag's physical size, on a block-averaged frame. */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/search.h"

#include "search_box.h"

#include <string.h>

#if defined(__ARM_FEATURE_SIMD32) && defined(__GNUC__) && !defined(ACTAG_NO_DSP)
#define SEARCH_DSP 1
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
        for (c = 0; c < hc; c++, a += ACTAG_SEARCH_FACTOR) {
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
    for (r = 0; r < z->hr; r++) {
        const int16_t *m = z->map + (size_t)r * (size_t)z->hc;
        for (c = 0; c < z->hc; c++)
            if (m[c] > best) {
                best = m[c];
                br = r;
                bc = c;
            }
    }
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

