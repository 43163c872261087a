/* median_rows.h -- internal to median.c, which includes it once per vector
 * width (no include guard): the row-block median for radii up to 7,
 * median_rows16 (SSE2, NEON) and median_rows32 (AVX2), written once.
 *
 * Before each inclusion median.c defines
 *   RB_LANES  16 or 32: output rows a pass, one byte lane each
 *   RB_ATTR   the functions' attribute (empty, or ACTAG__AVX2_TARGET)
 *   RB_FN(x)  the name of function x for this width (x ## RB_LANES)
 * and the vector primitives under these names (for 32 lanes they are
 * #defined to the AVX2 ones of median_avx2.h): the type vu8 (RB_LANES
 * bytes), v_load, v_store, v_zero, v_dup, v_add, v_sub, v_nonneg,
 * v_select, v_zip (a full-width byte interleave), v_hmin, v_hmax, and a
 * set of lanes: the type lanes, lanes_all, lanes_none, lanes_any,
 * lanes_not, lanes_nonneg, lanes_any_neg, lanes_all_neg; for 32 lanes
 * also rb_offsets32 (RB_ROW). rb_refs and MEDIAN_ROWS_MAX_R come from
 * median.c (both widths).
 *
 * Huang's sliding histogram shared by RB_LANES output rows (the portable
 * path's median_quad with 16 or 32 lanes instead of four). hist[v] holds,
 * in byte lane p, the count of level v in the window of output row i0 + p
 * (at most (2R+1)^2 <= 225). Moving the windows one column right, each of
 * the 2R+RB_LANES source rows of the block adds its sample of the entering
 * column and removes that of the leaving one in the windows that contain
 * the row (a lane mask): two vector read-modify-writes a row, 48 per 16
 * pixels at R = 4 with 16 lanes, instead of a column histogram update, two
 * kernel slides and two searches per pixel (median_strip8). No count is
 * kept per sample: the medians are then found together by a vector scan
 * of the levels near the previous column's lowest median (medians).
 * Both were measured against the alternatives: per-sample counts below
 * each median (a compare a sample) cost 7 instructions a row, and walking
 * each lane's median in scalar code mispredicted about one branch in two
 * pixels. The medians are collected column by column and transposed into
 * the output RB_LANES x RB_LANES bytes at a time. */
#if RB_LANES != 16 && RB_LANES != 32
#error "median_rows.h: RB_LANES is 16 or 32"
#endif
#define RB_NT_MAX (2 * MEDIAN_ROWS_MAX_R + RB_LANES) /* source rows of a block */
#if RB_LANES == 32
#define RB_HIST (256 + RB_NT_MAX) /* levels, then row t's spare level 256 + t */
#define RB_CHUNK 32               /* columns between transposes */
#else
#define RB_HIST 512 /* levels, then the spare levels 256 + (v ^ t) */
#define RB_CHUNK 64
#endif

/* Writes np rows of the n <= RB_CHUNK columns of medians col[0..n-1]
 * (lane p: output row p) from d on. Full groups of RB_LANES columns: a
 * byte transpose, log2(RB_LANES) rounds of interleaving vector k with
 * vector k + RB_LANES / 2 (each round rotates the (vector, lane) index,
 * 2 log2(RB_LANES) bits, left by one bit). */
RB_ATTR static void RB_FN(rb_store)(const vu8 *col, int n, uint8_t *d, size_t dstride, int np)
{
    int g, k, p, c;
    for (g = 0; g + RB_LANES <= n; g += RB_LANES) {
        vu8 a[RB_LANES], b[RB_LANES];
        const vu8 *x = col + g;
        vu8 *y = a;
        int round;
        /* each round from x into y, a and b in turn (no copies) */
        for (round = 1; round < RB_LANES; round *= 2) {
            for (k = 0; k < RB_LANES / 2; k++)
                v_zip(x[k], x[k + RB_LANES / 2], &y[2 * k], &y[2 * k + 1]);
            x = y;
            y = y == a ? b : a;
        }
        for (p = 0; p < np; p++)
            v_store(d + (size_t)p * dstride + (size_t)g, x[p]);
    }
    for (c = g; c < n; c++) {
        const uint8_t *m = (const uint8_t *)&col[c];
        for (p = 0; p < np; p++)
            d[(size_t)p * dstride + (size_t)c] = m[p];
    }
}

/* Source row t: its sample of column ca enters, that of cr leaves the
 * windows of mask[t] (0xFF lanes: subtracting adds one). When the two are
 * equal (v) both go to a spare level instead, which stays zero: in a flat
 * region (the black corners of a sonar fan) the same level would be read
 * and written 2 (2R + RB_LANES) times a column, each load waiting for the
 * previous store; spread over the rows' spare levels the updates are
 * independent. Selected with a mask, not a branch (equal samples come and
 * go at random in noise).
 * 16 lanes: the spare level is 256 + (v ^ t), chosen here from the two
 * samples. 32 lanes: the byte offsets of both entries, the spare one being
 * 256 + t, were computed with those of the next columns (rb_offsets32,
 * the column's k32 in offs), and the updates are 16-byte halves, only
 * those the row's windows touch: rows 0..15 (RB_ROW_LO) are in windows
 * 0..15 only, rows 32.. (RB_ROW) in windows 18..31 only (R <= 7), rows
 * 16..31 (RB_ROW_MID) in both halves. Whole 32-byte updates took 10 %
 * less time in the median but left the detector's next stages (threshold,
 * contours, quads) 5-8 % slower for a millisecond or more after it on the
 * test machine (even after a cache flush: presumably the core's power
 * management), a net loss over the pipeline; 16-byte halves do not. */
#if RB_LANES == 32
/* half h (lanes 16 h .. 16 h + 15) of row t's update */
#define RB_HALF(t, h)                                                                          \
    do {                                                                                       \
        const __m128i m_ = _mm_load_si128((const __m128i *)(const void *)&mask[t] + (h));      \
        __m128i *const hi_ = (__m128i *)(void *)((char *)hist + offs[t][0][k32]) + (h);        \
        __m128i *const ho_ = (__m128i *)(void *)((char *)hist + offs[t][1][k32]) + (h);        \
        *hi_ = _mm_sub_epi8(*hi_, m_);                                                         \
        *ho_ = _mm_add_epi8(*ho_, m_);                                                         \
    } while (0)
#define RB_ROW(t) RB_HALF(t, 1)
#define RB_ROW_MID(t)                                                                          \
    do {                                                                                       \
        RB_HALF(t, 0);                                                                         \
        RB_HALF(t, 1);                                                                         \
    } while (0)
#define RB_ROW_LO(t) RB_HALF(t, 0)
#else
#define RB_ROW(t)                                                                              \
    do {                                                                                       \
        const uint8_t *s_ = rowp[t];                                                           \
        const vu8 m_ = mask[t];                                                                \
        const size_t vi_ = s_[ca], vo_ = s_[cr];                                               \
        const size_t sp_ = ((size_t)0 - (size_t)(vi_ == vo_)) & (size_t)(256 | (t));          \
        vu8 *const hi_ = &hist[vi_ ^ sp_];                                                     \
        vu8 *const ho_ = &hist[vo_ ^ sp_];                                                     \
        *hi_ = v_sub(*hi_, m_);                                                                \
        *ho_ = v_add(*ho_, m_);                                                                \
    } while (0)
#define RB_ROW_LO(t) RB_ROW(t)
#endif

/* Per lane, the samples below level ref: the sum of the levels below ref,
 * or all the samples (N per lane) less those at or above ref, whichever
 * is fewer levels (two sums in flight). */
RB_ATTR static vu8 RB_FN(rb_below)(const vu8 *hist, unsigned ref, vu8 vn)
{
    vu8 a = v_zero(), b = v_zero();
    unsigned L;
    if (ref <= 128u) {
        for (L = 0; L + 4 <= ref; L += 4) {
            a = v_add(a, v_add(hist[L], hist[L + 2]));
            b = v_add(b, v_add(hist[L + 1], hist[L + 3]));
        }
        /* the last ref % 4 levels, or level 256 (zero): no loop exit to
         * mispredict when ref moves */
        a = v_add(a, hist[L < ref ? L : 256u]);
        b = v_add(b, hist[L + 1 < ref ? L + 1 : 256u]);
        a = v_add(a, hist[L + 2 < ref ? L + 2 : 256u]);
        return v_add(a, b);
    }
    /* levels 256 .. 258 are spare ones: zero here */
    for (L = ref; L < 256u; L += 4) {
        a = v_add(a, v_add(hist[L], hist[L + 2]));
        b = v_add(b, v_add(hist[L + 1], hist[L + 3]));
    }
    return v_sub(vn, v_add(a, b));
}

/* The windows' medians, all lanes at once, by a scan of the levels up
 * from lo: the medians of neighbouring rows are close (about 10 levels
 * apart on sonar frames), so a scan from the lowest one is short. d =
 * half - the lane's samples below the level, in -113 .. 112: the lane's
 * median is above the level while d stays >= 0 after subtracting the
 * level's count (its sign bit). When the medians lie far apart
 * (bright and dark rows in one block) the scan would cross the levels
 * between them every column: the lanes are then grouped, each column, by
 * the side of mid (the middle of their range) their median is on (a sum
 * of the levels below mid), and the high group is scanned down from hi.
 * Levels 256 .. 258 of hist are read by the unrolled scan and must be
 * zero. */
RB_ATTR static vu8 RB_FN(rb_medians)(const vu8 *hist, rb_refs *rf, vu8 vhalf, vu8 vn)
{
    lanes lset = lanes_all(), hset = lanes_none(); /* the low and high groups */
    unsigned k = 0;
    vu8 gh = v_zero(), med = v_zero();

    if (rf->grouped) {
        const vu8 dm = v_sub(vhalf, RB_FN(rb_below)(hist, rf->mid, vn));
        hset = lanes_nonneg(dm);
        lset = lanes_not(hset);
        gh = v_nonneg(dm);
    }
    if (lanes_any(lset)) {
        /* Low group: lo down while a lane has more than half its samples
         * below it, then up to the group's lowest median. */
        unsigned ref = rf->lo;
        const vu8 *hp;
        vu8 d = v_sub(vhalf, RB_FN(rb_below)(hist, ref, vn)), e;
        while (lanes_any_neg(d, lset)) {
            d = v_add(d, hist[--ref]);
            k++;
        }
        for (;;) {
            e = v_sub(d, hist[ref]);
            if (lanes_any_neg(e, lset))
                break;
            d = e;
            ref++;
            k++;
        }
        /* Each lane's median: ref + the levels above ref that leave its
         * d >= 0 (v_nonneg: -1 there). Four levels a test. */
        med = v_dup(ref);
        for (hp = &hist[ref + 1]; !lanes_all_neg(e, lset); hp += 4, k += 4) {
            med = v_sub(med, v_nonneg(e));
            e = v_sub(e, hp[0]);
            med = v_sub(med, v_nonneg(e));
            e = v_sub(e, hp[1]);
            med = v_sub(med, v_nonneg(e));
            e = v_sub(e, hp[2]);
            med = v_sub(med, v_nonneg(e));
            e = v_sub(e, hp[3]);
        }
        rf->lo = ref;
    }
    if (lanes_any(hset)) {
        /* High group, mirrored: u = half - the samples above the level; a
         * lane's median is the highest level whose count leaves u < 0. */
        unsigned refh = rf->hi;
        const vu8 *hp;
        vu8 u, f, medh;
        u = v_sub(vhalf, v_sub(v_sub(vn, RB_FN(rb_below)(hist, refh, vn)), hist[refh]));
        while (lanes_any_neg(u, hset)) {
            u = v_add(u, hist[++refh]);
            k++;
        }
        for (;;) {
            f = v_sub(u, hist[refh]);
            if (lanes_any_neg(f, hset))
                break;
            u = f;
            refh--;
            k++;
        }
        /* one level a test: no read below level 0 */
        medh = v_dup(refh);
        for (hp = &hist[refh]; !lanes_all_neg(f, hset); k++) {
            medh = v_add(medh, v_nonneg(f));
            f = v_sub(f, *--hp);
        }
        rf->hi = refh;
        med = v_select(gh, medh, med);
        if (lanes_any(lset) && refh >= rf->lo && refh - rf->lo < 32u)
            rf->grouped = 0; /* close again: one group (lo <= every median) */
    }
    if (k > 24) {
        /* k levels scanned: when many, group the lanes if their medians
         * are far apart (or move the groups' split). */
        unsigned mn = v_hmin(med), mx = v_hmax(med);
        rf->grouped = mx - mn > 48u;
        if (rf->grouped) {
            rf->lo = mn;
            rf->hi = mx;
            rf->mid = (mn + mx) / 2u + 1u;
        }
    }
    return med;
}

/* Output rows y0 .. y1-1 of the rows x cols frame rs, RB_LANES a pass
 * (fewer in the last block), radius 1 .. MEDIAN_ROWS_MAX_R. */
RB_ATTR static void RB_FN(median_rows)(rowsrc *rs, int rows, int cols, uint8_t *dst,
                                       size_t dstride, int R, int y0, int y1)
{
    vu8 hist[RB_HIST];    /* levels: 0 .. 255 counts, then spare ones (zero) */
    vu8 mask[RB_NT_MAX];  /* 0xFF in lane p when source row t is in window p */
    vu8 mbuf[RB_CHUNK];   /* medians of a chunk of columns */
    const uint8_t *rowp[RB_NT_MAX];
#if RB_LANES == 32
    /* byte offsets in hist of the entering [0] and leaving [1] samples of
     * each row for the 32 columns from j1 (rb_offsets32) */
    __attribute__((aligned(32))) uint16_t offs[RB_NT_MAX][2][32];
    int j1 = 0, k32;
#endif
    const int n = 2 * R + 1, nt = n + RB_LANES - 1;
    const vu8 vhalf = v_dup((unsigned)(n * n) / 2u);
    const vu8 vn = v_dup((unsigned)(n * n));
    int i0, j0, j, t, p;

    for (t = 0; t < nt; t++) {
        uint8_t mb[RB_LANES];
        for (p = 0; p < RB_LANES; p++)
            mb[p] = (uint8_t)(p <= t && t <= p + n - 1 ? 0xFF : 0);
        mask[t] = v_load(mb);
    }
    memset(hist, 0, sizeof hist);
    for (i0 = y0; i0 < y1; i0 += RB_LANES) {
        const int np = y1 - i0 < RB_LANES ? y1 - i0 : RB_LANES; /* output rows in this block */
        rb_refs rf;
        for (t = 0; t < nt; t++)
            rowp[t] = get_row(rs, clampi(i0 - R + t, 0, rows - 1), -1);

        /* Windows of column 0: columns clamp(-R..R). Only levels 0 .. 255
         * are cleared: the spare ones are back to zero after every row
         * (each takes a sample and gives it back). */
        memset(hist, 0, 256 * sizeof hist[0]);
        rf.lo = rf.hi = rf.mid = rf.grouped = 0;
        for (t = 0; t < nt; t++) {
            int b;
            for (b = -R; b <= R; b++) {
                unsigned v = rowp[t][clampi(b, 0, cols - 1)];
                hist[v] = v_sub(hist[v], mask[t]);
            }
        }

        for (j0 = 0; j0 < cols; j0 += RB_CHUNK) {
            const int jn = cols - j0 < RB_CHUNK ? cols - j0 : RB_CHUNK;
            for (j = j0; j < j0 + jn; j++) {
                size_t ca = (size_t)(j + R < cols ? j + R : cols - 1); /* column entering */
                size_t cr = (size_t)(j - R - 1 > 0 ? j - R - 1 : 0);   /* column leaving */
#if RB_LANES == 32
                if ((j - j0) % 32 == 0) {
                    j1 = j;
                    for (t = 0; t < nt; t++)
                        rb_offsets32(rowp[t], cols, j1, R, (unsigned)t, offs[t][0], offs[t][1]);
                }
                k32 = j - j1;
#endif
                if (j > 0 && ca != cr) {
                    /* The 2R + RB_LANES rows unrolled (in any order: the
                     * sums commute), entered by R: a loop's exit was
                     * mispredicted about once a column. */
                    switch (R) {
                    case 7:
                        RB_ROW(RB_LANES + 13);
                        RB_ROW(RB_LANES + 12);
                        /* fall through */
                    case 6:
                        RB_ROW(RB_LANES + 11);
                        RB_ROW(RB_LANES + 10);
                        /* fall through */
                    case 5:
                        RB_ROW(RB_LANES + 9);
                        RB_ROW(RB_LANES + 8);
                        /* fall through */
                    case 4:
                        RB_ROW(RB_LANES + 7);
                        RB_ROW(RB_LANES + 6);
                        /* fall through */
                    case 3:
                        RB_ROW(RB_LANES + 5);
                        RB_ROW(RB_LANES + 4);
                        /* fall through */
                    case 2:
                        RB_ROW(RB_LANES + 3);
                        RB_ROW(RB_LANES + 2);
                        /* fall through */
                    default:
                        RB_ROW(RB_LANES + 1);
                        RB_ROW(RB_LANES);
                    }
#if RB_LANES == 32
                    RB_ROW_MID(31);
                    RB_ROW_MID(30);
                    RB_ROW_MID(29);
                    RB_ROW_MID(28);
                    RB_ROW_MID(27);
                    RB_ROW_MID(26);
                    RB_ROW_MID(25);
                    RB_ROW_MID(24);
                    RB_ROW_MID(23);
                    RB_ROW_MID(22);
                    RB_ROW_MID(21);
                    RB_ROW_MID(20);
                    RB_ROW_MID(19);
                    RB_ROW_MID(18);
                    RB_ROW_MID(17);
                    RB_ROW_MID(16);
#endif
                    RB_ROW_LO(15);
                    RB_ROW_LO(14);
                    RB_ROW_LO(13);
                    RB_ROW_LO(12);
                    RB_ROW_LO(11);
                    RB_ROW_LO(10);
                    RB_ROW_LO(9);
                    RB_ROW_LO(8);
                    RB_ROW_LO(7);
                    RB_ROW_LO(6);
                    RB_ROW_LO(5);
                    RB_ROW_LO(4);
                    RB_ROW_LO(3);
                    RB_ROW_LO(2);
                    RB_ROW_LO(1);
                    RB_ROW_LO(0);
                }
                mbuf[j - j0] = RB_FN(rb_medians)(hist, &rf, vhalf, vn);
            }
            RB_FN(rb_store)(mbuf, jn, dst + (size_t)i0 * dstride + (size_t)j0, dstride, np);
        }
    }
}
#undef RB_ROW
#undef RB_ROW_LO
#undef RB_ROW_MID
#undef RB_HALF
#undef RB_NT_MAX
#undef RB_HIST
#undef RB_CHUNK
