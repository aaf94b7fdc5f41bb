/*
 * session.c — simulation sessions (session.h): registry, state machine, and
 * the step and run jobs that advance a session's model on the worker pool.
 *
 * State diagram (the function that makes each transition in brackets):
 *
 *            [tsd_session_create]
 *                    │
 *                    ▼        [tsd_session_run]
 *                 created ─────────────────────────┐
 *                    │ [step_job]                  ▼
 *                    ▼        [tsd_session_run]
 *        ┌───────▶ paused ─────────────────────▶ running ──[run_finish: t = duration]──▶ done
 *        │           ▲ │ [step_job]              │  │ │
 *        │           │ └──────────┘              │  │ └──[run_finish: model error]──▶ failed
 *        │           │                           │  │                                (sticky)
 *        │           └──[run_finish: until <     │  │
 *        │               duration, or cancelled]─┘  │
 *        │                                          │ [run_finish during shutdown;
 *        │ [step_job]                               ▼  load_session: "running" in the
 *        └──────────────────────────────── interrupted  database at start-up]
 *                                   [tsd_session_run] ──▶ running
 *
 *   step_job also goes to done (t reached run.duration) or failed (model error)
 *   from created | paused | interrupted. tsd_session_delete removes a session
 *   in any state (a running job stops at its next sample).
 *
 * Invariants:
 *  (1) Only the holder of `busy` touches d, the batch and the snapshot, and
 *      only workers hold it; HTTP threads read the copies kept under mu.
 *  (2) Rows reach the database in batches (BATCH_ROWS, or at the end of each
 *      slice), each batch together with the state snapshot at its last row
 *      in one transaction (db.h), so stored rows and stored state agree; t,
 *      index and latest describe the last STORED row (index + 1 rows stored).
 *  (3) A run advances in slices of at most SLICE_WALL seconds and re-queues
 *      itself, so many sessions share few workers; with rtf > 0 the next
 *      slice is queued for when real time has caught up (no sleeping).
 *  (4) failed is sticky: ts_advance's error is sticky too, and a failed
 *      session accepts no step or run (409).
 *  (5) A deleted session's rows are removed by whoever releases it last
 *      from busy (the worker) or at once when idle (the handler); it is
 *      marked deleted in the store first (no mark, no delete), so the
 *      DELETE's answer holds if the daemon dies before the rows go (db.c
 *      purges it at the next start).
 *  (6) A batch the store refuses (a full disk) rolls the state back to the
 *      last stored row: the session is paused there, not failed, and goes
 *      on once the store takes rows again (roll_back_to_store).
 */
#define _GNU_SOURCE
#include "session.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../api/config_json.h"
#include "../api/problem.h"
#include "../api/session_json.h"
#include "db.h"
#include "operations.h"
#include "pool.h"

#define BATCH_ROWS 256  /* rows per database transaction during a run */
#define SLICE_WALL 0.05 /* wall seconds a run may hold a worker before re-queueing */
#define PACE_AHEAD                                                                                 \
    0.02 /* a paced run yields once it is this far ahead of real time [s]                          \
            (so a batch holds >= 20 ms of samples, not one row) */
#define PACE_POLL                                                                                  \
    0.2 /* a paced run waiting for its next row looks at cancel, shutdown and                      \
           --max-run-wall at least this often [s] */

typedef struct tsd_registry {
    pthread_mutex_t mu;
    tsd_session **v; /* in seq order */
    int n, cap;
    int reserved; /* places taken by creates in progress (n + reserved <= --max-sessions) */
    long next_seq;
} tsd_registry;

static const char *const status_names[TSD_NSTATUS] = {"created", "running", "paused",
                                                      "done",    "failed",  "interrupted"};

const char *tsd_status_name(tsd_status st)
{
    return (st >= 0 && st < TSD_NSTATUS) ? status_names[st] : "unknown";
}

/* A stored status by name; one this build does not know is read as failed,
 * with why in error (n bytes). */
static tsd_status status_from_name(const char *s, char *error, size_t n)
{
    for (int i = 0; i < TSD_NSTATUS; i++)
        if (strcmp(status_names[i], s) == 0) return (tsd_status)i;
    snprintf(error, n,
             "its stored status '%.40s' is not one this build knows (the store was written by "
             "another build or changed outside the daemon)",
             s);
    return TSD_FAILED;
}

/* Best-effort store writes. A status or a removal the store refuses is
 * logged (db.c) and counted (/metrics tanksimd_store_writes_refused_total),
 * and the session goes on as it is in memory; what each caller relies on
 * when the write fails is said where it is called. */
static void store_status(tsd_server *srv, long seq, tsd_status st, const char *error)
{
    if (tsd_db_session_status(srv->db, seq, tsd_status_name(st), error) != 0)
        atomic_fetch_add(&srv->metrics.store_writes_refused, 1);
}

static void store_delete(tsd_server *srv, long seq)
{
    if (tsd_db_session_delete(srv->db, seq) != 0)
        atomic_fetch_add(&srv->metrics.store_writes_refused, 1);
}

/* ---- lifetime ---------------------------------------------------------------- */

static void session_free(tsd_session *s)
{
    ts_data_free(s->d);
    ts_model_free(s->m);
    json_decref(s->config);
    free(s->batch);
    free(s->snapshot);
    free(s->latest);
    tsd_channels_free(&s->ch);
    pthread_mutex_destroy(&s->mu);
    pthread_mutex_destroy(&s->build_mu);
    free(s);
}

void tsd_session_put(tsd_session *s)
{
    if (!s) return;
    pthread_mutex_lock(&s->mu);
    int last = --s->refs == 0;
    pthread_mutex_unlock(&s->mu);
    if (last) session_free(s);
}

void tsd_session_hold(tsd_session *s)
{
    pthread_mutex_lock(&s->mu);
    s->refs++;
    pthread_mutex_unlock(&s->mu);
}

/* A session around a resolved config (steals resolved), without a model. */
static tsd_session *session_shell(tsd_server *srv, json_t *resolved, ts_err *err)
{
    tsd_session *s = calloc(1, sizeof *s);
    if (!s) {
        ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
        json_decref(resolved);
        return NULL;
    }
    pthread_mutex_init(&s->mu, NULL);
    pthread_mutex_init(&s->build_mu, NULL);
    s->srv = srv;
    s->refs = 1;
    s->config = resolved;
    s->index = 0;
    return s;
}

/* Allocate a session around a resolved config (steals resolved); builds model
 * and data when it can (m stays NULL and err is filled when it cannot). cfg is
 * resolved already read (NULL: read it here). */
static tsd_session *session_alloc(tsd_server *srv, json_t *resolved, const ts_config *cfg,
                                  ts_err *err)
{
    tsd_session *s = session_shell(srv, resolved, err);
    if (!s) return NULL;
    ts_config own;
    ts_err_clear(err);
    if (!cfg) {
        if (tsa_config_load(resolved, &own, NULL, NULL, err) != TS_OK) return s;
        cfg = &own;
    }
    s->m = ts_model_make(cfg, err);
    if (!s->m) return s;
    s->d = ts_data_make(s->m, err);
    s->nch = ts_model_nchannel(s->m);
    s->batch_cap = BATCH_ROWS;
    s->batch = calloc((size_t)s->batch_cap * (size_t)s->nch, sizeof *s->batch);
    s->latest = calloc((size_t)s->nch, sizeof *s->latest);
    s->snapshot_size = ts_state_size(s->m);
    s->snapshot = malloc(s->snapshot_size ? s->snapshot_size : 1);
    int chok = tsd_channels_from_model(&s->ch, s->m) == 0;
    if (!s->d || !s->batch || !s->latest || !s->snapshot || !chok) {
        if (s->d) ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
        ts_data_free(s->d);
        s->d = NULL;
        ts_model_free(s->m);
        s->m = NULL;
        tsd_channels_free(&s->ch);
        s->nch = 0;
    }
    return s;
}

/* ---- registry ---------------------------------------------------------------- */

static int registry_add(tsd_registry *g, tsd_session *s)
{
    if (g->n == g->cap) {
        int cap = g->cap ? 2 * g->cap : 64;
        tsd_session **nv = realloc(g->v, sizeof *nv * (size_t)cap);
        if (!nv) return -1;
        g->v = nv;
        g->cap = cap;
    }
    /* Keep seq order (listing pages on seq): concurrent creates draw their
     * seq before storing and may get here in another order. */
    int i = g->n;
    while (i > 0 && g->v[i - 1]->seq > s->seq)
        i--;
    memmove(&g->v[i + 1], &g->v[i], sizeof g->v[0] * (size_t)(g->n - i));
    g->v[i] = s;
    g->n++;
    return 0;
}

/* Store row 0 and the state at it (a new session, or a stored one whose
 * creation was cut between its record and its first row). 0 on success. */
static int store_first_row(tsd_session *s)
{
    ts_err err;
    if (ts_state_save(s->m, s->d, s->snapshot, s->snapshot_size, &err) != TS_OK) {
        fprintf(stderr, "tanksimd: session %s: cannot save its state: %s\n", s->id, err.msg);
        return -1;
    }
    return tsd_db_append(s->srv->db, s->seq, 0, 1, s->nch, ts_latest(s->d), s->snapshot,
                         s->snapshot_size, ts_time(s->d), 0, tsd_status_name(s->status), NULL);
}

/* Read s's last stored row into s->index, s->t and s->latest (tsd_db_last_row;
 * its return). A damaged row (-2) still gives index and time; no latest values
 * are shown then, and why (n bytes, a string) gets the reason appended. */
static int read_last_row(tsd_session *s, char *why, size_t n)
{
    long last = -1;
    double t_last = 0.0;
    int lr = tsd_db_last_row(s->srv->db, s->seq, &last, &t_last, s->nch ? s->latest : NULL, s->nch);
    s->index = last; /* -1 and 0 s when the store cannot say */
    s->t = t_last;
    if (lr == -2) {
        s->latest_damaged = 1;
        size_t k = strlen(why);
        snprintf(why + k, n - k,
                 "%sits last stored row (%ld) is damaged (not %d channels wide; the store was "
                 "changed outside the daemon)",
                 k ? "; " : "", last, s->nch);
    }
    return lr;
}

/* Bring a loaded session to its last stored row: restore the latest state
 * snapshot (invariant 2: it is the state at the last stored row). 0 on
 * success. -1 with the reason in why when it cannot: then NOTHING is deleted
 * (the snapshot may be from a build with another state layout, and a build
 * that reads it may come back), d is left unusable, and t, index and latest
 * describe the last stored row, so the rows stay readable. */
static int restore_stored(tsd_session *s, char *why, size_t n)
{
    tsd_db *db = s->srv->db;
    ts_err err;
    void *blob = NULL;
    size_t size = 0;
    long sidx = -1;
    int rc = -1;
    why[0] = '\0';
    int lr = read_last_row(s, why, n); /* the stored rows' end, kept on failure */
    long last = s->index;
    if (lr != 0 || tsd_db_state(db, s->seq, &blob, &size, &sidx) != 0) {
        if (lr != -2) /* -2: read_last_row said why */
            snprintf(why, n, "its stored rows or state cannot be read (see the daemon log)");
    } else if (ts_reset(s->m, s->d, &err) != TS_OK)
        snprintf(why, n, "its model cannot be reset: %.300s", err.msg);
    else if (!blob && last > 0)
        snprintf(why, n, "no stored state for its %ld stored rows", last + 1);
    else if (blob && ts_state_restore(s->m, s->d, blob, size, &err) != TS_OK)
        snprintf(why, n, "its stored state cannot be restored: %.300s", err.msg);
    else if (!blob && last < 0 && store_first_row(s) != 0)
        snprintf(why, n, "its first row cannot be stored (see the daemon log)");
    else if (last >= 0 ? ts_sample_index(s->d) > last : blob != NULL)
        snprintf(why, n, "its stored state is at row %ld but its stored rows end at %ld",
                 ts_sample_index(s->d), last);
    else if (last > ts_sample_index(s->d))
        /* rows past the state: the daemon stores each batch with its state in
         * one transaction (invariant 2), so the store was changed outside it
         * (a snapshot removed) or damaged. Those rows were deleted here once,
         * on the first read; they are kept now, and the session cannot go on. */
        snprintf(why, n,
                 "its stored state is at row %ld but its stored rows go on to %ld (the store was "
                 "changed outside the daemon); the rows are kept and readable",
                 ts_sample_index(s->d), last);
    else
        rc = 0;
    free(blob);
    if (rc != 0) return -1;
    s->t = ts_time(s->d);
    s->index = ts_sample_index(s->d);
    memcpy(s->latest, ts_latest(s->d), sizeof(double) * (size_t)s->nch);
    return 0;
}

/* Recovery of one stored session (tsd_db_sessions callback). A session that
 * cannot be brought back (config no longer builds a model, state cannot be
 * restored) is listed as failed with the reason, in memory only: its stored
 * rows, state and status are left as they are, so nothing is lost and a
 * build that can read them continues it. */
typedef struct {
    tsd_server *srv;
    int loaded, interrupted, unrestored, deferred;
} load_ctx;

/* Serve s's rows with the channel table stored with it (steals c) in place of
 * its model's: s is unrestored, so it is never advanced and its batch (laid
 * out for the model) is never used. Then read its last row. */
static void adopt_stored_channels(tsd_session *s, tsd_channels *c)
{
    double *latest = calloc((size_t)c->view.n, sizeof *latest);
    if (!latest) {
        fprintf(stderr, "tanksimd: session %s: out of memory for its channels\n", s->id);
        tsd_channels_free(c);
        tsd_channels_free(&s->ch);
        s->nch = 0;
        return;
    }
    free(s->latest);
    s->latest = latest;
    tsd_channels_free(&s->ch);
    s->ch = *c;
    memset(c, 0, sizeof *c);
    s->nch = s->ch.view.n;
}

static void load_session(void *ud, long seq, const char *id, double created, const char *preset,
                         const char *config_json, const char *status, const char *error,
                         const char *channels_json)
{
    load_ctx *lc = ud;
    tsd_server *srv = lc->srv;
    /* First: even a session that is not loaded keeps its seq, so a new
     * session can never be stored under it (nor clean up "its" rows). */
    if (seq >= srv->reg->next_seq) srv->reg->next_seq = seq + 1;
    if (strcmp(status, "deleted") == 0) return; /* deleted while it ran: db.c removes it */
    json_error_t je;
    json_t *resolved = json_loads(config_json, 0, &je);
    ts_err err;
    ts_err_clear(&err);
    /* The channel list stored with it (none: a store older than that column;
     * then the model's, as before). */
    tsd_channels stored = {0};
    char cwhy[160] = "";
    int have = channels_json[0] && tsd_channels_parse(&stored, channels_json, cwhy, sizeof cwhy) == 0;
    if (channels_json[0] && !have)
        fprintf(stderr, "tanksimd: session %s: %s; its model's channels are used\n", id, cwhy);
    /* With its channel table its rows are served without the model: the
     * model is built and the state restored at its first use (materialize),
     * so start-up does not grow with the number of stored sessions (a
     * crank-angle engine's idle search alone takes ~0.4 s). */
    int defer = resolved && have;
    /* a config that is not JSON builds no model (not the default one: its
     * rows are another model's) */
    tsd_session *s = defer      ? session_shell(srv, resolved, &err)
                     : resolved ? session_alloc(srv, resolved, NULL, &err)
                                : session_shell(srv, json_object(), &err);
    if (!s) {
        fprintf(stderr, "tanksimd: session %s not loaded: %s (its stored data are kept)\n", id,
                err.msg);
        tsd_channels_free(&stored);
        return;
    }
    snprintf(s->id, sizeof s->id, "%s", id);
    snprintf(s->preset, sizeof s->preset, "%s", preset);
    s->seq = seq;
    s->created = created;
    snprintf(s->error, sizeof s->error, "%s", error);
    s->status = status_from_name(status, s->error, sizeof s->error);
    if (s->status == TSD_RUNNING) {
        s->status = TSD_INTERRUPTED; /* the daemon died during the run */
        snprintf(s->error, sizeof s->error,
                 "the daemon stopped (killed or crashed) during a run of this session; run it "
                 "again to go on from its last stored row");
        lc->interrupted++;
        /* refused: the next start finds it running and marks it again */
        store_status(srv, seq, s->status, s->error);
    }
    char why[TS_ERR_MSG_LEN] = "";
    int ok;
    if (defer) {
        adopt_stored_channels(s, &stored);
        /* a damaged last row: failed now, not at its first use */
        ok = read_last_row(s, why, sizeof why) != -2;
        if (ok) atomic_store(&s->deferred, 1);
    } else if (!s->m || (have && !tsd_channels_match(&stored, s->m))) {
        if (!s->m && resolved)
            snprintf(why, sizeof why, "its model cannot be rebuilt: %.300s", err.msg);
        else if (!s->m)
            snprintf(why, sizeof why,
                     "its model cannot be rebuilt: the stored config is not JSON (%.160s)",
                     je.text);
        else
            snprintf(why, sizeof why,
                     "its stored rows have other channels than this build's model (%d stored, "
                     "%d in the model, or other names, units or sample rate)",
                     stored.view.n, ts_model_nchannel(s->m));
        if (have) adopt_stored_channels(s, &stored); /* rows readable without the model */
        ok = 0;
        read_last_row(s, why, sizeof why);
    } else {
        ok = restore_stored(s, why, sizeof why) == 0;
    }
    tsd_channels_free(&stored);
    if (!ok) {
        s->status = TSD_FAILED;
        s->unrestored = 1;
        snprintf(s->error, sizeof s->error, "%s", why);
        lc->unrestored++;
        fprintf(stderr,
                "tanksimd: session %s cannot be advanced: %s; its %ld stored rows are kept\n", id,
                why, s->index + 1);
    }
    if (registry_add(srv->reg, s) != 0) {
        fprintf(stderr, "tanksimd: session %s not loaded: out of memory (its stored data are "
                        "kept)\n", id);
        session_free(s);
        return;
    }
    lc->loaded++;
    if (atomic_load(&s->deferred)) lc->deferred++;
}

/* Build a deferred session's model and restore its stored state (the part of
 * load_session put off to its first use; session.h). The model is built and restored on
 * a private session t, then moved into s under s->mu, so listings running
 * meanwhile see the stored table or the model's, never a mix. On failure s
 * stays on its stored table, unrestored and failed with the reason, as at
 * start-up. */
int tsd_session_deferred(tsd_session *s)
{
    return atomic_load(&s->deferred);
}

void tsd_session_build(tsd_session *s)
{
    if (!atomic_load(&s->deferred)) return;
    pthread_mutex_lock(&s->build_mu);
    if (!atomic_load(&s->deferred)) {
        pthread_mutex_unlock(&s->build_mu);
        return;
    }
    pthread_mutex_lock(&s->mu);
    int deleted = s->deleted;
    if (deleted) { /* a request that waited for the build: no model, so no step/frames */
        s->unrestored = 1;
        snprintf(s->error, sizeof s->error, "the session was deleted");
    }
    pthread_mutex_unlock(&s->mu);
    if (deleted) { /* its rows are gone: restoring would store a row 0 for nobody */
        atomic_store(&s->deferred, 0);
        pthread_mutex_unlock(&s->build_mu);
        return;
    }
    char why[TS_ERR_MSG_LEN] = "";
    ts_err err;
    ts_err_clear(&err);
    tsd_session *t = session_alloc(s->srv, json_incref(s->config), NULL, &err);
    int ok = 0;
    if (!t || !t->m)
        snprintf(why, sizeof why, "its model cannot be rebuilt: %.300s", err.msg);
    else if (!tsd_channels_match(&s->ch, t->m))
        snprintf(why, sizeof why,
                 "its stored rows have other channels than this build's model (%d stored, %d "
                 "in the model, or other names, units or sample rate)",
                 s->ch.view.n, ts_model_nchannel(t->m));
    else {
        t->seq = s->seq;
        memcpy(t->id, s->id, sizeof t->id);
        ok = restore_stored(t, why, sizeof why) == 0;
    }
    pthread_mutex_lock(&s->mu);
    if (ok) { /* trade places: s gets the model's, t the stored table (freed with t) */
        tsd_session keep = *s;
        s->m = t->m, t->m = keep.m;
        s->d = t->d, t->d = keep.d;
        s->nch = t->nch, t->nch = keep.nch;
        s->ch = t->ch, t->ch = keep.ch;
        s->batch = t->batch, t->batch = keep.batch;
        s->batch_cap = t->batch_cap, t->batch_cap = keep.batch_cap;
        s->snapshot = t->snapshot, t->snapshot = keep.snapshot;
        s->snapshot_size = t->snapshot_size, t->snapshot_size = keep.snapshot_size;
        s->latest = t->latest, t->latest = keep.latest;
        s->t = t->t;
        s->index = t->index;
    } else {
        s->status = TSD_FAILED;
        s->unrestored = 1;
        s->latest_damaged = t && t->latest_damaged;
        snprintf(s->error, sizeof s->error, "%s", why);
    }
    long rows = s->index + 1;
    pthread_mutex_unlock(&s->mu);
    if (!ok)
        fprintf(stderr,
                "tanksimd: session %s cannot be advanced: %s; its %ld stored rows are kept\n",
                s->id, why, rows);
    if (t) session_free(t);
    atomic_store(&s->deferred, 0);
    pthread_mutex_unlock(&s->build_mu);
}

int tsd_sessions_init(tsd_server *srv, char *err, size_t errlen)
{
    srv->reg = calloc(1, sizeof *srv->reg);
    if (!srv->reg) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    pthread_mutex_init(&srv->reg->mu, NULL);
    srv->reg->next_seq = 1;
    load_ctx lc = {srv, 0, 0, 0, 0};
    if (tsd_db_sessions(srv->db, load_session, &lc) != 0) {
        snprintf(err, errlen, "cannot read stored sessions");
        return -1;
    }
    if (lc.loaded)
        fprintf(stderr,
                "tanksimd: %d stored sessions loaded (%d to be rebuilt at first use), %d "
                "interrupted runs, %d cannot be advanced\n",
                lc.loaded, lc.deferred, lc.interrupted, lc.unrestored);
    return 0;
}

void tsd_sessions_free(tsd_server *srv)
{
    tsd_registry *g = srv->reg;
    if (!g) return;
    for (int i = 0; i < g->n; i++)
        tsd_session_put(g->v[i]);
    free(g->v);
    pthread_mutex_destroy(&g->mu);
    free(g);
    srv->reg = NULL;
}

void tsd_sessions_count(tsd_server *srv, long counts[TSD_NSTATUS])
{
    for (int i = 0; i < TSD_NSTATUS; i++)
        counts[i] = 0;
    pthread_mutex_lock(&srv->reg->mu);
    for (int i = 0; i < srv->reg->n; i++) {
        tsd_session *s = srv->reg->v[i];
        pthread_mutex_lock(&s->mu);
        counts[s->status]++;
        pthread_mutex_unlock(&s->mu);
    }
    pthread_mutex_unlock(&srv->reg->mu);
}

/* Index of session id in the registry or -1. Caller holds g->mu. */
static int registry_find_locked(const tsd_registry *g, const char *id)
{
    for (int i = 0; i < g->n; i++)
        if (strcmp(g->v[i]->id, id) == 0) return i;
    return -1;
}

tsd_session *tsd_session_get(tsd_server *srv, const char *id)
{
    tsd_session *found = NULL;
    pthread_mutex_lock(&srv->reg->mu);
    int i = registry_find_locked(srv->reg, id);
    if (i >= 0) {
        found = srv->reg->v[i];
        tsd_session_hold(found);
    }
    pthread_mutex_unlock(&srv->reg->mu);
    return found;
}

/* ---- streams ---------------------------------------------------------------- */

/* Resume every waiting stream. Caller holds s->mu. */
static void wake_locked(tsd_session *s)
{
    for (tsd_waiter *w = s->waiters; w; w = w->next) {
        w->linked = 0;
        MHD_resume_connection(w->conn);
    }
    s->waiters = NULL;
}

void tsd_sessions_wake_all(tsd_server *srv)
{
    pthread_mutex_lock(&srv->reg->mu);
    for (int i = 0; i < srv->reg->n; i++) {
        tsd_session *s = srv->reg->v[i];
        pthread_mutex_lock(&s->mu);
        wake_locked(s);
        pthread_mutex_unlock(&s->mu);
    }
    pthread_mutex_unlock(&srv->reg->mu);
}

int tsd_session_await(tsd_session *s, long next, tsd_waiter *w)
{
    int r;
    pthread_mutex_lock(&s->mu);
    if (next <= s->index)
        r = 1;
    else if (s->status != TSD_RUNNING || s->deleted || atomic_load(&s->srv->stopping))
        r = -1;
    else {
        w->next = s->waiters;
        w->linked = 1;
        s->waiters = w;
        MHD_suspend_connection(w->conn);
        r = 0;
    }
    pthread_mutex_unlock(&s->mu);
    return r;
}

void tsd_session_unwait(tsd_session *s, tsd_waiter *w)
{
    pthread_mutex_lock(&s->mu);
    if (w->linked) {
        for (tsd_waiter **p = &s->waiters; *p; p = &(*p)->next)
            if (*p == w) {
                *p = w->next;
                break;
            }
        w->linked = 0;
    }
    pthread_mutex_unlock(&s->mu);
}

/* ---- create / delete / describe ------------------------------------------------ */

/* The part of tsd_session_create after a registry place was reserved: build,
 * store row 0, and add to the registry (taking the reservation over). */
static ts_rc create_reserved(tsd_server *srv, const json_t *doc, json_t *resolved,
                             const ts_config *cfg, tsd_session **out, ts_err *err)
{
    tsd_session *s = session_alloc(srv, resolved, cfg, err);
    if (!s) return err->code;
    ts_rc rc;
    if (!s->m) {
        rc = err->code != TS_OK ? err->code : TS_ERR_INTERNAL;
        session_free(s);
        return rc;
    }
    rc = ts_reset(s->m, s->d, err);
    if (rc != TS_OK) {
        session_free(s);
        return rc;
    }
    const json_t *preset = json_object_get(doc, "preset");
    snprintf(s->preset, sizeof s->preset, "%s",
             json_is_string(preset) ? json_string_value(preset) : "");
    tsd_random_id(s->id, sizeof s->id, "s");
    s->created = tsd_unix_now();
    s->status = TSD_CREATED;
    s->t = 0.0;
    s->index = 0;
    memcpy(s->latest, ts_latest(s->d), sizeof(double) * (size_t)s->nch);

    pthread_mutex_lock(&srv->reg->mu);
    s->seq = srv->reg->next_seq++;
    pthread_mutex_unlock(&srv->reg->mu);
    char *cfg_text = json_dumps(resolved, JSON_COMPACT | JSON_REAL_PRECISION(17));
    char *ch_text = tsd_channels_dump(&s->ch.view);
    int dbrc = cfg_text && ch_text ? tsd_db_session_insert(srv->db, s->seq, s->id, s->created,
                                                           s->preset, cfg_text, s->nch, ch_text,
                                                           "created")
                                   : -1;
    free(cfg_text);
    free(ch_text);
    int inserted = dbrc == 0;
    if (dbrc == 0) dbrc = store_first_row(s);
    if (dbrc != 0) {
        if (inserted) store_delete(srv, s->seq); /* only what this create stored */
        session_free(s);
        return tsd_err_store(srv, err, dbrc, "cannot store the session");
    }
    pthread_mutex_lock(&srv->reg->mu);
    int ok = registry_add(srv->reg, s) == 0;
    if (ok) srv->reg->reserved--; /* the place is taken now */
    pthread_mutex_unlock(&srv->reg->mu);
    if (!ok) {
        store_delete(srv, s->seq);
        session_free(s);
        return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
    }
    atomic_fetch_add(&srv->metrics.sessions_created, 1);
    atomic_fetch_add(&srv->metrics.samples_stored, 1);
    tsd_session_hold(s);
    *out = s;
    return TS_OK;
}

/* A refusal of the config at ptr: listed in errors (may be NULL) and in err. */
static ts_rc refuse(json_t *errors, ts_err *err, const char *ptr, const char *msg)
{
    if (errors) json_array_append_new(errors, json_pack("{s:s,s:s}", "pointer", ptr, "message", msg));
    return ts_err_set(err, TS_ERR_PARAM, ptr, "%s", msg);
}

/* Unless started with --client-files yes, the daemon opens no file a client
 * names: a profile terrain (/terrain/profile_csv) and a bump course that is
 * not one of the shipped ones embedded in the binary (which tsa_config_load
 * has already turned into inline bumps) would make sim/terrain.c read a path
 * of the client's choosing on this machine. */
static ts_rc refuse_client_files(const ts_config *cfg, json_t *errors, ts_err *err)
{
    const ts_terrain_config *t = &cfg->terrain;
    const char *ptr = NULL;
    char msg[TS_ERR_MSG_LEN];
    if (t->kind == TS_TERRAIN_PROFILE) {
        ptr = "/terrain/profile_csv";
        snprintf(msg, sizeof msg,
                 "%s: this daemon reads no file named by a client (started without "
                 "--client-files yes); give the ground inline as bumps (/terrain/bump_start, "
                 "/terrain/bump_height, /terrain/bump_length) or use a shipped course",
                 ptr);
    } else if (t->kind == TS_TERRAIN_BUMPS && t->bump_n == 0) { /* a course read from disk */
        if (!tsa_course_dir_is_shipped(t)) {
            ptr = "/terrain/course_dir";
            snprintf(msg, sizeof msg,
                     "%s: this daemon reads no course file from a directory a client names "
                     "(started without --client-files yes); leave it out for the shipped "
                     "courses, or give the bumps inline (/terrain/bump_start, "
                     "/terrain/bump_height, /terrain/bump_length)",
                     ptr);
        } else {
            /* the shipped courses, by name (the review typed one blind) */
            char names[128] = "";
            json_t *shipped = tsa_shipped_courses();
            size_t i;
            json_t *name;
            json_array_foreach(shipped, i, name)
            {
                size_t used = strlen(names);
                snprintf(names + used, sizeof names - used, "%s'%s'", i ? ", " : "",
                         json_string_value(name));
            }
            json_decref(shipped);
            ptr = "/terrain/course";
            snprintf(msg, sizeof msg,
                     "%s: no shipped course named '%.64s' (shipped: %.64s), and this daemon reads "
                     "no course file named by a client (started without --client-files yes); "
                     "give the bumps inline (/terrain/bump_start, /terrain/bump_height, "
                     "/terrain/bump_length)",
                     ptr, t->course, names);
        }
    }
    return ptr ? refuse(errors, err, ptr, msg) : TS_OK;
}

/* Every row a session produces is stored: a config whose run would store more
 * than --max-rows (run.duration 3600 s at 20 kHz: 72 million rows, ~24 GB)
 * is refused before it fills the disk. */
static ts_rc check_rows(const tsd_server *srv, const ts_config *cfg, json_t *errors, ts_err *err)
{
    double rows = (double)ts_grid_row(cfg->run.duration, 1.0 / cfg->run.sample_rate) + 1.0;
    if (srv->opt.max_rows <= 0 || rows <= (double)srv->opt.max_rows) return TS_OK;
    const char *ptr = "/run/duration";
    char msg[TS_ERR_MSG_LEN];
    snprintf(msg, sizeof msg,
             "%s: %g s at run.sample_rate %g Hz is %.0f stored rows, more than this daemon "
             "keeps per session (--max-rows %ld); shorten /run/duration, lower "
             "/run/sample_rate, or start tanksimd with a larger --max-rows",
             ptr, cfg->run.duration, cfg->run.sample_rate, rows, srv->opt.max_rows);
    return refuse(errors, err, ptr, msg);
}

ts_rc tsd_session_create(tsd_server *srv, const json_t *doc, tsd_session **out, json_t *errors,
                         ts_err *err)
{
    *out = NULL;
    ts_config cfg;
    json_t *resolved = NULL;
    ts_rc rc = tsa_config_load(doc, &cfg, &resolved, errors, err);
    if (rc == TS_OK && tsa_config_runnable(doc, "session", err) != TS_OK) {
        rc = err->code;
        if (errors)
            json_array_append_new(errors, json_pack("{s:s,s:s}", "pointer", err->pointer,
                                                    "message", err->msg));
    }
    if (rc == TS_OK && !srv->opt.client_files) rc = refuse_client_files(&cfg, errors, err);
    if (rc == TS_OK) rc = check_rows(srv, &cfg, errors, err);
    if (rc != TS_OK) {
        json_decref(resolved);
        return rc;
    }
    /* Check the cap and reserve a place in one lock section: creates in
     * progress count, so concurrent creates cannot pass the cap together. */
    tsd_registry *g = srv->reg;
    pthread_mutex_lock(&g->mu);
    int full = g->n + g->reserved >= srv->opt.max_sessions;
    if (!full) g->reserved++;
    pthread_mutex_unlock(&g->mu);
    if (full) {
        json_decref(resolved);
        return ts_err_set(err, TS_ERR_LIMIT, NULL,
                          "the daemon holds its limit of %d sessions (--max-sessions, counting "
                          "creates in progress); delete some first",
                          srv->opt.max_sessions);
    }
    rc = create_reserved(srv, doc, resolved, &cfg, out, err);
    if (rc != TS_OK) {
        pthread_mutex_lock(&g->mu);
        g->reserved--;
        pthread_mutex_unlock(&g->mu);
    }
    return rc;
}

int tsd_session_is_deleted(tsd_session *s)
{
    pthread_mutex_lock(&s->mu);
    int deleted = s->deleted;
    pthread_mutex_unlock(&s->mu);
    return deleted;
}

ts_rc tsd_session_err_deleted(const tsd_session *s, ts_err *err)
{
    return ts_err_set(err, TS_ERR_NOTFOUND, NULL, "session %s was deleted", s->id);
}

ts_rc tsd_session_delete(tsd_session *s, ts_err *err)
{
    tsd_server *srv = s->srv;
    const char *id = s->id;
    /* build_mu: a first-use build in progress finishes before the rows go, and
     * one queued after finds the session deleted and stores nothing; two
     * DELETEs go one after the other. The store marks the session deleted
     * first, so the 204 holds through a crash (db.c purges marked sessions at
     * the next start); if it refuses even that, nothing is deleted. Not under
     * mu: the write may wait seconds for the store's lock, and the session
     * list waits for every session's mu. A step that starts meanwhile is
     * cancelled below; the mark stands against the status its end writes
     * (status<>'deleted'). The rows go after: now when idle, else by the
     * worker (invariant 5). */
    pthread_mutex_lock(&s->build_mu);
    ts_rc rc = TS_OK;
    if (tsd_session_is_deleted(s)) /* the DELETE before this one */
        rc = ts_err_set(err, TS_ERR_NOTFOUND, NULL, "no session '%s'", id);
    else if (tsd_db_session_status(srv->db, s->seq, "deleted", NULL) != 0)
        rc = ts_err_set(err, TS_ERR_IO, NULL,
                        "the store could not record the delete (see the daemon log); "
                        "session %s is kept",
                        id);
    if (rc != TS_OK) {
        pthread_mutex_unlock(&s->build_mu);
        return rc;
    }
    pthread_mutex_lock(&s->mu);
    s->deleted = 1;
    atomic_store(&s->cancel, 1);
    int idle = !s->busy;
    wake_locked(s);
    pthread_mutex_unlock(&s->mu);
    if (idle) /* if this fails, the mark has the next start purge the rows */
        store_delete(srv, s->seq);
    tsd_registry *g = srv->reg;
    pthread_mutex_lock(&g->mu);
    int i = registry_find_locked(g, s->id); /* there: only this, once, under build_mu, removes */
    assert(i >= 0 && g->v[i] == s);
    memmove(&g->v[i], &g->v[i + 1], sizeof g->v[0] * (size_t)(g->n - i - 1));
    g->n--;
    pthread_mutex_unlock(&g->mu);
    pthread_mutex_unlock(&s->build_mu);
    tsd_session_put(s); /* the registry's reference (not the last: the caller's) */
    return TS_OK;
}

static json_t *json_locked(tsd_session *s, int summary)
{
    /* The rows' table (channels.h) gives channels, latest and sample_rate;
     * one adopted from the store means the model (if any) is not the rows'
     * (no kind or duration then). */
    int stored_table = s->ch.doc != NULL;
    tsa_session_view v = {
        .id = s->id,
        /* deleted: seen only by whoever still holds it (a stream's end event) */
        .status = s->deleted ? "deleted" : tsd_status_name(s->status),
        .preset = s->preset,
        .created = s->created,
        .t = s->t,
        .index = s->index > 0 ? s->index : 0,
        .persisted = s->index + 1, /* -1: a stored session without rows */
        .config = s->config,
        .m = stored_table ? NULL : s->m,
        .ch = s->nch ? &s->ch.view : NULL,
        .latest =
            (stored_table ? s->index >= 0 : s->m != NULL) && !s->latest_damaged ? s->latest : NULL,
        .error = s->error,
        .operation = s->op_id,
        .integrators = stored_table ? NULL : s->integrators,
        .nintegrators = stored_table ? 0 : s->nintegrators,
    };
    if (atomic_load(&s->deferred)) { /* the config's: the model is built at first use */
        json_t *run = json_object_get(s->config, "run");
        v.kind = json_string_value(json_object_get(run, "kind"));
        v.duration = json_number_value(json_object_get(run, "duration"));
    }
    return tsa_session_json(&v, summary);
}

json_t *tsd_session_json(tsd_session *s, int summary)
{
    pthread_mutex_lock(&s->mu);
    json_t *j = json_locked(s, summary);
    pthread_mutex_unlock(&s->mu);
    return j;
}

json_t *tsd_session_list(tsd_server *srv, long page_size, long after_seq)
{
    json_t *arr = json_array();
    long last = -1;
    int more = 0;
    pthread_mutex_lock(&srv->reg->mu);
    for (int i = 0; i < srv->reg->n; i++) {
        tsd_session *s = srv->reg->v[i];
        if (s->seq <= after_seq) continue;
        if ((long)json_array_size(arr) == page_size) {
            more = 1;
            break;
        }
        json_array_append_new(arr, tsd_session_json(s, 1));
        last = s->seq;
    }
    pthread_mutex_unlock(&srv->reg->mu);
    json_t *o = json_pack("{s:o}", "sessions", arr);
    if (more) {
        char tok[32];
        snprintf(tok, sizeof tok, "%ld", last);
        json_object_set_new(o, "next_page_token", json_string(tok));
    }
    return o;
}

/* ---- advancing (worker side) ---------------------------------------------------- */

/* Store the batch with the snapshot at its last row (invariant 2), the
 * session's status and error with it, and publish the last row to readers.
 * Busy holder only. 0 on success, else tsd_db_append's code. */
static int flush(tsd_session *s, const char *status, const char *error)
{
    if (s->batch_n == 0) return 0;
    if (tsd_session_is_deleted(s)) {
        s->batch_n = 0;
        return 0;
    }
    ts_err err;
    const double *last = s->batch + (size_t)(s->batch_n - 1) * (size_t)s->nch;
    long idx = s->batch_first + s->batch_n - 1;
    int rc = ts_state_save(s->m, s->d, s->snapshot, s->snapshot_size, &err) == TS_OK ? 0 : -1;
    ts_integrator_stats ist[TS_MAX_INTEGRATORS];
    int nist = ts_integrator_stats_get(s->m, s->d, ist, TS_MAX_INTEGRATORS);
    if (rc == 0)
        rc = tsd_db_append(s->srv->db, s->seq, s->batch_first, s->batch_n, s->nch, s->batch,
                           s->snapshot, s->snapshot_size, last[0], idx, status, error);
    if (rc == 0) {
        atomic_fetch_add(&s->srv->metrics.samples_stored, s->batch_n);
        pthread_mutex_lock(&s->mu);
        s->t = last[0];
        s->index = idx;
        memcpy(s->latest, last, sizeof(double) * (size_t)s->nch);
        memcpy(s->integrators, ist, sizeof ist);
        s->nintegrators = nist;
        wake_locked(s);
        pthread_mutex_unlock(&s->mu);
    }
    s->batch_n = 0;
    return rc;
}

typedef enum { ADV_NONE, ADV_YIELD, ADV_PACE, ADV_CANCEL, ADV_STOP, ADV_IO, ADV_GONE } adv_reason;

typedef struct advance_ctx {
    tsd_session *s;
    const char *status; /* status stored with each batch */
    const char *error;  /* error stored with each batch: what a crash during it leaves */
    int store_rc;       /* the refused batch's tsd_db_append code (ADV_IO) */
    double slice_end;   /* monotonic deadline of this slice (0 = none) */
    double rtf;         /* real-time cap (0 = none) */
    double pace_t0;     /* simulated time at pace_wall0 */
    double pace_wall0;  /* monotonic time the run started */
    double until;       /* the run's end [s] */
    double resume_at;   /* when paced out: monotonic time to continue */
    struct MHD_Connection *client; /* a step's request: stop when it hangs up (NULL: run) */
    adv_reason reason;
} advance_ctx;

/* Pacing, after the row at simulated time t: the next row is computed only
 * when it is due, so a flush never publishes a row ahead of real time. 1 (and
 * a->resume_at set) when that row is not due yet at `now`; 0 when it is, when
 * there is no cap, or when t was the run's last row (nothing to wait for). */
static int pace_hold(advance_ctx *a, double t, double now)
{
    if (!(a->rtf > 0)) return 0;
    double dt = ts_model_sample_period(a->s->m), next = t + dt;
    if (next > a->until + 0.5 * dt) return 0;
    a->resume_at = a->pace_wall0 + (next - a->pace_t0) / a->rtf;
    return a->resume_at > now + PACE_AHEAD;
}

/* ts_sample_fn: batch the row; stop for cancel, shutdown, end of slice, pacing. */
static int on_sample(void *ud, long index, double t, const double *v, int n)
{
    advance_ctx *a = ud;
    tsd_session *s = a->s;
    if (s->batch_n == 0) s->batch_first = index;
    memcpy(s->batch + (size_t)s->batch_n * (size_t)s->nch, v, sizeof(double) * (size_t)n);
    s->batch_n++;
    if (s->batch_n == s->batch_cap && (a->store_rc = flush(s, a->status, a->error)) != 0) {
        a->reason = ADV_IO;
        return 1;
    }
    if (atomic_load(&s->cancel)) {
        a->reason = ADV_CANCEL;
        return 1;
    }
    if (atomic_load(&s->srv->stopping)) {
        a->reason = ADV_STOP;
        return 1;
    }
    if (a->client && index % 16 == 0 && tsd_client_gone(a->client)) {
        a->reason = ADV_GONE; /* nobody reads the step's answer: stop, paused here */
        return 1;
    }
    double now = a->slice_end > 0 || a->rtf > 0 ? tsd_now() : 0;
    if (pace_hold(a, t, now)) {
        a->reason = ADV_PACE;
        return 1;
    }
    if (a->slice_end > 0 && now >= a->slice_end) {
        a->reason = ADV_YIELD;
        return 1;
    }
    return 0;
}

static int at_end(const tsd_session *s, double t)
{
    return t >= ts_model_config(s->m)->run.duration - 0.5 * ts_model_sample_period(s->m);
}

static void add_sim_time(tsd_server *srv, double dt_sim, double dt_wall)
{
    atomic_fetch_add(&srv->metrics.sim_microseconds, (long long)llround(dt_sim * 1e6));
    atomic_fetch_add(&srv->metrics.wall_microseconds, (long long)llround(dt_wall * 1e6));
}

/* Give busy back when nothing was advanced (a refused run): status, error
 * and the database are left as they were. */
static void unbusy(tsd_session *s)
{
    pthread_mutex_lock(&s->mu);
    s->busy = 0;
    int deleted = s->deleted;
    wake_locked(s);
    pthread_mutex_unlock(&s->mu);
    if (deleted) store_delete(s->srv, s->seq); /* invariant 5 */
}

/* Release busy with the new status and error (NULL: none — the stored error
 * column is cleared the same way); store it; wake streams; delete if asked.
 *
 * The status is stored BEFORE busy is cleared, while this holder still
 * owns the session. It used to be stored after: in the gap a run could
 * acquire the session and store "running" (tsd_session_run), and this
 * late write then replaced it with the previous step's or run's "paused"
 * and its stale error — a daemon killed during that run would bring the
 * session back as paused with an old error instead of interrupted. Stored
 * first, the store's status follows the order of the busy holders: the
 * next holder's "running" can only come after ours. A DELETE meanwhile is
 * safe either way: its 'deleted' mark is never overwritten (db.c writes
 * WHERE status<>'deleted') and the rows go below (invariant 5). A status
 * write that fails (db.c logs it) leaves the stored one, as before. The
 * in-memory status changes after the write: a GET in between still shows
 * the holder's (e.g. "running") for the time of one UPDATE. */
static void release(tsd_session *s, tsd_status st, const char *error)
{
    if (!tsd_session_is_deleted(s)) store_status(s->srv, s->seq, st, error);
    pthread_mutex_lock(&s->mu);
    s->status = st;
    snprintf(s->error, sizeof s->error, "%s", error ? error : "");
    s->busy = 0;
    int deleted = s->deleted;
    wake_locked(s);
    pthread_mutex_unlock(&s->mu);
    if (deleted) store_delete(s->srv, s->seq); /* invariant 5 */
}

/* ---- step -------------------------------------------------------------------- */

/* The store refused a batch (a full disk, say), so d has run past the last
 * stored row (invariant 2). Put d back at the state stored with that row so
 * the session can go on from there once the store takes rows again: PAUSED,
 * or FAILED when even that state cannot be read. dbrc: the refused batch's
 * code (a full disk is said as such); err: what the caller says.
 * Busy holder only. */
static tsd_status roll_back_to_store(tsd_session *s, int dbrc, ts_err *err)
{
    void *blob = NULL;
    size_t size = 0;
    long sidx = -1;
    pthread_mutex_lock(&s->mu);
    long stored = s->index;
    double t = s->t;
    pthread_mutex_unlock(&s->mu);
    ts_err e;
    int ok = tsd_db_state(s->srv->db, s->seq, &blob, &size, &sidx) == 0 && blob &&
             sidx == stored && ts_state_restore(s->m, s->d, blob, size, &e) == TS_OK;
    free(blob);
    if (!ok) {
        ts_err_set(err, TS_ERR_IO, NULL,
                   "cannot store samples, nor return to the last stored row (see the daemon "
                   "log)");
        return TSD_FAILED;
    }
    tsd_err_store(s->srv, err, dbrc,
                  "cannot store samples (the session is back at its last stored row, t = %g s, "
                  "and goes on from there once the store takes rows again)",
                  t);
    return TSD_PAUSED;
}

typedef struct step_job_arg {
    tsd_session *s;
    struct MHD_Connection *client;
    double duration;
    json_t **result;
    ts_err *err;
    void (*done)(void *ud);
    void *ud;
} step_job_arg;

/* created | paused | interrupted -> paused | done | failed. */
static void step_job(void *arg)
{
    step_job_arg *j = arg;
    tsd_session *s = j->s;
    double t0 = ts_time(s->d), w0 = tsd_now();
    /* the batches go to the store as "paused", with the reason a crash during
     * the step would leave (release() clears it at the end; a run's "running"
     * says it for runs): so does the session in memory from the start (a GET
     * during a long step said "created" while the store, and the session
     * after a crash, said "paused") */
    char why[TS_ERR_MSG_LEN];
    snprintf(why, sizeof why,
             "the daemon stopped (killed or crashed) during a step of this session to t = %g s; "
             "it is paused at its last stored row: step again to go on",
             t0 + j->duration);
    advance_ctx a = {.s = s, .status = "paused", .error = why, .client = j->client};
    pthread_mutex_lock(&s->mu);
    s->status = TSD_PAUSED;
    pthread_mutex_unlock(&s->mu);
    ts_err err;
    ts_rc rc = ts_advance(s->m, s->d, t0 + j->duration, on_sample, &a, &err);
    int dbrc = a.reason == ADV_IO ? a.store_rc : flush(s, a.status, a.error);
    add_sim_time(s->srv, ts_time(s->d) - t0, tsd_now() - w0);
    atomic_fetch_add(&s->srv->metrics.steps, 1);
    if (rc == TS_ERR_CANCELLED && a.reason != ADV_IO) rc = TS_OK; /* deleted/shutdown: stop */
    tsd_status st = rc == TS_OK ? (at_end(s, ts_time(s->d)) ? TSD_DONE : TSD_PAUSED) : TSD_FAILED;
    if (dbrc != 0 && (rc == TS_OK || rc == TS_ERR_CANCELLED)) { /* invariant 6 */
        st = roll_back_to_store(s, dbrc, &err);
        rc = err.code;
    }
    double t = ts_time(s->d); /* while busy is held (invariant 1) */
    int cut = t < t0 + j->duration - 0.5 * ts_model_sample_period(s->m);
    release(s, st, rc == TS_OK ? NULL : err.msg);
    /* A step cut short is not a success: the reply says where it stopped
     * (the session itself is fine: paused there, rows up to it stored). */
    if (rc == TS_OK && cut && a.reason == ADV_STOP)
        rc = ts_err_set(&err, TSD_ERR_SHUTDOWN, NULL,
                        "the daemon began shutting down during the step: session %s stopped at "
                        "t = %g s (rows up to it are stored); step again once it is back",
                        s->id, t);
    else if (rc == TS_OK && cut && a.reason == ADV_CANCEL)
        rc = ts_err_set(&err, TS_ERR_NOTFOUND, NULL, "session %s was deleted during the step",
                        s->id);
    else if (rc == TS_OK && cut && a.reason == ADV_GONE) /* for the log; no one reads it */
        rc = ts_err_set(&err, TS_ERR_CANCELLED, NULL,
                        "the client closed the connection during the step: session %s stopped "
                        "at t = %g s (rows up to it are stored)",
                        s->id, t);
    if (rc == TS_OK) {
        pthread_mutex_lock(&s->mu);
        *j->result = json_pack("{s:s,s:s,s:f,s:I,s:o}", "id", s->id, "status",
                               tsd_status_name(s->status), "t", s->t, "index", (json_int_t)s->index,
                               "values", tsa_values_json(&s->ch.view, s->latest));
        pthread_mutex_unlock(&s->mu);
    } else {
        *j->err = err;
    }
    j->done(j->ud);
    tsd_session_put(s);
    free(j);
}

/* Take busy for a step or run: 409 unless created | paused | interrupted. */
static ts_rc acquire(tsd_session *s, ts_err *err)
{
    /* deleted before unrestored: a session deleted while its first-use build
     * was queued is marked unrestored too (tsd_session_build), but its rows
     * are gone — 404, as a step a DELETE cuts short, not a 409 saying the
     * rows are kept */
    pthread_mutex_lock(&s->mu);
    ts_rc rc = TS_OK;
    if (s->deleted) /* also when a DELETE landed after the router looked the session up */
        rc = tsd_session_err_deleted(s, err);
    else if (s->unrestored) /* immutable once the session is built */
        rc = ts_err_set(err, TS_ERR_STATE, NULL,
                        "session %s cannot be advanced by this daemon: %s (its stored rows "
                        "are kept and can be read)",
                        s->id, s->error);
    else if (s->busy)
        rc =
            ts_err_set(err, TS_ERR_STATE, NULL, "session %s is busy (%s)", s->id,
                       s->status == TSD_RUNNING ? "a run is in progress" : "a step is in progress");
    else if (s->status == TSD_DONE)
        rc = ts_err_set(err, TS_ERR_STATE, NULL,
                        "session %s is done: it reached run.duration = %g s", s->id,
                        ts_model_config(s->m)->run.duration);
    else if (s->status == TSD_FAILED)
        rc = ts_err_set(err, TS_ERR_STATE, NULL, "session %s failed earlier: %s", s->id, s->error);
    else {
        s->busy = 1;
        atomic_store(&s->cancel, 0);
    }
    pthread_mutex_unlock(&s->mu);
    return rc;
}

ts_rc tsd_session_step(tsd_session *s, struct MHD_Connection *client, double duration,
                       json_t **result, ts_err *err, void (*done)(void *ud), void *ud)
{
    ts_rc rc = acquire(s, err);
    if (rc != TS_OK) return rc;
    step_job_arg *j = calloc(1, sizeof *j);
    if (!j) {
        unbusy(s);
        return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
    }
    tsd_session_hold(s);
    *j = (step_job_arg){s, client, duration, result, err, done, ud};
    if (tsd_pool_submit(s->srv->pool, step_job, j, 0) != 0) {
        free(j);
        unbusy(s);
        tsd_session_put(s);
        return atomic_load(&s->srv->stopping)
                   ? tsd_err_shutdown(err)
                   : ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory queueing the step");
    }
    return TS_OK;
}

/* ---- run --------------------------------------------------------------------- */

typedef struct run_job_arg {
    tsd_session *s;
    tsd_op *op;
    double until, rtf;
    double t_start, wall_start;
} run_job_arg;

static void run_slice(void *arg);

/* running -> paused | done | failed | interrupted; finishes the operation. */
static void run_finish(run_job_arg *j, tsd_status st, ts_rc rc, const ts_err *err)
{
    tsd_session *s = j->s;
    tsd_server *srv = s->srv;
    double t = ts_time(s->d); /* read while busy is still held (invariant 1) */
    /* a cancel is the client's own doing; an interruption (the daemon shut
     * down) is said on the session too: its operation is not stored */
    release(s, st,
            rc == TS_OK || (rc == TS_ERR_CANCELLED && st != TSD_INTERRUPTED) ? NULL : err->msg);

    int r = st == TSD_DONE     ? 0
            : st == TSD_PAUSED ? (rc == TS_ERR_CANCELLED ? 2 : 1)
            : st == TSD_FAILED ? 3
                               : 4;
    atomic_fetch_add(&srv->metrics.runs_ended[r], 1);
    tsd_op_progress(srv, j->op, t);
    if (rc != TS_OK)
        tsd_op_fail(srv, j->op, err);
    else
        tsd_op_finish(srv, j->op, tsd_session_json(s, 1), NULL);
    tsd_session_put(s);
    free(j);
}

static void run_slice(void *arg)
{
    run_job_arg *j = arg;
    tsd_session *s = j->s;
    tsd_server *srv = s->srv;
    advance_ctx a = {.s = s,
                     .status = "running",
                     .slice_end = tsd_now() + SLICE_WALL,
                     .rtf = j->rtf,
                     .pace_t0 = j->t_start,
                     .pace_wall0 = j->wall_start,
                     .until = j->until};
    ts_err err;
    ts_err_clear(&err);
    double t0 = ts_time(s->d), w0 = tsd_now();
    ts_rc rc = TS_OK;
    if (atomic_load(&srv->stopping) || atomic_load(&s->cancel)) {
        a.reason = atomic_load(&s->cancel) ? ADV_CANCEL : ADV_STOP;
    } else if (pace_hold(&a, t0, w0)) { /* woken to poll before the next row is due */
        a.reason = ADV_PACE;
    } else {
        rc = ts_advance(s->m, s->d, j->until, on_sample, &a, &err);
    }
    int dbrc = a.reason == ADV_IO ? a.store_rc : flush(s, a.status, a.error);
    add_sim_time(srv, ts_time(s->d) - t0, tsd_now() - w0);
    tsd_op_progress(srv, j->op, ts_time(s->d));
    if (dbrc != 0) { /* invariant 6 */
        tsd_status st = roll_back_to_store(s, dbrc, &err);
        run_finish(j, st, err.code, &err);
        return;
    }
    if (rc != TS_OK && rc != TS_ERR_CANCELLED) {
        run_finish(j, TSD_FAILED, rc, &err);
        return;
    }
    if (a.reason == ADV_YIELD || a.reason == ADV_PACE) {
        if (srv->opt.max_run_wall > 0 && tsd_now() - j->wall_start >= srv->opt.max_run_wall) {
            ts_err_set(&err, TS_ERR_LIMIT, NULL,
                       "the run used its wall-clock budget of %g s (--max-run-wall) at t = %g s; "
                       "run the session again to continue",
                       srv->opt.max_run_wall, ts_time(s->d));
            run_finish(j, TSD_PAUSED, TS_ERR_LIMIT, &err);
            return;
        }
        /* paced: back when the next row is due, or sooner to look at
         * cancel, shutdown and the wall budget (a 1-Hz run capped at 0.02
         * waited 50 s for its next slice, deaf to a cancel) */
        double due = a.reason == ADV_PACE ? fmin(a.resume_at, tsd_now() + PACE_POLL) : 0;
        if (tsd_pool_submit(srv->pool, run_slice, j, due) == 0) return;
        a.reason = ADV_STOP;
    }
    if (a.reason == ADV_STOP || (a.reason == ADV_NONE && atomic_load(&srv->stopping) &&
                                 ts_time(s->d) < j->until - 0.5 * ts_model_sample_period(s->m))) {
        if (atomic_load(&srv->stopping)) /* the operation's error: 14 UNAVAILABLE */
            ts_err_set(&err, TSD_ERR_SHUTDOWN, NULL,
                       "the daemon shut down at t = %g s; run the session again to continue",
                       ts_time(s->d));
        else /* the next slice could not be queued: only a failed allocation does that */
            ts_err_set(&err, TS_ERR_CANCELLED, NULL,
                       "out of memory queueing the run's next slice at t = %g s; run the "
                       "session again to continue",
                       ts_time(s->d));
        run_finish(j, TSD_INTERRUPTED, TS_ERR_CANCELLED, &err);
        return;
    }
    if (a.reason == ADV_CANCEL) {
        ts_err_set(&err, TS_ERR_CANCELLED, NULL, "cancelled at t = %g s", ts_time(s->d));
        run_finish(j, TSD_PAUSED, TS_ERR_CANCELLED, &err);
        return;
    }
    run_finish(j, at_end(s, ts_time(s->d)) ? TSD_DONE : TSD_PAUSED, TS_OK, &err);
}

ts_rc tsd_session_run(tsd_session *s, double until, double rtf, json_t **opdoc, ts_err *err)
{
    if (s->m && until > ts_model_config(s->m)->run.duration + 1e-9)
        return ts_err_set(err, TS_ERR_RANGE, "/until",
                          "/until: at most run.duration = %g s for this session, got %g",
                          ts_model_config(s->m)->run.duration, until);
    ts_rc rc = acquire(s, err);
    if (rc != TS_OK) return rc;
    double t0 = ts_time(s->d);
    if (until < t0) {
        unbusy(s);
        return ts_err_set(err, TS_ERR_RANGE, "/until",
                          "/until: the session is already at t = %g s, got %g", t0, until);
    }
    run_job_arg *j = calloc(1, sizeof *j);
    tsd_op *op = j ? tsd_op_new(s->srv, s->id, t0, until) : NULL;
    if (!op) {
        int nomem = !j; /* (j is not read once freed) */
        free(j);
        unbusy(s);
        return nomem ? ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory")
                     : ts_err_set(err, TS_ERR_LIMIT, NULL, "too many operations in progress");
    }
    tsd_session_hold(s);
    *j = (run_job_arg){s, op, until, rtf, t0, tsd_now()};
    pthread_mutex_lock(&s->mu);
    tsd_status before = s->status;
    char before_error[sizeof s->error], before_op[sizeof s->op_id];
    memcpy(before_error, s->error, sizeof before_error);
    memcpy(before_op, s->op_id, sizeof before_op);
    s->status = TSD_RUNNING; /* created | paused | interrupted -> running */
    s->error[0] = '\0';
    snprintf(s->op_id, sizeof s->op_id, "%s", tsd_op_id(op));
    pthread_mutex_unlock(&s->mu);
    /* refused: the run's first stored batch writes it with its rows; a crash
     * before that brings the session back as stored, not interrupted */
    store_status(s->srv, s->seq, TSD_RUNNING, NULL);
    *opdoc = tsd_op_json_of(s->srv, op);
    if (tsd_pool_submit(s->srv->pool, run_slice, j, 0) != 0) {
        /* Nothing ran: the session goes back as it was, the operation ends
         * with the reason (14 UNAVAILABLE, or 8 for the memory), and the
         * caller gets it too (not a 202). */
        ts_rc why = atomic_load(&s->srv->stopping)
                        ? tsd_err_shutdown(err)
                        : ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory queueing the run");
        /* Not run_finish: that would count a run ended that never started
         * and store the session without its previous error and operation. */
        tsd_op_fail(s->srv, op, err);
        pthread_mutex_lock(&s->mu);
        s->status = before;
        memcpy(s->error, before_error, sizeof before_error);
        memcpy(s->op_id, before_op, sizeof before_op);
        pthread_mutex_unlock(&s->mu);
        store_status(s->srv, s->seq, before, before_error);
        unbusy(s);
        tsd_session_put(s); /* the job's reference */
        free(j);
        json_decref(*opdoc);
        *opdoc = NULL;
        return why;
    }
    atomic_fetch_add(&s->srv->metrics.runs_started, 1);
    return TS_OK;
}

void tsd_session_cancel(tsd_session *s, const char *op_id)
{
    /* Under mu: status and op_id change together in tsd_session_run and
     * release, and acquire clears cancel under mu, so a later step or run
     * never sees this request. */
    pthread_mutex_lock(&s->mu);
    if (s->status == TSD_RUNNING && strcmp(s->op_id, op_id) == 0) atomic_store(&s->cancel, 1);
    pthread_mutex_unlock(&s->mu);
}
