/*
 * actag_detect: find AcTags in sonar frames (8/16-bit binary PGM or raw).
 *
 *   actag_detect --max-range M (--aperture-deg D | --bearings FILE) [options] FILE...
 *
 * See usage() for the options. Host-only example: uses stdio and malloc; the
 * library itself does not. Exit status 0 when every file was processed, 2
 * when an option was bad (nothing processed) or any file failed (the others
 * are still processed).
 */
#define _POSIX_C_SOURCE 200809L
#include "actag/actag.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#define PROG "actag_detect"

static void usage(FILE *f)
{
    fprintf(f,
            "usage: " PROG " [options] FILE...\n"
            "Finds AcTags in sonar frames: binary PGM (P5, 8 or 16 bit, recognised by its magic)\n"
            "or headerless raw frames (--rows/--cols). Rows are range bins, columns beams.\n"
            "Sonar geometry (required):\n"
            "  --min-range M          range of the nearest row in metres (default 0)\n"
            "  --max-range M          range of the farthest row in metres\n"
            "  --aperture-deg D       horizontal aperture in degrees, or\n"
            "  --bearings FILE        one azimuth per column in radians (whitespace separated)\n"
            "  --range-ascending      row 0 is the nearest range (default: the farthest)\n"
            "  --azimuth-ascending    column 0 is the most negative bearing (default: +aperture/2)\n"
            "Raw frames:\n"
            "  --rows R --cols C [--depth 8|16] [--stride S]  (16-bit raw is little-endian;\n"
            "                         stride in pixels, default C)\n"
            "Tags and pipeline:\n"
            "  --family NAME          tag family (default AcTag24h10)\n"
            "  --tag-size M           side of the inner white square, metres (default 0.130628571)\n"
            "  --bit-corrections N    allowed corrected bits (default: min(3, family maximum))\n"
            "  --seed N               RANSAC seed (default 1)\n"
            "  --decode fit|binary    fit (default): fit the cell grid to the filtered frame and\n"
            "                         read each bit against its neighbours; binary: the paper's\n"
            "                         reading of the binary frame\n"
            "  --search N             structure-search candidates per frame, 0 (off) to 8 (default 2)\n"
            "  --min-margin F         least decision margin (log-likelihood ratio) of a reading\n"
            "                         (default 5); --search-min-margin F for search readings (10)\n"
            "  --median-radius N      (default 4)   --threshold-radius N (default 8)\n"
            "  --threshold-offset N   (default 1)   --inlier-ratio F (default 0.8)\n"
            "  --inlier-distance F    pixels (default 2.5)  --ransac-iterations N (default 100)\n"
            "Output:\n"
            "  --json                 one JSON line per file\n"
            "  --overlay OUT.ppm      draw corners, corner numbers, IDs and sampled bits\n"
            "                         (with several files, OUT-<file>.ppm)\n"
            "  --stages DIR           write each stage's image as PGM into DIR\n"
            "  --help\n");
}

static void opt_error(const char *msg, const char *arg)
{
    fprintf(stderr, PROG ": %s%s%s\n", msg, arg ? ": " : "", arg ? arg : "");
    exit(2);
}

static double parse_double(const char *opt, const char *s)
{
    char *end;
    double v;
    errno = 0;
    v = strtod(s, &end);
    if (errno || end == s || *end != '\0' || !isfinite(v))
        opt_error("expected a number after", opt);
    return v;
}

static long parse_long(const char *opt, const char *s, long lo, long hi)
{
    char *end;
    long v;
    errno = 0;
    v = strtol(s, &end, 10);
    if (errno || end == s || *end != '\0' || v < lo || v > hi) {
        char msg[128];
        snprintf(msg, sizeof msg, "expected an integer from %ld to %ld after", lo, hi);
        opt_error(msg, opt);
    }
    return v;
}

/* ------------------------------------------------------------------ input */

typedef struct {
    void *data;
    int rows, cols, stride, depth;
} image;

/* The last per-file error, for the --json error line. */
static char last_error[256];

static int fail(const char *file, const char *what)
{
    fprintf(stderr, PROG ": %s: %s\n", file, what);
    snprintf(last_error, sizeof last_error, "%s", what);
    return -1;
}

static unsigned char *read_all(const char *path, long *len)
{
    FILE *f = fopen(path, "rb");
    unsigned char *buf;
    long n;
    if (!f)
        return NULL;
    if (fseek(f, 0, SEEK_END) != 0 || (n = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) != 0) {
        fclose(f);
        return NULL;
    }
    buf = (unsigned char *)malloc((size_t)n + 1);
    if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) {
        free(buf);
        buf = NULL;
    }
    fclose(f);
    *len = n;
    return buf;
}

/* Parses the next PGM header integer, skipping whitespace and comments. */
static long pgm_int(const unsigned char *b, long len, long *pos)
{
    long v = 0;
    int digits = 0;
    while (*pos < len) {
        if (b[*pos] == '#') {
            while (*pos < len && b[*pos] != '\n')
                (*pos)++;
        } else if (b[*pos] == ' ' || b[*pos] == '\t' || b[*pos] == '\n' || b[*pos] == '\r') {
            (*pos)++;
        } else {
            break;
        }
    }
    while (*pos < len && b[*pos] >= '0' && b[*pos] <= '9' && digits < 9) {
        v = v * 10 + (b[*pos] - '0');
        (*pos)++;
        digits++;
    }
    return digits ? v : -1;
}

static int load_image(const char *path, int raw_rows, int raw_cols, int raw_depth, int raw_stride,
                      image *im)
{
    long len, pos = 2, w, h, maxv, need, i;
    unsigned char *b = read_all(path, &len);
    if (!b)
        return fail(path, strerror(errno ? errno : EIO));
    memset(im, 0, sizeof *im);
    if (len >= 2 && b[0] == 'P' && b[1] == '5') {
        int bytes;
        w = pgm_int(b, len, &pos);
        h = pgm_int(b, len, &pos);
        maxv = pgm_int(b, len, &pos);
        if (w < 1 || h < 1 || w > ACTAG_MAX_DIM || h > ACTAG_MAX_DIM || maxv < 1 ||
            maxv > 65535 || pos >= len) {
            free(b);
            return fail(path, "bad PGM header (need P5, size 1..32767, maxval 1..65535)");
        }
        pos++; /* the single whitespace after maxval */
        bytes = maxv > 255 ? 2 : 1;
        need = w * h * bytes;
        if (len - pos < need) {
            free(b);
            return fail(path, "PGM file is shorter than its header says");
        }
        im->rows = (int)h;
        im->cols = (int)w;
        im->stride = (int)w;
        im->depth = 8 * bytes;
        im->data = malloc((size_t)need);
        if (!im->data) {
            free(b);
            return fail(path, "out of memory");
        }
        if (bytes == 1) {
            memcpy(im->data, b + pos, (size_t)need);
        } else {
            uint16_t *d = (uint16_t *)im->data;
            for (i = 0; i < w * h; i++) /* PGM 16-bit samples are big-endian */
                d[i] = (uint16_t)((b[pos + 2 * i] << 8) | b[pos + 2 * i + 1]);
        }
    } else if (len >= 2 && b[0] == 'P' && b[1] >= '1' && b[1] <= '7') {
        free(b);
        return fail(path, "only binary PGM (P5) images are supported");
    } else {
        int bytes = raw_depth / 8, stride = raw_stride ? raw_stride : raw_cols;
        long minimum, full;
        if (raw_rows <= 0 || raw_cols <= 0) {
            free(b);
            return fail(path, "not a PGM file; raw frames need --rows and --cols");
        }
        if (stride < raw_cols) {
            free(b);
            return fail(path, "--stride is smaller than --cols");
        }
        minimum = ((long)(raw_rows - 1) * stride + raw_cols) * bytes;
        full = (long)raw_rows * stride * bytes;
        if (len < minimum || len > full) {
            char msg[160];
            snprintf(msg, sizeof msg, "raw frame is %ld bytes, expected %ld (rows x stride x %d)",
                     len, full, bytes);
            free(b);
            return fail(path, msg);
        }
        im->rows = raw_rows;
        im->cols = raw_cols;
        im->stride = stride;
        im->depth = raw_depth;
        im->data = calloc((size_t)full, 1);
        if (!im->data) {
            free(b);
            return fail(path, "out of memory");
        }
        if (bytes == 1) {
            memcpy(im->data, b, (size_t)len);
        } else {
            uint16_t *d = (uint16_t *)im->data;
            for (i = 0; i < len / 2; i++)
                d[i] = (uint16_t)(b[2 * i] | (b[2 * i + 1] << 8));
        }
    }
    free(b);
    return 0;
}

static int load_bearings(const char *path, int cols, float *out)
{
    FILE *f = fopen(path, "r");
    int n = 0;
    double v;
    if (!f)
        return fail(path, strerror(errno));
    while (n < cols && fscanf(f, "%lf", &v) == 1)
        out[n++] = (float)v;
    if (n == cols && fscanf(f, "%lf", &v) == 1)
        n++;
    fclose(f);
    if (n != cols) {
        char msg[128];
        snprintf(msg, sizeof msg, "bearing table has %s%d values, the frame has %d columns",
                 n > cols ? "more than " : "", n > cols ? cols : n, cols);
        return fail(path, msg);
    }
    return 0;
}

/* ----------------------------------------------------------------- output */

static const char *base_name(const char *p)
{
    const char *s = strrchr(p, '/');
    return s ? s + 1 : p;
}

static void json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            fprintf(f, "\\%c", c);
        else if (c < 0x20)
            fprintf(f, "\\u%04x", c);
        else
            fputc(c, f);
    }
    fputc('"', f);
}

/* In --json mode every input file gets exactly one line, errors included. */
static void json_error(int json, const char *file)
{
    if (!json)
        return;
    printf("{\"file\": ");
    json_string(stdout, file);
    printf(", \"error\": ");
    json_string(stdout, last_error);
    printf("}\n");
    fflush(stdout);
}

static uint8_t grey8(const image *im, int r, int c, uint32_t maxv)
{
    if (im->depth == 8)
        return ((const uint8_t *)im->data)[(size_t)r * (size_t)im->stride + (size_t)c];
    return (uint8_t)(maxv ? ((uint32_t)((const uint16_t *)im->data)[(size_t)r * (size_t)im->stride +
                                                                     (size_t)c] *
                             255u) /
                                maxv
                          : 0u);
}

static int write_pgm(const char *path, const uint8_t *px, int rows, int cols, int binary)
{
    FILE *f = fopen(path, "wb");
    int i, n = rows * cols;
    if (!f)
        return fail(path, "cannot write");
    fprintf(f, "P5\n%d %d\n255\n", cols, rows);
    for (i = 0; i < n; i++)
        fputc(binary ? (px[i] ? 255 : 0) : px[i], f);
    return fclose(f) == 0 ? 0 : fail(path, "write error");
}

typedef struct {
    uint8_t *rgb;
    int rows, cols;
} canvas;

static void put(canvas *cv, int x, int y, uint8_t r, uint8_t g, uint8_t b)
{
    uint8_t *p;
    if (x < 0 || y < 0 || x >= cv->cols || y >= cv->rows)
        return;
    p = cv->rgb + 3 * ((size_t)y * (size_t)cv->cols + (size_t)x);
    p[0] = r;
    p[1] = g;
    p[2] = b;
}

static void line(canvas *cv, actag_point a, actag_point b, uint8_t r, uint8_t g, uint8_t bl)
{
    float dx = b.x - a.x, dy = b.y - a.y;
    int n = (int)(fabsf(dx) > fabsf(dy) ? fabsf(dx) : fabsf(dy)) + 1, i;
    for (i = 0; i <= n; i++) {
        float t = (float)i / (float)n;
        put(cv, (int)lroundf(a.x + t * dx), (int)lroundf(a.y + t * dy), r, g, bl);
    }
}

/* 3x5 digits, one row per 3 bits. */
static const unsigned char font[10][5] = {
    {7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7}, {5, 5, 7, 1, 1},
    {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1}, {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7}};

static void text(canvas *cv, int x, int y, const char *s, int scale, uint8_t r, uint8_t g,
                 uint8_t b)
{
    for (; *s; s++, x += 4 * scale) {
        int row, col, sy, sx;
        if (*s < '0' || *s > '9')
            continue;
        for (row = 0; row < 5; row++)
            for (col = 0; col < 3; col++)
                if (font[*s - '0'][row] & (4 >> col))
                    for (sy = 0; sy < scale; sy++)
                        for (sx = 0; sx < scale; sx++)
                            put(cv, x + col * scale + sx, y + row * scale + sy, r, g, b);
    }
}

static int write_overlay(const char *path, const image *im, const uint8_t *binary,
                         const actag_detection *det, int n, const actag_family *fam)
{
    canvas cv;
    FILE *f;
    int i, r, c;
    uint32_t maxv = 0;
    cv.rows = im->rows;
    cv.cols = im->cols;
    cv.rgb = (uint8_t *)malloc((size_t)im->rows * (size_t)im->cols * 3u);
    if (!cv.rgb)
        return fail(path, "out of memory");
    if (im->depth == 16)
        for (r = 0; r < im->rows; r++)
            for (c = 0; c < im->cols; c++) {
                uint32_t v = ((const uint16_t *)im->data)[(size_t)r * (size_t)im->stride + (size_t)c];
                if (v > maxv)
                    maxv = v;
            }
    for (r = 0; r < im->rows; r++)
        for (c = 0; c < im->cols; c++) {
            uint8_t g = grey8(im, r, c, maxv);
            put(&cv, c, r, g, g, g);
        }
    for (i = 0; i < n; i++) {
        actag_point bitpos[32];
        char buf[16];
        int k;
        for (k = 0; k < 4; k++)
            line(&cv, det[i].corners[k], det[i].corners[(k + 1) % 4], 0, 255, 0);
        if (actag_decode_bit_positions(det[i].corners, fam->bits, bitpos) == ACTAG_OK)
            for (k = 0; k < fam->bits; k++) {
                int x = (int)lroundf(bitpos[k].x), y = (int)lroundf(bitpos[k].y), on;
                on = x >= 0 && y >= 0 && x < im->cols && y < im->rows &&
                     binary[(size_t)y * (size_t)im->cols + (size_t)x];
                put(&cv, x, y, on ? 255 : 0, on ? 255 : 128, on ? 0 : 255);
                put(&cv, x + 1, y, on ? 255 : 0, on ? 255 : 128, on ? 0 : 255);
                put(&cv, x, y + 1, on ? 255 : 0, on ? 255 : 128, on ? 0 : 255);
                put(&cv, x + 1, y + 1, on ? 255 : 0, on ? 255 : 128, on ? 0 : 255);
            }
        for (k = 0; k < 4; k++) {
            int x = (int)lroundf(det[i].corners[k].x), y = (int)lroundf(det[i].corners[k].y), d;
            for (d = -2; d <= 2; d++) {
                put(&cv, x + d, y, 255, 0, 0);
                put(&cv, x, y + d, 255, 0, 0);
            }
            snprintf(buf, sizeof buf, "%d", k);
            text(&cv, x + 3, y + 3, buf, 1, 255, 64, 64);
        }
        {
            actag_point m;
            m.x = 0.25f * (det[i].corners[0].x + det[i].corners[1].x + det[i].corners[2].x +
                           det[i].corners[3].x);
            m.y = 0.25f * (det[i].corners[0].y + det[i].corners[1].y + det[i].corners[2].y +
                           det[i].corners[3].y);
            snprintf(buf, sizeof buf, "%d", det[i].id);
            text(&cv, (int)m.x - 4, (int)m.y - 5, buf, 2, 0, 255, 255);
        }
    }
    f = fopen(path, "wb");
    if (!f) {
        free(cv.rgb);
        return fail(path, "cannot write overlay");
    }
    fprintf(f, "P6\n%d %d\n255\n", cv.cols, cv.rows);
    fwrite(cv.rgb, 3, (size_t)cv.rows * (size_t)cv.cols, f);
    free(cv.rgb);
    return fclose(f) == 0 ? 0 : fail(path, "write error");
}

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

/* ------------------------------------------------------------------- main */

int main(int argc, char **argv)
{
    actag_sonar_geometry geo;
    actag_params params;
    actag_family fam;
    const char *family_name = "AcTag24h10", *bearings_path = NULL, *overlay = NULL,
               *stages = NULL;
    int raw_rows = 0, raw_cols = 0, raw_depth = 8, raw_stride = 0, json = 0, i, status = 0;
    int nfiles = 0, have_max = 0, have_aperture = 0;
    double aperture_deg = 0;
    const char **files = (const char **)calloc((size_t)argc, sizeof(char *));

    if (!files)
        opt_error("out of memory", NULL);
    memset(&geo, 0, sizeof geo);
    actag_params_default(&params);
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = (i + 1 < argc) ? argv[i + 1] : NULL;
#define NEEDV()                                                                                   \
    do {                                                                                          \
        if (!v)                                                                                   \
            opt_error("missing value after", a);                                                  \
        i++;                                                                                      \
    } while (0)
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            return 0;
        } else if (strcmp(a, "--json") == 0) {
            json = 1;
        } else if (strcmp(a, "--range-ascending") == 0) {
            geo.flags |= ACTAG_RANGE_ASCENDING;
        } else if (strcmp(a, "--azimuth-ascending") == 0) {
            geo.flags |= ACTAG_AZIMUTH_ASCENDING;
        } else if (strcmp(a, "--min-range") == 0) {
            NEEDV();
            geo.min_range = (float)parse_double(a, v);
        } else if (strcmp(a, "--max-range") == 0) {
            NEEDV();
            geo.max_range = (float)parse_double(a, v);
            have_max = 1;
        } else if (strcmp(a, "--aperture-deg") == 0) {
            NEEDV();
            aperture_deg = parse_double(a, v);
            have_aperture = 1;
        } else if (strcmp(a, "--bearings") == 0) {
            NEEDV();
            bearings_path = v;
        } else if (strcmp(a, "--rows") == 0) {
            NEEDV();
            raw_rows = (int)parse_long(a, v, 1, ACTAG_MAX_DIM);
        } else if (strcmp(a, "--cols") == 0) {
            NEEDV();
            raw_cols = (int)parse_long(a, v, 1, ACTAG_MAX_DIM);
        } else if (strcmp(a, "--depth") == 0) {
            NEEDV();
            raw_depth = (int)parse_long(a, v, 8, 16);
            if (raw_depth != 8 && raw_depth != 16)
                opt_error("--depth must be 8 or 16", v);
        } else if (strcmp(a, "--stride") == 0) {
            NEEDV();
            raw_stride = (int)parse_long(a, v, 1, 1 << 20);
        } else if (strcmp(a, "--family") == 0) {
            NEEDV();
            family_name = v;
        } else if (strcmp(a, "--tag-size") == 0) {
            NEEDV();
            params.tag_size = (float)parse_double(a, v);
        } else if (strcmp(a, "--bit-corrections") == 0) {
            NEEDV();
            params.max_bit_corrections = (int)parse_long(a, v, 0, 64);
        } else if (strcmp(a, "--decode") == 0) {
            NEEDV();
            if (strcmp(v, "binary") == 0)
                params.decode_mode = ACTAG_DECODE_BINARY;
            else if (strcmp(v, "fit") == 0)
                params.decode_mode = ACTAG_DECODE_FIT;
            else
                opt_error("--decode takes fit or binary", v);
        } else if (strcmp(a, "--search") == 0) {
            NEEDV();
            params.search_candidates = (int)parse_long(a, v, 0, ACTAG_SEARCH_MAX);
        } else if (strcmp(a, "--min-structure") == 0) {
            NEEDV();
            params.min_structure = (float)parse_double(a, v);
        } else if (strcmp(a, "--min-side-fraction") == 0) {
            NEEDV();
            params.min_side_fraction = (float)parse_double(a, v);
        } else if (strcmp(a, "--min-margin") == 0) {
            NEEDV();
            params.fit.min_margin = (float)parse_double(a, v);
        } else if (strcmp(a, "--search-min-margin") == 0) {
            NEEDV();
            params.search_min_margin = (float)parse_double(a, v);
        } else if (strcmp(a, "--seed") == 0) {
            NEEDV();
            params.seed = (uint32_t)parse_long(a, v, 0, 4294967295L);
        } else if (strcmp(a, "--median-radius") == 0) {
            NEEDV();
            params.median_radius = (int)parse_long(a, v, 0, ACTAG_MEDIAN_MAX_RADIUS);
        } else if (strcmp(a, "--threshold-radius") == 0) {
            NEEDV();
            params.threshold_radius = (int)parse_long(a, v, 0, ACTAG_MAX_DIM);
        } else if (strcmp(a, "--threshold-offset") == 0) {
            NEEDV();
            params.threshold_offset = (int)parse_long(a, v, -255, 255);
        } else if (strcmp(a, "--inlier-ratio") == 0) {
            NEEDV();
            params.quad.inlier_ratio = (float)parse_double(a, v);
        } else if (strcmp(a, "--inlier-distance") == 0) {
            NEEDV();
            params.quad.inlier_distance = (float)parse_double(a, v);
        } else if (strcmp(a, "--ransac-iterations") == 0) {
            NEEDV();
            params.quad.max_iterations = (int)parse_long(a, v, 1, 1000000);
        } else if (strcmp(a, "--overlay") == 0) {
            NEEDV();
            overlay = v;
        } else if (strcmp(a, "--stages") == 0) {
            NEEDV();
            stages = v;
        } else if (a[0] == '-' && a[1] != '\0') {
            fprintf(stderr, PROG ": unknown option %s (see --help)\n", a);
            return 2;
        } else {
            files[nfiles++] = a;
        }
#undef NEEDV
    }
    if (nfiles == 0) {
        fprintf(stderr, PROG ": no input files (see --help)\n");
        return 2;
    }
    if (!have_max)
        opt_error("--max-range is required", NULL);
    if (!have_aperture && !bearings_path)
        opt_error("--aperture-deg or --bearings is required", NULL);
    geo.aperture = (float)(aperture_deg * 3.14159265358979323846 / 180.0);
    if (actag_family_get(family_name, &fam) != ACTAG_OK) {
        fprintf(stderr, PROG ": unknown family %s (built in:", family_name);
        for (i = 0; i < actag_family_count(); i++) {
            actag_family f;
            actag_family_get_at(i, &f);
            fprintf(stderr, " %s", f.name);
        }
        fprintf(stderr, ")\n");
        return 2;
    }
    params.family = &fam;
    {
        int rc = actag_params_validate(&params);
        if (rc != ACTAG_OK) {
            fprintf(stderr, PROG ": bad parameters: %s (family %s allows at most %d bit corrections)\n",
                    actag_strerror(rc), fam.name, actag_family_max_corrections(&fam));
            return 2;
        }
    }
    if (stages) {
        struct stat sb;
        if (stat(stages, &sb) != 0 || !S_ISDIR(sb.st_mode))
            opt_error("--stages needs an existing directory", stages);
    }

    for (i = 0; i < nfiles; i++) {
        image im;
        actag_frame fr;
        actag_detection det[64];
        actag_stats st;
        float *bearings = NULL;
        void *ws;
        size_t wsize;
        double t0, t1;
        int n, k;
        const char *file = files[i];

        if (load_image(file, raw_rows, raw_cols, raw_depth, raw_stride, &im) != 0) {
            json_error(json, file);
            status = 2;
            continue;
        }
        geo.bearings = NULL;
        if (bearings_path) {
            bearings = (float *)malloc((size_t)im.cols * sizeof(float));
            if (!bearings || load_bearings(bearings_path, im.cols, bearings) != 0) {
                json_error(json, file);
                free(bearings);
                free(im.data);
                status = 2;
                continue;
            }
            geo.bearings = bearings;
        }
        wsize = actag_workspace_size(im.rows, im.cols);
        ws = malloc(wsize);
        if (!ws) {
            fail(file, "out of memory for the workspace");
            json_error(json, file);
            free(bearings);
            free(im.data);
            status = 2;
            continue;
        }
        fr.data = im.data;
        fr.rows = im.rows;
        fr.cols = im.cols;
        fr.stride = im.stride;
        fr.depth = im.depth;
        t0 = now_ms();
        n = actag_detect(&fr, &geo, &params, ws, wsize, det, 64, &st);
        t1 = now_ms();
        if (n < 0) {
            fail(file, actag_strerror(n));
            json_error(json, file);
            status = 2;
        } else if (json) {
            printf("{\"file\": ");
            json_string(stdout, file);
            printf(", \"rows\": %d, \"cols\": %d, \"detections\": [", im.rows, im.cols);
            for (k = 0; k < n; k++) {
                int c;
                printf("%s{\"id\": %d, \"hamming\": %d, \"decision_margin\": %.2f, "
                       "\"mirrored\": %s, \"corners_px\": [",
                       k ? ", " : "", det[k].id, det[k].hamming, (double)det[k].decision_margin,
                       det[k].mirrored ? "true" : "false");
                for (c = 0; c < 4; c++)
                    printf("%s[%.3f, %.3f]", c ? ", " : "", (double)det[k].corners[c].y,
                           (double)det[k].corners[c].x);
                printf("], \"corners_polar\": [");
                for (c = 0; c < 4; c++)
                    printf("%s[%.5f, %.5f]", c ? ", " : "", (double)det[k].range[c],
                           (double)det[k].azimuth[c]);
                printf("]}");
            }
            printf("], \"time_ms\": %.3f}\n", t1 - t0);
        } else {
            if (n == 0)
                printf("%s: no tags (%.2f ms)\n", file, t1 - t0);
            for (k = 0; k < n; k++) {
                int c;
                printf("%s: %s id %d hamming %d margin %.1f%s corners (row,col | range m,azimuth rad):",
                       file, fam.name, det[k].id, det[k].hamming,
                       (double)det[k].decision_margin, det[k].mirrored ? " mirrored" : "");
                for (c = 0; c < 4; c++)
                    printf(" (%.1f,%.1f | %.4f,%.4f)", (double)det[k].corners[c].y,
                           (double)det[k].corners[c].x, (double)det[k].range[c],
                           (double)det[k].azimuth[c]);
                printf(" (%.2f ms)\n", t1 - t0);
            }
        }
        if (n >= 0 && st.dropped > 0)
            fprintf(stderr, PROG ": %s: %d more tags than the 64 reported\n", file, st.dropped);
        if (n >= 0 && overlay) {
            char path[4096];
            if (nfiles == 1) {
                snprintf(path, sizeof path, "%s", overlay);
            } else {
                const char *dot = strrchr(overlay, '.');
                int stem = dot ? (int)(dot - overlay) : (int)strlen(overlay);
                snprintf(path, sizeof path, "%.*s-%s.ppm", stem, overlay, base_name(file));
            }
            if (write_overlay(path, &im, actag_workspace_binary(ws, im.rows, im.cols), det, n,
                              &fam) != 0)
                status = 2;
        }
        if (n >= 0 && stages) {
            char path[4096];
            uint8_t *in8 = (uint8_t *)malloc((size_t)im.rows * (size_t)im.cols);
            int r, c;
            uint32_t maxv = 0;
            if (in8) {
                if (im.depth == 16)
                    for (r = 0; r < im.rows; r++)
                        for (c = 0; c < im.cols; c++) {
                            uint32_t v = ((const uint16_t *)im.data)[(size_t)r * (size_t)im.stride + (size_t)c];
                            if (v > maxv)
                                maxv = v;
                        }
                for (r = 0; r < im.rows; r++)
                    for (c = 0; c < im.cols; c++)
                        in8[(size_t)r * (size_t)im.cols + (size_t)c] = grey8(&im, r, c, maxv);
                snprintf(path, sizeof path, "%s/%s-1-input.pgm", stages, base_name(file));
                if (write_pgm(path, in8, im.rows, im.cols, 0) != 0)
                    status = 2;
                free(in8);
            }
            snprintf(path, sizeof path, "%s/%s-2-median.pgm", stages, base_name(file));
            if (write_pgm(path, actag_workspace_filtered(ws, im.rows, im.cols), im.rows, im.cols,
                          0) != 0)
                status = 2;
            snprintf(path, sizeof path, "%s/%s-3-threshold.pgm", stages, base_name(file));
            if (write_pgm(path, actag_workspace_binary(ws, im.rows, im.cols), im.rows, im.cols,
                          1) != 0)
                status = 2;
        }
        fflush(stdout);
        free(ws);
        free(bearings);
        free(im.data);
    }
    free(files);
    return status;
}
