/* The consumer project's program: detects the tag of the repository's
 * sample frame (AcTag24h10 ID 0) through the library built by
 * add_subdirectory(); exit status 0 when it is found. */
#include "actag/actag.h"
#include "actag/families.h"

#include <stdio.h>
#include <stdlib.h>

#ifndef ACTAG_HAVE_AcTag24h10
#error "ACTAG_FAMILIES of the consumer must hold AcTag24h10"
#endif

static uint8_t ws[ACTAG_WORKSPACE_SIZE(463, 620)];
static uint8_t px[463 * 620];

int main(int argc, char **argv)
{
    actag_family fam;
    actag_params p;
    actag_sonar_geometry g = {0.1f, 1.5f, 1.0471976f, NULL, 0u};
    actag_frame f = {px, 463, 620, 620, 8};
    actag_detection det[4];
    int w, h, m, n;
    FILE *in;
    if (argc != 2 || (in = fopen(argv[1], "rb")) == NULL)
        return 2;
    if (fscanf(in, "P5 %d %d %d", &w, &h, &m) != 3 || w != 620 || h != 463 || m != 255 ||
        fgetc(in) == EOF || fread(px, 1, sizeof px, in) != sizeof px)
        return 2;
    fclose(in);
    if (actag_family_AcTag24h10(&fam) != ACTAG_OK || actag_family_count() != 2)
        return 1;
    actag_params_default(&p);
    p.family = &fam;
    n = actag_detect(&f, &g, &p, ws, sizeof ws, det, 4, NULL);
    printf("consumer: %d tag(s)%s\n", n, n == 1 && det[0].id == 0 ? ", ID 0" : "");
    return n == 1 && det[0].id == 0 ? 0 : 1;
}
