/* Tests of the AprilTag 3 adapter (optical/actag_apriltag.c): the families
 * handed to AprilTag, the helpers, and AprilTag reading rendered AcTags of
 * every family (all IDs of h10/h8/h6, >= 200 spread IDs of h4) in all four
 * rotations, sharp and blurred, plus the real camera photo. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hostio.h"
#include "unity.h"

#include "actag/actag_apriltag.h"
#include "actag/family.h"
#include "actag/render.h"

#include <apriltag/apriltag.h>
#include <apriltag/common/image_u8.h>
#include <apriltag/common/zarray.h>

#include "camera_sheet.h"

/* Resources of the running test, released in tearDown() even after a failed
 * assertion (which longjmps out of the test). */
static apriltag_detector_t *g_td[2];
static apriltag_family_t *g_copy[2];
static uint8_t *g_buf[4];

void setUp(void) {}

void tearDown(void)
{
    int i;
    for (i = 0; i < 2; i++) {
        if (g_td[i])
            apriltag_detector_destroy(g_td[i]);
        g_td[i] = NULL;
    }
    for (i = 0; i < 2; i++) {
        actag_apriltag_family_destroy(g_copy[i]);
        g_copy[i] = NULL;
    }
    for (i = 0; i < 4; i++) {
        free(g_buf[i]);
        g_buf[i] = NULL;
    }
}

static uint64_t rng_state = 0x2545f4914f6cdd1dull;
static uint32_t rng(void)
{
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return (uint32_t)((rng_state * 0x2545f4914f6cdd1dull) >> 32);
}

/* ------------------------------------------------------------ references */

/* Grid cell (x, y) of data bit i (i = 0 is the code's MSB), SPEC section 2,
 * written independently of the library: walk the outer ring clockwise from
 * the top-left cell. */
static void ref_bit_cell(int k, int i, int *x, int *y)
{
    int cx = 0, cy = 0, j;
    for (j = 0; j < i; j++) {
        if (cy == 0 && cx < k)
            cx++;
        else if (cx == k && cy < k)
            cy++;
        else if (cy == k && cx > 0)
            cx--;
        else
            cy--;
    }
    *x = cx;
    *y = cy;
}

/* Layout value of cell (x, y): data bit, black ring (0) or white inside (1). */
static int ref_cell(uint32_t code, int k, int x, int y)
{
    int ring = x, i;
    if (y < ring)
        ring = y;
    if (k - x < ring)
        ring = k - x;
    if (k - y < ring)
        ring = k - y;
    if (ring == 1)
        return 0;
    if (ring > 1)
        return 1;
    for (i = 0; i < 4 * k; i++) {
        int bx, by;
        ref_bit_cell(k, i, &bx, &by);
        if (bx == x && by == y)
            return (int)((code >> (4 * k - 1 - i)) & 1u);
    }
    return -1;
}

/* Camera image of a tag: foam (1) dark, aluminium (0) light; margin_value is
 * a layout grey level (255 = foam-like), inverted like the rest (render.h). */
static void ref_render_camera(uint32_t code, int k, int cell, int margin, int margin_value,
                              uint8_t *out, int side)
{
    int x, y;
    for (y = 0; y < side; y++)
        for (x = 0; x < side; x++) {
            int gx = x - margin, gy = y - margin;
            uint8_t v = (uint8_t)(255 - margin_value);
            if (gx >= 0 && gy >= 0 && gx < (k + 1) * cell && gy < (k + 1) * cell)
                v = ref_cell(code, k, gx / cell, gy / cell) ? 0 : 255;
            out[y * side + x] = v;
        }
}

/* The published codes (data/families, independent of the generator) of the
 * published families AcTag24h*, or -1 for the others. */
static int read_published(const char *name, uint32_t *codes, int cap)
{
    char path[512], err[HOSTIO_ERRLEN];
    size_t n = 0;
    if (strncmp(name, "AcTag24h", 8) != 0)
        return -1;
    snprintf(path, sizeof path, "%s/data/families/%s.txt", ACTAG_SOURCE_DIR, name);
    if (hostio_read_codes(path, codes, (size_t)cap, &n, err) != HOSTIO_OK)
        TEST_FAIL_MESSAGE(err);
    return (int)n;
}

/* Rotate a side x side image by 90 degrees clockwise (as displayed, x right,
 * y down): out(x, y) = in(y, side-1-x). A point (X, Y) moves to (side-1-Y, X). */
static void rot90cw(const uint8_t *in, uint8_t *out, int side)
{
    int x, y;
    for (y = 0; y < side; y++)
        for (x = 0; x < side; x++)
            out[y * side + x] = in[(side - 1 - x) * side + y];
}

static apriltag_detector_t *new_detector(int slot, apriltag_family_t *fam, int bits)
{
    g_td[slot] = test_detector(fam, bits);
    return g_td[slot];
}

static int family_built(const char *name)
{
    actag_family f;
    return actag_family_get(name, &f) == ACTAG_OK;
}

/* ------------------------------------------------------------ registry */

static void test_registry_matches_core_and_published(void)
{
    static uint32_t pub[8000];
    int n = actag_apriltag_family_count(), i, j;
    TEST_ASSERT_EQUAL_INT(actag_family_count(), n);
    TEST_ASSERT_GREATER_THAN(0, n);
    TEST_ASSERT_NULL(actag_apriltag_family_name(-1));
    TEST_ASSERT_NULL(actag_apriltag_family_name(n));
    TEST_ASSERT_NULL(actag_apriltag_family(NULL));
    TEST_ASSERT_NULL(actag_apriltag_family("AcTag24h11"));
    TEST_ASSERT_NULL(actag_apriltag_family("actag24h10")); /* exact names */
    TEST_ASSERT_NULL(actag_apriltag_family(""));
    for (i = 0; i < n; i++) {
        actag_family core;
        const char *name = actag_apriltag_family_name(i);
        apriltag_family_t *f = actag_apriltag_family(name);
        int k, npub;
        TEST_ASSERT_NOT_NULL(name);
        TEST_ASSERT_NOT_NULL(f);
        TEST_ASSERT_TRUE(f == actag_apriltag_family(name)); /* one static object */
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get_at(i, &core));
        TEST_ASSERT_EQUAL_INT(0, strcmp(core.name, name));
        TEST_ASSERT_EQUAL_INT(0, strcmp(f->name, name));
        k = core.bits / 4;
        TEST_ASSERT_EQUAL_UINT(core.bits, f->nbits);
        TEST_ASSERT_EQUAL_UINT(core.hamming, f->h);
        TEST_ASSERT_EQUAL_UINT(core.ncodes, f->ncodes);
        TEST_ASSERT_EQUAL_INT(k - 3, f->width_at_border);
        TEST_ASSERT_EQUAL_INT(k + 1, f->total_width);
        TEST_ASSERT_TRUE(f->reversed_border);
        TEST_ASSERT_NULL(f->impl);
        for (j = 0; j < core.ncodes; j++)
            TEST_ASSERT_EQUAL_HEX64((uint64_t)core.codes[j], f->codes[j]);
        /* bit positions relative to the inner white square, whose top-left
         * cell is grid cell (2, 2); negative values are stored as uint32_t */
        for (j = 0; j < core.bits; j++) {
            int x, y;
            ref_bit_cell(k, j, &x, &y);
            TEST_ASSERT_EQUAL_INT(x - 2, (int)f->bit_x[j]);
            TEST_ASSERT_EQUAL_INT(y - 2, (int)f->bit_y[j]);
        }
        npub = read_published(name, pub, 8000);
        if (npub >= 0) {
            TEST_ASSERT_EQUAL_INT(npub, (int)f->ncodes); /* complete family */
            for (j = 0; j < npub; j++)
                TEST_ASSERT_EQUAL_HEX64((uint64_t)pub[j], f->codes[j]);
        }
    }
}

static void test_max_bits_corrected(void)
{
    static const int expect[14] = {0, 0, 0, 1, 1, 2, 2, 3, 3, 3, 3, 3, 3, 3};
    apriltag_family_t f;
    int h;
    memset(&f, 0, sizeof f);
    TEST_ASSERT_EQUAL_INT(-1, actag_apriltag_max_bits_corrected(NULL));
    for (h = 0; h < 14; h++) {
        /* even h: h/2-1, odd h: floor(h/2); AprilTag stops at 3 */
        f.h = (uint32_t)h;
        TEST_ASSERT_EQUAL_INT_MESSAGE(expect[h], actag_apriltag_max_bits_corrected(&f), "h");
    }
    if (family_built("AcTag24h4"))
        TEST_ASSERT_EQUAL_INT(1, actag_apriltag_max_bits_corrected(actag_apriltag_family("AcTag24h4")));
    if (family_built("AcTag24h10"))
        TEST_ASSERT_EQUAL_INT(3, actag_apriltag_max_bits_corrected(actag_apriltag_family("AcTag24h10")));
}

/* ------------------------------------------------------------ helpers */

static void test_invert(void)
{
    int sizes[5][3] = {{1, 1, 1}, {1, 7, 3}, {7, 1, 9}, {13, 5, 16}, {64, 33, 64}};
    int t, x, y;
    actag_apriltag_invert(NULL); /* no crash */
    for (t = 0; t < 5; t++) {
        int w = sizes[t][0], h = sizes[t][1], stride = sizes[t][2];
        size_t n = (size_t)stride * (size_t)h;
        uint8_t *buf = (uint8_t *)malloc(n), *orig = (uint8_t *)malloc(n);
        g_buf[0] = buf;
        g_buf[1] = orig;
        for (x = 0; x < (int)n; x++)
            orig[x] = buf[x] = (uint8_t)rng();
        buf[0] = orig[0] = 0;
        if (n > 1)
            buf[n - 1] = orig[n - 1] = 255;
        image_u8_t im = {.width = w, .height = h, .stride = stride, .buf = buf};
        actag_apriltag_invert(&im);
        for (y = 0; y < h; y++)
            for (x = 0; x < stride; x++) {
                size_t p = (size_t)y * (size_t)stride + (size_t)x;
                if (p >= n)
                    continue;
                if (x < w)
                    TEST_ASSERT_EQUAL_UINT8(255 - orig[p], buf[p]);
                else
                    TEST_ASSERT_EQUAL_UINT8(orig[p], buf[p]); /* padding untouched */
            }
        actag_apriltag_invert(&im);
        TEST_ASSERT_EQUAL_INT(0, memcmp(buf, orig, n));
        if (h > 1) { /* a stride under the width (rows would overlap): untouched */
            image_u8_t bad = {.width = stride, .height = h, .stride = stride - 1, .buf = buf};
            actag_apriltag_invert(&bad);
            TEST_ASSERT_EQUAL_INT(0, memcmp(buf, orig, n));
        }
        {
            image_u8_t none = {.width = 0, .height = h, .stride = stride, .buf = buf};
            actag_apriltag_invert(&none);
            TEST_ASSERT_EQUAL_INT(0, memcmp(buf, orig, n));
        }
        free(buf);
        free(orig);
        g_buf[0] = g_buf[1] = NULL;
    }
}

static void test_corners_to_actag_synthetic(void)
{
    apriltag_detection_t det;
    double out[4][2];
    int i;
    memset(&det, 0, sizeof det);
    /* AprilTag order: bottom-left, bottom-right, top-right, top-left */
    det.p[0][0] = 10.5; det.p[0][1] = 90.5;
    det.p[1][0] = 90.5; det.p[1][1] = 91.5;
    det.p[2][0] = 89.5; det.p[2][1] = 11.5;
    det.p[3][0] = 11.5; det.p[3][1] = 12.5;
    for (i = 0; i < 4; i++)
        out[i][0] = out[i][1] = -99.0;
    actag_apriltag_corners_to_actag(NULL, out);
    TEST_ASSERT_EQUAL_FLOAT(-99.0f, (float)out[0][0]); /* untouched */
    actag_apriltag_corners_to_actag(&det, out);
    TEST_ASSERT_EQUAL_FLOAT(11.0f, (float)out[0][0]); /* top-left */
    TEST_ASSERT_EQUAL_FLOAT(12.0f, (float)out[0][1]);
    TEST_ASSERT_EQUAL_FLOAT(89.0f, (float)out[1][0]); /* top-right */
    TEST_ASSERT_EQUAL_FLOAT(11.0f, (float)out[1][1]);
    TEST_ASSERT_EQUAL_FLOAT(90.0f, (float)out[2][0]); /* bottom-right */
    TEST_ASSERT_EQUAL_FLOAT(91.0f, (float)out[2][1]);
    TEST_ASSERT_EQUAL_FLOAT(10.0f, (float)out[3][0]); /* bottom-left */
    TEST_ASSERT_EQUAL_FLOAT(90.0f, (float)out[3][1]);
}

/* ------------------------------------------------------------ rendered tags */

#define CELL 8
#define MARGIN 8

typedef struct {
    int cases, found, extra;
    double sum_dx, sum_dy, max_err;
} read_stats;

/* Renders tag `id` in camera colours, checks the core renderer against the
 * reference, then for rotations 0..3, sharp and blurred: invert, detect,
 * expect exactly one detection with this ID and hamming 0, and the corners in
 * AcTag order at the rendered inner-square corners. */
static void read_back(apriltag_detector_t *td, const actag_family *core, int id, read_stats *st)
{
    int k = core->bits / 4;
    int side = actag_render_side(core->bits, CELL, MARGIN);
    size_t n = (size_t)side * (size_t)side;
    int margin_value = (id * 85) % 256; /* 0, 85, 170, 255, ... */
    uint8_t *img = g_buf[0], *ref = g_buf[1], *rot = g_buf[2], *work = g_buf[3];
    double corner[4][2];
    int r, blur, i;
    char msg[200];

    TEST_ASSERT_EQUAL_INT((k + 1) * CELL + 2 * MARGIN, side);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_render_tag(core, id, CELL, MARGIN, margin_value, 1, img,
                                                     side, n));
    ref_render_camera(core->codes[id], k, CELL, MARGIN, margin_value, ref, side);
    snprintf(msg, sizeof msg, "%s id %d: core render differs from SPEC layout", core->name, id);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, memcmp(img, ref, n), msg);

    /* Inner white square: cells 2 .. k-2; its corners in actag pixel
     * coordinates (pixel centres at integers) lie half a pixel outside the
     * first/last white pixel. Printed order TL, TR, BR, BL. */
    {
        double lo = MARGIN + 2 * CELL - 0.5, hi = MARGIN + (k - 1) * CELL - 0.5;
        corner[0][0] = lo; corner[0][1] = lo;
        corner[1][0] = hi; corner[1][1] = lo;
        corner[2][0] = hi; corner[2][1] = hi;
        corner[3][0] = lo; corner[3][1] = hi;
    }
    memcpy(rot, img, n);
    for (r = 0; r < 4; r++) {
        if (r > 0) {
            memcpy(work, rot, n);
            rot90cw(work, rot, side);
            for (i = 0; i < 4; i++) {
                double X = corner[i][0], Y = corner[i][1];
                corner[i][0] = side - 1 - Y;
                corner[i][1] = X;
            }
        }
        for (blur = 0; blur < 2; blur++) {
            zarray_t *dets;
            apriltag_detection_t *det;
            double c[4][2];
            if (blur)
                box_blur3(rot, work, side);
            else
                memcpy(work, rot, n);
            image_u8_t im = {.width = side, .height = side, .stride = side, .buf = work};
            actag_apriltag_invert(&im);
            dets = apriltag_detector_detect(td, &im);
            /* Exactly one detection of this ID. With the family's maximum
             * corrections AprilTag can also report a bogus quad inside the
             * data ring as another ID; those are counted (and must have
             * corrected bits: an exact bogus code would be a real problem). */
            st->cases++;
            {
                int nd = zarray_size(dets), j, nid = 0, bad_exact = 0;
                det = NULL;
                for (j = 0; j < nd; j++) {
                    apriltag_detection_t *dj;
                    zarray_get(dets, j, &dj);
                    if (dj->id == id) {
                        nid++;
                        det = dj;
                    } else {
                        st->extra++;
                        bad_exact += dj->hamming == 0;
                    }
                }
                snprintf(msg, sizeof msg, "%s id %d rot %d blur %d: %d detections of the ID, %d exact others",
                         core->name, id, r, blur, nid, bad_exact);
                if (nid != 1 || bad_exact != 0 || det->hamming != 0) {
                    apriltag_detections_destroy(dets);
                    TEST_FAIL_MESSAGE(msg);
                }
            }
            actag_apriltag_corners_to_actag(det, c);
            apriltag_detections_destroy(dets);
            st->found++;
            for (i = 0; i < 4; i++) {
                double dx = c[i][0] - corner[i][0], dy = c[i][1] - corner[i][1];
                double e = fabs(dx) > fabs(dy) ? fabs(dx) : fabs(dy);
                st->sum_dx += dx;
                st->sum_dy += dy;
                if (e > st->max_err)
                    st->max_err = e;
                snprintf(msg, sizeof msg, "%s id %d rot %d blur %d corner %d", core->name, id,
                         r, blur, i);
                TEST_ASSERT_FLOAT_WITHIN_MESSAGE(0.4f, (float)corner[i][0], (float)c[i][0], msg);
                TEST_ASSERT_FLOAT_WITHIN_MESSAGE(0.4f, (float)corner[i][1], (float)c[i][1], msg);
            }
        }
    }
}

static void read_family(const char *name, int id_step, const int *extra, int nextra)
{
    actag_family core;
    apriltag_family_t *fam;
    apriltag_detector_t *td;
    read_stats st;
    size_t n;
    int id, i, side, bits;
    char msg[200];

    if (!family_built(name)) {
        TEST_IGNORE_MESSAGE("family not in ACTAG_FAMILIES");
        return;
    }
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get(name, &core));
    g_copy[0] = fam = actag_apriltag_family_create(name);
    TEST_ASSERT_NOT_NULL(fam);
    bits = actag_apriltag_max_bits_corrected(fam);
    if (bits > 2)
        bits = 2; /* the table for 3 is larger and slower to build */
    td = new_detector(0, fam, bits);
    side = actag_render_side(core.bits, CELL, MARGIN);
    TEST_ASSERT_GREATER_THAN(0, side);
    n = (size_t)side * (size_t)side;
    for (i = 0; i < 4; i++) {
        g_buf[i] = (uint8_t *)malloc(n);
        TEST_ASSERT_NOT_NULL(g_buf[i]);
    }
    memset(&st, 0, sizeof st);
    for (id = 0; id < core.ncodes; id += id_step)
        read_back(td, &core, id, &st);
    for (i = 0; i < nextra; i++)
        if (extra[i] < core.ncodes && extra[i] % id_step != 0)
            read_back(td, &core, extra[i], &st);
    TEST_ASSERT_EQUAL_INT(st.cases, st.found);
    /* AprilTag's corners carry a small bias (its edge refinement); the mean
     * must be far smaller than the 0.5 px of a wrong pixel convention. */
    snprintf(msg, sizeof msg,
             "%s (%d bits corrected): %d reads of %d IDs, %d bogus extra detections, corner error "
             "mean (%.3f, %.3f) px, max %.3f px",
             name, bits, st.found, st.found / 8, st.extra, st.sum_dx / (4.0 * st.found),
             st.sum_dy / (4.0 * st.found), st.max_err);
    TEST_MESSAGE(msg);
    TEST_ASSERT_FLOAT_WITHIN(0.25f, 0.0f, (float)(st.sum_dx / (4.0 * st.found)));
    TEST_ASSERT_FLOAT_WITHIN(0.25f, 0.0f, (float)(st.sum_dy / (4.0 * st.found)));
    TEST_ASSERT_LESS_OR_EQUAL(st.cases / 100, st.extra); /* rare: <= 1 % */
}

static void test_read_all_AcTag24h10(void) { read_family("AcTag24h10", 1, NULL, 0); }
static void test_read_all_AcTag24h8(void) { read_family("AcTag24h8", 1, NULL, 0); }
static void test_read_all_AcTag24h6(void) { read_family("AcTag24h6", 1, NULL, 0); }

/* 6261 codes: every 29th ID (216 IDs, 0 .. 6235) and the IDs around the
 * reference's cut at 2591 (its AprilTag copy stops at 2590), 6000 and the last. */
static void test_read_sample_AcTag24h4(void)
{
    static const int extra[] = {1, 2589, 2590, 2591, 2592, 4000, 5999, 6000, 6001, 6259, 6260};
    read_family("AcTag24h4", 29, extra, (int)(sizeof extra / sizeof extra[0]));
}

/* ------------------------------------------------------------ detector sharing */

/* A static family and a heap copy in two live detectors with different
 * bits_corrected: each detector has its own decode table. */
static void test_copy_and_static_in_two_detectors(void)
{
    const char *name = "AcTag24h10";
    actag_family core;
    apriltag_family_t *stat, *copy;
    int side, cx, cy, x, y, bx, by, d;
    size_t n;
    uint8_t *img;

    if (!family_built(name)) {
        TEST_IGNORE_MESSAGE("AcTag24h10 not in ACTAG_FAMILIES");
        return;
    }
    TEST_ASSERT_NULL(actag_apriltag_family_create("nope"));
    TEST_ASSERT_NULL(actag_apriltag_family_create(NULL));
    actag_apriltag_family_destroy(NULL);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get(name, &core));
    stat = actag_apriltag_family(name);
    TEST_ASSERT_NULL(stat->impl);
    new_detector(0, stat, 0);
    TEST_ASSERT_NOT_NULL(stat->impl);
    /* a copy made while the static family is in use gets no table */
    g_copy[0] = copy = actag_apriltag_family_create(name);
    TEST_ASSERT_NOT_NULL(copy);
    TEST_ASSERT_TRUE(copy != stat);
    TEST_ASSERT_NULL(copy->impl);
    TEST_ASSERT_EQUAL_INT(0, strcmp(copy->name, name));
    TEST_ASSERT_EQUAL_UINT(stat->ncodes, copy->ncodes);
    TEST_ASSERT_TRUE(copy->codes == stat->codes);

    new_detector(1, copy, 2);
    TEST_ASSERT_NOT_NULL(stat->impl);
    TEST_ASSERT_NOT_NULL(copy->impl);
    TEST_ASSERT_TRUE(stat->impl != copy->impl);

    /* tag 2 with data bit 3 flipped (printed cell (3, 0)) */
    side = actag_render_side(core.bits, 10, 10);
    n = (size_t)side * (size_t)side;
    g_buf[0] = img = (uint8_t *)malloc(n);
    TEST_ASSERT_NOT_NULL(img);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_render_tag(&core, 2, 10, 10, 128, 1, img, side, n));
    ref_bit_cell(core.bits / 4, 3, &bx, &by);
    for (y = 0; y < 10; y++)
        for (x = 0; x < 10; x++) {
            cx = 10 + bx * 10 + x;
            cy = 10 + by * 10 + y;
            img[cy * side + cx] = (uint8_t)(255 - img[cy * side + cx]);
        }
    image_u8_t im = {.width = side, .height = side, .stride = side, .buf = img};
    actag_apriltag_invert(&im);
    for (d = 0; d < 2; d++) {
        zarray_t *dets = apriltag_detector_detect(g_td[d], &im);
        int nd = zarray_size(dets), id = -1, ham = -1;
        if (nd == 1) {
            apriltag_detection_t *det;
            zarray_get(dets, 0, &det);
            id = det->id;
            ham = det->hamming;
        }
        apriltag_detections_destroy(dets);
        if (d == 0) {
            TEST_ASSERT_EQUAL_INT_MESSAGE(0, nd, "0 bits corrected must not read a 1-bit error");
        } else {
            TEST_ASSERT_EQUAL_INT(1, nd);
            TEST_ASSERT_EQUAL_INT(2, id);
            TEST_ASSERT_EQUAL_INT(1, ham);
        }
    }
    /* destroying a detector frees the family's table and resets impl */
    apriltag_detector_destroy(g_td[0]);
    g_td[0] = NULL;
    TEST_ASSERT_NULL(stat->impl);
    TEST_ASSERT_NOT_NULL(copy->impl);
    apriltag_detector_destroy(g_td[1]);
    g_td[1] = NULL;
    TEST_ASSERT_NULL(copy->impl);
    actag_apriltag_family_destroy(copy);
    g_copy[0] = NULL;
    actag_apriltag_family_destroy(stat); /* static: ignored */
    TEST_ASSERT_TRUE(actag_apriltag_family(name) == stat);
    TEST_ASSERT_EQUAL_HEX64(0xd35f2aull, stat->codes[0]);
}

/* ------------------------------------------------------------ pose */

static void test_pose_tag_size_is_inner_square(void)
{
    /* Fronto-parallel tag, inner white square 3 cells = 60 px, f = 600 px,
     * tag_size 0.13 m: the tag is at z = 600 * 0.13 / 60 = 1.3 m. If AprilTag's
     * tagsize meant another square (the black ring: 5 cells, the whole tag:
     * 7), z would be 0.78 m or 0.557 m. */
    const char *name = "AcTag24h10";
    const int cell = 20, margin = 40;
    actag_family core;
    apriltag_family_t *fam;
    int side, r, i;
    size_t n;
    double centre, R[9], t[3];
    uint8_t *img, *tmp;

    if (!family_built(name)) {
        TEST_IGNORE_MESSAGE("AcTag24h10 not in ACTAG_FAMILIES");
        return;
    }
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get(name, &core));
    g_copy[0] = fam = actag_apriltag_family_create(name);
    new_detector(0, fam, 2);
    side = actag_render_side(core.bits, cell, margin);
    n = (size_t)side * (size_t)side;
    g_buf[0] = img = (uint8_t *)malloc(n);
    g_buf[1] = tmp = (uint8_t *)malloc(n);
    TEST_ASSERT_NOT_NULL(img);
    TEST_ASSERT_NOT_NULL(tmp);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_render_tag(&core, 3, cell, margin, 255, 1, img, side, n));
    {
        image_u8_t im = {.width = side, .height = side, .stride = side, .buf = img};
        actag_apriltag_invert(&im);
    }
    centre = margin + 3.5 * cell - 0.5; /* tag centre, pixel centres at integers */
    for (r = 0; r < 2; r++) {
        zarray_t *dets;
        apriltag_detection_t *det;
        double err;
        if (r == 1) { /* a quarter turn clockwise; the centre stays put */
            memcpy(tmp, img, n);
            rot90cw(tmp, img, side);
        }
        image_u8_t im = {.width = side, .height = side, .stride = side, .buf = img};
        dets = apriltag_detector_detect(g_td[0], &im);
        TEST_ASSERT_EQUAL_INT(1, zarray_size(dets));
        zarray_get(dets, 0, &det);
        TEST_ASSERT_EQUAL_INT(3, det->id);
        TEST_ASSERT_EQUAL_FLOAT(-1.0f, (float)actag_apriltag_pose(det, 0.0, 600, 600, centre, centre, R, t));
        TEST_ASSERT_EQUAL_FLOAT(-1.0f, (float)actag_apriltag_pose(NULL, 0.13, 600, 600, centre, centre, R, t));
        {
            /* values outside the bounds (AprilTag aborted the process on
             * these): -1, R and t untouched */
            const double nan = strtod("nan", NULL), inf = HUGE_VAL;
            const double bad[][5] = {{0.13, 600, 600, 1e7, centre},  {0.13, 600, 600, nan, centre},
                                     {0.13, 600, 600, centre, -inf}, {inf, 600, 600, centre, centre},
                                     {1e-300, 600, 600, centre, centre},
                                     {1e300, 600, 600, centre, centre},
                                     {0.13, 1e7, 1e7, centre, centre}, {0.13, 1e-300, 600, centre, centre},
                                     {0.13, 600, inf, centre, centre}, {0.13, nan, 600, centre, centre}};
            double R0[9], t0[3];
            actag_pose ps;
            for (i = 0; i < (int)(sizeof bad / sizeof bad[0]); i++) {
                memset(R0, 0x5a, sizeof R0);
                memset(t0, 0x5a, sizeof t0);
                TEST_ASSERT_EQUAL_FLOAT(-1.0f, (float)actag_apriltag_pose(det, bad[i][0], bad[i][1],
                                                                          bad[i][2], bad[i][3],
                                                                          bad[i][4], R0, t0));
                TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM,
                                      actag_apriltag_pose_sensor(det, bad[i][0], bad[i][1], bad[i][2],
                                                                 bad[i][3], bad[i][4], &ps));
                {
                    unsigned char pat[sizeof R0];
                    memset(pat, 0x5a, sizeof pat);
                    TEST_ASSERT_EQUAL_INT(0, memcmp(R0, pat, sizeof R0));
                    TEST_ASSERT_EQUAL_INT(0, memcmp(t0, pat, sizeof t0));
                }
            }
            /* in bounds, but the tag subtends under ACTAG_APRILTAG_MIN_SPREAD
             * (this one aborted the process inside AprilTag): refused */
            TEST_ASSERT_EQUAL_FLOAT(-1.0f, (float)actag_apriltag_pose(
                                               det, ACTAG_APRILTAG_MIN_TAG_SIZE,
                                               ACTAG_APRILTAG_MAX_FOCAL, ACTAG_APRILTAG_MAX_FOCAL,
                                               ACTAG_APRILTAG_MAX_CENTRE,
                                               -ACTAG_APRILTAG_MAX_CENTRE, R0, t0));
            /* the tag size's bounds themselves are taken */
            TEST_ASSERT_TRUE(actag_apriltag_pose(det, ACTAG_APRILTAG_MIN_TAG_SIZE, 600.0, 600.0,
                                                 centre, centre, R0, t0) >= 0.0);
            TEST_ASSERT_TRUE(actag_apriltag_pose(det, ACTAG_APRILTAG_MAX_TAG_SIZE, 600.0, 600.0,
                                                 centre, centre, R0, t0) >= 0.0);
        }
        err = actag_apriltag_pose(det, 0.13, 600.0, 600.0, centre, centre, R, t);
        {
            /* the same pose in the sensor frame shared with the sonar
             * (pose.h): x = z_opt, y = -x_opt, z = -y_opt */
            actag_pose ps;
            TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_apriltag_pose_sensor(det, 0.13, 600.0, 600.0,
                                                                       centre, centre, &ps));
            TEST_ASSERT_FLOAT_WITHIN(1e-5f, (float)t[2], ps.t[0]);
            TEST_ASSERT_FLOAT_WITHIN(1e-5f, (float)-t[0], ps.t[1]);
            TEST_ASSERT_FLOAT_WITHIN(1e-5f, (float)-t[1], ps.t[2]);
            for (i = 0; i < 3; i++) {
                TEST_ASSERT_FLOAT_WITHIN(1e-5f, (float)R[6 + i], ps.R[i]);
                TEST_ASSERT_FLOAT_WITHIN(1e-5f, (float)-R[i], ps.R[3 + i]);
                TEST_ASSERT_FLOAT_WITHIN(1e-5f, (float)-R[3 + i], ps.R[6 + i]);
            }
            /* tag facing the camera: its z (into the tag) is the sensor's forward */
            TEST_ASSERT_FLOAT_WITHIN(0.02f, 1.0f, ps.R[2]);
            TEST_ASSERT_TRUE(ps.flags & ACTAG_POSE_NO_COVARIANCE);
            TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_apriltag_pose_sensor(det, 0.0, 600.0,
                                                                              600.0, centre,
                                                                              centre, &ps));
            TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_apriltag_pose_sensor(det, 0.13, 600.0,
                                                                             600.0, centre,
                                                                             centre, NULL));
        }
        {
            /* with the covariance: the same pose, the detected corners
             * reprojected within a pixel (corners matched to the wrong tag
             * corners would be off by the tag's side), positive variances */
            actag_pose ps, pc, keep;
            double rms;
            const double nan = strtod("nan", NULL);
            const double bad_sd[] = {0.0, -0.3, 5e-7, 2e3, nan};
            TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_apriltag_pose_sensor(det, 0.13, 600.0, 600.0,
                                                                       centre, centre, &ps));
            TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_apriltag_pose_sensor_cov(det, 0.13, 600.0, 600.0,
                                                                           centre, centre, 0.3, &pc));
            TEST_ASSERT_EQUAL_MEMORY(ps.R, pc.R, sizeof ps.R);
            TEST_ASSERT_EQUAL_MEMORY(ps.t, pc.t, sizeof ps.t);
            TEST_ASSERT_EQUAL_UINT(0u, pc.flags & (ACTAG_POSE_NO_COVARIANCE | ACTAG_POSE_DEGENERATE));
            for (i = 0; i < 6; i++)
                TEST_ASSERT_TRUE(pc.cov[7 * i] > 0.0f);
            rms = sqrt((double)pc.chi2 * 0.3 * 0.3 / 8.0);
            {
                char m[96];
                snprintf(m, sizeof m, "rot %d: reprojection %.3f px RMS a coordinate", r, rms);
                TEST_MESSAGE(m);
            }
            TEST_ASSERT_TRUE(rms < 1.0);
            memset(&keep, 0x5a, sizeof keep);
            for (i = 0; i < (int)(sizeof bad_sd / sizeof bad_sd[0]); i++) {
                pc = keep;
                TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM,
                                      actag_apriltag_pose_sensor_cov(det, 0.13, 600.0, 600.0, centre,
                                                                     centre, bad_sd[i], &pc));
                TEST_ASSERT_EQUAL_MEMORY(&keep, &pc, sizeof pc);
            }
            TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_apriltag_pose_sensor_cov(det, 0.0, 600.0, 600.0,
                                                                                  centre, centre, 0.3,
                                                                                  &pc));
            TEST_ASSERT_EQUAL_MEMORY(&keep, &pc, sizeof pc);
            TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_apriltag_pose_sensor_cov(NULL, 0.13, 600.0, 600.0,
                                                                                 centre, centre, 0.3,
                                                                                 &pc));
            TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_apriltag_pose_sensor_cov(det, 0.13, 600.0, 600.0,
                                                                                 centre, centre, 0.3,
                                                                                 NULL));
        }
        apriltag_detections_destroy(dets);
        TEST_ASSERT_TRUE(err >= 0);
        {
            char m[160];
            snprintf(m, sizeof m, "rot %d: t = (%.5f, %.5f, %.5f) m, err %.3g", r, t[0], t[1], t[2], err);
            TEST_MESSAGE(m);
        }
        TEST_ASSERT_FLOAT_WITHIN(0.013f, 1.3f, (float)t[2]); /* 1 % */
        /* 0.5 px (a wrong pixel convention for cx, cy) is 1.1 mm here;
         * AprilTag's own corner bias (about -0.1 px) is 0.3 mm */
        TEST_ASSERT_FLOAT_WITHIN(0.0006f, 0.0f, (float)t[0]);
        TEST_ASSERT_FLOAT_WITHIN(0.0006f, 0.0f, (float)t[1]);
        /* r = 0: tag axes = camera axes. r = 1: printed right (tag x) points
         * down the image (camera +y), printed down (tag y) points left (-x). */
        {
            static const double expect[2][9] = {{1, 0, 0, 0, 1, 0, 0, 0, 1},
                                                {0, -1, 0, 1, 0, 0, 0, 0, 1}};
            for (i = 0; i < 9; i++)
                TEST_ASSERT_FLOAT_WITHIN(0.02f, (float)expect[r][i], (float)R[i]);
        }
    }
}

/* ------------------------------------------------------------ real photo */
/* (The full data set's photo: run with --full-data, CTest test
 * test_apriltag_adapter_full_data.) */

static void test_real_photo_id0(void)
{
    const char *path = ACTAG_SHARED_DIR "/data/optical/exampleCameraImage.pgm";
    image_u8_t *im;
    apriltag_family_t *fam;
    zarray_t *dets;
    apriltag_detection_t *det;
    double c[4][2];
    int i, nd, n0;

    if (!family_built("AcTag24h10")) {
        TEST_IGNORE_MESSAGE("AcTag24h10 not in ACTAG_FAMILIES");
        return;
    }
    im = image_u8_create_from_pnm(path);
    TEST_ASSERT_NOT_NULL_MESSAGE(im, path);
    TEST_ASSERT_EQUAL_INT(2103, im->width);
    TEST_ASSERT_EQUAL_INT(2012, im->height);
    g_copy[0] = fam = actag_apriltag_family_create("AcTag24h10");
    new_detector(0, fam, 2);
    g_td[0]->quad_decimate = 2.0f; /* 2103 x 2012: the default decimation */

    /* as photographed (aluminium light): not tag 0 */
    dets = apriltag_detector_detect(g_td[0], im);
    n0 = 0;
    for (i = 0; i < zarray_size(dets); i++) {
        zarray_get(dets, i, &det);
        n0 += det->id == 0;
    }
    apriltag_detections_destroy(dets);

    actag_apriltag_invert(im);
    dets = apriltag_detector_detect(g_td[0], im);
    nd = zarray_size(dets);
    if (nd == 1) {
        zarray_get(dets, 0, &det);
        TEST_ASSERT_EQUAL_INT(0, det->id);
        TEST_ASSERT_EQUAL_INT(0, det->hamming);
        actag_apriltag_corners_to_actag(det, c);
        /* a real tag passes the mirror check of actag_apriltag_detect() */
        TEST_ASSERT_EQUAL_INT(0, actag_apriltag_mirror_check(det, im));
    }
    apriltag_detections_destroy(dets);
    dets = actag_apriltag_detect(g_td[0], im);
    TEST_ASSERT_EQUAL_INT(nd, zarray_size(dets));
    apriltag_detections_destroy(dets);
    image_u8_destroy(im);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, n0, "tag 0 read without inverting the photo");
    TEST_ASSERT_EQUAL_INT(1, nd);
    /* The inner white square (dark in the photo), checked by eye: top-left as
     * printed at about (645, 584), sides about 826 px, clockwise in the image
     * (a camera sees the printed side, unmirrored). */
    TEST_ASSERT_FLOAT_WITHIN(5.0f, 645.0f, (float)c[0][0]);
    TEST_ASSERT_FLOAT_WITHIN(5.0f, 584.0f, (float)c[0][1]);
    TEST_ASSERT_FLOAT_WITHIN(5.0f, 1470.0f, (float)c[1][0]);
    TEST_ASSERT_FLOAT_WITHIN(5.0f, 589.0f, (float)c[1][1]);
    TEST_ASSERT_FLOAT_WITHIN(5.0f, 1470.0f, (float)c[2][0]);
    TEST_ASSERT_FLOAT_WITHIN(5.0f, 1413.0f, (float)c[2][1]);
    TEST_ASSERT_FLOAT_WITHIN(5.0f, 641.0f, (float)c[3][0]);
    TEST_ASSERT_FLOAT_WITHIN(5.0f, 1412.0f, (float)c[3][1]);
}

int main(int argc, char **argv)
{
    UNITY_BEGIN();
    if (argc > 1 && strcmp(argv[1], "--full-data") == 0) {
        RUN_TEST(test_real_photo_id0);
        return UNITY_END();
    }
    RUN_TEST(test_registry_matches_core_and_published);
    RUN_TEST(test_max_bits_corrected);
    RUN_TEST(test_invert);
    RUN_TEST(test_corners_to_actag_synthetic);
    RUN_TEST(test_copy_and_static_in_two_detectors);
    RUN_TEST(test_pose_tag_size_is_inner_square);
    RUN_TEST(test_read_all_AcTag24h10);
    RUN_TEST(test_read_all_AcTag24h8);
    RUN_TEST(test_read_all_AcTag24h6);
    RUN_TEST(test_read_sample_AcTag24h4);
    return UNITY_END();
}
