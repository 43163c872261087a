/*
 * syscalls.c -- newlib's system calls over ARM semihosting, for the tests
 * and examples run under qemu-system-arm (board support only: never linked
 * into libactag). stdio goes to QEMU's stdout/stderr (":tt"), fopen() opens
 * host files (QEMU -semihosting-config target=native), malloc() takes its
 * memory from the board's heap region (__heap_start .. __heap_end in the
 * linker script), exit(n) ends QEMU with status n, clock() reads the
 * semihosting clock. system(), mkdir() (semihosting has no directories)
 * and the process calls fail with ENOSYS.
 */
#include "semihost.h"

#include <errno.h>
#include <fcntl.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/times.h>
#include <time.h>
#include <unistd.h>

#undef errno
extern int errno;

int _open(const char *path, int flags, int mode);
int _close(int fd);
int _read(int fd, char *buf, int len);
int _write(int fd, const char *buf, int len);
int _lseek(int fd, int off, int whence);
int _fstat(int fd, struct stat *st);
int _stat(const char *path, struct stat *st);
int _isatty(int fd);
void *_sbrk(ptrdiff_t incr);
void _exit(int status);
int _kill(int pid, int sig);
int _getpid(void);
clock_t _times(struct tms *t);
int _gettimeofday(struct timeval *tv, void *tz);
int _unlink(const char *path);
int _link(const char *old, const char *new_path);
int _system(const char *cmd);
int mkdir(const char *path, mode_t mode);

#define BOARD_MAX_FILES 16

/* fd -> semihosting handle (0 = closed) and the file position. */
static struct {
    int32_t handle;
    int32_t pos;
} files[BOARD_MAX_FILES];

static int32_t tt_handle(int fd)
{
    /* ":tt" with mode 0 ("r") is stdin, 4 ("w") stdout, 8 ("a") stderr */
    if (files[fd].handle == 0) {
        uint32_t args[3];
        args[0] = (uint32_t)(uintptr_t)":tt";
        args[1] = (uint32_t)(fd * 4);
        args[2] = 3u;
        files[fd].handle = semihost_call(SH_SYS_OPEN, args);
    }
    return files[fd].handle;
}

static int32_t handle_of(int fd)
{
    if (fd < 0 || fd >= BOARD_MAX_FILES)
        return -1;
    if (fd <= 2)
        return tt_handle(fd);
    return files[fd].handle > 0 ? files[fd].handle : -1;
}

int _open(const char *path, int flags, int mode)
{
    uint32_t args[3];
    int fd, acc = flags & O_ACCMODE;
    int32_t sm, h;
    (void)mode;
    if (flags & O_APPEND)
        sm = acc == O_RDWR ? 11 : 9;
    else if (flags & (O_CREAT | O_TRUNC))
        sm = acc == O_RDWR ? 7 : 5;
    else
        sm = acc == O_RDWR ? 3 : acc == O_WRONLY ? 5 : 1;
    for (fd = 3; fd < BOARD_MAX_FILES && files[fd].handle != 0; fd++) {
    }
    if (fd == BOARD_MAX_FILES) {
        errno = EMFILE;
        return -1;
    }
    args[0] = (uint32_t)(uintptr_t)path;
    args[1] = (uint32_t)sm;
    args[2] = (uint32_t)strlen(path);
    h = semihost_call(SH_SYS_OPEN, args);
    if (h <= 0) {
        errno = ENOENT;
        return -1;
    }
    files[fd].handle = h;
    files[fd].pos = 0;
    return fd;
}

int _close(int fd)
{
    uint32_t args[1];
    if (fd <= 2)
        return 0;
    if (handle_of(fd) < 0) {
        errno = EBADF;
        return -1;
    }
    args[0] = (uint32_t)files[fd].handle;
    files[fd].handle = 0;
    return semihost_call(SH_SYS_CLOSE, args) == 0 ? 0 : -1;
}

/* SYS_READ or SYS_WRITE (op) of len bytes at buf on fd: the number of bytes
 * moved (the file position advances by as many), or -1. */
static int transfer(int fd, int32_t op, const void *buf, int len)
{
    uint32_t args[3];
    int32_t h = handle_of(fd), left;
    if (h < 0) {
        errno = EBADF;
        return -1;
    }
    args[0] = (uint32_t)h;
    args[1] = (uint32_t)(uintptr_t)buf;
    args[2] = (uint32_t)len;
    left = semihost_call(op, args); /* bytes NOT read / written */
    if (left < 0 || left > len) {
        errno = EIO;
        return -1;
    }
    files[fd].pos += len - left;
    return len - left;
}

int _read(int fd, char *buf, int len) { return transfer(fd, SH_SYS_READ, buf, len); }

int _write(int fd, const char *buf, int len) { return transfer(fd, SH_SYS_WRITE, buf, len); }

int _lseek(int fd, int off, int whence)
{
    uint32_t args[2];
    int32_t h = handle_of(fd), target;
    if (h < 0 || fd <= 2) {
        errno = fd <= 2 ? ESPIPE : EBADF;
        return -1;
    }
    if (whence == SEEK_SET)
        target = off;
    else if (whence == SEEK_CUR)
        target = files[fd].pos + off;
    else {
        int32_t len;
        args[0] = (uint32_t)h;
        len = semihost_call(SH_SYS_FLEN, args);
        if (len < 0) {
            errno = EIO;
            return -1;
        }
        target = len + off;
    }
    if (target < 0) {
        errno = EINVAL;
        return -1;
    }
    args[0] = (uint32_t)h;
    args[1] = (uint32_t)target;
    if (semihost_call(SH_SYS_SEEK, args) != 0) {
        errno = EIO;
        return -1;
    }
    files[fd].pos = target;
    return target;
}

int _fstat(int fd, struct stat *st)
{
    memset(st, 0, sizeof *st);
    if (handle_of(fd) < 0) {
        errno = EBADF;
        return -1;
    }
    st->st_mode = fd <= 2 ? S_IFCHR : S_IFREG;
    st->st_blksize = 1024;
    return 0;
}

int _stat(const char *path, struct stat *st)
{
    int fd = _open(path, O_RDONLY, 0);
    if (fd < 0)
        return -1;
    _fstat(fd, st);
    _close(fd);
    return 0;
}

int _isatty(int fd) { return fd >= 0 && fd <= 2; }

void *_sbrk(ptrdiff_t incr)
{
    extern char __heap_start[], __heap_end[];
    static char *brk;
    char *prev;
    if (brk == NULL)
        brk = __heap_start;
    if (incr > __heap_end - brk || incr < __heap_start - brk) {
        errno = ENOMEM;
        return (void *)-1;
    }
    prev = brk;
    brk += incr;
    return prev;
}

void _exit(int status) { semihost_exit(status & 0xff); }

int _kill(int pid, int sig)
{
    (void)pid;
    semihost_exit(128 + (sig & 0x7f)); /* abort(): raise(SIGABRT) ends here */
}

int _getpid(void) { return 1; }

clock_t _times(struct tms *t)
{
    /* SYS_CLOCK: centiseconds since the program started */
    clock_t c = (clock_t)semihost_call(SH_SYS_CLOCK, NULL) * (clock_t)(CLOCKS_PER_SEC / 100);
    if (t != NULL) {
        t->tms_utime = c;
        t->tms_stime = 0;
        t->tms_cutime = 0;
        t->tms_cstime = 0;
    }
    return c;
}

int _gettimeofday(struct timeval *tv, void *tz)
{
    (void)tz;
    if (tv != NULL) {
        tv->tv_sec = semihost_call(SH_SYS_TIME, NULL);
        tv->tv_usec = 0;
    }
    return 0;
}

int _unlink(const char *path)
{
    uint32_t args[2];
    args[0] = (uint32_t)(uintptr_t)path;
    args[1] = (uint32_t)strlen(path);
    return semihost_call(SH_SYS_REMOVE, args) == 0 ? 0 : -1;
}

int _link(const char *old, const char *new_path)
{
    (void)old;
    (void)new_path;
    errno = ENOSYS;
    return -1;
}

int _system(const char *cmd)
{
    (void)cmd;
    errno = ENOSYS;
    return -1;
}

/* newlib declares mkdir() but has no system call for it (tools/hostio's
 * hostio_mkdirs refers to it; the tests on the board never create folders). */
int mkdir(const char *path, mode_t mode)
{
    (void)path;
    (void)mode;
    errno = ENOSYS;
    return -1;
}
