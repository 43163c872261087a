/* Reading a candidate and judging the reading (internal; detect.c): the
 * decoders with the pipeline's options, a contour's grid guesses, and the
 * checks of a reading against its rivals at the same place. What each
 * rule is for, and the frames it was made on: the comments in readings.c
 * and docs/decoder.md. Verdicts are trace.h's ACTAG_TRACE_* outcomes. */
#ifndef ACTAG_READINGS_H
#define ACTAG_READINGS_H

#include "actag/actag.h"
#include "actag/trace.h"
#include "decode_fit_grids.h"

/* What every reading of one frame reads and how: the filtered frame (the
 * fit decoder's), the binary bitmap (the paper's decoder's), the geometry
 * and the resolved parameters (detect.c, resolve_params). */
typedef struct actag__reader {
    const uint8_t *grey;  /* B: rows x cols, stride cols */
    const uint32_t *bin;  /* A: the binary bitmap (common.h) */
    int rows, cols;
    const actag_sonar_geometry *geometry;
    const actag_params *params;
} actag__reader;

/* Contours per frame whose extreme points are tried as a grid guess when
 * RANSAC gives no reading (each a wide-search decode, ~0.1 ms). */
#define ACTAG_GUESS_MAX 16

#define ACTAG__GUESS_UNREAD (-1) /* no extreme points, or the decode budget is spent */
#define ACTAG__GUESS_BORDER (-2) /* a corner on the frame's border: not read */

/* Hypotheses of one contour's ambiguous quad readings kept for the rival
 * check (the reading and its rival, for each of the two grids of two
 * quads). */
#define ACTAG_AMB_MAX 8

/* Hypotheses of quad and contour-guess readings that the template check
 * refused as too close to call (the reading and the rival that refused
 * it), kept per frame so that a search reading of their place must explain
 * the cells better than each (rival_explains). */
#define ACTAG_HELD_MAX 8

/* A quad reading with this many corrected bits or more is checked against
 * its contour's grid guess (detect.c's read_quads, "cross-check"). */
#define ACTAG_CROSS_HAMMING 2

/* One more decoder call within limits.max_decodes? Counts the call, or
 * the refusal (stats.decode_cap). */
int actag__decode_budget(actag_stats *st, const actag_params *p);

/* The structure budget (readings.c). */
int actag__structure_ok(const actag_decode_result *dr, const actag_params *p, int limit);

/* The texture test of a fit-decoder reading (readings.c, texture.h): 0
 * when it is refused (ACTAG_TRACE_TEXTURE). */
int actag__texture_ok(const actag__reader *r, const actag_decode_result *dr);

/* The configured decoder (tuning.decode_mode) on one quad: ACTAG_OK with
 * *dr, or the decoder's error; amb (or NULL): the hypotheses the template
 * check refused as too close to call. */
int actag__decode_any(const actag__reader *r, const actag_point quad[4], actag__fit_amb *amb,
                      actag_decode_result *dr);

/* A blind start (a search box, a contour's extreme points) read with the
 * wide search and judged as such: ACTAG_TRACE_ACCEPTED or the refusal's
 * verdict; verify 0: without the template check (a tentative reading). */
int actag__read_wide(const actag__reader *r, const actag_point quad[4], int verify,
                     actag__fit_grids *grids, actag__fit_amb *amb, actag_decode_result *dr);

/* Keeps a refused pair (the reading, its rival) in held[] (ACTAG_HELD_MAX). */
void actag__hold_pair(actag__fit_rival *held, int *nheld, const actag__fit_rival pair[2]);

/* Guesses: gq read with the template check (refused pairs held); a
 * contour's guess from its extreme points (ACTAG__GUESS_UNREAD, ACTAG__GUESS_BORDER or
 * the verdict); a tentative guess read again with the check. */
int actag__read_guess(const actag__reader *r, actag__fit_grids *gg, actag__fit_rival *held,
                      int *nheld, const actag_point gq[4], actag_decode_result *dr);
int actag__contour_guess(const actag__reader *r, const actag_ipoint *pts, int npts,
                         actag_stats *st, int read_before, actag__fit_grids *gg, int *nguess,
                         actag__fit_rival *held, int *nheld, actag_point gq[4],
                         actag_decode_result *dr);
int actag__read_guess_again(const actag__reader *r, actag_stats *st, actag__fit_grids *gg,
                            actag__fit_rival *held, int *nheld, const actag_point gq[4],
                            actag_decode_result *dr);

/* Places: a quad's centre; two quads at one place (either centre inside
 * the other's circumcircle). actag__place keeps what the test needs of a
 * quad (its centre and the square of half its 0-2 diagonal), for a caller
 * that keeps places rather than corners. */
typedef struct {
    actag_point c;
    float r2;
} actag__place;
actag_point actag__centre(const actag_point c[4]);
actag__place actag__place_of(const actag_point q[4]);
int actag__places_meet(actag__place a, actag__place b);
int actag__same_place(const actag_point *d, const actag_point *c);

/* A reading as the rival checks see it. */
actag__fit_rival actag__rival_of(const actag_decode_result *r);

/* 1 to refuse reading *dr at corners: a search reading (sk, nsk; the
 * winner marked in contested) or a held hypothesis (amb, namb) at its
 * place disagrees and explains the cells at least as well. */
int actag__rival_explains(const actag__reader *r, const actag_decode_result *dr,
                          const actag_decode_result *sk, int nsk, const actag__fit_rival *amb,
                          int namb, const actag_point corners[4], int *contested);

/* q with corner j (0..3) moved to the parallelogram through the other
 * three (q[j-1] + q[j+1] - q[j+2], indices mod 4), into t (the other
 * corners copied); returns 1 when that moves it by at least a quarter of
 * q's mean side, else 0 (q nearly a parallelogram there, or a point): the
 * starts actag__turned_rival_refuses reads besides the turns. */
int actag__complete_corner(const actag_point q[4], int j, actag_point t[4]);

/* 1 to refuse blind reading *dr of box q: a reading of q with one corner
 * completed to the parallelogram through the other three, or of q turned
 * +30, -30 or +45 degrees, disagrees at its place and explains the cells
 * at least as well. */
int actag__turned_rival_refuses(const actag__reader *r, const actag_point q[4],
                                const actag_decode_result *dr);

/* 1 to refuse quad reading *qdr: its contour's guess (read tentatively
 * into gq, gg) disagrees and the quad's template does not lead by the
 * least margin. */
int actag__cross_check(const actag__reader *r, const actag_ipoint *pts, int npts, actag_stats *st,
                       int *nguess, const actag_decode_result *qdr, actag_point gq[4],
                       actag__fit_grids *gg);

#endif
