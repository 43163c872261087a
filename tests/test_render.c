/* Tag layout and renderer: every cell against the SPEC's explicit 24-bit
 * coordinate list, a generic perimeter walk for other sizes, the rotation
 * property (rot90 of the code = the tag turned 90 degrees), pixel-exact renders, corner tabs against a flood-fill reference,
 * and every error path. */
#include "unity.h"
#include "test_util.h"

#include "actag/render.h"
#include "actag/tag_grid.h"

void setUp(void) {}
void tearDown(void) {}

/* SPEC section 2, bit i at (x, y) with (0,0) the top-left cell of the white
 * square; copied from the SPEC text, not computed. */
static const int spec_x[24] = {-2, -1, 0, 1, 2, 3, 4, 4, 4, 4, 4,  4,
                               4,  3,  2, 1, 0, -1, -2, -2, -2, -2, -2, -2};
static const int spec_y[24] = {-2, -2, -2, -2, -2, -2, -2, -1, 0, 1, 2, 3,
                               4,  4,  4,  4,  4,  4,  4,  3,  2, 1, 0, -1};

/* Expected 24-bit layout value from the SPEC list (grid cell = spec + 2). */
static int spec_cell(uint32_t code, int x, int y)
{
    int i;
    for (i = 0; i < 24; i++)
        if (spec_x[i] + 2 == x && spec_y[i] + 2 == y)
            return (int)((code >> (23 - i)) & 1u);
    if (x == 1 || y == 1 || x == 5 || y == 5)
        return 0;
    return 1;
}

/* Generic reference for any k: walk the border clockwise from (0,0), one
 * step at a time, turning at the corners. */
static int walk_cell(uint32_t code, int k, int x, int y)
{
    int cx = 0, cy = 0, dx = 1, dy = 0, i;
    for (i = 0; i < 4 * k; i++) {
        if (cx == x && cy == y)
            return (int)((code >> (4 * k - 1 - i)) & 1u);
        if (cx + dx < 0 || cx + dx > k || cy + dy < 0 || cy + dy > k) {
            int t = dx; /* turn clockwise (y down): (1,0)->(0,1)->(-1,0)->(0,-1) */
            dx = -dy;
            dy = t;
        }
        cx += dx;
        cy += dy;
    }
    if (x == 1 || y == 1 || x == k - 1 || y == k - 1)
        return 0;
    return 1;
}

static void test_spec_list_is_a_clockwise_walk(void)
{
    /* Sanity of the transcription itself: consecutive entries are 4-neighbours. */
    int i;
    for (i = 0; i < 24; i++) {
        int j = (i + 1) % 24;
        int d = abs(spec_x[i] - spec_x[j]) + abs(spec_y[i] - spec_y[j]);
        TEST_ASSERT_EQUAL_INT(1, d); /* including 23 -> 0 */
    }
}

static void test_every_cell_every_code_h10_h8_h6(void)
{
    static const char *const names[3] = {"AcTag24h10", "AcTag24h8", "AcTag24h6"};
    int f;
    for (f = 0; f < 3; f++) {
        actag_family fam;
        int id, x, y;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get(names[f], &fam));
        for (id = 0; id < fam.ncodes; id++)
            for (y = 0; y <= 6; y++)
                for (x = 0; x <= 6; x++)
                    TEST_ASSERT_EQUAL_INT(spec_cell(fam.codes[id], x, y),
                                          actag_layout_cell(&fam, id, x, y));
    }
}

static void test_sample_of_h4(void)
{
    actag_family fam;
    int n, x, y;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h4", &fam));
    tu_seed(4);
    for (n = 0; n < 800; n++) {
        int id = n < 2 ? (n == 0 ? 0 : fam.ncodes - 1) : (n == 2 ? 6000 : tu_range(0, fam.ncodes - 1));
        for (y = 0; y <= 6; y++)
            for (x = 0; x <= 6; x++)
                TEST_ASSERT_EQUAL_INT(spec_cell(fam.codes[id], x, y),
                                      actag_layout_cell(&fam, id, x, y));
    }
}

static void test_first_code_picture(void)
{
    /* 0xd35f2a drawn by hand from the SPEC list:
     * bits 110100 110101 111100 101010 */
    static const char *const rows[7] = {"1101001", "0000001", "1011100", "0011101",
                                        "1011100", "0000001", "1001111"};
    actag_family fam;
    int x, y;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
    for (y = 0; y < 7; y++)
        for (x = 0; x < 7; x++)
            TEST_ASSERT_EQUAL_INT(rows[y][x] - '0', actag_layout_cell(&fam, 0, x, y));
}

static void test_other_sizes_and_rotation(void)
{
    /* Synthetic families of 16..32 bits with random codes: the layout equals
     * the perimeter walk, and rendering rot90(code) equals the grid of code
     * turned by 90 degrees (SPEC: rotation = cyclic shift by k). */
    static uint32_t codes[2];
    int bits;
    tu_seed(77);
    for (bits = 16; bits <= 32; bits += 4) {
        int k = bits / 4, t, x, y;
        actag_family fam;
        fam.name = "test";
        fam.bits = bits;
        fam.hamming = 1;
        fam.ncodes = 2;
        fam.codes = codes;
        for (t = 0; t < 50; t++) {
            codes[0] = tu_rand() & actag_code_mask(bits);
            codes[1] = actag_code_rot90(codes[0], bits);
            for (y = 0; y <= k; y++)
                for (x = 0; x <= k; x++) {
                    int v = actag_layout_cell(&fam, 0, x, y);
                    TEST_ASSERT_EQUAL_INT(walk_cell(codes[0], k, x, y), v);
                    /* rot90 = the printed tag turned 90 degrees counter-clockwise
                     * (y down), which moves cell (x,y) to (y, k-x) */
                    TEST_ASSERT_EQUAL_INT(v, actag_layout_cell(&fam, 1, y, k - x));
                }
        }
    }
}

static void check_render(const actag_family *fam, int id, int cell, int margin, int mval,
                         int camera, int extra_stride)
{
    int side = actag_render_side(fam->bits, cell, margin);
    int stride = side + extra_stride, r, c, k = fam->bits / 4;
    size_t need = (size_t)(side - 1) * (size_t)stride + (size_t)side;
    uint8_t *buf = (uint8_t *)malloc(need + 16);
    TEST_ASSERT_NOT_NULL(buf);
    TEST_ASSERT_EQUAL_INT((k + 1) * cell + 2 * margin, side);
    memset(buf, 0xa5, need + 16);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_render_tag(fam, id, cell, margin, mval, camera, buf,
                                                     stride, need));
    for (r = 0; r < side; r++) {
        for (c = 0; c < stride; c++) {
            size_t at = (size_t)r * (size_t)stride + (size_t)c;
            int expect;
            if (at >= need) {
                break;
            } else if (c >= side) {
                expect = 0xa5; /* padding never written */
            } else if (r < margin || c < margin || r >= side - margin || c >= side - margin) {
                expect = camera ? 255 - mval : mval;
            } else {
                int v = walk_cell(fam->codes[id], k, (c - margin) / cell, (r - margin) / cell);
                expect = (v ? 255 : 0);
                if (camera)
                    expect = 255 - expect;
            }
            TEST_ASSERT_EQUAL_INT(expect, buf[at]);
        }
    }
    for (r = 0; r < 16; r++)
        TEST_ASSERT_EQUAL_HEX8(0xa5, buf[need + (size_t)r]);
    free(buf);
}

static void test_render_pixels(void)
{
    actag_family fam;
    int t;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h4", &fam));
    check_render(&fam, 6000, 1, 0, 0, 0, 0); /* 7x7, one pixel per cell */
    check_render(&fam, 6000, 3, 2, 77, 0, 5);
    check_render(&fam, 6000, 3, 2, 77, 1, 5);
    check_render(&fam, 0, 10, 10, 0, 1, 0);
    tu_seed(5);
    for (t = 0; t < 30; t++) {
        /* one draw per declarator: a fixed order (the x86-64 build's order
         * when they were call arguments: the last one first) */
        int extra = tu_range(0, 9), camera = tu_range(0, 1), mval = tu_range(0, 255);
        int margin = tu_range(0, 7), cell = tu_range(1, 9), id = tu_range(0, fam.ncodes - 1);
        check_render(&fam, id, cell, margin, mval, camera, extra);
    }
}

static void test_render_known_pixels(void)
{
    /* Hand-picked pixels of AcTag24h10 ID 0 (rows above) at 4 px per cell,
     * 2 px margin of 128. */
    static uint8_t img[ACTAG_RENDER_IMAGE_SIZE(24, 4, 2)];
    actag_family fam;
    int side;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
    side = actag_render_side(24, 4, 2);
    TEST_ASSERT_EQUAL_INT(32, side);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_render_tag(&fam, 0, 4, 2, 128, 0, img, side, sizeof img));
    TEST_ASSERT_EQUAL_INT(128, img[0]);
    TEST_ASSERT_EQUAL_INT(128, img[31 * 32 + 31]);
    TEST_ASSERT_EQUAL_INT(255, img[2 * 32 + 2]);          /* cell (0,0) = 1 */
    TEST_ASSERT_EQUAL_INT(0, img[2 * 32 + 2 + 4 * 2]);    /* cell (2,0) = 0 */
    TEST_ASSERT_EQUAL_INT(0, img[(2 + 4) * 32 + 2 + 4]);  /* ring */
    TEST_ASSERT_EQUAL_INT(255, img[(2 + 13) * 32 + 2 + 13]); /* centre */
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_render_tag(&fam, 0, 4, 2, 128, 1, img, side, sizeof img));
    TEST_ASSERT_EQUAL_INT(127, img[0]);
    TEST_ASSERT_EQUAL_INT(0, img[2 * 32 + 2]);
    TEST_ASSERT_EQUAL_INT(0, img[(2 + 13) * 32 + 2 + 13]);
}

/* Reference for tabs: flood-fill the black cells of the (k+1)^2 grid with
 * 4-connectivity from the black ring; a black corner cell that is not
 * reached touches the rest of the metal only diagonally. */
static int flood_tabs(const actag_family *fam, int id)
{
    int k = fam->bits / 4, n = k + 1, x, y, changed = 1, mask = 0, c;
    int g[9][9], seen[9][9];
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            g[y][x] = walk_cell(fam->codes[id], k, x, y);
            seen[y][x] = (x == 1 && y == 1);
        }
    while (changed) {
        changed = 0;
        for (y = 0; y < n; y++)
            for (x = 0; x < n; x++) {
                if (seen[y][x] || g[y][x] != 0)
                    continue;
                if ((x > 0 && seen[y][x - 1]) || (x < k && seen[y][x + 1]) ||
                    (y > 0 && seen[y - 1][x]) || (y < k && seen[y + 1][x])) {
                    seen[y][x] = 1;
                    changed = 1;
                }
            }
    }
    for (c = 0; c < 4; c++) {
        int cx = (c == 1 || c == 2) ? k : 0, cy = c >= 2 ? k : 0;
        if (g[cy][cx] == 0 && !seen[cy][cx])
            mask |= 1 << c;
    }
    /* no other black cell may be detached */
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++)
            if (g[y][x] == 0 && !seen[y][x] && !((x == 0 || x == k) && (y == 0 || y == k)))
                return -100;
    return mask;
}

static void test_corner_tabs_all_families(void)
{
    int f, nf = actag_family_count(), total = 0;
    TEST_ASSERT_EQUAL_INT(ACTAG_CORNER_TOP_LEFT, 1);
    for (f = 0; f < nf; f++) {
        actag_family fam;
        int id, with = 0, corners = 0;
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get_at(f, &fam));
        for (id = 0; id < fam.ncodes; id++) {
            int m = actag_layout_corner_tabs(&fam, id);
            TEST_ASSERT_EQUAL_INT(flood_tabs(&fam, id), m);
            if (m) {
                with++;
                corners += (m & 1) + ((m >> 1) & 1) + ((m >> 2) & 1) + ((m >> 3) & 1);
            }
        }
        printf("%s: %d of %d tags need corner tabs (%d corners)\n", fam.name, with, fam.ncodes,
               corners);
        /* the exception really occurs (in every family large enough for it to
         * be certain: AcTag24m10's only code needs no tab) */
        if (fam.ncodes >= 40)
            TEST_ASSERT_GREATER_THAN(0, with);
        total += with;
    }
    TEST_ASSERT_GREATER_THAN(0, total);
}

static void test_known_tab_example(void)
{
    /* AcTag24h10 ID 0 (picture above): all four corner cells are white, so
     * it needs no tab. */
    actag_family fam;
    static uint32_t code[1];
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
    TEST_ASSERT_EQUAL_INT(0, actag_layout_corner_tabs(&fam, 0));
    /* A synthetic code: only the four corner bits black, everything else white. */
    fam.codes = code;
    fam.ncodes = 1;
    code[0] = 0xffffffu & ~((1u << 23) | (1u << 17) | (1u << 11) | (1u << 5));
    TEST_ASSERT_EQUAL_INT(15, actag_layout_corner_tabs(&fam, 0));
    code[0] |= 1u << 17; /* bit 6 = top-right corner white again */
    TEST_ASSERT_EQUAL_INT(ACTAG_CORNER_TOP_LEFT | ACTAG_CORNER_BOTTOM_RIGHT |
                              ACTAG_CORNER_BOTTOM_LEFT,
                          actag_layout_corner_tabs(&fam, 0));
    code[0] &= ~(1u << 22); /* bit 1 black: top-left corner has a black neighbour */
    TEST_ASSERT_EQUAL_INT(ACTAG_CORNER_BOTTOM_RIGHT | ACTAG_CORNER_BOTTOM_LEFT,
                          actag_layout_corner_tabs(&fam, 0));
}

static void test_errors(void)
{
    static uint8_t img[64 * 64];
    actag_family fam, bad;
    int side;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
    side = actag_render_side(24, 8, 4);
    TEST_ASSERT_EQUAL_INT(64, side);

    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_render_side(22, 8, 4));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_render_side(12, 8, 4));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_render_side(36, 8, 4));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_render_side(24, 0, 4));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_render_side(24, 8, -1));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_render_side(24, 5000, 0));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_render_side(24, 1, 20000));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_render_side(24, 2147483647, 0));
    TEST_ASSERT_EQUAL_INT(7, actag_render_side(24, 1, 0));

    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_render_tag(NULL, 0, 8, 4, 0, 0, img, 64, sizeof img));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_render_tag(&fam, 0, 8, 4, 0, 0, NULL, 64, sizeof img));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_FAMILY, actag_render_tag(&fam, -1, 8, 4, 0, 0, img, 64, sizeof img));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_FAMILY, actag_render_tag(&fam, 7, 8, 4, 0, 0, img, 64, sizeof img));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_render_tag(&fam, 0, 0, 4, 0, 0, img, 64, sizeof img));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_render_tag(&fam, 0, 8, -1, 0, 0, img, 64, sizeof img));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_render_tag(&fam, 0, 8, 4, -1, 0, img, 64, sizeof img));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_render_tag(&fam, 0, 8, 4, 256, 0, img, 64, sizeof img));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_render_tag(&fam, 0, 8, 4, 0, 0, img, 63, sizeof img));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE, actag_render_tag(&fam, 0, 8, 4, 0, 0, img, 64, sizeof img - 1));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE, actag_render_tag(&fam, 0, 8, 4, 0, 0, img, 65, sizeof img));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_render_tag(&fam, 0, 5000, 0, 0, 0, img, 64, sizeof img));
    /* nothing written on error */
    memset(img, 0x33, sizeof img);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE, actag_render_tag(&fam, 0, 8, 4, 0, 0, img, 64, 100));
    TEST_ASSERT_EQUAL_INT(0x33, img[0]);
    /* exact size accepted: (side-1)*stride + side */
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_render_tag(&fam, 0, 8, 4, 0, 0, img, 64, sizeof img));
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_render_tag(&fam, 0, 8, 0, 0, 0, img, 64, 55 * 64 + 56));

    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_layout_cell(NULL, 0, 0, 0));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_FAMILY, actag_layout_cell(&fam, 7, 0, 0));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_layout_cell(&fam, 0, -1, 0));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_layout_cell(&fam, 0, 0, 7));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_layout_cell(&fam, 0, 7, 0));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_layout_corner_tabs(NULL, 0));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_FAMILY, actag_layout_corner_tabs(&fam, 7));
    bad = fam;
    bad.codes = NULL;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_FAMILY, actag_layout_cell(&bad, 0, 0, 0));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_FAMILY, actag_render_tag(&bad, 0, 8, 4, 0, 0, img, 64, sizeof img));
    bad = fam;
    bad.bits = 22;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_FAMILY, actag_layout_cell(&bad, 0, 0, 0));
}

/* tag_grid.h: bit cells and the layout are each other's inverse on the
 * data ring for every size; corners in tag order; clockwise reordering. */
static void test_tag_grid_cells_and_corners(void)
{
    static const actag_point cw[4] = {{0, 0}, {10, 0}, {10, 10}, {0, 10}};
    static const actag_point ccw[4] = {{0, 0}, {0, 10}, {10, 10}, {10, 0}};
    static const actag_point flat[4] = {{0, 0}, {5, 0}, {10, 0}, {5, 0}};
    actag_point q[4], c[4];
    float H[9];
    int bits, i, r;
    for (bits = 16; bits <= 32; bits += 4) {
        int k = bits / 4, x, y, seen = 0;
        for (i = 0; i < bits; i++) {
            uint32_t one = 1u << (bits - 1 - i);
            actag_tag_bit_cell(bits, i, &x, &y);
            TEST_ASSERT_TRUE(x == 0 || y == 0 || x == k || y == k);
            TEST_ASSERT_EQUAL_INT(1, actag_tag_cell_value(one, bits, x, y));
            TEST_ASSERT_EQUAL_INT(0, actag_tag_cell_value(~one, bits, x, y));
            seen |= 1 << (x == 0 ? 0 : 1); /* both edges reached */
        }
        TEST_ASSERT_EQUAL_INT(3, seen);
        TEST_ASSERT_EQUAL_INT(0, actag_tag_cell_value(0xffffffffu, bits, 1, 1));
        TEST_ASSERT_EQUAL_INT(1, actag_tag_cell_value(0u, bits, 2, 2));
    }
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_tag_quad_clockwise(ccw, q));
    for (i = 0; i < 4; i++) {
        TEST_ASSERT_EQUAL_FLOAT(cw[i].x, q[i].x);
        TEST_ASSERT_EQUAL_FLOAT(cw[i].y, q[i].y);
    }
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_tag_quad_clockwise(flat, q));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_tag_quad_clockwise(NULL, q));
    for (r = 0; r < 4; r++) {
        actag_tag_corners(cw, r, 0, c); /* q[0] is printed corner r */
        TEST_ASSERT_EQUAL_FLOAT(cw[0].x, c[r].x);
        TEST_ASSERT_EQUAL_FLOAT(cw[1].x, c[(r + 1) & 3].x);
        actag_tag_corners(cw, r, 1, c); /* mirrored: q[n] is corner r - n */
        TEST_ASSERT_EQUAL_FLOAT(cw[0].x, c[r].x);
        TEST_ASSERT_EQUAL_FLOAT(cw[1].x, c[(r + 3) & 3].x);
    }
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_tag_map(cw, 24, ACTAG_DECODE_PROJECTIVE, H));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_tag_map(cw, 24, 7, H));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_PARAM, actag_tag_map(cw, 22, ACTAG_DECODE_AFFINE, H));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_spec_list_is_a_clockwise_walk);
    RUN_TEST(test_every_cell_every_code_h10_h8_h6);
    RUN_TEST(test_sample_of_h4);
    RUN_TEST(test_first_code_picture);
    RUN_TEST(test_other_sizes_and_rotation);
    RUN_TEST(test_render_pixels);
    RUN_TEST(test_render_known_pixels);
    RUN_TEST(test_corner_tabs_all_families);
    RUN_TEST(test_known_tab_example);
    RUN_TEST(test_errors);
    RUN_TEST(test_tag_grid_cells_and_corners);
    return UNITY_END();
}
