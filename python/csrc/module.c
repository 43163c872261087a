/*
 * module.c -- pyactag._core: module init, ActagError, small functions.
 */
#include "pyactag.h"

#include "actag/pose.h"
#include "actag/track.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

PyObject *pyactag_error = NULL;
PyObject *pyactag_family_type = NULL;

const char *pyactag_code_name(int code)
{
    switch (code) {
    case ACTAG_OK: return "ACTAG_OK";
    case ACTAG_ERR_NULL: return "ACTAG_ERR_NULL";
    case ACTAG_ERR_SIZE: return "ACTAG_ERR_SIZE";
    case ACTAG_ERR_PARAM: return "ACTAG_ERR_PARAM";
    case ACTAG_ERR_GEOMETRY: return "ACTAG_ERR_GEOMETRY";
    case ACTAG_ERR_WORKSPACE: return "ACTAG_ERR_WORKSPACE";
    case ACTAG_ERR_FAMILY: return "ACTAG_ERR_FAMILY";
    case ACTAG_ERR_CORRECTIONS: return "ACTAG_ERR_CORRECTIONS";
    case ACTAG_ERR_NO_MATCH: return "ACTAG_ERR_NO_MATCH";
    case ACTAG_ERR_OVERFLOW: return "ACTAG_ERR_OVERFLOW";
    case ACTAG_ERR_NO_QUAD: return "ACTAG_ERR_NO_QUAD";
    case ACTAG_ERR_BUILD: return "ACTAG_ERR_BUILD";
    default: return "ACTAG_ERR_UNKNOWN";
    }
}

PyObject *pyactag_raise_message(int code, PyObject *msg)
{
    PyObject *exc = PyObject_CallFunctionObjArgs(pyactag_error, msg, NULL);
    PyObject *c, *n;
    if (exc == NULL)
        return NULL;
    c = PyLong_FromLong(code);
    n = PyUnicode_FromString(pyactag_code_name(code));
    if (c == NULL || n == NULL || PyObject_SetAttrString(exc, "code", c) != 0 ||
        PyObject_SetAttrString(exc, "name", n) != 0) {
        Py_XDECREF(c);
        Py_XDECREF(n);
        Py_DECREF(exc);
        return NULL;
    }
    Py_DECREF(c);
    Py_DECREF(n);
    PyErr_SetObject(pyactag_error, exc);
    Py_DECREF(exc);
    return NULL;
}

PyObject *pyactag_raise_detail(const char *context, const actag_error_detail *d)
{
    char field[96], text[512];
    const char *f = d->field ? d->field : "?";
    size_t i, o = 0;
    PyObject *msg, *type, *value, *tb, *fo;
    /* library names -> Python keywords: tuning.quad.inlier_ratio ->
     * quad_inlier_ratio, geometry.min_range -> min_range,
     * tuning.limits.max_decodes -> max_decodes */
    if (strncmp(f, "tuning.", 7) == 0)
        f += 7;
    else if (strncmp(f, "geometry.", 9) == 0)
        f += 9;
    if (strncmp(f, "limits.", 7) == 0) /* tuning.limits.max_contours -> max_contours */
        f += 7;
    for (i = 0; f[i] && o + 1 < sizeof field; i++)
        field[o++] = f[i] == '.' ? '_' : f[i];
    field[o] = '\0';
    if (d->index >= 0 && o + 16 < sizeof field)
        snprintf(field + o, sizeof field - o, "[%d]", d->index);
    if (d->other)
        snprintf(text, sizeof text, "%s: %s %s (got %g, limit %g): %s (%s)", context, field,
                 d->rule ? d->rule : "is invalid", d->value, d->limit,
                 actag_strerror(d->code), pyactag_code_name(d->code));
    else
        snprintf(text, sizeof text, "%s: %s %s (got %g): %s (%s)", context, field,
                 d->rule ? d->rule : "is invalid", d->value, actag_strerror(d->code),
                 pyactag_code_name(d->code));
    msg = PyUnicode_FromString(text);
    if (msg == NULL)
        return NULL;
    pyactag_raise_message(d->code, msg);
    Py_DECREF(msg);
    /* attach the field to the exception just raised */
    PyErr_Fetch(&type, &value, &tb);
    fo = PyUnicode_FromString(field);
    if (value != NULL && fo != NULL)
        PyObject_SetAttrString(value, "field", fo);
    Py_XDECREF(fo);
    PyErr_Restore(type, value, tb);
    return NULL;
}

PyObject *pyactag_raise(int code, const char *context)
{
    PyObject *msg = PyUnicode_FromFormat("%s: %s (%s)", context, actag_strerror(code),
                                         pyactag_code_name(code));
    if (msg == NULL)
        return NULL;
    pyactag_raise_message(code, msg);
    Py_DECREF(msg);
    return NULL;
}

char *pyactag_strdup(PyObject *str)
{
    PyObject *b = PyUnicode_AsUTF8String(str); /* PyUnicode_AsUTF8AndSize is not in 3.9's limited API */
    char *out;
    const char *s;
    size_t n;
    if (b == NULL)
        return NULL;
    s = PyBytes_AsString(b);
    n = strlen(s);
    if ((Py_ssize_t)n != PyBytes_Size(b)) { /* C would stop at the NUL */
        PyErr_Format(PyExc_ValueError, "%R contains a NUL character", str);
        Py_DECREF(b);
        return NULL;
    }
    out = (char *)malloc(n + 1);
    if (out == NULL) {
        Py_DECREF(b);
        PyErr_NoMemory();
        return NULL;
    }
    memcpy(out, s, n + 1);
    Py_DECREF(b);
    return out;
}

static PyObject *m_family_names(PyObject *self, PyObject *noargs)
{
    int i, n = actag_family_count();
    PyObject *t = PyTuple_New(n);
    (void)self;
    (void)noargs;
    if (t == NULL)
        return NULL;
    for (i = 0; i < n; i++) {
        actag_family f;
        PyObject *s;
        if (actag_family_get_at(i, &f) != ACTAG_OK || (s = PyUnicode_FromString(f.name)) == NULL) {
            Py_DECREF(t);
            return PyErr_Occurred() ? NULL : pyactag_raise(ACTAG_ERR_FAMILY, "family_names");
        }
        PyTuple_SetItem(t, i, s);
    }
    return t;
}

static PyObject *m_default_params(PyObject *self, PyObject *noargs)
{
    actag_params p;
    (void)self;
    (void)noargs;
    actag_params_default(&p);
    return pyactag_params_to_dict(&p);
}

static PyObject *m_tuning_names(PyObject *self, PyObject *noargs)
{
    (void)self;
    (void)noargs;
    return pyactag_tuning_names();
}

/* A size of workspace_size(): any integer (TypeError otherwise); one beyond
 * a C int is a bad size like 0, not an OverflowError. Returns 0 or -1. */
static int size_arg(PyObject *o, int *out)
{
    PyObject *ix = PyNumber_Index(o);
    long v;
    int overflow = 0;
    if (ix == NULL)
        return -1;
    v = PyLong_AsLongAndOverflow(ix, &overflow);
    Py_DECREF(ix);
    if (v == -1 && PyErr_Occurred())
        return -1;
    *out = overflow || v < INT_MIN || v > INT_MAX ? 0 : (int)v;
    return 0;
}

static PyObject *m_workspace_size(PyObject *self, PyObject *args)
{
    PyObject *rows_o, *cols_o;
    int rows, cols;
    (void)self;
    if (!PyArg_ParseTuple(args, "OO:workspace_size", &rows_o, &cols_o))
        return NULL;
    if (size_arg(rows_o, &rows) != 0 || size_arg(cols_o, &cols) != 0)
        return NULL;
    return PyLong_FromSize_t(actag_workspace_size(rows, cols));
}

static PyObject *m_strerror(PyObject *self, PyObject *args)
{
    int code;
    (void)self;
    if (!PyArg_ParseTuple(args, "i:strerror", &code))
        return NULL;
    return PyUnicode_FromString(actag_strerror(code));
}

int pyactag_float_overflows(double d)
{
    return isfinite(d) && (d > FLT_MAX || d < -FLT_MAX || (d != 0.0 && (float)d == 0.0f));
}

int pyactag_is_bool(PyObject *obj)
{
    PyObject *tp = (PyObject *)Py_TYPE(obj), *mod, *name;
    int r = 0;
    if (PyBool_Check(obj))
        return 1;
    /* numpy.bool_ (numpy.bool in numpy 2) by its name: numpy is optional */
    mod = PyObject_GetAttrString(tp, "__module__");
    name = mod != NULL ? PyObject_GetAttrString(tp, "__name__") : NULL;
    if (name != NULL && PyUnicode_Check(mod) && PyUnicode_Check(name))
        r = PyUnicode_CompareWithASCIIString(mod, "numpy") == 0 &&
            (PyUnicode_CompareWithASCIIString(name, "bool_") == 0 ||
             PyUnicode_CompareWithASCIIString(name, "bool") == 0);
    Py_XDECREF(mod);
    Py_XDECREF(name);
    PyErr_Clear(); /* a type without __module__ or __name__ is no bool */
    return r;
}

int pyactag_code_arg(PyObject *obj, const char *name, int bits, uint32_t *out)
{
    PyObject *idx;
    unsigned long long c;
    if (PyBool_Check(obj) || PyFloat_Check(obj)) {
        PyErr_Format(PyExc_TypeError, "%s must be an integer, got %R", name, obj);
        return -1;
    }
    idx = PyNumber_Index(obj);
    if (idx == NULL) {
        PyErr_Clear();
        PyErr_Format(PyExc_TypeError, "%s must be an integer, got %R", name, obj);
        return -1;
    }
    c = PyLong_AsUnsignedLongLong(idx); /* negative or >= 2**64: OverflowError */
    if (PyErr_Occurred() || c > actag_code_mask(bits)) {
        char mask[16]; /* PyErr_Format has no %lx */
        snprintf(mask, sizeof mask, "0x%lx", (unsigned long)actag_code_mask(bits));
        PyErr_Clear();
        PyErr_Format(PyExc_ValueError, "%s must fit in %d bits (0..%s), got %R", name, bits, mask,
                     idx);
        Py_DECREF(idx);
        return -1;
    }
    Py_DECREF(idx);
    *out = (uint32_t)c;
    return 0;
}

static int code_args(PyObject *args, const char *fmt, uint32_t *code, int *bits)
{
    PyObject *code_o;
    if (!PyArg_ParseTuple(args, fmt, &code_o, bits))
        return -1;
    if (*bits < 1 || *bits > 32) {
        PyErr_Format(PyExc_ValueError, "bits must be 1..32, got %d", *bits);
        return -1;
    }
    return pyactag_code_arg(code_o, "code", *bits, code);
}

static PyObject *m_code_rot90(PyObject *self, PyObject *args)
{
    uint32_t c;
    int bits;
    (void)self;
    if (code_args(args, "Oi:code_rot90", &c, &bits) != 0)
        return NULL;
    if (bits % 4 != 0) {
        PyErr_SetString(PyExc_ValueError, "bits must be a multiple of 4");
        return NULL;
    }
    return PyLong_FromUnsignedLong(actag_code_rot90(c, bits));
}

static PyObject *m_code_reverse(PyObject *self, PyObject *args)
{
    uint32_t c;
    int bits;
    (void)self;
    if (code_args(args, "Oi:code_reverse", &c, &bits) != 0)
        return NULL;
    return PyLong_FromUnsignedLong(actag_code_reverse(c, bits));
}

static PyObject *m_code_mirror(PyObject *self, PyObject *args)
{
    uint32_t c;
    int bits;
    (void)self;
    if (code_args(args, "Oi:code_mirror", &c, &bits) != 0)
        return NULL;
    return PyLong_FromUnsignedLong(actag_code_mirror(c, bits));
}

static PyObject *m_code_corners(PyObject *self, PyObject *args)
{
    int bits;
    (void)self;
    if (!PyArg_ParseTuple(args, "i:code_corners", &bits))
        return NULL;
    if (bits < 16 || bits > 32 || bits % 4 != 0) {
        PyErr_SetString(PyExc_ValueError, "bits must be a multiple of 4 from 16 to 32");
        return NULL;
    }
    return PyLong_FromUnsignedLong(actag_code_corners(bits));
}

static PyMethodDef module_methods[] = {
    {"family_names", m_family_names, METH_NOARGS, "names of the built-in families"},
    {"default_params", m_default_params, METH_NOARGS,
     "every detection parameter with its C default (actag_params_default)"},
    {"tuning_names", m_tuning_names, METH_NOARGS, "names of the tuning parameters"},
    {"workspace_size", m_workspace_size, METH_VARARGS,
     "workspace_size(rows, cols) -> bytes (actag_workspace_size; 0 for bad sizes: any\n"
     "integer outside 1..MAX_DIM)"},
    {"strerror", m_strerror, METH_VARARGS, "strerror(code) -> the library's message"},
    {"code_rot90", m_code_rot90, METH_VARARGS,
     "code_rot90(code, bits): the code of the tag turned 90 degrees counter-clockwise"},
    {"code_reverse", m_code_reverse, METH_VARARGS, "code_reverse(code, bits): bit order reversed"},
    {"code_mirror", m_code_mirror, METH_VARARGS,
     "code_mirror(code, bits): the physical reflection P (position s -> -s mod bits)"},
    {"code_corners", m_code_corners, METH_VARARGS,
     "code_corners(bits): mask of the 4 corner cells of the data ring"},
    {"sonar_pose", pyactag_sonar_pose, METH_VARARGS,
     "sonar_pose(ranges, azimuths, mirrored, family, tag_size, vertical_aperture, extent,\n"
     "           range_sd, azimuth_sd, max_iterations, plane, plane_sd, plane_tilt_sd)\n"
     "-> (R, t, cov, range, azimuth, elevation, elevation_lo, elevation_hi, residual,\n"
     "    chi2, iterations, flags): actag_pose_estimate (use pyactag.sonar_pose)"},
    {"camera_pose", pyactag_camera_pose, METH_VARARGS,
     "camera_pose(R_opt, t_opt, camera, corners)\n"
     "R_opt: 9 numbers (row-major, tag -> optical frame), t_opt: 3 (m), camera: None or\n"
     "(fx, fy, cx, cy, pixel_sd, tag_size), corners: None or 8 (x0, y0, .. x3, y3, px)\n"
     "-> the tuple of sonar_pose: actag_pose_from_camera, then\n"
     "actag_pose_camera_covariance with camera (use pyactag.camera_pose)"},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module_def = {PyModuleDef_HEAD_INIT, "_core",
                                        "libactag bindings (use the pyactag package).", -1,
                                        module_methods, NULL, NULL, NULL, NULL};

static int add(PyObject *m, const char *name, PyObject *o)
{
    if (o == NULL)
        return -1;
    if (PyModule_AddObject(m, name, o) != 0) { /* steals o on success only */
        Py_DECREF(o);
        return -1;
    }
    return 0;
}

PyMODINIT_FUNC PyInit__core(void);
PyMODINIT_FUNC PyInit__core(void)
{
    PyObject *m = PyModule_Create(&module_def), *det_type;
    if (m == NULL)
        return NULL;
    if (pyactag_error == NULL) {
        pyactag_error = PyErr_NewExceptionWithDoc(
            "pyactag.ActagError",
            "An error code of libactag; str() is the library's message, .code the "
            "ACTAG_ERR_* number and .name its name.",
            PyExc_ValueError, NULL);
        if (pyactag_error == NULL)
            goto fail;
    }
    Py_INCREF(pyactag_error);
    if (add(m, "ActagError", pyactag_error) != 0)
        goto fail;
    if (pyactag_family_type == NULL) {
        pyactag_family_type = pyactag_family_type_create(m);
        if (pyactag_family_type == NULL)
            goto fail;
    }
    Py_INCREF(pyactag_family_type);
    if (add(m, "Family", pyactag_family_type) != 0)
        goto fail;
    det_type = pyactag_detector_type_create(m);
    if (add(m, "Detector", det_type) != 0)
        goto fail;
    if (add(m, "Tracker", pyactag_tracker_type_create(m)) != 0)
        goto fail;
    if (PyModule_AddStringConstant(m, "LIBRARY_VERSION", ACTAG_VERSION_STRING) != 0 ||
        PyModule_AddIntConstant(m, "MAX_DIM", ACTAG_MAX_DIM) != 0 ||
        PyModule_AddIntConstant(m, "MAX_DETECTIONS", PYACTAG_MAX_DETECTIONS) != 0 ||
        PyModule_AddIntConstant(m, "SEARCH_MAX", ACTAG_SEARCH_MAX) != 0 ||
        PyModule_AddIntConstant(m, "MAX_THRESHOLD_RADIUS", ACTAG_MAX_THRESHOLD_RADIUS) != 0 ||
        PyModule_AddIntConstant(m, "MIRROR_REVERSE", ACTAG_MIRROR_REVERSE) != 0 ||
        PyModule_AddIntConstant(m, "MIRROR_PHYSICAL", ACTAG_MIRROR_PHYSICAL) != 0 ||
        PyModule_AddIntConstant(m, "CORNER_TOP_LEFT", ACTAG_CORNER_TOP_LEFT) != 0 ||
        PyModule_AddIntConstant(m, "CORNER_TOP_RIGHT", ACTAG_CORNER_TOP_RIGHT) != 0 ||
        PyModule_AddIntConstant(m, "CORNER_BOTTOM_RIGHT", ACTAG_CORNER_BOTTOM_RIGHT) != 0 ||
        PyModule_AddIntConstant(m, "CORNER_BOTTOM_LEFT", ACTAG_CORNER_BOTTOM_LEFT) != 0 ||
        PyModule_AddIntConstant(m, "FIT_NO_SEARCH", ACTAG_FIT_NO_SEARCH) != 0 ||
        PyModule_AddIntConstant(m, "FIT_LOCAL", ACTAG_FIT_LOCAL) != 0 ||
        PyModule_AddIntConstant(m, "FIT_SPLIT", ACTAG_FIT_SPLIT) != 0 ||
        PyModule_AddIntConstant(m, "FIT_WIDE", ACTAG_FIT_WIDE) != 0 ||
        PyModule_AddIntConstant(m, "FIT_ERASE_CORNERS", ACTAG_FIT_ERASE_CORNERS) != 0 ||
        PyModule_AddIntConstant(m, "FIT_VERIFY", ACTAG_FIT_VERIFY) != 0 ||
        PyModule_AddIntConstant(m, "FIT_LEVEL_NOISE", ACTAG_FIT_LEVEL_NOISE) != 0 ||
        PyModule_AddIntConstant(m, "FIT_SEPARATE_NOISE", ACTAG_FIT_SEPARATE_NOISE) != 0 ||
        PyModule_AddIntConstant(m, "TRACK_MAX", ACTAG_TRACK_MAX) != 0 ||
        /* the pose's default corner noise (pose.h), as the library has it */
        add(m, "POSE_RANGE_SD", PyFloat_FromDouble((double)ACTAG_POSE_RANGE_SD)) != 0 ||
        add(m, "POSE_AZIMUTH_SD", PyFloat_FromDouble((double)ACTAG_POSE_AZIMUTH_SD)) != 0 ||
        /* the camera covariance's pixel_sd bounds (pose.h), as the library has them */
        add(m, "POSE_PIXEL_SD_MIN", PyFloat_FromDouble((double)ACTAG_POSE_PIXEL_SD_MIN)) != 0 ||
        add(m, "POSE_PIXEL_SD_MAX", PyFloat_FromDouble((double)ACTAG_POSE_PIXEL_SD_MAX)) != 0)
        goto fail;
    return m;
fail:
    Py_DECREF(m);
    return NULL;
}
