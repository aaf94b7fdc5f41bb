/*
 * server.c — tanksimd's HTTP plumbing over libmicrohttpd: listening socket,
 * the per-request lifecycle (allocate on first call, collect the body, route,
 * log and free on completion) and the response helpers.
 */
#define _GNU_SOURCE
#include "server.h"

#include "../api/problem.h"
#include "db.h"
#include "pool.h"
#include "session.h"

#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

static enum MHD_Result queue(tsd_request *r, unsigned status, struct MHD_Response *resp,
                             const char *content_type, size_t len)
{
    if (!resp) return MHD_NO;
    if (content_type) MHD_add_response_header(resp, MHD_HTTP_HEADER_CONTENT_TYPE, content_type);
    if (r->etag[0] && (status == 200 || status == 304)) { /* a stored sample's frame never changes */
        MHD_add_response_header(resp, MHD_HTTP_HEADER_ETAG, r->etag);
        MHD_add_response_header(resp, "Cache-Control", "private, max-age=31536000, immutable");
    } else {
        MHD_add_response_header(resp, "Cache-Control", "no-store");
    }
    if (r->location[0]) MHD_add_response_header(resp, MHD_HTTP_HEADER_LOCATION, r->location);
    if (r->next_token[0]) MHD_add_response_header(resp, "X-Next-Page-Token", r->next_token);
    if (r->retry_after > 0) {
        char ra[16];
        snprintf(ra, sizeof ra, "%d", r->retry_after);
        MHD_add_response_header(resp, MHD_HTTP_HEADER_RETRY_AFTER, ra);
    }
    if (r->allow[0] && status == 405) /* RFC 9110 §15.5.6: a 405 lists what is allowed */
        MHD_add_response_header(resp, MHD_HTTP_HEADER_ALLOW, r->allow);
    if (r->www_authenticate)
        MHD_add_response_header(resp, MHD_HTTP_HEADER_WWW_AUTHENTICATE,
                                "Bearer realm=\"tanksimd\"");
    r->status = status;
    r->bytes = len;
    enum MHD_Result ret = MHD_queue_response(r->conn, status, resp);
    MHD_destroy_response(resp);
    return ret;
}

int tsd_request_is_head(const tsd_request *r)
{
    return strcmp(r->method, "HEAD") == 0;
}

static ssize_t no_body(void *cls, uint64_t pos, char *buf, size_t max)
{
    (void)cls;
    (void)pos;
    (void)buf;
    (void)max;
    return MHD_CONTENT_READER_END_OF_STREAM;
}

/* An answer without a body and WITHOUT Content-Length: a 304, or the HEAD of
 * a streamed (chunked) GET. RFC 9110 §8.6: Content-Length there may only be
 * the length the 200's content would have had, which is unknown (a frame not
 * drawn, a stream not yet made). In libmicrohttpd 0.9.75 a response of known
 * size always gets its own Content-Length ("0" for an empty buffer;
 * MHD_RF_INSANITY_HEADER_CONTENT_LENGTH only lets the application add a second
 * one), and one of unknown size is sent chunked, its last chunk "0\r\n\r\n"
 * following the header as stray bytes. Unknown size in its HTTP/1.0-compatible
 * mode is the one combination with neither: the end of the (empty) answer is
 * the connection closing ("Connection: close" is sent), and the reader is
 * never called. content_type NULL: none. */
static enum MHD_Result reply_no_length(tsd_request *r, unsigned status, const char *content_type)
{
    struct MHD_Response *resp =
        MHD_create_response_from_callback(MHD_SIZE_UNKNOWN, 16, no_body, NULL, NULL);
    if (resp &&
        MHD_set_response_options(resp, MHD_RF_HTTP_1_0_COMPATIBLE_STRICT, MHD_RO_END) != MHD_YES) {
        MHD_destroy_response(resp);
        resp = NULL;
    }
    return queue(r, status, resp, content_type, 0);
}

enum MHD_Result tsd_reply_chunked(tsd_request *r, const char *content_type, size_t block,
                                  MHD_ContentReaderCallback reader, void *ctx,
                                  MHD_ContentReaderFreeCallback release)
{
    if (tsd_request_is_head(r)) { /* its GET has no length to give: none (no_length) */
        release(ctx);
        return reply_no_length(r, MHD_HTTP_OK, content_type);
    }
    struct MHD_Response *resp =
        MHD_create_response_from_callback(MHD_SIZE_UNKNOWN, block, reader, ctx, release);
    if (!resp) {
        release(ctx);
        return MHD_NO;
    }
    MHD_add_response_header(resp, "X-Accel-Buffering", "no"); /* proxies: pass it on as made */
    return queue(r, MHD_HTTP_OK, resp, content_type, 0);
}

/* A counted answer (server.h TSD_REPLY_BUDGET): its bytes are given back to
 * the budget when libmicrohttpd frees the response (sent, or the connection
 * closed or timed out). */
typedef struct held_reply {
    tsd_server *srv;
    char *text;
    size_t len;
} held_reply;

static void held_free(void *cls)
{
    held_reply *h = cls;
    atomic_fetch_sub(&h->srv->reply_bytes, h->len);
    free(h->text);
    free(h);
}

enum MHD_Result tsd_reply_busy(tsd_request *r, const char *title, const char *detail)
{
    atomic_fetch_add(&r->srv->metrics.replies_busy, 1);
    r->next_token[0] = r->etag[0] = r->location[0] = '\0'; /* of the answer not sent */
    r->retry_after = TSD_RETRY_AFTER_BUSY_S;
    return tsd_reply_problem(r, MHD_HTTP_SERVICE_UNAVAILABLE, "/problems/busy", title, detail,
                             NULL);
}

/* Whether the reply budget refuses a counted answer of len bytes with held
 * bytes held already: the first one held always goes. */
static int over_budget(size_t held, size_t len)
{
    return held > 0 && held + len > TSD_REPLY_BUDGET;
}

/* The 503 /problems/busy of an answer (len bytes, 0 when not yet made) the
 * reply budget refuses with held bytes held. */
static enum MHD_Result reply_over_budget(tsd_request *r, size_t held, size_t len)
{
    char detail[256];
    char one[64] = "";
    if (len) snprintf(one, sizeof one, "; this one (%zu kB) would pass", len >> 10);
    snprintf(detail, sizeof detail,
             "%zu MB of answers are waiting for their clients to read them%s the daemon's %zu MB "
             "for them: retry shortly",
             held >> 20, len ? one : ",", TSD_REPLY_BUDGET >> 20);
    return tsd_reply_busy(r, "Too many answers waiting to be read", detail);
}

int tsd_reply_budget_full(tsd_request *r, enum MHD_Result *ret)
{
    size_t held = atomic_load(&r->srv->reply_bytes);
    /* reply_buffer refuses any counted answer (>= TSD_REPLY_COUNTED_MIN) past
     * this, as something is held; an answer too small to be counted would
     * still go, but what is asked for here is rarely that small */
    if (!over_budget(held, TSD_REPLY_COUNTED_MIN)) return 0;
    *ret = reply_over_budget(r, held, 0);
    return 1;
}

/* Queue the malloc'd text (taken over) as the answer: counted against the
 * reply budget when large, and replaced by a 503 /problems/busy when the
 * budget cannot take it. */
static enum MHD_Result reply_buffer(tsd_request *r, unsigned status, const char *content_type,
                                    char *text, size_t len)
{
    struct MHD_Response *resp;
    if (len < TSD_REPLY_COUNTED_MIN) {
        resp = MHD_create_response_from_buffer(len, text, MHD_RESPMEM_MUST_FREE);
        if (!resp) free(text);
        return queue(r, status, resp, content_type, len);
    }
    tsd_server *srv = r->srv;
    size_t held = atomic_fetch_add(&srv->reply_bytes, len); /* held before this one */
    if (over_budget(held, len)) {
        /* others are held: this one waits */
        atomic_fetch_sub(&srv->reply_bytes, len);
        free(text);
        return reply_over_budget(r, held, len);
    }
    held_reply *h = malloc(sizeof *h);
    if (!h) {
        atomic_fetch_sub(&srv->reply_bytes, len);
        free(text);
        return MHD_NO;
    }
    *h = (held_reply){srv, text, len};
    resp = MHD_create_response_from_buffer_with_free_callback_cls(len, text, held_free, h);
    if (!resp) held_free(h);
    return queue(r, status, resp, content_type, len);
}

enum MHD_Result tsd_reply_text(tsd_request *r, unsigned status, const char *content_type,
                               const char *text, size_t len)
{
    struct MHD_Response *resp =
        MHD_create_response_from_buffer(len, (void *)text, MHD_RESPMEM_MUST_COPY);
    return queue(r, status, resp, content_type, len);
}

static enum MHD_Result reply_dump(tsd_request *r, unsigned status, json_t *body,
                                  const char *content_type)
{
    /* 17 digits: a double read back is the same double, so a config echoed
     * by the daemon reruns bit for bit (at 12 a session's config gave
     * phi_curvature 8.09366786689e-6 and a point-mass run 4e-5 km/h off) */
    char *text = body ? json_dumps(body, JSON_COMPACT | JSON_REAL_PRECISION(17)) : NULL;
    json_decref(body);
    if (!text) {
        static const char oom[] = "{\"type\":\"/problems/internal\",\"title\":\"Internal error\","
                                  "\"status\":500,\"detail\":\"could not build the response\"}";
        return tsd_reply_text(r, 500, "application/problem+json", oom, sizeof oom - 1);
    }
    return reply_buffer(r, status, content_type, text, strlen(text));
}

enum MHD_Result tsd_reply_owned(tsd_request *r, unsigned status, const char *content_type,
                                char *text, size_t len)
{
    return reply_buffer(r, status, content_type, text, len);
}

enum MHD_Result tsd_reply_not_modified(tsd_request *r)
{
    return reply_no_length(r, MHD_HTTP_NOT_MODIFIED, NULL); /* no Content-Type either (§15.4.5) */
}

enum MHD_Result tsd_reply_problem_json(tsd_request *r, unsigned status, json_t *p)
{
    return reply_dump(r, status, p, "application/problem+json");
}

static int long_job_cap(const tsd_server *s)
{
    return s->opt.threads > 1 ? s->opt.threads - 1 : 1;
}

ts_rc tsd_long_job_take(tsd_server *s, int *retry_after, ts_err *err)
{
    int cap = long_job_cap(s);
    int n = atomic_load(&s->long_jobs);
    do {
        if (n >= cap) {
            *retry_after = TSD_RETRY_AFTER_BUSY_S;
            return ts_err_set(err, TS_ERR_LIMIT, NULL,
                              "%d long jobs already running (engine maps, tunings, APNG "
                              "animations: at most %d at once with %d worker threads, so that "
                              "session runs and steps keep one); retry when one is done",
                              n, cap, s->opt.threads);
        }
    } while (!atomic_compare_exchange_weak(&s->long_jobs, &n, n + 1));
    return TS_OK;
}

void tsd_long_job_give(tsd_server *s)
{
    atomic_fetch_sub(&s->long_jobs, 1);
}

int tsd_client_gone(struct MHD_Connection *conn)
{
    const union MHD_ConnectionInfo *ci =
        MHD_get_connection_info(conn, MHD_CONNECTION_INFO_CONNECTION_FD);
    if (!ci) return 0;
    struct pollfd p = {.fd = ci->connect_fd, .events = POLLRDHUP};
    return poll(&p, 1, 0) > 0 && (p.revents & (POLLRDHUP | POLLHUP | POLLERR));
}

ts_rc tsd_err_shutdown(ts_err *err)
{
    return ts_err_set(err, TSD_ERR_SHUTDOWN, NULL, "%s", TSD_SHUTDOWN_MSG);
}

ts_rc tsd_err_store(const tsd_server *srv, ts_err *err, int dbrc, const char *fmt, ...)
{
    char what[TS_ERR_MSG_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    if (dbrc == TSD_DB_FULL)
        return ts_err_set(err, TSD_ERR_STORE_FULL, NULL,
                          "%s: the disk holding the store (%s) is full; free space there", what,
                          srv->opt.data_dir);
    return ts_err_set(err, TS_ERR_IO, NULL, "%s: the store is failing (see the daemon log)", what);
}

json_t *tsd_problem_from_err(const ts_err *err, json_t *errors)
{
    if (err->code == TSD_ERR_STORE_FULL)
        return tsa_problem(MHD_HTTP_INSUFFICIENT_STORAGE, "/problems/store-full",
                           "Insufficient storage", err->msg, errors);
    return tsa_problem_from_err(err, errors);
}

enum MHD_Result tsd_reply_shutting_down(tsd_request *r, const char *detail)
{
    r->retry_after = TSD_RETRY_AFTER_S;
    return tsd_reply_problem(r, MHD_HTTP_SERVICE_UNAVAILABLE, "/problems/shutting-down",
                             "Shutting down", detail ? detail : TSD_SHUTDOWN_MSG, NULL);
}

enum MHD_Result tsd_reply_err(tsd_request *r, const ts_err *err, json_t *errors)
{
    if (err->code == TSD_ERR_SHUTDOWN) return tsd_reply_shutting_down(r, err->msg);
    json_t *p = tsd_problem_from_err(err, errors);
    return reply_dump(r, (unsigned)json_integer_value(json_object_get(p, "status")), p,
                      "application/problem+json");
}

void tsd_request_defer(tsd_request *r, enum MHD_Result (*on_resume)(tsd_request *r))
{
    r->on_resume = on_resume;
    MHD_suspend_connection(r->conn);
}

void tsd_request_resume(tsd_request *r)
{
    MHD_resume_connection(r->conn);
}

enum MHD_Result tsd_reply_json(tsd_request *r, unsigned status, json_t *body)
{
    return reply_dump(r, status, body, "application/json");
}

enum MHD_Result tsd_reply_problem(tsd_request *r, unsigned status, const char *type,
                                  const char *title, const char *detail, json_t *errors)
{
    /* tsa_problem: detail often quotes the request, which need not be UTF-8 */
    return reply_dump(r, status, tsa_problem((int)status, type, title, detail, errors),
                      "application/problem+json");
}

/* Each connection's requests are parsed in one memory pool of CONN_MEMORY
 * bytes (libmicrohttpd's default, set here because the limits below depend on
 * it): the bytes received, then a 64-byte record for each query parameter and
 * each header, then the response's header. libmicrohttpd 0.9.75 answers a
 * request line that does not fit at all with its own 414 (an HTML body) and
 * too many headers with its own 431, but when the query parameters do not fit
 * it drops the 431 it has queued and waits for the connection timeout
 * (parse_initial_message_line() ignores the failure and moves the connection
 * on to reading headers, with reading stopped): from ~460 short parameters,
 * or fewer long ones, up to a request line of ~32 KiB. So a target longer than
 * MAX_TARGET bytes or with more than MAX_QUERY_PARAMS parameters has its query
 * dropped unread (uri_seen) and is answered 414. Within both limits the line
 * is read into the first half of the pool (plus at most one growth step) and
 * its parameter records take at most 8 KiB, leaving ~6 KiB for headers. */
#define CONN_MEMORY      (32 * 1024)
#define MAX_TARGET       (16 * 1024) /* [bytes] of the request target */
#define MAX_QUERY_PARAMS 128         /* no route reads more than 12 */
#define ARG_RECORD       64          /* [bytes] libmicrohttpd 0.9.75 pool use per parameter */
_Static_assert(MAX_TARGET + 2 * 1024 + MAX_QUERY_PARAMS * ARG_RECORD + 6 * 1024 <= CONN_MEMORY,
               "the request target limits must leave room in the connection's pool");

/* Past either limit: the query is dropped unread and the answer is 414. */
static int target_too_long(const tsd_request *r)
{
    return r->target_len > MAX_TARGET || r->target_params > MAX_QUERY_PARAMS;
}

/* The raw request target, before libmicrohttpd decodes the path in place
 * for the access handler: a %00 would end the path early (".../ID%00/frames"
 * routed as ".../ID") and a %2F would add a segment, so either in the path is
 * refused (400) instead of routed. A target past the limits above is refused
 * (414) and its query cut off here: uri is libmicrohttpd's own request-line
 * buffer, from which it splits the query right after this call, so an empty
 * query there gives no parameters and takes no pool memory. The request
 * object starts here; completed() frees it, also for a request libmicrohttpd
 * itself rejects later. */
static void *uri_seen(void *cls, const char *uri, struct MHD_Connection *conn)
{
    (void)cls;
    (void)conn;
    tsd_request *r = calloc(1, sizeof *r);
    if (!r) return NULL; /* the access handler then closes the connection */
    if (!uri) return r;  /* libmicrohttpd refuses a request line without one first */
    size_t n = strcspn(uri, "?");
    for (size_t i = 0; i + 2 < n; i++)
        if (uri[i] == '%' && ((uri[i + 1] == '0' && uri[i + 2] == '0') ||
                              (uri[i + 1] == '2' && (uri[i + 2] | 0x20) == 'f')))
            r->bad_path = 1;
    r->target_len = strlen(uri);
    if (uri[n] == '?' && uri[n + 1]) { /* as MHD_parse_arguments_: one per '&', plus one */
        r->target_params = 1;
        for (const char *c = uri + n + 1; *c; c++)
            r->target_params += *c == '&';
    }
    if (target_too_long(r)) {
        if (uri[n] == '?') ((char *)uri)[n + 1] = '\0';
    }
    return r;
}

static enum MHD_Result reply_target_too_long(tsd_request *r)
{
    char detail[160];
    if (r->target_params > MAX_QUERY_PARAMS)
        snprintf(detail, sizeof detail,
                 "the request has %zu query parameters; at most %d are read (no route takes "
                 "more than a few)",
                 r->target_params, MAX_QUERY_PARAMS);
    else
        snprintf(detail, sizeof detail,
                 "the request target (path and query) is %zu bytes long; at most %d are read",
                 r->target_len, MAX_TARGET);
    return tsd_reply_problem(r, MHD_HTTP_URI_TOO_LONG, "/problems/uri-too-long",
                             "Request target too long", detail, NULL);
}

static enum MHD_Result reply_too_large(tsd_request *r)
{
    char detail[128];
    snprintf(detail, sizeof detail, "request body larger than %zu bytes", r->srv->opt.max_body);
    return tsd_reply_problem(r, MHD_HTTP_CONTENT_TOO_LARGE, "/problems/body-too-large",
                             "Request body too large", detail, NULL);
}

/* A browser sends any page's form or fetch POST to 127.0.0.1 without asking
 * (a "simple" request needs no CORS preflight): without --token a page of
 * another site could create, run, cancel or delete. Browsers name the page's
 * origin in Origin; one that is not this daemon's own (scheme://Host) is
 * refused for anything but a read. Clients that are not browsers (curl,
 * scripts) send no Origin and are not affected. */
static int cross_site(tsd_request *r)
{
    if (!strcmp(r->method, "GET") || !strcmp(r->method, "HEAD") || !strcmp(r->method, "OPTIONS"))
        return 0;
    const char *origin = MHD_lookup_connection_value(r->conn, MHD_HEADER_KIND, "Origin");
    if (!origin) return 0;
    const char *rest = !strncmp(origin, "http://", 7)    ? origin + 7
                       : !strncmp(origin, "https://", 8) ? origin + 8
                                                         : NULL;
    if (!rest) return 1; /* "null" (a sandboxed page, a file) or anything else */
    /* behind a reverse proxy the public host is in X-Forwarded-Host, which a
     * cross-site page cannot set without a preflight this daemon never grants */
    const char *names[2] = {MHD_HTTP_HEADER_HOST, "X-Forwarded-Host"};
    for (int i = 0; i < 2; i++) {
        const char *host = MHD_lookup_connection_value(r->conn, MHD_HEADER_KIND, names[i]);
        if (host && strcasecmp(rest, host) == 0) return 0;
    }
    return 1;
}

/* MHD_KeyValueIterator: counts the Content-Length headers into *cls. */
static enum MHD_Result count_length_header(void *cls, enum MHD_ValueKind kind, const char *key,
                                           const char *value)
{
    (void)kind;
    (void)value;
    if (strcasecmp(key, MHD_HTTP_HEADER_CONTENT_LENGTH) == 0) ++*(int *)cls;
    return MHD_YES;
}

static enum MHD_Result access_handler(void *cls, struct MHD_Connection *conn, const char *url,
                                      const char *method, const char *version,
                                      const char *upload_data, size_t *upload_data_size,
                                      void **con_cls)
{
    (void)version;
    tsd_server *s = cls;
    tsd_request *r = *con_cls;
    if (!r) return MHD_NO; /* uri_seen ran out of memory: its path went unchecked */
    if (!r->srv) {         /* first call: headers only */
        r->srv = s;
        r->conn = conn;
        r->method = method;
        r->url = url;
        r->t_start = tsd_now();
        *con_cls = r;
        atomic_fetch_add(&s->inflight, 1);
        /* what the headers and path alone refuse is refused now, before any
         * of the body is read */
        if (cross_site(r))
            return tsd_reply_problem(r, MHD_HTTP_FORBIDDEN, "/problems/cross-origin",
                                     "Cross-origin request refused",
                                     "a page of another origin may not change this daemon's "
                                     "state (its Origin header names another host); the "
                                     "dashboard is served by the daemon itself",
                                     NULL);
        if (target_too_long(r)) return reply_target_too_long(r);
        if (r->bad_path)
            return tsd_reply_problem(r, MHD_HTTP_BAD_REQUEST, "/problems/bad-path",
                                     "Bad request path",
                                     "the path holds an encoded NUL (%00) or slash (%2F); "
                                     "neither is part of any route",
                                     NULL);
        /* two Content-Length headers: libmicrohttpd 0.9.75 frames the body by
         * one of them; a proxy in front may have taken the other, and the
         * rest of the body would be read as the next request (RFC 9112 6.3:
         * an invalid message, 400, and the connection closed) */
        int lengths = 0;
        MHD_get_connection_values(conn, MHD_HEADER_KIND, count_length_header, &lengths);
        if (lengths > 1)
            return tsd_reply_problem(r, MHD_HTTP_BAD_REQUEST, "/problems/bad-framing",
                                     "Bad message framing",
                                     "more than one Content-Length header: the body's length "
                                     "is ambiguous",
                                     NULL);
        /* a declared length past the limit too (a chunked body is counted as
         * it arrives, below) */
        const char *cl =
            MHD_lookup_connection_value(conn, MHD_HEADER_KIND, MHD_HTTP_HEADER_CONTENT_LENGTH);
        if (cl && *cl) {
            char *end;
            unsigned long long n = strtoull(cl, &end, 10);
            if (*end == '\0' && n > s->opt.max_body) return reply_too_large(r);
        }
        return MHD_YES;
    }
    if (*upload_data_size > 0) { /* body chunk (none kept once answered) */
        if (!r->body_too_large && !r->status) {
            if (r->body_len + *upload_data_size > s->opt.max_body) {
                r->body_too_large = 1;
            } else {
                char *nb = realloc(r->body, r->body_len + *upload_data_size + 1);
                if (!nb) return MHD_NO;
                memcpy(nb + r->body_len, upload_data, *upload_data_size);
                r->body = nb;
                r->body_len += *upload_data_size;
                r->body[r->body_len] = '\0';
            }
        }
        *upload_data_size = 0;
        return MHD_YES;
    }
    if (r->on_resume) { /* a worker finished what this request waited for */
        enum MHD_Result (*fn)(tsd_request *) = r->on_resume;
        r->on_resume = NULL;
        return fn(r);
    }
    if (r->status) return MHD_YES; /* already answered */
    if (r->body_too_large) return reply_too_large(r);
    return tsd_route(r);
}

/* Bytes of a decoded path that the log writes percent-encoded again:
 * libmicrohttpd hands the path decoded, so a %0A in it would start a line of
 * the client's choosing; blanks would split the line's fields. */
static int log_escaped(unsigned char c)
{
    return c <= 0x20 || c == 0x7f || c == '%';
}

/* The path as one log line's field: url itself when it holds no byte to
 * escape (every ordinary request), else the escaped copy, also put in *owned
 * for the caller to free; "?" when that copy cannot be made. */
static const char *log_path(const char *url, char **owned)
{
    size_t n = 0, esc = 0;
    for (; url[n]; n++)
        esc += log_escaped((unsigned char)url[n]);
    *owned = NULL;
    if (!esc) return url;
    char *out = malloc(n + 2 * esc + 1);
    if (!out) return "?";
    static const char hex[] = "0123456789ABCDEF";
    char *o = out;
    for (const unsigned char *c = (const unsigned char *)url; *c; c++)
        if (log_escaped(*c)) {
            *o++ = '%';
            *o++ = hex[*c >> 4];
            *o++ = hex[*c & 15];
        } else
            *o++ = (char)*c;
    *o = 0;
    return *owned = out;
}

static void completed(void *cls, struct MHD_Connection *conn, void **con_cls,
                      enum MHD_RequestTerminationCode toe)
{
    (void)conn;
    tsd_server *s = cls;
    tsd_request *r = *con_cls;
    if (!r) return;
    if (!r->srv) { /* made by uri_seen, never reached the access handler */
        free(r);
        *con_cls = NULL;
        return;
    }
    tsd_metrics_request(&s->metrics, r->status);
    char when[32];
    time_t now = time(NULL);
    struct tm tm;
    gmtime_r(&now, &tm);
    strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%SZ", &tm);
    char *owned;
    const char *path = log_path(r->url, &owned);
    fprintf(stderr, "%s %s %s %u %zu %.1fms%s\n", when, r->method, path, r->status, r->bytes,
            1e3 * (tsd_now() - r->t_start),
            toe == MHD_REQUEST_TERMINATED_COMPLETED_OK ? "" : " (aborted)");
    free(owned);
    tsd_session_put(r->session);
    json_decref(r->async_result);
    json_decref(r->async_errors);
    json_decref(r->async_doc);
    if (r->async_free) r->async_free(r->async_ctx);
    free(r->body);
    free(r);
    *con_cls = NULL;
    atomic_fetch_sub(&s->inflight, 1);
}

/* The address of opt.bind and opt.port into *ss: its length, 0 when bind is
 * neither an IPv4 nor an IPv6 address. */
static socklen_t listen_address(const tsd_options *o, struct sockaddr_storage *ss)
{
    memset(ss, 0, sizeof *ss);
    struct sockaddr_in *a4 = (struct sockaddr_in *)ss;
    struct sockaddr_in6 *a6 = (struct sockaddr_in6 *)ss;
    if (inet_pton(AF_INET, o->bind, &a4->sin_addr) == 1) {
        a4->sin_family = AF_INET;
        a4->sin_port = htons((uint16_t)o->port);
        return sizeof *a4;
    }
    if (inet_pton(AF_INET6, o->bind, &a6->sin6_addr) == 1) {
        a6->sin6_family = AF_INET6;
        a6->sin6_port = htons((uint16_t)o->port);
        return sizeof *a6;
    }
    return 0;
}

int tsd_server_bind(tsd_server *s, char *err, size_t errlen)
{
    struct sockaddr_storage ss;
    socklen_t len = listen_address(&s->opt, &ss);
    if (len == 0) {
        snprintf(err, errlen, "--bind: '%s' is not an IPv4 or IPv6 address", s->opt.bind);
        return -1;
    }
    int fd = socket(ss.ss_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        snprintf(err, errlen, "cannot open a socket for %s: %s", s->opt.bind, strerror(errno));
        return -1;
    }
    /* as libmicrohttpd does with a socket of its own: SO_REUSEADDR (a restart
     * binds while the last run's connections linger in TIME_WAIT; a port some
     * socket listens on is still refused), and an IPv6 address is IPv6 only */
    int on = 1;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
    if (ss.ss_family == AF_INET6) setsockopt(fd, IPPROTO_IPV6, IPV6_V6ONLY, &on, sizeof on);
    if (bind(fd, (struct sockaddr *)&ss, len) != 0) {
        int e = errno;
        close(fd);
        snprintf(err, errlen, "cannot listen on %s port %d: %s", s->opt.bind, s->opt.port,
                 strerror(e));
        return -1;
    }
    /* --port 0: the kernel chose one at bind; say which */
    len = sizeof ss;
    if (getsockname(fd, (struct sockaddr *)&ss, &len) == 0)
        s->opt.port = ntohs(ss.ss_family == AF_INET6 ? ((struct sockaddr_in6 *)&ss)->sin6_port
                                                     : ((struct sockaddr_in *)&ss)->sin_port);
    s->listen_fd = fd;
    return 0;
}

void tsd_server_unbind(tsd_server *s)
{
    if (s->listen_fd >= 0) close(s->listen_fd);
    s->listen_fd = -1;
}

/* libmicrohttpd's error log. While the daemon starts, the first message is
 * kept for the daemon's own ("cannot start ...: WHY"), not printed raw before
 * it; once it serves, each goes to stderr as "tanksimd: libmicrohttpd: ...",
 * but for a client's hang-up, which is counted in /metrics. */
static void mhd_log(void *cls, const char *fmt, va_list ap)
{
    tsd_server *s = cls;
    char msg[sizeof s->mhd_start_msg];
    vsnprintf(msg, sizeof msg, fmt, ap);
    msg[strcspn(msg, "\n")] = '\0';
    if (atomic_load(&s->mhd_starting)) {
        if (!s->mhd_start_msg[0]) snprintf(s->mhd_start_msg, sizeof s->mhd_start_msg, "%s", msg);
        return;
    }
    /* A client that closes its connection before the answer is sent (a
     * stream or an animation abandoned part way) is ordinary: counted, not
     * logged (a soak test's log held ~4,000 such lines in 27 minutes). */
    if (strstr(msg, "closed by remote peer") || strstr(msg, "no longer available for sending")) {
        atomic_fetch_add(&s->metrics.answers_cut, 1);
        return;
    }
    fprintf(stderr, "tanksimd: libmicrohttpd: %s\n", msg);
}

int tsd_server_start(tsd_server *s, char *err, size_t errlen)
{
    unsigned flags = MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_EPOLL_LINUX_ONLY |
                     MHD_ALLOW_SUSPEND_RESUME | MHD_USE_ERROR_LOG;
    if (s->listen_fd < 0) {
        snprintf(err, errlen, "internal error: no socket bound (tsd_server_bind)");
        return -1;
    }
    struct sockaddr_storage ss; /* the family of the bound socket */
    socklen_t len = sizeof ss;
    if (getsockname(s->listen_fd, (struct sockaddr *)&ss, &len) == 0 && ss.ss_family == AF_INET6)
        flags |= MHD_USE_IPv6;
    if (listen(s->listen_fd, SOMAXCONN) != 0) {
        snprintf(err, errlen, "cannot listen on %s port %d: %s", s->opt.bind, s->opt.port,
                 strerror(errno));
        return -1;
    }
    s->mhd_start_msg[0] = '\0';
    atomic_store(&s->mhd_starting, 1);
    s->mhd = MHD_start_daemon(
        flags, 0, NULL, NULL, access_handler, s, MHD_OPTION_EXTERNAL_LOGGER, mhd_log, s,
        MHD_OPTION_LISTEN_SOCKET, s->listen_fd, MHD_OPTION_URI_LOG_CALLBACK, uri_seen, s,
        MHD_OPTION_NOTIFY_COMPLETED, completed, s, MHD_OPTION_THREAD_POOL_SIZE,
        (unsigned)s->opt.http_threads, MHD_OPTION_CONNECTION_TIMEOUT, s->opt.conn_timeout,
        MHD_OPTION_CONNECTION_LIMIT, (unsigned)s->opt.max_connections,
        MHD_OPTION_CONNECTION_MEMORY_LIMIT, (size_t)CONN_MEMORY, MHD_OPTION_END);
    atomic_store(&s->mhd_starting, 0);
    /* handed over: MHD_stop_daemon closes it; after a failed start whether
     * libmicrohttpd closed it is its business (the daemon exits), so it is
     * never closed twice here */
    s->listen_fd = -1;
    if (!s->mhd) {
        snprintf(err, errlen, "cannot start the HTTP server on %s port %d%s%s", s->opt.bind,
                 s->opt.port, s->mhd_start_msg[0] ? ": " : "", s->mhd_start_msg);
        return -1;
    }
    return 0;
}

void tsd_server_settle(tsd_server *s, double timeout, const sigset_t *stop)
{
    double until = tsd_now() + timeout;
    while (atomic_load(&s->inflight) > 0 && tsd_now() < until) {
        struct timespec ts = {0, 10 * 1000 * 1000};
        if (!stop)
            nanosleep(&ts, NULL);
        else if (sigtimedwait(stop, NULL, &ts) > 0)
            return; /* another stop signal: close now */
    }
}

void tsd_server_stop(tsd_server *s)
{
    if (s->mhd) MHD_stop_daemon(s->mhd);
    s->mhd = NULL;
}
