/*
 * analyses.c — engine map and IVS tuning as operations (analyses.h). The
 * document is built by api/analysis_json.c on a pool worker; this file caps
 * the analyses running at once (the operation registry counts them) and
 * stored at once (--max-analyses), feeds the operation's progress, turns a
 * stop into the operation's error (a cancel: google.rpc 1 CANCELLED; the
 * daemon stopping: 14 UNAVAILABLE), and keeps each operation's document in
 * the store (db.h, table analyses): written when it starts, after each part
 * and when it ends (one small row; a part takes 0.1-5 s), so a finished
 * result survives a restart and one a crash cut short is reported as such
 * instead of vanishing.
 */
#include "analyses.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../api/config_json.h"
#include "../sim/engine_sweep.h"
#include "db.h"
#include "operations.h"
#include "pool.h"

typedef struct analysis_job {
    tsd_server *srv;
    tsd_op *op;
    int parts_done, parts_total;
    int store_failed; /* a progress row was not stored (store_op's code): stopped */
    tsd_analysis_req req;
} analysis_job;

static const char *kind_name(tsd_analysis_kind k)
{
    return k == TSD_ANALYSIS_ENGINE_MAP ? "engine_map" : "tune";
}

/* Store an analysis' operation document: 0, or -1 when the store refused it
 * (db.c logged why) or memory ran out. The request goes to its own column
 * only: the stored document leaves metadata.request out (a shallow copy
 * without it), and tsd_analysis_stored puts it back. It used to be stored
 * twice, in the column and in the document, and rewritten twice after each
 * part. */
static int put_doc(tsd_server *srv, json_t *doc)
{
    json_t *md = json_object_get(doc, "metadata");
    json_t *md2 = json_copy(md), *doc2 = json_copy(doc);
    char *text = NULL, *req = NULL;
    if (md2 && doc2 && json_object_del(md2, "request") == 0 &&
        json_object_set(doc2, "metadata", md2) == 0) {
        text = json_dumps(doc2, JSON_COMPACT);
        req = json_dumps(json_object_get(md, "request"), JSON_COMPACT | JSON_ENCODE_ANY);
    }
    json_decref(md2);
    json_decref(doc2);
    int rc = -1;
    if (text && req)
        rc = tsd_db_analysis_put(srv->db, json_string_value(json_object_get(doc, "id")),
                                 json_string_value(json_object_get(md, "kind")),
                                 json_number_value(json_object_get(md, "created")),
                                 json_is_true(json_object_get(doc, "done")),
                                 (int)json_integer_value(
                                     json_object_get(json_object_get(doc, "error"), "code")),
                                 req, text);
    else
        fprintf(stderr, "tanksimd: out of memory storing analysis %s\n",
                json_string_value(json_object_get(doc, "id")));
    free(text);
    free(req);
    return rc;
}

/* tsd_op_finish_persisted's writer: 0 when stored. */
static int store_doc(void *ud, json_t *doc)
{
    return put_doc(ud, doc);
}

/* The progress row: 0 when stored, -1 (TSD_DB_FULL: its disk is full) when
 * the store refused it, -2 without memory for it. Either stops the analysis
 * (on_progress): its result could not be kept either. */
static int store_op(tsd_server *srv, tsd_op *op)
{
    json_t *doc = tsd_op_json_of(srv, op);
    int rc = doc ? store_doc(srv, doc) : -2;
    json_decref(doc);
    return rc;
}

/* End op with response or error (one of them; stolen). Its long-job place is
 * given back first, so a client that sees it done can start the next one at
 * once; its final document is stored before it is marked done: once a client
 * can see it done it may DELETE it (the row would come back if stored after)
 * and the registry may drop it (op freed). */
static void finish(tsd_server *srv, tsd_op *op, json_t *response, json_t *error)
{
    tsd_long_job_give(srv);
    tsd_op_finish_persisted(srv, op, response, error, store_doc, srv);
}

/* ts_progress_fn: record the part; stop on cancel or shutdown. */
static int on_progress(void *ud, int done, int total)
{
    analysis_job *j = ud;
    /* also called every few samples of a tune's runs only to ask whether to
     * stop (ts_ivs_tune_polled): the operation is recorded and stored when its
     * count of parts moves */
    if (done != j->parts_done || total != j->parts_total) {
        j->parts_done = done;
        j->parts_total = total;
        tsd_op_parts(j->srv, j->op, done, total);
        /* a crash after this part reports how far it got */
        int rc = store_op(j->srv, j->op);
        if (rc != 0) j->store_failed = rc;
    }
    if (j->store_failed) return 1;
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
    if (!doc && e.code == TS_ERR_CANCELLED) {
        if (j->store_failed == -2)
            ts_err_set(&e, TS_ERR_NOMEM, NULL,
                       "stopped after %d of %d parts: no memory to store its progress",
                       j->parts_done, j->parts_total);
        else if (j->store_failed)
            tsd_err_store(srv, &e, j->store_failed,
                          "stopped after %d of %d parts: the store refused its progress",
                          j->parts_done, j->parts_total);
        else if (atomic_load(&srv->stopping))
            ts_err_set(&e, TSD_ERR_SHUTDOWN, NULL,
                       "the daemon shut down after %d of %d parts; start the analysis again",
                       j->parts_done, j->parts_total);
        else
            ts_err_set(&e, TS_ERR_CANCELLED, NULL, "cancelled after %d of %d parts",
                       j->parts_done, j->parts_total);
    }
    finish(srv, j->op, doc, doc ? NULL : tsd_op_error_json(&e));
    free(j);
}

ts_rc tsd_analysis_start(tsd_server *srv, const tsd_analysis_req *req, json_t **opdoc,
                         int *retry_after, ts_err *err)
{
    *opdoc = NULL;
    json_t *request = req->request;
    if (atomic_load(&srv->stopping)) {
        json_decref(request);
        return tsd_err_shutdown(err);
    }
    /* The stored count, the operation and its first row in one section: two
     * requests cannot pass --max-analyses together (a row that could not be
     * stored is not counted: db.c logs why). */
    pthread_mutex_lock(&srv->analyses_lock);
    long stored = 0;
    /* a store that cannot count (db.c logged why) does not stop the analysis:
     * its result is still served from memory */
    int counted = tsd_db_analysis_count(srv->db, &stored) == 0;
    if (counted && stored >= srv->opt.max_analyses) {
        pthread_mutex_unlock(&srv->analyses_lock);
        json_decref(request);
        return ts_err_set(err, TS_ERR_LIMIT, NULL,
                          "the daemon holds its limit of %d stored analyses (--max-analyses, "
                          "running ones included); delete some first (DELETE /v1/analyses/{id}, "
                          "GET /v1/analyses lists them)",
                          srv->opt.max_analyses);
    }
    ts_rc busy = tsd_long_job_take(srv, retry_after, err);
    if (busy != TS_OK) {
        pthread_mutex_unlock(&srv->analyses_lock);
        json_decref(request);
        return busy;
    }
    analysis_job *j = calloc(1, sizeof *j);
    int total = req->kind == TSD_ANALYSIS_ENGINE_MAP ? TS_ENGINE_SWEEP_NPOINT : 1 + req->n;
    if (!j) json_decref(request);
    tsd_op *op = j ? tsd_op_new_analysis(srv, kind_name(req->kind), total, request) : NULL;
    if (!op) {
        pthread_mutex_unlock(&srv->analyses_lock);
        tsd_long_job_give(srv);
        int nomem = !j;
        free(j);
        return nomem ? ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory")
                     : ts_err_set(err, TS_ERR_LIMIT, NULL, "too many operations in progress");
    }
    j->srv = srv;
    j->op = op;
    j->req = *req;
    j->req.request = NULL; /* the operation holds it */
    *opdoc = tsd_op_json_of(srv, op);
    int put = *opdoc ? put_doc(srv, *opdoc) : -2;
    if (put != 0) {
        /* not stored, not started: an analysis the store never held would be
         * lost at the next restart, where the README promises it is kept */
        pthread_mutex_unlock(&srv->analyses_lock);
        ts_rc why = put == -2 ? ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory")
                              : tsd_err_store(srv, err, put,
                                              "cannot store the analysis, so it was not started");
        char id[64]; /* the op may be freed once finished */
        snprintf(id, sizeof id, "%s", tsd_op_id(op));
        tsd_long_job_give(srv);
        tsd_op_fail(srv, op, err); /* not finish(): nothing to store */
        tsd_op_forget(srv, id);
        free(j);
        json_decref(*opdoc);
        *opdoc = NULL;
        return why;
    }
    pthread_mutex_unlock(&srv->analyses_lock);
    if (tsd_pool_submit(srv->pool, analysis_run, j, 0) != 0) {
        ts_rc why = atomic_load(&srv->stopping)
                        ? tsd_err_shutdown(err)
                        : ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory queueing the job");
        finish(srv, op, NULL, tsd_op_error_json(err));
        free(j);
        json_decref(*opdoc);
        *opdoc = NULL;
        return why;
    }
    return TS_OK;
}

/* ---- stored analyses -------------------------------------------------------------- */

json_t *tsd_analysis_stored(tsd_server *srv, const char *id, ts_err *err)
{
    char *text = NULL, *request = NULL;
    if (tsd_db_analysis_get(srv->db, id, &text, &request) != 0) {
        ts_err_set(err, TS_ERR_IO, NULL, "cannot read analysis '%s' from the store", id);
        return NULL;
    }
    if (!text) {
        ts_err_set(err, TS_ERR_NOTFOUND, NULL,
                   "no operation '%s' (run operations are kept in memory until the daemon "
                   "stops; analyses are stored until deleted)",
                   id);
        return NULL;
    }
    json_t *j = json_loads(text, 0, NULL);
    free(text);
    json_t *md = json_object_get(j, "metadata");
    /* stored once, in its column (put_doc); stores older than that also
     * have it in the document: that copy is the same */
    if (json_is_object(md) && !json_object_get(md, "request")) {
        json_t *req = json_loads(request, JSON_DECODE_ANY, NULL);
        json_object_set_new(md, "request", req ? req : json_null());
    }
    /* older daemons stored it with its comment keys: shown without them */
    tsa_strip_comments(json_object_get(md, "request"));
    free(request);
    if (!j) ts_err_set(err, TS_ERR_INTERNAL, NULL, "stored analysis '%s' is not JSON", id);
    return j;
}

typedef struct recover_ctx {
    tsd_server *srv;
    int n, failed;
} recover_ctx;

/* tsd_db_analysis_id_fn: an analysis stored as not done was cut short by a
 * daemon that stopped without finishing it (killed, crashed, power loss):
 * store it done, with an error saying so. Only these are read (their
 * documents and requests); finished ones are not touched at start-up. */
static void recover_one(void *ud, const char *id)
{
    recover_ctx *c = ud;
    ts_err e;
    json_t *doc = tsd_analysis_stored(c->srv, id, &e);
    if (!json_is_object(doc)) {
        fprintf(stderr, "tanksimd: analysis %s: %s\n", id,
                doc ? "its stored document is not an object" : e.msg);
        json_decref(doc);
        c->failed++;
        return;
    }
    json_t *md = json_object_get(doc, "metadata");
    ts_err_set(&e, TSD_ERR_SHUTDOWN, NULL,
               "the daemon stopped (killed or crashed) after %d of %d parts of this analysis; "
               "start it again",
               (int)json_integer_value(json_object_get(md, "parts_done")),
               (int)json_integer_value(json_object_get(md, "parts_total")));
    json_object_set_new(doc, "done", json_true());
    json_object_set_new(doc, "error", tsd_op_error_json(&e));
    int stored = store_doc(c->srv, doc) == 0;
    json_decref(doc);
    if (!stored) {
        c->failed++; /* db.c logged why */
        return;
    }
    fprintf(stderr, "tanksimd: analysis %s was interrupted (the daemon stopped during it)\n", id);
    c->n++;
}

int tsd_analyses_recover(tsd_server *srv)
{
    recover_ctx c = {srv, 0, 0};
    if (tsd_db_analyses_unfinished(srv->db, recover_one, &c) != 0 || c.failed) return -1;
    return c.n;
}

/* tsd_db_analysis_fn: one entry of the list (ud: the array), with the whole
 * request when the store gave it (GET /v1/analyses/{id}). */
static void list_one(void *ud, const char *id, const char *kind, double created, int done,
                     int error_code, const char *asked_json, const char *request_json)
{
    char name[48];
    snprintf(name, sizeof name, "operations/%s", id);
    json_t *asked = json_loads(asked_json, 0, NULL);
    json_t *o = json_pack("{s:s,s:s,s:s,s:f,s:b,s:b,s:i,s:o}", "id", id, "name", name, "kind", kind,
                          "created", created, "done", done, "failed", error_code != 0, "error_code",
                          error_code, "asked", asked ? asked : json_object());
    if (o && request_json) {
        json_t *req = json_loads(request_json, JSON_DECODE_ANY, NULL);
        tsa_strip_comments(req); /* stored by an older daemon with them */
        json_object_set_new(o, "request", req ? req : json_null());
    }
    json_array_append_new(ud, o);
}

/* The stored analyses (id NULL: all, without bodies; else that one) as a new
 * array, or NULL with err filled. */
static json_t *read_analyses(tsd_server *srv, const char *id, ts_err *err)
{
    json_t *list = json_array();
    if (!list) {
        ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
        return NULL;
    }
    if (tsd_db_analyses(srv->db, id, list_one, list) != 0) {
        json_decref(list);
        if (id)
            ts_err_set(err, TS_ERR_IO, NULL, "cannot read analysis '%s' from the store", id);
        else
            ts_err_set(err, TS_ERR_IO, NULL, "cannot list the stored analyses");
        return NULL;
    }
    return list;
}

json_t *tsd_analyses_json(tsd_server *srv, ts_err *err)
{
    json_t *list = read_analyses(srv, NULL, err);
    return list ? json_pack("{s:o}", "analyses", list) : NULL;
}

json_t *tsd_analysis_json(tsd_server *srv, const char *id, ts_err *err)
{
    json_t *list = read_analyses(srv, id, err);
    if (!list) return NULL;
    json_t *one = json_incref(json_array_get(list, 0));
    json_decref(list);
    if (!one)
        ts_err_set(err, TS_ERR_NOTFOUND, NULL,
                   "no stored analysis '%s' (GET /v1/analyses lists them)", id);
    return one;
}

ts_rc tsd_analysis_delete(tsd_server *srv, const char *id, ts_err *err)
{
    int forgot = tsd_op_forget(srv, id);
    if (forgot < 0)
        return ts_err_set(err, TS_ERR_STATE, NULL,
                          "analysis '%s' is running: cancel it (POST "
                          "/v1/operations/%s:cancel), then delete it",
                          id, id);
    int deleted = 0;
    if (tsd_db_analysis_delete(srv->db, id, &deleted) != 0)
        return ts_err_set(err, TS_ERR_IO, NULL, "cannot delete analysis '%s' from the store", id);
    if (!deleted && !forgot) return ts_err_set(err, TS_ERR_NOTFOUND, NULL, "no stored analysis '%s'", id);
    return TS_OK;
}
