/*
 * channels.h — a session's channel table (name, SI unit, description per
 * column of its stored rows, and the sample period) and the text shapes of
 * stored rows built from it: series JSON/CSV, stream rows, channel selection.
 *
 * Why a table and not the model: the rows in the store are laid out by the
 * channel list of the build that wrote them. It is stored with the session
 * (db.h sessions.channels) at creation, so a session whose config no longer
 * builds a model (an upgrade removed its kind, changed a parameter's range)
 * or whose model now has other channels is still served from its stored rows
 * with its own names and units. Sessions stored before that column existed
 * take the table from their model, as they did before.
 *
 * The text shapes are the same as api/session_json.h's tsa_csv_header,
 * tsa_row_json, tsa_series_json and tsa_channel_select (%.12g for time, %.9g
 * otherwise, null for non-finite), with the table in place of the model; the
 * daemon's reads go through this one path for every session.
 *
 * Ownership: a tsd_channels owns doc; the ts_channel strings point into doc,
 * or into the model it was taken from (which must outlive it).
 */
#ifndef TSD_CHANNELS_H
#define TSD_CHANNELS_H

#include <jansson.h>

#include "../api/session_json.h"
#include "../sim/model.h"

typedef struct tsd_channels {
    json_t *doc;     /* the stored document (NULL when taken from a model) */
    ts_channel *v;   /* n entries, v[0] is time "t" */
    int n;
    double period;   /* sample period [s] */
} tsd_channels;

/* The stored form of m's table: {"sample_rate": Hz, "channels": [{"name",
 * "unit", "description"}, ...]}, malloc'd compact JSON text; NULL on no memory. */
char *tsd_channels_dump(const ts_model *m);

/* Fill c from m (strings borrowed from m). 0, or -1 on no memory. */
int tsd_channels_from_model(tsd_channels *c, const ts_model *m);

/* Fill c from stored text (tsd_channels_dump's form). 0, or -1 with the
 * reason in why (malformed, no channels, first channel not "t"). */
int tsd_channels_parse(tsd_channels *c, const char *text, char *why, size_t whylen);

/* 1 when c lists exactly m's channels (names and units, in order) and sample period. */
int tsd_channels_match(const tsd_channels *c, const ts_model *m);

void tsd_channels_free(tsd_channels *c); /* zeroes c; a zeroed c is a no-op */

/* Comma-separated names -> column indexes, "t" (0) always first, duplicates
 * dropped; NULL or "" selects all (at most max). TS_ERR_NOTFOUND names an
 * unknown channel, pointer /channels. */
ts_rc tsd_channels_select(const tsd_channels *c, const char *list, int *idx, int max, int *n,
                          ts_err *err);

/* {"name": value, ...} of one row of c->n values. */
json_t *tsd_channels_values_json(const tsd_channels *c, const double *row);
/* [{"name", "unit", "description"}, ...] */
json_t *tsd_channels_json(const tsd_channels *c);

void tsd_channels_csv_header(tsa_buf *b, const tsd_channels *c, const int *idx, int n);
void tsd_channels_row_json(tsa_buf *b, const tsd_channels *c, long index, const double *row,
                           const int *idx, int n);
void tsd_channels_series_json(tsa_buf *b, const char *session, const tsd_channels *c,
                              const int *idx, int n, const long *index, const double *rows,
                              long nrows, long every, const char *next_token);

#endif
