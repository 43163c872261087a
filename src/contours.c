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

/* Bits 0..2 = padded-row bits b .. b+2 (pixels b-1 .. b+1 of that row). */
static unsigned bits3(const uint32_t *row, size_t b)
{
    uint32_t w = row[b / 32u] >> (b % 32u);
    if (b % 32u > 29u)
        w |= row[b / 32u + 1u] << (32u - b % 32u);
    return (unsigned)(w & 7u);
}

/* k_rev3[x]: bits 0..2 of x reversed (the row above is read right to left
 * in direction order). */
static const uint8_t k_rev3[8] = {0, 4, 2, 6, 1, 5, 3, 7};

/* Bit d set when the neighbour in direction d is white; outside the image is
 * black (the bitmap's padding), so every pixel takes the same path. up is
 * the padded row above the pixel's (its row r is up + wpr). */
static unsigned nb_mask(const uint32_t *up, size_t wpr, int c)
{
    size_t b = (size_t)c; /* padded bit index of column c - 1 */
    unsigned u = bits3(up, b), m = bits3(up + wpr, b), d = bits3(up + 2u * wpr, b);
    return (m >> 2) | (unsigned)k_rev3[u] << 1 | (m & 1u) << 4 | d << 5;
}

/* Traces the border through (r0, c0), whose black neighbour in direction
 * from_dir (4 = W for an outer border, 0 = E for a hole border) is the
 * border's black side, and marks every traced pixel. With info != NULL (an
 * outer border) it also reports the points and fills npoints, bbox and area.
 * Everything the walk updates lives in locals. */
static void trace(const actag_contour_scanner *s, int r0, int c0, int from_dir,
                  actag_ipoint *pts, int cap, actag_contour_info *info)
{
    const uint32_t *const white = s->white;
    uint32_t *const marks = s->marks;
    const size_t wpr = ACTAG_BITMAP_WORDS(s->cols);
    unsigned m;
    int d, k, r, c, r1, c1, dp;
    int n = 0, minx = c0, maxx = c0, maxy = r0, pr = 0, pc = 0;
    int64_t twice_area = 0;

    /* Step 3.1: clockwise from the black side, find the last border pixel
     * before the start (the walk ends on the step from it back to the start). */
    m = nb_mask(white + (size_t)r0 * wpr, wpr, c0);
    if (!m) { /* isolated pixel: traced, its east neighbour black */
        size_t i = (size_t)(r0 + 1) * wpr, b = (size_t)c0 + 1u;
        marks[i + b / 32u] |= (uint32_t)1u << (b % 32u);
        b++;
        marks[i + b / 32u] |= (uint32_t)1u << (b % 32u);
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
    r1 = r0 + k_dr[d];
    c1 = c0 + k_dc[d];
    dp = d; /* direction from the current pixel to the previous one */
    r = r0;
    c = c0;
    for (;;) {
        int sweep0 = (dp + 1) & 7, last = r == r1 && c == c1;
        size_t mi = (size_t)(r + 1) * wpr, b = (size_t)c + 1u;
        m = nb_mask(white + (size_t)r * wpr, wpr, c);
        /* Step 3.3: counterclockwise from just after the previous pixel to the
         * first white neighbour (the previous pixel is white, so k < 8). */
        k = k_ctz8[((m >> sweep0) | (m << (8 - sweep0))) & 0xffu];
        d = (sweep0 + k) & 7;
        /* Step 3.4: traced; and the east neighbour (black) marked when the
         * sweep passed over it ((8 - sweep0) & 7 is where east comes). */
        marks[mi + b / 32u] |= (uint32_t)1u << (b % 32u);
        if (((8 - sweep0) & 7) < k) {
            b++;
            marks[mi + b / 32u] |= (uint32_t)1u << (b % 32u);
        }
        if (info) {
            int dr = r - r0, dc = c - c0;
            if (n < cap) {
                pts[n].x = (int16_t)c;
                pts[n].y = (int16_t)r;
            }
            n += n < INT_MAX;
            minx = c < minx ? c : minx;
            maxx = c > maxx ? c : maxx;
            maxy = r > maxy ? r : maxy;
            /* Shoelace relative to the start, where the closing term vanishes;
             * written with the step (dr - pr, dc - pc) so nothing overflows. */
            twice_area += pc * (dr - pr) - (dc - pc) * pr;
            pr = dr;
            pc = dc;
        }
        r += k_dr[d];
        c += k_dc[d];
        /* Step 3.5: back at the start, coming from the last pixel. */
        if (last && r == r0 && c == c0)
            break;
        dp = (d + 4) & 7;
    }
    if (info) {
        info->npoints = n;
        info->min_x = minx;
        info->max_x = maxx;
        info->min_y = r0; /* the start is the blob's first pixel in raster order */
        info->max_y = maxy;
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
