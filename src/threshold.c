/* Adaptive threshold with van Herk / Gil-Werman min and max, see
 * actag/threshold.h.
 *
 * Window extrema with edge replication equal the extrema over the window
 * cut at the border, so along one direction (n samples, radius r clamped
 * to n-1, w = 2r+1) output i is the extremum over [lo, hi] with
 * lo = max(0, i-r), hi = min(n-1, i+r). Split the samples into blocks of w
 * starting at 0 (the last one possibly shorter) and let P[t] be the
 * extremum from the start of t's block to t, S[t] from t to the end of its
 * block. Then the extremum over [lo, hi] is
 *   S[lo] op P[hi]  when lo and hi are in different blocks,
 *   P[hi]           when they share a block and lo starts it,
 *   S[lo]           when they share a block otherwise (only possible when
 *                   hi = n-1 ends that block),
 * and for a full window (hi - lo = 2r) the first form always holds. */
#include "actag/threshold.h"

#include <string.h>

#if defined(__SSE2__) && !defined(ACTAG_NO_SIMD)
#define THRESHOLD_SSE2 1
#include <emmintrin.h>
#endif

static uint8_t min8(uint8_t a, uint8_t b)
{
    return a < b ? a : b;
}

static uint8_t max8(uint8_t a, uint8_t b)
{
    return a > b ? a : b;
}

#ifdef THRESHOLD_SSE2
static __m128i ld(const uint8_t *p)
{
    return _mm_loadu_si128((const __m128i *)(const void *)p);
}

static void st(uint8_t *p, __m128i v)
{
    _mm_storeu_si128((__m128i *)(void *)p, v);
}
#endif

/* dmin = min(amin, bmin), dmax = max(amax, bmax) over n bytes. d may equal
 * a or b (same pointer); no other overlap. The row operations below have an
 * SSE2 body and a portable one (and tail); both give the same bytes. */
static void minmax_rows(uint8_t *dmin, uint8_t *dmax, const uint8_t *amin, const uint8_t *amax,
                        const uint8_t *bmin, const uint8_t *bmax, size_t n)
{
    size_t k = 0;
#ifdef THRESHOLD_SSE2
    for (; k + 16 <= n; k += 16) {
        __m128i mn = _mm_min_epu8(ld(amin + k), ld(bmin + k));
        __m128i mx = _mm_max_epu8(ld(amax + k), ld(bmax + k));
        st(dmin + k, mn);
        st(dmax + k, mx);
    }
#endif
    for (; k < n; k++) {
        uint8_t mn = min8(amin[k], bmin[k]), mx = max8(amax[k], bmax[k]);
        dmin[k] = mn;
        dmax[k] = mx;
    }
}

/* Full-window thresholds of n consecutive pixels x:
 * d = (2x + off2 >= min(sa, pa) + max(sb, pb)), off2 = 2 * offset in
 * [-512, 510]. */
static void threshold_run(uint8_t *restrict d, const uint8_t *restrict x,
                          const uint8_t *restrict sa, const uint8_t *restrict pa,
                          const uint8_t *restrict sb, const uint8_t *restrict pb, size_t n, int off2)
{
    size_t k = 0;
#ifdef THRESHOLD_SSE2
    /* 2x + off2 >= mn + mx  <=>  x + off >= ceil((mn + mx) / 2) = avg(mn, mx)
     * (the left side is an integer), compared in 16 bits. */
    const __m128i z = _mm_setzero_si128(), one = _mm_set1_epi8(1);
    const __m128i off = _mm_set1_epi16((short)(off2 / 2));
    for (; k + 16 <= n; k += 16) {
        __m128i a = _mm_avg_epu8(_mm_min_epu8(ld(sa + k), ld(pa + k)),
                                 _mm_max_epu8(ld(sb + k), ld(pb + k)));
        __m128i xv = ld(x + k);
        __m128i lt0 = _mm_cmpgt_epi16(_mm_unpacklo_epi8(a, z), _mm_add_epi16(_mm_unpacklo_epi8(xv, z), off));
        __m128i lt1 = _mm_cmpgt_epi16(_mm_unpackhi_epi8(a, z), _mm_add_epi16(_mm_unpackhi_epi8(xv, z), off));
        st(d + k, _mm_andnot_si128(_mm_packs_epi16(lt0, lt1), one));
    }
#endif
    for (; k < n; k++)
        d[k] = (uint8_t)(2 * x[k] + off2 >= min8(sa[k], pa[k]) + max8(sb[k], pb[k]));
}

/* Horizontal pass in place: on entry xmin/xmax hold one line of vertical
 * extrema; on exit they hold the block prefix extrema P, and smin/smax the
 * block suffix extrema S (blocks of w samples, the last one possibly
 * shorter). S is computed first, while xmin/xmax still hold the input. */
static void block_prefix_suffix(uint8_t *restrict xmin, uint8_t *restrict xmax,
                                uint8_t *restrict smin, uint8_t *restrict smax, int n, int w)
{
    int b0, k;
    for (b0 = 0; b0 < n; b0 += w) {
        int end = n - b0 > w ? b0 + w : n; /* one past the block's end */
        uint8_t a = xmin[end - 1], c = xmax[end - 1];
        smin[end - 1] = a;
        smax[end - 1] = c;
        for (k = end - 2; k >= b0; k--) {
            a = min8(a, xmin[k]);
            c = max8(c, xmax[k]);
            smin[k] = a;
            smax[k] = c;
        }
        a = xmin[b0];
        c = xmax[b0];
        for (k = b0 + 1; k < end; k++) {
            a = min8(a, xmin[k]);
            c = max8(c, xmax[k]);
            xmin[k] = a;
            xmax[k] = c;
        }
    }
}

int actag_adaptive_threshold(const uint8_t *src, int rows, int cols, int src_stride,
                             uint8_t *dst, int dst_stride, int radius, int offset,
                             void *scratch, size_t scratch_size)
{
    size_t ucols, sstride, dstride, nblk;
    uint8_t *sbuf_min, *sbuf_max, *pmin, *pmax, *hmin, *hmax, *hsmin, *hsmax;
    int rv, rh, wv, wh, i, j, sblk, phi, off2;

    if (src == NULL || dst == NULL || scratch == NULL)
        return ACTAG_ERR_NULL;
    if (rows < 1 || cols < 1 || rows > ACTAG_MAX_DIM || cols > ACTAG_MAX_DIM ||
        src_stride < cols || dst_stride < cols)
        return ACTAG_ERR_SIZE;
    if (radius < 0 || (const void *)src == (const void *)dst)
        return ACTAG_ERR_PARAM;
    if (scratch_size < ACTAG_THRESHOLD_SCRATCH_SIZE_R(rows, cols, radius))
        return ACTAG_ERR_WORKSPACE;

    /* A radius beyond the image gives the same windows as n-1. */
    rv = radius < rows - 1 ? radius : rows - 1;
    rh = radius < cols - 1 ? radius : cols - 1;
    wv = 2 * rv + 1;
    wh = 2 * rh + 1;
    /* 2x - mn - mx lies in [-510, 510], so offsets beyond [-256, 255] give
     * the same answers as those bounds; clamping avoids int overflow. */
    off2 = 2 * (offset < -256 ? -256 : (offset > 255 ? 255 : offset));

    ucols = (size_t)cols;
    sstride = (size_t)src_stride;
    dstride = (size_t)dst_stride;
    if (rv == 0 && rh == 0) {
        /* 1 x 1 windows: mn = mx = x, so the answer is offset >= 0. */
        for (i = 0; i < rows; i++)
            memset(dst + (size_t)i * dstride, offset >= 0, ucols);
        return ACTAG_OK;
    }
    nblk = (size_t)(wv < rows ? wv : rows);
    sbuf_min = (uint8_t *)scratch;
    sbuf_max = sbuf_min + nblk * ucols;
    pmin = sbuf_max + nblk * ucols;
    pmax = pmin + ucols;
    hmin = pmax + ucols;
    hmax = hmin + ucols;
    hsmin = hmax + ucols;
    hsmax = hsmin + ucols;

    sblk = -1; /* block whose suffix extrema are in sbuf */
    phi = -1;  /* last row folded into pmin/pmax */
    for (i = 0; i < rows; i++) {
        int lo = i - rv > 0 ? i - rv : 0;
        int hi = i + rv < rows - 1 ? i + rv : rows - 1;
        int bl = lo / wv;
        const uint8_t *x = src + (size_t)i * sstride;
        uint8_t *d = dst + (size_t)i * dstride;

        /* Vertical: suffix extrema of lo's block, computed when first needed
         * (lo only moves forward, so one block buffer suffices). */
        if (bl != sblk) {
            int b0 = bl * wv;
            int end = rows - b0 > wv ? b0 + wv : rows;
            int t = end - 1 - b0;
            const uint8_t *row = src + (size_t)(end - 1) * sstride;
            memcpy(sbuf_min + (size_t)t * ucols, row, ucols);
            memcpy(sbuf_max + (size_t)t * ucols, row, ucols);
            for (t--; t >= 0; t--) {
                uint8_t *smn = sbuf_min + (size_t)t * ucols, *smx = sbuf_max + (size_t)t * ucols;
                row = src + (size_t)(b0 + t) * sstride;
                minmax_rows(smn, smx, smn + ucols, smx + ucols, row, row, ucols);
            }
            sblk = bl;
        }
        /* Vertical: prefix extrema of hi's block up to hi. */
        while (phi < hi) {
            const uint8_t *row;
            phi++;
            row = src + (size_t)phi * sstride;
            if (phi % wv == 0) {
                memcpy(pmin, row, ucols);
                memcpy(pmax, row, ucols);
            } else {
                minmax_rows(pmin, pmax, pmin, pmax, row, row, ucols);
            }
        }
        {
            const uint8_t *smn = sbuf_min + (size_t)(lo - bl * wv) * ucols;
            const uint8_t *smx = sbuf_max + (size_t)(lo - bl * wv) * ucols;
            if (hi / wv != bl) {
                minmax_rows(hmin, hmax, smn, smx, pmin, pmax, ucols);
            } else if (lo % wv == 0) { /* lo starts hi's block */
                memcpy(hmin, pmin, ucols);
                memcpy(hmax, pmax, ucols);
            } else { /* same block, cut at the bottom */
                memcpy(hmin, smn, ucols);
                memcpy(hmax, smx, ucols);
            }
        }

        /* Horizontal, then the threshold: 2x + 2 offset >= mn + mx. */
        block_prefix_suffix(hmin, hmax, hsmin, hsmax, cols, wh);
        for (j = 0; j < cols; j++) {
            int jlo = j - rh > 0 ? j - rh : 0;
            int jhi = j + rh < cols - 1 ? j + rh : cols - 1;
            int mn, mx;
            if (j >= rh && j + rh <= cols - 1) {
                /* Full windows, j .. cols-rh-1: S[j-rh] op P[j+rh]. */
                int jend = cols - rh;
                threshold_run(d + j, x + j, hsmin + (j - rh), hmin + (j + rh), hsmax + (j - rh),
                              hmax + (j + rh), (size_t)(jend - j), off2);
                j = jend - 1;
                continue;
            }
            if (jhi / wh != jlo / wh) {
                mn = min8(hsmin[jlo], hmin[jhi]);
                mx = max8(hsmax[jlo], hmax[jhi]);
            } else if (jlo % wh == 0) {
                mn = hmin[jhi];
                mx = hmax[jhi];
            } else {
                mn = hsmin[jlo];
                mx = hsmax[jlo];
            }
            d[j] = (uint8_t)(2 * x[j] + off2 >= mn + mx);
        }
    }
    return ACTAG_OK;
}
