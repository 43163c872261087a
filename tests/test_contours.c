/* Contour scanner: outer borders of 8-connected white blobs, checked against
 * a brute-force reference (flood-fill labelling of white 8-components and
 * black 4-components) on seeded random images, edge cases and real sonar
 * frames; cap/overflow, image marks, row padding and error codes. */
#include "unity.h"
#include "test_util.h"

#include "actag/contours.h"

void setUp(void) {}
void tearDown(void) {}

/* ------------------------------------------------------------------ images */

typedef struct timg {
    int rows, cols, stride;
    uint8_t *px; /* rows * stride bytes, padding filled with garbage */
} timg;

/* The last row has no padding: the buffer ends right after its last pixel,
 * so reading past it is an out-of-bounds access (visible under ASan). */
static size_t timg_bytes(const timg *t)
{
    return (size_t)(t->rows - 1) * (size_t)t->stride + (size_t)t->cols;
}

static timg timg_new(int rows, int cols, int pad)
{
    timg t;
    size_t i, n;
    t.rows = rows;
    t.cols = cols;
    t.stride = cols + pad;
    n = timg_bytes(&t);
    t.px = (uint8_t *)malloc(n ? n : 1);
    TEST_ASSERT_NOT_NULL(t.px);
    for (i = 0; i < n; i++)
        t.px[i] = (uint8_t)tu_rand(); /* garbage everywhere, incl. padding */
    return t;
}

static int white(const timg *t, int r, int c)
{
    if (r < 0 || c < 0 || r >= t->rows || c >= t->cols)
        return 0;
    return t->px[(size_t)r * (size_t)t->stride + (size_t)c] != 0;
}

/* Sets a pixel white (random nonzero value) or black. */
static void setpx(timg *t, int r, int c, int w)
{
    if (r < 0 || c < 0 || r >= t->rows || c >= t->cols)
        return;
    t->px[(size_t)r * (size_t)t->stride + (size_t)c] = w ? (uint8_t)tu_range(1, 255) : 0;
}

/* --------------------------------------------------------------- reference */

typedef struct ref {
    int ncomp;
    int *wlab;    /* rows*cols: white 8-component label, raster order of first pixels; -1 black */
    int *first;   /* ncomp: index r*cols+c of each component's first pixel */
    int *nborder; /* ncomp: number of outer-border pixels */
    uint8_t *border; /* rows*cols: 1 if the pixel is on its component's outer border */
    int nholes;      /* enclosed black 4-components of 2+ pixels */
} ref;




static void ref_build(const timg *t, ref *R)
{
    const int rows = t->rows, cols = t->cols;
    const int pw = cols + 2, ph = rows + 2;
    const size_t n = (size_t)rows * (size_t)cols, pn = (size_t)pw * (size_t)ph;
    int *blab = (int *)malloc(pn * sizeof(int));
    int nb = 0, r, c, k;
    size_t i;
    int *g_stack = (int *)malloc((pn + 1) * sizeof(int)); /* each pixel is pushed once */
    R->wlab = (int *)malloc(n * sizeof(int));
    R->first = (int *)malloc((n + 1) * sizeof(int));
    R->nborder = (int *)calloc(n + 1, sizeof(int));
    R->border = (uint8_t *)calloc(n, 1);
    TEST_ASSERT_NOT_NULL(blab);
    TEST_ASSERT_NOT_NULL(g_stack);
    TEST_ASSERT_TRUE(R->wlab && R->first && R->nborder && R->border);
    for (i = 0; i < n; i++)
        R->wlab[i] = -1;
    for (i = 0; i < pn; i++)
        blab[i] = -1;
    R->ncomp = 0;
    /* White 8-components. */
    for (r = 0; r < rows; r++)
        for (c = 0; c < cols; c++) {
            int sp = 0, lab;
            if (!white(t, r, c) || R->wlab[r * cols + c] >= 0)
                continue;
            lab = R->ncomp++;
            R->first[lab] = r * cols + c;
            R->wlab[r * cols + c] = lab;
            g_stack[sp++] = r * cols + c;
            while (sp) {
                int p = g_stack[--sp], pr = p / cols, pc = p % cols, dr, dc;
                for (dr = -1; dr <= 1; dr++)
                    for (dc = -1; dc <= 1; dc++) {
                        int qr = pr + dr, qc = pc + dc;
                        if (white(t, qr, qc) && R->wlab[qr * cols + qc] < 0) {
                            R->wlab[qr * cols + qc] = lab;
                            g_stack[sp++] = qr * cols + qc;
                        }
                    }
            }
        }
    /* Black 4-components of the image framed by one ring of black. */
    for (r = 0; r < ph; r++)
        for (c = 0; c < pw; c++) {
            int sp = 0, lab;
            if (white(t, r - 1, c - 1) || blab[r * pw + c] >= 0)
                continue;
            lab = nb++;
            blab[r * pw + c] = lab;
            g_stack[sp++] = r * pw + c;
            while (sp) {
                static const int d4r[4] = {0, 0, 1, -1}, d4c[4] = {1, -1, 0, 0};
                int p = g_stack[--sp], pr = p / pw, pc = p % pw;
                for (k = 0; k < 4; k++) {
                    int qr = pr + d4r[k], qc = pc + d4c[k];
                    if (qr < 0 || qc < 0 || qr >= ph || qc >= pw)
                        continue;
                    if (!white(t, qr - 1, qc - 1) && blab[qr * pw + qc] < 0) {
                        blab[qr * pw + qc] = lab;
                        g_stack[sp++] = qr * pw + qc;
                    }
                }
            }
        }
    /* Holes: black 4-components apart from the one holding the frame. */
    {
        int *size = (int *)calloc((size_t)nb + 1, sizeof(int));
        TEST_ASSERT_NOT_NULL(size);
        for (i = 0; i < pn; i++)
            if (blab[i] >= 0)
                size[blab[i]]++;
        R->nholes = 0;
        for (k = 0; k < nb; k++)
            if (k != blab[0] && size[k] >= 2)
                R->nholes++;
        free(size);
    }
    /* Outer border: pixels 4-adjacent to the black region left of the first pixel. */
    for (r = 0; r < rows; r++)
        for (c = 0; c < cols; c++) {
            int lab = R->wlab[r * cols + c], f, bg;
            if (lab < 0)
                continue;
            f = R->first[lab];
            bg = blab[(f / cols + 1) * pw + (f % cols)]; /* padded (fr+1, fc+1-1) */
            TEST_ASSERT_TRUE(bg >= 0);
            if (blab[(r + 1) * pw + c + 2] == bg || blab[(r + 1) * pw + c] == bg ||
                blab[r * pw + c + 1] == bg || blab[(r + 2) * pw + c + 1] == bg) {
                R->border[r * cols + c] = 1;
                R->nborder[lab]++;
            }
        }
    free(blab);
    free(g_stack);

}

static void ref_free(ref *R)
{
    free(R->wlab);
    free(R->first);
    free(R->nborder);
    free(R->border);
}

/* ----------------------------------------------------------------- checker */

typedef struct got {
    int n;                   /* contours */
    actag_contour_info *info; /* per contour */
    actag_ipoint **pts;      /* per contour, info.stored points */
    int holes;               /* scanner's count of hole borders walked */
} got;

static void got_free(got *g)
{
    int i;
    for (i = 0; i < g->n; i++)
        free(g->pts[i]);
    free(g->pts);
    free(g->info);
}

#define GUARD 4

/* The bitmap of t (actag_bitmap_pack), checked against t pixel by pixel and
 * for zero padding, in a buffer of exactly ACTAG_BITMAP_SIZE bytes (so that
 * reading beyond it is visible under ASan). */
static uint32_t *pack_checked(const timg *t)
{
    size_t n = ACTAG_BITMAP_SIZE(t->rows, t->cols), wpr = ACTAG_BITMAP_WORDS(t->cols);
    uint32_t *bm = (uint32_t *)malloc(n);
    uint8_t *back = (uint8_t *)malloc((size_t)t->rows * (size_t)t->cols);
    int r, c;
    size_t b;
    TEST_ASSERT_NOT_NULL(bm);
    TEST_ASSERT_NOT_NULL(back);
    memset(bm, 0xa5, n);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_bitmap_pack(t->px, t->rows, t->cols, t->stride, bm));
    for (r = -1; r <= t->rows; r++)
        for (b = 0; b < 32u * wpr; b++) {
            int bit = (int)((bm[(size_t)(r + 1) * wpr + b / 32u] >> (b % 32u)) & 1u);
            c = (int)b - 1;
            TEST_ASSERT_EQUAL_INT(white(t, r, c), bit); /* padding: 0 */
        }
    for (r = 0; r < t->rows; r++)
        for (c = 0; c < t->cols; c++)
            TEST_ASSERT_EQUAL_INT(white(t, r, c), actag_bitmap_get(bm, t->cols, r, c));
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_bitmap_unpack(bm, t->rows, t->cols, back, t->cols, 255u));
    for (r = 0; r < t->rows; r++)
        for (c = 0; c < t->cols; c++)
            TEST_ASSERT_EQUAL_UINT8(white(t, r, c) ? 255u : 0u, back[(size_t)r * (size_t)t->cols + (size_t)c]);
    free(back);
    return bm;
}

/* A scanner over t: *bm its bitmap, *mk the marks (both to be freed). */
static void scan_init(actag_contour_scanner *s, const timg *t, uint32_t **bm, uint32_t **mk)
{
    *bm = pack_checked(t);
    *mk = (uint32_t *)malloc(ACTAG_BITMAP_SIZE(t->rows, t->cols));
    TEST_ASSERT_NOT_NULL(*mk);
    memset(*mk, 0x5a, ACTAG_BITMAP_SIZE(t->rows, t->cols)); /* init clears it */
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_contour_scanner_init(s, *bm, *mk, t->rows, t->cols));
}
/* Runs the scanner over a copy of t with buffer capacity cap (cap < 0: big
 * enough for any contour) and checks the marks and padding afterwards. */
static got run_scanner(const timg *t, int cap)
{
    uint32_t *bm, *mk;
    actag_contour_scanner s;
    got g;
    int alloc = 64, bigcap = 4 * t->rows * t->cols + 8, ucap = cap < 0 ? bigcap : cap;
    actag_ipoint *buf = (actag_ipoint *)malloc((size_t)(ucap + GUARD) * sizeof(actag_ipoint));
    int rc, r, c, i;
    TEST_ASSERT_NOT_NULL(buf);
    g.n = 0;
    g.info = (actag_contour_info *)malloc((size_t)alloc * sizeof(actag_contour_info));
    g.pts = (actag_ipoint **)malloc((size_t)alloc * sizeof(actag_ipoint *));
    scan_init(&s, t, &bm, &mk);
    for (i = 0; i < ucap + GUARD; i++) {
        buf[i].x = -7;
        buf[i].y = -9;
    }
    for (;;) {
        actag_contour_info info;
        int end;
        memset(&info, 0xa5, sizeof info);
        rc = actag_contour_next(&s, cap == 0 ? NULL : buf, ucap, &info);
        TEST_ASSERT_TRUE(rc == 0 || rc == 1);
        if (rc == 0)
            break;
        TEST_ASSERT_TRUE(info.npoints >= 1);
        TEST_ASSERT_TRUE(info.stored >= 0 && info.stored <= ucap);
        /* Nothing written past the stored points (the buffer held only the
         * marker before the call; checked as far as a full trace would go). */
        end = info.npoints + GUARD < ucap + GUARD ? info.npoints + GUARD : ucap + GUARD;
        for (i = info.stored; i < end; i++) {
            TEST_ASSERT_EQUAL_INT(-7, buf[i].x);
            TEST_ASSERT_EQUAL_INT(-9, buf[i].y);
        }
        TEST_ASSERT_EQUAL_INT(info.npoints < ucap ? info.npoints : ucap, info.stored);
        TEST_ASSERT_EQUAL_INT(info.npoints > ucap, info.overflow);
        if (g.n == alloc) {
            alloc *= 2;
            g.info = (actag_contour_info *)realloc(g.info, (size_t)alloc * sizeof(actag_contour_info));
            g.pts = (actag_ipoint **)realloc(g.pts, (size_t)alloc * sizeof(actag_ipoint *));
            TEST_ASSERT_TRUE(g.info && g.pts);
        }
        g.info[g.n] = info;
        g.pts[g.n] = (actag_ipoint *)malloc((size_t)(info.stored + 1) * sizeof(actag_ipoint));
        memcpy(g.pts[g.n], buf, (size_t)info.stored * sizeof(actag_ipoint));
        g.n++;
        for (i = 0; i < info.stored; i++) { /* back to the marker */
            buf[i].x = -7;
            buf[i].y = -9;
        }
    }
    g.holes = s.holes;
    /* Finished scans stay finished. */
    {
        actag_contour_info tmp;
        TEST_ASSERT_EQUAL_INT(0, actag_contour_next(&s, cap == 0 ? NULL : buf, ucap, &tmp));
    }
    /* The bitmap is unchanged; a mark is set only on a white pixel or on a
     * black one (or the padding column right of the image) whose west
     * neighbour is white, never elsewhere in the padding. */
    {
        uint32_t *again = pack_checked(t);
        size_t wpr = ACTAG_BITMAP_WORDS(t->cols), b;
        TEST_ASSERT_EQUAL_MEMORY(again, bm, ACTAG_BITMAP_SIZE(t->rows, t->cols));
        free(again);
        for (r = -1; r <= t->rows; r++)
            for (b = 0; b < 32u * wpr; b++) {
                c = (int)b - 1;
                if ((mk[(size_t)(r + 1) * wpr + b / 32u] >> (b % 32u)) & 1u)
                    TEST_ASSERT_TRUE(r >= 0 && r < t->rows && c >= 0 && c <= t->cols &&
                                     (white(t, r, c) || white(t, r, c - 1)));
            }
    }
    free(buf);
    free(bm);
    free(mk);
    return g;
}

static int64_t shoelace2(const actag_ipoint *p, int n)
{
    int64_t s = 0;
    int i;
    for (i = 0; i < n; i++) {
        const actag_ipoint *a = &p[i], *b = &p[(i + 1) % n];
        s += (int64_t)a->x * b->y - (int64_t)b->x * a->y;
    }
    return s < 0 ? -s : s;
}

/* Full check of image t against the reference; returns the number of contours. */
static int check_image(const timg *t)
{
    ref R;
    got g;
    const int rows = t->rows, cols = t->cols;
    int *seen = (int *)malloc((size_t)rows * (size_t)cols * sizeof(int));
    int *edge = (int *)malloc((size_t)rows * (size_t)cols * 8 * sizeof(int));
    int k, i, ncont;
    static const int caps[6] = {0, 1, 2, 3, 5, 17};

    TEST_ASSERT_TRUE(seen && edge);
    for (i = 0; i < rows * cols; i++)
        seen[i] = -1;
    for (i = 0; i < rows * cols * 8; i++)
        edge[i] = -1;
    ref_build(t, &R);
    g = run_scanner(t, -1);
    TEST_ASSERT_EQUAL_INT(R.ncomp, g.n);
    /* Each hole border walked exactly once (one-pixel holes need no walk):
     * a redundant walk cannot change the output but would cost time. */
    TEST_ASSERT_EQUAL_INT(R.nholes, g.holes);
    for (k = 0; k < g.n; k++) {
        const actag_contour_info *in = &g.info[k];
        const actag_ipoint *p = g.pts[k];
        int n = in->npoints, distinct = 0, minx = 1 << 30, maxx = -1, miny = 1 << 30, maxy = -1;
        TEST_ASSERT_EQUAL_INT(n, in->stored);
        TEST_ASSERT_EQUAL_INT(0, in->overflow);
        /* Starts at the component's first pixel in raster order. */
        TEST_ASSERT_EQUAL_INT(R.first[k] % cols, p[0].x);
        TEST_ASSERT_EQUAL_INT(R.first[k] / cols, p[0].y);
        for (i = 0; i < n; i++) {
            int x = p[i].x, y = p[i].y, pix, dx, dy, dir;
            TEST_ASSERT_TRUE(x >= 0 && x < cols && y >= 0 && y < rows);
            pix = y * cols + x;
            TEST_ASSERT_EQUAL_INT(k, R.wlab[pix]);
            TEST_ASSERT_EQUAL_INT(1, R.border[pix]);
            if (seen[pix] != k) {
                seen[pix] = k;
                distinct++;
            }
            if (x < minx) minx = x;
            if (x > maxx) maxx = x;
            if (y < miny) miny = y;
            if (y > maxy) maxy = y;
            if (n > 1) { /* closed walk of 8-neighbour steps, no step taken twice */
                const actag_ipoint *q = &p[(i + 1) % n];
                dx = q->x - x;
                dy = q->y - y;
                TEST_ASSERT_TRUE(dx >= -1 && dx <= 1 && dy >= -1 && dy <= 1 && (dx || dy));
                dir = (dy + 1) * 3 + (dx + 1);
                dir = dir > 4 ? dir - 1 : dir;
                TEST_ASSERT_EQUAL_INT(-1, edge[pix * 8 + dir]);
                edge[pix * 8 + dir] = k;
            }
        }
        TEST_ASSERT_EQUAL_INT(R.nborder[k], distinct);
        TEST_ASSERT_EQUAL_INT(minx, in->min_x);
        TEST_ASSERT_EQUAL_INT(maxx, in->max_x);
        TEST_ASSERT_EQUAL_INT(miny, in->min_y);
        TEST_ASSERT_EQUAL_INT(maxy, in->max_y);
        TEST_ASSERT_EQUAL_FLOAT((float)shoelace2(p, n) * 0.5f, in->area);
    }
    /* Small buffers: same contours, prefixes stored, whole-border info. */
    for (i = 0; i < 6; i++) {
        got h = run_scanner(t, caps[i]);
        TEST_ASSERT_EQUAL_INT(g.n, h.n);
        TEST_ASSERT_EQUAL_INT(g.holes, h.holes);
        for (k = 0; k < g.n; k++) {
            const actag_contour_info *a = &g.info[k], *b = &h.info[k];
            TEST_ASSERT_EQUAL_INT(a->npoints, b->npoints);
            TEST_ASSERT_EQUAL_INT(a->npoints < caps[i] ? a->npoints : caps[i], b->stored);
            TEST_ASSERT_EQUAL_INT(a->npoints > caps[i], b->overflow);
            TEST_ASSERT_EQUAL_INT(a->min_x, b->min_x);
            TEST_ASSERT_EQUAL_INT(a->max_x, b->max_x);
            TEST_ASSERT_EQUAL_INT(a->min_y, b->min_y);
            TEST_ASSERT_EQUAL_INT(a->max_y, b->max_y);
            TEST_ASSERT_EQUAL_FLOAT(a->area, b->area);
            if (b->stored)
                TEST_ASSERT_EQUAL_MEMORY(g.pts[k], h.pts[k], (size_t)b->stored * sizeof(actag_ipoint));
        }
        got_free(&h);
    }
    ncont = g.n;
    got_free(&g);
    ref_free(&R);
    free(seen);
    free(edge);
    return ncont;
}

/* ------------------------------------------------------------- generators */

static void fill_random(timg *t, int permille)
{
    int r, c;
    for (r = 0; r < t->rows; r++)
        for (c = 0; c < t->cols; c++)
            setpx(t, r, c, tu_range(0, 999) < permille);
}

/* Box-blurred noise thresholded: blobs of many sizes, with holes. */
static void fill_blobby(timg *t, int rad, int permille)
{
    const int rows = t->rows, cols = t->cols;
    int *v = (int *)malloc((size_t)rows * (size_t)cols * sizeof(int));
    int r, c, dr, dc;
    TEST_ASSERT_NOT_NULL(v);
    for (r = 0; r < rows * cols; r++)
        v[r] = tu_range(0, 999);
    for (r = 0; r < rows; r++)
        for (c = 0; c < cols; c++) {
            int s = 0, n = 0;
            for (dr = -rad; dr <= rad; dr++)
                for (dc = -rad; dc <= rad; dc++)
                    if (r + dr >= 0 && r + dr < rows && c + dc >= 0 && c + dc < cols) {
                        s += v[(r + dr) * cols + c + dc];
                        n++;
                    }
            setpx(t, r, c, s < permille * n);
        }
    free(v);
}

/* ------------------------------------------------------------------ tests */

static void test_random_images(void)
{
    int it, total = 0;
    tu_seed(12345);
    for (it = 0; it < 6000; it++) {
        int rows = tu_range(1, it < 1500 ? 6 : 40), cols = tu_range(1, it < 1500 ? 6 : 40);
        timg t = timg_new(rows, cols, tu_range(0, 3) ? 0 : tu_range(1, 9));
        if (it % 3 == 2) {
            /* one draw per declarator: a fixed order (the x86-64 build's
             * order when they were call arguments: the last one first) */
            int pm = tu_range(400, 600), nb = tu_range(1, 2);
            fill_blobby(&t, nb, pm);
        } else
            fill_random(&t, tu_range(0, 1000));
        total += check_image(&t);
        free(t.px);
    }
    TEST_ASSERT_GREATER_THAN(20000, total); /* the generator really makes blobs */
}

static void test_larger_images(void)
{
    int it;
    tu_seed(777);
    for (it = 0; it < 30; it++) {
        /* one draw per declarator: a fixed order (the x86-64 build's order
         * when they were call arguments: the last one first) */
        int cols = tu_range(100, 200), rows = tu_range(100, 200);
        timg t = timg_new(rows, cols, it & 1 ? 13 : 0);
        if (it % 3 == 0) {
            fill_random(&t, tu_range(300, 700));
        } else {
            int pm = tu_range(420, 580), nb = tu_range(1, 4);
            fill_blobby(&t, nb, pm);
        }
        TEST_ASSERT_GREATER_THAN(0, check_image(&t));
        free(t.px);
    }
}

static void test_edge_cases(void)
{
    int n, v, r, c;
    tu_seed(99);
    /* 1x1 black and white. */
    for (v = 0; v < 2; v++) {
        timg t = timg_new(1, 1, v ? 3 : 0);
        setpx(&t, 0, 0, v);
        TEST_ASSERT_EQUAL_INT(v, check_image(&t));
        free(t.px);
    }
    /* 1xN, Nx1, all black, all white. */
    for (n = 1; n <= 70; n += 3) {
        timg a = timg_new(1, n, n % 2), b = timg_new(n, 1, n % 5), k = timg_new(n, n + 1, 2),
             w = timg_new(n + 2, n, 1);
        fill_random(&a, 500);
        fill_random(&b, 500);
        fill_random(&k, 0);
        fill_random(&w, 1000);
        check_image(&a);
        check_image(&b);
        TEST_ASSERT_EQUAL_INT(0, check_image(&k));
        TEST_ASSERT_EQUAL_INT(1, check_image(&w));
        free(a.px);
        free(b.px);
        free(k.px);
        free(w.px);
    }
    /* Checkerboards: one blob (diagonal contacts), border = its edge pixels only. */
    for (n = 1; n <= 12; n++) {
        timg t = timg_new(n, n + 3, 0), u = timg_new(n + 1, n, 4);
        for (r = 0; r < t.rows; r++)
            for (c = 0; c < t.cols; c++)
                setpx(&t, r, c, (r + c) % 2 == 0);
        for (r = 0; r < u.rows; r++)
            for (c = 0; c < u.cols; c++)
                setpx(&u, r, c, (r + c) % 2 == 1);
        /* 1 x 4: two separate pixels; otherwise diagonals join everything. */
        TEST_ASSERT_EQUAL_INT(n == 1 ? 2 : 1, check_image(&t));
        TEST_ASSERT_EQUAL_INT(1, check_image(&u));
        free(t.px);
        free(u.px);
    }
}

/* One-pixel holes (no walk: scanner.holes does not count them) beside
 * black notches, at every column offset in a word. (The mutation run of
 * contours.c asked whether the scan's second test of a one-pixel hole reads
 * the hole's neighbours: it does, but the word-wise candidate test before
 * it already drops such holes, so a wrong second test changes nothing.) */
static void test_one_pixel_holes_beside_notches(void)
{
    static const char *pat[5] = {"0000000", "0101110", "0111010", "0111110", "0000000"};
    int off, r, c;
    for (off = 0; off < 70; off++) {
        timg t = timg_new(5, off + 9, off % 3);
        for (r = 0; r < 5; r++)
            for (c = 0; c < t.cols; c++)
                setpx(&t, r, c, c >= off && c < off + 7 && pat[r][c - off] == '1');
        /* one blob; its one-pixel hole at (2, off + 4) and the notch at
         * (1, off + 2), open to the outside through (0, off + 2) */
        TEST_ASSERT_EQUAL_INT(1, check_image(&t));
        free(t.px);
    }
}

/* Concentric square rings, alternating white/black, with a dot in the middle:
 * every ring is its own blob (and every black ring a hole of the one outside). */
static void test_nested_rings(void)
{
    int size;
    tu_seed(4242);
    for (size = 1; size <= 41; size += 2) {
        timg t = timg_new(size + 4, size + 6, 3);
        int r, c, expect = 0, d;
        fill_random(&t, 0);
        for (r = 0; r < size; r++)
            for (c = 0; c < size; c++) {
                int dd = r < c ? r : c;
                if (size - 1 - r < dd) dd = size - 1 - r;
                if (size - 1 - c < dd) dd = size - 1 - c;
                setpx(&t, r + 2, c + 3, dd % 2 == 0);
            }
        for (d = 0; 2 * d < size; d += 2)
            expect++;
        TEST_ASSERT_EQUAL_INT(expect, check_image(&t));
        free(t.px);
    }
}

/* Known geometry: a filled w x h rectangle walks its perimeter of pixel centres. */
static void test_rectangle_geometry(void)
{
    int w, h;
    tu_seed(5);
    for (w = 1; w <= 9; w++)
        for (h = 1; h <= 9; h++) {
            timg t = timg_new(h + 3, w + 4, 0);
            actag_contour_scanner s;
            actag_contour_info info;
            actag_ipoint pts[64];
            int r, c, per = (w == 1 || h == 1) ? (w * h == 1 ? 1 : 2 * (w * h - 1)) : 2 * (w + h) - 4;
            fill_random(&t, 0);
            for (r = 0; r < h; r++)
                for (c = 0; c < w; c++)
                    setpx(&t, r + 1, c + 2, 1);
            uint32_t *bm, *mk;
            scan_init(&s, &t, &bm, &mk);
            TEST_ASSERT_EQUAL_INT(1, actag_contour_next(&s, pts, 64, &info));
            TEST_ASSERT_EQUAL_INT(per, info.npoints);
            TEST_ASSERT_EQUAL_FLOAT((float)((w - 1) * (h - 1)), info.area);
            TEST_ASSERT_EQUAL_INT(2, info.min_x);
            TEST_ASSERT_EQUAL_INT(w + 1, info.max_x);
            TEST_ASSERT_EQUAL_INT(1, info.min_y);
            TEST_ASSERT_EQUAL_INT(h, info.max_y);
            if (w > 1 && h > 1) { /* counterclockwise on screen: down the left side first */
                TEST_ASSERT_EQUAL_INT(2, pts[1].x);
                TEST_ASSERT_EQUAL_INT(2, pts[1].y);
            }
            TEST_ASSERT_EQUAL_INT(0, actag_contour_next(&s, pts, 64, &info));
            free(t.px);
            free(bm);
            free(mk);
        }
}

/* Overflow in the middle of a scan: the next call still continues correctly
 * (checked on every image by check_image); here explicitly. */
static void test_overflow_then_continue(void)
{
    uint32_t *bm, *mk;
    timg t;
    actag_contour_scanner s;
    actag_contour_info info;
    actag_ipoint pts[8];
    int r, c;
    tu_seed(8);
    t = timg_new(20, 30, 2);
    fill_random(&t, 0);
    for (r = 2; r < 12; r++) /* a 10x10 square (36 border points)... */
        for (c = 2; c < 12; c++)
            setpx(&t, r, c, 1);
    for (r = 4; r < 8; r++) /* ...with a 4x4 hole... */
        for (c = 4; c < 8; c++)
            setpx(&t, r, c, 0);
    setpx(&t, 5, 5, 1); /* ...holding a dot, */
    setpx(&t, 3, 20, 1); /* a dot to the right, */
    setpx(&t, 15, 1, 1); /* and a 2-pixel bar below. */
    setpx(&t, 15, 2, 1);
    TEST_ASSERT_EQUAL_INT(4, check_image(&t)); /* against the reference too */
    scan_init(&s, &t, &bm, &mk);
    TEST_ASSERT_EQUAL_INT(1, actag_contour_next(&s, pts, 8, &info));
    TEST_ASSERT_EQUAL_INT(36, info.npoints);
    TEST_ASSERT_EQUAL_INT(8, info.stored);
    TEST_ASSERT_EQUAL_INT(1, info.overflow);
    TEST_ASSERT_EQUAL_FLOAT(81.0f, info.area);
    TEST_ASSERT_EQUAL_INT(1, actag_contour_next(&s, NULL, 0, &info));
    TEST_ASSERT_EQUAL_INT(1, info.npoints);
    TEST_ASSERT_EQUAL_INT(0, info.stored);
    TEST_ASSERT_EQUAL_INT(1, info.overflow);
    TEST_ASSERT_EQUAL_INT(20, info.min_x);
    TEST_ASSERT_EQUAL_INT(1, actag_contour_next(&s, pts, 8, &info));
    TEST_ASSERT_EQUAL_INT(1, info.npoints);
    TEST_ASSERT_EQUAL_INT(5, pts[0].x);
    TEST_ASSERT_EQUAL_INT(5, pts[0].y);
    TEST_ASSERT_EQUAL_INT(1, actag_contour_next(&s, pts, 1, &info));
    TEST_ASSERT_EQUAL_INT(2, info.npoints);
    TEST_ASSERT_EQUAL_INT(1, info.stored);
    TEST_ASSERT_EQUAL_INT(1, info.overflow);
    TEST_ASSERT_EQUAL_INT(1, pts[0].x);
    TEST_ASSERT_EQUAL_INT(15, pts[0].y);
    TEST_ASSERT_EQUAL_FLOAT(0.0f, info.area);
    TEST_ASSERT_EQUAL_INT(0, actag_contour_next(&s, pts, 8, &info));
    TEST_ASSERT_EQUAL_INT(0, actag_contour_next(&s, pts, 8, &info));
    free(t.px);
    free(bm);
    free(mk);
}

/* Emulated: the reference needs ~20 MB for a whole frame, more than the
 * board's 16 MB heap, so the two halves of every frame are checked apart. */
#define REAL_BANDS (TU_EMULATED ? 2 : 1)

static void test_real_sonar_frames(void)
{
    static const char *const frames[2] = {"f_0001.pgm", "f_0291.pgm"};
    static const int thresholds[3] = {10, 20, 40};
    int f, th, band;
    for (f = 0; f < 2; f++) {
        char path[600];
        int rows = 0, cols = 0, i;
        uint8_t *px;
        snprintf(path, sizeof path, "%s/pool-video/%s", TU_DATA, frames[f]);
        px = tu_read_pgm(path, &rows, &cols);
        TEST_ASSERT_EQUAL_INT(530, rows);
        TEST_ASSERT_EQUAL_INT(512, cols);
        for (th = 0; th < 3; th++) {
            int contours = 0;
            for (band = 0; band < REAL_BANDS; band++) {
                timg t;
                int r0 = band * rows / REAL_BANDS, r1 = (band + 1) * rows / REAL_BANDS;
                const uint8_t *src = px + (size_t)r0 * (size_t)cols;
                t.rows = r1 - r0;
                t.cols = cols;
                t.stride = cols;
                t.px = (uint8_t *)malloc((size_t)t.rows * (size_t)cols);
                TEST_ASSERT_NOT_NULL(t.px);
                for (i = 0; i < t.rows * cols; i++)
                    t.px[i] = src[i] >= thresholds[th] ? src[i] : 0;
                contours += check_image(&t);
                free(t.px);
            }
            TEST_ASSERT_GREATER_THAN(100, contours);
        }
        free(px);
    }
}

static void test_errors(void)
{
    uint8_t img[12] = {0, 1, 0, 1, 1, 1, 0, 0, 0, 0, 0, 1};
    uint32_t bm[ACTAG_BITMAP_SIZE(3, 4) / 4], mk[ACTAG_BITMAP_SIZE(3, 4) / 4];
    actag_contour_scanner s;
    actag_contour_info info;
    actag_ipoint pts[4];
    uint8_t back[12];
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_bitmap_pack(NULL, 3, 4, 4, bm));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_bitmap_pack(img, 3, 4, 4, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_bitmap_pack(img, 0, 4, 4, bm));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_bitmap_pack(img, 3, 4, 3, bm));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_bitmap_pack(img, 3, ACTAG_MAX_DIM + 1, ACTAG_MAX_DIM + 1, bm));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_bitmap_unpack(NULL, 3, 4, back, 4, 1u));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_bitmap_unpack(bm, 3, 4, NULL, 4, 1u));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_bitmap_unpack(bm, 3, 4, back, 3, 1u));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_bitmap_unpack(bm, -1, 4, back, 4, 1u));
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_bitmap_pack(img, 3, 4, 4, bm));
    memset(mk, 0x77, sizeof mk);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_contour_scanner_init(NULL, bm, mk, 3, 4));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_contour_scanner_init(&s, NULL, mk, 3, 4));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_contour_scanner_init(&s, bm, NULL, 3, 4));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_contour_scanner_init(&s, bm, mk, 0, 4));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_contour_scanner_init(&s, bm, mk, 3, 0));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_contour_scanner_init(&s, bm, mk, -1, 4));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_contour_scanner_init(&s, bm, mk, ACTAG_MAX_DIM + 1, 1));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_contour_scanner_init(&s, bm, mk, 1, ACTAG_MAX_DIM + 1));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_contour_scanner_init(&s, bm, bm, 3, 4));
    /* Failed inits wrote nothing. */
    TEST_ASSERT_EQUAL_HEX32(0x77777777u, mk[0]);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_contour_scanner_init(&s, bm, mk, 3, 4));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_contour_next(NULL, pts, 4, &info));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_contour_next(&s, pts, 4, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_contour_next(&s, NULL, 4, &info));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_contour_next(&s, pts, -1, &info));
    /* Errors do not advance the scan. */
    TEST_ASSERT_EQUAL_INT(1, actag_contour_next(&s, pts, 4, &info));
    TEST_ASSERT_EQUAL_INT(3, info.npoints); /* (x,y) = (1,0) (0,1) (1,1) */
    TEST_ASSERT_EQUAL_INT(1, pts[0].x);
    TEST_ASSERT_EQUAL_INT(0, pts[0].y);
    TEST_ASSERT_EQUAL_INT(0, pts[1].x);
    TEST_ASSERT_EQUAL_INT(1, pts[1].y);
    TEST_ASSERT_EQUAL_INT(1, pts[2].x);
    TEST_ASSERT_EQUAL_INT(1, pts[2].y);
    TEST_ASSERT_EQUAL_FLOAT(0.5f, info.area);
    TEST_ASSERT_EQUAL_INT(1, actag_contour_next(&s, NULL, 0, &info)); /* (3,0) */
    TEST_ASSERT_EQUAL_INT(1, info.npoints);
    TEST_ASSERT_EQUAL_INT(3, info.min_x);
    TEST_ASSERT_EQUAL_INT(0, info.min_y);
    TEST_ASSERT_EQUAL_INT(1, actag_contour_next(&s, pts, 4, &info)); /* (3,2) */
    TEST_ASSERT_EQUAL_INT(1, info.npoints);
    TEST_ASSERT_EQUAL_INT(3, pts[0].x);
    TEST_ASSERT_EQUAL_INT(2, pts[0].y);
    TEST_ASSERT_EQUAL_INT(0, actag_contour_next(&s, NULL, 0, &info));
    /* Uninitialised scanner. */
    memset(&s, 0, sizeof s);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_contour_next(&s, pts, 4, &info));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_errors);
    RUN_TEST(test_rectangle_geometry);
    RUN_TEST(test_overflow_then_continue);
    RUN_TEST(test_edge_cases);
    RUN_TEST(test_one_pixel_holes_beside_notches);
    RUN_TEST(test_nested_rings);
    RUN_TEST(test_random_images);
    RUN_TEST(test_larger_images);
    RUN_TEST(test_real_sonar_frames);
    return UNITY_END();
}
