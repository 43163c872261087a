/* The library's structure search without its SSE2 loops (ACTAG_NO_SIMD:
 * the plain C ones, as Cortex-M and other targets run them), compiled
 * under other names into test_search_paths, which checks the library (on
 * x86-64 the SSE2 block sums, row scores and best-position scan) against
 * it. */
#define ACTAG_NO_SIMD 1
#define actag_search_map actag_search_map_scalar
#define actag_search_next actag_search_next_scalar
#define actag__search_box actag__search_box_scalar
#include "../src/search.c"
