/* Sonar geometry: SPEC section 4 mapping, orientation flags, bearing tables, errors. */
#include "unity.h"
#include "test_util.h"

#include "actag/geometry.h"

#include <math.h>

void setUp(void) {}
void tearDown(void) {}

static void test_reference_mapping(void)
{
    /* SPEC section 6: (row 145, col 314) of the 463 x 620 example -> (1.0606 m, -0.0076 rad) */
    actag_sonar_geometry g = {0.1f, 1.5f, 1.0472f, NULL, 0u};
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_geometry_validate(&g, 463, 620, NULL));
    TEST_ASSERT_FLOAT_WITHIN(1e-4f, 1.0606f, actag_geometry_range(&g, 463, 145.0f));
    TEST_ASSERT_FLOAT_WITHIN(1e-4f, -0.0076f, actag_geometry_azimuth(&g, 620, 314.0f));
    TEST_ASSERT_FLOAT_WITHIN(1e-4f, 1.1576f, actag_geometry_range(&g, 463, 113.0f));
    TEST_ASSERT_FLOAT_WITHIN(1e-4f, 0.1108f, actag_geometry_azimuth(&g, 620, 244.0f));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 1.5f, actag_geometry_range(&g, 463, 0.0f));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.1f, actag_geometry_range(&g, 463, 462.0f));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.5236f, actag_geometry_azimuth(&g, 620, 0.0f));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, -0.5236f, actag_geometry_azimuth(&g, 620, 619.0f));
    TEST_ASSERT_FLOAT_WITHIN(1e-7f, 1.4f / 462.0f, actag_geometry_range_step(&g, 463));
    TEST_ASSERT_FLOAT_WITHIN(1e-7f, 1.0472f / 619.0f, actag_geometry_azimuth_step(&g, 620, 3.0f));
}

static void test_orientation_flags_mirror_the_axes(void)
{
    actag_sonar_geometry g = {0.1f, 1.5f, 1.0472f, NULL, 0u};
    actag_sonar_geometry a = g;
    int t;
    a.flags = ACTAG_RANGE_ASCENDING | ACTAG_AZIMUTH_ASCENDING;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_geometry_validate(&a, 530, 512, NULL));
    tu_seed(5);
    for (t = 0; t < 1000; t++) {
        float y = (float)tu_range(0, 52900) / 100.0f, x = (float)tu_range(0, 51100) / 100.0f;
        TEST_ASSERT_FLOAT_WITHIN(1e-5f, actag_geometry_range(&g, 530, y),
                                 actag_geometry_range(&a, 530, 529.0f - y));
        TEST_ASSERT_FLOAT_WITHIN(1e-5f, actag_geometry_azimuth(&g, 512, x),
                                 actag_geometry_azimuth(&a, 512, 511.0f - x));
    }
}

static void test_bearing_table(void)
{
    float b[6] = {0.3f, 0.2f, 0.15f, 0.0f, -0.1f, -0.3f};
    actag_sonar_geometry g = {0.5f, 20.0f, 0.0f, b, 0u};
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_geometry_validate(&g, 10, 6, NULL));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.15f, actag_geometry_azimuth(&g, 6, 2.0f));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.175f, actag_geometry_azimuth(&g, 6, 1.5f));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, -0.2f, actag_geometry_azimuth(&g, 6, 4.5f));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.35f, actag_geometry_azimuth(&g, 6, -0.5f)); /* extrapolated */
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, -0.4f, actag_geometry_azimuth(&g, 6, 5.5f));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.1f, actag_geometry_azimuth_step(&g, 6, 3.2f));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.15f, actag_geometry_azimuth_step(&g, 6, 2.9f));
    b[3] = 0.15f; /* not strictly monotonic */
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, actag_geometry_validate(&g, 10, 6, NULL));
    b[3] = 0.4f; /* changes direction */
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, actag_geometry_validate(&g, 10, 6, NULL));
    b[3] = NAN;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, actag_geometry_validate(&g, 10, 6, NULL));
}

/* actag_geometry_row / actag_geometry_column invert the mappings: on random
 * geometries (both orientations, uniform fans and random monotonic bearing
 * tables either way), the sub-pixel position of the mapped value is the
 * position, inside the frame and past its ends (extrapolated); the column
 * found by bisection is the brute-force scan's interval. */
static void test_inverse_mappings(void)
{
    static float b[300];
    int t;
    tu_seed(77);
    for (t = 0; t < 400; t++) {
        int rows = tu_range(2, 600), cols = tu_range(2, 300), i, c;
        actag_sonar_geometry g = {0.0f, 0.0f, 0.0f, NULL, 0u};
        g.min_range = 0.01f * (float)tu_range(0, 100);
        g.max_range = g.min_range + 0.05f * (float)tu_range(1, 200);
        g.aperture = 0.01f * (float)tu_range(5, 300);
        if (tu_range(0, 1))
            g.flags |= ACTAG_RANGE_ASCENDING;
        if (tu_range(0, 1))
            g.flags |= ACTAG_AZIMUTH_ASCENDING;
        if (t % 2) {
            /* random steps of 1e-3 .. 1e-2 rad, ascending or descending */
            int up = tu_range(0, 1);
            b[0] = -0.5f;
            for (c = 1; c < cols; c++) {
                float step = 1e-3f * (float)tu_range(1, 10);
                b[c] = b[c - 1] + (up ? step : -step);
            }
            g.bearings = b;
        }
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_geometry_validate(&g, rows, cols, NULL));
        for (i = 0; i < 20; i++) {
            float y = 0.01f * (float)tu_range(-1000, 100 * rows + 1000);
            float x = 0.01f * (float)tu_range(-1000, 100 * cols + 1000);
            float r = actag_geometry_range(&g, rows, y), a = actag_geometry_azimuth(&g, cols, x);
            float tol = 1e-3f + 2e-5f * (float)(rows > cols ? rows : cols);
            TEST_ASSERT_FLOAT_WITHIN(tol, y, actag_geometry_row(&g, rows, r));
            TEST_ASSERT_FLOAT_WITHIN(tol, x, actag_geometry_column(&g, cols, a));
            if (g.bearings != NULL && x >= 0.0f && x <= (float)(cols - 1)) {
                /* brute force: the interval whose beams bracket a */
                int k, ref = -1;
                for (k = 0; k + 1 < cols; k++)
                    if ((a - b[k]) * (a - b[k + 1]) <= 0.0f) {
                        ref = k;
                        break;
                    }
                TEST_ASSERT_TRUE(ref >= 0);
                TEST_ASSERT_FLOAT_WITHIN(0.5f + tol, (float)ref + 0.5f,
                                         actag_geometry_column(&g, cols, a));
            }
        }
    }
    {
        /* fewer than 2 rows or columns: 0; NaN gives NaN */
        actag_sonar_geometry g = {0.5f, 1.5f, 1.0f, NULL, 0u};
        TEST_ASSERT_EQUAL_FLOAT(0.0f, actag_geometry_row(&g, 1, 1.0f));
        TEST_ASSERT_EQUAL_FLOAT(0.0f, actag_geometry_column(&g, 1, 0.1f));
        TEST_ASSERT_TRUE(actag_geometry_row(&g, 10, NAN) != actag_geometry_row(&g, 10, NAN));
        g.bearings = b;
        TEST_ASSERT_TRUE(actag_geometry_column(&g, 10, NAN) != actag_geometry_column(&g, 10, NAN));
    }
}

/* A NaN column with a bearing table: no int conversion of the NaN (it
 * indexed the table at INT_MIN), NaN azimuth, the first beam step; the
 * ends and infinities still clamp to the end intervals. */
static void test_nan_column_with_bearing_table(void)
{
    float b[4] = {0.3f, 0.1f, -0.1f, -0.3f};
    actag_sonar_geometry g = {0.5f, 20.0f, 0.0f, b, 0u};
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_geometry_validate(&g, 10, 4, NULL));
    TEST_ASSERT_TRUE(isnan(actag_geometry_azimuth(&g, 4, NAN)));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.2f, actag_geometry_azimuth_step(&g, 4, NAN));
    TEST_ASSERT_TRUE(isnan(actag_geometry_range(&g, 10, NAN)));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.2f, actag_geometry_azimuth_step(&g, 4, INFINITY));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.2f, actag_geometry_azimuth_step(&g, 4, -INFINITY));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.3f, actag_geometry_azimuth(&g, 4, 0.0f));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, -0.3f, actag_geometry_azimuth(&g, 4, 3.0f));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.2f, actag_geometry_azimuth(&g, 4, 0.5f));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, -0.4f, actag_geometry_azimuth(&g, 4, 3.5f));
}

static void test_errors(void)
{
    actag_sonar_geometry g = {0.1f, 1.5f, 1.0472f, NULL, 0u};
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_NULL, actag_geometry_validate(NULL, 10, 10, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_geometry_validate(&g, 0, 10, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_SIZE, actag_geometry_validate(&g, 10, ACTAG_MAX_DIM + 1, NULL));
    g.max_range = 0.1f;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, actag_geometry_validate(&g, 10, 10, NULL));
    g.max_range = 1.5f;
    g.min_range = -1.0f;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, actag_geometry_validate(&g, 10, 10, NULL));
    g.min_range = 0.0f;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_geometry_validate(&g, 1, 1, NULL));
    g.aperture = 0.0f;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, actag_geometry_validate(&g, 10, 10, NULL));
    g.aperture = 7.0f;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, actag_geometry_validate(&g, 10, 10, NULL));
    g.aperture = INFINITY;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, actag_geometry_validate(&g, 10, 10, NULL));
    g.aperture = 1.0f;
    g.flags = 4u;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, actag_geometry_validate(&g, 10, 10, NULL));
    g.flags = 0u;
    g.max_range = NAN;
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, actag_geometry_validate(&g, 10, 10, NULL));
}

/* actag_geometry_mirrors against the mapping itself: the frame is a mirror
 * image of the reference orientation when azimuth-per-column times
 * range-per-row has the other sign (the reference's two are both negative);
 * every flag pair, with and without bearing tables of either direction. */
static void test_mirrors_from_the_mapping(void)
{
    static float up[64], down[64];
    int f, b, c;
    for (c = 0; c < 64; c++) {
        up[c] = -0.5f + 0.015f * (float)c;
        down[c] = 0.5f - 0.015f * (float)c;
    }
    for (b = 0; b < 3; b++)
        for (f = 0; f < 4; f++) {
            actag_sonar_geometry g = {0.1f, 1.5f, 1.0472f, NULL, (unsigned)f};
            float daz, dr;
            g.bearings = b == 0 ? NULL : b == 1 ? up : down;
            TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_geometry_validate(&g, 40, 64, NULL));
            daz = actag_geometry_azimuth(&g, 64, 1.0f) - actag_geometry_azimuth(&g, 64, 0.0f);
            dr = actag_geometry_range(&g, 40, 1.0f) - actag_geometry_range(&g, 40, 0.0f);
            TEST_ASSERT_EQUAL_INT_MESSAGE(daz * dr < 0.0f, actag_geometry_mirrors(&g, 64),
                                          b == 0 ? "flags" : "bearing table");
        }
}

/* A table with no beam (cols 0 or below, not a valid frame) reads no
 * entry: the azimuth is 0 (before, the entries before the table's start
 * were read: here the 99s). */
static void test_bearing_table_without_beams(void)
{
    static const float mem[6] = {99.0f, 99.0f, 0.3f, 0.1f, -0.1f, -0.3f};
    actag_sonar_geometry g = {0.1f, 1.5f, 0.6f, mem + 2, 0};
    TEST_ASSERT_EQUAL_FLOAT(0.0f, actag_geometry_azimuth(&g, 0, 1.0f));
    TEST_ASSERT_EQUAL_FLOAT(0.0f, actag_geometry_azimuth(&g, -3, 0.5f));
    TEST_ASSERT_EQUAL_FLOAT(0.3f, actag_geometry_azimuth(&g, 1, 0.5f));
}

/* Boundaries found by mutation testing (tools/mutate/mutate.py): the
 * smallest frames and the last beam exactly. A frame of 2 rows has a range
 * step (1 row: none); a frame of 1 column a finite azimuth and no step; at
 * the last column of a bearing table, and past it, the mapping and its step
 * read no entry after the table (a NaN sits there: reading it would show). */
static void test_boundaries_of_the_mappings(void)
{
    float mem[7] = {0.3f, 0.2f, 0.15f, 0.0f, -0.1f, -0.3f, NAN};
    actag_sonar_geometry g = {0.5f, 2.5f, 1.0f, NULL, 0u};
    actag_sonar_geometry t = {0.5f, 2.5f, 0.0f, mem, 0u};
    float x;
    TEST_ASSERT_EQUAL_FLOAT(0.0f, actag_geometry_range_step(&g, 1));
    TEST_ASSERT_EQUAL_FLOAT(2.0f, actag_geometry_range_step(&g, 2));
    TEST_ASSERT_EQUAL_FLOAT(2.5f, actag_geometry_range(&g, 2, 0.0f));
    TEST_ASSERT_EQUAL_FLOAT(0.5f, actag_geometry_range(&g, 2, 1.0f));
    TEST_ASSERT_EQUAL_FLOAT(0.75f, actag_geometry_row(&g, 2, 1.0f));
    TEST_ASSERT_EQUAL_FLOAT(0.0f, actag_geometry_row(&g, 1, 1.0f));
    /* one column: the fan's edge, the same for every x, no step */
    TEST_ASSERT_EQUAL_FLOAT(0.5f, actag_geometry_azimuth(&g, 1, 0.0f));
    TEST_ASSERT_EQUAL_FLOAT(0.5f, actag_geometry_azimuth(&g, 1, 0.25f));
    TEST_ASSERT_EQUAL_FLOAT(0.0f, actag_geometry_azimuth_step(&g, 1, 0.0f));
    TEST_ASSERT_EQUAL_FLOAT(0.0f, actag_geometry_column(&g, 1, 0.1f));
    /* two columns: the fan's two edges */
    TEST_ASSERT_EQUAL_FLOAT(0.5f, actag_geometry_azimuth(&g, 2, 0.0f));
    TEST_ASSERT_EQUAL_FLOAT(-0.5f, actag_geometry_azimuth(&g, 2, 1.0f));
    TEST_ASSERT_EQUAL_FLOAT(1.0f, actag_geometry_azimuth_step(&g, 2, 0.5f));
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_geometry_validate(&t, 10, 6, NULL));
    /* the last beam exactly, and past it (extrapolated from the last interval) */
    TEST_ASSERT_EQUAL_FLOAT(-0.3f, actag_geometry_azimuth(&t, 6, 5.0f));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, -0.5f, actag_geometry_azimuth(&t, 6, 6.0f));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, -0.7f, actag_geometry_azimuth(&t, 6, 7.0f));
    for (x = 4.0f; x <= 8.0f; x += 0.25f)
        TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.2f, actag_geometry_azimuth_step(&t, 6, x));
    /* the first interval up to the first beam and before it */
    for (x = -2.0f; x < 1.0f; x += 0.25f) {
        TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.1f, actag_geometry_azimuth_step(&t, 6, x));
        TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.3f - 0.1f * x, actag_geometry_azimuth(&t, 6, x));
    }
    /* a beam exactly starts its own interval */
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.05f, actag_geometry_azimuth_step(&t, 6, 1.0f));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.15f, actag_geometry_azimuth_step(&t, 6, 2.0f));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 5.0f, actag_geometry_column(&t, 6, -0.3f));
    TEST_ASSERT_FLOAT_WITHIN(1e-5f, 6.0f, actag_geometry_column(&t, 6, -0.5f));
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.0f, actag_geometry_column(&t, 6, 0.3f));
    /* a table of two beams, ascending: its direction comes from both ends */
    {
        static const float two[4] = {-0.2f, 0.2f, NAN, NAN}; /* NaNs: nothing past the beams is read */
        actag_sonar_geometry t2 = {0.5f, 2.5f, 0.0f, two, 0u};
        TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_geometry_validate(&t2, 10, 2, NULL));
        TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.5f, actag_geometry_column(&t2, 2, 0.0f));
        TEST_ASSERT_FLOAT_WITHIN(1e-6f, 1.0f, actag_geometry_column(&t2, 2, 0.2f));
        TEST_ASSERT_FLOAT_WITHIN(1e-6f, 1.5f, actag_geometry_column(&t2, 2, 0.4f));
        TEST_ASSERT_EQUAL_INT(1, actag_geometry_mirrors(&t2, 2));
        TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.2f, actag_geometry_azimuth(&t2, 2, 1.0f));
        TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.4f, actag_geometry_azimuth_step(&t2, 2, 1.0f));
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_reference_mapping);
    RUN_TEST(test_orientation_flags_mirror_the_axes);
    RUN_TEST(test_bearing_table);
    RUN_TEST(test_inverse_mappings);
    RUN_TEST(test_nan_column_with_bearing_table);
    RUN_TEST(test_bearing_table_without_beams);
    RUN_TEST(test_mirrors_from_the_mapping);
    RUN_TEST(test_boundaries_of_the_mappings);
    RUN_TEST(test_errors);
    return UNITY_END();
}
