/* actag-render end to end: runs the tool and checks its PGM images pixel by
 * pixel against actag_layout_cell(), its DXF cut files with an AutoCAD R12
 * structure checker and geometry checks written here (areas, positions,
 * holes, tabs), its SVG files with a tag-balance checker (and Python's
 * minidom when python3 is there), its sheets, --list-tabs for every code of
 * every family, and its error exits: options the output does not use are
 * refused, and a failed write leaves no file behind. */
#define _POSIX_C_SOURCE 200809L
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "actag/family.h"
#include "hostio.h"
#include "unity.h"

#include "actag/render.h"
#include "actag/version.h"

#ifndef ACTAG_RENDER_PATH
#error "ACTAG_RENDER_PATH must name the actag-render executable"
#endif

#define TAG_SIZE 0.130628571
#define MAXP 512

static char dir[1024];
static char errtext[4096];

void setUp(void) {}
void tearDown(void) {}

/* ------------------------------------------------------------------ running the tool */

static void path_of(char *buf, size_t n, const char *name)
{
    snprintf(buf, n, "%s/%s", dir, name);
}

/* Runs actag-render with args (stdout to dir/stdout.bin); returns the exit
 * status and keeps stderr in errtext. */
static int run(const char *args)
{
    char cmd[8192], errf[1200], outf[1200];
    char *e;
    size_t n = 0;
    int st;
    path_of(errf, sizeof errf, "stderr.txt");
    path_of(outf, sizeof outf, "stdout.bin");
    snprintf(cmd, sizeof cmd, "'%s' %s > '%s' 2> '%s'", ACTAG_RENDER_PATH, args, outf, errf);
    st = hostio_run(cmd, NULL);
    errtext[0] = '\0';
    e = (char *)hostio_slurp(errf, &n, NULL);
    if (e) {
        snprintf(errtext, sizeof errtext, "%s", e);
        free(e);
    }
    return st;
}

static int count_lines(const char *s)
{
    int n = 0;
    for (; *s; s++)
        n += *s == '\n';
    return n;
}

static int file_exists(const char *name)
{
    char p[1200];
    struct stat st;
    path_of(p, sizeof p, name);
    return stat(p, &st) == 0;
}

/* A file of dir as a NUL-terminated string (NULL when it cannot be read). */
static char *slurp(const char *name, size_t *len)
{
    char p[1200];
    path_of(p, sizeof p, name);
    return (char *)hostio_slurp(p, len, NULL);
}

/* An 8-bit PGM written by the tool (NULL when it does not parse as one). */
static uint8_t *read_pgm8(const char *path, int *rows, int *cols)
{
    hostio_image im;
    if (hostio_pgm_read(path, &im, NULL) != HOSTIO_OK)
        return NULL;
    if (im.depth != 8) {
        hostio_image_free(&im);
        return NULL;
    }
    *rows = im.rows;
    *cols = im.cols;
    return (uint8_t *)im.data;
}

/* ------------------------------------------------------------------ geometry helpers */

static double cell_mm(double tag_size, int bits) { return tag_size * 1000.0 / (double)(bits / 4 - 3); }

typedef struct {
    char layer[32];
    int n, closed;
    double x[MAXP], y[MAXP];
} poly_t;

static double poly_area(const poly_t *p) /* signed */
{
    double a = 0;
    int i;
    for (i = 0; i < p->n; i++) {
        int j = (i + 1) % p->n;
        a += p->x[i] * p->y[j] - p->x[j] * p->y[i];
    }
    return 0.5 * a;
}

/* even-odd point in polygon */
static int inside(const poly_t *p, double x, double y)
{
    int i, c = 0;
    for (i = 0; i < p->n; i++) {
        int j = (i + 1) % p->n;
        if ((p->y[i] > y) != (p->y[j] > y) &&
            x < p->x[i] + (y - p->y[i]) * (p->x[j] - p->x[i]) / (p->y[j] - p->y[i]))
            c = !c;
    }
    return c;
}

/* ------------------------------------------------------------------ DXF R12 checker */

typedef struct {
    int npolys, ncircles, npoints, ntexts, nlines;
    poly_t *polys;
    double cx[256], cy[256], cr[256];
    double px[64], py[64];
    char texts[64][80];
    char acadver[16];
    int insunits;
    double extmax_x, extmax_y;
    char layers[16][32];
    int nlayers;
} dxf_t;

static const char *const r12_entities[] = {"LINE",  "POINT",  "CIRCLE", "ARC",    "TRACE",
                                           "SOLID", "TEXT",   "SHAPE",  "INSERT", "ATTDEF",
                                           "ATTRIB", "POLYLINE", "VERTEX", "SEQEND", "3DFACE",
                                           "VIEWPORT", "DIMENSION", NULL};

static int is_r12_entity(const char *s)
{
    int i;
    for (i = 0; r12_entities[i]; i++)
        if (strcmp(s, r12_entities[i]) == 0)
            return 1;
    return 0;
}

/* Reads group code / value pairs. Returns 1 and fills code/val, 0 at end,
 * -1 on a malformed group code line. */
/* Copies src into dst[n], truncating (and always terminating). */
static void copy_str(char *dst, size_t n, const char *src)
{
    size_t len = strlen(src);
    if (len >= n)
        len = n - 1;
    memcpy(dst, src, len);
    dst[len] = '\0';
}

static int next_pair(char **cur, int *code, char *val, size_t valn)
{
    char *p = *cur, *nl, *end;
    long c;
    size_t len;
    if (*p == '\0')
        return 0;
    nl = strchr(p, '\n');
    if (!nl)
        return -1;
    *nl = '\0';
    errno = 0;
    c = strtol(p, &end, 10);
    while (*end == ' ' || *end == '\r')
        end++;
    if (end == p || *end != '\0' || errno || c < 0 || c > 1071)
        return -1;
    p = nl + 1;
    nl = strchr(p, '\n');
    if (!nl)
        return -1; /* a code without a value line */
    *nl = '\0';
    len = strlen(p);
    if (len && p[len - 1] == '\r')
        p[--len] = '\0';
    while (*p == ' ' && c != 1 && c != 999) /* numeric values may be right aligned */
        p++;
    snprintf(val, valn, "%s", p);
    *code = (int)c;
    *cur = nl + 1;
    return 1;
}

static int is_number(const char *s)
{
    char *end;
    errno = 0;
    strtod(s, &end);
    return end != s && *end == '\0' && errno == 0;
}

/* Parses and checks an R12 DXF; returns NULL on success or an error text. */
static const char *check_dxf(const char *name, dxf_t *d)
{
    static char msg[256];
    size_t len;
    char *text = slurp(name, &len), *cur, val[256];
    int code, r, section_seen[4] = {0, 0, 0, 0}, last_section = -1, in_poly = 0, saw_eof = 0;
    poly_t *poly = NULL;
    char ent[32] = "", hvar[64] = "";
    memset(d, 0, sizeof *d);
    d->insunits = -1;
    d->polys = (poly_t *)calloc(256, sizeof(poly_t));
    if (!text)
        return "cannot read file";
    cur = text;
#define FAIL(m)                                                                \
    do {                                                                       \
        snprintf(msg, sizeof msg, "%s (near '%.160s')", (m), val);                 \
        free(text);                                                            \
        return msg;                                                            \
    } while (0)
    val[0] = '\0';
    for (;;) {
        int sec;
        r = next_pair(&cur, &code, val, sizeof val);
        if (r < 0)
            FAIL("group code / value pairs do not alternate");
        if (r == 0)
            break;
        if (saw_eof)
            FAIL("data after EOF");
        if (code == 999)
            continue;
        if (code != 0)
            FAIL("expected group 0 at top level");
        if (strcmp(val, "EOF") == 0) {
            saw_eof = 1;
            continue;
        }
        if (strcmp(val, "SECTION") != 0)
            FAIL("expected SECTION");
        if (next_pair(&cur, &code, val, sizeof val) != 1 || code != 2)
            FAIL("SECTION without a name");
        sec = strcmp(val, "HEADER") == 0     ? 0
              : strcmp(val, "TABLES") == 0   ? 1
              : strcmp(val, "BLOCKS") == 0   ? 2
              : strcmp(val, "ENTITIES") == 0 ? 3
                                             : -1;
        if (sec < 0 || section_seen[sec] || sec <= last_section)
            FAIL("unknown, repeated or out-of-order section");
        section_seen[sec] = 1;
        last_section = sec;
        /* section body up to ENDSEC */
        for (;;) {
            r = next_pair(&cur, &code, val, sizeof val);
            if (r != 1)
                FAIL("section not closed by ENDSEC");
            if (code == 0 && strcmp(val, "ENDSEC") == 0) {
                if (in_poly)
                    FAIL("POLYLINE without SEQEND");
                break;
            }
            if (sec == 0) {
                if (code == 9)
                    copy_str(hvar, sizeof hvar, val);
                else if (strcmp(hvar, "$ACADVER") == 0 && code == 1)
                    copy_str(d->acadver, sizeof d->acadver, val);
                else if (strcmp(hvar, "$INSUNITS") == 0 && code == 70)
                    d->insunits = atoi(val);
                else if (strcmp(hvar, "$EXTMAX") == 0 && code == 10)
                    d->extmax_x = atof(val);
                else if (strcmp(hvar, "$EXTMAX") == 0 && code == 20)
                    d->extmax_y = atof(val);
                else if (code == 0)
                    FAIL("entity in HEADER");
            } else if (sec == 1) {
                if (code == 0)
                    copy_str(ent, sizeof ent, val);
                else if (code == 2 && strcmp(ent, "LAYER") == 0 && d->nlayers < 16)
                    copy_str(d->layers[d->nlayers++], 32, val);
            } else if (sec == 3) {
                if (code == 0) {
                    if (!is_r12_entity(val))
                        FAIL("entity type not in AutoCAD R12");
                    if (in_poly && strcmp(val, "VERTEX") != 0 && strcmp(val, "SEQEND") != 0)
                        FAIL("POLYLINE interrupted");
                    if (!in_poly && (strcmp(val, "VERTEX") == 0 || strcmp(val, "SEQEND") == 0))
                        FAIL("VERTEX/SEQEND outside a POLYLINE");
                    if (in_poly && strcmp(val, "SEQEND") == 0) {
                        in_poly = 0;
                        if (poly->n < 3)
                            FAIL("POLYLINE with fewer than 3 vertices");
                        d->npolys++;
                    }
                    copy_str(ent, sizeof ent, val);
                    if (strcmp(ent, "POLYLINE") == 0) {
                        if (d->npolys >= 256)
                            FAIL("too many polylines for the checker");
                        in_poly = 1;
                        poly = &d->polys[d->npolys];
                        memset(poly, 0, sizeof *poly);
                        poly->closed = -1;
                    } else if (strcmp(ent, "VERTEX") == 0) {
                        if (poly->n >= MAXP)
                            FAIL("too many vertices for the checker");
                        poly->n++;
                    } else if (strcmp(ent, "CIRCLE") == 0) {
                        d->ncircles++;
                    } else if (strcmp(ent, "POINT") == 0) {
                        d->npoints++;
                    } else if (strcmp(ent, "TEXT") == 0) {
                        d->ntexts++;
                    } else if (strcmp(ent, "LINE") == 0) {
                        d->nlines++;
                    }
                    continue;
                }
                if ((code >= 10 && code <= 40) || code == 70 || code == 66) {
                    if (!is_number(val))
                        FAIL("non-numeric coordinate");
                }
                if (code == 8) {
                    int i, ok = 0;
                    for (i = 0; i < d->nlayers; i++)
                        ok |= strcmp(d->layers[i], val) == 0;
                    if (!ok)
                        FAIL("entity on an undefined layer");
                    if (strcmp(ent, "POLYLINE") == 0)
                        copy_str(poly->layer, sizeof poly->layer, val);
                    else if (strcmp(ent, "VERTEX") == 0 && strcmp(poly->layer, val) != 0)
                        FAIL("VERTEX on another layer than its POLYLINE");
                }
                if (strcmp(ent, "POLYLINE") == 0 && code == 70)
                    poly->closed = atoi(val) & 1;
                if (strcmp(ent, "POLYLINE") == 0 && code == 66 && atoi(val) != 1)
                    FAIL("POLYLINE without vertices-follow flag");
                if (strcmp(ent, "VERTEX") == 0 && code == 10)
                    poly->x[poly->n - 1] = atof(val);
                if (strcmp(ent, "VERTEX") == 0 && code == 20)
                    poly->y[poly->n - 1] = atof(val);
                if (strcmp(ent, "CIRCLE") == 0 && d->ncircles <= 256) {
                    if (code == 10)
                        d->cx[d->ncircles - 1] = atof(val);
                    if (code == 20)
                        d->cy[d->ncircles - 1] = atof(val);
                    if (code == 40)
                        d->cr[d->ncircles - 1] = atof(val);
                }
                if (strcmp(ent, "POINT") == 0 && d->npoints <= 64) {
                    if (code == 10)
                        d->px[d->npoints - 1] = atof(val);
                    if (code == 20)
                        d->py[d->npoints - 1] = atof(val);
                }
                if (strcmp(ent, "TEXT") == 0 && code == 1 && d->ntexts <= 64)
                    copy_str(d->texts[d->ntexts - 1], 80, val);
            }
        }
    }
    if (!saw_eof)
        FAIL("no EOF");
    if (!section_seen[0] || !section_seen[3])
        FAIL("HEADER or ENTITIES section missing");
    {
        int i;
        for (i = 0; i < d->npolys; i++)
            if (d->polys[i].closed != 1)
                FAIL("POLYLINE not closed (group 70 bit 1)");
    }
#undef FAIL
    free(text);
    return NULL;
}

static void free_dxf(dxf_t *d) { free(d->polys); }

/* Is (x, y) metal in the DXF: inside an odd number of OUTLINE/CUTOUT loops? */
static int dxf_metal(const dxf_t *d, double x, double y)
{
    int i, c = 0;
    for (i = 0; i < d->npolys; i++)
        c ^= inside(&d->polys[i], x, y);
    return c;
}

/* Full geometric check of one face plate DXF (single plate at the origin).
 * margin in cells, tab width w in mm, holes: 1 = default corner holes of
 * diameter hole_d. */
static void check_face_plate(const char *name, const actag_family *fam, int id, double tag_size,
                             double margin_cells, double w, double hole_d)
{
    dxf_t d;
    const char *err = check_dxf(name, &d);
    int k = fam->bits / 4, x, y, i, white = 0, nout = 0, ntabs = 0, tabs, c;
    double cell = cell_mm(tag_size, fam->bits), m = margin_cells * cell, W = (k + 1) * cell + 2 * m;
    double out_area = 0, cut_area = 0, expect_white;
    char msg[300];
    const char *mp = msg;
    snprintf(msg, sizeof msg, "%s: %s", name, err ? err : "");
    TEST_ASSERT_NULL_MESSAGE(err, mp);
    TEST_ASSERT_EQUAL_STRING("AC1009", d.acadver);
    TEST_ASSERT_EQUAL_INT(4, d.insunits);
    TEST_ASSERT_FLOAT_WITHIN(1e-3f, (float)W, (float)d.extmax_x);
    tabs = actag_layout_corner_tabs(fam, id);
    TEST_ASSERT_GREATER_OR_EQUAL(0, tabs);
    if (w > 0)
        for (c = 0; c < 4; c++)
            ntabs += (tabs >> c) & 1;

    for (i = 0; i < d.npolys; i++) {
        const poly_t *p = &d.polys[i];
        int v;
        double a = poly_area(p);
        for (v = 0; v < p->n; v++) {
            int nv = (v + 1) % p->n;
            TEST_ASSERT_TRUE_MESSAGE(p->x[v] >= -1e-6 && p->x[v] <= W + 1e-6 && p->y[v] >= -1e-6 &&
                                         p->y[v] <= W + 1e-6,
                                     "vertex outside the plate");
            /* rectilinear: every edge is horizontal or vertical */
            TEST_ASSERT_TRUE(fabs(p->x[v] - p->x[nv]) < 1e-9 || fabs(p->y[v] - p->y[nv]) < 1e-9);
        }
        if (strcmp(p->layer, "OUTLINE") == 0) {
            nout++;
            out_area += fabs(a);
        } else {
            TEST_ASSERT_EQUAL_STRING("CUTOUT", p->layer);
            cut_area += fabs(a);
        }
    }
    TEST_ASSERT_EQUAL_INT(1, nout); /* one piece of metal */

    /* the foam area the layout asks for, less the tabs' corners in white cells */
    for (y = 0; y <= k; y++)
        for (x = 0; x <= k; x++)
            white += actag_layout_cell(fam, id, x, y);
    expect_white = white * cell * cell - ntabs * w * w / 2;
    if (margin_cells > 0) {
        TEST_ASSERT_FLOAT_WITHIN(1e-6f, 1.0f, (float)(out_area / (W * W)));
        TEST_ASSERT_FLOAT_WITHIN(1e-6f, 1.0f, (float)(cut_area / expect_white));
    } else {
        TEST_ASSERT_FLOAT_WITHIN(1e-6f, 1.0f, (float)((W * W - (out_area - cut_area)) / expect_white));
    }

    /* every cell centre (and points near cell corners) is metal exactly when the layout says
     * black; DXF y is up */
    for (y = 0; y <= k; y++)
        for (x = 0; x <= k; x++) {
            int black = actag_layout_cell(fam, id, x, y) == 0, q;
            static const double off[5][2] = {{0.5, 0.5}, {0.1, 0.1}, {0.9, 0.1}, {0.1, 0.9}, {0.9, 0.9}};
            for (q = 0; q < 5; q++) {
                double px = m + (x + off[q][0]) * cell, py = W - (m + (y + off[q][1]) * cell);
                snprintf(msg, sizeof msg, "%s: cell (%d,%d) sample %d", name, x, y, q);
                /* sample points closer than w/2 to a tab centre may be metal */
                if (q > 0 && ntabs > 0 && !black) {
                    int t, neartab = 0;
                    for (t = 0; t < d.npoints; t++)
                        neartab |= fabs(px - d.px[t]) < w && fabs(py - d.py[t]) < w;
                    if (neartab)
                        continue;
                }
                TEST_ASSERT_EQUAL_INT_MESSAGE(black, dxf_metal(&d, px, py), msg);
            }
        }
    /* margin is metal */
    if (margin_cells > 0) {
        TEST_ASSERT_TRUE(dxf_metal(&d, m / 2, m / 2));
        TEST_ASSERT_TRUE(dxf_metal(&d, W - m / 2, W / 2));
    }

    /* tabs: one POINT at each, at the contact corner of the black ring, and metal there */
    TEST_ASSERT_EQUAL_INT(ntabs, d.npoints);
    for (i = 0; i < d.npoints; i++) {
        double tx = d.px[i] - m, ty = (W - d.py[i]) - m;
        int gx = (int)lround(tx / cell), gy = (int)lround(ty / cell), corner;
        TEST_ASSERT_FLOAT_WITHIN(1e-4f, (float)(gx * cell), (float)tx);
        TEST_ASSERT_FLOAT_WITHIN(1e-4f, (float)(gy * cell), (float)ty);
        TEST_ASSERT_TRUE((gx == 1 || gx == k) && (gy == 1 || gy == k));
        corner = gy == 1 ? (gx == 1 ? ACTAG_CORNER_TOP_LEFT : ACTAG_CORNER_TOP_RIGHT)
                         : (gx == k ? ACTAG_CORNER_BOTTOM_RIGHT : ACTAG_CORNER_BOTTOM_LEFT);
        TEST_ASSERT_TRUE(tabs & corner);
        /* the bridge: metal just off the contact point inside both white neighbours */
        TEST_ASSERT_TRUE(dxf_metal(&d, d.px[i] + w / 4, d.py[i] + w / 4));
        TEST_ASSERT_TRUE(dxf_metal(&d, d.px[i] - w / 4, d.py[i] - w / 4));
        TEST_ASSERT_TRUE(dxf_metal(&d, d.px[i] + w / 4, d.py[i] - w / 4));
        TEST_ASSERT_TRUE(dxf_metal(&d, d.px[i] - w / 4, d.py[i] + w / 4));
        TEST_ASSERT_FALSE(dxf_metal(&d, d.px[i] + w, d.py[i] + w) && dxf_metal(&d, d.px[i] - w, d.py[i] + w) &&
                          dxf_metal(&d, d.px[i] + w, d.py[i] - w) && dxf_metal(&d, d.px[i] - w, d.py[i] - w));
    }

    /* holes: the four corner cells of the black ring */
    if (hole_d > 0) {
        TEST_ASSERT_EQUAL_INT(4, d.ncircles);
        for (i = 0; i < 4; i++) {
            double ex = m + ((i == 1 || i == 2) ? k - 0.5 : 1.5) * cell;
            double ey = W - (m + (i >= 2 ? k - 0.5 : 1.5) * cell);
            int j, found = 0;
            for (j = 0; j < 4; j++)
                found |= fabs(d.cx[j] - ex) < 1e-4 && fabs(d.cy[j] - ey) < 1e-4 &&
                         fabs(d.cr[j] - hole_d / 2) < 1e-6;
            TEST_ASSERT_TRUE_MESSAGE(found, "screw hole missing");
            TEST_ASSERT_TRUE(dxf_metal(&d, ex, ey));
        }
    } else {
        TEST_ASSERT_EQUAL_INT(0, d.ncircles);
    }
    free_dxf(&d);
}

/* ------------------------------------------------------------------ SVG checker */

/* Tag balance: every start tag closed in order, one root <svg> with
 * width/height in mm and a viewBox. Accumulates the absolute area of path
 * loops in groups OUTLINE and CUTOUT. Returns NULL when well formed. */
/* Every early return of check_svg frees the file text. */
#define SVG_FAIL(m)                                                            \
    do {                                                                       \
        free(s);                                                               \
        return (m);                                                            \
    } while (0)
static const char *check_svg(const char *name, double *outline_area, double *cutout_area,
                             int *ntext, int *ncircle)
{
    static char stack[64][32];
    size_t len;
    char *s = slurp(name, &len), *p;
    int depth = 0, roots = 0;
    char group[32] = "";
    *outline_area = *cutout_area = 0;
    *ntext = *ncircle = 0;
    if (!s)
        SVG_FAIL("cannot read");
    p = s;
    while ((p = strchr(p, '<')) != NULL) {
        char nm[32];
        char *end;
        size_t n = 0;
        int closing = 0, selfclose;
        if (strncmp(p, "<?", 2) == 0) {
            end = strstr(p, "?>");
            if (!end)
                SVG_FAIL("unterminated <?");
            p = end + 2;
            continue;
        }
        if (strncmp(p, "<!--", 4) == 0) {
            end = strstr(p, "-->");
            if (!end)
                SVG_FAIL("unterminated comment");
            p = end + 3;
            continue;
        }
        end = strchr(p, '>');
        if (!end)
            SVG_FAIL("unterminated tag");
        p++;
        if (*p == '/') {
            closing = 1;
            p++;
        }
        while ((isalnum((unsigned char)p[n]) || p[n] == ':' || p[n] == '-') && n < sizeof nm - 1)
            n++;
        if (n == 0)
            SVG_FAIL("tag without a name");
        memcpy(nm, p, n);
        nm[n] = '\0';
        selfclose = end[-1] == '/';
        /* attributes: quotes balanced */
        {
            char *q;
            int quotes = 0;
            for (q = p; q < end; q++)
                quotes += *q == '"';
            if (quotes % 2)
                SVG_FAIL("unbalanced quotes");
        }
        if (closing) {
            if (depth == 0 || strcmp(stack[depth - 1], nm) != 0)
                SVG_FAIL("closing tag does not match");
            depth--;
            if (strcmp(nm, "g") == 0)
                group[0] = '\0';
        } else {
            *end = '\0';
            if (strcmp(nm, "svg") == 0) {
                roots++;
                if (depth != 0 || !strstr(p, "viewBox=\"") || !strstr(p, "mm\" height=\"") ||
                    !strstr(p, "width=\""))
                    SVG_FAIL("svg root without mm size or viewBox");
            } else if (depth == 0) {
                SVG_FAIL("content outside the root");
            }
            if (strcmp(nm, "g") == 0) {
                char *id = strstr(p, "id=\"");
                if (id)
                    sscanf(id + 4, "%31[^\"]", group);
            }
            if (strcmp(nm, "text") == 0)
                (*ntext)++;
            if (strcmp(nm, "circle") == 0)
                (*ncircle)++;
            if (strcmp(nm, "path") == 0 &&
                (strcmp(group, "OUTLINE") == 0 || strcmp(group, "CUTOUT") == 0)) {
                char *dd = strstr(p, " d=\"");
                poly_t *poly = (poly_t *)calloc(1, sizeof(poly_t));
                char *t;
                if (!dd || !poly) {
                    free(poly);
                    SVG_FAIL("path without d");
                }
                t = dd + 4;
                for (;;) {
                    double x, y;
                    int used = 0;
                    while (*t == ' ')
                        t++;
                    if (*t == 'M' || *t == 'L') {
                        if (*t == 'M')
                            poly->n = 0;
                        if (sscanf(t + 1, "%lf %lf%n", &x, &y, &used) != 2 || poly->n >= MAXP) {
                            free(poly);
                            SVG_FAIL("bad path data");
                        }
                        poly->x[poly->n] = x;
                        poly->y[poly->n++] = y;
                        t += 1 + used;
                    } else if (*t == 'Z') {
                        double a = fabs(poly_area(poly));
                        if (group[0] == 'O')
                            *outline_area += a;
                        else
                            *cutout_area += a;
                        t++;
                    } else {
                        break;
                    }
                }
                free(poly);
            }
            if (!selfclose) {
                if (depth >= 64)
                    SVG_FAIL("too deep");
                snprintf(stack[depth++], 32, "%s", nm);
            }
            *end = '>';
        }
        p = end + 1;
    }
    free(s);
    s = NULL;
    if (depth != 0)
        SVG_FAIL("unclosed element");
    if (roots != 1)
        SVG_FAIL("not exactly one <svg> root");
    return NULL;
}
#undef SVG_FAIL

static int have_python_minidom(void)
{
    return system("python3 -c 'import xml.dom.minidom' >/dev/null 2>&1") == 0;
}

static void minidom_check(const char *name)
{
    char cmd[2048], p[1200];
    if (!have_python_minidom())
        return;
    path_of(p, sizeof p, name);
    snprintf(cmd, sizeof cmd,
             "python3 -c 'import sys, xml.dom.minidom; xml.dom.minidom.parse(sys.argv[1])' '%s'", p);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, system(cmd), "python3 xml.dom.minidom rejects the SVG");
}

/* ------------------------------------------------------------------ tests */

static void check_pgm_against_layout(const char *name, const actag_family *fam, int id, int cell,
                                     int margin, int margin_val, int camera)
{
    char p[1200];
    int rows = 0, cols = 0, r, c, k = fam->bits / 4;
    uint8_t *img;
    path_of(p, sizeof p, name);
    img = read_pgm8(p, &rows, &cols);
    TEST_ASSERT_NOT_NULL_MESSAGE(img, "PGM does not parse");
    TEST_ASSERT_EQUAL_INT((k + 1) * cell + 2 * margin, rows);
    TEST_ASSERT_EQUAL_INT(rows, cols);
    for (r = 0; r < rows; r++)
        for (c = 0; c < cols; c++) {
            int e;
            if (r < margin || c < margin || r >= rows - margin || c >= cols - margin)
                e = margin_val;
            else
                e = actag_layout_cell(fam, id, (c - margin) / cell, (r - margin) / cell) ? 255 : 0;
            if (camera)
                e = 255 - e;
            TEST_ASSERT_EQUAL_INT(e, img[r * cols + c]);
        }
    free(img);
}

static void test_pgm_6000(void)
{
    actag_family fam;
    char args[2048];
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h4", &fam));
    snprintf(args, sizeof args, "--family AcTag24h4 --id 6000 --cell-px 7 --margin-cells 2 --out '%s/a.pgm'", dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
    check_pgm_against_layout("a.pgm", &fam, 6000, 7, 14, 0, 0);
    snprintf(args, sizeof args,
             "--family AcTag24h4 --id 6000 --camera --margin-colour foam --out '%s/b.pgm'", dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
    check_pgm_against_layout("b.pgm", &fam, 6000, 20, 20, 255, 1);
    /* to stdout, defaults, fractional margin */
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run("--family AcTag24h10 --id 3 --cell-px 4 --margin-cells 0.5"), errtext);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
    check_pgm_against_layout("stdout.bin", &fam, 3, 4, 2, 0, 0);
    TEST_ASSERT_EQUAL_STRING("", errtext);
}

static void test_dxf_6000(void)
{
    actag_family fam;
    char args[2048];
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h4", &fam));
    /* ID 6000 has a black bottom-left corner bit with white neighbours */
    TEST_ASSERT_EQUAL_INT(ACTAG_CORNER_BOTTOM_LEFT, actag_layout_corner_tabs(&fam, 6000));
    snprintf(args, sizeof args,
             "--family AcTag24h4 --id 6000 --cut --tab-width 5 --hole-diameter 4 --out '%s/c.dxf'", dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
    TEST_ASSERT_EQUAL_STRING("", errtext);
    check_face_plate("c.dxf", &fam, 6000, TAG_SIZE, 0, 5, 4);
    /* default format is DXF, default tab 0.15 cell; with a one-cell metal margin every
     * white cell is a window */
    snprintf(args, sizeof args,
             "--family AcTag24h4 --id 6000 --cut --margin-cells 1 --tag-size 0.05 --tab-width 2 "
             "--out '%s/d.dxf'", dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
    check_face_plate("d.dxf", &fam, 6000, 0.05, 1, 2, 3.4);
    /* no tab: the plate falls apart; the tool warns but writes it */
    snprintf(args, sizeof args, "--family AcTag24h4 --id 6000 --cut --tab-width 0 --out '%s/e.dxf'", dir);
    TEST_ASSERT_EQUAL_INT(0, run(args));
    TEST_ASSERT_NOT_NULL(strstr(errtext, "warning"));
    {
        dxf_t d;
        int i, nout = 0;
        TEST_ASSERT_NULL(check_dxf("e.dxf", &d));
        for (i = 0; i < d.npolys; i++)
            nout += strcmp(d.polys[i].layer, "OUTLINE") == 0;
        TEST_ASSERT_EQUAL_INT(2, nout);
        TEST_ASSERT_EQUAL_INT(0, d.npoints);
        free_dxf(&d);
    }
    /* back plate: a square and four holes */
    snprintf(args, sizeof args, "--family AcTag24h4 --id 6000 --back-plate --out '%s/f.dxf'", dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
    {
        dxf_t d;
        TEST_ASSERT_NULL(check_dxf("f.dxf", &d));
        TEST_ASSERT_EQUAL_INT(1, d.npolys);
        TEST_ASSERT_EQUAL_INT(4, d.polys[0].n);
        TEST_ASSERT_FLOAT_WITHIN(1e-3f, 304.8f, (float)sqrt(fabs(poly_area(&d.polys[0]))));
        TEST_ASSERT_EQUAL_INT(4, d.ncircles);
        free_dxf(&d);
    }
    /* custom holes in mm from the tag's top-left corner, no holes */
    snprintf(args, sizeof args,
             "--family AcTag24h4 --id 6000 --cut --screw-holes 65,65,152.4,239 --out '%s/g.dxf'", dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
    {
        dxf_t d;
        TEST_ASSERT_NULL(check_dxf("g.dxf", &d));
        TEST_ASSERT_EQUAL_INT(2, d.ncircles);
        TEST_ASSERT_FLOAT_WITHIN(1e-4f, 152.4f, (float)d.cx[1]);
        TEST_ASSERT_FLOAT_WITHIN(1e-4f, (float)(304.799999 - 239), (float)d.cy[1]);
        free_dxf(&d);
    }
    snprintf(args, sizeof args, "--family AcTag24h4 --id 6000 --cut --screw-holes none --out '%s/h.dxf'", dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
    check_face_plate("h.dxf", &fam, 6000, TAG_SIZE, 0, 0.15 * cell_mm(TAG_SIZE, 24), 0);
}

static void test_dxf_many_tags_and_tabs(void)
{
    /* Every tag of the families of up to 48 codes and a sample of the others
     * (published and mirror-safe, 24 and 28 bits): one piece of metal, right
     * areas, tabs exactly where actag_layout_corner_tabs says. */
    static const char *const names[12] = {"AcTag24h10", "AcTag24h8",  "AcTag24h6",  "AcTag24h4",
                                          "AcTag24m10", "AcTag24m8",  "AcTag24m6",  "AcTag24m4",
                                          "AcTag28m10", "AcTag28m8",  "AcTag28m6",  "AcTag28m4"};
    int f, tabbed = 0;
    for (f = 0; f < 12; f++) {
        actag_family fam;
        char args[2048], ids[4096], name[128];
        int n = 0, i, list[64];
        if (f >= 4 && actag_family_get(names[f], &fam) != ACTAG_OK)
            continue; /* mirror-safe family not in ACTAG_FAMILIES */
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get(names[f], &fam));
        if (fam.ncodes <= 48) {
            for (i = 0; i < fam.ncodes; i++)
                list[n++] = i;
        } else {
            /* the first 30 IDs and the last one */
            for (i = 0; i < 30; i++)
                list[n++] = i;
            list[n++] = fam.ncodes - 1;
        }
        ids[0] = '\0';
        for (i = 0; i < n; i++)
            snprintf(ids + strlen(ids), sizeof ids - strlen(ids), "%s%d", i ? "," : "", list[i]);
        TEST_ASSERT_TRUE(snprintf(args, sizeof args,
                                  "--family %s --ids %s --cut --tab-width 3 --hole-diameter 5 "
                                  "--out-dir '%s'",
                                  names[f], ids, dir) < (int)sizeof args);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
        TEST_ASSERT_EQUAL_STRING("", errtext);
        for (i = 0; i < n; i++) {
            snprintf(name, sizeof name, "%s-%d-face.dxf", names[f], list[i]);
            check_face_plate(name, &fam, list[i], TAG_SIZE, 0, 3, 5);
            tabbed += actag_layout_corner_tabs(&fam, list[i]) != 0;
        }
    }
    TEST_ASSERT_GREATER_THAN(10, tabbed);
}

static void test_list_tabs_all_families(void)
{
    /* --list-tabs over every code of every built-in family equals
     * actag_layout_corner_tabs() (itself checked against a flood fill in
     * tests/test_render.c). */
    int f, nf = actag_family_count();
    for (f = 0; f < nf; f++) {
        actag_family fam;
        char args[256], *text, *line;
        int id, listed = 0;
        int *mask;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get_at(f, &fam));
        snprintf(args, sizeof args, "--family %s --all --list-tabs", fam.name);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
        text = slurp("stdout.bin", NULL);
        TEST_ASSERT_NOT_NULL(text);
        mask = (int *)calloc((size_t)fam.ncodes, sizeof(int));
        for (line = strtok(text, "\n"); line; line = strtok(NULL, "\n")) {
            char corners[32];
            TEST_ASSERT_EQUAL_INT(2, sscanf(line, "%d %31s", &id, corners));
            TEST_ASSERT_TRUE(id >= 0 && id < fam.ncodes);
            mask[id] = (strstr(corners, "TL") ? ACTAG_CORNER_TOP_LEFT : 0) |
                       (strstr(corners, "TR") ? ACTAG_CORNER_TOP_RIGHT : 0) |
                       (strstr(corners, "BR") ? ACTAG_CORNER_BOTTOM_RIGHT : 0) |
                       (strstr(corners, "BL") ? ACTAG_CORNER_BOTTOM_LEFT : 0);
            listed++;
        }
        for (id = 0; id < fam.ncodes; id++)
            TEST_ASSERT_EQUAL_INT(actag_layout_corner_tabs(&fam, id), mask[id]);
        printf("%s: %d of %d face plates need corner tabs\n", fam.name, listed, fam.ncodes);
        free(mask);
        free(text);
    }
}

static void test_svg(void)
{
    char args[2048];
    double oa, ca;
    int nt, nc, x, y, white = 0;
    const char *err;
    actag_family fam;
    double cell = cell_mm(TAG_SIZE, 24), expect;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h4", &fam));
    /* cut SVG: same geometry as the DXF */
    snprintf(args, sizeof args,
             "--family AcTag24h4 --id 6000 --cut --format svg --tab-width 5 --margin-cells 1 --out '%s/c.svg'",
             dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
    err = check_svg("c.svg", &oa, &ca, &nt, &nc);
    TEST_ASSERT_NULL_MESSAGE(err, err);
    minidom_check("c.svg");
    for (y = 0; y <= 6; y++)
        for (x = 0; x <= 6; x++)
            white += actag_layout_cell(&fam, 6000, x, y);
    expect = white * cell * cell - 25.0 / 2;
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 1.0f, (float)(ca / expect));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 1.0f, (float)(oa / (81 * cell * cell)));
    TEST_ASSERT_EQUAL_INT(4, nc);
    /* image SVG (camera colours) */
    snprintf(args, sizeof args, "--family AcTag24h4 --id 6000 --format svg --camera --out '%s/i.svg'", dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
    err = check_svg("i.svg", &oa, &ca, &nt, &nc);
    TEST_ASSERT_NULL_MESSAGE(err, err);
    minidom_check("i.svg");
    /* the checker itself rejects broken XML */
    {
        char p[1200];
        FILE *f;
        path_of(p, sizeof p, "broken.svg");
        f = fopen(p, "w");
        TEST_ASSERT_NOT_NULL(f);
        fputs("<svg width=\"1mm\" height=\"1mm\" viewBox=\"0 0 1 1\"><g></svg></g>\n", f);
        fclose(f);
        TEST_ASSERT_NOT_NULL(check_svg("broken.svg", &oa, &ca, &nt, &nc));
    }
}

/* Does the page contain the tag image exactly, at some position? */
static int find_block(const uint8_t *page, int pw, int ph, const uint8_t *blk, int bs)
{
    int x, y, r;
    for (y = 0; y + bs <= ph; y++)
        for (x = 0; x + bs <= pw; x++) {
            for (r = 0; r < bs; r++)
                if (memcmp(page + (size_t)(y + r) * (size_t)pw + x, blk + (size_t)r * (size_t)bs,
                           (size_t)bs) != 0)
                    break;
            if (r == bs)
                return 1;
        }
    return 0;
}

static void test_sheets(void)
{
    char args[2048], p[1200];
    actag_family fam;
    int side = actag_render_side(24, 6, 6), rows = 0, cols = 0, t;
    uint8_t *blk = (uint8_t *)malloc((size_t)side * (size_t)side), *page;
    static const int ids[3] = {0, 5, 6000};
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h4", &fam));
    snprintf(args, sizeof args,
             "--family AcTag24h4 --ids 0,5,6000 --sheet --columns 2 --rows 1 --cell-px 6 --out '%s/s.pgm'",
             dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
    TEST_ASSERT_TRUE(file_exists("s-p1.pgm"));
    TEST_ASSERT_TRUE(file_exists("s-p2.pgm"));
    TEST_ASSERT_FALSE(file_exists("s-p3.pgm"));
    for (t = 0; t < 3; t++) {
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_render_tag(&fam, ids[t], 6, 6, 0, 0, blk, side,
                                                         (size_t)side * (size_t)side));
        path_of(p, sizeof p, t < 2 ? "s-p1.pgm" : "s-p2.pgm");
        page = read_pgm8(p, &rows, &cols);
        TEST_ASSERT_NOT_NULL(page);
        TEST_ASSERT_TRUE_MESSAGE(find_block(page, cols, rows, blk, side), "tag not on its page");
        free(page);
    }
    free(blk);

    /* SVG sheet of small paper tags, each labelled */
    snprintf(args, sizeof args,
             "--family AcTag24h10 --all --sheet --format svg --tag-size 0.03 --page-width 400 "
             "--page-height 400 --out '%s/s.svg'", dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
    {
        double oa, ca;
        int nt, nc;
        const char *err = check_svg("s.svg", &oa, &ca, &nt, &nc);
        char *s;
        TEST_ASSERT_NULL_MESSAGE(err, err);
        TEST_ASSERT_EQUAL_INT(7, nt);
        s = slurp("s.svg", NULL);
        TEST_ASSERT_NOT_NULL(strstr(s, ">AcTag24h10 ID 6</text>"));
        free(s);
        minidom_check("s.svg");
    }

    /* DXF cut sheet on a 1000 x 700 mm metal sheet: 7 plates of 304.8 mm -> 2 pages */
    snprintf(args, sizeof args,
             "--family AcTag24h10 --all --cut --sheet --page-width 1000 --page-height 700 --out-dir '%s'",
             dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
    {
        dxf_t d;
        int i, v, total = 0;
        for (t = 1; t <= 2; t++) {
            char name[64];
            snprintf(name, sizeof name, "AcTag24h10-face-sheet-p%d.dxf", t);
            TEST_ASSERT_NULL(check_dxf(name, &d));
            TEST_ASSERT_EQUAL_INT(4 * d.ntexts, d.ncircles);
            for (i = 0; i < d.npolys; i++)
                for (v = 0; v < d.polys[i].n; v++)
                    TEST_ASSERT_TRUE(d.polys[i].x[v] >= 0 && d.polys[i].x[v] <= 1000 &&
                                     d.polys[i].y[v] >= 0 && d.polys[i].y[v] <= 700);
            total += d.ntexts;
            free_dxf(&d);
        }
        TEST_ASSERT_EQUAL_INT(7, total);
        TEST_ASSERT_FALSE(file_exists("AcTag24h10-face-sheet-p3.dxf"));
    }

    /* A huge page of tiny tags: the fitted columns x rows once wrapped the
     * int (SIGFPE dividing by a zero tags-per-page, signed overflow under
     * UBSan); they are capped at 10000 each, as --columns/--rows are. */
    {
        static const char *const huge[] = {
            "--tag-size 0.002 --gap 0 --page-width 393217 --page-height 507905",
            "--tag-size 1e-4 --gap 0 --page-width 1e6 --page-height 1e6", NULL};
        for (t = 0; huge[t]; t++) {
            char *s;
            int nt, nc;
            double oa, ca;
            const char *err;
            snprintf(args, sizeof args,
                     "--family AcTag24h10 --id 0 --sheet --format svg %s --out '%s/huge.svg'",
                     huge[t], dir);
            TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
            err = check_svg("huge.svg", &oa, &ca, &nt, &nc);
            TEST_ASSERT_NULL_MESSAGE(err, err);
            TEST_ASSERT_EQUAL_INT(1, nt);
            s = slurp("huge.svg", NULL);
            TEST_ASSERT_NOT_NULL(s);
            TEST_ASSERT_NOT_NULL(strstr(s, "page 1 of 1"));
            free(s);
        }
    }
}

static void test_errors(void)
{
    static const char *const bad[] = {
        "",
        "--family Nope --id 0",
        "--family AcTag24h4 --id 6261",
        "--family AcTag24h4 --id -1",
        "--family AcTag24h4 --id 12x",
        "--family AcTag24h4",
        "--family AcTag24h4 --id 1 --all",
        "--family AcTag24h4 --id 1 --cell-px 0",
        "--family AcTag24h4 --id 1 --cell-px abc",
        "--family AcTag24h4 --id 1 --tag-size -1",
        "--family AcTag24h4 --id 1 --tag-size nan",
        "--family AcTag24h4 --id 1 --cut --tag-size 90", /* millimetres, not metres */
        "--family AcTag24h4 --id 1 --margin-cells 1e999",
        "--family AcTag24h4 --id 1 --format png",
        "--family AcTag24h4 --id 1 --cut --format pgm",
        "--family AcTag24h4 --id 1 --cut --camera",
        "--family AcTag24h4 --id 1 --cut --hole-diameter 60",
        "--family AcTag24h4 --id 1 --cut --screw-holes 1,2,3",
        "--family AcTag24h4 --id 1 --cut --screw-holes 0,0",
        "--family AcTag24h4 --id 1 --cut --screw-holes 10,10,", /* a trailing separator */
        "--family AcTag24h4 --id 1 --cut --tab-width 50",
        "--family AcTag24h4 --ids 3-1",
        "--family AcTag24h4 --ids 1,,2",
        "--family AcTag24h4 --ids 0-2",
        "--family AcTag24h4 --id 1 --columns 3",
        "--family AcTag24h4 --id 1 --out /nonexistent-dir/x.pgm",
        "--family AcTag24h4 --id 1 --out-dir /dev/null/plates", /* cannot be created */
        "--family AcTag24h4 --id 1 --frobnicate",
        "--family AcTag24h4 --id",
        "--family AcTag24h10 --all --sheet --format svg",
        /* an option given twice (the last one was kept: plate 5 was cut) */
        "--family AcTag24h10 --id 0 --id 5 --cut",
        "--family AcTag24h10 --family AcTag24h4 --id 1",
        "--family AcTag24h4 --id 1 --cut --tag-size 0.05 --tag-size 0.1",
        "--family AcTag24h4 --id 1 --margin-cells 1 --margin-colour foam --margin-color metal",
        NULL};
    int i;
    for (i = 0; bad[i]; i++) {
        char msg[700];
        int st = run(bad[i]);
        snprintf(msg, sizeof msg, "args '%s': status %d, stderr '%.400s'", bad[i], st, errtext);
        TEST_ASSERT_EQUAL_INT_MESSAGE(2, st, msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(1, count_lines(errtext), msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, strncmp(errtext, "actag-render: ", 14), msg);
    }
    TEST_ASSERT_EQUAL_INT(0, run("--help"));
    /* hostio's option messages, as every host tool ("--id needs a value" before) */
    TEST_ASSERT_EQUAL_INT(2, run("--family AcTag24h4 --id"));
    TEST_ASSERT_EQUAL_STRING("actag-render: --id: missing value\n", errtext);
    TEST_ASSERT_EQUAL_INT(2, run("--family AcTag24h4 --id 1 --frobnicate"));
    TEST_ASSERT_EQUAL_STRING("actag-render: unknown option '--frobnicate' (try --help)\n", errtext);
}

/* Arguments actag-render refuses, the option the message must name and
 * the value (or text) it must quote. */
typedef struct {
    const char *args, *opt, *value;
} refused_t;

/* Each bad[i] (up to the one with args NULL), run as "--family <family>
 * ARGS --out DIR/<out>": status 2, one line on stderr starting
 * "actag-render: " and naming bad[i].opt and bad[i].value, and no file
 * <out> written. */
static void check_refused(const char *family, const refused_t *bad, const char *out)
{
    char args[2048], msg[1200];
    int i;
    for (i = 0; bad[i].args; i++) {
        int st;
        path_of(msg, sizeof msg, out);
        remove(msg);
        snprintf(args, sizeof args, "--family %s %s --out '%s/%s'", family, bad[i].args, dir, out);
        st = run(args);
        snprintf(msg, sizeof msg, "args '%s': status %d, stderr '%.400s'", bad[i].args, st,
                 errtext);
        TEST_ASSERT_EQUAL_INT_MESSAGE(2, st, msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(1, count_lines(errtext), msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, strncmp(errtext, "actag-render: ", 14), msg);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(errtext, bad[i].opt), msg);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(errtext, bad[i].value), msg);
        TEST_ASSERT_FALSE_MESSAGE(file_exists(out), msg);
    }
}

/* An option the chosen output does not use is refused (status 2, one line
 * naming the option and its value), never silently ignored, and no file is
 * written. (--tag-size with a PGM image, --hole-diameter with an image and
 * --tab-width with a back plate once gave files byte-identical to the
 * defaults; --list-tabs --out FILE printed to stdout and made no file.) */
static void test_unused_options_refused(void)
{
    static const refused_t bad[] = {
        {"--id 3 --tag-size 2.5", "--tag-size", "2.5"},
        {"--ids 0-3 --sheet --tag-size 0.05", "--tag-size", "0.05"},
        {"--id 3 --hole-diameter 9", "--hole-diameter", "9"},
        {"--id 3 --format svg --hole-diameter 9", "--hole-diameter", "9"},
        {"--id 3 --screw-holes corners", "--screw-holes", "corners"},
        {"--id 3 --back-plate --tab-width 5", "--tab-width", "5"},
        {"--id 3 --back-plate --format svg --tab-width 0", "--tab-width", "0"},
        {"--id 3 --format svg --tab-width 5", "--tab-width", "5"},
        {"--id 3 --cut --screw-holes none --hole-diameter 5", "--hole-diameter", "5"},
        {"--id 3 --format svg --cell-px 50", "--cell-px", "50"},
        {"--id 3 --cut --cell-px 50", "--cell-px", "50"},
        {"--id 3 --cut --margin-colour foam", "--margin-colour", "foam"},
        {"--id 3 --back-plate --margin-colour metal", "--margin-colour", "metal"},
        {"--id 3 --margin-cells 0 --margin-colour foam", "--margin-colour", "foam"},
        {"--ids 0-3 --sheet --gap 3", "--gap", "3"},
        {"--ids 0-3 --sheet --page-width 300", "--page-width", "300"},
        {"--all --list-tabs", "--list-tabs", "--out"}, /* check_refused appends --out FILE */
        {"--all --list-tabs --format svg", "--list-tabs", "--format"},
        {"--all --list-tabs --back-plate", "--list-tabs", "--back-plate"},
        {"--all --list-tabs --tab-width 3", "--list-tabs", "--tab-width"},
        {NULL, NULL, NULL}};
    char args[2048];
    check_refused("AcTag24h10", bad, "unused.out");
    /* --list-tabs --out-dir: refused before the folder is made */
    snprintf(args, sizeof args, "rm -rf '%s/unused-dir'", dir);
    TEST_ASSERT_EQUAL_INT(0, system(args));
    snprintf(args, sizeof args, "--family AcTag24h10 --all --list-tabs --out-dir '%s/unused-dir'",
             dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, run(args), errtext);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(errtext, "--out-dir"), errtext);
    TEST_ASSERT_FALSE(file_exists("unused-dir"));

    /* where they apply, the same options are taken: --list-tabs with --cut
     * (face plates are what it is about) lists the same, --hole-diameter
     * sizes the back plate's holes, --margin-colour an image's margin */
    {
        char *plain, *cut;
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, run("--family AcTag24h10 --all --list-tabs"), errtext);
        plain = slurp("stdout.bin", NULL);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, run("--family AcTag24h10 --all --list-tabs --cut"), errtext);
        cut = slurp("stdout.bin", NULL);
        TEST_ASSERT_NOT_NULL(plain);
        TEST_ASSERT_NOT_NULL(cut);
        TEST_ASSERT_TRUE(strlen(plain) > 0);
        TEST_ASSERT_EQUAL_STRING(plain, cut);
        free(plain);
        free(cut);
    }
    snprintf(args, sizeof args,
             "--family AcTag24h10 --id 3 --back-plate --hole-diameter 5 --out '%s/unused-b.dxf'", dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
    {
        dxf_t d;
        int h;
        TEST_ASSERT_NULL(check_dxf("unused-b.dxf", &d));
        TEST_ASSERT_EQUAL_INT(4, d.ncircles);
        for (h = 0; h < d.ncircles; h++)
            TEST_ASSERT_FLOAT_WITHIN(1e-6f, 2.5f, (float)d.cr[h]);
        free_dxf(&d);
    }
    snprintf(args, sizeof args,
             "--family AcTag24h10 --id 3 --format svg --tag-size 0.05 --margin-colour foam "
             "--out '%s/unused-i.svg'", dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
    TEST_ASSERT_TRUE(file_exists("unused-i.svg"));
}

/* A refused value is named with the option (one line, status 2): the
 * --tab-width message once left the value out, and numbers written as
 * hexadecimal, with leading whitespace or a '+' sign were taken
 * (--format svg --tag-size 0x1p-3 drew a 0.125 m tag, --ids ' 1' tag 1). */
static void test_bad_values_named(void)
{
    static const refused_t bad[] = {
        {"--id 1 --cut --tab-width 0.001", "--tab-width", "(got 0.001)"},
        {"--id 1 --format svg --tag-size 0x1p-3", "--tag-size", "'0x1p-3'"},
        {"--id 1 --format svg --tag-size ' 0.05'", "--tag-size", "' 0.05'"},
        {"--id 1 --format svg --tag-size +0.05", "--tag-size", "'+0.05'"},
        {"--ids ' 1'", "--ids", "' 1'"},
        {"--ids '1,+2'", "--ids", "'+2'"},
        {"--id +1", "--id", "'+1'"},
        {"--id 1 --cell-px ' 8'", "--cell-px", "' 8'"},
        /* an ID given twice (a sheet drew it twice, --out-dir wrote its file twice) */
        {"--ids 1,1 --sheet", "--ids", "ID 1 given twice in '1,1'"},
        {"--ids 0-2,1 --sheet", "--ids", "ID 1 given twice in '0-2,1'"},
        {NULL, NULL, NULL}};
    char args[2048];
    check_refused("AcTag24h4", bad, "badval.out");
    snprintf(args, sizeof args, "--family AcTag24h4 --ids 2,3,2 --out-dir '%s/dup_ids'", dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, run(args), errtext);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(errtext, "--ids: ID 2 given twice"), errtext);
    TEST_ASSERT_FALSE(file_exists("dup_ids/AcTag24h4-3.pgm"));
    /* the ordinary forms are taken */
    snprintf(args, sizeof args,
             "--family AcTag24h4 --id 1 --format svg --tag-size .05 --out '%s/badval.svg'", dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
    snprintf(args, sizeof args,
             "--family AcTag24h4 --id 1 --cut --tab-width 0.01 --out '%s/badval.dxf'", dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
}

/* run() under a file-size limit of `blocks` 512-byte blocks (POSIX sh
 * ulimit -f) with SIGXFSZ ignored, so that a write past the limit fails
 * with an error (EFBIG) instead of killing the tool. */
static int run_limited(int blocks, const char *args)
{
    char cmd[8192], errf[1200], outf[1200];
    char *e;
    int st;
    path_of(errf, sizeof errf, "stderr.txt");
    path_of(outf, sizeof outf, "stdout.bin");
    snprintf(cmd, sizeof cmd, "(trap '' XFSZ; ulimit -f %d && exec '%s' %s) > '%s' 2> '%s'",
             blocks, ACTAG_RENDER_PATH, args, outf, errf);
    st = hostio_run(cmd, NULL);
    errtext[0] = '\0';
    e = (char *)hostio_slurp(errf, NULL, NULL);
    if (e) {
        snprintf(errtext, sizeof errtext, "%s", e);
        free(e);
    }
    return st;
}

/* A write that fails leaves no file: the tool exits with status 2 and
 * removes what it had written (a 1800 x 1800 PGM under a 100 KB limit was
 * once left truncated). PGM images (written by tools/hostio), SVG and DXF
 * (written here), a sheet page; a file that existed before is not left
 * truncated either. Paths that cannot be opened make no file at all. */
static void test_failed_write_leaves_no_file(void)
{
    static const struct {
        const char *args, *name;
        int blocks;
    } cases[] = {
        {"--family AcTag24h10 --id 3 --cell-px 200", "big.pgm", 200},
        {"--family AcTag24h4 --id 6000 --format svg", "big.svg", 1},
        {"--family AcTag24h4 --id 6000 --cut", "big.dxf", 1},
        {"--family AcTag24h4 --id 6000 --back-plate --format svg", "big-back.svg", 1},
        {"--family AcTag24h10 --ids 0-5 --sheet --cell-px 20", "big-sheet.pgm", 20},
        {NULL, NULL, 0}};
    char args[2048], p[1200], msg[1200], sh[2200];
    int i;
    for (i = 0; cases[i].args; i++) {
        FILE *f;
        int st;
        /* an older file of that name: opened, truncated, then removed */
        path_of(p, sizeof p, cases[i].name);
        f = fopen(p, "w");
        TEST_ASSERT_NOT_NULL(f);
        fputs("older\n", f);
        fclose(f);
        snprintf(args, sizeof args, "%s --out '%s'", cases[i].args, p);
        st = run_limited(cases[i].blocks, args);
        snprintf(msg, sizeof msg, "'%.600s' under ulimit -f %d: status %d, stderr '%.400s'", args,
                 cases[i].blocks, st, errtext);
        TEST_ASSERT_EQUAL_INT_MESSAGE(2, st, msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(1, count_lines(errtext), msg);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(errtext, cases[i].name), msg);
        TEST_ASSERT_FALSE_MESSAGE(file_exists(cases[i].name), msg);
        /* with room for it the same command writes the file: the limit was
         * what failed */
        st = run_limited(1 << 20, args);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, st, errtext);
        TEST_ASSERT_TRUE_MESSAGE(file_exists(cases[i].name), args);
        remove(p);
    }
    /* --out-dir: the first file fails, is removed, and the tool stops */
    snprintf(sh, sizeof sh, "rm -rf '%s/limited' && mkdir '%s/limited'", dir, dir);
    TEST_ASSERT_EQUAL_INT(0, system(sh));
    snprintf(args, sizeof args, "--family AcTag24h10 --ids 1,2 --cut --out-dir '%s/limited'", dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, run_limited(1, args), errtext);
    TEST_ASSERT_FALSE(file_exists("limited/AcTag24h10-1-face.dxf"));
    TEST_ASSERT_FALSE(file_exists("limited/AcTag24h10-2-face.dxf"));

    /* places that cannot be written: a missing folder, a path under a
     * regular file (never creatable) */
    snprintf(args, sizeof args, "--family AcTag24h10 --id 3 --out '%s/no-such-dir/x.pgm'", dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, run(args), errtext);
    TEST_ASSERT_EQUAL_INT(1, count_lines(errtext));
    TEST_ASSERT_FALSE(file_exists("no-such-dir/x.pgm"));
    TEST_ASSERT_FALSE(file_exists("no-such-dir"));
    path_of(p, sizeof p, "plain-file");
    {
        FILE *f = fopen(p, "w");
        TEST_ASSERT_NOT_NULL(f);
        fclose(f);
    }
    snprintf(args, sizeof args, "--family AcTag24h10 --id 3 --cut --out '%s/x.dxf'", p);
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, run(args), errtext);
    TEST_ASSERT_EQUAL_INT(1, count_lines(errtext));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(errtext, "plain-file/x.dxf"), errtext);
}

static void test_dxf_checker_rejects(void)
{
    /* The checker must be able to fail. */
    static const char *const bad[] = {
        "  0\nSECTION\n  2\nENTITIES\n  0\nENDSEC\n",                                /* no EOF */
        "  0\nSECTION\n  2\nENTITIES\n  0\nLWPOLYLINE\n  8\n0\n  0\nENDSEC\n  0\nEOF\n", /* R14 */
        "  0\nSECTION\n  2\nENTITIES\nx\n  0\nENDSEC\n  0\nEOF\n",                     /* pairs */
        NULL};
    int i;
    for (i = 0; bad[i]; i++) {
        char p[1200];
        FILE *f;
        dxf_t d;
        path_of(p, sizeof p, "bad.dxf");
        f = fopen(p, "w");
        TEST_ASSERT_NOT_NULL(f);
        fputs(bad[i], f);
        fclose(f);
        TEST_ASSERT_NOT_NULL(check_dxf("bad.dxf", &d));
        free_dxf(&d);
    }
}

/* Every actag-render command in the README, run as written (in a scratch
 * folder), writes exactly the files the command names: --out FILE makes
 * FILE (a sheet that fits one page is not renamed), --out-dir DIR makes
 * the folder and fills it. */
static void test_readme_commands_write_what_they_say(void)
{
    char *readme = (char *)hostio_slurp(ACTAG_SOURCE_DIR "/README.md", NULL, NULL), *line;
    const char *prefix = "    build/tools/render/actag-render ";
    int ncmd = 0;
    char clean[2200];
    TEST_ASSERT_NOT_NULL(readme);
    snprintf(clean, sizeof clean, "rm -rf '%s/readme' && mkdir -p '%s/readme'", dir, dir);
    TEST_ASSERT_EQUAL_INT(0, system(clean));
    for (line = strstr(readme, prefix); line; line = strstr(line + 1, prefix)) {
        char args[400], cmd[8192], name[128], msg[1200];
        const char *a = line + strlen(prefix), *o;
        size_t n = strcspn(a, "\n");
        int st;
        snprintf(args, sizeof args, "%.*s", (int)(n < 390 ? n : 390), a);
        snprintf(cmd, sizeof cmd, "cd '%s/readme' && '%s' %s 2>/dev/null", dir,
                 ACTAG_RENDER_PATH, args);
        st = system(cmd);
        snprintf(msg, sizeof msg, "README command failed: %s", args);
        TEST_ASSERT_TRUE_MESSAGE(st != -1 && WIFEXITED(st) && WEXITSTATUS(st) == 0, msg);
        if ((o = strstr(args, "--out ")) != NULL) {
            size_t l = strcspn(o + 6, " ");
            snprintf(name, sizeof name, "readme/%.*s", (int)(l < 100 ? l : 100), o + 6);
            snprintf(msg, sizeof msg, "'%s' did not write %s", args, name + 7);
            TEST_ASSERT_TRUE_MESSAGE(file_exists(name), msg);
            if (strstr(args, "--sheet")) { /* one page: no NAME-p1 beside NAME */
                char *dot = strrchr(name, '.');
                char p1[160];
                snprintf(p1, sizeof p1, "%.*s-p1%s", (int)(dot - name), name, dot);
                snprintf(msg, sizeof msg, "'%s' wrote %s, not %s", args, p1 + 7, name + 7);
                TEST_ASSERT_FALSE_MESSAGE(file_exists(p1), msg);
            }
        } else if ((o = strstr(args, "--out-dir ")) != NULL) {
            char p[1400];
            size_t l = strcspn(o + 10, " ");
            snprintf(name, sizeof name, "readme/%.*s", (int)(l < 100 ? l : 100), o + 10);
            path_of(p, sizeof p, name);
            snprintf(cmd, sizeof cmd, "test -n \"$(ls -A '%s')\"", p);
            snprintf(msg, sizeof msg, "'%s' left %s empty", args, name + 7);
            TEST_ASSERT_EQUAL_INT_MESSAGE(0, system(cmd), msg);
        }
        ncmd++;
    }
    TEST_ASSERT_TRUE(ncmd >= 5);
    free(readme);
}

/* A multi-page sheet names its pages on stderr; --out-dir creates nested
 * folders; --version prints the project version. */
static void test_pages_folders_version(void)
{
    char args[2048], p[1200];
    snprintf(args, sizeof args,
             "--family AcTag24h10 --all --sheet --format svg --tag-size 0.03 --out '%s/pages.svg'", dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
    TEST_ASSERT_TRUE(file_exists("pages-p1.svg"));
    TEST_ASSERT_TRUE(file_exists("pages-p2.svg"));
    TEST_ASSERT_FALSE(file_exists("pages.svg"));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(errtext, "the sheet needs 2 pages: "), errtext);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(errtext, "pages-p1.svg .. -p2.svg"), errtext);
    path_of(p, sizeof p, "new/a/b");
    snprintf(args, sizeof args, "rm -rf '%s/new'", dir);
    TEST_ASSERT_EQUAL_INT(0, system(args));
    snprintf(args, sizeof args, "--family AcTag24h10 --ids 1,2 --cut --out-dir '%s'", p);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
    TEST_ASSERT_TRUE(file_exists("new/a/b/AcTag24h10-1-face.dxf"));
    TEST_ASSERT_TRUE(file_exists("new/a/b/AcTag24h10-2-face.dxf"));
    /* a file where the folder should be: one line, status 2 */
    path_of(p, sizeof p, "new/a/b/AcTag24h10-1-face.dxf");
    snprintf(args, sizeof args, "--family AcTag24h10 --ids 1,2 --cut --out-dir '%s'", p);
    TEST_ASSERT_EQUAL_INT(2, run(args));
    TEST_ASSERT_EQUAL_INT(1, count_lines(errtext));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(errtext, "actag-render: --out-dir: "), errtext);
    TEST_ASSERT_EQUAL_INT(0, run("--version"));
    path_of(p, sizeof p, "stdout.bin");
    {
        char *v = (char *)hostio_slurp(p, NULL, NULL);
        TEST_ASSERT_NOT_NULL(v);
        TEST_ASSERT_EQUAL_STRING("actag-render " ACTAG_VERSION_STRING "\n", v);
        free(v);
    }
}

/* The PGM sheet labels ("AcTag24m4 ID 0") use the tool's own 5x7 font:
 * every built-in family's name must be spelled (the m families' 'm' was
 * drawn as a box). */
static void test_every_family_name_is_spelled(void)
{
    int i;
    for (i = 0; i < actag_family_count(); i++) {
        actag_family f;
        char args[1400];
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get_at(i, &f));
        snprintf(args, sizeof args,
                 "--family %s --ids 0 --sheet --columns 1 --rows 1 --cell-px 8 --out '%s/lab.pgm'",
                 f.name, dir);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(args), errtext);
        TEST_ASSERT_NULL_MESSAGE(strstr(errtext, "no glyph"), errtext);
    }
}

/* --out - is standard output, as no --out is (it wrote a file named "-"). */
static void test_out_dash_is_stdout(void)
{
    size_t n = 0;
    char *o;
    FILE *f;
    remove("./-");
    TEST_ASSERT_EQUAL_INT(0, run("--family AcTag24h10 --id 3 --out -"));
    o = slurp("stdout.bin", &n);
    TEST_ASSERT_NOT_NULL(o);
    TEST_ASSERT_TRUE(n > 2 && o[0] == 'P' && o[1] == '5');
    free(o);
    f = fopen("./-", "rb");
    TEST_ASSERT_NULL_MESSAGE(f, "--out - wrote a file named '-'");
    if (f)
        fclose(f);
    /* still one output: --out - with --out-dir is refused as --out FILE is */
    TEST_ASSERT_EQUAL_INT(2, run("--family AcTag24h10 --id 3 --out - --out-dir od"));
    TEST_ASSERT_NOT_NULL(strstr(errtext, "not both"));
}

/* An --out name whose extension (.pgm, .svg, .dxf) is another format's than
 * the output's is refused: status 2, one line naming the file, the format and
 * how to choose it, and no file ("--out a.dxf" and "--out a.svg" wrote a PGM
 * image under those names, status 0). Matching names, in any case, other
 * extensions and none are written as before. */
static void test_out_extension_matches_format(void)
{
    static const refused_t as_dxf[] = {
        {"--id 1", "/a.dxf': the extension .dxf does not match the output format pgm",
         "--format dxf"},
        {"--id 1 --format svg", "does not match the output format svg (--format svg)",
         "--format dxf"},
        {"--id 1 --cut --format svg", "a.dxf", "name the file .svg"},
        {NULL, NULL, NULL}};
    static const refused_t as_svg[] = {
        {"--id 1", "/a.svg': the extension .svg does not match the output format pgm",
         "--format svg"},
        {"--id 1 --cut", "does not match the output format dxf (the default for cut files)",
         "--format svg"},
        {"--id 1 --back-plate", "a.svg", "--format svg"},
        {"--ids 0-2 --sheet", "a.svg", "--format svg"},
        {NULL, NULL, NULL}};
    static const refused_t as_pgm[] = {
        {"--id 1 --format svg", "a.pgm", "--format pgm"},
        {"--id 1 --format dxf", "a.pgm", "--format pgm"},
        {"--id 1 --cut", "a.pgm", "PGM is for images, not cut files (--cut)"},
        {"--id 1 --back-plate --format svg", "a.pgm", "not cut files (--back-plate)"},
        {NULL, NULL, NULL}};
    static const struct {
        const char *args, *out, *magic;
    } ok[] = {{"--id 1", "ok.pgm", "P5"},
              {"--id 1", "ok.PGM", "P5"},
              {"--id 1", "ok.png", "P5"}, /* not a known format: written as given */
              {"--id 1", "ok", "P5"},
              {"--id 1 --format svg", "ok.svg", "<?xml"},
              {"--id 1 --cut", "ok.DXF", "999\n"},
              {"--id 1 --cut --format svg", "ok.Svg", "<?xml"},
              {NULL, NULL, NULL}};
    int i;
    check_refused("AcTag24h10", as_dxf, "a.dxf");
    check_refused("AcTag24h10", as_svg, "a.svg");
    check_refused("AcTag24h10", as_pgm, "a.pgm");
    for (i = 0; ok[i].args; i++) {
        char args[1200], msg[2000];
        char *f;
        size_t n = 0;
        int st;
        path_of(msg, sizeof msg, ok[i].out);
        remove(msg);
        snprintf(args, sizeof args, "--family AcTag24h10 %s --out '%s/%s'", ok[i].args, dir,
                 ok[i].out);
        st = run(args);
        snprintf(msg, sizeof msg, "args '%s': stderr '%.400s'", args, errtext);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, st, msg);
        f = slurp(ok[i].out, &n);
        TEST_ASSERT_NOT_NULL_MESSAGE(f, args);
        TEST_ASSERT_TRUE_MESSAGE(n > strlen(ok[i].magic) &&
                                     strncmp(f, ok[i].magic, strlen(ok[i].magic)) == 0,
                                 args);
        free(f);
    }
}

int main(void)
{
    snprintf(dir, sizeof dir, "%s/render_tool_test", ACTAG_BINARY_DIR);
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "cannot create %s\n", dir);
        return 1;
    }
    UNITY_BEGIN();
    RUN_TEST(test_out_dash_is_stdout);
    RUN_TEST(test_pgm_6000);
    RUN_TEST(test_dxf_6000);
    RUN_TEST(test_dxf_many_tags_and_tabs);
    RUN_TEST(test_list_tabs_all_families);
    RUN_TEST(test_svg);
    RUN_TEST(test_sheets);
    RUN_TEST(test_errors);
    RUN_TEST(test_every_family_name_is_spelled);
    RUN_TEST(test_unused_options_refused);
    RUN_TEST(test_bad_values_named);
    RUN_TEST(test_failed_write_leaves_no_file);
    RUN_TEST(test_dxf_checker_rejects);
    RUN_TEST(test_readme_commands_write_what_they_say);
    RUN_TEST(test_pages_folders_version);
    RUN_TEST(test_out_extension_matches_format);
    return UNITY_END();
}
