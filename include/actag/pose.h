/*
 * actag/pose.h -- 6-DOF tag pose from one sonar detection, with covariance,
 *                 and the camera pose in the same frame convention.
 *
 * MANUAL
 *   FRAMES (defined once here for the sonar and the camera paths)
 *     Tag frame    origin at the centre of the tag's face (the centre of the
 *                  inner white square), x toward the printed right edge, y
 *                  toward the printed bottom edge, z into the tag (AprilTag's
 *                  tag frame); the face you read is the side toward -z. The
 *                  inner white square's corners, in actag's tag order
 *                  (top-left, top-right, bottom-right, bottom-left as
 *                  printed), are (-s/2,-s/2,0) (s/2,-s/2,0) (s/2,s/2,0)
 *                  (-s/2,s/2,0), s = tag_size.
 *     Sensor frame x forward, y to the sensor's left, z up (right-handed).
 *                  Sonar: the AcTag paper's frame (section III-A): a point p
 *                  has range |p|, azimuth atan2(y, x) (positive toward +y,
 *                  image column 0 in the reference orientation) and
 *                  elevation asin(z / |p|), which the image loses.
 *                  Camera: x along the optical axis, y to the left of the
 *                  image (toward column 0), z toward the image's top row;
 *                  from the optical frame (x right, y down, z forward) of
 *                  AprilTag/OpenCV: x = z_opt, y = -x_opt, z = -y_opt
 *                  (actag_pose_from_camera).
 *     Pose         p_sensor = R p_tag + t; R row-major, t in metres (the tag
 *                  centre in the sensor frame).
 *     Covariance   6 x 6, row-major, of the error vector (dt, w): dt = t_true
 *                  - t (metres) and w the rotation vector (radians, sensor
 *                  axes) with R_true = exp([w]x) R. Units m^2, m rad, rad^2.
 *
 *   WHAT ONE PING DETERMINES
 *     Each corner lies somewhere on its elevation arc (fixed range and
 *     azimuth). Four arcs and a rigid square of known side fix:
 *       - the range and azimuth of the tag centre (about the corner noise
 *         divided by 2);
 *       - the tag's orientation: the image of the square is the square
 *         projected along the elevation direction, so its area and shape
 *         give the tilt out of the fan plane (poorly when the tag lies
 *         almost in the fan plane: the tilt then enters only through the
 *         shortfall of the image's side lengths, a square-root effect);
 *       - with a proper rotation and the printed face toward the sonar,
 *         the reflection across the horizontal plane (the sonar's classic
 *         two-fold ambiguity) is resolved: the reflected solution shows the
 *         tag's back. What remains of it is the sign of the face's tilt out
 *         of the fan plane, the winding of the corners in the image, which
 *         is exactly the detector's `mirrored` flag: unmirrored means the
 *         face normal (-z of the tag) points toward +elevation (for example
 *         a tag on the seabed seen from an upright sonar above it), mirrored
 *         toward -elevation (the same tag seen by an upside-down sonar, or a
 *         tag under a ceiling). The fit takes the side from the corners'
 *         winding, not from the flag: the cost has no minimum on the other
 *         side (a fit started there comes back), so `mirrored` only sets
 *         ACTAG_POSE_MIRROR_CONFLICT when the winding clearly (by more than
 *         2 sds of the image's area) says otherwise. Within 2 sds (a nearly
 *         flat image, flagged ACTAG_POSE_DEGENERATE: near head-on views)
 *         noise may give the other side; the tilt out of the fan plane is
 *         small there.
 *     The centre's elevation is almost unobservable: moving the whole tag
 *     along the elevation arcs changes the corners' (range, azimuth) only by
 *     a second-order term (the azimuth spread shrinks by cos(elevation),
 *     0.5 % at 6 degrees), far below the corner noise except at very short
 *     range. The estimator therefore combines the corners with what the
 *     image itself proves: the tag was seen, so its outline (params.extent)
 *     lies within the vertical aperture. This is a uniform prior on the
 *     centre's elevation over the band where the whole outline fits,
 *     entered in the least squares as a Gaussian of the band's mean and
 *     standard deviation (width / sqrt(12)); the covariance carries it, so
 *     the position's error ellipsoid is long in elevation (about range *
 *     band / sqrt(12)). The band is computed from the fitted tilt, so its
 *     edges are uncertain as the tilt is: their variances and covariance
 *     (the edges' gradients through the fit's covariance) are added, the
 *     middle's variance and the width's / 12, so the prior's sd is never
 *     below what is known of the band itself (a band that only just fits,
 *     a sliver of a fraction of a mrad, no longer claims the elevation to
 *     that fraction). When the outline's band may be empty (a close or
 *     tall tag: a real beam's edge is soft), the inner square's band takes
 *     over, and when that may be empty too, a weak pull (sd half the
 *     aperture) to its middle: the three are blended, each band weighted
 *     by how likely it is non-empty given its width and the width's sd (a
 *     smoothstep over width / sd in -2..2, within 0.03 of the normal
 *     distribution function), and the blend's mean and variance taken, so
 *     the prior moves continuously with the corners. ACTAG_POSE_ELEVATION
 *     is set when, at the solution, not even the inner square fits (the
 *     corners are not those of a tag of this size in view) or the fit lies
 *     outside the band reported in elevation_lo/hi by more than 2 of the
 *     prior's sds.
 *
 *   METHOD
 *     Start: the corners placed at one elevation give each edge's in-fan
 *     components; the elevation components follow from the square's side
 *     and right angle (a rank-one 2 x 2 problem), signed so the face is
 *     toward the sonar. Then Levenberg-Marquardt on the 6 pose parameters
 *     (t, and a rotation vector applied on the left) over the 8 corner
 *     residuals, range / range_sd and azimuth / azimuth_sd, plus the
 *     elevation prior, each step a column-scaled Householder QR (no normal
 *     equations). Starts across the elevation band (the cost along
 *     the arcs is flat and can have two minima, near +e and -e): five, or
 *     one every 4 degrees for a band wider than 16 degrees, at most 17;
 *     among their fits, one whose printed face looks at the sonar is taken
 *     over one that shows the tag's back (the pose reflected in the
 *     horizontal plane has the same corners), then the least cost; the best
 *     one refined; the band is recomputed from the fit and the fit repeated
 *     (at most 3 passes; max_iterations trial steps per start and pass).
 *     A fit has converged when a nearly undamped step is shorter than
 *     1e-3 of the solution's sd (|J d| < 1e-3 in the normalised residuals)
 *     or gains nothing, or when the cost refuses one shorter than 1e-2 sd
 *     (over so short a step that is the cost's float rounding, not the
 *     model); ACTAG_POSE_NOT_CONVERGED when the last pass reached
 *     max_iterations first.
 *     The covariance is (J^T J)^-1 at the solution (prior included), from
 *     the same QR factor, plus the second-order part of the elevation
 *     slide: the centre moves on a sphere of fixed range, so a slide of
 *     sd s_e along the arc also moves it toward the sonar by r de^2 / 2,
 *     added as 3/4 r^2 s_e^4 along t / |t| (without it the truth fell
 *     outside the 95 % position ellipsoid about one time in five). All in float; the trigonometry is the library's
 *     own (sums and products only, plus sqrtf), so results are identical on
 *     every IEEE-754 platform built with -ffp-contract=off. No heap, no
 *     static state; about 0.3 M x86 instructions (well under 0.1 ms on a
 *     desktop core) with five starts (a 12 degree aperture); about 3.3 M
 *     with the 17 starts of a 150 degree aperture.
 *
 *   CORNER NOISE DEFAULTS (ACTAG_POSE_RANGE_SD, ACTAG_POSE_AZIMUTH_SD)
 *     0.0024 m and 0.0013 rad: the simulator's measured corner error at the
 *     paper's settings when the defaults were set (refine.h's refinement
 *     on the median-filtered frame: actag-eval --frames 1000 --seed 1,
 *     1,360 corners, sd 0.24 cm in range, 0.0013 rad in azimuth; 0.88 cm
 *     and 0.0040 rad unrefined). The refinement now reads the raw frame
 *     and the same run gives 2,800 corners at 0.139 cm and 0.00078 rad, so
 *     the defaults are pessimistic (the 95 % ellipsoid holds the truth
 *     99-100 % of the time, docs/pose.md); they are kept for sonars
 *     noisier than the simulator's. Corners of another sonar
 *     (resolution, range) deserve their own figures: the covariance scales
 *     with them.
 *
 *   KNOWN PLANE (optional: params.plane, plane_sd, plane_tilt_sd)
 *     A vehicle often knows what one ping cannot show: a tag lying on a flat
 *     seabed is in the plane its altitude (DVL) and attitude (IMU) give, in
 *     the sonar's frame n . p = d (for an upright sonar at altitude h over
 *     level ground: n = (0, 0, 1), d = -h). With plane_sd > 0 the face
 *     centre's offset from that plane enters the fit as one more residual of
 *     sd plane_sd; with plane_tilt_sd > 0 the face normal's angle from n
 *     enters as two (its components across n, sd plane_tilt_sd). Either one
 *     pins the elevation slide that the corners leave free (the slide turns
 *     the tag and moves its centre across the plane), so the position error
 *     falls from the elevation band's to about the plane's own error (see
 *     docs/pose.md for figures). The band prior stays; the covariance
 *     carries the plane terms. ACTAG_POSE_PLANE is set when the fit sits more
 *     than 3 sds off the plane (offset, or tilt): the plane, the corners or
 *     the tag's placement disagree (a plane outside the aperture may show as
 *     ACTAG_POSE_ELEVATION instead, when the plane wins over the band). The
 *     sds are the plane's errors at the tag: an attitude error a at range r
 *     adds r a to the offset's. The plane cannot pin the slide when it
 *     contains the elevation direction at the tag (an edge-on image). Only
 *     the plane's orientation and offset matter, not the sign of n.
 *   CAMERA POSES
 *     actag_pose_from_camera() turns a camera pose of the same tag frame
 *     (AprilTag's estimate_tag_pose, optical frame) into the sensor frame
 *     above, so both sensors report p_sensor = R p_tag + t with x forward,
 *     y left, z up; a vehicle then applies each sensor's mounting.
 *     (optical/: actag_apriltag_pose_sensor does both steps.)
 *     actag_pose_camera_covariance() then gives such a pose the covariance
 *     the sonar's have (the same error vector and frame): the four corners'
 *     pixel noise (pixel_sd, a sd per coordinate, independent) carried
 *     through the pinhole projection to first order, (J^T J)^-1 of the
 *     whitened Jacobian of the 8 corner coordinates in (dt, w). It is the
 *     covariance of the estimate's local minimum: a view close to head-on
 *     has a second, mirror-image minimum (the planar pose ambiguity) that
 *     a camera estimator may choose instead, which no local covariance
 *     describes. Distortion is assumed removed. (optical/:
 *     actag_apriltag_pose_sensor_cov does all three steps.)
 *
 * FUNCTIONS
 *   void actag_pose_params_default(actag_pose_params *p, const actag_family *family,
 *                                  float tag_size, float vertical_aperture)
 *       Defaults: the given tag size (m) and vertical aperture (rad, full
 *       width), extent = the family's full tag side over tag_size ((k+1)/(k-3)
 *       for 4k bits: 7/3 for 24 bits; 1 when family is NULL), the noise
 *       defaults above, 20 iterations, no known plane. NULL p: nothing.
 *   int actag_pose_estimate(const float range[4], const float azimuth[4], int mirrored,
 *                           const actag_pose_params *p, actag_pose *out)
 *       Pose from the four corners in tag order (metres, radians, as in
 *       actag_detection). Returns ACTAG_OK (out filled; check out->flags),
 *       ACTAG_ERR_NULL (a pointer is NULL), ACTAG_ERR_PARAM (a corner not
 *       finite, a range outside 1e-3 .. 1e4 m, an azimuth outside (-4 pi,
 *       4 pi), tag_size outside 1e-3 .. 1e4 m (the fit squares lengths:
 *       beyond these they leave the float range), vertical_aperture outside
 *       (0, pi), extent < 1 or the outline's side extent x tag_size above
 *       1e4 m, range_sd or azimuth_sd <= 0, not finite or
 *       so small that 1 / sd^2 overflows a float (below about 5e-20),
 *       max_iterations outside 1..100, plane_sd or plane_tilt_sd negative,
 *       not finite or, when not 0, that small, or, when either is > 0,
 *       plane not finite, its normal zero or its offset |d| / |n| above
 *       1e4 m; the normal may have any scale, (0, 0, 1e-30) as (0, 0, 1e20)).
 *       "Finite" here means |v| < 3e38, a little below FLT_MAX, for every
 *       float argument (also actag_pose_from_camera's).
 *       ACTAG_ERR_BUILD (compiled with fused multiply-adds or reciprocal
 *       divisions, as actag_detect). Degenerate geometry is not an error: out is filled
 *       as well as possible and flagged.
 *   int actag_pose_from_detection(const actag_detection *d, const actag_pose_params *p,
 *                                 actag_pose *out)
 *       actag_pose_estimate(d->range, d->azimuth, d->mirrored, p, out), with
 *       its error codes; ACTAG_ERR_NULL also for d NULL.
 *   int actag_pose_from_camera(const float R_opt[9], const float t_opt[3], actag_pose *out)
 *       Camera pose in the optical frame (R row-major tag -> camera, t in
 *       metres) to the sensor frame; fills R, t, range, azimuth, elevation,
 *       zeroes the rest (no covariance: flags = ACTAG_POSE_NO_COVARIANCE;
 *       actag_pose_camera_covariance adds it).
 *       ACTAG_ERR_NULL, or ACTAG_ERR_PARAM (an entry not finite, or of t_opt
 *       beyond +-1e4 m), else ACTAG_OK.
 *   int actag_pose_camera_covariance(const float corners[8], float fx, float fy,
 *                                    float cx, float cy, float pixel_sd,
 *                                    float tag_size, actag_pose *pose)
 *       The covariance of a camera pose (pose->R, pose->t in the sensor
 *       frame, as actag_pose_from_camera leaves them) from the corner noise
 *       (CAMERA POSES above). fx, fy: focal lengths (px, 1 .. 1e6); cx, cy:
 *       principal point (px, within +-1e5; the centre of the top-left pixel
 *       at (0, 0), as actag_detection's corners); pixel_sd: sd of each
 *       measured corner coordinate (px, ACTAG_POSE_PIXEL_SD_MIN .. _MAX:
 *       1e-6 .. 1e3; 0.1-0.3 px is
 *       typical of AprilTag's corners on sharp images, more with blur or
 *       turbid water: measure it for your camera); tag_size: side of the
 *       inner white square (m). corners: the four measured corners of the
 *       inner white square in tag order (x0, y0, .. x3, y3; px), or NULL.
 *       Fills pose->cov and clears ACTAG_POSE_NO_COVARIANCE; with corners,
 *       also sets pose->residual to the RMS reprojection error of the
 *       corners in metres at each corner's depth (pixels x depth / focal
 *       length) and pose->chi2 to the sum of the 8 squared reprojection
 *       errors over pixel_sd^2 (about 2 expected: 8 coordinates - 6
 *       parameters); without, those stay as they are. A corner not in front
 *       of the camera (depth under tag_size / 1000: nothing to project, so
 *       residual and chi2 stay as they are too), or a Jacobian that is
 *       singular or leaves the float range (only absurd geometry does: even
 *       an edge-on tag's image changes at first order with every motion,
 *       its tilt best of all), sets ACTAG_POSE_DEGENERATE and leaves cov
 *       zero and ACTAG_POSE_NO_COVARIANCE set; that is not an error.
 *       Otherwise ACTAG_POSE_DEGENERATE is cleared (this function decides
 *       it for a camera pose); other flags are kept.
 *       Returns ACTAG_OK, ACTAG_ERR_NULL (pose NULL), ACTAG_ERR_PARAM (a
 *       value outside the ranges above, NaN included, tag_size outside 1e-3
 *       .. 1e4 m, an entry of pose->R not finite, of pose->t beyond +-1e4
 *       m, a corner coordinate beyond +-1e7 px), ACTAG_ERR_BUILD (compiled
 *       with fused multiply-adds or reciprocal divisions, as actag_detect).
 *       Nothing of *pose changes on an error.
 *   float actag_pose_angle(const float Ra[9], const float Rb[9])
 *       The angle (rad, 0..pi) of the rotation between Ra and Rb. This and
 *       actag_pose_rotation_vector check nothing and have no error codes.
 *   void actag_pose_rotation_vector(const float Ra[9], const float Rb[9], float w[3])
 *       w with Ra = exp([w]x) Rb (the covariance's rotation error).
 */
#ifndef ACTAG_POSE_H
#define ACTAG_POSE_H

#include "actag/actag.h"

#ifdef __cplusplus
extern "C" {
#endif

#ifndef ACTAG_POSE_RANGE_SD
#define ACTAG_POSE_RANGE_SD 0.0024f /* m: simulator, paper settings, refined corners */
#endif
#ifndef ACTAG_POSE_AZIMUTH_SD
#define ACTAG_POSE_AZIMUTH_SD 0.0013f /* rad */
#endif

/* Bounds of actag_pose_camera_covariance's pixel_sd (px), inclusive. */
#define ACTAG_POSE_PIXEL_SD_MIN 1.0e-6f
#define ACTAG_POSE_PIXEL_SD_MAX 1.0e3f

/* flags of actag_pose */
#define ACTAG_POSE_DEGENERATE 1u       /* image of the tag nearly a line (edge-on in the
                                          projection: all corners at one range or one
                                          azimuth), or a singular fit: orientation unreliable */
#define ACTAG_POSE_ELEVATION 2u        /* no elevation puts even the inner square inside the
                                          vertical aperture, or the fit left the band by
                                          more than 2 prior sds (see the manual) */
#define ACTAG_POSE_NOT_CONVERGED 4u    /* the last pass reached max_iterations before a
                                          step shorter than 1e-3 sd (see METHOD) */
#define ACTAG_POSE_MIRROR_CONFLICT 8u  /* the corners' winding contradicts `mirrored` */
#define ACTAG_POSE_NO_COVARIANCE 16u   /* cov not computed, all zero: camera poses
                                          without actag_pose_camera_covariance, and
                                          fits whose Jacobian is singular (then with
                                          ACTAG_POSE_DEGENERATE) */
#define ACTAG_POSE_PLANE 32u           /* the fit left the known plane by more than 3 of its
                                          sds (offset, or tilt): plane or corners wrong */

typedef struct actag_pose_params {
    float tag_size;          /* m, side of the inner white square */
    float vertical_aperture; /* rad, full width of the sonar's elevation fan */
    float extent;            /* side of the square that must lie inside the aperture, in
                                tag sizes (default: the whole tag, (k+1)/(k-3)) */
    float range_sd;          /* m, corner range noise (ACTAG_POSE_RANGE_SD) */
    float azimuth_sd;        /* rad, corner azimuth noise (ACTAG_POSE_AZIMUTH_SD) */
    int max_iterations;      /* trial steps per pass, 1..100 (20) */
    /* Optional: what the vehicle knows of the plane the tag lies on (see KNOWN PLANE).
     * Unused while plane_sd and plane_tilt_sd are both 0 (the default). */
    float plane[4];          /* (nx, ny, nz, d): the tag's face lies in n . p = d, sensor
                                frame, metres; n any length but not zero, |d| / |n|
                                at most 1e4 m */
    float plane_sd;          /* m, sd of the face centre's offset from the plane; 0: unused */
    float plane_tilt_sd;     /* rad, sd of the angle between the face normal and n; 0: unused */
} actag_pose_params;

typedef struct actag_pose {
    float R[9];        /* row-major rotation, tag -> sensor */
    float t[3];        /* m, tag centre in the sensor frame */
    float cov[36];     /* 6x6 row-major covariance of (dt, w), see the manual */
    float range;       /* m, |t| */
    float azimuth;     /* rad, atan2(t_y, t_x) */
    float elevation;   /* rad, asin(t_z / |t|) */
    float elevation_lo, elevation_hi; /* rad, band of centre elevations that keep the
                                         outline inside the aperture; where there is
                                         none, the inner square's (lo > hi: none either) */
    float residual;    /* m, RMS distance between measured and fitted corners in the fan
                          plane (range, range * azimuth) */
    float chi2;        /* sum of squared normalised corner residuals (8 terms, ~3 expected
                          with the assumed noise: 8 measurements - 6 + 1 prior) */
    int iterations;    /* trial steps taken over all passes */
    unsigned flags;    /* ACTAG_POSE_* */
} actag_pose;

void actag_pose_params_default(actag_pose_params *p, const actag_family *family,
                               float tag_size, float vertical_aperture);
int actag_pose_estimate(const float range[4], const float azimuth[4], int mirrored,
                        const actag_pose_params *p, actag_pose *out);
int actag_pose_from_detection(const actag_detection *d, const actag_pose_params *p,
                              actag_pose *out);
int actag_pose_from_camera(const float R_opt[9], const float t_opt[3], actag_pose *out);
int actag_pose_camera_covariance(const float corners[8], float fx, float fy, float cx, float cy,
                                 float pixel_sd, float tag_size, actag_pose *pose);
float actag_pose_angle(const float Ra[9], const float Rb[9]);
void actag_pose_rotation_vector(const float Ra[9], const float Rb[9], float w[3]);

#ifdef __cplusplus
}
#endif
#endif /* ACTAG_POSE_H */
