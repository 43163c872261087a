/* AVX2 (32-byte) versions of median.c's vector primitives, for
 * median_rows32 (median_rows.h): included by median.c only, when
 * ACTAG__AVX2 (cpu_x86.h), after its SSE2 primitives. Each function is
 * compiled for AVX2 by its attribute alone (the rest of the library stays
 * baseline x86-64) and runs only when actag__cpu_avx2() says so. Same
 * integers lane for lane as the 16-byte ones (tests/test_median.c compares
 * the AVX2, SSE2 and portable paths with a brute-force median). */
#ifndef ACTAG_MEDIAN_AVX2_H
#define ACTAG_MEDIAN_AVX2_H

typedef __m256i yu8;

ACTAG__AVX2_TARGET static yu8 y_load(const uint8_t *p)
{
    return _mm256_loadu_si256((const __m256i *)(const void *)p);
}

ACTAG__AVX2_TARGET static void y_store(uint8_t *p, yu8 v)
{
    _mm256_storeu_si256((__m256i *)(void *)p, v);
}

ACTAG__AVX2_TARGET static yu8 y_zero(void)
{
    return _mm256_setzero_si256();
}

ACTAG__AVX2_TARGET static yu8 y_dup(unsigned x)
{
    return _mm256_set1_epi8((char)x);
}

ACTAG__AVX2_TARGET static yu8 y_add(yu8 a, yu8 b)
{
    return _mm256_add_epi8(a, b);
}

ACTAG__AVX2_TARGET static yu8 y_sub(yu8 a, yu8 b)
{
    return _mm256_sub_epi8(a, b);
}

/* 0xFF in the lanes that are >= 0 as signed bytes. */
ACTAG__AVX2_TARGET static yu8 y_nonneg(yu8 a)
{
    return _mm256_cmpgt_epi8(a, _mm256_set1_epi8(-1));
}

/* m ? a : b, lane by lane (m: 0x00 or 0xFF lanes). */
ACTAG__AVX2_TARGET static yu8 y_select(yu8 m, yu8 a, yu8 b)
{
    return _mm256_blendv_epi8(b, a, m);
}

/* Interleaves the bytes of a and b over the whole 32 lanes: lo = a0 b0 ..
 * a15 b15, hi = a16 b16 .. a31 b31 (the unpacks work within each 16-byte
 * half; the permutes put the halves in order). */
ACTAG__AVX2_TARGET static void y_zip(yu8 a, yu8 b, yu8 *lo, yu8 *hi)
{
    const __m256i l = _mm256_unpacklo_epi8(a, b), h = _mm256_unpackhi_epi8(a, b);
    *lo = _mm256_permute2x128_si256(l, h, 0x20);
    *hi = _mm256_permute2x128_si256(l, h, 0x31);
}

/* Lowest and highest lane: the two halves' lanes paired, then SSE2's. */
ACTAG__AVX2_TARGET static unsigned y_hmin(yu8 v)
{
    return r16_hmin(_mm_min_epu8(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1)));
}

ACTAG__AVX2_TARGET static unsigned y_hmax(yu8 v)
{
    return r16_hmax(_mm_max_epu8(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1)));
}

/* A set of lanes: bit p for lane p (movemask). */
typedef uint32_t ylanes;

static ylanes ylanes_all(void)
{
    return 0xFFFFFFFFu;
}

static ylanes ylanes_none(void)
{
    return 0u;
}

static int ylanes_any(ylanes s)
{
    return s != 0u;
}

static ylanes ylanes_not(ylanes s)
{
    return ~s;
}

/* The lanes of d that are >= 0 as signed bytes. */
ACTAG__AVX2_TARGET static ylanes ylanes_nonneg(yu8 d)
{
    return ~(uint32_t)_mm256_movemask_epi8(d);
}

/* Is some lane of s negative in d (sign bit set)? */
ACTAG__AVX2_TARGET static int ylanes_any_neg(yu8 d, ylanes s)
{
    return ((uint32_t)_mm256_movemask_epi8(d) & s) != 0u;
}

/* Is every lane of s negative in d? */
ACTAG__AVX2_TARGET static int ylanes_all_neg(yu8 d, ylanes s)
{
    return ((uint32_t)_mm256_movemask_epi8(d) & s) == s;
}

/* 32 bytes of row from column c0 on, each column clamped to 0 .. cols-1
 * (at the frame's sides: a copy; never a read outside the row). */
ACTAG__AVX2_TARGET static __m256i rb_load_clamped(const uint8_t *row, int cols, int c0)
{
    uint8_t b[32];
    int k;
    if (c0 >= 0 && c0 + 32 <= cols)
        return y_load(row + c0);
    for (k = 0; k < 32; k++) {
        const int c = c0 + k;
        b[k] = row[c < 0 ? 0 : (c < cols ? c : cols - 1)];
    }
    return y_load(b);
}

/* For median_rows32's row t (samples row, cols columns), columns j1 ..
 * j1+31: the byte offsets in its hist of the entry the sample entering
 * the windows (column min(j + R, cols - 1)) updates, oi[j - j1], and of
 * the one the sample leaving them (max(j - R - 1, 0)) does, oo[j - j1]:
 * 32 v for level v, or both the row's spare entry 256 + t when the two
 * samples are equal (RB_ROW). Four 16-lane halves of 16-bit offsets. */
ACTAG__AVX2_TARGET static void rb_offsets32(const uint8_t *row, int cols, int j1, int R,
                                            unsigned t, uint16_t *oi, uint16_t *oo)
{
    const __m256i a = rb_load_clamped(row, cols, j1 + R);
    const __m256i b = rb_load_clamped(row, cols, j1 - R - 1);
    const __m256i eq = _mm256_cmpeq_epi8(a, b);
    const __m256i spare = _mm256_set1_epi16((short)((256u + t) * 32u));
    int h;
    for (h = 0; h < 2; h++) {
        const __m128i ah = h ? _mm256_extracti128_si256(a, 1) : _mm256_castsi256_si128(a);
        const __m128i bh = h ? _mm256_extracti128_si256(b, 1) : _mm256_castsi256_si128(b);
        const __m128i eh = h ? _mm256_extracti128_si256(eq, 1) : _mm256_castsi256_si128(eq);
        /* spare where equal (0xFFFF lanes), else 0: larger than any 32 v */
        const __m256i s = _mm256_and_si256(_mm256_cvtepi8_epi16(eh), spare);
        _mm256_store_si256((__m256i *)(void *)(oi + 16 * h),
                           _mm256_max_epu16(_mm256_slli_epi16(_mm256_cvtepu8_epi16(ah), 5), s));
        _mm256_store_si256((__m256i *)(void *)(oo + 16 * h),
                           _mm256_max_epu16(_mm256_slli_epi16(_mm256_cvtepu8_epi16(bh), 5), s));
    }
}

#endif /* ACTAG_MEDIAN_AVX2_H */
