/*
 * geometry.c -- the sonar geometry of detect() and Tracker.update(): the
 * range limits, aperture or bearing table and orientation flags as the
 * library takes them, each bad value named (the library's own checks,
 * actag_check, follow in the callers).
 */
#include "pyactag.h"

#include <stdlib.h>
#include <string.h>

/* A geometry value narrowed to the C float the library takes: a finite
 * value the float cannot hold (beyond FLT_MAX: inf; nonzero below the least
 * subnormal: 0) is an OverflowError naming the value given, as for the
 * parameters (params.c), not the library's complaint about inf or 0.
 * NaN and infinities pass to the library, which names them. */
static int narrow_geo(double d, const char *name, int index, float *out)
{
    if (pyactag_float_overflows(d)) {
        PyObject *v = PyFloat_FromDouble(d);
        if (v == NULL)
            return -1;
        if (index >= 0)
            PyErr_Format(PyExc_OverflowError, "sonar geometry: %s[%d] is outside the range of a "
                         "C float, got %R", name, index, v);
        else
            PyErr_Format(PyExc_OverflowError, "sonar geometry: %s is outside the range of a C "
                         "float, got %R", name, v);
        Py_DECREF(v);
        return -1;
    }
    *out = (float)d;
    return 0;
}

/* Bearing table: an iterable of exactly `cols` numbers (radians); an element
 * that is no real number (a str, a bool) is a TypeError naming bearings[i].
 * Reading stops at the first value past `cols` (cols <= ACTAG_MAX_DIM), so an
 * endless iterator (itertools.count()) is refused, not read forever. */
float *pyactag_read_bearings(PyObject *obj, int cols)
{
    PyObject *it = PyObject_GetIter(obj), *item;
    float *b;
    int n = 0;
    if (it == NULL)
        return NULL;
    b = (float *)malloc((size_t)cols * sizeof(float));
    if (b == NULL) {
        Py_DECREF(it);
        PyErr_NoMemory();
        return NULL;
    }
    while ((item = PyIter_Next(it)) != NULL) {
        int is_bool;
        double d;
        if (n == cols) { /* one value too many: the count when it has one */
            Py_ssize_t len;
            Py_DECREF(item);
            Py_DECREF(it);
            free(b);
            len = PyObject_Size(obj); /* a sequence's; an iterator has none */
            if (len < 0)
                PyErr_Clear();
            if (len > cols)
                PyErr_Format(PyExc_ValueError, "bearings has %zd values, the frame has %d columns",
                             len, cols);
            else
                PyErr_Format(PyExc_ValueError,
                             "bearings has more than %d values, the frame has %d columns", cols,
                             cols);
            return NULL;
        }
        is_bool = pyactag_is_bool(item);
        d = is_bool ? -1.0 : PyFloat_AsDouble(item);
        if (is_bool || (d == -1.0 && PyErr_Occurred())) {
            PyErr_Clear();
            PyErr_Format(PyExc_TypeError, "bearings[%d] must be a real number, got %R", n, item);
            Py_DECREF(item);
            break;
        }
        Py_DECREF(item);
        if (narrow_geo(d, "bearings", n, &b[n]) != 0)
            break;
        n++;
    }
    Py_DECREF(it);
    if (PyErr_Occurred()) {
        free(b);
        return NULL;
    }
    if (n != cols) {
        PyErr_Format(PyExc_ValueError, "bearings has %d values, the frame has %d columns", n,
                     cols);
        free(b);
        return NULL;
    }
    return b;
}

int pyactag_geometry_head(double min_range, double max_range, PyObject *aperture_o,
                          PyObject *bearings_o, int range_asc, int az_asc,
                          actag_sonar_geometry *geo)
{
    if ((aperture_o == Py_None) == (bearings_o == Py_None)) {
        PyErr_SetString(PyExc_ValueError,
                        aperture_o == Py_None
                            ? "sonar geometry: give aperture (radians) or bearings (one azimuth "
                              "per column)"
                            : "sonar geometry: give aperture or bearings, not both");
        return -1;
    }
    if (az_asc && bearings_o != Py_None) { /* the table overrides the flag: refused, not ignored */
        PyErr_SetString(PyExc_ValueError,
                        "sonar geometry: azimuth_ascending=True does not apply with bearings "
                        "(the table gives each column's azimuth in column order)");
        return -1;
    }
    memset(geo, 0, sizeof *geo);
    if (narrow_geo(min_range, "min_range", -1, &geo->min_range) != 0 ||
        narrow_geo(max_range, "max_range", -1, &geo->max_range) != 0)
        return -1;
    if (aperture_o != Py_None) {
        double ap = PyFloat_AsDouble(aperture_o);
        if (ap == -1.0 && PyErr_Occurred())
            return -1;
        if (narrow_geo(ap, "aperture", -1, &geo->aperture) != 0)
            return -1;
    }
    geo->flags = (range_asc ? ACTAG_RANGE_ASCENDING : 0u) | (az_asc ? ACTAG_AZIMUTH_ASCENDING : 0u);

    return 0;
}
