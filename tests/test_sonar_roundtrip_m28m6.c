/* Sonar round trip of every ID of AcTag28m6 in all 8 orientations
 * (sonar_roundtrip.h). */
#include "sonar_roundtrip.h"

void setUp(void) {}
void tearDown(void) {}

static void test_every_id_of_AcTag28m6(void) { rt_check_family("AcTag28m6", 1); }

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_every_id_of_AcTag28m6);
    return UNITY_END();
}
