"""Answers made whole before sending (a /series page, a spectrum, a PNG) are
held until the client reads them: clients that ask and never read used to
hold one each without bound (20 unread /series answers: RSS 68 MB -> 666 MB).
Now every large held answer counts against a budget of 128 MB; past it the
daemon answers 503 /problems/busy with Retry-After, small answers (health)
go on, and once the held answers are gone the same request succeeds."""
import socket
import time

import pytest
import requests

import conftest
from conftest import Daemon

BUDGET = 128 << 20


@pytest.fixture(scope="module")
def d():
    dm = Daemon()
    yield dm
    dm.stop()


def rss_kb(pid):
    with open(f"/proc/{pid}/status") as f:
        return int(f.read().split("VmRSS:")[1].split()[0])


def test_unread_answers_are_bounded(d):
    r = requests.post(d.url + "/v1/sessions",
                      json={"preset": "bump-coupled-rack90", "run": {"sample_rate": 20000, "duration": 1}})
    sid = r.json()["id"]
    assert requests.post(f"{d.url}/v1/sessions/{sid}/step", json={"duration": 1}).status_code == 200
    page = requests.get(f"{d.url}/v1/sessions/{sid}/series")
    size = len(page.content)
    assert size > 8 << 20
    before = rss_kb(d.proc.pid)
    socks = []
    try:
        for _ in range(20):  # 20 x ~10 MB asked for, never read
            s = socket.create_connection(("127.0.0.1", d.port))
            s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
            s.sendall(f"GET /v1/sessions/{sid}/series HTTP/1.1\r\nHost: x\r\n\r\n".encode())
            socks.append(s)
        statuses, busy = [], None
        for s in socks:
            s.settimeout(10)
            head = b""
            while b"\r\n\r\n" not in head:
                chunk = s.recv(1024)
                assert chunk
                head += chunk
            statuses.append(int(head.split()[1]))
            if statuses[-1] == 503 and busy is None:
                busy = head
        held = statuses.count(200)
        assert held * size <= BUDGET + size, statuses
        assert busy is not None, statuses
        assert b"Retry-After:" in busy and b"/problems/busy" in busy, busy
        t0 = time.time()
        assert requests.get(d.url + "/v1/health", timeout=5).status_code == 200
        assert time.time() - t0 < 2
        # the held answers, plus what building them left in the allocator
        if not conftest.SANITIZED:  # ASan's quarantine keeps the freed answers resident
            assert rss_kb(d.proc.pid) - before < (BUDGET + 8 * size) >> 10
    finally:
        for s in socks:
            s.close()
    deadline = time.time() + 5  # the held answers go with their connections
    while time.time() < deadline:
        r = requests.get(f"{d.url}/v1/sessions/{sid}/series")
        if r.status_code == 200:
            break
        time.sleep(0.1)
    assert r.status_code == 200 and len(r.content) == size
