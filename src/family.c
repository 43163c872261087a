/* Family look-up, code orientation helpers and the matchers (hard and soft: one scan). */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/family.h"

#include <string.h>

/* Provided by the generated families registry (build tree, from ACTAG_FAMILIES). */
int actag_builtin_family_count(void);
int actag_builtin_family_fill(int index, actag_family *out);

int actag_family_count(void) { return actag_builtin_family_count(); }

/* The generated fill functions of published-rule families (and tables
 * generated before the fields existed) leave mirror and excluded alone. */
static int fill(int i, actag_family *out)
{
    out->mirror = ACTAG_MIRROR_REVERSE;
    out->excluded = 0u;
    return actag_builtin_family_fill(i, out);
}

int actag_family_get_at(int i, actag_family *out)
{
    if (out == NULL)
        return ACTAG_ERR_NULL;
    if (i < 0 || i >= actag_builtin_family_count())
        return ACTAG_ERR_FAMILY;
    return fill(i, out);
}

int actag_family_get(const char *name, actag_family *out)
{
    int i, n = actag_builtin_family_count();
    actag_family f;
    if (name == NULL || out == NULL)
        return ACTAG_ERR_NULL;
    for (i = 0; i < n; i++) {
        if (fill(i, &f) == ACTAG_OK && strcmp(f.name, name) == 0) {
            *out = f; /* only on success: an unknown name leaves *out as it was */
            return ACTAG_OK;
        }
    }
    return ACTAG_ERR_FAMILY;
}

int actag_family_validate(const actag_family *family)
{
    uint32_t extra;
    int i;
    if (family == NULL)
        return ACTAG_ERR_NULL;
    if (family->codes == NULL || family->bits < 16 || family->bits > 32 || family->bits % 4 != 0 ||
        family->hamming < 1 || family->ncodes < 1)
        return ACTAG_ERR_FAMILY;
    /* a code with bits above `bits` would be matched differently by the
     * hard matchers (stray bits count as errors) and the fit decoder's
     * (masked off), and the soft matcher's bound lb[] does not reach them */
    extra = ~actag_code_mask(family->bits);
    for (i = 0; i < family->ncodes; i++)
        if (family->codes[i] & extra)
            return ACTAG_ERR_FAMILY;
    return ACTAG_OK;
}
int actag_family_max_corrections(const actag_family *family)
{
    if (family == NULL)
        return ACTAG_ERR_NULL;
    return (family->hamming % 2 == 0) ? family->hamming / 2 - 1 : family->hamming / 2;
}

uint32_t actag_code_mask(int bits)
{
    return bits >= 32 ? 0xffffffffu : ((uint32_t)1u << bits) - 1u;
}

uint32_t actag_code_rot90(uint32_t code, int bits)
{
    int k = bits / 4;
    uint32_t mask = actag_code_mask(bits);
    code &= mask;
    return ((code << k) | (code >> (bits - k))) & mask;
}

uint32_t actag_code_reverse(uint32_t code, int bits)
{
    uint32_t r = 0;
    int i;
    for (i = 0; i < bits; i++) {
        r = (r << 1) | (code & 1u);
        code >>= 1;
    }
    return r;
}

uint32_t actag_code_mirror(uint32_t code, int bits)
{
    uint32_t msb;
    if (bits < 2 || bits > 32)
        return code;
    code &= actag_code_mask(bits);
    msb = (uint32_t)1u << (bits - 1);
    return (code & msb) | (actag_code_reverse(code, bits) >> 1);
}

uint32_t actag_code_corners(int bits)
{
    int k = bits / 4, j;
    uint32_t m = 0u;
    if (bits < 4 || bits > 32)
        return 0u;
    for (j = 0; j < 4; j++)
        m |= (uint32_t)1u << (bits - 1 - j * k);
    return m;
}

int actag_popcount32(uint32_t v)
{
    /* Portable SWAR popcount: same result on every platform. */
    v = v - ((v >> 1) & 0x55555555u);
    v = (v & 0x33333333u) + ((v >> 2) & 0x33333333u);
    v = (v + (v >> 4)) & 0x0f0f0f0fu;
    return (int)((v * 0x01010101u) >> 24);
}

/* The views of an observation: view o (0..3) undoes rotation o on w, view
 * 4 + o on wm (the mirrored reading), so that view v equals code c exactly
 * when the reading is that orientation of c (observed == rot^o(c) <=>
 * rot^-o(observed) == c): the observation is turned, not the whole table. */
static void undo_views(uint32_t w, uint32_t wm, int bits, uint32_t obs[8])
{
    int o, s;
    for (o = 0; o < 4; o++) {
        uint32_t a = w, b = wm;
        for (s = 0; s < (4 - o) % 4; s++) { /* rot^-o == rot^(4-o) */
            a = actag_code_rot90(a, bits);
            b = actag_code_rot90(b, bits);
        }
        obs[o] = a;
        obs[4 + o] = b;
    }
}

/* The one scan behind every matcher: each code against the views v whose
 * bit (1 << v) is set in `views`,
 * counting the bits in keep. A reading's cost is the summed weight of its
 * disagreeing bits, the weights (0..31) given as bit planes pl[v][b] (bit b
 * of every bit's weight, in view v's order); without planes every bit
 * weighs 1 and the cost is the Hamming distance h: the hard match is the
 * soft one with equal confidences. The maxtop cheapest readings go to
 * top[], cheapest first (then fewer disagreeing bits; equal readings keep
 * scan order: lower ID, then lower view). keepv[v]: the kept bits in view
 * v's order (the reading's kept bits, the view undone). With lb (lb[h]: the
 * least cost of h disagreeing bits) a reading is skipped unscored when it
 * cannot rank above the runner-up (lb[h] above its cost, or equal to it
 * with no fewer disagreeing bits) and, unless the list is full, nor above
 * the last kept one: exact for the best two; the rest of the list, full or
 * not, may miss readings (a skipped one can rank above a worse reading
 * kept after it). Listing every reading instead (2026-12-05, a review)
 * gave the fit decoder's template check more rivals to polish: the same
 * detections, two pool margins lower, but the worst pool frame's decoding
 * 72 -> 151 M Cortex-M7 instructions, so not taken. Returns the number
 * kept. */
static int lb_no_better(int lbh, int h, const actag_soft_reading *t)
{
    /* every reading of h disagreeing bits costs lbh or more; at a cost
     * equal to t's it ranks above t only with fewer disagreeing bits */
    return lbh > t->d || (lbh == t->d && h >= t->h);
}

static int scan_codes(const actag_family *family, const uint32_t *obs, unsigned views,
                      const uint32_t *keepv, const uint32_t (*pl)[5], const int *lb,
                      actag_soft_reading *top, int maxtop)
{
    int i, v, b, ntop = 0;
    for (i = 0; i < family->ncodes; i++) {
        uint32_t c = family->codes[i];
        for (v = 0; v < 8; v++) {
            uint32_t mis = (c ^ obs[v]) & keepv[v];
            if (!(views & (1u << v)))
                continue;
            int h = actag_popcount32(mis), d = h, j;
            if (lb && ntop > 1 && lb_no_better(lb[h], h, &top[1]) &&
                (ntop == maxtop || lb_no_better(lb[h], h, &top[ntop - 1])))
                continue;
            if (pl) {
                d = 0;
                for (b = 0; b < 5; b++)
                    d += actag_popcount32(mis & pl[v][b]) << b;
            }
            if (ntop < maxtop) {
                j = ntop++;
            } else {
                j = maxtop - 1;
                if (!(d < top[j].d || (d == top[j].d && h < top[j].h)))
                    continue;
            }
            while (j > 0 && (d < top[j - 1].d || (d == top[j - 1].d && h < top[j - 1].h))) {
                top[j] = top[j - 1];
                j--;
            }
            top[j].d = d;
            top[j].h = h;
            top[j].id = i;
            top[j].view = v;
        }
        /* nothing beats a full list of exact matches */
        if (ntop == maxtop && top[maxtop - 1].d == 0 && top[maxtop - 1].h == 0)
            break;
    }
    return ntop;
}

/* The hard matchers: norient is 4 (rotations) or 8 (rotations and reversals). */
static int match_orientations(const actag_family *family, uint32_t observed, int max_corrections,
                              int norient, actag_match *out)
{
    uint32_t obs[8], w;
    actag_soft_reading best = {0, 0, 0, 0}; /* every family has a code: always filled */
    static const uint32_t all[8] = {0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu,
                                    0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu};
    int maxc, rc = actag_family_validate(family);
    if (out == NULL)
        return ACTAG_ERR_NULL;
    if (rc != ACTAG_OK)
        return rc;
    maxc = actag_family_max_corrections(family);
    if (max_corrections < 0 || max_corrections > maxc)
        return ACTAG_ERR_CORRECTIONS;
    /* observed == rev(rot^r(c))  <=>  rot^-r(rev(observed)) == c */
    w = observed & actag_code_mask(family->bits);
    undo_views(w, actag_code_reverse(w, family->bits), family->bits, obs);
    scan_codes(family, obs, norient == 4 ? ACTAG_VIEWS_UNMIRRORED : ACTAG_VIEWS_ALL,
               all, NULL, NULL, &best, 1);
    if (best.h > max_corrections) /* *out untouched, as on every error */
        return ACTAG_ERR_NO_MATCH;
    out->id = best.id;
    out->rotation = best.view & 3;
    out->mirrored = best.view >> 2;
    out->hamming = best.h;
    return ACTAG_OK;
}

int actag_family_match(const actag_family *family, uint32_t observed, int max_corrections,
                       actag_match *out)
{
    return match_orientations(family, observed, max_corrections, 8, out);
}

int actag_family_match_rotations(const actag_family *family, uint32_t observed,
                                 int max_corrections, actag_match *out)
{
    return match_orientations(family, observed, max_corrections, 4, out);
}

int actag_family_match_soft(const actag_family *family, const float *conf, uint32_t keep,
                            actag_soft_match *res)
{
    return actag_family_match_soft_views(family, conf, keep, ACTAG_VIEWS_ALL, res);
}

int actag_family_match_soft_views(const actag_family *family, const float *conf, uint32_t keep,
                                  unsigned views, actag_soft_match *res)
{
    int bits, i, b, v, nk = 0, q[32], lb[33], rc;
    uint32_t w = 0, plane[5] = {0, 0, 0, 0, 0}, obs[8], pl[8][5], keepv[8];
    if (family == NULL || conf == NULL || res == NULL)
        return ACTAG_ERR_NULL;
    rc = actag_family_validate(family);
    if (rc != ACTAG_OK)
        return rc;
    views &= ACTAG_VIEWS_ALL;
    if (views == 0u)
        return ACTAG_ERR_PARAM;
    bits = family->bits;
    res->other = 33;
    /* the reading's signs, and its weights |c_i| in 1/ACTAG_SOFT_SCALE as
     * bit planes: a soft distance is then five masked popcounts */
    for (i = 0; i < bits; i++) {
        float a = conf[i] < 0.0f ? -conf[i] : conf[i];
        /* a NaN confidence weighs 0 (no evidence; its conversion to int
         * would be undefined), an infinite one 1 */
        int qi = a >= 1.0f ? ACTAG_SOFT_SCALE
                 : a >= 0.0f ? (int)(a * (float)ACTAG_SOFT_SCALE + 0.5f) : 0;
        uint32_t bit = (uint32_t)1u << (bits - 1 - i);
        if (conf[i] > 0.0f)
            w |= bit;
        for (b = 0; b < 5; b++)
            if (qi & (1 << b))
                plane[b] |= bit;
        if (keep & bit)
            q[nk++] = qi;
    }
    /* lb[h]: the least soft distance of h disagreeing kept bits */
    for (i = 1; i < nk; i++) {
        int j, t = q[i];
        for (j = i; j > 0 && q[j - 1] > t; j--)
            q[j] = q[j - 1];
        q[j] = t;
    }
    lb[0] = 0;
    for (i = 0; i < nk; i++)
        lb[i + 1] = lb[i] + q[i];
    /* views 4..7: the physical reflection P of the reading; the kept bits
     * are the reading's, so they go through each view with it (the same
     * in every view for the decoder's masks: all bits, all but the
     * corners; other masks were applied in the code's order, and lb then
     * bounded nothing) */
    undo_views(w, actag_code_mirror(w, bits), bits, obs);
    keep &= actag_code_mask(bits);
    undo_views(keep, actag_code_mirror(keep, bits), bits, keepv);
    for (b = 0; b < 5; b++) {
        uint32_t pv[8];
        undo_views(plane[b], actag_code_mirror(plane[b], bits), bits, pv);
        for (v = 0; v < 8; v++)
            pl[v][b] = pv[v];
    }
    res->ntop = scan_codes(family, obs, views, keepv, (const uint32_t(*)[5])pl, lb, res->top,
                           ACTAG_SOFT_TOP);
    res->d1 = res->top[0].d; /* ncodes >= 1: at least one reading */
    res->d2 = res->ntop > 1 ? res->top[1].d : 1 << 28;
    res->best.id = res->top[0].id;
    res->best.rotation = res->top[0].view & 3;
    res->best.mirrored = res->top[0].view >> 2;
    res->best.hamming = res->top[0].h;
    /* hard distances: the other handedness' best (mirror_margin) and the
     * best of every reading but the chosen one (the bit margin) */
    res->h2 = 33;
    for (i = 0; i < family->ncodes; i++) {
        uint32_t c = family->codes[i];
        for (v = 0; v < 8; v++) {
            int h;
            if (!(views & (1u << v)))
                continue; /* not a hypothesis */
            h = actag_popcount32((c ^ obs[v]) & keepv[v]);
            if ((v >> 2) != res->best.mirrored && h < res->other)
                res->other = h;
            if (h < res->h2 && !(i == res->best.id && (v & 3) == res->best.rotation &&
                                 (v >> 2) == res->best.mirrored))
                res->h2 = h;
        }
    }
    return ACTAG_OK;
}
