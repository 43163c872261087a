/*
 * fuzz_quad.c -- libFuzzer harness: the contour scanner and the RANSAC quad
 * fit (contours.h, quad.h) on arbitrary input.
 *
 * Contours: an arbitrary binary image (up to 64 x 64, any stride, guarded)
 * is scanned; against a brute-force 8-connected labelling: exactly one
 * contour per white component, in raster order of the components' first
 * pixels, starting at that pixel; every stored point a pixel of that
 * component that is 4-adjacent to black or to the outside; consecutive
 * points (and last -> first) 8-neighbours; the bounding box the
 * component's; counts and overflow flags consistent; row padding untouched.
 * Quad fit: the stored points of the first contour, or arbitrary points
 * from the input, with fuzzed parameters (max_iterations capped at 300 to
 * keep each run short); ACTAG_ERR_PARAM exactly when a parameter is outside
 * its documented range; on success finite corners, clockwise on screen,
 * topmost (then leftmost) first, inlier ratio within [required, 1],
 * iterations <= max_iterations; the same result from the same generator
 * state; the scratch buffer's guards intact (any alignment).
 */
#include "fuzz_util.h"

#include "actag/contours.h"
#include "actag/quad.h"
#include "actag/rng.h"

#define FQ_MAX 64

static int label[FQ_MAX * FQ_MAX];

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_reader r;
    fz_guarded gimg = {0}, gscr = {0};
    actag_contour_scanner sc;
    actag_contour_info ci;
    actag_quad_params qp;
    actag_ipoint pts[4 * FQ_MAX * FQ_MAX + 8], first[4 * FQ_MAX * FQ_MAX + 8];
    int rows, cols, stride, cap, i, rc, ncomp = 0, nfirst = -1, x, y, mode;
    int minx[FQ_MAX * FQ_MAX], maxx[FQ_MAX * FQ_MAX], miny[FQ_MAX * FQ_MAX],
        maxy[FQ_MAX * FQ_MAX], fx[FQ_MAX * FQ_MAX], fy[FQ_MAX * FQ_MAX];
    uint8_t *img, *copy;
    size_t bytes, nin, k = 0;
    const uint8_t *pix;
    unsigned density;

    fz_init(&r, data, size);
    rows = 1 + fz_u8(&r) % FQ_MAX;
    cols = 1 + fz_u8(&r) % FQ_MAX;
    stride = cols + fz_u8(&r) % 5;
    cap = fz_int(&r, 4 * FQ_MAX * FQ_MAX, 0, 64);
    if (cap > 4 * FQ_MAX * FQ_MAX + 8)
        cap = 4 * FQ_MAX * FQ_MAX + 8;
    density = fz_u8(&r);
    mode = fz_u8(&r) % 3;
    actag_quad_params_default(&qp);
    qp.max_iterations = fz_int(&r, 50, 1, 300);
    qp.sample_fraction = fz_float(&r, qp.sample_fraction, 0.0f, 1.0f);
    qp.inlier_ratio = fz_float(&r, qp.inlier_ratio, 0.0f, 1.0f);
    qp.inlier_distance = fz_float(&r, qp.inlier_distance, 0.0f, 10.0f);
    qp.min_parallel_cos = fz_float(&r, qp.min_parallel_cos, 0.0f, 1.0f);
    qp.min_inlier_ratio = fz_float(&r, qp.min_inlier_ratio, 0.0f, 1.0f);
    {
        uint32_t seed = fz_u32(&r);
        unsigned misalign = fz_u8(&r);
        actag_rng rng1, rng2;
        actag_quad q1, q2;
        int nq, iters_cap;
        const actag_ipoint *qpts;
        uint8_t *scr;
        size_t scr_size;

        /* the image: input bits, or squares (tag-like outlines) */
        bytes = (size_t)(rows - 1) * (size_t)stride + (size_t)cols;
        img = fz_guard_alloc(&gimg, bytes, misalign >> 4);
        pix = fz_rest(&r, &nin);
        for (i = 0; i < (int)bytes; i++)
            img[i] = 0xC3; /* padding pattern */
        for (y = 0; y < rows; y++)
            for (x = 0; x < cols; x++) {
                uint8_t v;
                if (mode == 0)
                    v = nin ? (uint8_t)(pix[(k / 8) % nin] >> (k % 8) & 1u) : 0u;
                else if (mode == 1)
                    v = nin ? (uint8_t)(pix[k % nin] < density) : 0u;
                else
                    v = (uint8_t)(x >= 3 && y >= 3 && x < cols - 3 && y < rows - 3 &&
                                  ((x - 3) % 17 < 12) && ((y - 3) % 17 < 12));
                k++;
                img[(size_t)y * (size_t)stride + (size_t)x] = v ? (uint8_t)(1 + (k & 0x7f)) : 0u;
            }
        copy = (uint8_t *)malloc(bytes);
        FZ_CHECK(copy != NULL, "oom");
        memcpy(copy, img, bytes);

        /* brute force: 8-connected components in raster order of first pixels */
        for (i = 0; i < rows * cols; i++)
            label[i] = -1;
        for (y = 0; y < rows; y++)
            for (x = 0; x < cols; x++) {
                int stack_n = 0;
                static int stack[FQ_MAX * FQ_MAX];
                if (!img[(size_t)y * (size_t)stride + (size_t)x] || label[y * cols + x] >= 0)
                    continue;
                label[y * cols + x] = ncomp;
                minx[ncomp] = maxx[ncomp] = fx[ncomp] = x;
                miny[ncomp] = maxy[ncomp] = fy[ncomp] = y;
                stack[stack_n++] = y * cols + x;
                while (stack_n) {
                    int p = stack[--stack_n], px = p % cols, py = p / cols, dx, dy;
                    minx[ncomp] = px < minx[ncomp] ? px : minx[ncomp];
                    maxx[ncomp] = px > maxx[ncomp] ? px : maxx[ncomp];
                    miny[ncomp] = py < miny[ncomp] ? py : miny[ncomp];
                    maxy[ncomp] = py > maxy[ncomp] ? py : maxy[ncomp];
                    for (dy = -1; dy <= 1; dy++)
                        for (dx = -1; dx <= 1; dx++) {
                            int nx = px + dx, ny = py + dy;
                            if (nx < 0 || ny < 0 || nx >= cols || ny >= rows)
                                continue;
                            if (img[(size_t)ny * (size_t)stride + (size_t)nx] &&
                                label[ny * cols + nx] < 0) {
                                label[ny * cols + nx] = ncomp;
                                stack[stack_n++] = ny * cols + nx;
                            }
                        }
                }
                ncomp++;
            }

        /* the scanner */
        {
            static uint32_t bm[ACTAG_BITMAP_SIZE(FQ_MAX, FQ_MAX) / 4];
            static uint32_t mk[ACTAG_BITMAP_SIZE(FQ_MAX, FQ_MAX) / 4];
            rc = actag_bitmap_pack(img, rows, cols, stride, bm);
            FZ_CHECK(rc == ACTAG_OK, "bitmap pack %d", rc);
            rc = actag_contour_scanner_init(&sc, bm, mk, rows, cols);
            FZ_CHECK(rc == ACTAG_OK, "scanner init %d", rc);
        }
        if (cap < 0) {
            rc = actag_contour_next(&sc, pts, cap, &ci);
            FZ_CHECK(rc == ACTAG_ERR_PARAM, "negative cap: %d", rc);
            cap = 0;
        }
        for (i = 0;; i++) {
            int j, n;
            rc = actag_contour_next(&sc, cap ? pts : NULL, cap, &ci);
            FZ_CHECK(rc == 0 || rc == 1, "contour_next %d", rc);
            if (rc == 0)
                break;
            FZ_CHECK(i < ncomp, "more contours than components (%d)", ncomp);
            n = ci.stored;
            FZ_CHECK(ci.npoints >= 1 && n == (ci.npoints < cap ? ci.npoints : cap) &&
                         ci.overflow == (ci.npoints > cap),
                     "counts: npoints %d stored %d cap %d overflow %d", ci.npoints, n, cap,
                     ci.overflow);
            FZ_CHECK(ci.min_x == minx[i] && ci.max_x == maxx[i] && ci.min_y == miny[i] &&
                         ci.max_y == maxy[i],
                     "contour %d box (%d..%d, %d..%d), component (%d..%d, %d..%d)", i, ci.min_x,
                     ci.max_x, ci.min_y, ci.max_y, minx[i], maxx[i], miny[i], maxy[i]);
            FZ_CHECK(ci.area >= 0.0f && isfinite(ci.area), "area");
            if (n > 0)
                FZ_CHECK(pts[0].x == fx[i] && pts[0].y == fy[i], "contour %d starts at (%d,%d)",
                         i, pts[0].x, pts[0].y);
            for (j = 0; j < n; j++) {
                int px = pts[j].x, py = pts[j].y, b = 0;
                FZ_CHECK(px >= 0 && py >= 0 && px < cols && py < rows, "point outside");
                FZ_CHECK(label[py * cols + px] == i, "point of another component");
                b |= px == 0 || py == 0 || px == cols - 1 || py == rows - 1;
                b |= px > 0 && !img[(size_t)py * (size_t)stride + (size_t)(px - 1)];
                b |= py > 0 && !img[(size_t)(py - 1) * (size_t)stride + (size_t)px];
                b |= px < cols - 1 && !img[(size_t)py * (size_t)stride + (size_t)(px + 1)];
                b |= py < rows - 1 && !img[(size_t)(py + 1) * (size_t)stride + (size_t)px];
                FZ_CHECK(b, "point (%d,%d) not 4-adjacent to black", px, py);
                if (j > 0 || (n == ci.npoints && n > 1)) {
                    const actag_ipoint *a = &pts[j > 0 ? j - 1 : n - 1];
                    FZ_CHECK(abs(a->x - px) <= 1 && abs(a->y - py) <= 1,
                             "points %d and its predecessor not 8-neighbours", j);
                }
            }
            if (nfirst < 0 && !ci.overflow && n >= ACTAG_QUAD_MIN_POINTS) {
                memcpy(first, pts, (size_t)n * sizeof *pts);
                nfirst = n;
            }
        }
        FZ_CHECK(i == ncomp, "%d contours for %d components", i, ncomp);
        fz_guard_check(&gimg, "binary image");
        for (y = 0; y < rows; y++) /* row padding untouched, white stays white */
            for (x = 0; x < stride && (size_t)y * (size_t)stride + (size_t)x < bytes; x++) {
                size_t at = (size_t)y * (size_t)stride + (size_t)x;
                if (x >= cols)
                    FZ_CHECK(img[at] == copy[at], "row padding written");
                else
                    FZ_CHECK((img[at] != 0) == (copy[at] != 0), "pixel colour changed");
            }

        /* the quad fit */
        if (nfirst > 0 && !(density & 1)) {
            qpts = first;
            nq = nfirst;
        } else {
            /* arbitrary points from the input */
            nq = (int)(nin / 2 < 1000 ? nin / 2 : 1000);
            for (i = 0; i < nq; i++) {
                first[i].x = (int16_t)(pix[2 * i] % 64);
                first[i].y = (int16_t)(pix[2 * i + 1] % 64);
            }
            qpts = first;
        }
        scr_size = ACTAG_QUAD_SCRATCH_SIZE(nq) - (size_t)((density >> 1) == 0x7f);
        scr = fz_guard_alloc(&gscr, scr_size, misalign);
        iters_cap = qp.max_iterations > 300 ? 300 : qp.max_iterations;
        qp.max_iterations = iters_cap;
        actag_rng_seed(&rng1, seed);
        rng2 = rng1;
        memset(&q1, 0x11, sizeof q1);
        rc = actag_quad_fit(qpts, nq, &qp, &rng1, scr, scr_size, &q1);
        {
            float d = qp.inlier_distance;
            int bad = qp.max_iterations < 1 ||
                      !(qp.sample_fraction > 0.0f && qp.sample_fraction <= 1.0f) ||
                      !(qp.inlier_ratio > 0.0f && qp.inlier_ratio <= 1.0f) ||
                      !(qp.min_inlier_ratio > 0.0f && qp.min_inlier_ratio <= 1.0f) ||
                      !(d > 0.0f && d <= 1e6f) ||
                      !(qp.min_parallel_cos >= 0.0f && qp.min_parallel_cos <= 1.0f);
            if (bad)
                FZ_CHECK(rc == ACTAG_ERR_PARAM, "bad parameters accepted: %d", rc);
            else if (scr_size < ACTAG_QUAD_SCRATCH_SIZE(nq))
                FZ_CHECK(rc == ACTAG_ERR_WORKSPACE, "small scratch accepted: %d", rc);
            else
                FZ_CHECK(rc == ACTAG_OK || rc == ACTAG_ERR_NO_QUAD, "quad fit %d", rc);
        }
        fz_guard_check(&gscr, "quad scratch");
        if (rc == ACTAG_OK || rc == ACTAG_ERR_NO_QUAD) {
            int rc2;
            float req = qp.min_inlier_ratio < qp.inlier_ratio ? qp.min_inlier_ratio
                                                              : qp.inlier_ratio;
            FZ_CHECK(q1.iterations >= 0 && q1.iterations <= iters_cap, "iterations %d",
                     q1.iterations);
            rc2 = actag_quad_fit(qpts, nq, &qp, &rng2, scr, scr_size, &q2);
            FZ_CHECK(rc2 == rc && memcmp(&q1, &q2, sizeof q1) == 0 &&
                         memcmp(&rng1, &rng2, sizeof rng1) == 0,
                     "quad fit not repeatable");
            if (rc == ACTAG_OK) {
                FZ_CHECK(q1.inlier_ratio >= req && q1.inlier_ratio <= 1.0f, "ratio %g < %g",
                         (double)q1.inlier_ratio, (double)req);
                for (i = 0; i < 4; i++) {
                    const actag_point *a = &q1.corners[i], *b = &q1.corners[(i + 1) & 3],
                                      *c = &q1.corners[(i + 2) & 3];
                    FZ_CHECK(isfinite(a->x) && isfinite(a->y), "corner %d not finite", i);
                    FZ_CHECK((b->x - a->x) * (c->y - b->y) - (b->y - a->y) * (c->x - b->x) > 0.0f,
                             "corners not clockwise on screen at %d", i);
                    if (i > 0)
                        FZ_CHECK(q1.corners[0].y < a->y ||
                                     (q1.corners[0].y == a->y && q1.corners[0].x <= a->x),
                                 "corner 0 is not the topmost-leftmost");
                }
            }
        }
        free(copy);
        fz_guard_free(&gimg);
        fz_guard_free(&gscr);
    }
    return 0;
}
