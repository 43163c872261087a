/* Error messages for the ACTAG_ERR_* codes. */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/common.h"

const char *actag_strerror(int code)
{
    switch (code) {
    case ACTAG_OK: return "success";
    case ACTAG_ERR_NULL: return "a required pointer is NULL";
    case ACTAG_ERR_SIZE: return "invalid image size or stride";
    case ACTAG_ERR_PARAM: return "a parameter is out of range";
    case ACTAG_ERR_GEOMETRY: return "invalid sonar geometry";
    case ACTAG_ERR_WORKSPACE: return "workspace too small for this frame";
    case ACTAG_ERR_FAMILY: return "unknown or invalid tag family";
    case ACTAG_ERR_CORRECTIONS: return "more bit corrections than the family allows";
    case ACTAG_ERR_NO_MATCH: return "no match";
    case ACTAG_ERR_OVERFLOW: return "a bounded buffer is too small";
    case ACTAG_ERR_NO_QUAD: return "no quadrilateral could be fitted";
    case ACTAG_ERR_BUILD:
        return "library compiled with fused multiply-adds (-ffp-contract=fast) or reciprocal "
               "divisions (clang -freciprocal-math)";
    default: return code > 0 ? "success" : "unknown error";
    }
}

int actag_check_build(void)
{
    return actag_fp_fuses() ? ACTAG_ERR_BUILD : ACTAG_OK;
}
