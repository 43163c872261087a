/*
 * actag-familygen: generates AcTag families (SPEC section 3).
 *
 *   actag-familygen --bits N --hamming H [--format txt|c|apriltag]
 *                   [--name NAME] [--out FILE]
 *
 * Greedy lexicode search identical to the modified AprilTag 3 generator used
 * for the published families: candidates v = 0x445965 + i * 982451653 (mod
 * 2^N) in that order; a candidate is accepted when its layout is complex
 * enough, its 8 orientations (4 rotations, each optionally reversed) differ
 * pairwise in >= H bits, and each differs in >= H bits from every
 * orientation of every accepted code. The last test is one bitmap look-up:
 * accepting a code marks the Hamming ball of radius H-1 around each of its
 * orientations as forbidden. (The orientation set is closed under the
 * dihedral group, so testing v alone against the marked balls is the same as
 * testing all 8 of its orientations.)
 *
 * Exit status: 0 success; 2 bad arguments or unwritable output; 1 when the
 * family would be empty or memory runs out.
 *
 * Host-only tool: uses the standard library freely.
 */
#include <ctype.h>
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define PROG "actag-familygen"
#define PRIME 982451653ull
#define SEED 0x445965ull

static void die(int status, const char *fmt, const char *arg)
{
    fprintf(stderr, PROG ": ");
    fprintf(stderr, fmt, arg);
    fputc('\n', stderr);
    exit(status);
}

static void usage_error(const char *fmt, const char *arg)
{
    fprintf(stderr, PROG ": ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, " (usage: " PROG " --bits N --hamming H [--format txt|c|apriltag] "
                    "[--name NAME] [--out FILE])\n");
    exit(2);
}

typedef struct {
    int bits, k;
    uint64_t mask;
} layout;

static uint64_t rot90(const layout *L, uint64_t w)
{
    return ((w << L->k) | (w >> (L->bits - L->k))) & L->mask;
}

static uint64_t reverse_bits(const layout *L, uint64_t w)
{
    uint64_t r = 0;
    int i;
    for (i = 0; i < L->bits; i++) {
        r = (r << 1) | (w & 1u);
        w >>= 1;
    }
    return r;
}

static int popcount64(uint64_t v)
{
    v = v - ((v >> 1) & 0x5555555555555555ull);
    v = (v & 0x3333333333333333ull) + ((v >> 2) & 0x3333333333333333ull);
    v = (v + (v >> 4)) & 0x0f0f0f0f0f0f0f0full;
    return (int)((v * 0x0101010101010101ull) >> 56);
}

/* Grid cell (x, y) in 0..k of data bit i (i = 0 is the MSB), SPEC section 2. */
static void bit_cell(const layout *L, int i, int *x, int *y)
{
    int k = L->k, side = i / k, t = i % k;
    switch (side) {
    case 0: *x = t; *y = 0; break;         /* top row, left to right */
    case 1: *x = k; *y = t; break;         /* right column, downwards */
    case 2: *x = k - t; *y = k; break;     /* bottom row, right to left */
    default: *x = 0; *y = k - t; break;    /* left column, upwards */
    }
}

/* Energy of the full (k+1)^2 layout: adjacent cell pairs that differ. */
static int layout_energy(const layout *L, uint64_t code)
{
    int n = L->k + 1, x, y, i, e = 0;
    unsigned char grid[16][16];
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            int d = x < y ? x : y;
            if (n - 1 - x < d) d = n - 1 - x;
            if (n - 1 - y < d) d = n - 1 - y;
            grid[y][x] = (unsigned char)(d == 1 ? 0 : 1);
        }
    for (i = 0; i < L->bits; i++) {
        bit_cell(L, i, &x, &y);
        grid[y][x] = (unsigned char)((code >> (L->bits - 1 - i)) & 1u);
    }
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            if (x + 1 < n && grid[y][x] != grid[y][x + 1]) e++;
            if (y + 1 < n && grid[y][x] != grid[y + 1][x]) e++;
        }
    return e;
}

/* The same energy in closed form: the data ring is a cycle of 4k cells, each
 * 4-adjacent only to its ring neighbours and (except the 4 corners) to one
 * black-ring cell; everything else is the same for every code. So
 * energy(code) = energy(0) + transitions around the ring + white non-corner
 * bits. Checked against layout_energy() at start-up. */
typedef struct {
    int base;
    uint64_t noncorner;
} energy_model;

static void energy_init(const layout *L, energy_model *m)
{
    int i;
    m->base = layout_energy(L, 0);
    m->noncorner = 0;
    for (i = 0; i < L->bits; i++)
        if (i % L->k != 0)
            m->noncorner |= 1ull << (L->bits - 1 - i);
}

static int fast_energy(const layout *L, const energy_model *m, uint64_t code)
{
    uint64_t rotl1 = ((code << 1) | (code >> (L->bits - 1))) & L->mask;
    return m->base + popcount64(code ^ rotl1) + popcount64(code & m->noncorner);
}

typedef struct {
    uint64_t *bitmap;
    const layout *L;
} forbid_map;

static void mark_ball(forbid_map *F, uint64_t v, int start, int radius)
{
    int i;
    F->bitmap[v >> 6] |= 1ull << (v & 63);
    if (radius == 0)
        return;
    for (i = start; i < F->L->bits; i++)
        mark_ball(F, v ^ (1ull << i), i + 1, radius - 1);
}

static int parse_int(const char *opt, const char *s)
{
    char *end;
    long v;
    errno = 0;
    v = strtol(s, &end, 10);
    if (errno || *s == '\0' || *end != '\0' || v < -1000000 || v > 1000000)
        usage_error("%s needs an integer", opt);
    return (int)v;
}

static void write_txt(FILE *f, const layout *L, const uint64_t *codes, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        fprintf(f, "0x%0*llx\n", L->bits / 4, (unsigned long long)codes[i]);
}

static void write_c(FILE *f, const layout *L, int h, const char *name, const uint64_t *codes,
                    size_t n)
{
    size_t i;
    fprintf(f, "/* Generated by " PROG " --bits %d --hamming %d --name %s: do not edit.\n"
               " * %lu codes in ID order, MSB = bit 0 = top-left cell as printed. */\n",
            L->bits, h, name, (unsigned long)n);
    fprintf(f, "#include \"actag/family.h\"\n\n");
    fprintf(f, "static const uint32_t actag_codes_%s[%lu] = {\n", name, (unsigned long)n);
    for (i = 0; i < n; i++)
        fprintf(f, "%s0x%0*llxu,%s", (i % 8 == 0) ? "    " : " ", L->bits / 4,
                (unsigned long long)codes[i], (i % 8 == 7 || i + 1 == n) ? "\n" : "");
    fprintf(f, "};\n\n");
    fprintf(f, "void actag_family_fill_%s(actag_family *out);\n", name);
    fprintf(f, "void actag_family_fill_%s(actag_family *out)\n{\n", name);
    fprintf(f, "    out->name = \"%s\";\n    out->bits = %d;\n    out->hamming = %d;\n", name,
            L->bits, h);
    fprintf(f, "    out->ncodes = %lu;\n    out->codes = actag_codes_%s;\n}\n", (unsigned long)n,
            name);
}

static void write_apriltag(FILE *f, const layout *L, int h, const char *name,
                           const uint64_t *codes, size_t n)
{
    size_t i;
    int b, x, y;
    fprintf(f, "/* Generated by " PROG " --bits %d --hamming %d --name %s --format apriltag:\n"
               " * do not edit. An AprilTag 3 family (apriltag_family_t) from static data;\n"
               " * %lu codes, the complete family. Images must be inverted (SPEC section 1). */\n",
            L->bits, h, name, (unsigned long)n);
    fprintf(f, "#include <stdbool.h>\n#include <stddef.h>\n#include <stdint.h>\n"
               "#include <apriltag/apriltag.h>\n\n");
    fprintf(f, "static uint64_t actag_at_codes_%s[%lu] = {\n", name, (unsigned long)n);
    for (i = 0; i < n; i++)
        fprintf(f, "%s0x%0*llxULL,%s", (i % 6 == 0) ? "    " : " ", L->bits / 4,
                (unsigned long long)codes[i], (i % 6 == 5 || i + 1 == n) ? "\n" : "");
    fprintf(f, "};\n\n");
    /* AprilTag bit coordinates are relative to the white square's top-left
     * cell; negative values are stored modulo 2^32 as AprilTag's own families do. */
    for (b = 0; b < 2; b++) {
        fprintf(f, "static uint32_t actag_at_bit%c_%s[%d] = {", b ? 'y' : 'x', name, L->bits);
        for (i = 0; i < (size_t)L->bits; i++) {
            int v;
            bit_cell(L, (int)i, &x, &y);
            v = (b ? y : x) - 2;
            fprintf(f, "%s(uint32_t)%d", i ? ", " : "", v);
        }
        fprintf(f, "};\n");
    }
    fprintf(f, "static char actag_at_name_%s[] = \"%s\";\n\n", name, name);
    fprintf(f, "static apriltag_family_t actag_at_family_%s = {\n", name);
    fprintf(f, "    .ncodes = %lu,\n    .codes = actag_at_codes_%s,\n", (unsigned long)n, name);
    fprintf(f, "    .width_at_border = %d,\n    .total_width = %d,\n    .reversed_border = true,\n",
            L->k - 3, L->k + 1);
    fprintf(f, "    .nbits = %d,\n    .bit_x = actag_at_bitx_%s,\n    .bit_y = actag_at_bity_%s,\n",
            L->bits, name, name);
    fprintf(f, "    .h = %d,\n    .name = actag_at_name_%s,\n    .impl = NULL,\n};\n\n", h, name);
    fprintf(f, "apriltag_family_t *actag_apriltag_family_%s(void);\n", name);
    fprintf(f, "apriltag_family_t *actag_apriltag_family_%s(void)\n{\n"
               "    return &actag_at_family_%s;\n}\n", name, name);
}

int main(int argc, char **argv)
{
    int bits = -1, h = -1, i, ncand_bits;
    const char *format = "txt", *name = NULL, *outpath = NULL;
    char default_name[64];
    layout L;
    FILE *out = stdout;
    uint64_t *codes = NULL, v, iter, total;
    size_t ncodes = 0, capcodes = 0;
    forbid_map F;
    energy_model em;
    double min_energy;
    clock_t t0 = clock(), last_report;
    int reported = 0;
    size_t codes_at_report = 0; /* codes at the last progress check */

    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            printf("usage: " PROG " --bits N --hamming H [--format txt|c|apriltag] [--name NAME] "
                   "[--out FILE]\n"
                   "  N: data bits, a multiple of 4 from 16 to 32; H: minimum Hamming distance >= 1\n"
                   "  txt: one 0x code per line in ID order; c: libactag table; apriltag: an\n"
                   "  AprilTag 3 apriltag_family_t from static data.\n");
            return 0;
        }
        if (strcmp(a, "--bits") && strcmp(a, "--hamming") && strcmp(a, "--format") &&
            strcmp(a, "--name") && strcmp(a, "--out"))
            usage_error("unknown option '%s'", a);
        if (i + 1 >= argc)
            usage_error("%s needs a value", a);
        if (strcmp(a, "--bits") == 0)
            bits = parse_int(a, argv[++i]);
        else if (strcmp(a, "--hamming") == 0)
            h = parse_int(a, argv[++i]);
        else if (strcmp(a, "--format") == 0)
            format = argv[++i];
        else if (strcmp(a, "--name") == 0)
            name = argv[++i];
        else
            outpath = argv[++i];
    }
    if (bits == -1)
        usage_error("%s", "--bits is required");
    if (h == -1)
        usage_error("%s", "--hamming is required");
    if (bits % 4 != 0 || bits < 16 || bits > 32) {
        snprintf(default_name, sizeof default_name, "%d", bits);
        usage_error("--bits %s: must be a multiple of 4 from 16 to 32", default_name);
    }
    if (h < 1)
        usage_error("%s", "--hamming must be at least 1");
    if (strcmp(format, "txt") && strcmp(format, "c") && strcmp(format, "apriltag"))
        usage_error("unknown --format '%s' (txt, c or apriltag)", format);
    if (name == NULL) {
        snprintf(default_name, sizeof default_name, "AcTag%dh%d", bits, h);
        name = default_name;
    }
    if (!(isalpha((unsigned char)name[0]) || name[0] == '_') || strlen(name) > 48)
        usage_error("--name '%s' must be a C identifier of at most 48 characters", name);
    for (i = 0; name[i]; i++)
        if (!(isalnum((unsigned char)name[i]) || name[i] == '_'))
            usage_error("--name '%s' must be a C identifier", name);
    if (outpath) {
        out = fopen(outpath, "w");
        if (!out)
            usage_error("cannot write '%s'", outpath);
    }

    L.bits = bits;
    L.k = bits / 4;
    L.mask = (bits == 64) ? ~0ull : ((1ull << bits) - 1);
    ncand_bits = bits;
    total = 1ull << ncand_bits;
    F.L = &L;
    F.bitmap = calloc((size_t)(total / 64), sizeof(uint64_t));
    if (!F.bitmap)
        die(1, "out of memory for the %s bitmap", bits >= 32 ? "512 MiB" : "forbidden-word");
    min_energy = 0.3333 * 2.0 * (L.k + 1) * (L.k + 1);
    energy_init(&L, &em);
    {
        /* the closed form must agree with the rendered layout */
        uint64_t t = 0x9e3779b97f4a7c15ull;
        for (i = 0; i < 4096; i++) {
            t = t * 6364136223846793005ull + 1442695040888963407ull;
            if (fast_energy(&L, &em, (t >> 17) & L.mask) != layout_energy(&L, (t >> 17) & L.mask))
                die(1, "%s", "internal error: energy model mismatch");
        }
    }

    v = SEED & L.mask;
    last_report = t0;
    for (iter = 0; iter < total; iter++) {
        uint64_t o[8];
        int a, b, ok = 1;
        v = (v + PRIME) & L.mask;
        if ((iter & 0xffff) == 0 || ncodes != codes_at_report) {
            clock_t now = clock();
            codes_at_report = ncodes; /* next check: after 2^16 more or a new code */
            if ((double)(now - last_report) / CLOCKS_PER_SEC >= 2.0) {
                fprintf(stderr, "\r" PROG ": %s: %5.1f%% searched, %lu codes", name,
                        100.0 * (double)iter / (double)total, (unsigned long)ncodes);
                fflush(stderr);
                last_report = now;
                reported = 1;
            }
        }
        if (F.bitmap[v >> 6] & (1ull << (v & 63)))
            continue; /* too close to an accepted code */
        if (fast_energy(&L, &em, v) < min_energy)
            continue;
        o[0] = v;
        for (a = 1; a < 4; a++)
            o[a] = rot90(&L, o[a - 1]);
        for (a = 0; a < 4; a++)
            o[4 + a] = reverse_bits(&L, o[a]);
        for (a = 0; a < 8 && ok; a++)
            for (b = a + 1; b < 8; b++)
                if (popcount64(o[a] ^ o[b]) < h) {
                    ok = 0;
                    break;
                }
        if (!ok)
            continue;
        if (ncodes == capcodes) {
            uint64_t *nc;
            capcodes = capcodes ? capcodes * 2 : 1024;
            nc = realloc(codes, capcodes * sizeof *codes);
            if (!nc)
                die(1, "%s", "out of memory for the code list");
            codes = nc;
        }
        codes[ncodes++] = v;
        for (a = 0; a < 8; a++)
            mark_ball(&F, o[a], 0, h - 1);
    }
    if (reported)
        fprintf(stderr, "\r" PROG ": %s: 100.0%% searched, %lu codes\n", name,
                (unsigned long)ncodes);
    free(F.bitmap);
    if (ncodes == 0) {
        if (outpath) {
            fclose(out);
            remove(outpath);
        }
        die(1, "%s has no code at all: lower --hamming", name);
    }
    if (strcmp(format, "txt") == 0)
        write_txt(out, &L, codes, ncodes);
    else if (strcmp(format, "c") == 0)
        write_c(out, &L, h, name, codes, ncodes);
    else
        write_apriltag(out, &L, h, name, codes, ncodes);
    free(codes);
    if (fflush(out) != 0 || ferror(out) || (outpath && fclose(out) != 0))
        die(2, "error writing '%s'", outpath ? outpath : "standard output");
    return 0;
}
