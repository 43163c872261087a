/*
 * actag_detect_optical -- read AcTags in camera images (8-bit PGM) with AprilTag 3.
 *
 *   actag_detect_optical [--family NAME] [--tag-size M --fx F --fy F --cx C --cy C]
 *                        [--no-invert] [--json] [--bits-corrected N] [--decimate X]
 *                        IMAGE.pgm...          (IMAGE "-" reads standard input)
 *
 * For every image: inverts it (camera: aluminium light, foam dark; SPEC section 1)
 * unless --no-invert, runs AprilTag 3 with the AcTag family (actag_apriltag_detect:
 * readings that a mirrored view of the family explains at least as well, e.g. a
 * published AcTag24h4/h6/h8 tag seen in a mirror, are dropped; see MIRRORED TAGS
 * in actag/actag_apriltag.h) and prints per tag its
 * ID, corrected bits, decision margin, the corners of the inner white square in
 * AcTag order (top-left as printed, then clockwise) as x = column, y = row in
 * pixels with the centre of the top-left pixel at (0,0) (the convention of every
 * actag tool and of the C API) and, when --tag-size and all four intrinsics are given, the
 * tag's pose from AprilTag's estimate_tag_pose() (actag_apriltag_pose()):
 *   t (metres) is the tag centre in camera coordinates (x right, y down,
 *   z forward); R (row-major) turns tag axes (x = printed right, y = printed
 *   down, z into the tag) into camera axes.
 *   --tag-size is AcTag's tag_size: the side of the inner white square in metres
 *   (3/7 ft = 0.130628571 for a 1 ft 24-bit tag). --fx --fy --cx --cy are in
 *   pixels, principal point with pixel centres at integers (OpenCV, ROS).
 * --sensor-frame adds the same pose in the frame shared with the sonar
 * (actag/pose.h: x forward, y left, z up; the same tag frame), "pose_sensor".
 * --pixel-sd PX adds its covariance (actag_pose_camera_covariance) from the
 * corners' pixel noise: "sd", "cov" (6 x 6), "chi2" and "flags" in
 * "pose_sensor".
 * --json prints one line per image (an image that cannot be read:
 * {"file":...,"error":...}):
 *   {"file":...,"detections":[{"id":..,"hamming":..,"margin":..,
 *    "corners":[{"x_col":..,"y_row":..} x 4],"pose":{"R":[9],"t":[3]}}]}
 * Images: binary PGM (P5) through the host I/O library (tools/hostio), 8 or
 * 16 bit, scaled to 0..255 by their maxval.
 * Defaults: --family AcTag24h10, --bits-corrected min(2, family limit),
 * --decimate 2 (AprilTag's quad_decimate; 1 = full resolution).
 * Exit status: 0 ok, 2 a bad option or an unreadable image (reported on stderr
 * in one line naming the option or file and the value; the other images are
 * still processed).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <apriltag/apriltag.h>
#include <apriltag/common/image_u8.h>
#include <apriltag/common/zarray.h>

#include "actag/actag_apriltag.h"
#include "actag/version.h"
#include "hostio.h"

#define PROG "actag_detect_optical"

static void usage(FILE *f)
{
    fprintf(f,
        "usage: " PROG " [--family NAME] [--tag-size M --fx F --fy F --cx C --cy C]\n"
        "       [--no-invert] [--json] [--sensor-frame] [--pixel-sd PX] [--bits-corrected N]\n"
        "       [--decimate X] IMAGE.pgm...\n"
        "  IMAGE                binary PGM, 8 or 16 bit; - reads standard input\n"
        "  --family NAME        AcTag family (default AcTag24h10); built in:");
    for (int i = 0; i < actag_apriltag_family_count(); i++)
        fprintf(f, " %s", actag_apriltag_family_name(i));
    fprintf(f,
        "\n"
        "  --tag-size M         side of the inner white square, metres (AcTag tag_size)\n"
        "  --fx F --fy F        focal lengths, pixels\n"
        "  --cx C --cy C        principal point, pixels (pixel centres at integers)\n"
        "                       pose is printed when all five are given\n"
        "  --no-invert          image already has foam white (default: invert camera image)\n"
        "  --json               one JSON line per image (corners as x_col, y_row)\n"
        "  --sensor-frame       also the pose in the frame shared with the sonar (actag/pose.h:\n"
        "                       x forward, y left, z up), JSON member pose_sensor\n"
        "  --pixel-sd PX        with it the pose's covariance (actag/pose.h), from this sd of\n"
        "                       each corner coordinate in pixels (1e-6..1e3; 0.1-0.3 on sharp\n"
        "                       images); implies --sensor-frame. JSON: sd (of dt and the\n"
        "                       rotation vector w), cov (6 x 6), chi2, flags\n"
        "  --bits-corrected N   bit errors AprilTag may correct (default min(2, family limit))\n"
        "  --decimate X         AprilTag quad_decimate >= 1 (default 2)\n"
        "  --help  --version\n"
        "Corners: the inner white square's top-left (as printed), top-right, bottom-right,\n"
        "bottom-left, as x = column, y = row in pixels, centre of the top-left pixel (0,0).\n"
        "Readings a mirrored view explains as well (a tag seen in a mirror) are not printed.\n");
}

/* ------------------------------------------------------------------ image */

/* Reads a binary PGM (8 or 16 bit) into an AprilTag image, scaled to 0..255
 * by its maxval. Returns NULL with a message in err. */
static image_u8_t *read_image(const char *path, char *err)
{
    hostio_image hi;
    image_u8_t *im;
    if (hostio_frame_read(path, NULL, &hi, err) != HOSTIO_OK)
        return NULL;
    im = image_u8_create((unsigned)hi.cols, (unsigned)hi.rows);
    if (im == NULL) {
        snprintf(err, HOSTIO_ERRLEN, "%s: out of memory", hostio_frame_name(path));
        hostio_image_free(&hi);
        return NULL;
    }
    for (int y = 0; y < hi.rows; y++) {
        uint8_t *row = im->buf + (size_t)y * (size_t)im->stride;
        for (int x = 0; x < hi.cols; x++) {
            size_t i = (size_t)y * (size_t)hi.stride + (size_t)x;
            uint32_t v = hi.depth == 8 ? ((const uint8_t *)hi.data)[i]
                                       : ((const uint16_t *)hi.data)[i];
            uint32_t mx = (uint32_t)hi.maxval;
            row[x] = (uint8_t)(mx == 255 ? v : v >= mx ? 255u : (v * 255u + mx / 2u) / mx);
        }
    }
    hostio_image_free(&hi);
    return im;
}

/* ------------------------------------------------------------------ output */

static void json_number(double v, const char *fmt)
{
    if (isfinite(v))
        printf(fmt, v);
    else
        printf("null");
}

/* n floats as the inside of a JSON array (comma-separated) */
static void json_floats(const float *v, int n, const char *fmt)
{
    int k;
    for (k = 0; k < n; k++) {
        if (k)
            putchar(',');
        json_number(v[k], fmt);
    }
}

/* ------------------------------------------------------------------ options */

#define die(msg) hostio_die(PROG, (msg))

typedef struct {
    const char *family;
    double tag_size, fx, fy, cx, cy;
    int have[5]; /* tag-size fx fy cx cy given */
    int invert, json, bits, sensor;
    double decimate;
    double pixel_sd; /* > 0: the sensor-frame pose's covariance (--pixel-sd) */
} options;

/* The pose in the sensor frame shared with the sonar (actag/pose.h). */
static void print_sensor_pose(const apriltag_detection_t *det, const options *o, int json,
                              const char *name)
{
    actag_pose p;
    int k;
    int rc = o->pixel_sd > 0.0
                 ? actag_apriltag_pose_sensor_cov(det, o->tag_size, o->fx, o->fy, o->cx, o->cy,
                                                  o->pixel_sd, &p)
                 : actag_apriltag_pose_sensor(det, o->tag_size, o->fx, o->fy, o->cx, o->cy, &p);
    if (rc != ACTAG_OK) {
        /* (|t| beyond actag_pose_from_camera's 1e4 m, a corner beyond the
         * covariance's 1e7 px, a build refused): said, not silently left out */
        fprintf(stderr, PROG ": %s: tag %d: no sensor-frame pose (%s: %s)\n", name, det->id,
                o->pixel_sd > 0.0 ? "actag_apriltag_pose_sensor_cov" : "actag_pose_from_camera",
                actag_strerror(rc));
        return;
    }
    if (json) {
        printf(",\"pose_sensor\":{\"R\":[");
        json_floats(p.R, 9, "%.6f");
        printf("],\"t\":[");
        json_floats(p.t, 3, "%.6f");
        printf("],\"range\":");
        json_number(p.range, "%.6f");
        printf(",\"azimuth\":");
        json_number(p.azimuth, "%.6f");
        printf(",\"elevation\":");
        json_number(p.elevation, "%.6f");
        if (o->pixel_sd > 0.0) {
            /* the sds of (dt, w) (m, rad), the whole covariance, chi2 */
            float sd[6];
            for (k = 0; k < 6; k++)
                sd[k] = sqrtf(p.cov[7 * k]);
            printf(",\"sd\":[");
            json_floats(sd, 6, "%.6g");
            printf("],\"cov\":[");
            json_floats(p.cov, 36, "%.6g");
            printf("],\"chi2\":");
            json_number(p.chi2, "%.4f");
            printf(",\"flags\":%u", p.flags);
        }
        putchar('}');
    } else {
        printf("    sensor frame (x forward, y left, z up): t [m] %.6f %.6f %.6f, range %.6f m, "
               "azimuth %.6f rad, elevation %.6f rad\n",
               (double)p.t[0], (double)p.t[1], (double)p.t[2], (double)p.range,
               (double)p.azimuth, (double)p.elevation);
        if (o->pixel_sd > 0.0) {
            if (p.flags & ACTAG_POSE_NO_COVARIANCE)
                printf("    no covariance (degenerate geometry, flags %u)\n", p.flags);
            else
                printf("    sd: position [m] %.6f %.6f %.6f, rotation [rad] %.6f %.6f %.6f; "
                       "chi2 %.3f (about 2 expected)\n",
                       (double)sqrtf(p.cov[0]), (double)sqrtf(p.cov[7]), (double)sqrtf(p.cov[14]),
                       (double)sqrtf(p.cov[21]), (double)sqrtf(p.cov[28]), (double)sqrtf(p.cov[35]),
                       (double)p.chi2);
        }
    }
}

int main(int argc, char **argv)
{
    options o;
    int status = 0, nfiles = 0, only_files = 0;
    /* Options may come before or after the images; "--" ends the options. */
    int *files = (int *)malloc(sizeof(int) * (size_t)(argc > 0 ? argc : 1));
    if (files == NULL) {
        fprintf(stderr, PROG ": out of memory\n");
        return 2;
    }
    memset(&o, 0, sizeof(o));
    o.family = "AcTag24h10";
    o.invert = 1;
    o.bits = -1;
    o.decimate = 2.0;

    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = (i + 1 < argc) ? argv[i + 1] : NULL;
        static const char *const pose_opts[5] = {"--tag-size", "--fx", "--fy", "--cx", "--cy"};
        int k, matched = 0;
        if (only_files || a[0] != '-' || a[1] == '\0') {
            for (k = 0; k < nfiles && strcmp(a, "-") == 0; k++)
                if (strcmp(argv[files[k]], "-") == 0)
                    die("-: standard input can be read only once");
            files[nfiles++] = i;
            continue;
        }
        if (strcmp(a, "--") == 0) {
            only_files = 1;
            continue;
        }
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            free(files);
            return 0;
        }
        if (strcmp(a, "--version") == 0) {
            printf(PROG " %s\n", ACTAG_VERSION_STRING);
            free(files);
            return 0;
        }
        for (k = 0; k < 5; k++) {
            if (strcmp(a, pose_opts[k]) == 0) {
                double *dst[5] = {&o.tag_size, &o.fx, &o.fy, &o.cx, &o.cy};
                /* actag_apriltag_pose()'s bounds (AprilTag aborts beyond) */
                static const double lo[5] = {ACTAG_APRILTAG_MIN_TAG_SIZE, ACTAG_APRILTAG_MIN_FOCAL,
                                             ACTAG_APRILTAG_MIN_FOCAL, -ACTAG_APRILTAG_MAX_CENTRE,
                                             -ACTAG_APRILTAG_MAX_CENTRE};
                static const double hi[5] = {ACTAG_APRILTAG_MAX_TAG_SIZE, ACTAG_APRILTAG_MAX_FOCAL,
                                             ACTAG_APRILTAG_MAX_FOCAL, ACTAG_APRILTAG_MAX_CENTRE,
                                             ACTAG_APRILTAG_MAX_CENTRE};
                *dst[k] = hostio_opt_double(PROG, a, v, lo[k], hi[k]);
                o.have[k] = 1;
                matched = 1;
                i++;
                break;
            }
        }
        if (matched)
            continue;
        if (strcmp(a, "--family") == 0) {
            o.family = hostio_opt_value(PROG, argc, argv, &i);
        } else if (strcmp(a, "--no-invert") == 0) {
            o.invert = 0;
        } else if (strcmp(a, "--json") == 0) {
            o.json = 1;
        } else if (strcmp(a, "--sensor-frame") == 0) {
            o.sensor = 1;
        } else if (strcmp(a, "--pixel-sd") == 0) {
            o.pixel_sd = hostio_opt_double(PROG, a, v, ACTAG_POSE_PIXEL_SD_MIN, ACTAG_POSE_PIXEL_SD_MAX);
            o.sensor = 1;
            i++;
        } else if (strcmp(a, "--bits-corrected") == 0) {
            o.bits = (int)hostio_opt_long(PROG, a, v, 0, 3);
            i++;
        } else if (strcmp(a, "--decimate") == 0) {
            o.decimate = hostio_opt_double(PROG, a, v, 1.0, 64.0);
            i++;
        } else {
            hostio_opt_unknown(PROG, a);
        }
    }
    if (nfiles == 0) {
        fprintf(stderr, PROG ": no image given (see --help)\n");
        goto bad_option;
    }

    int npose = o.have[0] + o.have[1] + o.have[2] + o.have[3] + o.have[4];
    if (npose != 0 && npose != 5) {
        fprintf(stderr, PROG ": the pose needs --tag-size, --fx, --fy, --cx and --cy together\n");
        goto bad_option;
    }
    if (o.sensor && npose != 5) {
        fprintf(stderr, PROG ": %s needs the pose: --tag-size, --fx, --fy, --cx and --cy\n",
                o.pixel_sd > 0.0 ? "--pixel-sd" : "--sensor-frame");
        goto bad_option;
    }

    apriltag_family_t *fam = actag_apriltag_family(o.family);
    if (fam == NULL) {
        fprintf(stderr, PROG ": unknown family '%s' (see --help for the built-in ones)\n", o.family);
        goto bad_option;
    }
    int maxbits = actag_apriltag_max_bits_corrected(fam);
    if (o.bits < 0) {
        o.bits = maxbits < 2 ? maxbits : 2;
    } else if (o.bits > maxbits) {
        fprintf(stderr, PROG ": --bits-corrected %d is more than %s can correct (%d)\n",
                o.bits, o.family, maxbits);
        goto bad_option;
    }

    apriltag_detector_t *td = apriltag_detector_create();
    td->quad_decimate = (float)o.decimate;
    td->nthreads = 1;
    apriltag_detector_add_family_bits(td, fam, o.bits);

    for (int i = 0; i < nfiles; i++) {
        const char *path = argv[files[i]];
        char msg[HOSTIO_ERRLEN];
        image_u8_t *im = read_image(path, msg);
        if (im == NULL) {
            fprintf(stderr, PROG ": %s\n", msg);
            if (o.json) { /* every file gets its line, as actag_detect's --json */
                printf("{\"file\":");
                hostio_json_string(stdout, path);
                printf(",\"error\":");
                hostio_json_string(stdout, msg);
                printf("}\n");
            }
            status = 2;
            continue;
        }
        if (o.invert)
            actag_apriltag_invert(im);
        zarray_t *dets = actag_apriltag_detect(td, im); /* empty on tiny images */
        int n = zarray_size(dets);

        if (o.json) {
            printf("{\"file\":");
            hostio_json_string(stdout, path);
            printf(",\"detections\":[");
        } else {
            printf("%s: %d detection%s (%s)\n", path, n, n == 1 ? "" : "s", o.family);
        }
        for (int j = 0; j < n; j++) {
            apriltag_detection_t *det;
            double c[4][2];
            double R[9], t[3], err = 0;
            int have_pose = 0;
            zarray_get(dets, j, &det);
            actag_apriltag_corners_to_actag(det, c);
            if (npose == 5) {
                err = actag_apriltag_pose(det, o.tag_size, o.fx, o.fy, o.cx, o.cy, R, t);
                have_pose = err >= 0;
                if (!have_pose) /* said, not silently left out */
                    fprintf(stderr, PROG ": %s: tag %d: no pose (AprilTag's estimate failed)\n",
                            hostio_frame_name(path), det->id);
            }
            if (o.json) {
                printf("%s{\"id\":%d,\"hamming\":%d,\"margin\":", j ? "," : "", det->id,
                       det->hamming);
                json_number(det->decision_margin, "%.3f");
                printf(",\"corners\":[");
                for (int k = 0; k < 4; k++) {
                    printf("%s{\"x_col\":", k ? "," : "");
                    json_number(c[k][0], "%.3f");
                    printf(",\"y_row\":");
                    json_number(c[k][1], "%.3f");
                    putchar('}');
                }
                putchar(']');
                if (have_pose) {
                    printf(",\"pose\":{\"R\":[");
                    for (int k = 0; k < 9; k++) {
                        if (k)
                            putchar(',');
                        json_number(R[k], "%.6f");
                    }
                    printf("],\"t\":[");
                    for (int k = 0; k < 3; k++) {
                        if (k)
                            putchar(',');
                        json_number(t[k], "%.6f");
                    }
                    printf("]}");
                    if (o.sensor)
                        print_sensor_pose(det, &o, 1, hostio_frame_name(path));
                }
                putchar('}');
            } else {
                printf("  id %d  hamming %d  margin %.3f\n", det->id, det->hamming,
                       (double)det->decision_margin);
                printf("    corners TL TR BR BL (x=col, y=row px): (%.3f, %.3f) (%.3f, %.3f) "
                       "(%.3f, %.3f) (%.3f, %.3f)\n",
                       c[0][0], c[0][1], c[1][0], c[1][1], c[2][0], c[2][1], c[3][0], c[3][1]);
                if (have_pose) {
                    printf("    pose t [m]: %.6f %.6f %.6f\n", t[0], t[1], t[2]);
                    printf("    pose R: [%.6f %.6f %.6f; %.6f %.6f %.6f; %.6f %.6f %.6f]"
                           "  object-space error %.3g\n",
                           R[0], R[1], R[2], R[3], R[4], R[5], R[6], R[7], R[8], err);
                    if (o.sensor)
                        print_sensor_pose(det, &o, 0, hostio_frame_name(path));
                }
            }
        }
        if (o.json)
            printf("]}\n");
        fflush(stdout);
        apriltag_detections_destroy(dets);
        image_u8_destroy(im);
    }
    apriltag_detector_destroy(td);
    free(files);
    /* results lost to a full disk or a closed pipe are not exit 0 */
    if (fflush(stdout) != 0 || ferror(stdout)) {
        fprintf(stderr, PROG ": standard output: write error\n");
        status = 2;
    }
    return status;
bad_option:
    free(files);
    return 2;
}
