/* The library's family matchers without their SSE2 path (ACTAG_NO_SIMD:
 * the plain C scan, as Cortex-M and other targets run it), compiled under
 * other names into test_family_paths, which checks the library (on x86-64
 * the SSE2 soft matcher) against it and against a reference. */
#define ACTAG_NO_SIMD 1
#define actag_family_count actag_family_count_scalar
#define actag_family_get_at actag_family_get_at_scalar
#define actag_family_get actag_family_get_scalar
#define actag_family_validate actag_family_validate_scalar
#define actag_family_max_corrections actag_family_max_corrections_scalar
#define actag_code_mask actag_code_mask_scalar
#define actag_code_rot90 actag_code_rot90_scalar
#define actag_code_reverse actag_code_reverse_scalar
#define actag_code_mirror actag_code_mirror_scalar
#define actag_code_corners actag_code_corners_scalar
#define actag_popcount32 actag_popcount32_scalar
#define actag_family_match actag_family_match_scalar
#define actag_family_match_rotations actag_family_match_rotations_scalar
#define actag_family_match_soft actag_family_match_soft_scalar
#define actag_family_match_soft_views actag_family_match_soft_views_scalar
#include "../src/family.c"
