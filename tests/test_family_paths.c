/* The family matchers' paths: the library (on x86-64 the soft matcher's
 * SSE2 scan, scan_soft_sse2 and weights_sse2), the same file in plain C
 * (tests/family_scalar_copy.c: ACTAG_NO_SIMD, under other names) and a
 * reference written here as the matchers were before them (the bit loops,
 * turns one rot90 at a time, lb by sorting, the list by scan_codes): the
 * same return code and every field of the result, the whole list top[]
 * included, bit for bit. Random and edge-case confidences (NaN, infinities,
 * signed zeros, exact rounding ties, clamped weights), keep masks and view
 * masks, on every built-in family and on made-up ones of 16 to 32 bits
 * (duplicate codes, codes whose every view reads exactly, lists of exact
 * matches that end the list early). */
#include "unity.h"
#include "test_util.h"

#include "actag/family.h"

#include <float.h>
#include <math.h>
#include <string.h>

/* tests/family_scalar_copy.c */
int actag_family_match_scalar(const actag_family *family, uint32_t observed, int max_corrections,
                              actag_match *out);
int actag_family_match_rotations_scalar(const actag_family *family, uint32_t observed,
                                        int max_corrections, actag_match *out);
int actag_family_match_soft_views_scalar(const actag_family *family, const float *conf,
                                         uint32_t keep, unsigned views, actag_soft_match *res);
uint32_t actag_code_reverse_scalar(uint32_t code, int bits);
uint32_t actag_code_mirror_scalar(uint32_t code, int bits);

void setUp(void) {}
void tearDown(void) {}

/* ---- the reference: the matchers before the SSE2 scan ---- */

static uint32_t ref_mask(int bits)
{
    return bits >= 32 ? 0xffffffffu : ((uint32_t)1u << bits) - 1u;
}

static uint32_t ref_rot90(uint32_t code, int bits)
{
    int k = bits / 4;
    uint32_t mask = ref_mask(bits);
    code &= mask;
    return ((code << k) | (code >> (bits - k))) & mask;
}

static uint32_t ref_reverse(uint32_t code, int bits)
{
    uint32_t r = 0;
    int i;
    for (i = 0; i < bits; i++) {
        r = (r << 1) | (code & 1u);
        code >>= 1;
    }
    return r;
}

static uint32_t ref_mirror(uint32_t code, int bits)
{
    uint32_t msb;
    if (bits < 2 || bits > 32)
        return code;
    code &= ref_mask(bits);
    msb = (uint32_t)1u << (bits - 1);
    return (code & msb) | (ref_reverse(code, bits) >> 1);
}

static void ref_undo_views(uint32_t w, uint32_t wm, int bits, uint32_t obs[8])
{
    int o, s;
    for (o = 0; o < 4; o++) {
        uint32_t a = w, b = wm;
        for (s = 0; s < (4 - o) % 4; s++) {
            a = ref_rot90(a, bits);
            b = ref_rot90(b, bits);
        }
        obs[o] = a;
        obs[4 + o] = b;
    }
}

static int ref_no_better(int lbh, int h, const actag_soft_reading *t)
{
    return lbh > t->d || (lbh == t->d && h >= t->h);
}

static int ref_scan(const actag_family *family, const uint32_t *obs, unsigned views,
                    const uint32_t *keepv, const uint32_t (*pl)[5], const int *lb,
                    actag_soft_reading *top, int maxtop)
{
    int i, v, b, ntop = 0;
    for (i = 0; i < family->ncodes; i++) {
        uint32_t c = family->codes[i];
        for (v = 0; v < 8; v++) {
            uint32_t mis = (c ^ obs[v]) & keepv[v];
            int h, d, j;
            if (!(views & (1u << v)))
                continue;
            h = tu_popcount(mis);
            d = h;
            if (lb && ntop > 1 && ref_no_better(lb[h], h, &top[1]) &&
                (ntop == maxtop || ref_no_better(lb[h], h, &top[ntop - 1])))
                continue;
            if (pl) {
                d = 0;
                for (b = 0; b < 5; b++)
                    d += tu_popcount(mis & pl[v][b]) << b;
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
        if (ntop == maxtop && top[maxtop - 1].d == 0 && top[maxtop - 1].h == 0)
            break;
    }
    return ntop;
}

/* (the argument checks are the library's: only valid calls reach here) */
static void ref_soft(const actag_family *family, const float *conf, uint32_t keep, unsigned views,
                     actag_soft_match *res)
{
    int bits = family->bits, i, b, v, nk = 0, q[32], lb[33];
    uint32_t w = 0, plane[5] = {0, 0, 0, 0, 0}, obs[8], pl[8][5], keepv[8];
    views &= ACTAG_VIEWS_ALL;
    res->other = 33;
    for (i = 0; i < bits; i++) {
        float a = conf[i] < 0.0f ? -conf[i] : conf[i];
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
    for (i = 1; i < nk; i++) {
        int j, t = q[i];
        for (j = i; j > 0 && q[j - 1] > t; j--)
            q[j] = q[j - 1];
        q[j] = t;
    }
    lb[0] = 0;
    for (i = 0; i < nk; i++)
        lb[i + 1] = lb[i] + q[i];
    ref_undo_views(w, ref_mirror(w, bits), bits, obs);
    keep &= ref_mask(bits);
    ref_undo_views(keep, ref_mirror(keep, bits), bits, keepv);
    for (b = 0; b < 5; b++) {
        uint32_t pv[8];
        ref_undo_views(plane[b], ref_mirror(plane[b], bits), bits, pv);
        for (v = 0; v < 8; v++)
            pl[v][b] = pv[v];
    }
    res->ntop = ref_scan(family, obs, views, keepv, (const uint32_t(*)[5])pl, lb, res->top,
                         ACTAG_SOFT_TOP);
    res->d1 = res->top[0].d;
    res->d2 = res->ntop > 1 ? res->top[1].d : 1 << 28;
    res->best.id = res->top[0].id;
    res->best.rotation = res->top[0].view & 3;
    res->best.mirrored = res->top[0].view >> 2;
    res->best.hamming = res->top[0].h;
    res->h2 = 33;
    for (i = 0; i < family->ncodes; i++) {
        uint32_t c = family->codes[i];
        for (v = 0; v < 8; v++) {
            int h;
            if (!(views & (1u << v)))
                continue;
            h = tu_popcount((c ^ obs[v]) & keepv[v]);
            if ((v >> 2) != res->best.mirrored && h < res->other)
                res->other = h;
            if (h < res->h2 && !(i == res->best.id && (v & 3) == res->best.rotation &&
                                 (v >> 2) == res->best.mirrored))
                res->h2 = h;
        }
    }
}

/* ---- comparisons ---- */

static void same_match(const actag_soft_match *a, const actag_soft_match *b, const char *what)
{
    int j;
    TEST_ASSERT_EQUAL_INT_MESSAGE(a->best.id, b->best.id, what);
    TEST_ASSERT_EQUAL_INT_MESSAGE(a->best.rotation, b->best.rotation, what);
    TEST_ASSERT_EQUAL_INT_MESSAGE(a->best.mirrored, b->best.mirrored, what);
    TEST_ASSERT_EQUAL_INT_MESSAGE(a->best.hamming, b->best.hamming, what);
    TEST_ASSERT_EQUAL_INT_MESSAGE(a->d1, b->d1, what);
    TEST_ASSERT_EQUAL_INT_MESSAGE(a->d2, b->d2, what);
    TEST_ASSERT_EQUAL_INT_MESSAGE(a->other, b->other, what);
    TEST_ASSERT_EQUAL_INT_MESSAGE(a->h2, b->h2, what);
    TEST_ASSERT_EQUAL_INT_MESSAGE(a->ntop, b->ntop, what);
    for (j = 0; j < a->ntop; j++) {
        TEST_ASSERT_EQUAL_INT_MESSAGE(a->top[j].d, b->top[j].d, what);
        TEST_ASSERT_EQUAL_INT_MESSAGE(a->top[j].h, b->top[j].h, what);
        TEST_ASSERT_EQUAL_INT_MESSAGE(a->top[j].id, b->top[j].id, what);
        TEST_ASSERT_EQUAL_INT_MESSAGE(a->top[j].view, b->top[j].view, what);
    }
}

/* One confidence: mostly ordinary, often an edge case. */
static float rand_conf(void)
{
    static const float edge[] = {0.0f, -0.0f, 1.0f, -1.0f, 0.99999994f, -1.0000001f, 0.03125f,
                                 -0.09375f, 0.96875f, 1e30f, -1e-30f, FLT_MIN, -FLT_MIN / 4.0f,
                                 2.5f, -7.0f};
    int kind = tu_range(0, 9);
    if (kind < 5)
        return ((float)tu_range(-3000, 3000)) / 2000.0f;
    if (kind == 5) /* multiples of 1/32: a * 16 + 0.5 lands on exact halves and integers */
        return (float)tu_range(-40, 40) / 32.0f;
    if (kind == 6)
        return edge[tu_range(0, (int)(sizeof edge / sizeof edge[0]) - 1)];
    if (kind == 7) {
        int s = tu_range(0, 3);
        return s == 0 ? NAN : s == 1 ? -NAN : s == 2 ? INFINITY : -INFINITY;
    }
    /* a reading near a code: weights of a few levels (one draw a
     * statement: the same inputs on every compiler) */
    {
        float sign = tu_range(0, 1) ? 1.0f : -1.0f;
        return sign * (float)tu_range(0, 20) / 16.0f;
    }
}

/* One matcher call on all three paths. */
static void check_one(const actag_family *fam, const float *conf, uint32_t keep, unsigned views)
{
    actag_soft_match a, b, r;
    int rca, rcb;
    memset(&a, 0x11, sizeof a);
    memset(&b, 0x22, sizeof b);
    memset(&r, 0x33, sizeof r);
    rca = actag_family_match_soft_views(fam, conf, keep, views, &a);
    rcb = actag_family_match_soft_views_scalar(fam, conf, keep, views, &b);
    TEST_ASSERT_EQUAL_INT(rca, rcb);
    if ((views & ACTAG_VIEWS_ALL) == 0u) {
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, rca);
        return;
    }
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, rca);
    ref_soft(fam, conf, keep, views, &r);
    same_match(&r, &a, "library against the reference");
    same_match(&r, &b, "plain C against the reference");
}

static uint32_t rand_keep(int bits, int t)
{
    uint32_t m = ref_mask(bits);
    switch (t % 5) {
    case 0: return m;
    case 1: return m & ~actag_code_corners(bits);
    case 2: return tu_rand(); /* bits above the code's too */
    case 3: return tu_rand() & tu_rand() & m;
    default: return t % 7 == 0 ? 0u : m;
    }
}

static unsigned rand_views(int t)
{
    static const unsigned masks[4] = {ACTAG_VIEWS_ALL, ACTAG_VIEWS_UNMIRRORED,
                                      ACTAG_VIEWS_MIRRORED, 0x100u | ACTAG_VIEWS_ALL};
    return t % 3 == 0 ? (unsigned)tu_range(0, 511) : masks[t % 4];
}

/* Confidences near a view of code c (bits flipped, weights random). */
static void conf_near(uint32_t c, int bits, int flips, float *conf)
{
    int i;
    for (i = 0; i < flips; i++)
        c ^= (uint32_t)1u << tu_range(0, bits - 1);
    for (i = 0; i < bits; i++) {
        float a = (float)tu_range(0, 18) / 16.0f;
        if (tu_range(0, 15) == 0)
            a = rand_conf();
        conf[i] = ((c >> (bits - 1 - i)) & 1u) ? a : -a;
    }
}

static void test_soft_paths_builtin_families(void)
{
    int f, t, n = actag_family_count();
    tu_seed(11);
    TEST_ASSERT_GREATER_OR_EQUAL(1, n);
    for (f = 0; f < n; f++) {
        actag_family fam;
        int trials = TU_TRIALS(300, 20);
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get_at(f, &fam));
        if (fam.ncodes > 1000)
            trials = TU_TRIALS(40, 20);
        for (t = 0; t < trials; t++) {
            float conf[32];
            int i;
            if (t % 2 == 0) {
                for (i = 0; i < fam.bits; i++)
                    conf[i] = rand_conf();
            } else {
                uint32_t c = fam.codes[tu_range(0, fam.ncodes - 1)];
                int v = tu_range(0, 7), r;
                for (r = 0; r < (v & 3); r++)
                    c = ref_rot90(c, fam.bits);
                if (v >> 2)
                    c = ref_mirror(c, fam.bits);
                conf_near(c, fam.bits, tu_range(0, 6), conf);
            }
            check_one(&fam, conf, rand_keep(fam.bits, t), rand_views(t));
        }
    }
}

/* Made-up families of 16 to 32 bits: random codes with duplicates, the
 * all-zero and all-one codes (every view of them the same word), codes
 * read exactly (a list of exact matches ends the scan; the hard distances
 * still take every code). */
static void test_soft_paths_made_up_families(void)
{
    static uint32_t codes[40];
    int t;
    tu_seed(12);
    for (t = 0; t < TU_TRIALS(6000, 40); t++) {
        actag_family fam;
        int bits = 16 + 4 * tu_range(0, 4), n = tu_range(1, 40), i;
        uint32_t m = ref_mask(bits), base = tu_rand() & m;
        float conf[32];
        for (i = 0; i < n; i++) {
            int kind = tu_range(0, 5);
            codes[i] = kind == 0 ? 0u : kind == 1 ? m : kind == 2 ? base : tu_rand() & m;
            if (i > 0 && tu_range(0, 4) == 0)
                codes[i] = codes[tu_range(0, i - 1)]; /* duplicates */
        }
        memset(&fam, 0, sizeof fam);
        fam.name = "made-up";
        fam.bits = bits;
        fam.hamming = 1;
        fam.ncodes = n;
        fam.codes = codes;
        switch (t % 4) {
        case 0: /* exactly the shared code, every bit sure */
            for (i = 0; i < bits; i++)
                conf[i] = ((base >> (bits - 1 - i)) & 1u) ? 1.0f : -1.0f;
            break;
        case 1: /* all white or all black: the uniform codes read exactly */
            for (i = 0; i < bits; i++)
                conf[i] = t % 8 == 1 ? 0.5f : -0.75f;
            break;
        case 2:
            {
                int which = tu_range(0, n - 1);
                int flips = tu_range(0, 3);
                conf_near(codes[which], bits, flips, conf);
            }
            break;
        default:
            for (i = 0; i < bits; i++)
                conf[i] = rand_conf();
        }
        check_one(&fam, conf, rand_keep(bits, t), rand_views(t));
    }
}

/* The hard matchers (the new turns and reversal) against a brute force:
 * the first (ID, then orientation) of the least distance. */
static void test_hard_paths(void)
{
    int f, t, n = actag_family_count();
    tu_seed(13);
    for (f = 0; f < n; f++) {
        actag_family fam;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get_at(f, &fam));
        for (t = 0; t < TU_TRIALS(200, 20); t++) {
            uint32_t w = tu_rand(), m = ref_mask(fam.bits), wm, c;
            int maxc = actag_family_max_corrections(&fam), norient, id, o;
            if (t % 2) { /* near a code */
                c = fam.codes[tu_range(0, fam.ncodes - 1)];
                for (o = tu_range(0, 3); o > 0; o--)
                    c = ref_rot90(c, fam.bits);
                if (tu_range(0, 1))
                    c = ref_reverse(c, fam.bits);
                w = c ^ ((uint32_t)1u << tu_range(0, fam.bits - 1));
            }
            wm = ref_reverse(w & m, fam.bits);
            for (norient = 4; norient <= 8; norient += 4) {
                actag_match a, b;
                int bh = 99, bid = -1, bo = -1, rca, rcb, want;
                for (id = 0; id < fam.ncodes; id++)
                    for (o = 0; o < norient; o++) {
                        uint32_t v[8];
                        int h;
                        ref_undo_views(w & m, wm, fam.bits, v);
                        h = tu_popcount(fam.codes[id] ^ v[o]);
                        if (h < bh) {
                            bh = h;
                            bid = id;
                            bo = o;
                        }
                    }
                memset(&a, 0x44, sizeof a);
                memset(&b, 0x44, sizeof b);
                rca = norient == 4 ? actag_family_match_rotations(&fam, w, maxc, &a)
                                   : actag_family_match(&fam, w, maxc, &a);
                rcb = norient == 4 ? actag_family_match_rotations_scalar(&fam, w, maxc, &b)
                                   : actag_family_match_scalar(&fam, w, maxc, &b);
                want = bh <= maxc ? ACTAG_OK : ACTAG_ERR_NO_MATCH;
                TEST_ASSERT_EQUAL_INT(want, rca);
                TEST_ASSERT_EQUAL_INT(want, rcb);
                TEST_ASSERT_EQUAL_MEMORY(&a, &b, sizeof a);
                if (want == ACTAG_OK) {
                    TEST_ASSERT_EQUAL_INT(bid, a.id);
                    TEST_ASSERT_EQUAL_INT(bo & 3, a.rotation);
                    TEST_ASSERT_EQUAL_INT(bo >> 2, a.mirrored);
                    TEST_ASSERT_EQUAL_INT(bh, a.hamming);
                }
            }
        }
    }
}

/* actag_code_reverse and actag_code_mirror (no loop for 1..32 bits) against
 * the bit loop, for every width, 0 and out of range included. */
static void test_reverse_and_mirror(void)
{
    int bits, t;
    tu_seed(14);
    for (bits = -2; bits <= 40; bits++)
        for (t = 0; t < 2000; t++) {
            uint32_t c = t == 0 ? 0u : t == 1 ? 0xffffffffu : t == 2 ? 0x80000001u : tu_rand();
            TEST_ASSERT_EQUAL_HEX32(ref_reverse(c, bits), actag_code_reverse(c, bits));
            TEST_ASSERT_EQUAL_HEX32(ref_reverse(c, bits), actag_code_reverse_scalar(c, bits));
            TEST_ASSERT_EQUAL_HEX32(ref_mirror(c, bits), actag_code_mirror(c, bits));
            TEST_ASSERT_EQUAL_HEX32(ref_mirror(c, bits), actag_code_mirror_scalar(c, bits));
        }
}

int main(void)
{
#if defined(__SSE2__) && !defined(ACTAG_NO_SIMD)
    printf("test_family_paths: the library's SSE2 matcher compared with the plain C copy and the former code\n");
#else
    printf("test_family_paths: no SSE2 in this build: the library's plain C compared with its copy and the former code\n");
#endif
    UNITY_BEGIN();
    RUN_TEST(test_reverse_and_mirror);
    RUN_TEST(test_soft_paths_builtin_families);
    RUN_TEST(test_soft_paths_made_up_families);
    RUN_TEST(test_hard_paths);
    return UNITY_END();
}
