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
import threading
import time

import pytest
import requests

BUILD = os.environ.get("TANKSIM_BUILD", os.path.join(os.path.dirname(__file__), "..", "build"))
TANKSIMD = os.path.join(BUILD, "tanksimd")
TANKSIM = os.path.join(BUILD, "tanksim")


def _sanitized(path):
    """Whether the binary at path is built with ASan or TSan (make asan / tsan):
    their allocators keep freed memory (quarantine, shadow), so a test of the
    daemon's resident size measures the sanitizer, not the daemon."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError:
        return False
    return b"__asan_init" in data or b"__tsan_init" in data


SANITIZED = _sanitized(TANKSIMD)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Daemon:
    """A running tanksimd; .url is its base URL, .log its captured stderr."""

    def __init__(self, *extra, data_dir=None, preexec_fn=None):
        """preexec_fn: run in the child before tanksimd (e.g. its own limits)."""
        self.port = free_port()
        self.data_dir = data_dir or tempfile.mkdtemp(prefix="tanksimd-")
        self.log = tempfile.NamedTemporaryFile(prefix="tanksimd-", suffix=".log", delete=False)
        self.args = [TANKSIMD, "--port", str(self.port), "--data-dir", self.data_dir, *extra]
        self.proc = subprocess.Popen(self.args, stdout=subprocess.PIPE, stderr=self.log, text=True,
                                     preexec_fn=preexec_fn)
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

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop()

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


# ---- helpers for the daemon API tests (tests/server/) ----------------------

REPO = os.path.join(os.path.dirname(__file__), "..")
BASE_PRESET = "pointmass-prescribed"  # the foundation's preset; every build has it


def stepped_session(url, preset=BASE_PRESET, step=0.5, sample_rate=50, duration=1.0):
    """Create a session of preset (a `duration`-s run, `sample_rate`-Hz samples;
    1 s at 50 Hz unless told), step it `step` s; its id."""
    r = requests.post(url + "/v1/sessions",
                      json={"preset": preset, "run": {"duration": duration, "sample_rate": sample_rate}})
    assert r.status_code == 201, r.text
    s = r.json()["id"]
    r = requests.post(f"{url}/v1/sessions/{s}/step", json={"duration": step}, timeout=120)
    assert r.status_code == 200, r.text
    return s


def wide_session(url):
    """A session of 20001 rows x 65 channels (bump-coupled-rack90, 1 s at 20 kHz:
    ~0.4 s to make); its id."""
    return stepped_session(url, "bump-coupled-rack90", step=1, sample_rate=20000, duration=1)


def metric(url, name):
    """The value of the unlabelled metric name in GET /metrics."""
    for line in requests.get(url + "/metrics", timeout=10).text.splitlines():
        if line.startswith(name + " "):
            return float(line.split()[1])
    raise AssertionError(f"no {name} in /metrics")


def wait_metric(url, name, value, timeout=20):
    """Poll GET /metrics until name equals value (e.g. tanksimd_jobs_pending: the
    worker-pool jobs queued or running, to know requests wait on the pool)."""
    deadline = time.time() + timeout
    while time.time() < deadline:
        if metric(url, name) == value:
            return
        time.sleep(0.02)
    raise AssertionError(f"{name} is {metric(url, name)}, not {value}, after {timeout} s")


def ask_unread(d, path):
    """Send GET path to daemon d on a socket whose answer is never read
    past its head (a small receive buffer); the socket."""
    s = socket.create_connection(("127.0.0.1", d.port))
    s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    s.sendall(f"GET {path} HTTP/1.1\r\nHost: x\r\n\r\n".encode())
    return s


def read_head(s):
    """The status and head (bytes) of the answer on socket s of ask_unread."""
    s.settimeout(10)
    head = b""
    while b"\r\n\r\n" not in head:
        chunk = s.recv(1024)
        assert chunk
        head += chunk
    return int(head.split()[1]), head


def unread(d, path):
    """Ask daemon d for path on a socket that is never read: (socket, status)."""
    s = ask_unread(d, path)
    return s, read_head(s)[0]


def wait_released(url):
    """Wait until no answer is held for an unread client (the held answers go
    with their connections)."""
    deadline = time.time() + 5
    while metric(url, "tanksimd_reply_held_bytes") != 0 and time.time() < deadline:
        time.sleep(0.05)
    assert metric(url, "tanksimd_reply_held_bytes") == 0


def rss_kb(pid):
    """Resident size of process pid [kB]."""
    with open(f"/proc/{pid}/status") as f:
        return int(f.read().split("VmRSS:")[1].split()[0])


@pytest.fixture(scope="module")
def sid(daemon):
    """A point-mass session with 0.5 s of stored samples, shared by a module's tests
    (a module may define its own `sid` instead)."""
    return stepped_session(daemon.url)


def preset_names():
    """Names of the shipped presets, from the source tree (the daemon embeds the same files)."""
    d = os.path.join(REPO, "sim", "data", "presets")
    return sorted(f[:-5] for f in os.listdir(d) if f.endswith(".json"))


def is_problem(r, status, pointer=None):
    """Assert r is an RFC 9457 problem with this status (and an errors entry for pointer)."""
    assert r.status_code == status, (r.status_code, r.text)
    assert r.headers["Content-Type"] == "application/problem+json", r.headers
    p = r.json()
    assert p["status"] == status and p["title"] and p["type"] and "detail" in p
    if pointer is not None:
        pointers = [e["pointer"] for e in p.get("errors", [])]
        assert pointer in pointers, (pointer, p)
    return p


def step_in_background(url, sid, duration, out=None):
    """Start POST .../step {duration} on a thread (its response in out["r"],
    a connection cut by a killed daemon ignored) and wait until the session's
    first batch is stored or the step ended; the thread."""
    def step():
        try:
            r = requests.post(f"{url}/v1/sessions/{sid}/step", json={"duration": duration},
                              timeout=120)
            if out is not None:
                out["r"] = r
        except requests.ConnectionError:
            pass  # the kill cuts the reply
    th = threading.Thread(target=step)
    th.start()
    deadline = time.time() + 60
    while time.time() < deadline and th.is_alive():
        if requests.get(f"{url}/v1/sessions/{sid}").json()["index"] > 0:
            break
        time.sleep(0.01)
    return th


def wait_op(url, op_id, timeout=30, seen=None):
    """Poll an operation until done; appends each metadata to seen (list)."""
    deadline = time.time() + timeout
    while time.time() < deadline:
        op = requests.get(f"{url}/v1/operations/{op_id}", timeout=10).json()
        if seen is not None:
            seen.append(op["metadata"])
        if op["done"]:
            return op
        time.sleep(0.02)
    raise AssertionError(f"operation {op_id} not done after {timeout} s")


def sse_events(resp, stop_after=None):
    """Parse a text/event-stream response (or a list of the lines read from one
    before it was cut) into [(event, id, data_str)]; stop after stop_after
    sample events (then the caller closes the connection)."""
    events, ev, eid, data = [], None, None, []
    lines = resp + [""] if isinstance(resp, list) else resp.iter_lines(decode_unicode=True)
    for raw in lines:
        line = raw if raw is not None else ""
        if line == "":
            if data or ev:
                events.append((ev or "message", eid, "\n".join(data)))
                if stop_after is not None and sum(e[0] == "sample" for e in events) >= stop_after:
                    return events
            ev, eid, data = None, None, []
            continue
        if line.startswith(":"):
            continue
        field, _, value = line.partition(":")
        value = value[1:] if value.startswith(" ") else value
        if field == "event":
            ev = value
        elif field == "id":
            eid = value
        elif field == "data":
            data.append(value)
    return events
