/*
 * test_json_error.c — the JSON Pointer of a parse error (api/json_error.h):
 * the scanner alone on chosen stops (RFC 6901 escaping, nested arrays,
 * strings holding braces, quotes and escapes, a pointer too long for its
 * buffer), then jansson's own stops for each kind of error, through
 * tsa_parse_object and the problem document a client gets.
 */
#include "test_util.h"

#include <string.h>

#include "api/json_error.h"
#include "api/problem.h"
#include "api/session_json.h"

/* The pointer the scanner names for text stopped at the end of the first
 * `cut` bytes (all of them when cut < 0). */
static const char *at(const char *text, int cut, tsa_stop stop)
{
    static char out[TS_ERR_POINTER_LEN];
    size_t pos = cut < 0 ? strlen(text) : (size_t)cut;
    assert_int_equal(tsa_json_pointer_at(text, pos, stop, out, sizeof out), 0);
    return out;
}

static void scanner_escapes_keys(void **state)
{
    (void)state;
    /* ~ and / escaped as ~0 and ~1, in that order of reading ("~1" stays two bytes) */
    assert_string_equal(at("{\"a/b\":{\"c~d\":{\"~1\":1", -1, TSA_STOP_ON_TOKEN), "/a~1b/c~0d/~01");
    /* JSON escapes decoded first: \/ is a slash, \u007e a tilde, \u00e9 UTF-8 */
    assert_string_equal(at("{\"x\\/y\":{\"\\u007e\\u00e9\":2", -1, TSA_STOP_ON_TOKEN),
                        "/x~1y/~0\xc3\xa9");
    /* a surrogate pair is one character (U+1F600, 4 bytes of UTF-8) */
    assert_string_equal(at("{\"\\ud83d\\ude00\":1", -1, TSA_STOP_ON_TOKEN), "/\xf0\x9f\x98\x80");
    /* the empty key is a member too */
    assert_string_equal(at("{\"\":{\"\":1", -1, TSA_STOP_ON_TOKEN), "//");
}

static void scanner_nested_arrays(void **state)
{
    (void)state;
    const char *t = "{\"a\":[[1,2],[3,[4,5,6]]],\"b\":[{\"c\":[7,8]}]}";
    /* stop on 6: the third element of /a/1/1 */
    assert_string_equal(at(t, (int)(strchr(t, '6') - t) + 1, TSA_STOP_ON_TOKEN), "/a/1/1/2");
    /* stop on 8 */
    assert_string_equal(at(t, (int)(strchr(t, '8') - t) + 1, TSA_STOP_ON_TOKEN), "/b/0/c/1");
    /* closed arrays are left: stop on the key "b" names /b */
    assert_string_equal(at(t, (int)(strstr(t, "\"b\"") - t) + 3, TSA_STOP_ON_TOKEN), "/b");
    /* at a position: after "[3," the next element (1) of /a/1 is awaited */
    assert_string_equal(at("{\"a\":[[1,2],[3,", -1, TSA_STOP_AT_POS), "/a/1/1");
    /* between elements: the array itself */
    assert_string_equal(at("{\"a\":[[1,2],[3", -1, TSA_STOP_AT_POS), "/a/1");
    /* an empty array closed, then the next member's value */
    assert_string_equal(at("[[],[],{\"k\":", -1, TSA_STOP_AT_POS), "/2/k");
}

static void scanner_strings_hold_anything(void **state)
{
    (void)state;
    /* braces, brackets, colons, commas and escaped quotes inside strings are text */
    const char *t = "{\"k\\\"}{[\":{\"v\":\"]},:\\\"{\",\"w\":[\"[\",\"\\\\\",9";
    assert_string_equal(at(t, -1, TSA_STOP_ON_TOKEN), "/k\"}{[/w/2");
    /* a backslash before the closing quote: the string is still open */
    assert_string_equal(at("{\"a\":{\"b\":\"x\\\\\\\"", -1, TSA_STOP_AT_POS), "/a/b");
    /* a key cut by the stop is not known yet: its object is named */
    assert_string_equal(at("{\"a\":{\"bc", -1, TSA_STOP_AT_POS), "/a");
    /* a string value cut by the stop is that value */
    assert_string_equal(at("{\"a\":{\"b\":\"c}", -1, TSA_STOP_AT_POS), "/a/b");
}

static void scanner_syntax_names_the_place(void **state)
{
    (void)state;
    assert_string_equal(at("{\"a\": }", -1, TSA_STOP_ON_TOKEN), "/a");   /* missing value */
    assert_string_equal(at("{\"a\" 1", -1, TSA_STOP_ON_TOKEN), "/a");    /* missing colon */
    assert_string_equal(at("{\"a\":1 x", -1, TSA_STOP_ON_TOKEN), "");    /* between members */
    assert_string_equal(at("{\"a\":[1 x", -1, TSA_STOP_ON_TOKEN), "/a"); /* between elements */
    assert_string_equal(at("{\"a\":{b", -1, TSA_STOP_ON_TOKEN), "/a");   /* bad key */
    assert_string_equal(at("[1,]", -1, TSA_STOP_ON_TOKEN), "/1");
    assert_string_equal(at("{\"a\":1}}", -1, TSA_STOP_ON_TOKEN), ""); /* after the root */
    assert_string_equal(at("", 0, TSA_STOP_AT_POS), "");
    /* a token the grammar refuses before the stop is the culprit */
    assert_string_equal(at("{\"a\":{\"b\" ] 1,2", -1, TSA_STOP_AT_POS), "/a/b");
}

static void scanner_keeps_whole_segments(void **state)
{
    (void)state;
    char big[300] = "{\"short\":{\"";
    size_t n = strlen(big);
    memset(big + n, 'k', 200);
    strcpy(big + n + 200, "\":1");
    char out[TS_ERR_POINTER_LEN];
    assert_int_equal(tsa_json_pointer_at(big, strlen(big), TSA_STOP_ON_TOKEN, out, sizeof out), 0);
    assert_string_equal(out, "/short"); /* /short/kkk... does not fit: its parent */
    assert_int_equal(tsa_json_pointer_at(big, strlen(big), TSA_STOP_ON_TOKEN, out, 4), 0);
    assert_string_equal(out, "");
}

/* tsa_parse_object's pointer for body */
static const char *parse_pointer(const char *body, ts_err *err)
{
    json_t *doc = tsa_parse_object(body, strlen(body), err);
    assert_null(doc);
    assert_int_equal(err->code, TS_ERR_PARAM);
    assert_non_null(strstr(err->msg, "malformed JSON at line"));
    return err->pointer;
}

static void jansson_errors_by_kind(void **state)
{
    (void)state;
    ts_err err;
    /* duplicate key: the member */
    assert_string_equal(
        parse_pointer("{\"preset\":\"p\",\"run\":{\"duration\":1,\"duration\":2}}", &err),
        "/run/duration");
    assert_non_null(strstr(err.msg, "duplicate object key"));
    assert_int_equal(err.at_root, 0);
    assert_string_equal(parse_pointer("{\"duration\":0.01,\"duration\":0.02}", &err), "/duration");
    /* numbers out of range: the value */
    assert_string_equal(parse_pointer("{\"run\":{\"duration\":1e400}}", &err), "/run/duration");
    assert_non_null(strstr(err.msg, "real number overflow"));
    assert_string_equal(parse_pointer("{\"run\":{\"x\":[1,99999999999999999999999]}}", &err),
                        "/run/x/1");
    assert_non_null(strstr(err.msg, "too big integer"));
    assert_string_equal(parse_pointer("{\"a\":[-99999999999999999999999]}", &err), "/a/0");
    /* \u0000 in a value: the value; in a key: the object */
    assert_string_equal(parse_pointer("{\"a\":{\"b\":\"x\\u0000\"}}", &err), "/a/b");
    assert_string_equal(parse_pointer("{\"a\":{\"b\\u0000\":1}}", &err), "/a");
    /* bad escapes, control characters, bytes that are not UTF-8 in a string */
    assert_string_equal(parse_pointer("{\"a\":[\"x\\q\"]}", &err), "/a/0");
    assert_string_equal(parse_pointer("{\"a\":{\"b\":\"x\ty\"}}", &err), "/a/b");
    assert_string_equal(parse_pointer("{\"a\":{\"b\":\"x\xff\"}}", &err), "/a/b");
    assert_string_equal(parse_pointer("{\"a\":\"\\ud800\"}", &err), "/a");
    /* a byte that is not UTF-8 outside a string: what begins there */
    assert_string_equal(parse_pointer("{\"a\":[1, \xff]}", &err), "/a/1");
    assert_string_equal(parse_pointer("{\"a\":[1,2\xff]}", &err), "/a");
    assert_string_equal(parse_pointer("{\"a\":1\xff}", &err), "");
    /* syntax */
    assert_string_equal(parse_pointer("{\"preset\": ", &err), "/preset");
    assert_string_equal(parse_pointer("{\"a\":{\"b\":tru}}", &err), "/a/b");
    assert_string_equal(parse_pointer("{\"a\":{\"b\":1.5e}}", &err), "/a/b");
    /* bad numbers end where jansson's lexer ends them: the value, not the array */
    assert_string_equal(parse_pointer("{\"a\":[1.]}", &err), "/a/0");
    assert_string_equal(parse_pointer("{\"a\":[2,1.,3]}", &err), "/a/1");
    assert_string_equal(parse_pointer("{\"a\":[1. ]}", &err), "/a/0");
    assert_string_equal(parse_pointer("{\"a\":[1.e5]}", &err), "/a/0");
    assert_string_equal(parse_pointer("{\"a\":[1e]}", &err), "/a/0");
    assert_string_equal(parse_pointer("{\"a\":[1e+]}", &err), "/a/0");
    assert_string_equal(parse_pointer("{\"a\":[-]}", &err), "/a/0");
    assert_string_equal(parse_pointer("{\"a\":[-x]}", &err), "/a/0");
    assert_string_equal(parse_pointer("{\"a\":[01]}", &err), "/a/0");
    assert_string_equal(parse_pointer("{\"a\":[-01]}", &err), "/a/0");
    assert_string_equal(parse_pointer("{\"a\":{\"b\":1.}}", &err), "/a/b");
    /* a number then a stray ".": the array ("1.5." is 1.5 then ".") */
    assert_string_equal(parse_pointer("{\"a\":[1.5.]}", &err), "/a");
    assert_string_equal(parse_pointer("{\"a\":[1e5.]}", &err), "/a");
    assert_string_equal(parse_pointer("{\"a\":{\"b\":1 2}}", &err), "/a");
    assert_string_equal(parse_pointer("{\"a\":[1,2}", &err), "/a");
    assert_string_equal(parse_pointer("{\"a\":[1,2", &err), "/a");
    /* at the root: pointer "" naming the whole document */
    assert_string_equal(parse_pointer("{duration: 1}", &err), "");
    assert_int_equal(err.at_root, 1);
    assert_string_equal(parse_pointer("{\"a\":1,}", &err), "");
    assert_string_equal(parse_pointer("{\"a\":1}x", &err), "");
    assert_string_equal(parse_pointer("99999999999999999999999", &err), "");
    /* the depth limit: the value that went too deep */
    char deep[2 * 2100 + 16] = "{\"a\":";
    size_t n = strlen(deep);
    memset(deep + n, '[', 2100);
    deep[n + 2100] = '\0';
    const char *p = parse_pointer(deep, &err);
    assert_true(strncmp(p, "/a/0/0/0/", 9) == 0);
}

static void parse_error_problem_lists_pointer(void **state)
{
    (void)state;
    ts_err err;
    const char *body = "{\"run\":{\"duration\":1,\"duration\":2}}";
    assert_null(tsa_parse_object(body, strlen(body), &err));
    json_t *p = tsa_problem_from_err(&err, NULL);
    json_t *e0 = json_array_get(json_object_get(p, "errors"), 0);
    assert_non_null(e0);
    assert_string_equal(json_string_value(json_object_get(e0, "pointer")), "/run/duration");
    assert_int_equal(json_integer_value(json_object_get(p, "status")), 400);
    json_decref(p);
    /* the root too: errors [{"pointer": ""}] */
    assert_null(tsa_parse_object("{x", 2, &err));
    p = tsa_problem_from_err(&err, NULL);
    e0 = json_array_get(json_object_get(p, "errors"), 0);
    assert_non_null(e0);
    assert_string_equal(json_string_value(json_object_get(e0, "pointer")), "");
    json_decref(p);
    /* an error naming no field has no errors array */
    ts_err_set(&err, TS_ERR_NOTFOUND, NULL, "no such thing");
    p = tsa_problem_from_err(&err, NULL);
    assert_null(json_object_get(p, "errors"));
    json_decref(p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(scanner_escapes_keys),
        cmocka_unit_test(scanner_nested_arrays),
        cmocka_unit_test(scanner_strings_hold_anything),
        cmocka_unit_test(scanner_syntax_names_the_place),
        cmocka_unit_test(scanner_keeps_whole_segments),
        cmocka_unit_test(jansson_errors_by_kind),
        cmocka_unit_test(parse_error_problem_lists_pointer),
    };
    return cmocka_run_group_tests_name("api/json_error", tests, NULL, NULL);
}
