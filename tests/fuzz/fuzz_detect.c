/*
 * fuzz_detect.c -- libFuzzer harness for actag_detect (and actag_detect_multi).
 *
 * Every input (format: fuzz_detect_case.h) is one call on an arbitrary
 * frame (size, stride, depth, alignment, pixels), geometry (ranges,
 * aperture, flags, bearing table), family, every parameter, output count
 * and workspace size/alignment. The call must:
 *   - touch nothing outside the caller's buffers: guard bytes (poisoned under
 *     AddressSanitizer) around the workspace, the frame, the bearing table
 *     and the output array; the frame (with its row padding), the bearing
 *     table, the geometry and the parameters unmodified;
 *   - return only documented codes, and an error exactly when a validator
 *     rejects the input (NULL pointers, frame size/stride/depth,
 *     actag_params_validate, actag_geometry_validate, workspace size), with
 *     the code of one of the rejecting checks;
 *   - when it succeeds: at most max_out sane detections (IDs in the family,
 *     hamming within the corrections, finite corners, polar values from the
 *     geometry) and consistent counters; the same result again after the
 *     workspace was filled with garbage;
 *   - with actag_detect_multi: each set exactly its own actag_detect call;
 *   - actag_detect_inplace (median radius <= 7) on a guarded copy of the
 *     frame with a guarded workspace of exactly its size: writes only within
 *     the frame's extent and the workspace, and gives actag_detect's tags,
 *     IDs, handedness, hamming, margins, support and statistics (the
 *     corners too when refine_corners is 0; refined, they are finite).
 * Validator completeness: when the validators accept, the stages accept the
 * same parameters too (RANSAC, the fit decoder, threshold, median filter):
 * an accepted parameter that a stage rejects would be swallowed as "no tags".
 */
#include "fuzz_detect_case.h"

#include "actag/actag.h"
#include "actag/render.h"

#define ERRBIT(code) (1u << (unsigned)(-(code)))

static int sizes_ok(int rows, int cols, int stride, int depth)
{
    return rows >= 1 && cols >= 1 && rows <= ACTAG_MAX_DIM && cols <= ACTAG_MAX_DIM &&
           stride >= cols && (depth == 8 || depth == 16);
}

/* 8-bit value of the pattern at (r, c). */
static unsigned pattern(const fzd_case *c, int r, int col, uint32_t *rng, const uint8_t *tagimg,
                        int tagside, int tr, int tc)
{
    unsigned a = (unsigned)c->pix_a, b = (unsigned)c->pix_b;
    switch (c->pix_mode) {
    case FZD_PIX_CONST: return a & 255u;
    case FZD_PIX_CHECKER: {
        unsigned s = 1u + a % 64u;
        return (((unsigned)r / s + (unsigned)col / s) & 1u) ? 255u : (b & 63u);
    }
    case FZD_PIX_SPECKLE: return (fz_xs(rng) & 255u) < (a & 255u) ? 200u + (b & 55u) : (b & 15u);
    case FZD_PIX_BLOBS: {
        unsigned s = 1u + a % 32u, t = s + 1u + b % 32u;
        return ((unsigned)r % t < s && (unsigned)col % t < s) ? 255u : 10u;
    }
    case FZD_PIX_NOISE: return fz_xs(rng) & 255u;
    case FZD_PIX_TAG: {
        int y = r - tr, x = col - tc;
        unsigned noise = fz_xs(rng) & 31u;
        if (tagimg && y >= 0 && x >= 0 && y < tagside && x < tagside) {
            unsigned v = tagimg[(size_t)y * (size_t)tagside + (size_t)x];
            return v > 128u ? v - noise : v + noise;
        }
        return 20u + noise;
    }
    case FZD_PIX_STRIPES: {
        unsigned s = 1u + a % 16u;
        return ((((b & 1u) ? (unsigned)col : (unsigned)r) / s) & 1u) ? 230u : 25u;
    }
    default: return 0u;
    }
}

/* Fills the frame (tight buffer: the last row has no padding), padding
 * bytes with a pattern the call must leave alone. */
static void fill_frame(const fzd_case *c, uint8_t *buf, size_t bytes, int rows, int cols,
                       int stride, int bpp, const actag_family *fam)
{
    uint32_t rng = c->pix_seed | 1u;
    uint8_t *tagimg = NULL;
    int tagside = 0, tr = 0, tc = 0, r, col;
    size_t k = 0, i;
    for (i = 0; i < bytes; i++)
        buf[i] = (uint8_t)(0x5Au ^ (uint8_t)i);
    if (c->pix_mode == FZD_PIX_TAG && fam) {
        int cell = 1 + c->pix_a % 12;
        tagside = actag_render_side(fam->bits, cell, cell);
        if (tagside > 0 && tagside <= 400) {
            tagimg = (uint8_t *)malloc((size_t)tagside * (size_t)tagside);
            /* the family may be one of the harness's invalid ones (no codes):
             * ID 0 then, and actag_render_tag must refuse it */
            int id = fam->ncodes > 0 ? (int)(c->pix_seed % (uint32_t)fam->ncodes) : 0;
            if (tagimg &&
                actag_render_tag(fam, id, cell, cell, 0,
                                 0, tagimg, tagside,
                                 (size_t)tagside * (size_t)tagside) != ACTAG_OK) {
                free(tagimg);
                tagimg = NULL;
            }
            tr = (int)((unsigned)c->pix_b % (unsigned)(rows > 1 ? rows : 1));
            tc = (int)(((unsigned)c->pix_b >> 8) % (unsigned)(cols > 1 ? cols : 1));
        }
    }
    for (r = 0; r < rows; r++)
        for (col = 0; col < cols; col++) {
            size_t at = ((size_t)r * (size_t)stride + (size_t)col) * (size_t)bpp;
            unsigned v;
            if (c->pix_mode == FZD_PIX_INPUT) {
                if (c->npixels) {
                    buf[at] = c->pixels[k++ % c->npixels];
                    if (bpp == 2)
                        buf[at + 1] = c->pixels[k++ % c->npixels];
                } else {
                    buf[at] = 0;
                    if (bpp == 2)
                        buf[at + 1] = 0;
                }
                continue;
            }
            v = pattern(c, r, col, &rng, tagimg, tagside, tr, tc);
            if (bpp == 1) {
                buf[at] = (uint8_t)v;
            } else {
                /* host-order 16-bit sample, written bytewise (buf may be odd) */
                uint16_t s = (uint16_t)(v * 257u ^ (fz_xs(&rng) & 0x7fu));
                memcpy(buf + at, &s, 2);
            }
        }
    free(tagimg);
}

/* Which error codes the validators allow for these arguments (0: none, the
 * call must succeed). */
static unsigned expected_errors(const actag_frame *frame, const actag_sonar_geometry *geo,
                                const actag_params *p, const void *ws, size_t ws_size,
                                const actag_detection *out, int max_out)
{
    unsigned mask = 0;
    int sz;
    if (!frame || !geo || !p || !ws || (frame && !frame->data) || (!out && max_out > 0))
        mask |= ERRBIT(ACTAG_ERR_NULL);
    if (!frame)
        return mask;
    sz = sizes_ok(frame->rows, frame->cols, frame->stride, frame->depth);
    if (!sz)
        mask |= ERRBIT(ACTAG_ERR_SIZE);
    if (max_out < 0)
        mask |= ERRBIT(ACTAG_ERR_PARAM);
    if (p) {
        int rc = actag_params_validate(p, NULL);
        if (rc != ACTAG_OK)
            mask |= ERRBIT(rc);
    }
    if (geo && sz) {
        int rc = actag_geometry_validate(geo, frame->rows, frame->cols, NULL);
        if (rc != ACTAG_OK)
            mask |= ERRBIT(rc);
    }
    if (sz && ws_size < actag_workspace_size(frame->rows, frame->cols))
        mask |= ERRBIT(ACTAG_ERR_WORKSPACE);
    /* the rules across structs (tag size against the range, least range and
     * azimuth steps, output count), which only actag_check() knows */
    if (frame->data && geo && p && sz) {
        int rc = actag_check(frame, geo, p, ws_size, max_out, NULL);
        if (rc != ACTAG_OK)
            mask |= ERRBIT(rc);
    }
    return mask;
}

/* Validator completeness: the stages accept what actag_params_validate
 * accepted (p already validated; corrections resolved as the pipeline does).
 * The validators of src/validate.c cover every stage's rule (quad.min_inlier_ratio,
 * quad.inlier_distance, fit.min_bit_margin included), so any refusal by a
 * stage is a finding; FZ_LAX_VALIDATORS accepts ACTAG_ERR_PARAM there. */
#ifndef FZ_LAX_VALIDATORS
#define FZ_STAGE_CHECK(cond, ...) FZ_CHECK(cond, __VA_ARGS__)
#else
#define FZ_STAGE_CHECK(cond, ...) FZ_CHECK((cond) || rc == ACTAG_ERR_PARAM, __VA_ARGS__)
#endif
static void check_stages_accept(const actag_params *p)
{
    static const actag_ipoint sq[40] = {
        {0, 0},  {1, 0},  {2, 0},  {3, 0},  {4, 0},  {5, 0},  {6, 0},  {7, 0},  {8, 0},  {9, 0},
        {10, 0}, {10, 1}, {10, 2}, {10, 3}, {10, 4}, {10, 5}, {10, 6}, {10, 7}, {10, 8}, {10, 9},
        {10, 10}, {9, 10}, {8, 10}, {7, 10}, {6, 10}, {5, 10}, {4, 10}, {3, 10}, {2, 10}, {1, 10},
        {0, 10}, {0, 9},  {0, 8},  {0, 7},  {0, 6},  {0, 5},  {0, 4},  {0, 3},  {0, 2},  {0, 1}};
    static uint8_t img[48 * 48], out[48 * 48];
    static uint8_t scratch[ACTAG_QUAD_SCRATCH_SIZE(40)];
    static uint8_t tscratch[ACTAG_THRESHOLD_SCRATCH_SIZE_R(48, 48, ACTAG_MAX_THRESHOLD_RADIUS)];
    static uint8_t mscratch[ACTAG_MEDIAN_SCRATCH_SIZE(48, 48)];
    actag_rng rng;
    actag_quad q;
    actag_decode_result dr;
    actag_point quad[4] = {{14, 14}, {33, 14}, {33, 33}, {14, 33}};
    int rc, maxc = p->max_bit_corrections, i;
    if (maxc == ACTAG_CORRECTIONS_AUTO) {
        maxc = actag_family_max_corrections(p->family);
        maxc = maxc < ACTAG_AUTO_CORRECTIONS ? maxc : ACTAG_AUTO_CORRECTIONS;
    }
    for (i = 0; i < 48 * 48; i++)
        img[i] = (uint8_t)(i * 7u);
    actag_rng_seed(&rng, p->seed);
    rc = actag_quad_fit(sq, 40, &p->tuning.quad, &rng, scratch, sizeof scratch, &q);
    FZ_STAGE_CHECK(rc == ACTAG_OK || rc == ACTAG_ERR_NO_QUAD,
             "validated quad parameters rejected by actag_quad_fit (%d: %s)", rc,
             actag_strerror(rc));
    rc = actag_decode_quad_fit(img, 48, 48, 48, quad, p->family, maxc, &p->tuning.fit, &dr);
    FZ_STAGE_CHECK(rc == ACTAG_OK || rc == ACTAG_ERR_NO_MATCH,
             "validated fit parameters rejected by actag_decode_quad_fit (%d: %s)", rc,
             actag_strerror(rc));
    rc = actag_adaptive_threshold(img, 48, 48, 48, out, 48, p->tuning.threshold_radius,
                                  p->tuning.threshold_offset, tscratch, sizeof tscratch);
    FZ_CHECK(rc == ACTAG_OK, "validated threshold parameters rejected (%d: %s)", rc,
             actag_strerror(rc));
    rc = actag_median_filter(img, 48, 48, 48, out, 48, p->tuning.median_radius, mscratch,
                             sizeof mscratch);
    FZ_CHECK(rc == ACTAG_OK, "validated median radius rejected (%d: %s)", rc, actag_strerror(rc));
}

static void check_detections(const actag_detection *det, int n, const actag_params *p,
                             const actag_stats *st)
{
    int i, c, maxc = p->max_bit_corrections;
    if (maxc == ACTAG_CORRECTIONS_AUTO) {
        maxc = actag_family_max_corrections(p->family);
        maxc = maxc < ACTAG_AUTO_CORRECTIONS ? maxc : ACTAG_AUTO_CORRECTIONS;
    }
    for (i = 0; i < n; i++) {
        const actag_detection *d = &det[i];
        FZ_CHECK(d->id >= 0 && d->id < p->family->ncodes, "detection %d: id %d", i, d->id);
        FZ_CHECK(d->hamming >= 0 && d->hamming <= maxc, "detection %d: hamming %d > %d", i,
                 d->hamming, maxc);
        FZ_CHECK(d->mirrored == 0 || d->mirrored == 1, "detection %d: mirrored %d", i,
                 d->mirrored);
        for (c = 0; c < 4; c++) {
            FZ_CHECK(isfinite(d->corners[c].x) && isfinite(d->corners[c].y),
                     "detection %d: corner %d not finite", i, c);
            FZ_CHECK(!isnan(d->range[c]) && !isnan(d->azimuth[c]),
                     "detection %d: polar corner %d NaN", i, c);
        }
        FZ_CHECK(!isnan(d->decision_margin) && !isnan(d->inlier_ratio),
                 "detection %d: NaN margin/ratio", i);
    }
    if (st) {
        FZ_CHECK(st->contours >= 0 && st->size_ok >= 0 && st->size_ok <= st->contours &&
                     st->overflowed >= 0 && st->quads >= 0 && st->decoded >= 0 &&
                     st->duplicates >= 0 && st->dropped >= 0 && st->searched >= 0,
                 "inconsistent stats");
        FZ_CHECK(n <= st->decoded, "%d detections from %d decoded", n, st->decoded);
    }
}

/* actag_detect_inplace against the call that gave out[0..n-1] (*st when not
 * NULL); the frame's fbytes bytes are copied into a guarded buffer. */
static void check_inplace(const actag_frame *frame, const actag_sonar_geometry *geo,
                          const actag_params *p, size_t fbytes, unsigned fmis, unsigned wmis,
                          const actag_detection *out, int n, int max_out, const actag_stats *st)
{
    fz_guarded gf = {0}, gw = {0};
    actag_frame f = *frame;
    actag_stats s2;
    actag_detection *o2 = (actag_detection *)malloc(((size_t)max_out + 1) * sizeof *o2);
    size_t wsz = actag_workspace_size_inplace(frame->rows, frame->cols);
    uint8_t *buf = fz_guard_alloc(&gf, fbytes, fmis);
    void *w = fz_guard_alloc(&gw, wsz, wmis);
    int n2, i, c;
    FZ_CHECK(o2 != NULL, "oom");
    memcpy(buf, frame->data, fbytes);
    f.data = buf;
    n2 = actag_detect_inplace(&f, geo, p, w, wsz, o2, max_out, &s2);
    fz_guard_check(&gf, "frame (in place)");
    fz_guard_check(&gw, "workspace (in place)");
    FZ_CHECK(n2 == n, "in place: %d tags (%s), actag_detect %d", n2,
             n2 < 0 ? actag_strerror(n2) : "ok", n);
    FZ_CHECK(!st || memcmp(st, &s2, sizeof s2) == 0, "in place: other stats");
    for (i = 0; i < n; i++) {
        FZ_CHECK(o2[i].id == out[i].id && o2[i].hamming == out[i].hamming &&
                     o2[i].mirrored == out[i].mirrored &&
                     memcmp(&o2[i].decision_margin, &out[i].decision_margin, sizeof(float)) == 0 &&
                     memcmp(&o2[i].inlier_ratio, &out[i].inlier_ratio, sizeof(float)) == 0,
                 "in place: detection %d differs", i);
        for (c = 0; c < 4; c++)
            FZ_CHECK(isfinite(o2[i].corners[c].x) && isfinite(o2[i].corners[c].y),
                     "in place: detection %d corner %d not finite", i, c);
    }
    FZ_CHECK(p->tuning.refine_corners || n == 0 || memcmp(o2, out, (size_t)n * sizeof *out) == 0,
             "in place, no refinement: other detections");
    free(o2);
    fz_guard_free(&gf);
    fz_guard_free(&gw);
}

/* How many inputs gave tags, said when the replay ends: the checks of each
 * detection above (and in place) run only on those, so the CTest replay
 * requires at least one (a corpus without a tag once left them unrun). */
static long fzd_with_tags;

static void fzd_say_tags(void)
{
    printf("fuzz_detect: %ld inputs with tags\n", fzd_with_tags);
}

static void fzd_count_tags(int n)
{
    if (n > 0 && fzd_with_tags++ == 0)
        atexit(fzd_say_tags);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fzd_case c;
    actag_family fam, *famp = NULL;
    actag_params params, params_copy;
    actag_sonar_geometry geo, geo_copy;
    actag_frame frame, *framep = &frame;
    actag_stats st, st2, *stp;
    fz_guarded gframe = {0}, gbear = {0}, gws = {0}, gout = {0};
    uint8_t *fbuf, *fcopy = NULL, *bcopy = NULL;
    float *bear = NULL;
    actag_detection *out, *out2 = NULL;
    void *ws;
    size_t fbytes, ws_size, need = 0;
    int rows, cols, stride, bpp, n, n2, i, nfam = actag_family_count(), max_out;
    unsigned mask;

    fzd_decode(&c, data, size);

    /* family */
    if (c.fam_sel % (nfam + 5) < nfam) {
        actag_family_get_at(c.fam_sel % (nfam + 5), &fam);
        if (c.fam_subset % 4 == 3) /* a valid sub-family: its first codes */
            fam.ncodes = 1 + (c.fam_subset >> 2) % fam.ncodes;
        famp = &fam;
    } else {
        actag_family_get_at(0, &fam);
        switch (c.fam_sel % (nfam + 5) - nfam) {
        case 0: fam.bits = 12 + 4 * (c.fam_subset % 8); break; /* 12, 36, ...: invalid */
        case 1: fam.ncodes = 0; break;
        case 2: fam.codes = NULL; break;
        case 3: fam.hamming = 0; break;
        default: famp = NULL; break; /* params.family NULL */
        }
        if (c.fam_sel % (nfam + 5) - nfam < 4)
            famp = &fam;
    }
    params = c.p;
    params.family = famp;

    /* frame: a tight, guarded buffer (misaligned as asked) */
    rows = c.rows;
    cols = c.cols;
    stride = c.stride;
    bpp = c.depth == 16 ? 2 : 1;
    if (sizes_ok(rows, cols, stride, c.depth)) {
        /* cut big frames down: fewer rows, then fewer columns */
        if ((size_t)cols > FZD_MAX_PIXELS)
            cols = (int)FZD_MAX_PIXELS;
        if (stride < cols)
            stride = cols;
        if (rows > 1 && (uint64_t)(rows - 1) * (uint64_t)stride + (uint64_t)cols > FZD_MAX_PIXELS)
            rows = 1 + (int)((FZD_MAX_PIXELS - (uint64_t)cols) / (uint64_t)stride);
        fbytes = ((size_t)(rows - 1) * (size_t)stride + (size_t)cols) * (size_t)bpp;
    } else {
        fbytes = 64; /* the call must not read it */
    }
    fbuf = fz_guard_alloc(&gframe, fbytes, c.frame_misalign);
    if (sizes_ok(rows, cols, stride, c.depth))
        fill_frame(&c, fbuf, fbytes, rows, cols, stride, bpp, famp && famp->codes ? famp : NULL);
    else
        memset(fbuf, 0x33, fbytes);
    fcopy = (uint8_t *)malloc(fbytes);
    FZ_CHECK(fcopy != NULL, "oom");
    memcpy(fcopy, fbuf, fbytes);
    frame.data = fbuf;
    frame.rows = rows;
    frame.cols = cols;
    frame.stride = stride;
    frame.depth = c.depth;

    /* geometry and bearing table */
    geo = c.geo;
    geo.bearings = NULL;
    if (c.bear_mode != 0 && cols >= 1 && cols <= 40000) {
        size_t nb = (size_t)cols, k = 0;
        size_t rest;
        const uint8_t *raw = c.pixels;
        bear = (float *)(void *)fz_guard_alloc(&gbear, nb * sizeof(float), 0);
        rest = c.npixels;
        for (i = 0; i < cols; i++) {
            float t = cols > 1 ? (float)i / (float)(cols - 1) : 0.0f;
            switch (c.bear_mode) {
            case 1: bear[i] = 0.5f * geo.aperture - t * geo.aperture; break;
            case 2: bear[i] = -0.5f * geo.aperture + t * geo.aperture; break;
            case 3:
                if (rest >= 4 * (k + 1)) {
                    memcpy(&bear[i], raw + 4 * k, 4);
                    k++;
                } else {
                    bear[i] = (float)i;
                }
                break;
            case 4: bear[i] = 0.5f - 0.01f * (float)(i == cols / 2 ? i - 1 : i); break;
            case 5: bear[i] = i == cols / 3 ? NAN : 0.5f - 0.01f * (float)i; break;
            default: bear[i] = c.bear_start + (float)i * c.bear_step; break;
            }
        }
        bcopy = (uint8_t *)malloc(nb * sizeof(float));
        FZ_CHECK(bcopy != NULL, "oom");
        memcpy(bcopy, bear, nb * sizeof(float));
        geo.bearings = bear;
    }

    /* output and workspace */
    max_out = c.max_out > 64 ? 64 : c.max_out; /* the output buffer holds no more */
    out = (actag_detection *)(void *)fz_guard_alloc(
        &gout, (size_t)(max_out > 0 ? max_out : 0) * sizeof(actag_detection), 0);
    if (sizes_ok(rows, cols, stride, c.depth))
        need = actag_workspace_size(rows, cols);
    switch (c.ws_mode) {
    case 0: ws_size = need; break;
    case 1: ws_size = need ? need - 1 : 0; break;
    case 2: ws_size = need + (size_t)(c.ws_extra % 4096); break;
    case 3: ws_size = 0; break;
    default: ws_size = need + (size_t)c.ws_extra; break;
    }
    ws = fz_guard_alloc(&gws, ws_size, c.ws_misalign);
    for (i = 0; i < (int)(ws_size < 4096 ? ws_size : 4096); i++) /* stale contents */
        ((uint8_t *)ws)[i] = (uint8_t)(i * 13u);

    /* pointers made NULL on request */
    {
        const actag_sonar_geometry *geop = &geo;
        const actag_params *pp = &params;
        void *wsp = ws;
        actag_detection *outp = out;
        stp = c.no_stats ? NULL : &st;
        switch (c.null_sel) {
        case 0: framep = NULL; break;
        case 1: frame.data = NULL; break;
        case 2: geop = NULL; break;
        case 3: pp = NULL; break;
        case 4: params.family = NULL; break;
        case 5: wsp = NULL; break;
        case 6: outp = NULL; break;
        case 7: stp = NULL; break;
        default: break;
        }
        params_copy = params;
        geo_copy = geo;
        mask = expected_errors(framep, geop, pp, wsp, ws_size, outp, max_out);
        n = actag_detect(framep, geop, pp, wsp, ws_size, outp, max_out, stp);

        /* untouched inputs and guards */
        fz_guard_check(&gframe, "frame");
        FZ_CHECK(memcmp(fcopy, fbuf, fbytes) == 0, "frame (or its row padding) modified");
        if (bear) {
            fz_guard_check(&gbear, "bearings");
            FZ_CHECK(memcmp(bcopy, bear, (size_t)cols * sizeof(float)) == 0, "bearings modified");
        }
        fz_guard_check(&gws, "workspace");
        fz_guard_check(&gout, "output");
        FZ_CHECK(memcmp(&params_copy, &params, sizeof params) == 0, "params modified");
        FZ_CHECK(memcmp(&geo_copy, &geo, sizeof geo) == 0, "geometry modified");

        /* an error exactly when a validator rejects, with one of its codes */
        if (mask) {
            FZ_CHECK(n < 0, "returned %d although the validators reject (mask %#x)", n, mask);
            FZ_CHECK(n >= ACTAG_ERR_NO_QUAD && (mask & ERRBIT(n)),
                     "error %d (%s) is not one of the rejecting checks' (mask %#x)", n,
                     actag_strerror(n), mask);
            goto done;
        }
        FZ_CHECK(n >= 0, "error %d (%s) although every validator accepts", n, actag_strerror(n));
        FZ_CHECK(n <= max_out, "%d detections > max_out %d", n, max_out);
        check_stages_accept(&params);
        check_detections(out, n, &params, stp);
        fzd_count_tags(n);

        /* the same again on a scrambled workspace */
        {
            uint32_t s = c.pix_seed ^ 0xdeadbeefu;
            size_t k;
            for (k = 0; k < ws_size; k++)
                ((uint8_t *)ws)[k] = (uint8_t)fz_xs(&s);
            out2 = (actag_detection *)malloc(((size_t)max_out + 1) * sizeof(actag_detection));
            FZ_CHECK(out2 != NULL, "oom");
            n2 = actag_detect(framep, geop, pp, wsp, ws_size, out2, max_out, &st2);
            FZ_CHECK(n2 == n, "second call on a scrambled workspace: %d tags, first %d", n2, n);
            FZ_CHECK(n == 0 || memcmp(out, out2, (size_t)n * sizeof *out) == 0,
                     "second call on a scrambled workspace: other detections");
            FZ_CHECK(!stp || memcmp(stp, &st2, sizeof st2) == 0,
                     "second call on a scrambled workspace: other stats");
            fz_guard_check(&gws, "workspace (second call)");
        }

        /* in place: the same tags from the small workspace */
        if (params.tuning.median_radius <= ACTAG_MEDIAN_INPLACE_MAX_RADIUS)
            check_inplace(framep, geop, &params, fbytes, c.frame_misalign, c.ws_misalign,
                          out, n, max_out, stp);

        /* several sets at once: each exactly its own call */
        if (c.multi && max_out > 0) {
            actag_params sets[2];
            actag_detection *mout, *single;
            int counts[2], rc, j;
            sets[0] = params;
            sets[1] = params;
            sets[1].seed = params.seed + 1u;
            sets[1].tuning.search_candidates = params.tuning.search_candidates ? 0 : 1;
            mout = (actag_detection *)malloc(2u * (size_t)max_out * sizeof *mout);
            single = (actag_detection *)malloc((size_t)max_out * sizeof *single);
            FZ_CHECK(mout && single, "oom");
            rc = actag_detect_multi(framep, geop, sets, 2, wsp, ws_size, mout, max_out, counts);
            FZ_CHECK(rc == ACTAG_OK, "actag_detect_multi: %d (%s)", rc, actag_strerror(rc));
            for (j = 0; j < 2; j++) {
                int ns = actag_detect(framep, geop, &sets[j], wsp, ws_size, single, max_out, NULL);
                FZ_CHECK(ns == counts[j], "multi set %d: %d tags, alone %d", j, counts[j], ns);
                FZ_CHECK(ns <= 0 || memcmp(single, mout + (size_t)j * (size_t)max_out,
                                           (size_t)ns * sizeof *single) == 0,
                         "multi set %d: other detections than alone", j);
            }
            free(mout);
            free(single);
            fz_guard_check(&gws, "workspace (multi)");
        }
    }
done:
    free(out2);
    free(fcopy);
    free(bcopy);
    fz_guard_free(&gframe);
    fz_guard_free(&gbear);
    fz_guard_free(&gws);
    fz_guard_free(&gout);
    return 0;
}
