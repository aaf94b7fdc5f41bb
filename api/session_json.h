/*
 * session_json.h — JSON and text shapes of the daemon's session resources:
 * request bodies in (step/run numbers, the session-create document), and out
 * the session object, channel lists, latest values, sample rows as CSV,
 * NDJSON/SSE lines and the columnar series document.
 *
 * Why here and not in server/: handlers never parse or build JSON by hand
 * (style guide, rule 13), so the mapping can be tested without HTTP and reused
 * by other front ends. Nothing here knows about sockets or SQLite.
 *
 * Ownership: json_t* results are NEW references (caller json_decref);
 * tsa_buf memory is the caller's (tsa_buf_free). All numbers are SI, with the
 * unit of every channel given beside it (a tsa_channels table: the model.h
 * channel registry or a list stored with the rows).
 */
#ifndef TSA_SESSION_JSON_H
#define TSA_SESSION_JSON_H

#include <jansson.h>
#include <stddef.h>

#include "../sim/model.h"

/* ---- growable text buffer ------------------------------------------------ */

typedef struct tsa_buf {
    char *p;    /* NUL-terminated text (NULL while empty) */
    size_t n;   /* bytes used, without the NUL */
    size_t cap; /* bytes allocated */
    int oom;    /* set once an allocation failed; later appends are dropped */
} tsa_buf;

void tsa_buf_printf(tsa_buf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void tsa_buf_put(tsa_buf *b, const char *s, size_t n);
void tsa_buf_free(tsa_buf *b);
/* Hand the text to the caller (malloc'd, free()) and empty the buffer; NULL on oom. */
char *tsa_buf_take(tsa_buf *b, size_t *len);

/* ---- request bodies ------------------------------------------------------- */

/* Parse a request body that must be a JSON object. Malformed JSON ->
 * TS_ERR_PARAM with the pointer of where the parser stopped (json_error.h)
 * and its line/column; an empty body or another type -> TS_ERR_PARAM at the
 * root (at_root). New ref. */
json_t *tsa_parse_object(const char *body, size_t len, ts_err *err);

/* One numeric member of a small request body ({"duration": 0.5}). */
typedef struct tsa_num_field {
    const char *name; /* member name; its pointer is "/name" */
    int required;     /* 1: missing is an error */
    double min, max;  /* closed range */
    double *out;      /* receives the value when present */
    int *present;     /* may be NULL; set to 1 when present */
    const char *unit; /* SI unit for the range message ("s"); NULL: none */
} tsa_num_field;

/* Read the fields from obj; unknown members, wrong types, missing required
 * members and out-of-range values each append {pointer, message} to errors
 * (may be NULL) and the first goes to err. TS_OK, TS_ERR_PARAM or TS_ERR_RANGE. */
TS_MUST_CHECK ts_rc tsa_read_numbers(const json_t *obj, const tsa_num_field *f, int nf,
                                     json_t *errors, ts_err *err);

/* ---- channel tables ------------------------------------------------------- */

/* The channel table of a series of rows: entry i names and gives the SI unit
 * of column i of every row (v[0] is time "t" [s]); period is the sample period
 * [s] (1 / run.sample_rate; > 0 and finite: the shapes print 1 / period as
 * the sample_rate, and a non-finite one is not JSON). Every text and JSON shape below takes one, so the
 * same shapes serve a live model (tsa_channels_from_model) and rows stored
 * with a list of their own (the daemon's store, server/channels.h) alike.
 *
 * Ownership: a view, nothing is owned. v and the strings it points to are the
 * filler's and must outlive every use of the view. */
typedef struct tsa_channels {
    const ts_channel *v; /* n entries */
    int n;
    double period; /* sample period [s] */
} tsa_channels;

/* Fill c with m's table: the n = ts_model_nchannel(m) entries are copied into
 * store (cap entries, the caller's), their strings stay m's. So c is valid
 * while both store and m live. TS_ERR_LIMIT when m has more than cap channels
 * (c is then left empty). */
TS_MUST_CHECK ts_rc tsa_channels_from_model(tsa_channels *c, ts_channel *store, int cap,
                                            const ts_model *m, ts_err *err);

/* Column of the channel named name, -1 when c has none. */
int tsa_channel_index(const tsa_channels *c, const char *name);

/* [{"name","unit","description"}] of the n channels idx names, in that order
 * (idx NULL: every channel). */
json_t *tsa_channels_json(const tsa_channels *c, const int *idx, int n);

/* {"name": value, ...} of one row of c->n values. */
json_t *tsa_values_json(const tsa_channels *c, const double *row);

/* A JSON number, or null for NaN and infinities (json_real would give NULL,
 * which an append or a pack drops or fails on). New reference. */
json_t *tsa_json_real(double v);

/* Parse a comma-separated channel list ("vehicle.speed,sprocket.torque") into
 * channel indexes; "t" (index 0) is always first and never repeated. NULL or ""
 * selects every channel. param names where the list came from (the query
 * parameter, e.g. "channels"): errors carry pointer "/<param>" and name it.
 * Unknown names -> TS_ERR_NOTFOUND. Writes at most max indexes to idx, the
 * count to *n. */
TS_MUST_CHECK ts_rc tsa_channel_select(const tsa_channels *c, const char *param, const char *list,
                                       int *idx, int max, int *n, ts_err *err);

/* ---- sample rows as text --------------------------------------------------- */

/* "name [unit],..." header line for the selected channels. */
void tsa_csv_header(tsa_buf *b, const tsa_channels *c, const int *idx, int n);
/* One CSV line of the selected values of a full row. */
void tsa_csv_row(tsa_buf *b, const double *row, const int *idx, int n);
/* One JSON object {"index":k,"t":t,"values":{name:value}} without newline. */
void tsa_row_json(tsa_buf *b, const tsa_channels *c, long index, const double *row, const int *idx,
                  int n);

/* The columnar series document:
 * {"session","sample_rate","every","count","channels":[{"name","unit","values":[...]}],
 *  "index":[...], "next_page_token"?: "K"} — rows are full rows (c->n values
 * each), index[k] the sample index of row k; next_token NULL when this page is
 * the last. */
void tsa_series_json(tsa_buf *b, const char *session, const tsa_channels *c, const int *idx, int n,
                     const long *index, const double *rows, long nrows, long every,
                     const char *next_token);

/* ---- integrator work ------------------------------------------------------- */

/* [{"integrator", "method", "steps", "rhs_evals", "jac_evals", "lin_setups",
 *   "err_test_fails", "newton_iters", "newton_fails"}], counts as integers,
 * null where the method has none (ts_integrator_stats: -1). New reference. */
json_t *tsa_integrators_json(const ts_integrator_stats *s, int n);

/* ---- run figures ------------------------------------------------------------- */

/* How many figures tsa_model_metrics makes room for at first; a scenario with
 * more gets a second, exact-size call (ts_model_metrics counts past its max). */
#define TSA_METRICS_FIRST 32

/* Every figure ts_model_metrics gives for rows (nrows rows of the model's
 * channels), none dropped: *out malloc'd (the caller frees it, also when *n
 * is 0), *n their count. TS_ERR_NOMEM, or TS_ERR_INTERNAL when the count
 * changed between the two calls. Threads: as ts_model_metrics (serialise it
 * with every FFT user). */
TS_MUST_CHECK ts_rc tsa_model_metrics(const ts_model *m, const double *rows, long nrows,
                                      ts_metric **out, int *n, ts_err *err);

/* [{"name","unit","value","description"}] of n figures in order, value null
 * when not finite (the run did not reach it). New reference. */
json_t *tsa_metrics_json(const ts_metric *mt, int n);

/* GET /v1/sessions/{id}/summary: a session's figures over its stored rows. */
typedef struct tsa_run_summary {
    const char *id;
    const char *kind;   /* scenario kind */
    const char *status; /* session status when the rows were read */
    int complete;       /* 1: the run reached run.duration (status done) */
    double t;           /* time of the last row used [s] */
    long rows;          /* rows used: indexes 0..rows-1 */
    int dof;            /* ts_model_dof */
    const ts_metric *metrics;
    int nmetric;
} tsa_run_summary;

/* {"id","kind","status","complete","t","rows","dof","metrics":[tsa_metrics_json]}.
 * New reference (NULL when out of memory). */
json_t *tsa_run_summary_json(const tsa_run_summary *v);

/* ---- the session resource ------------------------------------------------ */

typedef struct tsa_session_view {
    const char *id;
    const char *status;     /* created | running | paused | done | failed | interrupted */
    const char *preset;     /* "" when none */
    double created;         /* Unix time [s] */
    double t;               /* time of the latest sample [s] */
    long index;             /* index of the latest sample */
    long persisted;         /* samples stored (index of the last stored row + 1) */
    const json_t *config;   /* resolved config document (may be NULL in summaries) */
    const ts_model *m;      /* kind, duration (may be NULL: no model, or not the rows') */
    const char *kind;       /* without m: kind and duration from the config (NULL: none) */
    double duration;
    const tsa_channels *ch; /* channels and sample_rate of the rows (may be NULL: unknown) */
    const double *latest;   /* latest row, ch->n values (may be NULL; ignored without ch) */
    const char *error;      /* message of a failed run ("" or NULL when none) */
    const char *operation;  /* id of the run in progress ("" or NULL) */
    const ts_integrator_stats *integrators; /* work counters (NULL: unknown) */
    int nintegrators;
} tsa_session_view;

/* The session object with links; summary = 1 leaves out config and channels. */
json_t *tsa_session_json(const tsa_session_view *v, int summary);

#endif
