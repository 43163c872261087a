/*
 * actag_detect_optical -- read AcTags in camera images (8-bit PGM) with AprilTag 3.
 *
 *   actag_detect_optical [--family NAME] [--tag-size M --fx F --fy F --cx C --cy C]
 *                        [--no-invert] [--json] [--bits-corrected N] [--decimate X]
 *                        IMAGE.pgm...
 *
 * For every image: inverts it (camera: aluminium light, foam dark; SPEC section 1)
 * unless --no-invert, runs AprilTag 3 with the AcTag family and prints per tag its
 * ID, corrected bits, decision margin, the corners of the inner white square in
 * AcTag order (top-left as printed, then clockwise; pixels, centre of the top-left
 * pixel at (0,0)) and, when --tag-size and all four intrinsics are given, the
 * tag's pose from AprilTag's estimate_tag_pose() (actag_apriltag_pose()):
 *   t (metres) is the tag centre in camera coordinates (x right, y down,
 *   z forward); R (row-major) turns tag axes (x = printed right, y = printed
 *   down, z into the tag) into camera axes.
 *   --tag-size is AcTag's tag_size: the side of the inner white square in metres
 *   (3/7 ft = 0.130628571 for a 1 ft 24-bit tag). --fx --fy --cx --cy are in
 *   pixels, principal point with pixel centres at integers (OpenCV, ROS).
 * --json prints one line per image:
 *   {"file":...,"detections":[{"id":..,"hamming":..,"margin":..,
 *    "corners_px":[[x,y],[x,y],[x,y],[x,y]],"pose":{"R":[9],"t":[3]}}]}
 * Defaults: --family AcTag24h10, --bits-corrected min(2, family limit),
 * --decimate 2 (AprilTag's quad_decimate; 1 = full resolution).
 * Exit status: 0 ok, 2 a bad option or an unreadable image (reported on stderr
 * in one line; the other images are still processed).
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

#define PROG "actag_detect_optical"

static void usage(FILE *f)
{
    fprintf(f,
        "usage: " PROG " [--family NAME] [--tag-size M --fx F --fy F --cx C --cy C]\n"
        "       [--no-invert] [--json] [--bits-corrected N] [--decimate X] IMAGE.pgm...\n"
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
        "  --json               one JSON line per image\n"
        "  --bits-corrected N   bit errors AprilTag may correct (default min(2, family limit))\n"
        "  --decimate X         AprilTag quad_decimate >= 1 (default 2)\n");
}

/* ------------------------------------------------------------------ PGM reader */

/* Skips whitespace and '#' comments in a PNM header. */
static int pnm_skip(FILE *f)
{
    int c;
    for (;;) {
        c = fgetc(f);
        if (c == '#') {
            while (c != '\n' && c != '\r' && c != EOF)
                c = fgetc(f);
        } else if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f') {
            continue;
        } else {
            return c;
        }
    }
}

/* Reads a decimal header field; -1 on error. */
static long pnm_uint(FILE *f)
{
    int c = pnm_skip(f);
    long v = 0;
    if (c < '0' || c > '9')
        return -1;
    while (c >= '0' && c <= '9') {
        if (v > 100000000L)
            return -1;
        v = v * 10 + (c - '0');
        c = fgetc(f);
    }
    /* exactly one whitespace character ends the field (before binary data) */
    if (c != ' ' && c != '\t' && c != '\n' && c != '\r' && c != '#')
        return -1;
    if (c == '#')
        ungetc(c, f);
    return v;
}

/* Reads an 8-bit binary PGM (P5, maxval <= 255; scaled to 0..255).
 * Returns NULL and sets *why on failure. */
static image_u8_t *read_pgm(const char *path, const char **why)
{
    FILE *f = fopen(path, "rb");
    image_u8_t *im = NULL;
    long w, h, maxv;
    if (f == NULL) {
        *why = strerror(errno);
        return NULL;
    }
    if (fgetc(f) != 'P' || fgetc(f) != '5') {
        *why = "not a binary PGM (P5) file";
        goto fail;
    }
    w = pnm_uint(f);
    h = pnm_uint(f);
    maxv = pnm_uint(f);
    if (w <= 0 || h <= 0 || maxv <= 0) {
        *why = "bad PGM header";
        goto fail;
    }
    if (maxv > 255) {
        *why = "16-bit PGM is not supported (need maxval <= 255)";
        goto fail;
    }
    if (w > 65535 || h > 65535) {
        *why = "image too large";
        goto fail;
    }
    im = image_u8_create((unsigned)w, (unsigned)h);
    if (im == NULL) {
        *why = "out of memory";
        goto fail;
    }
    for (long y = 0; y < h; y++) {
        uint8_t *row = im->buf + y * im->stride;
        if (fread(row, 1, (size_t)w, f) != (size_t)w) {
            *why = "PGM data truncated";
            goto fail;
        }
        if (maxv != 255)
            for (long x = 0; x < w; x++)
                row[x] = (uint8_t)(row[x] > maxv ? 255 : (row[x] * 255 + maxv / 2) / maxv);
    }
    fclose(f);
    return im;
fail:
    if (im != NULL)
        image_u8_destroy(im);
    fclose(f);
    return NULL;
}

/* ------------------------------------------------------------------ output */

static void json_string(const char *s)
{
    putchar('"');
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            printf("\\%c", c);
        else if (c < 0x20)
            printf("\\u%04x", c);
        else
            putchar(c);
    }
    putchar('"');
}

static void json_number(double v, const char *fmt)
{
    if (isfinite(v))
        printf(fmt, v);
    else
        printf("null");
}

/* ------------------------------------------------------------------ options */

static int parse_double(const char *opt, const char *s, double *out)
{
    char *end;
    double v;
    if (s == NULL) {
        fprintf(stderr, PROG ": option %s needs a value\n", opt);
        return -1;
    }
    errno = 0;
    v = strtod(s, &end);
    if (end == s || *end != '\0' || errno != 0 || !isfinite(v)) {
        fprintf(stderr, PROG ": option %s: '%s' is not a number\n", opt, s);
        return -1;
    }
    *out = v;
    return 0;
}

typedef struct {
    const char *family;
    double tag_size, fx, fy, cx, cy;
    int have[5]; /* tag-size fx fy cx cy given */
    int invert, json, bits;
    double decimate;
} options;

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
        for (k = 0; k < 5; k++) {
            if (strcmp(a, pose_opts[k]) == 0) {
                double *dst[5] = {&o.tag_size, &o.fx, &o.fy, &o.cx, &o.cy};
                if (parse_double(a, v, dst[k]) != 0)
                    goto bad_option;
                if (k <= 2 && !(*dst[k] > 0)) {
                    fprintf(stderr, PROG ": option %s must be > 0\n", a);
                    goto bad_option;
                }
                o.have[k] = 1;
                matched = 1;
                i++;
                break;
            }
        }
        if (matched)
            continue;
        if (strcmp(a, "--family") == 0) {
            if (v == NULL) {
                fprintf(stderr, PROG ": option --family needs a value\n");
                goto bad_option;
            }
            o.family = v;
            i++;
        } else if (strcmp(a, "--no-invert") == 0) {
            o.invert = 0;
        } else if (strcmp(a, "--json") == 0) {
            o.json = 1;
        } else if (strcmp(a, "--bits-corrected") == 0) {
            double b;
            if (parse_double(a, v, &b) != 0)
                goto bad_option;
            if (b != floor(b) || b < 0 || b > 3) {
                fprintf(stderr, PROG ": option --bits-corrected must be an integer 0..3\n");
                goto bad_option;
            }
            o.bits = (int)b;
            i++;
        } else if (strcmp(a, "--decimate") == 0) {
            if (parse_double(a, v, &o.decimate) != 0)
                goto bad_option;
            if (!(o.decimate >= 1.0) || o.decimate > 64.0) {
                fprintf(stderr, PROG ": option --decimate must be in [1, 64]\n");
                goto bad_option;
            }
            i++;
        } else {
            fprintf(stderr, PROG ": unknown option '%s' (see --help)\n", a);
            goto bad_option;
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
        const char *why = "";
        image_u8_t *im = read_pgm(path, &why);
        if (im == NULL) {
            fprintf(stderr, PROG ": %s: %s\n", path, why);
            status = 2;
            continue;
        }
        if (o.invert)
            actag_apriltag_invert(im);
        zarray_t *dets = apriltag_detector_detect(td, im);
        int n = zarray_size(dets);

        if (o.json) {
            printf("{\"file\":");
            json_string(path);
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
            }
            if (o.json) {
                printf("%s{\"id\":%d,\"hamming\":%d,\"margin\":", j ? "," : "", det->id,
                       det->hamming);
                json_number(det->decision_margin, "%.3f");
                printf(",\"corners_px\":[");
                for (int k = 0; k < 4; k++) {
                    printf("%s[", k ? "," : "");
                    json_number(c[k][0], "%.3f");
                    putchar(',');
                    json_number(c[k][1], "%.3f");
                    putchar(']');
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
                }
                putchar('}');
            } else {
                printf("  id %d  hamming %d  margin %.3f\n", det->id, det->hamming,
                       (double)det->decision_margin);
                printf("    corners px (TL TR BR BL): (%.3f, %.3f) (%.3f, %.3f) (%.3f, %.3f) "
                       "(%.3f, %.3f)\n",
                       c[0][0], c[0][1], c[1][0], c[1][1], c[2][0], c[2][1], c[3][0], c[3][1]);
                if (have_pose) {
                    printf("    pose t [m]: %.6f %.6f %.6f\n", t[0], t[1], t[2]);
                    printf("    pose R: [%.6f %.6f %.6f; %.6f %.6f %.6f; %.6f %.6f %.6f]"
                           "  object-space error %.3g\n",
                           R[0], R[1], R[2], R[3], R[4], R[5], R[6], R[7], R[8], err);
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
    return status;
bad_option:
    free(files);
    return 2;
}
