/*
 * channels.h — a session's channel table (name, SI unit, description per
 * column of its stored rows, and the sample period): kept with the session in
 * the database, read back, matched against a model.
 *
 * Why a table and not the model: the rows in the store are laid out by the
 * channel list of the build that wrote them. It is stored with the session
 * (db.h sessions.channels) at creation, so a session whose config no longer
 * builds a model (an upgrade removed its kind, changed a parameter's range)
 * or whose model now has other channels is still served from its stored rows
 * with its own names and units. Sessions stored before that column existed
 * take the table from their model, as they did before.
 *
 * What is the daemon's own is here: storing the table with a session, parsing
 * it back, matching it against a model. Every text and JSON shape of the rows
 * (series JSON/CSV, stream rows, channel lists, latest values, channel
 * selection) is api/session_json.h's, fed the table's tsa_channels view, so a
 * session served from its stored list reads exactly as one served from its
 * model.
 *
 * Ownership: a tsd_channels owns its entries (own) and doc; the entries'
 * strings point into doc, or into the model the table was taken from (which
 * must outlive it). view borrows both: valid until tsd_channels_free.
 */
#ifndef TSD_CHANNELS_H
#define TSD_CHANNELS_H

#include <jansson.h>

#include "../api/session_json.h"
#include "../sim/model.h"

typedef struct tsd_channels {
    tsa_channels view; /* for session_json.h: view.v = own, v[0] is time "t" */
    ts_channel *own;   /* view.n entries (malloc'd) */
    json_t *doc;       /* the stored document (NULL when taken from a model) */
} tsd_channels;

/* The stored form of a table: {"sample_rate": Hz, "channels": [{"name",
 * "unit", "description"}, ...]}, malloc'd compact JSON text; NULL on no memory. */
char *tsd_channels_dump(const tsa_channels *c);

/* Fill c from m (strings borrowed from m). 0, or -1 on no memory. */
TS_MUST_CHECK int tsd_channels_from_model(tsd_channels *c, const ts_model *m);

/* Fill c from stored text (tsd_channels_dump's form). 0, or -1 with the
 * reason in why (malformed, no channels, first channel not "t"). */
TS_MUST_CHECK int tsd_channels_parse(tsd_channels *c, const char *text, char *why, size_t whylen);

/* 1 when c lists exactly m's channels (names and units, in order) and sample period. */
int tsd_channels_match(const tsd_channels *c, const ts_model *m);

void tsd_channels_free(tsd_channels *c); /* zeroes c; a zeroed c is a no-op */

#endif
