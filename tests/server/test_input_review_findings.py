"""Findings of a bad-input review of the daemon (session 32), each reproduced
against the daemon before its fix:
- a stream whose session was deleted while it was sent ended cleanly, with
  no `end` event, after part of the rows (the rows went with the session
  before the stream's wait noticed the deletion);
- a frame asked half a sample period past the last stored one was drawn at
  the last sample under the next sample's ETag (marked immutable), so a
  client revalidating it later got 304 for an image of another sample;
- /fft with the Hann window over 2 samples answered 200 with an empty
  amplitude list (the symmetric window over 2 points is all zeros: NaN
  amplitudes, which jansson cannot write);
- POST /v1/engine-map and /v1/tune answered 202 to configs that a session
  refuses with 400 (the analysis' own checks ran on the worker);
- a %0A in the path started a line of the client's choosing in the log;
- a made-up /series page_token read rows before `from` or off the `every`
  grid;
- a body with 90,000 unknown fields got a 6.5-MB problem listing each;
- a string's limit, counted in bytes, was said in characters: 40 'é' (80
  bytes) got "at most 63 characters, got 80";
- a request with two different Content-Length headers was taken (201):
  RFC 9112 6.3 makes it invalid, and behind a proxy that framed the body by
  the other one its tail would be read as a request of its own;
- a synchronous step went on after its client hung up (a 10-s step of a
  session with max_step 1 us holds a worker for minutes, and every other
  step of the session got 409 meanwhile).
"""
import socket
import time

import requests

from conftest import is_problem


def stepped_session(url, preset="bump-prescribed-static", seconds=1.0):
    r = requests.post(url + "/v1/sessions", json={"preset": preset})
    assert r.status_code == 201, r.text
    s = r.json()["id"]
    r = requests.post(f"{url}/v1/sessions/{s}/step", json={"duration": seconds}, timeout=120)
    assert r.status_code == 200, r.text
    return s


def read_stream_across_delete(daemon, fmt):
    """A done 30-s session's whole stream, read slowly, with the session
    deleted once the first bytes arrived: (text received, cut: the
    connection closed without the chunked body's last chunk)."""
    url = daemon.url
    r = requests.post(url + "/v1/sessions",
                      json={"preset": "bump-prescribed-static", "run": {"duration": 30}})
    sid = r.json()["id"]
    for _ in range(3):  # 6001 rows, ~12 MB of SSE: more than the sockets' buffers hold
        r = requests.post(f"{url}/v1/sessions/{sid}/step", json={"duration": 10}, timeout=120)
        assert r.status_code == 200, r.text
    host, port = daemon.url.split("//")[1].split(":")
    s = socket.socket()
    # a small window, set before connecting: the daemon cannot hand the kernel
    # the whole stream before the delete lands (a 4-kB one makes the reads slow)
    s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 65536)
    s.connect((host, int(port)))
    s.sendall(f"GET /v1/sessions/{sid}/stream?format={fmt} HTTP/1.1\r\nHost: x\r\n"
              "Connection: close\r\n\r\n".encode())
    data = s.recv(2000)
    time.sleep(0.3)
    assert requests.delete(f"{url}/v1/sessions/{sid}").status_code == 204
    s.settimeout(20)
    while True:
        try:
            chunk = s.recv(65536)
        except ConnectionResetError:
            break
        if not chunk:
            break
        data += chunk
    s.close()
    text = data.decode("utf-8", "replace")
    return text, not text.endswith("0\r\n\r\n")


def test_sse_stream_of_a_deleted_session_ends_with_end_deleted(daemon):
    text, cut = read_stream_across_delete(daemon, "sse")
    samples = text.count("event: sample")
    # the reader was slow: the delete landed while rows were still unsent
    assert 0 < samples < 6001, samples
    assert "event: end" in text and '"status":"deleted"' in text, text[-400:]
    assert not cut


def test_ndjson_stream_of_a_deleted_session_is_cut(daemon):
    text, cut = read_stream_across_delete(daemon, "ndjson")
    rows = text.count('"index"')
    assert 0 < rows < 6001, rows
    assert cut, text[-200:]  # no end line in NDJSON: a clean end would claim every row


def test_frame_half_a_period_past_the_last_sample_is_the_last_sample(daemon):
    url = daemon.url
    s = stepped_session(url)  # 200 Hz: the last sample is 200, at 1 s
    frame = f"{url}/v1/sessions/{s}/frame.png"
    size = {"width": 64, "height": 64}
    last = requests.get(frame, params={"t": 1, **size})
    r = requests.get(frame, params={"t": 1.0025, **size})  # 200.5 periods: still sample 200
    assert r.status_code == 200 and "-200-" in r.headers["ETag"], r.headers
    assert r.headers["ETag"] == last.headers["ETag"] and r.content == last.content
    # once sample 201 is stored, the ETag of 1.0025 s does not answer for it
    assert requests.post(f"{url}/v1/sessions/{s}/step", json={"duration": 0.5}).status_code == 200
    r = requests.get(frame, params={"t": 1.005, **size}, headers={"If-None-Match": last.headers["ETag"]})
    assert r.status_code == 200 and "-201-" in r.headers["ETag"], r.headers
    is_problem(requests.get(frame, params={"t": 1.5051, **size}), 400, "/t")


def test_hann_spectrum_needs_three_samples(daemon):
    url = daemon.url
    s = stepped_session(url)
    fft = f"{url}/v1/sessions/{s}/fft"
    q = {"channel": "vehicle.speed", "window": "hann", "from": 0}
    p = is_problem(requests.get(fft, params={**q, "to": 0.005}), 400, "/from")
    assert "at least 3 with the Hann window" in p["detail"], p
    r = requests.get(fft, params={**q, "to": 0.01})
    assert r.status_code == 200 and len(r.json()["amplitude"]) == 2, r.text
    # the rectangular window over 2 samples is a spectrum
    r = requests.get(fft, params={**q, "window": "rect", "to": 0.005})
    assert r.status_code == 200 and len(r.json()["amplitude"]) == 2, r.text


def test_analyses_refuse_their_own_config_errors_before_queueing(daemon):
    url = daemon.url
    is_problem(requests.post(url + "/v1/engine-map",
                             json={"engine": {"fidelity": "map", "map_speed": [100]}}),
               400, "/engine/map_speed")
    is_problem(requests.post(url + "/v1/tune", json={"control": {"tune_window": 4}}),
               400, "/control/tune_window")
    # nothing was stored for them (no other test here starts an analysis)
    assert requests.get(url + "/v1/analyses").json()["analyses"] == []


def test_control_bytes_in_the_path_cannot_forge_a_log_line(daemon):
    forged = "2026-11-25T00:00:00Z DELETE /v1/sessions/FORGED 204 0 1.0ms"
    r = requests.get(daemon.url + "/v1/sessions/x%0A" + forged.replace(" ", "%20"))
    assert r.status_code == 404
    time.sleep(0.2)
    log = daemon.stderr()
    assert forged not in log.splitlines(), log[-500:]
    assert "/v1/sessions/x%0A2026-11-25T00:00:00Z%20DELETE" in log, log[-500:]


def test_series_page_token_must_be_one_of_the_querys_pages(daemon):
    url = daemon.url
    s = stepped_session(url)
    series = f"{url}/v1/sessions/{s}/series"
    is_problem(requests.get(series, params={"from": 0.5, "page_token": 0}), 400, "/page_token")
    is_problem(requests.get(series, params={"every": 10, "page_token": 7}), 400, "/page_token")
    r = requests.get(series, params={"every": 10, "page_size": 2})
    first = r.json()
    assert first["index"] == [0, 10], first["index"]
    r = requests.get(series, params={"every": 10, "page_size": 2,
                                     "page_token": first["next_page_token"]})
    assert r.status_code == 200 and r.json()["index"] == [20, 30], r.text


def test_a_body_with_many_errors_lists_the_first_hundred(daemon):
    # 90,000 unknown fields made a 6.5 MB problem with 90,000 entries
    body = {"vehicle": {f"k{i}": 1 for i in range(5000)}}
    r = requests.post(daemon.url + "/v1/sessions", json=body)
    p = is_problem(r, 400, "/vehicle/k0")
    assert len(p["errors"]) == 101, len(p["errors"])
    assert p["errors"][99]["pointer"] == "/vehicle/k99"
    assert p["errors"][100] == {"pointer": "",
                                "message": "more errors were found; the first 100 are listed"}
    assert len(r.content) < 20000, len(r.content)
    # a body with exactly 100 has no note
    r = requests.post(daemon.url + "/v1/sessions",
                      json={"vehicle": {f"k{i}": 1 for i in range(100)}})
    assert len(is_problem(r, 400)["errors"]) == 100


def test_a_string_limit_is_said_in_bytes(daemon):
    r = requests.post(daemon.url + "/v1/sessions",
                      json={"terrain": {"kind": "bumps", "course": "\u00e9" * 40}})
    p = is_problem(r, 400, "/terrain/course")
    assert "at most 63 bytes of UTF-8, got 80" in p["detail"], p
    course = requests.get(daemon.url + "/v1/schema").json()["properties"]["terrain"]["properties"]["course"]
    assert course["maxLength"] == 63 and course["x-max-bytes"] == 63, course


def test_two_content_length_headers_are_refused(daemon):
    host, port = daemon.url.split("//")[1].split(":")
    before = len(requests.get(daemon.url + "/v1/sessions").json()["sessions"])
    body = b'{"preset":"pointmass-prescribed"}'
    with socket.create_connection((host, int(port)), timeout=10) as s:
        s.sendall(b"POST /v1/sessions HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
                  + f"Content-Length: {len(body)}\r\nContent-Length: {len(body) - 1}\r\n\r\n".encode()
                  + body)
        data = b""
        while b"\r\n\r\n" not in data or not data.rstrip().endswith(b"}"):
            chunk = s.recv(65536)
            if not chunk:
                break
            data += chunk
    text = data.decode()
    assert text.startswith("HTTP/1.1 400"), text
    assert "/problems/bad-framing" in text and "Content-Length" in text, text
    assert len(requests.get(daemon.url + "/v1/sessions").json()["sessions"]) == before


def test_a_step_stops_when_its_client_hangs_up(daemon):
    url = daemon.url
    # ~1 us steps: a 10-s step would take minutes of worker time
    r = requests.post(url + "/v1/sessions",
                      json={"preset": "bump-prescribed-static", "run": {"max_step": 1e-6}})
    sid = r.json()["id"]
    try:
        requests.post(f"{url}/v1/sessions/{sid}/step", json={"duration": 10}, timeout=1.5)
        assert False, "the step answered within 1.5 s"
    except requests.exceptions.ReadTimeout:
        pass  # the client gives up and closes the connection
    deadline = time.time() + 10
    while time.time() < deadline:
        r = requests.post(f"{url}/v1/sessions/{sid}/step", json={"duration": 0.005}, timeout=30)
        if r.status_code != 409:
            break
        time.sleep(0.1)
    assert r.status_code == 200, r.text  # the abandoned step let go of the session
    s = requests.get(f"{url}/v1/sessions/{sid}").json()
    assert s["status"] == "paused" and s["t"] < 5, s
