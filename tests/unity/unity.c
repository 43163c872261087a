/* Implementation of the small Unity-compatible runner (see unity.h).
 * Result lines follow Unity 2.6's default format:
 *   file:line:test:PASS
 *   file:line:test:FAIL: <detail>[. <message>]     (assertions)
 *   file:line:test:FAIL[: <message>]               (TEST_FAIL / boolean asserts)
 *   file:line:test:IGNORE[: <message>]
 *   file:line:test:INFO[: <message>]
 * Unlike Unity's default build, stdout is flushed after every test so that
 * the lines already printed survive a crash in a later test. */
#include "unity.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static struct {
    const char *file;
    const char *test;
    unsigned tests, failures, ignored;
    int current_failed, current_ignored;
    jmp_buf abort_frame;
} U;

static const char POINTLESS[] = "You Asked Me To Compare Nothing, Which Was Pointless.";

void UnityBegin(const char *filename)
{
    memset(&U, 0, sizeof U);
    U.file = filename;
}

static void line_start(int line)
{
    printf("%s:%d:%s:", U.file, line, U.test ? U.test : "?");
}

void UnityDefaultTestRun(void (*func)(void), const char *name, int line)
{
    U.test = name;
    U.tests++;
    U.current_failed = 0;
    U.current_ignored = 0;
    if (setjmp(U.abort_frame) == 0) {
        setUp();
        func();
    }
    if (setjmp(U.abort_frame) == 0)
        tearDown();
    if (U.current_ignored)
        U.ignored++;
    else if (U.current_failed)
        U.failures++;
    else {
        line_start(line);
        printf("PASS\n");
    }
    fflush(stdout);
}

int UnityEnd(void)
{
    printf("\n-----------------------\n%u Tests %u Failures %u Ignored \n%s\n", U.tests,
           U.failures, U.ignored, U.failures ? "FAIL" : "OK");
    fflush(stdout);
    /* main() returns this: 77 would read as "skipped" to CTest
     * (SKIP_RETURN_CODE of the emulated suites) and a count above 255
     * would wrap to 0, so the count is capped at 76 */
    return U.failures > 76u ? 76 : (int)U.failures;
}

/* Already failed or ignored (e.g. an assertion in tearDown after a failure):
 * like Unity, every assertion function then aborts without a word. */
static void abort_if_done(void)
{
    if (U.current_failed || U.current_ignored)
        longjmp(U.abort_frame, 1);
}

/* An assertion failed: "FAIL: <detail>[. <msg>]", then abort the test. */
static void fail_now(int line, const char *detail, const char *msg)
{
    abort_if_done();
    line_start(line);
    printf("FAIL: %s", detail);
    if (msg)
        printf(". %s", msg);
    printf("\n");
    U.current_failed = 1;
    longjmp(U.abort_frame, 1);
}

void UnityFail(const char *msg, int line)
{
    abort_if_done();
    line_start(line);
    printf("FAIL");
    if (msg)
        printf(":%s%s", msg[0] == ' ' ? "" : " ", msg);
    printf("\n");
    U.current_failed = 1;
    longjmp(U.abort_frame, 1);
}

void UnityIgnore(const char *msg, int line)
{
    abort_if_done();
    line_start(line);
    printf("IGNORE");
    if (msg)
        printf(": %s", msg);
    printf("\n");
    U.current_ignored = 1;
    longjmp(U.abort_frame, 1);
}

void UnityPassAbort(void)
{
    longjmp(U.abort_frame, 1);
}

void UnityMessage(const char *msg, int line)
{
    line_start(line);
    printf("INFO");
    if (msg)
        printf(": %s", msg);
    printf("\n");
}

void UnityAssertInt(long long e, long long a, const char *msg, int line, int nibbles)
{
    char buf[160];
    abort_if_done();
    if (e == a)
        return;
    if (nibbles)
        snprintf(buf, sizeof buf, "Expected 0x%0*llX Was 0x%0*llX", nibbles, (unsigned long long)e,
                 nibbles, (unsigned long long)a);
    else
        snprintf(buf, sizeof buf, "Expected %lld Was %lld", e, a);
    fail_now(line, buf, msg);
}

void UnityAssertUInt(unsigned long long e, unsigned long long a, const char *msg, int line, int nibbles)
{
    char buf[160];
    abort_if_done();
    if (e == a)
        return;
    if (nibbles)
        snprintf(buf, sizeof buf, "Expected 0x%0*llX Was 0x%0*llX", nibbles, e, nibbles, a);
    else
        snprintf(buf, sizeof buf, "Expected %llu Was %llu", e, a);
    fail_now(line, buf, msg);
}

void UnityAssertIntWithin(long long d, long long e, long long a, const char *msg, int line)
{
    /* Unity: the delta is unsigned and the difference is taken in unsigned arithmetic */
    char buf[200];
    unsigned long long diff = a > e ? (unsigned long long)a - (unsigned long long)e
                                    : (unsigned long long)e - (unsigned long long)a;
    abort_if_done();
    if (diff <= (unsigned long long)d)
        return;
    snprintf(buf, sizeof buf, "Values Not Within Delta %lld Expected %lld Was %lld", d, e, a);
    fail_now(line, buf, msg);
}

void UnityAssertUIntWithin(unsigned long long d, unsigned long long e, unsigned long long a, const char *msg,
                           int line)
{
    char buf[200];
    unsigned long long diff = a > e ? a - e : e - a;
    abort_if_done();
    if (diff <= d)
        return;
    snprintf(buf, sizeof buf, "Values Not Within Delta %llu Expected %llu Was %llu", d, e, a);
    fail_now(line, buf, msg);
}

/* Unity's UnityFloatsWithin: equal infinities and NaN == NaN pass; a NaN or
 * infinite difference fails; otherwise |a - e| <= |delta|. */
void UnityAssertFloatWithin(float d, float e, float a, const char *msg, int line)
{
    char buf[160];
    float diff;
    abort_if_done();
    if (isinf(e) && isinf(a) && ((e < 0) == (a < 0)))
        return;
    if (isnan(e) && isnan(a))
        return;
    diff = a - e;
    if (diff < 0)
        diff = -diff;
    if (d < 0)
        d = -d;
    if (!isnan(diff) && !isinf(diff) && !(diff > d))
        return;
    snprintf(buf, sizeof buf, "Expected %.7g Was %.7g", (double)e, (double)a);
    fail_now(line, buf, msg);
}

void UnityAssertCompare(long long t, long long a, int op, const char *msg, int line)
{
    static const char *const words[] = {"greater than", "greater than or equal to", "less than",
                                        "less than or equal to"};
    char buf[160];
    int ok = op == 0 ? a > t : op == 1 ? a >= t : op == 2 ? a < t : a <= t;
    abort_if_done();
    if (ok)
        return;
    snprintf(buf, sizeof buf, "Expected %lld to be %s %lld", a, words[op], t);
    fail_now(line, buf, msg);
}

void UnityAssertString(const char *e, const char *a, const char *msg, int line)
{
    char buf[400];
    abort_if_done();
    if (e == a || (e && a && strcmp(e, a) == 0))
        return;
    snprintf(buf, sizeof buf, "Expected %s%s%s Was %s%s%s", e ? "'" : "", e ? e : "NULL", e ? "'" : "",
             a ? "'" : "", a ? a : "NULL", a ? "'" : "");
    fail_now(line, buf, msg);
}

/* Unity's checks before comparing arrays: nothing to compare is a failure,
 * two equal pointers (both NULL included) pass, one NULL pointer fails. */
static int arrays_trivial(const void *e, const void *a, size_t count, const char *msg, int line)
{
    if (count == 0)
        fail_now(line, POINTLESS, msg);
    if (e == a)
        return 1;
    if (e == NULL)
        fail_now(line, "Expected pointer to be NULL", msg);
    if (a == NULL)
        fail_now(line, "Actual pointer was NULL", msg);
    return 0;
}

void UnityAssertMemory(const void *e, const void *a, size_t len, size_t num, const char *msg, int line)
{
    char buf[160];
    size_t i;
    const unsigned char *pe = (const unsigned char *)e, *pa = (const unsigned char *)a;
    abort_if_done();
    if (len == 0)
        num = 0;
    if (arrays_trivial(e, a, num, msg, line))
        return;
    for (i = 0; i < len * num; i++) {
        if (pe[i] != pa[i]) {
            if (num > 1)
                snprintf(buf, sizeof buf, "Memory Mismatch. Element %lu Byte %lu Expected 0x%02X Was 0x%02X",
                         (unsigned long)(i / len), (unsigned long)(i % len), pe[i], pa[i]);
            else
                snprintf(buf, sizeof buf, "Memory Mismatch. Byte %lu Expected 0x%02X Was 0x%02X",
                         (unsigned long)i, pe[i], pa[i]);
            fail_now(line, buf, msg);
        }
    }
}

static unsigned long long load_unsigned(const unsigned char *p, size_t size)
{
    uint8_t u8;
    uint16_t u16;
    uint32_t u32;
    switch (size) {
    case 1: memcpy(&u8, p, 1); return u8;
    case 2: memcpy(&u16, p, 2); return u16;
    default: memcpy(&u32, p, 4); return u32;
    }
}

void UnityAssertUIntArray(const void *e, const void *a, size_t size, size_t num, const char *msg, int line,
                          int nibbles)
{
    char buf[200];
    size_t i;
    abort_if_done();
    if (arrays_trivial(e, a, num, msg, line))
        return;
    for (i = 0; i < num; i++) {
        unsigned long long ve = load_unsigned((const unsigned char *)e + i * size, size);
        unsigned long long va = load_unsigned((const unsigned char *)a + i * size, size);
        if (ve == va)
            continue;
        if (nibbles)
            snprintf(buf, sizeof buf, "Element %lu Expected 0x%0*llX Was 0x%0*llX", (unsigned long)i, nibbles,
                     ve, nibbles, va);
        else
            snprintf(buf, sizeof buf, "Element %lu Expected %llu Was %llu", (unsigned long)i, ve, va);
        fail_now(line, buf, msg);
    }
}

void UnityAssertBits(unsigned long long mask, unsigned long long e, unsigned long long a, const char *msg, int line)
{
    UnityAssertUInt(e & mask, a & mask, msg, line, 16);
}
