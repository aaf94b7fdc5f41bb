/*
 * db.h — persistence of sessions and their samples in SQLite (DATA_DIR/tanksimd.db).
 *
 * Tables:
 *   sessions(seq PK, id UNIQUE, created, preset, config JSON, nchannel, status,
 *            t, idx, error, channels JSON)  one row per session, updated on each
 *                                    batch; channels = {"sample_rate", "channels":
 *                                    [{name, unit, description}]} of its rows,
 *                                    stored at creation so that the rows stay
 *                                    readable when the model cannot be rebuilt
 *                                    (NULL in stores older than the column,
 *                                    which tsd_db_open adds)
 *   samples(seq, idx, vals BLOB)     one row per sample row: nchannel float64
 *                                    in channel order (native byte order)
 *   snapshots(seq, idx, t, blob)     ts_state_save snapshots, one per batch: the
 *                                    latest restarts an interrupted run; older
 *                                    ones let frames of past times be rebuilt
 *   analyses(id PK, kind, created, done, error_code, request, document)
 *                                    one row per analysis operation (engine
 *                                    map, tuning; analyses.h): its operation
 *                                    document as last stored (at start, then
 *                                    done), so a result outlives the daemon
 * WAL journal, synchronous=NORMAL: a committed batch survives a killed daemon
 * (not necessarily a power cut). Samples and the state they end at are
 * written in ONE transaction (tsd_db_append), so after a crash the stored
 * state always matches the last stored sample and a run continues from it
 * without gaps or duplicates.
 *
 * Threads: one writer connection and one reader connection, each behind its
 * own mutex; WAL lets readers (series, streams) proceed while a batch commits.
 * All calls return 0 on success, -1 on failure with the SQLite message
 * written to the daemon's log; a write refused because the disk holding the
 * store is full returns TSD_DB_FULL instead (a client is told so: 507).
 */
#ifndef TSD_DB_H
#define TSD_DB_H

#include <stddef.h>

#include "../sim/errors.h"

typedef struct tsd_db tsd_db;

#define TSD_DB_FULL (-3) /* a write refused: the disk is full (SQLITE_FULL) */

/* Open (create) DIR/tanksimd.db; NULL with a message in err on failure. */
tsd_db *tsd_db_open(const char *dir, char *err, size_t errlen);
void tsd_db_close(tsd_db *db); /* NULL is a no-op */

TS_MUST_CHECK int tsd_db_session_insert(tsd_db *db, long seq, const char *id, double created,
                                        const char *preset, const char *config_json, int nchannel,
                                        const char *channels_json, const char *status);
TS_MUST_CHECK int tsd_db_session_status(tsd_db *db, long seq, const char *status,
                                        const char *error);
TS_MUST_CHECK int tsd_db_session_delete(tsd_db *db, long seq);

/* One batch: rows[nrows][nchannel] with indexes first..first+nrows-1, then
 * the state snapshot (may be NULL) taken at the last row, and the session's
 * status/error/t/idx (error NULL: none) — all in one transaction. */
TS_MUST_CHECK int tsd_db_append(tsd_db *db, long seq, long first, long nrows, int nchannel,
                                const double *rows, const void *state, size_t state_size, double t,
                                long idx, const char *status, const char *error);

/* Visit every stored session in seq order (startup recovery). Its t and idx
 * are not passed: the state snapshot (tsd_db_state) is what a session
 * restarts from; the columns keep them for inspection of the file. */
typedef void (*tsd_db_session_fn)(void *ud, long seq, const char *id, double created,
                                  const char *preset, const char *config_json,
                                  const char *status, const char *error,
                                  const char *channels_json /* "" when none stored */);
TS_MUST_CHECK int tsd_db_sessions(tsd_db *db, tsd_db_session_fn fn, void *ud);

/* Store (insert or replace) analysis id: its kind, creation time [Unix s],
 * whether it is done, its error's google.rpc code (0: none), the request
 * (JSON text) and the operation document (JSON text). The request is kept
 * once, in its own column: the caller leaves metadata.request out of the
 * document (analyses.c puts it back when reading). */
TS_MUST_CHECK int tsd_db_analysis_put(tsd_db *db, const char *id, const char *kind, double created,
                                      int done, int error_code, const char *request_json,
                                      const char *document_json);

/* The stored operation document of analysis id and its request: *doc and
 * *request malloc'd JSON text (caller frees), both NULL when there is no
 * such analysis. */
TS_MUST_CHECK int tsd_db_analysis_get(tsd_db *db, const char *id, char **doc, char **request);

/* How many analyses are stored (*n). */
TS_MUST_CHECK int tsd_db_analysis_count(tsd_db *db, long *n);

/* Remove analysis id; *deleted = 1 when there was one. */
TS_MUST_CHECK int tsd_db_analysis_delete(tsd_db *db, const char *id, int *deleted);

/* Visit the stored analyses, newest first (id NULL), or analysis id only
 * (the rows are copied out before the first call, so fn may use the
 * database). asked_json: what was asked, small whatever the body — the
 * request's query parameters (schedule_mass, schedule_grade) with its
 * body's preset and engine.fidelity as "preset" and "engine_fidelity"
 * (null when absent), made by SQLite from the stored request so that only
 * that summary leaves the store. request_json: the whole request when
 * id is given, else NULL. */
typedef void (*tsd_db_analysis_fn)(void *ud, const char *id, const char *kind, double created,
                                   int done, int error_code, const char *asked_json,
                                   const char *request_json);
TS_MUST_CHECK int tsd_db_analyses(tsd_db *db, const char *id, tsd_db_analysis_fn fn, void *ud);

/* Visit the ids of the analyses stored as not done (start-up recovery),
 * without reading their requests or documents (copied out first, as above). */
typedef void (*tsd_db_analysis_id_fn)(void *ud, const char *id);
TS_MUST_CHECK int tsd_db_analyses_unfinished(tsd_db *db, tsd_db_analysis_id_fn fn, void *ud);

/* The stored state snapshot: *blob malloc'd (caller frees), *idx its index;
 * *blob = NULL when there is none. */
TS_MUST_CHECK int tsd_db_state(tsd_db *db, long seq, void **blob, size_t *size, long *idx);

/* The latest snapshot with index <= at (same contract as tsd_db_state). */
TS_MUST_CHECK int tsd_db_snapshot_at(tsd_db *db, long seq, long at, void **blob, size_t *size,
                                     long *idx);

/* The stored row with the highest index of a session: *idx (-1 when it has
 * none), *t its first value (the time channel), and, when row is not NULL,
 * its nchannel values. 0, -1 on a store error, -2 when that row is not
 * nchannel doubles wide (damaged; logged; *idx and, if it has one, *t set,
 * row zeroed). */
TS_MUST_CHECK int tsd_db_last_row(tsd_db *db, long seq, long *idx, double *t, double *row,
                                  int nchannel);

/* Read rows with from <= index <= to and (index - from) % every == 0, in
 * index order, at most max rows: index[] and rows[max][ncol] (caller
 * allocated), row k's value j being stored channel cols[j] (cols NULL: all
 * nchannel stored channels, ncol = nchannel), so a reader of a few channels
 * allocates for those only. Returns the count, -1 on a store error, or -2
 * when a row is not nchannel doubles wide (damaged; logged), index[0] then
 * naming it. *more = 1 when further rows match. */
long tsd_db_rows(tsd_db *db, long seq, long from, long to, long every, long max, int nchannel,
                 const int *cols, int ncol, long *index, double *rows, int *more);

#endif
