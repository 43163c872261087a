/*
 * semihost.h -- ARM semihosting calls (the "Angel" interface) for the
 * Cortex-M firmware: BKPT 0xAB with the operation in r0 and a pointer to
 * the argument block (or the argument itself) in r1; the result comes back
 * in r0. QEMU serves them with -semihosting-config enable=on,target=native
 * (files are opened on the host, relative to QEMU's working directory).
 */
#ifndef ARMCHECK_SEMIHOST_H
#define ARMCHECK_SEMIHOST_H

#include <stdint.h>

#define SH_SYS_OPEN 0x01
#define SH_SYS_CLOSE 0x02
#define SH_SYS_WRITE0 0x04
#define SH_SYS_WRITE 0x05
#define SH_SYS_READ 0x06
#define SH_SYS_FLEN 0x0C
#define SH_SYS_GET_CMDLINE 0x15
#define SH_SYS_EXIT 0x18

/* SYS_OPEN modes (ISO C fopen modes by index) */
#define SH_MODE_RB 1
#define SH_MODE_WB 5

/* SYS_EXIT reasons: QEMU exits with status 0 for ApplicationExit and 1 for
 * anything else (AArch32 passes the reason itself in r1). */
#define SH_ADP_STOPPED_APPLICATION_EXIT 0x20026
#define SH_ADP_STOPPED_RUNTIME_ERROR_UNKNOWN 0x20023

static inline int32_t semihost_call(int32_t op, const void *arg)
{
    register int32_t r0 __asm__("r0") = op;
    register const void *r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

/* Ends the QEMU process: status 0 when ok, 1 otherwise. */
static inline void semihost_exit(int ok)
{
    for (;;)
        (void)semihost_call(SH_SYS_EXIT,
                            (const void *)(uintptr_t)(ok ? SH_ADP_STOPPED_APPLICATION_EXIT
                                                         : SH_ADP_STOPPED_RUNTIME_ERROR_UNKNOWN));
}

#endif
