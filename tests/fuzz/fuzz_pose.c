/*
 * fuzz_pose.c -- libFuzzer harness: the sonar pose (pose.h,
 * actag_pose_estimate) and the camera pose's covariance
 * (actag_pose_camera_covariance) on arbitrary corners and parameters.
 *
 * Corners come either as raw floats (any value: NaN, inf, huge, equal) or
 * as the exact corners of a square of the fuzzed size at a fuzzed pose, so
 * that both garbage and near-valid geometry are reached. Checks, for each
 * call that returns ACTAG_OK:
 *   - flags hold only the documented ACTAG_POSE_* bits;
 *   - the covariance is absent (ACTAG_POSE_NO_COVARIANCE, all 36 entries
 *     zero) or present (flag clear, every entry finite, exactly symmetric,
 *     non-negative diagonal): the review of 2026-12-07 found an inf
 *     covariance with the flag clear (a vertical aperture of 1e-8 rad);
 *   - the same inputs give the same bytes (no dependence on memory left
 *     from another call).
 * Any other result is one of the documented error codes, and then *out is
 * not read.
 */
#include "fuzz_util.h"

#include "actag/pose.h"

#include <math.h>
#include <string.h>

#define FP_FLAGS                                                                             \
    (ACTAG_POSE_DEGENERATE | ACTAG_POSE_ELEVATION | ACTAG_POSE_NOT_CONVERGED |             \
     ACTAG_POSE_MIRROR_CONFLICT | ACTAG_POSE_NO_COVARIANCE | ACTAG_POSE_PLANE)

static int fp_finite(float v) { return v == v && v <= 3.4e38f && v >= -3.4e38f; }

static void check_cov(const actag_pose *o, const char *what)
{
    int i, j, nonzero = 0;
    FZ_CHECK((o->flags & ~(unsigned)FP_FLAGS) == 0u, "%s: unknown flag bits %#x", what, o->flags);
    for (i = 0; i < 36; i++)
        nonzero += o->cov[i] != 0.0f;
    if (o->flags & ACTAG_POSE_NO_COVARIANCE) {
        FZ_CHECK(nonzero == 0, "%s: no covariance, but %d entries are not zero", what, nonzero);
        return;
    }
    for (i = 0; i < 6; i++) {
        FZ_CHECK(o->cov[i * 6 + i] >= 0.0f, "%s: cov[%d][%d] = %g < 0", what, i, i,
                 (double)o->cov[i * 6 + i]);
        for (j = 0; j < 6; j++) {
            FZ_CHECK(fp_finite(o->cov[i * 6 + j]), "%s: cov[%d][%d] = %g with the flag clear",
                     what, i, j, (double)o->cov[i * 6 + j]);
            FZ_CHECK(o->cov[i * 6 + j] == o->cov[j * 6 + i], "%s: cov not symmetric at %d, %d",
                     what, i, j);
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_reader r;
    actag_pose_params pp;
    actag_pose o1, o2;
    float range[4], az[4], ts, ap;
    int mirrored, mode, i, rc;

    fz_init(&r, data, size);
    mode = fz_u8(&r) % 3;
    ts = fz_float(&r, 0.13f, 1e-4f, 100.0f);
    ap = fz_float(&r, 0.2094f, 0.0f, 3.1415926f);
    actag_pose_params_default(&pp, NULL, ts, ap);
    pp.range_sd = fz_float(&r, pp.range_sd, 1e-6f, 1.0f);
    pp.azimuth_sd = fz_float(&r, pp.azimuth_sd, 1e-6f, 1.0f);
    pp.max_iterations = fz_int(&r, pp.max_iterations, 1, 100);
    if (fz_u8(&r) & 1u) {
        for (i = 0; i < 4; i++)
            pp.plane[i] = fz_float(&r, i == 2 ? 1.0f : 0.0f, -10.0f, 10.0f);
        pp.plane_sd = fz_float(&r, 0.01f, 0.0f, 1.0f);
        pp.plane_tilt_sd = fz_float(&r, 0.05f, 0.0f, 1.0f);
    }
    mirrored = fz_u8(&r) & 1;
    if (mode == 0) { /* raw corners */
        for (i = 0; i < 4; i++) {
            range[i] = fz_float(&r, 1.0f + 0.01f * (float)i, 0.0f, 100.0f);
            az[i] = fz_float(&r, 0.01f * (float)i, -1.6f, 1.6f);
        }
    } else { /* a square of side ts at distance d, azimuth a, elevation e, turned */
        float d = fz_float(&r, 2.0f, 0.01f, 100.0f), a = fz_float(&r, 0.0f, -1.0f, 1.0f);
        float e = fz_float(&r, 0.0f, -0.5f, 0.5f), yaw = fz_float(&r, 0.3f, -3.2f, 3.2f);
        float tilt = fz_float(&r, 0.7f, -1.6f, 1.6f), s = 0.5f * ts;
        float cy = cosf(yaw), sy = sinf(yaw), ct = cosf(tilt), st = sinf(tilt);
        float cx = d * cosf(e) * cosf(a), cyy = d * cosf(e) * sinf(a), cz = d * sinf(e);
        static const float u[4] = {-1, 1, 1, -1}, v[4] = {-1, -1, 1, 1};
        for (i = 0; i < 4; i++) {
            /* tag plane: x along (cos yaw, sin yaw, 0), y tilted out of the fan */
            float px = s * u[i], py = s * v[i];
            float X = cx + px * cy - py * ct * sy, Y = cyy + px * sy + py * ct * cy,
                  Z = cz + py * st;
            range[i] = sqrtf(X * X + Y * Y + Z * Z);
            az[i] = atan2f(Y, X) + (mode == 2 ? fz_float(&r, 0.0f, -0.01f, 0.01f) : 0.0f);
        }
    }
    memset(&o1, 0x5a, sizeof o1);
    memset(&o2, 0xa5, sizeof o2);
    rc = actag_pose_estimate(range, az, mirrored, &pp, &o1);
    FZ_CHECK(rc == ACTAG_OK || rc == ACTAG_ERR_PARAM || rc == ACTAG_ERR_BUILD,
             "actag_pose_estimate returned %d", rc);
    FZ_CHECK(actag_pose_estimate(range, az, mirrored, &pp, &o2) == rc, "a second call differs");
    if (rc == ACTAG_OK) {
        check_cov(&o1, "sonar pose");
        FZ_CHECK(memcmp(&o1, &o2, sizeof o1) == 0, "the same inputs gave other bytes");
    }

    /* the camera covariance of a pose near that square, from fuzzed intrinsics */
    {
        float Ro[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, to[3], corners[8];
        float f = fz_float(&r, 800.0f, 1.0f, 1e6f), psd = fz_float(&r, 0.3f, 1e-6f, 1e3f);
        actag_pose cp;
        int use = fz_u8(&r) & 1;
        to[0] = fz_float(&r, 0.0f, -5.0f, 5.0f);
        to[1] = fz_float(&r, 0.0f, -5.0f, 5.0f);
        to[2] = fz_float(&r, 1.5f, -5.0f, 50.0f);
        for (i = 0; i < 8; i++)
            corners[i] = fz_float(&r, 320.0f + 10.0f * (float)(i & 3), -1e5f, 1e5f);
        if (actag_pose_from_camera(Ro, to, &cp) == ACTAG_OK) {
            rc = actag_pose_camera_covariance(use ? corners : NULL, f, f, 320.0f, 240.0f, psd, ts,
                                              &cp);
            FZ_CHECK(rc == ACTAG_OK || rc == ACTAG_ERR_PARAM, "camera covariance returned %d",
                     rc);
            if (rc == ACTAG_OK)
                check_cov(&cp, "camera pose");
        }
    }
    return 0;
}
