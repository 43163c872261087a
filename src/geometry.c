/* Pixel <-> (range, azimuth) for polar sonar frames (SPEC section 4). */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/geometry.h"

/* actag_geometry_validate() is in validate.c with the other rules. */

float actag_geometry_range_step(const actag_sonar_geometry *geo, int rows)
{
    return rows > 1 ? (geo->max_range - geo->min_range) / (float)(rows - 1) : 0.0f;
}

float actag_geometry_range(const actag_sonar_geometry *geo, int rows, float y)
{
    float step = actag_geometry_range_step(geo, rows);
    if (geo->flags & ACTAG_RANGE_ASCENDING)
        return geo->min_range + y * step;
    return geo->max_range - y * step;
}

float actag_geometry_azimuth(const actag_sonar_geometry *geo, int cols, float x)
{
    if (geo->bearings != NULL) {
        int c0;
        float t;
        if (cols < 2) /* one beam; none (not a valid frame): no entry is read */
            return cols == 1 ? geo->bearings[0] : 0.0f;
        /* interpolate in the beam interval containing x (extrapolate at the
         * ends); a NaN x fails both tests, takes interval 0 and gives NaN */
        c0 = x > 0.0f ? (x < (float)(cols - 1) ? (int)x : cols - 2) : 0;
        t = x - (float)c0;
        return geo->bearings[c0] + t * (geo->bearings[c0 + 1] - geo->bearings[c0]);
    } else {
        float half = 0.5f * geo->aperture;
        float step = cols > 1 ? geo->aperture / (float)(cols - 1) : 0.0f;
        if (geo->flags & ACTAG_AZIMUTH_ASCENDING)
            return -half + x * step;
        return half - x * step;
    }
}

float actag_geometry_azimuth_step(const actag_sonar_geometry *geo, int cols, float x)
{
    float d;
    if (cols < 2)
        return 0.0f;
    if (geo->bearings != NULL) {
        /* as in actag_geometry_azimuth: a NaN x takes interval 0 */
        int c0 = x > 0.0f ? (x < (float)(cols - 1) ? (int)x : cols - 2) : 0;
        d = geo->bearings[c0 + 1] - geo->bearings[c0];
    } else {
        d = geo->aperture / (float)(cols - 1);
    }
    return d < 0.0f ? -d : d;
}

float actag_geometry_row(const actag_sonar_geometry *geo, int rows, float r)
{
    float step = actag_geometry_range_step(geo, rows);
    if (!(step > 0.0f))
        return 0.0f;
    if (geo->flags & ACTAG_RANGE_ASCENDING)
        return (r - geo->min_range) / step;
    return (geo->max_range - r) / step;
}

float actag_geometry_column(const actag_sonar_geometry *geo, int cols, float a)
{
    if (cols < 2)
        return 0.0f;
    if (geo->bearings != NULL) {
        /* the last interval c (0 .. cols-2) whose start a has reached, in
         * the table's direction; the end intervals extrapolate */
        const float *b = geo->bearings;
        int asc = b[cols - 1] > b[0], lo = 0, hi = cols - 2;
        while (lo < hi) {
            int mid = lo + (hi - lo + 1) / 2;
            if (asc ? a >= b[mid] : a <= b[mid])
                lo = mid;
            else
                hi = mid - 1;
        }
        return (float)lo + (a - b[lo]) / (b[lo + 1] - b[lo]);
    } else {
        float half = 0.5f * geo->aperture, step = geo->aperture / (float)(cols - 1);
        if (geo->flags & ACTAG_AZIMUTH_ASCENDING)
            return (a + half) / step;
        return (half - a) / step;
    }
}

int actag_geometry_mirrors(const actag_sonar_geometry *geo, int cols)
{
    int az_asc = geo->bearings ? (cols > 1 && geo->bearings[cols - 1] > geo->bearings[0])
                               : (geo->flags & ACTAG_AZIMUTH_ASCENDING) != 0u;
    int r_asc = (geo->flags & ACTAG_RANGE_ASCENDING) != 0u;
    return az_asc ^ r_asc;
}
