/* Ground-truth JSON, pool settings, random IDs, the tools' shared options,
 * tag statistics, real-frame comparison. */
#define _POSIX_C_SOURCE 200809L
#include "simio.h"
#include "actag/version.h"
#include "../hostio/hostio.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define DEGF (3.14159265358979f / 180.0f)
#define DEG (3.14159265358979 / 180.0)

void simio_pool_sonar(sim_sonar *s)
{
    memset(s, 0, sizeof *s);
    s->rows = 530;
    s->cols = 512;
    s->geo.min_range = 0.1f;
    s->geo.max_range = 1.5f;
    s->geo.aperture = 60.0f * DEGF;
    s->geo.bearings = NULL;
    s->geo.flags = 0;
    s->vertical_aperture = 12.0f * DEGF;
}

void simio_pool_settings(sim_sonar *s, sim_view_params *v)
{
    simio_pool_sonar(s);
    v->min_distance = 0.9f;
    v->max_distance = 1.4f;
    v->min_incidence = 55.0f * DEGF;
    v->max_incidence = 75.0f * DEGF;
}

int simio_random_id(uint32_t seed, int ncodes)
{
    actag_rng g;
    actag_rng_seed(&g, seed ^ 0x5bd1e995u);
    return (int)actag_rng_below(&g, (uint32_t)ncodes);
}

/* ------------------------------------------------------------ options */

int simio_opt_defaults(int argc, char **argv, sim_sonar *s, sim_view_params *v,
                       sim_appearance *a)
{
    int i, pool = 0;
    memset(s, 0, sizeof *s);
    s->rows = 1024;
    s->cols = 512;
    s->geo.min_range = 0.1f;
    s->geo.max_range = 5.0f;
    s->vertical_aperture = (float)(12.0 * DEG);
    sim_appearance_default(a);
    sim_view_params_default(v);
    for (i = 1; i < argc; i++)
        if (!strcmp(argv[i], "--pool"))
            pool = 1;
    if (pool)
        simio_pool_settings(s, v);
    return pool;
}

void simio_opt_need(const char *prog, const char *opt, const char *value, int *i)
{
    if (!value) { /* hostio_opt_value's wording */
        char m[128];
        snprintf(m, sizeof m, "%.100s: missing value", opt);
        hostio_die(prog, m);
    }
    (*i)++;
}

int simio_opt_common(const simio_cli *cli, int argc, char **argv, int *i)
{
    const char *prog = cli->prog, *o = argv[*i];
    const char *val = *i + 1 < argc ? argv[*i + 1] : NULL;
    sim_sonar *s = cli->sonar;
    sim_view_params *v = cli->view;
#define NEED() simio_opt_need(prog, o, val, i)
#define num(lo, hi) hostio_opt_double(prog, o, val, (lo), (hi))
#define inum(lo, hi) hostio_opt_long(prog, o, val, (lo), (hi))
    if (!strcmp(o, "--help")) {
        cli->usage(stdout);
        exit(0);
    } else if (!strcmp(o, "--version")) {
        printf("%s %s\n", prog, ACTAG_VERSION_STRING);
        exit(0);
    } else if (!strcmp(o, "--pool")) {
        /* applied first (simio_opt_defaults) */
    } else if (!strcmp(o, "--min-distance")) {
        NEED();
        v->min_distance = (float)num(0.01, 1000.0);
    } else if (!strcmp(o, "--max-distance")) {
        NEED();
        v->max_distance = (float)num(0.01, 1000.0);
    } else if (!strcmp(o, "--min-incidence-deg")) {
        NEED();
        v->min_incidence = (float)(num(0.0, 89.9) * DEG);
    } else if (!strcmp(o, "--max-incidence-deg")) {
        NEED();
        v->max_incidence = (float)(num(0.0, 89.9) * DEG);
    } else if (!strcmp(o, "--max-yaw-deg")) {
        NEED();
        v->max_yaw = (float)(num(0.0, 180.0) * DEG);
    } else if (!strcmp(o, "--mirror-fraction")) {
        NEED();
        v->mirror_fraction = (float)num(0.0, 1.0);
    } else if (!strcmp(o, "--clutter")) {
        NEED();
        v->clutter = (int)inum(0, SIM_MAX_PATCHES / 2);
    } else if (!strcmp(o, "--rows")) {
        NEED();
        s->rows = (int)inum(cli->min_dim, cli->max_dim);
    } else if (!strcmp(o, "--cols")) {
        NEED();
        s->cols = (int)inum(cli->min_dim, cli->max_dim);
    } else if (!strcmp(o, "--min-range")) {
        NEED();
        s->geo.min_range = (float)num(0.0, 10000.0);
    } else if (!strcmp(o, "--max-range")) {
        NEED();
        s->geo.max_range = (float)num(0.0, 10000.0);
    } else if (!strcmp(o, "--aperture-deg")) {
        NEED();
        *cli->aperture_deg = num(0.01, 359.9);
    } else if (!strcmp(o, "--vertical-aperture-deg")) {
        NEED();
        s->vertical_aperture = (float)(num(0.1, 90.0) * DEG);
    } else if (!strcmp(o, "--range-ascending")) {
        s->geo.flags |= ACTAG_RANGE_ASCENDING;
    } else if (!strcmp(o, "--azimuth-ascending")) {
        s->geo.flags |= ACTAG_AZIMUTH_ASCENDING;
    } else {
        return 0;
    }
    return 1;
#undef NEED
#undef num
#undef inum
}

void simio_opt_check_views(const char *prog, const sim_view_params *v)
{
    char m[200];
    if (v->max_distance < v->min_distance) {
        snprintf(m, sizeof m, "--max-distance: must be at least --min-distance %g (got %g)",
                 (double)v->min_distance, (double)v->max_distance);
        hostio_die(prog, m);
    }
    if (v->max_incidence < v->min_incidence) {
        snprintf(m, sizeof m, "--max-incidence-deg: must be at least --min-incidence-deg %g (got %g)",
                 (double)v->min_incidence * (180.0 / 3.14159265358979323846),
                 (double)v->max_incidence * (180.0 / 3.14159265358979323846));
        hostio_die(prog, m);
    }
}

void simio_opt_family(const char *prog, const char *opt, const char *name, actag_family *fam)
{
    if (actag_family_get(name, fam) != ACTAG_OK) {
        char m[300];
        snprintf(m, sizeof m, "%s: unknown family '%s'", opt, name);
        hostio_die(prog, m);
    }
}

/* ------------------------------------------------------------ ground truth */

void simio_truth_line(FILE *f, const char *file, int frame, uint32_t seed, const sim_sonar *s,
                      const sim_scene *scene)
{
    int t, n, j;
    fprintf(f, "{\"file\": ");
    hostio_json_string(f, file);
    fprintf(f, ", \"frame\": %d, \"seed\": %u, \"rows\": %d, \"cols\": %d, \"clutter\": %d, "
               "\"coordinates\": \"x_col = column, y_row = row, pixels, centre of the top-left pixel at (0, 0)\", \"tags\": [",
            frame, (unsigned)seed, s->rows, s->cols, scene->npatches);
    for (t = 0; t < scene->ntags; t++) {
        const sim_tag *tag = &scene->tags[t];
        sim_truth tr;
        float rpy[3];
        sim_truth_of(s, tag, &tr);
        sim_pose_rpy(&tag->pose, rpy);
        fprintf(f, "%s{\"family\": ", t ? ", " : "");
        hostio_json_string(f, tag->family.name);
        fprintf(f, ", \"id\": %d, \"tag_size\": %.9g, \"mirrored\": %d, \"visible\": %d, "
                   "\"distance\": %.6f, \"incidence_deg\": %.4f, \"pose\": {\"t\": [%.6f, %.6f, %.6f], "
                   "\"rpy_deg\": [%.4f, %.4f, %.4f], \"R\": [",
                tag->id, (double)tag->tag_size, tr.mirrored, tr.visible, (double)tr.distance,
                (double)(tr.incidence / DEGF), (double)tag->pose.t[0], (double)tag->pose.t[1],
                (double)tag->pose.t[2], (double)(rpy[0] / DEGF), (double)(rpy[1] / DEGF),
                (double)(rpy[2] / DEGF));
        for (j = 0; j < 9; j++)
            fprintf(f, "%s%.7f", j ? ", " : "", (double)tag->pose.R[j]);
        fprintf(f, "]}, \"corners\": [");
        for (n = 0; n < 4; n++)
            fprintf(f, "%s{\"x_col\": %.3f, \"y_row\": %.3f, \"range_m\": %.6f, \"azimuth_rad\": %.6f}",
                    n ? ", " : "", (double)tr.px[n].x, (double)tr.px[n].y, (double)tr.range[n],
                    (double)tr.azimuth[n]);
        fprintf(f, "]}");
    }
    fprintf(f, "]}\n");
}

static float bilinear(const uint8_t *img, int rows, int cols, float x, float y)
{
    int x0, y0;
    float fx, fy, a, b, c, d;
    if (x < 0.0f) x = 0.0f;
    if (y < 0.0f) y = 0.0f;
    if (x > (float)cols - 1.001f) x = (float)cols - 1.001f;
    if (y > (float)rows - 1.001f) y = (float)rows - 1.001f;
    x0 = (int)x;
    y0 = (int)y;
    fx = x - (float)x0;
    fy = y - (float)y0;
    a = img[(size_t)y0 * (size_t)cols + (size_t)x0];
    b = img[(size_t)y0 * (size_t)cols + (size_t)x0 + 1];
    c = img[(size_t)(y0 + 1) * (size_t)cols + (size_t)x0];
    d = img[(size_t)(y0 + 1) * (size_t)cols + (size_t)x0 + 1];
    return (a * (1 - fx) + b * fx) * (1 - fy) + (c * (1 - fx) + d * fx) * fy;
}

static int cmp_u8(const void *a, const void *b)
{
    return (int)*(const uint8_t *)a - (int)*(const uint8_t *)b;
}

int simio_tag_stats_of(const uint8_t *img, int rows, int cols, const actag_point corners[4],
                       int bits, simio_tag_stats *out)
{
    float H[9];
    int k = bits / 4, i, j, nf = 0, nm = 0, x, y;
    double sf = 0.0, sm = 0.0, sb = 0.0;
    float xmin = 1e30f, xmax = -1e30f, ymin = 1e30f, ymax = -1e30f, cxm, cym, hw, hh;
    uint8_t *bg;
    size_t nb = 0;
    if (actag_tag_affine(corners, bits, H) != ACTAG_OK)
        return -1;
    /* foam: a lattice inside the white square [2, k-1], away from its edges */
    for (i = 0; i < 9; i++)
        for (j = 0; j < 9; j++) {
            actag_point p;
            float u = 2.3f + ((float)k - 3.6f) * (float)i / 8.0f;
            float v = 2.3f + ((float)k - 3.6f) * (float)j / 8.0f;
            actag_homography_apply(H, u, v, &p);
            sf += bilinear(img, rows, cols, p.x, p.y);
            nf++;
        }
    /* metal: centres of the black ring's cells (ring 1), +-0.2 cell */
    for (y = 1; y <= k - 1; y++)
        for (x = 1; x <= k - 1; x++) {
            int a, b;
            if (x != 1 && x != k - 1 && y != 1 && y != k - 1)
                continue;
            for (a = -1; a <= 1; a++)
                for (b = -1; b <= 1; b++) {
                    actag_point p;
                    actag_homography_apply(H, (float)x + 0.5f + 0.2f * (float)a,
                                           (float)y + 0.5f + 0.2f * (float)b, &p);
                    sm += bilinear(img, rows, cols, p.x, p.y);
                    nm++;
                }
        }
    /* background: outside twice the tag's bounding box */
    for (i = 0; i < 4; i++) {
        xmin = fminf(xmin, corners[i].x);
        xmax = fmaxf(xmax, corners[i].x);
        ymin = fminf(ymin, corners[i].y);
        ymax = fmaxf(ymax, corners[i].y);
    }
    cxm = 0.5f * (xmin + xmax);
    cym = 0.5f * (ymin + ymax);
    hw = (xmax - xmin) * (float)(k + 1) / (float)(k - 3); /* full tag, times 2 / 2 */
    hh = (ymax - ymin) * (float)(k + 1) / (float)(k - 3);
    bg = (uint8_t *)malloc((size_t)rows * (size_t)cols);
    if (!bg)
        return -1;
    for (y = 0; y < rows; y++)
        for (x = 0; x < cols; x++) {
            if (fabsf((float)x - cxm) <= hw && fabsf((float)y - cym) <= hh)
                continue;
            bg[nb++] = img[(size_t)y * (size_t)cols + (size_t)x];
            sb += img[(size_t)y * (size_t)cols + (size_t)x];
        }
    if (nb == 0) {
        free(bg);
        return -1;
    }
    qsort(bg, nb, 1, cmp_u8);
    out->background = bg[nb / 2];
    out->background_mean = (float)(sb / (double)nb);
    free(bg);
    out->foam = (float)(sf / nf);
    out->metal = (float)(sm / nm);
    return 0;
}

/* ------------------------------------------------------------ comparison */

typedef struct {
    float *v;
    int n;
} series;

static void push(series *s, float v) { s->v[s->n++] = v; }

static int cmp_f(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return x < y ? -1 : x > y;
}

static float pct(series *s, float p)
{
    if (s->n == 0)
        return 0.0f;
    qsort(s->v, (size_t)s->n, sizeof(float), cmp_f);
    return s->v[(int)(p * (float)(s->n - 1) + 0.5f)];
}

static void downscale_into(const uint8_t *img, int rows, int cols, uint8_t *canvas, int cw,
                           int ox, int oy)
{
    int r, c;
    for (r = 0; r < rows / 2; r++)
        for (c = 0; c < cols / 2; c++) {
            const uint8_t *p = img + (size_t)(2 * r) * (size_t)cols + (size_t)(2 * c);
            canvas[(size_t)(oy + r) * (size_t)cw + (size_t)(ox + c)] =
                (uint8_t)((p[0] + p[1] + p[cols] + p[cols + 1] + 2) / 4);
        }
}

/* One clean-up path for every way out: early returns leaked the names, the
 * series and the buffers, and no allocation was checked. */
int simio_compare_real(const char *dir, int n, uint32_t seed, const sim_appearance *a,
                       const char *montage, FILE *out, char *err)
{
    char **names = NULL;
    int nnames = 0, i, q, shown_real = 0, shown_sim = 0, rc = -1;
    series st[2][5]; /* [real/sim][background, foam, metal, contrast, ratio] */
    static const char *label[5] = {"background median", "foam mean", "metal mean",
                                   "foam - metal", "foam / metal"};
    actag_family fam;
    actag_params p;
    actag_sonar_geometry geo;
    sim_sonar sonar;
    sim_view_params view;
    void *ws = NULL;
    uint8_t *canvas = NULL, *img = NULL;
    int cw = 4 * 256, ch = 2 * 265;
    memset(st, 0, sizeof st); /* every series NULL: freed below whatever was made */
    {
        char e2[HOSTIO_ERRLEN];
        names = hostio_list_dir(dir, "", ".pgm", &nnames, e2);
        if (!names) {
            if (err)
                snprintf(err, HOSTIO_ERRLEN, "--compare-real: %.200s", e2);
            return -1;
        }
    }
    if (nnames == 0) {
        if (err)
            snprintf(err, HOSTIO_ERRLEN, "--compare-real: no .pgm frames in '%.150s'", dir);
        goto done;
    }
    for (i = 0; montage && i < nnames; i++)
        if (hostio_same_file(montage, names[i])) { /* refused before any work, not replaced */
            if (err)
                snprintf(err, HOSTIO_ERRLEN, "--montage '%.80s': is the input frame '%.80s' "
                         "(--compare-real); not overwritten", montage, names[i]);
            goto done;
        }
    for (q = 0; q < 2; q++)
        for (i = 0; i < 5; i++) {
            st[q][i].v = (float *)malloc((size_t)(nnames > n ? nnames : n) * sizeof(float));
            if (!st[q][i].v)
                goto out_of_memory;
        }
    if (montage) {
        canvas = (uint8_t *)calloc((size_t)cw * (size_t)ch, 1);
        if (!canvas)
            goto out_of_memory;
    }
    ws = malloc(ACTAG_WORKSPACE_SIZE(530, 512));
    img = (uint8_t *)malloc(530 * 512);
    if (!ws || !img)
        goto out_of_memory;
    actag_family_get("AcTag24h10", &fam);
    actag_params_default(&p);
    p.family = &fam;
    p.tag_size = 0.130628571f;
    memset(&sonar, 0, sizeof sonar);
    sim_view_params_default(&view);
    simio_pool_settings(&sonar, &view);
    geo = sonar.geo;
    for (i = 0; i < nnames; i++) {
        hostio_image im;
        actag_frame fr;
        actag_detection det[4];
        int nd;
        simio_tag_stats ts;
        if (hostio_pgm_read(names[i], &im, err) != HOSTIO_OK)
            goto done;
        if (im.depth != 8 || im.rows > 530 || im.cols > 512) { /* said, not silently left out */
            fprintf(stderr, "--compare-real: %s: skipped (a %d x %d, %d-bit frame; the comparison "
                            "reads 8-bit pool frames of at most 512 x 530)\n",
                    names[i], im.cols, im.rows, im.depth);
            hostio_image_free(&im);
            continue;
        }
        hostio_image_frame(&im, &fr); /* depth 8 */
        nd = actag_detect(&fr, &geo, &p, ws, ACTAG_WORKSPACE_SIZE(530, 512), det, 4, NULL);
        if (nd == 1 && simio_tag_stats_of((const uint8_t *)im.data, im.rows, im.cols,
                                          det[0].corners, 24, &ts) == 0) {
            push(&st[0][0], ts.background);
            push(&st[0][1], ts.foam);
            push(&st[0][2], ts.metal);
            push(&st[0][3], ts.foam - ts.metal);
            push(&st[0][4], ts.foam / fmaxf(ts.metal, 1.0f));
            if (canvas && shown_real < 4 && im.rows == 530 && im.cols == 512 &&
                (i % 9 == 0 || nnames - i <= 4 - shown_real)) {
                downscale_into((const uint8_t *)im.data, 530, 512, canvas, cw, 256 * shown_real, 0);
                shown_real++;
            }
        }
        hostio_image_free(&im);
    }
    if (st[0][0].n == 0) { /* nothing to compare with: not a table of zeros and status 0 */
        if (err)
            snprintf(err, HOSTIO_ERRLEN,
                     "--compare-real: no tag detected in any of the %d .pgm frames in '%.150s'",
                     nnames, dir);
        goto done;
    }
    for (i = 0; i < n; i++) {
        sim_tag tag;
        sim_scene sc;
        sim_truth tr;
        simio_tag_stats ts;
        uint32_t fs = sim_frame_seed(seed, (uint32_t)i);
        memset(&tag, 0, sizeof tag);
        tag.family = fam;
        tag.id = 0;
        tag.tag_size = 0.130628571f;
        view.mirror_fraction = 0.0f;
        if (sim_sample_view(&sonar, &view, fs, &tag, &sc) != 0)
            continue;
        if (sim_render(&sonar, &sc, a, fs, img, NULL, 512, err) != 0)
            goto done;
        sim_truth_of(&sonar, &tag, &tr);
        if (simio_tag_stats_of(img, 530, 512, tr.px, 24, &ts) != 0)
            continue;
        push(&st[1][0], ts.background);
        push(&st[1][1], ts.foam);
        push(&st[1][2], ts.metal);
        push(&st[1][3], ts.foam - ts.metal);
        push(&st[1][4], ts.foam / fmaxf(ts.metal, 1.0f));
        if (canvas && shown_sim < 4) {
            downscale_into(img, 530, 512, canvas, cw, 256 * shown_sim, 265);
            shown_sim++;
        }
    }
    fprintf(out, "grey levels (8-bit): median [10th-90th percentile] over frames\n");
    fprintf(out, "%-20s %-24s %-24s %s\n", "", "real (pool frames)", "simulated (pool views)",
            "sim/real (medians)");
    fprintf(out, "%-20s %-24d %-24d\n", "frames", st[0][0].n, st[1][0].n);
    for (i = 0; i < 5; i++) {
        char a1[64], a2[64];
        float m0 = pct(&st[0][i], 0.5f), m1 = pct(&st[1][i], 0.5f);
        snprintf(a1, sizeof a1, "%.1f [%.1f-%.1f]", (double)m0, (double)pct(&st[0][i], 0.1f),
                 (double)pct(&st[0][i], 0.9f));
        snprintf(a2, sizeof a2, "%.1f [%.1f-%.1f]", (double)m1, (double)pct(&st[1][i], 0.1f),
                 (double)pct(&st[1][i], 0.9f));
        fprintf(out, "%-20s %-24s %-24s %.2f\n", label[i], a1, a2,
                m0 > 0.0f ? (double)(m1 / m0) : 0.0);
    }
    if (canvas) {
        hostio_image im;
        im.data = canvas;
        im.rows = ch;
        im.cols = cw;
        im.stride = cw;
        im.depth = 8;
        im.maxval = 255;
        if (hostio_pgm_write(montage, &im, err) != HOSTIO_OK)
            goto done;
        fprintf(out, "montage: %s (top: real pool frames, bottom: simulated, half size)\n",
                montage);
    }
    rc = 0;
    goto done;
out_of_memory:
    if (err)
        snprintf(err, HOSTIO_ERRLEN, "--compare-real: out of memory");
done:
    for (q = 0; q < 2; q++)
        for (i = 0; i < 5; i++)
            free(st[q][i].v);
    hostio_list_free(names, nnames);
    free(ws);
    free(img);
    free(canvas);
    return rc;
}
