/* The corner refinement's model at one grid (internal; refine.c), for
 * tests/test_refine_model.c: are the Gauss-Newton normal equations the
 * derivatives of the residual sum they minimise?
 *
 * actag__refine_probe: the refinement of tag id's corners (tag order) on an
 * 8-bit frame, set up as actag_refine_corners sets it up, with the template
 * edges of its second pass (blur pixels) and the six levels fitted at the
 * start grid and held; then, at the start grid moved by dp (its 6
 * parameters: the centre, then the two cell vectors; fan-plane metres with
 * a geometry, pixels without), over the start grid's pixel set: *rss the
 * residual sum of squares, b the right side J'r and A the packed upper
 * triangle of J'J (21, rows in turn) of the normal equations. start (if
 * not NULL): the start grid's 6 parameters. Returns ACTAG_OK, or
 * ACTAG_ERR_NULL, ACTAG_ERR_PARAM or ACTAG_ERR_NO_MATCH as
 * actag_refine_corners would for these arguments. */
#ifndef ACTAG_REFINE_PROBE_H
#define ACTAG_REFINE_PROBE_H

#include "actag/refine.h"

int actag__refine_probe(const uint8_t *img, int rows, int cols, int stride,
                        const actag_sonar_geometry *geometry, float tag_size,
                        const actag_family *family, int id, const actag_point corners[4],
                        float blur, const float dp[6], float *rss, float b[6], float A[21],
                        float start[6]);

#endif
