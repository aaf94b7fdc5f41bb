"""JSON that does not parse names where, as a bad field does: the JSON Pointer
of the member or value the parser stopped in (api/json_error.h), in the same
problem+json shape with an errors array. It used to be pointer "" (no errors
array) for a duplicate key, a number out of range and every syntax error."""
import requests

from conftest import BASE_PRESET, is_problem, stepped_session


def post(d, path, body):
    return requests.post(d.url + path, data=body, headers={"Content-Type": "application/json"},
                         timeout=30)


def only_error(p):
    assert len(p["errors"]) == 1, p
    return p["errors"][0]


def test_duplicate_key_names_the_member(daemon):
    body = '{"preset":"%s","run":{"duration":1,"duration":2}}' % BASE_PRESET
    p = is_problem(post(daemon, "/v1/sessions", body), 400, "/run/duration")
    assert "duplicate object key" in p["detail"] and "line 1, column" in p["detail"]
    assert p["type"] == "/problems/invalid-config"
    e = only_error(p)
    assert e["pointer"] == "/run/duration" and "duplicate" in e["message"]


def test_numbers_out_of_range_name_the_value(daemon):
    p = is_problem(post(daemon, "/v1/sessions", '{"run":{"duration":1e400}}'), 400,
                   "/run/duration")
    assert "real number overflow" in p["detail"]
    p = is_problem(post(daemon, "/v1/sessions",
                        '{"run":{"duration":99999999999999999999999}}'), 400, "/run/duration")
    assert "too big integer" in p["detail"]
    p = is_problem(post(daemon, "/v1/sessions", '{"vehicle":{"x":[1,-99999999999999999999999]}}'),
                   400, "/vehicle/x/1")
    assert "too big negative integer" in p["detail"]


def test_step_body_duplicate_key(daemon):
    sid = stepped_session(daemon.url)
    p = is_problem(post(daemon, f"/v1/sessions/{sid}/step", '{"duration":0.01,"duration":0.02}'),
                   400, "/duration")
    assert "duplicate" in only_error(p)["message"]


def test_syntax_errors_name_the_place(daemon):
    cases = [('{"preset": ', "/preset"),             # value missing at the end
             ('{"run": {"duration": }}', "/run/duration"),  # value missing
             ('{"run": {"duration" 1}}', "/run/duration"),  # ':' missing after the key
             ('{"run": {"duration": 1 "x": 2}}', "/run"),    # ',' missing: the object
             ('{"run": {"duration": tru}}', "/run/duration"),
             ('{"a~b/c": {"x": [1, 2, }}', "/a~0b~1c/x/2"),  # RFC 6901 escaping
             ('{"k\\"}{[": {"v": "]}", "w": x}}', '/k"}{[/w'),  # braces, quotes in strings
             ('{"a": "x\\q"}', "/a")]                  # bad escape in a value
    for body, ptr in cases:
        p = is_problem(post(daemon, "/v1/sessions", body), 400, ptr)
        assert only_error(p)["pointer"] == ptr, (body, p)
        assert "malformed JSON" in p["detail"], p


def test_root_errors_list_the_empty_pointer(daemon):
    for body in ("{duration: 1}", '{"a": 1} x', "99999999999999999999999", '{"a": 1,', "[1, 2]"):
        p = is_problem(post(daemon, "/v1/sessions", body), 400, "")
        assert only_error(p)["pointer"] == "", (body, p)
