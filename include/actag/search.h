/*
 * actag/search.h -- structure search: where a tag's white square may be,
 * without contours.
 *
 * MANUAL
 *   A tag's white square inside its black ring is a bright box in a dark
 *   frame, at a size known from the sonar geometry. When the white square
 *   merges with neighbouring data cells in the binary frame, no contour
 *   isolates it; this stage finds such places directly in the (median-
 *   filtered) grey frame, for the decoder's grid fit to examine.
 *
 *   actag_search_map() averages the frame over ACTAG_SEARCH_FACTOR^2 blocks
 *   (integral image in caller scratch) and scores every block position by
 *       8 * (mean of the inner box - mean of the ring between inner and outer box)
 *   in grey levels x 8, where at the block's range the inner box is the white
 *   square (k-3 cells, k = bits / 4: 1.5 cells either side of the centre for
 *   24 bits, 2 for 28) and the outer box one cell more either side (cell =
 *   tag_size / (k-3); along the range axis the cell is scaled by range_scale,
 *   because tilted tags look shorter in range; along azimuth the cell is
 *   measured with the azimuth step at the block's own column, which varies
 *   across a bearing table, as actag_search_next sizes its quad). Positions
 *   whose geometry gives no azimuth step, and positions whose outer box
 *   leaves the frame, score
 *   INT16_MIN. Scores are clamped to +-2040. Box half-sizes are computed in
 *   float and saturate at the map's size before they become ints, so any
 *   finite tag_size and geometry (even a range of almost 0) is defined
 *   behaviour: a box larger than the frame simply scores INT16_MIN. So do
 *   positions whose outer box holds more than ACTAG_SEARCH_MAX_BOX_BLOCKS
 *   blocks (1,052,688: a larger box of bright pixels could sum past the
 *   uint32 integral image); only frames of more than about 16.8 M pixels,
 *   with a tag almost as large as the frame, have such boxes.
 *
 *   actag_search_next() takes the best remaining position with a score >=
 *   min_score, blanks a 1.5-tag neighbourhood around it (the blocks within
 *   0.75 tag, in whole blocks, + 1 of it in each direction, clipped to the
 *   map), and returns the axis-aligned white-square quad it implies
 *   (full-resolution pixels, clockwise on screen from the top-left; tag
 *   sizes at its own position). Returns 1, or 0 when nothing is
 *   left, so `while (actag_search_next(...) == 1)` ends for any min_score: a
 *   min_score below INT16_MIN + 1 counts as INT16_MIN + 1 (unscored and
 *   blanked positions, INT16_MIN, are never taken). It has no error codes
 *   and checks nothing: z must come from a successful actag_search_map()
 *   with the same geometry, tag_size, range_scale, rows and cols.
 *
 *   Memory: ACTAG_SEARCH_MAP_SIZE bytes for the score map (int16_t: 2-byte
 *   aligned) and ACTAG_SEARCH_INTEGRAL_SIZE bytes of scratch (uint32_t:
 *   4-byte aligned), both caller-owned; the actag_search struct only points
 *   into them.
 *
 * ERRORS (actag_search_map)
 *   ACTAG_ERR_NULL       a pointer is NULL
 *   ACTAG_ERR_SIZE       rows or cols < 1 or > ACTAG_MAX_DIM (checked with the
 *                        geometry, first), stride < cols, or the frame is smaller
 *                        than 4 blocks in either direction (nothing to search)
 *   ACTAG_ERR_PARAM      scratch not 4-byte or map not 2-byte aligned (checked after
 *                        the pointers); tag_size or range_scale not positive and
 *                        finite, bits not a multiple of 4 in 16..32
 *   ACTAG_ERR_GEOMETRY   invalid geometry for this frame (geometry.h)
 *   ACTAG_ERR_WORKSPACE  map or scratch smaller than the sizes below
 */
#ifndef ACTAG_SEARCH_H
#define ACTAG_SEARCH_H

#include "actag/common.h"
#include "actag/geometry.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Resolution reduction of the search (F x F blocks averaged). */
#define ACTAG_SEARCH_FACTOR 4

/* Most blocks an outer box may hold to be scored: its sum of up to
 * F^2 x 255 per block stays below 2^32 (actag_search_map). */
#define ACTAG_SEARCH_MAX_BOX_BLOCKS                                                          \
    (UINT32_MAX / (255u * ACTAG_SEARCH_FACTOR * ACTAG_SEARCH_FACTOR))

/* Bytes of the int16 score map, and of the uint32 integral-image scratch. */
#define ACTAG_SEARCH_MAP_SIZE(rows, cols)                                                    \
    ((size_t)(rows) / ACTAG_SEARCH_FACTOR * ((size_t)(cols) / ACTAG_SEARCH_FACTOR) * 2u)
#define ACTAG_SEARCH_INTEGRAL_SIZE(rows, cols)                                               \
    (((size_t)(rows) / ACTAG_SEARCH_FACTOR + 1u) * ((size_t)(cols) / ACTAG_SEARCH_FACTOR + 1u) * 4u)

typedef struct actag_search {
    uint32_t *ii; /* (hr + 1) x (hc + 1) integral of the block-averaged frame */
    int16_t *map; /* hr x hc scores */
    int hr, hc;   /* block rows and columns */
} actag_search;

/* Scores every block position of the 8-bit frame img (rows x cols, stride
 * bytes) for a white square of tag_size metres (the family's bits give the
 * cells per side; range_scale shortens the cell along range:
 * tuning.search_range_scale, 0.75 by default, in actag_detect), into map
 * (map_size bytes), using scratch (scratch_size bytes) for the integral
 * image; fills *z. Returns ACTAG_OK or an error of ERRORS above. */
int actag_search_map(actag_search *z, const uint8_t *img, int rows, int cols, int stride,
                     const actag_sonar_geometry *g, float tag_size, int bits, float range_scale,
                     void *map, size_t map_size, void *scratch, size_t scratch_size);

/* The next best position scoring at least min_score (grey levels x 8, as
 * the map), as the white-square quad it implies in pixels (tag_size in
 * metres, the same geometry, tag_size, range_scale, rows and cols as the
 * map): returns 1 and fills quad, or 0 when none is left. No error codes
 * (see the manual). */
int actag_search_next(actag_search *z, int min_score, const actag_sonar_geometry *g,
                      float tag_size, float range_scale, int rows, int cols,
                      actag_point quad[4]);

#ifdef __cplusplus
}
#endif
#endif
