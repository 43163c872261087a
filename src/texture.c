/* The texture test (texture.h): a reading's contrast against the
 * cell-to-cell variation of the texture around its tag. */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "texture.h"

#include "actag/tag_grid.h"

#include <string.h>

/* The background reaches this many cells beyond the tag's data ring. */
#define TEX_OUT 4
/* Cells a side of the measured window at 32 bits (k = 8). */
#define TEX_MAXN (8 + 1 + 2 * TEX_OUT)
/* Side-by-side background pairs at 32 bits, the most: along each axis,
 * the 2 (TEX_OUT - 1) lines wholly in the background hold TEX_MAXN - 1
 * pairs each, the other lines 2 (TEX_OUT - 2) (280 floats on the stack). */
#define TEX_MAXPAIRS                                                                            \
    (2 * (2 * (TEX_OUT - 1) * (TEX_MAXN - 1) + (TEX_MAXN - 2 * (TEX_OUT - 1)) * 2 * (TEX_OUT - 2)))
/* The median of a chi-square variable with one degree of freedom: the
 * median of d^2 for a normal d of variance 1. */
#define TEX_CHI2_MEDIAN 0.4549364f

/* Bilinear sample of grey at (x, y); -1 when its 2 x 2 pixels leave the
 * frame (or x, y is NaN). */
static float tex_sample(const uint8_t *grey, int rows, int cols, float x, float y)
{
    int x0, y0;
    float fx, fy;
    const uint8_t *a;
    if (!(x >= 0.0f && y >= 0.0f && x < (float)(cols - 1) && y < (float)(rows - 1)))
        return -1.0f;
    x0 = (int)x;
    y0 = (int)y;
    fx = x - (float)x0;
    fy = y - (float)y0;
    a = grey + (size_t)y0 * (size_t)cols + (size_t)x0;
    return (1.0f - fy) * ((1.0f - fx) * (float)a[0] + fx * (float)a[1]) +
           fy * ((1.0f - fx) * (float)a[cols] + fx * (float)a[cols + 1]);
}

/* Mean of cell (cx, cy)'s 3 x 3 samples at 1/6, 1/2, 5/6 of the cell
 * through the affine map H; -1 when a sample leaves the frame. */
static float tex_cell(const float H[9], const uint8_t *grey, int rows, int cols, int cx, int cy)
{
    static const float at[3] = {1.0f / 6.0f, 0.5f, 5.0f / 6.0f};
    float s = 0.0f;
    int i, j;
    for (j = 0; j < 3; j++)
        for (i = 0; i < 3; i++) {
            float u = (float)cx + at[i], v = (float)cy + at[j];
            float p = tex_sample(grey, rows, cols, H[0] * u + H[1] * v + H[2],
                                 H[3] * u + H[4] * v + H[5]);
            if (p < 0.0f)
                return -1.0f;
            s += p;
        }
    return s * (1.0f / 9.0f);
}

/* The element of rank n / 2 of v[0..n-1] (n >= 1; v is reordered):
 * quickselect with a median-of-three pivot, the same on every platform. */
static float tex_median(float *v, int n)
{
    int lo = 0, hi = n - 1, want = n / 2;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2, i = lo, j = hi;
        float a = v[lo], b = v[mid], c = v[hi], pivot;
        pivot = a < b ? (b < c ? b : (a < c ? c : a)) : (a < c ? a : (b < c ? c : b));
        while (i <= j) {
            while (v[i] < pivot)
                i++;
            while (v[j] > pivot)
                j--;
            if (i <= j) {
                float t = v[i];
                v[i] = v[j];
                v[j] = t;
                i++;
                j--;
            }
        }
        if (want <= j)
            hi = j;
        else if (want >= i)
            lo = i;
        else
            break;
    }
    return v[want];
}

float actag__texture_contrast(const uint8_t *grey, int rows, int cols, const actag_point fit[4],
                              int bits)
{
    float H[9], prev[TEX_MAXN] = {0.0f}, cur[TEX_MAXN], d2[TEX_MAXPAIRS], sw = 0.0f, sb = 0.0f,
          med, contrast;
    int k = bits / 4, lo = -TEX_OUT, hi, n, nw = 0, nb = 0, npairs = 0, cx, cy;
    if (grey == NULL || fit == NULL || bits < 16 || bits > 32 || bits % 4 != 0 ||
        actag_tag_affine(fit, bits, H) != ACTAG_OK)
        return ACTAG__TEXTURE_UNJUDGED;
    hi = k + TEX_OUT;
    n = hi - lo + 1;
    for (cy = lo; cy <= hi; cy++) {
        for (cx = lo; cx <= hi; cx++) {
            int i = cx - lo;
            float m;
            if (cx >= -1 && cx <= k + 1 && cy >= -1 && cy <= k + 1) {
                /* the tag and its one-cell margin: not background */
                cur[i] = -1.0f;
                if (cx < 1 || cx > k - 1 || cy < 1 || cy > k - 1)
                    continue; /* the data ring and the margin */
                m = tex_cell(H, grey, rows, cols, cx, cy);
                if (m < 0.0f)
                    return ACTAG__TEXTURE_UNJUDGED;
                if (actag_tag_cell_value(0u, bits, cx, cy) == 0) { /* the black ring */
                    sb += m;
                    nb++;
                } else { /* the white interior */
                    sw += m;
                    nw++;
                }
                continue;
            }
            m = tex_cell(H, grey, rows, cols, cx, cy);
            cur[i] = m;
            if (m < 0.0f)
                continue;
            if (i > 0 && cur[i - 1] >= 0.0f && npairs < TEX_MAXPAIRS) {
                float d = m - cur[i - 1];
                d2[npairs++] = d * d;
            }
            if (cy > lo && prev[i] >= 0.0f && npairs < TEX_MAXPAIRS) {
                float d = m - prev[i];
                d2[npairs++] = d * d;
            }
        }
        memcpy(prev, cur, (size_t)n * sizeof cur[0]);
    }
    if (npairs < ACTAG__TEXTURE_MIN_PAIRS || nw == 0 || nb == 0)
        return ACTAG__TEXTURE_UNJUDGED;
    /* s^2 = median(d^2) / (2 x the chi-square median): the variance of a
     * cell mean for normal differences; the median ignores the few pairs
     * across an edge of the scene (the dark band before the seabed) */
    med = tex_median(d2, npairs);
    if (!(med > 0.0f))
        return ACTAG__TEXTURE_UNJUDGED;
    contrast = sw / (float)nw - sb / (float)nb;
    return contrast / actag_sqrtf(med / (2.0f * TEX_CHI2_MEDIAN));
}
