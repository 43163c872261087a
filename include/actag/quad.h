/*
 * actag/quad.h -- fit a parallelogram to one traced contour (RANSAC).
 *
 * MANUAL
 *   Stage 4 of the sonar detector (SPEC section 5, paper Algorithm 2): given
 *   the border of one white blob, find the quadrilateral whose four sides
 *   explain at least a given fraction of the border points, and accept it only
 *   if it is a parallelogram.
 *
 *     actag_quad_params qp;
 *     actag_rng rng;
 *     actag_quad q;
 *     static unsigned char scratch[ACTAG_QUAD_SCRATCH_SIZE(4096)];
 *     actag_quad_params_default(&qp);
 *     actag_rng_seed(&rng, 1);
 *     if (actag_quad_fit(pts, npts, &qp, &rng, scratch, sizeof scratch, &q) == ACTAG_OK)
 *         ... q.corners[0..3] ...
 *
 *   Input: the points of one closed contour in tracing order (consecutive
 *   points are neighbours; the last one neighbours the first), as produced by
 *   a border follower; duplicates are harmless. Coordinates are pixels
 *   (x = column, y = row).
 *
 *   Algorithm (bounded, deterministic). Each RANSAC iteration:
 *     1. For each of 4 lines: pick a random start index, take the next
 *        m = round(sample_fraction * npoints) (at least 3) points, in contour
 *        order, that no earlier line of this iteration claimed; fit a line by
 *        total least squares. If those m points do not lie on a line (mean
 *        squared residual above (inlier_distance/2)^2, i.e. the run wraps a
 *        corner or the border is ragged) the iteration is abandoned at once.
 *        Otherwise every unclaimed point within inlier_distance of the line is
 *        claimed by it.
 *     2. If the claimed points are fewer than inlier_ratio * npoints, no quad
 *        built on these lines can pass (its side inliers are a subset), so the
 *        iteration ends here, before any geometry.
 *     3. The lines are ordered clockwise by the direction from the contour's
 *        centroid to the centroid of their claimed points, and consecutive
 *        lines are intersected to give the corners.
 *     4. Inliers are recounted as the points within inlier_distance of the
 *        quad's four sides (segments). If the fraction reaches inlier_ratio,
 *        each side is refitted (total least squares, two passes) to the
 *        points closest to it, leaving out those within min(inlier_distance/2,
 *        side/5) of either corner so corner rounding does not bend the sides,
 *        and the refined lines are intersected (sub-pixel corners). The refined
 *        quad is accepted if it passes the tests below (else the unrefined one
 *        is tried):
 *          - inlier fraction (recounted) >= inlier_ratio,
 *          - |cos| between the two pairs of opposite sides >= min_parallel_cos,
 *          - convex, adjacent sides at least asin(0.2) = 11.5 degrees apart,
 *            every side at least inlier_distance long, every corner within
 *            inlier_distance + a quarter of the contour's extent of its
 *            bounding box.
 *   The first accepted quad is returned (early exit), after at most
 *   max_iterations iterations. A ragged blob is usually turned down within a
 *   few hundred nanoseconds per iteration because step 1 stops at the first
 *   crooked sample.
 *
 *   Determinism: only integer sums, float + - * / and sqrtf decide the result
 *   (no libm transcendental functions); same points, same parameters, same
 *   generator state -> same quad, bit for bit, on any IEEE-754 platform that
 *   evaluates float expressions in float without contraction into fused
 *   multiply-add (the default for GCC in -std=c99 mode; for other compilers
 *   use -ffp-contract=off). The generator advances by a data-dependent
 *   number of draws.
 *
 *   Output: corners[0..3] are consecutive corners, clockwise as seen on the
 *   screen (x right, y down), starting with the topmost corner (smallest y;
 *   on a tie the smallest x). inlier_ratio is the recounted fraction of
 *   contour points within inlier_distance of the returned quad's sides;
 *   iterations is the number of RANSAC iterations used (also on
 *   ACTAG_ERR_NO_QUAD, when the corners and ratio are zeroed).
 *
 *   Memory: scratch must hold ACTAG_QUAD_SCRATCH_SIZE(npoints) bytes (one byte
 *   per point, any alignment). No other memory is used; re-entrant.
 *
 * ERRORS
 *   ACTAG_ERR_NULL       pts, params, rng, scratch or out is NULL
 *   ACTAG_ERR_PARAM      npoints < 0, max_iterations < 1, sample_fraction or
 *                        inlier_ratio outside (0, 1], inlier_distance not > 0
 *                        (or not finite), min_parallel_cos outside [0, 1]
 *   ACTAG_ERR_SIZE       npoints > ACTAG_QUAD_MAX_POINTS
 *   ACTAG_ERR_WORKSPACE  scratch_size < ACTAG_QUAD_SCRATCH_SIZE(npoints)
 *   ACTAG_ERR_NO_QUAD    fewer than ACTAG_QUAD_MIN_POINTS points, or no
 *                        acceptable parallelogram within max_iterations
 */
#ifndef ACTAG_QUAD_H
#define ACTAG_QUAD_H

#include "actag/common.h"
#include "actag/rng.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Fewest contour points worth fitting. */
#define ACTAG_QUAD_MIN_POINTS 8
/* Most contour points accepted (keeps the exact 64-bit moment sums safe). */
#define ACTAG_QUAD_MAX_POINTS 32767

/* Scratch bytes actag_quad_fit() needs for npoints contour points. */
#define ACTAG_QUAD_SCRATCH_SIZE(npoints) ((size_t)(npoints) * 9u + 4u)

typedef struct actag_quad_params {
    int max_iterations;     /* RANSAC iterations, default 500 */
    float sample_fraction;  /* fraction of contour points per line sample, default 0.10 */
    float inlier_ratio;     /* inlier fraction that ends the search, default 0.85 (paper Table I) */
    float inlier_distance;  /* pixels, default 2.5 (paper Table I) */
    float min_parallel_cos; /* |cos| between opposite sides must be >= this, default 0.9 */
    float min_inlier_ratio; /* inlier fraction required of the best quad, default 0.80 */
} actag_quad_params;

/* Fills *p with the defaults above (no-op for NULL). */
void actag_quad_params_default(actag_quad_params *p);

typedef struct actag_quad {
    actag_point corners[4]; /* consecutive, clockwise on screen, topmost first (pixels) */
    float inlier_ratio;     /* fraction of contour points within inlier_distance of the sides */
    int iterations;         /* RANSAC iterations used */
} actag_quad;

/* Fits a parallelogram to the closed contour pts[0..npoints-1] (see MANUAL).
 * Returns ACTAG_OK and fills *out, or an ACTAG_ERR_* code. */
int actag_quad_fit(const actag_ipoint *pts, int npoints, const actag_quad_params *params,
                   actag_rng *rng, void *scratch, size_t scratch_size, actag_quad *out);

#ifdef __cplusplus
}
#endif
#endif /* ACTAG_QUAD_H */
