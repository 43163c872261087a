/*
 * actag/tag_grid.h -- the tag's cell grid: layout, bit cells, grid -> image maps.
 *
 * MANUAL
 *   Geometry that the decoders (decode.h) and the renderer (render.h) share.
 *
 *   Tag grid coordinates (u, v): a family of 4k bits uses (k+1) x (k+1) cells;
 *   u runs to the right, v down, as printed, both in cells, 0 .. k+1 on the
 *   grid lines, so cell (cx, cy) has its centre at (cx + 0.5, cy + 0.5). The
 *   outer ring holds the data bits, the next ring is black, the rest white:
 *   the white square spans [2, k-1] x [2, k-1]. Data bit i (i = 0 is the
 *   code's MSB) lies in cell
 *       i = 0   .. k-1 : (i, 0)              top row, left to right
 *       i = k   .. 2k-1: (k, i-k)            right column, downwards
 *       i = 2k  .. 3k-1: (3k-i, k)           bottom row, right to left
 *       i = 3k  .. 4k-1: (0, 4k-i)           left column, upwards
 *   (SPEC section 2; for 24 bits these are the AprilTag 3 bit_x/bit_y.)
 *   Corner n of the white square: 0 = top-left (2,2), 1 = top-right (k-1,2),
 *   2 = bottom-right (k-1,k-1), 3 = bottom-left (2,k-1), as printed.
 *
 *   actag_tag_bit_cell(bits, i, &cx, &cy)
 *       The cell of data bit i (the table above).
 *   actag_tag_cell_value(code, bits, cx, cy)
 *       The layout value of a cell: the code's bit on the data ring, 0
 *       (black) on the ring inside it, 1 (white) in the interior.
 *
 *   Grid -> image maps. Each takes quad[0..3] as white-square corners 0..3
 *   in the order given (no reordering) and fills a 3x3 matrix H (row-major):
 *   x = (H0 u + H1 v + H2) / w, y = (H3 u + H4 v + H5) / w, w = H6 u + H7 v + H8.
 *   actag_tag_affine(quad, bits, H)       ACTAG_DECODE_AFFINE (the default)
 *       The least-squares affine map of the 4 corners (H6 = H7 = 0, H8 = 1):
 *       exact for a parallelogram, otherwise the corners' mean fit.
 *   actag_tag_homography(quad, bits, H)   ACTAG_DECODE_PROJECTIVE
 *       The exact 4-point homography (quad[n] lands on corner n).
 *   actag_tag_map(quad, bits, model, H)
 *       The one of the two that model names.
 *   Why affine by default: a sonar image has no perspective (range and
 *   azimuth are not a central projection), so the projective part of a
 *   4-point fit is corner noise, and the data ring lies outside the white
 *   square, where that noise is extrapolated. On the 58 pool frames plus the
 *   example frame (our pipeline's quads, inlier ratio 0.75) the affine map
 *   read tag 0 in 23 quads with 4 corrections (1 wrong ID) against 10
 *   (4 wrong IDs) for the homography; at 2 corrections 6 against 2. The
 *   reference decoder also fits an affine map (a pseudo-inverse). Use
 *   ACTAG_DECODE_PROJECTIVE for camera-like images with real perspective.
 *   actag_homography_apply(H, u, v, &p)
 *       Applies H. No checks; w > 0 everywhere on the tag grid for any H
 *       produced by the functions above.
 *   actag_decode_bit_positions(quad, bits, out)
 *       Image positions of the 4k data-cell centres, in bit order, through
 *       the default map (pass a tag-order corner list, e.g. a result's
 *       corners[], to get the tag's own bit order).
 *
 *   Corner order. actag_tag_quad_clockwise(quad, q) copies a quad clockwise
 *   on screen (x right, y down), quad[0] staying first; the decoders read
 *   from that order, so "mirrored" means mirrored on screen.
 *   actag_tag_corners(q, rotation, mirrored, corners) puts the white
 *   square's corners in the tag's own order (TL, TR, BR, BL as printed) from
 *   a clockwise-on-screen quad q whose q[0] is printed corner `rotation`:
 *       unmirrored: corners[n] = q[(n - rotation) mod 4]
 *       mirrored:   corners[n] = q[(rotation - n) mod 4]
 *   (decode.h explains rotation and mirrored.)
 *
 * ERRORS
 *   ACTAG_ERR_NULL   a pointer argument is NULL
 *   ACTAG_ERR_PARAM  bits not one of 16, 20, 24, 28, 32; unknown model;
 *                    degenerate quad: non-finite, not strictly convex (each
 *                    corner's turn must have |sin| > 1e-3, all the same way,
 *                    judged in float: a quad so small that the products of
 *                    its sides underflow, sides under about 1e-11 pixels, is
 *                    degenerate), or (homography only) the map sends part of
 *                    the (k+1)^2 tag grid through infinity (extreme
 *                    perspective)
 *   actag_homography_apply, actag_tag_bit_cell, actag_tag_cell_value and
 *   actag_tag_corners check nothing and have no error codes.
 */
#ifndef ACTAG_TAG_GRID_H
#define ACTAG_TAG_GRID_H

#include "actag/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Grid -> image map models. */
#define ACTAG_DECODE_AFFINE 0     /* least-squares affine fit of the 4 corners */
#define ACTAG_DECODE_PROJECTIVE 1 /* exact 4-point homography */
#define ACTAG_DECODE_DEFAULT_MODEL ACTAG_DECODE_AFFINE

/* Cell (cx, cy) of data bit i (0 = the code's MSB) of a 4k-bit tag. */
void actag_tag_bit_cell(int bits, int i, int *cx, int *cy);

/* Layout value of cell (cx, cy), 0 <= cx, cy <= k: 1 white, 0 black. */
int actag_tag_cell_value(uint32_t code, int bits, int cx, int cy);

/* Homography from tag grid (u,v) to image (x,y), quad[n] at white-square corner n. */
int actag_tag_homography(const actag_point quad[4], int bits, float H[9]);

/* Least-squares affine map from tag grid (u,v) to image (x,y) (H6 = H7 = 0, H8 = 1). */
int actag_tag_affine(const actag_point quad[4], int bits, float H[9]);

/* actag_tag_affine (ACTAG_DECODE_AFFINE) or actag_tag_homography
 * (ACTAG_DECODE_PROJECTIVE); ACTAG_ERR_PARAM for any other model. */
int actag_tag_map(const actag_point quad[4], int bits, int model, float H[9]);

/* out = H applied to (u, v). No checks, no error codes. */
void actag_homography_apply(const float H[9], float u, float v, actag_point *out);

/* Image positions of the `bits` data-cell centres in bit order (out has `bits`
 * entries), through the default map. */
int actag_decode_bit_positions(const actag_point quad[4], int bits, actag_point *out);

/* q = quad clockwise on screen, quad[0] first. ACTAG_ERR_PARAM when the
 * quad is degenerate (see ERRORS), ACTAG_ERR_NULL. */
int actag_tag_quad_clockwise(const actag_point quad[4], actag_point q[4]);

/* The white square's corners in tag order (TL, TR, BR, BL) from a
 * clockwise-on-screen quad q with printed corner `rotation` at q[0]. */
void actag_tag_corners(const actag_point q[4], int rotation, int mirrored,
                       actag_point corners[4]);

#ifdef __cplusplus
}
#endif
#endif /* ACTAG_TAG_GRID_H */
