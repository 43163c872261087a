/* Reference for tests/test_contour_walk.c: the contour scanner as it was
 * before its walks took the table k_walk and two walkers and its raster scan
 * took whole words of candidates (commit 2f2e9a4, src/contours.c): one
 * forward walk per border, each step a bit reversal table, a rotation and a
 * ctz table, every run start and end checked one at a time. The library
 * must give the same contours, points, counts, boxes, areas, scanner state
 * and marks after every call. Names prefixed ref_. */
#ifndef ACTAG_TEST_CONTOURS_REF_H
#define ACTAG_TEST_CONTOURS_REF_H

#include <limits.h>
#include <string.h>

#include "actag/contours.h"

static const int ref_dr[8] = {0, -1, -1, -1, 0, 1, 1, 1};
static const int ref_dc[8] = {1, 1, 0, -1, -1, -1, 0, 1};

static int ref_ctz32(uint32_t x)
{
    int i = 0;
    while (!(x >> i & 1u))
        i++;
    return i;
}

/* Index of the lowest set bit of an 8-bit value (8 for 0). */
static unsigned ref_ctz8(unsigned x)
{
    unsigned i = 0;
    while (i < 8u && !(x >> i & 1u))
        i++;
    return i;
}

/* Bit d set when the neighbour in direction d of the pixel at q is white. */
static unsigned ref_nb_mask(const uint32_t *white, size_t wpr, size_t q)
{
    static const uint8_t rev3[8] = {0, 4, 2, 6, 1, 5, 3, 7};
    const uint32_t *w = white + q / 32u;
    unsigned sh = (unsigned)(q % 32u);
    uint32_t u = w[0] >> sh, m = w[wpr] >> sh, d = w[2u * wpr] >> sh;
    if (sh > 29u) {
        u |= w[1] << (32u - sh);
        m |= w[wpr + 1u] << (32u - sh);
        d |= w[2u * wpr + 1u] << (32u - sh);
    }
    return (unsigned)(m >> 2 & 1u) | (unsigned)rev3[u & 7u] << 1 | (unsigned)(m & 1u) << 4 |
           (unsigned)(d & 7u) << 5;
}

static void ref_set_bit(uint32_t *bits, size_t b)
{
    bits[b / 32u] |= (uint32_t)1u << (b % 32u);
}

static unsigned ref_walk_step(const uint32_t *white, uint32_t *mrow0, size_t wpr, size_t q,
                              unsigned s1)
{
    unsigned m = ref_nb_mask(white, wpr, q), t;
    t = s1 + ref_ctz8(((m | m << 8) >> s1) & 0xffu);
    {
        uint32_t *mw = mrow0 + (q + 1u) / 32u;
        unsigned sh = (unsigned)((q + 1u) % 32u), e = (t + 7u) >> 4; /* t > 8 */
        *mw |= (uint32_t)(e + e + 1u) << sh;
        if (sh == 31u && e)
            mw[1] |= 1u;
    }
    return t;
}

static void ref_trace(const actag_contour_scanner *s, int r0, int c0, int from_dir,
                      actag_ipoint *pts, int cap, actag_contour_info *info)
{
    const uint32_t *const white = s->white;
    const size_t wpr = ACTAG_BITMAP_WORDS(s->cols);
    uint32_t *const mrow0 = s->marks + wpr;
    const size_t q0 = (size_t)r0 * 32u * wpr + (size_t)c0;
    size_t step[8], q;
    unsigned m, t, dback;
    int d, k;

    for (d = 0; d < 8; d++)
        step[d] = (size_t)ref_dr[d] * 32u * wpr + (size_t)ref_dc[d];
    m = ref_nb_mask(white, wpr, q0);
    if (!m) {
        ref_set_bit(mrow0, q0 + 1u);
        ref_set_bit(mrow0, q0 + 2u);
        if (info) {
            if (cap > 0) {
                pts[0].x = (int16_t)c0;
                pts[0].y = (int16_t)r0;
            }
            info->npoints = 1;
            info->min_x = info->max_x = c0;
            info->min_y = info->max_y = r0;
            info->area = 0.0f;
        }
        return;
    }
    for (k = 1; !(m & (1u << ((from_dir - k) & 7))); k++)
        ;
    d = (from_dir - k) & 7;
    dback = (unsigned)(d + 4) & 7u;
    t = (unsigned)d + 4u;
    q = q0;
    if (!info) {
        for (;;) {
            t = ref_walk_step(white, mrow0, wpr, q, ((t + 4u) & 7u) + 1u);
            q += step[t & 7u];
            if (q == q0 && (t & 7u) == dback)
                return;
        }
    } else {
        int n = 0, minx = 0, maxx = 0, maxy = 0, dr = 0, dc = 0;
        int64_t twice_area = 0;
        for (;;) {
            int sr, sc;
            t = ref_walk_step(white, mrow0, wpr, q, ((t + 4u) & 7u) + 1u);
            if (n < cap) {
                pts[n].x = (int16_t)(c0 + dc);
                pts[n].y = (int16_t)(r0 + dr);
            }
            n += n < INT_MAX;
            minx = dc < minx ? dc : minx;
            maxx = dc > maxx ? dc : maxx;
            maxy = dr > maxy ? dr : maxy;
            sr = ref_dr[t & 7u];
            sc = ref_dc[t & 7u];
            twice_area += dc * sr - dr * sc;
            dr += sr;
            dc += sc;
            q += step[t & 7u];
            if (q == q0 && (t & 7u) == dback)
                break;
        }
        info->npoints = n;
        info->min_x = c0 + minx;
        info->max_x = c0 + maxx;
        info->min_y = r0;
        info->max_y = r0 + maxy;
        info->area = (float)(twice_area < 0 ? -twice_area : twice_area) * 0.5f;
    }
}

/* actag_contour_next() of the reference, on a scanner set up by
 * actag_contour_scanner_init() (arguments valid). */
static int ref_contour_next(actag_contour_scanner *s, actag_ipoint *pts, int cap,
                            actag_contour_info *info)
{
    int r, c;
    const int rows = s->rows, cols = s->cols;
    const size_t wpr = ACTAG_BITMAP_WORDS(cols);

    for (r = s->r, c = s->c; r < rows; r++, c = 0) {
        const uint32_t *row = s->white + (size_t)(r + 1) * wpr;
        const uint32_t *mrow = s->marks + (size_t)(r + 1) * wpr;
        size_t k;
        for (k = (size_t)(c + 1) / 32u; k < wpr; k++) {
            uint32_t w = row[k], starts, ends, ev;
            starts = w & ~((w << 1) | (k > 0 ? row[k - 1] >> 31 : 0u));
            ends = w & ~((w >> 1) | (k + 1 < wpr ? row[k + 1] << 31 : 0u));
            ev = starts | ends;
            if ((size_t)(c + 1) / 32u == k)
                ev &= ~0u << ((size_t)(c + 1) % 32u);
            while (ev) {
                int i = ref_ctz32(ev), cc = (int)(k * 32u) + i - 1;
                ev &= ev - 1u;
                if ((starts >> i & 1u) && !(mrow[k] >> i & 1u) &&
                    !actag_bitmap_get(s->white, cols, r - 1, cc - 1)) {
                    ref_trace(s, r, cc, 4, pts, cap, info);
                    info->stored = info->npoints < cap ? info->npoints : cap;
                    info->overflow = info->npoints > cap;
                    s->r = r;
                    s->c = cc + 1;
                    return 1;
                }
                if ((ends >> i & 1u) && !actag_bitmap_get(s->marks, cols, r, cc + 1) &&
                    !(actag_bitmap_get(s->white, cols, r, cc + 2) &&
                      actag_bitmap_get(s->white, cols, r - 1, cc + 1) &&
                      actag_bitmap_get(s->white, cols, r + 1, cc + 1))) {
                    ref_trace(s, r, cc, 0, NULL, 0, NULL);
                    s->holes++;
                }
            }
        }
    }
    s->r = rows;
    s->c = 0;
    return 0;
}

#endif /* ACTAG_TEST_CONTOURS_REF_H */
