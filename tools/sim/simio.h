/*
 * simio.h -- what actag-sim and actag-eval share besides the renderer:
 * ground-truth JSON, the pool recording's settings, the random frames' tag
 * IDs, the sonar and view options of both command lines, tag-region
 * statistics and the comparison with real frames. Host only.
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

/* The tag ID of a random frame seeded with `seed` (sim_frame_seed): one of
 * ncodes, the same draw in actag-sim --random and actag-eval, so that frame F
 * of an actag-eval run is frame F of actag-sim --random with its seed. */
int simio_random_id(uint32_t seed, int ncodes);

/* ---- the command-line options actag-sim and actag-eval share. Errors:
 * "prog: message" naming the option and value on stderr, exit status 2
 * (hostio_die). */

/* The defaults both tools start from: the paper's sonar (1024 x 512,
 * 0.1-5 m, 12 degrees vertical; every other field 0, the aperture left to
 * the caller), sim_appearance_default and sim_view_params_default, then
 * simio_pool_settings when --pool is anywhere in argv (so that later
 * options override it). Returns 1 with --pool, else 0. */
int simio_opt_defaults(int argc, char **argv, sim_sonar *s, sim_view_params *v,
                       sim_appearance *a);

/* For an option opt that takes a value: dies with "opt: missing value" when
 * value is NULL, else advances *i past it. */
void simio_opt_need(const char *prog, const char *opt, const char *value, int *i);

/* A tool's command line, for the options both tools take. */
typedef struct simio_cli {
    const char *prog;        /* "actag-sim": messages, --version */
    void (*usage)(FILE *f);  /* --help */
    long min_dim, max_dim;   /* the range of --rows and --cols */
    sim_sonar *sonar;
    sim_view_params *view;
    double *aperture_deg;    /* --aperture-deg, for the tool to apply */
} simio_cli;

/* The options both tools take, at argv[*i]: --help (usage on stdout) and
 * --version ("prog VERSION"), both ending the program with status 0; --pool
 * (applied by simio_opt_defaults), --min-distance, --max-distance,
 * --min-incidence-deg, --max-incidence-deg, --max-yaw-deg,
 * --mirror-fraction, --clutter, --rows and --cols (min_dim..max_dim),
 * --min-range, --max-range, --aperture-deg, --vertical-aperture-deg,
 * --range-ascending, --azimuth-ascending. Sets the option and returns 1,
 * with *i past its value; returns 0 when argv[*i] is none of them. */
int simio_opt_common(const simio_cli *cli, int argc, char **argv, int *i);


/* The view limits in order (--max-distance >= --min-distance,
 * --max-incidence-deg >= --min-incidence-deg), else dies naming them. */
void simio_opt_check_views(const char *prog, const sim_view_params *v);

/* The family option opt names (dies with "opt: unknown family 'NAME'"). */
void simio_opt_family(const char *prog, const char *opt, const char *name, actag_family *fam);

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
 * with montage, a PGM of 4 real and 4 simulated frames. A folder without
 * .pgm frames, or none of whose frames gives a tag, is an error (-1, err). */
int simio_compare_real(const char *dir, int n, uint32_t seed, const sim_appearance *a,
                       const char *montage, FILE *out, char *err);

#ifdef __cplusplus
}
#endif
#endif
