/*
 * worst_bench: the worst frame time of actag_detect over an adversarial set
 * against the median pool frame (issue 10, bounded time).
 *
 *   worst_bench [--repeat N] [--callgrind] [--list] [--only NAME] [POOL.pgm...]
 *   (--help: usage)
 *
 * Frames: the pool recording's frames (default: the 58 of
 * ../shared/data/sonar/pool-video; 530 x 512, 0.1-1.5 m, 60 degrees) and,
 * at the same size and geometry, adversarial frames: dense speckle (10-50 %),
 * checkerboards of cell sizes 1..64, thousands of small blobs, grids of
 * tag-sized squares (plain, with a dark ring and random cells inside: fake
 * tags the decoder must read and reject), uniform noise, all white/black.
 * Default parameters, AcTag24h10, 16 MiB of static workspace.
 *
 * Time: CPU time of the process (CLOCK_PROCESS_CPUTIME_ID), the best of
 * --repeat runs per frame (default 3). With --callgrind, run under
 *     valgrind --tool=callgrind --collect-atstart=no --callgrind-out-file=OUT.%p \
 *              build/bench/worst_bench --callgrind
 * each frame's actag_detect call is collected alone and dumped as its own
 * part ("frame NAME"); bench/worst_callgrind.sh runs this and prints
 * instructions per frame, the median pool frame, the worst adversarial
 * frame and their ratio. Printed per frame: name, ms, detections, and the
 * cap counters of actag_stats.
 */
#define _POSIX_C_SOURCE 200809L
#include "actag/actag.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#ifdef ACTAG_HAVE_CALLGRIND_H
#include <valgrind/callgrind.h>
#else
#define CALLGRIND_TOGGLE_COLLECT
#define CALLGRIND_DUMP_STATS_AT(s) ((void)(s))
#endif

#include "../tests/adversarial.h"
#include "hostio.h"

#ifndef ACTAG_SHARED_DIR
#define ACTAG_SHARED_DIR "../shared"
#endif

#define PROG "worst_bench"
#define ROWS ADV_ROWS
#define COLS ADV_COLS
#define MAX_POOL 200 /* pool frames given; v[] holds them and adv_specs' 31 */

static uint8_t g_ws[ACTAG_WORKSPACE_SIZE(ROWS, COLS)];

static double cpu_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}


static void usage(void)
{
    printf("usage: " PROG " [--repeat N] [--callgrind] [--list] [--only NAME] [POOL.pgm...]\n"
           "The worst actag_detect time over an adversarial frame set against the median pool\n"
           "frame (default pool frames: the 58 of the full data set; 8-bit 530 x 512).\n"
           "  --repeat N    runs per frame, the best one counts (default 3)\n"
           "  --callgrind   one run per frame, each collected and dumped on its own (run\n"
           "                under valgrind --tool=callgrind --collect-atstart=no)\n"
           "  --list        print the frames' names and stop\n"
           "  --only NAME   only the frames whose name contains NAME\n"
           "  --help, -h    this text\n");
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

int main(int argc, char **argv)
{
    static adv_spec v[256];
    static uint8_t img[ROWS * COLS];
    static double pool_ms[256];
    const char *only = NULL;
    int n = 0, npool = 0, i, repeat = 3, callgrind = 0, list = 0;
    actag_family fam;
    actag_params p;
    actag_sonar_geometry g = {0.1f, 1.5f, 1.0471976f, NULL, 0u};
    double worst = 0.0;
    const char *worst_name = "";

    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            usage();
            return 0;
        } else if (strcmp(argv[i], "--repeat") == 0)
            repeat = (int)hostio_opt_long(PROG, "--repeat", hostio_opt_value(PROG, argc, argv, &i),
                                          1, 1000000);
        else if (strcmp(argv[i], "--callgrind") == 0)
            callgrind = 1;
        else if (strcmp(argv[i], "--list") == 0)
            list = 1;
        else if (strcmp(argv[i], "--only") == 0)
            only = hostio_opt_value(PROG, argc, argv, &i);
        else if (argv[i][0] == '-' && argv[i][1] != '\0') /* "-" is a frame: standard input */
            hostio_opt_unknown(PROG, argv[i]);
        else {
            /* refused, not left out: frames past the 200th were ignored and a
             * path past 511 characters cut short without a word */
            char m[300];
            if (n >= MAX_POOL) {
                snprintf(m, sizeof m, "at most %d frames ('%.150s' is one more)", MAX_POOL,
                         argv[i]);
                hostio_die(PROG, m);
            }
            if (adv_pool_spec(&v[n], argv[i]) != 0) {
                snprintf(m, sizeof m, "'%.60s...': a path of %lu characters (at most %d)",
                         argv[i], (unsigned long)strlen(argv[i]), (int)sizeof v[n].path - 1);
                hostio_die(PROG, m);
            }
            n++;
        }
    }
    if (n == 0)
        for (i = 1; i <= 571; i += 10) {
            v[n].kind = K_POOL;
            snprintf(v[n].path, sizeof v[n].path, ACTAG_SHARED_DIR "/data/sonar/pool-video/f_%04d.pgm", i);
            snprintf(v[n].name, sizeof v[n].name, "pool f_%04d", i);
            n++;
        }
    npool = n;
    n = adv_specs(v, n);
    if (list) {
        for (i = 0; i < n; i++)
            printf("%s\n", v[i].name);
        hostio_stdout_check(PROG);
        return 0;
    }
    actag_family_get("AcTag24h10", &fam);
    actag_params_default(&p);
    p.family = &fam;
    printf("%-28s %9s %4s %8s %7s %6s %6s %7s %7s %6s %s\n", "frame", "cpu ms", "tags",
           "contours", "size_ok", "quads", "search", "decoded", "decodes", "iters",
           "limits reached (contour_cap ransac_exhausted contour_budget frame_budget decode_cap "
           "search_cap guess_cap overflowed)");
    for (i = 0; i < n; i++) {
        actag_frame fr;
        actag_detection det[16];
        actag_stats st;
        double best = 1e30;
        int k, got = 0, rows = ROWS, cols = COLS;
        if (only && !strstr(v[i].name, only))
            continue;
        if (v[i].kind == K_POOL) {
            char err[HOSTIO_ERRLEN];
            hostio_image im;
            if (hostio_pgm_read(v[i].path, &im, err) != HOSTIO_OK) {
                fprintf(stderr, "worst_bench: %s\n", err);
                return 2;
            }
            if (im.depth != 8 || im.rows != ROWS || im.cols != COLS) {
                fprintf(stderr, "worst_bench: %s: %d x %d, %d-bit (expected an 8-bit 530 x 512 PGM)\n",
                        v[i].path, im.rows, im.cols, im.depth);
                hostio_image_free(&im);
                return 2;
            }
            rows = im.rows;
            cols = im.cols;
            memcpy(img, im.data, sizeof img);
            hostio_image_free(&im);
        } else {
            adv_generate(&v[i], img);
        }
        fr.data = img;
        fr.rows = rows;
        fr.cols = cols;
        fr.stride = cols;
        fr.depth = 8;
        for (k = 0; k < (callgrind ? 1 : repeat); k++) {
            double t0, t1;
            if (callgrind)
                CALLGRIND_TOGGLE_COLLECT;
            t0 = cpu_ms();
            got = actag_detect(&fr, &g, &p, g_ws, sizeof g_ws, det, 16, &st);
            t1 = cpu_ms();
            if (callgrind) {
                CALLGRIND_TOGGLE_COLLECT;
                CALLGRIND_DUMP_STATS_AT(v[i].name);
            }
            if (t1 - t0 < best)
                best = t1 - t0;
        }
        if (got < 0) {
            fprintf(stderr, "worst_bench: %s: %s\n", v[i].name, actag_strerror(got));
            return 2;
        }
        printf("%-28s %9.3f %4d %8d %7d %6d %6d %7d %7d %6d %d %d %d %d %d %d %d %d\n",
               v[i].name, best, got, st.contours, st.size_ok, st.quads, st.searched, st.decoded,
               st.decodes, st.iterations, st.contour_cap, st.ransac_exhausted, st.contour_budget,
               st.frame_budget, st.decode_cap, st.search_cap, st.guess_cap, st.overflowed);
        if (i < npool)
            pool_ms[i] = best;
        else if (best > worst) {
            worst = best;
            worst_name = v[i].name;
        }
    }
    if (!only && npool > 0) {
        double med;
        qsort(pool_ms, (size_t)npool, sizeof pool_ms[0], cmp_double);
        med = npool % 2 ? pool_ms[npool / 2] : 0.5 * (pool_ms[npool / 2 - 1] + pool_ms[npool / 2]);
        printf("median pool frame: %.3f ms CPU (%d frames); worst adversarial: %.3f ms (%s); "
               "ratio %.2f\n",
               med, npool, worst, worst_name, med > 0 ? worst / med : 0.0);
    }
    hostio_stdout_check(PROG); /* a table lost to a full disk is not exit 0 */
    return 0;
}
