/*
 * c_stats.c -- what libactag itself returns for one frame, for the tests'
 * comparison with pyactag (conftest.py compiles it against the C build's
 * library, next to actag_detect): the detections' IDs, inlier ratios and
 * decision margins and every counter of actag_stats, which actag_detect
 * --json does not print.
 *
 *   c_stats FRAME.raw ROWS COLS APERTURE_RAD [NAME=VALUE ...]
 *
 * FRAME.raw: ROWS x COLS uint8 pixels, row-major. Geometry: min_range 0.1,
 * max_range 1.5, the aperture in radians, default orientation; family
 * AcTag24h10, the parameters' C defaults but for NAME=VALUE (a few integer
 * tuning fields, below), at most 64 detections (pyactag's default).
 * Output: one JSON line {"n", "detections": [{"id", "inlier_ratio",
 * "decision_margin"}], "stats": {every actag_stats field by its C name}};
 * floats with 9 significant digits (exact for a float).
 */
#include "actag/actag.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_OUT 64

static int set_param(actag_params *p, const char *arg)
{
    const char *eq = strchr(arg, '=');
    int v;
    size_t len;
    if (eq == NULL)
        return -1;
    len = (size_t)(eq - arg);
    v = atoi(eq + 1);
#define FIELD(name, member)                                                                   \
    if (len == sizeof name - 1 && strncmp(arg, name, len) == 0) {                             \
        p->member = v;                                                                        \
        return 0;                                                                             \
    }
    FIELD("max_contours", tuning.limits.max_contours)
    FIELD("max_contour_iterations", tuning.limits.max_contour_iterations)
    FIELD("max_frame_iterations", tuning.limits.max_frame_iterations)
    FIELD("max_decodes", tuning.limits.max_decodes)
    FIELD("search_candidates", tuning.search_candidates)
#undef FIELD
    return -1;
}

int main(int argc, char **argv)
{
    static actag_detection det[MAX_OUT];
    actag_family fam;
    actag_params p;
    actag_sonar_geometry geo;
    actag_frame fr;
    actag_stats st;
    unsigned char *px;
    void *ws;
    size_t need, npx;
    FILE *f;
    int rows, cols, n, i;
    if (argc < 5) {
        fprintf(stderr, "usage: c_stats FRAME.raw ROWS COLS APERTURE_RAD [NAME=VALUE ...]\n");
        return 2;
    }
    rows = atoi(argv[2]);
    cols = atoi(argv[3]);
    if (rows < 1 || cols < 1) {
        fprintf(stderr, "c_stats: bad size %s x %s\n", argv[2], argv[3]);
        return 2;
    }
    npx = (size_t)rows * (size_t)cols;
    px = (unsigned char *)malloc(npx);
    f = fopen(argv[1], "rb");
    if (px == NULL || f == NULL || fread(px, 1, npx, f) != npx) {
        fprintf(stderr, "c_stats: cannot read %lu bytes from %s\n", (unsigned long)npx, argv[1]);
        return 2;
    }
    fclose(f);
    actag_params_default(&p);
    if (actag_family_get("AcTag24h10", &fam) != ACTAG_OK)
        return 2;
    p.family = &fam;
    for (i = 5; i < argc; i++)
        if (set_param(&p, argv[i]) != 0) {
            fprintf(stderr, "c_stats: unknown parameter %s\n", argv[i]);
            return 2;
        }
    memset(&geo, 0, sizeof geo);
    geo.min_range = (float)0.1;
    geo.max_range = (float)1.5;
    geo.aperture = (float)strtod(argv[4], NULL);
    fr.data = px;
    fr.rows = rows;
    fr.cols = cols;
    fr.stride = cols;
    fr.depth = 8;
    need = actag_workspace_size(rows, cols);
    ws = malloc(need);
    if (ws == NULL)
        return 2;
    memset(&st, 0, sizeof st);
    n = actag_detect(&fr, &geo, &p, ws, need, det, MAX_OUT, &st);
    if (n < 0) {
        fprintf(stderr, "c_stats: %s\n", actag_strerror(n));
        return 2;
    }
    printf("{\"n\": %d, \"detections\": [", n);
    for (i = 0; i < n; i++)
        printf("%s{\"id\": %d, \"inlier_ratio\": %.9g, \"decision_margin\": %.9g}", i ? ", " : "",
               det[i].id, (double)det[i].inlier_ratio, (double)det[i].decision_margin);
    printf("], \"stats\": {\"contours\": %d, \"size_ok\": %d, \"overflowed\": %d, \"quads\": %d, "
           "\"decoded\": %d, \"duplicates\": %d, \"dropped\": %d, \"searched\": %d, "
           "\"decodes\": %d, \"iterations\": %d, \"contour_cap\": %d, \"ransac_exhausted\": %d, "
           "\"contour_budget\": %d, \"frame_budget\": %d, \"decode_cap\": %d, "
           "\"search_cap\": %d, \"guess_cap\": %d}}\n",
           st.contours, st.size_ok, st.overflowed, st.quads, st.decoded, st.duplicates,
           st.dropped, st.searched, st.decodes, st.iterations, st.contour_cap,
           st.ransac_exhausted, st.contour_budget, st.frame_budget, st.decode_cap, st.search_cap,
           st.guess_cap);
    free(ws);
    free(px);
    return 0;
}
