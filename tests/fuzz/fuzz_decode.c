/*
 * fuzz_decode.c -- libFuzzer harness: the decoder entry points (decode.h) on
 * arbitrary and degenerate quads.
 *
 * An input gives an image (size, stride; pixels from the input or a
 * rendered tag with noise), a quad (free corners, or a square, a duplicated
 * corner, three collinear corners, a bow-tie, a concave quad, a tiny, a huge
 * or a non-finite one), a family (built-in or invalid), corrections, the map
 * model and the fit decoder's options. Checks, from decode.h:
 *   - only the documented codes, in the documented precedence (image, then
 *     family, corrections and options, then the quad);
 *   - a clearly degenerate quad (a non-finite corner, a turn with |sin| <
 *     0.5e-3 or turns both ways) is ACTAG_ERR_PARAM, a clearly convex one of
 *     moderate size is not (affine map);
 *   - results: ID in the family, hamming within the corrections, rotation
 *     0..3, corners[] the input corners in the documented order (clockwise
 *     on screen from quad[0]; unmirrored corners[n] = q[(n - rot) mod 4],
 *     mirrored q[(rot - n) mod 4]), observed (or its reflection P) within
 *     hamming bits of rot90^rotation(code); read_word only the family's bits;
 *   - the image's guard bytes untouched, results identical on a second call.
 */
#include "fuzz_util.h"

#include "actag/decode.h"
#include "actag/family.h"
#include "actag/render.h"

#define FZQ_MAX 96

/* +1 clearly convex clockwise, -1 clearly convex counter-clockwise, 0
 * clearly degenerate, 2 too close to the documented |sin| > 1e-3 boundary
 * (or too large to judge in float). */
static int judge_quad(const actag_point q[4])
{
    int i, pos = 0, neg = 0, near = 0;
    for (i = 0; i < 4; i++) {
        double ax = q[i].x, ay = q[i].y, bx = q[(i + 1) & 3].x, by = q[(i + 1) & 3].y;
        double cx = q[(i + 2) & 3].x, cy = q[(i + 2) & 3].y;
        double e1x = bx - ax, e1y = by - ay, e2x = cx - bx, e2y = cy - by;
        double z = e1x * e2y - e1y * e2x, l1 = sqrt(e1x * e1x + e1y * e1y),
               l2 = sqrt(e2x * e2x + e2y * e2y), s;
        if (!isfinite(ax) || !isfinite(ay) || !isfinite(z) || !isfinite(l1 * l2))
            return isfinite(ax) && isfinite(ay) && isfinite(bx) && isfinite(by) ? 2 : 0;
        if (fabs(ax) > 1e15 || fabs(ay) > 1e15)
            near = 1; /* squares of the sides overflow float: the decoder refuses */
        if (l1 * l2 < 1e-18)
            near = 1; /* products of the sides underflow float (found by fuzzing:
                       * a square of side 4e-41): degenerate there, documented */
        if (!(l1 * l2 > 0.0))
            return 0;
        s = z / (l1 * l2);
        if (fabs(s) < 0.5e-3)
            return 0;
        if (fabs(s) < 2e-3)
            near = 1;
        if (s > 0)
            pos++;
        else
            neg++;
    }
    if (near)
        return 2;
    if (pos == 4)
        return 1;
    if (neg == 4)
        return -1;
    return 0;
}

static uint32_t rot_n(uint32_t c, int bits, int n)
{
    while (n-- > 0)
        c = actag_code_rot90(c, bits);
    return c;
}

static void check_result(const actag_decode_result *d, const actag_point quad[4], int judge,
                         const actag_family *f, int maxcorr, int exact_corners, int check_word)
{
    actag_point q[4];
    int n, i;
    FZ_CHECK(d->id >= 0 && d->id < f->ncodes, "id %d", d->id);
    FZ_CHECK(d->hamming >= 0 && d->hamming <= maxcorr, "hamming %d > %d", d->hamming, maxcorr);
    FZ_CHECK(d->rotation >= 0 && d->rotation <= 3, "rotation %d", d->rotation);
    FZ_CHECK(d->mirrored == 0 || d->mirrored == 1, "mirrored %d", d->mirrored);
    FZ_CHECK(!isnan(d->decision_margin), "NaN margin");
    if (judge != 1 && judge != -1)
        return;
    q[0] = quad[0];
    for (i = 1; i < 4; i++)
        q[i] = quad[judge > 0 ? i : 4 - i];
    if (exact_corners)
        for (n = 0; n < 4; n++) {
            int j = d->mirrored ? (d->rotation - n + 8) & 3 : (n - d->rotation + 8) & 3;
            FZ_CHECK(d->corners[n].x == q[j].x && d->corners[n].y == q[j].y,
                     "corner %d is not q[%d] (rotation %d, mirrored %d)", n, j, d->rotation,
                     d->mirrored);
        }
    if (check_word) {
        uint32_t w = d->mirrored ? actag_code_mirror(d->observed, f->bits) : d->observed;
        uint32_t c = rot_n(f->codes[d->id], f->bits, d->rotation);
        FZ_CHECK(actag_popcount32((w ^ c) & actag_code_mask(f->bits)) == d->hamming,
                 "observed %#x is not %d bits from rot90^%d(code %d)", d->observed, d->hamming,
                 d->rotation, d->id);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_reader r;
    fz_guarded gimg = {0};
    actag_family fam;
    actag_fit_params fp;
    actag_point quad[4], pos[32];
    actag_decode_result d1, d2;
    float H[9];
    uint32_t word;
    uint8_t *img;
    size_t bytes, nin, k = 0;
    const uint8_t *pix;
    int rows, cols, stride, qmode, imode, sel, maxcorr, model, rc, rc2, judge, maxc, i, x, y;
    int image_ok, fam_ok, corr_ok, fp_ok, moderate, nfam = actag_family_count(), tag_id = 0;
    float cx, cy, half, ang;

    fz_init(&r, data, size);
    rows = fz_int(&r, 48, 1, FZQ_MAX);
    cols = fz_int(&r, 48, 1, FZQ_MAX);
    {
        int64_t st64 = (int64_t)cols + fz_int(&r, 0, 0, 8);
        stride = st64 > INT_MAX ? INT_MAX : st64 < INT_MIN ? INT_MIN : (int)st64;
    }
    imode = fz_u8(&r) % 3;
    qmode = fz_u8(&r) % 10;
    cx = fz_float(&r, 24.0f, -10.0f, 100.0f);
    cy = fz_float(&r, 24.0f, -10.0f, 100.0f);
    half = fz_float(&r, 9.0f, 0.0f, 60.0f);
    ang = fz_float(&r, 0.0f, -3.2f, 3.2f);
    sel = fz_u8(&r);
    maxcorr = fz_int(&r, 2, -1, 5);
    model = fz_int(&r, 0, 0, 1);
    actag_fit_params_default(&fp);
    fp.flags = fz_int(&r, fp.flags, 0, 255);
    fp.level = fz_float(&r, fp.level, 0.0f, 1.0f);
    fp.min_contrast = fz_int(&r, fp.min_contrast, 0, 255);
    fp.sample_offset = fz_float(&r, fp.sample_offset, 0.0f, 0.5f);
    fp.min_margin = fz_float(&r, fp.min_margin, -10.0f, 30.0f);
    fp.min_bit_margin = fz_int(&r, fp.min_bit_margin, 0, 32);
    fp.many_corrections = fz_int(&r, fp.many_corrections, 0, 33);
    /* fp.min_bit_odds keeps its default: a field read here would move the
     * corpus' later bytes (test_decode checks actag_fit_bit_lead on every
     * valid input) */

    /* family: built-in, or an invalid one */
    actag_family_get_at((sel >> 2) % nfam, &fam);
    switch (sel & 3) {
    case 3:
        switch ((sel >> 2) & 3) {
        case 0: fam.bits = 36; break;
        case 1: fam.ncodes = 0; break;
        case 2: fam.codes = NULL; break;
        default: fam.hamming = 0; break;
        }
        break;
    default: break;
    }
    fam_ok = actag_family_validate(&fam) == ACTAG_OK;
    maxc = fam_ok ? actag_family_max_corrections(&fam) : 0;
    corr_ok = maxcorr >= 0 && maxcorr <= maxc;
    fp_ok = fp.min_contrast >= 0 && fp.min_contrast <= 255 && fp.level >= 0.0f &&
            fp.level <= 1.0f && fp.sample_offset >= 0.0f && fp.sample_offset <= 0.5f &&
            fp.min_margin >= -1.0e6f && fp.min_margin <= 1.0e6f && fp.min_bit_margin >= 0 &&
            fp.min_bit_margin <= 32 && fp.many_corrections >= 0 && fp.many_corrections <= 33 &&
            !((fp.flags & ACTAG_FIT_ONLY_UNMIRRORED) && (fp.flags & ACTAG_FIT_ONLY_MIRRORED));

    /* the quad */
    {
        float c = cosf(ang), s = sinf(ang);
        float sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
        for (i = 0; i < 4; i++) {
            quad[i].x = cx + half * (c * sx[i] - s * sy[i]);
            quad[i].y = cy + half * (s * sx[i] + c * sy[i]);
        }
        switch (qmode) {
        case 0: /* free corners */
            for (i = 0; i < 4; i++) {
                quad[i].x = fz_float(&r, quad[i].x, -20.0f, 120.0f);
                quad[i].y = fz_float(&r, quad[i].y, -20.0f, 120.0f);
            }
            break;
        case 1: break; /* the square (clockwise on screen) */
        case 2: { actag_point t = quad[1]; quad[1] = quad[3]; quad[3] = t; } break; /* ccw */
        case 3: quad[2] = quad[1]; break;                               /* duplicate */
        case 4: /* three collinear */
            quad[2].x = 2.0f * quad[1].x - quad[0].x;
            quad[2].y = 2.0f * quad[1].y - quad[0].y;
            break;
        case 5: { actag_point t = quad[1]; quad[1] = quad[2]; quad[2] = t; } break; /* bow-tie */
        case 6: /* concave */
            quad[2].x = 0.5f * (quad[0].x + quad[2].x) + 0.1f * (quad[0].x - quad[2].x);
            quad[2].y = 0.5f * (quad[0].y + quad[2].y) + 0.1f * (quad[0].y - quad[2].y);
            break;
        case 7: /* tiny */
            for (i = 0; i < 4; i++) {
                quad[i].x = cx + (quad[i].x - cx) * 1e-4f;
                quad[i].y = cy + (quad[i].y - cy) * 1e-4f;
            }
            break;
        case 8: /* huge */
            for (i = 0; i < 4; i++) {
                quad[i].x *= 1e18f;
                quad[i].y *= 1e18f;
            }
            break;
        default: { /* two reads, in this order (one expression left it to the compiler) */
            int corner = fz_u8(&r) & 3;
            quad[corner].y = (fz_u8(&r) & 1) ? NAN : -INFINITY;
            break;
        }
        }
    }
    judge = judge_quad(quad);
    moderate = 1;
    for (i = 0; i < 4; i++)
        moderate &= fabsf(quad[i].x) < 1e6f && fabsf(quad[i].y) < 1e6f;

    /* the image (tight, guarded) */
    image_ok = rows >= 1 && cols >= 1 && rows <= ACTAG_MAX_DIM && cols <= ACTAG_MAX_DIM &&
               stride >= cols;
    if (image_ok && rows > 1 && (uint64_t)(rows - 1) * (uint64_t)stride > (1u << 22))
        rows = 1 + (int)((1u << 22) / (uint64_t)stride); /* keep the buffer small */
    bytes = image_ok ? (size_t)(rows - 1) * (size_t)stride + (size_t)cols : 16;
    img = fz_guard_alloc(&gimg, bytes, fz_u8(&r));
    pix = fz_rest(&r, &nin);
    for (i = 0; i < (int)bytes; i++)
        img[i] = nin ? pix[k++ % nin] : (uint8_t)(i * 31);
    if (image_ok && imode == 1 && fam_ok && fam.bits / 4 <= ACTAG_DECODE_MAX_K &&
        fabsf(cx) < 1000.0f && fabsf(cy) < 1000.0f && half > 0.0f && half < 100.0f) {
        /* a tag whose white square is about the square quad */
        int kk = fam.bits / 4, cell = (int)(2.0f * half / (float)(kk - 3) + 0.5f);
        if (cell >= 1 && cell <= 20) {
            int side = actag_render_side(fam.bits, cell, 0);
            uint8_t *t = (uint8_t *)malloc((size_t)side * (size_t)side);
            tag_id = (int)(nin ? pix[0] : 0) % fam.ncodes;
            if (t && actag_render_tag(&fam, tag_id, cell, 0, 0, 0, t, side,
                                      (size_t)side * (size_t)side) == ACTAG_OK) {
                int ox = (int)(cx - (float)side * 0.5f), oy = (int)(cy - (float)side * 0.5f);
                for (y = 0; y < side; y++)
                    for (x = 0; x < side; x++)
                        if (oy + y >= 0 && oy + y < rows && ox + x >= 0 && ox + x < cols)
                            img[(size_t)(oy + y) * (size_t)stride + (size_t)(ox + x)] =
                                t[(size_t)y * (size_t)side + (size_t)x];
            }
            free(t);
        }
    }
    {
        uint8_t *copy = (uint8_t *)malloc(bytes);
        FZ_CHECK(copy != NULL, "oom");
        memcpy(copy, img, bytes);

        /* grid maps */
        rc = actag_tag_affine(quad, fam.bits, H);
        FZ_CHECK(rc == ACTAG_OK || rc == ACTAG_ERR_PARAM, "affine %d", rc);
        if (fam.bits >= 16 && fam.bits <= 32 && fam.bits % 4 == 0) {
            if (judge == 0)
                FZ_CHECK(rc == ACTAG_ERR_PARAM, "affine map of a degenerate quad accepted");
            if ((judge == 1 || judge == -1) && moderate)
                FZ_CHECK(rc == ACTAG_OK, "affine map of a convex quad refused");
        }
        if (rc == ACTAG_OK)
            for (i = 0; i < 9; i++)
                FZ_CHECK(isfinite(H[i]), "affine H[%d] not finite", i);
        rc = actag_tag_homography(quad, fam.bits, H);
        FZ_CHECK(rc == ACTAG_OK || rc == ACTAG_ERR_PARAM, "homography %d", rc);
        if (rc == ACTAG_OK) {
            for (i = 0; i < 9; i++)
                FZ_CHECK(isfinite(H[i]), "homography H[%d] not finite", i);
            FZ_CHECK(judge != 0, "homography of a degenerate quad accepted");
        }
        rc = actag_decode_bit_positions(quad, fam.bits, pos);
        FZ_CHECK(rc == ACTAG_OK || rc == ACTAG_ERR_PARAM, "bit positions %d", rc);

        /* the raw word */
        rc = actag_decode_read_word(img, rows, cols, stride, quad, fam.bits, model, &word);
        if (!image_ok)
            FZ_CHECK(rc == ACTAG_ERR_SIZE, "read_word on a bad image: %d", rc);
        else
            FZ_CHECK(rc == ACTAG_OK || rc == ACTAG_ERR_PARAM, "read_word %d", rc);
        if (rc == ACTAG_OK)
            FZ_CHECK((word & ~actag_code_mask(fam.bits)) == 0u, "word beyond the bits");

        /* the binary decoder, both models */
        for (i = 0; i < 2; i++) {
            memset(&d1, 0, sizeof d1);
            memset(&d2, 0, sizeof d2);
            rc = actag_decode_quad_ex(img, rows, cols, stride, quad, &fam, maxcorr, i, &d1);
            rc2 = actag_decode_quad_ex(img, rows, cols, stride, quad, &fam, maxcorr, i, &d2);
            FZ_CHECK(rc == rc2 && memcmp(&d1, &d2, sizeof d1) == 0, "decode not repeatable");
            if (!image_ok)
                FZ_CHECK(rc == ACTAG_ERR_SIZE, "decode on a bad image: %d", rc);
            else if (!fam_ok)
                FZ_CHECK(rc == ACTAG_ERR_FAMILY, "decode with a bad family: %d", rc);
            else if (!corr_ok)
                FZ_CHECK(rc == ACTAG_ERR_CORRECTIONS, "decode with bad corrections: %d", rc);
            else if (judge == 0)
                FZ_CHECK(rc == ACTAG_ERR_PARAM, "decode of a degenerate quad: %d", rc);
            else
                FZ_CHECK(rc == ACTAG_OK || rc == ACTAG_ERR_NO_MATCH || rc == ACTAG_ERR_PARAM,
                         "decode %d", rc);
            if (i == 0 && (judge == 1 || judge == -1) && image_ok && fam_ok && corr_ok &&
                moderate)
                FZ_CHECK(rc != ACTAG_ERR_PARAM, "affine decode of a convex quad refused");
            if (rc == ACTAG_OK)
                check_result(&d1, quad, judge, &fam, maxcorr, 1, 1);
        }
        FZ_CHECK(actag_decode_quad(img, rows, cols, stride, quad, &fam, maxcorr, &d2) ==
                     actag_decode_quad_ex(img, rows, cols, stride, quad, &fam, maxcorr,
                                          ACTAG_DECODE_DEFAULT_MODEL, &d1),
                 "decode_quad is not decode_quad_ex with the default model");

        /* the grid-fitting decoder */
        memset(&d1, 0, sizeof d1);
        memset(&d2, 0, sizeof d2);
        rc = actag_decode_quad_fit(img, rows, cols, stride, quad, &fam, maxcorr, &fp, &d1);
        rc2 = actag_decode_quad_fit(img, rows, cols, stride, quad, &fam, maxcorr, &fp, &d2);
        FZ_CHECK(rc == rc2 && memcmp(&d1, &d2, sizeof d1) == 0, "fit decode not repeatable");
        if (!image_ok)
            FZ_CHECK(rc == ACTAG_ERR_SIZE, "fit on a bad image: %d", rc);
        else if (!fam_ok)
            FZ_CHECK(rc == ACTAG_ERR_FAMILY, "fit with a bad family: %d", rc);
        else if (!fp_ok)
            FZ_CHECK(rc == ACTAG_ERR_PARAM, "fit with bad options: %d", rc);
        else if (!corr_ok)
            FZ_CHECK(rc == ACTAG_ERR_CORRECTIONS, "fit with bad corrections: %d", rc);
        else if (judge == 0)
            FZ_CHECK(rc == ACTAG_ERR_PARAM, "fit of a degenerate quad: %d", rc);
        else
            FZ_CHECK(rc == ACTAG_OK || rc == ACTAG_ERR_NO_MATCH || rc == ACTAG_ERR_PARAM,
                     "fit %d", rc);
        if ((judge == 1 || judge == -1) && image_ok && fam_ok && corr_ok && fp_ok && moderate)
            FZ_CHECK(rc != ACTAG_ERR_PARAM, "fit of a convex quad refused");
        if (rc == ACTAG_OK) {
            check_result(&d1, quad, judge, &fam, maxcorr, 1, 0);
            for (i = 0; i < 4; i++)
                FZ_CHECK(isfinite(d1.fit_corners[i].x) && isfinite(d1.fit_corners[i].y),
                         "fit corner %d not finite", i);
        }
        (void)tag_id;

        fz_guard_check(&gimg, "image");
        FZ_CHECK(memcmp(copy, img, bytes) == 0, "image modified");
        free(copy);
    }
    /* NULL arguments */
    FZ_CHECK(actag_decode_quad_fit(NULL, rows, cols, stride, quad, &fam, maxcorr, &fp, &d1) ==
                 ACTAG_ERR_NULL, "NULL image");
    FZ_CHECK(actag_decode_quad_ex(img, rows, cols, stride, NULL, &fam, maxcorr, 0, &d1) ==
                 ACTAG_ERR_NULL, "NULL quad");
    FZ_CHECK(actag_decode_quad(img, rows, cols, stride, quad, NULL, maxcorr, &d1) ==
                 ACTAG_ERR_NULL, "NULL family");
    FZ_CHECK(actag_decode_read_word(img, rows, cols, stride, quad, fam.bits, model, NULL) ==
                 ACTAG_ERR_NULL, "NULL word");
    fz_guard_free(&gimg);
    return 0;
}
