/*
 * analyses.h — the daemon's analyses: computations that answer one question
 * about a configuration instead of advancing a session. The engine's
 * full-load map on a dynamometer (paper Section III.B.3, Fig. 18; the same
 * document as `tanksim engine-map`, api/analysis_json.h) and the IVS speed
 * controller's Ziegler–Nichols tuning with an optional gain schedule (Eqs.
 * 11-12, Figs. 26-27; `tanksim tune`).
 *
 * They take seconds to minutes (a crank-angle sweep ~3 s; a tune at the
 * crank-angle fidelity ~5 s per schedule point), so each runs as an
 * operation (operations.h): POST answers 202 with it, GET
 * /v1/operations/{id} shows parts done and, at the end, the document as its
 * response; :cancel stops it after the part in progress. An analysis holds a
 * worker thread from start to end, so at most max(1, threads - 1) run at
 * once: session runs always keep a worker when there are two.
 *
 * Each analysis's operation document is stored (db.h, table analyses) when
 * it starts, after each part and when it ends: GET /v1/operations/{id} finds it after a
 * restart, GET /v1/analyses lists them, DELETE /v1/analyses/{id} removes
 * one. An analysis the daemon did not finish (killed, crashed) is stored
 * done with an error at the next start-up (tsd_analyses_recover); one the
 * daemon's shutdown stopped already ends with such an error.
 */
#ifndef TSD_ANALYSES_H
#define TSD_ANALYSES_H

#include <jansson.h>

#include "../api/analysis_json.h"
#include "../sim/config.h"
#include "../sim/errors.h"
#include "server.h"

typedef enum tsd_analysis_kind { TSD_ANALYSIS_ENGINE_MAP, TSD_ANALYSIS_TUNE } tsd_analysis_kind;

typedef struct tsd_analysis_req {
    tsd_analysis_kind kind;
    ts_config cfg;                     /* the loaded configuration */
    char var[8];                       /* tune: "mass" or "grade" when n > 0 */
    double x[TSA_TUNE_SCHEDULE_MAX];   /* tune: the schedule's values (kg or rad) */
    int n;                             /* tune: schedule points (0: none) */
    json_t *request;                   /* the request as metadata.request shows it */
} tsd_analysis_req;

/* Queue the analysis; *opdoc (new reference) is its operation document.
 * req->request is stolen in every case. TS_ERR_LIMIT when --max-analyses
 * are stored, or when the long jobs are at their cap (then *retry_after is
 * set, server.h tsd_long_job_take), TSD_ERR_SHUTDOWN once shutdown began,
 * TS_ERR_NOMEM. */
TS_MUST_CHECK ts_rc tsd_analysis_start(tsd_server *srv, const tsd_analysis_req *req, json_t **opdoc,
                                       int *retry_after, ts_err *err);

/* Start-up: store every analysis left not done as done with an error.
 * Returns how many, -1 on a store error (logged). */
TS_MUST_CHECK int tsd_analyses_recover(tsd_server *srv);

/* The stored operation document of analysis id (for one the daemon no
 * longer holds in memory: tsd_op_json first). New reference, or NULL with
 * err (TS_ERR_NOTFOUND when not stored). */
json_t *tsd_analysis_stored(tsd_server *srv, const char *id, ts_err *err);

/* {"analyses": [{id, name, kind, created, done, failed, error_code,
 * asked}]}, the stored analyses newest first; asked is what was asked
 * ({preset, engine_fidelity} of the body and the query parameters,
 * db.h), never the body: bodies may be large and the list holds up to
 * --max-analyses of them (GET /v1/analyses/{id} or the operation give the
 * whole request). New reference, or NULL with err. */
json_t *tsd_analyses_json(tsd_server *srv, ts_err *err);

/* One stored analysis's list entry with its whole request ("request": as
 * metadata.request shows it). New reference, or NULL with err
 * (TS_ERR_NOTFOUND when not stored). */
json_t *tsd_analysis_json(tsd_server *srv, const char *id, ts_err *err);

/* Remove a finished analysis from the store and from memory:
 * TS_ERR_STATE while it runs, TS_ERR_NOTFOUND when not stored. */
TS_MUST_CHECK ts_rc tsd_analysis_delete(tsd_server *srv, const char *id, ts_err *err);

#endif
