/*
 * db.c — SQLite persistence (db.h). Prepared statements are made per call:
 * sqlite3_prepare_v2 of these short statements costs microseconds next to a
 * batch commit, and it keeps the module free of statement caches.
 */
#define _GNU_SOURCE
#include "db.h"

#include <pthread.h>
#include <sqlite3.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct tsd_db {
    sqlite3 *w;          /* writer connection */
    sqlite3 *r;          /* reader connection */
    pthread_mutex_t wmu; /* guards w */
    pthread_mutex_t rmu; /* guards r */
};

static const char schema[] =
    "PRAGMA journal_mode=WAL;"
    "PRAGMA synchronous=NORMAL;"
    "CREATE TABLE IF NOT EXISTS sessions(seq INTEGER PRIMARY KEY, id TEXT UNIQUE NOT NULL,"
    " created REAL, preset TEXT, config TEXT, nchannel INTEGER, status TEXT, t REAL,"
    " idx INTEGER, error TEXT, channels TEXT);"
    "CREATE TABLE IF NOT EXISTS samples(seq INTEGER, idx INTEGER, vals BLOB,"
    " PRIMARY KEY(seq, idx)) WITHOUT ROWID;"
    "CREATE TABLE IF NOT EXISTS snapshots(seq INTEGER, idx INTEGER, t REAL, blob BLOB,"
    " PRIMARY KEY(seq, idx)) WITHOUT ROWID;"
    "CREATE TABLE IF NOT EXISTS analyses(id TEXT PRIMARY KEY, kind TEXT, created REAL,"
    " done INTEGER, error_code INTEGER, request TEXT, document TEXT);";

/* PRAGMA user_version of the schema above (0: a store from before it was
 * set, brought up by migrate). A store from a newer build is refused: its
 * tables may mean something this build would misread or damage.
 *   1  sessions.channels
 *   2  SI units for the three engine fields that had their correlations'
 *      units: phi_curvature [1/rpm^2 -> s^2/rad^2], fmep_b [Pa/rpm ->
 *      Pa*s/rad], id_a [ms -> s] (a stored config holds every field) */
#define SCHEMA_VERSION 2

/* Version 1 -> 2, in the transaction that sets version 2 (never twice). */
static const char to_si_units[] =
    "BEGIN IMMEDIATE;"
    "UPDATE sessions SET config=json_set(config,'$.engine.phi_curvature',"
    " json_extract(config,'$.engine.phi_curvature')*91.18906527810401)"
    " WHERE json_valid(config) AND json_type(config,'$.engine.phi_curvature') IN "
    "('real','integer');"
    "UPDATE sessions SET config=json_set(config,'$.engine.fmep_b',"
    " json_extract(config,'$.engine.fmep_b')*9.549296585513721)"
    " WHERE json_valid(config) AND json_type(config,'$.engine.fmep_b') IN ('real','integer');"
    "UPDATE sessions SET config=json_set(config,'$.engine.id_a',"
    " json_extract(config,'$.engine.id_a')*0.001)"
    " WHERE json_valid(config) AND json_type(config,'$.engine.id_a') IN ('real','integer');"
    "PRAGMA user_version=2;"
    "COMMIT;";

/* A session deleted while it ran is marked so at once (its DELETE is
 * answered then) and removed by its worker; one the daemon died before
 * removing goes here, at the next start. */
static const char purge_deleted[] =
    "BEGIN IMMEDIATE;"
    "DELETE FROM samples WHERE seq IN (SELECT seq FROM sessions WHERE status='deleted');"
    "DELETE FROM snapshots WHERE seq IN (SELECT seq FROM sessions WHERE status='deleted');"
    "DELETE FROM sessions WHERE status='deleted';"
    "COMMIT;";

static void log_err(sqlite3 *c, const char *what)
{
    fprintf(stderr, "tanksimd: sqlite: %s: %s\n", what, sqlite3_errmsg(c));
}

/* Log a write the writer connection refused: TSD_DB_FULL when the disk is
 * full, else -1. Before the ROLLBACK, which would replace the error. */
static int write_failed(tsd_db *db, const char *what)
{
    log_err(db->w, what);
    return sqlite3_errcode(db->w) == SQLITE_FULL ? TSD_DB_FULL : -1;
}

static const char *col_text(sqlite3_stmt *st, int i)
{
    const unsigned char *s = sqlite3_column_text(st, i);
    return s ? (const char *)s : "";
}

/* SQLite's message for c's last error, with the system's reason when the
 * error came from the operating system ("unable to open database file" says
 * neither which file nor why: permission, a directory in its place, ...). */
static void sql_reason(sqlite3 *c, char *out, size_t n)
{
    if (!c) {
        snprintf(out, n, "no memory");
        return;
    }
    int e = sqlite3_system_errno(c);
    snprintf(out, n, "%s%s%s", sqlite3_errmsg(c), e ? ": " : "", e ? strerror(e) : "");
}

static sqlite3 *open_conn(const char *path, char *err, size_t errlen)
{
    sqlite3 *c = NULL;
    if (sqlite3_open_v2(path, &c, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX,
                        NULL) != SQLITE_OK) {
        char why[256];
        sql_reason(c, why, sizeof why);
        snprintf(err, errlen, "cannot open %s: %s", path, why);
        sqlite3_close(c);
        return NULL;
    }
    sqlite3_busy_timeout(c, 5000);
    return c;
}

/* Bring a store written by an older build up to this schema. Stores made
 * before the channels column (sessions.channels) get it, NULL for their
 * sessions: those derive their channels from the model, as before. */
static int migrate(sqlite3 *c, char *err, size_t errlen)
{
    sqlite3_stmt *st = NULL;
    int has = 0, s;
    if (sqlite3_prepare_v2(c, "PRAGMA table_info(sessions)", -1, &st, NULL) != SQLITE_OK) {
        snprintf(err, errlen, "schema: %s", sqlite3_errmsg(c));
        return -1;
    }
    while ((s = sqlite3_step(st)) == SQLITE_ROW)
        has |= strcmp(col_text(st, 1), "channels") == 0;
    sqlite3_finalize(st);
    if (s != SQLITE_DONE) {
        snprintf(err, errlen, "schema: %s", sqlite3_errmsg(c));
        return -1;
    }
    if (has) return 0;
    char *msg = NULL;
    if (sqlite3_exec(c, "ALTER TABLE sessions ADD COLUMN channels TEXT", NULL, NULL, &msg) !=
        SQLITE_OK) {
        snprintf(err, errlen, "schema: adding sessions.channels: %s", msg ? msg : "failed");
        sqlite3_free(msg);
        return -1;
    }
    return 0;
}

/* Run a script of statements (a whole transaction, BEGIN ... COMMIT, or a
 * single statement) on the writer connection w, rolled back if one fails: 0,
 * or -1 logged under what. The caller holds wmu, or is tsd_db_open (no
 * other thread yet). */
static int exec_script(sqlite3 *w, const char *sql, const char *what)
{
    char *msg = NULL;
    if (sqlite3_exec(w, sql, NULL, NULL, &msg) == SQLITE_OK) return 0;
    fprintf(stderr, "tanksimd: sqlite: %s: %s\n", what, msg ? msg : sqlite3_errmsg(w));
    sqlite3_free(msg);
    sqlite3_exec(w, "ROLLBACK", NULL, NULL, NULL);
    return -1;
}

/* 0 with the store's version in *version, or -1 with why in err when the
 * store is from a newer schema or its version cannot be read. */
static int check_version(sqlite3 *c, const char *path, long *version, char *err, size_t errlen)
{
    sqlite3_stmt *st = NULL;
    long v = -1;
    if (sqlite3_prepare_v2(c, "PRAGMA user_version", -1, &st, NULL) == SQLITE_OK &&
        sqlite3_step(st) == SQLITE_ROW)
        v = (long)sqlite3_column_int64(st, 0);
    sqlite3_finalize(st);
    if (v < 0) {
        char why[256];
        sql_reason(c, why, sizeof why);
        int code = sqlite3_errcode(c);
        snprintf(err, errlen, "%s: cannot read its schema version: %s%s", path, why,
                 code == SQLITE_CORRUPT || code == SQLITE_NOTADB
                     ? " (the store is damaged: `sqlite3 FILE .recover` may salvage its rows "
                       "into a new store; or move it and its -wal and -shm files aside to start "
                       "an empty one)"
                     : " (the -wal and -shm files beside it are read too)");
        return -1;
    }
    if (v > SCHEMA_VERSION) {
        snprintf(err, errlen,
                 "%s is from a newer tanksimd (store schema %ld; this build reads up to %d): "
                 "use that build, or another --data-dir",
                 path, v, SCHEMA_VERSION);
        return -1;
    }
    *version = v;
    return 0;
}

tsd_db *tsd_db_open(const char *dir, char *err, size_t errlen)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/tanksimd.db", dir);
    tsd_db *db = calloc(1, sizeof *db);
    if (!db) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    db->w = open_conn(path, err, errlen);
    /* a newer build's store is refused before anything is written to it */
    long version = 0;
    if (!db->w || check_version(db->w, path, &version, err, errlen) != 0) goto fail;
    char *msg = NULL;
    if (sqlite3_exec(db->w, schema, NULL, NULL, &msg) != SQLITE_OK) {
        snprintf(err, errlen, "%s: %s", path, msg ? msg : "schema failed");
        sqlite3_free(msg);
        goto fail;
    }
    if (migrate(db->w, err, errlen) != 0) goto fail;
    /* best effort: a full disk must not keep the daemon from serving what
     * is stored (a session still marked deleted is not loaded: session.c) */
    exec_script(db->w, purge_deleted, "removing sessions deleted during a run (next start)");
    /* ... but a store this process cannot write is refused: it would serve
     * reads and answer every new sample with "the store is failing". The
     * probe rewrites the version the store has: it may still need the SI
     * conversion below, which sets the new one in its own transaction. */
    char probe[64];
    snprintf(probe, sizeof probe, "PRAGMA user_version=%ld", version);
    if (sqlite3_exec(db->w, probe, NULL, NULL, NULL) != SQLITE_OK) {
        int code = sqlite3_errcode(db->w);
        char why[256];
        sql_reason(db->w, why, sizeof why);
        if (code == SQLITE_READONLY || code == SQLITE_PERM || code == SQLITE_CANTOPEN) {
            snprintf(err, errlen,
                     "%s cannot be written (%s): the daemon stores every sample; give the user "
                     "it runs as write access to it, to its -wal and -shm files and to their "
                     "directory",
                     path, why);
            goto fail;
        }
        fprintf(stderr, "tanksimd: sqlite: setting the schema version: %s\n", why);
    }
    /* not best effort: a session rebuilt from an unconverted config would
     * run another engine */
    if (version < 2 && exec_script(db->w, to_si_units, "converting engine fields to SI") != 0) {
        snprintf(err, errlen,
                 "%s: converting its stored configs to SI units failed (see the message above); "
                 "the store is unchanged",
                 path);
        goto fail;
    }
    db->r = open_conn(path, err, errlen);
    if (!db->r) goto fail;
    pthread_mutex_init(&db->wmu, NULL);
    pthread_mutex_init(&db->rmu, NULL);
    return db;
fail:
    sqlite3_close(db->w);
    sqlite3_close(db->r);
    free(db);
    return NULL;
}

void tsd_db_close(tsd_db *db)
{
    if (!db) return;
    sqlite3_close(db->r);
    sqlite3_close(db->w);
    pthread_mutex_destroy(&db->wmu);
    pthread_mutex_destroy(&db->rmu);
    free(db);
}

/* Bind the parameters described by fmt: 'i' long, 'd' double, 's' text
 * (NULL -> SQL NULL). */
static void bind_args(sqlite3_stmt *st, const char *fmt, va_list ap)
{
    for (int i = 0; fmt[i]; i++) {
        if (fmt[i] == 'i')
            sqlite3_bind_int64(st, i + 1, va_arg(ap, long));
        else if (fmt[i] == 'd')
            sqlite3_bind_double(st, i + 1, va_arg(ap, double));
        else {
            const char *s = va_arg(ap, const char *);
            if (s)
                sqlite3_bind_text(st, i + 1, s, -1, SQLITE_TRANSIENT);
            else
                sqlite3_bind_null(st, i + 1);
        }
    }
}

/* Run one statement with the parameters of fmt (bind_args) on the writer
 * connection; the rows it changed into *changes when that is not NULL. */
static int exec_w(tsd_db *db, long *changes, const char *sql, const char *fmt, ...)
{
    sqlite3_stmt *st = NULL;
    int rc = -1;
    pthread_mutex_lock(&db->wmu);
    if (sqlite3_prepare_v2(db->w, sql, -1, &st, NULL) != SQLITE_OK) goto out;
    va_list ap;
    va_start(ap, fmt);
    bind_args(st, fmt, ap);
    va_end(ap);
    rc = sqlite3_step(st) == SQLITE_DONE ? 0 : -1;
    if (rc == 0 && changes) *changes = sqlite3_changes(db->w);
out:
    if (rc != 0) rc = write_failed(db, sql);
    sqlite3_finalize(st);
    pthread_mutex_unlock(&db->wmu);
    return rc;
}

int tsd_db_session_insert(tsd_db *db, long seq, const char *id, double created, const char *preset,
                          const char *config_json, int nchannel, const char *channels_json,
                          const char *status)
{
    return exec_w(db, NULL,
                  "INSERT INTO sessions(seq,id,created,preset,config,nchannel,channels,status,t,"
                  "idx,error) VALUES(?,?,?,?,?,?,?,?,0,0,NULL)",
                  "isdssiss", seq, id, created, preset, config_json, (long)nchannel, channels_json,
                  status);
}

/* A session marked deleted keeps that status: a worker's late status write
 * must not bring it back (purge_deleted removes it at the next start). */
int tsd_db_session_status(tsd_db *db, long seq, const char *status, const char *error)
{
    return exec_w(db, NULL,
                  "UPDATE sessions SET status=?, error=? WHERE seq=? AND status<>'deleted'", "ssi",
                  status, error && error[0] ? error : NULL, seq);
}

/* A script of statements on the writer, its text from printf(fmt, ...) —
 * integers only (a seq, an index), which are safe to print into SQL. */
static int exec_script_w(tsd_db *db, const char *what, const char *fmt, ...)
{
    char sql[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(sql, sizeof sql, fmt, ap);
    va_end(ap);
    pthread_mutex_lock(&db->wmu);
    int rc = exec_script(db->w, sql, what);
    pthread_mutex_unlock(&db->wmu);
    return rc;
}

int tsd_db_session_delete(tsd_db *db, long seq)
{
    /* one transaction: a crash between separate DELETEs left a session row
     * without its rows */
    int rc = exec_script_w(db, "delete session",
                           "BEGIN IMMEDIATE; DELETE FROM sessions WHERE seq=%ld; DELETE FROM "
                           "samples WHERE seq=%ld; DELETE FROM snapshots WHERE seq=%ld; COMMIT;",
                           seq, seq, seq);
    /* The deletes went through the write-ahead log page by page (a long run's
     * rows: hundreds of MB); copy them back and truncate the log, so a delete
     * does not leave the store larger than before it. The freed pages stay in
     * the database file, where SQLite reuses them for the next rows. Best
     * effort: a reader in the log's middle only shortens the checkpoint. */
    pthread_mutex_lock(&db->wmu);
    sqlite3_wal_checkpoint_v2(db->w, NULL, SQLITE_CHECKPOINT_TRUNCATE, NULL, NULL);
    pthread_mutex_unlock(&db->wmu);
    return rc;
}

int tsd_db_append(tsd_db *db, long seq, long first, long nrows, int nchannel, const double *rows,
                  const void *state, size_t state_size, double t, long idx, const char *status,
                  const char *error)
{
    sqlite3_stmt *ins = NULL, *st = NULL, *up = NULL;
    int rc = -1;
    const char *what = "BEGIN";
    pthread_mutex_lock(&db->wmu);
    if (sqlite3_exec(db->w, "BEGIN IMMEDIATE", NULL, NULL, NULL) != SQLITE_OK) goto out;
    what = "insert samples";
    if (sqlite3_prepare_v2(db->w, "INSERT OR REPLACE INTO samples(seq,idx,vals) VALUES(?,?,?)", -1,
                           &ins, NULL) != SQLITE_OK)
        goto rollback;
    for (long k = 0; k < nrows; k++) {
        sqlite3_bind_int64(ins, 1, seq);
        sqlite3_bind_int64(ins, 2, first + k);
        sqlite3_bind_blob(ins, 3, rows + (size_t)k * (size_t)nchannel,
                          (int)(sizeof(double) * (size_t)nchannel), SQLITE_STATIC);
        if (sqlite3_step(ins) != SQLITE_DONE) goto rollback;
        sqlite3_reset(ins);
    }
    if (state) {
        what = "save state";
        if (sqlite3_prepare_v2(db->w,
                               "INSERT OR REPLACE INTO snapshots(seq,idx,t,blob) VALUES(?,?,?,?)",
                               -1, &st, NULL) != SQLITE_OK)
            goto rollback;
        sqlite3_bind_int64(st, 1, seq);
        sqlite3_bind_int64(st, 2, idx);
        sqlite3_bind_double(st, 3, t);
        sqlite3_bind_blob(st, 4, state, (int)state_size, SQLITE_STATIC);
        if (sqlite3_step(st) != SQLITE_DONE) goto rollback;
    }
    what = "update session";
    if (sqlite3_prepare_v2(db->w,
                           "UPDATE sessions SET t=?, idx=?, status=?, error=? WHERE seq=? AND "
                           "status<>'deleted'",
                           -1, &up, NULL) != SQLITE_OK)
        goto rollback;
    sqlite3_bind_double(up, 1, t);
    sqlite3_bind_int64(up, 2, idx);
    sqlite3_bind_text(up, 3, status, -1, SQLITE_STATIC);
    if (error && error[0])
        sqlite3_bind_text(up, 4, error, -1, SQLITE_STATIC);
    else
        sqlite3_bind_null(up, 4);
    sqlite3_bind_int64(up, 5, seq);
    if (sqlite3_step(up) != SQLITE_DONE) goto rollback;
    what = "COMMIT";
    if (sqlite3_exec(db->w, "COMMIT", NULL, NULL, NULL) != SQLITE_OK) goto rollback;
    rc = 0;
    goto out;
rollback:
    rc = write_failed(db, what);
    sqlite3_exec(db->w, "ROLLBACK", NULL, NULL, NULL);
    what = NULL;
out:
    if (rc != 0 && what) rc = write_failed(db, what);
    sqlite3_finalize(ins);
    sqlite3_finalize(st);
    sqlite3_finalize(up);
    pthread_mutex_unlock(&db->wmu);
    return rc;
}

/* The rows of a reader query, copied out (protected values,
 * sqlite3_value_dup) so that the caller may use the database again while it
 * walks them: row i's column k is v[i * ncol + k]. */
typedef struct row_copy {
    sqlite3_value **v;
    long n;
    int ncol;
} row_copy;

static void free_rows(row_copy *t)
{
    for (long i = 0; i < t->n * t->ncol; i++)
        sqlite3_value_free(t->v[i]);
    free(t->v);
    memset(t, 0, sizeof *t);
}

/* Run sql with the parameters of fmt (bind_args) on the reader connection:
 * 0, or -1 with the SQLite message logged under what (t is then empty). */
static int select_rows(tsd_db *db, const char *sql, const char *what, row_copy *t,
                       const char *fmt, ...)
{
    sqlite3_stmt *st = NULL;
    long cap = 0;
    int rc = -1, s = SQLITE_ERROR;
    memset(t, 0, sizeof *t);
    pthread_mutex_lock(&db->rmu);
    if (sqlite3_prepare_v2(db->r, sql, -1, &st, NULL) != SQLITE_OK) goto out;
    va_list ap;
    va_start(ap, fmt);
    bind_args(st, fmt, ap);
    va_end(ap);
    t->ncol = sqlite3_column_count(st);
    while ((s = sqlite3_step(st)) == SQLITE_ROW) {
        if (t->n == cap) {
            cap = cap ? 2 * cap : 64;
            sqlite3_value **nv = realloc(t->v, sizeof *nv * (size_t)(cap * t->ncol));
            if (!nv) goto out;
            t->v = nv;
        }
        sqlite3_value **row = t->v + t->n * t->ncol;
        int k = 0;
        while (k < t->ncol && (row[k] = sqlite3_value_dup(sqlite3_column_value(st, k))))
            k++;
        if (k < t->ncol) { /* out of memory: free this row's copies */
            while (k-- > 0)
                sqlite3_value_free(row[k]);
            goto out;
        }
        t->n++;
    }
    rc = s == SQLITE_DONE ? 0 : -1;
out:
    if (rc) log_err(db->r, what);
    sqlite3_finalize(st);
    pthread_mutex_unlock(&db->rmu);
    if (rc) free_rows(t);
    return rc;
}

/* A copied value as text, "" for NULL. */
static const char *val_text(sqlite3_value *v)
{
    const unsigned char *s = sqlite3_value_text(v);
    return s ? (const char *)s : "";
}

int tsd_db_sessions(tsd_db *db, tsd_db_session_fn fn, void *ud)
{
    row_copy t; /* fn may read the database again (state blobs) */
    if (select_rows(db,
                    "SELECT seq,id,created,preset,config,status,error,channels"
                    " FROM sessions ORDER BY seq",
                    "list sessions", &t, "") != 0)
        return -1;
    for (long i = 0; i < t.n; i++) {
        sqlite3_value **c = t.v + i * t.ncol;
        fn(ud, (long)sqlite3_value_int64(c[0]), val_text(c[1]), sqlite3_value_double(c[2]),
           val_text(c[3]), val_text(c[4]), val_text(c[5]), val_text(c[6]), val_text(c[7]));
    }
    free_rows(&t);
    return 0;
}

/* ---- analyses ------------------------------------------------------------------ */

int tsd_db_analysis_put(tsd_db *db, const char *id, const char *kind, double created, int done,
                        int error_code, const char *request_json, const char *document_json)
{
    return exec_w(
        db, NULL,
        "INSERT OR REPLACE INTO analyses(id,kind,created,done,error_code,request,document)"
        " VALUES(?,?,?,?,?,?,?)",
        "ssdiiss", id, kind, created, (long)done, (long)error_code, request_json, document_json);
}

int tsd_db_analysis_get(tsd_db *db, const char *id, char **doc, char **request)
{
    row_copy t;
    *doc = *request = NULL;
    if (select_rows(db, "SELECT document, request FROM analyses WHERE id=?", "read analysis", &t,
                    "s", id))
        return -1;
    int rc = 0;
    if (t.n == 1 && !(*doc = strdup(val_text(t.v[0])))) rc = -1;
    if (rc == 0 && t.n == 1 && !(*request = strdup(val_text(t.v[1])))) {
        free(*doc);
        *doc = NULL;
        rc = -1;
    }
    free_rows(&t);
    return rc;
}

int tsd_db_analysis_count(tsd_db *db, long *n)
{
    row_copy t;
    *n = 0;
    if (select_rows(db, "SELECT COUNT(*) FROM analyses", "count analyses", &t, "")) return -1;
    if (t.n == 1) *n = (long)sqlite3_value_int64(t.v[0]);
    free_rows(&t);
    return 0;
}

int tsd_db_analysis_delete(tsd_db *db, const char *id, int *deleted)
{
    long n = 0;
    int rc = exec_w(db, &n, "DELETE FROM analyses WHERE id=?", "s", id);
    *deleted = rc == 0 && n > 0;
    return rc;
}

/* The list's summary of a stored request (db.h tsd_db_analyses): computed
 * by SQLite, so a large body is parsed there and never copied out; '{}' for
 * a request that is not a JSON object (a store written by hand). */
#define ASKED_SQL                                                                                  \
    "CASE WHEN json_valid(request) AND json_type(request)='object' THEN"                           \
    " json_set(json_remove(request,'$.body'),'$.preset',json_extract(request,'$.body.preset'),"    \
    "'$.engine_fidelity',json_extract(request,'$.body.engine.fidelity')) ELSE '{}' END"

int tsd_db_analyses(tsd_db *db, const char *id, tsd_db_analysis_fn fn, void *ud)
{
    row_copy t; /* fn may use the database */
    char sql[640];
    snprintf(sql, sizeof sql,
             "SELECT id,kind,created,done,error_code," ASKED_SQL ",%s FROM analyses%s"
             " ORDER BY created DESC, id",
             id ? "request" : "NULL", id ? " WHERE id=?" : "");
    if ((id ? select_rows(db, sql, "list analyses", &t, "s", id)
            : select_rows(db, sql, "list analyses", &t, "")) != 0)
        return -1;
    for (long i = 0; i < t.n; i++) {
        sqlite3_value **c = t.v + i * t.ncol;
        fn(ud, val_text(c[0]), val_text(c[1]), sqlite3_value_double(c[2]), sqlite3_value_int(c[3]),
           sqlite3_value_int(c[4]), val_text(c[5]), id ? val_text(c[6]) : NULL);
    }
    free_rows(&t);
    return 0;
}

int tsd_db_analyses_unfinished(tsd_db *db, tsd_db_analysis_id_fn fn, void *ud)
{
    row_copy t; /* fn reads and writes the database (analyses.c recovery) */
    if (select_rows(db, "SELECT id FROM analyses WHERE done=0 ORDER BY created, id",
                    "list unfinished analyses", &t, "") != 0)
        return -1;
    for (long i = 0; i < t.n; i++)
        fn(ud, val_text(t.v[i * t.ncol]));
    free_rows(&t);
    return 0;
}

/* ---- state snapshots ------------------------------------------------------------ */

int tsd_db_state(tsd_db *db, long seq, void **blob, size_t *size, long *idx)
{
    return tsd_db_snapshot_at(db, seq, 1L << 62, blob, size, idx);
}

int tsd_db_snapshot_at(tsd_db *db, long seq, long at, void **blob, size_t *size, long *idx)
{
    sqlite3_stmt *st = NULL;
    int rc = -1;
    *blob = NULL;
    *size = 0;
    pthread_mutex_lock(&db->rmu);
    if (sqlite3_prepare_v2(db->r,
                           "SELECT idx, blob FROM snapshots WHERE seq=? AND idx<=?"
                           " ORDER BY idx DESC LIMIT 1",
                           -1, &st, NULL) != SQLITE_OK)
        goto out;
    sqlite3_bind_int64(st, 1, seq);
    sqlite3_bind_int64(st, 2, at);
    int s = sqlite3_step(st);
    if (s == SQLITE_ROW) {
        size_t n = (size_t)sqlite3_column_bytes(st, 1);
        const void *p = sqlite3_column_blob(st, 1);
        *blob = malloc(n ? n : 1);
        if (!*blob) goto out;
        if (n) memcpy(*blob, p, n);
        *size = n;
        *idx = (long)sqlite3_column_int64(st, 0);
        rc = 0;
    } else {
        rc = s == SQLITE_DONE ? 0 : -1;
    }
out:
    if (rc) log_err(db->r, "read state");
    sqlite3_finalize(st);
    pthread_mutex_unlock(&db->rmu);
    return rc;
}

/* Whether a stored row's blob of nb bytes is one row of nchannel doubles (a
 * row of another width is damage: the daemon writes every row of a session
 * at its width; it was read zero-filled or cut once, and served so). */
static int row_intact(long seq, long idx, size_t nb, int nchannel)
{
    if (nb == sizeof(double) * (size_t)nchannel) return 1;
    fprintf(stderr,
            "tanksimd: store: session %ld row %ld has %zu bytes, not %zu (%d channels): damaged\n",
            seq, idx, nb, sizeof(double) * (size_t)nchannel, nchannel);
    return 0;
}

int tsd_db_last_row(tsd_db *db, long seq, long *idx, double *t, double *row, int nchannel)
{
    sqlite3_stmt *st = NULL;
    int rc = -1;
    *idx = -1;
    *t = 0.0;
    pthread_mutex_lock(&db->rmu);
    if (sqlite3_prepare_v2(db->r,
                           "SELECT idx, vals FROM samples WHERE seq=? ORDER BY idx DESC LIMIT 1",
                           -1, &st, NULL) != SQLITE_OK)
        goto out;
    sqlite3_bind_int64(st, 1, seq);
    int s = sqlite3_step(st);
    if (s == SQLITE_ROW) {
        *idx = (long)sqlite3_column_int64(st, 0);
        const void *b = sqlite3_column_blob(st, 1);
        size_t nb = (size_t)sqlite3_column_bytes(st, 1);
        if (b && nb >= sizeof(double)) memcpy(t, b, sizeof(double));
        /* no channels asked: the index and time alone */
        int intact = (!row && nchannel == 0) || (b && row_intact(seq, *idx, nb, nchannel));
        if (row && intact)
            memcpy(row, b, nb);
        else if (row)
            memset(row, 0, sizeof(double) * (size_t)nchannel);
        rc = intact ? 0 : -2; /* -2: row_intact said why */
    } else {
        rc = s == SQLITE_DONE ? 0 : -1;
    }
out:
    if (rc == -1) log_err(db->r, "read last sample");
    sqlite3_finalize(st);
    pthread_mutex_unlock(&db->rmu);
    return rc;
}

long tsd_db_rows(tsd_db *db, long seq, long from, long to, long every, long max, int nchannel,
                 const int *cols, int ncol, long *index, double *rows, int *more)
{
    sqlite3_stmt *st = NULL;
    long n = -1;
    *more = 0;
    if (every < 1) every = 1;
    pthread_mutex_lock(&db->rmu);
    const char *sql = every == 1
                          ? "SELECT idx, vals FROM samples WHERE seq=?1 AND idx BETWEEN ?2 AND ?3"
                            " ORDER BY idx"
                          : "SELECT idx, vals FROM samples WHERE seq=?1 AND idx BETWEEN ?2 AND ?3"
                            " AND (idx - ?2) % ?4 = 0 ORDER BY idx";
    if (sqlite3_prepare_v2(db->r, sql, -1, &st, NULL) != SQLITE_OK) goto out;
    sqlite3_bind_int64(st, 1, seq);
    sqlite3_bind_int64(st, 2, from);
    sqlite3_bind_int64(st, 3, to);
    if (every > 1) sqlite3_bind_int64(st, 4, every);
    n = 0;
    int s;
    const size_t rowbytes = sizeof(double) * (size_t)nchannel;
    while ((s = sqlite3_step(st)) == SQLITE_ROW) {
        if (n == max) {
            *more = 1;
            break;
        }
        index[n] = (long)sqlite3_column_int64(st, 0);
        const void *b = sqlite3_column_blob(st, 1);
        size_t nb = (size_t)sqlite3_column_bytes(st, 1);
        if (!b || !row_intact(seq, index[n], nb, nchannel)) {
            index[0] = index[n];
            n = -2;
            break;
        }
        if (!cols) {
            memcpy(rows + (size_t)n * (size_t)nchannel, b, rowbytes);
        } else { /* the blob's doubles may be unaligned: copy each */
            double *dst = rows + (size_t)n * (size_t)ncol;
            for (int j = 0; j < ncol; j++) {
                dst[j] = 0.0;
                if (cols[j] >= 0 && cols[j] < nchannel)
                    memcpy(&dst[j], (const char *)b + sizeof(double) * (size_t)cols[j],
                           sizeof(double));
            }
        }
        n++;
    }
    if (n >= 0 && s != SQLITE_ROW && s != SQLITE_DONE) n = -1;
out:
    if (n == -1) log_err(db->r, "read samples");
    sqlite3_finalize(st);
    pthread_mutex_unlock(&db->rmu);
    return n;
}
