/*
 * session.h — simulation sessions: one model + one run state each, the
 * registry of them, and the jobs that advance them on the worker pool.
 * The state diagram and its transition functions are in session.c.
 *
 * Ownership and locking:
 *   - A session is reference-counted: the registry holds one reference,
 *     tsd_session_get (by id) and tsd_session_hold (a session already held) add
 *     one, tsd_session_put drops one; the last put frees.
 *   - m (ts_model) and config are immutable after creation: any thread may read.
 *   - d (ts_data), the sample batch and the snapshot buffer belong to whoever
 *     holds `busy` (a worker running a step or a run slice) — never an HTTP
 *     thread.
 *   - Fields marked (mu) are read and written under s->mu.
 */
#ifndef TSD_SESSION_H
#define TSD_SESSION_H

#include <jansson.h>
#include <microhttpd.h>
#include <pthread.h>
#include <stdatomic.h>

#include "../sim/model.h"
#include "channels.h"
#include "server.h"

typedef enum tsd_status {
    TSD_CREATED,     /* built, row 0 stored, never advanced */
    TSD_RUNNING,     /* a run operation owns it */
    TSD_PAUSED,      /* advanced by steps or runs, can go on */
    TSD_DONE,        /* reached run.duration */
    TSD_FAILED,      /* the model reported an error; sticky */
    TSD_INTERRUPTED, /* the daemon stopped during a run; can run again */
    TSD_NSTATUS
} tsd_status;

const char *tsd_status_name(tsd_status st);

/* A suspended stream connection waiting for samples (stream.c owns it). */
typedef struct tsd_waiter {
    struct MHD_Connection *conn;
    struct tsd_waiter *next;
    int linked; /* (mu) in the session's waiter list */
} tsd_waiter;

typedef struct tsd_session {
    tsd_server *srv;
    char id[24];      /* "s" + 16 hex digits */
    long seq;         /* creation order; the database key */
    double created;   /* Unix time [s] */
    char preset[128]; /* preset named at creation ("" if none) */
    json_t *config;   /* resolved config document (immutable) */
    ts_model *m;      /* NULL when the model could not be rebuilt after a restart */
    ts_data *d;       /* owned by the busy holder */
    int nch;          /* channels per row (= ch.view.n; 0: no table, rows unreadable) */
    tsd_channels ch;  /* names, units and sample period of the stored rows: the
                         model's, or the list stored with the session when this
                         build's model cannot be made or has other channels
                         (channels.h); immutable once shared */
    double *batch;    /* rows not yet stored, batch_cap x nch (busy holder) */
    long batch_n, batch_cap, batch_first;
    void *snapshot; /* ts_state_size bytes (busy holder) */
    size_t snapshot_size;
    int unrestored;   /* loaded at start-up but its model or stored state could not be
                         rebuilt (reason in error): rows readable, no step or run;
                         set at start-up or by tsd_session_build before any handler
                         sees the session, then immutable */
    int latest_damaged;  /* its last stored row is damaged (db.h: -2): no latest values
                            are shown; set and immutable as unrestored */
    atomic_int deferred; /* loaded at start-up without its model (rows read through the
                            stored channel table), built at first use (tsd_session_build,
                            under build_mu), so start-up does not grow with the store */
    pthread_mutex_t build_mu;
    atomic_int cancel; /* set by cancel/delete/shutdown; read by the running job */
    pthread_mutex_t mu;
    int refs;            /* (mu) */
    tsd_status status;   /* (mu) */
    int busy;            /* (mu) a worker owns d */
    int deleted;         /* (mu) removed from the registry */
    double t;            /* (mu) time of the last stored row [s] */
    long index;          /* (mu) index of the last stored row (-1: none, unrestored only) */
    double *latest;      /* (mu) last stored row, nch values */
    ts_integrator_stats integrators[TS_MAX_INTEGRATORS]; /* (mu) work counters at the last
                                                          * stored row, in this process */
    int nintegrators;                                    /* (mu) entries of integrators */
    char error[384];     /* (mu) message of the failure (failed) */
    char op_id[24];      /* (mu) the run operation in progress or last run */
    tsd_waiter *waiters; /* (mu) suspended streams */
} tsd_session;

/* Registry: make, load what the database holds (running -> interrupted), free. */
TS_MUST_CHECK int tsd_sessions_init(tsd_server *srv, char *err, size_t errlen);
void tsd_sessions_wake_all(tsd_server *srv); /* resume every waiting stream */
void tsd_sessions_free(tsd_server *srv);
void tsd_sessions_count(tsd_server *srv, long counts[TSD_NSTATUS]);

/* Create from a request document {"preset", sections...}: config errors ->
 * TS_ERR_PARAM/RANGE with every violation in errors; unknown preset ->
 * TS_ERR_NOTFOUND; scenario not built -> TS_ERR_UNSUPPORTED; too many
 * sessions -> TS_ERR_LIMIT. *out gets a reference. */
TS_MUST_CHECK ts_rc tsd_session_create(tsd_server *srv, const json_t *doc, tsd_session **out,
                                       json_t *errors, ts_err *err);
tsd_session *tsd_session_get(tsd_server *srv, const char *id); /* NULL if unknown */
/* A session loaded at start-up is deferred: listed and its rows served from
 * the stored channel table, its model not built. tsd_session_build (on the
 * worker pool: it is physics, up to ~0.4 s) builds the model and restores the
 * stored state, once, however many callers; a failure leaves the session
 * unrestored and failed with the reason, as a failure at start-up did. The
 * router builds a deferred session before any handler sees it. */
int tsd_session_deferred(tsd_session *s);
void tsd_session_build(tsd_session *s);
void tsd_session_hold(tsd_session *s); /* one more reference to a session the caller holds */
void tsd_session_put(tsd_session *s);
/* Non-zero once s has been deleted (taken under its lock): a reader holding
 * a reference answers 404 instead of what the removed rows would give. */
int tsd_session_is_deleted(tsd_session *s);
/* err := 404 TS_ERR_NOTFOUND "session ID was deleted", the one answer for a
 * session a DELETE removed under a request; returns TS_ERR_NOTFOUND. */
ts_rc tsd_session_err_deleted(const tsd_session *s, ts_err *err);
/* Delete s (the caller holds a reference): 404 when it already is, IO when the
 * store will not record it (the session is kept). */
TS_MUST_CHECK ts_rc tsd_session_delete(tsd_session *s, ts_err *err);

/* Session object (session_json.h shape), taken under the lock. */
json_t *tsd_session_json(tsd_session *s, int summary);
/* {"sessions": [...], "next_page_token"?} in creation order after page_token. */
json_t *tsd_session_list(tsd_server *srv, long page_size, long after_seq);

/* Advance by duration on the pool, then call done(ud) from the worker after
 * filling *result ({"id","status","t","index","values"}) or *err. TS_ERR_STATE
 * when busy/done/failed; the callback is not called when this fails. client
 * (may be NULL) is the request's connection: when its client hangs up the
 * step stops, the session paused at its last row (TS_ERR_CANCELLED). */
TS_MUST_CHECK ts_rc tsd_session_step(tsd_session *s, struct MHD_Connection *client, double duration,
                                     json_t **result, ts_err *err, void (*done)(void *ud),
                                     void *ud);

/* Start a run to `until` (<= run.duration), at most rtf x real time when
 * rtf > 0. Returns the operation document (new reference). */
TS_MUST_CHECK ts_rc tsd_session_run(tsd_session *s, double until, double rtf, json_t **op,
                                    ts_err *err);

/* Ask the run of operation op_id to stop (run -> paused). A no-op unless
 * that run is the one in progress: a cancel that arrives after its run ended
 * must not stop whatever the session does next (a step would be cut short
 * and reported as if the session had been deleted). */
void tsd_session_cancel(tsd_session *s, const char *op_id);

/* Streams: 1 when rows with index >= next are stored; 0 when none are yet
 * and the caller's connection has been suspended and queued in w (it is
 * resumed when rows arrive or the run ends); -1 when no more rows will come. */
TS_MUST_CHECK int tsd_session_await(tsd_session *s, long next, tsd_waiter *w);
void tsd_session_unwait(tsd_session *s, tsd_waiter *w);

#endif
