/* actag-eval and actag-sim as a user runs them: a small seeded evaluation
 * with fixed bounds on error and detection rate, the tag-free run, the SVG
 * output, ground truth written by actag-sim, bad options (exit 2, a
 * message naming the option and the value) and the appearance options. */
#define _POSIX_C_SOURCE 200809L
#include "unity.h"
#include "hostio.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

void setUp(void) {}
void tearDown(void) {}

static char out_path[512], err_path[512];

static int run(const char *tool, const char *args)
{
    char cmd[4096];
    snprintf(out_path, sizeof out_path, "%s/eval_out.txt", ACTAG_BINARY_DIR);
    snprintf(err_path, sizeof err_path, "%s/eval_err.txt", ACTAG_BINARY_DIR);
    snprintf(cmd, sizeof cmd, "\"%s\" %s > \"%s\" 2> \"%s\"", tool, args, out_path, err_path);
    return hostio_run(cmd, NULL);
}

/* A whole output file as a string (NULL when it cannot be read). */
static char *slurp(const char *path) { return (char *)hostio_slurp(path, NULL, NULL); }

/* The number after "key": (the first occurrence after from). */
static double json_num(const char *s, const char *key)
{
    char pat[128];
    const char *p;
    snprintf(pat, sizeof pat, "\"%s\": ", key);
    p = strstr(s, pat);
    TEST_ASSERT_NOT_NULL_MESSAGE(p, key);
    return atof(p + strlen(pat));
}

/* 60 pool-geometry views, seed 3: bounds from the figures such a run gives
 * (about 70 % found, range sd 0.6 cm, azimuth sd 0.005 rad), with slack; no
 * wrong ID, mirror or order error in any case. */
static void test_small_seeded_evaluation(void)
{
    char *js, *rng, *az;
    TEST_ASSERT_EQUAL_INT(0, run(ACTAG_EVAL_PATH, "--pool --frames 60 --seed 3 --json --quiet"));
    js = slurp(out_path);
    TEST_ASSERT_NOT_NULL(js);
    TEST_ASSERT_EQUAL_INT(60, (int)json_num(js, "views"));
    TEST_ASSERT_TRUE(json_num(js, "detection_rate") >= 0.5);
    TEST_ASSERT_EQUAL_INT(0, (int)json_num(js, "wrong_ids"));
    TEST_ASSERT_EQUAL_INT(0, (int)json_num(js, "false_tags"));
    TEST_ASSERT_EQUAL_INT(0, (int)json_num(js, "mirror_errors"));
    TEST_ASSERT_EQUAL_INT(0, (int)json_num(js, "corner_order_errors"));
    rng = strstr(js, "\"range_error_m\"");
    az = strstr(js, "\"azimuth_error_rad\"");
    TEST_ASSERT_NOT_NULL(rng);
    TEST_ASSERT_NOT_NULL(az);
    TEST_ASSERT_TRUE(json_num(rng, "sd") <= 0.012);
    TEST_ASSERT_TRUE(json_num(rng, "mean") <= 0.005 && json_num(rng, "mean") >= -0.005);
    TEST_ASSERT_TRUE(json_num(az, "sd") <= 0.008);
    TEST_ASSERT_TRUE(json_num(az, "mean") <= 0.002 && json_num(az, "mean") >= -0.002);
    free(js);
}

/* Tag-free frames: nothing at the default corrections, for every family;
 * the same figures with 1 thread as with 2 (frames are independent). */
static void test_tag_free_and_threads(void)
{
    char *a, *b, *p;
    TEST_ASSERT_EQUAL_INT(0, run(ACTAG_EVAL_PATH, "--frames 0 --tag-free 24 --json --quiet"));
    a = slurp(out_path);
    TEST_ASSERT_NOT_NULL(a);
    for (p = strstr(a, "\"default\": "); p; p = strstr(p + 1, "\"default\": "))
        TEST_ASSERT_EQUAL_INT(0, (int)json_num(p, "detections"));
    TEST_ASSERT_EQUAL_INT(0, run(ACTAG_EVAL_PATH,
                                 "--frames 0 --tag-free 24 --json --quiet --threads 1"));
    b = slurp(out_path);
    TEST_ASSERT_NOT_NULL(b);
    /* identical up to the timing fields at the end */
    TEST_ASSERT_EQUAL_INT(0, strncmp(a, b, (size_t)(strstr(a, "\"seconds\"") - a)));
    free(a);
    free(b);
}

static void test_svg_output(void)
{
    char args[1024], path[1024];
    static const char *names[4] = {"range_error.svg", "azimuth_error.svg", "rate_vs_distance.svg",
                                   "rate_vs_incidence.svg"};
    int i;
    snprintf(args, sizeof args, "--pool --frames 12 --quiet --svg \"%s/eval_svg\"",
             ACTAG_BINARY_DIR);
    TEST_ASSERT_EQUAL_INT(0, run(ACTAG_EVAL_PATH, args));
    for (i = 0; i < 4; i++) {
        char *s;
        snprintf(path, sizeof path, "%s/eval_svg/%s", ACTAG_BINARY_DIR, names[i]);
        s = slurp(path);
        TEST_ASSERT_NOT_NULL_MESSAGE(s, path);
        TEST_ASSERT_NOT_NULL(strstr(s, "<svg"));
        TEST_ASSERT_NOT_NULL(strstr(s, "</svg>"));
        free(s);
    }
}

/* --pose-dump: one JSON line per right reading (as many as the summary's
 * pose readings), each with the truth and the estimate; errors within the
 * bounds the estimator gives at these short ranges. */
static void test_pose_dump(void)
{
    char args[1200], path[512];
    char *js, *dump, *line;
    int lines = 0;
    snprintf(path, sizeof path, "%s/eval_pose.jsonl", ACTAG_BINARY_DIR);
    snprintf(args, sizeof args, "--pool --frames 20 --seed 3 --json --quiet --pose-dump \"%s\"",
             path);
    TEST_ASSERT_EQUAL_INT(0, run(ACTAG_EVAL_PATH, args));
    js = slurp(out_path);
    dump = slurp(path);
    TEST_ASSERT_NOT_NULL(js);
    TEST_ASSERT_NOT_NULL(dump);
    for (line = dump; (line = strstr(line, "{\"frame\": ")) != NULL; line++) {
        lines++;
        TEST_ASSERT_TRUE(json_num(line, "position_error") < 0.2 * json_num(line, "range"));
        TEST_ASSERT_TRUE(json_num(line, "orientation_error") < 0.5);
        TEST_ASSERT_NOT_NULL(strstr(line, "\"range_errors\": ["));
    }
    TEST_ASSERT_TRUE(lines > 5);
    TEST_ASSERT_EQUAL_INT((int)json_num(strstr(js, "\"pose\""), "readings"), lines);
    free(js);
    free(dump);
}

/* --plane-sd/--plane-tilt-deg: the same readings, each pose fitted with the
 * tag's plane as a vehicle would know it; the median position error falls
 * (20 frames at the paper's settings: the elevation is the error there). */
static void test_known_plane_options(void)
{
    char *a, *b;
    double ea, eb;
    TEST_ASSERT_EQUAL_INT(0, run(ACTAG_EVAL_PATH, "--frames 30 --seed 3 --json --quiet"));
    a = slurp(out_path);
    TEST_ASSERT_EQUAL_INT(0, run(ACTAG_EVAL_PATH, "--frames 30 --seed 3 --json --quiet "
                                                  "--plane-sd 0.01 --plane-tilt-deg 0.5"));
    b = slurp(out_path);
    TEST_ASSERT_NOT_NULL(a);
    TEST_ASSERT_NOT_NULL(b);
    TEST_ASSERT_EQUAL_INT((int)json_num(strstr(a, "\"pose\""), "readings"),
                          (int)json_num(strstr(b, "\"pose\""), "readings"));
    TEST_ASSERT_TRUE(json_num(strstr(a, "\"pose\""), "readings") >= 5);
    ea = json_num(strstr(a, "\"pose\""), "median_position_error_pct_of_range");
    eb = json_num(strstr(b, "\"pose\""), "median_position_error_pct_of_range");
    printf("median position error: %.2f %% of range without a plane, %.2f %% with\n", ea, eb);
    TEST_ASSERT_TRUE(eb < 0.5 * ea);
    free(a);
    free(b);
}

/* --sequence-failures: the file is written (one pass, a few frames), and
 * every line it holds names the pass's seed and ID for actag-sim. */
static void test_sequence_failures_file(void)
{
    char args[1200], path[512];
    char *txt, *line;
    snprintf(path, sizeof path, "%s/eval_seq_failures.jsonl", ACTAG_BINARY_DIR);
    remove(path);
    snprintf(args, sizeof args,
             "--pool --frames 0 --sequences 1 --sequence-length 4 --seed 3 --quiet "
             "--sequence-failures \"%s\"",
             path);
    TEST_ASSERT_EQUAL_INT(0, run(ACTAG_EVAL_PATH, args));
    txt = slurp(path);
    TEST_ASSERT_NOT_NULL_MESSAGE(txt, "--sequence-failures wrote no file");
    for (line = txt; (line = strstr(line, "{\"sequence\": ")) != NULL; line++) {
        TEST_ASSERT_NOT_NULL(strstr(line, "\"sequence_seed\": "));
        TEST_ASSERT_NOT_NULL(strstr(line, "\"id\": "));
    }
    free(txt);
}

/* actag-sim writes frames and one truth line per frame. */
static void test_sim_writes_frames_and_truth(void)
{
    char args[1024], path[1024];
    char *t;
    int lines = 0;
    const char *p;
    snprintf(args, sizeof args, "--pool --random 3 --quiet --out-dir \"%s/sim_out\"",
             ACTAG_BINARY_DIR);
    TEST_ASSERT_EQUAL_INT(0, run(ACTAG_SIM_PATH, args));
    snprintf(path, sizeof path, "%s/sim_out/truth.jsonl", ACTAG_BINARY_DIR);
    t = slurp(path);
    TEST_ASSERT_NOT_NULL(t);
    for (p = t; *p; p++)
        lines += *p == '\n';
    TEST_ASSERT_EQUAL_INT(3, lines);
    TEST_ASSERT_NOT_NULL(strstr(t, "\"corners\": [{\"x_col\": "));
    TEST_ASSERT_NOT_NULL(strstr(t, "\"mirrored\": "));
    free(t);
    snprintf(path, sizeof path, "%s/sim_out/sim_0002.pgm", ACTAG_BINARY_DIR);
    t = slurp(path);
    TEST_ASSERT_NOT_NULL(t);
    TEST_ASSERT_EQUAL_INT(0, strncmp(t, "P5\n512 530\n255\n", 15));
    free(t);
    /* a fixed tag pose */
    snprintf(args, sizeof args,
             "--pool --tag AcTag24h10:3:1.0,0,-0.3,0,-20,0 --quiet --out-dir \"%s/sim_out2\"",
             ACTAG_BINARY_DIR);
    TEST_ASSERT_EQUAL_INT(0, run(ACTAG_SIM_PATH, args));
}

static void expect_error(const char *tool, const char *args, const char *what)
{
    char *e;
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, run(tool, args), args);
    e = slurp(err_path);
    TEST_ASSERT_NOT_NULL(e);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(e, what), e);
    free(e);
}

/* expect_error, the message also naming the value (or saying it is missing). */
static void expect_error_of(const char *tool, const char *args, const char *what,
                            const char *value)
{
    char *e;
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, run(tool, args), args);
    e = slurp(err_path);
    TEST_ASSERT_NOT_NULL(e);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(e, what), e);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(e, value), e);
    free(e);
}

static void test_bad_options(void)
{
    expect_error(ACTAG_EVAL_PATH, "--frames -1", "--frames");
    expect_error(ACTAG_EVAL_PATH, "--frames 10 --family AcTag99h1", "AcTag99h1");
    expect_error(ACTAG_EVAL_PATH, "--max-range 0.05", "--max-range");
    expect_error(ACTAG_EVAL_PATH, "--corrections 9", "--corrections");
    expect_error_of(ACTAG_EVAL_PATH, "--many-corrections-margin -1", "--many-corrections-margin",
                    "-1");
    expect_error(ACTAG_EVAL_PATH, "--bogus", "--bogus");
    expect_error(ACTAG_EVAL_PATH, "--frames 2 --plane-sd -0.1", "--plane-sd");
    expect_error(ACTAG_EVAL_PATH, "--frames 2 --plane-tilt-deg 91", "--plane-tilt-deg");
    expect_error(ACTAG_EVAL_PATH, "--frames 2 --pose-dump /nonexistent-dir/p.jsonl",
                 "/nonexistent-dir/p.jsonl");
    expect_error(ACTAG_EVAL_PATH, "--frames 2 --sequence-failures x.jsonl", "--sequence-failures");
    expect_error(ACTAG_EVAL_PATH,
                 "--frames 0 --sequences 1 --sequence-length 2 --sequence-failures "
                 "/nonexistent-dir/s.jsonl",
                 "/nonexistent-dir/s.jsonl");
    expect_error(ACTAG_SIM_PATH, "--random 2", "--out-dir");
    expect_error(ACTAG_SIM_PATH, "--tag AcTag24h10:99:1,0,0,0,0,0 --out-dir /tmp", "99");
    expect_error(ACTAG_SIM_PATH, "--tag AcTag24h10:1:1,0,0 --out-dir /tmp", "--tag pose");
    expect_error(ACTAG_SIM_PATH, "--random 2 --aperture-deg 400 --out-dir /tmp", "--aperture-deg");
}

/* The appearance options (actag-sim's): a bad value exits with status 2 and a
 * message naming the option and the value; a value changes the frames (8 pool
 * views, seed 3: receiver noise far above the default, 0.0006, drowns the
 * tags, so fewer are found than at the defaults). */
static void test_appearance_options(void)
{
    char *js;
    int plain, noisy;
    expect_error_of(ACTAG_EVAL_PATH, "--frames 1 --noise -1", "--noise", "-1");
    expect_error_of(ACTAG_EVAL_PATH, "--frames 1 --looks 9", "--looks", "9");
    expect_error_of(ACTAG_EVAL_PATH, "--frames 1 --psf-azimuth abc", "--psf-azimuth", "abc");
    expect_error_of(ACTAG_EVAL_PATH, "--frames 1 --spreading 5", "--spreading", "5");
    expect_error_of(ACTAG_EVAL_PATH, "--frames 1 --gain", "--gain", "missing value");
    TEST_ASSERT_EQUAL_INT(0, run(ACTAG_EVAL_PATH,
                                 "--pool --frames 8 --seed 3 --json --quiet --threads 1"));
    js = slurp(out_path);
    TEST_ASSERT_NOT_NULL(js);
    plain = (int)json_num(js, "detected");
    free(js);
    TEST_ASSERT_EQUAL_INT(0, run(ACTAG_EVAL_PATH, "--pool --frames 8 --seed 3 --json --quiet "
                                                  "--threads 1 --noise 1"));
    js = slurp(out_path);
    TEST_ASSERT_NOT_NULL(js);
    noisy = (int)json_num(js, "detected");
    free(js);
    TEST_ASSERT_TRUE_MESSAGE(plain >= 6, "default appearance: most of 8 pool views found");
    TEST_ASSERT_TRUE_MESSAGE(2 * noisy <= plain, "--noise 1 must lower the detections");
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_small_seeded_evaluation);
    RUN_TEST(test_tag_free_and_threads);
    RUN_TEST(test_svg_output);
    RUN_TEST(test_pose_dump);
    RUN_TEST(test_known_plane_options);
    RUN_TEST(test_sequence_failures_file);
    RUN_TEST(test_sim_writes_frames_and_truth);
    RUN_TEST(test_bad_options);
    RUN_TEST(test_appearance_options);
    return UNITY_END();
}
