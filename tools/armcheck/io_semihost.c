/* armcheck I/O for the Cortex-M firmware: host files through semihosting.
 * No newlib stdio, so no heap and no syscall stubs are needed. */
#include "armcheck_io.h"
#include "semihost.h"

#include <string.h>

static int32_t out_handle = -1;

static int32_t sh_open(const char *path, int32_t mode)
{
    uint32_t args[3];
    args[0] = (uint32_t)(uintptr_t)path;
    args[1] = (uint32_t)mode;
    args[2] = (uint32_t)strlen(path);
    return semihost_call(SH_SYS_OPEN, args);
}

static void sh_close(int32_t h)
{
    uint32_t args[1];
    args[0] = (uint32_t)h;
    (void)semihost_call(SH_SYS_CLOSE, args);
}

int ac_out_open(const char *path)
{
    out_handle = sh_open(path, SH_MODE_WB);
    return out_handle >= 0 ? 0 : -1;
}

int ac_out_write(const char *buf, size_t n)
{
    uint32_t args[3];
    if (out_handle < 0)
        return -1;
    args[0] = (uint32_t)out_handle;
    args[1] = (uint32_t)(uintptr_t)buf;
    args[2] = (uint32_t)n;
    /* SYS_WRITE returns the number of bytes NOT written */
    return semihost_call(SH_SYS_WRITE, args) == 0 ? 0 : -1;
}

int ac_out_close(void)
{
    if (out_handle < 0)
        return -1;
    sh_close(out_handle);
    out_handle = -1;
    return 0;
}

long ac_read_file(const char *path, unsigned char *buf, size_t cap)
{
    uint32_t args[3];
    int32_t h = sh_open(path, SH_MODE_RB), len, left;
    if (h < 0)
        return -1;
    args[0] = (uint32_t)h;
    len = semihost_call(SH_SYS_FLEN, args);
    if (len < 0 || (size_t)len > cap) {
        sh_close(h);
        return -1;
    }
    args[0] = (uint32_t)h;
    args[1] = (uint32_t)(uintptr_t)buf;
    args[2] = (uint32_t)len;
    left = semihost_call(SH_SYS_READ, args); /* bytes NOT read */
    sh_close(h);
    return left == 0 ? (long)len : -1;
}

void ac_log(const char *msg)
{
    (void)semihost_call(SH_SYS_WRITE0, msg);
}
