/* The paper's binary decoder: the quad's grid (tag_grid.c) mapped onto the
 * binary frame, each cell read by a 3x3 majority vote, the word and its
 * reflection matched by Hamming distance (family.c). See decode.h. */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/decode.h"
#include "decode_common.h"

#include <string.h>

typedef struct sampler {
    const uint8_t *img;
    const uint32_t *bitmap; /* instead of img when not NULL */
    int rows, cols, stride;
    float H[9];
} sampler;

/* The sampler of the quad's grid (quad[n] = corner n) under a map model. */
static int sampler_init(sampler *s, const uint8_t *binary, int rows, int cols, int stride,
                        const actag_point quad[4], int bits, int model)
{
    s->img = binary;
    s->bitmap = NULL;
    s->rows = rows;
    s->cols = cols;
    s->stride = stride;
    return actag_tag_map(quad, bits, model, s->H);
}

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
    if (s->bitmap != NULL)
        return actag_bitmap_get(s->bitmap, s->cols, r, c);
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
        actag_tag_bit_cell(bits, i, &cx, &cy);
        w = (w << 1) | (cell_votes(s, cx, cy) >= 5 ? 1u : 0u);
    }
    return w;
}

int actag_decode_read_word(const uint8_t *binary, int rows, int cols, int stride,
                           const actag_point quad[4], int bits, int model, uint32_t *word)
{
    sampler s;
    int rc;
    if (binary == NULL || quad == NULL || word == NULL)
        return ACTAG_ERR_NULL;
    rc = decode_check_image(binary, rows, cols, stride);
    if (rc != ACTAG_OK)
        return rc;
    rc = sampler_init(&s, binary, rows, cols, stride, quad, bits, model);
    if (rc != ACTAG_OK)
        return rc;
    *word = read_word(&s, bits);
    return ACTAG_OK;
}

uint32_t actag_decode_mirror(uint32_t word, int bits)
{
    return actag_code_mirror(word, bits);
}

/* Matches the word read clockwise on screen (unmirrored) and its reflection
 * P (mirrored) up to the family limit, so the margin between them is known;
 * the caller's limit applies to the better one. Returns ACTAG_OK,
 * ACTAG_ERR_NO_MATCH, or the matcher's error. */
static int match_both(const actag_family *family, uint32_t w, int maxc, int max_corrections,
                      actag_match *mu, int *du, actag_match *mm, int *dm)
{
    int rcu = actag_family_match_rotations(family, w, maxc, mu);
    int rcm = actag_family_match_rotations(family, actag_decode_mirror(w, family->bits), maxc, mm);
    if (rcu != ACTAG_OK && rcu != ACTAG_ERR_NO_MATCH)
        return rcu;
    if (rcm != ACTAG_OK && rcm != ACTAG_ERR_NO_MATCH)
        return rcm;
    *du = rcu == ACTAG_OK ? mu->hamming : maxc + 1;
    *dm = rcm == ACTAG_OK ? mm->hamming : maxc + 1;
    return (*du > max_corrections && *dm > max_corrections) ? ACTAG_ERR_NO_MATCH : ACTAG_OK;
}

int actag_decode_quad(const uint8_t *binary, int rows, int cols, int stride,
                      const actag_point quad[4], const actag_family *family,
                      int max_corrections, actag_decode_result *out)
{
    return actag_decode_quad_ex(binary, rows, cols, stride, quad, family, max_corrections,
                                ACTAG_DECODE_DEFAULT_MODEL, out);
}

static int decode_core(const uint8_t *binary, const uint32_t *bitmap, int rows, int cols,
                       int stride, const actag_point quad[4], const actag_family *family,
                       int max_corrections, int model, actag_decode_result *out);

int actag_decode_quad_ex(const uint8_t *binary, int rows, int cols, int stride,
                         const actag_point quad[4], const actag_family *family,
                         int max_corrections, int model, actag_decode_result *out)
{
    int rc;
    if (binary == NULL || quad == NULL || family == NULL || out == NULL)
        return ACTAG_ERR_NULL;
    rc = decode_check_frame_family(binary, rows, cols, stride, family);
    if (rc != ACTAG_OK)
        return rc;
    return decode_core(binary, NULL, rows, cols, stride, quad, family, max_corrections, model,
                       out);
}

int actag_decode_quad_bitmap(const uint32_t *bitmap, int rows, int cols,
                             const actag_point quad[4], const actag_family *family,
                             int max_corrections, actag_decode_result *out)
{
    int rc;
    if (bitmap == NULL || quad == NULL || family == NULL || out == NULL)
        return ACTAG_ERR_NULL;
    rc = decode_check_frame_family((const uint8_t *)(const void *)bitmap, rows, cols, cols,
                                   family);
    if (rc != ACTAG_OK)
        return rc;
    return decode_core(NULL, bitmap, rows, cols, cols, quad, family, max_corrections,
                       ACTAG_DECODE_DEFAULT_MODEL, out);
}

/* actag_decode_quad_ex() on bytes (binary) or a bitmap, arguments checked. */
static int decode_core(const uint8_t *binary, const uint32_t *bitmap, int rows, int cols,
                       int stride, const actag_point quad[4], const actag_family *family,
                       int max_corrections, int model, actag_decode_result *out)
{
    sampler s;
    actag_point q[4];
    actag_match mu, mm;
    uint32_t w;
    int rc, bits, k, du, dm, cx, cy;
    int ring_n = 0, ring_black = 0, in_n = 0, in_white = 0;
    rc = decode_check_corrections(family, max_corrections);
    if (rc != ACTAG_OK)
        return rc;
    bits = family->bits;
    k = bits / 4;

    /* Clockwise on screen, quad[0] first, so that "mirrored" means mirrored
     * on screen whatever order the quad stage used. */
    rc = actag_tag_quad_clockwise(quad, q);
    if (rc != ACTAG_OK)
        return rc;
    rc = sampler_init(&s, binary, rows, cols, stride, q, bits, model);
    if (rc != ACTAG_OK)
        return rc;
    s.bitmap = bitmap;

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

    rc = match_both(family, w, actag_family_max_corrections(family), max_corrections, &mu, &du,
                    &mm, &dm);
    if (rc != ACTAG_OK)
        return rc;

    out->observed = w;
    out->contrast = 0.0f;
    out->flip_weight = 0.0f;
    out->min_confidence = 0.0f;
    out->ring_black = ring_n ? (float)ring_black / (float)ring_n : 1.0f;
    out->interior_white = in_n ? (float)in_white / (float)in_n : 1.0f;
    if (dm < du) { /* the handedness with fewer corrected bits, unmirrored on a tie */
        mm.mirrored = 1;
        decode_set_reading(out, q, &mm, du);
    } else {
        decode_set_reading(out, q, &mu, dm);
    }
    out->decision_margin = (float)out->mirror_margin; /* the hard decoder: other handedness */
    out->bit_margin = 0; /* no runner-up reading (decode.h) */
    /* no fitted grid: its corners are the reading's (the detector refines
     * from them; they were left unset once) */
    memcpy(out->fit_corners, out->corners, sizeof out->fit_corners);
    return ACTAG_OK;
}
