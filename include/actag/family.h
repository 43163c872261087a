/*
 * actag/family.h -- AcTag families: compiled-in code tables and the matcher.
 *
 * MANUAL
 *   A family of 4k data bits (16 <= 4k <= 32) is a list of codes in ID order.
 *   Bit 0 of a tag's bit sequence is the code's most significant bit (bit
 *   4k-1); it sits in the top-left cell as printed and the sequence walks the
 *   outer ring clockwise (see SPEC section 2).
 *
 *   The built-in families are generated at build time by actag-familygen and
 *   linked as const tables (flash, not RAM). Which ones are built is chosen by
 *   the CMake cache variable ACTAG_FAMILIES.
 *
 *     actag_family f;
 *     actag_match m;
 *     if (actag_family_get("AcTag24h10", &f) != ACTAG_OK) ...unknown name...
 *     if (actag_family_match(&f, observed_word, 2, &m) == ACTAG_OK)
 *         printf("id %d rot %d mirrored %d hamming %d\n",
 *                m.id, m.rotation, m.mirrored, m.hamming);
 *
 *   Firmware can skip the name look-up (and its strcmp, and the tables it
 *   does not use): the generated header actag/families.h declares one
 *   accessor per built-in family, e.g. actag_family_AcTag24h10(&f), and
 *   defines ACTAG_HAVE_AcTag24h10.
 *
 *   Two kinds of family (docs/families.md):
 *     AcTag<bits>h<h>  the published families (AcTag24h4 .. AcTag24h10) and
 *                      others made by the same rule: distance >= h between
 *                      the 8 orientations rot90^j(c) and reverse(rot90^j(c))
 *                      of all codes, over all bits. mirror = ACTAG_MIRROR_REVERSE,
 *                      excluded = 0.
 *     AcTag<bits>m<h>  mirror-safe families (AcTag24m4 .. AcTag28m10): the
 *                      distance >= h holds between the 8 views a sonar can
 *                      show, rot90^j(c) and P(rot90^j(c)) (P = the physical
 *                      reflection, actag_code_mirror), counted over the bits
 *                      the default sonar decoder reads (all but the 4 corner
 *                      cells), hence also over all bits and between plain
 *                      rotations. mirror = ACTAG_MIRROR_PHYSICAL, excluded =
 *                      the 4 corner bits.
 *     AcTag<bits>p<h>  (not built by default) physical mirror, all bits.
 *   The fields mirror and excluded say which rule the family's hamming holds
 *   for; both are 0 for the published rule. actag_family_get() and
 *   actag_family_get_at() always set them; they are descriptive only:
 *   actag_family_validate() and the matchers do not read them (a family
 *   struct filled field by field, as before they existed, works as before).
 *
 *   Orientation model of actag_family_match(): the 8 orientations the
 *   published families' generator guarantees distances for (SPEC sections 2-3):
 *       w == rot90^rotation(c)                 (mirrored == 0), or
 *       w == reverse(rot90^rotation(c))        (mirrored == 1),
 *   up to m.hamming flipped bits. rot90 is the printed tag turned 90 degrees
 *   counter-clockwise (cell (x,y) moves to (y, k-x)). For a mirror-safe
 *   family the guaranteed views are w and actag_code_mirror(w) matched with
 *   actag_family_match_rotations() (or actag_family_match_soft()), as the
 *   decoders do; its
 *   reverse() matches carry no guarantee.
 *   Note: a physically mirrored tag read clockwise from a corner is NOT
 *   reverse(...) of a rotation (a reflection keeps a corner cell fixed; the
 *   full-word reversal does not); it is P(w) with sequence position s taking
 *   position -s mod 4k. The binary decoder (decode.h) therefore matches w
 *   and P(w) with actag_family_match_rotations(), and the default fit
 *   decoder the same 8 views with actag_family_match_soft(); see decode.h
 *   for what this means for the guaranteed distances of the published
 *   families (none of it applies to the AcTag<bits>m<h> families, made for
 *   exactly that).
 *
 *   Soft matching, actag_family_match_soft() (the sonar fit decoder's
 *   matcher): the reading is given as one confidence c_i per bit (bit i of
 *   the sequence, i = 0 the MSB; > 0 reads white = 1, the size is how sure;
 *   |c_i| is clamped at 1 and quantised to 1/ACTAG_SOFT_SCALE). Every code
 *   in each of the 8 physical views, rot90^r(c) and P(rot90^r(c)) (P =
 *   actag_code_mirror, mirrored = 1), gets a soft distance d: the sum of
 *   |c_i| over the counted bits (the reading's bits set in keep, whatever
 *   the view; any mask) where the code disagrees
 *   with the sign of c_i; under independent Gaussian cell noise the least d
 *   is the likeliest code, and with c_i = (cell - mid) / contrast (a clean
 *   cell reads +-0.5, as the fit decoder's are) the runner-up's d minus the
 *   best's is the log-likelihood ratio between them times sigma^2 /
 *   contrast^2 (sigma the cell noise; the fit decoder's margin without the
 *   template check is that ratio).
 *   With all |c_i| equal the ranking is the hard (Hamming) one; the hard
 *   matchers above are the same scan with every bit weighing 1.
 *   Result (actag_soft_match): best (hamming = its hard distance over the
 *   kept bits), d1 and d2 (soft distances of the best and the runner-up,
 *   1 << 28 when there is none), other (the best hard distance of the other
 *   handedness), h2 (the best hard distance of any reading but best), and
 *   top[0 .. ntop-1], the likeliest readings, best first (ties: fewer
 *   disagreeing bits, then lower ID, then lower view = rotation + 4 *
 *   mirrored). Readings whose hard distance alone bounds their d at or above
 *   the runner-up's are skipped unscored, so best, d1 and d2 are exact and
 *   top[2 ..] may miss readings, whether the list is full or not (a list of
 *   fewer than ACTAG_SOFT_TOP entries is not every reading, and a skipped
 *   reading can rank above one listed after top[1]). Cost: 8 ncodes views, five
 *   popcounts each unless skipped, then one more popcount pass (on x86-64
 *   the 8 views of a code at once, SSE2, the same result).
 *   actag_family_match_soft_views() is the same over a subset of the 8
 *   views (ACTAG_VIEWS_UNMIRRORED, ACTAG_VIEWS_MIRRORED or any bit mask):
 *   the views left out are not hypotheses at all, so they are neither the
 *   best nor the runner-up (actag_params.handedness uses it).
 *
 *   actag_family is a small value the caller owns; it points into the const
 *   code tables. (The tables are reached through functions rather than const
 *   structs holding pointers, so that position-independent builds keep every
 *   byte of the library read-only: no .data, no .data.rel.ro.)
 *
 * ERRORS
 *   ACTAG_ERR_FAMILY       unknown family name or index; the matchers: a family that
 *                          fails actag_family_validate()
 *   ACTAG_ERR_NULL         a pointer argument is NULL
 *   ACTAG_ERR_CORRECTIONS  max_corrections < 0 or above actag_family_max_corrections()
 *   ACTAG_ERR_NO_MATCH     no code within max_corrections in any orientation
 *   ACTAG_ERR_PARAM        actag_family_match_soft_views(): no view in the mask
 *   (actag_family_match_soft: only ACTAG_ERR_NULL and ACTAG_ERR_FAMILY; it
 *   always reports the likeliest reading.)
 */
#ifndef ACTAG_FAMILY_H
#define ACTAG_FAMILY_H

#include "actag/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Mirror rule of a family (actag_family.mirror). */
#define ACTAG_MIRROR_REVERSE 0  /* full bit reversal: the published families */
#define ACTAG_MIRROR_PHYSICAL 1 /* the reflection P a sonar shows (actag_code_mirror) */

/* A tag family: a view of a const code table. The last two fields were
 * added after the first five; zero (the published rule) is their default. */
typedef struct actag_family {
    const char *name;      /* e.g. "AcTag24h10" */
    int bits;              /* number of data bits, 4k */
    int hamming;           /* minimum Hamming distance between orientations */
    int ncodes;            /* number of codes (IDs 0 .. ncodes-1) */
    const uint32_t *codes; /* codes in ID order */
    int mirror;            /* ACTAG_MIRROR_*: which mirror image hamming holds for */
    uint32_t excluded;     /* code bits hamming does not count (0: none) */
} actag_family;

/* Result of actag_family_match(). */
typedef struct actag_match {
    int id;       /* tag ID (index into codes) */
    int rotation; /* 0..3: observed = rot90^rotation(code) (before any reversal) */
    int mirrored; /* 1 when the observation is the reversed sequence */
    int hamming;  /* number of corrected bits */
} actag_match;

/* Fill *out with the built-in family of that exact name ("AcTag24h10").
 * Returns ACTAG_OK, ACTAG_ERR_FAMILY if it is not built in, or ACTAG_ERR_NULL
 * (*out untouched on an error). */
int actag_family_get(const char *name, actag_family *out);

/* Number of built-in families (ACTAG_FAMILIES at build time); no error codes. */
int actag_family_count(void);

/* Fill *out with the i-th built-in family, 0 <= i < actag_family_count().
 * Returns ACTAG_OK, ACTAG_ERR_FAMILY when i is out of range, or ACTAG_ERR_NULL. */
int actag_family_get_at(int i, actag_family *out);

/* Checks a family's fields (bits a multiple of 4 in 16..32, hamming >= 1,
 * ncodes >= 1, codes non-NULL, no code with a bit set at or above `bits`).
 * Returns ACTAG_OK or ACTAG_ERR_FAMILY / ACTAG_ERR_NULL. */
int actag_family_validate(const actag_family *family);

/* Largest number of bit corrections the family supports:
 * h/2 - 1 for even h, floor(h/2) for odd h. -1 (ACTAG_ERR_NULL) for NULL. The
 * family is not validated (hamming 0 also gives -1). */
int actag_family_max_corrections(const actag_family *family);

/* The code helpers below (actag_code_* and actag_popcount32) have no error
 * codes and check nothing; bits is a family's, a multiple of 4 in 16..32. */

/* Mask of the low `bits` bits (bits in 1..32). */
uint32_t actag_code_mask(int bits);

/* Rotate a code by 90 degrees: cyclic shift by bits/4 towards the MSB. */
uint32_t actag_code_rot90(uint32_t code, int bits);

/* Reverse the order of the low `bits` bits (bit i <-> bit bits-1-i). */
uint32_t actag_code_reverse(uint32_t code, int bits);

/* The reflection P (sequence position s -> -s mod bits): keeps the MSB
 * (position 0) and reverses the other bits; its own inverse. The same map
 * as actag_decode_mirror(). */
uint32_t actag_code_mirror(uint32_t code, int bits);

/* Mask of the 4 corner cells of the data ring (sequence positions 0, k, 2k,
 * 3k) as code bits: the cells the default sonar decoder ignores and the
 * AcTag<bits>m<h> families exclude. */
uint32_t actag_code_corners(int bits);

/* Number of set bits of v. */
int actag_popcount32(uint32_t v);

/* Match an observed bit word against every code of the family in all 8
 * orientations (rotations and reversals, see above). Returns ACTAG_OK and fills *out with the closest match
 * (smallest Hamming distance; ties go to the lowest ID, then the lowest
 * orientation, unmirrored first), ACTAG_ERR_NO_MATCH if nothing is within
 * max_corrections, ACTAG_ERR_NULL (family or out NULL), ACTAG_ERR_FAMILY (the
 * family fails actag_family_validate) or ACTAG_ERR_CORRECTIONS (max_corrections
 * < 0 or above actag_family_max_corrections); *out is written only with
 * ACTAG_OK. */
int actag_family_match(const actag_family *family, uint32_t observed,
                       int max_corrections, actag_match *out);

/* Like actag_family_match() but only over the 4 rotations (out->mirrored is
 * always 0), with the same error codes. Decoders that undo a physical mirror
 * themselves use this. */
int actag_family_match_rotations(const actag_family *family, uint32_t observed,
                                 int max_corrections, actag_match *out);

/* Soft distances count 1/ACTAG_SOFT_SCALE of a confidence. */
#define ACTAG_SOFT_SCALE 16
/* Readings actag_family_match_soft() keeps (the fit decoder's template check
 * verifies them; 4 let a wrong handedness through on a simulated view read
 * from a contour guess). */
#define ACTAG_SOFT_TOP 6

/* One reading of actag_family_match_soft(). */
typedef struct actag_soft_reading {
    int d;    /* soft distance, 1/ACTAG_SOFT_SCALE units */
    int h;    /* hard distance: disagreeing bits among the kept ones */
    int id;   /* code */
    int view; /* rotation + 4 * mirrored (mirrored: the reflection P) */
} actag_soft_reading;

/* Result of actag_family_match_soft() (see the manual). */
typedef struct actag_soft_match {
    actag_match best; /* the likeliest reading; mirrored: P(observed) == rot90^rotation(code) */
    int d1, d2;       /* soft distances of the best and the runner-up */
    int other;        /* best hard distance of the other handedness */
    int h2;           /* best hard distance of any reading but best */
    actag_soft_reading top[ACTAG_SOFT_TOP]; /* the likeliest readings, best first */
    int ntop;         /* entries of top (1 .. ACTAG_SOFT_TOP) */
} actag_soft_match;

/* Matches a reading given as per-bit confidences (conf[0 .. bits-1], bit 0
 * the MSB) over the bits set in keep, in the 8 physical views, by soft
 * distance. A confidence's weight is min(|c_i|, 1); a NaN confidence weighs
 * 0 and reads as bit 0. Returns ACTAG_OK (*out filled), ACTAG_ERR_NULL or
 * ACTAG_ERR_FAMILY. */
int actag_family_match_soft(const actag_family *family, const float *conf, uint32_t keep,
                            actag_soft_match *out);

/* View masks of actag_family_match_soft_views(): bit v stands for view v
 * (rotation v & 3, mirrored v >> 2, as actag_soft_reading.view). */
#define ACTAG_VIEWS_ALL 0xffu
#define ACTAG_VIEWS_UNMIRRORED 0x0fu /* views 0..3: the reading as printed, turned */
#define ACTAG_VIEWS_MIRRORED 0xf0u   /* views 4..7: the reflection P, turned */

/* actag_family_match_soft() over the views in `views` only (a prior: e.g. a
 * sonar mounting that shows every tag with one handedness); the runner-up,
 * `other` and h2 are taken over those views too (`other` is 33 when they
 * hold one handedness). views is masked to 8 bits. Returns ACTAG_OK,
 * ACTAG_ERR_NULL, ACTAG_ERR_FAMILY, or ACTAG_ERR_PARAM when no view is left. */
int actag_family_match_soft_views(const actag_family *family, const float *conf, uint32_t keep,
                                  unsigned views, actag_soft_match *out);

#ifdef __cplusplus
}
#endif
#endif /* ACTAG_FAMILY_H */
