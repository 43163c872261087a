/*
 * fuzz_hostio.c -- libFuzzer harness: the host tools' frame readers
 * (tools/hostio): hostio_pgm_parse, hostio_frame_parse (PGM by magic, raw by
 * layout) and the number parsers.
 *
 * Input: a raw layout (rows, cols, depth, stride from the first bytes) and
 * the file contents (the rest, handed over in an exact-size buffer, so any
 * read past it is reported by AddressSanitizer). Checks:
 *   - pgm_parse: success only with a header inside the buffer, 1..32767 x
 *     1..32767, maxval 1..65535, 1 or 2 bytes per sample by maxval, and all
 *     pixel bytes present; errors carry a message naming the input;
 *   - frame_parse: a buffer of the raw layout's size is raw, byte for byte
 *     (16-bit little-endian), other P5 buffers agree with pgm_parse (samples
 *     above maxval an error, 8-bit samples scaled by maxval exactly as
 *     documented, 16-bit big-endian samples as stored), everything else an
 *     error with a message and no image; no leak (LeakSanitizer);
 *   - the number parsers: success only for a value inside the range.
 */
#include "fuzz_util.h"

#include "hostio.h"

static int is_ws(uint8_t c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

static void check_frame(const uint8_t *buf, size_t len, const hostio_raw_spec *raw)
{
    char err[HOSTIO_ERRLEN];
    hostio_pgm_view v;
    hostio_image im;
    int prc, frc, stride, fits;
    size_t i;
    err[0] = '\0';
    prc = hostio_pgm_parse(buf, len, "in.pgm", &v, err);
    if (prc == HOSTIO_OK) {
        size_t off, need;
        FZ_CHECK(len >= 3 && buf[0] == 'P' && buf[1] == '5', "accepted without P5 magic");
        FZ_CHECK(v.rows >= 1 && v.rows <= 32767 && v.cols >= 1 && v.cols <= 32767, "size");
        FZ_CHECK(v.maxval >= 1 && v.maxval <= 65535, "maxval %d", v.maxval);
        FZ_CHECK(v.bytes_per_sample == (v.maxval > 255 ? 2 : 1), "bytes per sample");
        FZ_CHECK(v.pixels > buf && v.pixels <= buf + len, "pixels outside the buffer");
        off = (size_t)(v.pixels - buf);
        need = (size_t)v.rows * (size_t)v.cols * (size_t)v.bytes_per_sample;
        FZ_CHECK(len - off >= need, "pixel bytes missing");
        FZ_CHECK(is_ws(buf[off - 1]), "no whitespace before the pixels");
    } else {
        FZ_CHECK(prc == -1 && err[0] != '\0' && strstr(err, "in.pgm") != NULL,
                 "pgm error without a message naming the input: '%s'", err);
    }

    memset(&im, 0x77, sizeof im);
    err[0] = '\0';
    frc = hostio_frame_parse(buf, len, "in.raw", raw, &im, err);
    stride = raw && raw->stride ? raw->stride : raw ? raw->cols : 0;
    /* the documented rule: a buffer of the raw layout's size is raw */
    fits = raw && raw->rows >= 1 && raw->cols >= 1 && raw->rows <= 32767 && raw->cols <= 32767 &&
           (raw->depth == 8 || raw->depth == 16) && stride >= raw->cols &&
           ((uint64_t)(raw->rows - 1) * (uint64_t)stride + (uint64_t)raw->cols) *
                   (uint64_t)(raw->depth / 8) <= (uint64_t)len &&
           (uint64_t)raw->rows * (uint64_t)stride * (uint64_t)(raw->depth / 8) >= (uint64_t)len;
    if (fits) {
        /* samples addressed by the layout: the last row ends at its cols */
        size_t full = (size_t)(raw->rows - 1) * (size_t)stride + (size_t)raw->cols;
        FZ_CHECK(frc == HOSTIO_OK, "a buffer of the raw layout's size refused: %s", err);
        FZ_CHECK(im.rows == raw->rows && im.cols == raw->cols && im.stride == stride &&
                     im.depth == raw->depth,
                 "raw layout");
        for (i = 0; i < full; i++) {
            unsigned want;
            if (raw->depth == 8) {
                want = i < len ? buf[i] : 0u;
                FZ_CHECK(((uint8_t *)im.data)[i] == want, "raw byte %lu", (unsigned long)i);
            } else {
                want = 2 * i + 1 < len ? (unsigned)(buf[2 * i] | (buf[2 * i + 1] << 8)) : 0u;
                FZ_CHECK(((uint16_t *)im.data)[i] == want, "raw sample %lu", (unsigned long)i);
            }
        }
        hostio_image_free(&im);
        return;
    }
    if (frc != HOSTIO_OK) {
        FZ_CHECK(frc == -1 && err[0] != '\0' && strstr(err, "in.raw") != NULL,
                 "frame error without a message naming the input: '%s'", err);
        FZ_CHECK(im.data == NULL, "image left on error");
        if (prc == HOSTIO_OK && !(raw && raw->rows > 0 && raw->cols > 0)) {
            /* a valid PGM is refused only for a sample above maxval */
            size_t n = (size_t)v.rows * (size_t)v.cols, above = 0;
            for (i = 0; i < n; i++) {
                uint32_t smp = v.bytes_per_sample == 1
                                   ? v.pixels[i]
                                   : (uint32_t)((v.pixels[2 * i] << 8) | v.pixels[2 * i + 1]);
                above += smp > (uint32_t)v.maxval;
            }
            FZ_CHECK(above > 0, "valid PGM refused: %s", err);
        }
        return;
    }
    {
        /* PGM: agrees with pgm_parse */
        size_t n;
        FZ_CHECK(im.data != NULL, "no image");
        FZ_CHECK(prc == HOSTIO_OK, "frame accepted as PGM, pgm_parse refused");
        FZ_CHECK(im.rows == v.rows && im.cols == v.cols && im.stride == v.cols, "PGM size");
        FZ_CHECK(im.depth == 8 * v.bytes_per_sample, "PGM depth");
        n = (size_t)v.rows * (size_t)v.cols;
        for (i = 0; i < n; i++) {
            uint32_t smp = v.bytes_per_sample == 1
                               ? v.pixels[i]
                               : (uint32_t)((v.pixels[2 * i] << 8) | v.pixels[2 * i + 1]);
            uint32_t mx = (uint32_t)v.maxval;
            FZ_CHECK(smp <= mx, "sample above maxval accepted");
            if (v.bytes_per_sample == 1)
                FZ_CHECK(((uint8_t *)im.data)[i] == (uint8_t)((smp * 255u + mx / 2u) / mx),
                         "8-bit sample %lu not scaled by maxval", (unsigned long)i);
            else
                FZ_CHECK(((uint16_t *)im.data)[i] == smp, "16-bit sample %lu", (unsigned long)i);
        }
    }
    hostio_image_free(&im);
}

static void check_numbers(const uint8_t *buf, size_t len)
{
    char s[64], err[HOSTIO_ERRLEN];
    size_t n = len < sizeof s - 1 ? len : sizeof s - 1;
    double d, list[8];
    long l;
    int cnt;
    memcpy(s, buf, n);
    s[n] = '\0';
    if (hostio_parse_double("--x", s, -10.0, 1e6, &d, err) == HOSTIO_OK)
        FZ_CHECK(d >= -10.0 && d <= 1e6, "double %g outside its range", d);
    else
        FZ_CHECK(strstr(err, "--x") != NULL, "double error without the option name");
    if (hostio_parse_long("--n", s, -5, 70000, &l, err) == HOSTIO_OK)
        FZ_CHECK(l >= -5 && l <= 70000, "long %ld outside its range", l);
    else
        FZ_CHECK(strstr(err, "--n") != NULL, "long error without the option name");
    if (hostio_parse_doubles("--v", s, ',', list, 3, err) == HOSTIO_OK)
        FZ_CHECK(isfinite(list[0]) && isfinite(list[1]) && isfinite(list[2]), "not finite");
    if (hostio_parse_list("--l", s, list, 8, &cnt, err) == HOSTIO_OK)
        FZ_CHECK(cnt >= 0 && cnt <= 9, "list count %d", cnt);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_reader r;
    hostio_raw_spec raw;
    const uint8_t *rest;
    uint8_t *exact;
    size_t len;
    int use_raw;
    fz_init(&r, data, size);
    use_raw = fz_u8(&r) & 1;
    raw.rows = fz_int(&r, 4, 1, 64);
    raw.cols = fz_int(&r, 4, 1, 64);
    raw.depth = fz_u8(&r) & 1 ? 16 : fz_int(&r, 8, 0, 17);
    raw.stride = fz_int(&r, 0, 0, 80);
    rest = fz_rest(&r, &len);
    exact = (uint8_t *)malloc(len ? len : 1);
    FZ_CHECK(exact != NULL, "oom");
    if (len)
        memcpy(exact, rest, len);
    check_frame(exact, len, use_raw ? &raw : NULL);
    check_numbers(exact, len);
    free(exact);
    return 0;
}
