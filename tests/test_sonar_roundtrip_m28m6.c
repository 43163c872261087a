/* Sonar round trip of AcTag28m6 in all 8 orientations (sonar_roundtrip.h):
 * every 2nd ID and the last (ACTAG_FULL_ROUNDTRIP=1 in the environment: all
 * 515). */
#include "sonar_roundtrip.h"

void setUp(void) {}
void tearDown(void) {}

static void test_ids_of_AcTag28m6(void) { rt_check_family("AcTag28m6", 2); }

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_ids_of_AcTag28m6);
    return UNITY_END();
}
