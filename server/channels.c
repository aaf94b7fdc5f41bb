/*
 * channels.c — a session's channel table (channels.h): its stored form, read
 * back and checked, or taken from a model. The text of the rows is
 * api/session_json.c's (tsa_series_json, tsa_row_json, ...), fed c->view.
 */
#include "channels.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

char *tsd_channels_dump(const tsa_channels *c)
{
    json_t *o =
        json_pack("{s:f,s:o}", "sample_rate", 1.0 / c->period, "channels", tsa_channels_json(c, NULL, 0));
    char *text = o ? json_dumps(o, JSON_COMPACT | JSON_REAL_PRECISION(17)) : NULL;
    json_decref(o);
    return text;
}

int tsd_channels_from_model(tsd_channels *c, const ts_model *m)
{
    memset(c, 0, sizeof *c);
    int n = ts_model_nchannel(m);
    c->own = calloc((size_t)(n > 0 ? n : 1), sizeof *c->own);
    if (!c->own) return -1;
    ts_err err;
    if (tsa_channels_from_model(&c->view, c->own, n, m, &err) != TS_OK) { /* n entries: fits */
        tsd_channels_free(c);
        return -1;
    }
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
        snprintf(why, whylen, "its stored channel list is malformed%s%.100s", doc ? "" : ": ",
                 doc ? "" : je.text);
        json_decref(doc);
        return -1;
    }
    c->own = calloc(n, sizeof *c->own);
    if (!c->own) {
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
            free(c->own);
            c->own = NULL;
            json_decref(doc);
            return -1;
        }
        c->own[i] = (ts_channel){name, unit, desc ? desc : ""};
    }
    c->doc = doc;
    c->view = (tsa_channels){c->own, (int)n, 1.0 / rate};
    return 0;
}

int tsd_channels_match(const tsd_channels *c, const ts_model *m)
{
    const tsa_channels *t = &c->view;
    if (t->n != ts_model_nchannel(m)) return 0;
    /* rates are stored with 17 digits: the round trip is exact up to 1/x */
    if (fabs(t->period - ts_model_sample_period(m)) > 1e-12 * t->period) return 0;
    for (int i = 0; i < t->n; i++) {
        const ts_channel *k = ts_model_channel(m, i);
        if (strcmp(t->v[i].name, k->name) != 0 || strcmp(t->v[i].unit, k->unit) != 0) return 0;
    }
    return 1;
}

void tsd_channels_free(tsd_channels *c)
{
    json_decref(c->doc);
    free(c->own);
    memset(c, 0, sizeof *c);
}
