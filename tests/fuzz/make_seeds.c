/*
 * make_seeds.c -- writes the fuzz harnesses' seed inputs (build time).
 *
 *   fuzz_make_seeds OUTDIR EXAMPLE.pgm [POOLDIR]
 *
 * OUTDIR/detect: crops of the real example frame and of pool frames (when
 *   POOLDIR exists) around their tag (found with actag_detect, else the
 *   centre), with the crop's own geometry; simulated pool views (tools/sim),
 *   8 and 16 bit, both row orders, a bearing table; synthetic adversarial
 *   frames (checkerboards 1..64, blobs, speckle, noise, stripes, a rendered
 *   tag); the hostile inputs of issue 10 (huge tag size, NaN and swapped
 *   ranges, apertures 0 and > 2 pi, workspace one byte short, stride < cols,
 *   odd 16-bit frames, ...).
 * OUTDIR/decode, family, hostio, quad, pose, track: small hand-made starts.
 * Every file is a valid input of its harness by construction (the detect
 * seeds through fzd_encode); OUTDIR/stamp marks completion.
 */
#define _POSIX_C_SOURCE 200809L
#include "fuzz_detect_case.h"
#include "hostio.h"
#include "sim.h"

#include <sys/stat.h>

static const char *g_out;
static int g_count;

static void put(const char *harness, const char *name, const uint8_t *data, size_t n)
{
    char path[4096], err[HOSTIO_ERRLEN];
    snprintf(path, sizeof path, "%s/%s", g_out, harness);
    if (hostio_mkdirs(path, err) != HOSTIO_OK) {
        fprintf(stderr, "fuzz_make_seeds: %s\n", err);
        exit(1);
    }
    snprintf(path, sizeof path, "%s/%s/%s", g_out, harness, name);
    if (hostio_write_file(path, data, n, err) != HOSTIO_OK) {
        fprintf(stderr, "fuzz_make_seeds: %s\n", err);
        exit(1);
    }
    g_count++;
}

static void put_case(const char *name, const fzd_case *c)
{
    uint8_t *buf = (uint8_t *)malloc(512 + c->npixels);
    size_t n;
    if (!buf)
        exit(1);
    n = fzd_encode(c, buf);
    put("detect", name, buf, n);
    free(buf);
}

/* A crop of h x w pixels around (cr, cc) of an 8-bit frame with its
 * geometry (reference orientation): the crop's own ranges and aperture. */
static void put_crop(const char *name, const uint8_t *img, int rows, int cols,
                     const actag_sonar_geometry *g, int cr, int cc, int h, int w)
{
    uint8_t *px;
    fzd_case c;
    int r0, c0, r;
    float rmax, rmin, ap;
    if (h > rows)
        h = rows;
    if (w > cols)
        w = cols;
    r0 = cr - h / 2;
    c0 = cc - w / 2;
    r0 = r0 < 0 ? 0 : r0 + h > rows ? rows - h : r0;
    c0 = c0 < 0 ? 0 : c0 + w > cols ? cols - w : c0;
    px = (uint8_t *)malloc((size_t)h * (size_t)w);
    if (!px)
        exit(1);
    for (r = 0; r < h; r++)
        memcpy(px + (size_t)r * (size_t)w, img + (size_t)(r0 + r) * (size_t)cols + (size_t)c0,
               (size_t)w);
    rmax = actag_geometry_range(g, rows, (float)r0);
    rmin = actag_geometry_range(g, rows, (float)(r0 + h - 1));
    ap = actag_geometry_azimuth_step(g, cols, (float)c0) * (float)(w - 1);
    fzd_default_case(&c, h, w, rmin, rmax, ap, px);
    put_case(name, &c);
    free(px);
}

/* Where actag_detect finds a tag in a frame (else the centre). */
static void tag_centre(const uint8_t *img, int rows, int cols, const actag_sonar_geometry *g,
                       int *cr, int *cc)
{
    actag_family fam;
    actag_params p;
    actag_frame f;
    actag_detection det[4];
    void *ws = malloc(actag_workspace_size(rows, cols));
    int n;
    *cr = rows / 2;
    *cc = cols / 2;
    if (!ws)
        return;
    actag_family_get("AcTag24h10", &fam);
    actag_params_default(&p);
    p.family = &fam;
    f.data = img;
    f.rows = rows;
    f.cols = cols;
    f.stride = cols;
    f.depth = 8;
    n = actag_detect(&f, g, &p, ws, actag_workspace_size(rows, cols), det, 4, NULL);
    if (n > 0) {
        *cc = (int)(0.25f * (det[0].corners[0].x + det[0].corners[1].x + det[0].corners[2].x +
                             det[0].corners[3].x));
        *cr = (int)(0.25f * (det[0].corners[0].y + det[0].corners[1].y + det[0].corners[2].y +
                             det[0].corners[3].y));
    }
    free(ws);
}

static void real_frames(const char *example, const char *pooldir)
{
    static const char *const pool[] = {"f_0001.pgm", "f_0101.pgm", "f_0241.pgm", "f_0401.pgm",
                                       "f_0561.pgm"};
    actag_sonar_geometry g = {0.1f, 1.5f, 1.0471976f, NULL, 0u};
    char err[HOSTIO_ERRLEN], path[4096], name[64];
    hostio_image im;
    int i, cr, cc;
    if (hostio_frame_read(example, NULL, &im, err) != HOSTIO_OK || im.depth != 8) {
        fprintf(stderr, "fuzz_make_seeds: %s\n", err);
        exit(1);
    }
    tag_centre((const uint8_t *)im.data, im.rows, im.cols, &g, &cr, &cc);
    put_crop("real-example-tag", (const uint8_t *)im.data, im.rows, im.cols, &g, cr, cc, 160, 200);
    put_crop("real-example-empty", (const uint8_t *)im.data, im.rows, im.cols, &g, im.rows - 40,
             60, 64, 96);
    hostio_image_free(&im);
    for (i = 0; pooldir && i < (int)(sizeof pool / sizeof pool[0]); i++) {
        struct stat sb;
        snprintf(path, sizeof path, "%s/%s", pooldir, pool[i]);
        if (stat(path, &sb) != 0 || hostio_frame_read(path, NULL, &im, err) != HOSTIO_OK)
            continue;
        if (im.depth == 8) {
            tag_centre((const uint8_t *)im.data, im.rows, im.cols, &g, &cr, &cc);
            snprintf(name, sizeof name, "real-pool-%s", pool[i]);
            put_crop(name, (const uint8_t *)im.data, im.rows, im.cols, &g, cr, cc, 200, 200);
        }
        hostio_image_free(&im);
    }
}

static void sim_frames(void)
{
    static uint8_t img[530 * 512];
    static uint16_t img16[530 * 512];
    sim_sonar s;
    sim_appearance a;
    sim_view_params v;
    sim_scene sc;
    sim_tag tag;
    sim_truth tr;
    fzd_case c;
    char name[64];
    int i;
    memset(&s, 0, sizeof s);
    s.rows = 530;
    s.cols = 512;
    s.geo.min_range = 0.1f;
    s.geo.max_range = 1.5f;
    s.geo.aperture = 1.0471976f;
    s.vertical_aperture = 0.20943951f;
    sim_appearance_default(&a);
    sim_view_params_default(&v);
    v.min_distance = 0.8f;
    v.max_distance = 1.3f;
    for (i = 0; i < 4; i++) {
        int cr, cc, r0, c0, h = 96, w = 112, r;
        uint8_t *px;
        memset(&tag, 0, sizeof tag);
        actag_family_get(i == 3 ? "AcTag24m10" : "AcTag24h10", &tag.family);
        tag.id = i % tag.family.ncodes;
        tag.tag_size = 0.130628571f;
        if (sim_sample_view(&s, &v, 100u + (uint32_t)i, &tag, &sc) != 0 ||
            sim_render(&s, &sc, &a, 7u + (uint32_t)i, img, i == 1 ? img16 : NULL, s.cols, NULL) !=
                0)
            continue;
        sim_truth_of(&s, &tag, &tr);
        cc = (int)(0.25f * (tr.px[0].x + tr.px[1].x + tr.px[2].x + tr.px[3].x));
        cr = (int)(0.25f * (tr.px[0].y + tr.px[1].y + tr.px[2].y + tr.px[3].y));
        r0 = cr - h / 2;
        c0 = cc - w / 2;
        r0 = r0 < 0 ? 0 : r0 + h > s.rows ? s.rows - h : r0;
        c0 = c0 < 0 ? 0 : c0 + w > s.cols ? s.cols - w : c0;
        px = (uint8_t *)malloc((size_t)h * (size_t)w * 2u);
        if (!px)
            exit(1);
        for (r = 0; r < h; r++) {
            if (i == 1) /* 16 bit, host order */
                memcpy(px + (size_t)r * (size_t)w * 2u,
                       img16 + (size_t)(r0 + r) * (size_t)s.cols + (size_t)c0, (size_t)w * 2u);
            else
                memcpy(px + (size_t)r * (size_t)w,
                       img + (size_t)(r0 + r) * (size_t)s.cols + (size_t)c0, (size_t)w);
        }
        fzd_default_case(&c, h, w, actag_geometry_range(&s.geo, s.rows, (float)(r0 + h - 1)),
                         actag_geometry_range(&s.geo, s.rows, (float)r0),
                         s.geo.aperture / (float)(s.cols - 1) * (float)(w - 1), px);
        c.fam_sel = i == 3 ? 7 : 3; /* AcTag24m10 / AcTag24h10 in the default list */
        if (i == 1) {
            c.depth = 16;
            c.npixels *= 2u;
        }
        if (i == 2) { /* rows stored nearest first, with a uniform bearing table */
            int rr;
            uint8_t *t = (uint8_t *)malloc((size_t)w);
            for (rr = 0; t && rr < h / 2; rr++) {
                memcpy(t, px + (size_t)rr * (size_t)w, (size_t)w);
                memcpy(px + (size_t)rr * (size_t)w, px + (size_t)(h - 1 - rr) * (size_t)w,
                       (size_t)w);
                memcpy(px + (size_t)(h - 1 - rr) * (size_t)w, t, (size_t)w);
            }
            free(t);
            c.geo.flags = ACTAG_RANGE_ASCENDING;
            c.bear_mode = 1;
        }
        snprintf(name, sizeof name, "sim-%d%s", i, i == 1 ? "-16bit" : i == 2 ? "-ascending" : "");
        put_case(name, &c);
        free(px);
    }
}

static void synthetic(void)
{
    static const int checker[] = {1, 2, 3, 4, 8, 16, 32, 64};
    fzd_case c;
    char name[64];
    int i;
    for (i = 0; i < (int)(sizeof checker / sizeof checker[0]); i++) {
        fzd_default_case(&c, 128, 128, 0.1f, 1.5f, 1.0471976f, NULL);
        c.pix_mode = FZD_PIX_CHECKER;
        c.pix_a = checker[i] - 1;
        snprintf(name, sizeof name, "adv-checker-%d", checker[i]);
        put_case(name, &c);
    }
    fzd_default_case(&c, 128, 128, 0.1f, 1.5f, 1.0471976f, NULL);
    c.pix_mode = FZD_PIX_BLOBS;
    c.pix_a = 5;
    c.pix_b = 3;
    put_case("adv-blobs", &c);
    c.pix_a = 14; /* tag-sized squares */
    c.pix_b = 6;
    put_case("adv-squares", &c);
    c.pix_mode = FZD_PIX_SPECKLE;
    c.pix_a = 60;
    c.pix_b = 0;
    put_case("adv-speckle", &c);
    c.pix_mode = FZD_PIX_NOISE;
    put_case("adv-noise", &c);
    c.pix_mode = FZD_PIX_STRIPES;
    c.pix_a = 3;
    put_case("adv-stripes", &c);
    c.pix_mode = FZD_PIX_TAG;
    c.pix_a = 3;
    c.pix_b = 40 | (40 << 8);
    put_case("synthetic-tag", &c);
    /* the tag pattern with each of the harness's invalid families (the
     * harness once divided by a family's zero code count here) */
    for (i = 0; i < 5; i++) {
        c.fam_sel = actag_family_count() + i;
        snprintf(name, sizeof name, "synthetic-tag-bad-family-%d", i);
        put_case(name, &c);
    }
    c.fam_sel = 3;
    c.pix_mode = FZD_PIX_CONST;
    c.pix_a = 255;
    put_case("all-white", &c);
    c.pix_a = 0;
    put_case("all-black", &c);
}

/* Issue 10's hostile inputs as seeds (the named tests check them too). */
static void hostile(void)
{
    fzd_case c, base;
    fzd_default_case(&base, 48, 48, 0.1f, 1.5f, 1.0471976f, NULL);
    base.pix_mode = FZD_PIX_NOISE;
#define HOSTILE(name, stmt)                                                                   \
    do {                                                                                      \
        c = base;                                                                             \
        stmt;                                                                                 \
        put_case("hostile-" name, &c);                                                        \
    } while (0)
    HOSTILE("tag-size-1e30", c.p.tag_size = 1e30f);
    HOSTILE("tag-size-0", c.p.tag_size = 0.0f);
    HOSTILE("min-inlier-ratio-0", c.p.tuning.quad.min_inlier_ratio = 0.0f);
    HOSTILE("min-inlier-ratio-nan", c.p.tuning.quad.min_inlier_ratio = NAN);
    HOSTILE("min-inlier-ratio-1.5", c.p.tuning.quad.min_inlier_ratio = 1.5f);
    HOSTILE("inlier-distance-1e7", c.p.tuning.quad.inlier_distance = 1e7f);
    HOSTILE("tiny-azimuth-step", c.geo.aperture = 1e-30f);
    HOSTILE("nan-range", c.geo.min_range = NAN);
    HOSTILE("inf-range", c.geo.max_range = INFINITY);
    HOSTILE("negative-range", c.geo.min_range = -1.0f);
    HOSTILE("swapped-ranges", (c.geo.min_range = 1.5f, c.geo.max_range = 0.1f));
    HOSTILE("aperture-0", c.geo.aperture = 0.0f);
    HOSTILE("aperture-400deg", c.geo.aperture = 6.98f);
    HOSTILE("bearings-not-monotonic", c.bear_mode = 4);
    HOSTILE("bearings-nan", c.bear_mode = 5);
    HOSTILE("radius-0", (c.p.tuning.median_radius = 0, c.p.tuning.threshold_radius = 0));
    HOSTILE("radius-larger-than-frame", (c.p.tuning.median_radius = 127, c.p.tuning.threshold_radius = 32));
    HOSTILE("threshold-radius-33", c.p.tuning.threshold_radius = 33);
    HOSTILE("corrections-5", c.p.max_bit_corrections = 5);
    HOSTILE("workspace-one-short", c.ws_mode = 1);
    HOSTILE("stride-lt-cols", c.stride = c.cols - 1);
    HOSTILE("rows-0", c.rows = 0);
    HOSTILE("rows-1", c.rows = 1);
    HOSTILE("cols-1", c.cols = c.stride = 1);
    HOSTILE("rows-max", (c.rows = ACTAG_MAX_DIM, c.cols = c.stride = 4));
    HOSTILE("cols-max", (c.rows = 4, c.cols = c.stride = ACTAG_MAX_DIM));
    HOSTILE("rows-too-many", c.rows = ACTAG_MAX_DIM + 1);
    HOSTILE("odd-16bit", (c.depth = 16, c.frame_misalign = 1));
    HOSTILE("depth-12", c.depth = 12);
    HOSTILE("null-data", c.null_sel = 1);
    HOSTILE("max-out-negative", c.max_out = -1);
    HOSTILE("ransac-1", c.p.tuning.quad.max_iterations = 1);
    HOSTILE("multi", c.multi = 1);
#undef HOSTILE
}

static void small_seeds(void)
{
    uint8_t b[256];
    size_t at;
    int f, i;
    /* decode: a rendered tag under the default square quad, each family */
    for (f = 0; f < actag_family_count(); f++) {
        char name[32];
        memset(b, 0, sizeof b);
        at = 3;
        b[at++] = 1; /* image: rendered tag */
        b[at++] = 1; /* quad: the square */
        at += 4;     /* cx cy half ang: defaults */
        b[at++] = (uint8_t)(f << 2);
        at += 2 + 6; /* corrections, model, fit options: defaults */
        b[at++] = 0; /* misalignment */
        b[at++] = (uint8_t)(f * 3); /* tag id */
        snprintf(name, sizeof name, "tag-family-%d", f);
        put("decode", name, b, at);
        b[4] = 9; /* a non-finite corner */
        snprintf(name, sizeof name, "nan-corner-%d", f);
        put("decode", name, b, at);
    }
    for (i = 2; i <= 8; i++) {
        char name[32];
        memset(b, 0, sizeof b);
        b[3] = 1;
        b[4] = (uint8_t)i;
        b[9] = 3 << 2;
        snprintf(name, sizeof name, "degenerate-%d", i);
        put("decode", name, b, 24);
    }
    /* family: each family, an exact code and a noisy one */
    for (f = 0; f < actag_family_count(); f++) {
        actag_family fam;
        char name[32];
        actag_family_get_at(f, &fam);
        at = 0;
        at = fz_put_u8(b, at, (uint8_t)(2 * f));
        at = fz_put_u32(b, at, actag_code_rot90(fam.codes[fam.ncodes / 2], fam.bits) ^ 5u);
        at = fz_put_default(b, at);
        at = fz_put_u8(b, at, (uint8_t)f);
        snprintf(name, sizeof name, "family-%d", f);
        put("family", name, b, at);
    }
    /* hostio: PGMs and raw frames (a 6-byte layout header first) */
    {
#define S(lit) {lit, sizeof lit - 1}
        static const struct {
            const char *s;
            size_t n;
        } files[] = {S("P5 3 2 255\n\001\002\003\004\005\006"),
                     S("P5\n# comment\n2 2\n100\n\000\012\144\062"),
                     S("P5 2 1 65535\n\001\002\377\376"),
                     S("P5 2 1 1000\n\003\350\003\351"),
                     S("P2 1 1 255\n0\n"),
                     S("P5 4 4 255\n\001\002"),
                     S("P5 2 1 255\n\007\010\011\012\013")};
#undef S
        for (i = 0; i < (int)(sizeof files / sizeof files[0]); i++) {
            char name[32];
            memset(b, 0, sizeof b);
            b[0] = (uint8_t)(i == 6); /* the last one with the 4 x 4 raw layout */
            memcpy(b + 6, files[i].s, files[i].n);
            snprintf(name, sizeof name, i == 6 ? "raw-p5" : "pgm-%d", i);
            put("hostio", name, b, 6 + files[i].n);
        }
    }
    /* quad: squares, speckle, raw bits */
    for (i = 0; i < 3; i++) {
        char name[32];
        memset(b, 0, sizeof b);
        b[0] = 60;
        b[1] = 60;
        b[4] = 90;
        b[5] = (uint8_t)(2 - i);
        for (at = 40; at < sizeof b; at++)
            b[at] = (uint8_t)(at * 37u);
        snprintf(name, sizeof name, "quad-%d", i);
        put("quad", name, b, sizeof b);
    }
    /* pose: squares at 0.5-20 m, tilted 0-1.4 rad (fuzz_pose's mode 1),
     * with apertures from the paper's 12 degrees down to 1e-6 rad */
    for (i = 0; i < 6; i++) {
        static const float dist[6] = {0.5f, 1.0f, 2.0f, 4.0f, 8.0f, 20.0f};
        static const float aps[6] = {0.2094f, 0.2094f, 0.05f, 0.01f, 1e-4f, 1e-6f};
        char name[32];
        memset(b, 0, sizeof b);
        at = fz_put_u8(b, 0, 1);               /* mode 1: an exact square */
        at = fz_put_default(b, at);            /* tag size */
        at = fz_put_float(b, at, aps[i]);      /* vertical aperture */
        at = fz_put_default(b, at);            /* range sd */
        at = fz_put_default(b, at);            /* azimuth sd */
        at = fz_put_default(b, at);            /* iterations */
        at = fz_put_u8(b, at, (uint8_t)(i & 1)); /* a known plane (its defaults) */
        if (i & 1)
            at += 6;                           /* the plane's six values: defaults */
        at = fz_put_u8(b, at, (uint8_t)(i >> 1 & 1)); /* mirrored */
        at = fz_put_float(b, at, dist[i]);
        at = fz_put_float(b, at, 0.1f * (float)i);   /* azimuth */
        at = fz_put_default(b, at);                 /* elevation */
        at = fz_put_default(b, at);                 /* yaw */
        at = fz_put_float(b, at, 0.28f * (float)i); /* tilt */
        snprintf(name, sizeof name, "pose-%d", i);
        put("pose", name, b, at + 40);
    }
    /* track: default parameters, six frames of a tag moving 3 px a frame;
     * then a second tag beside it; then the first gone, a third ID come */
    for (i = 0; i < 3; i++) {
        char name[32];
        int f;
        memset(b, 0, sizeof b);
        at = 10;                                    /* ten parameters: defaults */
        at = fz_put_u8(b, at, i == 2 ? 230 : 0);    /* the frame counter (230: near its end) */
        at = fz_put_u8(b, at, 5);                   /* six frames */
        for (f = 0; f < 6; f++) {
            int two = i >= 1 && f >= 2, gone = i == 2 && f >= 4;
            at = fz_put_u8(b, at, (uint8_t)(two ? 2 : 1));
            at = fz_put_u8(b, at, (uint8_t)(gone ? 3 : 0));           /* id */
            at = fz_put_u8(b, at, (uint8_t)(20 + 3 * f));             /* x */
            at = fz_put_u8(b, at, 20);                                /* y - 40 */
            if (two) {
                at = fz_put_u8(b, at, 1);
                at = fz_put_u8(b, at, 110);
                at = fz_put_u8(b, at, 24);
            }
        }
        snprintf(name, sizeof name, "track-%d", i);
        put("track", name, b, at);
    }
}

int main(int argc, char **argv)
{
    char err[HOSTIO_ERRLEN], path[4096];
    struct stat sb;
    if (argc < 3) {
        fprintf(stderr, "usage: fuzz_make_seeds OUTDIR EXAMPLE.pgm [POOLDIR]\n");
        return 2;
    }
    g_out = argv[1];
    if (hostio_mkdirs(g_out, err) != HOSTIO_OK) {
        fprintf(stderr, "fuzz_make_seeds: %s\n", err);
        return 1;
    }
    real_frames(argv[2], argc > 3 && stat(argv[3], &sb) == 0 ? argv[3] : NULL);
    sim_frames();
    synthetic();
    hostile();
    small_seeds();
    snprintf(path, sizeof path, "%s/stamp", g_out);
    if (hostio_write_file(path, "ok\n", 3, err) != HOSTIO_OK) {
        fprintf(stderr, "fuzz_make_seeds: %s\n", err);
        return 1;
    }
    printf("fuzz_make_seeds: %d seeds in %s\n", g_count, g_out);
    return 0;
}
