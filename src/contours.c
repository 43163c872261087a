/*
 * Border following after Suzuki & Abe (1985), "Topological structural
 * analysis of digitized binary images by border following", algorithm 1,
 * 8-connectivity, without the hierarchy (no NBD labels): we only need to know
 * whether a pixel has been traced and whether its right neighbour was seen as
 * the black side of a border, so three pixel states suffice and fit in the
 * image bytes themselves. That is what makes the scanner allocation-free and
 * streaming.
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

/* Pixel states after init (black stays 0). */
#define PX_WHITE 1u /* white, not traced yet (Suzuki-Abe's 1) */
#define PX_TRACED 2u /* on a traced border (Suzuki-Abe's +NBD) */
#define PX_EAST 3u /* on a traced border whose east neighbour is the black side of
                      a traced border (Suzuki-Abe's -NBD): no hole starts here */

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

/* Bit i set when p[i] != 0, for i = 0..3 (SWAR, any byte order). */
static uint32_t white4(const uint8_t *p)
{
    uint32_t x = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
    /* High bit of each byte := byte != 0, then move it down to bit 0. */
    x = ((((x & 0x7f7f7f7fu) + 0x7f7f7f7fu) | x) & 0x80808080u) >> 7;
    /* Gather bits 0, 8, 16, 24 into bits 24..27 (no carries). */
    return (x * 0x01020408u) >> 24;
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

/* Bit d set when the neighbour in direction d is white; outside is black. */
static unsigned mask_checked(const actag_contour_scanner *s, int r, int c)
{
    unsigned m = 0u;
    int d;
    for (d = 0; d < 8; d++) {
        int rr = r + k_dr[d], cc = c + k_dc[d];
        if ((unsigned)rr < (unsigned)s->rows && (unsigned)cc < (unsigned)s->cols &&
            s->img[(ptrdiff_t)rr * s->stride + cc])
            m |= 1u << d;
    }
    return m;
}

/* The same for a pixel at least one pixel away from the image edge. */
static unsigned mask_fast(const uint8_t *p, ptrdiff_t stride)
{
    const uint8_t *q = p - stride, *u = p + stride;
    return (unsigned)(p[1] != 0) | (unsigned)(q[1] != 0) << 1 | (unsigned)(q[0] != 0) << 2 |
           (unsigned)(q[-1] != 0) << 3 | (unsigned)(p[-1] != 0) << 4 |
           (unsigned)(u[-1] != 0) << 5 | (unsigned)(u[0] != 0) << 6 | (unsigned)(u[1] != 0) << 7;
}

/* Traces the border through (r0, c0), whose black neighbour in direction
 * from_dir (4 = W for an outer border, 0 = E for a hole border) is the
 * border's black side, and marks every traced pixel. With info != NULL (an
 * outer border) it also reports the points and fills npoints, bbox and area.
 * Everything the walk updates lives in locals: stores through uint8_t may
 * alias anything, so fields reached through pointers would be reloaded from
 * memory on every step. */
static void trace(const actag_contour_scanner *s, int r0, int c0, int from_dir,
                  actag_ipoint *pts, int cap, actag_contour_info *info)
{
    uint8_t *const img = s->img;
    const ptrdiff_t st = s->stride;
    const int rlast = s->rows - 1, clast = s->cols - 1;
    uint8_t *p, *p0 = img + (ptrdiff_t)r0 * st + c0, *p1, *pend, pendv;
    ptrdiff_t off[8];
    unsigned m;
    int d, k, r, c, dp;
    int n = 0, minx = c0, maxx = c0, maxy = r0, pr = 0, pc = 0;
    int64_t twice_area = 0;

    for (d = 0; d < 8; d++)
        off[d] = (ptrdiff_t)k_dr[d] * st + k_dc[d];

    /* Step 3.1: clockwise from the black side, find the last border pixel
     * before the start (the walk ends on the step from it back to the start). */
    if (r0 > 0 && r0 < rlast && c0 > 0 && c0 < clast)
        m = mask_fast(p0, st);
    else
        m = mask_checked(s, r0, c0);
    if (!m) { /* isolated pixel */
        *p0 = PX_EAST;
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
    p1 = p0 + off[d];
    dp = d; /* direction from the current pixel to the previous one */
    r = r0;
    c = c0;
    p = p0;
    /* Each pixel's new mark is written one step late, after the next
     * neighbourhood (which includes the pixel) has been read, so the walk does
     * not wait on its own stores. Marks never turn white into black, so the
     * stale value reads the same. */
    pend = p0;
    pendv = *p0;
    for (;;) {
        int sweep0 = (dp + 1) & 7;
        if (r > 0 && r < rlast && c > 0 && c < clast)
            m = mask_fast(p, st);
        else
            m = mask_checked(s, r, c);
        *pend = pendv;
        /* Step 3.3: counterclockwise from just after the previous pixel to the
         * first white neighbour (the previous pixel is white, so k < 8). */
        k = k_ctz8[((m >> sweep0) | (m << (8 - sweep0))) & 0xffu];
        d = (sweep0 + k) & 7;
        /* Step 3.4: EAST if the sweep passed over a black east neighbour, else
         * TRACED unless already EAST. The states are ordered WHITE < TRACED <
         * EAST, so this is a max() and needs no branch. */
        {
            /* (8 - sweep0) & 7 is where east comes in the sweep. */
            unsigned v = *p, t = PX_TRACED + (unsigned)(((8 - sweep0) & 7) < k);
            pend = p;
            pendv = (uint8_t)(v > t ? v : t);
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
        if (p == p1 && r == r0 && c == c0)
            break;
        p += off[d];
        dp = (d + 4) & 7;
    }
    *pend = pendv;
    if (info) {
        info->npoints = n;
        info->min_x = minx;
        info->max_x = maxx;
        info->min_y = r0; /* the start is the blob's first pixel in raster order */
        info->max_y = maxy;
        info->area = (float)(twice_area < 0 ? -twice_area : twice_area) * 0.5f;
    }
}

int actag_contour_scanner_init(actag_contour_scanner *s, uint8_t *binary, int rows, int cols,
                               int stride)
{
    int r, c;
    if (!s || !binary)
        return ACTAG_ERR_NULL;
    if (rows < 1 || cols < 1 || rows > ACTAG_MAX_DIM || cols > ACTAG_MAX_DIM || stride < cols)
        return ACTAG_ERR_SIZE;
    /* Any nonzero input value could collide with the marks, so normalise,
     * 8 bytes at a time (the per-byte formula does not care about byte order). */
    for (r = 0; r < rows; r++) {
        uint8_t *row = binary + (ptrdiff_t)r * stride;
        for (c = 0; c + 8 <= cols; c += 8) {
            uint64_t x;
            memcpy(&x, row + c, 8);
            x = ((((x & 0x7f7f7f7f7f7f7f7fu) + 0x7f7f7f7f7f7f7f7fu) | x) & 0x8080808080808080u) >> 7;
            memcpy(row + c, &x, 8);
        }
        for (; c < cols; c++)
            row[c] = (uint8_t)(row[c] != 0);
    }
    s->img = binary;
    s->rows = rows;
    s->cols = cols;
    s->stride = stride;
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

    if (!s || !info || (cap > 0 && !pts))
        return ACTAG_ERR_NULL;
    if (cap < 0 || s->magic != SCANNER_MAGIC || !s->img)
        return ACTAG_ERR_PARAM;

    for (r = s->r, c = s->c; r < rows; r++, c = 0) {
        const uint8_t *row = s->img + (ptrdiff_t)r * s->stride;
        const int inner = r > 0 && r < rows - 1; /* rows above and below exist */
        const uint8_t *up = r > 0 ? row - s->stride : row;
        const uint8_t *down = r < rows - 1 ? row + s->stride : row;
        int base;
        /* 32 pixels at a time: only run starts (white, left black) can begin an
         * outer border and only run ends (white, right black) a hole border.
         * Tracing changes white values but never which pixels are white, so
         * the run masks stay valid while the row is processed. */
        for (base = c & ~31; base < cols; base += 32) {
            int n = cols - base < 32 ? cols - base : 32, i;
            uint32_t w = 0u, starts, ends, ev;
            if (n == 32) {
                for (i = 0; i < 32; i += 4)
                    w |= white4(row + base + i) << i;
            } else {
                for (i = 0; i < n; i++)
                    w |= (uint32_t)(row[base + i] != 0) << i;
            }
            starts = w & ~((w << 1) | (uint32_t)(base > 0 && row[base - 1] != 0));
            ends = w & ~((w >> 1) | (uint32_t)(n == 32 && base + 32 < cols && row[base + 32] != 0)
                                         << 31);
            ev = starts | ends;
            if (c > base)
                ev &= ~0u << (c - base); /* resuming after an outer border */
            while (ev) {
                int cc;
                unsigned v;
                i = ctz32(ev);
                ev &= ev - 1u;
                cc = base + i;
                v = row[cc];
                /* A black pixel whose four neighbours are white is a one-pixel
                 * hole (speckle makes many). Its border needs no walk: only
                 * the pixels left and right of it would consult its marks.
                 * The one right of it can then be unmarked, but its up-left
                 * neighbour (above the hole) is white, so it is not the first
                 * pixel of its blob; a white up-left neighbour always says so. */
                if ((starts >> i & 1u) && v == PX_WHITE && !(r > 0 && cc > 0 && up[cc - 1])) {
                    /* First pixel of a new blob: its outer border. */
                    trace(s, r, cc, 4, pts, cap, info);
                    info->stored = info->npoints < cap ? info->npoints : cap;
                    info->overflow = info->npoints > cap;
                    s->r = r;
                    s->c = cc + 1;
                    return 1;
                }
                if ((ends >> i & 1u) && v != PX_EAST &&
                    !(inner && cc + 2 < cols && row[cc + 2] && up[cc + 1] && down[cc + 1])) {
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
