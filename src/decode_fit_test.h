/*
 * decode_fit_test.h -- internal: hooks of decode_fit.c for its unit tests
 * (not part of the API).
 */
#ifndef ACTAG_SRC_DECODE_FIT_TEST_H
#define ACTAG_SRC_DECODE_FIT_TEST_H

#include "actag/common.h"

/* The 5-sample cell means of grid g = {mx, my, ax, ay, bx, by} (image point
 * of grid point (u, v): m + a (u - g) + b (v - g), as in decode_fit.c)
 * shifted by (i/2, j/2) cells: from the wide search's half-cell lattice
 * (lat) and read grid by grid (direct), (k+1)^2 floats each. k in 4..8,
 * i, j in -2..2, so in 0..0.5; ACTAG_OK or ACTAG_ERR_PARAM. */
int actag__fit_shift_cells(const uint8_t *img, int rows, int cols, int stride, const float g[6],
                           int k, float so, int i, int j, float *lat, float *direct);

/* The scalar cell reads (the ones without SIMD: fcells_on, flattice, the
 * Cortex-M path, with its DSP asm on Cortex-M4/M7) against the
 * straightforward code, every sample by the clamping sampler (fsample), bit
 * for bit; what, grid, image and outputs as for actag__fit_simd_cells (any
 * rows, cols >= 1, stride >= cols). ACTAG_OK, or ACTAG_ERR_PARAM for bad
 * arguments. */
int actag__fit_scalar_cells(const uint8_t *img, int rows, int cols, int stride, const float g[6],
                            int k, float so, int what, float *ref, float *scalar);

/* 1 when this build's scalar reads of cells inside the frame are the
 * Cortex-M4/M7 DSP asm (fit_cells.c, FIT_DSP), else 0: the tests say which
 * code they compared. */
int actag__fit_dsp_reads(void);

/* 1 when this build and this processor read the cells of grids inside the
 * frame by the x86-64 AVX2 path (fit_cells.c; compiled in by cpu_x86.h's
 * ACTAG__AVX2, chosen at run time), else 0. */
int actag__fit_avx2_reads(void);

/* The template layout of code `id` of `family` in view `view` (0..3: that
 * many quarter turns, 4..7: the same after the physical mirror) as the
 * template check builds it: (bits/4 + 1)^2 cells in row order, 1 white, 0
 * black. ACTAG_OK, ACTAG_ERR_NULL or ACTAG_ERR_PARAM. */
struct actag_family;
int actag__fit_layout(const struct actag_family *family, int id, int view, uint8_t *L);

/* The corrected bits a blind box's own grid may be read with
 * (decode_fit.c, fblind_corrections; decode_fit_grids.h, blind): the most t
 * in 0..max_corrections with views x ncodes x V(nbits, t) <= 2^nbits / 100,
 * -1 when not even t = 0 passes. nbits in 1..32, ncodes >= 1, views 4 or
 * 8, max_corrections in 0..nbits; else ACTAG_ERR_PARAM. */
int actag__fit_blind_corrections(int nbits, int ncodes, int views, int max_corrections);

/* The level-noise scores of the template check (ACTAG_FIT_LEVEL_NOISE,
 * ACTAG_FIT_SEPARATE_NOISE) of cells m ((k+1)^2 floats in row order) under
 * template L (1 white, 0 black), over the cells template_rss counts (erase
 * != 0: the outer ring's 4 corner cells left out), with nb, nw the black
 * and white cells and ssb, ssw their sums of squares about their own means:
 *     *level    = ssb / var[0] + ssw / var[1] + nb ln var[0] + nw ln var[1]
 *     *separate = nb ln max(ssb / nb, floor2) + nw ln max(ssw / nw, floor2)
 * (an empty class adds nothing). ACTAG_OK; ACTAG_ERR_NULL; ACTAG_ERR_PARAM
 * for k outside 4..8, floor2 or a variance not > 0. */
int actag__fit_level_devs(const float *m, const uint8_t *L, int k, int erase, float floor2,
                          const float var[2], float *level, float *separate);

#if defined(__SSE2__) && !defined(ACTAG_NO_SIMD)
#define ACTAG__FIT_SIMD 1
/* The SSE2 cell reads against the portable ones, bit for bit: what 0: the
 * 9-sample cell means, 1: the 5-sample ones (fcell5), 2: 9 samples with the
 * data corners erased (fcells_x's skip), 4 + pi + 2 pj: the half-cell
 * lattice of parity class (pi, pj) (flattice, (k+3-pi) x (k+3-pj) points in
 * row order). Grid and image as for actag__fit_shift_cells; portable and
 * simd receive the same number of floats (at most (k+3)^2). Any grid:
 * inside the frame, across its edges or wholly outside (edge replication),
 * any rows, cols >= 1. ACTAG_OK, or ACTAG_ERR_PARAM for bad arguments. */
int actag__fit_simd_cells(const uint8_t *img, int rows, int cols, int stride, const float g[6],
                          int k, float so, int what, float *portable, float *simd);

/* The same with the AVX2 reads as the decoder takes them where
 * actag__fit_avx2_reads() is 1: eight cells a lane each (the clamping
 * AVX2 sampler for grids that leave frames of 2 rows and columns or
 * more), the lattice's points eight a time inside the frame, the SSE2
 * clamping sampler for the rest (actag__fit_simd_cells above compares the
 * SSE2 path alone, on any processor). 1 when the AVX2 path read the grid,
 * 0 when the SSE2 sampler did, ACTAG_ERR_PARAM as above and where
 * actag__fit_avx2_reads() is 0. */
int actag__fit_avx2_cells(const uint8_t *img, int rows, int cols, int stride, const float g[6],
                          int k, float so, int what, float *portable, float *avx2);
#endif

#endif
