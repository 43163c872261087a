/* The host I/O library's frame reader (PGM by magic, raw by layout, errors
 * naming the file and value), folder creation, number lists, PPM writer,
 * JSON strings and the output guard (hostio_out). */
#define _POSIX_C_SOURCE 200809L
#include "unity.h"
#include "hostio.h"

#include "actag/actag.h"

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <signal.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

void setUp(void) {}
void tearDown(void) {}

#define DIR ACTAG_BINARY_DIR "/hostio_test"

static void put(const char *name, const void *data, size_t n)
{
    char err[HOSTIO_ERRLEN], path[512];
    snprintf(path, sizeof path, DIR "/%s", name);
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_write_file(path, data, n, err), err);
}

static void expect_error(const char *name, const hostio_raw_spec *raw, const char *msg)
{
    char err[HOSTIO_ERRLEN], path[512], m[700];
    hostio_image im;
    snprintf(path, sizeof path, DIR "/%s", name);
    TEST_ASSERT_EQUAL_INT_MESSAGE(-1, hostio_frame_read(path, raw, &im, err), name);
    snprintf(m, sizeof m, "expected '%s' in '%s'", msg, err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, msg), m);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, name), m); /* names the file */
    TEST_ASSERT_NULL(im.data);
}

static void test_frames(void)
{
    static const uint8_t pgm8[] = "P5\n# c\n3 2\n255\n\x01\x02\x03\x04\x05\x06";
    static const uint8_t pgm16[] = "P5 2 1 65535 \x01\x02\xff\xfe";
    static const uint8_t raw16[] = {1, 2, 3, 4, 0xaa, 0xbb, 5, 6, 7, 8};
    char err[HOSTIO_ERRLEN];
    hostio_image im;
    hostio_raw_spec raw = {2, 2, 16, 3}; /* 2 x 2, stride 3, 16-bit */
    actag_frame fr;
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_mkdirs(DIR, err));
    put("a.pgm", pgm8, sizeof pgm8 - 1);
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_frame_read(DIR "/a.pgm", &raw, &im, err), err);
    TEST_ASSERT_EQUAL_INT(2, im.rows);
    TEST_ASSERT_EQUAL_INT(3, im.cols);
    TEST_ASSERT_EQUAL_INT(8, im.depth);
    TEST_ASSERT_EQUAL_UINT8(6, ((uint8_t *)im.data)[5]);
    hostio_image_frame(&im, &fr); /* the library's view of it */
    TEST_ASSERT_TRUE(fr.data == im.data);
    TEST_ASSERT_EQUAL_INT(2, fr.rows);
    TEST_ASSERT_EQUAL_INT(3, fr.cols);
    TEST_ASSERT_EQUAL_INT(3, fr.stride);
    TEST_ASSERT_EQUAL_INT(8, fr.depth);
    hostio_image_free(&im);
    put("b.pgm", pgm16, sizeof pgm16 - 1);
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_frame_read(DIR "/b.pgm", NULL, &im, err), err);
    TEST_ASSERT_EQUAL_INT(16, im.depth);
    TEST_ASSERT_EQUAL_UINT16(0x0102, ((uint16_t *)im.data)[0]); /* big-endian in the file */
    TEST_ASSERT_EQUAL_UINT16(0xfffe, ((uint16_t *)im.data)[1]);
    hostio_image_free(&im);
    /* raw, little-endian, stride 3; the last row's padding may be absent */
    put("c.raw", raw16, sizeof raw16);
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_frame_read(DIR "/c.raw", &raw, &im, err), err);
    TEST_ASSERT_EQUAL_INT(3, im.stride);
    TEST_ASSERT_EQUAL_UINT16(0x0201, ((uint16_t *)im.data)[0]);
    TEST_ASSERT_EQUAL_UINT16(0x0403, ((uint16_t *)im.data)[1]);
    TEST_ASSERT_EQUAL_UINT16(0x0605, ((uint16_t *)im.data)[3]);
    TEST_ASSERT_EQUAL_UINT16(0x0807, ((uint16_t *)im.data)[4]);
    hostio_image_free(&im);
    /* errors name the file and the value */
    expect_error("c.raw", NULL, "c.raw: not a PGM file (no P5 magic)");
    {   /* a tool that reads raw frames names the options they need */
        hostio_raw_spec none = {0, 0, 8, 0};
        expect_error("c.raw", &none,
                     "not a PGM file (no P5 magic); raw frames need --rows and --cols");
    }
    raw.stride = 0;
    expect_error("c.raw", &raw, "raw frame is 10 bytes, expected 8 (2 rows x stride 2 x 2 bytes)");
    raw.stride = 1;
    expect_error("c.raw", &raw, "raw stride 1 is smaller than the 2 columns");
    put("d.pgm", "P2\n1 1\n255\n0\n", 12);
    expect_error("d.pgm", &raw, "a P2 image: only binary PGM (P5) is supported");
    put("e.pgm", "P5\n4 4\n0\n", 9);
    expect_error("e.pgm", NULL, "PGM maxval '0' is not a whole number in 1..65535");
    expect_error("missing.pgm", NULL, "No such file");
}

static void test_mkdirs(void)
{
    char err[HOSTIO_ERRLEN];
    struct stat sb;
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_mkdirs(DIR "/x/y//z/", err), err);
    TEST_ASSERT_EQUAL_INT(0, stat(DIR "/x/y/z", &sb));
    TEST_ASSERT_TRUE(S_ISDIR(sb.st_mode));
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_mkdirs(DIR "/x/y/z", err)); /* exists: fine */
    put("file", "x", 1);
    TEST_ASSERT_EQUAL_INT(-1, hostio_mkdirs(DIR "/file", err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "file: exists and is not a folder"), err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_mkdirs(DIR "/file/sub", err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "file/sub: cannot create folder"), err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_mkdirs("", err));
}

static void test_lists(void)
{
    char err[HOSTIO_ERRLEN];
    double v[4];
    int n = 0;
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_parse_list("t", " 1, -2.5\n3e-1\t", v, 4, &n, err));
    TEST_ASSERT_EQUAL_INT(3, n);
    TEST_ASSERT_FLOAT_WITHIN(1e-9f, -2.5f, (float)v[1]);
    TEST_ASSERT_FLOAT_WITHIN(1e-7f, 0.3f, (float)v[2]);
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_parse_list("t", "1 2 3 4 5 6", v, 4, &n, err));
    TEST_ASSERT_EQUAL_INT(5, n); /* more than cap: cap + 1 */
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_parse_list("t", "", v, 4, &n, err));
    TEST_ASSERT_EQUAL_INT(0, n);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_list("tab.txt", "1 2x 3", v, 4, &n, err));
    TEST_ASSERT_EQUAL_STRING("tab.txt: value 2 is not a finite number (got '2x')", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_list("tab.txt", "1 inf", v, 4, &n, err));
    TEST_ASSERT_EQUAL_STRING("tab.txt: value 2 is not a finite number (got 'inf')", err);
    /* a binary file's bytes are not written into the message */
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_list("bin", "\x7f" "ELF\x02\x01\xff,1", v, 4, &n, err));
    TEST_ASSERT_EQUAL_STRING("bin: value 1 is not a finite number (got '?ELF\?\?\?')", err);
}

static void test_ppm(void)
{
    static const uint8_t rgb[2 * 3 * 3] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18};
    char err[HOSTIO_ERRLEN];
    size_t len;
    uint8_t *s;
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_ppm_write(DIR "/p.ppm", rgb, 2, 3, err));
    s = hostio_slurp(DIR "/p.ppm", &len, err);
    TEST_ASSERT_NOT_NULL(s);
    TEST_ASSERT_EQUAL_UINT(11 + sizeof rgb, len);
    TEST_ASSERT_EQUAL_MEMORY("P6\n3 2\n255\n", s, 11);
    TEST_ASSERT_EQUAL_MEMORY(rgb, s + 11, sizeof rgb);
    free(s);
    TEST_ASSERT_EQUAL_INT(-1, hostio_ppm_write(DIR "/nofolder/p.ppm", rgb, 2, 3, err));
    TEST_ASSERT_NOT_NULL(strstr(err, "nofolder/p.ppm: cannot write"));
    TEST_ASSERT_EQUAL_STRING("stdin", hostio_frame_name("-"));
    TEST_ASSERT_EQUAL_STRING("a/b", hostio_frame_name("a/b"));
}

/* Library details in option names: the plain form, two fields, an array
 * entry, names inside the rule, a scaled unit, an unmapped field. */
static void test_detail_messages(void)
{
    static const hostio_optname map[] = {
        {"tag_size", "--tag-size", 0},
        {"geometry.min_range", "--min-range", 0},
        {"geometry.max_range", "--max-range", 0},
        {"geometry.aperture", "--aperture-deg", 57.29577951308232},
        {"geometry.bearings", "--bearings", 0},
    };
    const int n = (int)(sizeof map / sizeof map[0]);
    char err[HOSTIO_ERRLEN];
    actag_family fam;
    actag_params p;
    actag_sonar_geometry g = {0.1f, 1.5f, 1.0472f, NULL, 0u};
    static const uint8_t px[4] = {0, 0, 0, 0};
    actag_frame f = {px, 2, 2, 2, 8};
    float b[2] = {0.5f, 0.5f};
    actag_error_detail d;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
    actag_params_default(&p);
    p.family = &fam;
    p.tag_size = 0.0f;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_check(&f, &g, &p, SIZE_MAX, 4, &d));
    TEST_ASSERT_EQUAL_INT(0, hostio_detail_message(&d, map, n, err));
    TEST_ASSERT_EQUAL_STRING("--tag-size: must be a finite number > 0 (metres) (got 0)", err);
    p.tag_size = 0.13f;
    g.min_range = 2.0f;
    actag_check(&f, &g, &p, SIZE_MAX, 4, &d);
    hostio_detail_message(&d, map, n, err);
    TEST_ASSERT_EQUAL_STRING("--min-range/--max-range: must be below --max-range (got 2, limit 1.5)",
                             err);
    g.min_range = 0.1f;
    g.aperture = 7.0f;
    actag_check(&f, &g, &p, SIZE_MAX, 4, &d);
    hostio_detail_message(&d, map, n, err);
    TEST_ASSERT_EQUAL_STRING("--aperture-deg: must be a number > 0 and < 2 pi (radians) (got "
                             "401.07)", err);
    g.bearings = b;
    actag_check(&f, &g, &p, SIZE_MAX, 4, &d);
    hostio_detail_message(&d, map, n, err);
    TEST_ASSERT_EQUAL_STRING("--bearings: value 2 must differ from the previous bearing (the "
                             "table must be strictly monotonic) (got 0.5 after 0.5)", err);
    g.bearings = NULL;
    g.aperture = 1.0f;
    p.tuning.quad.min_inlier_ratio = 1.5f; /* not in the map: the library's name */
    actag_check(&f, &g, &p, SIZE_MAX, 4, &d);
    hostio_detail_message(&d, map, n, err);
    TEST_ASSERT_EQUAL_STRING("tuning.quad.min_inlier_ratio: must be a number > 0 and <= 1 (got "
                             "1.5)", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_detail_message(NULL, map, n, err));
}

/* A raw frame whose first bytes happen to be "P5" (issue 10): with a raw
 * layout given and a file of that layout's size, it is read as raw; a PGM of
 * another size next to it is still a PGM. */
static void test_raw_frame_starting_with_p5(void)
{
    /* 4 x 4 8-bit raw: "P5 4 4 255\n" + 5 more bytes would parse as a PGM */
    static const uint8_t rawp5[16] = {'P', '5', ' ', '2', ' ', '1', ' ', '2', '5', '5', '\n',
                                      7, 8, 9, 10, 11};
    char err[HOSTIO_ERRLEN];
    hostio_image im;
    hostio_raw_spec raw = {4, 4, 8, 0};
    int i;
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_mkdirs(DIR, err));
    put("p5.raw", rawp5, sizeof rawp5);
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_frame_read(DIR "/p5.raw", &raw, &im, err), err);
    TEST_ASSERT_EQUAL_INT(4, im.rows);
    TEST_ASSERT_EQUAL_INT(4, im.cols);
    TEST_ASSERT_EQUAL_INT(8, im.depth);
    for (i = 0; i < 16; i++)
        TEST_ASSERT_EQUAL_UINT8(rawp5[i], ((uint8_t *)im.data)[i]);
    hostio_image_free(&im);
    /* without a raw layout the same bytes are a 2 x 1 PGM with 3 bytes over:
     * refused, not read with the rest dropped */
    TEST_ASSERT_EQUAL_INT(-1, hostio_frame_read(DIR "/p5.raw", NULL, &im, err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "3 bytes after the PGM's 2 pixel bytes"), err);
    TEST_ASSERT_NULL(im.data);
    /* the buffer form gives the same */
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK,
                                  hostio_frame_parse(rawp5, sizeof rawp5, "buf", &raw, &im, err), err);
    TEST_ASSERT_EQUAL_INT(4, im.rows);
    hostio_image_free(&im);
}

/* 8-bit PGM maxval (issue 10): samples of a maxval below 255 are scaled to
 * 0..255 like 16-bit frames are by the library; a sample above maxval is an
 * error naming it; maxval 255 is taken as is. */
static void test_pgm_8bit_maxval(void)
{
    static const uint8_t m100[] = "P5 4 1 100\n\x00\x01\x32\x64";   /* 0 1 50 100 */
    static const uint8_t m1[] = "P5 2 1 1\n\x00\x01";               /* a binary frame */
    static const uint8_t over[] = "P5 3 1 100\n\x00\x65\x01";       /* 101 > 100 */
    static const uint8_t over16[] = "P5 2 1 1000\n\x03\xe8\x03\xe9"; /* 1000, 1001 */
    static const uint8_t m255[] = "P5 2 1 255\n\x00\xff";
    char err[HOSTIO_ERRLEN];
    hostio_image im;
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_frame_parse(m100, sizeof m100 - 1, "m100.pgm", NULL, &im, err));
    TEST_ASSERT_EQUAL_INT(8, im.depth);
    TEST_ASSERT_EQUAL_INT(255, im.maxval);
    TEST_ASSERT_EQUAL_UINT8(0, ((uint8_t *)im.data)[0]);
    TEST_ASSERT_EQUAL_UINT8(3, ((uint8_t *)im.data)[1]);   /* (255 + 50) / 100 */
    TEST_ASSERT_EQUAL_UINT8(128, ((uint8_t *)im.data)[2]); /* (12750 + 50) / 100 */
    TEST_ASSERT_EQUAL_UINT8(255, ((uint8_t *)im.data)[3]);
    hostio_image_free(&im);
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_frame_parse(m1, sizeof m1 - 1, "m1.pgm", NULL, &im, err));
    TEST_ASSERT_EQUAL_UINT8(0, ((uint8_t *)im.data)[0]);
    TEST_ASSERT_EQUAL_UINT8(255, ((uint8_t *)im.data)[1]);
    hostio_image_free(&im);
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_frame_parse(m255, sizeof m255 - 1, "m255.pgm", NULL, &im, err));
    TEST_ASSERT_EQUAL_UINT8(255, ((uint8_t *)im.data)[1]);
    hostio_image_free(&im);
    TEST_ASSERT_EQUAL_INT(-1, hostio_frame_parse(over, sizeof over - 1, "over.pgm", NULL, &im, err));
    TEST_ASSERT_EQUAL_STRING("over.pgm: PGM sample 101 at row 0, column 1 is above maxval 100", err);
    TEST_ASSERT_NULL(im.data);
    TEST_ASSERT_EQUAL_INT(-1, hostio_frame_parse(over16, sizeof over16 - 1, "over16.pgm", NULL, &im, err));
    TEST_ASSERT_EQUAL_STRING("over16.pgm: PGM sample 1001 at row 0, column 1 is above maxval 1000", err);
}

/* A folder given as a file: the reason is named (it was "read error"). */
static void test_slurp_folder_names_the_reason(void)
{
    char err[HOSTIO_ERRLEN];
    hostio_image im;
    TEST_ASSERT_NULL(hostio_slurp(DIR, NULL, err));
    TEST_ASSERT_EQUAL_STRING(DIR ": Is a directory", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_frame_read(DIR, NULL, &im, err));
    TEST_ASSERT_EQUAL_STRING(DIR ": Is a directory", err);
}

/* hostio_slurp_text: a text file whole; a NUL byte inside is an error
 * naming its offset (it used to end the text silently: a bearing table
 * with a NUL after its 100th value read as a table of 100). */
static void test_slurp_text_refuses_nul(void)
{
    static const uint8_t bad[] = {'0', '.', '1', ' ', '0', '.', '2', 0, 'x', 'y'};
    char err[HOSTIO_ERRLEN];
    size_t len = 0;
    char *t;
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_mkdirs(DIR, err));
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_write_file(DIR "/text.txt", "0.1 0.2\n", 8, err));
    t = hostio_slurp_text(DIR "/text.txt", &len, err);
    TEST_ASSERT_NOT_NULL_MESSAGE(t, err);
    TEST_ASSERT_EQUAL_size_t(8, len);
    TEST_ASSERT_EQUAL_STRING("0.1 0.2\n", t);
    free(t);
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_write_file(DIR "/nul.txt", bad, sizeof bad, err));
    TEST_ASSERT_NULL(hostio_slurp_text(DIR "/nul.txt", &len, err));
    TEST_ASSERT_NOT_NULL(strstr(err, "nul.txt: byte 7 is a NUL byte"));
}

/* hostio_same_file: one file by two names (a path and the same path with
 * "./" parts), the same string, two different files, a missing file; two
 * spellings of one file not yet created are one file (two outputs of
 * actag-eval, --pose-dump out.jsonl --failures ./out.jsonl, were written
 * interleaved into it). */
static void test_same_file(void)
{
    char err[HOSTIO_ERRLEN];
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_mkdirs(DIR, err));
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_write_file(DIR "/a.txt", "a", 1, err));
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_write_file(DIR "/b.txt", "b", 1, err));
    TEST_ASSERT_EQUAL_INT(1, hostio_same_file(DIR "/a.txt", DIR "/./a.txt"));
    TEST_ASSERT_EQUAL_INT(1, hostio_same_file(DIR "/a.txt", DIR "/a.txt"));
    TEST_ASSERT_EQUAL_INT(0, hostio_same_file(DIR "/a.txt", DIR "/b.txt"));
    TEST_ASSERT_EQUAL_INT(0, hostio_same_file(DIR "/a.txt", DIR "/missing.txt"));
    TEST_ASSERT_EQUAL_INT(1, hostio_same_file(DIR "/missing.txt", DIR "/./missing.txt"));
    TEST_ASSERT_EQUAL_INT(1, hostio_same_file(DIR "/missing.txt", DIR "//missing.txt"));
    TEST_ASSERT_EQUAL_INT(0, hostio_same_file(DIR "/missing.txt", DIR "/missing2.txt"));
    TEST_ASSERT_EQUAL_INT(0, hostio_same_file(DIR "/missing.txt", DIR "/nodir/missing.txt"));
    TEST_ASSERT_EQUAL_INT(1, hostio_same_file("hostio_missing.txt", "./hostio_missing.txt"));
}

/* hostio_parse_bearings / hostio_read_bearings: the one bearing-table
 * reader of actag_detect and actag-sim (each had its own): exactly cols
 * numbers, whitespace or commas; the wrong count names the file and where
 * the columns come from. */
static void test_bearings(void)
{
    char err[HOSTIO_ERRLEN];
    float b[3];
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_parse_bearings("t.txt", "0.5, 0.1\n-0.25", 3,
                                                                   NULL, b, err), err);
    TEST_ASSERT_EQUAL_FLOAT(0.5f, b[0]);
    TEST_ASSERT_EQUAL_FLOAT(0.1f, b[1]);
    TEST_ASSERT_EQUAL_FLOAT(-0.25f, b[2]);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_bearings("t.txt", "0.5 0.1", 3, NULL, b, err));
    TEST_ASSERT_EQUAL_STRING("t.txt: bearing table has 2 values, the frame has 3 columns", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_bearings("t.txt", "4 3 2 1", 3, "--cols", b, err));
    TEST_ASSERT_EQUAL_STRING("t.txt: bearing table has more than 3 values, --cols is 3", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_bearings("t.txt", "0.5 x 1", 3, NULL, b, err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "t.txt: value 2"), err);
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_mkdirs(DIR, err));
    put("bearings.txt", "0.3\n0.2\n0.1\n", 12);
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_read_bearings(DIR "/bearings.txt", 3, "--cols",
                                                                  b, err), err);
    TEST_ASSERT_EQUAL_FLOAT(0.1f, b[2]);
    TEST_ASSERT_EQUAL_INT(-1, hostio_read_bearings(DIR "/missing.txt", 3, "--cols", b, err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "missing.txt"), err);
}

/* hostio_list_dir: the one folder scan of actag-eval --pool-sequence and
 * actag-sim --compare-real (each had its own): names by prefix and suffix,
 * longer than both, sorted; an empty match is a list of 0; a missing
 * folder is an error naming it. */
static void test_list_dir(void)
{
    char err[HOSTIO_ERRLEN];
    char **names;
    int n = -1;
    TEST_ASSERT_EQUAL_INT(0, system("rm -rf '" DIR "/list' && mkdir -p '" DIR "/list'"));
    put("list/f_0011.pgm", "x", 1);
    put("list/f_0001.pgm", "x", 1);
    put("list/f_.pgm", "x", 1);      /* nothing between prefix and suffix */
    put("list/g_0002.pgm", "x", 1);  /* another prefix */
    put("list/f_0003.pgm.txt", "x", 1);
    names = hostio_list_dir(DIR "/list", "f_", ".pgm", &n, err);
    TEST_ASSERT_NOT_NULL_MESSAGE(names, err);
    TEST_ASSERT_EQUAL_INT(2, n);
    TEST_ASSERT_EQUAL_STRING(DIR "/list/f_0001.pgm", names[0]);
    TEST_ASSERT_EQUAL_STRING(DIR "/list/f_0011.pgm", names[1]);
    hostio_list_free(names, n);
    names = hostio_list_dir(DIR "/list", "", ".pgm", &n, err);
    TEST_ASSERT_NOT_NULL_MESSAGE(names, err);
    TEST_ASSERT_EQUAL_INT(4, n);
    TEST_ASSERT_EQUAL_STRING(DIR "/list/f_.pgm", names[0]);
    TEST_ASSERT_EQUAL_STRING(DIR "/list/g_0002.pgm", names[3]);
    hostio_list_free(names, n);
    names = hostio_list_dir(DIR "/list", "", ".raw", &n, err);
    TEST_ASSERT_NOT_NULL_MESSAGE(names, err);
    TEST_ASSERT_EQUAL_INT(0, n);
    hostio_list_free(names, n);
    TEST_ASSERT_NULL(hostio_list_dir(DIR "/no-such-folder", "", ".pgm", &n, err));
    TEST_ASSERT_EQUAL_INT(0, n);
    TEST_ASSERT_EQUAL_STRING("cannot open folder '" DIR "/no-such-folder': No such file or directory",
                             err);
}

/* hostio_pgm_read (the pool frames of actag-eval --pool-sequence, actag-sim
 * --compare-real, the benchmarks) takes frames as hostio_frame_read does:
 * it copied samples as stored, so a maxval 100 frame with a sample of 200
 * passed and a maxval 100 frame was read unscaled. */
static void test_pgm_read_checks_maxval(void)
{
    static const uint8_t m100[] = "P5 4 1 100\n\x00\x01\x32\x64"; /* 0 1 50 100 */
    static const uint8_t over[] = "P5 2 1 100\n\x00\xc8";         /* 200 > 100 */
    static const uint8_t over16[] = "P5 2 1 1000\n\x03\xe8\x03\xe9"; /* 1000, 1001 */
    char err[HOSTIO_ERRLEN];
    hostio_image im;
    put("pr100.pgm", m100, sizeof m100 - 1);
    put("prover.pgm", over, sizeof over - 1);
    put("prover16.pgm", over16, sizeof over16 - 1);
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_pgm_read(DIR "/pr100.pgm", &im, err), err);
    TEST_ASSERT_EQUAL_INT(8, im.depth);
    TEST_ASSERT_EQUAL_INT(255, im.maxval);
    TEST_ASSERT_EQUAL_UINT8(3, ((uint8_t *)im.data)[1]);
    TEST_ASSERT_EQUAL_UINT8(128, ((uint8_t *)im.data)[2]);
    TEST_ASSERT_EQUAL_UINT8(255, ((uint8_t *)im.data)[3]);
    hostio_image_free(&im);
    TEST_ASSERT_EQUAL_INT(-1, hostio_pgm_read(DIR "/prover.pgm", &im, err));
    TEST_ASSERT_EQUAL_STRING(DIR "/prover.pgm: PGM sample 200 at row 0, column 1 is above maxval 100", err);
    TEST_ASSERT_NULL(im.data);
    TEST_ASSERT_EQUAL_INT(-1, hostio_pgm_read(DIR "/prover16.pgm", &im, err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "above maxval 1000"), err);
    TEST_ASSERT_NULL(im.data);
}

/* Raw size products (issue 10): 32767 rows x stride 2^20 x 2 bytes is 2^36
 * bytes, beyond a 32-bit long; the expected size is computed and reported
 * exactly (or, where size_t is 32 bits, the layout is refused as too large). */
/* hostio_json_string: quotes, '"' and '\\' escaped, control characters as
 * \u00XX, UTF-8 as it is, bytes that are not UTF-8 (a stray 0xff, a
 * truncated sequence, an overlong form, a surrogate) as \ufffd. */
/* hostio_json_num: the number as fmt prints it, or null for nothing
 * measured (whatever the value). */
static void test_json_num(void)
{
    char b[HOSTIO_JNUM_LEN], b2[HOSTIO_JNUM_LEN];
    TEST_ASSERT_EQUAL_STRING("0.2500", hostio_json_num(b, "%.4f", 0.25, 1));
    TEST_ASSERT_EQUAL_STRING("-3", hostio_json_num(b2, "%g", -3.0, 1));
    TEST_ASSERT_EQUAL_STRING("0.2500", b); /* each call its own buffer */
    TEST_ASSERT_EQUAL_STRING("null", hostio_json_num(b, "%.4f", 0.0, 0));
    TEST_ASSERT_EQUAL_STRING("null", hostio_json_num(b, "%.4f", 1.5, 0));
}

static void test_json_string(void)
{
    static const char in[] = "a\"b\\c\x01\td \xc3\xa9/\xff\xc3 \xc0\xaf\xed\xa0\x80\xf0\x9f\x98\x80";
    static const char want[] = "\"a\\\"b\\\\c\\u0001\\u0009d \xc3\xa9/\\ufffd\\ufffd "
                               "\\ufffd\\ufffd\\ufffd\\ufffd\\ufffd\xf0\x9f\x98\x80\"\"\""
                               /* overlong 3- and 4-byte forms, above U+10FFFF, cut at the end;
                                  U+10FFFF, U+FFFF and U+0080 themselves pass */
                               "\"\\ufffd\\ufffd\\ufffd|\\ufffd\\ufffd\\ufffd\\ufffd|"
                               "\\ufffd\\ufffd\\ufffd\\ufffd|\xf4\x8f\xbf\xbf\xef\xbf\xbf\xc2\x80|"
                               "\\ufffd\\ufffd\"";
    char err[HOSTIO_ERRLEN];
    size_t len = 0;
    uint8_t *got;
    FILE *f;
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_mkdirs(DIR, err));
    f = fopen(DIR "/json.txt", "w");
    TEST_ASSERT_NOT_NULL(f);
    hostio_json_string(f, in);
    hostio_json_string(f, "");
    hostio_json_string(f, "\xe0\x80\x80|\xf0\x80\x80\x80|\xf4\x90\x80\x80|"
                          "\xf4\x8f\xbf\xbf\xef\xbf\xbf\xc2\x80|\xe2\x82");
    TEST_ASSERT_EQUAL_INT(0, fclose(f));
    got = hostio_slurp(DIR "/json.txt", &len, err);
    TEST_ASSERT_NOT_NULL_MESSAGE(got, err);
    TEST_ASSERT_EQUAL_STRING(want, (const char *)got);
    TEST_ASSERT_EQUAL_size_t(sizeof want - 1, len);
    free(got);
}

static void test_raw_size_overflow(void)
{
    static const uint8_t small[64] = {0};
    char err[HOSTIO_ERRLEN];
    hostio_image im;
    hostio_raw_spec raw = {32767, 32767, 16, 1 << 20};
    TEST_ASSERT_EQUAL_INT(-1, hostio_frame_parse(small, sizeof small, "big.raw", &raw, &im, err));
    if (sizeof(size_t) >= 8)
        TEST_ASSERT_EQUAL_STRING("big.raw: raw frame is 64 bytes, expected 68717379584 (32767 "
                                 "rows x stride 1048576 x 2 bytes)",
                                 err);
    else
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "too large to address"), err);
    TEST_ASSERT_NULL(im.data);
    /* 32767 x 32767 8-bit: 1073676289 bytes, just under 2^30 */
    raw.depth = 8;
    raw.stride = 0;
    TEST_ASSERT_EQUAL_INT(-1, hostio_frame_parse(small, sizeof small, "big8.raw", &raw, &im, err));
    TEST_ASSERT_EQUAL_STRING("big8.raw: raw frame is 64 bytes, expected 1073676289 (32767 rows x "
                             "stride 32767 x 1 byte)",
                             err);
    /* out-of-range layouts are refused before any arithmetic */
    raw.rows = 40000;
    TEST_ASSERT_EQUAL_INT(-1, hostio_frame_parse(small, sizeof small, "r.raw", &raw, &im, err));
    TEST_ASSERT_EQUAL_STRING("r.raw: raw frame size 40000 x 32767 outside 1..32767", err);
}

static void test_parse_choice(void)
{
    static const char *const words[3] = {"any", "unmirrored", "mirrored"};
    char err[HOSTIO_ERRLEN];
    int i = -1;
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_parse_choice("--h", "mirrored", words, 3, &i, err));
    TEST_ASSERT_EQUAL_INT(2, i);
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_parse_choice("--h", "any", words, 3, &i, err));
    TEST_ASSERT_EQUAL_INT(0, i);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_choice("--h", "Mirrored", words, 3, &i, err));
    TEST_ASSERT_EQUAL_STRING("--h: must be any, unmirrored or mirrored (got 'Mirrored')", err);
    TEST_ASSERT_EQUAL_INT(0, i); /* unchanged on a miss */
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_choice("--h", "", words, 3, &i, err));
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_choice("--h", NULL, words, 3, &i, err));
    TEST_ASSERT_EQUAL_STRING("--h: missing value", err);
}

/* PGM header faults quote the text found (they once reported -1 for "abc"
 * and 1000000000 for 4294967296), and bytes after the frame are an error
 * (a second frame in one file was dropped silently). */
/* a string literal's bytes, without its terminating NUL */
#define PUT_TEXT(name, lit) put((name), (lit), sizeof(lit) - 1)

/* Seeds: the whole 32-bit range whatever the width of long (32-bit ARM
 * Linux), nothing negative, nothing that wraps. */
static void test_parse_u32(void)
{
    char err[HOSTIO_ERRLEN];
    uint32_t v = 7u;
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_parse_u32("--seed", "4294967295", 0u, 4294967295u, &v, err));
    TEST_ASSERT_EQUAL_UINT32(4294967295u, v);
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_parse_u32("--seed", "0", 0u, 4294967295u, &v, err));
    TEST_ASSERT_EQUAL_UINT32(0u, v);
    v = 7u;
    TEST_ASSERT_TRUE(hostio_parse_u32("--seed", "4294967296", 0u, 4294967295u, &v, err) != HOSTIO_OK);
    TEST_ASSERT_EQUAL_STRING("--seed: must be a whole number from 0 to 4294967295 (got 4294967296)", err);
    TEST_ASSERT_TRUE(hostio_parse_u32("--seed", "-1", 0u, 4294967295u, &v, err) != HOSTIO_OK);
    TEST_ASSERT_NOT_NULL(strstr(err, "(got -1)"));
    TEST_ASSERT_TRUE(hostio_parse_u32("--seed", " -5", 0u, 4294967295u, &v, err) != HOSTIO_OK);
    /* strtoull would read this one as 1 (the negation wraps) */
    TEST_ASSERT_TRUE(hostio_parse_u32("--seed", "\n-18446744073709551615", 0u, 4294967295u, &v,
                                      err) != HOSTIO_OK);
    TEST_ASSERT_TRUE(hostio_parse_u32("--seed", "1e3", 0u, 4294967295u, &v, err) != HOSTIO_OK);
    TEST_ASSERT_EQUAL_STRING("--seed: must be an integer (got '1e3')", err);
    TEST_ASSERT_TRUE(hostio_parse_u32("--seed", "", 0u, 4294967295u, &v, err) != HOSTIO_OK);
    TEST_ASSERT_TRUE(hostio_parse_u32("--seed", "99999999999999999999999", 0u, 4294967295u, &v,
                                      err) != HOSTIO_OK);
    /* beyond 64 bits (strtoull's ERANGE) is out of range, not "not an integer" */
    TEST_ASSERT_EQUAL_STRING("--seed: must be a whole number from 0 to 4294967295 "
                             "(got 99999999999999999999999)", err);
    TEST_ASSERT_TRUE(hostio_parse_u32("--n", "3", 5u, 9u, &v, err) != HOSTIO_OK);
    TEST_ASSERT_EQUAL_STRING("--n: must be a whole number from 5 to 9 (got 3)", err);
    TEST_ASSERT_TRUE(hostio_parse_u32("--seed", NULL, 0u, 1u, &v, err) != HOSTIO_OK);
    TEST_ASSERT_EQUAL_UINT32(7u, v); /* untouched by the failures */
}

/* Numbers in decimal only, the whole string the number: strtod read
 * "0x10", "0x1p-3" and " 5", strtol " 5" and "+5" (--decimate 0x10,
 * --tag-size " 5", --ids " 1", --bits " 24" were taken). */
static void test_parse_number_forms(void)
{
    static const char *const bad_double[] = {" 5", "\t5", "\n5", "+5", "+0.5", "0x10",
                                             "0X10", "0x1p-3", "-0x1p-3", "+0x10", "inf",
                                             "-inf", "INF", "infinity", "nan", "NAN", "-nan",
                                             "nan(1)", "5 ", "", "-", ".", "e3", NULL};
    static const char *const bad_long[] = {" 5", "\t5", "+5", "0x10", "0X10", "-0x10", "+0x10",
                                           "5 ", "inf", "nan", "", "-", "5.", "1e3", NULL};
    static const struct {
        const char *s;
        double v;
    } good_double[] = {{"5", 5.0},     {"-5", -5.0},  {"1e-3", 1e-3},  {"0.5", 0.5},
                       {".5", 0.5},    {"5.", 5.0},   {"-.5", -0.5},   {"1E+2", 100.0},
                       {"0", 0.0},     {"007", 7.0},  {"-0", 0.0},     {"2.5e1", 25.0}};
    char err[HOSTIO_ERRLEN], msg[200];
    double d = 42.0;
    long l = 42;
    uint32_t u = 42u;
    size_t i;
    for (i = 0; bad_double[i]; i++) {
        snprintf(msg, sizeof msg, "double '%s'", bad_double[i]);
        TEST_ASSERT_EQUAL_INT_MESSAGE(-1, hostio_parse_double("--x", bad_double[i], -1e9, 1e9,
                                                              &d, err), msg);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "--x: "), err);
    }
    for (i = 0; bad_long[i]; i++) {
        snprintf(msg, sizeof msg, "long '%s'", bad_long[i]);
        TEST_ASSERT_EQUAL_INT_MESSAGE(-1, hostio_parse_long("--n", bad_long[i], -1000, 1000, &l,
                                                            err), msg);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "--n: "), err);
    }
    TEST_ASSERT_TRUE(d == 42.0); /* untouched by the failures */
    TEST_ASSERT_EQUAL_INT32(42, (int32_t)l);
    /* the messages say what is wrong and quote the value */
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_double("--tag-size", " 5", 0, 10, &d, err));
    TEST_ASSERT_EQUAL_STRING("--tag-size: must be a number without leading whitespace (got ' 5')",
                             err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_double("--tag-size", "+5", 0, 10, &d, err));
    TEST_ASSERT_EQUAL_STRING("--tag-size: must be a number without a '+' sign (got '+5')", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_double("--tag-size", "0x1p-3", 0, 10, &d, err));
    TEST_ASSERT_EQUAL_STRING("--tag-size: must be a number in decimal, not hexadecimal (got "
                             "'0x1p-3')", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_double("--tag-size", "nan", 0, 10, &d, err));
    TEST_ASSERT_EQUAL_STRING("--tag-size: must be a finite number (got 'nan')", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_long("--decimate", "0x10", 1, 64, &l, err));
    TEST_ASSERT_EQUAL_STRING("--decimate: must be an integer in decimal, not hexadecimal (got "
                             "'0x10')", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_long("--bits", " 24", 1, 64, &l, err));
    TEST_ASSERT_EQUAL_STRING("--bits: must be an integer without leading whitespace (got ' 24')",
                             err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_long("--bits", "+24", 1, 64, &l, err));
    TEST_ASSERT_EQUAL_STRING("--bits: must be an integer without a '+' sign (got '+24')", err);
    /* u32: no leading whitespace either (strtoull skipped it) */
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_u32("--seed", " 5", 0u, 4294967295u, &u, err));
    TEST_ASSERT_EQUAL_STRING("--seed: must be an integer without leading whitespace (got ' 5')",
                             err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_u32("--seed", "\t5", 0u, 4294967295u, &u, err));
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_u32("--seed", "+5", 0u, 4294967295u, &u, err));
    /* the '+' named as the other parsers name it (it said "from 0 to 4294967295") */
    TEST_ASSERT_EQUAL_STRING("--seed: must be an integer without a '+' sign (got '+5')", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_u32("--seed", "0x10", 0u, 4294967295u, &u, err));
    TEST_ASSERT_EQUAL_STRING("--seed: must be an integer in decimal, not hexadecimal (got "
                             "'0x10')", err);
    TEST_ASSERT_EQUAL_UINT32(42u, u);
    /* the ordinary forms */
    for (i = 0; i < sizeof good_double / sizeof good_double[0]; i++) {
        snprintf(msg, sizeof msg, "double '%s'", good_double[i].s);
        TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_parse_double("--x", good_double[i].s,
                                                                     -1e9, 1e9, &d, err), msg);
        TEST_ASSERT_TRUE_MESSAGE(d == good_double[i].v, msg);
    }
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_parse_long("--n", "5", -10, 10, &l, err));
    TEST_ASSERT_EQUAL_INT32(5, (int32_t)l);
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_parse_long("--n", "-5", -10, 10, &l, err));
    TEST_ASSERT_EQUAL_INT32(-5, (int32_t)l);
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_parse_long("--n", "010", -10, 10, &l, err));
    TEST_ASSERT_EQUAL_INT32(10, (int32_t)l); /* decimal, not octal */
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_parse_u32("--seed", "5", 0u, 9u, &u, err));
    TEST_ASSERT_EQUAL_UINT32(5u, u);
}

/* Numbers beyond the type are out of range, not malformed: strtol's and
 * strtoull's ERANGE said "must be an integer", and a double below the
 * smallest normal one (strtod's ERANGE: 0 or a denormal) "must be a finite
 * number". An overflowing double is infinite: still "finite number". */
static void test_parse_out_of_range(void)
{
    char err[HOSTIO_ERRLEN];
    double d = 42.0;
    long l = 42;
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_long("--median-radius", "99999999999999999999",
                                                -2147483647L - 1, 2147483647L, &l, err));
    TEST_ASSERT_EQUAL_STRING("--median-radius: must be an integer from -2147483648 to 2147483647 "
                             "(got 99999999999999999999)", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_long("--n", "-99999999999999999999", 0, 9, &l, err));
    TEST_ASSERT_EQUAL_STRING("--n: must be an integer from 0 to 9 (got -99999999999999999999)",
                             err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_double("--min-range", "1e-400", -1e9, 1e9, &d, err));
    TEST_ASSERT_EQUAL_STRING("--min-range: must be 0 or at least 2.22507e-308 in magnitude "
                             "(got 1e-400: too small for a double)", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_double("--x", "-1e-400", -1.0, 1.0, &d, err));
    TEST_ASSERT_EQUAL_STRING("--x: must be 0 or at least 2.22507e-308 in magnitude "
                             "(got -1e-400: too small for a double)", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_double("--x", "1e-310", 0.0, 1.0, &d, err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "(got 1e-310: too small for a double)"), err);
    /* a range that leaves out the tiny value: the range is the reason */
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_double("--tag-size", "1e-400", 1e-4, 10.0, &d, err));
    TEST_ASSERT_EQUAL_STRING("--tag-size: must be from 0.0001 to 10 (got 1e-400)", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_double("--x", "-1e-400", 0.0, 10.0, &d, err));
    TEST_ASSERT_EQUAL_STRING("--x: must be from 0 to 10 (got -1e-400)", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_double("--x", "1e400", -1e9, 1e9, &d, err));
    TEST_ASSERT_EQUAL_STRING("--x: must be a finite number (got '1e400')", err);
    TEST_ASSERT_TRUE(d == 42.0); /* untouched by the failures */
    TEST_ASSERT_EQUAL_INT32(42, (int32_t)l);
    /* the smallest normal double and 0 are numbers */
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_parse_double("--x", "2.3e-308", 0.0, 1.0, &d, err));
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_parse_double("--x", "0e-400", 0.0, 1.0, &d, err));
    TEST_ASSERT_TRUE(d == 0.0);
}

/* The same for the number lists: no hexadecimal, no whitespace or '+'
 * inside parse_doubles' values; parse_list's values are separated by
 * whitespace and may carry a '+' (a file's "%+f"), not hexadecimal. */
static void test_parse_lists_decimal(void)
{
    static const char *const bad_doubles[] = {"0x10,1", "1,0x1p-3", "1, 2", " 1,2", "+1,2",
                                              "1,+2", "1,-0x2", "1,inf", "nan,1", NULL};
    char err[HOSTIO_ERRLEN], msg[200];
    double v[4];
    int n = -1;
    size_t i;
    for (i = 0; bad_doubles[i]; i++) {
        snprintf(msg, sizeof msg, "doubles '%s'", bad_doubles[i]);
        TEST_ASSERT_EQUAL_INT_MESSAGE(-1, hostio_parse_doubles("--v", bad_doubles[i], ',', v, 2,
                                                               err), msg);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, bad_doubles[i]), err); /* quotes the value */
    }
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_parse_doubles("--v", "-1,.5,5.,1e-3", ',', v, 4,
                                                          err));
    TEST_ASSERT_TRUE(v[0] == -1.0);
    TEST_ASSERT_TRUE(v[1] == 0.5);
    TEST_ASSERT_TRUE(v[2] == 5.0);
    TEST_ASSERT_TRUE(v[3] == 1e-3);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_list("tab.txt", "1 0x10 3", v, 4, &n, err));
    TEST_ASSERT_EQUAL_STRING("tab.txt: value 2 is not a finite number (got '0x10')", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_list("tab.txt", "1,-0X1p-3", v, 4, &n, err));
    TEST_ASSERT_EQUAL_STRING("tab.txt: value 2 is not a finite number (got '-0X1p-3')", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_parse_list("tab.txt", "nan", v, 4, &n, err));
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_parse_list("tab.txt", "+1.5 -2 .5", v, 4, &n, err));
    TEST_ASSERT_EQUAL_INT(3, n);
    TEST_ASSERT_TRUE(v[0] == 1.5);
    TEST_ASSERT_TRUE(v[2] == 0.5);
}

/* A wrong magic quotes the bytes found (escaped, at most 8); the message
 * once said only "no P5 magic". */
static void test_pgm_magic_quoted(void)
{
    static const uint8_t gif[] = "GIF89a\x01\x00\x01\x00";
    static const uint8_t p5x[] = "P5x3 2\n255\n";
    static const uint8_t q[] = "'\\\t\rab";
    char err[HOSTIO_ERRLEN];
    hostio_pgm_view v;
    TEST_ASSERT_EQUAL_INT(-1, hostio_pgm_parse(gif, sizeof gif - 1, "a.gif", &v, err));
    TEST_ASSERT_EQUAL_STRING("a.gif: not a binary PGM (no P5 magic; it starts "
                             "'GIF89a\\x01\\x00...')", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_pgm_parse(p5x, sizeof p5x - 1, "x.pgm", &v, err));
    TEST_ASSERT_EQUAL_STRING("x.pgm: not a binary PGM (no P5 magic; it starts 'P5x3 2\\n2...')",
                             err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_pgm_parse(q, sizeof q - 1, NULL, &v, err));
    TEST_ASSERT_EQUAL_STRING("PGM: not a binary PGM (no P5 magic; it starts '\\'\\\\\\t\\rab')",
                             err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_pgm_parse(q, 1, "one", &v, err));
    TEST_ASSERT_EQUAL_STRING("one: not a binary PGM (no P5 magic; it starts '\\'')", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_pgm_parse(q, 0, "empty", &v, err));
    TEST_ASSERT_EQUAL_STRING("empty: not a binary PGM (no P5 magic; it is empty)", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_pgm_parse((const uint8_t *)"P5", 2, "p5", &v, err));
    TEST_ASSERT_EQUAL_STRING("p5: PGM header truncated after its P5 magic (no width)", err);
}

/* A comment right after maxval, as Netpbm reads it: its end of line is the
 * single whitespace before the pixels (it was refused: "maxval is not
 * followed by whitespace"). Other bytes there are still refused. */
static void test_pgm_comment_after_maxval(void)
{
    static const uint8_t c1[] = "P5\n2 1\n255#x\n\x0a\x20";
    static const uint8_t c2[] = "P5\n2 1\n255#\n\x01\x02";
    static const uint8_t c3[] = "P5 2 1 255# a comment # more\n\x23\x0a"; /* pixels '#' '\n' */
    static const uint8_t open_c[] = "P5\n2 1\n255# no end of line";
    static const uint8_t junk[] = "P5\n2 1\n255x\n\x01\x02";
    static const uint8_t short_px[] = "P5\n2 1\n255#x\n\x01";
    char err[HOSTIO_ERRLEN];
    hostio_pgm_view v;
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_pgm_parse(c1, sizeof c1 - 1, "c1", &v, err),
                                  err);
    TEST_ASSERT_EQUAL_INT(2, v.cols);
    TEST_ASSERT_EQUAL_INT(1, v.rows);
    TEST_ASSERT_EQUAL_INT(255, v.maxval);
    TEST_ASSERT_TRUE(v.pixels == c1 + 13);
    TEST_ASSERT_EQUAL_UINT8(0x0a, v.pixels[0]); /* a pixel that looks like a newline */
    TEST_ASSERT_EQUAL_UINT8(0x20, v.pixels[1]);
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_pgm_parse(c2, sizeof c2 - 1, "c2", &v, err),
                                  err);
    TEST_ASSERT_EQUAL_UINT8(1, v.pixels[0]);
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_pgm_parse(c3, sizeof c3 - 1, "c3", &v, err),
                                  err);
    TEST_ASSERT_EQUAL_UINT8('#', v.pixels[0]);
    TEST_ASSERT_EQUAL_UINT8('\n', v.pixels[1]);
    TEST_ASSERT_EQUAL_INT(-1, hostio_pgm_parse(open_c, sizeof open_c - 1, "open", &v, err));
    TEST_ASSERT_EQUAL_STRING("open: PGM header ends without pixel data", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_pgm_parse(junk, sizeof junk - 1, "junk", &v, err));
    TEST_ASSERT_EQUAL_STRING("junk: PGM maxval '255x' is not a whole number in 1..65535", err);
    TEST_ASSERT_EQUAL_INT(-1, hostio_pgm_parse(short_px, sizeof short_px - 1, "s", &v, err));
    TEST_ASSERT_EQUAL_STRING("s: PGM has 1 pixel bytes, its header needs 2", err);
    /* through the file readers too */
    PUT_TEXT("cm.pgm", "P5\n2 1\n100#x\n\x00\x64");
    {
        hostio_image im;
        TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_frame_read(DIR "/cm.pgm", NULL, &im, err),
                                      err);
        TEST_ASSERT_EQUAL_UINT8(255, ((uint8_t *)im.data)[1]); /* maxval 100 scaled */
        hostio_image_free(&im);
        TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_pgm_read(DIR "/cm.pgm", &im, err), err);
        TEST_ASSERT_EQUAL_INT(2, im.cols);
        hostio_image_free(&im);
    }
}

static void test_pgm_header_messages(void)
{
    static const uint8_t two[] = "P5\n2 1\n255\n\x01\x02P5\n2 1\n255\n\x03\x04";
    PUT_TEXT("h1.pgm", "P5\nabc 4\n255\n");
    expect_error("h1.pgm", NULL, "PGM width 'abc' is not a whole number in 1..32767");
    PUT_TEXT("h2.pgm", "P5\n-620 4\n255\n");
    expect_error("h2.pgm", NULL, "PGM width '-620' is not a whole number in 1..32767");
    PUT_TEXT("h3.pgm", "P5\n4294967296 2\n255\n");
    expect_error("h3.pgm", NULL, "PGM width '4294967296' is not a whole number in 1..32767");
    PUT_TEXT("h4.pgm", "P5\n512 ");
    expect_error("h4.pgm", NULL, "PGM height missing (the header ends)");
    PUT_TEXT("h5.pgm", "P5\n2 1\n70000\n");
    expect_error("h5.pgm", NULL, "PGM maxval '70000' is not a whole number in 1..65535");
    PUT_TEXT("h6.pgm", "P5\n2 1#c\n255\n\x01\x02"); /* a comment right after a number */
    {
        char err[HOSTIO_ERRLEN];
        hostio_image im;
        TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_frame_read(DIR "/h6.pgm", NULL, &im, err),
                                      err);
        TEST_ASSERT_EQUAL_INT(2, im.cols);
        hostio_image_free(&im);
    }
    put("h7.pgm", two, sizeof two - 1);
    expect_error("h7.pgm", NULL, "13 bytes after the PGM's 2 pixel bytes (one frame per file)");
}

/* A write that fails part way leaves no file (the writers remove it), and
 * a device given as the path is never removed. The failure is a file size
 * limit (RLIMIT_FSIZE, SIGXFSZ ignored): the writes past it fail. */
static void test_failed_write_leaves_nothing(void)
{
    static uint8_t px[64 * 64];
    char err[HOSTIO_ERRLEN];
    hostio_image img = {px, 64, 64, 64, 8, 255};
    struct rlimit old, lim;
    struct stat st;
    void (*prev)(int);
    int a, b, c;
    if (getrlimit(RLIMIT_FSIZE, &old) != 0 || (old.rlim_max != RLIM_INFINITY &&
                                               old.rlim_max < 100000))
        TEST_IGNORE_MESSAGE("no file size limit to lower");
    prev = signal(SIGXFSZ, SIG_IGN);
    lim = old;
    lim.rlim_cur = 1000; /* bytes: the 4 KiB frame cannot be written */
    TEST_ASSERT_EQUAL_INT(0, setrlimit(RLIMIT_FSIZE, &lim));
    a = hostio_pgm_write(DIR "/big.pgm", &img, err);
    b = hostio_ppm_write(DIR "/big.ppm", px, 32, 32, err);
    c = hostio_write_file(DIR "/big.raw", px, sizeof px, err);
    setrlimit(RLIMIT_FSIZE, &old);
    signal(SIGXFSZ, prev);
    TEST_ASSERT_EQUAL_INT(-1, a);
    TEST_ASSERT_EQUAL_INT(-1, b);
    TEST_ASSERT_EQUAL_INT(-1, c);
    TEST_ASSERT_NOT_NULL(strstr(err, "big.raw: write error"));
    TEST_ASSERT_NOT_EQUAL(0, stat(DIR "/big.pgm", &st));
    TEST_ASSERT_NOT_EQUAL(0, stat(DIR "/big.ppm", &st));
    TEST_ASSERT_NOT_EQUAL(0, stat(DIR "/big.raw", &st));
    /* the same writes within the limit succeed */
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_pgm_write(DIR "/big.pgm", &img, err), err);
    TEST_ASSERT_EQUAL_INT(0, stat(DIR "/big.pgm", &st));
    {   /* a symbolic link is neither followed nor removed */
        char lnk[600];
        snprintf(lnk, sizeof lnk, "%s", DIR "/link.pgm");
        remove(lnk);
        if (symlink("big.pgm", lnk) == 0) {
            hostio_remove_partial(lnk);
            TEST_ASSERT_EQUAL_INT(0, lstat(lnk, &st));
            TEST_ASSERT_EQUAL_INT(0, stat(DIR "/big.pgm", &st));
            remove(lnk);
        }
        hostio_remove_partial(DIR "/big.pgm"); /* the file itself: removed */
        TEST_ASSERT_NOT_EQUAL(0, stat(DIR "/big.pgm", &st));
    }
    if (stat("/dev/full", &st) == 0) { /* a device: the error, and the device stays */
        TEST_ASSERT_EQUAL_INT(-1, hostio_write_file("/dev/full", px, sizeof px, err));
        TEST_ASSERT_EQUAL_INT(0, stat("/dev/full", &st));
    }
}

/* The output guard: a closed file stays; an abandoned one is removed, as is
 * one whose close fails; a device, a symbolic link (and what it points to)
 * and standard output are never removed. */
static void test_out_guard(void)
{
    char err[HOSTIO_ERRLEN];
    hostio_out o;
    struct stat st;
    /* closed: kept; closing or abandoning the idle guard again does nothing */
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_out_open(&o, DIR "/kept.txt", "w", err), err);
    TEST_ASSERT_EQUAL_INT(1, o.removable);
    fputs("kept\n", o.f);
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_out_close(&o, err), err);
    TEST_ASSERT_NULL(o.f);
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_out_close(&o, err));
    hostio_out_abandon(&o);
    TEST_ASSERT_EQUAL_INT(0, stat(DIR "/kept.txt", &st));
    TEST_ASSERT_EQUAL_INT(5, (int)st.st_size);
    /* abandoned: removed, also when it existed before (it was truncated) */
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_out_open(&o, DIR "/kept.txt", "w", err), err);
    fputs("half", o.f);
    hostio_out_abandon(&o);
    TEST_ASSERT_NULL(o.f);
    TEST_ASSERT_NOT_EQUAL(0, stat(DIR "/kept.txt", &st));
    /* a symbolic link: written through, neither removed nor followed */
    put("target.txt", "target\n", 7);
    remove(DIR "/link.txt");
    if (symlink("target.txt", DIR "/link.txt") == 0) {
        TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_out_open(&o, DIR "/link.txt", "w", err),
                                      err);
        TEST_ASSERT_EQUAL_INT(0, o.removable);
        fputs("half", o.f);
        hostio_out_abandon(&o);
        TEST_ASSERT_EQUAL_INT(0, lstat(DIR "/link.txt", &st));
        TEST_ASSERT_TRUE(S_ISLNK(st.st_mode));
        TEST_ASSERT_EQUAL_INT(0, stat(DIR "/target.txt", &st));
        remove(DIR "/link.txt");
    }
    /* a device: not removable, and abandoning it leaves it */
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_out_open(&o, "/dev/null", "w", err), err);
    TEST_ASSERT_EQUAL_INT(0, o.removable);
    fputs("x", o.f);
    hostio_out_abandon(&o);
    TEST_ASSERT_EQUAL_INT(0, stat("/dev/null", &st));
    TEST_ASSERT_TRUE(S_ISCHR(st.st_mode));
    /* a device that fails the write: the error and its reason, the device stays */
    if (stat("/dev/full", &st) == 0) {
        TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_out_open(&o, "/dev/full", "w", err), err);
        fputs("x", o.f);
        TEST_ASSERT_EQUAL_INT(-1, hostio_out_close(&o, err));
        TEST_ASSERT_EQUAL_STRING("/dev/full: write error", err);
        TEST_ASSERT_NOT_EQUAL(0, o.why); /* ENOSPC */
        TEST_ASSERT_EQUAL_INT(0, stat("/dev/full", &st));
        TEST_ASSERT_TRUE(S_ISCHR(st.st_mode));
    }
    /* a path that cannot be opened: errno and the message */
    TEST_ASSERT_EQUAL_INT(-1, hostio_out_open(&o, DIR "/no-such-dir/x.txt", "w", err));
    TEST_ASSERT_NULL(o.f);
    TEST_ASSERT_NOT_EQUAL(0, o.why);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "no-such-dir/x.txt: cannot write: "), err);
    /* standard output: flushed, never closed (its descriptor stays open) */
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_out_open(&o, NULL, "w", err));
    TEST_ASSERT_TRUE(o.f == stdout);
    hostio_out_abandon(&o);
    TEST_ASSERT_NOT_EQUAL(-1, fcntl(STDOUT_FILENO, F_GETFD));
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_out_open(&o, NULL, "w", err));
    TEST_ASSERT_EQUAL_INT(HOSTIO_OK, hostio_out_close(&o, err));
    TEST_ASSERT_NOT_EQUAL(-1, fcntl(STDOUT_FILENO, F_GETFD));
}

/* A file whose writing failed is removed when it is closed: a size limit
 * (RLIMIT_FSIZE, SIGXFSZ ignored) makes the writes past it fail, and the
 * close reports it (the stream's error flag). */
static void test_out_close_failure_removes(void)
{
    static char big[64 * 1024];
    char err[HOSTIO_ERRLEN];
    hostio_out o;
    struct rlimit old, lim;
    struct stat st;
    void (*prev)(int);
    int rc;
    if (getrlimit(RLIMIT_FSIZE, &old) != 0 || (old.rlim_max != RLIM_INFINITY &&
                                               old.rlim_max < 100000))
        TEST_IGNORE_MESSAGE("no file size limit to lower");
    memset(big, 'x', sizeof big);
    TEST_ASSERT_EQUAL_INT_MESSAGE(HOSTIO_OK, hostio_out_open(&o, DIR "/cut.txt", "w", err), err);
    prev = signal(SIGXFSZ, SIG_IGN);
    lim = old;
    lim.rlim_cur = 1000;
    TEST_ASSERT_EQUAL_INT(0, setrlimit(RLIMIT_FSIZE, &lim));
    fwrite(big, 1, sizeof big, o.f);
    rc = hostio_out_close(&o, err);
    setrlimit(RLIMIT_FSIZE, &old);
    signal(SIGXFSZ, prev);
    TEST_ASSERT_EQUAL_INT(-1, rc);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "cut.txt: write error"), err);
    TEST_ASSERT_NOT_EQUAL(0, stat(DIR "/cut.txt", &st));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_frames);
    RUN_TEST(test_mkdirs);
    RUN_TEST(test_lists);
    RUN_TEST(test_ppm);
    RUN_TEST(test_detail_messages);
    RUN_TEST(test_raw_frame_starting_with_p5);
    RUN_TEST(test_pgm_8bit_maxval);
    RUN_TEST(test_pgm_read_checks_maxval);
    RUN_TEST(test_slurp_folder_names_the_reason);
    RUN_TEST(test_slurp_text_refuses_nul);
    RUN_TEST(test_same_file);
    RUN_TEST(test_bearings);
    RUN_TEST(test_list_dir);
    RUN_TEST(test_raw_size_overflow);
    RUN_TEST(test_json_string);
    RUN_TEST(test_json_num);
    RUN_TEST(test_parse_choice);
    RUN_TEST(test_parse_u32);
    RUN_TEST(test_pgm_header_messages);
    RUN_TEST(test_parse_number_forms);
    RUN_TEST(test_parse_out_of_range);
    RUN_TEST(test_parse_lists_decimal);
    RUN_TEST(test_pgm_magic_quoted);
    RUN_TEST(test_pgm_comment_after_maxval);
    RUN_TEST(test_failed_write_leaves_nothing);
    RUN_TEST(test_out_guard);
    RUN_TEST(test_out_close_failure_removes);
    return UNITY_END();
}
