/*
 * problem.c — ts_rc -> HTTP status and RFC 9457 problem documents (problem.h).
 *
 * Problem texts often quote what the client sent (a query value, a path
 * segment, a preset name). Those bytes need not be UTF-8, and jansson refuses
 * to build a string that is not: the problem would then be NULL and the
 * client got a 500 "could not build the response" for its own mistake (found
 * by tests/fuzz/http_fuzz.py). So every text goes in through utf8_string,
 * which replaces each byte of an invalid sequence with U+FFFD.
 */
#include "problem.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const struct {
    int status;
    const char *type;
    const char *title;
} map[TS_NRC] = {
    [TS_OK] = {200, "about:blank", "OK"},
    [TS_ERR_PARAM] = {400, "/problems/invalid-config", "Invalid request"},
    [TS_ERR_RANGE] = {400, "/problems/invalid-config", "Value out of range"},
    [TS_ERR_NOMEM] = {503, "/problems/out-of-memory", "Out of memory"},
    /* the model could not be solved with the config sent: the request's
     * content, not a fault of the server (RFC 9110 15.5.21) */
    [TS_ERR_SOLVER] = {422, "/problems/solver-failed", "Solver failed"},
    [TS_ERR_DIVERGED] = {422, "/problems/diverged", "Simulation diverged"},
    [TS_ERR_IO] = {500, "/problems/io", "I/O error"},
    [TS_ERR_STATE] = {409, "/problems/conflict", "Not allowed in the current state"},
    [TS_ERR_NOTFOUND] = {404, "/problems/not-found", "Not found"},
    [TS_ERR_UNSUPPORTED] = {422, "/problems/unsupported", "Not supported"},
    [TS_ERR_CANCELLED] = {409, "/problems/cancelled", "Cancelled"},
    [TS_ERR_LIMIT] = {429, "/problems/limit", "Limit exceeded"},
    [TS_ERR_INTERNAL] = {500, "/problems/internal", "Internal error"},
};

/* Length of the valid UTF-8 sequence at s (RFC 3629: no overlong forms, no
 * surrogates, at most U+10FFFF), 0 when the bytes there are not one. */
static size_t utf8_seq(const unsigned char *s)
{
    unsigned c = s[0];
    if (c < 0x80) return 1;
    size_t n = c >= 0xC2 && c <= 0xDF   ? 2
               : c >= 0xE0 && c <= 0xEF ? 3
               : c >= 0xF0 && c <= 0xF4 ? 4
                                        : 0; /* 0x80-0xC1: continuation or overlong lead */
    if (n == 0) return 0;
    for (size_t i = 1; i < n; i++)
        if ((s[i] & 0xC0) != 0x80) return 0;
    if (c == 0xE0 && s[1] < 0xA0) return 0; /* overlong */
    if (c == 0xED && s[1] > 0x9F) return 0; /* surrogate */
    if (c == 0xF0 && s[1] < 0x90) return 0; /* overlong */
    if (c == 0xF4 && s[1] > 0x8F) return 0; /* above U+10FFFF */
    return n;
}

/* json_string of s with every byte of an invalid sequence replaced by U+FFFD. */
static json_t *utf8_string(const char *s)
{
    json_t *j = json_string(s);
    if (j) return j;
    size_t len = strlen(s);
    char *out = malloc(3 * len + 1);
    if (!out) return NULL;
    size_t o = 0;
    for (const unsigned char *p = (const unsigned char *)s; *p;) {
        size_t n = utf8_seq(p);
        if (n) {
            memcpy(out + o, p, n);
            o += n;
            p += n;
        } else {
            memcpy(out + o, "\xEF\xBF\xBD", 3);
            o += 3;
            p++;
        }
    }
    out[o] = '\0';
    j = json_string(out);
    free(out);
    return j;
}

int tsa_http_status(ts_rc rc)
{
    if ((int)rc < 0 || rc >= TS_NRC) return 500;
    return map[rc].status;
}

const char *tsa_problem_type(ts_rc rc)
{
    if ((int)rc < 0 || rc >= TS_NRC) return "/problems/internal";
    return map[rc].type;
}

json_t *tsa_problem(int status, const char *type, const char *title, const char *detail,
                    json_t *errors)
{
    json_t *p = json_pack("{s:s,s:s,s:i,s:o}", "type", type ? type : "about:blank", "title",
                          title ? title : "", "status", status, "detail",
                          utf8_string(detail ? detail : ""));
    if (p && errors) json_object_set(p, "errors", errors);
    return p;
}

json_t *tsa_problem_from_err(const ts_err *err, json_t *errors)
{
    ts_rc rc = err->code;
    if ((int)rc < 0 || rc >= TS_NRC) rc = TS_ERR_INTERNAL;
    json_t *own = NULL;
    if (!errors && (err->pointer[0] || err->at_root)) {
        own = json_pack("[{s:o,s:o}]", "pointer", utf8_string(err->pointer), "message",
                        utf8_string(err->msg));
        errors = own;
    }
    json_t *p = tsa_problem(map[rc].status, map[rc].type, map[rc].title, err->msg, errors);
    json_decref(own);
    return p;
}

ts_rc tsa_root_err(ts_err *err, ts_rc code, const char *fmt, ...)
{
    if (!err) return code;
    char msg[TS_ERR_MSG_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    ts_err_set(err, code, "", "%s", msg);
    err->at_root = 1;
    return code;
}

char *tsa_pointer_join(char *out, size_t n, const char *parent, const char *key)
{
    if (n == 0) return out;
    size_t k = (size_t)snprintf(out, n, "%s/", parent);
    for (const char *c = key; *c && k + 1 < n; c++) {
        if (*c == '~' || *c == '/') {
            if (k + 2 >= n) break; /* no half escape */
            out[k++] = '~';
            out[k++] = *c == '~' ? '0' : '1';
        } else {
            out[k++] = *c;
        }
    }
    if (k >= n) k = n - 1;
    out[k] = '\0';
    return out;
}

void tsa_errors_add(json_t *errors, int count, const char *pointer, const char *message)
{
    if (!errors || count > TSA_ERRORS_MAX) return;
    if (count == TSA_ERRORS_MAX) {
        char note[80];
        snprintf(note, sizeof note, "more errors were found; the first %d are listed",
                 TSA_ERRORS_MAX);
        json_array_append_new(errors, json_pack("{s:s,s:s}", "pointer", "", "message", note));
    } else
        json_array_append_new(errors,
                              json_pack("{s:s,s:s}", "pointer", pointer, "message", message));
}
