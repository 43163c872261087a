/* The tag's cell grid: layout, data-bit cells, grid -> image maps (tag_grid.h). */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/tag_grid.h"

/* 1 for 16, 20, 24, 28, 32 data bits. */
static int bits_ok(int bits) { return bits >= 16 && bits <= 32 && bits % 4 == 0; }

/* +1 if quad is strictly convex and clockwise on screen (x right, y down),
 * -1 if strictly convex and counter-clockwise, 0 if degenerate. Every turn
 * must have |sin| > 1e-3 and the same sign; NaN/inf fail the comparisons. */
static int quad_orientation(const actag_point q[4])
{
    int i, pos = 0, neg = 0;
    for (i = 0; i < 4; i++) {
        const actag_point *a = &q[i], *b = &q[(i + 1) & 3], *c = &q[(i + 2) & 3];
        float e1x = b->x - a->x, e1y = b->y - a->y;
        float e2x = c->x - b->x, e2y = c->y - b->y;
        float z = e1x * e2y - e1y * e2x;
        float l = (e1x * e1x + e1y * e1y) * (e2x * e2x + e2y * e2y);
        /* z^2 > 1e-6 * |e1|^2 |e2|^2  <=>  |sin(turn)| > 1e-3 */
        if (!(z * z > 1e-6f * l) || !(l <= 3.0e38f))
            return 0;
        if (z > 0.0f)
            pos++;
        else
            neg++;
    }
    return pos == 4 ? 1 : (neg == 4 ? -1 : 0);
}

/* The argument checks of both maps. */
static int check_quad(const actag_point quad[4], int bits, const float *H)
{
    if (quad == NULL || H == NULL)
        return ACTAG_ERR_NULL;
    if (!bits_ok(bits))
        return ACTAG_ERR_PARAM;
    if (quad_orientation(quad) == 0)
        return ACTAG_ERR_PARAM;
    return ACTAG_OK;
}

void actag_homography_apply(const float H[9], float u, float v, actag_point *out)
{
    float w = H[6] * u + H[7] * v + H[8];
    out->x = (H[0] * u + H[1] * v + H[2]) / w;
    out->y = (H[3] * u + H[4] * v + H[5]) / w;
}

int actag_tag_homography(const actag_point quad[4], int bits, float H[9])
{
    float x0, y0, x1, y1, x2, y2, x3, y3, dx1, dx2, dx3, dy1, dy2, dy3;
    float a, b, c, d, e, f, g, h, den, il;
    int k, i;
    int rc = check_quad(quad, bits, H);
    if (rc != ACTAG_OK)
        return rc;
    k = bits / 4;
    x0 = quad[0].x; y0 = quad[0].y;
    x1 = quad[1].x; y1 = quad[1].y;
    x2 = quad[2].x; y2 = quad[2].y;
    x3 = quad[3].x; y3 = quad[3].y;
    /* Unit square (s,t) -> quad with (0,0),(1,0),(1,1),(0,1) -> q0..q3
     * (Heckbert's closed form; g = h = 0 for a parallelogram). */
    dx1 = x1 - x2; dx2 = x3 - x2; dx3 = x0 - x1 + x2 - x3;
    dy1 = y1 - y2; dy2 = y3 - y2; dy3 = y0 - y1 + y2 - y3;
    den = dx1 * dy2 - dx2 * dy1;
    if (!(den != 0.0f))
        return ACTAG_ERR_PARAM;
    g = (dx3 * dy2 - dx2 * dy3) / den;
    h = (dx1 * dy3 - dx3 * dy1) / den;
    a = x1 - x0 + g * x1; b = x3 - x0 + h * x3; c = x0;
    d = y1 - y0 + g * y1; e = y3 - y0 + h * y3; f = y0;
    /* Then grid -> unit square: s = (u - 2) / (k - 3), t = (v - 2) / (k - 3). */
    il = 1.0f / (float)(k - 3);
    H[0] = a * il; H[1] = b * il; H[2] = c - 2.0f * (a + b) * il;
    H[3] = d * il; H[4] = e * il; H[5] = f - 2.0f * (d + e) * il;
    H[6] = g * il; H[7] = h * il; H[8] = 1.0f - 2.0f * (g + h) * il;
    for (i = 0; i < 9; i++)
        if (!(H[i] >= -3.0e38f && H[i] <= 3.0e38f))
            return ACTAG_ERR_PARAM;
    /* w is affine in (u,v): positive at the 4 corners of the whole (k+1)^2
     * grid means no tag point is sent through infinity. */
    for (i = 0; i < 4; i++) {
        float u = (i == 1 || i == 2) ? (float)(k + 1) : 0.0f;
        float v = (i >= 2) ? (float)(k + 1) : 0.0f;
        if (!(H[6] * u + H[7] * v + H[8] > 0.0f))
            return ACTAG_ERR_PARAM;
    }
    return ACTAG_OK;
}

int actag_tag_affine(const actag_point quad[4], int bits, float H[9])
{
    float h, g, ax, bx, ay, by, mx, my;
    int i;
    int rc = check_quad(quad, bits, H);
    if (rc != ACTAG_OK)
        return rc;
    /* Least squares over the 4 corners. The grid corners are a square of
     * half side h about g = (k+1)/2, so the normal equations are diagonal:
     * the columns are the mean side vectors, the offset the centroid. */
    h = (float)(bits / 4 - 3) * 0.5f;
    g = (float)(bits / 4 + 1) * 0.5f;
    ax = ((quad[1].x - quad[0].x) + (quad[2].x - quad[3].x)) / (4.0f * h);
    ay = ((quad[1].y - quad[0].y) + (quad[2].y - quad[3].y)) / (4.0f * h);
    bx = ((quad[3].x - quad[0].x) + (quad[2].x - quad[1].x)) / (4.0f * h);
    by = ((quad[3].y - quad[0].y) + (quad[2].y - quad[1].y)) / (4.0f * h);
    mx = ((quad[0].x + quad[2].x) + (quad[1].x + quad[3].x)) * 0.25f;
    my = ((quad[0].y + quad[2].y) + (quad[1].y + quad[3].y)) * 0.25f;
    H[0] = ax; H[1] = bx; H[2] = mx - (ax + bx) * g;
    H[3] = ay; H[4] = by; H[5] = my - (ay + by) * g;
    H[6] = 0.0f; H[7] = 0.0f; H[8] = 1.0f;
    for (i = 0; i < 6; i++)
        if (!(H[i] >= -3.0e38f && H[i] <= 3.0e38f))
            return ACTAG_ERR_PARAM;
    return ACTAG_OK;
}

int actag_tag_map(const actag_point quad[4], int bits, int model, float H[9])
{
    if (model == ACTAG_DECODE_AFFINE)
        return actag_tag_affine(quad, bits, H);
    if (model == ACTAG_DECODE_PROJECTIVE)
        return actag_tag_homography(quad, bits, H);
    return ACTAG_ERR_PARAM;
}

void actag_tag_bit_cell(int bits, int i, int *cx, int *cy)
{
    int k = bits / 4, side = i / k, j = i % k;
    switch (side) {
    case 0: *cx = j; *cy = 0; break;
    case 1: *cx = k; *cy = j; break;
    case 2: *cx = k - j; *cy = k; break;
    default: *cx = 0; *cy = k - j; break;
    }
}

int actag_tag_cell_value(uint32_t code, int bits, int cx, int cy)
{
    int k = bits / 4, i;
    if (cx == 0 || cy == 0 || cx == k || cy == k) {
        /* Data ring, clockwise from the top-left corner; each side owns k cells
         * starting at its first corner (the inverse of actag_tag_bit_cell). */
        if (cy == 0 && cx < k)
            i = cx;
        else if (cx == k && cy < k)
            i = k + cy;
        else if (cy == k && cx > 0)
            i = 3 * k - cx;
        else
            i = 4 * k - cy; /* cx == 0, cy > 0 */
        return (int)((code >> (4 * k - 1 - i)) & 1u);
    }
    if (cx == 1 || cy == 1 || cx == k - 1 || cy == k - 1)
        return 0; /* black ring */
    return 1;     /* white interior */
}

int actag_decode_bit_positions(const actag_point quad[4], int bits, actag_point *out)
{
    float H[9];
    int i, cx, cy, rc;
    if (quad == NULL || out == NULL)
        return ACTAG_ERR_NULL;
    rc = actag_tag_map(quad, bits, ACTAG_DECODE_DEFAULT_MODEL, H);
    if (rc != ACTAG_OK)
        return rc;
    for (i = 0; i < bits; i++) {
        actag_tag_bit_cell(bits, i, &cx, &cy);
        actag_homography_apply(H, (float)cx + 0.5f, (float)cy + 0.5f, &out[i]);
    }
    return ACTAG_OK;
}

int actag_tag_quad_clockwise(const actag_point quad[4], actag_point q[4])
{
    int i, orient;
    if (quad == NULL || q == NULL)
        return ACTAG_ERR_NULL;
    orient = quad_orientation(quad);
    if (orient == 0)
        return ACTAG_ERR_PARAM;
    q[0] = quad[0];
    for (i = 1; i < 4; i++)
        q[i] = quad[orient > 0 ? i : 4 - i];
    return ACTAG_OK;
}

void actag_tag_corners(const actag_point q[4], int rotation, int mirrored,
                       actag_point corners[4])
{
    int i, r = rotation;
    for (i = 0; i < 4; i++)
        corners[i] = mirrored ? q[(r - i + 4) & 3] : q[(i - r + 4) & 3];
}
