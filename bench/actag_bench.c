/*
 * actag_bench: per-stage and whole-pipeline time per frame over a set of
 * sonar frames (default: the 58 pool frames of the full data set in
 * ../shared/data/sonar/pool-video, or when it is absent the 6 that ship in
 * data/pool-video; data/README.md), printed as a table (ms per frame, ns per
 * pixel), plus the workspace bytes.
 *
 *   actag_bench [--repeat N] [--family NAME] [FRAME.pgm...]   (--help: usage)
 *
 * Geometry is the pool recording's: 0.1-1.5 m, 60 degrees; default parameters
 * (the paper's Table I median/threshold radii and offset).
 * Single-threaded; times are the thread's CPU time (best of --repeat runs). Host-only (stdio, malloc).
 */
#define _POSIX_C_SOURCE 200809L
#include "actag/actag.h"
#include "actag/version.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "hostio.h"

#define PROG "actag_bench"

#ifndef ACTAG_SHARED_DIR
#define ACTAG_SHARED_DIR "../shared"
#endif
#ifndef ACTAG_SOURCE_DIR
#define ACTAG_SOURCE_DIR "."
#endif

static int file_exists(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (f)
        fclose(f);
    return f != NULL;
}

/* The thread's own CPU time: other processes on a shared machine do not
 * count (they still disturb the caches; compare builds side by side). */
static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}


static void usage(void)
{
    printf("usage: " PROG " [--repeat N] [--family NAME] [FRAME.pgm...]\n"
           "Per-stage and whole-pipeline time per frame (ms, ns per pixel) and the workspace\n"
           "bytes, over the frames given (8-bit PGM) or else the 58 pool frames of the full\n"
           "data set (the 6 of data/pool-video without it); pool geometry, default parameters.\n"
           "  --repeat N     runs per frame, the best one counts (default 5)\n"
           "  --family NAME  (default AcTag24h10)\n"
           "  --help, -h     this text   --version\n");
}

enum { S_MEDIAN, S_THRESH, S_CONTOUR, S_QUAD_DECODE, S_TOTAL, S_N };
static const char *const stage_names[S_N] = {"median filter (R=4)", "adaptive threshold (R=8)",
                                             "contours + size filter", "search + quads + decode (rest)",
                                             "whole pipeline (actag_detect)"};

int main(int argc, char **argv)
{
    const char *files[1024];
    static char pathbuf[64][512];
    int nfiles = 0, repeat = 5, i, r, s;
    const char *family_name = "AcTag24h10";
    actag_family fam;
    actag_params p;
    actag_sonar_geometry g = {0.1f, 1.5f, 1.0471976f, NULL, 0u};
    double best[S_N], sum[S_N];
    long pixels = 0;
    int frames = 0, found = 0;

    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--version") == 0) {
            printf("actag_bench %s\n", ACTAG_VERSION_STRING);
            return 0;
        } else if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            usage();
            return 0;
        } else if (strcmp(argv[i], "--repeat") == 0)
            repeat = (int)hostio_opt_long(PROG, "--repeat", hostio_opt_value(PROG, argc, argv, &i),
                                          1, 1000000);
        else if (strcmp(argv[i], "--family") == 0)
            family_name = hostio_opt_value(PROG, argc, argv, &i);
        else if (argv[i][0] == '-')
            hostio_opt_unknown(PROG, argv[i]);
        else if (nfiles < 1024)
            files[nfiles++] = argv[i];
        else {
            fprintf(stderr, "%s: at most 1024 frames, got more (%s is the 1025th)\n", PROG,
                    argv[i]);
            return 2;
        }
    }
    if (nfiles == 0 && file_exists(ACTAG_SHARED_DIR "/data/sonar/pool-video/f_0001.pgm")) {
        for (i = 0; i < 58; i++) {
            snprintf(pathbuf[i], sizeof pathbuf[0], "%s/data/sonar/pool-video/f_%04d.pgm",
                     ACTAG_SHARED_DIR, 1 + 10 * i);
            files[nfiles++] = pathbuf[i];
        }
    } else if (nfiles == 0) {
        static const int subset[6] = {1, 11, 291, 421, 491, 561};
        printf("(the full data set is not in %s/data: timing the 6 pool frames of data/)\n",
               ACTAG_SHARED_DIR);
        for (i = 0; i < 6; i++) {
            snprintf(pathbuf[i], sizeof pathbuf[0], "%s/data/pool-video/f_%04d.pgm",
                     ACTAG_SOURCE_DIR, subset[i]);
            files[nfiles++] = pathbuf[i];
        }
    }
    if (actag_family_get(family_name, &fam) != ACTAG_OK) {
        fprintf(stderr, "actag_bench: unknown family %s\n", family_name);
        return 2;
    }
    actag_params_default(&p);
    p.family = &fam;
    for (s = 0; s < S_N; s++)
        sum[s] = 0;

    for (i = 0; i < nfiles; i++) {
        int rows, cols;
        uint8_t *img, *filt, *scratch;
        uint32_t *bin, *marks;
        size_t wsize, ssize;
        void *ws;
        actag_frame fr;
        actag_detection det[16];
        hostio_image im;
        char err[HOSTIO_ERRLEN];
        if (hostio_pgm_read(files[i], &im, err) != HOSTIO_OK)
            hostio_die("actag_bench", err);
        if (im.depth != 8) {
            snprintf(err, sizeof err, "%s: expected an 8-bit PGM", files[i]);
            hostio_die("actag_bench", err);
        }
        img = (uint8_t *)im.data;
        rows = im.rows;
        cols = im.cols;
        wsize = actag_workspace_size(rows, cols);
        /* one scratch for the median, the threshold and the contour points */
        ssize = ACTAG_MEDIAN_SCRATCH_SIZE(rows, cols);
        if (ssize < ACTAG_THRESHOLD_BITMAP_SCRATCH_SIZE_R(rows, cols, p.tuning.threshold_radius))
            ssize = ACTAG_THRESHOLD_BITMAP_SCRATCH_SIZE_R(rows, cols, p.tuning.threshold_radius);
        if (ssize < ACTAG_CONTOUR_CAP(rows, cols) * sizeof(actag_ipoint))
            ssize = ACTAG_CONTOUR_CAP(rows, cols) * sizeof(actag_ipoint);
        ws = malloc(wsize);
        filt = (uint8_t *)malloc((size_t)rows * (size_t)cols);
        bin = (uint32_t *)malloc(ACTAG_BITMAP_SIZE(rows, cols));
        marks = (uint32_t *)malloc(ACTAG_BITMAP_SIZE(rows, cols));
        scratch = (uint8_t *)malloc(ssize);
        if (!ws || !filt || !bin || !marks || !scratch)
            return 2;
        fr.data = img;
        fr.rows = rows;
        fr.cols = cols;
        fr.stride = cols;
        fr.depth = 8;
        for (s = 0; s < S_N; s++)
            best[s] = 1e30;
        for (r = 0; r < repeat; r++) {
            double t0, t1, t2, t3;
            actag_contour_scanner sc;
            actag_contour_info ci;
            actag_ipoint *pts = (actag_ipoint *)(void *)scratch;
            int n;
            t0 = now_ms();
            actag_median_filter(img, rows, cols, cols, filt, cols, p.tuning.median_radius, scratch, ssize);
            t1 = now_ms();
            actag_adaptive_threshold_bitmap(filt, rows, cols, cols, bin, p.tuning.threshold_radius,
                                            p.tuning.threshold_offset, scratch, ssize);
            t2 = now_ms();
            actag_contour_scanner_init(&sc, bin, marks, rows, cols);
            while (actag_contour_next(&sc, pts, (int)ACTAG_CONTOUR_CAP(rows, cols), &ci) == 1)
                ;
            t3 = now_ms();
            if (t1 - t0 < best[S_MEDIAN]) best[S_MEDIAN] = t1 - t0;
            if (t2 - t1 < best[S_THRESH]) best[S_THRESH] = t2 - t1;
            if (t3 - t2 < best[S_CONTOUR]) best[S_CONTOUR] = t3 - t2;
            t0 = now_ms();
            n = actag_detect(&fr, &g, &p, ws, wsize, det, 16, NULL);
            t1 = now_ms();
            if (t1 - t0 < best[S_TOTAL]) best[S_TOTAL] = t1 - t0;
            if (r == 0 && n > 0)
                found++;
        }
        best[S_QUAD_DECODE] = best[S_TOTAL] - best[S_MEDIAN] - best[S_THRESH] - best[S_CONTOUR];
        if (best[S_QUAD_DECODE] < 0)
            best[S_QUAD_DECODE] = 0;
        for (s = 0; s < S_N; s++)
            sum[s] += best[s];
        pixels += (long)rows * cols;
        frames++;
        free(img);
        free(ws);
        free(filt);
        free(bin);
        free(marks);
        free(scratch);
    }
    printf("actag_bench: %d frames, best of %d runs each, family %s, default parameters (Table I radii)\n",
           frames, repeat, fam.name);
    printf("%-32s %12s %12s\n", "stage", "ms/frame", "ns/pixel");
    for (s = 0; s < S_N; s++)
        printf("%-32s %12.3f %12.2f\n", stage_names[s], sum[s] / frames,
               sum[s] * 1e6 / (double)pixels);
    printf("frames with a detection: %d of %d\n", found, frames);
    printf("workspace bytes: 530x512 %lu, 1024x1024 %lu (ACTAG_WORKSPACE_SIZE)\n",
           (unsigned long)ACTAG_WORKSPACE_SIZE(530, 512),
           (unsigned long)ACTAG_WORKSPACE_SIZE(1024, 1024));
    hostio_stdout_check(PROG); /* a table lost to a full disk is not exit 0 */
    return 0;
}
