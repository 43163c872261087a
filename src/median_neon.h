/* NEON (AArch64, ARMv7-A with NEON; little-endian) versions of median.c's
 * 16-lane primitives: included by median.c only (MEDIAN_NEON), where the
 * SSE2 ones sit beside the portable ones; median_strip8, median_rows16 and
 * median_net16 there are written once for both vector units. Same
 * integers as the SSE2 and portable primitives (tests/test_median.c
 * checks every path against a brute-force median).
 *
 * What differs from SSE2: NEON has unsigned compares (no 0x8000 bias in
 * h16) and widening adds, but no movemask, so a set of lanes is a vector
 * mask (0xFF lanes) rather than a bit mask, and the tests on it are
 * across-lane maxima and minima (one instruction on AArch64). */
#ifndef ACTAG_MEDIAN_NEON_H
#define ACTAG_MEDIAN_NEON_H

#include <arm_neon.h>

typedef uint8x16_t vu8;

static vu8 load16(const uint8_t *p)
{
    return vld1q_u8(p);
}

static void store16(uint8_t *p, vu8 v)
{
    vst1q_u8(p, v);
}

static vu8 v_zero(void)
{
    return vdupq_n_u8(0);
}

static vu8 v_dup(unsigned x)
{
    return vdupq_n_u8((uint8_t)x);
}

static vu8 v_add(vu8 a, vu8 b)
{
    return vaddq_u8(a, b);
}

static vu8 v_sub(vu8 a, vu8 b)
{
    return vsubq_u8(a, b);
}

/* 0xFF in the lanes that are >= 0 as signed bytes. */
static vu8 v_nonneg(vu8 a)
{
    return vcgeq_s8(vreinterpretq_s8_u8(a), vdupq_n_s8(0));
}

/* m ? a : b, lane by lane (m: 0x00 or 0xFF lanes). */
static vu8 v_select(vu8 m, vu8 a, vu8 b)
{
    return vbslq_u8(m, a, b);
}

/* Interleaves the bytes of a and b: lo = a0 b0 a1 b1 .. a7 b7, hi = a8 b8 ... */
static void v_zip(vu8 a, vu8 b, vu8 *lo, vu8 *hi)
{
    uint8x16x2_t z = vzipq_u8(a, b);
    *lo = z.val[0];
    *hi = z.val[1];
}

/* Lane-wise unsigned min (median_net16). */
static vu8 v_min(vu8 a, vu8 b)
{
    return vminq_u8(a, b);
}

/* Lane-wise unsigned max (median_net16). */
static vu8 v_max(vu8 a, vu8 b)
{
    return vmaxq_u8(a, b);
}

/* Bytes p[0], p[2], .. p[30] to e and p[1], .. p[31] to o (median_net16):
 * VLD2 de-interleaves as it loads. */
static void mn_split16(const uint8_t *p, uint8_t *e, uint8_t *o)
{
    const uint8x16x2_t v = vld2q_u8(p);
    vst1q_u8(e, v.val[0]);
    vst1q_u8(o, v.val[1]);
}

/* a0 b0 a1 b1 .. a15 b15 to d (median_net16): VST2 interleaves. */
static void mn_zip16(vu8 a, vu8 b, uint8_t *d)
{
    uint8x16x2_t v;
    v.val[0] = a;
    v.val[1] = b;
    vst2q_u8(d, v);
}

/* Highest and lowest lane. */
static unsigned r16_hmax(vu8 v)
{
#if defined(__aarch64__)
    return vmaxvq_u8(v);
#else
    uint8x8_t t = vpmax_u8(vget_low_u8(v), vget_high_u8(v));
    t = vpmax_u8(t, t);
    t = vpmax_u8(t, t);
    t = vpmax_u8(t, t);
    return vget_lane_u8(t, 0);
#endif
}

static unsigned r16_hmin(vu8 v)
{
#if defined(__aarch64__)
    return vminvq_u8(v);
#else
    uint8x8_t t = vpmin_u8(vget_low_u8(v), vget_high_u8(v));
    t = vpmin_u8(t, t);
    t = vpmin_u8(t, t);
    t = vpmin_u8(t, t);
    return vget_lane_u8(t, 0);
#endif
}

/* Number of 0xFF lanes of a mask. */
static unsigned v_count_ff(vu8 m)
{
    const vu8 ones = vshrq_n_u8(m, 7);
#if defined(__aarch64__)
    return vaddvq_u8(ones);
#else
    const uint64x2_t s = vpaddlq_u32(vpaddlq_u16(vpaddlq_u8(ones)));
    return (unsigned)(vgetq_lane_u64(s, 0) + vgetq_lane_u64(s, 1));
#endif
}

/* A set of lanes (r16_medians): 0xFF in its lanes. */
typedef vu8 lanes;

static lanes lanes_all(void)
{
    return vdupq_n_u8(0xFF);
}

static lanes lanes_none(void)
{
    return vdupq_n_u8(0);
}

static int lanes_any(lanes s)
{
    return r16_hmax(s) != 0u;
}

static lanes lanes_not(lanes s)
{
    return vmvnq_u8(s);
}

/* The lanes of d that are >= 0 as signed bytes. */
static lanes lanes_nonneg(vu8 d)
{
    return v_nonneg(d);
}

/* Is some lane of s negative in d (sign bit set)? */
static int lanes_any_neg(vu8 d, lanes s)
{
    return r16_hmax(vandq_u8(d, s)) >= 0x80u;
}

/* Is every lane of s negative in d? (lanes outside s read as 0xFF) */
static int lanes_all_neg(vu8 d, lanes s)
{
    return r16_hmin(vornq_u8(d, s)) >= 0x80u;
}

/* Number of lanes <= rank in a nondecreasing 16-lane histogram of 8-bit
 * counts whose last lane exceeds rank. */
static unsigned h8_count_le(vu8 h, vu8 rank)
{
    return v_count_ff(vcleq_u8(h, rank));
}

/* (step_mask[v >> 4] is (v & 0xF0) bytes into the table, step_mask[v &
 * 15] (v << 4) & 0xF0, as in the SSE2 version.) */
static void col_update(uint8_t *cc, uint8_t *fin, uint8_t *fout, unsigned vin, unsigned vout)
{
    const uint8_t *sm = step_mask[0];
    store16(cc, vsubq_u8(vaddq_u8(load16(cc), load16(sm + (vin & 0xF0u))),
                         load16(sm + (vout & 0xF0u))));
    store16(fin, vaddq_u8(load16(fin), load16(sm + ((vin << 4) & 0xF0u))));
    store16(fout, vsubq_u8(load16(fout), load16(sm + ((vout << 4) & 0xF0u))));
}

/* Kernel histogram: lanes 0-7 in lo, 8-15 in hi, plain unsigned counts. */
typedef struct {
    uint16x8_t lo, hi;
} h16;

static void h16_zero(h16 *h)
{
    h->lo = h->hi = vdupq_n_u16(0);
}

static void h16_add(h16 *h, const uint8_t *a)
{
    const vu8 va = load16(a);
    h->lo = vaddw_u8(h->lo, vget_low_u8(va));
    h->hi = vaddw_u8(h->hi, vget_high_u8(va));
}

static void h16_sub(h16 *h, const uint8_t *a)
{
    const vu8 va = load16(a);
    h->lo = vsubw_u8(h->lo, vget_low_u8(va));
    h->hi = vsubw_u8(h->hi, vget_high_u8(va));
}

static void h16_slide(h16 *d, const h16 *h, const uint8_t *a, const uint8_t *r)
{
    const vu8 va = load16(a), vr = load16(r);
    d->lo = vsubw_u8(vaddw_u8(h->lo, vget_low_u8(va)), vget_low_u8(vr));
    d->hi = vsubw_u8(vaddw_u8(h->hi, vget_high_u8(va)), vget_high_u8(vr));
}

static unsigned h16_count_le(const h16 *h, unsigned rank)
{
    const uint16x8_t r = vdupq_n_u16((uint16_t)rank);
    return v_count_ff(vcombine_u8(vmovn_u16(vcleq_u16(h->lo, r)), vmovn_u16(vcleq_u16(h->hi, r))));
}

static unsigned h16_get(const h16 *h, unsigned k)
{
    uint16_t t[16];
    vst1q_u16(t, h->lo);
    vst1q_u16(t + 8, h->hi);
    return t[k];
}

#endif /* ACTAG_MEDIAN_NEON_H */
