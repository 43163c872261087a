/* median_quad.h -- internal to median.c, which includes it once (no include
 * guard) where no 16-byte vector unit is built (!MEDIAN_SIMD): the
 * row-block medians for radii up to 7 of the portable path, median_quad()
 * (four rows a pass), and on Cortex-M4/M7 median_quad_dsp() (the DSP
 * instructions; eight rows a pass at R >= 3). It uses median.c's rowsrc,
 * get_row and clampi. */

/* ----------------------------------------------------------------------
 * Radii up to 7: four output rows at a time, one histogram (Huang's
 * scheme, as above) for the four windows. hist[v] packs the four windows'
 * 8-bit counts of level v (a window holds (2R+1)^2 <= 225 samples); the
 * 2R+4 source rows of a block of four output rows enter the windows of the
 * rows they cover (mask[t], 0x01 per covered lane), so each sample costs
 * one histogram update for all four windows instead of up to four.
 * ---------------------------------------------------------------------- */
#define MEDIAN_QUAD_MAX_R 7

/* Cortex-M4/M7 (__ARM_FEATURE_SIMD32, little-endian, Thumb-2):
 * median_quad_dsp(); ACTAG_NO_DSP selects the portable median_quad() there
 * too. Thumb-2 only: the asm's LDRD/STRD take any two registers there, an
 * even-odd pair in ARM state (a Cortex-A build with -marm failed to
 * assemble). A build that keeps a frame pointer and reserves r9 as well
 * (-fno-omit-frame-pointer with -ffixed-r9, -msingle-pic-base or
 * -mpic-register=r9) leaves the column asm too few registers: define
 * ACTAG_NO_DSP there. */
#if defined(__ARM_FEATURE_SIMD32) && defined(__GNUC__) && !defined(ACTAG_NO_DSP) &&            \
    !defined(__ARM_BIG_ENDIAN) && defined(__thumb2__)
#define MEDIAN_DSP 1
#endif

/* mask8[t]: 0x01 in lane p when source row t of a block is in window p. */
static void quad_masks(int n, uint32_t *mask8, uint64_t *mask16)
{
    int t, p;
    for (t = 0; t < n + 3; t++) {
        uint32_t m8 = 0;
        uint64_t m16 = 0;
        for (p = 0; p < 4; p++) {
            if (p <= t && t <= p + n - 1) {
                m8 |= (uint32_t)1u << (8 * p);
                m16 |= (uint64_t)1u << (16 * p);
            }
        }
        mask8[t] = m8;
        if (mask16 != NULL)
            mask16[t] = m16;
    }
}

#ifdef MEDIAN_DSP
/* DSP path. leb packs the four windows' counts of samples <= their median
 * (8-bit lanes: at most 225), medb the four medians. A sample v changes
 * leb by the lanes where med[p] >= v: USUB8 (medb - v in each lane) sets
 * GE there and SEL picks the row's mask byte, 0 elsewhere; MUL broadcasts
 * v (GCC would spend two shifted adds). The lanes are added into leb as a
 * plain 32-bit word: carries between lanes cancel, because every lane ends
 * in 0..225 (the word is sum le[p] * 256^p modulo 2^32 throughout). The
 * median of window p then moves from med[p] while le[p] <= half (up) or
 * le[p] - hist_p[med[p]] > half (down); lane p of hist[m] is read as byte
 * 4m + p. Cost at R = 4, 530 x 512 (QEMU -icount, tools/budget), four-row
 * blocks only: 21.1 M instructions per frame on Cortex-M7 -O2 (about 78
 * per pixel: per column of a block, 2R+4 rows at 17 each and about 11 per
 * median), 21.7 M at -Os, 20.7 M on Cortex-M4 -O2; 30.1 M (111 per pixel)
 * before the asm blocks. With oct_block's eight-row blocks (below) on
 * every eight rows of a band: 14.2 M on M7 -O2 (about 52 per pixel),
 * 14.3 M at -Os, 14.2 M on M4 -O2 (18.4 M, 68 per pixel, with the blocks
 * taking the interior rows only and these per-sample compares). Stack:
 * 4.4 KiB (oct_block's 4 KiB of histogram entries). */
__attribute__((always_inline)) static inline uint32_t
le_lanes(unsigned v, uint32_t medb, uint32_t m)
{
    uint32_t r;
    __asm__("mul %0, %1, %5\n\tusub8 %0, %2, %0\n\tsel %0, %4, %3"
            : "=&r"(r)
            : "r"(v), "r"(medb), "r"(0u), "r"(m), "r"(0x01010101u)
            : "cc");
    return r;
}

/* Sample v of a row with mask m enters (+) or leaves (-) the windows. */
#define QSAMPLE(op, v, m)                                                                      \
    do {                                                                                       \
        hist[v] op (m);                                                                        \
        leb op le_lanes((v), medb, (m));                                                       \
    } while (0)

/* New median of window p from its old one (lane p of medb) and the count
 * of samples <= it (lane p of leb); adds both to nb, nl. */
#define QLANE(p, mout)                                                                         \
    do {                                                                                       \
        unsigned le_ = (leb >> (8 * (p))) & 0xFFu;                                             \
        const uint8_t *h_ = h8 + 4u * ((medb >> (8 * (p))) & 0xFFu);                           \
        if (le_ <= half) {                                                                     \
            do {                                                                               \
                h_ += 4;                                                                       \
                le_ += h_[p];                                                                  \
            } while (le_ <= half);                                                             \
        } else {                                                                               \
            unsigned c_ = h_[p];                                                               \
            while (le_ - c_ > half) {                                                          \
                le_ -= c_;                                                                     \
                h_ -= 4;                                                                       \
                c_ = h_[p];                                                                    \
            }                                                                                  \
        }                                                                                      \
        mout = (unsigned)(h_ - h8) >> 2;                                                       \
        nb |= (uint32_t)mout << (8 * (p));                                                     \
        nl |= (uint32_t)le_ << (8 * (p));                                                      \
    } while (0)

/* One source row of an interior block: its samples q[dq] entering and
 * q[0] leaving the windows of mask m; q moves to the next row. One asm
 * block, 17 instructions: GCC, given the C, rematerialises the constants
 * and re-extends the bytes (about 20). hist is written: "memory".
 * Always inlined: at -Os GCC calls it, with q and leb in memory. */
__attribute__((always_inline)) static inline void
quad_row(uint32_t *hist, const uint8_t **q, size_t dq, size_t sstride, uint32_t medb, uint32_t m,
         uint32_t *leb)
{
    uint32_t vi, vo, t;
    __asm__("ldrb %[vi], [%[q], %[dq]]\n\t"
            "ldrb %[vo], [%[q]]\n\t"
            "add %[q], %[q], %[ss]\n\t"
            "ldr %[t], [%[h], %[vi], lsl #2]\n\t"
            "add %[t], %[t], %[m]\n\t"
            "str %[t], [%[h], %[vi], lsl #2]\n\t"
            "ldr %[t], [%[h], %[vo], lsl #2]\n\t"
            "sub %[t], %[t], %[m]\n\t"
            "str %[t], [%[h], %[vo], lsl #2]\n\t"
            "mul %[vi], %[vi], %[k]\n\t"
            "usub8 %[vi], %[medb], %[vi]\n\t"
            "sel %[vi], %[m], %[z]\n\t"
            "add %[le], %[le], %[vi]\n\t"
            "mul %[vo], %[vo], %[k]\n\t"
            "usub8 %[vo], %[medb], %[vo]\n\t"
            "sel %[vo], %[m], %[z]\n\t"
            "sub %[le], %[le], %[vo]"
            : [vi] "=&r"(vi), [vo] "=&r"(vo), [t] "=&r"(t), [q] "+r"(*q), [le] "+r"(*leb)
            : [dq] "r"(dq), [ss] "r"(sstride), [h] "r"(hist), [medb] "r"(medb), [m] "r"(m),
              [k] "r"(0x01010101u), [z] "r"(0u)
            : "cc", "memory");
}

/* The median search of one window's lane as asm text (four-row blocks;
 * oct_block's OLANE is a variant): ES bytes per histogram entry (1 << LG).
 * Walk the cumulative count down while le - hist_p[m] > half (label 1), up
 * while le <= half (label 2); the moved median and count go back into
 * their lanes of medb and leb (BFI); label 4 is where the store follows. */
#define LANE_SEARCH_ASM(ES, LG)                                                                \
    "ubfx %[le], %[leb], #%c[sh], #8\n\t"                                                       \
    "ubfx %[m], %[medb], #%c[sh], #8\n\t"                                                       \
    "add %[h], %[h8], %[m], lsl #" #LG "\n\t"                                                   \
    "cmp %[le], %[half]\n\t"                                                                    \
    "bls 2f\n\t"                                                                                \
    "ldrb %[c], [%[h], #%c[lp]]\n\t"                                                            \
    "sub %[c], %[le], %[c]\n\t"                                                                 \
    "cmp %[c], %[half]\n\t"                                                                     \
    "bls 4f\n"                                                                                   \
    "1:\n\t"                                                                                    \
    "mov %[le], %[c]\n\t"                                                                       \
    "sub %[h], %[h], #" #ES "\n\t"                                                              \
    "ldrb %[c], [%[h], #%c[lp]]\n\t"                                                            \
    "sub %[c], %[le], %[c]\n\t"                                                                 \
    "cmp %[c], %[half]\n\t"                                                                     \
    "bhi 1b\n\t"                                                                                \
    "b 3f\n"                                                                                     \
    "2:\n\t"                                                                                    \
    "add %[h], %[h], #" #ES "\n\t"                                                              \
    "ldrb %[c], [%[h], #%c[lp]]\n\t"                                                            \
    "add %[le], %[le], %[c]\n\t"                                                                \
    "cmp %[le], %[half]\n\t"                                                                    \
    "bls 2b\n"                                                                                   \
    "3:\n\t"                                                                                    \
    "sub %[m], %[h], %[h8]\n\t"                                                                 \
    "lsr %[m], %[m], #" #LG "\n\t"                                                              \
    "bfi %[medb], %[m], #%c[sh], #8\n\t"                                                        \
    "bfi %[leb], %[le], #%c[sh], #8\n"                                                           \
    "4:\n\t"

/* QLANE for the interior columns as one asm block: lanes of medb and leb
 * updated in place (BFI) and only when the median moves, the median
 * stored by `store` (d: column pointer of output row 0, ds: dstride). The
 * usual case, no move, is 10 instructions. */
#define QLANE_ASM(lane, store)                                                                 \
    do {                                                                                       \
        uint32_t le_, m_, h_, c_;                                                              \
        __asm__(LANE_SEARCH_ASM(4, 2) store                                                    \
                : [le] "=&r"(le_), [m] "=&r"(m_), [h] "=&r"(h_), [c] "=&r"(c_),                \
                  [medb] "+r"(medb), [leb] "+r"(leb)                                           \
                : [h8] "r"(h8), [half] "r"(half), [d] "r"(dcol), [ds] "r"(dstride),            \
                  [sh] "i"(8 * (lane)), [lp] "i"(lane)                                         \
                : "cc", "memory");                                                             \
    } while (0)

/* Columns 1 .. cols-1 of a block whose 2R+4 source rows are all inside the
 * image at row0 + t * sstride: the masks are constants, one pointer walks
 * the rows, all four output rows are stored (a function of its own: fewer
 * live values, so fewer spills). */
static void quad_interior(uint32_t *hist, const uint8_t *row0, size_t sstride, uint8_t *d0,
                          size_t dstride, int cols, int R, uint32_t medb, uint32_t leb)
{
    const uint8_t *const h8 = (const uint8_t *)hist;
    const int n = 2 * R + 1;
    const unsigned half = (unsigned)(n * n) / 2u;
    const size_t midrows = (size_t)(n - 3) * sstride;
    /* Columns jm0 .. jm1-1 clamp neither the entering nor the leaving
     * column: there the leaving one is q and the entering one q + n. */
    const int jm0 = R + 1 < cols ? R + 1 : cols;
    const int jm1 = cols - R > jm0 ? cols - R : jm0;
    int j;

/* Column j: its samples q[dq] (entering) and q[0] (leaving) in each of
 * the 2R+4 rows from q, and the four medians stored from d. Rows 0-2 are
 * in windows 0..t, rows 3..n-1 in all four, rows n..n+2 in windows
 * t-n+1..3. */
#define QCOLUMN(q0, dq, d)                                                                     \
    do {                                                                                       \
        const uint8_t *q = (q0), *qe;                                                          \
        if ((dq) != 0) {                                                                       \
            quad_row(hist, &q, (dq), sstride, medb, 0x00000001u, &leb);                        \
            quad_row(hist, &q, (dq), sstride, medb, 0x00000101u, &leb);                        \
            quad_row(hist, &q, (dq), sstride, medb, 0x00010101u, &leb);                        \
            /* n - 3 = 2R - 2 rows, two a turn (less loop overhead) */                        \
            for (qe = q + midrows; q != qe;) {                                                 \
                quad_row(hist, &q, (dq), sstride, medb, 0x01010101u, &leb);                    \
                quad_row(hist, &q, (dq), sstride, medb, 0x01010101u, &leb);                    \
            }                                                                                  \
            quad_row(hist, &q, (dq), sstride, medb, 0x01010100u, &leb);                        \
            quad_row(hist, &q, (dq), sstride, medb, 0x01010000u, &leb);                        \
            quad_row(hist, &q, (dq), sstride, medb, 0x01000000u, &leb);                        \
        }                                                                                      \
        {                                                                                      \
            uint8_t *const dcol = (d);                                                         \
            QLANE_ASM(0, "strb %[m], [%[d]]");                                                 \
            QLANE_ASM(1, "strb %[m], [%[d], %[ds]]");                                          \
            QLANE_ASM(2, "add %[c], %[d], %[ds], lsl #1\n\tstrb %[m], [%[c]]");                \
            QLANE_ASM(3, "add %[c], %[d], %[ds], lsl #1\n\tstrb %[m], [%[c], %[ds]]");         \
        }                                                                                      \
    } while (0)

    for (j = 1; j < cols; j++) {
        const uint8_t *qc;
        uint8_t *d;
        if (j == jm0) {
            /* no clamps: one pointer for the rows, one for the output */
            for (qc = row0 + (jm0 - R - 1), d = d0 + jm0; qc != row0 + (jm1 - R - 1); qc++, d++)
                QCOLUMN(qc, (size_t)n, d);
            j = jm1;
            if (j == cols)
                break;
        }
        {
            size_t ca = (size_t)(j + R < cols ? j + R : cols - 1); /* column entering */
            size_t cr = (size_t)(j - R - 1 > 0 ? j - R - 1 : 0);   /* column leaving */
            QCOLUMN(row0 + cr, ca - cr, d0 + j);
        }
    }
#undef QCOLUMN
}
#undef QLANE_ASM

/* Eight output rows a pass (R >= 3, 8-bit frames; the block's 2R+8 source
 * rows sstride apart: in the frame, or a copy with the clamped rows
 * repeated, see median_quad_dsp). A level's histogram entry is four words:
 * the counts of windows 0-3 (lanes as in median_quad_dsp), an indicator
 * for them (lane p is 1 while the level is <= window p's median, else 0),
 * then the same two words for windows 4-7. A sample's change to the
 * counts le is its row's mask ANDed with the indicator word, loaded with
 * the counts (no AND where the row is in all four windows of a half): no
 * broadcast of the sample and no compare against the medians, the four-
 * row blocks' MUL/USUB8/SEL. The median searches keep the indicators in
 * step, one byte store for each level a median crosses. Source rows 4 ..
 * 2R+3 are in windows of both halves: one sample load, one LDM of the
 * entry and one STM of its first three words serve both (the LDM wants
 * its registers in order: four pinned ones, r0-r3), so a row there costs
 * 17-19 instructions against 2 x 17 for two four-row blocks; rows 0-3
 * touch only the low words, rows 2R+4 .. 2R+7 only the high ones (LDRD),
 * 13-15. R >= 3 gives the fixed row pattern the asm spells out (rows 4-6
 * full in the low half, 2R+1 .. 2R+3 full in the high half, 2R-6 rows
 * full in both); full masks are the immediate 0x01010101. At R = 4 on the
 * pool frames (M7 -O2) a column of eight outputs takes about 415
 * instructions: 285 for the rows, 118 for the medians (a third of them
 * move, 1.7-1.8 levels on average), 12 for the column; 533 with the
 * four-row blocks' compares and 8-byte entries (375 for the rows). */
#define OCT_MIN_R 3
/* Unoptimised builds keep a frame pointer and cannot give the column's asm
 * its 13 registers: four-row blocks only there. */
#if defined(__OPTIMIZE__)
#define MEDIAN_OCT 1
#endif

/* The state of a block's eight windows, in the words before hist (byte
 * offsets from it, so that the column asm reaches them from its one base
 * register): at -32 the counts le, a byte a window as the four-row
 * blocks' leb but biased by 127 - half (bit 7 set while le > half, and
 * the lanes stay in 15 .. 241: no carries between them); at -24 the
 * medians; at -16 sstride, the number of row pairs in all eight windows,
 * dstride; for the columns of one run at -48 their last output pointer,
 * at -40 what q steps back a column (the rows walk it down) and at -36
 * the step of dq. */
#define OCT_STATE_WORDS 12

#ifdef MEDIAN_OCT

/* A row in one half only (count word LB, entry offset OFF: 0 low, 8
 * high): sample q[dq] enters and q[0] leaves the windows of mask M (the
 * register p, with AND the indicators' AND, or all four: OK_). */
#define OROW1(M, AND, LB, OFF)                                                                 \
    "ldrb %[v], [%[q], %[dq]]\n\t"                                                             \
    "add %[v], %[h], %[v], lsl #4\n\t"                                                         \
    "ldrd %[c0], %[i0], [%[v], #" OFF "]\n\t"                                                  \
    "add %[c0], %[c0], " M "\n\t"                                                              \
    "str %[c0], [%[v], #" OFF "]\n\t" AND "add %[" LB "], %[" LB "], %[i0]\n\t"              \
    "ldrb %[v], [%[q]]\n\t"                                                                    \
    "add %[q], %[q], %[ss]\n\t"                                                                \
    "add %[v], %[h], %[v], lsl #4\n\t"                                                         \
    "ldrd %[c0], %[i0], [%[v], #" OFF "]\n\t"                                                  \
    "sub %[c0], %[c0], " M "\n\t"                                                              \
    "str %[c0], [%[v], #" OFF "]\n\t" AND "sub %[" LB "], %[" LB "], %[i0]\n\t"
#define OK_ "#0x01010101"
#define OP_ "%[p]"
#define OAND0 "and %[i0], %[i0], %[p]\n\t"
#define OAND1 "and %[i1], %[i1], %[p]\n\t"

/* One sample of a row in both halves (masks A low, B high; ANDA, ANDB
 * the indicators' AND for a partial mask, or nothing). The STM writes
 * the low indicator back unchanged. */
#define OSAMPLE2(LOAD, OP, A, ANDA, B, ANDB)                                                   \
    LOAD                                                                                       \
    "add %[v], %[h], %[v], lsl #4\n\t"                                                         \
    "ldm %[v], {%[c0], %[i0], %[c1], %[i1]}\n\t"                                               \
    OP " %[c0], %[c0], " A "\n\t"                                                              \
    OP " %[c1], %[c1], " B "\n\t"                                                              \
    "stm %[v], {%[c0], %[i0], %[c1]}\n\t" ANDA OP " %[ll], %[ll], %[i0]\n\t" ANDB OP          \
    " %[lh], %[lh], %[i1]\n\t"
#define OROW2(A, ANDA, B, ANDB)                                                                \
    OSAMPLE2("ldrb %[v], [%[q], %[dq]]\n\t", "add", A, ANDA, B, ANDB)                          \
    OSAMPLE2("ldrb %[v], [%[q]]\n\tadd %[q], %[q], %[ss]\n\t", "sub", A, ANDA, B, ANDB)

/* Median of window P (a digit; O: its byte in an entry) kept or moved one
 * level at a time as in LANE_SEARCH_ASM, from its count and median bytes.
 * With v = le - (half + 1) the sign of one SUBS/ADDS decides each step.
 * Each level crossed gets its indicator byte (O + 4): 0 going down (the
 * level leaves le), 1 going up (it joins). STORE stores the median (c0).
 * 8 instructions and the store when the median stays. */
#define OLANE(P, O, STORE)                                                                     \
    "ldrb %[v], [%[h], #(-32+" #P ")]\n\t"                                                     \
    "ldrb %[c0], [%[h], #(-24+" #P ")]\n\t"                                                    \
    "add %[i0], %[h], %[c0], lsl #4\n\t"                                                       \
    "subs %[v], %[v], #128\n\t"                                                                \
    "bmi 5f\n\t"                                                                               \
    "ldrb %[c1], [%[i0], #" #O "]\n\t"                                                         \
    "subs %[v], %[v], %[c1]\n\t"                                                               \
    "bmi 4f\n\t"                                                                               \
    "movs %[c0], #0\n"                                                                         \
    "1:\n\t"                                                                                   \
    "strb %[c0], [%[i0], #(4+" #O ")]\n\t"                                                     \
    "sub %[i0], %[i0], #16\n\t"                                                                \
    "ldrb %[c1], [%[i0], #" #O "]\n\t"                                                         \
    "subs %[v], %[v], %[c1]\n\t"                                                               \
    "bpl 1b\n\t"                                                                               \
    "add %[v], %[v], %[c1]\n\t"                                                                \
    "b 3f\n"                                                                                   \
    "5:\n\t"                                                                                   \
    "movs %[c0], #1\n"                                                                         \
    "2:\n\t"                                                                                   \
    "add %[i0], %[i0], #16\n\t"                                                                \
    "ldrb %[c1], [%[i0], #" #O "]\n\t"                                                         \
    "strb %[c0], [%[i0], #(4+" #O ")]\n\t"                                                     \
    "adds %[v], %[v], %[c1]\n\t"                                                               \
    "bmi 2b\n"                                                                                 \
    "3:\n\t"                                                                                   \
    "add %[v], %[v], #128\n\t"                                                                 \
    "sub %[c0], %[i0], %[h]\n\t"                                                               \
    "lsr %[c0], %[c0], #4\n\t"                                                                 \
    "strb %[c0], [%[h], #(-24+" #P ")]\n\t"                                                    \
    "strb %[v], [%[h], #(-32+" #P ")]\n"                                                       \
    "4:\n\t" STORE "\n\t"

/* Columns d .. dend-1 of a run where q0 and dq step by the same amounts
 * (the clamps at the frame's sides change them), as one asm block: no
 * register holds anything but the column's work (with separate blocks for
 * the rows and each median, GCC spent about 35 instructions a column on
 * spills and the clamps). Rows from q (entering sample at +dq); the
 * medians go to d + p * dstride (ll, lh, i1: rows 2, 4, 6). The asm
 * stores (histogram, state, medians) and its register outputs are dead:
 * volatile. */
__attribute__((always_inline)) static inline void oct_run(uint32_t *hist, const uint8_t *q,
                                                          size_t dq, uint8_t *d)
{
    register uint32_t c0 __asm__("r0"), i0 __asm__("r1"), c1 __asm__("r2"), i1 __asm__("r3");
    uint32_t v, p, ll, lh, ss;
    __asm__ volatile(
        "9:\n\t"
        "ldrd %[ll], %[lh], [%[h], #-32]\n\t"
        "ldr %[ss], [%[h], #-16]\n\t"
        "mov %[p], #1\n\t" OROW1(OP_, OAND0, "ll", "0")
        "movw %[p], #0x101\n\t" OROW1(OP_, OAND0, "ll", "0")
        "add %[p], %[p], #0x10000\n\t" OROW1(OP_, OAND0, "ll", "0")
        OROW1(OK_, "", "ll", "0")
        "mov %[p], #1\n\t" OROW2(OK_, "", OP_, OAND1)
        "movw %[p], #0x101\n\t" OROW2(OK_, "", OP_, OAND1)
        "add %[p], %[p], #0x10000\n\t" OROW2(OK_, "", OP_, OAND1)
        "ldr %[p], [%[h], #-12]\n\t"
        "cmp %[p], #0\n\t"
        "beq 8f\n"
        "7:\n\t" OROW2(OK_, "", OK_, "") OROW2(OK_, "", OK_, "")
        "subs %[p], %[p], #1\n\t"
        "bne 7b\n"
        "8:\n\t"
        "mov %[p], #0x01010101\n\t"
        "bic %[p], %[p], #0xFF\n\t" OROW2(OP_, OAND0, OK_, "")
        "bic %[p], %[p], #0x100\n\t" OROW2(OP_, OAND0, OK_, "")
        "mov %[p], #0x01000000\n\t" OROW2(OP_, OAND0, OK_, "")
        OROW1(OK_, "", "lh", "8")
        "mov %[p], #0x01010101\n\t"
        "bic %[p], %[p], #0xFF\n\t" OROW1(OP_, OAND0, "lh", "8")
        "bic %[p], %[p], #0x100\n\t" OROW1(OP_, OAND0, "lh", "8")
        "mov %[p], #0x01000000\n\t" OROW1(OP_, OAND0, "lh", "8")
        "strd %[ll], %[lh], [%[h], #-32]\n\t"
        "ldr %[ss], [%[h], #-8]\n\t"
        "add %[ll], %[d], %[ss], lsl #1\n\t"
        "add %[lh], %[d], %[ss], lsl #2\n\t"
        "add %[i1], %[lh], %[ss], lsl #1\n\t"
        OLANE(0, 0, "strb %[c0], [%[d]]")
        OLANE(1, 1, "strb %[c0], [%[d], %[ss]]")
        OLANE(2, 2, "strb %[c0], [%[ll]]")
        OLANE(3, 3, "strb %[c0], [%[ll], %[ss]]")
        OLANE(4, 8, "strb %[c0], [%[lh]]")
        OLANE(5, 9, "strb %[c0], [%[lh], %[ss]]")
        OLANE(6, 10, "strb %[c0], [%[i1]]")
        OLANE(7, 11, "strb %[c0], [%[i1], %[ss]]")
        "ldrd %[v], %[p], [%[h], #-40]\n\t"
        "sub %[q], %[q], %[v]\n\t"
        "add %[dq], %[dq], %[p]\n\t"
        "ldr %[v], [%[h], #-48]\n\t"
        "add %[d], %[d], #1\n\t"
        "cmp %[d], %[v]\n\t"
        "bne 9b"
        : [c0] "=&r"(c0), [i0] "=&r"(i0), [c1] "=&r"(c1), [i1] "=&r"(i1), [v] "=&r"(v),
          [p] "=&r"(p), [ll] "=&r"(ll), [lh] "=&r"(lh), [ss] "=&r"(ss), [q] "+r"(q),
          [dq] "+r"(dq), [d] "+r"(d)
        : [h] "r"(hist)
        : "cc", "memory");
}

/* Output rows i0 .. i0+7, source rows from row0 = row i0 - R (all inside
 * the image, sstride apart); hist: 1024 words of scratch after
 * OCT_STATE_WORDS. noinline: inlined into median_quad_dsp, GCC spilled
 * more around the asm (measured before oct_run). */
__attribute__((noinline)) static void oct_block(uint32_t *hist, const uint8_t *row0,
                                                size_t sstride, uint8_t *d0, size_t dstride,
                                                int cols, int R, const uint32_t *mask8)
{
    uint8_t *const h8 = (uint8_t *)hist;
    uint32_t *const st = hist - OCT_STATE_WORDS;
    const int n = 2 * R + 1, nt = n + 7;
    const unsigned half = (unsigned)(n * n) / 2u;
    int t, b, p, j;

    /* Windows of column 0: columns clamp(-R..R). The entries cleared 64
     * bytes a loop (memset took 7 instructions a 16 bytes, 0.1 M a frame
     * more): STM wants ascending registers. */
    {
        register uint32_t z0 __asm__("r0") = 0u, z1 __asm__("r1") = 0u;
        register uint32_t z2 __asm__("r2") = 0u, z3 __asm__("r3") = 0u;
        uint32_t *w = hist;
        __asm__ volatile("1:\n\t"
                         "stm %[w]!, {%[z0], %[z1], %[z2], %[z3]}\n\t"
                         "stm %[w]!, {%[z0], %[z1], %[z2], %[z3]}\n\t"
                         "stm %[w]!, {%[z0], %[z1], %[z2], %[z3]}\n\t"
                         "stm %[w]!, {%[z0], %[z1], %[z2], %[z3]}\n\t"
                         "cmp %[w], %[e]\n\t"
                         "bne 1b"
                         : [w] "+r"(w)
                         : [z0] "r"(z0), [z1] "r"(z1), [z2] "r"(z2), [z3] "r"(z3),
                           [e] "r"(hist + 1024)
                         : "cc", "memory");
    }
    for (t = 0; t < nt; t++) {
        const uint8_t *s = row0 + (size_t)t * sstride;
        const uint32_t ml = t <= n + 2 ? mask8[t] : 0u, mh = t >= 4 ? mask8[t - 4] : 0u;
        for (b = -R; b <= R; b++) {
            unsigned v = s[clampi(b, 0, cols - 1)];
            hist[4u * v] += ml;
            hist[4u * v + 2u] += mh;
        }
    }
    st[4] = st[5] = st[6] = st[7] = 0u;
    for (p = 0; p < 8; p++) {
        const unsigned o = (unsigned)p + ((unsigned)p & 4u); /* its count byte in an entry */
        const unsigned sh = 8u * ((unsigned)p & 3u);
        unsigned m = 0, le = h8[o];
        h8[o + 4u] = 1u;
        while (le <= half) {
            le += h8[16u * ++m + o];
            h8[16u * m + o + 4u] = 1u;
        }
        st[4 + p / 4] |= (uint32_t)(le + 127u - half) << sh;
        st[6 + p / 4] |= (uint32_t)m << sh;
        d0[(size_t)p * dstride] = (uint8_t)m;
    }
    st[8] = (uint32_t)sstride;
    st[9] = (uint32_t)(R - 3);
    st[10] = (uint32_t)dstride;

    /* Runs of columns between the points where a clamp starts or stops:
     * the leaving column cr = max(j - R - 1, 0) steps from column R + 1
     * on, the entering one ca = min(j + R, cols - 1) up to cols - R - 1. */
    for (j = 1; j < cols;) {
        const int ca = j + R < cols ? j + R : cols - 1, cr = j - R - 1 > 0 ? j - R - 1 : 0;
        const int a = j >= R + 1, i = j <= cols - R - 2;
        int je = cols;
        if (!a && R + 1 < je)
            je = R + 1;
        if (i && cols - R - 1 < je)
            je = cols - R - 1;
        st[0] = (uint32_t)(uintptr_t)(d0 + je);
        st[2] = (uint32_t)((size_t)nt * sstride - (size_t)a);
        st[3] = (uint32_t)(i - a);
        oct_run(hist, row0 + cr, (size_t)(ca - cr), d0 + j);
        j = je;
    }
}
#undef OLANE
#undef OROW1
#undef OSAMPLE2
#undef OROW2
#undef OK_
#undef OP_
#undef OAND0
#undef OAND1
#endif /* MEDIAN_OCT */

static void median_quad_dsp(rowsrc *rs, int rows, int cols, uint8_t *dst, size_t dstride, int R,
                            int y0, int y1)
{
    const size_t sstride = rs->src8 != NULL ? rs->stride : rs->cols;
    /* oct_block's state and 16-byte entries; four-row blocks: hist[v] */
    uint32_t entries[OCT_STATE_WORDS + 4 * 256];
    uint32_t *const hist = entries + OCT_STATE_WORDS;
    const uint8_t *const h8 = (const uint8_t *)hist;
    const uint8_t *rowp[2 * MEDIAN_QUAD_MAX_R + 4];
    uint32_t mask8[2 * MEDIAN_QUAD_MAX_R + 4];
    const int n = 2 * R + 1, nt = n + 3;
    const unsigned half = (unsigned)(n * n) / 2u;
    int i0, j, t, p, step;

    quad_masks(n, mask8, NULL);
    for (i0 = y0; i0 < y1; i0 += step) {
        uint32_t medb = 0, leb = 0;
        const int np = y1 - i0 < 4 ? y1 - i0 : 4; /* output rows in this block */
        uint8_t *const d0 = dst + (size_t)i0 * dstride;

#ifdef MEDIAN_OCT
        /* Eight rows at once (8-bit frames): from the frame where their
         * 2R+8 source rows are in it, else (top and bottom) from a copy of
         * them in the ring with the clamped rows repeated, when the ring is
         * free and large enough (not in place); at the end of the band its
         * last eight rows (a few computed twice: the same bytes). */
        if (R >= OCT_MIN_R && rs->src8 != NULL && y1 - y0 >= 8) {
            const int ib = y1 - i0 >= 8 ? i0 : y1 - 8, nt8 = 2 * R + 8;
            uint8_t *const db = dst + (size_t)ib * dstride;
            if (ib - R >= 0 && ib + 7 + R <= rows - 1) {
                oct_block(hist, rs->src8 + (size_t)(ib - R) * sstride, sstride, db, dstride,
                          cols, R, mask8);
                step = ib + 8 - i0;
                continue;
            }
            if (rs->ring != NULL && rs->k >= nt8) {
                for (t = 0; t < nt8; t++)
                    memcpy(rs->ring + (size_t)t * (size_t)cols,
                           rs->src8 + (size_t)clampi(ib - R + t, 0, rows - 1) * sstride,
                           (size_t)cols);
                oct_block(hist, rs->ring, (size_t)cols, db, dstride, cols, R, mask8);
                step = ib + 8 - i0;
                continue;
            }
        }
#endif
        step = 4;

        /* Windows of column 0: columns clamp(-R..R). */
        memset(hist, 0, 256u * sizeof *hist);
        for (t = 0; t < nt; t++) {
            const uint8_t *s;
            int b;
            rowp[t] = get_row(rs, clampi(i0 - R + t, 0, rows - 1), -1);
            s = rowp[t];
            for (b = -R; b <= R; b++)
                hist[s[clampi(b, 0, cols - 1)]] += mask8[t];
        }
        for (p = 0; p < 4; p++) {
            unsigned m = 0, le = h8[p];
            while (le <= half)
                le += h8[4u * ++m + (unsigned)p];
            medb |= (uint32_t)m << (8 * p);
            leb |= (uint32_t)le << (8 * p);
            if (p < np)
                d0[(size_t)p * dstride] = (uint8_t)m;
        }
        if (np == 4 && i0 - R >= 0 && i0 - R + nt - 1 <= rows - 1 &&
            rowp[nt - 1] == rowp[0] + (size_t)(nt - 1) * sstride) {
            quad_interior(hist, rowp[0], sstride, d0, dstride, cols, R, medb, leb);
            continue;
        }

        for (j = 1; j < cols; j++) {
            size_t ca = (size_t)(j + R < cols ? j + R : cols - 1); /* column entering */
            size_t cr = (size_t)(j - R - 1 > 0 ? j - R - 1 : 0);   /* column leaving */
            uint32_t nb = 0, nl = 0;
            unsigned m[4];
            for (t = 0; t < nt && ca != cr; t++) {
                unsigned vin = rowp[t][ca], vout = rowp[t][cr];
                QSAMPLE(+=, vin, mask8[t]);
                QSAMPLE(-=, vout, mask8[t]);
            }
            QLANE(0, m[0]);
            QLANE(1, m[1]);
            QLANE(2, m[2]);
            QLANE(3, m[3]);
            medb = nb;
            leb = nl;
            for (p = 0; p < np; p++)
                dst[(size_t)(i0 + p) * dstride + (size_t)j] = (uint8_t)m[p];
        }
    }
}
#undef QSAMPLE
#undef QLANE

#else /* !MEDIAN_DSP */
/* Portable: the number of samples below each window's median is updated
 * for all four at once with 16-bit lanes of a 64-bit word: lane p of medb
 * is med[p] + 255, so bit 8 of lane p of medb - v * 0x0001000100010001 is
 * (v < med[p]) and no lane borrows. */
#define LANES16 0x0001000100010001ull

/* bcast16[v]: v in each of four 16-bit lanes (a table: cheaper than the
 * multiply or shifts on both x86-64 and Cortex-M). */
#define BC1(v) ((uint64_t)(v) * LANES16)
#define BC4(v) BC1(v), BC1((v) + 1), BC1((v) + 2), BC1((v) + 3)
#define BC16(v) BC4(v), BC4((v) + 4), BC4((v) + 8), BC4((v) + 12)
#define BC64(v) BC16(v), BC16((v) + 16), BC16((v) + 32), BC16((v) + 48)
static const uint64_t bcast16_tab[256] = {BC64(0), BC64(64), BC64(128), BC64(192)};
#define bcast16(v) bcast16_tab[v]

static void median_quad(rowsrc *rs, int rows, int cols, uint8_t *dst, size_t dstride, int R,
                        int y0, int y1)
{
    uint32_t hist[256];
    const uint8_t *rowp[2 * MEDIAN_QUAD_MAX_R + 4];
    uint32_t mask8[2 * MEDIAN_QUAD_MAX_R + 4];
    uint64_t mask16[2 * MEDIAN_QUAD_MAX_R + 4];
    const int n = 2 * R + 1, nt = n + 3;
    const unsigned half = (unsigned)(n * n) / 2u;
    int i0, j, t, p;

    quad_masks(n, mask8, mask16);
    for (i0 = y0; i0 < y1; i0 += 4) {
        unsigned med[4], lt[4];
        uint64_t medb = 0;
        int np = y1 - i0 < 4 ? y1 - i0 : 4; /* output rows in this block */
        for (t = 0; t < nt; t++)
            rowp[t] = get_row(rs, clampi(i0 - R + t, 0, rows - 1), -1);

        /* Windows of column 0: columns clamp(-R..R). */
        memset(hist, 0, sizeof hist);
        for (t = 0; t < nt; t++) {
            const uint8_t *s = rowp[t];
            int b;
            for (b = -R; b <= R; b++)
                hist[s[clampi(b, 0, cols - 1)]] += mask8[t];
        }
        for (p = 0; p < 4; p++) {
            unsigned m = 0, l = 0, sh = 8u * (unsigned)p;
            while (l + ((hist[m] >> sh) & 0xFFu) <= half) {
                l += (hist[m] >> sh) & 0xFFu;
                m++;
            }
            med[p] = m;
            lt[p] = l;
            medb |= ((uint64_t)m + 255u) << (16 * p);
            if (p < np)
                dst[(size_t)(i0 + p) * dstride] = (uint8_t)m;
        }

        for (j = 1; j < cols; j++) {
            size_t ca = (size_t)(j + R < cols ? j + R : cols - 1); /* column entering */
            size_t cr = (size_t)(j - R - 1 > 0 ? j - R - 1 : 0);   /* column leaving */
            if (ca != cr) {
                /* acc collects 256 * the change of lt per 16-bit lane; the
                 * lanes start at 64 so that they never go negative (at most
                 * 2R+4 <= 18 samples leave a window in one step). */
                uint64_t acc = 64u * 256u * LANES16;
                for (t = 0; t < nt; t++) {
                    unsigned vin = rowp[t][ca], vout = rowp[t][cr];
                    uint64_t m16 = mask16[t];
                    uint32_t m8 = mask8[t];
                    if (t == 3 && n > 3) {
                        /* Rows 3 .. n-1 are in all four windows. */
                        for (; t < n; t++) {
                            vin = rowp[t][ca];
                            vout = rowp[t][cr];
                            hist[vin] += 0x01010101u;
                            hist[vout] -= 0x01010101u;
                            acc += (medb - bcast16(vin)) & (256u * LANES16);
                            acc -= (medb - bcast16(vout)) & (256u * LANES16);
                        }
                        vin = rowp[t][ca];
                        vout = rowp[t][cr];
                        m16 = mask16[t];
                        m8 = mask8[t];
                    }
                    hist[vin] += m8;
                    hist[vout] -= m8;
                    acc += (medb - bcast16(vin)) & (m16 << 8);
                    acc -= (medb - bcast16(vout)) & (m16 << 8);
                }
                acc >>= 8;
                medb = 0;
                for (p = 0; p < 4; p++) {
                    unsigned sh = 8u * (unsigned)p;
                    unsigned m = med[p];
                    unsigned l = lt[p] + (unsigned)((acc >> (16 * p)) & 0xFFFFu) - 64u;
                    if (l > half) {
                        do {
                            m--;
                            l -= (hist[m] >> sh) & 0xFFu;
                        } while (l > half);
                    } else {
                        while (l + ((hist[m] >> sh) & 0xFFu) <= half) {
                            l += (hist[m] >> sh) & 0xFFu;
                            m++;
                        }
                    }
                    med[p] = m;
                    lt[p] = l;
                    medb |= ((uint64_t)m + 255u) << (16 * p);
                }
            }
            for (p = 0; p < np; p++)
                dst[(size_t)(i0 + p) * dstride + (size_t)j] = (uint8_t)med[p];
        }
    }
}
#endif /* MEDIAN_DSP */
