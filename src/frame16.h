/* 16-bit frames (actag_frame.depth 16): samples in host byte order at any
 * address, scaled to 8 bits by the frame's maximum, v8 = (v * 255 + max / 2)
 * / max (actag.h). Shared by the median (which scales rows as it reads them)
 * and the corner refinement (which reads the caller's frame). Internal. */
#ifndef ACTAG_FRAME16_H
#define ACTAG_FRAME16_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

/* One sample at p (memcpy: no misaligned halfword load, which faults on some
 * cores; compilers make it a plain load where that is allowed). */
static inline uint32_t frame16_load(const uint8_t *p)
{
    uint16_t v;
    memcpy(&v, p, sizeof v);
    return v;
}

/* The largest sample of a rows x cols frame (stride in samples). */
static inline uint32_t frame16_max(const uint8_t *src, int rows, int cols, size_t stride)
{
    uint32_t mx = 0, v;
    int r, c;
    for (r = 0; r < rows; r++)
        for (c = 0; c < cols; c++)
            if ((v = frame16_load(src + 2u * ((size_t)r * stride + (size_t)c))) > mx)
                mx = v;
    return mx;
}

/* actag_median_filter16() (median.h) for a frame whose largest sample is
 * max16 (0: scan the frame for it, as actag_median_filter16 does): the same
 * results. actag_detect scans a 16-bit frame once for the median and the
 * corner refinement (refine_frame.h). */
int actag__median_filter16_max(const void *src, uint32_t max16, int rows, int cols,
                               int src_stride, uint8_t *dst, int dst_stride, int radius,
                               void *scratch, size_t scratch_size);

#endif
