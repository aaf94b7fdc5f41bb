"""How many HTTP connections the daemon holds, and the open-file limit.

Found in session 17's audit: ~1016 idle connections locked every other client
out until the idle timeout (60 s), because libmicrohttpd's default connection
limit is FD_SETSIZE - 4 even with epoll. Now the limit is --max-connections
(default 4096; more wait in the listen queue) and the daemon fits the open-file limit to it: it raises the
soft limit up to the hard one, else lowers the connection count and says so,
keeping descriptors for the store and the dashboard's files.
"""
import resource
import socket
import time

import pytest
import requests

from conftest import Daemon


def pid_nofile(pid):
    with open(f"/proc/{pid}/limits") as f:
        for line in f:
            if line.startswith("Max open files"):
                soft, hard = line.split()[3:5]
                return int(soft), int(hard)
    raise AssertionError("no open-files line")


class LimitNofile:
    """This process's open-file limit for the children started inside."""

    def __init__(self, soft, hard=None):
        self.new = (soft, hard if hard is not None else resource.getrlimit(resource.RLIMIT_NOFILE)[1])

    def __enter__(self):
        self.old = resource.getrlimit(resource.RLIMIT_NOFILE)
        if self.new[1] > self.old[1] and self.old[1] != resource.RLIM_INFINITY:
            pytest.skip(f"hard open-file limit {self.old[1]} below {self.new[1]}")
        # soft first, so it never exceeds the (possibly lowered) hard limit
        resource.setrlimit(resource.RLIMIT_NOFILE, (min(self.new[0], self.old[0]), self.old[1]))
        resource.setrlimit(resource.RLIMIT_NOFILE, self.new)

    def __exit__(self, *exc):
        resource.setrlimit(resource.RLIMIT_NOFILE, (self.new[0], self.new[1]))
        if self.old[1] == resource.RLIM_INFINITY or self.old[1] <= self.new[1]:
            resource.setrlimit(resource.RLIMIT_NOFILE, self.old)


def test_more_idle_connections_than_the_old_limit_do_not_lock_others_out():
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    need = 1300
    if soft < need:
        if hard != resource.RLIM_INFINITY and hard < need:
            pytest.skip(f"hard open-file limit {hard} < {need}")
        resource.setrlimit(resource.RLIMIT_NOFILE, (need, hard))
    d = Daemon()
    socks = []
    try:
        for _ in range(1100):  # idle: connected, nothing sent
            s = socket.create_connection(("127.0.0.1", d.port))
            socks.append(s)
        time.sleep(0.3)
        t0 = time.time()
        r = requests.get(d.url + "/v1/health", timeout=5)
        assert r.status_code == 200 and time.time() - t0 < 2
    finally:
        for s in socks:
            s.close()
        d.stop()
        resource.setrlimit(resource.RLIMIT_NOFILE, (soft, hard))


def test_connections_past_the_limit_wait_until_one_is_free():
    d = Daemon("--max-connections", "20")
    socks = []
    try:
        for _ in range(20):
            socks.append(socket.create_connection(("127.0.0.1", d.port)))
        time.sleep(0.3)
        # the 21st waits in the listen queue: no answer while 20 are open
        with pytest.raises(requests.exceptions.ReadTimeout):
            requests.get(d.url + "/v1/health", timeout=1)
        socks.pop().close()
        assert requests.get(d.url + "/v1/health", timeout=5).status_code == 200
    finally:
        for s in socks:
            s.close()
        d.stop()


def test_soft_open_file_limit_is_raised_to_fit():
    with LimitNofile(300, 8192):
        d = Daemon()
    try:
        assert pid_nofile(d.proc.pid) == (4096 + 256, 8192)
        assert "open-file limit" not in d.stderr()
    finally:
        d.stop()


def test_a_hard_limit_too_low_lowers_the_connection_count_and_says_so():
    with LimitNofile(512, 512):
        d = Daemon()
    try:
        assert pid_nofile(d.proc.pid) == (512, 512)
        assert "at most 256 connections, not 4096" in d.stderr()
        assert requests.get(d.url + "/v1/health", timeout=5).status_code == 200
    finally:
        d.stop()


def test_a_limit_below_the_reserve_is_refused():
    with LimitNofile(200, 200):
        d = None
        with pytest.raises(RuntimeError, match="at least 272 needed"):
            d = Daemon()
    assert d is None
