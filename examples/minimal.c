/*
 * minimal.c -- the smallest complete program using libactag: reads an 8-bit
 * binary PGM sonar frame and prints every AcTag in it.
 *
 *   cc minimal.c $(pkg-config --cflags --libs actag) -o minimal
 *   ./minimal data/exampleSonarImage.pgm
 *
 * The frame is the example of data/: 0.1-1.5 m, 60 degree aperture, row 0 the
 * farthest range, column 0 the +30 degree beam, family AcTag24h10 with tags
 * whose inner white square is 0.130628571 m wide. Like the library, the
 * program allocates nothing: the frame and the workspace are static arrays
 * sized for the largest frame it accepts (1024 x 1024).
 */
#include <stdint.h>
#include <stdio.h>

#include "actag/actag.h"

#define MAX_ROWS 1024
#define MAX_COLS 1024

static uint8_t pixels[MAX_ROWS * MAX_COLS];
static uint8_t ws[ACTAG_WORKSPACE_SIZE(MAX_ROWS, MAX_COLS)];

/* The next header number of a PGM, after whitespace and '#' comment lines:
 * decimal digits worth at most 99999 (a larger width cannot be valid here,
 * and an int must not wrap), ended by whitespace (consumed: after maxval it
 * is the one byte before the pixels) or by a comment (left to be skipped). */
static int header_int(FILE *f, int *v)
{
    int ch, digits = 0;
    while ((ch = fgetc(f)) == '#' || ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r')
        if (ch == '#')
            while ((ch = fgetc(f)) != '\n' && ch != EOF)
                ;
    for (*v = 0; ch >= '0' && ch <= '9'; ch = fgetc(f), digits++)
        if ((*v = *v * 10 + (ch - '0')) > 99999)
            return 0;
    if (ch == '#')
        return digits > 0 && ungetc(ch, f) != EOF;
    return digits > 0 && (ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r');
}

/* After the magic "P5": whitespace or a comment, not a digit ("P540 30 255"
 * is no PGM; it was read as 40 columns). */
static int magic_end(FILE *f)
{
    int ch = fgetc(f);
    return (ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r' || ch == '#') &&
           ungetc(ch, f) != EOF;
}

/* A bare-bones P5 reader (8 bit), one frame a file. Returns NULL, or why the
 * file is refused. */
static const char *read_pgm(const char *path, int *rows, int *cols)
{
    FILE *f = fopen(path, "rb");
    const char *why = NULL;
    int maxval = 0;
    if (!f)
        return "cannot open it";
    if (fgetc(f) != 'P' || fgetc(f) != '5' || !magic_end(f) || !header_int(f, cols) ||
        !header_int(f, rows) || !header_int(f, &maxval))
        why = "not a binary (P5) PGM";
    else if (*rows < 1 || *rows > MAX_ROWS || *cols < 1 || *cols > MAX_COLS)
        why = "larger than 1024 x 1024 pixels (or empty)";
    else if (maxval != 255)
        why = "not an 8-bit PGM of maxval 255 (this example does not rescale)";
    else if (fread(pixels, 1, (size_t)*rows * (size_t)*cols, f) != (size_t)*rows * (size_t)*cols)
        why = "cut short (fewer pixels than its header says)";
    else if (fgetc(f) != EOF) /* trailing bytes: not the frame its header says */
        why = "longer than its header says (bytes after the pixels)";
    fclose(f);
    return why;
}

int main(int argc, char **argv)
{
    actag_family fam;
    actag_params p;
    actag_sonar_geometry geo = {0.1f, 1.5f, 1.0472f, NULL, 0}; /* m, m, rad */
    actag_frame frame;
    actag_detection det[8];
    int rows, cols, n, i, c;
    const char *why;

    if (argc != 2 || argv[1][0] == '-') { /* --help, --version, anything else */
        fprintf(stderr, "usage: minimal FRAME.pgm (8-bit binary PGM, at most %d x %d)\n",
                MAX_COLS, MAX_ROWS);
        return 2;
    }
    if ((why = read_pgm(argv[1], &rows, &cols)) != NULL) {
        fprintf(stderr, "minimal: %s: %s\n", argv[1], why);
        return 2;
    }
    frame.data = pixels;
    frame.rows = rows; /* range bins */
    frame.cols = cols; /* beams */
    frame.stride = cols;
    frame.depth = 8;

    actag_family_get("AcTag24h10", &fam);
    actag_params_default(&p);
    p.family = &fam;
    p.tag_size = 0.130628571f; /* side of the inner white square, m */
    n = actag_detect(&frame, &geo, &p, ws, sizeof ws, det, 8, NULL);
    if (n < 0) {
        fprintf(stderr, "minimal: %s: %s\n", argv[1], actag_strerror(n));
        return 2;
    }
    printf("%s: %d tag%s\n", argv[1], n, n == 1 ? "" : "s");
    for (i = 0; i < n; i++) {
        printf("tag %d (%s), hamming %d, margin %.1f\n", det[i].id,
               det[i].mirrored ? "mirrored" : "not mirrored", det[i].hamming,
               (double)det[i].decision_margin);
        for (c = 0; c < 4; c++) /* corners in the tag's own order TL TR BR BL */
            printf("  corner %d: x %.1f y %.1f px, range %.3f m, azimuth %+.4f rad\n", c,
                   (double)det[i].corners[c].x, (double)det[i].corners[c].y,
                   (double)det[i].range[c], (double)det[i].azimuth[c]);
    }
    return 0;
}
