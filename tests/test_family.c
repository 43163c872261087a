/* Family tables and matcher: published codes, orientation algebra, matching
 * in all 8 orientations with bit flips, rejection beyond the limit. */
#include "unity.h"
#include "test_util.h"

#include "actag/families.h"
#include "actag/family.h"

#include <math.h>
#include <string.h>

void setUp(void) {}
void tearDown(void) {}

static const char *const names[4] = {"AcTag24h4", "AcTag24h6", "AcTag24h8", "AcTag24h10"};
static const int sizes[4] = {6261, 453, 45, 7};

/* Brute-force references written independently of the library. */
static uint32_t ref_seq_rot(uint32_t w, int bits) /* sequence index i -> i+k */
{
    int k = bits / 4, i;
    uint32_t r = 0;
    for (i = 0; i < bits; i++) {
        int src = (i + k) % bits; /* rot90(w) sequence[i] = w sequence[i+k] */
        uint32_t bit = (w >> (bits - 1 - src)) & 1u;
        r |= bit << (bits - 1 - i);
    }
    return r;
}
static uint32_t ref_rev(uint32_t w, int bits)
{
    uint32_t r = 0;
    int i;
    for (i = 0; i < bits; i++)
        if (w & (1u << i))
            r |= 1u << (bits - 1 - i);
    return r;
}

static void test_builtin_families_match_published(void)
{
    static uint32_t pub[7000];
    char path[512];
    int f, i;
    TEST_ASSERT_GREATER_OR_EQUAL(4, actag_family_count());
    for (f = 0; f < 4; f++) {
        actag_family fam;
        int n;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get(names[f], &fam));
        TEST_ASSERT_EQUAL_STRING(names[f], fam.name);
        TEST_ASSERT_EQUAL_INT(24, fam.bits);
        TEST_ASSERT_EQUAL_INT(sizes[f], fam.ncodes);
        TEST_ASSERT_EQUAL_HEX32(0xd35f2a, fam.codes[0]);
        snprintf(path, sizeof path, "%s/families/%s.txt", TU_DATA, names[f]);
        n = tu_read_codes(path, pub, 7000);
        TEST_ASSERT_EQUAL_INT(sizes[f], n);
        for (i = 0; i < n; i++)
            TEST_ASSERT_EQUAL_HEX32(pub[i], fam.codes[i]);
    }
}

/* actag/families.h: each accessor fills exactly what the name look-up does. */
static void check_accessor(int (*get)(actag_family *), const char *name)
{
    actag_family a, b;
    memset(&a, 0x5a, sizeof a); /* every field must be written */
    memset(&b, 0xa5, sizeof b);
    TEST_ASSERT_EQUAL_INT_MESSAGE(ACTAG_OK, get(&a), name);
    TEST_ASSERT_EQUAL_INT_MESSAGE(ACTAG_OK, actag_family_get(name, &b), name);
    TEST_ASSERT_EQUAL_STRING(b.name, a.name);
    TEST_ASSERT_EQUAL_INT(b.bits, a.bits);
    TEST_ASSERT_EQUAL_INT(b.hamming, a.hamming);
    TEST_ASSERT_EQUAL_INT(b.ncodes, a.ncodes);
    TEST_ASSERT_TRUE(a.codes == b.codes);
    TEST_ASSERT_EQUAL_INT(b.mirror, a.mirror);
    TEST_ASSERT_EQUAL_HEX32(b.excluded, a.excluded);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, get(NULL));
}

static void test_direct_accessors_equal_lookup(void)
{
    int checked = 0;
#define CHECK_FAMILY(name)                                                                     \
    do {                                                                                       \
        check_accessor(actag_family_##name, #name);                                            \
        checked++;                                                                             \
    } while (0)
#ifdef ACTAG_HAVE_AcTag24h4
    CHECK_FAMILY(AcTag24h4);
#endif
#ifdef ACTAG_HAVE_AcTag24h10
    CHECK_FAMILY(AcTag24h10);
#endif
#ifdef ACTAG_HAVE_AcTag24m4
    CHECK_FAMILY(AcTag24m4);
#endif
#ifdef ACTAG_HAVE_AcTag24m10
    CHECK_FAMILY(AcTag24m10);
#endif
#ifdef ACTAG_HAVE_AcTag28m4
    CHECK_FAMILY(AcTag28m4);
#endif
#ifdef ACTAG_HAVE_AcTag28m8
    CHECK_FAMILY(AcTag28m8);
#endif
#undef CHECK_FAMILY
    if (checked == 0)
        TEST_IGNORE_MESSAGE("none of the checked families is built in (ACTAG_FAMILIES)");
}

static void test_family_lookup_errors(void)
{
    actag_family fam;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_FAMILY, actag_family_get("AcTag24h5", &fam));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_FAMILY, actag_family_get("", &fam));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_family_get(NULL, &fam));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_family_get("AcTag24h10", NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_FAMILY, actag_family_get_at(-1, &fam));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_FAMILY, actag_family_get_at(actag_family_count(), &fam));
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get_at(actag_family_count() - 1, &fam));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_family_max_corrections(NULL));
}

static void test_max_corrections(void)
{
    actag_family fam = {"x", 24, 4, 1, NULL, ACTAG_MIRROR_REVERSE, 0u};
    int h;
    for (h = 1; h <= 12; h++) {
        fam.hamming = h;
        TEST_ASSERT_EQUAL_INT(h % 2 == 0 ? h / 2 - 1 : h / 2, actag_family_max_corrections(&fam));
    }
}

static void test_rotation_reverse_algebra(void)
{
    int bits, t;
    tu_seed(1);
    for (bits = 16; bits <= 32; bits += 4) {
        uint32_t mask = actag_code_mask(bits);
        for (t = 0; t < 2000; t++) {
            uint32_t w = tu_rand() & mask, r = w;
            int j;
            for (j = 0; j < 4; j++) {
                TEST_ASSERT_EQUAL_HEX32(ref_seq_rot(r, bits), actag_code_rot90(r, bits));
                r = actag_code_rot90(r, bits);
            }
            TEST_ASSERT_EQUAL_HEX32(w, r); /* rot90^4 == id */
            TEST_ASSERT_EQUAL_HEX32(ref_rev(w, bits), actag_code_reverse(w, bits));
            TEST_ASSERT_EQUAL_HEX32(w, actag_code_reverse(actag_code_reverse(w, bits), bits));
            /* reverse o rot90 == rot90^-1 o reverse (rot90^-1 == rot90^3) */
            {
                uint32_t lhs = actag_code_reverse(actag_code_rot90(w, bits), bits);
                uint32_t rhs = actag_code_reverse(w, bits);
                for (j = 0; j < 3; j++)
                    rhs = actag_code_rot90(rhs, bits);
                TEST_ASSERT_EQUAL_HEX32(lhs, rhs);
            }
            TEST_ASSERT_EQUAL_INT(tu_popcount(w), actag_popcount32(w));
        }
    }
    TEST_ASSERT_EQUAL_HEX32(0xffffffffu, actag_code_mask(32));
    TEST_ASSERT_EQUAL_INT(32, actag_popcount32(0xffffffffu));
}

static uint32_t orient(uint32_t c, int rot, int mir, int bits)
{
    int j;
    for (j = 0; j < rot; j++)
        c = ref_seq_rot(c, bits);
    return mir ? ref_rev(c, bits) : c;
}

static uint32_t flip_bits(uint32_t w, int nflips, int bits)
{
    uint32_t flipped = 0;
    while (nflips > 0) {
        uint32_t b = 1u << (tu_rand() % (uint32_t)bits);
        if (flipped & b)
            continue;
        flipped |= b;
        nflips--;
    }
    return w ^ flipped;
}

static void test_every_code_every_orientation(void)
{
    int f, id, o;
    if (TU_EMULATED)
        TEST_MESSAGE("emulated: every 16th code of AcTag24h4 (the host suite: all)");
    tu_seed(2);
    for (f = 0; f < 4; f++) {
        actag_family fam;
        int maxc;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get(names[f], &fam));
        maxc = actag_family_max_corrections(&fam);
        for (id = 0; id < fam.ncodes; id += fam.ncodes > 1000 ? TU_STEP(16) : 1) {
            for (o = 0; o < 8; o++) {
                actag_match m;
                int nflips = tu_range(0, maxc);
                uint32_t w = flip_bits(orient(fam.codes[id], o & 3, o >> 2, 24), nflips, 24);
                TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_match(&fam, w, maxc, &m));
                TEST_ASSERT_EQUAL_INT(id, m.id);
                TEST_ASSERT_EQUAL_INT(o & 3, m.rotation);
                TEST_ASSERT_EQUAL_INT(o >> 2, m.mirrored);
                TEST_ASSERT_EQUAL_INT(nflips, m.hamming);
                if (o < 4) {
                    TEST_ASSERT_EQUAL_INT(ACTAG_OK,
                                          actag_family_match_rotations(&fam, w, maxc, &m));
                    TEST_ASSERT_EQUAL_INT(id, m.id);
                    TEST_ASSERT_EQUAL_INT(o, m.rotation);
                    TEST_ASSERT_EQUAL_INT(0, m.mirrored);
                }
            }
        }
    }
}

/* Random words: the matcher agrees with a brute-force minimum distance. */
static void test_random_words_against_brute_force(void)
{
    int f, t;
    tu_seed(3);
    for (f = 1; f < 4; f++) { /* h6, h8, h10: brute force stays fast */
        actag_family fam;
        int maxc, rejected = 0, accepted = 0;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get(names[f], &fam));
        maxc = actag_family_max_corrections(&fam);
        for (t = 0; t < TU_TRIALS(3000, 6); t++) {
            uint32_t w;
            int best = 99, id, o, rc;
            actag_match m;
            if (t % 2 == 0) { /* near a code: exercises the boundary at maxc and maxc+1 */
                /* one draw per declarator: a fixed order (the x86-64 build's
                 * order when they were call arguments: the last one first) */
                int nfl = tu_range(0, maxc + 2), mir = tu_range(0, 1);
                int rot = tu_range(0, 3), cid = tu_range(0, fam.ncodes - 1);
                w = flip_bits(orient(fam.codes[cid], rot, mir, 24), nfl, 24);
            } else
                w = tu_rand() & 0xffffffu;
            for (id = 0; id < fam.ncodes; id++)
                for (o = 0; o < 8; o++) {
                    int d = tu_popcount(w ^ orient(fam.codes[id], o & 3, o >> 2, 24));
                    if (d < best)
                        best = d;
                }
            rc = actag_family_match(&fam, w, maxc, &m);
            if (best > maxc) {
                TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, rc);
                rejected++;
            } else {
                TEST_ASSERT_EQUAL_INT(ACTAG_OK, rc);
                TEST_ASSERT_EQUAL_INT(best, m.hamming);
                TEST_ASSERT_EQUAL_INT(m.hamming, tu_popcount(w ^ orient(fam.codes[m.id], m.rotation,
                                                                    m.mirrored, 24)));
                accepted++;
            }
        }
        TEST_ASSERT_GREATER_THAN(TU_TRIALS(3000, 6) / 30, rejected); /* host: 100 */
        TEST_ASSERT_GREATER_THAN(TU_TRIALS(3000, 6) / 30, accepted);
    }
}

/* The physical reflection P: sequence position s takes position -s mod bits. */
static uint32_t ref_P(uint32_t w, int bits)
{
    uint32_t r = 0;
    int s;
    for (s = 0; s < bits; s++)
        if ((w >> (bits - 1 - s)) & 1u)
            r |= 1u << (bits - 1 - (bits - s) % bits);
    return r;
}

/* Readings that tie in soft cost rank by fewer disagreeing bits (family.h),
 * and the matcher's pruning must not skip them: confidences of weight 0
 * (|c| 0.001) carrying a code's signs cost 0 for every reading, so the best
 * is that code at hamming 0, for every code of the family and every view
 * of it. (The pruning skipped a reading whose least cost equalled the
 * runner-up's: code 5 of AcTag24h10 came out as code 0 at hamming 13.) */
static void test_soft_match_ties_rank_by_fewer_bits(void)
{
    int f;
    for (f = 1; f < 4; f++) {
        actag_family fam;
        int id;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get(names[f], &fam));
        for (id = 0; id < fam.ncodes; id += 1 + fam.ncodes / 40) {
            int rot;
            for (rot = 0; rot < 4; rot++) {
                uint32_t c = orient(fam.codes[id], rot, 0, 24);
                float conf[24];
                actag_soft_match r;
                int i;
                for (i = 0; i < 24; i++)
                    conf[i] = ((c >> (23 - i)) & 1u) ? 0.001f : -0.001f;
                TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_match_soft(&fam, conf, 0xffffffu, &r));
                TEST_ASSERT_EQUAL_INT(0, r.d1);
                TEST_ASSERT_EQUAL_INT(0, r.best.hamming);
                TEST_ASSERT_EQUAL_INT(id, r.best.id);
                TEST_ASSERT_EQUAL_INT(rot, r.best.rotation);
                TEST_ASSERT_EQUAL_INT(0, r.best.mirrored);
            }
        }
    }
}

/* actag_family_match_soft against a brute force over all codes and the 8
 * physical views: best, d1, d2, other and h2, with every bit, all but the
 * corner bits or any bits of the reading kept; the list top[]: the best two
 * exact, the rest real readings in order, each no better than the true
 * reading of its rank (family.h: top[2 ..] may miss readings); with equal
 * confidences the best is the hard (Hamming) match. (A keep that differs
 * between views was applied in the code's order, and readings that should
 * win were pruned: 359 of 20,000 random cases.) */
static void test_soft_match_against_brute_force(void)
{
    int f, t;
    for (f = 1; f < 4; f++) {
        actag_family fam;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get(names[f], &fam));
        for (t = 0; t < TU_TRIALS(400, 8); t++) {
            float conf[24];
            int q[24], i, id, v, equal = t % 4 == 0;
            uint32_t keep = t % 3 == 1   ? 0xffffffu & ~actag_code_corners(24)
                            : t % 3 == 2 ? (uint32_t)tu_range(0, 0xffffff) | 1u
                                         : 0xffffffu,
                     w = 0;
            int bd = 1 << 30, bh = 0, bid = -1, bv = -1, d2 = 1 << 28, other = 33, h2 = 33;
            /* the ACTAG_SOFT_TOP best readings (d, h), ranked as the
             * matcher ranks them (ties keep scan order: ID, then view), and
             * how many readings there are */
            int rd[ACTAG_SOFT_TOP], rh[ACTAG_SOFT_TOP], nr = 0, nk = 0, j;
            actag_soft_match r;
            /* all views (the plain matcher), one handedness, or any other mask */
            static const unsigned masks[3] = {ACTAG_VIEWS_ALL, ACTAG_VIEWS_UNMIRRORED,
                                              ACTAG_VIEWS_MIRRORED};
            unsigned views = t % 5 < 3 ? masks[t % 5] : (unsigned)tu_range(1, 255);
            int id0 = tu_range(0, fam.ncodes - 1), rot0 = tu_range(0, 3);
            uint32_t c0 = orient(fam.codes[id0], rot0, 0, 24);
            if (tu_range(0, 1))
                c0 = ref_P(c0, 24);
            c0 = flip_bits(c0, tu_range(0, 4), 24);
            for (i = 0; i < 24; i++) {
                int a = equal ? 8 : tu_range(0, 20); /* 17..20: clamped to 16 */
                q[i] = a > 16 ? 16 : a;
                conf[i] = ((c0 >> (23 - i)) & 1u ? 1.0f : -1.0f) * (float)a / 16.0f;
                if (a == 0)
                    conf[i] = ((c0 >> (23 - i)) & 1u) ? 0.001f : -0.001f;
                if (conf[i] > 0.0f)
                    w |= 1u << (23 - i);
            }
            if (views == ACTAG_VIEWS_ALL)
                TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_match_soft(&fam, conf, keep, &r));
            else
                TEST_ASSERT_EQUAL_INT(ACTAG_OK,
                                      actag_family_match_soft_views(&fam, conf, keep, views, &r));
            for (id = 0; id < fam.ncodes; id++)
                for (v = 0; v < 8; v++) {
                    uint32_t e = orient(fam.codes[id], v & 3, 0, 24), mis;
                    int d = 0, h;
                    if (!(views & (1u << v)))
                        continue; /* not a hypothesis */
                    if (v >> 2)
                        e = ref_P(e, 24);
                    mis = (e ^ w) & keep; /* the reading's kept bits */
                    h = tu_popcount(mis);
                    for (i = 0; i < 24; i++)
                        if ((mis >> (23 - i)) & 1u)
                            d += q[i];
                    nr++;
                    j = nk < ACTAG_SOFT_TOP ? nk++ : ACTAG_SOFT_TOP;
                    while (j > 0 && (rd[j - 1] > d || (rd[j - 1] == d && rh[j - 1] > h))) {
                        if (j < ACTAG_SOFT_TOP) {
                            rd[j] = rd[j - 1];
                            rh[j] = rh[j - 1];
                        }
                        j--;
                    }
                    if (j < ACTAG_SOFT_TOP) {
                        rd[j] = d;
                        rh[j] = h;
                    }
                    if (d < bd || (d == bd && h < bh)) {
                        if (bid >= 0)
                            d2 = bd;
                        bd = d;
                        bh = h;
                        bid = id;
                        bv = v;
                    } else if (d < d2) {
                        d2 = d;
                    }
                }
            for (id = 0; id < fam.ncodes; id++)
                for (v = 0; v < 8; v++) {
                    uint32_t e = orient(fam.codes[id], v & 3, 0, 24);
                    int h;
                    if (!(views & (1u << v)))
                        continue;
                    if (v >> 2)
                        e = ref_P(e, 24);
                    h = tu_popcount((e ^ w) & keep);
                    if ((v >> 2) != (bv >> 2) && h < other)
                        other = h;
                    if (!(id == bid && v == bv) && h < h2)
                        h2 = h;
                }
            TEST_ASSERT_EQUAL_INT(bid, r.best.id);
            TEST_ASSERT_EQUAL_INT(bv & 3, r.best.rotation);
            TEST_ASSERT_EQUAL_INT(bv >> 2, r.best.mirrored);
            TEST_ASSERT_EQUAL_INT(bh, r.best.hamming);
            TEST_ASSERT_EQUAL_INT(bd, r.d1);
            TEST_ASSERT_EQUAL_INT(d2, r.d2);
            TEST_ASSERT_EQUAL_INT(other, r.other);
            TEST_ASSERT_EQUAL_INT(h2, r.h2);
            if (equal) /* equal weights: the soft distance is 8 per mismatched bit */
                TEST_ASSERT_EQUAL_INT(8 * r.best.hamming, r.d1);
            TEST_ASSERT_TRUE(r.ntop >= (nr < 2 ? nr : 2) && r.ntop <= ACTAG_SOFT_TOP && r.ntop <= nr);
            for (j = 0; j < r.ntop; j++) {
                if (j < 2) { /* exact */
                    TEST_ASSERT_EQUAL_INT(rd[j], r.top[j].d);
                    TEST_ASSERT_EQUAL_INT(rh[j], r.top[j].h);
                } else { /* in order, no better than the true j-th */
                    TEST_ASSERT_TRUE(r.top[j].d >= rd[j]);
                    TEST_ASSERT_TRUE(r.top[j].d > r.top[j - 1].d ||
                                     (r.top[j].d == r.top[j - 1].d && r.top[j].h >= r.top[j - 1].h));
                }
            }
        }
    }
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_family_match_soft(NULL, NULL, 0u, NULL));
    {
        actag_family fam;
        actag_soft_match r;
        float conf[24] = {0};
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM,
                              actag_family_match_soft_views(&fam, conf, 0xffffffu, 0u, &r));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, /* only bits above the 8 views */
                              actag_family_match_soft_views(&fam, conf, 0xffffffu, 0x100u, &r));
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_family_match_soft_views(
                                                  &fam, NULL, 0xffffffu, ACTAG_VIEWS_ALL, &r));
    }
}

static void test_match_errors(void)
{
    actag_family fam;
    actag_match m;
    actag_family bad = {"bad", 24, 4, 0, NULL, ACTAG_MIRROR_REVERSE, 0u};
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_CORRECTIONS, actag_family_match(&fam, 0, 5, &m));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_CORRECTIONS, actag_family_match(&fam, 0, -1, &m));
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_match(&fam, fam.codes[3], 4, &m));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_family_match(NULL, 0, 0, &m));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_family_match(&fam, 0, 0, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_FAMILY, actag_family_match(&bad, 0, 0, &m));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_FAMILY, actag_family_validate(&bad));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, actag_family_match(&fam, 0, 0, &m));
}

/* Outputs are written only on success (they were filled on ACTAG_ERR_NO_MATCH
 * and, for an unknown name, with the last family tried), and NaN
 * confidences weigh 0 (their conversion to int was undefined). */
static void test_outputs_untouched_on_errors(void)
{
    actag_family fam, f2;
    actag_match m, m0;
    actag_soft_match sm;
    float conf[24];
    int i, j;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
    memset(&f2, 0x5b, sizeof f2);
    memcpy(&m0, &f2, sizeof m0);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_FAMILY, actag_family_get("AcTag24h11", &f2));
    for (i = 0; i < (int)sizeof f2; i++)
        TEST_ASSERT_EQUAL_HEX8(0x5b, ((const unsigned char *)&f2)[i]);
    memset(&m, 0x5b, sizeof m);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, actag_family_match(&fam, 0, 0, &m));
    TEST_ASSERT_EQUAL_MEMORY(&m0, &m, sizeof m);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_MATCH, actag_family_match_rotations(&fam, 0, 0, &m));
    TEST_ASSERT_EQUAL_MEMORY(&m0, &m, sizeof m);
    /* NaN confidences: as 0 (no evidence), so all-NaN reads like all-zero */
    for (j = 0; j < 2; j++) {
        actag_soft_match ref;
        for (i = 0; i < 24; i++)
            conf[i] = j ? 0.0f : (float)NAN;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_match_soft(&fam, conf, 0xffffffu, j ? &ref : &sm));
        if (j) {
            TEST_ASSERT_EQUAL_INT(ref.d1, sm.d1);
            TEST_ASSERT_EQUAL_INT(ref.d2, sm.d2);
            TEST_ASSERT_EQUAL_INT(ref.best.id, sm.best.id);
            TEST_ASSERT_EQUAL_INT(ref.best.hamming, sm.best.hamming);
        }
    }
    /* one NaN among clear confidences: the code is still read */
    for (i = 0; i < 24; i++)
        conf[i] = ((fam.codes[5] >> (23 - i)) & 1u) ? 0.9f : -0.9f;
    conf[7] = (float)NAN;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_match_soft(&fam, conf, 0xffffffu, &sm));
    TEST_ASSERT_EQUAL_INT(5, sm.best.id);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_builtin_families_match_published);
    RUN_TEST(test_family_lookup_errors);
    RUN_TEST(test_direct_accessors_equal_lookup);
    RUN_TEST(test_max_corrections);
    RUN_TEST(test_rotation_reverse_algebra);
    RUN_TEST(test_every_code_every_orientation);
    RUN_TEST(test_random_words_against_brute_force);
    RUN_TEST(test_match_errors);
    RUN_TEST(test_outputs_untouched_on_errors);
    RUN_TEST(test_soft_match_against_brute_force);
    RUN_TEST(test_soft_match_ties_rank_by_fewer_bits);
    return UNITY_END();
}
