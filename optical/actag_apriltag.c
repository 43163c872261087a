/* actag_apriltag.c -- AcTag families for AprilTag 3 (see actag/actag_apriltag.h). */
#include "actag/actag_apriltag.h"

#include <apriltag/apriltag_pose.h>

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

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

zarray_t *actag_apriltag_detect(apriltag_detector_t *td, image_u8_t *im)
{
    float d;
    int min_side;
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
    return apriltag_detector_detect(td, im);
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
