/* The library's median filter without its AVX2 path (ACTAG_NO_AVX2: the
 * 16-lane median_rows16, and median_net16 at R = 4, on SSE2 or NEON, or
 * the Cortex-M code, whatever the processor), compiled under other names
 * into test_median, which checks it beside the library (median_rows32 and
 * median_net32 on an x86-64 processor with AVX2) and the portable copy: on
 * an AVX2 machine both x86-64 vector paths. */
#define ACTAG_NO_AVX2 1
#define actag_median_filter actag_median_filter_sse2
#define actag_median_filter16 actag_median_filter16_sse2
#define actag__median_filter16_max actag__median_filter16_max_sse2
#define actag_median_filter_inplace actag_median_filter_inplace_sse2
#define actag__median_filter_bands actag__median_filter_bands_sse2
#define actag__median_filter_inplace_bands actag__median_filter_inplace_bands_sse2
#include "../src/median.c"
