/* The texture test (internal): does a reading's white square and black
 * ring stand out from the texture around the tag, or are they that
 * texture? Used by the readings' judges (readings.c, detect.c); tested in
 * tests/test_texture.c against a brute-force reference of its own.
 *
 * Why. The decision margin (decode.h) is a log-likelihood ratio whose
 * noise is estimated from the reading's own ring and interior cells, and
 * those cells were picked because they look like a tag: a speckle blob
 * the threshold outlined as a white square has a dark surround by
 * selection, so its noise looks small and its margin large. Where the
 * beam's spread makes neighbouring cells alike (single-look speckle, a
 * wide beam, small far cells) such blobs were read as tags at margins up
 * to 13 (docs/evaluation.md, thirty-seventh session). The texture around
 * the tag is independent of that selection: its cell-to-cell variation,
 * measured on cells of the reading's own grid beyond the tag, says how
 * much two neighbouring patches of this frame differ by chance. A tag's
 * contrast is many times that; a blob of the texture's is about twice.
 *
 * The measure. On the reading's grid (fit corners = the white square's,
 * tag order; the affine map of tag_grid.h), cell means of B from 3 x 3
 * bilinear samples each:
 *   contrast = mean of the interior cells - mean of the black-ring cells
 *              (grid cells 2..k-2 square; the ring 1..k-1 around it),
 *   s^2      = median of (m_a - m_b)^2 over the pairs of side-by-side
 *              background cells (along either grid axis), divided by
 *              2 x 0.4549 (the chi-square median: for normal differences,
 *              the variance of one cell mean), background = cells -4..k+4
 *              on both axes outside the tag and its one-cell margin
 *              (-1..k+1 on both axes),
 * k = bits / 4. Cells with a sample outside the frame are left out. The
 * ratio contrast / s is the reading's texture contrast. Differences of
 * neighbouring cells, unlike the spread of all background cells, do not
 * count the frame's large-scale structure (a brightness gradient) as
 * texture, and their median ignores the few pairs across a sharp edge
 * (the dark band before the seabed, a wall): on the real pool frames the
 * mean of the squares put tags as low as 4.5, the median 11. */
#ifndef ACTAG_TEXTURE_H
#define ACTAG_TEXTURE_H

#include "actag/actag.h"

/* Least background pairs for a judgement: with fewer (a tag filling the
 * frame, or at its edge with little around it) the texture is not known
 * and the reading is not judged. */
#define ACTAG__TEXTURE_MIN_PAIRS 16

/* The texture contrast of a reading whose fitted white-square corners are
 * fit[0..3] (tag order) on the 8-bit frame grey (rows x cols, stride
 * cols) for a family of `bits` bits (16..32, a multiple of 4). Returns
 * contrast / s as above; ACTAG__TEXTURE_UNJUDGED when fewer than
 * ACTAG__TEXTURE_MIN_PAIRS pairs lie in the frame, s is 0 (a flat
 * background: a synthetic render; more than half the pairs alike), a ring or
 * interior cell leaves the frame, or the corners are not finite. Stack:
 * about 1.3 KB (the pairs' squared differences, at most 280). */
#define ACTAG__TEXTURE_UNJUDGED 3.0e38f
float actag__texture_contrast(const uint8_t *grey, int rows, int cols, const actag_point fit[4],
                              int bits);

#endif
