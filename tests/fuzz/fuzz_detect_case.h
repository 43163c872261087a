/*
 * fuzz_detect_case.h -- the input format of fuzz_detect (decoder and seed
 * encoder side by side, so that they cannot drift apart).
 *
 * An input is read front to back (fuzz_util.h readers; missing bytes are 0):
 *   frame:     rows, cols (fz_int), stride extra (fz_int, added to cols),
 *              depth selector (u8: 0-159 8 bit, 160-239 16 bit, else raw int
 *              from fz_int), frame misalignment (u8 % 16), pixel mode (u8),
 *              pixel seed (u32), pixel parameters a, b (u16 each)
 *   pointers:  null selector (u8: values 0-7 make one argument NULL)
 *   geometry:  min_range, max_range, aperture (fz_float), flags (u8; values
 *              >= 240 raw u32), bearing mode (u8), bearing start/step
 *              (fz_float)
 *   family:    selector (u8), subset size (u16)
 *   params:    every actag_params field in declaration order (fz_int /
 *              fz_float around its default), but tuning.fit.min_bit_odds,
 *              which came later and keeps its default (a field read here
 *              would move every later byte of the corpus' inputs;
 *              test_decode checks actag_fit_bit_lead on every valid input)
 *   call:      max_out (fz_int), workspace mode (u8), workspace extra (u16),
 *              workspace misalignment (u8 % 16), stats (u8: odd = none),
 *              multi (u8: >= 224 also runs actag_detect_multi; below 224, the
 *              value % 3 is params.handedness and bit 2 set turns
 *              tuning.refine_corners off)
 *   pixels:    the rest of the input (pixel mode 0 cycles through it).
 */
#ifndef ACTAG_FUZZ_DETECT_CASE_H
#define ACTAG_FUZZ_DETECT_CASE_H

#include "actag/actag.h"
#include "fuzz_util.h"

/* Frame pixels at most (bigger valid frames are cut down to this many). */
#define FZD_MAX_PIXELS (1u << 18)

/* Pixel modes. */
enum {
    FZD_PIX_INPUT,   /* the input's remaining bytes, cycled (16 bit: byte pairs) */
    FZD_PIX_CONST,   /* all a */
    FZD_PIX_CHECKER, /* checkerboard, cells of 1 + a % 64 pixels, levels 0 / 255 */
    FZD_PIX_SPECKLE, /* dark background, bright pixels with probability (a % 256) / 256 */
    FZD_PIX_BLOBS,   /* grid of bright squares: side 1 + a % 32, period side + 1 + b % 32 */
    FZD_PIX_NOISE,   /* uniform noise */
    FZD_PIX_TAG,     /* a rendered tag (cell 1 + a % 12 px) at offset b, in noise */
    FZD_PIX_STRIPES, /* stripes of 1 + a % 16 pixels, along rows or columns (b & 1) */
    FZD_PIX_MODES
};

typedef struct fzd_case {
    int rows, cols, stride, depth;
    unsigned frame_misalign;
    int pix_mode;
    uint32_t pix_seed;
    int pix_a, pix_b;
    int null_sel;
    actag_sonar_geometry geo;
    int bear_mode; /* 0 none, 1 uniform fan, 2 reversed fan, 3 raw floats, 4 one repeat,
                      5 a NaN, 6 start/step as given */
    float bear_start, bear_step;
    int fam_sel, fam_subset;
    actag_params p;  /* family is set by the harness from fam_sel */
    int max_out;
    int ws_mode; /* 0 exact, 1 one byte short, 2 extra bytes, 3 zero, 4 huge claim */
    int ws_extra;
    unsigned ws_misalign;
    int no_stats;
    int multi;
    int handedness, no_refine; /* from the multi byte when below 224 */
    const uint8_t *pixels;
    size_t npixels;
} fzd_case;

static inline void fzd_decode(fzd_case *c, const uint8_t *data, size_t size)
{
    fz_reader r;
    actag_params d;
    uint8_t m;
    fz_init(&r, data, size);
    memset(c, 0, sizeof *c);
    c->rows = fz_int(&r, 48, 1, 300);
    c->cols = fz_int(&r, 48, 1, 300);
    {
        int64_t st64 = (int64_t)c->cols + fz_int(&r, 0, 0, 40);
        c->stride = st64 > INT_MAX ? INT_MAX : st64 < INT_MIN ? INT_MIN : (int)st64;
    }
    m = fz_u8(&r);
    c->depth = m < 160 ? 8 : m < 240 ? 16 : fz_int(&r, 8, 0, 32);
    c->frame_misalign = fz_u8(&r) & 15u;
    c->pix_mode = fz_u8(&r) % FZD_PIX_MODES;
    c->pix_seed = fz_u32(&r);
    c->pix_a = fz_u16(&r);
    c->pix_b = fz_u16(&r);
    c->null_sel = fz_u8(&r);
    c->geo.min_range = fz_float(&r, 0.1f, 0.0f, 5.0f);
    c->geo.max_range = fz_float(&r, 1.5f, 0.0f, 60.0f);
    c->geo.aperture = fz_float(&r, 1.0471976f, 0.0f, 6.2831853f);
    m = fz_u8(&r);
    c->geo.flags = m < 240 ? (unsigned)(m & 3u) : fz_u32(&r);
    c->bear_mode = fz_u8(&r) % 7;
    c->bear_start = fz_float(&r, 0.5f, -3.2f, 3.2f);
    c->bear_step = fz_float(&r, -0.002f, -0.05f, 0.05f);
    c->fam_sel = fz_u8(&r);
    c->fam_subset = fz_u16(&r);
    actag_params_default(&d);
    c->p = d;
    c->p.tag_size = fz_float(&r, d.tag_size, 0.005f, 2.0f);
    c->p.max_bit_corrections = fz_int(&r, d.max_bit_corrections, -1, 4);
    c->p.tuning.median_radius = fz_int(&r, d.tuning.median_radius, 0, ACTAG_MEDIAN_MAX_RADIUS);
    c->p.tuning.threshold_radius = fz_int(&r, d.tuning.threshold_radius, 0, ACTAG_MAX_THRESHOLD_RADIUS);
    c->p.tuning.threshold_offset = fz_int(&r, d.tuning.threshold_offset, -255, 255);
    c->p.tuning.size_tolerance = fz_float(&r, d.tuning.size_tolerance, 0.0f, 10.0f);
    c->p.tuning.min_area_fraction = fz_float(&r, d.tuning.min_area_fraction, 0.0f, 2.0f);
    c->p.tuning.max_area_fraction = fz_float(&r, d.tuning.max_area_fraction, 0.0f, 10.0f);
    c->p.tuning.quad.max_iterations = fz_int(&r, d.tuning.quad.max_iterations, 1, 1000);
    c->p.tuning.quad.sample_fraction = fz_float(&r, d.tuning.quad.sample_fraction, 0.0f, 1.0f);
    c->p.tuning.quad.inlier_ratio = fz_float(&r, d.tuning.quad.inlier_ratio, 0.0f, 1.0f);
    c->p.tuning.quad.inlier_distance = fz_float(&r, d.tuning.quad.inlier_distance, 0.0f, 20.0f);
    c->p.tuning.quad.min_parallel_cos = fz_float(&r, d.tuning.quad.min_parallel_cos, 0.0f, 1.0f);
    c->p.tuning.quad.min_inlier_ratio = fz_float(&r, d.tuning.quad.min_inlier_ratio, 0.0f, 1.0f);
    c->p.tuning.decode_mode = fz_int(&r, d.tuning.decode_mode, 0, 1);
    c->p.seed = (uint32_t)fz_int(&r, (int)d.seed, 0, INT_MAX);
    c->p.tuning.fit.flags = fz_int(&r, d.tuning.fit.flags, 0, 255);
    c->p.tuning.fit.level = fz_float(&r, d.tuning.fit.level, 0.0f, 1.0f);
    c->p.tuning.fit.min_contrast = fz_int(&r, d.tuning.fit.min_contrast, 0, 255);
    c->p.tuning.fit.sample_offset = fz_float(&r, d.tuning.fit.sample_offset, 0.0f, 0.5f);
    c->p.min_margin = fz_float(&r, d.min_margin, -10.0f, 40.0f);
    c->p.tuning.fit.min_bit_margin = fz_int(&r, d.tuning.fit.min_bit_margin, 0, 8);
    c->p.tuning.min_structure = fz_float(&r, d.tuning.min_structure, 0.0f, 1.0f);
    c->p.tuning.min_side_fraction = fz_float(&r, d.tuning.min_side_fraction, 0.0f, 2.0f);
    c->p.tuning.max_side_fraction = fz_float(&r, d.tuning.max_side_fraction, 0.0f, 4.0f);
    c->p.tuning.search_candidates = fz_int(&r, d.tuning.search_candidates, 0, ACTAG_SEARCH_MAX);
    c->p.tuning.search_min_score = fz_int(&r, d.tuning.search_min_score, 0, 255);
    c->p.tuning.search_max_corrections = fz_int(&r, d.tuning.search_max_corrections, 0, 4);
    c->p.tuning.search_min_margin = fz_float(&r, d.tuning.search_min_margin, -10.0f, 40.0f);
    c->p.tuning.search_range_scale = fz_float(&r, d.tuning.search_range_scale, 0.05f, 4.0f);
    c->max_out = fz_int(&r, 8, 0, 16);
    c->ws_mode = fz_u8(&r) % 5;
    c->ws_extra = fz_u16(&r);
    c->ws_misalign = fz_u8(&r) & 15u;
    c->no_stats = fz_u8(&r) & 1;
    m = fz_u8(&r);
    c->multi = m >= 224;
    if (m < 224) {
        c->handedness = m % 3; /* ACTAG_HANDEDNESS_ANY, _UNMIRRORED, _MIRRORED */
        c->no_refine = (m >> 2) & 1;
        /* bit 4: the median's fixed radius (median_per_range 0; written as
         * 48, which keeps m % 3 and bit 2) */
        c->p.tuning.median_per_range = !((m >> 4) & 1);
        c->p.handedness = c->handedness;
        if (c->no_refine)
            c->p.tuning.refine_corners = 0;
    }
    c->pixels = fz_rest(&r, &c->npixels);
}

/* Writes c as an input (every field as raw bits) followed by the pixel
 * bytes; returns the length. buf must hold 512 + npixels bytes. */
static inline size_t fzd_encode(const fzd_case *c, uint8_t *buf)
{
    size_t at = 0;
    at = fz_put_int(buf, at, c->rows);
    at = fz_put_int(buf, at, c->cols);
    at = fz_put_int(buf, at, (int)((int64_t)c->stride - c->cols));
    at = fz_put_u8(buf, at, c->depth == 8 ? 0 : c->depth == 16 ? 200 : 245);
    if (c->depth != 8 && c->depth != 16)
        at = fz_put_int(buf, at, c->depth);
    at = fz_put_u8(buf, at, (uint8_t)c->frame_misalign);
    at = fz_put_u8(buf, at, (uint8_t)c->pix_mode);
    at = fz_put_u32(buf, at, c->pix_seed);
    at = fz_put_u16(buf, at, (uint16_t)c->pix_a);
    at = fz_put_u16(buf, at, (uint16_t)c->pix_b);
    at = fz_put_u8(buf, at, (uint8_t)c->null_sel);
    at = fz_put_float(buf, at, c->geo.min_range);
    at = fz_put_float(buf, at, c->geo.max_range);
    at = fz_put_float(buf, at, c->geo.aperture);
    at = fz_put_u8(buf, at, 240);
    at = fz_put_u32(buf, at, c->geo.flags);
    at = fz_put_u8(buf, at, (uint8_t)c->bear_mode);
    at = fz_put_float(buf, at, c->bear_start);
    at = fz_put_float(buf, at, c->bear_step);
    at = fz_put_u8(buf, at, (uint8_t)c->fam_sel);
    at = fz_put_u16(buf, at, (uint16_t)c->fam_subset);
    at = fz_put_float(buf, at, c->p.tag_size);
    at = fz_put_int(buf, at, c->p.max_bit_corrections);
    at = fz_put_int(buf, at, c->p.tuning.median_radius);
    at = fz_put_int(buf, at, c->p.tuning.threshold_radius);
    at = fz_put_int(buf, at, c->p.tuning.threshold_offset);
    at = fz_put_float(buf, at, c->p.tuning.size_tolerance);
    at = fz_put_float(buf, at, c->p.tuning.min_area_fraction);
    at = fz_put_float(buf, at, c->p.tuning.max_area_fraction);
    at = fz_put_int(buf, at, c->p.tuning.quad.max_iterations);
    at = fz_put_float(buf, at, c->p.tuning.quad.sample_fraction);
    at = fz_put_float(buf, at, c->p.tuning.quad.inlier_ratio);
    at = fz_put_float(buf, at, c->p.tuning.quad.inlier_distance);
    at = fz_put_float(buf, at, c->p.tuning.quad.min_parallel_cos);
    at = fz_put_float(buf, at, c->p.tuning.quad.min_inlier_ratio);
    at = fz_put_int(buf, at, c->p.tuning.decode_mode);
    at = fz_put_int(buf, at, (int)c->p.seed);
    at = fz_put_int(buf, at, c->p.tuning.fit.flags);
    at = fz_put_float(buf, at, c->p.tuning.fit.level);
    at = fz_put_int(buf, at, c->p.tuning.fit.min_contrast);
    at = fz_put_float(buf, at, c->p.tuning.fit.sample_offset);
    at = fz_put_float(buf, at, c->p.tuning.fit.min_margin);
    at = fz_put_int(buf, at, c->p.tuning.fit.min_bit_margin);
    at = fz_put_float(buf, at, c->p.tuning.min_structure);
    at = fz_put_float(buf, at, c->p.tuning.min_side_fraction);
    at = fz_put_float(buf, at, c->p.tuning.max_side_fraction);
    at = fz_put_int(buf, at, c->p.tuning.search_candidates);
    at = fz_put_int(buf, at, c->p.tuning.search_min_score);
    at = fz_put_int(buf, at, c->p.tuning.search_max_corrections);
    at = fz_put_float(buf, at, c->p.tuning.search_min_margin);
    at = fz_put_float(buf, at, c->p.tuning.search_range_scale);
    at = fz_put_int(buf, at, c->max_out);
    at = fz_put_u8(buf, at, (uint8_t)c->ws_mode);
    at = fz_put_u16(buf, at, (uint16_t)c->ws_extra);
    at = fz_put_u8(buf, at, (uint8_t)c->ws_misalign);
    at = fz_put_u8(buf, at, (uint8_t)c->no_stats);
    at = fz_put_u8(buf, at, (uint8_t)(c->multi ? 255
                                           : c->handedness % 3 + 12 * (c->no_refine != 0) +
                                                 48 * (c->p.tuning.median_per_range == 0)));
    if (c->npixels)
        memcpy(buf + at, c->pixels, c->npixels);
    return at + c->npixels;
}

/* A case with every default: a rows x cols 8-bit frame of the given pixels
 * (mode FZD_PIX_INPUT), geometry min..max range, aperture, AcTag24h10. */
static inline void fzd_default_case(fzd_case *c, int rows, int cols, float min_range, float max_range,
                             float aperture, const uint8_t *pixels)
{
    memset(c, 0, sizeof *c);
    c->rows = rows;
    c->cols = cols;
    c->stride = cols;
    c->depth = 8;
    c->pix_mode = FZD_PIX_INPUT;
    c->null_sel = 255;
    c->geo.min_range = min_range;
    c->geo.max_range = max_range;
    c->geo.aperture = aperture;
    c->bear_start = 0.5f;
    c->bear_step = -0.002f;
    c->fam_sel = 3; /* AcTag24h10 in the default family list */
    actag_params_default(&c->p);
    c->max_out = 8;
    c->pixels = pixels;
    c->npixels = pixels ? (size_t)rows * (size_t)cols : 0u;
}

#endif /* ACTAG_FUZZ_DETECT_CASE_H */
