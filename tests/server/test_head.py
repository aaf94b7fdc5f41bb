"""HEAD is answered wherever GET is (RFC 9110 §9.1: a general-purpose server
MUST support GET and HEAD; §9.3.2: the same header fields as GET, no content).

The daemon used to answer 405 to every HEAD, so a monitor probing
`HEAD /v1/health` saw the service as broken. Each test compares the HEAD answer
with the GET answer of the same URL.
"""
import socket

import pytest
import requests

from conftest import stepped_session


@pytest.mark.parametrize("path", ["/v1/health", "/v1/presets", "/v1/schema", "/",
                                  "/v1/sessions/{sid}", "/v1/sessions/{sid}/series?format=csv",
                                  "/v1/sessions/{sid}/fft?channel=vehicle.speed"])
def test_head_has_the_get_headers_and_no_body(daemon, sid, path):
    url = daemon.url + path.format(sid=sid)
    g = requests.get(url, timeout=10)
    h = requests.head(url, timeout=10)
    assert g.status_code == 200 and h.status_code == 200, (g.status_code, h.status_code)
    assert h.content == b""
    assert h.headers["Content-Type"] == g.headers["Content-Type"]
    if "Content-Length" in g.headers:
        assert h.headers["Content-Length"] == g.headers["Content-Length"]


@pytest.fixture(scope="module")
def vsid(daemon):
    # a vehicle session: frames need the tank's geometry
    return stepped_session(daemon.url, "bump-prescribed-static", 0.2)


@pytest.mark.parametrize("path,ctype", [
    ("/v1/sessions/{sid}/stream", b"text/event-stream"),
    ("/v1/sessions/{sid}/stream?format=ndjson", b"application/x-ndjson"),
    ("/v1/sessions/{vsid}/frames?format=multipart&width=64&height=48&to=0.1&fps=10",
     b"multipart/x-mixed-replace")])
def test_head_on_a_stream_returns_at_once_with_nothing_after_the_headers(daemon, sid, vsid, path,
                                                                         ctype):
    # a live stream never ends under GET; HEAD must answer with its headers and
    # nothing else on the connection (libmicrohttpd would send a chunked
    # response's last chunk "0\r\n\r\n", read by a keep-alive client as the
    # start of its next response): what follows is the next response or the
    # connection's end, announced. No Content-Length: the GET has none to give,
    # and "0" would be false (RFC 9110 §8.6; it was sent until session 21)
    host, port = daemon.url.split("//")[1].split(":")
    with socket.create_connection((host, int(port)), timeout=5) as c:
        c.sendall(f"HEAD {path.format(sid=sid, vsid=vsid)} HTTP/1.1\r\nHost: x\r\n\r\n"
                  "GET /v1/health HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n".encode())
        data = b""
        while True:
            chunk = c.recv(4096)  # socket timeout 5 s: a hang fails the test
            if not chunk:
                break
            data += chunk
    head, _, rest = data.partition(b"\r\n\r\n")
    assert head.startswith(b"HTTP/1.1 200"), head
    assert ctype in head
    assert b"\r\ncontent-length:" not in head.lower(), head
    assert rest.startswith(b"HTTP/1.1 200") or (rest == b"" and b"connection: close" in head.lower()), rest[:40]


def test_head_on_a_post_only_path_is_405_listing_get_free_methods(daemon, sid):
    r = requests.head(f"{daemon.url}/v1/sessions/{sid}/step", timeout=10)
    assert r.status_code == 405
    assert {m.strip() for m in r.headers["Allow"].split(",")} == {"POST"}
