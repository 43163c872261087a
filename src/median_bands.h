/* The median's radius per band of rows (internal): where a tag's cells are
 * not much wider than the median's window, the window blurs them, so the
 * radius follows the cell width the sonar's geometry gives at each range
 * (actag_tuning.median_per_range, actag.h). Shared by actag_detect,
 * actag_detect_inplace and actag_detect_multi (the tracker's windows have
 * their own rule, track.c). */
#ifndef ACTAG_MEDIAN_BANDS_H
#define ACTAG_MEDIAN_BANDS_H

#include "actag/actag.h"

#include <stddef.h>
#include <stdint.h>

/* Radii 1..7 in bands monotone in range: at most 7 bands. */
#define ACTAG__MEDIAN_BANDS_MAX 8

typedef struct actag__median_bands {
    int n;                              /* bands, 1..ACTAG__MEDIAN_BANDS_MAX */
    int end[ACTAG__MEDIAN_BANDS_MAX];   /* band i is rows end[i - 1] (0 for i = 0) .. end[i] - 1;
                                           end[n - 1] = rows */
    int radius[ACTAG__MEDIAN_BANDS_MAX]; /* its median radius */
} actag__median_bands;

/* The radius for cells `cell_px` pixels wide: the largest r <= r0 whose
 * window, 2 r + 1 pixels, spans at most half the cell plus 2 pixels (4 r -
 * 2 <= cell_px), at least 2 (NaN or tiny cells: 2); r0 itself when r0 < 2
 * (actag.h, DEFAULTS AND WHY). */
int actag__median_radius_for_cell(float cell_px, int r0);

/* The bands of a rows x cols frame for parameters p: one band of
 * p->tuning.median_radius when median_per_range is 0 or the radius is 0 or
 * above ACTAG_MEDIAN_INPLACE_MAX_RADIUS; else each row takes
 * actag__median_radius_for_cell of the cell width in beams at its range
 * (p->tag_size over the cells across the white square, over range x the
 * mean beam spacing), rows of equal radius forming a band. */
void actag__median_bands_of(const actag_sonar_geometry *g, int rows, int cols,
                            const actag_params *p, actag__median_bands *b);

/* Do two band sets filter a frame alike? */
int actag__median_bands_equal(const actag__median_bands *a, const actag__median_bands *b);

/* actag_median_filter (depth 8) or actag__median_filter16_max (depth 16)
 * with each band's rows filtered at the band's radius: output row y is the
 * median of the (2R+1)^2 window around it in the whole frame (edge
 * replication at the frame's edges only), R its band's radius; a single
 * band is the plain filter. More than one band needs every radius <=
 * ACTAG_MEDIAN_INPLACE_MAX_RADIUS and, for 16-bit frames, a scratch of at
 * least ACTAG_MEDIAN_INPLACE_SCRATCH_SIZE(cols) bytes (ACTAG_ERR_PARAM /
 * ACTAG_ERR_WORKSPACE otherwise). */
int actag__median_filter_bands(const void *src, int depth, uint32_t max16, int rows, int cols,
                               int src_stride, uint8_t *dst, int dst_stride,
                               const actag__median_bands *b, void *scratch, size_t scratch_size);

/* actag_median_filter_inplace with bands (as above; every radius <=
 * ACTAG_MEDIAN_INPLACE_MAX_RADIUS). */
int actag__median_filter_inplace_bands(void *frame, int depth, int rows, int cols, int stride,
                                       uint32_t max16, const actag__median_bands *b,
                                       void *scratch, size_t scratch_size);

#endif
