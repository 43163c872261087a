/* The detection pipeline: workspace layout, stage sequencing, the physical
 * size filter, duplicate suppression and the polar output. The stages
 * themselves live in their own files (median.c, threshold.c, contours.c,
 * quad.c, decode.c). */
#include "actag/actag.h"

#include <string.h>

/* Workspace layout (see ACTAG_WORKSPACE_SIZE):
 *   [0..15 alignment][A: binary (16-bit input is converted here first)]
 *   [B: filtered][S: stage scratch, reused by each stage in turn]          */
typedef struct {
    uint8_t *a, *b, *s;
    size_t s_size;
} ws_layout;

static uint8_t *align16(const void *p)
{
    uintptr_t u = (uintptr_t)p;
    return (uint8_t *)(((u + 15u) & ~(uintptr_t)15u));
}

static void ws_split(void *workspace, int rows, int cols, ws_layout *w)
{
    size_t img = ACTAG__ALIGN16((size_t)rows * (size_t)cols);
    w->a = align16(workspace);
    w->b = w->a + img;
    w->s = w->b + img;
    w->s_size = ACTAG__ALIGN16(ACTAG__STAGE_SCRATCH(rows, cols));
}

size_t actag_workspace_size(int rows, int cols)
{
    if (rows < 1 || cols < 1 || rows > ACTAG_MAX_DIM || cols > ACTAG_MAX_DIM)
        return 0;
    return ACTAG_WORKSPACE_SIZE(rows, cols);
}

const uint8_t *actag_workspace_filtered(const void *workspace, int rows, int cols)
{
    ws_layout w;
    if (workspace == NULL || actag_workspace_size(rows, cols) == 0)
        return NULL;
    ws_split((void *)(uintptr_t)workspace, rows, cols, &w);
    return w.b;
}

const uint8_t *actag_workspace_binary(const void *workspace, int rows, int cols)
{
    ws_layout w;
    if (workspace == NULL || actag_workspace_size(rows, cols) == 0)
        return NULL;
    ws_split((void *)(uintptr_t)workspace, rows, cols, &w);
    return w.a;
}

void actag_params_default(actag_params *p)
{
    if (p == NULL)
        return;
    memset(p, 0, sizeof *p);
    p->family = NULL;
    p->tag_size = 0.130628571f; /* 3/7 ft: inner square of a 1 ft, 24-bit tag */
    p->max_bit_corrections = 0;
    p->median_radius = 4;
    p->threshold_radius = 8;
    p->threshold_offset = 1;
    p->size_tolerance = 0.2f;
    p->min_area_fraction = 0.1f;
    p->max_area_fraction = 1.0f;
    actag_quad_params_default(&p->quad);
    p->decode_mode = ACTAG_DECODE_GREY;
    p->min_contrast = 5;
    p->seed = 1u;
}

static int finite_pos(float v) { return v == v && v > 0.0f && v < 3.0e38f; }

int actag_params_validate(const actag_params *p)
{
    int rc, maxc;
    if (p == NULL || p->family == NULL)
        return ACTAG_ERR_NULL;
    rc = actag_family_validate(p->family);
    if (rc != ACTAG_OK)
        return rc;
    maxc = actag_family_max_corrections(p->family);
    if (p->max_bit_corrections < 0 || p->max_bit_corrections > maxc)
        return ACTAG_ERR_CORRECTIONS;
    if (!finite_pos(p->tag_size) || p->median_radius < 0 ||
        p->median_radius > ACTAG_MEDIAN_MAX_RADIUS || p->threshold_radius < 0 ||
        p->threshold_radius > ACTAG_MAX_THRESHOLD_RADIUS || p->threshold_offset < -255 ||
        p->threshold_offset > 255)
        return ACTAG_ERR_PARAM;
    if (!(p->size_tolerance >= 0.0f && p->size_tolerance < 10.0f) ||
        !(p->min_area_fraction >= 0.0f) || !(p->max_area_fraction >= p->min_area_fraction) ||
        !(p->max_area_fraction < 1.0e6f))
        return ACTAG_ERR_PARAM;
    if (p->decode_mode < ACTAG_DECODE_GREY || p->decode_mode > ACTAG_DECODE_ALIGNED ||
        p->min_contrast < 0 || p->min_contrast > 255)
        return ACTAG_ERR_PARAM;
    if (p->quad.max_iterations < 1 || !(p->quad.sample_fraction > 0.0f) ||
        !(p->quad.sample_fraction <= 1.0f) || !(p->quad.inlier_ratio > 0.0f) ||
        !(p->quad.inlier_ratio <= 1.0f) || !finite_pos(p->quad.inlier_distance) ||
        !(p->quad.min_parallel_cos >= 0.0f) || !(p->quad.min_parallel_cos <= 1.0f))
        return ACTAG_ERR_PARAM;
    return ACTAG_OK;
}

/* 16-bit frames: scale by the frame's maximum into 8 bits (integer, exact). */
static void convert16(const actag_frame *f, uint8_t *dst)
{
    const uint16_t *src = (const uint16_t *)f->data;
    uint32_t mx = 0;
    int r, c;
    for (r = 0; r < f->rows; r++)
        for (c = 0; c < f->cols; c++) {
            uint32_t v = src[(size_t)r * (size_t)f->stride + (size_t)c];
            if (v > mx)
                mx = v;
        }
    for (r = 0; r < f->rows; r++)
        for (c = 0; c < f->cols; c++) {
            uint32_t v = src[(size_t)r * (size_t)f->stride + (size_t)c];
            dst[(size_t)r * (size_t)f->cols + (size_t)c] =
                (uint8_t)(mx ? (v * 255u + mx / 2u) / mx : 0u);
        }
}

/* Physical size filter (SPEC section 5): the white square's extents and area,
 * in pixels, must fit a tag of this size at this range. */
static int size_plausible(const actag_contour_info *ci, const actag_sonar_geometry *g,
                          const actag_params *p, int rows, int cols)
{
    float yc = 0.5f * (float)(ci->min_y + ci->max_y);
    float xc = 0.5f * (float)(ci->min_x + ci->max_x);
    float range = actag_geometry_range(g, rows, yc);
    float dr = actag_geometry_range_step(g, rows);
    float daz = actag_geometry_azimuth_step(g, cols, xc) * range;
    float diag = p->tag_size * 1.41421356f;
    float diag_r_px, diag_az_px, ext_r, ext_az, ref_area, tol = p->size_tolerance;
    if (!(dr > 0.0f) || !(daz > 0.0f))
        return 0;
    diag_r_px = diag / dr;
    diag_az_px = diag / daz;
    ext_r = (float)(ci->max_y - ci->min_y + 1);
    ext_az = (float)(ci->max_x - ci->min_x + 1);
    if (ext_r > diag_r_px * (1.0f + tol) || ext_az > diag_az_px * (1.0f + tol))
        return 0;
    ref_area = diag_r_px * diag_az_px;
    if (ci->area < p->min_area_fraction * (1.0f - tol) * ref_area ||
        ci->area > p->max_area_fraction * (1.0f + tol) * ref_area)
        return 0;
    return 1;
}

static float dist2(actag_point a, actag_point b)
{
    float dx = a.x - b.x, dy = a.y - b.y;
    return dx * dx + dy * dy;
}

static actag_point centre(const actag_point c[4])
{
    actag_point m;
    m.x = 0.25f * (c[0].x + c[1].x + c[2].x + c[3].x);
    m.y = 0.25f * (c[0].y + c[1].y + c[2].y + c[3].y);
    return m;
}

/* Same ID and centre inside the other quad's circumcircle: the same tag. */
static int same_tag(const actag_detection *d, int id, const actag_point c[4])
{
    actag_point a = centre(d->corners), b = centre(c);
    float r2 = dist2(d->corners[0], d->corners[2]) * 0.25f;
    return d->id == id && dist2(a, b) <= r2;
}

static int better(int hamming, float ratio, const actag_detection *d)
{
    return hamming < d->hamming || (hamming == d->hamming && ratio > d->inlier_ratio);
}

int actag_detect(const actag_frame *frame, const actag_sonar_geometry *geometry,
                 const actag_params *params, void *workspace, size_t workspace_size,
                 actag_detection *out, int max_out, actag_stats *stats)
{
    actag_stats st;
    ws_layout w;
    const uint8_t *src;
    int src_stride, rc, rows, cols, nout = 0, flip_mirror;
    actag_contour_scanner scan;
    actag_ipoint *pts;
    void *qscratch;
    size_t cap, qscratch_size;
    actag_rng rng;

    memset(&st, 0, sizeof st);
    if (stats)
        *stats = st;
    if (frame == NULL || geometry == NULL || params == NULL || workspace == NULL ||
        frame->data == NULL || (out == NULL && max_out > 0))
        return ACTAG_ERR_NULL;
    rows = frame->rows;
    cols = frame->cols;
    if (rows < 1 || cols < 1 || rows > ACTAG_MAX_DIM || cols > ACTAG_MAX_DIM ||
        frame->stride < cols || (frame->depth != 8 && frame->depth != 16))
        return ACTAG_ERR_SIZE;
    if (max_out < 0)
        return ACTAG_ERR_PARAM;
    rc = actag_params_validate(params);
    if (rc != ACTAG_OK)
        return rc;
    rc = actag_geometry_validate(geometry, rows, cols);
    if (rc != ACTAG_OK)
        return rc;
    if (workspace_size < actag_workspace_size(rows, cols))
        return ACTAG_ERR_WORKSPACE;

    ws_split(workspace, rows, cols, &w);
    if (frame->depth == 16) {
        convert16(frame, w.a);
        src = w.a;
        src_stride = cols;
    } else {
        src = (const uint8_t *)frame->data;
        src_stride = frame->stride;
    }

    /* 1. median filter: src -> B */
    rc = actag_median_filter(src, rows, cols, src_stride, w.b, cols, params->median_radius, w.s,
                             w.s_size);
    if (rc != ACTAG_OK)
        return rc;
    /* 2. adaptive threshold: B -> A (A's 16-bit copy is no longer needed) */
    rc = actag_adaptive_threshold(w.b, rows, cols, cols, w.a, cols, params->threshold_radius,
                                  params->threshold_offset, w.s, w.s_size);
    if (rc != ACTAG_OK)
        return rc;

    /* 3.-5. contours, one at a time, each through size filter, quad, decode */
    cap = ACTAG_CONTOUR_CAP(rows, cols);
    pts = (actag_ipoint *)(void *)w.s;
    qscratch = w.s + ACTAG__ALIGN16(cap * sizeof(actag_ipoint));
    qscratch_size = w.s_size - ACTAG__ALIGN16(cap * sizeof(actag_ipoint));
    rc = actag_contour_scanner_init(&scan, w.a, rows, cols, cols);
    if (rc != ACTAG_OK)
        return rc;
    actag_rng_seed(&rng, params->seed);
    /* The decoder reports mirroring relative to the image; flipping exactly
     * one image axis relative to the reference orientation mirrors it again. */
    {
        int az_asc = geometry->bearings
                         ? (cols > 1 && geometry->bearings[cols - 1] > geometry->bearings[0])
                         : (geometry->flags & ACTAG_AZIMUTH_ASCENDING) != 0u;
        int r_asc = (geometry->flags & ACTAG_RANGE_ASCENDING) != 0u;
        flip_mirror = az_asc ^ r_asc;
    }

    for (;;) {
        actag_contour_info ci;
        actag_quad q;
        actag_decode_result dr;
        int k, dup = -1;
        rc = actag_contour_next(&scan, pts, (int)cap, &ci);
        if (rc < 0)
            return rc;
        if (rc == 0)
            break;
        st.contours++;
        if (ci.overflow) {
            st.overflowed++;
            continue;
        }
        if (!size_plausible(&ci, geometry, params, rows, cols))
            continue;
        st.size_ok++;
        if (actag_quad_fit(pts, ci.stored, &params->quad, &rng, qscratch, qscratch_size, &q) !=
            ACTAG_OK)
            continue;
        st.quads++;
        rc = params->decode_mode == ACTAG_DECODE_GREY
                 ? actag_decode_quad_grey(w.b, rows, cols, cols, q.corners, params->family,
                                          params->max_bit_corrections, params->min_contrast, &dr)
                 : params->decode_mode == ACTAG_DECODE_ALIGNED
                       ? actag_decode_quad_aligned(w.a, w.b, rows, cols, cols, q.corners,
                                                   params->family, params->max_bit_corrections,
                                                   &dr)
                       : actag_decode_quad(w.a, rows, cols, cols, q.corners, params->family,
                                           params->max_bit_corrections, &dr);
        if (rc != ACTAG_OK)
            continue;
        st.decoded++;
        for (k = 0; k < nout && k < max_out; k++)
            if (same_tag(&out[k], dr.id, dr.corners)) {
                dup = k;
                break;
            }
        if (dup >= 0) {
            st.duplicates++;
            if (!better(dr.hamming, q.inlier_ratio, &out[dup]))
                continue;
            k = dup;
        } else {
            if (nout >= max_out) {
                st.dropped++;
                continue;
            }
            k = nout++;
        }
        out[k].id = dr.id;
        out[k].hamming = dr.hamming;
        out[k].mirrored = dr.mirrored ^ flip_mirror;
        out[k].inlier_ratio = q.inlier_ratio;
        {
            int c;
            for (c = 0; c < 4; c++) {
                out[k].corners[c] = dr.corners[c];
                out[k].range[c] = actag_geometry_range(geometry, rows, dr.corners[c].y);
                out[k].azimuth[c] = actag_geometry_azimuth(geometry, cols, dr.corners[c].x);
            }
        }
    }
    if (stats)
        *stats = st;
    return nout;
}
