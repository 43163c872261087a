/* The corner refinement with a 16-bit frame's maximum already known
 * (internal): actag_detect refines every reported tag of one frame, and a
 * 16-bit frame's 8-bit scale (frame16.h) is one full-frame scan, taken once
 * per frame instead of once per tag. */
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

#endif
