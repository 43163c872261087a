/* Tracking evaluation for actag-eval (see eval_track.h). */
#define _POSIX_C_SOURCE 200809L
#include "eval_track.h"
#include "simio.h"
#include "../hostio/hostio.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#ifdef __GNUC__
#define TE_NOINLINE __attribute__((noinline))
#else
#define TE_NOINLINE
#endif

void te_options_default(te_options *o)
{
    memset(o, 0, sizeof *o);
    actag_track_params_default(&o->track);
    o->relax_roi = 0;
    o->sequences = 0;
    o->length = 100;
    o->threads = 2;
}

TE_NOINLINE int te_full_frame(const actag_frame *f, const actag_sonar_geometry *g,
                              const actag_params *p, void *ws, size_t wss,
                              actag_detection *det, int max)
{
    return actag_detect(f, g, p, ws, wss, det, max, NULL);
}

TE_NOINLINE int te_track_frame(actag_tracker *t, const actag_frame *f,
                               const actag_sonar_geometry *g, const actag_params *p,
                               const actag_params *rp, void *ws, size_t wss, actag_track *out,
                               int max, actag_track_stats *st)
{
    return actag_tracker_update(t, f, g, p, rp, ws, wss, out, max, st);
}

TE_NOINLINE int te_track_frame_tracked(actag_tracker *t, const actag_frame *f,
                                       const actag_sonar_geometry *g, const actag_params *p,
                                       const actag_params *rp, void *ws, size_t wss,
                                       actag_track *out, int max, actag_track_stats *st)
{
    return actag_tracker_update(t, f, g, p, rp, ws, wss, out, max, st);
}

static void te_params(const actag_family *fam, float tag_size, const te_options *o,
                      actag_params *p, actag_params *rp)
{
    actag_params_default(p);
    p->family = fam;
    p->tag_size = tag_size;
    p->handedness = o->handedness;
    *rp = *p;
    if (o->relax_roi) {
        rp->min_margin = -2.0f;
        rp->tuning.search_min_margin = 0.0f;
    }
}

static void te_add(te_counts *a, const te_counts *b)
{
    a->frames += b->frames;
    a->visible += b->visible;
    a->full_found += b->full_found;
    a->full_wrong += b->full_wrong;
    a->full_false += b->full_false;
    a->full_mirror += b->full_mirror;
    a->truth_known |= b->truth_known;
    a->full_order += b->full_order;
    a->track_read += b->track_read;
    a->track_reported += b->track_reported;
    a->track_wrong += b->track_wrong;
    a->track_false += b->track_false;
    a->track_mirror += b->track_mirror;
    a->track_order += b->track_order;
    a->id_switches += b->id_switches;
    a->breaks += b->breaks;
    a->tracked_frames += b->tracked_frames;
    a->tracked_full += b->tracked_full;
    a->full_pixels += b->full_pixels;
    a->track_pixels += b->track_pixels;
    a->tracked_pixels += b->tracked_pixels;
}

/* Track IDs seen in one run and the tag ID each reported last. */
#define TE_IDMAP_MAX 4096
typedef struct {
    uint32_t tid[TE_IDMAP_MAX];
    int id[TE_IDMAP_MAX];
    int n;
} te_idmap;

/* 1 when track tid reports another tag ID than it did last: each change
 * counts once (a track that keeps its new ID is not counted again). Past
 * TE_IDMAP_MAX tracks in a run the rest are not followed (a pass starts a
 * few dozen). */
static int te_switched(te_idmap *m, uint32_t tid, int id)
{
    int i;
    for (i = 0; i < m->n; i++)
        if (m->tid[i] == tid) {
            if (m->id[i] == id)
                return 0;
            m->id[i] = id;
            return 1;
        }
    if (m->n < TE_IDMAP_MAX) {
        m->tid[m->n] = tid;
        m->id[m->n++] = id;
    }
    return 0;
}

static actag_point te_centre(const actag_point *c)
{
    actag_point m;
    m.x = 0.25f * (c[0].x + c[1].x + c[2].x + c[3].x);
    m.y = 0.25f * (c[0].y + c[1].y + c[2].y + c[3].y);
    return m;
}

/* One frame of both paths. truth_px NULL: no truth (files); then "at the
 * tag" means "ID tag_id". */
typedef struct {
    actag_tracker tr;
    te_idmap ids;
    uint32_t tag_track; /* track ID last reported at the tag (0: none) */
} te_run;

/* A right-ID reading is wrong all the same with the other handedness or its
 * corners out of order: counted in *mirror / *order when the truth is known
 * (truth_mirrored >= 0, truth_px not NULL: simulated passes). Returns 1
 * for such a reading: it is an error, not a detection (nor a track
 * reading) of the tag. */
static int te_judge(int mirrored, const actag_point corners[4], int truth_mirrored,
                    const actag_point *truth_px, int *mirror, int *order)
{
    int wrong = 0;
    if (truth_mirrored >= 0 && mirrored != truth_mirrored) {
        (*mirror)++;
        wrong = 1;
    }
    if (truth_px && sim_corner_order_wrong(corners, truth_px, NULL)) {
        (*order)++;
        wrong = 1;
    }
    return wrong;
}

static void te_frame(te_run *run, const actag_frame *fr, const actag_sonar_geometry *g,
                     const actag_params *p, const actag_params *rp, void *ws, size_t wss,
                     const actag_point *truth_px, int truth_mirrored, int visible, int tag_id,
                     te_counts *c)
{
    actag_detection det[16];
    actag_track out[ACTAG_TRACK_MAX];
    actag_track_stats st;
    actag_point tc = {0.0f, 0.0f};
    float diag = 0.0f;
    int nd, nt, i, tracked = 0, found = 0, judged = 0, read = 0, rep = 0, rep_ok = 0;
    uint32_t at_tid = 0;
    char m[200];
    if (truth_px) {
        c->truth_known = 1;
        tc = te_centre(truth_px);
        diag = hypotf(truth_px[0].x - truth_px[2].x, truth_px[0].y - truth_px[2].y) +
               hypotf(truth_px[1].x - truth_px[3].x, truth_px[1].y - truth_px[3].y);
    }
    c->frames++;
    c->visible += visible > 0;
    nd = te_full_frame(fr, g, p, ws, wss, det, 16);
    if (nd < 0) {
        snprintf(m, sizeof m, "actag_detect failed: %s", actag_strerror(nd));
        te_die(m);
    }
    c->full_pixels += (double)fr->rows * fr->cols;
    for (i = 0; i < nd; i++) {
        actag_point dc = te_centre(det[i].corners);
        int at = truth_px ? hypotf(dc.x - tc.x, dc.y - tc.y) < 0.5f * diag + 3.0f : visible >= 0;
        if (at && det[i].id == tag_id && !judged) {
            /* a reading with the wrong handedness or corner order is an
             * error, not a detection */
            judged = 1;
            found = !te_judge(det[i].mirrored, det[i].corners, truth_mirrored, truth_px,
                              &c->full_mirror, &c->full_order);
        } else if (at && det[i].id != tag_id)
            c->full_wrong++;
        else
            c->full_false++;
    }
    c->full_found += found && visible > 0;
    for (i = 0; i < run->tr.ntracks; i++)
        tracked |= run->tr.tracks[i].confirmed;
    if (tracked)
        nt = te_track_frame_tracked(&run->tr, fr, g, p, rp, ws, wss, out, ACTAG_TRACK_MAX, &st);
    else
        nt = te_track_frame(&run->tr, fr, g, p, rp, ws, wss, out, ACTAG_TRACK_MAX, &st);
    if (nt < 0) {
        snprintf(m, sizeof m, "actag_tracker_update failed: %s", actag_strerror(nt));
        te_die(m);
    }
    c->track_pixels += (double)st.pixels;
    if (tracked) {
        c->tracked_frames++;
        c->tracked_full += st.full_frame;
        c->tracked_pixels += (double)st.pixels;
    }
    for (i = 0; i < nt; i++) {
        actag_point dc = te_centre(out[i].corners);
        int at = truth_px ? hypotf(dc.x - tc.x, dc.y - tc.y) < 0.5f * diag + 3.0f : visible >= 0;
        if (te_switched(&run->ids, out[i].track_id, out[i].id))
            c->id_switches++;
        /* (a track reported coasting through a tag-free file, with
         * report_coasting, is a tag where there is none: a false tag) */
        if (at && out[i].id == tag_id && !rep) {
            rep = 1;
            at_tid = out[i].track_id;
            rep_ok = !te_judge(out[i].mirrored, out[i].corners, truth_mirrored, truth_px,
                               &c->track_mirror, &c->track_order);
            read = rep_ok && out[i].measured;
        } else if (at && out[i].id != tag_id) {
            c->track_wrong++;
        } else {
            /* elsewhere, or a second track of the tag's ID at the tag (as
             * a second detection there counts in the whole frame's) */
            c->track_false++;
        }
    }
    c->track_read += read && visible > 0;
    c->track_reported += rep_ok && visible > 0;
    if (at_tid != 0) {
        if (run->tag_track != 0 && at_tid != run->tag_track && visible > 0)
            c->breaks++;
        run->tag_track = at_tid;
    }
}

/* ------------------------------------------------------------ simulated passes */

typedef struct {
    const sim_sonar *s;
    const sim_view_params *v;
    const sim_appearance *a;
    const actag_family *fam;
    float tag_size;
    uint32_t seed;
    const te_options *o;
    te_counts sum;
    pthread_mutex_t lock;
    int next, done, quiet;
} te_ctx;

static void *te_worker(void *arg)
{
    te_ctx *c = (te_ctx *)arg;
    size_t wss = actag_workspace_size(c->s->rows, c->s->cols);
    void *ws = malloc(wss);
    uint8_t *img = (uint8_t *)malloc((size_t)c->s->rows * (size_t)c->s->cols);
    te_run *run = (te_run *)malloc(sizeof *run);
    actag_params p, rp;
    char err[HOSTIO_ERRLEN];
    if (!ws || !img || !run)
        te_die("out of memory");
    te_params(c->fam, c->tag_size, c->o, &p, &rp);
    for (;;) {
        int q, i;
        te_counts cnt;
        uint32_t qs;
        sim_tag tag;
        pthread_mutex_lock(&c->lock);
        q = c->next++;
        pthread_mutex_unlock(&c->lock);
        if (q >= c->o->sequences)
            break;
        memset(&cnt, 0, sizeof cnt);
        memset(run, 0, sizeof *run);
        if (actag_tracker_init(&run->tr, &c->o->track) != ACTAG_OK)
            te_die("invalid tracking parameters");
        qs = sim_frame_seed(c->seed ^ 0x7a3c9e51u, (uint32_t)q);
        memset(&tag, 0, sizeof tag);
        tag.family = *c->fam;
        tag.tag_size = c->tag_size;
        tag.id = simio_random_id(qs, c->fam->ncodes);
        for (i = 0; i < c->o->length; i++) {
            sim_scene sc;
            sim_truth tr;
            actag_frame fr;
            sim_sequence_view(c->s, c->v, qs, i, c->o->length, &tag, &sc);
            if (sim_render(c->s, &sc, c->a, sim_frame_seed(qs, (uint32_t)i), img, NULL,
                           c->s->cols, err) != 0)
                te_die(err);
            sim_truth_of(c->s, &tag, &tr);
            fr.data = img;
            fr.rows = c->s->rows;
            fr.cols = c->s->cols;
            fr.stride = c->s->cols;
            fr.depth = 8;
            {
                te_counts before = cnt;
                te_frame(run, &fr, &c->s->geo, &p, &rp, ws, wss, tr.px, tr.mirrored, tr.visible,
                         tag.id, &cnt);
                if (c->o->failures && (cnt.full_wrong > before.full_wrong ||
                                       cnt.full_false > before.full_false ||
                                       cnt.track_wrong > before.track_wrong ||
                                       cnt.track_false > before.track_false)) {
                    /* reproducible: actag-sim --sequence LENGTH --seed SEQUENCE_SEED --id ID
                     * with the same sonar options writes this pass; FRAME is its file */
                    pthread_mutex_lock(&c->lock);
                    fprintf(c->o->failures,
                            "{\"sequence\": %d, \"frame\": %d, \"sequence_seed\": %u, "
                            "\"length\": %d, \"id\": %d, \"visible\": %d, "
                            "\"whole_frame_wrong_ids\": %d, \"whole_frame_false_tags\": %d, "
                            "\"tracker_wrong_ids\": %d, \"tracker_false_tags\": %d}\n",
                            q, i, (unsigned)qs, c->o->length, tag.id, tr.visible,
                            cnt.full_wrong - before.full_wrong,
                            cnt.full_false - before.full_false,
                            cnt.track_wrong - before.track_wrong,
                            cnt.track_false - before.track_false);
                    pthread_mutex_unlock(&c->lock);
                }
            }
        }
        pthread_mutex_lock(&c->lock);
        te_add(&c->sum, &cnt);
        c->done++;
        if (!c->quiet)
            fprintf(stderr, "actag-eval: sequence %d/%d\n", c->done, c->o->sequences);
        pthread_mutex_unlock(&c->lock);
    }
    free(ws);
    free(img);
    free(run);
    return NULL;
}

int te_run_sequences(const sim_sonar *s, const sim_view_params *v, const sim_appearance *a,
                     const actag_family *fam, float tag_size, uint32_t seed,
                     const te_options *o, te_counts *out, int quiet)
{
    static te_ctx c; /* host tool: one run at a time */
    pthread_t th[16];
    int i, n = o->threads < 1 ? 1 : (o->threads > 16 ? 16 : o->threads);
    memset(&c, 0, sizeof c);
    c.s = s;
    c.v = v;
    c.a = a;
    c.fam = fam;
    c.tag_size = tag_size;
    c.seed = seed;
    c.o = o;
    c.quiet = quiet;
    pthread_mutex_init(&c.lock, NULL);
    for (i = 0; i < n; i++)
        pthread_create(&th[i], NULL, te_worker, &c);
    for (i = 0; i < n; i++)
        pthread_join(th[i], NULL);
    pthread_mutex_destroy(&c.lock);
    *out = c.sum;
    return 0;
}

/* ------------------------------------------------------------ files */

int te_run_files(const char *const *names, int n, int want_rows, int want_cols,
                 const actag_sonar_geometry *g, const actag_family *fam, float tag_size,
                 int tag_id, const int *visible, const te_options *o, te_counts *out, char *err)
{
    te_run *run = (te_run *)calloc(1, sizeof *run);
    actag_params p, rp;
    void *ws = NULL;
    size_t wss = 0;
    int i, rows = 0, cols = 0;
    memset(out, 0, sizeof *out);
    if (!run) {
        snprintf(err, HOSTIO_ERRLEN, "out of memory");
        return -1;
    }
    if (actag_tracker_init(&run->tr, &o->track) != ACTAG_OK) {
        snprintf(err, HOSTIO_ERRLEN, "invalid tracking parameters");
        free(run);
        return -1;
    }
    te_params(fam, tag_size, o, &p, &rp);
    for (i = 0; i < n; i++) {
        hostio_image im;
        actag_frame fr;
        if (hostio_pgm_read(names[i], &im, err) != HOSTIO_OK)
            goto fail;
        if (want_rows > 0 && (im.rows != want_rows || im.cols != want_cols)) {
            snprintf(err, HOSTIO_ERRLEN, "%.150s: a %d x %d frame (rows x columns); "
                     "the geometry needs %d x %d", names[i], im.rows, im.cols, want_rows,
                     want_cols);
            hostio_image_free(&im);
            goto fail;
        }
        if (i == 0) {
            rows = im.rows;
            cols = im.cols;
            wss = actag_workspace_size(rows, cols);
            ws = malloc(wss);
            if (!ws) {
                snprintf(err, HOSTIO_ERRLEN, "out of memory");
                hostio_image_free(&im);
                goto fail;
            }
        } else if (im.rows != rows || im.cols != cols) {
            snprintf(err, HOSTIO_ERRLEN, "%s: %d x %d frame in a sequence of %d x %d frames",
                     names[i], im.rows, im.cols, rows, cols);
            hostio_image_free(&im);
            goto fail;
        }
        hostio_image_frame(&im, &fr);
        te_frame(run, &fr, g, &p, &rp, ws, wss, NULL, -1, visible ? visible[i] : 1, tag_id, out);
        hostio_image_free(&im);
    }
    free(ws);
    free(run);
    return 0;
fail:
    free(ws);
    free(run);
    return -1;
}

/* ------------------------------------------------------------ report */

void te_print(FILE *f, const char *title, const te_counts *c, const te_options *o, int json)
{
    double vis = c->visible > 0 ? c->visible : 1.0;
    double px_ratio = c->track_pixels > 0 ? c->full_pixels / c->track_pixels : 0.0;
    double px_tracked = c->tracked_pixels > 0
                            ? (double)c->tracked_frames * (c->full_pixels / (c->frames ? c->frames : 1)) /
                                  c->tracked_pixels
                            : 0.0;
    if (json) {
        char jb[5][HOSTIO_JNUM_LEN]; /* rates and ratios of nothing: null */
        /* the title may be a folder's path: a JSON string, escaped */
        fputs("{\"source\": ", f);
        hostio_json_string(f, title);
        fprintf(f, ", \"frames\": %d, \"visible\": %d, "
                   "\"full_frame\": {\"found\": %d, \"rate\": %s, \"wrong_ids\": %d, "
                   "\"false_tags\": %d, \"mirror_errors\": %d, \"order_errors\": %d}, "
                   "\"tracking\": {\"read\": %d, \"read_rate\": %s, "
                   "\"reported\": %d, \"reported_rate\": %s, \"wrong_ids\": %d, "
                   "\"false_tags\": %d, \"mirror_errors\": %d, \"order_errors\": %d, "
                   "\"id_switches\": %d, \"track_breaks\": %d, "
                   "\"tracked_frames\": %d, \"tracked_full_searches\": %d, "
                   "\"pixels_ratio\": %s, \"pixels_ratio_tracked\": %s, "
                   "\"full_every\": %d, \"confirm_frames\": %d, \"confirm_margin\": %g, "
                   "\"max_missed\": %d, \"roi_scale\": %g, \"relaxed_roi\": %d, "
                   "\"report_coasting\": %d}}",
                c->frames, c->visible, c->full_found,
                hostio_json_num(jb[0], "%.4f", c->full_found / vis, c->visible > 0), c->full_wrong,
                c->full_false, c->truth_known ? c->full_mirror : -1,
                c->truth_known ? c->full_order : -1, c->track_read,
                hostio_json_num(jb[1], "%.4f", c->track_read / vis, c->visible > 0),
                c->track_reported,
                hostio_json_num(jb[2], "%.4f", c->track_reported / vis, c->visible > 0),
                c->track_wrong, c->track_false,
                c->truth_known ? c->track_mirror : -1, c->truth_known ? c->track_order : -1,
                c->id_switches, c->breaks, c->tracked_frames, c->tracked_full,
                hostio_json_num(jb[3], "%.2f", px_ratio, c->track_pixels > 0),
                hostio_json_num(jb[4], "%.2f", px_tracked, c->tracked_pixels > 0),
                o->track.full_every, o->track.confirm_frames, (double)o->track.confirm_margin,
                o->track.max_missed, (double)o->track.roi_scale, o->relax_roi,
                o->track.report_coasting);
        return;
    }
    fprintf(f, "%s: %d frames, %d with the tag wholly in view\n", title, c->frames, c->visible);
    fprintf(f, "  whole-frame detection: tag read in %d = %.1f %%; wrong IDs %d, false tags %d",
            c->full_found, 100.0 * c->full_found / vis, c->full_wrong, c->full_false);
    if (c->truth_known)
        fprintf(f, ", mirrored-flag errors %d, corner-order errors %d", c->full_mirror,
                c->full_order);
    fprintf(f, "\n  tracking: tag read in %d = %.1f %% (reported, with any coasting: %d = %.1f %%);"
               " wrong IDs %d, false tags %d, ID switches %d, track breaks %d",
            c->track_read, 100.0 * c->track_read / vis, c->track_reported,
            100.0 * c->track_reported / vis, c->track_wrong, c->track_false, c->id_switches,
            c->breaks);
    if (c->truth_known)
        fprintf(f, ", mirrored-flag errors %d, corner-order errors %d", c->track_mirror,
                c->track_order);
    fprintf(f, "\n");
    fprintf(f, "  pixels searched: %.2fx fewer than whole frames overall, %.2fx while tracked "
               "(%d frames, %d of them searched whole)\n",
            px_ratio, px_tracked, c->tracked_frames, c->tracked_full);
}
