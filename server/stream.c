/*
 * stream.c — SSE / NDJSON streaming of stored samples (stream.h).
 */
#define _GNU_SOURCE
#include "stream.h"

#include <stdlib.h>
#include <string.h>

#include "../api/session_json.h"
#include "db.h"

#define CHUNK_ROWS          256 /* rows read from the database per refill */
#define MAX_STREAM_CHANNELS 512

typedef struct stream_ctx {
    tsd_server *srv;
    tsd_session *s; /* reference held until the response is freed */
    tsd_waiter w;
    int idx[MAX_STREAM_CHANNELS];
    int n;
    long next; /* index of the next row to send */
    int ndjson;
    int ended;
    int failed; /* a database read failed: cut the stream */
    int cut;    /* a damaged stored row: cut the stream once the text before it is sent */
    tsa_buf buf; /* formatted text not yet handed to MHD */
    size_t off;
    long index[CHUNK_ROWS];
    double *rows; /* CHUNK_ROWS x nch */
} stream_ctx;

/* The rows before a damaged stored row are sent, then (SSE) an error event
 * naming it, then the stream is cut: a clean end would claim every row was
 * sent, and a reconnecting client meets the same row again. */
static void damaged_end(stream_ctx *c, long bad)
{
    if (!c->ndjson)
        tsa_buf_printf(&c->buf,
                       "event: error\ndata: {\"status\":500,\"detail\":\"stored row %ld of "
                       "session %s is damaged (not %d channels wide); the store was changed "
                       "outside the daemon\"}\n\n",
                       bad, c->s->id, c->s->nch);
    c->cut = 1;
}

static void finish(stream_ctx *c)
{
    c->ended = 1;
    if (c->ndjson) { /* no end line in NDJSON: a deleted session's stream is cut, so the
                        client does not take the rows it got for all of them */
        if (tsd_session_is_deleted(c->s)) c->cut = 1;
        return;
    }
    json_t *j = tsd_session_json(c->s, 1);
    json_t *st = json_pack("{s:O,s:O,s:O}", "status", json_object_get(j, "status"), "t",
                           json_object_get(j, "t"), "index", json_object_get(j, "index"));
    char *text = st ? json_dumps(st, JSON_COMPACT) : NULL;
    tsa_buf_printf(&c->buf, "event: end\ndata: %s\n\n", text ? text : "{}");
    free(text);
    json_decref(st);
    json_decref(j);
}

static void refill(stream_ctx *c)
{
    tsd_session *s = c->s;
    int more;
    long got = tsd_db_rows(c->srv->db, s->seq, c->next, c->next + CHUNK_ROWS - 1, 1, CHUNK_ROWS,
                           s->nch, NULL, s->nch, c->index, c->rows, &more);
    long bad = -1;
    if (got == -2) { /* a damaged row: the rows before it, then the error */
        bad = c->index[0];
        got = bad > c->next ? tsd_db_rows(c->srv->db, s->seq, c->next, bad - 1, 1, CHUNK_ROWS,
                                          s->nch, NULL, s->nch, c->index, c->rows, &more)
                            : 0;
        if (got == 0) {
            damaged_end(c, bad);
            return;
        }
    }
    if (got < 0) { /* database error: cut the stream, so that the client sees it is
                      incomplete (a clean end would claim every row was sent) */
        c->failed = 1;
        return;
    }
    if (got == 0) { /* the rows went with the session (deleted under us): end as the
                       await path does, with the end event saying so; rows that vanished
                       otherwise cut the stream (a clean end would claim them sent) */
        if (tsd_session_is_deleted(s))
            finish(c);
        else
            c->failed = 1;
        return;
    }
    for (long k = 0; k < got; k++) {
        const double *row = c->rows + (size_t)k * (size_t)s->nch;
        if (c->ndjson) {
            tsa_row_json(&c->buf, &s->ch.view, c->index[k], row, c->idx, c->n);
            tsa_buf_put(&c->buf, "\n", 1);
        } else {
            tsa_buf_printf(&c->buf, "id: %ld\nevent: sample\ndata: ", c->index[k]);
            tsa_row_json(&c->buf, &s->ch.view, c->index[k], row, c->idx, c->n);
            tsa_buf_put(&c->buf, "\n\n", 2);
        }
    }
    c->next = c->index[got - 1] + 1;
    if (bad >= 0) damaged_end(c, bad);
}

static ssize_t reader(void *cls, uint64_t pos, char *out, size_t max)
{
    (void)pos;
    stream_ctx *c = cls;
    if (c->off >= c->buf.n) {
        c->buf.n = 0;
        c->off = 0;
        if (c->cut) return MHD_CONTENT_READER_END_WITH_ERROR;
        if (c->ended) return MHD_CONTENT_READER_END_OF_STREAM;
        int r = tsd_session_await(c->s, c->next, &c->w);
        if (r == 0) return 0; /* suspended; resumed by the next stored batch */
        if (r > 0)
            refill(c);
        else
            finish(c);
        if (c->buf.oom || c->failed) return MHD_CONTENT_READER_END_WITH_ERROR;
        if (c->buf.n == 0)
            return c->cut     ? MHD_CONTENT_READER_END_WITH_ERROR
                   : c->ended ? MHD_CONTENT_READER_END_OF_STREAM
                              : 0;
    }
    size_t k = c->buf.n - c->off;
    if (k > max) k = max;
    memcpy(out, c->buf.p + c->off, k);
    c->off += k;
    return (ssize_t)k;
}

static void release(void *cls)
{
    stream_ctx *c = cls;
    tsd_session_unwait(c->s, &c->w);
    tsd_session_put(c->s);
    tsa_buf_free(&c->buf);
    free(c->rows);
    free(c);
}

enum MHD_Result tsd_stream_reply(tsd_request *r, tsd_session *s, const int *idx, int n, long since,
                                 int ndjson)
{
    stream_ctx *c = calloc(1, sizeof *c);
    if (!c) return MHD_NO;
    c->rows = calloc((size_t)CHUNK_ROWS * (size_t)s->nch, sizeof *c->rows);
    if (!c->rows) {
        free(c);
        return MHD_NO;
    }
    c->srv = r->srv;
    c->s = s;
    c->w.conn = r->conn;
    c->n = n < MAX_STREAM_CHANNELS ? n : MAX_STREAM_CHANNELS;
    memcpy(c->idx, idx, sizeof(int) * (size_t)c->n);
    c->next = since + 1 > 0 ? since + 1 : 0;
    c->ndjson = ndjson;
    tsd_session_hold(s);
    if (!ndjson) {
        tsa_buf_put(&c->buf, "retry: 1000\n\n", 13);
        /* the rows carry names only: say once what they are and in which unit */
        json_t *list = tsa_channels_json(&s->ch.view, c->idx, c->n);
        char *text = json_dumps(list, JSON_COMPACT);
        tsa_buf_printf(&c->buf, "event: channels\ndata: %s\n\n", text ? text : "[]");
        free(text);
        json_decref(list);
    }
    return tsd_reply_chunked(r, ndjson ? "application/x-ndjson" : "text/event-stream", 16384,
                             reader, c, release);
}
