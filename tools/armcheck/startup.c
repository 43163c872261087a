/*
 * startup.c -- vector table and reset code of the armcheck firmware
 * (Cortex-M4F/M7, bare metal, run under QEMU with semihosting).
 *
 * Reset: enable the FPU (before any floating-point instruction can run),
 * copy .data from its load address, clear .bss, fetch the command line
 * through semihosting (QEMU: -semihosting-config arg=...), split it at
 * spaces into argv and call main(); its return value becomes QEMU's exit
 * status (0 or 1). Any fault prints a line and ends QEMU with status 1.
 */
#include "semihost.h"

#include <stdint.h>

int main(int argc, char **argv);

extern uint32_t __stack_top[];
extern uint32_t __data_start[], __data_end[], __data_load[];
extern uint32_t __bss_start[], __bss_end[];

void Reset_Handler(void);
void armcheck_start(void);
void armcheck_fault(void);

#define ARMCHECK_MAX_ARGS 80
#define ARMCHECK_CMDLINE 2048

/* Lives in .bss, which is cleared before it is filled. */
static char cmdline[ARMCHECK_CMDLINE];

/* Must not touch the FPU: CPACR grants CP10/CP11 (full access) first. */
__attribute__((naked, noreturn)) void Reset_Handler(void)
{
    __asm__ volatile("ldr r0, =0xE000ED88\n\t" /* CPACR */
                     "ldr r1, [r0]\n\t"
                     "orr r1, r1, #(0xF << 20)\n\t"
                     "str r1, [r0]\n\t"
                     "dsb\n\t"
                     "isb\n\t"
                     "b armcheck_start\n\t");
}

void armcheck_fault(void)
{
    (void)semihost_call(SH_SYS_WRITE0, "armcheck: CPU fault (HardFault/MemManage/BusFault/UsageFault)\n");
    semihost_exit(0);
}

__attribute__((noreturn)) void armcheck_start(void)
{
    uint32_t *src = __data_load, *dst;
    uint32_t args[2];
    char *argv[ARMCHECK_MAX_ARGS + 1];
    int argc = 0, rc;
    char *p;

    for (dst = __data_start; dst < __data_end; dst++)
        *dst = *src++;
    for (dst = __bss_start; dst < __bss_end; dst++)
        *dst = 0;

    args[0] = (uint32_t)(uintptr_t)cmdline;
    args[1] = ARMCHECK_CMDLINE - 1;
    if (semihost_call(SH_SYS_GET_CMDLINE, args) != 0)
        cmdline[0] = '\0';
    cmdline[ARMCHECK_CMDLINE - 1] = '\0';

    p = cmdline;
    while (*p != '\0' && argc < ARMCHECK_MAX_ARGS) {
        while (*p == ' ')
            *p++ = '\0';
        if (*p == '\0')
            break;
        argv[argc++] = p;
        while (*p != '\0' && *p != ' ')
            p++;
    }
    argv[argc] = 0;

    rc = main(argc, argv);
    semihost_exit(rc == 0);
    for (;;) {
    }
}

/* Cortex-M vector table: initial stack pointer, then the handlers. Only the
 * 16 system entries: armcheck enables no interrupts. */
__attribute__((section(".vectors"), used)) void (*const armcheck_vectors[16])(void) = {
    (void (*)(void))(uintptr_t)__stack_top, /* 0: initial SP */
    Reset_Handler,                          /* 1: reset */
    armcheck_fault,                         /* 2: NMI */
    armcheck_fault,                         /* 3: HardFault */
    armcheck_fault,                         /* 4: MemManage */
    armcheck_fault,                         /* 5: BusFault */
    armcheck_fault,                         /* 6: UsageFault */
    0, 0, 0, 0,                             /* 7-10: reserved */
    armcheck_fault,                         /* 11: SVCall */
    armcheck_fault,                         /* 12: DebugMon */
    0,                                      /* 13: reserved */
    armcheck_fault,                         /* 14: PendSV */
    armcheck_fault,                         /* 15: SysTick */
};
