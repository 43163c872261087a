/*
 * Border following after Suzuki & Abe (1985), "Topological structural
 * analysis of digitized binary images by border following", algorithm 1,
 * 8-connectivity, without the hierarchy (no NBD labels): we only need to know
 * whether a pixel has been traced and whether its right neighbour was seen as
 * the black side of a border, so one mark bit per pixel beside the binary
 * bitmap suffices (see the pixel states below). That is what makes the
 * scanner allocation-free and streaming.
 *
 * Both outer and hole borders are traced (each exactly once, as in the
 * paper); hole borders only to mark their pixels, so that the raster scan
 * never mistakes the pixel right of a hole for the first pixel of a new blob.
 * One-pixel holes, frequent in speckle, are recognised in the raster scan
 * and not walked at all.
 *
 * Cost: every pixel is looked at O(1) times by the raster scan (32 at a time
 * to find run starts and ends) and every border pixel O(1) times by the
 * walks, so a scan is O(rows * cols + total border length).
 */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/contours.h"

#include <limits.h>
#include <string.h>

/* Pixel states, kept in two bitmaps (common.h layout):
 *   white  the binary image (1 = white), read only;
 *   marks  bit (r, c) of a WHITE pixel: on a traced border (Suzuki-Abe's
 *          +NBD or -NBD); bit (r, c + 1) when (r, c + 1) is BLACK (or the
 *          padding column right of the image): the white pixel (r, c) left of
 *          it is on a traced border whose black side that pixel is
 *          (Suzuki-Abe's -NBD: no hole border starts at (r, c)).
 * The second meaning only ever marks black pixels, the first only white
 * ones, so the four states of a byte-per-pixel tracer (black, white, traced,
 * traced with east black) fit in two bits per pixel. */

#define SCANNER_MAGIC 0x43545253 /* "CTRS" */

/* Neighbour directions, counterclockwise on screen (y down):
 * 0 E, 1 NE, 2 N, 3 NW, 4 W, 5 SW, 6 S, 7 SE. */
static const int k_dr[8] = {0, -1, -1, -1, 0, 1, 1, 1};
static const int k_dc[8] = {1, 1, 0, -1, -1, -1, 0, 1};

/* Count of trailing zero bits (x != 0), by de Bruijn multiplication: portable
 * C99, no compiler builtins, same result everywhere. */
static const uint8_t k_debruijn[32] = {0,  1,  28, 2,  29, 14, 24, 3,  30, 22, 20,
                                       15, 25, 17, 4,  8,  31, 27, 13, 23, 21, 19,
                                       16, 7,  26, 12, 18, 6,  11, 5,  10, 9};
static int ctz32(uint32_t x)
{
    return k_debruijn[((x & (0u - x)) * 0x077CB531u) >> 27];
}

/* Index of the lowest set bit of an 8-bit value (8 for 0). */
static const uint8_t k_ctz8[256] = {
    8, 0, 1, 0, 2, 0, 1, 0, 3, 0, 1, 0, 2, 0, 1, 0, 4, 0, 1, 0, 2, 0, 1, 0, 3, 0, 1, 0, 2, 0, 1, 0,
    5, 0, 1, 0, 2, 0, 1, 0, 3, 0, 1, 0, 2, 0, 1, 0, 4, 0, 1, 0, 2, 0, 1, 0, 3, 0, 1, 0, 2, 0, 1, 0,
    6, 0, 1, 0, 2, 0, 1, 0, 3, 0, 1, 0, 2, 0, 1, 0, 4, 0, 1, 0, 2, 0, 1, 0, 3, 0, 1, 0, 2, 0, 1, 0,
    5, 0, 1, 0, 2, 0, 1, 0, 3, 0, 1, 0, 2, 0, 1, 0, 4, 0, 1, 0, 2, 0, 1, 0, 3, 0, 1, 0, 2, 0, 1, 0,
    7, 0, 1, 0, 2, 0, 1, 0, 3, 0, 1, 0, 2, 0, 1, 0, 4, 0, 1, 0, 2, 0, 1, 0, 3, 0, 1, 0, 2, 0, 1, 0,
    5, 0, 1, 0, 2, 0, 1, 0, 3, 0, 1, 0, 2, 0, 1, 0, 4, 0, 1, 0, 2, 0, 1, 0, 3, 0, 1, 0, 2, 0, 1, 0,
    6, 0, 1, 0, 2, 0, 1, 0, 3, 0, 1, 0, 2, 0, 1, 0, 4, 0, 1, 0, 2, 0, 1, 0, 3, 0, 1, 0, 2, 0, 1, 0,
    5, 0, 1, 0, 2, 0, 1, 0, 3, 0, 1, 0, 2, 0, 1, 0, 4, 0, 1, 0, 2, 0, 1, 0, 3, 0, 1, 0, 2, 0, 1, 0,
};

/* k_rev3[x]: bits 0..2 of x reversed (the row above is read right to left
 * in direction order). */
static const uint8_t k_rev3[8] = {0, 4, 2, 6, 1, 5, 3, 7};

/* The walks address a pixel (r, c) by q = r * 32 * wpr + c, the bit index
 * of its up-left neighbour (r - 1, c - 1) in the padded bitmap: one add per
 * step, the neighbourhood words come from q without a multiply and the
 * pixel's mark is bit q + 1 of the marks from row 0 on (marks + wpr). */
#define CINLINE __attribute__((always_inline)) static inline

/* Bit d set when the neighbour in direction d of the pixel at q is white;
 * outside the image is black (the bitmap's padding), so every pixel takes
 * the same path. The three rows' bits share one shift; they straddle a word
 * only for 2 positions in 32. */
CINLINE unsigned nb_mask(const uint32_t *white, size_t wpr, size_t q)
{
    const uint32_t *w = white + q / 32u;
    unsigned sh = (unsigned)(q % 32u);
    uint32_t u = w[0] >> sh, m = w[wpr] >> sh, d = w[2u * wpr] >> sh;
    if (sh > 29u) {
        u |= w[1] << (32u - sh);
        m |= w[wpr + 1u] << (32u - sh);
        d |= w[2u * wpr + 1u] << (32u - sh);
    }
    return (unsigned)(m >> 2 & 1u) | (unsigned)k_rev3[u & 7u] << 1 | (unsigned)(m & 1u) << 4 |
           (unsigned)(d & 7u) << 5;
}

/* Sets bit b of a bitmap. */
CINLINE void set_bit(uint32_t *bits, size_t b)
{
    bits[b / 32u] |= (uint32_t)1u << (b % 32u);
}

/* One step of the walk (steps 3.3 and 3.4) at q, whose previous pixel lies
 * in direction s1 - 1 (s1 = 1 .. 8). Marks the pixel traced, and its east
 * neighbour (black) when the sweep passed over it; returns t = s1 + k, where
 * k is the counterclockwise sweep from just after the previous pixel to the
 * first white neighbour (the previous pixel is white, so k < 8): the next
 * direction is t & 7. With the mask doubled the rotation by 8 is the one by
 * 0, and east (direction 8 from the sweep's origin) was passed iff t > 8. */
CINLINE unsigned walk_step(const uint32_t *white, uint32_t *mrow0, size_t wpr, size_t q,
                           unsigned s1)
{
    unsigned m = nb_mask(white, wpr, q), t;
    t = s1 + k_ctz8[((m | m << 8) >> s1) & 0xffu];
    /* Both marks with one write to the word, bar the east one across it. */
    {
        uint32_t *mw = mrow0 + (q + 1u) / 32u;
        unsigned sh = (unsigned)((q + 1u) % 32u), e = (t + 7u) >> 4; /* t > 8 */
        *mw |= (uint32_t)(e + e + 1u) << sh;
        if (sh == 31u && e)
            mw[1] |= 1u;
    }
    return t;
}

/* Traces the border through (r0, c0), whose black neighbour in direction
 * from_dir (4 = W for an outer border, 0 = E for a hole border) is the
 * border's black side, and marks every traced pixel. With info != NULL (an
 * outer border) it also reports the points and fills npoints, bbox and area.
 * Everything the walk updates lives in locals; hole borders take a loop of
 * their own that keeps nothing but the position. */
static void trace(const actag_contour_scanner *s, int r0, int c0, int from_dir,
                  actag_ipoint *pts, int cap, actag_contour_info *info)
{
    const uint32_t *const white = s->white;
    const size_t wpr = ACTAG_BITMAP_WORDS(s->cols);
    uint32_t *const mrow0 = s->marks + wpr;
    const size_t q0 = (size_t)r0 * 32u * wpr + (size_t)c0;
    size_t step[8], q;
    unsigned m, t, dback;
    int d, k;

    for (d = 0; d < 8; d++) /* unsigned wraparound for the negative steps */
        step[d] = (size_t)k_dr[d] * 32u * wpr + (size_t)k_dc[d];
    /* Step 3.1: clockwise from the black side, find the last border pixel
     * before the start (the walk ends on the step from it back to the start). */
    m = nb_mask(white, wpr, q0);
    if (!m) { /* isolated pixel: traced, its east neighbour black */
        set_bit(mrow0, q0 + 1u);
        set_bit(mrow0, q0 + 2u);
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
    /* Step 3.5: the walk ends on arriving at the start in direction dback,
     * i.e. from the last pixel (the one in direction d of the start). */
    dback = (unsigned)(d + 4) & 7u;
    /* t = s1 + k of the step that led here: the previous pixel is in
     * direction d, so the first sweep starts at s1 = d + 1. */
    t = (unsigned)d + 4u;
    q = q0;
    if (!info) {
        for (;;) {
            t = walk_step(white, mrow0, wpr, q, ((t + 4u) & 7u) + 1u);
            q += step[t & 7u];
            if (q == q0 && (t & 7u) == dback)
                return;
        }
    } else {
        int n = 0, minx = 0, maxx = 0, maxy = 0, dr = 0, dc = 0;
        int64_t twice_area = 0;
        for (;;) {
            int sr, sc;
            t = walk_step(white, mrow0, wpr, q, ((t + 4u) & 7u) + 1u);
            if (n < cap) {
                pts[n].x = (int16_t)(c0 + dc);
                pts[n].y = (int16_t)(r0 + dr);
            }
            n += n < INT_MAX;
            minx = dc < minx ? dc : minx;
            maxx = dc > maxx ? dc : maxx;
            maxy = dr > maxy ? dr : maxy;
            /* Shoelace relative to the start, where the first and closing
             * terms vanish, written with the step so nothing overflows. */
            sr = k_dr[t & 7u];
            sc = k_dc[t & 7u];
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
        info->min_y = r0; /* the start is the blob's first pixel in raster order */
        info->max_y = r0 + maxy;
        info->area = actag_i64_to_f(twice_area < 0 ? -twice_area : twice_area) * 0.5f;
    }
}

int actag_bitmap_pack(const uint8_t *img, int rows, int cols, int stride, uint32_t *bitmap)
{
    size_t wpr, r, c;
    if (!img || !bitmap)
        return ACTAG_ERR_NULL;
    if (rows < 1 || cols < 1 || rows > ACTAG_MAX_DIM || cols > ACTAG_MAX_DIM || stride < cols)
        return ACTAG_ERR_SIZE;
    wpr = ACTAG_BITMAP_WORDS(cols);
    memset(bitmap, 0, ACTAG_BITMAP_SIZE(rows, cols));
    for (r = 0; r < (size_t)rows; r++) {
        const uint8_t *src = img + r * (size_t)stride;
        uint32_t *row = bitmap + (r + 1u) * wpr;
        for (c = 0; c < (size_t)cols; c++)
            row[(c + 1u) / 32u] |= (uint32_t)(src[c] != 0) << ((c + 1u) % 32u);
    }
    return ACTAG_OK;
}

int actag_bitmap_unpack(const uint32_t *bitmap, int rows, int cols, uint8_t *dst, int dst_stride,
                        uint8_t white)
{
    size_t wpr, r, c;
    if (!bitmap || !dst)
        return ACTAG_ERR_NULL;
    if (rows < 1 || cols < 1 || rows > ACTAG_MAX_DIM || cols > ACTAG_MAX_DIM || dst_stride < cols)
        return ACTAG_ERR_SIZE;
    wpr = ACTAG_BITMAP_WORDS(cols);
    for (r = 0; r < (size_t)rows; r++) {
        const uint32_t *row = bitmap + (r + 1u) * wpr;
        uint8_t *d = dst + r * (size_t)dst_stride;
        for (c = 0; c < (size_t)cols; c++)
            d[c] = ((row[(c + 1u) / 32u] >> ((c + 1u) % 32u)) & 1u) ? white : 0u;
    }
    return ACTAG_OK;
}

int actag_contour_scanner_init(actag_contour_scanner *s, const uint32_t *white, uint32_t *marks,
                               int rows, int cols)
{
    if (!s || !white || !marks)
        return ACTAG_ERR_NULL;
    if (rows < 1 || cols < 1 || rows > ACTAG_MAX_DIM || cols > ACTAG_MAX_DIM)
        return ACTAG_ERR_SIZE;
    if ((const void *)white == (const void *)marks)
        return ACTAG_ERR_PARAM;
    memset(marks, 0, ACTAG_BITMAP_SIZE(rows, cols));
    s->white = white;
    s->marks = marks;
    s->rows = rows;
    s->cols = cols;
    s->r = 0;
    s->c = 0;
    s->holes = 0;
    s->magic = SCANNER_MAGIC;
    return ACTAG_OK;
}

int actag_contour_next(actag_contour_scanner *s, actag_ipoint *pts, int cap,
                       actag_contour_info *info)
{
    int r, c;
    const int rows = s ? s->rows : 0, cols = s ? s->cols : 0;
    size_t wpr;

    if (!s || !info || (cap > 0 && !pts))
        return ACTAG_ERR_NULL;
    if (cap < 0 || s->magic != SCANNER_MAGIC || !s->white || !s->marks)
        return ACTAG_ERR_PARAM;
    wpr = ACTAG_BITMAP_WORDS(cols);

    for (r = s->r, c = s->c; r < rows; r++, c = 0) {
        const uint32_t *row = s->white + (size_t)(r + 1) * wpr;
        const uint32_t *mrow = s->marks + (size_t)(r + 1) * wpr;
        size_t k;
        /* 32 padded bits at a time: only run starts (white, left black) can
         * begin an outer border and only run ends (white, right black) a hole
         * border. The padding bits are black, so bits outside the image never
         * start or end a run and no edge needs a special case. */
        for (k = (size_t)(c + 1) / 32u; k < wpr; k++) {
            uint32_t w = row[k], starts, ends, ev;
            starts = w & ~((w << 1) | (k > 0 ? row[k - 1] >> 31 : 0u));
            ends = w & ~((w >> 1) | (k + 1 < wpr ? row[k + 1] << 31 : 0u));
            ev = starts | ends;
            if ((size_t)(c + 1) / 32u == k)
                ev &= ~0u << ((size_t)(c + 1) % 32u); /* resuming after an outer border */
            while (ev) {
                int i = ctz32(ev), cc = (int)(k * 32u) + i - 1;
                ev &= ev - 1u;
                /* A black pixel whose four neighbours are white is a one-pixel
                 * hole (speckle makes many). Its border needs no walk: only
                 * the pixels left and right of it would consult its marks.
                 * The one right of it can then be unmarked, but its up-left
                 * neighbour (above the hole) is white, so it is not the first
                 * pixel of its blob; a white up-left neighbour always says so. */
                if ((starts >> i & 1u) && !(mrow[k] >> i & 1u) &&
                    !actag_bitmap_get(s->white, cols, r - 1, cc - 1)) {
                    /* First pixel of a new blob: its outer border. */
                    trace(s, r, cc, 4, pts, cap, info);
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
                    trace(s, r, cc, 0, NULL, 0, NULL); /* a hole border not traced yet */
                    s->holes++;
                }
            }
        }
    }
    s->r = rows;
    s->c = 0;
    return 0;
}
