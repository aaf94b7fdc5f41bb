/*
 * server.h — tanksimd's one state object and the request record handlers see.
 *
 * All daemon state lives in tsd_server, passed to libmicrohttpd as its closure
 * (no file-scope mutable state except the signal mask set up in main.c).
 * A tsd_request is made on libmicrohttpd's first call for a request, collects
 * the body, is dispatched through the routing table (routes.c) once the body
 * is complete, and is freed — after its log line — in the completion callback.
 */
#ifndef TSD_SERVER_H
#define TSD_SERVER_H

#include <jansson.h>
#include <microhttpd.h>
#include <stddef.h>

#define TSD_MAX_PATH_PARAMS 4

typedef struct tsd_options {
    char bind[64];          /* listen address (IPv4 or IPv6 literal) */
    int port;               /* TCP port */
    char data_dir[512];     /* where sessions and results persist */
    int threads;            /* simulation worker threads */
    int http_threads;       /* libmicrohttpd thread-pool size */
    size_t max_body;        /* largest request body accepted [bytes] */
    unsigned conn_timeout;  /* idle connection timeout [s] */
    char token[128];        /* bearer token; empty = no authentication */
    char web_root[512];     /* dashboard files served at / (static_files.c) */
} tsd_options;

typedef struct tsd_server {
    tsd_options opt;
    struct MHD_Daemon *mhd;
} tsd_server;

typedef struct tsd_request {
    tsd_server *srv;
    struct MHD_Connection *conn;
    const char *method;       /* "GET", ... (owned by libmicrohttpd) */
    const char *url;          /* path without query (owned by libmicrohttpd) */
    char *body;               /* request body, NUL-terminated (owned) */
    size_t body_len;
    int body_too_large;       /* set when the body passed opt.max_body */
    char params[TSD_MAX_PATH_PARAMS][128]; /* {id}-style path segments matched */
    int nparams;
    unsigned status;          /* status sent (for the log) */
    size_t bytes;             /* response body bytes (for the log) */
    double t_start;           /* monotonic seconds at arrival */
} tsd_request;

/* Start listening as configured; 0 on success, -1 with a message in err. */
int tsd_server_start(tsd_server *s, char *err, size_t errlen);
void tsd_server_stop(tsd_server *s);

/* Responses: each queues exactly one response and returns MHD's result. */
enum MHD_Result tsd_reply_json(tsd_request *r, unsigned status, json_t *body); /* steals body */
enum MHD_Result tsd_reply_text(tsd_request *r, unsigned status, const char *content_type,
                               const char *text, size_t len);
enum MHD_Result tsd_reply_problem(tsd_request *r, unsigned status, const char *type,
                                  const char *title, const char *detail, json_t *errors);

/* Route the request (routes.c). */
enum MHD_Result tsd_route(tsd_request *r);

#endif
