/* The structure search's paths: the library (on x86-64 its SSE2 block
 * sums, uniform-fan row scores in double and best-position scan) against
 * the same file in plain C (tests/search_scalar_copy.c: ACTAG_NO_SIMD,
 * under other names): the same return code, integral image and score map
 * byte for byte, then the same picks, quads and blanked maps, pick after
 * pick. Random frames of any width (not multiples of 4 or 16), strides,
 * fans, bearing tables, tag sizes from a block to most of the frame (the
 * rows whose products need 64 bits), constant frames (ties everywhere),
 * and a bright frame whose inner boxes sum past 2^31. */
#include "unity.h"
#include "test_util.h"

#include "actag/search.h"

#include <limits.h>
#include <string.h>

/* tests/search_scalar_copy.c */
int actag_search_map_scalar(actag_search *z, const uint8_t *img, int rows, int cols, int stride,
                            const actag_sonar_geometry *g, float tag_size, int bits,
                            float range_scale, void *mapmem, size_t mapmem_size, void *scratch,
                            size_t scratch_size);
int actag_search_next_scalar(actag_search *z, int min_score, const actag_sonar_geometry *g,
                             float tag_size, float range_scale, int rows, int cols,
                             actag_point quad[4]);

void setUp(void) {}
void tearDown(void) {}

/* Both paths on one frame; returns how many positions scored (not
 * INT16_MIN) on the library's map. */
static int check_frame(const uint8_t *img, int rows, int cols, int stride,
                       const actag_sonar_geometry *g, float tag, int bits, float rs, int picks)
{
    size_t ms = ACTAG_SEARCH_MAP_SIZE(rows, cols), is = ACTAG_SEARCH_INTEGRAL_SIZE(rows, cols);
    void *map = malloc(ms), *map2 = malloc(ms), *ii = malloc(is), *ii2 = malloc(is);
    actag_search z, z2;
    int rc, rc2, scored = 0, k, min_score;
    size_t i;
    TEST_ASSERT_NOT_NULL(map);
    TEST_ASSERT_NOT_NULL(map2);
    TEST_ASSERT_NOT_NULL(ii);
    TEST_ASSERT_NOT_NULL(ii2);
    memset(map, 0x5a, ms);
    memset(map2, 0x5a, ms);
    memset(ii, 0xa5, is);
    memset(ii2, 0xa5, is);
    rc = actag_search_map(&z, img, rows, cols, stride, g, tag, bits, rs, map, ms, ii, is);
    rc2 = actag_search_map_scalar(&z2, img, rows, cols, stride, g, tag, bits, rs, map2, ms, ii2, is);
    TEST_ASSERT_EQUAL_INT(rc2, rc);
    if (rc == ACTAG_OK) {
        TEST_ASSERT_EQUAL_INT(z2.hr, z.hr);
        TEST_ASSERT_EQUAL_INT(z2.hc, z.hc);
        TEST_ASSERT_EQUAL_MEMORY(ii2, ii, is);
        TEST_ASSERT_EQUAL_MEMORY(map2, map, ms);
        for (i = 0; i < (size_t)z.hr * (size_t)z.hc; i++)
            scored += z.map[i] != INT16_MIN;
        min_score = tu_range(0, 3) == 0 ? INT_MIN : tu_range(-2100, 2100);
        for (k = 0; k < picks; k++) {
            actag_point q[4], q2[4];
            int n, n2;
            memset(q, 0, sizeof q);
            memset(q2, 0, sizeof q2);
            n = actag_search_next(&z, min_score, g, tag, rs, rows, cols, q);
            n2 = actag_search_next_scalar(&z2, min_score, g, tag, rs, rows, cols, q2);
            TEST_ASSERT_EQUAL_INT(n2, n);
            TEST_ASSERT_EQUAL_MEMORY(q2, q, sizeof q);
            TEST_ASSERT_EQUAL_MEMORY(map2, map, ms);
            if (n == 0)
                break;
        }
    }
    free(map);
    free(map2);
    free(ii);
    free(ii2);
    return scored;
}

/* The inner box (blocks) of the scored positions of block row r of a
 * uniform fan, as search.c sizes the boxes (0 when none is scored); *outer
 * (if not NULL) the outer box's. */
static long inner_blocks(const actag_sonar_geometry *g, int rows, int cols, float tag, int bits,
                         float rs, int r, long *outer)
{
    int hr = rows / 4, hc = cols / 4, ir, ic, orr, oc;
    float y = (float)(4 * r) + 1.5f, range = actag_geometry_range(g, rows, y);
    float cell = tag / (float)(bits / 4 - 3), half_in = 0.5f * (float)(bits / 4 - 3);
    float cr = cell * rs / actag_geometry_range_step(g, rows) / 4.0f;
    float cc = cell / (actag_geometry_azimuth_step(g, cols, 0.5f * (float)cols) * range) / 4.0f;
    ir = (int)(half_in * cr + 0.5f);
    ic = (int)(half_in * cc + 0.5f);
    orr = (int)((half_in + 1.0f) * cr + 0.5f);
    oc = (int)((half_in + 1.0f) * cc + 0.5f);
    if (r - orr < 0 || r + orr >= hr || 2 * oc + 1 > hc ||
        (long)(2 * orr + 1) * (2 * oc + 1) > (long)ACTAG_SEARCH_MAX_BOX_BLOCKS)
        return 0;
    if (outer)
        *outer = (long)(2 * orr + 1) * (2 * oc + 1);
    return (long)(2 * ir + 1) * (2 * ic + 1);
}

static void test_random_frames(void)
{
    int t, big = 0, wide = 0, scored = 0;
    tu_seed(31);
    for (t = 0; t < TU_TRIALS(400, 40); t++) {
        int rows = tu_range(12, t % 10 == 0 ? 700 : 260), cols = tu_range(t % 10 == 0 ? 300 : 12, t % 10 == 0 ? 700 : 260);
        int stride = cols + (t % 3 ? tu_range(0, 37) : 0), r, c, kind = t % 5;
        int bits = 16 + 4 * tu_range(0, 4);
        float tag = t % 4 == 0 ? 0.01f + (float)tu_range(0, 3000) * 0.001f
                               : 0.02f + (float)tu_range(0, 200) * 0.001f;
        float rs = 0.5f + (float)tu_range(0, 100) * 0.01f;
        float lo = 0.05f + (float)tu_range(0, 100) * 0.01f;
        actag_sonar_geometry g = {0.0f, 0.0f, 0.0f, NULL, 0u};
        float *bearings = (float *)malloc((size_t)cols * sizeof(float));
        uint8_t *img = (uint8_t *)malloc((size_t)rows * (size_t)stride);
        TEST_ASSERT_NOT_NULL(img);
        TEST_ASSERT_NOT_NULL(bearings);
        g.min_range = lo;
        g.max_range = lo + 0.2f + (float)tu_range(0, 300) * 0.01f;
        g.aperture = 0.2f + (float)tu_range(0, 200) * 0.01f;
        if (t % 3 == 1)
            g.flags = ACTAG_RANGE_ASCENDING;
        if (t % 7 == 3)
            g.flags |= ACTAG_AZIMUTH_ASCENDING;
        if (t % 6 == 5) { /* a bearing table: the per-column path, unchanged */
            for (c = 0; c < cols; c++)
                bearings[c] = -0.5f + (float)c / (float)(cols - 1);
            g.bearings = bearings;
        }
        for (r = 0; r < rows; r++)
            for (c = 0; c < stride; c++) {
                uint8_t v;
                if (kind == 0)
                    v = (uint8_t)tu_rand();
                else if (kind == 1) /* constant: every score ties */
                    v = (uint8_t)(t * 37);
                else if (kind == 2) /* bright squares on a dark floor */
                    v = (uint8_t)(((r / 9) + (c / 13)) % 5 == 0 ? tu_range(180, 255) : tu_range(0, 40));
                else if (kind == 3)
                    v = (uint8_t)(r < rows / 2 ? 255 : 0);
                else
                    v = (uint8_t)((tu_rand() % 4u == 0u) ? tu_range(150, 255) : tu_range(0, 60));
                img[(size_t)r * (size_t)stride + (size_t)c] = v;
            }
        if (cols >= 300)
            big++;
        /* rows whose products pass int32 (8 x 4080 ni (no - ni)) */
        for (r = 0; r < rows / 4 && g.bearings == NULL; r++) {
            long no = 0, ni = inner_blocks(&g, rows, cols, tag, bits, rs, r, &no);
            if (ni > 0 && 32640.0 * (double)ni * (double)(no - ni) > 2147483647.0) {
                wide++;
                break;
            }
        }
        scored += check_frame(img, rows, cols, stride, &g, tag, bits, rs, tu_range(1, 12)) > 0;
        free(img);
        free(bearings);
    }
    TEST_ASSERT_TRUE(TU_EMULATED || big > 0);
    TEST_ASSERT_TRUE(TU_EMULATED || wide > 0);
    TEST_ASSERT_GREATER_THAN_INT(0, scored); /* frames with scored positions compared */
}

/* A white frame with 32-bit tags whose outer box nearly fills the map:
 * inner sums of 4080 a block over more than 2^31 / 4080 blocks pass 2^31
 * (the SSE2 run reads them as unsigned), the products 2^53 nearly. */
static void test_bright_frame_past_int32(void)
{
    int rows = 4104, cols = 4104, r, found = 0;
    /* beams as wide as the range bins at 1.5 m: square boxes */
    actag_sonar_geometry g = {1.0f, 2.0f, 4104.0f / 4103.0f / 1.5f, NULL, 0u};
    float tag = 0.0f;
    uint8_t *img;
    if (TU_EMULATED) /* 16 MB: the host only (the SSE2 loops are x86's anyway) */
        return;
    for (tag = 0.69f; tag < 0.73f && !found; tag += 0.0005f)
        for (r = 0; r < rows / 4 && !found; r++)
            found = inner_blocks(&g, rows, cols, tag, 32, 1.0f, r, NULL) * 4080L > 2147483647L;
    TEST_ASSERT_TRUE_MESSAGE(found, "no geometry with inner sums past 2^31");
    tag -= 0.0005f;
    img = (uint8_t *)malloc((size_t)rows * (size_t)cols);
    TEST_ASSERT_NOT_NULL(img);
    memset(img, 255, (size_t)rows * (size_t)cols);
    TEST_ASSERT_GREATER_THAN_INT(0, check_frame(img, rows, cols, cols, &g, tag, 32, 1.0f, 2));
    for (r = 0; r < 4000; r++) { /* dark pixels: scores other than 0 */
        size_t y = (size_t)tu_range(0, rows - 1); /* one draw a statement */
        img[y * (size_t)cols + (size_t)tu_range(0, cols - 1)] = 0;
    }
    TEST_ASSERT_GREATER_THAN_INT(0, check_frame(img, rows, cols, cols, &g, tag, 32, 1.0f, 2));
    free(img);
}

int main(void)
{
#if defined(__SSE2__) && !defined(ACTAG_NO_SIMD)
    printf("test_search_paths: the library's SSE2 search compared with the plain C copy\n");
#else
    printf("test_search_paths: no SSE2 in this build: the plain C compared with its copy\n");
#endif
    UNITY_BEGIN();
    RUN_TEST(test_random_frames);
    RUN_TEST(test_bright_frame_past_int32);
    return UNITY_END();
}
