/*
 * routes.c — the routing table of tanksimd and its handlers.
 *
 * Columns: method, path pattern ("{name}" matches one path segment, captured
 * into r->params in order), handler. Rows are tried in order; a path that
 * matches no row gets 404, a path that matches with another method 405. Every
 * error body is application/problem+json (RFC 9457).
 */
#include <stdio.h>
#include <string.h>

#include "../sim/version.h"
#include "server.h"
#include "static_files.h"

typedef enum MHD_Result (*tsd_handler)(tsd_request *r);

typedef struct tsd_route_row {
    const char *method;
    const char *pattern;
    tsd_handler handler;
} tsd_route_row;

static enum MHD_Result get_health(tsd_request *r)
{
    return tsd_reply_json(r, MHD_HTTP_OK,
                          json_pack("{s:s,s:s}", "status", "ok", "version", TS_VERSION));
}

static const tsd_route_row routes[] = {
    {"GET", "/v1/health", get_health},
    {"GET", "/", tsd_static_index},
    {"GET", "/static/{file}", tsd_static_file},
};
#define NROUTES (sizeof routes / sizeof routes[0])

/* Match url against pattern, capturing {..} segments. 1 on match. */
static int match(const char *pattern, const char *url, tsd_request *r)
{
    int n = 0;
    const char *p = pattern, *u = url;
    while (*p && *u) {
        if (*p == '{') {
            const char *pe = strchr(p, '}');
            const char *ue = strchr(u, '/');
            size_t len = ue ? (size_t)(ue - u) : strlen(u);
            if (!pe || len == 0 || len >= sizeof r->params[0] || n >= TSD_MAX_PATH_PARAMS)
                return 0;
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

enum MHD_Result tsd_route(tsd_request *r)
{
    int path_matched = 0;
    for (size_t i = 0; i < NROUTES; i++) {
        if (!match(routes[i].pattern, r->url, r)) continue;
        path_matched = 1;
        if (strcmp(routes[i].method, r->method) == 0) return routes[i].handler(r);
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
