/*
 * cpu_x86.h -- internal: the run-time choice of the x86-64 AVX2 paths.
 *
 * The library is built for baseline x86-64 (SSE2), so one binary runs on
 * every x86-64 machine; a stage with an AVX2 path compiles that path with
 * ACTAG__AVX2_TARGET (GCC's and Clang's target attribute: no -mavx2 is
 * needed, and nothing else of the file uses AVX2) and calls it when
 * actag__cpu_avx2() says the processor and the operating system support
 * it. Both paths compute the same bytes (each stage's tests compare them).
 *
 * actag__cpu_avx2() reads the feature bits the compiler's runtime (libgcc,
 * compiler-rt) sets once before main (__builtin_cpu_supports, which also
 * checks that the OS saves the YMM registers): no state of this library,
 * re-entrant, no call before constructors needs it.
 *
 * ACTAG_NO_AVX2 (or ACTAG_NO_SIMD) compiles the AVX2 paths out; so does a
 * compiler without the target attribute (GCC < 5, Clang < 6, others), and
 * Windows (MinGW GCC cannot align the stack to 32 bytes for the AVX2
 * spills, GCC PR 54412; clang-cl does not link __cpu_model by default).
 * The check references __cpu_model (libgcc, compiler-rt): a link with
 * -nostdlib needs -lgcc, or a build with ACTAG_NO_AVX2.
 * Built with -mavx2 already (__AVX2__), the check is a constant 1.
 */
#ifndef ACTAG_SRC_CPU_X86_H
#define ACTAG_SRC_CPU_X86_H

#if defined(__x86_64__) && defined(__SSE2__) && !defined(ACTAG_NO_SIMD) &&                     \
    !defined(ACTAG_NO_AVX2) && !defined(_WIN32) && !defined(__CYGWIN__) &&                     \
    ((defined(__clang__) && __clang_major__ >= 6) || (!defined(__clang__) && defined(__GNUC__) && __GNUC__ >= 5))
#define ACTAG__AVX2 1
#define ACTAG__AVX2_TARGET __attribute__((target("avx2")))
#include <immintrin.h>

/* 1 when the AVX2 paths may run on this processor, else 0. */
static inline int actag__cpu_avx2(void)
{
#if defined(__AVX2__)
    return 1;
#else
    return __builtin_cpu_supports("avx2") ? 1 : 0;
#endif
}
#else
#define ACTAG__AVX2 0
#endif

#endif
