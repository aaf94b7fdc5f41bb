"""tanksimd persistence across a crash (issue 7): kill -9 the daemon during a
run, restart it on the same --data-dir: the session and every sample stored
before the kill are there unchanged, the status is `interrupted`, and a new
run continues from the stored state to the end without gaps or duplicates —
agreeing with an uninterrupted run of the same config to the integrator's
tolerance (CVODE restarts from the snapshot, so agreement is to ~rtol, not
bitwise)."""
import signal
import sqlite3
import time

import pytest
import requests

from conftest import BASE_PRESET, Daemon, step_in_background, wait_op


def series(d, sid, **params):
    return requests.get(f"{d.url}/v1/sessions/{sid}/series",
                        params={"channels": "vehicle.speed,vehicle.x", **params}).json()


def test_kill_9_during_run_then_restart_and_finish(tmp_path):
    cfg = {"preset": BASE_PRESET, "run": {"duration": 10.0}}
    d = Daemon(data_dir=str(tmp_path))
    try:
        sid = requests.post(d.url + "/v1/sessions", json=cfg).json()["id"]
        op = requests.post(f"{d.url}/v1/sessions/{sid}/run",
                           json={"real_time_factor": 5}).json()
        while requests.get(f"{d.url}/v1/operations/{op['id']}").json()["metadata"]["t"] < 2.0:
            time.sleep(0.05)
        before = series(d, sid)  # what is stored now (the run goes on)
        assert before["count"] > 500
        d.stop(sig=signal.SIGKILL)
    finally:
        d.stop()
    d2 = Daemon(data_dir=str(tmp_path))
    try:
        s = requests.get(f"{d2.url}/v1/sessions/{sid}").json()
        assert s["status"] == "interrupted"
        assert "killed or crashed" in s["error"], s  # session 25: it carried no reason
        assert 2.0 <= s["t"] < 10.0
        assert s["samples"] == s["index"] + 1 >= before["count"]
        after = series(d2, sid)
        assert after["index"] == list(range(s["index"] + 1))
        n = before["count"]
        for k in (1, 2):  # every sample seen before the kill is there, unchanged
            assert after["channels"][k]["values"][:n] == before["channels"][k]["values"]
        assert "interrupted" in d2.stderr()
        op = requests.post(f"{d2.url}/v1/sessions/{sid}/run", json={}).json()
        final = wait_op(d2.url, op["id"])
        assert final["response"]["status"] == "done"
        assert "error" not in final["response"], final
        full = series(d2, sid)
        assert full["index"] == list(range(5001))
        # the same config run without interruption
        ref = requests.post(d2.url + "/v1/sessions", json=cfg).json()["id"]
        wait_op(d2.url, requests.post(f"{d2.url}/v1/sessions/{ref}/run", json={}).json()["id"])
        want = series(d2, ref)
        for k in (1, 2):
            assert full["channels"][k]["values"] == pytest.approx(want["channels"][k]["values"],
                                                                  rel=1e-5, abs=1e-6)
    finally:
        d2.stop()


def test_kill_9_during_step_leaves_the_reason(tmp_path):
    """A session whose synchronous step was cut by kill -9 came back `paused`
    short of the step with no error, as if the step had asked for less
    (session-25 probe). It now carries the reason until its next step or run
    ends; the rows stored before the kill are there. The kill comes once the
    step's first batch (256 rows) is stored; the step must still be going
    then: the preset as shipped made the whole 10-s step in ~0.4 s, the
    first batch ~0.2 s before its end, and a client slowed by a loaded machine
    found the step over. max_step 20 us makes the step ~10 s of wall time,
    and 2000 samples/s brings the first batch within ~0.1 s of its start."""
    d = Daemon(data_dir=str(tmp_path))
    try:
        sid = requests.post(d.url + "/v1/sessions",
                            json={"preset": "bump-coupled-ivs5mph",
                                  "run": {"max_step": 2e-5, "sample_rate": 2000}}).json()["id"]
        th = step_in_background(d.url, sid, 10.0)
        alive = th.is_alive()
        d.stop(sig=signal.SIGKILL)
        th.join(30)
        assert alive, "the step ended before the kill: make it longer"
    finally:
        d.stop()
    d2 = Daemon(data_dir=str(tmp_path))
    try:
        s = requests.get(f"{d2.url}/v1/sessions/{sid}").json()
        assert s["status"] == "paused" and 0 < s["t"] < 10.0, s
        assert "during a step of this session to t = 10 s" in s["error"], s
        r = requests.post(f"{d2.url}/v1/sessions/{sid}/step", json={"duration": 0.1})
        assert r.status_code == 200, r.text
        assert "error" not in requests.get(f"{d2.url}/v1/sessions/{sid}").json()
    finally:
        d2.stop()
    d3 = Daemon(data_dir=str(tmp_path))  # and the cleared reason is stored
    try:
        assert "error" not in requests.get(f"{d3.url}/v1/sessions/{sid}").json()
    finally:
        d3.stop()


def test_clean_shutdown_during_run_marks_interrupted(tmp_path):
    d = Daemon(data_dir=str(tmp_path))
    sid = requests.post(d.url + "/v1/sessions", json={"preset": BASE_PRESET}).json()["id"]
    requests.post(f"{d.url}/v1/sessions/{sid}/run", json={"real_time_factor": 5})
    time.sleep(0.3)
    t0 = time.time()
    assert d.stop(sig=signal.SIGTERM) == 0
    assert time.time() - t0 < 5
    d2 = Daemon(data_dir=str(tmp_path))
    try:
        s = requests.get(f"{d2.url}/v1/sessions/{sid}").json()
        assert s["status"] == "interrupted" and s["t"] > 0
        assert "shut down at t = " in s["error"], s  # session 25: it carried no reason
        ser = series(d2, sid)
        assert ser["index"] == list(range(s["index"] + 1))
    finally:
        d2.stop()


def test_stored_sessions_are_rebuilt_at_first_use(tmp_path):
    # Start-up built every stored session's model and restored its state before
    # answering: with 24 stored sessions (crank-angle engines among them, whose
    # idle search takes ~0.4 s each) /v1/health came after 5.9 s. Now a stored
    # session is served from its stored channel table until its first use.
    d = Daemon(data_dir=str(tmp_path))
    try:
        ids = []
        for preset in ("accel-pointmass-lhr05", BASE_PRESET, "bump-prescribed-static"):
            s = requests.post(d.url + "/v1/sessions", json={"preset": preset}).json()
            r = requests.post(d.url + s["links"]["step"], json={"duration": 0.1})
            assert r.status_code == 200, r.text
            ids.append((s["id"], s["kind"], s["duration"], r.json()["index"]))
        broken = requests.post(d.url + "/v1/sessions", json={"preset": BASE_PRESET}).json()["id"]
    finally:
        assert d.stop() == 0
    with sqlite3.connect(f"{tmp_path}/tanksimd.db") as c:  # a config this build cannot make
        c.execute("UPDATE sessions SET config = replace(config, '\"pointmass\"', "
                  "'\"nosuchkind\"') WHERE id = ?", (broken,))
    d2 = Daemon(data_dir=str(tmp_path))
    try:
        assert "4 stored sessions loaded (4 to be rebuilt at first use)" in d2.stderr()
        # listed before any use: kind and duration from the stored config, rows as stored
        listed = {s["id"]: s for s in requests.get(d2.url + "/v1/sessions").json()["sessions"]}
        assert len(listed) == 4
        for sid, kind, duration, index in ids:
            assert listed[sid]["kind"] == kind and listed[sid]["duration"] == duration
            assert listed[sid]["index"] == index and listed[sid]["status"] == "paused"
        # two first uses at once: one build, both answered with the restored session
        from concurrent.futures import ThreadPoolExecutor
        sid, kind, _, index = ids[0]
        with ThreadPoolExecutor(4) as ex:
            got = list(ex.map(lambda _: requests.get(f"{d2.url}/v1/sessions/{sid}"), range(4)))
        assert all(g.status_code == 200 and g.json()["index"] == index for g in got)
        # deleting a stored session needs no model: none is built for it (the
        # broken one's build would log that it cannot be advanced)
        assert requests.delete(f"{d2.url}/v1/sessions/{broken}").status_code == 204
        assert f"session {broken} cannot be advanced" not in d2.stderr()
        assert requests.get(f"{d2.url}/v1/sessions/{broken}").status_code == 404
        for sid, kind, _, index in ids:  # each goes on from its stored state
            r = requests.post(f"{d2.url}/v1/sessions/{sid}/step", json={"duration": 0.1})
            assert r.status_code == 200, r.text
            assert r.json()["index"] == 2 * index
            assert series(d2, sid)["index"] == list(range(2 * index + 1))
    finally:
        d2.stop()
