/* The tracker's frame counter at the end of its type, on the target's own
 * long: on Cortex-M (ILP32) long is as narrow as int, so full_every
 * INT_MAX (which actag_tracker_init accepts) made the restart value
 * full_every + 1 overflow, and INT_MAX - 1 the increment after it; the
 * counter went negative and every later call returned ACTAG_ERR_PARAM.
 * On the host (LP64) these cases always passed: this test matters in the
 * emulated Cortex-M suites. (tools/sim/test_track.c tests the counters
 * with tags in view.) */
#include "unity.h"
#include "actag/actag.h"
#include "actag/track.h"

#include <limits.h>
#include <string.h>

enum { ROWS = 64, COLS = 64 };

static uint8_t ws[ACTAG_WORKSPACE_SIZE(ROWS, COLS)];
static uint8_t img[ROWS * COLS];

void setUp(void) {}
void tearDown(void) {}

/* Feeds `n` blank frames from a counter at LONG_MAX - 1 with this
 * full_every; every call succeeds and the counter stays in 1..LONG_MAX
 * with the last whole-frame search before it. */
static void run_at_the_end(int full_every, int n)
{
    static actag_tracker tr;
    actag_track_params tp;
    actag_params p;
    actag_family fam;
    actag_sonar_geometry g = {0.1f, 1.5f, 1.0472f, NULL, 0u};
    actag_frame fr = {img, ROWS, COLS, COLS, 8};
    actag_track out[ACTAG_TRACK_MAX];
    int i, rc;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
    actag_params_default(&p);
    p.family = &fam;
    p.tag_size = 0.13f;
    actag_track_params_default(&tp);
    tp.full_every = full_every;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_tracker_init(&tr, &tp));
    tr.frame = LONG_MAX - 1;
    for (i = 0; i < n; i++) {
        rc = actag_tracker_update(&tr, &fr, &g, &p, NULL, ws, sizeof ws, out, ACTAG_TRACK_MAX,
                                  NULL);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, rc, "a blank frame: no tag, no error");
        TEST_ASSERT_TRUE_MESSAGE(tr.frame > 0, "the counter stays positive");
        TEST_ASSERT_TRUE(tr.last_full >= -1 && tr.last_full < tr.frame);
    }
}

static void test_full_every_int_max(void) { run_at_the_end(INT_MAX, 4); }

static void test_full_every_int_max_less_one(void) { run_at_the_end(INT_MAX - 1, 4); }

static void test_full_every_default(void) { run_at_the_end(10, 4); }

int main(void)
{
    memset(img, 0, sizeof img);
    UNITY_BEGIN();
    RUN_TEST(test_full_every_int_max);
    RUN_TEST(test_full_every_int_max_less_one);
    RUN_TEST(test_full_every_default);
    return UNITY_END();
}
