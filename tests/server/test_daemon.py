"""tanksimd foundation behaviour (issue 2): flags, health, problem+json 404,
request log lines, clean shutdown on SIGTERM and SIGINT."""
import os
import signal
import socket
import subprocess
import time

import pytest
import requests

from conftest import TANKSIMD, Daemon


def test_health_reports_ok_and_version(daemon):
    r = requests.get(daemon.url + "/v1/health")
    assert r.status_code == 200
    assert r.headers["Content-Type"].startswith("application/json")
    body = r.json()
    assert body["status"] == "ok"
    assert body["version"].count(".") == 2


def test_unknown_path_is_problem_json_404(daemon):
    r = requests.get(daemon.url + "/nope")
    assert r.status_code == 404
    assert r.headers["Content-Type"] == "application/problem+json"
    p = r.json()
    assert p["status"] == 404
    assert p["title"] and p["type"] and "/nope" in p["detail"]


def test_wrong_method_is_405(daemon):
    r = requests.delete(daemon.url + "/v1/health")
    assert r.status_code == 405
    assert r.json()["status"] == 405


def test_one_log_line_per_request(daemon):
    requests.get(daemon.url + "/v1/health?probe=log")
    requests.get(daemon.url + "/nope-logged")
    # The line is written when libmicrohttpd reports the request complete, which
    # can come a moment after the client has read the response: wait for it.
    deadline = time.time() + 5
    while True:
        lines = [l for l in daemon.stderr().splitlines() if "/nope-logged" in l]
        if lines or time.time() > deadline:
            break
        time.sleep(0.02)
    time.sleep(0.2)  # and make sure no second line follows
    lines = [l for l in daemon.stderr().splitlines() if "/nope-logged" in l]
    assert len(lines) == 1 and " 404 " in lines[0]


def test_sigterm_and_sigint_shut_down_cleanly():
    for sig in (signal.SIGTERM, signal.SIGINT):
        d = Daemon()
        assert requests.get(d.url + "/v1/health").ok
        assert d.stop(sig) == 0
        assert "shutting down" in d.stderr()


@pytest.mark.parametrize("flag,value", [
    ("--port", "99999"), ("--max-step", "0"), ("--drain", "-1"), ("--max-run-wall", "-1"),
    ("--max-run-wall", "x"), ("--client-files", "maybe"),
    # numbers are read as written in decimal, as query values and CLI options
    # are: before session 21 " 2" started 2 workers, "" was 0 and seconds took
    # hex ("0x10" = 16) and leading blanks
    ("--threads", " 2"), ("--threads", ""), ("--threads", "2.5"), ("--port", ""),
    ("--max-step", "0x10"), ("--drain", " 1")])
def test_bad_flag_value_is_refused_naming_the_flag(flag, value, tmp_path):
    out = subprocess.run([TANKSIMD, flag, value, "--data-dir", str(tmp_path)],
                         capture_output=True, text=True, timeout=20)
    assert out.returncode == 2 and flag in out.stderr, out.stderr


def test_help_version_and_bad_flags(tmp_path):
    out = subprocess.run([TANKSIMD, "--help"], capture_output=True, text=True)
    assert out.returncode == 0 and "--data-dir" in out.stdout and "--threads" in out.stdout
    out = subprocess.run([TANKSIMD, "--version"], capture_output=True, text=True)
    assert out.returncode == 0 and out.stdout.startswith("tanksimd ")
    out = subprocess.run([TANKSIMD, "--bogus", "1"], capture_output=True, text=True)
    assert out.returncode == 2 and "unknown option" in out.stderr
    # a --data-dir of its own: the default ./var is `make run`'s store, which
    # this test must neither create nor find locked by a running `make run`
    out = subprocess.run([TANKSIMD, "--bind", "not-an-ip", "--port", "0",
                          "--data-dir", str(tmp_path / "store")],
                         capture_output=True, text=True, timeout=10)
    assert out.returncode == 1 and "--bind" in out.stderr


def test_failed_start_leaves_no_store(tmp_path):
    # Found by a review: `--bind not-an-ip` or a port in use exited 1 but left
    # DIR/tanksimd.db and DIR/tanksimd.lock (and DIR itself) behind: the store
    # was created and locked before the address was checked and bound. And
    # libmicrohttpd printed its own "Failed to bind to port N" first.
    store = tmp_path / "a" / "b"
    out = subprocess.run([TANKSIMD, "--bind", "not-an-ip", "--port", "0", "--data-dir", str(store)],
                         capture_output=True, text=True, timeout=10)
    assert out.returncode == 1, out
    assert out.stderr == "tanksimd: --bind: 'not-an-ip' is not an IPv4 or IPv6 address\n", out
    assert not (tmp_path / "a").exists()
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen(1)
        port = busy.getsockname()[1]
        out = subprocess.run([TANKSIMD, "--bind", "127.0.0.1", "--port", str(port),
                              "--data-dir", str(store)], capture_output=True, text=True, timeout=10)
    assert out.returncode == 1, out
    assert out.stderr == ("tanksimd: cannot listen on 127.0.0.1 port %d: Address already in use\n"
                          % port), out  # the daemon's one line, not libmicrohttpd's too
    assert not (tmp_path / "a").exists()
    # an existing store is left as it was: no lock file, no database added
    store.mkdir(parents=True)
    out = subprocess.run([TANKSIMD, "--bind", "256.1.1.1", "--data-dir", str(store)],
                         capture_output=True, text=True, timeout=10)
    assert out.returncode == 1 and "--bind" in out.stderr, out
    assert os.listdir(store) == []
    # a start that succeeds makes it there
    d = Daemon(data_dir=str(store))
    try:
        assert requests.get(d.url + "/v1/health", timeout=5).status_code == 200
        assert {"tanksimd.db", "tanksimd.lock"} <= set(os.listdir(store))
    finally:
        d.stop()


def test_port_zero_reports_the_port_it_serves(tmp_path):
    # the socket is bound by tanksimd itself (before the store), so the port the
    # kernel chose comes from it, not from libmicrohttpd
    p = subprocess.Popen([TANKSIMD, "--port", "0", "--data-dir", str(tmp_path)],
                         stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        line = p.stdout.readline()
        assert line.startswith("tanksimd: open http://127.0.0.1:"), line
        port = int(line.split("http://127.0.0.1:")[1].split("/")[0])
        assert port > 0
        assert requests.get("http://127.0.0.1:%d/v1/health" % port, timeout=5).status_code == 200
    finally:
        p.terminate()
        p.wait(timeout=20)


def test_second_daemon_on_one_data_dir_is_refused_before_touching_it(tmp_path):
    # Found by a deployment review (session 11): a second `make run` opened the
    # first one's store, marked its running session `interrupted` and only then
    # failed to bind; on another port it advanced the same session too.
    first = Daemon(data_dir=str(tmp_path))
    try:
        r = requests.post(first.url + "/v1/sessions", json={"preset": "pointmass-prescribed"})
        assert r.status_code == 201
        second = subprocess.run([TANKSIMD, "--port", "0", "--data-dir", str(tmp_path)],
                                capture_output=True, text=True, timeout=20)
        assert second.returncode == 1, second
        assert "in use by another tanksimd (pid %d)" % first.proc.pid in second.stderr, second
        s = requests.get(first.url + "/v1/sessions/" + r.json()["id"]).json()
        assert s["status"] == "created", s
    finally:
        first.stop()
    # the lock goes with the process: the directory serves again
    again = Daemon(data_dir=str(tmp_path))
    again.stop()


@pytest.mark.parametrize("how", ["file", "env"])
def test_token_from_a_file_or_the_environment(tmp_path, how, monkeypatch):
    # --token T shows in /proc/PID/cmdline to every local user; a file or the
    # environment (/proc/PID/environ is the owner's) keeps it private
    if how == "file":
        f = tmp_path / "token"
        f.write_text("s3cret\n")
        d = Daemon("--token-file", str(f))
    else:
        monkeypatch.setenv("TANKSIM_TOKEN", "s3cret")
        d = Daemon()
    try:
        assert requests.get(d.url + "/v1/sessions").status_code == 401
        ok = requests.get(d.url + "/v1/sessions", headers={"Authorization": "Bearer s3cret"})
        assert ok.status_code == 200
        assert "s3cret" not in open("/proc/%d/cmdline" % d.proc.pid).read()
    finally:
        d.stop()


def test_empty_token_file_is_refused(tmp_path):
    f = tmp_path / "token"
    f.write_text("\n")
    out = subprocess.run([TANKSIMD, "--token-file", str(f), "--data-dir", str(tmp_path)],
                         capture_output=True, text=True, timeout=20)
    assert out.returncode == 2 and "--token-file" in out.stderr, out
