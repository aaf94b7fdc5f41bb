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


def daemon_with_nofile(soft, hard):
    """A Daemon started under the open-file limit (soft, hard): set in the
    child only, so this process's own limit is left as it was."""
    cur_hard = resource.getrlimit(resource.RLIMIT_NOFILE)[1]
    if cur_hard != resource.RLIM_INFINITY and hard > cur_hard:
        pytest.skip(f"hard open-file limit {cur_hard} below {hard}")
    return Daemon(preexec_fn=lambda: resource.setrlimit(resource.RLIMIT_NOFILE, (soft, hard)))


def test_more_idle_connections_than_the_old_limit_do_not_lock_others_out():
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    need = 1300
    if soft < need:
        if hard != resource.RLIM_INFINITY and hard < need:
            pytest.skip(f"hard open-file limit {hard} < {need}")
        resource.setrlimit(resource.RLIMIT_NOFILE, (need, hard))
    d = None
    socks = []
    try:
        d = Daemon()
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
        if d:
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
    d = daemon_with_nofile(300, 16384)
    try:  # a socket and a file per connection, 256 for the store
        assert pid_nofile(d.proc.pid) == (2 * 4096 + 256, 16384)
        assert "open-file limit" not in d.stderr()
    finally:
        d.stop()


def test_a_hard_limit_too_low_lowers_the_connection_count_and_says_so():
    d = daemon_with_nofile(512, 512)
    try:
        assert pid_nofile(d.proc.pid) == (512, 512)
        assert "at most 128 connections, not 4096" in d.stderr()
        assert requests.get(d.url + "/v1/health", timeout=5).status_code == 200
    finally:
        d.stop()


def test_a_limit_below_the_reserve_is_refused():
    with pytest.raises(RuntimeError, match="at least 288 needed"):
        daemon_with_nofile(200, 200)
