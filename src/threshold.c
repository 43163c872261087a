/* Adaptive threshold with van Herk / Gil-Werman min and max, see
 * actag/threshold.h.
 *
 * Window extrema with edge replication equal the extrema over the window
 * cut at the border, so along one direction (n samples, radius r clamped
 * to n-1, w = 2r+1) output i is the extremum over [lo, hi] with
 * lo = max(0, i-r), hi = min(n-1, i+r). Split the samples into blocks of w
 * starting at 0 (the last one possibly shorter) and let P[t] be the
 * extremum from the start of t's block to t, S[t] from t to the end of its
 * block. Then the extremum over [lo, hi] is
 *   S[lo] op P[hi]  when lo and hi are in different blocks,
 *   P[hi]           when they share a block and lo starts it,
 *   S[lo]           when they share a block otherwise (only possible when
 *                   hi = n-1 ends that block),
 * and for a full window (hi - lo = 2r) the first form always holds. */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/threshold.h"

#include <string.h>

#if defined(__SSE2__) && !defined(ACTAG_NO_SIMD)
#define THRESHOLD_SSE2 1
#include <emmintrin.h>
#elif defined(ACTAG_FORCE_SWAR) ||                                                        \
    !(defined(__SSE2__) || defined(__ARM_NEON) || defined(__ARM_FEATURE_MVE) ||          \
      defined(__riscv_vector) || defined(__ALTIVEC__))
/* No vector unit for the compiler to use (Cortex-M, ...): word-at-a-time
 * (SWAR) row operations and a horizontal pass fused with the threshold.
 * (With one, the plain byte loops below are vectorized by the compiler,
 * which beats SWAR.) ACTAG_FORCE_SWAR selects this variant anywhere, so
 * that the tests check it on any host. */
#define THRESHOLD_SCALAR 1
#endif

static uint8_t min8(uint8_t a, uint8_t b)
{
    return a < b ? a : b;
}

static uint8_t max8(uint8_t a, uint8_t b)
{
    return a > b ? a : b;
}

#ifdef THRESHOLD_SSE2
static __m128i ld(const uint8_t *p)
{
    return _mm_loadu_si128((const __m128i *)(const void *)p);
}

static void st(uint8_t *p, __m128i v)
{
    _mm_storeu_si128((__m128i *)(void *)p, v);
}
#endif

#ifdef THRESHOLD_SCALAR
/* Portable word-at-a-time (SWAR) byte min/max: a machine word holds 8
 * (64-bit targets) or 4 bytes; unaligned words are moved with memcpy,
 * which compilers turn into single loads and stores. ACTAG_SWAR_WORD32
 * selects 4-byte words anywhere (the tests check both sizes). */
#if UINTPTR_MAX > 0xFFFFFFFFu && !defined(ACTAG_SWAR_WORD32)
typedef uint64_t word_t;
#define WORD_ONES 0x0101010101010101ull
#else
typedef uint32_t word_t;
#define WORD_ONES 0x01010101u
#endif
#define WORD_HIGH (WORD_ONES * 0x80u)

static word_t ldw(const uint8_t *p)
{
    word_t w;
    memcpy(&w, p, sizeof w);
    return w;
}

static void stw(uint8_t *p, word_t w)
{
    memcpy(p, &w, sizeof w);
}

#if defined(__ARM_FEATURE_SIMD32) && defined(__GNUC__) && !defined(ACTAG_NO_DSP) &&            \
    UINTPTR_MAX <= 0xFFFFFFFFu
#define THRESHOLD_DSP 1
#ifdef __OPTIMIZE__
/* The radius-8 path's loops in assembly (below) need up to 13 registers,
 * which GCC cannot give with the frame pointer of -O0: there the same
 * steps in C. */
#define THRESHOLD_DSP_ASM 1
#endif
/* Cortex-M4/M7 DSP byte instructions: USUB8 sets the GE flag of every byte
 * lane where a >= b, SEL picks per lane by it (2 instructions instead of
 * about 15). ACTAG_NO_DSP selects the portable words. */
static word_t minw(word_t a, word_t b)
{
    word_t r;
    __asm__("usub8 %0, %1, %2\n\tsel %0, %2, %1" : "=&r"(r) : "r"(a), "r"(b) : "cc");
    return r;
}

static word_t maxw(word_t a, word_t b)
{
    word_t r;
    __asm__("usub8 %0, %1, %2\n\tsel %0, %1, %2" : "=&r"(r) : "r"(a), "r"(b) : "cc");
    return r;
}

/* 0x01 in every byte lane where a >= b, else 0. */
static word_t gew(word_t a, word_t b)
{
    word_t r;
    __asm__("usub8 %0, %1, %2\n\tsel %0, %3, %4"
            : "=&r"(r)
            : "r"(a), "r"(b), "r"((word_t)WORD_ONES), "r"((word_t)0u)
            : "cc");
    return r;
}
#else
/* 0xFF in every byte lane where a < b (unsigned), else 0: the lane's
 * borrow of a - b, from a subtraction of the low 7 bits that cannot
 * borrow across lanes and the lanes' top bits. */
static word_t lt_mask(word_t a, word_t b)
{
    word_t t = (a | WORD_HIGH) - (b & ~WORD_HIGH);
    word_t lt = ((~a & b) | ~((a ^ b) | t)) & WORD_HIGH;
    return (lt >> 7) * 0xFFu;
}

static word_t minw(word_t a, word_t b)
{
    return b ^ ((a ^ b) & lt_mask(a, b));
}

static word_t maxw(word_t a, word_t b)
{
    return a ^ ((a ^ b) & lt_mask(a, b));
}

#if WORD_ONES > 0xFFFFFFFFu || defined(ACTAG_THRESHOLD_DOUBLING) /* THRESHOLD_DOUBLING */
static word_t gew(word_t a, word_t b)
{
    return (lt_mask(a, b) & WORD_ONES) ^ WORD_ONES;
}
#endif
#endif

/* The horizontal pass by doubling (row_threshold_doubling below) where a
 * word's min or max is cheap: the DSP instructions, or 8-byte words.
 * ACTAG_THRESHOLD_DOUBLING selects it anywhere (the tests check it with
 * portable 4-byte words too). */
#if defined(THRESHOLD_DSP) || WORD_ONES > 0xFFFFFFFFu || defined(ACTAG_THRESHOLD_DOUBLING)
#define THRESHOLD_DOUBLING 1
#endif
#endif

/* The bitmap at radius 8 (the detector's) with 4-byte words (the DSP path;
 * the tests also run it with the portable words): the vertical prefix
 * extrema and the vertical window extrema in one pass over the row,
 * written straight into the edge-padded lines of the horizontal pass
 * (vertical_fused), and one horizontal pass per row that takes the 17-wide
 * window extrema of a word from 4-sample extrema, thresholds and packs the
 * bits itself (row_r8_bitmap). On the DSP path, when optimizing, these
 * loops and the vertical block suffix rows are assembly (GCC's code for
 * them spills); the C loops give the same bytes. */
#if defined(THRESHOLD_DOUBLING) && WORD_ONES <= 0xFFFFFFFFu
#define THRESHOLD_R8 1
#ifndef THRESHOLD_DSP_ASM /* the C steps' word operations */
#ifdef THRESHOLD_DSP
/* ceil((a + b) / 2) per lane: a - floor((a - b) / 2), the halving
 * difference in [-128, 127] and the result in [0, 255]. */
static word_t avgw(word_t a, word_t b)
{
    word_t h, r;
    __asm__("uhsub8 %0, %2, %3\n\tusub8 %1, %2, %0" : "=&r"(h), "=&r"(r) : "r"(a), "r"(b) : "cc");
    return r;
}

/* min(a + b, 255) and max(a - b, 0) per lane. */
static word_t qaddw(word_t a, word_t b)
{
    word_t r;
    __asm__("uqadd8 %0, %1, %2" : "=r"(r) : "r"(a), "r"(b));
    return r;
}

static word_t qsubw(word_t a, word_t b)
{
    word_t r;
    __asm__("uqsub8 %0, %1, %2" : "=r"(r) : "r"(a), "r"(b));
    return r;
}
#else
static word_t avgw(word_t a, word_t b)
{
    return (a | b) - (((a ^ b) >> 1) & (WORD_ONES * 0x7Fu));
}

static word_t qaddw(word_t a, word_t b)
{
    return minw(a, ~b) + b;
}

static word_t qsubw(word_t a, word_t b)
{
    return maxw(a, b) - b;
}
#endif
#endif
#endif

/* dmin = min(amin, bmin), dmax = max(amax, bmax) over n bytes. d may equal
 * a or b (same pointer); no other overlap. The row operations below have an
 * SSE2 body and a portable one (and tail); both give the same bytes. */
static void minmax_rows(uint8_t *dmin, uint8_t *dmax, const uint8_t *amin, const uint8_t *amax,
                        const uint8_t *bmin, const uint8_t *bmax, size_t n)
{
    size_t k = 0;
#ifdef THRESHOLD_SSE2
    for (; k + 16 <= n; k += 16) {
        __m128i mn = _mm_min_epu8(ld(amin + k), ld(bmin + k));
        __m128i mx = _mm_max_epu8(ld(amax + k), ld(bmax + k));
        st(dmin + k, mn);
        st(dmax + k, mx);
    }
#elif defined(THRESHOLD_SCALAR)
    for (; k + sizeof(word_t) <= n; k += sizeof(word_t)) {
        word_t mn = minw(ldw(amin + k), ldw(bmin + k));
        word_t mx = maxw(ldw(amax + k), ldw(bmax + k));
        stw(dmin + k, mn);
        stw(dmax + k, mx);
    }
#endif
    for (; k < n; k++) {
        uint8_t mn = min8(amin[k], bmin[k]), mx = max8(amax[k], bmax[k]);
        dmin[k] = mn;
        dmax[k] = mx;
    }
}

#ifndef THRESHOLD_SCALAR
/* Full-window thresholds of n consecutive pixels x:
 * d = (2x + off2 >= min(sa, pa) + max(sb, pb)), off2 = 2 * offset in
 * [-512, 510]. */
static void threshold_run(uint8_t *restrict d, const uint8_t *restrict x,
                          const uint8_t *restrict sa, const uint8_t *restrict pa,
                          const uint8_t *restrict sb, const uint8_t *restrict pb, size_t n, int off2)
{
    size_t k = 0;
#ifdef THRESHOLD_SSE2
    /* 2x + off2 >= mn + mx  <=>  x + off >= ceil((mn + mx) / 2) = avg(mn, mx)
     * (the left side is an integer), compared in 16 bits. */
    const __m128i z = _mm_setzero_si128(), one = _mm_set1_epi8(1);
    const __m128i off = _mm_set1_epi16((short)(off2 / 2));
    for (; k + 16 <= n; k += 16) {
        __m128i a = _mm_avg_epu8(_mm_min_epu8(ld(sa + k), ld(pa + k)),
                                 _mm_max_epu8(ld(sb + k), ld(pb + k)));
        __m128i xv = ld(x + k);
        __m128i lt0 = _mm_cmpgt_epi16(_mm_unpacklo_epi8(a, z), _mm_add_epi16(_mm_unpacklo_epi8(xv, z), off));
        __m128i lt1 = _mm_cmpgt_epi16(_mm_unpackhi_epi8(a, z), _mm_add_epi16(_mm_unpackhi_epi8(xv, z), off));
        st(d + k, _mm_andnot_si128(_mm_packs_epi16(lt0, lt1), one));
    }
#endif
    for (; k < n; k++)
        d[k] = (uint8_t)(2 * x[k] + off2 >= min8(sa[k], pa[k]) + max8(sb[k], pb[k]));
}

/* Horizontal pass in place: on entry xmin/xmax hold one line of vertical
 * extrema; on exit they hold the block prefix extrema P, and smin/smax the
 * block suffix extrema S (blocks of w samples, the last one possibly
 * shorter). S is computed first, while xmin/xmax still hold the input. */
static void block_prefix_suffix(uint8_t *restrict xmin, uint8_t *restrict xmax,
                                uint8_t *restrict smin, uint8_t *restrict smax, int n, int w)
{
    int b0, k;
    for (b0 = 0; b0 < n; b0 += w) {
        int end = n - b0 > w ? b0 + w : n; /* one past the block's end */
        uint8_t a = xmin[end - 1], c = xmax[end - 1];
        smin[end - 1] = a;
        smax[end - 1] = c;
        for (k = end - 2; k >= b0; k--) {
            a = min8(a, xmin[k]);
            c = max8(c, xmax[k]);
            smin[k] = a;
            smax[k] = c;
        }
        a = xmin[b0];
        c = xmax[b0];
        for (k = b0 + 1; k < end; k++) {
            a = min8(a, xmin[k]);
            c = max8(c, xmax[k]);
            xmin[k] = a;
            xmax[k] = c;
        }
    }
}

#endif /* !THRESHOLD_SCALAR */

#ifdef THRESHOLD_SCALAR
/* Horizontal pass and threshold of one row in two passes (no SIMD): on
 * entry hmin/hmax hold the row's vertical extrema h (n samples), x the
 * row's pixels; smin/smax receive the block suffix extrema S (blocks of w =
 * 2r+1). A forward pass then keeps the block prefix extremum p of h[t] in
 * a register and writes pixel j = t - r, whose window is [max(0, j-r), t]:
 * min(S[j-r], p) for j >= r (a full window, see the top of the file),
 * p alone for j < r (then t < 2r, inside block 0, so p = extremum of
 * h[0..t]). The pixels j > n-1-r (window [max(0, j-r), n-1]) follow from
 * S and the prefix of the last block up to n-1. */
static void row_threshold(uint8_t *restrict d, const uint8_t *restrict x,
                          const uint8_t *restrict hmin, const uint8_t *restrict hmax,
                          uint8_t *restrict smin, uint8_t *restrict smax, int n, int r, int off2)
{
    const int w = 2 * r + 1;
    int b0, t, j;
    uint8_t pmn = 0, pmx = 0;  /* prefix extrema of the current block */
    int last0 = 0;             /* start of the last block */

    for (b0 = 0; b0 < n; b0 += w) {
        int end = n - b0 > w ? b0 + w : n;
        uint8_t a = hmin[end - 1], c = hmax[end - 1];
        smin[end - 1] = a;
        smax[end - 1] = c;
        for (t = end - 2; t >= b0; t--) {
            a = min8(a, hmin[t]);
            c = max8(c, hmax[t]);
            smin[t] = a;
            smax[t] = c;
        }
    }
    /* Block 0: outputs j = t - r for r <= t < 2r (windows [0, t]); t = 2r,
     * the block's last sample, gives j = r, a full window equal to p. */
    {
        int end = n < w ? n : w;
        pmn = hmin[0];
        pmx = hmax[0];
        for (t = 0; t < end; t++) {
            pmn = min8(pmn, hmin[t]);
            pmx = max8(pmx, hmax[t]);
            if (t >= r)
                d[t - r] = (uint8_t)(2 * x[t - r] + off2 >= pmn + pmx);
        }
    }
    for (b0 = w; b0 < n; b0 += w) {
        int end = n - b0 > w ? b0 + w : n;
        last0 = b0;
        pmn = hmin[b0];
        pmx = hmax[b0];
        for (t = b0; t < end; t++) {
            pmn = min8(pmn, hmin[t]);
            pmx = max8(pmx, hmax[t]);
            d[t - r] = (uint8_t)(2 * x[t - r] + off2 >=
                                 min8(smin[t - 2 * r], pmn) + max8(smax[t - 2 * r], pmx));
        }
    }
    /* Pixels whose window reaches n-1: pmn/pmx now hold the last block's
     * prefix extrema up to n-1. */
    for (j = n - r > 0 ? n - r : 0; j < n; j++) {
        int lo = j - r > 0 ? j - r : 0;
        int mn = smin[lo], mx = smax[lo];
        if (lo < last0) {
            mn = min8(smin[lo], pmn);
            mx = max8(smax[lo], pmx);
        }
        d[j] = (uint8_t)(2 * x[j] + off2 >= mn + mx);
    }
}
#endif

#ifdef THRESHOLD_DOUBLING
/* Minimum and maximum over windows of 2^p samples, in place: on entry a[j]
 * and b[j] are extrema over [j, j + 2^(p-1)), valid for j < len + s (s =
 * 2^(p-1)); on exit over [j, j + 2^p), valid for j < len. Word at a time
 * in increasing j: a word's loads come before its store, and the next
 * word's samples are not yet overwritten. Reads up to len + s + W - 2 and
 * writes up to len + W - 2 (W the word size; the caller's slack). */
static void double_pass(uint8_t *a, uint8_t *b, size_t len, size_t s)
{
    size_t j;
    for (j = 0; j < len; j += sizeof(word_t)) {
        word_t mn = minw(ldw(a + j), ldw(a + j + s));
        word_t mx = maxw(ldw(b + j), ldw(b + j + s));
        stw(a + j, mn);
        stw(b + j, mx);
    }
}

/* Horizontal pass and threshold of one row by doubling, words at a time
 * (no sequential dependency along the row, unlike van Herk): the row's
 * vertical extrema, padded with r copies of the edge sample on each side
 * (window extrema with edge replication), length L = n + 2r; K passes
 * give extrema over windows of 2^K <= w = 2r+1 < 2^(K+1) samples; the
 * window of pixel j, [j, j + w) in the padded row, is the union of
 * [j, j + 2^K) and [j + w - 2^K, j + w). Then x + off >= ceil((mn + mx) /
 * 2) per lane, which is 2x + off2 >= mn + mx (off = off2 / 2 in
 * [-256, 255]): for off >= 0, x >= max(avg, off) - off (avg - off clamped
 * at 0, where the test holds anyway); for off < 0, with q = -off - 1 in
 * [0, 255], x > min(avg, 255 - q) + q (a sum above 255 fails either way).
 *
 * Memory: bufa and bufb hold 2n bytes each and need L + W <= 2n; on entry
 * bufb[0..n) holds hmin and bufb[n..2n) hmax (the caller's layout). */
static void row_threshold_doubling(uint8_t *restrict d, const uint8_t *restrict x,
                                   uint8_t *restrict bufa, uint8_t *restrict bufb, int n, int r,
                                   int off2)
{
    const size_t un = (size_t)n, ur = (size_t)r, len = un + 2u * ur, w = 2u * ur + 1u;
    const int off = off2 / 2;
    const word_t offw = (word_t)WORD_ONES * (word_t)(off >= 0 ? off : -off - 1);
    size_t p2 = 1, c, j;

    /* bufa: padded hmin; bufb: padded hmax (moved down over hmin). */
    memcpy(bufa + ur, bufb, un);
    memset(bufa, bufb[0], ur);
    memset(bufa + ur + un, bufb[un - 1u], ur);
    memmove(bufb + ur, bufb + un, un);
    memset(bufb, bufb[ur], ur);
    memset(bufb + ur + un, bufb[ur + un - 1u], ur);
    memset(bufa + len, 0, sizeof(word_t));
    memset(bufb + len, 0, sizeof(word_t));
    while (2u * p2 <= w) {
        double_pass(bufa, bufb, len - 2u * p2 + 1u, p2);
        p2 *= 2u;
    }
    c = w - p2;
    for (j = 0; j + sizeof(word_t) <= un; j += sizeof(word_t)) {
        word_t mn = minw(ldw(bufa + j), ldw(bufa + j + c));
        word_t mx = maxw(ldw(bufb + j), ldw(bufb + j + c));
        word_t avg = (mn | mx) - (((mn ^ mx) >> 1) & (WORD_ONES * 0x7Fu));
        word_t xv = ldw(x + j);
        word_t res;
        if (off >= 0)
            res = gew(xv, maxw(avg, offw) - offw);
        else
            res = gew(minw(avg, ~offw) + offw, xv) ^ WORD_ONES;
        stw(d + j, res);
    }
    for (; j < un; j++)
        d[j] = (uint8_t)(2 * x[j] + off2 >= min8(bufa[j], bufa[j + c]) + max8(bufb[j], bufb[j + c]));
}
#endif

#ifdef THRESHOLD_R8
#ifndef THRESHOLD_DSP_ASM
/* Vertical extrema of one row where hi's block prefix advances by exactly
 * one row within its block and lo lies in the block before: P = P op row
 * (pmin, pmax updated), then min(S[lo], P) and max(S[lo], P) into hmin and
 * hmax. One pass, the row loaded once. */
static void vertical_fused(uint8_t *restrict hmin, uint8_t *restrict hmax, uint8_t *restrict pmin,
                           uint8_t *restrict pmax, const uint8_t *restrict smin,
                           const uint8_t *restrict smax, const uint8_t *restrict row, size_t n)
{
    size_t c = 0;
    for (; c + sizeof(word_t) <= n; c += sizeof(word_t)) {
        word_t v = ldw(row + c);
        word_t pn = minw(ldw(pmin + c), v), px = maxw(ldw(pmax + c), v);
        stw(pmin + c, pn);
        stw(pmax + c, px);
        stw(hmin + c, minw(ldw(smin + c), pn));
        stw(hmax + c, maxw(ldw(smax + c), px));
    }
    for (; c < n; c++) {
        uint8_t pn = min8(pmin[c], row[c]), px = max8(pmax[c], row[c]);
        pmin[c] = pn;
        pmax[c] = px;
        hmin[c] = min8(smin[c], pn);
        hmax[c] = max8(smax[c], px);
    }
}
#else
/* The DSP path's lines b = a + ROW_R8_D (an immediate offset of the loads
 * below), a 32-byte aligned: a's n + 16 bytes and b's fit in the 5 lines
 * from hmin on when 268 <= n <= 1008. */
#define ROW_R8_D 1024
#define ROW_R8_ASM_MIN_N 268u
#define ROW_R8_ASM_MAX_N 1008u

/* One word of vertical_fused_asm's loop (the loop does two). */
#define VERTICAL_FUSED_WORD                                                                  \
    "ldr %[v], [%[rp]], #4\n\t"                                                              \
    "ldr %[pn], [%[pp]]\n\t"                                                                 \
    "ldr %[px], [%[pp], %[n]]\n\t"                                                           \
    "usub8 %[s1], %[pn], %[v]\n\t"                                                           \
    "sel %[pn], %[v], %[pn]\n\t"                                                             \
    "usub8 %[s1], %[px], %[v]\n\t"                                                           \
    "sel %[px], %[px], %[v]\n\t"                                                             \
    "str %[px], [%[pp], %[n]]\n\t"                                                           \
    "str %[pn], [%[pp]], #4\n\t"                                                             \
    "ldr %[s1], [%[sp], %[sd]]\n\t"                                                          \
    "ldr %[s2], [%[sp]], #4\n\t"                                                             \
    "usub8 %[v], %[s2], %[pn]\n\t"                                                           \
    "sel %[s2], %[pn], %[s2]\n\t"                                                            \
    "usub8 %[v], %[s1], %[px]\n\t"                                                           \
    "sel %[s1], %[s1], %[px]\n\t"                                                            \
    "str %[s1], [%[hp], #1024]\n\t"                                                          \
    "str %[s2], [%[hp]], #4\n\t"

/* vertical_fused for the DSP path's lines in assembly (GCC's code for the
 * C loop keeps its seven pointers poorly): hmax = hmin + ROW_R8_D, pmax =
 * pmin + n, smax = smin + sdist. smin may be pmin (then sdist = n): it is
 * read after pmin's word is stored, min(P, P) = P. Two words per loop,
 * n >= 8; the last n % 8 bytes in C. */
static void vertical_fused_asm(uint8_t *hmin, uint8_t *pmin, const uint8_t *smin, size_t sdist,
                               const uint8_t *row, size_t n)
{
    size_t nw = n & ~(size_t)7u, c;
    const uint8_t *end = row + nw;
    const uint8_t *rp = row;
    uint8_t *hp = hmin, *pp = pmin;
    const uint8_t *sp = smin;
    word_t v, pn, px, s1, s2;
    __asm__ volatile("1:\n\t"
                     VERTICAL_FUSED_WORD VERTICAL_FUSED_WORD
                     "cmp %[rp], %[end]\n\t"
                     "bne 1b"
                     : [rp] "+&r"(rp), [pp] "+&r"(pp), [sp] "+&r"(sp), [hp] "+&r"(hp),
                       [v] "=&r"(v), [pn] "=&r"(pn), [px] "=&r"(px), [s1] "=&r"(s1),
                       [s2] "=&r"(s2)
                     : [end] "r"(end), [n] "r"(n), [sd] "r"(sdist)
                     : "cc", "memory");
    for (c = nw; c < n; c++) {
        uint8_t a = min8(pmin[c], row[c]), b = max8(pmin[c + n], row[c]);
        pmin[c] = a;
        pmin[c + n] = b;
        hmin[c] = min8(smin[c], a);
        hmin[c + ROW_R8_D] = max8(smin[c + sdist], b);
    }
}

/* One word of suffix_rows_asm's loop (the loop does two). */
#define SUFFIX_ROWS_WORD                                                                     \
    "ldr %[v], [%[rp]], #4\n\t"                                                              \
    "ldr %[a], [%[mp], %[n]]\n\t"                                                            \
    "ldr %[b], [%[xp], %[n]]\n\t"                                                            \
    "usub8 %[t], %[a], %[v]\n\t"                                                             \
    "sel %[a], %[v], %[a]\n\t"                                                               \
    "usub8 %[t], %[b], %[v]\n\t"                                                             \
    "sel %[b], %[b], %[v]\n\t"                                                               \
    "str %[a], [%[mp]], #4\n\t"                                                              \
    "str %[b], [%[xp]], #4\n\t"

/* smin = min(smin + n, row), smax = max(smax + n, row) over n bytes (the
 * vertical block suffix extrema, one row up). Two words per loop, n >= 8;
 * the last n % 8 bytes in C. */
static void suffix_rows_asm(uint8_t *smin, uint8_t *smax, const uint8_t *row, size_t n)
{
    size_t nw = n & ~(size_t)7u, c;
    const uint8_t *end = row + nw;
    const uint8_t *rp = row;
    uint8_t *mp = smin, *xp = smax;
    word_t v, a, b, t;
    __asm__ volatile("1:\n\t"
                     SUFFIX_ROWS_WORD SUFFIX_ROWS_WORD
                     "cmp %[rp], %[end]\n\t"
                     "bne 1b"
                     : [rp] "+&r"(rp), [mp] "+&r"(mp), [xp] "+&r"(xp), [v] "=&r"(v),
                       [a] "=&r"(a), [b] "=&r"(b), [t] "=&r"(t)
                     : [end] "r"(end), [n] "r"(n)
                     : "cc", "memory");
    (void)t;
    for (c = nw; c < n; c++) {
        smin[c] = min8(smin[c + n], row[c]);
        smax[c] = max8(smax[c + n], row[c]);
    }
}
#endif

/* min over the 4 samples from p on, per lane (p[0..6] read). */
static word_t min4w(const uint8_t *p)
{
    return minw(minw(ldw(p), ldw(p + 1)), minw(ldw(p + 2), ldw(p + 3)));
}

static word_t max4w(const uint8_t *p)
{
    return maxw(maxw(ldw(p), ldw(p + 1)), maxw(ldw(p + 2), ldw(p + 3)));
}

#ifndef THRESHOLD_DSP_ASM
/* Lane k's a >= b (unsigned) at bit 28 + k, every other bit 0. */
#ifdef THRESHOLD_DSP
static uint32_t ge_top4(word_t a, word_t b)
{
    /* MRS APSR: the GE flags of USUB8 in bits 16..19. On Cortex-M the
     * other bits below 27 read 0; on Cortex-A (user mode) they hold the
     * CPSR's mode, Thumb and IT bits: masked (an armhf build's bitmap was
     * wrong at every radius-8 pixel whose lane those bits hit). */
    uint32_t r;
    __asm__("usub8 %0, %1, %2\n\tmrs %0, APSR" : "=&r"(r) : "r"(a), "r"(b) : "cc");
    return (r & 0x000F0000u) << 12;
}
#else
static uint32_t ge_top4(word_t a, word_t b)
{
    /* the multiply puts lane k's bit 8k at bit 28 + k, without carries */
    return (gew(a, b) * 0x10204080u) & 0xF0000000u;
}
#endif
#else

/* The steps of row_r8_bitmap from p = a + j to end (words), off >= 0
 * (neg = 0) or < 0 (neg = 1), in assembly: GCC's code for the C steps keeps
 * fewer values in registers. The C steps' operations, min and max steps in
 * one loop; acc takes the words' bits as there. */
#define ROW_R8_ASM_STEP(CMP)                                                                 \
                     "ldr %[h0], [%[p], #12]\n\t"                                            \
                     "ldr %[h1], [%[p], #13]\n\t"                                            \
                     "ldr %[h2], [%[p], #14]\n\t"                                            \
                     "ldr %[h3], [%[p], #15]\n\t"                                            \
                     "usub8 %[t], %[h0], %[h1]\n\t"                                          \
                     "sel %[t], %[h1], %[h0]\n\t"                                            \
                     "usub8 %[h0], %[h2], %[h3]\n\t"                                         \
                     "sel %[h0], %[h3], %[h2]\n\t"                                           \
                     "usub8 %[h1], %[t], %[h0]\n\t"                                          \
                     "sel %[h1], %[h0], %[t]\n\t"                                            \
                     "usub8 %[t], %[an8], %[h1]\n\t"                                         \
                     "sel %[t], %[h1], %[an8]\n\t"                                           \
                     "mov %[an8], %[h1]\n\t"                                                 \
                     "ldr %[h0], [%[p]]\n\t"                                                 \
                     "ldr %[h1], [%[p], #16]\n\t"                                            \
                     "str %[t], [%[p], #8]\n\t"                                              \
                     "usub8 %[h2], %[h0], %[t]\n\t"                                          \
                     "sel %[h2], %[t], %[h0]\n\t"                                            \
                     "usub8 %[h3], %[h2], %[h1]\n\t"                                         \
                     "sel %[h3], %[h1], %[h2]\n\t"                                           \
                     "ldr %[h0], [%[p], #1024+12]\n\t"                                       \
                     "ldr %[h1], [%[p], #1024+13]\n\t"                                       \
                     "usub8 %[h2], %[h0], %[h1]\n\t"                                         \
                     "sel %[h2], %[h0], %[h1]\n\t"                                           \
                     "ldr %[h0], [%[p], #1024+14]\n\t"                                       \
                     "ldr %[h1], [%[p], #1024+15]\n\t"                                       \
                     "usub8 %[t], %[h0], %[h1]\n\t"                                          \
                     "sel %[t], %[h0], %[h1]\n\t"                                            \
                     "usub8 %[h0], %[h2], %[t]\n\t"                                          \
                     "sel %[h0], %[h2], %[t]\n\t"                                            \
                     "usub8 %[h1], %[bx8], %[h0]\n\t"                                        \
                     "sel %[h1], %[bx8], %[h0]\n\t"                                          \
                     "mov %[bx8], %[h0]\n\t"                                                 \
                     "ldr %[h0], [%[p], #1024]\n\t"                                          \
                     "ldr %[h2], [%[p], #1024+16]\n\t"                                       \
                     "str %[h1], [%[p], #1024+8]\n\t"                                        \
                     "usub8 %[t], %[h0], %[h1]\n\t"                                          \
                     "sel %[t], %[h0], %[h1]\n\t"                                            \
                     "usub8 %[h1], %[t], %[h2]\n\t"                                          \
                     "sel %[h1], %[t], %[h2]\n\t"                                            \
                     "uhsub8 %[h0], %[h3], %[h1]\n\t"                                        \
                     "usub8 %[h2], %[h3], %[h0]\n\t"                                         \
                     "ldr %[t], [%[p], %[dx]]\n\t"                                           \
                     CMP                                                                     \
                     "mrs %[t], APSR\n\t"                                                    \
                     "and %[t], %[t], #0x000F0000\n\t" /* GE only (Cortex-A: CPSR bits) */ \
                     "lsl %[t], %[t], #12\n\t"                                               \
                     "orr %[acc], %[t], %[acc], lsr #4\n\t"                                  \
                     "adds %[p], %[p], #4\n\t"

#define ROW_R8_ASM_OPERANDS                                                                  \
    [p] "+&r"(p), [dx] "+&r"(dx), [acc] "+&r"(acc), [an8] "+&r"(an8), [bx8] "+&r"(bx8),        \
        [h0] "=&r"(h0), [h1] "=&r"(h1), [h2] "=&r"(h2), [h3] "=&r"(h3), [t] "=&r"(t)

/* Words from p to end (end > p). */
#define ROW_R8_ASM(CMP)                                                                      \
    __asm__ volatile("sub %[dx], %[dx], %[p]\n"                                              \
                     "1:\n\t" ROW_R8_ASM_STEP(CMP) "cmp %[p], %[end]\n\t"                  \
                     "bne 1b"                                                                \
                     : ROW_R8_ASM_OPERANDS                                                   \
                     : [end] "r"(end), [offw] "r"(offw)                                      \
                     : "cc", "memory")

/* One step of ROW_R8_ASM32: m4(j + 8) of the minima into operand AN, of
 * the maxima into BN, the previous step's in AP and BP; the loop runs it
 * twice with the roles swapped, so no register moves. */
#define ROW_R8_ASM32_STEP(CMP, AN, AP, BN, BP)                                               \
    "ldr %[h0], [%[p], #12]\n\t"                                                             \
    "ldr %[h1], [%[p], #13]\n\t"                                                             \
    "usub8 %[h2], %[h0], %[h1]\n\t"                                                          \
    "sel %[h2], %[h1], %[h0]\n\t"                                                            \
    "ldr %[h0], [%[p], #14]\n\t"                                                             \
    "usub8 %[h1], %[h2], %[h0]\n\t"                                                          \
    "sel %[h1], %[h0], %[h2]\n\t"                                                            \
    "ldr %[h0], [%[p], #15]\n\t"                                                             \
    "usub8 %[" AN "], %[h1], %[h0]\n\t"                                                      \
    "sel %[" AN "], %[h0], %[h1]\n\t"                                                        \
    "usub8 %[h1], %[" AP "], %[" AN "]\n\t"                                                  \
    "sel %[h1], %[" AN "], %[" AP "]\n\t"                                                    \
    "ldr %[h0], [%[p]]\n\t"                                                                  \
    "str %[h1], [%[p], #8]\n\t"                                                              \
    "usub8 %[h2], %[h0], %[h1]\n\t"                                                          \
    "sel %[h2], %[h1], %[h0]\n\t"                                                            \
    "ldr %[h0], [%[p], #16]\n\t"                                                             \
    "usub8 %[h3], %[h2], %[h0]\n\t"                                                          \
    "sel %[h3], %[h0], %[h2]\n\t"                                                            \
    "ldr %[h0], [%[p], #1036]\n\t"                                                           \
    "ldr %[h1], [%[p], #1037]\n\t"                                                           \
    "usub8 %[h2], %[h0], %[h1]\n\t"                                                          \
    "sel %[h2], %[h0], %[h1]\n\t"                                                            \
    "ldr %[h0], [%[p], #1038]\n\t"                                                           \
    "usub8 %[h1], %[h2], %[h0]\n\t"                                                          \
    "sel %[h1], %[h2], %[h0]\n\t"                                                            \
    "ldr %[h0], [%[p], #1039]\n\t"                                                           \
    "usub8 %[" BN "], %[h1], %[h0]\n\t"                                                      \
    "sel %[" BN "], %[h1], %[h0]\n\t"                                                        \
    "usub8 %[h1], %[" BP "], %[" BN "]\n\t"                                                  \
    "sel %[h1], %[" BP "], %[" BN "]\n\t"                                                    \
    "ldr %[h0], [%[p], #1024]\n\t"                                                           \
    "str %[h1], [%[p], #1032]\n\t"                                                           \
    "usub8 %[h2], %[h0], %[h1]\n\t"                                                          \
    "sel %[h2], %[h0], %[h1]\n\t"                                                            \
    "ldr %[h0], [%[p], #1040]\n\t"                                                           \
    "usub8 %[h1], %[h2], %[h0]\n\t"                                                          \
    "sel %[h1], %[h2], %[h0]\n\t"                                                            \
    "uhsub8 %[h0], %[h3], %[h1]\n\t"                                                         \
    "usub8 %[h2], %[h3], %[h0]\n\t"                                                          \
    "ldr %[h0], [%[p], %[dx]]\n\t"                                                           \
    CMP                                                                                      \
    "mrs %[h0], APSR\n\t"                                                                    \
    "and %[h0], %[h0], #0x000F0000\n\t" /* GE only (Cortex-A: CPSR bits) */                  \
    "lsl %[h0], %[h0], #12\n\t"                                                              \
    "orr %[acc], %[h0], %[acc], lsr #4\n\t"                                                  \
    "adds %[p], %[p], #4\n\t"

/* Whole words of 32 pixels from p to end (p 32-byte aligned, end - p a
 * positive multiple of 32), two steps per loop, with the two steps'
 * m4(j + 8) in swapped registers (no moves) and 3 temporaries besides the
 * minima: the same results as ROW_R8_ASM_STEP. Each word's acc (raw) is
 * stored over a at its last 4 bytes, which no later step reads. */
#define ROW_R8_ASM32(CMP)                                                                    \
    __asm__ volatile("sub %[dx], %[dx], %[p]\n"                                              \
                     "1:\n\t"                                                                \
                     ROW_R8_ASM32_STEP(CMP, "anB", "anA", "bxB", "bxA")                      \
                     ROW_R8_ASM32_STEP(CMP, "anA", "anB", "bxA", "bxB")                      \
                     "tst %[p], #31\n\t"                                                     \
                     "bne 1b\n\t"                                                            \
                     "str %[acc], [%[p], #-4]\n\t"                                           \
                     "ldr %[h0], %[end]\n\t"                                                 \
                     "cmp %[p], %[h0]\n\t"                                                   \
                     "bne 1b"                                                                \
                     : [p] "+&r"(p), [dx] "+&r"(dx), [acc] "+&r"(acc), [anA] "+&r"(an8),      \
                       [anB] "+&r"(an8b), [bxA] "+&r"(bx8), [bxB] "+&r"(bx8b), [h0] "=&r"(h0), \
                       [h1] "=&r"(h1), [h2] "=&r"(h2), [h3] "=&r"(h3)                        \
                     : [end] "m"(end), [offw] "r"(offw)                                      \
                     : "cc", "memory")

static void row_r8_words32_asm(uint8_t *p, const uint8_t *end, const uint8_t *x, word_t offw,
                               int neg, word_t *an8p, word_t *bx8p)
{
    uint32_t acc = 0u;
    word_t an8 = *an8p, bx8 = *bx8p, an8b = 0u, bx8b = 0u, h0, h1, h2, h3;
    const uint8_t *dx = x;
    if (!neg)
        ROW_R8_ASM32("uqadd8 %[h0], %[h0], %[offw]\n\t"
                     "usub8 %[h0], %[h0], %[h2]\n\t");
    else
        ROW_R8_ASM32("uqsub8 %[h0], %[h0], %[offw]\n\t"
                     "usub8 %[h0], %[h2], %[h0]\n\t");
    (void)h0;
    (void)h1;
    (void)h2;
    (void)h3;
    (void)acc;
    (void)an8b;
    (void)bx8b;
    *an8p = an8;
    *bx8p = bx8;
}

static void row_r8_steps_asm(uint8_t *p, const uint8_t *end, const uint8_t *x, word_t offw,
                             int neg, uint32_t *accp, word_t *an8p, word_t *bx8p)
{
    uint32_t acc = *accp;
    word_t an8 = *an8p, bx8 = *bx8p, h0, h1, h2, h3, t;
    const uint8_t *dx = x;
    if (!neg) /* min(x + off, 255) >= avg */
        ROW_R8_ASM("uqadd8 %[t], %[t], %[offw]\n\t"
                   "usub8 %[t], %[t], %[h2]\n\t");
    else /* avg >= max(x - q, 0), inverted by the caller */
        ROW_R8_ASM("uqsub8 %[t], %[t], %[offw]\n\t"
                   "usub8 %[t], %[h2], %[t]\n\t");
    (void)h0;
    (void)h1;
    (void)h2;
    (void)h3;
    (void)t;
    *accp = acc;
    *an8p = an8;
    *bx8p = bx8;
}
#undef ROW_R8_ASM
#undef ROW_R8_ASM32
#undef ROW_R8_ASM32_STEP
#undef ROW_R8_ASM_STEP
#undef ROW_R8_ASM_OPERANDS
#endif

/* One bitmap row (common.h layout) at radius 8 from the row's vertical
 * extrema padded with 8 copies of the edge sample on each side (a: min,
 * b: max, n + 16 bytes each, n >= 16; overwritten) and the row's pixels x.
 * The window of pixel j is [j, j + 16] of the padded lines; for the word of
 * pixels j..j+3 it is the union of the 4-sample windows at j, j + 4, j + 8,
 * j + 12 and the sample j + 16: with m4(p) the 4-sample extrema and m8(p) =
 * m4(p) op m4(p + 4), the word's extrema are m8(j) op m8(j + 8) op h(j +
 * 16). The step for word j computes m4(j + 12) (m4(j + 8) is the step
 * before's) and m8(j + 8), which it stores over a and b at j + 8, where
 * the step for j + 8 reads it (the samples below j + 16 are not needed any
 * more). Then, per lane, x + off >= ceil((mn + mx) / 2), which is 2x + 2 off
 * >= mn + mx: for off >= 0, min(x + off, 255) >= avg; for off < 0, with
 * q = -off - 1 in [0, 255], not avg >= max(x - q, 0). The bits of 8 words
 * gather into one word of 32 pixels, which goes to the row shifted by the
 * padding column. The last n % 4 pixels are done first, bytewise, before
 * the steps overwrite their samples. */
static void row_r8_bitmap(uint32_t *restrict row, const uint8_t *restrict x, uint8_t *restrict a,
                          uint8_t *restrict b, size_t n, int off)
{
    const word_t offw = (word_t)WORD_ONES * (word_t)(off >= 0 ? off : -off - 1);
    const uint32_t flip = off >= 0 ? 0u : 0xFFFFFFFFu;
    const size_t nw = n & ~(size_t)3u;
    word_t an8 = min4w(a + 8), bx8 = max4w(b + 8);
    uint32_t acc = 0u, carry = 0u, tail = 0u, g;
    size_t j, k = 0, i;

    for (j = nw; j < n; j++) {
        int mn = a[j], mx = b[j];
        for (i = 1; i <= 16u; i++) {
            mn = min8((uint8_t)mn, a[j + i]);
            mx = max8((uint8_t)mx, b[j + i]);
        }
        tail |= (uint32_t)(2 * x[j] + 2 * off >= mn + mx) << (j - nw);
    }
    {
        word_t an4 = min4w(a + 4), bx4 = max4w(b + 4);
        word_t an0 = min4w(a), bx0 = max4w(b);
        stw(a, minw(an0, an4));
        stw(b, maxw(bx0, bx4));
        stw(a + 4, minw(an4, an8));
        stw(b + 4, maxw(bx4, bx8));
    }
#ifdef THRESHOLD_DSP_ASM
    { /* b == a + ROW_R8_D, a 32-byte aligned, 268 <= n <= 1008 */
        size_t n32 = nw & ~(size_t)31u;
        j = 0;
        if (n32 > 0u) {
            row_r8_words32_asm(a, a + n32, x, offw, off < 0, &an8, &bx8);
            for (; k < n32 / 32u; k++) {
                memcpy(&g, a + 32u * k + 28u, 4);
                g ^= flip;
                row[k] = g << 1 | carry;
                carry = g >> 31;
            }
            j = n32;
        }
        if (j < nw) {
            row_r8_steps_asm(a + j, a + nw, x + j, offw, off < 0, &acc, &an8, &bx8);
            j = nw;
        }
    }
#else
    /* The minima first (their word j stored over a at j), then the maxima
     * and the threshold: fewer values live at once than in one loop. */
    for (j = 0; j < nw; j += 4u) {
        word_t an12 = min4w(a + j + 12), am = minw(an8, an12);
        word_t mn = minw(minw(ldw(a + j), am), ldw(a + j + 16));
        stw(a + j + 8, am);
        stw(a + j, mn);
        an8 = an12;
    }
#define ROW_R8_STEP(THR)                                                                     \
    {                                                                                        \
        word_t bx12 = max4w(b + j + 12), bm = maxw(bx8, bx12);                               \
        word_t mx = maxw(maxw(ldw(b + j), bm), ldw(b + j + 16)), avg = avgw(ldw(a + j), mx);  \
        stw(b + j + 8, bm);                                                                  \
        bx8 = bx12;                                                                          \
        acc = (acc >> 4) | (THR);                                                            \
    }
    j = 0;
    while (j < nw) {
        size_t e = nw - j >= 32u ? j + 32u : nw;
        if (off >= 0) {
            for (; j < e; j += 4u)
                ROW_R8_STEP(ge_top4(qaddw(ldw(x + j), offw), avg))
        } else {
            for (; j < e; j += 4u)
                ROW_R8_STEP(ge_top4(avg, qsubw(ldw(x + j), offw)))
        }
        if ((j & 31u) == 0u) {
            acc ^= flip;
            row[k++] = acc << 1 | carry;
            carry = acc >> 31;
        }
    }
#undef ROW_R8_STEP
#endif
    g = (j & 31u) != 0u ? (acc ^ flip) >> (32u - (j & 31u)) : 0u;
    g |= tail << (j & 31u); /* (j & 31) + n % 4 < 32 */
    row[k++] = g << 1 | carry;
    for (; k < ACTAG_BITMAP_WORDS(n); k++)
        row[k] = 0u;
}
#endif

/* Bit i set when p[i] is 1, for i = 0..3 (bytes of 0 / 1; the multiply
 * gathers bits 0, 8, 16, 24 into bits 24..27 without carries; any byte
 * order, as the word is assembled bytewise). */
static uint32_t gather4(const uint8_t *p)
{
    uint32_t x = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
    return (x * 0x01020408u) >> 24;
}

/* Row i of a bitmap (common.h layout) from cols bytes of 0 / 1, padding
 * bits 0: 32 pixels gathered into a word, shifted by the padding column. */
static void pack_row(uint32_t *row, const uint8_t *d, size_t cols)
{
    uint32_t carry = 0u, g;
    size_t c, i, k = 0;
    for (c = 0; c + 32u <= cols; c += 32u) {
        g = 0u;
        for (i = 0; i < 32u; i += 4u)
            g |= gather4(d + c + i) << i;
        row[k++] = g << 1 | carry;
        carry = g >> 31;
    }
    g = 0u;
    for (i = 0; c + i < cols; i++)
        g |= (uint32_t)d[c + i] << i;
    row[k++] = g << 1 | carry;
    for (; k < ACTAG_BITMAP_WORDS(cols); k++)
        row[k] = 0u;
}

#ifdef THRESHOLD_SSE2
/* The SSE2 row path (any radius >= 1, bytes or bitmap, where the scratch
 * holds its two lines): the vertical extrema of a row go straight into
 * lines padded with r copies of the edge sample on each side (window
 * extrema with edge replication), and the horizontal pass works by
 * doubling, 16 lanes at a time (van Herk's block prefix and suffix scans
 * go along the row a byte at a time; the doubling passes do not). With h
 * the smallest power of two such that 3h >= w = 2r + 1, passes s = 1, 2,
 * .., h/2 take the lines, in place, from extrema over s samples to
 * extrema over 2s; the window [j, j + w) of pixel j in the padded line is
 * then the union of the h-sample windows at j, j + o1 and j + o2, o1 =
 * min(h, w - h), o2 = w - h (at r = 8: 3 passes, windows at 0, 8, 9). */
typedef struct {
    size_t r;   /* horizontal radius, >= 1 */
    size_t h;   /* extrema over h samples after the passes */
    size_t o1;  /* the second window's offset */
    size_t o2;  /* the last window's offset */
    size_t end; /* the passes run over [0, end), whole pairs of vectors */
    size_t len; /* bytes of a line, its padding and slack included */
} sse2_geom;

/* The geometry of the lines for n pixels at radius r. The pixels below n
 * need the h-sample extrema below n + w - h; a pass over [0, end) leaves
 * the extrema over 2s samples correct below end - (2s - 2), so end >= n +
 * 2r - 1 suffices. Reads reach end + h/2 (passes) and n16 + w - h (the
 * last vector of pixels, n16 = n rounded up to 16; its lanes from n on
 * are junk, never used); the padding stores (r <= 16) reach n + r + 16. */
static sse2_geom sse2_geometry(size_t n, size_t r)
{
    sse2_geom g;
    size_t w = 2u * r + 1u, e;
    g.r = r;
    g.h = 1u;
    while (3u * g.h < w)
        g.h *= 2u;
    g.o2 = w - g.h;
    g.o1 = g.h < g.o2 ? g.h : g.o2;
    g.end = (n + 2u * r - 1u + 31u) & ~(size_t)31u;
    g.len = g.end + g.h / 2u;
    e = ((n + 15u) & ~(size_t)15u) + g.o2;
    if (e > g.len)
        g.len = e;
    e = r <= 16u ? n + r + 16u : n + 2u * r;
    if (e > g.len)
        g.len = e;
    return g;
}

/* The vertical extrema of one row where hi's block prefix advances by one
 * row and lo lies in the block before (S[lo] op P[hi]): P op= row into
 * pmin and pmax, then min(S, P) and max(S, P) into vmin and vmax, the row
 * loaded once; vector c of it. */
static void vertical_vec_sse2(uint8_t *restrict vmin, uint8_t *restrict vmax,
                              uint8_t *restrict pmin, uint8_t *restrict pmax,
                              const uint8_t *restrict smin, const uint8_t *restrict smax,
                              const uint8_t *restrict row, size_t c)
{
    __m128i v = ld(row + c);
    __m128i pn = _mm_min_epu8(ld(pmin + c), v), px = _mm_max_epu8(ld(pmax + c), v);
    st(pmin + c, pn);
    st(pmax + c, px);
    st(vmin + c, _mm_min_epu8(ld(smin + c), pn));
    st(vmax + c, _mm_max_epu8(ld(smax + c), px));
}

/* The whole row (n >= 16). min and max are idempotent, so the last
 * vector may overlap the one before. */
static void vertical_fused_sse2(uint8_t *restrict vmin, uint8_t *restrict vmax,
                                uint8_t *restrict pmin, uint8_t *restrict pmax,
                                const uint8_t *restrict smin, const uint8_t *restrict smax,
                                const uint8_t *restrict row, size_t n)
{
    size_t c;
    for (c = 0; c + 16u < n; c += 16u)
        vertical_vec_sse2(vmin, vmax, pmin, pmax, smin, smax, row, c);
    vertical_vec_sse2(vmin, vmax, pmin, pmax, smin, smax, row, n - 16u);
}

/* One row of the vertical block suffix extrema, one row up from the
 * last: smin = min(smin + n, row), smax = max(smax + n, row), the row
 * loaded once (n >= 16; the last vector may overlap the one before). */
static void suffix_vec_sse2(uint8_t *smin, uint8_t *smax, const uint8_t *row, size_t n, size_t c)
{
    __m128i v = ld(row + c);
    __m128i mn = _mm_min_epu8(ld(smin + n + c), v), mx = _mm_max_epu8(ld(smax + n + c), v);
    st(smin + c, mn);
    st(smax + c, mx);
}

static void suffix_row_sse2(uint8_t *smin, uint8_t *smax, const uint8_t *row, size_t n)
{
    size_t c;
    for (c = 0; c + 16u < n; c += 16u)
        suffix_vec_sse2(smin, smax, row, n, c);
    suffix_vec_sse2(smin, smax, row, n, n - 16u);
}

/* Edge padding of a line (vertical extrema at l + r, n of them): r copies
 * of each end sample; for r <= 16 one vector store on each side (the left
 * one reaches 16 - r bytes before the line, the right one 16 - r after
 * the padding: room of the caller's layout). */
static void pad_line_sse2(uint8_t *l, size_t n, size_t r)
{
    if (r <= 16u) {
        st(l + r - 16u, _mm_set1_epi8((char)l[r]));
        st(l + r + n, _mm_set1_epi8((char)l[r + n - 1u]));
    } else {
        memset(l, l[r], r);
        memset(l + r + n, l[r + n - 1u], r);
    }
}

/* The doubling passes over both lines, in place (a vector's loads come
 * before its store, and the next vector's samples are not yet
 * overwritten); two vectors per loop. */
static void double_lines_sse2(uint8_t *restrict a, uint8_t *restrict b, const sse2_geom *g)
{
    size_t s, t;
    for (s = 1u; s < g->h; s *= 2u)
        for (t = 0; t < g->end; t += 32u) {
            __m128i mn0 = _mm_min_epu8(ld(a + t), ld(a + t + s));
            __m128i mx0 = _mm_max_epu8(ld(b + t), ld(b + t + s));
            __m128i mn1 = _mm_min_epu8(ld(a + t + 16u), ld(a + t + 16u + s));
            __m128i mx1 = _mm_max_epu8(ld(b + t + 16u), ld(b + t + 16u + s));
            st(a + t, mn0);
            st(b + t, mx0);
            st(a + t + 16u, mn1);
            st(b + t + 16u, mx1);
        }
}

/* ceil((mn + mx) / 2) of the windows of pixels q..q+15 after the passes. */
static __m128i avg16_sse2(const uint8_t *a, const uint8_t *b, size_t q, const sse2_geom *g)
{
    __m128i mn = _mm_min_epu8(_mm_min_epu8(ld(a + q), ld(a + q + g->o1)), ld(a + q + g->o2));
    __m128i mx = _mm_max_epu8(_mm_max_epu8(ld(b + q), ld(b + q + g->o1)), ld(b + q + g->o2));
    return _mm_avg_epu8(mn, mx);
}

/* Per lane x + off >= avg, which is 2x + 2 off >= mn + mx (the left side
 * an integer). off >= 0 (ov = off): 0xFF where it holds, min(x + off, 255)
 * >= avg. off < 0 (ov = -off - 1 in [0, 255]): 0xFF where it fails, avg >=
 * max(x - ov, 0) (for x <= ov both fail, as avg >= 0 > x + off). */
static __m128i holds16_sse2(__m128i xv, __m128i avg, __m128i ov)
{
    __m128i u = _mm_adds_epu8(xv, ov);
    return _mm_cmpeq_epi8(_mm_max_epu8(u, avg), u);
}

static __m128i fails16_sse2(__m128i xv, __m128i avg, __m128i ov)
{
    __m128i u = _mm_subs_epu8(xv, ov);
    return _mm_cmpeq_epi8(_mm_max_epu8(u, avg), avg);
}

/* The mask bits of pixels q..q+15 (xp: their pixels). */
static uint32_t bits16_sse2(const uint8_t *xp, const uint8_t *a, const uint8_t *b, size_t q,
                            const sse2_geom *g, __m128i ov, int neg)
{
    __m128i avg = avg16_sse2(a, b, q, g);
    return (uint32_t)_mm_movemask_epi8(neg ? fails16_sse2(ld(xp), avg, ov)
                                           : holds16_sse2(ld(xp), avg, ov));
}

/* The mask bits of pixels q..q+31, bit k for pixel q + k (xp: their
 * pixels); CMP holds16_sse2 or fails16_sse2. */
#define BITS32_SSE2(CMP, xp)                                                                 \
    ((uint32_t)_mm_movemask_epi8(CMP(ld(xp), avg16_sse2(a, b, q, g), ov)) |                    \
     (uint32_t)_mm_movemask_epi8(CMP(ld((xp) + 16), avg16_sse2(a, b, q + 16u, g), ov)) << 16)

/* The threshold of one row of n pixels x from the lines a, b after the
 * passes: into bytes d (bitmap row NULL) or into the bitmap row (common.h
 * layout, padding bits 0), 32 pixels to a word. For off < 0 the masks are
 * of the pixels that fail, inverted at the end. The last n % 16 (bytes) or
 * n % 32 (bitmap) pixels are read through a local copy (their bytes then
 * written one at a time), so x and d are not accessed beyond n. */
static void row_threshold_sse2(uint8_t *d, uint32_t *row, const uint8_t *x, const uint8_t *a,
                               const uint8_t *b, size_t n, const sse2_geom *g, int off)
{
    const __m128i ov = _mm_set1_epi8((char)(off < 0 ? -off - 1 : off)), one = _mm_set1_epi8(1);
    const uint32_t flip = off < 0 ? 0xFFFFFFFFu : 0u;
    uint8_t xb[32];
    size_t q = 0, k = 0, rem;
    uint32_t carry = 0u, m;

    if (row == NULL) {
        if (off < 0) {
            for (; q + 16u <= n; q += 16u) {
                __m128i z = fails16_sse2(ld(x + q), avg16_sse2(a, b, q, g), ov);
                st(d + q, _mm_andnot_si128(z, one));
            }
        } else {
            for (; q + 16u <= n; q += 16u) {
                __m128i z = holds16_sse2(ld(x + q), avg16_sse2(a, b, q, g), ov);
                st(d + q, _mm_and_si128(z, one));
            }
        }
        rem = n - q; /* 0..15 */
        if (rem > 0u) {
            memset(xb, 0, 16);
            memcpy(xb, x + q, rem);
            m = bits16_sse2(xb, a, b, q, g, ov, off < 0) ^ flip;
            for (k = 0; k < rem; k++)
                d[q + k] = (uint8_t)(m >> k & 1u);
        }
        return;
    }
    if (off < 0) {
        for (; q + 32u <= n; q += 32u) {
            m = ~BITS32_SSE2(fails16_sse2, x + q);
            row[k++] = m << 1 | carry;
            carry = m >> 31;
        }
    } else {
        for (; q + 32u <= n; q += 32u) {
            m = BITS32_SSE2(holds16_sse2, x + q);
            row[k++] = m << 1 | carry;
            carry = m >> 31;
        }
    }
    rem = n - q; /* 0..31 */
    m = 0u;
    if (rem > 0u) {
        memset(xb, 0, sizeof xb);
        memcpy(xb, x + q, rem);
        m = bits16_sse2(xb, a, b, q, g, ov, off < 0);
        if (rem > 16u) /* (no vector of pixels from n16 on: see sse2_geometry) */
            m |= bits16_sse2(xb + 16, a, b, q + 16u, g, ov, off < 0) << 16;
        m = (m ^ flip) & ((1u << rem) - 1u);
    }
    row[k++] = m << 1 | carry;
    for (; k < ACTAG_BITMAP_WORDS(n); k++)
        row[k] = 0u;
}
#undef BITS32_SSE2
#endif

/* The threshold into bytes (bitmap == NULL: dst, dst_stride) or into a
 * bitmap (each row through the cols bytes after the scratch's own). */
/* The vertical extrema of rows lo..hi into vmin/vmax: the rows up to hi
 * folded into hi's block prefix extrema pmin/pmax (from *phi, the last row
 * folded, on), then combined with lo's block suffix extrema smn/smx (or
 * either alone when lo and hi share a block). */
static void vertical_window(uint8_t *vmin, uint8_t *vmax, uint8_t *pmin, uint8_t *pmax,
                            const uint8_t *smn, const uint8_t *smx, const uint8_t *src,
                            size_t sstride, int *phi, int lo, int hi, int wv, size_t ucols)
{
    while (*phi < hi) {
        const uint8_t *row;
        ++*phi;
        row = src + (size_t)*phi * sstride;
        if (*phi % wv == 0) {
            memcpy(pmin, row, ucols);
            memcpy(pmax, row, ucols);
        } else {
            minmax_rows(pmin, pmax, pmin, pmax, row, row, ucols);
        }
    }
    if (hi / wv != lo / wv) {
        minmax_rows(vmin, vmax, smn, smx, pmin, pmax, ucols);
    } else if (lo % wv == 0) { /* lo starts hi's block */
        memcpy(vmin, pmin, ucols);
        memcpy(vmax, pmax, ucols);
    } else { /* same block, cut at the bottom */
        memcpy(vmin, smn, ucols);
        memcpy(vmax, smx, ucols);
    }
}

static int threshold_core(const uint8_t *src, int rows, int cols, int src_stride, uint8_t *dst,
                          int dst_stride, uint32_t *bitmap, int radius, int offset,
                          void *scratch, size_t scratch_size)
{
    uint8_t *rowbuf;
    size_t ucols, sstride, dstride, nblk;
    uint8_t *sbuf_min, *sbuf_max, *pmin, *pmax, *hmin, *hmax, *hsmin, *hsmax;
    int rv, rh, wv, wh, i, j, sblk, phi, off2;
#ifdef THRESHOLD_R8
    int fast8;
#endif
#ifdef THRESHOLD_SSE2
    sse2_geom geo;
    uint8_t *la = NULL, *lb = NULL;
    int fastx = 0;
#endif

    if (src == NULL || (dst == NULL && bitmap == NULL) || scratch == NULL)
        return ACTAG_ERR_NULL;
    if (rows < 1 || cols < 1 || rows > ACTAG_MAX_DIM || cols > ACTAG_MAX_DIM ||
        src_stride < cols || (bitmap == NULL && dst_stride < cols))
        return ACTAG_ERR_SIZE;
    if (radius < 0 || (bitmap == NULL ? (const void *)src == (const void *)dst
                                      : (const void *)src == (const void *)bitmap))
        return ACTAG_ERR_PARAM;
    if (scratch_size < ACTAG_THRESHOLD_SCRATCH_SIZE_R(rows, cols, radius) +
                           (bitmap != NULL ? (size_t)cols : 0u))
        return ACTAG_ERR_WORKSPACE;

    /* A radius beyond the image gives the same windows as n-1. */
    rv = radius < rows - 1 ? radius : rows - 1;
    rh = radius < cols - 1 ? radius : cols - 1;
    wv = 2 * rv + 1;
    wh = 2 * rh + 1;
    /* 2x - mn - mx lies in [-510, 510], so offsets beyond [-256, 255] give
     * the same answers as those bounds; clamping avoids int overflow. */
    off2 = 2 * (offset < -256 ? -256 : (offset > 255 ? 255 : offset));

    ucols = (size_t)cols;
    sstride = (size_t)src_stride;
    dstride = (size_t)dst_stride;
    rowbuf = (uint8_t *)scratch + ACTAG_THRESHOLD_SCRATCH_SIZE_R(rows, cols, radius);
    if (bitmap != NULL) { /* the padding rows */
        size_t wpr = ACTAG_BITMAP_WORDS(cols);
        memset(bitmap, 0, wpr * 4u);
        memset(bitmap + ((size_t)rows + 1u) * wpr, 0, wpr * 4u);
    }
    if (rv == 0 && rh == 0) {
        /* 1 x 1 windows: mn = mx = x, so the answer is offset >= 0. */
        for (i = 0; i < rows; i++) {
            if (bitmap != NULL) {
                memset(rowbuf, offset >= 0, ucols);
                pack_row(bitmap + ((size_t)i + 1u) * ACTAG_BITMAP_WORDS(cols), rowbuf, ucols);
            } else if (dst != NULL) { /* always, without a bitmap (GCC cannot tell) */
                memset(dst + (size_t)i * dstride, offset >= 0, ucols);
            }
        }
        return ACTAG_OK;
    }
    nblk = (size_t)(wv < rows ? wv : rows);
    sbuf_min = (uint8_t *)scratch;
    sbuf_max = sbuf_min + nblk * ucols;
    pmin = sbuf_max + nblk * ucols;
    pmax = pmin + ucols;
    hmin = pmax + ucols;
    hmax = hmin + ucols;
    hsmin = hmax + ucols;
    hsmax = hsmin + ucols;

#ifdef THRESHOLD_R8
    /* hsmin..hsmax and hmin..hmax hold 2 cols bytes each (cols + 16 needed);
     * the assembly's lines need 268 <= cols <= 1008 */
    fast8 = bitmap != NULL && rh == 8 && cols >= 16;
#ifdef THRESHOLD_DSP_ASM
    fast8 = fast8 && ucols >= ROW_R8_ASM_MIN_N && ucols <= ROW_R8_ASM_MAX_N;
#endif
#endif
#ifdef THRESHOLD_SSE2
    /* The SSE2 row path where its two lines fit in the 4 cols bytes from
     * hmin on (5 with the bitmap's row bytes, which it does not use): 16
     * bytes before each line for the left padding store. The lines' slack
     * is cleared once, so that the junk lanes read only defined bytes. */
    if (rh >= 1 && cols >= 16) {
        size_t full = ucols + 2u * (size_t)rh;
        geo = sse2_geometry(ucols, (size_t)rh);
        if (32u + 2u * geo.len <= (bitmap != NULL ? 5u : 4u) * ucols) {
            fastx = 1;
            la = hmin + 16;
            lb = la + geo.len + 16u;
            memset(la + full, 0, geo.len - full);
            memset(lb + full, 0, geo.len - full);
        }
    }
#endif
    sblk = -1; /* block whose suffix extrema are in sbuf */
    phi = -1;  /* last row folded into pmin/pmax */
    for (i = 0; i < rows; i++) {
        int lo = i - rv > 0 ? i - rv : 0;
        int hi = i + rv < rows - 1 ? i + rv : rows - 1;
        int bl = lo / wv;
        const uint8_t *x = src + (size_t)i * sstride;
        uint8_t *d = bitmap != NULL ? rowbuf : dst + (size_t)i * dstride;

        /* Vertical: suffix extrema of lo's block, computed when first needed
         * (lo only moves forward, so one block buffer suffices). */
        if (bl != sblk) {
            int b0 = bl * wv;
            int end = rows - b0 > wv ? b0 + wv : rows;
            int t = end - 1 - b0;
            const uint8_t *row = src + (size_t)(end - 1) * sstride;
            memcpy(sbuf_min + (size_t)t * ucols, row, ucols);
            memcpy(sbuf_max + (size_t)t * ucols, row, ucols);
            for (t--; t >= 0; t--) {
                uint8_t *smn = sbuf_min + (size_t)t * ucols, *smx = sbuf_max + (size_t)t * ucols;
                row = src + (size_t)(b0 + t) * sstride;
#ifdef THRESHOLD_DSP_ASM
                if (ucols >= 8u) {
                    suffix_rows_asm(smn, smx, row, ucols);
                    continue;
                }
#endif
#ifdef THRESHOLD_SSE2
                if (ucols >= 16u) {
                    suffix_row_sse2(smn, smx, row, ucols);
                    continue;
                }
#endif
                minmax_rows(smn, smx, smn + ucols, smx + ucols, row, row, ucols);
            }
            sblk = bl;
        }
#ifdef THRESHOLD_SSE2
        if (fastx) {
            const uint8_t *smn = sbuf_min + (size_t)(lo - bl * wv) * ucols;
            const uint8_t *smx = sbuf_max + (size_t)(lo - bl * wv) * ucols;
            uint8_t *va = la + geo.r, *vb = lb + geo.r;
            if (phi == hi - 1 && hi % wv != 0 && hi / wv != bl) {
                vertical_fused_sse2(va, vb, pmin, pmax, smn, smx, src + (size_t)hi * sstride,
                                    ucols);
                phi = hi;
            } else {
                vertical_window(va, vb, pmin, pmax, smn, smx, src, sstride, &phi, lo, hi, wv,
                                ucols);
            }
            pad_line_sse2(la, ucols, geo.r);
            pad_line_sse2(lb, ucols, geo.r);
            double_lines_sse2(la, lb, &geo);
            row_threshold_sse2(
                d, bitmap != NULL ? bitmap + ((size_t)i + 1u) * ACTAG_BITMAP_WORDS(cols) : NULL, x,
                la, lb, ucols, &geo, off2 / 2);
            continue;
        }
#endif
#ifdef THRESHOLD_R8
        /* Radius 8 into a bitmap: the edge-padded vertical extrema in
         * hsmin..hsmax (min) and hmin..hmax (max), 2 cols bytes each. */
        if (fast8) {
            const uint8_t *smn = sbuf_min + (size_t)(lo - bl * wv) * ucols;
            const uint8_t *smx = sbuf_max + (size_t)(lo - bl * wv) * ucols;
#ifdef THRESHOLD_DSP_ASM
            /* The 5 cols bytes from hmin on (hmin..hsmax and the bitmap's
             * row bytes), a 32-byte aligned. One assembly pass wherever P
             * advances by at most one row: lo in the block before hi's
             * (S[lo] op P[hi]; a new block starts P from the identity; a
             * row folded again changes nothing), or lo starting hi's block
             * (P[hi] alone: S := the old P, min(P, P op row) = P op row). */
            uint8_t *pa = hmin + ((32u - ((uintptr_t)hmin & 31u)) & 31u), *pb = pa + ROW_R8_D;
            if ((phi == hi - 1 || phi == hi) &&
                (hi / wv != bl || (lo % wv == 0 && phi == hi - 1))) {
                if (phi == hi - 1 && hi % wv == 0) {
                    memset(pmin, 0xFF, ucols);
                    memset(pmax, 0, ucols);
                }
                if (hi / wv != bl)
                    vertical_fused_asm(pa + 8, pmin, smn, (size_t)(smx - smn),
                                       src + (size_t)hi * sstride, ucols);
                else
                    vertical_fused_asm(pa + 8, pmin, pmin, ucols, src + (size_t)hi * sstride,
                                       ucols);
                phi = hi;
#else
            uint8_t *pa = hsmin, *pb = hmin;
            if (phi == hi - 1 && hi % wv != 0 && hi / wv != bl) {
                vertical_fused(pa + 8, pb + 8, pmin, pmax, smn, smx, src + (size_t)hi * sstride,
                               ucols);
                phi = hi;
#endif
            } else {
                vertical_window(pa + 8, pb + 8, pmin, pmax, smn, smx, src, sstride, &phi, lo, hi,
                                wv, ucols);
            }
            {
                /* the edge padding: 8 copies of each end sample */
                word_t e0 = (word_t)WORD_ONES * pa[8], e1 = (word_t)WORD_ONES * pa[7 + ucols];
                word_t e2 = (word_t)WORD_ONES * pb[8], e3 = (word_t)WORD_ONES * pb[7 + ucols];
                stw(pa, e0);
                stw(pa + 4, e0);
                stw(pa + 8 + ucols, e1);
                stw(pa + 12 + ucols, e1);
                stw(pb, e2);
                stw(pb + 4, e2);
                stw(pb + 8 + ucols, e3);
                stw(pb + 12 + ucols, e3);
            }
            row_r8_bitmap(bitmap + ((size_t)i + 1u) * ACTAG_BITMAP_WORDS(cols), x, pa, pb, ucols,
                          off2 / 2);
            continue;
        }
#endif
        /* Vertical: the window's rows lo..hi */
        vertical_window(hmin, hmax, pmin, pmax, sbuf_min + (size_t)(lo - bl * wv) * ucols,
                        sbuf_max + (size_t)(lo - bl * wv) * ucols, src, sstride, &phi, lo, hi,
                        wv, ucols);

        /* Horizontal, then the threshold: 2x + 2 offset >= mn + mx. */
#ifdef THRESHOLD_SCALAR
        (void)wh;
        (void)j;
#ifdef THRESHOLD_DOUBLING
        /* hmin, hmax and hsmin, hsmax are contiguous: 2 cols bytes each */
        if (cols + 2 * rh + (int)sizeof(word_t) <= 2 * cols)
            row_threshold_doubling(d, x, hsmin, hmin, cols, rh, off2);
        else
#endif
            row_threshold(d, x, hmin, hmax, hsmin, hsmax, cols, rh, off2);
#else
        block_prefix_suffix(hmin, hmax, hsmin, hsmax, cols, wh);
        for (j = 0; j < cols; j++) {
            int jlo = j - rh > 0 ? j - rh : 0;
            int jhi = j + rh < cols - 1 ? j + rh : cols - 1;
            int mn, mx;
            if (j >= rh && j + rh <= cols - 1) {
                /* Full windows, j .. cols-rh-1: S[j-rh] op P[j+rh]. */
                int jend = cols - rh;
                threshold_run(d + j, x + j, hsmin + (j - rh), hmin + (j + rh), hsmax + (j - rh),
                              hmax + (j + rh), (size_t)(jend - j), off2);
                j = jend - 1;
                continue;
            }
            if (jhi / wh != jlo / wh) {
                mn = min8(hsmin[jlo], hmin[jhi]);
                mx = max8(hsmax[jlo], hmax[jhi]);
            } else if (jlo % wh == 0) {
                mn = hmin[jhi];
                mx = hmax[jhi];
            } else {
                mn = hsmin[jlo];
                mx = hsmax[jlo];
            }
            d[j] = (uint8_t)(2 * x[j] + off2 >= mn + mx);
        }
#endif
        if (bitmap != NULL)
            pack_row(bitmap + ((size_t)i + 1u) * ACTAG_BITMAP_WORDS(cols), d, ucols);
    }
    return ACTAG_OK;
}

int actag_adaptive_threshold(const uint8_t *src, int rows, int cols, int src_stride,
                             uint8_t *dst, int dst_stride, int radius, int offset,
                             void *scratch, size_t scratch_size)
{
    if (dst == NULL)
        return ACTAG_ERR_NULL;
    return threshold_core(src, rows, cols, src_stride, dst, dst_stride, NULL, radius, offset,
                          scratch, scratch_size);
}

int actag_adaptive_threshold_bitmap(const uint8_t *src, int rows, int cols, int src_stride,
                                    uint32_t *bitmap, int radius, int offset, void *scratch,
                                    size_t scratch_size)
{
    if (bitmap == NULL)
        return ACTAG_ERR_NULL;
    return threshold_core(src, rows, cols, src_stride, NULL, 0, bitmap, radius, offset, scratch,
                          scratch_size);
}
