/* The tracker's search window around a predicted tag (internal; track.c,
 * tested in tools/sim/test_track.c against the rule below).
 *
 * actag__track_window: the pixel window [x0, x1] x [y0, y1] (inclusive) of a
 * frame of rows x cols around the predicted corners pred (x = column,
 * y = row): about the corners' centre, half the corners' bounding box in
 * each direction times extent (the whole tag over its white square:
 * (k + 1) / (k - 3) for a family of 4k bits), times 1 + grow, plus pad
 * pixels, at least ACTAG__TRACK_MIN_WINDOW / 2 each side; cut to the
 * frame, then widened back to ACTAG__TRACK_MIN_WINDOW pixels (or the whole
 * frame's side, when smaller) inside it, so it always holds pixels: a
 * prediction wholly outside the frame gets the strip of that width at the
 * nearest edge (a tag leaving the view is read there, if at all). Returns
 * 0, or -1 (the window unset or useless) when a side of it lies beyond 1e7
 * pixels (or is NaN), or when it is wider than ACTAG_TRACK_ROI_MAX_COLS. */
#ifndef ACTAG_TRACK_WINDOW_H
#define ACTAG_TRACK_WINDOW_H

#include "actag/track.h"

/* pixels a window spans at least (the structure search wants >= 16) */
#define ACTAG__TRACK_MIN_WINDOW 24

int actag__track_window(const actag_point pred[4], float extent, float grow, float pad, int rows,
                        int cols, int *x0, int *y0, int *x1, int *y1);

#endif
