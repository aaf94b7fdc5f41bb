"""What the store holds after the daemon's less travelled paths: a run's status
written before its first row, a delete racing a run, a refused write rolled
back so the store stays writable for every other session, a create whose
first row is refused leaving nothing behind, a session's rows removed when
the worker holding it lets go, a decimated series counted from its `from`.
Each test was written for a change to server/db.c or server/session.c that
the rest of the suite let through (session-27 mutation pass; the mutant is
named in each docstring, M-numbers of that pass), and fails on it."""
import signal
import sqlite3
import threading
import time

import requests

from conftest import Daemon, metric


def test_kill_9_before_a_paced_runs_first_row_comes_back_interrupted(tmp_path):
    """Kills M18 (no "running" written when a run starts): a run whose first
    row is not due yet (10 samples/s at real_time_factor 1e-3: the row 0.1 s
    on is due 100 s later) stored nothing yet; a kill -9 now must still bring the session
    back interrupted, with the reason, not as 'created'."""
    d = Daemon(data_dir=str(tmp_path))
    try:
        sid = requests.post(d.url + "/v1/sessions", json={"preset": "pointmass-prescribed",
                                                          "run": {"sample_rate": 10}}).json()["id"]
        r = requests.post(f"{d.url}/v1/sessions/{sid}/run", json={"real_time_factor": 1e-3})
        assert r.status_code == 202, r.text
        time.sleep(0.5)
        s = requests.get(f"{d.url}/v1/sessions/{sid}").json()
        assert s["status"] == "running" and s["index"] == 0, s
        d.stop(sig=signal.SIGKILL)
    finally:
        d.stop()
    with Daemon(data_dir=str(tmp_path)) as d2:
        s = requests.get(f"{d2.url}/v1/sessions/{sid}").json()
        assert s["status"] == "interrupted", s
        assert "killed or crashed" in s["error"], s


def test_run_started_while_a_delete_waits_cannot_unmark_the_delete(tmp_path):
    """Kills M02 (the status UPDATE without status<>'deleted'). A DELETE
    waits on the store's lock (held here) before it marks the session in
    memory; a run started meanwhile passes acquire and queues its "running"
    write behind the mark. The rows' removal is refused (a trigger), so only
    the mark carries the delete to the next start: it must not be
    overwritten by the run's "running"."""
    d = Daemon(data_dir=str(tmp_path))
    db = sqlite3.connect(str(tmp_path / "tanksimd.db"), isolation_level=None)
    try:
        sid = requests.post(d.url + "/v1/sessions", json={"preset": "pointmass-prescribed"}).json()["id"]
        db.execute("CREATE TRIGGER keep_sessions BEFORE DELETE ON sessions "
                   "BEGIN SELECT RAISE(ABORT, 'kept by the test'); END")
        box = {}
        db.execute("BEGIN IMMEDIATE")  # the write lock, held
        td = threading.Thread(target=lambda: box.update(
            d=requests.delete(f"{d.url}/v1/sessions/{sid}", timeout=30)))
        td.start()
        time.sleep(0.5)  # the DELETE now waits in its 'deleted' write (holding the writer)
        tr = threading.Thread(target=lambda: box.update(
            r=requests.post(f"{d.url}/v1/sessions/{sid}/run", json={"real_time_factor": 0.001},
                            timeout=30)))
        tr.start()
        time.sleep(0.5)  # the run passed acquire; its "running" write waits behind the DELETE's
        db.execute("ROLLBACK")
        td.join(30)
        tr.join(30)
        assert box["d"].status_code == 204, box["d"].text
        time.sleep(1.0)  # the run's worker sees the cancel; its removal of the rows is refused
        assert requests.get(f"{d.url}/v1/sessions/{sid}").status_code == 404
        d.stop()
        db.execute("DROP TRIGGER keep_sessions")
        st = db.execute("SELECT status FROM sessions").fetchall()
        assert st == [("deleted",)], st
    finally:
        db.close()
        d.stop()
    with Daemon(data_dir=str(tmp_path)) as d2:
        assert requests.get(f"{d2.url}/v1/sessions/{sid}").status_code == 404


MEAN_VALUE_DYNO = {"run": {"kind": "engine_dyno"}, "engine": {"fidelity": "mean_value"},
                   "control": {"rack": 1.0}}


def test_max_analyses_holds_while_the_first_row_waits_for_the_store(tmp_path):
    """Kills M42 (analyses_lock not taken around count + first row).
    Deterministic form of the race in test_analyses_store: the store's write
    lock is held, so the first request waits in its first row's INSERT
    (inside analyses_lock); the second must wait for it and then be counted
    against --max-analyses 1, not pass the count beside it."""
    with Daemon("--threads", "3", "--max-analyses", "1", data_dir=str(tmp_path)) as d:
        db = sqlite3.connect(str(tmp_path / "tanksimd.db"), isolation_level=None)
        box = {}
        try:
            db.execute("BEGIN IMMEDIATE")
            post = lambda k: box.update({k: requests.post(d.url + "/v1/engine-map",
                                                          json=MEAN_VALUE_DYNO, timeout=30)})
            ta = threading.Thread(target=post, args=("a",))
            ta.start()
            time.sleep(0.5)
            tb = threading.Thread(target=post, args=("b",))
            tb.start()
            time.sleep(0.5)
            db.execute("ROLLBACK")
            ta.join(30)
            tb.join(30)
        finally:
            db.close()
        codes = sorted([box["a"].status_code, box["b"].status_code])
        assert codes == [202, 429], (codes, box["a"].text, box["b"].text)
        assert len(requests.get(d.url + "/v1/analyses").json()["analyses"]) == 1


def test_delete_of_an_idle_session_removes_its_rows_at_once(tmp_path):
    """Kills M17b (the idle DELETE skips tsd_db_session_delete): the session
    then stays in the store, marked 'deleted', with every sample and
    snapshot, until the next start; a long-lived daemon's store only grows."""
    with Daemon(data_dir=str(tmp_path)) as d:
        sid = requests.post(d.url + "/v1/sessions", json={"preset": "pointmass-prescribed"}).json()["id"]
        assert requests.post(f"{d.url}/v1/sessions/{sid}/step", json={"duration": 1.0}).status_code == 200
        assert requests.delete(f"{d.url}/v1/sessions/{sid}").status_code == 204
        db = sqlite3.connect(str(tmp_path / "tanksimd.db"))
        try:
            for table in ("sessions", "samples", "snapshots"):
                n = db.execute(f"SELECT COUNT(*) FROM {table}").fetchone()[0]
                assert n == 0, (table, n)
        finally:
            db.close()


def test_new_session_is_still_created_after_a_restart(tmp_path):
    """Kills M51 (row 0 stored with status "paused"): a session never stepped
    nor run comes back from a restart as it was listed before, "created"."""
    with Daemon(data_dir=str(tmp_path)) as d:
        sid = requests.post(d.url + "/v1/sessions", json={"preset": "pointmass-prescribed"}).json()["id"]
        assert requests.get(f"{d.url}/v1/sessions/{sid}").json()["status"] == "created"
    with Daemon(data_dir=str(tmp_path)) as d2:
        s = requests.get(f"{d2.url}/v1/sessions/{sid}").json()
        assert s["status"] == "created" and s["index"] == 0 and s["t"] == 0, s


def test_a_delete_the_store_refuses_to_finish_leaves_the_store_writable(tmp_path):
    """Kills M54 (exec_script without its ROLLBACK): the removal of a deleted
    session's rows is refused midway (a trigger standing in for any store
    error that ends only the statement); its transaction must be rolled back,
    else every later write of the daemon runs inside it, uncommitted, and the
    next batch's BEGIN fails: new sessions cannot be created."""
    with Daemon(data_dir=str(tmp_path)) as d:
        a = requests.post(d.url + "/v1/sessions", json={"preset": "pointmass-prescribed"}).json()["id"]
        assert requests.post(f"{d.url}/v1/sessions/{a}/step", json={"duration": 0.1}).status_code == 200
        db = sqlite3.connect(str(tmp_path / "tanksimd.db"))
        db.execute("CREATE TRIGGER keep_rows BEFORE DELETE ON samples "
                   "BEGIN SELECT RAISE(ABORT, 'kept by the test'); END")
        db.commit()
        db.close()
        assert requests.delete(f"{d.url}/v1/sessions/{a}").status_code == 204  # the mark holds it
        r = requests.post(d.url + "/v1/sessions", json={"preset": "pointmass-prescribed"})
        assert r.status_code == 201, r.text
        b = r.json()["id"]
        r = requests.post(f"{d.url}/v1/sessions/{b}/step", json={"duration": 0.1})
        assert r.status_code == 200, r.text
    with Daemon(data_dir=str(tmp_path)) as d2:  # b's rows were committed
        assert requests.get(f"{d2.url}/v1/sessions/{b}").json()["t"] > 0


def test_a_removal_the_store_refuses_is_counted(tmp_path):
    """Session 33: the status and removal writes are best effort (the
    session goes on as it is in memory; a deleted one's mark has the next
    start purge its rows), and their failures were only logged. They are
    counted now, so an operator can alert on a store that refuses them:
    /metrics tanksimd_store_writes_refused_total (0 before, 1 after a
    removal a trigger refuses)."""
    with Daemon(data_dir=str(tmp_path)) as d:
        a = requests.post(d.url + "/v1/sessions", json={"preset": "pointmass-prescribed"}).json()["id"]
        assert metric(d.url, "tanksimd_store_writes_refused_total") == 0
        db = sqlite3.connect(str(tmp_path / "tanksimd.db"))
        db.execute("CREATE TRIGGER keep_rows BEFORE DELETE ON samples "
                   "BEGIN SELECT RAISE(ABORT, 'kept by the test'); END")
        db.commit()
        db.close()
        assert requests.delete(f"{d.url}/v1/sessions/{a}").status_code == 204
        assert metric(d.url, "tanksimd_store_writes_refused_total") == 1
        assert requests.get(f"{d.url}/v1/sessions/{a}").status_code == 404


def test_a_batch_the_store_refuses_does_not_block_other_sessions(tmp_path):
    """Kills M55 (tsd_db_append without its ROLLBACK): one session's batch is
    refused by a statement-level error (trigger on that session's seq only);
    its transaction must be rolled back, else it stays open on the writer and
    every other session's next batch fails to BEGIN."""
    with Daemon(data_dir=str(tmp_path)) as d:
        a = requests.post(d.url + "/v1/sessions", json={"preset": "pointmass-prescribed"}).json()["id"]
        b = requests.post(d.url + "/v1/sessions", json={"preset": "pointmass-prescribed"}).json()["id"]
        db = sqlite3.connect(str(tmp_path / "tanksimd.db"))
        seq_a = db.execute("SELECT seq FROM sessions WHERE id=?", (a,)).fetchone()[0]
        db.execute(f"CREATE TRIGGER refuse_a BEFORE INSERT ON samples WHEN NEW.seq={seq_a} "
                   "BEGIN SELECT RAISE(ABORT, 'refused by the test'); END")
        db.commit()
        db.close()
        r = requests.post(f"{d.url}/v1/sessions/{a}/step", json={"duration": 0.1})
        assert r.status_code == 500, r.text
        r = requests.post(f"{d.url}/v1/sessions/{b}/step", json={"duration": 0.1})
        assert r.status_code == 200, r.text


def test_session_whose_first_row_was_never_stored_gets_row_0_back(tmp_path):
    """Kills M66 (restore_stored skips store_first_row): a session record
    whose creation was cut before its first row (a crash between the INSERT
    and the first batch) is rebuilt at row 0, and row 0 is stored, so its
    series starts at index 0 with no gap."""
    with Daemon(data_dir=str(tmp_path)) as d:
        sid = requests.post(d.url + "/v1/sessions", json={"preset": "pointmass-prescribed"}).json()["id"]
    db = sqlite3.connect(str(tmp_path / "tanksimd.db"))
    db.execute("DELETE FROM samples")
    db.execute("DELETE FROM snapshots")
    db.commit()
    db.close()
    with Daemon(data_dir=str(tmp_path)) as d2:
        r = requests.post(f"{d2.url}/v1/sessions/{sid}/step", json={"duration": 0.1})
        assert r.status_code == 200, r.text
        s = requests.get(f"{d2.url}/v1/sessions/{sid}").json()
        ser = requests.get(f"{d2.url}/v1/sessions/{sid}/series",
                           params={"channels": "vehicle.speed"}).json()
        assert ser["index"] == list(range(s["index"] + 1)), (ser["index"][:3], s["index"])


def test_decimated_series_starts_at_from_not_at_a_multiple_of_every(tmp_path):
    """Kills M69 (decimation on idx % every, not (idx - from) % every)."""
    with Daemon(data_dir=str(tmp_path)) as d:
        sid = requests.post(d.url + "/v1/sessions", json={"preset": "pointmass-prescribed"}).json()["id"]
        assert requests.post(f"{d.url}/v1/sessions/{sid}/step", json={"duration": 1.0}).status_code == 200
        j = requests.get(f"{d.url}/v1/sessions/{sid}/series",
                         params={"channels": "vehicle.speed", "from": 0.01, "to": 1.0, "every": 10}).json()
        assert j["index"] == list(range(5, 501, 10)), j["index"][:3]


def test_create_whose_first_row_is_refused_leaves_no_session_behind(tmp_path):
    """Kills M71 (a failed create keeps its sessions row): the client got an
    error, so the session must not appear, not now and not after a restart."""
    with Daemon(data_dir=str(tmp_path)) as d:
        db = sqlite3.connect(str(tmp_path / "tanksimd.db"))
        db.execute("CREATE TRIGGER refuse_rows BEFORE INSERT ON samples "
                   "BEGIN SELECT RAISE(ABORT, 'refused by the test'); END")
        db.commit()
        r = requests.post(d.url + "/v1/sessions", json={"preset": "pointmass-prescribed"})
        assert r.status_code >= 500, r.text
        db.execute("DROP TRIGGER refuse_rows")
        db.commit()
        n = db.execute("SELECT COUNT(*) FROM sessions").fetchone()[0]
        db.close()
        assert n == 0, n
    with Daemon(data_dir=str(tmp_path)) as d2:
        assert requests.get(d2.url + "/v1/sessions").json()["sessions"] == []


def test_delete_during_a_run_removes_the_rows_when_the_run_stops(tmp_path):
    """Kills M22b (release() skips the delete of a session deleted while busy):
    the rows of a session deleted mid-run go when its worker lets go of it,
    not at the next start."""
    with Daemon(data_dir=str(tmp_path)) as d:
        sid = requests.post(d.url + "/v1/sessions", json={"preset": "pointmass-prescribed"}).json()["id"]
        op = requests.post(f"{d.url}/v1/sessions/{sid}/run", json={"real_time_factor": 1}).json()
        time.sleep(0.5)
        assert requests.delete(f"{d.url}/v1/sessions/{sid}").status_code == 204
        deadline = time.time() + 10
        while not requests.get(f"{d.url}/v1/operations/{op['id']}").json()["done"]:
            assert time.time() < deadline
            time.sleep(0.05)
        # the operation's end is published before the worker lets go: wait for the rows
        db = sqlite3.connect(str(tmp_path / "tanksimd.db"))
        try:
            deadline = time.time() + 10
            while True:
                left = {t: db.execute(f"SELECT COUNT(*) FROM {t}").fetchone()[0]
                        for t in ("sessions", "samples", "snapshots")}
                if not any(left.values()):
                    break
                assert time.time() < deadline, left
                time.sleep(0.05)
        finally:
            db.close()


def test_cancel_of_a_finished_run_operation_leaves_the_next_run_alone(tmp_path):
    """Kills M57b (tsd_session_cancel without the op_id match): a cancel sent
    for a run operation that already finished must not stop the session's
    current run (another operation)."""
    with Daemon(data_dir=str(tmp_path)) as d:
        sid = requests.post(d.url + "/v1/sessions", json={"preset": "pointmass-prescribed"}).json()["id"]
        op1 = requests.post(f"{d.url}/v1/sessions/{sid}/run", json={"until": 0.2}).json()
        deadline = time.time() + 10
        while not requests.get(f"{d.url}/v1/operations/{op1['id']}").json()["done"]:
            assert time.time() < deadline
            time.sleep(0.05)
        op2 = requests.post(f"{d.url}/v1/sessions/{sid}/run", json={"real_time_factor": 1}).json()
        time.sleep(0.3)
        requests.post(f"{d.url}/v1/operations/{op1['id']}:cancel")
        time.sleep(0.5)
        o2 = requests.get(f"{d.url}/v1/operations/{op2['id']}").json()
        assert not o2["done"], o2
        assert requests.get(f"{d.url}/v1/sessions/{sid}").json()["status"] == "running"
        requests.post(f"{d.url}/v1/operations/{op2['id']}:cancel")
