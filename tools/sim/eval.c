/*
 * actag-eval: the AcTag paper's evaluation protocol (section VI-B) on
 * simulated frames with ground truth, plus a tag-free false-positive run
 * (paper Table II).
 *
 *   actag-eval [--frames N] [--tag-free N] [--family NAME] [--json] [--svg DIR] ...
 *
 * For each frame: a random sonar pose within the distance limits of one tag
 * whose face is toward the sonar and which is wholly in view, a simulated
 * frame (sim.h), actag_detect() with default parameters, and a comparison
 * with the truth. Tag-free frames (seabed and clutter only) are run through
 * every chosen family at its default bit corrections, and the sweep families
 * (the four published ones by default) also with 0 and the maximal ones.
 * Every tag read gets a pose (pose.h), compared with the truth: position
 * and orientation error against distance and incidence, and how often the
 * error lies inside the predicted 95 % ellipsoid. --sequences runs
 * simulated sonar passes and --pool-sequence a folder of frames in order
 * through the tracker (track.h) beside whole-frame detection
 * (eval_track.h). Frames are independent streams of the seed, so the
 * figures do not depend on --threads. Progress on stderr. Exit status 0,
 * 2 on bad options or when an output (a file, standard output) cannot be
 * written. Options, sonar geometries, --pool-sequence's folder and the
 * output paths are checked before the first frame; a run that fails leaves
 * none of its --pose-dump, --failures and --sequence-failures files.
 */
#define _POSIX_C_SOURCE 200809L
#include "sim.h"
#include "simio.h"
#include "../hostio/hostio.h"
#include "eval_track.h"
#include "actag/pose.h"


#include <errno.h>
#include <math.h>
#include <pthread.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#define PROG "actag-eval"
#define DEG (3.14159265358979 / 180.0)
#define MAX_FAM 32
#define NCORR 3 /* 0, default, maximal corrections */
#define MAX_BINS 64

static void usage(FILE *f)
{
    fprintf(f,
        "usage: " PROG " [options]\n"
        "The AcTag paper's simulated evaluation: detection rate, wrong IDs, corner-order and\n"
        "mirrored-flag errors, range/azimuth error per corner, and false detections on\n"
        "tag-free frames (paper Table II).\n"
        "  --frames N             frames with one tag (default 1000; 0 skips)\n"
        "  --tag-free N           tag-free frames (default 0; the acceptance run uses 10000)\n"
        "  --family NAME          family of the tagged frames (default AcTag24h10)\n"
        "  --tag-free-families all|NAME[,NAME...]  families run on tag-free frames (all)\n"
        "  --sweep-families all|NAME[,NAME...]  families also run with zero and maximal\n"
        "                         corrections on tag-free frames (default: the four published\n"
        "                         24-bit families, paper Table II); the others at default only\n"
        "  --free-rows R --free-cols C  tag-free frame size (default 530 x 512)\n"
        "  --free-max-range LO,HI tag-free frames' maximum range, uniform per frame (3,6 m:\n"
        "                         the paper's tag-free set)\n"
        "  --corrections N        bit corrections for the tagged frames (default: the\n"
        "                         library's default for the family)\n"
        "  --min-margin F --search-min-margin F  least decision margins (library defaults)\n"
        "  --many-corrections-margin F  extra margin of readings with 3 or more corrected\n"
        "                         bits (library default 1.5; 0: none)\n"
        "  --level-noise 0|1      ACTAG_FIT_LEVEL_NOISE (decode.h; default 1): poor fits must\n"
        "                         also lead with black and white cells at their own noise\n"
        "  --separate-noise       set ACTAG_FIT_SEPARATE_NOISE (decode.h): stricter, each\n"
        "                         template at its own black and white noise\n"
        "  --handedness any|unmirrored|mirrored  the views the decoder may read (actag_params\n"
        "                         handedness; default any). The tagged frames of a run with\n"
        "                         unmirrored want --mirror-fraction 0\n"
        "  --min-bit-margin N     least lead in corrected bits over the runner-up\n"
        "  --min-bit-odds N       least odds of the lead from the corrected bits (decode.h;\n"
        "                         library default 100, 1: off)\n"
        "  --plane-sd M --plane-tilt-deg D  give each pose fit the tag's plane as a vehicle\n"
        "                         would know it (pose.h KNOWN PLANE): the true face plane,\n"
        "                         its offset and normal perturbed by these sds (default: none)\n"
        "  --min-structure F --min-side-fraction F  the pipeline's structure and side gates\n"
        "  --min-texture-contrast F  the texture test's least contrast ratio (actag.h;\n"
        "                         library default 5, 0: off)\n"
        "  --median-radius N --median-per-range 0|1  the tagged frames' median: largest\n"
        "                         radius, and whether it follows the cell width per range\n"
        "                         (library defaults 4, 1)\n"
        "  --seed S (default 1)   --threads N (default 2)\n"
        "Views and sonar (defaults: the paper's: 0.1-5 m, 60 x 12 degrees, 1024 x 512,\n"
        "sonar within 0.5-5 m of the tag, 30-80 degrees incidence):\n"
        "  --min-distance M --max-distance M --min-incidence-deg D --max-incidence-deg D\n"
        "  --max-yaw-deg D --mirror-fraction F --clutter N --rows R --cols C --min-range M --max-range M\n"
        "  --aperture-deg D --vertical-aperture-deg D --range-ascending --azimuth-ascending\n"
        "  --pool                 the pool recording's sonar and views (see actag-sim)\n"
        "Appearance (defaults: actag-sim's, tuned to the pool frames):\n"
        "  --gain G --noise N --bands RATE --psf-azimuth RAD --psf-range M (beam sigma)\n"
        "  --foam F --seabed-level S --metal-specular M --metal-diffuse D --spreading P --looks N\n");
    fprintf(f, /* two strings: C99 compilers need not take longer ones */
        "Output:\n"
        "  --json                 one JSON summary object on stdout (instead of text)\n"
        "  --svg DIR              error histograms and rate-versus-distance/incidence curves\n"
        "  --pose-dump FILE       JSON lines, one per right reading: distance, incidence,\n"
        "                         hamming, decision margin, read by the search or not,\n"
        "                         true and estimated centre elevation and band, position and\n"
        "                         orientation errors, rotation error vector, pose flags\n"
        "  --failures FILE        JSON lines of frames with a wrong ID, false tag, order or\n"
        "                         mirror error; frame F of run seed S is frame F of\n"
        "                         actag-sim --seed S --random F+1 with the same sonar, view\n"
        "                         and appearance options (--first F: that frame alone)\n"
        "  --quiet                no progress on stderr\n"
        "Tracking (track.h; the tag frames' pose figures are always printed):\n"
        "  --sequences N          N simulated sonar passes (sim_sequence_view) through the\n"
        "                         tracker beside whole-frame detection (default 0)\n"
        "  --sequence-length L    frames per pass (default 100)\n"
        "  --sequence-failures FILE  JSON lines of pass frames with a wrong ID or a false tag\n"
        "                         (whole frame or tracker); pass Q's frames are those of\n"
        "                         actag-sim --sequence LENGTH --seed SEQUENCE_SEED --id ID\n"
        "                         with the same sonar, view and appearance options\n"
        "  --pool-sequence DIR    DIR's f_*.pgm in name order as one sequence (the pool\n"
        "                         recording: 530 x 512, 0.1-1.5 m, 60 degrees, tag ID 0;\n"
        "                         its 6 tag-free and 5 partial frames are not counted)\n"
        "  --full-every N --confirm-frames M --confirm-margin F --max-missed K --roi-scale F\n"
        "  --refind-after K\n"
        "                         tracker settings (track.h defaults)\n"
        "  --relax-roi            ROI searches accept decision margins down to -2 (search 0)\n"
        "  --report-coasting      report a track on the first frame it is not read, at its\n"
        "                         prediction (track.h report_coasting; counted in the\n"
        "                         reported figure and in the tracker's errors)\n"
        "  --help  --version\n");
}

/* The run's output files (--pose-dump, --failures, --sequence-failures),
 * opened before the run and closed after it: die() abandons them, so that
 * a run that fails leaves none of them behind (hostio_out: never a device
 * or a link). */
static hostio_out g_pose_out, g_fail_out, g_seq_out;

/* Errors: the host I/O library's, exit status 2, without the run's files. */
static void die(const char *msg)
{
    hostio_out_abandon(&g_pose_out);
    hostio_out_abandon(&g_fail_out);
    hostio_out_abandon(&g_seq_out);
    hostio_die(PROG, msg);
}

/* eval_track.c's errors (eval_track.h) go the same way. */
void te_die(const char *msg) { die(msg); }

/* Option values: the host I/O library's, exit status 2 (while parsing
 * options, before any output is open). */
#define num(opt, s, lo, hi) hostio_opt_double(PROG, (opt), (s), (lo), (hi))
#define inum(opt, s, lo, hi) hostio_opt_long(PROG, (opt), (s), (lo), (hi))

/* Opens the output file of option opt, or exits with status 2 naming both. */
static FILE *open_output(hostio_out *o, const char *opt, const char *path)
{
    if (hostio_out_open(o, path, "w", NULL) != HOSTIO_OK) {
        char m[1300];
        snprintf(m, sizeof m, "%s: cannot write '%s': %s", opt, path, strerror(o->why));
        die(m);
    }
    return o->f;
}

/* Closes an output file; a write error (a full disk) exits with status 2
 * naming the option and file, and the file is removed rather than left
 * half-written (hostio_out_close: never a link or a device). */
static void close_output(hostio_out *o, const char *opt)
{
    char m[1300];
    if (hostio_out_close(o, NULL) == HOSTIO_OK)
        return;
    snprintf(m, sizeof m, "%s: cannot write '%s': %s", opt, o->path,
             o->why ? strerror(o->why) : "write error");
    die(m);
}

/* ------------------------------------------------------------ per frame */

typedef struct {
    int sampled;      /* a visible view was found */
    float distance, incidence;
    int mirrored;     /* truth */
    int found;        /* right ID at the tag */
    int wrong_id;     /* other IDs at the tag */
    int false_tags;   /* detections away from the tag (or a second right ID) */
    int mirror_err, order_err;
    int hamming;
    float margin, wrong_margin; /* decision margin of the right reading, largest of the wrong */
    int wrong_hamming, wrong_search, found_search;
    float range_err[4], az_err[4], px_err;
    uint32_t seed;
    /* pose of the right reading (pose.h) against the truth */
    int pose_flags;
    float pos_err, ori_err, elev_err; /* m, rad, rad */
    float m2_pos, m2_ori, m2_all;     /* squared Mahalanobis distances */
    float el_true, el_est, el_lo, el_hi; /* rad: centre elevation, truth and estimate, band */
    float range_true, w_err[3];       /* m; rad, rotation error vector (sensor axes) */
} tag_result;

/* A detection of the tag: the right ID at the tag with the right
 * handedness and corner order (a right ID read with either wrong is an
 * error, counted as such, and no detection). */
static int right_reading(const tag_result *R)
{
    return R->sampled && R->found && !R->mirror_err && !R->order_err;
}

/* The bin of v among n bins of width step from lo (a value a rounding
 * outside the first or last bin is in it). */
static int bin_of(double v, double lo, double step, int n)
{
    int b = (int)floor((v - lo) / step);
    return b < 0 ? 0 : b >= n ? n - 1 : b;
}

typedef struct {
    int det[MAX_FAM][NCORR]; /* detections per family and corrections setting */
} free_result;

typedef struct {
    sim_sonar sonar, free_sonar;
    float free_min_max_range, free_max_max_range;
    sim_view_params view;
    sim_appearance app;
    actag_family fam;
    int corrections;
    float min_margin, search_min_margin; /* < 0: the library's defaults */
    float many_margin;                   /* < 0: the library's default */
    int min_bit_margin;                  /* < 0: the library's default */
    int min_bit_odds;                    /* < 1: the library's default */
    float plane_sd, plane_tilt;          /* --plane-sd (m), --plane-tilt-deg (rad); 0: off */
    int handedness;                      /* actag_params.handedness (default any) */
    int separate_noise;                  /* --separate-noise: ACTAG_FIT_SEPARATE_NOISE */
    int level_noise;                     /* --level-noise: < 0 the default, 0 off, 1 on */
    float min_structure, min_side;       /* < 0: the library's defaults */
    float min_texture;                   /* < 0: the library's default */
    int median_radius, median_per_range; /* < 0: the library's defaults */
    actag_family free_fam[MAX_FAM];
    int nfree_fam;
    int sweep[MAX_FAM]; /* 1: also zero and maximal corrections (Table II) */
    int frames, tag_free;
    uint32_t seed;
    tag_result *tres;
    free_result *fres;
    /* work queue */
    pthread_mutex_t lock;
    int next;
    int done;
    int quiet;
    double t0;
} eval_ctx;

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static const float tag_size_default = 0.130628571f;

/* e^T C^-1 e for the n x n leading block (first = 0) or the trailing one
 * (first = 3) of a 6 x 6 covariance, by Gaussian elimination in double. */
static float mahalanobis2(const float *cov, const double *e6, int first, int n)
{
    double A[6][7], x[6], m = 0.0;
    int i, j, k;
    for (i = 0; i < n; i++) {
        for (j = 0; j < n; j++)
            A[i][j] = cov[6 * (first + i) + first + j];
        A[i][n] = e6[first + i];
    }
    for (k = 0; k < n; k++) {
        int piv = k;
        for (i = k + 1; i < n; i++)
            if (fabs(A[i][k]) > fabs(A[piv][k]))
                piv = i;
        if (piv != k)
            for (j = 0; j <= n; j++) {
                double t = A[k][j];
                A[k][j] = A[piv][j];
                A[piv][j] = t;
            }
        if (A[k][k] == 0.0)
            return 1e30f;
        for (i = k + 1; i < n; i++) {
            double f = A[i][k] / A[k][k];
            for (j = k; j <= n; j++)
                A[i][j] -= f * A[k][j];
        }
    }
    for (i = n - 1; i >= 0; i--) {
        double v = A[i][n];
        for (j = i + 1; j < n; j++)
            v -= A[i][j] * x[j];
        x[i] = v / A[i][i];
    }
    for (i = 0; i < n; i++)
        m += e6[first + i] * x[i];
    return (float)m;
}

/* A standard normal deviate (Box-Muller) from the call's own generator. */
static double normal_of(actag_rng *g)
{
    double u1 = ((double)actag_rng_next(g) + 1.0) / 4294967297.0;
    double u2 = (double)actag_rng_next(g) / 4294967296.0;
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

/* --plane-sd/--plane-tilt-deg: what a vehicle would know of the tag's plane
 * (its altitude and attitude over a flat seabed): the true face plane in the
 * sonar frame, its normal turned about the tag's centre by a normal deviate
 * of sd plane_tilt about each of two axes across it, then moved along it by
 * one of sd plane_sd: the errors the fit's plane terms assume (pose.h; an
 * attitude error a at range r adds r a to a real plane's offset error).
 * Seeded by the frame: the same plane at any --threads. */
static void known_plane(const eval_ctx *c, const sim_tag *tag, uint32_t seed,
                        actag_pose_params *pp)
{
    actag_rng g;
    double n[3], a[3] = {0.0, 0.0, 0.0}, u[3], v[3], nn, d;
    int q;
    actag_rng_seed(&g, seed ^ 0x9E3779B9u);
    for (q = 0; q < 3; q++)
        n[q] = tag->pose.R[3 * q + 2]; /* the face normal, R e3 */
    d = n[0] * tag->pose.t[0] + n[1] * tag->pose.t[1] + n[2] * tag->pose.t[2];
    a[fabs(n[0]) < 0.9 ? 0 : 1] = 1.0;
    u[0] = n[1] * a[2] - n[2] * a[1];
    u[1] = n[2] * a[0] - n[0] * a[2];
    u[2] = n[0] * a[1] - n[1] * a[0];
    nn = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (q = 0; q < 3; q++)
        u[q] /= nn;
    v[0] = n[1] * u[2] - n[2] * u[1];
    v[1] = n[2] * u[0] - n[0] * u[2];
    v[2] = n[0] * u[1] - n[1] * u[0];
    {
        double e1 = normal_of(&g) * c->plane_tilt, e2 = normal_of(&g) * c->plane_tilt;
        double dd = normal_of(&g) * c->plane_sd;
        double m[3], mm;
        for (q = 0; q < 3; q++)
            m[q] = n[q] + e1 * u[q] + e2 * v[q];
        mm = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
        /* turned about the tag's centre, then moved along the new normal */
        d = (m[0] * tag->pose.t[0] + m[1] * tag->pose.t[1] + m[2] * tag->pose.t[2]) / mm + dd;
        for (q = 0; q < 3; q++)
            pp->plane[q] = (float)(m[q] / mm);
        pp->plane[3] = (float)d;
    }
    /* the fit assumes the sds the plane was drawn with (0: that term off) */
    pp->plane_sd = c->plane_sd;
    pp->plane_tilt_sd = c->plane_tilt;
}

static void pose_errors(const eval_ctx *c, const sim_tag *tag, const actag_detection *d,
                        tag_result *R)
{
    actag_pose_params pp;
    actag_pose P;
    double e[6];
    float w[3], el_true;
    int q;
    actag_pose_params_default(&pp, &c->fam, tag->tag_size, c->sonar.vertical_aperture);
    if (c->plane_sd > 0.0f || c->plane_tilt > 0.0f)
        known_plane(c, tag, R->seed, &pp);
    if (actag_pose_from_detection(d, &pp, &P) != ACTAG_OK)
        die("actag_pose_from_detection failed");
    actag_pose_rotation_vector(tag->pose.R, P.R, w);
    for (q = 0; q < 3; q++) {
        e[q] = (double)tag->pose.t[q] - P.t[q];
        e[3 + q] = w[q];
    }
    R->pose_flags = (int)P.flags;
    R->pos_err = (float)sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    R->ori_err = sqrtf(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    el_true = asinf(tag->pose.t[2] / sqrtf(tag->pose.t[0] * tag->pose.t[0] +
                                           tag->pose.t[1] * tag->pose.t[1] +
                                           tag->pose.t[2] * tag->pose.t[2]));
    R->elev_err = P.elevation - el_true;
    R->el_true = el_true;
    R->el_est = P.elevation;
    R->el_lo = P.elevation_lo;
    R->el_hi = P.elevation_hi;
    R->range_true = sqrtf(tag->pose.t[0] * tag->pose.t[0] + tag->pose.t[1] * tag->pose.t[1] +
                          tag->pose.t[2] * tag->pose.t[2]);
    for (q = 0; q < 3; q++)
        R->w_err[q] = w[q];
    R->m2_pos = mahalanobis2(P.cov, e, 0, 3);
    R->m2_ori = mahalanobis2(P.cov, e, 3, 3);
    R->m2_all = mahalanobis2(P.cov, e, 0, 6);
}

/* The detector's parameters of the tagged frames (the options given,
 * the library's defaults otherwise). */
static void tag_params(const eval_ctx *c, actag_params *p)
{
    actag_params_default(p);
    p->family = &c->fam;
    p->tag_size = tag_size_default;
    p->max_bit_corrections = c->corrections;
    if (c->min_margin > -1e5f)
        p->min_margin = c->min_margin;
    if (c->min_bit_margin >= 0)
        p->tuning.fit.min_bit_margin = c->min_bit_margin;
    if (c->min_bit_odds >= 1)
        p->tuning.fit.min_bit_odds = c->min_bit_odds;
    if (c->min_structure >= 0.0f)
        p->tuning.min_structure = c->min_structure;
    if (c->min_texture >= 0.0f)
        p->tuning.min_texture_contrast = c->min_texture;
    if (c->min_side >= 0.0f)
        p->tuning.min_side_fraction = c->min_side;
    if (c->median_radius >= 0)
        p->tuning.median_radius = c->median_radius;
    if (c->median_per_range >= 0)
        p->tuning.median_per_range = c->median_per_range;
    if (c->search_min_margin > -1e5f)
        p->tuning.search_min_margin = c->search_min_margin;
    if (c->many_margin >= 0.0f)
        p->tuning.fit.many_corrections_margin = c->many_margin;
    p->handedness = c->handedness;
    if (c->separate_noise)
        p->tuning.fit.flags |= ACTAG_FIT_SEPARATE_NOISE;
    if (c->level_noise == 0)
        p->tuning.fit.flags &= ~ACTAG_FIT_LEVEL_NOISE;
    else if (c->level_noise == 1)
        p->tuning.fit.flags |= ACTAG_FIT_LEVEL_NOISE;
}

static void eval_tag_frame(eval_ctx *c, int i, uint8_t *img, void *ws, size_t wss)
{
    tag_result *R = &c->tres[i];
    sim_tag tag;
    sim_scene sc;
    sim_truth tr;
    actag_params p;
    actag_frame fr;
    actag_detection det[16];
    uint32_t fs = sim_frame_seed(c->seed, (uint32_t)i);
    int nd, d, n;
    float cx = 0.0f, cy = 0.0f, diag;
    char err[HOSTIO_ERRLEN];
    memset(R, 0, sizeof *R);
    R->seed = fs;
    memset(&tag, 0, sizeof tag);
    tag.family = c->fam;
    tag.tag_size = tag_size_default;
    tag.id = simio_random_id(fs, c->fam.ncodes);
    if (sim_sample_view(&c->sonar, &c->view, fs, &tag, &sc) != 0)
        return;
    if (sim_render(&c->sonar, &sc, &c->app, fs, img, NULL, c->sonar.cols, err) != 0)
        die(err);
    sim_truth_of(&c->sonar, &tag, &tr);
    R->sampled = 1;
    R->distance = tr.distance;
    R->incidence = tr.incidence;
    R->mirrored = tr.mirrored;
    tag_params(c, &p);
    fr.data = img;
    fr.rows = c->sonar.rows;
    fr.cols = c->sonar.cols;
    fr.stride = c->sonar.cols;
    fr.depth = 8;
    nd = actag_detect(&fr, &c->sonar.geo, &p, ws, wss, det, 16, NULL);
    if (nd < 0) {
        char m[200];
        snprintf(m, sizeof m, "actag_detect failed: %s", actag_strerror(nd));
        die(m);
    }
    for (n = 0; n < 4; n++) {
        cx += 0.25f * tr.px[n].x;
        cy += 0.25f * tr.px[n].y;
    }
    diag = hypotf(tr.px[0].x - tr.px[2].x, tr.px[0].y - tr.px[2].y) +
           hypotf(tr.px[1].x - tr.px[3].x, tr.px[1].y - tr.px[3].y);
    for (d = 0; d < nd; d++) {
        float dx = 0.0f, dy = 0.0f;
        int at_tag;
        for (n = 0; n < 4; n++) {
            dx += 0.25f * det[d].corners[n].x;
            dy += 0.25f * det[d].corners[n].y;
        }
        at_tag = hypotf(dx - cx, dy - cy) < 0.5f * diag + 3.0f;
        if (at_tag && det[d].id == tag.id && !R->found) {
            int m;
            R->found = 1;
            R->hamming = det[d].hamming;
            R->margin = det[d].decision_margin;
            R->found_search = det[d].inlier_ratio == 0.0f;
            R->mirror_err = det[d].mirrored != tr.mirrored;
            R->order_err = sim_corner_order_wrong(det[d].corners, tr.px, &R->px_err);
            pose_errors(c, &tag, &det[d], R);
            for (m = 0; m < 4; m++) {
                R->range_err[m] = det[d].range[m] - tr.range[m];
                R->az_err[m] = det[d].azimuth[m] - tr.azimuth[m];
            }
        } else if (at_tag && det[d].id != tag.id) {
            R->wrong_id++;
            if (det[d].decision_margin > R->wrong_margin) {
                R->wrong_margin = det[d].decision_margin;
                R->wrong_hamming = det[d].hamming;
                R->wrong_search = det[d].inlier_ratio == 0.0f;
            }
        } else {
            R->false_tags++;
            if (det[d].decision_margin > R->wrong_margin) {
                R->wrong_margin = det[d].decision_margin;
                R->wrong_hamming = det[d].hamming;
                R->wrong_search = det[d].inlier_ratio == 0.0f;
            }
        }
    }
}

/* Corrections of setting k (0 zero, 1 default, 2 maximal) for a family. */
static int corrections_of(const actag_family *f, int k)
{
    int mx = actag_family_max_corrections(f);
    if (k == 0)
        return 0;
    if (k == 1)
        return mx < ACTAG_AUTO_CORRECTIONS ? mx : ACTAG_AUTO_CORRECTIONS;
    return mx;
}

static void eval_free_frame(eval_ctx *c, int i, uint8_t *img, void *ws, size_t wss)
{
    free_result *R = &c->fres[i];
    sim_scene sc;
    sim_sonar sonar = c->free_sonar;
    actag_frame fr;
    actag_detection *det;
    actag_rng g;
    uint32_t fs = sim_frame_seed(c->seed ^ 0xa5a5a5a5u, (uint32_t)i);
    int f, k;
    char err[HOSTIO_ERRLEN];
    memset(R, 0, sizeof *R);
    /* the paper's tag-free set: maximum ranges between 3 and 6 m */
    actag_rng_seed(&g, fs ^ 0x27d4eb2du);
    sonar.geo.max_range = c->free_min_max_range +
                          (c->free_max_max_range - c->free_min_max_range) *
                              (float)(actag_rng_next(&g) >> 8) * (1.0f / 16777216.0f);
    sim_sample_empty(&sonar, &c->view, fs, &sc);
    if (sim_render(&sonar, &sc, &c->app, fs, img, NULL, sonar.cols, err) != 0)
        die(err);
    fr.data = img;
    fr.rows = sonar.rows;
    fr.cols = sonar.cols;
    fr.stride = sonar.cols;
    fr.depth = 8;
    {
        /* every (family, corrections) setting in one actag_detect_multi
         * call: the frame is filtered once (identical to separate calls) */
        actag_params p[MAX_FAM * NCORR];
        int slot[MAX_FAM][NCORR], np = 0, rc, counts[MAX_FAM * NCORR];
        for (f = 0; f < c->nfree_fam; f++)
            for (k = 0; k < NCORR; k++) {
                int j, corr = corrections_of(&c->free_fam[f], k);
                slot[f][k] = -1;
                if (k != 1 && !c->sweep[f])
                    continue; /* not run */
                for (j = 0; j < k; j++) /* the same setting twice: one run */
                    if (slot[f][j] >= 0 && corrections_of(&c->free_fam[f], j) == corr)
                        break;
                if (j < k) {
                    slot[f][k] = slot[f][j];
                    continue;
                }
                actag_params_default(&p[np]);
                p[np].family = &c->free_fam[f];
                p[np].tag_size = tag_size_default;
                p[np].max_bit_corrections = corr;
                p[np].handedness = c->handedness;
                slot[f][k] = np++;
            }
        det = (actag_detection *)malloc((size_t)np * 16u * sizeof *det);
        if (!det)
            die("out of memory");
        rc = actag_detect_multi(&fr, &sonar.geo, p, np, ws, wss, det, 16, counts);
        free(det);
        if (rc < 0) {
            char m[200];
            snprintf(m, sizeof m, "actag_detect_multi failed: %s", actag_strerror(rc));
            die(m);
        }
        for (f = 0; f < c->nfree_fam; f++)
            for (k = 0; k < NCORR; k++)
                R->det[f][k] = slot[f][k] >= 0 ? counts[slot[f][k]] : -1;
    }
}

static void *worker(void *arg)
{
    eval_ctx *c = (eval_ctx *)arg;
    int rows = c->sonar.rows > c->free_sonar.rows ? c->sonar.rows : c->free_sonar.rows;
    int cols = c->sonar.cols > c->free_sonar.cols ? c->sonar.cols : c->free_sonar.cols;
    size_t wss = actag_workspace_size(rows, cols);
    void *ws = malloc(wss);
    uint8_t *img = (uint8_t *)malloc((size_t)rows * (size_t)cols);
    int total = c->frames + c->tag_free;
    if (!ws || !img)
        die("out of memory");
    for (;;) {
        int i;
        pthread_mutex_lock(&c->lock);
        i = c->next++;
        pthread_mutex_unlock(&c->lock);
        if (i >= total)
            break;
        if (i < c->frames)
            eval_tag_frame(c, i, img, ws, wss);
        else
            eval_free_frame(c, i - c->frames, img, ws, wss);
        pthread_mutex_lock(&c->lock);
        c->done++;
        if (!c->quiet && (c->done % 250 == 0 || c->done == total)) {
            double el = now_s() - c->t0;
            fprintf(stderr, PROG ": %d/%d frames, %.0f s, about %.0f s left\n", c->done, total,
                    el, el / c->done * (total - c->done));
        }
        pthread_mutex_unlock(&c->lock);
    }
    free(ws);
    free(img);
    return NULL;
}

/* ------------------------------------------------------------ statistics */

typedef struct {
    double mean, sd, p95, abs_mean;
    int n;
} err_stats;

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static err_stats stats_of(const double *v, int n)
{
    err_stats s;
    double *a = (double *)malloc((size_t)(n > 0 ? n : 1) * sizeof *a);
    int i;
    memset(&s, 0, sizeof s);
    s.n = n;
    for (i = 0; i < n; i++) {
        s.mean += v[i];
        s.abs_mean += fabs(v[i]);
        a[i] = fabs(v[i]);
    }
    if (n > 0) {
        s.mean /= n;
        s.abs_mean /= n;
        for (i = 0; i < n; i++)
            s.sd += (v[i] - s.mean) * (v[i] - s.mean);
        s.sd = n > 1 ? sqrt(s.sd / (n - 1)) : 0.0;
        qsort(a, (size_t)n, sizeof *a, cmp_d);
        s.p95 = a[(int)(0.95 * (n - 1) + 0.5)];
    }
    free(a);
    return s;
}

/* ------------------------------------------------------------ SVG */

/* An SVG file being written: the guard and the path it names (malloc'd to
 * fit: a fixed buffer cut a long --svg DIR short). */
typedef struct {
    hostio_out out;
    char *path;
} svg_file;

static FILE *svg_open(svg_file *s, const char *dir, const char *name, const char *title, int w,
                      int h)
{
    char err[HOSTIO_ERRLEN];
    FILE *f;
    size_t n = strlen(dir) + strlen(name) + 2;
    s->path = (char *)malloc(n);
    if (!s->path)
        die("out of memory");
    snprintf(s->path, n, "%s/%s", dir, name);
    if (hostio_out_open(&s->out, s->path, "w", err) != HOSTIO_OK)
        die(err); /* "PATH: cannot write: REASON" */
    f = s->out.f;
    fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" "
               "font-family=\"sans-serif\" font-size=\"12\">\n"
               "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n"
               "<text x=\"%d\" y=\"18\" text-anchor=\"middle\" font-size=\"14\">%s</text>\n",
            w, h, w / 2, title);
    return f;
}

static void svg_close(svg_file *s)
{
    close_output(&s->out, "--svg");
    free(s->path);
    s->path = NULL;
}

/* Histogram of v (n values) over [lo, hi] in nb bins. */
static void svg_histogram(const char *dir, const char *name, const char *title, const char *xlabel,
                          const double *v, int n, double lo, double hi, int nb)
{
    int W = 520, H = 340, L = 60, Rm = 20, T = 30, B = 50, i, cnt[200] = {0}, maxc = 1;
    svg_file svg;
    FILE *f = svg_open(&svg, dir, name, title, W, H);
    double bw = (hi - lo) / nb;
    for (i = 0; i < n; i++) {
        int b = (int)floor((v[i] - lo) / bw);
        if (b >= 0 && b < nb)
            cnt[b]++;
    }
    for (i = 0; i < nb; i++)
        if (cnt[i] > maxc)
            maxc = cnt[i];
    for (i = 0; i < nb; i++) {
        double x = L + (double)i * (W - L - Rm) / nb, w = (double)(W - L - Rm) / nb;
        double h = (double)cnt[i] / maxc * (H - T - B);
        fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"#4a7ab5\" "
                   "stroke=\"white\" stroke-width=\"0.5\"/>\n",
                x, H - B - h, w, h);
    }
    fprintf(f, "<line x1=\"%d\" y1=\"%d\" x2=\"%d\" y2=\"%d\" stroke=\"black\"/>\n", L, H - B,
            W - Rm, H - B);
    fprintf(f, "<line x1=\"%d\" y1=\"%d\" x2=\"%d\" y2=\"%d\" stroke=\"black\"/>\n", L, T, L, H - B);
    for (i = 0; i <= 4; i++) {
        double xv = lo + (hi - lo) * i / 4, x = L + (double)(W - L - Rm) * i / 4;
        fprintf(f, "<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">%.3g</text>\n", x, H - B + 16,
                xv);
        fprintf(f, "<text x=\"%d\" y=\"%.1f\" text-anchor=\"end\">%d</text>\n", L - 4,
                H - B - (double)(H - T - B) * i / 4 + 4, (int)(maxc * i / 4));
    }
    fprintf(f, "<text x=\"%d\" y=\"%d\" text-anchor=\"middle\">%s</text>\n", (W + L) / 2, H - 12,
            xlabel);
    fprintf(f, "<text x=\"14\" y=\"%d\" transform=\"rotate(-90 14 %d)\" text-anchor=\"middle\">"
               "corners</text>\n</svg>\n",
            H / 2, H / 2);
    svg_close(&svg);
}

/* Detection rate (0..1) per bin, with the number of frames per bin. */
static void svg_rate(const char *dir, const char *name, const char *title, const char *xlabel,
                     const double *centres, const double *rate, const int *count, int nb)
{
    int W = 520, H = 340, L = 60, Rm = 20, T = 30, B = 50, i;
    double lo = centres[0], hi = centres[nb - 1];
    svg_file svg;
    FILE *f = svg_open(&svg, dir, name, title, W, H);
    if (hi <= lo)
        hi = lo + 1.0;
    fprintf(f, "<polyline fill=\"none\" stroke=\"#c0392b\" stroke-width=\"2\" points=\"");
    for (i = 0; i < nb; i++)
        if (count[i] > 0)
            fprintf(f, "%.1f,%.1f ", L + (centres[i] - lo) / (hi - lo) * (W - L - Rm),
                    H - B - rate[i] * (H - T - B));
    fprintf(f, "\"/>\n");
    for (i = 0; i < nb; i++)
        if (count[i] > 0) {
            double x = L + (centres[i] - lo) / (hi - lo) * (W - L - Rm);
            double y = H - B - rate[i] * (H - T - B);
            fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3\" fill=\"#c0392b\"/>\n", x, y);
            fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\" font-size=\"9\" "
                       "fill=\"gray\">n=%d</text>\n", x, y - 6, count[i]);
            fprintf(f, "<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">%.3g</text>\n", x,
                    H - B + 16, centres[i]);
        }
    fprintf(f, "<line x1=\"%d\" y1=\"%d\" x2=\"%d\" y2=\"%d\" stroke=\"black\"/>\n", L, H - B,
            W - Rm, H - B);
    fprintf(f, "<line x1=\"%d\" y1=\"%d\" x2=\"%d\" y2=\"%d\" stroke=\"black\"/>\n", L, T, L, H - B);
    for (i = 0; i <= 4; i++)
        fprintf(f, "<text x=\"%d\" y=\"%.1f\" text-anchor=\"end\">%d%%</text>\n", L - 4,
                H - B - (double)(H - T - B) * i / 4 + 4, 25 * i);
    fprintf(f, "<text x=\"%d\" y=\"%d\" text-anchor=\"middle\">%s</text>\n", (W + L) / 2, H - 12,
            xlabel);
    fprintf(f, "<text x=\"14\" y=\"%d\" transform=\"rotate(-90 14 %d)\" text-anchor=\"middle\">"
               "detection rate</text>\n</svg>\n",
            H / 2, H / 2);
    svg_close(&svg);
}

/* ------------------------------------------------------------ pose summary */

static double median_of(double *v, int n)
{
    if (n <= 0)
        return 0.0;
    qsort(v, (size_t)n, sizeof *v, cmp_d);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Pose figures of the right readings (corner order and handedness right):
 * medians overall and per distance / incidence bin, covariance consistency.
 * Text lines, or a JSON member "pose": {...} followed by ", ". */
static void pose_summary(const eval_ctx *c, int json, double dlo, double dstep, int nbd,
                         double ilo, double istep, int nbi)
{
    int n = 0, i, b, in_pos = 0, in_ori = 0, in_all = 0, degen = 0, elev = 0, conflict = 0,
        nconv = 0;
    double *rel = (double *)malloc((size_t)(c->frames + 1) * sizeof(double));
    double *pos = (double *)malloc((size_t)(c->frames + 1) * sizeof(double));
    double *ori = (double *)malloc((size_t)(c->frames + 1) * sizeof(double));
    double *ele = (double *)malloc((size_t)(c->frames + 1) * sizeof(double));
    double *tmp = (double *)malloc((size_t)(c->frames + 1) * sizeof(double));
    double *tmp2 = (double *)malloc((size_t)(c->frames + 1) * sizeof(double));
    double mrel, mpos, mori, mele;
    char jb[4][HOSTIO_JNUM_LEN]; /* the JSON numbers of one printf */
    if (!rel || !pos || !ori || !ele || !tmp || !tmp2)
        die("out of memory");
    for (i = 0; i < c->frames; i++) {
        const tag_result *R = &c->tres[i];
        if (!right_reading(R))
            continue;
        rel[n] = 100.0 * R->pos_err / R->distance;
        pos[n] = R->pos_err;
        ori[n] = R->ori_err / DEG;
        ele[n] = fabs((double)R->elev_err) / DEG;
        in_pos += R->m2_pos <= 7.815f;
        in_ori += R->m2_ori <= 7.815f;
        in_all += R->m2_all <= 12.592f;
        degen += (R->pose_flags & (int)ACTAG_POSE_DEGENERATE) != 0;
        elev += (R->pose_flags & (int)ACTAG_POSE_ELEVATION) != 0;
        conflict += (R->pose_flags & (int)ACTAG_POSE_MIRROR_CONFLICT) != 0;
        nconv += (R->pose_flags & (int)ACTAG_POSE_NOT_CONVERGED) != 0;
        n++;
    }
    mrel = median_of(rel, n);
    mpos = median_of(pos, n);
    mori = median_of(ori, n);
    mele = median_of(ele, n);
    if (json) {
        printf("\"pose\": {\"readings\": %d, \"median_position_error_m\": %s, "
               "\"median_position_error_pct_of_range\": %s, "
               "\"median_orientation_error_deg\": %s, \"median_elevation_error_deg\": %s, ",
               n, hostio_json_num(jb[0], "%.5f", mpos, n > 0),
               hostio_json_num(jb[1], "%.3f", mrel, n > 0),
               hostio_json_num(jb[2], "%.3f", mori, n > 0),
               hostio_json_num(jb[3], "%.3f", mele, n > 0));
        printf("\"inside_95_position\": %s, \"inside_95_orientation\": %s, "
               "\"inside_95_6d\": %s, \"flags\": {\"degenerate\": %d, \"elevation\": %d, "
               "\"mirror_conflict\": %d, \"not_converged\": %d}, \"by_distance\": [",
               hostio_json_num(jb[0], "%.4f", n ? (double)in_pos / n : 0.0, n > 0),
               hostio_json_num(jb[1], "%.4f", n ? (double)in_ori / n : 0.0, n > 0),
               hostio_json_num(jb[2], "%.4f", n ? (double)in_all / n : 0.0, n > 0), degen, elev,
               conflict, nconv);
    }
    else {
        printf("  pose of the %d readings (pose.h, corner noise %.4f m / %.4f rad):\n", n,
               (double)ACTAG_POSE_RANGE_SD, (double)ACTAG_POSE_AZIMUTH_SD);
        printf("    median position error %.4f m = %.2f %% of range (elevation %.2f deg), "
               "median orientation error %.2f deg\n", mpos, mrel, mele, mori);
        printf("    inside the predicted 95 %% ellipsoid: position %.1f %%, orientation %.1f %%, "
               "6-D %.1f %%\n", n ? 100.0 * in_pos / n : 0.0, n ? 100.0 * in_ori / n : 0.0,
               n ? 100.0 * in_all / n : 0.0);
        printf("    flags: degenerate %d, elevation %d, mirror conflict %d, not converged %d\n",
               degen, elev, conflict, nconv);
        printf("    by distance (m: n, position %% of range, orientation deg):");
    }
    for (b = 0; b < nbd + nbi; b++) {
        int m = 0, inc = b >= nbd, bb = inc ? b - nbd : b;
        for (i = 0; i < c->frames; i++) {
            const tag_result *R = &c->tres[i];
            int k;
            if (!right_reading(R))
                continue;
            k = inc ? bin_of(R->incidence / DEG, ilo, istep, nbi)
                    : bin_of(R->distance, dlo, dstep, nbd);
            if (k != bb)
                continue;
            tmp[m] = 100.0 * R->pos_err / R->distance;
            tmp2[m++] = R->ori_err / DEG;
        }
        if (b == nbd) {
            if (json)
                printf("], \"by_incidence\": [");
            else
                printf("\n    by incidence (deg: n, position %% of range, orientation deg):");
        }
        {
            double centre = inc ? ilo + (bb + 0.5) * istep : dlo + (bb + 0.5) * dstep;
            double a = median_of(tmp, m), o = median_of(tmp2, m);
            if (json)
                printf("%s{\"%s\": %.2f, \"readings\": %d, \"median_position_error_pct\": %s, "
                       "\"median_orientation_error_deg\": %s}",
                       bb ? ", " : "", inc ? "incidence_deg" : "distance_m", centre, m,
                       hostio_json_num(jb[0], "%.3f", a, m > 0),
                       hostio_json_num(jb[1], "%.3f", o, m > 0));
            else if (m > 0)
                printf(" %.4g: %d, %.2f, %.1f;", centre, m, a, o);
        }
    }
    if (json)
        printf("]}, ");
    else
        printf("\n");
    free(rel);
    free(pos);
    free(ori);
    free(ele);
    free(tmp);
    free(tmp2);
}

/* ------------------------------------------------------------ main */

/* The library's rules for a sonar the run renders, in this tool's option
 * names (as actag-sim words them). Checked before any frame: a worker
 * thread stopped on the library's field names, or a run that found no view
 * measured nothing and exited 0. */
static void check_geometry(const sim_sonar *s, const hostio_optname *names, int n)
{
    actag_error_detail d;
    if (actag_geometry_validate(&s->geo, s->rows, s->cols, &d) != ACTAG_OK) {
        char m[HOSTIO_ERRLEN];
        hostio_detail_message(&d, names, n, m);
        die(m);
    }
}

/* DIR's f_*.pgm in name order (f_0001, f_0011, ...: frame order), each as
 * DIR/NAME, malloc'd; dies when DIR cannot be read or holds none. */
static char **pool_frames(const char *dir, int *count)
{
    char err[HOSTIO_ERRLEN], m[HOSTIO_ERRLEN + 40];
    char **names = hostio_list_dir(dir, "f_", ".pgm", count, err);
    if (!names) {
        snprintf(m, sizeof m, "--pool-sequence: %s", err);
        die(m);
    }
    if (*count == 0) {
        hostio_list_free(names, 0);
        snprintf(m, sizeof m, "--pool-sequence: no f_*.pgm in '%.200s'", dir);
        die(m);
    }
    return names;
}

/* The run's output paths (NULL: option not given) are checked before any
 * of them is opened: one that names an input frame (--pool-sequence) would
 * be truncated when opened and removed by die(), and a path given to two
 * outputs would get both interleaved. Exits with status 2 naming both. */
typedef struct {
    const char *opt;
    const char *path;
} out_path;

static void check_outputs(const out_path *outs, int nout, char *const *inputs, int ninputs)
{
    int a, b;
    for (a = 0; a < nout; a++) {
        if (!outs[a].path)
            continue;
        for (b = 0; b < a; b++)
            if (outs[b].path && hostio_same_file(outs[a].path, outs[b].path)) {
                char m[1300];
                snprintf(m, sizeof m, "%s '%.500s' and %s '%.500s' are the same file; "
                         "give each output its own", outs[b].opt, outs[b].path, outs[a].opt,
                         outs[a].path);
                die(m);
            }
        for (b = 0; b < ninputs; b++)
            if (hostio_same_file(outs[a].path, inputs[b])) {
                char m[1300];
                snprintf(m, sizeof m, "%s '%.500s': is the input frame '%.500s' "
                         "(--pool-sequence); not overwritten", outs[a].opt, outs[a].path,
                         inputs[b]);
                die(m);
            }
    }
}

/* A family list with an empty name ("A,", ",A", "A,,B") is refused, not
 * read as the names it has. */
static void check_names(const char *opt, const char *list)
{
    size_t L = strlen(list);
    if (L > 0 && (list[0] == ',' || list[L - 1] == ',' || strstr(list, ",,"))) {
        char m[1200];
        snprintf(m, sizeof m, "%s: empty family name in '%.1000s'", opt, list);
        die(m);
    }
}

static void parse_free_families(eval_ctx *c, const char *list)
{
    if (!strcmp(list, "all")) {
        int i, n = actag_family_count();
        for (i = 0; i < n && c->nfree_fam < MAX_FAM; i++)
            actag_family_get_at(i, &c->free_fam[c->nfree_fam++]);
        return;
    }
    {
        char buf[1024], *tok, *save = NULL;
        if (strlen(list) >= sizeof buf)
            die("--tag-free-families: list too long");
        strcpy(buf, list);
        for (tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
            int j;
            if (c->nfree_fam >= MAX_FAM)
                die("--tag-free-families: too many families");
            if (actag_family_get(tok, &c->free_fam[c->nfree_fam]) != ACTAG_OK) {
                char m[1100];
                snprintf(m, sizeof m, "--tag-free-families: unknown family '%s'", tok);
                die(m);
            }
            for (j = 0; j < c->nfree_fam; j++)
                if (strcmp(c->free_fam[j].name, c->free_fam[c->nfree_fam].name) == 0) {
                    char m[1100];
                    snprintf(m, sizeof m, "--tag-free-families: '%s' given twice", tok);
                    die(m);
                }
            c->nfree_fam++;
        }
    }
}

int main(int argc, char **argv)
{
    static eval_ctx c;
    int i, threads = 2, json = 0, pool, corrections_set = 0, free_rows = 530, free_cols = 512;
    const char *seq_failures = NULL;
    const char *family = "AcTag24h10", *svg = NULL, *free_list = "all", *failures = NULL,
               *pose_dump = NULL;
    const char *sweep_list = "AcTag24h4,AcTag24h6,AcTag24h8,AcTag24h10";
    double aperture_deg = 60.0, elapsed;
    pthread_t th[16];
    te_options topt;
    te_counts seq_counts, pool_counts;
    const char *pool_dir = NULL;
    char **pool_names = NULL;
    int npool = 0;
    const char *free_opt = NULL, *track_opt = NULL, *length_opt = NULL; /* given, for checks */
    const char *tagged_opt = NULL; /* a setting only the tagged frames use */
    const char *scene_opt = NULL;  /* a sonar, view or appearance setting (not --pool) */
    int have_seq = 0, have_pool = 0;
    const simio_cli cli = {PROG, usage, 16, 8192, &c.sonar, &c.view, &aperture_deg};

#ifdef __GLIBC__
    /* The renderer's per-frame buffers (a few MB) would otherwise be mmap'ed
     * and faulted in anew every frame, and page faults serialise threads. */
    mallopt(M_MMAP_THRESHOLD, 256 * 1024 * 1024);
    mallopt(M_TRIM_THRESHOLD, 512 * 1024 * 1024);
#endif
    memset(&c, 0, sizeof c);
    te_options_default(&topt);
    memset(&seq_counts, 0, sizeof seq_counts);
    memset(&pool_counts, 0, sizeof pool_counts);
    c.frames = 1000;
    c.seed = 1;
    c.min_margin = c.search_min_margin = -1.0e6f;
    c.many_margin = -1.0f;
    c.min_bit_margin = -1;
    c.min_bit_odds = 0;
    c.level_noise = -1;
    c.min_structure = c.min_side = -1.0f;
    c.min_texture = -1.0f;
    c.median_radius = c.median_per_range = -1;
    pool = simio_opt_defaults(argc, argv, &c.sonar, &c.view, &c.app); /* --pool first */
    for (i = 1; i < argc; i++) {
        const char *o = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
#define NEED() simio_opt_need(PROG, o, v, &i)
        if (simio_opt_common(&cli, argc, argv, &i)) {
            if (strcmp(o, "--pool") != 0)
                scene_opt = o;
        } else if (!strcmp(o, "--frames")) {
            NEED();
            c.frames = (int)inum(o, v, 0, 10000000);
        } else if (!strcmp(o, "--tag-free")) {
            NEED();
            c.tag_free = (int)inum(o, v, 0, 10000000);
        } else if (!strcmp(o, "--family")) {
            scene_opt = o;
            NEED();
            family = v;
        } else if (!strcmp(o, "--tag-free-families")) {
            free_opt = o;
            NEED();
            free_list = v;
        } else if (!strcmp(o, "--corrections")) {
            tagged_opt = o;
            NEED();
            c.corrections = (int)inum(o, v, 0, 16);
            corrections_set = 1;
        } else if (!strcmp(o, "--min-margin")) {
            tagged_opt = o;
            NEED();
            c.min_margin = (float)num(o, v, -1e6, 1e6);
        } else if (!strcmp(o, "--min-structure")) {
            tagged_opt = o;
            NEED();
            c.min_structure = (float)num(o, v, 0.0, 1.0);
        } else if (!strcmp(o, "--min-texture-contrast")) {
            tagged_opt = o;
            NEED();
            c.min_texture = (float)num(o, v, 0.0, 1e6);
        } else if (!strcmp(o, "--min-side-fraction")) {
            tagged_opt = o;
            NEED();
            c.min_side = (float)num(o, v, 0.0, 10.0);
        } else if (!strcmp(o, "--median-radius")) {
            tagged_opt = o;
            NEED();
            c.median_radius = (int)inum(o, v, 0, 127);
        } else if (!strcmp(o, "--median-per-range")) {
            tagged_opt = o;
            NEED();
            c.median_per_range = (int)inum(o, v, 0, 1);
        } else if (!strcmp(o, "--plane-sd")) {
            tagged_opt = o;
            NEED();
            c.plane_sd = (float)num(o, v, 0.0, 100.0);
        } else if (!strcmp(o, "--plane-tilt-deg")) {
            tagged_opt = o;
            NEED();
            c.plane_tilt = (float)(num(o, v, 0.0, 90.0) * DEG);
        } else if (!strcmp(o, "--min-bit-margin")) {
            tagged_opt = o;
            NEED();
            c.min_bit_margin = (int)inum(o, v, 0, 32);
        } else if (!strcmp(o, "--min-bit-odds")) {
            tagged_opt = o;
            NEED();
            c.min_bit_odds = (int)inum(o, v, 1, 1000000);
        } else if (!strcmp(o, "--search-min-margin")) {
            tagged_opt = o;
            NEED();
            c.search_min_margin = (float)num(o, v, -1e6, 1e6);
        } else if (!strcmp(o, "--many-corrections-margin")) {
            tagged_opt = o;
            NEED();
            c.many_margin = (float)num(o, v, 0.0, 1e6);
        } else if (!strcmp(o, "--level-noise")) {
            tagged_opt = o;
            NEED();
            c.level_noise = (int)inum(o, v, 0, 1);
        } else if (!strcmp(o, "--separate-noise")) {
            tagged_opt = o;
            c.separate_noise = 1;
        } else if (!strcmp(o, "--handedness")) {
            static const char *const words[3] = {"any", "unmirrored", "mirrored"};
            NEED(); /* the words in ACTAG_HANDEDNESS_* order */
            c.handedness = hostio_opt_choice(PROG, o, v, words, 3);
        } else if (!strcmp(o, "--seed")) {
            NEED();
            c.seed = hostio_opt_u32(PROG, o, v, 0u, 4294967295u);
        } else if (!strcmp(o, "--threads")) {
            NEED();
            threads = (int)inum(o, v, 1, 16);
        } else if (!strcmp(o, "--sweep-families")) {
            free_opt = o;
            NEED();
            sweep_list = v;
        } else if (!strcmp(o, "--free-rows")) {
            free_opt = o;
            NEED();
            free_rows = (int)inum(o, v, 16, 8192);
        } else if (!strcmp(o, "--free-cols")) {
            free_opt = o;
            NEED();
            free_cols = (int)inum(o, v, 16, 8192);
        } else if (!strcmp(o, "--free-max-range")) {
            double mm[2];
            char e2[HOSTIO_ERRLEN];
            free_opt = o;
            NEED();
            if (hostio_parse_doubles(o, v, ',', mm, 2, e2) != HOSTIO_OK)
                die(e2);
            if (!(mm[0] > 0.0 && mm[1] >= mm[0])) {
                char m[HOSTIO_ERRLEN + 80];
                snprintf(m, sizeof m, "--free-max-range: expected LO,HI with 0 < LO <= HI (got %s)",
                         v);
                die(m);
            }
            c.free_min_max_range = (float)mm[0];
            c.free_max_max_range = (float)mm[1];
        } else if (!strcmp(o, "--gain")) { /* appearance: actag-sim's ranges */
            scene_opt = o;
            NEED();
            c.app.gain = (float)num(o, v, 0.0, 1e6);
        } else if (!strcmp(o, "--noise")) {
            scene_opt = o;
            NEED();
            c.app.noise = (float)num(o, v, 0.0, 1e6);
        } else if (!strcmp(o, "--bands")) {
            scene_opt = o;
            NEED();
            c.app.band_rate = (float)num(o, v, 0.0, 20.0);
        } else if (!strcmp(o, "--psf-azimuth")) {
            scene_opt = o;
            NEED();
            c.app.psf_azimuth = (float)num(o, v, 0.0, 0.5);
        } else if (!strcmp(o, "--psf-range")) {
            scene_opt = o;
            NEED();
            c.app.psf_range = (float)num(o, v, 0.0, 1.0);
        } else if (!strcmp(o, "--foam")) {
            scene_opt = o;
            NEED();
            c.app.foam = (float)num(o, v, 0.0, 1e6);
        } else if (!strcmp(o, "--seabed-level")) {
            scene_opt = o;
            NEED();
            c.app.seabed = (float)num(o, v, 0.0, 1e6);
        } else if (!strcmp(o, "--metal-specular")) {
            scene_opt = o;
            NEED();
            c.app.metal_specular = (float)num(o, v, 0.0, 1e6);
        } else if (!strcmp(o, "--metal-diffuse")) {
            scene_opt = o;
            NEED();
            c.app.metal_diffuse = (float)num(o, v, 0.0, 1e6);
        } else if (!strcmp(o, "--spreading")) {
            scene_opt = o;
            NEED();
            c.app.spreading = (float)num(o, v, -4.0, 4.0);
        } else if (!strcmp(o, "--looks")) {
            scene_opt = o;
            NEED();
            c.app.looks = (int)inum(o, v, 1, 8);
        } else if (!strcmp(o, "--json")) {
            json = 1;
        } else if (!strcmp(o, "--svg")) {
            NEED();
            svg = v;
        } else if (!strcmp(o, "--pose-dump")) {
            tagged_opt = o;
            NEED();
            pose_dump = v;
        } else if (!strcmp(o, "--failures")) {
            tagged_opt = o;
            NEED();
            failures = v;
        } else if (!strcmp(o, "--quiet")) {
            c.quiet = 1;
        } else if (!strcmp(o, "--sequences")) {
            NEED();
            topt.sequences = (int)inum(o, v, 0, 100000);
        } else if (!strcmp(o, "--sequence-failures")) {
            NEED();
            seq_failures = v;
        } else if (!strcmp(o, "--sequence-length")) {
            length_opt = o;
            NEED();
            topt.length = (int)inum(o, v, 1, 100000);
        } else if (!strcmp(o, "--pool-sequence")) {
            NEED();
            pool_dir = v;
        } else if (!strcmp(o, "--full-every")) {
            track_opt = o;
            NEED();
            topt.track.full_every = (int)inum(o, v, 1, 100000);
        } else if (!strcmp(o, "--confirm-frames")) {
            track_opt = o;
            NEED();
            topt.track.confirm_frames = (int)inum(o, v, 1, 1000);
        } else if (!strcmp(o, "--confirm-margin")) {
            track_opt = o;
            NEED();
            topt.track.confirm_margin = (float)num(o, v, -1e6, 1e6);
        } else if (!strcmp(o, "--max-missed")) {
            track_opt = o;
            NEED();
            topt.track.max_missed = (int)inum(o, v, 0, 1000);
        } else if (!strcmp(o, "--roi-scale")) {
            track_opt = o;
            NEED();
            topt.track.roi_scale = (float)num(o, v, 0.01, 10.0);
        } else if (!strcmp(o, "--refind-after")) {
            track_opt = o;
            NEED();
            topt.track.refind_after = (int)inum(o, v, 0, 1000);
        } else if (!strcmp(o, "--relax-roi")) {
            track_opt = o;
            topt.relax_roi = 1;
        } else if (!strcmp(o, "--report-coasting")) {
            track_opt = o;
            topt.track.report_coasting = 1;
        } else {
            hostio_opt_unknown(PROG, o);
        }
#undef NEED
    }
    if (!pool || aperture_deg != 60.0)
        c.sonar.geo.aperture = (float)(aperture_deg * DEG);
    if (!(c.sonar.geo.max_range > c.sonar.geo.min_range)) {
        char m[200];
        snprintf(m, sizeof m, "--max-range: must be above --min-range %g (got %g)",
                 (double)c.sonar.geo.min_range, (double)c.sonar.geo.max_range);
        die(m);
    }
    simio_opt_check_views(PROG, &c.view);
    simio_opt_family(PROG, "--family", family, &c.fam);
    if (!corrections_set)
        c.corrections = ACTAG_CORRECTIONS_AUTO;
    else if (c.corrections > actag_family_max_corrections(&c.fam)) {
        char m[300];
        snprintf(m, sizeof m, "--corrections: %s allows at most %d (got %d)", family,
                 actag_family_max_corrections(&c.fam), c.corrections);
        die(m);
    }
    /* options of runs that are not made would be ignored: refuse them */
    if (free_opt && c.tag_free == 0) {
        char m[200];
        snprintf(m, sizeof m, "%s: applies to tag-free frames only; it needs --tag-free N (N > 0)",
                 free_opt);
        die(m);
    }
    if (tagged_opt && c.frames == 0) {
        char m[200];
        snprintf(m, sizeof m, "%s: a setting of the tagged frames; it needs --frames N (N > 0)",
                 tagged_opt);
        die(m);
    }
    if (scene_opt && c.frames == 0 && c.tag_free == 0 && topt.sequences == 0) {
        char m[240];
        snprintf(m, sizeof m, "%s: a simulated frame's setting; --pool-sequence alone reads the "
                 "recorded frames (their sonar is the pool's)", scene_opt);
        die(m);
    }
    if (track_opt && topt.sequences == 0 && !pool_dir) {
        char m[200];
        snprintf(m, sizeof m, "%s: a tracker setting; it needs --sequences N (N > 0) or "
                 "--pool-sequence DIR", track_opt);
        die(m);
    }
    if (length_opt && topt.sequences == 0)
        die("--sequence-length needs --sequences N (N > 0)");
    if (seq_failures && topt.sequences == 0)
        die("--sequence-failures needs --sequences N (N > 0)");
    check_names("--tag-free-families", free_list);
    check_names("--sweep-families", sweep_list);
    if (c.frames > 0) { /* settings the detector refuses: now, named by their options */
        static const hostio_optname names[] = {
            {"max_bit_corrections", "--corrections", 0},
            {"min_margin", "--min-margin", 0},
            {"handedness", "--handedness", 0},
            {"tuning.fit.min_bit_margin", "--min-bit-margin", 0},
            {"tuning.fit.min_bit_odds", "--min-bit-odds", 0},
            {"tuning.min_structure", "--min-structure", 0},
            {"tuning.min_texture_contrast", "--min-texture-contrast", 0},
            {"tuning.min_side_fraction", "--min-side-fraction", 0},
            {"tuning.median_radius", "--median-radius", 0},
            {"tuning.median_per_range", "--median-per-range", 0},
            {"tuning.search_min_margin", "--search-min-margin", 0},
            {"tuning.fit.many_corrections_margin", "--many-corrections-margin", 0},
        };
        actag_params p;
        actag_error_detail d;
        char m[HOSTIO_ERRLEN];
        tag_params(&c, &p);
        if (c.min_side > p.tuning.max_side_fraction) { /* the pair's rule, said plainly */
            snprintf(m, sizeof m, "--min-side-fraction: must be at most %g, the largest side "
                     "fraction (got %g)", (double)p.tuning.max_side_fraction, (double)c.min_side);
            die(m);
        }
        if (actag_params_validate(&p, &d) != ACTAG_OK) {
            hostio_detail_message(&d, names, (int)(sizeof names / sizeof names[0]), m);
            die(m);
        }
    }
    parse_free_families(&c, free_list);
    if (c.nfree_fam == 0)
        die("--tag-free-families: no family given");
    if (strcmp(sweep_list, "all") != 0) { /* every sweep name must be a family */
        char buf[1024], *tok, *save = NULL;
        actag_family tmp;
        if (strlen(sweep_list) >= sizeof buf)
            die("--sweep-families: list too long");
        strcpy(buf, sweep_list);
        for (tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save))
            if (actag_family_get(tok, &tmp) != ACTAG_OK) {
                char m[1100];
                snprintf(m, sizeof m, "--sweep-families: unknown family '%s'", tok);
                die(m);
            }
    }
    {
        int f;
        for (f = 0; f < c.nfree_fam; f++) {
            size_t L = strlen(c.free_fam[f].name);
            const char *p = sweep_list;
            c.sweep[f] = !strcmp(sweep_list, "all");
            /* token by token: a name that is a prefix of another must not match */
            while (!c.sweep[f] && (p = strstr(p, c.free_fam[f].name)) != NULL) {
                if ((p == sweep_list || p[-1] == ',') && (p[L] == ',' || p[L] == 0))
                    c.sweep[f] = 1;
                p += L;
            }
        }
    }
    c.free_sonar = c.sonar;
    c.free_sonar.rows = free_rows;
    c.free_sonar.cols = free_cols;
    {
        int given = c.free_max_max_range > 0.0f;
        if (!given) {
            c.free_min_max_range = 3.0f;
            c.free_max_max_range = 6.0f;
        }
        if (c.tag_free > 0 && !(c.free_min_max_range > c.sonar.geo.min_range)) {
            char m[200];
            snprintf(m, sizeof m, "--free-max-range: must be above --min-range %g (got %g,%g%s)",
                     (double)c.sonar.geo.min_range, (double)c.free_min_max_range,
                     (double)c.free_max_max_range, given ? "" : ", the default");
            die(m);
        }
    }
    topt.handedness = c.handedness;
    if (c.frames + c.tag_free == 0 && topt.sequences == 0 && !pool_dir)
        die("--frames, --tag-free and --sequences are 0 and no --pool-sequence: nothing to do");
    {
        /* the sonars the run renders, in actag-sim's option names */
        static const hostio_optname names[] = {
            {"min_range", "--min-range", 0},   {"max_range", "--max-range", 0},
            {"aperture", "--aperture-deg", 57.29577951308232},
            {"flags", "--range/azimuth-ascending", 0},
            {"rows", "--rows", 0},             {"cols", "--cols", 0}};
        static const hostio_optname free_names[] = {
            {"min_range", "--min-range", 0},   {"max_range", "--free-max-range", 0},
            {"aperture", "--aperture-deg", 57.29577951308232},
            {"flags", "--range/azimuth-ascending", 0},
            {"rows", "--free-rows", 0},        {"cols", "--free-cols", 0}};
        const int nn = (int)(sizeof names / sizeof names[0]);
        if (c.frames > 0 || topt.sequences > 0)
            check_geometry(&c.sonar, names, nn);
        if (c.tag_free > 0) {
            /* each tag-free frame draws its maximum range from LO..HI: both ends */
            sim_sonar fs = c.free_sonar;
            fs.geo.max_range = c.free_min_max_range;
            check_geometry(&fs, free_names, nn);
            fs.geo.max_range = c.free_max_max_range;
            check_geometry(&fs, free_names, nn);
        }
    }
    if (svg)
        hostio_opt_mkdirs(PROG, "--svg", svg); /* parents too */
    /* Before the run, not after minutes of it: an empty --pool-sequence
     * folder and an output path that cannot be written are refused at once
     * (the files are closed when the run has succeeded). */
    if (pool_dir)
        pool_names = pool_frames(pool_dir, &npool);
    {
        /* the files of --svg DIR too (svg_histogram and svg_rate's names) */
        static const char *const svg_names[4] = {"range_error.svg", "azimuth_error.svg",
                                                 "rate_vs_distance.svg", "rate_vs_incidence.svg"};
        char *svg_paths[4] = {NULL, NULL, NULL, NULL};
        int k;
        for (k = 0; k < 4 && svg; k++) {
            size_t n = strlen(svg) + strlen(svg_names[k]) + 2;
            svg_paths[k] = (char *)malloc(n);
            if (svg_paths[k])
                snprintf(svg_paths[k], n, "%s/%s", svg, svg_names[k]);
            else
                die("out of memory");
        }
        {
            const out_path outs[] = {{"--pose-dump", pose_dump},
                                     {"--failures", failures},
                                     {"--sequence-failures", seq_failures},
                                     {"--svg", svg_paths[0]},
                                     {"--svg", svg_paths[1]},
                                     {"--svg", svg_paths[2]},
                                     {"--svg", svg_paths[3]}};
            check_outputs(outs, (int)(sizeof outs / sizeof outs[0]), pool_names, npool);
        }
        for (k = 0; k < 4; k++)
            free(svg_paths[k]);
    }
    if (pose_dump)
        open_output(&g_pose_out, "--pose-dump", pose_dump);
    if (failures)
        open_output(&g_fail_out, "--failures", failures);
    if (seq_failures)
        topt.failures = open_output(&g_seq_out, "--sequence-failures", seq_failures);
    c.tres = (tag_result *)calloc((size_t)(c.frames > 0 ? c.frames : 1), sizeof *c.tres);
    c.fres = (free_result *)calloc((size_t)(c.tag_free > 0 ? c.tag_free : 1), sizeof *c.fres);
    if (!c.tres || !c.fres)
        die("out of memory");
    pthread_mutex_init(&c.lock, NULL);
    c.t0 = now_s();
    for (i = 0; i < threads; i++)
        pthread_create(&th[i], NULL, worker, &c);
    for (i = 0; i < threads; i++)
        pthread_join(th[i], NULL);
    /* ---- tracking */
    topt.threads = threads;
    if (topt.sequences > 0) {
        te_run_sequences(&c.sonar, &c.view, &c.app, &c.fam, tag_size_default, c.seed, &topt,
                         &seq_counts, c.quiet);
        topt.failures = NULL;
        have_seq = 1;
    }
    if (pool_dir) {
        char **names = pool_names, err[HOSTIO_ERRLEN];
        int nn = npool;
        actag_sonar_geometry pg = {0.1f, 1.5f, (float)(60.0 * DEG), NULL, 0u};
        actag_family f24;
        if (actag_family_get("AcTag24h10", &f24) != ACTAG_OK)
            die("--pool-sequence needs the AcTag24h10 family in the build");
        {
            /* The pool recording's visibility, judged once by eye (the same
             * judgement as bench/pool_recall.sh): no tag in 0011 0111 0211
             * 0321 0421 0521, the tag partly out of view in 0331-0371. */
            static const char *const tag_free[] = {"0011", "0111", "0211", "0321", "0421", "0521"};
            static const char *const partial[] = {"0331", "0341", "0351", "0361", "0371"};
            int *vis = (int *)malloc((size_t)nn * sizeof *vis), a2;
            if (!vis)
                die("out of memory");
            for (i = 0; i < nn; i++) {
                const char *b = strrchr(names[i], '/');
                b = b ? b + 1 : names[i];
                vis[i] = 1;
                for (a2 = 0; a2 < 6; a2++)
                    if (!strncmp(b + 2, tag_free[a2], 4))
                        vis[i] = -1;
                for (a2 = 0; a2 < 5; a2++)
                    if (!strncmp(b + 2, partial[a2], 4))
                        vis[i] = 0;
            }
            /* pg is the pool recording's geometry: its 530 x 512 frames only */
            if (te_run_files((const char *const *)names, nn, 530, 512, &pg, &f24,
                             tag_size_default, 0, vis, &topt, &pool_counts, err) != 0) {
                char m[HOSTIO_ERRLEN + 100];
                snprintf(m, sizeof m, "--pool-sequence: %s", err);
                die(m);
            }
            free(vis);
        }
        hostio_list_free(names, nn);
        have_pool = 1;
    }
    elapsed = now_s() - c.t0;

    /* ---- aggregate the tagged frames */
    {
        int sampled = 0, found = 0, wrong = 0, falset = 0, merr = 0, oerr = 0, nerr = 0;
        int mirrored_views = 0, found_mirrored = 0, hcount[17] = {0};
        double *re = (double *)malloc((size_t)(4 * c.frames + 1) * sizeof(double));
        double *ae = (double *)malloc((size_t)(4 * c.frames + 1) * sizeof(double));
        int nbd, nbi, bd_cnt[MAX_BINS] = {0}, bd_hit[MAX_BINS] = {0}, bi_cnt[MAX_BINS] = {0},
                       bi_hit[MAX_BINS] = {0};
        double bd_c[MAX_BINS], bi_c[MAX_BINS], bd_r[MAX_BINS], bi_r[MAX_BINS];
        double bd_rsd[MAX_BINS], bd_asd[MAX_BINS];
        double dstep = 0.5, istep = 10.0, dlo = floor(c.view.min_distance / 0.5) * 0.5;
        double ilo = floor(c.view.min_incidence / DEG / 10.0) * 10.0;
        err_stats rs, as;
        int fam_total[MAX_FAM][NCORR], fam_frames[MAX_FAM][NCORR];
        FILE *ff = g_fail_out.f; /* --failures, or NULL */
        /* the limits come back from float (80 degrees as 80.0000045): a
         * millionth of a bin below an edge is on it (no empty 85 bin) */
        nbd = (int)ceil((c.view.max_distance - dlo) / dstep - 1e-6);
        if (nbd > MAX_BINS) {
            /* far tags: bins of a wider multiple of 0.5 m, so that every
             * distance has its own bin (not all beyond 32 m the last) */
            dstep = 0.5 * ceil((c.view.max_distance - c.view.min_distance) / (0.5 * (MAX_BINS - 1)));
            dlo = floor(c.view.min_distance / dstep) * dstep;
            nbd = (int)ceil((c.view.max_distance - dlo) / dstep - 1e-6);
        }
        nbi = (int)ceil((c.view.max_incidence / DEG - ilo) / istep - 1e-6);
        if (nbd < 1) nbd = 1;
        if (nbi < 1) nbi = 1;
        if (nbd > MAX_BINS) nbd = MAX_BINS;
        if (nbi > MAX_BINS) nbi = MAX_BINS;
        if (pose_dump) {
            FILE *pf = g_pose_out.f;
            for (i = 0; i < c.frames; i++) {
                const tag_result *R = &c.tres[i];
                if (!right_reading(R))
                    continue;
                fprintf(pf,
                        "{\"frame\": %d, \"distance\": %.4f, \"incidence_deg\": %.3f, "
                        "\"range\": %.5f, \"mirrored\": %d, \"elevation\": %.6f, "
                        "\"elevation_est\": %.6f, \"band\": [%.6f, %.6f], "
                        "\"position_error\": %.6f, \"orientation_error\": %.6f, "
                        "\"w\": [%.6f, %.6f, %.6f], \"flags\": %d, "
                        "\"range_errors\": [%.6f, %.6f, %.6f, %.6f], "
                        "\"azimuth_errors\": [%.7f, %.7f, %.7f, %.7f], "
                        "\"m2\": [%.3f, %.3f, %.3f], \"hamming\": %d, "
                        "\"decision_margin\": %.3f, \"from_search\": %d}\n",
                        i, R->distance, R->incidence / DEG, R->range_true, R->mirrored,
                        R->el_true, R->el_est, R->el_lo, R->el_hi, R->pos_err, R->ori_err,
                        R->w_err[0], R->w_err[1], R->w_err[2], R->pose_flags, R->range_err[0],
                        R->range_err[1], R->range_err[2], R->range_err[3], R->az_err[0],
                        R->az_err[1], R->az_err[2], R->az_err[3], R->m2_pos, R->m2_ori,
                        R->m2_all, R->hamming, R->margin, R->found_search);
            }
        }
        {
            /* per distance bin error spread (range, azimuth) */
            double *tmpr = (double *)malloc((size_t)(4 * c.frames + 1) * sizeof(double));
            double *tmpa = (double *)malloc((size_t)(4 * c.frames + 1) * sizeof(double));
            int b;
            for (b = 0; b < nbd; b++) {
                int m = 0;
                for (i = 0; i < c.frames; i++) {
                    const tag_result *R = &c.tres[i];
                    int bb, n;
                    if (!right_reading(R))
                        continue;
                    bb = bin_of(R->distance, dlo, dstep, nbd);
                    if (bb != b)
                        continue;
                    for (n = 0; n < 4; n++) {
                        tmpr[m] = R->range_err[n];
                        tmpa[m++] = R->az_err[n];
                    }
                }
                bd_rsd[b] = stats_of(tmpr, m).sd;
                bd_asd[b] = stats_of(tmpa, m).sd;
            }
            free(tmpr);
            free(tmpa);
        }
        for (i = 0; i < c.frames; i++) {
            const tag_result *R = &c.tres[i];
            int bd, bi, n;
            if (!R->sampled)
                continue;
            sampled++;
            mirrored_views += R->mirrored;
            bd = bin_of(R->distance, dlo, dstep, nbd);
            bi = bin_of(R->incidence / DEG, ilo, istep, nbi);
            bd_cnt[bd]++;
            bi_cnt[bi]++;
            wrong += R->wrong_id;
            falset += R->false_tags;
            if (ff && (R->wrong_id || R->false_tags || (R->found && (R->mirror_err || R->order_err))))
                fprintf(ff, "{\"frame\": %d, \"run_seed\": %u, \"frame_seed\": %u, \"distance\": %.4f, \"incidence_deg\": "
                            "%.2f, \"mirrored\": %d, \"found\": %d, \"wrong_id\": %d, "
                            "\"false_tags\": %d, \"mirror_error\": %d, \"order_error\": %d, "
                            "\"margin\": %.3f, \"wrong_margin\": %.3f, \"wrong_hamming\": %d, "
                            "\"wrong_from_search\": %d, \"found_from_search\": %d}\n",
                        i, (unsigned)c.seed, (unsigned)R->seed, (double)R->distance, R->incidence / DEG,
                        R->mirrored, R->found, R->wrong_id, R->false_tags, R->mirror_err,
                        R->order_err, (double)R->margin, (double)R->wrong_margin,
                        R->wrong_hamming, R->wrong_search, R->found_search);
            if (!R->found)
                continue;
            merr += R->mirror_err;
            oerr += R->order_err;
            if (!right_reading(R))
                continue; /* the right ID read wrongly: an error, no detection */
            found++;
            found_mirrored += R->mirrored;
            bd_hit[bd]++;
            bi_hit[bi]++;
            if (R->hamming >= 0 && R->hamming < 17)
                hcount[R->hamming]++;
            for (n = 0; n < 4; n++) {
                re[nerr] = R->range_err[n];
                ae[nerr++] = R->az_err[n];
            }
        }
        if (c.frames > 0 && sampled == 0) /* measured nothing: not a result */
            die("--frames: no view keeps the whole tag in the field of view; widen "
                "--min-distance/--max-distance or the apertures");
        rs = stats_of(re, nerr);
        as = stats_of(ae, nerr);
        for (i = 0; i < nbd; i++) {
            bd_c[i] = dlo + (i + 0.5) * dstep;
            bd_r[i] = bd_cnt[i] ? (double)bd_hit[i] / bd_cnt[i] : 0.0;
        }
        for (i = 0; i < nbi; i++) {
            bi_c[i] = ilo + (i + 0.5) * istep;
            bi_r[i] = bi_cnt[i] ? (double)bi_hit[i] / bi_cnt[i] : 0.0;
        }
        {
            int f, k, j;
            for (f = 0; f < c.nfree_fam; f++)
                for (k = 0; k < NCORR; k++) {
                    fam_total[f][k] = 0;
                    fam_frames[f][k] = 0;
                    for (j = 0; j < c.tag_free; j++) {
                        if (c.fres[j].det[f][k] < 0) {
                            fam_total[f][k] = fam_frames[f][k] = -1;
                            break;
                        }
                        fam_total[f][k] += c.fres[j].det[f][k];
                        fam_frames[f][k] += c.fres[j].det[f][k] > 0;
                    }
                }
        }
        if (json) {
            int f, k;
            char jb[4][HOSTIO_JNUM_LEN]; /* the JSON numbers of one printf */
            printf("{\"family\": \"%s\", \"seed\": %u, \"rows\": %d, \"cols\": %d, "
                   "\"min_range\": %g, \"max_range\": %g, \"aperture_deg\": %g, "
                   "\"vertical_aperture_deg\": %g, \"min_distance\": %g, \"max_distance\": %g, "
                   "\"frames\": %d, \"views\": %d, \"mirrored_views\": %d, \"detected\": %d, "
                   "\"detection_rate\": %s, \"detected_mirrored\": %d, \"wrong_ids\": %d, "
                   "\"false_tags\": %d, \"mirror_errors\": %d, \"corner_order_errors\": %d, "
                   "\"hamming\": [",
                   c.fam.name, (unsigned)c.seed, c.sonar.rows, c.sonar.cols,
                   (double)c.sonar.geo.min_range, (double)c.sonar.geo.max_range,
                   c.sonar.geo.bearings ? 0.0 : c.sonar.geo.aperture / DEG,
                   c.sonar.vertical_aperture / DEG, (double)c.view.min_distance,
                   (double)c.view.max_distance, c.frames, sampled, mirrored_views, found,
                   hostio_json_num(jb[0], "%.4f", sampled ? (double)found / sampled : 0.0,
                                   sampled > 0),
                   found_mirrored, wrong, falset, merr, oerr);
            for (k = 0; k <= actag_family_max_corrections(&c.fam) && k < 17; k++)
                printf("%s%d", k ? ", " : "", hcount[k]);
            printf("], \"range_error_m\": {\"mean\": %s, \"sd\": %s, \"p95_abs\": %s, "
                   "\"corners\": %d}, ",
                   hostio_json_num(jb[0], "%.6f", rs.mean, rs.n > 0),
                   hostio_json_num(jb[1], "%.6f", rs.sd, rs.n > 1),
                   hostio_json_num(jb[2], "%.6f", rs.p95, rs.n > 0), rs.n);
            printf("\"azimuth_error_rad\": {\"mean\": %s, \"sd\": %s, "
                   "\"p95_abs\": %s, \"corners\": %d}, \"by_distance\": [",
                   hostio_json_num(jb[0], "%.6f", as.mean, as.n > 0),
                   hostio_json_num(jb[1], "%.6f", as.sd, as.n > 1),
                   hostio_json_num(jb[2], "%.6f", as.p95, as.n > 0), as.n);
            /* a bin's spread needs two corners, its rate a view: null without */
            for (i = 0; i < nbd; i++)
                printf("%s{\"distance_m\": %.2f, \"views\": %d, \"detected\": %d, \"rate\": %s, "
                       "\"range_sd_m\": %s, \"azimuth_sd_rad\": %s}",
                       i ? ", " : "", bd_c[i], bd_cnt[i], bd_hit[i],
                       hostio_json_num(jb[0], "%.4f", bd_r[i], bd_cnt[i] > 0),
                       hostio_json_num(jb[1], "%.6f", bd_rsd[i], bd_hit[i] > 0),
                       hostio_json_num(jb[2], "%.6f", bd_asd[i], bd_hit[i] > 0));
            printf("], \"by_incidence\": [");
            for (i = 0; i < nbi; i++)
                printf("%s{\"incidence_deg\": %.1f, \"views\": %d, \"detected\": %d, \"rate\": %s}",
                       i ? ", " : "", bi_c[i], bi_cnt[i], bi_hit[i],
                       hostio_json_num(jb[0], "%.4f", bi_r[i], bi_cnt[i] > 0));
            printf("], ");
            pose_summary(&c, 1, dlo, dstep, nbd, ilo, istep, nbi);
            printf("\"tag_free\": {\"frames\": %d, \"families\": [", c.tag_free);
            for (f = 0; f < c.nfree_fam; f++) {
                printf("%s{\"family\": \"%s\", \"codes\": %d", f ? ", " : "", c.free_fam[f].name,
                       c.free_fam[f].ncodes);
                for (k = 0; k < NCORR; k++) {
                    static const char *kn[NCORR] = {"zero", "default", "maximal"};
                    if (fam_frames[f][k] < 0) { /* not run */
                        printf(", \"%s\": null", kn[k]);
                        continue;
                    }
                    printf(", \"%s\": {\"corrections\": %d, \"detections\": %d, \"frames_with_"
                           "detections\": %d, \"rate\": %s}",
                           kn[k], corrections_of(&c.free_fam[f], k),
                           fam_total[f][k], fam_frames[f][k],
                           hostio_json_num(jb[0], "%.6f", c.tag_free ? (double)fam_frames[f][k] / c.tag_free : 0.0,
                                c.tag_free > 0));
                }
                printf("}");
            }
            printf("]}, ");
            if (have_seq) {
                printf("\"tracking_sequences\": ");
                te_print(stdout, "simulated passes", &seq_counts, &topt, 1);
                printf(", \"sequences\": %d, \"sequence_length\": %d, ", topt.sequences,
                       topt.length);
            }
            if (have_pool) {
                printf("\"tracking_pool\": ");
                te_print(stdout, pool_dir, &pool_counts, &topt, 1);
                printf(", ");
            }
            printf("\"seconds\": %.1f, \"threads\": %d}\n", elapsed, threads);
        } else {
            int f, k;
            if (c.frames > 0) {
                printf("tagged frames: %d (%s, %d x %d, %.2f-%.2f m, sonar %.2f-%.2f m from the "
                       "tag, %.0f-%.0f deg incidence)\n",
                       c.frames, c.fam.name, c.sonar.rows, c.sonar.cols,
                       (double)c.sonar.geo.min_range, (double)c.sonar.geo.max_range,
                       (double)c.view.min_distance, (double)c.view.max_distance,
                       c.view.min_incidence / DEG, c.view.max_incidence / DEG);
                printf("  views with the whole tag in the field of view: %d (%d mirrored)\n",
                       sampled, mirrored_views);
                printf("  detected (right ID, handedness and corner order at the tag): %d = %.1f %% (%d of them mirrored)\n",
                       found, sampled ? 100.0 * found / sampled : 0.0, found_mirrored);
                printf("  wrong IDs: %d   false tags: %d   mirrored-flag errors: %d   "
                       "corner-order errors: %d\n",
                       wrong, falset, merr, oerr);
                printf("  hamming of the detections:");
                for (k = 0; k <= actag_family_max_corrections(&c.fam) && k < 17; k++)
                    printf(" %d:%d", k, hcount[k]);
                {
                    double *mv = (double *)malloc((size_t)(found + 1) * sizeof(double));
                    int nm = 0;
                    for (k = 0; k < c.frames; k++)
                        if (right_reading(&c.tres[k]))
                            mv[nm++] = c.tres[k].margin;
                    if (nm > 0) {
                        double med = median_of(mv, nm); /* sorts mv */
                        printf("\n  decision margin of the detections: min %.2f  5%% %.2f  median %.2f",
                               mv[0], mv[(int)(0.05 * (nm - 1))], med);
                    }
                    nm = 0;
                    for (k = 0; k < c.frames; k++)
                        if (right_reading(&c.tres[k]) && c.tres[k].found_search)
                            nm++;
                    printf(" (%d read by the structure search)", nm);
                    free(mv);
                }
                printf("\n  range error per corner (m):     mean %+.5f  sd %.5f  95%% |e| %.5f  "
                       "(%d corners)\n",
                       rs.mean, rs.sd, rs.p95, rs.n);
                printf("  azimuth error per corner (rad): mean %+.5f  sd %.5f  95%% |e| %.5f\n",
                       as.mean, as.sd, as.p95);
                printf("  by distance (m):   ");
                for (i = 0; i < nbd; i++)
                    printf(" %.2f: %d/%d", bd_c[i], bd_hit[i], bd_cnt[i]);
                printf("\n  by incidence (deg):");
                for (i = 0; i < nbi; i++)
                    printf(" %.0f: %d/%d", bi_c[i], bi_hit[i], bi_cnt[i]);
                printf("\n");
                pose_summary(&c, 0, dlo, dstep, nbd, ilo, istep, nbi);
            }
            if (c.tag_free > 0) {
                printf("tag-free frames: %d; frames with false detections (detections), by bit "
                       "corrections\n",
                       c.tag_free);
                printf("  %-12s %6s  %-22s %-22s %-22s\n", "family", "codes", "zero", "default",
                       "maximal");
                for (f = 0; f < c.nfree_fam; f++) {
                    int mx = actag_family_max_corrections(&c.free_fam[f]);
                    int df = mx < ACTAG_AUTO_CORRECTIONS ? mx : ACTAG_AUTO_CORRECTIONS;
                    char b0[64], b1[64], b2[64];
                    snprintf(b0, sizeof b0, "0: %d (%d) %.3f%%", fam_frames[f][0], fam_total[f][0],
                             100.0 * fam_frames[f][0] / c.tag_free);
                    if (fam_frames[f][0] < 0)
                        snprintf(b0, sizeof b0, "-");
                    snprintf(b1, sizeof b1, "%d: %d (%d) %.3f%%", df, fam_frames[f][1],
                             fam_total[f][1], 100.0 * fam_frames[f][1] / c.tag_free);
                    snprintf(b2, sizeof b2, "%d: %d (%d) %.3f%%", mx, fam_frames[f][2],
                             fam_total[f][2], 100.0 * fam_frames[f][2] / c.tag_free);
                    if (fam_frames[f][2] < 0)
                        snprintf(b2, sizeof b2, "-");
                    printf("  %-12s %6d  %-22s %-22s %-22s\n", c.free_fam[f].name,
                           c.free_fam[f].ncodes, b0, b1, b2);
                }
            }
            if (have_seq) {
                char title[200];
                snprintf(title, sizeof title, "tracking, %d simulated passes of %d frames",
                         topt.sequences, topt.length);
                te_print(stdout, title, &seq_counts, &topt, 0);
            }
            if (have_pool)
                te_print(stdout, "tracking, frames in order", &pool_counts, &topt, 0);
            printf("time: %.1f s with %d threads\n", elapsed, threads);
        }
        if (svg) {
            double *rcm = (double *)malloc((size_t)(nerr + 1) * sizeof(double));
            int n2;
            for (n2 = 0; n2 < nerr; n2++)
                rcm[n2] = re[n2] * 100.0;
            svg_histogram(svg, "range_error.svg", "Range error per corner", "range error (cm)",
                          rcm, nerr, -4.0, 4.0, 40);
            svg_histogram(svg, "azimuth_error.svg", "Azimuth error per corner",
                          "azimuth error (rad)", ae, nerr, -0.02, 0.02, 40);
            svg_rate(svg, "rate_vs_distance.svg", "Detection rate versus distance",
                     "sonar to tag distance (m)", bd_c, bd_r, bd_cnt, nbd);
            svg_rate(svg, "rate_vs_incidence.svg", "Detection rate versus incidence",
                     "incidence angle (deg)", bi_c, bi_r, bi_cnt, nbi);
            free(rcm);
        }
        free(re);
        free(ae);
    }
    free(c.tres);
    free(c.fres);
    /* a summary lost to a full disk or a closed pipe is an error, not exit 0 */
    errno = 0;
    if (fflush(stdout) != 0 || ferror(stdout)) {
        char m[300];
        snprintf(m, sizeof m, "standard output: cannot write: %s",
                 errno ? strerror(errno) : "write error");
        die(m);
    }
    /* the run has succeeded: its files are kept */
    close_output(&g_pose_out, "--pose-dump");
    close_output(&g_fail_out, "--failures");
    close_output(&g_seq_out, "--sequence-failures");
    return 0;
}
