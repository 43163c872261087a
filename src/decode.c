/* Decode stage: quad -> homography -> sampled data ring -> family match. */
#include "actag/decode.h"

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
    int grey; /* 1: return grey levels (0..255); 0: binary (0/1) */
    float H[9];
    float su, sv, c; /* grid scale about the tag centre c (1, 1: none) */
} sampler;

/* Nearest pixel of grid point (u,v); outside the image counts as black.
 * Binary images give 0/1, grey images their grey level. */
static int sample_px(const sampler *s, float u, float v)
{
    actag_point p;
    int r, c;
    actag_homography_apply(s->H, s->c + (u - s->c) * s->su, s->c + (v - s->c) * s->sv, &p);
    if (!(p.x >= -0.5f && p.x < (float)s->cols - 0.5f && p.y >= -0.5f &&
          p.y < (float)s->rows - 0.5f))
        return 0;
    c = (int)(p.x + 0.5f); /* >= 0 here, so truncation is floor */
    r = (int)(p.y + 0.5f);
    if (c >= s->cols) /* float rounding just below the edge */
        c = s->cols - 1;
    if (r >= s->rows)
        r = s->rows - 1;
    if (s->grey)
        return s->img[(size_t)r * (size_t)s->stride + (size_t)c];
    return s->img[(size_t)r * (size_t)s->stride + (size_t)c] != 0;
}

/* White votes (0..9) of cell (cx, cy) over the 3x3 sample pattern; for a
 * grey image the sum of the 9 grey levels (0..2295). */
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

/* Grey-level reading: each cell's summed samples against a threshold half
 * way between this tag's own black ring and white interior, so the bits
 * follow the tag's local contrast rather than a window-wide threshold. Also
 * gives the structure fractions. Returns 0 when the tag has no contrast. */
static int read_word_grey(const sampler *s, int bits, int min_contrast, uint32_t *word,
                          float *ring_black, float *interior_white)
{
    int k = bits / 4, cx, cy, i, ring_n = 0, in_n = 0, ring_ok = 0, in_ok = 0;
    long ring_sum = 0, in_sum = 0;
    int thr;
    uint32_t w = 0;
    for (cy = 1; cy < k; cy++)
        for (cx = 1; cx < k; cx++) {
            int v = cell_votes(s, cx, cy);
            if (cx == 1 || cy == 1 || cx == k - 1 || cy == k - 1) {
                ring_sum += v;
                ring_n++;
            } else {
                in_sum += v;
                in_n++;
            }
        }
    if (ring_n == 0 || in_n == 0)
        return 0;
    if (in_sum * ring_n - ring_sum * in_n < (long)min_contrast * 9L * ring_n * in_n)
        return 0;
    thr = (int)((ring_sum * in_n + in_sum * ring_n) / (2L * ring_n * in_n));
    for (cy = 1; cy < k; cy++)
        for (cx = 1; cx < k; cx++) {
            int v = cell_votes(s, cx, cy);
            if (cx == 1 || cy == 1 || cx == k - 1 || cy == k - 1)
                ring_ok += v <= thr;
            else
                in_ok += v > thr;
        }
    for (i = 0; i < bits; i++) {
        bit_cell(i, k, &cx, &cy);
        w = (w << 1) | (cell_votes(s, cx, cy) > thr ? 1u : 0u);
    }
    *word = w;
    *ring_black = (float)ring_ok / (float)ring_n;
    *interior_white = (float)in_ok / (float)in_n;
    return 1;
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
    s.grey = 0;
    s.su = s.sv = 1.0f;
    s.c = 0.5f * (float)(bits / 4 + 1);
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

int actag_decode_quad(const uint8_t *binary, int rows, int cols, int stride,
                      const actag_point quad[4], const actag_family *family,
                      int max_corrections, actag_decode_result *out)
{
    return actag_decode_quad_ex(binary, rows, cols, stride, quad, family, max_corrections,
                                ACTAG_DECODE_DEFAULT_MODEL, out);
}

/* Mean grey of the white interior minus mean grey of the black ring, from
 * 5 samples (centre and +-0.25 cell) per cell. */
static float structure_contrast(const sampler *s, int k)
{
    int cx, cy, j;
    long ring = 0, in = 0;
    int nr = 0, ni = 0;
    static const float du[5] = {0.0f, -0.25f, 0.25f, 0.0f, 0.0f};
    static const float dv[5] = {0.0f, 0.0f, 0.0f, -0.25f, 0.25f};
    for (cy = 1; cy < k; cy++)
        for (cx = 1; cx < k; cx++) {
            int v = 0;
            for (j = 0; j < 5; j++)
                v += sample_px(s, (float)cx + 0.5f + du[j], (float)cy + 0.5f + dv[j]);
            if (cx == 1 || cy == 1 || cx == k - 1 || cy == k - 1) {
                ring += v;
                nr++;
            } else {
                in += v;
                ni++;
            }
        }
    return (float)in / (float)(5 * ni) - (float)ring / (float)(5 * nr);
}

/* The decoder proper; grey selects grey-level reading (min_contrast in grey
 * levels) instead of binary votes; align (a grey image, or NULL) enables the
 * grid scale search. */
static int decode_quad(const uint8_t *binary, const uint8_t *align, int rows, int cols,
                       int stride, const actag_point quad[4], const actag_family *family,
                       int max_corrections, int model, int grey, int min_contrast,
                       actag_decode_result *out)
{
    sampler s;
    actag_point q[4];
    actag_match mu, mm;
    uint32_t w;
    int rc, rcu, rcm, maxc, bits, k, du, dm, i, orient, cx, cy;
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
    s.grey = grey;
    s.su = s.sv = 1.0f;
    s.c = 0.5f * (float)(k + 1);
    if (align != NULL) {
        /* Sonar returns bloom: white areas grow, so the white square seen by
         * the quad stage is larger than printed and extrapolating to the
         * data ring overshoots. Shrink (or grow) the sampling grid about the
         * tag centre along each tag axis and keep the scale at which the
         * black ring is darkest relative to the white interior. */
        float best = -1e30f;
        int a, b2;
        sampler t = s;
        t.img = align;
        t.grey = 1;
        for (a = 0; a < ACTAG_DECODE_ALIGN_STEPS; a++)
            for (b2 = 0; b2 < ACTAG_DECODE_ALIGN_STEPS; b2++) {
                float sc;
                t.su = 1.0f - ACTAG_DECODE_ALIGN_STEP * (float)(a - ACTAG_DECODE_ALIGN_GROW);
                t.sv = 1.0f - ACTAG_DECODE_ALIGN_STEP * (float)(b2 - ACTAG_DECODE_ALIGN_GROW);
                sc = structure_contrast(&t, k);
                if (sc > best) {
                    best = sc;
                    s.su = t.su;
                    s.sv = t.sv;
                }
            }
    }

    if (grey) {
        float rb, iw;
        if (!read_word_grey(&s, bits, min_contrast, &w, &rb, &iw))
            return ACTAG_ERR_NO_MATCH;
        ring_n = in_n = 1000;
        ring_black = (int)(rb * 1000.0f + 0.5f);
        in_white = (int)(iw * 1000.0f + 0.5f);
        cy = k; /* skip the binary statistics below */
    } else {
        w = read_word(&s, bits);
        cy = 1;
    }
    /* Structure statistics (informative): black ring at distance 1, white
     * square inside. */
    for (; cy < k; cy++) {
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

    /* Match both handednesses up to the family limit, so the margin between
     * them is known; the caller's limit is applied to the winner. */
    rcu = actag_family_match_rotations(family, w, maxc, &mu);
    rcm = actag_family_match_rotations(family, actag_decode_mirror(w, bits), maxc, &mm);
    if ((rcu != ACTAG_OK && rcu != ACTAG_ERR_NO_MATCH) ||
        (rcm != ACTAG_OK && rcm != ACTAG_ERR_NO_MATCH))
        return rcu != ACTAG_OK && rcu != ACTAG_ERR_NO_MATCH ? rcu : rcm;
    du = rcu == ACTAG_OK ? mu.hamming : maxc + 1;
    dm = rcm == ACTAG_OK ? mm.hamming : maxc + 1;
    if (du > max_corrections && dm > max_corrections)
        return ACTAG_ERR_NO_MATCH;

    out->observed = w;
    out->ring_black = ring_n ? (float)ring_black / (float)ring_n : 1.0f;
    out->interior_white = in_n ? (float)in_white / (float)in_n : 1.0f;
    if (du <= dm) {
        /* observed == rot^r(code): screen cell s shows code cell s + rk, so
         * q[n] is printed corner n + r. */
        int r = mu.rotation;
        out->id = mu.id;
        out->hamming = du;
        out->mirrored = 0;
        out->rotation = r;
        out->mirror_margin = dm - du;
        for (i = 0; i < 4; i++)
            out->corners[i] = q[(i - r + 4) & 3];
    } else {
        /* P(observed) == rot^r(code): screen cell s shows code cell rk - s,
         * so q[n] is printed corner r - n. */
        int r = mm.rotation;
        out->id = mm.id;
        out->hamming = dm;
        out->mirrored = 1;
        out->rotation = r;
        out->mirror_margin = du - dm;
        for (i = 0; i < 4; i++)
            out->corners[i] = q[(r - i + 4) & 3];
    }
    return ACTAG_OK;
}

int actag_decode_quad_ex(const uint8_t *binary, int rows, int cols, int stride,
                         const actag_point quad[4], const actag_family *family,
                         int max_corrections, int model, actag_decode_result *out)
{
    return decode_quad(binary, NULL, rows, cols, stride, quad, family, max_corrections, model, 0,
                       0, out);
}

int actag_decode_quad_grey(const uint8_t *grey, int rows, int cols, int stride,
                           const actag_point quad[4], const actag_family *family,
                           int max_corrections, int min_contrast, actag_decode_result *out)
{
    if (min_contrast < 0 || min_contrast > 255)
        return ACTAG_ERR_PARAM;
    return decode_quad(grey, grey, rows, cols, stride, quad, family, max_corrections,
                       ACTAG_DECODE_DEFAULT_MODEL, 1, min_contrast, out);
}

int actag_decode_quad_aligned(const uint8_t *binary, const uint8_t *grey, int rows, int cols,
                              int stride, const actag_point quad[4], const actag_family *family,
                              int max_corrections, actag_decode_result *out)
{
    if (grey == NULL)
        return ACTAG_ERR_NULL;
    return decode_quad(binary, grey, rows, cols, stride, quad, family, max_corrections,
                       ACTAG_DECODE_DEFAULT_MODEL, 0, 0, out);
}
