/* A Unity suite whose 80 tests all fail (tests/CMakeLists.txt,
 * unity_exit_status): its exit status must read as a failure to CTest,
 * neither 77 (the emulated suites' "skipped") nor a count wrapped past 255. */
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

static void test_fails(void)
{
    TEST_ASSERT_EQUAL_INT(1, 2);
}

int main(void)
{
    int i;
    UnityBegin(__FILE__);
    for (i = 0; i < 80; i++)
        RUN_TEST(test_fails);
    return UNITY_END();
}
