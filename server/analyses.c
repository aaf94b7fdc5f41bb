/*
 * analyses.c — engine map and IVS tuning as operations (analyses.h). The
 * document is built by api/analysis_json.c on a pool worker; this file only
 * caps the analyses running at once (the operation registry counts them),
 * feeds the operation's progress and turns a stop (cancel or shutdown) into
 * the operation's error.
 */
#include "analyses.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../sim/engine_sweep.h"
#include "operations.h"
#include "pool.h"

typedef struct analysis_job {
    tsd_server *srv;
    tsd_op *op;
    int parts_done, parts_total;
    tsd_analysis_req req;
} analysis_job;

/* At most this many at once: session runs keep a worker when there are two. */
static int analysis_cap(const tsd_server *srv)
{
    return srv->opt.threads > 1 ? srv->opt.threads - 1 : 1;
}

static const char *kind_name(tsd_analysis_kind k)
{
    return k == TSD_ANALYSIS_ENGINE_MAP ? "engine_map" : "tune";
}

/* ts_progress_fn: record the part; stop on cancel or shutdown. */
static int on_progress(void *ud, int done, int total)
{
    analysis_job *j = ud;
    j->parts_done = done;
    j->parts_total = total;
    tsd_op_parts(j->srv, j->op, done, total);
    return atomic_load(&j->srv->stopping) || tsd_op_cancel_requested(j->srv, j->op);
}

static void analysis_run(void *arg)
{
    analysis_job *j = arg;
    tsd_server *srv = j->srv;
    const tsd_analysis_req *q = &j->req;
    ts_err e;
    memset(&e, 0, sizeof e);
    json_t *doc = NULL;
    if (atomic_load(&srv->stopping)) /* queued behind the shutdown: do not start */
        ts_err_set(&e, TS_ERR_CANCELLED, NULL, "stop");
    else if (q->kind == TSD_ANALYSIS_ENGINE_MAP)
        doc = tsa_engine_map_json(&q->cfg, on_progress, j, &e);
    else
        doc = tsa_tune_json(&q->cfg, q->n > 0 ? q->var : NULL, q->x, q->n, on_progress, j, &e);
    if (!doc && e.code == TS_ERR_CANCELLED)
        ts_err_set(&e, TS_ERR_CANCELLED, NULL,
                   atomic_load(&srv->stopping)
                       ? "the daemon shut down after %d of %d parts; start the analysis again"
                       : "cancelled after %d of %d parts",
                   j->parts_done, j->parts_total);
    if (doc)
        tsd_op_finish(srv, j->op, doc, NULL);
    else
        tsd_op_fail(srv, j->op, &e);
    free(j);
}

ts_rc tsd_analysis_start(tsd_server *srv, const tsd_analysis_req *req, json_t **opdoc,
                         ts_err *err)
{
    *opdoc = NULL;
    if (atomic_load(&srv->stopping)) return tsd_err_shutdown(err);
    int cap = analysis_cap(srv), busy = 0;
    analysis_job *j = calloc(1, sizeof *j);
    int total = req->kind == TSD_ANALYSIS_ENGINE_MAP ? TS_ENGINE_SWEEP_NPOINT : 1 + req->n;
    tsd_op *op = j ? tsd_op_new_analysis(srv, kind_name(req->kind), total, cap, &busy) : NULL;
    if (!op) {
        int nomem = !j;
        free(j);
        if (busy)
            return ts_err_set(err, TS_ERR_LIMIT, NULL,
                              "%d analyses already running (at most %d at once with %d worker "
                              "threads, so that session runs keep one); retry when one is done",
                              cap, cap, srv->opt.threads);
        return nomem ? ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory")
                     : ts_err_set(err, TS_ERR_LIMIT, NULL, "too many operations in progress");
    }
    j->srv = srv;
    j->op = op;
    j->req = *req;
    *opdoc = tsd_op_json_of(srv, op);
    if (tsd_pool_submit(srv->pool, analysis_run, j, 0) != 0) {
        ts_rc why = atomic_load(&srv->stopping)
                        ? tsd_err_shutdown(err)
                        : ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory queueing the job");
        ts_err e2;
        ts_err_set(&e2, TS_ERR_CANCELLED, NULL, "%s", err->msg);
        tsd_op_fail(srv, op, &e2);
        free(j);
        json_decref(*opdoc);
        *opdoc = NULL;
        return why;
    }
    return TS_OK;
}
