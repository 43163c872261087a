/* The corner refinement's Gauss-Newton model (src/refine_probe.h): its
 * normal equations' right side J'r is minus half the gradient of the
 * residual sum it minimises, and J'J the (Gauss-Newton) derivative of J'r,
 * both against central differences of the sums themselves, on a rendered
 * tag, with no geometry (a flat grid) and through a sonar geometry (a grid
 * bent in the fan plane). */
#include "../src/refine_probe.h"

#include "unity.h"
#include "test_util.h"

#include "actag/render.h"

#include <math.h>

void setUp(void) {}
void tearDown(void) {}

#define ROWS 200
#define COLS 200
#define CELL 12
#define MARGIN 6

static uint8_t frame[ROWS * COLS];
static actag_family fam;

/* A tag at (x0, y0), its edges softened by a 3 x 3 mean, with noise of
 * +-noise grey levels; its white square's corners (tag order) in q. */
static void render(int x0, int y0, int noise, actag_point q[4])
{
    static uint8_t tag[120 * 120], raw[ROWS * COLS];
    int side = actag_render_side(fam.bits, CELL, MARGIN), x, y, k = fam.bits / 4;
    float a = (float)(MARGIN + 2 * CELL) - 0.5f, b = (float)(MARGIN + (k - 1) * CELL) - 0.5f;
    TEST_ASSERT_TRUE(side <= 120 && x0 + side <= COLS && y0 + side <= ROWS);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_render_tag(&fam, 3, CELL, MARGIN, 0, 0, tag, side, sizeof tag));
    memset(raw, 20, sizeof raw);
    for (y = 0; y < side; y++)
        for (x = 0; x < side; x++)
            raw[(y0 + y) * COLS + x0 + x] = (uint8_t)(tag[y * side + x] ? 220 : 20);
    for (y = 0; y < ROWS; y++)
        for (x = 0; x < COLS; x++) {
            int s = 0, dx, dy, v;
            for (dy = -1; dy <= 1; dy++)
                for (dx = -1; dx <= 1; dx++) {
                    int yy = y + dy < 0 ? 0 : (y + dy >= ROWS ? ROWS - 1 : y + dy);
                    int xx = x + dx < 0 ? 0 : (x + dx >= COLS ? COLS - 1 : x + dx);
                    s += raw[yy * COLS + xx];
                }
            v = (s + 4) / 9 + (noise ? tu_range(-noise, noise) : 0);
            frame[y * COLS + x] = (uint8_t)(v < 0 ? 0 : (v > 255 ? 255 : v));
        }
    q[0].x = (float)x0 + a; q[0].y = (float)y0 + a;
    q[1].x = (float)x0 + b; q[1].y = (float)y0 + a;
    q[2].x = (float)x0 + b; q[2].y = (float)y0 + b;
    q[3].x = (float)x0 + a; q[3].y = (float)y0 + b;
}

/* Index of (i, j), i <= j, in the packed upper triangle of a 6 x 6. */
static int packed(int i, int j)
{
    int t = i < j ? i : j, u = i < j ? j : i;
    return t * 6 - t * (t - 1) / 2 + (u - t);
}

/* At grids near the start: the gradient of rss against -2 b, and (check_A)
 * on a noise-free frame with the start at the truth, the change of b
 * against -A. Through a geometry the pixel-square render is not exactly the
 * fan-plane model's shape, the residuals stay, and Gauss-Newton's J'J
 * differs from the derivative by their curvature term: there only the
 * gradient is checked. */
static void check(const actag_sonar_geometry *g, float tag_size, int check_A, const char *what)
{
    actag_point q[4], c[4];
    float dp[6], start[6], rss, b[6], A[21], rp, rm, bp[6], bm[6], Ap[21], hs[6];
    int t, k, i, compared = 0;
    char msg[200];
    tu_seed(93);
    for (t = 0; t < 12; t++) {
        render(40 + tu_range(0, 30), 40 + tu_range(0, 30), t % 3 ? 6 : 0, q);
        /* start corners up to a pixel off (at the truth for the noise-free
         * cases whose J'J is checked) */
        for (i = 0; i < 4; i++) {
            int off = t % 3 == 0 && t < 6 ? 0 : 100;
            c[i].x = q[i].x + (float)tu_range(-off, off) * 0.01f;
            c[i].y = q[i].y + (float)tu_range(-off, off) * 0.01f;
        }
        memset(dp, 0, sizeof dp);
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag__refine_probe(frame, ROWS, COLS, COLS, g, tag_size,
                                                            &fam, 3, c, 2.0f, dp, &rss, b, A,
                                                            start));
        /* steps of a thousandth of a cell: the centre by that much of the
         * first cell vector's length, each vector's components by a
         * thousandth of its length */
        {
            float len = sqrtf(start[2] * start[2] + start[3] * start[3]);
            for (k = 0; k < 6; k++)
                hs[k] = 1e-3f * len;
        }
        for (k = 0; k < 6; k++) {
            double fd;
            memset(dp, 0, sizeof dp);
            dp[k] = hs[k];
            TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag__refine_probe(frame, ROWS, COLS, COLS, g,
                                                                tag_size, &fam, 3, c, 2.0f, dp,
                                                                &rp, bp, Ap, NULL));
            dp[k] = -hs[k];
            TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag__refine_probe(frame, ROWS, COLS, COLS, g,
                                                                tag_size, &fam, 3, c, 2.0f, dp,
                                                                &rm, bm, Ap, NULL));
            fd = ((double)rp - (double)rm) / (2.0 * hs[k]);
            snprintf(msg, sizeof msg, "%s, case %d: d rss / d p%d: differences %.6g, -2 b %.6g",
                     what, t, k, fd, -2.0 * b[k]);
            /* 2 % of the gradient, and the float sums' rounding (about
             * 1e-5 of rss) over the difference's span */
            TEST_ASSERT_TRUE_MESSAGE(fabs(fd + 2.0 * b[k]) <=
                                         0.02 * fabs(2.0 * b[k]) + 1e-5 * (double)rss / hs[k],
                                     msg);
            compared++;
            if (check_A && t % 3 == 0 && t < 6) {
                /* noise-free, the start near the truth: d b / d p = -A
                 * where the residuals are small (Gauss-Newton's
                 * approximation; a tenth of slack) */
                for (i = 0; i < 6; i++) {
                    double db = ((double)bp[i] - (double)bm[i]) / (2.0 * hs[k]);
                    double a = A[packed(i, k)];
                    snprintf(msg, sizeof msg, "%s, case %d: d b%d / d p%d: differences %.6g, -A %.6g",
                             what, t, i, k, db, -a);
                    TEST_ASSERT_TRUE_MESSAGE(fabs(db + a) <= 0.1 * sqrt(fabs(A[packed(i, i)] * A[packed(k, k)])) + 1e-6,
                                             msg);
                }
            }
        }
    }
    TEST_ASSERT_EQUAL_INT(72, compared);
}

static void test_flat_grid(void) { check(NULL, 0.0f, 1, "no geometry"); }

static void test_grid_bent_by_the_fan(void)
{
    /* 200 rows over 1.0-1.4 m, 200 beams over 40 degrees: a tag cell of
     * 12 px is about 2.4 cm in range and 4.4 cm across at 1.2 m */
    const actag_sonar_geometry g = {1.0f, 1.4f, 0.6981317f, NULL, 0u};
    check(&g, 0.09f, 0, "fan");
}

int main(void)
{
    if (actag_family_get("AcTag24h10", &fam) != ACTAG_OK)
        return 1;
    UNITY_BEGIN();
    RUN_TEST(test_flat_grid);
    RUN_TEST(test_grid_bent_by_the_fan);
    return UNITY_END();
}
