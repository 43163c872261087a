/* The corner refinement with a 16-bit frame's maximum already known
 * (internal): actag_detect refines every reported tag of one frame, and a
 * 16-bit frame's 8-bit scale (frame16.h) is one full-frame scan, taken once
 * per frame instead of once per tag. Also a test hook of the acceptance. */
#ifndef ACTAG_REFINE_FRAME_H
#define ACTAG_REFINE_FRAME_H

#include "actag/refine.h"

/* actag_refine_corners_depth() for a frame whose largest sample is max16
 * (depth 16; 0: scan the frame for it, as actag_refine_corners_depth does;
 * ignored for depth 8). The same results as actag_refine_corners_depth(). */
int actag__refine_corners_max16(const void *img, int depth, uint32_t max16, int rows, int cols,
                                int stride, const actag_sonar_geometry *geometry, float tag_size,
                                const actag_family *family, int id, const actag_point corners[4],
                                const actag_refine_params *rp, actag_point out[4],
                                actag_refine_info *info);

/* Test hook: 1 when a fitted grid `fit` passes the shape rules of the
 * acceptance (refine.h, Safety: finite, the start's handedness, sides
 * within 25 % or grown to at most the cell size) against the start grid
 * `start`, else 0. Grids as (m1, m2, M11, M21, M12, M22): centre and the
 * two cell vectors in the fan plane (metres; pixels without a geometry);
 * cell2 the squared cell side (m^2; 0: no geometry). */
int actag__refine_shape_ok(const float start[6], const float fit[6], float cell2);

#endif
