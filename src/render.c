/* The allocation-free 8-bit renderer and the layout queries (see render.h; the
 * cell layout itself is tag_grid.c). */
#include "fpmath.h" /* first: float results independent of the build flags */
#include "actag/render.h"
#include "actag/tag_grid.h"

#include <string.h>

static int check_family_id(const actag_family *family, int id)
{
    int rc;
    if (family == NULL)
        return ACTAG_ERR_NULL;
    rc = actag_family_validate(family);
    if (rc != ACTAG_OK)
        return rc;
    if (id < 0 || id >= family->ncodes)
        return ACTAG_ERR_FAMILY;
    return ACTAG_OK;
}

int actag_render_side(int bits, int cell_px, int margin_px)
{
    long side;
    if (bits < 16 || bits > 32 || bits % 4 != 0 || cell_px < 1 || margin_px < 0)
        return ACTAG_ERR_PARAM;
    if (cell_px > ACTAG_MAX_DIM || margin_px > ACTAG_MAX_DIM)
        return ACTAG_ERR_SIZE;
    side = (long)(bits / 4 + 1) * (long)cell_px + 2L * (long)margin_px;
    if (side > ACTAG_MAX_DIM)
        return ACTAG_ERR_SIZE;
    return (int)side;
}

int actag_layout_cell(const actag_family *family, int id, int x, int y)
{
    int k, rc = check_family_id(family, id);
    if (rc != ACTAG_OK)
        return rc;
    k = family->bits / 4;
    if (x < 0 || y < 0 || x > k || y > k)
        return ACTAG_ERR_PARAM;
    return actag_tag_cell_value(family->codes[id], family->bits, x, y);
}

int actag_layout_corner_tabs(const actag_family *family, int id)
{
    /* For each corner: the corner cell and its two ring neighbours (along the
     * top/bottom row and along the left/right column). */
    int k, bits, rc = check_family_id(family, id), mask = 0, c;
    uint32_t code;
    if (rc != ACTAG_OK)
        return rc;
    bits = family->bits;
    k = bits / 4;
    code = family->codes[id];
    for (c = 0; c < 4; c++) {
        int cx = (c == 1 || c == 2) ? k : 0;
        int cy = (c >= 2) ? k : 0;
        int nx = cx == 0 ? 1 : k - 1; /* neighbour along the row */
        int ny = cy == 0 ? 1 : k - 1; /* neighbour along the column */
        if (actag_tag_cell_value(code, bits, cx, cy) == 0 &&
            actag_tag_cell_value(code, bits, nx, cy) == 1 &&
            actag_tag_cell_value(code, bits, cx, ny) == 1)
            mask |= 1 << c;
    }
    return mask;
}

int actag_render_tag(const actag_family *family, int id, int cell_px, int margin_px,
                     int margin_value, int camera, uint8_t *out, int out_stride,
                     size_t out_size)
{
    int k, side, r, rc;
    uint32_t code;
    uint8_t flip, mval;
    if (out == NULL)
        return ACTAG_ERR_NULL;
    rc = check_family_id(family, id);
    if (rc != ACTAG_OK)
        return rc;
    if (margin_value < 0 || margin_value > 255)
        return ACTAG_ERR_PARAM;
    side = actag_render_side(family->bits, cell_px, margin_px);
    if (side < 0)
        return side;
    if (out_stride < side)
        return ACTAG_ERR_SIZE;
    if (out_size < (size_t)(side - 1) * (size_t)out_stride + (size_t)side)
        return ACTAG_ERR_WORKSPACE;

    k = family->bits / 4;
    code = family->codes[id];
    flip = camera ? 255u : 0u; /* p ^ 255 == 255 - p for bytes */
    mval = (uint8_t)((uint8_t)margin_value ^ flip);
    for (r = 0; r < side; r++) {
        uint8_t *row = out + (size_t)r * (size_t)out_stride;
        int y, x;
        if (r < margin_px || r >= side - margin_px) {
            memset(row, mval, (size_t)side);
            continue;
        }
        y = (r - margin_px) / cell_px;
        memset(row, mval, (size_t)margin_px);
        memset(row + side - margin_px, mval, (size_t)margin_px);
        for (x = 0; x <= k; x++) {
            uint8_t v = actag_tag_cell_value(code, family->bits, x, y) ? 255u : 0u;
            memset(row + margin_px + x * cell_px, (uint8_t)(v ^ flip), (size_t)cell_px);
        }
    }
    return ACTAG_OK;
}
