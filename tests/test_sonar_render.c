/* Rendered tags (layout colours: white = foam) through the whole sonar
 * pipeline: every ID of AcTag24h10 and AcTag24h8 and samples of AcTag24h6 and
 * AcTag24h4 (incl. IDs above 2590 and 6000), in all 8 orientations (4
 * rotations, optionally mirrored); the ID, the mirrored flag and the corners
 * in tag order must come back. IDs within 2 bits of another reading over the
 * default decoder's cells (AcTag24h4 has such neighbours, and twins) may give
 * no reading, never a wrong one. */
#include "unity.h"
#include "test_util.h"

#include "actag/actag.h"
#include "actag/render.h"

void setUp(void) {}
void tearDown(void) {}

#define RT_FRAME 160 /* square frame, tag side 7*10 + 2*25 = 120 placed at RT_OFF */
#include "sonar_roundtrip.h"

/* Distance from code `id` (as printed) to the nearest other reading, over
 * the bits the default decoder counts (the data ring's corner cells
 * excluded): every code in its 4 rotations and 4 reflections, except id
 * itself unturned. 0: the decoder cannot tell id from that reading. */
static int decoder_distance(const actag_family *fam, int id)
{
    int bits = fam->bits, k = bits / 4, j, v, i, best = 99;
    uint32_t keep = actag_code_mask(bits), c0 = fam->codes[id];
    for (i = 0; i < 4; i++)
        keep &= ~((uint32_t)1u << (bits - 1 - i * k));
    for (j = 0; j < fam->ncodes; j++) {
        uint32_t w = fam->codes[j];
        for (v = 0; v < 4; v++) {
            for (i = 0; i < 2; i++) {
                uint32_t o = i ? actag_decode_mirror(w, bits) : w;
                int d = actag_popcount32((o ^ c0) & keep);
                if (!(j == id && v == 0 && i == 0) && d < best)
                    best = d;
            }
            w = actag_code_rot90(w, bits);
        }
    }
    return best;
}

static void check_tag(const actag_family *fam, int id)
{
    /* within 2 bits of another reading the likelihood margin may refuse
     * even a clean render (AcTag24h4 needs e^10.8 odds for 6261 codes) */
    rt_check_tag_or_none(fam, id, decoder_distance(fam, id) <= 2);
}

static void test_every_id_of_small_families(void)
{
    static const char *const names[2] = {"AcTag24h10", "AcTag24h8"};
    int f, id;
    for (f = 0; f < 2; f++) {
        actag_family fam;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get(names[f], &fam));
        for (id = 0; id < fam.ncodes; id += fam.ncodes > 10 ? TU_STEP(5) : 1) /* emulated: sampled */
            check_tag(&fam, id);
    }
}

static void test_sampled_ids_of_large_families(void)
{
    static const int h4_ids[] = {0, 1, 777, 2590, 2591, 2592, 4000, 6000, 6260};
    actag_family fam;
    int i;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h6", &fam));
    for (i = 0; i < fam.ncodes; i += 37 * TU_STEP(3)) /* emulated: every 111th */
        check_tag(&fam, i);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h4", &fam));
    for (i = 0; i < (int)(sizeof h4_ids / sizeof h4_ids[0]); i += TU_STEP(3))
        check_tag(&fam, h4_ids[i]);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_every_id_of_small_families);
    RUN_TEST(test_sampled_ids_of_large_families);
    return UNITY_END();
}
