/*
 * errors.c — result-code names and the error-record helpers declared in errors.h.
 */
#include "errors.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

static const char *const rc_names[TS_NRC] = {
    "TS_OK",           "TS_ERR_PARAM",     "TS_ERR_RANGE",       "TS_ERR_NOMEM",
    "TS_ERR_SOLVER",   "TS_ERR_DIVERGED",  "TS_ERR_IO",          "TS_ERR_STATE",
    "TS_ERR_NOTFOUND", "TS_ERR_UNSUPPORTED", "TS_ERR_CANCELLED", "TS_ERR_LIMIT",
    "TS_ERR_INTERNAL",
};

const char *ts_rc_name(ts_rc rc)
{
    if ((int)rc < 0 || rc >= TS_NRC) return "TS_ERR_UNKNOWN";
    return rc_names[rc];
}

void ts_err_clear(ts_err *err)
{
    if (!err) return;
    err->code = TS_OK;
    err->pointer[0] = '\0';
    err->at_root = 0;
    err->msg[0] = '\0';
}

ts_rc ts_err_set(ts_err *err, ts_rc code, const char *pointer, const char *fmt, ...)
{
    if (!err) return code;
    err->code = code;
    snprintf(err->pointer, sizeof err->pointer, "%s", pointer ? pointer : "");
    err->at_root = 0;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->msg, sizeof err->msg, fmt, ap);
    va_end(ap);
    return code;
}
