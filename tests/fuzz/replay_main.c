/* Replays fuzz inputs through a harness without libFuzzer: every file named
 * on the command line, or every file in a named folder (sorted by name), is
 * passed to LLVMFuzzerTestOneInput once. A harness check aborts (the test
 * fails); otherwise prints how many inputs ran. This is how the checked-in
 * regression inputs (tests/fuzz/corpus/NAME) and the generated seeds run in
 * every build, sanitized or not, with any C compiler. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int run_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    uint8_t *buf = NULL;
    size_t n = 0, cap = 0, got;
    if (!f) {
        fprintf(stderr, "replay: cannot open %s\n", path);
        return -1;
    }
    do {
        if (n + 65536 > cap) {
            uint8_t *nb = (uint8_t *)realloc(buf, cap = cap * 2 + 65536);
            if (!nb) {
                free(buf);
                fclose(f);
                return -1;
            }
            buf = nb;
        }
        got = fread(buf + n, 1, cap - n, f);
        n += got;
    } while (got > 0);
    fclose(f);
    {
        /* an exact-size copy, so that reading past the input is caught */
        uint8_t *exact = (uint8_t *)malloc(n ? n : 1);
        if (!exact) {
            free(buf);
            return -1;
        }
        if (n)
            memcpy(exact, buf, n);
        free(buf);
        LLVMFuzzerTestOneInput(exact, n);
        free(exact);
    }
    return 0;
}

static int cmp(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

int main(int argc, char **argv)
{
    int i, count = 0;
    for (i = 1; i < argc; i++) {
        struct stat sb;
        if (stat(argv[i], &sb) != 0) {
            fprintf(stderr, "replay: no such file or folder %s\n", argv[i]);
            return 1;
        }
        if (S_ISDIR(sb.st_mode)) {
            DIR *d = opendir(argv[i]);
            struct dirent *e;
            char **names = NULL;
            size_t nn = 0, cap = 0, k;
            if (!d)
                return 1;
            while ((e = readdir(d)) != NULL) {
                char path[4096];
                struct stat fs;
                if (e->d_name[0] == '.')
                    continue;
                snprintf(path, sizeof path, "%s/%s", argv[i], e->d_name);
                if (stat(path, &fs) != 0 || !S_ISREG(fs.st_mode))
                    continue;
                if (nn == cap) {
                    char **nb = (char **)realloc(names, (cap = cap * 2 + 64) * sizeof *names);
                    if (!nb)
                        return 1;
                    names = nb;
                }
                names[nn] = (char *)malloc(strlen(path) + 1);
                if (!names[nn])
                    return 1;
                strcpy(names[nn++], path);
            }
            closedir(d);
            if (nn)
                qsort(names, nn, sizeof *names, cmp);
            for (k = 0; k < nn; k++) {
                if (run_file(names[k]) != 0)
                    return 1;
                count++;
                free(names[k]);
            }
            free(names);
        } else {
            if (run_file(argv[i]) != 0)
                return 1;
            count++;
        }
    }
    printf("replay: %d inputs passed\n", count);
    return count > 0 ? 0 : 1;
}
