/*
 * actag/render.h -- the AcTag layout as cells and as an 8-bit image.
 *
 * MANUAL
 *   A tag of a family with 4k data bits is a square grid of (k+1) x (k+1)
 *   cells (SPEC sections 1-2). Grid cell (x, y) has 0 <= x, y <= k, x to the
 *   right and y down, as printed (front view):
 *     - the outer ring holds the 4k data bits of the tag's code. Bit i of
 *       the sequence (i = 0 is the code's most significant bit) sits at
 *         top row       (i, 0)          for i = 0 .. k-1
 *         right column  (k, i-k)        for i = k .. 2k-1
 *         bottom row    (3k-i, k)       for i = 2k .. 3k-1
 *         left column   (0, 4k-i)       for i = 3k .. 4k-1
 *       i.e. clockwise from the top-left corner;
 *     - the ring at distance 1 from the edge is black (0);
 *     - everything inside it is white (1): a (k-3) x (k-3) square whose
 *       side is the tag_size used by the detectors.
 *   Layout colours: white (1) is foam, which scatters sound and looks
 *   bright in a sonar image; black (0) is the aluminium face plate, dark in
 *   a sonar image. A camera sees the opposite (aluminium is lighter), so
 *   camera renders are inverted.
 *
 *     actag_family f;
 *     static uint8_t img[ACTAG_RENDER_IMAGE_SIZE(24, 10, 10)];  (90 x 90)
 *     actag_family_get("AcTag24h10", &f);
 *     int side = actag_render_side(f.bits, 10, 10);             (90)
 *     actag_render_tag(&f, 0, 10, 10, 0, 0, img, side, sizeof img);
 *
 *   Rendered pixels: cell (x, y) covers rows margin_px + y*cell_px ..
 *   margin_px + (y+1)*cell_px - 1 and the same columns for x. Layout value
 *   1 is written as 255 and 0 as 0; the margin (margin_px pixels on every
 *   side) is written as margin_value. With camera != 0 every pixel p
 *   (margin included) is written as 255 - p.
 *
 *   actag_layout_corner_tabs() tells which corners of the face plate need a
 *   small metal tab: when a corner data bit is black and both of its ring
 *   neighbours are white, that corner cell touches the rest of the metal
 *   only at one point (diagonally, at the corner of the black ring), so a
 *   cut plate needs a little extra metal there (paper, section IV).
 *
 * MEMORY
 *   Nothing is allocated; the image buffer belongs to the caller and must
 *   hold at least (side - 1) * out_stride + side bytes. Bytes between side
 *   and the stride are never written. No static or global state.
 *
 * ERRORS
 *   ACTAG_ERR_NULL       family or out is NULL
 *   ACTAG_ERR_FAMILY     invalid family (see actag_family_validate; a NULL
 *                        code table is invalid) or id outside 0 .. ncodes-1
 *   ACTAG_ERR_PARAM      bits not a multiple of 4 in 16..32, cell_px < 1,
 *                        margin_px < 0, margin_value outside 0..255, or a
 *                        cell coordinate outside 0..k
 *   ACTAG_ERR_SIZE       the side would exceed ACTAG_MAX_DIM, or out_stride < side
 *   ACTAG_ERR_WORKSPACE  out_size < (side - 1) * out_stride + side
 *   On error nothing is written.
 */
#ifndef ACTAG_RENDER_H
#define ACTAG_RENDER_H

#include "actag/common.h"
#include "actag/family.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Side in pixels of a rendered tag (compile-time form, no checks). */
#define ACTAG_RENDER_SIDE(bits, cell_px, margin_px) \
    (((bits) / 4 + 1) * (cell_px) + 2 * (margin_px))

/* Bytes needed for a rendered tag with a row stride equal to its side. */
#define ACTAG_RENDER_IMAGE_SIZE(bits, cell_px, margin_px)   \
    ((size_t)ACTAG_RENDER_SIDE(bits, cell_px, margin_px) * \
     (size_t)ACTAG_RENDER_SIDE(bits, cell_px, margin_px))

/* Corner bits of actag_layout_corner_tabs(). */
#define ACTAG_CORNER_TOP_LEFT 1     /* cell (0, 0) */
#define ACTAG_CORNER_TOP_RIGHT 2    /* cell (k, 0) */
#define ACTAG_CORNER_BOTTOM_RIGHT 4 /* cell (k, k) */
#define ACTAG_CORNER_BOTTOM_LEFT 8  /* cell (0, k) */

/* Side in pixels of a rendered tag: (k+1)*cell_px + 2*margin_px, k = bits/4.
 * Returns the side (> 0) or ACTAG_ERR_PARAM (bad bits, cell_px < 1,
 * margin_px < 0) or ACTAG_ERR_SIZE (side > ACTAG_MAX_DIM). */
int actag_render_side(int bits, int cell_px, int margin_px);

/* Layout value (1 white / foam, 0 black / aluminium) of grid cell (x, y),
 * 0 <= x, y <= k, of tag `id`. Returns 0 or 1, or a negative error. */
int actag_layout_cell(const actag_family *family, int id, int x, int y);

/* Render tag `id` into out (side x side pixels, row stride out_stride bytes),
 * side = actag_render_side(family->bits, cell_px, margin_px). Layout white
 * -> 255, black -> 0, margin -> margin_value; camera != 0 inverts every
 * pixel. Returns ACTAG_OK or a negative error (nothing written). */
int actag_render_tag(const actag_family *family, int id, int cell_px, int margin_px,
                     int margin_value, int camera, uint8_t *out, int out_stride,
                     size_t out_size);

/* Which corners of tag `id`'s face plate need a tab: an OR of
 * ACTAG_CORNER_* bits (0 when none), or a negative error. */
int actag_layout_corner_tabs(const actag_family *family, int id);

#ifdef __cplusplus
}
#endif
#endif /* ACTAG_RENDER_H */
