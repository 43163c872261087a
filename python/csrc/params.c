/*
 * params.c -- actag_params <-> Python keyword arguments.
 *
 * The one place that knows the parameter names: a table of (name, C type,
 * offset into actag_params). Python names are the C field names: the user
 * settings of actag_params (tag_size, max_bit_corrections, seed, min_margin, handedness)
 * and the fields of actag_params.tuning, nested structs flattened with their
 * prefix (tuning.quad.inlier_ratio -> quad_inlier_ratio, tuning.fit.level ->
 * fit_level). When actag_params changes layout, only the table changes.
 */
#include "pyactag.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <stddef.h>
#include <string.h>

enum field_kind { K_INT, K_FLOAT, K_U32, K_CORRECTIONS, K_DECODE };

typedef struct field {
    const char *name;
    enum field_kind kind;
    size_t offset;
    int tuning; /* 1: belongs to the tuning group */
} field;

#define F(name, kind, member, tuning) {name, kind, offsetof(actag_params, member), tuning}

/* User settings, then the stage tuning (actag_params.tuning). min_margin is
 * actag_params.min_margin, the margin actag_detect() reads; it wins over
 * tuning.fit.min_margin, which is therefore not offered. */
static const field fields[] = {
    F("tag_size", K_FLOAT, tag_size, 0),
    F("max_bit_corrections", K_CORRECTIONS, max_bit_corrections, 0),
    F("seed", K_U32, seed, 0),
    F("min_margin", K_FLOAT, min_margin, 0),
    F("handedness", K_INT, handedness, 0),
    F("median_radius", K_INT, tuning.median_radius, 1),
    F("median_per_range", K_INT, tuning.median_per_range, 1),
    F("threshold_radius", K_INT, tuning.threshold_radius, 1),
    F("threshold_offset", K_INT, tuning.threshold_offset, 1),
    F("size_tolerance", K_FLOAT, tuning.size_tolerance, 1),
    F("min_area_fraction", K_FLOAT, tuning.min_area_fraction, 1),
    F("max_area_fraction", K_FLOAT, tuning.max_area_fraction, 1),
    F("quad_max_iterations", K_INT, tuning.quad.max_iterations, 1),
    F("quad_sample_fraction", K_FLOAT, tuning.quad.sample_fraction, 1),
    F("quad_inlier_ratio", K_FLOAT, tuning.quad.inlier_ratio, 1),
    F("quad_inlier_distance", K_FLOAT, tuning.quad.inlier_distance, 1),
    F("quad_min_parallel_cos", K_FLOAT, tuning.quad.min_parallel_cos, 1),
    F("quad_min_inlier_ratio", K_FLOAT, tuning.quad.min_inlier_ratio, 1),
    F("decode_mode", K_DECODE, tuning.decode_mode, 1),
    F("fit_flags", K_INT, tuning.fit.flags, 1),
    F("fit_level", K_FLOAT, tuning.fit.level, 1),
    F("fit_min_contrast", K_INT, tuning.fit.min_contrast, 1),
    F("fit_sample_offset", K_FLOAT, tuning.fit.sample_offset, 1),
    F("fit_min_bit_margin", K_INT, tuning.fit.min_bit_margin, 1),
    F("fit_min_bit_odds", K_INT, tuning.fit.min_bit_odds, 1),
    F("fit_many_corrections", K_INT, tuning.fit.many_corrections, 1),
    F("fit_many_corrections_margin", K_FLOAT, tuning.fit.many_corrections_margin, 1),
    F("min_structure", K_FLOAT, tuning.min_structure, 1),
    F("min_texture_contrast", K_FLOAT, tuning.min_texture_contrast, 1),
    F("min_side_fraction", K_FLOAT, tuning.min_side_fraction, 1),
    F("max_side_fraction", K_FLOAT, tuning.max_side_fraction, 1),
    F("search_candidates", K_INT, tuning.search_candidates, 1),
    F("search_min_score", K_INT, tuning.search_min_score, 1),
    F("search_max_corrections", K_INT, tuning.search_max_corrections, 1),
    F("search_min_margin", K_FLOAT, tuning.search_min_margin, 1),
    F("search_range_scale", K_FLOAT, tuning.search_range_scale, 1),
    F("refine_corners", K_INT, tuning.refine_corners, 1),
    F("max_contours", K_INT, tuning.limits.max_contours, 1),
    F("max_contour_points", K_INT, tuning.limits.max_contour_points, 1),
    F("max_contour_iterations", K_INT, tuning.limits.max_contour_iterations, 1),
    F("max_frame_iterations", K_INT, tuning.limits.max_frame_iterations, 1),
    F("max_decodes", K_INT, tuning.limits.max_decodes, 1),
};

#define NFIELDS ((int)(sizeof fields / sizeof fields[0]))

static const field *find_field(const char *name)
{
    int i;
    for (i = 0; i < NFIELDS; i++)
        if (strcmp(fields[i].name, name) == 0)
            return &fields[i];
    return NULL;
}

/* A Python integer (or an object with __index__, e.g. a numpy integer) in
 * lo..hi; floats and bools (numpy's too) are refused so that typos do not
 * truncate. */
static int get_long(PyObject *v, const char *name, long long lo, long long hi, long long *out)
{
    PyObject *idx;
    long long x;
    int overflow = 0;
    if (pyactag_is_bool(v) || PyFloat_Check(v)) {
        PyErr_Format(PyExc_TypeError, "parameter '%s' must be an integer, not %s (got %R)", name,
                     PyFloat_Check(v) ? "float" : "bool", v);
        return -1;
    }
    idx = PyNumber_Index(v);
    if (idx == NULL) {
        PyErr_Clear();
        PyErr_Format(PyExc_TypeError, "parameter '%s' must be an integer, got %R", name, v);
        return -1;
    }
    x = PyLong_AsLongLongAndOverflow(idx, &overflow);
    if (x == -1 && PyErr_Occurred()) {
        Py_DECREF(idx);
        return -1;
    }
    if (overflow || x < lo || x > hi) {
        PyErr_Format(PyExc_OverflowError,
                     "parameter '%s' must be an integer from %lld to %lld, got %R", name, lo, hi,
                     idx);
        Py_DECREF(idx);
        return -1;
    }
    Py_DECREF(idx);
    *out = x;
    return 0;
}

/* A real number as a C float. NaN and +-inf pass on to the library's check,
 * which names the field and its rule; a finite value the float cannot hold
 * (beyond FLT_MAX, or nonzero but below the least subnormal, which would
 * become 0) is an OverflowError naming the value. Bools (numpy's too) are
 * refused. */
static int get_float(PyObject *v, const char *name, float *out)
{
    double d;
    if (pyactag_is_bool(v)) {
        PyErr_Format(PyExc_TypeError, "parameter '%s' must be a number, not bool (got %R)", name,
                     v);
        return -1;
    }
    d = PyFloat_AsDouble(v);
    if (d == -1.0 && PyErr_Occurred()) {
        if (PyErr_ExceptionMatches(PyExc_OverflowError)) { /* an int beyond the double range */
            PyErr_Clear();
            PyErr_Format(PyExc_OverflowError, "parameter '%s' is outside the range of a C float, "
                         "got %R", name, v);
            return -1;
        }
        PyErr_Clear();
        PyErr_Format(PyExc_TypeError, "parameter '%s' must be a number, got %R", name, v);
        return -1;
    }
    if (pyactag_float_overflows(d)) {
        char range[96];
        /* the least positive float, 2**-149 for IEEE single precision */
        snprintf(range, sizeof range, "nonzero magnitudes from %.2g to %.6g",
                 ldexp(1.0, FLT_MIN_EXP - FLT_MANT_DIG), (double)FLT_MAX);
        PyErr_Format(PyExc_OverflowError,
                     "parameter '%s' is outside the range of a C float (%s), got %R", name, range,
                     v);
        return -1;
    }
    *out = (float)d;
    return 0;
}

static int set_field(const field *f, PyObject *v, actag_params *p)
{
    char *base = (char *)p + f->offset;
    long long x;
    switch (f->kind) {
    case K_INT:
        if (get_long(v, f->name, INT_MIN, INT_MAX, &x) != 0)
            return -1;
        *(int *)(void *)base = (int)x;
        return 0;
    case K_U32:
        if (get_long(v, f->name, 0, 0xffffffffLL, &x) != 0)
            return -1;
        *(uint32_t *)(void *)base = (uint32_t)x;
        return 0;
    case K_CORRECTIONS: /* None: the automatic choice */
        if (v == Py_None) {
            *(int *)(void *)base = ACTAG_CORRECTIONS_AUTO;
            return 0;
        }
        if (get_long(v, f->name, ACTAG_CORRECTIONS_AUTO, INT_MAX, &x) != 0)
            return -1;
        *(int *)(void *)base = (int)x;
        return 0;
    case K_DECODE: {
        if (PyUnicode_Check(v)) {
            if (PyUnicode_CompareWithASCIIString(v, "fit") == 0) {
                *(int *)(void *)base = ACTAG_DECODE_FIT;
                return 0;
            }
            if (PyUnicode_CompareWithASCIIString(v, "binary") == 0) {
                *(int *)(void *)base = ACTAG_DECODE_BINARY;
                return 0;
            }
        }
        PyErr_Format(PyExc_ValueError, "parameter 'decode_mode' must be 'fit' or 'binary'");
        return -1;
    }
    case K_FLOAT:
    default:
        return get_float(v, f->name, (float *)(void *)base);
    }
}

int pyactag_params_from_dict(PyObject *kwargs, actag_params *p)
{
    PyObject *key, *value;
    Py_ssize_t pos = 0;
    actag_params tmp;
    if (kwargs == NULL || kwargs == Py_None)
        return 0;
    if (!PyDict_Check(kwargs)) {
        PyErr_SetString(PyExc_TypeError, "parameters must be a dict");
        return -1;
    }
    tmp = *p; /* all or nothing */
    while (PyDict_Next(kwargs, &pos, &key, &value)) {
        const field *f;
        char *name;
        int rc;
        if (!PyUnicode_Check(key)) {
            PyErr_SetString(PyExc_TypeError, "parameter names must be strings");
            return -1;
        }
        name = pyactag_strdup(key);
        if (name == NULL)
            return -1;
        f = find_field(name);
        if (f == NULL) {
            PyErr_Format(PyExc_TypeError,
                         "unknown parameter '%s' (pyactag.default_params() lists them)", name);
            free(name);
            return -1;
        }
        free(name);
        /* value is borrowed from the dict, which its __index__ or __float__
         * could empty: held while it is read */
        Py_INCREF(value);
        rc = set_field(f, value, &tmp);
        Py_DECREF(value);
        if (rc != 0)
            return -1;
    }
    *p = tmp;
    return 0;
}

/* The shortest decimal that reads back as the same float (0.2f -> 0.2, not
 * 0.20000000298...), so that the dict shows the values as written in C. */
static PyObject *float_value(float f)
{
    char buf[32];
    int prec;
    for (prec = 6; prec < 9; prec++) {
        snprintf(buf, sizeof buf, "%.*g", prec, (double)f);
        if ((float)strtod(buf, NULL) == f)
            return PyFloat_FromDouble(strtod(buf, NULL));
    }
    return PyFloat_FromDouble((double)f);
}

static PyObject *field_value(const field *f, const actag_params *p)
{
    const char *base = (const char *)p + f->offset;
    switch (f->kind) {
    case K_INT:
        return PyLong_FromLong(*(const int *)(const void *)base);
    case K_U32:
        return PyLong_FromUnsignedLong(*(const uint32_t *)(const void *)base);
    case K_CORRECTIONS: {
        int c = *(const int *)(const void *)base;
        if (c == ACTAG_CORRECTIONS_AUTO)
            Py_RETURN_NONE;
        return PyLong_FromLong(c);
    }
    case K_DECODE:
        return PyUnicode_FromString(*(const int *)(const void *)base == ACTAG_DECODE_BINARY
                                        ? "binary"
                                        : "fit");
    case K_FLOAT:
    default:
        return float_value(*(const float *)(const void *)base);
    }
}

PyObject *pyactag_params_to_dict(const actag_params *p)
{
    PyObject *d = PyDict_New();
    int i;
    if (d == NULL)
        return NULL;
    for (i = 0; i < NFIELDS; i++) {
        PyObject *v = field_value(&fields[i], p);
        if (v == NULL || PyDict_SetItemString(d, fields[i].name, v) != 0) {
            Py_XDECREF(v);
            Py_DECREF(d);
            return NULL;
        }
        Py_DECREF(v);
    }
    return d;
}

PyObject *pyactag_tuning_names(void)
{
    PyObject *t;
    int i, n = 0, k = 0;
    for (i = 0; i < NFIELDS; i++)
        n += fields[i].tuning;
    t = PyTuple_New(n);
    if (t == NULL)
        return NULL;
    for (i = 0; i < NFIELDS; i++) {
        PyObject *s;
        if (!fields[i].tuning)
            continue;
        s = PyUnicode_FromString(fields[i].name);
        if (s == NULL) {
            Py_DECREF(t);
            return NULL;
        }
        PyTuple_SetItem(t, k++, s);
    }
    return t;
}
