/* Output files that a failed run must not leave half-written (see hostio.h:
 * hostio_out_open, hostio_out_close, hostio_out_abandon and
 * hostio_remove_partial). */
#define _POSIX_C_SOURCE 200809L /* fileno, lstat */
#include "hostio.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

/* lstat where there is one; bare-metal newlib (the emulated test builds)
 * has no symbolic links and no lstat. */
#if defined(__NEWLIB__) && !defined(__CYGWIN__)
#define HOSTIO_LSTAT stat
#else
#define HOSTIO_LSTAT lstat
#endif

/* Is path itself a regular file? lstat: a symbolic link such as /dev/stdout
 * is not (removing it would delete the link, not the output), nor is a
 * device such as /dev/full or a FIFO. */
static int is_regular(const char *path)
{
    struct stat st;
    return HOSTIO_LSTAT(path, &st) == 0 && S_ISREG(st.st_mode);
}

void hostio_remove_partial(const char *path)
{
    if (path && strcmp(path, "-") != 0 && is_regular(path))
        remove(path);
}

/* Does path itself name the regular file f writes? Checked when the file
 * is opened, so that only a file this run created or truncated is ever
 * removed (not what a link points to, not a device). */
static int names_stream(FILE *f, const char *path)
{
    struct stat fs, ls;
    return fstat(fileno(f), &fs) == 0 && HOSTIO_LSTAT(path, &ls) == 0 && S_ISREG(fs.st_mode) &&
           S_ISREG(ls.st_mode) && fs.st_dev == ls.st_dev && fs.st_ino == ls.st_ino;
}

int hostio_out_open(hostio_out *o, const char *path, const char *mode, char *err)
{
    o->path = path;
    o->why = 0;
    o->removable = 0;
    if (path == NULL) {
        o->f = stdout;
        return HOSTIO_OK;
    }
    o->f = fopen(path, mode);
    if (o->f == NULL) {
        o->why = errno;
        if (err)
            snprintf(err, HOSTIO_ERRLEN, "%s: cannot write: %s", path, strerror(o->why));
        return -1;
    }
    /* only a file this run truncated or created ("w"): appending to or
     * updating one keeps what was there before, which a failure must not
     * take with it */
    o->removable = mode != NULL && mode[0] == 'w' && names_stream(o->f, path);
    return HOSTIO_OK;
}

/* Removes the file if it is ours (checked again: a link or device put in
 * its place since is kept) and leaves the guard idle. */
static void discard(hostio_out *o)
{
    if (o->removable && is_regular(o->path))
        remove(o->path);
    o->removable = 0;
}

int hostio_out_close(hostio_out *o, char *err)
{
    FILE *f = o->f;
    int bad;
    if (f == NULL)
        return HOSTIO_OK; /* idle: never opened, closed or abandoned */
    o->f = NULL;
    /* a write error shows in fflush, the stream's error flag (an earlier
     * flush failed) or fclose; the first reason known is kept */
    errno = 0;
    bad = fflush(f) != 0;
    o->why = bad ? errno : 0;
    bad |= ferror(f) != 0;
    if (o->path != NULL) { /* standard output stays open */
        errno = 0;
        if (fclose(f) != 0) {
            bad = 1;
            if (o->why == 0)
                o->why = errno;
        }
    }
    if (!bad) {
        o->removable = 0;
        return HOSTIO_OK;
    }
    discard(o);
    if (err)
        snprintf(err, HOSTIO_ERRLEN, "%s: write error", o->path ? o->path : "standard output");
    return -1;
}

void hostio_out_abandon(hostio_out *o)
{
    if (o->f != NULL && o->path != NULL)
        fclose(o->f); /* its errors do not matter: the file goes */
    o->f = NULL;
    discard(o);
}
