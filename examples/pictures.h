/*
 * pictures.h -- actag_detect's pictures: the overlay (polar frame and fan
 * beside it, with a legend) and the stage images (host only).
 *
 * MANUAL
 *   Coordinates: image positions are x = column, y = row (pixels, pixel
 *   centres at integers), as everywhere in actag.
 *
 *   Candidates come from actag_detect_traced() (actag/trace.h): pass
 *   pic_trace_event as the callback and a pic_trace as its user pointer;
 *   the trace keeps every search position and quad (and, when asked, every
 *   contour's points) of one frame. pic_trace_clear() readies it for the
 *   next frame. Memory errors set trace.oom (the pictures then lack
 *   candidates; detection is unaffected).
 *
 *   pic_overlay(path, frame, show_rejected, err) writes one PPM (P6):
 *     left   the polar frame as stored (x = column, y = row), with each tag's
 *            edges (green), corner 0 = the top-left corner as printed (red),
 *            corners 1-3 clockwise as printed (orange, numbered), the sampled
 *            data bits (yellow = read 1, blue = read 0) and a label "#n ID i";
 *     right  the same frame as a fan (Cartesian, metres to scale): the sonar
 *            at the bottom, forward up, positive azimuth to the left (the
 *            reference's column 0 side), range arcs and bearing lines;
 *     bottom a legend: the colour key and, per tag, ID, hamming, decision
 *            margin, mirrored flag and its centre's range and azimuth.
 *     With show_rejected, the rejected candidates (quads, structure-search
 *     boxes and contour grid guesses that did not become detections) are
 *     drawn faintly in both views.
 *
 *   pic_stages(dir, stem, frame, err) writes every stage of the pipeline as
 *   DIR/STEM-N-NAME.EXT:
 *     1-input.pgm     the input as 8 bits (16-bit frames scaled by their
 *                     maximum, as the library does)
 *     2-median.pgm    the median-filtered frame
 *     3-search.ppm    the structure search's score map (grey = box contrast:
 *                     128 + (inner - ring mean), black = not searched), the
 *                     positions it decoded boxed (green kept, red rejected)
 *     4-binary.pgm    the adaptive threshold's output
 *     5-contours.ppm  every outer border: yellow passed the size filter,
 *                     red too small/large, magenta too long to store
 *     6-quads.ppm     every RANSAC quad: green decoded, red sides implausible,
 *                     orange no code, violet failed the structure/margin check;
 *                     the grid guesses from contours' extreme points likewise,
 *                     faintly
 *     7-decoded.ppm   each detection's cell grid through its corners: cells
 *                     filled with the decoded code's value (white 1, black 0),
 *                     ringed green where the binary frame agrees, red where
 *                     it does not, grey where the decoder does not read;
 *                     below the legend each tag (up to 4) enlarged
 *   The colour stages carry a legend strip below the frame (the frame keeps
 *   its pixel positions).
 *
 *   Both return 0, or -1 with a message naming the file in err
 *   (HOSTIO_ERRLEN bytes).
 */
#ifndef ACTAG_EXAMPLES_PICTURES_H
#define ACTAG_EXAMPLES_PICTURES_H

#include "actag/actag.h"

#include <stddef.h>

typedef struct pic_candidate {
    int kind, outcome;   /* ACTAG_TRACE_SEARCH, _QUAD or _GUESS; ACTAG_TRACE_* */
    actag_point quad[4]; /* as examined (image pixels) */
    int id;              /* decoded ID, or -1 */
} pic_candidate;

typedef struct pic_contour {
    int outcome;        /* ACTAG_TRACE_ACCEPTED (size ok), _SIZE or _OVERFLOW */
    size_t first;       /* index of its first point in pic_trace.points */
    int npoints;        /* stored points (0 on overflow) */
    int min_x, max_x, min_y, max_y;
} pic_contour;

typedef struct pic_trace {
    int keep_contours; /* store contour points too (for the stages) */
    pic_candidate *cand;
    int ncand, cap_cand;
    pic_contour *cont;
    int ncont, cap_cont;
    actag_ipoint *points;
    size_t npoints, cap_points;
    int oom;
} pic_trace;

void pic_trace_init(pic_trace *t, int keep_contours);
void pic_trace_clear(pic_trace *t);
void pic_trace_free(pic_trace *t);
void pic_trace_event(void *user, const actag_trace_event *e);

/* One processed frame, as the pictures need it. */
typedef struct pic_frame {
    const char *name;           /* shown in the legend */
    const uint8_t *input8;      /* rows x cols, 8-bit view of the input */
    const uint8_t *filtered;    /* actag_workspace_filtered() */
    const uint8_t *binary;      /* actag_workspace_bitmap(), unpacked: 0 black, 1 white */
    int rows, cols;
    const actag_sonar_geometry *geo;
    const actag_params *params; /* family, tag size, search settings */
    const actag_detection *det;
    int ndet;
    const pic_trace *trace;     /* may be NULL */
} pic_frame;

int pic_overlay(const char *path, const pic_frame *f, int show_rejected, char *err);
int pic_stages(const char *dir, const char *stem, const pic_frame *f, char *err);
/* The path of stage file i (0 .. PIC_STAGE_FILES - 1) that pic_stages
 * writes for dir and stem (so a caller can refuse to overwrite an input). */
#define PIC_STAGE_FILES 7
void pic_stage_path(const char *dir, const char *stem, int i, char *out, size_t n);

#endif
