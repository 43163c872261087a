/* The grid-fit decoder (actag_decode_quad_fit, decode.h): the tag's cell
 * grid fitted to the grey frame, every bit a confidence, matched by
 * likelihood (family.c), the likeliest readings checked as whole templates. */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/decode.h"
#include "decode_common.h"
#include "decode_fit_grids.h"
#include "decode_fit_test.h"
#include "fit_cells.h"

#include <string.h>

/* Every cell of grid gr (fit_cells.h). */
static void fcells(const fimg *im, const fgrid *gr, int k, float *m)
{
    actag__fit_cells(im, gr, k, m, 0);
}

static int is_ring(int cx, int cy, int k)
{
    return (cx == 1 || cy == 1 || cx == k - 1 || cy == k - 1) && cx >= 1 && cy >= 1 &&
           cx <= k - 1 && cy <= k - 1;
}

/* Black ring mean and white interior mean of the cell means. Each sum
 * adds its cells in row order (as a scan of all cells with is_ring would),
 * visiting only them; k >= 4 (bits 16..32), so the ring's rows 1 and k-1
 * differ. */
static void flevels(const float *m, int k, float *black, float *white)
{
    int cx, cy, n = k + 1;
    float sr = 0.0f, si = 0.0f;
    for (cx = 1; cx < k; cx++)
        sr += m[n + cx];
    for (cy = 2; cy < k - 1; cy++) {
        sr += m[cy * n + 1];
        sr += m[cy * n + k - 1];
        for (cx = 2; cx < k - 1; cx++)
            si += m[cy * n + cx];
    }
    for (cx = 1; cx < k; cx++)
        sr += m[(k - 1) * n + cx];
    *black = sr / (float)(4 * (k - 2));
    *white = si / (float)((k - 3) * (k - 3));
}

#define FIT_INITS 5
/* grids the ACTAG_FIT_WIDE search compares: 5 starts x (25 + 8) shifts */
#define FIT_WIDE_GRIDS (FIT_INITS * 33)
/* Splits that read as different tags: the closest must lead the others by
 * this many bits, else the threshold would decide the ID. */
#define FIT_SPLIT_LEAD 1
/* Where cells are judged between the black ring (0) and the white interior
 * (1): the grid score's data-cell distance and the ring / interior counts. */
#define FIT_MID_LEVEL 0.5f

/* fscore_of's term of one border cell */
static inline float fedge(float v, float t, float half)
{
    v -= t;
    v = v < 0.0f ? -v : v;
    return v < half ? v : half;
}

/* Code-agnostic crispness of a grid: black ring cells below, interior
 * cells above the mid level, data cells far from it (either side, capped
 * at half the contrast so bright clutter cannot pull the grid). The border
 * cells are summed in row order, visiting only them. */
static float fscore_of(const float *m, int k)
{
    int cx, cy, n = k + 1;
    float black, white, t, half, s = 0.0f;
    flevels(m, k, &black, &white);
    t = black + FIT_MID_LEVEL * (white - black);
    half = FIT_MID_LEVEL * (white - black);
    for (cx = 0; cx < n; cx++)
        s += fedge(m[cx], t, half);
    for (cy = 1; cy < k; cy++) {
        s += fedge(m[cy * n], t, half);
        s += fedge(m[cy * n + k], t, half);
    }
    for (cx = 0; cx < n; cx++)
        s += fedge(m[k * n + cx], t, half);
    return s + (white - black) * (float)((k - 1) * (k - 1));
}

static float fscore(const fimg *im, const fgrid *gr, int k, float *m)
{
    fcells(im, gr, k, m);
    return fscore_of(m, k);
}

/* Coarse translation search (+-1 cell, quarter-cell steps) by fscore. */
static void fshift(const fimg *im, fgrid *gr, int k, float *m)
{
    /* Starting grids: as given, rotated by +-30 degrees, and sheared
     * (sonar images show tags as parallelograms) by b += +-a (lb / la);
     * each on a quarter-cell lattice of shifts within +-1 cell (along the
     * given grid's cell vectors). The given grid's half-cell shifts share
     * one lattice (flattice); the others' do not, and shifting those along
     * their own vectors instead lost a real pool frame (f_0301). */
    static const float rc[FIT_INITS] = {1.0f, 0.8660254f, 0.8660254f, 1.0f, 1.0f};
    static const float rs[FIT_INITS] = {0.0f, 0.5f, -0.5f, 0.0f, 0.0f};
    static const float hb[FIT_INITS] = {0.0f, 0.0f, 0.0f, 1.0f, -1.0f};
    fgrid g0 = *gr, t;
    float best = -1e30f, Q[FIT_LAT_MAX * FIT_LAT_MAX];
    float la = actag_sqrtf(g0.ax * g0.ax + g0.ay * g0.ay), lb = actag_sqrtf(g0.bx * g0.bx + g0.by * g0.by);
    float q = la > 0.0f ? lb / la : 1.0f;
    int i, j, o;
    for (o = 0; o < FIT_INITS; o++) {
        fgrid gro = g0;
        gro.ax = rc[o] * g0.ax + rs[o] * g0.bx / q;
        gro.ay = rc[o] * g0.ay + rs[o] * g0.by / q;
        gro.bx = -rs[o] * g0.ax * q + rc[o] * g0.bx + hb[o] * q * g0.ax;
        gro.by = -rs[o] * g0.ay * q + rc[o] * g0.by + hb[o] * q * g0.ay;
        /* half-cell lattice within +-1 cell, then the quarter-cell
         * neighbours of the best point */
        {
            fgrid bo = gro;
            float bs = -1e30f, sc25[25];
            int pi, pj;
            /* all 25 scores from the lattice, one parity class at a time */
            for (pj = 0; pj < 2 && o == 0; pj++)
                for (pi = 0; pi < 2; pi++) {
                    actag__fit_lattice(im, &gro, k, pi, pj, Q);
                    for (j = pj - 2; j <= 2; j += 2)
                        for (i = pi - 2; i <= 2; i += 2) {
                            actag__fit_lattice_cells(Q, k, i, j, m);
                            sc25[(j + 2) * 5 + i + 2] = fscore_of(m, k);
                        }
                }
            for (j = -2; j <= 2; j++)
                for (i = -2; i <= 2; i++) {
                    float sc;
                    t = gro;
                    t.mx += 0.5f * ((float)i * g0.ax + (float)j * g0.bx);
                    t.my += 0.5f * ((float)i * g0.ay + (float)j * g0.by);
                    sc = o == 0 ? sc25[(j + 2) * 5 + i + 2] : fscore(im, &t, k, m);
                    if (sc > bs) {
                        bs = sc;
                        bo = t;
                    }
                }
            for (j = -1; j <= 1; j++)
                for (i = -1; i <= 1; i++) {
                    float sc;
                    if (i == 0 && j == 0)
                        continue;
                    t = bo;
                    t.mx += 0.25f * ((float)i * g0.ax + (float)j * g0.bx);
                    t.my += 0.25f * ((float)i * g0.ay + (float)j * g0.by);
                    sc = fscore(im, &t, k, m);
                    if (sc > bs) {
                        bs = sc;
                        bo = t;
                    }
                }
            if (bs > best) {
                best = bs;
                *gr = bo;
            }
        }
    }
}

static float tscore(const fimg *im, const fgrid *gr, int k, float *m, const uint8_t *L,
                    int erase);
static float template_rss(const float *m, const uint8_t *L, int k, int erase, int *ncells);

static float objective(const fimg *im, const fgrid *gr, int k, float *m, const uint8_t *L,
                       int erase)
{
    return L ? tscore(im, gr, k, m, L, erase) : fscore(im, gr, k, m);
}

/* The grid ascent: steps per step size, and how far it may go from the
 * starting grid (squared centre shift in cells^2: half a cell; squared side
 * lengths: 65-134 %), so it cannot wander onto a neighbouring tag. */
#define FIT_ASCENT_STEPS 4
#define FIT_ASCENT_SHIFT2 0.25f
#define FIT_ASCENT_HI 1.8f
#define FIT_ASCENT_LO 0.42f
/* A template's polish (tight): a reading refits the grid it came from,
 * so fewer steps, a quarter cell and +-15 % (1.15^2, 0.85^2). */
#define FIT_POLISH_STEPS 2
#define FIT_POLISH_SHIFT2 0.0625f
#define FIT_POLISH_HI 1.3225f
#define FIT_POLISH_LO 0.7225f

/* Ascent of the objective (fscore, or tscore for a template L) over the 6
 * affine parameters, 3 step sizes, by Gauss-Seidel sweeps: each parameter
 * moves as soon as a move improves (taking the best of all 12 moves per
 * step instead measured worse on the pool frames: 36-38 vs 37-39 of 47 over
 * flips and seeds). */
/* The template check's refusal of a rival template whose rss is r (see
 * actag_decode_quad_fit): r <= rss0, or its margin below min_margin. It only
 * grows with r, and a polish only lowers r, so once a polish reaches it the
 * final r would too. */
typedef struct frefuse {
    float rss0, s2, look, min_margin;
} frefuse;

/* The cell noise variance (grey levels^2) of a template fit whose residual
 * is rss over nc cells (two levels fitted), at least floor2. */
static float fcell_noise2(float rss, int nc, float floor2)
{
    float s2 = rss / (float)(nc > 3 ? nc - 2 : 1);
    return s2 < floor2 ? floor2 : s2;
}

static int frefused(const frefuse *rf, float r)
{
    return r <= rf->rss0 || 0.5f * (r - rf->rss0) / rf->s2 - rf->look < rf->min_margin;
}

/* m0: the cells of *gr when known (NULL: read them). rf (a template's
 * polish, NULL: none): stop as soon as the template's rss is refused;
 * returns 1 then, else 0. *score (if not NULL): the objective of the final
 * *gr, which a read of that grid would give again bit for bit. */
static int ffit(const fimg *im, fgrid *gr, int k, float *m, const uint8_t *L, int erase,
                int tight, const float *m0, const frefuse *rf, float *score)
{
    static const float scales[3] = {1.0f, 0.5f, 0.25f};
    fgrid g0 = *gr;
    float la = actag_sqrtf(gr->ax * gr->ax + gr->ay * gr->ay);
    float lb = actag_sqrtf(gr->bx * gr->bx + gr->by * gr->by);
    float best = m0 == NULL ? objective(im, gr, k, m, L, erase)
                 : L ? -template_rss(m0, L, k, erase, NULL) : fscore_of(m0, k);
    int lvl, it, p, sgn;
    /* the grid before the last move, whose score is below best: a trial
     * that lands on it bit for bit (the move undone, often exact in
     * float) cannot improve and is not read */
    fgrid gp = *gr;
    if (rf && frefused(rf, -best))
        return 1;
    for (lvl = tight ? 1 : 0; lvl < 3; lvl++) { /* a polish starts at half steps */
        for (it = 0; it < (tight ? FIT_POLISH_STEPS : FIT_ASCENT_STEPS); it++) {
            fgrid bt = *gr;
            float bs = best;
            for (p = 0; p < 6; p++)
                for (sgn = -1; sgn <= 1; sgn += 2) {
                    fgrid t = *gr;
                    float d, s;
                    float *f = p == 0 ? &t.mx : p == 1 ? &t.my : p == 2 ? &t.ax
                             : p == 3 ? &t.ay : p == 4 ? &t.bx : &t.by;
                    d = (p < 2 ? 0.15f * (la < lb ? la : lb) : 0.05f * (p < 4 ? la : lb)) *
                        scales[lvl] * (float)sgn;
                    *f += d;
                    /* stay near the starting grid */
                    if ((t.mx - g0.mx) * (t.mx - g0.mx) + (t.my - g0.my) * (t.my - g0.my) >
                            (tight ? FIT_POLISH_SHIFT2 : FIT_ASCENT_SHIFT2) * la * lb ||
                        t.ax * t.ax + t.ay * t.ay > (tight ? FIT_POLISH_HI : FIT_ASCENT_HI) * la * la ||
                        t.ax * t.ax + t.ay * t.ay < (tight ? FIT_POLISH_LO : FIT_ASCENT_LO) * la * la ||
                        t.bx * t.bx + t.by * t.by > (tight ? FIT_POLISH_HI : FIT_ASCENT_HI) * lb * lb ||
                        t.bx * t.bx + t.by * t.by < (tight ? FIT_POLISH_LO : FIT_ASCENT_LO) * lb * lb)
                        continue;
                    if (memcmp(&t, &gp, sizeof t) == 0)
                        continue;
                    s = objective(im, &t, k, m, L, erase);
                    if (s > bs) {
                        gp = *gr;
                        bs = s;
                        bt = t;
                        *gr = bt; /* Gauss-Seidel sweep: move at once */
                        if (rf && frefused(rf, -s))
                            return 1;
                        break;
                    }
                }
            if (!(bs > best))
                break;
            best = bs;
            *gr = bt;
        }
    }
    if (score)
        *score = best;
    return 0;
}

/* Data cell i's reference cells: the black-ring cell next to it (towards the
 * tag centre; the ring corner for the data ring's corners) and the interior
 * cell next to that one. */
static void fref_cells(int i, int k, int *rx, int *ry, int *wx, int *wy)
{
    int cx, cy;
    actag_tag_bit_cell(4 * k, i, &cx, &cy);
    *rx = cx < 1 ? 1 : cx > k - 1 ? k - 1 : cx;
    *ry = cy < 1 ? 1 : cy > k - 1 ? k - 1 : cy;
    *wx = *rx < 2 ? 2 : *rx > k - 2 ? k - 2 : *rx;
    *wy = *ry < 2 ? 2 : *ry > k - 2 ? k - 2 : *ry;
}


/* Floor of the cell noise estimate, confidence units: clean renders have
 * none, and the margins divide by it. */
#define FIT_MIN_NOISE 0.05f

/* The least cell-noise variance a reading may claim: cells read to 10 % of
 * its contrast (a nearly perfect fit does not make any lead a certainty).
 * The template check and actag__fit_rss_llr share it. */
static float fnoise_floor2(float contrast)
{
    float f = FIT_MIN_NOISE * 2.0f * contrast;
    return f * f;
}

/* Template check (ACTAG_FIT_VERIFY). Each of the most likely readings is
 * a full hypothesis for all (k+1)^2 cells (data ring from its code, black
 * ring, white interior); its grid is refitted to that template and scored
 * by the residual of a two-level least-squares fit of the cell means
 * (rss). Every hypothesis thus gets its own best alignment, so a reading
 * that only a misaligned grid supports loses to the right one; the margin
 * is the log-likelihood ratio of the best against the next hypothesis
 * under Gaussian cell noise estimated from the best one's residual. */
static void layout_of(const actag_family *family, int id, int view, int k, uint8_t *L)
{
    int bits = 4 * k, n = k + 1, i, cx, cy;
    uint32_t e = family->codes[id];
    for (i = 0; i < (view & 3); i++)
        e = actag_code_rot90(e, bits);
    if (view >> 2)
        e = actag_code_mirror(e, bits);
    /* actag_tag_cell_value's layout, written side by side: black ring and
     * white interior, then the data ring clockwise from the top-left
     * corner, each side's k cells from its first corner, bit i of the ring
     * being bit (bits - 1 - i) of e (tests/test_decode_rival.c compares
     * every code and view with actag_tag_cell_value) */
    for (cy = 1; cy < k; cy++)
        for (cx = 1; cx < k; cx++)
            L[cy * n + cx] = (uint8_t)!(cx == 1 || cy == 1 || cx == k - 1 || cy == k - 1);
    for (i = 0; i < k; i++) {
        L[i] = (uint8_t)((e >> (bits - 1 - i)) & 1u);
        L[i * n + k] = (uint8_t)((e >> (bits - 1 - (k + i))) & 1u);
        L[k * n + (k - i)] = (uint8_t)((e >> (bits - 1 - (2 * k + i))) & 1u);
        L[(k - i) * n] = (uint8_t)((e >> (bits - 1 - (3 * k + i))) & 1u);
    }
}

/* decode_fit_test.h */
int actag__fit_layout(const actag_family *family, int id, int view, uint8_t *L)
{
    if (family == NULL || L == NULL)
        return ACTAG_ERR_NULL;
    if (family->bits < 16 || family->bits > 32 || family->bits % 4 != 0 || id < 0 ||
        id >= family->ncodes || view < 0 || view > 7)
        return ACTAG_ERR_PARAM;
    layout_of(family, id, view, family->bits / 4, L);
    return ACTAG_OK;
}

/* Residual of the cell means against a layout after a two-level (black,
 * white) least-squares fit. */
static float template_rss(const float *m, const uint8_t *L, int k, int erase, int *ncells)
{
    int n = k + 1, cx, cy, nw = 0, nb = 0;
    float sw = 0.0f, sb = 0.0f, ss = 0.0f;
    for (cy = 0; cy < n; cy++) {
        int c0 = erase && (cy == 0 || cy == k); /* erased corners: by the row's bounds */
        for (cx = c0; cx <= k - c0; cx++) {
            float v = m[cy * n + cx];
            ss += v * v;
            if (L[cy * n + cx]) {
                sw += v;
                nw++;
            } else {
                sb += v;
                nb++;
            }
        }
    }
    if (ncells)
        *ncells = nw + nb;
    return ss - (nw ? sw * sw / (float)nw : 0.0f) - (nb ? sb * sb / (float)nb : 0.0f);
}

/* The level-noise checks of the template check (ACTAG_FIT_LEVEL_NOISE,
 * ACTAG_FIT_SEPARATE_NOISE) apply when the reading's own template leaves
 * cell noise above this fraction of the contrast: the two-level model with
 * one noise variance then explains the cells poorly, and speckle being
 * multiplicative, a blurred or faded tag's white cells spread far more than
 * its ring. At 0.2 a cell misreads with probability 0.6 % (Phi(-0.5 /
 * 0.2)). Measured (docs/evaluation.md, thirty-ninth session): the seven
 * wrong IDs of the held-out sweeps had 0.24-0.32; a tenth of the right
 * readings at the paper's settings lie above 0.2; below it the checks
 * refused only right readings. */
#define FIT_LEVEL_NOISE_GATE 0.2f

/* The black (0) and white (1) cells of template L as template_rss counts
 * them: how many (cnt) and their sum of squares about their own mean (ss),
 * in two passes (means, then squares about them: one pass's sum of squares
 * minus the squared sum loses the variance of bright cells). */
static void template_class_ss(const float *m, const uint8_t *L, int k, int erase, int cnt[2],
                              float ss[2])
{
    int n = k + 1, cx, cy, pass;
    float sum[2] = {0.0f, 0.0f}, mean[2] = {0.0f, 0.0f};
    cnt[0] = cnt[1] = 0;
    ss[0] = ss[1] = 0.0f;
    for (pass = 0; pass < 2; pass++) {
        for (cy = 0; cy < n; cy++) {
            int c0 = erase && (cy == 0 || cy == k);
            for (cx = c0; cx <= k - c0; cx++) {
                int w = L[cy * n + cx] != 0;
                float v = m[cy * n + cx];
                if (pass == 0) {
                    sum[w] += v;
                    cnt[w]++;
                } else
                    ss[w] += (v - mean[w]) * (v - mean[w]);
            }
        }
        mean[0] = cnt[0] ? sum[0] / (float)cnt[0] : 0.0f;
        mean[1] = cnt[1] ? sum[1] / (float)cnt[1] : 0.0f;
    }
}

/* The level-noise model of one reading: its black and white cells' noise
 * variances (unbiased, each at least the floor) and their logs. */
typedef struct fnoise_lv {
    float var[2], lvar[2];
} fnoise_lv;

static void fnoise_lv_of(const int cnt[2], const float ss[2], float floor2, fnoise_lv *F)
{
    int w;
    for (w = 0; w < 2; w++) {
        float v = cnt[w] > 1 ? ss[w] / (float)(cnt[w] - 1) : floor2;
        F->var[w] = v < floor2 ? floor2 : v;
        F->lvar[w] = actag_logf(F->var[w]);
    }
}

/* -2 log-likelihood (up to a constant every template shares) of a
 * template's cells (cnt, ss as template_class_ss gives them): level noise
 * (ACTAG_FIT_LEVEL_NOISE), the reading's variances F for every template,
 * as s^2 is the reading's for the margin; separate noise
 * (ACTAG_FIT_SEPARATE_NOISE), each template's own maximum-likelihood
 * variances, floored (a generalised likelihood ratio: stricter). */
static float fdev_level(const int cnt[2], const float ss[2], const fnoise_lv *F)
{
    return ss[0] / F->var[0] + ss[1] / F->var[1] + (float)cnt[0] * F->lvar[0] +
           (float)cnt[1] * F->lvar[1];
}

static float fdev_separate(const int cnt[2], const float ss[2], float floor2)
{
    float d = 0.0f;
    int w;
    for (w = 0; w < 2; w++)
        if (cnt[w]) {
            float v = ss[w] / (float)cnt[w];
            d += (float)cnt[w] * actag_logf(v < floor2 ? floor2 : v);
        }
    return d;
}

int actag__fit_level_devs(const float *m, const uint8_t *L, int k, int erase, float floor2,
                          const float var[2], float *level, float *separate)
{
    int cnt[2];
    float ss[2];
    fnoise_lv F;
    if (!m || !L || !var || !level || !separate)
        return ACTAG_ERR_NULL;
    if (k < 4 || k > ACTAG_DECODE_MAX_K || !(floor2 > 0.0f) || !(var[0] > 0.0f) ||
        !(var[1] > 0.0f))
        return ACTAG_ERR_PARAM;
    template_class_ss(m, L, k, erase != 0, cnt, ss);
    F.var[0] = var[0];
    F.var[1] = var[1];
    F.lvar[0] = actag_logf(var[0]);
    F.lvar[1] = actag_logf(var[1]);
    *level = fdev_level(cnt, ss, &F);
    *separate = fdev_separate(cnt, ss, floor2);
    return ACTAG_OK;
}

static float tscore(const fimg *im, const fgrid *gr, int k, float *m, const uint8_t *L,
                    int erase)
{
    actag__fit_cells(im, gr, k, m, erase); /* template_rss skips erased corners: do not read them */
    return -template_rss(m, L, k, erase, NULL);
}

/* A wide-search start no ascent is likely to make readable: after the
 * lattice search, the black-ring cells above and interior cells below the
 * mid level plus the corrected bits of the likeliest code (5 samples a
 * cell, threshold 0) reach FIT_HOPELESS. An accepted wide reading needs
 * both together within its corrections (3). On the simulator's labelled
 * frames (pool seed 5, paper seed 6, 300 views each) and the 58 pool frames
 * the fitted grids that read had at most 10 here; 12 skips the ascent for
 * 15-41 % of the wide searches (docs/decoder.md). */
#define FIT_HOPELESS 12

/* Each data cell's confidence, (mean - threshold) / (white - black): the
 * threshold is level between the black ring and the white interior, or with
 * ACTAG_FIT_LOCAL the mean of the cell's two reference cells (fref_cells).
 * A clean bit reads +-0.5. white > black. */
static void fconfidences(const float *m, int k, int flags, float level, float black, float white,
                         float *c)
{
    int i, cx, cy, n = k + 1;
    float contrast = white - black;
    for (i = 0; i < 4 * k; i++) {
        float t;
        actag_tag_bit_cell(4 * k, i, &cx, &cy);
        if (flags & ACTAG_FIT_LOCAL) {
            int rx, ry, wx, wy;
            fref_cells(i, k, &rx, &ry, &wx, &wy);
            t = 0.5f * (m[ry * n + rx] + m[wy * n + wx]);
        } else {
            t = black + level * contrast;
        }
        c[i] = (m[cy * n + cx] - t) / contrast;
    }
}

/* The views a reading may take under the handedness flags. */
static unsigned fit_views(int flags)
{
    if (flags & ACTAG_FIT_ONLY_UNMIRRORED)
        return ACTAG_VIEWS_UNMIRRORED;
    if (flags & ACTAG_FIT_ONLY_MIRRORED)
        return ACTAG_VIEWS_MIRRORED;
    return ACTAG_VIEWS_ALL;
}

/* The family matcher's reading of cells m: their levels (*black, *white),
 * the data cells' confidences and the soft match over `views` into *r.
 * Returns 1, 0 when the cells show no contrast (white not above black; *r
 * untouched), or the matcher's negative error. */
static int fmatch_cells(const float *m, int k, int flags, float level, const actag_family *family,
                        uint32_t keep, unsigned views, float *black, float *white,
                        actag_soft_match *r)
{
    float c[32];
    int rc;
    flevels(m, k, black, white);
    if (!(*white - *black > 0.0f))
        return 0;
    fconfidences(m, k, flags, level, *black, *white, c);
    rc = actag_family_match_soft_views(family, c, keep, views, r);
    return rc == ACTAG_OK ? 1 : rc;
}

static int fhopeless(const fimg *im, const fgrid *gr, int k, int flags, float level,
                     const actag_family *family, uint32_t keep, float *m, int *err)
{
    int cx, cy, n = k + 1, miss = 0, rc;
    float black, white, mid;
    actag_soft_match r;
    fcells(im, gr, k, m);
    rc = fmatch_cells(m, k, flags, level, family, keep, fit_views(flags), &black, &white, &r);
    *err = rc < 0 ? rc : ACTAG_OK;
    if (rc == 0)
        return 1;
    if (rc < 0)
        return 0;
    mid = black + FIT_MID_LEVEL * (white - black);
    for (cy = 1; cy < k; cy++)
        for (cx = 1; cx < k; cx++) {
            float v = m[cy * n + cx];
            miss += is_ring(cx, cy, k) ? !(v < mid) : !(v > mid);
        }
    return miss + r.best.hamming >= FIT_HOPELESS;
}

/* a *= m for a little-endian number of ACTAG__BIG limbs (no overflow: the
 * operands of actag_fit_bit_lead stay below 2^180) */
#define ACTAG__BIG 6
static void big_mul(uint32_t *a, uint32_t m)
{
    uint64_t carry = 0;
    int i;
    for (i = 0; i < ACTAG__BIG; i++) {
        uint64_t v = (uint64_t)a[i] * m + carry;
        a[i] = (uint32_t)v;
        carry = v >> 32;
    }
}

/* a <= b */
static int big_le(const uint32_t *a, const uint32_t *b)
{
    int i;
    for (i = ACTAG__BIG - 1; i >= 0; i--)
        if (a[i] != b[i])
            return a[i] < b[i];
    return 1;
}

int actag_fit_bit_lead(int hamming, int nbits, int min_bit_margin, int min_bit_odds)
{
    /* exact: odds h^b and (n - h)^b as integers (below 2^20 32^32) */
    uint32_t lhs[ACTAG__BIG] = {0}, rhs[ACTAG__BIG] = {0};
    int b;
    if (nbits < 1 || nbits > 32 || hamming < 0 || hamming > nbits || min_bit_margin < 0 ||
        min_bit_margin > 32 || min_bit_odds < 1 || min_bit_odds > ACTAG_FIT_MAX_BIT_ODDS)
        return 33;
    if (hamming == 0 || min_bit_odds == 1)
        return min_bit_margin;
    if (2 * hamming >= nbits) /* a bit more of lead makes the runner-up no less likely */
        return 33;
    lhs[0] = (uint32_t)min_bit_odds;
    rhs[0] = 1u;
    for (b = 1; b <= 32; b++) {
        big_mul(lhs, (uint32_t)hamming);
        big_mul(rhs, (uint32_t)(nbits - hamming));
        if (big_le(lhs, rhs))
            return b > min_bit_margin ? b : min_bit_margin;
    }
    return 33;
}

void actag_fit_params_default(actag_fit_params *fp)
{
    if (fp == NULL)
        return;
    fp->flags = ACTAG_FIT_DEFAULT_FLAGS;
    fp->level = 0.5f;
    fp->min_contrast = 5;
    fp->sample_offset = 0.2f;
    fp->min_margin = ACTAG_FIT_MIN_MARGIN;
    fp->min_bit_margin = ACTAG_FIT_MIN_BIT_MARGIN;
    fp->min_bit_odds = ACTAG_FIT_MIN_BIT_ODDS;
    fp->many_corrections = ACTAG_FIT_MANY_CORRECTIONS;
    fp->many_corrections_margin = ACTAG_FIT_MANY_CORRECTIONS_MARGIN;
}

/* The affine grid of a clockwise white-square quad q (actag_tag_affine):
 * grid point (u, v) at m + a (u - n/2) + b (v - n/2), n = bits / 4 + 1. */
static int fgrid_of_quad(const actag_point q[4], int bits, fgrid *g)
{
    float H[9];
    int n = bits / 4 + 1, rc = actag_tag_affine(q, bits, H);
    if (rc != ACTAG_OK)
        return rc;
    g->ax = H[0];
    g->bx = H[1];
    g->ay = H[3];
    g->by = H[4];
    g->mx = H[2] + (H[0] + H[1]) * 0.5f * (float)n;
    g->my = H[5] + (H[3] + H[4]) * 0.5f * (float)n;
    return ACTAG_OK;
}

/* The at most nmax templates (allowed views, the reading's (id0, view0)
 * excepted) that best explain the cells m as whole templates, by rss,
 * lowest first (ties: the earlier template first), into id, view, rss;
 * L is scratch for a layout. Returns how many. */
static int frivals(const actag_family *family, unsigned views, int id0, int view0,
                   const float *m, int k, int erase, uint8_t *L, int nmax, int *id, int *view,
                   float *rss)
{
    int nr = 0, id2, v2, ia;
    for (id2 = 0; id2 < family->ncodes; id2++)
        for (v2 = 0; v2 < 8; v2++) {
            float r;
            if (!(views & (1u << v2)) || (id2 == id0 && v2 == view0))
                continue;
            layout_of(family, id2, v2, k, L);
            r = template_rss(m, L, k, erase, NULL);
            if (nr == nmax && !(r < rss[nr - 1]))
                continue;
            ia = nr < nmax ? nr++ : nr - 1;
            for (; ia > 0 && r < rss[ia - 1]; ia--) {
                rss[ia] = rss[ia - 1];
                id[ia] = id[ia - 1];
                view[ia] = view[ia - 1];
            }
            rss[ia] = r;
            id[ia] = id2;
            view[ia] = v2;
        }
    return nr;
}

/* Quad readings whose decision margin is below the least margin plus this
 * (nats) get the full-range re-check of their candidates (fread_grid).
 * Twice the default least margin: on simulated and real frames it refused
 * no right reading (docs/decoder.md); 2.5 and more cost real pool frames. */
#define FIT_RECHECK_BAND 2.0f

/* fread_grid's recheck bits */
#define FIT_RECHECK 1     /* the full-range re-check of a second-grid reading */
#define FIT_RECHECK_FAR 2 /* rivals by template: a quad far from affine */
/* Rivals a far-from-affine quad's reading is checked against: as many as
 * the likeliest readings of one grid (the Cortex-M7 budget's worst pool
 * frame: 123.9 M instructions with 6, 145.1 M with 12). */
#define FIT_FAR_RIVALS ACTAG_SOFT_TOP

/* The white-square corners of grid gr in tag order for a reading in view
 * (rotation, mirrored). */
static void fgrid_tag_corners(const fgrid *gr, int k, int rotation, int mirrored,
                              actag_point corners[4])
{
    actag_point fq[4];
    float lo = 2.0f - 0.5f * (float)(k + 1), hi = (float)(k - 1) - 0.5f * (float)(k + 1);
    static const int su[4] = {0, 1, 1, 0}, sv[4] = {0, 0, 1, 1};
    int i;
    for (i = 0; i < 4; i++) {
        float u = su[i] ? hi : lo, v = sv[i] ? hi : lo;
        fq[i].x = gr->mx + gr->ax * u + gr->bx * v;
        fq[i].y = gr->my + gr->ay * u + gr->by * v;
    }
    actag_tag_corners(fq, rotation, mirrored, corners);
}

/* A hypothesis (id, view) on grid g as a rival record. */
static void famb_set(actag__fit_rival *a, const fgrid *g, int k, int id, int view)
{
    a->id = id;
    a->rotation = view & 3;
    a->mirrored = view >> 2;
    fgrid_tag_corners(g, k, a->rotation, a->mirrored, a->fit_corners);
}

/* The stretched-grid check of a quad reading (fread_grid): the factors a
 * grid is stretched by along one axis, the rivals taken per start, the
 * most rivals polished, and the gate: a rival whose unpolished residual is
 * more than FIT_STRETCH_GATE times the reading's polished one is not
 * polished (its polish would have to lower it below the reading's by the
 * allowance; the polishes seen lowered a rival's residual by up to 3x, and
 * on the 58 pool frames every rival found lay beyond 2x: a cost gate, so
 * that correct readings pay 12 cell reads and no polish). */
#define FIT_STRETCH {1.25f, 1.5f}
/* the axes stretched: the grid's two (a, b), and the frame's rows (range:
 * the sonar erodes a white square at its near and far ranges, which is a
 * grid axis only when the tag stands upright in the image) */
#define FIT_STRETCH_AXES 3
#define FIT_STRETCH_RIVALS 2
#define FIT_STRETCH_MAX 4
#define FIT_STRETCH_GATE 2.0f

/* The stretched-grid check's rivals on cells m: the FIT_STRETCH_RIVALS
 * likeliest readings of the cells by the family matcher (as the template
 * check's candidates are found; a scan of every template, as frivals does,
 * costs 8 ncodes templates a grid: 71,280 for AcTag28m4), the reading
 * (id0, view0) excepted, with their template rss, in the matcher's
 * order. Returns how many, or the matcher's negative error. */
static int fstretch_rivals(const actag_family *family, unsigned views, int flags, float level,
                           uint32_t keep, int id0, int view0, const float *m, int k, int erase,
                           uint8_t *L, int *id, int *view, float *rss)
{
    float black, white;
    actag_soft_match mq;
    int a, nr = 0, rc;
    rc = fmatch_cells(m, k, flags, level, family, keep, views, &black, &white, &mq);
    if (rc <= 0)
        return rc;
    for (a = 0; a < mq.ntop && nr < FIT_STRETCH_RIVALS; a++) {
        if (mq.top[a].id == id0 && mq.top[a].view == view0)
            continue;
        id[nr] = mq.top[a].id;
        view[nr] = mq.top[a].view;
        layout_of(family, id[nr], view[nr], k, L);
        rss[nr] = template_rss(m, L, k, erase, NULL);
        nr++;
    }
    return nr;
}

/* The likelihood match of a grid's data confidences conf[0 .. bits-1]
 * (relative to the mid level). Thresholds: with ACTAG_FIT_SPLIT every split
 * of the sorted confidences between ACTAG_FIT_SPLIT_LO and _HI (relative
 * to the level) is read; otherwise the single threshold 0. Each reading is
 * matched by likelihood (actag_family_match_soft_views); the split whose
 * best code needs the fewest corrections wins (then the larger margin),
 * into *ml, its threshold into *tbest. Returns ACTAG_OK,
 * ACTAG_ERR_NO_MATCH (no split within max_corrections, a tie between the
 * two handednesses, or splits reading different tags without a lead of
 * FIT_SPLIT_LEAD bits), or the matcher's error. */
static int fmatch_splits(const float *conf, int bits, int flags, float level,
                         const actag_family *family, uint32_t keep, int max_corrections,
                         actag_soft_match *ml, float *tbest)
{
    float sv[32];
    int i, j, a, nsplit = 0, have = 0, rc;
    long key = -1;
    int kd = 99, od = 99; /* best distance of the kept key, of any other */
    if (flags & ACTAG_FIT_SPLIT) {
        for (i = 0; i < bits; i++)
            sv[i] = conf[i];
        for (i = 1; i < bits; i++)
            for (j = i; j > 0 && sv[j - 1] > sv[j]; j--) {
                float t = sv[j];
                sv[j] = sv[j - 1];
                sv[j - 1] = t;
            }
        nsplit = bits;
    } else {
        nsplit = 1;
    }
    for (j = 0; j < nsplit; j++) {
        float t, ct[32];
        actag_soft_match r;
        int dk;
        long key1;
        if (flags & ACTAG_FIT_SPLIT) {
            t = j == 0 ? sv[0] - 1.0f : 0.5f * (sv[j - 1] + sv[j]);
            if (t > ACTAG_FIT_SPLIT_HI - level)
                break;
            if (t < ACTAG_FIT_SPLIT_LO - level)
                continue;
        } else {
            t = 0.0f;
        }
        for (a = 0; a < bits; a++)
            ct[a] = conf[a] - t;
        rc = actag_family_match_soft_views(family, ct, keep, fit_views(flags), &r);
        if (rc != ACTAG_OK)
            return rc;
        dk = r.best.hamming;
        if (dk > max_corrections)
            continue;
        /* A tie between the two handednesses is no reading. */
        if (r.other == dk)
            return ACTAG_ERR_NO_MATCH;
        /* Splits that read as different tags (or poses): the threshold
         * decides the ID, so the reading is ambiguous unless one is closer
         * than every other by FIT_SPLIT_LEAD bits. */
        key1 = (long)r.best.id * 8L + (long)r.best.mirrored * 4L + (long)r.best.rotation;
        if (key < 0 || key == key1) {
            if (key < 0 || dk < kd)
                kd = dk;
            key = key1;
        } else if (dk < kd) {
            od = kd < od ? kd : od;
            kd = dk;
            key = key1;
        } else if (dk < od) {
            od = dk;
        }
        if (!have || dk < ml->best.hamming ||
            (dk == ml->best.hamming && r.d2 - r.d1 > ml->d2 - ml->d1)) {
            *ml = r;
            *tbest = t;
            have = 1;
        }
    }
    if (!have)
        return ACTAG_ERR_NO_MATCH;
    if (od < 99 && od - kd < FIT_SPLIT_LEAD)
        return ACTAG_ERR_NO_MATCH;
    return ACTAG_OK;
}

/* What the template check of one reading (fread_grid) and its further
 * checks share: the reading, the grids and cells it came from, and the
 * scratch they polish templates in. */
typedef struct fjudge {
    const fimg *im;
    const fgrid *gr;     /* the reading's grid */
    const fgrid *g_quad; /* the quad's own grid */
    const actag_family *family;
    const actag_fit_params *fp;
    const actag_point *q; /* the quad, clockwise */
    const actag_soft_match *ml; /* the reading's likelihood match */
    int k, n, bits, flags, erase, regrid;
    uint32_t keep;
    float level, look;
    float *m;    /* in: the cells of gr (of g_quad after a regrid); later scratch */
    float *mt;   /* scratch cells */
    uint8_t *L;  /* scratch layout */
    /* the candidates: the likeliest readings of gr, then of g_quad */
    int cid[2 * ACTAG_SOFT_TOP], cview[2 * ACTAG_SOFT_TOP], ncand;
    /* set by fjudge_templates: the reading's polished residual, the cell
     * noise it gives, and what fcell_noise2 needs again */
    float rss0, s2, floor2, contrast;
    int nc;
    int *ambig;            /* NULL, or set to 1 when a rival refuses the reading */
    actag__fit_rival *amb; /* NULL, or [0] the reading judged, [1] the rival */
} fjudge;

/* The reading is refused because hypothesis (id, view), polished from grid
 * g, explains the cells too nearly as well: records the rival. */
static int fjudge_refuse(const fjudge *J, const fgrid *g, int id, int view)
{
    if (J->ambig)
        *J->ambig = 1;
    if (J->amb)
        famb_set(&J->amb[1], g, J->k, id, view);
    return ACTAG_ERR_NO_MATCH;
}

/* The candidates' start grid: the reading's for its own likeliest
 * readings, the quad's for those found on the quad's grid. */
static const fgrid *fjudge_start(const fjudge *J, int jj)
{
    return jj < J->ml->ntop ? J->gr : J->g_quad;
}

/* The template check proper: every candidate's template polished near
 * the grid it came from (after the wide search, which may settle a cell
 * off, over the full range); the reading's (candidate 0) must explain the
 * cells better than each other by the least margin after the
 * look-elsewhere allowance. Sets J->rss0, s2, nc, floor2 and *margin (the
 * lead over the runner-up, before the allowance). */
static int fjudge_templates(fjudge *J, float *margin)
{
    const actag_soft_match *ml = J->ml;
    float rss0 = 0.0f, rss2 = 1e30f, s2 = 1.0f, lead_lv = 1e30f, dev0[2] = {0.0f, 0.0f}, ss[2];
    int jj, rc, levels = 0, cnt[2];
    fnoise_lv F = {{1.0f, 1.0f}, {0.0f, 0.0f}};
    J->ncand = 0;
    for (jj = 0; jj < ml->ntop; jj++) {
        J->cid[J->ncand] = ml->top[jj].id;
        J->cview[J->ncand++] = ml->top[jj].view;
    }
    if (J->amb) /* the reading the check judges, should it refuse it */
        famb_set(&J->amb[0], J->gr, J->k, J->cid[0], J->cview[0]);
    {
        float bq, wq;
        actag_soft_match mq;
        int a2, b2;
        fcells(J->im, J->g_quad, J->k, J->mt);
        rc = fmatch_cells(J->mt, J->k, J->flags, J->level, J->family, J->keep,
                          fit_views(J->flags), &bq, &wq, &mq);
        if (rc < 0)
            return rc;
        if (rc == 1) {
            for (a2 = 0; a2 < mq.ntop; a2++) {
                int dup = 0;
                for (b2 = 0; b2 < J->ncand; b2++)
                    dup |= J->cid[b2] == mq.top[a2].id && J->cview[b2] == mq.top[a2].view;
                if (!dup) {
                    J->cid[J->ncand] = mq.top[a2].id;
                    J->cview[J->ncand++] = mq.top[a2].view;
                }
            }
        }
    }
    for (jj = 0; jj < J->ncand; jj++) {
        float r, sc;
        frefuse rf;
        fgrid g = *fjudge_start(J, jj);
        layout_of(J->family, J->cid[jj], J->cview[jj], J->k, J->L);
        rf.rss0 = rss0;
        rf.s2 = s2;
        rf.look = J->look;
        rf.min_margin = J->fp->min_margin;
        /* the polish's own score of its final grid is that grid's rss (no
         * second read); m holds the cells of gr (the quad's grid after
         * regrid) */
        if (ffit(J->im, &g, J->k, J->mt, J->L, J->erase, !(J->flags & ACTAG_FIT_WIDE),
                 (jj < ml->ntop || J->regrid) ? J->m : NULL, jj ? &rf : NULL, &sc))
            /* refused before the polish ends */
            return fjudge_refuse(J, fjudge_start(J, jj), J->cid[jj], J->cview[jj]);
        r = -sc;
        if (jj == 0) {
            J->nc = J->n * J->n - (J->erase ? 4 : 0); /* the cells template_rss counts */
            rss0 = r;
            J->floor2 = fnoise_floor2(J->contrast);
            s2 = fcell_noise2(rss0, J->nc, J->floor2);
            /* the level-noise checks, for a poor fit (FIT_LEVEL_NOISE_GATE) */
            levels = s2 > FIT_LEVEL_NOISE_GATE * FIT_LEVEL_NOISE_GATE * J->contrast *
                              J->contrast
                         ? J->flags & (ACTAG_FIT_LEVEL_NOISE | ACTAG_FIT_SEPARATE_NOISE)
                         : 0;
            if (levels) { /* the cells of the polished grid, not of its last trial */
                actag__fit_cells(J->im, &g, J->k, J->mt, J->erase);
                template_class_ss(J->mt, J->L, J->k, J->erase, cnt, ss);
                fnoise_lv_of(cnt, ss, J->floor2, &F);
                dev0[0] = fdev_level(cnt, ss, &F);
                dev0[1] = fdev_separate(cnt, ss, J->floor2);
            }
            continue;
        }
        /* Another hypothesis explains the cells better once each has its
         * own grid (the code-agnostic reading cannot be trusted), or too
         * nearly as well: refuse now. The margin only falls as rss2 does,
         * so the first such hypothesis decides exactly what the least one
         * would. */
        if (r <= rss0 || 0.5f * (r - rss0) / s2 - J->look < J->fp->min_margin)
            return fjudge_refuse(J, fjudge_start(J, jj), J->cid[jj], J->cview[jj]);
        if (levels) { /* the same lead under each level's own noise */
            float lead = 1e30f;
            actag__fit_cells(J->im, &g, J->k, J->mt, J->erase);
            template_class_ss(J->mt, J->L, J->k, J->erase, cnt, ss);
            if (levels & ACTAG_FIT_LEVEL_NOISE)
                lead = 0.5f * (fdev_level(cnt, ss, &F) - dev0[0]);
            if (levels & ACTAG_FIT_SEPARATE_NOISE) {
                float l2 = 0.5f * (fdev_separate(cnt, ss, J->floor2) - dev0[1]);
                lead = l2 < lead ? l2 : lead;
            }
            if (lead - J->look < J->fp->min_margin)
                return fjudge_refuse(J, fjudge_start(J, jj), J->cid[jj], J->cview[jj]);
            if (lead < lead_lv)
                lead_lv = lead;
        }
        if (r < rss2)
            rss2 = r;
    }
    J->rss0 = rss0;
    J->s2 = s2;
    *margin = 0.5f * (rss2 - rss0) / s2;
    if (lead_lv < *margin) /* the lead under the least favourable noise model */
        *margin = lead_lv;
    return ACTAG_OK;
}

/* Full-range re-check (recheck FIT_RECHECK: the quad's own grid read after
 * the fitted grid's template check found a rival within the margin; or a
 * quad reading whose margin lies within FIT_RECHECK_BAND of the least). A
 * quad reading polishes each template only a quarter cell and +-15 % from
 * the grid it came from, so a hypothesis whose alignment lies farther away
 * (a quad of an eroded or bloomed white square, a fifth of a side short or
 * rotated) is judged at a grid that does not fit it: the ranking then
 * reflects the start grid, not the cells. That two grids of one quad rank
 * the same two hypotheses so differently is the sign of it. Each template
 * is polished again from its start over the full range of the
 * code-agnostic ascent (half a cell, 65-134 % of the sides); if a rival
 * then explains the cells better than the reading (each at its own best
 * grid), there is no reading, as in the tight check. (Simulated frame 444
 * of actag-eval --seed 102, docs/decoder.md: a mirrored tag 3 read as tag
 * 2 at margin 6.3 on the second grid; at full range tag 3's rss 408 beats
 * tag 2's 479.) The same, against the other IDs among the candidates, for
 * every quad reading whose margin lies within FIT_RECHECK_BAND of the
 * least: a thin lead over another ID won with tight polishes is no lead
 * when the rival's own grid lies farther away (the reading's other views
 * keep the tight check: a tracker's verify, which reads one code, is not
 * weakened). (Simulated frame 803 of actag-eval --seed 121: a mirrored tag
 * 1 at 3.67 m and 72 degrees read as tag 5 at margin 3.07 from a good
 * quad; at full range tag 1's rss 292 beats tag 5's 304.) A refusal here
 * names no rival (*ambig is left as it is). */
static int fjudge_full_range(const fjudge *J, int recheck)
{
    float f0 = 0.0f;
    int jj, other_ids = !(recheck & FIT_RECHECK); /* the thin margin's check */
    for (jj = 0; jj < J->ncand; jj++) {
        fgrid g = *fjudge_start(J, jj);
        float sc;
        frefuse rf;
        if (jj && other_ids && J->cid[jj] == J->cid[0])
            continue;
        layout_of(J->family, J->cid[jj], J->cview[jj], J->k, J->L);
        rf.rss0 = f0;
        rf.s2 = 1.0f;
        rf.look = 0.0f;
        rf.min_margin = -1e30f; /* refused only when r <= f0 */
        if (ffit(J->im, &g, J->k, J->mt, J->L, J->erase, 0,
                 (jj < J->ml->ntop || J->regrid) ? J->m : NULL, jj ? &rf : NULL, &sc))
            return ACTAG_ERR_NO_MATCH; /* a rival explains the cells better */
        if (jj == 0)
            f0 = -sc;
    }
    return ACTAG_OK;
}

/* Rivals by template for a quad no affine grid fits (recheck
 * FIT_RECHECK_FAR, see actag_decode_quad_fit). The candidates of the
 * template check are the likeliest by the bits read on the reading's grid
 * and the quad's, each polished a quarter cell from there; when the quad's
 * corners lie farther than that from any affine grid, the right hypothesis
 * may be neither a candidate nor within reach, and the margin then
 * measures the grid, not the cells. So the FIT_FAR_RIVALS hypotheses that
 * best explain the cells of the reading's grid as whole templates (rss, as
 * many as one grid's likeliest readings) are polished over the ascent's
 * full range, as is the reading's own, which must beat each by the least
 * margin after the look-elsewhere allowance. Bounded: at most
 * FIT_FAR_RIVALS + 1 polishes. (Simulated frame 673 of actag-eval --pool
 * --seed 105, docs/decoder.md: an unmirrored tag 4 read as a mirrored tag
 * 5 at margin 14.1; tag 4 was no candidate, ranks 5th here, and at full
 * range comes within 1.3 nats of tag 5.)
 * Then the quad's parallelograms: a quad this far from affine has a corner
 * cut (eroded) or grown (bloomed), and the parallelogram through its other
 * three corners is then near the tag, a cell or more from the reading's
 * grid, out of the polish's reach. From each of the four, the hypothesis
 * that best explains its cells (the reading excepted) is polished over the
 * full range and must stay below the reading by the least margin. Bounded:
 * 4 more polishes. (Simulated frame 586 of actag-eval --pool --seed 122:
 * an unmirrored tag 4 whose quad has one corner 1.3 cells inside, read as
 * a mirrored tag 5 at margin 9.9; tag 4 ranks 8th on the reading's grid,
 * first on the parallelogram without that corner, and comes within 0.7
 * nats of tag 5 there.) The cells of each are read into J->m: the
 * reading's own are not needed again. */
static int fjudge_far(const fjudge *J)
{
    const actag_soft_match *ml = J->ml;
    unsigned views = fit_views(J->flags);
    int rid[FIT_FAR_RIVALS], rview[FIT_FAR_RIVALS], nr, ia, k = J->k;
    float rr[FIT_FAR_RIVALS], f0, sc;
    fgrid g = *J->gr;
    frefuse rf;
    nr = frivals(J->family, views, ml->top[0].id, ml->top[0].view, J->m, k, J->erase, J->L,
                 FIT_FAR_RIVALS, rid, rview, rr);
    layout_of(J->family, ml->top[0].id, ml->top[0].view, k, J->L);
    ffit(J->im, &g, k, J->mt, J->L, J->erase, 0, J->m, NULL, &sc);
    f0 = -sc;
    rf.rss0 = f0;
    rf.s2 = fcell_noise2(f0, J->nc, J->floor2);
    rf.look = J->look;
    rf.min_margin = J->fp->min_margin;
    for (ia = 0; ia < nr; ia++) {
        layout_of(J->family, rid[ia], rview[ia], k, J->L);
        g = *J->gr;
        if (ffit(J->im, &g, k, J->mt, J->L, J->erase, 0, J->m, &rf, NULL))
            return fjudge_refuse(J, J->gr, rid[ia], rview[ia]); /* a rival within the margin */
    }
    for (ia = 0; ia < 4; ia++) {
        float rb;
        actag_point qc[4];
        int bid, bv;
        memcpy(qc, J->q, sizeof qc);
        qc[ia].x = J->q[(ia + 3) & 3].x + J->q[(ia + 1) & 3].x - J->q[(ia + 2) & 3].x;
        qc[ia].y = J->q[(ia + 3) & 3].y + J->q[(ia + 1) & 3].y - J->q[(ia + 2) & 3].y;
        if (fgrid_of_quad(qc, J->bits, &g) != ACTAG_OK)
            continue;
        fcells(J->im, &g, k, J->m);
        if (frivals(J->family, views, ml->top[0].id, ml->top[0].view, J->m, k, J->erase, J->L, 1,
                    &bid, &bv, &rb) < 1)
            continue;
        layout_of(J->family, bid, bv, k, J->L);
        if (J->amb) /* the parallelogram's grid, before the polish moves it */
            famb_set(&J->amb[1], &g, k, bid, bv);
        if (ffit(J->im, &g, k, J->mt, J->L, J->erase, 0, J->m, &rf, NULL)) {
            if (J->ambig)
                *J->ambig = 1;
            return ACTAG_ERR_NO_MATCH;
        }
    }
    return ACTAG_OK;
}

/* The reading's own other handedness, for a wide reading (a search
 * position or contour guess, which the quad checks below do not cover)
 * and for a quad reading with a thin margin (FIT_RECHECK_BAND) or a
 * corrected bit: the same code in each allowed view of the other
 * handedness (the same corners labelled in reflected orders) is polished
 * over the full range from the reading's grid, as is the reading's
 * template; when one explains the cells better, there is no reading.
 * AcTag24h10's codes lie only 4 of the 20 read bits from their own mirror
 * images (docs/families.md), and the bit-by-bit reading can favour the
 * wrong one where the cells as a whole do not; the soft match ranks the
 * right view far down (6 bits), so it is no candidate of the template
 * check, and unpolished on the reading's grid its template explains the
 * cells 2-3 times worse. At most 5 polishes a reading.
 * (Simulated frame 905 of actag-eval --seed 9210 on the 530 x 512 sonar
 * with both orientation flags: a mirrored tag 5 at 2.33 m read unmirrored,
 * top for bottom, at margin 2.2; the quad's own grid then reads it
 * mirrored at margin 5.4. Frame 920 of --seed 314: a mirrored tag 6 read
 * unmirrored at margin 3.4, which the extra margin at the correction limit
 * refused. Frame 230 of --seed 311 --gain 520 --bands 5 --looks 1: a
 * mirrored tag 5 read unmirrored by the structure search at margin 6.5.
 * Checking every quad reading too cost 5.4 M Cortex-M7 instructions a pool
 * frame, these 1.2 M.) Quad readings with a corrected bit, whatever their
 * margin: the bits are then not the code's own, and its own mirror image
 * lies only 4 bits off (held-out frames 948 of bench/heldout_sweep.py
 * --mix c24h10 seed 9710 and 631 of seed 9729: a mirrored tag 5 read
 * unmirrored, top for bottom, at hamming 1 and 2, margins 6.2 and 4.9; 2.0
 * M more a pool frame). */
static int fjudge_handedness(const fjudge *J)
{
    const actag_soft_match *ml = J->ml;
    int mir = ml->top[0].view >> 2, v2;
    /* the allowed views of the other handedness */
    unsigned others =
        fit_views(J->flags) & (mir ? ACTAG_VIEWS_UNMIRRORED : ACTAG_VIEWS_MIRRORED);
    float f0 = 0.0f, sc;
    fgrid g;
    if (others) { /* the reading's template, polished once */
        layout_of(J->family, ml->top[0].id, ml->top[0].view, J->k, J->L);
        g = *J->gr;
        ffit(J->im, &g, J->k, J->mt, J->L, J->erase, 0, NULL, NULL, &sc);
        f0 = -sc < J->rss0 ? -sc : J->rss0;
    }
    for (v2 = 0; v2 < 8; v2++) {
        if (!(others & (1u << v2)))
            continue;
        layout_of(J->family, ml->top[0].id, v2, J->k, J->L);
        g = *J->gr;
        ffit(J->im, &g, J->k, J->mt, J->L, J->erase, 0, NULL, NULL, &sc);
        if (-sc < f0)
            return fjudge_refuse(J, J->gr, ml->top[0].id, v2);
    }
    return ACTAG_OK;
}

/* Stretched grids (a quad reading that would be accepted): a white square
 * eroded along one axis (the tag's near and far edges lost to the
 * threshold, or one of them) gives a quad, and a grid, that is short along
 * that axis; the right template's grid then lies beyond the polishes'
 * reach (65-134 % of the sides), and a wrong one fits the misplaced cells.
 * So the grid is stretched along each of its axes and along the frame's
 * rows (FIT_STRETCH_AXES; a tag turned in the image is eroded in range,
 * across its axes) by FIT_STRETCH (a quarter, a half), about its centre
 * and about either end (18 starts); on each, the FIT_STRETCH_RIVALS
 * templates other than the reading that best explain the cells are the
 * rivals. A rival that explains them better than the reading's own
 * template there (both unpolished) and within FIT_STRETCH_GATE of the
 * reading's polished residual is polished over the full range from that
 * start, as is the reading's template; when the rival then explains the
 * cells better than the reading (its best of the two polishes), there is
 * no reading: the reading has lost its lead to a hypothesis at a grid the
 * sonar can show. (Before 2026-12-03's seventh session the rival had to
 * win by ln 24 nats, an allowance for the starts tried; frame 378 of
 * actag-eval --seed 1009 --rows 530 --cols 512 --min-range 0.1 --max-range
 * 3.5 --min-distance 0.5 --max-distance 3 --range-ascending: an unmirrored
 * tag 4 at 1.71 m and 79 degrees, turned 37 degrees in the image, its quad
 * two thirds of the tag's height in range, read as tag 5 at margin 6.0;
 * from the grid stretched by a half along the rows tag 4's template
 * explains the cells 0.9 nats better.) (Simulated frame 810 of actag-eval
 * --pool --seed 91: a mirrored tag 6 at 0.94 m and 70 degrees whose quad
 * is a quarter short in range, read as an unmirrored tag 5 at margin 4.11;
 * from the grid stretched by a quarter about its near end, tag 6's
 * template explains the cells by 7.8 nats better. The same on frame 408 of
 * --seed 311 with --seabed-level 0.18 or --gain 130 --metal-specular 1.2
 * --seabed-level 0.18.) */
static int fjudge_stretched(const fjudge *J)
{
    static const float fac[2] = FIT_STRETCH;
    const actag_soft_match *ml = J->ml;
    const fgrid *gr = J->gr;
    unsigned views = fit_views(J->flags);
    int ax2, fi, an, nst = 0, ci, j3, k = J->k;
    int sid[FIT_STRETCH_MAX], sview[FIT_STRETCH_MAX];
    float sgap[FIT_STRETCH_MAX], half = 0.5f * (float)J->n;
    fgrid sg[FIT_STRETCH_MAX];
    for (ax2 = 0; ax2 < FIT_STRETCH_AXES; ax2++)
        for (fi = 0; fi < 2; fi++)
            for (an = -1; an <= 1; an++) {
                fgrid g = *gr;
                float rr3[FIT_STRETCH_RIVALS], rown;
                float sx = ax2 == 1 ? gr->bx : gr->ax, sy = ax2 == 1 ? gr->by : gr->ay;
                int id3[FIT_STRETCH_RIVALS], v3[FIT_STRETCH_RIVALS], nr3;
                if (ax2 == 2) {
                    /* along the rows only: the grid's extent in y scales,
                     * its x stays */
                    sx = 0.0f;
                    sy = (gr->ay < 0.0f ? -gr->ay : gr->ay) + (gr->by < 0.0f ? -gr->by : gr->by);
                    g.ay *= fac[fi];
                    g.by *= fac[fi];
                } else if (ax2) {
                    g.bx *= fac[fi];
                    g.by *= fac[fi];
                } else {
                    g.ax *= fac[fi];
                    g.ay *= fac[fi];
                }
                /* an = -1 / +1: the low / high end stays */
                g.mx += (float)an * (fac[fi] - 1.0f) * half * sx;
                g.my += (float)an * (fac[fi] - 1.0f) * half * sy;
                fcells(J->im, &g, k, J->mt);
                nr3 = fstretch_rivals(J->family, views, J->flags, J->level, J->keep,
                                      ml->top[0].id, ml->top[0].view, J->mt, k, J->erase, J->L,
                                      id3, v3, rr3);
                if (nr3 < 0)
                    return nr3;
                layout_of(J->family, ml->top[0].id, ml->top[0].view, k, J->L);
                rown = template_rss(J->mt, J->L, k, J->erase, NULL);
                for (j3 = 0; j3 < nr3; j3++) {
                    float gap = rown - rr3[j3];
                    if (!(gap > 0.0f) || !(rr3[j3] < FIT_STRETCH_GATE * J->rss0))
                        continue;
                    /* each rival once, from its start of largest lead */
                    for (ci = 0; ci < nst; ci++)
                        if (sid[ci] == id3[j3] && sview[ci] == v3[j3])
                            break;
                    if (ci < nst) {
                        if (gap > sgap[ci]) {
                            sgap[ci] = gap;
                            sg[ci] = g;
                        }
                    } else if (nst < FIT_STRETCH_MAX) {
                        sid[nst] = id3[j3];
                        sview[nst] = v3[j3];
                        sgap[nst] = gap;
                        sg[nst++] = g;
                    }
                }
            }
    for (ci = 0; ci < nst; ci++) {
        fgrid g = sg[ci];
        float sc, f0, rr;
        layout_of(J->family, ml->top[0].id, ml->top[0].view, k, J->L);
        ffit(J->im, &g, k, J->mt, J->L, J->erase, 0, NULL, NULL, &sc);
        f0 = -sc < J->rss0 ? -sc : J->rss0;
        g = sg[ci];
        layout_of(J->family, sid[ci], sview[ci], k, J->L);
        ffit(J->im, &g, k, J->mt, J->L, J->erase, 0, NULL, NULL, &sc);
        rr = -sc;
        if (rr < f0)
            return fjudge_refuse(J, &sg[ci], sid[ci], sview[ci]);
    }
    return ACTAG_OK;
}

/* The template check and the checks after it, in order (see fread_grid):
 * ACTAG_OK when the reading stands, with *margin its lead over the
 * runner-up before the look-elsewhere allowance. */
static int fjudge_reading(fjudge *J, int recheck, float *margin)
{
    const float least = J->fp->min_margin;
    int wide = (J->flags & ACTAG_FIT_WIDE) != 0, rc;
    rc = fjudge_templates(J, margin);
    if (rc != ACTAG_OK)
        return rc;
    if (((recheck & FIT_RECHECK) || *margin - J->look < least + FIT_RECHECK_BAND) && !wide &&
        *margin - J->look >= least) {
        rc = fjudge_full_range(J, recheck);
        if (rc != ACTAG_OK)
            return rc;
    }
    if ((recheck & FIT_RECHECK_FAR) && !wide && *margin - J->look >= least) {
        rc = fjudge_far(J);
        if (rc != ACTAG_OK)
            return rc;
    }
    if (*margin - J->look >= least &&
        (wide || J->ml->best.hamming >= 1 || *margin - J->look < least + FIT_RECHECK_BAND)) {
        rc = fjudge_handedness(J);
        if (rc != ACTAG_OK)
            return rc;
    }
    if (!wide && *margin - J->look >= least)
        return fjudge_stretched(J);
    return ACTAG_OK;
}

/* One reading of grid gr (9 samples a cell into m): levels, confidences,
 * the likelihood match (fmatch_splits), the bit margin and the template
 * check with the checks after it (fjudge_reading), as the manual in
 * decode.h describes. regrid: this is the quad's own grid read
 * after the fitted one read nothing (one more grid in the look-elsewhere
 * allowance). *ambig (if not NULL) is set to 1 when the template check
 * refused the reading because a rival template came within the margin, or
 * the bit lead's odds did (actag_fit_bit_lead; amb then holds the reading
 * and its nearest other view in bits, both on this grid).
 * recheck (bits): FIT_RECHECK, before accepting a tightly polished
 * reading, polish every candidate template again over the ascent's full
 * range; FIT_RECHECK_FAR, polish the reading's template and its
 * FIT_FAR_RIVALS likeliest rivals over the full range (see the template
 * check). amb (if not NULL, 2 readings): once the template check starts,
 * amb[0] is the reading it judges, and when it refuses it as ambiguous
 * (*ambig), amb[1] is the rival that did (famb_set: id, rotation, mirrored,
 * fit_corners on the grid its polish started from).
 * Returns ACTAG_OK (out filled), ACTAG_ERR_NO_MATCH, or the matcher's
 * error. */
static int fread_grid(const fimg *im, const fgrid *gr, const fgrid *g_quad, int k,
                      const actag_family *family, int max_corrections,
                      const actag_fit_params *fp, uint32_t keep, const actag_point q[4],
                      int regrid, float *m, actag_decode_result *out, int *ambig, int recheck,
                      actag__fit_rival *amb)
{
    int flags = fp->flags, min_contrast = fp->min_contrast, bits = family->bits, n = k + 1;
    float level = fp->level;
    float conf[32], black, white, contrast, flips = 0.0f, minc = 1e30f;
    actag_soft_match ml;
    float margin = 0.0f, noise2 = 0.0f, look;
    int nknown = 0, rc, i, ring_ok = 0, in_ok = 0, cx, cy;
    uint32_t w = 0, e, diff;
    memset(&ml, 0, sizeof ml);
    fcells(im, gr, k, m); /* the reading itself: all 9 samples per cell */
    /* The whole grid must lie in the image: a tag cut by the frame edge
     * cannot be read (edge replication would invent its data cells). */
    {
        float ex = (gr->ax < 0.0f ? -gr->ax : gr->ax) + (gr->bx < 0.0f ? -gr->bx : gr->bx);
        float ey = (gr->ay < 0.0f ? -gr->ay : gr->ay) + (gr->by < 0.0f ? -gr->by : gr->by);
        float hw = 0.5f * (float)k; /* centre to the data cells' centres, cells */
        if (gr->mx - ex * hw < 0.0f || gr->mx + ex * hw > (float)(im->cols - 1) ||
            gr->my - ey * hw < 0.0f || gr->my + ey * hw > (float)(im->rows - 1))
            return ACTAG_ERR_NO_MATCH;
    }
    flevels(m, k, &black, &white);
    contrast = white - black;
    if (!(contrast >= (float)min_contrast) || !(contrast > 0.0f))
        return ACTAG_ERR_NO_MATCH;
    for (cy = 1; cy < k; cy++)
        for (cx = 1; cx < k; cx++) {
            float v = m[cy * n + cx], d;
            if (is_ring(cx, cy, k)) {
                ring_ok += v < black + FIT_MID_LEVEL * contrast;
                d = v - black;
            } else {
                in_ok += v > black + FIT_MID_LEVEL * contrast;
                d = v - white;
            }
            noise2 += d * d;
            nknown++;
        }
    /* cell noise in confidence units (a clean bit reads +-0.5), from the
     * cells whose value is known; floored so clean renders stay finite */
    noise2 = noise2 / ((float)nknown * contrast * contrast);
    if (noise2 < FIT_MIN_NOISE * FIT_MIN_NOISE)
        noise2 = FIT_MIN_NOISE * FIT_MIN_NOISE;
    fconfidences(m, k, flags, level, black, white, conf);
    for (i = 0; i < bits; i++) {
        float c = conf[i];
        w = (w << 1) | (c > 0.0f ? 1u : 0u);
        c = c < 0.0f ? -c : c;
        if (c < minc)
            minc = c;
    }

    {
        float tbest = 0.0f;
        rc = fmatch_splits(conf, bits, flags, level, family, keep, max_corrections, &ml, &tbest);
        if (rc != ACTAG_OK)
            return rc;
        w = 0;
        for (i = 0; i < bits; i++) { /* confidences relative to the chosen threshold */
            conf[i] -= tbest;
            if (conf[i] == 0.0f)
                conf[i] = -0.01f;
            w = (w << 1) | (conf[i] > 0.0f ? 1u : 0u);
        }
        /* the bit margin and its odds (ACTAG_FIT_MIN_BIT_ODDS) need no
         * template check: refuse before it. A reading the odds refuse has
         * a view too near for its bit errors: it is refused as too close
         * to call, as by a rival template (*ambig, amb: the reading and
         * its nearest other view in bits, on this grid), so that the
         * quad's own grid is read with the recheck and the pair contests
         * other readings of the place (detect.c: the contour's guesses,
         * the search's readings) as a rival's refusal does */
        if (ml.h2 - ml.best.hamming < fp->min_bit_margin)
            return ACTAG_ERR_NO_MATCH;
        if (ml.h2 - ml.best.hamming < actag_fit_bit_lead(ml.best.hamming, actag_popcount32(keep),
                                                          fp->min_bit_margin, fp->min_bit_odds)) {
            if (amb) {
                int jj, near = 0;
                for (jj = 1; jj < ml.ntop; jj++)
                    if (near == 0 || ml.top[jj].h < ml.top[near].h)
                        near = jj;
                famb_set(&amb[0], gr, k, ml.top[0].id, ml.top[0].view);
                famb_set(&amb[1], gr, k, ml.top[near].id, ml.top[near].view);
            }
            if (ambig)
                *ambig = 1;
            return ACTAG_ERR_NO_MATCH;
        }
        /* Look-elsewhere allowance: the best of N hypotheses (8 views of
         * every code, times the grids the wide search tries, times 2 on the
         * second grid) beats the next by ln N on pure noise; the margin
         * counts what is left. */
        look = actag_logf(8.0f * (float)family->ncodes *
                          ((flags & ACTAG_FIT_WIDE) ? (float)FIT_WIDE_GRIDS : 1.0f) *
                          (regrid ? 2.0f : 1.0f) * im->looks);
        /* log-likelihood ratio best : runner-up under Gaussian cell noise */
        margin = (float)(ml.d2 - ml.d1) * (1.0f / (float)ACTAG_SOFT_SCALE) / noise2;
        if ((flags & ACTAG_FIT_VERIFY) && ml.ntop > 1) {
            /* the template check (fjudge_reading) */
            uint8_t L[(ACTAG_DECODE_MAX_K + 1) * (ACTAG_DECODE_MAX_K + 1)];
            float mt[(ACTAG_DECODE_MAX_K + 1) * (ACTAG_DECODE_MAX_K + 1)];
            fjudge J;
            memset(&J, 0, sizeof J);
            J.im = im;
            J.gr = gr;
            J.g_quad = g_quad;
            J.family = family;
            J.fp = fp;
            J.q = q;
            J.ml = &ml;
            J.k = k;
            J.n = n;
            J.bits = bits;
            J.flags = flags;
            J.erase = (flags & ACTAG_FIT_ERASE_CORNERS) != 0;
            J.regrid = regrid;
            J.keep = keep;
            J.level = level;
            J.look = look;
            J.m = m;
            J.mt = mt;
            J.L = L;
            J.contrast = contrast;
            J.ambig = ambig;
            J.amb = amb;
            rc = fjudge_reading(&J, recheck, &margin);
            if (rc != ACTAG_OK)
                return rc;
        }
        margin -= look;
        /* at the correction limit another code may be as near as the read
         * one: the soft evidence must lead by more (decode.h) */
        if (margin < fp->min_margin + (ml.best.hamming >= fp->many_corrections
                                           ? fp->many_corrections_margin
                                           : 0.0f))
            return ACTAG_ERR_NO_MATCH;
        out->bit_margin = ml.h2 - ml.best.hamming;
    }

    out->observed = w;
    out->ring_black = (float)ring_ok / (float)(4 * (k - 2));
    out->interior_white = (float)in_ok / (float)((k - 3) * (k - 3));
    decode_set_reading(out, q, &ml.best, ml.other);
    out->decision_margin = margin;
    /* the word a perfect reading would have given */
    e = family->codes[out->id];
    for (i = 0; i < out->rotation; i++)
        e = actag_code_rot90(e, bits);
    if (out->mirrored)
        e = actag_decode_mirror(e, bits);
    /* the fitted grid's white-square corners, in the same tag order */
    fgrid_tag_corners(gr, k, out->rotation, out->mirrored, out->fit_corners);
    diff = (w ^ e) & keep;
    for (i = 0; i < bits; i++)
        if (diff & ((uint32_t)1u << (bits - 1 - i)))
            flips += conf[i] < 0.0f ? -conf[i] : conf[i];
    out->contrast = contrast;
    out->flip_weight = flips;
    out->min_confidence = minc;
    return ACTAG_OK;
}

/* The frame as the cell reads see it: 9 samples a cell, looks as given
 * (2: a second look, see fimg), the SSE2 samplers where they apply and the
 * AVX2 ones where the processor has them. */
static void fimg_of(const uint8_t *grey, int rows, int cols, int stride,
                    const actag_fit_params *fp, float looks, fimg *im)
{
    im->img = grey;
    im->rows = rows;
    im->cols = cols;
    im->stride = stride;
    im->so = fp->sample_offset;
    im->fast = 0;
    im->looks = looks;
#if ACTAG__FIT_SIMD
    im->simd = actag__fit_simd_ok(rows, cols, stride);
    im->avx2 = actag__fit_avx2_reads();
#endif
}

/* From the quad's grid *gr: with ACTAG_FIT_WIDE the lattice search
 * (fshift) and the hopeless test, then (unless ACTAG_FIT_NO_SEARCH) the
 * code-agnostic ascent. Returns 1 for a hopeless start (*gr then the
 * lattice's best, no ascent), 0, or the matcher's negative error. */
static int fsearch(fimg *im, fgrid *gr, int k, int flags, float level,
                   const actag_family *family, uint32_t keep, float *m)
{
    int rc = ACTAG_OK;
    if (flags & ACTAG_FIT_WIDE) {
        im->fast = 1; /* the coarse search compares grids: 5 samples a cell suffice */
        fshift(im, gr, k, m);
        if (!(flags & ACTAG_FIT_NO_SEARCH) &&
            fhopeless(im, gr, k, flags, level, family, keep, m, &rc)) {
            im->fast = 0;
            return 1;
        }
        im->fast = 0;
        if (rc != ACTAG_OK)
            return rc;
    }
    if (!(flags & ACTAG_FIT_NO_SEARCH))
        ffit(im, gr, k, m, NULL, 0, 0, NULL, NULL, NULL);
    return 0;
}

int actag_decode_quad_fit(const uint8_t *grey, int rows, int cols, int stride,
                          const actag_point quad[4], const actag_family *family,
                          int max_corrections, const actag_fit_params *fp,
                          actag_decode_result *out)
{
    return actag__decode_quad_fit_grids(grey, rows, cols, stride, quad, family, max_corrections,
                                        fp, out, NULL, NULL);
}

/* Corrected bits a blind box's own grid may be read with (decode_fit_grids.h,
 * blind), -1 for none: the most t <= max_corrections at which a chance word
 * of the nbits read lies within t bits of one of the family's ncodes codes
 * in one of its `views` views with probability at most 1 % (views x ncodes
 * x V(nbits, t) <= 2^nbits / 100, V the Hamming ball's volume). Such a
 * grid was never fitted to the tag: over a tag turned in the image it is a
 * lattice across the tag's cells, and what it reads is close to a chance
 * word, yet with every black-ring and white-interior cell right
 * (actag-eval --seed 12, frame 759: a search box over a mirrored tag 4
 * turned 40 degrees read tag 5 at hamming 2, margin 10.9). AcTag24h10 (7
 * codes, 8 views, 20 bits): 1; AcTag24m10 (1 code): 2; AcTag24h8 (45): 1;
 * AcTag24h6 (453): 0; AcTag24h4 (6261): none. */
static int fblind_corrections(int nbits, int ncodes, int views, int max_corrections)
{
    /* no overflow: while n x vol <= 2^nbits, the next term adds at most
     * nbits times as much (C(nbits, t) <= nbits V(nbits, t - 1)), so n x vol
     * stays below 2^32 x 33 */
    uint64_t vol = 0u, c = 1u, n = (uint64_t)views * (uint64_t)ncodes * 100u;
    int t;
    for (t = 0; t <= max_corrections; t++) {
        if (t > 0)
            c = c * (uint64_t)(nbits - t + 1) / (uint64_t)t; /* C(nbits, t), exact */
        vol += c;
        if (n * vol > ((uint64_t)1u << nbits))
            return t - 1;
    }
    return max_corrections;
}

/* Test hook (decode_fit_test.h). */
int actag__fit_blind_corrections(int nbits, int ncodes, int views, int max_corrections)
{
    if (nbits < 1 || nbits > 32 || ncodes < 1 || ncodes > 32768 || (views != 4 && views != 8) ||
        max_corrections < 0 || max_corrections > nbits)
        return ACTAG_ERR_PARAM;
    return fblind_corrections(nbits, ncodes, views, max_corrections);
}

/* decode_fit_grids.h */
int actag__decode_quad_fit_grids(const uint8_t *grey, int rows, int cols, int stride,
                                 const actag_point quad[4], const actag_family *family,
                                 int max_corrections, const actag_fit_params *fp,
                                 actag_decode_result *out, actag__fit_grids *grids,
                                 actag__fit_amb *amb)
{
    int flags;
    float level;
    fimg im;
    fgrid gr, g_quad;
    float m[(ACTAG_DECODE_MAX_K + 1) * (ACTAG_DECODE_MAX_K + 1)];
    actag_point q[4];
    uint32_t keep;
    int rc, bits, k, ambig = 0, far = 0, hopeless, qmax;
    if (grey == NULL || quad == NULL || family == NULL || fp == NULL || out == NULL)
        return ACTAG_ERR_NULL;
    rc = decode_check_frame_family(grey, rows, cols, stride, family);
    if (rc != ACTAG_OK)
        return rc;
    flags = fp->flags;
    level = fp->level;
    if (actag_fit_params_validate(fp, NULL) != ACTAG_OK)
        return ACTAG_ERR_PARAM;
    rc = decode_check_corrections(family, max_corrections);
    if (rc != ACTAG_OK)
        return rc;
    bits = family->bits;
    k = bits / 4;
    keep = actag_code_mask(bits);
    if (flags & ACTAG_FIT_ERASE_CORNERS)
        keep &= ~actag_code_corners(bits);
    /* The quad's own grid (the second grid, and the only one after a
     * hopeless start): a blind box's with fblind_corrections. */
    qmax = grids && grids->blind
               ? fblind_corrections(actag_popcount32(keep), family->ncodes,
                                    actag_popcount32(fit_views(flags)), max_corrections)
               : max_corrections;
    rc = actag_tag_quad_clockwise(quad, q);
    if (rc != ACTAG_OK)
        return rc;
    rc = fgrid_of_quad(q, bits, &gr);
    if (rc != ACTAG_OK)
        return rc;
    fimg_of(grey, rows, cols, stride, fp, grids && grids->read_before ? 2.0f : 1.0f, &im);
    g_quad = gr; /* the quad's own grid: the template check's second start and the second grid */
    {
        /* A quad no affine grid fits to within the tight polish's reach:
         * the least-squares affine grid misses each corner by a quarter of
         * d = q0 - q1 + q2 - q3 (an affine grid's corners have d = 0), so
         * when |d| / 4 exceeds the polish's quarter cell (its shift limit,
         * FIT_POLISH_SHIFT2 of la * lb) the template check cannot trust its
         * start (FIT_RECHECK_FAR). */
        float dx = q[0].x - q[1].x + q[2].x - q[3].x, dy = q[0].y - q[1].y + q[2].y - q[3].y;
        float la2 = gr.ax * gr.ax + gr.ay * gr.ay, lb2 = gr.bx * gr.bx + gr.by * gr.by;
        if ((dx * dx + dy * dy) * (1.0f / 16.0f) >
            FIT_POLISH_SHIFT2 * actag_sqrtf(la2) * actag_sqrtf(lb2))
            far = FIT_RECHECK_FAR;
    }
    if (grids && (flags & ACTAG_FIT_WIDE) && grids->state != 0) {
        /* the wide search of an earlier reading of this candidate */
        hopeless = grids->state == 2;
        gr.mx = grids->g[0];
        gr.my = grids->g[1];
        gr.ax = grids->g[2];
        gr.ay = grids->g[3];
        gr.bx = grids->g[4];
        gr.by = grids->g[5];
    } else {
        hopeless = fsearch(&im, &gr, k, flags, level, family, keep, m);
        if (hopeless < 0)
            return hopeless;
        if (grids && (flags & ACTAG_FIT_WIDE)) {
            grids->g[0] = gr.mx;
            grids->g[1] = gr.my;
            grids->g[2] = gr.ax;
            grids->g[3] = gr.ay;
            grids->g[4] = gr.bx;
            grids->g[5] = gr.by;
            grids->state = hopeless ? 2 : 1;
        }
    }
    /* a hopeless start: straight to the quad's own grid (the second grid,
     * as if the fitted one had read nothing) */
    if (amb)
        amb->amb = amb->amb2 = 0;
    if (hopeless && qmax < 0)
        return ACTAG_ERR_NO_MATCH;
    if (hopeless) {
        rc = fread_grid(&im, &g_quad, &g_quad, k, family, qmax, fp, keep, q, 1, m,
                        out, &ambig, 0, amb ? amb->r : NULL);
        if (amb && rc == ACTAG_ERR_NO_MATCH && ambig)
            amb->amb = 1;
        return rc;
    }
    rc = fread_grid(&im, &gr, &g_quad, k, family, max_corrections, fp, keep, q, 0, m, out,
                    &ambig, far, amb ? amb->r : NULL);
    if (amb && rc == ACTAG_ERR_NO_MATCH && ambig)
        amb->amb = 1;
    /* The code-agnostic fit can settle on a lattice where the tag does not
     * read while the quad's own grid does: read that grid too (one more
     * grid in the look-elsewhere allowance). */
    if (rc == ACTAG_ERR_NO_MATCH && !(flags & ACTAG_FIT_NO_SEARCH) && qmax >= 0) {
        int ambig2 = 0, first = amb && amb->amb;
        /* the first grid's ambiguity, if any, stays in r; the second's
         * goes to r (none before) or r2 */
        rc = fread_grid(&im, &g_quad, &g_quad, k, family, qmax, fp, keep, q, 1, m,
                        out, &ambig2, (ambig ? FIT_RECHECK : 0) | far,
                        amb ? (first ? amb->r2 : amb->r) : NULL);
        if (amb && rc == ACTAG_ERR_NO_MATCH && ambig2) {
            if (first)
                amb->amb2 = 1;
            else
                amb->amb = 1;
        }
    }
    return rc;
}

/* decode_fit_grids.h */
int actag__fit_rival_explains(const uint8_t *grey, int rows, int cols, int stride,
                              const actag_family *family, const actag_fit_params *fp, int id,
                              const actag_point corners[4], int id2,
                              const actag_point corners2[4], float *rss, float *rss2)
{
    return actag__fit_rival_explains_own(grey, rows, cols, stride, family, fp, id, corners, id2,
                                         corners2, rss, rss2, NULL);
}

int actag__fit_rival_explains_own(const uint8_t *grey, int rows, int cols, int stride,
                                  const actag_family *family, const actag_fit_params *fp, int id,
                                  const actag_point corners[4], int id2,
                                  const actag_point corners2[4], float *rss, float *rss2,
                                  float *own)
{
    uint8_t L[(ACTAG_DECODE_MAX_K + 1) * (ACTAG_DECODE_MAX_K + 1)];
    float mt[(ACTAG_DECODE_MAX_K + 1) * (ACTAG_DECODE_MAX_K + 1)], r[2];
    fgrid g[4];
    fimg im;
    int rc, k, h, s, erase;
    if (grey == NULL || family == NULL || fp == NULL || corners == NULL || corners2 == NULL ||
        rss == NULL || rss2 == NULL)
        return ACTAG_ERR_NULL;
    rc = decode_check_frame_family(grey, rows, cols, stride, family);
    if (rc != ACTAG_OK)
        return rc;
    if (actag_fit_params_validate(fp, NULL) != ACTAG_OK || id < 0 || id >= family->ncodes ||
        id2 < 0 || id2 >= family->ncodes)
        return ACTAG_ERR_PARAM;
    k = family->bits / 4;
    erase = (fp->flags & ACTAG_FIT_ERASE_CORNERS) != 0;
    /* g[2 h + s]: reading h's template at reading s's place, in reading h's
     * rotation and handedness (s's corners in the corner order nearest h's:
     * its grid then carries h's orientation) */
    for (h = 0; h < 2; h++)
        for (s = 0; s < 2; s++) {
            const actag_point *ch = h ? corners2 : corners, *cs = s ? corners2 : corners;
            actag_point q[4];
            int i, p, best = 0;
            float dbest = 0.0f;
            for (p = 0; p < 8; p++) { /* 4 rotations, then 4 reflections of the order */
                float d = 0.0f;
                for (i = 0; i < 4; i++) {
                    const actag_point *c = &cs[p < 4 ? (i + p) & 3 : (p - i) & 3];
                    d += (c->x - ch[i].x) * (c->x - ch[i].x) + (c->y - ch[i].y) * (c->y - ch[i].y);
                }
                if (p == 0 || d < dbest) {
                    dbest = d;
                    best = p;
                }
            }
            for (i = 0; i < 4; i++)
                q[i] = cs[best < 4 ? (i + best) & 3 : (best - i) & 3];
            if (fgrid_of_quad(q, family->bits, &g[2 * h + s]) != ACTAG_OK)
                return ACTAG_ERR_PARAM;
        }
    fimg_of(grey, rows, cols, stride, fp, 1.0f, &im);
    /* each reading's template, view 0 (the grid carries rotation and
     * handedness), polished over the full range from either place */
    for (h = 0; h < 2; h++) {
        layout_of(family, h ? id2 : id, 0, k, L);
        r[h] = 1e30f;
        for (s = 0; s < 2; s++) {
            float v;
            if (h == 0 && s == 0 && own != NULL && *own >= 0.0f) {
                v = *own; /* reading 1 at its own place: polished before */
            } else {
                fgrid t = g[2 * h + s];
                float sc;
                ffit(&im, &t, k, mt, L, erase, 0, NULL, NULL, &sc);
                v = -sc;
                if (h == 0 && s == 0 && own != NULL)
                    *own = v;
            }
            if (v < r[h])
                r[h] = v;
        }
    }
    *rss = r[0];
    *rss2 = r[1];
    return r[1] <= r[0];
}

float actag__fit_rss_llr(const actag_family *family, const actag_fit_params *fp, float rss,
                         float rss2, float contrast)
{
    int n = family->bits / 4 + 1;
    int nc = n * n - ((fp->flags & ACTAG_FIT_ERASE_CORNERS) ? 4 : 0);
    /* the template check's floor (the binary decoder's readings carry no
     * contrast: then the least variance the float division bears) */
    float floor2 = fnoise_floor2(contrast);
    if (!(floor2 >= 1e-6f))
        floor2 = 1e-6f;
    return 0.5f * (rss2 - rss) / fcell_noise2(rss, nc, floor2);
}
