/* median_net.h -- internal to median.c, which includes it once per vector
 * width (no include guard): the radius-4 median by sorting networks,
 * median_net16 (SSE2, NEON) and median_net32 (AVX2), written once.
 *
 * Before each inclusion median.c defines
 *   MN_LANES  16 or 32: tiles a vector, one byte lane each
 *   MN_NT     tiles a pass at most (a multiple of MN_LANES)
 *   MN_FN(x)  the name of function x for this width (x ## MN_LANES)
 *   MN_V, MN_MIN, MN_MAX, MN_LD, MN_ST, MN_ATTR  the vector type, lane-wise
 *             unsigned byte min and max, load, store, attribute
 *             (tools/gen_median_net.py's docstring)
 * and, for this width, MN_FN(mn_split)(p, e, o): the bytes p[0], p[2], ..
 * p[2L-2] to e and p[1], p[3], .. p[2L-1] to o (L = MN_LANES), and
 * MN_FN(mn_zip)(a, b, d): the bytes a0 b0 a1 b1 .. to d[0 .. 2L-1].
 * The end of this file undefines those parameters (not MN_FN), so the
 * next inclusion starts afresh.
 *
 * Sorting networks (Adams 2021, "Fast median filters using separable
 * sorting networks") on 2 x 2 tiles of outputs, one tile a byte lane, two
 * output rows and up to 2 MN_NT columns a pass. median_net9.h (written
 * and checked by tools/gen_median_net.py, which explains the scheme) holds
 * the networks. The columns are split into even and odd ones, so that the
 * pieces the tiles share, indexed by position (column xs + 2e is position
 * e of the even half, xs + 2e + 1 of the odd one), sit at fixed lane
 * offsets from a tile's lane: a tile at column x = xs + 2m reads positions
 * m-2 .. m+2. Per pass: the core rows y-3 .. y+4 of every column sorted
 * (S1), merged in pairs and fours of columns (S2, S4) and the rows above
 * and below in pairs and fours (H2, H4), each once per position; then
 * mn_tile per MN_LANES tiles. About 800 min/max a tile (four outputs);
 * the same bytes as the histogram paths (a median is a median:
 * test_median checks both against the brute force). */
#if MN_LANES != 16 && MN_LANES != 32
#error "median_net.h: MN_LANES is 16 or 32"
#endif
#include "median_net9.h"

#define MN_W (MN_NT + 4) /* positions -2 .. NT+1, stored from index 0 */

/* Vector bases covering indices 0 .. n-1 (n >= MN_LANES) MN_LANES at a
 * time, the last one moved back to end at n - 1 (it recomputes some,
 * identically). */
#define MN_FOR_BASES(q, i, n)                                                                      \
    for ((i) = 0; (q) = (i) + MN_LANES > (n) ? (n)-MN_LANES : (i), (i) < (n); (i) += MN_LANES)

#define MN_PLANE(i) (planes + (size_t)(i)*MN_W)
#define MN_SPLIT(t, h) MN_PLANE((t)*2 + (h))
#define MN_S1(h, j) MN_PLANE(20 + (h)*8 + (j))
#define MN_S2(j) MN_PLANE(36 + (j))
#define MN_S4(j) MN_PLANE(52 + (j))
#define MN_H2(r, j) MN_PLANE(84 + (r)*2 + (j))
#define MN_H4(r, j) MN_PLANE(88 + (r)*4 + (j))

/* Output rows y0 .. y1-1 at radius 4, two a pass (the last pass of an odd
 * count computes row y1 too, and drops it). rs holds the 10 rows a pass
 * reads (8-bit rows, or a 16-bit ring of at least 10). */
/* Not inlined (GCC, Clang): its ~14 KB of planes would otherwise join the
 * frame of median_block, and so the stack of every radius (Clang inlines
 * it: 18 KB there instead of 11.5). */
#if defined(__GNUC__)
__attribute__((noinline))
#endif
MN_ATTR static void MN_FN(median_net)(rowsrc *rs, int rows, int cols, uint8_t *dst,
                                      size_t dstride, int y0, int y1)
{
    /* 96 planes of MN_W positions in one array (MN_PLANE), so that the
     * strided lists below stay inside one object: MN_SPLIT(t, h) row
     * y-4+t, half h (0 even, 1 odd columns) at [e + 2]; MN_S1(h, j) rank j
     * of the core rows; MN_S2, MN_S4, MN_H2, MN_H4 (r: 0 the row above, 1
     * below) the merged pieces */
    uint8_t planes[96 * MN_W];
    uint8_t pad[2 * MN_NT + 8];
    int y, xs, nt, t, h, i, q, v;

    for (y = y0; y < y1; y += 2) {
        const uint8_t *src[10];
        for (t = 0; t < 10; t++)
            src[t] = get_row(rs, clampi(y - 4 + t, 0, rows - 1), -1);
        for (xs = 0; xs < cols; xs += 2 * nt) {
            /* as few tile vectors as cover the rest of the row (a whole
             * last pass, moved back, would redo up to 2 MN_NT - 2 columns:
             * 768 columns' work on a 640-column frame), its right edge
             * through the clamped copy */
            const int left = (cols - xs + 2 * MN_LANES - 1) / (2 * MN_LANES);
            const int nv = left < MN_NT / MN_LANES ? left : MN_NT / MN_LANES;
            const int span = 2 * MN_LANES * nv + 8;
            nt = MN_LANES * nv;
            for (t = 0; t < 10; t++) {
                const uint8_t *p = pad;
                if (xs >= 4 && xs + span - 4 <= cols) {
                    p = src[t] + (xs - 4);
                } else {
                    /* the frame's edges: columns clamped, as every path */
                    const int a = xs < 4 ? 4 - xs : 0;                      /* first in the row */
                    const int b = xs - 4 + span > cols ? cols - xs + 4 : span; /* past the last */
                    memset(pad, src[t][0], (size_t)a);
                    memcpy(pad + a, src[t] + (xs - 4 + a), (size_t)(b - a));
                    memset(pad + b, src[t][cols - 1], (size_t)(span - b));
                }
                /* positions -2 .. nt+1: 2 MN_LANES bytes (MN_LANES of each
                 * half) a step */
                MN_FOR_BASES(q, i, span / 2)
                    MN_FN(mn_split)(p + 2 * q, MN_SPLIT(t, 0) + q, MN_SPLIT(t, 1) + q);
            }
            for (h = 0; h < 2; h++)
                MN_FOR_BASES(q, i, nt + 4)
                    MN_FN(mn_sort_8_)(MN_SPLIT(1, h) + q, 2 * MN_W, MN_S1(h, 0) + q, MN_W);
            /* S2(q): columns xs + 2q - 3 (odd half, index q) and
             * xs + 2q - 2 (even half, index q + 1); S4(q): S2(q), S2(q + 1);
             * H2, H4 likewise on rows y - 4 (MN_SPLIT(0, h)) and y + 5
             * (MN_SPLIT(9, h)) */
            MN_FOR_BASES(q, i, nt + 3) {
                MN_FN(mn_merge_8_8_)(MN_S1(1, 0) + q, MN_W, MN_S1(0, 0) + q + 1, MN_W,
                                     MN_S2(0) + q, MN_W);
                MN_FN(mn_sort_1_1_)(MN_SPLIT(0, 1) + q, 0, MN_SPLIT(0, 0) + q + 1, 0,
                                    MN_H2(0, 0) + q, MN_W);
                MN_FN(mn_sort_1_1_)(MN_SPLIT(9, 1) + q, 0, MN_SPLIT(9, 0) + q + 1, 0,
                                    MN_H2(1, 0) + q, MN_W);
            }
            MN_FOR_BASES(q, i, nt + 2) {
                MN_FN(mn_merge_16_16_)(MN_S2(0) + q, MN_W, MN_S2(0) + q + 1, MN_W,
                                       MN_S4(0) + q, MN_W);
                MN_FN(mn_merge_2_2_)(MN_H2(0, 0) + q, MN_W, MN_H2(0, 0) + q + 1, MN_W,
                                     MN_H4(0, 0) + q, MN_W);
                MN_FN(mn_merge_2_2_)(MN_H2(1, 0) + q, MN_W, MN_H2(1, 0) + q + 1, MN_W,
                                     MN_H4(1, 0) + q, MN_W);
            }
            for (v = 0; v < nv; v++) {
                /* tile m = MN_LANES v + lane at column xs + 2m: S4(m),
                 * S4(m + 2); column x - 4 even half index m, x + 5 odd
                 * half m + 4 */
                const int m0 = MN_LANES * v, c0 = xs + 2 * m0;
                MN_V out[4];
                MN_FN(mn_tile)(MN_S4(0) + m0, MN_S4(0) + m0 + 2, MN_W, MN_H4(0, 0) + m0,
                               MN_H4(0, 0) + m0 + 2, MN_H4(1, 0) + m0, MN_H4(1, 0) + m0 + 2, MN_W,
                               MN_S1(0, 0) + m0, MN_S1(1, 0) + m0 + 4, MN_W, MN_SPLIT(0, 0) + m0,
                               MN_SPLIT(0, 1) + m0 + 4, MN_SPLIT(9, 0) + m0,
                               MN_SPLIT(9, 1) + m0 + 4, out);
                for (h = 0; h < 2 && y + h < y1; h++) {
                    /* the even and odd columns of row y + h interleaved */
                    uint8_t *d = dst + (size_t)(y + h) * dstride + (size_t)c0;
                    if (cols - c0 >= 2 * MN_LANES) {
                        MN_FN(mn_zip)(out[2 * h], out[2 * h + 1], d);
                    } else {
                        uint8_t tmp[2 * MN_LANES];
                        MN_FN(mn_zip)(out[2 * h], out[2 * h + 1], tmp);
                        memcpy(d, tmp, (size_t)(cols - c0));
                    }
                }
            }
        }
    }
}
#undef MN_FOR_BASES
#undef MN_PLANE
#undef MN_SPLIT
#undef MN_S1
#undef MN_S2
#undef MN_S4
#undef MN_H2
#undef MN_H4
#undef MN_W
#undef MN_LANES
#undef MN_NT
#undef MN_V
#undef MN_MIN
#undef MN_MAX
#undef MN_LD
#undef MN_ST
#undef MN_ATTR
