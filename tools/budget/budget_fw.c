/*
 * budget_fw.c -- firmware for tools/budget/budget.py: instructions per frame
 * and per stage of actag_detect on a Cortex-M4/M7, under
 * qemu-system-arm -icount shift=0 (one instruction per nanosecond of
 * virtual time), read from the MPS2 board's 25 MHz timer: one tick is 40
 * instructions (the calibration loop below checks it).
 *
 * Stages: the calls detect.c makes are routed through wrappers at link time
 * (-Wl,--wrap=<function>, see CMakeLists.txt), which add the time spent in
 * them to the stage's counter; "other" is the rest of actag_detect (16-bit
 * scaling, size and side filters, merging, geometry). The library itself is
 * the unchanged libactag.a of the build.
 *
 *   median     actag__median_filter_bands, actag__median_filter_inplace_bands
 *              (src/median_bands.h: the median per range band, as detect.c
 *              calls it), actag_median_filter (the tracker's windows),
 *              actag__median_filter16_max, actag_median_filter_inplace (the
 *              16-bit frame's maximum, scanned in detect.c, counts as other)
 *   search     actag_search_map, actag_search_next
 *   threshold  actag_adaptive_threshold_bitmap
 *   contours   actag_contour_scanner_init, actag_contour_next
 *   ransac     actag_quad_fit
 *   decode     actag__decode_quad_fit_grids (src/decode_fit_grids.h: the fit
 *              decoder as detect.c calls it), actag__fit_rival_explains_own (the
 *              rival check of two readings of one place), actag_decode_quad_bitmap
 *   refine     actag__refine_corners_max16 (src/refine_frame.h)
 * (budget.py checks that every stage function detect.c calls is wrapped:
 * a renamed stage would otherwise be counted as "other".)
 *
 * Also the stack actag_detect used (painted before the call, high-water
 * mark after) and the workspace sizes of three frame sizes.
 *
 * usage (semihosting arguments): budget_fw FRAME.pgm...
 * One line per frame:
 *   frame <path> rows <r> cols <c> tags <n> total <instr> median <instr> ... stack <bytes>
 * Host files through semihosting (newlib stdio, board support); the
 * measured calls do no I/O.
 */
#include "actag/actag.h"
#include "actag/families.h"
#include "../../src/decode_fit_grids.h"
#include "../../src/median_bands.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

#define MAX_ROWS 530
#define MAX_COLS 620
#define INSTR_PER_TICK 40u /* 25 MHz timer, 1 GHz of virtual instructions */

enum { ST_MEDIAN, ST_SEARCH, ST_THRESHOLD, ST_CONTOURS, ST_RANSAC, ST_DECODE, ST_REFINE, ST_N };
static const char *const stage_names[ST_N] = {"median", "search",   "threshold", "contours",
                                              "ransac", "decode",   "refine"};
static uint32_t stage_ticks[ST_N];

static uint8_t ws[ACTAG_WORKSPACE_SIZE(MAX_ROWS, MAX_COLS)];
static uint8_t px[MAX_ROWS * MAX_COLS];
/* actag_detect_inplace: its workspace, and the copy of the frame it filters */
static uint8_t ws_ip[ACTAG_WORKSPACE_SIZE_INPLACE(MAX_ROWS, MAX_COLS)];
static uint8_t px_ip[MAX_ROWS * MAX_COLS];

/* ------------------------------------------------------------ timer */

#define TIMER0_CTRL (*(volatile uint32_t *)0x40000000u)
#define TIMER0_VALUE (*(volatile uint32_t *)0x40000004u)
#define TIMER0_RELOAD (*(volatile uint32_t *)0x40000008u)

static uint32_t ticks(void) { return 0xffffffffu - TIMER0_VALUE; }

static void timer_start(void)
{
    TIMER0_CTRL = 0u;
    TIMER0_RELOAD = 0xffffffffu;
    TIMER0_VALUE = 0xffffffffu;
    TIMER0_CTRL = 1u;
}

/* ------------------------------------------------------------ wrappers */

/* WRAPPED(stage, name, (parameters), (arguments)) defines __wrap_name, which
 * the linker puts in place of every call to name (-Wl,--wrap=name); it
 * calls the library's __real_name and adds the ticks to the stage. Each
 * parameter list is written once, so the three declarations cannot drift
 * apart (a list that differs from a public header's fails to compile). */
#define WRAPPED(stage, name, params, args)                                                     \
    int __real_##name params;                                                                  \
    int __wrap_##name params;                                                                  \
    int __wrap_##name params                                                                   \
    {                                                                                          \
        uint32_t t0_ = ticks();                                                                \
        int rc_ = __real_##name args;                                                          \
        stage_ticks[stage] += ticks() - t0_;                                                   \
        return rc_;                                                                            \
    }

WRAPPED(ST_MEDIAN, actag_median_filter,
        (const uint8_t *src, int rows, int cols, int src_stride, uint8_t *dst, int dst_stride,
         int radius, void *scratch, size_t scratch_size),
        (src, rows, cols, src_stride, dst, dst_stride, radius, scratch, scratch_size))

WRAPPED(ST_MEDIAN, actag__median_filter16_max,
        (const void *src, uint32_t max16, int rows, int cols, int src_stride, uint8_t *dst,
         int dst_stride, int radius, void *scratch, size_t scratch_size),
        (src, max16, rows, cols, src_stride, dst, dst_stride, radius, scratch, scratch_size))

WRAPPED(ST_MEDIAN, actag_median_filter_inplace,
        (void *frame, int depth, int rows, int cols, int stride, uint32_t max16, int radius,
         void *scratch, size_t scratch_size),
        (frame, depth, rows, cols, stride, max16, radius, scratch, scratch_size))

WRAPPED(ST_MEDIAN, actag__median_filter_bands,
        (const void *src, int depth, uint32_t max16, int rows, int cols, int src_stride,
         uint8_t *dst, int dst_stride, const actag__median_bands *b, void *scratch,
         size_t scratch_size),
        (src, depth, max16, rows, cols, src_stride, dst, dst_stride, b, scratch, scratch_size))

WRAPPED(ST_MEDIAN, actag__median_filter_inplace_bands,
        (void *frame, int depth, int rows, int cols, int stride, uint32_t max16,
         const actag__median_bands *b, void *scratch, size_t scratch_size),
        (frame, depth, rows, cols, stride, max16, b, scratch, scratch_size))

WRAPPED(ST_SEARCH, actag_search_map,
        (actag_search *z, const uint8_t *img, int rows, int cols, int stride,
         const actag_sonar_geometry *g, float tag_size, int bits, float range_scale, void *map,
         size_t map_size, void *scratch, size_t scratch_size),
        (z, img, rows, cols, stride, g, tag_size, bits, range_scale, map, map_size, scratch,
         scratch_size))

WRAPPED(ST_SEARCH, actag_search_next,
        (actag_search *z, int min_score, const actag_sonar_geometry *g, float tag_size,
         float range_scale, int rows, int cols, actag_point quad[4]),
        (z, min_score, g, tag_size, range_scale, rows, cols, quad))

WRAPPED(ST_THRESHOLD, actag_adaptive_threshold_bitmap,
        (const uint8_t *src, int rows, int cols, int src_stride, uint32_t *bitmap, int radius,
         int offset, void *scratch, size_t scratch_size),
        (src, rows, cols, src_stride, bitmap, radius, offset, scratch, scratch_size))

WRAPPED(ST_CONTOURS, actag_contour_scanner_init,
        (actag_contour_scanner *s, const uint32_t *white, uint32_t *marks, int rows, int cols),
        (s, white, marks, rows, cols))

WRAPPED(ST_CONTOURS, actag_contour_next,
        (actag_contour_scanner *s, actag_ipoint *pts, int cap, actag_contour_info *info),
        (s, pts, cap, info))

WRAPPED(ST_RANSAC, actag_quad_fit,
        (const actag_ipoint *pts, int npoints, const actag_quad_params *params, actag_rng *rng,
         void *scratch, size_t scratch_size, actag_quad *out),
        (pts, npoints, params, rng, scratch, scratch_size, out))

WRAPPED(ST_DECODE, actag__decode_quad_fit_grids,
        (const uint8_t *grey, int rows, int cols, int stride, const actag_point quad[4],
         const actag_family *family, int max_corrections, const actag_fit_params *fp,
         actag_decode_result *out, actag__fit_grids *grids, actag__fit_amb *amb),
        (grey, rows, cols, stride, quad, family, max_corrections, fp, out, grids, amb))

WRAPPED(ST_DECODE, actag__fit_rival_explains_own,
        (const uint8_t *grey, int rows, int cols, int stride, const actag_family *family,
         const actag_fit_params *fp, int id, const actag_point corners[4], int id2,
         const actag_point corners2[4], float *rss, float *rss2, float *own),
        (grey, rows, cols, stride, family, fp, id, corners, id2, corners2, rss, rss2, own))

WRAPPED(ST_DECODE, actag_decode_quad_bitmap,
        (const uint32_t *bitmap, int rows, int cols, const actag_point quad[4],
         const actag_family *family, int max_corrections, actag_decode_result *out),
        (bitmap, rows, cols, quad, family, max_corrections, out))

WRAPPED(ST_REFINE, actag__refine_corners_max16,
        (const void *img, int depth, uint32_t max16, int rows, int cols, int stride,
         const actag_sonar_geometry *geometry, float tag_size, const actag_family *family, int id,
         const actag_point corners[4], const actag_refine_params *rp, actag_point out[4],
         actag_refine_info *info),
        (img, depth, max16, rows, cols, stride, geometry, tag_size, family, id, corners, rp, out,
         info))

/* ------------------------------------------------------------ stack paint */

#define PAINT 0x5a5a5a5au
#define PAINT_WORDS 4096u /* 16 KB below the stack pointer */

static uint32_t *stack_pointer(void)
{
    uint32_t *sp;
    __asm__ volatile("mov %0, sp" : "=r"(sp));
    return sp;
}

/* Fills the 16 KB below the stack pointer of main's callees (this
 * function's frame is a few words at most) with PAINT; returns that top. */
static __attribute__((noinline)) uint32_t *paint_stack(void)
{
    volatile uint32_t *sp = stack_pointer();
    uint32_t i;
    for (i = 1u; i <= PAINT_WORDS; i++)
        sp[-(int32_t)i] = PAINT;
    return (uint32_t *)sp;
}

/* Bytes below top written since paint_stack(): the deepest word that no
 * longer holds PAINT, searched from the bottom of the painted area. */
static __attribute__((noinline)) uint32_t stack_used(const uint32_t *top)
{
    const volatile uint32_t *p = top;
    uint32_t i;
    for (i = PAINT_WORDS; i >= 1u; i--)
        if (p[-(int32_t)i] != PAINT)
            return i * 4u;
    return 0u;
}

/* ------------------------------------------------------------ frames */

static int read_pgm(const char *path, int *rows, int *cols)
{
    FILE *f = fopen(path, "rb");
    int w, h, m, ok;
    if (f == NULL)
        return -1;
    ok = fscanf(f, "P5 %d %d %d", &w, &h, &m) == 3 && m <= 255 && w >= 1 && h >= 1 &&
         w <= MAX_COLS && h <= MAX_ROWS && fgetc(f) != EOF &&
         fread(px, 1, (size_t)w * (size_t)h, f) == (size_t)w * (size_t)h;
    fclose(f);
    *rows = h;
    *cols = w;
    return ok ? 0 : -1;
}

/* Two instructions an iteration (subs, bne): 2 n + a few. */
static __attribute__((noinline)) void spin(uint32_t n)
{
    __asm__ volatile("1: subs %0, %0, #1\n\tbne 1b" : "+r"(n) : : "cc");
}

/* One detection (in place or not) on *f, timed per stage, with the stack
 * painted; prints "<label> NAME rows R cols C tags N total T <stage> T ...
 * other T stack S" and returns the number of tags (-1 when the stack went
 * deeper than the painted area: no measurement). */
static int run_frame(const char *label, const char *name, const actag_frame *f,
                     const actag_sonar_geometry *g, const actag_params *p, int inplace)
{
    actag_detection det[8];
    uint32_t t0, t, sum = 0u, used, *top;
    int n, k;
    memset(stage_ticks, 0, sizeof stage_ticks);
    top = paint_stack();
    t0 = ticks();
    n = inplace ? actag_detect_inplace(f, g, p, ws_ip, sizeof ws_ip, det, 8, NULL)
                : actag_detect(f, g, p, ws, sizeof ws, det, 8, NULL);
    t = ticks() - t0;
    used = stack_used(top);
    printf("%s %s rows %d cols %d tags %d total %lu", label, name, f->rows, f->cols, n,
           (unsigned long)(t * INSTR_PER_TICK));
    for (k = 0; k < ST_N; k++) {
        printf(" %s %lu", stage_names[k], (unsigned long)(stage_ticks[k] * INSTR_PER_TICK));
        sum += stage_ticks[k];
    }
    printf(" other %lu stack %lu\n", (unsigned long)((t - sum) * INSTR_PER_TICK),
           (unsigned long)used);
    return used >= PAINT_WORDS * 4u ? -1 : n;
}

int main(int argc, char **argv)
{
    actag_family fam;
    actag_params p;
    actag_sonar_geometry g = {0.1f, 1.5f, 1.0471976f, NULL, 0u};
    int i, status = 0;

    timer_start();
    {
        uint32_t t0 = ticks(), t;
        spin(5000000u);
        t = ticks() - t0;
        /* expected: 10,000,000 instructions = 250,000 ticks */
        printf("calibration spin 10000000 measured %lu\n", (unsigned long)(t * INSTR_PER_TICK));
    }
    printf("workspace 256x256 %lu 530x512 %lu 1024x1024 %lu\n",
           (unsigned long)actag_workspace_size(256, 256), (unsigned long)actag_workspace_size(530, 512),
           (unsigned long)actag_workspace_size(1024, 1024));
    printf("workspace_inplace 256x256 %lu 530x512 %lu 1024x1024 %lu\n",
           (unsigned long)actag_workspace_size_inplace(256, 256),
           (unsigned long)actag_workspace_size_inplace(530, 512),
           (unsigned long)actag_workspace_size_inplace(1024, 1024));
    if (actag_family_AcTag24h10(&fam) != ACTAG_OK)
        return 1;
    actag_params_default(&p);
    p.family = &fam;
    for (i = 1; i < argc; i++) {
        actag_frame f;
        int rows, cols, n;
        if (read_pgm(argv[i], &rows, &cols) != 0) {
            printf("frame %s unreadable\n", argv[i]);
            status = 1;
            continue;
        }
        f.data = px;
        f.rows = rows;
        f.cols = cols;
        f.stride = cols;
        f.depth = 8;
        n = run_frame("frame", argv[i], &f, &g, &p, 0);
        if (n < 0)
            status = 1;
        /* actag_detect_inplace on a copy (the same tags: docs/memory.md) */
        memcpy(px_ip, px, (size_t)rows * (size_t)cols);
        f.data = px_ip;
        if (run_frame("inplace", argv[i], &f, &g, &p, 1) != n)
            status = 1;
    }
    return status;
}
