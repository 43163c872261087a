/* Shared by test_familygen.c and test_familygen_28.c, the tests of the host
 * program actag-familygen: Unity's setUp/tearDown (nothing to do) and, in
 * cross builds (no ACTAG_FAMILYGEN_PATH: the emulated suites), the program's
 * main(): one test reported IGNORE and exit status 77, which CTest shows as
 * skipped (tu_main_without_generator, test_util.h); in host builds, the
 * Hamming distances of the families both tests check. The including file
 * puts its tests and its own main() inside #ifdef ACTAG_FAMILYGEN_PATH. */
#ifndef ACTAG_FAMILYGEN_TEST_H
#define ACTAG_FAMILYGEN_TEST_H

#include "unity.h"
#include "test_util.h"

void setUp(void) {}
void tearDown(void) {}

#ifdef ACTAG_FAMILYGEN_PATH
/* The minimum Hamming distances of the published families, AcTag24h4 ..
 * AcTag24h10 and AcTag28m4 .. AcTag28m10. */
#define FG_NHAMMING 4
static const int FG_HAMMING[FG_NHAMMING] = {4, 6, 8, 10};
#else
/* __BASE_FILE__: the test's .c file, which Unity names in its report. */
int main(void)
{
    return tu_main_without_generator(__BASE_FILE__);
}
#endif

#endif
