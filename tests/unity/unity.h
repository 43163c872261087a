/*
 * A small Unity-compatible test runner, used when no real Unity
 * (ThrowTheSwitch/Unity) is supplied to the build. It implements the subset
 * of Unity's API that actag's tests use, with Unity's semantics and its
 * summary format ("N Tests N Failures N Ignored" then "OK" or "FAIL").
 * Tests written against it compile unchanged against the real Unity.
 * Only the FLOAT (not DOUBLE) assertions are provided, as in a default Unity.
 * Checked against Unity 2.6.0 (same PASS/FAIL/IGNORE/INFO lines and summary).
 * One deliberate difference: the sized asserts (INT8/16/32, UINT8/16/32,
 * HEX8/32) compare the full values, where Unity first truncates both to the
 * named width; so this runner is the stricter of the two there.
 */
#ifndef ACTAG_MINI_UNITY_H
#define ACTAG_MINI_UNITY_H

#include <setjmp.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

void setUp(void);
void tearDown(void);

void UnityBegin(const char *filename);
int UnityEnd(void);
void UnityDefaultTestRun(void (*func)(void), const char *name, int line);
void UnityFail(const char *msg, int line);
void UnityIgnore(const char *msg, int line);
void UnityMessage(const char *msg, int line);
void UnityPassAbort(void);
/* nibbles: 0 prints decimal, else hex zero-padded to that many digits (Unity: HEX8 2, HEX32 8, HEX64 16) */
void UnityAssertInt(long long expected, long long actual, const char *msg, int line, int nibbles);
void UnityAssertUInt(unsigned long long expected, unsigned long long actual, const char *msg, int line, int nibbles);
void UnityAssertIntWithin(long long delta, long long expected, long long actual, const char *msg, int line);
void UnityAssertUIntWithin(unsigned long long delta, unsigned long long expected, unsigned long long actual, const char *msg, int line);
void UnityAssertFloatWithin(float delta, float expected, float actual, const char *msg, int line);
void UnityAssertCompare(long long threshold, long long actual, int op, const char *msg, int line);
void UnityAssertString(const char *expected, const char *actual, const char *msg, int line);
void UnityAssertMemory(const void *expected, const void *actual, size_t len, size_t num, const char *msg, int line);
void UnityAssertUIntArray(const void *expected, const void *actual, size_t size, size_t num, const char *msg, int line, int nibbles);
void UnityAssertBits(unsigned long long mask, unsigned long long expected, unsigned long long actual, const char *msg, int line);

#define UNITY_BEGIN() UnityBegin(__FILE__)
#define UNITY_END() UnityEnd()
#define RUN_TEST(func) UnityDefaultTestRun(func, #func, __LINE__)

#define TEST_FAIL_MESSAGE(m) UnityFail((m), __LINE__)
#define TEST_FAIL() UnityFail(NULL, __LINE__)
#define TEST_IGNORE_MESSAGE(m) UnityIgnore((m), __LINE__)
#define TEST_IGNORE() UnityIgnore(NULL, __LINE__)
#define TEST_MESSAGE(m) UnityMessage((m), __LINE__)
#define TEST_PASS() UnityPassAbort() /* ends the test at once, as passed */

#define TEST_ASSERT_MESSAGE(c, m) do { if (!(c)) UnityFail((m), __LINE__); } while (0)
#define TEST_ASSERT(c) TEST_ASSERT_MESSAGE((c), "Expression Evaluated To FALSE")
#define TEST_ASSERT_TRUE(c) TEST_ASSERT_MESSAGE((c), "Expected TRUE Was FALSE")
#define TEST_ASSERT_FALSE(c) TEST_ASSERT_MESSAGE(!(c), "Expected FALSE Was TRUE")
#define TEST_ASSERT_TRUE_MESSAGE(c, m) TEST_ASSERT_MESSAGE((c), (m))
#define TEST_ASSERT_FALSE_MESSAGE(c, m) TEST_ASSERT_MESSAGE(!(c), (m))
#define TEST_ASSERT_NULL(p) TEST_ASSERT_MESSAGE((p) == NULL, "Expected NULL")
#define TEST_ASSERT_NOT_NULL(p) TEST_ASSERT_MESSAGE((p) != NULL, "Expected Non-NULL")
#define TEST_ASSERT_NULL_MESSAGE(p, m) TEST_ASSERT_MESSAGE((p) == NULL, (m))
#define TEST_ASSERT_NOT_NULL_MESSAGE(p, m) TEST_ASSERT_MESSAGE((p) != NULL, (m))

#define TEST_ASSERT_EQUAL_INT_MESSAGE(e, a, m) UnityAssertInt((long long)(e), (long long)(a), (m), __LINE__, 0)
#define TEST_ASSERT_EQUAL_INT(e, a) TEST_ASSERT_EQUAL_INT_MESSAGE((e), (a), NULL)
#define TEST_ASSERT_EQUAL(e, a) TEST_ASSERT_EQUAL_INT((e), (a))
#define TEST_ASSERT_EQUAL_MESSAGE(e, a, m) TEST_ASSERT_EQUAL_INT_MESSAGE((e), (a), (m))
#define TEST_ASSERT_EQUAL_INT8(e, a) TEST_ASSERT_EQUAL_INT((e), (a))
#define TEST_ASSERT_EQUAL_INT16(e, a) TEST_ASSERT_EQUAL_INT((e), (a))
#define TEST_ASSERT_EQUAL_INT32(e, a) TEST_ASSERT_EQUAL_INT((e), (a))
#define TEST_ASSERT_EQUAL_INT64(e, a) TEST_ASSERT_EQUAL_INT((e), (a))
#define TEST_ASSERT_EQUAL_UINT_MESSAGE(e, a, m) UnityAssertUInt((unsigned long long)(e), (unsigned long long)(a), (m), __LINE__, 0)
#define TEST_ASSERT_EQUAL_UINT(e, a) TEST_ASSERT_EQUAL_UINT_MESSAGE((e), (a), NULL)
#define TEST_ASSERT_EQUAL_UINT8(e, a) TEST_ASSERT_EQUAL_UINT((e), (a))
#define TEST_ASSERT_EQUAL_UINT16(e, a) TEST_ASSERT_EQUAL_UINT((e), (a))
#define TEST_ASSERT_EQUAL_UINT32(e, a) TEST_ASSERT_EQUAL_UINT((e), (a))
#define TEST_ASSERT_EQUAL_UINT64(e, a) TEST_ASSERT_EQUAL_UINT((e), (a))
#define TEST_ASSERT_EQUAL_size_t(e, a) TEST_ASSERT_EQUAL_UINT((e), (a))
#define TEST_ASSERT_EQUAL_UINT8_MESSAGE(e, a, m) TEST_ASSERT_EQUAL_UINT_MESSAGE((e), (a), (m))
#define TEST_ASSERT_EQUAL_UINT32_MESSAGE(e, a, m) TEST_ASSERT_EQUAL_UINT_MESSAGE((e), (a), (m))
#define TEST_ASSERT_EQUAL_HEX32_MESSAGE(e, a, m) UnityAssertUInt((unsigned long long)(e), (unsigned long long)(a), (m), __LINE__, 8)
#define TEST_ASSERT_EQUAL_HEX32(e, a) TEST_ASSERT_EQUAL_HEX32_MESSAGE((e), (a), NULL)
#define TEST_ASSERT_EQUAL_HEX64(e, a) UnityAssertUInt((unsigned long long)(e), (unsigned long long)(a), NULL, __LINE__, 16)
#define TEST_ASSERT_EQUAL_HEX8(e, a) UnityAssertUInt((unsigned long long)(e), (unsigned long long)(a), NULL, __LINE__, 2)
#define TEST_ASSERT_EQUAL_HEX(e, a) TEST_ASSERT_EQUAL_HEX32_MESSAGE((e), (a), NULL)
#define TEST_ASSERT_NOT_EQUAL(e, a) TEST_ASSERT_MESSAGE((e) != (a), "Expected Not-Equal")
#define TEST_ASSERT_NOT_EQUAL_MESSAGE(e, a, m) TEST_ASSERT_MESSAGE((e) != (a), (m))
#define TEST_ASSERT_BITS(mask, e, a) UnityAssertBits((unsigned long long)(mask), (unsigned long long)(e), (unsigned long long)(a), NULL, __LINE__)

#define TEST_ASSERT_INT_WITHIN_MESSAGE(d, e, a, m) UnityAssertIntWithin((long long)(d), (long long)(e), (long long)(a), (m), __LINE__)
#define TEST_ASSERT_INT_WITHIN(d, e, a) TEST_ASSERT_INT_WITHIN_MESSAGE((d), (e), (a), NULL)
#define TEST_ASSERT_UINT_WITHIN(d, e, a) UnityAssertUIntWithin((unsigned long long)(d), (unsigned long long)(e), (unsigned long long)(a), NULL, __LINE__)
#define TEST_ASSERT_FLOAT_WITHIN_MESSAGE(d, e, a, m) UnityAssertFloatWithin((float)(d), (float)(e), (float)(a), (m), __LINE__)
#define TEST_ASSERT_FLOAT_WITHIN(d, e, a) TEST_ASSERT_FLOAT_WITHIN_MESSAGE((d), (e), (a), NULL)
/* Unity: delta = expected * UNITY_FLOAT_PRECISION (1e-5f), in float; so an expected 0 must match exactly */
#define TEST_ASSERT_EQUAL_FLOAT(e, a) TEST_ASSERT_FLOAT_WITHIN((float)(e) * 1e-5f, (e), (a))

/* op: 0 greater-than, 1 greater-or-equal, 2 less-than, 3 less-or-equal (actual vs threshold) */
#define TEST_ASSERT_GREATER_THAN(t, a) UnityAssertCompare((long long)(t), (long long)(a), 0, NULL, __LINE__)
#define TEST_ASSERT_GREATER_OR_EQUAL(t, a) UnityAssertCompare((long long)(t), (long long)(a), 1, NULL, __LINE__)
#define TEST_ASSERT_LESS_THAN(t, a) UnityAssertCompare((long long)(t), (long long)(a), 2, NULL, __LINE__)
#define TEST_ASSERT_LESS_OR_EQUAL(t, a) UnityAssertCompare((long long)(t), (long long)(a), 3, NULL, __LINE__)
#define TEST_ASSERT_GREATER_THAN_MESSAGE(t, a, m) UnityAssertCompare((long long)(t), (long long)(a), 0, (m), __LINE__)
#define TEST_ASSERT_GREATER_OR_EQUAL_MESSAGE(t, a, m) UnityAssertCompare((long long)(t), (long long)(a), 1, (m), __LINE__)
#define TEST_ASSERT_LESS_THAN_MESSAGE(t, a, m) UnityAssertCompare((long long)(t), (long long)(a), 2, (m), __LINE__)
#define TEST_ASSERT_LESS_OR_EQUAL_MESSAGE(t, a, m) UnityAssertCompare((long long)(t), (long long)(a), 3, (m), __LINE__)
#define TEST_ASSERT_GREATER_THAN_INT(t, a) TEST_ASSERT_GREATER_THAN((t), (a))
#define TEST_ASSERT_LESS_THAN_INT(t, a) TEST_ASSERT_LESS_THAN((t), (a))
#define TEST_ASSERT_GREATER_OR_EQUAL_INT(t, a) TEST_ASSERT_GREATER_OR_EQUAL((t), (a))
#define TEST_ASSERT_LESS_OR_EQUAL_INT(t, a) TEST_ASSERT_LESS_OR_EQUAL((t), (a))

#define TEST_ASSERT_EQUAL_STRING_MESSAGE(e, a, m) UnityAssertString((e), (a), (m), __LINE__)
#define TEST_ASSERT_EQUAL_STRING(e, a) TEST_ASSERT_EQUAL_STRING_MESSAGE((e), (a), NULL)
#define TEST_ASSERT_EQUAL_MEMORY_MESSAGE(e, a, len, m) UnityAssertMemory((e), (a), (size_t)(len), 1, (m), __LINE__)
#define TEST_ASSERT_EQUAL_MEMORY(e, a, len) TEST_ASSERT_EQUAL_MEMORY_MESSAGE((e), (a), (len), NULL)
/* Like Unity, comparing 0 bytes / 0 elements fails ("...Which Was Pointless."). */
#define TEST_ASSERT_EQUAL_UINT8_ARRAY(e, a, n) UnityAssertUIntArray((e), (a), 1, (size_t)(n), NULL, __LINE__, 0)
#define TEST_ASSERT_EQUAL_UINT8_ARRAY_MESSAGE(e, a, n, m) UnityAssertUIntArray((e), (a), 1, (size_t)(n), (m), __LINE__, 0)
#define TEST_ASSERT_EQUAL_UINT16_ARRAY(e, a, n) UnityAssertUIntArray((e), (a), 2, (size_t)(n), NULL, __LINE__, 0)
#define TEST_ASSERT_EQUAL_UINT32_ARRAY(e, a, n) UnityAssertUIntArray((e), (a), 4, (size_t)(n), NULL, __LINE__, 0)
#define TEST_ASSERT_EQUAL_HEX32_ARRAY(e, a, n) UnityAssertUIntArray((e), (a), 4, (size_t)(n), NULL, __LINE__, 8)

#ifdef __cplusplus
}
#endif
#endif
