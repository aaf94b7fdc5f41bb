"""The daemon's flags and plumbing after the mutation pass of session 28: each
test here was seen to fail with one small edit of server/main.c, server.c or
frames.c applied (named in its comment) and to pass on the source.

A flag value is checked before the socket is bound, so a start with
`--bind not-an-ip` tells an accepted value (exit 1, the --bind message) from a
refused one (exit 2 naming the flag) without a daemon ever serving."""
import os
import signal
import subprocess

import pytest
import requests

from conftest import TANKSIMD, Daemon


def start(*args, env=None, tmp=None):
    return subprocess.run([TANKSIMD, *args, "--bind", "not-an-ip", "--data-dir", str(tmp)],
                          capture_output=True, text=True, timeout=20, env=env)


def accepted(out):
    return out.returncode == 1 and "--bind: 'not-an-ip'" in out.stderr


@pytest.mark.parametrize("flag,value", [
    ("--threads", "257"),        # at most 256 workers (a bound of 1024 let 257 start)
    ("--max-body", "1023"),      # at least 1 KiB
    ("--timeout", "0"),          # 0 would be no idle timeout at all in libmicrohttpd
    ("--max-samples", "9"),      # at least 10 rows a page
    ("--token", "a" * 128),      # the options' buffer holds 127 characters and its NUL
    ("--token", "two words"),    # a header value cannot carry the blank (`<` for `<=`)
    ("--token", "del\x7f"),      # nor DEL (`>` for `>=`)
])
def test_flag_values_out_of_range_are_refused(flag, value, tmp_path):
    out = start(flag, value, tmp=tmp_path)
    assert out.returncode == 2 and flag in out.stderr, out.stderr


@pytest.mark.parametrize("flag,value", [
    ("--max-rows", "0"),         # documented: 0 is no limit (a lower bound of 1 refused it)
    ("--drain", "0"),            # the default, given explicitly ((0, S] refused it)
    ("--token", "a" * 127),      # the longest token that fits
    ("--threads", "256"),
])
def test_flag_values_at_their_bounds_are_taken(flag, value, tmp_path):
    out = start(flag, value, tmp=tmp_path)
    assert accepted(out), out.stderr


def test_a_flag_without_its_value_is_a_usage_error(tmp_path):
    # exit 2 as every usage error (the mutant: 1, as a failed start)
    out = subprocess.run([TANKSIMD, "--data-dir", str(tmp_path), "--port"],
                         capture_output=True, text=True, timeout=20)
    assert out.returncode == 2 and "missing value: --port" in out.stderr, out.stderr


def test_an_empty_token_variable_means_no_token(tmp_path):
    # TANKSIM_TOKEN= (set, empty) is no token, as unset: it was refused as an
    # empty token once the emptiness test was dropped
    out = start(env=dict(os.environ, TANKSIM_TOKEN=""), tmp=tmp_path)
    assert accepted(out), out.stderr


def test_the_token_flag_wins_over_the_environment(tmp_path, monkeypatch):
    # the flag given is the token; TANKSIM_TOKEN only when neither flag is
    monkeypatch.setenv("TANKSIM_TOKEN", "fromenv")
    d = Daemon("--token", "fromflag", data_dir=str(tmp_path))
    try:
        url = d.url + "/v1/sessions"
        assert requests.get(url, headers={"Authorization": "Bearer fromflag"}).status_code == 200
        assert requests.get(url, headers={"Authorization": "Bearer fromenv"}).status_code == 401
    finally:
        d.stop()


def test_a_token_file_with_crlf_is_read(tmp_path):
    # a token file saved with Windows line ends: its "\r" is not the token's
    f = tmp_path / "token"
    f.write_bytes(b"s3cret\r\n")
    d = Daemon("--token-file", str(f), data_dir=str(tmp_path / "store"))
    try:
        ok = requests.get(d.url + "/v1/sessions", headers={"Authorization": "Bearer s3cret"})
        assert ok.status_code == 200
    finally:
        d.stop()


def test_client_files_no_keeps_them_refused(tmp_path):
    # --client-files no is the default said explicitly: it enabled them when
    # only the word was checked
    csv = tmp_path / "ground.csv"
    csv.write_text("distance_m,height_m\n0,0\n100,1\n")
    d = Daemon("--client-files", "no", data_dir=str(tmp_path / "store"))
    try:
        doc = {"preset": "bump-prescribed-static", "run": {"duration": 0.02},
               "terrain": {"kind": "profile", "profile_csv": str(csv)}}
        r = requests.post(d.url + "/v1/sessions", json=doc)
        assert r.status_code == 400, r.text
        assert [e["pointer"] for e in r.json()["errors"]] == ["/terrain/profile_csv"]
    finally:
        d.stop()


def test_sighup_stops_cleanly(tmp_path):
    # the terminal of `make run` closed: the same clean stop as SIGTERM (without
    # SIGHUP in the waited-for set the daemon died of it, the store not closed)
    d = Daemon(data_dir=str(tmp_path))
    assert requests.get(d.url + "/v1/health").ok
    assert d.stop(signal.SIGHUP) == 0
    assert "SIGHUP received, shutting down" in d.stderr() and "tanksimd: stopped" in d.stderr()


def test_a_body_of_exactly_max_body_bytes_is_read(tmp_path):
    # --max-body N is the largest body taken: N bytes are read (`>=` for `>` in
    # the declared-length or the received-bytes check answered them 413), N + 1
    # are not
    d = Daemon("--max-body", "1024", data_dir=str(tmp_path))
    try:
        doc = '{"preset": "pointmass-prescribed"}'
        for n, status in [(1024, 201), (1025, 413)]:
            body = doc + " " * (n - len(doc))
            r = requests.post(d.url + "/v1/sessions", data=body.encode(),
                              headers={"Content-Type": "application/json"})
            assert r.status_code == status, (n, r.status_code, r.text)
    finally:
        d.stop()


def test_the_origin_check_ignores_the_case_of_the_host(daemon):
    # host names are case-insensitive (RFC 9110 4.2.3): a proxy forwarding
    # "Tank.Example" for a page of https://tank.example is the same site
    # (strcmp for strcasecmp refused its writes 403)
    r = requests.post(daemon.url + "/v1/sessions", json={"preset": "pointmass-prescribed"},
                      headers={"Origin": "https://tank.example", "X-Forwarded-Host": "Tank.Example"})
    assert r.status_code == 201, r.text


def test_405_says_allow_and_answers_are_not_cached(daemon):
    # RFC 9110 15.5.6: a 405 lists the methods the resource takes (the Allow
    # header was dropped); and an answer that changes (a session's status, a
    # problem) says Cache-Control: no-store, so a browser or proxy does not
    # serve a stale one
    r = requests.delete(daemon.url + "/v1/health")
    assert r.status_code == 405 and "GET" in r.headers.get("Allow", ""), r.headers
    assert r.headers.get("Cache-Control") == "no-store", r.headers
    r = requests.get(daemon.url + "/v1/sessions")
    assert r.status_code == 200 and r.headers.get("Cache-Control") == "no-store", r.headers


def test_a_head_with_a_foreign_origin_is_a_read(daemon):
    # HEAD changes nothing: like GET it is answered whatever the Origin (it
    # was refused 403 when only GET and OPTIONS were exempt)
    r = requests.head(daemon.url + "/v1/health", headers={"Origin": "http://evil.example"})
    assert r.status_code == 200, r.headers


def test_a_chunked_body_past_max_body_is_413(tmp_path):
    # a body sent chunked has no Content-Length to refuse it by: it is counted
    # as it arrives and answered 413 (without the final check the part kept
    # was routed, and a cut JSON document got 400)
    d = Daemon("--max-body", "1024", data_dir=str(tmp_path))
    try:
        doc = b'{"preset": "pointmass-prescribed", "description": "' + b"x" * 3000 + b'"}'
        r = requests.post(d.url + "/v1/sessions", data=iter([doc[:1000], doc[1000:]]),
                          headers={"Content-Type": "application/json"})
        assert r.status_code == 413, r.text
        assert "1024" in r.json()["detail"]
    finally:
        d.stop()


def test_multipart_frames_name_their_sample_index(daemon):
    # X-Frame-Index is the stored sample drawn (t x sample_rate), as
    # X-Frame-Time is its time (it gave the count of frames drawn so far)
    body = {"preset": "bump-prescribed-static", "run": {"duration": 1.0, "sample_rate": 100}}
    s = requests.post(daemon.url + "/v1/sessions", json=body).json()
    base = daemon.url + s["links"]["self"]
    r = requests.post(base + "/step", json={"duration": 0.2})
    assert r.status_code == 200, r.text
    a = requests.get(base + "/frames", params={"from": 0, "to": 0.2, "fps": 10, "width": 16,
                                               "height": 16, "format": "multipart"})
    assert a.status_code == 200, a.text
    heads = [dict(l.split(": ", 1) for l in chunk.partition(b"\r\n\r\n")[0].decode().split("\r\n"))
             for chunk in a.content.split(b"--frame\r\n")[1:]]
    assert [h["X-Frame-Index"] for h in heads] == ["0", "10", "20"], heads
    assert [float(h["X-Frame-Time"]) for h in heads] == [0, 0.1, 0.2], heads
