/*
 * actag-sim: simulated imaging-sonar frames of AcTags, with ground truth.
 *
 *   actag-sim [sonar options] (--tag SPEC ... | --random N | --tag-free N)
 *             --out-dir DIR [--seed S] [...]
 *
 * Writes DIR/<prefix>_NNNN.pgm (or .raw) and DIR/truth.jsonl, one JSON line
 * per frame. See usage(). Exit status 0, or 2 with a message naming the bad
 * option or file. A run that fails removes its truth file (a half-written
 * truth would pass for a shorter run); the frames finished before the
 * failure stay, the one being written does not.
 */
#define _POSIX_C_SOURCE 200809L
#include "sim.h"
#include "simio.h"
#include "../hostio/hostio.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define PROG "actag-sim"
#define DEG (3.14159265358979 / 180.0)

static void usage(FILE *f)
{
    fprintf(f,
        "usage: " PROG " [options] --out-dir DIR\n"
        "Renders polar sonar frames (rows = range bins, columns = beams) of AcTags at given or\n"
        "random 6-DOF poses, with ground truth as JSON lines (DIR/truth.jsonl; each tag's\n"
        "corners TL TR BR BL as printed, as {\"x_col\", \"y_row\", \"range_m\", \"azimuth_rad\"}:\n"
        "x = column, y = row in pixels, centre of the top-left pixel at (0, 0)).\n"
        "Scene (one of):\n"
        "  --tag FAMILY:ID:X,Y,Z,ROLL,PITCH,YAW[:SIZE]\n"
        "                         a tag at this pose in the sonar frame (x forward, y left,\n"
        "                         z up; metres; degrees, R = Rz(yaw) Ry(pitch) Rx(roll);\n"
        "                         tag frame x right, y down as printed, z into the tag);\n"
        "                         repeat for several tags (SIZE default 0.130628571 m)\n"
        "  --random N             N frames of one tag (--family, --id) at random views of the\n"
        "                         evaluation protocol (tag face toward the sonar, fully in view)\n"
        "  --tag-free N           N frames of seabed and clutter only\n"
        "  --first F              with --random or --tag-free: write only frames F..N-1, each\n"
        "                         as a run from frame 0 writes it (one frame of a long run)\n"
        "  --sequence N           N frames of a sonar moving past one tag (--family, --id):\n"
        "                         a straight pass at constant height (tracking tests)\n"
        "  --frames N             with --tag: N frames (new noise each), default 1\n"
        "  --seabed none|tag|NX,NY,NZ,D  with --tag: no seabed, the first tag's plane 14 mm\n"
        "                         behind its face (default), or the plane n.p = D\n"
        "Random views:\n"
        "  --family NAME (default AcTag24h10)  --id N (default: random per frame)\n"
        "  --tag-size M (default 0.130628571)\n"
        "  --min-distance M --max-distance M   sonar to tag centre (default 0.5, 5)\n"
        "  --min-incidence-deg D --max-incidence-deg D  line of sight vs face normal (30, 80)\n"
        "  --max-yaw-deg D        the tag's turn about its normal from upright (default 180: any)\n"
        "  --mirror-fraction F    share of views from the other side of the sonar's\n"
        "                         horizontal plane (mirrored images), default 0.5\n"
        "  --clutter N            mean clutter patches per frame (default 4)\n"
        "Sonar (defaults: the paper's settings, 1024 x 512):\n"
        "  --rows R --cols C      range bins, beams\n"
        "  --min-range M --max-range M   (default 0.1, 5)\n"
        "  --aperture-deg D       horizontal aperture (default 60) or (not both)\n"
        "  --bearings FILE        one azimuth per column in radians (whitespace or commas;\n"
        "                         not with --azimuth-ascending: the table gives the order)\n"
        "  --vertical-aperture-deg D  (default 12)\n"
        "  --range-ascending --azimuth-ascending   orientation flags (see geometry.h)\n"
        "  --pool                 the pool recording's sonar: 530 x 512, 0.1-1.5 m, and views\n"
        "                         at 0.9-1.4 m, 55-75 degrees incidence\n"
        "Appearance (defaults tuned to the pool frames):\n"
        "  --gain G --noise N --bands RATE --psf-azimuth RAD --psf-range M (beam sigma)\n"
        "  --foam F --seabed-level S --metal-specular M --metal-diffuse D --spreading P --looks N\n"
        "Output:\n"
        "  --out-dir DIR (created)  --prefix NAME (default sim)  --raw  --depth 8|16\n"
        "  --seed S (default 1)   --quiet\n"
        "Comparison with real frames:\n"
        "  --compare-real DIR     print background and foam/metal statistics of DIR's real\n"
        "                         frames (tag found by actag_detect, pool settings) beside\n"
        "                         simulated pool frames (N = --random, default 60);\n"
        "                         --montage FILE.pgm writes 4 real and 4 simulated frames;\n"
        "                         a DIR none of whose .pgm frames gives a tag is an error\n"
        "  --help  --version\n");
}

/* The truth file while it is written: die() abandons it. */
static hostio_out g_truth;

/* Errors: the host I/O library's, exit status 2, without the truth file. */
static void die(const char *msg)
{
    hostio_out_abandon(&g_truth);
    hostio_die(PROG, msg);
}

/* Option values: the host I/O library's (exit status 2). */
#define num(opt, s, lo, hi) hostio_opt_double(PROG, (opt), (s), (lo), (hi))
#define inum(opt, s, lo, hi) hostio_opt_long(PROG, (opt), (s), (lo), (hi))

static void parse_tag(const char *spec, sim_tag *t)
{
    char buf[512], *fam, *id, *pose, *size, msg[700];
    double p[6];
    long idv;
    char err[HOSTIO_ERRLEN];
    if (strlen(spec) >= sizeof buf)
        die("--tag: specification too long");
    strcpy(buf, spec);
    fam = buf;
    id = strchr(fam, ':');
    if (!id)
        goto bad;
    *id++ = 0;
    pose = strchr(id, ':');
    if (!pose)
        goto bad;
    *pose++ = 0;
    size = strchr(pose, ':');
    if (size)
        *size++ = 0;
    if (actag_family_get(fam, &t->family) != ACTAG_OK) {
        snprintf(msg, sizeof msg, "--tag: unknown family '%s'", fam);
        die(msg);
    }
    if (hostio_parse_long("--tag ID", id, 0, t->family.ncodes - 1, &idv, err) != HOSTIO_OK)
        die(err);
    t->id = (int)idv;
    if (hostio_parse_doubles("--tag pose", pose, ',', p, 6, err) != HOSTIO_OK)
        die(err);
    {
        /* finite is not enough: 1e30 m gives "distance": inf in the truth */
        static const char *const names[6] = {"X", "Y", "Z", "ROLL", "PITCH", "YAW"};
        const char *tok = pose;
        int k;
        for (k = 0; k < 6; k++) {
            double lim = k < 3 ? 1000.0 : 360.0;
            if (k > 0)
                tok = strchr(tok, ',') + 1; /* six numbers: five commas */
            if (fabs(p[k]) > lim) {
                snprintf(msg, sizeof msg, "--tag pose: %s must be from %g to %g %s (got %.*s)",
                         names[k], -lim, lim, k < 3 ? "metres" : "degrees",
                         (int)strcspn(tok, ","), tok);
                die(msg);
            }
        }
    }
    t->tag_size = size ? (float)num("--tag SIZE", size, 1e-3, 100.0) : 0.130628571f;
    sim_pose_from_rpy((float)p[0], (float)p[1], (float)p[2], (float)(p[3] * DEG),
                      (float)(p[4] * DEG), (float)(p[5] * DEG), &t->pose);
    return;
bad:
    snprintf(msg, sizeof msg, "--tag: expected FAMILY:ID:X,Y,Z,ROLL,PITCH,YAW[:SIZE] (got '%s')",
             spec);
    die(msg);
}

/* --seabed NX,NY,NZ,D (the text v, for messages) to a unit normal and its
 * offset, while the options are checked (before --out-dir is made). The
 * normal is divided by its largest component first, as actag_detect's
 * --plane: its squares then neither overflow (1e300 gave a zero normal)
 * nor vanish (1e-200 was "must not be zero"). The offset must be a
 * distance a frame can show: at most 1e6 m. */
static void seabed_normalise(double p[4], const char *v)
{
    double big = fabs(p[0]), u[4], ns;
    char m[HOSTIO_ERRLEN];
    int j;
    for (j = 1; j < 3; j++)
        if (fabs(p[j]) > big)
            big = fabs(p[j]);
    if (!(big > 0.0)) {
        snprintf(m, sizeof m, "--seabed: the normal must not be zero (got %.100s)", v);
        die(m);
    }
    for (j = 0; j < 4; j++)
        u[j] = p[j] / big;
    ns = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]); /* 1 to sqrt 3 */
    if (!(fabs(u[3]) / ns <= 1e6)) {
        snprintf(m, sizeof m, "--seabed: the plane must lie within 1e6 m of the sonar (got "
                 "offset %g m for %.100s)", u[3] / ns, v);
        die(m);
    }
    for (j = 0; j < 4; j++)
        p[j] = u[j] / ns;
}

/* The run writes DIR/truth.jsonl and DIR/PREFIX_NNNN.EXT (frames 0 ..
 * total - 1): none of them may be the --bearings table (it was replaced by
 * the truth file). Checked before anything is created; exits 2 naming both. */
static void check_outputs_keep(const char *bearings, const char *out_dir, const char *prefix,
                               const char *ext, int total)
{
    size_t n = strlen(out_dir) + strlen(prefix) + 40;
    char *p = (char *)malloc(n);
    int i;
    if (!p)
        die("out of memory");
    for (i = -1; i < total; i++) {
        if (i < 0)
            snprintf(p, n, "%s/truth.jsonl", out_dir);
        else
            snprintf(p, n, "%s/%s_%04d.%s", out_dir, prefix, i, ext);
        if (hostio_same_file(p, bearings)) {
            char m[HOSTIO_ERRLEN + 200];
            snprintf(m, sizeof m, "--out-dir: its file '%.150s' is the --bearings table "
                     "'%.150s'; not overwritten", p, bearings);
            free(p);
            die(m);
        }
    }
    free(p);
}

int main(int argc, char **argv)
{
    sim_sonar sonar;
    sim_appearance app;
    sim_view_params view;
    sim_scene scene;
    static sim_tag tags[SIM_MAX_TAGS];
    int ntags = 0, i, nrandom = -1, nfree = -1, nseq = -1, frames = 1, raw = 0, depth = 8;
    int first = 0;
    int quiet = 0, fixed_id = -1, seabed_mode = 1;
    /* options given, so that one the scene would ignore is refused */
    int frames_set = 0, seabed_set = 0, aperture_set = 0;
    const char *random_opt = NULL; /* --family, --id or --tag-size */
    const char *view_opt = NULL;   /* a random view's limit (--min-distance ...) */
    const char *scene_opt = NULL;  /* an option --compare-real does not use */
    static const char *const view_opts[] = {"--min-distance", "--max-distance",
        "--min-incidence-deg", "--max-incidence-deg", "--max-yaw-deg", "--mirror-fraction",
        "--clutter"};
    const char *tag_spec[SIM_MAX_TAGS];
    double seabed_plane[4] = {0, 0, 1, 0};
    uint32_t seed = 1;
    const char *out_dir = NULL, *prefix = "sim", *bearings = NULL, *compare = NULL;
    const char *montage = NULL, *family = "AcTag24h10";
    float tag_size = 0.130628571f, *btab = NULL;
    double aperture_deg = 60.0;
    char err[HOSTIO_ERRLEN], *truth_path = NULL, *path = NULL;
    size_t path_size;
    uint8_t *img8 = NULL;
    uint16_t *img16 = NULL;
    const simio_cli cli = {PROG, usage, 2, ACTAG_MAX_DIM, &sonar, &view, &aperture_deg};

    simio_opt_defaults(argc, argv, &sonar, &view, &app); /* --pool first */
    for (i = 1; i < argc; i++) {
        const char *o = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
#define NEED() simio_opt_need(PROG, o, v, &i)
        if (simio_opt_common(&cli, argc, argv, &i)) {
            size_t k;
            if (!strcmp(o, "--aperture-deg"))
                aperture_set = 1;
            if (strcmp(o, "--pool") != 0) /* the comparison renders the pool's sonar */
                scene_opt = o;
            for (k = 0; k < sizeof view_opts / sizeof view_opts[0]; k++)
                if (!strcmp(o, view_opts[k]))
                    view_opt = o;
        } else if (!strcmp(o, "--tag")) {
            scene_opt = o;
            NEED();
            if (ntags >= SIM_MAX_TAGS)
                die("--tag: at most 16 tags");
            tag_spec[ntags] = v;
            parse_tag(v, &tags[ntags++]);
        } else if (!strcmp(o, "--random")) {
            NEED();
            nrandom = (int)inum(o, v, 1, 10000000);
        } else if (!strcmp(o, "--first")) {
            NEED();
            first = (int)inum(o, v, 0, 10000000);
        } else if (!strcmp(o, "--tag-free")) {
            scene_opt = o;
            NEED();
            nfree = (int)inum(o, v, 1, 10000000);
        } else if (!strcmp(o, "--sequence")) {
            scene_opt = o;
            NEED();
            nseq = (int)inum(o, v, 2, 1000000);
        } else if (!strcmp(o, "--frames")) {
            scene_opt = o;
            NEED();
            frames = (int)inum(o, v, 1, 10000000);
            frames_set = 1;
        } else if (!strcmp(o, "--seabed")) {
            scene_opt = o;
            NEED();
            seabed_set = 1;
            if (!strcmp(v, "none"))
                seabed_mode = 0;
            else if (!strcmp(v, "tag"))
                seabed_mode = 1;
            else {
                if (hostio_parse_doubles(o, v, ',', seabed_plane, 4, err) != HOSTIO_OK)
                    die(err);
                seabed_normalise(seabed_plane, v);
                seabed_mode = 2;
            }
        } else if (!strcmp(o, "--family")) {
            scene_opt = o;
            NEED();
            random_opt = o;
            family = v;
        } else if (!strcmp(o, "--id")) {
            scene_opt = o;
            NEED();
            random_opt = o;
            fixed_id = (int)inum(o, v, 0, 1000000);
        } else if (!strcmp(o, "--tag-size")) {
            scene_opt = o;
            NEED();
            random_opt = o;
            tag_size = (float)num(o, v, 1e-3, 100.0);
        } else if (!strcmp(o, "--bearings")) {
            scene_opt = o;
            NEED();
            bearings = v;
        } else if (!strcmp(o, "--gain")) {
            NEED();
            app.gain = (float)num(o, v, 0.0, 1e6);
        } else if (!strcmp(o, "--noise")) {
            NEED();
            app.noise = (float)num(o, v, 0.0, 1e6);
        } else if (!strcmp(o, "--bands")) {
            NEED();
            app.band_rate = (float)num(o, v, 0.0, 20.0);
        } else if (!strcmp(o, "--psf-azimuth")) {
            NEED();
            app.psf_azimuth = (float)num(o, v, 0.0, 0.5);
        } else if (!strcmp(o, "--psf-range")) {
            NEED();
            app.psf_range = (float)num(o, v, 0.0, 1.0);
        } else if (!strcmp(o, "--foam")) {
            NEED();
            app.foam = (float)num(o, v, 0.0, 1e6);
        } else if (!strcmp(o, "--seabed-level")) {
            NEED();
            app.seabed = (float)num(o, v, 0.0, 1e6);
        } else if (!strcmp(o, "--metal-specular")) {
            NEED();
            app.metal_specular = (float)num(o, v, 0.0, 1e6);
        } else if (!strcmp(o, "--looks")) {
            NEED();
            app.looks = (int)inum(o, v, 1, 8);
        } else if (!strcmp(o, "--metal-diffuse")) {
            NEED();
            app.metal_diffuse = (float)num(o, v, 0.0, 1e6);
        } else if (!strcmp(o, "--spreading")) {
            NEED();
            app.spreading = (float)num(o, v, -4.0, 4.0);
        } else if (!strcmp(o, "--out-dir")) {
            scene_opt = o;
            NEED();
            out_dir = v;
        } else if (!strcmp(o, "--prefix")) {
            scene_opt = o;
            NEED();
            prefix = v;
        } else if (!strcmp(o, "--raw")) {
            scene_opt = o;
            raw = 1;
        } else if (!strcmp(o, "--depth")) {
            scene_opt = o;
            NEED();
            depth = (int)inum(o, v, 8, 16);
            if (depth != 8 && depth != 16) {
                char m[HOSTIO_ERRLEN];
                snprintf(m, sizeof m, "--depth: must be 8 or 16 (got %.40s)", v);
                die(m);
            }
        } else if (!strcmp(o, "--seed")) {
            NEED();
            seed = hostio_opt_u32(PROG, o, v, 0u, 4294967295u);
        } else if (!strcmp(o, "--quiet")) {
            quiet = 1;
        } else if (!strcmp(o, "--compare-real")) {
            NEED();
            compare = v;
        } else if (!strcmp(o, "--montage")) {
            NEED();
            montage = v;
        } else {
            hostio_opt_unknown(PROG, o);
        }
#undef NEED
    }
    if (!(sonar.geo.max_range > sonar.geo.min_range)) {
        char m[200];
        snprintf(m, sizeof m, "--max-range: must be above --min-range %g (got %g)",
                 (double)sonar.geo.min_range, (double)sonar.geo.max_range);
        die(m);
    }
    simio_opt_check_views(PROG, &view);
    if (aperture_set && bearings)
        die("--aperture-deg and --bearings exclude each other: give one");
    /* the table overrides the flag (geometry.h): refused, not ignored */
    if (bearings && (sonar.geo.flags & ACTAG_AZIMUTH_ASCENDING))
        die("--azimuth-ascending does not apply with --bearings (the table gives each column's "
            "bearing in column order)");
    if (montage && !compare)
        die("--montage: needs --compare-real DIR (it shows real and simulated frames)");
    if (bearings) {
        btab = (float *)malloc((size_t)sonar.cols * sizeof *btab);
        if (!btab)
            die("out of memory");
        if (hostio_read_bearings(bearings, sonar.cols, "--cols", btab, err) != HOSTIO_OK)
            die(err); /* "PATH: value K is not a finite number (got '...')" */
        sonar.geo.bearings = btab;
    } else {
        sonar.geo.aperture = (float)(aperture_deg * DEG);
    }
    {
        /* the library's rules, in this tool's option names */
        static const hostio_optname names[] = {
            {"min_range", "--min-range", 0},   {"max_range", "--max-range", 0},
            {"aperture", "--aperture-deg", 57.29577951308232},
            {"bearings", "--bearings", 0},     {"flags", "--range/azimuth-ascending", 0},
            {"rows", "--rows", 0},             {"cols", "--cols", 0}};
        actag_error_detail d;
        if (actag_geometry_validate(&sonar.geo, sonar.rows, sonar.cols, &d) != ACTAG_OK) {
            char m[HOSTIO_ERRLEN];
            hostio_detail_message(&d, names, (int)(sizeof names / sizeof names[0]), m);
            die(m);
        }
    }

    if (compare && scene_opt) {
        char m[200];
        snprintf(m, sizeof m, "%s: does not apply with --compare-real (it renders %s pool frames "
                 "of its own; --random N, --seed, --montage and the appearance options apply)",
                 scene_opt, "AcTag24h10");
        die(m);
    }
    if (compare) {
        int n = nrandom > 0 ? nrandom : 60;
        int rc = simio_compare_real(compare, n, seed, &app, montage, stdout, err);
        if (rc != 0)
            die(err);
        if (fflush(stdout) != 0 || ferror(stdout)) /* the comparison is the result */
            die("standard output: write error");
        return 0;
    }
    if ((ntags > 0) + (nrandom > 0) + (nfree > 0) + (nseq > 0) != 1)
        die("give exactly one of --tag, --random, --tag-free, --sequence (see --help)");
    /* options the chosen scene would ignore */
    if (frames_set && ntags == 0)
        die("--frames: applies only with --tag (--random, --tag-free and --sequence take "
            "their frame count)");
    if (first > 0 && nrandom <= 0 && nfree <= 0)
        die("--first: applies only with --random or --tag-free");
    if (first > 0 && first >= (nrandom > 0 ? nrandom : nfree)) {
        char m[200];
        snprintf(m, sizeof m, "--first: must be below the frame count %d (got %d)",
                 nrandom > 0 ? nrandom : nfree, first);
        die(m);
    }
    if (seabed_set && ntags == 0)
        die("--seabed: applies only with --tag (the other scenes draw their own seabed)");
    if (random_opt && (ntags > 0 || nfree > 0)) {
        char m[200];
        snprintf(m, sizeof m, "%s: applies only with --random or --sequence (not with "
                 "--tag or --tag-free)", random_opt);
        die(m);
    }
    if (view_opt && ntags > 0) {
        char m[200];
        snprintf(m, sizeof m, "%s: a random view's setting; --tag gives the pose itself",
                 view_opt);
        die(m);
    }
    if (!out_dir)
        die("--out-dir: required");
    for (i = 0; i < ntags; i++) {
        /* a tag out of view or turned away is a valid scene, but rarely the
         * one meant: say so (the truth's "visible" is 0, or its incidence
         * above 90 degrees) */
        sim_truth tr;
        sim_truth_of(&sonar, &tags[i], &tr);
        if (!tr.visible)
            fprintf(stderr, PROG ": warning: --tag %s: the tag is not wholly in the sonar's "
                    "field of view (truth \"visible\": 0)\n", tag_spec[i]);
        if (tr.incidence >= (float)(90.0 * DEG))
            fprintf(stderr, PROG ": warning: --tag %s: the tag's face is turned away from the "
                    "sonar (incidence %.1f degrees)\n", tag_spec[i], (double)tr.incidence / DEG);
    }
    if (bearings)
        check_outputs_keep(bearings, out_dir, prefix, raw ? "raw" : "pgm",
                           ntags > 0 ? frames : (nrandom > 0 ? nrandom : (nfree > 0 ? nfree : nseq)));
    hostio_opt_mkdirs(PROG, "--out-dir", out_dir); /* parents too */
    if (depth == 16)
        img16 = (uint16_t *)malloc((size_t)sonar.rows * (size_t)sonar.cols * 2);
    else
        img8 = (uint8_t *)malloc((size_t)sonar.rows * (size_t)sonar.cols);
    if (!img8 && !img16)
        die("out of memory");

    {
        int total = ntags > 0 ? frames : (nrandom > 0 ? nrandom : (nfree > 0 ? nfree : nseq));
        actag_family fam;
        sim_tag base;
        memset(&base, 0, sizeof base);
        if (ntags == 0 && nfree <= 0) {
            simio_opt_family(PROG, "--family", family, &fam);
            if (fixed_id >= fam.ncodes) {
                char m[300];
                snprintf(m, sizeof m, "--id: %s has IDs 0..%d (got %d)", family, fam.ncodes - 1,
                         fixed_id);
                die(m);
            }
            base.family = fam;
            base.tag_size = tag_size;
        }
        /* Sized to fit: fixed buffers cut a long --out-dir short and wrote
         * every frame to one truncated name. */
        path_size = strlen(out_dir) + strlen(prefix) + 40;
        truth_path = (char *)malloc(path_size);
        path = (char *)malloc(path_size);
        if (!truth_path || !path)
            die("out of memory");
        /* opened once the options are all checked: a refused option leaves
         * no truth file */
        snprintf(truth_path, path_size, "%s/truth.jsonl", out_dir);
        if (hostio_out_open(&g_truth, truth_path, "w", err) != HOSTIO_OK)
            die(err); /* "PATH: cannot write: REASON" */
        for (i = first; i < total; i++) { /* a frame depends on its seed alone */
            uint32_t fs = sim_frame_seed(seed, (uint32_t)i);
            int t;
            memset(&scene, 0, sizeof scene);
            if (ntags > 0) {
                for (t = 0; t < ntags; t++)
                    scene.tags[t] = tags[t];
                scene.ntags = ntags;
                if (seabed_mode == 1) {
                    /* the first tag's plane, 14 mm behind its face */
                    const sim_tag *t0 = &tags[0];
                    scene.has_seabed = 1;
                    scene.seabed_n[0] = -t0->pose.R[2];
                    scene.seabed_n[1] = -t0->pose.R[5];
                    scene.seabed_n[2] = -t0->pose.R[8];
                    scene.seabed_d = -(t0->pose.R[2] * t0->pose.t[0] + t0->pose.R[5] * t0->pose.t[1] +
                                       t0->pose.R[8] * t0->pose.t[2]) - 0.014f;
                } else if (seabed_mode == 2) { /* normalised by seabed_normalise */
                    scene.has_seabed = 1;
                    for (t = 0; t < 3; t++)
                        scene.seabed_n[t] = (float)seabed_plane[t];
                    scene.seabed_d = (float)seabed_plane[3];
                }
            } else if (nrandom > 0) {
                sim_tag tg = base;
                tg.id = fixed_id >= 0 ? fixed_id : simio_random_id(fs, fam.ncodes);
                if (sim_sample_view(&sonar, &view, fs, &tg, &scene) != 0)
                    die("--random: no view keeps the whole tag in the field of view; widen "
                        "--min-distance/--max-distance or the apertures");
            } else if (nfree > 0) {
                sim_sample_empty(&sonar, &view, fs, &scene);
            } else {
                sim_tag tg = base;
                tg.id = fixed_id >= 0 ? fixed_id : 0;
                sim_sequence_view(&sonar, &view, seed, i, total, &tg, &scene);
            }
            if (sim_render(&sonar, &scene, &app, fs, img8, img16, sonar.cols, err) != 0)
                die(err);
            snprintf(path, path_size, "%s/%s_%04d.%s", out_dir, prefix, i, raw ? "raw" : "pgm");
            if (raw) {
                if (hostio_write_file(path, img8 ? (const void *)img8 : (const void *)img16,
                                      (size_t)sonar.rows * (size_t)sonar.cols * (size_t)(depth / 8),
                                      err) != HOSTIO_OK)
                    die(err);
            } else {
                hostio_image im;
                im.data = img8 ? (void *)img8 : (void *)img16;
                im.rows = sonar.rows;
                im.cols = sonar.cols;
                im.stride = sonar.cols;
                im.depth = depth;
                im.maxval = depth == 8 ? 255 : 65535;
                if (hostio_pgm_write(path, &im, err) != HOSTIO_OK)
                    die(err);
            }
            simio_truth_line(g_truth.f, path, i, fs, &sonar, &scene);
            if (!quiet && (i + 1) % 100 == 0)
                fprintf(stderr, PROG ": %d/%d frames\n", i + 1, total);
        }
    }
    /* a failed close has removed the file (hostio_out_close) */
    if (hostio_out_close(&g_truth, err) != HOSTIO_OK)
        die(err); /* "PATH: write error" */
    free(img8);
    free(img16);
    free(btab);
    free(path);
    free(truth_path);
    return 0;
}
