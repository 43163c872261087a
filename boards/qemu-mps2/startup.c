/*
 * startup.c -- vector table and reset code of the QEMU mps2 board support
 * (mps2-an386: Cortex-M4F, mps2-an500: Cortex-M7), used only by the tests
 * and examples built with cmake/toolchains/cortex-m4.cmake or cortex-m7.cmake
 * and by the armcheck firmware (tools/armcheck/build.sh, with its own
 * armcheck.ld: it needs __stack_top, __data_start/_end/_load and
 * __bss_start/_end from the linker script).
 *
 * Reset: grant the FPU (CPACR CP10/CP11 full access) before any
 * floating-point instruction can run, copy .data from its load address,
 * clear .bss, split the semihosting command line (QEMU:
 * -semihosting-config arg=...) into argv, call main() and end QEMU with
 * main's return value as its exit status, after flushing stdio if the
 * program uses it. A CPU fault prints the faulting PC and ends QEMU with
 * status 99, so a crash never looks like a pass.
 *
 * Nothing here pulls newlib's stdio or its reentrancy data (impure_data)
 * into a program that does not use them: fflush is a weak reference, and
 * board_puts writes through semihosting directly.
 */
#include "board.h"
#include "semihost.h"

#include <stdint.h>
#include <stdio.h>

/* Linked only when the program uses stdio for something else. */
#pragma weak fflush

int main(int argc, char **argv);

extern uint32_t __stack_top[];
extern uint32_t __data_start[], __data_end[], __data_load[];
extern uint32_t __bss_start[], __bss_end[];

void Reset_Handler(void);
void board_start(void);
void board_fault(void);
void board_fault_report(const uint32_t *frame);
void _init(void);
void _fini(void);

/* newlib's __libc_init_array / __libc_fini_array call these (crti/crtn are
 * not linked: -nostartfiles); C needs no constructors. */
void _init(void) {}
void _fini(void) {}

#define BOARD_MAX_ARGS 128
#define BOARD_CMDLINE 4096

/* Must not touch the FPU before CPACR grants it. */
__attribute__((naked, noreturn)) void Reset_Handler(void)
{
    __asm__ volatile("ldr r0, =0xE000ED88\n\t" /* CPACR */
                     "ldr r1, [r0]\n\t"
                     "orr r1, r1, #(0xF << 20)\n\t"
                     "str r1, [r0]\n\t"
                     "dsb\n\t"
                     "isb\n\t"
                     "b board_start\n\t");
}

static void put_hex(char *out, uint32_t v)
{
    int i;
    for (i = 7; i >= 0; i--) {
        unsigned d = (unsigned)(v & 15u);
        out[i] = (char)(d < 10u ? '0' + d : 'a' + d - 10u);
        v >>= 4;
    }
}

/* frame: the exception stack frame (r0-r3, r12, lr, pc, xpsr). */
void board_fault_report(const uint32_t *frame)
{
    char msg[] = "board: CPU fault at pc 0x........ lr 0x........ cfsr 0x........\n";
    /* the digits go where the dots are: offsets 25, 39 and 55 (they were
     * written one byte late, over the spaces and the newline) */
    put_hex(msg + 25, frame[6]);
    put_hex(msg + 39, frame[5]);
    put_hex(msg + 55, *(volatile const uint32_t *)0xE000ED28u); /* CFSR */
    (void)semihost_call(SH_SYS_WRITE0, msg);
    semihost_exit(99);
}

__attribute__((naked)) void board_fault(void)
{
    __asm__ volatile("tst lr, #4\n\t"
                     "ite eq\n\t"
                     "mrseq r0, msp\n\t"
                     "mrsne r0, psp\n\t"
                     "b board_fault_report\n\t");
}

__attribute__((noreturn)) void board_start(void)
{
    static char cmdline[BOARD_CMDLINE]; /* in .bss: cleared below before use */
    static char *argv[BOARD_MAX_ARGS + 1];
    uint32_t *src = __data_load, *dst;
    uint32_t args[2];
    int argc = 0, rc;
    char *p;

    for (dst = __data_start; dst < __data_end; dst++)
        *dst = *src++;
    for (dst = __bss_start; dst < __bss_end; dst++)
        *dst = 0;

    args[0] = (uint32_t)(uintptr_t)cmdline;
    args[1] = BOARD_CMDLINE - 1;
    if (semihost_call(SH_SYS_GET_CMDLINE, args) != 0)
        cmdline[0] = '\0';
    cmdline[BOARD_CMDLINE - 1] = '\0';
    p = cmdline;
    while (*p != '\0' && argc < BOARD_MAX_ARGS) {
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
    if (&fflush != 0)
        (void)fflush(NULL); /* newlib: every open stream */
    semihost_exit(rc);
}

void board_puts(const char *s) { (void)semihost_call(SH_SYS_WRITE0, s); }

/* Cortex-M vector table: the initial stack pointer, then the 15 system
 * handlers. No interrupts are enabled. */
__attribute__((section(".vectors"), used)) void (*const board_vectors[16])(void) = {
    (void (*)(void))(uintptr_t)__stack_top, /* 0: initial SP */
    Reset_Handler,                          /* 1: reset */
    board_fault,                            /* 2: NMI */
    board_fault,                            /* 3: HardFault */
    board_fault,                            /* 4: MemManage */
    board_fault,                            /* 5: BusFault */
    board_fault,                            /* 6: UsageFault */
    0, 0, 0, 0,                             /* 7-10: reserved */
    board_fault,                            /* 11: SVCall */
    board_fault,                            /* 12: DebugMon */
    0,                                      /* 13: reserved */
    board_fault,                            /* 14: PendSV */
    board_fault,                            /* 15: SysTick */
};
