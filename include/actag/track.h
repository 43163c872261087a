/*
 * actag/track.h -- following tags across the pings of a sonar stream.
 *
 * MANUAL
 *   A tag seen in the last ping is almost where it was. Feed the frames in
 *   order; for each frame the tracker
 *     1. reads every confirmed track where it is predicted ("verify"): the
 *        window around the predicted tag is median-filtered and the
 *        grid-fitting decoder (decode.h) starts on the predicted corners;
 *        when that reads nothing and the track has no velocity yet (one
 *        reading) or missed the last frame (its prediction can then be a
 *        cell or more off), the decoder tries once more, searching +-1
 *        cell about the prediction (ACTAG_FIT_WIDE).
 *        The window's median radius is the parameters' or half the track's
 *        predicted cell width (pixels, at least 1), whichever is smaller:
 *        a median wider than a cell erases a far tag's cells (the paper's
 *        sonar beyond 3 m, docs/tracking.md); step 2 uses the same radius.
 *        A verify reading whose grid changed shape (its corners about their
 *        centre) by more than a quarter of the predicted diagonal is not
 *        the tag read, and refused.
 *        The only hypotheses are the track's own code (its 4 rotations in
 *        the track's handedness) and "no tag": a reading of another ID or
 *        handedness could not update the track, so the family's other codes
 *        and the mirror views are not candidates. The reading must keep at
 *        most the corrections limit in data bits,
 *        the decision margin over "no tag" (min_margin) and the likelihood
 *        and template checks; black-ring misses, interior misses and
 *        corrected bits together may reach twice the corrections limit (6
 *        for AcTag24h10; the whole-frame pipeline allows the limit): a
 *        random 49-cell pattern is that close to one given template with
 *        probability below 1e-7. A reading with corrected bits is read
 *        again from the prediction against the whole family (the track's
 *        handedness, the pipeline's margins): when that reads another ID,
 *        another tag lies there (the one-code polish can bend the grid
 *        toward the track's code) and the verify reads nothing. This
 *        skips the structure search, the threshold, the contours and
 *        RANSAC, which is where most of a frame's work is
 *        (docs/tracking.md);
 *     2. for tracks not read so (and tentative ones), runs actag_detect() on
 *        a region of interest (ROI) around the prediction: a sub-frame view
 *        of the caller's frame (same data and stride, offset start) with
 *        the sonar geometry of that window (the range limits of its rows and
 *        a bearing table of its columns, kept in the tracker state), in the
 *        track's handedness (params.handedness of the ROI search set to it
 *        when the caller's is ACTAG_HANDEDNESS_ANY: a track never changes
 *        handedness, and the other one's views are the published
 *        families' nearest rivals of a code; a tag of the other handedness
 *        in the window is left to the whole-frame searches);
 *     3. runs actag_detect() on the whole frame every `full_every` frames,
 *        whenever no confirmed track exists, and when a confirmed track has
 *        gone `refind_after` frames in a row without a reading (a tag that
 *        moved more than foreseen); a confirmed track that the whole frame
 *        did not read is then verified as in step 1 (unless step 1 verified
 *        it in this frame: at most one verify per track and frame).
 *
 *   Tracks. A reading that matches no track starts a tentative track; it is
 *   confirmed after `confirm_frames` consecutive frames with a consistent
 *   reading (same ID, same handedness, centre within `gate` tag diagonals of
 *   the prediction, the gate growing by one diagonal per frame the track has
 *   missed), or at once when its decision margin reaches `confirm_margin`.
 *   A track of one reading has no velocity, so no prediction: its second
 *   reading is the nearest of its ID and handedness anywhere in the frame
 *   that no track took within its gate, and the filter starts from the two (corners the second's, velocity
 *   their displacement per frame); the third must fall within the gate of
 *   what the two predict (a tag moving more than a diagonal a frame was
 *   never confirmed before).
 *   A reading of a confirmed track's ID and handedness outside its gate,
 *   when that track got no reading in this frame (a tag that moved farther
 *   than the gate allows, e.g. between whole-frame searches), re-acquires
 *   it instead of starting a second track of the same tag: its corners are
 *   set to the reading's (no smoothing) and its velocity to zero.
 *   A tentative track that misses a frame is dropped; a confirmed one after
 *   more than `max_missed` consecutive frames without a reading (meanwhile
 *   it is kept and its window searched, and not reported: only what was
 *   read in this frame is; with report_coasting 1 it is reported as
 *   coasting, measured = 0, on the first frame it misses only, and only
 *   once it has been read twice: a track of one reading has no velocity,
 *   and its prediction would be the place of that reading however far the
 *   tag has moved; later predictions drift from the tag, and even the
 *   first lay off the tag in 4 of 148 simulated reports, docs/tracking.md;
 *   the state's tracks[] hold them for a caller that wants them), or as soon
 *   as a frame without a reading
 *   predicts its centre outside the frame (the tag has left the view; a
 *   window at the sonar too short in range for a tag is read as holding
 *   none, not as an error). A track's tag ID and
 *   handedness never change: a reading of another ID (or the other
 *   handedness) at a tracked tag's place (its centre within `gate`
 *   predicted diagonals of the prediction's, not widened while the track
 *   coasts) is ignored and counted (stats.conflicts), never assigned. Corners are smoothed by an alpha-beta
 *   filter per pixel coordinate (alpha = smoothing, beta = alpha^2 /
 *   (2 - alpha)), which also predicts the next frame's position; a reading
 *   whose corners lie more than a quarter of its diagonal from the prediction
 *   (innovation) is a tag that moved otherwise than foreseen, and its
 *   corners are taken as read (smoothed, they would trail it by 1 - alpha
 *   of that distance), the velocity updated as usual; the range
 *   and azimuth of the smoothed corners come from the geometry. Only
 *   confirmed tracks are reported. Verify readings carry the fitted grid's
 *   corners (inlier_ratio 0, like structure-search readings).
 *
 *   roi_params: the parameters of steps 1-2 (NULL: the whole-frame ones).
 *   Since only a track's own ID near its prediction can update it, a
 *   caller may lower the decision margins there (e.g. min_margin -2);
 *   measured gain in docs/tracking.md. Its family must be params' family
 *   (the same pointer, or the same bits, ncodes and codes): tracks are
 *   started under one and read under the other by their IDs. That family
 *   must stay the same for the tracker's life (the state keeps its bits,
 *   ncodes and a 32-bit checksum of its codes from the first frame; another
 *   family needs actag_tracker_init).
 *
 *   Memory: actag_tracker is a caller-owned struct of fixed size (about
 *   6 KB with the defaults of ACTAG_TRACK_MAX and ACTAG_TRACK_ROI_MAX_COLS),
 *   no heap, no static state; the workspace of one whole-frame
 *   actag_detect() call serves every step. Stack: actag_tracker_update's
 *   own frame is under 1 KB (912 bytes on x86-64 -O2: two actag_params
 *   copies for a track's window) beside that of the actag_detect() or
 *   decoder call it makes. The same frames and parameters
 *   give the same output on every platform. 16-bit frames: actag_detect()
 *   scales each view by its own maximum, so an ROI's 8-bit image can differ
 *   slightly from the whole frame's; step 1 runs on 8-bit frames with the
 *   fit decoder only (others go to step 2).
 *
 * FUNCTIONS
 *   void actag_track_params_default(actag_track_params *p)
 *       full_every 10, confirm_frames 3, confirm_margin 15, max_missed 5,
 *       roi_scale 0.5, gate 1.0, smoothing 0.7, refind_after 2, verify 1,
 *       report_coasting 0.
 *       NULL p: nothing (no error codes).
 *   int actag_tracker_init(actag_tracker *t, const actag_track_params *p)
 *       Empty state. ACTAG_ERR_NULL (t or p), ACTAG_ERR_PARAM (full_every < 1,
 *       confirm_frames < 1, confirm_margin not finite (FLT_MAX is: no
 *       confirmation by margin alone), max_missed < 0,
 *       roi_scale <= 0 or > 10, gate <= 0 or > 10, smoothing outside (0, 1],
 *       NaN included, refind_after < 0, verify or report_coasting not 0/1),
 *       ACTAG_OK.
 *   int actag_tracker_update(actag_tracker *t, const actag_frame *frame,
 *                            const actag_sonar_geometry *geometry,
 *                            const actag_params *params, const actag_params *roi_params,
 *                            void *workspace, size_t workspace_size,
 *                            actag_track *out, int max_out, actag_track_stats *stats)
 *       One frame. Writes up to max_out confirmed tracks (in track order)
 *       and returns their number, or a negative error, first found of:
 *       ACTAG_ERR_NULL for t; ACTAG_ERR_PARAM for a t that
 *       actag_tracker_init did not make (a zeroed or overwritten state:
 *       parameters init refuses, a track count outside 0..ACTAG_TRACK_MAX,
 *       track ID 0; the frame counter is not advanced then); what actag_check() (actag_detect's checks)
 *       returns for the frame with params (max_out included), then with
 *       roi_params (when given); ACTAG_ERR_NULL for workspace or out
 *       (max_out > 0); ACTAG_ERR_PARAM when roi_params' family is not params' family, or
 *       that family is not the first frame's (roi_params above).
 *       stats may be NULL. On an error the state is unchanged except the
 *       frame counter.
 *       A new sonar setting mid-stream (another range window, aperture,
 *       orientation, bearing table or frame size: a sonar's range scale
 *       changed by its operator) keeps the tracks: each smoothed corner is
 *       moved to the pixel of its range and azimuth in the new frame, its
 *       velocity carried over through the old mapping (restarted when the
 *       old frame had a bearing table, or either frame a single row or
 *       column), so the track is read at its place
 *       in the new frame; `last` keeps the reading as it was returned. A
 *       bearing table changed in place is noticed by a checksum of its
 *       values; a change that moves no track by more than 0.01 px (an ulp
 *       of max_range recomputed every ping) leaves the tracks as they are.
 *       A frame of one row (column) holds no tag and has no range
 *       (azimuth) axis: the tracks coast through it keeping their range
 *       (azimuth), and are found at their place in the next frame.
 *
 *   Cost per frame (stats): pixels filtered (verify windows, ROIs, whole
 *   frame), verify attempts, ROI calls, whether the whole frame was
 *   searched, and the detector's counters summed. Measured instructions:
 *   docs/tracking.md (bench/track_bench under callgrind).
 */
#ifndef ACTAG_TRACK_H
#define ACTAG_TRACK_H

#include "actag/actag.h"

#ifdef __cplusplus
extern "C" {
#endif

#ifndef ACTAG_TRACK_MAX
#define ACTAG_TRACK_MAX 8 /* tracks (tentative and confirmed) per tracker */
#endif
#ifndef ACTAG_TRACK_ROI_MAX_COLS
#define ACTAG_TRACK_ROI_MAX_COLS 512 /* widest ROI (beams); wider: the whole frame */
#endif
#define ACTAG_TRACK_MAX_DET 16 /* readings kept per actag_detect() call */

typedef struct actag_track_params {
    int full_every;      /* search the whole frame every N frames (10) */
    int confirm_frames;  /* consecutive consistent frames to confirm a tag (3) */
    float confirm_margin; /* a reading with this decision margin confirms at once (15) */
    int max_missed;      /* a confirmed track survives this many frames unseen (5) */
    float roi_scale;     /* ROI = the tag's predicted box (whole tag) grown by this many
                            box sizes on every side, plus the filter radii (0.5) */
    float gate;          /* a reading matches a track within this many tag diagonals of the
                            predicted centre (1.0) */
    float smoothing;     /* alpha of the corner filter, (0, 1]; 1 = no smoothing (0.7) */
    int refind_after;    /* a confirmed track missed in its ROI this many frames in a row
                            triggers a whole-frame search in the same frame (2; 0: never) */
    int verify;          /* 1: read a confirmed track first at its prediction (below) (1) */
    int report_coasting; /* 1: also report a confirmed track on the first frame it is not
                            read, at its prediction (measured = 0); set it to bridge a
                            missed ping where a prediction is worth more than nothing; 4
                            of 148 such reports lay off the tag on simulated passes,
                            docs/tracking.md (0: only tracks read in this frame) (0) */
} actag_track_params;

typedef struct actag_track {
    uint32_t track_id;       /* unique within the tracker: never 0, not reused before
                                2^32 - 1 further tracks (then 1 again) */
    int id;                  /* tag ID (never changes) */
    int mirrored;            /* handedness (never changes) */
    int confirmed;           /* 1 once confirmed */
    int measured;            /* 1: read in this frame; 0: coasting on the prediction */
    int hits;                /* frames with a reading (saturates at INT_MAX, as age) */
    int missed;              /* consecutive frames without one (saturates at INT_MAX) */
    int age;                 /* frames since the track started */
    actag_point corners[4];  /* smoothed corners, tag order (x = column, y = row) */
    float range[4];          /* metres, of the smoothed corners (a coasting
                                track's may lie outside the frame: the
                                geometry's mapping extended; a reported
                                track's ranges below 0 are given as 0, the
                                state's tracks[] keep the mapping's) */
    float azimuth[4];        /* radians */
    actag_point velocity[4]; /* pixels per frame */
    float innovation;        /* pixels: how far the latest reading's corners lay from
                                the prediction (the largest of the four; 0 after a
                                track's first reading) */
    actag_detection last;    /* the latest reading (unsmoothed) */
} actag_track;

typedef struct actag_track_stats {
    int full_frame;      /* 1: the whole frame was searched */
    int rois;            /* ROI calls of actag_detect() */
    long pixels;         /* pixels filtered: verify windows, ROIs and the whole frame */
    int readings;        /* detections returned by those calls */
    int conflicts;       /* readings ignored: another ID or handedness at a tracked tag */
    int started, confirmed, dropped; /* track events this frame */
    int verified;        /* confirmed tracks tried at their prediction (verify; at most
                            once per track) */
    int quads, decoded, searched; /* actag_stats of those calls, summed: quads fitted,
                                     decoded, structure-search candidates decoded */
} actag_track_stats;

typedef struct actag_tracker {
    actag_track_params params;
    actag_track tracks[ACTAG_TRACK_MAX];
    int ntracks;
    long frame;              /* frames fed (including failed ones); past LONG_MAX
                                it goes on from params.full_every + 1 (at most
                                from LONG_MAX - 1) */
    long last_full;          /* frame index of the last whole-frame search (-1: none) */
    uint32_t next_track_id;
    int rows, cols;          /* of the last frame (0: none yet) */
    /* the last frame's sonar geometry: when the next one differs (range
     * setting, aperture, orientation, bearing table), the tracks are
     * carried over through their range and azimuth (track.c) */
    float geo_min_range, geo_max_range, geo_aperture;
    unsigned geo_flags;
    uint32_t geo_bearings_sum; /* checksum of its bearing table (0: none) */
    int family_bits, family_ncodes; /* of the first frame's params.family */
    uint32_t family_sum;     /* and a checksum of its codes (track.c) */
    float bearings[ACTAG_TRACK_ROI_MAX_COLS];   /* an ROI's bearing table */
    actag_detection det[ACTAG_TRACK_MAX_DET];   /* one call's readings */
    actag_detection pool[ACTAG_TRACK_MAX_DET];  /* one frame's readings, frame coordinates */
    int pool_from_roi[ACTAG_TRACK_MAX_DET];     /* track index of the ROI, -1: whole frame */
} actag_tracker;

void actag_track_params_default(actag_track_params *p);
int actag_tracker_init(actag_tracker *t, const actag_track_params *p);
int actag_tracker_update(actag_tracker *t, const actag_frame *frame,
                         const actag_sonar_geometry *geometry, const actag_params *params,
                         const actag_params *roi_params, void *workspace, size_t workspace_size,
                         actag_track *out, int max_out, actag_track_stats *stats);

#ifdef __cplusplus
}
#endif
#endif /* ACTAG_TRACK_H */
