/*
 * pose.c -- pyactag._core.sonar_pose: actag_pose_estimate (actag/pose.h) on
 * four corners; pyactag._core.camera_pose: actag_pose_from_camera and
 * actag_pose_camera_covariance on a camera's pose. The Python layer
 * (pyactag/pose.py) checks every argument and names the bad one; here only
 * what it cannot see (the floats the library gets) is checked again, so a
 * direct call of _core.sonar_pose or _core.camera_pose with bad values
 * still gets ActagError, never a crash.
 */
#include "pyactag.h"

#include "actag/pose.h"

/* n real numbers from a sequence of exactly n (name: for messages).
 * (PySequence_Fast's item access is not in the limited API.) */
static int n_floats(PyObject *seq, const char *name, int n_want, float *out)
{
    Py_ssize_t n = PySequence_Check(seq) ? PySequence_Size(seq) : -1;
    int i;
    if (n < 0) {
        /* an error of the object's own __len__ is its own; no sequence: TypeError */
        if (PyErr_Occurred() && !PyErr_ExceptionMatches(PyExc_TypeError))
            return -1;
        PyErr_Clear();
        PyErr_Format(PyExc_TypeError, "%s must be a sequence of %d numbers, got %R", name,
                     n_want, seq);
        return -1;
    }
    if (n != n_want) {
        PyErr_Format(PyExc_ValueError, "%s must hold %d numbers, got %zd", name, n_want, n);
        return -1;
    }
    for (i = 0; i < n_want; i++) {
        PyObject *item = PySequence_GetItem(seq, i);
        double d;
        int bad;
        if (item == NULL)
            return -1;
        bad = pyactag_is_bool(item);
        d = bad ? -1.0 : PyFloat_AsDouble(item);
        if (bad || (d == -1.0 && PyErr_Occurred())) {
            PyErr_Clear();
            PyErr_Format(PyExc_TypeError, "%s[%d] must be a real number, got %R", name, i, item);
            Py_DECREF(item);
            return -1;
        }
        Py_DECREF(item);
        out[i] = (float)d;
    }
    return 0;
}

/* *out = float(obj) unless obj is None (the default stays). Returns 0, or -1
 * with the conversion's exception. */
static int optional_float(PyObject *obj, float *out)
{
    double d;
    if (obj == Py_None)
        return 0;
    d = PyFloat_AsDouble(obj);
    if (d == -1.0 && PyErr_Occurred())
        return -1;
    *out = (float)d;
    return 0;
}

static PyObject *float_tuple(const float *v, int n)
{
    PyObject *t = PyTuple_New(n);
    int i;
    if (t == NULL)
        return NULL;
    for (i = 0; i < n; i++) {
        PyObject *f = PyFloat_FromDouble((double)v[i]);
        if (f == NULL) {
            Py_DECREF(t);
            return NULL;
        }
        PyTuple_SetItem(t, i, f);
    }
    return t;
}

/* The tuple both functions return (see sonar_pose), or NULL with an exception. */
static PyObject *pose_tuple(const actag_pose *P)
{
    PyObject *R = float_tuple(P->R, 9), *t = float_tuple(P->t, 3), *cov = float_tuple(P->cov, 36);
    if (R == NULL || t == NULL || cov == NULL) {
        Py_XDECREF(R);
        Py_XDECREF(t);
        Py_XDECREF(cov);
        return NULL;
    }
    return Py_BuildValue("(NNNdddddddiI)", R, t, cov, (double)P->range, (double)P->azimuth,
                         (double)P->elevation, (double)P->elevation_lo, (double)P->elevation_hi,
                         (double)P->residual, (double)P->chi2, P->iterations, P->flags);
}

/* sonar_pose(ranges, azimuths, mirrored, family, tag_size, vertical_aperture,
 *            extent, range_sd, azimuth_sd, max_iterations, plane, plane_sd,
 *            plane_tilt_sd)
 * family: a Family or None (extent 1 unless given); extent, range_sd,
 * azimuth_sd: None for pose.h's defaults; plane: None or 4 numbers.
 * -> (R (9), t (3), cov (36), range, azimuth, elevation, elevation_lo,
 *     elevation_hi, residual, chi2, iterations, flags) */
PyObject *pyactag_sonar_pose(PyObject *self, PyObject *args)
{
    PyObject *ranges_o, *azimuths_o, *family_o, *extent_o, *rsd_o, *asd_o, *plane_o;
    int mirrored, max_iterations, rc;
    double tag_size, vertical, plane_sd, plane_tilt_sd;
    float range[4], azimuth[4];
    const actag_family *fam = NULL;
    actag_pose_params pp;
    actag_pose P;
    (void)self;
    if (!PyArg_ParseTuple(args, "OOpOddOOOiOdd:sonar_pose", &ranges_o, &azimuths_o, &mirrored,
                          &family_o, &tag_size, &vertical, &extent_o, &rsd_o, &asd_o,
                          &max_iterations, &plane_o, &plane_sd, &plane_tilt_sd))
        return NULL;
    if (n_floats(ranges_o, "ranges", 4, range) != 0 ||
        n_floats(azimuths_o, "azimuths", 4, azimuth) != 0)
        return NULL;
    if (family_o != Py_None) {
        fam = pyactag_family_of(family_o);
        if (fam == NULL)
            return NULL;
    }
    actag_pose_params_default(&pp, fam, (float)tag_size, (float)vertical);
    if (optional_float(extent_o, &pp.extent) != 0 || optional_float(rsd_o, &pp.range_sd) != 0 ||
        optional_float(asd_o, &pp.azimuth_sd) != 0)
        return NULL;
    pp.max_iterations = max_iterations;
    if (plane_o != Py_None && n_floats(plane_o, "plane", 4, pp.plane) != 0)
        return NULL;
    pp.plane_sd = (float)plane_sd;
    pp.plane_tilt_sd = (float)plane_tilt_sd;
    rc = actag_pose_estimate(range, azimuth, mirrored, &pp, &P);
    if (rc != ACTAG_OK)
        return pyactag_raise(rc, "sonar_pose (pose.h: corner ranges 0.001 to 10000 m, azimuths "
                                 "within +-4 pi, tag_size 0.001 to 10000 m, vertical aperture "
                                 "in (0, pi), positive noise sds, max_iterations 1 to 100)");
    return pose_tuple(&P);
}

/* camera_pose(R_opt, t_opt, camera, corners)
 * R_opt: 9 numbers (row-major, tag -> optical frame); t_opt: 3 numbers (m);
 * camera: None (no covariance), or (fx, fy, cx, cy, pixel_sd, tag_size) as
 * actag_pose_camera_covariance takes them; corners: None or 8 numbers (x0,
 * y0, .. x3, y3; px, tag order), only with camera.
 * -> the tuple of sonar_pose */
PyObject *pyactag_camera_pose(PyObject *self, PyObject *args)
{
    PyObject *R_o, *t_o, *camera_o, *corners_o;
    float R_opt[9], t_opt[3], cam[6], corners[8];
    actag_pose P;
    int rc;
    (void)self;
    if (!PyArg_ParseTuple(args, "OOOO:camera_pose", &R_o, &t_o, &camera_o, &corners_o))
        return NULL;
    if (n_floats(R_o, "R_opt", 9, R_opt) != 0 || n_floats(t_o, "t_opt", 3, t_opt) != 0)
        return NULL;
    if (camera_o != Py_None && n_floats(camera_o, "camera", 6, cam) != 0)
        return NULL;
    if (corners_o != Py_None) {
        if (camera_o == Py_None) {
            PyErr_SetString(PyExc_ValueError,
                            "corners need camera (fx, fy, cx, cy, pixel_sd, tag_size)");
            return NULL;
        }
        if (n_floats(corners_o, "corners", 8, corners) != 0)
            return NULL;
    }
    rc = actag_pose_from_camera(R_opt, t_opt, &P);
    if (rc != ACTAG_OK)
        return pyactag_raise(rc, "camera_pose (pose.h: R_opt finite, t_opt within +-10000 m)");
    if (camera_o != Py_None) {
        rc = actag_pose_camera_covariance(corners_o != Py_None ? corners : NULL, cam[0], cam[1],
                                          cam[2], cam[3], cam[4], cam[5], &P);
        if (rc != ACTAG_OK)
            return pyactag_raise(rc, "camera_pose (pose.h: fx, fy 1 to 1e6 px, cx, cy within "
                                     "+-1e5 px, pixel_sd 1e-6 to 1e3 px, tag_size 0.001 to "
                                     "10000 m, corners within +-1e7 px)");
    }
    return pose_tuple(&P);
}
