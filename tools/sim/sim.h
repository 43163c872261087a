/*
 * sim.h -- a sonar simulator with ground truth (host only).
 *
 * MANUAL
 *   Renders polar imaging-sonar frames (rows = range bins, columns = beams,
 *   any orientation flags or bearing table of actag_sonar_geometry) of AcTags
 *   at known 6-DOF poses, and computes where each tag's corners must appear.
 *   It is what actag-sim and actag-eval are built on; tests use it directly.
 *
 *   Frames (coordinates of the AcTag paper, section III-A):
 *     sonar frame  x forward, y to the sonar's left, z up. A point projects
 *                  to range r = |p| and azimuth theta = atan2(y, x) (paper
 *                  eq. 3); its elevation e = asin(z / r) is lost. The sonar
 *                  sees |e| <= vertical_aperture / 2 (-3 dB edges) and a
 *                  Gaussian beam beyond that (down to -12 dB at the full
 *                  aperture, nothing past it). Azimuth +aperture/2 is image
 *                  column 0 in the reference orientation (SPEC section 4).
 *     tag frame    origin at the centre of the tag's face, x to the right
 *                  and y down as printed, z into the tag (the AprilTag
 *                  convention); the face you read is the side toward -z.
 *                  Inner white square corners (tag order TL TR BR BL):
 *                  (-s/2,-s/2,0) (s/2,-s/2,0) (s/2,s/2,0) (-s/2,s/2,0),
 *                  s = tag_size; cells are s/(k-3) wide, the tag (k+1).
 *     pose         p_sonar = R p_tag + t (R row-major, t in metres).
 *
 *   Image model (per pixel, supersampled where a tag can be):
 *     For every planar surface (tags, seabed) the points at the pixel's
 *     range and azimuth form an arc in elevation; each point of the arc on
 *     the surface returns  sigma(material, incidence) * beam(e) *
 *     |de/dr| * dr * (r0 / r)^spreading, unless a tag between it and the
 *     sonar shadows it. Materials: foam (white cells) scatters diffusely,
 *     sigma = foam * cos(inc)^foam_exp; aluminium (black cells, and the
 *     back of a tag) is specular, sigma = metal_specular *
 *     exp(-(inc/metal_lobe)^2) + metal_diffuse; the seabed is
 *     seabed * cos(inc)^seabed_exp, brighter in clutter patches.
 *     The intensity image then becomes a complex field with Rayleigh
 *     speckle (circular Gaussian per pixel), blurred by the beam's point
 *     spread (Gaussian, sigma psf_azimuth rad / psf_range m; receiver noise
 *     is added before the spread, so it is blurred too); the root of `looks` such fields' mean power (the
 *     sonar's ping averaging) times `gain` is the pixel, after
 *     interference bands (constant-range rows across all beams, gain between
 *     band_min and band_max, band_rate per frame on average). Same inputs
 *     and seed: same frame.
 *
 *   Ground truth (sim_truth): for each tag the true range/azimuth and pixel
 *   position of its inner-square corners in tag order, the mirrored flag
 *   (the image shows the printed tag reflected, relative to the reference
 *   orientation: the flag actag_detection.mirrored must report), whether
 *   the whole tag is in the field of view, its distance and incidence.
 *
 * ERRORS: functions return 0 or -1 and write a message into err (may be NULL).
 */
#ifndef ACTAG_SIM_H
#define ACTAG_SIM_H

#include "actag/actag.h"
#include "actag/render.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SIM_MAX_TAGS 16
#define SIM_MAX_PATCHES 64
#define SIM_MAX_K 8

typedef struct sim_sonar {
    int rows, cols;            /* range bins, beams */
    actag_sonar_geometry geo;  /* ranges (m), aperture (rad), bearings, flags */
    float vertical_aperture;   /* rad, full -3 dB width (paper: 12 degrees) */
} sim_sonar;

typedef struct sim_pose {
    float R[9]; /* row-major rotation, tag (or patch) frame -> sonar frame */
    float t[3]; /* metres */
} sim_pose;

typedef struct sim_tag {
    actag_family family;
    int id;
    float tag_size; /* metres, inner white square side */
    sim_pose pose;
} sim_tag;

/* A rectangle of brighter (or darker) seabed: clutter. */
typedef struct sim_patch {
    float centre[3];  /* sonar frame, on the seabed */
    float axis[2][3]; /* unit in-plane axes */
    float half[2];    /* half sizes, metres */
    float gain;       /* backscatter multiplier */
} sim_patch;

typedef struct sim_scene {
    sim_tag tags[SIM_MAX_TAGS];
    int ntags;
    int has_seabed;
    float seabed_n[3]; /* unit normal pointing toward the sonar side */
    float seabed_d;    /* plane: n . p = d (d < 0 when the sonar is above) */
    sim_patch patches[SIM_MAX_PATCHES];
    int npatches;
} sim_scene;

/* Appearance: how the materials, sonar and noise look. sim_appearance_default()
 * gives values tuned to the pool frames (actag-sim --compare-real). */
typedef struct sim_appearance {
    float foam, foam_exp;                        /* diffuse foam backscatter */
    float metal_specular, metal_lobe, metal_diffuse; /* aluminium; lobe in rad */
    float seabed, seabed_exp;                    /* seabed backscatter */
    float spreading;                             /* intensity * (r0/r)^spreading */
    float spreading_r0;                          /* metres */
    float psf_azimuth, psf_range;                /* beam spread, Gaussian sigma: rad, m */
    float noise;                                 /* receiver noise power (intensity units) */
    float gain;                                  /* pixel = gain * amplitude */
    float band_rate;                             /* mean interference bands per frame */
    float band_min, band_max;                    /* band gain range */
    int supersample;                             /* samples per pixel side near tags (1..4) */
    int looks;                                   /* independent speckle looks averaged (1..8) */
    int speckle;                                 /* 1: Rayleigh speckle; 0: the mean field
                                                    (geometry tests) */
} sim_appearance;

typedef struct sim_truth {
    int id;
    int mirrored;            /* 1: the image shows the tag reflected */
    int visible;             /* 1: the whole tag is inside range, azimuth and elevation limits */
    float range[4];          /* metres, inner-square corners TL TR BR BL */
    float azimuth[4];        /* radians */
    actag_point px[4];       /* image position (x = column, y = row) */
    float distance;          /* metres, sonar to tag centre */
    float incidence;         /* rad, between the line of sight and the face normal */
} sim_truth;

/* Settings of the paper's evaluation protocol (section VI-B), see sim_sample_view. */
typedef struct sim_view_params {
    float min_distance, max_distance; /* metres, sonar to tag centre */
    float min_incidence, max_incidence; /* rad, line of sight vs face normal */
    float max_roll;                   /* rad, sonar roll jitter */
    float mirror_fraction;            /* share of views from the other side of the plane */
    int clutter;                      /* mean clutter patches per frame */
    float max_yaw;                    /* rad, the tag's turn about its normal away from
                                         "printed top farthest from the sonar" (pi: any) */
} sim_view_params;

void sim_appearance_default(sim_appearance *a);
void sim_view_params_default(sim_view_params *v);

/* Pose from position and roll/pitch/yaw (rad, R = Rz(yaw) Ry(pitch) Rx(roll)). */
void sim_pose_from_rpy(float x, float y, float z, float roll, float pitch, float yaw,
                       sim_pose *out);
/* roll/pitch/yaw of a rotation (inverse of the above). */
void sim_pose_rpy(const sim_pose *p, float rpy[3]);

/* Image position of (range, azimuth): 0, or -1 when outside the frame's limits
 * (the position is still written, extrapolated). */
int sim_pixel_of(const sim_sonar *s, float range, float azimuth, float *x, float *y);

/* The ground truth of one tag. */
void sim_truth_of(const sim_sonar *s, const sim_tag *tag, sim_truth *out);

/* Is a detection's corner order wrong against the truth's corners (both
 * TL TR BR BL as printed, pixels)? 1 when one of the 7 other rotations or
 * reflections of the detection's labels fits the truth better by more than
 * 4 px summed over the corners, or when some detected corner i lies nearer
 * another truth corner than truth corner i (a swapped pair, a bow-tie, a
 * corner far off, a quad a side away), or when some detected corner lies
 * more than SIM_CORNER_TOLERANCE of the truth's mean side from its own truth
 * corner (a quad about the right centre but of another size: the whole
 * tag's outline, one cell), or when a detected coordinate is not finite
 * (*mean_px NaN then); else 0. *mean_px (or NULL): the mean distance of
 * detected corner i to truth corner i. */
/* 0.45 of a side: 1.35 cells of a 24-bit tag. A quad scaled about the
 * right centre by 0.3 or less, or by 7/3 (the whole tag's outline), has
 * every corner farther (0.49 and 0.94 of a side); right readings reach
 * 0.33 (actag-eval --frames 1000 --seed 1) and the tracker's smoothed
 * corners 0.40 (test_track's far passes, 3-4.5 m). */
#define SIM_CORNER_TOLERANCE 0.45f
int sim_corner_order_wrong(const actag_point det[4], const actag_point truth[4], float *mean_px);

/* Renders the scene into out (8-bit, rows x cols, row stride out_stride)
 * or, when out16 != NULL instead, 16-bit (pixel * 256 + sub-grey detail).
 * Returns 0 or -1 (bad arguments, out of memory). */
int sim_render(const sim_sonar *s, const sim_scene *scene, const sim_appearance *a,
               uint32_t seed, uint8_t *out, uint16_t *out16, int out_stride, char *err);

/* The evaluation protocol: a random tag pose (family/id/size set by the
 * caller in *tag) seen from a random sonar pose, tag face toward the sonar,
 * the whole tag in the field of view; the seabed is the tag's plane 14 mm
 * behind its face, with random clutter patches. Fills tag->pose and scene
 * (tag included). Returns 0, or -1 when no visible pose was found. */
int sim_sample_view(const sim_sonar *s, const sim_view_params *v, uint32_t seed, sim_tag *tag,
                    sim_scene *scene);

/* The same seabed and clutter geometry without a tag (tag-free frames). */
void sim_sample_empty(const sim_sonar *s, const sim_view_params *v, uint32_t seed,
                      sim_scene *scene);

/* Frame i of n of a sonar pass: the sonar moves at a constant height (that of
 * the mean distance at the mean incidence) from max_distance * sin(incidence)
 * to min_distance * sin(incidence) horizontally while turning around the tag
 * by 40 degrees, aimed at it with a slow wobble (tracking sequences); the
 * distance and incidence change along the pass, and the tag may leave the
 * field of view (see sim_truth.visible). */
void sim_sequence_view(const sim_sonar *s, const sim_view_params *v, uint32_t seed, int i, int n,
                       sim_tag *tag, sim_scene *scene);

/* A seed for frame `index` of a run seeded with `seed` (independent streams). */
uint32_t sim_frame_seed(uint32_t seed, uint32_t index);

#ifdef __cplusplus
}
#endif
#endif
