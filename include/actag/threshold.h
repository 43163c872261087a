/*
 * actag/threshold.h -- adaptive (local min/max) threshold of 8-bit images.
 *
 * MANUAL
 *   actag_adaptive_threshold() writes a binary image: for every pixel x,
 *   with mn and mx the minimum and maximum of the (2R+1) x (2R+1) window
 *   centred on it (R = radius, in pixels),
 *
 *       dst = 1  if  x >= (mn + mx) / 2 - offset   (exact real arithmetic,
 *                                                  i.e. 2x >= mn + mx - 2 offset)
 *       dst = 0  otherwise.
 *
 *   Output bytes are exactly 0 or 1. Pixels outside the image are replaced
 *   by the nearest edge pixel (edge replication), which for a min/max simply
 *   means the window is cut at the image border. offset may be any int,
 *   negative included; R may exceed the image size (the window then spans
 *   the whole image in that direction).
 *
 *     uint8_t scratch[ACTAG_THRESHOLD_SCRATCH_SIZE_R(530, 512, 8)];  (20,480 B)
 *     int rc = actag_adaptive_threshold(med, 530, 512, 512, bin, 512, 8, 1,
 *                                       scratch, sizeof scratch);
 *
 *   Images are row-major, one byte per pixel; the stride is the distance in
 *   bytes between the starts of two rows (>= cols). Bytes between cols and
 *   the stride are never read in src and never written in dst.
 *
 *   Algorithm: the window min and max are separable. A vertical pass and
 *   then a horizontal pass each use the van Herk / Gil-Werman scheme (block
 *   prefix and suffix extrema over blocks of 2R+1 samples, one comparison
 *   of a prefix and a suffix per output), so the work per pixel does not
 *   depend on R. The vertical pass works on whole rows at a time and only
 *   keeps the suffix extrema of one block of 2R+1 rows.
 *
 *   x86-64 (SSE2): the vertical pass as above, 16 columns per operation;
 *   the horizontal pass by doubling instead, as van Herk's scans go along
 *   the row a byte at a time: each row's vertical extrema go into two
 *   lines padded with R copies of the edge samples, in-place passes take
 *   them to extrema over h samples (h the smallest power of two with 3h >=
 *   2R+1: 3 passes at R = 8, so the work grows with log R), three such
 *   windows make each pixel's, and 16 pixels are thresholded at once (the
 *   bitmap takes their bits with one movemask). That path needs its two
 *   lines in the scratch: rows from 34 columns on for the bitmap and 58 for
 *   bytes at R = 8 (from 22 to 112 over R = 1 .. 33); narrower rows take
 *   the van Herk rows. A 530 x 512 frame at R = 8 on one core of our 2.3
 *   GHz VMs: about 0.09 ms into a bitmap and 0.10 ms into bytes, 5.3 and
 *   5.2 instructions per pixel (callgrind on the 58 pool frames), against
 *   0.40-0.42 ms and 28-29 per pixel with van Herk's horizontal scans.
 *   ACTAG_NO_SIMD selects the portable C path, identical output.
 *
 *   Portable C path: where the compiler has a vector unit to vectorize
 *   plain byte loops (SSE2, NEON, MVE, ...), the row operations are such
 *   loops. Elsewhere (Cortex-M3/M4/M7, other scalar cores; or any build
 *   with ACTAG_FORCE_SWAR defined, which the tests use) the vertical pass
 *   works a machine word at a time (8 or 4 byte lanes, SWAR min/max with
 *   integer operations only) and the horizontal pass is fused with the
 *   threshold (the block prefix extrema stay in registers). Measured as
 *   x86-64 gcc -O3 -fno-tree-vectorize instruction counts at R = 8: ~51 per
 *   pixel with 8-byte words and ~69 with 4-byte words (ACTAG_SWAR_WORD32,
 *   as on 32-bit cores), against ~73 for the plain byte loops: SWAR min/max
 *   costs about 15 integer operations per word, so on 32-bit cores nearly
 *   all of the gain is the fused horizontal pass. On cores with the DSP
 *   extension (__ARM_FEATURE_SIMD32: Cortex-M4/M7, and ARMv7-A builds without
 *   NEON such as Debian armhf) a 4-byte min or max is
 *   USUB8 + SEL, 2 instructions (ACTAG_NO_DSP: the portable words), and the
 *   horizontal pass works by doubling, a word at a time: 10.9 instead of
 *   19.5 million instructions per 530 x 512 frame at R = 8 on a Cortex-M7 at
 *   -O2 (QEMU -icount, tools/budget). At R = 8 into a bitmap (the
 *   detector's case) the DSP path goes further: the vertical prefix and
 *   window extrema in one pass into edge-padded lines, then per row one
 *   pass that takes each word's 17-wide window extrema from 4-sample ones,
 *   thresholds and packs the bits (assembly loops when optimizing, for
 *   268 to 1008 columns): 5.5 instead of 11.6 million (5.4 before the GE flags were masked) instructions per
 *   frame. Every variant gives the same bytes.
 *
 *   src and dst must not overlap (src == dst is rejected with
 *   ACTAG_ERR_PARAM; other overlaps are undefined behaviour).
 *
 * MEMORY
 *   scratch must hold ACTAG_THRESHOLD_SCRATCH_SIZE_R(rows, cols, radius)
 *   bytes: (2 * min(2R+1, rows) + 6) * cols. ACTAG_THRESHOLD_SCRATCH_SIZE
 *   (rows, cols) = (2 * rows + 6) * cols is enough for every radius. For
 *   530 x 512: 20,480 bytes at R = 8, 545,792 bytes for any R. No alignment
 *   is required. Stack use is a few hundred bytes (280 on a Cortex-M7 at
 *   -O2; 688 on x86-64 with gcc -O3, 1000 with clang).
 *
 * ERRORS
 *   ACTAG_ERR_NULL       src, dst or scratch is NULL
 *   ACTAG_ERR_SIZE       rows or cols < 1 or > ACTAG_MAX_DIM, or a stride < cols
 *   ACTAG_ERR_PARAM      radius < 0, or src == dst
 *   ACTAG_ERR_WORKSPACE  scratch_size < ACTAG_THRESHOLD_SCRATCH_SIZE_R(rows, cols, radius)
 *   Returns ACTAG_OK on success. On error dst is left untouched.
 */
#ifndef ACTAG_THRESHOLD_H
#define ACTAG_THRESHOLD_H

#include "actag/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Scratch bytes for one radius (radius >= 0): the suffix extrema of one
 * block of min(2R+1, rows) rows for the min and the max, plus six lines. */
#define ACTAG_THRESHOLD_SCRATCH_SIZE_R(rows, cols, radius)                               \
    ((2u * ((size_t)(radius) * 2u + 1u < (size_t)(rows) ? (size_t)(radius) * 2u + 1u     \
                                                         : (size_t)(rows)) + 6u) *       \
     (size_t)(cols))

/* Scratch bytes that suffice for every radius. */
#define ACTAG_THRESHOLD_SCRATCH_SIZE(rows, cols) ((2u * (size_t)(rows) + 6u) * (size_t)(cols))

int actag_adaptive_threshold(const uint8_t *src, int rows, int cols, int src_stride,
                             uint8_t *dst, int dst_stride, int radius, int offset,
                             void *scratch, size_t scratch_size);

/* Scratch bytes of actag_adaptive_threshold_bitmap(): one row more. */
#define ACTAG_THRESHOLD_BITMAP_SCRATCH_SIZE_R(rows, cols, radius)                        \
    (ACTAG_THRESHOLD_SCRATCH_SIZE_R(rows, cols, radius) + (size_t)(cols))

/* The same threshold written as a bitmap (common.h layout: one bit per
 * pixel, 1 = white, ACTAG_BITMAP_SIZE(rows, cols) bytes, every padding bit
 * 0), for the contour scanner (contours.h). Pixel (r, c) of the bitmap equals
 * byte (r, c) of actag_adaptive_threshold()'s output. scratch: at least
 * ACTAG_THRESHOLD_BITMAP_SCRATCH_SIZE_R(rows, cols, radius) bytes (each row
 * is computed as bytes in the last cols of them, then packed). Errors as
 * actag_adaptive_threshold (ACTAG_ERR_PARAM for src == bitmap); on error
 * the bitmap is left untouched. */
int actag_adaptive_threshold_bitmap(const uint8_t *src, int rows, int cols, int src_stride,
                                    uint32_t *bitmap, int radius, int offset, void *scratch,
                                    size_t scratch_size);

#ifdef __cplusplus
}
#endif
#endif /* ACTAG_THRESHOLD_H */
