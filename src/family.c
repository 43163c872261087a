/* Family look-up, code orientation helpers and the orientation-aware matcher. */
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
    if (name == NULL || out == NULL)
        return ACTAG_ERR_NULL;
    for (i = 0; i < n; i++) {
        if (fill(i, out) == ACTAG_OK && strcmp(out->name, name) == 0)
            return ACTAG_OK;
    }
    return ACTAG_ERR_FAMILY;
}

int actag_family_validate(const actag_family *family)
{
    if (family == NULL)
        return ACTAG_ERR_NULL;
    if (family->codes == NULL || family->bits < 16 || family->bits > 32 || family->bits % 4 != 0 ||
        family->hamming < 1 || family->ncodes < 1)
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

/* Shared matcher: norient is 4 (rotations) or 8 (rotations and reversals). */
static int match_orientations(const actag_family *family, uint32_t observed, int max_corrections,
                              int norient, actag_match *out)
{
    uint32_t obs[8];
    int o, i, best = 1 << 30;
    int maxc, rc = actag_family_validate(family);
    if (out == NULL)
        return ACTAG_ERR_NULL;
    if (rc != ACTAG_OK)
        return rc;
    maxc = actag_family_max_corrections(family);
    if (max_corrections < 0 || max_corrections > maxc)
        return ACTAG_ERR_CORRECTIONS;
    /* Undo the orientation on the observation instead of transforming the
     * whole table: observed == rot^r(c)  <=>  rot^-r(observed) == c, and
     * observed == rev(rot^r(c))   <=>  rot^-r(rev(observed)) == c. */
    {
        uint32_t w = observed & actag_code_mask(family->bits);
        uint32_t rv = actag_code_reverse(w, family->bits);
        for (o = 0; o < 4; o++) {
            uint32_t a = w, b = rv;
            int s;
            for (s = 0; s < (4 - o) % 4; s++) { /* rot^-o == rot^(4-o) */
                a = actag_code_rot90(a, family->bits);
                b = actag_code_rot90(b, family->bits);
            }
            obs[o] = a;
            obs[4 + o] = b;
        }
    }
    for (i = 0; i < family->ncodes; i++) {
        uint32_t c = family->codes[i];
        for (o = 0; o < norient; o++) {
            int d = actag_popcount32(c ^ obs[o]);
            if (d < best) {
                best = d;
                out->id = i;
                out->rotation = o & 3;
                out->mirrored = o >> 2;
                out->hamming = d;
            }
        }
        if (best == 0)
            break;
    }
    if (best > max_corrections)
        return ACTAG_ERR_NO_MATCH;
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
