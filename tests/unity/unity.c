/* Implementation of the small Unity-compatible runner (see unity.h). */
#include "unity.h"

#include <stdio.h>
#include <string.h>

static struct {
    const char *file;
    const char *test;
    unsigned tests, failures, ignored;
    int current_failed, current_ignored;
    jmp_buf abort_frame;
} U;

void UnityBegin(const char *filename)
{
    memset(&U, 0, sizeof U);
    U.file = filename;
}

static void finish_line(int line, const char *status, const char *msg)
{
    printf("%s:%d:%s:%s", U.file, line, U.test ? U.test : "?", status);
    if (msg)
        printf(":%s", msg);
    printf("\n");
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
    if (U.current_failed)
        U.failures++;
    else if (U.current_ignored)
        U.ignored++;
    else
        finish_line(line, "PASS", NULL);
    fflush(stdout);
}

int UnityEnd(void)
{
    printf("\n-----------------------\n%u Tests %u Failures %u Ignored \n%s\n", U.tests,
           U.failures, U.ignored, U.failures ? "FAIL" : "OK");
    fflush(stdout);
    return (int)U.failures;
}

static void fail_now(int line, const char *detail, const char *msg)
{
    char buf[512];
    if (detail && msg)
        snprintf(buf, sizeof buf, "%s %s", detail, msg);
    else
        snprintf(buf, sizeof buf, "%s", detail ? detail : (msg ? msg : ""));
    finish_line(line, "FAIL", buf);
    U.current_failed = 1;
    longjmp(U.abort_frame, 1);
}

void UnityFail(const char *msg, int line) { fail_now(line, NULL, msg ? msg : "Failed"); }

void UnityIgnore(const char *msg, int line)
{
    finish_line(line, "IGNORE", msg);
    U.current_ignored = 1;
    longjmp(U.abort_frame, 1);
}

void UnityMessage(const char *msg, int line) { finish_line(line, "INFO", msg); }

void UnityAssertInt(long long e, long long a, const char *msg, int line, int hex)
{
    char buf[160];
    if (e == a)
        return;
    if (hex)
        snprintf(buf, sizeof buf, "Expected 0x%llX Was 0x%llX", (unsigned long long)e, (unsigned long long)a);
    else
        snprintf(buf, sizeof buf, "Expected %lld Was %lld", e, a);
    fail_now(line, buf, msg);
}

void UnityAssertUInt(unsigned long long e, unsigned long long a, const char *msg, int line, int hex)
{
    char buf[160];
    if (e == a)
        return;
    if (hex)
        snprintf(buf, sizeof buf, "Expected 0x%llX Was 0x%llX", e, a);
    else
        snprintf(buf, sizeof buf, "Expected %llu Was %llu", e, a);
    fail_now(line, buf, msg);
}

void UnityAssertIntWithin(long long d, long long e, long long a, const char *msg, int line)
{
    char buf[160];
    long long diff = a > e ? a - e : e - a;
    if (diff <= d)
        return;
    snprintf(buf, sizeof buf, "Values Not Within Delta %lld Expected %lld Was %lld", d, e, a);
    fail_now(line, buf, msg);
}

void UnityAssertFloatWithin(float d, float e, float a, const char *msg, int line)
{
    char buf[160];
    float diff = a > e ? a - e : e - a;
    if (d < 0)
        d = -d;
    if (diff <= d && diff == diff)
        return;
    snprintf(buf, sizeof buf, "Expected %g Was %g (delta %g)", (double)e, (double)a, (double)d);
    fail_now(line, buf, msg);
}

void UnityAssertCompare(long long t, long long a, int op, const char *msg, int line)
{
    static const char *const words[] = {"greater than", "greater or equal to", "less than",
                                        "less or equal to"};
    char buf[160];
    int ok = op == 0 ? a > t : op == 1 ? a >= t : op == 2 ? a < t : a <= t;
    if (ok)
        return;
    snprintf(buf, sizeof buf, "Expected %lld to be %s %lld", a, words[op], t);
    fail_now(line, buf, msg);
}

void UnityAssertString(const char *e, const char *a, const char *msg, int line)
{
    char buf[400];
    if (e == a || (e && a && strcmp(e, a) == 0))
        return;
    snprintf(buf, sizeof buf, "Expected '%s' Was '%s'", e ? e : "NULL", a ? a : "NULL");
    fail_now(line, buf, msg);
}

void UnityAssertMemory(const void *e, const void *a, size_t len, size_t num, const char *msg, int line)
{
    char buf[160];
    size_t i;
    const unsigned char *pe = (const unsigned char *)e, *pa = (const unsigned char *)a;
    if (e == NULL || a == NULL) {
        if (e != a)
            fail_now(line, "Expected Non-NULL", msg);
        return;
    }
    for (i = 0; i < len * num; i++) {
        if (pe[i] != pa[i]) {
            snprintf(buf, sizeof buf, "Element %lu Byte %lu Expected 0x%02X Was 0x%02X",
                     (unsigned long)(i / len), (unsigned long)(i % len), pe[i], pa[i]);
            fail_now(line, buf, msg);
        }
    }
}

void UnityAssertBits(unsigned long long mask, unsigned long long e, unsigned long long a, const char *msg, int line)
{
    UnityAssertUInt(e & mask, a & mask, msg, line, 1);
}
