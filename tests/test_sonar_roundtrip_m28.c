/* Sonar round trip of the 28-bit mirror-safe families in all 8 orientations
 * (sonar_roundtrip.h): every ID of AcTag28m10 and m8 (AcTag28m6: its own
 * test); every 50th ID of AcTag28m4 and its last (ACTAG_FULL_ROUNDTRIP=1 in
 * the environment: every one of its 8910 IDs, about 22 minutes of CPU time;
 * all 71,280 readings pass, docs/families.md). */
#include "sonar_roundtrip.h"

void setUp(void) {}
void tearDown(void) {}

static void test_every_id_of_AcTag28m10_m8(void)
{
    rt_check_family("AcTag28m10", 1);
    rt_check_family("AcTag28m8", 1);
}

static void test_ids_of_AcTag28m4(void) { rt_check_family("AcTag28m4", 50); }

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_every_id_of_AcTag28m10_m8);
    RUN_TEST(test_ids_of_AcTag28m4);
    return UNITY_END();
}
