/*
 * tracker_type.c -- pyactag._core.Tracker: an actag_tracker (actag/track.h),
 * the validated parameters of its whole-frame and ROI searches, the family
 * they point at, and the workspace of its updates.
 *
 * Threads: update() releases the GIL around actag_tracker_update(). A
 * tracker's state belongs to one stream, so a second update() while one is
 * running (another thread, same object) is a RuntimeError, not a second
 * workspace: the busy flag is only read and written with the GIL held.
 */
#include "pyactag.h"

#include "actag/track.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

typedef struct trackobj {
    PyObject_HEAD
    actag_params params, roi_params;
    int have_roi;
    PyObject *family;       /* the Family both parameter sets point into */
    actag_tracker *tracker; /* malloc: about 6 KB */
    void *ws;               /* kept workspace (malloc), or NULL */
    size_t ws_size;
    int busy;               /* an update() is running (read and written with the GIL) */
    long frames;            /* tracker->frame after the last update (with the GIL) */
} trackobj;

/* The fields of actag_track_params with actag_tracker_init()'s rules
 * (track.h): integers in lo..hi, reals in (lo, hi] (lo_open) or [lo, hi]. */
typedef struct tp_field {
    const char *name;
    size_t offset; /* of the int (is_int) or float in actag_track_params */
    int is_int, lo_open;
    double lo, hi;
    const char *rule;
} tp_field;

#define TP_AT(f) offsetof(actag_track_params, f)
static const tp_field tp_fields[] = {
    {"full_every", TP_AT(full_every), 1, 0, 1.0, (double)INT_MAX, "at least 1"},
    {"confirm_frames", TP_AT(confirm_frames), 1, 0, 1.0, (double)INT_MAX, "at least 1"},
    /* any finite value, checked as a float (FLT_MAX: no confirmation by
     * margin alone) */
    {"confirm_margin", TP_AT(confirm_margin), 0, 0, -DBL_MAX, DBL_MAX, "finite"},
    {"max_missed", TP_AT(max_missed), 1, 0, 0.0, (double)INT_MAX, "at least 0"},
    {"roi_scale", TP_AT(roi_scale), 0, 1, 0.0, 10.0, "in (0, 10]"},
    {"gate", TP_AT(gate), 0, 1, 0.0, 10.0, "in (0, 10]"},
    {"smoothing", TP_AT(smoothing), 0, 1, 0.0, 1.0, "in (0, 1]"},
    {"refind_after", TP_AT(refind_after), 1, 0, 0.0, (double)INT_MAX, "at least 0"},
    {"verify", TP_AT(verify), 1, 0, 0.0, 1.0, "0 or 1"},
    {"report_coasting", TP_AT(report_coasting), 1, 0, 0.0, 1.0, "0 or 1"}};
#undef TP_AT
#define TP_NFIELDS ((int)(sizeof tp_fields / sizeof tp_fields[0]))

static int tp_in_range(const tp_field *f, double v)
{
    return (f->lo_open ? v > f->lo : v >= f->lo) && v <= f->hi; /* NaN fails */
}

/* Field f of *p from value (with the GIL; value borrowed from the caller's
 * dict, which its __index__ or __float__ could empty); the bad value named. */
static int tp_set_owned(const tp_field *f, PyObject *value, actag_track_params *p)
{
    double v;
    float fv;
    int is_bool = pyactag_is_bool(value); /* first: it clears any pending error */
    if (f->is_int) {
        PyObject *ix = is_bool || PyFloat_Check(value) ? NULL : PyNumber_Index(value);
        long l;
        int overflow = 0;
        if (ix == NULL) {
            PyErr_Clear();
            PyErr_Format(PyExc_TypeError, "track parameter %s must be an integer, got %R",
                         f->name, value);
            return -1;
        }
        l = PyLong_AsLongAndOverflow(ix, &overflow);
        Py_DECREF(ix);
        if (overflow || l > INT_MAX || l < INT_MIN) {
            PyErr_Format(PyExc_OverflowError, "track parameter %s does not fit a C int, got %R",
                         f->name, value);
            return -1;
        }
        if (!tp_in_range(f, (double)l)) {
            PyErr_Format(PyExc_ValueError, "track parameter %s must be %s, got %R", f->name,
                         f->rule, value);
            return -1;
        }
        *(int *)(void *)((char *)p + f->offset) = (int)l;
        return 0;
    }
    v = is_bool ? -1.0 : PyFloat_AsDouble(value);
    if (is_bool || (v == -1.0 && PyErr_Occurred())) {
        int too_big = !is_bool && PyErr_ExceptionMatches(PyExc_OverflowError);
        PyErr_Clear();
        PyErr_Format(too_big ? PyExc_OverflowError : PyExc_TypeError,
                     too_big ? "track parameter %s is too large for a floating-point number, got %R"
                             : "track parameter %s must be a real number, got %R",
                     f->name, value);
        return -1;
    }
    /* the rule on the value given (NaN and infinities fail every one), then
     * on the float the library gets */
    if (!tp_in_range(f, v)) {
        PyErr_Format(PyExc_ValueError, "track parameter %s must be %s, got %R", f->name, f->rule,
                     value);
        return -1;
    }
    /* beyond FLT_MAX once rounded to a float (3.4028235e38, numpy's float32
     * maximum as printed, rounds to it and is a float) */
    if (fabs(v) > 3.4028235677973366e38) {
        PyErr_Format(PyExc_OverflowError,
                     "track parameter %s is outside the range of a C float, got %R", f->name,
                     value);
        return -1;
    }
    fv = fabs(v) > FLT_MAX ? (v > 0.0 ? FLT_MAX : -FLT_MAX) : (float)v;
    if (!tp_in_range(f, (double)fv)) {
        PyErr_Format(PyExc_ValueError, "track parameter %s must be %s as a C float, got %R",
                     f->name, f->rule, value);
        return -1;
    }
    *(float *)(void *)((char *)p + f->offset) = fv;
    return 0;
}

static int tp_set(const tp_field *f, PyObject *value, actag_track_params *p)
{
    int rc;
    Py_INCREF(value);
    rc = tp_set_owned(f, value, p);
    Py_DECREF(value);
    return rc;
}

/* actag_track_params from a dict (None: the defaults), each field checked by
 * the rule actag_tracker_init() applies (track.h), the bad one named. */
static int track_params_from_dict(PyObject *d, actag_track_params *p)
{
    PyObject *key, *value;
    Py_ssize_t pos = 0;
    actag_track_params_default(p);
    if (d == NULL || d == Py_None)
        return 0;
    if (!PyDict_Check(d)) {
        PyErr_SetString(PyExc_TypeError, "track parameters must be a dict");
        return -1;
    }
    while (PyDict_Next(d, &pos, &key, &value)) {
        char *name;
        int i;
        if (!PyUnicode_Check(key)) {
            PyErr_SetString(PyExc_TypeError, "track parameter names must be strings");
            return -1;
        }
        name = pyactag_strdup(key);
        if (name == NULL)
            return -1;
        for (i = 0; i < TP_NFIELDS && strcmp(name, tp_fields[i].name) != 0; i++)
            ;
        if (i == TP_NFIELDS) {
            PyErr_Format(PyExc_TypeError,
                         "unknown track parameter '%s' (full_every, confirm_frames, "
                         "confirm_margin, max_missed, roi_scale, gate, smoothing, refind_after, "
                         "verify, report_coasting)",
                         name);
            free(name);
            return -1;
        }
        free(name);
        if (tp_set(&tp_fields[i], value, p) != 0)
            return -1;
    }
    return 0;
}

static PyObject *tracker_new(PyTypeObject *type, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"family", "params", "roi_params", "track_params", NULL};
    PyObject *family, *params = Py_None, *roi = Py_None, *tparams = Py_None;
    const actag_family *fam;
    actag_track_params tp;
    allocfunc alloc;
    trackobj *self;
    actag_error_detail d;
    int rc;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "O|OOO:Tracker", kwlist, &family, &params, &roi,
                                     &tparams))
        return NULL;
    fam = pyactag_family_of(family);
    if (fam == NULL)
        return NULL;
    if (track_params_from_dict(tparams, &tp) != 0)
        return NULL;
    alloc = (allocfunc)PyType_GetSlot(type, Py_tp_alloc);
    self = (trackobj *)alloc(type, 0);
    if (self == NULL)
        return NULL;
    actag_params_default(&self->params);
    if (pyactag_params_from_dict(params, &self->params) != 0) {
        Py_DECREF(self);
        return NULL;
    }
    self->params.family = fam;
    rc = actag_params_validate(&self->params, &d);
    if (rc != ACTAG_OK) {
        Py_DECREF(self);
        return pyactag_raise_detail("invalid parameters", &d);
    }
    /* the ROI searches: the whole-frame parameters with the given changes */
    self->roi_params = self->params;
    if (roi != Py_None) {
        self->have_roi = 1;
        if (pyactag_params_from_dict(roi, &self->roi_params) != 0) {
            Py_DECREF(self);
            return NULL;
        }
        self->roi_params.family = fam;
        if (self->roi_params.tag_size != self->params.tag_size) {
            PyObject *a = PyFloat_FromDouble((double)self->roi_params.tag_size);
            PyObject *b = PyFloat_FromDouble((double)self->params.tag_size);
            if (a != NULL && b != NULL)
                PyErr_Format(PyExc_ValueError,
                             "roi_params cannot change tag_size (got %S, the tracker's is %S): "
                             "the tags searched around tracks are the tracked ones",
                             a, b);
            Py_XDECREF(a);
            Py_XDECREF(b);
            Py_DECREF(self);
            return NULL;
        }
        rc = actag_params_validate(&self->roi_params, &d);
        if (rc != ACTAG_OK) {
            Py_DECREF(self);
            return pyactag_raise_detail("invalid roi_params", &d);
        }
    }
    Py_INCREF(family);
    self->family = family;
    self->tracker = (actag_tracker *)malloc(sizeof *self->tracker);
    if (self->tracker == NULL) {
        Py_DECREF(self);
        return PyErr_NoMemory();
    }
    rc = actag_tracker_init(self->tracker, &tp);
    if (rc != ACTAG_OK) { /* the checks above follow its rules: not expected */
        Py_DECREF(self);
        return pyactag_raise(rc, "actag_tracker_init");
    }
    return (PyObject *)self;
}

/* Cyclic GC, as the Detector (detector_type.c): the Family is the one
 * object a Tracker holds; a heap type's instances also visit their type. */
static int tracker_traverse(PyObject *o, visitproc visit, void *arg)
{
    Py_VISIT(Py_TYPE(o));
    Py_VISIT(((trackobj *)o)->family);
    return 0;
}

/* Drops the Family (both parameter sets point into it); the tracker state
 * and the workspace stay for dealloc. A cleared Tracker refuses update(). */
static int tracker_clear(PyObject *o)
{
    trackobj *self = (trackobj *)o;
    self->params.family = NULL;
    self->roi_params.family = NULL;
    Py_CLEAR(self->family);
    return 0;
}

static void tracker_dealloc(PyObject *o)
{
    trackobj *self = (trackobj *)o;
    PyTypeObject *tp = Py_TYPE(o);
    freefunc tfree = (freefunc)PyType_GetSlot(tp, Py_tp_free);
    PyObject_GC_UnTrack(o);
    tracker_clear(o);
    free(self->ws);
    self->ws = NULL;
    free(self->tracker);
    self->tracker = NULL;
    tfree(o);
    Py_DECREF(tp);
}

static int tracker_cleared(const trackobj *self)
{
    if (self->family != NULL)
        return 0;
    PyErr_SetString(PyExc_RuntimeError,
                    "Tracker: cleared by the garbage collector (it no longer has a family)");
    return 1;
}

static PyObject *xy4(const actag_point *p)
{
    return Py_BuildValue("((dd)(dd)(dd)(dd))", (double)p[0].x, (double)p[0].y, (double)p[1].x,
                         (double)p[1].y, (double)p[2].x, (double)p[2].y, (double)p[3].x,
                         (double)p[3].y);
}

/* (track_id, id, mirrored, confirmed, measured, hits, missed, age,
 *  ((x, y) x 4), ((range, azimuth) x 4), ((vx, vy) x 4), innovation,
 *  last detection) */
static PyObject *track_tuple(const void *item)
{
    const actag_track *t = (const actag_track *)item;
    PyObject *c = xy4(t->corners), *v = xy4(t->velocity), *last = pyactag_detection_tuple(&t->last);
    PyObject *polar = Py_BuildValue("((dd)(dd)(dd)(dd))", (double)t->range[0],
                                    (double)t->azimuth[0], (double)t->range[1],
                                    (double)t->azimuth[1], (double)t->range[2],
                                    (double)t->azimuth[2], (double)t->range[3],
                                    (double)t->azimuth[3]);
    if (c == NULL || v == NULL || last == NULL || polar == NULL) {
        Py_XDECREF(c);
        Py_XDECREF(v);
        Py_XDECREF(last);
        Py_XDECREF(polar);
        return NULL;
    }
    return Py_BuildValue("(kiOOOiiiNNNdN)", (unsigned long)t->track_id, t->id,
                         t->mirrored ? Py_True : Py_False, t->confirmed ? Py_True : Py_False,
                         t->measured ? Py_True : Py_False, t->hits, t->missed, t->age, c, polar,
                         v, (double)t->innovation, last);
}

/* Every counter of actag_track_stats, by its C name (include/actag/track.h). */
static PyObject *track_stats_dict(const actag_track_stats *s)
{
    return Py_BuildValue("{sOsisLsisisisisisisisisi}", "full_frame",
                         s->full_frame ? Py_True : Py_False, "rois", s->rois, "pixels",
                         (long long)s->pixels, "readings", s->readings, "conflicts", s->conflicts,
                         "started", s->started, "confirmed", s->confirmed, "dropped", s->dropped,
                         "verified", s->verified, "quads", s->quads, "decoded", s->decoded,
                         "searched", s->searched);
}

static PyObject *tracker_update(PyObject *o, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"frame",           "min_range",         "max_range", "aperture",
                             "bearings",        "range_ascending",   "azimuth_ascending",
                             NULL};
    trackobj *self = (trackobj *)o;
    PyObject *frame_o, *aperture_o = Py_None, *bearings_o = Py_None;
    double min_range, max_range;
    int range_asc = 0, az_asc = 0, n;
    pyactag_frame_view view;
    actag_sonar_geometry geo;
    actag_track out[ACTAG_TRACK_MAX];
    actag_track_stats st;
    float *bearings = NULL;
    size_t need;
    PyObject *list = NULL, *result = NULL;

    if (!PyArg_ParseTupleAndKeywords(args, kwds, "Odd|OOpp:update", kwlist, &frame_o, &min_range,
                                     &max_range, &aperture_o, &bearings_o, &range_asc, &az_asc))
        return NULL;
    if (tracker_cleared(self))
        return NULL;
    if (pyactag_geometry_head(min_range, max_range, aperture_o, bearings_o, range_asc, az_asc,
                              &geo) != 0)
        return NULL;
    /* claimed before anything that may run Python code (the frame's
     * __array_interface__, a bearings iterator) and so let another thread in */
    if (self->busy) {
        PyErr_SetString(PyExc_RuntimeError,
                        "Tracker.update: another thread is updating this tracker (a tracker "
                        "follows one stream: give each stream its own)");
        return NULL;
    }
    self->busy = 1;
    memset(&view, 0, sizeof view);
    if (pyactag_frame_get(frame_o, &view) != 0) {
        self->busy = 0;
        return NULL;
    }
    if (bearings_o != Py_None) {
        bearings = pyactag_read_bearings(bearings_o, view.frame.cols);
        if (bearings == NULL)
            goto done;
        geo.bearings = bearings;
    }
    need = actag_workspace_size(view.frame.rows, view.frame.cols);
    if (need > self->ws_size) {
        void *w = malloc(need);
        if (w == NULL) {
            PyErr_NoMemory();
            goto done;
        }
        free(self->ws);
        self->ws = w;
        self->ws_size = need;
    }
    memset(&st, 0, sizeof st);
    Py_BEGIN_ALLOW_THREADS
    n = actag_tracker_update(self->tracker, &view.frame, &geo, &self->params,
                             self->have_roi ? &self->roi_params : NULL, self->ws,
                             self->ws_size, out, ACTAG_TRACK_MAX, &st);
    Py_END_ALLOW_THREADS
    self->frames = self->tracker->frame; /* read with the GIL by the frame getter */
    if (n < 0) {
        /* the frame's and the geometry's errors come from actag_check, with
         * the whole-frame parameters or else the ROI ones (track.h) */
        actag_error_detail d;
        if (self->have_roi &&
            actag_check(&view.frame, &geo, &self->params, self->ws_size, ACTAG_TRACK_MAX, &d) !=
                n &&
            actag_check(&view.frame, &geo, &self->roi_params, self->ws_size, ACTAG_TRACK_MAX,
                        &d) == n)
            pyactag_raise_detail("Tracker.update, roi_params", &d);
        else
            pyactag_raise_call(n, "Tracker.update", &view.frame, &geo, &self->params,
                               self->ws_size, ACTAG_TRACK_MAX);
        goto done;
    }
    list = pyactag_list_of(out, sizeof out[0], n, track_tuple);
    if (list == NULL)
        goto done;
    {
        PyObject *sd = track_stats_dict(&st);
        if (sd == NULL)
            goto done;
        result = Py_BuildValue("(NN)", list, sd);
        list = NULL;
    }
done:
    self->busy = 0;
    Py_XDECREF(list);
    free(bearings);
    pyactag_frame_release(&view);
    return result;
}

static PyObject *get_frame(PyObject *o, void *c)
{
    (void)c;
    return PyLong_FromLong(((trackobj *)o)->frames);
}

static PyObject *get_track_params(PyObject *o, void *c)
{
    const actag_track_params *p = &((trackobj *)o)->tracker->params;
    (void)c;
    return Py_BuildValue("{sisisdsisdsdsdsisisi}", "full_every", p->full_every,
                         "confirm_frames", p->confirm_frames, "confirm_margin",
                         (double)p->confirm_margin, "max_missed", p->max_missed, "roi_scale",
                         (double)p->roi_scale, "gate", (double)p->gate, "smoothing",
                         (double)p->smoothing, "refind_after", p->refind_after, "verify",
                         p->verify, "report_coasting", p->report_coasting);
}

static PyObject *get_params(PyObject *o, void *c)
{
    (void)c;
    return pyactag_params_to_dict(&((trackobj *)o)->params);
}

static PyObject *get_roi_params(PyObject *o, void *c)
{
    (void)c;
    return pyactag_params_to_dict(&((trackobj *)o)->roi_params);
}

static PyObject *get_family(PyObject *o, void *c)
{
    trackobj *self = (trackobj *)o;
    (void)c;
    if (tracker_cleared(self))
        return NULL;
    Py_INCREF(self->family);
    return self->family;
}

static PyGetSetDef tracker_getset[] = {
    {"frame", get_frame, NULL, "frames fed so far (failed ones included)", NULL},
    {"track_params", get_track_params, NULL, "the actag_track_params as a dict (a copy)", NULL},
    {"params", get_params, NULL, "the whole-frame parameters as a dict (a copy)", NULL},
    {"roi_params", get_roi_params, NULL, "the ROI searches' parameters as a dict (a copy)", NULL},
    {"family", get_family, NULL, "the Family", NULL},
    {NULL, NULL, NULL, NULL, NULL}};

static PyMethodDef tracker_methods[] = {
    {"update", (PyCFunction)(void (*)(void))tracker_update, METH_VARARGS | METH_KEYWORDS,
     "update(frame, min_range, max_range, aperture=None, bearings=None, range_ascending=False,\n"
     "       azimuth_ascending=False)\n"
     "-> (list of (track_id, id, mirrored, confirmed, measured, hits, missed, age,\n"
     "             ((x, y) x 4), ((range, azimuth) x 4), ((vx, vy) x 4), innovation,\n"
     "             last detection),\n"
     "    stats dict)"},
    {NULL, NULL, 0, NULL}};

static PyType_Slot tracker_slots[] = {
    {Py_tp_new, (void *)tracker_new},
    {Py_tp_dealloc, (void *)tracker_dealloc},
    {Py_tp_traverse, (void *)tracker_traverse},
    {Py_tp_clear, (void *)tracker_clear},
    {Py_tp_getset, tracker_getset},
    {Py_tp_methods, tracker_methods},
    {Py_tp_doc, (void *)"Tracker(family, params=None, roi_params=None, track_params=None): "
                        "an actag_tracker and its workspace."},
    {0, NULL}};

static PyType_Spec tracker_spec = {"pyactag._core.Tracker", sizeof(trackobj), 0,
                                   Py_TPFLAGS_DEFAULT | Py_TPFLAGS_HAVE_GC, tracker_slots};

PyObject *pyactag_tracker_type_create(PyObject *module)
{
    (void)module;
    return PyType_FromSpec(&tracker_spec);
}
