/*
 * problem.c — ts_rc -> HTTP status and RFC 9457 problem documents (problem.h).
 */
#include "problem.h"

static const struct {
    int status;
    const char *type;
    const char *title;
} map[TS_NRC] = {
    [TS_OK] = {200, "about:blank", "OK"},
    [TS_ERR_PARAM] = {400, "/problems/invalid-config", "Invalid request"},
    [TS_ERR_RANGE] = {400, "/problems/invalid-config", "Value out of range"},
    [TS_ERR_NOMEM] = {503, "/problems/out-of-memory", "Out of memory"},
    [TS_ERR_SOLVER] = {500, "/problems/solver-failed", "Solver failed"},
    [TS_ERR_DIVERGED] = {500, "/problems/diverged", "Simulation diverged"},
    [TS_ERR_IO] = {500, "/problems/io", "I/O error"},
    [TS_ERR_STATE] = {409, "/problems/conflict", "Not allowed in the current state"},
    [TS_ERR_NOTFOUND] = {404, "/problems/not-found", "Not found"},
    [TS_ERR_UNSUPPORTED] = {422, "/problems/unsupported", "Not supported"},
    [TS_ERR_CANCELLED] = {409, "/problems/cancelled", "Cancelled"},
    [TS_ERR_LIMIT] = {429, "/problems/limit", "Limit exceeded"},
    [TS_ERR_INTERNAL] = {500, "/problems/internal", "Internal error"},
};

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
    json_t *p = json_pack("{s:s,s:s,s:i,s:s}", "type", type ? type : "about:blank", "title",
                          title ? title : "", "status", status, "detail", detail ? detail : "");
    if (p && errors) json_object_set(p, "errors", errors);
    return p;
}

json_t *tsa_problem_from_err(const ts_err *err, json_t *errors)
{
    ts_rc rc = err->code;
    if ((int)rc < 0 || rc >= TS_NRC) rc = TS_ERR_INTERNAL;
    json_t *own = NULL;
    if (!errors && err->pointer[0]) {
        own = json_pack("[{s:s,s:s}]", "pointer", err->pointer, "message", err->msg);
        errors = own;
    }
    json_t *p = tsa_problem(map[rc].status, map[rc].type, map[rc].title, err->msg, errors);
    json_decref(own);
    return p;
}
