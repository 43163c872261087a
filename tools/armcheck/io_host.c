/* armcheck I/O for the host build: plain stdio. */
#include "armcheck_io.h"

#include <stdio.h>

static FILE *out_file;

int ac_out_open(const char *path)
{
    out_file = fopen(path, "wb");
    return out_file != NULL ? 0 : -1;
}

int ac_out_write(const char *buf, size_t n)
{
    if (out_file == NULL)
        return -1;
    return fwrite(buf, 1, n, out_file) == n ? 0 : -1;
}

int ac_out_close(void)
{
    int rc;
    if (out_file == NULL)
        return -1;
    rc = fclose(out_file);
    out_file = NULL;
    return rc == 0 ? 0 : -1;
}

long ac_read_file(const char *path, unsigned char *buf, size_t cap)
{
    FILE *f = fopen(path, "rb");
    size_t n;
    if (f == NULL)
        return -1;
    n = fread(buf, 1, cap, f);
    /* longer than cap: one more byte is still there */
    if (n == cap && fgetc(f) != EOF) {
        fclose(f);
        return -1;
    }
    if (ferror(f)) {
        fclose(f);
        return -1;
    }
    fclose(f);
    return (long)n;
}

void ac_log(const char *msg)
{
    fputs(msg, stderr);
}
