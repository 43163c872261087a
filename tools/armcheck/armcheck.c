/*
 * armcheck.c -- same input and seed, same output, on x86 and on ARM.
 *
 * Runs actag_detect() on a few real sonar frames with fixed parameters and
 * writes a report: every detection (id, hamming, mirrored, corners, range,
 * azimuth, inlier ratio) and its sonar pose (actag_pose_from_detection:
 * position, rotation, elevation band, residual, flags) with floats as C99
 * hex floats (exact), the call's counters, and FNV-1a 64-bit digests of the
 * raw detection and pose structs and of the workspace's filtered and binary
 * stage images; then the frame goes on, in the order given, through a
 * tracker (actag/track.h, default settings; the frames of one folder are
 * one stream, a new folder starts a new tracker): its confirmed tracks
 * (smoothed corners, range, azimuth, velocity, counters) and the sonar pose
 * of each track's smoothed corners, the same way. The same file is built
 * natively (io_host.c) and for a Cortex-M (io_semihost.c and the board
 * support's boards/qemu-mps2/startup.c, run under QEMU); .ci/armcheck
 * requires the two reports to be byte-identical.
 *
 * The report is formatted here without printf, so both builds use the same
 * formatting code (newlib's and glibc's printf need not agree on "%a"); the
 * host build checks every hex float against its printf("%a").
 *
 * usage: armcheck OUT_REPORT SONAR_DATA_DIR [FRAME.pgm ...]
 *   SONAR_DATA_DIR is shared/data/sonar; frames are relative to it
 *   (default: example/exampleSonarImage.pgm and pool-video f_0001, f_0291,
 *   f_0561). Exit status 0 when every frame was read and every call
 *   returned >= 0.
 */
#include "actag/actag.h"
#include "actag/pose.h"
#include "actag/track.h"
#include "actag/version.h" /* generated: the build passes -I<build>/include */
#include "armcheck_io.h"

#include <string.h>
#ifdef ARMCHECK_HOST
#include <stdio.h>
#endif

/* Largest frames: 463 x 620 (example) and 530 x 512 (pool video). */
#define AC_MAX_ROWS 530
#define AC_MAX_COLS 620
#define AC_FILE_CAP ((size_t)AC_MAX_ROWS * AC_MAX_COLS + 256u)
#define AC_MAX_DET 16

static uint8_t ac_ws[ACTAG_WORKSPACE_SIZE(AC_MAX_ROWS, AC_MAX_COLS)];
static unsigned char ac_file[AC_FILE_CAP];
static actag_detection ac_det[AC_MAX_DET];
static actag_pose ac_pose[AC_MAX_DET];
/* the frames of one recording (one folder), in the order given, as one
 * stream through a tracker; a frame from another folder starts a new one */
static actag_tracker ac_tracker;
static actag_track ac_tracks[ACTAG_TRACK_MAX];
static actag_pose ac_track_pose[ACTAG_TRACK_MAX];
static char ac_stream[128];
/* The pose's vertical aperture (rad): 20 degrees, a typical imaging sonar's
 * (the pool recording's is not published; any aperture exercises the same
 * arithmetic). */
#define AC_VERTICAL_APERTURE 0.34906585f

static const char *const ac_default_frames[] = {
    "example/exampleSonarImage.pgm",
    "pool-video/f_0001.pgm",
    "pool-video/f_0291.pgm",
    "pool-video/f_0561.pgm",
};

/* ------------------------------------------------------------ report text */

static char ac_line[512];
static size_t ac_len;
static int ac_failed;

static void put_s(const char *s)
{
    while (*s != '\0' && ac_len < sizeof ac_line - 1)
        ac_line[ac_len++] = *s++;
}

static void put_u(unsigned long v)
{
    char t[24];
    int n = 0;
    do {
        t[n++] = (char)('0' + (int)(v % 10u));
        v /= 10u;
    } while (v != 0u);
    while (n > 0 && ac_len < sizeof ac_line - 1)
        ac_line[ac_len++] = t[--n];
}

static void put_d(long v)
{
    if (v < 0) {
        put_s("-");
        put_u(0ul - (unsigned long)v);
    } else {
        put_u((unsigned long)v);
    }
}

static void put_x64(uint64_t v)
{
    static const char hex[] = "0123456789abcdef";
    char t[17];
    int i;
    for (i = 15; i >= 0; i--) {
        t[i] = hex[v & 15u];
        v >>= 4;
    }
    t[16] = '\0';
    put_s(t);
}

/* A float as glibc prints the double it promotes to with "%a"
 * ([-]0x1.hhhhhhp[+-]d, 0x0p+0, inf, nan): exact, from its bits. */
static void fmt_hexfloat(float f, char *out)
{
    static const char hex[] = "0123456789abcdef";
    uint32_t b, mant;
    int e, exp2, i, n, last;
    char *p = out;
    char digits[8];
    memcpy(&b, &f, sizeof b);
    mant = b & 0x7FFFFFu;
    e = (int)((b >> 23) & 0xFFu);
    if (b >> 31)
        *p++ = '-';
    if (e == 0xFF) {
        strcpy(p, mant ? "nan" : "inf");
        return;
    }
    if (e == 0 && mant == 0) {
        strcpy(p, "0x0p+0");
        return;
    }
    if (e == 0) { /* subnormal float, normal as a double: normalise */
        int top = 22;
        while (!(mant & (1u << top)))
            top--;
        exp2 = top - 149;
        mant = (mant << (23 - top)) & 0x7FFFFFu;
    } else {
        exp2 = e - 127;
    }
    /* 23 fraction bits, left-aligned in 6 hex digits (24 bits) */
    mant <<= 1;
    last = -1;
    for (i = 0; i < 6; i++) {
        digits[i] = hex[(mant >> (20 - 4 * i)) & 15u];
        if (digits[i] != '0')
            last = i;
    }
    *p++ = '0';
    *p++ = 'x';
    *p++ = '1';
    if (last >= 0) {
        *p++ = '.';
        for (i = 0; i <= last; i++)
            *p++ = digits[i];
    }
    *p++ = 'p';
    *p++ = exp2 < 0 ? '-' : '+';
    n = exp2 < 0 ? -exp2 : exp2;
    {
        char t[8];
        int k = 0;
        do {
            t[k++] = (char)('0' + n % 10);
            n /= 10;
        } while (n != 0);
        while (k > 0)
            *p++ = t[--k];
    }
    *p = '\0';
}

static void put_f(float f)
{
    char t[32];
    fmt_hexfloat(f, t);
#ifdef ARMCHECK_HOST
    {
        char ref[64];
        snprintf(ref, sizeof ref, "%a", (double)f);
        if (strcmp(ref, t) != 0) {
            fprintf(stderr, "armcheck: hex float formatter: %s, printf: %s\n", t, ref);
            ac_failed = 1;
        }
    }
#endif
    put_s(t);
}

/* " name value": one field of a report line */
static void put_kd(const char *name, long v)
{
    put_s(" ");
    put_s(name);
    put_s(" ");
    put_d(v);
}

static void put_ku(const char *name, unsigned long v)
{
    put_s(" ");
    put_s(name);
    put_s(" ");
    put_u(v);
}

static void put_kf(const char *name, float v)
{
    put_s(" ");
    put_s(name);
    put_s(" ");
    put_f(v);
}

/* " v0 v1 ...": n floats, each after a space */
static void put_floats(const float *v, int n)
{
    int i;
    for (i = 0; i < n; i++) {
        put_s(" ");
        put_f(v[i]);
    }
}

static void end_line(void)
{
    ac_line[ac_len++] = '\n';
    if (ac_out_write(ac_line, ac_len) != 0)
        ac_failed = 1;
    ac_len = 0;
}

/* ------------------------------------------------------------ digests */

#define FNV_OFFSET 0xcbf29ce484222325ull
#define FNV_PRIME 0x100000001b3ull

static uint64_t fnv1a(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = (const unsigned char *)data;
    size_t i;
    for (i = 0; i < n; i++) {
        h ^= p[i];
        h *= FNV_PRIME;
    }
    return h;
}

/* ------------------------------------------------------------ frames */

/* Binary 8-bit PGM (P5, maxval <= 255). Returns the pixel offset in buf. */
static long parse_pgm(const unsigned char *buf, long len, int *rows, int *cols)
{
    long i = 2;
    int field, v[3];
    if (len < 2 || buf[0] != 'P' || buf[1] != '5')
        return -1;
    for (field = 0; field < 3; field++) {
        for (;;) {
            if (i >= len)
                return -1;
            if (buf[i] == '#') {
                while (i < len && buf[i] != '\n')
                    i++;
            } else if (buf[i] == ' ' || buf[i] == '\t' || buf[i] == '\n' || buf[i] == '\r') {
                i++;
            } else {
                break;
            }
        }
        if (buf[i] < '0' || buf[i] > '9')
            return -1;
        v[field] = 0;
        while (i < len && buf[i] >= '0' && buf[i] <= '9' && v[field] < 100000)
            v[field] = v[field] * 10 + (buf[i++] - '0');
    }
    i++; /* the single whitespace after maxval */
    if (v[2] < 1 || v[2] > 255 || v[0] < 1 || v[1] < 1 || v[0] > AC_MAX_COLS ||
        v[1] > AC_MAX_ROWS || len - i < (long)v[0] * v[1])
        return -1;
    *cols = v[0];
    *rows = v[1];
    return i;
}

/* ------------------------------------------------------------ runs */

/* Parameter sets: actag_params_default() (family AcTag24h10) with these
 * changes. "corrections4" makes detections happen on the sample frames;
 * "binary4" also runs the paper's binary decoder; "far4" reads the frames
 * as if they spanned 0.1-5 m, so the median's radius changes with range
 * (bands of radius 2, 3 and 4, median_bands.h) and the banded filter and
 * everything after it are compared too. */
typedef struct {
    const char *name;
    int max_bit_corrections;
    int decode_mode; /* -1: the default */
    float max_range; /* 0: the frames' own */
} ac_setting;

static const ac_setting ac_settings[] = {
    {"defaults", 0, -1, 0.0f},
    {"corrections4", 4, -1, 0.0f},
    {"binary4", 4, ACTAG_DECODE_BINARY, 0.0f},
    {"far4", 4, -1, 5.0f},
};

/* "  corner K x X y Y range R azimuth A" (the line left open: a track adds
 * its velocity) */
static void put_corner(int k, actag_point c, float range, float azimuth)
{
    put_s("  corner ");
    put_d(k);
    put_kf("x", c.x);
    put_kf("y", c.y);
    put_kf("range", range);
    put_kf("azimuth", azimuth);
}

/* A pose's result line (prefix, result, flags, iterations) and its
 * values: centre, elevation and band, residual, chi2, rotation. */
static void put_pose(const char *prefix, int rc, const actag_pose *q)
{
    put_s(prefix);
    put_s("result ");
    put_d(rc);
    put_ku("flags", q->flags);
    put_kd("iterations", q->iterations);
    end_line();
    put_s("  t");
    put_floats(q->t, 3);
    put_kf("elevation", q->elevation);
    put_kf("band", q->elevation_lo);
    put_s(" ");
    put_f(q->elevation_hi);
    put_kf("residual", q->residual);
    put_kf("chi2", q->chi2);
    end_line();
    put_s("  R");
    put_floats(q->R, 9);
    end_line();
}

/* The frame fed to the tracker (default parameters, the stream's next
 * frame): its confirmed tracks and their poses into the report. */
static uint64_t track_frame(const char *rel, const actag_frame *frame,
                            const actag_sonar_geometry *geo, const actag_family *fam,
                            uint64_t total)
{
    actag_params p;
    actag_track_stats st;
    int n, i, k;
    uint64_t ht, hp;
    const char *slash = strrchr(rel, '/');
    size_t dlen = slash ? (size_t)(slash - rel) : 0u;
    if (dlen >= sizeof ac_stream)
        dlen = sizeof ac_stream - 1u;
    if (strlen(ac_stream) != dlen || strncmp(ac_stream, rel, dlen) != 0) {
        /* another recording: a stream of its own */
        actag_track_params tp;
        actag_track_params_default(&tp);
        /* the coasting reports too (not a default): more to compare */
        tp.report_coasting = 1;
        memcpy(ac_stream, rel, dlen);
        ac_stream[dlen] = '\0';
        if (actag_tracker_init(&ac_tracker, &tp) != ACTAG_OK) {
            put_s("tracker init error");
            end_line();
            ac_failed = 1;
        }
        put_s("track stream ");
        put_s(dlen ? ac_stream : ".");
        end_line();
    }
    actag_params_default(&p);
    p.family = fam;
    memset(ac_tracks, 0, sizeof ac_tracks); /* no stale bytes in the digest */
    memset(&st, 0, sizeof st);
    n = actag_tracker_update(&ac_tracker, frame, geo, &p, NULL, ac_ws, sizeof ac_ws, ac_tracks,
                             ACTAG_TRACK_MAX, &st);
    put_s("track frame ");
    put_d(ac_tracker.frame - 1);
    put_kd("result", n);
    end_line();
    if (n < 0) {
        put_s("error ");
        put_s(actag_strerror(n));
        end_line();
        ac_failed = 1;
        return fnv1a(total, &n, sizeof n);
    }
    put_s("track stats full_frame ");
    put_d(st.full_frame);
    put_kd("rois", st.rois);
    put_kd("pixels", st.pixels);
    put_kd("readings", st.readings);
    put_kd("conflicts", st.conflicts);
    put_kd("verified", st.verified);
    put_kd("started", st.started);
    put_kd("confirmed", st.confirmed);
    put_kd("dropped", st.dropped);
    put_kd("quads", st.quads);
    put_kd("decoded", st.decoded);
    put_kd("searched", st.searched);
    end_line();
    memset(ac_track_pose, 0, sizeof ac_track_pose);
    for (i = 0; i < n; i++) {
        const actag_track *t = &ac_tracks[i];
        actag_pose_params pp;
        int prc;
        put_s("track ");
        put_u(t->track_id);
        put_kd("id", t->id);
        put_kd("mirrored", t->mirrored);
        put_kd("measured", t->measured);
        put_kd("hits", t->hits);
        put_kd("missed", t->missed);
        put_kd("age", t->age);
        put_kf("innovation", t->innovation);
        end_line();
        for (k = 0; k < 4; k++) {
            put_corner(k, t->corners[k], t->range[k], t->azimuth[k]);
            put_kf("velocity", t->velocity[k].x);
            put_s(" ");
            put_f(t->velocity[k].y);
            end_line();
        }
        /* the pose of the smoothed corners */
        actag_pose_params_default(&pp, fam, p.tag_size, AC_VERTICAL_APERTURE);
        prc = actag_pose_estimate(t->range, t->azimuth, t->mirrored, &pp, &ac_track_pose[i]);
        put_pose("  pose ", prc, &ac_track_pose[i]);
    }
    ht = fnv1a(FNV_OFFSET, ac_tracks, (size_t)n * sizeof ac_tracks[0]);
    hp = fnv1a(FNV_OFFSET, ac_track_pose, (size_t)n * sizeof ac_track_pose[0]);
    put_s("digest tracks ");
    put_x64(ht);
    put_s(" poses ");
    put_x64(hp);
    end_line();
    total = fnv1a(total, &ht, sizeof ht);
    return fnv1a(total, &hp, sizeof hp);
}

static uint64_t run_frame(const char *data_dir, const char *rel, const actag_family *fam,
                          uint64_t total)
{
    char path[384];
    long len, off;
    int rows = 0, cols = 0;
    size_t si;
    actag_frame frame;
    actag_sonar_geometry geo;

    if (strlen(data_dir) + strlen(rel) + 2 > sizeof path) {
        ac_log("armcheck: path too long\n");
        ac_failed = 1;
        return total;
    }
    strcpy(path, data_dir);
    strcat(path, "/");
    strcat(path, rel);
    len = ac_read_file(path, ac_file, sizeof ac_file);
    off = len < 0 ? -1 : parse_pgm(ac_file, len, &rows, &cols);
    put_s("frame ");
    put_s(rel);
    if (off < 0) {
        put_s(" unreadable");
        end_line();
        ac_log("armcheck: cannot read frame ");
        ac_log(path);
        ac_log("\n");
        ac_failed = 1;
        return fnv1a(total, "unreadable", 10);
    }
    frame.data = ac_file + off;
    frame.rows = rows;
    frame.cols = cols;
    frame.stride = cols;
    frame.depth = 8;
    put_kd("rows", rows);
    put_kd("cols", cols);
    put_s(" fnv ");
    put_x64(fnv1a(FNV_OFFSET, frame.data, (size_t)rows * (size_t)cols));
    end_line();

    /* data/README: every frame 0.1 .. 1.5 m, 60 degree aperture */
    geo.min_range = 0.1f;
    geo.max_range = 1.5f;
    geo.aperture = 1.0472f;
    geo.bearings = NULL;
    geo.flags = 0;

    for (si = 0; si < sizeof ac_settings / sizeof ac_settings[0]; si++) {
        actag_params p;
        actag_stats st;
        actag_sonar_geometry g = geo;
        int n, i, k;
        uint64_t hd, hf, hb, hp;
        const uint8_t *img;

        if (ac_settings[si].max_range > 0.0f)
            g.max_range = ac_settings[si].max_range;

        actag_params_default(&p);
        p.family = fam;
        p.max_bit_corrections = ac_settings[si].max_bit_corrections;
        if (ac_settings[si].decode_mode >= 0)
            p.tuning.decode_mode = ac_settings[si].decode_mode;
        memset(ac_det, 0, sizeof ac_det); /* no stale bytes in the digest */
        memset(&st, 0, sizeof st);
        n = actag_detect(&frame, &g, &p, ac_ws, sizeof ac_ws, ac_det, AC_MAX_DET, &st);

        put_s("run ");
        put_s(ac_settings[si].name);
        put_kf("max_range", g.max_range);
        put_kd("max_bit_corrections", p.max_bit_corrections);
        put_kd("decode_mode", p.tuning.decode_mode);
        put_ku("seed", p.seed);
        put_kd("result", n);
        end_line();
        if (n < 0) {
            put_s("error ");
            put_s(actag_strerror(n));
            end_line();
            ac_failed = 1;
            total = fnv1a(total, &n, sizeof n);
            continue;
        }
        put_s("stats contours ");
        put_d(st.contours);
        put_kd("size_ok", st.size_ok);
        put_kd("overflowed", st.overflowed);
        put_kd("quads", st.quads);
        put_kd("decoded", st.decoded);
        put_kd("duplicates", st.duplicates);
        put_kd("dropped", st.dropped);
        end_line();
        for (i = 0; i < n; i++) {
            const actag_detection *d = &ac_det[i];
            put_s("det ");
            put_d(i);
            put_kd("id", d->id);
            put_kd("hamming", d->hamming);
            put_kd("mirrored", d->mirrored);
            put_kf("inlier_ratio", d->inlier_ratio);
            end_line();
            for (k = 0; k < 4; k++) {
                put_corner(k, d->corners[k], d->range[k], d->azimuth[k]);
                end_line();
            }
        }
        /* the sonar pose of every detection (pose.h): float arithmetic and
         * the library's own trigonometry, so bit-identical as well */
        memset(ac_pose, 0, sizeof ac_pose); /* no stale bytes in the digest */
        for (i = 0; i < n; i++) {
            actag_pose_params pp;
            int prc;
            actag_pose_params_default(&pp, fam, p.tag_size, AC_VERTICAL_APERTURE);
            prc = actag_pose_from_detection(&ac_det[i], &pp, &ac_pose[i]);
            put_s("pose ");
            put_d(i);
            put_pose(" ", prc, &ac_pose[i]);
        }
        hp = fnv1a(FNV_OFFSET, ac_pose, (size_t)n * sizeof ac_pose[0]);
        hd = fnv1a(FNV_OFFSET, ac_det, (size_t)n * sizeof ac_det[0]);
        img = actag_workspace_filtered(ac_ws, rows, cols);
        hf = img != NULL ? fnv1a(FNV_OFFSET, img, (size_t)rows * (size_t)cols) : 0u;
        img = (const uint8_t *)(const void *)actag_workspace_bitmap(ac_ws, rows, cols);
        hb = img != NULL ? fnv1a(FNV_OFFSET, img, ACTAG_BITMAP_SIZE(rows, cols)) : 0u;
        put_s("digest detections ");
        put_x64(hd);
        put_s(" filtered ");
        put_x64(hf);
        put_s(" binary ");
        put_x64(hb);
        put_s(" poses ");
        put_x64(hp);
        end_line();
        total = fnv1a(total, &hd, sizeof hd);
        total = fnv1a(total, &hp, sizeof hp);
        total = fnv1a(total, &hf, sizeof hf);
        total = fnv1a(total, &hb, sizeof hb);
    }
    return track_frame(rel, &frame, &geo, fam, total);
}

int main(int argc, char **argv)
{
    actag_family fam;
    uint64_t total = FNV_OFFSET;
    int i, rc;

    if (argc < 3) {
        ac_log("usage: armcheck OUT_REPORT SONAR_DATA_DIR [FRAME.pgm ...]\n");
        return 2;
    }
    if (ac_out_open(argv[1]) != 0) {
        ac_log("armcheck: cannot open the report file\n");
        return 1;
    }
    put_s("armcheck actag ");
    put_s(ACTAG_VERSION_STRING);
    put_s(" sizeof(actag_detection) ");
    put_u((unsigned long)sizeof(actag_detection));
    put_ku("workspace", (unsigned long)sizeof ac_ws);
    end_line();

    rc = actag_family_get("AcTag24h10", &fam);
    if (rc != ACTAG_OK) {
        put_s("family AcTag24h10 error ");
        put_s(actag_strerror(rc));
        end_line();
        ac_failed = 1;
    } else if (argc > 3) {
        for (i = 3; i < argc; i++)
            total = run_frame(argv[2], argv[i], &fam, total);
    } else {
        for (i = 0; i < (int)(sizeof ac_default_frames / sizeof ac_default_frames[0]); i++)
            total = run_frame(argv[2], ac_default_frames[i], &fam, total);
    }
    put_s("total ");
    put_x64(total);
    put_s(ac_failed ? " FAILED" : " ok");
    end_line();
    if (ac_out_close() != 0)
        ac_failed = 1;
    return ac_failed ? 1 : 0;
}
