/* hostio_dir.c -- folder listings for the host tools (hostio.h): not built
 * for the emulated suites, whose C library has no <dirent.h>. */
#define _POSIX_C_SOURCE 200809L
/* 64-bit inode numbers and offsets on 32-bit hosts: without it, glibc's
 * readdir on armhf fails with EOVERFLOW on file systems with large inode
 * numbers (an overlay, qemu-user), which read as an empty folder */
#define _FILE_OFFSET_BITS 64
#include "hostio.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int cmp_path(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

void hostio_list_free(char **names, int n)
{
    int i;
    if (!names)
        return;
    for (i = 0; i < n; i++)
        free(names[i]);
    free(names);
}

char **hostio_list_dir(const char *dir, const char *prefix, const char *suffix, int *n,
                       char *err)
{
    DIR *dp = opendir(dir);
    struct dirent *de;
    char **names = NULL;
    int nn = 0, cap = 0;
    size_t lp = strlen(prefix), ls = strlen(suffix), ld = strlen(dir);
    *n = 0;
    if (!dp) {
        if (err)
            snprintf(err, HOSTIO_ERRLEN, "cannot open folder '%.150s': %s", dir, strerror(errno));
        return NULL;
    }
    for (;;) {
        size_t L;
        errno = 0;
        de = readdir(dp);
        if (de == NULL) {
            if (errno != 0) { /* an error, not the end of the folder */
                int e = errno;
                closedir(dp);
                hostio_list_free(names, nn);
                if (err)
                    snprintf(err, HOSTIO_ERRLEN, "cannot read folder '%.150s': %s", dir,
                             strerror(e));
                return NULL;
            }
            break;
        }
        L = strlen(de->d_name);
        if (L <= lp + ls || strncmp(de->d_name, prefix, lp) != 0 ||
            strcmp(de->d_name + L - ls, suffix) != 0)
            continue;
        if (nn == cap) {
            int ncap = cap ? 2 * cap : 64;
            char **more = (char **)realloc(names, (size_t)ncap * sizeof *names);
            if (!more)
                goto out_of_memory;
            names = more;
            cap = ncap;
        }
        names[nn] = (char *)malloc(ld + L + 2);
        if (!names[nn])
            goto out_of_memory;
        memcpy(names[nn], dir, ld);
        names[nn][ld] = '/';
        memcpy(names[nn] + ld + 1, de->d_name, L + 1);
        nn++;
    }
    closedir(dp);
    if (nn > 0)
        qsort(names, (size_t)nn, sizeof *names, cmp_path);
    else if (!names) /* an empty list is no error: a non-NULL array of 0 */
        names = (char **)malloc(sizeof *names);
    if (!names) {
        if (err)
            snprintf(err, HOSTIO_ERRLEN, "%.200s: out of memory", dir);
        return NULL;
    }
    *n = nn;
    return names;
out_of_memory:
    closedir(dp);
    hostio_list_free(names, nn);
    if (err)
        snprintf(err, HOSTIO_ERRLEN, "%.200s: out of memory", dir);
    return NULL;
}
