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

#define CELL 10
#define MARGIN 25
#define FRAME 160 /* square frame, tag side 7*10 + 2*25 = 120 placed at OFF */
#define OFF 17

static uint8_t g_ws[ACTAG_WORKSPACE_SIZE(FRAME, FRAME)];

/* Frame geometry whose pixel size matches the tag: 3 cells = 30 px = tag_size. */
static actag_sonar_geometry geometry(void)
{
    actag_sonar_geometry g;
    float px = 0.13f / 30.0f;
    g.min_range = 1.0f;
    g.max_range = 1.0f + (float)(FRAME - 1) * px;
    g.aperture = (float)(FRAME - 1) * px / (0.5f * (g.min_range + g.max_range));
    g.bearings = NULL;
    g.flags = 0u;
    return g;
}

/* Dihedral transform t (0..7) of a point in a FRAME x FRAME image:
 * rotate by 90 degrees (t & 3) times, then mirror left-right if t & 4. */
static void xform(int t, float x, float y, float *ox, float *oy)
{
    int r;
    float n = (float)(FRAME - 1);
    for (r = 0; r < (t & 3); r++) {
        float nx = n - y, ny = x;
        x = nx;
        y = ny;
    }
    if (t & 4)
        x = n - x;
    *ox = x;
    *oy = y;
}

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
    int ambiguous = decoder_distance(fam, id) <= 2;
    static uint8_t tag[120 * 120], frame[FRAME * FRAME], out[FRAME * FRAME];
    actag_params p;
    actag_sonar_geometry g = geometry();
    int side = actag_render_side(fam->bits, CELL, MARGIN), t, x, y, c;
    /* white-square corners as printed: pixel centres of its corner pixels */
    const float sq[4][2] = {{OFF + MARGIN + 2 * CELL, OFF + MARGIN + 2 * CELL},
                            {OFF + MARGIN + 5 * CELL - 1, OFF + MARGIN + 2 * CELL},
                            {OFF + MARGIN + 5 * CELL - 1, OFF + MARGIN + 5 * CELL - 1},
                            {OFF + MARGIN + 2 * CELL, OFF + MARGIN + 5 * CELL - 1}};
    TEST_ASSERT_EQUAL_INT(120, side);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_render_tag(fam, id, CELL, MARGIN, 255, 0, tag, side,
                                                     sizeof tag));
    memset(frame, 255, sizeof frame);
    for (y = 0; y < side; y++)
        memcpy(frame + (size_t)(OFF + y) * FRAME + OFF, tag + (size_t)y * (size_t)side, (size_t)side);
    actag_params_default(&p);
    p.family = fam;
    p.tag_size = 0.13f;
    /* The tag is drawn square in the polar frame, which no physical tag
     * shows; the corner refinement (refine.h) fits a physical square in the
     * fan plane and so moves these corners by ~2 px. This test is about the
     * reading and the quad corners: refinement off. */
    p.tuning.refine_corners = 0;
    for (t = 0; t < 8; t++) {
        actag_frame f;
        actag_detection det[4];
        int n;
        char msg[96];
        for (y = 0; y < FRAME; y++)
            for (x = 0; x < FRAME; x++) {
                float tx, ty;
                xform(t, (float)x, (float)y, &tx, &ty);
                out[(size_t)ty * FRAME + (size_t)tx] = frame[(size_t)y * FRAME + (size_t)x];
            }
        f.data = out;
        f.rows = FRAME;
        f.cols = FRAME;
        f.stride = FRAME;
        f.depth = 8;
        n = actag_detect(&f, &g, &p, g_ws, sizeof g_ws, det, 4, NULL);
        snprintf(msg, sizeof msg, "%s id %d transform %d", fam->name, id, t);
        if (ambiguous && n == 0)
            continue; /* no reading: never a wrong one */
        TEST_ASSERT_EQUAL_INT_MESSAGE(1, n, msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(id, det[0].id, msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, det[0].hamming, msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(t >= 4, det[0].mirrored, msg);
        for (c = 0; c < 4; c++) {
            float ex, ey;
            xform(t, sq[c][0], sq[c][1], &ex, &ey);
            TEST_ASSERT_FLOAT_WITHIN_MESSAGE(1.5f, ex, det[0].corners[c].x, msg);
            TEST_ASSERT_FLOAT_WITHIN_MESSAGE(1.5f, ey, det[0].corners[c].y, msg);
        }
    }
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
