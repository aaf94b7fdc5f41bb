/*
 * channels.c — a session's channel table and the text of its stored rows
 * (channels.h). The formats match api/session_json.c byte for byte (the
 * daemon's tests compare served series with those of a model-built session).
 */
#define _GNU_SOURCE
#include "channels.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

char *tsd_channels_dump(const ts_model *m)
{
    json_t *o = json_pack("{s:f,s:o}", "sample_rate", 1.0 / ts_model_sample_period(m),
                          "channels", tsa_channels_json(m));
    char *text = o ? json_dumps(o, JSON_COMPACT | JSON_REAL_PRECISION(17)) : NULL;
    json_decref(o);
    return text;
}

int tsd_channels_from_model(tsd_channels *c, const ts_model *m)
{
    memset(c, 0, sizeof *c);
    int n = ts_model_nchannel(m);
    c->v = calloc((size_t)(n > 0 ? n : 1), sizeof *c->v);
    if (!c->v) return -1;
    for (int i = 0; i < n; i++)
        c->v[i] = *ts_model_channel(m, i);
    c->n = n;
    c->period = ts_model_sample_period(m);
    return 0;
}

int tsd_channels_parse(tsd_channels *c, const char *text, char *why, size_t whylen)
{
    memset(c, 0, sizeof *c);
    json_error_t je;
    json_t *doc = json_loads(text, 0, &je);
    json_t *arr = json_object_get(doc, "channels");
    double rate = json_number_value(json_object_get(doc, "sample_rate"));
    size_t n = json_array_size(arr);
    if (!doc || !json_is_array(arr) || n == 0 || n > 100000 || !(rate > 0) || !isfinite(rate)) {
        snprintf(why, whylen, "its stored channel list is malformed%s%.100s",
                 doc ? "" : ": ", doc ? "" : je.text);
        json_decref(doc);
        return -1;
    }
    c->v = calloc(n, sizeof *c->v);
    if (!c->v) {
        snprintf(why, whylen, "out of memory");
        json_decref(doc);
        return -1;
    }
    for (size_t i = 0; i < n; i++) {
        json_t *e = json_array_get(arr, i);
        const char *name = json_string_value(json_object_get(e, "name"));
        const char *unit = json_string_value(json_object_get(e, "unit"));
        const char *desc = json_string_value(json_object_get(e, "description"));
        if (!name || !*name || !unit || (i == 0 && strcmp(name, "t") != 0)) {
            snprintf(why, whylen, "its stored channel %zu is malformed", i);
            free(c->v);
            c->v = NULL;
            json_decref(doc);
            return -1;
        }
        c->v[i] = (ts_channel){name, unit, desc ? desc : ""};
    }
    c->doc = doc;
    c->n = (int)n;
    c->period = 1.0 / rate;
    return 0;
}

int tsd_channels_match(const tsd_channels *c, const ts_model *m)
{
    if (c->n != ts_model_nchannel(m)) return 0;
    /* rates are stored with 17 digits: the round trip is exact up to 1/x */
    if (fabs(c->period - ts_model_sample_period(m)) > 1e-12 * c->period) return 0;
    for (int i = 0; i < c->n; i++) {
        const ts_channel *k = ts_model_channel(m, i);
        if (strcmp(c->v[i].name, k->name) != 0 || strcmp(c->v[i].unit, k->unit) != 0) return 0;
    }
    return 1;
}

void tsd_channels_free(tsd_channels *c)
{
    json_decref(c->doc);
    free(c->v);
    memset(c, 0, sizeof *c);
}

static int index_of(const tsd_channels *c, const char *name)
{
    for (int i = 0; i < c->n; i++)
        if (strcmp(c->v[i].name, name) == 0) return i;
    return -1;
}

ts_rc tsd_channels_select(const tsd_channels *c, const char *list, int *idx, int max, int *n,
                          ts_err *err)
{
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
            return ts_err_set(err, TS_ERR_PARAM, "/channels", "channels: name too long");
        memcpy(name, p, len);
        name[len] = '\0';
        if (len > 0) {
            int ci = index_of(c, name);
            if (ci < 0)
                return ts_err_set(err, TS_ERR_NOTFOUND, "/channels",
                                  "channels: no channel named '%s' (see the session's channels)",
                                  name);
            int dup = 0;
            for (int i = 0; i < k; i++)
                dup |= idx[i] == ci;
            if (!dup) {
                if (k >= max)
                    return ts_err_set(err, TS_ERR_LIMIT, "/channels", "channels: too many");
                idx[k++] = ci;
            }
        }
        p += len;
        if (*p == ',') p++;
    }
    *n = k;
    return TS_OK;
}

json_t *tsd_channels_values_json(const tsd_channels *c, const double *row)
{
    json_t *o = json_object();
    for (int i = 0; i < c->n; i++)
        json_object_set_new(o, c->v[i].name, isfinite(row[i]) ? json_real(row[i]) : json_null());
    return o;
}

json_t *tsd_channels_json(const tsd_channels *c)
{
    json_t *a = json_array();
    for (int i = 0; i < c->n; i++)
        json_array_append_new(a, json_pack("{s:s,s:s,s:s}", "name", c->v[i].name, "unit",
                                           c->v[i].unit, "description", c->v[i].description));
    return a;
}

/* As api/session_json.c: %.12g for time (t = index / rate round-trips), %.9g
 * otherwise, null when not finite. */
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

void tsd_channels_csv_header(tsa_buf *b, const tsd_channels *c, const int *idx, int n)
{
    for (int i = 0; i < n; i++)
        tsa_buf_printf(b, "%s%s [%s]", i ? "," : "", c->v[idx[i]].name, c->v[idx[i]].unit);
    tsa_buf_put(b, "\n", 1);
}

void tsd_channels_row_json(tsa_buf *b, const tsd_channels *c, long index, const double *row,
                           const int *idx, int n)
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

void tsd_channels_series_json(tsa_buf *b, const char *session, const tsd_channels *c,
                              const int *idx, int n, const long *index, const double *rows,
                              long nrows, long every, const char *next_token)
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
