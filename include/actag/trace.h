/*
 * actag/trace.h -- watch the detection pipeline's candidates (debugging,
 * overlays), without changing what it detects.
 *
 * MANUAL
 *   actag_detect_traced() is actag_detect() with a callback that sees every
 *   candidate the pipeline examines, in the order it examines them (search
 *   positions read tentatively: at the end, see below):
 *
 *     ACTAG_TRACE_SEARCH   a structure-search position (search.h): its
 *                          axis-aligned white-square quad and what the fit
 *                          decoder made of it. A position is first read
 *                          without the template check: a refusal is traced
 *                          at once; a tentative reading after the contours,
 *                          as ACTAG_TRACE_ACCEPTED with that reading when a
 *                          quad's reading superseded it, as
 *                          ACTAG_TRACE_RIVAL when it refused a quad's or
 *                          guess's reading of its place (contested: not
 *                          reported either) or when a quad's or guess's
 *                          hypothesis there, refused as too close to call,
 *                          explains the cells at least as well, or when a
 *                          reading of its box turned +30, -30 or +45
 *                          degrees does (another tag, handedness or corner
 *                          order there), else with the outcome of its
 *                          reading with the check.
 *     ACTAG_TRACE_CONTOUR  an outer border of the binary frame (contours.h):
 *                          its points, bounding box and whether it passed the
 *                          physical size filter.
 *     ACTAG_TRACE_QUAD     a RANSAC quadrilateral fitted to a size-plausible
 *                          contour (quad.h) and what became of it.
 *     ACTAG_TRACE_GUESS    when no quad of a contour reads: the grid guess from
 *                          the contour's extreme points and what the fit
 *                          decoder's wide search made of it (judged like a
 *                          search position, its turned boxes included,
 *                          and its extreme points with one corner
 *                          completed to a parallelogram);
 *                          also, right after a contour
 *                          refused by size (ACTAG_TRACE_SIZE) as too large
 *                          where cells are under 10 beams, the white
 *                          square's box at its centre (a white square
 *                          merged with its data cells, actag.h).
 *
 *   Each event carries an outcome: ACTAG_TRACE_ACCEPTED (the candidate went
 *   on: a contour to RANSAC, a quad or search position to the detections,
 *   where duplicate suppression may still drop it) or the reason it was
 *   rejected. Detections themselves are the function's output, as with
 *   actag_detect().
 *
 *   The callback gets pointers into the workspace and the stack that are
 *   valid only during the call; it must not call back into the library with
 *   the same workspace. It cannot influence the pipeline: with any callback
 *   (or none) the detections, their order and the stats are exactly those of
 *   actag_detect() on the same input. The library keeps no state: `user` is
 *   passed through untouched, so the call stays re-entrant.
 *
 *   Cost: one pointer test per candidate when trace is NULL (actag_detect()
 *   is actag_detect_traced(..., NULL, NULL)).
 *
 * ERRORS
 *   Those of actag_detect() (actag.h).
 */
#ifndef ACTAG_TRACE_H
#define ACTAG_TRACE_H

#include "actag/common.h"
#include "actag/contours.h"
#include "actag/decode.h"

#ifdef __cplusplus
extern "C" {
#endif

/* actag_trace_event.kind */
#define ACTAG_TRACE_SEARCH 1
#define ACTAG_TRACE_CONTOUR 2
#define ACTAG_TRACE_QUAD 3
#define ACTAG_TRACE_GUESS 4

/* actag_trace_event.outcome */
#define ACTAG_TRACE_ACCEPTED 0    /* went on to the next stage / the detections */
#define ACTAG_TRACE_OVERFLOW 1    /* contour longer than the point buffer */
#define ACTAG_TRACE_SIZE 2        /* contour outside the physical size filter */
#define ACTAG_TRACE_SIDES 3       /* quad or fitted grid: a side outside
                                     [min, max]_side_fraction * tag_size */
#define ACTAG_TRACE_NO_MATCH 4    /* the decoder found no code (or failed) */
#define ACTAG_TRACE_STRUCTURE 5   /* decoded, but black ring / white interior
                                     failed the structure budget */
#define ACTAG_TRACE_MARGIN 6      /* decoded, but decision margin too small (a
                                     merged blob's guess: also more than 2
                                     corrected bits) */
#define ACTAG_TRACE_RIVAL 7       /* a quad's or guess's reading where a search
                                     position (or, for a guess, one of the
                                     contour's quads refused as too close to
                                     call) read another tag, handedness or
                                     corner order whose template explains the
                                     cells at least as well (both polished over
                                     the full range at both places): no reading;
                                     for a search position, its reading did
                                     that to another reading of its place
                                     (contested), or a quad's or guess's
                                     hypothesis refused there as too close
                                     to call did it to the search reading:
                                     it is not reported either; and a search
                                     position's or guess's reading that a
                                     reading of its box turned +30, -30 or +45
                                     degrees, or (a guess's) of its extreme
                                     points with one corner completed to the
                                     parallelogram through the other three,
                                     contests in the same way (another tag,
                                     handedness or corner order there whose
                                     template explains the cells at least as
                                     well: docs/decoder.md, "Blind readings
                                     and turned starts") */
#define ACTAG_TRACE_BORDER 8      /* a guess with a corner on the frame's
                                     border: not read (its tag's data cells
                                     would leave the frame) */
#define ACTAG_TRACE_TEXTURE 9     /* decoded, but its white-minus-ring
                                     contrast does not stand out from the
                                     texture around the tag by
                                     tuning.min_texture_contrast (a blob of
                                     the texture; actag.h, src/texture.h) */

typedef struct actag_trace_event {
    int kind;                           /* ACTAG_TRACE_SEARCH / _CONTOUR / _QUAD / _GUESS */
    int outcome;                        /* ACTAG_TRACE_ACCEPTED or a reason above */
    /* _CONTOUR: the traced border (points valid during the call only; NULL
     * and 0 on overflow) and its description */
    const actag_ipoint *points;
    int npoints;
    const actag_contour_info *contour;
    /* _SEARCH, _QUAD, _GUESS: the candidate's white-square corners as
     * examined (image pixels, x = column, y = row; clockwise on screen for
     * the search, the RANSAC order for quads, the extreme points for
     * guesses); inlier_ratio: the quad's RANSAC support (0 otherwise) */
    actag_point quad[4];
    float inlier_ratio;
    /* _SEARCH, _QUAD, _GUESS: the decoder's result when it decoded
     * (outcomes _ACCEPTED, _STRUCTURE, _MARGIN, and _SIDES for search and
     * guess readings whose fitted grid failed the side check), else NULL.
     * Accepted quads report decoded->corners, search and guess readings
     * decoded->fit_corners. Its corners and
     * mirrored flag are in image terms, before the geometry's orientation
     * flags are applied. */
    const actag_decode_result *decoded;
} actag_trace_event;

typedef void (*actag_trace_fn)(void *user, const actag_trace_event *event);

#ifdef __cplusplus
}
#endif
#endif /* ACTAG_TRACE_H */
