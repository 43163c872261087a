/* The physical size filter and the first guesses of a blob's grid
 * (size_filter.h): what actag_detect asks of a contour or a quad before it
 * reads one. */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "size_filter.h"

#include "search_box.h"

/* A contour's extents and the white square's expected size there, in
 * pixels (size_plausible and merged_box judge the one against the other). */
typedef struct contour_size {
    float xc, yc;             /* the bounding box's centre */
    float dr, daz;            /* metres per row, per column at (xc, yc) */
    float diag_r, diag_az;    /* the white square's diagonal in rows, in columns */
    float ext_r, ext_az;      /* the contour's extents in rows, in columns */
} contour_size;

/* Returns 0 when the geometry gives no positive step there. */
static int contour_size_of(const actag_contour_info *ci, const actag_sonar_geometry *g,
                           const actag_params *p, int rows, int cols, contour_size *z)
{
    float diag = p->tag_size * 1.41421356f;
    z->yc = 0.5f * (float)(ci->min_y + ci->max_y);
    z->xc = 0.5f * (float)(ci->min_x + ci->max_x);
    z->dr = actag_geometry_range_step(g, rows);
    z->daz = actag_geometry_azimuth_step(g, cols, z->xc) * actag_geometry_range(g, rows, z->yc);
    if (!(z->dr > 0.0f) || !(z->daz > 0.0f))
        return 0;
    z->diag_r = diag / z->dr;
    z->diag_az = diag / z->daz;
    z->ext_r = (float)(ci->max_y - ci->min_y + 1);
    z->ext_az = (float)(ci->max_x - ci->min_x + 1);
    return 1;
}

/* Physical size filter (SPEC section 5): the white square's extents and area,
 * in pixels, must fit a tag of this size at this range. */
int actag__size_plausible(const actag_contour_info *ci, const actag_sonar_geometry *g,
                          const actag_params *p, int rows, int cols)
{
    contour_size z;
    float ref_area, tol = p->tuning.size_tolerance;
    if (!contour_size_of(ci, g, p, rows, cols, &z))
        return 0;
    if (z.ext_r > z.diag_r * (1.0f + tol) || z.ext_az > z.diag_az * (1.0f + tol))
        return 0;
    ref_area = z.diag_r * z.diag_az;
    if (ci->area < p->tuning.min_area_fraction * (1.0f - tol) * ref_area ||
        ci->area > p->tuning.max_area_fraction * (1.0f + tol) * ref_area)
        return 0;
    return 1;
}

/* A contour too large for a white square, within ACTAG_MERGED_EXTENT times
 * its extents and ACTAG_MERGED_AREA times its area (as size_plausible
 * measures them), where a tag's cells are narrower than ACTAG_MERGED_CELL
 * beams: there the beam's spread fills the one-cell black ring, and the
 * white square's blob merges with data cells (1.4-2.4 times its width in
 * beams, docs/evaluation.md). Wider cells keep their ring: such a guess
 * read nothing there and cost a wide decode per large clutter blob (the
 * pool frames, cells of 14 beams or more: +8 % Cortex-M7 instructions).
 * The guess is a white square's box at the blob's centre, sized as
 * actag_search_next sizes its quads (range extent times
 * search_range_scale), for the fit decoder's wide search. Returns 1 with
 * the box in q (clockwise on screen), else 0. */
int actag__merged_box(const actag_contour_info *ci, const actag_sonar_geometry *g,
                      const actag_params *p, int rows, int cols, actag_point q[4])
{
    contour_size z;
    float ref_area, tol = p->tuning.size_tolerance;
    if (!contour_size_of(ci, g, p, rows, cols, &z))
        return 0;
    if (!(p->tag_size / (float)(p->family->bits / 4 - 3) / z.daz < ACTAG_MERGED_CELL))
        return 0;
    ref_area = z.diag_r * z.diag_az;
    /* too large (not merely too small in area), but not by much */
    if (z.ext_r <= z.diag_r * (1.0f + tol) && z.ext_az <= z.diag_az * (1.0f + tol))
        return 0;
    if (!(z.ext_r <= ACTAG_MERGED_EXTENT * z.diag_r) ||
        !(z.ext_az <= ACTAG_MERGED_EXTENT * z.diag_az) ||
        !(ci->area <= ACTAG_MERGED_AREA * ref_area) ||
        !(ci->area >= p->tuning.min_area_fraction * ref_area))
        return 0;
    actag__search_box(g, rows, cols, z.xc, z.yc, p->tag_size, p->tuning.search_range_scale, q,
                      NULL, NULL);
    return 1;
}

/* Physical plausibility of a fitted quad: every side, measured in metres
 * through the sonar geometry, within [min, max] * tag_size. */
int actag__sides_plausible(const actag_point c[4], const actag_sonar_geometry *g,
                           const actag_params *p, int rows, int cols)
{
    float rg[4], az[4], lo = p->tuning.min_side_fraction * p->tag_size,
                        hi = p->tuning.max_side_fraction * p->tag_size;
    int i;
    for (i = 0; i < 4; i++) {
        rg[i] = actag_geometry_range(g, rows, c[i].y);
        az[i] = actag_geometry_azimuth(g, cols, c[i].x);
    }
    for (i = 0; i < 4; i++) {
        int j = (i + 1) & 3;
        float dr = rg[i] - rg[j];
        float da = (az[i] - az[j]) * 0.5f * (rg[i] + rg[j]);
        float l2 = dr * dr + da * da;
        if (!(l2 >= lo * lo) || !(l2 <= hi * hi))
            return 0;
    }
    return 1;
}

/* A first guess of a blob's tag grid when RANSAC finds no quad on its
 * border (ragged sonar outlines): the border point farthest from the
 * centroid, the point farthest from it, and the points farthest on either
 * side of the line through those two. The fit decoder's wide search only
 * needs a start within about a cell. Returns 0 when one side of that
 * line holds no point (size_filter.h). */
int actag__extreme_quad(const actag_ipoint *pts, int n, actag_point q[4])
{
    float cx = 0.0f, cy = 0.0f, best = -1.0f, dx, dy, lo = 0.0f, hi = 0.0f;
    long sx = 0, sy = 0;
    int i, i0 = 0, i1 = -1, i2 = 0, i3 = -1;
    if (n < 4)
        return 0;
    for (i = 0; i < n; i++) {
        sx += pts[i].x;
        sy += pts[i].y;
    }
    cx = (float)sx / (float)n;
    cy = (float)sy / (float)n;
    for (i = 0; i < n; i++) {
        float ex = (float)pts[i].x - cx, ey = (float)pts[i].y - cy, d = ex * ex + ey * ey;
        if (d > best) {
            best = d;
            i0 = i;
        }
    }
    best = -1.0f;
    for (i = 0; i < n; i++) {
        float ex = (float)(pts[i].x - pts[i0].x), ey = (float)(pts[i].y - pts[i0].y);
        float d = ex * ex + ey * ey;
        if (d > best) {
            best = d;
            i2 = i;
        }
    }
    dx = (float)(pts[i2].x - pts[i0].x);
    dy = (float)(pts[i2].y - pts[i0].y);
    for (i = 0; i < n; i++) {
        float s = dx * (float)(pts[i].y - pts[i0].y) - dy * (float)(pts[i].x - pts[i0].x);
        if (s > hi) {
            hi = s;
            i1 = i;
        }
        if (s < lo) {
            lo = s;
            i3 = i;
        }
    }
    if (i1 < 0 || i3 < 0)
        return 0;
    q[0].x = (float)pts[i0].x;
    q[0].y = (float)pts[i0].y;
    q[1].x = (float)pts[i1].x;
    q[1].y = (float)pts[i1].y;
    q[2].x = (float)pts[i2].x;
    q[2].y = (float)pts[i2].y;
    q[3].x = (float)pts[i3].x;
    q[3].y = (float)pts[i3].y;
    return 1;
}

/* Does a guess's corner (a contour point) lie on the frame's border? The
 * blob then reaches the frame's edge: either it is a white square whose
 * black ring and data cells lie outside the frame (the fit decoder reads no
 * grid whose data cells leave the frame), or the extreme point belongs to
 * something the blob merged with, not to the tag. On the simulator's
 * labelled frames no such guess read (0 of 53: 400 frames at the paper's
 * settings, 400 at the pool's), while a third of the pool frames' guesses
 * are such blobs (near-range returns and the fan's edges) and each costs a
 * wide search. */
int actag__guess_on_border(const actag_point q[4], int rows, int cols)
{
    int i;
    for (i = 0; i < 4; i++)
        if (q[i].x <= 0.0f || q[i].y <= 0.0f || q[i].x >= (float)(cols - 1) ||
            q[i].y >= (float)(rows - 1))
            return 1;
    return 0;
}
