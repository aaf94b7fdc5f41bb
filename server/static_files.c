/*
 * static_files.c — the dashboard's files over HTTP (see static_files.h).
 *
 * Why in the daemon: `make run` must serve a working dashboard with nothing
 * else installed. The files are small and few (index.html, app.js, app.css and
 * their source maps), so each request opens the file and hands the descriptor
 * to libmicrohttpd (MHD_create_response_from_fd), which sends it and closes it.
 * Leaves out: ranges, ETags/conditional requests, compression, HEAD.
 */
#define _GNU_SOURCE
#include "static_files.h"

#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Content type by file-name extension; anything else is not served. */
static const struct {
    const char *ext;
    const char *type;
} types[] = {
    {".html", "text/html; charset=utf-8"},
    {".js", "text/javascript; charset=utf-8"},
    {".mjs", "text/javascript; charset=utf-8"},
    {".css", "text/css; charset=utf-8"},
    {".map", "application/json"},
    {".json", "application/json"},
    {".svg", "image/svg+xml"},
    {".png", "image/png"},
    {".ico", "image/x-icon"},
    {".txt", "text/plain; charset=utf-8"},
};

static const char *content_type(const char *name)
{
    const char *dot = strrchr(name, '.');
    if (!dot) return NULL;
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (strcmp(dot, types[i].ext) == 0) return types[i].type;
    return NULL;
}

/* A flat, safe file name: [A-Za-z0-9._-]+, not starting with '.'. */
static int safe_name(const char *name)
{
    size_t n = strlen(name);
    if (n == 0 || n > 100 || name[0] == '.') return 0;
    for (size_t i = 0; i < n; i++) {
        char c = name[i];
        int ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                 c == '.' || c == '_' || c == '-';
        if (!ok) return 0;
    }
    return 1;
}

static int has_index(const char *dir)
{
    char p[PATH_MAX];
    if (snprintf(p, sizeof p, "%s/index.html", dir) >= (int)sizeof p) return 0;
    return access(p, R_OK) == 0;
}

void tsd_static_default_root(char *out, size_t n)
{
    char exe[PATH_MAX];
    ssize_t len = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (len > 0) {
        exe[len] = '\0';
        char *slash = strrchr(exe, '/');
        if (slash) {
            *slash = '\0';
            /* the build tree (build/../web_static), then `make install`'s
             * PREFIX/bin/../share/tanksim/web_static */
            static const char *const rel[] = {"../web_static", "../share/tanksim/web_static"};
            for (size_t i = 0; i < sizeof rel / sizeof rel[0]; i++) {
                char cand[PATH_MAX];
                if (snprintf(cand, sizeof cand, "%s/%s", exe, rel[i]) < (int)sizeof cand &&
                    has_index(cand)) {
                    char real[PATH_MAX];
                    snprintf(out, n, "%s", realpath(cand, real) ? real : cand);
                    return;
                }
            }
        }
    }
    snprintf(out, n, "./web_static");
}

static enum MHD_Result not_found(tsd_request *r, const char *detail)
{
    return tsd_reply_problem(r, MHD_HTTP_NOT_FOUND, "/problems/not-found", "Not found", detail,
                             NULL);
}

static enum MHD_Result serve(tsd_request *r, const char *name)
{
    const char *type = content_type(name);
    if (!safe_name(name) || !type) {
        char detail[200];
        snprintf(detail, sizeof detail, "no static file named %.100s", name);
        return not_found(r, detail);
    }
    char path[PATH_MAX];
    if (snprintf(path, sizeof path, "%s/%s", r->srv->opt.web_root, name) >= (int)sizeof path)
        return not_found(r, "static path too long");
    int fd = open(path, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    struct stat st;
    if (fd < 0 || fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        if (fd >= 0) close(fd);
        char detail[700];
        if (strcmp(name, "index.html") == 0)
            snprintf(detail, sizeof detail,
                     "the dashboard is not built in %.500s: run `make web` (or start tanksimd "
                     "with --web-root DIR)",
                     r->srv->opt.web_root);
        else
            snprintf(detail, sizeof detail, "no static file named %.100s", name);
        return not_found(r, detail);
    }
    struct MHD_Response *resp = MHD_create_response_from_fd((uint64_t)st.st_size, fd);
    if (!resp) {
        close(fd);
        return MHD_NO;
    }
    MHD_add_response_header(resp, MHD_HTTP_HEADER_CONTENT_TYPE, type);
    MHD_add_response_header(resp, "Cache-Control", "no-cache");
    MHD_add_response_header(resp, "X-Content-Type-Options", "nosniff");
    r->status = MHD_HTTP_OK;
    r->bytes = (size_t)st.st_size;
    enum MHD_Result ret = MHD_queue_response(r->conn, MHD_HTTP_OK, resp);
    MHD_destroy_response(resp);
    return ret;
}

enum MHD_Result tsd_static_index(tsd_request *r)
{
    return serve(r, "index.html");
}

enum MHD_Result tsd_static_file(tsd_request *r)
{
    return serve(r, r->nparams > 0 ? r->params[0] : "");
}
