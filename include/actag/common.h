/*
 * actag/common.h -- types and error codes shared by every actag header.
 *
 * MANUAL
 *   Every actag function that can fail returns an int: 0 (ACTAG_OK) or a
 *   positive count on success, a negative ACTAG_ERR_* code on failure.
 *   actag_strerror() turns a code into a one-line English message.
 *
 *   Image coordinates: x is the column, y is the row, both in pixels, with
 *   the centre of pixel (row r, column c) at (x, y) = (c, r).
 *
 *   The library never allocates: every buffer is owned by the caller.
 *   Nothing here keeps global or static mutable state; all functions are
 *   re-entrant.
 */
#ifndef ACTAG_COMMON_H
#define ACTAG_COMMON_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define ACTAG_VERSION_MAJOR 0
#define ACTAG_VERSION_MINOR 1
#define ACTAG_VERSION_PATCH 0
#define ACTAG_VERSION_STRING "0.1.0"

/* Largest image side (rows or columns) any stage accepts: coordinates are
 * stored as int16_t in contour buffers. */
#define ACTAG_MAX_DIM 32767

/* Error codes (negative). */
#define ACTAG_OK 0
#define ACTAG_ERR_NULL (-1)        /* a required pointer is NULL */
#define ACTAG_ERR_SIZE (-2)        /* zero, negative or too large image size, or stride < cols */
#define ACTAG_ERR_PARAM (-3)       /* a parameter is out of range */
#define ACTAG_ERR_GEOMETRY (-4)    /* sonar geometry is invalid (ranges, aperture, bearings) */
#define ACTAG_ERR_WORKSPACE (-5)   /* the workspace is too small for this frame */
#define ACTAG_ERR_FAMILY (-6)      /* unknown or invalid tag family */
#define ACTAG_ERR_CORRECTIONS (-7) /* more bit corrections than the family allows */
#define ACTAG_ERR_NO_MATCH (-8)    /* nothing matched (decoder, family matcher) */
#define ACTAG_ERR_OVERFLOW (-9)    /* a bounded buffer was too small */
#define ACTAG_ERR_NO_QUAD (-10)    /* no quadrilateral could be fitted */

/* A 2-D point in image coordinates (pixels, sub-pixel). */
typedef struct actag_point {
    float x; /* column */
    float y; /* row */
} actag_point;

/* An integer contour point (pixels). */
typedef struct actag_ipoint {
    int16_t x; /* column */
    int16_t y; /* row */
} actag_ipoint;

/* One-line English description of an ACTAG_* code; never NULL. */
const char *actag_strerror(int code);

#ifdef __cplusplus
}
#endif
#endif /* ACTAG_COMMON_H */
