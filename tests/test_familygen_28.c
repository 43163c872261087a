/* actag-familygen: the checked-in 28-bit mirror-safe tables (AcTag28m4 ..
 * AcTag28m10) equal the generator's output for the options their names
 * stand for (about 2 s per family; the 24-bit ones: test_familygen). */
#define _POSIX_C_SOURCE 200809L
#include "familygen_test.h"

#include <time.h>

/* Cross builds: only familygen_test.h's main(); the host suite runs these. */
#ifdef ACTAG_FAMILYGEN_PATH

static void test_checked_in_28_bit_tables_equal_generator(void)
{
    int i;
    for (i = 0; i < FG_NHAMMING; i++) {
        char args[1024], a[256], b[256], msg[128];
        size_t la = 0, lb = 0;
        char *ca, *cb;
        struct timespec t0, t1;
        snprintf(a, sizeof a, "%s/gen_AcTag28m%d.c", ACTAG_BINARY_DIR, FG_HAMMING[i]);
        snprintf(args, sizeof args,
                 "--bits 28 --hamming %d --mirror physical --exclude corners --format c --out %s "
                 "2>/dev/null", FG_HAMMING[i], a);
        clock_gettime(CLOCK_MONOTONIC, &t0);
        TEST_ASSERT_EQUAL_INT(0, tu_run_gen(args));
        clock_gettime(CLOCK_MONOTONIC, &t1);
        snprintf(msg, sizeof msg, "AcTag28m%d: %.2f s", FG_HAMMING[i],
                 (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec));
        TEST_MESSAGE(msg);
        snprintf(b, sizeof b, "%s/families/AcTag28m%d.c", ACTAG_SOURCE_DIR, FG_HAMMING[i]);
        ca = tu_slurp(a, &la);
        cb = tu_slurp(b, &lb);
        TEST_ASSERT_NOT_NULL(ca);
        TEST_ASSERT_NOT_NULL_MESSAGE(cb, "checked-in family table missing");
        TEST_ASSERT_NOT_NULL(strstr(ca, "--name AcTag28m")); /* the default name */
        TEST_ASSERT_EQUAL_INT(la, lb);
        TEST_ASSERT_EQUAL_MEMORY(ca, cb, la);
        free(ca);
        free(cb);
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_checked_in_28_bit_tables_equal_generator);
    return UNITY_END();
}
#endif
