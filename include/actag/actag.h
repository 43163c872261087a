/*
 * actag/actag.h -- AcTag detection in imaging-sonar frames, without a heap.
 *
 * MANUAL
 *   actag finds AcTag fiducial markers in a polar sonar frame (rows = range
 *   bins, columns = beams) and reports, for every tag, its ID and the four
 *   corners of its inner white square with sub-pixel image coordinates and
 *   (range m, azimuth rad).
 *
 *   Pipeline (one source file per stage, each public on its own):
 *     median filter (median.h) -> structure search (search.h) ->
 *     adaptive threshold (threshold.h) -> contours (contours.h) ->
 *     physical size filter (geometry.h) -> RANSAC quadrilateral (quad.h) ->
 *     decode (decode.h, grid-fitting grey decoder by default).
 *   See DEFAULTS AND WHY below actag_params. (A program that calls the
 *   stages alone calls actag_check_build() (common.h) once: actag_detect
 *   checks the build itself, the stages do not.)
 *
 *   Memory: the caller hands in one workspace; the library never allocates.
 *   ACTAG_WORKSPACE_SIZE(rows, cols) is a constant expression, so firmware can
 *   write
 *       static uint8_t ws[ACTAG_WORKSPACE_SIZE(530, 512)];
 *   and a workspace sized for the largest frame serves every smaller frame.
 *   actag_workspace_size() returns the same number at run time (398,752
 *   bytes at 530 x 512: the filtered frame is most of it). Firmware that can
 *   let the library overwrite the frame buffer calls actag_detect_inplace()
 *   instead, with ACTAG_WORKSPACE_SIZE_INPLACE(rows, cols) bytes (127,392 at
 *   530 x 512: a 128 KiB DTCM) and the same tags.
 *   (The library stores integers and floats in the workspace. Strict C99
 *   effective-type rules allow that in allocated storage; in a declared
 *   uint8_t array they do not, though GCC and Clang, which see the
 *   workspace only through a pointer passed across files (unless link-time
 *   optimisation joins them), compile it as intended. Firmware that wants the
 *   letter of the standard gives the workspace no declared type, e.g. a
 *   linker-script section it reaches through an extern pointer.)
 *
 *   Typical use:
 *       actag_family fam;
 *       actag_params p;
 *       actag_sonar_geometry g = {0.1f, 1.5f, 1.0472f, NULL, 0};
 *       actag_frame f = {pixels, 530, 512, 512, 8};
 *       actag_detection det[8];
 *       int n;
 *       actag_family_get("AcTag24h10", &fam);
 *       actag_params_default(&p);
 *       p.family = &fam;
 *       p.tag_size = 0.130628571f;
 *       n = actag_detect(&f, &g, &p, ws, sizeof ws, det, 8, NULL);
 *       if (n < 0) fprintf(stderr, "%s\n", actag_strerror(n));
 *
 *   Image orientation, range/azimuth mapping and the bearing table: see
 *   geometry.h (SPEC section 4). Coordinates: x = column, y = row (pixels).
 *
 *   Corners: corners[0..3] are the inner white square's top-left, top-right,
 *   bottom-right and bottom-left corners AS PRINTED on the tag, wherever the
 *   tag appears in the image; `mirrored` says the sonar showed the tag
 *   mirrored (relative to the reference image orientation), which tells on
 *   which side of the sonar's horizontal plane the tag lies.
 *
 *   Determinism: the RANSAC stage draws from a small PRNG seeded with
 *   params.seed on every call; identical input and seed give identical output
 *   on every platform. The call keeps no state between calls; it is
 *   re-entrant (use one workspace per concurrent call).
 *
 *   16-bit frames (depth 16) are first scaled to 8 bits by the frame's own
 *   maximum: v8 = (v * 255 + max/2) / max; the stages then run on 8 bits
 *   (the median filter scales a row at a time inside its scratch,
 *   actag_median_filter16: no 8-bit copy of the frame is made).
 *   Alignment: none required. 16-bit samples are in host byte order and are
 *   read bytewise-safe, so frame->data may be at any address (an odd one
 *   included, e.g. a frame inside a packet after a 1-byte header).
 *   Buffer extent: the frame is read only at rows 0..rows-1, columns
 *   0..cols-1; the last row needs no padding, i.e. a buffer of
 *   ((rows - 1) * stride + cols) samples suffices, and padding bytes are
 *   never read.
 *
 * ERRORS (negative return values of actag_detect)
 *   ACTAG_ERR_BUILD        the library's sources were compiled to fuse multiplies
 *                          and adds (Clang -ffp-contract=fast on an FMA target,
 *                          which ignores the sources' pragmas; GCC honours them)
 *                          or to turn divisions into reciprocal products (Clang
 *                          -freciprocal-math or -funsafe-math-optimizations on
 *                          ARM, AArch64 or RISC-V, where its float_control pragma is
 *                          ignored): compile them with -ffp-contract=off and
 *                          without those (checked first)
 *   ACTAG_ERR_NULL         frame, frame->data, geometry, params, params->family,
 *                          workspace or out (when max_out > 0) is NULL
 *   ACTAG_ERR_SIZE         rows/cols < 1 or > ACTAG_MAX_DIM, stride < cols,
 *                          depth not 8 or 16, (rows-1) * stride + cols elements
 *                          beyond SIZE_MAX bytes
 *   ACTAG_ERR_PARAM        max_out < 0, a parameter or tuning value out of range
 *                          (actag_params_validate), tag_size above
 *                          sqrt(2) * geometry->max_range
 *   ACTAG_ERR_GEOMETRY     invalid sonar geometry (actag_geometry_validate)
 *   ACTAG_ERR_FAMILY       invalid family
 *   ACTAG_ERR_CORRECTIONS  max_bit_corrections not -1 (automatic) or 0 .. the
 *                          family's limit
 *   ACTAG_ERR_WORKSPACE    workspace_size < actag_workspace_size(rows, cols)
 *   When more tags are found than max_out, the first max_out (in scan order)
 *   are written and stats->dropped counts the rest (a tag read twice once:
 *   its other reading counts in stats->duplicates; past 8 such tags every
 *   further reading counts as dropped).
 *
 * ERROR DETAILS (which input was wrong, and why)
 *   actag_check(frame, geometry, params, workspace_size, max_out, &detail)
 *   runs exactly the checks actag_detect() runs before it touches a pixel,
 *   in the same order, and returns the same code (ACTAG_OK when actag_detect
 *   would run; actag_detect's only further checks, after these, are
 *   workspace and out being NULL). It also fills the optional actag_error_detail (common.h):
 *       actag_error_detail d;
 *       if (actag_check(&f, &g, &p, sizeof ws, 8, &d) != ACTAG_OK)
 *           printf("%s: %s (got %g)\n", d.field, d.rule, d.value);
 *   prints e.g. "tag_size: must be a finite number > 0 (metres) (got 0)",
 *   "tuning.quad.min_inlier_ratio: must be a number > 0 and <= 1 (got 1.5)",
 *   "geometry.min_range: must be below geometry.max_range (got 2)" (then
 *   d.other = "geometry.max_range", d.limit = 1.5), or for a bearing table
 *   d.field = "geometry.bearings" with d.index the entry at fault. Field
 *   names are the C expressions from actag_check's arguments: params
 *   members bare ("tag_size", "tuning.median_radius"), the others prefixed
 *   ("frame.stride", "geometry.aperture", "workspace_size", "max_out").
 *   Every string is a literal; nothing is stored anywhere else, so the
 *   checks stay re-entrant.
 *   The validators of the single structs take the same optional pointer:
 *   actag_params_validate, actag_tuning_validate (below),
 *   actag_geometry_validate (geometry.h), actag_quad_params_validate
 *   (quad.h), actag_fit_params_validate (decode.h). The stages call them too
 *   (actag_quad_fit, actag_decode_quad_fit, actag_search_map), so a value
 *   is judged by one rule wherever it enters, and anything a stage would
 *   refuse is an error from actag_detect, not a silent "no tag". Besides the
 *   per-field ranges documented with actag_tuning / actag_params, the rules
 *   bound everything that scales with the frame: tag_size at most
 *   sqrt(2) * max_range, and the geometry's least range and azimuth steps
 *   (geometry.h), so no stage computes an out-of-range pixel count.
 */
#ifndef ACTAG_ACTAG_H
#define ACTAG_ACTAG_H

#include "actag/common.h"
#include "actag/contours.h"
#include "actag/decode.h"
#include "actag/family.h"
#include "actag/geometry.h"
#include "actag/median.h"
#include "actag/quad.h"
#include "actag/refine.h"
#include "actag/rng.h"
#include "actag/search.h"
#include "actag/threshold.h"
#include "actag/trace.h"

#ifdef __cplusplus
extern "C" {
#endif

/* An input frame: 8- or 16-bit unsigned pixels, row-major. */
typedef struct actag_frame {
    const void *data; /* const uint8_t * (depth 8) or const uint16_t * (depth 16, host byte
                         order, any alignment: odd addresses are read safely) */
    int rows;         /* range bins */
    int cols;         /* beams */
    int stride;       /* elements (not bytes) from one row to the next, >= cols */
    int depth;        /* 8 or 16 */
} actag_frame;

/* Work limits of one call (bounded time, issue 10): every loop whose length
 * depends on the image stops at one of these, and actag_stats counts each
 * time a limit was reached. The defaults are far above what real frames use
 * (docs/robustness.md: same detections on every pool frame with and
 * without them) and keep the worst adversarial frame (tag-sized squares,
 * fake tags, checkerboards, speckle, noise) within 3x the median pool
 * frame's instructions (bench/worst_callgrind.sh). Each is >= 1. */
typedef struct actag_limits {
    int max_contours;           /* outer borders examined per frame (default 20000); the
                                   scan stops there (stats.contour_cap) */
    int max_contour_points;     /* points of one border (default 4096, at most
                                   ACTAG_CONTOUR_CAP(rows, cols) is used); longer borders are
                                   skipped (stats.overflowed) */
    int max_contour_iterations; /* RANSAC iterations per contour over all its quad tries
                                   (default 1000) (stats.contour_budget) */
    int max_frame_iterations;   /* RANSAC iterations per frame (default 6000)
                                   (stats.frame_budget) */
    int max_decodes;            /* decoder calls per frame: quads, search candidates,
                                   extreme-point and merged-blob guesses (default 40)
                                   (stats.decode_cap); a
                                   search candidate's second reading, with the template
                                   check, counts with its first (at most search_candidates);
                                   so do the checks of a reported search or guess reading
                                   from its box turned +30, -30 and +45 degrees and, for a
                                   contour's guess, from its extreme points with one corner
                                   completed to a parallelogram (at most 7 wide readings and
                                   7 template polishes each, so at most 7 x (16 guesses +
                                   search_candidates) a frame; readings.c,
                                   actag__turned_rival_refuses) */
} actag_limits;

#define ACTAG_LIMIT_CONTOURS 20000
#define ACTAG_LIMIT_CONTOUR_POINTS 4096
#define ACTAG_LIMIT_CONTOUR_ITERATIONS 1000
#define ACTAG_LIMIT_FRAME_ITERATIONS 6000
#define ACTAG_LIMIT_DECODES 40

/* Tuning of the pipeline stages: the values the defaults were measured with
 * (see DEFAULTS AND WHY below). actag_tuning_default() fills them; most
 * users never change them. Each field: unit, default, when to change it. */
typedef struct actag_tuning {
    int median_radius;          /* pixels, 0..ACTAG_MEDIAN_MAX_RADIUS (default 4; 0 disables
                                   the filter): the largest radius (see median_per_range).
                                   Lower it (2-3) when tags span few pixels (under ~15 px),
                                   raise it (5-6) on very speckled frames. */
    int median_per_range;       /* 0 or 1 (default 1): at each range the radius is the
                                   largest whose window (2 r + 1 px) spans at most half a tag
                                   cell's width in beams there plus 2 px, i.e. r <= (cell +
                                   2) / 4 with cell = tag_size / (bits/4 - 3) over range x
                                   beam spacing; at least 2 (a 5 x 5 window; median_radius
                                   when that is smaller), so the median
                                   keeps the cells of far tags (a 9 x 9 window mixes cells
                                   under ~14 px with their neighbours). Applies when
                                   median_radius is 1..7 (never above it); rows of
                                   one radius form a band (see DEFAULTS AND WHY). 0:
                                   median_radius at every range (earlier versions'
                                   behaviour). Set 0 when tag_size is not the size of the
                                   tags in view. */
    int threshold_radius;       /* pixels, 0..ACTAG_MAX_THRESHOLD_RADIUS (default 8): half side
                                   of the adaptive threshold's window. About the white square's
                                   half side in pixels works best; raise it for large tags. */
    int threshold_offset;       /* grey levels, -255..255 (default 1): a pixel is white when
                                   it reaches the midpoint of its window's minimum and
                                   maximum less this (threshold.h). Lower it (0 or below)
                                   when background speckle forms many small white
                                   contours; raise it when white squares break up. */
    float size_tolerance;       /* fraction, [0, 10) (default 0.2): slack of the physical size
                                   filter (extents and area). Raise it when the range or
                                   aperture is known only roughly. */
    float min_area_fraction;    /* fraction, [0, 1e6) (default 0.175): a contour's area must reach
                                   this * diag_r_px * diag_az_px * (1 - size_tolerance), with
                                   diag_*_px the tag diagonal in pixels at the contour's range.
                                   The white square fills half that box face-on and
                                   0.5 cos(tilt) of it tilted: the default (0.14 of the box)
                                   passes tilts up to 74 degrees, beyond which the decoder
                                   read none in simulation. Lower it (the reference's 0.1)
                                   only when flatter tags must be tried: each contour it
                                   lets through costs RANSAC and a decode. */
    float max_area_fraction;    /* fraction, [min_area_fraction, 1e6) (default 1.0): ... at most
                                   this * diag_r_px * diag_az_px * (1 + size_tolerance). Raise
                                   it when blooming makes the white square look larger. */
    actag_quad_params quad;     /* RANSAC quadrilateral (quad.h; here: 100 iterations, sample
                                   fraction 0.1, early exit at inlier ratio 0.8, 0.6 required,
                                   inlier distance 2.5 px, parallel cos 0.9). More iterations
                                   (500, the paper's) cost time and rarely find more. */
    int decode_mode;            /* ACTAG_DECODE_FIT (default) or ACTAG_DECODE_BINARY (the
                                   paper's binary reading, for comparison with it). */
    actag_fit_params fit;       /* options of the fit decoder (decode.h, actag_fit_params_default)
                                   except min_margin: actag_detect() takes the least decision
                                   margin from actag_params.min_margin, which wins, and does not
                                   read fit.min_margin (it is there for direct callers of
                                   actag_decode_quad_fit; actag_tuning_default sets it to the
                                   same default). Change only to study the decoder, except
                                   fit.many_corrections_margin (1.5): the extra margin a
                                   reading with 3 or more corrected bits needs, raise it on
                                   murky sonars, 0 for recall where a wrong ID costs little;
                                   and fit.min_bit_odds (100): how much a reading with
                                   corrected bits must lead the next view by in bits (3 for
                                   2 or 3 corrected bits of a 24-bit tag), 10 for 4-5 % more
                                   far or blurred readings where a wrong ID costs little,
                                   1000 where none may happen; and the level-noise
                                   checks of poorly fitting readings (decode.h):
                                   ACTAG_FIT_LEVEL_NOISE (on by default; clear it only to
                                   compare with earlier builds), ACTAG_FIT_SEPARATE_NOISE
                                   (off; set it where a wrong ID costs far more than a
                                   miss on blurred or grazing tags: held-out runs, every
                                   known wrong ID refused for 1-2.4 % of simulated and 6 %
                                   of real pool readings, docs/evaluation.md). */
    float min_structure;        /* fraction, 0..1 (default 0): the fit decoder's black-ring
                                   and white-interior fractions must reach this; the misses
                                   below 1 are charged to the corrections budget anyway, which
                                   is the gate by default (1.0 refuses any miss, as before
                                   issue 8). */
    float min_texture_contrast; /* ratio, 0..1e6 (default ACTAG_MIN_TEXTURE_CONTRAST, 5): a fit-
                                   decoder reading's white-interior-minus-black-ring contrast
                                   must reach this many times the sd of a cell mean of the
                                   texture around its tag, from neighbouring cells' differences
                                   (src/texture.h; docs/decoder.md, "The texture test").
                                   Readings of speckle blobs measured 1.9-4.2, tags 11 or more
                                   on the real pool frames, 7.8 or more on simulated ones.
                                   Lower it (0: off) only where tags lie on texture as bright
                                   as their white squares; the paper's binary decoder
                                   (decode_mode) is not judged. */
    float min_side_fraction;    /* fraction of tag_size, [0, 1e6] (default 0.5): each quad side,
                                   measured in metres, must reach this * tag_size. Lower it
                                   (0.4) only where recall at low incidence matters more than
                                   clutter: 0.4 read 1.4 % more held-out views but gave 14
                                   wrong or false readings in 24,000 frames instead of 8
                                   (docs/evaluation.md, thirty-first session). */
    float max_side_fraction;    /* fraction of tag_size, [min_side_fraction, 1e6] (default 1.6):
                                   ... and stay within this * tag_size. Raise it when blooming
                                   is strong (near range, high gain). */
    int search_candidates;      /* structure search: positions decoded per frame, 0..ACTAG_SEARCH_MAX
                                   (default 2; 0 turns the search off). Raise it when several
                                   tags share a frame (each candidate costs one wide grid fit). */
    int search_min_score;       /* grey levels, 0..255 (default 15): least interior-minus-ring box
                                   contrast of a search position. Raise it on low-contrast
                                   clutter, lower it on faint tags. */
    int search_max_corrections; /* bits, >= 0 (default 3), capped by max_bit_corrections: the
                                   corrections limit of search readings. Lower it for fewer
                                   chance readings in clutter. */
    float search_min_margin;    /* decision margin, -1e6..1e6 (default ACTAG_SEARCH_MIN_MARGIN,
                                   1.0): search readings need this AND min_margin (the margin
                                   already allows for the ~165 grids the search tries). */
    float search_range_scale;   /* ratio, (0.05, 4] (default 0.75): expected range extent of a
                                   tag / tag_size in the search (tilted tags look shorter in
                                   range). Lower it for tags seen mostly edge-on in range. */
    int refine_corners;         /* 0 or 1 (default 1): each detection's corners refined by
                                   fitting its decoded template to the caller's frame (the
                                   filtered one in actag_detect_inplace; refine.h); the
                                   corners move, nothing else changes. The fit also
                                   starts from the fit decoder's grid when that lies more
                                   than half a cell from the quad (the smaller residual
                                   wins; docs/pose.md). 0 reports the quad's or the fit
                                   decoder's corners. */
    actag_limits limits;        /* work limits per call (see actag_limits above). Raise them
                                   only if stats report a limit reached on real frames. */
} actag_tuning;

/* Detection parameters: what a user sets, plus the tuning (by value).
 * actag_params_default() gives the defaults (the paper's Table I where kept;
 * DEFAULTS AND WHY above lists what changed and why). */
typedef struct actag_params {
    const actag_family *family; /* required: e.g. from actag_family_get() */
    float tag_size;             /* metres: side of the inner white square (default 3/7 ft,
                                   0.130628571); finite, > 0, below ACTAG_MAX_TAG_SIZE
                                   (1000 m) and at most sqrt(2) * geometry max_range
                                   (actag_check) */
    int max_bit_corrections;    /* 0 .. actag_family_max_corrections(family), or
                                   ACTAG_CORRECTIONS_AUTO (default): min(3, family maximum) */
    uint32_t seed;              /* RANSAC seed (default 1); any value */
    float min_margin;           /* least decision margin of a fit-decoder reading (decode.h;
                                   default ACTAG_FIT_MIN_MARGIN, 2.0), -1e6..1e6: raise it
                                   (e.g. 3) for fewer chance readings in clutter (held-out
                                   runs: 4 would refuse half the rare wrong IDs for 0.6-1.6 %
                                   of right readings, docs/evaluation.md; see also
                                   ACTAG_FIT_SEPARATE_NOISE in tuning.fit), lower it (e.g. -2)
                                   for recall on clean scenes. This one wins over
                                   tuning.fit.min_margin. */
    int handedness;             /* which views the sonar's mounting can show: ACTAG_HANDEDNESS_ANY
                                   (0, default), _UNMIRRORED or _MIRRORED (detection's
                                   `mirrored` = 0 or 1). A sonar upright above tags on the
                                   seabed sees every tag unmirrored, one mounted upside down
                                   every tag mirrored (docs/pose.md); saying so removes the
                                   other handedness from the decoder's hypotheses, and most
                                   wrong IDs on simulated frames were readings of that other
                                   handedness (docs/families.md). */
    actag_tuning tuning;        /* stage tuning (actag_tuning_default) */
} actag_params;

/* actag_params.handedness */
#define ACTAG_HANDEDNESS_ANY 0
#define ACTAG_HANDEDNESS_UNMIRRORED 1
#define ACTAG_HANDEDNESS_MIRRORED 2

/* decode_mode:
 *   ACTAG_DECODE_FIT     the grid-fitting grey decoder, actag_decode_quad_fit()
 *                        on the median-filtered frame (default; see below)
 *   ACTAG_DECODE_BINARY  actag_decode_quad() on the binary frame (the paper's) */
#define ACTAG_DECODE_FIT 0
#define ACTAG_DECODE_BINARY 1

/* max_bit_corrections = ACTAG_CORRECTIONS_AUTO (the default): the family's
 * maximum, capped at ACTAG_AUTO_CORRECTIONS. */
#define ACTAG_CORRECTIONS_AUTO (-1)
#define ACTAG_AUTO_CORRECTIONS 3

/* tuning.min_texture_contrast's default (see there). */
#ifndef ACTAG_MIN_TEXTURE_CONTRAST
#define ACTAG_MIN_TEXTURE_CONTRAST 5.0f
#endif
/* Default least decision margin of structure-search readings. */
#ifndef ACTAG_SEARCH_MIN_MARGIN
#define ACTAG_SEARCH_MIN_MARGIN 1.0f
#endif

/* Most structure-search candidates per frame (search_candidates). */
#define ACTAG_SEARCH_MAX 8

/* DEFAULTS AND WHY (measured on the 58 pool frames + the example frame, see
 * the decode.h manual for the decoder):
 *   - Pipeline order: median -> structure search -> threshold -> contours ->
 *     size filter -> RANSAC quad -> side-length check -> decode -> merge.
 *   - Median radius per range band (median_per_range 1): a tag's cells
 *     shrink in beams as 1 / range, and a square median whose window
 *     reaches into the neighbouring cells blurs them together, so each row
 *     takes the largest radius whose window spans at most half the cell's
 *     width in beams at its range plus 2 pixels (r <= (cell + 2) / 4): the
 *     windows around the decoder's sample points (0.2 cell from a cell's
 *     centre, the window's half-width about a quarter cell) then lie
 *     mostly inside the cell. Never below 2: a 3 x 3 window
 *     leaves too much speckle (1,000 simulated views at the paper's
 *     settings, seed 1: 436 read at radius 1 everywhere, 680 at 2). At
 *     most median_radius. The pool recording's sonar (0.1-1.5 m, 60
 *     degrees, 512 beams: cells 14 beams or wider) keeps 4 on every row:
 *     its detections are those of the fixed radius. The paper's sonar
 *     (0.1-5 m) takes 3 beyond 1.52 m and 2 beyond 2.12 m. Chosen on
 *     radius-per-distance runs (radius 2, 3 and 4 everywhere, tuning seeds
 *     31 and 32: radius 3 reads most at cells of 8-17 beams, 2 below 7;
 *     the rule takes 3 at 10-14 beams and 2 or 4 on either side, within
 *     1-4 views of radius 3 there; the earlier rule, half the cell, kept 4
 *     down to 8 beams), then
 *     checked on seeds nobody tuned on: paper seeds 1-10 read 627-674 ->
 *     655-704 of 1,000 (0 wrong IDs, mirror or order errors; seed 5's one
 *     wrong reading is gone); 24 held-out sweep runs of mixed sonars,
 *     appearances and families 10,833 -> 14,056 right readings with 6 ->
 *     8 frames in error (the same rate per reading, 5.5e-4 and 5.7e-4;
 *     docs/evaluation.md); 0 false detections on 10,000 tag-free frames,
 *     every family. Not the range direction: a cell's range extent
 *     depends on the view, unknown before the tag is found. The tracker's
 *     windows are capped at half the predicted cell's least width
 *     (track.h; its ROI searches take the band rule under that cap):
 *     measured better there than this rule's cap (pool passes 633 vs 629
 *     of 634).
 *   - Structure search: box sums over a 4x4-averaged copy of the filtered
 *     frame score every position by mean(3x3-cell box) - mean(ring of cells
 *     around it) at the tag's physical size (range extent scaled by
 *     search_range_scale); the best search_candidates separated maxima are
 *     decoded with ACTAG_FIT_WIDE, first without the template check (a
 *     tentative reading). It finds tags whose white square merged with data
 *     cells or clutter in the binary frame (no quad). A contour containing a
 *     tentative reading gets up to 10 RANSAC quads until one decodes, and a
 *     quad reading replaces the search reading at the same place, so corners
 *     come from quads whenever one decodes. A quad's (or contour guess's)
 *     reading that names another ID, handedness or corner order than the
 *     search's there is refused when the search's template, polished over
 *     the full range at both places, explains the cells at least as well
 *     (two readings of one place, neither with the lead its margin claims;
 *     the contour's next quad may read; trace outcome ACTAG_TRACE_RIVAL),
 *     and the search's reading is then not reported either: both readings
 *     passed their own checks, so the place gives no reading.
 *     A contour guess's reading is judged so against the search's reading
 *     and against the hypotheses of the contour's quads that the template
 *     check refused as too close to call.
 *     A tentative reading no quad
 *     replaced, and that refused no quad's or guess's reading, is read
 *     again with the template check (from the grids the first reading
 *     found) and reported with fitted-grid corners if it passes. Most search readings of a tag are replaced, so their template
 *     check, the costliest part of a wide reading, is skipped. Memory: the score map (int16, rows/4 x cols/4) uses the
 *     binary bitmap's and the contour marks' place before the threshold
 *     fills them, the integral
 *     image (uint32, (rows/4+1) x (cols/4+1)) the stage scratch (both
 *     counted in ACTAG_WORKSPACE_SIZE); frames under 16 pixels in either
 *     direction are not searched. Cost: the score map is about 5 % of a
 *     pool frame's x86 instructions (~0.15 ms on a desktop core), each
 *     position read about 3 M x86 instructions more (the wide grid search).
 *   - A size-plausible contour on which no RANSAC quad reads (ragged or
 *     hollow outlines of speckled white squares) is tried once more: its
 *     extreme points (farthest from the centroid, farthest from that, and
 *     farthest on either side of the line through both) start the fit
 *     decoder's wide grid search, and the reading is judged like a search
 *     reading (search corrections, margin, budget, sides), at most 16
 *     contours per frame. On 2,000 simulated pool views (seeds 1, 3) it
 *     raised the detection rate from 77 % to 87 % and at the paper's
 *     settings (seed 2) from 36 % to 38 %, with 0 wrong IDs, 0 mirror and 0
 *     order errors, and 0 false detections on 2,000 tag-free frames for
 *     every family; it costs ~60 % more decoder work per frame. A guess
 *     with a corner (an extreme point) on the frame's first or last row or
 *     column is not read (trace outcome ACTAG_TRACE_BORDER): the blob
 *     reaches the frame's edge, so its tag's data cells would lie outside
 *     the frame, or the point belongs to something the blob merged with.
 *   - A contour too large for a white square (up to 2.5 times its extents,
 *     3 times its area), where the tag's cells are under 10 beams wide, is
 *     a white square merged with its data cells: the beam's spread fills
 *     the one-cell black ring (far tags: blobs 1.4-2.4 times the white
 *     square's width). A white square's box at the blob's centre (sized as
 *     the structure search's) starts the wide grid search, judged like a
 *     contour's guess but with at most 2 corrected bits (the start is
 *     blind: with 3, a far tag was read turned half a turn at margin 4 in
 *     a held-out sweep), within the same 16 guesses per frame. Simulated
 *     paper settings: seed 1 692 -> 700 of 1,000, tuning seed 31 682 ->
 *     692, all beyond 2.5 m, 0 errors (docs/evaluation.md). Not where
 *     cells are 10 beams or wider: there it read nothing and cost a wide
 *     decode per large clutter blob (pool frames: +8 % Cortex-M7
 *     instructions); the pool frames' detections and costs are unchanged.
 *   - Search positions and merged blobs' boxes are blind boxes (the white
 *     square's size, axis-aligned, never fitted to an outline). Their own
 *     grid, which the decoder reads when the grid its wide search fitted
 *     reads nothing, is read with at most the corrected bits at which a
 *     chance word would match one of the family's codes with probability
 *     1 % (AcTag24h10: 1 instead of 3, 2 with a handedness prior; decode.h):
 *     over a tag turned in the
 *     image such a grid is a lattice across the tag's cells (a wrong ID at
 *     the paper's settings, seed 12 frame 759, hamming 2, margin 10.9;
 *     docs/decoder.md, "Blind boxes"). The pool frames' detections are
 *     unchanged.
 *   - Size filter's least area (min_area_fraction 0.175, the paper's 0.1
 *     before): a contour must reach 0.14 of the box of the tag's diagonal
 *     (with the 20 % tolerance), the white square seen 74 degrees off its
 *     normal (it fills half the box face-on, 0.5 cos(tilt) tilted). On
 *     1,375 simulated readings from contours no contour below 0.162 gave
 *     one, while half the clutter contours of the pool frames lie below
 *     0.14: they cost RANSAC and a wide-search guess each. Pool frames:
 *     x86 instructions -14 % (decoder -24 %, RANSAC -52 %); recall within
 *     the spread RANSAC seeds give (simulated paper settings, seed 2,
 *     RANSAC seeds 1-4: 1,928 vs 1,931 readings; pool frames 33-38 of 47
 *     over orientations and seeds 1-8 as before), 0 wrong IDs.
 *   - Two readings at the same place (centre inside the other's
 *     circumcircle) are one tag: the lower hamming wins (then the higher
 *     inlier ratio); this also drops misreadings with another ID.
 *   - Trust: every reading passes the fit decoder's likelihood match,
 *     template check and decision margin (decode.h), and its black ring,
 *     white interior and corrected bits share one budget: ring cells read
 *     white plus interior cells read black plus corrected bits within the
 *     corrections limit (min_structure 0: no separate gate; 1.0 before
 *     issue 8 cost 6 + 5 of 1,000 simulated pool views, seeds 1 and 3,
 *     and pool frame 0311, with no error either way).
 *     And its white interior must stand out from its black ring by
 *     min_texture_contrast (5) times the sd of a cell mean of the texture
 *     around the tag (src/texture.h): the margin's noise is estimated
 *     from cells chosen because they look like a tag, so single-look or
 *     beam-blurred speckle blobs reached margins of 13 (ACTAG_TRACE_TEXTURE).
 *     Measured with actag-eval (docs/evaluation.md): 0 wrong IDs, 0 wrong
 *     handednesses and 0 corner-order errors in 1,000 simulated views at
 *     the paper's settings and 1,000 at the pool's (9 wrong IDs and 3
 *     wrong handednesses per 1,000 pool views before).
 *   - Table I values kept: median radius 4 (the largest: see the bands
 *     above), threshold radius 8, offset 1,
 *     inlier distance 2.5. Changed: RANSAC early exit 0.85 -> 0.8 with
 *     0.6 required (ragged sonar contours; the decoder judges), 500 -> 100
 *     iterations (the search covers RANSAC misses; same recall, ~2 ms less).
 */

/* One detected tag. */
typedef struct actag_detection {
    int id;                    /* tag ID in the family */
    int hamming;               /* corrected bits */
    int mirrored;              /* 1 when the sonar shows the tag mirrored */
    actag_point corners[4];    /* image position (x = column, y = row), tag order TL TR BR BL */
    float range[4];            /* metres, per corner */
    float azimuth[4];          /* radians, per corner */
    float inlier_ratio;        /* RANSAC support of the quadrilateral */
    float decision_margin;     /* how much better the reported code and orientation explain
                                  the cells than the next hypothesis (another ID, rotation or
                                  handedness): the log-likelihood ratio less ln(number of
                                  hypotheses: 8 views of every code, times the grids tried,
                                  counted so also when p.handedness leaves 4 views), so about
                                  0 on pure noise and 5-30 on a clear tag (decode.h,
                                  actag_decode_quad_fit); binary decoder: the other
                                  handedness' extra bits, but for readings of the structure
                                  search, which always uses the fit decoder (set
                                  tuning.search_candidates = 0 for the paper's pipeline) */
} actag_detection;

/* Optional counters of one call. */
typedef struct actag_stats {
    int contours;        /* outer borders traced */
    int size_ok;         /* contours that passed the physical size filter */
    int overflowed;      /* contours longer than the point buffer (skipped) */
    int quads;           /* quadrilaterals fitted */
    int decoded;         /* readings accepted after their rival checks (of quads, search
                            candidates and contour guesses; a search reading that a
                            quad's or guess's reading of its place superseded counts
                            too), before duplicates and max_out drop some */
    int duplicates;      /* accepted readings dropped as the same tag seen twice */
    int dropped;         /* tags beyond max_out (one per tag: see ERRORS above) */
    int searched;        /* structure-search candidates decoded */
    /* work done and limits reached (actag_limits): contour_cap, contour_budget,
     * frame_budget, decode_cap and guess_cap are 0 on every pool frame at the
     * defaults; ransac_exhausted, search_cap and overflowed are not (a border
     * longer than the point limit, a fit without an early exit, more search
     * positions than search_candidates are ordinary) */
    int decodes;          /* decoder calls made (quads, search, guesses) */
    int iterations;       /* RANSAC iterations run */
    int contour_cap;      /* 1 when the scan stopped at limits.max_contours */
    int ransac_exhausted; /* quad fits that ran all their iterations without an early exit */
    int contour_budget;   /* contours whose quad tries stopped at limits.max_contour_iterations
                             (a fit skipped, or one that ran the lowered cap out) */
    int frame_budget;     /* quad fits skipped, or cut short (ran the lowered cap out), by
                             limits.max_frame_iterations; a cap lowered but not reached
                             is not counted */
    int decode_cap;       /* decoder calls skipped at limits.max_decodes */
    int search_cap;       /* 1 when candidates above search_min_score were left undecoded */
    int guess_cap;        /* contours given no extreme-point or merged-blob guess (16
                             guesses per frame at most) */
} actag_stats;

/* Largest threshold_radius the workspace is sized for (stb-style
 * configuration: define it before including actag.h, and build the library
 * with the same value). The paper uses 8. */
#ifndef ACTAG_MAX_THRESHOLD_RADIUS
#define ACTAG_MAX_THRESHOLD_RADIUS 32
#endif

/* Points buffered for one contour: no contour that could be a tag is longer. */
#define ACTAG_CONTOUR_CAP(rows, cols) (4 * ((size_t)(rows) + (size_t)(cols)) + 64u)

#define ACTAG__ALIGN16(n) ((((size_t)(n)) + 15u) & ~(size_t)15u)
#define ACTAG__MAX(a, b) ((a) > (b) ? (a) : (b))
#define ACTAG__SUBSAT(a, b) ((a) > (b) ? (a) - (b) : 0u)
/* actag_detect_inplace's S (see ACTAG_WORKSPACE_SIZE_INPLACE): the contour
 * and quad buffers, or what the other stages need beyond the two bitmaps. */
#define ACTAG__INPLACE_SCRATCH(rows, cols)                                                   \
    ACTAG__MAX(ACTAG__MAX(ACTAG__ALIGN16(ACTAG_CONTOUR_CAP(rows, cols) * sizeof(actag_ipoint)) + \
                              ACTAG_QUAD_SCRATCH_SIZE(ACTAG_CONTOUR_CAP(rows, cols)),          \
                          ACTAG__SUBSAT(ACTAG_THRESHOLD_BITMAP_SCRATCH_SIZE_R(                 \
                                            rows, cols, ACTAG_MAX_THRESHOLD_RADIUS),           \
                                        ACTAG__ALIGN16(ACTAG_BITMAP_SIZE(rows, cols)))),       \
               ACTAG__SUBSAT(ACTAG__MAX(ACTAG__ALIGN16(ACTAG_SEARCH_MAP_SIZE(rows, cols)) +    \
                                            ACTAG_SEARCH_INTEGRAL_SIZE(rows, cols),           \
                                        ACTAG_MEDIAN_INPLACE_SCRATCH_SIZE(cols)),              \
                             2u * ACTAG__ALIGN16(ACTAG_BITMAP_SIZE(rows, cols))))

/* actag_detect's S: the same, and the median's column histograms beyond
 * what the bitmaps hold (the median fills B, so A, M and S are its scratch). */
#define ACTAG__STAGE_SCRATCH(rows, cols)                                                     \
    ACTAG__MAX(ACTAG__INPLACE_SCRATCH(rows, cols),                                          \
               ACTAG__SUBSAT(ACTAG_MEDIAN_SCRATCH_SIZE(rows, cols),                         \
                             2u * ACTAG__ALIGN16(ACTAG_BITMAP_SIZE(rows, cols))))

/* Workspace bytes for frames of up to rows x cols pixels (a constant
 * expression), each part 16-byte aligned, plus 16 bytes to align the start:
 *   - A, the binary bitmap, and M, the contour marks, one bit per pixel each
 *     (ACTAG_BITMAP_SIZE: (rows + 2) * ((cols + 33) / 32) * 4 bytes): scale
 *     with rows * cols, 1/4 byte per pixel together;
 *   - S, the contour point buffer and the quad scratch (ACTAG_CONTOUR_CAP
 *     points, 13 bytes each: about 52 (rows + cols) bytes), or what the
 *     other stages need beyond A and M while those are free, whichever is
 *     larger: A, M and S are one region each stage uses in turn (the
 *     median's column histograms, 272 bytes for each of at most 256
 *     columns, and 2 bytes per column for 16-bit rows; the search's score
 *     map and integral image, 3/8 byte a pixel; the threshold's row buffers
 *     in M and S, (2 * min(2 * ACTAG_MAX_THRESHOLD_RADIUS + 1, rows) + 7)
 *     bytes per column);
 *   - B, the median-filtered frame, one byte per pixel: rows * cols.
 * 530 x 512: 72,352 + 55,024 (contours + quads 55,020; the median 70,656,
 * the threshold 70,144 and the search 102,420 fit A, M and S) + 271,360 +
 * 16 = 398,752 bytes. */
#define ACTAG_WORKSPACE_SIZE(rows, cols)                                                     \
    (16u + 2u * ACTAG__ALIGN16(ACTAG_BITMAP_SIZE(rows, cols)) +                             \
     ACTAG__ALIGN16(ACTAG__STAGE_SCRATCH(rows, cols)) +                                     \
     ACTAG__ALIGN16((size_t)(rows) * (size_t)(cols)))

/* ACTAG_WORKSPACE_SIZE at run time; 0 for sizes outside 1..ACTAG_MAX_DIM. */
size_t actag_workspace_size(int rows, int cols);

/* Workspace bytes of actag_detect_inplace() for frames of up to rows x cols
 * pixels (a constant expression): the two bitmaps as in
 * ACTAG_WORKSPACE_SIZE, and no filtered frame (it goes into the caller's
 * buffer), so the largest of the contour point and quad buffers (ACTAG_
 * CONTOUR_CAP points: 13 bytes each), the threshold's row buffers at
 * ACTAG_MAX_THRESHOLD_RADIUS, the search's score map and integral image and
 * the median's row copy, less what of them the bitmaps' bytes hold while
 * those are free, plus 16 alignment bytes. Scales like the bitmaps (rows x
 * cols / 4 bytes) plus the contour buffers (13 bytes per point of
 * ACTAG_CONTOUR_CAP, about 52 (rows + cols)); for large frames the search's
 * map and integral image (3/8 byte a pixel) decide. 530 x 512: 16 + 72,352
 * + 55,024 (the contour and quad buffers) = 127,392 bytes (a 128 KiB DTCM
 * holds it); 256 x 256: 46,080; 1024 x 1024: 395,296 (there the search
 * decides). */
#define ACTAG_WORKSPACE_SIZE_INPLACE(rows, cols)                                             \
    (16u + 2u * ACTAG__ALIGN16(ACTAG_BITMAP_SIZE(rows, cols)) +                             \
     ACTAG__ALIGN16(ACTAG__INPLACE_SCRATCH(rows, cols)))

/* ACTAG_WORKSPACE_SIZE_INPLACE at run time; 0 for sizes outside
 * 1..ACTAG_MAX_DIM. */
size_t actag_workspace_size_inplace(int rows, int cols);

/* Fill *p with the defaults (the paper's Table I where kept, DEFAULTS AND
 * WHY lists the changes; family NULL: set it). No-op for NULL; no error
 * codes. */
void actag_params_default(actag_params *p);

/* Fill *t with the default tuning (the values documented in actag_tuning;
 * no-op for NULL). actag_params_default() calls it. */
void actag_tuning_default(actag_tuning *t);

/* Checks *p alone (no frame or geometry): family, max_bit_corrections,
 * tag_size finite, > 0 and below ACTAG_MAX_TAG_SIZE, min_margin in [-1e6, 1e6],
 * handedness one of
 * ACTAG_HANDEDNESS_ANY, _UNMIRRORED, _MIRRORED, then the tuning
 * (actag_tuning_validate, fields named "tuning.*"). Returns ACTAG_OK or
 * ACTAG_ERR_NULL (p or p->family), _FAMILY, _CORRECTIONS, _PARAM; fills
 * *detail when not NULL (ERROR DETAILS above). */
int actag_params_validate(const actag_params *p, actag_error_detail *detail);

/* Checks *t: the ranges documented with each actag_tuning field, then
 * actag_quad_params_validate(&t->quad) and actag_fit_params_validate(&t->fit)
 * (fields "quad.inlier_distance", "fit.level", ...). Returns ACTAG_OK,
 * ACTAG_ERR_NULL or ACTAG_ERR_PARAM; fills *detail when not NULL. */
int actag_tuning_validate(const actag_tuning *t, actag_error_detail *detail);

/* Every check actag_detect(frame, geometry, params, <workspace>,
 * workspace_size, <out>, max_out, ...) makes before it runs, with the same
 * result code (ERROR DETAILS above): ACTAG_OK, or ACTAG_ERR_BUILD (checked
 * first), _NULL, _SIZE, _PARAM, _GEOMETRY, _FAMILY, _CORRECTIONS,
 * _WORKSPACE. Fills *detail when not NULL. Reads the bearing table, no
 * pixels. */
int actag_check(const actag_frame *frame, const actag_sonar_geometry *geometry,
                const actag_params *params, size_t workspace_size, int max_out,
                actag_error_detail *detail);

/* Detect tags. Writes at most max_out detections to out and returns their
 * number (>= 0), or a negative ACTAG_ERR_* code. stats may be NULL. */
int actag_detect(const actag_frame *frame, const actag_sonar_geometry *geometry,
                 const actag_params *params, void *workspace, size_t workspace_size,
                 actag_detection *out, int max_out, actag_stats *stats);

/* actag_check() for actag_detect_inplace(): the same checks, then
 * tuning.median_radius at most ACTAG_MEDIAN_INPLACE_MAX_RADIUS (7; the
 * default is 4) else ACTAG_ERR_PARAM, and workspace_size at least
 * actag_workspace_size_inplace(rows, cols) else ACTAG_ERR_WORKSPACE. */
int actag_check_inplace(const actag_frame *frame, const actag_sonar_geometry *geometry,
                        const actag_params *params, size_t workspace_size, int max_out,
                        actag_error_detail *detail);

/* actag_detect() for firmware that can give up the frame buffer: the
 * median-filtered frame is written over the caller's pixels
 * (actag_median_filter_inplace, median.h) instead of into the workspace, so
 * the workspace is ACTAG_WORKSPACE_SIZE_INPLACE(rows, cols) bytes (127,392
 * at 530 x 512, against 398,752 for actag_detect).
 *   frame->data must point to WRITABLE memory (not a frame in flash): on
 *   return its first rows * cols bytes hold the filtered 8-bit frame, stride
 *   cols, and the rest of the buffer is unspecified (on an error code
 *   before the filter, e.g. ACTAG_ERR_WORKSPACE, it is untouched).
 *   Results: the same tags, IDs, handedness, corner order, margins and
 *   statistics as actag_detect() with the same arguments; only the corner
 *   refinement (tuning.refine_corners) differs, as it reads the filtered
 *   frame instead of the raw one (the corners move by a fraction of a pixel;
 *   docs/memory.md gives the figures). With refine_corners 0 the output is
 *   identical.
 *   Errors: those of actag_check_inplace(), and ACTAG_ERR_NULL for a NULL
 *   workspace or a NULL out with max_out > 0; every error is returned before
 *   the filter writes, so the frame is untouched then. No tracer; stats may
 *   be NULL. */
int actag_detect_inplace(const actag_frame *frame, const actag_sonar_geometry *geometry,
                         const actag_params *params, void *workspace, size_t workspace_size,
                         actag_detection *out, int max_out, actag_stats *stats);

/* actag_detect() with a callback that sees every candidate (trace.h); trace
 * may be NULL. Same results, same errors. */
int actag_detect_traced(const actag_frame *frame, const actag_sonar_geometry *geometry,
                        const actag_params *params, void *workspace, size_t workspace_size,
                        actag_detection *out, int max_out, actag_stats *stats,
                        actag_trace_fn trace, void *user);

/* Several parameter sets on one frame (for example several families, or one
 * family at several correction limits): the frame is median-filtered once and
 * every set runs the rest of the pipeline on it, so set i gets exactly what
 * actag_detect(frame, geometry, &params[i], ...) would give, at a fraction of
 * the cost. A set whose median radii differ from the previous set's (another
 * median_radius or median_per_range, or with median_per_range another
 * tag_size or cell count, e.g. a 28-bit family after a 24-bit one) filters
 * the frame again: order the sets so that alike ones follow each other.
 * Set i's detections go to out[i * max_out_each ...], their number
 * to counts[i] (extra ones are dropped, as with actag_detect). Returns ACTAG_OK
 * or the first error: ACTAG_ERR_NULL (params, workspace, counts, or out with
 * max_out_each > 0), ACTAG_ERR_PARAM for nparams < 1, then for i = 0, 1, ...
 * what actag_check(frame, geometry, &params[i], workspace_size, max_out_each)
 * returns; counts is then undefined. The
 * workspace is that of one actag_detect call. */
int actag_detect_multi(const actag_frame *frame, const actag_sonar_geometry *geometry,
                       const actag_params *params, int nparams, void *workspace,
                       size_t workspace_size, actag_detection *out, int max_out_each,
                       int *counts);

/* After a successful actag_detect() on a rows x cols frame, these point at
 * the stage images inside the workspace: actag_workspace_filtered() at the
 * median-filtered frame (one byte per pixel, row stride = cols),
 * actag_workspace_bitmap() at the binary frame as a bitmap (one bit per
 * pixel, 1 = white, the layout in common.h; read a pixel with
 * actag_bitmap_get(), or turn it into bytes with actag_bitmap_unpack(),
 * contours.h). They return NULL for a NULL workspace or a size outside
 * 1..ACTAG_MAX_DIM; no other error codes. For debugging/overlays. */
const uint8_t *actag_workspace_filtered(const void *workspace, int rows, int cols);
const uint32_t *actag_workspace_bitmap(const void *workspace, int rows, int cols);

#ifdef __cplusplus
}
#endif
#endif /* ACTAG_ACTAG_H */
