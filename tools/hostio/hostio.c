/* The host tools' shared I/O (see hostio.h). */
#define _POSIX_C_SOURCE 200809L
#include "hostio.h"

#include "actag/actag.h"

#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

static int fail(char *err, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err, HOSTIO_ERRLEN, fmt, ap);
        va_end(ap);
    }
    return -1;
}

const char *hostio_frame_name(const char *path)
{
    return (path && strcmp(path, "-") == 0) ? "stdin" : path;
}

uint8_t *hostio_slurp(const char *path, size_t *len, char *err)
{
    int is_stdin = strcmp(path, "-") == 0;
    FILE *f = is_stdin ? stdin : fopen(path, "rb");
    uint8_t *buf = NULL;
    size_t cap = 0, n = 0;
    const char *why = NULL; /* set when the file is not read whole */
    int read_errno = 0;     /* fread's reason ("Is a directory"), kept for the message */
    path = hostio_frame_name(path);
    if (!f) {
        fail(err, "%s: %s", path, strerror(errno));
        return NULL;
    }
    for (;;) { /* read in chunks: works for pipes and /dev/stdin too */
        size_t got;
        if (n + 65536 + 1 > cap) {
            size_t ncap = cap ? cap * 2 : 65536 * 2;
            uint8_t *nb;
            if (ncap > (size_t)HOSTIO_MAX_FILE + 65536 + 1) { /* /dev/zero, a stray pipe */
                why = "too large";
                break;
            }
            nb = (uint8_t *)realloc(buf, ncap);
            if (!nb) {
                why = "out of memory";
                break;
            }
            buf = nb;
            cap = ncap;
        }
        errno = 0;
        got = fread(buf + n, 1, cap - n - 1, f);
        n += got;
        if (got == 0) {
            read_errno = errno;
            break;
        }
        if (n > (size_t)HOSTIO_MAX_FILE) {
            why = "too large";
            break;
        }
    }
    if (!why && ferror(f))
        why = read_errno ? strerror(read_errno) : "read error";
    if (!is_stdin)
        fclose(f);
    if (why) { /* one clean-up for every way the file is not read whole */
        free(buf);
        if (strcmp(why, "too large") == 0)
            fail(err, "%s: larger than %lu bytes: not a file the tools read", path,
                 (unsigned long)HOSTIO_MAX_FILE);
        else
            fail(err, "%s: %s", path, why);
        return NULL;
    }
    buf[n] = 0;
    if (len)
        *len = n;
    return buf;
}

/* The writers go through hostio_out (hostio_out.c): a file whose writing
 * fails is removed again, never a link or a device. */
int hostio_write_file(const char *path, const void *data, size_t n, char *err)
{
    hostio_out o;
    if (hostio_out_open(&o, path, "wb", err) != HOSTIO_OK)
        return -1;
    fwrite(data, 1, n, o.f); /* a short write sets the error flag: close fails */
    return hostio_out_close(&o, err);
}

int hostio_mkdirs(const char *path, char *err)
{
    char buf[4096];
    size_t n = strlen(path), i;
    struct stat sb;
    if (n == 0)
        return fail(err, "cannot create a folder with an empty name");
    if (n >= sizeof buf)
        return fail(err, "%.64s...: folder name too long", path);
    memcpy(buf, path, n + 1);
    for (i = 1; i <= n; i++) {
        if (buf[i] != '/' && buf[i] != '\0')
            continue;
        if (buf[i - 1] == '/')
            continue; /* "a//b" */
        buf[i] = '\0';
        if (mkdir(buf, 0777) != 0 && errno != EEXIST)
            return fail(err, "%s: cannot create folder: %s", buf, strerror(errno));
        buf[i] = i < n ? '/' : '\0';
    }
    if (stat(path, &sb) != 0 || !S_ISDIR(sb.st_mode))
        return fail(err, "%s: exists and is not a folder", path);
    return HOSTIO_OK;
}

const char *hostio_json_num(char *buf, const char *fmt, double v, int have)
{
    if (!have)
        return "null";
    snprintf(buf, HOSTIO_JNUM_LEN, fmt, v);
    return buf;
}

char *hostio_slurp_text(const char *path, size_t *len, char *err)
{
    size_t n = 0;
    uint8_t *buf = hostio_slurp(path, &n, err);
    const uint8_t *nul;
    if (buf == NULL)
        return NULL;
    nul = (const uint8_t *)memchr(buf, 0, n);
    if (nul != NULL) {
        if (err)
            snprintf(err, HOSTIO_ERRLEN, "%.180s: byte %lu is a NUL byte: not a text file",
                     hostio_frame_name(path), (unsigned long)(nul - buf));
        free(buf);
        return NULL;
    }
    if (len)
        *len = n;
    return (char *)buf;
}

/* path's folder into dir (cap bytes; "." when it names none) and its last
 * name returned; NULL when it ends in '/' or the folder does not fit. */
static const char *split_path(const char *path, char *dir, size_t cap)
{
    const char *slash = strrchr(path, '/');
    size_t n;
    if (!slash) {
        snprintf(dir, cap, ".");
        return path;
    }
    if (slash[1] == '\0')
        return NULL;
    n = slash == path ? 1 : (size_t)(slash - path); /* "/x": the root */
    if (n >= cap)
        return NULL;
    memcpy(dir, path, n);
    dir[n] = '\0';
    return slash + 1;
}

static int same_inode(const struct stat *sa, const struct stat *sb)
{
    return sa->st_dev == sb->st_dev && sa->st_ino == sb->st_ino && sa->st_ino != 0;
}

int hostio_parse_bearings(const char *name, const char *text, int cols, const char *cols_opt,
                          float *out, char *err)
{
    double *v;
    int n = 0, i, rc = -1;
    if (cols < 1)
        return fail(err, "%.200s: bearing table for %d columns", name, cols);
    v = (double *)malloc(((size_t)cols + 1) * sizeof *v);
    if (!v)
        return fail(err, "%.200s: out of memory", name);
    if (hostio_parse_list(name, text, v, cols, &n, err) == HOSTIO_OK) {
        if (n != cols) {
            if (cols_opt)
                fail(err, "%.200s: bearing table has %s%d values, %.20s is %d", name,
                     n > cols ? "more than " : "", n > cols ? cols : n, cols_opt, cols);
            else
                fail(err, "%.200s: bearing table has %s%d values, the frame has %d columns",
                     name, n > cols ? "more than " : "", n > cols ? cols : n, cols);
        } else {
            for (i = 0; i < cols; i++)
                out[i] = (float)v[i];
            rc = HOSTIO_OK;
        }
    }
    free(v);
    return rc;
}

int hostio_read_bearings(const char *path, int cols, const char *cols_opt, float *out,
                         char *err)
{
    size_t len;
    char *text = hostio_slurp_text(path, &len, err);
    int rc;
    if (!text)
        return -1;
    rc = hostio_parse_bearings(hostio_frame_name(path), text, cols, cols_opt, out, err);
    free(text);
    return rc;
}

int hostio_same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    int ha, hb;
    char da[4096], db[4096];
    const char *na, *nb;
    if (strcmp(a, b) == 0)
        return 1;
    ha = stat(a, &sa) == 0;
    hb = stat(b, &sb) == 0;
    if (ha && hb)
        return same_inode(&sa, &sb);
    if (ha || hb)
        return 0;
    /* Neither exists yet (two outputs about to be created): the same name
     * in the same folder ("out.txt" and "./out.txt") is one file. */
    na = split_path(a, da, sizeof da);
    nb = split_path(b, db, sizeof db);
    return na && nb && strcmp(na, nb) == 0 && stat(da, &sa) == 0 && stat(db, &sb) == 0 &&
           same_inode(&sa, &sb);
}

/* Length of the well-formed UTF-8 sequence at s (RFC 3629: no overlong
 * forms, no surrogates, at most U+10FFFF), or 0 when it is not one. */
static int utf8_len(const unsigned char *s)
{
    unsigned char c = s[0];
    int n, i;
    if (c < 0x80)
        return 1;
    if (c >= 0xC2 && c <= 0xDF)
        n = 2;
    else if (c >= 0xE0 && c <= 0xEF)
        n = 3;
    else if (c >= 0xF0 && c <= 0xF4)
        n = 4;
    else
        return 0;
    for (i = 1; i < n; i++)
        if ((s[i] & 0xC0) != 0x80) /* the terminating NUL fails here too */
            return 0;
    if ((c == 0xE0 && s[1] < 0xA0) || (c == 0xED && s[1] > 0x9F) || (c == 0xF0 && s[1] < 0x90) ||
        (c == 0xF4 && s[1] > 0x8F))
        return 0;
    return n;
}

void hostio_json_string(FILE *stream, const char *s)
{
    const unsigned char *p = (const unsigned char *)s;
    fputc('"', stream);
    while (*p) {
        int n = utf8_len(p);
        if (n == 0) { /* not UTF-8 (a file name's bytes): JSON holds Unicode only */
            fputs("\\ufffd", stream);
            p++;
        } else if (*p == '"' || *p == '\\') {
            fprintf(stream, "\\%c", *p++);
        } else if (*p < 0x20) {
            fprintf(stream, "\\u%04x", *p++);
        } else {
            fwrite(p, 1, (size_t)n, stream);
            p += n;
        }
    }
    fputc('"', stream);
}

/* Next header field (after whitespace and comments) as an integer in
 * lo..hi; else fails with a message quoting the text found there (at most
 * 20 characters, unprintable bytes as '?') or saying it is missing. */
static int pgm_field(const uint8_t *b, size_t len, size_t *pos, const char *nm,
                     const char *what, long lo, long hi, long *v, char *err)
{
    size_t start, i;
    char tok[24];
    int bad = 0;
    long val = 0;
    while (*pos < len) {
        if (b[*pos] == '#') {
            while (*pos < len && b[*pos] != '\n')
                (*pos)++;
        } else if (b[*pos] == ' ' || b[*pos] == '\t' || b[*pos] == '\n' || b[*pos] == '\r') {
            (*pos)++;
        } else {
            break;
        }
    }
    start = *pos;
    while (*pos < len && !(b[*pos] == ' ' || b[*pos] == '\t' || b[*pos] == '\n' ||
                           b[*pos] == '\r' || b[*pos] == '#')) {
        if (b[*pos] < '0' || b[*pos] > '9')
            bad = 1;
        else if (val <= hi) /* stops growing once above hi: no overflow */
            val = val * 10 + (b[*pos] - '0');
        (*pos)++;
    }
    if (*pos == start)
        return fail(err, "%s: PGM %s missing (the header ends)", nm, what);
    for (i = 0; i < 20 && start + i < *pos; i++)
        tok[i] = b[start + i] >= 0x20 && b[start + i] < 0x7f ? (char)b[start + i] : '?';
    if (start + i < *pos)
        tok[i++] = '.', tok[i++] = '.', tok[i++] = '.';
    tok[i] = '\0';
    if (bad || val < lo || val > hi)
        return fail(err, "%s: PGM %s '%s' is not a whole number in %ld..%ld", nm, what, tok, lo,
                    hi);
    *v = val;
    return HOSTIO_OK;
}

/* The first bytes of b (at most 8) as quotable text: printable ASCII as it
 * is, '\\' and '\'' escaped, \n \r \t, other bytes as \xHH; "..." when
 * there are more. q holds at least 8 * 4 + 4 characters. */
static void quote_start(const uint8_t *b, size_t len, char *q)
{
    size_t i, o = 0;
    for (i = 0; i < len && i < 8; i++) {
        uint8_t c = b[i];
        if (c == '\\' || c == '\'') {
            q[o++] = '\\';
            q[o++] = (char)c;
        } else if (c == '\n' || c == '\r' || c == '\t') {
            q[o++] = '\\';
            q[o++] = c == '\n' ? 'n' : c == '\r' ? 'r' : 't';
        } else if (c >= 0x20 && c < 0x7f) {
            q[o++] = (char)c;
        } else {
            q[o++] = '\\';
            q[o++] = 'x';
            q[o++] = "0123456789abcdef"[c >> 4];
            q[o++] = "0123456789abcdef"[c & 15];
        }
    }
    if (i < len)
        q[o++] = '.', q[o++] = '.', q[o++] = '.';
    q[o] = '\0';
}

int hostio_pgm_parse(const uint8_t *buf, size_t len, const char *name, hostio_pgm_view *out,
                     char *err)
{
    size_t pos = 2, need;
    long w, h, maxv;
    const char *nm = name ? name : "PGM";
    if (!buf || !out)
        return fail(err, "%s: no buffer", nm);
    if (len < 3 || buf[0] != 'P' || buf[1] != '5' ||
        !(buf[2] == ' ' || buf[2] == '\t' || buf[2] == '\n' || buf[2] == '\r' || buf[2] == '#')) {
        char q[8 * 4 + 4];
        if (len == 0)
            return fail(err, "%s: not a binary PGM (no P5 magic; it is empty)", nm);
        if (len == 2 && buf[0] == 'P' && buf[1] == '5')
            return fail(err, "%s: PGM header truncated after its P5 magic (no width)", nm);
        quote_start(buf, len, q);
        return fail(err, "%s: not a binary PGM (no P5 magic; it starts '%s')", nm, q);
    }
    if (pgm_field(buf, len, &pos, nm, "width", 1, 32767, &w, err) != HOSTIO_OK ||
        pgm_field(buf, len, &pos, nm, "height", 1, 32767, &h, err) != HOSTIO_OK ||
        pgm_field(buf, len, &pos, nm, "maxval", 1, 65535, &maxv, err) != HOSTIO_OK)
        return -1;
    /* A comment right after maxval (Netpbm reads one there): its end of line
     * is then the single whitespace before the pixels. */
    if (pos < len && buf[pos] == '#')
        while (pos < len && buf[pos] != '\n')
            pos++;
    if (pos >= len)
        return fail(err, "%s: PGM header ends without pixel data", nm);
    if (!(buf[pos] == ' ' || buf[pos] == '\t' || buf[pos] == '\n' || buf[pos] == '\r'))
        return fail(err, "%s: PGM maxval is not followed by whitespace", nm);
    pos++; /* the single whitespace after maxval */
    out->bytes_per_sample = maxv > 255 ? 2 : 1;
    need = (size_t)w * (size_t)h * (size_t)out->bytes_per_sample;
    if (len - pos < need)
        return fail(err, "%s: PGM has %lu pixel bytes, its header needs %lu", nm,
                    (unsigned long)(len - pos), (unsigned long)need);
    if (len - pos > need) /* more frames, or junk: nothing is dropped silently */
        return fail(err, "%s: %lu bytes after the PGM's %lu pixel bytes (one frame per file)",
                    nm, (unsigned long)(len - pos - need), (unsigned long)need);
    out->pixels = buf + pos;
    out->rows = (int)h;
    out->cols = (int)w;
    out->maxval = (int)maxv;
    return HOSTIO_OK;
}

int hostio_pgm_fwrite(FILE *f, const char *name, const hostio_image *img, char *err)
{
    int r, c, maxv;
    const char *nm = name ? name : "PGM";
    if (!img || !img->data || img->rows < 1 || img->cols < 1 || img->stride < img->cols ||
        (img->depth != 8 && img->depth != 16))
        return fail(err, "%s: bad image to write", nm);
    maxv = img->maxval > 0 ? img->maxval : (img->depth == 8 ? 255 : 65535);
    if (fprintf(f, "P5\n%d %d\n%d\n", img->cols, img->rows, maxv) < 0)
        return fail(err, "%s: write error", nm);
    for (r = 0; r < img->rows; r++) {
        if (img->depth == 8) {
            const uint8_t *row = (const uint8_t *)img->data + (size_t)r * (size_t)img->stride;
            if (fwrite(row, 1, (size_t)img->cols, f) != (size_t)img->cols)
                break;
        } else {
            const uint16_t *row = (const uint16_t *)img->data + (size_t)r * (size_t)img->stride;
            for (c = 0; c < img->cols; c++) {
                fputc(row[c] >> 8, f);
                fputc(row[c] & 0xff, f);
            }
        }
    }
    if (ferror(f))
        return fail(err, "%s: write error", nm);
    return HOSTIO_OK;
}

int hostio_pgm_write(const char *path, const hostio_image *img, char *err)
{
    hostio_out o;
    if (!img || !img->data || img->rows < 1 || img->cols < 1 || img->stride < img->cols ||
        (img->depth != 8 && img->depth != 16))
        return fail(err, "%s: bad image to write", path);
    if (hostio_out_open(&o, path, "wb", err) != HOSTIO_OK)
        return -1;
    if (hostio_pgm_fwrite(o.f, path, img, err) != HOSTIO_OK) {
        hostio_out_abandon(&o); /* the message is hostio_pgm_fwrite's */
        return -1;
    }
    return hostio_out_close(&o, err);
}

int hostio_ppm_write(const char *path, const uint8_t *rgb, int rows, int cols, char *err)
{
    hostio_out o;
    size_t n = (size_t)rows * (size_t)cols;
    if (!rgb || rows < 1 || cols < 1)
        return fail(err, "%s: bad picture to write", path);
    if (hostio_out_open(&o, path, "wb", err) != HOSTIO_OK)
        return -1;
    fprintf(o.f, "P6\n%d %d\n255\n", cols, rows);
    fwrite(rgb, 3, n, o.f); /* a failed write sets the error flag: close fails */
    return hostio_out_close(&o, err);
}

void hostio_image_free(hostio_image *img)
{
    if (img) {
        free(img->data);
        img->data = NULL;
    }
}

void hostio_image_frame(const hostio_image *img, actag_frame *frame)
{
    frame->data = img->data;
    frame->rows = img->rows;
    frame->cols = img->cols;
    frame->stride = img->stride;
    frame->depth = img->depth;
}

/* Bytes of a raw frame of spec's layout: the whole frame (*full) and the
 * least a file may hold (*minimum: the last row's padding may be absent).
 * Computed in 64 bits and checked against SIZE_MAX, so that no product
 * overflows (rows 32767 x stride 2^20 x 2 bytes is 2^36, beyond a 32-bit
 * size_t or long). Returns 0 when the frame cannot be addressed. */
static int raw_sizes(const hostio_raw_spec *raw, int stride, size_t *minimum, size_t *full)
{
    uint64_t bytes = (uint64_t)(raw->depth / 8);
    uint64_t mn = ((uint64_t)(raw->rows - 1) * (uint64_t)stride + (uint64_t)raw->cols) * bytes;
    uint64_t fl = (uint64_t)raw->rows * (uint64_t)stride * bytes;
    if (fl > (uint64_t)SIZE_MAX)
        return 0;
    *minimum = (size_t)mn;
    *full = (size_t)fl;
    return 1;
}

/* Checks raw's layout; 0 with a message in err when it is unusable. */
static int raw_check(const char *name, const hostio_raw_spec *raw, int stride, char *err)
{
    if (raw->depth != 8 && raw->depth != 16)
        return fail(err, "%s: raw depth %d is not 8 or 16", name, raw->depth);
    if (raw->rows < 1 || raw->cols < 1 || raw->rows > 32767 || raw->cols > 32767)
        return fail(err, "%s: raw frame size %d x %d outside 1..32767", name, raw->rows,
                    raw->cols);
    if (stride < raw->cols)
        return fail(err, "%s: raw stride %d is smaller than the %d columns", name, stride,
                    raw->cols);
    return HOSTIO_OK;
}

/* A raw frame of spec's layout from a buffer (whole file). */
static int raw_frame(const uint8_t *b, size_t len, const char *name, const hostio_raw_spec *raw,
                     hostio_image *out, char *err)
{
    int bytes = raw->depth / 8, stride = raw->stride ? raw->stride : raw->cols;
    size_t minimum, full, i;
    if (raw_check(name, raw, stride, err) != HOSTIO_OK)
        return -1;
    if (!raw_sizes(raw, stride, &minimum, &full))
        return fail(err, "%s: raw frame of %d rows x stride %d x %d bytes is too large to address",
                    name, raw->rows, stride, bytes);
    if (len < minimum || len > full)
        return fail(err,
                    "%s: raw frame is %llu bytes, expected %llu (%d rows x stride %d x %d byte%s)",
                    name, (unsigned long long)len, (unsigned long long)full, raw->rows, stride, bytes,
                    bytes > 1 ? "s" : "");
    /* only the bytes the frame addresses (the last row's padding is not
     * kept): a one-row frame with a huge stride in a small file must not
     * allocate the stride (found by fuzz_hostio: 25 bytes, 2 GB) */
    out->data = malloc(minimum);
    if (!out->data)
        return fail(err, "%s: out of memory", name);
    if (bytes == 1) {
        memcpy(out->data, b, minimum);
    } else {
        uint16_t *d = (uint16_t *)out->data;
        for (i = 0; i + 1 < minimum; i += 2) /* little-endian samples */
            d[i / 2] = (uint16_t)(b[i] | (b[i + 1] << 8));
    }
    out->rows = raw->rows;
    out->cols = raw->cols;
    out->stride = stride;
    out->depth = raw->depth;
    out->maxval = raw->depth == 8 ? 255 : 65535;
    return HOSTIO_OK;
}

/* Does a buffer of len bytes fit raw's layout (a usable raw spec given)? */
static int raw_fits(const hostio_raw_spec *raw, size_t len)
{
    int stride;
    size_t minimum, full;
    if (!raw || raw->rows <= 0 || raw->cols <= 0)
        return 0;
    stride = raw->stride ? raw->stride : raw->cols;
    if (raw_check("", raw, stride, NULL) != HOSTIO_OK || !raw_sizes(raw, stride, &minimum, &full))
        return 0;
    return len >= minimum && len <= full;
}

/* A PGM view into a malloc'd image: 16-bit samples to host order, every
 * sample checked against maxval, and 8-bit samples of a maxval below 255
 * scaled to 0..255 (v * 255 / maxval, rounded), so that 8-bit frames are
 * full scale like 16-bit ones, which actag_detect scales by their maximum. */
static int pgm_image(const hostio_pgm_view *v, const char *name, hostio_image *out, char *err)
{
    size_t n = (size_t)v->rows * (size_t)v->cols, i;
    uint32_t mx = (uint32_t)v->maxval;
    out->data = malloc(n * (size_t)v->bytes_per_sample);
    if (!out->data)
        return fail(err, "%s: out of memory", name);
    for (i = 0; i < n; i++) {
        uint32_t s = v->bytes_per_sample == 1
                         ? v->pixels[i]
                         : (uint32_t)((v->pixels[2 * i] << 8) | v->pixels[2 * i + 1]);
        if (s > mx) {
            free(out->data);
            out->data = NULL;
            return fail(err, "%s: PGM sample %lu at row %lu, column %lu is above maxval %lu", name,
                        (unsigned long)s, (unsigned long)(i / (size_t)v->cols),
                        (unsigned long)(i % (size_t)v->cols), (unsigned long)mx);
        }
        if (v->bytes_per_sample == 1)
            ((uint8_t *)out->data)[i] = (uint8_t)(mx == 255u ? s : (s * 255u + mx / 2u) / mx);
        else
            ((uint16_t *)out->data)[i] = (uint16_t)s;
    }
    out->rows = v->rows;
    out->cols = v->cols;
    out->stride = v->cols;
    out->depth = 8 * v->bytes_per_sample;
    out->maxval = v->bytes_per_sample == 1 ? 255 : v->maxval;
    return HOSTIO_OK;
}

int hostio_frame_parse(const uint8_t *b, size_t len, const char *name, const hostio_raw_spec *raw,
                       hostio_image *out, char *err)
{
    hostio_pgm_view v;
    const char *nm = name ? name : "frame";
    if (!out)
        return fail(err, "%s: no image to fill", nm);
    memset(out, 0, sizeof *out);
    if (!b)
        return fail(err, "%s: no buffer", nm);
    /* With a raw layout given, a buffer of that layout's size is a raw frame,
     * whatever its first bytes (a raw frame may start with "P5"). */
    if (raw_fits(raw, len))
        return raw_frame(b, len, nm, raw, out, err);
    if (len >= 2 && b[0] == 'P' && b[1] >= '1' && b[1] <= '7' && b[1] != '5')
        return fail(err, "%s: a P%c image: only binary PGM (P5) is supported", nm, (char)b[1]);
    if (len >= 2 && b[0] == 'P' && b[1] == '5') {
        if (hostio_pgm_parse(b, len, nm, &v, err) != HOSTIO_OK)
            return -1;
        return pgm_image(&v, nm, out, err);
    }
    if (!raw)
        return fail(err, "%s: not a PGM file (no P5 magic)", nm);
    if (raw->rows <= 0 || raw->cols <= 0)
        return fail(err, "%s: not a PGM file (no P5 magic); raw frames need --rows and --cols",
                    nm);
    return raw_frame(b, len, nm, raw, out, err);
}

int hostio_frame_read(const char *path, const hostio_raw_spec *raw, hostio_image *out,
                      char *err)
{
    size_t len;
    uint8_t *b;
    int rc;
    memset(out, 0, sizeof *out);
    b = hostio_slurp(path, &len, err);
    if (!b)
        return -1;
    rc = hostio_frame_parse(b, len, hostio_frame_name(path), raw, out, err);
    free(b);
    return rc;
}

/* Through pgm_image, as hostio_frame_read: it copied the samples as stored,
 * so samples above maxval passed (actag_detect refuses them) and a maxval
 * below 255 gave other pixels than actag_detect sees. */
int hostio_pgm_read(const char *path, hostio_image *out, char *err)
{
    size_t len;
    hostio_pgm_view v;
    uint8_t *b;
    int rc = -1;
    const char *nm = hostio_frame_name(path);
    memset(out, 0, sizeof *out);
    b = hostio_slurp(path, &len, err);
    if (!b)
        return -1;
    if (hostio_pgm_parse(b, len, nm, &v, err) == HOSTIO_OK)
        rc = pgm_image(&v, nm, out, err);
    free(b);
    return rc;
}

/* Whether p starts as a hexadecimal number ("0x10", "-0X1p-3"), which
 * strtod reads. */
static int hex_number(const char *p)
{
    if (*p == '-' || *p == '+')
        p++;
    return p[0] == '0' && (p[1] == 'x' || p[1] == 'X');
}

/* Why s does not start as a number written in decimal, or NULL: strtod and
 * strtol skip leading whitespace and take a '+' sign, and strtod reads
 * hexadecimal ("0x10", "0x1p-3"), none of which the tools' numbers are
 * ("the whole string must be the number"). A '-' sign is taken here: the
 * range decides. Other non-numbers ("inf", "nan", "abc") are left to the
 * caller's strtod/strtol and its own message. */
static const char *not_decimal(const char *s)
{
    if (isspace((unsigned char)*s))
        return "without leading whitespace";
    if (*s == '+')
        return "without a '+' sign";
    if (hex_number(s))
        return "in decimal, not hexadecimal";
    return NULL;
}

int hostio_parse_double(const char *name, const char *s, double lo, double hi, double *v,
                        char *err)
{
    char *end;
    double x;
    const char *why;
    if (!s)
        return fail(err, "%s: missing value", name);
    if ((why = not_decimal(s)) != NULL)
        return fail(err, "%s: must be a number %s (got '%s')", name, why, s);
    errno = 0;
    x = strtod(s, &end);
    if (end == s || *end != '\0' || !isfinite(x))
        return fail(err, "%s: must be a finite number (got '%s')", name, s);
    if (errno == ERANGE || (x != 0.0 && fabs(x) < DBL_MIN)) {
        /* below the smallest normal double: 0 or a denormal, with ERANGE
         * ("1e-400" was "not a finite number"); an overflow is infinite above */
        int neg = *s == '-';
        if (neg ? (lo >= 0.0 || hi < 0.0) : (lo > 0.0 || hi <= 0.0))
            return fail(err, "%s: must be from %g to %g (got %s)", name, lo, hi, s);
        return fail(err, "%s: must be 0 or at least %g in magnitude (got %s: too small for "
                    "a double)", name, DBL_MIN, s);
    }
    if (x < lo || x > hi)
        return fail(err, "%s: must be from %g to %g (got %s)", name, lo, hi, s);
    *v = x;
    return HOSTIO_OK;
}

int hostio_parse_long(const char *name, const char *s, long lo, long hi, long *v, char *err)
{
    char *end;
    long x;
    const char *why;
    if (!s)
        return fail(err, "%s: missing value", name);
    if ((why = not_decimal(s)) != NULL)
        return fail(err, "%s: must be an integer %s (got '%s')", name, why, s);
    errno = 0;
    x = strtol(s, &end, 10);
    if (end == s || *end != '\0')
        return fail(err, "%s: must be an integer (got '%s')", name, s);
    if (errno == ERANGE || x < lo || x > hi) /* ERANGE: beyond long, so beyond lo..hi */
        return fail(err, "%s: must be an integer from %ld to %ld (got %s)", name, lo, hi, s);
    *v = x;
    return HOSTIO_OK;
}

int hostio_parse_u32(const char *name, const char *s, uint32_t lo, uint32_t hi, uint32_t *v,
                     char *err)
{
    char *end;
    unsigned long long x;
    const char *why;
    if (!s)
        return fail(err, "%s: missing value", name);
    /* strtoull would skip whitespace and take a '+' sign: the same words as
     * hostio_parse_long ("+5" was "a whole number from 0 to ..., got +5") */
    if ((why = not_decimal(s)) != NULL)
        return fail(err, "%s: must be an integer %s (got '%s')", name, why, s);
    if (*s == '-') /* strtoull would wrap a minus sign */
        return fail(err, "%s: must be a whole number from %lu to %lu (got %s)", name,
                    (unsigned long)lo, (unsigned long)hi, s);
    errno = 0;
    x = strtoull(s, &end, 10);
    if (end == s || *end != '\0')
        return fail(err, "%s: must be an integer (got '%s')", name, s);
    if (errno == ERANGE || x < lo || x > hi) /* ERANGE: beyond 64 bits, so beyond hi */
        return fail(err, "%s: must be a whole number from %lu to %lu (got %s)", name,
                    (unsigned long)lo, (unsigned long)hi, s);
    *v = (uint32_t)x;
    return HOSTIO_OK;
}

int hostio_parse_choice(const char *name, const char *s, const char *const *choices, int n,
                        int *index, char *err)
{
    char words[HOSTIO_ERRLEN / 2];
    size_t used = 0;
    int i;
    if (!s)
        return fail(err, "%s: missing value", name);
    for (i = 0; i < n; i++)
        if (strcmp(s, choices[i]) == 0) {
            *index = i;
            return HOSTIO_OK;
        }
    words[0] = '\0';
    for (i = 0; i < n && used < sizeof words; i++) {
        int w = snprintf(words + used, sizeof words - used, "%s%s",
                         i == 0 ? "" : (i == n - 1 ? " or " : ", "), choices[i]);
        if (w < 0)
            break;
        used += (size_t)w;
    }
    return fail(err, "%s: must be %s (got '%.40s')", name, words, s);
}

int hostio_parse_doubles(const char *name, const char *s, char sep, double *out, int n,
                         char *err)
{
    int i;
    const char *p = s;
    if (!s)
        return fail(err, "%s: missing value", name);
    for (i = 0; i < n; i++) {
        char *end;
        double x;
        errno = 0;
        x = strtod(p, &end);
        if (not_decimal(p) || end == p || errno == ERANGE || !isfinite(x))
            return fail(err, "%s: expected %d numbers separated by '%c' (got '%s')", name, n,
                        sep, s);
        out[i] = x;
        p = end;
        if (i < n - 1) {
            if (*p != sep)
                return fail(err, "%s: expected %d numbers separated by '%c' (got '%s')", name,
                            n, sep, s);
            p++;
        }
    }
    if (*p != '\0')
        return fail(err, "%s: expected exactly %d numbers (got '%s')", name, n, s);
    return HOSTIO_OK;
}

int hostio_parse_list(const char *name, const char *s, double *out, int cap, int *n,
                      char *err)
{
    const char *p = s;
    int count = 0;
    if (!s)
        return fail(err, "%s: missing value", name);
    for (;;) {
        char *end;
        double x;
        while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r' || *p == ',')
            p++;
        if (*p == '\0')
            break;
        errno = 0;
        x = strtod(p, &end);
        if (end == p || errno == ERANGE || !isfinite(x) || hex_number(p) ||
            !(*end == '\0' || *end == ' ' || *end == '\t' || *end == '\n' || *end == '\r' ||
              *end == ',')) {
            /* the token as text: a binary file's bytes are shown as '?', not
             * written to the terminal */
            char tok[41];
            size_t tl = strcspn(p, " \t\r\n,"), i;
            for (i = 0; i < tl && i < 40; i++)
                tok[i] = p[i] >= 0x20 && p[i] < 0x7f ? p[i] : '?';
            tok[i] = '\0';
            return fail(err, "%s: value %d is not a finite number (got '%s')", name, count + 1,
                        tok);
        }
        if (count < cap)
            out[count] = x;
        count++;
        if (count > cap)
            break;
        p = end;
    }
    *n = count;
    return HOSTIO_OK;
}

int hostio_read_codes(const char *path, uint32_t *codes, size_t cap, size_t *n, char *err)
{
    size_t len, pos = 0, count = 0;
    long line = 0;
    uint8_t *b = hostio_slurp(path, &len, err);
    *n = 0;
    if (!b)
        return -1;
    while (pos < len) {
        size_t end = pos, s, e, s0;
        uint64_t v = 0;
        int digits = 0;
        while (end < len && b[end] != '\n')
            end++;
        line++;
        s = pos;
        e = end;
        pos = end + 1;
        while (s < e && (b[s] == ' ' || b[s] == '\t'))
            s++;
        while (e > s && (b[e - 1] == ' ' || b[e - 1] == '\t' || b[e - 1] == '\r'))
            e--;
        if (s == e || b[s] == '#')
            continue;
        s0 = s;
        if (e - s > 2 && b[s] == '0' && (b[s + 1] == 'x' || b[s + 1] == 'X')) {
            for (s += 2; s < e && isxdigit(b[s]); s++, digits++)
                v = v * 16u + (uint64_t)(isdigit(b[s]) ? b[s] - '0' : (b[s] | 0x20) - 'a' + 10);
        }
        if (s != e || digits == 0 || digits > 8) {
            int shown = e - s0 > 40 ? 40 : (int)(e - s0);
            fail(err, "%s:%ld: '%.*s' is not a 0x-prefixed hexadecimal code of at most 32 bits",
                 path, line, shown, (const char *)b + s0);
            free(b);
            return -1;
        }
        if (count == cap) {
            free(b);
            return fail(err, "%s:%ld: more than %lu codes", path, line, (unsigned long)cap);
        }
        codes[count++] = (uint32_t)v;
    }
    free(b);
    *n = count;
    return HOSTIO_OK;
}

int hostio_run(const char *cmd, char *err)
{
    int st;
    fflush(NULL); /* our buffered output before the child's */
    st = system(cmd);
    if (st == -1)
        return fail(err, "cannot run '%s': %s", cmd, strerror(errno));
    if (!WIFEXITED(st))
        return fail(err, "'%s' was ended by signal %d", cmd, WIFSIGNALED(st) ? WTERMSIG(st) : 0);
    return WEXITSTATUS(st);
}

void hostio_die(const char *prog, const char *msg)
{
    fprintf(stderr, "%s: %s\n", prog, msg);
    exit(2);
}

void hostio_stdout_check(const char *prog)
{
    if (fflush(stdout) != 0 || ferror(stdout))
        hostio_die(prog, "standard output: write error");
}

double hostio_opt_double(const char *prog, const char *name, const char *s, double lo,
                         double hi)
{
    char err[HOSTIO_ERRLEN];
    double v = 0.0;
    if (hostio_parse_double(name, s, lo, hi, &v, err) != HOSTIO_OK)
        hostio_die(prog, err);
    return v;
}

long hostio_opt_long(const char *prog, const char *name, const char *s, long lo, long hi)
{
    char err[HOSTIO_ERRLEN];
    long v = 0;
    if (hostio_parse_long(name, s, lo, hi, &v, err) != HOSTIO_OK)
        hostio_die(prog, err);
    return v;
}

uint32_t hostio_opt_u32(const char *prog, const char *name, const char *s, uint32_t lo,
                        uint32_t hi)
{
    char err[HOSTIO_ERRLEN];
    uint32_t v = 0;
    if (hostio_parse_u32(name, s, lo, hi, &v, err) != HOSTIO_OK)
        hostio_die(prog, err);
    return v;
}

int hostio_opt_choice(const char *prog, const char *name, const char *s,
                      const char *const *choices, int n)
{
    char err[HOSTIO_ERRLEN];
    int i = 0;
    if (hostio_parse_choice(name, s, choices, n, &i, err) != HOSTIO_OK)
        hostio_die(prog, err);
    return i;
}

void hostio_opt_mkdirs(const char *prog, const char *name, const char *path)
{
    char err[HOSTIO_ERRLEN], m[HOSTIO_ERRLEN + 16];
    if (hostio_mkdirs(path, err) != HOSTIO_OK) {
        snprintf(m, sizeof m, "%s: %s", name, err);
        hostio_die(prog, m);
    }
}

const char *hostio_opt_value(const char *prog, int argc, char **argv, int *i)
{
    char m[HOSTIO_ERRLEN];
    if (*i + 1 < argc)
        return argv[++*i];
    snprintf(m, sizeof m, "%.200s: missing value", argv[*i]);
    hostio_die(prog, m);
    return NULL; /* not reached */
}

void hostio_opt_unknown(const char *prog, const char *opt)
{
    char m[HOSTIO_ERRLEN];
    snprintf(m, sizeof m, "unknown option '%.200s' (try --help)", opt);
    hostio_die(prog, m);
}
