/*
 * eval_track.h -- tracking evaluation for actag-eval (host only).
 *
 * MANUAL
 *   Runs frames in order through the whole-frame detector (actag_detect)
 *   and through the tracker (track.h) side by side, and counts, per frame,
 *   whether the tag is reported at its place with its ID, wrong IDs and
 *   false tags, track breaks and the pixels each path hands to the
 *   detector. Two sources of frames:
 *     te_run_sequences  simulated passes (sim_sequence_view) with truth;
 *     te_run_files      a list of frames without truth (the pool
 *                       recording): the tag is the one ID given, any other
 *                       ID is wrong.
 *   The tracker's per-frame work goes through te_track_frame() and the
 *   detector's through te_full_frame() (never inlined), so that
 *   `valgrind --tool=callgrind` and callgrind_annotate --inclusive=yes
 *   give each path's instructions; te_track_frame_tracked() is the same
 *   call for frames that start with a confirmed track ("while tracked").
 */
#ifndef ACTAG_EVAL_TRACK_H
#define ACTAG_EVAL_TRACK_H

#include "sim.h"
#include "actag/track.h"

#include <stdio.h>

typedef struct te_counts {
    int frames;           /* frames run */
    int visible;          /* frames with the tag wholly in view (files: all) */
    int full_found;       /* whole-frame detector: right ID at the tag */
    int full_wrong;       /* ... wrong IDs at the tag */
    int full_false;       /* ... detections elsewhere */
    int full_mirror;      /* ... right ID at the tag with the mirrored flag wrong */
    int full_order;       /* ... right ID at the tag in the wrong corner order */
    int track_read;       /* tracker: confirmed track of the right ID at the tag, read this frame */
    int track_reported;   /* ... reported at all (read or coasting within the gate) */
    int track_wrong;      /* ... confirmed tracks of another ID at the tag */
    int track_false;      /* ... confirmed tracks away from the tag */
    int track_mirror;     /* ... the tag's track with the mirrored flag wrong */
    int track_order;      /* ... the tag's track with its (smoothed) corners in the wrong order */
    int truth_known;      /* 1: the frames had corner truth (simulated passes), so the
                             mirror and order counts mean something */
    int id_switches;      /* a track whose reported tag ID changed (never, by design) */
    int breaks;           /* the tag's track replaced by a new one while visible */
    int tracked_frames;   /* frames that started with a confirmed track */
    int tracked_full;     /* ... of them searched whole (every N, or re-acquisition) */
    double full_pixels, track_pixels, tracked_pixels; /* pixels handed to the detector */
} te_counts;

typedef struct te_options {
    actag_track_params track;
    int relax_roi;        /* 1: ROI searches with min_margin -2 and search_min_margin 0 */
    int handedness;       /* actag_params.handedness of both parameter sets */
    int sequences, length;
    int threads;
    FILE *failures;       /* not NULL: one JSON line per pass frame with a wrong ID or a false tag */
} te_options;

void te_options_default(te_options *o);

/* Simulated passes: `sequences` of `length` frames each, seed per pass.
 * Returns 0 (counts summed over passes). */
int te_run_sequences(const sim_sonar *s, const sim_view_params *v, const sim_appearance *a,
                     const actag_family *fam, float tag_size, uint32_t seed,
                     const te_options *o, te_counts *out, int quiet);

/* Frames from files (8-bit PGM), in the order given, with one sonar
 * geometry, each want_rows x want_cols (a frame of another size is an
 * error naming it and its size; want_rows 0: any size, all frames the
 * first one's); tag_id is the ID present. visible[i] (NULL: all 1): 1 the whole
 * tag is in view (counts for recall), 0 part of it (a reading of tag_id is
 * neither counted nor an error), -1 no tag (every reading is a false tag).
 * Returns 0, or -1 with a message in err (HOSTIO_ERRLEN). */
int te_run_files(const char *const *names, int n, int want_rows, int want_cols,
                 const actag_sonar_geometry *g, const actag_family *fam, float tag_size,
                 int tag_id, const int *visible, const te_options *o, te_counts *out, char *err);

/* Errors: provided by the program (actag-eval's die(): the message on
 * stderr, the run's output files removed, exit status 2). */
void te_die(const char *msg);

/* Text or one JSON object (no newline). */
void te_print(FILE *f, const char *title, const te_counts *c, const te_options *o, int json);

/* The two paths, for instruction counts. */
int te_full_frame(const actag_frame *f, const actag_sonar_geometry *g, const actag_params *p,
                  void *ws, size_t wss, actag_detection *det, int max);
int te_track_frame(actag_tracker *t, const actag_frame *f, const actag_sonar_geometry *g,
                   const actag_params *p, const actag_params *rp, void *ws, size_t wss,
                   actag_track *out, int max, actag_track_stats *st);
int te_track_frame_tracked(actag_tracker *t, const actag_frame *f,
                           const actag_sonar_geometry *g, const actag_params *p,
                           const actag_params *rp, void *ws, size_t wss, actag_track *out,
                           int max, actag_track_stats *st);

#endif
