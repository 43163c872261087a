/*
 * pyactag.h -- declarations shared by the files of the pyactag._core extension.
 *
 * The extension is built against the CPython limited API of 3.9 (abi3), so
 * one binary serves every CPython >= 3.9. Files:
 *   module.c        module init, ActagError, small module functions
 *   params.c        actag_params <-> Python dict (the one place that knows
 *                   the parameter names)
 *   frame.c         a Python 2-D uint8/uint16 buffer -> actag_frame
 *   family_type.c   the Family type (built-in or caller-supplied codes)
 *   detector_type.c the Detector type (parameters, workspace, detection)
 *   pose.c          sonar_pose (actag_pose_estimate), camera_pose
 *                   (actag_pose_from_camera, actag_pose_camera_covariance)
 *   geometry.c      the sonar geometry arguments of Detector and Tracker
 *   tracker_type.c  the Tracker type (actag/track.h state, workspace)
 *
 * The core library never allocates; the workspace, the output array and any
 * frame copy belong to this extension (malloc/free).
 */
#ifndef PYACTAG_H
#define PYACTAG_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include "actag/actag.h"
#include "actag/render.h"
#include "actag/version.h"

/* Most detections one call returns (pyactag._core.MAX_DETECTIONS). */
#define PYACTAG_MAX_DETECTIONS 4096

/* Module state shared by the types (one interpreter; the types are heap types). */
extern PyObject *pyactag_error;      /* pyactag.ActagError (a ValueError) */
extern PyObject *pyactag_family_type; /* pyactag._core.Family */

/* Raise ActagError for a negative ACTAG_ERR_* code: "<context>: <library
 * message> (ACTAG_ERR_NAME)", with attributes code and name. Returns NULL. */
PyObject *pyactag_raise(int code, const char *context);

/* Raise ActagError for a failed check with its detail (actag_check and the
 * validators): "<context>: <field> <rule> (got <value>): <library message>
 * (ACTAG_ERR_NAME)", the field in Python's names (quad_inlier_ratio,
 * min_range, bearings[7]), with attributes code, name and field. Returns NULL. */
PyObject *pyactag_raise_detail(const char *context, const actag_error_detail *d);

/* Raise ActagError(msg) with attributes code and name. Returns NULL. */
PyObject *pyactag_raise_message(int code, PyObject *msg);

/* Name of an ACTAG_* code ("ACTAG_ERR_PARAM"), or "ACTAG_ERR_UNKNOWN". */
const char *pyactag_code_name(int code);

/* A Python str -> new UTF-8 copy (malloc); NULL with an exception set
 * (ValueError for a str holding a NUL character, which C would cut there). */
char *pyactag_strdup(PyObject *str);

/* 1 when obj is a bool or a numpy bool (numpy.bool_), which Python would
 * take as the number 0 or 1; else 0 (never an exception). */
int pyactag_is_bool(PyObject *obj);

/* 1 when a finite d would not survive narrowing to a C float: beyond
 * FLT_MAX (inf) or nonzero below the least subnormal (0); else 0 (NaN and
 * infinities included: the library names those). */
int pyactag_float_overflows(double d);

/* A code word argument (a Python integer, not bool or float) that fits in
 * `bits` bits: TypeError or ValueError naming `name` and the value, never
 * reduced modulo 2**64. Returns 0, or -1 with an exception. */
int pyactag_code_arg(PyObject *obj, const char *name, int bits, uint32_t *out);

/* ---------------------------------------------------------------- params.c */

/* Fill *p from a dict of keyword arguments (None or empty: nothing changes).
 * Names are those of pyactag_params_to_dict(); unknown names, wrong types and
 * values out of the C type's range raise TypeError/ValueError/OverflowError.
 * The family pointer is not touched. Returns 0, or -1 with an exception. */
int pyactag_params_from_dict(PyObject *kwargs, actag_params *p);

/* New dict of every parameter of *p by name (family excluded). */
PyObject *pyactag_params_to_dict(const actag_params *p);

/* New tuple of the names of the actag_params.tuning fields (the rest are the
 * user settings: tag_size, max_bit_corrections, seed, min_margin). */
PyObject *pyactag_tuning_names(void);

/* ----------------------------------------------------------------- frame.c */

typedef struct pyactag_frame_view {
    actag_frame frame; /* what actag_detect reads */
    PyObject *keep;    /* reference that keeps the pixels alive, or NULL */
    void *copy;        /* our contiguous copy (malloc), or NULL */
    int copied;        /* 1 when the pixels were copied (non-contiguous, swapped...) */
} pyactag_frame_view;

/* Describe a 2-D uint8/uint16 object as an actag_frame: zero-copy through
 * __array_interface__ when rows are contiguous in memory (numpy arrays and
 * their row-strided views), otherwise a copy; any other object through the
 * buffer protocol (memoryview). Returns 0, or -1 with TypeError/ValueError. */
int pyactag_frame_get(PyObject *obj, pyactag_frame_view *v);

/* Release what pyactag_frame_get() took (safe on a zeroed view). */
void pyactag_frame_release(pyactag_frame_view *v);

/* ----------------------------------------------------------- family_type.c */

typedef struct pyactag_family_object {
    PyObject_HEAD
    actag_family fam;
    uint32_t *codes_owned; /* caller-supplied codes (malloc), or NULL */
    char *name_owned;      /* its name (malloc), or NULL */
} pyactag_family_object;

/* Create the Family type; returns a new reference or NULL. */
PyObject *pyactag_family_type_create(PyObject *module);

/* The actag_family of a Family instance, or NULL with TypeError. */
const actag_family *pyactag_family_of(PyObject *obj);

/* --------------------------------------------------------- detector_type.c */

/* Create the Detector type; returns a new reference or NULL. */
PyObject *pyactag_detector_type_create(PyObject *module);

/* -------------------------------------------------------------- geometry.c */

/* The geometry of one call without its bearing table: aperture (a number,
 * radians) or bearings given, not both; azimuth_ascending not with
 * bearings; values a float cannot hold are OverflowErrors naming them.
 * Fills *geo (bearings NULL). Returns 0, or -1 with an exception. */
int pyactag_geometry_head(double min_range, double max_range, PyObject *aperture_o,
                          PyObject *bearings_o, int range_asc, int az_asc,
                          actag_sonar_geometry *geo);

/* A bearing table: an iterable of exactly `cols` real numbers (radians) ->
 * a new float array (malloc; free() it), or NULL with an exception naming
 * bearings[i] or the count. */
float *pyactag_read_bearings(PyObject *obj, int cols);

/* --------------------------------------------------------- detector_type.c */

/* One detection as detect() returns it: (id, hamming, mirrored,
 * decision_margin, inlier_ratio, ((x, y) x 4), ((range, azimuth) x 4)). */
PyObject *pyactag_detection_tuple(const actag_detection *d);

/* A new list of the n items (size bytes each) converted by conv, or NULL
 * with an exception. */
PyObject *pyactag_list_of(const void *items, size_t size, int n, PyObject *(*conv)(const void *));

/* Raise the error n (< 0) of a call on this frame, geometry and parameters:
 * with actag_check's detail (the field named) when it finds the same code,
 * else the code alone (pyactag_raise). Returns NULL. */
PyObject *pyactag_raise_call(int n, const char *context, const actag_frame *frame,
                             const actag_sonar_geometry *geometry, const actag_params *params,
                             size_t workspace_size, int max_out);

/* ---------------------------------------------------------- tracker_type.c */

/* Create the Tracker type; returns a new reference or NULL. */
PyObject *pyactag_tracker_type_create(PyObject *module);

/* ------------------------------------------------------------------ pose.c */

/* _core.sonar_pose (pose.c has the arguments); METH_VARARGS. */
PyObject *pyactag_sonar_pose(PyObject *self, PyObject *args);

/* _core.camera_pose (pose.c has the arguments); METH_VARARGS. */
PyObject *pyactag_camera_pose(PyObject *self, PyObject *args);

#endif /* PYACTAG_H */
