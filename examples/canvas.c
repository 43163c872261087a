/* A small RGB raster with a 5x7 font (see canvas.h). */
#include "canvas.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int canvas_new(canvas *cv, int w, int h, rgb_t fill)
{
    size_t i, n = (size_t)w * (size_t)h;
    cv->w = w;
    cv->h = h;
    cv->rgb = (uint8_t *)malloc(n * 3u);
    if (!cv->rgb)
        return -1;
    for (i = 0; i < n; i++) {
        cv->rgb[3 * i] = fill.r;
        cv->rgb[3 * i + 1] = fill.g;
        cv->rgb[3 * i + 2] = fill.b;
    }
    return 0;
}

void canvas_free(canvas *cv)
{
    free(cv->rgb);
    cv->rgb = NULL;
}

static uint8_t mix(uint8_t under, uint8_t over, float a)
{
    return (uint8_t)lroundf((float)under + a * ((float)over - (float)under));
}

void canvas_put(canvas *cv, int x, int y, rgb_t c, float alpha)
{
    uint8_t *p;
    if (x < 0 || y < 0 || x >= cv->w || y >= cv->h)
        return;
    p = cv->rgb + 3 * ((size_t)y * (size_t)cv->w + (size_t)x);
    if (alpha >= 1.0f) {
        p[0] = c.r;
        p[1] = c.g;
        p[2] = c.b;
    } else {
        p[0] = mix(p[0], c.r, alpha);
        p[1] = mix(p[1], c.g, alpha);
        p[2] = mix(p[2], c.b, alpha);
    }
}

void canvas_rect(canvas *cv, int x, int y, int w, int h, rgb_t c, float alpha)
{
    int i, j;
    for (j = y; j < y + h; j++)
        for (i = x; i < x + w; i++)
            canvas_put(cv, i, j, c, alpha);
}

void canvas_line(canvas *cv, float x0, float y0, float x1, float y1, rgb_t c, float alpha)
{
    float dx = x1 - x0, dy = y1 - y0;
    float len = fabsf(dx) > fabsf(dy) ? fabsf(dx) : fabsf(dy);
    int n, i, lx = -1000000, ly = -1000000;
    if (!(len < 1e5f))
        return; /* not finite or absurd: draw nothing */
    n = (int)ceilf(len);
    if (n < 1)
        n = 1;
    for (i = 0; i <= n; i++) {
        float t = (float)i / (float)n;
        int x = (int)lroundf(x0 + t * dx), y = (int)lroundf(y0 + t * dy);
        if (x == lx && y == ly)
            continue; /* blend each pixel once */
        canvas_put(cv, x, y, c, alpha);
        lx = x;
        ly = y;
    }
}

void canvas_dot(canvas *cv, float x, float y, int radius, rgb_t c, float alpha)
{
    int cx = (int)lroundf(x), cy = (int)lroundf(y);
    if (!(fabsf(x) < 1e6f && fabsf(y) < 1e6f))
        return;
    canvas_rect(cv, cx - radius, cy - radius, 2 * radius + 1, 2 * radius + 1, c, alpha);
}

/* 5x7 glyphs, one byte per row, bit 4 = leftmost column. */
typedef struct {
    char ch;
    uint8_t row[7];
} glyph;

static const glyph font[] = {
    {'0', {14, 17, 19, 21, 25, 17, 14}}, {'1', {4, 12, 4, 4, 4, 4, 14}},
    {'2', {14, 17, 1, 2, 4, 8, 31}},     {'3', {31, 2, 4, 2, 1, 17, 14}},
    {'4', {2, 6, 10, 18, 31, 2, 2}},     {'5', {31, 16, 30, 1, 1, 17, 14}},
    {'6', {6, 8, 16, 30, 17, 17, 14}},   {'7', {31, 1, 2, 4, 8, 8, 8}},
    {'8', {14, 17, 17, 14, 17, 17, 14}}, {'9', {14, 17, 17, 15, 1, 2, 12}},
    {'A', {14, 17, 17, 31, 17, 17, 17}}, {'B', {30, 17, 17, 30, 17, 17, 30}},
    {'C', {14, 17, 16, 16, 16, 17, 14}}, {'D', {28, 18, 17, 17, 17, 18, 28}},
    {'E', {31, 16, 16, 30, 16, 16, 31}}, {'F', {31, 16, 16, 30, 16, 16, 16}},
    {'G', {14, 17, 16, 23, 17, 17, 15}}, {'H', {17, 17, 17, 31, 17, 17, 17}},
    {'I', {14, 4, 4, 4, 4, 4, 14}},      {'J', {7, 2, 2, 2, 2, 18, 12}},
    {'K', {17, 18, 20, 24, 20, 18, 17}}, {'L', {16, 16, 16, 16, 16, 16, 31}},
    {'M', {17, 27, 21, 21, 17, 17, 17}}, {'N', {17, 17, 25, 21, 19, 17, 17}},
    {'O', {14, 17, 17, 17, 17, 17, 14}}, {'P', {30, 17, 17, 30, 16, 16, 16}},
    {'Q', {14, 17, 17, 17, 21, 18, 13}}, {'R', {30, 17, 17, 30, 20, 18, 17}},
    {'S', {15, 16, 16, 14, 1, 1, 30}},   {'T', {31, 4, 4, 4, 4, 4, 4}},
    {'U', {17, 17, 17, 17, 17, 17, 14}}, {'V', {17, 17, 17, 17, 17, 10, 4}},
    {'W', {17, 17, 17, 21, 21, 21, 10}}, {'X', {17, 17, 10, 4, 10, 17, 17}},
    {'Y', {17, 17, 17, 10, 4, 4, 4}},    {'Z', {31, 1, 2, 4, 8, 16, 31}},
    {'.', {0, 0, 0, 0, 0, 12, 12}},      {',', {0, 0, 0, 0, 12, 4, 8}},
    {':', {0, 12, 12, 0, 12, 12, 0}},    {'-', {0, 0, 0, 31, 0, 0, 0}},
    {'+', {0, 4, 4, 31, 4, 4, 0}},       {'=', {0, 0, 31, 0, 31, 0, 0}},
    {'/', {0, 1, 2, 4, 8, 16, 0}},       {'(', {2, 4, 8, 8, 8, 4, 2}},
    {')', {8, 4, 2, 2, 2, 4, 8}},        {'%', {24, 25, 2, 4, 8, 19, 3}},
    {'#', {10, 10, 31, 10, 31, 10, 10}}, {'_', {0, 0, 0, 0, 0, 0, 31}},
    {'<', {2, 4, 8, 16, 8, 4, 2}},       {'>', {8, 4, 2, 1, 2, 4, 8}},
    {'\'', {12, 4, 8, 0, 0, 0, 0}},      {'?', {14, 17, 1, 2, 4, 0, 4}},
    {'[', {14, 8, 8, 8, 8, 8, 14}},      {']', {14, 2, 2, 2, 2, 2, 14}},
    {'|', {4, 4, 4, 4, 4, 4, 4}},        {'*', {0, 4, 21, 14, 21, 4, 0}},
    {'~', {0, 0, 8, 21, 2, 0, 0}},
};

static const uint8_t *glyph_of(char ch)
{
    size_t i;
    if (ch >= 'a' && ch <= 'z')
        ch = (char)(ch - 'a' + 'A');
    for (i = 0; i < sizeof font / sizeof font[0]; i++)
        if (font[i].ch == ch)
            return font[i].row;
    return NULL;
}

int canvas_text_width(const char *text, int scale)
{
    int n = (int)strlen(text);
    return n > 0 ? (6 * n - 1) * scale : 0;
}

void canvas_text(canvas *cv, int x, int y, int scale, const char *text, rgb_t c)
{
    for (; *text; text++, x += 6 * scale) {
        const uint8_t *g;
        int row, col;
        if (*text == ' ')
            continue;
        g = glyph_of(*text);
        if (!g)
            g = glyph_of('?');
        for (row = 0; row < 7; row++)
            for (col = 0; col < 5; col++)
                if (g[row] & (16 >> col))
                    canvas_rect(cv, x + col * scale, y + row * scale, scale, scale, c, 1.0f);
    }
}

void canvas_label(canvas *cv, int x, int y, int scale, const char *text, rgb_t c)
{
    const rgb_t dark = {0, 0, 0};
    canvas_rect(cv, x - scale, y - scale, canvas_text_width(text, scale) + 2 * scale,
                9 * scale, dark, 0.7f);
    canvas_text(cv, x, y, scale, text, c);
}

void canvas_grey(canvas *cv, int x0, int y0, const uint8_t *grey, int rows, int cols,
                 int stride)
{
    int r, c;
    for (r = 0; r < rows; r++)
        for (c = 0; c < cols; c++) {
            uint8_t v = grey[(size_t)r * (size_t)stride + (size_t)c];
            rgb_t g;
            g.r = g.g = g.b = v;
            canvas_put(cv, x0 + c, y0 + r, g, 1.0f);
        }
}
