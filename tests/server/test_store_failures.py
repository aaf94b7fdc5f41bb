"""What the store keeps when the daemon dies or the disk fills (session 16).

Found by an audit of crash safety, each reproduced before the fix:
- a session deleted while it ran (DELETE answered 204) came back after a
  kill -9, with its rows: the rows were left for the worker to remove;
- a run whose batch the store refused (a full disk) left the session
  `failed` for good, though its stored rows and state were consistent:
  now it is paused at its last stored row and goes on once there is room;
- an engine map started while the store could not write it was answered 202,
  ran in memory and was gone after a restart: now refused (nothing started);
- (session 26) a full disk is said as such: 507 /problems/store-full naming
  the data directory, google.rpc 8 RESOURCE_EXHAUSTED in an operation, where
  it was the 500 /problems/io of any failing store ("full or failing");
- a store written by a newer build (PRAGMA user_version) was opened as if
  it were this build's.
The full-disk cases need a small tmpfs (root and mount rights); they are
skipped where it cannot be mounted.
"""
import os
import shutil
import signal
import sqlite3
import subprocess
import tempfile
import threading
import time

import pytest
import requests

from conftest import TANKSIMD, Daemon, free_port, wait_op


def test_delete_of_a_running_session_holds_through_kill_9(tmp_path):
    d = Daemon(data_dir=str(tmp_path))
    try:
        sid = requests.post(d.url + "/v1/sessions", json={"preset": "bump-prescribed-coupled"}).json()["id"]
        op = requests.post(f"{d.url}/v1/sessions/{sid}/run", json={"real_time_factor": 5}).json()
        while requests.get(f"{d.url}/v1/operations/{op['id']}").json()["metadata"]["t"] < 0.5:
            time.sleep(0.05)
        assert requests.delete(f"{d.url}/v1/sessions/{sid}").status_code == 204
        d.stop(sig=signal.SIGKILL)  # at once: before the worker removes the rows
    finally:
        d.stop()
    d2 = Daemon(data_dir=str(tmp_path))
    try:
        assert requests.get(f"{d2.url}/v1/sessions/{sid}").status_code == 404
        assert all(s["id"] != sid for s in requests.get(d2.url + "/v1/sessions").json()["sessions"])
    finally:
        d2.stop()
    db = sqlite3.connect(str(tmp_path / "tanksimd.db"))
    try:  # and nothing of it is left in the store
        assert db.execute("SELECT count(*) FROM sessions").fetchone()[0] == 0
        assert db.execute("SELECT count(*) FROM samples").fetchone()[0] == 0
        assert db.execute("SELECT count(*) FROM snapshots").fetchone()[0] == 0
    finally:
        db.close()


def test_store_from_a_newer_build_is_refused(tmp_path):
    Daemon(data_dir=str(tmp_path)).stop()
    db = sqlite3.connect(str(tmp_path / "tanksimd.db"))
    assert db.execute("PRAGMA user_version").fetchone()[0] == 2
    db.execute("PRAGMA user_version=99")
    db.execute("DROP TABLE analyses")   # say the newer schema has none
    db.commit()
    db.close()
    p = subprocess.run([TANKSIMD, "--port", str(free_port()), "--data-dir", str(tmp_path)],
                       capture_output=True, text=True, timeout=30)
    assert p.returncode != 0
    assert "newer tanksimd" in p.stderr and "schema 99" in p.stderr, p.stderr
    # refused before anything was written: this build's CREATE TABLE IF NOT EXISTS ran first
    db = sqlite3.connect(str(tmp_path / "tanksimd.db"))
    try:
        names = [r[0] for r in db.execute("SELECT name FROM sqlite_master WHERE type='table'")]
        assert "analyses" not in names, names
    finally:
        db.close()


@pytest.fixture
def small_store(tmp_path):
    """A 1-MiB tmpfs as --data-dir (skipped where it cannot be mounted)."""
    mnt = tmp_path / "small"
    mnt.mkdir()
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m", "tmpfs", str(mnt)],
                       capture_output=True, text=True)
    if r.returncode != 0:
        pytest.skip("cannot mount a tmpfs here: " + r.stderr.strip())
    try:
        yield mnt
    finally:
        subprocess.run(["umount", "-l", str(mnt)], capture_output=True)


def fill(mnt):
    """Take every free byte of the mount."""
    fd = os.open(mnt / "filler", os.O_WRONLY | os.O_CREAT)
    try:
        while os.write(fd, b"\0" * 4096) > 0:
            pass
    except OSError:
        pass
    os.close(fd)


def test_analysis_the_store_cannot_hold_is_not_started(small_store):
    d = Daemon(data_dir=str(small_store))
    try:
        fill(small_store)
        body = {"preset": "engine-map-conventional", "engine": {"fidelity": "map"}}
        r = requests.post(d.url + "/v1/engine-map", json=body)
        assert r.status_code == 507 and r.json()["type"] == "/problems/store-full", r.text
        assert "not started" in r.json()["detail"] and str(small_store) + ") is full" in r.text
        assert requests.get(d.url + "/v1/analyses").json()["analyses"] == []
        r = requests.post(d.url + "/v1/sessions", json={"preset": "pointmass-prescribed"})
        assert r.status_code == 507 and "cannot store the session" in r.json()["detail"], r.text
        assert requests.get(d.url + "/v1/health").status_code == 200  # still serving
        os.remove(small_store / "filler")
        r = requests.post(d.url + "/v1/engine-map", json=body)
        assert r.status_code == 202, r.text
        done = wait_op(d.url, r.json()["id"], timeout=60)
        assert done["done"] and "error" not in done, done
        assert [a["id"] for a in requests.get(d.url + "/v1/analyses").json()["analyses"]] == [done["id"]]
    finally:
        d.stop()


def test_analysis_whose_progress_the_store_refuses_ends_with_an_io_error(small_store):
    """Session 25 probe: a crank-angle engine map during which the disk
    filled was shown done with its full response while the store kept its
    row of part 3 of 14; after a restart the map was gone and said "the
    daemon stopped". A progress row the store refuses now stops the analysis
    with an I/O error naming the cause."""
    d = Daemon(data_dir=str(small_store))
    try:
        r = requests.post(d.url + "/v1/engine-map", json={"preset": "engine-map-conventional"})
        assert r.status_code == 202, r.text
        op_id = r.json()["id"]
        deadline = time.time() + 60
        while requests.get(f"{d.url}/v1/operations/{op_id}").json()["metadata"]["parts_done"] < 1:
            assert time.time() < deadline
            time.sleep(0.05)
        fill(small_store)
        done = wait_op(d.url, op_id, timeout=120)
        assert "response" not in done, done
        err = done["error"]
        assert err["code"] == 8 and err["status"] == 507, err  # RESOURCE_EXHAUSTED
        assert "store refused its progress" in err["message"] and ") is full" in err["message"]
        assert done["metadata"]["parts_done"] < done["metadata"]["parts_total"], done
        assert requests.get(d.url + "/v1/health").status_code == 200
    finally:
        d.stop()


def test_full_store_pauses_the_run_at_its_last_stored_row_then_it_goes_on(small_store):
    d = Daemon(data_dir=str(small_store))
    try:
        # 20 kHz of 10 s: ~200,000 rows, far more than 1 MiB holds
        r = requests.post(d.url + "/v1/sessions", json={"preset": "pointmass-prescribed",
                                                         "run": {"duration": 10, "sample_rate": 20000}})
        assert r.status_code == 201, r.text
        sid = r.json()["id"]
        op = requests.post(f"{d.url}/v1/sessions/{sid}/run", json={}).json()
        final = wait_op(d.url, op["id"], timeout=60)
        assert final["error"]["status"] == 507 and final["error"]["code"] == 8, final
        s = requests.get(f"{d.url}/v1/sessions/{sid}").json()
        assert s["status"] == "paused", s
        assert "last stored row" in s["error"], s
        stored = requests.get(f"{d.url}/v1/sessions/{sid}/series",
                              params={"channels": "vehicle.speed"}).json()
        assert stored["count"] == s["index"] + 1 and stored["index"][-1] == s["index"]
        t_stop = s["t"]
        assert 0 < t_stop < 10
        # room again: the session goes on from its last stored row, no gap
        subprocess.run(["mount", "-o", "remount,size=64m", str(small_store)], check=True)
        r = requests.post(f"{d.url}/v1/sessions/{sid}/step", json={"duration": 0.01})
        assert r.status_code == 200, r.text
        assert r.json()["t"] == pytest.approx(t_stop + 0.01, abs=1e-9)
        after = requests.get(f"{d.url}/v1/sessions/{sid}/series",
                             params={"channels": "vehicle.speed", "from": t_stop - 0.001}).json()
        idx = after["index"]
        assert idx[0] <= s["index"] and idx[-1] == s["index"] + 200, (idx[:3], idx[-3:])
        assert idx == list(range(idx[0], idx[-1] + 1))  # no gap, no duplicate
    finally:
        d.stop()


def test_delete_the_store_cannot_record_keeps_the_session(tmp_path):
    """A DELETE whose mark the store refuses (another writer holds its lock
    past the 5-s busy timeout) was answered 204 with the session gone from
    the daemon but whole in the store: it came back at the next start. Now
    nothing is deleted and the answer says so; once the store writes again
    the DELETE goes through."""
    d = Daemon(data_dir=str(tmp_path))
    try:
        sid = requests.post(d.url + "/v1/sessions", json={"preset": "pointmass-prescribed"}).json()["id"]
        other = requests.post(d.url + "/v1/sessions", json={"preset": "pointmass-prescribed"}).json()["id"]
        assert requests.post(f"{d.url}/v1/sessions/{sid}/step", json={"duration": 0.1}).status_code == 200
        db = sqlite3.connect(str(tmp_path / "tanksimd.db"), isolation_level=None)
        box = {}
        try:
            db.execute("BEGIN IMMEDIATE")  # the write lock, held
            t = threading.Thread(target=lambda: box.update(r=requests.delete(f"{d.url}/v1/sessions/{sid}", timeout=30)))
            t.start()
            time.sleep(0.5)
            # the DELETE waits for the store outside the session's lock: the
            # list and other sessions answer meanwhile (they waited 4-5 s)
            for url in (f"{d.url}/v1/sessions", f"{d.url}/v1/sessions/{other}", f"{d.url}/v1/sessions/{sid}"):
                t0 = time.time()
                assert requests.get(url, timeout=10).status_code == 200
                assert time.time() - t0 < 1.0, (url, time.time() - t0)
            # and the DELETE was waiting all along (else the checks above proved nothing)
            assert t.is_alive()
            t.join(30)
            db.execute("ROLLBACK")
        finally:
            db.close()
        r = box["r"]
        assert r.status_code == 500 and r.json()["type"].endswith("/problems/io"), r.text
        assert "is kept" in r.json()["detail"]
        s = requests.get(f"{d.url}/v1/sessions/{sid}")
        assert s.status_code == 200 and s.json()["status"] == "paused", s.text
        assert requests.post(f"{d.url}/v1/sessions/{sid}/step", json={"duration": 0.1}).status_code == 200
        assert requests.delete(f"{d.url}/v1/sessions/{sid}").status_code == 204
        assert requests.get(f"{d.url}/v1/sessions/{sid}").status_code == 404
    finally:
        d.stop()
    d2 = Daemon(data_dir=str(tmp_path))
    try:
        assert requests.get(f"{d2.url}/v1/sessions/{sid}").status_code == 404
    finally:
        d2.stop()


def test_store_this_user_cannot_write_is_refused_at_start(tmp_path):
    """Session 25 probe: a store the daemon's user could only read started as
    healthy (/v1/health ok, reads served) and answered every step and create
    with 500 "the store is full or failing". It is refused at start, naming
    the file and what to change. Run as nobody (root writes through 0444);
    skipped where nobody cannot run this build."""
    probe = subprocess.run(["setpriv", "--reuid=nobody", "--regid=nogroup", "--clear-groups",
                            TANKSIMD, "--help"], capture_output=True, text=True)
    if probe.returncode != 0:
        pytest.skip("nobody cannot run this build here: " + probe.stderr.strip()[:200])
    Daemon(data_dir=str(tmp_path)).stop()  # a store with its schema
    store = tempfile.mkdtemp(prefix="tanksim-ro-")  # pytest's tmp_path is root's alone
    try:
        shutil.copy(tmp_path / "tanksimd.db", store)
        os.chmod(store, 0o777)
        os.chmod(os.path.join(store, "tanksimd.db"), 0o444)
        p = subprocess.run(["setpriv", "--reuid=nobody", "--regid=nogroup", "--clear-groups",
                            TANKSIMD, "--port", str(free_port()), "--data-dir", store],
                           capture_output=True, text=True, timeout=30)
        assert p.returncode == 1, p.stderr
        assert "tanksimd.db cannot be written" in p.stderr and "write access" in p.stderr, p.stderr
    finally:
        shutil.rmtree(store, ignore_errors=True)


def test_damaged_store_start_up_says_what_to_do(tmp_path):
    """Session 25 probe: a truncated store stopped the daemon with SQLite's
    "database disk image is malformed" alone."""
    Daemon(data_dir=str(tmp_path)).stop()
    db = tmp_path / "tanksimd.db"
    with open(db, "r+b") as f:
        f.seek(0)
        f.write(b"not a database header, not at all" * 3)
    p = subprocess.run([TANKSIMD, "--port", str(free_port()), "--data-dir", str(tmp_path)],
                       capture_output=True, text=True, timeout=30)
    assert p.returncode == 1, p.stderr
    assert "tanksimd.db" in p.stderr and ".recover" in p.stderr and "aside" in p.stderr, p.stderr


def test_a_store_that_fails_for_another_reason_is_not_called_full(tmp_path):
    """The other branch of tsd_err_store: rows refused for a reason other than
    a full disk (here an SQLite trigger, RAISE(ABORT)) are a 500 /problems/io
    pointing at the daemon log, the session paused at its last stored row."""
    d = Daemon(data_dir=str(tmp_path))
    try:
        sid = requests.post(d.url + "/v1/sessions", json={"preset": "pointmass-prescribed"}).json()["id"]
        db = sqlite3.connect(str(tmp_path / "tanksimd.db"))
        db.execute("CREATE TRIGGER refuse_rows BEFORE INSERT ON samples "
                   "BEGIN SELECT RAISE(ABORT, 'refused by the test'); END")
        db.commit()
        db.close()
        r = requests.post(f"{d.url}/v1/sessions/{sid}/step", json={"duration": 0.1})
        assert r.status_code == 500 and r.json()["type"] == "/problems/io", r.text
        assert "the store is failing (see the daemon log)" in r.json()["detail"], r.text
        assert "refused by the test" in d.stderr()
        s = requests.get(f"{d.url}/v1/sessions/{sid}").json()
        assert s["status"] == "paused" and s["t"] == 0 and "last stored row" in s["error"], s
    finally:
        d.stop()


def test_stored_configs_are_converted_to_si_units_once(tmp_path):
    """Store schema 2 (session 26): phi_curvature, fmep_b and id_a went from
    their correlations' units (1/rpm^2, Pa/rpm, ms) to SI. A session stored
    by a schema-1 daemon holds its whole resolved config in the old units;
    the first start-up converts it, once (the conversion and the new version
    are one transaction), so the session rebuilds the engine it was run with."""
    with Daemon(data_dir=str(tmp_path)) as d:
        sid = requests.post(d.url + "/v1/sessions",
                            json={"preset": "accel-pointmass-conventional"}).json()["id"]
        new = requests.get(f"{d.url}/v1/sessions/{sid}").json()["config"]["engine"]
    db = sqlite3.connect(str(tmp_path / "tanksimd.db"))
    assert db.execute("PRAGMA user_version").fetchone()[0] == 2
    # as a schema-1 daemon stored it
    db.execute("UPDATE sessions SET config=json_set(config,'$.engine.phi_curvature',8.8757e-08,"
               "'$.engine.fmep_b',33.1,'$.engine.id_a',3.45)")
    db.execute("PRAGMA user_version=1")
    db.commit()
    db.close()
    for _ in range(2):  # converted at the first start, left alone at the second
        with Daemon(data_dir=str(tmp_path)) as d:
            eng = requests.get(f"{d.url}/v1/sessions/{sid}").json()["config"]["engine"]
            for k in ("phi_curvature", "fmep_b", "id_a"):
                assert eng[k] == pytest.approx(new[k], rel=1e-12), (k, eng[k], new[k])
            r = requests.post(f"{d.url}/v1/sessions/{sid}/step", json={"duration": 0.1})
            assert r.status_code == 200, r.text
    db = sqlite3.connect(str(tmp_path / "tanksimd.db"))
    assert db.execute("PRAGMA user_version").fetchone()[0] == 2
    db.close()
