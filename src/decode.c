/* Decode stage: quad -> homography -> sampled data ring -> family match. */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/decode.h"

#include <math.h>
#include <string.h>

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
    if (quad == NULL || H == NULL)
        return ACTAG_ERR_NULL;
    if (!bits_ok(bits))
        return ACTAG_ERR_PARAM;
    if (quad_orientation(quad) == 0)
        return ACTAG_ERR_PARAM;
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
    if (quad == NULL || H == NULL)
        return ACTAG_ERR_NULL;
    if (!bits_ok(bits))
        return ACTAG_ERR_PARAM;
    if (quad_orientation(quad) == 0)
        return ACTAG_ERR_PARAM;
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

/* The grid -> image map of the chosen model. */
static int tag_map(const actag_point quad[4], int bits, int model, float H[9])
{
    if (model == ACTAG_DECODE_AFFINE)
        return actag_tag_affine(quad, bits, H);
    if (model == ACTAG_DECODE_PROJECTIVE)
        return actag_tag_homography(quad, bits, H);
    return ACTAG_ERR_PARAM;
}

/* Cell (cx, cy) of data bit i (sequence position, 0 = MSB). */
static void bit_cell(int i, int k, int *cx, int *cy)
{
    int side = i / k, j = i % k;
    switch (side) {
    case 0: *cx = j; *cy = 0; break;
    case 1: *cx = k; *cy = j; break;
    case 2: *cx = k - j; *cy = k; break;
    default: *cx = 0; *cy = k - j; break;
    }
}

int actag_decode_bit_positions(const actag_point quad[4], int bits, actag_point *out)
{
    float H[9];
    int i, cx, cy, rc;
    if (quad == NULL || out == NULL)
        return ACTAG_ERR_NULL;
    rc = tag_map(quad, bits, ACTAG_DECODE_DEFAULT_MODEL, H);
    if (rc != ACTAG_OK)
        return rc;
    for (i = 0; i < bits; i++) {
        bit_cell(i, bits / 4, &cx, &cy);
        actag_homography_apply(H, (float)cx + 0.5f, (float)cy + 0.5f, &out[i]);
    }
    return ACTAG_OK;
}

typedef struct sampler {
    const uint8_t *img;
    int rows, cols, stride;
    float H[9];
} sampler;

/* Nearest pixel of grid point (u,v); outside the image counts as black. */
static int sample_px(const sampler *s, float u, float v)
{
    actag_point p;
    int r, c;
    actag_homography_apply(s->H, u, v, &p);
    if (!(p.x >= -0.5f && p.x < (float)s->cols - 0.5f && p.y >= -0.5f &&
          p.y < (float)s->rows - 0.5f))
        return 0;
    c = (int)(p.x + 0.5f); /* >= 0 here, so truncation is floor */
    r = (int)(p.y + 0.5f);
    if (c >= s->cols) /* float rounding just below the edge */
        c = s->cols - 1;
    if (r >= s->rows)
        r = s->rows - 1;
    return s->img[(size_t)r * (size_t)s->stride + (size_t)c] != 0;
}

/* White votes (0..9) of cell (cx, cy) over the 3x3 sample pattern. */
static int cell_votes(const sampler *s, int cx, int cy)
{
    int a, b, n = 0;
    for (b = -1; b <= 1; b++)
        for (a = -1; a <= 1; a++)
            n += sample_px(s, (float)cx + 0.5f + (float)a * ACTAG_DECODE_SAMPLE_OFFSET,
                           (float)cy + 0.5f + (float)b * ACTAG_DECODE_SAMPLE_OFFSET);
    return n;
}

static uint32_t read_word(const sampler *s, int bits)
{
    uint32_t w = 0;
    int i, cx, cy;
    for (i = 0; i < bits; i++) {
        bit_cell(i, bits / 4, &cx, &cy);
        w = (w << 1) | (cell_votes(s, cx, cy) >= 5 ? 1u : 0u);
    }
    return w;
}

static int check_image(const uint8_t *binary, int rows, int cols, int stride)
{
    if (binary == NULL)
        return ACTAG_ERR_NULL;
    if (rows < 1 || cols < 1 || rows > ACTAG_MAX_DIM || cols > ACTAG_MAX_DIM || stride < cols)
        return ACTAG_ERR_SIZE;
    return ACTAG_OK;
}

int actag_decode_read_word(const uint8_t *binary, int rows, int cols, int stride,
                           const actag_point quad[4], int bits, int model, uint32_t *word)
{
    sampler s;
    int rc;
    if (binary == NULL || quad == NULL || word == NULL)
        return ACTAG_ERR_NULL;
    rc = check_image(binary, rows, cols, stride);
    if (rc != ACTAG_OK)
        return rc;
    rc = tag_map(quad, bits, model, s.H);
    if (rc != ACTAG_OK)
        return rc;
    s.img = binary;
    s.rows = rows;
    s.cols = cols;
    s.stride = stride;
    *word = read_word(&s, bits);
    return ACTAG_OK;
}

uint32_t actag_decode_mirror(uint32_t word, int bits)
{
    /* Sequence position s <- (-s) mod n: position 0 (the MSB) stays, the
     * remaining n-1 positions are reversed. */
    uint32_t msb, r = 0;
    int i;
    if (bits < 2 || bits > 32)
        return word;
    msb = (uint32_t)1u << (bits - 1);
    for (i = 0; i < bits - 1; i++)
        if (word & ((uint32_t)1u << i))
            r |= (uint32_t)1u << (bits - 2 - i);
    return r | (word & msb);
}

/* actag_family_match_rotations() counting only the bits in keep (a set of
 * sequence positions closed under rotation and reflection, e.g. all but
 * the four corner cells). */
static int match_rot_masked(const actag_family *family, uint32_t observed, uint32_t keep,
                            int max_corrections, actag_match *out)
{
    uint32_t obs[4];
    int o, i, best = 33;
    if (keep == actag_code_mask(family->bits))
        return actag_family_match_rotations(family, observed, max_corrections, out);
    obs[0] = observed & actag_code_mask(family->bits);
    for (o = 1; o < 4; o++) /* obs[o] = rot^-o(observed) = rot^(4-o) */
        obs[o] = actag_code_rot90(actag_code_rot90(actag_code_rot90(obs[o - 1], family->bits),
                                                   family->bits),
                                  family->bits);
    for (i = 0; i < family->ncodes; i++) {
        uint32_t c = family->codes[i];
        for (o = 0; o < 4; o++) {
            int d = actag_popcount32((c ^ obs[o]) & keep);
            if (d < best) {
                best = d;
                out->id = i;
                out->rotation = o;
                out->mirrored = 0;
                out->hamming = d;
            }
        }
        if (best == 0)
            break;
    }
    return best > max_corrections ? ACTAG_ERR_NO_MATCH : ACTAG_OK;
}

/* Matches the word read clockwise on screen (unmirrored) and its reflection
 * P (mirrored) up to the family limit, so the margin between them is known;
 * the caller's limit applies to the better one. Returns ACTAG_OK,
 * ACTAG_ERR_NO_MATCH, or the matcher's error. */
static int match_both(const actag_family *family, uint32_t w, uint32_t keep, int maxc,
                      int max_corrections, actag_match *mu, int *du, actag_match *mm, int *dm)
{
    int rcu = match_rot_masked(family, w, keep, maxc, mu);
    int rcm = match_rot_masked(family, actag_decode_mirror(w, family->bits), keep, maxc, mm);
    if (rcu != ACTAG_OK && rcu != ACTAG_ERR_NO_MATCH)
        return rcu;
    if (rcm != ACTAG_OK && rcm != ACTAG_ERR_NO_MATCH)
        return rcm;
    *du = rcu == ACTAG_OK ? mu->hamming : maxc + 1;
    *dm = rcm == ACTAG_OK ? mm->hamming : maxc + 1;
    return (*du > max_corrections && *dm > max_corrections) ? ACTAG_ERR_NO_MATCH : ACTAG_OK;
}

/* Picks the handedness with fewer corrected bits (unmirrored on a tie) and
 * fills id, hamming, mirrored, rotation, mirror_margin and the corners in
 * tag order from the clockwise-on-screen quad q:
 *   unmirrored, observed == rot^r(code): screen cell s shows code cell
 *     s + rk, so q[n] is printed corner n + r;
 *   mirrored, P(observed) == rot^r(code): screen cell s shows code cell
 *     rk - s, so q[n] is printed corner r - n. */
static void set_orientation(actag_decode_result *out, const actag_point q[4],
                            const actag_match *mu, int du, const actag_match *mm, int dm)
{
    int i, mirrored = dm < du;
    const actag_match *m = mirrored ? mm : mu;
    int r = m->rotation;
    out->id = m->id;
    out->hamming = mirrored ? dm : du;
    out->mirrored = mirrored;
    out->rotation = r;
    out->mirror_margin = mirrored ? du - dm : dm - du;
    for (i = 0; i < 4; i++)
        out->corners[i] = mirrored ? q[(r - i + 4) & 3] : q[(i - r + 4) & 3];
}

/* set_orientation() with the handedness given (the ML decoder's choice);
 * mirror_margin = the other handedness' distance minus this one's (it may
 * be negative when likelihood prefers the reading with more flipped bits). */
static void set_orientation_as(actag_decode_result *out, const actag_point q[4],
                               const actag_match *m, int mirrored, int dm, int du)
{
    int i, r = m->rotation;
    out->id = m->id;
    out->hamming = m->hamming;
    out->mirrored = mirrored;
    out->rotation = r;
    out->mirror_margin = mirrored ? du - dm : dm - du;
    for (i = 0; i < 4; i++)
        out->corners[i] = mirrored ? q[(r - i + 4) & 3] : q[(i - r + 4) & 3];
}

int actag_decode_quad(const uint8_t *binary, int rows, int cols, int stride,
                      const actag_point quad[4], const actag_family *family,
                      int max_corrections, actag_decode_result *out)
{
    return actag_decode_quad_ex(binary, rows, cols, stride, quad, family, max_corrections,
                                ACTAG_DECODE_DEFAULT_MODEL, out);
}

int actag_decode_quad_ex(const uint8_t *binary, int rows, int cols, int stride,
                         const actag_point quad[4], const actag_family *family,
                         int max_corrections, int model, actag_decode_result *out)
{
    sampler s;
    actag_point q[4];
    actag_match mu, mm;
    uint32_t w;
    int rc, maxc, bits, k, du, dm, i, orient, cx, cy;
    int ring_n = 0, ring_black = 0, in_n = 0, in_white = 0;
    if (binary == NULL || quad == NULL || family == NULL || out == NULL)
        return ACTAG_ERR_NULL;
    rc = check_image(binary, rows, cols, stride);
    if (rc != ACTAG_OK)
        return rc;
    rc = actag_family_validate(family);
    if (rc != ACTAG_OK)
        return rc;
    maxc = actag_family_max_corrections(family);
    if (max_corrections < 0 || max_corrections > maxc)
        return ACTAG_ERR_CORRECTIONS;
    bits = family->bits;
    k = bits / 4;

    /* Clockwise on screen, quad[0] first, so that "mirrored" means mirrored
     * on screen whatever order the quad stage used. */
    orient = quad_orientation(quad);
    if (orient == 0)
        return ACTAG_ERR_PARAM;
    q[0] = quad[0];
    for (i = 1; i < 4; i++)
        q[i] = quad[orient > 0 ? i : 4 - i];
    rc = tag_map(q, bits, model, s.H);
    if (rc != ACTAG_OK)
        return rc;
    s.img = binary;
    s.rows = rows;
    s.cols = cols;
    s.stride = stride;

    w = read_word(&s, bits);
    /* Structure statistics (informative): black ring at distance 1, white
     * square inside. */
    for (cy = 1; cy < k; cy++) {
        for (cx = 1; cx < k; cx++) {
            int v = cell_votes(&s, cx, cy);
            if (cx == 1 || cy == 1 || cx == k - 1 || cy == k - 1) {
                ring_n += 9;
                ring_black += 9 - v;
            } else {
                in_n += 9;
                in_white += v;
            }
        }
    }

    rc = match_both(family, w, actag_code_mask(bits), maxc, max_corrections, &mu, &du, &mm, &dm);
    if (rc != ACTAG_OK)
        return rc;

    out->observed = w;
    out->contrast = 0.0f;
    out->flip_weight = 0.0f;
    out->min_confidence = 0.0f;
    out->ring_black = ring_n ? (float)ring_black / (float)ring_n : 1.0f;
    out->interior_white = in_n ? (float)in_white / (float)in_n : 1.0f;
    set_orientation(out, q, &mu, du, &mm, dm);
    out->decision_margin = (float)out->mirror_margin; /* the hard decoder: other handedness */
    return ACTAG_OK;
}

/* ------------------------------------------------------------------------
 * Grid-fitting soft decoder (actag_decode_quad_fit). */

/* The affine tag grid: image point of grid point (u, v) is
 * m + a (u - g) + b (v - g), g the grid centre. */
typedef struct fgrid {
    float mx, my, ax, ay, bx, by;
} fgrid;

typedef struct fimg {
    const uint8_t *img;
    int rows, cols, stride;
    float so; /* sample offset, cells */
    int fast; /* 1: 5 samples per cell instead of 9 */
} fimg;

/* Bilinear grey level at (x, y), pixel centres on integers; edge pixels
 * are replicated outside the image. Only + - * decide it. */
static float fsample(const fimg *im, float x, float y)
{
    int x0, y0, x1, y1;
    float fx, fy, v00, v01, v10, v11;
    const uint8_t *r0, *r1;
    if (!(x >= 0.0f))
        x = 0.0f;
    if (!(y >= 0.0f))
        y = 0.0f;
    if (x > (float)(im->cols - 1))
        x = (float)(im->cols - 1);
    if (y > (float)(im->rows - 1))
        y = (float)(im->rows - 1);
    x0 = (int)x;
    y0 = (int)y;
    fx = x - (float)x0;
    fy = y - (float)y0;
    x1 = x0 + 1 < im->cols ? x0 + 1 : x0;
    y1 = y0 + 1 < im->rows ? y0 + 1 : y0;
    r0 = im->img + (size_t)y0 * (size_t)im->stride;
    r1 = im->img + (size_t)y1 * (size_t)im->stride;
    v00 = (float)r0[x0];
    v01 = (float)r0[x1];
    v10 = (float)r1[x0];
    v11 = (float)r1[x1];
    v00 += (v01 - v00) * fx;
    v10 += (v11 - v10) * fx;
    return v00 + (v10 - v00) * fy;
}

/* Mean grey level of every cell of the (k+1)^2 grid over a 3x3 sample
 * pattern (+-ACTAG_DECODE_SAMPLE_OFFSET cell), m[cy * (k+1) + cx]. */
static void fcells(const fimg *im, const fgrid *gr, int k, float *m)
{
    int cx, cy, a, b, n = k + 1;
    float g = 0.5f * (float)n;
    for (cy = 0; cy < n; cy++)
        for (cx = 0; cx < n; cx++) {
            float s = 0.0f, u0 = (float)cx + 0.5f - g, v0 = (float)cy + 0.5f - g;
            float x0 = gr->mx + gr->ax * u0 + gr->bx * v0;
            float y0 = gr->my + gr->ay * u0 + gr->by * v0;
            if (im->fast) {
                /* centre and the 4 diagonal points */
                float dx1 = im->so * (gr->ax + gr->bx), dy1 = im->so * (gr->ay + gr->by);
                float dx2 = im->so * (gr->ax - gr->bx), dy2 = im->so * (gr->ay - gr->by);
                s = fsample(im, x0, y0) + fsample(im, x0 + dx1, y0 + dy1) +
                    fsample(im, x0 - dx1, y0 - dy1) + fsample(im, x0 + dx2, y0 + dy2) +
                    fsample(im, x0 - dx2, y0 - dy2);
                m[cy * n + cx] = s * 0.2f;
                continue;
            }
            for (b = -1; b <= 1; b++) {
                float v = (float)b * im->so;
                for (a = -1; a <= 1; a++) {
                    float u = (float)a * im->so;
                    s += fsample(im, x0 + gr->ax * u + gr->bx * v, y0 + gr->ay * u + gr->by * v);
                }
            }
            m[cy * n + cx] = s * (1.0f / 9.0f);
        }
}

static int is_ring(int cx, int cy, int k)
{
    return (cx == 1 || cy == 1 || cx == k - 1 || cy == k - 1) && cx >= 1 && cy >= 1 &&
           cx <= k - 1 && cy <= k - 1;
}

/* Black ring mean and white interior mean of the cell means. */
static void flevels(const float *m, int k, float *black, float *white)
{
    int cx, cy, n = k + 1, nr = 0, ni = 0;
    float sr = 0.0f, si = 0.0f;
    for (cy = 1; cy < k; cy++)
        for (cx = 1; cx < k; cx++) {
            if (is_ring(cx, cy, k)) {
                sr += m[cy * n + cx];
                nr++;
            } else {
                si += m[cy * n + cx];
                ni++;
            }
        }
    *black = sr / (float)nr;
    *white = si / (float)ni;
}

#define FIT_INITS 5
/* grids the ACTAG_FIT_WIDE search compares: 5 starts x (25 + 8) shifts */
#define FIT_WIDE_GRIDS (FIT_INITS * 33)
#ifndef ACTAG_FIT_MARGIN
#define ACTAG_FIT_MARGIN 1
#endif
#ifndef FIT_STEEPEST
#define FIT_STEEPEST 0
#endif
#ifndef FIT_MAX_STEPS
#define FIT_MAX_STEPS 4
#endif
#ifndef FIT_FAST_ASCENT
#define FIT_FAST_ASCENT 0
#endif
#ifndef FIT_FAST_SHIFT
#define FIT_FAST_SHIFT 1
#endif
#ifndef ACTAG_FIT_RING_LEVEL
#define ACTAG_FIT_RING_LEVEL 0.5f
#endif
#ifndef ACTAG_FIT_INTERIOR_LEVEL
#define ACTAG_FIT_INTERIOR_LEVEL 0.5f
#endif
#ifndef ACTAG_FIT_DATA_LEVEL
#define ACTAG_FIT_DATA_LEVEL 0.5f
#endif

/* Code-agnostic crispness of a grid: black ring cells below, interior
 * cells above the mid level, data cells far from it (either side, capped
 * at half the contrast so bright clutter cannot pull the grid). */
static float fscore(const fimg *im, const fgrid *gr, int k, float *m)
{
    int cx, cy, n = k + 1;
    float black, white, t, half, s = 0.0f;
    fcells(im, gr, k, m);
    flevels(m, k, &black, &white);
    t = black + ACTAG_FIT_DATA_LEVEL * (white - black);
    half = ACTAG_FIT_DATA_LEVEL * (white - black);
    for (cy = 0; cy < n; cy++)
        for (cx = 0; cx < n; cx++) {
            float v = m[cy * n + cx] - t;
            if (cx == 0 || cy == 0 || cx == k || cy == k) {
                v = v < 0.0f ? -v : v;
                s += v < half ? v : half;
            }
        }
    return s + (white - black) * (float)((k - 1) * (k - 1));
}

/* Coarse translation search (+-1 cell, quarter-cell steps) by fscore. */
static void fshift(const fimg *im, fgrid *gr, int k, float *m)
{
    /* Starting grids: as given, rotated by +-30 degrees, and sheared
     * (sonar images show tags as parallelograms) by b += +-a (lb / la);
     * each on a quarter-cell lattice of shifts within +-1 cell. */
    static const float rc[FIT_INITS] = {1.0f, 0.8660254f, 0.8660254f, 1.0f, 1.0f};
    static const float rs[FIT_INITS] = {0.0f, 0.5f, -0.5f, 0.0f, 0.0f};
    static const float hb[FIT_INITS] = {0.0f, 0.0f, 0.0f, 1.0f, -1.0f};
    fgrid g0 = *gr, t;
    float best = -1e30f;
    float la = actag_sqrtf(g0.ax * g0.ax + g0.ay * g0.ay), lb = actag_sqrtf(g0.bx * g0.bx + g0.by * g0.by);
    float q = la > 0.0f ? lb / la : 1.0f;
    int i, j, o;
    for (o = 0; o < FIT_INITS; o++) {
        fgrid gro = g0;
        gro.ax = rc[o] * g0.ax + rs[o] * g0.bx / q;
        gro.ay = rc[o] * g0.ay + rs[o] * g0.by / q;
        gro.bx = -rs[o] * g0.ax * q + rc[o] * g0.bx + hb[o] * q * g0.ax;
        gro.by = -rs[o] * g0.ay * q + rc[o] * g0.by + hb[o] * q * g0.ay;
        /* half-cell lattice within +-1 cell, then the quarter-cell
         * neighbours of the best point */
        {
            fgrid bo = gro;
            float bs = -1e30f;
            for (j = -2; j <= 2; j++)
                for (i = -2; i <= 2; i++) {
                    float sc;
                    t = gro;
                    t.mx += 0.5f * ((float)i * g0.ax + (float)j * g0.bx);
                    t.my += 0.5f * ((float)i * g0.ay + (float)j * g0.by);
                    sc = fscore(im, &t, k, m);
                    if (sc > bs) {
                        bs = sc;
                        bo = t;
                    }
                }
            for (j = -1; j <= 1; j++)
                for (i = -1; i <= 1; i++) {
                    float sc;
                    if (i == 0 && j == 0)
                        continue;
                    t = bo;
                    t.mx += 0.25f * ((float)i * g0.ax + (float)j * g0.bx);
                    t.my += 0.25f * ((float)i * g0.ay + (float)j * g0.by);
                    sc = fscore(im, &t, k, m);
                    if (sc > bs) {
                        bs = sc;
                        bo = t;
                    }
                }
            if (bs > best) {
                best = bs;
                *gr = bo;
            }
        }
    }
}

/* Ascent of fscore over the 6 affine parameters, 3 step sizes. Default:
 * Gauss-Seidel sweeps (each parameter moves as soon as a move improves);
 * FIT_STEEPEST=1 takes the best of all 12 moves per step instead (order
 * independent, but measured worse on the pool frames: 36-38 vs 37-39 of
 * 47 over flips and seeds). */
static float tscore(const fimg *im, const fgrid *gr, int k, float *m, const uint8_t *L,
                    int erase);

static float objective(const fimg *im, const fgrid *gr, int k, float *m, const uint8_t *L,
                       int erase)
{
    return L ? tscore(im, gr, k, m, L, erase) : fscore(im, gr, k, m);
}

#ifndef FIT_T_STEPS
#define FIT_T_STEPS 2 /* template polish: steps per step size */
#endif
#ifndef FIT_T_SHIFT2
#define FIT_T_SHIFT2 0.0625f /* template polish: squared shift bound, cells^2 */
#endif
#ifndef FIT_T_HI
#define FIT_T_HI 1.3225f /* (1.15)^2 */
#endif
#ifndef FIT_T_LO
#define FIT_T_LO 0.7225f /* (0.85)^2 */
#endif
static void ffit(const fimg *im, fgrid *gr, int k, float *m, const uint8_t *L, int erase,
                 int tight)
{
    static const float scales[3] = {1.0f, 0.5f, 0.25f};
    fgrid g0 = *gr;
    float la = actag_sqrtf(gr->ax * gr->ax + gr->ay * gr->ay);
    float lb = actag_sqrtf(gr->bx * gr->bx + gr->by * gr->by);
    float best = objective(im, gr, k, m, L, erase);
    int lvl, it, p, sgn;
    for (lvl = tight ? 1 : 0; lvl < 3; lvl++) { /* a polish starts at half steps */
        for (it = 0; it < (tight ? FIT_T_STEPS : FIT_MAX_STEPS); it++) {
            fgrid bt = *gr;
            float bs = best;
            for (p = 0; p < 6; p++)
                for (sgn = -1; sgn <= 1; sgn += 2) {
                    fgrid t = *gr;
                    float d, s;
                    float *f = p == 0 ? &t.mx : p == 1 ? &t.my : p == 2 ? &t.ax
                             : p == 3 ? &t.ay : p == 4 ? &t.bx : &t.by;
                    d = (p < 2 ? 0.15f * (la < lb ? la : lb) : 0.05f * (p < 4 ? la : lb)) *
                        scales[lvl] * (float)sgn;
                    *f += d;
                    /* stay within half a cell and +-35 % of the starting grid
                     * (a template polish: a quarter cell and +-15 %) */
                    if ((t.mx - g0.mx) * (t.mx - g0.mx) + (t.my - g0.my) * (t.my - g0.my) >
                            (tight ? FIT_T_SHIFT2 : 0.25f) * la * lb ||
                        t.ax * t.ax + t.ay * t.ay > (tight ? FIT_T_HI : 1.8f) * la * la ||
                        t.ax * t.ax + t.ay * t.ay < (tight ? FIT_T_LO : 0.42f) * la * la ||
                        t.bx * t.bx + t.by * t.by > (tight ? FIT_T_HI : 1.8f) * lb * lb ||
                        t.bx * t.bx + t.by * t.by < (tight ? FIT_T_LO : 0.42f) * lb * lb)
                        continue;
                    s = objective(im, &t, k, m, L, erase);
                    if (s > bs) {
                        bs = s;
                        bt = t;
#if !FIT_STEEPEST
                        *gr = bt; /* Gauss-Seidel sweep: move at once */
                        break;
#endif
                    }
                }
            if (!(bs > best))
                break;
            best = bs;
            *gr = bt;
        }
    }
}

/* Data cell i's reference cells: the black-ring cell next to it (towards the
 * tag centre; the ring corner for the data ring's corners) and the interior
 * cell next to that one. */
static void fref_cells(int i, int k, int *rx, int *ry, int *wx, int *wy)
{
    int cx, cy;
    bit_cell(i, k, &cx, &cy);
    *rx = cx < 1 ? 1 : cx > k - 1 ? k - 1 : cx;
    *ry = cy < 1 ? 1 : cy > k - 1 ? k - 1 : cy;
    *wx = *rx < 2 ? 2 : *rx > k - 2 ? k - 2 : *rx;
    *wy = *ry < 2 ? 2 : *ry > k - 2 ? k - 2 : *ry;
}


/* Soft maximum-likelihood matching (the fit decoder's matcher).
 * Every code in each of the 8 physical views (rotations, and reflections P
 * of the reading) is scored by its soft distance to the reading: the sum of
 * |c_i| over the bits where the code disagrees with the sign of the bit's
 * confidence c_i (clamped to 1 = the tag's black-to-white contrast).
 * Under independent Gaussian cell noise this ranks codes by likelihood, and
 * the soft distance of the runner-up minus the best's is twice the log
 * likelihood ratio between them in units of contrast^2 / sigma^2: the
 * decision margin. Confidences are quantised to 1/16 so that a distance is
 * five masked popcounts; candidates whose hard distance alone bounds their
 * soft distance above the runner-up's are skipped (exact pruning). */
#define ML_Q 16
#define ML_TOP 6 /* readings kept for the template check (4 let a wrong handedness
                          through on a simulated view read from a contour guess) */
#ifndef ACTAG_FIT_MIN_NOISE
#define ACTAG_FIT_MIN_NOISE 0.05f /* floor of the cell noise estimate, confidence units */
#endif
typedef struct {
    actag_match best; /* ML best: id, rotation, mirrored, hamming (hard, kept bits) */
    int d1, d2;       /* soft distances of the best and the runner-up, 1/ML_Q units */
    int other;        /* best hard distance of the other handedness */
    int h2;           /* best hard distance of any other reading */
    struct {
        int d, h, id, view; /* view: rotation + 4 * mirrored */
    } top[ML_TOP];    /* the ML_TOP most likely readings, best first */
    int ntop;
} ml_result;

static uint32_t rot_inv(uint32_t w, int o, int bits) /* rot^-o(w) */
{
    int s;
    for (s = 0; s < (4 - o) % 4; s++)
        w = actag_code_rot90(w, bits);
    return w;
}

static void ml_match(const actag_family *family, const float *conf, uint32_t keep, ml_result *res)
{
    int bits = family->bits, i, b, v, nk = 0, q[32], lb[33];
    uint32_t w = 0, plane[5] = {0, 0, 0, 0, 0}, obs[8], pl[8][5];
    res->d1 = res->d2 = 1 << 28;
    res->other = 33;
    res->best.id = res->best.rotation = res->best.mirrored = 0;
    res->best.hamming = 33;
    for (i = 0; i < bits; i++) {
        float a = conf[i] < 0.0f ? -conf[i] : conf[i];
        int qi = a >= 1.0f ? ML_Q : (int)(a * (float)ML_Q + 0.5f);
        uint32_t bit = (uint32_t)1u << (bits - 1 - i);
        if (conf[i] > 0.0f)
            w |= bit;
        for (b = 0; b < 5; b++)
            if (qi & (1 << b))
                plane[b] |= bit;
        if (keep & bit)
            q[nk++] = qi;
    }
    /* lb[h]: the least soft distance of h disagreeing kept bits */
    for (i = 1; i < nk; i++) {
        int j, t = q[i];
        for (j = i; j > 0 && q[j - 1] > t; j--)
            q[j] = q[j - 1];
        q[j] = t;
    }
    lb[0] = 0;
    for (i = 0; i < nk; i++)
        lb[i + 1] = lb[i] + q[i];
    for (v = 0; v < 8; v++) {
        int o = v & 3, m = v >> 2;
        obs[v] = rot_inv(m ? actag_decode_mirror(w, bits) : w, o, bits);
        for (b = 0; b < 5; b++)
            pl[v][b] = rot_inv(m ? actag_decode_mirror(plane[b], bits) : plane[b], o, bits);
    }
    res->ntop = 0;
    for (i = 0; i < family->ncodes; i++) {
        uint32_t c = family->codes[i];
        for (v = 0; v < 8; v++) {
            uint32_t mis = (c ^ obs[v]) & keep;
            int h = actag_popcount32(mis), d, j;
            /* prune: cannot enter the kept list (or beat the runner-up) */
            if (lb[h] >= res->d2 && (res->ntop == ML_TOP || lb[h] >= res->top[res->ntop - 1].d))
                continue;
            d = 0;
            for (b = 0; b < 5; b++)
                d += actag_popcount32(mis & pl[v][b]) << b;
            /* insert into the sorted list of the ML_TOP best readings */
            if (res->ntop < ML_TOP) {
                j = res->ntop++;
            } else {
                j = ML_TOP - 1;
                if (!(d < res->top[j].d || (d == res->top[j].d && h < res->top[j].h)))
                    continue;
            }
            while (j > 0 && (d < res->top[j - 1].d || (d == res->top[j - 1].d && h < res->top[j - 1].h))) {
                res->top[j] = res->top[j - 1];
                j--;
            }
            res->top[j].d = d;
            res->top[j].h = h;
            res->top[j].id = i;
            res->top[j].view = v;
            res->d1 = res->top[0].d;
            res->d2 = res->ntop > 1 ? res->top[1].d : 1 << 28;
        }
    }
    if (res->ntop > 0) {
        res->best.id = res->top[0].id;
        res->best.rotation = res->top[0].view & 3;
        res->best.mirrored = res->top[0].view >> 2;
        res->best.hamming = res->top[0].h;
    }
    /* hard distances: the other handedness' best (mirror_margin) and the
     * best of every reading but the chosen one (the bit margin) */
    res->h2 = 33;
    for (i = 0; i < family->ncodes; i++) {
        uint32_t c = family->codes[i];
        for (v = 0; v < 8; v++) {
            int h = actag_popcount32((c ^ obs[v]) & keep);
            if ((v >> 2) != res->best.mirrored && h < res->other)
                res->other = h;
            if (h < res->h2 && !(i == res->best.id && (v & 3) == res->best.rotation &&
                                 (v >> 2) == res->best.mirrored))
                res->h2 = h;
        }
    }
}

/* Template check (ACTAG_FIT_VERIFY). Each of the most likely readings is
 * a full hypothesis for all (k+1)^2 cells (data ring from its code, black
 * ring, white interior); its grid is refitted to that template and scored
 * by the residual of a two-level least-squares fit of the cell means
 * (rss). Every hypothesis thus gets its own best alignment, so a reading
 * that only a misaligned grid supports loses to the right one; the margin
 * is the log-likelihood ratio of the best against the next hypothesis
 * under Gaussian cell noise estimated from the best one's residual. */
static int is_data_corner(int cx, int cy, int k)
{
    return (cx == 0 || cx == k) && (cy == 0 || cy == k);
}

static void layout_of(const actag_family *family, int id, int view, int k, uint8_t *L)
{
    int bits = 4 * k, n = k + 1, i, cx, cy;
    uint32_t e = family->codes[id];
    for (i = 0; i < (view & 3); i++)
        e = actag_code_rot90(e, bits);
    if (view >> 2)
        e = actag_decode_mirror(e, bits);
    for (cy = 0; cy < n; cy++)
        for (cx = 0; cx < n; cx++)
            L[cy * n + cx] = (uint8_t)(cx >= 2 && cy >= 2 && cx <= k - 2 && cy <= k - 2);
    for (i = 0; i < bits; i++) {
        bit_cell(i, k, &cx, &cy);
        L[cy * n + cx] = (uint8_t)((e >> (bits - 1 - i)) & 1u);
    }
}

/* Residual of the cell means against a layout after a two-level (black,
 * white) least-squares fit. */
static float template_rss(const float *m, const uint8_t *L, int k, int erase, int *ncells)
{
    int n = k + 1, cx, cy, nw = 0, nb = 0;
    float sw = 0.0f, sb = 0.0f, ss = 0.0f;
    for (cy = 0; cy < n; cy++)
        for (cx = 0; cx < n; cx++) {
            float v = m[cy * n + cx];
            if (erase && is_data_corner(cx, cy, k))
                continue;
            ss += v * v;
            if (L[cy * n + cx]) {
                sw += v;
                nw++;
            } else {
                sb += v;
                nb++;
            }
        }
    if (ncells)
        *ncells = nw + nb;
    return ss - (nw ? sw * sw / (float)nw : 0.0f) - (nb ? sb * sb / (float)nb : 0.0f);
}

static float tscore(const fimg *im, const fgrid *gr, int k, float *m, const uint8_t *L,
                    int erase)
{
    fcells(im, gr, k, m);
    return -template_rss(m, L, k, erase, NULL);
}

void actag_fit_params_default(actag_fit_params *fp)
{
    if (fp == NULL)
        return;
    fp->flags = ACTAG_FIT_DEFAULT_FLAGS;
    fp->level = 0.5f;
    fp->min_contrast = 5;
    fp->sample_offset = 0.2f;
    fp->min_margin = ACTAG_FIT_MIN_MARGIN;
    fp->min_bit_margin = ACTAG_FIT_MIN_BIT_MARGIN;
}

int actag_decode_quad_fit(const uint8_t *grey, int rows, int cols, int stride,
                          const actag_point quad[4], const actag_family *family,
                          int max_corrections, const actag_fit_params *fp,
                          actag_decode_result *out)
{
    int flags, min_contrast;
    float level;
    fimg im;
    fgrid gr, g_quad;
    float H[9], m[(ACTAG_DECODE_MAX_K + 1) * (ACTAG_DECODE_MAX_K + 1)];
    float conf[32], black, white, contrast, flips = 0.0f, minc = 1e30f;
    actag_point q[4];
    actag_match mu, mm;
    ml_result ml;
    float margin = 0.0f, noise2 = 0.0f;
    int nknown = 0;
    memset(&ml, 0, sizeof ml);
    uint32_t w = 0, e, diff, keep;
    int rc, maxc, bits, k, n, du, dm, i, orient, ring_ok = 0, in_ok = 0, cx, cy;
    int regrid = 0; /* 1: reading the quad's own grid after the fitted one read nothing */
    if (grey == NULL || quad == NULL || family == NULL || fp == NULL || out == NULL)
        return ACTAG_ERR_NULL;
    rc = check_image(grey, rows, cols, stride);
    if (rc != ACTAG_OK)
        return rc;
    rc = actag_family_validate(family);
    if (rc != ACTAG_OK)
        return rc;
    flags = fp->flags;
    min_contrast = fp->min_contrast;
    level = fp->level;
    if (actag_fit_params_validate(fp, NULL) != ACTAG_OK)
        return ACTAG_ERR_PARAM;
    maxc = actag_family_max_corrections(family);
    if (max_corrections < 0 || max_corrections > maxc)
        return ACTAG_ERR_CORRECTIONS;
    bits = family->bits;
    k = bits / 4;
    n = k + 1;
    keep = actag_code_mask(bits);
    if (flags & ACTAG_FIT_ERASE_CORNERS)
        for (i = 0; i < 4; i++) /* sequence positions 0, k, 2k, 3k */
            keep &= ~((uint32_t)1u << (bits - 1 - i * k));
    orient = quad_orientation(quad);
    if (orient == 0)
        return ACTAG_ERR_PARAM;
    q[0] = quad[0];
    for (i = 1; i < 4; i++)
        q[i] = quad[orient > 0 ? i : 4 - i];
    rc = actag_tag_affine(q, bits, H);
    if (rc != ACTAG_OK)
        return rc;
    im.img = grey;
    im.rows = rows;
    im.cols = cols;
    im.stride = stride;
    im.so = fp->sample_offset;
    im.fast = 0;
    gr.ax = H[0];
    gr.bx = H[1];
    gr.ay = H[3];
    gr.by = H[4];
    gr.mx = H[2] + (H[0] + H[1]) * 0.5f * (float)n;
    gr.my = H[5] + (H[3] + H[4]) * 0.5f * (float)n;
    g_quad = gr; /* the quad's own grid: the template check's second start */
    if (flags & ACTAG_FIT_WIDE) {
        im.fast = FIT_FAST_SHIFT;
        fshift(&im, &gr, k, m);
        im.fast = 0;
    }
    if (!(flags & ACTAG_FIT_NO_SEARCH)) {
        im.fast = FIT_FAST_ASCENT;
        ffit(&im, &gr, k, m, NULL, 0, 0);
        im.fast = 0;
    }
reread:
    fcells(&im, &gr, k, m); /* the reading itself: all 9 samples per cell */
    /* The whole grid must lie in the image: a tag cut by the frame edge
     * cannot be read (edge replication would invent its data cells). */
    {
        float ex = (gr.ax < 0.0f ? -gr.ax : gr.ax) + (gr.bx < 0.0f ? -gr.bx : gr.bx);
        float ey = (gr.ay < 0.0f ? -gr.ay : gr.ay) + (gr.by < 0.0f ? -gr.by : gr.by);
        float hw = 0.5f * (float)k; /* centre to the data cells' centres, cells */
        if (gr.mx - ex * hw < 0.0f || gr.mx + ex * hw > (float)(cols - 1) ||
            gr.my - ey * hw < 0.0f || gr.my + ey * hw > (float)(rows - 1))
            goto no_reading;
    }
    flevels(m, k, &black, &white);
    contrast = white - black;
    if (!(contrast >= (float)min_contrast) || !(contrast > 0.0f))
        goto no_reading;
    for (cy = 1; cy < k; cy++)
        for (cx = 1; cx < k; cx++) {
            float v = m[cy * n + cx], d;
            if (is_ring(cx, cy, k)) {
                ring_ok += v < black + ACTAG_FIT_RING_LEVEL * contrast;
                d = v - black;
            } else {
                in_ok += v > black + ACTAG_FIT_INTERIOR_LEVEL * contrast;
                d = v - white;
            }
            noise2 += d * d;
            nknown++;
        }
    /* cell noise in confidence units (a clean bit reads +-0.5), from the
     * cells whose value is known; floored so clean renders stay finite */
    noise2 = noise2 / ((float)nknown * contrast * contrast);
    if (noise2 < ACTAG_FIT_MIN_NOISE * ACTAG_FIT_MIN_NOISE)
        noise2 = ACTAG_FIT_MIN_NOISE * ACTAG_FIT_MIN_NOISE;
    for (i = 0; i < bits; i++) {
        float t, c;
        bit_cell(i, k, &cx, &cy);
        if (flags & ACTAG_FIT_LOCAL) {
            int rx, ry, wx, wy;
            fref_cells(i, k, &rx, &ry, &wx, &wy);
            t = 0.5f * (m[ry * n + rx] + m[wy * n + wx]);
        } else {
            t = black + level * contrast;
        }
        c = (m[cy * n + cx] - t) / contrast;
        conf[i] = c;
        w = (w << 1) | (c > 0.0f ? 1u : 0u);
        c = c < 0.0f ? -c : c;
        if (c < minc)
            minc = c;
    }

    {
        /* Thresholds: with ACTAG_FIT_SPLIT every split of the sorted data
         * confidences between ACTAG_FIT_SPLIT_LO and _HI (relative to the
         * mid level) is read; otherwise the single threshold 0. Each reading
         * is matched by likelihood (ml_match); the split whose best code
         * needs the fewest corrections wins (then the larger margin). */
        float sv[32], tbest = 0.0f;
        int j, a, nsplit = 0, have = 0;
        long key = -1;
        int kd = 99, od = 99; /* best distance of the kept key, of any other */
        if (flags & ACTAG_FIT_SPLIT) {
            for (i = 0; i < bits; i++)
                sv[i] = conf[i];
            for (i = 1; i < bits; i++)
                for (j = i; j > 0 && sv[j - 1] > sv[j]; j--) {
                    float t = sv[j];
                    sv[j] = sv[j - 1];
                    sv[j - 1] = t;
                }
            nsplit = bits;
        } else {
            nsplit = 1;
        }
        for (j = 0; j < nsplit; j++) {
            float t, ct[32];
            ml_result r;
            int dk;
            long key1;
            if (flags & ACTAG_FIT_SPLIT) {
                t = j == 0 ? sv[0] - 1.0f : 0.5f * (sv[j - 1] + sv[j]);
                if (t > ACTAG_FIT_SPLIT_HI - level)
                    break;
                if (t < ACTAG_FIT_SPLIT_LO - level)
                    continue;
            } else {
                t = 0.0f;
            }
            for (a = 0; a < bits; a++)
                ct[a] = conf[a] - t;
            ml_match(family, ct, keep, &r);
            dk = r.best.hamming;
            if (dk > max_corrections)
                continue;
            /* A tie between the two handednesses is no reading. */
            if (r.other == dk)
                goto no_reading;
            /* Splits that read as different tags (or poses): the threshold
             * decides the ID, so the reading is ambiguous unless one is
             * closer than every other by ACTAG_FIT_MARGIN bits. */
            key1 = (long)r.best.id * 8L + (long)r.best.mirrored * 4L + (long)r.best.rotation;
            if (key < 0 || key == key1) {
                if (key < 0 || dk < kd)
                    kd = dk;
                key = key1;
            } else if (dk < kd) {
                od = kd < od ? kd : od;
                kd = dk;
                key = key1;
            } else if (dk < od) {
                od = dk;
            }
            if (!have || dk < ml.best.hamming ||
                (dk == ml.best.hamming && r.d2 - r.d1 > ml.d2 - ml.d1)) {
                ml = r;
                tbest = t;
                have = 1;
            }
        }
        if (!have)
            goto no_reading;
        if (od < 99 && od - kd < ACTAG_FIT_MARGIN)
            goto no_reading;
        w = 0;
        for (i = 0; i < bits; i++) { /* confidences relative to the chosen threshold */
            conf[i] -= tbest;
            if (conf[i] == 0.0f)
                conf[i] = -0.01f;
            w = (w << 1) | (conf[i] > 0.0f ? 1u : 0u);
        }
        /* log-likelihood ratio best : runner-up under Gaussian cell noise */
        margin = (float)(ml.d2 - ml.d1) * (1.0f / (float)ML_Q) / noise2;
        if ((flags & ACTAG_FIT_VERIFY) && ml.ntop > 1) {
            uint8_t L[(ACTAG_DECODE_MAX_K + 1) * (ACTAG_DECODE_MAX_K + 1)];
            float mt[(ACTAG_DECODE_MAX_K + 1) * (ACTAG_DECODE_MAX_K + 1)];
            float rss0 = 0.0f, rss2 = 1e30f, s2, floor2;
            int jj, nc = 1, erase = (flags & ACTAG_FIT_ERASE_CORNERS) != 0;
            int cid[2 * ML_TOP], cview[2 * ML_TOP], ncand = 0;
            /* candidates: the likeliest readings on the fitted grid, and on
             * the quad's own grid (the code-agnostic fit may have settled
             * where the right reading is not among its likeliest) */
            for (jj = 0; jj < ml.ntop; jj++) {
                cid[ncand] = ml.top[jj].id;
                cview[ncand++] = ml.top[jj].view;
            }
            {
                float cq[32], bq, wq;
                ml_result mq;
                int a2, b2;
                fcells(&im, &g_quad, k, mt);
                flevels(mt, k, &bq, &wq);
                if (wq - bq > 0.0f) {
                    for (i = 0; i < bits; i++) {
                        float t;
                        bit_cell(i, k, &cx, &cy);
                        if (flags & ACTAG_FIT_LOCAL) {
                            int rx, ry, wx, wy;
                            fref_cells(i, k, &rx, &ry, &wx, &wy);
                            t = 0.5f * (mt[ry * n + rx] + mt[wy * n + wx]);
                        } else {
                            t = bq + level * (wq - bq);
                        }
                        cq[i] = (mt[cy * n + cx] - t) / (wq - bq);
                    }
                    ml_match(family, cq, keep, &mq);
                    for (a2 = 0; a2 < mq.ntop; a2++) {
                        int dup = 0;
                        for (b2 = 0; b2 < ncand; b2++)
                            dup |= cid[b2] == mq.top[a2].id && cview[b2] == mq.top[a2].view;
                        if (!dup) {
                            cid[ncand] = mq.top[a2].id;
                            cview[ncand++] = mq.top[a2].view;
                        }
                    }
                }
            }
            for (jj = 0; jj < ncand; jj++) {
                float r;
                layout_of(family, cid[jj], cview[jj], k, L);
                /* a polish near the grid the reading came from (after the
                 * wide search, which may settle a cell off, the full range) */
                {
                    fgrid g = jj < ml.ntop ? gr : g_quad;
                    im.fast = FIT_FAST_ASCENT;
                    ffit(&im, &g, k, mt, L, erase, !(flags & ACTAG_FIT_WIDE));
                    im.fast = 0;
                    fcells(&im, &g, k, mt);
                    r = template_rss(mt, L, k, erase, &nc);
                }
                if (jj == 0)
                    rss0 = r;
                else if (r < rss2)
                    rss2 = r;
            }
            /* another hypothesis explains the cells better once each has
             * its own grid: the code-agnostic reading cannot be trusted */
            if (rss2 <= rss0)
                goto no_reading;
            s2 = rss0 / (float)(nc > 3 ? nc - 2 : 1);
            floor2 = ACTAG_FIT_MIN_NOISE * 2.0f * contrast;
            floor2 *= floor2;
            if (s2 < floor2)
                s2 = floor2;
            margin = 0.5f * (rss2 - rss0) / s2;
        }
        /* Look-elsewhere allowance: the best of N hypotheses (8 views of
         * every code, times the grids the wide search tries) beats the
         * next by ln N on pure noise; the margin counts what is left. */
        margin -= actag_logf(8.0f * (float)family->ncodes *
                       ((flags & ACTAG_FIT_WIDE) ? (float)FIT_WIDE_GRIDS : 1.0f) *
                       (regrid ? 2.0f : 1.0f));
        if (margin < fp->min_margin || ml.h2 - ml.best.hamming < fp->min_bit_margin)
            goto no_reading;
        out->bit_margin = ml.h2 - ml.best.hamming;
    }

    out->observed = w;
    out->ring_black = (float)ring_ok / (float)(4 * (k - 2));
    out->interior_white = (float)in_ok / (float)((k - 3) * (k - 3));
    if (ml.best.mirrored) {
        mm = ml.best;
        dm = ml.best.hamming;
        du = ml.other;
    } else {
        mu = ml.best;
        du = ml.best.hamming;
        dm = ml.other;
    }
    set_orientation_as(out, q, ml.best.mirrored ? &mm : &mu, ml.best.mirrored, dm, du);
    out->decision_margin = margin;
    /* the word a perfect reading would have given */
    e = family->codes[out->id];
    for (i = 0; i < out->rotation; i++)
        e = actag_code_rot90(e, bits);
    if (out->mirrored)
        e = actag_decode_mirror(e, bits);
    {
        /* the fitted grid's white-square corners, in the same tag order */
        actag_point fq[4];
        float lo = 2.0f - 0.5f * (float)n, hi = (float)(k - 1) - 0.5f * (float)n;
        static const int su[4] = {0, 1, 1, 0}, sv[4] = {0, 0, 1, 1};
        for (i = 0; i < 4; i++) {
            float u = su[i] ? hi : lo, v = sv[i] ? hi : lo;
            fq[i].x = gr.mx + gr.ax * u + gr.bx * v;
            fq[i].y = gr.my + gr.ay * u + gr.by * v;
        }
        for (i = 0; i < 4; i++)
            out->fit_corners[i] = out->mirrored ? fq[(out->rotation - i + 4) & 3]
                                                : fq[(i - out->rotation + 4) & 3];
    }
    diff = (w ^ e) & keep;
    for (i = 0; i < bits; i++)
        if (diff & ((uint32_t)1u << (bits - 1 - i)))
            flips += conf[i] < 0.0f ? -conf[i] : conf[i];
    out->contrast = contrast;
    out->flip_weight = flips;
    out->min_confidence = minc;
    return ACTAG_OK;

no_reading:
    /* The code-agnostic fit can settle on a lattice where the tag does not
     * read while the quad's own grid does: read that grid too (one more
     * grid in the look-elsewhere allowance). */
    if (!regrid && !(flags & ACTAG_FIT_NO_SEARCH)) {
        regrid = 1;
        gr = g_quad;
        ring_ok = in_ok = nknown = 0;
        noise2 = 0.0f;
        minc = 1e30f;
        w = 0;
        goto reread;
    }
    return ACTAG_ERR_NO_MATCH;
}
