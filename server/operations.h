/*
 * operations.h — long-running operations in the style of Google AIP-151:
 * POST /v1/sessions/{id}/run answers 202 with an operation; GET
 * /v1/operations/{id} shows {name, done, metadata{kind "run", session,
 * progress 0..1, t, until, real_time_factor}, error | response}; :cancel asks
 * it to stop. The analyses (POST /v1/engine-map, /v1/tune; analyses.h) are
 * operations too, without a session: metadata{kind, progress, parts_done,
 * parts_total, wall_time_s}; their cancel flag lives in the operation.
 *
 * Operations live in memory (the last TSD_MAX_OPS; the oldest finished ones
 * are forgotten first) — after a restart they are gone and the session's
 * status (interrupted) tells what happened. Every field is guarded by the
 * registry's one mutex; workers update progress through tsd_op_progress.
 */
#ifndef TSD_OPERATIONS_H
#define TSD_OPERATIONS_H

#include <jansson.h>

#include "server.h"

#define TSD_MAX_OPS 1024

typedef struct tsd_op tsd_op;

int tsd_ops_init(tsd_server *srv);
void tsd_ops_free(tsd_server *srv);

/* A new operation for a run of session sid from t_start to until. NULL on oom
 * or when every kept operation is still running. */
tsd_op *tsd_op_new(tsd_server *srv, const char *sid, double t_start, double until);
/* A new operation of an analysis (kind: a static string, "engine_map", "tune")
 * in parts_total parts, not tied to a session. NULL as tsd_op_new. */
tsd_op *tsd_op_new_analysis(tsd_server *srv, const char *kind, int parts_total);
/* An analysis's progress: parts_done of its parts finished. */
void tsd_op_parts(tsd_server *srv, tsd_op *op, int parts_done, int parts_total);
/* Ask the analysis with this id to stop: 1 if it is a running analysis (its
 * worker sees tsd_op_cancel_requested), 0 otherwise (a run is cancelled
 * through its session). */
int tsd_op_request_cancel(tsd_server *srv, const char *id);
int tsd_op_cancel_requested(tsd_server *srv, tsd_op *op);
const char *tsd_op_id(const tsd_op *op); /* stable while the op exists */
void tsd_op_progress(tsd_server *srv, tsd_op *op, double t);
/* Mark done with response or error (steals both; either may be NULL). */
void tsd_op_finish(tsd_server *srv, tsd_op *op, json_t *response, json_t *error);

/* The operation document by id (new reference), NULL if unknown. *sid (if
 * non-NULL, 24 bytes) receives its session id; *done its state. */
json_t *tsd_op_json(tsd_server *srv, const char *id, char *sid, int *done);
json_t *tsd_op_json_of(tsd_server *srv, tsd_op *op);

#endif
