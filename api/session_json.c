/*
 * session_json.c — the daemon's session/series/stream shapes (session_json.h).
 *
 * Numbers are printed with %.9g (enough for float64 channels at the precision
 * the models integrate to: rtol 1e-6) except time, printed with %.12g so that
 * t = index / sample_rate round-trips. Non-finite values (never produced by a
 * healthy run: ts_advance stops on them) print as null.
 */
#include "session_json.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json_error.h"
#include "problem.h"

/* ---- buffer --------------------------------------------------------------- */

static int reserve(tsa_buf *b, size_t extra)
{
    if (b->oom) return -1;
    if (b->n + extra + 1 <= b->cap) return 0;
    size_t cap = b->cap ? b->cap : 4096;
    while (cap < b->n + extra + 1)
        cap *= 2;
    char *np = realloc(b->p, cap);
    if (!np) {
        b->oom = 1;
        return -1;
    }
    b->p = np;
    b->cap = cap;
    return 0;
}

void tsa_buf_put(tsa_buf *b, const char *s, size_t n)
{
    if (reserve(b, n) != 0) return;
    memcpy(b->p + b->n, s, n);
    b->n += n;
    b->p[b->n] = '\0';
}

void tsa_buf_printf(tsa_buf *b, const char *fmt, ...)
{
    va_list ap;
    char small[256];
    va_start(ap, fmt);
    int k = vsnprintf(small, sizeof small, fmt, ap);
    va_end(ap);
    if (k < 0) return;
    if ((size_t)k < sizeof small) {
        tsa_buf_put(b, small, (size_t)k);
        return;
    }
    if (reserve(b, (size_t)k) != 0) return;
    va_start(ap, fmt);
    vsnprintf(b->p + b->n, (size_t)k + 1, fmt, ap);
    va_end(ap);
    b->n += (size_t)k;
}

void tsa_buf_free(tsa_buf *b)
{
    free(b->p);
    memset(b, 0, sizeof *b);
}

char *tsa_buf_take(tsa_buf *b, size_t *len)
{
    if (b->oom) {
        tsa_buf_free(b);
        return NULL;
    }
    if (!b->p) reserve(b, 0);
    if (b->oom) return NULL;
    b->p[b->n] = '\0';
    char *p = b->p;
    if (len) *len = b->n;
    memset(b, 0, sizeof *b);
    return p;
}

static void put_num(tsa_buf *b, double v, int time)
{
    if (!isfinite(v))
        tsa_buf_put(b, "null", 4);
    else
        tsa_buf_printf(b, time ? "%.12g" : "%.9g", v);
}

/* JSON string literal: escapes quotes, backslashes and control characters. */
static void put_str(tsa_buf *b, const char *s)
{
    tsa_buf_put(b, "\"", 1);
    for (const unsigned char *p = (const unsigned char *)(s ? s : ""); *p; p++) {
        if (*p == '"' || *p == '\\')
            tsa_buf_printf(b, "\\%c", *p);
        else if (*p < 0x20)
            tsa_buf_printf(b, "\\u%04x", *p);
        else
            tsa_buf_put(b, (const char *)p, 1);
    }
    tsa_buf_put(b, "\"", 1);
}

/* ---- request bodies -------------------------------------------------------- */

json_t *tsa_parse_object(const char *body, size_t len, ts_err *err)
{
    if (!body || len == 0) {
        tsa_root_err(err, TS_ERR_PARAM, "the request body must be a JSON object; it is empty");
        return NULL;
    }
    json_error_t je;
    json_t *j = json_loadb(body, len, JSON_REJECT_DUPLICATES, &je);
    if (!j) {
        char lead[64];
        snprintf(lead, sizeof lead, "malformed JSON at line %d, column %d", je.line, je.column);
        tsa_json_parse_err(body, len, &je, lead, err);
        return NULL;
    }
    if (!json_is_object(j)) {
        json_decref(j);
        tsa_root_err(err, TS_ERR_PARAM, "the request body must be a JSON object");
        return NULL;
    }
    return j;
}

static void add_error(json_t *errors, ts_err *err, int *count, ts_rc code, const char *pointer,
                      const char *msg)
{
    tsa_errors_add(errors, *count, pointer, msg);
    if ((*count)++ == 0) ts_err_set(err, code, pointer, "%s", msg);
}

static const char *type_word(const json_t *j)
{
    switch (json_typeof(j)) {
    case JSON_OBJECT:
        return "an object";
    case JSON_ARRAY:
        return "an array";
    case JSON_STRING:
        return "a string";
    case JSON_INTEGER:
    case JSON_REAL:
        return "a number";
    case JSON_TRUE:
    case JSON_FALSE:
        return "a boolean";
    default:
        return "null";
    }
}

ts_rc tsa_read_numbers(const json_t *obj, const tsa_num_field *f, int nf, json_t *errors,
                       ts_err *err)
{
    int count = 0;
    ts_rc first = TS_OK;
    char ptr[TS_ERR_POINTER_LEN], msg[TS_ERR_MSG_LEN];
    const char *key;
    json_t *val;
    json_object_foreach((json_t *)obj, key, val)
    {
        int known = 0;
        for (int i = 0; i < nf; i++)
            known |= strcmp(f[i].name, key) == 0;
        if (known) continue;
        tsa_pointer_join(ptr, sizeof ptr, "", key);
        snprintf(msg, sizeof msg, "%.100s: unknown field", ptr);
        if (!count) first = TS_ERR_PARAM;
        add_error(errors, err, &count, TS_ERR_PARAM, ptr, msg);
    }
    for (int i = 0; i < nf; i++) {
        json_t *v = json_object_get(obj, f[i].name);
        snprintf(ptr, sizeof ptr, "/%s", f[i].name);
        if (f[i].present) *f[i].present = v != NULL;
        if (!v) {
            if (!f[i].required) continue;
            snprintf(msg, sizeof msg, "%s: required number is missing", ptr);
            if (!count) first = TS_ERR_PARAM;
            add_error(errors, err, &count, TS_ERR_PARAM, ptr, msg);
            continue;
        }
        if (!json_is_number(v)) {
            snprintf(msg, sizeof msg, "%s: number expected, got %s", ptr, type_word(v));
            if (!count) first = TS_ERR_PARAM;
            add_error(errors, err, &count, TS_ERR_PARAM, ptr, msg);
            continue;
        }
        double x = json_number_value(v);
        if (!(x >= f[i].min && x <= f[i].max)) {
            snprintf(msg, sizeof msg, "%s: number in [%g, %g]%s%s expected, got %g", ptr, f[i].min,
                     f[i].max, f[i].unit ? " " : "", f[i].unit ? f[i].unit : "", x);
            if (!count) first = TS_ERR_RANGE;
            add_error(errors, err, &count, TS_ERR_RANGE, ptr, msg);
            continue;
        }
        *f[i].out = x;
    }
    return first;
}

/* ---- channels --------------------------------------------------------------- */

ts_rc tsa_channels_from_model(tsa_channels *c, ts_channel *store, int cap, const ts_model *m,
                              ts_err *err)
{
    const int n = ts_model_nchannel(m);
    *c = (tsa_channels){NULL, 0, 0.0};
    if (n > cap)
        return ts_err_set(err, TS_ERR_LIMIT, NULL, "the model has %d channels, room for %d", n,
                          cap);
    for (int i = 0; i < n; i++)
        store[i] = *ts_model_channel(m, i);
    *c = (tsa_channels){store, n, ts_model_sample_period(m)};
    return TS_OK;
}

int tsa_channel_index(const tsa_channels *c, const char *name)
{
    for (int i = 0; i < c->n; i++)
        if (strcmp(c->v[i].name, name) == 0) return i;
    return -1;
}

json_t *tsa_channels_json(const tsa_channels *c, const int *idx, int n)
{
    json_t *a = json_array();
    if (!idx) n = c->n;
    for (int k = 0; k < n; k++) {
        const ts_channel *ch = &c->v[idx ? idx[k] : k];
        json_array_append_new(a, json_pack("{s:s,s:s,s:s}", "name", ch->name, "unit", ch->unit,
                                           "description", ch->description));
    }
    return a;
}

json_t *tsa_json_real(double v)
{
    return isfinite(v) ? json_real(v) : json_null();
}

json_t *tsa_values_json(const tsa_channels *c, const double *row)
{
    json_t *o = json_object();
    for (int i = 0; i < c->n; i++)
        json_object_set_new(o, c->v[i].name, tsa_json_real(row[i]));
    return o;
}

ts_rc tsa_channel_select(const tsa_channels *c, const char *param, const char *list, int *idx,
                         int max, int *n, ts_err *err)
{
    char ptr[TS_ERR_POINTER_LEN];
    snprintf(ptr, sizeof ptr, "/%s", param);
    int k = 0;
    if (max < 1) return ts_err_set(err, TS_ERR_INTERNAL, NULL, "no room for channels");
    idx[k++] = 0;
    if (!list || !*list) {
        for (int i = 1; i < c->n && k < max; i++)
            idx[k++] = i;
        *n = k;
        return TS_OK;
    }
    const char *p = list;
    while (*p) {
        const char *e = strchr(p, ',');
        size_t len = e ? (size_t)(e - p) : strlen(p);
        char name[128];
        if (len >= sizeof name)
            return ts_err_set(err, TS_ERR_PARAM, ptr, "%s: name too long", param);
        memcpy(name, p, len);
        name[len] = '\0';
        if (len > 0) {
            int ci = tsa_channel_index(c, name);
            if (ci < 0)
                return ts_err_set(err, TS_ERR_NOTFOUND, ptr,
                                  "%s: no channel named '%s' (see the session's channels)", param,
                                  name);
            int dup = 0;
            for (int i = 0; i < k; i++)
                dup |= idx[i] == ci;
            if (!dup) {
                if (k >= max)
                    return ts_err_set(err, TS_ERR_LIMIT, ptr, "%s: too many", param);
                idx[k++] = ci;
            }
        }
        p += len;
        if (*p == ',') p++;
    }
    *n = k;
    return TS_OK;
}

/* ---- rows as text ----------------------------------------------------------- */

void tsa_csv_header(tsa_buf *b, const tsa_channels *c, const int *idx, int n)
{
    for (int i = 0; i < n; i++)
        tsa_buf_printf(b, "%s%s [%s]", i ? "," : "", c->v[idx[i]].name, c->v[idx[i]].unit);
    tsa_buf_put(b, "\n", 1);
}

void tsa_csv_row(tsa_buf *b, const double *row, const int *idx, int n)
{
    for (int i = 0; i < n; i++) {
        if (i) tsa_buf_put(b, ",", 1);
        if (isfinite(row[idx[i]])) tsa_buf_printf(b, idx[i] == 0 ? "%.12g" : "%.9g", row[idx[i]]);
    }
    tsa_buf_put(b, "\n", 1);
}

void tsa_row_json(tsa_buf *b, const tsa_channels *c, long index, const double *row, const int *idx,
                  int n)
{
    tsa_buf_printf(b, "{\"index\":%ld,\"t\":", index);
    put_num(b, row[0], 1);
    tsa_buf_put(b, ",\"values\":{", 11);
    int first = 1;
    for (int i = 0; i < n; i++) {
        if (idx[i] == 0) continue;
        if (!first) tsa_buf_put(b, ",", 1);
        first = 0;
        put_str(b, c->v[idx[i]].name);
        tsa_buf_put(b, ":", 1);
        put_num(b, row[idx[i]], 0);
    }
    tsa_buf_put(b, "}}", 2);
}

void tsa_series_json(tsa_buf *b, const char *session, const tsa_channels *c, const int *idx, int n,
                     const long *index, const double *rows, long nrows, long every,
                     const char *next_token)
{
    tsa_buf_put(b, "{\"session\":", 11);
    put_str(b, session);
    tsa_buf_printf(b, ",\"sample_rate\":%.12g,\"every\":%ld,\"count\":%ld,\"index\":[",
                   1.0 / c->period, every, nrows);
    for (long r = 0; r < nrows; r++)
        tsa_buf_printf(b, r ? ",%ld" : "%ld", index[r]);
    tsa_buf_put(b, "],\"channels\":[", 14);
    for (int i = 0; i < n; i++) {
        const ts_channel *ch = &c->v[idx[i]];
        tsa_buf_put(b, i ? ",{\"name\":" : "{\"name\":", i ? 9 : 8);
        put_str(b, ch->name);
        tsa_buf_put(b, ",\"unit\":", 8);
        put_str(b, ch->unit);
        tsa_buf_put(b, ",\"values\":[", 11);
        for (long r = 0; r < nrows; r++) {
            if (r) tsa_buf_put(b, ",", 1);
            put_num(b, rows[(size_t)r * (size_t)c->n + (size_t)idx[i]], idx[i] == 0);
        }
        tsa_buf_put(b, "]}", 2);
    }
    tsa_buf_put(b, "]", 1);
    if (next_token) {
        tsa_buf_put(b, ",\"next_page_token\":", 19);
        put_str(b, next_token);
    }
    tsa_buf_put(b, "}", 1);
}

/* ---- integrator work ------------------------------------------------------------ */

static json_t *count_json(long v)
{
    return v >= 0 ? json_integer((json_int_t)v) : json_null();
}

json_t *tsa_integrators_json(const ts_integrator_stats *s, int n)
{
    json_t *a = json_array();
    for (int i = 0; a && i < n; i++) {
        json_t *o = json_pack("{s:s,s:s}", "integrator", s[i].name, "method", s[i].method);
        if (!o) break;
        json_object_set_new(o, "steps", count_json(s[i].steps));
        json_object_set_new(o, "rhs_evals", count_json(s[i].rhs_evals));
        json_object_set_new(o, "jac_evals", count_json(s[i].jac_evals));
        json_object_set_new(o, "lin_setups", count_json(s[i].lin_setups));
        json_object_set_new(o, "err_test_fails", count_json(s[i].err_test_fails));
        json_object_set_new(o, "newton_iters", count_json(s[i].newton_iters));
        json_object_set_new(o, "newton_fails", count_json(s[i].newton_fails));
        json_array_append_new(a, o);
    }
    return a;
}

/* ---- run figures ------------------------------------------------------------ */

ts_rc tsa_model_metrics(const ts_model *m, const double *rows, long nrows, ts_metric **out, int *n,
                        ts_err *err)
{
    *out = NULL;
    *n = 0;
    int cap = TSA_METRICS_FIRST;
    for (int attempt = 0; attempt < 2; attempt++) {
        ts_metric *mt = malloc(sizeof *mt * (size_t)cap);
        if (!mt)
            return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory for %d run figures", cap);
        int k = ts_model_metrics(m, rows, nrows, mt, cap);
        if (k <= cap) {
            *out = mt;
            *n = k;
            return TS_OK;
        }
        free(mt); /* k figures, room for cap: once more with room for all */
        cap = k;
    }
    return ts_err_set(err, TS_ERR_INTERNAL, NULL,
                      "the %s model's figure count changed between two calls over the same rows",
                      ts_model_kind(m));
}

json_t *tsa_metrics_json(const ts_metric *mt, int n)
{
    json_t *a = json_array();
    for (int i = 0; a && i < n; i++) {
        json_t *o = json_pack("{s:s,s:s,s:o,s:s}", "name", mt[i].name, "unit", mt[i].unit, "value",
                              tsa_json_real(mt[i].value), "description", mt[i].description);
        if (!o || json_array_append_new(a, o) != 0) {
            json_decref(a);
            return NULL;
        }
    }
    return a;
}

json_t *tsa_run_summary_json(const tsa_run_summary *v)
{
    json_t *metrics = tsa_metrics_json(v->metrics, v->nmetric);
    if (!metrics) return NULL;
    return json_pack("{s:s,s:s,s:s,s:b,s:f,s:I,s:i,s:o}", "id", v->id, "kind", v->kind, "status",
                     v->status, "complete", v->complete, "t", v->t, "rows", (json_int_t)v->rows,
                     "dof", v->dof, "metrics", metrics);
}

/* ---- session ---------------------------------------------------------------- */

json_t *tsa_session_json(const tsa_session_view *v, int summary)
{
    char base[160];
    snprintf(base, sizeof base, "/v1/sessions/%s", v->id);
    json_t *links = json_object();
    json_object_set_new(links, "self", json_string(base));
    static const char *const rel[] = {"step", "run",     "series",    "stream",
                                      "fft",  "summary", "frame.png", "frames"};
    for (size_t i = 0; i < sizeof rel / sizeof rel[0]; i++) {
        char u[200];
        snprintf(u, sizeof u, "%s/%s", base, rel[i]);
        json_object_set_new(links, rel[i], json_string(u));
    }
    if (v->operation && v->operation[0]) {
        char u[200];
        snprintf(u, sizeof u, "/v1/operations/%s", v->operation);
        json_object_set_new(links, "operation", json_string(u));
    }
    json_t *o = json_pack("{s:s,s:s,s:s,s:f,s:f,s:I,s:I}", "id", v->id, "status", v->status,
                          "preset", v->preset ? v->preset : "", "created", v->created, "t", v->t,
                          "index", (json_int_t)v->index, "samples", (json_int_t)v->persisted);
    if (!o) {
        json_decref(links);
        return NULL;
    }
    if (v->m) {
        json_object_set_new(o, "kind", json_string(ts_model_kind(v->m)));
        json_object_set_new(o, "duration", json_real(ts_model_config(v->m)->run.duration));
    } else if (v->kind) {
        json_object_set_new(o, "kind", json_string(v->kind));
        json_object_set_new(o, "duration", json_real(v->duration));
    }
    if (v->ch) json_object_set_new(o, "sample_rate", json_real(1.0 / v->ch->period));
    if (v->error && v->error[0]) json_object_set_new(o, "error", json_string(v->error));
    if (v->operation && v->operation[0])
        json_object_set_new(o, "operation", json_string(v->operation));
    if (!summary) {
        if (v->config) json_object_set(o, "config", (json_t *)v->config);
        if (v->ch) {
            json_object_set_new(o, "channels", tsa_channels_json(v->ch, NULL, 0));
            if (v->latest) json_object_set_new(o, "latest", tsa_values_json(v->ch, v->latest));
        }
        if (v->integrators)
            json_object_set_new(o, "integrators",
                                tsa_integrators_json(v->integrators, v->nintegrators));
    }
    json_object_set_new(o, "links", links);
    return o;
}
