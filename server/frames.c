/*
 * frames.c — PNG frames and animations of a session (frames.h).
 */
#define _GNU_SOURCE
#include "frames.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../api/session_json.h"
#include "../render/apng.h"
#include "db.h"
#include "pool.h"

#define MAX_RENDERERS 64

typedef struct tsd_renderers {
    pthread_mutex_t mu;
    tsr_ctx *idle[MAX_RENDERERS];
    int nidle;
} tsd_renderers;

int tsd_renderers_init(tsd_server *srv)
{
    srv->renderers = calloc(1, sizeof *srv->renderers);
    if (!srv->renderers) return -1;
    pthread_mutex_init(&srv->renderers->mu, NULL);
    return 0;
}

void tsd_renderers_free(tsd_server *srv)
{
    tsd_renderers *g = srv->renderers;
    if (!g) return;
    for (int i = 0; i < g->nidle; i++)
        tsr_ctx_free(g->idle[i]);
    pthread_mutex_destroy(&g->mu);
    free(g);
    srv->renderers = NULL;
}

static tsr_ctx *renderer_take(tsd_server *srv, ts_err *err)
{
    tsd_renderers *g = srv->renderers;
    tsr_ctx *c = NULL;
    pthread_mutex_lock(&g->mu);
    if (g->nidle > 0) c = g->idle[--g->nidle];
    pthread_mutex_unlock(&g->mu);
    return c ? c : tsr_ctx_make(err);
}

/* Samples of the largest frame after which a renderer goes back to the pool
 * (a full-HD single-sampled frame; the default frame is 1280 x 720, the
 * dashboard's 640 x 360). A renderer keeps the buffers of its largest frame —
 * colour, depth, the multisampled pair with antialias, the read-back — and an
 * idle pooled one held them until it drew a smaller frame: one 4096 x 4096
 * antialiased frame left RSS at 818 MB (100 MB before it). One that drew more
 * is freed instead; the next large frame makes a new context (~50 ms beside
 * its ~0.6 s draw). Samples, not pixels: an antialiased frame's multisampled
 * pair holds RENDERER_MSAA_SAMPLES a pixel besides the single-sampled one, so
 * a 1920 x 1080 antialiased renderer (+79 MB idle) was kept under a pixel
 * bound. */
#define RENDERER_KEEP_SAMPLES (1920L * 1080L)
#define RENDERER_MSAA_SAMPLES 4L /* render.c MSAA_SAMPLES, at most */

/* Samples a renderer holds after drawing view v (above): the multisampled
 * pair is made only for lit antialiased frames (render.c tsr_render_png). */
static long view_samples(const tsr_view *v)
{
    long pixels = (long)v->width * v->height;
    int ms = v->antialias && v->shading != TSR_SHADE_IDS;
    return ms ? pixels * (1 + RENDERER_MSAA_SAMPLES) : pixels;
}

/* Back to the pool after a frame of the given samples, or freed (above). */
static void renderer_give(tsd_server *srv, tsr_ctx *c, long samples)
{
    tsd_renderers *g = srv->renderers;
    if (samples > RENDERER_KEEP_SAMPLES) {
        tsr_ctx_free(c);
        return;
    }
    pthread_mutex_lock(&g->mu);
    if (g->nidle < MAX_RENDERERS) {
        g->idle[g->nidle++] = c;
        c = NULL;
    }
    pthread_mutex_unlock(&g->mu);
    tsr_ctx_free(c);
}

typedef struct frames_ctx {
    tsd_server *srv;
    tsd_session *s; /* reference */
    struct MHD_Connection *conn;
    tsr_view view;
    double k0, dk; /* sample index of frame i: round(k0 + i dk) */
    long n, i;     /* frames in all, next to draw */
    int single;
    int apng;    /* draw every frame in one job and answer one APNG: holds a long job
                  * (server.h tsd_long_job_take) */
    double fps;  /* frame rate of the APNG */
    int pending; /* a draw job is queued or running */
    ts_data *d;  /* scratch state (draw jobs only) */
    int have_state;
    ts_geom *g;
    unsigned char *png; /* the frame drawn last, not yet sent */
    size_t png_len;
    long png_k;
    ts_rc rc; /* first failure */
    ts_err err;
    tsa_buf out; /* multipart text not yet handed to MHD */
    size_t off;
    int ended;
} frames_ctx;

static void frames_free(void *cls)
{
    frames_ctx *f = cls;
    if (!f) return;
    ts_data_free(f->d);
    free(f->g);
    free(f->png);
    tsa_buf_free(&f->out);
    tsd_session_put(f->s);
    if (f->apng) tsd_long_job_give(f->srv);
    free(f);
}

/* The client closed its end: a half-closed or reset socket polls as hung up. */

/* The answer of a draw job whose session was deleted, wherever the job
 * notices it: between frames, in a rebuild, or at a frame's snapshot that a
 * DELETE removed meanwhile (the same words whichever comes first). */
static ts_rc err_deleted(const frames_ctx *f, ts_err *err)
{
    return ts_err_set(err, TS_ERR_NOTFOUND, NULL,
                      "session %s was deleted while its frames were drawn", f->s->id);
}

/* Whether a draw job should stop: an APNG before its next frame, a state
 * rebuild before its next samples (frames.h); the reason in why. */
static ts_rc job_interrupted(frames_ctx *f, ts_err *why)
{
    if (atomic_load(&f->srv->stopping)) return tsd_err_shutdown(why);
    if (tsd_session_is_deleted(f->s)) return err_deleted(f, why);
    if (tsd_client_gone(f->conn)) /* nobody reads this answer; it ends the job */
        return ts_err_set(why, TS_ERR_CANCELLED, NULL, "the client closed the connection");
    return TS_OK;
}

/* ts_sample_fn of a rebuild: every 16 samples, whether to stop (the daemon
 * stopping, the session deleted, the client gone: job_interrupted, the
 * reason kept in why). A rebuild covers at most one stored batch, but its
 * samples may be slow (many modes, a small max_step): one took 76 s of CPU
 * for a deleted session's frame. */
typedef struct rebuild_ctx {
    frames_ctx *f;
    ts_err why;
} rebuild_ctx;

static int rebuild_sample(void *ud, long index, double t, const double *values, int n)
{
    (void)t, (void)values, (void)n;
    rebuild_ctx *c = ud;
    return index % 16 == 0 && job_interrupted(c->f, &c->why) != TS_OK;
}

/* Rebuild the stored state at sample index k into f->d. */
static ts_rc state_at(frames_ctx *f, long k)
{
    const ts_model *m = f->s->m;
    if (tsd_session_is_deleted(f->s)) /* also unrestored when deleted before its build */
        return err_deleted(f, &f->err);
    if (f->s->unrestored) /* its snapshots do not fit this build (session.c) */
        return ts_err_set(&f->err, TS_ERR_STATE, NULL, "session %s has no frames here: %s",
                          f->s->id, f->s->error);
    if (!f->d && !(f->d = ts_data_make(m, &f->err))) return f->err.code;
    void *blob = NULL;
    size_t n = 0;
    long sidx = -1;
    if (tsd_db_snapshot_at(f->srv->db, f->s->seq, k, &blob, &n, &sidx) != 0 || !blob) {
        free(blob);
        /* a DELETE took the snapshots meanwhile: not /t's fault */
        if (tsd_session_is_deleted(f->s)) return err_deleted(f, &f->err);
        return ts_err_set(&f->err, TS_ERR_NOTFOUND, "/t",
                          "/t: no stored state at or before t = %g s",
                          (double)k * ts_model_sample_period(m));
    }
    ts_rc rc = TS_OK;
    long cur = f->have_state ? ts_sample_index(f->d) : -1;
    if (!f->have_state || k < cur || sidx > cur) {
        rc = ts_state_restore(m, f->d, blob, n, &f->err);
        f->have_state = rc == TS_OK;
    }
    free(blob);
    if (rc == TS_OK && ts_sample_index(f->d) < k) {
        rebuild_ctx c = {.f = f};
        ts_err_clear(&c.why);
        rc = ts_advance(m, f->d, (double)k * ts_model_sample_period(m), rebuild_sample, &c,
                        &f->err);
        if (rc == TS_ERR_CANCELLED && c.why.code != TS_OK) {
            f->err = c.why;
            rc = c.why.code;
        }
    }
    if (rc != TS_OK) f->have_state = 0;
    return rc;
}

/* Draw frame f->i into f->png (f->png_k gets its sample index). */
static ts_rc draw_one(frames_ctx *f)
{
    pthread_mutex_lock(&f->s->mu);
    long last = f->s->index;
    pthread_mutex_unlock(&f->s->mu);
    long k = lround(f->k0 + (double)f->i * f->dk);
    if (k > last) k = last;
    if (k < 0) k = 0;
    ts_rc rc = state_at(f, k);
    if (rc == TS_OK && !f->g && !(f->g = malloc(sizeof *f->g)))
        rc = ts_err_set(&f->err, TS_ERR_NOMEM, NULL, "out of memory");
    if (rc == TS_OK) rc = ts_geometry(f->s->m, f->d, f->g, &f->err);
    if (rc == TS_OK) {
        tsr_ctx *c = renderer_take(f->srv, &f->err);
        if (!c)
            rc = f->err.code != TS_OK ? f->err.code : TS_ERR_UNSUPPORTED;
        else {
            rc = tsr_render_png(c, f->g, &f->view, NULL, &f->png, &f->png_len, &f->err);
            renderer_give(f->srv, c, view_samples(&f->view));
        }
    }
    if (rc == TS_OK) f->png_k = k;
    f->i++;
    return rc;
}

/* A frame's delay 1/fps s as num / den, both 16-bit (APNG fcTL): the closest
 * such fraction, found over every denominator, so exact for any rate with a
 * 16-bit rational period (0.5 fps: 2/1, 29.97: 100/2997, 1000: 1/1000).
 * Earlier forms lost either the slow end (k / (k fps) with the largest k gave
 * 0.5 fps as 65535/32768 s) or the fast one (1000 / (1000 fps) capped the
 * denominator: every rate above 65.5 fps played at 65.5). */
static void apng_delay(double fps, unsigned *num, unsigned *den)
{
    double period = 1.0 / fps, best = INFINITY;
    *num = *den = 1;
    for (unsigned d = 1; d <= 65535 && best > 0; d++) {
        double n = round(period * d);
        if (n < 1 || n > 65535) continue;
        double e = fabs(n / d - period);
        if (e < best) best = e, *num = (unsigned)n, *den = d;
    }
}

/* Every frame, then one APNG in f->png (apng.h says why APNG). */
static ts_rc draw_apng(frames_ctx *f)
{
    unsigned char **pngs = calloc((size_t)f->n, sizeof *pngs);
    size_t *lens = calloc((size_t)f->n, sizeof *lens);
    ts_rc rc = pngs && lens ? TS_OK : ts_err_set(&f->err, TS_ERR_NOMEM, NULL, "out of memory");
    long done = 0;
    while (rc == TS_OK && f->i < f->n) {
        rc = job_interrupted(f, &f->err);
        if (rc == TS_OK) rc = draw_one(f);
        if (rc == TS_OK) {
            pngs[done] = f->png;
            lens[done++] = f->png_len;
            f->png = NULL;
        }
    }
    if (rc == TS_OK) {
        unsigned num, den;
        apng_delay(f->fps, &num, &den);
        rc = tsr_apng_assemble((const unsigned char *const *)pngs, lens, (int)done, num, den,
                               &f->png, &f->png_len, &f->err);
    }
    for (long j = 0; j < done; j++) free(pngs[j]);
    free(pngs);
    free(lens);
    return rc;
}

/* Worker: draw the next frame (or, for an APNG, all of them) into f->png,
 * then resume the connection. */
static void draw_job(void *arg)
{
    frames_ctx *f = arg;
    ts_rc rc = f->apng ? draw_apng(f) : draw_one(f);
    if (rc != TS_OK && f->rc == TS_OK) f->rc = rc;
    f->pending = 0;
    MHD_resume_connection(f->conn);
}

/* Queue the next draw with the connection suspended; 0 on success. */
static int queue_draw(frames_ctx *f)
{
    f->pending = 1;
    MHD_suspend_connection(f->conn);
    if (tsd_pool_submit(f->srv->pool, draw_job, f, 0) != 0) {
        f->pending = 0;
        f->rc = atomic_load(&f->srv->stopping)
                    ? tsd_err_shutdown(&f->err)
                    : ts_err_set(&f->err, TS_ERR_NOMEM, NULL, "out of memory queueing a frame");
        MHD_resume_connection(f->conn);
        return -1;
    }
    return 0;
}

static void put_part(frames_ctx *f)
{
    double t = (double)f->png_k * ts_model_sample_period(f->s->m);
    tsa_buf_printf(&f->out,
                   "--frame\r\nContent-Type: image/png\r\nContent-Length: %zu\r\n"
                   "X-Frame-Index: %ld\r\nX-Frame-Time: %.9g\r\n\r\n",
                   f->png_len, f->png_k, t);
    tsa_buf_put(&f->out, (const char *)f->png, f->png_len);
    tsa_buf_put(&f->out, "\r\n", 2);
    free(f->png);
    f->png = NULL;
}

static ssize_t reader(void *cls, uint64_t pos, char *buf, size_t max)
{
    (void)pos;
    frames_ctx *f = cls;
    if (f->off >= f->out.n) {
        f->out.n = 0;
        f->off = 0;
        if (f->ended) return MHD_CONTENT_READER_END_OF_STREAM;
        if (f->png)
            put_part(f);
        else if (f->rc != TS_OK)
            return MHD_CONTENT_READER_END_WITH_ERROR; /* cut the stream */
        else if (f->i < f->n) {
            if (!f->pending) queue_draw(f);
            return 0; /* suspended until the frame is drawn */
        } else {
            tsa_buf_put(&f->out, "--frame--\r\n", 11);
            f->ended = 1;
        }
        if (f->out.oom) return MHD_CONTENT_READER_END_WITH_ERROR;
    }
    size_t k = f->out.n - f->off;
    if (k > max) k = max;
    memcpy(buf, f->out.p + f->off, k);
    f->off += k;
    return (ssize_t)k;
}

/* The first frame is drawn: answer the request. */
static enum MHD_Result first_frame_ready(tsd_request *r)
{
    frames_ctx *f = r->async_ctx;
    r->async_ctx = NULL;
    r->async_free = NULL;
    if (f->rc != TS_OK) {
        enum MHD_Result ret = tsd_reply_err(r, &f->err, NULL);
        frames_free(f);
        return ret;
    }
    if (f->single || f->apng) {
        unsigned char *png = f->png;
        size_t len = f->png_len;
        const char *type = f->apng ? "image/apng" : "image/png";
        f->png = NULL;
        frames_free(f);
        return tsd_reply_owned(r, MHD_HTTP_OK, type, (char *)png, len);
    }
    return tsd_reply_chunked(r, "multipart/x-mixed-replace; boundary=frame", 1 << 16, reader, f,
                             frames_free);
}

enum MHD_Result tsd_frames_reply(tsd_request *r, tsd_session *s, const tsr_view *v, double k0,
                                 double dk, long n, int single, double apng_fps)
{
    int apng = !single && apng_fps > 0;
    ts_err e;
    if (apng && tsd_long_job_take(r->srv, &r->retry_after, &e) != TS_OK) {
        size_t k = strlen(e.msg);
        snprintf(e.msg + k, sizeof e.msg - k,
                 ", or ask for the frames as format=multipart "
                 "(one frame per job)");
        return tsd_reply_err(r, &e, NULL);
    }
    frames_ctx *f = calloc(1, sizeof *f);
    if (!f) {
        if (apng) tsd_long_job_give(r->srv);
        return MHD_NO;
    }
    f->srv = r->srv;
    f->s = s;
    tsd_session_hold(s);
    f->conn = r->conn;
    f->view = *v;
    f->k0 = k0;
    f->dk = dk;
    f->n = n;
    f->single = single;
    f->apng = apng;
    f->fps = apng_fps;
    r->async_ctx = f;
    r->async_free = frames_free;
    r->on_resume = first_frame_ready;
    queue_draw(f); /* on failure f->rc is set and the connection already resumed */
    return MHD_YES;
}
