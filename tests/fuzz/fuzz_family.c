/*
 * fuzz_family.c -- libFuzzer harness: the family matcher against a brute
 * force oracle.
 *
 * An input picks a built-in family (or builds one from its bytes: any bits,
 * hamming, up to 64 codes, including invalid ones), an observed word, a
 * corrections limit and the matcher (all 8 orientations or rotations only).
 * The oracle, written from the documented definitions (family.h) and not
 * from the implementation:
 *   - rot90 / reverse / mirror / corners / popcount from single bits of the
 *     sequence (rot90: cyclic shift by k towards the MSB; reverse: bit i <->
 *     bits-1-i; mirror: sequence position s -> -s mod bits);
 *   - the closest code in every orientation rot90^r(c) (and reverse() of
 *     it), distance over the family's bits only, ties to the lowest ID, then
 *     the lowest orientation with every unmirrored one first;
 *   - ACTAG_ERR_FAMILY for an invalid family, _NULL for no out, _CORRECTIONS outside
 *     0..max, _NO_MATCH beyond the limit; the out struct untouched on error
 *     (other than _NO_MATCH, whose contents are not specified).
 */
#include "fuzz_util.h"

#include "actag/family.h"

static int ref_bit(uint32_t w, int bits, int s) { return (int)((w >> (bits - 1 - s)) & 1u); }

static uint32_t ref_from_seq(const int *seq, int bits)
{
    uint32_t w = 0;
    int s;
    for (s = 0; s < bits; s++)
        w |= (uint32_t)seq[s] << (bits - 1 - s);
    return w;
}

/* rot90: the sequence moves k positions towards the MSB (position s takes
 * position s + k). */
static uint32_t ref_rot90(uint32_t w, int bits)
{
    int seq[32], s, k = bits / 4;
    for (s = 0; s < bits; s++)
        seq[s] = ref_bit(w, bits, (s + k) % bits);
    return ref_from_seq(seq, bits);
}

static uint32_t ref_reverse(uint32_t w, int bits)
{
    int seq[32], s;
    for (s = 0; s < bits; s++)
        seq[s] = ref_bit(w, bits, bits - 1 - s);
    return ref_from_seq(seq, bits);
}

static uint32_t ref_mirror(uint32_t w, int bits)
{
    int seq[32], s;
    for (s = 0; s < bits; s++)
        seq[s] = ref_bit(w, bits, (bits - s) % bits);
    return ref_from_seq(seq, bits);
}

static int ref_popcount(uint32_t v)
{
    int n = 0;
    while (v) {
        n += (int)(v & 1u);
        v >>= 1;
    }
    return n;
}

static int ref_valid(const actag_family *f)
{
    return f->bits >= 16 && f->bits <= 32 && f->bits % 4 == 0 && f->hamming >= 1 &&
           f->ncodes >= 1 && f->codes != NULL;
}

static int ref_maxc(int h) { return h % 2 == 0 ? h / 2 - 1 : h / 2; }

/* The documented matcher; returns the expected code. Distances are taken
 * on the observation side: rotations and reversal permute bit positions,
 * so d(rot^r(c), w) = d(c, rot^-r(w)) and d(reverse(rot^r(c)), w) =
 * d(c, rot^-r(reverse(w))), with the sequence-level reference functions
 * above (rot^-r = rot^(4-r)). */
static int ref_match(const actag_family *f, uint32_t obs, int maxcorr, int norient,
                     actag_match *m)
{
    static uint8_t pc8[256];
    uint32_t mask, view[8];
    int i, o, best = 1 << 30, maxc;
    if (!pc8[255])
        for (i = 0; i < 256; i++)
            pc8[i] = (uint8_t)ref_popcount((uint32_t)i);
    if (!ref_valid(f))
        return ACTAG_ERR_FAMILY; /* a NULL code table included (ERR_NULL: no family) */
    maxc = ref_maxc(f->hamming);
    if (maxcorr < 0 || maxcorr > maxc)
        return ACTAG_ERR_CORRECTIONS;
    mask = f->bits == 32 ? 0xffffffffu : (1u << f->bits) - 1u;
    for (o = 0; o < 8; o++) {
        uint32_t w = o >= 4 ? ref_reverse(obs & mask, f->bits) : obs & mask;
        int j;
        for (j = 0; j < (4 - (o & 3)) % 4; j++)
            w = ref_rot90(w, f->bits);
        view[o] = w;
    }
    for (i = 0; i < f->ncodes; i++)
        for (o = 0; o < norient; o++) { /* o = 4 * mirrored + rotation */
            uint32_t x = (f->codes[i] ^ view[o]) & mask;
            int d = pc8[x & 255u] + pc8[(x >> 8) & 255u] + pc8[(x >> 16) & 255u] + pc8[x >> 24];
            /* strict <: the first in (id, mirrored, rotation) order wins ties */
            if (d < best) {
                best = d;
                m->id = i;
                m->rotation = o & 3;
                m->mirrored = o >> 2;
                m->hamming = d;
            }
        }
    return best > maxcorr ? ACTAG_ERR_NO_MATCH : ACTAG_OK;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_reader r;
    actag_family fam;
    uint32_t codes[64], obs, mask;
    actag_match got, want, before;
    int sel, nfam = actag_family_count(), maxcorr, norient, rc, want_rc, bits, i, b;

    fz_init(&r, data, size);
    sel = fz_u8(&r);
    if (sel % 2 == 0) {
        FZ_CHECK(actag_family_get_at((sel / 2) % nfam, &fam) == ACTAG_OK, "get_at");
    } else {
        int n = 1 + fz_u8(&r) % 64;
        uint32_t fmask;
        memset(&fam, 0, sizeof fam);
        fam.name = "fuzz";
        fam.bits = fz_int(&r, 24, 16, 32);
        fam.hamming = fz_int(&r, 10, 1, 16);
        fam.ncodes = n;
        fmask = fam.bits >= 32 || fam.bits < 1 ? 0xffffffffu : (1u << fam.bits) - 1u;
        for (i = 0; i < n; i++)
            codes[i] = fz_u32(&r) & fmask; /* codes within the family's bits */
        fam.codes = (fz_u8(&r) == 0xff) ? NULL : codes;
        if (fz_u8(&r) == 0xff)
            fam.ncodes = fz_int(&r, n, -2, n);
        if (fam.ncodes > n)
            fam.ncodes = n; /* never beyond the table (the caller's promise) */
    }
    obs = fz_u32(&r);
    maxcorr = fz_int(&r, 2, -1, 8);
    norient = (fz_u8(&r) & 1) ? 4 : 8;

    /* bit helpers against the sequence definitions, for every bits value */
    for (b = 16; b <= 32; b += 4) {
        uint32_t m = b == 32 ? 0xffffffffu : (1u << b) - 1u, w = obs & m;
        FZ_CHECK(actag_code_mask(b) == m, "mask %d", b);
        FZ_CHECK(actag_code_rot90(w, b) == ref_rot90(w, b), "rot90 %#x bits %d", w, b);
        FZ_CHECK(actag_code_reverse(w, b) == ref_reverse(w, b), "reverse %#x bits %d", w, b);
        FZ_CHECK(actag_code_mirror(w, b) == ref_mirror(w, b), "mirror %#x bits %d", w, b);
        FZ_CHECK(actag_code_mirror(actag_code_mirror(w, b), b) == w, "mirror not an involution");
        {
            uint32_t c = 0;
            int j;
            for (j = 0; j < 4; j++)
                c |= 1u << (b - 1 - j * (b / 4));
            FZ_CHECK(actag_code_corners(b) == c, "corners bits %d", b);
        }
    }
    FZ_CHECK(actag_popcount32(obs) == ref_popcount(obs), "popcount %#x", obs);

    /* the matcher */
    bits = fam.bits;
    mask = bits >= 32 || bits < 1 ? 0xffffffffu : (1u << bits) - 1u;
    memset(&want, 0, sizeof want);
    want_rc = ref_match(&fam, obs & mask, maxcorr, norient, &want);
    memset(&got, 0x5b, sizeof got);
    before = got;
    rc = norient == 8 ? actag_family_match(&fam, obs, maxcorr, &got)
                      : actag_family_match_rotations(&fam, obs, maxcorr, &got);
    FZ_CHECK(rc == want_rc, "match returned %d, oracle %d (bits %d h %d n %d obs %#x maxc %d)", rc,
             want_rc, fam.bits, fam.hamming, fam.ncodes, obs, maxcorr);
    if (rc == ACTAG_OK) {
        FZ_CHECK(got.id == want.id && got.rotation == want.rotation &&
                     got.mirrored == want.mirrored && got.hamming == want.hamming,
                 "match id %d rot %d mir %d ham %d, oracle id %d rot %d mir %d ham %d", got.id,
                 got.rotation, got.mirrored, got.hamming, want.id, want.rotation, want.mirrored,
                 want.hamming);
    } else {
        FZ_CHECK(memcmp(&got, &before, sizeof got) == 0, "out written on error %d", rc);
    }
    FZ_CHECK(actag_family_validate(&fam) == (ref_valid(&fam) ? ACTAG_OK : ACTAG_ERR_FAMILY),
             "validate disagrees");
    FZ_CHECK(actag_family_max_corrections(&fam) == ref_maxc(fam.hamming) ||
                 !ref_valid(&fam),
             "max_corrections");
    /* NULL out */
    FZ_CHECK(actag_family_match(&fam, obs, maxcorr, NULL) == ACTAG_ERR_NULL, "NULL out");
    return 0;
}
