/*
 * fit_cells.h -- internal: the grid-fit decoder's cell reads (fit_cells.c),
 * shared with decode_fit.c. Not part of the API.
 *
 * A grid's cell means are what every decision of the fit decoder rests on;
 * they are read here, by bilinear samples of the (filtered) frame: 9 a cell
 * (a 3 x 3 pattern at +-so cell along the grid's axes) or, with im->fast, 5
 * (the centre and the 4 diagonal points). The SSE2 paths (x86-64), and the
 * AVX2 ones where the processor has it, give the portable code's floats bit
 * for bit.
 */
#ifndef ACTAG_SRC_FIT_CELLS_H
#define ACTAG_SRC_FIT_CELLS_H

#include "actag/decode.h"
#include "decode_fit_test.h" /* ACTAG__FIT_SIMD */

/* The affine tag grid: image point of grid point (u, v) is
 * m + a (u - g) + b (v - g), g the grid centre. */
typedef struct fgrid {
    float mx, my, ax, ay, bx, by;
} fgrid;

typedef struct fimg {
    const uint8_t *img;
    int rows, cols, stride;
    float so; /* sample offset, cells */
    int fast; /* 1: 5 samples per cell instead of 9 */
    float looks; /* 2: the candidate was read before by other means (a
                    second look: the allowance counts both), else 1 */
#if ACTAG__FIT_SIMD
    int simd; /* 1: the SSE2 samplers serve the cell reads (fsimd_ok) */
    int avx2; /* 1 (with simd): the AVX2 ones serve grids inside the frame
                 (actag__fit_avx2_reads, asked once a decode) */
#endif
} fimg;

/* Lattice points per side of one parity class of the half-cell lattice. */
#define FIT_LAT_MAX (ACTAG_DECODE_MAX_K + 3)

/* Mean grey level of every cell of the (k+1)^2 grid gr, m[cy * (k+1) + cx]
 * (skip: the data ring's four corners are not read, m 0 there). */
void actag__fit_cells(const fimg *im, const fgrid *gr, int k, float *m, int skip);

/* The half-cell lattice of grid gr's 25 half-cell shifts, parity class
 * (pi, pj) (see fit_cells.c), into Q (FIT_LAT_MAX^2 floats, 5 samples a
 * point), and shift (i, j)'s cell means from it. */
void actag__fit_lattice(const fimg *im, const fgrid *gr, int k, int pi, int pj, float *Q);
void actag__fit_lattice_cells(const float *Q, int k, int i, int j, float *m);

#if ACTAG__FIT_SIMD
/* Can the SSE2 samplers read this frame (offsets within 16 bits)? */
int actag__fit_simd_ok(int rows, int cols, int stride);
#endif

#endif
