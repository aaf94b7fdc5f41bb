"""GET /v1/sessions/{id}/summary: the figures `tanksim run` writes to
summary.json (ts_model_metrics over the sampled rows), for a session, over its
stored rows. For the same config they must be the CLI's: same names in the
same order, same units and descriptions, the same doubles (the daemon stores
rows as float64 and prints the figures with 17 digits, so the comparison is
exact). Also: a session with row 0 only, a run in progress (the figures of what
is stored, "complete": false, equal to the CLI's `--until` that time), an
unknown or deleted id (404), a stored session whose model this build cannot
make (409 with the reason, as its frames), and the same figures after a
restart (the session's model rebuilt at first use)."""
import json
import sqlite3
import subprocess
import time

import pytest
import requests

from conftest import TANKSIM, Daemon, is_problem, wait_op


def create(url, body):
    r = requests.post(url + "/v1/sessions", json=body)
    assert r.status_code == 201, r.text
    return r.json()


def summary(url, sid):
    r = requests.get(f"{url}/v1/sessions/{sid}/summary")
    assert r.status_code == 200, r.text
    assert r.headers["Content-Type"] == "application/json"
    return r.json()


def cli_summary(tmp_path, body, until=None):
    cfg = tmp_path / "config.json"
    cfg.write_text(json.dumps(body))
    out = tmp_path / "out"
    cmd = [TANKSIM, "run", str(cfg), "--out", str(out)]
    if until is not None:
        cmd += ["--until", repr(until)]
    subprocess.run(cmd, check=True, capture_output=True, timeout=60)
    return json.loads((out / "summary.json").read_text())


def assert_same_figures(daemon_sum, cli_sum):
    """Every figure of the CLI's summary.json, in its order, bit for bit."""
    mine = daemon_sum["metrics"]
    theirs = cli_sum["metrics"]
    assert [m["name"] for m in mine] == list(theirs)
    for m in mine:
        t = theirs[m["name"]]
        assert (m["unit"], m["description"]) == (t["unit"], t["description"]), m["name"]
        assert m["value"] == t["value"], (m["name"], m["value"], t["value"])  # None == None too
    assert daemon_sum["dof"] == cli_sum["dof"]
    assert daemon_sum["rows"] == cli_sum["samples"]
    assert daemon_sum["t"] == cli_sum["t_end_s"]
    assert daemon_sum["kind"] == cli_sum["kind"]


CASES = {
    # 21-DOF vehicle over the bump course: peak tension, FFT peaks, span figures
    "vehicle": {"preset": "bump-prescribed-static", "run": {"duration": 2.0}},
    # powertrain + vehicle: the 1-2 shift at ~4 s, the 2-3 and 3-4 not reached (null)
    "coupled": {"preset": "flat-coupled-rack90", "run": {"duration": 5.0}},
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_figures_equal_the_cli_summary(daemon, tmp_path, case):
    body = CASES[case]
    s = create(daemon.url, body)
    assert s["links"]["summary"] == f"/v1/sessions/{s['id']}/summary"
    op = requests.post(f"{daemon.url}/v1/sessions/{s['id']}/run", json={}).json()
    assert "error" not in wait_op(daemon.url, op["id"], timeout=60)
    got = summary(daemon.url, s["id"])
    assert got["id"] == s["id"] and got["status"] == "done" and got["complete"] is True
    assert got["t"] == body["run"]["duration"]
    assert_same_figures(got, cli_summary(tmp_path, body))
    if case == "coupled":
        shifts = {m["name"]: m["value"] for m in got["metrics"] if m["name"].startswith("shift_")}
        assert 3.5 < shifts["shift_1_2_half_s"] < 4.5 and shifts["shift_3_4_half_s"] is None
    else:
        names = [m["name"] for m in got["metrics"]]
        assert "peak_tension" in names and "tension_peak_13_20hz" in names


def test_a_new_session_has_row_0_only(daemon):
    # the daemon stores row 0 at creation, so there is no session without rows:
    # 200 with what the model makes of that one row, as /series serves it
    s = create(daemon.url, CASES["coupled"])
    got = summary(daemon.url, s["id"])
    assert (got["status"], got["complete"], got["rows"], got["t"]) == ("created", False, 1, 0)
    assert got["dof"] == 31 and got["metrics"] == []  # the coupled kind needs two rows
    s = create(daemon.url, {"preset": "accel-pointmass-conventional", "run": {"duration": 2.0}})
    got = summary(daemon.url, s["id"])
    assert got["rows"] == 1 and got["complete"] is False
    values = {m["name"]: m["value"] for m in got["metrics"]}
    assert values["speed_at_end_kmh"] == 0 and values["t_0_60_kmh_s"] is None


def test_a_run_in_progress_gives_the_figures_of_what_is_stored(daemon, tmp_path):
    body = {"preset": "accel-pointmass-conventional", "run": {"duration": 6.0}}
    s = create(daemon.url, body)
    op = requests.post(f"{daemon.url}/v1/sessions/{s['id']}/run",
                       json={"real_time_factor": 2}).json()
    try:
        deadline = time.time() + 20
        while True:
            got = summary(daemon.url, s["id"])
            if got["status"] == "running" and got["t"] >= 1.0:
                break
            assert time.time() < deadline, got
            time.sleep(0.05)
    finally:
        requests.post(f"{daemon.url}/v1/operations/{op['id']}:cancel")
    assert got["complete"] is False and got["t"] < 6.0
    assert got["rows"] == round(got["t"] * 100) + 1
    # exactly the CLI's figures of a run stopped at that time
    assert_same_figures(got, cli_summary(tmp_path, body, until=got["t"]))
    wait_op(daemon.url, op["id"])
    after = summary(daemon.url, s["id"])
    assert after["status"] == "paused" and after["complete"] is False
    assert after["rows"] >= got["rows"]


def test_unknown_and_deleted_sessions_are_404(daemon):
    p = is_problem(requests.get(daemon.url + "/v1/sessions/s0123456789abcdef/summary"), 404)
    assert "s0123456789abcdef" in p["detail"]
    s = create(daemon.url, CASES["vehicle"])
    assert requests.delete(f"{daemon.url}/v1/sessions/{s['id']}").status_code == 204
    is_problem(requests.get(f"{daemon.url}/v1/sessions/{s['id']}/summary"), 404)


def test_a_session_this_build_cannot_rebuild_is_409_then_as_before(tmp_path):
    data = str(tmp_path / "store")
    body = {"preset": "accel-pointmass-conventional", "run": {"duration": 1.0}}
    dm = Daemon(data_dir=data)
    try:
        sid = create(dm.url, body)["id"]
        op = requests.post(f"{dm.url}/v1/sessions/{sid}/run", json={}).json()
        wait_op(dm.url, op["id"])
        before = summary(dm.url, sid)
        assert before["complete"] is True and before["rows"] == 101
    finally:
        assert dm.stop() == 0
    with sqlite3.connect(f"{data}/tanksimd.db") as c:
        ((config,),) = c.execute("SELECT config FROM sessions WHERE seq=1").fetchall()
        c.execute("UPDATE sessions SET config=? WHERE seq=1", ('{"run": {"kind": "no-such"}}',))
    dm = Daemon(data_dir=data)
    try:
        p = is_problem(requests.get(f"{dm.url}/v1/sessions/{sid}/summary"), 409)
        assert "model cannot be rebuilt" in p["detail"], p
    finally:
        assert dm.stop() == 0
    with sqlite3.connect(f"{data}/tanksimd.db") as c:
        c.execute("UPDATE sessions SET config=? WHERE seq=1", (config,))
    dm = Daemon(data_dir=data)
    try:  # the model built at first use, over the stored rows: the same figures
        assert summary(dm.url, sid) == before
    finally:
        dm.stop()
