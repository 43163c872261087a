/* Shared by test_sonar_render.c and test_sonar_roundtrip_m*.c: a rendered
 * tag (layout colours: white = foam) of any size through the whole sonar
 * pipeline (actag_detect with default parameters) in all 8 orientations (4
 * rotations, optionally mirrored); the ID, hamming 0, the mirrored flag and
 * the corners in tag order must come back. The functions are static inline:
 * a test uses those it needs. */
#ifndef ACTAG_SONAR_ROUNDTRIP_H
#define ACTAG_SONAR_ROUNDTRIP_H

#include "unity.h"
#include "test_util.h"

#include "actag/actag.h"
#include "actag/render.h"

#define RT_CELL 10
#define RT_MARGIN 25
#ifndef RT_FRAME /* test_sonar_render.c (24-bit tags only): 160 */
#define RT_FRAME 170 /* square frame; a 28-bit tag is 8*10 + 2*25 = 130 px */
#endif
#define RT_OFF 17
#define RT_PX (0.13f / 30.0f) /* metres per pixel: 3 cells of 10 px = 0.13 m */

static uint8_t rt_ws[ACTAG_WORKSPACE_SIZE(RT_FRAME, RT_FRAME)];

static inline actag_sonar_geometry rt_geometry(void)
{
    actag_sonar_geometry g;
    g.min_range = 1.0f;
    g.max_range = 1.0f + (float)(RT_FRAME - 1) * RT_PX;
    g.aperture = (float)(RT_FRAME - 1) * RT_PX / (0.5f * (g.min_range + g.max_range));
    g.bearings = NULL;
    g.flags = 0u;
    return g;
}

/* Dihedral transform t (0..7) of a point: rotate by 90 degrees (t & 3)
 * times, then mirror left-right if t & 4. */
static inline void rt_xform(int t, float x, float y, float *ox, float *oy)
{
    int r;
    float n = (float)(RT_FRAME - 1);
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

/* may_miss: no reading passes too (never a wrong one). */
static inline void rt_check_tag_or_none(const actag_family *fam, int id, int may_miss)
{
    static uint8_t tag[RT_FRAME * RT_FRAME], frame[RT_FRAME * RT_FRAME], out[RT_FRAME * RT_FRAME];
    actag_params p;
    actag_sonar_geometry g = rt_geometry();
    int k = fam->bits / 4;
    int side = actag_render_side(fam->bits, RT_CELL, RT_MARGIN), t, x, y, c;
    float lo = (float)(RT_OFF + RT_MARGIN + 2 * RT_CELL);
    float hi = (float)(RT_OFF + RT_MARGIN + (k - 1) * RT_CELL - 1);
    /* white-square corners as printed: pixel centres of its corner pixels */
    const float sq[4][2] = {{lo, lo}, {hi, lo}, {hi, hi}, {lo, hi}};
    TEST_ASSERT_EQUAL_INT((k + 1) * RT_CELL + 2 * RT_MARGIN, side);
    TEST_ASSERT_TRUE(RT_OFF + side <= RT_FRAME);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_render_tag(fam, id, RT_CELL, RT_MARGIN, 255, 0, tag,
                                                     side, sizeof tag));
    memset(frame, 255, sizeof frame);
    for (y = 0; y < side; y++)
        memcpy(frame + (size_t)(RT_OFF + y) * RT_FRAME + RT_OFF, tag + (size_t)y * (size_t)side,
               (size_t)side);
    actag_params_default(&p);
    p.family = fam;
    p.tag_size = (float)((k - 3) * RT_CELL) * RT_PX;
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
        for (y = 0; y < RT_FRAME; y++)
            for (x = 0; x < RT_FRAME; x++) {
                float tx, ty;
                rt_xform(t, (float)x, (float)y, &tx, &ty);
                out[(size_t)ty * RT_FRAME + (size_t)tx] = frame[(size_t)y * RT_FRAME + (size_t)x];
            }
        f.data = out;
        f.rows = RT_FRAME;
        f.cols = RT_FRAME;
        f.stride = RT_FRAME;
        f.depth = 8;
        n = actag_detect(&f, &g, &p, rt_ws, sizeof rt_ws, det, 4, NULL);
        snprintf(msg, sizeof msg, "%s id %d transform %d", fam->name, id, t);
        if (may_miss && n == 0)
            continue;
        TEST_ASSERT_EQUAL_INT_MESSAGE(1, n, msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(id, det[0].id, msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, det[0].hamming, msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(t >= 4, det[0].mirrored, msg);
        for (c = 0; c < 4; c++) {
            float ex, ey;
            rt_xform(t, sq[c][0], sq[c][1], &ex, &ey);
            TEST_ASSERT_FLOAT_WITHIN_MESSAGE(1.5f, ex, det[0].corners[c].x, msg);
            TEST_ASSERT_FLOAT_WITHIN_MESSAGE(1.5f, ey, det[0].corners[c].y, msg);
        }
    }
}

static inline void rt_check_tag(const actag_family *fam, int id)
{
    rt_check_tag_or_none(fam, id, 0);
}

/* ACTAG_FULL_ROUNDTRIP=1 in the environment: every ID of every family. */
static inline int rt_full(void)
{
    const char *f = getenv("ACTAG_FULL_ROUNDTRIP");
    return f != NULL && strcmp(f, "1") == 0;
}

/* Every ID of the family (step 1) or every step-th plus the last (every ID
 * with ACTAG_FULL_ROUNDTRIP=1; about 4 IDs per family in the emulated
 * suites, TU_EMULATED). */
static inline void rt_check_family(const char *name, int step)
{
    actag_family fam;
    int id;
    if (rt_full())
        step = 1;
    TEST_ASSERT_EQUAL_INT_MESSAGE(ACTAG_OK, actag_family_get(name, &fam), name);
    if (TU_EMULATED && step < fam.ncodes / 3)
        step = fam.ncodes / 3;
    for (id = 0; id < fam.ncodes; id += step)
        rt_check_tag(&fam, id);
    if ((fam.ncodes - 1) % step != 0)
        rt_check_tag(&fam, fam.ncodes - 1);
}

#endif
