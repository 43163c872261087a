/* actag-familygen: published families reproduced bit for bit, checked-in
 * tables equal the generator's output, argument errors exit with status 2. */
#define _POSIX_C_SOURCE 200809L
#include "unity.h"
#include "test_util.h"

#include <sys/wait.h>

void setUp(void) {}
void tearDown(void) {}

/* Runs the generator with args; returns its exit status (or -1). */
static int run_gen(const char *args)
{
    char cmd[4096];
    int st;
    snprintf(cmd, sizeof cmd, "\"%s\" %s", ACTAG_FAMILYGEN_PATH, args);
    st = system(cmd);
    if (st == -1 || !WIFEXITED(st))
        return -1;
    return WEXITSTATUS(st);
}

static void test_txt_equals_published(void)
{
    static const int hs[4] = {4, 6, 8, 10};
    int i;
    for (i = 0; i < 4; i++) {
        char args[1024], pub[256], line[128];
        static uint32_t want[7000];
        int n, got = 0;
        FILE *f;
        snprintf(args, sizeof args, "--bits 24 --hamming %d --format txt > %s/gen_h%d.txt",
                 hs[i], ACTAG_BINARY_DIR, hs[i]);
        TEST_ASSERT_EQUAL_INT(0, run_gen(args));
        snprintf(pub, sizeof pub, "%s/data/families/AcTag24h%d.txt", ACTAG_SHARED_DIR, hs[i]);
        n = tu_read_codes(pub, want, 7000);
        TEST_ASSERT_GREATER_THAN(0, n);
        snprintf(pub, sizeof pub, "%s/gen_h%d.txt", ACTAG_BINARY_DIR, hs[i]);
        f = fopen(pub, "r");
        TEST_ASSERT_NOT_NULL(f);
        while (fgets(line, sizeof line, f)) {
            char want_line[32];
            TEST_ASSERT_LESS_THAN(n, got);
            snprintf(want_line, sizeof want_line, "0x%06lx\n", (unsigned long)want[got]);
            TEST_ASSERT_EQUAL_STRING(want_line, line); /* nothing else on stdout */
            got++;
        }
        fclose(f);
        TEST_ASSERT_EQUAL_INT(n, got);
    }
}

static void test_checked_in_tables_equal_generator(void)
{
    static const int hs[4] = {4, 6, 8, 10};
    int i;
    for (i = 0; i < 4; i++) {
        char args[1024], a[256], b[256];
        long la = 0, lb = 0;
        char *ca, *cb;
        snprintf(a, sizeof a, "%s/gen_h%d.c", ACTAG_BINARY_DIR, hs[i]);
        snprintf(args, sizeof args, "--bits 24 --hamming %d --format c --out %s", hs[i], a);
        TEST_ASSERT_EQUAL_INT(0, run_gen(args));
        snprintf(b, sizeof b, "%s/families/AcTag24h%d.c", ACTAG_SOURCE_DIR, hs[i]);
        ca = tu_slurp(a, &la);
        cb = tu_slurp(b, &lb);
        TEST_ASSERT_NOT_NULL(ca);
        TEST_ASSERT_NOT_NULL_MESSAGE(cb, "checked-in family table missing");
        TEST_ASSERT_EQUAL_INT(la, lb);
        TEST_ASSERT_EQUAL_MEMORY(ca, cb, la);
        free(ca);
        free(cb);
    }
}

static void test_apriltag_format_is_static(void)
{
    char path[256], args[1024];
    long n = 0;
    char *s;
    snprintf(path, sizeof path, "%s/gen_at.c", ACTAG_BINARY_DIR);
    snprintf(args, sizeof args, "--bits 24 --hamming 10 --format apriltag --out %s", path);
    TEST_ASSERT_EQUAL_INT(0, run_gen(args));
    s = tu_slurp(path, &n);
    TEST_ASSERT_NOT_NULL(s);
    TEST_ASSERT_NOT_NULL(strstr(s, "apriltag_family_t *actag_apriltag_family_AcTag24h10(void)"));
    TEST_ASSERT_NOT_NULL(strstr(s, ".width_at_border = 3"));
    TEST_ASSERT_NOT_NULL(strstr(s, ".total_width = 7"));
    TEST_ASSERT_NOT_NULL(strstr(s, ".reversed_border = true"));
    TEST_ASSERT_NOT_NULL(strstr(s, "0xd35f2aULL"));
    /* SPEC section 2: bit 0 at (-2,-2), bit 6 at (4,-2), bit 23 at (-2,-1) */
    TEST_ASSERT_NOT_NULL(strstr(s, "bitx_AcTag24h10[24] = {(uint32_t)-2, (uint32_t)-1, (uint32_t)0, (uint32_t)1, (uint32_t)2, (uint32_t)3, (uint32_t)4, (uint32_t)4,"));
    TEST_ASSERT_NOT_NULL(strstr(s, "bity_AcTag24h10[24] = {(uint32_t)-2, (uint32_t)-2, (uint32_t)-2, (uint32_t)-2, (uint32_t)-2, (uint32_t)-2, (uint32_t)-2, (uint32_t)-1,"));
    TEST_ASSERT_NULL(strstr(s, "calloc"));
    TEST_ASSERT_NULL(strstr(s, "strdup"));
    free(s);
}

static void test_other_sizes(void)
{
    char args[1024], path[256], line[64];
    FILE *f;
    int n = 0;
    snprintf(path, sizeof path, "%s/gen_16.txt", ACTAG_BINARY_DIR);
    snprintf(args, sizeof args, "--bits 16 --hamming 5 --out %s", path);
    TEST_ASSERT_EQUAL_INT(0, run_gen(args));
    f = fopen(path, "r");
    TEST_ASSERT_NOT_NULL(f);
    while (fgets(line, sizeof line, f)) {
        TEST_ASSERT_EQUAL_INT(7, (int)strlen(line)); /* "0x" + 4 hex digits + newline */
        n++;
    }
    fclose(f);
    TEST_ASSERT_GREATER_THAN(0, n);
}

static void test_argument_errors(void)
{
    char args[1024];
    TEST_ASSERT_EQUAL_INT(2, run_gen("--bits 23 --hamming 4 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, run_gen("--bits 12 --hamming 4 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, run_gen("--bits 36 --hamming 4 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, run_gen("--bits 24 --hamming 0 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, run_gen("--bits 24 --hamming -3 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, run_gen("--bits 24 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, run_gen("--hamming 4 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, run_gen("--bits 24 --hamming 4 --frobnicate > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, run_gen("--bits 24 --hamming > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, run_gen("--bits x24 --hamming 4 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, run_gen("--bits 24 --hamming 4 --format png > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, run_gen("--bits 24 --hamming 4 --name 9bad > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, run_gen("--bits 24 --hamming 4 --out /nonexistent-dir/x.txt 2>/dev/null"));
    /* one line on stderr */
    snprintf(args, sizeof args, "--bits 23 --hamming 4 2> %s/gen_err.txt", ACTAG_BINARY_DIR);
    TEST_ASSERT_EQUAL_INT(2, run_gen(args));
    {
        char path[256];
        long n = 0;
        char *s;
        snprintf(path, sizeof path, "%s/gen_err.txt", ACTAG_BINARY_DIR);
        s = tu_slurp(path, &n);
        TEST_ASSERT_NOT_NULL(s);
        TEST_ASSERT_GREATER_THAN(10, n);
        TEST_ASSERT_NOT_NULL(strstr(s, "multiple of 4"));
        TEST_ASSERT_EQUAL_INT('\n', s[n - 1]);
        TEST_ASSERT_NULL(strchr(s, '\n') + 1 < s + n ? strchr(strchr(s, '\n') + 1, '\n') : NULL);
        free(s);
    }
    /* an empty family is an error, not an empty table */
    TEST_ASSERT_EQUAL_INT(1, run_gen("--bits 16 --hamming 17 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(0, run_gen("--help > /dev/null"));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_txt_equals_published);
    RUN_TEST(test_checked_in_tables_equal_generator);
    RUN_TEST(test_apriltag_format_is_static);
    RUN_TEST(test_other_sizes);
    RUN_TEST(test_argument_errors);
    return UNITY_END();
}
