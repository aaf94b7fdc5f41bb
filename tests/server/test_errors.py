"""tanksimd bad input (issue 7): every rejection is a 4xx application/problem+json
(RFC 9457) with status, title, detail, and for body/config errors an errors
array whose JSON Pointer names the field. The daemon keeps serving after each."""
import socket

import pytest
import requests

from conftest import BASE_PRESET, Daemon, is_problem


def post(d, path, data=None, **kw):
    return requests.post(d.url + path, data=data, headers={"Content-Type": "application/json"},
                         **kw)


@pytest.fixture(scope="module")
def sid(daemon):
    r = requests.post(daemon.url + "/v1/sessions", json={"preset": BASE_PRESET})
    return r.json()["id"]


def test_malformed_json(daemon, sid):
    p = is_problem(post(daemon, "/v1/sessions", '{"preset": '), 400)
    assert "malformed JSON" in p["detail"] and "line 1" in p["detail"]
    is_problem(post(daemon, f"/v1/sessions/{sid}/step", "{duration: 1}"), 400)
    is_problem(post(daemon, "/v1/sessions", "[1, 2]"), 400)
    is_problem(post(daemon, "/v1/sessions", ""), 400)


def test_wrong_types(daemon, sid):
    p = is_problem(requests.post(daemon.url + "/v1/sessions",
                                 json={"preset": BASE_PRESET, "run": {"duration": "long"}}),
                   400, "/run/duration")
    assert "number" in p["detail"]
    is_problem(requests.post(daemon.url + "/v1/sessions", json={"preset": 7}), 400, "/preset")
    p = is_problem(requests.post(f"{daemon.url}/v1/sessions/{sid}/step",
                                 json={"duration": "1"}), 400, "/duration")
    assert "number expected, got a string" in p["detail"]
    is_problem(requests.post(f"{daemon.url}/v1/sessions/{sid}/run",
                             json={"until": [1]}), 400, "/until")


def test_unknown_fields(daemon, sid):
    is_problem(requests.post(daemon.url + "/v1/sessions",
                             json={"preset": BASE_PRESET, "vehicle": {"mass_typo": 1}}),
               400, "/vehicle/mass_typo")
    is_problem(requests.post(daemon.url + "/v1/sessions",
                             json={"preset": BASE_PRESET, "nonsense": {}}), 400, "/nonsense")
    is_problem(requests.post(f"{daemon.url}/v1/sessions/{sid}/step",
                             json={"duration": 0.1, "speed": 3}), 400, "/speed")
    is_problem(requests.post(f"{daemon.url}/v1/sessions/{sid}/run",
                             json={"untill": 3}), 400, "/untill")


def test_out_of_range_values_all_reported(daemon, sid):
    r = requests.post(daemon.url + "/v1/sessions",
                      json={"preset": BASE_PRESET, "vehicle": {"mass": -5},
                            "run": {"sample_rate": 1e9}})
    p = is_problem(r, 400, "/vehicle/mass")
    assert "/run/sample_rate" in [e["pointer"] for e in p["errors"]]
    is_problem(requests.post(f"{daemon.url}/v1/sessions/{sid}/step",
                             json={"duration": -1}), 400, "/duration")
    is_problem(requests.post(f"{daemon.url}/v1/sessions/{sid}/run",
                             json={"real_time_factor": 0}), 400, "/real_time_factor")
    is_problem(requests.get(f"{daemon.url}/v1/sessions/{sid}/series", params={"every": 0}),
               400, "/every")
    is_problem(requests.get(f"{daemon.url}/v1/sessions/{sid}/series", params={"from": "x"}),
               400, "/from")
    is_problem(requests.get(f"{daemon.url}/v1/sessions/{sid}/series", params={"format": "xml"}),
               400, "/format")
    is_problem(requests.get(f"{daemon.url}/v1/sessions/{sid}/series",
                            params={"channels": "vehicle.speed,bogus"}), 404, "/channels")
    p = is_problem(requests.get(f"{daemon.url}/v1/sessions/{sid}/stream",
                                headers={"Last-Event-ID": "abc"}), 400, "/Last-Event-ID")
    assert p["detail"].startswith("header Last-Event-ID:"), p
    is_problem(requests.get(f"{daemon.url}/v1/sessions/{sid}/stream", params={"format": "xml"}),
               400, "/format")
    is_problem(requests.get(daemon.url + "/v1/sessions", params={"page_size": 0}), 400,
               "/page_size")


def test_unknown_preset_and_session(daemon):
    p = is_problem(requests.post(daemon.url + "/v1/sessions", json={"preset": "no-such"}), 400,
                   "/preset")
    assert "no-such" in p["detail"]
    for method, path in [("GET", ""), ("DELETE", ""), ("POST", "/step"), ("POST", "/run"),
                         ("GET", "/series"), ("GET", "/stream"), ("GET", "/fft")]:
        r = requests.request(method, f"{daemon.url}/v1/sessions/snope{path}", json={})
        p = is_problem(r, 404)
        assert "snope" in p["detail"]


def test_oversize_body_is_413(tmp_path):
    d = Daemon("--max-body", "1024", data_dir=str(tmp_path))
    try:
        big = '{"preset": "%s", "description": "%s"}' % (BASE_PRESET, "x" * 4000)
        p = is_problem(post(d, "/v1/sessions", big), 413)
        assert "1024" in p["detail"]
        assert requests.get(d.url + "/v1/health").ok
    finally:
        d.stop()


def test_session_limit_is_429(tmp_path):
    d = Daemon("--max-sessions", "2", data_dir=str(tmp_path))
    try:
        for _ in range(2):
            assert requests.post(d.url + "/v1/sessions", json={"preset": BASE_PRESET}).ok
        p = is_problem(requests.post(d.url + "/v1/sessions", json={"preset": BASE_PRESET}), 429)
        assert "--max-sessions" in p["detail"]
    finally:
        d.stop()


def test_token_required_everywhere_but_health(tmp_path):
    d = Daemon("--token", "s3cret", data_dir=str(tmp_path))
    try:
        assert requests.get(d.url + "/v1/health").ok
        for method, path in [("GET", "/v1/presets"), ("POST", "/v1/sessions"),
                             ("GET", "/v1/sessions"), ("GET", "/metrics"),
                             ("GET", "/v1/openapi.yaml"), ("GET", "/v1/operations/x"),
                             ("GET", "/nope")]:
            r = requests.request(method, d.url + path, json={"preset": BASE_PRESET})
            is_problem(r, 401)
            assert r.headers["WWW-Authenticate"].startswith("Bearer")
        bad = requests.get(d.url + "/v1/presets", headers={"Authorization": "Bearer s3creT"})
        is_problem(bad, 401)
        ok = requests.post(d.url + "/v1/sessions", json={"preset": BASE_PRESET},
                           headers={"Authorization": "Bearer s3cret"})
        assert ok.status_code == 201
    finally:
        d.stop()


def test_binds_loopback_by_default(daemon):
    out = socket.socket()
    try:
        assert out.connect_ex(("127.0.0.1", daemon.port)) == 0
    finally:
        out.close()
    assert "listening on 127.0.0.1" in daemon.stderr()
