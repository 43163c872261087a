/* Guaranteed distances of every built-in family by brute force over all
 * pairs of codes and all orientations (docs/families.md's table):
 *   rot   the 4 rotations, all bits
 *   rev   rotations and full reversals (the published rule), all bits
 *   phys  rotations and the physical mirror P, all bits
 *   dec   rotations and P over the default decoder's cells (all but the 4
 *         corner cells of the data ring)
 *   ophys, odec  phys and dec between different IDs only (the nearest
 *         other ID; the and SPEC's "closest pair of different codes")
 * A family's distance is the minimum over all pairs of different views
 * (code i in orientation g, code j in orientation g'), the same code's own
 * views included (they must differ too, or the rotation or handedness of a
 * reading is undecided). Every mirror-safe family (AcTag<bits>m<h>) must
 * reach its hamming in all of them; the published ones must reach it under
 * their own rule (rev) and keep the measured values below. */
#include "unity.h"
#include "test_util.h"

#include "actag/family.h"

void setUp(void) {}
void tearDown(void) {}

/* Written independently of the library: sequence position s of a word w is
 * bit (bits-1-s). */
static uint32_t seqbit(uint32_t w, int bits, int s) { return (w >> (bits - 1 - s)) & 1u; }
static uint32_t setseq(int bits, int s) { return 1u << (bits - 1 - s); }

/* View g (0..7) of w: rotation by g&3 quarter turns (sequence s <- s+k),
 * then for g >= 4 the mirror: mode 0 reverse (s <- bits-1-s), 1 P (s <- -s). */
static uint32_t view(uint32_t w, int bits, int g, int mode)
{
    int k = bits / 4, s;
    uint32_t r = 0, m = 0;
    for (s = 0; s < bits; s++)
        if (seqbit(w, bits, (s + (g & 3) * k) % bits))
            r |= setseq(bits, s);
    if (g < 4)
        return r;
    for (s = 0; s < bits; s++) {
        int src = mode == 0 ? bits - 1 - s : (bits - s) % bits;
        if (seqbit(r, bits, src))
            m |= setseq(bits, s);
    }
    return m;
}

static int pop(uint32_t v)
{
    static const unsigned char t[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};
    int n = 0;
    for (; v; v >>= 4)
        n += t[v & 15u];
    return n;
}

static uint32_t corner_mask(int bits)
{
    int j;
    uint32_t m = 0;
    for (j = 0; j < 4; j++)
        m |= setseq(bits, j * (bits / 4));
    return m;
}

typedef struct {
    int rot, rev, phys, ophys, dec, other;
} dists;

#define NOCODE 99

/* Brute force. full: every pair of codes in all 8 x 8 orientation pairs;
 * otherwise code i in its own orientation against the 8 orientations of
 * code j (the same minimum, because every view set here is a group and the
 * counted cells are invariant under it; checked against full below). */
static dists measure(const actag_family *f, int full)
{
    static uint32_t v[3][8][9000]; /* [mode: 0 rev, 1 P][view][id] */
    dists d = {NOCODE, NOCODE, NOCODE, NOCODE, NOCODE, NOCODE};
    uint32_t all = actag_code_mask(f->bits), keep = all & ~corner_mask(f->bits);
    int i, j, g, h, n = f->ncodes;
    TEST_ASSERT_TRUE(n <= 9000);
    for (i = 0; i < n; i++)
        for (g = 0; g < 8; g++) {
            v[0][g][i] = view(f->codes[i], f->bits, g, 0);
            v[1][g][i] = view(f->codes[i], f->bits, g, 1);
        }
    for (i = 0; i < n; i++)
        for (j = i; j < n; j++)
            for (g = 0; g < (full ? 8 : 1); g++)
                for (h = 0; h < 8; h++) {
                    int x;
                    if (i == j && g == h)
                        continue;
                    if (g < 4 && h < 4) {
                        x = pop(v[0][g][i] ^ v[0][h][j]);
                        if (x < d.rot)
                            d.rot = x;
                    }
                    x = pop((v[0][g][i] ^ v[0][h][j]) & all);
                    if (x < d.rev)
                        d.rev = x;
                    x = pop((v[1][g][i] ^ v[1][h][j]) & all);
                    if (x < d.phys)
                        d.phys = x;
                    if (i != j && x < d.ophys)
                        d.ophys = x;
                    x = pop((v[1][g][i] ^ v[1][h][j]) & keep);
                    if (x < d.dec)
                        d.dec = x;
                    if (i != j && x < d.other)
                        d.other = x;
                }
    return d;
}

/* Measured once by this brute force; docs/families.md quotes them
 * (NOCODE: a one-code family has no other ID). */
static const struct {
    const char *name;
    int ncodes;
    dists d;
} expected[] = {
    {"AcTag24h4", 6261, {4, 4, 0, 0, 0, 0}},
    {"AcTag24h6", 453, {6, 6, 2, 2, 1, 1}},
    {"AcTag24h8", 45, {8, 8, 2, 4, 2, 3}},
    {"AcTag24h10", 7, {10, 10, 6, 8, 4, 5}},
    {"AcTag24m4", 661, {4, 0, 4, 4, 4, 4}},
    {"AcTag24m6", 51, {6, 2, 6, 6, 6, 6}},
    {"AcTag24m8", 9, {8, 4, 8, 8, 8, 8}},
    {"AcTag24m10", 1, {12, 8, 12, NOCODE, 10, NOCODE}},
    {"AcTag28m4", 8910, {4, 0, 4, 4, 4, 4}},
    {"AcTag28m6", 515, {6, 2, 6, 6, 6, 6}},
    {"AcTag28m8", 48, {8, 0, 8, 8, 8, 8}},
    {"AcTag28m10", 6, {10, 8, 10, 10, 10, 10}},
};

static void print_row(const actag_family *f, dists d)
{
    printf("| %s | %d | %d | %d | %d | %d | %d | %d |\n", f->name, f->ncodes, d.rot, d.rev, d.phys,
           d.ophys, d.dec, d.other);
}

static void test_view_helpers_agree_with_library(void)
{
    int bits, t;
    tu_seed(11);
    for (bits = 16; bits <= 32; bits += 4) {
        TEST_ASSERT_EQUAL_HEX32(corner_mask(bits), actag_code_corners(bits));
        for (t = 0; t < 500; t++) {
            uint32_t w = tu_rand() & actag_code_mask(bits);
            TEST_ASSERT_EQUAL_HEX32(view(w, bits, 4, 1), actag_code_mirror(w, bits));
            TEST_ASSERT_EQUAL_HEX32(view(w, bits, 4, 0), actag_code_reverse(w, bits));
            TEST_ASSERT_EQUAL_HEX32(view(w, bits, 1, 0), actag_code_rot90(w, bits));
            TEST_ASSERT_EQUAL_HEX32(w, actag_code_mirror(actag_code_mirror(w, bits), bits));
            /* P keeps position 0 and swaps s with bits - s */
            TEST_ASSERT_EQUAL_UINT32(seqbit(w, bits, 0), seqbit(actag_code_mirror(w, bits), bits, 0));
            TEST_ASSERT_EQUAL_UINT32(seqbit(w, bits, 1),
                                     seqbit(actag_code_mirror(w, bits), bits, bits - 1));
        }
    }
    TEST_ASSERT_EQUAL_HEX32(0x820820u, actag_code_corners(24)); /* positions 0, 6, 12, 18 */
}

static void test_rule_fields(void)
{
    int i, n = actag_family_count(), seen_m = 0;
    for (i = 0; i < n; i++) {
        actag_family f;
        int bits, h, used = 0;
        char c;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get_at(i, &f));
        TEST_ASSERT_EQUAL_INT(3, sscanf(f.name, "AcTag%d%c%d%n", &bits, &c, &h, &used));
        TEST_ASSERT_EQUAL_INT((int)strlen(f.name), used);
        TEST_ASSERT_EQUAL_INT(bits, f.bits);
        TEST_ASSERT_EQUAL_INT(h, f.hamming);
        if (c == 'h') {
            TEST_ASSERT_EQUAL_INT(ACTAG_MIRROR_REVERSE, f.mirror);
            TEST_ASSERT_EQUAL_HEX32(0u, f.excluded);
        } else if (c == 'm') {
            TEST_ASSERT_EQUAL_INT(ACTAG_MIRROR_PHYSICAL, f.mirror);
            TEST_ASSERT_EQUAL_HEX32(corner_mask(bits), f.excluded);
            seen_m++;
        } else {
            TEST_ASSERT_EQUAL_INT('p', c);
            TEST_ASSERT_EQUAL_INT(ACTAG_MIRROR_PHYSICAL, f.mirror);
            TEST_ASSERT_EQUAL_HEX32(0u, f.excluded);
        }
    }
    if (n >= 12) /* the default ACTAG_FAMILIES */
        TEST_ASSERT_EQUAL_INT(8, seen_m);
}

static void test_distances_of_every_family(void)
{
    int i, e, n = actag_family_count();
    printf("| family | codes | rot | rev | phys | other ID (phys) | dec | other ID (dec) |\n");
    for (i = 0; i < n; i++) {
        actag_family f;
        dists d;
        int found = 0;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get_at(i, &f));
        if (TU_EMULATED && f.ncodes > 1000) { /* n^2 pairs: 10-20 s each under QEMU */
            printf("%s: %d codes, measured in the host suite only\n", f.name, f.ncodes);
            continue;
        }
        d = measure(&f, f.ncodes <= 1000);
        if (f.ncodes <= 1000 && f.ncodes > 1) { /* the reduction is exact */
            dists r = measure(&f, 0);
            TEST_ASSERT_EQUAL_INT(d.rot, r.rot);
            TEST_ASSERT_EQUAL_INT(d.rev, r.rev);
            TEST_ASSERT_EQUAL_INT(d.phys, r.phys);
            TEST_ASSERT_EQUAL_INT(d.ophys, r.ophys);
            TEST_ASSERT_EQUAL_INT(d.dec, r.dec);
            TEST_ASSERT_EQUAL_INT(d.other, r.other);
        }
        print_row(&f, d);
        /* every family keeps its distance under its own rule */
        if (f.mirror == ACTAG_MIRROR_REVERSE && f.excluded == 0u)
            TEST_ASSERT_GREATER_OR_EQUAL(f.hamming, d.rev);
        if (f.mirror == ACTAG_MIRROR_PHYSICAL && f.excluded == 0u)
            TEST_ASSERT_GREATER_OR_EQUAL(f.hamming, d.phys);
        if (f.mirror == ACTAG_MIRROR_PHYSICAL && f.excluded == actag_code_corners(f.bits)) {
            /* mirror-safe: the distance holds for every view a sonar gives,
             * over the cells the default decoder reads, hence everywhere */
            TEST_ASSERT_GREATER_OR_EQUAL(f.hamming, d.dec);
            TEST_ASSERT_GREATER_OR_EQUAL(f.hamming, d.phys);
            TEST_ASSERT_GREATER_OR_EQUAL(f.hamming, d.rot);
        }
        for (e = 0; e < (int)(sizeof expected / sizeof expected[0]); e++)
            if (strcmp(expected[e].name, f.name) == 0) {
                found = 1;
                TEST_ASSERT_EQUAL_INT_MESSAGE(expected[e].ncodes, f.ncodes, f.name);
                TEST_ASSERT_EQUAL_INT_MESSAGE(expected[e].d.rot, d.rot, f.name);
                TEST_ASSERT_EQUAL_INT_MESSAGE(expected[e].d.rev, d.rev, f.name);
                TEST_ASSERT_EQUAL_INT_MESSAGE(expected[e].d.phys, d.phys, f.name);
                TEST_ASSERT_EQUAL_INT_MESSAGE(expected[e].d.ophys, d.ophys, f.name);
                TEST_ASSERT_EQUAL_INT_MESSAGE(expected[e].d.dec, d.dec, f.name);
                TEST_ASSERT_EQUAL_INT_MESSAGE(expected[e].d.other, d.other, f.name);
            }
        if (!found) /* families outside the default list have no expectations */
            printf("%s: not in the table of expected distances\n", f.name);
    }
}

/* The brute force sees a defect: a family with two mirror images of each
 * other, or a symmetric code, or two codes closer than claimed. */
static void test_brute_force_catches_bad_families(void)
{
    static uint32_t codes[3];
    actag_family f = {"bad", 24, 4, 2, codes, ACTAG_MIRROR_PHYSICAL, 0u};
    dists d;
    codes[0] = 0xd35f2au;
    codes[1] = actag_code_mirror(actag_code_rot90(0xd35f2au, 24), 24);
    d = measure(&f, 1);
    TEST_ASSERT_EQUAL_INT(0, d.phys);
    TEST_ASSERT_EQUAL_INT(0, d.other);
    TEST_ASSERT_GREATER_THAN(0, d.rot);
    codes[1] = 0xd35f2au ^ 0x000100u; /* one non-corner bit apart */
    d = measure(&f, 1);
    TEST_ASSERT_EQUAL_INT(1, d.dec);
    codes[1] = 0xd35f2au ^ 0x800000u; /* only a corner bit apart */
    d = measure(&f, 1);
    TEST_ASSERT_EQUAL_INT(1, d.phys);
    TEST_ASSERT_EQUAL_INT(0, d.dec);
    f.ncodes = 1;
    codes[0] = 0xffffffu; /* symmetric: its views coincide */
    d = measure(&f, 1);
    TEST_ASSERT_EQUAL_INT(0, d.rot);
    TEST_ASSERT_EQUAL_INT(NOCODE, d.other);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_view_helpers_agree_with_library);
    RUN_TEST(test_rule_fields);
    RUN_TEST(test_brute_force_catches_bad_families);
    RUN_TEST(test_distances_of_every_family);
    return UNITY_END();
}
