/*
 * actag/median.h -- constant-time square median filter for 8-bit images.
 *
 * MANUAL
 *   actag_median_filter() replaces every pixel by the median of the
 *   (2R+1) x (2R+1) window centred on it (R = radius, in pixels). Pixels
 *   outside the image are replaced by the nearest edge pixel (edge
 *   replication: row and column indices are clamped into the image), so the
 *   window always holds exactly (2R+1)^2 samples and the result is its exact
 *   middle element. R = 0 copies the image. R may exceed the image size.
 *
 *     static uint8_t scratch[ACTAG_MEDIAN_SCRATCH_SIZE(530, 512)];
 *     int rc = actag_median_filter(img, 530, 512, 512, out, 512, 4,
 *                                  scratch, sizeof scratch);
 *
 *   Images are row-major, one byte per pixel; the stride is the distance in
 *   bytes between the starts of two rows (>= cols). Bytes between cols and
 *   the stride are never read in src and never written in dst.
 *
 *   Algorithm: Perreault & Hebert, "Median filtering in constant time"
 *   (IEEE TIP 2007): one histogram per image column, slid down one row at a
 *   time, and a kernel histogram slid along the row by adding one column
 *   histogram and removing another. Histograms have two levels (16 coarse
 *   bins of 16 grey levels, 256 fine bins); the fine level of the kernel is
 *   only brought up to date, lazily, for the coarse bin that holds the
 *   median. Integer arithmetic only; the work per pixel does not depend on R
 *   (the set-up per row is O(R)). Frames wider than ACTAG_MEDIAN_HIST_COLS
 *   (256) columns are filtered in vertical strips, so that at most 256
 *   column histograms exist at a time (see MEMORY). On x86-64 an SSE2 path and
 *   on ARM with NEON (AArch64, ARMv7-A with -mfpu=neon, little-endian) the
 *   same path over NEON vectors is used (radii >= 8: this scheme in 16-byte
 *   lanes; radii 1..7: below; "SSE2 path" below means either);
 *   defining ACTAG_NO_SIMD when building the library selects the portable
 *   C path, which gives identical output. On x86-64 processors with AVX2
 *   (checked at run time; the library itself is built for baseline
 *   x86-64) radii 1..7 take the same scheme on 32 output rows at a time
 *   (8.5 instead of 11.9 million instructions per pool frame at R = 4,
 *   about 0.72 instead of 0.88 ms); ACTAG_NO_AVX2 compiles that path out.
 *   At radius 4 (the default) every vector path (AVX2, SSE2, NEON) takes
 *   sorting networks instead (after Adams 2021, "Fast median filters using
 *   separable sorting networks"): 2 x 2 tiles of outputs, one a byte lane,
 *   built from sorted pieces that neighbouring tiles share
 *   (src/median_net.h, the networks generated and checked by
 *   tools/gen_median_net.py): 3.7 instead of 8.5 million instructions per
 *   pool frame with AVX2 (about 0.37 instead of 0.85 ms), 8.5 instead of
 *   12.0 with SSE2 (about 0.53 instead of 1.0 ms).
 *   Identical output on every path.
 *
 *   SSE2 path, radii 1..7: Huang's sliding histogram shared by 16 output
 *   rows, one 16-byte vector of the 16 windows' 8-bit counts per grey
 *   level; moving the windows one column right, each of the 2R+16 source
 *   rows of the block adds its entering sample to and removes its leaving
 *   one from the windows that hold the row (a lane mask), and the 16
 *   medians are found together by a vector scan of the levels from the
 *   previous column's lowest median (rows far apart: two groups, one
 *   scanned down from the top). On the 58 pool frames (530 x 512, gcc -O3,
 *   callgrind) 43.8 instructions per pixel at R = 4 instead of 91.3 for
 *   the constant-time SSE2 path (R = 1: 43 vs 90, R = 7: 49 vs 93, first
 *   10 frames), and about 1.0 ms per frame instead of 1.5-1.6 at R = 4 on
 *   one core of a 2-core VM (stage_bench; ranges in the commit). The
 *   cost depends on the content, unlike the constant-time path: images
 *   whose neighbouring rows alternate between 3 or more far apart grey
 *   levels (synthetic bands a few rows high) take up to about 2x the
 *   constant-time path's instructions; every frame of bench/worst_bench
 *   (checkerboards, speckle, blobs, stripes, noise) takes fewer.
 *
 *   Portable path (no SSE2 or NEON: Cortex-M, ARM without NEON, or
 *   ACTAG_NO_SIMD), radii 1..7:
 *   Huang's sliding histogram instead, one 256-bin histogram shared by four
 *   output rows (their four 8-bit counts packed in one 32-bit word per
 *   level, so a sample entering or leaving costs one update for all the
 *   windows it belongs to) and the four "samples below the median" counts
 *   updated together in 16-bit lanes of a 64-bit word. O(R) per pixel but
 *   plain integer operations only: at R = 4 about 3.3x fewer instructions
 *   than the portable constant-time path (x86-64 gcc -O3: ~129 vs ~431 per
 *   pixel; ~128 vs ~534 with -fno-tree-vectorize, closer to a scalar core)
 *   and about 3x less time. A constant 2 KiB table (bcast16_tab) goes to
 *   read-only memory. On cores with the DSP extension (__ARM_FEATURE_SIMD32,
 *   little-endian: Cortex-M4/M7, and ARMv7-A builds without NEON such as
 *   Debian armhf) the four windows' counts of samples <= their
 *   medians are 8-bit lanes of one word (MUL + USUB8 + SEL a sample, no
 *   table), a source row's histogram and count update is one 17-instruction
 *   asm block, and the median search reads a window's lane as a byte
 *   (ACTAG_NO_DSP: the 16-bit lanes); at R >= 3 eight rows share a pass
 *   where they can, with an indicator byte (level <= median) per level and
 *   window. At R = 4 on a 530 x 512 frame that is 14.2 million
 *   instructions on a Cortex-M7 at -O2, about 52 per pixel (was 30.1 M,
 *   111), 14.3 M at -Os, 14.2 M on a Cortex-M4 at -O2 (QEMU -icount,
 *   tools/budget, the README's table; the portable lanes: about 51 M). It needs no
 *   scratch (the scratch size is still checked, so that one size fits every
 *   radius). Radii >= 8 use the constant-time path.
 *
 *   src and dst must not overlap (src == dst is rejected with
 *   ACTAG_ERR_PARAM; other overlaps are undefined behaviour).
 *
 * MEMORY
 *   The caller provides `scratch` of at least
 *   ACTAG_MEDIAN_SCRATCH_SIZE(rows, cols) bytes: 272 bytes of 8-bit column
 *   histograms for each of min(cols, 256) columns and 2 bytes per column
 *   for two rows of actag_median_filter16's ring; it scales with cols only
 *   (70,656 bytes for 512 columns, 274 per column up to 256 columns, then 2
 *   more per column; whatever the number of rows or the radius). No
 *   alignment is required. The kernel histograms live on the stack (under
 *   1 KiB; 1.4 KiB for the summed columns of R >= 64 on wide frames; the
 *   portable path's four-row histogram for R <= 7 under 1.5 KiB; the SSE2
 *   path's 16-row histogram for R <= 7 about 11 KiB: 512 levels of 16
 *   lanes, half of them spare, and the medians of 64 columns awaiting
 *   their transposition into the output; the AVX2 path's 32-row one about
 *   22 KiB; at radius 4 the sorting networks of the AVX2, SSE2 and NEON
 *   paths about 14 KiB).
 *   scratch is checked for every radius, R = 0 included.
 *
 *   Strips: with H column histograms (H = as many as fit next to the two
 *   ring rows, at least min(cols, 256); a larger scratch gives more), a
 *   frame of cols <= H columns is one strip; wider frames are cut into
 *   vertical strips whose histograms cover the strip and the R + 1 columns
 *   left of it and R right of it (clamped at the image edges): the first
 *   strip is H - R columns wide, the others H - 2R - 1 (at 512 columns and
 *   R = 4: 3 strips, 530 column histograms slid per row instead of 512).
 *   When that would be narrower than H / 2 (R >= 64 at H = 256), strips
 *   are H / 2 columns wide whatever R: only the columns that leave or enter
 *   the window as it slides along the strip have histograms, and those
 *   that every window of the strip covers are summed in one histogram of
 *   16-bit counts (on the stack), slid down by a sample per column and row.
 *   The output is the same bytes whatever the strips. Cost (SSE2 path, one
 *   x86-64 core, 530 x 512, against one strip with 274 * cols bytes of
 *   scratch): R = 16 about the same time; R = 32 to 127 about 1.2x to
 *   1.7x the time (R = 127: ~10 ms instead of ~6 ms on a loaded machine);
 *   R = 4, when it took this path, +1.4 % instructions. Pass a larger
 *   scratch (e.g. 274 * cols bytes: one strip) to avoid the strips. The
 *   16-bit ring converts only a strip's columns; rows are converted again
 *   for every strip. At R <= 7 neither path needs column histograms (so
 *   no strips): the portable path's 16-bit ring of 2R+4 rows fits the
 *   scratch up to 4352 columns, the SSE2 path's of 2R+16 rows up to 2486
 *   columns at R = 7 (3165 at R = 4), and wider 16-bit frames take the
 *   constant-time path.
 *
 * LIMITS
 *   0 <= radius <= ACTAG_MEDIAN_MAX_RADIUS (127): column histogram counters
 *   are 8-bit (a column holds 2R+1 <= 255 samples) and kernel counters are
 *   16-bit ((2R+1)^2 <= 65025).
 *
 * ERRORS
 *   ACTAG_ERR_NULL       src, dst or scratch is NULL
 *   ACTAG_ERR_SIZE       rows or cols < 1 or > ACTAG_MAX_DIM, or a stride < cols
 *   ACTAG_ERR_PARAM      radius < 0 or > ACTAG_MEDIAN_MAX_RADIUS, or src == dst
 *   ACTAG_ERR_WORKSPACE  scratch_size < ACTAG_MEDIAN_SCRATCH_SIZE(rows, cols)
 *   Returns ACTAG_OK on success. On error dst is left untouched.
 */
#ifndef ACTAG_MEDIAN_H
#define ACTAG_MEDIAN_H

#include "actag/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Largest radius: column histograms count up to 2R+1 samples in 8 bits. */
#define ACTAG_MEDIAN_MAX_RADIUS 127

/* Scratch bytes for any radius <= ACTAG_MEDIAN_MAX_RADIUS (a constant
 * expression; cols is evaluated more than once): for each of at most
 * ACTAG_MEDIAN_HIST_COLS columns a 16-bin coarse and a 256-bin fine 8-bit
 * histogram (272 bytes; wider frames are filtered in vertical strips), and
 * 2 bytes per column for the 16-bit input's row ring
 * (actag_median_filter16). Scales with cols only: 274 * cols up to 256
 * columns, 69,632 + 2 * cols beyond. rows is unused but kept so that every
 * stage's macro has the same shape. */
#define ACTAG_MEDIAN_HIST_COLS 256
#define ACTAG_MEDIAN_SCRATCH_SIZE(rows, cols)                                                    \
    ((size_t)((cols) < ACTAG_MEDIAN_HIST_COLS ? (cols) : ACTAG_MEDIAN_HIST_COLS) * 272u +       \
     (size_t)(cols) * 2u)

int actag_median_filter(const uint8_t *src, int rows, int cols, int src_stride,
                        uint8_t *dst, int dst_stride, int radius,
                        void *scratch, size_t scratch_size);

/* The same filter on a 16-bit frame (host byte order, any alignment: read
 * bytewise-safe; src_stride in samples), first scaled to 8 bits by the
 * frame's maximum exactly as actag_detect() documents, v8 = (v * 255 +
 * max / 2) / max (0 for an all-zero frame): the output equals
 * actag_median_filter() on the scaled frame. The scaled rows are made one
 * at a time in a ring of rows inside the scratch (no frame-sized copy);
 * same scratch size, same errors. */
int actag_median_filter16(const void *src, int rows, int cols, int src_stride, uint8_t *dst,
                          int dst_stride, int radius, void *scratch, size_t scratch_size);

/* The same filter in place, for callers that can give up the frame (the
 * detector's actag_detect_inplace, so that no frame-sized buffer is needed
 * besides the caller's): on return the first rows * cols bytes of `frame`
 * hold the filtered 8-bit frame, row-major with stride cols, byte for byte
 * what actag_median_filter() (depth 8) or actag_median_filter16() (depth 16,
 * scaled by max16, or by the frame's maximum when max16 is 0) would have
 * written; the rest of the buffer is left in an unspecified state.
 *   max16    depth 16: the sample that maps to 255, 0 (the frame's maximum,
 *            as actag_detect scales) to 65535; a sample above it reads as
 *            255. Ignored for depth 8.
 *   frame    depth 8: bytes, stride in bytes; depth 16: samples in host byte
 *            order at any alignment, stride in samples
 *   radius   0 .. ACTAG_MEDIAN_INPLACE_MAX_RADIUS (the row-block paths)
 *   scratch  at least ACTAG_MEDIAN_INPLACE_SCRATCH_SIZE(cols) bytes, any
 *            alignment: a copy of the source rows of one band of output
 *            rows (a larger scratch gives taller bands, fewer halo copies)
 * Work: the filter's, plus copying each source row once (and 2R rows once
 * more per band). Errors: ACTAG_ERR_NULL (frame or scratch), _SIZE (rows or
 * cols < 1 or > ACTAG_MAX_DIM, stride < cols), _PARAM (depth not 8 or 16,
 * radius out of range, depth 16 with max16 above 65535), _WORKSPACE
 * (scratch too small); on error the frame is untouched. */
#define ACTAG_MEDIAN_INPLACE_MAX_RADIUS 7
#define ACTAG_MEDIAN_INPLACE_SCRATCH_SIZE(cols)                                                  \
    ((size_t)(2 * ACTAG_MEDIAN_INPLACE_MAX_RADIUS + 16) * (size_t)(cols))

int actag_median_filter_inplace(void *frame, int depth, int rows, int cols, int stride,
                                uint32_t max16, int radius, void *scratch, size_t scratch_size);

#ifdef __cplusplus
}
#endif
#endif /* ACTAG_MEDIAN_H */
