/*
 * actag/contours.h -- outer borders of the white blobs of a binary image.
 *
 * MANUAL
 *   Input: a binary image of rows x cols bytes, row r starting at
 *   binary + r * stride; 0 = black, any nonzero value = white. Pixels outside
 *   the image count as black (the frame of Suzuki & Abe 1985).
 *
 *   The scanner walks the image in raster order and yields, one call at a
 *   time, the OUTER border of every white 8-connected component (blob):
 *   exactly one contour per component, in raster order of the components'
 *   first pixels. Hole borders (black regions enclosed by white) are traced
 *   internally to mark pixels but are never returned. Blobs nested inside the
 *   holes of other blobs (a ring inside a ring) are returned like any other.
 *
 *     actag_contour_scanner s;
 *     actag_contour_info info;
 *     actag_ipoint pts[1024];
 *     int rc;
 *     if (actag_contour_scanner_init(&s, bin, rows, cols, stride) != ACTAG_OK) ...
 *     while ((rc = actag_contour_next(&s, pts, 1024, &info)) == 1) {
 *         if (info.overflow) continue;           (border longer than 1024)
 *         ...use pts[0 .. info.stored-1]...
 *     }
 *     if (rc < 0) ...error...
 *
 *   A contour is the closed walk of Suzuki-Abe outer border following with
 *   8-connectivity: it starts at the blob's first pixel in raster order,
 *   consecutive points are 8-neighbours (and the last point is an
 *   8-neighbour of the first), it runs counterclockwise as seen on screen
 *   (x right, y down: down the left side first). A pixel may appear more than
 *   once (a one-pixel-wide line is walked out and back). A single isolated
 *   pixel is a 1-point contour. The set of points is exactly the set of the
 *   blob's pixels that are 4-adjacent to the black region around the blob.
 *
 *   Cost: O(rows * cols + total border length), no allocation, no limit on
 *   the number of contours (the scanner streams them). A whole scan of a
 *   530 x 512 thresholded sonar frame (hundreds to thousands of blobs) takes
 *   0.3-0.7 ms on one x86-64 server core (-O3), about 1 ms for the noisiest
 *   binarisations.
 *
 *   Hole borders are walked internally (one walk per enclosed black
 *   4-connected region of two or more pixels; one-pixel holes need none);
 *   scanner.holes counts the walks, for diagnostics and tests.
 *
 *   The image is MODIFIED: actag_contour_scanner_init() sets every nonzero
 *   pixel to 1, and tracing then marks border pixels with 2 or 3. Black stays
 *   0 and white stays nonzero, so later stages may still read the image as
 *   0 = black / nonzero = white. Bytes between cols and stride (row padding)
 *   are never read or written. Do not modify the image between
 *   actag_contour_scanner_init() and the end of the scan.
 *
 *   No workspace is needed beyond the scanner struct (caller-owned, a few
 *   words); ACTAG_CONTOUR_WORKSPACE_BYTES is 0 and exists for uniformity.
 *
 * ERRORS
 *   ACTAG_ERR_NULL   a required pointer is NULL (pts may be NULL when cap == 0)
 *   ACTAG_ERR_SIZE   rows or cols < 1 or > ACTAG_MAX_DIM, or stride < cols
 *   ACTAG_ERR_PARAM  cap < 0, or the scanner was not initialised
 */
#ifndef ACTAG_CONTOURS_H
#define ACTAG_CONTOURS_H

#include "actag/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Scratch bytes the contour stage needs for a rows x cols image: none. */
#define ACTAG_CONTOUR_WORKSPACE_BYTES(rows, cols) ((size_t)0)

/* What actag_contour_next() reports about one contour. npoints, the bounding
 * box and the area always describe the WHOLE traced border, even when only
 * the first cap points were stored. */
typedef struct actag_contour_info {
    int npoints;  /* points traced (may exceed the stored count; saturates at INT_MAX) */
    int stored;   /* points written to the caller's buffer, min(npoints, cap) */
    int overflow; /* 1 when npoints > cap: the caller's buffer was too small */
    int min_x, max_x, min_y, max_y; /* bounding box of the border, pixels (inclusive) */
    float area;   /* |shoelace area| of the closed border polygon through the
                     pixel centres, pixels^2 (0 for 1- and 2-point contours) */
} actag_contour_info;

/* Scanner state; the caller owns it (e.g. on the stack). Fields are private
 * except holes, which may be read. */
typedef struct actag_contour_scanner {
    uint8_t *img;  /* image, row 0 */
    int rows;      /* image height, pixels */
    int cols;      /* image width, pixels */
    int stride;    /* bytes from one row to the next */
    int r, c;      /* next pixel the raster scan examines */
    int holes;     /* statistics: hole borders walked so far (one per enclosed
                      black 4-connected region of 2+ pixels) */
    int magic;     /* set by init; guards against uninitialised use */
} actag_contour_scanner;

/* Prepares a scan of the binary image: validates the arguments and sets
 * every nonzero pixel to 1 (O(rows * cols)). Returns ACTAG_OK,
 * ACTAG_ERR_NULL or ACTAG_ERR_SIZE; on error nothing is written. */
int actag_contour_scanner_init(actag_contour_scanner *s, uint8_t *binary, int rows, int cols,
                               int stride);

/* Finds the next outer border in raster order and traces it completely.
 * Writes its first min(npoints, cap) points to pts (x = column, y = row) and
 * fills *info. Returns 1 when a contour was found, 0 when the scan is
 * finished (and on every later call), or a negative ACTAG_ERR_* code.
 * cap == 0 counts only (pts may then be NULL). */
int actag_contour_next(actag_contour_scanner *s, actag_ipoint *pts, int cap,
                       actag_contour_info *info);

#ifdef __cplusplus
}
#endif
#endif /* ACTAG_CONTOURS_H */
