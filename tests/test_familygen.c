/* actag-familygen: published families reproduced bit for bit (and fast),
 * checked-in tables equal the generator's output, the mirror / excluded-cell
 * rules equal an independent naive greedy search, argument errors exit with
 * status 2 and name the bad value, a failed run leaves no output file.
 * (The 28-bit tables: test_familygen_28.) */
#define _POSIX_C_SOURCE 200809L
#include "familygen_test.h"

#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>

/* Cross builds: only familygen_test.h's main(); the host suite runs these. */
#ifdef ACTAG_FAMILYGEN_PATH

static void test_txt_equals_published(void)
{
    int i;
    for (i = 0; i < FG_NHAMMING; i++) {
        char args[1024], pub[256], line[128];
        static uint32_t want[7000];
        int n, got = 0;
        FILE *f;
        snprintf(args, sizeof args, "--bits 24 --hamming %d --format txt > %s/gen_h%d.txt",
                 FG_HAMMING[i], ACTAG_BINARY_DIR, FG_HAMMING[i]);
        TEST_ASSERT_EQUAL_INT(0, tu_run_gen(args));
        snprintf(pub, sizeof pub, "%s/families/AcTag24h%d.txt", TU_DATA, FG_HAMMING[i]);
        n = tu_read_codes(pub, want, 7000);
        TEST_ASSERT_GREATER_THAN(0, n);
        snprintf(pub, sizeof pub, "%s/gen_h%d.txt", ACTAG_BINARY_DIR, FG_HAMMING[i]);
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

/* Generator options of a standard family name (docs/families.md). */
static const char *rule_flags(const char *name)
{
    const char *p = strchr(name + 5, 'm') ? "--mirror physical --exclude corners"
                    : strchr(name + 5, 'p') ? "--mirror physical"
                                            : "";
    return p;
}

static void check_table(const char *name)
{
    char args[1024], a[256], b[256];
    size_t la = 0, lb = 0;
    char *ca, *cb;
    int bits, h;
    char c;
    TEST_ASSERT_EQUAL_INT(3, sscanf(name, "AcTag%d%c%d", &bits, &c, &h));
    snprintf(a, sizeof a, "%s/gen_%s.c", ACTAG_BINARY_DIR, name);
    snprintf(args, sizeof args, "--bits %d --hamming %d %s --format c --name %s --out %s", bits, h,
             rule_flags(name), name, a);
    TEST_ASSERT_EQUAL_INT(0, tu_run_gen(args));
    snprintf(b, sizeof b, "%s/families/%s.c", ACTAG_SOURCE_DIR, name);
    ca = tu_slurp(a, &la);
    cb = tu_slurp(b, &lb);
    TEST_ASSERT_NOT_NULL(ca);
    TEST_ASSERT_NOT_NULL_MESSAGE(cb, "checked-in family table missing");
    TEST_ASSERT_EQUAL_INT_MESSAGE(la, lb, name);
    TEST_ASSERT_EQUAL_MEMORY_MESSAGE(ca, cb, la, name);
    free(ca);
    free(cb);
}

static void test_checked_in_tables_equal_generator(void)
{
    static const char *const names[] = {"AcTag24h4", "AcTag24h6", "AcTag24h8", "AcTag24h10",
                                        "AcTag24m4", "AcTag24m6", "AcTag24m8", "AcTag24m10"};
    int i;
    for (i = 0; i < (int)(sizeof names / sizeof names[0]); i++)
        check_table(names[i]);
}

/* The four published families, one generator run each, as CMake runs them:
 * the time is reported (README, docs/families.md) and bounded in CPU time,
 * which other jobs on the machine disturb far less than wall-clock time
 * (the previous generator needed about 2.8 s of CPU on our 2-core machines,
 * this one about 0.5 s). */
static double children_cpu(void)
{
    struct rusage ru;
    getrusage(RUSAGE_CHILDREN, &ru);
    return (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec +
           (double)ru.ru_stime.tv_sec + 1e-6 * (double)ru.ru_stime.tv_usec;
}

static void test_published_four_are_fast(void)
{
    struct timespec t0, t1;
    double s, c0, cpu;
    char msg[128];
    c0 = children_cpu();
    clock_gettime(CLOCK_MONOTONIC, &t0);
    TEST_ASSERT_EQUAL_INT(0, tu_run_gen("--bits 24 --hamming 4 > /dev/null"));
    TEST_ASSERT_EQUAL_INT(0, tu_run_gen("--bits 24 --hamming 6 > /dev/null"));
    TEST_ASSERT_EQUAL_INT(0, tu_run_gen("--bits 24 --hamming 8 > /dev/null"));
    TEST_ASSERT_EQUAL_INT(0, tu_run_gen("--bits 24 --hamming 10 > /dev/null"));
    clock_gettime(CLOCK_MONOTONIC, &t1);
    cpu = children_cpu() - c0;
    s = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    snprintf(msg, sizeof msg, "four published 24-bit families: %.2f s wall, %.2f s CPU", s, cpu);
    TEST_MESSAGE(msg);
#ifdef ACTAG_SANITIZED
    TEST_ASSERT_TRUE_MESSAGE(cpu < 40.0, msg); /* instrumented: about 10x slower */
#else
    TEST_ASSERT_TRUE_MESSAGE(cpu < 2.0, msg);
#endif
}

/* ---------------------------------------------------------------- naive reference */

/* Sequence position s of w is bit bits-1-s. */
static uint32_t nv_view(uint32_t w, int bits, int g, int physical)
{
    int k = bits / 4, s;
    uint32_t r = 0, m = 0;
    for (s = 0; s < bits; s++)
        if ((w >> (bits - 1 - (s + (g & 3) * k) % bits)) & 1u)
            r |= 1u << (bits - 1 - s);
    if (g < 4)
        return r;
    for (s = 0; s < bits; s++) {
        int src = physical ? (bits - s) % bits : bits - 1 - s;
        if ((r >> (bits - 1 - src)) & 1u)
            m |= 1u << (bits - 1 - s);
    }
    return m;
}

/* Layout energy by rendering the (k+1)^2 grid (SPEC sections 1-3). */
static int nv_energy(uint32_t w, int bits)
{
    int k = bits / 4, n = k + 1, g[9][9], x, y, i, e = 0;
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            int d = x;
            if (y < d) d = y;
            if (k - x < d) d = k - x;
            if (k - y < d) d = k - y;
            g[y][x] = d == 1 ? 0 : 1;
        }
    for (i = 0; i < bits; i++) {
        if (i < k) { x = i; y = 0; }
        else if (i < 2 * k) { x = k; y = i - k; }
        else if (i < 3 * k) { x = 3 * k - i; y = k; }
        else { x = 0; y = 4 * k - i; }
        g[y][x] = (int)((w >> (bits - 1 - i)) & 1u);
    }
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            if (x + 1 < n && g[y][x] != g[y][x + 1]) e++;
            if (y + 1 < n && g[y][x] != g[y + 1][x]) e++;
        }
    return e;
}

/* SPEC section 3, literally: every candidate in order, all 8 x 8 view
 * pairs against every accepted code; keep = counted bits. */
static int naive_family(int bits, int h, int physical, uint32_t keep, uint32_t *out, int cap)
{
    static uint32_t views[4096][8];
    uint32_t mask = (uint32_t)((1ull << bits) - 1), v = 0x445965u & mask;
    unsigned long iter, total = 1ul << bits;
    int n = 0, k = bits / 4;
    double emin = 0.3333 * 2.0 * (k + 1) * (k + 1);
    for (iter = 0; iter < total; iter++) {
        uint32_t o[8];
        int a, b, c, ok = 1;
        v = (uint32_t)((v + 982451653ull) & mask);
        if (nv_energy(v, bits) < emin)
            continue;
        for (a = 0; a < 8; a++)
            o[a] = nv_view(v, bits, a, physical);
        for (a = 0; a < 8 && ok; a++)
            for (b = a + 1; b < 8 && ok; b++)
                ok = tu_popcount((o[a] ^ o[b]) & keep) >= h;
        for (c = 0; c < n && ok; c++)
            for (a = 0; a < 8 && ok; a++)
                for (b = 0; b < 8 && ok; b++)
                    ok = tu_popcount((o[a] ^ views[c][b]) & keep) >= h;
        if (!ok)
            continue;
        TEST_ASSERT_TRUE(n < cap && n < 4096);
        for (a = 0; a < 8; a++)
            views[n][a] = o[a];
        out[n++] = v;
    }
    return n;
}

static void check_against_naive(int bits, int h, int physical, const char *exclude, uint32_t keep)
{
    static uint32_t want[4096], got[4096];
    char args[512], path[256], msg[512];
    int n, m, i;
    snprintf(path, sizeof path, "%s/gen_naive.txt", ACTAG_BINARY_DIR);
    snprintf(args, sizeof args, "--bits %d --hamming %d --mirror %s --exclude %s --out %s 2>/dev/null",
             bits, h, physical ? "physical" : "reverse", exclude, path);
    snprintf(msg, sizeof msg, "%s", args);
    {
        clock_t t0 = clock();
        n = naive_family(bits, h, physical, keep, want, 4096);
        printf("naive %s: %d codes, %.2f s\n", args, n, (double)(clock() - t0) / CLOCKS_PER_SEC);
    }
    TEST_ASSERT_EQUAL_INT_MESSAGE(n > 0 ? 0 : 2, tu_run_gen(args), msg); /* empty: a usage error */
    m = n > 0 ? tu_read_codes(path, got, 4096) : 0;
    TEST_ASSERT_EQUAL_INT_MESSAGE(n, m, msg);
    for (i = 0; i < n; i++)
        TEST_ASSERT_EQUAL_HEX32_MESSAGE(want[i], got[i], msg);
}

static void test_rules_equal_naive_search(void)
{
    uint32_t m16 = 0xffffu, c16 = 0x8888u; /* corners: positions 0, 4, 8, 12 */
    uint32_t c20 = 0x84210u;               /* positions 0, 5, 10, 15 */
    int h;
    check_against_naive(16, 2, 1, "corners", m16 & ~c16); /* (h2 without exclusion: 10 s) */
    for (h = 3; h <= 7; h++) { /* h7 with corners excluded is empty: exit status 2 */
        check_against_naive(16, h, 0, "none", m16);
        check_against_naive(16, h, 1, "none", m16);
        check_against_naive(16, h, 1, "corners", m16 & ~c16);
    }
    /* positions 2, 6, 10, 14 (and 14, 10, 6, 2 under P): closed, not the corners */
    check_against_naive(16, 3, 1, "2,6,10,14", m16 & ~0x2222u);
    check_against_naive(20, 6, 1, "corners", 0xfffffu & ~c20);
    check_against_naive(20, 8, 1, "corners", 0xfffffu & ~c20);
}
static void test_apriltag_format_is_static(void)
{
    char path[256], args[1024];
    size_t n = 0;
    char *s;
    snprintf(path, sizeof path, "%s/gen_at.c", ACTAG_BINARY_DIR);
    snprintf(args, sizeof args, "--bits 24 --hamming 10 --format apriltag --out %s", path);
    TEST_ASSERT_EQUAL_INT(0, tu_run_gen(args));
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
    TEST_ASSERT_EQUAL_INT(0, tu_run_gen(args));
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
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 23 --hamming 4 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 12 --hamming 4 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 36 --hamming 4 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 24 --hamming 0 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 24 --hamming -3 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 24 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--hamming 4 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 24 --hamming 4 --frobnicate > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 24 --hamming > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits x24 --hamming 4 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 24 --hamming 4 --format png > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 24 --hamming 4 --name 9bad > /dev/null 2>&1"));
    /* an output path under a regular file can never be created (unlike a
     * missing folder, which another program on the machine might make) */
    snprintf(args, sizeof args, "--bits 24 --hamming 4 --out '%s/CMakeCache.txt/x.txt' 2>/dev/null",
             ACTAG_BINARY_DIR);
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen(args));
    /* the rule options */
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 24 --hamming 4 --mirror sideways > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 24 --hamming 4 --mirror > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 24 --hamming 4 --exclude 24 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 24 --hamming 4 --exclude 3,x > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 24 --hamming 4 --exclude -1 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 24 --hamming 4 --exclude 0,6,12 --mirror physical > /dev/null 2>&1"));
    /* the corners are not closed under the full reversal (0 -> 23) */
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 24 --hamming 4 --exclude corners > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 24 --hamming 4 --min-complexity 1.5 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 24 --hamming 4 --min-complexity abc > /dev/null 2>&1"));
    /* a standard name must carry its rule; other rules need their own name */
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 24 --hamming 10 --mirror physical --name AcTag24h10 --format c > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 24 --hamming 10 --name AcTag24m10 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 24 --hamming 10 --mirror physical --exclude corners --name AcTag24m8 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 24 --hamming 10 --min-complexity 0.2 --format c > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(0, tu_run_gen("--bits 24 --hamming 10 --min-complexity 0.2 --format c --name Custom24 > /dev/null 2>&1"));
    {
        /* the message names the bad value */
        char path[256], args[512];
        char *s;
        snprintf(path, sizeof path, "%s/gen_err2.txt", ACTAG_BINARY_DIR);
        snprintf(args, sizeof args, "--bits 24 --hamming 4 --mirror physical --exclude 0,6,12 2> %s", path);
        TEST_ASSERT_EQUAL_INT(2, tu_run_gen(args));
        s = tu_slurp(path, NULL);
        TEST_ASSERT_NOT_NULL(s);
        TEST_ASSERT_NOT_NULL(strstr(s, "'0,6,12'"));
        TEST_ASSERT_NOT_NULL(strstr(s, "position 18"));
        free(s);
        snprintf(args, sizeof args, "--bits 24 --hamming 4 --mirror sideways 2> %s", path);
        TEST_ASSERT_EQUAL_INT(2, tu_run_gen(args));
        s = tu_slurp(path, NULL);
        TEST_ASSERT_NOT_NULL(s);
        TEST_ASSERT_NOT_NULL(strstr(s, "'sideways'"));
        free(s);
    }
    /* one line on stderr */
    snprintf(args, sizeof args, "--bits 23 --hamming 4 2> %s/gen_err.txt", ACTAG_BINARY_DIR);
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen(args));
    {
        char path[256];
        size_t n = 0;
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
    /* an empty family is an error (of the options), not an empty table */
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 16 --hamming 17 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen("--bits 16 --hamming 16 > /dev/null 2>&1"));
    TEST_ASSERT_EQUAL_INT(0, tu_run_gen("--help > /dev/null"));
}

static int gen_file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* Runs the generator with args, stderr to gen_msg.txt; returns the exit
 * status and the message (malloc'd; "" when none) in *msg. */
static int gen_message(const char *args, char **msg)
{
    char path[256], cmd[1024];
    int st;
    snprintf(path, sizeof path, "%s/gen_msg.txt", ACTAG_BINARY_DIR);
    snprintf(cmd, sizeof cmd, "%s > /dev/null 2> '%s'", args, path);
    st = tu_run_gen(cmd);
    *msg = tu_slurp(path, NULL);
    TEST_ASSERT_NOT_NULL(*msg);
    return st;
}

/* Bad, missing and impossible values: status 2 and a message that names the
 * option and the value (a negative --bits or --hamming was once reported as
 * missing, and a --hamming no code can meet exited with status 1). */
static void test_bad_values_are_named(void)
{
    static const struct {
        const char *args, *want;
    } cases[] = {
        {"--bits 24 --hamming -1", "--hamming -1"},
        {"--bits -1 --hamming 4", "--bits -1"},
        {"--hamming -1 --bits 24", "--hamming -1"},
        {"--bits 24", "--hamming is required"},
        {"--hamming 4", "--bits is required"},
        /* more than the counted bits: decided before any search */
        {"--bits 24 --hamming 99", "--hamming 99"},
        {"--bits 24 --hamming 25", "--hamming 25"},
        {"--bits 24 --hamming 21 --mirror physical --exclude corners", "--hamming 21"},
        /* within the bits but met by no code: the search finds the family empty */
        {"--bits 16 --hamming 16", "--hamming 16"},
        {"--bits 16 --hamming 4 --min-complexity 1", "--min-complexity 1"},
        {"--bits 24 --hamming 4 --out /nonexistent-actag-dir/x.txt", "/nonexistent-actag-dir/x.txt"},
    };
    size_t i;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char *msg = NULL, what[512];
        int st = gen_message(cases[i].args, &msg);
        snprintf(what, sizeof what, "%s: status %d, '%.300s'", cases[i].args, st, msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(2, st, what);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(msg, cases[i].want), what);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, strncmp(msg, "actag-familygen: ", 17), what);
        free(msg);
    }
    {
        /* the limit is the number of counted bits: 24 itself is allowed
         * (the search finds no code, status 2 with the empty-family message) */
        char *msg = NULL;
        TEST_ASSERT_EQUAL_INT(2, gen_message("--bits 24 --hamming 24", &msg));
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(msg, "would be empty"), msg);
        free(msg);
    }
}

/* --out is opened only when the search is done: a run that fails before
 * (an empty family) or is interrupted (SIGINT during a long search) leaves
 * an older file as it was (it was truncated at start-up, then removed or
 * left empty). A write that fails (a file-size limit, ulimit -f, with
 * SIGXFSZ ignored so that the write returns an error instead of killing
 * the program) removes the file: none is left truncated. */
static void test_failed_run_leaves_no_file(void)
{
    char path[256], args[1024], cmd[2048];
    char *txt;
    FILE *f;
    snprintf(path, sizeof path, "%s/gen_fail.txt", ACTAG_BINARY_DIR);
    f = fopen(path, "w");
    TEST_ASSERT_NOT_NULL(f);
    fputs("an older file\n", f);
    fclose(f);
    snprintf(args, sizeof args, "--bits 16 --hamming 16 --out '%s' 2>/dev/null", path);
    TEST_ASSERT_EQUAL_INT(2, tu_run_gen(args));
    txt = (char *)hostio_slurp(path, NULL, NULL);
    TEST_ASSERT_NOT_NULL_MESSAGE(txt, "empty family: the older file was removed");
    TEST_ASSERT_EQUAL_STRING_MESSAGE("an older file\n", txt, "empty family: older file changed");
    free(txt);
    /* a 32-bit search runs for hours: stopped after a second */
    snprintf(cmd, sizeof cmd,
             "timeout -s INT 1 \"%s\" --bits 32 --hamming 12 --out '%s' 2>/dev/null",
             ACTAG_FAMILYGEN_PATH, path);
    TEST_ASSERT_EQUAL_INT(124, tu_run(cmd)); /* timeout's status: the search was stopped */
    txt = (char *)hostio_slurp(path, NULL, NULL);
    TEST_ASSERT_NOT_NULL_MESSAGE(txt, "interrupted run: the older file was removed");
    TEST_ASSERT_EQUAL_STRING_MESSAGE("an older file\n", txt, "interrupted run: older file changed");
    free(txt);

    /* the 24-bit h4 table is about 55 KB: 4 blocks of 512 bytes do not hold it */
    snprintf(cmd, sizeof cmd,
             "(trap '' XFSZ; ulimit -f 4 && exec \"%s\" --bits 24 --hamming 4 --out '%s') "
             "2>/dev/null",
             ACTAG_FAMILYGEN_PATH, path);
    TEST_ASSERT_EQUAL_INT(2, tu_run(cmd));
    TEST_ASSERT_FALSE_MESSAGE(gen_file_exists(path), "failed write: truncated file left behind");
    /* the same with room for it: written (the limit was what failed) */
    snprintf(cmd, sizeof cmd,
             "(trap '' XFSZ; ulimit -f 100000 && exec \"%s\" --bits 24 --hamming 4 --out '%s') "
             "2>/dev/null",
             ACTAG_FAMILYGEN_PATH, path);
    TEST_ASSERT_EQUAL_INT(0, tu_run(cmd));
    TEST_ASSERT_TRUE(gen_file_exists(path));
    remove(path);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_txt_equals_published);
    RUN_TEST(test_checked_in_tables_equal_generator);
    RUN_TEST(test_published_four_are_fast);
    RUN_TEST(test_rules_equal_naive_search);
    RUN_TEST(test_apriltag_format_is_static);
    RUN_TEST(test_other_sizes);
    RUN_TEST(test_argument_errors);
    RUN_TEST(test_bad_values_are_named);
    RUN_TEST(test_failed_run_leaves_no_file);
    return UNITY_END();
}
#endif
