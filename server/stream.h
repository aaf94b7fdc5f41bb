/*
 * stream.h — live samples of a session over one long HTTP response.
 *
 * Formats: Server-Sent Events (text/event-stream; "id: INDEX", "event:
 * sample", "data: {index,t,values}"; a final "event: end" with the session's
 * status) or NDJSON (application/x-ndjson; one {index,t,values} per line).
 * The stream starts after sample `since` (Last-Event-ID or ?since=; -1 = from
 * row 0), sends every stored row in index order, then waits for more while
 * the session is running and ends when it is not: so a client that
 * reconnects with the last id it saw gets each row exactly once.
 *
 * No thread waits: when no row is stored yet the content-reader callback
 * suspends the connection (MHD_suspend_connection) and registers it with the
 * session; the worker that stores the next batch, or ends the run, resumes
 * it (session.c wake_locked). Rows are read from the database (db.h), so a
 * stream sees exactly what a series query or a restarted daemon sees.
 */
#ifndef TSD_STREAM_H
#define TSD_STREAM_H

#include "server.h"
#include "session.h"

/* Queue the streaming response. idx[n] are the channels (index 0 = t first). */
enum MHD_Result tsd_stream_reply(tsd_request *r, tsd_session *s, const int *idx, int n, long since,
                                 int ndjson);

#endif
