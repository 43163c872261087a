/* actag_detect_traced(): the callback sees every candidate the counters
 * count, every detection comes from an accepted candidate, and the results
 * (detections, order, stats) are byte-identical to actag_detect() on real
 * frames, noise and synthetic squares, at several parameter settings. */
#include "unity.h"
#include "test_util.h"

#include "actag/actag.h"

void setUp(void) {}
void tearDown(void) {}

#define MAXR 530
#define MAXC 620
static uint8_t g_ws[ACTAG_WORKSPACE_SIZE(MAXR, MAXC)];
static uint8_t g_ws2[ACTAG_WORKSPACE_SIZE(MAXR, MAXC)];

#define MAX_ACC 4096
typedef struct {
    int kind_count[5];    /* by kind */
    int contour_accepted; /* contours that passed the size filter */
    int contour_overflow;
    int accepted;         /* quads and search positions that decoded and went on */
    int bad;              /* malformed events */
    int nacc;
    actag_point acc_corners[MAX_ACC][4]; /* corners of accepted readings */
    int acc_id[MAX_ACC];
    int rows, cols;       /* the frame's, for the border rule of guesses */
    int after_size;       /* the last event was a contour refused by size */
} tally;

/* Events seen over all frames checked so far, by kind and outcome. */
#define N_OUTCOMES (ACTAG_TRACE_TEXTURE + 1)
static int g_seen[5][N_OUTCOMES];

/* Reference for the border rule: a corner on the frame's first or last
 * row or column (guess corners are contour points, so integers). */
static int corner_on_border(const actag_point q[4], int rows, int cols)
{
    int i;
    for (i = 0; i < 4; i++) {
        int x = (int)q[i].x, y = (int)q[i].y;
        if ((float)x != q[i].x || (float)y != q[i].y)
            return -1; /* not a contour point */
        if (x == 0 || y == 0 || x == cols - 1 || y == rows - 1)
            return 1;
    }
    return 0;
}

/* The same for a merged blob's box (any coordinates): a corner on or
 * beyond the frame's first or last row or column. */
static int box_on_border(const actag_point q[4], int rows, int cols)
{
    int i;
    for (i = 0; i < 4; i++)
        if (!(q[i].x > 0.0f && q[i].y > 0.0f && q[i].x < (float)(cols - 1) &&
              q[i].y < (float)(rows - 1)))
            return 1;
    return 0;
}

static void on_event(void *user, const actag_trace_event *e)
{
    tally *t = (tally *)user;
    if (e->kind < ACTAG_TRACE_SEARCH || e->kind > ACTAG_TRACE_GUESS) {
        t->bad++;
        return;
    }
    t->kind_count[e->kind]++;
    if (e->outcome >= 0 && e->outcome < N_OUTCOMES)
        g_seen[e->kind][e->outcome]++;
    else
        t->bad++;
    /* a guess is skipped exactly when a corner lies on the border, and then
     * carries no reading */
    if (e->kind == ACTAG_TRACE_GUESS) {
        /* right after a contour refused by size: a merged blob's box
         * (corners not on pixels), skipped when a corner leaves the open
         * frame (0, cols - 1) x (0, rows - 1) */
        int b = t->after_size ? box_on_border(e->quad, t->rows, t->cols)
                              : corner_on_border(e->quad, t->rows, t->cols);
        if (b < 0 || b != (e->outcome == ACTAG_TRACE_BORDER) ||
            (b && e->decoded != NULL))
            t->bad++;
    }
    t->after_size = e->kind == ACTAG_TRACE_CONTOUR && e->outcome == ACTAG_TRACE_SIZE;
    if (e->kind == ACTAG_TRACE_CONTOUR) {
        if (e->contour == NULL)
            t->bad++;
        else if (e->outcome == ACTAG_TRACE_OVERFLOW)
            t->contour_overflow += (e->points == NULL && e->npoints == 0) ? 1 : 0;
        else if (e->points == NULL || e->npoints != e->contour->stored)
            t->bad++;
        if (e->outcome == ACTAG_TRACE_ACCEPTED)
            t->contour_accepted++;
        return;
    }
    if (e->outcome == ACTAG_TRACE_ACCEPTED) {
        const actag_point *c;
        if (e->decoded == NULL) {
            t->bad++;
            return;
        }
        t->accepted++;
        c = e->kind == ACTAG_TRACE_QUAD ? e->decoded->corners : e->decoded->fit_corners;
        if (t->nacc < MAX_ACC) {
            memcpy(t->acc_corners[t->nacc], c, sizeof t->acc_corners[0]);
            t->acc_id[t->nacc] = e->decoded->id;
            t->nacc++;
        }
    } else if ((e->outcome == ACTAG_TRACE_STRUCTURE || e->outcome == ACTAG_TRACE_MARGIN ||
                e->outcome == ACTAG_TRACE_RIVAL) &&
               e->decoded == NULL) {
        t->bad++;
    }
}

/* Runs both entry points on one frame and checks everything listed above. */
static int check_frame(const uint8_t *px, int rows, int cols, const actag_sonar_geometry *geo,
                       const actag_params *p, const char *what)
{
    actag_frame f;
    actag_detection a[32], b[32];
    actag_stats sa, sb;
    static tally t;
    int na, nb, i, j;
    f.data = px;
    f.rows = rows;
    f.cols = cols;
    f.stride = cols;
    f.depth = 8;
    memset(a, 0, sizeof a);
    memset(b, 0, sizeof b);
    memset(&t, 0, sizeof t);
    t.rows = rows;
    t.cols = cols;
    na = actag_detect(&f, geo, p, g_ws, sizeof g_ws, a, 32, &sa);
    nb = actag_detect_traced(&f, geo, p, g_ws2, sizeof g_ws2, b, 32, &sb, on_event, &t);
    TEST_ASSERT_EQUAL_INT_MESSAGE(na, nb, what);
    TEST_ASSERT_TRUE_MESSAGE(na >= 0, what);
    TEST_ASSERT_EQUAL_MEMORY_MESSAGE(a, b, sizeof a, what);
    TEST_ASSERT_EQUAL_MEMORY_MESSAGE(&sa, &sb, sizeof sa, what);
    /* the stage images are the same too */
    TEST_ASSERT_EQUAL_MEMORY_MESSAGE(actag_workspace_bitmap(g_ws, rows, cols),
                                     actag_workspace_bitmap(g_ws2, rows, cols),
                                     ACTAG_BITMAP_SIZE(rows, cols), what);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, t.bad, what);
    TEST_ASSERT_EQUAL_INT_MESSAGE(sa.contours, t.kind_count[ACTAG_TRACE_CONTOUR], what);
    TEST_ASSERT_EQUAL_INT_MESSAGE(sa.size_ok, t.contour_accepted, what);
    TEST_ASSERT_EQUAL_INT_MESSAGE(sa.overflowed, t.contour_overflow, what);
    TEST_ASSERT_EQUAL_INT_MESSAGE(sa.quads, t.kind_count[ACTAG_TRACE_QUAD], what);
    TEST_ASSERT_EQUAL_INT_MESSAGE(sa.searched, t.kind_count[ACTAG_TRACE_SEARCH], what);
    TEST_ASSERT_EQUAL_INT_MESSAGE(sa.decoded, t.accepted, what);
    /* every detection is one of the accepted readings (its corners refined,
     * refine.h: moved by at most a cell, a quarter of the diagonal) */
    for (i = 0; i < na; i++) {
        int found = 0;
        for (j = 0; j < t.nacc && !found; j++) {
            const actag_point *q = t.acc_corners[j];
            float dx = q[2].x - q[0].x, dy = q[2].y - q[0].y;
            float tol2 = 0.0625f * (dx * dx + dy * dy) + 9.0f;
            int c;
            found = t.acc_id[j] == a[i].id;
            for (c = 0; c < 4 && found; c++) {
                float ex = q[c].x - a[i].corners[c].x, ey = q[c].y - a[i].corners[c].y;
                found = ex * ex + ey * ey <= tol2;
            }
        }
        TEST_ASSERT_TRUE_MESSAGE(found, what);
    }
    return na;
}

static void params_for(actag_params *p, const actag_family *fam, int variant)
{
    actag_params_default(p);
    p->family = fam;
    switch (variant) {
    case 1: /* the paper's binary decoder, no search */
        p->tuning.decode_mode = ACTAG_DECODE_BINARY;
        p->tuning.search_candidates = 0;
        break;
    case 2: /* every search candidate, loose margins */
        p->tuning.search_candidates = ACTAG_SEARCH_MAX;
        p->tuning.search_min_margin = -5.0f;
        p->min_margin = -2.0f;
        break;
    default:
        break;
    }
}

static void test_example_frame_every_variant(void)
{
    int rows = 0, cols = 0, v, found = 0;
    actag_family fam;
    actag_params p;
    const actag_sonar_geometry geo = {0.1f, 1.5f, 1.0472f, NULL, 0u};
    uint8_t *img = tu_read_pgm(ACTAG_SOURCE_DIR "/data/exampleSonarImage.pgm", &rows, &cols);
    TEST_ASSERT_NOT_NULL(img);
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
    for (v = 0; v < 3; v++) {
        char what[64];
        snprintf(what, sizeof what, "example frame, variant %d", v);
        params_for(&p, &fam, v);
        found += check_frame(img, rows, cols, &geo, &p, what) > 0;
    }
    TEST_ASSERT_EQUAL_INT(3, found); /* the tag is there in every variant */
    free(img);
}

/* Pool frames: the 6 in data/pool-video, or with --full-data the 58 of the
 * full data set (test_trace_full_data). */
static const char *g_pool_dir = TU_DATA "/pool-video";
static int g_pool_frames[58] = {1, 11, 291, 421, 491, 561};
static int g_pool_n = 6;

static void test_pool_frames(void)
{
    int i, total = 0;
    actag_family fam;
    actag_params p;
    const actag_sonar_geometry geo = {0.1f, 1.5f, 1.0472f, NULL, 0u};
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
    params_for(&p, &fam, 0);
    for (i = 0; i < g_pool_n; i++) {
        char path[512];
        int rows = 0, cols = 0;
        uint8_t *img;
        snprintf(path, sizeof path, "%s/f_%04d.pgm", g_pool_dir, g_pool_frames[i]);
        img = tu_read_pgm(path, &rows, &cols);
        TEST_ASSERT_TRUE(rows <= MAXR && cols <= MAXC);
        total += check_frame(img, rows, cols, &geo, &p, path);
        free(img);
    }
    TEST_ASSERT_TRUE(total > 0);
    { /* the ragged pool outlines exercise the extreme-point grid guesses */
        int k, guesses = 0;
        for (k = 0; k < N_OUTCOMES; k++)
            guesses += g_seen[ACTAG_TRACE_GUESS][k];
        TEST_ASSERT_TRUE(guesses > 0);
    }
}

/* Noise with bright squares (some with a dark ring) under the orientation
 * flags: many contours, quads and failed decodes. */
static void test_synthetic_frames(void)
{
    static uint8_t img[300 * 280];
    int trial, rows = 300, cols = 280;
    actag_family fam;
    actag_params p;
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
    tu_seed(11);
    for (trial = 0; trial < 12; trial++) {
        actag_sonar_geometry geo = {0.1f, 1.5f, 1.0472f, NULL, 0u};
        int i, s, r0, c0, r, c, n;
        char what[64];
        geo.flags = (unsigned)(trial & 3);
        for (i = 0; i < rows * cols; i++)
            img[i] = (uint8_t)tu_range(0, 60);
        for (s = 0; s < 6; s++) {
            int side = tu_range(12, 40), ring = tu_range(0, 1);
            r0 = tu_range(0, rows - side - 1);
            c0 = tu_range(0, cols - side - 1);
            for (r = r0; r < r0 + side; r++)
                for (c = c0; c < c0 + side; c++) {
                    int edge = ring && (r - r0 < side / 4 || r0 + side - 1 - r < side / 4 ||
                                        c - c0 < side / 4 || c0 + side - 1 - c < side / 4);
                    img[r * cols + c] = edge ? 10 : (uint8_t)tu_range(180, 255);
                }
        }
        params_for(&p, &fam, trial % 3);
        snprintf(what, sizeof what, "synthetic trial %d", trial);
        n = check_frame(img, rows, cols, &geo, &p, what);
        /* bright squares, ringed or not, carry no code: no tag */
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, n, what);
    }
    /* the frames exercised the rejection paths, not only acceptance */
    TEST_ASSERT_TRUE(g_seen[ACTAG_TRACE_CONTOUR][ACTAG_TRACE_SIZE] > 0);
    TEST_ASSERT_TRUE(g_seen[ACTAG_TRACE_CONTOUR][ACTAG_TRACE_ACCEPTED] > 0);
    TEST_ASSERT_TRUE(g_seen[ACTAG_TRACE_QUAD][ACTAG_TRACE_NO_MATCH] +
                         g_seen[ACTAG_TRACE_QUAD][ACTAG_TRACE_SIDES] +
                         g_seen[ACTAG_TRACE_QUAD][ACTAG_TRACE_STRUCTURE] > 0);
    TEST_ASSERT_TRUE(g_seen[ACTAG_TRACE_SEARCH][ACTAG_TRACE_NO_MATCH] +
                         g_seen[ACTAG_TRACE_SEARCH][ACTAG_TRACE_MARGIN] +
                         g_seen[ACTAG_TRACE_SEARCH][ACTAG_TRACE_STRUCTURE] > 0);
    /* squares at the frame's edge: guesses skipped by the border rule, and
     * guesses inside read as usual */
    TEST_ASSERT_TRUE(g_seen[ACTAG_TRACE_GUESS][ACTAG_TRACE_BORDER] > 0);
    TEST_ASSERT_TRUE(g_seen[ACTAG_TRACE_GUESS][ACTAG_TRACE_NO_MATCH] > 0);
}

/* Errors come back exactly as from actag_detect, with no event. */
static void test_errors_without_events(void)
{
    static uint8_t img[64 * 64];
    static tally t;
    actag_family fam;
    actag_params p;
    actag_frame f = {img, 64, 64, 64, 8};
    actag_detection d[4];
    const actag_sonar_geometry bad = {1.0f, 0.5f, 1.0f, NULL, 0u};
    const actag_sonar_geometry good = {0.1f, 1.5f, 1.0f, NULL, 0u};
    TEST_ASSERT_EQUAL_INT(ACTAG_OK, actag_family_get("AcTag24h10", &fam));
    params_for(&p, &fam, 0);
    memset(&t, 0, sizeof t);
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, actag_detect(&f, &bad, &p, g_ws, sizeof g_ws, d, 4, NULL));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_GEOMETRY, actag_detect_traced(&f, &bad, &p, g_ws, sizeof g_ws,
                                                                  d, 4, NULL, on_event, &t));
    TEST_ASSERT_EQUAL_INT(ACTAG_ERR_WORKSPACE,
                          actag_detect_traced(&f, &good, &p, g_ws, 10, d, 4, NULL, on_event, &t));
    /* no event of any kind, a malformed one (bad) included */
    TEST_ASSERT_EQUAL_INT(0, t.kind_count[1] + t.kind_count[2] + t.kind_count[3] + t.kind_count[4]);
    TEST_ASSERT_EQUAL_INT(0, t.bad);
}

int main(int argc, char **argv)
{
    UNITY_BEGIN();
    if (tu_full_data(argc, argv)) {
        int i;
        g_pool_dir = TU_FULL_DATA "/sonar/pool-video";
        for (i = 0; i < 58; i++)
            g_pool_frames[i] = 1 + 10 * i;
        g_pool_n = 58;
        RUN_TEST(test_pool_frames);
        return UNITY_END();
    }
    RUN_TEST(test_example_frame_every_variant);
    RUN_TEST(test_pool_frames);
    RUN_TEST(test_synthetic_frames);
    RUN_TEST(test_errors_without_events);
    return UNITY_END();
}
