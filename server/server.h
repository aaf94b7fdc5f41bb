/*
 * server.h — tanksimd's one state object and the request record handlers see.
 *
 * All daemon state lives in tsd_server, passed to libmicrohttpd as its closure
 * (no file-scope mutable state except the signal mask set up in main.c).
 * A tsd_request is made on libmicrohttpd's first call for a request, collects
 * the body, is dispatched through the routing table (routes.c) once the body
 * is complete, and is freed — after its log line — in the completion callback.
 */
#ifndef TSD_SERVER_H
#define TSD_SERVER_H

#include <jansson.h>
#include <microhttpd.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stddef.h>

#include "../sim/errors.h"
#include "metrics.h"

struct tsd_pool;
struct tsd_db;
struct tsd_registry;
struct tsd_ops;
struct tsd_renderers;

#define TSD_MAX_PATH_PARAMS 4

typedef struct tsd_options {
    char bind[64];         /* listen address (IPv4 or IPv6 literal) */
    int port;              /* TCP port */
    char data_dir[512];    /* where sessions and results persist */
    int threads;           /* simulation worker threads */
    int http_threads;      /* libmicrohttpd thread-pool size */
    size_t max_body;       /* largest request body accepted [bytes] */
    unsigned conn_timeout; /* idle connection timeout [s] */
    int max_connections;   /* HTTP connections open at once (more wait in the listen queue) */
    char token[128];       /* bearer token; empty = no authentication */
    int max_sessions;      /* sessions kept at once (create beyond -> 429) */
    int max_analyses;      /* analyses stored at once (a new one beyond -> 429) */
    long max_samples;      /* sample rows per series/FFT response (page past it) */
    long max_rows;         /* sample rows one session may store (0: no limit) */
    double max_step;       /* longest synchronous step [s simulated] (longer -> 422) */
    char web_root[512];    /* dashboard files served at / (static_files.c) */
    double drain;          /* after SIGTERM/SIGINT, keep answering this long [s] (main.c) */
    double max_run_wall;   /* wall-clock budget of one run operation [s]; 0 = none (session.c) */
    int client_files;      /* 1: configs may name files the daemon opens (/terrain/profile_csv,
                            * a course outside the embedded store); 0 (default): refused */
} tsd_options;

/* The daemon's own result code beside sim's ts_rc values: work refused (or a
 * step cut short) because shutdown has begun. tsd_reply_err answers it with
 * 503 /problems/shutting-down and Retry-After: TSD_RETRY_AFTER_S — never with
 * the "Out of memory" of TS_ERR_NOMEM, which is what a refused submission to
 * the stopped worker pool used to be reported as. */
#define TSD_ERR_SHUTDOWN ((ts_rc)(TS_NRC + 1))
/* Work the store refused because the disk holding it is full: 507
 * /problems/store-full, google.rpc 8 RESOURCE_EXHAUSTED (tsd_err_store). */
#define TSD_ERR_STORE_FULL ((ts_rc)(TS_NRC + 2))
#define TSD_RETRY_AFTER_S 5 /* [s] a restart under systemd (RestartSec) takes about this */
#define TSD_SHUTDOWN_MSG "the daemon is shutting down; retry once it is back"

/* Fill err with TSD_ERR_SHUTDOWN and TSD_SHUTDOWN_MSG; returns the code. */
ts_rc tsd_err_shutdown(ts_err *err);

/* Whether the client of conn has closed its side (poll POLLRDHUP, no wait):
 * long jobs ask it between units of work, so nobody's abandoned request
 * holds a worker (frames between drawings, a step every 16 samples). */
int tsd_client_gone(struct MHD_Connection *conn);

typedef struct tsd_server {
    tsd_options opt;
    struct MHD_Daemon *mhd;
    int listen_fd;           /* bound by tsd_server_bind, -1 when none (or once MHD owns it) */
    atomic_int mhd_starting; /* libmicrohttpd's messages are kept, not printed (server.c) */
    char mhd_start_msg[160]; /* the first one kept */
    struct tsd_pool *pool;           /* simulation workers (pool.h) */
    struct tsd_db *db;               /* persistence (db.h) */
    struct tsd_registry *reg;        /* sessions (session.h) */
    struct tsd_ops *ops;             /* run operations (operations.h) */
    struct tsd_renderers *renderers; /* OpenGL contexts for frames (frames.h) */
    tsd_metrics metrics;             /* counters for /metrics (metrics.h) */
    pthread_mutex_t fft_lock;        /* FFTW's planner is not thread-safe */
    pthread_mutex_t analyses_lock;   /* a new analysis: the --max-analyses count, its
                                        operation and its first stored row (analyses.c) */
    atomic_int stopping;             /* set once shutdown begins */
    atomic_int inflight;             /* requests between arrival and completion (shutdown
                                        waits for them, bounded, before stopping MHD) */
    atomic_int long_jobs;            /* analyses and APNG animations holding a worker */
    atomic_size_t reply_bytes;       /* bytes of counted answers not yet sent (server.c) */
    atomic_size_t summary_bytes;     /* rows held by /summary answers (routes.c get_summary) */
} tsd_server;

/* Fill err for a write the store refused with dbrc (db.h): the message fmt
 * says what was refused and the cause follows it — TSD_ERR_STORE_FULL
 * naming the data directory for TSD_DB_FULL, TS_ERR_IO ("see the daemon
 * log") otherwise. Returns the code. */
ts_rc tsd_err_store(const tsd_server *srv, ts_err *err, int dbrc, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* The problem document of err (new reference; errors as tsa_problem_from_err):
 * api/problem.h's for sim's codes, 507 /problems/store-full for
 * TSD_ERR_STORE_FULL. TSD_ERR_SHUTDOWN is answered by its callers. */
json_t *tsd_problem_from_err(const ts_err *err, json_t *errors);

typedef struct tsd_request {
    tsd_server *srv;
    struct MHD_Connection *conn;
    const char *method; /* "GET", ... (owned by libmicrohttpd) */
    const char *url;    /* path without query (owned by libmicrohttpd) */
    char *body;         /* request body, NUL-terminated (owned) */
    size_t body_len;
    int body_too_large;                    /* set when the body passed opt.max_body */
    char params[TSD_MAX_PATH_PARAMS][128]; /* {id}-style path segments matched */
    int nparams;
    unsigned status; /* status sent (for the log) */
    size_t bytes;    /* response body bytes (for the log) */
    double t_start;  /* monotonic seconds at arrival */
    /* Deferred replies: a handler that hands work to the pool suspends the
     * connection and sets on_resume; the worker fills async_* and resumes it;
     * the next access-handler call runs on_resume to queue the response. */
    enum MHD_Result (*on_resume)(struct tsd_request *r);
    /* the route's handler, run once a deferred session is built (routes.c) */
    enum MHD_Result (*built_handler)(struct tsd_request *r);
    json_t *async_result;          /* owned; set by the worker */
    unsigned async_status;         /* status of a reply with async_result (routes.c) */
    ts_err async_err;              /* set by the worker on failure */
    json_t *async_errors;          /* owned; config errors [{pointer, message}] on failure */
    json_t *async_doc;             /* owned; the parsed body handed to the worker */
    void *async_ctx;               /* handler's own job context */
    void (*async_free)(void *ctx); /* frees async_ctx at completion (NULL: nothing) */
    struct tsd_session *session;   /* RF_SESSION routes: looked-up session (reference) */
    char location[96];             /* Location header of the reply ("" = none) */
    char next_token[32];           /* X-Next-Page-Token header of the reply ("" = none) */
    char etag[96];   /* ETag of a cacheable response (frames of stored times) */
    char allow[64];                /* Allow header of a 405: the path's methods ("" = none) */
    int www_authenticate;          /* add WWW-Authenticate: Bearer (401) */
    int retry_after;               /* add Retry-After: N seconds (0 = none) */
    int bad_path;                  /* the raw path had %00 or %2F (server.c refuses it) */
    size_t target_len;             /* bytes of the raw request target (uri_seen, server.c) */
    size_t target_params;          /* its query parameters, counted as libmicrohttpd splits them */
} tsd_request;

/* Long jobs — engine maps, tunings (analyses.c) and APNG animations
 * (frames.c) — each hold a worker for seconds to minutes. Together at most
 * max(1, threads - 1) run at once, so session runs and
 * steps keep a worker. take: TS_OK, or TS_ERR_LIMIT with the message and
 * *retry_after set to the Retry-After of its 429; every take that
 * succeeded is given back once, when the job ends. */
#define TSD_RETRY_AFTER_BUSY_S 2 /* [s] Retry-After of the 429 at the long-job cap */
TS_MUST_CHECK ts_rc tsd_long_job_take(tsd_server *s, int *retry_after, ts_err *err);
void tsd_long_job_give(tsd_server *s);

/* Answers made whole before they are sent (a /series page, a spectrum, a
 * PNG) stay in memory until the client has read them, or until the
 * connection times out (--timeout): clients that ask and never read held
 * one each, without bound (20 such /series requests: +600 MB). Every buffered
 * answer of at least TSD_REPLY_COUNTED_MIN bytes counts against
 * TSD_REPLY_BUDGET for as long as it is held; one that would pass it is
 * answered 503 /problems/busy with Retry-After: TSD_RETRY_AFTER_BUSY_S
 * instead (unless nothing else is held: a single answer is always sent).
 * Smaller answers (health, errors, session documents) are never refused. */
#define TSD_REPLY_COUNTED_MIN ((size_t)64 << 10)
#define TSD_REPLY_BUDGET      ((size_t)128 << 20) /* ~12 full /series pages */

/* 503 /problems/busy (title, detail) with Retry-After: TSD_RETRY_AFTER_BUSY_S,
 * in place of an answer the daemon cannot give now: the reply budget is
 * full, or another run summary is being computed. Counted in /metrics
 * tanksimd_reply_busy_total. */
enum MHD_Result tsd_reply_busy(tsd_request *r, const char *title, const char *detail);

/* Ahead of work whose answer is made whole and counted (a frame, an APNG):
 * 1 with that 503 /problems/busy queued in *ret when the answers held already
 * leave no room for any counted answer, so that it is not drawn (a 4096 x 4096
 * frame ~0.6 s, an APNG seconds) only to be refused when queued; else 0. The
 * exact check stays where the answer is queued. */
int tsd_reply_budget_full(tsd_request *r, enum MHD_Result *ret);

/* Bind the listening socket of opt.bind and opt.port (opt.port 0: set to the
 * port the kernel chose), not listening yet: done first, before the store is
 * created or locked, so that a bad --bind or a port in use leaves nothing
 * behind. 0, or -1 with a message in err. unbind closes it (a later failure). */
TS_MUST_CHECK int tsd_server_bind(tsd_server *s, char *err, size_t errlen);
void tsd_server_unbind(tsd_server *s);
/* Listen on the bound socket and serve it (libmicrohttpd, which owns the
 * socket from the call on); 0 on success, -1 with a message in err. Until
 * here a client's connection is refused, as before the daemon ran.
 * libmicrohttpd's own error messages go into err while it starts, and to
 * stderr as "tanksimd: libmicrohttpd: ..." once it serves. */
TS_MUST_CHECK int tsd_server_start(tsd_server *s, char *err, size_t errlen);
void tsd_server_stop(tsd_server *s);
/* Wait (at most timeout seconds, polling) until no request is in flight — at
 * shutdown, so that replies of deferred requests that workers resumed (a step
 * cut short, a create) are sent before libmicrohttpd closes the connections.
 * stop (blocked signals; may be NULL): one of them arriving ends the wait. */
void tsd_server_settle(tsd_server *s, double timeout, const sigset_t *stop);

/* Responses: each queues exactly one response and returns MHD's result. */
enum MHD_Result tsd_reply_json(tsd_request *r, unsigned status, json_t *body); /* steals body */
enum MHD_Result tsd_reply_text(tsd_request *r, unsigned status, const char *content_type,
                               const char *text, size_t len);
enum MHD_Result tsd_reply_problem(tsd_request *r, unsigned status, const char *type,
                                  const char *title, const char *detail, json_t *errors);
/* 304 Not Modified for r->etag: no body, no Content-Length (the 200's length
 * is not known without drawing it), and the connection closes after it (the
 * only framing libmicrohttpd 0.9.75 offers for that; server.c). */
enum MHD_Result tsd_reply_not_modified(tsd_request *r);

/* Reply with a malloc'd buffer, which the response takes over. */
enum MHD_Result tsd_reply_owned(tsd_request *r, unsigned status, const char *content_type,
                                char *text, size_t len);
/* Reply with a ready problem document (steals p). */
enum MHD_Result tsd_reply_problem_json(tsd_request *r, unsigned status, json_t *p);
/* Problem from a ts_err (status from api/problem.h; TSD_ERR_SHUTDOWN -> 503
 * shutting-down with Retry-After); errors may be NULL (not stolen). */
enum MHD_Result tsd_reply_err(tsd_request *r, const ts_err *err, json_t *errors);
/* Suspend r until a worker calls tsd_request_resume; on_resume then replies. */
void tsd_request_defer(tsd_request *r, enum MHD_Result (*on_resume)(tsd_request *r));
void tsd_request_resume(tsd_request *r);

/* 503 /problems/shutting-down with Retry-After (detail NULL: TSD_SHUTDOWN_MSG). */
enum MHD_Result tsd_reply_shutting_down(tsd_request *r, const char *detail);

/* Route the request (routes.c). */
enum MHD_Result tsd_route(tsd_request *r);
/* Print the routing table, "METHOD PATTERN" per line (routes.c; --routes). */
void tsd_routes_print(void);
/* Query argument or NULL. */
const char *tsd_arg(tsd_request *r, const char *name);
/* Non-zero for a HEAD request (routed as GET). */
int tsd_request_is_head(const tsd_request *r);
/* 200 with a body made as it goes (chunked, unknown length: live streams,
 * multipart frames): reader fills blocks of up to block bytes from ctx,
 * release(ctx) frees it (also here, on failure or HEAD). A HEAD gets the
 * headers only, without Content-Length (the GET has no length to give; "0"
 * would be wrong, RFC 9110 §8.6), and the connection closes after it (as the
 * 304's: the only framing libmicrohttpd 0.9.75 offers for it, server.c). */
enum MHD_Result tsd_reply_chunked(tsd_request *r, const char *content_type, size_t block,
                                  MHD_ContentReaderCallback reader, void *ctx,
                                  MHD_ContentReaderFreeCallback release);

#endif
