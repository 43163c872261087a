/*
 * actag/geometry.h -- the sonar's polar image: pixel <-> (range, azimuth).
 *
 * MANUAL
 *   A sonar frame is a polar image: rows are range bins, columns are beams.
 *   Default orientation (SPEC section 4, the reference's): row 0 is the
 *   maximum range, the last row the minimum range; column 0 is the largest
 *   (positive) azimuth +aperture/2, the last column -aperture/2. Pixel centres
 *   map linearly:
 *       range(row)   = max_range - row * (max_range - min_range) / (rows - 1)
 *       azimuth(col) = +aperture/2 - col * aperture / (cols - 1)
 *   Flags select the other orientation real drivers emit:
 *       ACTAG_RANGE_ASCENDING    row 0 is the minimum (nearest) range
 *       ACTAG_AZIMUTH_ASCENDING  column 0 is the most negative bearing
 *   Instead of a uniform aperture, `bearings` may point to one azimuth per
 *   column (radians, in column order, strictly monotonic), as published by
 *   sonars such as the Blueprint Subsea Oculus; it then overrides `aperture`
 *   and ACTAG_AZIMUTH_ASCENDING. Sub-pixel columns interpolate linearly
 *   between neighbouring beams (extrapolating past the first/last beam).
 *
 *   Units: ranges in metres, angles in radians, positions in pixels
 *   (x = column, y = row, pixel centres at integers).
 *
 *   Validation: actag_geometry_validate(geo, rows, cols, detail) checks a
 *   geometry for a rows x cols frame; detail (may be NULL) names the field
 *   at fault ("min_range", "bearings" with its index, ...), its value and
 *   the rule (actag_error_detail, common.h; inside actag_check the names
 *   are "geometry.min_range" etc.). The rules, in the order checked:
 *     flags           only ACTAG_RANGE_ASCENDING | ACTAG_AZIMUTH_ASCENDING
 *     min_range       finite, >= 0
 *     max_range       finite; min_range < max_range
 *     range step      (max_range - min_range) / (rows - 1) >=
 *                     ACTAG_MIN_RANGE_STEP * max_range (rows > 1), so every
 *                     row has its own range in float
 *     bearings        (when given) every entry finite; strictly monotonic,
 *                     each step at least ACTAG_MIN_AZIMUTH_STEP rad; the
 *                     whole table spans less than 2 pi
 *     aperture        (without bearings) > 0 and < 2 pi, and
 *                     aperture / (cols - 1) >= ACTAG_MIN_AZIMUTH_STEP
 *   The two least steps keep every pixel-size computation of the stages
 *   (search.c, the size filter) finite and far from int overflow; real
 *   sonars are orders of magnitude above them.
 *
 * ERRORS
 *   ACTAG_ERR_NULL      geometry pointer NULL
 *   ACTAG_ERR_SIZE      rows or cols < 1 or > ACTAG_MAX_DIM
 *   ACTAG_ERR_GEOMETRY  any rule above broken
 */
#ifndef ACTAG_GEOMETRY_H
#define ACTAG_GEOMETRY_H

#include "actag/common.h"

#ifdef __cplusplus
extern "C" {
#endif

#define ACTAG_RANGE_ASCENDING 1u
#define ACTAG_AZIMUTH_ASCENDING 2u

typedef struct actag_sonar_geometry {
    float min_range;       /* metres, range of the nearest row's centre */
    float max_range;       /* metres, range of the farthest row's centre */
    float aperture;        /* radians, horizontal field of view (ignored with bearings) */
    const float *bearings; /* optional per-column azimuth table (cols entries), or NULL */
    unsigned flags;        /* ACTAG_RANGE_ASCENDING | ACTAG_AZIMUTH_ASCENDING */
} actag_sonar_geometry;

/* Least range step between rows, as a fraction of max_range. */
#define ACTAG_MIN_RANGE_STEP 1e-6f
/* Least azimuth step between columns, radians. */
#define ACTAG_MIN_AZIMUTH_STEP 1e-6f

/* Checks the geometry for a rows x cols frame (rules above). Returns
 * ACTAG_OK or an error code; fills *detail when it is not NULL. */
int actag_geometry_validate(const actag_sonar_geometry *geo, int rows, int cols,
                            actag_error_detail *detail);

/* The mappings below have no error codes and check nothing: geo must
 * not be NULL and should be validated for the frame. Any float x or y is
 * safe, NaN and infinities included (no out-of-range int conversion, no
 * read outside the bearing table): a NaN gives a NaN range or azimuth, and
 * actag_geometry_azimuth_step() the table's first step for a NaN x. */

/* Range (m) at a sub-pixel row y. Assumes a validated geometry. */
float actag_geometry_range(const actag_sonar_geometry *geo, int rows, float y);

/* Azimuth (rad) at a sub-pixel column x. Assumes a validated geometry. */
float actag_geometry_azimuth(const actag_sonar_geometry *geo, int cols, float x);

/* The inverses: the sub-pixel row at range r (m) and the sub-pixel column
 * at azimuth a (rad), so that actag_geometry_range(geo, rows,
 * actag_geometry_row(geo, rows, r)) is r up to float rounding, and the
 * same for the column (past the first or last row or beam they
 * extrapolate, as the mappings do; a bearing table's interval is found by
 * bisection, O(log cols)). 0 when rows (cols) < 2; a NaN gives a NaN.
 * For predictions made in metres (a navigation filter's, the tracker's
 * across a new sonar setting). */
float actag_geometry_row(const actag_sonar_geometry *geo, int rows, float r);
float actag_geometry_column(const actag_sonar_geometry *geo, int cols, float a);

/* Metres per row (>= 0 for a validated geometry; 0 when rows < 2). */
float actag_geometry_range_step(const actag_sonar_geometry *geo, int rows);

/* Radians per column near sub-pixel column x (always >= 0; 0 when cols < 2). */
float actag_geometry_azimuth_step(const actag_sonar_geometry *geo, int cols, float x);

/* 1 when the frame's orientation is a mirror image of the reference one
 * (exactly one of its axes reversed: ACTAG_RANGE_ASCENDING, or azimuth
 * ascending along the columns, by the flag or by the bearing table), else 0.
 * A tag's handedness as seen in such a frame is the other one, so the
 * detector flips the decoder's `mirrored` (and its handedness prior) by it.
 * Assumes a validated geometry for a frame of `cols` columns. */
int actag_geometry_mirrors(const actag_sonar_geometry *geo, int cols);

#ifdef __cplusplus
}
#endif
#endif
