/*
 * stage_bench: thread CPU time per frame of the median filter and the
 * adaptive threshold, each in two builds of the same source: the library's
 * (SSE2 on x86-64 unless the library was built with ACTAG_NO_SIMD) and the
 * portable C path (src/median.c and src/threshold.c compiled into this
 * program with ACTAG_NO_SIMD, as the tests do).
 *
 *   stage_bench [--repeat N] [--median-radius R] [--threshold-radius R]
 *               [--offset K] [--only median|threshold] [--path library|portable]
 *               FRAME.pgm...   (--help: usage)
 *
 * Each stage runs N times over every frame (the threshold on the median's
 * output, as in actag_detect); for each repeat the mean thread CPU time per
 * frame (clock_gettime(CLOCK_THREAD_CPUTIME_ID)) is taken, and the best and
 * worst repeat are printed. The FNV-1a digest of every output over all
 * frames is printed too, so that two builds can be checked bit-identical,
 * and the program fails when the two paths disagree. With --repeat 1 and
 * --path portable it suits `valgrind --tool=callgrind
 * --toggle-collect=actag_median_filter_portable` (instruction counts).
 * Pin it (taskset -c 1) on a quiet machine. Host-only (stdio, malloc).
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "actag/median.h"
#include "actag/threshold.h"
#include "actag/version.h"
#include "hostio.h"

#define PROG "stage_bench"

/* The portable paths, compiled in under other names. */
int actag_median_filter_portable(const uint8_t *src, int rows, int cols, int src_stride,
                                 uint8_t *dst, int dst_stride, int radius, void *scratch,
                                 size_t scratch_size);
int actag_adaptive_threshold_portable(const uint8_t *src, int rows, int cols, int src_stride,
                                      uint8_t *dst, int dst_stride, int radius, int offset,
                                      void *scratch, size_t scratch_size);
int actag_median_filter16_portable(const void *src, int rows, int cols, int src_stride,
                                   uint8_t *dst, int dst_stride, int radius, void *scratch,
                                   size_t scratch_size);
int actag_adaptive_threshold_bitmap_portable(const uint8_t *src, int rows, int cols,
                                             int src_stride, uint32_t *bitmap, int radius,
                                             int offset, void *scratch, size_t scratch_size);
#define ACTAG_NO_SIMD 1
#define actag_median_filter actag_median_filter_portable
#define actag_median_filter16 actag_median_filter16_portable
#define actag__median_filter16_max actag__median_filter16_max_portable
#define actag_median_filter_inplace actag_median_filter_inplace_portable
int actag_median_filter_inplace_portable(void *frame, int depth, int rows, int cols, int stride,
                                         uint32_t max16, int radius, void *scratch,
                                         size_t scratch_size);
#define actag__median_filter_bands actag__median_filter_bands_portable
#define actag__median_filter_inplace_bands actag__median_filter_inplace_bands_portable
#include "../src/median.c"
#undef actag__median_filter_bands
#undef actag__median_filter_inplace_bands
#undef actag_median_filter
#undef actag_median_filter16
#undef actag__median_filter16_max
#undef actag_median_filter_inplace
#define actag_adaptive_threshold actag_adaptive_threshold_portable
#define actag_adaptive_threshold_bitmap actag_adaptive_threshold_bitmap_portable
#include "../src/threshold.c"
#undef actag_adaptive_threshold
#undef actag_adaptive_threshold_bitmap

typedef struct {
    uint8_t *img, *med, *bin;
    int rows, cols;
    const char *path; /* for messages */
} frame;

static double thread_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static uint64_t fnv(uint64_t h, const uint8_t *p, size_t n)
{
    size_t k;
    for (k = 0; k < n; k++) {
        h ^= p[k];
        h *= 0x100000001b3ull;
    }
    return h;
}

static void usage(void)
{
    printf("usage: stage_bench [--repeat N] [--median-radius R] [--threshold-radius R]\n"
           "                   [--offset K] [--only median|threshold] [--path library|portable]\n"
           "                   FRAME.pgm...\n"
           "Thread CPU time per frame of the median filter and the adaptive threshold, the\n"
           "library's path and the portable C path, best and worst of N repeats, with the\n"
           "outputs' digests (the program fails when the two paths disagree).\n"
           "  --repeat N              repeats (default 5)\n"
           "  --median-radius R       (default 4)   --threshold-radius R (default 8)\n"
           "  --offset K              threshold offset (default 1)\n"
           "  --only median|threshold one stage     --path library|portable  one path\n"
           "  --help, -h              this text     --version\n");
}

static int parse_int(const char *name, const char *s, long lo, long hi, int *v)
{
    long x;
    char err[HOSTIO_ERRLEN];
    if (hostio_parse_long(name, s, lo, hi, &x, err) != HOSTIO_OK) {
        fprintf(stderr, "stage_bench: %s\n", err);
        return -1;
    }
    *v = (int)x;
    return 0;
}

int main(int argc, char **argv)
{
    frame *fr;
    int nfr = 0, i, r, p, repeat = 5, mr = 4, tr = 8, off = 1, only = 0, path = -1;
    size_t scr_size = 0, maxpix = 0;
    uint8_t *scratch = NULL, *other = NULL;
    const char *pname[2] = {"library", "portable"};
    int failed = 0;

    fr = (frame *)calloc((size_t)argc, sizeof *fr);
    if (!fr)
        return 2;
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--version") == 0) {
            printf("stage_bench %s\n", ACTAG_VERSION_STRING);
            free(fr);
            return 0;
        } else if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage();
            free(fr);
            return 0;
        } else if (strcmp(a, "--repeat") == 0) {
            if (parse_int(a, hostio_opt_value(PROG, argc, argv, &i), 1, 100000, &repeat))
                goto fail;
        } else if (strcmp(a, "--median-radius") == 0) {
            if (parse_int(a, hostio_opt_value(PROG, argc, argv, &i), 0,
                          ACTAG_MEDIAN_MAX_RADIUS, &mr))
                goto fail;
        } else if (strcmp(a, "--threshold-radius") == 0) {
            if (parse_int(a, hostio_opt_value(PROG, argc, argv, &i), 0, 100000, &tr))
                goto fail;
        } else if (strcmp(a, "--offset") == 0) {
            if (parse_int(a, hostio_opt_value(PROG, argc, argv, &i), -255, 255, &off))
                goto fail;
        } else if (strcmp(a, "--only") == 0) {
            const char *v = hostio_opt_value(PROG, argc, argv, &i);
            only = strcmp(v, "median") == 0 ? 1 : strcmp(v, "threshold") == 0 ? 2 : -1;
            if (only < 0) {
                fprintf(stderr, "stage_bench: --only median|threshold\n");
                goto fail;
            }
        } else if (strcmp(a, "--path") == 0) {
            const char *v = hostio_opt_value(PROG, argc, argv, &i);
            path = strcmp(v, "library") == 0 ? 0 : strcmp(v, "portable") == 0 ? 1 : -2;
            if (path < -1) {
                fprintf(stderr, "stage_bench: --path library|portable\n");
                goto fail;
            }
        } else if (a[0] == '-') {
            hostio_opt_unknown(PROG, a);
        } else {
            hostio_image im;
            char err[HOSTIO_ERRLEN];
            size_t n;
            int y;
            if (hostio_pgm_read(a, &im, err) != HOSTIO_OK) {
                fprintf(stderr, "stage_bench: %s\n", err);
                goto fail;
            }
            if (im.depth != 8) {
                fprintf(stderr, "stage_bench: %s: 8-bit PGM expected\n", a);
                hostio_image_free(&im);
                goto fail;
            }
            n = (size_t)im.rows * (size_t)im.cols;
            fr[nfr].path = a;
            fr[nfr].rows = im.rows;
            fr[nfr].cols = im.cols;
            fr[nfr].img = (uint8_t *)malloc(n);
            fr[nfr].med = (uint8_t *)malloc(n);
            fr[nfr].bin = (uint8_t *)malloc(n);
            if (!fr[nfr].img || !fr[nfr].med || !fr[nfr].bin) {
                hostio_image_free(&im);
                goto fail;
            }
            for (y = 0; y < im.rows; y++)
                memcpy(fr[nfr].img + (size_t)y * (size_t)im.cols,
                       (const uint8_t *)im.data + (size_t)y * (size_t)im.stride, (size_t)im.cols);
            hostio_image_free(&im);
            if (n > maxpix)
                maxpix = n;
            nfr++;
        }
    }
    if (nfr == 0) {
        fprintf(stderr, "stage_bench: no frames given\n");
        goto fail;
    }
    /* sized once every option is read: sized per file, a --threshold-radius
     * after the files was not counted ("stage 2 failed (-5)") */
    for (i = 0; i < nfr; i++) {
        size_t s = ACTAG_MEDIAN_SCRATCH_SIZE(fr[i].rows, fr[i].cols);
        if (ACTAG_THRESHOLD_SCRATCH_SIZE_R(fr[i].rows, fr[i].cols, tr) > s)
            s = ACTAG_THRESHOLD_SCRATCH_SIZE_R(fr[i].rows, fr[i].cols, tr);
        if (s > scr_size)
            scr_size = s;
    }
    scratch = (uint8_t *)malloc(scr_size);
    other = (uint8_t *)malloc(maxpix);
    if (!scratch || !other)
        goto fail;
    printf("stage_bench: %d frames (first %d x %d), best/worst of %d repeats, thread CPU time\n",
           nfr, fr[0].rows, fr[0].cols, repeat);
    printf("scratch bytes for the first frame: median %lu (R=%d), threshold %lu (R=%d)\n",
           (unsigned long)ACTAG_MEDIAN_SCRATCH_SIZE(fr[0].rows, fr[0].cols), mr,
           (unsigned long)ACTAG_THRESHOLD_SCRATCH_SIZE_R(fr[0].rows, fr[0].cols, tr), tr);

    for (p = 0; p < 2; p++) {
        int st;
        if (path >= 0 && p != path)
            continue;
        for (st = 1; st <= 2; st++) {
            double best = 1e30, worst = 0;
            uint64_t h = 0xcbf29ce484222325ull;
            if (only && st != only)
                continue;
            for (r = 0; r < repeat; r++) {
                double total = 0;
                for (i = 0; i < nfr; i++) {
                    frame *f = &fr[i];
                    double t0, t1;
                    int rc;
                    if (st == 2 && r == 0) {
                        /* threshold input: the frame's median (library path) */
                        rc = actag_median_filter(f->img, f->rows, f->cols, f->cols, f->med,
                                                 f->cols, mr, scratch, scr_size);
                        if (rc != ACTAG_OK) {
                            fprintf(stderr, "stage_bench: %s: median: %s\n", f->path,
                                    actag_strerror(rc));
                            goto fail;
                        }
                    }
                    t0 = thread_ms();
                    if (st == 1)
                        rc = (p == 0 ? actag_median_filter : actag_median_filter_portable)(
                            f->img, f->rows, f->cols, f->cols, f->med, f->cols, mr, scratch,
                            scr_size);
                    else
                        rc = (p == 0 ? actag_adaptive_threshold : actag_adaptive_threshold_portable)(
                            f->med, f->rows, f->cols, f->cols, f->bin, f->cols, tr, off, scratch,
                            scr_size);
                    t1 = thread_ms();
                    if (rc != ACTAG_OK) {
                        fprintf(stderr, "stage_bench: %s: %s: %s\n", f->path,
                                st == 1 ? "median" : "threshold", actag_strerror(rc));
                        goto fail;
                    }
                    total += t1 - t0;
                    if (r == 0) {
                        size_t n = (size_t)f->rows * (size_t)f->cols;
                        const uint8_t *out = st == 1 ? f->med : f->bin;
                        int rc2;
                        h = fnv(h, out, n);
                        /* the other path must give the same bytes */
                        if (st == 1)
                            rc2 = (p == 1 ? actag_median_filter : actag_median_filter_portable)(
                                f->img, f->rows, f->cols, f->cols, other, f->cols, mr, scratch,
                                scr_size);
                        else
                            rc2 = (p == 1 ? actag_adaptive_threshold
                                          : actag_adaptive_threshold_portable)(
                                f->med, f->rows, f->cols, f->cols, other, f->cols, tr, off,
                                scratch, scr_size);
                        if (rc2 != ACTAG_OK || memcmp(other, out, n) != 0) {
                            fprintf(stderr, "stage_bench: frame %d: paths differ\n", i);
                            failed = 1;
                        }
                    }
                }
                total /= nfr;
                if (total < best)
                    best = total;
                if (total > worst)
                    worst = total;
            }
            printf("%-9s %-22s %8.3f .. %8.3f ms/frame  digest %016llx\n", pname[p],
                   st == 1 ? "median" : "threshold", best, worst, (unsigned long long)h);
        }
    }
    if (0) {
    fail: /* every error after the frame table exists: status 2, nothing leaked */
        failed = 2;
    }
    for (i = 0; i <= nfr && i < argc; i++) { /* [nfr]: a frame being read */
        free(fr[i].img);
        free(fr[i].med);
        free(fr[i].bin);
    }
    free(fr);
    free(scratch);
    free(other);
    hostio_stdout_check(PROG); /* timings lost to a full disk are not exit 0 */
    return failed;
}
