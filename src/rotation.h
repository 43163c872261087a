/* 3-vectors and rotations in float (internal; pose.c): row-major 3 x 3
 * matrices, R = exp([w]x) by Rodrigues and its inverse, an orthonormal
 * frame from two axes. Tested against double references by
 * tests/test_trig.c. Static (ACTAG__INTERNAL, trig.h), as in pose.c
 * before. */
#ifndef ACTAG_ROTATION_H
#define ACTAG_ROTATION_H

#include "trig.h"

ACTAG__INTERNAL float actag__dot3(const float *a, const float *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

ACTAG__INTERNAL void actag__cross3(const float *a, const float *b, float *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

ACTAG__INTERNAL float actag__norm3(const float *a) { return actag_sqrtf(actag__dot3(a, a)); }

ACTAG__INTERNAL void actag__mat_vec(const float *R, const float *v, float *o)
{
    o[0] = R[0] * v[0] + R[1] * v[1] + R[2] * v[2];
    o[1] = R[3] * v[0] + R[4] * v[1] + R[5] * v[2];
    o[2] = R[6] * v[0] + R[7] * v[1] + R[8] * v[2];
}

ACTAG__INTERNAL void actag__mat_mul(const float *A, const float *B, float *o)
{
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            o[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
}

/* Rotation with columns x, y (orthonormalised), z = x cross y. */
/* R with columns x = xa / |xa| (the first axis when xa is 0), y = ya
 * made perpendicular to x and normalised (any perpendicular when ya is
 * parallel to xa or 0), z = x cross y: a rotation for any finite input. */
ACTAG__INTERNAL void actag__rot_from_axes(const float *xa, const float *ya, float *R)
{
    float x[3], y[3], z[3], d, n;
    int i;
    n = actag__norm3(xa);
    for (i = 0; i < 3; i++)
        x[i] = n > 0.0f ? xa[i] / n : (i == 0);
    d = actag__dot3(ya, x);
    for (i = 0; i < 3; i++)
        y[i] = ya[i] - d * x[i];
    n = actag__norm3(y);
    if (n < 0.1f * actag__norm3(ya)) {
        /* ya within 6 degrees of xa: the difference above cancelled most
         * of ya, and its rounding leaves y off the perpendicular (ya = 3 xa
         * gave columns 19 degrees from orthogonal); once more */
        d = actag__dot3(y, x);
        for (i = 0; i < 3; i++)
            y[i] -= d * x[i];
        n = actag__norm3(y);
    }
    if (!(n > 1e-6f * actag__norm3(ya)) || !(n > 1e-30f)) { /* any perpendicular */
        float e[3] = {0.0f, 0.0f, 0.0f};
        e[(x[0] * x[0] < 0.5f) ? 0 : 1] = 1.0f;
        actag__cross3(x, e, z);
        actag__cross3(z, x, y);
        n = actag__norm3(y);
    }
    for (i = 0; i < 3; i++)
        y[i] /= n;
    actag__cross3(x, y, z);
    for (i = 0; i < 3; i++) {
        R[3 * i] = x[i];
        R[3 * i + 1] = y[i];
        R[3 * i + 2] = z[i];
    }
}

/* exp([w]x), Rodrigues */
ACTAG__INTERNAL void actag__rot_exp(const float *w, float *R)
{
    float th2 = actag__dot3(w, w), a, b, s, c;
    if (th2 < 1e-8f) {
        a = 1.0f - th2 / 6.0f;
        b = 0.5f - th2 / 24.0f;
    } else {
        float th = actag_sqrtf(th2);
        actag__sincos(th, &s, &c);
        a = s / th;
        b = (1.0f - c) / th2;
    }
    R[0] = 1.0f - b * (w[1] * w[1] + w[2] * w[2]);
    R[4] = 1.0f - b * (w[0] * w[0] + w[2] * w[2]);
    R[8] = 1.0f - b * (w[0] * w[0] + w[1] * w[1]);
    R[1] = -a * w[2] + b * w[0] * w[1];
    R[3] = a * w[2] + b * w[0] * w[1];
    R[2] = a * w[1] + b * w[0] * w[2];
    R[6] = -a * w[1] + b * w[0] * w[2];
    R[5] = -a * w[0] + b * w[1] * w[2];
    R[7] = a * w[0] + b * w[1] * w[2];
}

/* w with R = exp([w]x) */
ACTAG__INTERNAL void actag__rot_log(const float *R, float *w)
{
    float v[3], sn, cs, th, tr = R[0] + R[4] + R[8];
    v[0] = 0.5f * (R[7] - R[5]);
    v[1] = 0.5f * (R[2] - R[6]);
    v[2] = 0.5f * (R[3] - R[1]);
    sn = actag__norm3(v);
    cs = 0.5f * (tr - 1.0f);
    th = actag__atan2(sn, cs);
    if (cs > -0.9f) {
        float k = sn > 1e-7f ? th / sn : 1.0f + sn * sn / 6.0f;
        w[0] = k * v[0];
        w[1] = k * v[1];
        w[2] = k * v[2];
    } else {
        /* near pi: the axis from the symmetric part, (R + R^T)/2 = I + (1-cos) (u u^T - I) */
        float om = 1.0f - cs, u[3], n;
        int i = (R[0] >= R[4] && R[0] >= R[8]) ? 0 : (R[4] >= R[8] ? 1 : 2), j;
        float d = (R[4 * i] - cs) / om;
        u[i] = actag_sqrtf(d > 0.0f ? d : 0.0f);
        for (j = 0; j < 3; j++)
            if (j != i)
                u[j] = 0.5f * (R[3 * i + j] + R[3 * j + i]) / (om * (u[i] > 1e-6f ? u[i] : 1e-6f));
        n = actag__norm3(u);
        if (n > 0.0f)
            for (j = 0; j < 3; j++)
                u[j] /= n;
        if (actag__dot3(u, v) < 0.0f)
            for (j = 0; j < 3; j++)
                u[j] = -u[j];
        for (j = 0; j < 3; j++)
            w[j] = th * u[j];
    }
}

#endif
