/*
 * family_type.c -- pyactag._core.Family: a built-in family (actag_family_get)
 * or one made from caller-supplied codes (copied and owned here), with the
 * family matcher and the tag renderer of render.h.
 */
#include "pyactag.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef pyactag_family_object famobj;

/* The object's real type, not isinstance(): isinstance() believes a
 * __class__ attribute (unittest.mock.Mock(spec=Family), a proxy), and such an
 * object has no actag_family inside it to read. */
const actag_family *pyactag_family_of(PyObject *obj)
{
    if (!PyObject_TypeCheck(obj, (PyTypeObject *)pyactag_family_type)) {
        PyErr_Format(PyExc_TypeError, "family must be a pyactag.Family, not %R (type %R)", obj,
                     (PyObject *)Py_TYPE(obj));
        return NULL;
    }
    return &((famobj *)obj)->fam;
}

static PyObject *family_new(PyTypeObject *type, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"name", "codes", "bits", "hamming", "mirror", "excluded", NULL};
    PyObject *name_o, *codes_o = Py_None, *excluded_o = Py_None;
    int bits = 0, hamming = 0, mirror = 0;
    uint32_t excluded = 0;
    allocfunc alloc;
    famobj *self;
    int rc;

    if (!PyArg_ParseTupleAndKeywords(args, kwds, "U|OiiiO:Family", kwlist, &name_o, &codes_o,
                                     &bits, &hamming, &mirror, &excluded_o))
        return NULL;
    if (PyUnicode_FindChar(name_o, 0, 0, PyUnicode_GetLength(name_o), 1) != -1) {
        if (!PyErr_Occurred()) /* C would cut the name at the NUL */
            PyErr_Format(PyExc_ValueError, "family name %R contains a NUL character", name_o);
        return NULL;
    }
    alloc = (allocfunc)PyType_GetSlot(type, Py_tp_alloc);
    self = (famobj *)alloc(type, 0);
    if (self == NULL)
        return NULL;
    self->codes_owned = NULL;
    self->name_owned = pyactag_strdup(name_o);
    if (self->name_owned == NULL) {
        Py_DECREF(self);
        return NULL;
    }
    if (codes_o == Py_None) {
        if (bits || hamming || mirror || excluded_o != Py_None) {
            PyErr_SetString(PyExc_TypeError,
                            "bits, hamming, mirror and excluded describe caller-supplied codes; "
                            "a built-in family takes only its name");
            Py_DECREF(self);
            return NULL;
        }
        rc = actag_family_get(self->name_owned, &self->fam);
        if (rc != ACTAG_OK) {
            int i;
            char list[512];
            size_t len = 0;
            list[0] = '\0';
            for (i = 0; i < actag_family_count(); i++) {
                actag_family f;
                if (actag_family_get_at(i, &f) == ACTAG_OK && len + strlen(f.name) + 3 < sizeof list)
                    len += (size_t)snprintf(list + len, sizeof list - len, "%s%s", i ? ", " : "",
                                            f.name);
            }
            {
                PyObject *msg = PyUnicode_FromFormat(
                    "unknown family '%s': %s (%s); built in: %s", self->name_owned,
                    actag_strerror(rc), pyactag_code_name(rc), list);
                if (msg != NULL) {
                    pyactag_raise_message(rc, msg);
                    Py_DECREF(msg);
                }
            }
            Py_DECREF(self);
            return NULL;
        }
        self->fam.name = self->name_owned; /* same text; ours lives as long as self */
        return (PyObject *)self;
    } else {
        PyObject *it, *item;
        Py_ssize_t n, i = 0;
        n = PyObject_Length(codes_o);
        if (n < 0) {
            Py_DECREF(self);
            return NULL;
        }
        if (n < 1 || n > 0x7fffffff) {
            PyErr_SetString(PyExc_ValueError, "a family needs at least one code");
            Py_DECREF(self);
            return NULL;
        }
        if (bits % 4 != 0 || bits < 16 || bits > 32) {
            PyErr_Format(PyExc_ValueError, "bits must be a multiple of 4 from 16 to 32, not %d",
                         bits);
            Py_DECREF(self);
            return NULL;
        }
        if (mirror != ACTAG_MIRROR_REVERSE && mirror != ACTAG_MIRROR_PHYSICAL) {
            PyErr_SetString(PyExc_ValueError, "mirror must be 0 (reverse) or 1 (physical)");
            Py_DECREF(self);
            return NULL;
        }
        if (excluded_o != Py_None &&
            pyactag_code_arg(excluded_o, "excluded", bits, &excluded) != 0) {
            Py_DECREF(self);
            return NULL;
        }
        self->codes_owned = (uint32_t *)malloc((size_t)n * sizeof(uint32_t));
        if (self->codes_owned == NULL) {
            Py_DECREF(self);
            return PyErr_NoMemory();
        }
        it = PyObject_GetIter(codes_o);
        if (it == NULL) {
            Py_DECREF(self);
            return NULL;
        }
        while ((item = PyIter_Next(it)) != NULL) {
            char what[40];
            uint32_t c = 0;
            int bad;
            snprintf(what, sizeof what, "codes[%zd]", i);
            bad = i >= n || pyactag_code_arg(item, what, bits, &c) != 0;
            Py_DECREF(item);
            if (bad) {
                Py_DECREF(it);
                if (!PyErr_Occurred())
                    PyErr_SetString(PyExc_ValueError, "codes changed length while being read");
                Py_DECREF(self);
                return NULL;
            }
            self->codes_owned[i++] = c;
        }
        Py_DECREF(it);
        if (PyErr_Occurred() || i != n) {
            if (!PyErr_Occurred())
                PyErr_SetString(PyExc_ValueError, "codes changed length while being read");
            Py_DECREF(self);
            return NULL;
        }
        self->fam.name = self->name_owned;
        self->fam.bits = bits;
        self->fam.hamming = hamming;
        self->fam.ncodes = (int)n;
        self->fam.codes = self->codes_owned;
        self->fam.mirror = mirror;
        self->fam.excluded = excluded;
        rc = actag_family_validate(&self->fam);
        if (rc != ACTAG_OK) {
            Py_DECREF(self);
            return pyactag_raise(rc, "Family");
        }
        return (PyObject *)self;
    }
}

static void family_dealloc(PyObject *o)
{
    famobj *self = (famobj *)o;
    PyTypeObject *tp = Py_TYPE(o);
    freefunc tfree = (freefunc)PyType_GetSlot(tp, Py_tp_free);
    free(self->codes_owned);
    free(self->name_owned);
    tfree(o);
    Py_DECREF(tp);
}

static PyObject *family_repr(PyObject *o)
{
    famobj *self = (famobj *)o;
    return PyUnicode_FromFormat("Family('%s', bits=%d, hamming=%d, ncodes=%d%s)", self->fam.name,
                                self->fam.bits, self->fam.hamming, self->fam.ncodes,
                                self->codes_owned ? ", custom" : "");
}

static Py_ssize_t family_len(PyObject *o) { return ((famobj *)o)->fam.ncodes; }

/* ---------------------------------------------------------------- getters */

static PyObject *get_name(PyObject *o, void *c)
{
    (void)c;
    return PyUnicode_FromString(((famobj *)o)->fam.name);
}
static PyObject *get_bits(PyObject *o, void *c)
{
    (void)c;
    return PyLong_FromLong(((famobj *)o)->fam.bits);
}
static PyObject *get_hamming(PyObject *o, void *c)
{
    (void)c;
    return PyLong_FromLong(((famobj *)o)->fam.hamming);
}
static PyObject *get_ncodes(PyObject *o, void *c)
{
    (void)c;
    return PyLong_FromLong(((famobj *)o)->fam.ncodes);
}
static PyObject *get_mirror(PyObject *o, void *c)
{
    (void)c;
    return PyLong_FromLong(((famobj *)o)->fam.mirror);
}
static PyObject *get_excluded(PyObject *o, void *c)
{
    (void)c;
    return PyLong_FromUnsignedLong(((famobj *)o)->fam.excluded);
}
static PyObject *get_builtin(PyObject *o, void *c)
{
    (void)c;
    return PyBool_FromLong(((famobj *)o)->codes_owned == NULL);
}
static PyObject *get_max_corrections(PyObject *o, void *c)
{
    (void)c;
    return PyLong_FromLong(actag_family_max_corrections(&((famobj *)o)->fam));
}
static PyObject *get_codes(PyObject *o, void *c)
{
    famobj *self = (famobj *)o;
    PyObject *t = PyTuple_New(self->fam.ncodes);
    int i;
    (void)c;
    if (t == NULL)
        return NULL;
    for (i = 0; i < self->fam.ncodes; i++) {
        PyObject *v = PyLong_FromUnsignedLong(self->fam.codes[i]);
        if (v == NULL) {
            Py_DECREF(t);
            return NULL;
        }
        PyTuple_SetItem(t, i, v);
    }
    return t;
}

static PyGetSetDef family_getset[] = {
    {"name", get_name, NULL, "family name, e.g. 'AcTag24h10'", NULL},
    {"bits", get_bits, NULL, "data bits (4k)", NULL},
    {"hamming", get_hamming, NULL, "minimum Hamming distance the family guarantees", NULL},
    {"ncodes", get_ncodes, NULL, "number of codes (IDs 0 .. ncodes-1)", NULL},
    {"codes", get_codes, NULL, "the codes in ID order (MSB = top-left cell as printed)", NULL},
    {"mirror", get_mirror, NULL,
     "mirror rule of the distance: 0 full bit reversal (published), 1 physical reflection", NULL},
    {"excluded", get_excluded, NULL, "code bits the distance does not count (0: none)", NULL},
    {"builtin", get_builtin, NULL, "True for a family compiled into libactag", NULL},
    {"max_corrections", get_max_corrections, NULL,
     "most bit corrections the family supports (h/2 - 1 for even h, floor(h/2) for odd h)",
     NULL},
    {NULL, NULL, NULL, NULL, NULL}};

/* ---------------------------------------------------------------- methods */

static PyObject *family_match(PyObject *o, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"word", "max_corrections", "rotations_only", NULL};
    famobj *self = (famobj *)o;
    PyObject *word_o, *maxc_o = NULL, *rot_o = NULL;
    uint32_t word;
    int maxc = -1, rot_only = 0, rc;
    actag_match m;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "O|OO:match", kwlist, &word_o, &maxc_o, &rot_o))
        return NULL;
    /* checked, not converted: "False" is no bool, True no count */
    if (rot_o != NULL) {
        if (!pyactag_is_bool(rot_o)) {
            PyErr_Format(PyExc_TypeError, "rotations_only must be a bool, got %R", rot_o);
            return NULL;
        }
        rot_only = PyObject_IsTrue(rot_o);
    }
    if (maxc_o != NULL) {
        long v;
        PyObject *ix = pyactag_is_bool(maxc_o) ? NULL : PyNumber_Index(maxc_o); /* numpy ints too */
        if (ix == NULL) {
            PyErr_Clear();
            PyErr_Format(PyExc_TypeError, "max_corrections must be an integer, got %R", maxc_o);
            return NULL;
        }
        v = PyLong_AsLong(ix);
        Py_DECREF(ix);
        if (v == -1 && PyErr_Occurred())
            return NULL;
        if (v < -1 || v > 32) {
            PyErr_Format(PyExc_ValueError, "max_corrections must be -1 (the family's limit) .. 32, "
                         "got %ld", v);
            return NULL;
        }
        maxc = (int)v;
    }
    if (pyactag_code_arg(word_o, "word", self->fam.bits, &word) != 0)
        return NULL;
    if (maxc < 0)
        maxc = actag_family_max_corrections(&self->fam);
    rc = rot_only ? actag_family_match_rotations(&self->fam, word, maxc, &m)
                  : actag_family_match(&self->fam, word, maxc, &m);
    if (rc == ACTAG_ERR_NO_MATCH)
        Py_RETURN_NONE;
    if (rc != ACTAG_OK)
        return pyactag_raise(rc, "Family.match");
    return Py_BuildValue("{sisisOsi}", "id", m.id, "rotation", m.rotation, "mirrored",
                         m.mirrored ? Py_True : Py_False, "hamming", m.hamming);
}

static PyObject *family_render(PyObject *o, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"id", "cell_px", "margin_px", "margin_value", "camera", NULL};
    famobj *self = (famobj *)o;
    int id, cell = 10, margin = 0, mvalue = 255, camera = 0, side, rc;
    PyObject *bytes;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "i|iiip:render", kwlist, &id, &cell, &margin,
                                     &mvalue, &camera))
        return NULL;
    side = actag_render_side(self->fam.bits, cell, margin);
    if (side < 0)
        return pyactag_raise(side, "render");
    bytes = PyBytes_FromStringAndSize(NULL, (Py_ssize_t)side * side);
    if (bytes == NULL)
        return NULL;
    rc = actag_render_tag(&self->fam, id, cell, margin, mvalue, camera,
                          (uint8_t *)PyBytes_AsString(bytes), side, (size_t)side * (size_t)side);
    if (rc != ACTAG_OK) {
        Py_DECREF(bytes);
        return pyactag_raise(rc, "render");
    }
    return Py_BuildValue("(Ni)", bytes, side);
}

static PyObject *family_layout_cell(PyObject *o, PyObject *args)
{
    famobj *self = (famobj *)o;
    int id, x, y, rc;
    if (!PyArg_ParseTuple(args, "iii:layout_cell", &id, &x, &y))
        return NULL;
    rc = actag_layout_cell(&self->fam, id, x, y);
    if (rc < 0)
        return pyactag_raise(rc, "layout_cell");
    return PyLong_FromLong(rc);
}

static PyObject *family_corner_tabs(PyObject *o, PyObject *args)
{
    famobj *self = (famobj *)o;
    int id, rc;
    if (!PyArg_ParseTuple(args, "i:corner_tabs", &id))
        return NULL;
    rc = actag_layout_corner_tabs(&self->fam, id);
    if (rc < 0)
        return pyactag_raise(rc, "corner_tabs");
    return PyLong_FromLong(rc);
}

static PyMethodDef family_methods[] = {
    {"match", (PyCFunction)(void (*)(void))family_match, METH_VARARGS | METH_KEYWORDS,
     "match(word, max_corrections=-1, rotations_only=False) -> dict or None\n"
     "Closest code to an observed bit word in the 8 orientations (4 with rotations_only):\n"
     "{'id', 'rotation', 'mirrored', 'hamming'}; max_corrections -1: the family maximum."},
    {"_render", (PyCFunction)(void (*)(void))family_render, METH_VARARGS | METH_KEYWORDS,
     "_render(id, cell_px=10, margin_px=0, margin_value=255, camera=False) -> (bytes, side)"},
    {"layout_cell", family_layout_cell, METH_VARARGS,
     "layout_cell(id, x, y) -> 1 (white, foam) or 0 (black, aluminium); grid cell (x, y), "
     "0 <= x, y <= bits/4, x to the right, y down, as printed"},
    {"corner_tabs", family_corner_tabs, METH_VARARGS,
     "corner_tabs(id) -> OR of CORNER_TOP_LEFT (1), _TOP_RIGHT (2), _BOTTOM_RIGHT (4), "
     "_BOTTOM_LEFT (8): face-plate corners that need a small metal tab"},
    {NULL, NULL, 0, NULL}};

static PyType_Slot family_slots[] = {
    {Py_tp_new, (void *)family_new},
    {Py_tp_dealloc, (void *)family_dealloc},
    {Py_tp_repr, (void *)family_repr},
    {Py_tp_getset, family_getset},
    {Py_tp_methods, family_methods},
    {Py_sq_length, (void *)family_len},
    {Py_tp_doc, (void *)"Family(name) -> a built-in family; "
                        "Family(name, codes, bits, hamming, mirror=0, excluded=0) -> caller codes."},
    {0, NULL}};

static PyType_Spec family_spec = {"pyactag._core.Family", sizeof(famobj), 0,
                                  Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE, family_slots};

PyObject *pyactag_family_type_create(PyObject *module)
{
    (void)module;
    return PyType_FromSpec(&family_spec);
}
