/* Reading a candidate and judging the reading (readings.h): the decoder
 * calls with the pipeline's options, a contour's grid guesses, and the
 * checks of a reading against rival readings of its place. */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "readings.h"

#include "size_filter.h"
#include "texture.h"

#include <string.h>

/* One more decoder call within limits.max_decodes? Counts the call, or
 * the refusal (stats.decode_cap). */
int actag__decode_budget(actag_stats *st, const actag_params *p)
{
    if (st->decodes >= p->tuning.limits.max_decodes) {
        st->decode_cap++;
        return 0;
    }
    st->decodes++;
    return 1;
}





/* The structure budget: black-ring cells read white, interior cells read
 * black and corrected bits together may not exceed the reading's
 * corrections limit, and each structure fraction must reach min_structure.
 * (One budget instead of an all-or-nothing gate: a speckled ring cell
 * costs what a corrected bit costs.) */
int actag__structure_ok(const actag_decode_result *dr, const actag_params *p, int limit)
{
    int k = p->family->bits / 4;
    float ring = (float)(4 * (k - 2)), in = (float)((k - 3) * (k - 3));
    int misses = (int)((1.0f - dr->ring_black) * ring + 0.5f) +
                 (int)((1.0f - dr->interior_white) * in + 0.5f);
    return dr->ring_black >= p->tuning.min_structure && dr->interior_white >= p->tuning.min_structure &&
           misses + dr->hamming <= limit;
}

/* The texture test (texture.h) of a fit-decoder reading: 1 when its
 * contrast reaches tuning.min_texture_contrast times the texture's
 * cell-to-cell variation around it, or cannot be judged, or the test is
 * off (0); the paper's binary decoder is not judged. Asked last, of a
 * reading about to be reported (detect.c: read_quads, judge_blind), never
 * of the readings that only contest others (turned and completed starts,
 * a quad's cross-check, tentative search readings): a rival keeps its
 * veto whatever its contrast, as before the test. */
int actag__texture_ok(const actag__reader *r, const actag_decode_result *dr)
{
    const actag_params *p = r->params;
    if (p->tuning.decode_mode != ACTAG_DECODE_FIT || !(p->tuning.min_texture_contrast > 0.0f))
        return 1;
    return actag__texture_contrast(r->grey, r->rows, r->cols, dr->fit_corners,
                                   p->family->bits) >= p->tuning.min_texture_contrast;
}

/* The grid-fitting decoder with the pipeline's options (flags added, and
 * ACTAG_FIT_VERIFY dropped when verify is 0); grids: a wide reading's
 * grids kept for a second reading (decode_fit_grids.h), or NULL. */
static int decode_fit(const uint8_t *grey, int rows, int cols, const actag_point quad[4],
                      const actag_params *p, int max_corrections, int extra_flags, int verify,
                      actag__fit_grids *grids, actag__fit_amb *amb, actag_decode_result *dr)
{
    actag_fit_params fp = p->tuning.fit;
    fp.flags |= extra_flags;
    if (!verify)
        fp.flags &= ~ACTAG_FIT_VERIFY;
    fp.min_margin = p->min_margin; /* the user's margin wins over the tuning's */
    return actag__decode_quad_fit_grids(grey, rows, cols, cols, quad, p->family, max_corrections,
                                        &fp, dr, grids, amb);
}

/* The configured decoder on one quad. */
int actag__decode_any(const actag__reader *r, const actag_point quad[4], actag__fit_amb *amb,
                     actag_decode_result *dr)
{
    const actag_params *params = r->params;
    if (amb)
        amb->amb = amb->amb2 = 0;
    switch (params->tuning.decode_mode) {
    case ACTAG_DECODE_FIT:
        return decode_fit(r->grey, r->rows, r->cols, quad, params, params->max_bit_corrections, 0,
                          1, NULL, amb, dr);
    default: {
        /* the paper's decoder has no hypothesis set to restrict: its
         * readings of the other handedness are dropped */
        int f = params->tuning.fit.flags, rc;
        rc = actag_decode_quad_bitmap(r->bin, r->rows, r->cols, quad, params->family,
                                      params->max_bit_corrections, dr);
        if (rc == ACTAG_OK && (((f & ACTAG_FIT_ONLY_UNMIRRORED) && dr->mirrored) ||
                               ((f & ACTAG_FIT_ONLY_MIRRORED) && !dr->mirrored)))
            rc = ACTAG_ERR_NO_MATCH;
        return rc;
    }
    }
}

/* A first guess of a tag's grid (a search box, a contour's extreme points)
 * read with the fit decoder's wide search and judged as such readings are:
 * the wide-search corrections, search_min_margin, the structure budget and
 * the fitted grid's sides. verify 0: without the template check (a
 * tentative reading, see detect.c's search_stage), 1: with it as configured. grids:
 * as for decode_fit. amb (or NULL): the template check's hypotheses when
 * it refused the reading as too close to call (amb->amb 1). Returns
 * ACTAG_TRACE_ACCEPTED or the reason for refusing it; *dr is filled unless
 * ACTAG_TRACE_NO_MATCH. */
int actag__read_wide(const actag__reader *r, const actag_point quad[4], int verify,
                     actag__fit_grids *grids, actag__fit_amb *amb, actag_decode_result *dr)
{
    const actag_params *params = r->params;
    /* search_max_corrections, capped by max_bit_corrections */
    int lim = params->tuning.search_max_corrections < params->max_bit_corrections
                  ? params->tuning.search_max_corrections
                  : params->max_bit_corrections;
    if (amb)
        amb->amb = amb->amb2 = 0;
    if (decode_fit(r->grey, r->rows, r->cols, quad, params, lim, ACTAG_FIT_WIDE, verify, grids, amb,
                   dr) != ACTAG_OK)
        return ACTAG_TRACE_NO_MATCH;
    if (!(dr->decision_margin >= params->tuning.search_min_margin))
        return ACTAG_TRACE_MARGIN;
    if (!actag__structure_ok(dr, params, lim))
        return ACTAG_TRACE_STRUCTURE;
    if (!actag__sides_plausible(dr->fit_corners, r->geometry, params, r->rows, r->cols))
        return ACTAG_TRACE_SIDES;
    return ACTAG_TRACE_ACCEPTED;
}

/* Keeps hypothesis h in held[] (ACTAG_HELD_MAX) unless one of the same
 * tag, handedness and rotation at the same place is kept already. */
static void hold(actag__fit_rival *held, int *nheld, const actag__fit_rival *h)
{
    int i;
    for (i = 0; i < *nheld; i++)
        if (held[i].id == h->id && held[i].mirrored == h->mirrored &&
            held[i].rotation == h->rotation &&
            actag__same_place(held[i].fit_corners, h->fit_corners))
            return;
    if (*nheld < ACTAG_HELD_MAX)
        held[(*nheld)++] = *h;
}

/* Keeps both hypotheses of a reading refused as too close to call (the
 * reading and the rival that refused it: pair[0], pair[1]). */
void actag__hold_pair(actag__fit_rival *held, int *nheld, const actag__fit_rival pair[2])
{
    hold(held, nheld, &pair[0]);
    hold(held, nheld, &pair[1]);
}

/* The start of a contour's grid guess: its extreme points (gq), not on
 * the frame's border (such a guess is not read and not counted against
 * ACTAG_GUESS_MAX), within the decode budget; *gg is cleared for the read
 * (read_before: a quad of the contour was read before: one more look) and
 * the guess counted. Returns 0, ACTAG__GUESS_UNREAD or ACTAG__GUESS_BORDER. */
static int guess_start(const actag__reader *r, const actag_ipoint *pts, int npts,
                       actag_stats *st, int read_before, actag__fit_grids *gg, int *nguess,
                       actag_point gq[4])
{
    if (!actag__extreme_quad(pts, npts, gq))
        return ACTAG__GUESS_UNREAD;
    if (actag__guess_on_border(gq, r->rows, r->cols))
        return ACTAG__GUESS_BORDER;
    if (!actag__decode_budget(st, r->params))
        return ACTAG__GUESS_UNREAD;
    memset(gg, 0, sizeof *gg);
    gg->read_before = read_before;
    (*nguess)++;
    return 0;
}

/* A guess gq read with the wide search and the template check (read_wide,
 * into *dr; *gg: its grids, kept or found); a reading the check refused
 * as too close to call is held for the search readings' rival check.
 * Returns read_wide's verdict. */
int actag__read_guess(const actag__reader *r, actag__fit_grids *gg, actag__fit_rival *held,
                      int *nheld, const actag_point gq[4], actag_decode_result *dr)
{
    actag__fit_amb ga;
    int verdict = actag__read_wide(r, gq, 1, gg, &ga, dr);
    if (verdict == ACTAG_TRACE_NO_MATCH && ga.amb)
        actag__hold_pair(held, nheld, ga.r);
    return verdict;
}

/* A contour's grid guess (guess_start, then read_guess). Returns
 * read_wide's verdict, ACTAG__GUESS_UNREAD or ACTAG__GUESS_BORDER. */
int actag__contour_guess(const actag__reader *r, const actag_ipoint *pts, int npts,
                         actag_stats *st, int read_before, actag__fit_grids *gg, int *nguess,
                         actag__fit_rival *held, int *nheld, actag_point gq[4],
                         actag_decode_result *dr)
{
    int rc = guess_start(r, pts, npts, st, read_before, gg, nguess, gq);
    return rc ? rc : actag__read_guess(r, gg, held, nheld, gq, dr);
}

/* The second reading of a guess read tentatively (cross_check), now with
 * the template check, from the grids the first one kept: what a first
 * reading with the check would have given (decode_fit_grids.h). Returns
 * read_wide's verdict or ACTAG__GUESS_UNREAD (decode budget spent). */
int actag__read_guess_again(const actag__reader *r, actag_stats *st, actag__fit_grids *gg,
                            actag__fit_rival *held, int *nheld, const actag_point gq[4],
                            actag_decode_result *dr)
{
    if (!actag__decode_budget(st, r->params))
        return ACTAG__GUESS_UNREAD;
    return actag__read_guess(r, gg, held, nheld, gq, dr);
}

static float dist2(actag_point a, actag_point b)
{
    float dx = a.x - b.x, dy = a.y - b.y;
    return dx * dx + dy * dy;
}

actag_point actag__centre(const actag_point c[4])
{
    actag_point m;
    m.x = 0.25f * (c[0].x + c[1].x + c[2].x + c[3].x);
    m.y = 0.25f * (c[0].y + c[1].y + c[2].y + c[3].y);
    return m;
}

actag__place actag__place_of(const actag_point q[4])
{
    actag__place p;
    p.c = actag__centre(q);
    p.r2 = dist2(q[0], q[2]) * 0.25f;
    return p;
}

/* Centre inside the other quad's circumcircle (either way round). */
int actag__places_meet(actag__place a, actag__place b)
{
    return dist2(a.c, b.c) <= (a.r2 > b.r2 ? a.r2 : b.r2);
}

/* actag__places_meet of two quads' places; d, c: 4 corners each. */
int actag__same_place(const actag_point *d, const actag_point *c)
{
    return actag__places_meet(actag__place_of(d), actag__place_of(c));
}


/* A reading as the rival check sees it (decode_fit_grids.h). */
actag__fit_rival actag__rival_of(const actag_decode_result *r)
{
    actag__fit_rival v;
    v.id = r->id;
    v.rotation = r->rotation;
    v.mirrored = r->mirrored;
    memcpy(v.fit_corners, r->fit_corners, sizeof v.fit_corners);
    return v;
}

/* Do two readings of one place name different tags, handedness or corner
 * order? Corner order: b's first corner is not the nearest of a's corners
 * to a's first. */
static int readings_disagree(const actag__fit_rival *a, const actag__fit_rival *b)
{
    int j, near = 0;
    if (a->id != b->id || a->mirrored != b->mirrored)
        return 1;
    for (j = 1; j < 4; j++)
        if (dist2(a->fit_corners[0], b->fit_corners[j]) <
            dist2(a->fit_corners[0], b->fit_corners[near]))
            near = j;
    return near != 0;
}

/* A reading (a quad's or a contour guess's, *dr, reported at corners) at
 * the place of other readings (other[0..nother-1]) that disagree with it:
 * each disagreeing pair is judged as whole templates, polished over the
 * full range at both places (actag__fit_rival_explains); when the other
 * explains the cells at least as well, the place has two readings and
 * neither has the lead its decision margin stands for. The others are the
 * tentative search readings and, for a contour's grid guess, the
 * hypotheses of the contour's quads that the template check refused as too
 * close to call (the reading and the rival that refused it); for a search
 * reading reported after the contours (nsk 0), the hypotheses of the
 * readings that the template checks of the frame's quads and guesses
 * refused as too close to call, each reading and its rival (held,
 * detect.c's search_readings and judge_blind; heldout seed 9722 frame 177 of bench/heldout_sweep.py
 * --mix c24h10: the rival was the truth). A search
 * reading that refuses a reading here is marked in contested[] (nsk
 * entries): the place then has two readings that each passed their own
 * checks, and neither is reported (detect.c's search_readings). (Simulated
 * frame 408 of actag-eval --seed 311:
 * an unmirrored tag 4 at 2.5 m whose thresholded white square lost a fifth
 * of its height at both range edges; the quad read tag 5 at margin 6.3 on
 * the short grid, the search tag 4 on a grid of the right height. Frame 62
 * of pass 17 of actag-eval --pool --sequences 20 --seed 81: the quads found
 * tag 2 and a mirrored tag 6 too close to call, the guess read tag 6 at
 * margin 7.4 on a grid a quarter short. Frame 672 of actag-eval --seed 401
 * --family AcTag24h8: an unmirrored tag 5 at 1.03 m and 68 degrees, read
 * right by its quad at margin 25.9, hamming 0; the search, whose grids are
 * not sheared like the tag's image, read tag 32 turned half a turn at
 * margin 23.3, and its template explained the filtered cells better, so
 * tag 32 was reported. Frame 15 of actag-eval --pool --seed 3005 --clutter
 * 12 --azimuth-ascending: an unmirrored tag 0 at 1.23 m whose guess read
 * tag 0 on the right grid, residual 4,806, and was refused as too close to
 * call; the search read the mirrored tag 5 on a grid where tag 0 was no
 * candidate, margin 9.2, and nothing contested it.) Returns 1 to refuse the reading. */
int actag__rival_explains(const actag__reader *r, const actag_decode_result *dr,
                          const actag_decode_result *sk, int nsk, const actag__fit_rival *amb,
                          int namb, const actag_point corners[4], int *contested)
{
    const actag_params *params = r->params;
    actag__fit_rival a = actag__rival_of(dr), o;
    int k;
    float own = -1.0f; /* the reading's polish at its own place, once */
    if (params->tuning.decode_mode != ACTAG_DECODE_FIT)
        return 0;
    for (k = 0; k < nsk + namb; k++) {
        float r1, r2;
        o = k < nsk ? actag__rival_of(&sk[k]) : amb[k - nsk];
        if (!actag__same_place(corners, o.fit_corners) || !readings_disagree(&a, &o))
            continue;
        if (actag__fit_rival_explains_own(r->grey, r->rows, r->cols, r->cols, params->family,
                                          &params->tuning.fit, a.id, a.fit_corners, o.id,
                                          o.fit_corners, &r1, &r2, &own) == 1) {
            if (k < nsk)
                contested[k] = 1;
            return 1;
        }
    }
    return 0;
}

/* Turns of a blind box about its centre (cos, sin), in the box's own
 * frame: +30, -30 and +45 degrees. With the box itself these are clean
 * starts at 0, 30, 45 and 60 degrees (-30 is 60 modulo 90) in the tag's
 * plane, so every turn of a tag lies within 15 degrees of one; the wide
 * search adds its own starts turned +-30 degrees in pixels (decode.h),
 * which for a box square in pixels are the same turns (and bring every
 * turn within 7.5 degrees of a start), for an oblong one sheared ones. */
static const float blind_turns[3][2] = {
    {0.8660254f, 0.5f}, {0.8660254f, -0.5f}, {0.70710678f, 0.70710678f}};

/* The box q turned by (c, s) = (cos, sin) about its centre in its own
 * frame (q as the affine image of a unit square, so that a box of one tag
 * size along range and along azimuth turns as the tag would), into t. */
static void turn_box(const actag_point q[4], float c, float s, actag_point t[4])
{
    static const float su[4] = {-0.5f, 0.5f, 0.5f, -0.5f}, sv[4] = {-0.5f, -0.5f, 0.5f, 0.5f};
    actag_point m = actag__centre(q);
    float ax = 0.5f * (q[1].x - q[0].x + q[2].x - q[3].x);
    float ay = 0.5f * (q[1].y - q[0].y + q[2].y - q[3].y);
    float bx = 0.5f * (q[3].x - q[0].x + q[2].x - q[1].x);
    float by = 0.5f * (q[3].y - q[0].y + q[2].y - q[1].y);
    int j;
    for (j = 0; j < 4; j++) {
        float u = c * su[j] - s * sv[j], v = s * su[j] + c * sv[j];
        t[j].x = m.x + u * ax + v * bx;
        t[j].y = m.y + u * ay + v * by;
    }
}

/* Start t read as a tentative wide reading against blind reading *dr
 * (its rival form a; *own its polish at its own place, computed once):
 * 0 when it reads the same tag, handedness and corner order at dr's
 * place, 1 when it reads another one there whose template explains the
 * cells at least as well (both polished over the full range at both
 * places, as rival_explains judges), -1 otherwise (nothing there, or a
 * weaker other reading: it says nothing). */
static inline int start_rival(const actag__reader *r, const actag_point t[4],
                              const actag_decode_result *dr, const actag__fit_rival *a,
                              float *own)
{
    const actag_params *params = r->params;
    actag__fit_grids gg;
    actag_decode_result tdr;
    actag__fit_rival o;
    float r1, r2;
    memset(&gg, 0, sizeof gg); /* state 0: not read before */
    gg.blind = 1;
    if (actag__read_wide(r, t, 0, &gg, NULL, &tdr) != ACTAG_TRACE_ACCEPTED)
        return -1;
    o = actag__rival_of(&tdr);
    if (!actag__same_place(dr->fit_corners, o.fit_corners))
        return -1;
    if (!readings_disagree(a, &o))
        return 0;
    return actag__fit_rival_explains_own(r->grey, r->rows, r->cols, r->cols, params->family,
                                         &params->tuning.fit, a->id, a->fit_corners, o.id,
                                         o.fit_corners, &r1, &r2, own) == 1
               ? 1
               : -1;
}

/* q with corner j moved to the parallelogram through the other three, into
 * t; 0 when that moves it by less than a quarter of q's mean side (q is
 * nearly a parallelogram there: a box's completions are the box; or q
 * is a point). */
int actag__complete_corner(const actag_point q[4], int j, actag_point t[4])
{
    float side2 = 0.0f, dx, dy;
    int i;
    for (i = 0; i < 4; i++) {
        dx = q[(i + 1) & 3].x - q[i].x;
        dy = q[(i + 1) & 3].y - q[i].y;
        side2 += 0.25f * (dx * dx + dy * dy);
    }
    memcpy(t, q, 4 * sizeof *t);
    t[j].x = q[(j + 3) & 3].x + q[(j + 1) & 3].x - q[(j + 2) & 3].x;
    t[j].y = q[(j + 3) & 3].y + q[(j + 1) & 3].y - q[(j + 2) & 3].y;
    dx = t[j].x - q[j].x;
    dy = t[j].y - q[j].y;
    return side2 > 0.0f && dx * dx + dy * dy >= 0.0625f * side2;
}

/* A blind reading *dr (a search position's or a contour guess's, box q:
 * a start that knows the tag's size but not its turn) against the readings
 * of other starts at its place, each read as a tentative wide reading
 * (start_rival): when one reads another tag, handedness or corner order
 * whose template explains the cells at least as well, the place has two
 * readings and *dr is refused.
 *   1. q with one corner completed to the parallelogram through the other
 *      three (actag__complete_corner; each that moves a corner by a quarter side
 *      or more, so only a contour guess's extreme points, never a box): a
 *      white square whose contour lost a corner's part (merged with the
 *      ring, or cut by speckle) gives extreme points with one corner
 *      inside the tag, and the wide search from them can settle on a grid
 *      across the tag's cells. Every completion is tried: one made from
 *      the misplaced corner may read the same chance word.
 *   2. q turned (blind_turns); the first turned start that reads the same
 *      tag, handedness and corner order ends the check (two starts agree),
 *      one that reads nothing says nothing. The wide search picks its
 *      start grid by a code-agnostic score, so over a tag turned 30-45
 *      degrees it can settle on a grid across the tag's cells whose
 *      reading is a chance word; a turned start then finds the tag's own
 *      grid, which explains the cells far better.
 * (docs/decoder.md, "Blind readings and turned starts": with AcTag24m10,
 * whose one code such grids read in the wrong handedness, 7 mirrored-flag
 * and corner-order errors in 12 held-out runs, 3 after the turns; held-out
 * run 15046 frame 412, a guess from a white square missing its far corner,
 * read tag 0 in the wrong handedness at margin 16.9 past the turns, and
 * the completion refuses it.) Returns 1 to refuse. */
#if defined(__GNUC__)
__attribute__((noinline))
#endif
int actag__turned_rival_refuses(const actag__reader *r, const actag_point q[4],
                                const actag_decode_result *dr)
{
    const actag_params *params = r->params;
    actag__fit_rival a = actag__rival_of(dr);
    float own = -1.0f; /* the reading's polish at its own place, once */
    actag_point t[4];
    int i, v;
    if (params->tuning.decode_mode != ACTAG_DECODE_FIT)
        return 0;
    for (i = 0; i < 4; i++)
        if (actag__complete_corner(q, i, t) && start_rival(r, t, dr, &a, &own) == 1)
            return 1;
    for (i = 0; i < (int)(sizeof blind_turns / sizeof blind_turns[0]); i++) {
        turn_box(q, blind_turns[i][0], blind_turns[i][1], t);
        v = start_rival(r, t, dr, &a, &own);
        if (v == 0)
            return 0; /* a second start reads the same: the reading stands */
        if (v == 1)
            return 1;
    }
    return 0;
}

/* The cross-check of a quad reading *qdr (detect.c's read_quads): its contour's
 * grid guess read tentatively, without the template check (gq and *gg keep
 * it for read_guess_again). Returns 1 when the guess reads another tag,
 * handedness or corner order at the quad's place and the quad's template
 * does not lead the guess's by the least decision margin (both polished
 * over the full range at both places): the quad's reading is to be
 * refused. Its own frame keeps the guess's reading off read_quads'. */
#if defined(__GNUC__)
__attribute__((noinline))
#endif
int actag__cross_check(const actag__reader *r, const actag_ipoint *pts, int npts, actag_stats *st,
                       int *nguess, const actag_decode_result *qdr, actag_point gq[4],
                       actag__fit_grids *gg)
{
    const actag_params *params = r->params;
    actag_decode_result gdr;
    actag__fit_rival a, o;
    float r1, r2;
    /* read without the template check, in this frame: no refused
     * hypothesis is held from a tentative read */
    if (guess_start(r, pts, npts, st, 1, gg, nguess, gq) != 0)
        return 0;
    if (actag__read_wide(r, gq, 0, gg, NULL, &gdr) != ACTAG_TRACE_ACCEPTED)
        return 0;
    a = actag__rival_of(qdr);
    o = actag__rival_of(&gdr);
    if (!actag__same_place(qdr->corners, gdr.fit_corners) || !readings_disagree(&a, &o))
        return 0;
    if (actag__fit_rival_explains_own(r->grey, r->rows, r->cols, r->cols, params->family,
                                      &params->tuning.fit, a.id, a.fit_corners, o.id,
                                      o.fit_corners, &r1, &r2, NULL) < 0)
        return 0;
    return actag__fit_rss_llr(params->family, &params->tuning.fit, r1, r2, qdr->contrast) <
           params->min_margin;
}
