/*
 * fuzz_util.h -- shared pieces of the libFuzzer harnesses (tests/fuzz).
 *
 *   fz_reader   takes values from the front of the fuzzer's input, zeros
 *               once it is used up (every input is a valid case).
 *   fz_int / fz_float
 *               a parameter from one mode byte: mostly the default, else a
 *               value inside the documented range, a hostile special (0, -1,
 *               INT_MIN, NaN, +-inf, 1e30, denormals, just outside the
 *               range, ...) or raw bits. Encoders for seeds write mode
 *               FZ_RAW followed by the raw bits (fz_put_int / fz_put_float).
 *   fz_guarded  a buffer with FZ_GUARD bytes of a known pattern on both
 *               sides and a chosen misalignment; under AddressSanitizer the
 *               guards are also poisoned, so any read or write of them is
 *               reported at once; fz_guard_check() verifies the pattern
 *               (every build) after the call under test.
 *   FZ_CHECK    aborts with a message: libFuzzer reports the input, the
 *               replay driver fails its test.
 *
 * Host-only test code (malloc, stdio).
 */
#ifndef ACTAG_FUZZ_UTIL_H
#define ACTAG_FUZZ_UTIL_H

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define FZ_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define FZ_ASAN 1
#endif
#ifdef FZ_ASAN
#include <sanitizer/asan_interface.h>
#define FZ_POISON(p, n) ASAN_POISON_MEMORY_REGION((p), (n))
#define FZ_UNPOISON(p, n) ASAN_UNPOISON_MEMORY_REGION((p), (n))
#else
#define FZ_POISON(p, n) ((void)(p), (void)(n))
#define FZ_UNPOISON(p, n) ((void)(p), (void)(n))
#endif

#define FZ_CHECK(cond, ...)                                                                  \
    do {                                                                                     \
        if (!(cond)) {                                                                       \
            fprintf(stderr, "fuzz check failed at %s:%d: %s: ", __FILE__, __LINE__, #cond);  \
            fprintf(stderr, __VA_ARGS__);                                                    \
            fputc('\n', stderr);                                                             \
            abort();                                                                         \
        }                                                                                    \
    } while (0)

/* ------------------------------------------------------------------ reader */

typedef struct fz_reader {
    const uint8_t *p;
    size_t n, i;
} fz_reader;

static inline void fz_init(fz_reader *r, const uint8_t *p, size_t n)
{
    r->p = p;
    r->n = n;
    r->i = 0;
}

static inline uint8_t fz_u8(fz_reader *r) { return r->i < r->n ? r->p[r->i++] : 0u; }

static inline uint16_t fz_u16(fz_reader *r)
{
    uint16_t a = fz_u8(r);
    return (uint16_t)(a | (uint16_t)(fz_u8(r) << 8));
}

static inline uint32_t fz_u32(fz_reader *r)
{
    uint32_t a = fz_u16(r);
    return a | ((uint32_t)fz_u16(r) << 16);
}

/* The bytes not read yet. */
static inline const uint8_t *fz_rest(const fz_reader *r, size_t *len)
{
    *len = r->i < r->n ? r->n - r->i : 0;
    return r->p + (r->i < r->n ? r->i : r->n);
}

/* Mode bytes: [0, FZ_IN) default, [FZ_IN, FZ_SPECIAL) in range,
 * [FZ_SPECIAL, FZ_RAW) a special value, [FZ_RAW, 256) raw bits. */
#define FZ_IN 150
#define FZ_SPECIAL 210
#define FZ_RAW 250

static inline int fz_int(fz_reader *r, int def, int lo, int hi)
{
    uint8_t m = fz_u8(r);
    if (m < FZ_IN)
        return def;
    if (m < FZ_SPECIAL) {
        uint32_t span = (uint32_t)((int64_t)hi - (int64_t)lo + 1);
        return span ? (int)((int64_t)lo + (int64_t)(fz_u32(r) % span)) : lo;
    }
    if (m < FZ_RAW) {
        static const int64_t sp[] = {0, 1, -1, 2, INT_MIN, INT_MAX, INT_MIN + 1, INT_MAX - 1,
                                     -2, 255, 256, 32767, 32768, -32768, 65535, 1000000};
        int k = fz_u8(r) % (int)(sizeof sp / sizeof sp[0] + 4);
        switch (k - (int)(sizeof sp / sizeof sp[0])) {
        case 0: return lo > INT_MIN ? lo - 1 : lo;
        case 1: return hi < INT_MAX ? hi + 1 : hi;
        case 2: return def > INT_MIN ? def - 1 : def;
        case 3: return def < INT_MAX ? def + 1 : def;
        default: return (int)sp[k];
        }
    }
    return (int)fz_u32(r);
}

static inline float fz_bits_float(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static inline float fz_float(fz_reader *r, float def, float lo, float hi)
{
    uint8_t m = fz_u8(r);
    if (m < FZ_IN)
        return def;
    if (m < FZ_SPECIAL)
        return lo + (hi - lo) * ((float)fz_u16(r) / 65535.0f);
    if (m < FZ_RAW) {
        static const float sp[] = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, 2.0f, 1e-30f, -1e-30f,
                                   1e30f, -1e30f, FLT_MAX, -FLT_MAX, FLT_MIN, 1e-45f, 1e7f,
                                   3.0e38f, 6.2831853f, 6.2831855f, 3.1415927f, 1e-6f};
        int n = (int)(sizeof sp / sizeof sp[0]), k = fz_u8(r) % (n + 8);
        switch (k - n) {
        case 0: return NAN;
        case 1: return INFINITY;
        case 2: return -INFINITY;
        case 3: return lo;
        case 4: return hi;
        case 5: return nextafterf(lo, -INFINITY);
        case 6: return nextafterf(hi, INFINITY);
        case 7: return -def;
        default: return sp[k];
        }
    }
    return fz_bits_float(fz_u32(r));
}

/* Seed encoders: a value as raw bits (read back exactly by fz_int / fz_float). */
static inline size_t fz_put_u8(uint8_t *b, size_t at, uint8_t v)
{
    b[at] = v;
    return at + 1;
}
static inline size_t fz_put_u16(uint8_t *b, size_t at, uint16_t v)
{
    b[at] = (uint8_t)v;
    b[at + 1] = (uint8_t)(v >> 8);
    return at + 2;
}
static inline size_t fz_put_u32(uint8_t *b, size_t at, uint32_t v)
{
    at = fz_put_u16(b, at, (uint16_t)v);
    return fz_put_u16(b, at, (uint16_t)(v >> 16));
}
static inline size_t fz_put_int(uint8_t *b, size_t at, int v)
{
    at = fz_put_u8(b, at, FZ_RAW);
    return fz_put_u32(b, at, (uint32_t)v);
}
static inline size_t fz_put_float(uint8_t *b, size_t at, float v)
{
    uint32_t u;
    memcpy(&u, &v, sizeof u);
    at = fz_put_u8(b, at, FZ_RAW);
    return fz_put_u32(b, at, u);
}
/* "keep the default" */
static inline size_t fz_put_default(uint8_t *b, size_t at) { return fz_put_u8(b, at, 0); }

/* ------------------------------------------------------------- guarded buffers */

#define FZ_GUARD 64u
#define FZ_PATTERN(i) ((uint8_t)(0xA5u ^ (uint8_t)((i) * 29u)))

typedef struct fz_guarded {
    uint8_t *base;  /* malloc'd block */
    uint8_t *data;  /* the caller's buffer inside it */
    size_t size;    /* bytes of data */
    size_t lead;    /* bytes before data (guard + misalignment) */
} fz_guarded;

/* A buffer of size bytes at an address = misalign (mod 16), guarded. */
static inline uint8_t *fz_guard_alloc(fz_guarded *g, size_t size, unsigned misalign)
{
    size_t i, total;
    g->lead = FZ_GUARD + (misalign & 15u);
    total = g->lead + size + FZ_GUARD;
    g->base = (uint8_t *)malloc(total + 16u);
    FZ_CHECK(g->base != NULL, "out of memory (%lu bytes)", (unsigned long)total);
    /* base is 16-aligned (glibc); move so that data lands on misalign mod 16 */
    g->lead += (16u - ((uintptr_t)(g->base + FZ_GUARD) & 15u)) & 15u;
    g->data = g->base + g->lead;
    g->size = size;
    for (i = 0; i < g->lead; i++)
        g->base[i] = FZ_PATTERN(i);
    for (i = 0; i < FZ_GUARD; i++)
        g->data[size + i] = FZ_PATTERN(i + 7u);
    FZ_POISON(g->base, g->lead);
    FZ_POISON(g->data + size, FZ_GUARD);
    return g->data;
}

/* The guards must be intact (and are unpoisoned for reading them). */
static inline void fz_guard_check(const fz_guarded *g, const char *what)
{
    size_t i;
    FZ_UNPOISON(g->base, g->lead);
    FZ_UNPOISON(g->data + g->size, FZ_GUARD);
    for (i = 0; i < g->lead; i++)
        FZ_CHECK(g->base[i] == FZ_PATTERN(i), "%s: guard byte %lu before the buffer written",
                 what, (unsigned long)(g->lead - i));
    for (i = 0; i < FZ_GUARD; i++)
        FZ_CHECK(g->data[g->size + i] == FZ_PATTERN(i + 7u),
                 "%s: guard byte %lu after the buffer written", what, (unsigned long)i);
    FZ_POISON(g->base, g->lead);
    FZ_POISON(g->data + g->size, FZ_GUARD);
}

static inline void fz_guard_free(fz_guarded *g)
{
    if (g->base) {
        FZ_UNPOISON(g->base, g->lead);
        FZ_UNPOISON(g->data + g->size, FZ_GUARD);
        free(g->base);
    }
    g->base = g->data = NULL;
}

/* xorshift32: deterministic pixel patterns from a seed */
static inline uint32_t fz_xs(uint32_t *s)
{
    uint32_t x = *s ? *s : 0x9e3779b9u;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    return *s = x;
}

#endif /* ACTAG_FUZZ_UTIL_H */
