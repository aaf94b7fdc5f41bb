"""Answers made whole before sending (a /series page, a spectrum, a PNG) are
held until the client reads them: clients that ask and never read used to
hold one each without bound (20 unread /series answers: RSS 68 MB -> 666 MB).
Now every large held answer counts against a budget of 128 MB; past it the
daemon answers 503 /problems/busy with Retry-After, small answers (health)
go on, and once the held answers are gone the same request succeeds."""
import time

import requests

import conftest
from conftest import ask_unread, read_head, rss_kb, wait_released, wide_session

BUDGET = 128 << 20


def test_unread_answers_are_bounded(daemon):
    sid = wide_session(daemon.url)
    page = requests.get(f"{daemon.url}/v1/sessions/{sid}/series")
    size = len(page.content)
    assert size > 8 << 20
    before = rss_kb(daemon.proc.pid)
    socks = []
    try:
        for _ in range(20):  # 20 x ~10 MB asked for (all at once), never read
            socks.append(ask_unread(daemon, f"/v1/sessions/{sid}/series"))
        heads = [read_head(s) for s in socks]
        statuses = [st for st, _ in heads]
        held = statuses.count(200)
        assert held * size <= BUDGET + size, statuses
        busy = next((h for st, h in heads if st == 503), None)
        assert busy is not None, statuses
        assert b"Retry-After:" in busy and b"/problems/busy" in busy, busy
        t0 = time.time()
        assert requests.get(daemon.url + "/v1/health", timeout=5).status_code == 200
        assert time.time() - t0 < 2
        # the held answers, plus what building them left in the allocator
        if not conftest.SANITIZED:  # ASan's quarantine keeps the freed answers resident
            assert rss_kb(daemon.proc.pid) - before < (BUDGET + 8 * size) >> 10
    finally:
        for s in socks:
            s.close()
    wait_released(daemon.url)
    r = requests.get(f"{daemon.url}/v1/sessions/{sid}/series")
    assert r.status_code == 200 and len(r.content) == size
