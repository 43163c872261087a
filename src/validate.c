/* The rules for every input of the pipeline, one validator per struct, and
 * the error detail they report (ERROR DETAILS in actag.h). The stages call
 * the validator of the struct they take (quad.c, decode_fit.c, search.c), and
 * actag_detect() calls actag_check(), so a value is accepted or rejected by
 * the same code wherever it enters. No state: every message is a string
 * literal. */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/actag.h"

#include <float.h>

#define TWO_PI 6.2831853f /* just below 2 pi in float */
#define SQRT2 1.41421356f

#define STR_(x) #x
#define STR(x) STR_(x)

/* Names relative to the validator's argument (level 0), inside the tuning
 * struct (1) or inside actag_params (2). */
#define QN(lv, f) ((lv) == 2 ? "tuning.quad." f : (lv) == 1 ? "quad." f : f)
#define FN(lv, f) ((lv) == 2 ? "tuning.fit." f : (lv) == 1 ? "fit." f : f)
#define TN(lv, f) ((lv) ? "tuning." f : f)
/* geometry.h's validator on its own (0) or inside actag_check (1) */
#define GN(lv, f) ((lv) ? "geometry." f : f)
#define SN(lv, f) ((lv) ? "frame." f : f)

static int set_ok(actag_error_detail *d)
{
    if (d != NULL) {
        d->code = ACTAG_OK;
        d->field = NULL;
        d->index = -1;
        d->value = 0.0;
        d->rule = NULL;
        d->other = NULL;
        d->limit = 0.0;
    }
    return ACTAG_OK;
}

static int fail_at(actag_error_detail *d, int code, const char *field, int index, double value,
                   const char *rule, const char *other, double limit)
{
    if (d != NULL) {
        d->code = code;
        d->field = field;
        d->index = index;
        d->value = value;
        d->rule = rule;
        d->other = other;
        d->limit = other != NULL ? limit : 0.0;
    }
    return code;
}

static int fail(actag_error_detail *d, int code, const char *field, double value,
                const char *rule)
{
    return fail_at(d, code, field, -1, value, rule, NULL, 0.0);
}

static int fail_vs(actag_error_detail *d, int code, const char *field, double value,
                   const char *rule, const char *other, double limit)
{
    return fail_at(d, code, field, -1, value, rule, other, limit);
}

static int is_finite_f(float v) { return v == v && v <= FLT_MAX && v >= -FLT_MAX; }
/* lo <= v <= hi (false for NaN) */
static int in_range(float v, float lo, float hi) { return v >= lo && v <= hi; }
/* lo < v <= hi */
static int in_range_open(float v, float lo, float hi) { return v > lo && v <= hi; }

/* ------------------------------------------------------------ quad params */

static int quad_check(const actag_quad_params *q, int lv, actag_error_detail *d)
{
    if (q == NULL)
        return fail(d, ACTAG_ERR_NULL, "params", 0.0, "must not be NULL");
    if (q->max_iterations < 1 || q->max_iterations > ACTAG_QUAD_MAX_ITERATIONS)
        return fail(d, ACTAG_ERR_PARAM, QN(lv, "max_iterations"), q->max_iterations,
                    "must be an integer from 1 to " STR(ACTAG_QUAD_MAX_ITERATIONS));
    if (!in_range_open(q->sample_fraction, 0.0f, 1.0f))
        return fail(d, ACTAG_ERR_PARAM, QN(lv, "sample_fraction"), q->sample_fraction,
                    "must be a number > 0 and <= 1");
    if (!in_range_open(q->inlier_ratio, 0.0f, 1.0f))
        return fail(d, ACTAG_ERR_PARAM, QN(lv, "inlier_ratio"), q->inlier_ratio,
                    "must be a number > 0 and <= 1");
    if (!in_range_open(q->min_inlier_ratio, 0.0f, 1.0f))
        return fail(d, ACTAG_ERR_PARAM, QN(lv, "min_inlier_ratio"), q->min_inlier_ratio,
                    "must be a number > 0 and <= 1");
    if (!in_range_open(q->inlier_distance, 0.0f, 1.0e6f))
        return fail(d, ACTAG_ERR_PARAM, QN(lv, "inlier_distance"), q->inlier_distance,
                    "must be a number of pixels > 0 and <= 1e6");
    if (!in_range(q->min_parallel_cos, 0.0f, 1.0f))
        return fail(d, ACTAG_ERR_PARAM, QN(lv, "min_parallel_cos"), q->min_parallel_cos,
                    "must be a number from 0 to 1");
    return set_ok(d);
}

int actag_quad_params_validate(const actag_quad_params *params, actag_error_detail *detail)
{
    return quad_check(params, 0, detail);
}

/* ------------------------------------------------------------- fit params */

static int fit_check(const actag_fit_params *f, int lv, actag_error_detail *d)
{
    if (f == NULL)
        return fail(d, ACTAG_ERR_NULL, "fp", 0.0, "must not be NULL");
    if (!in_range(f->level, 0.0f, 1.0f))
        return fail(d, ACTAG_ERR_PARAM, FN(lv, "level"), f->level,
                    "must be a number from 0 to 1");
    if (f->min_contrast < 0 || f->min_contrast > 255)
        return fail(d, ACTAG_ERR_PARAM, FN(lv, "min_contrast"), f->min_contrast,
                    "must be an integer from 0 to 255 (grey levels)");
    if (!in_range(f->sample_offset, 0.0f, 0.5f))
        return fail(d, ACTAG_ERR_PARAM, FN(lv, "sample_offset"), f->sample_offset,
                    "must be a number from 0 to 0.5 (cells)");
    if (!in_range(f->min_margin, -1.0e6f, 1.0e6f))
        return fail(d, ACTAG_ERR_PARAM, FN(lv, "min_margin"), f->min_margin,
                    "must be a number from -1e6 to 1e6");
    if (f->min_bit_margin < 0 || f->min_bit_margin > 32)
        return fail(d, ACTAG_ERR_PARAM, FN(lv, "min_bit_margin"), f->min_bit_margin,
                    "must be an integer from 0 to 32 (bits)");
    if (f->min_bit_odds < 1 || f->min_bit_odds > ACTAG_FIT_MAX_BIT_ODDS)
        return fail(d, ACTAG_ERR_PARAM, FN(lv, "min_bit_odds"), f->min_bit_odds,
                    "must be an integer from 1 to " STR(ACTAG_FIT_MAX_BIT_ODDS) " (1: the rule off)");
    if (f->many_corrections < 0 || f->many_corrections > 33)
        return fail(d, ACTAG_ERR_PARAM, FN(lv, "many_corrections"), f->many_corrections,
                    "must be an integer from 0 to 33 (bits; 33: never)");
    if (!in_range(f->many_corrections_margin, 0.0f, 1.0e6f))
        return fail(d, ACTAG_ERR_PARAM, FN(lv, "many_corrections_margin"),
                    f->many_corrections_margin, "must be a number from 0 to 1e6");
    if ((f->flags & ACTAG_FIT_ONLY_UNMIRRORED) && (f->flags & ACTAG_FIT_ONLY_MIRRORED))
        return fail(d, ACTAG_ERR_PARAM, FN(lv, "flags"), f->flags,
                    "must not hold both ACTAG_FIT_ONLY_UNMIRRORED and ACTAG_FIT_ONLY_MIRRORED");
    return set_ok(d);
}

int actag_fit_params_validate(const actag_fit_params *fp, actag_error_detail *detail)
{
    return fit_check(fp, 0, detail);
}

/* ----------------------------------------------------------------- tuning */

static int tuning_check(const actag_tuning *t, int lv, actag_error_detail *d)
{
    int rc;
    if (t == NULL)
        return fail(d, ACTAG_ERR_NULL, "tuning", 0.0, "must not be NULL");
    if (t->median_radius < 0 || t->median_radius > ACTAG_MEDIAN_MAX_RADIUS)
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "median_radius"), t->median_radius,
                    "must be an integer from 0 to " STR(ACTAG_MEDIAN_MAX_RADIUS) " (pixels)");
    if (t->median_per_range != 0 && t->median_per_range != 1)
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "median_per_range"), t->median_per_range,
                    "must be 0 or 1");
    if (t->threshold_radius < 0 || t->threshold_radius > ACTAG_MAX_THRESHOLD_RADIUS)
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "threshold_radius"), t->threshold_radius,
                    "must be an integer from 0 to ACTAG_MAX_THRESHOLD_RADIUS ("
                    STR(ACTAG_MAX_THRESHOLD_RADIUS) ", pixels)");
    if (t->threshold_offset < -255 || t->threshold_offset > 255)
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "threshold_offset"), t->threshold_offset,
                    "must be an integer from -255 to 255 (grey levels)");
    if (!(t->size_tolerance >= 0.0f && t->size_tolerance < 10.0f))
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "size_tolerance"), t->size_tolerance,
                    "must be a number >= 0 and < 10");
    if (!(t->min_area_fraction >= 0.0f && t->min_area_fraction < 1.0e6f))
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "min_area_fraction"), t->min_area_fraction,
                    "must be a number >= 0 and < 1e6");
    if (!(t->max_area_fraction < 1.0e6f))
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "max_area_fraction"), t->max_area_fraction,
                    "must be a number < 1e6");
    if (!(t->max_area_fraction >= t->min_area_fraction))
        return fail_vs(d, ACTAG_ERR_PARAM, TN(lv, "max_area_fraction"), t->max_area_fraction,
                       lv ? "must be at least tuning.min_area_fraction"
                          : "must be at least min_area_fraction",
                       TN(lv, "min_area_fraction"), t->min_area_fraction);
    rc = quad_check(&t->quad, lv ? 2 : 1, d);
    if (rc != ACTAG_OK)
        return rc;
    if (t->decode_mode != ACTAG_DECODE_FIT && t->decode_mode != ACTAG_DECODE_BINARY)
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "decode_mode"), t->decode_mode,
                    "must be ACTAG_DECODE_FIT (0) or ACTAG_DECODE_BINARY (1)");
    rc = fit_check(&t->fit, lv ? 2 : 1, d);
    if (rc != ACTAG_OK)
        return rc;
    if (!in_range(t->min_structure, 0.0f, 1.0f))
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "min_structure"), t->min_structure,
                    "must be a number from 0 to 1");
    if (!in_range(t->min_texture_contrast, 0.0f, 1.0e6f))
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "min_texture_contrast"), t->min_texture_contrast,
                    "must be a number from 0 to 1e6");
    if (!in_range(t->min_side_fraction, 0.0f, 1.0e6f))
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "min_side_fraction"), t->min_side_fraction,
                    "must be a number from 0 to 1e6");
    if (!(t->max_side_fraction <= 1.0e6f))
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "max_side_fraction"), t->max_side_fraction,
                    "must be a number <= 1e6");
    if (!(t->max_side_fraction >= t->min_side_fraction))
        return fail_vs(d, ACTAG_ERR_PARAM, TN(lv, "max_side_fraction"), t->max_side_fraction,
                       lv ? "must be at least tuning.min_side_fraction"
                          : "must be at least min_side_fraction",
                       TN(lv, "min_side_fraction"), t->min_side_fraction);
    if (t->search_candidates < 0 || t->search_candidates > ACTAG_SEARCH_MAX)
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "search_candidates"), t->search_candidates,
                    "must be an integer from 0 to ACTAG_SEARCH_MAX (" STR(ACTAG_SEARCH_MAX) ")");
    if (t->search_min_score < 0 || t->search_min_score > 255)
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "search_min_score"), t->search_min_score,
                    "must be an integer from 0 to 255 (grey levels)");
    if (t->search_max_corrections < 0)
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "search_max_corrections"),
                    t->search_max_corrections, "must be an integer >= 0");
    if (!in_range(t->search_min_margin, -1.0e6f, 1.0e6f))
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "search_min_margin"), t->search_min_margin,
                    "must be a number from -1e6 to 1e6");
    if (!in_range_open(t->search_range_scale, 0.05f, 4.0f))
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "search_range_scale"), t->search_range_scale,
                    "must be a number > 0.05 and <= 4");
    if (t->refine_corners != 0 && t->refine_corners != 1)
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "refine_corners"), t->refine_corners,
                    "must be 0 or 1");
    if (t->limits.max_contours < 1)
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "limits.max_contours"), t->limits.max_contours,
                    "must be an integer >= 1");
    if (t->limits.max_contour_points < 1)
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "limits.max_contour_points"),
                    t->limits.max_contour_points, "must be an integer >= 1");
    if (t->limits.max_contour_iterations < 1)
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "limits.max_contour_iterations"),
                    t->limits.max_contour_iterations, "must be an integer >= 1");
    if (t->limits.max_frame_iterations < 1)
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "limits.max_frame_iterations"),
                    t->limits.max_frame_iterations, "must be an integer >= 1");
    if (t->limits.max_decodes < 1)
        return fail(d, ACTAG_ERR_PARAM, TN(lv, "limits.max_decodes"), t->limits.max_decodes,
                    "must be an integer >= 1");
    return set_ok(d);
}

int actag_tuning_validate(const actag_tuning *t, actag_error_detail *detail)
{
    return tuning_check(t, 0, detail);
}

/* ----------------------------------------------------------------- params */

int actag_params_validate(const actag_params *p, actag_error_detail *d)
{
    int rc, maxc;
    if (p == NULL)
        return fail(d, ACTAG_ERR_NULL, "params", 0.0, "must not be NULL");
    if (p->family == NULL)
        return fail(d, ACTAG_ERR_NULL, "family", 0.0,
                    "must not be NULL (set it, e.g. with actag_family_get)");
    rc = actag_family_validate(p->family);
    if (rc != ACTAG_OK)
        return fail(d, rc, "family", 0.0,
                    "must be a valid family (actag_family_validate: bits a multiple of 4 "
                    "from 16 to 32, hamming, codes and their count)");
    maxc = actag_family_max_corrections(p->family);
    if ((p->max_bit_corrections < 0 && p->max_bit_corrections != ACTAG_CORRECTIONS_AUTO) ||
        p->max_bit_corrections > maxc)
        return fail_vs(d, ACTAG_ERR_CORRECTIONS, "max_bit_corrections", p->max_bit_corrections,
                       "must be ACTAG_CORRECTIONS_AUTO (-1) or an integer from 0 to the "
                       "family's limit (actag_family_max_corrections)",
                       "family", maxc);
    if (!(p->tag_size > 0.0f && is_finite_f(p->tag_size)))
        return fail(d, ACTAG_ERR_PARAM, "tag_size", p->tag_size,
                    "must be a finite number > 0 (metres)");
    /* the corner refinement's bound (refine.h), so that it is an error here
     * rather than corners silently left unrefined */
    if (!(p->tag_size < ACTAG_MAX_TAG_SIZE))
        return fail(d, ACTAG_ERR_PARAM, "tag_size", p->tag_size,
                    "must be below ACTAG_MAX_TAG_SIZE (1000 metres)");
    if (!in_range(p->min_margin, -1.0e6f, 1.0e6f))
        return fail(d, ACTAG_ERR_PARAM, "min_margin", p->min_margin,
                    "must be a number from -1e6 to 1e6");
    if (p->handedness != ACTAG_HANDEDNESS_ANY && p->handedness != ACTAG_HANDEDNESS_UNMIRRORED &&
        p->handedness != ACTAG_HANDEDNESS_MIRRORED)
        return fail(d, ACTAG_ERR_PARAM, "handedness", p->handedness,
                    "must be ACTAG_HANDEDNESS_ANY (0), _UNMIRRORED (1) or _MIRRORED (2)");
    return tuning_check(&p->tuning, 1, d);
}

/* --------------------------------------------------------------- geometry */

static int geometry_check(const actag_sonar_geometry *g, int rows, int cols, int lv,
                          actag_error_detail *d)
{
    if (g == NULL)
        return fail(d, ACTAG_ERR_NULL, lv ? "geometry" : "geo", 0.0, "must not be NULL");
    if (rows < 1 || rows > ACTAG_MAX_DIM)
        return fail(d, ACTAG_ERR_SIZE, SN(lv, "rows"), rows,
                    "must be an integer from 1 to ACTAG_MAX_DIM (" STR(ACTAG_MAX_DIM) ")");
    if (cols < 1 || cols > ACTAG_MAX_DIM)
        return fail(d, ACTAG_ERR_SIZE, SN(lv, "cols"), cols,
                    "must be an integer from 1 to ACTAG_MAX_DIM (" STR(ACTAG_MAX_DIM) ")");
    if ((g->flags & ~(ACTAG_RANGE_ASCENDING | ACTAG_AZIMUTH_ASCENDING)) != 0u)
        return fail(d, ACTAG_ERR_GEOMETRY, GN(lv, "flags"), (double)g->flags,
                    "must combine only ACTAG_RANGE_ASCENDING (1) and ACTAG_AZIMUTH_ASCENDING (2)");
    if (!(g->min_range >= 0.0f && is_finite_f(g->min_range)))
        return fail(d, ACTAG_ERR_GEOMETRY, GN(lv, "min_range"), g->min_range,
                    "must be a finite number >= 0 (metres)");
    if (!is_finite_f(g->max_range))
        return fail(d, ACTAG_ERR_GEOMETRY, GN(lv, "max_range"), g->max_range,
                    "must be a finite number (metres)");
    if (!(g->min_range < g->max_range))
        return fail_vs(d, ACTAG_ERR_GEOMETRY, GN(lv, "min_range"), g->min_range,
                       lv ? "must be below geometry.max_range" : "must be below max_range",
                       GN(lv, "max_range"), g->max_range);
    /* every row its own range: steps of at least ACTAG_MIN_RANGE_STEP * max_range */
    if (rows > 1 && !((g->max_range - g->min_range) / (float)(rows - 1) >=
                      ACTAG_MIN_RANGE_STEP * g->max_range))
        return fail_vs(d, ACTAG_ERR_GEOMETRY, GN(lv, "max_range"), g->max_range,
                       lv ? "must exceed geometry.min_range by at least (rows - 1) * "
                            "ACTAG_MIN_RANGE_STEP * max_range (rows too close in range)"
                          : "must exceed min_range by at least (rows - 1) * "
                            "ACTAG_MIN_RANGE_STEP * max_range (rows too close in range)",
                       GN(lv, "min_range"),
                       (double)g->min_range +
                           (double)(rows - 1) * (double)ACTAG_MIN_RANGE_STEP * g->max_range);
    if (g->bearings != NULL) {
        const float *b = g->bearings;
        int c, dir = 0;
        for (c = 0; c < cols; c++)
            if (!is_finite_f(b[c]))
                return fail_at(d, ACTAG_ERR_GEOMETRY, GN(lv, "bearings"), c, b[c],
                               "must be a finite number (radians)", NULL, 0.0);
        for (c = 1; c < cols; c++) {
            float step = b[c] - b[c - 1];
            int s = step > 0.0f ? 1 : step < 0.0f ? -1 : 0;
            if (s == 0 || (dir != 0 && s != dir))
                return fail_at(d, ACTAG_ERR_GEOMETRY, GN(lv, "bearings"), c, b[c],
                               dir > 0 ? "must be above the previous bearing (the table "
                                         "must be strictly monotonic: it increases)"
                               : dir < 0 ? "must be below the previous bearing (the table "
                                           "must be strictly monotonic: it decreases)"
                                         : "must differ from the previous bearing (the "
                                           "table must be strictly monotonic)",
                               GN(lv, "bearings"), b[c - 1]);
            dir = s;
            if (!((step < 0.0f ? -step : step) >= ACTAG_MIN_AZIMUTH_STEP))
                return fail_at(d, ACTAG_ERR_GEOMETRY, GN(lv, "bearings"), c, b[c],
                               "must differ from the previous bearing by at least "
                               "ACTAG_MIN_AZIMUTH_STEP (1e-6 rad)",
                               GN(lv, "bearings"), b[c - 1]);
        }
        if (cols > 1 && !((b[cols - 1] - b[0]) * (float)dir < TWO_PI))
            return fail_at(d, ACTAG_ERR_GEOMETRY, GN(lv, "bearings"), cols - 1, b[cols - 1],
                           "must lie less than 2 pi from the first bearing (the table "
                           "spans a full turn)",
                           GN(lv, "bearings"), b[0]);
    } else {
        if (!(g->aperture > 0.0f && g->aperture < TWO_PI))
            return fail(d, ACTAG_ERR_GEOMETRY, GN(lv, "aperture"), g->aperture,
                        "must be a number > 0 and < 2 pi (radians)");
        if (cols > 1 && !(g->aperture / (float)(cols - 1) >= ACTAG_MIN_AZIMUTH_STEP))
            return fail_vs(d, ACTAG_ERR_GEOMETRY, GN(lv, "aperture"), g->aperture,
                           "must be at least (cols - 1) * ACTAG_MIN_AZIMUTH_STEP (1e-6 rad "
                           "per column)",
                           SN(lv, "cols"), (double)(cols - 1) * (double)ACTAG_MIN_AZIMUTH_STEP);
    }
    return set_ok(d);
}

int actag_geometry_validate(const actag_sonar_geometry *geo, int rows, int cols,
                            actag_error_detail *detail)
{
    return geometry_check(geo, rows, cols, 0, detail);
}

/* ------------------------------------------------------------ the whole call */

/* actag_check and actag_check_inplace: everything but the workspace size */
static int check_call(const actag_frame *f, const actag_sonar_geometry *g, const actag_params *p,
                      int max_out, actag_error_detail *d)
{
    int rc, bytes;
    int fp = actag_fp_fuses();
    if (fp & ACTAG__FP_FMA)
        return fail(d, ACTAG_ERR_BUILD, "build", 0.0,
                    "the library's sources were compiled with floating-point contraction "
                    "(Clang -ffp-contract=fast): compile them with -ffp-contract=off");
    if (fp)
        return fail(d, ACTAG_ERR_BUILD, "build", 0.0,
                    "the library's sources were compiled to divide by reciprocals (Clang "
                    "-freciprocal-math or -funsafe-math-optimizations on a target that ignores "
                    "its float_control pragma: ARM, AArch64, RISC-V): compile them without those");
    if (f == NULL)
        return fail(d, ACTAG_ERR_NULL, "frame", 0.0, "must not be NULL");
    if (g == NULL)
        return fail(d, ACTAG_ERR_NULL, "geometry", 0.0, "must not be NULL");
    if (p == NULL)
        return fail(d, ACTAG_ERR_NULL, "params", 0.0, "must not be NULL");
    if (f->data == NULL)
        return fail(d, ACTAG_ERR_NULL, "frame.data", 0.0, "must not be NULL");
    if (f->rows < 1 || f->rows > ACTAG_MAX_DIM)
        return fail(d, ACTAG_ERR_SIZE, "frame.rows", f->rows,
                    "must be an integer from 1 to ACTAG_MAX_DIM (" STR(ACTAG_MAX_DIM) ")");
    if (f->cols < 1 || f->cols > ACTAG_MAX_DIM)
        return fail(d, ACTAG_ERR_SIZE, "frame.cols", f->cols,
                    "must be an integer from 1 to ACTAG_MAX_DIM (" STR(ACTAG_MAX_DIM) ")");
    if (f->stride < f->cols)
        return fail_vs(d, ACTAG_ERR_SIZE, "frame.stride", f->stride,
                       "must be at least frame.cols (elements)", "frame.cols", f->cols);
    if (f->depth != 8 && f->depth != 16)
        return fail(d, ACTAG_ERR_SIZE, "frame.depth", f->depth, "must be 8 or 16 (bits)");
    /* the last pixel's byte offset must be addressable */
    bytes = f->depth / 8;
    if (f->rows > 1 &&
        (size_t)f->stride > (SIZE_MAX / (size_t)bytes - (size_t)f->cols) / (size_t)(f->rows - 1))
        return fail(d, ACTAG_ERR_SIZE, "frame.stride", f->stride,
                    "must keep (rows - 1) * stride + cols elements within SIZE_MAX bytes");
    if (max_out < 0)
        return fail(d, ACTAG_ERR_PARAM, "max_out", max_out, "must be an integer >= 0");
    rc = actag_params_validate(p, d);
    if (rc != ACTAG_OK)
        return rc;
    rc = geometry_check(g, f->rows, f->cols, 1, d);
    if (rc != ACTAG_OK)
        return rc;
    /* the white square (diagonal sqrt(2) * tag_size) must fit within the
     * sonar's reach (a ball of radius max_range) */
    if (!(p->tag_size <= SQRT2 * g->max_range))
        return fail_vs(d, ACTAG_ERR_PARAM, "tag_size", p->tag_size,
                       "must be at most sqrt(2) * geometry.max_range (a larger white square "
                       "cannot lie within the sonar's range)",
                       "geometry.max_range", (double)(SQRT2 * g->max_range));
    return ACTAG_OK;
}

int actag_check(const actag_frame *f, const actag_sonar_geometry *g, const actag_params *p,
                size_t workspace_size, int max_out, actag_error_detail *d)
{
    size_t need;
    int rc = check_call(f, g, p, max_out, d);
    if (rc != ACTAG_OK)
        return rc;
    need = actag_workspace_size(f->rows, f->cols);
    if (workspace_size < need)
        return fail_vs(d, ACTAG_ERR_WORKSPACE, "workspace_size", (double)workspace_size,
                       "must be at least actag_workspace_size(rows, cols) (bytes)", "frame",
                       (double)need);
    return set_ok(d);
}

int actag_check_inplace(const actag_frame *f, const actag_sonar_geometry *g,
                        const actag_params *p, size_t workspace_size, int max_out,
                        actag_error_detail *d)
{
    size_t need;
    int rc = check_call(f, g, p, max_out, d);
    if (rc != ACTAG_OK)
        return rc;
    if (p->tuning.median_radius > ACTAG_MEDIAN_INPLACE_MAX_RADIUS)
        return fail(d, ACTAG_ERR_PARAM, "tuning.median_radius", p->tuning.median_radius,
                    "must be at most ACTAG_MEDIAN_INPLACE_MAX_RADIUS (" STR(
                        ACTAG_MEDIAN_INPLACE_MAX_RADIUS) ") for actag_detect_inplace");
    need = actag_workspace_size_inplace(f->rows, f->cols);
    if (workspace_size < need)
        return fail_vs(d, ACTAG_ERR_WORKSPACE, "workspace_size", (double)workspace_size,
                       "must be at least actag_workspace_size_inplace(rows, cols) (bytes)",
                       "frame", (double)need);
    return set_ok(d);
}
