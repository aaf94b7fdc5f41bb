/*
 * operations.c — run and analysis operations (operations.h): a fixed-capacity
 * list kept in creation order; when full, the oldest finished operation is
 * dropped.
 */
#define _GNU_SOURCE
#include "operations.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../api/problem.h"
#include "pool.h"

struct tsd_op {
    char id[24];
    char sid[24];      /* "" for an analysis */
    const char *kind;  /* "run", or the analysis's kind */
    double t_start, until, t;          /* a run's times [s] */
    int parts_done, parts_total;       /* an analysis's progress */
    int cancel;                        /* an analysis was asked to stop */
    double wall_start, wall_last;
    double created;                    /* an analysis's start [Unix s] */
    json_t *request;                   /* an analysis's request (metadata.request) */
    int done;
    json_t *response, *error;
};

typedef struct tsd_ops {
    pthread_mutex_t mu;
    tsd_op *v[TSD_MAX_OPS];
    int n;
} tsd_ops;

int tsd_ops_init(tsd_server *srv)
{
    srv->ops = calloc(1, sizeof *srv->ops);
    if (!srv->ops) return -1;
    pthread_mutex_init(&srv->ops->mu, NULL);
    return 0;
}

static void op_free(tsd_op *op)
{
    json_decref(op->request);
    json_decref(op->response);
    json_decref(op->error);
    free(op);
}

void tsd_ops_free(tsd_server *srv)
{
    if (!srv->ops) return;
    for (int i = 0; i < srv->ops->n; i++)
        op_free(srv->ops->v[i]);
    pthread_mutex_destroy(&srv->ops->mu);
    free(srv->ops);
    srv->ops = NULL;
}

/* Drop the i-th operation of the list. Caller holds the lock. */
static void op_remove(tsd_ops *o, int i)
{
    op_free(o->v[i]);
    memmove(&o->v[i], &o->v[i + 1], sizeof o->v[0] * (size_t)(o->n - i - 1));
    o->n--;
}

/* Register op (kept in creation order; when full, the oldest finished one is
 * dropped); frees it and returns NULL when every kept operation is running. */
static tsd_op *op_register(tsd_server *srv, tsd_op *op)
{
    tsd_ops *o = srv->ops;
    tsd_random_id(op->id, sizeof op->id, "op");
    op->wall_start = op->wall_last = tsd_now();
    pthread_mutex_lock(&o->mu);
    if (o->n == TSD_MAX_OPS) {
        int drop = -1;
        for (int i = 0; i < o->n && drop < 0; i++)
            if (o->v[i]->done) drop = i;
        if (drop < 0) {
            pthread_mutex_unlock(&o->mu);
            op_free(op);
            return NULL;
        }
        op_remove(o, drop);
    }
    o->v[o->n++] = op;
    pthread_mutex_unlock(&o->mu);
    return op;
}

tsd_op *tsd_op_new(tsd_server *srv, const char *sid, double t_start, double until)
{
    tsd_op *op = calloc(1, sizeof *op);
    if (!op) return NULL;
    op->kind = "run";
    snprintf(op->sid, sizeof op->sid, "%s", sid);
    op->t_start = op->t = t_start;
    op->until = until;
    return op_register(srv, op);
}

tsd_op *tsd_op_new_analysis(tsd_server *srv, const char *kind, int parts_total, json_t *request)
{
    tsd_op *op = calloc(1, sizeof *op);
    if (!op) {
        json_decref(request);
        return NULL;
    }
    op->kind = kind;
    op->parts_total = parts_total;
    op->created = tsd_unix_now();
    op->request = request;
    return op_register(srv, op);
}

int tsd_op_forget(tsd_server *srv, const char *id)
{
    tsd_ops *o = srv->ops;
    int rc = 0;
    pthread_mutex_lock(&o->mu);
    for (int i = 0; i < o->n; i++) {
        if (strcmp(o->v[i]->id, id) != 0 || o->v[i]->sid[0]) continue;
        if (!o->v[i]->done) {
            rc = -1;
            break;
        }
        op_remove(o, i);
        rc = 1;
        break;
    }
    pthread_mutex_unlock(&o->mu);
    return rc;
}

void tsd_op_parts(tsd_server *srv, tsd_op *op, int parts_done, int parts_total)
{
    pthread_mutex_lock(&srv->ops->mu);
    op->parts_done = parts_done;
    op->parts_total = parts_total;
    op->wall_last = tsd_now();
    pthread_mutex_unlock(&srv->ops->mu);
}

int tsd_op_request_cancel(tsd_server *srv, const char *id, char *sid)
{
    int found = 0;
    pthread_mutex_lock(&srv->ops->mu);
    for (int i = 0; i < srv->ops->n; i++) {
        tsd_op *op = srv->ops->v[i];
        if (strcmp(op->id, id) != 0) continue;
        if (!op->done) op->cancel = 1;
        snprintf(sid, 24, "%s", op->sid);
        found = 1;
        break;
    }
    pthread_mutex_unlock(&srv->ops->mu);
    return found;
}

int tsd_op_cancel_requested(tsd_server *srv, tsd_op *op)
{
    pthread_mutex_lock(&srv->ops->mu);
    int c = op->cancel;
    pthread_mutex_unlock(&srv->ops->mu);
    return c;
}

const char *tsd_op_id(const tsd_op *op)
{
    return op->id;
}

void tsd_op_progress(tsd_server *srv, tsd_op *op, double t)
{
    pthread_mutex_lock(&srv->ops->mu);
    op->t = t;
    op->wall_last = tsd_now();
    pthread_mutex_unlock(&srv->ops->mu);
}

/* Caller holds the lock. */
static json_t *op_json(const tsd_op *op)
{
    int run = op->sid[0] != '\0';
    double progress;
    if (run) {
        double span = op->until - op->t_start;
        progress = span > 0 ? (op->t - op->t_start) / span : 1.0;
    } else {
        progress = op->parts_total > 0 ? (double)op->parts_done / op->parts_total : 0.0;
    }
    if (progress < 0) progress = 0;
    if (progress > 1) progress = 1;
    if (op->done && !op->error) progress = 1.0;
    /* in progress: the time since it started (between two progress reports
     * a paced run may wait long; its rate must not read as the slice's) */
    double wall = (op->done ? op->wall_last : tsd_now()) - op->wall_start;
    char name[48];
    snprintf(name, sizeof name, "operations/%s", op->id);
    json_t *j;
    if (run)
        j = json_pack("{s:s,s:s,s:b,s:{s:s,s:s,s:f,s:f,s:f,s:f,s:f,s:f}}", "name", name, "id",
                      op->id, "done", op->done, "metadata", "kind", op->kind, "session", op->sid,
                      "progress", progress, "t", op->t, "t_start", op->t_start, "until",
                      op->until, "wall_time_s", wall, "real_time_factor",
                      wall > 0 ? (op->t - op->t_start) / wall : 0.0);
    else
        j = json_pack("{s:s,s:s,s:b,s:{s:s,s:f,s:O,s:f,s:i,s:i,s:f}}", "name", name, "id",
                      op->id, "done", op->done, "metadata", "kind", op->kind, "created",
                      op->created, "request", op->request ? op->request : json_null(),
                      "progress", progress, "parts_done", op->parts_done, "parts_total",
                      op->parts_total, "wall_time_s", wall);
    if (j && op->done) {
        if (op->error)
            json_object_set(j, "error", op->error);
        else if (op->response)
            json_object_set(j, "response", op->response);
    }
    return j;
}

/* Hand op's final document (done at wall_last with response or error) to
 * persist: its code (0 stored, -1 refused, db.h TSD_DB_FULL: its disk is full), or
 * -2 without memory for the document. */
static int persist_done(tsd_server *srv, tsd_op *op, double wall_last, json_t *response,
                        json_t *error, int (*persist)(void *ud, json_t *doc), void *ud)
{
    pthread_mutex_lock(&srv->ops->mu);
    tsd_op done = *op; /* as it will be; op itself stays running until persisted */
    done.done = 1;
    done.wall_last = wall_last;
    done.response = response;
    done.error = error;
    json_t *doc = op_json(&done);
    pthread_mutex_unlock(&srv->ops->mu);
    int rc = !doc ? -2 : persist(ud, doc);
    json_decref(doc);
    return rc;
}

void tsd_op_finish_persisted(tsd_server *srv, tsd_op *op, json_t *response, json_t *error,
                             int (*persist)(void *ud, json_t *doc), void *ud)
{
    double wall_last = tsd_now(); /* the stored document's and GET's alike */
    int rc = persist ? persist_done(srv, op, wall_last, response, error, persist, ud) : 0;
    if (rc != 0 && response) { /* not a success a restart would lose */
        ts_err e;
        if (rc == -2)
            ts_err_set(&e, TS_ERR_NOMEM, NULL,
                       "the result was computed but there was no memory to store it");
        else
            tsd_err_store(srv, &e, rc, "the result was computed but the store could not keep it");
        json_decref(response);
        response = NULL;
        json_decref(error);
        error = tsd_op_error_json(&e);
        /* refused too: the last stored row (running, k of n parts) stays */
        (void)persist_done(srv, op, wall_last, NULL, error, persist, ud);
    }
    pthread_mutex_lock(&srv->ops->mu);
    op->done = 1;
    op->wall_last = wall_last;
    op->response = response;
    op->error = error;
    pthread_mutex_unlock(&srv->ops->mu);
}

void tsd_op_finish(tsd_server *srv, tsd_op *op, json_t *response, json_t *error)
{
    tsd_op_finish_persisted(srv, op, response, error, NULL, NULL);
}

json_t *tsd_op_error_json(const ts_err *e)
{
    /* the daemon stopping (a shutdown, or the crash found at the next
     * start-up) is not the client's cancel: 503 and UNAVAILABLE, retry */
    int stopped = e->code == TSD_ERR_SHUTDOWN, full = e->code == TSD_ERR_STORE_FULL;
    json_t *error = stopped ? tsa_problem(MHD_HTTP_SERVICE_UNAVAILABLE, "/problems/interrupted",
                                          "Interrupted: the daemon stopped", e->msg, NULL)
                            : tsd_problem_from_err(e, NULL);
    int code = stopped                                                      ? 14
               : e->code == TS_ERR_CANCELLED                                ? 1
               : e->code == TS_ERR_PARAM || e->code == TS_ERR_RANGE         ? 3
               : e->code == TS_ERR_LIMIT || e->code == TS_ERR_NOMEM || full ? 8
                                                                            : 13;
    json_object_set_new(error, "code", json_integer(code));
    json_object_set_new(error, "message", json_string(e->msg));
    return error;
}

void tsd_op_fail(tsd_server *srv, tsd_op *op, const ts_err *e)
{
    tsd_op_finish(srv, op, NULL, tsd_op_error_json(e));
}

json_t *tsd_op_json_of(tsd_server *srv, tsd_op *op)
{
    pthread_mutex_lock(&srv->ops->mu);
    json_t *j = op_json(op);
    pthread_mutex_unlock(&srv->ops->mu);
    return j;
}

json_t *tsd_op_json(tsd_server *srv, const char *id)
{
    json_t *j = NULL;
    pthread_mutex_lock(&srv->ops->mu);
    for (int i = 0; i < srv->ops->n && !j; i++)
        if (strcmp(srv->ops->v[i]->id, id) == 0) j = op_json(srv->ops->v[i]);
    pthread_mutex_unlock(&srv->ops->mu);
    return j;
}
