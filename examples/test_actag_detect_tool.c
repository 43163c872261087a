/* The actag_detect example as a user runs it: PGM (8/16-bit) and raw input
 * with strides and orientation flags, standard input, --json (one line per
 * file, errors included, coordinates under x_col/y_row), --overlay and
 * --stages outputs (folders created, no two pictures with one name), bad
 * input and bad options (exit status 2, one line naming the file or option,
 * the remaining files still processed), --version. */
#define _POSIX_C_SOURCE 200809L
#include "unity.h"
#include "hostio.h"
#include "actag/version.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

void setUp(void) {}
void tearDown(void) {}

#define GEO "--min-range 0.1 --max-range 1.5 --aperture-deg 60 --family AcTag24h10"
#define EXAMPLE ACTAG_SOURCE_DIR "/data/exampleSonarImage.pgm"
#define OUT ACTAG_BINARY_DIR "/tool_test"

static char out_path[512], err_path[512];

/* Runs the tool with args (which may hold a "< file" redirection); stdout
 * and stderr go to files. Returns the exit status. */
static int run(const char *args)
{
    char cmd[4096];
    int st;
    snprintf(out_path, sizeof out_path, "%s/tool_out.txt", ACTAG_BINARY_DIR);
    snprintf(err_path, sizeof err_path, "%s/tool_err.txt", ACTAG_BINARY_DIR);
    snprintf(cmd, sizeof cmd, "\"%s\" %s > \"%s\" 2> \"%s\"", ACTAG_DETECT_PATH, args, out_path,
             err_path);
    st = system(cmd);
    return (st != -1 && WIFEXITED(st)) ? WEXITSTATUS(st) : -1;
}

static char *slurp(const char *path)
{
    char err[HOSTIO_ERRLEN];
    char *s = (char *)hostio_slurp(path, NULL, err);
    TEST_ASSERT_NOT_NULL_MESSAGE(s, err);
    return s;
}

static char *out_text(void) { return slurp(out_path); }
static char *err_text(void) { return slurp(err_path); }

static int exists(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0;
}

static int count_lines(const char *s)
{
    int n = 0;
    for (; *s; s++)
        n += *s == '\n';
    return n;
}

/* First detection's corners from a JSON line as (x_col, y_row); returns
 * the id or -1. */
static int parse_first(const char *line, float xy[4][2])
{
    const char *p = strstr(line, "\"id\": ");
    int id, c;
    if (!p || sscanf(p, "\"id\": %d", &id) != 1)
        return -1;
    p = strstr(p, "\"corners\": [");
    if (!p)
        return -1;
    for (c = 0; c < 4; c++) {
        p = strstr(p, "{\"x_col\": ");
        if (!p || sscanf(p, "{\"x_col\": %f, \"y_row\": %f,", &xy[c][0], &xy[c][1]) != 2)
            return -1;
        if (!strstr(p, "\"range_m\": ") || !strstr(p, "\"azimuth_rad\": "))
            return -1;
        p++;
    }
    return id;
}

/* SPEC section 6: the reference's corners, (row, col), tag order. */
static const float ref_rc[4][2] = {{145, 314}, {113, 339}, {103, 280}, {133, 244}};

static void assert_reference_tag(const char *json_line)
{
    float xy[4][2];
    int c;
    TEST_ASSERT_NOT_NULL(json_line);
    TEST_ASSERT_EQUAL_INT(0, parse_first(json_line, xy));
    TEST_ASSERT_NULL_MESSAGE(strstr(strstr(json_line, "\"id\": ") + 1, "\"id\": "),
                             "more than one detection");
    /* refined corners (refine.h): within 4.5 pixels of the reference's (the
     * third corner is 4.0 px off in column) */
    for (c = 0; c < 4; c++) {
        TEST_ASSERT_FLOAT_WITHIN(4.5f, ref_rc[c][1], xy[c][0]); /* x = column */
        TEST_ASSERT_FLOAT_WITHIN(4.5f, ref_rc[c][0], xy[c][1]); /* y = row */
    }
}

/* The part of a JSON line that does not depend on the file name or the time. */
static char *json_body(const char *line)
{
    const char *a = strstr(line, "\"rows\""), *b = strstr(line, "\"time_ms\"");
    char *s;
    TEST_ASSERT_NOT_NULL(a);
    TEST_ASSERT_NOT_NULL(b);
    s = (char *)calloc((size_t)(b - a) + 1, 1);
    TEST_ASSERT_NOT_NULL(s);
    memcpy(s, a, (size_t)(b - a));
    return s;
}

static void write_file(const char *path, const void *data, size_t n)
{
    char err[HOSTIO_ERRLEN];
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_write_file(path, data, n, err), err);
}

static void test_json_on_example(void)
{
    char *o;
    TEST_ASSERT_EQUAL_INT(0, run("--json " GEO " " EXAMPLE));
    o = out_text();
    TEST_ASSERT_EQUAL_INT(1, count_lines(o));
    TEST_ASSERT_EQUAL_INT(0, strncmp(o, "{\"file\": \"", 10));
    TEST_ASSERT_NOT_NULL(strstr(o, "\"rows\": 463, \"cols\": 620, \"detections\": [{"));
    TEST_ASSERT_NOT_NULL(strstr(o, "\"corners\": [{\"x_col\": "));
    TEST_ASSERT_NOT_NULL(strstr(o, "\"mirrored\": "));
    TEST_ASSERT_NOT_NULL(strstr(o, "\"time_ms\": "));
    TEST_ASSERT_NULL(strstr(o, "corners_px")); /* the old, ambiguous key */
    assert_reference_tag(o);
    free(o);
}

/* actag_detect with args exits with status 2 and its message holds says. */
static void expect_refused(const char *args, const char *says)
{
    char *e;
    TEST_ASSERT_EQUAL_INT(2, run(args));
    e = err_text();
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(e, says), e);
    free(e);
}

/* The example read with the options opts (JSON) gives no tag. */
static void expect_no_tag_with(const char *opts)
{
    char cmd[256], *o;
    snprintf(cmd, sizeof cmd, "--json " GEO " %s " EXAMPLE, opts);
    TEST_ASSERT_EQUAL_INT(0, run(cmd));
    o = out_text();
    TEST_ASSERT_NOT_NULL(strstr(o, "\"detections\": []"));
    free(o);
}

/* The example read with the options opts gives the same JSON as without
 * them: the reference tag. */
static void expect_default_with(const char *opts)
{
    char cmd[256], *o, *o2, *b, *b2;
    snprintf(cmd, sizeof cmd, "--json " GEO " %s " EXAMPLE, opts);
    TEST_ASSERT_EQUAL_INT(0, run(cmd));
    o = out_text();
    TEST_ASSERT_EQUAL_INT(0, run("--json " GEO " " EXAMPLE));
    o2 = out_text();
    b = json_body(o);
    b2 = json_body(o2);
    TEST_ASSERT_EQUAL_STRING(b2, b);
    assert_reference_tag(o);
    free(b);
    free(b2);
    free(o);
    free(o2);
}

/* --min-bit-margin reaches the decoder: the example's tag 0 (hamming 2) leads
 * its runner-up by fewer than 20 bits, so asking for 20 leaves no reading,
 * and 2 (the default) gives the same line as no option. */
static void test_min_bit_margin_option(void)
{
    expect_no_tag_with("--min-bit-margin 20");
    expect_default_with("--min-bit-margin 2");
}

/* --min-bit-odds reaches the decoder: the example's tag 0 has 2 corrected
 * bits of 20 and leads by 3; at odds 1000000 it would need 7 (9^7 >= 10^6),
 * so no reading; 100 (the default) gives the same line as no option, and 1
 * (the rule off) too. A value out of range is refused naming the option. */
static void test_min_bit_odds_option(void)
{
    expect_no_tag_with("--min-bit-odds 1000000");
    expect_default_with("--min-bit-odds 1");
    expect_default_with("--min-bit-odds 100");
    expect_refused(GEO " --min-bit-odds 0 " EXAMPLE, "--min-bit-odds");
}

/* --level-noise and --separate-noise: the example's tag 0 is read with
 * cell noise well under a fifth of its contrast, so neither check applies
 * and every setting gives the reference line (that they reach the decoder
 * on poorly fitting tags: tools/sim/test_heldout_regressions.c). A value
 * other than 0 or 1 is refused naming the option. */
static void test_level_noise_options(void)
{
    expect_default_with("--level-noise 0");
    expect_default_with("--level-noise 1");
    expect_default_with("--separate-noise");
    expect_default_with("--level-noise 0 --separate-noise");
    expect_refused(GEO " --level-noise 2 " EXAMPLE, "--level-noise");
}

/* The first tag's pose line of text output o: its t and the sd of t_z. */
static void pose_line(const char *o, float t[3], float *sd_z)
{
    const char *p = strstr(o, "pose: t (");
    TEST_ASSERT_NOT_NULL(p);
    TEST_ASSERT_EQUAL_INT(3, sscanf(p, "pose: t (%f, %f, %f)", &t[0], &t[1], &t[2]));
    p = strstr(p, "sd t (");
    TEST_ASSERT_NOT_NULL(p);
    TEST_ASSERT_EQUAL_INT(1, sscanf(p, "sd t (%*f, %*f, %f)", sd_z));
}

/* --pose with a known plane (pose.h KNOWN PLANE): the example tag's centre
 * moves onto the plane z = -0.03 m (1.2 cm from its plane-free elevation,
 * inside the band), its elevation sd shrinks from the band's to about the
 * plane's; bad plane options are refused with exit status 2 naming them. */
static void test_pose_plane_options(void)
{
    char *o;
    float t0[3], t1[3], s0, s1;
    TEST_ASSERT_EQUAL_INT(0, run(GEO " --pose " EXAMPLE));
    o = out_text();
    pose_line(o, t0, &s0);
    free(o);
    TEST_ASSERT_EQUAL_INT(0, run(GEO " --pose --plane 0,0,1,-0.03 --plane-sd 0.005 " EXAMPLE));
    o = out_text();
    pose_line(o, t1, &s1);
    TEST_ASSERT_FLOAT_WITHIN(0.005f, -0.03f, t1[2]);
    TEST_ASSERT_TRUE(t0[2] - t1[2] > 0.02f);
    TEST_ASSERT_TRUE(s1 < 0.5f * s0);
    TEST_ASSERT_NULL(strstr(o, "[plane]"));
    free(o);
    {
        /* the normal's scale does not matter (pose.h); a normal of 1e200
         * overflowed the tool's own normalisation to (0, 0, 0), and every
         * pose then failed with exit status 0 */
        static const char *const scaled[2] = {"0,0,1e200,-3e198", "0,0,1e-20,-3e-22"};
        char cmd[512];
        int i, c;
        for (i = 0; i < 2; i++) {
            float t2[3], s2;
            snprintf(cmd, sizeof cmd, GEO " --pose --plane %s --plane-sd 0.005 " EXAMPLE,
                     scaled[i]);
            TEST_ASSERT_EQUAL_INT(0, run(cmd));
            o = out_text();
            pose_line(o, t2, &s2);
            for (c = 0; c < 3; c++)
                TEST_ASSERT_FLOAT_WITHIN(1e-4f, t1[c], t2[c]);
            TEST_ASSERT_FLOAT_WITHIN(1e-4f, s1, s2);
            free(o);
        }
    }
    expect_refused(GEO " --pose --plane 0,0,1 --plane-sd 0.005 " EXAMPLE,
                   "--plane: expected 4 numbers");
    expect_refused(GEO " --pose --plane-tilt-deg 1 " EXAMPLE, "need --plane NX,NY,NZ,D");
    expect_refused(GEO " --pose --plane 0,0,1,0 --plane-sd -1 " EXAMPLE,
                   "--plane-sd: must be from 0");
}

/* The text output says its convention and lists x (column) first. */
static void test_text_output_convention(void)
{
    char *o;
    float x, y;
    const char *p;
    TEST_ASSERT_EQUAL_INT(0, run(GEO " " EXAMPLE));
    o = out_text();
    p = strstr(o, "(x=col, y=row px | range m, azimuth rad): (");
    TEST_ASSERT_NOT_NULL(p);
    TEST_ASSERT_EQUAL_INT(2, sscanf(p + strlen("(x=col, y=row px | range m, azimuth rad): ("),
                                    "%f, %f", &x, &y));
    TEST_ASSERT_FLOAT_WITHIN(2.0f, ref_rc[0][1], x);
    TEST_ASSERT_FLOAT_WITHIN(2.0f, ref_rc[0][0], y);
    free(o);
}

/* Raw frames: stride padding, 16-bit little-endian, orientation flags. */
static void test_raw_and_16bit_inputs(void)
{
    hostio_image im;
    char err[HOSTIO_ERRLEN], path[600], args[1400], *o;
    int rows, cols, r, c, stride = 631;
    uint8_t *img, *raw;
    uint16_t *raw16;
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_pgm_read(EXAMPLE, &im, err), err);
    img = (uint8_t *)im.data;
    rows = im.rows;
    cols = im.cols;
    /* 8-bit raw with a 631-pixel stride (padding full of 0xee) */
    raw = (uint8_t *)malloc((size_t)rows * (size_t)stride);
    TEST_ASSERT_NOT_NULL(raw);
    memset(raw, 0xee, (size_t)rows * (size_t)stride);
    for (r = 0; r < rows; r++)
        memcpy(raw + (size_t)r * (size_t)stride, img + (size_t)r * (size_t)cols, (size_t)cols);
    snprintf(path, sizeof path, "%s/example_stride.raw", ACTAG_BINARY_DIR);
    write_file(path, raw, (size_t)rows * (size_t)stride);
    snprintf(args, sizeof args, "--json " GEO " --rows %d --cols %d --stride %d %s", rows, cols,
             stride, path);
    TEST_ASSERT_EQUAL_INT(0, run(args));
    o = out_text();
    assert_reference_tag(o);
    free(o);
    /* the same frame, rows and columns reversed, said so with the flags:
     * the image coordinates are mirrored, the polar corners are the same */
    for (r = 0; r < rows; r++)
        for (c = 0; c < cols; c++)
            raw[(size_t)(rows - 1 - r) * (size_t)cols + (size_t)(cols - 1 - c)] =
                img[(size_t)r * (size_t)cols + (size_t)c];
    snprintf(path, sizeof path, "%s/example_flipped.raw", ACTAG_BINARY_DIR);
    write_file(path, raw, (size_t)rows * (size_t)cols);
    snprintf(args, sizeof args,
             "--json " GEO " --range-ascending --azimuth-ascending --rows %d --cols %d %s", rows,
             cols, path);
    TEST_ASSERT_EQUAL_INT(0, run(args));
    o = out_text();
    {
        float xy[4][2];
        TEST_ASSERT_EQUAL_INT(0, parse_first(o, xy));
        for (c = 0; c < 4; c++) {
            TEST_ASSERT_FLOAT_WITHIN(4.5f, (float)(cols - 1) - ref_rc[c][1], xy[c][0]);
            TEST_ASSERT_FLOAT_WITHIN(4.5f, (float)(rows - 1) - ref_rc[c][0], xy[c][1]);
        }
    }
    free(o);
    /* 16-bit raw, little-endian, values x 257 */
    raw16 = (uint16_t *)malloc((size_t)rows * (size_t)cols * 2u);
    TEST_ASSERT_NOT_NULL(raw16);
    for (r = 0; r < rows * cols; r++) {
        uint8_t *b = (uint8_t *)&raw16[r];
        unsigned v = img[r] * 257u;
        b[0] = (uint8_t)(v & 0xff);
        b[1] = (uint8_t)(v >> 8);
    }
    snprintf(path, sizeof path, "%s/example16.raw", ACTAG_BINARY_DIR);
    write_file(path, raw16, (size_t)rows * (size_t)cols * 2u);
    snprintf(args, sizeof args, "--json " GEO " --depth 16 --rows %d --cols %d %s", rows, cols, path);
    TEST_ASSERT_EQUAL_INT(0, run(args));
    o = out_text();
    TEST_ASSERT_NOT_NULL(strstr(o, "\"id\": 0"));
    free(o);
    /* 16-bit PGM (big-endian samples) */
    {
        hostio_image im16;
        for (r = 0; r < rows * cols; r++)
            raw16[r] = (uint16_t)(img[r] * 257u);
        im16.data = raw16;
        im16.rows = rows;
        im16.cols = cols;
        im16.stride = cols;
        im16.depth = 16;
        im16.maxval = 65535;
        snprintf(path, sizeof path, "%s/example16.pgm", ACTAG_BINARY_DIR);
        TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_pgm_write(path, &im16, err), err);
        snprintf(args, sizeof args, "--json " GEO " %s", path);
        TEST_ASSERT_EQUAL_INT(0, run(args));
        o = out_text();
        TEST_ASSERT_NOT_NULL(strstr(o, "\"id\": 0"));
        free(o);
    }
    free(raw16);
    free(raw);
    hostio_image_free(&im);
}

/* "-" reads the frame from standard input: the same JSON as from the file
 * (PGM and raw); standard input only once. */
static void test_stdin_gives_the_same_json(void)
{
    char *a, *b, *ba, *bb, args[1400];
    TEST_ASSERT_EQUAL_INT(0, run("--json " GEO " " EXAMPLE));
    a = out_text();
    TEST_ASSERT_EQUAL_INT(0, run("--json " GEO " - < " EXAMPLE));
    b = out_text();
    TEST_ASSERT_EQUAL_INT(0, strncmp(b, "{\"file\": \"-\", ", 14));
    ba = json_body(a);
    bb = json_body(b);
    TEST_ASSERT_EQUAL_STRING(ba, bb);
    assert_reference_tag(b);
    free(a);
    free(b);
    free(bb);
    /* a raw frame through a pipe */
    snprintf(args, sizeof args, "--json " GEO " --rows 463 --cols 620 --stride 631 - < %s",
             ACTAG_BINARY_DIR "/example_stride.raw");
    TEST_ASSERT_EQUAL_INT(0, run(args));
    b = out_text();
    bb = json_body(b);
    TEST_ASSERT_EQUAL_STRING(ba, bb);
    free(b);
    free(bb);
    free(ba);
    /* text mode, and bad input on standard input names it */
    TEST_ASSERT_EQUAL_INT(0, run(GEO " - < " EXAMPLE));
    a = out_text();
    TEST_ASSERT_EQUAL_INT(0, strncmp(a, "-: AcTag24h10 id 0 ", 19));
    free(a);
    expect_refused(GEO " - < /dev/null", "actag_detect: stdin: not a PGM file");
    expect_refused(GEO " - - < " EXAMPLE, "standard input can be read only once (two frames -)");
}

static void assert_header(const char *path, const char *magic, int w, int min_h)
{
    char *s = slurp(path);
    int fw = 0, fh = 0;
    char m[3] = {0, 0, 0};
    TEST_ASSERT_EQUAL_INT_MESSAGE(3, sscanf(s, "%2s %d %d", m, &fw, &fh), path);
    TEST_ASSERT_EQUAL_STRING_MESSAGE(magic, m, path);
    if (w > 0)
        TEST_ASSERT_EQUAL_INT_MESSAGE(w, fw, path);
    else
        TEST_ASSERT_TRUE_MESSAGE(fw > -w, path); /* w < 0: wider than -w */
    TEST_ASSERT_TRUE_MESSAGE(fh >= min_h, path);
    free(s);
}

/* --stages writes every stage into a folder it creates (parents too);
 * --overlay writes the polar + fan picture, into a new folder too. */
static void test_overlay_and_stages(void)
{
    static const char *const stage[7] = {"1-input.pgm", "2-median.pgm", "3-search.ppm",
                                         "4-binary.pgm", "5-contours.ppm", "6-quads.ppm",
                                         "7-decoded.ppm"};
    char path[700], *s;
    int i;
    TEST_ASSERT_EQUAL_INT(0, system("rm -rf \"" OUT "\""));
    TEST_ASSERT_FALSE(exists(OUT));
    TEST_ASSERT_EQUAL_INT(0, run(GEO " --overlay " OUT "/ov/ov.ppm --stages " OUT "/st/a/b " EXAMPLE));
    s = out_text();
    TEST_ASSERT_NOT_NULL(strstr(s, "id 0"));
    free(s);
    assert_header(OUT "/ov/ov.ppm", "P6", -620 - 200, 463); /* polar + fan side by side */
    for (i = 0; i < 7; i++) {
        snprintf(path, sizeof path, OUT "/st/a/b/exampleSonarImage-%s", stage[i]);
        assert_header(path, strstr(stage[i], ".pgm") ? "P5" : "P6", 620, 463);
    }
    /* --stages naming something that is not a folder: one line, status 2 */
    write_file(OUT "/plainfile", "x", 1);
    TEST_ASSERT_EQUAL_INT(2, run(GEO " --stages " OUT "/plainfile " EXAMPLE));
    s = err_text();
    TEST_ASSERT_EQUAL_INT(1, count_lines(s));
    TEST_ASSERT_NOT_NULL(strstr(s, "--stages: "));
    TEST_ASSERT_NOT_NULL(strstr(s, "plainfile"));
    free(s);
}

/* --overlay with a geometry the library accepts but no picture can show
 * (ranges up to 3e38 m): the fan's extent was inf, its width a NaN
 * converted to int, and the run failed with "out of memory" (under ASan an
 * allocation-size-too-big crash). Now one line naming the options and
 * values, status 2, no picture; a large but drawable fan still works. */
static void test_overlay_extreme_geometry(void)
{
    char *s;
    TEST_ASSERT_EQUAL_INT(0, system("mkdir -p \"" OUT "\""));
    remove(OUT "/extreme.ppm");
    TEST_ASSERT_EQUAL_INT(2, run("--min-range 1e30 --max-range 3e38 --aperture-deg 359.99 "
                                 "--overlay " OUT "/extreme.ppm " EXAMPLE));
    s = err_text();
    TEST_ASSERT_EQUAL_INT_MESSAGE(1, count_lines(s), s);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(s, "extreme.ppm: no fan picture for ranges 1e+30..3e+38 m"), s);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(s, "--max-range"), s);
    TEST_ASSERT_NULL_MESSAGE(strstr(s, "out of memory"), s);
    free(s);
    TEST_ASSERT_FALSE(exists(OUT "/extreme.ppm"));
    TEST_ASSERT_EQUAL_INT(2, run("--min-range 1e18 --max-range 1e19 --aperture-deg 359.99 "
                                 "--overlay " OUT "/extreme.ppm " EXAMPLE));
    TEST_ASSERT_EQUAL_INT(0, run("--min-range 1e16 --max-range 1e17 --aperture-deg 359.99 "
                                 "--overlay " OUT "/extreme.ppm " EXAMPLE));
    TEST_ASSERT_TRUE(exists(OUT "/extreme.ppm"));
}

/* --overlay naming an input (the frame itself, under another spelling of
 * its path, or the bearing table), or --stages writing onto one:
 * refused, status 2, the input kept byte for byte (it was overwritten with
 * the picture; --stages overwrote it before it was read); a tall frame's
 * overlay keeps its fan panel at 2,048 px (a 2 x 8,000 frame took a
 * 8k x 8k picture). */
static void test_overlay_never_overwrites_an_input(void)
{
    static uint8_t tall[16 + 2 * 8000];
    size_t n0, n1;
    uint8_t *before, *after;
    char *s;
    int i, hdr;
    TEST_ASSERT_EQUAL_INT(0, system("rm -rf \"" OUT "/ovin\" && mkdir -p \"" OUT "/ovin\""));
    TEST_ASSERT_EQUAL_INT(0, system("cp \"" EXAMPLE "\" \"" OUT "/ovin/f.pgm\""));
    before = (uint8_t *)hostio_slurp(OUT "/ovin/f.pgm", &n0, NULL);
    TEST_ASSERT_NOT_NULL(before);
    expect_refused(GEO " --overlay " OUT "/ovin/./f.pgm " OUT "/ovin/f.pgm",
                   "would overwrite an input file");
    after = (uint8_t *)hostio_slurp(OUT "/ovin/f.pgm", &n1, NULL);
    TEST_ASSERT_NOT_NULL(after);
    TEST_ASSERT_EQUAL_size_t(n0, n1);
    TEST_ASSERT_EQUAL_MEMORY(before, after, n0);
    free(before);
    free(after);
    /* the bearing table, named as given */
    {
        char cmd[1200];
        snprintf(cmd, sizeof cmd, "awk 'BEGIN { for (i = 0; i < 620; i++) print 0.5236 - i * 1.0472 / 619 }' > \"%s\"",
                 OUT "/ovin/b.txt");
        TEST_ASSERT_EQUAL_INT(0, system(cmd));
    }
    expect_refused("--min-range 0.1 --max-range 1.5 --bearings " OUT "/ovin/b.txt"
                   " --overlay " OUT "/ovin/b.txt " OUT "/ovin/f.pgm",
                   "would overwrite an input file");
    s = slurp(OUT "/ovin/b.txt");
    TEST_ASSERT_EQUAL_INT('0', s[0]); /* still the table's text */
    free(s);
    /* --stages too: a.pgm's stage picture a-1-input.pgm is another input
     * here; refused (status 2), that input kept and still read */
    {
        static const uint8_t small[] = "P5\n4 4\n255\n\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0";
        TEST_ASSERT_EQUAL_INT(0, system("cp \"" EXAMPLE "\" \"" OUT "/ovin/a.pgm\""));
        write_file(OUT "/ovin/a-1-input.pgm", small, sizeof small - 1);
        TEST_ASSERT_EQUAL_INT(2, run(GEO " --stages " OUT "/ovin " OUT "/ovin/a.pgm " OUT
                                     "/ovin/a-1-input.pgm"));
        s = err_text();
        TEST_ASSERT_NOT_NULL(strstr(s, "--stages " OUT "/ovin/a-1-input.pgm: would overwrite an input file"));
        free(s);
        s = out_text();
        TEST_ASSERT_NOT_NULL(strstr(s, "a-1-input.pgm: no tags"));
        free(s);
        after = (uint8_t *)hostio_slurp(OUT "/ovin/a-1-input.pgm", &n1, NULL);
        TEST_ASSERT_NOT_NULL(after);
        TEST_ASSERT_EQUAL_size_t(sizeof small - 1, n1);
        TEST_ASSERT_EQUAL_MEMORY(small, after, n1);
        free(after);
    }
    /* standard output carries the detections: no picture there */
    expect_refused(GEO " --overlay - " OUT "/ovin/f.pgm",
                   "--overlay -: standard output carries the detections");
    /* a tall, narrow frame: the picture is bounded */
    hdr = snprintf((char *)tall, sizeof tall, "P5\n2 8000\n255\n");
    for (i = 0; i < 2 * 8000; i++)
        tall[hdr + i] = (uint8_t)(i * 7);
    write_file(OUT "/ovin/tall.pgm", tall, (size_t)hdr + 2u * 8000u);
    TEST_ASSERT_EQUAL_INT(0, run(GEO " --overlay " OUT "/ovin/tall.ppm " OUT "/ovin/tall.pgm"));
    {
        char *ppm = slurp(OUT "/ovin/tall.ppm");
        int fw = 0, fh = 0;
        TEST_ASSERT_EQUAL_INT(2, sscanf(ppm, "P6 %d %d", &fw, &fh));
        TEST_ASSERT_TRUE(fw < 7000); /* the frame's 2 columns and a fan panel of 2,048 rows */
        TEST_ASSERT_TRUE(fh >= 8000);
        free(ppm);
    }
}

/* --show-rejected draws the candidates that did not become tags: the
 * example frame has one rejected search box, so the pictures differ. */
static void test_show_rejected_changes_the_overlay(void)
{
    char *a, *b;
    size_t la, lb;
    char err[HOSTIO_ERRLEN];
    TEST_ASSERT_EQUAL_INT(0, run(GEO " --overlay " OUT "/plain.ppm " EXAMPLE));
    TEST_ASSERT_EQUAL_INT(0, run(GEO " --show-rejected --overlay " OUT "/rej.ppm " EXAMPLE));
    a = (char *)hostio_slurp(OUT "/plain.ppm", &la, err);
    b = (char *)hostio_slurp(OUT "/rej.ppm", &lb, err);
    TEST_ASSERT_NOT_NULL(a);
    TEST_ASSERT_NOT_NULL(b);
    TEST_ASSERT_TRUE(la != lb || memcmp(a, b, la) != 0); /* the legend may grow too */
    TEST_ASSERT_NOT_NULL(strstr(b, "P6\n"));
    free(a);
    free(b);
}

/* a/x.pgm and b/x.pgm: pictures named by position, both kept; a unique
 * name keeps the plain stem. */
static void test_same_named_files_do_not_overwrite(void)
{
    hostio_image im;
    char err[HOSTIO_ERRLEN], *a, *b;
    size_t la, lb;
    int r;
    TEST_ASSERT_EQUAL_INT(0, system("mkdir -p \"" OUT "/a\" \"" OUT "/b\""));
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_pgm_read(EXAMPLE, &im, err), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_pgm_write(OUT "/a/x.pgm", &im, err), err);
    for (r = 0; r < im.rows * im.cols; r++) /* a different frame of the same size */
        ((uint8_t *)im.data)[r] = (uint8_t)(255 - ((uint8_t *)im.data)[r]);
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_pgm_write(OUT "/b/x.pgm", &im, err), err);
    hostio_image_free(&im);
    TEST_ASSERT_EQUAL_INT(0, run(GEO " --overlay " OUT "/two.ppm --stages " OUT "/two " OUT
                                     "/a/x.pgm " OUT "/b/x.pgm " EXAMPLE));
    TEST_ASSERT_TRUE(exists(OUT "/two-1-x.ppm"));
    TEST_ASSERT_TRUE(exists(OUT "/two-2-x.ppm"));
    TEST_ASSERT_TRUE(exists(OUT "/two-exampleSonarImage.ppm"));
    TEST_ASSERT_TRUE(exists(OUT "/two/1-x-1-input.pgm"));
    TEST_ASSERT_TRUE(exists(OUT "/two/2-x-7-decoded.ppm"));
    TEST_ASSERT_TRUE(exists(OUT "/two/exampleSonarImage-4-binary.pgm"));
    a = (char *)hostio_slurp(OUT "/two-1-x.ppm", &la, err);
    b = (char *)hostio_slurp(OUT "/two-2-x.ppm", &lb, err);
    TEST_ASSERT_NOT_NULL(a);
    TEST_ASSERT_NOT_NULL(b);
    TEST_ASSERT_TRUE(la != lb || memcmp(a, b, la) != 0); /* each its own frame */
    free(a);
    free(b);
    /* a file named like another's numbered name (1-x for a/x): every file
     * numbered, three pictures (1-x's was written over a/x's) */
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_pgm_read(EXAMPLE, &im, err), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_pgm_write(OUT "/1-x.pgm", &im, err), err);
    hostio_image_free(&im);
    TEST_ASSERT_EQUAL_INT(0, run(GEO " --overlay " OUT "/three.ppm " OUT "/a/x.pgm " OUT
                                     "/b/x.pgm " OUT "/1-x.pgm"));
    TEST_ASSERT_TRUE(exists(OUT "/three-1-x.ppm"));
    TEST_ASSERT_TRUE(exists(OUT "/three-2-x.ppm"));
    TEST_ASSERT_TRUE(exists(OUT "/three-3-1-x.ppm"));
    a = (char *)hostio_slurp(OUT "/three-1-x.ppm", &la, err);
    b = (char *)hostio_slurp(OUT "/three-3-1-x.ppm", &lb, err);
    TEST_ASSERT_NOT_NULL(a);
    TEST_ASSERT_NOT_NULL(b);
    TEST_ASSERT_TRUE(la != lb || memcmp(a, b, la) != 0); /* a/x.pgm's, not 1-x.pgm's */
    free(a);
    free(b);
}

static void test_bad_files_are_reported_and_the_rest_processed(void)
{
    char args[2000], p1[600], p2[600], p3[600], *o, *e;
    static const char trunc[] = "P5\n10 10\n255\nabc";
    snprintf(p1, sizeof p1, "%s/truncated.pgm", ACTAG_BINARY_DIR);
    write_file(p1, trunc, sizeof trunc - 1);
    snprintf(p2, sizeof p2, "%s/ascii.pgm", ACTAG_BINARY_DIR);
    write_file(p2, "P2\n2 2\n255\n0 1 2 3\n", 19);
    snprintf(p3, sizeof p3, "%s/notanimage.bin", ACTAG_BINARY_DIR);
    write_file(p3, "hello", 5);
    snprintf(args, sizeof args, "--json " GEO " %s /nonexistent/x.pgm %s %s " EXAMPLE, p1, p2, p3);
    TEST_ASSERT_EQUAL_INT(2, run(args));
    o = out_text();
    e = err_text();
    TEST_ASSERT_EQUAL_INT(5, count_lines(o)); /* one JSON line per input file */
    TEST_ASSERT_EQUAL_INT(4, count_lines(e)); /* one message per bad file */
    TEST_ASSERT_NOT_NULL(strstr(e, "truncated.pgm: PGM has 3 pixel bytes, its header needs 100"));
    TEST_ASSERT_NOT_NULL(strstr(e, "/nonexistent/x.pgm: "));
    TEST_ASSERT_NOT_NULL(strstr(e, "ascii.pgm: a P2 image"));
    TEST_ASSERT_NOT_NULL(strstr(e, "notanimage.bin: not a PGM file"));
    TEST_ASSERT_NOT_NULL(strstr(o, "\"error\": "));
    assert_reference_tag(strstr(o, "exampleSonarImage"));
    free(o);
    free(e);
    /* raw frame of the wrong size */
    snprintf(args, sizeof args, GEO " --rows 10 --cols 10 %s", p3);
    expect_refused(args, "notanimage.bin: raw frame is 5 bytes, expected 100");
}

/* A per-beam bearing table equal to the uniform 60-degree fan gives the
 * same detection; a table of the wrong length or with a bad value is a
 * per-file error naming the table. */
static void test_bearing_table_file(void)
{
    char path[600], args[1400], *a, *b, *ba, *bb;
    FILE *f;
    int c;
    snprintf(path, sizeof path, "%s/bearings620.txt", ACTAG_BINARY_DIR);
    f = fopen(path, "w");
    TEST_ASSERT_NOT_NULL(f);
    for (c = 0; c < 620; c++)
        fprintf(f, "%.9f\n", 0.5 * 1.0471975512 - c * 1.0471975512 / 619.0);
    fclose(f);
    TEST_ASSERT_EQUAL_INT(0, run("--json " GEO " " EXAMPLE));
    a = out_text();
    snprintf(args, sizeof args,
             "--json --min-range 0.1 --max-range 1.5 --family AcTag24h10 --bearings %s " EXAMPLE, path);
    TEST_ASSERT_EQUAL_INT(0, run(args));
    b = out_text();
    assert_reference_tag(b);
    ba = json_body(a);
    bb = json_body(b);
    TEST_ASSERT_EQUAL_STRING(ba, bb); /* same corners and polar values */
    free(a);
    free(b);
    free(ba);
    free(bb);
    /* the table on standard input: read once, used for every frame */
    snprintf(args, sizeof args,
             "--json --min-range 0.1 --max-range 1.5 --family AcTag24h10 --bearings - " EXAMPLE
             " " EXAMPLE " < %s", path);
    TEST_ASSERT_EQUAL_INT(0, run(args));
    a = out_text();
    TEST_ASSERT_EQUAL_INT(2, count_lines(a));
    b = strchr(a, '\n') + 1; /* the second frame's line */
    assert_reference_tag(b);
    b[-1] = '\0';
    assert_reference_tag(a);
    free(a);
    /* ... and so not also a frame there */
    snprintf(args, sizeof args,
             "--json --min-range 0.1 --max-range 1.5 --bearings - - < %s", path);
    TEST_ASSERT_EQUAL_INT(2, run(args));
    a = err_text();
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(a, "standard input can be read only once"), a);
    free(a);
    snprintf(args, sizeof args,
             "--json --min-range 0.1 --max-range 1.5 --family AcTag24h10 --bearings %s " EXAMPLE, path);
    f = fopen(path, "w");
    TEST_ASSERT_NOT_NULL(f);
    for (c = 0; c < 100; c++)
        fprintf(f, "%f\n", 0.5 - c * 0.01);
    fclose(f);
    expect_refused(args,
                   "bearings620.txt: bearing table has 100 values, the frame has 620 columns");
    write_file(path, "0.5 0.4 zebra\n", 14);
    expect_refused(args, "bearings620.txt: value 3 is not a finite number (got 'zebra')");
    /* a table that turns back at value 301 (index 300): the library's
     * detail names the entry, per frame, exit status 2 */
    f = fopen(path, "w");
    TEST_ASSERT_NOT_NULL(f);
    for (c = 0; c < 620; c++)
        fprintf(f, "%.3f\n", c == 300 ? 0.5 - 0.001 * 298 : 0.5 - 0.001 * c);
    fclose(f);
    TEST_ASSERT_EQUAL_INT(2, run(args));
    a = err_text();
    {   /* named by the table's file, not only by the frame's */
        char want[1400];
        snprintf(want, sizeof want,
                 "actag_detect: " EXAMPLE ": --bearings %s: value 301 must be below the "
                 "previous bearing (the table must be strictly monotonic: it "
                 "decreases) (got 0.202 after 0.201)\n", path);
        TEST_ASSERT_EQUAL_STRING(want, a);
    }
    free(a);
    /* the per-column azimuth step depends on the frame: checked per frame */
    TEST_ASSERT_EQUAL_INT(2, run("--min-range 0.1 --max-range 1.5 --aperture-deg 1e-7 " EXAMPLE));
    a = err_text();
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(a, EXAMPLE ": --aperture-deg: must be at least (cols - 1) "
                                           "* ACTAG_MIN_AZIMUTH_STEP"), a);
    free(a);
}

/* Runs args, expects status 2 and exactly one stderr line containing msg. */
static void expect_option_error(const char *args, const char *msg)
{
    char *e;
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, run(args), args);
    e = err_text();
    TEST_ASSERT_EQUAL_INT_MESSAGE(1, count_lines(e), args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, strncmp(e, "actag_detect: ", 14), e);
    if (!strstr(e, msg)) {
        char m[1200];
        snprintf(m, sizeof m, "'%s': expected '%s' in '%s'", args, msg, e);
        TEST_FAIL_MESSAGE(m);
    }
    free(e);
}

static void test_bad_options(void)
{
    expect_option_error("--min-range 0.1 --max-range 1.5 --aperture-deg 60 --family Nope " EXAMPLE,
                        "--family: unknown family Nope (built in: AcTag24h4");
    expect_option_error(GEO " --bit-corrections 5 " EXAMPLE,
                        "--bit-corrections: must be ACTAG_CORRECTIONS_AUTO (-1) or an integer "
                        "from 0 to the family's limit (actag_family_max_corrections) (got 5, "
                        "limit 4)");
    expect_option_error("--min-range 0.1 --aperture-deg 60 " EXAMPLE, "--max-range is required");
    expect_option_error("--max-range 1.5 --aperture-deg 60 " EXAMPLE, "--min-range is required");
    expect_option_error("--min-range 0.1 --max-range 1.5 " EXAMPLE,
                        "--aperture-deg or --bearings is required");
    expect_option_error(GEO " --bearings " ACTAG_BINARY_DIR "/bearings620.txt " EXAMPLE,
                        "--aperture-deg and --bearings exclude each other");
    /* hostio_opt_unknown's wording, as every host tool (it said "unknown option --frobnicate (see --help)") */
    expect_option_error(GEO " --frobnicate " EXAMPLE, "unknown option '--frobnicate' (try --help)");
    expect_option_error(GEO " --median-radius x " EXAMPLE, "--median-radius: must be an integer (got 'x')");
    expect_option_error(GEO " --aperture-deg -5 " EXAMPLE,
                        "--aperture-deg: must be a number > 0 and < 360 (got -5)");
    expect_option_error(GEO " --min-range nan " EXAMPLE, "--min-range: must be a finite number (got 'nan')");
    /* out of range, not malformed: an underflow ("must be a finite number"), a
     * seed beyond 64 bits ("must be an integer"); a '+' named as elsewhere */
    expect_option_error("--min-range 1e-400 --max-range 1.5 --aperture-deg 60 " EXAMPLE,
                        "--min-range: must be 0 or at least 2.22507e-308 in magnitude "
                        "(got 1e-400: too small for a double)");
    expect_option_error(GEO " --seed 99999999999999999999 " EXAMPLE,
                        "--seed: must be a whole number from 0 to 4294967295 "
                        "(got 99999999999999999999)");
    expect_option_error(GEO " --seed +5 " EXAMPLE,
                        "--seed: must be an integer without a '+' sign (got '+5')");
    expect_option_error(GEO " --decode guess " EXAMPLE, "--decode: must be fit or binary (got 'guess')");
    expect_option_error(GEO " --depth 12 " EXAMPLE, "--depth: must be 8 or 16 (got 12)");
    expect_option_error(GEO " --tag-size", "--tag-size: missing value");
    expect_option_error(GEO, "no input files");
    expect_option_error("--min-range 2 --max-range 1.5 --aperture-deg 60 " EXAMPLE,
                        "actag_detect: --min-range/--max-range: must be below --max-range "
                        "(got 2, limit 1.5)\n");
    /* a least side above the largest: both named, the largest settable
     * (--min-side-fraction 2 used to name only tuning.max_side_fraction,
     * which no option set) */
    expect_option_error(GEO " --min-side-fraction 2 " EXAMPLE,
                        "actag_detect: --max-side-fraction/--min-side-fraction: must be at least "
                        "--min-side-fraction (got 1.6, limit 2)\n");
    TEST_ASSERT_EQUAL_INT(0, run(GEO " --min-side-fraction 2 --max-side-fraction 3 " EXAMPLE));
    /* values the library judges: its rule, in the option's name */
    expect_option_error(GEO " --tag-size 0 " EXAMPLE,
                        "actag_detect: --tag-size: must be a finite number > 0 (metres) (got 0)\n");
    expect_option_error(GEO " --tag-size 5 " EXAMPLE,
                        "--tag-size/--max-range: must be at most sqrt(2) * --max-range");
    expect_option_error(GEO " --tag-size 1e30 " EXAMPLE,
                        "actag_detect: --tag-size: must be below ACTAG_MAX_TAG_SIZE (1000 metres) "
                        "(got 1e+30)\n");
    expect_option_error(GEO " --threshold-radius 33 " EXAMPLE,
                        "--threshold-radius: must be an integer from 0 to "
                        "ACTAG_MAX_THRESHOLD_RADIUS (32, pixels) (got 33)");
    expect_option_error(GEO " --inlier-ratio 2 " EXAMPLE,
                        "--inlier-ratio: must be a number > 0 and <= 1 (got 2)");
    expect_option_error(GEO " --inlier-distance 1e7 " EXAMPLE,
                        "--inlier-distance: must be a number of pixels > 0 and <= 1e6 (got 10000000)");
    expect_option_error(GEO " --ransac-iterations 0 " EXAMPLE,
                        "--ransac-iterations: must be an integer from 1 to 1000000 (got 0)");
    expect_option_error(GEO " --median-radius 128 " EXAMPLE,
                        "--median-radius: must be an integer from 0 to 127 (pixels) (got 128)");
    expect_option_error(GEO " --search 9 " EXAMPLE,
                        "--search: must be an integer from 0 to ACTAG_SEARCH_MAX (8) (got 9)");
    expect_option_error(GEO " --min-structure 1.5 " EXAMPLE,
                        "--min-structure: must be a number from 0 to 1 (got 1.5)");
    expect_option_error(GEO " --min-texture-contrast -1 " EXAMPLE,
                        "--min-texture-contrast: must be a number from 0 to 1e6 (got -1)");
    expect_option_error(GEO " --many-corrections-margin -1 " EXAMPLE,
                        "--many-corrections-margin: must be a number from 0 to 1e6 (got -1)");
    expect_option_error(GEO " --min-bit-margin 33 " EXAMPLE,
                        "--min-bit-margin: must be an integer from 0 to 32 (bits) (got 33)");
    expect_option_error(GEO " --min-bit-margin x " EXAMPLE,
                        "--min-bit-margin: must be an integer (got 'x')");
    /* whole numbers echoed in full (%g once printed -2.14748e+09) */
    expect_option_error(GEO " --bit-corrections -2147483648 " EXAMPLE, "(got -2147483648, limit 4)");
    expect_option_error("--min-range -1 --max-range 1.5 --aperture-deg 60 " EXAMPLE,
                        "--min-range: must be a finite number >= 0 (metres) (got -1)");
    expect_option_error("--min-range 0.1 --max-range 1.5 --aperture-deg 400 " EXAMPLE,
                        "--aperture-deg: must be a number > 0 and < 360 (got 400)");
    TEST_ASSERT_EQUAL_INT(0, run("--help"));
}

/* Options that apply only with others are refused alone, never ignored
 * (each was once accepted and dropped), and write errors on stdout and
 * several frames in one file are errors. */
static void test_options_that_need_others(void)
{
    char *e, args[1400];
    FILE *f;
    expect_option_error(GEO " --show-rejected " EXAMPLE, "--show-rejected draws into pictures: it "
                        "needs --overlay or --stages");
    expect_option_error(GEO " --vertical-aperture-deg 2.5 " EXAMPLE, "needs --pose or --check-geometry");
    expect_option_error(GEO " --plane 0,0,1,-0.3 --plane-sd 0.02 " EXAMPLE, "need --pose");
    expect_option_error(GEO " --pose --plane-sd 0 " EXAMPLE, "need --plane NX,NY,NZ,D");
    /* a tag size the pose refuses (pose.h: 1e-3 .. 1e4 m) is named up front */
    expect_option_error(GEO " --pose --tag-size 0.0005 " EXAMPLE,
                        "--pose: the tag size must be 0.001 to 10000 m (pose.h), got 0.0005");
    expect_option_error(GEO " --pose --plane 0,0,1,-0.3 " EXAMPLE,
                        "--plane needs --plane-sd M and/or --plane-tilt-deg D above 0");
    expect_option_error(GEO " --pose --plane 0,0,1,-0.3 --plane-sd 0 --plane-tilt-deg 0 " EXAMPLE,
                        "--plane needs --plane-sd M and/or --plane-tilt-deg D above 0");
    expect_option_error(GEO " --pose --plane 0,0,0,1 --plane-sd 0.02 " EXAMPLE,
                        "--plane: the normal (0, 0, 0) must be non-zero");
    expect_option_error(GEO " --pose --plane 1e-20,0,0,1 --plane-sd 0.02 " EXAMPLE,
                        "(got offset 1e+20 m for the normal (1e-20, 0, 0) and d 1)");
    /* sds the pose cannot use once in float (1e-50 became 0: the plane was
     * dropped without a word; 1e-25 made every pose fail) */
    expect_option_error(GEO " --pose --plane 0,0,1,-0.3 --plane-sd 1e-50 " EXAMPLE,
                        "--plane-sd: 1e-50 m is too small for the pose");
    expect_option_error(GEO " --pose --plane 0,0,1,-0.3 --plane-sd 1e-25 " EXAMPLE,
                        "--plane-sd: 1e-25 m is too small for the pose");
    expect_option_error(GEO " --pose --plane 0,0,1,-0.3 --plane-tilt-deg 1e-50 " EXAMPLE,
                        "--plane-tilt-deg: 1e-50 degrees is too small for the pose");
    expect_option_error(GEO " --rows 463 " EXAMPLE, "--rows and --cols go together");
    expect_option_error(GEO " --report-coasting " EXAMPLE, "--report-coasting needs --track");
    /* a bearing table overrides the flag (geometry.h): it was silently ignored */
    expect_option_error("--min-range 0.1 --max-range 1.5 --bearings b.txt --azimuth-ascending "
                        EXAMPLE, "--azimuth-ascending does not apply with --bearings");
    expect_option_error(GEO " --stride 700 " EXAMPLE, "--depth and --stride describe raw frames");
    /* a plane given with an unnormalised normal: the same pose */
    TEST_ASSERT_EQUAL_INT(0, run(GEO " --pose --plane 0,0,1,-0.03 --plane-sd 0.005 " EXAMPLE));
    e = out_text();
    TEST_ASSERT_EQUAL_INT(0, run(GEO " --pose --plane 0,0,4,-0.12 --plane-sd 0.005 " EXAMPLE));
    {
        char *o2 = out_text(), *p1 = strstr(e, "pose:"), *p2 = strstr(o2, "pose:");
        TEST_ASSERT_NOT_NULL(p1);
        TEST_ASSERT_NOT_NULL(p2);
        TEST_ASSERT_EQUAL_STRING(p1, p2);
        free(o2);
    }
    free(e);
    /* raw layout options with a PGM: read as the PGM, and said so (a
     * warning, as the status is 0) */
    TEST_ASSERT_EQUAL_INT(0, run(GEO " --rows 530 --cols 512 " EXAMPLE));
    e = err_text();
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(e, "actag_detect: warning: "), e);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(e, "a PGM of 620 x 463, 8 bit: --rows/--cols/--depth/"
                                           "--stride (raw frames) do not apply to it; read as "
                                           "the PGM"), e);
    free(e);
    /* two frames in one stream: an error, not the first frame alone */
    snprintf(args, sizeof args, GEO " - < \"%s/two_frames.pgm\"", ACTAG_BINARY_DIR);
    {
        char path[600], cmd[2000];
        snprintf(path, sizeof path, "%s/two_frames.pgm", ACTAG_BINARY_DIR);
        snprintf(cmd, sizeof cmd, "cat \"%s\" \"%s\" > \"%s\"", EXAMPLE, EXAMPLE, path);
        TEST_ASSERT_EQUAL_INT(0, system(cmd));
    }
    TEST_ASSERT_EQUAL_INT(2, run(args));
    e = err_text();
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(e, "stdin: 287075 bytes after the PGM's 287060 pixel bytes "
                                           "(one frame per file)"), e);
    free(e);
    /* --track with frames of another size than the first: named with both
     * sizes (the tracker's refusal said "invalid image size or stride") */
    {
        char path[600];
        static const char head[] = "P5 32 32 255\n";
        static uint8_t small[sizeof head - 1 + 32 * 32];
        memcpy(small, head, sizeof head - 1);
        snprintf(path, sizeof path, "%s/track32.pgm", ACTAG_BINARY_DIR);
        write_file(path, small, sizeof small);
        snprintf(args, sizeof args, GEO " --track \"%s\" " EXAMPLE, path);
        TEST_ASSERT_EQUAL_INT(2, run(args));
        e = err_text();
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(e, "actag_detect: " EXAMPLE ": 620 x 463 frame in a "
                                               "--track stream of 32 x 32 frames"), e);
        free(e);
    }
    /* results that cannot be written: status 2 and a message */
    f = fopen("/dev/full", "w");
    if (!f)
        TEST_IGNORE_MESSAGE("no /dev/full");
    fclose(f);
    {
        char cmd[2000];
        int st;
        snprintf(cmd, sizeof cmd, "\"%s\" " GEO " --json " EXAMPLE " > /dev/full 2> \"%s/full_err.txt\"",
                 ACTAG_DETECT_PATH, ACTAG_BINARY_DIR);
        st = system(cmd);
        TEST_ASSERT_TRUE(st != -1 && WIFEXITED(st));
        TEST_ASSERT_EQUAL_INT(2, WEXITSTATUS(st));
        snprintf(cmd, sizeof cmd, "%s/full_err.txt", ACTAG_BINARY_DIR);
        e = slurp(cmd);
        TEST_ASSERT_NOT_NULL(strstr(e, "actag_detect: standard output: write error"));
        free(e);
    }
}

/* --report-coasting: the example frame three times, then a blank frame of
 * its size: the track is reported there, coasting, only with the option
 * (track.h report_coasting); the frames before are reported the same. */
static void test_report_coasting(void)
{
    static const char head[] = "P5 620 463 255\n";
    static uint8_t blank[sizeof head - 1 + 620 * 463];
    char path[600], args[2000];
    char *plain, *asked, *p4, *a4;
    memcpy(blank, head, sizeof head - 1);
    snprintf(path, sizeof path, "%s/blank620x463.pgm", ACTAG_BINARY_DIR);
    write_file(path, blank, sizeof blank);
    snprintf(args, sizeof args, GEO " --track --json " EXAMPLE " " EXAMPLE " " EXAMPLE " \"%s\"",
             path);
    TEST_ASSERT_EQUAL_INT(0, run(args));
    plain = out_text();
    snprintf(args, sizeof args,
             GEO " --track --report-coasting --json " EXAMPLE " " EXAMPLE " " EXAMPLE " \"%s\"",
             path);
    TEST_ASSERT_EQUAL_INT(0, run(args));
    asked = out_text();
    p4 = strstr(plain, "\"frame\": 3,");
    a4 = strstr(asked, "\"frame\": 3,");
    TEST_ASSERT_NOT_NULL(p4);
    TEST_ASSERT_NOT_NULL(a4);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(p4, "\"tracks\": [],"), p4);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(a4, "\"tracks\": [{\"track\": 1, \"id\": 0, "
                                            "\"mirrored\": true, \"measured\": false, "
                                            "\"hits\": 3, \"missed\": 1,"), a4);
    /* the three frames before: the same lines, up to the time taken */
    {
        const char *a = plain, *b = asked;
        int k;
        for (k = 0; k < 3; k++) {
            const char *ta = strstr(a, "\"time_ms\""), *tb = strstr(b, "\"time_ms\"");
            TEST_ASSERT_NOT_NULL(ta);
            TEST_ASSERT_NOT_NULL(tb);
            TEST_ASSERT_EQUAL_INT((int)(ta - a), (int)(tb - b));
            TEST_ASSERT_EQUAL_INT(0, strncmp(a, b, (size_t)(ta - a)));
            a = strchr(ta, '\n');
            b = strchr(tb, '\n');
            TEST_ASSERT_NOT_NULL(a);
            TEST_ASSERT_NOT_NULL(b);
        }
    }
    free(plain);
    free(asked);
}

static void test_version(void)
{
    char *o;
    TEST_ASSERT_EQUAL_INT(0, run("--version"));
    o = out_text();
    TEST_ASSERT_EQUAL_STRING("actag_detect " ACTAG_VERSION_STRING "\n", o);
    free(o);
}

/* --check-geometry (geometry_check.h): on the example frame the aperture it
 * finds is the same whatever aperture was stated (the corners' pixels move
 * by under a pixel, their azimuths scale), and so is the tag size; its
 * median chi2 of one tag is the chi2 --pose prints, and a --plane given for
 * --pose does not enter it; the text has three lines; no tag in any file
 * and --track are errors (exit 2, one message; with --json an error line
 * too). Ground truth: tools/sim/test_check_geometry.c. */
static double gc_num(const char *s, const char *key)
{
    char pat[64];
    const char *p = strstr(s, "{\"geometry_check\": ");
    TEST_ASSERT_NOT_NULL_MESSAGE(p, s);
    snprintf(pat, sizeof pat, "\"%s\": ", key);
    p = strstr(p, pat);
    TEST_ASSERT_NOT_NULL_MESSAGE(p, key);
    return atof(p + strlen(pat));
}

static void test_check_geometry(void)
{
    static const char *const stated[3] = {"--aperture-deg 60", "--aperture-deg 54",
                                          "--aperture-deg 60 --tag-size 0.12"};
    double ap[3], size[3], chi2 = -1.0;
    char args[512], *o, *e, *p;
    unsigned char blank[13 + 64 * 64];
    int k;
    for (k = 0; k < 3; k++) {
        snprintf(args, sizeof args, "--check-geometry --json --min-range 0.1 --max-range 1.5 %s %s",
                 stated[k], EXAMPLE);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), args);
        o = out_text();
        TEST_ASSERT_EQUAL_INT(2, count_lines(o)); /* the frame's line, then the check */
        TEST_ASSERT_EQUAL_INT(1, (int)gc_num(o, "tags"));
        ap[k] = gc_num(o, "aperture_deg");
        size[k] = gc_num(o, "tag_size");
        if (k == 0)
            chi2 = gc_num(o, "median_chi2");
        TEST_ASSERT_EQUAL_INT(1, (int)gc_num(o, "fitted"));
        free(o);
    }
    TEST_ASSERT_FLOAT_WITHIN(0.3f, (float)ap[0], (float)ap[1]);
    TEST_ASSERT_FLOAT_WITHIN(0.002f, (float)size[0], (float)size[2]);
    /* the example frame is not at its published geometry either (docs/pose.md) */
    TEST_ASSERT_TRUE(chi2 > 3.0 && ap[0] > 55.0 && ap[0] < 59.0);
    TEST_ASSERT_EQUAL_INT(0, run("--json --pose " GEO " " EXAMPLE));
    o = out_text();
    p = strstr(o, "\"chi2\": ");
    TEST_ASSERT_NOT_NULL(p);
    TEST_ASSERT_FLOAT_WITHIN(0.002f, (float)chi2, (float)atof(p + 8));
    free(o);

    TEST_ASSERT_EQUAL_INT(0, run("--check-geometry " GEO " " EXAMPLE));
    o = out_text();
    TEST_ASSERT_EQUAL_INT(4, count_lines(o));
    TEST_ASSERT_NOT_NULL(strstr(o, "geometry check: 1 tags (1 with a pose), median pose chi2 "));
    TEST_ASSERT_NOT_NULL(strstr(o, "with the azimuths x "));
    TEST_ASSERT_NOT_NULL(strstr(o, "degrees)"));
    TEST_ASSERT_NOT_NULL(strstr(o, "with the tag size x "));
    free(o);
    TEST_ASSERT_EQUAL_INT(0, run("--check-geometry --json --pose --plane 0,0,1,-0.3 --plane-sd 0.02 "
                                 "--plane-tilt-deg 1 " GEO " " EXAMPLE));
    o = out_text();
    TEST_ASSERT_EQUAL_FLOAT((float)chi2, (float)gc_num(o, "median_chi2"));
    TEST_ASSERT_EQUAL_FLOAT((float)ap[0], (float)gc_num(o, "aperture_deg"));
    free(o);

    memcpy(blank, "P5\n64 64\n255\n", 13);
    memset(blank + 13, 0, 64 * 64);
    write_file(OUT "_blank.pgm", blank, sizeof blank);
    TEST_ASSERT_EQUAL_INT(2, run("--check-geometry --json " GEO " " OUT "_blank.pgm"));
    e = err_text();
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(e, "--check-geometry: no tag was found in the files read"), e);
    free(e);
    o = out_text();
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(o, "{\"geometry_check\": {\"error\": \"no tag was found"), o);
    free(o);
    expect_option_error(GEO " --check-geometry --track " EXAMPLE, "--check-geometry does not combine");
    TEST_ASSERT_EQUAL_INT(0, run("--check-geometry --vertical-aperture-deg 20 " GEO " " EXAMPLE));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_json_on_example);
    RUN_TEST(test_text_output_convention);
    RUN_TEST(test_raw_and_16bit_inputs);
    RUN_TEST(test_stdin_gives_the_same_json);
    RUN_TEST(test_overlay_and_stages);
    RUN_TEST(test_overlay_never_overwrites_an_input);
    RUN_TEST(test_overlay_extreme_geometry);
    RUN_TEST(test_show_rejected_changes_the_overlay);
    RUN_TEST(test_same_named_files_do_not_overwrite);
    RUN_TEST(test_bad_files_are_reported_and_the_rest_processed);
    RUN_TEST(test_bearing_table_file);
    RUN_TEST(test_bad_options);
    RUN_TEST(test_min_bit_margin_option);
    RUN_TEST(test_min_bit_odds_option);
    RUN_TEST(test_level_noise_options);
    RUN_TEST(test_pose_plane_options);
    RUN_TEST(test_options_that_need_others);
    RUN_TEST(test_report_coasting);
    RUN_TEST(test_version);
    RUN_TEST(test_check_geometry);
    return UNITY_END();
}
