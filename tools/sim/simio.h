/*
 * simio.h -- what actag-sim and actag-eval share besides the renderer:
 * ground-truth JSON, the pool recording's settings, tag-region statistics
 * and the comparison with real frames. Host only.
 */
#ifndef ACTAG_SIMIO_H
#define ACTAG_SIMIO_H

#include "sim.h"

#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The pool recording (../shared/data/sonar/pool-video): 530 x 512, 0.1-1.5 m,
 * 60 degrees, 12 degrees vertical; views at 0.9-1.4 m, 55-75 degrees. */
void simio_pool_settings(sim_sonar *s, sim_view_params *v);
/* The pool recording's sonar alone (every field set, reference orientation). */
void simio_pool_sonar(sim_sonar *s);

/* One JSON line: file, frame, seed, and per tag its family, id, size,
 * mirrored, visible, distance, incidence, pose and corners (x = column,
 * y = row, range m, azimuth rad). */
void simio_truth_line(FILE *f, const char *file, int frame, uint32_t seed, const sim_sonar *s,
                      const sim_scene *scene);

/* Grey levels of a tag in an 8-bit frame, from its inner-square corners
 * (tag order): the white interior (foam), the black ring (aluminium), and
 * the frame's median outside the tag's neighbourhood (background). */
typedef struct simio_tag_stats {
    float foam;       /* mean of the white square's interior */
    float metal;      /* mean of the black ring's cells */
    float background; /* median outside 2x the tag's bounding box */
    float background_mean;
} simio_tag_stats;

int simio_tag_stats_of(const uint8_t *img, int rows, int cols, const actag_point corners[4],
                       int bits, simio_tag_stats *out);

/* actag-sim --compare-real: statistics of real frames in dir (the tag found
 * by actag_detect with the pool settings) beside n simulated pool frames;
 * with montage, a PGM of 4 real and 4 simulated frames. */
int simio_compare_real(const char *dir, int n, uint32_t seed, const sim_appearance *a,
                       const char *montage, FILE *out, char *err);

#ifdef __cplusplus
}
#endif
#endif
