/* actag-eval's tracking counts (eval_track.c, included here for its
 * file-local rules): an ID switch counts once per change of a track's
 * reported tag ID, not once per frame after it (review of 2026-12-07: a
 * track that changed ID once and kept the new one for 15 frames counted
 * 15 switches). */
#include "unity.h"

#include "eval_track.c"

#include <stdio.h>

void te_die(const char *msg)
{
    TEST_FAIL_MESSAGE(msg);
}

void setUp(void) {}
void tearDown(void) {}

static void test_an_id_switch_counts_once(void)
{
    static te_idmap m; /* large */
    int f, sw = 0;
    memset(&m, 0, sizeof m);
    /* track 7: tag 3 in frames 0-4, tag 5 in 5-19 (one switch), tag 3 again
     * in 20-24 (a second); track 8: tag 3 throughout */
    for (f = 0; f < 25; f++) {
        sw += te_switched(&m, 7u, f < 5 || f >= 20 ? 3 : 5);
        sw += te_switched(&m, 8u, 3);
    }
    TEST_ASSERT_EQUAL_INT(2, sw);
    TEST_ASSERT_EQUAL_INT(2, m.n);
}

/* Past TE_IDMAP_MAX tracks a run follows no more (and counts no switch for
 * them); the first ones are still followed. */
static void test_the_map_is_bounded(void)
{
    static te_idmap m;
    uint32_t t;
    int sw = 0;
    memset(&m, 0, sizeof m);
    for (t = 1u; t <= (uint32_t)TE_IDMAP_MAX + 10u; t++)
        sw += te_switched(&m, t, 1);
    TEST_ASSERT_EQUAL_INT(0, sw);
    TEST_ASSERT_EQUAL_INT(TE_IDMAP_MAX, m.n);
    TEST_ASSERT_EQUAL_INT(1, te_switched(&m, 1u, 2));
    TEST_ASSERT_EQUAL_INT(0, te_switched(&m, (uint32_t)TE_IDMAP_MAX + 5u, 2));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_an_id_switch_counts_once);
    RUN_TEST(test_the_map_is_bounded);
    return UNITY_END();
}
