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
 *   Algorithm (bounded, deterministic): RANSAC over four lines, as the
 *   reference (actag 1.0.1) does it, with cheaper rejections. Each iteration:
 *     1. For each of 4 lines: from a random start index, take the next
 *        m = round(sample_fraction * npoints) (at least 3) points, in contour
 *        order, that no earlier line of this iteration claimed: a run along
 *        the border, which on a quad mostly lies on one side. Fit a line by
 *        total least squares; if its residuals exceed inlier_distance,
 *        refit it to the run's points within inlier_distance of it (a spike
 *        would tilt it), and drop the iteration if they are fewer than half
 *        of the run. The line claims every unclaimed point within
 *        inlier_distance.
 *     2. Every inlier of a quad built on these lines was claimed, so if the
 *        claimed fraction is below min_inlier_ratio - 0.1, or does not beat
 *        the best unrefined quad so far, the iteration ends here.
 *     3. The lines are ordered clockwise by the direction from the contour's
 *        centroid to their runs, consecutive lines are intersected, and the
 *        shape must be convex with sides >= inlier_distance, adjacent sides
 *        >= 11.5 degrees apart, corners within inlier_distance + a quarter of
 *        the contour's extent of its bounding box.
 *     4. Inliers = points within inlier_distance of the four sides (line
 *        segments), each assigned to its nearest side; every side's inliers
 *        must spread over at least half its length. A quad whose inlier
 *        fraction is at least min_inlier_ratio - 0.1 and the best so far is
 *        refined: each corner is tied to its nearest contour point, each side
 *        is refitted (total least squares) to the stretch of contour between
 *        its corners (points near its current line, at most inlier_distance
 *        and at least 1.5 px or 2.5 sigma away, and not nearer an adjacent
 *        side's line), the lines are re-intersected, until no corner moves by
 *        0.01 px (at most 8 passes): sub-pixel corners.
 *     5. The refined quad (else the unrefined one) is accepted if it passes
 *        step 3, step 4's support test, has inlier fraction >=
 *        min_inlier_ratio and |cos| >= min_parallel_cos between both pairs of
 *        opposite sides. The search stops at the first accepted quad with
 *        inlier fraction >= inlier_ratio; otherwise, after max_iterations, the
 *        best accepted quad (if any) is returned.
 *   Shortcuts that never change the result (tests/test_quad_paths.c checks
 *   them against the plain loops): step 3's shape test runs before the
 *   fourth line's claim count, which, like step 4's support count, stops as
 *   soon as the iteration can no longer reach the count the ratio tests
 *   need; without a vector unit (Cortex-M), the claim loops skip along the
 *   contour the points that cannot be within inlier_distance of the line
 *   (consecutive points are at most one pixel apart, so a point's distance
 *   changes by at most |nx| + |ny| per step; ACTAG_QUAD_FORCE_SKIP forces
 *   this path elsewhere). RANSAC on the 58 pool frames, Cortex-M7 -O2: 6.5
 *   M instructions per frame on average, 25.5 M at worst (tools/budget,
 *   the README's table).
 *   Cost: about 1 microsecond per iteration for a 200-point contour on a
 *   desktop core; a clean tag outline is usually found in 1-10 iterations,
 *   while a contour with no acceptable quad uses all max_iterations (lower
 *   it to trade a few marginal detections for time).
 *
 *   Differences from the reference: sub-pixel corners (it rounds them to
 *   whole pixels); lines ordered around the contour (it pairs them by slope);
 *   each line claims its inliers before the next run is drawn, as in the
 *   paper (its code removes only the sampled run); refinement on contour
 *   stretches until the corners settle (it refits once per improvement); the
 *   per-side support test (it has none).
 *
 *   Determinism: only integer sums, float + - * / and sqrtf decide the result
 *   (no libm transcendental functions); same points, same parameters, same
 *   generator state -> same quad, bit for bit, on any IEEE-754 platform that
 *   evaluates float expressions in float (FLT_EVAL_METHOD 0: SSE, ARM VFP;
 *   not x87) without contraction into fused multiply-add (the default for
 *   GCC in -std=c99 mode; elsewhere use -ffp-contract=off). The generator
 *   advances by a data-dependent number of draws.
 *
 *   Output: corners[0..3] are consecutive corners, clockwise as seen on the
 *   screen (x right, y down), starting with the topmost corner (smallest y;
 *   on a tie the smallest x). inlier_ratio is the fraction of the contour
 *   points within inlier_distance of the returned quad's sides; iterations
 *   is the number of RANSAC iterations run; stopped_early is 1 when the
 *   search ended at a quad of inlier fraction >= inlier_ratio (possibly on
 *   its last allowed iteration), else 0 (it ran all max_iterations). On
 *   ACTAG_ERR_NO_QUAD the corners and ratio are zero and iterations and
 *   stopped_early (0) are still set; on other errors *out is untouched.
 *
 *   Memory: scratch must hold ACTAG_QUAD_SCRATCH_SIZE(npoints) bytes, any
 *   alignment (9 bytes per point + 4). No other memory is used; re-entrant.
 *
 * ERRORS
 *   ACTAG_ERR_NULL       pts, params, rng, scratch or out is NULL
 *   ACTAG_ERR_PARAM      npoints < 0, or params fail actag_quad_params_validate():
 *                        max_iterations outside 1..ACTAG_QUAD_MAX_ITERATIONS,
 *                        sample_fraction, inlier_ratio or min_inlier_ratio
 *                        outside (0, 1], inlier_distance outside (0, 1e6],
 *                        min_parallel_cos outside [0, 1] (NaN is out of every
 *                        range)
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

/* Parameters; the defaults are the reference's (paper Table I and the
 * actag 1.0.1 package). */
typedef struct actag_quad_params {
    int max_iterations;     /* RANSAC iterations at most, default 500 */
    float sample_fraction;  /* fraction of the contour's points per line sample, default 0.10 */
    float inlier_ratio;     /* "desired": an accepted quad with this inlier fraction ends the
                               search at once, default 0.85 */
    float inlier_distance;  /* pixels, default 2.5 */
    float min_parallel_cos; /* |cos| between opposite sides must be >= this, default 0.9 */
    float min_inlier_ratio; /* "required": the least inlier fraction of a returned quad,
                               default 0.80 (taken as min(min_inlier_ratio, inlier_ratio)) */
} actag_quad_params;

/* Fills *p with the defaults above (no-op for NULL). */
void actag_quad_params_default(actag_quad_params *p);

/* Most RANSAC iterations accepted (bounds the time of one contour). */
#define ACTAG_QUAD_MAX_ITERATIONS 1000000

/* Checks *params against the rules of ERRORS below (the ones actag_quad_fit
 * applies). Returns ACTAG_OK, ACTAG_ERR_NULL or ACTAG_ERR_PARAM; fills
 * *detail (common.h; field names as "inlier_distance") when not NULL. */
int actag_quad_params_validate(const actag_quad_params *params, actag_error_detail *detail);

typedef struct actag_quad {
    actag_point corners[4]; /* consecutive, clockwise on screen, topmost first (pixels) */
    float inlier_ratio;     /* fraction of contour points within inlier_distance of the sides */
    int iterations;         /* RANSAC iterations used */
    int stopped_early;      /* 1: ended at a quad reaching inlier_ratio, 0: ran all
                               max_iterations (iterations == max_iterations alone does
                               not tell: the last iteration may be the one that stops) */
} actag_quad;

/* Fits a parallelogram to the closed contour pts[0..npoints-1] (see MANUAL).
 * Returns ACTAG_OK and fills *out, or an ACTAG_ERR_* code. */
int actag_quad_fit(const actag_ipoint *pts, int npoints, const actag_quad_params *params,
                   actag_rng *rng, void *scratch, size_t scratch_size, actag_quad *out);

#ifdef __cplusplus
}
#endif
#endif /* ACTAG_QUAD_H */
