/* actag_detect's overlay and stage pictures (see pictures.h). */
#include "pictures.h"

#include "canvas.h"
#include "hostio.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI_F 3.14159265f
#define RAD2DEG (180.0 / 3.14159265358979323846)

/* ---------------------------------------------------------------- colours */

static const rgb_t C_EDGE = {0, 230, 0};
static const rgb_t C_CORNER0 = {255, 30, 30};
static const rgb_t C_CORNER = {255, 150, 40};
static const rgb_t C_BIT1 = {255, 240, 0};
static const rgb_t C_BIT0 = {40, 120, 255};
static const rgb_t C_LABEL = {0, 255, 255};
static const rgb_t C_REJ_QUAD = {255, 140, 0};
static const rgb_t C_REJ_SEARCH = {255, 0, 220};
static const rgb_t C_REJ_GUESS = {90, 200, 255};
static const rgb_t C_TEXT = {230, 230, 230};
static const rgb_t C_GRID = {90, 160, 200};
static const rgb_t C_BG = {16, 20, 32};
static const rgb_t C_PANEL = {0, 0, 0};
static const rgb_t C_WHITE = {255, 255, 255};
static const rgb_t C_BLACK = {0, 0, 0};
static const rgb_t C_RED = {255, 40, 40};
static const rgb_t C_GREEN = {0, 220, 0};
static const rgb_t C_ORANGE = {255, 150, 0};
static const rgb_t C_VIOLET = {190, 90, 255};
static const rgb_t C_YELLOW = {255, 230, 0};
static const rgb_t C_MAGENTA = {255, 0, 255};
static const rgb_t C_GREY = {128, 128, 128};

#define REJECTED_ALPHA 0.45f

/* ---------------------------------------------------------------- trace */

void pic_trace_init(pic_trace *t, int keep_contours)
{
    memset(t, 0, sizeof *t);
    t->keep_contours = keep_contours;
}

void pic_trace_clear(pic_trace *t)
{
    t->ncand = 0;
    t->ncont = 0;
    t->npoints = 0;
    t->oom = 0;
}

void pic_trace_free(pic_trace *t)
{
    free(t->cand);
    free(t->cont);
    free(t->points);
    memset(t, 0, sizeof *t);
}

/* Grows *buf to hold `need` elements of `size` bytes. */
static int grow(void **buf, size_t *cap, size_t need, size_t size)
{
    size_t ncap;
    void *nb;
    if (need <= *cap)
        return 0;
    ncap = *cap ? *cap : 64;
    while (ncap < need)
        ncap *= 2;
    nb = realloc(*buf, ncap * size);
    if (!nb)
        return -1;
    *buf = nb;
    *cap = ncap;
    return 0;
}

void pic_trace_event(void *user, const actag_trace_event *e)
{
    pic_trace *t = (pic_trace *)user;
    if (e->kind == ACTAG_TRACE_CONTOUR) {
        pic_contour *c;
        size_t cap = (size_t)t->cap_cont;
        if (!t->keep_contours)
            return;
        if (grow((void **)&t->cont, &cap, (size_t)t->ncont + 1, sizeof *t->cont) != 0 ||
            grow((void **)&t->points, &t->cap_points, t->npoints + (size_t)e->npoints,
                 sizeof *t->points) != 0) {
            t->cap_cont = (int)cap;
            t->oom = 1;
            return;
        }
        t->cap_cont = (int)cap;
        c = &t->cont[t->ncont++];
        c->outcome = e->outcome;
        c->first = t->npoints;
        c->npoints = e->npoints;
        c->min_x = e->contour->min_x;
        c->max_x = e->contour->max_x;
        c->min_y = e->contour->min_y;
        c->max_y = e->contour->max_y;
        if (e->npoints > 0)
            memcpy(t->points + t->npoints, e->points, (size_t)e->npoints * sizeof *t->points);
        t->npoints += (size_t)e->npoints;
    } else {
        pic_candidate *c;
        size_t cap = (size_t)t->cap_cand;
        if (grow((void **)&t->cand, &cap, (size_t)t->ncand + 1, sizeof *t->cand) != 0) {
            t->oom = 1;
            return;
        }
        t->cap_cand = (int)cap;
        c = &t->cand[t->ncand++];
        c->kind = e->kind;
        c->outcome = e->outcome;
        memcpy(c->quad, e->quad, sizeof c->quad);
        c->id = e->decoded ? e->decoded->id : -1;
    }
}

/* ---------------------------------------------------------------- views */

/* Index (fractional) of v in a strictly monotonic table, half a step of
 * extrapolation allowed at either end; -1 outside. */
static float table_index(const float *t, int n, float v)
{
    int lo = 0, hi = n - 1, asc;
    float step;
    if (n == 1)
        return fabsf(v - t[0]) < 1e-6f ? 0.0f : -1.0f;
    asc = t[n - 1] > t[0];
    step = 0.5f * (t[1] - t[0]);
    if (asc ? (v < t[0] - fabsf(step)) : (v > t[0] + fabsf(step)))
        return -1.0f;
    step = 0.5f * fabsf(t[n - 1] - t[n - 2]);
    if (asc ? (v > t[n - 1] + step) : (v < t[n - 1] - step))
        return -1.0f;
    if (asc ? v <= t[0] : v >= t[0])
        return 0.0f;
    if (asc ? v >= t[n - 1] : v <= t[n - 1])
        return (float)(n - 1);
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (asc ? t[mid] <= v : t[mid] >= v)
            lo = mid;
        else
            hi = mid;
    }
    return (float)lo + (v - t[lo]) / (t[hi] - t[lo]);
}

/* The fan panel: metres to canvas pixels. */
typedef struct fan {
    int x0, y0, w, h;     /* panel on the canvas */
    float ox, oy, scale;  /* the sonar (apex) in canvas pixels; pixels per metre */
    float *row_range;     /* range of each row's centre */
    float *col_az;        /* azimuth of each column's centre */
    float rmin, rmax, azmin, azmax;
} fan;

static void fan_free(fan *fn)
{
    free(fn->row_range);
    free(fn->col_az);
    fn->row_range = fn->col_az = NULL;
}

/* The tallest fan panel of an overlay, pixels. */
#define PIC_FAN_MAX_H 2048

/* Sets up a fan of height h for frame f; fn->w is the width it needs.
 * Returns -1 with a message in err (path labels it) when memory runs out or
 * the geometry's fan cannot be drawn: ranges so large (1e30..3e38 m, which
 * the library accepts) that the fan's extent or a pixel's squared distance
 * is not finite in float made a NaN canvas width, converted to int. */
static int fan_setup(fan *fn, const pic_frame *f, int h, const char *path, char *err)
{
    const int pad = 24;
    int i;
    float lmin = 0, lmax = 0, xmin = 0, xmax = 0;
    double wd;
    memset(fn, 0, sizeof *fn);
    fn->row_range = (float *)malloc((size_t)f->rows * sizeof(float));
    fn->col_az = (float *)malloc((size_t)f->cols * sizeof(float));
    if (!fn->row_range || !fn->col_az) {
        fan_free(fn);
        snprintf(err, HOSTIO_ERRLEN, "%.200s: out of memory", path);
        return -1;
    }
    for (i = 0; i < f->rows; i++)
        fn->row_range[i] = actag_geometry_range(f->geo, f->rows, (float)i);
    for (i = 0; i < f->cols; i++)
        fn->col_az[i] = actag_geometry_azimuth(f->geo, f->cols, (float)i);
    fn->rmin = fminf(fn->row_range[0], fn->row_range[f->rows - 1]);
    fn->rmax = fmaxf(fn->row_range[0], fn->row_range[f->rows - 1]);
    fn->azmin = fminf(fn->col_az[0], fn->col_az[f->cols - 1]);
    fn->azmax = fmaxf(fn->col_az[0], fn->col_az[f->cols - 1]);
    for (i = 0; i <= 64; i++) { /* the outer arc bounds the fan (with the apex) */
        float az = fn->azmin + (fn->azmax - fn->azmin) * (float)i / 64.0f;
        float l = fn->rmax * sinf(az), x = fn->rmax * cosf(az);
        lmin = fminf(lmin, l);
        lmax = fmaxf(lmax, l);
        xmin = fminf(xmin, x);
        xmax = fmaxf(xmax, x);
    }
    /* fan_paint squares a pixel's distance in metres: the extent squared must
     * be finite too (ranges up to about 1e18 m) */
    if (!isfinite(fn->rmin) || !isfinite(fn->rmax) || !isfinite(fn->azmin) ||
        !isfinite(fn->azmax) || !isfinite((xmax - xmin) * (xmax - xmin) + (lmax - lmin) * (lmax - lmin))) {
        snprintf(err, HOSTIO_ERRLEN,
                 "%.60s: no fan picture for ranges %.3g..%.3g m, azimuths %.4g..%.4g deg "
                 "(--min-range/--max-range/--aperture-deg or --bearings): too large",
                 path, (double)f->geo->min_range, (double)f->geo->max_range, (double)fn->azmin * RAD2DEG,
                 (double)fn->azmax * RAD2DEG);
        fan_free(fn);
        return -1;
    }
    fn->h = h;
    fn->scale = (float)(h - 2 * pad) / fmaxf(xmax - xmin, 1e-6f);
    if ((lmax - lmin) * fn->scale > 3.0f * (float)h) /* very wide fans: keep it sane */
        fn->scale = 3.0f * (float)h / (lmax - lmin);
    wd = ceil((double)(lmax - lmin) * (double)fn->scale) + 2.0 * pad;
    fn->ox = (float)pad + lmax * fn->scale; /* left (positive azimuth) is to the left */
    fn->oy = (float)pad + xmax * fn->scale;
    /* checked before the conversion to int: at most 3 h wide (above) */
    if (!(fn->scale > 0.0f) || !isfinite(fn->scale) || !(wd >= 1.0) ||
        !(wd <= 3.0 * h + 2.0 * pad + 1.0) || !isfinite(fn->ox) || !isfinite(fn->oy)) {
        snprintf(err, HOSTIO_ERRLEN,
                 "%.60s: no fan picture for ranges %.3g..%.3g m, azimuths %.4g..%.4g deg "
                 "(--min-range/--max-range/--aperture-deg or --bearings): no sane size",
                 path, (double)f->geo->min_range, (double)f->geo->max_range, (double)fn->azmin * RAD2DEG,
                 (double)fn->azmax * RAD2DEG);
        fan_free(fn);
        return -1;
    }
    fn->w = (int)wd;
    return 0;
}

static void fan_place(fan *fn, int x0, int y0)
{
    fn->x0 = x0;
    fn->y0 = y0;
    fn->ox += (float)x0;
    fn->oy += (float)y0;
}

/* (range, azimuth) -> canvas pixel. */
static void fan_polar(const fan *fn, float r, float az, float *u, float *v)
{
    *u = fn->ox - r * sinf(az) * fn->scale;
    *v = fn->oy - r * cosf(az) * fn->scale;
}

/* Resamples the 8-bit frame into the fan panel (bilinear). */
static void fan_paint(canvas *cv, const fan *fn, const pic_frame *f)
{
    int u, v;
    for (v = fn->y0; v < fn->y0 + fn->h; v++)
        for (u = fn->x0; u < fn->x0 + fn->w; u++) {
            float l = (fn->ox - (float)u) / fn->scale, x = (fn->oy - (float)v) / fn->scale;
            float r = sqrtf(l * l + x * x), az = atan2f(l, x);
            float ri = table_index(fn->row_range, f->rows, r);
            float ci = table_index(fn->col_az, f->cols, az);
            rgb_t g;
            if (ri < 0.0f || ci < 0.0f) {
                canvas_put(cv, u, v, C_BG, 1.0f);
                continue;
            }
            {
                int r0 = (int)ri, c0 = (int)ci;
                int r1 = r0 + 1 < f->rows ? r0 + 1 : r0, c1 = c0 + 1 < f->cols ? c0 + 1 : c0;
                float fr = ri - (float)r0, fc = ci - (float)c0;
                const uint8_t *p = f->input8;
                float a = p[(size_t)r0 * (size_t)f->cols + (size_t)c0];
                float b = p[(size_t)r0 * (size_t)f->cols + (size_t)c1];
                float c = p[(size_t)r1 * (size_t)f->cols + (size_t)c0];
                float d = p[(size_t)r1 * (size_t)f->cols + (size_t)c1];
                float val = (1 - fr) * ((1 - fc) * a + fc * b) + fr * ((1 - fc) * c + fc * d);
                g.r = g.g = g.b = (uint8_t)lroundf(val);
            }
            canvas_put(cv, u, v, g, 1.0f);
        }
}

/* A nice step for about n divisions of span. */
static float nice_step(float span, int n)
{
    static const float m[4] = {1.0f, 2.0f, 2.5f, 5.0f};
    float e = powf(10.0f, floorf(log10f(span / (float)n))), best = e;
    int i;
    for (i = 0; i < 4; i++)
        if (span / (m[i] * e) >= (float)n * 0.7f)
            best = m[i] * e;
    return best;
}

static void fan_grid(canvas *cv, const fan *fn)
{
    float step = nice_step(fn->rmax, 4), r, u, v, u2, v2;
    int i, k;
    char buf[32];
    for (k = 1; (r = step * (float)k) <= fn->rmax * 1.0001f; k++) {
        for (i = 0; i < 96; i++) {
            float a0 = fn->azmin + (fn->azmax - fn->azmin) * (float)i / 96.0f;
            float a1 = fn->azmin + (fn->azmax - fn->azmin) * (float)(i + 1) / 96.0f;
            fan_polar(fn, r, a0, &u, &v);
            fan_polar(fn, r, a1, &u2, &v2);
            canvas_line(cv, u, v, u2, v2, C_GRID, 0.6f);
        }
        /* labelled inside the fan, below the arc's left (+azimuth) end */
        fan_polar(fn, r * 0.985f, fn->azmax - 0.02f * (fn->azmax - fn->azmin), &u, &v);
        snprintf(buf, sizeof buf, "%g M", (double)r);
        canvas_label(cv, (int)u + 4, (int)v + 4, 1, buf, C_GRID);
    }
    {
        float az[3];
        int n = 0;
        az[n++] = fn->azmax;
        if (fn->azmin < 0.0f && fn->azmax > 0.0f)
            az[n++] = 0.0f;
        az[n++] = fn->azmin;
        for (i = 0; i < n; i++) {
            fan_polar(fn, 0.0f, az[i], &u, &v);
            fan_polar(fn, fn->rmax, az[i], &u2, &v2);
            canvas_line(cv, u, v, u2, v2, C_GRID, 0.6f);
            snprintf(buf, sizeof buf, "%+.1f DEG", (double)az[i] * RAD2DEG);
            canvas_label(cv, (int)u2 - canvas_text_width(buf, 1) / 2, (int)v2 - 14, 1, buf,
                         C_GRID);
        }
    }
    fan_polar(fn, 0.0f, 0.0f, &u, &v);
    canvas_dot(cv, u, v, 2, C_WHITE, 1.0f);
    canvas_label(cv, (int)u + 6, (int)v - 3, 1, "SONAR", C_TEXT);
}

/* Where an image point goes in a view: the polar panel (fan == NULL) or the fan. */
typedef struct view {
    int x0, y0;       /* polar: where image point (ox, oy) lands on the canvas */
    float ox, oy;
    float zoom;       /* polar: canvas pixels per image pixel */
    const fan *fan;   /* NULL: polar */
    const pic_frame *f;
} view;

static view polar_view(const pic_frame *f, int x0, int y0)
{
    view vw;
    vw.x0 = x0;
    vw.y0 = y0;
    vw.ox = vw.oy = 0.0f;
    vw.zoom = 1.0f;
    vw.fan = NULL;
    vw.f = f;
    return vw;
}

static void view_map(const view *vw, actag_point p, float *u, float *v)
{
    if (!vw->fan) {
        *u = (float)vw->x0 + (p.x - vw->ox) * vw->zoom;
        *v = (float)vw->y0 + (p.y - vw->oy) * vw->zoom;
    } else {
        float r = actag_geometry_range(vw->f->geo, vw->f->rows, p.y);
        float az = actag_geometry_azimuth(vw->f->geo, vw->f->cols, p.x);
        fan_polar(vw->fan, r, az, u, v);
    }
}

/* An image-space segment, bent through the view (polar: straight). */
static void view_segment(canvas *cv, const view *vw, actag_point a, actag_point b, rgb_t c,
                         float alpha)
{
    int i, n = vw->fan ? 12 : 1;
    float u0, v0;
    view_map(vw, a, &u0, &v0);
    for (i = 1; i <= n; i++) {
        actag_point p;
        float u1, v1;
        p.x = a.x + (b.x - a.x) * (float)i / (float)n;
        p.y = a.y + (b.y - a.y) * (float)i / (float)n;
        view_map(vw, p, &u1, &v1);
        canvas_line(cv, u0, v0, u1, v1, c, alpha);
        u0 = u1;
        v0 = v1;
    }
}

static void view_quad(canvas *cv, const view *vw, const actag_point q[4], rgb_t c, float alpha)
{
    int k;
    for (k = 0; k < 4; k++)
        view_segment(cv, vw, q[k], q[(k + 1) % 4], c, alpha);
}

static actag_point quad_centre(const actag_point q[4])
{
    actag_point m;
    m.x = 0.25f * (q[0].x + q[1].x + q[2].x + q[3].x);
    m.y = 0.25f * (q[0].y + q[1].y + q[2].y + q[3].y);
    return m;
}

static int binary_at(const pic_frame *f, actag_point p)
{
    int x = (int)lroundf(p.x), y = (int)lroundf(p.y);
    return x >= 0 && y >= 0 && x < f->cols && y < f->rows &&
           f->binary[(size_t)y * (size_t)f->cols + (size_t)x] != 0;
}

static void draw_rejected(canvas *cv, const view *vw, const pic_trace *t)
{
    int i;
    if (!t)
        return;
    for (i = 0; i < t->ncand; i++) {
        const pic_candidate *c = &t->cand[i];
        if (c->outcome == ACTAG_TRACE_ACCEPTED)
            continue;
        view_quad(cv, vw, c->quad,
                  c->kind == ACTAG_TRACE_SEARCH  ? C_REJ_SEARCH
                  : c->kind == ACTAG_TRACE_GUESS ? C_REJ_GUESS
                                                 : C_REJ_QUAD,
                  REJECTED_ALPHA);
    }
}

static void draw_detections(canvas *cv, const view *vw, const pic_frame *f)
{
    int i, k;
    for (i = 0; i < f->ndet; i++) {
        const actag_detection *d = &f->det[i];
        actag_point bitpos[32];
        float u, v, top = 1e9f, left = 1e9f;
        char buf[32];
        if (actag_decode_bit_positions(d->corners, f->params->family->bits, bitpos) == ACTAG_OK)
            for (k = 0; k < f->params->family->bits; k++) {
                view_map(vw, bitpos[k], &u, &v);
                canvas_dot(cv, u, v, 1, binary_at(f, bitpos[k]) ? C_BIT1 : C_BIT0,
                           1.0f);
            }
        view_quad(cv, vw, d->corners, C_EDGE, 1.0f);
        for (k = 0; k < 4; k++) {
            view_map(vw, d->corners[k], &u, &v);
            canvas_dot(cv, u, v, k == 0 ? 2 : 1, k == 0 ? C_CORNER0 : C_CORNER, 1.0f);
            snprintf(buf, sizeof buf, "%d", k);
            canvas_text(cv, (int)u + 3, (int)v + 3, 1, buf, k == 0 ? C_CORNER0 : C_CORNER);
            top = fminf(top, v);
            left = fminf(left, u);
        }
        snprintf(buf, sizeof buf, "#%d ID %d", i + 1, d->id);
        canvas_label(cv, (int)left, (int)top - 14, 1, buf, C_LABEL);
    }
}

/* Text at scale 2 when it fits in maxw, else at scale 1. */
static void title(canvas *cv, int x, int y, int maxw, const char *text)
{
    int s = canvas_text_width(text, 2) <= maxw ? 2 : 1;
    canvas_text(cv, x, y, s, text, C_TEXT);
}

/* ---------------------------------------------------------------- legends */

/* A legend is a flow of items (a colour swatch and text) in lines of at
 * most `width` pixels; laid out twice: to measure (cv NULL) and to draw. */
typedef struct item {
    int swatch; /* 0 none, 1 line, 2 dot, 3 faint line, 4 filled box */
    rgb_t colour;
    char text[192];
    int newline; /* start a new line before this item */
} item;

#define LEGEND_SCALE 2
#define LEGEND_LINE (10 * LEGEND_SCALE)

static int legend_flow(canvas *cv, int x0, int y0, int width, const item *it, int n)
{
    int i, x = x0, y = y0, used = 0;
    for (i = 0; i < n; i++) {
        int sw = it[i].swatch ? 3 * LEGEND_SCALE * 3 : 0;
        char text[sizeof it[i].text];
        int w, len = (int)strlen(it[i].text), fit = (width - sw) / (6 * LEGEND_SCALE);
        if (len > fit && fit > 4) /* too long for a line: keep its end */
            snprintf(text, sizeof text, "...%s", it[i].text + len - (fit - 3));
        else /* a copy (snprintf("%s") here draws a false -Wformat-truncation on 32-bit GCC) */
            memcpy(text, it[i].text, sizeof text);
        text[sizeof text - 1] = '\0';
        w = sw + canvas_text_width(text, LEGEND_SCALE) + 4 * LEGEND_SCALE * 3;
        if (used && (it[i].newline || x + w > x0 + width)) {
            x = x0;
            y += LEGEND_LINE;
        }
        used = 1;
        if (cv) {
            int my = y + 3 * LEGEND_SCALE;
            switch (it[i].swatch) {
            case 1:
                canvas_rect(cv, x, my, sw - 6, 2, it[i].colour, 1.0f);
                break;
            case 2:
                canvas_dot(cv, (float)(x + sw / 2 - 3), (float)my, 2, it[i].colour, 1.0f);
                break;
            case 3:
                canvas_rect(cv, x, my, sw - 6, 2, it[i].colour, REJECTED_ALPHA + 0.2f);
                break;
            case 4:
                canvas_rect(cv, x, my - 5, sw - 6, 11, it[i].colour, 1.0f);
                break;
            default:
                break;
            }
            canvas_text(cv, x + sw, y, LEGEND_SCALE, text, C_TEXT);
        }
        x += w;
    }
    return used ? y - y0 + LEGEND_LINE : 0;
}

static item mk(int swatch, rgb_t c, int newline, const char *text)
{
    item it;
    size_t n = strlen(text);
    it.swatch = swatch;
    it.colour = c;
    it.newline = newline;
    if (n >= sizeof it.text)
        n = sizeof it.text - 1;
    memcpy(it.text, text, n);
    it.text[n] = '\0';
    return it;
}

/* ---------------------------------------------------------------- overlay */

#define MAX_ITEMS 96

int pic_overlay(const char *path, const pic_frame *f, int show_rejected, char *err)
{
    const int gap = 12, title_h = 26, margin = 10;
    fan fn;
    canvas cv;
    view pv, fv;
    item it[MAX_ITEMS];
    int n = 0, i, w, h, legend_h, nrej = 0, nrej_search = 0, nrej_guess = 0;
    char buf[160];

    /* the fan panel is as tall as the frame, but at most PIC_FAN_MAX_H
     * pixels (it may be 3 times as wide): a frame of 32,767 rows would
     * otherwise take a picture of gigabytes */
    if (fan_setup(&fn, f, f->rows < PIC_FAN_MAX_H ? f->rows : PIC_FAN_MAX_H, path, err) != 0)
        return -1;
    w = margin + f->cols + gap + fn.w + margin;
    if (f->trace)
        for (i = 0; i < f->trace->ncand; i++)
            if (f->trace->cand[i].outcome != ACTAG_TRACE_ACCEPTED) {
                nrej++;
                nrej_search += f->trace->cand[i].kind == ACTAG_TRACE_SEARCH;
                nrej_guess += f->trace->cand[i].kind == ACTAG_TRACE_GUESS;
            }

    /* the legend */
    snprintf(buf, sizeof buf, "%s: %d X %d (ROWS X COLUMNS), %s, %d TAG%s", f->name, f->rows,
             f->cols, f->params->family->name, f->ndet, f->ndet == 1 ? "" : "S");
    it[n++] = mk(0, C_TEXT, 0, buf);
    it[n++] = mk(1, C_EDGE, 1, "TAG EDGE");
    it[n++] = mk(2, C_CORNER0, 0, "CORNER 0 = TOP-LEFT AS PRINTED");
    it[n++] = mk(2, C_CORNER, 0, "CORNERS 1 2 3 CLOCKWISE AS PRINTED");
    it[n++] = mk(2, C_BIT1, 0, "BIT READ 1");
    it[n++] = mk(2, C_BIT0, 0, "BIT READ 0");
    if (show_rejected) {
        snprintf(buf, sizeof buf, "REJECTED QUAD (%d)", nrej - nrej_search - nrej_guess);
        it[n++] = mk(3, C_REJ_QUAD, 0, buf);
        snprintf(buf, sizeof buf, "REJECTED SEARCH BOX (%d)", nrej_search);
        it[n++] = mk(3, C_REJ_SEARCH, 0, buf);
        snprintf(buf, sizeof buf, "REJECTED GRID GUESS (%d)", nrej_guess);
        it[n++] = mk(3, C_REJ_GUESS, 0, buf);
    }
    for (i = 0; i < f->ndet && n < MAX_ITEMS - 1; i++) {
        const actag_detection *d = &f->det[i];
        actag_point m = quad_centre(d->corners);
        float r = actag_geometry_range(f->geo, f->rows, m.y);
        float az = actag_geometry_azimuth(f->geo, f->cols, m.x);
        snprintf(buf, sizeof buf,
                 "#%d  ID %d  HAMMING %d  MARGIN %.1f  MIRRORED %s  AT %.3f M, %+.2f DEG", i + 1,
                 d->id, d->hamming, (double)d->decision_margin, d->mirrored ? "YES" : "NO",
                 (double)r, (double)az * RAD2DEG);
        it[n++] = mk(0, C_LABEL, 1, buf);
    }
    if (f->ndet == 0)
        it[n++] = mk(0, C_TEXT, 1,
                     show_rejected ? "NO TAG FOUND" : "NO TAG FOUND (--SHOW-REJECTED DRAWS THE CANDIDATES)");
    legend_h = legend_flow(NULL, margin, 0, w - 2 * margin, it, n) + margin;
    h = title_h + f->rows + gap + legend_h + margin;

    if (canvas_new(&cv, w, h, C_PANEL) != 0) {
        fan_free(&fn);
        snprintf(err, HOSTIO_ERRLEN, "%.200s: out of memory", path);
        return -1;
    }
    /* polar panel */
    pv = polar_view(f, margin, title_h);
    title(&cv, margin, 6, f->cols, "POLAR: X = COLUMN (BEAM), Y = ROW (RANGE)");
    canvas_grey(&cv, pv.x0, pv.y0, f->input8, f->rows, f->cols, f->cols);
    if (show_rejected)
        draw_rejected(&cv, &pv, f->trace);
    draw_detections(&cv, &pv, f);
    /* where the frame's edges are in range and azimuth */
    snprintf(buf, sizeof buf, "ROW 0: %.2f M", (double)fn.row_range[0]);
    canvas_label(&cv, pv.x0 + 3, pv.y0 + 3, 1, buf, C_GRID);
    snprintf(buf, sizeof buf, "ROW %d: %.2f M", f->rows - 1, (double)fn.row_range[f->rows - 1]);
    canvas_label(&cv, pv.x0 + 3, pv.y0 + f->rows - 10, 1, buf, C_GRID);
    snprintf(buf, sizeof buf, "COL 0: %+.1f DEG", (double)fn.col_az[0] * RAD2DEG);
    canvas_label(&cv, pv.x0 + 3, pv.y0 + 14, 1, buf, C_GRID);
    snprintf(buf, sizeof buf, "COL %d: %+.1f DEG", f->cols - 1,
             (double)fn.col_az[f->cols - 1] * RAD2DEG);
    canvas_label(&cv, pv.x0 + f->cols - canvas_text_width(buf, 1) - 3, pv.y0 + 3, 1, buf,
                 C_GRID);
    /* fan panel */
    fan_place(&fn, margin + f->cols + gap, title_h);
    title(&cv, fn.x0, 6, fn.w, "FAN: SONAR BELOW, +AZIMUTH LEFT");
    fan_paint(&cv, &fn, f);
    fan_grid(&cv, &fn);
    fv = polar_view(f, 0, 0);
    fv.fan = &fn;
    if (show_rejected)
        draw_rejected(&cv, &fv, f->trace);
    draw_detections(&cv, &fv, f);
    /* legend */
    legend_flow(&cv, margin, title_h + f->rows + gap, w - 2 * margin, it, n);

    i = hostio_ppm_write(path, cv.rgb, cv.h, cv.w, err);
    canvas_free(&cv);
    fan_free(&fn);
    return i;
}

/* ---------------------------------------------------------------- stages */

/* The stage files, in pipeline order: their one list (pic_stage_path) */
void pic_stage_path(const char *dir, const char *stem, int i, char *out, size_t n)
{
    static const char *const name[PIC_STAGE_FILES] = {
        "1-input.pgm", "2-median.pgm", "3-search.ppm", "4-binary.pgm",
        "5-contours.ppm", "6-quads.ppm", "7-decoded.ppm"};
    snprintf(out, n, "%s/%s-%s", dir, stem, name[i < 0 || i >= PIC_STAGE_FILES ? 0 : i]);
}

/* Stage file `stage` (pic_stage_path's index; a .pgm) from px. */
static int write_grey(const char *dir, const char *stem, int stage, const uint8_t *px,
                      int rows, int cols, int binary, char *err)
{
    char path[4096];
    hostio_image im;
    uint8_t *copy = NULL;
    int rc;
    pic_stage_path(dir, stem, stage, path, sizeof path);
    if (binary) {
        size_t i, n = (size_t)rows * (size_t)cols;
        copy = (uint8_t *)malloc(n);
        if (!copy) {
            snprintf(err, HOSTIO_ERRLEN, "%.200s: out of memory", path);
            return -1;
        }
        for (i = 0; i < n; i++)
            copy[i] = px[i] ? 255 : 0;
    }
    memset(&im, 0, sizeof im);
    im.data = copy ? copy : (void *)(uintptr_t)px;
    im.rows = rows;
    im.cols = cols;
    im.stride = cols;
    im.depth = 8;
    im.maxval = 255;
    rc = hostio_pgm_write(path, &im, err);
    free(copy);
    return rc;
}

/* A colour stage: the frame-sized picture (cv, rows x cols at the top) and a
 * legend strip below it. */
static int colour_stage(canvas *cv, const pic_frame *f, const item *it, int n)
{
    int legend_h = legend_flow(NULL, 6, 0, f->cols - 12, it, n) + 12;
    if (f->cols < 160) /* no room for a legend */
        legend_h = 0;
    return canvas_new(cv, f->cols, f->rows + legend_h, C_PANEL);
}

/* Stage file `stage` (pic_stage_path's index; a .ppm) from cv, legend added. */
static int finish_stage(canvas *cv, const pic_frame *f, const item *it, int n, const char *dir,
                        const char *stem, int stage, char *err)
{
    char path[4096];
    int rc;
    if (f->cols >= 160) /* as colour_stage() made room */
        legend_flow(cv, 6, f->rows + 6, f->cols - 12, it, n);
    pic_stage_path(dir, stem, stage, path, sizeof path);
    rc = hostio_ppm_write(path, cv->rgb, cv->h, cv->w, err);
    canvas_free(cv);
    return rc;
}

static void oom(char *err, const char *dir, const char *stem)
{
    snprintf(err, HOSTIO_ERRLEN, "%.100s/%.100s: out of memory for the stage images", dir, stem);
}

static int stage_search(const char *dir, const char *stem, const pic_frame *f, char *err)
{
    const actag_params *p = f->params;
    size_t msize = ACTAG_SEARCH_MAP_SIZE(f->rows, f->cols) + 16u;
    size_t isize = ACTAG_SEARCH_INTEGRAL_SIZE(f->rows, f->cols) + 16u;
    void *map = malloc(msize), *ii = malloc(isize);
    actag_search z;
    canvas cv;
    item it[4];
    int n = 0, r, c, i, have;
    view vw;
    it[n++] = mk(4, C_GREY, 0, "GREY: 128 + 2 X BOX CONTRAST");
    it[n++] = mk(1, C_GREEN, 0, "KEPT");
    it[n++] = mk(1, C_RED, 0, "REJECTED");
    if (!map || !ii || colour_stage(&cv, f, it, n) != 0) {
        free(map);
        free(ii);
        oom(err, dir, stem);
        return -1;
    }
    have = actag_search_map(&z, f->filtered, f->rows, f->cols, f->cols, f->geo, p->tag_size,
                            p->family->bits, p->tuning.search_range_scale, map, msize, ii,
                            isize) == ACTAG_OK;
    for (r = 0; r < f->rows; r++)
        for (c = 0; c < f->cols; c++) {
            rgb_t g = {0, 0, 0};
            int br = r / ACTAG_SEARCH_FACTOR, bc = c / ACTAG_SEARCH_FACTOR;
            if (have && br < z.hr && bc < z.hc) {
                int s = z.map[(size_t)br * (size_t)z.hc + (size_t)bc];
                if (s != INT16_MIN) {
                    int v = 128 + s / 4; /* twice the box contrast */
                    g.r = g.g = g.b = (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : v);
                }
            }
            canvas_put(&cv, c, r, g, 1.0f);
        }
    vw = polar_view(f, 0, 0);
    if (f->trace)
        for (i = 0; i < f->trace->ncand; i++)
            if (f->trace->cand[i].kind == ACTAG_TRACE_SEARCH)
                view_quad(&cv, &vw, f->trace->cand[i].quad,
                          f->trace->cand[i].outcome == ACTAG_TRACE_ACCEPTED ? C_GREEN : C_RED,
                          1.0f);
    free(map);
    free(ii);
    return finish_stage(&cv, f, it, n, dir, stem, 2, err);
}

static int stage_contours(const char *dir, const char *stem, const pic_frame *f, char *err)
{
    canvas cv;
    item it[4];
    int n = 0, r, c, i, k;
    const pic_trace *t = f->trace;
    it[n++] = mk(2, C_YELLOW, 0, "SIZE OK");
    it[n++] = mk(2, C_RED, 0, "WRONG SIZE");
    it[n++] = mk(2, C_MAGENTA, 0, "TOO LONG");
    if (colour_stage(&cv, f, it, n) != 0) {
        oom(err, dir, stem);
        return -1;
    }
    for (r = 0; r < f->rows; r++)
        for (c = 0; c < f->cols; c++) {
            rgb_t g = {0, 0, 0};
            if (f->binary[(size_t)r * (size_t)f->cols + (size_t)c])
                g.r = g.g = g.b = 60;
            canvas_put(&cv, c, r, g, 1.0f);
        }
    if (t)
        for (i = 0; i < t->ncont; i++) {
            const pic_contour *pc = &t->cont[i];
            rgb_t col = pc->outcome == ACTAG_TRACE_ACCEPTED ? C_YELLOW
                        : pc->outcome == ACTAG_TRACE_SIZE   ? C_RED
                                                            : C_MAGENTA;
            if (pc->outcome == ACTAG_TRACE_SIZE)
                col.r = 170, col.g = 30, col.b = 30;
            if (pc->npoints == 0) { /* overflow: its bounding box */
                actag_point q[4];
                view vw;
                q[0].x = q[3].x = (float)pc->min_x;
                q[1].x = q[2].x = (float)pc->max_x;
                q[0].y = q[1].y = (float)pc->min_y;
                q[2].y = q[3].y = (float)pc->max_y;
                vw = polar_view(f, 0, 0);
                view_quad(&cv, &vw, q, col, 1.0f);
                continue;
            }
            for (k = 0; k < pc->npoints; k++) {
                const actag_ipoint *p = &t->points[pc->first + (size_t)k];
                canvas_put(&cv, p->x, p->y, col, 1.0f);
            }
        }
    return finish_stage(&cv, f, it, n, dir, stem, 4, err);
}

static int stage_quads(const char *dir, const char *stem, const pic_frame *f, char *err)
{
    canvas cv;
    item it[6];
    int n = 0, r, c, i;
    view vw;
    it[n++] = mk(1, C_GREEN, 0, "DECODED");
    it[n++] = mk(1, C_RED, 0, "SIDES");
    it[n++] = mk(1, C_ORANGE, 0, "NO CODE");
    it[n++] = mk(1, C_VIOLET, 0, "STRUCTURE");
    it[n++] = mk(3, C_TEXT, 1, "FAINT: GRID GUESS FROM A CONTOUR'S EXTREME POINTS");
    if (colour_stage(&cv, f, it, n) != 0) {
        oom(err, dir, stem);
        return -1;
    }
    for (r = 0; r < f->rows; r++)
        for (c = 0; c < f->cols; c++) {
            rgb_t g;
            g.r = g.g = g.b = (uint8_t)(f->filtered[(size_t)r * (size_t)f->cols + (size_t)c] * 3 / 4);
            canvas_put(&cv, c, r, g, 1.0f);
        }
    vw = polar_view(f, 0, 0);
    if (f->trace)
        for (i = 0; i < f->trace->ncand; i++) {
            const pic_candidate *q = &f->trace->cand[i];
            rgb_t col = q->outcome == ACTAG_TRACE_ACCEPTED ? C_GREEN
                        : q->outcome == ACTAG_TRACE_SIDES  ? C_RED
                        : q->outcome == ACTAG_TRACE_NO_MATCH ? C_ORANGE
                                                             : C_VIOLET;
            if (q->kind == ACTAG_TRACE_SEARCH)
                continue;
            view_quad(&cv, &vw, q->quad, col, q->kind == ACTAG_TRACE_GUESS ? 0.5f : 1.0f);
        }
    return finish_stage(&cv, f, it, n, dir, stem, 5, err);
}

/* The value cell (cx, cy) of a (k+1)-cell grid has for this code: data ring
 * from the code (bit 0 = MSB), black ring 0, interior 1; -1 for the data-ring
 * corners when the decoder skips them. */
static int cell_value(int cx, int cy, int k, uint32_t code, int skip_corners)
{
    int i;
    if (cx == 0 || cy == 0 || cx == k || cy == k) {
        if (cy == 0)
            i = cx;
        else if (cx == k)
            i = k + cy;
        else if (cy == k)
            i = 3 * k - cx;
        else
            i = 4 * k - cy;
        if (skip_corners && (i % k) == 0)
            return -1;
        return (int)((code >> (4 * k - 1 - i)) & 1u);
    }
    if (cx == 1 || cy == 1 || cx == k - 1 || cy == k - 1)
        return 0;
    return 1;
}

/* One detection's cell grid in a view. */
static void draw_grid(canvas *cv, const view *vw, const actag_detection *d, int skip)
{
    const pic_frame *f = vw->f;
    const actag_family *fam = f->params->family;
    int k = fam->bits / 4, cx, cy, g, rad = vw->zoom >= 3.0f ? (int)(vw->zoom * 0.9f) : 2;
    float H[9], u, v, u2, v2;
    uint32_t code;
    if (d->id < 0 || d->id >= fam->ncodes || actag_tag_affine(d->corners, fam->bits, H) != ACTAG_OK)
        return;
    code = fam->codes[d->id];
    for (g = 0; g <= k + 1; g++) { /* grid lines */
        actag_point a, b;
        actag_homography_apply(H, (float)g, 0.0f, &a);
        actag_homography_apply(H, (float)g, (float)(k + 1), &b);
        view_map(vw, a, &u, &v);
        view_map(vw, b, &u2, &v2);
        canvas_line(cv, u, v, u2, v2, C_GRID, 0.7f);
        actag_homography_apply(H, 0.0f, (float)g, &a);
        actag_homography_apply(H, (float)(k + 1), (float)g, &b);
        view_map(vw, a, &u, &v);
        view_map(vw, b, &u2, &v2);
        canvas_line(cv, u, v, u2, v2, C_GRID, 0.7f);
    }
    for (cy = 0; cy <= k; cy++)
        for (cx = 0; cx <= k; cx++) {
            actag_point p;
            int val = cell_value(cx, cy, k, code, skip);
            actag_homography_apply(H, (float)cx + 0.5f, (float)cy + 0.5f, &p);
            view_map(vw, p, &u, &v);
            if (val < 0) {
                canvas_dot(cv, u, v, rad, C_GREY, 1.0f);
                canvas_dot(cv, u, v, rad / 2, C_BLACK, 1.0f);
                continue;
            }
            canvas_dot(cv, u, v, rad, binary_at(f, p) == val ? C_GREEN : C_RED, 1.0f);
            canvas_dot(cv, u, v, rad / 2, val ? C_WHITE : C_BLACK, 1.0f);
        }
    view_quad(cv, vw, d->corners, C_EDGE, 1.0f);
}

#define MAX_ZOOM 6
#define MAX_INSETS 4

static int stage_decoded(const char *dir, const char *stem, const pic_frame *f, char *err)
{
    canvas cv, big;
    item it[6];
    int n = 0, r, c, i, ninset = f->ndet < MAX_INSETS ? f->ndet : MAX_INSETS;
    int skip = f->params->tuning.decode_mode == ACTAG_DECODE_FIT &&
               (f->params->tuning.fit.flags & ACTAG_FIT_ERASE_CORNERS) != 0;
    int box[MAX_INSETS][5], inset_h = 0, y_inset;
    const rgb_t dark = {40, 40, 40};
    view vw;
    it[n++] = mk(4, C_WHITE, 0, "CODE 1");
    it[n++] = mk(4, dark, 0, "CODE 0");
    it[n++] = mk(2, C_GREY, 0, "NOT READ");
    it[n++] = mk(2, C_GREEN, 1, "BINARY AGREES");
    it[n++] = mk(2, C_RED, 0, "DISAGREES");
    /* the enlarged crops below the legend, one under the other, each as
     * wide as the frame allows: the tag's bounding box plus a margin */
    for (i = 0; i < ninset; i++) {
        const actag_point *q = f->det[i].corners;
        float x0 = q[0].x, x1 = q[0].x, y0 = q[0].y, y1 = q[0].y, m;
        int k, z;
        for (k = 1; k < 4; k++) {
            x0 = fminf(x0, q[k].x);
            x1 = fmaxf(x1, q[k].x);
            y0 = fminf(y0, q[k].y);
            y1 = fmaxf(y1, q[k].y);
        }
        m = 0.55f * fmaxf(x1 - x0, y1 - y0) + 4.0f; /* the data ring and a little more */
        box[i][0] = (int)floorf(x0 - m);
        box[i][1] = (int)floorf(y0 - m);
        box[i][2] = (int)ceilf(x1 + m) - box[i][0] + 1;
        box[i][3] = (int)ceilf(y1 + m) - box[i][1] + 1;
        z = f->cols / box[i][2];
        if (z > MAX_ZOOM)
            z = MAX_ZOOM;
        if (z < 2 || box[i][3] * z > 4000) { /* the tag is large enough as it is */
            ninset = i;
            break;
        }
        box[i][4] = z;
        inset_h += box[i][3] * z + 8;
    }
    if (ninset > 0)
        it[n++] = mk(0, C_TEXT, 1, "BELOW: EACH TAG ENLARGED");
    if (colour_stage(&cv, f, it, n) != 0) {
        oom(err, dir, stem);
        return -1;
    }
    y_inset = cv.h;
    if (ninset > 0) { /* a taller canvas with room for the insets */
        if (canvas_new(&big, cv.w, cv.h + inset_h, C_PANEL) != 0) {
            canvas_free(&cv);
            oom(err, dir, stem);
            return -1;
        }
        canvas_free(&cv);
        cv = big;
    }
    for (r = 0; r < f->rows; r++)
        for (c = 0; c < f->cols; c++) {
            rgb_t g;
            g.r = g.g = g.b = (uint8_t)(f->filtered[(size_t)r * (size_t)f->cols + (size_t)c] / 2);
            canvas_put(&cv, c, r, g, 1.0f);
        }
    vw = polar_view(f, 0, 0);
    for (i = 0; i < f->ndet; i++)
        draw_grid(&cv, &vw, &f->det[i], skip);
    for (i = 0; i < ninset; i++) {
        int u, v, z = box[i][4];
        int x = (f->cols - box[i][2] * z) / 2;
        view zv = polar_view(f, x, y_inset);
        char buf[48];
        zv.ox = (float)box[i][0] - 0.5f + 0.5f / (float)z;
        zv.oy = (float)box[i][1] - 0.5f + 0.5f / (float)z;
        zv.zoom = (float)z;
        for (v = 0; v < box[i][3] * z; v++)
            for (u = 0; u < box[i][2] * z; u++) {
                int ix = box[i][0] + u / z, iy = box[i][1] + v / z;
                rgb_t g = C_BG;
                if (ix >= 0 && iy >= 0 && ix < f->cols && iy < f->rows)
                    g.r = g.g = g.b =
                        (uint8_t)(f->filtered[(size_t)iy * (size_t)f->cols + (size_t)ix] * 3 / 4);
                canvas_put(&cv, x + u, y_inset + v, g, 1.0f);
            }
        draw_grid(&cv, &zv, &f->det[i], skip);
        snprintf(buf, sizeof buf, "#%d ID %d (X%d)", i + 1, f->det[i].id, z);
        canvas_label(&cv, x + 4, y_inset + 4, 2, buf, C_LABEL);
        y_inset += box[i][3] * z + 8;
    }
    return finish_stage(&cv, f, it, n, dir, stem, 6, err);
}

int pic_stages(const char *dir, const char *stem, const pic_frame *f, char *err)
{
    if (write_grey(dir, stem, 0, f->input8, f->rows, f->cols, 0, err) != 0 ||
        write_grey(dir, stem, 1, f->filtered, f->rows, f->cols, 0, err) != 0 ||
        stage_search(dir, stem, f, err) != 0 ||
        write_grey(dir, stem, 3, f->binary, f->rows, f->cols, 1, err) != 0 ||
        stage_contours(dir, stem, f, err) != 0 || stage_quads(dir, stem, f, err) != 0 ||
        stage_decoded(dir, stem, f, err) != 0)
        return -1;
    return 0;
}
