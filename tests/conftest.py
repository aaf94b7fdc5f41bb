"""Shared pytest fixtures: a real tanksimd on a free loopback port.

The binaries come from $TANKSIM_BUILD (set by tests/run_all.sh; default
./build). Each daemon gets its own temporary --data-dir and is stopped with
SIGTERM at the end of the test module.
"""
import os
import signal
import socket
import subprocess
import tempfile
import time

import pytest
import requests

BUILD = os.environ.get("TANKSIM_BUILD", os.path.join(os.path.dirname(__file__), "..", "build"))
TANKSIMD = os.path.join(BUILD, "tanksimd")
TANKSIM = os.path.join(BUILD, "tanksim")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Daemon:
    """A running tanksimd; .url is its base URL, .log its captured stderr."""

    def __init__(self, *extra, data_dir=None):
        self.port = free_port()
        self.data_dir = data_dir or tempfile.mkdtemp(prefix="tanksimd-")
        self.log = tempfile.NamedTemporaryFile(prefix="tanksimd-", suffix=".log", delete=False)
        self.args = [TANKSIMD, "--port", str(self.port), "--data-dir", self.data_dir, *extra]
        self.proc = subprocess.Popen(self.args, stdout=subprocess.PIPE, stderr=self.log, text=True)
        self.url = f"http://127.0.0.1:{self.port}"
        deadline = time.time() + 20
        while time.time() < deadline:
            try:
                requests.get(self.url + "/v1/health", timeout=1)
                return
            except requests.ConnectionError:
                if self.proc.poll() is not None:
                    break
                time.sleep(0.05)
        raise RuntimeError("tanksimd did not start: " + self.stderr())

    def stderr(self):
        with open(self.log.name) as f:
            return f.read()

    def stop(self, sig=signal.SIGTERM, timeout=20):
        if self.proc.poll() is None:
            self.proc.send_signal(sig)
            try:
                self.proc.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        return self.proc.returncode


@pytest.fixture(scope="module")
def daemon():
    d = Daemon()
    yield d
    d.stop()
