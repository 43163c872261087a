/* The box the structure search reads a candidate at (internal): the tag's
 * white square, axis-aligned in pixels, centred at (x, y). Shared by
 * actag_search_next and the merged-blob guess of actag_detect (size_filter.c),
 * so both read a white square of the same size at one place. */
#ifndef ACTAG_SEARCH_BOX_H
#define ACTAG_SEARCH_BOX_H

#include "actag/geometry.h"

/* quad: the box at (x, y) (column, row; pixels), clockwise on screen from
 * its top-left corner, half a tag_size (metres) across in beams at (x, y)
 * and half of tag_size * range_scale in range bins; *hr and *hc (if not
 * NULL): those half extents, pixels. g is valid for rows x cols
 * (actag_geometry_validate); the extents are infinite or NaN when the beam
 * spacing at (x, y) is 0. */
void actag__search_box(const actag_sonar_geometry *g, int rows, int cols, float x, float y,
                       float tag_size, float range_scale, actag_point quad[4], float *hr,
                       float *hc);

#endif
