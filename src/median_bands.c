/* The median's radius per band of rows (median_bands.h). */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "median_bands.h"
#include "actag/geometry.h"
#include "actag/median.h"

int actag__median_radius_for_cell(float cell_px, int r0)
{
    /* the largest r <= r0 with 4 r - 2 <= cell_px (a window of 2 r + 1 <=
     * cell_px / 2 + 2 pixels), at least 2 (NaN: 2); r0 below 2 is kept */
    int r = r0;
    while (r > 2 && !(cell_px >= 4.0f * (float)r - 2.0f))
        r--;
    return r;
}

void actag__median_bands_of(const actag_sonar_geometry *g, int rows, int cols,
                            const actag_params *p, actag__median_bands *b)
{
    int r0 = p->tuning.median_radius, y, r;
    float cell_m, step;
    b->n = 1;
    b->end[0] = rows;
    b->radius[0] = r0;
    if (!p->tuning.median_per_range || r0 < 1 || r0 > ACTAG_MEDIAN_INPLACE_MAX_RADIUS ||
        rows < 1 || cols < 2)
        return;
    /* the cell: the white square is bits / 4 - 3 cells across */
    cell_m = p->tag_size / (float)(p->family->bits / 4 - 3);
    /* the mean beam spacing (a bearing table's too) */
    step = actag_geometry_azimuth(g, cols, 0.0f) - actag_geometry_azimuth(g, cols, (float)(cols - 1));
    step = (step < 0.0f ? -step : step) / (float)(cols - 1);
    b->n = 0;
    for (y = 0; y < rows; y++) {
        float range = actag_geometry_range(g, rows, (float)y), w = range * step;
        /* the nearest rows (range 0) take r0 */
        r = w > 0.0f ? actag__median_radius_for_cell(cell_m / w, r0) : r0;
        if (b->n > 0 && b->radius[b->n - 1] == r) {
            b->end[b->n - 1] = y + 1;
            continue;
        }
        if (b->n == ACTAG__MEDIAN_BANDS_MAX) { /* not reached: range is monotone */
            b->end[b->n - 1] = y + 1;
            if (r < b->radius[b->n - 1])
                b->radius[b->n - 1] = r;
            continue;
        }
        b->radius[b->n] = r;
        b->end[b->n] = y + 1;
        b->n++;
    }
}

int actag__median_bands_equal(const actag__median_bands *a, const actag__median_bands *b)
{
    int i;
    if (a->n != b->n)
        return 0;
    for (i = 0; i < a->n; i++)
        if (a->end[i] != b->end[i] || a->radius[i] != b->radius[i])
            return 0;
    return 1;
}
