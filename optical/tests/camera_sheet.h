/* Helpers shared by the optical tests (test_apriltag_adapter.c,
 * test_apriltag_mirror_check.c, test_apriltag_mirror_families.c): the
 * dihedral transforms of a square image, a 3 x 3 box blur, the AprilTag
 * detector they all use (made and released), and sheets of camera renders
 * (tags on tiles of `side` px, `tiles` per row, row-major) with the test of
 * where a detection's corners lie on them. Static inline: each test takes
 * what it needs. Not a test itself (the CMake glob takes tests/test_*.c). */
#ifndef ACTAG_OPTICAL_TESTS_CAMERA_SHEET_H
#define ACTAG_OPTICAL_TESTS_CAMERA_SHEET_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "unity.h"

#include "actag/actag_apriltag.h"
#include "actag/family.h"
#include "actag/render.h"

#include <apriltag/apriltag.h>

/* Dihedral transform t (0..7) of a point of a w x w image (pixel centres
 * at integers): rotate by 90 degrees (t & 3) times, (x, y) -> (w-1-y, x),
 * then mirror left-right if t & 4. */
static inline void xform(int t, int w, double x, double y, double *ox, double *oy)
{
    int r;
    for (r = 0; r < (t & 3); r++) {
        double nx = w - 1 - y, ny = x;
        x = nx;
        y = ny;
    }
    if (t & 4)
        x = w - 1 - x;
    *ox = x;
    *oy = y;
}

static inline void inverse_xform(int t, int w, double x, double y, double *ox, double *oy)
{
    int r;
    if (t & 4)
        x = w - 1 - x;
    for (r = 0; r < (t & 3); r++) { /* inverse of (x, y) -> (w-1-y, x) */
        double nx = y, ny = w - 1 - x;
        x = nx;
        y = ny;
    }
    *ox = x;
    *oy = y;
}

/* out = the w x w image in under transform t: in's pixel (x, y) goes to
 * xform(t, w, x, y). */
static inline void xform_image(int t, int w, const uint8_t *in, uint8_t *out)
{
    int x, y;
    for (y = 0; y < w; y++)
        for (x = 0; x < w; x++) {
            double ox, oy;
            xform(t, w, x, y, &ox, &oy);
            out[(size_t)oy * (size_t)w + (size_t)ox] = in[(size_t)y * (size_t)w + (size_t)x];
        }
}

/* 3 x 3 box blur of a side x side image, edges clamped, rounded. */
static inline void box_blur3(const uint8_t *in, uint8_t *out, int side)
{
    int x, y, dx, dy;
    for (y = 0; y < side; y++)
        for (x = 0; x < side; x++) {
            int s = 0;
            for (dy = -1; dy <= 1; dy++)
                for (dx = -1; dx <= 1; dx++) {
                    int xx = x + dx, yy = y + dy;
                    xx = xx < 0 ? 0 : (xx >= side ? side - 1 : xx);
                    yy = yy < 0 ? 0 : (yy >= side ? side - 1 : yy);
                    s += in[yy * side + xx];
                }
            out[y * side + x] = (uint8_t)((s + 4) / 9);
        }
}

/* An AprilTag detector at full resolution (no decimation), one thread,
 * reading family fam with `bits` corrected bits; the caller destroys it
 * (before the family). */
static inline apriltag_detector_t *test_detector(apriltag_family_t *fam, int bits)
{
    apriltag_detector_t *td = apriltag_detector_create();
    if (td) {
        td->quad_decimate = 1.0f;
        td->nthreads = 1;
        apriltag_detector_add_family_bits(td, fam, bits);
    }
    return td;
}

/* Destroys *td (if any), then *fam (after the detector that reads it), and
 * sets both to NULL. */
static inline void release_detector(apriltag_detector_t **td, apriltag_family_t **fam)
{
    if (*td)
        apriltag_detector_destroy(*td);
    *td = NULL;
    actag_apriltag_family_destroy(*fam);
    *fam = NULL;
}

/* A sheet of camera renders (actag_render_tag, margin like the foam, side
 * at most 200 px): tags ids[0 .. count-1] of core at tiles 0 .. count-1 of
 * `tiles` x `tiles`, cell and margin in px, the rest 0 (camera colours of a
 * foam-like surround). The sheet is side * tiles px square. */
static inline void render_sheet(const actag_family *core, const int *ids, int count, int cell,
                                int margin, int tiles, uint8_t *sheet)
{
    int side = actag_render_side(core->bits, cell, margin), w = side * tiles, i, y;
    static uint8_t tag[200 * 200];
    TEST_ASSERT_TRUE(side <= 200);
    memset(sheet, 0, (size_t)w * (size_t)w);
    for (i = 0; i < count; i++) {
        int tx = (i % tiles) * side, ty = (i / tiles) * side;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_render_tag(core, ids[i], cell, margin, 255, 1, tag,
                                                         side, sizeof tag));
        for (y = 0; y < side; y++)
            memcpy(sheet + (size_t)(ty + y) * (size_t)w + (size_t)tx,
                   tag + (size_t)y * (size_t)side, (size_t)side);
    }
}

/* Whether corners c (AcTag order) of a detection on such a sheet seen under
 * transform t are, within 0.5 px, those of the white square of the tag at
 * `tile` (k = the family's bits / 4). */
static inline int at_white_square(double c[4][2], int t, int tile, int k, int side,
                                  int tiles, int cell, int margin)
{
    int i, at_square = 1;
    for (i = 0; i < 4; i++) {
        double lo = margin + 2 * cell - 0.5, hi = margin + (k - 1) * cell - 0.5;
        double px = (tile % tiles) * side + ((i == 1 || i == 2) ? hi : lo);
        double py = (tile / tiles) * side + (i >= 2 ? hi : lo);
        double ex, ey;
        xform(t, side * tiles, px, py, &ex, &ey);
        if (fabs(ex - c[i][0]) > 0.5 || fabs(ey - c[i][1]) > 0.5)
            at_square = 0;
    }
    return at_square;
}

#endif
