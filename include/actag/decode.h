/*
 * actag/decode.h -- from a quadrilateral to a tag: ID, orientation, corners.
 *
 * MANUAL
 *   The quad stage hands over the 4 corners of a candidate tag's inner WHITE
 *   square (image pixels, x = column, y = row). This stage maps the tag's cell
 *   grid into the image (least-squares affine map by default, or the 4-point
 *   homography), samples the data ring in the binary image (0 = black =
 *   aluminium, nonzero = white = foam), and matches the bits against a family.
 *
 *   The tag's cell grid, its layout and the grid -> image maps
 *   (actag_tag_affine, actag_tag_homography, actag_decode_bit_positions, the
 *   ACTAG_DECODE_AFFINE / _PROJECTIVE models) are in tag_grid.h, which this
 *   header includes.
 *
 *   actag_decode_read_word(binary, ..., quad, bits, model, &word)
 *       The raw 4k-bit word read in quad order: bit i of the sequence (word
 *       bit 4k-1-i) is the vote of data cell i with quad[n] taken as corner n.
 *   actag_decode_mirror(word, bits)
 *       The reflection P of a word read from a corner: sequence position s
 *       takes sequence position (-s) mod 4k (position 0 stays, the rest is
 *       reversed; as a code: keep the MSB, reverse the low 4k-1 bits).
 *       P is its own inverse.
 *   actag_decode_quad(binary, ..., quad, family, max_corrections, &res)
 *       The decoder proper (default map); see below.
 *   actag_decode_quad_ex(..., max_corrections, model, &res)
 *       The same with a chosen map, ACTAG_DECODE_AFFINE or _PROJECTIVE.
 *
 *   Sampling: each cell is read at a 3x3 pattern of points, the cell centre
 *   +-0.25 cell in u and v, each mapped through the homography to the
 *   nearest pixel (pixels outside the image count as black); the majority of
 *   the 9 votes decides the bit (5 or more white -> 1).
 *
 *   Orientation and mirroring. The quad's corners are taken to be
 *   consecutive; the decoder does not assume which one is the tag's top-left.
 *   A quad given counter-clockwise on screen (x right, y down) is first
 *   reordered to clockwise, quad[0] staying first, so res.observed is always
 *   read clockwise ON SCREEN from quad[0]. For a tag shown as printed
 *   (rotated, perspective-warped), that word is rot90^r(code). For a tag shown
 *   mirrored (any geometric reflection of the printed layout, as the sonar's
 *   elevation projection can produce), reading clockwise on screen is
 *   reading the tag counter-clockwise from one of its corners, which gives
 *       P(observed) == rot90^r(code)
 *   and NOT reverse(rot90^r(code)): a reflection pivots on a corner cell
 *   (sequence position s <-> jk - s), whereas the SPEC's full-word reversal
 *   pivots between cells 0 and 4k-1 (s <-> -1 - s), which no reflection of
 *   the square does. (The reference decoder agrees with P: its
 *   "counter-clockwise" table swaps positions j and 4k-j, keeping 0 and 2k,
 *   and its corner order for those matches is the one below; SPEC section 2's
 *   "rev" misdescribes it.) The decoder therefore calls
 *   actag_family_match_rotations() on observed and on P(observed) and keeps
 *   the one with fewer corrected bits; on a tie, the unmirrored reading.
 *
 *   CAUTION: the family generator guarantees the minimum distance h between
 *   rotations and full reversals, not between rotations and reflections P.
 *   For the published 24-bit families the smallest distance between an
 *   unmirrored and a mirrored reading (same or other code) is 6 (h10), 2 (h8),
 *   2 (h6) and 0 (h4: 11 pairs of codes are each other's mirror images, e.g.
 *   IDs 402 and 2046, whose IDs cannot be told apart when mirroring is
 *   possible, and 7 codes are mirror-symmetric, e.g. ID 291, whose
 *   handedness cannot be told).
 *   So bit corrections can confuse a mirrored tag with an unmirrored one (or
 *   another ID) sooner than max_corrections suggests; use few corrections
 *   when mirrored tags are expected, and res.mirror_margin to judge.
 *
 *   Results (actag_decode_result):
 *     id, hamming  tag ID and number of corrected bits.
 *     mirrored     1 when the tag appears mirrored on screen.
 *     rotation     which printed corner (0 TL, 1 TR, 2 BR, 3 BL) of the white
 *                  square lies at quad[0] (unmirrored: observed ==
 *                  rot90^rotation(code); mirrored: P(observed) ==
 *                  rot90^rotation(code)).
 *     observed     the raw word read clockwise on screen from quad[0].
 *     corners[n]   the white square's printed corner n (TL, TR, BR, BL) in
 *                  the image: one of the input quad points, copied exactly.
 *                  Unmirrored: corners[n] = quad[(n - rotation) mod 4];
 *                  mirrored:   corners[n] = quad[(rotation - n) mod 4]
 *                  (quad here in its clockwise-on-screen order).
 *     mirror_margin  d_other - hamming (>= 0; the fit decoder's differs, see
 *                  actag_decode_quad_fit), where d_other is the best
 *                  distance of the OTHER handedness (mirrored if this reading
 *                  is unmirrored and vice versa); 0 means both fit equally
 *                  well (the unmirrored one was taken). When the other
 *                  handedness has nothing within the family's maximum
 *                  corrections m, d_other counts as m + 1 (a lower bound).
 *     ring_black   fraction (0..1) of the samples on the black ring (the ring
 *                  inside the data bits) that read black;
 *     interior_white  fraction of the white-square samples that read white.
 *                  Both are informative only: the decoder does not reject on
 *                  them (the reference does not check either; real sonar
 *                  frames are speckled). A pipeline may threshold them to cut
 *                  false positives (clean renders give 1.0).
 *
 *   Memory: no scratch buffer (ACTAG_DECODE_SCRATCH_BYTES is 0), a few
 *   hundred bytes of stack. Cost: (4k + 4(k-2) + (k-3)^2) cells x 9 samples,
 *   each one map evaluation (one division), then two family scans: about
 *   2 us per quad for AcTag24h10 and 70 us for AcTag24h4 (6261 codes x 4
 *   rotations x 2 handednesses) on a desktop x86 core.
 *
 * ERRORS
 *   ACTAG_ERR_NULL         a pointer argument is NULL
 *   ACTAG_ERR_SIZE         rows or cols < 1 or > ACTAG_MAX_DIM, or stride < cols
 *   ACTAG_ERR_PARAM        bits not one of 16, 20, 24, 28, 32; unknown model;
 *                          degenerate quad: non-finite, not strictly convex
 *                          (each corner's turn must have |sin| > 1e-3, all the
 *                          same way, judged in float: a quad so small that the
 *                          products of its sides underflow, sides under about
 *                          1e-11 pixels, is degenerate), or (projective only) the homography
 *                          sends part of the (k+1)^2 tag grid through
 *                          infinity (extreme perspective)
 *   ACTAG_ERR_FAMILY       the family fails actag_family_validate()
 *   ACTAG_ERR_CORRECTIONS  max_corrections < 0 or above
 *                          actag_family_max_corrections(family)
 *   ACTAG_ERR_NO_MATCH     no code within max_corrections, either handedness
 */
#ifndef ACTAG_DECODE_H
#define ACTAG_DECODE_H

#include "actag/common.h"
#include "actag/family.h"
#include "actag/tag_grid.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The decoder needs no workspace. */
#define ACTAG_DECODE_SCRATCH_BYTES(rows, cols) ((size_t)0)

/* Offset (cells) of the outer sample points from a cell centre. */
#define ACTAG_DECODE_SAMPLE_OFFSET 0.25f

typedef struct actag_decode_result {
    int id;                 /* tag ID in the family */
    int hamming;            /* corrected bits */
    int mirrored;           /* 1: the tag appears mirrored on screen */
    int rotation;           /* printed corner (0 TL .. 3 BL) at quad[0] */
    uint32_t observed;      /* word read clockwise on screen from quad[0] */
    actag_point corners[4]; /* white-square corners in the tag's order: TL, TR, BR, BL */
    int mirror_margin;      /* best other-handedness distance minus hamming */
    float ring_black;       /* fraction of black-ring samples read black */
    float interior_white;   /* fraction of white-square samples read white */
    /* Filled by actag_decode_quad_fit() (0 from the other decoders, whose
     * fit_corners are their corners): */
    float contrast;         /* white-interior minus black-ring mean, grey levels */
    float flip_weight;      /* sum of the corrected bits' confidences (see fit decoder) */
    float min_confidence;   /* smallest data-bit confidence */
    int bit_margin;         /* fit decoder: the runner-up's corrected bits minus hamming */
    float decision_margin;  /* fit decoder: log-likelihood ratio of this reading over the
                               next, less the look-elsewhere allowance (see
                               actag_decode_quad_fit); binary decoder: mirror_margin */
    actag_point fit_corners[4]; /* the fitted grid's white-square corners, tag order */
} actag_decode_result;

/* Reads the raw word in quad order (quad[n] = corner n, no reordering) from
 * the binary frame (rows x cols, stride bytes; nonzero = white), with the
 * bit-sampling model of actag_decode_quad (model), into *word. Returns
 * ACTAG_OK, ACTAG_ERR_NULL (binary, quad or word NULL), ACTAG_ERR_SIZE (rows
 * or cols < 1 or > ACTAG_MAX_DIM, stride < cols) or ACTAG_ERR_PARAM (bits not
 * a multiple of 4 in 16..32, unknown model, degenerate quad). */
int actag_decode_read_word(const uint8_t *binary, int rows, int cols, int stride,
                           const actag_point quad[4], int bits, int model, uint32_t *word);

/* The corner reflection P (see the manual); bits in 16..32, multiple of 4.
 * No error codes: bits outside 2..32 return word unchanged. */
uint32_t actag_decode_mirror(uint32_t word, int bits);

/* Decodes one quad with the default map; fills *out on ACTAG_OK only. */
int actag_decode_quad(const uint8_t *binary, int rows, int cols, int stride,
                      const actag_point quad[4], const actag_family *family,
                      int max_corrections, actag_decode_result *out);

/* The same with a chosen map model (ACTAG_DECODE_AFFINE / _PROJECTIVE). */
int actag_decode_quad_ex(const uint8_t *binary, int rows, int cols, int stride,
                         const actag_point quad[4], const actag_family *family,
                         int max_corrections, int model, actag_decode_result *out);

/* actag_decode_quad() on a bitmap (common.h layout, 1 = white; e.g. the
 * output of actag_adaptive_threshold_bitmap), rows x cols pixels: the same
 * reading as actag_decode_quad() on the bitmap's bytes (actag_bitmap_unpack).
 * Errors as actag_decode_quad (ACTAG_ERR_NULL for a NULL bitmap). */
int actag_decode_quad_bitmap(const uint32_t *bitmap, int rows, int cols,
                             const actag_point quad[4], const actag_family *family,
                             int max_corrections, actag_decode_result *out);


/* Largest k (bits / 4) the decoders handle. */
#define ACTAG_DECODE_MAX_K 8

/* Flags of actag_decode_quad_fit(). */
#define ACTAG_FIT_NO_SEARCH 1     /* read the quad's grid as given (no grid fit) */
#define ACTAG_FIT_LOCAL 2         /* per-bit mid level from the bit's own ring/interior neighbours */
#define ACTAG_FIT_SPLIT 4         /* code-aware data threshold (see the manual below) */
#define ACTAG_FIT_WIDE 16         /* start with a +-1 cell position / rotation / shear search */
#define ACTAG_FIT_ERASE_CORNERS 64 /* the data ring's 4 corner cells do not count */
#define ACTAG_FIT_VERIFY 128      /* template check of the likeliest readings (see below) */
/* Handedness prior (on screen, as the result's `mirrored`): the other
 * handedness' views are no hypotheses (actag_family_match_soft_views);
 * setting both is ACTAG_ERR_PARAM. actag_detect() sets them from
 * actag_params.handedness. */
#define ACTAG_FIT_ONLY_UNMIRRORED 256
#define ACTAG_FIT_ONLY_MIRRORED 512
/* Level noise (see the manual below, step 5): where the reading's template
 * explains the cells poorly (cell noise above a fifth of the contrast),
 * the template check also scores each template with the black and the
 * white cells at their own noise variance (the reading's, as s^2 is), and
 * decision_margin is the smaller lead. On by default: it refused six of
 * the nine wrong IDs known from held-out simulated frames (and lowered the
 * others' margins to 2.7-4.2) for 0.15-0.9 % of the simulated readings
 * and one real pool frame in three of the four orientations
 * (docs/evaluation.md, thirty-ninth session). */
#define ACTAG_FIT_LEVEL_NOISE 2048
/* Stricter, off by default: each template is scored with its own black
 * and white variances (a generalised likelihood ratio). It refused all
 * nine, at 1-2.4 % of the simulated readings and 6 % of the real pool
 * frame readings. */
#define ACTAG_FIT_SEPARATE_NOISE 1024
#define ACTAG_FIT_DEFAULT_FLAGS                                                              \
    (ACTAG_FIT_LOCAL | ACTAG_FIT_SPLIT | ACTAG_FIT_ERASE_CORNERS | ACTAG_FIT_VERIFY |         \
     ACTAG_FIT_LEVEL_NOISE)

/* ACTAG_FIT_SPLIT tries data thresholds from LO to HI of the tag's contrast
 * above its black ring. */
#define ACTAG_FIT_SPLIT_LO 0.1f
#define ACTAG_FIT_SPLIT_HI 0.5f

/* Default least decision margin of the fit decoder (log-likelihood units,
 * see actag_decode_quad_fit): the reading must be e^2 (7.4) times likelier
 * than the runner-up after the look-elsewhere allowance. 1 let one wrong ID
 * through in 300 simulated pool views read with rows flipped (a quad reading
 * of 3 corrections at margin 1.85, after the second grid was added); correct
 * readings below 2 are about 1 in 200 (docs/decoder.md). */
#define ACTAG_FIT_MIN_MARGIN 2.0f

/* Default least lead in corrected bits of a fit-decoder reading. */
#define ACTAG_FIT_MIN_BIT_MARGIN 2

/* Default least odds of a reading over its runner-up from the corrected bits
 * alone (actag_fit_params.min_bit_odds). A reading that corrected h of the n
 * bits it read has a bit-error rate of about h / n; were its bits flipped
 * independently at that rate, a view b bits further (bit_margin b) would be
 * (h / (n - h))^b times as likely to be the tag. The reading must make that
 * at most 1 / min_bit_odds. With 100 and the 20 bits a 24-bit family's
 * decoder reads: 2 bits of lead for 1 corrected bit, 3 for 2 or 3; 28-bit
 * families (24 bits read): 2 for 1 or 2, 3 for 3. The soft margin cannot do
 * this: its cell noise model is fitted to the cells, and a view the blur or
 * the grid turned into another code's explains them well. At the paper's
 * settings (actag-eval --frames 1000, seeds 101-111, 7,552 right readings)
 * the 3 wrong IDs were all readings of 2 or 3 corrected bits leading by 2
 * (margins 5.0-12.5, the other handedness of another ID); with 100 none is
 * read, for 4-6 % fewer right readings (docs/decoder.md, "Odds from the
 * corrected bits"). */
#define ACTAG_FIT_MIN_BIT_ODDS 100
/* The largest min_bit_odds accepted (actag_fit_bit_lead, the validator). */
#define ACTAG_FIT_MAX_BIT_ODDS 1000000

/* Defaults of the extra margin a reading at the correction limit needs
 * (actag_fit_params.many_corrections, .many_corrections_margin): with 3 or
 * more corrected bits a reading must lead by min_margin + 1.5. Over the 20
 * cells the decoder reads, a physically mirrored AcTag24h10 view is 5 bits
 * from another ID (docs/families.md), so a reading with 3 corrections may
 * lie as near another code as its own; its margin then rests on the soft
 * cell evidence alone, whose noise model is optimistic on speckle.
 * Measured on 24,000 simulated views (actag-eval at the paper's settings,
 * seeds 313-316, six appearances): 7 wrong IDs and 1 wrong handedness, all
 * with 3 corrections at margins 2.05-3.42, against 162 of the 8,098 right
 * readings (2 %) with 3 corrections below 3.5 (docs/decoder.md, "Readings
 * at the correction limit"). */
#define ACTAG_FIT_MANY_CORRECTIONS 3
#define ACTAG_FIT_MANY_CORRECTIONS_MARGIN 1.5f

/* Options of actag_decode_quad_fit(). */
typedef struct actag_fit_params {
    int flags;           /* ACTAG_FIT_* (default ACTAG_FIT_DEFAULT_FLAGS) */
    float level;         /* mid level between ring black (0) and interior white (1), 0.5 */
    int min_contrast;    /* interior minus ring mean must reach this, grey levels (5) */
    float sample_offset; /* cells from a cell centre to its outer sample points, 0..0.5 (0.2) */
    float min_margin;    /* least decision_margin accepted (default ACTAG_FIT_MIN_MARGIN, 2;
                            raise it, e.g. to 3, for fewer chance readings in clutter, lower
                            it, e.g. to -2, for recall on clean scenes). actag_detect() uses
                            actag_params.min_margin instead. */
    int min_bit_margin;  /* least lead in corrected bits over any other reading
                            (ACTAG_FIT_MIN_BIT_MARGIN, 2) */
    int min_bit_odds;    /* least odds of a reading with corrected bits over the runner-up
                            from its hard bits alone (1..ACTAG_FIT_MAX_BIT_ODDS = 1000000; default
                            ACTAG_FIT_MIN_BIT_ODDS, 100; 1 turns the rule off). Lower it
                            (e.g. 10) for recall of far or blurred tags where a wrong ID
                            does little harm; raise it (1000) where none may happen */
    int many_corrections; /* a reading with at least this many corrected bits ... (0..33;
                             default ACTAG_FIT_MANY_CORRECTIONS, 3; 33 turns the rule off) */
    float many_corrections_margin; /* ... needs decision_margin >= min_margin + this
                             (0..1e6; default ACTAG_FIT_MANY_CORRECTIONS_MARGIN, 1.5).
                             Lower it (0 turns the rule off) for recall of far or
                             grazing tags where a wrong ID does little harm; raise it on
                             murky sonars (more blur or speckle than the pool recording) */
} actag_fit_params;

/* Fills *fp with the defaults above (no-op for NULL). */
void actag_fit_params_default(actag_fit_params *fp);

/* The least bit_margin a fit-decoder reading of `hamming` corrected bits out
 * of `nbits` counted bits needs (actag_decode_quad_fit, step 4): the larger
 * of min_bit_margin and the least b with
 *     min_bit_odds * hamming^b <= (nbits - hamming)^b
 * (none for hamming 0 or min_bit_odds 1; ACTAG_FIT_MIN_BIT_ODDS says why),
 * compared exactly in integers. Returns 33 (no reading leads by that much)
 * when no b up to 32 does (always when 2 hamming >= nbits), and for
 * arguments outside nbits 1..32, hamming 0..nbits, min_bit_margin 0..32,
 * min_bit_odds 1..1000000. No error codes.
 * Examples (min_bit_margin 2, min_bit_odds 100): 20 bits read (24-bit
 * families): hamming 0 or 1 -> 2, 2 or 3 -> 3, 4 -> 4; 24 bits (28-bit
 * families): 1 or 2 -> 2, 3 -> 3. */
int actag_fit_bit_lead(int hamming, int nbits, int min_bit_margin, int min_bit_odds);

/* Checks *fp: level in [0, 1], min_contrast 0..255, sample_offset in
 * [0, 0.5], min_margin in [-1e6, 1e6], min_bit_margin 0..32, min_bit_odds
 * 1..1000000,
 * many_corrections 0..33, many_corrections_margin in [0, 1e6], not both
 * ACTAG_FIT_ONLY_UNMIRRORED and ACTAG_FIT_ONLY_MIRRORED (other unknown flag
 * bits are ignored). Returns ACTAG_OK, ACTAG_ERR_NULL or ACTAG_ERR_PARAM;
 * fills *detail (common.h; field names as "level") when not NULL.
 * actag_decode_quad_fit() applies the same rules. */
int actag_fit_params_validate(const actag_fit_params *fp, actag_error_detail *detail);

/*
 * actag_decode_quad_fit(grey, rows, cols, stride, quad, family, max_corrections, fp, &res)
 *   The sonar decoder (ACTAG_DECODE_FIT in actag.h). Reads a GREY image (the
 *   median-filtered frame), not the binary one, and treats the quad only as
 *   a first guess of the tag's cell grid:
 *   1. Grid: the least-squares affine map of the quad (as actag_tag_affine),
 *      written as centre + a (u - g) + b (v - g). With ACTAG_FIT_WIDE, first
 *      the best of 5 starting grids (as given, rotated +-30 degrees, sheared
 *      b += +-a lb/la) on a half-cell lattice of shifts within +-1 cell, then
 *      its quarter-cell neighbours (the given grid's 25 half-cell shifts are
 *      read from one shared half-cell lattice of cell means, equal to
 *      grid-by-grid reading up to the rounding of the sample points). A
 *      start no ascent is likely to make readable (structure misses plus
 *      the likeliest code's corrected bits, 5 samples a cell, reach 12;
 *      readable fitted grids measured at most 10) skips the ascent and the
 *      fitted grid: the quad's own grid is read as the second grid (below).
 *      Then (unless ACTAG_FIT_NO_SEARCH) an
 *      ascent over the 6 affine numbers (steps 0.15 cell in position, 5 % of
 *      a side vector, halved twice), kept within half a cell of the start
 *      and 65-134 % of its side lengths. The objective is code-agnostic:
 *      (white - black) * (k-1)^2 plus, for every data cell,
 *      min(|cell - mid|, half the contrast), where black / white are the
 *      mean black-ring / white-interior cell levels and mid = (black+white)/2.
 *      Sonar blooms (bright areas spread, most along the beams), so the
 *      white square of a quad is larger than printed; the fit pulls the
 *      grid back onto the ring and the data cells.
 *   2. Cells: bilinear samples at the centre and +-sample_offset cell (3x3)
 *      averaged. Every cell centre must lie inside the image (the samples
 *      around the outermost ones may reach past its edge, whose pixels are
 *      then repeated), and white - black must reach min_contrast, else
 *      ACTAG_ERR_NO_MATCH.
 *   3. Bits: confidence c_i = (cell_i - t_i) / (white - black) with
 *      t_i = black + level * contrast, or with ACTAG_FIT_LOCAL the mean of
 *      the black-ring cell next to bit i and the interior cell next to that
 *      (data bits at the tag's edges return less than its interior).
 *      ACTAG_FIT_SPLIT: instead of a single threshold 0, every split of the
 *      sorted c_i between ACTAG_FIT_SPLIT_LO - level and ACTAG_FIT_SPLIT_HI -
 *      level is read and matched; the word closest to a code wins. If splits
 *      read as different tags or poses the closest must win by at least one
 *      bit, and a tie between the two handednesses is no reading; else
 *      ACTAG_ERR_NO_MATCH (the threshold would decide the ID).
 *      ACTAG_FIT_ERASE_CORNERS: the 4 corner cells of the data ring are not
 *      counted (on the pool frames they held 39 of the 100 bit errors of
 *      39 correct readings, 2.3 times their share); the distance then runs
 *      over 4k-4 bits and a family's guaranteed distance drops by up to 4.
 *   4. Matching by likelihood (actag_family_match_soft, family.h; not by
 *      the nearest hard word): every code in
 *      each of its 8 physical views (rotations, and reflections P of the
 *      reading) gets a soft distance, the sum of |c_i| (clamped at 1) over
 *      the bits where it disagrees with the sign of c_i; the smallest wins
 *      (under independent Gaussian cell noise this is maximum likelihood).
 *      Its hard distance `hamming` (over the counted bits) must be within
 *      max_corrections, and lead every other reading by min_bit_margin
 *      bits (bit_margin) and, with h > 0 corrected bits of the n counted,
 *      by enough bits b that min_bit_odds h^b <= (n - h)^b
 *      (ACTAG_FIT_MIN_BIT_ODDS; a reading refused by that counts as too
 *      close to call, as a rival template's refusal in step 5 does); a tie
 *      between the two handednesses is no reading.
 *      Second grid: when the fitted grid gives no reading (grid outside
 *      the image, too little contrast, no split within max_corrections, an
 *      ambiguous split or handedness, the template check or the margins of
 *      step 5 refuse it) and ACTAG_FIT_NO_SEARCH is not set, steps 2-5 are
 *      repeated once on the quad's own grid, which then stands for the
 *      fitted one, and N in the allowance of step 5 is doubled (two grids
 *      read). The code-agnostic fit can settle on a lattice with 4-6 bit
 *      errors, or one where the tag reads with little evidence, where the
 *      quad's grid reads it well. On simulated pool views (seeds 1, 3)
 *      this read 868 -> 926 and 871 -> 938 of 1,000, at the paper's
 *      settings (seed 2) 381 -> 497, with no wrong ID, handedness or
 *      corner order, and no tag in 2,000 tag-free frames for any family.
 *      actag_detect() reads the second grid of its blind boxes (the
 *      structure search's positions and the merged blobs' boxes, actag.h:
 *      axis-aligned boxes of the white square's size, never fitted to an
 *      outline) with at most the corrected bits at which a chance word
 *      would match one of the family's codes with probability 1 % (any
 *      handedness, corners erased: AcTag24h10 1, AcTag24m10 2, AcTag24h4
 *      not read; with a handedness prior AcTag24h10 2): over a tag turned in the
 *      image such a box is a lattice across the tag's cells, not its grid
 *      (docs/decoder.md, "Blind boxes").
 *   5. Template check (ACTAG_FIT_VERIFY, default): the likeliest readings
 *      on the fitted grid and those on the quad's own grid (up to
 *      ACTAG_SOFT_TOP = 6 of each, the soft matcher's list, family.h; the
 *      code-agnostic fit can settle where the right reading is not among
 *      its likeliest) each become a full template of the (k+1)^2
 *      cells (their data ring, black ring, white interior); each template
 *      refits the grid it came from to itself (a quarter cell and +-15 %;
 *      the full range after ACTAG_FIT_WIDE, whose search may settle a cell
 *      off) and is scored by the residual of a two-level
 *      least-squares fit of the cell means. If another template explains
 *      the cells better than the chosen reading's, there is no reading
 *      (the code-agnostic grid favoured it). Otherwise
 *        decision_margin = (rss_next - rss_best) / (2 s^2) - ln N,
 *      the log-likelihood ratio of the best template against the next
 *      (s^2 = rss_best / (cells - 2), floored at (0.1 contrast)^2) less a
 *      look-elsewhere allowance for the N = 8 ncodes hypotheses (times 165
 *      grids after ACTAG_FIT_WIDE, times 2 after the second grid): pure
 *      noise reaches about 0. When s exceeds a fifth of the contrast
 *      (the two levels explain the cells poorly), ACTAG_FIT_LEVEL_NOISE
 *      (default) also scores each template with the black and the white
 *      cells about their own means at the reading's own black and white
 *      variances vb, vw (unbiased, floored as s^2):
 *        lead = (ssb / vb + ssw / vw + nb ln vb + nw ln vw)_next / 2
 *               - the same for the best,
 *      and ACTAG_FIT_SEPARATE_NOISE (off) with each template's own
 *      maximum-likelihood variances: lead = (nb ln vb + nw ln vw)_next / 2
 *      - the same for the best. decision_margin is the smallest lead less
 *      ln N: a blurred or grazing tag, whose white cells spread far more
 *      than its ring, then needs a lead under each noise model. A reading
 *      needs decision_margin >= min_margin (default ACTAG_FIT_MIN_MARGIN, 2),
 *      and one with at least fp->many_corrections corrected bits (3)
 *      decision_margin >= min_margin + fp->many_corrections_margin (1.5).
 *      Re-checks at the full range (without ACTAG_FIT_WIDE), refusing a
 *      reading that a rival then explains better: every candidate of a
 *      second-grid reading after a rival came within the margin on the
 *      first grid; the candidates of other IDs when decision_margin is
 *      below min_margin + 2; and, for a quad whose corners miss every
 *      affine grid by over a quarter cell, the 6 templates that best fit
 *      the reading's cells and the best one on each of the 4
 *      parallelograms through three of the quad's corners (these must
 *      also trail by the least margin). And for every quad reading (without
 *      ACTAG_FIT_WIDE) about to be accepted, the stretched-grid check: the
 *      grid stretched by 1.25 and 1.5 along each of its axes and along the
 *      frame's rows (range), about its centre and either end (18 grids); a
 *      rival template that explains such a grid's cells better than the
 *      reading's own, within twice the reading's residual, is polished over
 *      the full range there, as is the reading's template, and must not
 *      explain the cells better than the reading (a white square eroded in
 *      range makes a short quad whose right grid lies beyond the polishes).
 *      And for every reading with ACTAG_FIT_WIDE, and every other whose
 *      decision_margin is below min_margin + 2: the reading's own code in
 *      each allowed view of the
 *      other handedness (the same corners labelled in reflected orders;
 *      AcTag24h10's codes lie 4 read bits from their own mirror images) is
 *      polished over the full range from the reading's grid, as is the
 *      reading's template, and must not explain the cells better.
 *      docs/decoder.md has the cases.
 *      Without ACTAG_FIT_VERIFY the margin is the soft-distance lead over
 *      the runner-up divided by the cell noise (from the ring and interior
 *      cells), less the same allowance.
 *      Why: on 1,000 simulated pool views the nearest-word decoder read 9
 *      wrong IDs and 3 wrong handednesses; the template check removed 7 and
 *      3 of them, the margin the rest. With the defaults: 0 wrong IDs, 0
 *      wrong handednesses, 0 corner-order errors in 6,000 simulated views
 *      (pool settings seeds 1 and 3, the paper's seeds 1, 2, 4, 5); 34 of
 *      the 39 pool-frame readings kept (the others: hamming 3 or little
 *      evidence).
 *   Results as for actag_decode_quad (corners[] are the given quad's points
 *   in tag order), except mirror_margin: the other handedness' best hard
 *   distance over the read bits minus hamming, not capped at m + 1, and
 *   negative when the likelihood prefers the reading with more flipped
 *   bits; 33 - hamming when ACTAG_FIT_ONLY_UNMIRRORED / _MIRRORED leaves
 *   the other handedness no hypothesis. Plus: ring_black / interior_white =
 *   fractions of the ring / interior CELLS on the right side of mid
 *   (actag_detect does not require 1.0: with the default
 *   tuning.min_structure 0 a reading is kept while its ring misses,
 *   interior misses and corrected bits together stay within the
 *   corrections, actag.h), contrast, flip_weight = sum of |c_i| of the
 *   corrected bits, min_confidence = min |c_i|, fit_corners = the fitted grid's white-square
 *   corners in tag order.
 *   Deterministic: + - * / and sqrtf only. No memory beyond the stack: about 4.4 KB
 *   (x86-64 -O2, -fstack-usage over the call chain; the lattice alone is
 *   (k+3)^2 + 25 floats, 584 bytes for k = 8).
 *   Cost: one fit is ~100-200 evaluations of 49 cells x 9 (5 during the
 *   ACTAG_FIT_WIDE search) bilinear samples, 0.1-0.4 ms on a desktop core.
 *   Errors: ACTAG_ERR_NULL (any pointer NULL), ACTAG_ERR_SIZE, ACTAG_ERR_FAMILY,
 *   ACTAG_ERR_CORRECTIONS, ACTAG_ERR_PARAM (degenerate quad, or *fp fails
 *   actag_fit_params_validate), ACTAG_ERR_NO_MATCH.
 */
int actag_decode_quad_fit(const uint8_t *grey, int rows, int cols, int stride,
                          const actag_point quad[4], const actag_family *family,
                          int max_corrections, const actag_fit_params *fp,
                          actag_decode_result *out);

#ifdef __cplusplus
}
#endif
#endif /* ACTAG_DECODE_H */
