/*
 * routes.c — the routing table of tanksimd and its handlers.
 *
 * Table columns:
 *   method   HTTP method the row answers
 *   pattern  path; "{name}" matches one path segment (up to '/' or ':'),
 *            captured into r->params in order
 *   handler  function that queues exactly one response
 *   flags    RF_PUBLIC  served without the bearer token (--token)
 *            RF_SESSION the first parameter is a session id: the session is
 *                       looked up (404 problem if unknown) into r->session
 *                       before the handler runs, released after the response
 *            RF_WORK    starts work on the worker pool: once shutdown has
 *                       begun it is answered 503 /problems/shutting-down
 *                       with Retry-After (reads are still served)
 *   summary  one line, the same as the operation summary in api/openapi.yaml
 * Rows are tried in order; a path that matches no row gets 404, a path that
 * matches with another method 405. Every error body is
 * application/problem+json (RFC 9457). The table is printed by
 * `tanksimd --routes`; tests compare it with api/openapi.yaml.
 *
 * Handlers parse only query strings here; JSON bodies go through api/
 * (session_json.h, config_json.h) and sessions through session.h.
 */
#define _GNU_SOURCE
#include <ctype.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "../api/analysis_json.h"
#include "../api/config_json.h"
#include "../api/modes_json.h"
#include "../api/problem.h"
#include "../api/session_json.h"
#include "../api/spectrum.h"
#include "../api/store.h"
#include "../sim/param.h"
#include "../sim/version.h"
#include "analyses.h"
#include "db.h"
#include "frames.h"
#include "operations.h"
#include "pool.h"
#include "server.h"
#include "session.h"
#include "stream.h"
#include "static_files.h"

typedef enum MHD_Result (*tsd_handler)(tsd_request *r);

enum { RF_PUBLIC = 1, RF_SESSION = 2, RF_WORK = 4 };

typedef struct tsd_route_row {
    const char *method;
    const char *pattern;
    tsd_handler handler;
    int flags;
    const char *query; /* accepted query parameters, space-separated; "*": any */
    const char *summary;
} tsd_route_row;

#define MAX_CHANNELS_SELECT 512

/* ---- small helpers -------------------------------------------------------------- */

const char *tsd_arg(tsd_request *r, const char *name)
{
    return MHD_lookup_connection_value(r->conn, MHD_GET_ARGUMENT_KIND, name);
}

static enum MHD_Result bad_param(tsd_request *r, const char *name, const char *fmt, const char *v)
{
    ts_err e;
    char ptr[64];
    snprintf(ptr, sizeof ptr, "/%s", name);
    ts_err_set(&e, TS_ERR_PARAM, ptr, "query parameter %s: %s, got '%.100s'", name, fmt, v);
    return tsd_reply_err(r, &e, NULL);
}

/* Optional query number in [lo, hi]: 1 present, 0 absent, -1 replied 400. */
static int q_number(tsd_request *r, const char *name, double lo, double hi, double *out,
                    enum MHD_Result *ret)
{
    const char *v = tsd_arg(r, name);
    if (!v) return 0; /* an empty value was refused by check_query */
    if (tsa_parse_number(v, lo, hi, out) == 0) return 1;
    char what[96];
    snprintf(what, sizeof what, "number in [%g, %g] expected", lo, hi);
    *ret = bad_param(r, name, what, v);
    return -1;
}

/* Optional query integer in [lo, hi]: 1 present, 0 absent, -1 replied 400. */
static int q_integer(tsd_request *r, const char *name, long lo, long hi, long *out,
                     enum MHD_Result *ret)
{
    const char *v = tsd_arg(r, name);
    if (!v) return 0; /* an empty value was refused by check_query */
    if (tsa_parse_integer(v, lo, hi, out) != 0) {
        char what[96];
        snprintf(what, sizeof what, "integer in [%ld, %ld] expected", lo, hi);
        *ret = bad_param(r, name, what, v);
        return -1;
    }
    return 1;
}

static enum MHD_Result reply_body_err(tsd_request *r, const ts_err *e, json_t *errors)
{
    enum MHD_Result ret = tsd_reply_err(r, e, json_array_size(errors) ? errors : NULL);
    json_decref(errors);
    return ret;
}

/* Request body as a JSON object; an empty body reads as {} when optional.
 * NULL when a 400 reply was queued (*ret). */
static json_t *body_object(tsd_request *r, int optional, enum MHD_Result *ret)
{
    ts_err e;
    int empty = optional && r->body_len == 0;
    json_t *doc = tsa_parse_object(empty ? "{}" : r->body, empty ? 2 : r->body_len, &e);
    if (!doc) *ret = tsd_reply_err(r, &e, NULL);
    return doc;
}

/* Read numeric body fields (tsa_read_numbers); -1 when a 400 reply was queued. */
static int body_numbers(tsd_request *r, int optional, tsa_num_field *f, int n,
                        enum MHD_Result *ret)
{
    json_t *doc = body_object(r, optional, ret);
    if (!doc) return -1;
    ts_err e;
    json_t *errors = json_array();
    ts_rc rc = tsa_read_numbers(doc, f, n, errors, &e);
    json_decref(doc);
    if (rc != TS_OK) {
        *ret = reply_body_err(r, &e, errors);
        return -1;
    }
    json_decref(errors);
    return 0;
}

/* Problem from e with another status than its code maps to (e.g. a size
 * limit of one request answers 422, not the 429 of TS_ERR_LIMIT). */
static enum MHD_Result reply_err_status(tsd_request *r, const ts_err *e, unsigned status)
{
    json_t *p = tsa_problem_from_err(e, NULL);
    json_object_set_new(p, "status", json_integer(status));
    return tsd_reply_problem_json(r, status, p);
}

/* on_resume of a deferred request once its worker resumed it: async_result
 * with async_status, or the problem in async_err (with async_errors when
 * non-empty). */
static enum MHD_Result reply_async(tsd_request *r)
{
    if (r->async_result) {
        json_t *j = r->async_result;
        r->async_result = NULL;
        return tsd_reply_json(r, r->async_status, j);
    }
    r->location[0] = '\0';
    return tsd_reply_err(r, &r->async_err,
                         json_array_size(r->async_errors) ? r->async_errors : NULL);
}

/* Parse the body into r->async_doc and run job(r) on the pool with the
 * connection suspended; the job fills async_* and resumes; reply_async
 * answers with status on success. */
static enum MHD_Result defer_body_job(tsd_request *r, int optional, tsd_job_fn job,
                                      unsigned status)
{
    enum MHD_Result ret = MHD_NO;
    json_t *doc = body_object(r, optional, &ret);
    if (!doc) return ret;
    r->async_doc = doc;
    r->async_errors = json_array();
    r->async_status = status;
    tsd_request_defer(r, reply_async);
    if (tsd_pool_submit(r->srv->pool, job, r, 0) != 0) {
        /* refused only by a stopped pool (or no memory for the job record) */
        if (atomic_load(&r->srv->stopping))
            tsd_err_shutdown(&r->async_err);
        else
            ts_err_set(&r->async_err, TS_ERR_NOMEM, NULL, "out of memory queueing the job");
        tsd_request_resume(r);
    }
    return MHD_YES;
}

/* A stored session's first use after a restart: build its model and restore
 * its state on the pool (session.h), then run the route's handler as if the
 * request had just come in. */
static void build_job(void *arg)
{
    tsd_request *r = arg;
    tsd_session_build(r->session);
    tsd_request_resume(r);
}

/* The session may have been deleted while its build waited behind other work:
 * every route answers that 404 here, as the router does for a session deleted
 * before the request came (a GET of the session answered 200 with "status":
 * "deleted" while /series and /summary answered 404). Handlers keep their own
 * checks only for a DELETE that arrives while they run. */
static enum MHD_Result run_built(tsd_request *r)
{
    enum MHD_Result (*handler)(tsd_request *) = r->built_handler;
    r->built_handler = NULL;
    if (tsd_session_is_deleted(r->session)) {
        ts_err e;
        tsd_session_err_deleted(r->session, &e);
        return tsd_reply_err(r, &e, NULL);
    }
    return handler(r);
}

static enum MHD_Result get_session(tsd_request *r);

/* The next item of a comma-separated header list from p (leading blanks and
 * empty items skipped): its start, with *len the bytes up to the next comma
 * (trailing blanks included), or NULL at the end. */
static const char *list_item(const char *p, size_t *len)
{
    while (*p == ' ' || *p == '\t' || *p == ',')
        p++;
    if (!*p) return NULL;
    *len = strcspn(p, ",");
    return p;
}

/* The qvalue of len bytes at s in thousandths (RFC 9110 section 12.4.2:
 * "0" ["." 0*3DIGIT] / "1" ["." 0*3("0")]), or -1 when it is not one. A bare
 * strtod read "0.5x" as 0.5, "2" and "1e0" as weights, "0x1" as 1 and "nan". */
static int qvalue(const char *s, size_t len)
{
    if (len == 0 || (s[0] != '0' && s[0] != '1')) return -1;
    int q = (s[0] - '0') * 1000;
    if (len == 1) return q;
    if (s[1] != '.' || len > 5) return -1;
    for (size_t i = 2, scale = 100; i < len; i++, scale /= 10) {
        if (s[i] < '0' || s[i] > '9') return -1;
        q += (s[i] - '0') * (int)scale;
    }
    return q <= 1000 ? q : -1;
}

/* q (in thousandths) of media type `type` in an Accept header (RFC 9110
 * section 12.5.1): its own entry, else its major type with subtype "*", else
 * the all-types range (most specific wins; exact_only: its own entry only); -1
 * when none names it. A range whose q parameter is not a qvalue is left out,
 * as if not sent: the daemon answers what no range accepts with its default
 * representation rather than 406 (section 12.5.1 allows either), so a range it
 * cannot read is disregarded the same way, not refused with a 400. */
static int accept_q(const char *accept, const char *type, int exact_only)
{
    int best = -1, best_spec = -1;
    size_t major = strcspn(type, "/"), item;
    for (const char *p = accept; (p = list_item(p, &item)); p += item) {
        const char *e = p + item, *semi = memchr(p, ';', item);
        size_t len = (size_t)((semi ? semi : e) - p);
        while (len > 0 && (p[len - 1] == ' ' || p[len - 1] == '\t'))
            len--;
        int spec = -1;
        if (len == strlen(type) && strncasecmp(p, type, len) == 0)
            spec = 2;
        else if (!exact_only && len == major + 2 && strncasecmp(p, type, major + 1) == 0 &&
                 p[major + 1] == '*')
            spec = 1;
        else if (!exact_only && len == 3 && strncmp(p, "*/*", 3) == 0)
            spec = 0;
        if (spec <= best_spec) continue;
        int q = 1000;
        for (const char *a = semi; a && a < e && q >= 0;
             a = memchr(a + 1, ';', (size_t)(e - a - 1))) {
            const char *k = a + 1, *end = memchr(k, ';', (size_t)(e - k));
            while (k < e && (*k == ' ' || *k == '\t'))
                k++;
            if (!end) end = e;
            while (end > k && (end[-1] == ' ' || end[-1] == '\t'))
                end--;
            if (end - k >= 2 && (k[0] == 'q' || k[0] == 'Q') && k[1] == '=')
                q = qvalue(k + 2, (size_t)(end - k - 2));
        }
        if (q >= 0) best = q, best_spec = spec;
    }
    return best;
}

/* The alternative representation alt rather than the default base: alt is
 * named with q > 0 and not below base's q. A substring test served CSV to
 * "application/json, text/csv;q=0". */
static int accept_prefers(const char *accept, const char *alt, const char *base)
{
    if (!accept) return 0;
    int qa = accept_q(accept, alt, 1), qb = accept_q(accept, base, 0);
    return qa > 0 && qa >= qb;
}

static enum MHD_Result get_series(tsd_request *r);
static enum MHD_Result get_fft(tsd_request *r);

static enum MHD_Result build_then(tsd_request *r, enum MHD_Result (*handler)(tsd_request *))
{
    /* shutting down (the pool takes no jobs): what the stored channel table
     * serves without a model is still answered, as for a built session */
    if (atomic_load(&r->srv->stopping) &&
        (handler == get_session || handler == get_series || handler == get_fft))
        return handler(r);
    r->built_handler = handler;
    tsd_request_defer(r, run_built);
    if (tsd_pool_submit(r->srv->pool, build_job, r, 0) != 0) {
        if (atomic_load(&r->srv->stopping))
            tsd_err_shutdown(&r->async_err);
        else
            ts_err_set(&r->async_err, TS_ERR_NOMEM, NULL, "out of memory queueing the job");
        r->on_resume = reply_async;
        tsd_request_resume(r);
    }
    return MHD_YES;
}

/* ---- service --------------------------------------------------------------------- */

/* 200 {"status": "ok"}; 503 {"status": "stopping"} once shutdown has begun,
 * so that a load balancer or a client stops sending new work. */
static enum MHD_Result get_health(tsd_request *r)
{
    int stopping = atomic_load(&r->srv->stopping);
    if (stopping) r->retry_after = TSD_RETRY_AFTER_S;
    return tsd_reply_json(r, stopping ? MHD_HTTP_SERVICE_UNAVAILABLE : MHD_HTTP_OK,
                          json_pack("{s:s,s:s}", "status", stopping ? "stopping" : "ok",
                                    "version", TS_VERSION));
}

static enum MHD_Result get_openapi(tsd_request *r)
{
    const tsa_file *f = tsa_store_find("api/openapi.yaml");
    if (!f) {
        ts_err e;
        ts_err_set(&e, TS_ERR_NOTFOUND, NULL, "api/openapi.yaml is not in this build");
        return tsd_reply_err(r, &e, NULL);
    }
    return tsd_reply_text(r, MHD_HTTP_OK, "application/yaml; charset=utf-8", (const char *)f->data,
                          f->size);
}

static enum MHD_Result get_metrics(tsd_request *r)
{
    tsd_server *s = r->srv;
    tsd_metrics *m = &s->metrics;
    tsa_buf b = {0};
    long counts[TSD_NSTATUS];
    tsd_sessions_count(s, counts);
    tsa_buf_printf(&b, "# HELP tanksimd_sessions Sessions held, by status.\n"
                       "# TYPE tanksimd_sessions gauge\n");
    for (int i = 0; i < TSD_NSTATUS; i++)
        tsa_buf_printf(&b, "tanksimd_sessions{status=\"%s\"} %ld\n", tsd_status_name((tsd_status)i),
                       counts[i]);
    tsa_buf_printf(&b,
                   "# HELP tanksimd_sessions_created_total Sessions created since start.\n"
                   "# TYPE tanksimd_sessions_created_total counter\n"
                   "tanksimd_sessions_created_total %ld\n",
                   atomic_load(&m->sessions_created));
    tsa_buf_printf(&b,
                   "# HELP tanksimd_runs_started_total Run operations started.\n"
                   "# TYPE tanksimd_runs_started_total counter\n"
                   "tanksimd_runs_started_total %ld\n"
                   "# HELP tanksimd_runs_ended_total Run operations ended, by result.\n"
                   "# TYPE tanksimd_runs_ended_total counter\n",
                   atomic_load(&m->runs_started));
    for (int i = 0; i < TSD_NRUN_RESULTS; i++)
        tsa_buf_printf(&b, "tanksimd_runs_ended_total{result=\"%s\"} %ld\n",
                       tsd_run_result_names[i], atomic_load(&m->runs_ended[i]));
    tsa_buf_printf(&b,
                   "# HELP tanksimd_steps_total Synchronous steps executed.\n"
                   "# TYPE tanksimd_steps_total counter\n"
                   "tanksimd_steps_total %ld\n"
                   "# HELP tanksimd_simulated_seconds_total Simulated time advanced [s].\n"
                   "# TYPE tanksimd_simulated_seconds_total counter\n"
                   "tanksimd_simulated_seconds_total %.6f\n"
                   "# HELP tanksimd_advance_wall_seconds_total Wall time spent advancing [s].\n"
                   "# TYPE tanksimd_advance_wall_seconds_total counter\n"
                   "tanksimd_advance_wall_seconds_total %.6f\n"
                   "# HELP tanksimd_samples_stored_total Sample rows written to the database.\n"
                   "# TYPE tanksimd_samples_stored_total counter\n"
                   "tanksimd_samples_stored_total %ld\n"
                   "# HELP tanksimd_answers_cut_total Answers whose client closed the "
                   "connection before they were sent (abandoned streams, animations).\n"
                   "# TYPE tanksimd_answers_cut_total counter\n"
                   "tanksimd_answers_cut_total %ld\n"
                   "# HELP tanksimd_store_writes_refused_total Session status and removal "
                   "writes the store refused (each logged; the session goes on as in memory).\n"
                   "# TYPE tanksimd_store_writes_refused_total counter\n"
                   "tanksimd_store_writes_refused_total %ld\n"
                   "# HELP tanksimd_jobs_pending Worker-pool jobs queued or running.\n"
                   "# TYPE tanksimd_jobs_pending gauge\n"
                   "tanksimd_jobs_pending %d\n"
                   "# HELP tanksimd_long_jobs Analyses and APNG animations holding a worker.\n"
                   "# TYPE tanksimd_long_jobs gauge\n"
                   "tanksimd_long_jobs %d\n"
                   "# HELP tanksimd_reply_budget_bytes Bytes of answers that may be held "
                   "until their clients read them.\n"
                   "# TYPE tanksimd_reply_budget_bytes gauge\n"
                   "tanksimd_reply_budget_bytes %zu\n"
                   "# HELP tanksimd_reply_held_bytes Bytes of answers held until their "
                   "clients read them.\n"
                   "# TYPE tanksimd_reply_held_bytes gauge\n"
                   "tanksimd_reply_held_bytes %zu\n"
                   "# HELP tanksimd_reply_busy_total Answers refused 503 /problems/busy: the "
                   "reply budget full, or the summaries' row bound.\n"
                   "# TYPE tanksimd_reply_busy_total counter\n"
                   "tanksimd_reply_busy_total %ld\n"
                   "# HELP tanksimd_http_requests_total HTTP requests answered, by status.\n"
                   "# TYPE tanksimd_http_requests_total counter\n",
                   atomic_load(&m->steps), 1e-6 * (double)atomic_load(&m->sim_microseconds),
                   1e-6 * (double)atomic_load(&m->wall_microseconds),
                   atomic_load(&m->samples_stored), atomic_load(&m->answers_cut),
                   atomic_load(&m->store_writes_refused),
                   tsd_pool_pending(s->pool), atomic_load(&s->long_jobs), TSD_REPLY_BUDGET,
                   atomic_load(&s->reply_bytes), atomic_load(&m->replies_busy));
    for (int c = 1; c < 6; c++)
        for (int k = 0; k < 100; k++) {
            long n = atomic_load(&m->requests[c][k]);
            if (n)
                tsa_buf_printf(&b, "tanksimd_http_requests_total{code=\"%d\"} %ld\n", 100 * c + k,
                               n);
        }
    size_t len;
    char *text = tsa_buf_take(&b, &len);
    if (!text) return MHD_NO;
    enum MHD_Result ret =
        tsd_reply_text(r, MHD_HTTP_OK, "text/plain; version=0.0.4; charset=utf-8", text, len);
    free(text);
    return ret;
}

/* ---- presets and schema ----------------------------------------------------------- */

/* Scenario kind a preset resolves to ("" if it does not resolve). */
static void preset_kind(const char *name, char *kind, size_t n)
{
    ts_err e;
    json_t *doc = json_pack("{s:s}", "preset", name);
    json_t *res = tsa_config_resolve(doc, &e);
    json_t *k = json_object_get(json_object_get(res, "run"), "kind");
    snprintf(kind, n, "%s", json_is_string(k) ? json_string_value(k) : "");
    json_decref(res);
    json_decref(doc);
}

static enum MHD_Result get_presets(tsd_request *r)
{
    json_t *list = tsa_preset_list();
    size_t i;
    json_t *p;
    json_array_foreach(list, i, p)
    {
        char kind[64], link[200];
        const char *name = json_string_value(json_object_get(p, "name"));
        preset_kind(name, kind, sizeof kind);
        snprintf(link, sizeof link, "/v1/presets/%s", name);
        json_object_set_new(p, "kind", json_string(kind));
        json_object_set_new(p, "links", json_pack("{s:s}", "self", link));
    }
    return tsd_reply_json(r, MHD_HTTP_OK, json_pack("{s:o}", "presets", list));
}

static enum MHD_Result get_preset(tsd_request *r)
{
    ts_err e;
    json_t *doc = tsa_preset_get(r->params[0], &e);
    if (!doc) return tsd_reply_err(r, &e, NULL);
    json_t *req = json_pack("{s:s}", "preset", r->params[0]);
    json_t *resolved = tsa_config_resolve(req, &e);
    json_decref(req);
    if (!resolved) {
        json_decref(doc);
        return tsd_reply_err(r, &e, NULL);
    }
    return tsd_reply_json(
        r, MHD_HTTP_OK,
        json_pack("{s:s,s:o,s:o}", "name", r->params[0], "preset", doc, "config", resolved));
}

static enum MHD_Result get_schema(tsd_request *r)
{
    return tsd_reply_json(r, MHD_HTTP_OK, tsa_config_schema());
}

/* ---- sessions -------------------------------------------------------------------- */

/* Create: building a model and its initial state (ts_reset may solve for a
 * static equilibrium) is physics, so it runs on the pool like a step. */
static void create_job(void *arg)
{
    tsd_request *r = arg;
    tsd_session *s = NULL;
    if (tsd_session_create(r->srv, r->async_doc, &s, r->async_errors, &r->async_err) == TS_OK) {
        snprintf(r->location, sizeof r->location, "/v1/sessions/%s", s->id);
        r->async_result = tsd_session_json(s, 0);
        tsd_session_put(s);
    }
    tsd_request_resume(r);
}

static enum MHD_Result post_sessions(tsd_request *r)
{
    return defer_body_job(r, 0, create_job, MHD_HTTP_CREATED);
}

static enum MHD_Result get_sessions(tsd_request *r)
{
    enum MHD_Result ret = MHD_NO;
    long page_size = 50, after = 0;
    if (q_integer(r, "page_size", 1, 1000, &page_size, &ret) < 0) return ret;
    if (q_integer(r, "page_token", 0, 1L << 62, &after, &ret) < 0) return ret;
    return tsd_reply_json(r, MHD_HTTP_OK, tsd_session_list(r->srv, page_size, after));
}

static enum MHD_Result get_session(tsd_request *r)
{
    return tsd_reply_json(r, MHD_HTTP_OK, tsd_session_json(r->session, 0));
}

static enum MHD_Result delete_session(tsd_request *r)
{
    ts_err e;
    if (tsd_session_delete(r->session, &e) != TS_OK) return tsd_reply_err(r, &e, NULL);
    return tsd_reply_text(r, MHD_HTTP_NO_CONTENT, "application/json", "", 0);
}

/* Step: parse, hand to the pool, suspend; reply_async replies. */
static void step_done(void *ud)
{
    tsd_request_resume(ud);
}

/* Samples are stored at whole multiples of the sample period, and a step or
 * run stops on one: a duration or end time between them would be rounded
 * down without a word (0.0015 s at 500 Hz: no step at all). 0, or -1 with a
 * 400 naming field queued. */
static int check_on_grid(tsd_request *r, const char *field, double x, long min_rows,
                         enum MHD_Result *ret)
{
    double dt = r->session->ch.view.period;
    if (!(dt > 0)) return 0;
    ts_err e;
    char ptr[64];
    snprintf(ptr, sizeof ptr, "/%s", field);
    if (ts_on_sample_grid(x, dt, ptr, &e) == TS_OK) {
        if (ts_grid_row(x, dt) >= min_rows) return 0;
        ts_err_set(&e, TS_ERR_PARAM, ptr, /* a step of 0, or 1e-300 "on the grid" at row 0 */
                   "%s: at least %ld sample period(s) of %.15g s expected, got %g s", ptr, min_rows,
                   dt, x);
    }
    *ret = tsd_reply_err(r, &e, NULL);
    return -1;
}

static enum MHD_Result post_step(tsd_request *r)
{
    enum MHD_Result ret = MHD_NO;
    double duration = 0;
    tsa_num_field f[] = {{"duration", 1, 0.0, 1e9, &duration, NULL, "s"}};
    if (body_numbers(r, 0, f, 1, &ret) < 0) return ret;
    if (check_on_grid(r, "duration", duration, 1, &ret) < 0) return ret;
    if (duration > r->srv->opt.max_step) {
        char detail[300];
        snprintf(detail, sizeof detail,
                 "/duration: a synchronous step is at most %g s (--max-step), got %g; use POST "
                 "/v1/sessions/%s/run for longer advances",
                 r->srv->opt.max_step, duration, r->session->id);
        char run[96];
        snprintf(run, sizeof run, "/v1/sessions/%s/run", r->session->id);
        json_t *errs = json_pack("[{s:s,s:s}]", "pointer", "/duration", "message", detail);
        json_t *p = tsa_problem(422, "/problems/step-too-long", "Step too long", detail, errs);
        json_decref(errs);
        json_object_set_new(p, "run", json_string(run));
        json_object_set_new(p, "max_duration", json_real(r->srv->opt.max_step));
        return tsd_reply_problem_json(r, 422, p);
    }
    r->async_status = MHD_HTTP_OK;
    tsd_request_defer(r, reply_async);
    if (tsd_session_step(r->session, r->conn, duration, &r->async_result, &r->async_err, step_done,
                         r) != TS_OK) {
        /* nothing queued: r->async_err holds why; reply from the resume path */
        tsd_request_resume(r);
    }
    return MHD_YES;
}

static enum MHD_Result post_run(tsd_request *r)
{
    enum MHD_Result ret = MHD_NO;
    tsd_session *s = r->session;
    double until = -1, rtf = 0; /* until: absent unless set (its range starts at 0) */
    tsa_num_field f[] = {{"until", 0, 0.0, 1e12, &until, NULL, "s"},
                         {"real_time_factor", 0, 1e-3, 1e9, &rtf, NULL, NULL}};
    if (body_numbers(r, 1, f, 2, &ret) < 0) return ret;
    double end = s->m ? ts_model_config(s->m)->run.duration : 0;
    if (until < 0)
        until = end;
    else if (until < end && check_on_grid(r, "until", until, 0, &ret) < 0) /* past it: the end */
        return ret;
    ts_err e;
    json_t *op = NULL;
    if (tsd_session_run(s, until, rtf, &op, &e) != TS_OK) return tsd_reply_err(r, &e, NULL);
    snprintf(r->location, sizeof r->location, "/v1/operations/%s",
             json_string_value(json_object_get(op, "id")));
    return tsd_reply_json(r, MHD_HTTP_ACCEPTED, op);
}

/* Parse a channel list (from query parameter param, which its errors name),
 * from= and to= against a session; -1 when a reply was queued. */
typedef struct range_q {
    int idx[MAX_CHANNELS_SELECT];
    int n;
    long from, to; /* sample indexes, inclusive */
} range_q;

static int parse_range(tsd_request *r, tsd_session *s, const char *param, const char *channels,
                       range_q *q, enum MHD_Result *ret)
{
    ts_err e;
    if (s->nch == 0) { /* stored before channel lists were, and no model: names unknown */
        ts_err_set(&e, TS_ERR_STATE, NULL,
                   "session %s: the names and units of its stored rows are unknown (no model "
                   "and no stored channel list): %s",
                   s->id, s->error);
        *ret = tsd_reply_err(r, &e, NULL);
        return -1;
    }
    if (tsa_channel_select(&s->ch.view, param, channels, q->idx, MAX_CHANNELS_SELECT, &q->n,
                           &e) != TS_OK) {
        *ret = tsd_reply_err(r, &e, NULL);
        return -1;
    }
    double rate = 1.0 / s->ch.view.period;
    double from = 0, to = 1e300;
    if (q_number(r, "from", 0, 1e12, &from, ret) < 0) return -1;
    if (q_number(r, "to", 0, 1e12, &to, ret) < 0) return -1;
    if (to < from) { /* both given (to's default is past any time): an empty range by mistake */
        ts_err_set(&e, TS_ERR_PARAM, "/to", "query parameter to: at least from = %g s, got %g s",
                   from, to);
        *ret = tsd_reply_err(r, &e, NULL);
        return -1;
    }
    pthread_mutex_lock(&s->mu);
    long last = s->index;
    pthread_mutex_unlock(&s->mu);
    q->from = (long)ceil(from * rate - 1e-6);
    q->to = to * rate + 1e-6 >= (double)last ? last : (long)floor(to * rate + 1e-6);
    return 0;
}

/* Stored rows of s with from <= index <= to, every-th, at most max, into
 * malloc'd *index and *rows (the caller frees both, also on failure): of
 * each row the ncol stored channels cols[] only, rows[k * ncol + j] (so the
 * buffer is max x ncol, not max x every stored channel). The count, or -1
 * with err set (TS_ERR_NOMEM, TS_ERR_IO, TS_ERR_NOTFOUND). */
static long read_rows(tsd_request *r, tsd_session *s, long from, long to, long every, long max,
                      const int *cols, int ncol, long **index, double **rows, int *more,
                      ts_err *err)
{
    *more = 0;
    size_t cap = max > 0 ? (size_t)max : 1; /* malloc(0) may answer NULL */
    *index = malloc(sizeof(long) * cap);
    *rows = malloc(sizeof(double) * cap * (size_t)(ncol > 0 ? ncol : 1));
    if (!*index || !*rows) {
        ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory for %ld rows", max);
        return -1;
    }
    if (from > to || max < 1) return 0;
    long n = tsd_db_rows(r->srv->db, s->seq, from, to, every, max, s->nch, cols, ncol, *index,
                         *rows, more);
    /* a DELETE that landed meanwhile took the rows, or some of them: the
     * session is gone, not empty (nor an I/O failure) */
    if (tsd_session_is_deleted(s)) return tsd_session_err_deleted(s, err), -1;
    if (n == -2)
        ts_err_set(err, TS_ERR_IO, NULL,
                   "stored row %ld of session %s is damaged (not %d channels wide); the store "
                   "was changed outside the daemon",
                   (*index)[0], s->id, s->nch);
    else if (n < 0)
        ts_err_set(err, TS_ERR_IO, NULL, "cannot read samples (see the daemon log)");
    return n < 0 ? -1 : n;
}

/* Cells (rows x (channels + the index column)) of one /series page at most;
 * a page that would hold more ends early with next_page_token (api/openapi.yaml,
 * README). 10^6 cells are ~11 MB of JSON (17 MB at worst: every number at
 * full width) and 8 MB of rows read, built in ~0.2 s. Without it a page of a
 * wide session was the whole --max-samples rows: 100001 rows x 65 channels
 * took 1.3 s on an HTTP thread, 52 MB of rows and a 70 MB answer held until
 * the client read it, and eight such requests held /v1/health 6.4 s. */
#define SERIES_PAGE_CELLS 1000000L

static enum MHD_Result get_series(tsd_request *r)
{
    tsd_session *s = r->session;
    enum MHD_Result ret = MHD_NO;
    range_q q;
    if (parse_range(r, s, "channels", tsd_arg(r, "channels"), &q, &ret) < 0) return ret;
    long every = 1, page_size = r->srv->opt.max_samples, token = -1;
    if (q_integer(r, "every", 1, 1L << 40, &every, &ret) < 0) return ret;
    if (q_integer(r, "page_size", 1, r->srv->opt.max_samples, &page_size, &ret) < 0) return ret;
    if (q_integer(r, "page_token", 0, 1L << 62, &token, &ret) < 0) return ret;
    const char *format = tsd_arg(r, "format");
    const char *accept = MHD_lookup_connection_value(r->conn, MHD_HEADER_KIND, "Accept");
    int csv = format ? strcmp(format, "csv") == 0
                     : accept_prefers(accept, "text/csv", "application/json");
    if (format && !csv && strcmp(format, "json") != 0)
        return bad_param(r, "format", "json or csv expected", format);
    /* a token is a row this query's pages reach: from or after it, on its every grid
     * (a made-up one read rows before from, or off the grid, as if they were asked) */
    if (token >= 0 && (token < q.from || (token - q.from) % every != 0))
        return bad_param(r, "page_token", "the next_page_token of a page of this query expected",
                         tsd_arg(r, "page_token"));
    long start = token >= 0 ? token : q.from;
    long rows_cap = SERIES_PAGE_CELLS / (q.n + 1); /* q.n <= MAX_CHANNELS_SELECT: >= 1 */
    if (page_size > rows_cap) page_size = rows_cap;
    /* what the range still holds, not page_size: ?to=0 allocates one row */
    long need = start <= q.to ? (q.to - start) / every + 1 : 0;
    long max = need < page_size ? need : page_size;
    long *index;
    double *rows;
    int more;
    ts_err e;
    long n = read_rows(r, s, start, q.to, every, max, q.idx, q.n, &index, &rows, &more, &e);
    if (n < 0) {
        free(index);
        free(rows);
        return tsd_reply_err(r, &e, NULL);
    }
    /* rows hold the selected channels only: describe them as a table of q.n */
    ts_channel sel[MAX_CHANNELS_SELECT];
    int ident[MAX_CHANNELS_SELECT];
    for (int i = 0; i < q.n; i++) {
        sel[i] = s->ch.view.v[q.idx[i]];
        ident[i] = i;
    }
    tsa_channels view = {sel, q.n, s->ch.view.period};
    char next[32] = "";
    if (more && n > 0) snprintf(next, sizeof next, "%ld", index[n - 1] + every);
    tsa_buf b = {0};
    if (csv) {
        tsa_csv_header(&b, &view, ident, q.n);
        for (long k = 0; k < n; k++)
            tsa_csv_row(&b, rows + (size_t)k * (size_t)q.n, ident, q.n);
    } else {
        tsa_series_json(&b, s->id, &view, ident, q.n, index, rows, n, every, next[0] ? next : NULL);
    }
    free(index);
    free(rows);
    size_t len;
    char *text = tsa_buf_take(&b, &len);
    if (!text) return MHD_NO;
    if (next[0]) snprintf(r->next_token, sizeof r->next_token, "%s", next);
    ret = tsd_reply_owned(r, MHD_HTTP_OK, csv ? "text/csv; charset=utf-8" : "application/json",
                          text, len);
    return ret;
}

static enum MHD_Result get_stream(tsd_request *r)
{
    tsd_session *s = r->session;
    enum MHD_Result ret = MHD_NO;
    range_q q;
    if (parse_range(r, s, "channels", tsd_arg(r, "channels"), &q, &ret) < 0) return ret;
    long since = -1;
    const char *last_id = MHD_lookup_connection_value(r->conn, MHD_HEADER_KIND, "Last-Event-ID");
    if (q_integer(r, "since", -1, 1L << 62, &since, &ret) < 0) return ret;
    if (last_id && *last_id && tsa_parse_integer(last_id, -1, 1L << 62, &since) != 0) {
        ts_err e; /* a header, not a query parameter: bad_param's wording does not fit */
        ts_err_set(&e, TS_ERR_PARAM, "/Last-Event-ID",
                   "header Last-Event-ID: sample index in [-1, %ld] expected, got '%.100s'",
                   1L << 62, last_id);
        return tsd_reply_err(r, &e, NULL);
    }
    const char *accept = MHD_lookup_connection_value(r->conn, MHD_HEADER_KIND, "Accept");
    const char *format = tsd_arg(r, "format");
    if (format && strcmp(format, "sse") != 0 && strcmp(format, "ndjson") != 0)
        return bad_param(r, "format", "sse or ndjson expected", format);
    int ndjson = format ? strcmp(format, "ndjson") == 0
                        : accept_prefers(accept, "application/x-ndjson", "text/event-stream");
    return tsd_stream_reply(r, s, q.idx, q.n, since, ndjson);
}

/* /fft's window and detrend words, each at its sim/fft.h value (ts_fft_window,
 * ts_fft_detrend), and how the answer names it (label NULL: the word). */
typedef struct fft_word {
    const char *word, *label;
} fft_word;
static const fft_word fft_windows[] = {
    [TS_FFT_RECT] = {"rect", NULL}, [TS_FFT_HANN] = {"hann", NULL}, {NULL, NULL}};
static const fft_word fft_detrends[] = {[TS_FFT_NONE] = {"none", NULL},
                                        [TS_FFT_MEAN] = {"mean", "mean removed"},
                                        [TS_FFT_LINEAR] = {"linear", "line removed"},
                                        {NULL, NULL}};

/* The index (sim/fft.h value) of the word s in list (ended by a NULL word),
 * dflt when s is NULL, -1 when unknown. */
static int fft_word_of(const char *s, const fft_word *list, int dflt)
{
    if (!s) return dflt;
    for (int i = 0; list[i].word; i++)
        if (strcmp(s, list[i].word) == 0) return i;
    return -1;
}

static const char *fft_label(const fft_word *w)
{
    return w->label ? w->label : w->word;
}

/* "a, b or c expected" from the list's words. */
static const char *fft_expected(const fft_word *list, char *buf, size_t n)
{
    size_t k = 0;
    for (const fft_word *w = list; w->word && k < n; w++)
        k += (size_t)snprintf(buf + k, n - k, "%s%s",
                              w == list   ? ""
                              : w[1].word ? ", "
                                          : " or ",
                              w->word);
    if (k < n) snprintf(buf + k, n - k, " expected");
    return buf;
}

static enum MHD_Result get_fft(tsd_request *r)
{
    tsd_session *s = r->session;
    enum MHD_Result ret = MHD_NO;
    const char *ch = tsd_arg(r, "channel");
    ts_err e;
    if (!ch) {
        ts_err_set(&e, TS_ERR_PARAM, "/channel", "query parameter channel: required");
        return tsd_reply_err(r, &e, NULL);
    }
    if (strchr(ch, ',')) return bad_param(r, "channel", "exactly one channel name", ch);
    const char *wn = tsd_arg(r, "window"), *dn = tsd_arg(r, "detrend");
    int win = fft_word_of(wn, fft_windows, TS_FFT_RECT);
    int det = fft_word_of(dn, fft_detrends, TS_FFT_MEAN);
    char expected[64];
    if (win < 0)
        return bad_param(r, "window", fft_expected(fft_windows, expected, sizeof expected), wn);
    if (det < 0)
        return bad_param(r, "detrend", fft_expected(fft_detrends, expected, sizeof expected), dn);
    range_q q;
    if (parse_range(r, s, "channel", ch, &q, &ret) < 0) return ret;
    long want = q.to - q.from + 1;
    if (want > r->srv->opt.max_samples) {
        ts_err_set(&e, TS_ERR_LIMIT, "/to",
                   "/to: the range holds %ld samples, more than --max-samples = %ld; narrow "
                   "from/to",
                   want, r->srv->opt.max_samples);
        return reply_err_status(r, &e, 422);
    }
    long least = ts_fft_min_samples((ts_fft_window)win);
    if (want < least) {
        ts_err_set(&e, TS_ERR_PARAM, "/from",
                   "/from: the range holds %ld stored samples (from past the stored end or "
                   "after to); a spectrum needs at least %ld%s",
                   want > 0 ? want : 0, least, win == TS_FFT_HANN ? " with the Hann window" : "");
        return tsd_reply_err(r, &e, NULL);
    }
    long *index;
    double *rows;
    int more;
    int c = q.idx[q.n - 1]; /* the named channel (t is always idx[0]) */
    long n = read_rows(r, s, q.from, q.to, 1, want, &c, 1, &index, &rows, &more, &e);
    double *x = malloc(sizeof(double) * (size_t)want);
    long nf = want / 2 + 1;
    double *freq = malloc(sizeof(double) * (size_t)nf), *amp = malloc(sizeof(double) * (size_t)nf);
    ts_rc rc = n < 0 ? e.code : TS_OK;
    if (rc == TS_OK && !(x && freq && amp))
        rc = ts_err_set(&e, TS_ERR_NOMEM, NULL, "out of memory for a %ld-point spectrum", want);
    if (rc == TS_OK && n != want)
        rc = ts_err_set(&e, TS_ERR_IO, NULL, "could not read %ld samples", want);
    if (rc == TS_OK) {
        for (long k = 0; k < n; k++)
            x[k] = rows[k];
        pthread_mutex_lock(&r->srv->fft_lock);
        rc = tsa_amplitude_spectrum(x, n, 1.0 / s->ch.view.period, (ts_fft_detrend)det,
                                    (ts_fft_window)win, freq, amp, &e);
        pthread_mutex_unlock(&r->srv->fft_lock);
    }
    json_t *out = NULL;
    if (rc == TS_OK) {
        json_t *fa = json_array(), *aa = json_array();
        for (long k = 0; k < nf; k++) {
            json_array_append_new(fa, json_real(freq[k]));
            json_array_append_new(aa, tsa_json_real(amp[k])); /* NaN samples: null */
        }
        const ts_channel *chn = &s->ch.view.v[c];
        out = json_pack("{s:s,s:s,s:s,s:f,s:f,s:I,s:f,s:s,s:s,s:o,s:o}", "session", s->id,
                        "channel", chn->name, "unit", chn->unit, "from",
                        (double)q.from * s->ch.view.period, "to", (double)q.to * s->ch.view.period,
                        "n", (json_int_t)n, "df", 1.0 / ((double)n * s->ch.view.period), "detrend",
                        fft_label(&fft_detrends[det]), "window", fft_label(&fft_windows[win]),
                        "frequency", fa, "amplitude", aa);
        /* units of every number above: "unit" is the amplitude's (the channel's) */
        json_object_set_new(out, "units",
                            json_pack("{s:s,s:s,s:s,s:s,s:s}", "frequency", "Hz", "df", "Hz",
                                      "from", "s", "to", "s", "amplitude", chn->unit));
    }
    free(index);
    free(rows);
    free(x);
    free(freq);
    free(amp);
    if (!out) return tsd_reply_err(r, &e, NULL);
    return tsd_reply_json(r, MHD_HTTP_OK, out);
}

/* ---- run summary ------------------------------------------------------------------- */

/* The figures `tanksim run` writes to summary.json (tsa_model_metrics: top
 * speed, peak tension, spectral peaks, shift times, ...) over the rows the
 * session has stored, 0 to the last, read now: a run in progress gives those
 * of the rows stored so far, with "complete": false (true once the session is
 * done). A new session has row 0 only: 200 with what the model makes of one
 * row (often nothing), as /series answers what is stored. The session's model
 * computes them, so a stored session this build cannot rebuild (unrestored)
 * answers 409 with the reason, as its frames do. Post-processing of stored
 * rows like /fft, so on this HTTP thread, under fft_lock (the vehicle kind's
 * spectral figures plan FFTs). Printed with 17 digits: the same doubles as
 * the CLI's summary.json over the same rows.
 * It reads every stored row of every channel (200,001 rows x 65 channels:
 * 104 MB, 0.1 s; --max-rows 1e6: ~520 MB) on an HTTP thread: 8 such at once
 * held /v1/health 0.3-0.6 s and the rows of all 8. So the rows summaries
 * hold together are bounded (TSD_SUMMARY_BUDGET; one alone always goes, however
 * large): one that would pass the bound is answered 503 /problems/busy with
 * Retry-After rather than waiting, as a waiting HTTP thread would stall the
 * other connections it serves (Retry-After: TSD_RETRY_AFTER_BUSY_S). Small
 * summaries run side by side (until session 33 one at a time: a soak test's
 * 19-ms summaries of short runs refused each other). */
#define TSD_SUMMARY_BUDGET ((size_t)128 << 20)

/* Reserve bytes of rows for a summary: 1, or 0 when others hold rows and
 * these would take the total past TSD_SUMMARY_BUDGET. */
static int summary_reserve(tsd_server *srv, size_t bytes)
{
    size_t held = atomic_load(&srv->summary_bytes);
    for (;;) {
        if (held > 0 && held + bytes > TSD_SUMMARY_BUDGET) return 0;
        if (atomic_compare_exchange_weak(&srv->summary_bytes, &held, held + bytes)) return 1;
    }
}

static enum MHD_Result get_summary(tsd_request *r)
{
    tsd_session *s = r->session;
    ts_err e; /* deleted while its first-use build was queued: run_built answered 404 */
    /* unrestored is immutable once a handler sees the session; so is m */
    if (s->unrestored || !s->m || s->nch != ts_model_nchannel(s->m)) {
        ts_err_set(&e, TS_ERR_STATE, NULL, "session %s has no summary here: %s", s->id,
                   s->error[0] ? s->error : "its model cannot be built by this build");
        return tsd_reply_err(r, &e, NULL);
    }
    pthread_mutex_lock(&s->mu);
    tsd_status status = s->status;
    long last = s->index;
    pthread_mutex_unlock(&s->mu);
    /* the rows and their indexes, as read_rows allocates them */
    size_t bytes = (size_t)(last + 1) * ((size_t)s->nch + 1) * sizeof(double);
    if (!summary_reserve(r->srv, bytes))
        return tsd_reply_busy(r, "Other summaries are being computed",
                              "the rows of the summaries being computed fill their bound: retry "
                              "shortly");
    long *index;
    double *rows;
    int more;
    long n = read_rows(r, s, 0, last, 1, last >= 0 ? last + 1 : 1, NULL, s->nch, &index, &rows,
                       &more, &e);
    if (n >= 0 && n != last + 1) { /* rows are never removed but with the session */
        ts_err_set(&e, TS_ERR_IO, NULL, "could read %ld of the %ld stored rows", n, last + 1);
        n = -1;
    }
    ts_metric *mt = NULL;
    int nmt = 0;
    ts_rc rc = n < 0 ? e.code : TS_OK;
    if (rc == TS_OK) {
        pthread_mutex_lock(&r->srv->fft_lock);
        rc = tsa_model_metrics(s->m, rows, n, &mt, &nmt, &e);
        pthread_mutex_unlock(&r->srv->fft_lock);
    }
    char *text = NULL;
    if (rc == TS_OK) {
        tsa_run_summary v = {.id = s->id,
                             .kind = ts_model_kind(s->m),
                             .status = tsd_status_name(status),
                             .complete = status == TSD_DONE,
                             .t = n > 0 ? rows[(size_t)(n - 1) * (size_t)s->nch] : 0.0,
                             .rows = n,
                             .dof = ts_model_dof(s->m),
                             .metrics = mt,
                             .nmetric = nmt};
        json_t *j = tsa_run_summary_json(&v);
        text = j ? json_dumps(j, JSON_COMPACT | JSON_REAL_PRECISION(17)) : NULL;
        json_decref(j);
        if (!text) rc = ts_err_set(&e, TS_ERR_NOMEM, NULL, "out of memory for the summary");
    }
    free(index);
    free(rows);
    free(mt);
    atomic_fetch_sub(&r->srv->summary_bytes, bytes); /* its rows are freed */
    if (rc != TS_OK) return tsd_reply_err(r, &e, NULL);
    return tsd_reply_owned(r, MHD_HTTP_OK, "application/json", text, strlen(text));
}

/* ---- frames ------------------------------------------------------------------------ */

/* View from query parameters: width, height, view, exaggeration, color, text,
 * overlay, antialias. -1 when a 400 reply was queued. */
static int parse_view(tsd_request *r, tsr_view *v, enum MHD_Result *ret)
{
    tsr_view_default(v);
    long w = v->width, h = v->height, ov = v->overlay, aa = v->antialias;
    double ex = v->exaggeration;
    if (q_integer(r, "width", TSR_MIN_SIZE, TSR_MAX_SIZE, &w, ret) < 0) return -1;
    if (q_integer(r, "height", TSR_MIN_SIZE, TSR_MAX_SIZE, &h, ret) < 0) return -1;
    if (q_number(r, "exaggeration", 0, 1000, &ex, ret) < 0) return -1;
    if (q_integer(r, "overlay", 0, 1, &ov, ret) < 0) return -1;
    if (q_integer(r, "antialias", 0, 1, &aa, ret) < 0) return -1;
    v->width = (int)w;
    v->height = (int)h;
    v->exaggeration = ex;
    v->overlay = (int)ov;
    v->antialias = (int)aa;
    const char *kind = tsd_arg(r, "view");
    if (kind && (v->kind = tsr_view_kind_parse(kind)) < 0) {
        *ret = bad_param(r, "view", "side or three_quarter expected", kind);
        return -1;
    }
    const char *color = tsd_arg(r, "color");
    if (color) {
        if (strcmp(color, "tension") == 0)
            v->color_by_tension = 1;
        else if (strcmp(color, "plain") == 0)
            v->color_by_tension = 0;
        else {
            *ret = bad_param(r, "color", "tension or plain expected", color);
            return -1;
        }
    }
    const char *text = tsd_arg(r, "text");
    ts_err e;
    if ((text && tsr_view_set_text(v, text, &e) != TS_OK) || tsr_view_check(v, &e) != TS_OK) {
        /* the view's checks name a field (/text); here it is a query parameter */
        char msg[sizeof e.msg];
        snprintf(msg, sizeof msg, "query parameter %.40s: %.300s",
                 e.pointer[0] ? e.pointer + 1 : "?", e.msg);
        memcpy(e.msg, msg, sizeof msg);
        *ret = tsd_reply_err(r, &e, NULL);
        return -1;
    }
    return 0;
}

/* Frames are drawn from stored state snapshots and the model: a session that
 * could not be restored (session.c) has none this build can use — 409 with
 * the reason, before anything reads its model (which may not exist). */
static enum MHD_Result reply_no_frames(tsd_request *r, tsd_session *s)
{
    ts_err e;
    if (tsd_session_is_deleted(s)) /* its rows are gone, not kept: 404 as for a step */
        tsd_session_err_deleted(s, &e);
    else
        ts_err_set(&e, TS_ERR_STATE, NULL, "session %s has no frames here: %s", s->id, s->error);
    return tsd_reply_err(r, &e, NULL);
}

/* If-None-Match against our (strong) etag, RFC 9110 section 13.1.2: a
 * comma-separated list, weak comparison (W/ ignored), "*" matches any. It was
 * one exact string, so W/"..." or a list got the whole PNG again. */
static int etag_listed(const char *inm, const char *etag)
{
    size_t n = strlen(etag), item;
    for (const char *p = inm; (p = list_item(p, &item)); p += item) {
        const char *tag = p;
        size_t len = item;
        while (len > 0 && (tag[len - 1] == ' ' || tag[len - 1] == '\t'))
            len--;
        if (len == 1 && *tag == '*') return 1;
        if (len > 2 && tag[0] == 'W' && tag[1] == '/') tag += 2, len -= 2;
        if (len == n && strncmp(tag, etag, n) == 0) return 1;
    }
    return 0;
}

static enum MHD_Result get_frame(tsd_request *r)
{
    tsd_session *s = r->session;
    enum MHD_Result ret = MHD_NO;
    if (s->unrestored) return reply_no_frames(r, s);
    range_q q;
    if (parse_range(r, s, "channels", "t", &q, &ret) < 0) return ret;
    tsr_view v;
    if (parse_view(r, &v, &ret) < 0) return ret;
    double rate = 1.0 / s->ch.view.period, t = (double)q.to / rate;
    if (q_number(r, "t", 0, 1e12, &t, &ret) < 0) return ret;
    if (t * rate > (double)q.to + 0.5) {
        ts_err e;
        ts_err_set(&e, TS_ERR_PARAM, "/t",
                   "query parameter t: at most %g s (the last stored sample), got '%.100s'",
                   (double)q.to / rate, tsd_arg(r, "t"));
        return tsd_reply_err(r, &e, NULL);
    }
    /* A stored sample's frame never changes: a strong ETag over the session,
     * the sample index, the drawing options and the version answers repeat
     * requests with 304 without drawing (issue 8: caching of past frames). */
    static const char *const opts[] = {"width", "height",  "view",     "exaggeration",
                                        "color", "text",    "overlay",  "antialias"}; /* parse_view */
    uint64_t h = 1469598103934665603ULL; /* FNV-1a 64 */
    for (size_t i = 0; i < sizeof opts / sizeof opts[0]; i++) {
        const char *val = tsd_arg(r, opts[i]);
        for (const char *c = val ? val : ""; ; c++) {
            h = (h ^ (unsigned char)*c) * 1099511628211ULL;
            if (!*c) break;
        }
    }
    /* the sample drawn: the nearest stored one; up to half a period past the
     * last is the last (lround would name the next, which a later step stores,
     * and the ETag, immutable, would then stand for two images) */
    long k = lround(t * rate);
    if (k > q.to) k = q.to;
    snprintf(r->etag, sizeof r->etag, "\"%s-%ld-%016llx-%s\"", s->id, k, (unsigned long long)h,
             TS_VERSION);
    const char *inm = MHD_lookup_connection_value(r->conn, MHD_HEADER_KIND,
                                                  MHD_HTTP_HEADER_IF_NONE_MATCH);
    if (inm && etag_listed(inm, r->etag)) return tsd_reply_not_modified(r);
    if (tsd_reply_budget_full(r, &ret)) return ret; /* not drawn to be refused */
    return tsd_frames_reply(r, s, &v, (double)k, 0, 1, 1, 0);
}

static enum MHD_Result get_frames(tsd_request *r)
{
    tsd_session *s = r->session;
    enum MHD_Result ret = MHD_NO;
    if (s->unrestored) return reply_no_frames(r, s);
    range_q q;
    if (parse_range(r, s, "channels", "t", &q, &ret) < 0) return ret;
    tsr_view v;
    if (parse_view(r, &v, &ret) < 0) return ret;
    double fps = 25;
    if (q_number(r, "fps", 0.01, 1000, &fps, &ret) < 0) return ret;
    double rate = 1.0 / s->ch.view.period;
    long n = q.to >= q.from ? (long)floor((double)(q.to - q.from) / rate * fps + 1e-9) + 1 : 0;
    ts_err e;
    if (n < 1) {
        ts_err_set(&e, TS_ERR_PARAM, "/from", "query parameter from: after the last stored sample");
        return tsd_reply_err(r, &e, NULL);
    }
    const char *format = tsd_arg(r, "format");
    int apng = !format || strcmp(format, "apng") == 0;
    if (!apng && strcmp(format, "multipart") != 0)
        return bad_param(r, "format", "apng or multipart expected", format);
    int limit = apng ? TSD_MAX_APNG_FRAMES : TSD_MAX_FRAMES;
    if (n > limit) {
        ts_err_set(&e, TS_ERR_LIMIT, "/fps",
                   "/fps: %ld frames requested, at most %d per %s request; lower fps or narrow "
                   "from/to",
                   n, limit, apng ? "APNG (format=multipart streams up to 3000)" : "multipart");
        return reply_err_status(r, &e, 422);
    }
    /* an APNG is answered whole and counted; multipart frames are streamed */
    if (apng && tsd_reply_budget_full(r, &ret)) return ret;
    return tsd_frames_reply(r, s, &v, (double)q.from, rate / fps, n, 0, apng ? fps : 0);
}

/* ---- track eigenanalysis (tanksim modes over HTTP) -------------------------------- */

/* Eigenanalysis is physics: it runs on the pool; the connection waits suspended. */
static void modes_job(void *arg)
{
    tsd_request *r = arg;
    ts_config cfg;
    if (tsa_config_load(r->async_doc, &cfg, NULL, r->async_errors, &r->async_err) == TS_OK)
        r->async_result = tsa_modes_json(&cfg, &r->async_err);
    tsd_request_resume(r);
}

static enum MHD_Result post_modes(tsd_request *r)
{
    return defer_body_job(r, 1, modes_job, MHD_HTTP_OK);
}

/* ---- analyses: engine map (Fig. 18) and IVS tuning (Figs. 26-27) ------------------ */

/* The body's config (empty = the defaults) for command: a preset made for
 * another command only is refused naming /preset. -1 when a 4xx was queued;
 * else 0 and *request = {"body": the body as sent, without its comment keys}
 * (new reference, for the operation's metadata). */
static int analysis_config(tsd_request *r, const char *command, ts_config *cfg,
                           json_t **request, enum MHD_Result *ret)
{
    json_t *doc = body_object(r, 1, ret);
    if (!doc) return -1;
    ts_err e;
    json_t *errors = json_array();
    ts_rc rc = tsa_config_load(doc, cfg, NULL, errors, &e);
    if (rc == TS_OK) rc = tsa_config_runnable(doc, command, &e);
    /* the analysis' own refusals of the config (an engine table, the tune's
     * window), answered now as a session's are, not by an operation that fails */
    if (rc == TS_OK) rc = tsa_analysis_check(cfg, command, &e);
    if (rc != TS_OK) {
        json_decref(doc);
        *ret = reply_body_err(r, &e, errors);
        return -1;
    }
    json_decref(errors);
    tsa_strip_comments(doc); /* kept without them: a comment may be most of a body */
    *request = json_pack("{s:o}", "body", doc);
    return 0;
}

/* A 500 for an allocation that failed in a handler. */
static enum MHD_Result reply_oom(tsd_request *r)
{
    ts_err e;
    ts_err_set(&e, TS_ERR_NOMEM, NULL, "out of memory");
    return tsd_reply_err(r, &e, NULL);
}

/* Start the analysis and answer 202 with its operation. Frees q. */
static enum MHD_Result start_analysis(tsd_request *r, tsd_analysis_req *q)
{
    ts_err e;
    json_t *op = NULL;
    if (!q->request) {
        free(q);
        return reply_oom(r);
    }
    ts_rc rc = tsd_analysis_start(r->srv, q, &op, &r->retry_after, &e);
    free(q);
    if (rc != TS_OK) return tsd_reply_err(r, &e, NULL);
    snprintf(r->location, sizeof r->location, "/v1/operations/%s",
             json_string_value(json_object_get(op, "id")));
    return tsd_reply_json(r, MHD_HTTP_ACCEPTED, op);
}

static enum MHD_Result post_engine_map(tsd_request *r)
{
    enum MHD_Result ret = MHD_NO;
    tsd_analysis_req *q = calloc(1, sizeof *q);
    if (!q) return reply_oom(r);
    q->kind = TSD_ANALYSIS_ENGINE_MAP;
    if (analysis_config(r, "engine-map", &q->cfg, &q->request, &ret) < 0) {
        free(q);
        return ret;
    }
    return start_analysis(r, q);
}

/* Query parameter name as a tuning schedule over var (tsa_tune_schedule_parse):
 * 1 read (x[*n]), 0 absent, -1 replied 400 naming the parameter. */
static int q_schedule(tsd_request *r, const char *name, const char *var, double *x, int *n,
                      enum MHD_Result *ret)
{
    const char *v = tsd_arg(r, name);
    if (!v) return 0;
    ts_err e;
    if (tsa_tune_schedule_parse(v, var, x, n, &e) == TS_OK) return 1;
    *ret = bad_param(r, name, e.msg, v);
    return -1;
}

static enum MHD_Result post_tune(tsd_request *r)
{
    enum MHD_Result ret = MHD_NO;
    tsd_analysis_req *q = calloc(1, sizeof *q);
    if (!q) return reply_oom(r);
    q->kind = TSD_ANALYSIS_TUNE;
    int m = q_schedule(r, "schedule_mass", "mass", q->x, &q->n, &ret);
    int g = m < 0 ? 0 : q_schedule(r, "schedule_grade", "grade", q->x, &q->n, &ret);
    if (m < 0 || g < 0) {
        free(q);
        return ret;
    }
    if (m > 0 && g > 0) {
        free(q);
        ts_err e;
        ts_err_set(&e, TS_ERR_PARAM, "/schedule_grade",
                   "query parameters schedule_mass and schedule_grade: one schedule variable "
                   "per request");
        return tsd_reply_err(r, &e, NULL);
    }
    if (m > 0 || g > 0) snprintf(q->var, sizeof q->var, "%s", m > 0 ? "mass" : "grade");
    if (analysis_config(r, "tune", &q->cfg, &q->request, &ret) < 0) {
        free(q);
        return ret;
    }
    const char *sched = m > 0 ? "schedule_mass" : g > 0 ? "schedule_grade" : NULL;
    if (sched && q->request) /* the query as sent, beside the body */
        json_object_set_new(q->request, sched, json_string(tsd_arg(r, sched)));
    return start_analysis(r, q);
}

/* ---- operations ------------------------------------------------------------------- */

static enum MHD_Result get_operation(tsd_request *r)
{
    ts_err e;
    json_t *j = tsd_op_json(r->srv, r->params[0]); /* held in memory, or an analysis stored */
    if (!j) j = tsd_analysis_stored(r->srv, r->params[0], &e);
    if (!j) return tsd_reply_err(r, &e, NULL);
    return tsd_reply_json(r, MHD_HTTP_OK, j);
}

static enum MHD_Result cancel_operation(tsd_request *r)
{
    char sid[24] = "";
    if (!tsd_op_request_cancel(r->srv, r->params[0], sid)) /* stored (done) or 404 */
        return get_operation(r);
    if (sid[0]) { /* a run stops through its session; an analysis's worker sees the flag */
        tsd_session *s = tsd_session_get(r->srv, sid);
        if (s) {
            tsd_session_cancel(s, r->params[0]);
            tsd_session_put(s);
        }
    }
    return get_operation(r);
}

static enum MHD_Result get_analyses(tsd_request *r)
{
    ts_err e;
    json_t *j = tsd_analyses_json(r->srv, &e);
    return j ? tsd_reply_json(r, MHD_HTTP_OK, j) : tsd_reply_err(r, &e, NULL);
}

static enum MHD_Result get_analysis(tsd_request *r)
{
    ts_err e;
    json_t *j = tsd_analysis_json(r->srv, r->params[0], &e);
    return j ? tsd_reply_json(r, MHD_HTTP_OK, j) : tsd_reply_err(r, &e, NULL);
}

static enum MHD_Result delete_analysis(tsd_request *r)
{
    ts_err e;
    if (tsd_analysis_delete(r->srv, r->params[0], &e) != TS_OK) return tsd_reply_err(r, &e, NULL);
    return tsd_reply_text(r, MHD_HTTP_NO_CONTENT, "application/json", "", 0);
}

/* ---- the table ---------------------------------------------------------------------- */

/* The drawing options of parse_view, accepted by both frame routes. */
#define Q_VIEW "width height view exaggeration color text overlay antialias"

static const tsd_route_row routes[] = {
    {"GET", "/v1/health", get_health, RF_PUBLIC, "*", "Liveness and version"},
    {"GET", "/v1/openapi.yaml", get_openapi, 0, "", "This API description"},
    {"GET", "/metrics", get_metrics, 0, "", "Prometheus metrics"},
    {"GET", "/v1/presets", get_presets, 0, "", "List shipped presets"},
    {"GET", "/v1/presets/{name}", get_preset, 0, "", "One preset, as shipped and resolved"},
    {"GET", "/v1/schema", get_schema, 0, "", "JSON Schema of a run config"},
    {"POST", "/v1/sessions", post_sessions, RF_WORK, "",
     "Create a session from a preset and overrides"},
    {"GET", "/v1/sessions", get_sessions, 0, "page_size page_token", "List sessions (paged)"},
    {"GET", "/v1/sessions/{id}", get_session, RF_SESSION, "", "One session"},
    {"DELETE", "/v1/sessions/{id}", delete_session, RF_SESSION, "",
     "Delete a session and its data"},
    {"POST", "/v1/sessions/{id}/step", post_step, RF_SESSION | RF_WORK, "",
     "Advance synchronously (bounded)"},
    {"POST", "/v1/sessions/{id}/run", post_run, RF_SESSION | RF_WORK, "",
     "Start an asynchronous run"},
    {"GET", "/v1/sessions/{id}/series", get_series, RF_SESSION,
     "channels from to every page_size page_token format", "Stored samples (JSON or CSV)"},
    {"GET", "/v1/sessions/{id}/stream", get_stream, RF_SESSION, "channels since format",
     "Live samples (SSE or NDJSON)"},
    {"GET", "/v1/sessions/{id}/fft", get_fft, RF_SESSION, "channel from to window detrend",
     "Amplitude spectrum of a channel"},
    {"GET", "/v1/sessions/{id}/summary", get_summary, RF_SESSION, "",
     "Figures of the stored rows (tanksim run's summary metrics)"},
    {"GET", "/v1/sessions/{id}/frame.png", get_frame, RF_SESSION | RF_WORK, "t " Q_VIEW,
     "One rendered frame (PNG)"},
    {"GET", "/v1/sessions/{id}/frames", get_frames, RF_SESSION | RF_WORK,
     "fps format from to " Q_VIEW, "Animation of stored frames"},
    {"POST", "/v1/modes", post_modes, RF_WORK, "", "Track eigenanalysis (tanksim modes)"},
    {"POST", "/v1/engine-map", post_engine_map, RF_WORK, "",
     "Full-load engine map, an operation (tanksim engine-map)"},
    {"POST", "/v1/tune", post_tune, RF_WORK, "schedule_mass schedule_grade",
     "IVS Ziegler-Nichols tuning, an operation (tanksim tune)"},
    {"GET", "/v1/analyses", get_analyses, 0, "",
     "Stored analyses (engine maps, tunings), newest first"},
    {"GET", "/v1/analyses/{id}", get_analysis, 0, "",
     "One stored analysis: its list entry and the whole request"},
    {"DELETE", "/v1/analyses/{id}", delete_analysis, 0, "",
     "Remove a finished analysis from the store"},
    {"GET", "/v1/operations/{id}", get_operation, 0, "", "State of a run or analysis operation"},
    {"POST", "/v1/operations/{id}:cancel", cancel_operation, 0, "",
     "Cancel a run or analysis operation"},
    {"GET", "/", tsd_static_index, RF_PUBLIC, "*", "The browser dashboard (web_static/index.html)"},
    {"GET", "/static/{file}", tsd_static_file, RF_PUBLIC, "*",
     "Dashboard assets (web_static/FILE)"},
};
#define NROUTES (sizeof routes / sizeof routes[0])

void tsd_routes_print(void)
{
    for (size_t i = 0; i < NROUTES; i++)
        printf("%s %s\t%s\t%s\n", routes[i].method, routes[i].pattern, routes[i].summary,
               routes[i].query);
}

/* Match url against pattern, capturing {..} segments. 1 on match. */
static int match(const char *pattern, const char *url, tsd_request *r)
{
    int n = 0;
    const char *p = pattern, *u = url;
    while (*p && *u) {
        if (*p == '{') {
            const char *pe = strchr(p, '}');
            size_t len = strcspn(u, "/:");
            if (!pe || len == 0 || len >= sizeof r->params[0] || n >= TSD_MAX_PATH_PARAMS) return 0;
            memcpy(r->params[n], u, len);
            r->params[n][len] = '\0';
            n++;
            p = pe + 1;
            u += len;
            continue;
        }
        if (*p != *u) return 0;
        p++;
        u++;
    }
    if (*p || *u) return 0;
    r->nparams = n;
    return 1;
}

/* Constant-time comparison of the Authorization header with "Bearer TOKEN". */
static int authorized(tsd_request *r)
{
    const char *tok = r->srv->opt.token;
    if (!tok[0]) return 1;
    const char *h = MHD_lookup_connection_value(r->conn, MHD_HEADER_KIND, "Authorization");
    if (!h || strncasecmp(h, "Bearer ", 7) != 0) return 0;
    h += 7;
    size_t a = strlen(h), b = strlen(tok);
    unsigned diff = (unsigned)(a ^ b);
    for (size_t i = 0; i < a; i++)
        diff |= (unsigned char)h[i] ^ (unsigned char)tok[i % b];
    return diff == 0;
}

/* Query parameters against the route's list: a name it does not read (a typo
 * such as 'chanels' would otherwise be ignored silently), a name given twice
 * (only the first would count), an empty value ('from=' read as absent) or a
 * NUL byte (%00 cut the value short: '50000%00abc' read as 50000) is a 400
 * naming it, as unknown JSON fields are. */
typedef struct query_check {
    const char *accepted;
    char seen[32][48];
    int nseen;
    char bad[48];
    enum { QUERY_OK, QUERY_UNKNOWN, QUERY_REPEATED, QUERY_EMPTY, QUERY_NUL } why;
} query_check;

/* 1 when name is a whole word of the space-separated list. */
static int in_list(const char *list, const char *name)
{
    size_t n = strlen(name);
    for (const char *p = list; (p = strstr(p, name)) != NULL; p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return 1;
    return 0;
}

/* Why the walk stops at key (query_iter). */
static enum MHD_Result query_stop(query_check *c, const char *key, int why)
{
    snprintf(c->bad, sizeof c->bad, "%s", key);
    c->why = why;
    return MHD_NO;
}

static enum MHD_Result query_iter(void *cls, enum MHD_ValueKind kind, const char *key,
                                  size_t key_size, const char *value, size_t value_size)
{
    (void)kind;
    query_check *c = cls;
    if (!key[0] && (!value || !value[0]) && key_size == 0) return MHD_YES; /* a stray '&' */
    if (!key[0] || strlen(key) >= sizeof c->bad || !in_list(c->accepted, key))
        return query_stop(c, key, QUERY_UNKNOWN);
    if (key_size != strlen(key) || (value && value_size != strlen(value)))
        return query_stop(c, key, QUERY_NUL);
    if (!value || !value[0]) return query_stop(c, key, QUERY_EMPTY);
    for (int i = 0; i < c->nseen; i++)
        if (strcmp(c->seen[i], key) == 0) return query_stop(c, key, QUERY_REPEATED);
    if (c->nseen < (int)(sizeof c->seen / sizeof c->seen[0]))
        snprintf(c->seen[c->nseen++], sizeof c->seen[0], "%s", key);
    return MHD_YES;
}

/* 0, or -1 with a 400 queued in *ret. */
static int check_query(tsd_request *r, const tsd_route_row *row, enum MHD_Result *ret)
{
    if (strcmp(row->query, "*") == 0) return 0;
    query_check c = {.accepted = row->query};
    MHD_get_connection_values_n(r->conn, MHD_GET_ARGUMENT_KIND, query_iter, &c);
    if (c.why == QUERY_OK) return 0;
    ts_err e;
    char ptr[64];
    tsa_pointer_join(ptr, sizeof ptr, "", c.bad); /* the client's own key: escape it */
    if (c.why == QUERY_REPEATED)
        ts_err_set(&e, TS_ERR_PARAM, ptr, "query parameter %s: given more than once", c.bad);
    else if (c.why == QUERY_EMPTY)
        ts_err_set(&e, TS_ERR_PARAM, ptr,
                   "query parameter %s: a value expected (leave the parameter out for its "
                   "default)",
                   c.bad);
    else if (c.why == QUERY_NUL)
        ts_err_set(&e, TS_ERR_PARAM, ptr, "query parameter %s: a NUL byte (%%00) in it", c.bad);
    else
        ts_err_set(&e, TS_ERR_PARAM, ptr,
                   "query parameter '%s': unknown here; %s %s takes %s%s", c.bad, row->method,
                   row->pattern, row->query[0] ? "only: " : "none", row->query);
    *ret = tsd_reply_err(r, &e, NULL);
    return -1;
}

/* Add method to the Allow list of a 405 (r->allow, comma-separated, once each). */
static void allow_method(tsd_request *r, const char *method)
{
    size_t n = strlen(r->allow), m = strlen(method);
    for (const char *p = r->allow; (p = strstr(p, method)) != NULL; p += m)
        if ((p == r->allow || p[-1] == ' ') && (p[m] == ',' || p[m] == '\0')) return;
    if (n + m + 3 > sizeof r->allow) return; /* the table has at most a few per path */
    snprintf(r->allow + n, sizeof r->allow - n, "%s%s", n ? ", " : "", method);
}

enum MHD_Result tsd_route(tsd_request *r)
{
    int path_matched = 0;
    const tsd_route_row *row = NULL;
    /* HEAD is GET without the body (RFC 9110 9.3.2; libmicrohttpd sends the
     * headers only), so every GET row answers it */
    const char *method = tsd_request_is_head(r) ? "GET" : r->method;
    for (size_t i = 0; i < NROUTES; i++) {
        if (!match(routes[i].pattern, r->url, r)) continue;
        path_matched = 1;
        if (strcmp(routes[i].method, method) == 0) {
            row = &routes[i];
            break;
        }
        allow_method(r, routes[i].method);
        if (strcmp(routes[i].method, "GET") == 0) allow_method(r, "HEAD");
    }
    if (!(row && (row->flags & RF_PUBLIC)) && !authorized(r)) {
        r->www_authenticate = 1;
        return tsd_reply_problem(r, MHD_HTTP_UNAUTHORIZED, "/problems/unauthorized", "Unauthorized",
                                 "this daemon needs 'Authorization: Bearer TOKEN' (its --token or "
                                 "TANKSIM_TOKEN)",
                                 NULL);
    }
    if (row) {
        enum MHD_Result qret;
        if (check_query(r, row, &qret) < 0) return qret;
        /* A check ahead of the handler for a clear answer; a submission that
         * races with the start of shutdown is refused by the stopped pool and
         * answered the same way (TSD_ERR_SHUTDOWN). */
        if ((row->flags & RF_WORK) && atomic_load(&r->srv->stopping))
            return tsd_reply_shutting_down(r, NULL);
        if (row->flags & RF_SESSION) {
            r->session = tsd_session_get(r->srv, r->params[0]);
            if (!r->session) {
                char detail[200];
                snprintf(detail, sizeof detail, "no session '%s'", r->params[0]);
                return tsd_reply_problem(r, MHD_HTTP_NOT_FOUND, "/problems/not-found", "Not found",
                                         detail, NULL);
            }
            /* deleting needs no model: a stored session never used goes as it is */
            if (tsd_session_deferred(r->session) && row->handler != delete_session)
                return build_then(r, row->handler);
        }
        return row->handler(r);
    }
    char detail[600];
    if (path_matched) {
        snprintf(detail, sizeof detail, "%s is not allowed on %.500s", r->method, r->url);
        return tsd_reply_problem(r, MHD_HTTP_METHOD_NOT_ALLOWED, "/problems/method-not-allowed",
                                 "Method not allowed", detail, NULL);
    }
    snprintf(detail, sizeof detail, "no resource at %.500s", r->url);
    return tsd_reply_problem(r, MHD_HTTP_NOT_FOUND, "/problems/not-found", "Not found", detail,
                             NULL);
}
