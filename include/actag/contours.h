/*
 * actag/contours.h -- outer borders of the white blobs of a binary image.
 *
 * MANUAL
 *   Input: a binary image of rows x cols pixels as a bitmap (one bit per
 *   pixel, the layout in common.h: ACTAG_BITMAP_SIZE(rows, cols) bytes,
 *   1 = white, padding 0), e.g. from actag_adaptive_threshold_bitmap()
 *   (threshold.h) or actag_bitmap_pack() below. Pixels outside the image
 *   count as black (the frame of Suzuki & Abe 1985). The scanner also needs
 *   a second bitmap-sized buffer, `marks`, for its pixel marks.
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
 *     static uint32_t bin[ACTAG_BITMAP_SIZE(530, 512) / 4];
 *     static uint32_t marks[ACTAG_BITMAP_SIZE(530, 512) / 4];
 *     int rc;
 *     actag_bitmap_pack(bytes, rows, cols, stride, bin);   (or the threshold)
 *     if (actag_contour_scanner_init(&s, bin, marks, rows, cols) != ACTAG_OK) ...
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
 *   Cost: O(rows * cols / 32 + total border length), no allocation, no limit
 *   on the number of contours (the scanner streams them): the raster scan
 *   reads 32 pixels per bitmap word to find run starts and ends, the walks
 *   read each border pixel's 3 x 3 neighbourhood as three 3-bit fields.
 *
 *   Hole borders are walked internally (one walk per enclosed black
 *   4-connected region of two or more pixels; one-pixel holes need none);
 *   scanner.holes counts the walks, for diagnostics and tests.
 *
 *   The bitmap is only read, never modified: later stages (the binary
 *   decoder, debug pictures) still see the threshold's output.
 *   actag_contour_scanner_init() zeroes `marks` (ACTAG_BITMAP_SIZE(rows, cols)
 *   bytes, 4-byte aligned like the bitmap) and the walks set its bits: a
 *   white pixel's bit once it is on a traced border, a black pixel's bit
 *   when the white pixel left of it is on a traced border whose black side
 *   it is (the padding column right of the image included). Do not modify
 *   either buffer between actag_contour_scanner_init() and the end of the
 *   scan. ACTAG_CONTOUR_WORKSPACE_BYTES(rows, cols) is the size of `marks`.
 *
 *   actag_bitmap_pack(img, rows, cols, stride, bitmap) sets the bitmap from
 *   an image of one byte per pixel (nonzero = white; padding bits 0);
 *   actag_bitmap_unpack(bitmap, rows, cols, dst, dst_stride, white) writes
 *   it back as bytes, 0 for black and `white` (e.g. 1 or 255) for white.
 *   Both return ACTAG_OK, ACTAG_ERR_NULL or ACTAG_ERR_SIZE (rows or cols < 1
 *   or > ACTAG_MAX_DIM, stride < cols); bytes between cols and the stride
 *   are never read or written.
 *
 * ERRORS
 *   ACTAG_ERR_NULL   a required pointer is NULL (pts may be NULL when cap == 0)
 *   ACTAG_ERR_SIZE   rows or cols < 1 or > ACTAG_MAX_DIM
 *   ACTAG_ERR_PARAM  white == marks (init), cap < 0, or the scanner was not
 *                    initialised
 */
#ifndef ACTAG_CONTOURS_H
#define ACTAG_CONTOURS_H

#include "actag/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Scratch bytes the contour stage needs for a rows x cols image: the marks
 * bitmap. */
#define ACTAG_CONTOUR_WORKSPACE_BYTES(rows, cols) ACTAG_BITMAP_SIZE(rows, cols)

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
    const uint32_t *white; /* the binary bitmap */
    uint32_t *marks;       /* the pixel marks, a bitmap of the same size */
    int rows;      /* image height, pixels */
    int cols;      /* image width, pixels */
    int r, c;      /* next pixel the raster scan examines */
    int holes;     /* statistics: hole borders walked so far (one per enclosed
                      black 4-connected region of 2+ pixels) */
    int magic;     /* set by init; guards against uninitialised use */
} actag_contour_scanner;

/* Prepares a scan of the bitmap `white` (rows x cols pixels): validates
 * the arguments and zeroes `marks` (ACTAG_BITMAP_SIZE(rows, cols) bytes).
 * Returns ACTAG_OK, ACTAG_ERR_NULL, ACTAG_ERR_SIZE or ACTAG_ERR_PARAM (white
 * == marks); on error nothing is written. */
int actag_contour_scanner_init(actag_contour_scanner *s, const uint32_t *white, uint32_t *marks,
                               int rows, int cols);

/* Bitmap from bytes (nonzero = white) and back (0 / white); see above. */
int actag_bitmap_pack(const uint8_t *img, int rows, int cols, int stride, uint32_t *bitmap);
int actag_bitmap_unpack(const uint32_t *bitmap, int rows, int cols, uint8_t *dst, int dst_stride,
                        uint8_t white);

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
