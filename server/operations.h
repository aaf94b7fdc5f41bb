/*
 * operations.h — long-running operations in the style of Google AIP-151:
 * POST /v1/sessions/{id}/run answers 202 with an operation; GET
 * /v1/operations/{id} shows {name, done, metadata{kind "run", session,
 * progress 0..1, t, until, real_time_factor}, error | response}; :cancel asks
 * it to stop. The analyses (POST /v1/engine-map, /v1/tune; analyses.h) are
 * operations too, without a session: metadata{kind, created, request,
 * progress, parts_done, parts_total, wall_time_s}; their cancel flag lives in
 * the operation.
 *
 * Operations live in memory (the last TSD_MAX_OPS; the oldest finished ones
 * are forgotten first). After a restart a run's operation is gone and the
 * session's status (interrupted) tells what happened; an analysis's document
 * is also stored (analyses.c), and GET finds it there. Every field is guarded by the
 * registry's one mutex; workers update progress through tsd_op_progress.
 */
#ifndef TSD_OPERATIONS_H
#define TSD_OPERATIONS_H

#include <jansson.h>

#include "../sim/errors.h"
#include "server.h"

#define TSD_MAX_OPS 1024

typedef struct tsd_op tsd_op;

TS_MUST_CHECK int tsd_ops_init(tsd_server *srv);
void tsd_ops_free(tsd_server *srv);

/* A new operation for a run of session sid from t_start to until. NULL on oom
 * or when every kept operation is still running. */
tsd_op *tsd_op_new(tsd_server *srv, const char *sid, double t_start, double until);
/* A new operation of an analysis (kind: a static string, "engine_map", "tune")
 * in parts_total parts, not tied to a session, made from request (a JSON
 * object shown as metadata.request; stolen, even on failure). NULL as
 * tsd_op_new (how many run at once is the caller's: server.h long jobs). */
tsd_op *tsd_op_new_analysis(tsd_server *srv, const char *kind, int parts_total, json_t *request);
/* Drop the analysis operation with this id from memory if it is done: 1
 * dropped, 0 no such analysis (run operations are never dropped this way),
 * -1 it is still running. */
int tsd_op_forget(tsd_server *srv, const char *id);
/* An analysis's progress: parts_done of its parts finished. */
void tsd_op_parts(tsd_server *srv, tsd_op *op, int parts_done, int parts_total);
/* Ask the operation with this id to stop: 0 when there is none; else 1, and
 * sid (24 bytes) receives its session ("" for an analysis, whose worker sees
 * tsd_op_cancel_requested; a run is stopped through its session). */
int tsd_op_request_cancel(tsd_server *srv, const char *id, char *sid);
int tsd_op_cancel_requested(tsd_server *srv, tsd_op *op);
const char *tsd_op_id(const tsd_op *op); /* stable while the op exists */
void tsd_op_progress(tsd_server *srv, tsd_op *op, double t);
/* Mark done with response or error (steals both; either may be NULL). */
void tsd_op_finish(tsd_server *srv, tsd_op *op, json_t *response, json_t *error);
/* The same, handing the operation's final document (borrowed; the one GET
 * shows afterwards) to persist(ud, doc) first, while the operation still
 * looks running: no client can see it done, and delete it, before it is
 * stored, and the registry cannot drop it meanwhile. persist may be NULL;
 * it returns 0 when stored (db.h TSD_DB_FULL: refused, the disk is full). A
 * response the store refused is not shown as a success that the next
 * restart would lose: the operation ends with an I/O error instead
 * (google.rpc 13, or 8 for a full disk; stored if the store takes that). */
void tsd_op_finish_persisted(tsd_server *srv, tsd_op *op, json_t *response, json_t *error,
                             int (*persist)(void *ud, json_t *doc), void *ud);
/* Mark done with the error e: its problem document plus AIP-151's google.rpc
 * "code" (1 CANCELLED, 3 INVALID_ARGUMENT for a parameter, 8
 * RESOURCE_EXHAUSTED for a limit or out of memory, 14 UNAVAILABLE for TSD_ERR_SHUTDOWN: the
 * daemon stopped during it, problem 503 /problems/interrupted; 13 INTERNAL
 * otherwise) and "message". */
void tsd_op_fail(tsd_server *srv, tsd_op *op, const ts_err *e);
/* That error member alone (new reference). */
json_t *tsd_op_error_json(const ts_err *e);

/* The operation document by id (new reference), NULL if unknown. */
json_t *tsd_op_json(tsd_server *srv, const char *id);
json_t *tsd_op_json_of(tsd_server *srv, tsd_op *op);

#endif
