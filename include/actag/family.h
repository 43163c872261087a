/*
 * actag/family.h -- AcTag families: compiled-in code tables and the matcher.
 *
 * MANUAL
 *   A family of 4k data bits (16 <= 4k <= 32) is a list of codes in ID order.
 *   Bit 0 of a tag's bit sequence is the code's most significant bit (bit
 *   4k-1); it sits in the top-left cell as printed and the sequence walks the
 *   outer ring clockwise (see SPEC section 2).
 *
 *   The built-in families are generated at build time by actag-familygen and
 *   linked as const tables (flash, not RAM). Which ones are built is chosen by
 *   the CMake cache variable ACTAG_FAMILIES.
 *
 *     actag_family f;
 *     actag_match m;
 *     if (actag_family_get("AcTag24h10", &f) != ACTAG_OK) ...unknown name...
 *     if (actag_family_match(&f, observed_word, 2, &m) == ACTAG_OK)
 *         printf("id %d rot %d mirrored %d hamming %d\n",
 *                m.id, m.rotation, m.mirrored, m.hamming);
 *
 *   Orientation model of actag_family_match(): the 8 orientations the family
 *   generator guarantees distances for (SPEC sections 2-3):
 *       w == rot90^rotation(c)                 (mirrored == 0), or
 *       w == reverse(rot90^rotation(c))        (mirrored == 1),
 *   up to m.hamming flipped bits. rot90 is the printed tag turned 90 degrees
 *   counter-clockwise (cell (x,y) moves to (y, k-x)).
 *   Note: a physically mirrored tag read clockwise from a corner is NOT
 *   reverse(...) of a rotation (a reflection keeps a corner cell fixed; the
 *   full-word reversal does not); it is P(w) with sequence position s taking
 *   position -s mod 4k. The sonar decoder (decode.h) therefore matches w and
 *   P(w) with actag_family_match_rotations(); see decode.h for what this
 *   means for the guaranteed distances.
 *
 *   actag_family is a small value the caller owns; it points into the const
 *   code tables. (The tables are reached through functions rather than const
 *   structs holding pointers, so that position-independent builds keep every
 *   byte of the library read-only: no .data, no .data.rel.ro.)
 *
 * ERRORS
 *   ACTAG_ERR_FAMILY       unknown family name or index
 *   ACTAG_ERR_NULL         a pointer argument is NULL
 *   ACTAG_ERR_CORRECTIONS  max_corrections < 0 or above actag_family_max_corrections()
 *   ACTAG_ERR_NO_MATCH     no code within max_corrections in any orientation
 */
#ifndef ACTAG_FAMILY_H
#define ACTAG_FAMILY_H

#include "actag/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A tag family: a view of a const code table. */
typedef struct actag_family {
    const char *name;      /* e.g. "AcTag24h10" */
    int bits;              /* number of data bits, 4k */
    int hamming;           /* minimum Hamming distance between orientations */
    int ncodes;            /* number of codes (IDs 0 .. ncodes-1) */
    const uint32_t *codes; /* codes in ID order */
} actag_family;

/* Result of actag_family_match(). */
typedef struct actag_match {
    int id;       /* tag ID (index into codes) */
    int rotation; /* 0..3: observed = rot90^rotation(code) (before any reversal) */
    int mirrored; /* 1 when the observation is the reversed sequence */
    int hamming;  /* number of corrected bits */
} actag_match;

/* Fill *out with the built-in family of that exact name ("AcTag24h10").
 * Returns ACTAG_OK, ACTAG_ERR_FAMILY if it is not built in, or ACTAG_ERR_NULL. */
int actag_family_get(const char *name, actag_family *out);

/* Number of built-in families (ACTAG_FAMILIES at build time). */
int actag_family_count(void);

/* Fill *out with the i-th built-in family, 0 <= i < actag_family_count().
 * Returns ACTAG_OK, ACTAG_ERR_FAMILY when i is out of range, or ACTAG_ERR_NULL. */
int actag_family_get_at(int i, actag_family *out);

/* Checks a family's fields (bits a multiple of 4 in 16..32, hamming >= 1,
 * ncodes >= 1, codes non-NULL). Returns ACTAG_OK or ACTAG_ERR_FAMILY / ACTAG_ERR_NULL. */
int actag_family_validate(const actag_family *family);

/* Largest number of bit corrections the family supports:
 * h/2 - 1 for even h, floor(h/2) for odd h. -1 (ACTAG_ERR_NULL) for NULL. */
int actag_family_max_corrections(const actag_family *family);

/* Mask of the low `bits` bits (bits in 1..32). */
uint32_t actag_code_mask(int bits);

/* Rotate a code by 90 degrees: cyclic shift by bits/4 towards the MSB. */
uint32_t actag_code_rot90(uint32_t code, int bits);

/* Reverse the order of the low `bits` bits (bit i <-> bit bits-1-i). */
uint32_t actag_code_reverse(uint32_t code, int bits);

/* Number of differing bits between a and b. */
int actag_popcount32(uint32_t v);

/* Match an observed bit word against every code of the family in all 8
 * orientations. Returns ACTAG_OK and fills *out with the closest match
 * (smallest Hamming distance; ties go to the lowest ID, then the lowest
 * orientation, unmirrored first), ACTAG_ERR_NO_MATCH if nothing is within
 * max_corrections, or ACTAG_ERR_NULL / ACTAG_ERR_CORRECTIONS. */
int actag_family_match(const actag_family *family, uint32_t observed,
                       int max_corrections, actag_match *out);

/* Like actag_family_match() but only over the 4 rotations (out->mirrored is
 * always 0). Decoders that undo a physical mirror themselves use this. */
int actag_family_match_rotations(const actag_family *family, uint32_t observed,
                                 int max_corrections, actag_match *out);

#ifdef __cplusplus
}
#endif
#endif /* ACTAG_FAMILY_H */
