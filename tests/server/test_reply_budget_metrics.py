"""The reply budget (server.h TSD_REPLY_BUDGET) in GET /metrics: a gauge of
the bytes of answers held until their clients read them, the budget, and a
counter of the answers refused 503 /problems/busy."""
import time

import pytest
import requests

from conftest import metric, unread, wait_released, wide_session

BUDGET = 128 << 20


@pytest.fixture(scope="module")
def sid(daemon):
    return wide_session(daemon.url)


def test_metrics_show_held_reply_bytes_and_busy_refusals(daemon, sid):
    assert metric(daemon.url, "tanksimd_reply_budget_bytes") == BUDGET
    wait_released(daemon.url)
    busy0 = metric(daemon.url, "tanksimd_reply_busy_total")
    size = len(requests.get(f"{daemon.url}/v1/sessions/{sid}/series").content)
    assert size > 8 << 20
    socks, statuses = [], []
    try:
        for _ in range(20):
            s, st = unread(daemon, f"/v1/sessions/{sid}/series")
            socks.append(s)
            statuses.append(st)
        held = statuses.count(200)
        assert 503 in statuses, statuses
        assert metric(daemon.url, "tanksimd_reply_held_bytes") == held * size
        assert metric(daemon.url, "tanksimd_reply_busy_total") == busy0 + statuses.count(503)
    finally:
        for s in socks:
            s.close()
    wait_released(daemon.url)


def fill_budget(daemon, sid, socks):
    """Hold unread answers until no counted answer (64 kB and up) fits."""
    full = len(requests.get(f"{daemon.url}/v1/sessions/{sid}/series").content)
    while metric(daemon.url, "tanksimd_reply_held_bytes") + full <= BUDGET:
        s, st = unread(daemon, f"/v1/sessions/{sid}/series")
        socks.append(s)
        assert st == 200
    room = BUDGET - metric(daemon.url, "tanksimd_reply_held_bytes")
    lo, hi = 1, 20001  # the largest page that fits in the room left
    while lo < hi:
        k = (lo + hi + 1) // 2
        r = requests.get(f"{daemon.url}/v1/sessions/{sid}/series", params={"page_size": k})
        if r.status_code == 200 and len(r.content) <= room:
            lo = k
        else:
            hi = k - 1
    s, st = unread(daemon, f"/v1/sessions/{sid}/series?page_size={lo}")
    socks.append(s)
    assert st == 200
    left = BUDGET - metric(daemon.url, "tanksimd_reply_held_bytes")
    assert 0 <= left < 64 << 10, left


def test_frames_are_refused_before_they_are_drawn_when_the_budget_is_full(daemon, sid):
    wait_released(daemon.url)
    frame = f"{daemon.url}/v1/sessions/{sid}/frame.png"
    params = {"t": 0.5, "width": 4096, "height": 4096, "antialias": 1}
    t0 = time.time()
    assert requests.get(frame, params=params).status_code == 200
    draw = time.time() - t0
    socks = []
    try:
        fill_budget(daemon, sid, socks)
        busy0 = metric(daemon.url, "tanksimd_reply_busy_total")
        t0 = time.time()
        r = requests.get(frame, params={**params, "t": 0.6})  # not cached: a new frame
        took = time.time() - t0
        assert r.status_code == 503 and r.json()["type"].endswith("/problems/busy"), r.text
        assert r.headers.get("Retry-After")
        # refused up front: not drawn (~draw s) and thrown away
        assert took < draw / 3, (took, draw)
        t0 = time.time()
        r = requests.get(f"{daemon.url}/v1/sessions/{sid}/frames",
                         params={"from": 0, "to": 0.5, "fps": 20, "width": 2048, "height": 2048})
        assert r.status_code == 503 and r.json()["type"].endswith("/problems/busy"), r.text
        assert time.time() - t0 < draw / 3
        assert metric(daemon.url, "tanksimd_reply_busy_total") == busy0 + 2
    finally:
        for s in socks:
            s.close()
    wait_released(daemon.url)
    assert requests.get(frame, params={"t": 0.6, "width": 320, "height": 180}).status_code == 200
