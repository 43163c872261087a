/* A deliberately bad "library" for the check_nm.sh self-test: a writable
 * static, a zero-initialised one, and a heap call. Never linked anywhere. */
#include <stdlib.h>

static int counter = 1;
static int zeroed;

void *check_nm_bad_alloc(size_t n)
{
    zeroed += counter++;
    return malloc(n + (size_t)zeroed);
}
