/*
 * problem.h — HTTP problem details (RFC 9457) from tanksim errors.
 *
 * One table maps each ts_rc to an HTTP status and a problem "type" URI under
 * /problems/ (documented in api/openapi.yaml); config errors carry an "errors"
 * array of {pointer, message}.
 */
#ifndef TSA_PROBLEM_H
#define TSA_PROBLEM_H

#include <jansson.h>

#include "../sim/errors.h"

/* HTTP status for a result code (TS_ERR_PARAM -> 400, TS_ERR_NOTFOUND -> 404, ...). */
int tsa_http_status(ts_rc rc);

/* Problem "type" URI for a result code ("/problems/invalid-config", ...). */
const char *tsa_problem_type(ts_rc rc);

/* {"type","title","status","detail"[,"errors"]} — new reference. errors may be
 * NULL or an array (a reference is taken). detail (and, below, err's pointer
 * and message) may quote request bytes that are not UTF-8: each byte of an
 * invalid sequence becomes U+FFFD, so the document is always built. */
json_t *tsa_problem(int status, const char *type, const char *title, const char *detail,
                    json_t *errors);

/* Problem from a ts_err: status and type from its code, detail from its
 * message, and errors (if NULL, one built from err's pointer when non-empty
 * or when it names the whole document, at_root). */
json_t *tsa_problem_from_err(const ts_err *err, json_t *errors);

/* ts_err_set with the pointer "" naming the whole document (at_root set):
 * the problem then lists {"pointer": "", ...}. Returns code. */
ts_rc tsa_root_err(ts_err *err, ts_rc code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Errors listed in one problem at most: a body with 90,000 unknown fields
 * made a 6.5 MB answer and ~1 s of work. */
#define TSA_ERRORS_MAX 100

/* Append {pointer, message} to errors (may be NULL) as the count-th error of a
 * document (count from 0): the first TSA_ERRORS_MAX are listed, the next one
 * becomes a note that more were found and not listed, the rest are dropped. */
void tsa_errors_add(json_t *errors, int count, const char *pointer, const char *message);

/* JSON Pointer (RFC 6901) of a member: parent (a pointer, "" for the root)
 * then "/" and key with '~' written "~0" and '/' "~1", so a key "a/b" is not
 * read as two levels. Into out (n bytes), cut to fit; returns out. */
char *tsa_pointer_join(char *out, size_t n, const char *parent, const char *key);

#endif
