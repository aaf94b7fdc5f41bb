"""The reply budget (server.h TSD_REPLY_BUDGET) in GET /metrics: a gauge of
the bytes of answers held until their clients read them, the budget, and a
counter of the answers refused 503 /problems/busy."""
import socket
import time

import pytest
import requests

from conftest import Daemon

BUDGET = 128 << 20


@pytest.fixture(scope="module")
def d():
    dm = Daemon()
    yield dm
    dm.stop()


@pytest.fixture(scope="module")
def sid(d):
    r = requests.post(d.url + "/v1/sessions",
                      json={"preset": "bump-coupled-rack90", "run": {"sample_rate": 20000, "duration": 1}})
    sid = r.json()["id"]
    assert requests.post(f"{d.url}/v1/sessions/{sid}/step", json={"duration": 1}).status_code == 200
    return sid


def metric(url, name):
    for line in requests.get(url + "/metrics").text.splitlines():
        if line.startswith(name + " "):
            return float(line.split()[1])
    raise AssertionError(f"no {name} in /metrics")


def unread(d, path):
    """Ask for path on a socket that is never read: (socket, status)."""
    s = socket.create_connection(("127.0.0.1", d.port))
    s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    s.sendall(f"GET {path} HTTP/1.1\r\nHost: x\r\n\r\n".encode())
    s.settimeout(10)
    head = b""
    while b"\r\n\r\n" not in head:
        chunk = s.recv(1024)
        assert chunk
        head += chunk
    return s, int(head.split()[1])


def wait_released(url):
    deadline = time.time() + 5  # the held answers go with their connections
    while metric(url, "tanksimd_reply_held_bytes") != 0 and time.time() < deadline:
        time.sleep(0.05)
    assert metric(url, "tanksimd_reply_held_bytes") == 0


def test_metrics_show_held_reply_bytes_and_busy_refusals(d, sid):
    assert metric(d.url, "tanksimd_reply_budget_bytes") == BUDGET
    wait_released(d.url)
    busy0 = metric(d.url, "tanksimd_reply_busy_total")
    size = len(requests.get(f"{d.url}/v1/sessions/{sid}/series").content)
    assert size > 8 << 20
    socks, statuses = [], []
    try:
        for _ in range(20):
            s, st = unread(d, f"/v1/sessions/{sid}/series")
            socks.append(s)
            statuses.append(st)
        held = statuses.count(200)
        assert 503 in statuses, statuses
        assert metric(d.url, "tanksimd_reply_held_bytes") == held * size
        assert metric(d.url, "tanksimd_reply_busy_total") == busy0 + statuses.count(503)
    finally:
        for s in socks:
            s.close()
    wait_released(d.url)


def fill_budget(d, sid, socks):
    """Hold unread answers until no counted answer (64 kB and up) fits."""
    full = len(requests.get(f"{d.url}/v1/sessions/{sid}/series").content)
    while metric(d.url, "tanksimd_reply_held_bytes") + full <= BUDGET:
        s, st = unread(d, f"/v1/sessions/{sid}/series")
        socks.append(s)
        assert st == 200
    room = BUDGET - metric(d.url, "tanksimd_reply_held_bytes")
    lo, hi = 1, 20001  # the largest page that fits in the room left
    while lo < hi:
        k = (lo + hi + 1) // 2
        r = requests.get(f"{d.url}/v1/sessions/{sid}/series", params={"page_size": k})
        if r.status_code == 200 and len(r.content) <= room:
            lo = k
        else:
            hi = k - 1
    s, st = unread(d, f"/v1/sessions/{sid}/series?page_size={lo}")
    socks.append(s)
    assert st == 200
    left = BUDGET - metric(d.url, "tanksimd_reply_held_bytes")
    assert 0 <= left < 64 << 10, left


def test_frames_are_refused_before_they_are_drawn_when_the_budget_is_full(d, sid):
    wait_released(d.url)
    frame = f"{d.url}/v1/sessions/{sid}/frame.png"
    params = {"t": 0.5, "width": 4096, "height": 4096, "antialias": 1}
    t0 = time.time()
    assert requests.get(frame, params=params).status_code == 200
    draw = time.time() - t0
    socks = []
    try:
        fill_budget(d, sid, socks)
        busy0 = metric(d.url, "tanksimd_reply_busy_total")
        t0 = time.time()
        r = requests.get(frame, params={**params, "t": 0.6})  # not cached: a new frame
        took = time.time() - t0
        assert r.status_code == 503 and r.json()["type"].endswith("/problems/busy"), r.text
        assert r.headers.get("Retry-After")
        # refused up front: not drawn (~draw s) and thrown away
        assert took < draw / 3, (took, draw)
        t0 = time.time()
        r = requests.get(f"{d.url}/v1/sessions/{sid}/frames",
                         params={"from": 0, "to": 0.5, "fps": 20, "width": 2048, "height": 2048})
        assert r.status_code == 503 and r.json()["type"].endswith("/problems/busy"), r.text
        assert time.time() - t0 < draw / 3
        assert metric(d.url, "tanksimd_reply_busy_total") == busy0 + 2
    finally:
        for s in socks:
            s.close()
    wait_released(d.url)
    assert requests.get(frame, params={"t": 0.6, "width": 320, "height": 180}).status_code == 200
