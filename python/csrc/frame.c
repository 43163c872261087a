/*
 * frame.c -- a Python 2-D uint8/uint16 object as an actag_frame.
 *
 * The limited API of CPython 3.9 has no PyObject_GetBuffer (it joined the
 * limited API in 3.11), so pixels are reached in two ways that both stay
 * inside it:
 *   1. __array_interface__ (numpy arrays and views, Pillow images, ...):
 *      the data pointer, shape and byte strides. Rows that are contiguous
 *      in memory (column step = item size) are read in place with the row
 *      step as the frame's stride; anything else (column steps, negative
 *      steps, misaligned or byte-swapped 16-bit data) is copied.
 *   2. Any other object: memoryview(obj) (the buffer protocol), whose
 *      tobytes() gives a C-ordered copy; format 'B' or 'H' (with any byte
 *      order prefix), 2-D.
 * The object (or the copy) stays referenced until pyactag_frame_release().
 */
#include "pyactag.h"

#include <stdlib.h>
#include <string.h>

static int host_is_little(void)
{
    const uint16_t one = 1;
    return *(const unsigned char *)&one == 1;
}

static int bad_type(const char *what)
{
    PyErr_Format(PyExc_TypeError,
                 "frame must be a 2-D uint8 or uint16 array or buffer (rows = range bins, "
                 "columns = beams): %s",
                 what);
    return -1;
}

static int dims_ok(long long rows, long long cols)
{
    if (rows < 1 || cols < 1 || rows > ACTAG_MAX_DIM || cols > ACTAG_MAX_DIM) {
        PyErr_Format(PyExc_ValueError, "frame is %lld x %lld; rows and columns must be 1..%d",
                     rows, cols, ACTAG_MAX_DIM);
        return -1;
    }
    return 0;
}

/* Copy rows x cols items of `isize` bytes at base + r*s0 + c*s1 (byte steps,
 * any sign) into a new contiguous buffer, swapping 16-bit bytes if asked. */
static void *gather(const char *base, long long rows, long long cols, long long s0, long long s1,
                    int isize, int swap)
{
    unsigned char *dst = (unsigned char *)malloc((size_t)(rows * cols * isize));
    long long r, c;
    if (dst == NULL)
        return NULL;
    for (r = 0; r < rows; r++) {
        const char *row = base + r * s0;
        unsigned char *d = dst + (size_t)(r * cols * isize);
        if (isize == 1) {
            for (c = 0; c < cols; c++)
                d[c] = (unsigned char)row[c * s1];
        } else {
            for (c = 0; c < cols; c++) {
                const unsigned char *s = (const unsigned char *)(row + c * s1);
                d[2 * c] = swap ? s[1] : s[0];
                d[2 * c + 1] = swap ? s[0] : s[1];
            }
        }
    }
    return dst;
}

/* An integer: a Python int or any object with __index__ (numpy integers,
 * which a shape may hold). Returns 0; -1 when o is no integer, -2 when it
 * does not fit a long long; no exception is left set. __index__ may run
 * Python code: the caller holds what o is borrowed from. */
static int get_ll(PyObject *o, long long *out)
{
    PyObject *ix;
    long long v;
    int overflow = 0;
    if (o == NULL)
        return -1;
    ix = PyNumber_Index(o); /* TypeError for a float, a str, ... */
    if (ix == NULL) {
        PyErr_Clear();
        return -1;
    }
    v = PyLong_AsLongLongAndOverflow(ix, &overflow);
    Py_DECREF(ix);
    if (overflow)
        return -2;
    if (v == -1 && PyErr_Occurred()) {
        PyErr_Clear();
        return -1;
    }
    *out = v;
    return 0;
}

/* Shape or strides tuple of length 2: 0, or get_ll's -1 or -2 (-1 also when
 * t is no tuple of 2). */
static int get_pair(PyObject *t, long long out[2])
{
    int rc;
    if (t == NULL || !PyTuple_Check(t) || PyTuple_Size(t) != 2)
        return -1;
    rc = get_ll(PyTuple_GetItem(t, 0), &out[0]);
    return rc != 0 ? rc : get_ll(PyTuple_GetItem(t, 1), &out[1]);
}

static int fill(pyactag_frame_view *v, const void *data, long long rows, long long cols,
                long long stride_items, int depth)
{
    v->frame.data = data;
    v->frame.rows = (int)rows;
    v->frame.cols = (int)cols;
    v->frame.stride = (int)stride_items;
    v->frame.depth = depth;
    return 0;
}

/* The entries of __array_interface__ that are read (NULL when absent). */
enum { AI_TYPESTR, AI_SHAPE, AI_DATA, AI_STRIDES, AI_MASK, AI_OFFSET, AI_N };

/* Path 1 on the entries e[AI_N]. Returns 0 done, -1 error, 1 "not usable
 * here, try the buffer protocol". */
static int read_array_interface(PyObject *obj, PyObject *const *e, pyactag_frame_view *v)
{
    PyObject *typestr_o = e[AI_TYPESTR], *shape_o = e[AI_SHAPE], *data_o = e[AI_DATA];
    PyObject *strides_o = e[AI_STRIDES], *mask_o = e[AI_MASK];
    char typestr[8];
    long long shape[2], strides[2], ptr;
    int isize, swap = 0, rc;
    const char *t;
    char *tmp;
    PyObject *keep = obj; /* what holds the pixels */

    if (typestr_o == NULL || !PyUnicode_Check(typestr_o))
        return bad_type("__array_interface__ has no typestr");
    tmp = pyactag_strdup(typestr_o);
    if (tmp == NULL)
        return -1;
    strncpy(typestr, tmp, sizeof typestr - 1);
    typestr[sizeof typestr - 1] = '\0';
    free(tmp);
    t = typestr;
    if (strcmp(t, "|u1") == 0 || strcmp(t, "<u1") == 0 || strcmp(t, ">u1") == 0 ||
        strcmp(t, "=u1") == 0) {
        isize = 1;
    } else if (strcmp(t, "<u2") == 0 || strcmp(t, ">u2") == 0 || strcmp(t, "=u2") == 0 ||
               strcmp(t, "|u2") == 0) {
        isize = 2;
        swap = (t[0] == '<' && !host_is_little()) || (t[0] == '>' && host_is_little());
    } else {
        PyErr_Format(PyExc_TypeError,
                     "frame must hold uint8 or uint16 pixels, not array type '%s' "
                     "(convert with .astype(numpy.uint8) or numpy.uint16)",
                     t);
        return -1;
    }
    rc = get_pair(shape_o, shape);
    if (rc != 0) {
        if (shape_o != NULL && PyTuple_Check(shape_o) && PyTuple_Size(shape_o) != 2)
            PyErr_Format(PyExc_ValueError, "frame must be 2-D, not %zd-D",
                         PyTuple_Size(shape_o));
        else if (rc == -2)
            PyErr_Format(PyExc_ValueError, "frame shape %R: rows and columns must be 1..%d",
                         shape_o, ACTAG_MAX_DIM);
        else if (shape_o != NULL && PyTuple_Check(shape_o))
            PyErr_Format(PyExc_TypeError,
                         "frame must be a 2-D uint8 or uint16 array or buffer: its "
                         "__array_interface__ shape must be 2 integers, got %R",
                         shape_o);
        else
            bad_type("__array_interface__ has no 2-D shape");
        return -1;
    }
    if (mask_o != NULL && mask_o != Py_None)
        return bad_type("masked arrays are not supported");
    /* data: (pointer, read-only flag), or a bytes object (Pillow) plus an
     * optional offset; anything else (another buffer object, None): let the
     * buffer protocol read the object. */
    if (data_o != NULL && PyBytes_Check(data_o)) {
        PyObject *off_o = e[AI_OFFSET];
        long long off = 0;
        rc = off_o != NULL && off_o != Py_None ? get_ll(off_o, &off) : 0;
        if (rc != 0)
            return bad_type(rc == -2 ? "__array_interface__ offset outside its data"
                                     : "__array_interface__ offset is not an integer");
        if (dims_ok(shape[0], shape[1]) != 0)
            return -1;
        if (off < 0 || off > (long long)PyBytes_Size(data_o))
            return bad_type("__array_interface__ offset outside its data");
        ptr = (long long)(size_t)(PyBytes_AsString(data_o) + off);
        keep = data_o;
    } else if (data_o == NULL || !PyTuple_Check(data_o) || PyTuple_Size(data_o) < 1 ||
               get_ll(PyTuple_GetItem(data_o, 0), &ptr) != 0) {
        return 1;
    } else if (dims_ok(shape[0], shape[1]) != 0) {
        return -1;
    }
    if (strides_o == NULL || strides_o == Py_None) {
        strides[1] = isize;
        strides[0] = shape[1] * isize;
    } else if (get_pair(strides_o, strides) != 0) {
        return bad_type("__array_interface__ strides are not 2 integers");
    }
    if (ptr == 0)
        return bad_type("__array_interface__ data pointer is NULL");
    if (keep == data_o && PyBytes_Check(data_o)) { /* the pixels must fit in the bytes */
        long long size = (long long)PyBytes_Size(data_o), hi, lo;
        /* a stride beyond the bytes cannot fit (and the products below would
         * overflow: strides of 2**62 wrapped round and passed the check) */
        if (strides[0] > size || strides[0] < -size || strides[1] > size || strides[1] < -size)
            return bad_type("__array_interface__ data is smaller than its shape");
        hi = (shape[0] - 1) * (strides[0] > 0 ? strides[0] : 0) +
                       (shape[1] - 1) * (strides[1] > 0 ? strides[1] : 0);
        lo = (shape[0] - 1) * (strides[0] < 0 ? strides[0] : 0) +
                       (shape[1] - 1) * (strides[1] < 0 ? strides[1] : 0);
        const char *b = PyBytes_AsString(data_o);
        long long pos = (long long)((const char *)(size_t)ptr - b);
        if (pos + lo < 0 || pos + hi + isize > size)
            return bad_type("__array_interface__ data is smaller than its shape");
    }
    Py_INCREF(keep);
    v->keep = keep;
    if (strides[1] == isize && strides[0] > 0 && strides[0] % isize == 0 &&
        strides[0] / isize >= shape[1] && strides[0] / isize <= 0x7fffffffLL && !swap &&
        (isize == 1 || ptr % 2 == 0))
        return fill(v, (const void *)(size_t)ptr, shape[0], shape[1], strides[0] / isize,
                    8 * isize);
    v->copy = gather((const char *)(size_t)ptr, shape[0], shape[1], strides[0], strides[1], isize,
                     swap);
    if (v->copy == NULL) {
        PyErr_NoMemory();
        return -1;
    }
    v->copied = 1;
    return fill(v, v->copy, shape[0], shape[1], shape[1], 8 * isize);
}

/* Path 1: the entries held while they are read (an __index__ of a shape
 * entry runs Python code, which could empty the dict and free them). */
static int from_array_interface(PyObject *obj, PyObject *ai, pyactag_frame_view *v)
{
    static const char *const keys[AI_N] = {"typestr", "shape", "data", "strides", "mask",
                                           "offset"};
    PyObject *e[AI_N];
    int i, rc;
    if (!PyDict_Check(ai))
        return 1;
    for (i = 0; i < AI_N; i++) {
        e[i] = PyDict_GetItemString(ai, keys[i]);
        Py_XINCREF(e[i]);
    }
    rc = read_array_interface(obj, e, v);
    for (i = 0; i < AI_N; i++)
        Py_XDECREF(e[i]);
    return rc;
}

/* Path 2: the buffer protocol through memoryview. */
static int from_memoryview(PyObject *obj, pyactag_frame_view *v)
{
    PyObject *mv, *attr, *bytes;
    long long ndim, shape[2];
    char fmt[8];
    char *tmp;
    int isize, swap = 0;

    mv = PyMemoryView_FromObject(obj);
    if (mv == NULL) {
        PyErr_Clear();
        return bad_type("the object supports neither __array_interface__ nor the buffer protocol");
    }
    attr = PyObject_GetAttrString(mv, "ndim");
    if (attr == NULL || get_ll(attr, &ndim) != 0) {
        Py_XDECREF(attr);
        Py_DECREF(mv);
        return bad_type("memoryview without ndim");
    }
    Py_DECREF(attr);
    if (ndim != 2) {
        Py_DECREF(mv);
        PyErr_Format(PyExc_ValueError,
                     "frame must be 2-D, not %lld-D (a flat buffer can be given a shape with "
                     "memoryview(buf).cast('B', (rows, cols)))",
                     ndim);
        return -1;
    }
    attr = PyObject_GetAttrString(mv, "format");
    if (attr == NULL || !PyUnicode_Check(attr) || (tmp = pyactag_strdup(attr)) == NULL) {
        Py_XDECREF(attr);
        Py_DECREF(mv);
        if (!PyErr_Occurred())
            bad_type("memoryview without format");
        return -1;
    }
    Py_DECREF(attr);
    strncpy(fmt, tmp, sizeof fmt - 1);
    fmt[sizeof fmt - 1] = '\0';
    free(tmp);
    if (strcmp(fmt, "B") == 0 || strcmp(fmt, "@B") == 0 || strcmp(fmt, "=B") == 0 ||
        strcmp(fmt, "<B") == 0 || strcmp(fmt, ">B") == 0 || strcmp(fmt, "!B") == 0) {
        isize = 1;
    } else if (strcmp(fmt, "H") == 0 || strcmp(fmt, "@H") == 0 || strcmp(fmt, "=H") == 0) {
        isize = 2;
    } else if (strcmp(fmt, "<H") == 0) {
        isize = 2;
        swap = !host_is_little();
    } else if (strcmp(fmt, ">H") == 0 || strcmp(fmt, "!H") == 0) {
        isize = 2;
        swap = host_is_little();
    } else {
        Py_DECREF(mv);
        PyErr_Format(PyExc_TypeError,
                     "frame must hold uint8 or uint16 pixels (buffer format 'B' or 'H'), not '%s'",
                     fmt);
        return -1;
    }
    attr = PyObject_GetAttrString(mv, "shape");
    if (attr == NULL || get_pair(attr, shape) != 0) {
        Py_XDECREF(attr);
        Py_DECREF(mv);
        return bad_type("memoryview without a 2-D shape");
    }
    Py_DECREF(attr);
    if (dims_ok(shape[0], shape[1]) != 0) {
        Py_DECREF(mv);
        return -1;
    }
    bytes = PyObject_CallMethod(mv, "tobytes", NULL);
    Py_DECREF(mv);
    if (bytes == NULL)
        return -1;
    if (PyBytes_Size(bytes) != shape[0] * shape[1] * isize) {
        Py_DECREF(bytes);
        return bad_type("buffer size does not match its shape");
    }
    v->keep = bytes;
    v->copied = 1;
    if (swap || (isize == 2 && ((size_t)PyBytes_AsString(bytes)) % 2 != 0)) {
        v->copy = gather(PyBytes_AsString(bytes), shape[0], shape[1], shape[1] * isize, isize,
                         isize, swap);
        if (v->copy == NULL) {
            PyErr_NoMemory();
            return -1;
        }
        return fill(v, v->copy, shape[0], shape[1], shape[1], 8 * isize);
    }
    return fill(v, PyBytes_AsString(bytes), shape[0], shape[1], shape[1], 8 * isize);
}

/* Objects whose pixels would be read as something they are not: a numpy
 * masked array (its __array_interface__ does not carry the mask, so the
 * masked pixels would be read) and a Pillow palette image (its bytes are
 * palette indices, not grey levels). 1 when refused (TypeError set). */
static int refused_kind(PyObject *obj)
{
    PyObject *mode;
    if (PyObject_HasAttrString(obj, "mask") && PyObject_HasAttrString(obj, "filled") &&
        PyObject_HasAttrString(obj, "__array_interface__")) {
        bad_type("masked arrays are not supported (pass .filled(value) or .data)");
        return 1;
    }
    mode = PyObject_HasAttrString(obj, "getpalette") ? PyObject_GetAttrString(obj, "mode") : NULL;
    if (mode == NULL) {
        PyErr_Clear();
        return 0;
    }
    if (PyUnicode_Check(mode) && (PyUnicode_CompareWithASCIIString(mode, "P") == 0 ||
                                  PyUnicode_CompareWithASCIIString(mode, "PA") == 0)) {
        Py_DECREF(mode);
        bad_type("a palette image (mode 'P') holds palette indices, not grey levels: "
                 "convert it with .convert('L') first");
        return 1;
    }
    Py_DECREF(mode);
    return 0;
}

int pyactag_frame_get(PyObject *obj, pyactag_frame_view *v)
{
    PyObject *ai;
    memset(v, 0, sizeof *v);
    if (refused_kind(obj))
        return -1;
    ai = PyObject_GetAttrString(obj, "__array_interface__");
    if (ai != NULL) {
        int rc = from_array_interface(obj, ai, v);
        Py_DECREF(ai);
        if (rc <= 0) {
            if (rc < 0)
                pyactag_frame_release(v);
            return rc;
        }
        pyactag_frame_release(v);
        memset(v, 0, sizeof *v);
    } else {
        if (!PyErr_ExceptionMatches(PyExc_AttributeError))
            return -1;
        PyErr_Clear();
    }
    if (from_memoryview(obj, v) != 0) {
        pyactag_frame_release(v);
        return -1;
    }
    return 0;
}

void pyactag_frame_release(pyactag_frame_view *v)
{
    free(v->copy);
    v->copy = NULL;
    Py_XDECREF(v->keep);
    v->keep = NULL;
}
