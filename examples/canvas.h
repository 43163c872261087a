/*
 * canvas.h -- a small RGB raster for the example tools' pictures (host only).
 *
 * MANUAL
 *   A canvas is w x h RGB pixels, x to the right, y down, pixel centres at
 *   integers (the library's x = column, y = row). Drawing clips at the
 *   edges; `alpha` (0..1) blends a colour over what is there (1 = opaque).
 *
 *     canvas_new(&cv, w, h, rgb)       allocate, filled with one colour; -1
 *                                      when out of memory
 *     canvas_free(&cv)
 *     canvas_put(&cv, x, y, rgb, alpha)
 *     canvas_rect(&cv, x, y, w, h, rgb, alpha)           filled
 *     canvas_line(&cv, x0, y0, x1, y1, rgb, alpha)      one pixel wide
 *     canvas_dot(&cv, x, y, radius, rgb, alpha)         filled square
 *     canvas_text(&cv, x, y, scale, text, rgb)          5x7 glyphs scaled
 *                                      by `scale`, 6*scale pixels per
 *                                      character; lowercase is drawn as
 *                                      uppercase, unknown characters as '?'
 *     canvas_label(&cv, x, y, scale, text, rgb)         the same on a dark
 *                                      box (readable over any picture)
 *     canvas_text_width(text, scale)   pixels
 *     canvas_grey(&cv, x0, y0, grey, rows, cols, stride) paste an 8-bit image
 */
#ifndef ACTAG_EXAMPLES_CANVAS_H
#define ACTAG_EXAMPLES_CANVAS_H

#include <stddef.h>
#include <stdint.h>

typedef struct canvas {
    uint8_t *rgb; /* w * h * 3 bytes */
    int w, h;
} canvas;

typedef struct rgb_t {
    uint8_t r, g, b;
} rgb_t;

int canvas_new(canvas *cv, int w, int h, rgb_t fill);
void canvas_free(canvas *cv);
void canvas_put(canvas *cv, int x, int y, rgb_t c, float alpha);
void canvas_rect(canvas *cv, int x, int y, int w, int h, rgb_t c, float alpha);
void canvas_line(canvas *cv, float x0, float y0, float x1, float y1, rgb_t c, float alpha);
void canvas_dot(canvas *cv, float x, float y, int radius, rgb_t c, float alpha);
void canvas_text(canvas *cv, int x, int y, int scale, const char *text, rgb_t c);
void canvas_label(canvas *cv, int x, int y, int scale, const char *text, rgb_t c);
int canvas_text_width(const char *text, int scale);
void canvas_grey(canvas *cv, int x0, int y0, const uint8_t *grey, int rows, int cols,
                 int stride);

#endif
