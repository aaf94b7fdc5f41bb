"""`make install` and deploy/tanksimd.service (deployment review, session 11):
the unit named /usr/local/bin/tanksimd, a tanksim user and /var/lib/tanksim
that nothing created. Now `make install` puts the programs, the dashboard and
the unit in place (paths rewritten for PREFIX), the unit runs as a transient
user with a StateDirectory, and every flag it passes is one the daemon takes."""
import os
import re
import subprocess

from conftest import REPO, TANKSIMD


def test_make_install_puts_every_file_the_unit_names(tmp_path):
    dest, prefix = tmp_path / "root", "/opt/tanksim"
    out = subprocess.run(["make", "-s", "install", f"DESTDIR={dest}", f"PREFIX={prefix}"],
                         cwd=REPO, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    unit = (dest / "etc/systemd/system/tanksimd.service").read_text()
    exec_start = re.search(r"^ExecStart=(.*)$", unit, re.M).group(1).split()
    assert exec_start[0] == prefix + "/bin/tanksimd"
    for prog in ("tanksimd", "tanksim"):
        assert os.access(dest / ("." + prefix) / "bin" / prog, os.X_OK)
    web_root = exec_start[exec_start.index("--web-root") + 1]
    assert (dest / ("." + web_root) / "index.html").is_file()
    assert (dest / ("." + web_root) / "app.js").is_file()
    # the store: a directory systemd creates for the transient user
    data_dir = exec_start[exec_start.index("--data-dir") + 1]
    assert "DynamicUser=yes" in unit and f"StateDirectory={os.path.basename(data_dir)}" in unit
    assert data_dir == "/var/lib/" + os.path.basename(data_dir)
    # every flag of ExecStart is one the daemon documents
    usage = subprocess.run([TANKSIMD, "--help"], capture_output=True, text=True).stdout
    for flag in (a for a in exec_start[1:] if a.startswith("--")):
        assert flag in usage, flag
    assert "/usr/local" not in unit.split("[Unit]")[1]  # rewritten for PREFIX


def _start(cmd, cwd):
    """Start a daemon; return (process, url) from the line it prints on stdout."""
    p = subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = p.stdout.readline()
    m = re.search(r"open (http://[^/ ]+)/", line)
    if not m:
        p.kill()
        raise AssertionError(f"no URL line: {line!r} {p.stderr.read()!r}")
    return p, m.group(1)


def test_installed_daemon_finds_its_dashboard_and_says_which_port(tmp_path):
    """Deployment audit (session 17): an installed tanksimd started by hand,
    without --web-root, answered / with 404 (it looked only in bin/../web_static);
    --port 0 printed port 0; a user's own PREFIX failed on the unit in /etc."""
    import requests
    prefix = tmp_path / "home" / ".local"  # a user's own prefix, no DESTDIR
    out = subprocess.run(["make", "-s", "install", f"PREFIX={prefix}",
                          "UNITDIR=/proc/tanksim-no-unit-here"],
                         cwd=REPO, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    assert "systemd unit not installed" in out.stdout
    web = prefix / "share/tanksim/web_static"
    assert (web / "app.js.map").is_file()  # app.js names it (sourceMappingURL)
    exe = str(prefix / "bin/tanksimd")
    p, url = _start([exe, "--port", "0", "--data-dir", str(tmp_path / "var")], cwd="/")
    try:
        assert not url.endswith(":0"), url
        r = requests.get(url + "/", timeout=10)
        assert r.status_code == 200 and "text/html" in r.headers["Content-Type"]
        assert requests.get(url + "/static/app.js.map", timeout=10).status_code == 200
    finally:
        p.terminate()
        p.wait(timeout=30)


def test_sighup_stops_the_daemon_cleanly(tmp_path):
    """Deployment audit (session 17): SIGHUP (the terminal of `make run`
    closed) killed the daemon without its shutdown path (exit 129, WAL left)."""
    import signal
    p, url = _start([TANKSIMD, "--port", "0", "--data-dir", str(tmp_path / "var")], cwd=REPO)
    p.send_signal(signal.SIGHUP)
    assert p.wait(timeout=30) == 0
    err = p.stderr.read()
    assert "SIGHUP received, shutting down" in err, err
    assert not (tmp_path / "var" / "tanksimd.db-wal").exists() or \
        (tmp_path / "var" / "tanksimd.db-wal").stat().st_size == 0
