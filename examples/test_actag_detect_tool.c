/* The actag_detect example as a user runs it: PGM (8/16-bit) and raw input
 * with strides and orientation flags, --json (one line per file, errors
 * included), --overlay and --stages outputs, and bad input (exit status 2,
 * one line naming the file, the remaining files still processed). */
#define _POSIX_C_SOURCE 200809L
#include "unity.h"
#include "../tests/test_util.h"

#include <sys/wait.h>

void setUp(void) {}
void tearDown(void) {}

#define GEO "--min-range 0.1 --max-range 1.5 --aperture-deg 60 --family AcTag24h10"
#define EXAMPLE ACTAG_SOURCE_DIR "/data/exampleSonarImage.pgm"

static char out_path[512], err_path[512];

/* Runs the tool with args; stdout/stderr go to files. Returns exit status. */
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

static int count_lines(const char *s)
{
    int n = 0;
    for (; *s; s++)
        n += *s == '\n';
    return n;
}

/* First detection's corners_px from a JSON line; returns the id or -1. */
static int parse_first(const char *line, float rc[4][2])
{
    const char *p = strstr(line, "\"id\": ");
    int id, c;
    if (!p || sscanf(p, "\"id\": %d", &id) != 1)
        return -1;
    p = strstr(p, "\"corners_px\": [");
    if (!p)
        return -1;
    p += strlen("\"corners_px\": [");
    for (c = 0; c < 4; c++) {
        if (sscanf(p, " [%f, %f]", &rc[c][0], &rc[c][1]) != 2)
            return -1;
        p = strchr(p, ']') + 1;
        if (*p == ',')
            p++;
    }
    return id;
}

static const float ref_rc[4][2] = {{145, 314}, {113, 339}, {103, 280}, {133, 244}};

static void assert_reference_tag(const char *json_line)
{
    float rc[4][2];
    int c;
    TEST_ASSERT_EQUAL_INT(0, parse_first(json_line, rc));
    TEST_ASSERT_NULL_MESSAGE(strstr(strstr(json_line, "\"id\": ") + 1, "\"id\": "),
                             "more than one detection");
    for (c = 0; c < 4; c++) {
        TEST_ASSERT_FLOAT_WITHIN(2.0f, ref_rc[c][0], rc[c][0]);
        TEST_ASSERT_FLOAT_WITHIN(2.0f, ref_rc[c][1], rc[c][1]);
    }
}

static void test_json_on_example(void)
{
    char *o;
    TEST_ASSERT_EQUAL_INT(0, run("--json " GEO " " EXAMPLE));
    o = tu_slurp(out_path, NULL);
    TEST_ASSERT_NOT_NULL(o);
    TEST_ASSERT_EQUAL_INT(1, count_lines(o));
    TEST_ASSERT_EQUAL_INT(0, strncmp(o, "{\"file\": \"", 10));
    TEST_ASSERT_NOT_NULL(strstr(o, "\"rows\": 463, \"cols\": 620, \"detections\": [{"));
    TEST_ASSERT_NOT_NULL(strstr(o, "\"corners_polar\": [["));
    TEST_ASSERT_NOT_NULL(strstr(o, "\"mirrored\": "));
    TEST_ASSERT_NOT_NULL(strstr(o, "\"time_ms\": "));
    assert_reference_tag(o);
    free(o);
}

static void write_file(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    TEST_ASSERT_NOT_NULL(f);
    TEST_ASSERT_EQUAL_UINT(n, fwrite(data, 1, n, f));
    fclose(f);
}

/* Raw frames: stride padding, 16-bit little-endian, orientation flags. */
static void test_raw_and_16bit_inputs(void)
{
    int rows = 0, cols = 0, r, c, stride = 631;
    uint8_t *img = tu_read_pgm(EXAMPLE, &rows, &cols), *raw;
    uint16_t *raw16;
    char path[600], args[1400], *o;
    TEST_ASSERT_NOT_NULL(img);
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
    o = tu_slurp(out_path, NULL);
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
    o = tu_slurp(out_path, NULL);
    {
        float rc[4][2];
        TEST_ASSERT_EQUAL_INT(0, parse_first(o, rc));
        for (c = 0; c < 4; c++) {
            TEST_ASSERT_FLOAT_WITHIN(2.5f, (float)(rows - 1) - ref_rc[c][0], rc[c][0]);
            TEST_ASSERT_FLOAT_WITHIN(2.5f, (float)(cols - 1) - ref_rc[c][1], rc[c][1]);
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
    o = tu_slurp(out_path, NULL);
    TEST_ASSERT_NOT_NULL(strstr(o, "\"id\": 0"));
    free(o);
    /* 16-bit PGM (big-endian samples) */
    {
        FILE *f;
        snprintf(path, sizeof path, "%s/example16.pgm", ACTAG_BINARY_DIR);
        f = fopen(path, "wb");
        TEST_ASSERT_NOT_NULL(f);
        fprintf(f, "P5\n# 16-bit copy\n%d %d\n65535\n", cols, rows);
        for (r = 0; r < rows * cols; r++) {
            unsigned v = img[r] * 257u;
            fputc((int)(v >> 8), f);
            fputc((int)(v & 0xff), f);
        }
        fclose(f);
        snprintf(args, sizeof args, "--json " GEO " %s", path);
        TEST_ASSERT_EQUAL_INT(0, run(args));
        o = tu_slurp(out_path, NULL);
        TEST_ASSERT_NOT_NULL(strstr(o, "\"id\": 0"));
        free(o);
    }
    free(raw16);
    free(raw);
    free(img);
}

static void test_overlay_and_stages(void)
{
    char args[1400], path[700], *s;
    int i;
    static const char *const stage[3] = {"1-input", "2-median", "3-threshold"};
    snprintf(args, sizeof args, GEO " --overlay %s/ov.ppm --stages %s " EXAMPLE, ACTAG_BINARY_DIR,
             ACTAG_BINARY_DIR);
    TEST_ASSERT_EQUAL_INT(0, run(args));
    s = tu_slurp(out_path, NULL);
    TEST_ASSERT_NOT_NULL(strstr(s, "id 0"));
    free(s);
    snprintf(path, sizeof path, "%s/ov.ppm", ACTAG_BINARY_DIR);
    s = tu_slurp(path, NULL);
    TEST_ASSERT_NOT_NULL(s);
    TEST_ASSERT_EQUAL_INT(0, strncmp(s, "P6\n620 463\n255\n", 15));
    free(s);
    for (i = 0; i < 3; i++) {
        snprintf(path, sizeof path, "%s/exampleSonarImage.pgm-%s.pgm", ACTAG_BINARY_DIR, stage[i]);
        s = tu_slurp(path, NULL);
        TEST_ASSERT_NOT_NULL_MESSAGE(s, path);
        TEST_ASSERT_EQUAL_INT(0, strncmp(s, "P5\n620 463\n255\n", 15));
        free(s);
    }
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
    o = tu_slurp(out_path, NULL);
    e = tu_slurp(err_path, NULL);
    TEST_ASSERT_EQUAL_INT(5, count_lines(o)); /* one JSON line per input file */
    TEST_ASSERT_EQUAL_INT(4, count_lines(e)); /* one message per bad file */
    TEST_ASSERT_NOT_NULL(strstr(e, "truncated.pgm: "));
    TEST_ASSERT_NOT_NULL(strstr(e, "/nonexistent/x.pgm: "));
    TEST_ASSERT_NOT_NULL(strstr(e, "ascii.pgm: "));
    TEST_ASSERT_NOT_NULL(strstr(e, "notanimage.bin: "));
    TEST_ASSERT_NOT_NULL(strstr(o, "\"error\": "));
    assert_reference_tag(strstr(o, "exampleSonarImage"));
    free(o);
    free(e);
    /* raw frame of the wrong size */
    snprintf(args, sizeof args, GEO " --rows 10 --cols 10 %s", p3);
    TEST_ASSERT_EQUAL_INT(2, run(args));
    e = tu_slurp(err_path, NULL);
    TEST_ASSERT_NOT_NULL(strstr(e, "raw frame is 5 bytes"));
    free(e);
}

/* A per-beam bearing table equal to the uniform 60-degree fan gives the
 * same detection; a table of the wrong length is a per-file error. */
static void test_bearing_table_file(void)
{
    char path[600], args[1400], *a, *b;
    FILE *f;
    int c;
    snprintf(path, sizeof path, "%s/bearings620.txt", ACTAG_BINARY_DIR);
    f = fopen(path, "w");
    TEST_ASSERT_NOT_NULL(f);
    for (c = 0; c < 620; c++)
        fprintf(f, "%.9f\n", 0.5 * 1.0471975512 - c * 1.0471975512 / 619.0);
    fclose(f);
    TEST_ASSERT_EQUAL_INT(0, run("--json " GEO " " EXAMPLE));
    a = tu_slurp(out_path, NULL);
    snprintf(args, sizeof args,
             "--json --min-range 0.1 --max-range 1.5 --family AcTag24h10 --bearings %s " EXAMPLE, path);
    TEST_ASSERT_EQUAL_INT(0, run(args));
    b = tu_slurp(out_path, NULL);
    TEST_ASSERT_NOT_NULL(a);
    TEST_ASSERT_NOT_NULL(b);
    assert_reference_tag(b);
    /* same corners and polar values (time_ms differs) */
    TEST_ASSERT_EQUAL_MEMORY(a, b, (size_t)(strstr(a, "\"time_ms\"") - a));
    free(a);
    free(b);
    f = fopen(path, "w");
    TEST_ASSERT_NOT_NULL(f);
    for (c = 0; c < 100; c++)
        fprintf(f, "%f\n", 0.5 - c * 0.01);
    fclose(f);
    TEST_ASSERT_EQUAL_INT(2, run(args));
    a = tu_slurp(err_path, NULL);
    TEST_ASSERT_NOT_NULL(strstr(a, "bearing table has 100 values, the frame has 620 columns"));
    free(a);
}

static void test_bad_options(void)
{
    TEST_ASSERT_EQUAL_INT(2, run("--min-range 0.1 --max-range 1.5 --aperture-deg 60 --family Nope " EXAMPLE));
    TEST_ASSERT_EQUAL_INT(2, run(GEO " --bit-corrections 5 " EXAMPLE)); /* h10 allows 4 */
    TEST_ASSERT_EQUAL_INT(2, run("--min-range 0.1 --aperture-deg 60 " EXAMPLE)); /* no max range */
    TEST_ASSERT_EQUAL_INT(2, run("--min-range 0.1 --max-range 1.5 " EXAMPLE));   /* no aperture */
    TEST_ASSERT_EQUAL_INT(2, run(GEO " --frobnicate " EXAMPLE));
    TEST_ASSERT_EQUAL_INT(2, run(GEO " --median-radius x " EXAMPLE));
    TEST_ASSERT_EQUAL_INT(2, run(GEO));
    TEST_ASSERT_EQUAL_INT(2, run("--min-range 2 --max-range 1.5 --aperture-deg 60 " EXAMPLE));
    TEST_ASSERT_EQUAL_INT(0, run("--help"));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_json_on_example);
    RUN_TEST(test_raw_and_16bit_inputs);
    RUN_TEST(test_overlay_and_stages);
    RUN_TEST(test_bad_files_are_reported_and_the_rest_processed);
    RUN_TEST(test_bearing_table_file);
    RUN_TEST(test_bad_options);
    return UNITY_END();
}
