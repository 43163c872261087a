/* Family look-up, code orientation helpers and the matchers (hard and soft: one scan). */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/family.h"

#include <string.h>

/* x86-64 (SSE2, the baseline): the soft matcher's distances of the 8
 * views side by side (scan_soft_sse2), the same integers. */
#if defined(__SSE2__) && !defined(ACTAG_NO_SIMD)
#define FAMILY_SSE2 1
#include <emmintrin.h>
#else
#define FAMILY_SSE2 0
#endif

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
    if (bits >= 1 && bits <= 32) {
        /* all 32 bits reversed by swapping halves, bytes, nibbles, pairs and
         * bits (a few operations instead of a loop of `bits`), then the low
         * `bits` of code brought down to the low end: the loop's result */
        r = code;
        r = (r >> 16) | (r << 16);
        r = ((r >> 8) & 0x00FF00FFu) | ((r & 0x00FF00FFu) << 8);
        r = ((r >> 4) & 0x0F0F0F0Fu) | ((r & 0x0F0F0F0Fu) << 4);
        r = ((r >> 2) & 0x33333333u) | ((r & 0x33333333u) << 2);
        r = ((r >> 1) & 0x55555555u) | ((r & 0x55555555u) << 1);
        return r >> (32 - bits);
    }
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
    /* rot^-o == rot^(4-o): one turn by (4 - o) k bits (k = bits / 4, the
     * turns of actag_code_rot90 at once) */
    uint32_t mask = actag_code_mask(bits), a = w & mask, b = wm & mask;
    int o, s;
    obs[0] = w;
    obs[4] = wm;
    for (o = 1; o < 4; o++) {
        s = (4 - o) * (bits / 4); /* 0 < s < bits */
        obs[o] = ((a << s) | (a >> (bits - s))) & mask;
        obs[4 + o] = ((b << s) | (b >> (bits - s))) & mask;
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

/* Reading (d, h, code i, view v) into the list top[0 .. ntop-1] of at most
 * maxtop, kept in order (see scan_codes); returns the new ntop. */
static int top_insert(actag_soft_reading *top, int ntop, int maxtop, int d, int h, int i, int v)
{
    int j;
    if (ntop < maxtop) {
        j = ntop++;
    } else {
        j = maxtop - 1;
        if (!(d < top[j].d || (d == top[j].d && h < top[j].h)))
            return ntop;
    }
    while (j > 0 && (d < top[j - 1].d || (d == top[j - 1].d && h < top[j - 1].h))) {
        top[j] = top[j - 1];
        j--;
    }
    top[j].d = d;
    top[j].h = h;
    top[j].id = i;
    top[j].view = v;
    return ntop;
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
            int h = actag_popcount32(mis), d = h;
            if (lb && ntop > 1 && lb_no_better(lb[h], h, &top[1]) &&
                (ntop == maxtop || lb_no_better(lb[h], h, &top[ntop - 1])))
                continue;
            if (pl) {
                d = 0;
                for (b = 0; b < 5; b++)
                    d += actag_popcount32(mis & pl[v][b]) << b;
            }
            ntop = top_insert(top, ntop, maxtop, d, h, i, v);
        }
        /* nothing beats a full list of exact matches */
        if (ntop == maxtop && top[maxtop - 1].d == 0 && top[maxtop - 1].h == 0)
            break;
    }
    return ntop;
}

#if FAMILY_SSE2
/* Each byte's set bits (0..8), in that byte. */
static __m128i byte_counts(__m128i x)
{
    const __m128i m1 = _mm_set1_epi8(0x55), m2 = _mm_set1_epi8(0x33), m4 = _mm_set1_epi8(0x0f);
    x = _mm_sub_epi8(x, _mm_and_si128(_mm_srli_epi32(x, 1), m1));
    x = _mm_add_epi8(_mm_and_si128(x, m2), _mm_and_si128(_mm_srli_epi32(x, 2), m2));
    return _mm_and_si128(_mm_add_epi8(x, _mm_srli_epi32(x, 4)), m4);
}

/* The sum of each 32-bit lane's four bytes (each at most 255). */
static __m128i lane_sums(__m128i x)
{
    __m128i pairs = _mm_add_epi16(_mm_and_si128(x, _mm_set1_epi16(0xff)), _mm_srli_epi16(x, 8));
    return _mm_madd_epi16(pairs, _mm_set1_epi16(1));
}

static __m128i load4(const uint32_t *p)
{
    return _mm_loadu_si128((const __m128i *)(const void *)p);
}

/* h and d of code c in views o..o+3 (o 0 or 4; planes pl[b][v]): h =
 * popcount(mis), d = sum of popcount(mis & pl[b]) << b, the byte counts
 * weighted within each byte first (at most 8 x 31 = 248). */
static void views4_sse2(__m128i c, const uint32_t *obs, const uint32_t *keepv,
                        const uint32_t (*pl)[8], int o, __m128i *h, __m128i *d)
{
    __m128i mis = _mm_and_si128(_mm_xor_si128(c, load4(obs + o)), load4(keepv + o));
    __m128i t = byte_counts(_mm_and_si128(mis, load4(pl[4] + o)));
    int b;
    for (b = 3; b >= 0; b--) /* Horner: t = 2 t + the counts of plane b */
        t = _mm_add_epi8(_mm_add_epi8(t, t), byte_counts(_mm_and_si128(mis, load4(pl[b] + o))));
    *h = lane_sums(byte_counts(mis));
    *d = lane_sums(t);
}

/* The soft matcher's list as keys 33 d + h: a reading ranks above another
 * exactly when its key is lower (h <= 32), and lb_no_better(lbh, h, t) is
 * 33 lbh + h >= t's key; d <= 32 ACTAG_SOFT_SCALE, so a key fits 16 bits.
 * tag: 8 id + view. */
static int key_insert(int *key, int *tag, int ntop, int maxtop, int kk, int t)
{
    int j;
    if (ntop < maxtop) {
        j = ntop++;
    } else {
        j = maxtop - 1;
        if (!(kk < key[j]))
            return ntop;
    }
    while (j > 0 && kk < key[j - 1]) {
        key[j] = key[j - 1];
        tag[j] = tag[j - 1];
        j--;
    }
    key[j] = kk;
    tag[j] = t;
    return ntop;
}

/* scan_codes with planes and lb (the soft matcher; maxtop at most
 * ACTAG_SOFT_TOP), the planes given per plane (pl[b][v]): each code's h
 * and d in all 8 views at once, then the same list as scan_codes (the same
 * skips, in the same order: d is only formed ahead). Once the list is
 * full, a view whose key is not below the last one's is neither kept nor
 * changes anything (the keys of the list only fall), so only the others
 * go through the list. Also, over every reading in `views` (also after a
 * full list of exact matches ends the list), the least h of each view in
 * m1[v] and the least after it in m2[v] (33 without one), for the hard
 * distances the soft matcher reports. */
static int scan_soft_sse2(const actag_family *family, const uint32_t *obs, unsigned views,
                          const uint32_t *keepv, const uint32_t (*pl)[8], const int *lb,
                          actag_soft_reading *top, int maxtop, int16_t m1[8], int16_t m2[8])
{
    int i, v, ntop = 0, done = 0, key[ACTAG_SOFT_TOP], tag[ACTAG_SOFT_TOP];
    int16_t hs[8], ks[8], out[8];
    __m128i lo1 = _mm_set1_epi16(33), lo2 = lo1, skip;
    for (v = 0; v < 8; v++) /* views left out: 33, above every h */
        out[v] = (int16_t)((views & (1u << v)) ? 0 : 33);
    skip = _mm_loadu_si128((const __m128i *)(const void *)out);
    for (i = 0; i < family->ncodes; i++) {
        __m128i c = _mm_set1_epi32((int)family->codes[i]), h0, d0, h1, d1, hv, kv;
        unsigned cand;
        views4_sse2(c, obs, keepv, pl, 0, &h0, &d0);
        views4_sse2(c, obs, keepv, pl, 4, &h1, &d1);
        hv = _mm_packs_epi32(h0, h1);
        kv = _mm_add_epi16(_mm_mullo_epi16(_mm_packs_epi32(d0, d1), _mm_set1_epi16(33)), hv);
        _mm_storeu_si128((__m128i *)(void *)hs, hv);
        _mm_storeu_si128((__m128i *)(void *)ks, kv);
        hv = _mm_max_epi16(hv, skip);
        lo2 = _mm_min_epi16(lo2, _mm_max_epi16(lo1, hv));
        lo1 = _mm_min_epi16(lo1, hv);
        if (done)
            continue;
        cand = views;
        if (ntop == maxtop) /* views whose key is below the last one's */
            cand &= (unsigned)_mm_movemask_epi8(_mm_packs_epi16(
                _mm_cmplt_epi16(kv, _mm_set1_epi16((short)key[maxtop - 1])), _mm_setzero_si128()));
        for (v = 0; v < 8; v++) {
            int h = hs[v];
            if (!(cand & (1u << v)))
                continue;
            if (ntop > 1 && 33 * lb[h] + h >= key[1] &&
                (ntop == maxtop || 33 * lb[h] + h >= key[ntop - 1]))
                continue;
            ntop = key_insert(key, tag, ntop, maxtop, ks[v], 8 * i + v);
        }
        /* nothing beats a full list of exact matches */
        done = ntop == maxtop && key[maxtop - 1] == 0;
    }
    for (i = 0; i < ntop; i++) {
        top[i].d = key[i] / 33;
        top[i].h = key[i] % 33;
        top[i].id = tag[i] >> 3;
        top[i].view = tag[i] & 7;
    }
    _mm_storeu_si128((__m128i *)(void *)m1, lo1);
    _mm_storeu_si128((__m128i *)(void *)m2, lo2);
    return ntop;
}

/* The per-bit part of the soft matcher, four confidences at a time (bits
 * is a multiple of 4): the same weights q[i] (min(|c_i|, 1) in
 * 1/ACTAG_SOFT_SCALE, rounded; NaN 0), and the sign word *w and the weight
 * planes with bit i at bits - 1 - i (gathered at bit i, then reversed). */
static void weights_sse2(const float *conf, int bits, uint32_t *w, uint32_t plane[5], int *q)
{
    const __m128 one = _mm_set1_ps(1.0f), zero = _mm_setzero_ps();
    const __m128 scale = _mm_set1_ps((float)ACTAG_SOFT_SCALE), half = _mm_set1_ps(0.5f);
    const __m128 magn = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
    uint32_t wi = 0u, pi[5] = {0u, 0u, 0u, 0u, 0u};
    int i, b;
    for (i = 0; i < bits; i += 4) {
        __m128 c = _mm_loadu_ps(conf + i), a = _mm_and_ps(c, magn);
        __m128i qi = _mm_cvttps_epi32(_mm_add_ps(_mm_mul_ps(a, scale), half));
        __m128i ge1 = _mm_castps_si128(_mm_cmpge_ps(a, one));
        __m128i ge0 = _mm_castps_si128(_mm_cmpge_ps(a, zero)); /* false for NaN */
        qi = _mm_or_si128(_mm_and_si128(ge1, _mm_set1_epi32(ACTAG_SOFT_SCALE)),
                          _mm_andnot_si128(ge1, _mm_and_si128(ge0, qi)));
        _mm_storeu_si128((__m128i *)(void *)(q + i), qi);
        wi |= (uint32_t)_mm_movemask_ps(_mm_cmpgt_ps(c, zero)) << i;
        for (b = 0; b < 5; b++) /* bit b of each weight to its lane's sign */
            pi[b] |= (uint32_t)_mm_movemask_ps(_mm_castsi128_ps(_mm_slli_epi32(qi, 31 - b))) << i;
    }
    *w = actag_code_reverse(wi, bits);
    for (b = 0; b < 5; b++)
        plane[b] = actag_code_reverse(pi[b], bits);
}
#endif

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
    int bits, i, b, v, nk = 0, lb[33], rc, cnt[ACTAG_SOFT_SCALE + 1];
    uint32_t w = 0, plane[5] = {0, 0, 0, 0, 0}, obs[8], keepv[8];
#if FAMILY_SSE2
    uint32_t pl[5][8]; /* per plane: scan_soft_sse2 */
    int16_t m1[8], m2[8];
    int q[32];
#else
    uint32_t pl[8][5];
#endif
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
    memset(cnt, 0, sizeof cnt);
    /* the reading's signs, and its weights |c_i| in 1/ACTAG_SOFT_SCALE as
     * bit planes: a soft distance is then five masked popcounts */
#if FAMILY_SSE2
    weights_sse2(conf, bits, &w, plane, q);
    for (i = 0; i < bits; i++)
        if (keep & ((uint32_t)1u << (bits - 1 - i)))
            cnt[q[i]]++;
#else
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
            cnt[qi]++; /* 0 .. ACTAG_SOFT_SCALE */
    }
#endif
    /* lb[h]: the least soft distance of h disagreeing kept bits, the sum
     * of the h least weights (counted, not sorted: the same sums) */
    lb[0] = 0;
    for (b = 0; b <= ACTAG_SOFT_SCALE; b++)
        for (i = 0; i < cnt[b]; i++, nk++)
            lb[nk + 1] = lb[nk] + b;
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
#if FAMILY_SSE2
            pl[b][v] = pv[v];
#else
            pl[v][b] = pv[v];
#endif
    }
#if FAMILY_SSE2
    res->ntop = scan_soft_sse2(family, obs, views, keepv, (const uint32_t(*)[8])pl, lb, res->top,
                               ACTAG_SOFT_TOP, m1, m2);
#else
    res->ntop = scan_codes(family, obs, views, keepv, (const uint32_t(*)[5])pl, lb, res->top,
                           ACTAG_SOFT_TOP);
#endif
    res->d1 = res->top[0].d; /* ncodes >= 1: at least one reading */
    res->d2 = res->ntop > 1 ? res->top[1].d : 1 << 28;
    res->best.id = res->top[0].id;
    res->best.rotation = res->top[0].view & 3;
    res->best.mirrored = res->top[0].view >> 2;
    res->best.hamming = res->top[0].h;
    /* hard distances: the other handedness' best (mirror_margin) and the
     * best of every reading but the chosen one (the bit margin) */
    res->h2 = 33;
#if FAMILY_SSE2
    /* from each view's least two h: the chosen reading's view without one
     * of its h (its own, where that is the least) */
    for (v = 0; v < 8; v++) {
        int h = v == res->top[0].view && m1[v] == res->top[0].h ? m2[v] : m1[v];
        if ((v >> 2) != res->best.mirrored && m1[v] < res->other)
            res->other = m1[v];
        if (h < res->h2)
            res->h2 = h;
    }
#else
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
#endif
    return ACTAG_OK;
}
