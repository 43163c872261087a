/* actag_apriltag.c -- AcTag families for AprilTag 3 (see actag/actag_apriltag.h). */
#include "actag/actag_apriltag.h"

#include <apriltag/apriltag_pose.h>

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "actag/family.h"

/* actag_apriltag_families.h is written by optical/CMakeLists.txt into the
 * build tree: one X(<name>) per entry of ACTAG_FAMILIES. Each name has a
 * generated actag_apriltag_family_<name>() (actag-familygen --format apriltag). */
#define X(n) apriltag_family_t *actag_apriltag_family_##n(void);
#include "actag_apriltag_families.h"
#undef X

typedef apriltag_family_t *(*actag_apriltag_getter)(void);

static const actag_apriltag_getter actag_apriltag_getters[] = {
#define X(n) actag_apriltag_family_##n,
#include "actag_apriltag_families.h"
#undef X
};

#define ACTAG_APRILTAG_NFAM \
    ((int)(sizeof(actag_apriltag_getters) / sizeof(actag_apriltag_getters[0])))

int actag_apriltag_family_count(void)
{
    return ACTAG_APRILTAG_NFAM;
}

const char *actag_apriltag_family_name(int i)
{
    if (i < 0 || i >= ACTAG_APRILTAG_NFAM)
        return NULL;
    return actag_apriltag_getters[i]()->name;
}

apriltag_family_t *actag_apriltag_family(const char *name)
{
    int i;
    if (name == NULL)
        return NULL;
    for (i = 0; i < ACTAG_APRILTAG_NFAM; i++) {
        apriltag_family_t *f = actag_apriltag_getters[i]();
        if (strcmp(f->name, name) == 0)
            return f;
    }
    return NULL;
}

apriltag_family_t *actag_apriltag_family_create(const char *name)
{
    const apriltag_family_t *src = actag_apriltag_family(name);
    apriltag_family_t *f;
    if (src == NULL)
        return NULL;
    f = (apriltag_family_t *)malloc(sizeof(*f));
    if (f == NULL)
        return NULL;
    /* Shallow copy: AprilTag only reads codes, bit_x, bit_y and name; the one
     * field it writes is impl, which must be private to each copy. */
    *f = *src;
    f->impl = NULL;
    return f;
}

void actag_apriltag_family_destroy(apriltag_family_t *fam)
{
    int i;
    if (fam == NULL)
        return;
    for (i = 0; i < ACTAG_APRILTAG_NFAM; i++)
        if (fam == actag_apriltag_getters[i]())
            return; /* static object: never freed */
    free(fam);
}

int actag_apriltag_max_bits_corrected(const apriltag_family_t *fam)
{
    int h, m;
    if (fam == NULL)
        return -1;
    h = (int)fam->h;
    m = (h % 2 == 0) ? h / 2 - 1 : h / 2; /* SPEC section 3 */
    if (m > 3)
        m = 3; /* AprilTag's quick-decode table stops at 3 */
    if (m < 0)
        m = 0;
    return m;
}

/* Smallest image side AprilTag 3.3 handles: its threshold stage works on
 * 4 x 4 tiles of the decimated image and indexes before a zero-size tile
 * array when a side has fewer than 4 decimated pixels. */
#define ACTAG_APRILTAG_MIN_DECIMATED 4

/* ------------------------------------------------------------ mirror check
 * See "MIRRORED TAGS" in actag/actag_apriltag.h. The tag's cells are read
 * again through det->H: AprilTag's tag coordinates run from -1 to 1 across
 * the quad (the inner white square, width_at_border cells), so the centre of
 * cell (bx, by) (bit_x / bit_y of the family: -2 .. width_at_border + 1) is
 * at ((2 bx + 1) / wab - 1, (2 by + 1) / wab - 1); det->H already includes
 * the rotation AprilTag decoded, so a right reading returns the reported
 * code itself (not a rotation). Pixel centres at +0.5, as AprilTag's. */

#define ACTAG_AT_MAX_W 9 /* total_width of a 32-bit family */
/* Black-ring and interior cells that may read on the wrong side of the mid
 * level or lie outside the image (of 25 for 24-bit tags, 36 for 28-bit
 * ones). Renders and noisy projective views of tags read 0, AprilTag's
 * bogus quads on clutter and noise 8-14. */
#define ACTAG_AT_MAX_STRUCTURE_MISSES 2

/* Is cell (x, y) (0 .. tw-1, the data ring at 0 and tw-1) one of the black
 * ring's 4 corner cells, where the tag's screws go (tools/render
 * --screw-holes, docs/construction.md)? */
static int screw_cell(int x, int y, int tw)
{
    return (x == 1 || x == tw - 2) && (y == 1 || y == tw - 2);
}

/* A position of the generated bit_x / bit_y tables (negative numbers stored
 * as uint32_t) as int, without implementation-defined conversions. */
static int cell_pos(uint32_t v)
{
    return v > (uint32_t)INT32_MAX ? -(int)(~v) - 1 : (int)v;
}

/* Bilinear grey level at AprilTag pixel coordinates (px, py); 0 when the
 * point lies outside the pixel centres of the image. */
static int sample_at(const image_u8_t *im, double px, double py, double *v)
{
    double x = px - 0.5, y = py - 0.5, fx, fy;
    int x1, y1, x2, y2;
    const uint8_t *r1, *r2;
    if (!(x >= 0.0 && y >= 0.0 && x <= (double)(im->width - 1) &&
          y <= (double)(im->height - 1)))
        return 0; /* NaN too */
    x1 = (int)x;
    y1 = (int)y;
    fx = x - (double)x1;
    fy = y - (double)y1;
    x2 = x1 + 1 < im->width ? x1 + 1 : x1;
    y2 = y1 + 1 < im->height ? y1 + 1 : y1;
    r1 = im->buf + (size_t)y1 * (size_t)im->stride;
    r2 = im->buf + (size_t)y2 * (size_t)im->stride;
    *v = ((double)r1[x1] * (1.0 - fx) + (double)r1[x2] * fx) * (1.0 - fy) +
         ((double)r2[x1] * (1.0 - fx) + (double)r2[x2] * fx) * fy;
    return 1;
}

/* Least-squares plane v = a tx + b ty + c of one cell class (AprilTag's
 * "graymodel"); the mean when the points do not fix a plane. */
typedef struct {
    double s[3][3], r[3], c[3];
    int n;
} grey_plane;

static void plane_add(grey_plane *g, double tx, double ty, double v)
{
    double p[3];
    int i, j;
    p[0] = tx;
    p[1] = ty;
    p[2] = 1.0;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++)
            g->s[i][j] += p[i] * p[j];
        g->r[i] += p[i] * v;
    }
    g->n++;
}

static double det3(double m[3][3])
{
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

static void plane_solve(grey_plane *g)
{
    double d = det3(g->s);
    int i, j, col;
    g->c[0] = g->c[1] = 0.0;
    g->c[2] = g->n > 0 ? g->r[2] / (double)g->n : 0.0;
    /* s[2][2] = n; the determinant scales with n^3 (tag coordinates are
     * about +-1): a relative floor against collinear points */
    if (g->n < 3 || !(fabs(d) > 1e-6 * (double)g->n * (double)g->n * (double)g->n))
        return;
    for (col = 0; col < 3; col++) { /* Cramer's rule */
        double m[3][3];
        for (i = 0; i < 3; i++)
            for (j = 0; j < 3; j++)
                m[i][j] = j == col ? g->r[i] : g->s[i][j];
        g->c[col] = det3(m) / d;
    }
}

static double plane_at(const grey_plane *g, double tx, double ty)
{
    return g->c[0] * tx + g->c[1] * ty + g->c[2];
}

/* x with its lowest d set bits cleared, d = 0 .. 3 (0 when x has at most
 * d bits set). */
static uint32_t clear_low_bits(uint32_t x, int d)
{
    if (d >= 1)
        x &= x - 1;
    if (d >= 2)
        x &= x - 1;
    if (d >= 3)
        x &= x - 1;
    return x;
}

/* 1 when a code of fam lies within d (0 .. 3) bits of one of the words
 * q[0..3] over the bits set in k[0..3]. Branch-free over blocks of codes,
 * which compilers vectorise (the largest built-in families hold 6,261 and
 * 8,910 codes: about 3 us at -O3). */
static int scan_codes(const apriltag_family_t *fam, const uint32_t q[4], const uint32_t k[4],
                      int d)
{
    const uint64_t *codes = fam->codes;
    uint32_t j, n = fam->ncodes;
    for (j = 0; j < n;) {
        uint32_t end = n - j > 256 ? j + 256 : n, hit = 0;
        for (; j < end; j++) {
            uint32_t c = (uint32_t)codes[j];
            hit |= (uint32_t)(clear_low_bits((q[0] ^ c) & k[0], d) == 0) |
                   (uint32_t)(clear_low_bits((q[1] ^ c) & k[1], d) == 0) |
                   (uint32_t)(clear_low_bits((q[2] ^ c) & k[2], d) == 0) |
                   (uint32_t)(clear_low_bits((q[3] ^ c) & k[3], d) == 0);
        }
        if (hit)
            return 1;
    }
    return 0;
}

/* 1 when some code of fam, in some rotation, lies within d bits of q over
 * the bits set in qk. */
static int any_code_within(const apriltag_family_t *fam, uint32_t q, uint32_t qk, int d)
{
    uint32_t qr[4], kr[4], j;
    int r;
    for (r = 0; r < 4; r++) {
        qr[r] = q;
        kr[r] = qk;
        q = actag_code_rot90(q, (int)fam->nbits);
        qk = actag_code_rot90(qk, (int)fam->nbits);
    }
    /* one call per d, so that each loop is compiled with a constant d */
    switch (d) {
    case 0:
        return scan_codes(fam, qr, kr, 0);
    case 1:
        return scan_codes(fam, qr, kr, 1);
    case 2:
        return scan_codes(fam, qr, kr, 2);
    case 3:
        return scan_codes(fam, qr, kr, 3);
    default: /* a re-read 4 or more bits from the reported code: rare */
        for (j = 0; j < fam->ncodes; j++)
            for (r = 0; r < 4; r++)
                if (actag_popcount32((qr[r] ^ (uint32_t)fam->codes[j]) & kr[r]) <= d)
                    return 1;
        return 0;
    }
}

/* The built-in family det belongs to (a static family or a copy: copies
 * share the code table), or NULL. */
static const apriltag_family_t *actag_family_of(const apriltag_detection_t *det)
{
    int i;
    if (det->family == NULL)
        return NULL;
    for (i = 0; i < ACTAG_APRILTAG_NFAM; i++) {
        const apriltag_family_t *f = actag_apriltag_getters[i]();
        if (det->family == f || det->family->codes == f->codes)
            return f;
    }
    return NULL;
}

static int mirror_check(const apriltag_detection_t *det, const image_u8_t *im,
                        double sharpening)
{
    const apriltag_family_t *fam;
    const matd_t *H;
    double val[ACTAG_AT_MAX_W][ACTAG_AT_MAX_W], sharp[ACTAG_AT_MAX_W][ACTAG_AT_MAX_W];
    double tc[ACTAG_AT_MAX_W];
    int have[ACTAG_AT_MAX_W][ACTAG_AT_MAX_W];
    grey_plane black, white;
    uint32_t word = 0, keep = 0, q, qk, code;
    int nbits, wab, tw, x, y, i, d0, misses;

    if (det == NULL || im == NULL || im->buf == NULL || im->width < 1 || im->height < 1 ||
        im->stride < im->width)
        return -1;
    fam = actag_family_of(det);
    if (fam == NULL)
        return -1;
    nbits = (int)fam->nbits;
    wab = (int)fam->width_at_border;
    tw = (int)fam->total_width;
    /* the AcTag layout (SPEC section 2): 4k bits, k+1 cells, ring at -2 */
    if (nbits % 4 != 0 || nbits < 16 || nbits > 32 || tw != nbits / 4 + 1 || wab != tw - 4 ||
        tw > ACTAG_AT_MAX_W || !fam->reversed_border)
        return -1;
    H = det->H;
    if (det->id < 0 || det->id >= (int)fam->ncodes || H == NULL || H->nrows != 3 ||
        H->ncols != 3)
        return 2; /* nothing to check the reading against */

    /* every cell of the tag: the grey level at its centre (where AprilTag
     * reads it: several points a cell read a data-ring corner bit otherwise
     * when the quad is a quarter cell off, a review found) */
    memset(&black, 0, sizeof black);
    memset(&white, 0, sizeof white);
    for (i = 0; i < tw; i++)
        tc[i] = (2.0 * (double)(i - 2) + 1.0) / (double)wab - 1.0;
    for (y = 0; y < tw; y++)
        for (x = 0; x < tw; x++) {
            double px = 0, py = 0, z;
            val[y][x] = 0.0;
            z = MATD_EL(H, 2, 0) * tc[x] + MATD_EL(H, 2, 1) * tc[y] + MATD_EL(H, 2, 2);
            have[y][x] = 0;
            if (fabs(z) > 1e-12) {
                px = (MATD_EL(H, 0, 0) * tc[x] + MATD_EL(H, 0, 1) * tc[y] + MATD_EL(H, 0, 2)) / z;
                py = (MATD_EL(H, 1, 0) * tc[x] + MATD_EL(H, 1, 1) * tc[y] + MATD_EL(H, 1, 2)) / z;
                have[y][x] = sample_at(im, px, py, &val[y][x]);
            }
            if (!have[y][x] || x == 0 || y == 0 || x == tw - 1 || y == tw - 1 ||
                screw_cell(x, y, tw))
                continue; /* the data ring; the screws' cells */
            if (x == 1 || y == 1 || x == tw - 2 || y == tw - 2)
                plane_add(&black, tc[x], tc[y], val[y][x]);
            else
                plane_add(&white, tc[x], tc[y], val[y][x]);
        }
    plane_solve(&black);
    plane_solve(&white);
    if (black.n == 0 || white.n == 0 || !(plane_at(&white, 0, 0) > plane_at(&black, 0, 0)))
        return 2; /* no contrast to read the bits by */
    /* each cell against the mid level there, then AprilTag's sharpening (its
     * decode_sharpening: v + s * (4 v - the 4 neighbours in the grid)) */
    for (y = 0; y < tw; y++)
        for (x = 0; x < tw; x++)
            if (have[y][x])
                val[y][x] -= 0.5 * (plane_at(&black, tc[x], tc[y]) + plane_at(&white, tc[x], tc[y]));
    for (y = 0; y < tw; y++)
        for (x = 0; x < tw; x++) {
            double lap = 4.0 * val[y][x];
            if (x > 0)
                lap -= val[y][x - 1];
            if (x < tw - 1)
                lap -= val[y][x + 1];
            if (y > 0)
                lap -= val[y - 1][x];
            if (y < tw - 1)
                lap -= val[y + 1][x];
            sharp[y][x] = val[y][x] + sharpening * lap;
        }
    /* the tag's own structure must read as such when AprilTag corrected
     * bits: a quad on clutter or noise that AprilTag read as a code (its
     * reading has no mid level to speak of) has no reading to check. Not
     * the 4 black-ring corner cells, which hold the tag's screws; not a
     * reading of no corrected bit (a right code read whole: an occluder
     * on the interior must not cost it) */
    misses = 0;
    for (y = 1; y < tw - 1; y++)
        for (x = 1; x < tw - 1; x++) {
            int ring = x == 1 || y == 1 || x == tw - 2 || y == tw - 2;
            if (screw_cell(x, y, tw))
                continue;
            if (!have[y][x] || (ring ? sharp[y][x] >= 0.0 : sharp[y][x] <= 0.0))
                misses++;
        }
    if (det->hamming > 0 && misses > ACTAG_AT_MAX_STRUCTURE_MISSES)
        return 2;
    /* the word, bit i of the sequence = code bit nbits-1-i (AprilTag's order) */
    for (i = 0; i < nbits; i++) {
        int bx = cell_pos(fam->bit_x[i]) + 2, by = cell_pos(fam->bit_y[i]) + 2;
        word <<= 1;
        keep <<= 1;
        if (bx < 0 || by < 0 || bx >= tw || by >= tw)
            return -1; /* not the AcTag layout */
        if (have[by][bx]) {
            keep |= 1u;
            if (sharp[by][bx] > 0.0)
                word |= 1u;
        }
    }
    code = (uint32_t)fam->codes[det->id];
    d0 = actag_popcount32((word ^ code) & keep);
    /* every mirrored view P(rot90^r(c)) of every code c: its distance to
     * word is that of rot90^-r(c) to P(word) (P permutes positions) */
    q = actag_code_mirror(word, nbits);
    qk = actag_code_mirror(keep, nbits);
    return any_code_within(fam, q, qk, d0);
}

int actag_apriltag_mirror_check(const apriltag_detection_t *det, const image_u8_t *im)
{
    return mirror_check(det, im, ACTAG_APRILTAG_SHARPENING);
}

zarray_t *actag_apriltag_detect(apriltag_detector_t *td, image_u8_t *im)
{
    zarray_t *dets;
    float d;
    int min_side, i;
    if (td == NULL || im == NULL || im->buf == NULL || im->width < 1 || im->height < 1 ||
        im->stride < im->width)
        return NULL;
    d = td->quad_decimate > 1.0f ? td->quad_decimate : 1.0f;
    /* 4 * d, rounded up (d is a float the caller may set to anything > 1) */
    min_side = d < 1.0e6f ? (int)(ACTAG_APRILTAG_MIN_DECIMATED * d) : 1 << 30;
    if ((float)min_side < ACTAG_APRILTAG_MIN_DECIMATED * d)
        min_side++;
    if (im->width < min_side || im->height < min_side)
        return zarray_create(sizeof(apriltag_detection_t *));
    dets = apriltag_detector_detect(td, im);
    /* readings a mirrored view explains at least as well: dropped, in place
     * (the order of the others kept) */
    for (i = 0; dets != NULL && i < zarray_size(dets); i++) {
        apriltag_detection_t *det;
        zarray_get(dets, i, &det);
        if (mirror_check(det, im, (double)td->decode_sharpening) > 0) {
            apriltag_detection_destroy(det);
            zarray_remove_index(dets, i, 0);
            i--;
        }
    }
    return dets;
}

void actag_apriltag_invert(image_u8_t *im)
{
    int x, y;
    /* the sizes actag_apriltag_detect takes; others are left alone */
    if (im == NULL || im->buf == NULL || im->width < 1 || im->height < 1 ||
        im->stride < im->width)
        return;
    for (y = 0; y < im->height; y++) {
        uint8_t *row = im->buf + (size_t)y * (size_t)im->stride;
        for (x = 0; x < im->width; x++)
            row[x] = (uint8_t)(255 - row[x]);
    }
}

void actag_apriltag_corners_to_actag(const apriltag_detection_t *det, double out[4][2])
{
    int i;
    if (det == NULL || out == NULL)
        return;
    /* AprilTag: p[0..3] = tag points (-1,1) (1,1) (1,-1) (-1,-1), with tag y
     * pointing to the printed bottom: bottom-left, bottom-right, top-right,
     * top-left. AcTag: top-left first, clockwise as printed -> p[3], p[2],
     * p[1], p[0]. AprilTag puts pixel centres at +0.5, actag at integers. */
    for (i = 0; i < 4; i++) {
        out[i][0] = det->p[3 - i][0] - 0.5;
        out[i][1] = det->p[3 - i][1] - 0.5;
    }
}

/* The smaller of the angles (radians) between the camera rays through the
 * detection's opposite corners: AprilTag's orthogonal iteration inverts a
 * matrix that is singular when the rays are (nearly) parallel, and then
 * asserts (it aborted below about 1e-4 rad, whatever the tag size). */
static double ray_spread(const apriltag_detection_t *det, double fx, double fy, double cx,
                         double cy)
{
    double v[4][3], least = 1e30;
    int i, d;
    for (i = 0; i < 4; i++) {
        double n;
        v[i][0] = (det->p[i][0] - cx) / fx;
        v[i][1] = (det->p[i][1] - cy) / fy;
        v[i][2] = 1.0;
        n = sqrt(v[i][0] * v[i][0] + v[i][1] * v[i][1] + 1.0);
        for (d = 0; d < 3; d++)
            v[i][d] /= n;
    }
    for (i = 0; i < 2; i++) {
        const double *a = v[i], *b = v[i + 2];
        double cr[3], sn, cs, ang;
        cr[0] = a[1] * b[2] - a[2] * b[1];
        cr[1] = a[2] * b[0] - a[0] * b[2];
        cr[2] = a[0] * b[1] - a[1] * b[0];
        sn = sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
        cs = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        ang = atan2(sn, cs);
        if (!(ang >= least)) /* NaN too */
            least = ang;
    }
    return least;
}

double actag_apriltag_pose(const apriltag_detection_t *det, double tag_size,
                          double fx, double fy, double cx, double cy,
                          double R[9], double t[3])
{
    apriltag_detection_info_t info;
    apriltag_pose_t pose;
    double err;
    unsigned r, q;
    /* Bounds first: AprilTag's estimate_tag_pose() asserts (aborts the
     * process) when its matrices degenerate, as they do for non-finite or
     * extreme intrinsics (a principal point at 1e7 px, fx 1e7, tag_size
     * 1e-300). */
    if (det == NULL || R == NULL || t == NULL ||
        !(tag_size >= ACTAG_APRILTAG_MIN_TAG_SIZE && tag_size <= ACTAG_APRILTAG_MAX_TAG_SIZE) ||
        !(fx >= ACTAG_APRILTAG_MIN_FOCAL && fx <= ACTAG_APRILTAG_MAX_FOCAL) ||
        !(fy >= ACTAG_APRILTAG_MIN_FOCAL && fy <= ACTAG_APRILTAG_MAX_FOCAL) ||
        !(cx >= -ACTAG_APRILTAG_MAX_CENTRE && cx <= ACTAG_APRILTAG_MAX_CENTRE) ||
        !(cy >= -ACTAG_APRILTAG_MAX_CENTRE && cy <= ACTAG_APRILTAG_MAX_CENTRE) ||
        !(ray_spread(det, fx, fy, cx + 0.5, cy + 0.5) >= ACTAG_APRILTAG_MIN_SPREAD))
        return -1.0;
    /* estimate_tag_pose() only reads the detection. */
    info.det = (apriltag_detection_t *)(uintptr_t)det;
    info.tagsize = tag_size;
    info.fx = fx;
    info.fy = fy;
    info.cx = cx + 0.5; /* AprilTag's pixel centres are at +0.5 */
    info.cy = cy + 0.5;
    pose.R = NULL;
    pose.t = NULL;
    err = estimate_tag_pose(&info, &pose);
    if (pose.R != NULL && pose.t != NULL && pose.R->nrows == 3 && pose.R->ncols == 3 &&
        pose.t->nrows == 3 && pose.t->ncols == 1 && err >= 0) {
        for (r = 0; r < 3; r++) {
            for (q = 0; q < 3; q++)
                R[3 * r + q] = MATD_EL(pose.R, r, q);
            t[r] = MATD_EL(pose.t, r, 0);
        }
    } else {
        err = -1.0;
    }
    /* matd_t is one calloc'ed block (flexible array member), so free() is
     * what matd_destroy() does; Debian's libraries do not export the latter. */
    free(pose.R);
    free(pose.t);
    return err;
}

int actag_apriltag_pose_sensor(const apriltag_detection_t *det, double tag_size, double fx,
                               double fy, double cx, double cy, actag_pose *out)
{
    double R[9], t[3], err;
    float Rf[9], tf[3];
    int i, rc;
    if (det == NULL || out == NULL)
        return ACTAG_ERR_NULL;
    err = actag_apriltag_pose(det, tag_size, fx, fy, cx, cy, R, t);
    if (err < 0)
        return ACTAG_ERR_PARAM;
    for (i = 0; i < 9; i++)
        Rf[i] = (float)R[i];
    for (i = 0; i < 3; i++)
        tf[i] = (float)t[i];
    rc = actag_pose_from_camera(Rf, tf, out);
    if (rc == ACTAG_OK)
        out->residual = (float)err;
    return rc;
}

int actag_apriltag_pose_sensor_cov(const apriltag_detection_t *det, double tag_size, double fx,
                                   double fy, double cx, double cy, double pixel_sd,
                                   actag_pose *out)
{
    actag_pose p;
    double c[4][2];
    float cf[8];
    int i, rc;
    if (det == NULL || out == NULL)
        return ACTAG_ERR_NULL;
    /* pixel_sd first: nothing is estimated for a call that must fail */
    if (!(pixel_sd >= ACTAG_POSE_PIXEL_SD_MIN && pixel_sd <= ACTAG_POSE_PIXEL_SD_MAX))
        return ACTAG_ERR_PARAM;
    rc = actag_apriltag_pose_sensor(det, tag_size, fx, fy, cx, cy, &p);
    if (rc != ACTAG_OK)
        return rc;
    actag_apriltag_corners_to_actag(det, c);
    for (i = 0; i < 4; i++) {
        cf[2 * i] = (float)c[i][0];
        cf[2 * i + 1] = (float)c[i][1];
    }
    rc = actag_pose_camera_covariance(cf, (float)fx, (float)fy, (float)cx, (float)cy,
                                      (float)pixel_sd, (float)tag_size, &p);
    if (rc == ACTAG_OK)
        *out = p;
    return rc;
}
