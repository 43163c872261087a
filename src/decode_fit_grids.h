/*
 * decode_fit_grids.h -- internal: a wide reading's grids, kept for a second
 * reading of the same candidate (not part of the API).
 *
 * The wide search of actag_decode_quad_fit (the lattice of shifted starting
 * grids, the hopeless test and the code-agnostic ascent) does not depend on
 * ACTAG_FIT_VERIFY or on the corrections limit. detect.c reads a search
 * candidate first without the template check (a tentative reading, which
 * steers RANSAC's effort) and, only when the reading is reported, again
 * with it: the second reading starts from the grids the first one found, bit
 * for bit the grids it would find again.
 */
#ifndef ACTAG_SRC_DECODE_FIT_GRIDS_H
#define ACTAG_SRC_DECODE_FIT_GRIDS_H

#include "actag/decode.h"

typedef struct actag__fit_grids {
    float g[6];    /* the ascent's grid: mx, my, ax, ay, bx, by */
    int state;     /* 0: not searched yet; 1: g holds the ascent's grid;
                      2: the start was hopeless (the quad's own grid is read) */
    int read_before; /* in, any reading: 1 when the candidate was read before
                        by other means (the quads of the contour whose extreme
                        points are the quad): the look-elsewhere allowance
                        then counts twice the hypotheses, as for the second
                        grid; 0 otherwise */
    int blind;     /* in: 1 when the quad is a blind box (a structure-search
                      position or a merged blob's box: the white square's size,
                      axis-aligned, not fitted to any outline), whose own grid
                      is weak evidence of the tag's: it is read (after a
                      hopeless start, or as the second grid) with at most the
                      corrected bits at which a chance word matches a code
                      with probability 1 % (decode_fit.c, fblind_corrections;
                      any handedness, corners erased: AcTag24h10 1, AcTag24m10
                      2, AcTag24h4 not read; 4 views: AcTag24h10 2), and
                      never more than max_corrections; 0: a fitted quad or a
                      contour's extreme points (max_corrections) */
} actag__fit_grids;

/* A hypothesis of a refused reading: its code (id), its view (rotation,
 * mirrored) and its white-square corners in tag order on the grid its
 * polish started from. */
typedef struct actag__fit_rival {
    int id, rotation, mirrored;
    actag_point fit_corners[4];
} actag__fit_rival;

/* Out: when the template check refused a reading because a rival template
 * came within the margin (too close to call), amb = 1, r[0] the reading's
 * hypothesis and r[1] the rival that refused it; else amb = 0. When the
 * quad's own grid (the second grid) was read after such a refusal and its
 * reading was refused so too, amb2 = 1 and r2 holds that pair (the two
 * grids can read different tags: simulated frame 149 of actag-eval --seed
 * 9213 on the 530 x 512 sonar, both orientation flags, where the fitted
 * grid read tag 5 and the quad's grid the true tag 1); else amb2 = 0. */
typedef struct actag__fit_amb {
    int amb;
    actag__fit_rival r[2];
    int amb2;
    actag__fit_rival r2[2];
} actag__fit_amb;

/* actag_decode_quad_fit() (same arguments, result and errors) that, with
 * ACTAG_FIT_WIDE and grids not NULL, stores the wide search's outcome in
 * *grids when grids->state is 0 and starts from it otherwise. grids->state
 * must be 0 before the first reading of a candidate; the second reading
 * must pass the same frame, quad, family and fit flags other than
 * ACTAG_FIT_VERIFY (and the same read_before). grids NULL:
 * actag_decode_quad_fit(). amb (may be NULL): see actag__fit_amb. */
int actag__decode_quad_fit_grids(const uint8_t *grey, int rows, int cols, int stride,
                                 const actag_point quad[4], const actag_family *family,
                                 int max_corrections, const actag_fit_params *fp,
                                 actag_decode_result *out, actag__fit_grids *grids,
                                 actag__fit_amb *amb);

/* Two readings of one place that disagree (another ID, handedness or
 * rotation; detect.c: a quad's or a contour guess's reading and the
 * structure search's tentative one). Each reading is a whole template: its
 * code (id, as printed) on the grid through its white square's corners in
 * tag order (fit_corners: TL TR BR BL as printed, so the grid's handedness
 * is the reading's), polished over the code-agnostic ascent's full range
 * from both readings' places (the better of the two starts; at the other
 * reading's place its corners are taken in the order nearest this
 * reading's, so the start keeps this reading's rotation and handedness and
 * the two templates are each judged at both places). *rss, *rss2:
 * the residual of reading 1 and of reading 2 (grey levels^2, two levels
 * fitted). Returns 1 when reading 2 explains the cells at least as well as
 * reading 1 (rss2 <= rss), 0 when not, or ACTAG_ERR_NULL / ACTAG_ERR_PARAM
 * (bad frame, family, ID, corners or fit parameters). */
int actag__fit_rival_explains(const uint8_t *grey, int rows, int cols, int stride,
                              const actag_family *family, const actag_fit_params *fp, int id,
                              const actag_point corners[4], int id2,
                              const actag_point corners2[4], float *rss, float *rss2);

/* actag__fit_rival_explains with reading 1's polish at its own place kept
 * in *own between calls that judge one reading against several others
 * (bit for bit what it would polish again): *own < 0 on the first call.
 * own NULL: actag__fit_rival_explains. */
int actag__fit_rival_explains_own(const uint8_t *grey, int rows, int cols, int stride,
                                  const actag_family *family, const actag_fit_params *fp, int id,
                                  const actag_point corners[4], int id2,
                                  const actag_point corners2[4], float *rss, float *rss2,
                                  float *own);

/* The log-likelihood ratio (nats) of reading 1 over reading 2 from their
 * rss (actag__fit_rival_explains), under Gaussian cell noise of the
 * variance reading 1 leaves (the template check's noise model: its rss
 * over the cells less the two fitted levels, at least (0.1 contrast)^2,
 * contrast being reading 1's actag_decode_result.contrast). family and fp
 * as given to actag__fit_rival_explains (valid: not checked). */
float actag__fit_rss_llr(const actag_family *family, const actag_fit_params *fp, float rss,
                         float rss2, float contrast);

#endif
