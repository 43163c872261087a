/*
 * board.h -- what the QEMU mps2 board support offers a program besides
 * newlib (stdio, malloc, files and exit through semihosting, syscalls.c).
 */
#ifndef ACTAG_BOARD_H
#define ACTAG_BOARD_H

/* Writes the NUL-terminated text to the host's stdout (semihosting
 * SYS_WRITE0): no stdio, no heap, no newlib reentrancy data. */
void board_puts(const char *s);

#endif
