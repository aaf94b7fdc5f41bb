/*
 * json_error.h — the JSON Pointer of a document jansson refused to parse.
 *
 * jansson says where it stopped (json_error_t.position, a byte offset, with
 * line and column) but not in which member. Semantic errors name their field
 * by JSON Pointer (RFC 6901); a duplicate key, a number out of range of a
 * double or an int64, or a syntax error should too. tsa_json_pointer_at
 * re-reads the text up to the stop with a small tokenizer that keeps the stack
 * of open objects (the current key of each) and arrays (the current index).
 *
 * What is named, by the kind of error (jansson 2.14's json_error_code):
 *   duplicate key                       the member: {"a":1,"a":2} -> /a
 *   number overflow (real or integer)   the value: {"r":{"d":1e400}} -> /r/d
 *   \u0000 in a string value            the value
 *   depth limit                         the value that went too deep
 *   syntax (a token out of place)       where it stands: a missing or bad value
 *                                       names that value ({"a": } -> /a, [1,]
 *                                       -> /1), a bad token after a key names
 *                                       the member ({"a" 1} -> /a), a bad key or
 *                                       a bad token between members names the
 *                                       enclosing container ({"a":1 x} -> "")
 *   bad string (escape, control char,   the value it is, or, for a key (which
 *   lone surrogate), \u0000 in a key    names no member a pointer can reach),
 *                                       the enclosing object
 *   premature end, byte not UTF-8       as syntax, for what stands at the stop;
 *                                       inside a string: that string
 *   text after the root value           the root ""
 */
#ifndef TSA_JSON_ERROR_H
#define TSA_JSON_ERROR_H

#include <jansson.h>
#include <stddef.h>

#include "../sim/errors.h"

/* What the parser was reading when it stopped at byte pos. */
typedef enum tsa_stop {
    TSA_STOP_ON_TOKEN, /* the token that ends at pos (or that pos cuts: an unfinished string) */
    TSA_STOP_AT_POS,   /* what begins at pos (the end of the input, a byte that is not
                        * UTF-8), unless pos cuts a string: then that string */
} tsa_stop;

/* The JSON Pointer of the innermost value or member the parser was reading
 * when it stopped at byte pos of text (see the table above): into out (n
 * bytes); when it does not fit, the pointer of the nearest enclosing
 * container that does (never a cut segment). 0, or -1 when out of memory
 * (out is then "", the root). */
int tsa_json_pointer_at(const char *text, size_t pos, tsa_stop stop, char *out, size_t n);

/* Fill err for text (len bytes) that json_loadb refused with je:
 * TS_ERR_PARAM with the pointer of tsa_json_pointer_at (at_root set when it
 * is ""), message "POINTER: LEAD: JANSSON TEXT" (no "POINTER: " at the root);
 * TS_ERR_NOMEM when jansson ran out of memory. text may be the first
 * je->position bytes only (a file read again). Returns the code. */
ts_rc tsa_json_parse_err(const char *text, size_t len, const json_error_t *je, const char *lead,
                         ts_err *err);

#endif
