/* The sonar pose's least-squares model (internal; pose.c): what one
 * detection's corners say about a tag pose, as residuals and their
 * Jacobian. Exposed so that tests/test_pose_model.c can check the
 * analytic Jacobian against finite differences of the residuals. */
#ifndef ACTAG_POSE_MODEL_H
#define ACTAG_POSE_MODEL_H

#include "actag/pose.h"

#define ACTAG__POSE_NPAR 6 /* parameters: dt (3, metres), then dw (3, rad; R <- exp([dw]x) R) */
#define ACTAG__POSE_NRES 12 /* 8 corner residuals, the elevation prior, the plane's offset and tilt */

typedef struct actag__pose_model {
    float r[4], az[4];   /* measured corners */
    float s, E, half_v;  /* tag size, outline extent (tag sizes), half aperture */
    float sr, sa;        /* noise sds */
    float mu, sp;        /* elevation prior: mean, sd (rad) */
    /* the plane prior (params.plane): unit normal n, offset d (n.p = d), the
     * normal's two unit tangents u, v, and the sds' inverses (0: unused) */
    float n[3], d, u[3], v[3], wd, wt;
} actag__pose_model;

typedef struct actag__pose_state {
    float R[9], t[3]; /* the tag's rotation (row-major) and centre, sonar frame */
} actag__pose_state;

/* The residuals f (ACTAG__POSE_NRES: corner k's range then azimuth at
 * 2k, 2k + 1, in sds; the centre's elevation against the prior at 8; the
 * plane's offset at 9 and the face normal's two tilts at 10, 11, zero when
 * unused) of state x under model m, and when J is not NULL their Jacobian
 * (row-major, ACTAG__POSE_NRES x ACTAG__POSE_NPAR) over the step of
 * actag__pose_step; returns the sum of squares. */
float actag__pose_eval(const actag__pose_model *m, const actag__pose_state *x, float *f, float *J);

/* x moved by d (ACTAG__POSE_NPAR: t + d[0..2], R turned by exp([d[3..5]]x)
 * on the left and orthonormalised) into o. */
void actag__pose_step(const actag__pose_state *x, const float *d, actag__pose_state *o);

#endif
