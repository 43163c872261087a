/*
 * actag_detect: find AcTags in sonar frames (8/16-bit binary PGM or raw).
 *
 *   actag_detect --min-range M --max-range M (--aperture-deg D | --bearings FILE)
 *                [options] FILE...          (FILE "-" reads standard input)
 *
 * See usage() for the options. Host-only example: uses stdio and malloc; the
 * library itself does not. Frames, numbers and folders go through the host
 * I/O library (tools/hostio); the pictures are in pictures.c.
 *
 * Coordinates, in the text and the JSON output alike: image positions are
 * x = column (beam index), y = row (range bin), in pixels, with the centre of
 * the top-left pixel at (0, 0) (the C API's actag_point); corners are listed
 * in the tag's own order, top-left, top-right, bottom-right, bottom-left as
 * printed. Each corner also has its range (m) and azimuth (rad).
 *
 * Exit status 0 when every file was processed, 2 when an option was bad
 * (nothing processed) or any file failed (the others are still processed),
 * or when --check-geometry had no tag to check; every message is one line
 * naming the file or option and the value.
 */
#define _POSIX_C_SOURCE 200809L
#include "actag/actag.h"
#include "actag/pose.h"
#include "actag/track.h"
#include "actag/version.h"
#include "geometry_check.h"
#include "hostio.h"
#include "pictures.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define PROG "actag_detect"
#define MAX_DETECTIONS 64

static void usage(FILE *f)
{
    fprintf(f,
            "usage: " PROG " --min-range M --max-range M (--aperture-deg D | --bearings FILE)\n"
            "       [options] FILE...\n"
            "Finds AcTags in sonar frames: binary PGM (P5, 8 or 16 bit, recognised by its magic)\n"
            "or headerless raw frames (--rows/--cols). Rows are range bins, columns beams.\n"
            "FILE - reads one frame from standard input.\n"
            "Sonar geometry (required):\n"
            "  --min-range M          range of the nearest row's centre, metres (>= 0)\n"
            "  --max-range M          range of the farthest row's centre, metres\n"
            "  --aperture-deg D       horizontal aperture in degrees, or (not both)\n"
            "  --bearings FILE        one azimuth per column in radians (whitespace or commas)\n"
            "  --range-ascending      row 0 is the nearest range (default: the farthest)\n"
            "  --azimuth-ascending    column 0 is the most negative bearing (default: +aperture/2;\n"
            "                         not with --bearings, whose table gives the order)\n"
            "Raw frames:\n"
            "  --rows R --cols C [--depth 8|16] [--stride S]  (16-bit raw is little-endian;\n"
            "                         stride in pixels, default C)\n");
    fprintf(f,
            "Tags and pipeline:\n"
            "  --family NAME          tag family (default AcTag24h10)\n"
            "  --tag-size M           side of the inner white square, metres (default 0.130628571)\n"
            "  --bit-corrections N    allowed corrected bits (default, or -1: min(3, family maximum))\n"
            "  --seed N               RANSAC seed (default 1)\n"
            "  --decode fit|binary    fit (default): fit the cell grid to the filtered frame and\n"
            "                         read each bit against its neighbours; binary: the paper's\n"
            "                         reading of the binary frame\n"
            "  --search N             structure-search candidates per frame, 0 (off) to 8 (default 2)\n"
            "  --min-margin F         least decision margin (log-likelihood ratio) of a reading\n"
            "                         (default 2); --search-min-margin F for search readings (1);\n"
            "                         --many-corrections-margin F: readings with 3 or more\n"
            "                         corrected bits need min-margin + F (default 1.5)\n"
            "  --min-bit-margin N     least lead in corrected bits of a reading over the next,\n"
            "                         0..32 (default 2; 3 where a wrong ID must not happen with\n"
            "                         a dense family: docs/families.md)\n"
            "  --min-bit-odds N       a reading with corrected bits must also lead by enough bits\n"
            "                         that, at its own bit-error rate, the next is at most 1/N\n"
            "                         as likely, 1..1000000 (default 100; 1: off; decode.h)\n"
            "  --level-noise 0|1      where a reading's cells are far from two levels, it must\n"
            "                         also lead with black and white cells at their own noise\n"
            "                         (ACTAG_FIT_LEVEL_NOISE, decode.h; default 1)\n"
            "  --separate-noise       stricter: each template at its own black and white noise\n"
            "                         (ACTAG_FIT_SEPARATE_NOISE): fewer wrong IDs on blurred or\n"
            "                         grazing tags, at a few %% of the readings\n"
            "  --handedness any|unmirrored|mirrored  the views the sonar's mounting can show\n"
            "                         (default any; a sonar upright above seabed tags: unmirrored)\n"
            "  --median-radius N      (default 4): the largest; --median-per-range 0|1 (default 1):\n"
            "                         at each range a window of at most half a tag cell's\n"
            "                         width in beams plus 2 px, radius 2 at least, N at most\n"
            "                         (far tags keep their cells); 0: N everywhere\n"
            "  --threshold-radius N   (default 8)\n"
            "  --threshold-offset N   (default 1)   --inlier-ratio F (default 0.8)\n"
            "  --inlier-distance F    pixels (default 2.5)  --ransac-iterations N (default 100)\n"
            "  --min-structure F      least fraction of ring / interior cells read right, 0..1\n"
            "                         (default 0: the corrections budget is the gate)\n"
            "  --min-texture-contrast F  least ratio of a reading's white-minus-ring contrast to\n"
            "                         the cell-to-cell variation of the texture around the\n"
            "                         tag, 0..1e6 (default 5; 0: off; actag.h)\n"
            "  --min-side-fraction F  least quad side / tag size (default 0.5; 0.4 reads more\n"
            "                         grazing views and more clutter), at most\n"
            "                         --max-side-fraction\n"
            "  --max-side-fraction F  largest quad side / tag size (default 1.6)\n");
    fprintf(f,
            "Output (coordinates: x = column, y = row, pixels, centre of the top-left pixel at\n"
            "(0,0); corners in the tag's order TL TR BR BL as printed):\n"
            "  (default)              one line per tag: id, hamming, margin, mirrored, corners\n"
            "                         as (x=col, y=row | range m, azimuth rad)\n"
            "  --json                 one JSON line per file: {\"file\", \"rows\", \"cols\",\n"
            "                         \"detections\": [{\"id\", \"hamming\", \"decision_margin\",\n"
            "                         \"mirrored\", \"corners\": [{\"x_col\", \"y_row\", \"range_m\",\n"
            "                         \"azimuth_rad\"} x 4]}], \"time_ms\"}, or {\"file\", \"error\"}\n"
            "  --pose                 each tag's 6-DOF pose in the sonar frame with its covariance\n"
            "                         (actag/pose.h: x forward, y left, z up; JSON member \"pose\")\n"
            "  --check-geometry       after the files: do the geometry and tag size given fit the\n"
            "                         tags' corners? The median pose chi2 of all tags (0.1-0.5\n"
            "                         where they fit, with pose.h's corner noise), and the\n"
            "                         azimuth scale or else the tag-size scale (0.80-1.25) that\n"
            "                         would fit best: alternatives, for one of aperture, tag\n"
            "                         size and range scale can be found given the other two\n"
            "                         (docs/pose.md; about 12 ms a tag). With --json one last\n"
            "                         line {\"geometry_check\": {...}}. No tag to check: exit\n"
            "                         status 2. Not with --track\n"
            "  --vertical-aperture-deg D  the sonar's vertical aperture for --pose and\n"
            "                         --check-geometry (default 12)\n"
            "  --plane NX,NY,NZ,D --plane-sd M --plane-tilt-deg D  for --pose: the plane the tags\n"
            "                         lie on, n.p = D in the sonar frame (a seabed at altitude H\n"
            "                         under an upright sonar: 0,0,1,-H), with the sd of its\n"
            "                         offset (m) and of its tilt (degrees); pins the elevation\n"
            "                         one ping leaves free (pose.h, KNOWN PLANE)\n"
            "  --track                the files are consecutive frames of one stream: report the\n"
            "                         tracker's confirmed tracks (actag/track.h) instead of the\n"
            "                         detections; JSON {\"file\", \"frame\", \"tracks\": [{\"track\",\n"
            "                         \"id\", \"mirrored\", \"measured\", \"hits\", \"missed\",\n"
            "                         \"innovation\", \"decision_margin\", \"corners\"[, \"pose\"]}],\n"
            "                         \"whole_frame\", \"pixels\", \"time_ms\"} (no --overlay or\n"
            "                         --stages)\n"
            "  --report-coasting      with --track: also report a track on the first frame it is\n"
            "                         not read, at its prediction (\"measured\": false)\n"
            "  --inplace              detect as firmware with little RAM does (actag_detect_inplace:\n"
            "                         the filtered frame overwrites the pixels, workspace\n"
            "                         ACTAG_WORKSPACE_SIZE_INPLACE; corners refined on the\n"
            "                         filtered frame); not with --track, --overlay or --stages\n"
            "  --overlay OUT.ppm      picture: the polar frame and the fan (sonar below, +azimuth\n"
            "                         left) side by side, tag edges, corners, sampled bits, and a\n"
            "                         legend with ID, hamming, margin, mirrored per tag. Several\n"
            "                         files: OUT-NAME.ppm (NAME: the file name without folder and\n"
            "                         extension; OUT-N-NAME.ppm, N its position among the files,\n"
            "                         when two files share a NAME)\n"
            "  --show-rejected        also draw the rejected candidates (quads, search boxes)\n"
            "  --stages DIR           every stage as DIR/NAME-1-input.pgm, -2-median.pgm,\n"
            "                         -3-search.ppm, -4-binary.pgm, -5-contours.ppm, -6-quads.ppm,\n"
            "                         -7-decoded.ppm (DIR is created)\n"
            "  --help (-h)  --version\n");
}

#define die(msg) hostio_die(PROG, (msg))
#define num(opt, s, lo, hi) hostio_opt_double(PROG, (opt), (s), (lo), (hi))
#define inum(opt, s, lo, hi) hostio_opt_long(PROG, (opt), (s), (lo), (hi))
/* Values the library judges (actag_check): any float / int here. */
#define fnum(opt, s) ((float)num((opt), (s), -FLT_MAX, FLT_MAX))
#define anyint(opt, s) ((int)inum((opt), (s), INT_MIN, INT_MAX))

/* --handedness: ACTAG_HANDEDNESS_ANY, _UNMIRRORED, _MIRRORED in order. */
static const char *const handedness_words[3] = {"any", "unmirrored", "mirrored"};
/* --level-noise: off, on */
static const char *const zero_one_words[2] = {"0", "1"};

/* The options that set library fields, for the library's error details. */
static const hostio_optname option_names[] = {
    {"tag_size", "--tag-size", 0},
    {"max_bit_corrections", "--bit-corrections", 0},
    {"seed", "--seed", 0},
    {"min_margin", "--min-margin", 0},
    {"handedness", "--handedness", 0},
    {"tuning.decode_mode", "--decode", 0},
    {"tuning.search_candidates", "--search", 0},
    {"tuning.min_structure", "--min-structure", 0},
    {"tuning.min_texture_contrast", "--min-texture-contrast", 0},
    {"tuning.min_side_fraction", "--min-side-fraction", 0},
    {"tuning.max_side_fraction", "--max-side-fraction", 0},
    {"tuning.search_min_margin", "--search-min-margin", 0},
    {"tuning.fit.many_corrections_margin", "--many-corrections-margin", 0},
    {"tuning.fit.min_bit_margin", "--min-bit-margin", 0},
    {"tuning.fit.min_bit_odds", "--min-bit-odds", 0},
    {"tuning.median_radius", "--median-radius", 0},
    {"tuning.median_per_range", "--median-per-range", 0},
    {"tuning.threshold_radius", "--threshold-radius", 0},
    {"tuning.threshold_offset", "--threshold-offset", 0},
    {"tuning.quad.inlier_ratio", "--inlier-ratio", 0},
    {"tuning.quad.inlier_distance", "--inlier-distance", 0},
    {"tuning.quad.max_iterations", "--ransac-iterations", 0},
    {"geometry.min_range", "--min-range", 0},
    {"geometry.max_range", "--max-range", 0},
    {"geometry.aperture", "--aperture-deg", 57.29577951308232},
    {"geometry.bearings", "--bearings", 0},
};
#define NOPTION_NAMES ((int)(sizeof option_names / sizeof option_names[0]))

/* ------------------------------------------------------------------ options */

typedef struct options {
    actag_sonar_geometry geo;
    actag_params params;
    actag_family fam;
    hostio_raw_spec raw;
    const char *family_name, *bearings_path, *overlay, *stages;
    char *bearings_text; /* the table file's text, read once (for "-", stdin) */
    int json, show_rejected;
    int have_min, have_max, have_aperture;
    double aperture_deg;
    int pose, track;                 /* --pose, --track */
    int check_geometry;              /* --check-geometry */
    int report_coasting;             /* --report-coasting */
    int inplace;                     /* --inplace */
    double vertical_deg;             /* --vertical-aperture-deg */
    double plane[4], plane_sd, plane_tilt_deg; /* --plane, --plane-sd, --plane-tilt-deg */
    /* given on the command line (options that only apply with others) */
    int have_plane, have_plane_sd, have_plane_tilt, have_vertical, have_depth, have_stride;
    actag_pose_params pose_params;
} options;

/* Parses argv into *o and the file list (files[0..*nfiles-1]); exits with
 * status 2 and a one-line message on any bad option. */
static void parse_options(int argc, char **argv, options *o, const char **files, int *nfiles)
{
    int i, stdin_files = 0;
    memset(o, 0, sizeof *o);
    o->family_name = "AcTag24h10";
    o->raw.depth = 8;
    o->vertical_deg = 12.0;
    actag_params_default(&o->params);
    *nfiles = 0;
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = (i + 1 < argc) ? argv[i + 1] : NULL;
/* v, the value, is argv[i + 1]: hostio_opt_value dies without it and moves i onto it */
#define NEEDV() ((void)hostio_opt_value(PROG, argc, argv, &i))
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            exit(0);
        } else if (strcmp(a, "--version") == 0) {
            printf(PROG " %s\n", ACTAG_VERSION_STRING);
            exit(0);
        } else if (strcmp(a, "--json") == 0) {
            o->json = 1;
        } else if (strcmp(a, "--show-rejected") == 0) {
            o->show_rejected = 1;
        } else if (strcmp(a, "--pose") == 0) {
            o->pose = 1;
        } else if (strcmp(a, "--track") == 0) {
            o->track = 1;
        } else if (strcmp(a, "--check-geometry") == 0) {
            o->check_geometry = 1;
        } else if (strcmp(a, "--report-coasting") == 0) {
            o->report_coasting = 1;
        } else if (strcmp(a, "--inplace") == 0) {
            o->inplace = 1;
        } else if (strcmp(a, "--vertical-aperture-deg") == 0) {
            NEEDV();
            o->vertical_deg = num(a, v, 1e-3, 179.999);
            o->have_vertical = 1;
        } else if (strcmp(a, "--plane") == 0) {
            char pm[HOSTIO_ERRLEN];
            NEEDV();
            if (hostio_parse_doubles(a, v, ',', o->plane, 4, pm) != HOSTIO_OK)
                die(pm);
            o->have_plane = 1;
        } else if (strcmp(a, "--plane-sd") == 0) {
            NEEDV();
            o->plane_sd = num(a, v, 0.0, 1e6);
            o->have_plane_sd = 1;
        } else if (strcmp(a, "--plane-tilt-deg") == 0) {
            NEEDV();
            o->plane_tilt_deg = num(a, v, 0.0, 180.0);
            o->have_plane_tilt = 1;
        } else if (strcmp(a, "--range-ascending") == 0) {
            o->geo.flags |= ACTAG_RANGE_ASCENDING;
        } else if (strcmp(a, "--azimuth-ascending") == 0) {
            o->geo.flags |= ACTAG_AZIMUTH_ASCENDING;
        } else if (strcmp(a, "--min-range") == 0) {
            NEEDV();
            o->geo.min_range = fnum(a, v);
            o->have_min = 1;
        } else if (strcmp(a, "--max-range") == 0) {
            NEEDV();
            o->geo.max_range = fnum(a, v);
            o->have_max = 1;
        } else if (strcmp(a, "--aperture-deg") == 0) {
            NEEDV();
            o->aperture_deg = num(a, v, -DBL_MAX, DBL_MAX);
            if (!(o->aperture_deg > 0.0 && o->aperture_deg < 360.0)) {
                char m[128];
                snprintf(m, sizeof m, "--aperture-deg: must be a number > 0 and < 360 (got %g)",
                         o->aperture_deg);
                die(m);
            }
            o->have_aperture = 1;
        } else if (strcmp(a, "--bearings") == 0) {
            NEEDV();
            o->bearings_path = v;
            if (strcmp(v, "-") == 0 && ++stdin_files > 1)
                die("-: standard input can be read only once (--bearings - and a frame -)");
        } else if (strcmp(a, "--rows") == 0) {
            NEEDV();
            o->raw.rows = (int)inum(a, v, 1, ACTAG_MAX_DIM);
        } else if (strcmp(a, "--cols") == 0) {
            NEEDV();
            o->raw.cols = (int)inum(a, v, 1, ACTAG_MAX_DIM);
        } else if (strcmp(a, "--depth") == 0) {
            NEEDV();
            o->raw.depth = (int)inum(a, v, 8, 16);
            if (o->raw.depth != 8 && o->raw.depth != 16) {
                char m[128];
                snprintf(m, sizeof m, "--depth: must be 8 or 16 (got %s)", v);
                die(m);
            }
            o->have_depth = 1;
        } else if (strcmp(a, "--stride") == 0) {
            NEEDV();
            o->raw.stride = (int)inum(a, v, 1, 1 << 20);
            o->have_stride = 1;
        } else if (strcmp(a, "--family") == 0) {
            NEEDV();
            o->family_name = v;
        } else if (strcmp(a, "--tag-size") == 0) {
            NEEDV();
            o->params.tag_size = fnum(a, v);
        } else if (strcmp(a, "--bit-corrections") == 0) {
            NEEDV();
            o->params.max_bit_corrections = anyint(a, v);
        } else if (strcmp(a, "--decode") == 0) {
            NEEDV();
            if (strcmp(v, "binary") == 0) {
                o->params.tuning.decode_mode = ACTAG_DECODE_BINARY;
            } else if (strcmp(v, "fit") == 0) {
                o->params.tuning.decode_mode = ACTAG_DECODE_FIT;
            } else {
                char m[128];
                snprintf(m, sizeof m, "--decode: must be fit or binary (got '%.40s')", v);
                die(m);
            }
        } else if (strcmp(a, "--search") == 0) {
            NEEDV();
            o->params.tuning.search_candidates = anyint(a, v);
        } else if (strcmp(a, "--min-structure") == 0) {
            NEEDV();
            o->params.tuning.min_structure = fnum(a, v);
        } else if (strcmp(a, "--min-texture-contrast") == 0) {
            NEEDV();
            o->params.tuning.min_texture_contrast = fnum(a, v);
        } else if (strcmp(a, "--min-side-fraction") == 0) {
            NEEDV();
            o->params.tuning.min_side_fraction = fnum(a, v);
        } else if (strcmp(a, "--max-side-fraction") == 0) {
            NEEDV();
            o->params.tuning.max_side_fraction = fnum(a, v);
        } else if (strcmp(a, "--min-margin") == 0) {
            NEEDV();
            o->params.min_margin = fnum(a, v);
        } else if (strcmp(a, "--search-min-margin") == 0) {
            NEEDV();
            o->params.tuning.search_min_margin = fnum(a, v);
        } else if (strcmp(a, "--many-corrections-margin") == 0) {
            NEEDV();
            o->params.tuning.fit.many_corrections_margin = fnum(a, v);
        } else if (strcmp(a, "--min-bit-margin") == 0) {
            NEEDV();
            o->params.tuning.fit.min_bit_margin = anyint(a, v);
        } else if (strcmp(a, "--min-bit-odds") == 0) {
            NEEDV();
            o->params.tuning.fit.min_bit_odds = anyint(a, v);
        } else if (strcmp(a, "--level-noise") == 0) {
            NEEDV();
            if (hostio_opt_choice(PROG, a, v, zero_one_words, 2))
                o->params.tuning.fit.flags |= ACTAG_FIT_LEVEL_NOISE;
            else
                o->params.tuning.fit.flags &= ~ACTAG_FIT_LEVEL_NOISE;
        } else if (strcmp(a, "--separate-noise") == 0) {
            o->params.tuning.fit.flags |= ACTAG_FIT_SEPARATE_NOISE;
        } else if (strcmp(a, "--handedness") == 0) {
            NEEDV(); /* the words in ACTAG_HANDEDNESS_* order */
            o->params.handedness = hostio_opt_choice(PROG, a, v, handedness_words, 3);
        } else if (strcmp(a, "--seed") == 0) {
            NEEDV();
            o->params.seed = hostio_opt_u32(PROG, a, v, 0u, 4294967295u);
        } else if (strcmp(a, "--median-radius") == 0) {
            NEEDV();
            o->params.tuning.median_radius = anyint(a, v);
        } else if (strcmp(a, "--median-per-range") == 0) {
            NEEDV();
            o->params.tuning.median_per_range = anyint(a, v);
        } else if (strcmp(a, "--threshold-radius") == 0) {
            NEEDV();
            o->params.tuning.threshold_radius = anyint(a, v);
        } else if (strcmp(a, "--threshold-offset") == 0) {
            NEEDV();
            o->params.tuning.threshold_offset = anyint(a, v);
        } else if (strcmp(a, "--inlier-ratio") == 0) {
            NEEDV();
            o->params.tuning.quad.inlier_ratio = fnum(a, v);
        } else if (strcmp(a, "--inlier-distance") == 0) {
            NEEDV();
            o->params.tuning.quad.inlier_distance = fnum(a, v);
        } else if (strcmp(a, "--ransac-iterations") == 0) {
            NEEDV();
            o->params.tuning.quad.max_iterations = anyint(a, v);
        } else if (strcmp(a, "--overlay") == 0) {
            NEEDV();
            o->overlay = v;
        } else if (strcmp(a, "--stages") == 0) {
            NEEDV();
            o->stages = v;
        } else if (a[0] == '-' && a[1] != '\0') {
            hostio_opt_unknown(PROG, a);
        } else {
            if (strcmp(a, "-") == 0 && ++stdin_files > 1)
                die(o->bearings_path && strcmp(o->bearings_path, "-") == 0
                        ? "-: standard input can be read only once (--bearings - and a frame -)"
                        : "-: standard input can be read only once (two frames -)");
            files[(*nfiles)++] = a;
        }
#undef NEEDV
    }
    if (*nfiles == 0)
        die("no input files (see --help)");
    if (!o->have_min)
        die("--min-range is required (range of the nearest row's centre, metres)");
    if (!o->have_max)
        die("--max-range is required (range of the farthest row's centre, metres)");
    if (o->have_aperture && o->bearings_path)
        die("--aperture-deg and --bearings exclude each other: give one");
    if (!o->have_aperture && !o->bearings_path)
        die("--aperture-deg or --bearings is required");
    /* the table overrides the flag (geometry.h): refused, not ignored */
    if (o->bearings_path && (o->geo.flags & ACTAG_AZIMUTH_ASCENDING))
        die("--azimuth-ascending does not apply with --bearings (the table gives each column's "
            "bearing in column order)");
    o->geo.aperture = (float)(o->aperture_deg * 3.14159265358979323846 / 180.0);
    if (actag_family_get(o->family_name, &o->fam) != ACTAG_OK) {
        char m[1024];
        size_t len;
        snprintf(m, sizeof m, "--family: unknown family %.100s (built in:", o->family_name);
        for (i = 0; i < actag_family_count(); i++) {
            actag_family f;
            actag_family_get_at(i, &f);
            len = strlen(m);
            snprintf(m + len, sizeof m - len, " %s", f.name);
        }
        len = strlen(m);
        snprintf(m + len, sizeof m - len, ")");
        die(m);
    }
    o->params.family = &o->fam;
    {
        /* what does not depend on the frame, once: the library's checks on a
         * 2 x 1 stand-in frame (the bearing table and the per-column azimuth
         * step are checked with each frame) */
        static const uint8_t px[2] = {0, 0};
        actag_frame fr = {px, 2, 1, 1, 8};
        actag_sonar_geometry g = o->geo;
        actag_error_detail d;
        char m[HOSTIO_ERRLEN];
        if (o->bearings_path) {
            g.aperture = 1.0f; /* judged per frame */
        }
        if (actag_check(&fr, &g, &o->params, SIZE_MAX, MAX_DETECTIONS, &d) != ACTAG_OK) {
            hostio_detail_message(&d, option_names, NOPTION_NAMES, m);
            die(m);
        }
    }
    /* options that only apply with others: refused alone, never ignored */
    if ((o->raw.rows > 0) != (o->raw.cols > 0))
        die("--rows and --cols go together (the layout of raw frames)");
    if ((o->have_depth || o->have_stride) && o->raw.rows == 0)
        die("--depth and --stride describe raw frames: they need --rows and --cols");
    if (o->overlay && strcmp(o->overlay, "-") == 0)
        die("--overlay -: standard output carries the detections; give the picture a file name");
    if (o->show_rejected && !o->overlay && !o->stages)
        die("--show-rejected draws into pictures: it needs --overlay or --stages");
    if (!o->pose && !o->check_geometry && o->have_vertical)
        die("--vertical-aperture-deg needs --pose or --check-geometry");
    if (!o->pose && (o->have_plane || o->have_plane_sd || o->have_plane_tilt))
        die("--plane, --plane-sd and --plane-tilt-deg need --pose");
    if (o->check_geometry && o->track)
        die("--check-geometry does not combine with --track (it checks the detections' corners)");
    if ((o->have_plane_sd || o->have_plane_tilt) && !o->have_plane)
        die("--plane-sd and --plane-tilt-deg need --plane NX,NY,NZ,D");
    if ((o->pose || o->check_geometry) &&
        !(o->params.tag_size >= 1e-3f && o->params.tag_size <= 1e4f)) {
        char m[HOSTIO_ERRLEN];
        snprintf(m, sizeof m, "%s: the tag size must be 0.001 to 10000 m (pose.h), got %g",
                 o->pose ? "--pose" : "--check-geometry", (double)o->params.tag_size);
        die(m);
    }
    actag_pose_params_default(&o->pose_params, &o->fam, o->params.tag_size,
                              (float)(o->vertical_deg * 3.14159265358979323846 / 180.0));
    if (o->have_plane) {
        /* the normal divided by its largest component first, as pose.h
         * does: any scale (1e-20 or 1e200) is the same plane, and its
         * squares neither overflow nor vanish */
        double big = fabs(o->plane[0]), ns, u[4];
        char m[HOSTIO_ERRLEN];
        int j;
        for (j = 1; j < 3; j++)
            if (fabs(o->plane[j]) > big)
                big = fabs(o->plane[j]);
        if (!(big > 0.0)) {
            snprintf(m, sizeof m, "--plane: the normal (%g, %g, %g) must be non-zero",
                     o->plane[0], o->plane[1], o->plane[2]);
            die(m);
        }
        for (j = 0; j < 4; j++)
            u[j] = o->plane[j] / big;
        ns = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]); /* 1 to sqrt 3 */
        /* the plane is used through its sds: both 0 would leave it unused */
        if (!(o->plane_sd > 0.0 || o->plane_tilt_deg > 0.0))
            die("--plane needs --plane-sd M and/or --plane-tilt-deg D above 0 (how well the "
                "plane is known; a plane known exactly: give small ones, e.g. 0.001)");
        /* normalised here, in double: a tiny normal would put the plane at
         * an infinite offset in float */
        if (!(fabs(u[3]) / ns <= 1000.0)) {
            snprintf(m, sizeof m,
                     "--plane: the plane must lie within 1000 m of the sonar (got offset %g m "
                     "for the normal (%g, %g, %g) and d %g)",
                     u[3] / ns, o->plane[0], o->plane[1], o->plane[2], o->plane[3]);
            die(m);
        }
        for (j = 0; j < 4; j++)
            o->pose_params.plane[j] = (float)(u[j] / ns);
        o->pose_params.plane_sd = (float)o->plane_sd;
        o->pose_params.plane_tilt_sd = (float)(o->plane_tilt_deg * 3.14159265358979323846 / 180.0);
        /* the sds as the library gets them, in float, against its limit (pose.h:
         * > 0 with 1 / sd^2 a float): 1e-50 would become 0 and drop the plane
         * silently, 1e-25 make every pose fail */
        {
            float sd = o->pose_params.plane_sd, tilt = o->pose_params.plane_tilt_sd;
            if (o->plane_sd > 0.0 && !(sd > 0.0f && 1.0f / (sd * sd) <= FLT_MAX)) {
                snprintf(m, sizeof m, "--plane-sd: %g m is too small for the pose (at least 1e-19)",
                         o->plane_sd);
                die(m);
            }
            if (o->plane_tilt_deg > 0.0 && !(tilt > 0.0f && 1.0f / (tilt * tilt) <= FLT_MAX)) {
                snprintf(m, sizeof m,
                         "--plane-tilt-deg: %g degrees is too small for the pose (at least 1e-17)",
                         o->plane_tilt_deg);
                die(m);
            }
        }
    }
    if (o->track && (o->overlay || o->stages))
        die("--track does not combine with --overlay or --stages");
    if (o->report_coasting && !o->track)
        die("--report-coasting needs --track");
    if (o->inplace && (o->track || o->overlay || o->stages))
        die("--inplace does not combine with --track, --overlay or --stages");
    if (o->stages)
        hostio_opt_mkdirs(PROG, "--stages", o->stages);
}

/* ------------------------------------------------------------------ names */

/* The file name without folder and extension ("stdin" for "-"). */
static void stem_of(const char *path, char *out, size_t n)
{
    const char *s = strrchr(hostio_frame_name(path), '/'), *dot;
    size_t len;
    s = s ? s + 1 : hostio_frame_name(path);
    dot = strrchr(s, '.');
    len = (dot && dot != s) ? (size_t)(dot - s) : strlen(s);
    snprintf(out, n, "%.*s", (int)len, s);
}

/* The name that labels file i's pictures: its stem, or "N-stem" (N: its
 * place in the list) when another input file has the same stem or when
 * number_all is set (see names_collide), so no picture overwrites another. */
#define PICNAME_LEN 1100
static void picture_name(const char *const *files, int nfiles, int i, int number_all, char *out,
                         size_t n)
{
    char mine[1024], other[1024];
    int j, clash = number_all;
    stem_of(files[i], mine, sizeof mine);
    for (j = 0; j < nfiles && !clash; j++) {
        if (j == i)
            continue;
        stem_of(files[j], other, sizeof other);
        clash = strcmp(mine, other) == 0;
    }
    if (clash)
        snprintf(out, n, "%d-%s", i + 1, mine);
    else
        snprintf(out, n, "%s", mine);
}

/* Would two files get the same picture name from picture_name (a.pgm,
 * b/a.pgm and 1-a.pgm: "1-a" twice)? Then every file is numbered, which
 * no two share. Returns 1, 0, or -1 when out of memory. */
static int names_collide(const char *const *files, int nfiles)
{
    char *names = (char *)malloc((size_t)nfiles * PICNAME_LEN);
    int i, j, collide = 0;
    if (!names)
        return -1;
    for (i = 0; i < nfiles; i++)
        picture_name(files, nfiles, i, 0, names + (size_t)i * PICNAME_LEN, PICNAME_LEN);
    for (i = 0; i < nfiles && !collide; i++)
        for (j = i + 1; j < nfiles && !collide; j++)
            collide = strcmp(names + (size_t)i * PICNAME_LEN, names + (size_t)j * PICNAME_LEN) == 0;
    free(names);
    return collide;
}

/* Is path one of the input files (frames, the bearing table)? */
static int overwrites_input(const char *path, const char *const *files, int nfiles,
                            const char *bearings)
{
    int i;
    for (i = 0; i < nfiles; i++)
        if (strcmp(files[i], "-") != 0 && hostio_same_file(path, files[i]))
            return 1;
    return bearings != NULL && hostio_same_file(path, bearings);
}

/* --overlay OUT.ppm: OUT.ppm for one file, else OUT-NAME.ppm. */
static void overlay_path(const char *overlay, int nfiles, const char *name, char *out, size_t n)
{
    const char *dot = strrchr(overlay, '.'), *slash = strrchr(overlay, '/');
    int stem = (dot && (!slash || dot > slash)) ? (int)(dot - overlay) : (int)strlen(overlay);
    if (nfiles == 1)
        snprintf(out, n, "%s", overlay);
    else
        snprintf(out, n, "%.*s-%s%s", stem, overlay, name, overlay + stem);
}

/* ------------------------------------------------------------------ output */

/* In --json mode every input file gets exactly one line, errors included. */
static void json_error(const char *file, const char *msg)
{
    printf("{\"file\": ");
    hostio_json_string(stdout, file);
    printf(", \"error\": ");
    hostio_json_string(stdout, msg);
    printf("}\n");
    fflush(stdout);
}

static void print_pose(const float range[4], const float azimuth[4], int mirrored,
                       const actag_pose_params *pp, int json);
static double now_ms(void);

static void print_json(const char *file, const hostio_image *im, const actag_detection *det,
                       int n, double ms, const actag_pose_params *pp)
{
    int k, c;
    printf("{\"file\": ");
    hostio_json_string(stdout, file);
    printf(", \"rows\": %d, \"cols\": %d, \"detections\": [", im->rows, im->cols);
    for (k = 0; k < n; k++) {
        printf("%s{\"id\": %d, \"hamming\": %d, \"decision_margin\": %.2f, \"mirrored\": %s, "
               "\"corners\": [",
               k ? ", " : "", det[k].id, det[k].hamming, (double)det[k].decision_margin,
               det[k].mirrored ? "true" : "false");
        for (c = 0; c < 4; c++)
            printf("%s{\"x_col\": %.3f, \"y_row\": %.3f, \"range_m\": %.5f, "
                   "\"azimuth_rad\": %.5f}",
                   c ? ", " : "", (double)det[k].corners[c].x, (double)det[k].corners[c].y,
                   (double)det[k].range[c], (double)det[k].azimuth[c]);
        printf("]");
        if (pp)
            print_pose(det[k].range, det[k].azimuth, det[k].mirrored, pp, 1);
        printf("}");
    }
    printf("], \"time_ms\": %.3f}\n", ms);
}

static void print_text(const char *file, const actag_family *fam, const actag_detection *det,
                       int n, double ms, const actag_pose_params *pp)
{
    int k, c;
    if (n == 0)
        printf("%s: no tags (%.2f ms)\n", file, ms);
    for (k = 0; k < n; k++) {
        printf("%s: %s id %d hamming %d margin %.1f%s corners TL TR BR BL "
               "(x=col, y=row px | range m, azimuth rad):",
               file, fam->name, det[k].id, det[k].hamming, (double)det[k].decision_margin,
               det[k].mirrored ? " mirrored" : "");
        for (c = 0; c < 4; c++)
            printf(" (%.1f, %.1f | %.4f, %.4f)", (double)det[k].corners[c].x,
                   (double)det[k].corners[c].y, (double)det[k].range[c],
                   (double)det[k].azimuth[c]);
        printf(" (%.2f ms)\n", ms);
        if (pp)
            print_pose(det[k].range, det[k].azimuth, det[k].mirrored, pp, 0);
    }
}

/* ---- --pose and --track: kept apart from the rest of the output ---- */

static const char *const pose_flag_names[6] = {"degenerate", "elevation", "not_converged",
                                               "mirror_conflict", "no_covariance", "plane"};

/* JSON: ", \"pose\": {...}"; text: an indented line. */
static void print_pose(const float range[4], const float azimuth[4], int mirrored,
                       const actag_pose_params *pp, int json)
{
    actag_pose P;
    int i, first = 1, rc = actag_pose_estimate(range, azimuth, mirrored, pp, &P);
    if (rc != ACTAG_OK) {
        if (json)
            printf(", \"pose\": null");
        else if (rc == ACTAG_ERR_PARAM) /* the pose's bounds (pose.h) */
            printf("    pose: %s (corner ranges must be 0.001 to 10000 m)\n", actag_strerror(rc));
        else
            printf("    pose: %s\n", actag_strerror(rc));
        return;
    }
    if (!json) {
        printf("    pose: t (%.4f, %.4f, %.4f) m, range %.4f m, azimuth %.4f rad, elevation "
               "%.4f rad (band %.4f..%.4f), sd t (%.4f, %.4f, %.4f) m, rotation sd (%.4f, "
               "%.4f, %.4f) rad, residual %.4f m",
               (double)P.t[0], (double)P.t[1], (double)P.t[2], (double)P.range,
               (double)P.azimuth, (double)P.elevation, (double)P.elevation_lo,
               (double)P.elevation_hi, sqrt((double)P.cov[0]), sqrt((double)P.cov[7]),
               sqrt((double)P.cov[14]), sqrt((double)P.cov[21]), sqrt((double)P.cov[28]),
               sqrt((double)P.cov[35]), (double)P.residual);
        for (i = 0; i < 6; i++)
            if (P.flags & (1u << i))
                printf(" [%s]", pose_flag_names[i]);
        printf("\n");
        return;
    }
    printf(", \"pose\": {\"t\": [%.5f, %.5f, %.5f], \"R\": [", (double)P.t[0], (double)P.t[1],
           (double)P.t[2]);
    for (i = 0; i < 9; i++)
        printf("%s%.6f", i ? ", " : "", (double)P.R[i]);
    printf("], \"range\": %.5f, \"azimuth\": %.5f, \"elevation\": %.5f, "
           "\"elevation_band\": [%.5f, %.5f], \"cov\": [",
           (double)P.range, (double)P.azimuth, (double)P.elevation, (double)P.elevation_lo,
           (double)P.elevation_hi);
    for (i = 0; i < 36; i++)
        printf("%s%.4e", i ? ", " : "", (double)P.cov[i]);
    printf("], \"residual_m\": %.5f, \"chi2\": %.3f, \"flags\": [", (double)P.residual,
           (double)P.chi2);
    for (i = 0; i < 6; i++)
        if (P.flags & (1u << i)) {
            printf("%s\"%s\"", first ? "" : ", ", pose_flag_names[i]);
            first = 0;
        }
    printf("]}");
}

/* One frame of a --track run: feeds the tracker, prints its confirmed
 * tracks. Returns 0, or -1 with the message in err. */
static int track_frame(actag_tracker *tr, const actag_frame *fr, const actag_sonar_geometry *geo,
                       const options *o, void *ws, size_t wsize, const char *file, char *err)
{
    actag_track out[ACTAG_TRACK_MAX];
    actag_track_stats st;
    const actag_pose_params *pp = o->pose ? &o->pose_params : NULL;
    double t0 = now_ms(), t1;
    int n = actag_tracker_update(tr, fr, geo, &o->params, NULL, ws, wsize, out, ACTAG_TRACK_MAX,
                                 &st),
        k, c;
    t1 = now_ms();
    if (n < 0) {
        snprintf(err, HOSTIO_ERRLEN, "%s: %s", hostio_frame_name(file), actag_strerror(n));
        return -1;
    }
    if (o->json) {
        printf("{\"file\": ");
        hostio_json_string(stdout, file);
        printf(", \"frame\": %ld, \"tracks\": [", tr->frame - 1);
    } else if (n == 0) {
        printf("%s: no confirmed tracks", file);
    }
    for (k = 0; k < n; k++) {
        const actag_track *t = &out[k];
        if (o->json) {
            printf("%s{\"track\": %u, \"id\": %d, \"mirrored\": %s, \"measured\": %s, "
                   "\"hits\": %d, \"missed\": %d, \"innovation\": %.2f, "
                   "\"decision_margin\": %.2f, \"corners\": [",
                   k ? ", " : "", (unsigned)t->track_id, t->id, t->mirrored ? "true" : "false",
                   t->measured ? "true" : "false", t->hits, t->missed, (double)t->innovation,
                   (double)t->last.decision_margin);
            for (c = 0; c < 4; c++)
                printf("%s{\"x_col\": %.3f, \"y_row\": %.3f, \"range_m\": %.5f, "
                       "\"azimuth_rad\": %.5f}",
                       c ? ", " : "", (double)t->corners[c].x, (double)t->corners[c].y,
                       (double)t->range[c], (double)t->azimuth[c]);
            printf("]");
            if (pp)
                print_pose(t->range, t->azimuth, t->mirrored, pp, 1);
            printf("}");
        } else {
            printf("%s%s: track %u %s id %d%s %s (hits %d) corners TL TR BR BL "
                   "(x=col, y=row px | range m, azimuth rad):",
                   k ? "\n" : "", file, (unsigned)t->track_id, o->fam.name, t->id,
                   t->mirrored ? " mirrored" : "", t->measured ? "read" : "coasting", t->hits);
            for (c = 0; c < 4; c++)
                printf(" (%.1f, %.1f | %.4f, %.4f)", (double)t->corners[c].x,
                       (double)t->corners[c].y, (double)t->range[c], (double)t->azimuth[c]);
            if (pp) {
                printf("\n");
                print_pose(t->range, t->azimuth, t->mirrored, pp, 0);
            }
        }
    }
    if (o->json)
        printf("], \"whole_frame\": %s, \"pixels\": %ld, \"time_ms\": %.3f}\n",
               st.full_frame ? "true" : "false", st.pixels, t1 - t0);
    else
        printf("%s(%s, %ld pixels, %.2f ms)\n", (n > 0 && pp) ? "    " : " ",
               st.full_frame ? "whole frame" : "tracked windows", st.pixels, t1 - t0);
    return 0;
}

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

/* ------------------------------------------------------------------ one file */

/* The 8-bit view of a frame (16-bit: scaled by its maximum, as the library does). */
static uint8_t *to8(const hostio_image *im)
{
    uint8_t *out = (uint8_t *)malloc((size_t)im->rows * (size_t)im->cols);
    uint32_t mx = 0;
    int r, c;
    if (!out)
        return NULL;
    for (r = 0; r < im->rows; r++)
        for (c = 0; c < im->cols; c++) {
            size_t i = (size_t)r * (size_t)im->stride + (size_t)c;
            uint32_t v = im->depth == 8 ? ((const uint8_t *)im->data)[i]
                                        : ((const uint16_t *)im->data)[i];
            if (v > mx)
                mx = v;
        }
    for (r = 0; r < im->rows; r++)
        for (c = 0; c < im->cols; c++) {
            size_t i = (size_t)r * (size_t)im->stride + (size_t)c;
            uint32_t v = im->depth == 8 ? ((const uint8_t *)im->data)[i]
                                        : ((const uint16_t *)im->data)[i];
            out[(size_t)r * (size_t)im->cols + (size_t)c] =
                (uint8_t)(im->depth == 8 ? v : (mx ? (v * 255u + mx / 2u) / mx : 0u));
        }
    return out;
}

/* Detects, prints and draws one file. Returns 0, or -1 after reporting. */
static int process(const options *o, const char *file, const char *picname,
                   const char *const *files, int nfiles, actag_tracker *tracker, gc_tags *gc)
{
    char err[HOSTIO_ERRLEN];
    hostio_image im;
    actag_frame fr;
    actag_sonar_geometry geo = o->geo;
    actag_detection det[MAX_DETECTIONS];
    actag_stats st;
    pic_trace trace;
    int pictures = o->overlay || o->stages, n, status = 0;
    float *bearings = NULL;
    void *ws = NULL;
    size_t wsize;
    double t0, t1;

    if (hostio_frame_read(file, &o->raw, &im, err) != HOSTIO_OK)
        goto fail;
    if (o->raw.rows > 0 && (im.rows != o->raw.rows || im.cols != o->raw.cols ||
                            im.depth != o->raw.depth)) /* read as a PGM: say so */
        fprintf(stderr,
                PROG ": warning: %s: a PGM of %d x %d, %d bit: --rows/--cols/--depth/--stride "
                "(raw frames) do not apply to it; read as the PGM\n",
                hostio_frame_name(file), im.cols, im.rows, im.depth);
    if (o->track && tracker->rows > 0 && (im.rows != tracker->rows || im.cols != tracker->cols)) {
        /* the tracker's own refusal said only "invalid image size or stride" */
        snprintf(err, HOSTIO_ERRLEN, "%.150s: %d x %d frame in a --track stream of %d x %d frames",
                 hostio_frame_name(file), im.cols, im.rows, tracker->cols, tracker->rows);
        goto fail;
    }
    if (o->bearings_path) {
        bearings = (float *)malloc((size_t)im.cols * sizeof(float));
        if (!bearings) {
            snprintf(err, HOSTIO_ERRLEN, "%s: out of memory", hostio_frame_name(file));
            goto fail;
        }
        if (hostio_parse_bearings(o->bearings_path, o->bearings_text, im.cols, NULL, bearings,
                                  err) != HOSTIO_OK)
            goto fail;
        geo.bearings = bearings;
    }
    wsize = o->inplace ? actag_workspace_size_inplace(im.rows, im.cols)
                       : actag_workspace_size(im.rows, im.cols);
    ws = malloc(wsize);
    if (!ws) {
        snprintf(err, HOSTIO_ERRLEN, "%s: out of memory for the workspace", hostio_frame_name(file));
        goto fail;
    }
    hostio_image_frame(&im, &fr);
    {
        actag_error_detail d;
        char m[HOSTIO_ERRLEN];
        if ((o->inplace ? actag_check_inplace : actag_check)(&fr, &geo, &o->params, wsize,
                                                             MAX_DETECTIONS, &d) != ACTAG_OK) {
            const char *name = hostio_frame_name(file);
            size_t ml, nl, room;
            hostio_optname map[NOPTION_NAMES];
            char bopt[300];
            int j;
            /* a bad bearing table is named by its own file, not the frame's */
            memcpy(map, option_names, sizeof map);
            snprintf(bopt, sizeof bopt, "--bearings %.280s", o->bearings_path ? o->bearings_path : "");
            for (j = 0; j < NOPTION_NAMES; j++)
                if (o->bearings_path && strcmp(map[j].field, "geometry.bearings") == 0)
                    map[j].option = bopt;
            hostio_detail_message(&d, map, NOPTION_NAMES, m);
            /* "name: message", the message whole and the name cut to fit
             * (copied by hand: snprintf's truncation warning at -O1) */
            ml = strlen(m);
            if (ml > HOSTIO_ERRLEN - 3)
                ml = HOSTIO_ERRLEN - 3;
            room = HOSTIO_ERRLEN - 3 - ml;
            nl = strlen(name);
            if (nl > room)
                nl = room;
            memcpy(err, name, nl);
            memcpy(err + nl, ": ", 2);
            memcpy(err + nl + 2, m, ml);
            err[nl + 2 + ml] = '\0';
            goto fail;
        }
    }
    if (o->track) {
        if (track_frame(tracker, &fr, &geo, o, ws, wsize, file, err) != 0)
            goto fail;
        fflush(stdout);
        free(ws);
        free(bearings);
        hostio_image_free(&im);
        return 0;
    }
    pic_trace_init(&trace, o->stages != NULL);
    t0 = now_ms();
    if (o->inplace) /* the image's own pixel buffer, overwritten */
        n = actag_detect_inplace(&fr, &geo, &o->params, ws, wsize, det, MAX_DETECTIONS, &st);
    else
        n = actag_detect_traced(&fr, &geo, &o->params, ws, wsize, det, MAX_DETECTIONS, &st,
                                pictures ? pic_trace_event : NULL, pictures ? &trace : NULL);
    t1 = now_ms();
    if (n < 0) {
        snprintf(err, HOSTIO_ERRLEN, "%s: %s", hostio_frame_name(file), actag_strerror(n));
        pic_trace_free(&trace);
        goto fail;
    }
    if (o->json)
        print_json(file, &im, det, n, t1 - t0, o->pose ? &o->pose_params : NULL);
    else
        print_text(file, &o->fam, det, n, t1 - t0, o->pose ? &o->pose_params : NULL);
    fflush(stdout);
    if (gc && gc_add(gc, det, n) != 0) {
        fprintf(stderr, PROG ": %s: out of memory for --check-geometry\n", hostio_frame_name(file));
        status = -1;
    }
    if (st.dropped > 0)
        fprintf(stderr, PROG ": %s: %d more tags than the %d reported\n", hostio_frame_name(file),
                st.dropped, MAX_DETECTIONS);
    if (pictures) {
        pic_frame pf;
        uint8_t *in8 = to8(&im);
        uint8_t *bin8 = (uint8_t *)malloc((size_t)im.rows * (size_t)im.cols);
        pf.name = strrchr(hostio_frame_name(file), '/') ? strrchr(file, '/') + 1
                                                        : hostio_frame_name(file);
        pf.input8 = in8;
        pf.filtered = actag_workspace_filtered(ws, im.rows, im.cols);
        /* the binary frame as bytes, 0 = black, 1 = white */
        if (bin8)
            actag_bitmap_unpack(actag_workspace_bitmap(ws, im.rows, im.cols), im.rows, im.cols,
                                bin8, im.cols, 1u);
        pf.binary = bin8;
        pf.rows = im.rows;
        pf.cols = im.cols;
        pf.geo = &geo;
        pf.params = &o->params;
        pf.det = det;
        pf.ndet = n;
        pf.trace = &trace;
        if (!in8 || !bin8) {
            fprintf(stderr, PROG ": %s: out of memory for the pictures\n", pf.name);
            status = -1;
        } else {
            if (trace.oom)
                fprintf(stderr, PROG ": %s: out of memory: candidates missing from the pictures\n",
                        pf.name);
            if (o->overlay) {
                char path[4096];
                overlay_path(o->overlay, nfiles, picname, path, sizeof path);
                if (overwrites_input(path, files, nfiles, o->bearings_path)) {
                    fprintf(stderr, PROG ": --overlay %s: would overwrite an input file; not written\n",
                            path);
                    status = -1;
                } else if (pic_overlay(path, &pf, o->show_rejected, err) != 0) {
                    fprintf(stderr, PROG ": %s\n", err);
                    status = -1;
                }
            }
            if (o->stages) {
                char path[4096];
                int k, clash = 0;
                for (k = 0; k < PIC_STAGE_FILES && !clash; k++) {
                    pic_stage_path(o->stages, picname, k, path, sizeof path);
                    clash = overwrites_input(path, files, nfiles, o->bearings_path);
                }
                if (clash) {
                    fprintf(stderr, PROG ": --stages %s: would overwrite an input file; not written\n",
                            path);
                    status = -1;
                } else if (pic_stages(o->stages, picname, &pf, err) != 0) {
                    fprintf(stderr, PROG ": %s\n", err);
                    status = -1;
                }
            }
        }
        free(in8);
        free(bin8);
    }
    pic_trace_free(&trace);
    free(ws);
    free(bearings);
    hostio_image_free(&im);
    return status;

fail:
    fprintf(stderr, PROG ": %s\n", err);
    if (o->json)
        json_error(file, err);
    free(ws);
    free(bearings);
    hostio_image_free(&im);
    return -1;
}

/* --check-geometry's summary after the files (geometry_check.h). Returns 0,
 * or -1 after a message when there was nothing to check. */
static int print_geometry_check(const options *o, const gc_tags *gc)
{
    gc_result r;
    actag_pose_params pp = o->pose_params;
    /* the aperture the scale applies to (none with a bearing table) */
    double ap = o->bearings_path ? -1.0 : (double)o->geo.aperture * 180.0 / 3.14159265358979323846;
    double ts = (double)o->params.tag_size;
    char at_end[64];
    int rc;
    snprintf(at_end, sizeof at_end, " at the end of the scan (%.2f-%.2f)", GC_SCALE_MIN,
             GC_SCALE_MAX);
    /* the corners alone: a --plane given for --pose would pull the fit */
    pp.plane_sd = 0.0f;
    pp.plane_tilt_sd = 0.0f;
    rc = gc_check(gc, &pp, &r);
    if (rc != 0) {
        const char *why = rc == GC_NO_MEMORY ? "out of memory"
                          : r.tags == 0      ? "no tag was found in the files read: nothing to check"
                                             : "no tag's corners gave a pose (pose.h's bounds): "
                                               "nothing to check";
        fprintf(stderr, PROG ": --check-geometry: %s\n", why);
        if (o->json) {
            printf("{\"geometry_check\": {\"error\": ");
            hostio_json_string(stdout, why);
            printf("}}\n");
        }
        return -1;
    }
    if (o->json) {
        printf("{\"geometry_check\": {\"tags\": %d, \"fitted\": %d, \"median_chi2\": %.3f, "
               "\"azimuth_scale\": %.4f, \"aperture_deg\": ",
               r.tags, r.fitted, r.chi2, r.az_scale);
        if (ap > 0.0)
            printf("%.3f", ap * r.az_scale);
        else
            printf("null");
        printf(", \"azimuth_scale_chi2\": %.3f, \"tag_size_scale\": %.4f, \"tag_size\": %.6f, "
               "\"tag_size_scale_chi2\": %.3f, \"at_scan_end\": [%s%s%s]}}\n",
               r.az_chi2, r.size_scale, ts * r.size_scale, r.size_chi2,
               r.az_edge ? "\"azimuth_scale\"" : "", r.az_edge && r.size_edge ? ", " : "",
               r.size_edge ? "\"tag_size_scale\"" : "");
        return 0;
    }
    printf("geometry check: %d tags (%d with a pose), median pose chi2 %.2f (0.1-0.5 where "
           "the geometry fits)\n",
           r.tags, r.fitted, r.chi2);
    printf("geometry check: least median chi2 %.2f with the azimuths x %.4f", r.az_chi2, r.az_scale);
    if (ap > 0.0)
        printf(" (aperture %.2f degrees)", ap * r.az_scale);
    printf("%s\n", r.az_edge ? at_end : "");
    printf("geometry check: or %.2f with the tag size x %.4f (%.4f m)%s: one or the other\n",
           r.size_chi2, r.size_scale, ts * r.size_scale,
           r.size_edge ? at_end : "");
    return 0;
}

/* ------------------------------------------------------------------- main */

int main(int argc, char **argv)
{
    options o;
    static actag_tracker tracker; /* --track: one stream over all files */
    gc_tags gc = {NULL, 0, 0};    /* --check-geometry: every file's tags */
    actag_track_params tp;
    int i, nfiles, status = 0, number_all = 0;
    /* The file list is gathered in argv itself (file j goes to argv[j + 1],
     * never past the argument being read): no allocation, so the early exits
     * of parse_options leak nothing (LeakSanitizer would turn status 2 into 1). */
    const char **files = (const char **)(void *)(argv + 1);
    parse_options(argc, argv, &o, files, &nfiles);
    actag_track_params_default(&tp);
    tp.report_coasting = o.report_coasting;
    if (actag_tracker_init(&tracker, &tp) != ACTAG_OK)
        die("tracker initialisation failed");
    if (o.overlay) {
        const char *dot = strrchr(o.overlay, '/');
        if (dot) { /* the overlay's folder is created like --stages' */
            char dir[4096];
            snprintf(dir, sizeof dir, "%.*s", (int)(dot - o.overlay), o.overlay);
            if (dir[0])
                hostio_opt_mkdirs(PROG, "--overlay", dir);
        }
    }
    if (o.overlay || o.stages) {
        number_all = names_collide(files, nfiles);
        if (number_all < 0)
            die("out of memory for the picture names");
    }
    if (o.bearings_path) { /* read once (after the last exit above: nothing
                            * leaks): every frame uses the same table */
        char err[HOSTIO_ERRLEN];
        size_t len;
        o.bearings_text = hostio_slurp_text(o.bearings_path, &len, err);
        if (!o.bearings_text)
            die(err);
    }
    for (i = 0; i < nfiles; i++) {
        char picname[PICNAME_LEN];
        picture_name(files, nfiles, i, number_all, picname, sizeof picname);
        if (process(&o, files[i], picname, files, nfiles, &tracker,
                    o.check_geometry ? &gc : NULL) != 0)
            status = 2;
        if (ferror(stdout)) /* a full disk or a closed pipe: the results are lost */
            break;
    }
    if (o.check_geometry && !ferror(stdout) && print_geometry_check(&o, &gc) != 0)
        status = 2;
    gc_free(&gc);
    if (fflush(stdout) != 0 || ferror(stdout)) {
        fprintf(stderr, PROG ": standard output: write error (results not written)\n");
        status = 2;
    }
    free(o.bearings_text);
    return status;
}
