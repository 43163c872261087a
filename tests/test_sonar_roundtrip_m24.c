/* Sonar round trip of every ID of the 24-bit mirror-safe families
 * (AcTag24m4 .. AcTag24m10) in all 8 orientations (sonar_roundtrip.h). */
#include "sonar_roundtrip.h"

void setUp(void) {}
void tearDown(void) {}

static void test_every_id_of_AcTag24m10_m8_m6(void)
{
    rt_check_family("AcTag24m10", 1);
    rt_check_family("AcTag24m8", 1);
    rt_check_family("AcTag24m6", 1);
}

static void test_every_id_of_AcTag24m4(void) { rt_check_family("AcTag24m4", 1); }

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_every_id_of_AcTag24m10_m8_m6);
    RUN_TEST(test_every_id_of_AcTag24m4);
    return UNITY_END();
}
