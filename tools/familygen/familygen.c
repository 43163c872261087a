/*
 * actag-familygen: generates AcTag families (SPEC section 3).
 *
 *   actag-familygen --bits N --hamming H [--mirror reverse|physical]
 *                   [--exclude none|corners|LIST] [--min-complexity F]
 *                   [--format txt|c|apriltag] [--name NAME] [--out FILE]
 *
 * Greedy lexicode search identical to the modified AprilTag 3 generator used
 * for the published families: candidates v = 0x445965 + i * 982451653 (mod
 * 2^N) in that order; a candidate is accepted when its layout is complex
 * enough, its 8 orientations differ pairwise in >= H bits, and each differs
 * in >= H bits from every orientation of every accepted code.
 *
 * The 8 orientations are the 4 rotations, each optionally mirrored:
 *   --mirror reverse   (default) the full bit reversal, sequence position
 *                      s -> 4k-1-s: the published rule (AcTag<N>h<H>).
 *   --mirror physical  the reflection P a sonar shows, s -> -s mod 4k (bit 0
 *                      stays, the rest is reversed; decode.h).
 * --exclude leaves cells out of every distance: "corners" = the 4 data-ring
 * corner cells (sequence positions 0, k, 2k, 3k), which the default sonar
 * decoder ignores, or a comma-separated list of sequence positions. The
 * excluded set must map onto itself under the 8 orientations.
 * --min-complexity F: layout energy >= F * 2 (k+1)^2 (default 0.3333, the
 * published rule; the energy always counts the whole layout).
 *
 * Family names (docs/families.md): AcTag<N>h<H> = reverse, all cells (the
 * published rule); AcTag<N>p<H> = physical, all cells; AcTag<N>m<H> =
 * physical, corners excluded (mirror-safe over the default decoder's
 * cells). A name of that form must match the options; other option sets
 * need a --name of another form for c and apriltag output.
 *
 * Speed. The last test is one bitmap look-up: accepting a code marks the
 * Hamming ball of radius H-1 around each of its orientations as forbidden
 * (the orientation set is a group and the counted cells are invariant under
 * it, so testing v alone is the same as testing all 8 of its orientations).
 * The bitmap is indexed by the counted bits only (excluded cells squeezed
 * out). A ball is marked one 64-bit word at a time: the low 6 index bits
 * address a bit within a word, so for every high part within distance d of
 * the centre's high part the word gets the precomputed 6-bit ball of radius
 * H-1-d around the centre's low part. The high parts are a table of all
 * error patterns of weight <= H-1, sorted by value (XOR with the centre
 * keeps neighbouring patterns in neighbouring memory). Candidate look-ups
 * are prefetched 32 candidates ahead; with a bitmap larger than the caches
 * (more than 24 counted bits) the complexity test comes first, and only
 * candidates that pass it touch the bitmap.
 *
 * Progress (stderr, every 2 s once a run takes longer than that): fraction
 * searched, codes so far, elapsed wall-clock time and an estimate of the
 * time left in two parts: the search at its current rate (over the last
 * report interval, ball marking excluded; the rate grows as the bitmap
 * fills), plus the marking time per code so far for every further code
 * (how many more there will be nobody knows in advance; they thin out as
 * the search goes on).
 *
 * Exit status: 0 success; 2 bad arguments (options no code can satisfy, so
 * that the family would be empty, included) or unwritable output; 1 when
 * memory runs out. The output file is opened (and an older one truncated)
 * only when the search is done, so that an interrupted or failed run
 * leaves the older file as it was; a write that fails removes the file
 * again (no empty or half-written family file is left behind).
 *
 * Host-only tool: uses the standard library freely.
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime for wall-clock progress */
#include <ctype.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "actag/version.h"
#include "hostio.h"

#define PROG "actag-familygen"
#define PRIME 982451653ull
#define SEED 0x445965ull
#define DEFAULT_COMPLEXITY 0.3333
#define PREFETCH_AHEAD 32 /* candidates; a power of 2 */

#if defined(__GNUC__) || defined(__clang__)
#define PREFETCH(p) __builtin_prefetch(p)
#else
#define PREFETCH(p) ((void)0)
#endif

#define USAGE                                                                                 \
    PROG " --bits N --hamming H [--mirror reverse|physical] [--exclude none|corners|LIST] "   \
         "[--min-complexity F] [--format txt|c|apriltag] [--name NAME] [--out FILE]"

/* The output (--out or standard output) while it is open: die() abandons
 * it, so that a failed run leaves no empty or truncated family file behind
 * (hostio_out: a device such as /dev/null or a link is never removed). */
static hostio_out g_out;

static void die(int status, const char *fmt, const char *arg)
{
    fprintf(stderr, PROG ": ");
    fprintf(stderr, fmt, arg);
    fputc('\n', stderr);
    hostio_out_abandon(&g_out);
    exit(status);
}

/* --out's errno when it cannot be written (0: it can), checked at start-up
 * without opening it: opening truncates, and the search may run for hours
 * or be interrupted. The path must be a writable file or a new name in a
 * writable folder. */
static int out_path_error(const char *path)
{
    struct stat st;
    const char *slash;
    char *dir;
    int why = 0;
    if (stat(path, &st) == 0) {
        if (S_ISDIR(st.st_mode))
            return EISDIR;
        return access(path, W_OK) == 0 ? 0 : errno;
    }
    if (errno != ENOENT)
        return errno;
    slash = strrchr(path, '/');
    if (!slash)
        return access(".", W_OK | X_OK) == 0 ? 0 : errno;
    dir = (char *)malloc((size_t)(slash - path) + 2);
    if (!dir)
        return ENOMEM;
    memcpy(dir, path, (size_t)(slash - path) + 1); /* "/x" keeps its "/" */
    dir[slash == path ? 1 : slash - path] = '\0';
    if (stat(dir, &st) != 0)
        why = errno;
    else if (!S_ISDIR(st.st_mode))
        why = ENOTDIR;
    else if (access(dir, W_OK | X_OK) != 0)
        why = errno;
    free(dir);
    return why;
}

static void usage_error(const char *fmt, const char *arg)
{
    fprintf(stderr, PROG ": ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, " (usage: " USAGE ")\n");
    exit(2);
}

typedef struct {
    int bits, k;
    uint64_t mask;
    int physical;   /* mirror rule: 0 = full reversal, 1 = reflection P */
    uint64_t keep;  /* code bits counted in distances */
    int nkeep;      /* number of counted bits = index bits of the bitmap */
    int nruns;      /* runs of counted bits, for squeezing out the others */
    int run_shift[32], run_out[32];
    uint64_t run_mask[32];
} layout;

/* SWAR: without -mpopcnt, GCC's __builtin_popcountll is a library call. */
static int popcount64(uint64_t v)
{
    v = v - ((v >> 1) & 0x5555555555555555ull);
    v = (v & 0x3333333333333333ull) + ((v >> 2) & 0x3333333333333333ull);
    v = (v + (v >> 4)) & 0x0f0f0f0f0f0f0f0full;
    return (int)((v * 0x0101010101010101ull) >> 56);
}

static uint64_t rot90(const layout *L, uint64_t w)
{
    return ((w << L->k) | (w >> (L->bits - L->k))) & L->mask;
}

/* Bit i <-> bit bits-1-i. */
static uint64_t reverse_bits(const layout *L, uint64_t w)
{
    w = ((w >> 1) & 0x5555555555555555ull) | ((w & 0x5555555555555555ull) << 1);
    w = ((w >> 2) & 0x3333333333333333ull) | ((w & 0x3333333333333333ull) << 2);
    w = ((w >> 4) & 0x0f0f0f0f0f0f0f0full) | ((w & 0x0f0f0f0f0f0f0f0full) << 4);
    w = ((w >> 8) & 0x00ff00ff00ff00ffull) | ((w & 0x00ff00ff00ff00ffull) << 8);
    w = ((w >> 16) & 0x0000ffff0000ffffull) | ((w & 0x0000ffff0000ffffull) << 16);
    w = (w >> 32) | (w << 32);
    return w >> (64 - L->bits);
}

/* The orientation's mirror: reverse (s -> -1-s) or P (s -> -s: keep the
 * MSB, which is sequence position 0, and reverse the other bits). */
static uint64_t mirror(const layout *L, uint64_t w)
{
    uint64_t r = reverse_bits(L, w);
    if (!L->physical)
        return r;
    return (w & (1ull << (L->bits - 1))) | (r >> 1);
}

/* Sequence position s under the generators of the orientation group. */
static int pos_rot(const layout *L, int s) { return (s + L->k) % L->bits; }
static int pos_mirror(const layout *L, int s)
{
    return L->physical ? (L->bits - s) % L->bits : L->bits - 1 - s;
}

/* Bitmap index of a code: its counted bits, squeezed together. */
static uint64_t squeeze(const layout *L, uint64_t v)
{
    uint64_t r = 0;
    int i;
    if (L->nruns == 1 && L->run_shift[0] == 0)
        return v & L->run_mask[0];
    for (i = 0; i < L->nruns; i++)
        r |= ((v >> L->run_shift[i]) & L->run_mask[i]) << L->run_out[i];
    return r;
}

static void layout_runs(layout *L)
{
    int b = 0, out = 0;
    L->nruns = 0;
    while (b < L->bits) {
        int len = 0;
        if (!((L->keep >> b) & 1u)) {
            b++;
            continue;
        }
        while (b + len < L->bits && ((L->keep >> (b + len)) & 1u))
            len++;
        L->run_shift[L->nruns] = b;
        L->run_out[L->nruns] = out;
        L->run_mask[L->nruns] = (len >= 64) ? ~0ull : ((1ull << len) - 1);
        L->nruns++;
        out += len;
        b += len;
    }
    L->nkeep = out;
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

/* Forbidden-word bitmap over the squeezed index and the ball tables. */
typedef struct {
    uint64_t *bitmap;
    int lowbits;     /* index bits within one word: min(6, nkeep) */
    int radius;      /* H-1, at most nkeep */
    uint32_t *pats;  /* high-part error patterns of weight <= radius, sorted;
                        weight in bits 27..31 */
    size_t npats;
} forbid_map;

#define PAT_WSHIFT 27
#define PAT_MASK ((1u << PAT_WSHIFT) - 1u)

/* All high-part patterns (nkeep - lowbits bits, at most 26) of weight
 * <= radius in increasing order. Returns 0 when memory runs out. */
static int make_patterns(forbid_map *F, int hibits)
{
    uint64_t count = 0, p, end = 1ull << hibits;
    size_t n = 0;
    /* count first: sum of binomials */
    {
        uint64_t c = 1;
        int j;
        for (j = 0; j <= F->radius && j <= hibits; j++) {
            count += c;
            c = c * (uint64_t)(hibits - j) / (uint64_t)(j + 1);
        }
    }
    F->pats = malloc((size_t)count * sizeof *F->pats);
    if (!F->pats)
        return 0;
    if (F->radius >= hibits) {
        for (p = 0; p < end; p++)
            F->pats[n++] = (uint32_t)p | ((uint32_t)popcount64(p) << PAT_WSHIFT);
    } else {
        /* Walk the values in order, skipping blocks that are already too
         * heavy: after a prefix of weight > radius, jump to the next prefix. */
        p = 0;
        while (p < end) {
            int w = popcount64(p);
            if (w <= F->radius) {
                F->pats[n++] = (uint32_t)p | ((uint32_t)w << PAT_WSHIFT);
                p++;
            } else {
                /* clear bits from the lowest set bit up until the weight fits,
                 * then carry: p = next value with a lighter prefix */
                uint64_t low = p & (~p + 1); /* lowest set bit */
                p += low;
            }
        }
    }
    F->npats = n;
    return n == count;
}

/* Marks every index within distance radius of index c. */
static void mark_ball(forbid_map *F, uint64_t c)
{
    uint64_t ch = c >> F->lowbits, row[33];
    unsigned cl = (unsigned)(c & ((1u << F->lowbits) - 1u));
    unsigned x, nlow = 1u << F->lowbits;
    size_t i;
    int d;
    for (d = 0; d <= F->radius; d++) {
        uint64_t m = 0;
        for (x = 0; x < nlow; x++)
            if (popcount64((uint64_t)(x ^ cl)) <= F->radius - d)
                m |= 1ull << x;
        row[d] = m;
    }
    for (i = 0; i < F->npats; i++) {
        uint32_t e = F->pats[i];
        F->bitmap[ch ^ (e & PAT_MASK)] |= row[e >> PAT_WSHIFT];
    }
}

static int parse_int(const char *opt, const char *s)
{
    char err[HOSTIO_ERRLEN];
    long v = 0;
    if (hostio_parse_long(opt, s, -1000000, 1000000, &v, err) != HOSTIO_OK)
        usage_error("%s", err);
    return (int)v;
}

/* --exclude value -> set of excluded sequence positions (bit s = position s). */
static uint64_t parse_exclude(const char *s, int bits)
{
    uint64_t set = 0;
    const char *p = s;
    if (strcmp(s, "none") == 0)
        return 0;
    if (strcmp(s, "corners") == 0) {
        int j;
        for (j = 0; j < 4; j++)
            set |= 1ull << (j * (bits / 4));
        return set;
    }
    for (;;) {
        char tok[16];
        size_t len = strcspn(p, ",");
        long v = 0;
        if (len >= sizeof tok || !isdigit((unsigned char)*p))
            usage_error("--exclude '%s': expected none, corners or a comma-separated list of "
                        "sequence positions 0..4k-1", s);
        memcpy(tok, p, len);
        tok[len] = '\0';
        if (hostio_parse_long("--exclude", tok, 0, bits - 1, &v, NULL) != HOSTIO_OK)
            usage_error("--exclude '%s': expected none, corners or a comma-separated list of "
                        "sequence positions 0..4k-1", s);
        set |= 1ull << v;
        if (p[len] == '\0')
            break;
        p += len + 1;
    }
    return set;
}

static void write_txt(FILE *f, const layout *L, const uint64_t *codes, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        fprintf(f, "0x%0*llx\n", L->bits / 4, (unsigned long long)codes[i]);
}

static void write_c(FILE *f, const layout *L, int h, const char *rule, const char *name,
                    const uint64_t *codes, size_t n)
{
    size_t i;
    fprintf(f, "/* Generated by " PROG " --bits %d --hamming %d%s --name %s: do not edit.\n"
               " * %lu codes in ID order, MSB = bit 0 = top-left cell as printed. */\n",
            L->bits, h, rule, name, (unsigned long)n);
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
    fprintf(f, "    out->ncodes = %lu;\n    out->codes = actag_codes_%s;\n", (unsigned long)n,
            name);
    /* The published rule leaves mirror and excluded at 0 (set by the
     * library before it calls this), so those tables stay as they were. */
    if (L->physical)
        fprintf(f, "    out->mirror = ACTAG_MIRROR_PHYSICAL;\n");
    if (L->keep != L->mask)
        fprintf(f, "    out->excluded = 0x%0*llxu;\n", L->bits / 4,
                (unsigned long long)(L->mask & ~L->keep));
    fprintf(f, "}\n");
}

static void write_apriltag(FILE *f, const layout *L, int h, const char *rule, const char *name,
                           const uint64_t *codes, size_t n)
{
    size_t i;
    int b, x, y;
    fprintf(f, "/* Generated by " PROG " --bits %d --hamming %d%s --name %s --format apriltag:\n"
               " * do not edit. An AprilTag 3 family (apriltag_family_t) from static data;\n"
               " * %lu codes, the complete family. Images must be inverted (SPEC section 1). */\n",
            L->bits, h, rule, name, (unsigned long)n);
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

/* The rule letter of the standard names: 'h' published (reverse, all
 * cells), 'p' physical mirror, all cells, 'm' physical mirror without the
 * 4 corner cells; 0 for any other rule. */
static char rule_letter(const layout *L, uint64_t excluded_pos, double complexity)
{
    uint64_t corners = 0;
    int j;
    for (j = 0; j < 4; j++)
        corners |= 1ull << (j * L->k);
    if (complexity != DEFAULT_COMPLEXITY)
        return 0;
    if (!L->physical)
        return excluded_pos == 0 ? 'h' : 0;
    if (excluded_pos == 0)
        return 'p';
    return excluded_pos == corners ? 'm' : 0;
}

/* Wall-clock seconds (what a progress estimate is about); CPU time where
 * the POSIX clock is missing. */
static double now_s(void)
{
#if defined(CLOCK_MONOTONIC)
    struct timespec ts;
    if (clock_gettime(CLOCK_MONOTONIC, &ts) == 0)
        return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
#endif
    return (double)clock() / CLOCKS_PER_SEC;
}

static void fmt_secs(char *buf, size_t n, double s)
{
    if (s < 120)
        snprintf(buf, n, "%.0f s", s);
    else if (s < 7200)
        snprintf(buf, n, "%.1f min", s / 60);
    else
        snprintf(buf, n, "%.1f h", s / 3600);
}

int main(int argc, char **argv)
{
    int bits = 0, h = 0, have_bits = 0, have_h = 0, i, physical = 0, emin, energy_first;
    const char *format = "txt", *name = NULL, *outpath = NULL, *exclude = "none";
    char default_name[64], rule[160], letter;
    layout L;
    FILE *out;
    uint64_t *codes = NULL, v, iter, total, excluded_pos, pf, ring[PREFETCH_AHEAD], sentinel;
    size_t ncodes = 0, capcodes = 0;
    forbid_map F;
    energy_model em;
    double min_energy, complexity = DEFAULT_COMPLEXITY;
    double t0 = now_s(), last_report, t_mark = 0.0; /* t_mark: time spent marking balls */
    double last_scan = 0.0;
    uint64_t last_iter = 0;
    int reported = 0;
    size_t codes_at_report = 0; /* codes at the last progress check */

    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--version") == 0) {
            printf("actag-familygen %s\n", ACTAG_VERSION_STRING);
            return 0;
        }
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            printf("usage: " USAGE "\n"
                   "  N: data bits, a multiple of 4 from 16 to 32; H: minimum Hamming distance,\n"
                   "    1 to the number of counted bits (N less the --exclude cells); options no\n"
                   "    code can meet (an empty family) are an error, exit status 2\n"
                   "  --mirror: the mirror image the distance must hold for: reverse (default,\n"
                   "    the published families: bit i <-> bit N-1-i) or physical (the reflection\n"
                   "    a sonar shows: sequence position s <-> -s mod N)\n"
                   "  --exclude: cells not counted in any distance: none (default), corners (the\n"
                   "    4 data-ring corners the default sonar decoder ignores) or a list of\n"
                   "    sequence positions (0 = top-left cell), e.g. 0,6,12,18; the set must map\n"
                   "    onto itself under the 8 orientations: corners needs --mirror physical\n"
                   "  --min-complexity F: layout energy >= F * 2(k+1)^2 (default 0.3333)\n"
                   "  --name NAME: the family's name in the output (default: from the rule, below)\n"
                   "  --out FILE: write there instead of standard output\n"
                   "  names: AcTag<N>h<H> reverse, all cells (published); AcTag<N>p<H> physical,\n"
                   "    all cells; AcTag<N>m<H> physical, corners excluded (mirror-safe)\n"
                   "  txt: one 0x code per line in ID order; c: libactag table; apriltag: an\n"
                   "  AprilTag 3 apriltag_family_t from static data.\n"
                   "  --help  --version\n");
            return 0;
        }
        if (strcmp(a, "--bits") && strcmp(a, "--hamming") && strcmp(a, "--format") &&
            strcmp(a, "--name") && strcmp(a, "--out") && strcmp(a, "--mirror") &&
            strcmp(a, "--exclude") && strcmp(a, "--min-complexity"))
            usage_error("unknown option '%s'", a);
        if (i + 1 >= argc)
            usage_error("%s needs a value", a);
        if (strcmp(a, "--bits") == 0) {
            bits = parse_int(a, argv[++i]);
            have_bits = 1;
        } else if (strcmp(a, "--hamming") == 0) {
            h = parse_int(a, argv[++i]);
            have_h = 1;
        } else if (strcmp(a, "--format") == 0)
            format = argv[++i];
        else if (strcmp(a, "--name") == 0)
            name = argv[++i];
        else if (strcmp(a, "--mirror") == 0) {
            const char *m = argv[++i];
            if (strcmp(m, "reverse") == 0)
                physical = 0;
            else if (strcmp(m, "physical") == 0)
                physical = 1;
            else
                usage_error("unknown --mirror '%s' (reverse or physical)", m);
        } else if (strcmp(a, "--exclude") == 0)
            exclude = argv[++i];
        else if (strcmp(a, "--min-complexity") == 0) {
            const char *s = argv[++i];
            if (hostio_parse_double(a, s, 0.0, 1.0, &complexity, NULL) != HOSTIO_OK)
                usage_error("--min-complexity '%s': expected a number from 0 to 1", s);
        } else
            outpath = argv[++i];
    }
    if (!have_bits)
        usage_error("%s", "--bits is required");
    if (!have_h)
        usage_error("%s", "--hamming is required");
    if (bits % 4 != 0 || bits < 16 || bits > 32) {
        snprintf(default_name, sizeof default_name, "%d", bits);
        usage_error("--bits %s: must be a multiple of 4 from 16 to 32", default_name);
    }
    if (h < 1) {
        snprintf(default_name, sizeof default_name, "%d", h);
        usage_error("--hamming %s: must be at least 1", default_name);
    }
    if (strcmp(format, "txt") && strcmp(format, "c") && strcmp(format, "apriltag"))
        usage_error("unknown --format '%s' (txt, c or apriltag)", format);

    L.bits = bits;
    L.k = bits / 4;
    L.mask = (1ull << bits) - 1;
    L.physical = physical;
    excluded_pos = parse_exclude(exclude, bits);
    /* the excluded cells must be closed under the orientation group */
    for (i = 0; i < bits; i++)
        if ((excluded_pos >> i) & 1u) {
            int r = pos_rot(&L, i), m = pos_mirror(&L, i);
            if (!((excluded_pos >> r) & 1u) || !((excluded_pos >> m) & 1u)) {
                fprintf(stderr,
                        PROG ": --exclude '%s': position %d is excluded but its %s, position "
                             "%d, is not (the excluded cells must map onto each other under "
                             "rotation and --mirror %s)\n",
                        exclude, i, ((excluded_pos >> r) & 1u) ? "mirror image" : "rotation",
                        ((excluded_pos >> r) & 1u) ? m : r, physical ? "physical" : "reverse");
                exit(2);
            }
        }
    L.keep = L.mask;
    for (i = 0; i < bits; i++)
        if ((excluded_pos >> i) & 1u)
            L.keep &= ~(1ull << (bits - 1 - i));
    if (L.keep == 0)
        usage_error("--exclude '%s' leaves no cell to count", exclude);
    layout_runs(&L);
    if (h > L.nkeep) {
        /* two orientations of a code differ in at most the counted bits */
        char msg[200];
        snprintf(msg, sizeof msg,
                 "--hamming %d: must be at most %d, the number of counted bits (--bits %d%s)",
                 h, L.nkeep, bits, excluded_pos ? " without the --exclude cells" : "");
        usage_error("%s", msg);
    }

    /* names and their rules */
    letter = rule_letter(&L, excluded_pos, complexity);
    rule[0] = '\0';
    if (physical)
        strcat(rule, " --mirror physical");
    if (excluded_pos)
        snprintf(rule + strlen(rule), sizeof rule - strlen(rule), " --exclude %s", exclude);
    if (complexity != DEFAULT_COMPLEXITY)
        snprintf(rule + strlen(rule), sizeof rule - strlen(rule), " --min-complexity %g",
                 complexity);
    if (name == NULL) {
        if (letter == 0 && strcmp(format, "txt") != 0)
            usage_error("%s", "these options have no standard family name: give --name "
                              "(not of the form AcTag<N>[hpm]<H>)");
        snprintf(default_name, sizeof default_name, "AcTag%d%c%d", bits, letter ? letter : 'x',
                 h);
        name = default_name;
    }
    if (!(isalpha((unsigned char)name[0]) || name[0] == '_') || strlen(name) > 48)
        usage_error("--name '%s' must be a C identifier of at most 48 characters", name);
    for (i = 0; name[i]; i++)
        if (!(isalnum((unsigned char)name[i]) || name[i] == '_'))
            usage_error("--name '%s' must be a C identifier", name);
    {
        /* a standard-looking name must carry its own rule */
        int nb, nh, used = 0;
        char c = 0;
        if (sscanf(name, "AcTag%d%c%d%n", &nb, &c, &nh, &used) == 3 && name[used] == '\0' &&
            (c == 'h' || c == 'p' || c == 'm') && (nb != bits || nh != h || c != letter)) {
            char want[32];
            if (letter)
                snprintf(want, sizeof want, "AcTag%d%c%d", bits, letter, h);
            else
                snprintf(want, sizeof want, "a name of another form");
            fprintf(stderr,
                    PROG ": --name '%s' is the standard name of a family with other options "
                         "(AcTag<N>h<H>: --mirror reverse, all cells; AcTag<N>p<H>: --mirror "
                         "physical, all cells; AcTag<N>m<H>: --mirror physical --exclude "
                         "corners; all with the default complexity); these options need %s\n",
                    name, want);
            exit(2);
        }
    }
    if (outpath) {
        int why = out_path_error(outpath);
        if (why != 0) {
            char msg[HOSTIO_ERRLEN + 64];
            snprintf(msg, sizeof msg, "--out '%.200s': cannot write: %s", outpath,
                     strerror(why));
            die(2, "%s", msg);
        }
    }

    total = 1ull << bits;
    F.lowbits = L.nkeep < 6 ? L.nkeep : 6;
    F.radius = h - 1 < L.nkeep ? h - 1 : L.nkeep;
    /* one word more than the index needs: its bits are all set (sentinel) */
    sentinel = ((1ull << L.nkeep) + 63) / 64 * 64;
    F.bitmap = calloc((size_t)(sentinel / 64 + 1), sizeof(uint64_t));
    if (F.bitmap)
        F.bitmap[sentinel / 64] = ~0ull;
    if (!F.bitmap)
        die(1, "out of memory for the %s bitmap", L.nkeep >= 32 ? "512 MiB" : "forbidden-word");
    if (!make_patterns(&F, L.nkeep - F.lowbits))
        die(1, "%s", "out of memory for the Hamming-ball table");
    min_energy = complexity * 2.0 * (L.k + 1) * (L.k + 1);
    emin = (int)min_energy; /* energy >= min_energy <=> energy >= ceil(min_energy) */
    if ((double)emin < min_energy)
        emin++;
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

    /* A bitmap that fits the caches (up to 2^24 bits, 2 MiB) is cheaper to
     * look at than the energy test; a larger one is not, so then only the
     * candidates that pass the energy test touch it. */
    energy_first = L.nkeep > 24;
    v = SEED & L.mask;
    pf = v;
    {
        /* The bitmap word of the candidate PREFETCH_AHEAD steps ahead is
         * fetched while the candidates before it are looked at (with
         * energy_first only when it passes the complexity test). */
        int j;
        for (j = 0; j < PREFETCH_AHEAD; j++) {
            pf = (pf + PRIME) & L.mask;
            ring[j] = energy_first && fast_energy(&L, &em, pf) < emin ? sentinel : squeeze(&L, pf);
        }
    }
    last_report = t0;
    for (iter = 0; iter < total; iter++) {
        uint64_t o[8], idx;
        int a, ok = 1;
        v = (v + PRIME) & L.mask;
        idx = ring[iter & (PREFETCH_AHEAD - 1)];
        pf = (pf + PRIME) & L.mask;
        {
            /* branch-free: a code that fails the energy test gets the index
             * of the sentinel bit, which is always set */
            uint64_t pi = squeeze(&L, pf);
            if (energy_first) {
                uint64_t fail = 0 - (uint64_t)(fast_energy(&L, &em, pf) < emin);
                pi = (pi & ~fail) | (sentinel & fail);
            }
            PREFETCH(&F.bitmap[pi >> 6]);
            ring[iter & (PREFETCH_AHEAD - 1)] = pi;
        }
        if ((iter & 0xfffff) == 0 || ncodes != codes_at_report) {
            double now = now_s();
            codes_at_report = ncodes; /* next check: after 2^20 more or a new code */
            if (now - last_report >= 2.0 && iter > 0) {
                double el = now - t0, scan = el - t_mark;
                double frac = (double)iter / (double)total;
                /* the search's current rate: over the last report interval */
                double rate = (scan - last_scan) / (double)(iter - last_iter);
                char e1[32], e2[32], e3[48];
                fmt_secs(e1, sizeof e1, el);
                fmt_secs(e2, sizeof e2, rate * (double)(total - iter));
                if (last_iter == 0) /* the first interval holds the start-up: no rate yet */
                    snprintf(e3, sizeof e3, "estimating the time left");
                else
                    snprintf(e3, sizeof e3, "about %s left", e2);
                last_scan = scan;
                last_iter = iter;
                fprintf(stderr, "\r" PROG ": %s: %5.1f%% searched, %lu codes, %s; %s "
                                "+ %.2g s per further code  ",
                        name, 100.0 * frac, (unsigned long)ncodes, e1, e3,
                        ncodes ? t_mark / (double)ncodes : 0.0);
                fflush(stderr);
                last_report = now;
                reported = 1;
            }
        }
        if (F.bitmap[idx >> 6] & (1ull << (idx & 63)))
            continue; /* too close to an accepted code, or not complex enough */
        if (!energy_first && fast_energy(&L, &em, v) < emin)
            continue;
        o[0] = v;
        for (a = 1; a < 4; a++)
            o[a] = rot90(&L, o[a - 1]);
        for (a = 0; a < 4; a++)
            o[4 + a] = mirror(&L, o[a]);
        /* Pairwise distances of the 8 orientations: the orientations form a
         * group and the counted cells are invariant, so d(g v, g' v) =
         * d(v, g^-1 g' v) and comparing v with the other 7 covers all pairs. */
        for (a = 1; a < 8; a++)
            if (popcount64((o[0] ^ o[a]) & L.keep) < h) {
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
        {
            double tm = now_s();
            for (a = 0; a < 8; a++)
                mark_ball(&F, squeeze(&L, o[a]));
            t_mark += now_s() - tm;
        }
    }
    if (reported) {
        char e1[32];
        fmt_secs(e1, sizeof e1, now_s() - t0);
        fprintf(stderr, "\r" PROG ": %s: 100.0%% searched, %lu codes, %s%30s\n", name,
                (unsigned long)ncodes, e1, "");
    }
    free(F.bitmap);
    free(F.pats);
    if (ncodes == 0) {
        /* The first code that passes the complexity test and differs from
         * its own orientations in >= H bits is always accepted: none did. */
        char msg[300];
        snprintf(msg, sizeof msg,
                 "%s would be empty: no %d-bit code differs from its own rotations and "
                 "mirror images in at least --hamming %d counted bits while meeting "
                 "--min-complexity %g; lower --hamming%s",
                 name, bits, h, complexity,
                 complexity > 0.0 ? " or --min-complexity" : "");
        free(codes);
        die(2, "%s", msg);
    }
    /* opened only now: an interrupted search leaves an older file intact */
    if (hostio_out_open(&g_out, outpath, "w", NULL) != HOSTIO_OK) {
        char msg[HOSTIO_ERRLEN + 64];
        snprintf(msg, sizeof msg, "--out '%.200s': cannot write: %s", outpath,
                 strerror(g_out.why));
        free(codes);
        die(2, "%s", msg);
    }
    out = g_out.f;
    if (strcmp(format, "txt") == 0)
        write_txt(out, &L, codes, ncodes);
    else if (strcmp(format, "c") == 0)
        write_c(out, &L, h, rule, name, codes, ncodes);
    else
        write_apriltag(out, &L, h, rule, name, codes, ncodes);
    free(codes);
    /* a write error shows in fflush, the stream's error flag or fclose;
     * a failed file is removed by hostio_out_close */
    if (hostio_out_close(&g_out, NULL) != HOSTIO_OK) {
        int why = g_out.why;
        char msg[HOSTIO_ERRLEN + 64];
        snprintf(msg, sizeof msg, "error writing '%.200s'%s%s",
                 outpath ? outpath : "standard output", why ? ": " : "",
                 why ? strerror(why) : "");
        die(2, "%s", msg);
    }
    return 0;
}
