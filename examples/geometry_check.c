/* actag_detect --check-geometry: see geometry_check.h. */
#include "geometry_check.h"

#include <stdlib.h>
#include <string.h>

int gc_add(gc_tags *t, const actag_detection *det, int n)
{
    int k;
    if (t->n + n > t->cap) { /* room for all of them first: all or none */
        int cap = t->cap ? t->cap : 64;
        gc_tag *p;
        while (cap < t->n + n)
            cap *= 2;
        p = (gc_tag *)realloc(t->tag, (size_t)cap * sizeof *p);
        if (!p)
            return GC_NO_MEMORY;
        t->tag = p;
        t->cap = cap;
    }
    for (k = 0; k < n; k++) {
        gc_tag *g = &t->tag[t->n++];
        memcpy(g->range, det[k].range, sizeof g->range);
        memcpy(g->azimuth, det[k].azimuth, sizeof g->azimuth);
        g->mirrored = det[k].mirrored;
    }
    return 0;
}

void gc_free(gc_tags *t)
{
    free(t->tag);
    memset(t, 0, sizeof *t);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median chi2 of the tags' poses with the azimuths times az_k and the tag
 * size times size_k (tags without a pose left out); -1 when none has one.
 * buf: room for t->n values. *fitted (may be NULL): how many had a pose. */
static double median_chi2(const gc_tags *t, const actag_pose_params *pp, double az_k,
                          double size_k, double *buf, int *fitted)
{
    actag_pose_params q = *pp;
    int i, m = 0;
    q.tag_size = (float)(pp->tag_size * size_k);
    for (i = 0; i < t->n; i++) {
        const gc_tag *g = &t->tag[i];
        float az[4];
        actag_pose P;
        int c;
        for (c = 0; c < 4; c++)
            az[c] = (float)(g->azimuth[c] * az_k);
        if (actag_pose_estimate(g->range, az, g->mirrored, &q, &P) == ACTAG_OK)
            buf[m++] = (double)P.chi2;
    }
    if (fitted)
        *fitted = m;
    if (m == 0)
        return -1.0;
    qsort(buf, (size_t)m, sizeof *buf, cmp_double);
    return (m & 1) ? buf[m / 2] : 0.5 * (buf[m / 2 - 1] + buf[m / 2]);
}

/* The k in [GC_SCALE_MIN, GC_SCALE_MAX] with the least median chi2 (steps
 * of 0.005, then 0.001 around the best); which: 0 azimuth, 1 tag size. */
static void scan(const gc_tags *t, const actag_pose_params *pp, int which, double *buf,
                 double *best_k, double *best_chi2, int *edge)
{
    double k, lo, hi, bk = 1.0, bc = -1.0;
    int pass;
    lo = GC_SCALE_MIN;
    hi = GC_SCALE_MAX;
    for (pass = 0; pass < 2; pass++) {
        double step = pass == 0 ? 0.005 : 0.001;
        int i, steps = (int)((hi - lo) / step + 0.5);
        for (i = 0; i <= steps; i++) {
            double c;
            k = lo + step * i;
            c = median_chi2(t, pp, which == 0 ? k : 1.0, which == 1 ? k : 1.0, buf, NULL);
            if (c >= 0.0 && (bc < 0.0 || c < bc)) {
                bc = c;
                bk = k;
            }
        }
        lo = bk - 0.005 > GC_SCALE_MIN ? bk - 0.005 : GC_SCALE_MIN;
        hi = bk + 0.005 < GC_SCALE_MAX ? bk + 0.005 : GC_SCALE_MAX;
    }
    *best_k = bk;
    *best_chi2 = bc;
    *edge = bk <= GC_SCALE_MIN + 0.0005 || bk >= GC_SCALE_MAX - 0.0005;
}

int gc_check(const gc_tags *t, const actag_pose_params *pp, gc_result *r)
{
    double *buf;
    memset(r, 0, sizeof *r);
    r->tags = t->n;
    if (t->n == 0)
        return GC_NO_TAG;
    buf = (double *)malloc((size_t)t->n * sizeof *buf);
    if (!buf)
        return GC_NO_MEMORY;
    r->chi2 = median_chi2(t, pp, 1.0, 1.0, buf, &r->fitted);
    if (r->fitted == 0) {
        free(buf);
        return GC_NO_TAG;
    }
    scan(t, pp, 0, buf, &r->az_scale, &r->az_chi2, &r->az_edge);
    scan(t, pp, 1, buf, &r->size_scale, &r->size_chi2, &r->size_edge);
    free(buf);
    return 0;
}
