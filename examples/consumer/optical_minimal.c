/*
 * optical_minimal.c -- a program using the installed libactag_apriltag with
 * AprilTag 3: renders AcTag24h10 tag 3 as a camera sees it (actag's renderer),
 * hands it to AprilTag in an image_u8_t (AprilTag's image helpers: on Debian
 * they live in libapriltag-utils) through actag_apriltag_detect (AprilTag
 * without the readings a mirror image explains as well, and safe on tiny
 * images) and prints what it reads.
 *
 *   cc optical_minimal.c $(pkg-config --cflags --libs actag_apriltag) -o optical_minimal
 */
#include <stdio.h>

#include <actag/actag.h>
#include <actag/actag_apriltag.h>
#include <actag/render.h>

#include <apriltag/apriltag.h>
#include <apriltag/common/image_u8.h>

int main(void)
{
    static uint8_t tag[ACTAG_RENDER_IMAGE_SIZE(24, 10, 20)];
    actag_family core;
    apriltag_family_t *fam;
    apriltag_detector_t *td;
    image_u8_t *im;
    zarray_t *dets;
    int side, x, y, i, found = 0;

    if (actag_family_get("AcTag24h10", &core) != ACTAG_OK ||
        (fam = actag_apriltag_family("AcTag24h10")) == NULL) {
        fprintf(stderr, "optical_minimal: AcTag24h10 is not built in\n");
        return 1;
    }
    side = actag_render_side(core.bits, 10, 20);
    /* camera colours: aluminium light, foam dark, a light surround */
    if (actag_render_tag(&core, 3, 10, 20, 255, 1, tag, side, sizeof tag) != ACTAG_OK)
        return 1;
    im = image_u8_create((unsigned)side, (unsigned)side);
    for (y = 0; y < side; y++)
        for (x = 0; x < side; x++)
            im->buf[y * im->stride + x] = tag[y * side + x];
    actag_apriltag_invert(im); /* what every camera image needs before AprilTag */

    td = apriltag_detector_create();
    td->nthreads = 1;
    apriltag_detector_add_family_bits(td, fam, actag_apriltag_max_bits_corrected(fam));
    dets = actag_apriltag_detect(td, im); /* NULL only for a bad detector or image */
    if (dets == NULL)
        return 1;
    for (i = 0; i < zarray_size(dets); i++) {
        apriltag_detection_t *det;
        double c[4][2];
        zarray_get(dets, i, &det);
        actag_apriltag_corners_to_actag(det, c);
        printf("AprilTag read AcTag24h10 id %d, hamming %d, top-left corner (%.1f, %.1f)\n",
               det->id, det->hamming, c[0][0], c[0][1]);
        found += det->id == 3;
    }
    apriltag_detections_destroy(dets);
    apriltag_detector_destroy(td);
    image_u8_destroy(im);
    return found == 1 && i == 1 ? 0 : 1;
}
