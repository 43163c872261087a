/*
 * detector_type.c -- pyactag._core.Detector: validated actag_params, the
 * family they point at, and a workspace the object keeps for its next call.
 *
 * Threads: detect() releases the GIL around actag_detect(). The object's
 * workspace serves one call at a time; a call that finds it busy (another
 * thread is detecting with the same object) uses a workspace of its own for
 * that call. The busy flag is only read and written with the GIL held. The
 * parameters and the family are immutable after construction.
 */
#include "pyactag.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct detobj {
    PyObject_HEAD
    actag_params params;
    PyObject *family; /* the Family instance params.family points into */
    void *ws;         /* kept workspace (malloc), or NULL */
    size_t ws_size;
    int ws_busy;
} detobj;

static PyObject *detector_new(PyTypeObject *type, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"family", "params", NULL};
    PyObject *family, *params = Py_None;
    const actag_family *fam;
    allocfunc alloc;
    detobj *self;
    int rc;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "O|O:Detector", kwlist, &family, &params))
        return NULL;
    fam = pyactag_family_of(family);
    if (fam == NULL)
        return NULL;
    alloc = (allocfunc)PyType_GetSlot(type, Py_tp_alloc);
    self = (detobj *)alloc(type, 0);
    if (self == NULL)
        return NULL;
    actag_params_default(&self->params);
    if (pyactag_params_from_dict(params, &self->params) != 0) {
        Py_DECREF(self);
        return NULL;
    }
    Py_INCREF(family);
    self->family = family;
    self->params.family = fam;
    {
        actag_error_detail d;
        rc = actag_params_validate(&self->params, &d);
        if (rc != ACTAG_OK) {
            Py_DECREF(self);
            return pyactag_raise_detail("invalid parameters", &d);
        }
    }
    return (PyObject *)self;
}

/* Cyclic GC: the Family is the one object a Detector holds, and a cycle
 * through it (a Family subclass instance holding its Detector) is freed
 * only if the collector sees that reference. A heap type's instances also
 * visit their type (3.9+). */
static int detector_traverse(PyObject *o, visitproc visit, void *arg)
{
    Py_VISIT(Py_TYPE(o));
    Py_VISIT(((detobj *)o)->family);
    return 0;
}

/* Drops the Family (and params.family, which points into it); the
 * workspace stays for dealloc. A cleared Detector refuses detect(). */
static int detector_clear(PyObject *o)
{
    detobj *self = (detobj *)o;
    self->params.family = NULL;
    Py_CLEAR(self->family);
    return 0;
}

static void detector_dealloc(PyObject *o)
{
    detobj *self = (detobj *)o;
    PyTypeObject *tp = Py_TYPE(o);
    freefunc tfree = (freefunc)PyType_GetSlot(tp, Py_tp_free);
    PyObject_GC_UnTrack(o);
    detector_clear(o);
    free(self->ws);
    self->ws = NULL;
    tfree(o);
    Py_DECREF(tp);
}

static int detector_cleared(const detobj *self)
{
    if (self->family != NULL)
        return 0;
    PyErr_SetString(PyExc_RuntimeError,
                    "Detector: cleared by the garbage collector (it no longer has a family)");
    return 1;
}

PyObject *pyactag_detection_tuple(const actag_detection *d)
{
    const actag_point *c = d->corners;
    const float *r = d->range, *a = d->azimuth;
    return Py_BuildValue("(iiOdd((dd)(dd)(dd)(dd))((dd)(dd)(dd)(dd)))", d->id, d->hamming,
                         d->mirrored ? Py_True : Py_False, (double)d->decision_margin,
                         (double)d->inlier_ratio, (double)c[0].x, (double)c[0].y,
                         (double)c[1].x, (double)c[1].y, (double)c[2].x, (double)c[2].y,
                         (double)c[3].x, (double)c[3].y, (double)r[0], (double)a[0],
                         (double)r[1], (double)a[1], (double)r[2], (double)a[2], (double)r[3],
                         (double)a[3]);
}

static PyObject *detection_item(const void *d)
{
    return pyactag_detection_tuple((const actag_detection *)d);
}

PyObject *pyactag_list_of(const void *items, size_t size, int n, PyObject *(*conv)(const void *))
{
    PyObject *list = PyList_New(n);
    int i;
    if (list == NULL)
        return NULL;
    for (i = 0; i < n; i++) {
        PyObject *t = conv((const char *)items + (size_t)i * size);
        if (t == NULL) {
            Py_DECREF(list);
            return NULL;
        }
        PyList_SetItem(list, i, t);
    }
    return list;
}

PyObject *pyactag_raise_call(int n, const char *context, const actag_frame *frame,
                             const actag_sonar_geometry *geometry, const actag_params *params,
                             size_t workspace_size, int max_out)
{
    actag_error_detail d;
    if (actag_check(frame, geometry, params, workspace_size, max_out, &d) == n)
        return pyactag_raise_detail(context, &d);
    return pyactag_raise(n, context);
}

/* Every counter of actag_stats, by its C name (include/actag/actag.h). */
static PyObject *stats_dict(const actag_stats *s)
{
    return Py_BuildValue("{sisisisisisisisisisisisisisisisisi}", "contours", s->contours,
                         "size_ok", s->size_ok, "overflowed", s->overflowed, "quads", s->quads,
                         "decoded", s->decoded, "duplicates", s->duplicates, "dropped",
                         s->dropped, "searched", s->searched, "decodes", s->decodes,
                         "iterations", s->iterations, "contour_cap", s->contour_cap,
                         "ransac_exhausted", s->ransac_exhausted, "contour_budget",
                         s->contour_budget, "frame_budget", s->frame_budget, "decode_cap",
                         s->decode_cap, "search_cap", s->search_cap, "guess_cap", s->guess_cap);
}

static PyObject *detector_detect(PyObject *o, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"frame",           "min_range",         "max_range",
                             "aperture",        "bearings",          "range_ascending",
                             "azimuth_ascending", "max_detections",  "stages",
                             NULL};
    detobj *self = (detobj *)o;
    PyObject *frame_o, *aperture_o = Py_None, *bearings_o = Py_None;
    double min_range, max_range;
    int range_asc = 0, az_asc = 0, max_out = 64, want_stages = 0;
    pyactag_frame_view view;
    actag_sonar_geometry geo;
    actag_detection *det = NULL;
    actag_stats st;
    float *bearings = NULL;
    void *ws;
    size_t need;
    int own_ws, n;
    PyObject *list = NULL, *stages = NULL, *result = NULL;

    if (!PyArg_ParseTupleAndKeywords(args, kwds, "Odd|OOppip:detect", kwlist, &frame_o,
                                     &min_range, &max_range, &aperture_o, &bearings_o,
                                     &range_asc, &az_asc, &max_out, &want_stages))
        return NULL;
    if (detector_cleared(self))
        return NULL;
    if (max_out < 0 || max_out > PYACTAG_MAX_DETECTIONS) {
        PyErr_Format(PyExc_ValueError, "max_detections must be 0..%d", PYACTAG_MAX_DETECTIONS);
        return NULL;
    }
    if (pyactag_geometry_head(min_range, max_range, aperture_o, bearings_o, range_asc, az_asc,
                              &geo) != 0)
        return NULL;
    if (pyactag_frame_get(frame_o, &view) != 0)
        return NULL;
    if (bearings_o != Py_None) {
        bearings = pyactag_read_bearings(bearings_o, view.frame.cols);
        if (bearings == NULL)
            goto done;
        geo.bearings = bearings;
    }
    det = (actag_detection *)malloc((size_t)(max_out > 0 ? max_out : 1) * sizeof *det);
    if (det == NULL) {
        PyErr_NoMemory();
        goto done;
    }
    need = actag_workspace_size(view.frame.rows, view.frame.cols);
    own_ws = !self->ws_busy;
    if (own_ws) {
        if (self->ws_size < need) {
            free(self->ws);
            self->ws = malloc(need);
            self->ws_size = self->ws ? need : 0;
            if (self->ws == NULL) {
                PyErr_NoMemory();
                goto done;
            }
        }
        ws = self->ws;
        self->ws_busy = 1;
    } else {
        ws = malloc(need);
        if (ws == NULL) {
            PyErr_NoMemory();
            goto done;
        }
    }
    memset(&st, 0, sizeof st);
    Py_BEGIN_ALLOW_THREADS
    n = actag_detect(&view.frame, &geo, &self->params, ws, need, det, max_out, &st);
    Py_END_ALLOW_THREADS
    if (n >= 0 && want_stages) {
        const uint8_t *f = actag_workspace_filtered(ws, view.frame.rows, view.frame.cols);
        const uint32_t *b = actag_workspace_bitmap(ws, view.frame.rows, view.frame.cols);
        Py_ssize_t sz = (Py_ssize_t)view.frame.rows * view.frame.cols;
        PyObject *fb = f ? PyBytes_FromStringAndSize((const char *)f, sz) : NULL;
        PyObject *bb = b ? PyBytes_FromStringAndSize(NULL, sz) : NULL;
        if (fb && bb) {
            /* 0 = black, 255 = white */
            actag_bitmap_unpack(b, view.frame.rows, view.frame.cols,
                                (uint8_t *)PyBytes_AsString(bb), view.frame.cols, 255u);
            stages = Py_BuildValue("{sNsNsisi}", "filtered", fb, "binary", bb, "rows",
                                   view.frame.rows, "cols", view.frame.cols);
        } else {
            Py_XDECREF(fb);
            Py_XDECREF(bb);
            if (!PyErr_Occurred())
                PyErr_SetString(PyExc_RuntimeError, "stage images unavailable");
        }
    }
    if (own_ws)
        self->ws_busy = 0;
    else
        free(ws);
    if (n < 0) {
        pyactag_raise_call(n, "actag_detect", &view.frame, &geo, &self->params, need, max_out);
        goto done;
    }
    if (want_stages && stages == NULL)
        goto done;
    list = pyactag_list_of(det, sizeof *det, n, detection_item);
    if (list == NULL)
        goto done;
    {
        PyObject *sd = stats_dict(&st);
        if (sd == NULL)
            goto done;
        result = Py_BuildValue("(NNO)", list, sd, stages ? stages : Py_None);
        list = NULL;
    }
done:
    Py_XDECREF(list);
    Py_XDECREF(stages);
    free(det);
    free(bearings);
    pyactag_frame_release(&view);
    return result;
}

static PyObject *get_params(PyObject *o, void *c)
{
    (void)c;
    return pyactag_params_to_dict(&((detobj *)o)->params);
}

static PyObject *get_family(PyObject *o, void *c)
{
    detobj *self = (detobj *)o;
    (void)c;
    if (detector_cleared(self))
        return NULL;
    Py_INCREF(self->family);
    return self->family;
}

static PyObject *get_workspace_bytes(PyObject *o, void *c)
{
    (void)c;
    return PyLong_FromSize_t(((detobj *)o)->ws_size);
}

static PyGetSetDef detector_getset[] = {
    {"params", get_params, NULL, "the parameters as a dict (a copy)", NULL},
    {"family", get_family, NULL, "the Family", NULL},
    {"workspace_bytes", get_workspace_bytes, NULL,
     "bytes of the workspace kept for the next call (0 before the first)", NULL},
    {NULL, NULL, NULL, NULL, NULL}};

static PyMethodDef detector_methods[] = {
    {"detect", (PyCFunction)(void (*)(void))detector_detect, METH_VARARGS | METH_KEYWORDS,
     "detect(frame, min_range, max_range, aperture=None, bearings=None, range_ascending=False,\n"
     "       azimuth_ascending=False, max_detections=64, stages=False)\n"
     "-> (list of (id, hamming, mirrored, decision_margin, inlier_ratio,\n"
     "             ((x, y) x 4), ((range, azimuth) x 4)), stats dict, stages dict or None)"},
    {NULL, NULL, 0, NULL}};

static PyType_Slot detector_slots[] = {
    {Py_tp_new, (void *)detector_new},
    {Py_tp_dealloc, (void *)detector_dealloc},
    {Py_tp_traverse, (void *)detector_traverse},
    {Py_tp_clear, (void *)detector_clear},
    {Py_tp_getset, detector_getset},
    {Py_tp_methods, detector_methods},
    {Py_tp_doc, (void *)"Detector(family, params=None): validated parameters and a workspace."},
    {0, NULL}};

static PyType_Spec detector_spec = {"pyactag._core.Detector", sizeof(detobj), 0,
                                    Py_TPFLAGS_DEFAULT | Py_TPFLAGS_HAVE_GC,
                                    detector_slots};

PyObject *pyactag_detector_type_create(PyObject *module)
{
    (void)module;
    return PyType_FromSpec(&detector_spec);
}
