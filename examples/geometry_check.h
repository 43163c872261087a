/*
 * geometry_check.h -- actag_detect --check-geometry: is the sonar geometry
 * (aperture, range scale) and the tag size given to the detector the one
 * the frames were taken with?
 *
 * A tag's four corners, with the geometry and the tag size, must be those of
 * a square of that size seen by the sonar; the pose fit's chi2 (pose.h: 8
 * corner residuals at the assumed corner noise, about 3 expected) says how
 * far they are from it, without any truth. The check collects the reported
 * tags of all files, takes the median chi2 at the given geometry, and scans
 * two one-parameter changes for the least median chi2: every azimuth scaled
 * by k (a wrong aperture or bearing table) and the tag size scaled by k (a
 * wrong tag size, or a wrong range scale). They are alternatives, not two
 * findings: the corners fix the tag's extent in azimuth against its extent
 * in range and its size, so one of aperture, tag size and range scale can be
 * found given the other two, and each scan alone fits any of the three
 * errors. The pool recording of ../shared, at its published 60 degrees and
 * 0.1306 m, gives a median chi2 of 50.7, least (0.20) at azimuths x 0.923
 * (55.4 degrees), or (0.43) with a tag 8 % larger (docs/pose.md). The plane
 * of --pose is left out (the corners alone are judged). About 200 pose fits
 * a tag, 12 ms on a desktop core.
 */
#ifndef ACTAG_EXAMPLES_GEOMETRY_CHECK_H
#define ACTAG_EXAMPLES_GEOMETRY_CHECK_H

#include "actag/actag.h"
#include "actag/pose.h"

/* The range of k scanned (0.005 steps, then 0.001 around the least). */
#define GC_SCALE_MIN 0.80
#define GC_SCALE_MAX 1.25

typedef struct gc_tag {
    float range[4], azimuth[4];
    int mirrored;
} gc_tag;

/* The tags collected so far (heap; this is a host tool). */
typedef struct gc_tags {
    gc_tag *tag;
    int n, cap;
} gc_tags;

typedef struct gc_result {
    int tags;            /* tags collected */
    int fitted;          /* of them with a pose at the given geometry */
    double chi2;         /* median chi2 at the given geometry */
    double az_scale;     /* k for the azimuths with the least median chi2 ... */
    double az_chi2;      /* ... and that median */
    double size_scale;   /* k for the tag size with the least median chi2 ... */
    double size_chi2;    /* ... and that median */
    int az_edge, size_edge; /* 1 when the least lies at an end of the scan */
} gc_result;

/* gc_check's failures */
#define GC_NO_TAG (-1)    /* no tag, or none with a pose at the given geometry */
#define GC_NO_MEMORY (-2)

/* Adds detections det[0..n-1], all or none; returns 0, or GC_NO_MEMORY. */
int gc_add(gc_tags *t, const actag_detection *det, int n);

/* Median chi2 at the given pose parameters and the two scans. Returns 0,
 * GC_NO_TAG (r->tags, r->fitted say which) or GC_NO_MEMORY. */
int gc_check(const gc_tags *t, const actag_pose_params *pp, gc_result *r);

void gc_free(gc_tags *t);

#endif
