/* Sonar round trip of the 24-bit mirror-safe families (AcTag24m4 ..
 * AcTag24m10) in all 8 orientations (sonar_roundtrip.h): every ID of
 * AcTag24m10, m8 and m6, every 3rd ID of AcTag24m4 and its last (about 5 ms
 * per reading; ACTAG_FULL_ROUNDTRIP=1 in the environment: all 661). */
#include "sonar_roundtrip.h"

void setUp(void) {}
void tearDown(void) {}

static void test_every_id_of_AcTag24m10_m8_m6(void)
{
    rt_check_family("AcTag24m10", 1);
    rt_check_family("AcTag24m8", 1);
    rt_check_family("AcTag24m6", 1);
}

static void test_ids_of_AcTag24m4(void) { rt_check_family("AcTag24m4", 3); }

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_every_id_of_AcTag24m10_m8_m6);
    RUN_TEST(test_ids_of_AcTag24m4);
    return UNITY_END();
}
