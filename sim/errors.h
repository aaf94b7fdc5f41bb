/*
 * errors.h — result codes and the error record every fallible tanksim call fills.
 *
 * Pattern (SQLite result codes + anet's message buffer + MuJoCo's loader error):
 * a call that can fail returns ts_rc (constructors return NULL) and, when the
 * caller passes a non-NULL ts_err, writes the code, the JSON Pointer of the
 * offending configuration field (empty when no field is to blame) and a
 * human-readable message. sim/ and render/ never print, exit or abort.
 */
#ifndef TS_ERRORS_H
#define TS_ERRORS_H

#include <stddef.h>

/* A result code the caller must look at (-Werror makes an unchecked call a build error). */
#define TS_MUST_CHECK __attribute__((warn_unused_result))

typedef enum ts_rc {
    TS_OK = 0,          /* success */
    TS_ERR_PARAM,       /* a parameter has the wrong type, is unknown or missing */
    TS_ERR_RANGE,       /* a parameter is outside its documented range */
    TS_ERR_NOMEM,       /* an allocation failed */
    TS_ERR_SOLVER,      /* the integrator or a linear/nonlinear solver failed */
    TS_ERR_DIVERGED,    /* the state became NaN/Inf or left physical bounds */
    TS_ERR_IO,          /* a file could not be read or written */
    TS_ERR_STATE,       /* the call is not valid in the object's current state */
    TS_ERR_NOTFOUND,    /* a named thing (preset, channel, data file) does not exist */
    TS_ERR_UNSUPPORTED, /* the requested feature is not available in this build */
    TS_ERR_CANCELLED,   /* the caller asked to stop (sample callback returned non-zero) */
    TS_ERR_LIMIT,       /* a configured limit was exceeded */
    TS_ERR_INTERNAL,    /* a bug: an invariant did not hold */
    TS_NRC              /* number of result codes */
} ts_rc;

#define TS_ERR_POINTER_LEN 128
#define TS_ERR_MSG_LEN 384

typedef struct ts_err {
    ts_rc code;                        /* TS_OK when nothing went wrong */
    char pointer[TS_ERR_POINTER_LEN];  /* JSON Pointer of the field at fault ("" if none) */
    int at_root;                       /* 1: the pointer "" names the whole document (RFC 6901's
                                        * root: JSON that does not parse, a body that is not an
                                        * object), not "no field"; ts_err_set clears it */
    char msg[TS_ERR_MSG_LEN];          /* what went wrong, in words */
} ts_err;

/* Static name of a result code ("TS_ERR_RANGE"); never NULL. */
const char *ts_rc_name(ts_rc rc);

/* Clear an error record (code TS_OK, empty strings). NULL is a no-op. */
void ts_err_clear(ts_err *err);

/* Fill err (if non-NULL) with code, pointer (may be NULL) and a printf-style
 * message; returns code so callers can write `return ts_err_set(...)`. */
ts_rc ts_err_set(ts_err *err, ts_rc code, const char *pointer, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

#endif
