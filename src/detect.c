/* The detection pipeline: workspace layout, stage sequencing, the checks
 * a reading passes before it is reported (rival readings of its place),
 * duplicate suppression and the polar output. The stages themselves live
 * in their own files (median.c, search.c, threshold.c, contours.c,
 * size_filter.c, quad.c, decode_fit.c, decode_binary.c and refine.c). */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/actag.h"

#include "decode_fit_grids.h"
#include "frame16.h"
#include "median_bands.h"
#include "refine_frame.h"
#include "readings.h"
#include "size_filter.h"

#include <string.h>

/* Workspace layout (ACTAG_WORKSPACE_SIZE, ACTAG_WORKSPACE_SIZE_INPLACE), each
 * part 16-byte aligned:
 *   [0..15 alignment]
 *   [U: one region the stages use in turn:
 *       A: the binary bitmap (one bit per pixel, common.h),
 *       M: the contour scanner's marks bitmap,
 *       S: the contour points and the quad scratch;
 *     before A and M hold bitmaps, U is the median's scratch (column
 *     histograms, or actag_median_filter_inplace's copy of source rows),
 *     then the search's score map (at U's start) and integral image (after
 *     it); the threshold's row buffers are M and S]
 *   [B: the filtered frame, one byte per pixel (actag_detect); in place it
 *     is the caller's frame buffer instead]  */
typedef struct {
    uint8_t *a, *b, *s;
    uint32_t *bin, *marks;
    size_t a_size, s_size, u_size; /* A + M, S, and all of U */
    /* each stage's own buffers inside U */
    uint8_t *map, *ii, *th; /* search score map, its integral image, threshold scratch */
    size_t map_size, ii_size, th_size;
} ws_layout;

static uint8_t *align16(const void *p)
{
    uintptr_t u = (uintptr_t)p;
    return (uint8_t *)(((u + 15u) & ~(uintptr_t)15u));
}

/* U with an S of s_size bytes; B after it, or b when not NULL (in place). */
static void ws_layout_of(void *workspace, uint8_t *b, int rows, int cols, size_t s_size,
                         ws_layout *w)
{
    size_t bm = ACTAG__ALIGN16(ACTAG_BITMAP_SIZE(rows, cols));
    w->a = align16(workspace);
    w->a_size = 2u * bm;
    w->bin = (uint32_t *)(void *)w->a;
    w->marks = (uint32_t *)(void *)(w->a + bm);
    w->s = w->a + w->a_size;
    w->s_size = s_size;
    w->u_size = w->a_size + s_size;
    w->b = b != NULL ? b : w->s + s_size;
    w->map = w->a;
    w->map_size = ACTAG__ALIGN16(ACTAG_SEARCH_MAP_SIZE(rows, cols));
    w->ii = w->a + w->map_size;
    w->ii_size = w->u_size - w->map_size;
    w->th = w->a + bm;
    w->th_size = bm + s_size;
}

static void ws_split(void *workspace, int rows, int cols, ws_layout *w)
{
    ws_layout_of(workspace, NULL, rows, cols, ACTAG__ALIGN16(ACTAG__STAGE_SCRATCH(rows, cols)),
                 w);
}

static void ws_split_inplace(void *workspace, uint8_t *b, int rows, int cols, ws_layout *w)
{
    ws_layout_of(workspace, b, rows, cols, ACTAG__ALIGN16(ACTAG__INPLACE_SCRATCH(rows, cols)),
                 w);
}

size_t actag_workspace_size(int rows, int cols)
{
    if (rows < 1 || cols < 1 || rows > ACTAG_MAX_DIM || cols > ACTAG_MAX_DIM)
        return 0;
    return ACTAG_WORKSPACE_SIZE(rows, cols);
}

size_t actag_workspace_size_inplace(int rows, int cols)
{
    if (rows < 1 || cols < 1 || rows > ACTAG_MAX_DIM || cols > ACTAG_MAX_DIM)
        return 0;
    return ACTAG_WORKSPACE_SIZE_INPLACE(rows, cols);
}

const uint8_t *actag_workspace_filtered(const void *workspace, int rows, int cols)
{
    ws_layout w;
    if (workspace == NULL || actag_workspace_size(rows, cols) == 0)
        return NULL;
    ws_split((void *)(uintptr_t)workspace, rows, cols, &w);
    return w.b;
}

const uint32_t *actag_workspace_bitmap(const void *workspace, int rows, int cols)
{
    ws_layout w;
    if (workspace == NULL || actag_workspace_size(rows, cols) == 0)
        return NULL;
    ws_split((void *)(uintptr_t)workspace, rows, cols, &w);
    return w.bin;
}

void actag_tuning_default(actag_tuning *t)
{
    if (t == NULL)
        return;
    memset(t, 0, sizeof *t);
    t->median_radius = 4;
    t->median_per_range = 1;
    t->threshold_radius = 8;
    t->threshold_offset = 1;
    t->size_tolerance = 0.2f;
    /* 0.175: with the 20 % tolerance, 0.14 of the diagonal box, the white
     * square (half the box face-on) seen 74 degrees off its normal; no
     * simulated reading came from a flatter contour (least 0.162, 1,375
     * readings), and half the pool frames' clutter contours are flatter */
    t->min_area_fraction = 0.175f;
    t->max_area_fraction = 1.0f;
    actag_quad_params_default(&t->quad);
    /* Measured on the pool frames (see the manual in actag.h): RANSAC's
     * early exit at 0.8 and acceptance down to 0.6 let ragged sonar
     * contours through (the decoder judges them); 100 iterations suffice
     * because the structure search covers what RANSAC misses. */
    t->quad.inlier_ratio = 0.8f;
    t->quad.min_inlier_ratio = 0.6f;
    t->quad.max_iterations = 100;
    t->decode_mode = ACTAG_DECODE_FIT;
    actag_fit_params_default(&t->fit);
    /* the structure budget alone (structure_ok): a speckled ring or
     * interior cell costs what a corrected bit costs, no gate besides */
    t->min_structure = 0.0f;
    t->min_texture_contrast = ACTAG_MIN_TEXTURE_CONTRAST;
    t->min_side_fraction = 0.5f;
    t->max_side_fraction = 1.6f;
    t->search_candidates = 2;
    t->search_min_score = 15;
    t->search_range_scale = 0.75f;
    t->search_max_corrections = 3;
    t->search_min_margin = ACTAG_SEARCH_MIN_MARGIN;
    t->refine_corners = 1;
    t->limits.max_contours = ACTAG_LIMIT_CONTOURS;
    t->limits.max_contour_points = ACTAG_LIMIT_CONTOUR_POINTS;
    t->limits.max_contour_iterations = ACTAG_LIMIT_CONTOUR_ITERATIONS;
    t->limits.max_frame_iterations = ACTAG_LIMIT_FRAME_ITERATIONS;
    t->limits.max_decodes = ACTAG_LIMIT_DECODES;
}

void actag_params_default(actag_params *p)
{
    if (p == NULL)
        return;
    memset(p, 0, sizeof *p);
    p->family = NULL;
    p->tag_size = 0.130628571f; /* 3/7 ft: inner square of a 1 ft, 24-bit tag */
    p->max_bit_corrections = ACTAG_CORRECTIONS_AUTO;
    p->seed = 1u;
    p->min_margin = ACTAG_FIT_MIN_MARGIN;
    actag_tuning_default(&p->tuning);
}

/* actag_params_validate(), actag_tuning_validate() and actag_check() are in
 * validate.c with the other rules. */

/* RANSAC iterations multiplier for contours at a tag the search found. */
#define ACTAG_SEEK_QUAD_EFFORT 10

static int better(int hamming, float ratio, const actag_detection *d)
{
    return hamming < d->hamming || (hamming == d->hamming && ratio > d->inlier_ratio);
}

/* A detection from a decoder result, its corners and quad support. */
static void fill_det(actag_detection *d, const actag_decode_result *dr,
                     const actag_point corners[4], float ratio,
                     const actag_sonar_geometry *geometry, int rows, int cols, int flip_mirror)
{
    int c;
    d->id = dr->id;
    d->hamming = dr->hamming;
    d->mirrored = dr->mirrored ^ flip_mirror;
    d->inlier_ratio = ratio;
    d->decision_margin = dr->decision_margin;
    for (c = 0; c < 4; c++) {
        d->corners[c] = corners[c];
        d->range[c] = actag_geometry_range(geometry, rows, corners[c].y);
        d->azimuth[c] = actag_geometry_azimuth(geometry, cols, corners[c].x);
    }
}

/* Is some corner of the decoder's fitted grid (fit) more than half a cell
 * from the reported corner (q, the quad's)? Then the quad may have merged
 * with a neighbouring white cell or lost a corner's part while the grid
 * fit still found the tag: both starts are refined. Cell: the white
 * square spans k - 3 cells (tag_grid.h). */
static int starts_disagree(const actag_point q[4], const actag_point fit[4], int bits)
{
    float side = 0.0f, far2 = 0.0f, cell;
    int c;
    for (c = 0; c < 4; c++) {
        float dx = q[(c + 1) & 3].x - q[c].x, dy = q[(c + 1) & 3].y - q[c].y;
        float ex = fit[c].x - q[c].x, ey = fit[c].y - q[c].y;
        side += 0.25f * actag_sqrtf(dx * dx + dy * dy);
        far2 = ex * ex + ey * ey > far2 ? ex * ex + ey * ey : far2;
    }
    cell = side / (float)(bits / 4 - 3);
    return far2 > 0.25f * cell * cell;
}

/* Sub-pixel corners for a reported tag: its decoded template fitted to the
 * caller's frame as the sonar gave it (the median filter, a detection aid,
 * rounds corners and thins small cells: it biased the fitted shape); the
 * corners (and their range and azimuth) move when the fit is accepted,
 * nothing else. second (if not NULL: the decoder's fitted grid's corners,
 * in the same order) is the other start: tried when the fit from the
 * reported corners is refused (a RANSAC quad of a thin, grazing tag can lie
 * more than a cell off in range, beyond the refinement's reach, where the
 * decoder's grid is not), and also when it lies more than half a cell from
 * them (starts_disagree), the fit with the smaller residual kept: a quad
 * that took in a data cell beside the white square can pull the template
 * to a place that fits worse than the grid the code was read at (held-out
 * run 15101 frame 201: rms 72 from the quad, 41 from the grid). */
static void refine_det(actag_detection *d, const actag_frame *frame, uint32_t max16,
                       const actag_sonar_geometry *geometry, const actag_params *params,
                       const actag_point *second)
{
    actag_refine_params rp;
    actag_refine_info first_info, second_info;
    actag_point fine[4], alt[4];
    int c, ok, rows = frame->rows, cols = frame->cols;
    actag_refine_params_default(&rp);
    ok = actag__refine_corners_max16(frame->data, frame->depth, max16, rows, cols, frame->stride,
                                     geometry, params->tag_size, params->family, d->id,
                                     d->corners, &rp, fine, &first_info) == ACTAG_OK;
    if (second != NULL && memcmp(second, d->corners, sizeof d->corners) != 0 &&
        (!ok || starts_disagree(d->corners, second, params->family->bits)) &&
        actag__refine_corners_max16(frame->data, frame->depth, max16, rows, cols, frame->stride,
                                    geometry, params->tag_size, params->family, d->id, second,
                                    &rp, alt, &second_info) == ACTAG_OK &&
        (!ok || second_info.rms < first_info.rms)) {
        memcpy(fine, alt, sizeof fine);
        ok = 1;
    }
    if (!ok)
        return;
    for (c = 0; c < 4; c++) {
        d->corners[c] = fine[c];
        d->range[c] = actag_geometry_range(geometry, rows, fine[c].y);
        d->azimuth[c] = actag_geometry_azimuth(geometry, cols, fine[c].x);
    }
}

/* Detections whose refinement may start a second time from the decoder's
 * fitted grid (kept on the stack, 32 bytes each). */
#define REFINE_STARTS 8

/* Tags that did not fit out[] (max_out), by the place of their first
 * reading (actag__place_of), so that another reading of such a tag counts
 * in stats.duplicates, not as one more tag in stats.dropped. Beyond
 * DROPPED_PLACES such tags, every further reading counts as dropped. */
#define DROPPED_PLACES 8
typedef struct {
    actag__place at[DROPPED_PLACES];
    int n;
} dropped_places;

/* Is the reading at corners q at the place of a dropped tag? If not, and
 * there is room, it is one now. */
static int dropped_before(dropped_places *dp, const actag_point q[4])
{
    actag__place p = actag__place_of(q);
    int i;
    for (i = 0; i < dp->n; i++)
        if (actag__places_meet(p, dp->at[i]))
            return 1;
    if (dp->n < DROPPED_PLACES)
        dp->at[dp->n++] = p;
    return 0;
}

/* Adds a detection to out[], or replaces the reading at the same place
 * when this one is better; when it lands in out[0 .. REFINE_STARTS-1], its
 * reading's fitted-grid corners (fit) go to fit_start at the same index. A
 * reading with no room in out[] is counted in stats.dropped once per tag
 * (dp). */
static void record(actag_detection *out, int max_out, int *nout, actag_stats *st,
                   dropped_places *dp, const actag_detection *d, const actag_point fit[4],
                   actag_point fit_start[REFINE_STARTS][4])
{
    int k, dup = -1;
    /* Two tags cannot overlap: a reading at the place of an earlier one is
     * the same tag (same ID) or a misreading of one of the two (other ID);
     * either way only the better reading survives. */
    for (k = 0; k < *nout && k < max_out; k++)
        if (actag__same_place(out[k].corners, d->corners)) {
            dup = k;
            break;
        }
    if (dup >= 0) {
        st->duplicates++;
        if (!better(d->hamming, d->inlier_ratio, &out[dup]))
            return;
        k = dup;
    } else {
        if (*nout >= max_out) {
            if (dropped_before(dp, d->corners))
                st->duplicates++;
            else
                st->dropped++;
            return;
        }
        k = (*nout)++;
    }
    out[k] = *d;
    if (k < REFINE_STARTS)
        memcpy(fit_start[k], fit, sizeof fit_start[k]);
}

/* The optional candidate callback of actag_detect_traced() (trace.h). */
typedef struct {
    actag_trace_fn fn;
    void *user;
} tracer;

/* Reports a search position or quad (tr may be NULL: nothing to do). */
static void trace_quad(const tracer *tr, int kind, int outcome, const actag_point quad[4],
                       float ratio, const actag_decode_result *dr)
{
    actag_trace_event e;
    if (tr == NULL)
        return;
    memset(&e, 0, sizeof e);
    e.kind = kind;
    e.outcome = outcome;
    memcpy(e.quad, quad, sizeof e.quad);
    e.inlier_ratio = ratio;
    e.decoded = dr;
    tr->fn(tr->user, &e);
}

static void trace_contour(const tracer *tr, int outcome, const actag_ipoint *pts,
                          const actag_contour_info *ci)
{
    actag_trace_event e;
    if (tr == NULL)
        return;
    memset(&e, 0, sizeof e);
    e.kind = ACTAG_TRACE_CONTOUR;
    e.outcome = outcome;
    e.points = ci->overflow ? NULL : pts;
    e.npoints = ci->overflow ? 0 : ci->stored;
    e.contour = ci;
    tr->fn(tr->user, &e);
}

static int detect_filtered(const actag_frame *frame, const actag_sonar_geometry *geometry,
                           const actag_params *params,
                           const ws_layout *wl, uint32_t max16, int rows, int cols,
                           int flip_mirror,
                           actag_detection *out, int max_out, actag_stats *stats,
                           const tracer *tr);

/* *params (validated) with ACTAG_CORRECTIONS_AUTO resolved and the
 * handedness prior turned into the fit decoder's on-screen flags (the
 * decoder's handedness is the reported one, flipped when flip_mirror),
 * into *pe. */
static void resolve_params(const actag_params *params, int flip_mirror, actag_params *pe)
{
    *pe = *params;
    if (pe->handedness != ACTAG_HANDEDNESS_ANY) {
        int mirrored = (pe->handedness == ACTAG_HANDEDNESS_MIRRORED) ^ (flip_mirror != 0);
        pe->tuning.fit.flags &= ~(ACTAG_FIT_ONLY_UNMIRRORED | ACTAG_FIT_ONLY_MIRRORED);
        pe->tuning.fit.flags |= mirrored ? ACTAG_FIT_ONLY_MIRRORED : ACTAG_FIT_ONLY_UNMIRRORED;
    }
    if (pe->max_bit_corrections == ACTAG_CORRECTIONS_AUTO) {
        int maxc = actag_family_max_corrections(pe->family);
        pe->max_bit_corrections = maxc < ACTAG_AUTO_CORRECTIONS ? maxc : ACTAG_AUTO_CORRECTIONS;
    }
}

/* 1. median filter: the frame -> B, each band of rows at its radius (mb,
 * actag__median_bands_of), 16-bit frames scaled to 8 bits a row at a time
 * inside the median's scratch, by the frame's maximum, *max16, which the
 * corner refinement uses again; 0 for 8-bit frames. B is not written again
 * by any later stage, so several parameter sets can share it. */
static int filter_frame(const actag_frame *frame, const ws_layout *w, int rows, int cols,
                        const actag__median_bands *mb, uint32_t *max16)
{
    *max16 = 0u;
    if (frame->depth == 16)
        *max16 = frame16_max((const uint8_t *)frame->data, rows, cols, (size_t)frame->stride);
    return actag__median_filter_bands(frame->data, frame->depth, *max16, rows, cols,
                                      frame->stride, w->b, cols, mb, w->a, w->u_size);
}

int actag_detect(const actag_frame *frame, const actag_sonar_geometry *geometry,
                 const actag_params *params, void *workspace, size_t workspace_size,
                 actag_detection *out, int max_out, actag_stats *stats)
{
    return actag_detect_traced(frame, geometry, params, workspace, workspace_size, out, max_out,
                               stats, NULL, NULL);
}

/* What actag_detect_traced and actag_detect_inplace do before the median:
 * zeroed stats, the checks (actag_check or, in place, actag_check_inplace),
 * the resolved parameters *pe and the frame's handedness flip. */
static int detect_begin(const actag_frame *frame, const actag_sonar_geometry *geometry,
                        const actag_params *params, const void *workspace,
                        size_t workspace_size, const actag_detection *out, int max_out,
                        actag_stats *stats, int inplace, actag_params *pe, int *flip_mirror)
{
    int rc;
    if (stats)
        memset(stats, 0, sizeof *stats);
    /* actag_check's checks first, so that it returns what this would (two
     * direct calls, not a call through a pointer: the stack budget's call
     * graph, tools/budget/budget.py, sees both) */
    if (inplace)
        rc = actag_check_inplace(frame, geometry, params, workspace_size, max_out, NULL);
    else
        rc = actag_check(frame, geometry, params, workspace_size, max_out, NULL);
    if (rc != ACTAG_OK)
        return rc;
    if (workspace == NULL || (out == NULL && max_out > 0))
        return ACTAG_ERR_NULL;
    *flip_mirror = actag_geometry_mirrors(geometry, frame->cols);
    resolve_params(params, *flip_mirror, pe);
    return ACTAG_OK;
}

int actag_detect_traced(const actag_frame *frame, const actag_sonar_geometry *geometry,
                        const actag_params *params, void *workspace, size_t workspace_size,
                        actag_detection *out, int max_out, actag_stats *stats,
                        actag_trace_fn trace, void *user)
{
    tracer tr;
    actag_params pe;
    actag__median_bands mb;
    ws_layout w;
    uint32_t max16;
    int rc, flip_mirror;

    rc = detect_begin(frame, geometry, params, workspace, workspace_size, out, max_out, stats, 0,
                      &pe, &flip_mirror);
    if (rc != ACTAG_OK)
        return rc;
    ws_split(workspace, frame->rows, frame->cols, &w);
    actag__median_bands_of(geometry, frame->rows, frame->cols, &pe, &mb);
    rc = filter_frame(frame, &w, frame->rows, frame->cols, &mb, &max16);
    if (rc != ACTAG_OK)
        return rc;
    tr.fn = trace;
    tr.user = user;
    return detect_filtered(frame, geometry, &pe, &w, max16, frame->rows, frame->cols,
                           flip_mirror, out, max_out, stats, trace ? &tr : NULL);
}

int actag_detect_inplace(const actag_frame *frame, const actag_sonar_geometry *geometry,
                         const actag_params *params, void *workspace, size_t workspace_size,
                         actag_detection *out, int max_out, actag_stats *stats)
{
    actag_params pe;
    actag_frame fb;
    actag__median_bands mb;
    ws_layout w;
    uint8_t *b;
    int rc, flip_mirror;

    rc = detect_begin(frame, geometry, params, workspace, workspace_size, out, max_out, stats, 1,
                      &pe, &flip_mirror);
    if (rc != ACTAG_OK)
        return rc;
    /* the caller's buffer, writable by this function's contract; the
     * filtered frame B goes there (stride cols) */
    b = (uint8_t *)(uintptr_t)frame->data;
    ws_split_inplace(workspace, b, frame->rows, frame->cols, &w);
    actag__median_bands_of(geometry, frame->rows, frame->cols, &pe, &mb);
    rc = actag__median_filter_inplace_bands(b, frame->depth, frame->rows, frame->cols,
                                            frame->stride, 0u, &mb, w.a, w.u_size);
    if (rc != ACTAG_OK)
        return rc;
    /* the raw frame is gone: the corners are refined on B */
    fb = *frame;
    fb.data = b;
    fb.stride = frame->cols;
    fb.depth = 8;
    return detect_filtered(&fb, geometry, &pe, &w, 0u, frame->rows, frame->cols, flip_mirror,
                           out, max_out, stats, NULL);
}

/* A quad fit stopped by a lowered iteration cap (cut 1: the frame's
 * limits.max_frame_iterations, counted per fit; 2: the contour's
 * max_contour_iterations, counted once per contour in *contour_counted). */
static void count_budget(actag_stats *st, int cut, int *contour_counted)
{
    if (cut == 1) {
        st->frame_budget++;
    } else if (!*contour_counted) {
        st->contour_budget++;
        *contour_counted = 1;
    }
}

/* One frame's detection for one resolved parameter set, in progress: what
 * the stages of detect_filtered share. */
typedef struct {
    const ws_layout *w;
    /* the frame's size, geometry and resolved parameters, and the filtered
     * frame and bitmap of w, as the readings see them */
    actag__reader rd;
    int flip_mirror;
    const tracer *tr;
    actag_stats st;
    actag_detection *out;
    int max_out, nout;
    dropped_places dropped; /* tags beyond max_out, by place (record) */
    /* the decoder's fitted-grid corners of out[0 .. REFINE_STARTS-1]: the
     * refinement's second start (refine_det) */
    actag_point fit_start[REFINE_STARTS][4];
    /* the search's tentative readings, their search boxes and kept grids */
    actag_decode_result sk_dr[ACTAG_SEARCH_MAX];
    actag_point sk_box[ACTAG_SEARCH_MAX][4];
    actag__fit_grids sk_grids[ACTAG_SEARCH_MAX];
    int nsk;
    /* search readings that a quad's or guess's reading superseded */
    int sk_used[ACTAG_SEARCH_MAX];
    /* search readings that refused another reading at their place */
    int sk_contested[ACTAG_SEARCH_MAX];
    /* quad and guess readings refused as too close to call (rival_explains) */
    actag__fit_rival held[ACTAG_HELD_MAX];
    int nheld;
    int nguess;      /* contour guesses read, at most ACTAG_GUESS_MAX */
    actag_rng rng;   /* RANSAC's samples, seeded once a frame */
    int frame_iters; /* RANSAC iterations left in the frame */
} frame_run;

/* One size-plausible contour's readings in progress (read_contour). */
typedef struct {
    /* hypotheses of its quads' readings refused as too close to call */
    actag__fit_rival amb[ACTAG_AMB_MAX];
    int namb;
    /* its grid guess gq (grids ggx), once read tentatively by the
     * cross-check (guess_read 1), and kept for the guess stage when it
     * refused the quad's reading (2) */
    int guess_read;
    actag_point gq[4];
    actag__fit_grids ggx;
    int decoded_quads; /* quads that reached the decoder */
} contour_run;

/* The checks every blind reading (a search position's, a contour guess's,
 * a merged blob's box q) passes before it is reported: an accepted
 * verdict becomes ACTAG_TRACE_RIVAL when a rival at its place explains the
 * cells at least as well: the search readings (with_search: those in f,
 * marked contested when they win) or the held hypotheses amb (namb), then
 * the readings of q turned (turned_rival_refuses); and ACTAG_TRACE_TEXTURE
 * when it does not stand out from the texture around it (texture.h).
 * Traced as kind; returns the verdict. */
static inline int judge_blind(frame_run *f, int kind, int verdict, const actag_decode_result *dr,
                              int with_search, const actag__fit_rival *amb, int namb,
                              const actag_point q[4])
{
    if (verdict == ACTAG_TRACE_ACCEPTED &&
        actag__rival_explains(&f->rd, dr, with_search ? f->sk_dr : NULL,
                              with_search ? f->nsk : 0, amb, namb, dr->fit_corners,
                              with_search ? f->sk_contested : NULL))
        verdict = ACTAG_TRACE_RIVAL;
    if (verdict == ACTAG_TRACE_ACCEPTED &&
        actag__turned_rival_refuses(&f->rd, q, dr))
        verdict = ACTAG_TRACE_RIVAL;
    if (verdict == ACTAG_TRACE_ACCEPTED && !actag__texture_ok(&f->rd, dr))
        verdict = ACTAG_TRACE_TEXTURE; /* last, as in read_quads */
    trace_quad(f->tr, kind, verdict, q, 0.0f, verdict == ACTAG_TRACE_NO_MATCH ? NULL : dr);
    return verdict;
}

/* 2. The structure search (before the threshold overwrites A): candidates
 * the contours may miss. Each is read without the template check (the
 * wide reading's costliest part, a full-range polish of every likely
 * hypothesis): a tentative reading. Contours at one get more RANSAC
 * iterations (read_quads), so a tag seen by both reports the quad's
 * corners; a tentative reading that no quad supersedes is read again with
 * the check, from the grids found here, before it is reported
 * (search_readings). On the pool frames most search readings are
 * superseded, so their check was spent for nothing (Cortex-M7: 68.2 -> ~62
 * M instructions per frame). */
static void search_stage(frame_run *f)
{
    const actag_params *params = f->rd.params;
    const ws_layout *w = f->w;
    actag_search z;
    actag_point quad[4];
    int ncand = 0;
    if (params->tuning.search_candidates <= 0)
        return;
    /* the map uses A and M (free until the threshold), the integral image
     * S; a frame too small for them is simply not searched */
    if (actag_search_map(&z, w->b, f->rd.rows, f->rd.cols, f->rd.cols, f->rd.geometry,
                         params->tag_size, params->family->bits,
                         params->tuning.search_range_scale, w->map, w->map_size, w->ii,
                         w->ii_size) != ACTAG_OK)
        return;
    while (ncand < params->tuning.search_candidates &&
           actag_search_next(&z, params->tuning.search_min_score * 8, f->rd.geometry,
                             params->tag_size, params->tuning.search_range_scale, f->rd.rows,
                             f->rd.cols, quad)) {
        actag__fit_grids *gg = &f->sk_grids[f->nsk];
        actag_decode_result dr;
        int verdict;
        ncand++;
        if (!actag__decode_budget(&f->st, params)) {
            /* this candidate, above the least score, is left undecoded */
            f->st.search_cap = 1;
            return;
        }
        f->st.searched++;
        memset(gg, 0, sizeof *gg); /* state 0, not read before */
        gg->blind = 1;             /* a box, not a fitted quad */
        verdict = actag__read_wide(&f->rd, quad, 0, gg, NULL, &dr);
        if (verdict != ACTAG_TRACE_ACCEPTED) {
            /* the check only refuses: no reading either way */
            trace_quad(f->tr, ACTAG_TRACE_SEARCH, verdict, quad, 0.0f,
                       verdict == ACTAG_TRACE_NO_MATCH ? NULL : &dr);
            continue;
        }
        /* kept apart from the others at its place until checked */
        f->sk_dr[f->nsk] = dr;
        memcpy(f->sk_box[f->nsk], quad, sizeof f->sk_box[f->nsk]);
        f->nsk++;
    }
    /* candidates left above the least score: the limit decided */
    if (ncand == params->tuning.search_candidates &&
        actag_search_next(&z, params->tuning.search_min_score * 8, f->rd.geometry, params->tag_size,
                          params->tuning.search_range_scale, f->rd.rows, f->rd.cols, quad))
        f->st.search_cap = 1;
}

/* Corrected bits a merged blob's reading may have, one fewer than a
 * contour's guess (3): its start is blind (where the white square lies in
 * the blob, and how large it is, is unknown). With 3, a far tag was read
 * turned half a turn at hamming 3, margin 3.98 (held-out sweep seed 10708,
 * frame 85, beam spread 0.006 rad). A reading with more is traced as
 * ACTAG_TRACE_MARGIN. */
#define ACTAG_MERGED_CORRECTIONS 2

/* A contour refused by size that may be a white square merged with its
 * neighbours: a guess at its centre (merged_box), judged like a contour's
 * guess, with at most ACTAG_MERGED_CORRECTIONS corrected bits (a blind
 * start inside a corrupted blob: stronger evidence). Returns the reading's
 * corners (in *dr) or NULL. */
static const actag_point *read_merged(frame_run *f, const actag_contour_info *ci,
                                      actag_decode_result *dr)
{
    const actag_params *params = f->rd.params;
    actag_point gq[4];
    actag__fit_grids gg;
    int verdict;
    if (params->tuning.decode_mode != ACTAG_DECODE_FIT ||
        !actag__merged_box(ci, f->rd.geometry, params, f->rd.rows, f->rd.cols, gq))
        return NULL; /* not a merged white square: nothing to read */
    if (actag__guess_on_border(gq, f->rd.rows, f->rd.cols)) {
        trace_quad(f->tr, ACTAG_TRACE_GUESS, ACTAG_TRACE_BORDER, gq, 0.0f, NULL);
        return NULL;
    }
    if (f->nguess >= ACTAG_GUESS_MAX) {
        f->st.guess_cap++;
        return NULL;
    }
    if (!actag__decode_budget(&f->st, params))
        return NULL;
    memset(&gg, 0, sizeof gg);
    gg.blind = 1; /* a box, not a fitted quad */
    f->nguess++;
    verdict = actag__read_guess(&f->rd, &gg, f->held, &f->nheld, gq, dr);
    if (verdict == ACTAG_TRACE_ACCEPTED && dr->hamming > ACTAG_MERGED_CORRECTIONS)
        verdict = ACTAG_TRACE_MARGIN;
    verdict = judge_blind(f, ACTAG_TRACE_GUESS, verdict, dr, 1, NULL, 0, gq);
    /* kept as a contour's guess is (no quad to try) */
    return verdict == ACTAG_TRACE_ACCEPTED ? dr->fit_corners : NULL;
}

/* RANSAC quads of one size-plausible contour (pts, ci), each decoded,
 * until one reads: two tries, ACTAG_SEEK_QUAD_EFFORT at a place the search
 * found a tag, each within the contour's and the frame's iteration limits.
 * A reading is refused by the structure budget, by a search reading that
 * explains its place at least as well (rival_explains) and by the
 * cross-check. Returns ACTAG_OK with the reading in *dr and the quad's
 * RANSAC support in *ratio, or the last try's failure. */
static int read_quads(frame_run *f, const actag_ipoint *pts, const actag_contour_info *ci,
                      void *qscratch, size_t qscratch_size, contour_run *c,
                      actag_decode_result *dr, float *ratio)
{
    const actag_params *params = f->rd.params;
    actag_quad q;
    int k, rc = ACTAG_ERR_NO_QUAD, tries = 2,
           contour_iters = params->tuning.limits.max_contour_iterations, contour_limited = 0;
    /* A contour at a tag the search found gets several RANSAC quads (each
     * the first acceptable one) until one decodes, so the tag is reported
     * with a quad's corners. */
    for (k = 0; k < f->nsk; k++) {
        actag_point m = actag__centre(f->sk_dr[k].fit_corners);
        if (m.x >= (float)ci->min_x && m.x <= (float)ci->max_x && m.y >= (float)ci->min_y &&
            m.y <= (float)ci->max_y) {
            tries = ACTAG_SEEK_QUAD_EFFORT;
            break;
        }
    }
    for (k = 0; k < tries; k++) {
        actag_quad_params qp = params->tuning.quad;
        actag__fit_amb qa;
        /* which limit lowered this fit's cap: 0 none, 1 the frame's, 2 the
         * contour's; counted only when reached (a skipped fit, or one that
         * ran the lowered cap without stopping early) */
        int cut = 0;
        /* iterations: the per-fit limit, within the contour's and the frame's */
        if (qp.max_iterations > contour_iters)
            qp.max_iterations = contour_iters;
        if (qp.max_iterations > f->frame_iters)
            qp.max_iterations = f->frame_iters;
        if (qp.max_iterations < params->tuning.quad.max_iterations)
            cut = f->frame_iters < contour_iters ? 1 : 2;
        if (cut && qp.max_iterations < 1) {
            count_budget(&f->st, cut, &contour_limited);
            return ACTAG_ERR_NO_QUAD;
        }
        q.iterations = 0;
        q.stopped_early = 0;
        rc = actag_quad_fit(pts, ci->stored, &qp, &f->rng, qscratch, qscratch_size, &q);
        contour_iters -= q.iterations;
        f->frame_iters -= q.iterations;
        f->st.iterations += q.iterations;
        if (!q.stopped_early && q.iterations >= qp.max_iterations) {
            f->st.ransac_exhausted++;
            if (cut)
                count_budget(&f->st, cut, &contour_limited);
        }
        if (rc != ACTAG_OK)
            continue; /* another try draws other samples */
        f->st.quads++;
        if (!actag__sides_plausible(q.corners, f->rd.geometry, params, f->rd.rows, f->rd.cols)) {
            trace_quad(f->tr, ACTAG_TRACE_QUAD, ACTAG_TRACE_SIDES, q.corners, q.inlier_ratio,
                       NULL);
            rc = ACTAG_ERR_NO_QUAD;
            continue;
        }
        if (!actag__decode_budget(&f->st, params))
            return ACTAG_ERR_NO_MATCH;
        rc = actag__decode_any(&f->rd, q.corners, &qa, dr);
        if (rc == ACTAG_ERR_NO_MATCH && qa.amb) {
            /* each grid's refused pair: the reading, its rival */
            const actag__fit_rival *pair[2];
            int np = 0, ip;
            pair[np++] = qa.r;
            if (qa.amb2)
                pair[np++] = qa.r2;
            for (ip = 0; ip < np; ip++) {
                if (c->namb + 2 <= ACTAG_AMB_MAX) {
                    c->amb[c->namb++] = pair[ip][0];
                    c->amb[c->namb++] = pair[ip][1];
                }
                actag__hold_pair(f->held, &f->nheld, pair[ip]);
            }
        }
        c->decoded_quads++;
        if (rc != ACTAG_OK) {
            trace_quad(f->tr, ACTAG_TRACE_QUAD, ACTAG_TRACE_NO_MATCH, q.corners, q.inlier_ratio,
                       NULL);
            continue;
        }
        /* the fit decoder's structure gate: black ring and white interior
         * cells on the right side of the mid level */
        if (params->tuning.decode_mode == ACTAG_DECODE_FIT &&
            !actag__structure_ok(dr, params, params->max_bit_corrections)) {
            trace_quad(f->tr, ACTAG_TRACE_QUAD, ACTAG_TRACE_STRUCTURE, q.corners,
                       q.inlier_ratio, dr);
            rc = ACTAG_ERR_NO_MATCH;
            continue;
        }
        /* a search reading here that disagrees and explains the cells at
         * least as well: no reading (another quad may) */
        if (actag__rival_explains(&f->rd, dr, f->sk_dr, f->nsk, NULL, 0, dr->corners,
                                  f->sk_contested)) {
            trace_quad(f->tr, ACTAG_TRACE_QUAD, ACTAG_TRACE_RIVAL, q.corners, q.inlier_ratio,
                       dr);
            rc = ACTAG_ERR_NO_MATCH;
            continue;
        }
        /* Cross-check: a reading with corrected bits is read once more
         * from the contour's own grid guess (the wide search, other grids
         * than the quad's). When that reads another tag, handedness or
         * corner order here, the two are judged as whole templates, each
         * polished over the full range at both places: unless the quad's
         * leads by the least decision margin (the log-likelihood ratio
         * under the template check's noise model; each reading paid its
         * look-elsewhere allowance in its own check), the place has two
         * readings and the quad's is refused; the guess is then judged in
         * its place, against the quad's reading (amb), so it is reported
         * only when it explains the cells better. (Frame 435 of
         * bench/heldout_sweep.py's seed 9609, pool sonar, AcTag24h8: a
         * mirrored tag 27 whose quad read tag 8 unmirrored at hamming 2,
         * margin 4.6; the guess reads tag 27 at hamming 1, margin 9.9; as
         * templates tag 8 leads by 1.0 nat: no reading.) */
        if (params->tuning.decode_mode == ACTAG_DECODE_FIT && dr->hamming >= ACTAG_CROSS_HAMMING &&
            !c->guess_read && f->nguess < ACTAG_GUESS_MAX) {
            c->guess_read = 1;
            if (actag__cross_check(&f->rd, pts, ci->stored, &f->st, &f->nguess, dr, c->gq,
                                   &c->ggx)) {
                trace_quad(f->tr, ACTAG_TRACE_QUAD, ACTAG_TRACE_RIVAL, q.corners,
                           q.inlier_ratio, dr);
                if (c->namb < ACTAG_AMB_MAX)
                    c->amb[c->namb++] = actag__rival_of(dr);
                c->guess_read = 2;
                return ACTAG_ERR_NO_MATCH; /* the guess is read with the check */
            }
        }
        /* last: a blob of the texture (texture.h), after every check whose
         * side effects (held pairs, the guess read) judge other readings */
        if (!actag__texture_ok(&f->rd, dr)) {
            trace_quad(f->tr, ACTAG_TRACE_QUAD, ACTAG_TRACE_TEXTURE, q.corners, q.inlier_ratio,
                       dr);
            rc = ACTAG_ERR_NO_MATCH;
            continue;
        }
        trace_quad(f->tr, ACTAG_TRACE_QUAD, ACTAG_TRACE_ACCEPTED, q.corners, q.inlier_ratio, dr);
        *ratio = q.inlier_ratio;
        return ACTAG_OK;
    }
    return rc;
}

/* 4.-6. One size-plausible contour: its quads (read_quads); when none
 * reads, its extreme points as a first guess for the wide grid search,
 * judged like a search reading (after the cross-check's tentative reading,
 * read again with the template check from its grids). Returns the
 * reading's corners (in *dr, RANSAC support in *ratio, 0 for a guess) or
 * NULL. */
static const actag_point *read_contour(frame_run *f, const actag_ipoint *pts,
                                       const actag_contour_info *ci, void *qscratch,
                                       size_t qscratch_size, actag_decode_result *dr,
                                       float *ratio)
{
    const actag_params *params = f->rd.params;
    contour_run c;
    int rc, verdict, fit = params->tuning.decode_mode == ACTAG_DECODE_FIT;
    c.namb = 0;
    c.guess_read = 0;
    c.decoded_quads = 0;
    rc = read_quads(f, pts, ci, qscratch, qscratch_size, &c, dr, ratio);
    if (rc == ACTAG_OK)
        return dr->corners;
    if (!fit)
        return NULL;
    if (c.guess_read != 2 && f->nguess >= ACTAG_GUESS_MAX) {
        /* counted only where a guess would be read, as read_merged counts:
         * its extreme points found, off the frame's border */
        actag_point gq[4];
        if (actag__extreme_quad(pts, ci->stored, gq) &&
            !actag__guess_on_border(gq, f->rd.rows, f->rd.cols))
            f->st.guess_cap++;
        return NULL;
    }
    verdict = c.guess_read == 2
                  ? actag__read_guess_again(&f->rd, &f->st, &c.ggx, f->held, &f->nheld, c.gq,
                                            dr)
                  : actag__contour_guess(&f->rd, pts, ci->stored, &f->st, c.decoded_quads > 0,
                                         &c.ggx, &f->nguess, f->held, &f->nheld, c.gq, dr);
    if (verdict == ACTAG__GUESS_BORDER) {
        trace_quad(f->tr, ACTAG_TRACE_GUESS, ACTAG_TRACE_BORDER, c.gq, 0.0f, NULL);
        return NULL;
    }
    if (verdict == ACTAG__GUESS_UNREAD ||
        judge_blind(f, ACTAG_TRACE_GUESS, verdict, dr, 1, c.amb, c.namb, c.gq) !=
            ACTAG_TRACE_ACCEPTED)
        return NULL;
    *ratio = 0.0f;
    return dr->fit_corners;
}

/* A reading of a contour, at corners: a detection (record), and the search
 * readings at its place superseded. */
static void keep_reading(frame_run *f, const actag_decode_result *dr, const actag_point *corners,
                         float ratio)
{
    actag_detection d;
    int k;
    f->st.decoded++;
    fill_det(&d, dr, corners, ratio, f->rd.geometry, f->rd.rows, f->rd.cols, f->flip_mirror);
    for (k = 0; k < f->nsk; k++)
        if (actag__same_place(d.corners, f->sk_dr[k].fit_corners))
            f->sk_used[k] = 1;
    record(f->out, f->max_out, &f->nout, &f->st, &f->dropped, &d, dr->fit_corners,
           f->fit_start);
}

/* 4.-6. Contours, one at a time (the scanner over the bitmap A), each
 * through the size filter to its quads and guesses (read_contour), or, too
 * large, to a merged white square's box (read_merged). pts and qscratch:
 * the point buffer (cap points) and the quad fit's scratch in S. */
static int contour_stage(frame_run *f, actag_contour_scanner *scan, actag_ipoint *pts, int cap,
                         void *qscratch, size_t qscratch_size)
{
    const actag_params *params = f->rd.params;
    for (;;) {
        actag_contour_info ci;
        actag_decode_result dr;
        const actag_point *corners;
        float ratio = 0.0f;
        int rc = actag_contour_next(scan, pts, cap, &ci);
        if (rc < 0)
            return rc;
        if (rc == 0)
            return ACTAG_OK;
        /* asked after the next border is found: a frame of exactly
         * max_contours borders has been examined whole */
        if (f->st.contours >= params->tuning.limits.max_contours) {
            f->st.contour_cap = 1; /* the rest of the frame is not examined */
            return ACTAG_OK;
        }
        f->st.contours++;
        if (ci.overflow) {
            f->st.overflowed++;
            trace_contour(f->tr, ACTAG_TRACE_OVERFLOW, pts, &ci);
            continue;
        }
        if (actag__size_plausible(&ci, f->rd.geometry, params, f->rd.rows, f->rd.cols)) {
            trace_contour(f->tr, ACTAG_TRACE_ACCEPTED, pts, &ci);
            f->st.size_ok++;
            corners = read_contour(f, pts, &ci, qscratch, qscratch_size, &dr, &ratio);
        } else {
            trace_contour(f->tr, ACTAG_TRACE_SIZE, pts, &ci);
            corners = read_merged(f, &ci, &dr);
        }
        if (corners != NULL)
            keep_reading(f, &dr, corners, ratio);
    }
}

/* Search readings that no quad superseded: read again with the template
 * check from their grids; of those at one place, record keeps the one with
 * the fewest corrections. A contested one (it refused a quad's or guess's
 * reading that disagreed with it: rival_explains) is not: two readings of
 * one place that each pass their own checks give no reading (a wrong ID is
 * worse than a miss). */
static void search_readings(frame_run *f)
{
    int k;
    for (k = 0; k < f->nsk; k++) {
        actag_decode_result dr;
        actag_detection d;
        int verdict;
        if (f->sk_used[k]) { /* the tentative reading went on, a quad's superseded it */
            f->st.decoded++;
            trace_quad(f->tr, ACTAG_TRACE_SEARCH, ACTAG_TRACE_ACCEPTED, f->sk_box[k], 0.0f,
                       &f->sk_dr[k]);
            continue;
        }
        if (f->sk_contested[k]) {
            trace_quad(f->tr, ACTAG_TRACE_SEARCH, ACTAG_TRACE_RIVAL, f->sk_box[k], 0.0f,
                       &f->sk_dr[k]);
            continue;
        }
        verdict = actag__read_wide(&f->rd, f->sk_box[k], 1, &f->sk_grids[k], NULL, &dr);
        if (judge_blind(f, ACTAG_TRACE_SEARCH, verdict, &dr, 0, f->held, f->nheld,
                        f->sk_box[k]) != ACTAG_TRACE_ACCEPTED)
            continue;
        f->st.decoded++;
        fill_det(&d, &dr, dr.fit_corners, 0.0f, f->rd.geometry, f->rd.rows, f->rd.cols,
                 f->flip_mirror);
        record(f->out, f->max_out, &f->nout, &f->st, &f->dropped, &d, dr.fit_corners,
               f->fit_start);
    }
}

/* Stages 2-7 on a filtered frame (B) for one resolved parameter set. */
static int detect_filtered(const actag_frame *frame, const actag_sonar_geometry *geometry,
                           const actag_params *params,
                           const ws_layout *wl, uint32_t max16, int rows, int cols,
                           int flip_mirror,
                           actag_detection *out, int max_out, actag_stats *stats,
                           const tracer *tr)
{
    frame_run f;
    actag_contour_scanner scan;
    size_t cap, pts_size;
    int rc, k;

    memset(&f, 0, sizeof f);
    f.w = wl;
    f.flip_mirror = flip_mirror;
    f.tr = tr;
    f.out = out;
    f.max_out = max_out;
    f.rd.grey = wl->b;
    f.rd.bin = wl->bin;
    f.rd.rows = rows;
    f.rd.cols = cols;
    f.rd.geometry = geometry;
    f.rd.params = params;
    search_stage(&f);

    /* 3. adaptive threshold: B -> the bitmap A (the search map is done) */
    rc = actag_adaptive_threshold_bitmap(wl->b, rows, cols, cols, wl->bin,
                                         params->tuning.threshold_radius,
                                         params->tuning.threshold_offset, wl->th, wl->th_size);
    if (rc != ACTAG_OK)
        return rc;

    /* 4.-6. contours, one at a time, each through size filter, quad, decode */
    cap = ACTAG_CONTOUR_CAP(rows, cols);
    if ((size_t)params->tuning.limits.max_contour_points < cap)
        cap = (size_t)params->tuning.limits.max_contour_points;
    /* the quad fit takes at most ACTAG_QUAD_MAX_POINTS: a longer border is
     * skipped here and counted in stats.overflowed, as actag.h says, rather
     * than refused by actag_quad_fit without a count or a trace */
    if (cap > (size_t)ACTAG_QUAD_MAX_POINTS)
        cap = (size_t)ACTAG_QUAD_MAX_POINTS;
    pts_size = ACTAG__ALIGN16(ACTAG_CONTOUR_CAP(rows, cols) * sizeof(actag_ipoint));
    f.frame_iters = params->tuning.limits.max_frame_iterations;
    rc = actag_contour_scanner_init(&scan, wl->bin, wl->marks, rows, cols);
    if (rc != ACTAG_OK)
        return rc;
    actag_rng_seed(&f.rng, params->seed);
    rc = contour_stage(&f, &scan, (actag_ipoint *)(void *)wl->s, (int)cap, wl->s + pts_size,
                       wl->s_size - pts_size);
    if (rc != ACTAG_OK)
        return rc;
    search_readings(&f);

    /* 7. the reported tags' corners refined on the caller's frame (refine.h;
     * a 16-bit frame at the median's scale, max16); which tags, IDs,
     * handedness and corner order stay as they are */
    if (params->tuning.refine_corners)
        for (k = 0; k < f.nout && k < max_out; k++)
            refine_det(&out[k], frame, max16, geometry, params,
                       k < REFINE_STARTS ? &f.fit_start[k][0] : NULL);
    if (stats)
        *stats = f.st;
    return f.nout;
}

int actag_detect_multi(const actag_frame *frame, const actag_sonar_geometry *geometry,
                       const actag_params *params, int nparams, void *workspace,
                       size_t workspace_size, actag_detection *out, int max_out_each,
                       int *counts)
{
    ws_layout w;
    actag__median_bands mb0, mb;
    uint32_t max16;
    int rc, rows, cols, flip_mirror, i;
    if (params == NULL || workspace == NULL || counts == NULL ||
        (out == NULL && max_out_each > 0))
        return ACTAG_ERR_NULL;
    if (nparams < 1)
        return ACTAG_ERR_PARAM;
    for (i = 0; i < nparams; i++) {
        rc = actag_check(frame, geometry, &params[i], workspace_size, max_out_each, NULL);
        if (rc != ACTAG_OK)
            return rc;
    }
    rows = frame->rows;
    cols = frame->cols;
    ws_split(workspace, rows, cols, &w);
    flip_mirror = actag_geometry_mirrors(geometry, cols);
    for (i = 0; i < nparams; i++) {
        actag_params pe;
        /* one filtered frame serves every set with the same median radius
         * in every band; a set that needs other radii filters it again */
        actag__median_bands_of(geometry, rows, cols, &params[i], &mb);
        if (i == 0 || !actag__median_bands_equal(&mb, &mb0)) {
            rc = filter_frame(frame, &w, rows, cols, &mb, &max16);
            if (rc != ACTAG_OK)
                return rc;
            mb0 = mb;
        }
        resolve_params(&params[i], flip_mirror, &pe);
        rc = detect_filtered(frame, geometry, &pe, &w, max16, rows, cols, flip_mirror,
                             out ? out + (size_t)i * (size_t)max_out_each : NULL, max_out_each,
                             NULL, NULL);
        if (rc < 0)
            return rc;
        counts[i] = rc;
    }
    return ACTAG_OK;
}
