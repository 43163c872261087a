/*
 * track_bench: instructions per frame of whole-frame detection and of the
 * tracker (track.h) over a sequence of frames, for callgrind.
 *
 *   track_bench [--min-range M --max-range M --aperture-deg D] [--family NAME]
 *               [--tag-size M] [--full-every N] [--roi-scale F] [--refind-after K]
 *               [--roi-search N] [--roi-ransac N]
 *               FRAME.pgm...   (--help: usage)
 *
 * Every frame goes through bench_full() (actag_detect on the whole frame)
 * and through the tracker, as bench_track_tracked() when the tracker starts
 * the frame with a confirmed track and bench_track() otherwise. Run under
 *   valgrind --tool=callgrind --callgrind-out-file=cg.out track_bench ...
 *   callgrind_annotate --inclusive=yes cg.out | grep bench_
 * and divide each function's inclusive instructions by the call counts
 * printed here. Defaults: the pool recording's sonar (0.1-1.5 m, 60
 * degrees), AcTag24h10, 0.130628571 m, track.h's defaults; --roi-search N
 * gives the ROI searches N structure-search candidates and --roi-ransac N
 * RANSAC iterations (roi_params).
 * Host-only.
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "actag/track.h"
#include "hostio.h"

#define PROG "track_bench"

static void usage(void)
{
    printf("usage: " PROG " [--min-range M --max-range M --aperture-deg D] [--family NAME]\n"
           "                   [--tag-size M] [--full-every N] [--roi-scale F]\n"
           "                   [--refind-after K] [--roi-search N] [--roi-ransac N] FRAME.pgm...\n"
           "Runs every frame through whole-frame detection (bench_full) and the tracker\n"
           "(bench_track, bench_track_tracked) for callgrind's per-function instruction\n"
           "counts; prints the calls and pixels of each. Defaults: the pool sonar\n"
           "(0.1-1.5 m, 60 degrees), AcTag24h10, 0.130628571 m, track.h's settings.\n"
           "  --roi-search N   structure-search candidates of the ROI searches\n"
           "  --roi-ransac N   RANSAC iterations of the ROI searches\n"
           "  --help, -h       this text\n");
}

static const actag_params *roi_params; /* NULL: the whole-frame parameters */

#ifdef __GNUC__
#define NOINLINE __attribute__((noinline))
#else
#define NOINLINE
#endif

NOINLINE int bench_full(const actag_frame *f, const actag_sonar_geometry *g,
                        const actag_params *p, void *ws, size_t wss, actag_detection *d, int n);
NOINLINE int bench_track(actag_tracker *t, const actag_frame *f, const actag_sonar_geometry *g,
                         const actag_params *p, void *ws, size_t wss, actag_track *o, int n,
                         actag_track_stats *st);
NOINLINE int bench_track_tracked(actag_tracker *t, const actag_frame *f,
                                 const actag_sonar_geometry *g, const actag_params *p, void *ws,
                                 size_t wss, actag_track *o, int n, actag_track_stats *st);

NOINLINE int bench_full(const actag_frame *f, const actag_sonar_geometry *g,
                        const actag_params *p, void *ws, size_t wss, actag_detection *d, int n)
{
    return actag_detect(f, g, p, ws, wss, d, n, NULL);
}

NOINLINE int bench_track(actag_tracker *t, const actag_frame *f, const actag_sonar_geometry *g,
                         const actag_params *p, void *ws, size_t wss, actag_track *o, int n,
                         actag_track_stats *st)
{
    return actag_tracker_update(t, f, g, p, roi_params, ws, wss, o, n, st);
}

NOINLINE int bench_track_tracked(actag_tracker *t, const actag_frame *f,
                                 const actag_sonar_geometry *g, const actag_params *p, void *ws,
                                 size_t wss, actag_track *o, int n, actag_track_stats *st)
{
    return actag_tracker_update(t, f, g, p, roi_params, ws, wss, o, n, st);
}

/* A library error on frame `file`: the file named beside the message. */
static void die_frame(const char *file, int code)
{
    char m[400];
    snprintf(m, sizeof m, "%.300s: %s", file, actag_strerror(code));
    hostio_die(PROG, m);
}

int main(int argc, char **argv)
{
    static actag_tracker tr;
    actag_track_params tp;
    actag_params p;
    actag_family fam;
    actag_sonar_geometry g = {0.1f, 1.5f, 1.0471976f, NULL, 0u};
    const char *family = "AcTag24h10", *first = "";
    double tag_size = 0.130628571;
    void *ws = NULL;
    size_t wss = 0;
    int i, nfiles = 0, rows = 0, cols = 0, n_full = 0, n_track = 0, n_tracked = 0;
    int full_read = 0, track_read = 0, roi_search = -1, roi_ransac = -1;
    actag_params rp;
    long px_full = 0, px_track = 0, px_tracked = 0;
    char err[HOSTIO_ERRLEN];
    actag_track_params_default(&tp);
    for (i = 1; i < argc; i += 2) { /* --option value pairs, then the frames */
        const char *o = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (o[0] != '-' || o[1] == '\0') /* a frame ("-": standard input) */
            break;
        if (!strcmp(o, "--help") || !strcmp(o, "-h")) {
            usage();
            return 0;
        }
        if (!strcmp(o, "--min-range"))
            g.min_range = (float)hostio_opt_double(PROG, o, v, 0.0, 1e4);
        else if (!strcmp(o, "--max-range"))
            g.max_range = (float)hostio_opt_double(PROG, o, v, 0.0, 1e4);
        else if (!strcmp(o, "--aperture-deg"))
            g.aperture = (float)(hostio_opt_double(PROG, o, v, 0.1, 359.0) * 3.14159265358979 / 180.0);
        else if (!strcmp(o, "--family"))
            family = v;
        else if (!strcmp(o, "--tag-size"))
            tag_size = hostio_opt_double(PROG, o, v, 1e-3, 100.0);
        else if (!strcmp(o, "--full-every"))
            tp.full_every = (int)hostio_opt_long(PROG, o, v, 1, 100000);
        else if (!strcmp(o, "--roi-scale"))
            tp.roi_scale = (float)hostio_opt_double(PROG, o, v, 0.01, 10.0);
        else if (!strcmp(o, "--roi-search"))
            roi_search = (int)hostio_opt_long(PROG, o, v, 0, ACTAG_SEARCH_MAX);
        else if (!strcmp(o, "--roi-ransac"))
            roi_ransac = (int)hostio_opt_long(PROG, o, v, 1, 100000);
        else if (!strcmp(o, "--refind-after"))
            tp.refind_after = (int)hostio_opt_long(PROG, o, v, 0, 1000);
        else
            hostio_opt_unknown(PROG, o);
        if (!v) { /* the last argument (the number parsers have said so already) */
            char m[300];
            snprintf(m, sizeof m, "%.200s: missing value", o);
            hostio_die(PROG, m);
        }
    }
    if (i >= argc)
        hostio_die(PROG, "no frames (try --help)");
    if (actag_family_get(family, &fam) != ACTAG_OK) {
        char m[300];
        snprintf(m, sizeof m, "--family: unknown family '%.100s' (e.g. AcTag24h10)", family);
        hostio_die(PROG, m);
    }
    actag_params_default(&p);
    p.family = &fam;
    p.tag_size = (float)tag_size;
    rp = p;
    if (roi_search >= 0) {
        rp.tuning.search_candidates = roi_search;
        roi_params = &rp;
    }
    if (roi_ransac > 0) {
        rp.tuning.quad.max_iterations = roi_ransac;
        roi_params = &rp;
    }
    if (actag_tracker_init(&tr, &tp) != ACTAG_OK)
        hostio_die(PROG, "invalid tracker settings");
    for (; i < argc; i++) {
        hostio_image im;
        actag_frame f;
        actag_detection det[16];
        actag_track out[ACTAG_TRACK_MAX];
        actag_track_stats st;
        int n, k, tracked = 0;
        if (hostio_pgm_read(argv[i], &im, err) != HOSTIO_OK)
            hostio_die(PROG, err);
        if (nfiles == 0) {
            /* the geometry against the first frame, in this tool's option
             * names (detection said "invalid sonar geometry") */
            static const hostio_optname names[] = {
                {"min_range", "--min-range", 0},
                {"max_range", "--max-range", 0},
                {"aperture", "--aperture-deg", 57.29577951308232}};
            actag_error_detail d;
            if (actag_geometry_validate(&g, im.rows, im.cols, &d) != ACTAG_OK) {
                char m[HOSTIO_ERRLEN], m2[HOSTIO_ERRLEN + 200];
                hostio_detail_message(&d, names, (int)(sizeof names / sizeof names[0]), m);
                snprintf(m2, sizeof m2, "%s (frame %.150s)", m, argv[i]);
                hostio_die(PROG, m2);
            }
            first = argv[i];
            rows = im.rows;
            cols = im.cols;
            wss = actag_workspace_size(rows, cols);
            ws = malloc(wss);
            if (!ws)
                hostio_die(PROG, "out of memory");
        } else if (im.rows != rows || im.cols != cols) {
            char m[600];
            snprintf(m, sizeof m, "%.200s: a %d x %d frame (rows x columns), the first one "
                     "(%.200s) is %d x %d: frames of one size only", argv[i], im.rows, im.cols,
                     first, rows, cols);
            hostio_die(PROG, m);
        }
        nfiles++;
        hostio_image_frame(&im, &f);
        n = bench_full(&f, &g, &p, ws, wss, det, 16);
        if (n < 0)
            die_frame(argv[i], n);
        n_full++;
        px_full += (long)rows * cols;
        full_read += n > 0;
        for (k = 0; k < tr.ntracks; k++)
            tracked |= tr.tracks[k].confirmed;
        n = tracked ? bench_track_tracked(&tr, &f, &g, &p, ws, wss, out, ACTAG_TRACK_MAX, &st)
                    : bench_track(&tr, &f, &g, &p, ws, wss, out, ACTAG_TRACK_MAX, &st);
        if (n < 0)
            die_frame(argv[i], n);
        if (tracked) {
            n_tracked++;
            px_tracked += st.pixels;
        } else {
            n_track++;
        }
        px_track += st.pixels;
        for (k = 0; k < n; k++)
            if (out[k].measured) {
                track_read++;
                break;
            }
        hostio_image_free(&im);
    }
    printf("frames %d: bench_full calls %d (frames with a reading %d), bench_track calls %d, "
           "bench_track_tracked calls %d (frames with a measured track %d)\n",
           nfiles, n_full, full_read, n_track, n_tracked, track_read);
    printf("pixels per frame: whole %.0f, tracker %.0f, tracker while tracked %.0f\n",
           (double)px_full / nfiles, (double)px_track / nfiles,
           n_tracked ? (double)px_tracked / n_tracked : 0.0);
    free(ws);
    hostio_stdout_check(PROG); /* counts lost to a full disk are not exit 0 */
    return 0;
}
