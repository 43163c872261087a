/*
 * fuzz_track.c -- libFuzzer harness: the tracker (track.h) over a fuzzed
 * sequence of up to 10 small frames, each holding 0-3 rendered AcTag24h8
 * tags at fuzzed places (a tag may move, vanish, come back, or another
 * appear beside it), with fuzzed tracker parameters (in and out of their
 * documented ranges) and a fuzzed starting frame counter.
 *
 * Checks: actag_tracker_init refuses exactly what actag_tracker_update
 * would (a state it accepted never turns into ACTAG_ERR_PARAM later: the
 * review of 2026-12-07 found a counter that did on 32-bit long); every
 * update returns >= 0 or a documented code; at most ACTAG_TRACK_MAX tracks,
 * none with track_id 0, no two with one track_id; a track_id keeps its tag
 * ID and handedness for as long as it is reported; hits, age and missed are
 * never negative and frame never goes below 0; a second tracker fed the
 * same frames gives the same bytes.
 */
#include "fuzz_util.h"

#include "actag/actag.h"
#include "actag/render.h"
#include "actag/track.h"

#include <string.h>

enum { FT_R = 192, FT_C = 192, FT_CELL = 6, FT_MARGIN = 3, FT_FRAMES = 10, FT_TAGS = 3 };

static uint8_t ft_img[FT_R * FT_C];
static uint8_t ft_ws[ACTAG_WORKSPACE_SIZE(FT_R, FT_C)];
static actag_tracker ft_a, ft_b;

typedef struct {
    uint32_t track_id;
    int id, mirrored;
} ft_seen;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* 1 m a row; at row 100 (100 m) 1 m a beam: square cells there (a lone
     * tag with its top row at 40-100 is read) */
    const actag_sonar_geometry g = {0.0f, (float)(FT_R - 1), (float)(FT_C - 1) / 100.0f, NULL, 0u};
    fz_reader r;
    actag_family f8;
    actag_params p;
    actag_track_params tp;
    actag_track out_a[ACTAG_TRACK_MAX], out_b[ACTAG_TRACK_MAX];
    ft_seen seen[64];
    int nseen = 0, nframes, fno, rc_init, i, j, side;
    uint8_t tag[64 * 64];

    fz_init(&r, data, size);
    if (actag_family_get("AcTag24h8", &f8) != ACTAG_OK)
        return 0;
    side = actag_render_side(f8.bits, FT_CELL, FT_MARGIN);
    FZ_CHECK(side <= 64, "side %d", side);
    actag_params_default(&p);
    p.family = &f8;
    p.tag_size = 3.0f * FT_CELL;
    actag_track_params_default(&tp);
    tp.full_every = fz_int(&r, tp.full_every, 1, 20);
    tp.confirm_frames = fz_int(&r, tp.confirm_frames, 1, 5);
    tp.confirm_margin = fz_float(&r, tp.confirm_margin, 0.0f, 50.0f);
    tp.max_missed = fz_int(&r, tp.max_missed, 0, 10);
    tp.roi_scale = fz_float(&r, tp.roi_scale, 0.0f, 4.0f);
    tp.gate = fz_float(&r, tp.gate, 0.0f, 4.0f);
    tp.smoothing = fz_float(&r, tp.smoothing, 0.0f, 1.0f);
    tp.refind_after = fz_int(&r, tp.refind_after, 0, 5);
    tp.verify = fz_int(&r, tp.verify, 0, 1);
    tp.report_coasting = fz_int(&r, tp.report_coasting, 0, 1);
    rc_init = actag_tracker_init(&ft_a, &tp);
    FZ_CHECK(rc_init == ACTAG_OK || rc_init == ACTAG_ERR_PARAM, "init returned %d", rc_init);
    if (rc_init != ACTAG_OK)
        return 0;
    FZ_CHECK(actag_tracker_init(&ft_b, &tp) == ACTAG_OK, "init differs");
    { /* a counter near its end, as after years of pings */
        uint8_t m = fz_u8(&r);
        if (m >= 200) {
            ft_a.frame = LONG_MAX - (long)(m - 200);
            ft_b.frame = ft_a.frame;
        }
    }
    nframes = 1 + fz_u8(&r) % FT_FRAMES;
    for (fno = 0; fno < nframes; fno++) {
        actag_frame fr;
        int ntags = fz_u8(&r) % (FT_TAGS + 1), na, nb, k;
        memset(ft_img, 0, sizeof ft_img);
        for (k = 0; k < ntags; k++) {
            int id = fz_u8(&r) % 4, x0 = fz_u8(&r) % (FT_C - side + 1),
                y0 = 40 + fz_u8(&r) % 61, y; /* rows 40-148: read when alone */
            if (actag_render_tag(&f8, id, FT_CELL, FT_MARGIN, 0, 0, tag, side, sizeof tag) !=
                ACTAG_OK)
                continue;
            for (y = 0; y < side; y++) /* later tags overwrite earlier ones */
                memcpy(ft_img + (size_t)(y0 + y) * FT_C + (size_t)x0, tag + (size_t)y * (size_t)side,
                       (size_t)side);
        }
        fr.data = ft_img;
        fr.rows = FT_R;
        fr.cols = FT_C;
        fr.stride = FT_C;
        fr.depth = 8;
        na = actag_tracker_update(&ft_a, &fr, &g, &p, NULL, ft_ws, sizeof ft_ws, out_a,
                                  ACTAG_TRACK_MAX, NULL);
        FZ_CHECK(na >= 0, "frame %d: update returned %d on a state init accepted", fno, na);
        nb = actag_tracker_update(&ft_b, &fr, &g, &p, NULL, ft_ws, sizeof ft_ws, out_b,
                                  ACTAG_TRACK_MAX, NULL);
        FZ_CHECK(na == nb && memcmp(out_a, out_b, (size_t)na * sizeof out_a[0]) == 0,
                 "frame %d: the same frames gave other tracks", fno);
        FZ_CHECK(ft_a.ntracks >= 0 && ft_a.ntracks <= ACTAG_TRACK_MAX, "ntracks %d",
                 ft_a.ntracks);
        FZ_CHECK(ft_a.frame >= 0 && ft_a.last_full < ft_a.frame, "frame %ld last_full %ld",
                 ft_a.frame, ft_a.last_full);
        for (i = 0; i < ft_a.ntracks; i++) {
            const actag_track *t = &ft_a.tracks[i];
            FZ_CHECK(t->track_id != 0u, "track %d has track_id 0", i);
            FZ_CHECK(t->hits >= 0 && t->age >= 0 && t->missed >= 0, "negative counter");
            for (j = 0; j < i; j++)
                FZ_CHECK(ft_a.tracks[j].track_id != t->track_id, "two tracks with id %u",
                         t->track_id);
        }
        for (i = 0; i < na; i++) {
            for (j = 0; j < nseen && seen[j].track_id != out_a[i].track_id; j++)
                ;
            if (j < nseen) {
                FZ_CHECK(seen[j].id == out_a[i].id && seen[j].mirrored == out_a[i].mirrored,
                         "track %u switched from ID %d to %d", out_a[i].track_id, seen[j].id,
                         out_a[i].id);
            } else if (nseen < 64) {
                seen[nseen].track_id = out_a[i].track_id;
                seen[nseen].id = out_a[i].id;
                seen[nseen].mirrored = out_a[i].mirrored;
                nseen++;
            }
        }
    }
    return 0;
}
