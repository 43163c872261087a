/* The physical size filter (internal): is a contour, a blob or a fitted
 * quad the size of a tag's white square at its range (SPEC section 5)?
 * And the first guesses of a grid where RANSAC gives no quad: a blob's
 * extreme points, a merged blob's box. Used by actag_detect (detect.c);
 * tested in tests/test_size_filter.c against references of its own.
 *
 * All take the frame's sonar geometry g (valid for rows x cols,
 * actag_geometry_validate) and read p->tag_size (metres), p->family->bits
 * and the tuning fields named below; pixels are x = column, y = row. */
#ifndef ACTAG_SIZE_FILTER_H
#define ACTAG_SIZE_FILTER_H

#include "actag/actag.h"

/* 1 when a contour's bounding box fits the white square's diagonal at its
 * centre in rows and in columns (within 1 + tuning.size_tolerance), and
 * its area lies within [min_area_fraction * (1 - tol), max_area_fraction
 * * (1 + tol)] times the diagonal box's area; 0 otherwise, and where the
 * geometry gives no positive range or azimuth step at the box's centre. */
int actag__size_plausible(const actag_contour_info *ci, const actag_sonar_geometry *g,
                          const actag_params *p, int rows, int cols);

/* A contour too large for a white square, but within ACTAG_MERGED_EXTENT
 * times its extents and ACTAG_MERGED_AREA times its area (and not under
 * min_area_fraction of it), where a tag's cells are narrower than
 * ACTAG_MERGED_CELL beams: a white square merged with its data cells.
 * Returns 1 with the white square's box at the blob's centre in q
 * (actag__search_box: clockwise on screen, range extent times
 * search_range_scale), else 0. */
#define ACTAG_MERGED_EXTENT 2.5f
#define ACTAG_MERGED_AREA 3.0f
#define ACTAG_MERGED_CELL 10.0f
int actag__merged_box(const actag_contour_info *ci, const actag_sonar_geometry *g,
                      const actag_params *p, int rows, int cols, actag_point q[4]);

/* 1 when every side of quad c, measured in metres through the geometry
 * (range difference, and azimuth difference times the mean range), lies
 * within [min_side_fraction, max_side_fraction] * tag_size; 0 otherwise
 * (also for NaN corners). */
int actag__sides_plausible(const actag_point c[4], const actag_sonar_geometry *g,
                           const actag_params *p, int rows, int cols);

/* A first guess of a blob's grid from its n border points: the point
 * farthest from the centroid (q[0]; the first such point), the point
 * farthest from it (q[2]), and the points farthest on either side of the
 * line through those two: q[1] where the cross product
 * dx * (y - y0) - dy * (x - x0) (d = q[2] - q[0]) is largest and
 * positive, q[3] where it is smallest and negative (first such points).
 * Returns 1, or 0 for fewer than 4 points or when one side of that line
 * holds no point (the points on one line, or a border such as a
 * triangle's, which reaches only one side). */
int actag__extreme_quad(const actag_ipoint *pts, int n, actag_point q[4]);

/* 1 when a corner of q lies on the frame's border (x <= 0, y <= 0,
 * x >= cols - 1 or y >= rows - 1): such a guess is not read. */
int actag__guess_on_border(const actag_point q[4], int rows, int cols);

#endif
