/*
 * actag/refine.h -- sub-pixel corners of a decoded tag: the whole known
 *                   template fitted to the grey image.
 *
 * MANUAL
 *   The last stage of the sonar detector. The quad stage's corners come from
 *   a RANSAC fit to the binary contour of the white blob, the fit decoder's
 *   from a cell grid judged by 9 samples per cell: both are off by a pixel
 *   or two (simulated at the paper's settings: sd 0.9 cm in range and 0.004
 *   rad in azimuth per corner, nearly independent between corners), which
 *   is 7 % of the inner square of a 13 cm tag and sets the pose's
 *   orientation error (docs/pose.md). Once a tag is decoded its whole
 *   appearance is known: the data ring (the code), the black ring, the white
 *   interior. This stage fits that template to every pixel of the tag at
 *   once, so each corner rests on all the tag's edges instead of the few
 *   contour points near it.
 *
 *     actag_refine_params rp;
 *     actag_point fine[4];
 *     actag_refine_params_default(&rp);
 *     if (actag_refine_corners(grey, rows, cols, cols, &geo, tag_size, &fam, det.id,
 *                              det.corners, &rp, fine, NULL) == ACTAG_OK)
 *         ... fine[0..3] replace det.corners ...
 *   (geo: the frame's sonar geometry, or NULL to fit in pixels without the
 *   range curvature and the side rule below; tag_size: the white square's
 *   side in metres, used only with a geometry.)
 *
 *   Model. The tag's cell grid (u, v in cells, 0 .. k+1 on the grid lines,
 *   u to the right and v down as printed, decode.h) maps into the image by
 *   an affine map x = m + a (u - g) + b (v - g), g = (k+1)/2: a sonar image
 *   has no perspective, and over one tag the map from the tag's plane to
 *   (range, azimuth) is affine to well under a pixel. The template P(u, v)
 *   is the tag's layout (1 white, 0 black; outside the tag 0), each cell's
 *   indicator smoothed across its edges by a cubic step `blur` pixels wide
 *   on either side (the beam's point spread). The grey level is modelled as
 *       I = c0 + c1 P + c2 P u' + c3 P v' + c4 u' + c5 v',
 *   (u', v') the pixel's (u - g, v - g)/(k+1) under the START grid (affine,
 *   fixed during the fit): two levels whose contrast and offset may vary
 *   linearly across the tag (the elevation beam pattern brightens one
 *   side). Two passes: the first with the template's edges 0.4 cell wide
 *   (a wide basin for corners a cell off), the second with `blur`. Each
 *   pass fits the six levels c by linear least squares to its start grid
 *   (on a lattice of at least 300 pixels) and holds them; the grid's six
 *   numbers are then fitted by Gauss-Newton (Levenberg-Marquardt damping,
 *   one pass over the pixels per step) with analytic derivatives of the
 *   template and of the curvature term (no image gradients, which speckle
 *   makes noisy); pixels inside a cell, away from its edges, add to the
 *   residual only. Steps along one line shrinking by a ratio rho are
 *   extrapolated by 1/(1 - rho) (the residuals are not small: convergence
 *   is linear). Converged when no corner moves by more than 0.03 cell
 *   (pass 1) or 0.003 cell (pass 2).
 *
 *   Pixels: every pixel (centres on integer coordinates) whose grid
 *   position under the START map lies within [margin, k+1-margin] in u and
 *   v (the outer edge of the data ring borders an unknown background),
 *   subsampled on a regular lattice to at most max_samples pixels (pass 1:
 *   every 2nd to 4th lattice row and column, at least 250 pixels); the set
 *   is fixed during the fit (each lattice row's members from the first to
 *   the last). Pixels outside the image are not used.
 *
 *   Safety. The refined corners are returned only when the fit converged
 *   to a proper grid (finite, the same handedness as the start, side
 *   lengths within 25 % of the start's; with a geometry, a side may also
 *   grow by up to 50 % when it stays within 10 % of the tag's own cell
 *   size, since the sonar's projection only shortens sides and a RANSAC
 *   start can be short) and no corner moved more than
 *   max_shift cells from its start; otherwise the start corners are copied
 *   to out and ACTAG_ERR_NO_MATCH returned. The ID, handedness and corner
 *   order are never changed: this stage moves corners only.
 *
 *   Deterministic: + - * / and sqrtf only, float. About 3.5 KB of stack
 *   (Cortex-M7 -O2, GCC 12 -fstack-usage: 2,384 bytes in the main frame,
 *   most of it a bearing cache and the cell layout; 440 + 456 + 68 in the
 *   pass, the sweep and the sweep's batched sums below it; on x86-64 the
 *   SSE2 sweeps add a 16 KiB buffer of eight rows' grid offsets, about 17
 *   KB in all); no workspace.
 *   Cost: about 5 passes over the pixel set in all (pass 2: 1 + 2..4
 *   steps; pass 1 on a sparser lattice); a pool frame's tag (2,000-3,100
 *   pixels at lattice step 2) takes about 5 M instructions on x86
 *   (callgrind; 7 M before the sweep's rework of 2026-12-06) and 2.5-7.9 M,
 *   4.8 M on average, on a Cortex-M7 at -O2 (tools/budget; 3.8-11.8 M and
 *   7.4 M before).
 *
 *   actag_refine_params_default(&rp)
 *       blur 2 px, margin 0.3 cell, max_iterations 8 per pass, max_shift
 *       1 cell, max_samples 6000. NULL: no-op.
 *   actag_refine_corners(img, rows, cols, stride, geometry, tag_size, family, id,
 *                        corners, rp, out, info)
 *       img: 8-bit grey image (the detector passes the caller's frame as
 *       it came from the sonar, not its median-filtered copy: the 9 x 9
 *       median rounds the white square's corners and thins cells of 3-4
 *       pixels, which biased the fitted shape; least squares on the raw
 *       speckle does not. Simulated at the paper's settings the median
 *       pose orientation error fell from 3.48 to 2.62 degrees, seed 1, and
 *       3.46 to 2.50, seed 2, docs/pose.md); corners: the white square's corners in tag order (TL, TR,
 *       BR, BL as printed, as actag_detection.corners); id: the decoded
 *       code. info (may be NULL) receives the fit's figures.
 *
 *   actag_refine_corners_depth(img, depth, rows, cols, stride, geometry, tag_size,
 *                              family, id, corners, rp, out, info)
 *       The same on an 8- or 16-bit image (depth 8 or 16; stride in
 *       pixels; 16-bit pixels in host byte order at any address). A 16-bit
 *       image is read scaled by 255 / its maximum, as actag_detect scales
 *       16-bit frames (one pass over the image to find the maximum).
 *       actag_refine_corners(img, ...) is actag_refine_corners_depth(img, 8, ...).
 *
 * ERRORS
 *   ACTAG_ERR_NULL    img, family, corners, rp or out is NULL
 *   ACTAG_ERR_SIZE    rows or cols < 1 or > ACTAG_MAX_DIM, stride < cols
 *   ACTAG_ERR_PARAM   depth not 8 or 16, id outside the family, bits not 16..32 (multiple of 4),
 *                     the family's codes NULL,
 *                     a non-finite or degenerate corner quad, rp out of range
 *                     (blur in [0.25, 20], margin in [0, 1], max_iterations
 *                     1..50, max_shift in (0, 2], max_samples 64..100000),
 *                     with a geometry: tag_size not in
 *                     (0, ACTAG_MAX_TAG_SIZE = 1000) metres
 *   ACTAG_ERR_GEOMETRY the geometry (when not NULL) fails
 *                     actag_geometry_validate() for rows x cols
 *   ACTAG_ERR_NO_MATCH the fit did not give acceptable corners (out = corners)
 *   On ACTAG_ERR_PARAM for a degenerate quad (one the tag's grid cannot be
 *   laid on: found after the checks above) out = corners too; on every other
 *   error out is untouched.
 */
#ifndef ACTAG_REFINE_H
#define ACTAG_REFINE_H

#include "actag/common.h"
#include "actag/family.h"
#include "actag/geometry.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct actag_refine_params {
    float blur;         /* template edge half-width, pixels (2) */
    float margin;       /* cells left out inside the tag's outline (0.3) */
    int max_iterations; /* Gauss-Newton steps per pass (8) */
    float max_shift;    /* largest corner move accepted, cells (1) */
    int max_samples;    /* most pixels used (6000) */
} actag_refine_params;

typedef struct actag_refine_info {
    int samples;      /* pixels used */
    int iterations;   /* steps taken, both passes */
    float rms;        /* residual rms, grey levels */
    float contrast;   /* fitted white minus black at the tag centre, grey levels */
    float shift;      /* largest corner move, cells of the start grid (max_shift's unit) */
} actag_refine_info;

void actag_refine_params_default(actag_refine_params *rp);

int actag_refine_corners(const uint8_t *img, int rows, int cols, int stride,
                         const actag_sonar_geometry *geometry, float tag_size,
                         const actag_family *family, int id, const actag_point corners[4],
                         const actag_refine_params *rp, actag_point out[4],
                         actag_refine_info *info);
int actag_refine_corners_depth(const void *img, int depth, int rows, int cols, int stride,
                               const actag_sonar_geometry *geometry, float tag_size,
                               const actag_family *family, int id, const actag_point corners[4],
                               const actag_refine_params *rp, actag_point out[4],
                               actag_refine_info *info);

#ifdef __cplusplus
}
#endif
#endif /* ACTAG_REFINE_H */
