/*
 * actag/actag_apriltag.h -- read AcTags in camera images with AprilTag 3.
 *
 * MANUAL
 *   AcTags are built so that an ordinary camera can read them too: the AcTag
 *   families are valid AprilTag 3 "reversed border" families. This optional
 *   library (libactag_apriltag, CMake target actag::actag_apriltag) hands the
 *   AcTag families built into actag (CMake variable ACTAG_FAMILIES) to
 *   AprilTag 3 as apriltag_family_t objects, plus a few helpers. It is
 *   built only when libapriltag is found. Unlike the actag core it allocates
 *   (AprilTag does) and it is host-only.
 *
 *     #include <actag/actag_apriltag.h>
 *
 *     apriltag_family_t *fam = actag_apriltag_family("AcTag24h10");
 *     apriltag_detector_t *td = apriltag_detector_create();
 *     apriltag_detector_add_family_bits(td, fam,
 *                                       actag_apriltag_max_bits_corrected(fam));
 *     actag_apriltag_invert(im);             // camera: aluminium light, foam dark
 *     zarray_t *dets = actag_apriltag_detect(td, im);   // AprilTag + mirror check
 *     for (int i = 0; i < zarray_size(dets); i++) {
 *         apriltag_detection_t *det;
 *         double c[4][2];
 *         zarray_get(dets, i, &det);
 *         actag_apriltag_corners_to_actag(det, c);
 *         printf("id %d top-left corner (%.2f, %.2f)\n", det->id, c[0][0], c[0][1]);
 *     }
 *     apriltag_detections_destroy(dets);
 *     apriltag_detector_destroy(td);         // also frees fam's decode table
 *
 *   Link with $(pkg-config --cflags --libs actag_apriltag): -lactag_apriltag,
 *   libactag, -lapriltag and, on Debian, -lapriltag-utils for AprilTag's image
 *   helpers (image_u8_create, image_u8_create_from_pnm), which its
 *   apriltag.pc omits. (CMake: find_package(actag COMPONENTS apriltag),
 *   target actag::actag_apriltag.)
 *
 * IMAGE POLARITY
 *   Acoustically foam is bright and aluminium dark; optically aluminium is the
 *   lighter one, so a camera image must be inverted (actag_apriltag_invert)
 *   before AprilTag sees it. Then bit 1 (foam) is white, the black ring is
 *   black and the inner square is white, as the family describes.
 *
 * FAMILY OBJECTS AND AprilTag's DECODE TABLE
 *   apriltag_detector_add_family_bits() builds a quick-decode hash table for
 *   the family and stores it in family->impl, *only if impl is NULL*; the
 *   detector frees it (and resets impl to NULL) in
 *   apriltag_detector_remove_family(), _clear_families() and _destroy().
 *   AprilTag 3.3 offers no other way to free it. Therefore:
 *   - actag_apriltag_family(name) returns one static object per family. Add it
 *     to at most ONE detector at a time, and destroy or remove it from that
 *     detector before adding it to another one. (A second detector would share
 *     the first one's table, built for the first one's bits_corrected, and
 *     crash once the first detector frees it.) Not thread-safe for the same
 *     reason.
 *   - actag_apriltag_family_create(name) returns a fresh heap copy (the code
 *     and bit-position arrays are shared, read-only) for programs that run
 *     several detectors at once; each copy may be added to one detector.
 *     Release it with actag_apriltag_family_destroy() AFTER the detector that
 *     used it has been destroyed (or the family removed from it), exactly like
 *     AprilTag's own tag36h11_create()/tag36h11_destroy().
 *   bits_corrected: AprilTag supports 0..3; AcTag families can correct at most
 *   h/2-1 bits (even h) or floor(h/2) (odd h). actag_apriltag_max_bits_corrected()
 *   gives the smaller of the two. AprilTag's table has
 *   3 * ncodes * (1 + n + n(n-1) + n(n-1)(n-2)) entries of 16 bytes (terms up
 *   to bits_corrected, n = nbits): AcTag24h4 with 1 bit 7.5 MB (with 2 bits,
 *   beyond that family's limit, 173 MB); AcTag24h10 with 3 bits 4.3 MB.
 *
 * GEOMETRY
 *   The family is laid out exactly as the printed AcTag (SPEC section 2):
 *   width_at_border = k-3, total_width = k+1, reversed_border = true, where the
 *   tag has 4k data bits. AprilTag's quad is the edge between the black ring and
 *   the inner white square, so
 *   - detection corners (det->p) are the corners of the inner white square;
 *   - the tagsize of AprilTag's pose estimation (estimate_tag_pose) is the side
 *     of the inner white square, which is exactly AcTag's tag_size
 *     (e.g. 3/7 ft = 0.130628571 m for a 1 ft, 24-bit tag).
 *   AprilTag returns det->p as bottom-left, bottom-right, top-right, top-left
 *   of the tag as printed (counter-clockwise in the image), and its pixel
 *   coordinates put the centre of pixel (row r, column c) at (c+0.5, r+0.5).
 *   actag_apriltag_corners_to_actag() converts both to the actag conventions.
 *   AprilTag's pose: R, t map tag coordinates to camera coordinates; the tag
 *   frame has its origin at the tag centre, x towards the printed right edge,
 *   y towards the printed bottom edge, z into the tag; camera x right, y down,
 *   z forward. AprilTag's estimate_tag_pose() wants cx, cy in its own pixel
 *   convention (0.5 more than a principal point calibrated with pixel centres
 *   at integers, e.g. by OpenCV) and returns matd_t matrices; Debian's
 *   packages do not export matd_destroy(), so use actag_apriltag_pose().
 *   Mirrored tags: see MIRRORED TAGS.
 *   Accuracy on synthetic renders (tests): corners within 0.2 px, with a
 *   bias of about -0.05 to -0.13 px from AprilTag's edge refinement.
 *
 * MIRRORED TAGS
 *   A tag seen in a mirror (or from behind, through a clear plate) shows its
 *   layout reflected: read clockwise from a corner, its data ring is
 *   P(rot90^r(code)) (P = actag_code_mirror, family.h; docs/families.md).
 *   AprilTag matches only the 4 rotations of each code, so what it makes of
 *   such a view depends on how near the family's mirrored views come to its
 *   codes (over all bits):
 *   - mirror-safe for the camera: the "m" families (AcTag24m4 .. m10,
 *     AcTag28m4 .. m10: every mirrored view at least h bits from every code
 *     in every rotation) and AcTag24h10 (at least 6 bits). AprilTag
 *     corrects at most 3 bits, so it reads no clean mirrored view of these.
 *   - NOT mirror-safe: the published AcTag24h4 (the mirrored views of 29
 *     codes are exactly a rotation of a code, e.g. IDs 402 and 2046 of each
 *     other, ID 291 of itself; those of 210 more lie 1 bit from one),
 *     AcTag24h6 (37 codes at 2 bits) and AcTag24h8 (ID 30, 2 bits from its
 *     own mirrored view). apriltag_detector_detect() reads such views as a
 *     WRONG ID (AcTag24h6 ID 52 mirrored left-right: ID 189, hamming 2;
 *     AcTag24h4 ID 1: ID 5000, hamming 1) or as the right ID with its
 *     corners turned by 90 degrees (AcTag24h8 ID 30: a wrong pose), and
 *     nothing in the detection tells.
 *   actag_apriltag_detect() therefore judges every detection of a built-in
 *   AcTag family (actag_apriltag_mirror_check) and removes from the array
 *   (and frees) each one that a mirrored view explains at least as well:
 *   1. it reads the tag's cells again through det->H (the grey level at each
 *      cell centre, as AprilTag reads it; planes fitted to the black ring's
 *      and to the white interior's cells, without the ring's 4 corner cells,
 *      which hold the tag's screws; each cell against the mid level between
 *      the two planes; AprilTag's decode_sharpening), giving the word w;
 *   2. d = the bits where w differs from the reported code as reported
 *      (det->id in det->H's orientation, i.e. with its corners);
 *   3. the detection is dropped when any code of the family, mirrored and
 *      then rotated in any of 4 ways (the reported code itself included),
 *      lies within d bits of w. A reading with corrected bits is also
 *      dropped when its own black ring and white interior do not read as
 *      such (more than 2 of those cells, the ring's corner cells aside, on
 *      the wrong side of the mid level or outside the image), and any
 *      reading when there is no contrast: there is then no reading to judge
 *      (AprilTag's bogus quads on clutter, below). A reading of no corrected
 *      bit is not judged by its ring and interior: an occluder there (a
 *      fish, a weed) must not cost a code read whole. Cells outside the
 *      image do not count in 2-3.
 *   Effects (test_apriltag_mirror_check: every ID of AcTag24h6/h8/h10 and
 *   the m families of at most 500 codes, about 90 of the others, mirrored
 *   left-right in 4 rotations, sharp and blurred): AprilTag alone reported
 *   32 of 736 mirrored AcTag24h4 tag images (all wrong IDs), 296 of 3624
 *   AcTag24h6 (240 wrong IDs, 56 the own ID with turned corners) and 8 of
 *   360 AcTag24h8 (ID 30, turned corners), none of the other families;
 *   actag_apriltag_detect() none. Every unmirrored tag of those renders is
 *   still reported, with its ID and corners. But:
 *   - the 29 AcTag24h4 IDs whose view equals a mirrored view of a code are
 *     never reported, even as printed (they cannot be told from that
 *     mirror image): 291 402 655 850 887 1033 1093 1531 1587 1801 1886
 *     2027 2046 2287 2828 3071 3209 3268 3284 3376 3789 4269 4557 5221
 *     5235 6170 6179 6186 6220. Do not deploy them;
 *   - a reading with corrected bits is dropped when a mirrored view lies as
 *     near (AcTag24h4's 210 codes 1 bit from a mirrored view, when the
 *     error is that bit; AcTag24h6's 37 codes 2 bits from one, when one of
 *     those 2 bits is misread);
 *   - the protection of AcTag24h4, h6 and h8 is partial: where noise, blur
 *     and perspective make the re-read word nearer a wrong code than to any
 *     mirrored view, a mirrored tag is still reported as that code (reviews'
 *     trials of noisy projective mirrored views: 4 AcTag24h4 readings at
 *     hamming 1 and 1 AcTag24h6 at hamming 2 in 1,500 views each, against 90
 *     and 140 from AprilTag alone; 1 of the 38 AcTag24h8 readings AprilTag
 *     made of 2,000 views at 5 px a cell, blur 1.5, noise 15). Where a mirror
 *     image can occur, use a mirror-safe family.
 *   Drops are not counted anywhere. apriltag_detector_detect() still
 *   reports everything AprilTag reads (no check; mind the small-image limit
 *   of actag_apriltag_detect below): a program that knows no mirror image
 *   can occur may call it, and actag_apriltag_mirror_check() on its
 *   detections, to see or count what the check drops.
 *   Cost per detection: (k+1)^2 cells projected and sampled, two 3 x 3
 *   solves, then 4 comparisons per code of the family (branch-free and
 *   vectorised): 1-5 us on a desktop core, the most for AcTag24h4 and
 *   AcTag28m4 (6,261 and 8,910 codes). No heap, no static state.
 *
 * FALSE DETECTIONS
 *   With bits_corrected at the family's limit AprilTag now and then reads a
 *   slim bogus quad inside a tag's data ring as another ID with corrected
 *   bits (3 of 3624 clean AcTag24h6 renders with 2 bits; none with h8/h10 at
 *   2 bits or h4 at 1 bit). actag_apriltag_detect() drops all three (their
 *   black ring and white interior do not read as such, MIRRORED TAGS), as
 *   it dropped every such reading of noisy, blurred projective renders in
 *   our trials; apriltag_detector_detect() keeps them. Prefer hamming 0 and
 *   a high decision_margin, or use fewer corrections, where false IDs are
 *   costly.
 *
 * FUNCTIONS
 *   apriltag_family_t *actag_apriltag_family(const char *name)
 *       The static family of that exact name ("AcTag24h10"); NULL if the name
 *       is NULL or not among the built-in families. See the rules above.
 *   int actag_apriltag_family_count(void)
 *       Number of built-in families (the entries of ACTAG_FAMILIES).
 *   const char *actag_apriltag_family_name(int i)
 *       Name of the i-th family, 0 <= i < count; NULL when out of range.
 *   apriltag_family_t *actag_apriltag_family_create(const char *name)
 *       A new heap copy of the family with impl = NULL; NULL if the name is
 *       NULL or unknown or memory runs out.
 *   void actag_apriltag_family_destroy(apriltag_family_t *fam)
 *       Frees a copy made by actag_apriltag_family_create(). Ignores NULL and
 *       the static families. fam->impl must already be NULL (detector gone).
 *   int actag_apriltag_max_bits_corrected(const apriltag_family_t *fam)
 *       min(3, AcTag's correction limit for fam->h); -1 for NULL.
 *   double actag_apriltag_pose(const apriltag_detection_t *det, double tag_size,
 *                              double fx, double fy, double cx, double cy,
 *                              double R[9], double t[3])
 *       The tag's pose by AprilTag's estimate_tag_pose(). tag_size: AcTag's
 *       tag_size (side of the inner white square), metres; fx, fy: focal
 *       lengths in pixels; cx, cy: principal point in pixels with the centre of
 *       the top-left pixel at (0,0) (the 0.5 shift is added here). R: row-major
 *       rotation tag -> camera; t: tag centre in camera coordinates, metres.
 *       Returns AprilTag's object-space error (>= 0), or -1 (R, t untouched)
 *       for NULL arguments, a value outside its bounds (tag_size 1e-3 .. 1e4
 *       m, fx and fy 1 .. 1e6 px, cx and cy within +-1e5 px: the
 *       ACTAG_APRILTAG_* limits below; NaN and infinities are outside), a tag
 *       that subtends too small an angle (the rays through its opposite
 *       corners under ACTAG_APRILTAG_MIN_SPREAD = 5e-4 rad apart: 5 px at a
 *       focal length of 1e4 px) or a failed estimate. (AprilTag itself
 *       aborts the process below about 1e-4 rad; the checks keep such
 *       input from it.)
 *   int actag_apriltag_pose_sensor(const apriltag_detection_t *det, double tag_size,
 *                                  double fx, double fy, double cx, double cy,
 *                                  actag_pose *out)
 *       The same pose in the sensor frame shared with the sonar (actag/pose.h:
 *       x forward along the optical axis, y left, z up; the same tag frame):
 *       actag_apriltag_pose() then actag_pose_from_camera(). out->cov is not
 *       computed (flags ACTAG_POSE_NO_COVARIANCE); out->residual holds
 *       AprilTag's object-space error. Returns ACTAG_OK, ACTAG_ERR_NULL
 *       (det or out NULL) or ACTAG_ERR_PARAM (bad sizes or a failed estimate).
 *   int actag_apriltag_pose_sensor_cov(const apriltag_detection_t *det,
 *                                      double tag_size, double fx, double fy,
 *                                      double cx, double cy, double pixel_sd,
 *                                      actag_pose *out)
 *       actag_apriltag_pose_sensor() with the covariance the sonar's poses
 *       have (actag_pose_camera_covariance, actag/pose.h): pixel_sd is the sd
 *       of each detected corner coordinate in pixels (1e-6 .. 1e3; measure it
 *       for your camera and water: 0.1-0.3 px on sharp images). out->cov is
 *       filled (ACTAG_POSE_NO_COVARIANCE cleared unless the geometry is
 *       degenerate), out->residual is the corners' RMS reprojection error in
 *       metres at their depth (AprilTag's object-space error, as above, when
 *       a corner lies behind the camera), out->chi2 their sum of squared reprojection
 *       errors over pixel_sd^2 (about 2 expected; much more means a wrong
 *       pixel_sd, a distorted image or a bad detection). Returns ACTAG_OK,
 *       ACTAG_ERR_NULL (det or out NULL), ACTAG_ERR_PARAM (pixel_sd out of
 *       range, else as actag_apriltag_pose_sensor), ACTAG_ERR_BUILD (as
 *       actag_pose_camera_covariance); *out is untouched on an error.
 *   zarray_t *actag_apriltag_detect(apriltag_detector_t *td, image_u8_t *im)
 *       apriltag_detector_detect(td, im) without the detections that
 *       actag_apriltag_mirror_check() (with td->decode_sharpening) judges
 *       1 or 2 (MIRRORED TAGS; the others keep their order; detections of
 *       other families added to td are kept), safe on small images: AprilTag 3.3
 *       reads outside its buffers (and crashes) when the decimated image is
 *       under 4 pixels in either direction (e.g. under 8 rows at the default
 *       quad_decimate 2), so images of fewer than 4 * max(quad_decimate, 1)
 *       rows or columns (rounded up) give an empty array (no tag fits there:
 *       a tag is at least 8 cells wide). Free the result with
 *       apriltag_detections_destroy(). NULL for a NULL detector, image or
 *       pixel buffer, or a width/height/stride that does not describe one.
 *   int actag_apriltag_mirror_check(const apriltag_detection_t *det,
 *                                   const image_u8_t *im)
 *       The check of MIRRORED TAGS for one detection of
 *       apriltag_detector_detect(td, im) (im: the image AprilTag read, after
 *       actag_apriltag_invert; decode_sharpening taken as AprilTag's default,
 *       ACTAG_APRILTAG_SHARPENING). Returns 0: the reading stands (no
 *       mirrored view is as near); 1: a mirrored view of some code explains
 *       the tag's cells at least as well as the reading; 2: no reading to
 *       judge (no contrast; a reading with corrected bits whose black ring
 *       and white interior do not read as such; a det whose H is not 3 x 3
 *       or whose ID is not one of its family's); -1: det or im NULL, im not an image actag_apriltag_detect
 *       takes, or det->family not a built-in AcTag family (static or copy).
 *       Only reads det and im.
 *   void actag_apriltag_invert(image_u8_t *im)
 *       In place: v -> 255 - v over width x height (stride respected). NULL
 *       ok; an image actag_apriltag_detect would refuse (width or height
 *       under 1, stride under width) is left untouched.
 *   void actag_apriltag_corners_to_actag(const apriltag_detection_t *det,
 *                                        double out[4][2])
 *       The four corners of the inner white square in AcTag order: top-left
 *       of the printed tag first, then clockwise as printed (top-right,
 *       bottom-right, bottom-left). out[i][0] = x (column), out[i][1] = y
 *       (row), pixels, with the centre of pixel (row r, column c) at (c, r) as
 *       everywhere in actag (i.e. AprilTag's coordinates minus 0.5).
 */
#ifndef ACTAG_APRILTAG_H
#define ACTAG_APRILTAG_H

#include <apriltag/apriltag.h>

#include "actag/pose.h"

#ifdef __cplusplus
extern "C" {
#endif

/* actag_apriltag_pose()'s bounds (see there) */
#define ACTAG_APRILTAG_MIN_TAG_SIZE 1e-3 /* metres */
#define ACTAG_APRILTAG_MAX_TAG_SIZE 1e4
#define ACTAG_APRILTAG_MIN_FOCAL 1.0 /* pixels */
#define ACTAG_APRILTAG_MAX_FOCAL 1e6
#define ACTAG_APRILTAG_MAX_CENTRE 1e5 /* |cx|, |cy|, pixels */
#define ACTAG_APRILTAG_MIN_SPREAD 5e-4 /* radians between opposite corners' rays */
/* decode_sharpening of actag_apriltag_mirror_check() (AprilTag's default) */
#define ACTAG_APRILTAG_SHARPENING 0.25

apriltag_family_t *actag_apriltag_family(const char *name);
int actag_apriltag_family_count(void);
const char *actag_apriltag_family_name(int i);
apriltag_family_t *actag_apriltag_family_create(const char *name);
void actag_apriltag_family_destroy(apriltag_family_t *fam);
int actag_apriltag_max_bits_corrected(const apriltag_family_t *fam);
double actag_apriltag_pose(const apriltag_detection_t *det, double tag_size,
                          double fx, double fy, double cx, double cy,
                          double R[9], double t[3]);
int actag_apriltag_pose_sensor(const apriltag_detection_t *det, double tag_size, double fx,
                               double fy, double cx, double cy, actag_pose *out);
int actag_apriltag_pose_sensor_cov(const apriltag_detection_t *det, double tag_size, double fx,
                                   double fy, double cx, double cy, double pixel_sd,
                                   actag_pose *out);
zarray_t *actag_apriltag_detect(apriltag_detector_t *td, image_u8_t *im);
int actag_apriltag_mirror_check(const apriltag_detection_t *det, const image_u8_t *im);
void actag_apriltag_invert(image_u8_t *im);
void actag_apriltag_corners_to_actag(const apriltag_detection_t *det, double out[4][2]);

#ifdef __cplusplus
}
#endif
#endif /* ACTAG_APRILTAG_H */
