/* Quadrilateral fitting (RANSAC, paper Algorithm 2): synthetic parallelograms
 * with known corners, traced rasterised squares, rejection of circles, blobs,
 * trapezoids and kites, determinism, a brute-force recount of the reported
 * inlier ratio, error codes and scratch size. */
#include "unity.h"
#include "test_util.h"

#include <math.h>
#include <time.h>

#include "actag/quad.h"

void setUp(void) {}
void tearDown(void) {}

#define MAXP 8192
static actag_ipoint g_pts[MAXP];
static unsigned char g_scratch[ACTAG_QUAD_SCRATCH_SIZE(MAXP)];

/* ------------------------------------------------------------ helpers */

static double urand(void) { return (double)tu_rand() / 4294967296.0; }
/* Roughly Gaussian, unit variance (sum of 4 uniforms). The draws are summed
 * one statement at a time: operands of + are evaluated in an unspecified
 * order, and a different order would change the sum's rounding. */
static double nrand(void)
{
    double s = urand();
    s += urand();
    s += urand();
    s += urand();
    return (s - 2.0) * 1.7320508;
}

static short clamp16(double v)
{
    double r = floor(v + 0.5);
    if (r < -32768.0)
        r = -32768.0;
    if (r > 32767.0)
        r = 32767.0;
    return (short)r;
}

/* Signed area * 2 of a polygon; > 0 means clockwise on screen (y down). */
static double shoelace(const double *x, const double *y, int n)
{
    double s = 0;
    int i;
    for (i = 0; i < n; i++) {
        int j = (i + 1) % n;
        s += x[i] * y[j] - x[j] * y[i];
    }
    return s;
}

/* Contour along the polygon (cx, cy)[0..3]: ~1 px spacing, Gaussian noise
 * sigma, a fraction of outliers pushed 5..8 px off the side (only when every
 * side is >= 20 px: on smaller quads a cluster of them can legitimately make
 * a different quad pass the inlier test), rounded to integer pixels; random
 * start point and direction. Returns the count. */
static int g_side[MAXP]; /* side of each generated point, -1 for an outlier */
static int make_contour(const double *cx, const double *cy, double sigma, double outlier_frac,
                        actag_ipoint *out, int cap)
{
    static actag_ipoint tmp[MAXP];
    static int tside[MAXP];
    int n = 0, s, i, start, rev;
    double min_len = 1e30;
    for (s = 0; s < 4; s++) {
        double l = hypot(cx[(s + 1) % 4] - cx[s], cy[(s + 1) % 4] - cy[s]);
        min_len = l < min_len ? l : min_len;
    }
    for (s = 0; s < 4; s++) {
        double x0 = cx[s], y0 = cy[s], x1 = cx[(s + 1) % 4], y1 = cy[(s + 1) % 4];
        double len = sqrt((x1 - x0) * (x1 - x0) + (y1 - y0) * (y1 - y0));
        int steps = (int)ceil(len), k;
        double nx = -(y1 - y0) / len, ny = (x1 - x0) / len;
        for (k = 0; k < steps && n < cap; k++) {
            double t = (double)k / steps;
            double px = x0 + t * (x1 - x0), py = y0 + t * (y1 - y0);
            double off = sigma * nrand();
            tside[n] = s;
            if (urand() < outlier_frac && min_len >= 20.0) {
                double sign = urand() < 0.5 ? -1.0 : 1.0; /* two draws, in this order */
                off += sign * (5.0 + 3.0 * urand());
                tside[n] = -1;
            }
            tmp[n].x = clamp16(px + off * nx);
            tmp[n].y = clamp16(py + off * ny);
            n++;
        }
    }
    start = (int)(tu_rand() % (uint32_t)n);
    rev = (int)(tu_rand() & 1u);
    for (i = 0; i < n; i++) {
        int j = rev ? (start - i + n) % n : (start + i) % n;
        out[i] = tmp[j];
        g_side[i] = tside[j];
    }
    return n;
}

/* Oracle: the best any fit can do -- double-precision total least squares
 * of each side's own generated points (outliers excluded), intersected. */
static void oracle_corners(const actag_ipoint *pts, int n, double *ox, double *oy)
{
    double nx[4], ny[4], c[4];
    int s, i;
    for (s = 0; s < 4; s++) {
        double m = 0, mx = 0, my = 0, a = 0, b = 0, cc = 0, th;
        for (i = 0; i < n; i++)
            if (g_side[i] == s) {
                m++;
                mx += pts[i].x;
                my += pts[i].y;
            }
        mx /= m;
        my /= m;
        for (i = 0; i < n; i++)
            if (g_side[i] == s) {
                double dx = pts[i].x - mx, dy = pts[i].y - my;
                a += dx * dx;
                b += dx * dy;
                cc += dy * dy;
            }
        th = 0.5 * atan2(2 * b, a - cc); /* direction of the major axis */
        nx[s] = -sin(th);
        ny[s] = cos(th);
        c[s] = nx[s] * mx + ny[s] * my;
    }
    for (s = 0; s < 4; s++) { /* corner s+1 joins sides s and s+1 */
        int t = (s + 1) % 4;
        double det = nx[s] * ny[t] - ny[s] * nx[t];
        ox[t] = (c[s] * ny[t] - c[t] * ny[s]) / det;
        oy[t] = (nx[s] * c[t] - nx[t] * c[s]) / det;
    }
}

/* Random parallelogram with sides in [lmin, lmax] px and sub-pixel corners. */
static void random_parallelogram(double lmin, double lmax, double *cx, double *cy)
{
    double th = urand() * 6.283185307179586, al;
    double l1 = lmin + (lmax - lmin) * urand(), l2;
    double ox = 100.0 + 200.0 * urand(), oy = 100.0 + 200.0 * urand();
    double ux, uy, vx, vy;
    int kind = (int)(tu_rand() % 3u);
    if (kind == 0) { /* rotated square */
        l2 = l1;
        al = 1.5707963267948966;
    } else if (kind == 1) { /* rhombus */
        l2 = l1;
        al = (0.35 + 0.3 * urand()) * 3.141592653589793;
    } else { /* general parallelogram */
        l2 = lmin + (lmax - lmin) * urand();
        al = (0.3 + 0.4 * urand()) * 3.141592653589793;
    }
    if (tu_rand() & 1u)
        al = -al;
    ux = l1 * cos(th);
    uy = l1 * sin(th);
    vx = l2 * cos(th + al);
    vy = l2 * sin(th + al);
    cx[0] = ox;
    cy[0] = oy;
    cx[1] = ox + ux;
    cy[1] = oy + uy;
    cx[2] = ox + ux + vx;
    cy[2] = oy + uy + vy;
    cx[3] = ox + vx;
    cy[3] = oy + vy;
}

/* Truth corners reordered clockwise on screen. */
static void truth_clockwise(double *cx, double *cy)
{
    if (shoelace(cx, cy, 4) < 0) {
        double t = cx[1];
        cx[1] = cx[3];
        cx[3] = t;
        t = cy[1];
        cy[1] = cy[3];
        cy[3] = t;
    }
}

/* Largest corner error after the best cyclic shift (same orientation). */
static double corner_error(const actag_quad *q, const double *cx, const double *cy)
{
    double best = 1e30;
    int s, i;
    for (s = 0; s < 4; s++) {
        double worst = 0;
        for (i = 0; i < 4; i++) {
            double dx = q->corners[i].x - cx[(i + s) % 4], dy = q->corners[i].y - cy[(i + s) % 4];
            double e = sqrt(dx * dx + dy * dy);
            worst = e > worst ? e : worst;
        }
        best = worst < best ? worst : best;
    }
    return best;
}

/* Distance from p to segment ab (double, independent of the library). */
static double seg_dist(double px, double py, double ax, double ay, double bx, double by)
{
    double vx = bx - ax, vy = by - ay, wx = px - ax, wy = py - ay;
    double l2 = vx * vx + vy * vy, t = l2 > 0 ? (wx * vx + wy * vy) / l2 : 0.0;
    double dx, dy;
    if (t < 0)
        t = 0;
    if (t > 1)
        t = 1;
    dx = wx - t * vx;
    dy = wy - t * vy;
    return sqrt(dx * dx + dy * dy);
}

/* Everything a returned quad must satisfy, checked from scratch: clockwise
 * convex order, topmost corner first, parallel opposite sides, the required
 * inlier ratio, and the reported inlier ratio equal to a brute-force recount
 * (points within 1e-3 px of the threshold may go either way). */
static void check_quad_invariants(const actag_ipoint *pts, int n, const actag_quad_params *p,
                                  const actag_quad *q)
{
    double x[4], y[4], d = p->inlier_distance;
    int i, j, sure = 0, maybe = 0, ok = 0, c;
    for (i = 0; i < 4; i++) {
        x[i] = q->corners[i].x;
        y[i] = q->corners[i].y;
    }
    for (i = 0; i < 4; i++) {
        int i1 = (i + 1) % 4, i2 = (i + 2) % 4;
        double cr = (x[i1] - x[i]) * (y[i2] - y[i1]) - (y[i1] - y[i]) * (x[i2] - x[i1]);
        TEST_ASSERT_TRUE_MESSAGE(cr > 0, "corners not convex clockwise");
        if (i > 0)
            TEST_ASSERT_TRUE_MESSAGE(y[0] < y[i] || (y[0] == y[i] && x[0] <= x[i]),
                                     "first corner not topmost");
    }
    for (i = 0; i < 2; i++) {
        double ax = x[i + 1] - x[i], ay = y[i + 1] - y[i];
        double bx = x[(i + 3) % 4] - x[i + 2], by = y[(i + 3) % 4] - y[i + 2];
        double cs = fabs(ax * bx + ay * by) / sqrt((ax * ax + ay * ay) * (bx * bx + by * by));
        TEST_ASSERT_TRUE_MESSAGE(cs >= p->min_parallel_cos - 1e-5, "not a parallelogram");
    }
    for (i = 0; i < n; i++) {
        double best = 1e30;
        for (j = 0; j < 4; j++) {
            double e = seg_dist(pts[i].x, pts[i].y, x[j], y[j], x[(j + 1) % 4], y[(j + 1) % 4]);
            best = e < best ? e : best;
        }
        if (best <= d - 1e-3)
            sure++;
        else if (best <= d + 1e-3)
            maybe++;
    }
    for (c = sure; c <= sure + maybe; c++)
        if ((float)c / (float)n == q->inlier_ratio)
            ok = 1;
    TEST_ASSERT_TRUE_MESSAGE(ok, "inlier_ratio differs from a brute-force recount");
    TEST_ASSERT_TRUE(q->inlier_ratio >= (p->min_inlier_ratio < p->inlier_ratio ? p->min_inlier_ratio
                                                                                : p->inlier_ratio));
    TEST_ASSERT_TRUE(q->iterations >= 1 && q->iterations <= p->max_iterations);
}

static int fit(const actag_ipoint *pts, int n, const actag_quad_params *p, uint32_t seed,
               actag_quad *q)
{
    actag_rng r;
    actag_rng_seed(&r, seed);
    return actag_quad_fit(pts, n, p, &r, g_scratch, sizeof g_scratch, q);
}

/* ------------------------------------------------------------ raster + tracer */

#define IMG 256
static unsigned char g_img[IMG * IMG];

static int inside_convex(double px, double py, const double *cx, const double *cy, int n)
{
    int i;
    double sgn = shoelace(cx, cy, n) > 0 ? 1.0 : -1.0;
    for (i = 0; i < n; i++) {
        int j = (i + 1) % n;
        double cr = (cx[j] - cx[i]) * (py - cy[i]) - (cy[j] - cy[i]) * (px - cx[i]);
        if (cr * sgn < 0)
            return 0;
    }
    return 1;
}

static void raster_convex(const double *cx, const double *cy, int n)
{
    int r, c;
    for (r = 0; r < IMG; r++)
        for (c = 0; c < IMG; c++)
            g_img[r * IMG + c] = (unsigned char)inside_convex(c, r, cx, cy, n);
}

/* Star-shaped blob: radius R0 * (1 + sum a_k cos(k t + p_k)) around (x0, y0). */
static void raster_blob(double x0, double y0, double r0, const double *amp, const double *ph,
                        const int *harm, int nh)
{
    int r, c, k;
    double sum = 0.0, rin, rout;
    for (k = 0; k < nh; k++)
        sum += fabs(amp[k]);
    /* r0 * rad lies in [r0 (1 - sum), r0 (1 + sum)]: pixels a pixel or more
     * outside that ring are decided without the trigonometry (the same
     * image, far fewer atan2/cos calls: they are slow under emulation) */
    rin = r0 * (1.0 - sum) - 1.0;
    rout = r0 * (1.0 + sum) + 1.0;
    for (r = 0; r < IMG; r++)
        for (c = 0; c < IMG; c++) {
            double dx = c - x0, dy = r - y0, d2 = dx * dx + dy * dy, t, rad = 1.0;
            if (d2 > rout * rout || (rin > 0.0 && d2 < rin * rin)) {
                g_img[r * IMG + c] = (unsigned char)(d2 < rout * rout);
                continue;
            }
            t = atan2(dy, dx);
            for (k = 0; k < nh; k++)
                rad += amp[k] * cos(harm[k] * t + ph[k]);
            g_img[r * IMG + c] = (unsigned char)(sqrt(d2) <= r0 * rad);
        }
}

static int fg(int x, int y) { return x >= 0 && y >= 0 && x < IMG && y < IMG && g_img[y * IMG + x]; }

/* Moore-neighbour border tracing of the first blob in raster order: a closed
 * 8-connected loop, clockwise on screen. */
static int trace(actag_ipoint *out, int cap)
{
    static const int dx[8] = {1, 1, 0, -1, -1, -1, 0, 1};
    static const int dy[8] = {0, 1, 1, 1, 0, -1, -1, -1};
    int sx = -1, sy = -1, x, y, b, n = 0, i;
    for (i = 0; i < IMG * IMG && sx < 0; i++)
        if (g_img[i]) {
            sx = i % IMG;
            sy = i / IMG;
        }
    if (sx < 0)
        return 0;
    x = sx;
    y = sy;
    b = 4; /* the backtrack (a background pixel) lies west of the start */
    do {
        int k, d = -1;
        if (n < cap)
            out[n++] = (actag_ipoint){(int16_t)x, (int16_t)y};
        for (k = 1; k <= 8; k++) {
            int dd = (b + k) & 7;
            if (fg(x + dx[dd], y + dy[dd])) {
                d = dd;
                break;
            }
        }
        if (d < 0)
            break; /* isolated pixel */
        {
            int px = x + dx[(d + 7) & 7], py = y + dy[(d + 7) & 7];
            x += dx[d];
            y += dy[d];
            for (k = 0; k < 8; k++)
                if (x + dx[k] == px && y + dy[k] == py)
                    b = k;
        }
    } while (!(x == sx && y == sy) && n < cap);
    return n;
}

/* Corners of the polygon with each edge moved inward by half a pixel's
 * extent along its normal: where the centres of the traced border pixels lie
 * on average (0 .. max(|nx|,|ny|) inside the true edge). */
static void inset_corners(const double *cx, const double *cy, double *ix, double *iy)
{
    double nx[4], ny[4], c[4];
    int s;
    for (s = 0; s < 4; s++) { /* clockwise on screen: the inward normal is (-ey, ex) */
        double ex = cx[(s + 1) % 4] - cx[s], ey = cy[(s + 1) % 4] - cy[s];
        double l = sqrt(ex * ex + ey * ey), off;
        nx[s] = -ey / l;
        ny[s] = ex / l;
        off = 0.5 * (fabs(nx[s]) > fabs(ny[s]) ? fabs(nx[s]) : fabs(ny[s]));
        c[s] = nx[s] * cx[s] + ny[s] * cy[s] + off;
    }
    for (s = 0; s < 4; s++) { /* corner s+1 joins edges s and s+1 */
        int t = (s + 1) % 4;
        double det = nx[s] * ny[t] - ny[s] * nx[t];
        ix[t] = (c[s] * ny[t] - c[t] * ny[s]) / det;
        iy[t] = (nx[s] * c[t] - nx[t] * c[s]) / det;
    }
}

/* Centres the polygon in the test image, keeping its sub-pixel offset. */
static void centre_in_image(double *cx, double *cy, int n)
{
    double mx = 0, my = 0;
    int z;
    for (z = 0; z < n; z++) {
        mx += cx[z] / n;
        my += cy[z] / n;
    }
    for (z = 0; z < n; z++) {
        cx[z] += IMG / 2 - floor(mx);
        cy[z] += IMG / 2 - floor(my);
    }
}

static double min_side(const double *cx, const double *cy)
{
    double a = hypot(cx[1] - cx[0], cy[1] - cy[0]), b = hypot(cx[2] - cx[1], cy[2] - cy[1]);
    return a < b ? a : b;
}

/* ------------------------------------------------------------ tests */

static void test_params_default(void)
{
    actag_quad_params p;
    actag_quad_params_default(&p);
    TEST_ASSERT_EQUAL_INT(500, p.max_iterations);
    TEST_ASSERT_EQUAL_FLOAT(0.10f, p.sample_fraction);
    TEST_ASSERT_EQUAL_FLOAT(0.85f, p.inlier_ratio);
    TEST_ASSERT_EQUAL_FLOAT(2.5f, p.inlier_distance);
    TEST_ASSERT_EQUAL_FLOAT(0.9f, p.min_parallel_cos);
    actag_quad_params_default(NULL); /* must not crash */
}

/* A clean 30 px square contour (1 px steps) used by the API tests. */
static int square_contour(actag_ipoint *pts, int x0, int y0, int side)
{
    int n = 0, i;
    for (i = 0; i < side; i++)
        pts[n++] = (actag_ipoint){(int16_t)(x0 + i), (int16_t)y0};
    for (i = 0; i < side; i++)
        pts[n++] = (actag_ipoint){(int16_t)(x0 + side), (int16_t)(y0 + i)};
    for (i = 0; i < side; i++)
        pts[n++] = (actag_ipoint){(int16_t)(x0 + side - i), (int16_t)(y0 + side)};
    for (i = 0; i < side; i++)
        pts[n++] = (actag_ipoint){(int16_t)x0, (int16_t)(y0 + side - i)};
    return n;
}

static void test_error_codes_and_scratch_size(void)
{
    actag_quad_params p, b;
    actag_rng r;
    actag_quad q;
    int n = square_contour(g_pts, 10, 20, 30), k;
    size_t need = ACTAG_QUAD_SCRATCH_SIZE(n);
    actag_quad_params_default(&p);
    actag_rng_seed(&r, 1);
    TEST_ASSERT_EQUAL_UINT((size_t)n * 9u + 4u, need); /* documented: 9 bytes a point + 4 */

    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_quad_fit(NULL, n, &p, &r, g_scratch, need, &q));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_quad_fit(g_pts, n, NULL, &r, g_scratch, need, &q));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_quad_fit(g_pts, n, &p, NULL, g_scratch, need, &q));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_quad_fit(g_pts, n, &p, &r, NULL, need, &q));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_quad_fit(g_pts, n, &p, &r, g_scratch, need, NULL));

    /* Each invalid parameter on its own. */
    for (k = 0; k < 20; k++) {
        b = p;
        switch (k) {
        case 17: b.min_inlier_ratio = 0.0f; break;
        case 18: b.min_inlier_ratio = 1.5f; break;
        case 19: b.min_inlier_ratio = NAN; break;
        case 0: b.max_iterations = 0; break;
        case 1: b.max_iterations = -5; break;
        case 2: b.sample_fraction = 0.0f; break;
        case 3: b.sample_fraction = -0.1f; break;
        case 4: b.sample_fraction = 1.01f; break;
        case 5: b.sample_fraction = NAN; break;
        case 6: b.inlier_ratio = 0.0f; break;
        case 7: b.inlier_ratio = 1.5f; break;
        case 8: b.inlier_ratio = NAN; break;
        case 9: b.inlier_distance = 0.0f; break;
        case 10: b.inlier_distance = -1.0f; break;
        case 11: b.inlier_distance = INFINITY; break;
        case 12: b.inlier_distance = NAN; break;
        case 13: b.min_parallel_cos = -0.01f; break;
        case 14: b.min_parallel_cos = 1.01f; break;
        case 15: b.min_parallel_cos = NAN; break;
        default: b.inlier_ratio = -0.5f; break;
        }
        TEST_ASSERT_EQUAL_INT_MESSAGE(ACTAG_ERR_PARAM,
                                      actag_quad_fit(g_pts, n, &b, &r, g_scratch, need, &q),
                                      "invalid parameter accepted");
    }
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_quad_fit(g_pts, -1, &p, &r, g_scratch, need, &q));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_quad_fit(g_pts, ACTAG_QUAD_MAX_POINTS + 1, &p, &r,
                                                         g_scratch, (size_t)1 << 20, &q));
    {
        /* exactly ACTAG_QUAD_MAX_POINTS points (the border of a square of
         * 8191 pixels, its first 3 points again) is a size it takes */
        actag_ipoint *big = (actag_ipoint *)malloc(ACTAG_QUAD_MAX_POINTS * sizeof *big);
        size_t bs = ACTAG_QUAD_SCRATCH_SIZE(ACTAG_QUAD_MAX_POINTS);
        void *bscr = malloc(bs);
        int i, side = 8191, rc;
        actag_quad_params few;
        TEST_ASSERT_NOT_NULL(big);
        TEST_ASSERT_NOT_NULL(bscr);
        for (i = 0; i < 4 * side; i++) {
            int e = i / side, o = i % side;
            big[i].x = (int16_t)(e == 0 ? o : e == 1 ? side : e == 2 ? side - o : 0);
            big[i].y = (int16_t)(e == 0 ? 0 : e == 1 ? o : e == 2 ? side : side - o);
        }
        for (; i < ACTAG_QUAD_MAX_POINTS; i++)
            big[i] = big[i - 4 * side];
        /* a few iterations: the clean square needs no more, and the
         * emulated suites' Cortex-M runs stay short */
        few = p;
        few.max_iterations = 4;
        rc = actag_quad_fit(big, ACTAG_QUAD_MAX_POINTS, &few, &r, bscr, bs, &q);
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, rc);
        check_quad_invariants(big, ACTAG_QUAD_MAX_POINTS, &few, &q);
        free(big);
        free(bscr);
    }

    /* Scratch: one byte short fails, exact size works. */
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE, actag_quad_fit(g_pts, n, &p, &r, g_scratch, need - 1, &q));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE, actag_quad_fit(g_pts, n, &p, &r, g_scratch, 0, &q));
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_quad_fit(g_pts, n, &p, &r, g_scratch, need, &q));
    check_quad_invariants(g_pts, n, &p, &q);

    /* Boundary values of the parameters are valid. */
    b = p;
    b.sample_fraction = 1.0f;
    b.min_parallel_cos = 1.0f;
    b.max_iterations = 1;
    k = actag_quad_fit(g_pts, n, &b, &r, g_scratch, need, &q);
    TEST_ASSERT_TRUE(k == ACTAG_OK || k == ACTAG_ERR_NO_QUAD);
    b = p;
    b.inlier_ratio = 1.0f;
    b.min_parallel_cos = 0.0f;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_quad_fit(g_pts, n, &b, &r, g_scratch, need, &q));
    TEST_ASSERT_EQUAL_FLOAT(1.0f, q.inlier_ratio);

    /* Too few points: no quad, output cleared, no iterations. */
    for (k = 0; k < ACTAG_QUAD_MIN_POINTS; k++) {
        memset(&q, 0x55, sizeof q);
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_QUAD, actag_quad_fit(g_pts, k, &p, &r, g_scratch, need, &q));
        TEST_ASSERT_EQUAL_INT(0, q.iterations);
        TEST_ASSERT_EQUAL_FLOAT(0.0f, q.inlier_ratio);
        TEST_ASSERT_EQUAL_FLOAT(0.0f, q.corners[3].y);
    }
    TEST_ASSERT_EQUAL_STRING("no quadrilateral could be fitted", actag_strerror(ACTAG_ERR_NO_QUAD));
}

/* A 40 px square with a 20 px one-pixel spike sticking out of its right
 * side (walked out and back): no quad explains much more than 80 % of it.
 * The reference semantics: the search only stops early at inlier_ratio
 * ("desired"); after max_iterations the best quad found is returned if it
 * reaches min_inlier_ratio ("required"). */
static void test_desired_and_required_ratio(void)
{
    actag_quad_params p;
    actag_quad q, q2;
    int n = 0, i, rc;
    for (i = 0; i < 40; i++)
        g_pts[n++] = (actag_ipoint){(int16_t)(100 + i), 100};
    for (i = 0; i < 20; i++)
        g_pts[n++] = (actag_ipoint){140, (int16_t)(100 + i)};
    for (i = 1; i <= 20; i++)
        g_pts[n++] = (actag_ipoint){(int16_t)(140 + i), 120};
    for (i = 19; i >= 1; i--)
        g_pts[n++] = (actag_ipoint){(int16_t)(140 + i), 120};
    for (i = 0; i < 20; i++)
        g_pts[n++] = (actag_ipoint){140, (int16_t)(120 + i)};
    for (i = 0; i < 40; i++)
        g_pts[n++] = (actag_ipoint){(int16_t)(140 - i), 140};
    for (i = 0; i < 40; i++)
        g_pts[n++] = (actag_ipoint){100, (int16_t)(140 - i)};
    actag_quad_params_default(&p);
    p.max_iterations = 200;
    rc = fit(g_pts, n, &p, 9, &q);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, rc);
    check_quad_invariants(g_pts, n, &p, &q);
    TEST_ASSERT_TRUE(q.inlier_ratio >= p.min_inlier_ratio && q.inlier_ratio < p.inlier_ratio);
    TEST_ASSERT_EQUAL_INT(p.max_iterations, q.iterations); /* no early stop */
    TEST_ASSERT_EQUAL_INT(0, q.stopped_early);
    TEST_ASSERT_FLOAT_WITHIN(0.2f, 100.0f, q.corners[0].x);
    TEST_ASSERT_FLOAT_WITHIN(0.2f, 100.0f, q.corners[0].y);
    TEST_ASSERT_FLOAT_WITHIN(0.2f, 140.0f, q.corners[2].x);
    TEST_ASSERT_FLOAT_WITHIN(0.2f, 140.0f, q.corners[2].y);
    /* Requiring the desired ratio turns it down ... */
    p.min_inlier_ratio = 0.85f;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_QUAD, fit(g_pts, n, &p, 9, &q2));
    TEST_ASSERT_EQUAL_INT(p.max_iterations, q2.iterations);
    TEST_ASSERT_EQUAL_INT(0, q2.stopped_early);
    /* ... a required ratio above the desired one is capped at it ... */
    p.min_inlier_ratio = 0.95f;
    p.inlier_ratio = 0.8f;
    rc = fit(g_pts, n, &p, 9, &q2);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, rc);
    /* ... and desiring what it has stops the search early. */
    TEST_ASSERT_LESS_THAN(p.max_iterations, q2.iterations);
    TEST_ASSERT_EQUAL_INT(1, q2.stopped_early);
    TEST_ASSERT_TRUE(q2.inlier_ratio >= 0.8f);
    /* A stop on the last allowed iteration is still early: with exactly the
     * iterations it took, the fit is the same and says it stopped early (so
     * iterations == max_iterations does not mean the cap ran out). */
    p.max_iterations = q2.iterations;
    rc = fit(g_pts, n, &p, 9, &q);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, rc);
    TEST_ASSERT_EQUAL_INT(p.max_iterations, q.iterations);
    TEST_ASSERT_EQUAL_INT(1, q.stopped_early);
    TEST_ASSERT_EQUAL_MEMORY(q2.corners, q.corners, sizeof q.corners);
    /* one fewer: the cap runs out before the stopping quad */
    if (q2.iterations > 1) {
        p.max_iterations = q2.iterations - 1;
        (void)fit(g_pts, n, &p, 9, &q);
        TEST_ASSERT_EQUAL_INT(p.max_iterations, q.iterations);
        TEST_ASSERT_EQUAL_INT(0, q.stopped_early);
    }
}

/* Parallelograms whose sides lie on lattice lines: every contour point is
 * exactly on a side (no rounding), corners are sub-pixel (multiples of 1/5
 * or 1/2 px). The fit must be exact to float precision. */
static void test_exact_lattice_parallelograms(void)
{
    static const int dirs[8][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}, {2, 1}, {1, 2}, {2, -1}, {1, -2}};
    actag_quad_params p;
    int t, done = 0;
    actag_quad_params_default(&p);
    tu_seed(5);
    for (t = 0; t < 400 && done < 150; t++) {
        int a = tu_range(0, 7), b = tu_range(0, 7), s, n = 0, ok = 1, rc;
        long nx[4], ny[4], c[4];
        double cx[4], cy[4];
        actag_quad q;
        double cr = (double)dirs[a][0] * dirs[b][1] - (double)dirs[a][1] * dirs[b][0];
        double sn = fabs(cr) / hypot(dirs[a][0], dirs[a][1]) / hypot(dirs[b][0], dirs[b][1]);
        int w1 = tu_range(15, 45), w2 = tu_range(15, 45), x0 = tu_range(100, 200), y0 = tu_range(100, 200);
        if (sn < 0.4)
            continue;
        /* Lines n . x = c with integer normals: sides a, b, a, b. */
        nx[0] = -dirs[a][1], ny[0] = dirs[a][0];
        nx[1] = -dirs[b][1], ny[1] = dirs[b][0];
        nx[2] = nx[0], ny[2] = ny[0];
        nx[3] = nx[1], ny[3] = ny[1];
        /* lines 0 and 3 pass through (x0, y0) (+ a sub-pixel shift for 3),
         * 1 and 2 are their parallels w1 and w2 units away */
        c[0] = nx[0] * x0 + ny[0] * y0;
        c[3] = nx[3] * x0 + ny[3] * y0 + tu_range(0, 1);
        c[1] = c[3] + w1 * (nx[1] * dirs[a][0] + ny[1] * dirs[a][1] > 0 ? 1 : -1);
        c[2] = c[0] + w2 * (nx[0] * dirs[b][0] + ny[0] * dirs[b][1] > 0 ? 1 : -1);
        /* Corner s joins lines s-1 and s. */
        for (s = 0; s < 4; s++) {
            int u = (s + 3) % 4;
            double det = (double)nx[u] * ny[s] - (double)ny[u] * nx[s];
            cx[s] = ((double)c[u] * ny[s] - (double)c[s] * ny[u]) / det;
            cy[s] = ((double)nx[u] * c[s] - (double)nx[s] * c[u]) / det;
        }
        /* The lattice points of line s between corners s and s+1. */
        for (s = 0; s < 4 && ok; s++) {
            double ax = cx[s], ay = cy[s], bx = cx[(s + 1) % 4], by = cy[(s + 1) % 4];
            long dx = ny[s], dy = -nx[s], px, py, i, lo, hi;
            double len2 = (double)(dx * dx + dy * dy), ta, tb;
            /* a lattice point on the line: solve nx*px + ny*py = c by search */
            long found = 0;
            px = py = 0;
            for (i = -3; i <= 3 && !found; i++) {
                long j;
                for (j = -3; j <= 3; j++) {
                    long qx = (long)floor(ax) + i, qy = (long)floor(ay) + j;
                    if (nx[s] * qx + ny[s] * qy == c[s]) {
                        px = qx;
                        py = qy;
                        found = 1;
                        break;
                    }
                }
            }
            if (!found) {
                ok = 0;
                break;
            }
            ta = ((ax - px) * dx + (ay - py) * dy) / len2;
            tb = ((bx - px) * dx + (by - py) * dy) / len2;
            if (ta < tb) {
                lo = (long)ceil(ta + 1e-9);
                hi = (long)floor(tb - 1e-9);
                for (i = lo; i <= hi && n < MAXP; i++)
                    g_pts[n++] = (actag_ipoint){(int16_t)(px + i * dx), (int16_t)(py + i * dy)};
            } else {
                lo = (long)floor(ta - 1e-9);
                hi = (long)ceil(tb + 1e-9);
                for (i = lo; i >= hi && n < MAXP; i--)
                    g_pts[n++] = (actag_ipoint){(int16_t)(px + i * dx), (int16_t)(py + i * dy)};
            }
        }
        if (!ok || n < 40)
            continue;
        truth_clockwise(cx, cy);
        rc = fit(g_pts, n, &p, (uint32_t)t, &q);
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, rc);
        check_quad_invariants(g_pts, n, &p, &q);
        TEST_ASSERT_EQUAL_FLOAT(1.0f, q.inlier_ratio);
        if (corner_error(&q, cx, cy) > 0.01) {
            char msg[160];
            snprintf(msg, sizeof msg, "lattice trial %d: corner error %.4f px", t,
                     corner_error(&q, cx, cy));
            TEST_FAIL_MESSAGE(msg);
        }
        done++;
    }
    TEST_ASSERT_GREATER_OR_EQUAL(100, done);
}

/* Random parallelograms (squares, rhombi, general; sides 10-60 px,
 * sub-pixel corners) sampled every ~1 px with noise (sigma 0.2 px), 2 %
 * outliers 5-8 px off, rounded to integer pixels. Integer rounding alone
 * moves a near-axis side by up to 0.5 px, so the corners are judged against
 * the oracle (the best fit the points allow: each side's own points, least
 * squares in double) and, more loosely, against the truth. */
static void test_synthetic_parallelograms(void)
{
    actag_quad_params p;
    int t, trials = 600, big = 0;
    double worst_truth = 0, sum_oracle = 0, sum_truth = 0, sum_oracle_truth = 0;
    long iters = 0;
    actag_quad_params_default(&p);
    tu_seed(11);
    for (t = 0; t < trials; t++) {
        double cx[4], cy[4], ox[4], oy[4], e, eo, ms;
        actag_quad q, oq;
        int n, rc, z;
        char msg[200];
        random_parallelogram(10.0, 60.0, cx, cy);
        ms = min_side(cx, cy);
        n = make_contour(cx, cy, 0.2, 0.02, g_pts, MAXP);
        oracle_corners(g_pts, n, ox, oy);
        truth_clockwise(cx, cy);
        truth_clockwise(ox, oy);
        rc = fit(g_pts, n, &p, (uint32_t)t, &q);
        snprintf(msg, sizeof msg, "trial %d (n %d, min side %.1f px)", t, n, ms);
        TEST_ASSERT_EQUAL_INT_MESSAGE(ACTAG_OK, rc, msg);
        check_quad_invariants(g_pts, n, &p, &q);
        e = corner_error(&q, cx, cy);
        eo = corner_error(&q, ox, oy);
        for (z = 0; z < 4; z++) {
            oq.corners[z].x = (float)ox[z];
            oq.corners[z].y = (float)oy[z];
        }
        sum_oracle_truth += corner_error(&oq, cx, cy);
        snprintf(msg, sizeof msg, "trial %d (n %d, min side %.1f px): %.3f px from oracle, %.3f from truth",
                 t, n, ms, eo, e);
        if (!(eo <= (ms >= 20.0 ? 0.3 : 0.8)))
            TEST_FAIL_MESSAGE(msg);
        if (!(e <= 1.0))
            TEST_FAIL_MESSAGE(msg);
        big += ms >= 20.0;
        sum_oracle += eo;
        sum_truth += e;
        worst_truth = e > worst_truth ? e : worst_truth;
        iters += q.iterations;
    }
    printf("synthetic: worst-corner error mean %.3f px from oracle, %.3f px from truth (oracle itself "
           "%.3f), max %.3f px from truth; %d/%d with sides >= 20 px; mean iterations %.2f\n",
           sum_oracle / trials, sum_truth / trials, sum_oracle_truth / trials, worst_truth, big, trials,
           (double)iters / trials);
    TEST_ASSERT_TRUE(sum_oracle / trials < 0.12);
}

/* Rasterised filled parallelograms traced like a real contour. Border pixel
 * centres lie 0..1 px inside the true edges, so the fitted corners sit on
 * average half a pixel's extent inside: judged against that inset outline,
 * and squares also against the true corners (within 1 px). */
static void test_traced_rasterised_quads(void)
{
    actag_quad_params p;
    int t, trials = 300, squares = 0;
    double worst_sq = 0, worst_in = 0, sum_in = 0;
    actag_quad_params_default(&p);
    tu_seed(21);
    for (t = 0; t < trials; t++) {
        double cx[4], cy[4], ix[4], iy[4], e, ei;
        actag_quad q;
        int n, rc, is_square;
        char msg[160];
        random_parallelogram(12.0, 60.0, cx, cy);
        is_square = fabs((cx[1] - cx[0]) * (cx[2] - cx[1]) + (cy[1] - cy[0]) * (cy[2] - cy[1])) < 1e-6 &&
                    fabs(hypot(cx[1] - cx[0], cy[1] - cy[0]) - hypot(cx[2] - cx[1], cy[2] - cy[1])) < 1e-6;
        centre_in_image(cx, cy, 4);
        truth_clockwise(cx, cy);
        raster_convex(cx, cy, 4);
        n = trace(g_pts, MAXP);
        rc = fit(g_pts, n, &p, (uint32_t)t, &q);
        snprintf(msg, sizeof msg, "traced trial %d (n %d)", t, n);
        TEST_ASSERT_EQUAL_INT_MESSAGE(ACTAG_OK, rc, msg);
        check_quad_invariants(g_pts, n, &p, &q);
        inset_corners(cx, cy, ix, iy);
        ei = corner_error(&q, ix, iy);
        e = corner_error(&q, cx, cy);
        snprintf(msg, sizeof msg, "traced trial %d (n %d): %.3f px from inset outline, %.3f from truth",
                 t, n, ei, e);
        if (!(ei <= 0.9))
            TEST_FAIL_MESSAGE(msg);
        if (is_square) {
            if (!(e <= 1.5))
                TEST_FAIL_MESSAGE(msg);
            worst_sq = e > worst_sq ? e : worst_sq;
            squares++;
        }
        sum_in += ei;
        worst_in = ei > worst_in ? ei : worst_in;
    }
    printf("traced: worst-corner error from inset outline mean %.3f max %.3f px; %d rotated squares: "
           "max %.3f px from true corners\n", sum_in / trials, worst_in, squares, worst_sq);
    TEST_ASSERT_GREATER_THAN(50, squares);
    TEST_ASSERT_TRUE(sum_in / trials < 0.25);
}

static void test_circles_and_ellipses_rejected(void)
{
    actag_quad_params p;
    int t;
    actag_quad_params_default(&p);
    tu_seed(31);
    for (t = 0; t < 40; t++) {
        /* Radius >= 40 px. (A square with 2.5 px bands holds over 80 % of a
         * traced circle of radius up to about 30 px: with the default
         * parameters such small circles pass as quads; the decoder rejects
         * them.) */
        double rx = 40.0 + 30.0 * urand(), ry = t < 20 ? rx : rx * (0.7 + 0.25 * urand());
        double x0 = 128.0 + urand(), y0 = 128.0 + urand(), th = urand() * 3.14159;
        actag_quad q;
        int r, c, n;
        const double ct = cos(th), st = sin(th);
        for (r = 0; r < IMG; r++)
            for (c = 0; c < IMG; c++) {
                double dx = c - x0, dy = r - y0;
                double u = (dx * ct + dy * st) / rx, v = (-dx * st + dy * ct) / ry;
                g_img[r * IMG + c] = (unsigned char)(u * u + v * v <= 1.0);
            }
        n = trace(g_pts, MAXP);
        TEST_ASSERT_GREATER_THAN(100, n);
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_QUAD, fit(g_pts, n, &p, (uint32_t)t, &q));
        TEST_ASSERT_EQUAL_INT(p.max_iterations, q.iterations);
        TEST_ASSERT_EQUAL_FLOAT(0.0f, q.inlier_ratio);
    }
}

static void test_random_blobs_rejected(void)
{
    actag_quad_params p;
    int t;
    actag_quad_params_default(&p);
    tu_seed(41);
    for (t = 0; t < 60; t++) {
        /* Star-shaped blobs made of harmonics 2, 3, 5, 6, 7 (no 4th: that
         * one draws rounded squares). */
        static const int pool[5] = {2, 3, 5, 6, 7};
        double amp[3], ph[3];
        int harm[3], k, n;
        actag_quad q;
        for (k = 0; k < 3; k++) {
            harm[k] = pool[tu_range(0, 4)];
            amp[k] = 0.06 + 0.12 * urand();
            ph[k] = 6.283 * urand();
        }
        {
            /* one draw per declarator: a fixed order (the x86-64 build's
             * order when they were call arguments: the last one first) */
            double br = 25.0 + 30.0 * urand(), by = 128.0 + urand(), bx = 128.0 + urand();
            raster_blob(bx, by, br, amp, ph, harm, 3);
        }
        n = trace(g_pts, MAXP);
        TEST_ASSERT_GREATER_THAN(80, n);
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_QUAD, fit(g_pts, n, &p, (uint32_t)t, &q));
    }
    /* Ragged blobs: a random radius for each of 48 directions. */
    for (t = 0; t < 40; t++) {
        double rad[48], r0 = 20.0 + 20.0 * urand();
        int r, c, n, k;
        actag_quad q;
        for (k = 0; k < 48; k++)
            rad[k] = r0 * (0.8 + 0.4 * urand());
        for (r = 0; r < IMG; r++)
            for (c = 0; c < IMG; c++) {
                double dx = c - 128.0, dy = r - 128.0, d2 = dx * dx + dy * dy;
                int bin;
                /* every rad[] is in [0.8 r0, 1.2 r0]: decided without atan2
                 * a pixel or more outside that ring (the same image) */
                if (d2 > (1.2 * r0 + 1.0) * (1.2 * r0 + 1.0) ||
                    d2 < (0.8 * r0 - 1.0) * (0.8 * r0 - 1.0)) {
                    g_img[r * IMG + c] = (unsigned char)(d2 < (0.8 * r0 - 1.0) * (0.8 * r0 - 1.0));
                    continue;
                }
                bin = (int)floor((atan2(dy, dx) + 3.141592653589793) / 6.283185307179586 * 48.0) % 48;
                g_img[r * IMG + c] = (unsigned char)(sqrt(d2) <= rad[bin]);
            }
        n = trace(g_pts, MAXP);
        TEST_ASSERT_GREATER_THAN(60, n);
        TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_QUAD, fit(g_pts, n, &p, (uint32_t)t, &q));
    }
}

/* Smaller |cos| of the angles between the two pairs of opposite sides. */
static double min_opposite_cos(const actag_quad *q)
{
    double best = 1.0;
    int i;
    for (i = 0; i < 2; i++) {
        double ax = q->corners[i + 1].x - q->corners[i].x, ay = q->corners[i + 1].y - q->corners[i].y;
        double bx = q->corners[(i + 3) % 4].x - q->corners[i + 2].x;
        double by = q->corners[(i + 3) % 4].y - q->corners[i + 2].y;
        double c = fabs(ax * bx + ay * by) / sqrt((ax * ax + ay * ay) * (bx * bx + by * by));
        best = c < best ? c : best;
    }
    return best;
}

/* Traced trapezoid and kite: four straight sides, but not a parallelogram. */
static void test_non_parallelograms_rejected(void)
{
    static const double shapes[2][8] = {
        {-10, -20, 10, -20, 30, 20, -30, 20},  /* trapezoid: 20 and 60 px bases */
        {0, -15, 20, 0, 0, 60, -20, 0}};       /* kite: |cos| between opposite sides 0.82 */
    actag_quad_params p;
    int sh, t;
    actag_quad_params_default(&p);
    for (sh = 0; sh < 2; sh++)
        for (t = 0; t < 10; t++) {
            double cx[4], cy[4], sc = 1.0 + 0.1 * t, ang = 0.3 * t;
            actag_quad q;
            int z, n;
            actag_quad_params loose = p;
            for (z = 0; z < 4; z++) {
                double x = shapes[sh][2 * z] * sc, y = shapes[sh][2 * z + 1] * sc;
                cx[z] = 128.3 + x * cos(ang) - y * sin(ang);
                cy[z] = 120.6 + x * sin(ang) + y * cos(ang);
            }
            raster_convex(cx, cy, 4);
            n = trace(g_pts, MAXP);
            TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_QUAD, fit(g_pts, n, &p, (uint32_t)t, &q));
            /* With the parallel test relaxed, the same search finds a quad
             * whose opposite sides are not parallel: it was that test alone
             * that turned the shape down. */
            loose.min_parallel_cos = 0.0f;
            TEST_ASSERT_EQUAL_INT(ACTAG_OK, fit(g_pts, n, &loose, (uint32_t)t, &q));
            check_quad_invariants(g_pts, n, &loose, &q);
            TEST_ASSERT_TRUE(min_opposite_cos(&q) < p.min_parallel_cos);
        }
}

static void test_determinism_and_translation(void)
{
    actag_quad_params p;
    int t;
    actag_quad_params_default(&p);
    tu_seed(51);
    for (t = 0; t < 100; t++) {
        static actag_ipoint moved[MAXP];
        double cx[4], cy[4];
        actag_quad q1, q2, q3;
        actag_rng r1, r2, r3;
        int n, i, rc1, rc2, rc3, dx, dy;
        random_parallelogram(10.0, 60.0, cx, cy);
        n = make_contour(cx, cy, 0.4, 0.03, g_pts, MAXP);
        actag_rng_seed(&r1, (uint32_t)t * 7u);
        actag_rng_seed(&r2, (uint32_t)t * 7u);
        memset(&q1, 0, sizeof q1);
        memset(&q2, 0xff, sizeof q2);
        rc1 = actag_quad_fit(g_pts, n, &p, &r1, g_scratch, sizeof g_scratch, &q1);
        memset(g_scratch, 0xa5, n); /* stale scratch must not matter */
        rc2 = actag_quad_fit(g_pts, n, &p, &r2, g_scratch, sizeof g_scratch, &q2);
        TEST_ASSERT_EQUAL_INT(rc1, rc2);
        TEST_ASSERT_EQUAL_MEMORY(&q1, &q2, sizeof q1);
        TEST_ASSERT_EQUAL_MEMORY(&r1, &r2, sizeof r1);
        /* Integer translation (to near the int16 limits too) changes
         * nothing but the corner offsets: the fit works relative to the
         * contour's bounding box. */
        {   /* shift to touch the int16 limits, or somewhere random */
            int mnx = 32767, mxx = -32768, mny = 32767, mxy = -32768;
            for (i = 0; i < n; i++) {
                mnx = g_pts[i].x < mnx ? g_pts[i].x : mnx;
                mxx = g_pts[i].x > mxx ? g_pts[i].x : mxx;
                mny = g_pts[i].y < mny ? g_pts[i].y : mny;
                mxy = g_pts[i].y > mxy ? g_pts[i].y : mxy;
            }
            dx = t % 3 == 0 ? 32767 - mxx : (t % 3 == 1 ? -32768 - mnx : tu_range(-500, 500));
            dy = t % 2 == 0 ? -32768 - mny : (t % 4 == 1 ? 32767 - mxy : tu_range(-500, 500));
        }
        for (i = 0; i < n; i++) {
            moved[i].x = (int16_t)(g_pts[i].x + dx);
            moved[i].y = (int16_t)(g_pts[i].y + dy);
        }
        actag_rng_seed(&r3, (uint32_t)t * 7u);
        rc3 = actag_quad_fit(moved, n, &p, &r3, g_scratch, sizeof g_scratch, &q3);
        TEST_ASSERT_EQUAL_INT(rc1, rc3);
        TEST_ASSERT_EQUAL_INT(q1.iterations, q3.iterations);
        TEST_ASSERT_EQUAL_MEMORY(&q1.inlier_ratio, &q3.inlier_ratio, sizeof(float));
        TEST_ASSERT_EQUAL_MEMORY(&r1, &r3, sizeof r1);
        if (rc1 == ACTAG_OK) {
            for (i = 0; i < 4; i++) {
                TEST_ASSERT_FLOAT_WITHIN(0.01f, q1.corners[i].x + (float)dx, q3.corners[i].x);
                TEST_ASSERT_FLOAT_WITHIN(0.01f, q1.corners[i].y + (float)dy, q3.corners[i].y);
            }
            check_quad_invariants(moved, n, &p, &q3);
        }
    }
}

/* Pinned output for one contour and seed: any change in the arithmetic or in
 * the use of the generator shows up here (and would differ between
 * platforms if float evaluation did). */
static void test_pinned_result(void)
{
    /* Computed once by this implementation (x86-64, GCC -O3); float hex. */
    static const float expect[4][2] = {{0x1.908b42p+6f, 0x1.93f03ep+5f},
                                       {0x1.077d2p+7f, 0x1.d11dcp+5f},
                                       {0x1.163724p+7f, 0x1.6610dp+6f},
                                       {0x1.af1716p+6f, 0x1.478df8p+6f}};
    actag_quad_params p;
    actag_quad q;
    double cx[4] = {100.3, 131.7, 139.2, 107.8}, cy[4] = {50.6, 58.1, 89.5, 82.0};
    uint32_t sum = 0;
    int n, i;
    actag_quad_params_default(&p);
    tu_seed(77);
    n = make_contour(cx, cy, 0.3, 0.02, g_pts, MAXP);
    for (i = 0; i < n; i++) /* the input itself is pinned too */
        sum = sum * 31u + (uint32_t)(uint16_t)g_pts[i].x * 65536u + (uint32_t)(uint16_t)g_pts[i].y;
    TEST_ASSERT_EQUAL_INT(132, n);
    if (getenv("ACTAG_PRINT_PINNED"))
        printf("sum 0x%08x\n", (unsigned)sum);
    TEST_ASSERT_EQUAL_HEX32(0x5c869624u, sum);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, fit(g_pts, n, &p, 2024u, &q));
    check_quad_invariants(g_pts, n, &p, &q);
    TEST_ASSERT_EQUAL_INT(6, q.iterations);
    TEST_ASSERT_TRUE(q.inlier_ratio == 0x1.f45d18p-1f);
    for (i = 0; i < 4; i++) {
        TEST_ASSERT_TRUE(q.corners[i].x == expect[i][0]);
        TEST_ASSERT_TRUE(q.corners[i].y == expect[i][1]);
    }
}

static void test_degenerate_contours(void)
{
    actag_quad_params p;
    actag_quad q;
    int i, n;
    actag_quad_params_default(&p);
    /* all points equal */
    for (i = 0; i < 50; i++)
        g_pts[i] = (actag_ipoint){7, 9};
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_QUAD, fit(g_pts, 50, &p, 1, &q));
    /* a straight line walked there and back (a 1-pixel-wide blob) */
    n = 0;
    for (i = 0; i < 60; i++)
        g_pts[n++] = (actag_ipoint){(int16_t)(10 + i), (int16_t)(20 + i / 3)};
    for (i = 59; i > 0; i--)
        g_pts[n++] = (actag_ipoint){(int16_t)(10 + i), (int16_t)(20 + i / 3)};
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_QUAD, fit(g_pts, n, &p, 1, &q));
    /* tiny squares: sides shorter than the inlier distance */
    n = square_contour(g_pts, 5, 5, 2);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_QUAD, fit(g_pts, n, &p, 1, &q));
    /* a long thin rectangle 2 px wide */
    n = 0;
    for (i = 0; i < 60; i++)
        g_pts[n++] = (actag_ipoint){(int16_t)i, 0};
    for (i = 0; i < 2; i++)
        g_pts[n++] = (actag_ipoint){60, (int16_t)i};
    for (i = 60; i > 0; i--)
        g_pts[n++] = (actag_ipoint){(int16_t)i, 2};
    for (i = 2; i > 0; i--)
        g_pts[n++] = (actag_ipoint){0, (int16_t)i};
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NO_QUAD, fit(g_pts, n, &p, 1, &q));
    /* the largest coordinates: a square spanning the whole int16 range */
    n = 0;
    for (i = 0; i < 400; i++)
        g_pts[n++] = (actag_ipoint){(int16_t)(-32768 + i * 163), -32768};
    for (i = 0; i < 400; i++)
        g_pts[n++] = (actag_ipoint){32767, (int16_t)(-32768 + i * 163)};
    for (i = 0; i < 400; i++)
        g_pts[n++] = (actag_ipoint){(int16_t)(32767 - i * 163), 32767};
    for (i = 0; i < 400; i++)
        g_pts[n++] = (actag_ipoint){-32768, (int16_t)(32767 - i * 163)};
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, fit(g_pts, n, &p, 1, &q));
    check_quad_invariants(g_pts, n, &p, &q);
    TEST_ASSERT_FLOAT_WITHIN(0.05f, -32768.0f, q.corners[0].x);
    TEST_ASSERT_FLOAT_WITHIN(0.05f, -32768.0f, q.corners[0].y);
    TEST_ASSERT_FLOAT_WITHIN(0.05f, 32767.0f, q.corners[2].x);
    TEST_ASSERT_FLOAT_WITHIN(0.05f, 32767.0f, q.corners[2].y);
    /* a single iteration is honoured */
    p.max_iterations = 1;
    n = square_contour(g_pts, 10, 10, 40);
    i = fit(g_pts, n, &p, 3, &q);
    TEST_ASSERT_TRUE(i == ACTAG_OK || i == ACTAG_ERR_NO_QUAD);
    TEST_ASSERT_EQUAL_INT(1, q.iterations);
}

static double now_us(void) { return (double)clock() * 1e6 / CLOCKS_PER_SEC; }

static void test_timing_report(void)
{
    actag_quad_params p;
    int t, reps, kinds;
    if (TU_EMULATED)
        TEST_IGNORE_MESSAGE("timing is measured on the host (instruction counts on ARM: tools/budget)");
    actag_quad_params_default(&p);
    for (kinds = 0; kinds < 3; kinds++) {
        double t0, total = 0;
        reps = kinds == 0 ? 200 : 20;
        long pts = 0, ok = 0, it = 0;
        tu_seed(61);
        for (t = 0; t < 20; t++) {
            double cx[4], cy[4];
            int n, k;
            actag_quad q;
            if (kinds == 0) { /* traced tag-sized squares, ~200 points */
                random_parallelogram(45.0, 55.0, cx, cy);
                centre_in_image(cx, cy, 4);
                raster_convex(cx, cy, 4);
            } else if (kinds == 1) { /* traced circles */
                double r0 = 25.0 + 10.0 * urand(), amp[1] = {0}, ph[1] = {0};
                int harm[1] = {1};
                raster_blob(128.3, 127.6, r0, amp, ph, harm, 1);
            } else { /* traced star blobs */
                double amp[3], ph[3];
                int harm[3] = {3, 5, 7};
                for (k = 0; k < 3; k++) {
                    amp[k] = 0.06 + 0.1 * urand();
                    ph[k] = 6.283 * urand();
                }
                raster_blob(128.0, 128.0, 30.0, amp, ph, harm, 3);
            }
            n = trace(g_pts, MAXP);
            t0 = now_us();
            for (k = 0; k < reps; k++) {
                ok += fit(g_pts, n, &p, (uint32_t)k, &q) == ACTAG_OK;
                it += q.iterations;
            }
            total += now_us() - t0;
            pts += n;
        }
        printf("timing: %-22s %4.0f points, %6.1f us per fit, %5.1f iterations (%.2f us each), "
               "%3.0f%% fitted\n",
               kinds == 0 ? "tag-sized squares" : (kinds == 1 ? "circles r 25-35 px" : "star blobs r 30 px"),
               (double)pts / 20, total / (20.0 * reps), (double)it / (20.0 * reps), total / (double)it,
               100.0 * (double)ok / (20.0 * reps));
        /* what is timed must also be right: every square fitted, no circle
         * or star taken for a quadrilateral */
        TEST_ASSERT_EQUAL_INT(kinds == 0 ? 20L * reps : 0L, ok);
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_params_default);
    RUN_TEST(test_error_codes_and_scratch_size);
    RUN_TEST(test_desired_and_required_ratio);
    RUN_TEST(test_exact_lattice_parallelograms);
    RUN_TEST(test_synthetic_parallelograms);
    RUN_TEST(test_traced_rasterised_quads);
    RUN_TEST(test_circles_and_ellipses_rejected);
    RUN_TEST(test_random_blobs_rejected);
    RUN_TEST(test_non_parallelograms_rejected);
    RUN_TEST(test_determinism_and_translation);
    RUN_TEST(test_pinned_result);
    RUN_TEST(test_degenerate_contours);
    RUN_TEST(test_timing_report);
    return UNITY_END();
}
