/* Tag tracking across frames: ROI search, confirmation, smoothing (see actag/track.h). */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/track.h"
#include "track_window.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <string.h>

/* Frames a confirmed track is reported coasting on its prediction. On
 * simulated passes (2026-12-05: actag-eval --frames 0 --sequences 6 --seed
 * 5001, and 10 passes of 20 frames, --seed 7) the predictions of a track's
 * first missed frame lay at the tag in 44 of 46 frames, of its second in 17
 * of 24, of its third to fifth in 9 of 45: the others were wrong places
 * (false tags, corner-order errors). Kept longer, and searched, up to
 * max_missed frames; not reported. Even the first frame's are reported
 * only with params.report_coasting (2026-12-05, after the innovation rule
 * below: 4 of 148 lay off the tag on fast passes, seeds 7-9, and the paper
 * sonar's passes, seeds 5001-5003). */
#define T_REPORT_COAST 1
/* Innovation (reading diagonals) beyond which a reading is taken as read,
 * not smoothed: the smoothing is for corner noise. On the pool sonar's
 * simulated passes (2026-12-05) every innovation was under 0.2 diagonals;
 * the smoothed reports that lay off fast tags (corner-order errors) had
 * innovations of 1.5. */
#define T_MANOEUVRE 0.25f
/* A verify's fitted grid may change shape by at most this many predicted
 * diagonals (t_verify) */
#define T_VERIFY_SHAPE 0.25f
#define T_MIN_ROI ACTAG__TRACK_MIN_WINDOW
/* cells of the track's template that may disagree in a verify reading
 * (t_verify): twice the whole-frame budget */
#define T_VERIFY_BUDGET(limit) (2 * (limit))

void actag_track_params_default(actag_track_params *p)
{
    if (p == NULL)
        return;
    p->full_every = 10;
    p->confirm_frames = 3;
    p->confirm_margin = 15.0f;
    p->max_missed = 5;
    p->roi_scale = 0.5f;
    p->gate = 1.0f;
    p->smoothing = 0.7f;
    p->refind_after = 2;
    p->verify = 1;
    p->report_coasting = 0;
}

/* Every finite float, FLT_MAX included (confirm_margin FLT_MAX: never at
 * once); NaN fails both comparisons. */
static int t_finite(float v) { return v >= -FLT_MAX && v <= FLT_MAX; }

/* The parameters actag_tracker_init accepts (track.h). */
static int t_params_ok(const actag_track_params *p)
{
    return !(p->full_every < 1 || p->confirm_frames < 1 || p->max_missed < 0 ||
             !t_finite(p->confirm_margin) || !t_finite(p->roi_scale) || !(p->roi_scale > 0.0f) ||
             !(p->roi_scale <= 10.0f) || !t_finite(p->gate) || !(p->gate > 0.0f) ||
             !(p->gate <= 10.0f) || !t_finite(p->smoothing) || !(p->smoothing > 0.0f) ||
             !(p->smoothing <= 1.0f) || p->refind_after < 0 ||
             (p->verify != 0 && p->verify != 1) ||
             (p->report_coasting != 0 && p->report_coasting != 1));
}

/* A state actag_tracker_init made and actag_tracker_update kept: a zeroed
 * or overwritten tracker (never initialised: gate 0, a new track ID every
 * frame) is refused rather than run. */
static int t_state_ok(const actag_tracker *t)
{
    int i;
    if (!(t_params_ok(&t->params) && t->ntracks >= 0 && t->ntracks <= ACTAG_TRACK_MAX &&
          t->next_track_id != 0u && t->frame >= 0 && t->last_full >= -1 &&
          t->last_full < t->frame && t->rows >= 0 && t->cols >= 0))
        return 0;
    for (i = 0; i < t->ntracks; i++) /* a live track's ID is never 0 (track.h) */
        if (t->tracks[i].track_id == 0u)
            return 0;
    return 1;
}

int actag_tracker_init(actag_tracker *t, const actag_track_params *p)
{
    if (t == NULL || p == NULL)
        return ACTAG_ERR_NULL;
    if (!t_params_ok(p))
        return ACTAG_ERR_PARAM;
    memset(t, 0, sizeof *t);
    t->params = *p;
    t->last_full = -1;
    t->next_track_id = 1u;
    return ACTAG_OK;
}

/* One step of FNV-1a over 32-bit words (the checksums below). */
#define T_FNV_START 2166136261u
static uint32_t t_fnv(uint32_t h, uint32_t word)
{
    return (h ^ word) * 16777619u;
}

/* Checksum of a family's codes: with bits and ncodes, what the state
 * keeps of its first frame's family. */
static uint32_t t_family_sum(const actag_family *f)
{
    uint32_t h = T_FNV_START;
    int i;
    for (i = 0; i < f->ncodes; i++)
        h = t_fnv(h, f->codes[i]);
    return h;
}

/* One family: the same pointer, or the same bits and codes. */
static int t_same_family(const actag_family *a, const actag_family *b)
{
    return a == b ||
           (a->bits == b->bits && a->ncodes == b->ncodes &&
            (a->codes == b->codes ||
             memcmp(a->codes, b->codes, (size_t)a->ncodes * sizeof *a->codes) == 0));
}

static actag_point t_centre(const actag_point c[4])
{
    actag_point m;
    m.x = 0.25f * (c[0].x + c[1].x + c[2].x + c[3].x);
    m.y = 0.25f * (c[0].y + c[1].y + c[2].y + c[3].y);
    return m;
}

static float t_dist2(actag_point a, actag_point b)
{
    float dx = a.x - b.x, dy = a.y - b.y;
    return dx * dx + dy * dy;
}

/* The track's predicted corners (constant velocity). */
static void t_predict(const actag_track *k, actag_point pred[4])
{
    int i;
    for (i = 0; i < 4; i++) {
        pred[i].x = k->corners[i].x + k->velocity[i].x;
        pred[i].y = k->corners[i].y + k->velocity[i].y;
    }
}

/* The largest distance between a predicted corner and the reading's. */
static float t_innovation(const actag_point pred[4], const actag_point got[4])
{
    float m = 0.0f;
    int i;
    for (i = 0; i < 4; i++) {
        float d = t_dist2(pred[i], got[i]);
        m = d > m ? d : m;
    }
    return actag_sqrtf(m);
}

/* The largest move of a corner about the quad's centre from a to b: the
 * change of shape (size, skew, turn), translation left out. */
static float t_shape_change(const actag_point a[4], const actag_point b[4])
{
    actag_point ca = t_centre(a), cb = t_centre(b);
    float m = 0.0f;
    int i;
    for (i = 0; i < 4; i++) {
        float dx = (b[i].x - cb.x) - (a[i].x - ca.x), dy = (b[i].y - cb.y) - (a[i].y - ca.y);
        float d = dx * dx + dy * dy;
        m = d > m ? d : m;
    }
    return actag_sqrtf(m);
}

static float t_diag(const actag_point c[4])
{
    float a = t_dist2(c[0], c[2]), b = t_dist2(c[1], c[3]);
    return actag_sqrtf(a > b ? a : b);
}

/* Reading-to-track distance limit (pixels): `gate` predicted diagonals,
 * widening while the track coasts. */
static float t_gate(const actag_tracker *t, const actag_track *k, const actag_point pred[4])
{
    return t->params.gate * t_diag(pred) * (1.0f + (float)k->missed) + 2.0f;
}

/* The place of a tracked tag where another ID's reading is ignored
 * (pixels): `gate` predicted diagonals, not widened while the track coasts
 * (the widened gate, meant for finding the track's own tag again, would
 * hide a new tag anywhere near a lost one for max_missed frames). */
static float t_place(const actag_tracker *t, const actag_point pred[4])
{
    return t->params.gate * t_diag(pred) + 2.0f;
}

/* Is there a reading of track k (its ID and handedness) within its gate
 * among the frame's first npool readings? */
static int t_in_pool(const actag_tracker *t, const actag_track *k, int npool)
{
    actag_point pred[4];
    float gate;
    int j;
    t_predict(k, pred);
    gate = t_gate(t, k, pred);
    for (j = 0; j < npool; j++)
        if (t->pool[j].id == k->id && t->pool[j].mirrored == k->mirrored &&
            t_dist2(t_centre(t->pool[j].corners), t_centre(pred)) <= gate * gate)
            return 1;
    return 0;
}

/* Detections are the same tag: same ID and handedness, centres within a
 * quarter diagonal. */
static int t_same(const actag_detection *a, const actag_detection *b)
{
    float d = 0.25f * t_diag(a->corners);
    return a->id == b->id && a->mirrored == b->mirrored &&
           t_dist2(t_centre(a->corners), t_centre(b->corners)) <= d * d + 1.0f;
}

/* Adds t->det[0..n) to the frame's pool (shifted by x0, y0), skipping
 * readings already there. */
static void t_pool_add(actag_tracker *t, int *npool, int n, int x0, int y0, int from)
{
    int i, j, c;
    for (i = 0; i < n; i++) {
        actag_detection d = t->det[i];
        for (c = 0; c < 4; c++) {
            d.corners[c].x += (float)x0;
            d.corners[c].y += (float)y0;
        }
        for (j = 0; j < *npool; j++)
            if (t_same(&t->pool[j], &d))
                break;
        if (j < *npool || *npool >= ACTAG_TRACK_MAX_DET)
            continue;
        t->pool[*npool] = d;
        t->pool_from_roi[*npool] = from;
        (*npool)++;
    }
}

/* The whole tag's side over the inner square's for the family (7/3 for 24 bits). */
static float t_extent(const actag_params *p)
{
    int k = p->family != NULL ? p->family->bits / 4 : 6;
    return k > 3 ? (float)(k + 1) / (float)(k - 3) : 1.0f;
}

int actag__track_window(const actag_point pred[4], float extent, float grow, float pad, int rows,
                        int cols, int *x0, int *y0, int *x1, int *y1)
{
    actag_point c = t_centre(pred);
    float minx = 3.0e38f, maxx = -3.0e38f, miny = 3.0e38f, maxy = -3.0e38f, hx, hy;
    int i;
    for (i = 0; i < 4; i++) {
        if (pred[i].x < minx) minx = pred[i].x;
        if (pred[i].x > maxx) maxx = pred[i].x;
        if (pred[i].y < miny) miny = pred[i].y;
        if (pred[i].y > maxy) maxy = pred[i].y;
    }
    hx = 0.5f * (maxx - minx) * extent;
    hy = 0.5f * (maxy - miny) * extent;
    hx = hx * (1.0f + grow) + pad;
    hy = hy * (1.0f + grow) + pad;
    if (hx < 0.5f * T_MIN_ROI)
        hx = 0.5f * T_MIN_ROI;
    if (hy < 0.5f * T_MIN_ROI)
        hy = 0.5f * T_MIN_ROI;
    if (!(c.x - hx > -1.0e7f && c.x + hx < 1.0e7f && c.y - hy > -1.0e7f && c.y + hy < 1.0e7f))
        return -1;
    *x0 = (int)(c.x - hx < 0.0f ? 0.0f : c.x - hx);
    *x1 = (int)(c.x + hx);
    *y0 = (int)(c.y - hy < 0.0f ? 0.0f : c.y - hy);
    *y1 = (int)(c.y + hy);
    if (*x1 > cols - 1) *x1 = cols - 1;
    if (*y1 > rows - 1) *y1 = rows - 1;
    /* keep the minimum size inside the frame */
    if (*x1 - *x0 + 1 < T_MIN_ROI) {
        *x0 = *x1 - T_MIN_ROI + 1 < 0 ? 0 : *x1 - T_MIN_ROI + 1;
        *x1 = *x0 + T_MIN_ROI - 1 > cols - 1 ? cols - 1 : *x0 + T_MIN_ROI - 1;
    }
    if (*y1 - *y0 + 1 < T_MIN_ROI) {
        *y0 = *y1 - T_MIN_ROI + 1 < 0 ? 0 : *y1 - T_MIN_ROI + 1;
        *y1 = *y0 + T_MIN_ROI - 1 > rows - 1 ? rows - 1 : *y0 + T_MIN_ROI - 1;
    }
    if (*x1 < *x0 || *y1 < *y0)
        return -1;
    return *x1 - *x0 + 1 > ACTAG_TRACK_ROI_MAX_COLS ? -1 : 0;
}

/* ROI of a track: its window (actag__track_window) around its predicted
 * corners, in the tracker's frame size. */
static int t_roi(const actag_tracker *t, const actag_track *k, const actag_params *p, float grow,
                 float pad, int *x0, int *y0, int *x1, int *y1)
{
    actag_point pred[4];
    t_predict(k, pred);
    return actag__track_window(pred, t_extent(p), grow, pad, t->rows, t->cols, x0, y0, x1, y1);
}

/* actag_detect() on the ROI view; readings into t->det, how many (0 for a
 * window the detector refuses). */
static int t_detect_roi(actag_tracker *t, const actag_frame *frame,
                        const actag_sonar_geometry *g, const actag_params *p, void *ws,
                        size_t wss, int x0, int y0, int x1, int y1, actag_stats *ds)
{
    actag_frame sub;
    actag_sonar_geometry sg;
    int w = x1 - x0 + 1, h = y1 - y0 + 1, j, n;
    size_t off = (size_t)y0 * (size_t)frame->stride + (size_t)x0;
    float ra, rb;
    memset(ds, 0, sizeof *ds); /* no detection ran: nothing counted */
    /* One range row (a frame of one row) holds no tag, and its window
     * would span no range (min_range = max_range: no geometry at all) */
    if (h < 2)
        return 0;
    ra = actag_geometry_range(g, frame->rows, (float)y0);
    rb = actag_geometry_range(g, frame->rows, (float)y1);
    sub = *frame;
    /* bytes, not a uint16_t pointer: a 16-bit frame may start at an odd
     * address (actag.h), where such a pointer would be undefined */
    sub.data = (const void *)((const uint8_t *)frame->data +
                              (frame->depth == 16 ? 2u * off : off));
    sub.rows = h;
    sub.cols = w;
    for (j = 0; j < w; j++)
        t->bearings[j] = actag_geometry_azimuth(g, frame->cols, (float)(x0 + j));
    sg.bearings = t->bearings;
    sg.aperture = 0.0f;
    sg.flags = g->flags & ACTAG_RANGE_ASCENDING;
    sg.min_range = ra < rb ? ra : rb;
    sg.max_range = ra < rb ? rb : ra;
    /* A window the detector refuses holds no tag it could read: the
     * parameters and the frame passed their checks, so only the window's
     * own geometry can fail, e.g. a window at the sonar (a track coasting
     * past the near edge) whose far range is below tag_size / sqrt 2.
     * (actag_detect checks it; a second actag_check would scan the
     * family's codes again for every window.) */
    n = actag_detect(&sub, &sg, p, ws, wss, t->det, ACTAG_TRACK_MAX_DET, ds);
    if (n < 0) {
        memset(ds, 0, sizeof *ds);
        return 0;
    }
    return n;
}

static void t_add_stats(actag_track_stats *st, const actag_stats *ds)
{
    st->quads += ds->quads;
    st->decoded += ds->decoded;
    st->searched += ds->searched;
}

/* Half the cell width w (pixels), rounded down, at least 1, at most r0
 * (NaN: 1): the verify's radius, and the cap of the ROI searches' bands.
 * Not the whole frame's rule per range band (median_bands.h, a
 * window of half a cell plus 2 pixels, at least 2): w here is the predicted
 * cell's least width, which a grazing view narrows along range, and on the
 * pool sonar's simulated passes this rule reads more (633 against 629 of
 * 634 frames; the pool recording 41 against 39 of 47; docs/tracking.md). */
static int t_window_radius(float w, int r0)
{
    int r = !(w >= 2.0f) ? 1 : w >= 2.0f * (float)r0 + 2.0f ? r0 : (int)(0.5f * w);
    return r < r0 ? r : r0;
}

/* The parameters a track's window is read with: p's, but a median radius of
 * at most half the track's predicted cell width (pixels: the cell's least
 * width, its area over its longer side; at least 1, never above p's). The
 * median is there against speckle; a window wider than a cell erases the
 * cells of a small or far tag, which the whole-frame radius is not set for
 * (the paper's sonar at 3-4.5 m: cells 2-4 px wide; measured in
 * docs/tracking.md). */
static void t_window_params(const actag_track *k, const actag_params *p, actag_params *out)
{
    actag_point q[4];
    const float s = (float)(p->family->bits / 4 - 3); /* cells across the white square */
    float ax, ay, bx, by, cross, la, lb, w;
    *out = *p;
    t_predict(k, q);
    ax = (q[1].x - q[0].x) / s;
    ay = (q[1].y - q[0].y) / s;
    bx = (q[3].x - q[0].x) / s;
    by = (q[3].y - q[0].y) / s;
    cross = ax * by - ay * bx;
    la = ax * ax + ay * ay;
    lb = bx * bx + by * by;
    w = (cross < 0.0f ? -cross : cross) / actag_sqrtf(la > lb ? la : lb);
    out->tuning.median_radius = t_window_radius(w, p->tuning.median_radius);
}

/* The verify's reading (t_verify) of the track's code on grey (the w x h
 * window) from the prediction q (window coordinates) with the fit
 * parameters fa (the track's handedness, the pipeline's margin, with or
 * without ACTAG_FIT_WIDE), under the rules below: 1 with the reading in
 * *dr, 0 for none. */
static int t_read_at(const uint8_t *grey, int w, int h, const actag_point q[4],
                     const actag_track *k, const actag_params *p, const actag_fit_params *fa,
                     int limit, int flip, actag_decode_result *dr)
{
    /* Only the track's own code is a hypothesis here: another ID at the
     * prediction could not update the track anyway, so the reading is
     * judged against "no tag" (the decision margin) and the rotations of
     * this one code in the track's handedness, not against the family's
     * other codes. */
    actag_fit_params fp = *fa;
    actag_family own = *p->family;
    int kk, misses;
    float ring, in;
    own.codes = p->family->codes + k->id;
    own.ncodes = 1;
    /* no other code is a hypothesis, so none can lie as near as the read
     * one: the extra margin at the correction limit is moot */
    fp.many_corrections_margin = 0.0f;
    if (actag_decode_quad_fit(grey, h, w, w, q, &own, limit, &fp, dr) != ACTAG_OK)
        return 0;
    dr->id = k->id;
    kk = p->family->bits / 4;
    ring = (float)(4 * (kk - 2));
    in = (float)((kk - 3) * (kk - 3));
    misses = (int)((1.0f - dr->ring_black) * ring + 0.5f) +
             (int)((1.0f - dr->interior_white) * in + 0.5f);
    /* One template of bits + ring + interior cells (49 for 24-bit tags)
     * instead of the family's codes: T_VERIFY_BUDGET(limit) cells may
     * disagree in all (ring, interior and data together), where a whole-frame
     * reading may have `limit`. By chance a pattern of random cells lies that
     * close to one given 49-cell template with probability
     * sum_{e<=6} C(49,e) / 2^49 < 1e-7 per verify. */
    if ((dr->mirrored ^ flip) != k->mirrored || dr->ring_black < p->tuning.min_structure ||
        dr->interior_white < p->tuning.min_structure || misses + dr->hamming > T_VERIFY_BUDGET(limit))
        return 0;
    /* A verify refines the prediction: its grid may move, but in one ping the
     * tag's image keeps its shape to a few pixels. A grid whose corners,
     * about their centre, moved by more than T_VERIFY_SHAPE of the predicted
     * diagonal was sheared onto other structure (2026-12-05: a right ID at
     * hamming 2 with two corners 35 px off, one diagonal; a corner-order
     * error), not the tag read. */
    if (!(t_shape_change(q, dr->fit_corners) <= T_VERIFY_SHAPE * t_diag(q))) /* NaN too */
        return 0;
    /* But another tag where the track is predicted (a neighbour the
     * prediction drifted onto, a tag put in its place) can read as the
     * track's code when that code is the only hypothesis: its template
     * polish bends the grid toward it (simulated swaps of the tracked tag 5
     * for tag 4: 2 of 96 passes read tag 5 there, hamming 3, margins 13 and
     * 20). A reading with corrected bits is therefore read again from the
     * prediction against the whole family, in the track's handedness,
     * under the pipeline's rules: a reading of another ID there refuses it. */
    if (dr->hamming > 0) {
        actag_decode_result da;
        if (actag_decode_quad_fit(grey, h, w, w, q, p->family, limit, fa, &da) == ACTAG_OK &&
            da.id != k->id)
            return 0;
    }
    return 1;
}

/* The tracked tag read where it is predicted: the ROI median-filtered and
 * the grid-fitting decoder started on the predicted corners, with the
 * pipeline's trust rules (likelihood match, template check, margin,
 * structure budget). Only the track's own ID and handedness count. On
 * success t->det[0] holds the reading (frame coordinates, fitted-grid
 * corners) and 1 is returned; 0 means "run the ROI detector". 8-bit frames
 * with the fit decoder only. */
static int t_verify(actag_tracker *t, const actag_track *k, const actag_frame *frame,
                    const actag_sonar_geometry *g, const actag_params *p, void *ws,
                    actag_track_stats *st)
{
    actag_point q[4];
    actag_decode_result dr;
    actag_fit_params fa;
    uint8_t *grey;
    int x0, y0, x1, y1, w, h, c, limit, rc, flip;
    if (frame->depth != 8 || p->tuning.decode_mode != ACTAG_DECODE_FIT || !t->params.verify)
        return 0;
    /* the track's code is read from p's family (actag_tracker_update keeps
     * it the tracks' family; this guards the array read) */
    if (k->id < 0 || k->id >= p->family->ncodes)
        return 0;
    if (t_roi(t, k, p, 0.25f, (float)(p->tuning.median_radius + 2), &x0, &y0, &x1, &y1) != 0)
        return 0;
    w = x1 - x0 + 1;
    h = y1 - y0 + 1;
    grey = (uint8_t *)(((uintptr_t)ws + 15u) & ~(uintptr_t)15u);
    /* the workspace holds a whole frame's images and scratch: room for both */
    rc = actag_median_filter((const uint8_t *)frame->data + (size_t)y0 * (size_t)frame->stride +
                                 (size_t)x0,
                             h, w, frame->stride, grey, w, p->tuning.median_radius,
                             grey + (((size_t)w * (size_t)h + 15u) & ~(size_t)15u),
                             ACTAG_MEDIAN_SCRATCH_SIZE(h, w));
    st->verified++;
    st->pixels += (long)w * (long)h;
    if (rc != ACTAG_OK)
        return 0;
    t_predict(k, q);
    for (c = 0; c < 4; c++) {
        q[c].x -= (float)x0;
        q[c].y -= (float)y0;
    }
    limit = p->max_bit_corrections;
    if (limit == ACTAG_CORRECTIONS_AUTO) {
        int m = actag_family_max_corrections(p->family);
        limit = m < ACTAG_AUTO_CORRECTIONS ? m : ACTAG_AUTO_CORRECTIONS;
    }
    /* handedness relative to the reference orientation (as actag_detect) */
    flip = actag_geometry_mirrors(g, frame->cols);
    /* the pipeline's fit parameters (the user's margin wins, as in
     * actag_detect) in the track's own handedness only (on screen: flipped
     * with the image) */
    fa = p->tuning.fit;
    fa.min_margin = p->min_margin;
    fa.flags &= ~(ACTAG_FIT_ONLY_UNMIRRORED | ACTAG_FIT_ONLY_MIRRORED);
    fa.flags |= (k->mirrored ^ flip) ? ACTAG_FIT_ONLY_MIRRORED : ACTAG_FIT_ONLY_UNMIRRORED;
    /* A prediction without a velocity (one reading so far) or after a
     * missed frame can lie a cell or more off: a sonar passing at a few
     * knots moves a far tag's image about a cell a ping, and the track
     * coasted where it was. When the reading in place fails there, the
     * grid is searched +-1 cell about the prediction (ACTAG_FIT_WIDE), as
     * a first guess of a tag's grid is (read in place first: the wide
     * search picks its start by a code-agnostic score and can settle a
     * cell off a tag that reads in place). docs/tracking.md, thirty-eighth
     * session: simulated passes of the paper's sonar 815 -> 826 of 851
     * frames, where the frame after a one-reading confirmation had been
     * missed, and every frame of the coast after it. */
    if (!t_read_at(grey, w, h, q, k, p, &fa, limit, flip, &dr)) {
        if (!(k->hits < 2 || k->missed > 0))
            return 0;
        fa.flags |= ACTAG_FIT_WIDE;
        if (!t_read_at(grey, w, h, q, k, p, &fa, limit, flip, &dr))
            return 0;
    }
    memset(&t->det[0], 0, sizeof t->det[0]);
    t->det[0].id = dr.id;
    t->det[0].hamming = dr.hamming;
    t->det[0].mirrored = k->mirrored;
    t->det[0].decision_margin = dr.decision_margin;
    t->det[0].inlier_ratio = 0.0f; /* no quad: as the structure search's readings */
    for (c = 0; c < 4; c++) {
        t->det[0].corners[c].x = dr.fit_corners[c].x + (float)x0;
        t->det[0].corners[c].y = dr.fit_corners[c].y + (float)y0;
        t->det[0].range[c] = actag_geometry_range(g, frame->rows, t->det[0].corners[c].y);
        t->det[0].azimuth[c] = actag_geometry_azimuth(g, frame->cols, t->det[0].corners[c].x);
    }
    st->readings++;
    return 1;
}

/* A checksum of a geometry's bearing table (0: none), so that a table
 * changed in place is seen as a new geometry. */
static uint32_t t_bearings_sum(const actag_sonar_geometry *g, int cols)
{
    uint32_t h = T_FNV_START, b;
    int c;
    if (g->bearings == NULL)
        return 0u;
    for (c = 0; c < cols; c++) {
        memcpy(&b, &g->bearings[c], sizeof b); /* the float's bits */
        h = t_fnv(h, b);
    }
    return h | 1u; /* never 0 */
}

/* Is g another geometry than the one the tracks were last placed in? */
static int t_geometry_changed(const actag_tracker *t, const actag_sonar_geometry *g,
                              uint32_t bsum)
{
    /* a bearing table overrides the aperture and ACTAG_AZIMUTH_ASCENDING */
    unsigned used = g->bearings == NULL ? ~0u : ~(unsigned)ACTAG_AZIMUTH_ASCENDING;
    return g->min_range != t->geo_min_range || g->max_range != t->geo_max_range ||
           (g->bearings == NULL && g->aperture != t->geo_aperture) ||
           (g->flags & used) != (t->geo_flags & used) || bsum != t->geo_bearings_sum;
}

/* max(m, |d|); a NaN d counts as a move (no libm: firmware links none) */
static float t_absmax(float m, float d)
{
    float a = d < 0.0f ? -d : d;
    if (a != a)
        return 1e30f;
    return a > m ? a : m;
}

/* The tracks moved into a new geometry: each smoothed corner to the pixel
 * of its range and azimuth (kept from the last frame). Its velocity is
 * carried over through the old mapping when that can be rebuilt (no
 * bearing table: the old table may have been changed in place), else
 * restarted. A track no corner or velocity of which moves by more than
 * 0.01 px is left as it was (a driver that recomputes max_range every ping
 * changes the geometry by an ulp). `last` stays the reading as returned. */
static void t_reproject(actag_tracker *t, const actag_sonar_geometry *g, int rows, int cols)
{
    actag_sonar_geometry old;
    /* pixel velocities convert only through a frame whose rows and columns
     * span a range and an arc (a frame of one row or column maps every
     * pixel to one range or azimuth): else they restart at 0 */
    int i, c, known = t->geo_bearings_sum == 0u && t->rows > 1 && t->cols > 1 && rows > 1 &&
                      cols > 1;
    old.min_range = t->geo_min_range;
    old.max_range = t->geo_max_range;
    old.aperture = t->geo_aperture;
    old.bearings = NULL;
    old.flags = t->geo_flags;
    for (i = 0; i < t->ntracks; i++) {
        actag_track *k = &t->tracks[i];
        actag_point nc[4], nv[4];
        float moved = 0.0f;
        for (c = 0; c < 4; c++) {
            nc[c].x = actag_geometry_column(g, cols, k->azimuth[c]);
            nc[c].y = actag_geometry_row(g, rows, k->range[c]);
            nv[c].x = nv[c].y = 0.0f;
            if (known) { /* the predicted corner, old pixels -> metres -> new pixels */
                float px = k->corners[c].x + k->velocity[c].x;
                float py = k->corners[c].y + k->velocity[c].y;
                nv[c].x = actag_geometry_column(g, cols, actag_geometry_azimuth(&old, t->cols, px)) -
                          nc[c].x;
                nv[c].y = actag_geometry_row(g, rows, actag_geometry_range(&old, t->rows, py)) -
                          nc[c].y;
            }
            moved = t_absmax(moved, nc[c].x - k->corners[c].x);
            moved = t_absmax(moved, nc[c].y - k->corners[c].y);
            moved = t_absmax(moved, nv[c].x - k->velocity[c].x);
            moved = t_absmax(moved, nv[c].y - k->velocity[c].y);
        }
        if (!(moved > 0.01f))
            continue;
        memcpy(k->corners, nc, sizeof nc);
        memcpy(k->velocity, nv, sizeof nv);
    }
}

/* The track's corners in metres and radians. A frame of one row (column)
 * has no range (azimuth) axis: every pixel maps to one range (azimuth),
 * so the track keeps the place it had, and finds it again in the next
 * frame that has the axis (t_reproject). */
/* Restarts the filter of track k, of one reading, from two: its corners
 * (that reading's, in this frame's pixels: t_reproject moves them, not
 * k->last, when the sonar's setting changes) and d's, frames later: the
 * corners d's, the velocity their displacement per frame. */
static void t_from_two(actag_track *k, const actag_detection *d, int frames)
{
    float inv = 1.0f / (float)(frames > 0 ? frames : 1);
    int c;
    for (c = 0; c < 4; c++) {
        k->velocity[c].x = (d->corners[c].x - k->corners[c].x) * inv;
        k->velocity[c].y = (d->corners[c].y - k->corners[c].y) * inv;
        k->corners[c] = d->corners[c];
    }
}

/* Has the track's centre left the frame (the tag has left the view: it
 * can be read no more, and its prediction leads nowhere)? Not along an
 * axis the frame does not have (one row or column: see t_polar). */
static int t_left_frame(const actag_track *k, int rows, int cols)
{
    actag_point c = t_centre(k->corners);
    return (rows > 1 && !(c.y >= 0.0f && c.y <= (float)(rows - 1))) ||
           (cols > 1 && !(c.x >= 0.0f && c.x <= (float)(cols - 1)));
}

static void t_polar(const actag_sonar_geometry *g, int rows, int cols, actag_track *k)
{
    int i;
    for (i = 0; i < 4; i++) {
        if (rows > 1)
            k->range[i] = actag_geometry_range(g, rows, k->corners[i].y);
        if (cols > 1)
            k->azimuth[i] = actag_geometry_azimuth(g, cols, k->corners[i].x);
    }
}

int actag_tracker_update(actag_tracker *t, const actag_frame *frame,
                         const actag_sonar_geometry *geometry, const actag_params *params,
                         const actag_params *roi_params, void *workspace, size_t workspace_size,
                         actag_track *out, int max_out, actag_track_stats *stats)
{
    actag_track_stats st;
    actag_stats ds;
    const actag_params *rp = roi_params != NULL ? roi_params : params;
    long cur;
    int rc, i, j, npool = 0, need_full, nconf = 0, nout = 0;
    int assigned[ACTAG_TRACK_MAX], used[ACTAG_TRACK_MAX_DET], pass;
    /* verified in step 1: a second try in step 2 would repeat the same
     * decode at the same prediction */
    int tried[ACTAG_TRACK_MAX];
    uint32_t fsum, bsum;
    float alpha, beta;

    memset(&st, 0, sizeof st);
    if (stats)
        *stats = st;
    if (t == NULL)
        return ACTAG_ERR_NULL;
    if (!t_state_ok(t))
        return ACTAG_ERR_PARAM; /* not counted: the state is not one to count in */
    if (t->frame == LONG_MAX) {
        /* a count at its end (2^31 frames of a 32-bit long: 1.7 years at
         * 40 Hz) goes on from full_every + 1, the last whole-frame search
         * kept as far back (or none: one more whole-frame search); at most
         * from LONG_MAX - 1, so that neither the sum nor the increment
         * below overflows where long is as narrow as int (ILP32) */
        long back = t->last_full >= 0 ? t->frame - t->last_full : -1;
        long every = t->params.full_every;
        t->frame = every < LONG_MAX - 1 ? every + 1 : LONG_MAX - 1;
        t->last_full = back >= 0 && back <= t->frame ? t->frame - back : -1;
    }
    cur = t->frame++; /* every frame fed counts, failed ones too (track.h) */
    /* actag_detect's checks (actag_check) for both parameter sets first, so
     * that a call actag_check refuses gets its code (track.h) */
    rc = actag_check(frame, geometry, params, workspace_size, max_out, NULL);
    if (rc == ACTAG_OK && roi_params != NULL)
        rc = actag_check(frame, geometry, roi_params, workspace_size, max_out, NULL);
    if (rc != ACTAG_OK)
        return rc;
    if (workspace == NULL || (out == NULL && max_out > 0))
        return ACTAG_ERR_NULL;
    /* A track is started by a whole-frame reading (params) and read in its
     * window (roi_params): its ID must name the same code in both, and in
     * every frame of the stream. */
    fsum = t_family_sum(params->family);
    if (!t_same_family(params->family, rp->family) ||
        (t->rows != 0 && (params->family->bits != t->family_bits ||
                          params->family->ncodes != t->family_ncodes || fsum != t->family_sum)))
        return ACTAG_ERR_PARAM;
    bsum = t_bearings_sum(geometry, frame->cols);
    if (t->rows != 0 && (frame->rows != t->rows || frame->cols != t->cols ||
                         t_geometry_changed(t, geometry, bsum)))
        t_reproject(t, geometry, frame->rows, frame->cols);
    t->geo_min_range = geometry->min_range;
    t->geo_max_range = geometry->max_range;
    t->geo_aperture = geometry->aperture;
    t->geo_flags = geometry->flags;
    t->geo_bearings_sum = bsum;
    t->rows = frame->rows;
    t->cols = frame->cols;
    t->family_bits = params->family->bits;
    t->family_ncodes = params->family->ncodes;
    t->family_sum = fsum;

    for (i = 0; i < t->ntracks; i++)
        nconf += t->tracks[i].confirmed;
    need_full = nconf == 0 || t->last_full < 0 || cur - t->last_full >= t->params.full_every;
    for (i = 0; i < t->ntracks; i++)
        tried[i] = 0;

    /* 1. ROIs around every track (unless the whole frame is due anyway) */
    if (!need_full) {
        for (i = 0; i < t->ntracks; i++) {
            int x0, y0, x1, y1, n;
            actag_params rw; /* rp with the track's median radius */
            t_window_params(&t->tracks[i], rp, &rw);
            tried[i] = t->tracks[i].confirmed;
            if (t->tracks[i].confirmed && t_verify(t, &t->tracks[i], frame, geometry, &rw,
                                                   workspace, &st)) {
                t_pool_add(t, &npool, 1, 0, 0, i);
                continue;
            }
            if (t_roi(t, &t->tracks[i], &rw, t->params.roi_scale,
                      (float)(rw.tuning.median_radius + rw.tuning.threshold_radius + 4), &x0, &y0,
                      &x1, &y1) != 0) {
                need_full = 1;
                continue;
            }
            {
                /* A track never changes handedness, so its window is read in
                 * the track's own: the other handedness' views (for the
                 * published families, the nearest rivals of a code) are no
                 * hypotheses there. Tags of the other handedness in the
                 * window are left to the whole-frame searches. */
                actag_params rk = rw;
                if (rk.handedness == ACTAG_HANDEDNESS_ANY)
                    rk.handedness = t->tracks[i].mirrored ? ACTAG_HANDEDNESS_MIRRORED
                                                          : ACTAG_HANDEDNESS_UNMIRRORED;
                n = t_detect_roi(t, frame, geometry, &rk, workspace, workspace_size, x0, y0, x1,
                                 y1, &ds);
            }
            t_add_stats(&st, &ds);
            st.rois++;
            st.pixels += (long)(x1 - x0 + 1) * (long)(y1 - y0 + 1);
            st.readings += n; /* t_detect_roi: >= 0 */
            t_pool_add(t, &npool, n, x0, y0, i);
        }
        if (t->params.refind_after && !need_full) {
            /* a confirmed track with no reading of its own in its ROI */
            for (i = 0; i < t->ntracks && !need_full; i++) {
                const actag_track *k = &t->tracks[i];
                int found = 0;
                if (!k->confirmed || k->missed < t->params.refind_after - 1)
                    continue;
                for (j = 0; j < npool; j++)
                    if (t->pool[j].id == k->id && t->pool[j].mirrored == k->mirrored)
                        found = 1;
                if (!found)
                    need_full = 1;
            }
        }
    }
    /* 2. the whole frame */
    if (need_full) {
        int n = actag_detect(frame, geometry, params, workspace, workspace_size, t->det,
                             ACTAG_TRACK_MAX_DET, &ds);
        t_add_stats(&st, &ds);
        if (n < 0)
            return n;
        st.full_frame = 1;
        st.pixels += (long)frame->rows * (long)frame->cols;
        st.readings += n;
        t_pool_add(t, &npool, n, 0, 0, -1);
        t->last_full = cur;
        /* a confirmed track the whole frame did not read is still read
         * where it is predicted (one window and one decode), unless step 1
         * tried that already */
        for (i = 0; i < t->ntracks; i++) {
            actag_params rw;
            if (!t->tracks[i].confirmed || tried[i] || t_in_pool(t, &t->tracks[i], npool))
                continue;
            t_window_params(&t->tracks[i], rp, &rw);
            if (t_verify(t, &t->tracks[i], frame, geometry, &rw, workspace, &st))
                t_pool_add(t, &npool, 1, 0, 0, i);
        }
    }

    /* 3. assign readings to tracks: own ID and handedness, nearest to the
     * prediction within the gate; tracks in order (oldest first) */
    for (j = 0; j < npool; j++)
        used[j] = 0;
    for (i = 0; i < t->ntracks; i++)
        assigned[i] = -1;
    for (pass = 0; pass < 2; pass++) {
        for (i = 0; i < t->ntracks; i++) {
            actag_point pred[4], pc;
            float gate, best = 3.0e38f;
            int bj = -1, anywhere;
            if (assigned[i] >= 0 || (pass == 1 && t->tracks[i].hits != 1))
                continue;
            t_predict(&t->tracks[i], pred);
            pc = t_centre(pred);
            /* the gate widens while a track coasts; pass 1 within the gates,
             * pass 2: a track of one reading has no velocity, so no prediction
             * of where its tag went: its second reading is the nearest of its
             * ID and handedness that no track took in pass 1, anywhere (the
             * third must then fall where the two predict) */
            anywhere = pass == 1;
            gate = t_gate(t, &t->tracks[i], pred);
            for (j = 0; j < npool; j++) {
                float d2;
                if (used[j] || t->pool[j].id != t->tracks[i].id ||
                    t->pool[j].mirrored != t->tracks[i].mirrored)
                    continue;
                d2 = t_dist2(t_centre(t->pool[j].corners), pc);
                if ((anywhere || d2 <= gate * gate) && d2 < best) {
                    best = d2;
                    bj = j;
                }
            }
            if (bj >= 0) {
                assigned[i] = bj;
                used[bj] = 1;
            }
        }
    }
    /* readings at a tracked tag's place that are not its own: ignored */
    for (j = 0; j < npool; j++) {
        if (used[j])
            continue;
        for (i = 0; i < t->ntracks; i++) {
            actag_point pred[4];
            float gate;
            t_predict(&t->tracks[i], pred);
            gate = t_place(t, pred);
            if (t_dist2(t_centre(t->pool[j].corners), t_centre(pred)) <= gate * gate)
                break;
        }
        if (i < t->ntracks) {
            used[j] = 2;
            st.conflicts++;
        }
    }

    /* 4. update, coast or drop the tracks */
    alpha = t->params.smoothing;
    beta = alpha * alpha / (2.0f - alpha);
    for (i = 0; i < t->ntracks; i++) {
        actag_track *k = &t->tracks[i];
        actag_point pred[4];
        int c;
        t_predict(k, pred);
        k->age += k->age < INT_MAX; /* counts saturate (a tag in view for years) */
        if (assigned[i] >= 0) {
            const actag_detection *d = &t->pool[assigned[i]];
            k->innovation = t_innovation(pred, d->corners);
            if (k->hits == 1) {
                /* the second reading: the filter starts from the two
                 * (no velocity was known, so the prediction was only the
                 * first reading's place) */
                t_from_two(k, d, k->missed < INT_MAX ? k->missed + 1 : INT_MAX);
            } else {
                /* smoothing averages the corners' noise (a pixel or two);
                 * a reading more than a quarter of its diagonal from the
                 * prediction is a tag that moved otherwise than foreseen,
                 * and a filtered place would lag it by (1 - alpha) of
                 * that: the reading's corners are taken as they are */
                const int as_read = !(k->innovation <= T_MANOEUVRE * t_diag(d->corners));
                for (c = 0; c < 4; c++) {
                    float rx = d->corners[c].x - pred[c].x, ry = d->corners[c].y - pred[c].y;
                    if (as_read) {
                        k->corners[c] = d->corners[c];
                    } else {
                        k->corners[c].x = pred[c].x + alpha * rx;
                        k->corners[c].y = pred[c].y + alpha * ry;
                    }
                    k->velocity[c].x += beta * rx;
                    k->velocity[c].y += beta * ry;
                }
            }
            k->hits += k->hits < INT_MAX;
            k->missed = 0;
            k->measured = 1;
            k->last = *d;
            if (!k->confirmed && (k->hits >= t->params.confirm_frames ||
                                  d->decision_margin >= t->params.confirm_margin)) {
                k->confirmed = 1;
                st.confirmed++;
            }
        } else {
            for (c = 0; c < 4; c++) {
                k->corners[c] = pred[c];
                k->velocity[c].x *= 0.5f;
                k->velocity[c].y *= 0.5f;
            }
            if (k->missed < INT_MAX) /* saturates, as hits and age do */
                k->missed++;
            k->measured = 0;
        }
    }
    for (i = 0; i < t->ntracks;) {
        const actag_track *k = &t->tracks[i];
        if (k->missed > 0 && (!k->confirmed || k->missed > t->params.max_missed ||
                              t_left_frame(k, frame->rows, frame->cols))) {
            for (j = i; j + 1 < t->ntracks; j++) {
                t->tracks[j] = t->tracks[j + 1];
                assigned[j] = assigned[j + 1];
            }
            t->ntracks--;
            st.dropped++;
        } else {
            i++;
        }
    }
    /* 5. new tentative tracks from the remaining readings; but a reading of
     * a track's own tag that its gate missed (the tag moved farther than
     * foreseen, e.g. between whole-frame searches) re-acquires that track
     * when it got no reading this frame: a second track of one tag would be
     * confirmed at once by a strong margin and reported beside the old one
     * while that coasts */
    for (j = 0; j < npool; j++) {
        actag_track *k;
        if (used[j])
            continue;
        for (i = 0; i < t->ntracks; i++)
            if (!t->tracks[i].measured && t->tracks[i].id == t->pool[j].id &&
                t->tracks[i].mirrored == t->pool[j].mirrored)
                break;
        if (i < t->ntracks) {
            /* where it is now, no velocity: the old one led elsewhere */
            k = &t->tracks[i];
            /* step 4 put its corners at this frame's prediction */
            k->innovation = t_innovation(k->corners, t->pool[j].corners);
            memcpy(k->corners, t->pool[j].corners, sizeof k->corners);
            memset(k->velocity, 0, sizeof k->velocity);
            k->missed = 0;
            k->measured = 1;
            k->hits += k->hits < INT_MAX;
            k->last = t->pool[j];
            continue;
        }
        if (t->ntracks >= ACTAG_TRACK_MAX)
            continue;
        k = &t->tracks[t->ntracks++];
        memset(k, 0, sizeof *k);
        k->track_id = t->next_track_id;
        /* after 2^32 - 1 tracks the IDs start again at 1 (0 is never one) */
        t->next_track_id = t->next_track_id == UINT32_MAX ? 1u : t->next_track_id + 1u;
        k->id = t->pool[j].id;
        k->mirrored = t->pool[j].mirrored;
        memcpy(k->corners, t->pool[j].corners, sizeof k->corners);
        k->hits = 1;
        k->measured = 1;
        k->age = 1;
        k->last = t->pool[j];
        k->confirmed = t->params.confirm_frames <= 1 ||
                       t->pool[j].decision_margin >= t->params.confirm_margin;
        st.started++;
        st.confirmed += k->confirmed;
    }

    /* 6. report the confirmed tracks read in this frame; with
     * report_coasting a coasting one as well, but only once it has a
     * velocity (two readings): after a single reading its prediction is
     * that reading's place, wherever the tag has moved since (it stays a
     * track, and its window is still searched); and only on the first
     * frame it misses (T_REPORT_COAST): a prediction further on is no
     * place to put a landmark */
    for (i = 0; i < t->ntracks; i++) {
        actag_track *k = &t->tracks[i];
        int c;
        t_polar(geometry, frame->rows, frame->cols, k);
        if (!k->confirmed ||
            (!k->measured && (!t->params.report_coasting || k->hits < 2 ||
                              k->missed > T_REPORT_COAST)))
            continue;
        if (nout < max_out) {
            out[nout] = *k;
            /* a coasting track's corner may lie past the near edge, where
             * the geometry's linear map gives ranges below min_range: none
             * below 0 is reported (the state keeps the map's, which
             * t_reproject reads) */
            for (c = 0; c < 4; c++)
                if (!(out[nout].range[c] >= 0.0f))
                    out[nout].range[c] = 0.0f;
        }
        nout++;
    }
    if (stats)
        *stats = st;
    return nout < max_out ? nout : max_out;
}
