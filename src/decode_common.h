/*
 * decode_common.h -- internal: what the binary decoder (decode_binary.c)
 * and the grid-fit decoder (decode_fit.c) both do around their reading.
 */
#ifndef ACTAG_SRC_DECODE_COMMON_H
#define ACTAG_SRC_DECODE_COMMON_H

#include "actag/decode.h"

/* The image checks of decode.h (ACTAG_ERR_NULL, ACTAG_ERR_SIZE). */
static inline int decode_check_image(const uint8_t *img, int rows, int cols, int stride)
{
    if (img == NULL)
        return ACTAG_ERR_NULL;
    if (rows < 1 || cols < 1 || rows > ACTAG_MAX_DIM || cols > ACTAG_MAX_DIM || stride < cols)
        return ACTAG_ERR_SIZE;
    return ACTAG_OK;
}

/* The image, then the family (ACTAG_ERR_FAMILY), in the decoders' order. */
static inline int decode_check_frame_family(const uint8_t *img, int rows, int cols, int stride,
                                            const actag_family *family)
{
    int rc = decode_check_image(img, rows, cols, stride);
    return rc != ACTAG_OK ? rc : actag_family_validate(family);
}

/* max_corrections within 0..the family's largest (ACTAG_ERR_CORRECTIONS). */
static inline int decode_check_corrections(const actag_family *family, int max_corrections)
{
    int maxc = actag_family_max_corrections(family);
    return max_corrections < 0 || max_corrections > maxc ? ACTAG_ERR_CORRECTIONS : ACTAG_OK;
}

/* Fills id, hamming, mirrored, rotation, mirror_margin and the corners in
 * tag order from the clockwise-on-screen quad q, for reading m (m->mirrored:
 * P(observed) == rot^r(code)) whose other handedness is best at `other`
 * corrected bits. mirror_margin = other - m->hamming may be negative when
 * the fit decoder's likelihood prefers the reading with more flipped bits.
 *   unmirrored, observed == rot^r(code): screen cell s shows code cell
 *     s + rk, so q[n] is printed corner n + r;
 *   mirrored, P(observed) == rot^r(code): screen cell s shows code cell
 *     rk - s, so q[n] is printed corner r - n. */
static inline void decode_set_reading(actag_decode_result *out, const actag_point q[4],
                                      const actag_match *m, int other)
{
    out->id = m->id;
    out->hamming = m->hamming;
    out->mirrored = m->mirrored;
    out->rotation = m->rotation;
    out->mirror_margin = other - m->hamming;
    actag_tag_corners(q, m->rotation, m->mirrored, out->corners);
}

#endif /* ACTAG_SRC_DECODE_COMMON_H */
