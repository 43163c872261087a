/*
 * adversarial.h -- the adversarial frames of issue 10 (bounded time), shared
 * by bench/worst_bench.c and tests/test_limits.c: at the pool recording's
 * size and geometry (530 x 512, 0.1-1.5 m, 60 degrees) dense speckle,
 * checkerboards of cell sizes 1..64, thousands of small blobs, grids of
 * tag-sized squares (plain, and fake tags: a random data ring, a black ring
 * and a white middle), uniform noise, stripes, all white and all black.
 * adv_specs() lists them; adv_generate() draws one (deterministic).
 */
#ifndef ACTAG_ADVERSARIAL_H
#define ACTAG_ADVERSARIAL_H

#include <stdint.h>
#include <stdio.h>
#include <string.h>

#define ADV_ROWS 530
#define ADV_COLS 512

static inline uint32_t adv_xs(uint32_t *s)
{
    uint32_t x = *s;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    return *s = x;
}

typedef struct adv_spec {
    char name[64];
    int kind; /* 0 pool file, else the generator */
    int a, b;
    char path[512];
} adv_spec;

enum { K_POOL, K_SPECKLE, K_CHECKER, K_BLOBS, K_SQUARES, K_FAKETAGS, K_NOISE, K_CONST, K_STRIPES };

/* A pool file's spec (its name "pool BASENAME", a label, may be cut).
 * Returns 0, or -1 when the path does not fit in path[] (511 characters):
 * it was cut short silently, naming another file or none. */
static inline int adv_pool_spec(adv_spec *f, const char *path)
{
    const char *base = strrchr(path, '/');
    size_t n = strlen(path);
    if (n >= sizeof f->path)
        return -1;
    memset(f, 0, sizeof *f);
    f->kind = K_POOL;
    memcpy(f->path, path, n + 1);
    snprintf(f->name, sizeof f->name, "pool %s", base ? base + 1 : path);
    return 0;
}

/* Adversarial frame of kind k into img (ADV_ROWS x ADV_COLS). */
static inline void adv_generate(const adv_spec *f, uint8_t *img)
{
    uint32_t s = 0x1234567u + (uint32_t)f->a * 7919u + (uint32_t)f->b;
    int r, c;
    for (r = 0; r < ADV_ROWS; r++)
        for (c = 0; c < ADV_COLS; c++) {
            uint8_t v = 0;
            switch (f->kind) {
            case K_SPECKLE: v = (adv_xs(&s) % 100u) < (uint32_t)f->a ? 230 : (uint8_t)(adv_xs(&s) & 31u); break;
            case K_CHECKER: v = ((r / f->a + c / f->a) & 1) ? 255 : 0; break;
            case K_BLOBS: v = (r % f->b < f->a && c % f->b < f->a) ? 240 : 15; break;
            case K_NOISE: v = (uint8_t)adv_xs(&s); break;
            case K_CONST: v = (uint8_t)f->a; break;
            case K_STRIPES: v = ((f->b ? c : r) / f->a) & 1 ? 220 : 20; break;
            default: break;
            }
            img[(size_t)r * ADV_COLS + (size_t)c] = v;
        }
    if (f->kind == K_SQUARES || f->kind == K_FAKETAGS) {
        /* squares of the tag's size at their range: 0.13 m is ~49 rows and
         * 0.13 / (2.05e-3 rad * range) columns; a grid over the whole frame */
        int step_r = f->a, step_c = f->b;
        memset(img, 10, (size_t)ADV_ROWS * ADV_COLS);
        for (r = 4; r + step_r < ADV_ROWS; r += step_r + step_r / 3) {
            float range = 1.5f - (float)(r + step_r / 2) * (1.4f / 529.0f);
            int w = (int)(0.13f / (1.0471976f / 511.0f * range) * 0.75f);
            int c0, y, x;
            if (w > ADV_COLS / 2)
                w = ADV_COLS / 2;
            if (w < 6)
                w = 6;
            (void)step_c;
            for (c0 = 4; c0 + w < ADV_COLS; c0 += w + w / 3) {
                for (y = 0; y < step_r; y++)
                    for (x = 0; x < w; x++) {
                        uint8_t v = 235;
                        if (f->kind == K_FAKETAGS) {
                            /* 7 x 7 cells: data ring random, black ring, white middle */
                            int cy = y * 7 / step_r, cx = x * 7 / w;
                            if (cy == 0 || cx == 0 || cy == 6 || cx == 6)
                                v = (adv_xs(&s) & 1u) ? 235 : 10;
                            else if (cy == 1 || cx == 1 || cy == 5 || cx == 5)
                                v = 10;
                        }
                        img[(size_t)(r + y) * ADV_COLS + (size_t)(c0 + x)] = v;
                    }
            }
        }
    }
}

static inline int adv_add(adv_spec *v, int n, int kind, int a, int b, const char *name)
{
    memset(&v[n], 0, sizeof v[n]);
    v[n].kind = kind;
    v[n].a = a;
    v[n].b = b;
    snprintf(v[n].name, sizeof v[n].name, "%s", name);
    return n + 1;
}

/* Appends the adversarial set to v (room for 40); returns the new count.
 * Blob counts are the contours left after the default median filter. */
static inline int adv_specs(adv_spec *v, int n)
{
    static const int pct[] = {10, 30, 50};
    static const int cells[] = {1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64};
    char name[64];
    int i;
    for (i = 0; i < 3; i++) {
        snprintf(name, sizeof name, "speckle %d%%", pct[i]);
        n = adv_add(v, n, K_SPECKLE, pct[i], 0, name);
    }
    for (i = 0; i < (int)(sizeof cells / sizeof cells[0]); i++) {
        snprintf(name, sizeof name, "checkerboard %d", cells[i]);
        n = adv_add(v, n, K_CHECKER, cells[i], 0, name);
    }
    n = adv_add(v, n, K_BLOBS, 1, 3, "blobs 1px (29k drawn)");
    n = adv_add(v, n, K_BLOBS, 2, 5, "blobs 2px (10k drawn)");
    n = adv_add(v, n, K_BLOBS, 4, 8, "blobs 4px (4k drawn)");
    n = adv_add(v, n, K_BLOBS, 4, 6, "blobs 4px gap 2 (7.5k)");
    n = adv_add(v, n, K_BLOBS, 5, 7, "blobs 5px gap 2 (5.3k)");
    n = adv_add(v, n, K_BLOBS, 8, 12, "blobs 8px gap 4 (1.8k)");
    n = adv_add(v, n, K_BLOBS, 12, 18, "blobs 12px (870)");
    n = adv_add(v, n, K_SQUARES, 37, 0, "tag-sized squares");
    n = adv_add(v, n, K_SQUARES, 25, 0, "small tag-sized squares");
    n = adv_add(v, n, K_FAKETAGS, 37, 0, "fake tags (random cells)");
    n = adv_add(v, n, K_FAKETAGS, 49, 0, "large fake tags");
    n = adv_add(v, n, K_NOISE, 0, 0, "uniform noise");
    n = adv_add(v, n, K_STRIPES, 2, 0, "range stripes 2");
    n = adv_add(v, n, K_STRIPES, 2, 1, "beam stripes 2");
    n = adv_add(v, n, K_CONST, 255, 0, "all white");
    n = adv_add(v, n, K_CONST, 0, 0, "all black");
    return n;
}

#endif /* ACTAG_ADVERSARIAL_H */
