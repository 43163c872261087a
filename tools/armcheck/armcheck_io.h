/*
 * armcheck_io.h -- the little I/O armcheck needs, implemented twice:
 * io_host.c (stdio, for the x86 build) and io_semihost.c (ARM semihosting
 * calls, for the Cortex-M firmware under QEMU). Everything else in
 * armcheck.c is shared, so both builds format their report with the same
 * code and the two reports can be compared byte for byte.
 */
#ifndef ARMCHECK_IO_H
#define ARMCHECK_IO_H

#include <stddef.h>

/* Opens the report file (truncating it). Returns 0 on success. */
int ac_out_open(const char *path);
/* Appends n bytes to the report. Returns 0 on success. */
int ac_out_write(const char *buf, size_t n);
/* Closes the report. Returns 0 on success. */
int ac_out_close(void);
/* Reads a whole file into buf (at most cap bytes). Returns its length, or
 * -1 when it cannot be opened/read or is longer than cap. */
long ac_read_file(const char *path, unsigned char *buf, size_t cap);
/* A diagnostic line for the console (not part of the compared report). */
void ac_log(const char *msg);

#endif
