/*
 * semihost.h -- ARM semihosting calls for the QEMU board support (and the
 * armcheck firmware, tools/armcheck, which links this board's startup.c):
 * BKPT 0xAB with the operation in r0 and a pointer to the argument block in
 * r1; the result comes back in r0. QEMU serves them with
 * -semihosting-config enable=on,target=native (files are opened on the
 * host, relative to QEMU's working directory).
 */
#ifndef ACTAG_BOARD_SEMIHOST_H
#define ACTAG_BOARD_SEMIHOST_H

#include <stdint.h>

#define SH_SYS_OPEN 0x01
#define SH_SYS_CLOSE 0x02
#define SH_SYS_WRITE0 0x04
#define SH_SYS_WRITE 0x05
#define SH_SYS_READ 0x06
#define SH_SYS_ISTTY 0x09
#define SH_SYS_SEEK 0x0A
#define SH_SYS_FLEN 0x0C
#define SH_SYS_REMOVE 0x0E
#define SH_SYS_CLOCK 0x10
#define SH_SYS_TIME 0x11
#define SH_SYS_ERRNO 0x13
#define SH_SYS_GET_CMDLINE 0x15
#define SH_SYS_EXIT 0x18
#define SH_SYS_EXIT_EXTENDED 0x20

/* SYS_OPEN modes (ISO C fopen modes by index) */
#define SH_MODE_RB 1
#define SH_MODE_WB 5

/* SYS_EXIT reasons */
#define SH_ADP_STOPPED_APPLICATION_EXIT 0x20026
#define SH_ADP_STOPPED_RUNTIME_ERROR_UNKNOWN 0x20023

static inline int32_t semihost_call(int32_t op, const void *arg)
{
    register int32_t r0 __asm__("r0") = op;
    register const void *r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

/* Ends the QEMU process with exit status `status` (0..255 on the host). */
static inline __attribute__((noreturn)) void semihost_exit(int status)
{
    uint32_t args[2];
    args[0] = SH_ADP_STOPPED_APPLICATION_EXIT;
    args[1] = (uint32_t)status;
    for (;;)
        (void)semihost_call(SH_SYS_EXIT_EXTENDED, args);
}

#endif
