/*
 * actag-render -- images and manufacturing files for AcTags.
 *
 *   actag-render --family NAME (--id N | --ids LIST | --all) [options]
 *
 * Modes
 *   (default)      image of the tag: PGM (pixels) or SVG (millimetres), in
 *                  layout colours (foam white, aluminium black: what a sonar
 *                  sees) or, with --camera, inverted (what a camera sees).
 *   --cut          cut file for the aluminium face plate: DXF (AutoCAD R12,
 *                  millimetres) or SVG (millimetres). Layers: OUTLINE (plate
 *                  outline, with notches where white data bits reach the
 *                  edge), CUTOUT (windows where the foam shows), HOLES (screw
 *                  holes), TAB (DXF only: a POINT at each corner tab, nothing
 *                  to cut), LABEL (sheets only: TEXT naming each plate).
 *   --back-plate   cut file for the plain back plate (outline and screw holes).
 *   --list-tabs    print which selected IDs need corner tabs ("ID TL,BR").
 *   --sheet        several tags per page (images or cut files), each labelled.
 *
 * Host tool: uses stdio and malloc. Errors: one line on stderr, exit status 2
 * (an option the chosen output does not use is an error too, never silently
 * ignored); a file whose writing fails is removed again, not left half
 * written. Run with --help for the options.
 */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "actag/family.h"
#include "actag/render.h"
#include "actag/version.h"
#include "hostio.h"

#define DEFAULT_TAG_SIZE_M 0.130628571 /* 3/7 ft: inner white square of a 1 ft 24-bit tag */
#define DEFAULT_CELL_PX 20
#define DEFAULT_HOLE_MM 3.4 /* clearance for M3 screws */
#define MAX_HOLES 64
#define MAX_PGM_PIXELS 400000000.0

enum { FMT_NONE, FMT_PGM, FMT_SVG, FMT_DXF };
enum { MODE_IMAGE, MODE_FACE, MODE_BACK };
enum { HOLES_CORNERS, HOLES_NONE, HOLES_LIST };

typedef struct {
    const char *family_name;
    actag_family fam;
    int *ids;
    int nids;
    int format, mode, camera;
    int cell_px;
    double margin_cells;
    int margin_set, margin_foam;
    double tag_size_m;
    int holes_mode;
    double hole_xy[2 * MAX_HOLES];
    int nhole_list;
    double hole_d, tab_w;
    int tab_set, hole_d_set, cell_px_set, tag_size_set;
    const char *margin_colour; /* the --margin-colour value, NULL when not given */
    int sheet, columns, rows;
    double page_w, page_h, gap;
    int page_set, gap_set;
    int list_tabs;
    const char *out, *out_dir;
    int out_given; /* --out given, "-" (standard output) included */
} opts_t;

typedef struct {
    double x, y;
} pt2;

typedef struct {
    pt2 *v;
    int n;
    double area; /* > 0: outer boundary of metal; < 0: a window in it */
} loop_t;

typedef struct {
    loop_t *loops;
    int nloops, pieces;
    pt2 holes[MAX_HOLES];
    int nholes;
    double hole_r;
    pt2 tabs[4];
    int ntabs;
    double size; /* side of the square plate or image, mm */
} plate_t;

/* ------------------------------------------------------------------ errors */

/* The output being written (open_out .. close_out): die() abandons it, so
 * that a failed write leaves no truncated file behind (hostio_out: a device
 * such as /dev/null or a link is never removed; files of a run that were
 * finished before the error stay). */
static hostio_out g_out;

static void die(const char *fmt, ...)
{
    va_list ap;
    fputs("actag-render: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    hostio_out_abandon(&g_out);
    exit(2);
}

static void *xmalloc(size_t n)
{
    void *p = malloc(n ? n : 1);
    if (p == NULL)
        die("out of memory");
    return p;
}

static void usage(FILE *f)
{
    fputs(
        "usage: actag-render --family NAME (--id N | --ids LIST | --all) [options]\n"
        "  LIST: IDs and ranges separated by commas, e.g. 0,3,5-9\n"
        "\n"
        "what to make\n"
        "  --format pgm|svg|dxf   output format (default pgm; dxf implies --cut)\n"
        "  --camera               image as a camera sees it (inverted colours)\n"
        "  --cut                  face plate cut file (dxf by default, or svg)\n"
        "  --back-plate           back plate cut file (outline and screw holes)\n"
        "size\n"
        "  --cell-px N            pixels per cell in PGM images (default 20; PGM only)\n"
        "  --tag-size M           side of the inner white square in metres, for the\n"
        "                         millimetres of SVG and DXF (not PGM: --cell-px)\n"
        "                         (default 0.130628571 = 3/7 ft, a 1 ft 24-bit tag;\n"
        "                         0.0001 to 10: millimetres given as metres are refused)\n"
        "  --margin-cells X       border around the tag, in cells (default 1 for\n"
        "                         images, 0 for cut files; cut margins are metal)\n"
        "  --margin-colour metal|foam   colour of an image's border (default metal;\n"
        "                         images only: cut-file margins are metal; also spelt\n"
        "                         --margin-color, and black|white)\n"
        "plates\n"
        "  --screw-holes SPEC     corners (default: centres of the 4 corner cells of\n"
        "                         the black ring), none, or X,Y[,X,Y...] in mm from\n"
        "                         the tag's top-left corner (x right, y down)\n"
        "  --hole-diameter MM     screw hole diameter (default 3.4)\n"
        "  --tab-width MM         side of the square tab that holds an isolated\n"
        "                         black corner bit (default 0.15 cell; 0 = none;\n"
        "                         face plates only: the back plate has no tabs)\n"
        "  --list-tabs            only list the selected IDs whose face plate needs\n"
        "                         corner tabs: 'ID TL,TR,BR,BL' lines on stdout (takes\n"
        "                         no output, size or plate option; --cut is allowed)\n"
        "sheets\n"
        "  --sheet                several tags per page, each labelled\n"
        "  --columns N --rows N   tags per row / rows per page (PGM default 4 x 5;\n"
        "                         SVG/DXF default: as many as fit)\n"
        "  --page-width MM --page-height MM   SVG/DXF page (default 210 x 297)\n"
        "  --gap MM               space between tags and page margin (default 10;\n"
        "                         SVG/DXF: a PGM sheet's gap is one cell)\n"
        "output\n"
        "  --out FILE             output file (default or -: stdout). A sheet that fits one\n"
        "                         page is FILE itself; a longer one is FILE with -p1,\n"
        "                         -p2, ... before the extension (tags.svg: tags-p1.svg,\n"
        "                         tags-p2.svg, ...; the names are reported on stderr).\n"
        "                         The format is not taken from FILE: a .pgm, .svg or .dxf\n"
        "                         name must match it (--format; default pgm, dxf with\n"
        "                         --cut or --back-plate), other names are written as given\n"
        "  --out-dir DIR          one file per tag: DIR/FAMILY-ID[-face|-back].EXT,\n"
        "                         sheets DIR/FAMILY[-face|-back]-sheet-pN.EXT (DIR is\n"
        "                         created)\n"
        "  --help  --version\n",
        f);
}

/* Side of one cell in mm: tag_size is the inner white square, k-3 cells wide. */
static double cell_mm(const opts_t *o)
{
    return o->tag_size_m * 1000.0 / (double)(o->fam.bits / 4 - 3);
}

/* ------------------------------------------------------------------ parsing */

/* Whole numbers and reals with range checks (tools/hostio: the message names
 * the option and the value, exit status 2). */
static int parse_int(const char *opt, const char *s, long lo, long hi)
{
    return (int)hostio_opt_long("actag-render", opt, s, lo, hi);
}

static double parse_real(const char *opt, const char *s, double lo, double hi)
{
    return hostio_opt_double("actag-render", opt, s, lo, hi);
}

/* "0,5,10-12" -> ids (ranges inclusive). */
static void parse_ids(opts_t *o, const char *s, int ncodes)
{
    char buf[64];
    const char *p = s;
    int cap = 16;
    o->ids = (int *)xmalloc((size_t)cap * sizeof(int));
    o->nids = 0;
    while (*p) {
        size_t len = strcspn(p, ",");
        char *dash;
        int a, b, i;
        if (len == 0 || len >= sizeof buf)
            die("--ids: bad list '%s'", s);
        memcpy(buf, p, len);
        buf[len] = '\0';
        dash = strchr(buf + 1, '-');
        if (dash) {
            *dash = '\0';
            a = parse_int("--ids", buf, 0, INT_MAX);
            b = parse_int("--ids", dash + 1, 0, INT_MAX);
        } else {
            a = b = parse_int("--ids", buf, 0, INT_MAX);
        }
        if (b < a)
            die("--ids: empty range '%s'", s);
        if (b >= ncodes)
            die("--ids: ID %d out of range: %s has IDs 0..%d", b, o->family_name, ncodes - 1);
        for (i = a; i <= b; i++) {
            if (o->nids == cap) {
                int *n;
                cap *= 2;
                n = (int *)realloc(o->ids, (size_t)cap * sizeof(int));
                if (n == NULL)
                    die("out of memory");
                o->ids = n;
            }
            o->ids[o->nids++] = i;
        }
        p += len;
        if (*p == ',') {
            p++;
            if (*p == '\0')
                die("--ids: bad list '%s'", s);
        }
    }
    if (o->nids == 0)
        die("--ids: empty list");
    {
        /* an ID given twice wrote its file twice (--out-dir) or printed it
         * twice: refused, naming it */
        unsigned char *seen = (unsigned char *)xmalloc((size_t)ncodes);
        int k;
        memset(seen, 0, (size_t)ncodes);
        for (k = 0; k < o->nids; k++) {
            if (seen[o->ids[k]])
                die("--ids: ID %d given twice in '%s'", o->ids[k], s);
            seen[o->ids[k]] = 1;
        }
        free(seen);
    }
}

static void parse_holes(opts_t *o, const char *s)
{
    const char *p = s;
    if (strcmp(s, "corners") == 0) {
        o->holes_mode = HOLES_CORNERS;
        return;
    }
    if (strcmp(s, "none") == 0) {
        o->holes_mode = HOLES_NONE;
        return;
    }
    o->holes_mode = HOLES_LIST;
    o->nhole_list = 0;
    while (*p) {
        char buf[64];
        size_t len = strcspn(p, ",;");
        if (len == 0 || len >= sizeof buf || o->nhole_list >= 2 * MAX_HOLES)
            die("--screw-holes: expected corners, none or X,Y[,X,Y...] in mm, got '%s'", s);
        memcpy(buf, p, len);
        buf[len] = '\0';
        o->hole_xy[o->nhole_list++] = parse_real("--screw-holes", buf, -1e6, 1e6);
        p += len;
        if (*p && *++p == '\0') /* a separator must be followed by a number */
            die("--screw-holes: expected pairs X,Y in mm, got '%s'", s);
    }
    if (o->nhole_list == 0 || o->nhole_list % 2 != 0)
        die("--screw-holes: expected pairs X,Y in mm, got '%s'", s);
}

/* Options are parsed before any output is open: hostio's helpers (exit
 * status 2, the message every host tool gives) need no clean-up. */
static const char *need_arg(int argc, char **argv, int *i)
{
    return hostio_opt_value("actag-render", argc, argv, i);
}

/* A format's file extension (without the dot). */
static const char *ext_of(int format)
{
    return format == FMT_PGM ? "pgm" : format == FMT_SVG ? "svg" : "dxf";
}

/* The format a file name's extension says (.pgm, .svg or .dxf, in any case);
 * FMT_NONE for another extension or none. */
static int format_of_name(const char *path, const char **ext)
{
    const char *base = strrchr(path, '/'), *dot;
    int f, j;
    base = base ? base + 1 : path;
    dot = strrchr(base, '.');
    *ext = dot ? dot + 1 : "";
    if (dot == NULL || dot == base || strlen(dot + 1) != 3)
        return FMT_NONE;
    for (f = FMT_PGM; f <= FMT_DXF; f++) {
        for (j = 0; j < 3; j++)
            if (tolower((unsigned char)dot[1 + j]) != ext_of(f)[j])
                break;
        if (j == 3)
            return f;
    }
    return FMT_NONE;
}

/* An --out name whose extension is another known format's than the output's
 * is refused: "--out a.dxf" (no --format) wrote a PGM image into a.dxf. A
 * name with another extension, or none, is written as given. */
static void check_out_name(const opts_t *o, const char *fmt, int cut, int back)
{
    const char *ext, *have = ext_of(o->format);
    char chosen[64];
    int says;
    if (o->out == NULL) /* standard output */
        return;
    says = format_of_name(o->out, &ext);
    if (says == FMT_NONE || says == o->format)
        return;
    if (fmt)
        snprintf(chosen, sizeof chosen, "--format %s", have);
    else
        snprintf(chosen, sizeof chosen, "the default for %s", o->mode == MODE_IMAGE ? "images"
                                                                : "cut files");
    if (says == FMT_PGM && (cut || back))
        die("--out '%s': the extension .%s does not match the output format %s (%s); PGM is "
            "for images, not cut files (%s): name the file .%s, or .svg with --format svg",
            o->out, ext, have, chosen, cut ? "--cut" : "--back-plate", have);
    die("--out '%s': the extension .%s does not match the output format %s (%s); choose the "
        "format with --format %s, or name the file .%s", o->out, ext, have, chosen,
        ext_of(says), have);
}

static void parse_args(int argc, char **argv, opts_t *o)
{
    const char *ids_arg = NULL, *fmt = NULL, *holes = NULL;
    const char *shaping = NULL; /* the first option that shapes a file (not --list-tabs') */
    int i, have_id = 0, all = 0, id = 0, cut = 0, back = 0, nseen = 0;
    const char *seen[64]; /* the options given so far */
    memset(o, 0, sizeof *o);
    o->cell_px = DEFAULT_CELL_PX;
    o->tag_size_m = DEFAULT_TAG_SIZE_M;
    o->hole_d = DEFAULT_HOLE_MM;
    o->page_w = 210.0;
    o->page_h = 297.0;
    o->gap = 10.0;
    if (argc < 2)
        die("no arguments (try --help)");
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        /* an option given twice is refused, not the last one kept: "--id 0
         * --id 5 --cut" cut plate 5 without a word */
        if (strncmp(a, "--", 2) == 0) {
            const char *canon = strcmp(a, "--margin-color") == 0 ? "--margin-colour" : a;
            int k;
            for (k = 0; k < nseen; k++)
                if (strcmp(seen[k], canon) == 0)
                    die("%s given twice: give it once", a);
            if (nseen < (int)(sizeof seen / sizeof seen[0]))
                seen[nseen++] = canon;
        }
        if (shaping == NULL && strncmp(a, "--", 2) == 0 && strcmp(a, "--family") != 0 &&
            strcmp(a, "--id") != 0 && strcmp(a, "--ids") != 0 && strcmp(a, "--all") != 0 &&
            strcmp(a, "--cut") != 0 && strcmp(a, "--list-tabs") != 0)
            shaping = a;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            exit(0);
        } else if (strcmp(a, "--version") == 0) {
            printf("actag-render %s\n", ACTAG_VERSION_STRING);
            exit(0);
        } else if (strcmp(a, "--family") == 0) {
            o->family_name = need_arg(argc, argv, &i);
        } else if (strcmp(a, "--id") == 0) {
            id = parse_int("--id", need_arg(argc, argv, &i), 0, INT_MAX);
            have_id = 1;
        } else if (strcmp(a, "--ids") == 0) {
            ids_arg = need_arg(argc, argv, &i);
        } else if (strcmp(a, "--all") == 0) {
            all = 1;
        } else if (strcmp(a, "--format") == 0) {
            fmt = need_arg(argc, argv, &i);
        } else if (strcmp(a, "--camera") == 0) {
            o->camera = 1;
        } else if (strcmp(a, "--cut") == 0) {
            cut = 1;
        } else if (strcmp(a, "--back-plate") == 0) {
            back = 1;
        } else if (strcmp(a, "--cell-px") == 0) {
            o->cell_px = parse_int(a, need_arg(argc, argv, &i), 1, 4096);
            o->cell_px_set = 1;
        } else if (strcmp(a, "--margin-cells") == 0) {
            o->margin_cells = parse_real(a, need_arg(argc, argv, &i), 0.0, 100.0);
            o->margin_set = 1;
        } else if (strcmp(a, "--margin-colour") == 0 || strcmp(a, "--margin-color") == 0) {
            const char *v = need_arg(argc, argv, &i);
            o->margin_colour = v;
            if (strcmp(v, "metal") == 0 || strcmp(v, "black") == 0)
                o->margin_foam = 0;
            else if (strcmp(v, "foam") == 0 || strcmp(v, "white") == 0)
                o->margin_foam = 1;
            else
                die("%s: expected metal or foam, got '%s'", a, v);
        } else if (strcmp(a, "--tag-size") == 0) {
            /* at most 10 m: "--tag-size 90" meant as millimetres drew a 210 m plate */
            o->tag_size_m = parse_real(a, need_arg(argc, argv, &i), 1e-4, 10.0);
            o->tag_size_set = 1;
        } else if (strcmp(a, "--screw-holes") == 0) {
            holes = need_arg(argc, argv, &i);
        } else if (strcmp(a, "--hole-diameter") == 0) {
            o->hole_d = parse_real(a, need_arg(argc, argv, &i), 0.01, 1e5);
            o->hole_d_set = 1;
        } else if (strcmp(a, "--tab-width") == 0) {
            const char *v = need_arg(argc, argv, &i);
            o->tab_w = parse_real(a, v, 0.0, 1e5);
            if (o->tab_w > 0.0 && o->tab_w < 0.01)
                die("--tab-width: use 0 (no tabs) or at least 0.01 mm (got %.40s)", v);
            o->tab_set = 1;
        } else if (strcmp(a, "--list-tabs") == 0) {
            o->list_tabs = 1;
        } else if (strcmp(a, "--sheet") == 0) {
            o->sheet = 1;
        } else if (strcmp(a, "--columns") == 0) {
            o->columns = parse_int(a, need_arg(argc, argv, &i), 1, 10000);
        } else if (strcmp(a, "--rows") == 0) {
            o->rows = parse_int(a, need_arg(argc, argv, &i), 1, 10000);
        } else if (strcmp(a, "--page-width") == 0) {
            o->page_w = parse_real(a, need_arg(argc, argv, &i), 1.0, 1e6);
            o->page_set = 1;
        } else if (strcmp(a, "--page-height") == 0) {
            o->page_h = parse_real(a, need_arg(argc, argv, &i), 1.0, 1e6);
            o->page_set = 1;
        } else if (strcmp(a, "--gap") == 0) {
            o->gap = parse_real(a, need_arg(argc, argv, &i), 0.0, 1e5);
            o->gap_set = 1;
        } else if (strcmp(a, "--out") == 0) {
            o->out = need_arg(argc, argv, &i);
            o->out_given = 1;
            if (strcmp(o->out, "-") == 0) /* standard output, as without --out */
                o->out = NULL;
        } else if (strcmp(a, "--out-dir") == 0) {
            o->out_dir = need_arg(argc, argv, &i);
        } else {
            hostio_opt_unknown("actag-render", a);
        }
    }

    if (o->family_name == NULL)
        die("--family is required (e.g. --family AcTag24h10)");
    if (actag_family_get(o->family_name, &o->fam) != ACTAG_OK)
        die("unknown family '%s'", o->family_name);
    if (have_id + all + (ids_arg != NULL) != 1)
        die("give exactly one of --id N, --ids LIST, --all");
    if (have_id) {
        if (id >= o->fam.ncodes)
            die("--id %d out of range: %s has IDs 0..%d", id, o->family_name, o->fam.ncodes - 1);
        o->ids = (int *)xmalloc(sizeof(int));
        o->ids[0] = id;
        o->nids = 1;
    } else if (all) {
        int j;
        o->ids = (int *)xmalloc((size_t)o->fam.ncodes * sizeof(int));
        for (j = 0; j < o->fam.ncodes; j++)
            o->ids[j] = j;
        o->nids = o->fam.ncodes;
    } else {
        parse_ids(o, ids_arg, o->fam.ncodes);
    }
    if (o->list_tabs) {
        /* a list on stdout: nothing to write, size or plate */
        if (shaping)
            die("--list-tabs only prints the IDs that need corner tabs on stdout: it takes no "
                "%s", shaping);
        return;
    }

    if (cut && back)
        die("--cut and --back-plate are separate files: choose one");
    o->mode = cut ? MODE_FACE : back ? MODE_BACK : MODE_IMAGE;
    if (fmt == NULL)
        o->format = o->mode == MODE_IMAGE ? FMT_PGM : FMT_DXF;
    else if (strcmp(fmt, "pgm") == 0)
        o->format = FMT_PGM;
    else if (strcmp(fmt, "svg") == 0)
        o->format = FMT_SVG;
    else if (strcmp(fmt, "dxf") == 0)
        o->format = FMT_DXF;
    else
        die("--format: expected pgm, svg or dxf, got '%s'", fmt);
    if (o->format == FMT_DXF && o->mode == MODE_IMAGE)
        o->mode = MODE_FACE;
    if (o->format == FMT_PGM && o->mode != MODE_IMAGE)
        die("cut files are DXF or SVG, not PGM");
    if (o->camera && o->mode != MODE_IMAGE)
        die("--camera applies to images, not cut files");
    if (!o->margin_set)
        o->margin_cells = o->mode == MODE_IMAGE ? 1.0 : 0.0;
    if (!o->tab_set)
        o->tab_w = 0.15 * cell_mm(o);
    if (holes)
        parse_holes(o, holes);
    /* options the chosen output would not use are refused, not ignored */
    if (o->format == FMT_PGM && o->tag_size_set)
        die("--tag-size %g: PGM images are sized in pixels (--cell-px); --tag-size applies "
            "to SVG and DXF (millimetres)", o->tag_size_m);
    if (o->format != FMT_PGM && o->cell_px_set)
        die("--cell-px %d: applies to PGM images; %s files are sized in millimetres "
            "(--tag-size)", o->cell_px, o->format == FMT_SVG ? "SVG" : "DXF");
    if (o->mode != MODE_IMAGE && o->margin_colour)
        die("--margin-colour %s: applies to images; cut-file margins are metal",
            o->margin_colour);
    if (o->mode == MODE_IMAGE && o->margin_colour && o->margin_set && o->margin_cells == 0.0)
        die("--margin-colour %s: the image has no margin (--margin-cells 0)", o->margin_colour);
    if (o->mode == MODE_IMAGE && holes)
        die("--screw-holes %s: applies to cut files (--cut, --back-plate), not images", holes);
    if (o->mode == MODE_IMAGE && o->hole_d_set)
        die("--hole-diameter %g: applies to cut files (--cut, --back-plate), not images",
            o->hole_d);
    if (o->mode != MODE_FACE && o->tab_set)
        die("--tab-width %g: applies to face plates (--cut); %s", o->tab_w,
            o->mode == MODE_BACK ? "the back plate has no tabs" : "an image has no tabs");
    if (o->hole_d_set && o->holes_mode == HOLES_NONE)
        die("--hole-diameter %g: there are no screw holes (--screw-holes none)", o->hole_d);
    if (!o->sheet && (o->columns || o->rows || o->page_set || o->gap_set))
        die("--columns, --rows, --page-width, --page-height and --gap need --sheet");
    if (o->sheet && o->format == FMT_PGM && o->page_set)
        die("--page-width/--page-height %g x %g mm: PGM sheets are sized with --columns and "
            "--rows, not in mm", o->page_w, o->page_h);
    if (o->sheet && o->format == FMT_PGM && o->gap_set)
        die("--gap %g mm: PGM sheets are sized with --columns and --rows (the gap is one "
            "cell), not in mm", o->gap);
    if (o->out_given && o->out_dir)
        die("give --out or --out-dir, not both");
    if (!o->sheet && !o->list_tabs && o->nids > 1 && o->out_dir == NULL)
        die("several tags make several files: use --out-dir DIR (or --sheet)");
    check_out_name(o, fmt, cut, back);
}

/* ------------------------------------------------------------------ geometry */

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Sort and drop near-duplicates; returns the new count. */
static int unique_breaks(double *v, int n)
{
    int i, m = 0;
    qsort(v, (size_t)n, sizeof(double), cmp_double);
    for (i = 0; i < n; i++)
        if (m == 0 || v[i] - v[m - 1] > 1e-9)
            v[m++] = v[i];
    return m;
}

/* Boundary of the union of the marked rectangles of a rectilinear grid (nx x ny
 * rectangles between breakpoints X[0..nx], Y[0..ny], y down). Every boundary
 * edge is directed with metal on its right (clockwise on screen around metal);
 * where two metal rectangles touch only at a corner the walk turns right, so
 * such pieces stay separate (4-connected metal). Collinear vertices are
 * merged. Returns the number of loops. */
static int trace_union(const double *X, int nx, const double *Y, int ny,
                       const unsigned char *metal, loop_t **out)
{
    int nvx = nx + 1, nv = (nx + 1) * (ny + 1), ne = 0, nloops = 0, e0, i, j;
    int *outv = (int *)xmalloc((size_t)nv * 2 * sizeof(int));
    int cap = 4 * nx * ny + 4;
    int *from = (int *)xmalloc((size_t)cap * sizeof(int));
    int *to = (int *)xmalloc((size_t)cap * sizeof(int));
    unsigned char *used = (unsigned char *)xmalloc((size_t)cap);
    int *vbuf = (int *)xmalloc((size_t)cap * sizeof(int));
    loop_t *loops = (loop_t *)xmalloc((size_t)cap * sizeof(loop_t));

    for (i = 0; i < 2 * nv; i++)
        outv[i] = -1;
#define MET(a, b) ((a) >= 0 && (b) >= 0 && (a) < nx && (b) < ny && metal[(b) * nx + (a)])
#define ADD_EDGE(f, t)                                                      \
    do {                                                                    \
        from[ne] = (f);                                                     \
        to[ne] = (t);                                                       \
        used[ne] = 0;                                                       \
        if (outv[2 * (f)] < 0)                                              \
            outv[2 * (f)] = ne;                                             \
        else                                                                \
            outv[2 * (f) + 1] = ne;                                         \
        ne++;                                                               \
    } while (0)
    for (j = 0; j < ny; j++)
        for (i = 0; i < nx; i++) {
            if (!MET(i, j))
                continue;
            if (!MET(i, j - 1))
                ADD_EDGE(j * nvx + i, j * nvx + i + 1);
            if (!MET(i + 1, j))
                ADD_EDGE(j * nvx + i + 1, (j + 1) * nvx + i + 1);
            if (!MET(i, j + 1))
                ADD_EDGE((j + 1) * nvx + i + 1, (j + 1) * nvx + i);
            if (!MET(i - 1, j))
                ADD_EDGE((j + 1) * nvx + i, j * nvx + i);
        }
#undef MET
#undef ADD_EDGE

    for (e0 = 0; e0 < ne; e0++) {
        int e = e0, n = 0, k, m;
        loop_t *L;
        if (used[e0])
            continue;
        for (;;) {
            int v = to[e], a = outv[2 * v], b = outv[2 * v + 1], next;
            used[e] = 1;
            vbuf[n++] = from[e];
            if (b < 0) {
                next = a;
            } else {
                /* direction of e and of candidate a, in grid steps */
                int dx = to[e] % nvx - from[e] % nvx, dy = to[e] / nvx - from[e] / nvx;
                int ax = to[a] % nvx - from[a] % nvx, ay = to[a] / nvx - from[a] / nvx;
                next = (ax == -dy && ay == dx) ? a : b; /* right turn on screen */
            }
            if (next == e0)
                break;
            if (next < 0 || used[next])
                die("internal error: open boundary");
            e = next;
        }
        /* keep only corners */
        L = &loops[nloops++];
        L->v = (pt2 *)xmalloc((size_t)n * sizeof(pt2));
        L->n = 0;
        for (k = 0; k < n; k++) {
            int p = vbuf[(k + n - 1) % n], c = vbuf[k], q = vbuf[(k + 1) % n];
            int d1x = c % nvx - p % nvx, d1y = c / nvx - p / nvx;
            int d2x = q % nvx - c % nvx, d2y = q / nvx - c / nvx;
            if (d1x * d2y - d1y * d2x != 0) {
                L->v[L->n].x = X[c % nvx];
                L->v[L->n].y = Y[c / nvx];
                L->n++;
            }
        }
        L->area = 0.0;
        for (m = 0; m < L->n; m++) {
            const pt2 *P = &L->v[m], *Q = &L->v[(m + 1) % L->n];
            L->area += P->x * Q->y - Q->x * P->y;
        }
        L->area *= 0.5;
    }
    free(outv);
    free(from);
    free(to);
    free(used);
    free(vbuf);
    *out = loops;
    return nloops;
}

typedef struct {
    const opts_t *o;
    int id, k, mode;
    double cell, margin;
    const plate_t *p;
} region_t;

/* Is the point (x, y) (mm from the plate's top-left corner) metal? */
static int metal_at(const region_t *r, double x, double y)
{
    int gx = (int)floor((x - r->margin) / r->cell), gy = (int)floor((y - r->margin) / r->cell);
    int t;
    if (r->mode == MODE_BACK)
        return 1;
    if (gx < 0 || gy < 0 || gx > r->k || gy > r->k)
        return r->mode == MODE_FACE ? 1 : !r->o->margin_foam;
    if (actag_layout_cell(&r->o->fam, r->id, gx, gy) == 0)
        return 1;
    for (t = 0; t < r->p->ntabs; t++)
        if (fabs(x - r->p->tabs[t].x) < r->o->tab_w / 2 && fabs(y - r->p->tabs[t].y) < r->o->tab_w / 2)
            return 1;
    return 0;
}

static void free_plate(plate_t *p)
{
    int i;
    for (i = 0; i < p->nloops; i++)
        free(p->loops[i].v);
    free(p->loops);
    p->loops = NULL;
    p->nloops = 0;
}

/* Build the geometry of one tag: plate (mode face/back) or image metal region. */
static void build_plate(const opts_t *o, int id, int mode, plate_t *p)
{
    region_t r;
    int k = o->fam.bits / 4, nb = 0, nx, ny, i, j, nbx;
    double br[2 * (9 + 2) + 8 + 4];
    double *X, *Y;
    unsigned char *metal;
    char hole_err[200] = "";

    memset(p, 0, sizeof *p);
    r.o = o;
    r.id = id;
    r.k = k;
    r.mode = mode;
    r.cell = cell_mm(o);
    r.margin = o->margin_cells * r.cell;
    r.p = p;
    p->size = (double)(k + 1) * r.cell + 2.0 * r.margin;

    if (mode == MODE_FACE && o->tab_w > 0.0) {
        int mask = actag_layout_corner_tabs(&o->fam, id), c;
        if (mask < 0)
            die("internal error: %s", actag_strerror(mask));
        if (o->tab_w >= r.cell)
            die("--tab-width %g mm must be smaller than a cell (%g mm)", o->tab_w, r.cell);
        for (c = 0; c < 4; c++) {
            /* contact point of corner cell c with the black ring, in cells */
            static const int gx[4] = {1, -1, -1, 1}, gy[4] = {1, 1, -1, -1};
            if (!(mask & (1 << c)))
                continue;
            p->tabs[p->ntabs].x = r.margin + r.cell * (gx[c] > 0 ? 1.0 : (double)k);
            p->tabs[p->ntabs].y = r.margin + r.cell * (gy[c] > 0 ? 1.0 : (double)k);
            p->ntabs++;
        }
    }

    /* breakpoints: plate edges, cell lines, tab edges */
    br[nb++] = 0.0;
    br[nb++] = p->size;
    for (i = 0; i <= k + 1; i++)
        br[nb++] = r.margin + (double)i * r.cell;
    nbx = nb;
    X = (double *)xmalloc((size_t)(nb + 8) * sizeof(double));
    Y = (double *)xmalloc((size_t)(nb + 8) * sizeof(double));
    memcpy(X, br, (size_t)nbx * sizeof(double));
    memcpy(Y, br, (size_t)nbx * sizeof(double));
    nx = nbx;
    ny = nbx;
    for (i = 0; i < p->ntabs; i++) {
        X[nx++] = p->tabs[i].x - o->tab_w / 2;
        X[nx++] = p->tabs[i].x + o->tab_w / 2;
        Y[ny++] = p->tabs[i].y - o->tab_w / 2;
        Y[ny++] = p->tabs[i].y + o->tab_w / 2;
    }
    nx = unique_breaks(X, nx) - 1;
    ny = unique_breaks(Y, ny) - 1;
    metal = (unsigned char *)xmalloc((size_t)nx * (size_t)ny);
    for (j = 0; j < ny; j++)
        for (i = 0; i < nx; i++)
            metal[j * nx + i] =
                (unsigned char)metal_at(&r, 0.5 * (X[i] + X[i + 1]), 0.5 * (Y[j] + Y[j + 1]));
    p->nloops = trace_union(X, nx, Y, ny, metal, &p->loops);
    for (i = 0; i < p->nloops; i++)
        if (p->loops[i].area > 0)
            p->pieces++;

    if (mode != MODE_IMAGE) {
        p->hole_r = o->hole_d / 2;
        if (o->holes_mode == HOLES_CORNERS) {
            static const int cx[4] = {1, -1, -1, 1}, cy[4] = {1, 1, -1, -1};
            for (i = 0; i < 4; i++) {
                p->holes[i].x = r.margin + r.cell * (cx[i] > 0 ? 1.5 : (double)k - 0.5);
                p->holes[i].y = r.margin + r.cell * (cy[i] > 0 ? 1.5 : (double)k - 0.5);
            }
            p->nholes = 4;
        } else if (o->holes_mode == HOLES_LIST) {
            for (i = 0; i < o->nhole_list / 2; i++) {
                p->holes[i].x = r.margin + o->hole_xy[2 * i];
                p->holes[i].y = r.margin + o->hole_xy[2 * i + 1];
            }
            p->nholes = o->nhole_list / 2;
        }
        /* every hole must lie inside metal: clear of the plate edge and of
         * every foam rectangle */
        for (i = 0; i < p->nholes; i++) {
            double hx = p->holes[i].x, hy = p->holes[i].y, rr = p->hole_r;
            int a, b;
            if (hx - rr < 0 || hy - rr < 0 || hx + rr > p->size || hy + rr > p->size) {
                snprintf(hole_err, sizeof hole_err,
                         "screw hole %d at (%g, %g) mm does not fit on the %g mm plate", i + 1,
                         hx - r.margin, hy - r.margin, p->size);
                break;
            }
            for (b = 0; b < ny && !hole_err[0]; b++)
                for (a = 0; a < nx && !hole_err[0]; a++) {
                    double dx, dy;
                    if (metal[b * nx + a])
                        continue;
                    dx = hx < X[a] ? X[a] - hx : hx > X[a + 1] ? hx - X[a + 1] : 0.0;
                    dy = hy < Y[b] ? Y[b] - hy : hy > Y[b + 1] ? hy - Y[b + 1] : 0.0;
                    if (dx * dx + dy * dy < rr * rr)
                        snprintf(hole_err, sizeof hole_err,
                                 "screw hole %d at (%g, %g) mm (diameter %g) cuts into a foam "
                                 "window",
                                 i + 1, hx - r.margin, hy - r.margin, o->hole_d);
                }
            if (hole_err[0])
                break;
        }
    }
    /* free before any exit, so that LeakSanitizer sees a clean status 2 */
    free(X);
    free(Y);
    free(metal);
    if (hole_err[0])
        die("%s", hole_err);
}

/* ------------------------------------------------------------------ output helpers */

static const char *fnum(char *buf, double v)
{
    char *e;
    if (fabs(v) < 5e-7)
        v = 0.0;
    snprintf(buf, 40, "%.6f", v);
    e = buf + strlen(buf) - 1;
    while (*e == '0')
        *e-- = '\0';
    if (*e == '.')
        *e = '\0';
    return buf;
}

/* The output stream (stdout for a NULL path). Until close_out() a file is
 * removed again when the tool dies (g_out). */
static FILE *open_out(const char *path)
{
    if (hostio_out_open(&g_out, path, "wb", NULL) != HOSTIO_OK)
        die("cannot write '%s': %s", path, strerror(g_out.why));
    return g_out.f;
}

/* A failed close has removed the file already (hostio_out_close). */
static void close_out(void)
{
    const char *path = g_out.path;
    if (hostio_out_close(&g_out, NULL) == HOSTIO_OK)
        return;
    if (path == NULL)
        die("cannot write to stdout");
    if (g_out.why != 0)
        die("cannot write '%s': %s", path, strerror(g_out.why));
    die("cannot write '%s'", path);
}

static const char *mode_suffix(int mode)
{
    return mode == MODE_FACE ? "-face" : mode == MODE_BACK ? "-back" : "";
}

static const char *mode_name(int mode)
{
    return mode == MODE_FACE ? "face plate" : mode == MODE_BACK ? "back plate" : "image";
}

static void label_text(char *buf, size_t n, const opts_t *o, int id)
{
    snprintf(buf, n, "%s ID %d", o->fam.name, id);
}

/* ------------------------------------------------------------------ PGM */

/* 5x7 glyphs, one byte per row, bit 4 = leftmost pixel. The font's
 * characters; a character not among them is drawn as the box after the
 * last glyph. */
static const char glyph_chars[] = "0123456789ATacghID#- m";

/* Has character c a glyph of its own (not the box)? */
static int has_glyph(char c)
{
    return c != '\0' && strchr(glyph_chars, c) != NULL;
}

static const unsigned char *glyph(char c)
{
    const char *chars = glyph_chars;
    static const unsigned char g[][7] = {
        {14, 17, 19, 21, 25, 17, 14}, {4, 12, 4, 4, 4, 4, 14},    {14, 17, 1, 2, 4, 8, 31},
        {31, 2, 4, 2, 1, 17, 14},     {2, 6, 10, 18, 31, 2, 2},   {31, 16, 30, 1, 1, 17, 14},
        {6, 8, 16, 30, 17, 17, 14},   {31, 1, 2, 4, 8, 8, 8},     {14, 17, 17, 14, 17, 17, 14},
        {14, 17, 17, 15, 1, 2, 12},   {14, 17, 17, 31, 17, 17, 17}, {31, 4, 4, 4, 4, 4, 4},
        {0, 0, 14, 1, 15, 17, 15},    {0, 0, 14, 16, 16, 17, 14}, {0, 15, 17, 15, 1, 17, 14},
        {16, 16, 22, 25, 17, 17, 17}, {14, 4, 4, 4, 4, 4, 14},    {30, 17, 17, 17, 17, 17, 30},
        {10, 10, 31, 10, 31, 10, 10}, {0, 0, 0, 31, 0, 0, 0},     {0, 0, 0, 0, 0, 0, 0},
        {0, 0, 26, 21, 21, 17, 17},   {31, 17, 17, 17, 17, 17, 31}}; /* m; the box: none */
    const char *p = has_glyph(c) ? strchr(chars, c) : NULL;
    return g[p ? (size_t)(p - chars) : sizeof glyph_chars - 1];
}

/* Draws t; a character without a glyph is drawn as a box and named on
 * stderr (a label the font cannot spell is a defect of this tool). */
static void draw_text(uint8_t *img, long w, long h, long x0, long y0, int s, const char *t)
{
    const char *u;
    for (u = t; *u; u++)
        if (!has_glyph(*u))
            fprintf(stderr, "actag-render: label '%s': no glyph for '%c' (drawn as a box)\n", t, *u);
    for (; *t; t++, x0 += 6L * s) {
        const unsigned char *g = glyph(*t);
        long r, c;
        for (r = 0; r < 7L * s; r++)
            for (c = 0; c < 5L * s; c++) {
                long x = x0 + c, y = y0 + r;
                if (x >= 0 && y >= 0 && x < w && y < h && (g[r / s] >> (4 - c / s)) & 1)
                    img[y * w + x] = 0;
            }
    }
}

/* A failed write dies, and die() removes the partial file (open_out). */
static void write_pgm(FILE *f, const char *path, const uint8_t *img, long w, long h)
{
    hostio_image im;
    char err[HOSTIO_ERRLEN];
    im.data = (void *)(uintptr_t)img; /* only read */
    im.rows = (int)h;
    im.cols = (int)w;
    im.stride = (int)w;
    im.depth = 8;
    im.maxval = 255;
    if (hostio_pgm_fwrite(f, path ? path : "stdout", &im, err) != HOSTIO_OK)
        die("%s", err);
}

static int margin_px(const opts_t *o)
{
    return (int)lround(o->margin_cells * (double)o->cell_px);
}

static void render_into(const opts_t *o, int id, uint8_t *dst, long stride, int side)
{
    int rc = actag_render_tag(&o->fam, id, o->cell_px, margin_px(o), o->margin_foam ? 255 : 0,
                              o->camera, dst, (int)stride,
                              (size_t)(side - 1) * (size_t)stride + (size_t)side);
    if (rc != ACTAG_OK)
        die("cannot render: %s", actag_strerror(rc));
}

static int pgm_side(const opts_t *o)
{
    int side = actag_render_side(o->fam.bits, o->cell_px, margin_px(o));
    if (side < 0)
        die("image too large: --cell-px %d with --margin-cells %g", o->cell_px, o->margin_cells);
    return side;
}

static void pgm_single(const opts_t *o, int id, const char *path)
{
    int side = pgm_side(o);
    uint8_t *img = (uint8_t *)xmalloc((size_t)side * (size_t)side);
    FILE *f;
    render_into(o, id, img, side, side);
    f = open_out(path);
    write_pgm(f, path, img, side, side);
    close_out();
    free(img);
}

/* ------------------------------------------------------------------ SVG */

static void svg_begin(FILE *f, double w, double h, const char *what)
{
    char a[40], b[40];
    fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n");
    fprintf(f, "<!-- actag-render: %s; units mm -->\n", what);
    fprintf(f,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"%smm\" "
            "height=\"%smm\" viewBox=\"0 0 %s %s\">\n",
            fnum(a, w), fnum(b, h), a, b);
}

static void svg_path_d(FILE *f, const plate_t *p, double ox, double oy, int want)
{
    int i, m;
    char a[40], b[40];
    for (i = 0; i < p->nloops; i++) {
        const loop_t *L = &p->loops[i];
        if (want > 0 ? L->area <= 0 : want < 0 ? L->area >= 0 : 0)
            continue;
        for (m = 0; m < L->n; m++)
            fprintf(f, "%s%s %s ", m == 0 ? "M" : "L", fnum(a, L->v[m].x + ox), fnum(b, L->v[m].y + oy));
        fputs("Z ", f);
    }
}

static void svg_text(FILE *f, double x, double y, double size, const char *t)
{
    char a[40], b[40], c[40];
    fprintf(f,
            "<text x=\"%s\" y=\"%s\" font-family=\"sans-serif\" font-size=\"%s\" "
            "fill=\"#000000\" stroke=\"none\">%s</text>\n",
            fnum(a, x), fnum(b, y), fnum(c, size), t);
}

/* One image tag at (ox, oy): foam square, metal drawn as one even-odd path. */
static void svg_image_tag(FILE *f, const opts_t *o, const plate_t *p, double ox, double oy)
{
    const char *metal = o->camera ? "#ffffff" : "#000000";
    const char *foam = o->camera ? "#000000" : "#ffffff";
    char a[40], b[40], c[40];
    fprintf(f, "<rect x=\"%s\" y=\"%s\" width=\"%s\" height=\"%s\" fill=\"%s\" stroke=\"none\"/>\n",
            fnum(a, ox), fnum(b, oy), fnum(c, p->size), c, foam);
    fprintf(f, "<path fill=\"%s\" fill-rule=\"evenodd\" stroke=\"none\" d=\"", metal);
    svg_path_d(f, p, ox, oy, 0);
    fputs("\"/>\n", f);
}

/* Cut layers of several plates, as groups named like the DXF layers. */
static void svg_cut_layers(FILE *f, const plate_t *plates, const pt2 *org, int n)
{
    char a[40], b[40], c[40];
    int i, h;
    fputs("<g id=\"OUTLINE\" fill=\"none\" stroke=\"#000000\" stroke-width=\"0.1\">\n", f);
    for (i = 0; i < n; i++) {
        fputs("<path d=\"", f);
        svg_path_d(f, &plates[i], org[i].x, org[i].y, 1);
        fputs("\"/>\n", f);
    }
    fputs("</g>\n<g id=\"CUTOUT\" fill=\"none\" stroke=\"#ff0000\" stroke-width=\"0.1\">\n", f);
    for (i = 0; i < n; i++) {
        int j;
        for (j = 0; j < plates[i].nloops; j++)
            if (plates[i].loops[j].area < 0) {
                plate_t one = plates[i];
                one.loops = &plates[i].loops[j];
                one.nloops = 1;
                fputs("<path d=\"", f);
                svg_path_d(f, &one, org[i].x, org[i].y, -1);
                fputs("\"/>\n", f);
            }
    }
    fputs("</g>\n<g id=\"HOLES\" fill=\"none\" stroke=\"#0000ff\" stroke-width=\"0.1\">\n", f);
    for (i = 0; i < n; i++)
        for (h = 0; h < plates[i].nholes; h++)
            fprintf(f, "<circle cx=\"%s\" cy=\"%s\" r=\"%s\"/>\n",
                    fnum(a, plates[i].holes[h].x + org[i].x),
                    fnum(b, plates[i].holes[h].y + org[i].y), fnum(c, plates[i].hole_r));
    fputs("</g>\n", f);
    for (i = 0; i < n; i++)
        for (h = 0; h < plates[i].ntabs; h++)
            fprintf(f, "<!-- tab at (%s, %s) -->\n", fnum(a, plates[i].tabs[h].x + org[i].x),
                    fnum(b, plates[i].tabs[h].y + org[i].y));
}

/* ------------------------------------------------------------------ DXF (AutoCAD R12) */

static void gs(FILE *f, int code, const char *v) { fprintf(f, "%3d\n%s\n", code, v); }
static void gi(FILE *f, int code, int v) { fprintf(f, "%3d\n%d\n", code, v); }
static void gf(FILE *f, int code, double v)
{
    char b[40];
    fnum(b, v);
    if (strchr(b, '.') == NULL)
        strcat(b, ".0");
    fprintf(f, "%3d\n%s\n", code, b);
}

static void dxf_begin(FILE *f, double w, double h, const char *what)
{
    static const char *const layers[5] = {"OUTLINE", "CUTOUT", "HOLES", "TAB", "LABEL"};
    static const int colours[5] = {7, 1, 5, 3, 2};
    int i;
    gs(f, 999, what);
    gs(f, 0, "SECTION");
    gs(f, 2, "HEADER");
    gs(f, 9, "$ACADVER");
    gs(f, 1, "AC1009");
    gs(f, 9, "$INSUNITS");
    gi(f, 70, 4); /* millimetres */
    gs(f, 9, "$MEASUREMENT");
    gi(f, 70, 1); /* metric */
    gs(f, 9, "$EXTMIN");
    gf(f, 10, 0.0);
    gf(f, 20, 0.0);
    gf(f, 30, 0.0);
    gs(f, 9, "$EXTMAX");
    gf(f, 10, w);
    gf(f, 20, h);
    gf(f, 30, 0.0);
    gs(f, 9, "$LIMMIN");
    gf(f, 10, 0.0);
    gf(f, 20, 0.0);
    gs(f, 9, "$LIMMAX");
    gf(f, 10, w);
    gf(f, 20, h);
    gs(f, 0, "ENDSEC");

    gs(f, 0, "SECTION");
    gs(f, 2, "TABLES");
    gs(f, 0, "TABLE");
    gs(f, 2, "LTYPE");
    gi(f, 70, 1);
    gs(f, 0, "LTYPE");
    gs(f, 2, "CONTINUOUS");
    gi(f, 70, 0);
    gs(f, 3, "Solid line");
    gi(f, 72, 65);
    gi(f, 73, 0);
    gf(f, 40, 0.0);
    gs(f, 0, "ENDTAB");
    gs(f, 0, "TABLE");
    gs(f, 2, "LAYER");
    gi(f, 70, 5);
    for (i = 0; i < 5; i++) {
        gs(f, 0, "LAYER");
        gs(f, 2, layers[i]);
        gi(f, 70, 0);
        gi(f, 62, colours[i]);
        gs(f, 6, "CONTINUOUS");
    }
    gs(f, 0, "ENDTAB");
    gs(f, 0, "ENDSEC");

    gs(f, 0, "SECTION");
    gs(f, 2, "ENTITIES");
}

static void dxf_end(FILE *f)
{
    gs(f, 0, "ENDSEC");
    gs(f, 0, "EOF");
}

/* DXF has y up: a point (x, y) in page mm (y down) goes to (x, page_h - y). */
static void dxf_plate(FILE *f, const plate_t *p, double ox, double oy, double page_h)
{
    int i, m;
    for (i = 0; i < p->nloops; i++) {
        const loop_t *L = &p->loops[i];
        const char *layer = L->area > 0 ? "OUTLINE" : "CUTOUT";
        gs(f, 0, "POLYLINE");
        gs(f, 8, layer);
        gi(f, 66, 1);
        gf(f, 10, 0.0);
        gf(f, 20, 0.0);
        gf(f, 30, 0.0);
        gi(f, 70, 1); /* closed */
        for (m = 0; m < L->n; m++) {
            gs(f, 0, "VERTEX");
            gs(f, 8, layer);
            gf(f, 10, L->v[m].x + ox);
            gf(f, 20, page_h - (L->v[m].y + oy));
            gf(f, 30, 0.0);
        }
        gs(f, 0, "SEQEND");
        gs(f, 8, layer);
    }
    for (i = 0; i < p->nholes; i++) {
        gs(f, 0, "CIRCLE");
        gs(f, 8, "HOLES");
        gf(f, 10, p->holes[i].x + ox);
        gf(f, 20, page_h - (p->holes[i].y + oy));
        gf(f, 30, 0.0);
        gf(f, 40, p->hole_r);
    }
    for (i = 0; i < p->ntabs; i++) {
        gs(f, 0, "POINT");
        gs(f, 8, "TAB");
        gf(f, 10, p->tabs[i].x + ox);
        gf(f, 20, page_h - (p->tabs[i].y + oy));
        gf(f, 30, 0.0);
    }
}

static void dxf_text(FILE *f, double x, double y_base, double size, const char *t)
{
    gs(f, 0, "TEXT");
    gs(f, 8, "LABEL");
    gf(f, 10, x);
    gf(f, 20, y_base);
    gf(f, 30, 0.0);
    gf(f, 40, size);
    gs(f, 1, t);
}

/* ------------------------------------------------------------------ one file per tag */

static void warn_pieces(const opts_t *o, int id, const plate_t *p)
{
    if (p->pieces > 1)
        fprintf(stderr,
                "actag-render: warning: %s ID %d face plate falls apart into %d pieces "
                "(a corner bit needs a tab: use --tab-width > 0 or a margin)\n",
                o->fam.name, id, p->pieces);
}

static void vector_single(const opts_t *o, int id, const char *path)
{
    plate_t p;
    char what[160], lab[64];
    FILE *f;
    pt2 org = {0.0, 0.0};
    build_plate(o, id, o->mode, &p);
    if (o->mode == MODE_FACE)
        warn_pieces(o, id, &p);
    label_text(lab, sizeof lab, o, id);
    snprintf(what, sizeof what, "%s %s, tag_size %g m, cell %g mm", lab, mode_name(o->mode),
             o->tag_size_m, cell_mm(o));
    f = open_out(path);
    if (o->format == FMT_DXF) {
        dxf_begin(f, p.size, p.size, what);
        dxf_plate(f, &p, 0.0, 0.0, p.size);
        dxf_end(f);
    } else {
        svg_begin(f, p.size, p.size, what);
        if (o->mode == MODE_IMAGE)
            svg_image_tag(f, o, &p, 0.0, 0.0);
        else
            svg_cut_layers(f, &p, &org, 1);
        fputs("</svg>\n", f);
    }
    close_out();
    free_plate(&p);
}

/* ------------------------------------------------------------------ sheets */

static char *page_path(const opts_t *o, int page, int npages)
{
    size_t n = (o->out ? strlen(o->out) : 0) + (o->out_dir ? strlen(o->out_dir) : 0) + 128;
    char *s = (char *)xmalloc(n);
    if (o->out_dir) {
        snprintf(s, n, "%s/%s%s-sheet-p%d.%s", o->out_dir, o->fam.name, mode_suffix(o->mode),
                 page + 1, ext_of(o->format));
    } else if (o->out == NULL) {
        if (npages > 1)
            die("the sheet needs %d pages: use --out FILE or --out-dir DIR", npages);
        free(s);
        return NULL;
    } else if (npages == 1) {
        snprintf(s, n, "%s", o->out);
    } else {
        const char *dot = strrchr(o->out, '.'), *slash = strrchr(o->out, '/');
        size_t stem = (dot && (!slash || dot > slash)) ? (size_t)(dot - o->out) : strlen(o->out);
        snprintf(s, n, "%.*s-p%d%s", (int)stem, o->out, page + 1, o->out + stem);
        if (page == 0)
            fprintf(stderr, "actag-render: the sheet needs %d pages: %.*s-p1%s .. -p%d%s\n",
                    npages, (int)stem, o->out, o->out + stem, npages, o->out + stem);
    }
    return s;
}

static void pgm_sheet(const opts_t *o)
{
    int side = pgm_side(o), cols = o->columns ? o->columns : 4, rows = o->rows ? o->rows : 5;
    int per = cols * rows, npages, page, i, maxlen = 0;
    long s, textw, slot_w, slot_h, gap = o->cell_px, w, h;
    char lab[64];
    for (i = 0; i < o->nids; i++) {
        label_text(lab, sizeof lab, o, o->ids[i]);
        if ((int)strlen(lab) > maxlen)
            maxlen = (int)strlen(lab);
    }
    s = o->cell_px / 8;
    if (s < 1)
        s = 1;
    if (s > side / (6L * maxlen))
        s = side / (6L * maxlen) > 0 ? side / (6L * maxlen) : 1;
    textw = 6L * maxlen * s;
    slot_w = side > textw ? side : textw;
    slot_h = side + 10L * s;
    w = 2 * gap + cols * slot_w + (cols - 1) * gap;
    h = 2 * gap + rows * slot_h + (rows - 1) * gap;
    if ((double)w * (double)h > MAX_PGM_PIXELS)
        die("sheet too large (%ld x %ld pixels): reduce --cell-px, --columns or --rows", w, h);
    npages = (o->nids + per - 1) / per;
    for (page = 0; page < npages; page++) {
        uint8_t *img = (uint8_t *)xmalloc((size_t)(w * h));
        char *path = page_path(o, page, npages);
        FILE *f;
        memset(img, 255, (size_t)(w * h));
        for (i = page * per; i < o->nids && i < (page + 1) * per; i++) {
            int slot = i - page * per;
            long x0 = gap + (slot % cols) * (slot_w + gap), y0 = gap + (slot / cols) * (slot_h + gap);
            long tl;
            render_into(o, o->ids[i], img + y0 * w + x0 + (slot_w - side) / 2, w, side);
            label_text(lab, sizeof lab, o, o->ids[i]);
            tl = 6L * (long)strlen(lab) * s - s;
            draw_text(img, w, h, x0 + (slot_w - tl) / 2, y0 + side + 2 * s, (int)s, lab);
        }
        f = open_out(path);
        write_pgm(f, path, img, w, h);
        close_out();
        free(img);
        free(path);
    }
}

static void vector_sheet(const opts_t *o)
{
    plate_t probe;
    double P, font, slot_h, gap = o->gap, fit_cd, fit_rd;
    int cols, rows, per, npages, page, fit_c, fit_r;
    build_plate(o, o->ids[0], o->mode, &probe);
    P = probe.size;
    free_plate(&probe);
    font = P / 12.0 < 4.0 ? P / 12.0 : 4.0;
    slot_h = P + 1.5 * font + 1.0;
    /* Capped in double before the cast, as --columns/--rows are (10000): a
     * large page of tiny tags would overflow the int and cols * rows. */
    fit_cd = floor((o->page_w - 2 * gap + gap) / (P + gap) + 1e-9);
    fit_rd = floor((o->page_h - 2 * gap + gap) / (slot_h + gap) + 1e-9);
    fit_c = (int)(fit_cd < 1.0 ? 0.0 : fit_cd > 10000.0 ? 10000.0 : fit_cd);
    fit_r = (int)(fit_rd < 1.0 ? 0.0 : fit_rd > 10000.0 ? 10000.0 : fit_rd);
    if (fit_c < 1 || fit_r < 1)
        die("a %g mm tag with its label does not fit on a %g x %g mm page (gap %g mm)", P,
            o->page_w, o->page_h, gap);
    cols = o->columns ? o->columns : fit_c;
    rows = o->rows ? o->rows : fit_r;
    if (cols > fit_c || rows > fit_r)
        die("%d x %d tags of %g mm do not fit on a %g x %g mm page (at most %d x %d)", cols, rows,
            P, o->page_w, o->page_h, fit_c, fit_r);
    per = cols * rows; /* at most 10000 x 10000 */
    npages = (o->nids + per - 1) / per;
    for (page = 0; page < npages; page++) {
        int first = page * per, n = o->nids - first < per ? o->nids - first : per, i;
        plate_t *plates = (plate_t *)xmalloc((size_t)n * sizeof(plate_t));
        pt2 *org = (pt2 *)xmalloc((size_t)n * sizeof(pt2));
        char *path = page_path(o, page, npages), what[200], lab[64];
        FILE *f;
        for (i = 0; i < n; i++) {
            build_plate(o, o->ids[first + i], o->mode, &plates[i]);
            if (o->mode == MODE_FACE)
                warn_pieces(o, o->ids[first + i], &plates[i]);
            org[i].x = gap + (double)(i % cols) * (P + gap);
            org[i].y = gap + (double)(i / cols) * (slot_h + gap);
        }
        snprintf(what, sizeof what, "%s %s sheet, page %d of %d, tag_size %g m, cell %g mm",
                 o->fam.name, mode_name(o->mode), page + 1, npages, o->tag_size_m, cell_mm(o));
        f = open_out(path);
        if (o->format == FMT_DXF) {
            dxf_begin(f, o->page_w, o->page_h, what);
            for (i = 0; i < n; i++) {
                dxf_plate(f, &plates[i], org[i].x, org[i].y, o->page_h);
                label_text(lab, sizeof lab, o, o->ids[first + i]);
                dxf_text(f, org[i].x, o->page_h - (org[i].y + P + 0.5 * font + font), font, lab);
            }
            dxf_end(f);
        } else {
            svg_begin(f, o->page_w, o->page_h, what);
            if (o->mode == MODE_IMAGE) {
                for (i = 0; i < n; i++)
                    svg_image_tag(f, o, &plates[i], org[i].x, org[i].y);
            } else {
                svg_cut_layers(f, plates, org, n);
            }
            fputs("<g id=\"LABEL\">\n", f);
            for (i = 0; i < n; i++) {
                label_text(lab, sizeof lab, o, o->ids[first + i]);
                svg_text(f, org[i].x, org[i].y + P + 0.5 * font + font, font, lab);
            }
            fputs("</g>\n</svg>\n", f);
        }
        close_out();
        for (i = 0; i < n; i++)
            free_plate(&plates[i]);
        free(plates);
        free(org);
        free(path);
    }
}

/* ------------------------------------------------------------------ main */

int main(int argc, char **argv)
{
    opts_t o;
    int i;
    parse_args(argc, argv, &o);
    if (o.out_dir)
        hostio_opt_mkdirs("actag-render", "--out-dir", o.out_dir);
    if (o.list_tabs) {
        static const char *const names[4] = {"TL", "TR", "BR", "BL"};
        open_out(NULL); /* stdout, checked by close_out() */
        for (i = 0; i < o.nids; i++) {
            int mask = actag_layout_corner_tabs(&o.fam, o.ids[i]), c, first = 1;
            if (mask <= 0)
                continue;
            printf("%d ", o.ids[i]);
            for (c = 0; c < 4; c++)
                if (mask & (1 << c)) {
                    printf("%s%s", first ? "" : ",", names[c]);
                    first = 0;
                }
            putchar('\n');
        }
        close_out();
    } else if (o.sheet) {
        if (o.format == FMT_PGM)
            pgm_sheet(&o);
        else
            vector_sheet(&o);
    } else {
        for (i = 0; i < o.nids; i++) {
            char *path = NULL;
            if (o.out_dir) {
                size_t n = strlen(o.out_dir) + 128;
                path = (char *)xmalloc(n);
                snprintf(path, n, "%s/%s-%d%s.%s", o.out_dir, o.fam.name, o.ids[i],
                         mode_suffix(o.mode), ext_of(o.format));
            }
            if (o.format == FMT_PGM)
                pgm_single(&o, o.ids[i], path ? path : o.out);
            else
                vector_single(&o, o.ids[i], path ? path : o.out);
            free(path);
        }
    }
    free(o.ids);
    return 0;
}
