"""Regression tests for what the HTTP fuzzer (tests/fuzz/http_fuzz.py, seed 1) found
in tanksimd: each failed on the daemon before its fix.

- Problem texts quote the request (query values, path segments, names from the
  body cut to a length). Bytes that are not UTF-8 made jansson refuse the
  document, and the client got 500 "could not build the response", without
  the parameter named, for its own mistake (110 of 2376 requests).
- A 405 had no Allow header (RFC 9110 §15.5.6: the server MUST send one).
- GET .../fft?channel=NAME with an unknown NAME named "/channels", a parameter
  of other routes, not the "/channel" the request has.
"""
import pytest
import requests

from conftest import is_problem

REPLACEMENT = "\ufffd"


# (route under the session, query parameter); "" = /v1/sessions itself
NOT_UTF8_PARAMS = [("", "page_size"), ("", "page_token"), ("series", "from"),
                   ("series", "every"), ("series", "format"), ("series", "channels"),
                   ("stream", "since"), ("stream", "format"), ("fft", "channel"), ("fft", "from"),
                   ("frames", "format"), ("frame.png", "width")]


@pytest.mark.parametrize("route,param", NOT_UTF8_PARAMS)
@pytest.mark.parametrize("value", ["%ff%fe", "%C0%AF", "1%ED%A0%80"])  # bad byte, overlong, surrogate
def test_query_value_not_utf8_is_refused_naming_the_parameter(daemon, sid, route, param, value):
    base = "/v1/sessions" if not route else f"/v1/sessions/{sid}/{route}"
    extra = "&channel=vehicle.speed" if route == "fft" and param != "channel" else ""
    r = requests.get(f"{daemon.url}{base}?{param}={value}{extra}")
    status = 404 if param in ("channels", "channel") else 400  # unknown channel name: 404
    p = is_problem(r, status, "/" + param)
    assert REPLACEMENT in p["detail"], p


@pytest.mark.parametrize("path", ["/v1/presets/%ff", "/v1/sessions/%ff%fe",
                                  "/v1/sessions/%C0%AF/series", "/v1/%ff", "/static/%ff.js"])
def test_path_not_utf8_is_404_problem(daemon, path):
    p = is_problem(requests.get(daemon.url + path), 404)
    assert REPLACEMENT in p["detail"], p


def test_name_cut_inside_a_utf8_character_is_a_problem(daemon):
    # the no-such-preset message quotes the name cut to a byte length, here
    # inside a two-byte character; the request body itself is valid JSON and
    # UTF-8 (a name in a body is a bad value: 400 since session 29)
    r = requests.post(daemon.url + "/v1/sessions", json={"preset": "\u00e9" * 300})
    p = is_problem(r, 400, "/preset")
    assert "\u00e9\u00e9" in p["detail"]


def test_last_event_id_not_utf8_is_400(daemon, sid):
    r = requests.get(f"{daemon.url}/v1/sessions/{sid}/stream",
                     headers={"Last-Event-ID": b"\xff\xfe"})
    is_problem(r, 400, "/Last-Event-ID")


@pytest.mark.parametrize("method,path,allow", [
    ("DELETE", "/v1/health", {"GET", "HEAD"}),
    ("PUT", "/v1/sessions", {"GET", "HEAD", "POST"}),
    ("PATCH", "/v1/sessions/{sid}", {"GET", "HEAD", "DELETE"}),
    ("GET", "/v1/sessions/{sid}/step", {"POST"}),
    ("POST", "/v1/operations/op0:cancel/", None),  # no such path: 404, no Allow
    ("DELETE", "/v1/operations/op0:cancel", {"POST"}),
    ("FOO", "/", {"GET", "HEAD"}),
])
def test_405_lists_the_allowed_methods(daemon, sid, method, path, allow):
    r = requests.request(method, daemon.url + path.format(sid=sid))
    if allow is None:
        is_problem(r, 404)
        assert "Allow" not in r.headers
        return
    is_problem(r, 405)
    assert set(m.strip() for m in r.headers["Allow"].split(",")) == allow, r.headers


def test_fft_unknown_channel_names_the_channel_parameter(daemon, sid):
    r = requests.get(f"{daemon.url}/v1/sessions/{sid}/fft", params={"channel": "no.such"})
    p = is_problem(r, 404, "/channel")
    assert "no.such" in p["detail"]
    # the known one still works
    r = requests.get(f"{daemon.url}/v1/sessions/{sid}/fft", params={"channel": "vehicle.speed"})
    assert r.status_code == 200, r.text
